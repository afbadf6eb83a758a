//! Sphere vs box: the sphere centre is clamped to the box in the box frame
//! (Ericson 5.1.3); a centre inside the box is pushed out through the nearest
//! face.

use crate::contact::{Contact, ContactKind, Feature};
use crate::math::DVec3;
use crate::pose::Pose;
use crate::shape::{Cuboid, Polytope, Sphere};

/// Contact between sphere A and box B (at most one).
// Signature shared with every narrow routine (see `narrow`'s module docs);
// kept apart from `contact_sphere_polytope` because a box's clamp in its own
// frame is exact and needs no GJK.
pub fn contact_sphere_cuboid(
    a: &Sphere,
    pose_a: &Pose,
    b: &Cuboid,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    let h = b.half_extents();
    let c = pose_b.inverse_transform_point(pose_a.position);
    let q = c.clamp(-h, h);
    let diff = c - q;
    let (n_local, q, dist) = if diff != DVec3::ZERO {
        let len = diff.length();
        (diff / len, q, len)
    } else {
        // Inside: leave through the face with the least penetration.
        let slack = h - c.abs();
        let axis = if slack.x <= slack.y && slack.x <= slack.z {
            0
        } else if slack.y <= slack.z {
            1
        } else {
            2
        };
        let mut n = DVec3::ZERO;
        n[axis] = if c[axis] >= 0.0 { 1.0 } else { -1.0 };
        let mut q = c;
        q[axis] = n[axis] * h[axis];
        (n, q, -slack[axis])
    };
    let distance = dist - a.radius();
    if distance > margin {
        return;
    }
    let normal = pose_b.transform_vector(n_local);
    let pb = pose_b.transform_point(q);
    let pa = pose_a.position - normal * a.radius();
    out.push(Contact {
        point: (pa + pb) * 0.5,
        normal,
        distance,
        kind: ContactKind::Smooth,
        feature_a: Feature::WHOLE,
        feature_b: Feature::face(b.best_face(n_local) as u32),
    });
}
