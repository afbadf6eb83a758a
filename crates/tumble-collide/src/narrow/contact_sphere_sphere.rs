//! Sphere vs sphere: the centre line is the normal (Ericson 4.3.1).

use super::push_ball_ball;
use crate::contact::{Contact, Feature};
use crate::math::DVec3;
use crate::pose::Pose;
use crate::shape::Sphere;

/// Contact between sphere A and sphere B (at most one).
pub fn contact_sphere_sphere(
    a: &Sphere,
    pose_a: &Pose,
    b: &Sphere,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    push_ball_ball(
        pose_a.position,
        a.radius(),
        pose_b.position,
        b.radius(),
        Feature::WHOLE,
        Feature::WHOLE,
        DVec3::Z,
        margin,
        out,
    );
}
