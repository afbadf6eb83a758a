//! Closed-form results of rigid body mechanics that the tests, the demos
//! and the benchmarks compare simulations with: one home for each formula.
//!
//! - [`elliptic_k`]: the complete elliptic integral of the first kind, by the
//!   arithmetic-geometric mean (Abramowitz & Stegun 17.6), for large-swing
//!   pendulum periods and the torque-free top.
//! - [`rolling_period`]: the period of a body rolling without slipping
//!   (or sliding without friction) inside a sphere or a cylinder, a pendulum
//!   of length `(1 + k)(R - r)`.
//! - [`torque_free_period`]: the period of a free rigid body's body-frame
//!   angular velocity (Euler's equations solved by Jacobi elliptic
//!   functions; Landau & Lifshitz, Mechanics, section 37): the flip period of
//!   the Dzhanibekov effect.

use tumble_collide::DVec3;

/// Complete elliptic integral of the first kind
/// `K(m) = int_0^{pi/2} dθ / sqrt(1 - m sin²θ)`, parameter `m = k²` in
/// [0, 1), by the arithmetic-geometric mean: `K(m) = π / (2 AGM(1, sqrt(1 - m)))`.
/// Converges quadratically; NaN for `m` outside [0, 1).
pub fn elliptic_k(m: f64) -> f64 {
    if !(0.0..1.0).contains(&m) {
        return f64::NAN;
    }
    let (mut a, mut b) = (1.0f64, (1.0 - m).sqrt());
    for _ in 0..64 {
        if (a - b).abs() <= 1e-16 * a {
            break;
        }
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

/// The period of a body rolling without slipping inside a sphere or a
/// cylinder, its centre on a circle of radius `path` (m), `k = I / (m r^2)`
/// about its rolling axis (0 for sliding without friction), let go at `phi0`
/// (rad) under gravity `g` (m/s^2): a pendulum of length `(1 + k) path` at
/// that amplitude (s). From `(1 + k) path phi'' = -g sin phi`: the body's
/// speed is `path phi'`, its spin `path phi' / r`, and the contact force
/// does no work.
pub fn rolling_period(path: f64, k: f64, phi0: f64, g: f64) -> f64 {
    let length = (1.0 + k) * path;
    4.0 * (length / g).sqrt() * elliptic_k((phi0 / 2.0).sin().powi(2))
}

/// Period of the body-frame angular velocity of a torque-free rigid body
/// with principal moments `moments` (ascending) spinning at body-frame
/// angular velocity `omega`:
/// `T = 4 K(k²) / λ`, `λ² = (I3 - I2)(L² - 2E I1) / (I1 I2 I3)`,
/// `k² = (I2 - I1)(2E I3 - L²) / ((I3 - I2)(L² - 2E I1))` when
/// `L² > 2E I2` (I1 and I3 exchanged otherwise). NaN on the separatrix
/// (`L² = 2E I2`, where the period is infinite) or for equal moments.
pub fn torque_free_period(moments: DVec3, omega: DVec3) -> f64 {
    let i = moments;
    let two_e = (i * omega * omega).element_sum();
    let l2 = (i * omega).length_squared();
    let (i1, i2, i3) = if l2 > two_e * i.y {
        (i.x, i.y, i.z)
    } else {
        (i.z, i.y, i.x)
    };
    let lambda2 = (i3 - i2) * (l2 - two_e * i1) / (i1 * i2 * i3);
    let k2 = (i2 - i1) * (two_e * i3 - l2) / ((i3 - i2) * (l2 - two_e * i1));
    4.0 * elliptic_k(k2) / lambda2.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn elliptic_k_matches_known_values() {
        assert_eq!(elliptic_k(0.0), PI / 2.0);
        // K(1/2) = Γ(1/4)² / (4 sqrt(π)) (A&S 17.3.34 ff.)
        let gamma_quarter = 3.625_609_908_221_908;
        assert!((elliptic_k(0.5) - gamma_quarter * gamma_quarter / (4.0 * PI.sqrt())).abs() < 1e-14);
        // Against the integral by the midpoint rule.
        let m: f64 = 0.9;
        let n = 200_000;
        let h = PI / 2.0 / n as f64;
        let sum: f64 = (0..n)
            .map(|j| h / (1.0 - m * (h * (j as f64 + 0.5)).sin().powi(2)).sqrt())
            .sum();
        assert!((elliptic_k(m) - sum).abs() < 1e-9);
        assert!(elliptic_k(1.0).is_nan() && elliptic_k(-0.1).is_nan());
    }

    #[test]
    fn near_a_principal_axis_the_period_is_that_of_small_oscillations() {
        // Spin w about the minor axis (I1): small wobbles have angular
        // frequency w sqrt((I2 - I1)(I3 - I1) / (I2 I3)) (linearised Euler).
        let i = DVec3::new(1.0, 2.0, 3.0);
        let w = 2.0;
        let t = torque_free_period(i, DVec3::new(w, 1e-6, 1e-6));
        let small = 2.0 * PI / (w * ((i.y - i.x) * (i.z - i.x) / (i.y * i.z)).sqrt());
        assert!((t - small).abs() < 1e-6 * small, "{t} vs {small}");
        // The formula is symmetric in which of the stable axes is spun.
        let t3 = torque_free_period(i, DVec3::new(1e-6, 1e-6, w));
        let small3 = 2.0 * PI / (w * ((i.z - i.x) * (i.z - i.y) / (i.x * i.y)).sqrt());
        assert!((t3 - small3).abs() < 1e-6 * small3);
    }
}
