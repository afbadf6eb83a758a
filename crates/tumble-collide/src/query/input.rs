//! Checks every query runs on its input before any geometry (triangles are
//! placed in the world by `TriMesh::placed_triangle`).

use super::error::QueryError;
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

/// What a pairwise query was asked with, for [`checked_args`].
pub(crate) enum QueryArgs<'a> {
    /// `collide` and `collide_primitive`.
    Collide(&'a super::options::CollideOptions),
    /// `distance` and `distance_primitive`.
    Distance(&'a super::options::DistanceOptions),
    /// `within_tolerance` and `within_tolerance_primitive`: the tolerance.
    Tolerance(f64),
}

/// The checks every pairwise query makes before it reads a triangle, in
/// one place so that each error reads the same from every query: the two
/// poses ([`checked_pose`]), then the options. Returns the poses to use.
pub(crate) fn checked_args(
    pose_a: &Pose,
    pose_b: &Pose,
    args: QueryArgs<'_>,
) -> Result<(Pose, Pose), QueryError> {
    let poses = (checked_pose("pose_a", pose_a)?, checked_pose("pose_b", pose_b)?);
    match args {
        QueryArgs::Collide(o) => o.validate()?,
        QueryArgs::Distance(o) => o.validate()?,
        QueryArgs::Tolerance(tol) => super::options::nonneg_finite("within_tolerance tol", tol)?,
    }
    Ok(poses)
}
