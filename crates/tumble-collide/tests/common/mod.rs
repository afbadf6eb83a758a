//! Helpers shared by the collision library's integration tests: the
//! workspace's random sources (`tumble-testkit`).

pub use tumble_testkit::splitmix_f64 as rng;
