//! Shapes vs half-space (ground): every supporting point of the shape below
//! `margin` above the plane is a contact (Ericson 5.2.2, plane tests): the
//! sphere's lowest point, both end spheres of a capsule, the corners of a box
//! or the vertices of a hull (reduced to the 4 that span the largest area).
//! The half-space is always shape B; the normal is its outward plane normal.

use super::capsule_feature;
use super::reduce::reduce_to_four;
use crate::contact::{Contact, ContactKind, Feature};
use crate::math::DVec3;
use crate::pose::Pose;
use crate::shape::{Capsule, HalfSpace, Polytope, Sphere};

/// Contact between sphere A and half-space B (at most one).
pub fn contact_sphere_halfspace(
    a: &Sphere,
    pose_a: &Pose,
    b: &HalfSpace,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    push_ball_plane(
        pose_a.position,
        a.radius(),
        Feature::WHOLE,
        b,
        pose_b,
        margin,
        out,
    );
}

/// Contacts between capsule A and half-space B: each end sphere within the
/// margin (one when the capsule has zero length).
// The narrow routines' shared signature (see `narrow`); against a plane a
// capsule is just its two end spheres, which is all this body adds.
pub fn contact_capsule_halfspace(
    a: &Capsule,
    pose_a: &Pose,
    b: &HalfSpace,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    let [p, q] = a.world_segment(pose_a);
    push_ball_plane(p, a.radius(), capsule_feature(0.0), b, pose_b, margin, out);
    if a.half_height() > 0.0 {
        push_ball_plane(q, a.radius(), capsule_feature(1.0), b, pose_b, margin, out);
    }
}

fn push_ball_plane(
    c: DVec3,
    r: f64,
    fa: Feature,
    b: &HalfSpace,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    let (n, d) = b.world_plane(pose_b);
    let dist = n.dot(c) - d;
    if dist - r > margin {
        return;
    }
    let distance = dist - r;
    out.push(Contact {
        // Midpoint of the ball's lowest point c - n r and its projection.
        point: c - n * (r + 0.5 * distance),
        normal: n,
        distance,
        kind: ContactKind::Smooth,
        feature_a: fa,
        feature_b: Feature::face(0),
    });
}

/// Contacts between polytope A (box or convex hull) and half-space B: the
/// vertices within the margin (all of them up to 8, else reduced to 4).
// Starts like `contact_mesh_halfspace` (contact_mesh.rs): same plane, same
// `push_vertex_on_plane`. They part on the vertices' feature ids (a polytope
// has its own, a mesh names a vertex by its first triangle) and on reduction.
pub fn contact_polytope_halfspace<P: Polytope + ?Sized>(
    a: &P,
    pose_a: &Pose,
    b: &HalfSpace,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    let (n, d) = b.world_plane(pose_b);
    let start = out.len();
    for v in 0..a.vertex_count() {
        let p = pose_a.transform_point(a.vertex(v));
        push_vertex_on_plane(out, p, n, d, margin, a.vertex_feature(v));
    }
    // Up to 8 vertices (a whole box) are kept as they are: a reduction by
    // spread in the plane can drop a deep vertex in favour of a shallow one
    // above it (a thin plate landing on its face), and speculative contacts
    // need every vertex that can arrive within the step.
    if out.len() - start > 8 {
        reduce_in_place(out, start, n);
    }
}

/// A vertex of A at `p` (world) against the plane `n . x = d` of
/// half-space B: a vertex-face contact when it is within `margin`, its
/// point midway between the vertex and the plane.
pub(crate) fn push_vertex_on_plane(
    out: &mut Vec<Contact>,
    p: DVec3,
    n: DVec3,
    d: f64,
    margin: f64,
    feature_a: Feature,
) {
    let dist = n.dot(p) - d;
    if dist <= margin {
        out.push(Contact {
            point: p - n * (0.5 * dist),
            normal: n,
            distance: dist,
            kind: ContactKind::VertexFace,
            feature_a,
            feature_b: Feature::face(0),
        });
    }
}

/// Reduces the contacts `out[start..]` (on one plane of normal `n`) to
/// four well spread ones, in place.
pub(crate) fn reduce_in_place(out: &mut Vec<Contact>, start: usize, n: DVec3) {
    let count = out.len() - start;
    let (keep, k) = reduce_to_four(count, n, |i| (out[start + i].point, out[start + i].distance));
    for (slot, &i) in keep[..k].iter().enumerate() {
        out[start + slot] = out[start + i];
    }
    out.truncate(start + k);
}
