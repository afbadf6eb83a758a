//! Peer-engine side of the benchmark harness (issue 8): the standard scenes of
//! `shared/scenes.md` built in Rapier and parry from their one definition in
//! `tumble::scenes`, the JSON record that every peer prints (timing statistics: `tumble::scenes::TimingStats`), shared by the `peer-rapier` and `peer-parry` binaries and the
//! in-process criterion benches (`tori_vs_parry`, `dynamics_vs_rapier`).
#![warn(missing_docs)]

pub mod args;
pub mod parry_scenes;
pub mod rapier_scenes;
pub mod record;

pub use args::{ArgError, Args};
pub use record::Record;
