//! Closest points between points and segments (Ericson, "Real-Time Collision
//! Detection", 5.1.2 and 5.1.9), used by the sphere/capsule routines and for
//! edge-edge contacts.

use crate::math::DVec3;
use crate::triangle::tri_distance::segment_parameters;

/// Parameter `t` in [0, 1] and point of segment `a..b` closest to `p`.
pub(crate) fn closest_point_on_segment(p: DVec3, a: DVec3, b: DVec3) -> (f64, DVec3) {
    let ab = b - a;
    let l2 = ab.length_squared();
    if l2 <= f64::MIN_POSITIVE {
        return (0.0, a);
    }
    let t = ((p - a).dot(ab) / l2).clamp(0.0, 1.0);
    (t, a + ab * t)
}

/// Closest points between segments `p1..q1` and `p2..q2`: returns
/// `(s, t, c1, c2)` with `c1 = p1 + s (q1 - p1)`, `c2 = p2 + t (q2 - p2)`
/// (Ericson 5.1.9). Parallel segments get the `s` that the clamping of `t`
/// yields from `s = 0`, so the answer is deterministic.
///
/// The algorithm is `triangle::closest_points_segments`'s (one home:
/// `segment_parameters`), with tolerances of its own: the contact routines
/// treat segments within 1e-14 (relative) of parallel as parallel, so that
/// two capsules lying along each other keep the same contact end from step
/// to step, and a segment of squared length at most 1e-30 m^2 as a point;
/// the triangle distance keeps the exact formula down to machine epsilon,
/// which its brute-force oracles check.
pub(crate) fn closest_points_segments(
    p1: DVec3,
    q1: DVec3,
    p2: DVec3,
    q2: DVec3,
) -> (f64, f64, DVec3, DVec3) {
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    // Why the relative parallel test: denom = |d1|^2 |d2|^2 sin^2(angle).
    let Some((s, t)) = segment_parameters(d1, d2, p1 - p2, |_, _| 1e-30, 1e-14) else {
        return (0.0, 0.0, p1, p2);
    };
    (s, t, p1 + d1 * s, p2 + d2 * t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn v() -> impl Strategy<Value = DVec3> {
        (-2.0f64..2.0, -2.0f64..2.0, -2.0f64..2.0).prop_map(|(x, y, z)| DVec3::new(x, y, z))
    }

    proptest! {
        #[test]
        fn segment_closest_points_beat_sampling(p1 in v(), q1 in v(), p2 in v(), q2 in v()) {
            let (s, t, c1, c2) = closest_points_segments(p1, q1, p2, q2);
            prop_assert!((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t));
            prop_assert!((c1 - (p1 + (q1 - p1) * s)).length() < 1e-12);
            let d = (c1 - c2).length();
            // Brute force over a grid: nothing closer than the answer.
            let n = 40;
            for i in 0..=n {
                for j in 0..=n {
                    let a = p1 + (q1 - p1) * (i as f64 / n as f64);
                    let b = p2 + (q2 - p2) * (j as f64 / n as f64);
                    prop_assert!((a - b).length() >= d - 1e-9);
                }
            }
        }
    }
}
