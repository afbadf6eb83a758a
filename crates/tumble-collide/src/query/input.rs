//! Checks every query runs on its input before any geometry, and the
//! world-frame triangle access they share.

use super::error::QueryError;
use crate::math::DVec3;
use crate::mesh::TriMesh;
use crate::pose::Pose;

/// The pose re-validated (fields are public, so a `Pose` may have been built
/// without [`Pose::new`]). A quaternion that is unit to round-off is used
/// as given, bit for bit, so that the query sees the very coordinates the
/// caller's own transforms give; one off by more (up to the accepted
/// [`Pose::UNIT_TOLERANCE`]) is normalised.
pub(crate) fn checked_pose(which: &'static str, pose: &Pose) -> Result<Pose, QueryError> {
    let normalised =
        Pose::new(pose.position, pose.rotation).map_err(|source| QueryError::BadPose { which, source })?;
    if (pose.rotation.length_squared() - 1.0).abs() <= 8.0 * f64::EPSILON {
        Ok(*pose)
    } else {
        Ok(normalised)
    }
}

/// Triangle `t` of `mesh` placed by `pose` (world frame). Every query and
/// its brute-force oracle evaluate the exact predicates on these very
/// coordinates, so the answers agree bit for bit.
#[inline]
pub(crate) fn world_triangle(mesh: &TriMesh, pose: &Pose, t: u32) -> [DVec3; 3] {
    let [a, b, c] = mesh.triangles()[t as usize];
    let v = mesh.vertices();
    [
        pose.transform_point(v[a as usize]),
        pose.transform_point(v[b as usize]),
        pose.transform_point(v[c as usize]),
    ]
}
