//! Colliding contact (thesis 7.1): Newton's restitution law applied by
//! impulses before the resting-contact sub-steps.

use super::body::SolverBody;
use super::constraint::{ManifoldConstraint, PointConstraint, SolverParams};
use tumble_collide::DVec3;

/// Largest number of sweeps of [`resolve_collisions`].
pub const MAX_COLLISION_SWEEPS: usize = 32;

/// Colliding contact (thesis 7.1): before the resting-contact solve, every
/// point of a pair with restitution `e > 0` that approaches faster than the
/// threshold and will touch within `dt` gets the impulse that reverses its
/// normal velocity by Newton's law. (For `e = 0` the sub-steps' resting
/// solve stops the approach by itself, with friction acting together with
/// it; pushing many mesh points' impacts through here one by one, without
/// friction, shakes concave contacts.) Sweeps repeat until nothing approaches,
/// so an impact travels down a row of touching bodies in one step (Newton's
/// cradle; Guendelman, Bridson & Fedkiw 2003 process collisions the same way).
///
/// The impact happens a gap `g` before the surfaces meet. So that the bounce
/// loses nothing to that shift, the outgoing speed is the one the body would
/// have at `g` after bouncing at the surface under the pair's relative normal
/// acceleration `a` (gravity, forces): with `v_i^2 = v_n^2 - 2 a g` the speed
/// at impact, `v_out = sqrt(e^2 v_i^2 + 2 a g)`. For `e = 1` this is `|v_n|`
/// exactly; for a ball dropped on the ground it gives the apex `e^2` times the
/// drop height.
///
/// Semi-implicit Euler stores the velocity of the middle of the last
/// sub-step `h`, not of its end: the impact is computed with the velocity at
/// the step start, `v_n + a h / 2`, and the result is stored back half a
/// sub-step earlier, so that a perfectly elastic ball returns to its height.
///
/// `accel[i]` is body i's linear acceleration. Collision impulses are not
/// accumulated into the warm-start impulses. Returns the sweeps used.
pub fn resolve_collisions(
    manifolds: &[ManifoldConstraint],
    points: &mut [PointConstraint],
    bodies: &mut [SolverBody],
    accel: &[DVec3],
    params: &SolverParams,
    dt: f64,
    h: f64,
) -> usize {
    for sweep in 0..MAX_COLLISION_SWEEPS {
        let mut any = false;
        for m in manifolds {
            if m.restitution == 0.0 {
                continue;
            }
            let (ia, ib) = (m.a as usize, m.b as usize);
            let a_n_pair = accel[ia] - accel[ib];
            for p in &mut points[m.range()] {
                if p.normal_mass == 0.0 {
                    continue;
                }
                let (mut ba, mut bb) = (bodies[ia], bodies[ib]);
                let vn = p.normal.dot(ba.velocity_at(p.r_a) - bb.velocity_at(p.r_b));
                // A NaN approach (bodies whose velocities overflowed:
                // quarantined after the step) skips the point too.
                if vn.is_nan() || vn >= -params.restitution_threshold {
                    continue;
                }
                let a_n = p.normal.dot(a_n_pair);
                let gap = p.separation.max(0.0);
                if gap + vn * dt + 0.5 * a_n.min(0.0) * dt * dt > 0.0 {
                    continue; // will not touch during this step
                }
                let v_start = vn + 0.5 * a_n * h;
                let vi2 = v_start * v_start - 2.0 * a_n * gap;
                if vi2 <= 0.0 {
                    // Pushed apart (a_n > 0) hard enough to stop before the
                    // surfaces meet: no impact (the resting solve acts if
                    // they touch). Bouncing anyway would leave faster than
                    // the pair came: e^2 v^2 + 2 a g (1 - e^2) > v^2.
                    continue;
                }
                let e = m.restitution;
                let v_out = (e * e * vi2 + 2.0 * a_n * gap).max(0.0).sqrt() - 0.5 * a_n * h;
                if !v_out.is_finite() {
                    // Speeds or accelerations near the f64 limit overflowed:
                    // no bounce to give (the resting solve still acts, and a
                    // body left non-finite is quarantined).
                    continue;
                }
                // Restitution never creates energy: for e <= 1 the pair
                // leaves (at the step start) no faster than it came.
                debug_assert!(
                    e > 1.0 || (v_out + 0.5 * a_n * h).powi(2) <= v_start * v_start * (1.0 + 1e-9) + 1e-12,
                    "restitution {e}: out at {v_out} m/s after {vn} m/s in"
                );
                let magnitude = p.normal_mass * (v_out - vn);
                // A bounce is a touch: contact events see it like a resting impulse.
                p.max_normal_impulse = p.max_normal_impulse.max(magnitude);
                let impulse = p.normal * magnitude;
                ba.apply_impulse(impulse, p.r_a);
                bb.apply_impulse(-impulse, p.r_b);
                if ba.dynamic {
                    bodies[ia] = ba;
                }
                if bb.dynamic {
                    bodies[ib] = bb;
                }
                any = true;
            }
        }
        if !any {
            return sweep;
        }
    }
    MAX_COLLISION_SWEEPS
}
