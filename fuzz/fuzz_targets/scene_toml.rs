//! libFuzzer entry point of the `scene_toml` target (see fuzz/src/targets.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| tumble_fuzz::targets::scene_toml(data));
