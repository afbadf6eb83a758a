//! libFuzzer entry point of the `snapshot` target (see fuzz/src/targets.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tumble_fuzz::targets::snapshot(data));
