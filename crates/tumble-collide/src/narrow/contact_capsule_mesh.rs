//! Capsule vs triangle mesh: the capsule is its core segment inflated by its
//! radius, so every triangle near the capsule's box contributes the closest
//! points of the core and the triangle (Ericson, Real-Time Collision
//! Detection 5.1.9: for a disjoint segment and triangle the minimum is at an
//! end point against the triangle or at the segment against an edge).
//!
//! - Core apart from the triangle: one contact along the closest-point
//!   direction; when the capsule lies along the face (axis within
//!   [`PARALLEL_SIN`] of the plane), each core end that projects inside the
//!   face is a contact too, so a capsule resting on a mesh gets two points.
//! - Core touching or crossing the triangle: the capsule is pushed out along
//!   the triangle's outward normal, from its deepest core end (as
//!   `contact_sphere_mesh` does for a centre inside).
//!
//! As for spheres, a closest point on an internal edge between coplanar
//! triangles (or at a vertex between two such edges) is left to the
//! neighbouring face, and duplicates from shared edges are merged. On a
//! mesh with a smooth surface (`shape::SmoothSurface`) the core's nearest
//! point and its ends touch that surface instead, where they lie over it.

use super::capsule_feature;
use super::smooth_foot::{push_foot_contact, smooth_foot, SmoothFoot};
use crate::bvh::{self, Obb, Traverse};
use crate::contact::{Contact, ContactKind, Feature, SubFeature};
use crate::math::{DMat3, DVec3};
use crate::pose::Pose;
use crate::shape::{Capsule, MeshShape, SmoothSurface};
use crate::triangle::{
    closest_point_on_triangle, closest_points_segments, merge_contacts, segment_triangle_overlap, MergeParams,
};

/// A capsule counts as lying along a face when the sine of the angle between
/// its axis and the face plane is at most this (about 3 degrees; the value
/// of the capsule-polytope routine).
pub const PARALLEL_SIN: f64 = 0.05;

/// Contacts between capsule A and mesh B within `margin` (m), normals from
/// the mesh towards the capsule.
// Opens like every narrow routine (the `dispatch` signature); the body
// differs from `contact_sphere_mesh` (contact_mesh.rs) in querying the
// tree with the capsule's box and testing the core segment, not a point.
pub fn contact_capsule_mesh(
    a: &Capsule,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    let [p, q] = a.world_segment(pose_a);
    let r = a.radius();
    let query = Obb {
        center: pose_a.position,
        axes: DMat3::from_quat(pose_a.rotation),
        half_extents: DVec3::new(r, r, a.half_height() + r),
    };
    let start = out.len();
    let smooth = b.smooth_surface();
    let reach = smooth.map_or(0.0, |s| s.reach());
    // The core in the mesh's frame, where its smooth surface is.
    let local = smooth.map(|_| {
        [
            pose_b.inverse_transform_point(p),
            pose_b.inverse_transform_point(q),
        ]
    });
    let _ = bvh::query_obb(b.tree(), pose_b, &query, margin + reach, |t| {
        if let (Some(s), Some(local)) = (smooth, local) {
            if smooth_segment_contacts(local, r, s, b, t, pose_b, margin, out) {
                return Traverse::Continue;
            }
        }
        let tri = b.mesh().triangle(t as usize).map(|v| pose_b.transform_point(v));
        segment_triangle_contacts([p, q], r, &tri, t, b, margin, out);
        Traverse::Continue
    });
    let mut tail = out.split_off(start);
    // The default parameters are valid: merging cannot fail.
    let _ = merge_contacts(&mut tail, &[], b.mesh().triangles(), &MergeParams::default());
    out.extend(tail);
}

/// The contacts of the core `seg` (radius `r`, mesh B's frame) against the
/// smooth surface over triangle `t` (`shape::SmoothSurface`): the feet of
/// the core point nearest the flat triangle and of the two core ends, each
/// where it lies over `t` (a capsule lying in a trough gets its two ends
/// and its middle). `false` when the flat triangle decides instead (the
/// core crosses it, or a candidate lies beyond a crease): then nothing is
/// appended.
#[allow(clippy::too_many_arguments)]
fn smooth_segment_contacts(
    seg: [DVec3; 2],
    r: f64,
    s: &SmoothSurface,
    m: &MeshShape,
    t: u32,
    pose: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) -> bool {
    let tri = m.mesh().triangle(t as usize);
    if segment_triangle_overlap(seg[0], seg[1], &tri) {
        return false;
    }
    let (nearest, on_seg, _, _) = closest_segment_triangle(seg, &tri);
    let mut feet = [None; 3];
    for (slot, (k, x)) in feet
        .iter_mut()
        .zip([(nearest, on_seg), (0.0, seg[0]), (1.0, seg[1])])
    {
        match smooth_foot(s, m, t, x, r) {
            SmoothFoot::Over(foot) => *slot = Some((k, foot)),
            SmoothFoot::Neighbour => {}
            SmoothFoot::Crease => return false,
        }
    }
    for (k, foot) in feet.into_iter().flatten() {
        push_foot_contact(out, &foot, r, pose, margin, capsule_feature(k), t);
    }
    true
}

/// Closest points of the segment `seg` and triangle `t` (disjoint): segment
/// parameter, point on the segment, point on the triangle, triangle feature.
fn closest_segment_triangle(seg: [DVec3; 2], t: &[DVec3; 3]) -> (f64, DVec3, DVec3, SubFeature) {
    let mut best = (0.0, seg[0], seg[0], SubFeature::Face);
    let mut best_d2 = f64::INFINITY;
    for (s, e) in [(0.0, seg[0]), (1.0, seg[1])] {
        let (x, sub) = closest_point_on_triangle(e, t);
        let d2 = (e - x).length_squared();
        if d2 < best_d2 {
            best_d2 = d2;
            best = (s, e, x, sub);
        }
    }
    for k in 0..3 {
        let c = closest_points_segments(seg[0], seg[1], t[k], t[(k + 1) % 3]);
        let d2 = (c.point_a - c.point_b).length_squared();
        if d2 < best_d2 {
            best_d2 = d2;
            let sub = if c.t <= 0.0 {
                SubFeature::Vertex(k as u8)
            } else if c.t >= 1.0 {
                SubFeature::Vertex(((k + 1) % 3) as u8)
            } else {
                SubFeature::Edge(k as u8)
            };
            best = (c.s, c.point_a, c.point_b, sub);
        }
    }
    best
}

/// Unit normal of a triangle with an area (relative test), else `None`.
fn unit_normal(t: &[DVec3; 3]) -> Option<DVec3> {
    let raw = (t[1] - t[0]).cross(t[2] - t[0]);
    let longest2 = (t[1] - t[0])
        .length_squared()
        .max((t[2] - t[1]).length_squared())
        .max((t[0] - t[2]).length_squared());
    (raw.length() > 1e-12 * longest2).then(|| raw.normalize())
}

/// The contacts of the core `seg` (radius `r`) against world triangle `t`
/// (id `id` of mesh `m`).
fn segment_triangle_contacts(
    seg: [DVec3; 2],
    r: f64,
    t: &[DVec3; 3],
    id: u32,
    m: &MeshShape,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    let face = unit_normal(t);
    if segment_triangle_overlap(seg[0], seg[1], t) {
        // Zero-area triangles have no normal: their neighbours report.
        let Some(n) = face else { return };
        let h = [n.dot(seg[0] - t[0]), n.dot(seg[1] - t[0])];
        let k = if h[0] <= h[1] { 0 } else { 1 };
        let distance = h[k] - r;
        if distance <= margin {
            out.push(Contact {
                // Midpoint of the capsule's deepest point and its projection.
                point: seg[k] - n * (r + 0.5 * distance),
                normal: n,
                distance,
                kind: ContactKind::Penetrating,
                feature_a: capsule_feature(k as f64),
                feature_b: Feature::face(id),
            });
        }
        return;
    }
    let (s, on_seg, on_tri, sub) = closest_segment_triangle(seg, t);
    let delta = on_seg - on_tri;
    let d = delta.length();
    if d - r > margin {
        return;
    }
    let normal = if d > 1e-12 * (1.0 + r) {
        delta / d
    } else {
        face.unwrap_or(DVec3::ZERO)
    };
    // A closest point on an internal edge is the neighbour face's, unless
    // it lies straight below the core (then it is a face point of both).
    let keep = !is_internal(m, id, sub) || face.is_some_and(|n| along(normal, n));
    if keep && normal != DVec3::ZERO {
        out.push(Contact {
            point: on_tri + normal * (0.5 * (d - r)),
            normal,
            distance: d - r,
            kind: ContactKind::Smooth,
            feature_a: capsule_feature(s),
            feature_b: Feature { index: id, sub },
        });
    }
    // Lying along the face: the core ends above the face are contacts too.
    let Some(n) = face else { return };
    let axis = seg[1] - seg[0];
    if axis.length_squared() == 0.0 || n.dot(axis).abs() > PARALLEL_SIN * axis.length() {
        return;
    }
    let side = if n.dot(delta) >= 0.0 { n } else { -n };
    for (s_end, e) in [(0.0, seg[0]), (1.0, seg[1])] {
        let (x, sub) = closest_point_on_triangle(e, t);
        let h = side.dot(e - x);
        let above = sub == SubFeature::Face || (is_internal(m, id, sub) && along(e - x, side));
        if above && h > 0.0 && h - r <= margin {
            out.push(Contact {
                point: x + side * (0.5 * (h - r)),
                normal: side,
                distance: h - r,
                kind: ContactKind::Smooth,
                feature_a: capsule_feature(s_end),
                feature_b: Feature::face(id),
            });
        }
    }
}

/// `true` for an internal edge of triangle `id` (shared with a coplanar
/// neighbour), or a corner between two such edges.
fn is_internal(m: &MeshShape, id: u32, sub: SubFeature) -> bool {
    match sub {
        SubFeature::Edge(k) => m.is_flat_edge(id, k),
        SubFeature::Vertex(k) => m.is_flat_edge(id, k) && m.is_flat_edge(id, (k + 2) % 3),
        _ => false,
    }
}

/// `v` points along the unit normal `n` (or against it), to round-off.
fn along(v: DVec3, n: DVec3) -> bool {
    n.dot(v).abs() >= (1.0 - 1e-9) * v.length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::traverse::tests::{random_pose, rng};
    use crate::math::DQuat;
    use crate::mesh::{box_mesh, torus_mesh};
    use crate::narrow::{contact_capsule_polytope, contact_shapes};
    use crate::shape::{Cuboid, Shape};

    fn deepest(out: &[Contact]) -> f64 {
        out.iter().map(|c| c.distance).fold(f64::INFINITY, f64::min)
    }

    /// A capsule lying on the top face of a box mesh: two contacts at the
    /// core ends, at the gap, normal +z; the same as against a cuboid.
    #[test]
    fn lying_capsule_gets_two_end_contacts() {
        let mesh = MeshShape::new(box_mesh(DVec3::new(1.0, 1.0, 0.5)).unwrap()).unwrap();
        let cap = Capsule::new(0.1, 0.3).unwrap();
        let cuboid = Cuboid::new(DVec3::new(1.0, 1.0, 0.5)).unwrap();
        let lying = DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2) * DQuat::from_rotation_z(0.3);
        for gap in [0.02, 0.0, -0.03] {
            let pose = Pose::new(DVec3::new(0.2, -0.1, 0.5 + 0.1 + gap), lying).unwrap();
            let mut out = Vec::new();
            contact_capsule_mesh(&cap, &pose, &mesh, &Pose::IDENTITY, 0.05, &mut out);
            let mut box_out = Vec::new();
            contact_capsule_polytope(&cap, &pose, &cuboid, &Pose::IDENTITY, 0.05, &mut box_out);
            assert_eq!(out.len(), 2, "gap {gap}: {out:?}");
            for c in &out {
                assert!((c.distance - gap).abs() < 1e-12, "{c:?}");
                assert!((c.normal - DVec3::Z).length() < 1e-12);
                assert!((c.point.z - (0.5 + 0.5 * gap)).abs() < 1e-12);
            }
            assert!((deepest(&out) - deepest(&box_out)).abs() < 1e-12);
            // The two contacts are the two core ends, 0.6 m apart.
            assert!(((out[0].point - out[1].point).length() - 0.6).abs() < 1e-9);
        }
    }

    /// An upright capsule pushed into the top face: one contact from the
    /// deepest core end, depth = r - height of that end.
    #[test]
    fn upright_capsule_end_penetrates_and_crossing_core_pushes_out() {
        let mesh = MeshShape::new(box_mesh(DVec3::new(1.0, 1.0, 0.5)).unwrap()).unwrap();
        let cap = Capsule::new(0.1, 0.3).unwrap();
        // Lower core end 0.04 above the top face: depth 0.06.
        let pose = Pose::from_translation(DVec3::new(0.15, 0.25, 0.5 + 0.3 + 0.04));
        let mut out = Vec::new();
        contact_capsule_mesh(&cap, &pose, &mesh, &Pose::IDENTITY, 0.0, &mut out);
        assert_eq!(out.len(), 1, "{out:?}");
        assert!((out[0].distance + 0.06).abs() < 1e-12);
        assert!((out[0].normal - DVec3::Z).length() < 1e-12);
        // Core crossing the top face, lower end 0.05 below it: pushed out
        // along +z by 0.05 + r.
        let pose = Pose::from_translation(DVec3::new(0.15, 0.25, 0.5 + 0.3 - 0.05));
        let mut out = Vec::new();
        contact_capsule_mesh(&cap, &pose, &mesh, &Pose::IDENTITY, 0.0, &mut out);
        assert!((deepest(&out) + 0.15).abs() < 1e-12, "{out:?}");
        assert!(out.iter().all(|c| (c.normal - DVec3::Z).length() < 1e-12));
    }

    /// Against a torus at random poses: the deepest contact is the core's
    /// distance to the mesh (brute force over all triangles) minus r, and
    /// there is a contact exactly when that is within the margin.
    #[test]
    fn deepest_contact_matches_brute_force_core_distance() {
        let torus = torus_mesh(1.0, 0.3, 24, 12).unwrap();
        let mesh = MeshShape::new(torus.clone()).unwrap();
        let cap = Capsule::new(0.15, 0.4).unwrap();
        let mut r = rng(77);
        let (mut hits, margin) = (0, 0.05);
        for _ in 0..200 {
            let pc = random_pose(&mut r, 3.0);
            let pm = random_pose(&mut r, 0.5);
            let [p, q] = cap.world_segment(&pc);
            let mut core = f64::INFINITY;
            let mut crossing = false;
            for t in 0..torus.triangles().len() {
                let tri = torus.triangle(t).map(|v| pm.transform_point(v));
                crossing |= segment_triangle_overlap(p, q, &tri);
                let (_, a, b, _) = closest_segment_triangle([p, q], &tri);
                core = core.min((a - b).length());
            }
            let mut out = Vec::new();
            contact_capsule_mesh(&cap, &pc, &mesh, &pm, margin, &mut out);
            if crossing {
                assert!(!out.is_empty() && deepest(&out) < 0.0);
                continue;
            }
            let want = core - cap.radius();
            if want <= margin {
                hits += 1;
                assert!((deepest(&out) - want).abs() < 1e-9, "{} vs {want}", deepest(&out));
            } else {
                assert!(out.is_empty());
            }
        }
        assert!(hits > 20, "too few touching poses: {hits}");
    }

    #[test]
    fn dispatch_routes_both_orders_and_flips() {
        let m = Shape::Mesh(MeshShape::new(box_mesh(DVec3::splat(0.5)).unwrap()).unwrap());
        let c = Shape::Capsule(Capsule::new(0.1, 0.3).unwrap());
        let pc = Pose::from_translation(DVec3::new(0.1, 0.0, 0.5 + 0.3 + 0.05));
        let (mut ab, mut ba) = (Vec::new(), Vec::new());
        contact_shapes(&c, &pc, &m, &Pose::IDENTITY, 0.0, &mut ab).unwrap();
        contact_shapes(&m, &Pose::IDENTITY, &c, &pc, 0.0, &mut ba).unwrap();
        assert!(!ab.is_empty());
        assert_eq!(ab.iter().map(|x| x.flipped()).collect::<Vec<_>>(), ba);
    }
}
