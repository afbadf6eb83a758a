//! Torque-free rigid body rotation against the analytic solutions of Euler's equations
//! (Landau & Lifshitz, "Mechanics", §33 and §37).

mod common;

use common::*;
use tumble::collide::math::DVec3;
use tumble::integrate::Integrator;

/// Axisymmetric top I1 = I2 != I3: Euler's equations give dω3/dt = 0 and
/// dω1/dt = -Ω ω2, dω2/dt = Ω ω1 with Ω = (I3 - I1)/I1 ω3, so the body-frame ω precesses
/// about the symmetry axis at the constant rate Ω, while L stays fixed in the world.
#[test]
fn axisymmetric_top_precesses_at_analytic_rate() {
    for (i1, i3) in [(1.0, 1.8), (2.0, 0.7)] {
        let w0 = DVec3::new(0.6, -0.25, 2.0);
        let pose = tilted_pose();
        let mut b = spinning_body(DVec3::new(i1, i1, i3), w0, pose);
        let l0 = b.angular_momentum();
        let rate = (i3 - i1) / i1 * w0.z;
        let period = std::f64::consts::TAU / rate.abs();
        let dt = 1e-3;
        let steps_per_sample = 250;
        let mut t = 0.0;
        // Five precession periods, checked every 0.25 s.
        while t < 5.0 * period {
            run_free(&mut b, Integrator::Rk4, dt, steps_per_sample);
            t += dt * steps_per_sample as f64;
            let (s, c) = (rate * t).sin_cos();
            let expected = DVec3::new(w0.x * c - w0.y * s, w0.x * s + w0.y * c, w0.z);
            let w = omega_body(&b);
            assert!(
                (w - expected).length() < 1e-9,
                "I=({i1},{i3}) t={t}: {w:?} vs {expected:?}"
            );
            // L is fixed in the world (exactly: no torque ever enters it).
            assert_eq!(b.angular_momentum(), l0);
            let exact = axisymmetric_top_orientation(i1, i3, l0, pose.rotation, t);
            assert!(rotation_error(b.orientation(), exact) < 1e-9);
        }
    }
}

/// Dzhanibekov effect: spin about the intermediate axis of I1 < I2 < I3 with a small
/// perturbation flips periodically. The flip period from Euler's equations:
///
/// With E = 1/2 Σ I_i ω_i² and L² = Σ I_i² ω_i² (both conserved), Landau §37 solves
/// Euler's equations by Jacobi elliptic functions. For L² > 2 E I2:
///   ω1 ∝ cn τ, ω2 ∝ sn τ, ω3 ∝ dn τ,  τ = λ t,
///   λ² = (I3 - I2)(L² - 2 E I1) / (I1 I2 I3),
///   m = k² = (I2 - I1)(2 E I3 - L²) / ((I3 - I2)(L² - 2 E I1)).
/// For L² < 2 E I2 the indices 1 and 3 swap roles:
///   λ² = (I2 - I1)(2 E I3 - L²) / (I1 I2 I3),
///   m = (I3 - I2)(L² - 2 E I1) / ((I2 - I1)(2 E I3 - L²)).
/// sn has period 4 K(m) in τ, so ω2 returns to its value (one flip and one flip back)
/// after T = 4 K(m) / λ; K is computed by the AGM. As the perturbation shrinks, m -> 1
/// and T grows like ln(1/perturbation)/λ.
#[test]
fn intermediate_axis_flip_period_matches_elliptic_solution() {
    let inertia = DVec3::new(1.0, 2.0, 3.0);
    for w0 in [DVec3::new(0.01, 1.0, 0.02), DVec3::new(0.03, -1.5, 0.005)] {
        // Euler's equations solved by Jacobi elliptic functions (Landau &
        // Lifshitz 37): the period of the body-frame angular velocity.
        let period = tumble::analytic::torque_free_period(inertia, w0);

        let mut b = spinning_body(inertia, w0, tilted_pose());
        let dt = 2e-3;
        let mut prev = omega_body(&b).y;
        let mut t = 0.0;
        // Times at which ω2 crosses zero in the same direction as its first crossing.
        let mut crossings = Vec::new();
        let mut direction = 0.0;
        while crossings.len() < 4 {
            run_free(&mut b, Integrator::Rk4, dt, 1);
            t += dt;
            let w2 = omega_body(&b).y;
            if prev != 0.0 && prev.signum() != w2.signum() {
                let d = w2.signum();
                if direction == 0.0 {
                    direction = d;
                }
                if d == direction {
                    // Linear interpolation of the crossing inside the step.
                    crossings.push(t - dt * w2 / (w2 - prev));
                }
            }
            prev = w2;
            assert!(t < 10.0 * period, "no flips seen");
        }
        for pair in crossings.windows(2) {
            let measured = pair[1] - pair[0];
            eprintln!("flip period: measured {measured} s, analytic {period} s");
            assert!(
                // The task asks for 1%; RK4 at this step is far better, so hold it to 1e-6.
                (measured - period).abs() < 1e-6 * period,
                "ω0={w0:?}: measured {measured} s vs analytic {period} s"
            );
        }
    }
}

/// With no torque every stage adds exactly zero to L, so L (hence |L|) is conserved to the
/// last bit by every integrator, whatever the step size.
#[test]
fn angular_momentum_is_exactly_conserved_without_torque() {
    for integrator in Integrator::ALL {
        let mut b = spinning_body(
            DVec3::new(0.3, 0.8, 1.0),
            DVec3::new(3.0, -2.0, 5.0),
            tilted_pose(),
        );
        let l0 = b.angular_momentum();
        run_free(&mut b, integrator, 0.02, 2000);
        assert_eq!(b.angular_momentum(), l0, "{integrator:?}");
        assert_eq!(b.angular_momentum().length(), l0.length());
        assert!((b.orientation().length() - 1.0).abs() < 1e-15);
    }
}

/// RK4 energy drift bound. E = 1/2 L·ω depends only on q here (L is exact), and RK4's
/// global error over a time T is bounded by C T h⁴ with C made of fifth derivatives of
/// the flow, each of size |ω|⁵ (every time derivative of a rotation at rate ω brings a
/// factor ω; the classical error constant is well below 1). E is a smooth function of the
/// state with relative sensitivity O(1), so
///     |ΔE| / E <= (ω_max h)⁴ ω_max T,   ω_max = |L| / I_min >= |ω(t)|.
/// The drift must also shrink by at least 2³ when h halves (order >= 3; measured it
/// falls faster than 2⁴ on this problem).
#[test]
fn rk4_kinetic_energy_drift_is_bounded() {
    let inertia = DVec3::new(0.5, 1.0, 1.4);
    let w0 = DVec3::new(0.5, 2.0, 1.0);
    let total_time = 40.0;
    let drift = |h: f64| {
        let mut b = spinning_body(inertia, w0, tilted_pose());
        let e0 = b.kinetic_energy();
        let steps = (total_time / h).round() as usize;
        run_free(&mut b, Integrator::Rk4, h, steps);
        ((b.kinetic_energy() - e0) / e0).abs()
    };
    let b = spinning_body(inertia, w0, tilted_pose());
    let w_max = b.angular_momentum().length() / inertia.min_element();
    let (h1, h2) = (0.02, 0.01);
    let (d1, d2) = (drift(h1), drift(h2));
    for (h, d) in [(h1, d1), (h2, d2)] {
        let bound = (w_max * h).powi(4) * w_max * total_time;
        eprintln!("RK4 h={h}: |dE|/E = {d:e}, bound {bound:e}");
        assert!(d <= bound, "h={h}: drift {d} > bound {bound}");
    }
    assert!(d1 / d2 > 8.0, "drift ratio {} for halved h", d1 / d2);
}

/// The splitting integrator is symplectic for torque-free rotation: its energy error is
/// the O(h²) gap to a modified energy, bounded for all time instead of drifting. Bound:
/// |ΔE|/E <= (ω_max h)², the size of the O(h²) term of a second-order method whose
/// derivatives scale with ω_max; it must hold at every sample over a long run, and the
/// error over 400 s must not exceed (much) the error over the first 40 s.
#[test]
fn splitting_energy_error_is_bounded_without_drift() {
    let inertia = DVec3::new(0.5, 1.0, 1.4);
    let w0 = DVec3::new(0.5, 2.0, 1.0);
    let h = 0.01;
    let mut b = spinning_body(inertia, w0, tilted_pose());
    let e0 = b.kinetic_energy();
    let l0 = b.angular_momentum();
    let w_max = l0.length() / inertia.min_element();
    let bound = (w_max * h).powi(2);
    let (mut early, mut all) = (0.0f64, 0.0f64);
    for k in 0..400 {
        run_free(&mut b, Integrator::SemiImplicitSplitting, h, 100);
        let err = ((b.kinetic_energy() - e0) / e0).abs();
        if k < 40 {
            early = early.max(err);
        }
        all = all.max(err);
    }
    eprintln!("splitting h={h}: max |dE|/E {early:e} (40 s), {all:e} (400 s), bound {bound:e}");
    assert!(all <= bound, "max drift {all} > bound {bound}");
    assert!(
        all <= 2.0 * early,
        "energy drifts: {early} after 40 s, {all} after 400 s"
    );
    assert_eq!(b.angular_momentum(), l0);
}
