//! The collision query API, usable without any dynamics (thesis 4.6, 5.1,
//! 5.2: the JAOC queries; PQP's `PQP_Collide`, `PQP_Distance`,
//! `PQP_Tolerance`). A query object is a [`MeshShape`]: a validated
//! [`crate::TriMesh`] with its OBBTree, built once and cheap to clone.
//! Poses are position + unit quaternion ([`crate::Pose`]), re-checked by every
//! query.
//!
//! - [`collide`](fn@collide): intersecting triangle pairs, first-contact or all of them,
//!   and contacts ([`CollideOptions`], [`ReportMode`]);
//! - [`distance`](fn@distance): minimum distance and closest points, exact or with PQP's
//!   relative / absolute error ([`DistanceOptions`]);
//! - [`within_tolerance`]: whether two meshes come within a distance;
//! - [`time_of_impact`](fn@time_of_impact): when two moving shapes of any pair first touch
//!   (continuous collision; [`Motion`], [`ToiOptions`], [`Impact`]);
//! - [`collide_primitive`], [`distance_primitive`],
//!   [`within_tolerance_primitive`]: the same for a sphere, box, capsule or
//!   half-space (the body shapes' own [`crate::Shape`]) against a mesh;
//! - [`collide_shapes`], [`distance_shapes`], [`within_tolerance_shapes`]:
//!   any two shapes, dispatched to the fitting query (answers in the
//!   caller's A / B order).
//!
//! Files: `options` (settings), `report` (results and statistics), `error`,
//! `input` (pose checks, world triangles), one file per query, `primitive`
//! (primitive-triangle tests), `primitive_query` and `shape_pair` (the
//! dispatch over any two shapes). Usage in
//! `docs/collision.md` and the example on [`collide`](fn@collide).
//!
//! The query functions read alike at their ends by design. `collide`,
//! `distance` and `within_tolerance` and their `_primitive` twins share one
//! public signature shape, `(a, pose_a, b, pose_b, options or tol)` in PQP's
//! order, differing in A's type (`MeshShape` / `Shape`), so each keeps its
//! own header; each then opens with `input::checked_args` (the checks,
//! written once) and turns a walk's refusal of its margin into
//! `options::bad_nonneg`; a collision query records hits and ends through
//! `Report::record_hit` and `Report::finish`; the two tolerance queries end
//! at the first candidate within `tol` in the same few lines. What lies
//! between (which tree walk, which exact test, which contacts) is each
//! query's own.

mod collide;
mod distance;
mod error;
mod hull_distance;
mod input;
mod motion;
mod options;
mod primitive;
mod primitive_query;
mod report;
mod shape_pair;
mod time_of_impact;
mod tolerance;

pub use crate::shape::MeshShape;
pub use collide::collide;
pub use distance::distance;
pub use error::QueryError;
pub use motion::Motion;
pub use options::{CollideOptions, DistanceOptions, ReportMode};
pub use primitive_query::{collide_primitive, distance_primitive, within_tolerance_primitive};
pub use report::{DistanceResult, QueryStats, Report};
pub use shape_pair::{collide_shapes, distance_shapes, within_tolerance_shapes};
pub use time_of_impact::{time_of_impact, Impact, ToiOptions, ToiStats};
pub use tolerance::within_tolerance;
