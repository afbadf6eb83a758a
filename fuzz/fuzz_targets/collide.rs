//! libFuzzer entry point of the `collide` target (see fuzz/src/targets.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tumble_fuzz::targets::collide_target(data));
