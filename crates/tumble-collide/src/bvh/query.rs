//! One OBBTree against a query volume in world space: an oriented box, an
//! axis-aligned box or a sphere (for primitive-versus-mesh contact). Same
//! depth-first walk and callback protocol as [`super::traverse::collide`].
//!
//! `walk` in query/primitive_query.rs reads like [`query_obb`] (a placed
//! volume, the mesh and its pose, a margin, the callback) because it only
//! picks one of these queries by the primitive's kind (this module knows no
//! shapes).

use super::build::ObbTree;
use super::node::Node;
use super::obb::Obb;
use super::sat::{obb_disjoint, RelFrame};
use super::stack::SmallStack;
use super::traverse::{check_nonneg, TraversalError, TraversalStats, Traverse};
use crate::math::{DMat3, DVec3};
use crate::pose::Pose;

/// Shared walk: `hit(node)` decides whether a node's box passes.
fn walk(
    tree: &ObbTree,
    mut hit: impl FnMut(&Node) -> bool,
    mut on_tri: impl FnMut(u32) -> Traverse,
) -> TraversalStats {
    let nodes = tree.nodes();
    let mut stats = TraversalStats {
        bv_tests: 1,
        ..TraversalStats::default()
    };
    if nodes.is_empty() || !hit(&nodes[0]) {
        return stats;
    }
    let mut stack = SmallStack::<u32>::new();
    stack.push(0);
    while let Some(i) = stack.pop() {
        let n = &nodes[i as usize];
        if n.is_leaf() {
            stats.leaf_pairs += 1;
            for &t in tree.leaf_triangles(n) {
                stats.triangle_pairs += 1;
                if on_tri(t) == Traverse::Stop {
                    stats.stopped = true;
                    return stats;
                }
            }
            continue;
        }
        let c = n.first_child();
        for child in [c + 1, c] {
            stats.bv_tests += 1;
            if hit(&nodes[child as usize]) {
                stack.push(child);
            }
        }
    }
    stats
}

/// Reports every triangle of the tree (mesh placed by `pose`) whose leaf box
/// overlaps `query` (world frame) grown by `margin` (m) along its axes.
pub fn query_obb(
    tree: &ObbTree,
    pose: &Pose,
    query: &Obb,
    margin: f64,
    on_tri: impl FnMut(u32) -> Traverse,
) -> Result<TraversalStats, TraversalError> {
    check_nonneg("query margin", margin)?;
    // The query box in the mesh frame.
    let r_t = DMat3::from_quat(pose.rotation).transpose();
    let qc = r_t * (query.center - pose.position);
    let qa = r_t * query.axes;
    let hb = (query.half_extents + DVec3::splat(margin)).to_array();
    let hit = |n: &Node| {
        let na_t = n.axes_f64().transpose();
        let f = RelFrame::new(&(na_t * qa), na_t * (qc - n.center_f64()));
        !obb_disjoint(n.half_f64(), hb, &f)
    };
    Ok(walk(tree, hit, on_tri))
}

/// Reports every triangle whose leaf box overlaps the world-space
/// axis-aligned box `[min, max]` grown by `margin` (m).
pub fn query_aabb(
    tree: &ObbTree,
    pose: &Pose,
    min: DVec3,
    max: DVec3,
    margin: f64,
    on_tri: impl FnMut(u32) -> Traverse,
) -> Result<TraversalStats, TraversalError> {
    if !min.is_finite() || !max.is_finite() || !min.cmple(max).all() {
        return Err(TraversalError::BadParameter {
            what: "query AABB (min <= max, finite); min.x",
            value: min.x,
        });
    }
    query_obb(tree, pose, &Obb::from_aabb(min, max), margin, on_tri)
}

/// Reports every triangle whose leaf box comes within `radius` (m) of
/// `center` (world frame).
pub fn query_sphere(
    tree: &ObbTree,
    pose: &Pose,
    center: DVec3,
    radius: f64,
    on_tri: impl FnMut(u32) -> Traverse,
) -> Result<TraversalStats, TraversalError> {
    check_nonneg("query sphere radius", radius)?;
    let c = pose.inverse_transform_point(center);
    // The f32 axes are orthonormal to ~1e-7: a relative slack keeps the
    // per-axis distance sum conservative.
    let r2 = (radius * (1.0 + 1e-6)).powi(2);
    let hit = |n: &Node| {
        let u = n.axes_f64().transpose() * (c - n.center_f64());
        let h = DVec3::from_array(n.half_f64());
        let e = (u.abs() - h).max(DVec3::ZERO);
        e.length_squared() <= r2
    };
    Ok(walk(tree, hit, on_tri))
}

/// Reports every triangle whose leaf box reaches within `margin` (m) of the
/// world-space half-space `normal . x <= offset` (`normal` a unit vector;
/// the caller validates it, e.g. through [`crate::shape::HalfSpace`]).
pub fn query_halfspace(
    tree: &ObbTree,
    pose: &Pose,
    normal: DVec3,
    offset: f64,
    margin: f64,
    on_tri: impl FnMut(u32) -> Traverse,
) -> Result<TraversalStats, TraversalError> {
    check_nonneg("query margin", margin)?;
    if !normal.is_finite() || !offset.is_finite() {
        return Err(TraversalError::BadParameter {
            what: "half-space offset (finite, with a finite normal)",
            value: offset,
        });
    }
    // The plane in the mesh frame.
    let n = pose.rotation.conjugate() * normal;
    let d = offset - normal.dot(pose.position);
    let hit = |node: &Node| box_height_above(node, n, d) <= margin;
    Ok(walk(tree, hit, on_tri))
}

/// Lowest signed height of the node's box above the plane `n . x = d` (m;
/// negative when the box reaches below it), with a relative slack so that
/// round-off never makes it larger than the height of a contained vertex.
#[inline]
pub(crate) fn box_height_above(node: &Node, n: DVec3, d: f64) -> f64 {
    let a = node.axes_f64();
    let h = node.half_f64();
    let reach = h[0] * n.dot(a.x_axis).abs() + h[1] * n.dot(a.y_axis).abs() + h[2] * n.dot(a.z_axis).abs();
    let centre = n.dot(node.center_f64()) - d;
    centre - reach - 1e-12 * (centre.abs() + reach)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::traverse::tests::{random_pose, rng};
    use crate::math::DQuat;
    use crate::mesh::torus_mesh;

    #[test]
    fn queries_report_every_triangle_with_a_vertex_inside() {
        let m = torus_mesh(1.0, 0.3, 24, 12).unwrap();
        let t = ObbTree::build(&m).unwrap();
        let mut r = rng(17);
        for _ in 0..30 {
            let pose = random_pose(&mut r, 1.0);
            let world: Vec<[DVec3; 3]> = (0..m.triangles().len())
                .map(|i| m.triangle(i).map(|v| pose.transform_point(v)))
                .collect();
            let center = DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 3.0;
            let radius = 0.2 + r() * 0.5;
            let q = DQuat::from_xyzw(r() - 0.5, r() - 0.5, r() - 0.5, r() - 0.5).normalize();
            let obb = Obb {
                center,
                axes: DMat3::from_quat(q),
                half_extents: DVec3::new(r(), r(), r()) * 0.5,
            };
            let (lo, hi) = (center - DVec3::splat(radius), center + DVec3::splat(radius));
            let mut s = vec![];
            query_sphere(&t, &pose, center, radius, |i| {
                s.push(i);
                Traverse::Continue
            })
            .unwrap();
            let mut o = vec![];
            query_obb(&t, &pose, &obb, 0.0, |i| {
                o.push(i);
                Traverse::Continue
            })
            .unwrap();
            let mut a = vec![];
            query_aabb(&t, &pose, lo, hi, 0.0, |i| {
                a.push(i);
                Traverse::Continue
            })
            .unwrap();
            let aabb = Obb::from_aabb(lo, hi);
            for (i, tri) in world.iter().enumerate() {
                let i = i as u32;
                if tri.iter().any(|v| (*v - center).length() <= radius) {
                    assert!(s.contains(&i));
                }
                if tri.iter().any(|v| obb.contains(*v, 0.0)) {
                    assert!(o.contains(&i));
                }
                if tri.iter().any(|v| aabb.contains(*v, 0.0)) {
                    assert!(a.contains(&i));
                }
            }
            // Pruning: the sphere query never reports every triangle of a
            // torus when the sphere is smaller than the hole.
            assert!(s.len() < world.len());
        }
        let p = Pose::IDENTITY;
        assert!(query_sphere(&t, &p, DVec3::ZERO, -1.0, |_| Traverse::Continue).is_err());
        assert!(query_aabb(&t, &p, DVec3::ONE, DVec3::ZERO, 0.0, |_| Traverse::Continue).is_err());
    }

    // Same torus, tree and seeded rng as the test above (and as the tests of
    // volume_distance.rs): each test owns its setup and seed, so one can be
    // changed without moving the cases of the others.
    #[test]
    fn halfspace_query_reports_every_triangle_within_the_margin() {
        let m = torus_mesh(1.0, 0.3, 24, 12).unwrap();
        let t = ObbTree::build(&m).unwrap();
        let mut r = rng(29);
        for _ in 0..30 {
            let pose = random_pose(&mut r, 1.0);
            let n = DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5).normalize();
            let offset = r() - 0.5;
            let margin = 0.2 * r();
            let mut got = vec![];
            let stats = query_halfspace(&t, &pose, n, offset, margin, |i| {
                got.push(i);
                Traverse::Continue
            })
            .unwrap();
            let mut want = 0;
            for i in 0..m.triangles().len() {
                let low = m
                    .triangle(i)
                    .iter()
                    .map(|&v| n.dot(pose.transform_point(v)) - offset)
                    .fold(f64::INFINITY, f64::min);
                if low <= margin {
                    want += 1;
                    assert!(got.contains(&(i as u32)), "missed triangle {i} at height {low}");
                }
            }
            // Pruning: far fewer triangles than all when the plane cuts the torus.
            if want > 0 && want < m.triangles().len() / 4 {
                assert!(got.len() < m.triangles().len(), "{stats:?}");
            }
        }
        let p = Pose::IDENTITY;
        assert!(query_halfspace(&t, &p, DVec3::Z, 0.0, -1.0, |_| Traverse::Continue).is_err());
        assert!(query_halfspace(&t, &p, DVec3::Z, f64::NAN, 0.0, |_| Traverse::Continue).is_err());
    }
}
