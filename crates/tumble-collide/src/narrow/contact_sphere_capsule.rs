//! Sphere vs capsule: the sphere centre against the closest point of the
//! capsule's core segment (Ericson 5.1.2).

use super::geometry::closest_point_on_segment;
use super::{capsule_feature, push_ball_ball};
use crate::contact::{Contact, Feature};
use crate::math::DVec3;
use crate::pose::Pose;
use crate::shape::{Capsule, Sphere};

/// Contact between sphere A and capsule B (at most one).
// Same six arguments as the other narrow routines (the `dispatch` table's
// row shape); what is its own is the point-segment closest point, one contact.
pub fn contact_sphere_capsule(
    a: &Sphere,
    pose_a: &Pose,
    b: &Capsule,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    let [p, q] = b.world_segment(pose_b);
    let (t, c) = closest_point_on_segment(pose_a.position, p, q);
    push_ball_ball(
        pose_a.position,
        a.radius(),
        c,
        b.radius(),
        Feature::WHOLE,
        capsule_feature(t),
        // Centre on the core: any direction perpendicular to the core frees it.
        (q - p).normalize_or(DVec3::X).any_orthonormal_vector(),
        margin,
        out,
    );
}
