//! Export of recorded simulations for viewing and analysis.
//!
//! - [`recording`]: the plain [`Recording`] type (bodies, frame times, poses,
//!   optional per-frame viewer data) and its validation.
//! - [`glb`]: animated binary glTF 2.0 (`.glb`) export, Khronos glTF 2.0
//!   specification sections 3.6-3.11 (buffers, accessors, meshes, animations)
//!   and 4.4 (GLB container).
//! - [`csv`]: a flat trajectory table.
//! - [`atomic`]: write-to-temp-then-rename so readers never see half a file.
//!
//! The viewer in `viewer/` (repository root) reads the `.glb` files written here;
//! the `extras` schema it relies on is documented in [`glb`].

pub mod atomic;
pub mod csv;
pub mod glb;
mod mesh_data;
pub mod recording;

pub use csv::write_trajectory_csv;
pub use glb::{glb_bytes, write_glb};
pub use recording::{ContactMark, ExportError, FrameExtras, ObbBox, RecordedBody, Recording};

#[cfg(test)]
mod tests;
