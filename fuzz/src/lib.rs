//! tumble's fuzz targets as a library for the libFuzzer binaries in
//! `fuzz_targets/` (see [`targets`]).

pub mod targets;
