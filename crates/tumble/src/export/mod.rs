//! Export of recorded simulations for viewing and analysis.
//!
//! - [`recording`]: the plain [`Recording`] type (bodies, frame times, poses,
//!   optional per-frame viewer data) and its validation.
//! - [`glb`]: animated binary glTF 2.0 (`.glb`) export, Khronos glTF 2.0
//!   specification sections 3.6-3.11 (buffers, accessors, meshes, animations)
//!   and 4.4 (GLB container).
//! - [`csv`]: a flat trajectory table; [`npz`]: the same as NumPy arrays.
//! - [`live`]: the viewer's live-mode messages (JSON over a WebSocket);
//!   [`live_session`]: a live session's requests (spawning bodies).
//! - [`table`]: a column table (sweep results) as Parquet, CSV or JSON.
//! - [`atomic`]: write-to-temp-then-rename so readers never see half a file.
//!
//! The viewer in `viewer/` (repository root) reads the `.glb` files written here;
//! the `extras` schema it relies on is documented in [`glb`].
//!
//! ```
//! use tumble::collide::{mesh::box_mesh, DVec3, Pose};
//! use tumble::export::{glb_bytes, RecordedBody, Recording};
//!
//! // A box in free fall, sampled at 10 Hz for one second.
//! let mut rec = Recording {
//!     bodies: vec![RecordedBody {
//!         name: "box".into(),
//!         mesh: box_mesh(DVec3::splat(0.5)).unwrap(),
//!         color: [0.8, 0.3, 0.2, 1.0],
//!         is_static: false,
//!     }],
//!     ..Default::default()
//! };
//! for f in 0..=10 {
//!     let t = 0.1 * f as f64;
//!     rec.frame_times.push(t);
//!     rec.frames.push(vec![Pose::from_translation(DVec3::new(0.0, 0.0, 5.0 - 4.905 * t * t))]);
//! }
//! let bytes = glb_bytes(&rec)?; // or write_glb(&rec, "fall.glb")?
//! assert_eq!(&bytes[..4], b"glTF");
//! # Ok::<(), tumble::export::ExportError>(())
//! ```

pub mod atomic;
pub mod csv;
pub mod glb;
pub mod live;
pub mod live_session;
mod mesh_data;
pub mod npz;
pub mod recording;
pub mod table;
pub mod world_recorder;

pub use csv::{write_trajectory_csv, CsvStream};
pub use glb::{glb_bytes, write_glb};
pub use npz::{trajectory_npz, write_trajectory_npz};
pub use recording::{ContactMark, ExportError, FrameExtras, ObbBox, RecordedBody, RecordedJoint, Recording};
pub use world_recorder::{
    frame_extras, recorded_body, recorded_joints, shape_mesh, WorldRecorder, MAX_CONTACTS_DRAWN,
};

#[cfg(test)]
mod tests;
