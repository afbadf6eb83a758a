//! libFuzzer entry point of the `sweep` target (see fuzz/src/targets.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tumble_fuzz::targets::sweep(data));
