//! The one error type of the query API: what was wrong, where, and what was
//! expected. Queries check their input before touching any geometry, so an
//! error never leaves partial results behind.

use crate::mesh::MeshError;
use crate::narrow::NarrowError;
use crate::pose::PoseError;
use crate::shape::ShapeError;

/// Why a query refused its input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum QueryError {
    /// A pose with a non-finite position or a quaternion that is not finite
    /// or not of unit length (within [`crate::Pose::UNIT_TOLERANCE`]).
    #[error("{which}: {source}")]
    BadPose {
        /// Which argument: `"pose_a"` or `"pose_b"`.
        which: &'static str,
        /// What was wrong with it.
        source: PoseError,
    },
    /// An option or tolerance outside its valid range.
    #[error("{option} must be {expected}, got {value}")]
    BadOption {
        /// The option's name, e.g. `"DistanceOptions::rel_err"`.
        option: &'static str,
        /// The valid range, e.g. `"finite and >= 0"`.
        expected: &'static str,
        /// The value given.
        value: f64,
    },
    /// A mesh given to build a query object is invalid (NaN vertex,
    /// out-of-range index, empty, ...).
    #[error("mesh: {0}")]
    Mesh(#[from] MeshError),
    /// A shape could not be built (bad dimension, OBBTree failure).
    #[error("shape: {0}")]
    Shape(#[from] ShapeError),
    /// A shape pair without a contact routine, or one whose contact
    /// arithmetic overflowed (the queries over any shape pair).
    #[error("{0}")]
    Narrow(#[from] NarrowError),
    /// A primitive query (`collide_primitive`, `distance_primitive`,
    /// `within_tolerance_primitive`) was given a shape that is not a
    /// primitive: a convex hull or a mesh.
    #[error("{query}: shape A must be a sphere, cuboid, capsule or half_space, got a {kind} (meshes: collide, distance, within_tolerance)")]
    NotPrimitive {
        /// The query.
        query: &'static str,
        /// The shape given (`Shape::kind_name`).
        kind: &'static str,
    },
    /// A query over two primitives (the queries need at least one mesh).
    #[error("a query needs at least one mesh; got two primitives ({a} and {b})")]
    NoMesh {
        /// Shape A (`Shape::kind_name`).
        a: &'static str,
        /// Shape B.
        b: &'static str,
    },
    /// The result overflowed (coordinates so large that distances are not
    /// finite in f64).
    #[error("{0}: the result is not finite (coordinates beyond the range of f64 arithmetic)")]
    NotFinite(&'static str),
}
