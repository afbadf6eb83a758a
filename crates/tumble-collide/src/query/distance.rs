//! Mesh-mesh distance query (PQP's `PQP_Distance`; Larsen, Gottschalk, Lin &
//! Manocha 1999): branch and bound over both OBBTrees, nearest box pair
//! first, with the exact triangle-triangle distance ([`triangle_distance`],
//! Ericson 5.1.9) at the leaves and PQP's relative / absolute error pruning.
//!
//! Its head (signature, then `checked_args`) reads like `collide`'s and the
//! `_primitive` twins': one public shape in PQP's order, kept per query
//! because A's type and the options differ (query/mod.rs says more).

use super::error::QueryError;
use super::input::{checked_args, QueryArgs};
use super::options::{bad_nonneg, DistanceOptions};
use super::report::{DistanceResult, QueryStats};
use crate::bvh;
use crate::math::DVec3;
use crate::pose::Pose;
use crate::shape::MeshShape;
use crate::triangle::{triangle_distance, TriDistance};

/// Minimum distance between mesh A at `pose_a` and mesh B at `pose_b`, the
/// closest points (world frame) and the triangles holding them.
///
/// With `DistanceOptions::default()` (both errors 0) the answer is the exact
/// minimum of [`triangle_distance`] over all triangle pairs; otherwise it lies
/// in `[d, max((1 + rel_err) d, d + abs_err)]` and the closest points are
/// those of the pair that gave it. Intersecting meshes are at distance 0
/// (the walk stops at the first intersecting pair, whose common point is
/// returned). See [`super::collide`](fn@super::collide) for an example.
///
/// # Errors
/// [`QueryError::BadPose`], [`QueryError::BadOption`] (negative or
/// non-finite `rel_err` / `abs_err`), [`QueryError::NotFinite`] when the
/// coordinates are so large that no distance is finite.
pub fn distance(
    a: &MeshShape,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
    options: &DistanceOptions,
) -> Result<DistanceResult, QueryError> {
    let (pose_a, pose_b) = checked_args(pose_a, pose_b, QueryArgs::Distance(options))?;
    let (ma, mb) = (a.mesh(), b.mesh());
    let mut best: Option<(u32, u32, TriDistance)> = None;
    let mut tests = 0u64;
    let traversal = bvh::distance_with(
        a.tree(),
        &pose_a,
        b.tree(),
        &pose_b,
        f64::INFINITY,
        &options.tolerance(),
        |ta, tb, best_so_far| {
            let (wa, wb) = (
                ma.placed_triangle(ta as usize, &pose_a),
                mb.placed_triangle(tb as usize, &pose_b),
            );
            // The gap between the triangles' bounding boxes bounds their
            // distance from below: a pair that cannot win is skipped.
            if aabb_gap(&wa, &wb) >= best_so_far {
                return best_so_far;
            }
            tests += 1;
            let td = triangle_distance(&wa, &wb);
            // Same comparison as the traversal's, so the recorded pair is
            // the one whose distance it keeps.
            if td.distance < best_so_far {
                best = Some((ta, tb, td));
            }
            td.distance
        },
    )
    .map_err(|_| bad_nonneg("DistanceOptions", options.rel_err))?;
    let (tri_a, tri_b, td) = best.ok_or(QueryError::NotFinite("distance"))?;
    DistanceResult {
        distance: td.distance,
        point_a: td.point_a,
        point_b: td.point_b,
        tri_a,
        tri_b,
        stats: QueryStats::from_traversal(&traversal.stats, tests),
    }
    .finite("distance")
}

/// Euclidean distance between the axis-aligned boxes of two triangles (m),
/// a lower bound on the triangles' distance.
#[inline]
fn aabb_gap(a: &[DVec3; 3], b: &[DVec3; 3]) -> f64 {
    let (lo_a, hi_a) = (a[0].min(a[1]).min(a[2]), a[0].max(a[1]).max(a[2]));
    let (lo_b, hi_b) = (b[0].min(b[1]).min(b[2]), b[0].max(b[1]).max(b[2]));
    (lo_b - hi_a).max(lo_a - hi_b).max(DVec3::ZERO).length()
}
