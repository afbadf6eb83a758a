//! Tolerance query (PQP's `PQP_Tolerance`): are two meshes within a given
//! distance? Cheaper than the distance: both trees are walked with every box
//! grown by half the tolerance, and the walk ends at the first triangle pair
//! that is close enough.

use super::error::QueryError;
use super::input::{checked_args, QueryArgs};
use super::options::bad_nonneg;
use crate::bvh::{self, Traverse};
use crate::pose::Pose;
use crate::shape::MeshShape;
use crate::triangle::triangle_distance;

/// `true` when mesh A at `pose_a` and mesh B at `pose_b` come within `tol`
/// (m, finite, >= 0): some triangle pair has [`triangle_distance`] `<= tol`.
/// Exactly consistent with [`super::distance`](fn@super::distance) in its exact mode:
/// `within_tolerance(.., tol) == (distance(..) <= tol)`.
///
/// # Errors
/// [`QueryError::BadPose`]; [`QueryError::BadOption`] for a negative or
/// non-finite `tol`.
pub fn within_tolerance(
    a: &MeshShape,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
    tol: f64,
) -> Result<bool, QueryError> {
    let (pose_a, pose_b) = checked_args(pose_a, pose_b, QueryArgs::Tolerance(tol))?;
    let (ma, mb) = (a.mesh(), b.mesh());
    let mut within = false;
    // Boxes grown by tol / 2 each overlap whenever they are within tol: the
    // walk sees every pair that can be close enough.
    bvh::collide(a.tree(), &pose_a, b.tree(), &pose_b, tol, |ta, tb| {
        let d = triangle_distance(
            &ma.placed_triangle(ta as usize, &pose_a),
            &mb.placed_triangle(tb as usize, &pose_b),
        );
        if d.distance <= tol {
            within = true;
            Traverse::Stop
        } else {
            Traverse::Continue
        }
    })
    .map_err(|_| bad_nonneg("within_tolerance tol", tol))?;
    Ok(within)
}
