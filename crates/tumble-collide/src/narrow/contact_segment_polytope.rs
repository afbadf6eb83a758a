//! Sphere or capsule vs polytope (box or convex hull): the round shape is its
//! core (a point or a segment) inflated by its radius, so the contact comes
//! from the distance between the core and the polytope (Ericson 9.5; van den
//! Bergen 2003, 4.3):
//!
//! - core outside: GJK gives the distance and closest points; when the closest
//!   point lies inside a face (GJK normal = face normal), the core segment is
//!   clipped to that face's prism and both clipped ends become contacts, so a
//!   capsule lying on a box gets a 2-point manifold;
//! - core touching or inside: GJK cannot give a depth, so a separating-axis
//!   test over the face normals and the (edge x segment) axes finds the
//!   direction of least penetration (exact for a point; for a segment the
//!   candidate set is complete, as for two polytopes).

use super::capsule_feature;
use super::geometry::closest_points_segments;
use super::gjk::{gjk_distance, PolytopeSupport, SegmentSupport};
use crate::contact::{Contact, ContactKind, Feature};
use crate::math::{DMat3, DVec3};
use crate::pose::Pose;
use crate::shape::{Capsule, Polytope, Sphere};

/// Contact between sphere A and polytope B (box or convex hull), at most one.
// Signature of every narrow routine (the `dispatch` table calls them alike);
// compare `contact_sphere_mesh` in contact_mesh.rs, which walks triangles.
pub fn contact_sphere_polytope<P: Polytope + ?Sized>(
    a: &Sphere,
    pose_a: &Pose,
    b: &P,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    let c = pose_a.position;
    segment_polytope([c, c], a.radius(), |_| Feature::WHOLE, b, pose_b, margin, out);
}

/// Contacts between capsule A and polytope B (box or convex hull): one, or
/// two when the capsule lies along a face.
pub fn contact_capsule_polytope<P: Polytope + ?Sized>(
    a: &Capsule,
    pose_a: &Pose,
    b: &P,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    segment_polytope(
        a.world_segment(pose_a),
        a.radius(),
        capsule_feature,
        b,
        pose_b,
        margin,
        out,
    );
}

/// How much an edge axis must beat the best face axis before it is used
/// (relative to the face separation, plus an absolute part relative to size):
/// face contacts are steadier.
const EDGE_REL_BIAS: f64 = 0.05;
const ABS_BIAS: f64 = 1e-6;
/// A capsule counts as lying along a face when the sine of the angle between
/// its axis and the face is at most this (about 3 degrees).
pub(crate) const PARALLEL_SIN: f64 = 0.05;

/// Whether segment `s0 s1` and polytope `b` (both in B's frame) are more
/// than `reach` apart along one of B's axes: their distance is then larger
/// still, and GJK's larger again (its distance is the length of a point of
/// A - B, never shorter than the true distance), so the pair has no
/// contact within the margin and GJK (most of the cost of a capsule near
/// a box) can be skipped. `reach` carries a hair of slack over the radius
/// and margin so that rounding in GJK cannot bring it back in.
fn apart_along_axes<P: Polytope + ?Sized>(s0: DVec3, s1: DVec3, b: &P, reach: f64) -> bool {
    let (lo, hi) = (s0.min(s1), s0.max(s1));
    (0..3).any(|axis| {
        let e = DVec3::AXES[axis];
        let top = b.vertex(b.support_vertex(e))[axis];
        let bottom = b.vertex(b.support_vertex(-e))[axis];
        lo[axis] - top > reach || bottom - hi[axis] > reach
    })
}

#[allow(clippy::too_many_arguments)]
fn segment_polytope<P: Polytope + ?Sized>(
    seg_world: [DVec3; 2],
    radius: f64,
    seg_feature: impl Fn(f64) -> Feature,
    b: &P,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    // Work in B's frame.
    let s0 = pose_b.inverse_transform_point(seg_world[0]);
    let s1 = pose_b.inverse_transform_point(seg_world[1]);
    let scale = (0..b.vertex_count().min(8))
        .map(|i| b.vertex(i).length())
        .fold(radius, f64::max);
    if apart_along_axes(s0, s1, b, radius + margin + 1e-9 * scale) {
        return;
    }
    let poly = PolytopeSupport {
        poly: b,
        rot: DMat3::IDENTITY,
        trans: DVec3::ZERO,
    };
    let g = gjk_distance(&SegmentSupport([s0, s1]), &poly, scale);
    let emit = |n_local: DVec3,
                p_core: DVec3,
                p_b: DVec3,
                distance: f64,
                t: f64,
                face: usize,
                out: &mut Vec<Contact>| {
        let pa = p_core - n_local * radius;
        out.push(Contact {
            point: pose_b.transform_point((pa + p_b) * 0.5),
            normal: pose_b.transform_vector(n_local),
            distance,
            kind: ContactKind::Smooth,
            feature_a: seg_feature(t),
            feature_b: Feature::face(face as u32),
        });
    };
    let param = |p: DVec3| {
        let d = s1 - s0;
        let l2 = d.length_squared();
        if l2 > 0.0 {
            ((p - s0).dot(d) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        }
    };
    if !g.overlap {
        if g.distance - radius > margin {
            return;
        }
        let n = (g.point_a - g.point_b) / g.distance;
        let f = b.best_face(n);
        if b.face_normal(f).dot(n) >= 1.0 - 1e-9
            && face_prism_manifold(s0, s1, radius, b, f, margin, &seg_feature, pose_b, out)
        {
            return;
        }
        emit(
            n,
            g.point_a,
            g.point_b,
            g.distance - radius,
            param(g.point_a),
            f,
            out,
        );
        return;
    }

    // Overlapping core: least-penetration axis over faces and edge x segment.
    let mut best_face = 0;
    let mut face_sep = f64::NEG_INFINITY;
    for f in 0..b.face_count() {
        let n = b.face_normal(f);
        let sep = n.dot(s0).min(n.dot(s1)) - b.face_offset(f);
        if sep > face_sep {
            face_sep = sep;
            best_face = f;
        }
    }
    let dir = s1 - s0;
    let mut edge_best: Option<(f64, DVec3, usize)> = None;
    if dir.length_squared() > 0.0 {
        let centre = b.interior_point();
        for e in 0..b.edge_count() {
            let ([v0, v1], _) = b.edge(e);
            let (p, q) = (b.vertex(v0 as usize), b.vertex(v1 as usize));
            let axis = (q - p).cross(dir);
            let len = axis.length();
            if len <= 1e-9 * (q - p).length() * dir.length() {
                continue;
            }
            let mut l = axis / len;
            if l.dot(p - centre) < 0.0 {
                l = -l;
            }
            let sep = l.dot(s0).min(l.dot(s1)) - l.dot(b.vertex(b.support_vertex(l)));
            if !matches!(edge_best, Some((s, _, _)) if s >= sep) {
                edge_best = Some((sep, l, e));
            }
        }
    }
    if let Some((sep, l, e)) = edge_best {
        if sep > face_sep + EDGE_REL_BIAS * face_sep.abs() + ABS_BIAS * scale && sep - radius <= margin {
            let ([v0, v1], _) = b.edge(e);
            let (p, q) = (b.vertex(v0 as usize), b.vertex(v1 as usize));
            let (t, _, pc, pe) = closest_points_segments(s0, s1, p, q);
            // Depth along the axis, not the (zero) core-to-edge distance.
            let pb = pc - l * sep;
            let _ = pe;
            emit(l, pc, pb, sep - radius, t, b.best_face(l), out);
            return;
        }
    }
    let want = face_sep - radius;
    if want <= margin {
        let start = out.len();
        let ok = face_prism_manifold(s0, s1, radius, b, best_face, margin, &seg_feature, pose_b, out);
        let got = out[start..]
            .iter()
            .map(|c| c.distance)
            .fold(f64::INFINITY, f64::min);
        if !ok || got > want + 1e-9 * scale {
            // The deepest end lies outside the face's prism (the core dives
            // under an edge): report it unclipped with the SAT depth, so that
            // pushing out by the reported depth does separate.
            out.truncate(start);
            let n = b.face_normal(best_face);
            let (p, t) = if n.dot(s0) <= n.dot(s1) {
                (s0, 0.0)
            } else {
                (s1, 1.0)
            };
            let foot = p - n * (n.dot(p) - b.face_offset(best_face));
            emit(n, p, foot, want, t, best_face, out);
        }
    }
}

/// Clips the core segment to the prism over face `f` and pushes a contact for
/// each clipped end within the margin (one if the ends coincide). Returns
/// whether anything was clipped inside the prism.
#[allow(clippy::too_many_arguments)]
fn face_prism_manifold<P: Polytope + ?Sized>(
    s0: DVec3,
    s1: DVec3,
    radius: f64,
    b: &P,
    f: usize,
    margin: f64,
    seg_feature: &impl Fn(f64) -> Feature,
    pose_b: &Pose,
    out: &mut Vec<Contact>,
) -> bool {
    let n = b.face_normal(f);
    let d = b.face_offset(f);
    let k = b.face_len(f);
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let dir = s1 - s0;
    for j in 0..k {
        let v0 = b.vertex(b.face_vertex(f, j));
        let v1 = b.vertex(b.face_vertex(f, (j + 1) % k));
        let side = (v1 - v0).cross(n);
        // side . (s0 + t dir) <= side . v0
        let a = side.dot(s0) - side.dot(v0);
        let rate = side.dot(dir);
        if rate.abs() <= 1e-300 {
            if a > 0.0 {
                return false;
            }
        } else {
            let t = -a / rate;
            if rate > 0.0 {
                hi = hi.min(t);
            } else {
                lo = lo.max(t);
            }
        }
    }
    if lo > hi {
        return false;
    }
    let same = (hi - lo) * dir.length() <= 1e-12 * (1.0 + s0.length());
    // Both clipped ends when the core lies (nearly) along the face. For a
    // slanted core the deeper end, and the shallower one where the capsule
    // is within the margin of the face beneath it but not touching
    // (speculative): a manifold holds for the whole step, and a slanted limb
    // turning down onto the ground brought its upper end 2 cm into it with
    // the deeper end alone (a ragdoll's forearm). Beneath a slanted core the
    // capsule's surface is its cylinder, r / sqrt(1 - (n.u)^2) below the
    // core (the end sphere's lowest point p - n r lies inside the capsule).
    let len = dir.length();
    let slope = if len > 0.0 { n.dot(dir) / len } else { 0.0 };
    let parallel = len > 0.0 && slope.abs() <= PARALLEL_SIN;
    let (deeper, shallower) = if slope >= 0.0 { (lo, hi) } else { (hi, lo) };
    let ends = match (same, parallel) {
        (true, _) => [Some(lo), None],
        (false, true) => [Some(lo), Some(hi)],
        (false, false) => [Some(deeper), Some(shallower)],
    };
    for (k, t) in ends.into_iter().enumerate() {
        let Some(t) = t else { continue };
        let p = s0 + dir * t;
        let (below, on_cylinder) = if k == 1 && !parallel {
            // The cylinder's surface beneath p, if that part of the
            // capsule is cylinder (its axis foot inside the core).
            let sink = radius / (1.0 - slope * slope).sqrt();
            // p - n s projects on the core at t - s slope / len.
            let foot = t - sink * slope / len;
            if !(foot > 0.0 && foot < 1.0) {
                continue;
            }
            (sink, Some(foot))
        } else {
            (radius, None)
        };
        let dist = n.dot(p) - d - below;
        if k == 1 && !parallel && dist <= 0.0 {
            continue;
        }
        if dist <= margin {
            // Midpoint of the capsule's surface point p - n below and its
            // projection on the face plane p - n (dist + below).
            let point = p - n * (below + 0.5 * dist);
            let t_feature = if same { 0.5 } else { t };
            let t_feature = if t <= 0.0 || t >= 1.0 { t } else { t_feature };
            // A point on the cylinder belongs to the core's inside.
            let t_feature = on_cylinder.unwrap_or(t_feature);
            out.push(Contact {
                point: pose_b.transform_point(point),
                normal: pose_b.transform_vector(n),
                distance: dist,
                kind: ContactKind::Smooth,
                feature_a: seg_feature(t_feature),
                feature_b: Feature::face(f as u32),
            });
        }
    }
    true
}
