//! Exact distance from a convex polytope (a convex hull or a box) to a mesh:
//! branch and bound over the mesh's OBBTree ([`crate::bvh::volume_distance`](fn@crate::bvh::volume_distance))
//! with the polytope's oriented bounding box as the node bound, and GJK
//! (Gilbert, Johnson, Keerthi 1988) between the polytope and each triangle
//! at the leaves. The primitive queries cover spheres, boxes and capsules
//! with closed forms; a hull has none, and continuous collision needs the
//! distance of every shape to a mesh.

use super::error::QueryError;
use super::options::DistanceOptions;
use super::report::{DistanceResult, QueryStats};
use crate::bvh::sat::{obb_distance_lower_bound, RelFrame};
use crate::bvh::{self, Obb};
use crate::math::{DMat3, DVec3};
use crate::narrow::gjk::{gjk_distance, PolytopeSupport, SupportMap};
use crate::pose::Pose;
use crate::shape::{MeshShape, Polytope};

/// A triangle's support map.
struct TriangleSupport([DVec3; 3]);

impl SupportMap for TriangleSupport {
    fn support(&self, dir: DVec3) -> DVec3 {
        let d = self.0.map(|v| v.dot(dir));
        if d[0] >= d[1] && d[0] >= d[2] {
            self.0[0]
        } else if d[1] >= d[2] {
            self.0[1]
        } else {
            self.0[2]
        }
    }
}

/// Minimum distance between polytope A at `pose_a` and mesh B at `pose_b`,
/// with the closest points (world frame; `tri_a` is 0). Overlapping shapes
/// are at distance 0. Poses are the caller's, already checked.
pub(crate) fn polytope_mesh_distance<P: Polytope + ?Sized>(
    a: &P,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
) -> Result<DistanceResult, QueryError> {
    // A's box around its vertices, in B's frame for the node bounds.
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for i in 0..a.vertex_count() {
        lo = lo.min(a.vertex(i));
        hi = hi.max(a.vertex(i));
    }
    let rel = pose_b.inverse().mul_pose(pose_a);
    let obb = Obb {
        center: rel.transform_point((lo + hi) * 0.5),
        axes: DMat3::from_quat(rel.rotation),
        half_extents: (hi - lo) * 0.5,
    };
    let support = PolytopeSupport {
        poly: a,
        rot: DMat3::from_quat(pose_a.rotation),
        trans: pose_a.position,
    };
    let scale = (hi - lo).length();
    let mut best: Option<(u32, DVec3, DVec3, f64)> = None;
    let mut tests = 0u64;
    let traversal = bvh::volume_distance(
        b.tree(),
        f64::INFINITY,
        &DistanceOptions::default().tolerance(),
        |node| {
            // Round-off guard: a bound a hair too low only costs a visit.
            let at = node.axes_f64().transpose();
            let f = RelFrame::new(&(at * obb.axes), at * (obb.center - node.center_f64()));
            (obb_distance_lower_bound(node.half_f64(), obb.half_extents.to_array(), &f) * (1.0 - 1e-9))
                .max(0.0)
        },
        |t, best_so_far| {
            tests += 1;
            let g = gjk_distance(
                &support,
                &TriangleSupport(b.mesh().placed_triangle(t as usize, pose_b)),
                scale,
            );
            let d = if g.overlap { 0.0 } else { g.distance };
            if d < best_so_far {
                best = Some((t, g.point_a, g.point_b, d));
            }
            d
        },
    )
    .map_err(|_| QueryError::NotFinite("polytope-mesh distance"))?;
    let (tri_b, point_a, point_b, distance) = best.ok_or(QueryError::NotFinite("polytope-mesh distance"))?;
    if !(distance.is_finite() && point_a.is_finite() && point_b.is_finite()) {
        return Err(QueryError::NotFinite("polytope-mesh distance"));
    }
    Ok(DistanceResult {
        distance,
        point_a,
        point_b,
        tri_a: 0,
        tri_b,
        stats: QueryStats::from_traversal(&traversal.stats, tests),
    })
}
