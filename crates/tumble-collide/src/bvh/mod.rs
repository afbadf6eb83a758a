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
//! - [`front`]: where the last walk of two trees ended, to start the next from.
//! - [`query`]: one tree against a query box, sphere or half-space.
//! - [`volume_distance`](mod@volume_distance): one tree's distance to a convex query volume.

pub mod build;
pub mod fit;
pub mod front;
pub mod node;
pub mod obb;
pub mod query;
pub mod sat;
mod stack;
pub mod traverse;
pub mod volume_distance;

pub use build::{BuildOptions, BvhError, ObbTree, TreeStats, MAX_COORDINATE};
pub use front::{collide_leaves_front, FrontWalk, WalkFront};
pub use node::Node;
pub use obb::Obb;
pub use query::{query_aabb, query_halfspace, query_obb, query_sphere};
pub use traverse::{
    collide, collide_leaves, collide_moving, distance, distance_with, DistanceResult, DistanceTolerance,
    TraversalError, TraversalStats, Traverse,
};
pub use volume_distance::volume_distance;
