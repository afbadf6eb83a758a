//! libFuzzer entry point of the `joints` target (see fuzz/src/targets.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tumble_fuzz::targets::joints(data));
