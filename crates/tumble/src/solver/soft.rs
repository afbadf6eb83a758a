//! Soft constraint coefficients (E. Catto, "Solver2D", 2024; Box2D v3).
//!
//! A contact that has penetrated is treated as a critically damped
//! spring-damper of natural frequency `hertz` and damping ratio `zeta`,
//! integrated implicitly over the sub-step `h`. Solving the velocity
//! constraint `v_n + bias = 0` with that spring gives, per iteration,
//!
//! ```text
//! impulse = -m_eff * mass_scale * (v_n + bias) - impulse_scale * accumulated
//! omega = 2 pi hertz,  a1 = 2 zeta + h omega,  a2 = h omega a1,  a3 = 1 / (1 + a2)
//! bias = bias_rate * separation,  bias_rate = omega / a1
//! mass_scale = a2 a3,  impulse_scale = a3
//! ```
//!
//! Why soft rather than Baumgarte: the stiffness is stated in physical units
//! that do not depend on the time step or iteration count, and the implicit
//! spring cannot overshoot, so deep overlap is pushed out smoothly instead of
//! exploding.

/// Coefficients of a soft constraint for one sub-step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Softness {
    /// Position error to velocity bias (1/s).
    pub bias_rate: f64,
    /// Scale on the effective mass (dimensionless, in (0, 1]).
    pub mass_scale: f64,
    /// Scale on the accumulated impulse (dimensionless, in [0, 1)).
    pub impulse_scale: f64,
}

impl Softness {
    /// A rigid constraint: full mass, no bias, no impulse leakage.
    pub const RIGID: Softness = Softness {
        bias_rate: 0.0,
        mass_scale: 1.0,
        impulse_scale: 0.0,
    };

    /// Softness of a spring of `hertz` (Hz) and damping ratio `zeta` over a
    /// sub-step `h` (s). `hertz == 0` gives [`Softness::RIGID`].
    pub fn new(hertz: f64, zeta: f64, h: f64) -> Softness {
        if hertz <= 0.0 {
            return Softness::RIGID;
        }
        let omega = 2.0 * std::f64::consts::PI * hertz;
        let a1 = 2.0 * zeta + h * omega;
        let a2 = h * omega * a1;
        let a3 = 1.0 / (1.0 + a2);
        Softness {
            bias_rate: omega / a1,
            mass_scale: a2 * a3,
            impulse_scale: a3,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn softness_tends_to_rigid_as_stiffness_grows() {
        let h = 1.0 / 240.0;
        let soft = Softness::new(30.0, 10.0, h);
        let stiff = Softness::new(1e6, 1.0, h);
        assert!(soft.mass_scale < stiff.mass_scale && stiff.mass_scale < 1.0);
        assert!(stiff.impulse_scale < 1e-3);
        assert!((soft.mass_scale + soft.impulse_scale - 1.0).abs() < 1e-15);
    }

    #[test]
    fn implicit_spring_matches_closed_form() {
        // One body of unit mass at x0 < 0 (penetration), constraint x >= 0,
        // solved once per step: the soft impulse equals the implicit Euler step
        // of m x'' = -k x - c x' with k = m omega^2, c = 2 m zeta omega.
        let (hertz, zeta, h) = (10.0, 0.7, 0.01);
        let s = Softness::new(hertz, zeta, h);
        let (x, v) = (-0.1f64, 0.0f64);
        let dv = -(s.mass_scale * (v + s.bias_rate * x));
        let omega = 2.0 * std::f64::consts::PI * hertz;
        let (k, c) = (omega * omega, 2.0 * zeta * omega);
        // Implicit Euler: v1 = v + h(-k (x + h v1) - c v1) => v1 = (v - h k x) / (1 + h c + h^2 k)
        let v1 = (v - h * k * x) / (1.0 + h * c + h * h * k);
        assert!((v + dv - v1).abs() < 1e-12, "{} vs {}", v + dv, v1);
    }
}
