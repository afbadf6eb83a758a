//! OBBTree: a bounding volume hierarchy of oriented boxes over a triangle mesh
//! (thesis 4.5, 4.6, 5.1; Gottschalk, Lin & Manocha, "OBBTree: A Hierarchical
//! Structure for Rapid Interference Detection", SIGGRAPH 1996; the layout of
//! their PQP library).
//!
//! - [`obb`]: the f64 oriented box used by fitting and queries.
//! - [`fit`]: box axes from the area-weighted covariance of the convex hull.
//! - [`sat`]: the 15-axis separating axis test and a distance lower bound.
//! - [`node`]: the memory-compact f32 node with conservative rounding.
//! - [`build`]: top-down construction, [`ObbTree`] and its statistics.
//! - [`traverse`]: simultaneous traversal of two trees (overlap and distance).
//! - [`query`]: one tree against a query box or sphere.

pub mod build;
pub mod fit;
pub mod node;
pub mod obb;
pub mod query;
pub mod sat;
mod stack;
pub mod traverse;

pub use build::{BuildOptions, BvhError, ObbTree, TreeStats};
pub use node::Node;
pub use obb::Obb;
pub use query::{query_aabb, query_obb, query_sphere};
pub use traverse::{collide, distance, DistanceResult, TraversalError, TraversalStats, Traverse};
