//! Capsule vs capsule: closest points of the core segments (Ericson 5.1.9);
//! when the segments are parallel and overlap along their length (a capsule
//! lying on another) the manifold gets both ends of the overlap, so that the
//! pair does not rock about a single point.

use super::geometry::{closest_point_on_segment, closest_points_segments};
use super::{capsule_feature, push_ball_ball};
use crate::contact::Contact;
use crate::math::DVec3;
use crate::pose::Pose;
use crate::shape::Capsule;

/// Contacts between capsule A and capsule B (one, or two when parallel).
// The narrow phase's common signature (see the module docs of `narrow`);
// the body is capsule-only: segment-segment closest points plus the
// two-point manifold of parallel cores, which no other pair has.
pub fn contact_capsule_capsule(
    a: &Capsule,
    pose_a: &Pose,
    b: &Capsule,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    let [p1, q1] = a.world_segment(pose_a);
    let [p2, q2] = b.world_segment(pose_b);
    let (ra, rb) = (a.radius(), b.radius());
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    let l1 = d1.length();
    let l2 = d2.length();
    if l1 > 0.0 && l2 > 0.0 && d1.cross(d2).length() <= 1e-6 * l1 * l2 {
        // Parallel: the interval of A's segment facing B's segment.
        let u = d1 / l1;
        let t0 = (p2 - p1).dot(u) / l1;
        let t1 = (q2 - p1).dot(u) / l1;
        let lo = t0.min(t1).max(0.0);
        let hi = t0.max(t1).min(1.0);
        if hi - lo > 1e-9 {
            let start = out.len();
            for s in [lo, hi] {
                let ca = p1 + d1 * s;
                let (t, cb) = closest_point_on_segment(ca, p2, q2);
                push_ball_ball(
                    ca,
                    ra,
                    cb,
                    rb,
                    capsule_feature(s),
                    capsule_feature(t),
                    u.any_orthonormal_vector(),
                    margin,
                    out,
                );
            }
            if out.len() > start {
                return;
            }
        }
    }
    let (s, t, ca, cb) = closest_points_segments(p1, q1, p2, q2);
    // Crossing cores: the common perpendicular, oriented from B's centre to A's.
    let mut fallback = d1
        .cross(d2)
        .normalize_or(d1.normalize_or(DVec3::X).any_orthonormal_vector());
    if fallback.dot((p1 + q1) - (p2 + q2)) < 0.0 {
        fallback = -fallback;
    }
    // The parallel branch's call again, for the single closest pair: the two
    // differ in their points and fallback normal, and that branch may bail out
    // to here, so a shared closure would only hide which case is which.
    push_ball_ball(
        ca,
        ra,
        cb,
        rb,
        capsule_feature(s),
        capsule_feature(t),
        fallback,
        margin,
        out,
    );
}
