//! Convex hull of a point set (3D quickhull). Placeholder signature: the
//! implementation lands with the OBBTree work.

use crate::math::DVec3;
use crate::mesh::TriMesh;

/// Why a hull could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HullError {
    /// Fewer than four points, or all points coplanar/collinear.
    #[error("convex hull is degenerate: {0}")]
    Degenerate(String),
    /// A point is not finite.
    #[error("convex hull input point {0} is not finite")]
    NonFinite(usize),
    /// Not yet implemented.
    #[error("convex hull not implemented yet")]
    Unimplemented,
}

/// Convex hull of `points` as a closed, outward-wound triangle mesh.
pub fn convex_hull(points: &[DVec3]) -> Result<TriMesh, HullError> {
    let _ = points;
    Err(HullError::Unimplemented)
}
