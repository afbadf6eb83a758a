//! Property tests: laws every integrator must respect for arbitrary bodies and states.

mod common;

use common::*;
use proptest::prelude::*;
use tumble::collide::math::{DQuat, DVec3};
use tumble::collide::Pose;
use tumble::integrate::{integrate, Integrator};
use tumble::RigidBody;

fn arb_vec(r: f64) -> impl Strategy<Value = DVec3> {
    (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

fn arb_quat() -> impl Strategy<Value = DQuat> {
    (-3.0f64..3.0, -3.0f64..3.0, -3.0f64..3.0)
        .prop_map(|(a, b, c)| DQuat::from_euler(glam::EulerRot::ZYX, a, b, c))
}

/// Principal moments of a box with half-extents in [0.1, 1] (so always physical).
fn arb_inertia() -> impl Strategy<Value = DVec3> {
    (0.1f64..1.0, 0.1f64..1.0, 0.1f64..1.0)
        .prop_map(|(a, b, c)| DVec3::new(b * b + c * c, a * a + c * c, a * a + b * b) / 3.0)
}

fn arb_integrator() -> impl Strategy<Value = Integrator> {
    (0usize..Integrator::ALL.len()).prop_map(|i| Integrator::ALL[i])
}

#[allow(clippy::too_many_arguments)]
fn make(inertia: DVec3, x: DVec3, q: DQuat, v: DVec3, w: DVec3, f: DVec3, tau: DVec3) -> RigidBody {
    let mut b = RigidBody::new_dynamic(1.7, inertia, Pose::new(x, q).unwrap()).unwrap();
    b.set_linear_velocity(v).unwrap();
    b.set_angular_velocity(w).unwrap();
    b.apply_force(f).unwrap();
    b.apply_torque(tau).unwrap();
    b
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Frame indifference: rotating the whole initial state, the forces and gravity by a
    /// rotation R0 rotates the computed trajectory by R0 (the equations and every method
    /// are covariant), up to round-off.
    #[test]
    fn stepping_commutes_with_world_rotation(
        inertia in arb_inertia(), x in arb_vec(2.0), q in arb_quat(), v in arb_vec(2.0),
        w in arb_vec(4.0), f in arb_vec(3.0), tau in arb_vec(1.0), r0 in arb_quat(),
        integrator in arb_integrator(),
    ) {
        let g = DVec3::new(0.0, 0.0, -9.81);
        let mut a = [make(inertia, x, q, v, w, f, tau)];
        let mut b = [make(inertia, r0 * x, r0 * q, r0 * v, r0 * w, r0 * f, r0 * tau)];
        for _ in 0..20 {
            integrate(&mut a, g, 0.01, integrator).unwrap();
            integrate(&mut b, r0 * g, 0.01, integrator).unwrap();
        }
        let (a, b) = (&a[0], &b[0]);
        prop_assert!((r0 * a.position() - b.position()).length() < 1e-11);
        prop_assert!(rotation_error(r0 * a.orientation(), b.orientation()) < 1e-11);
        prop_assert!((r0 * a.linear_momentum() - b.linear_momentum()).length() < 1e-11);
        prop_assert!((r0 * a.angular_momentum() - b.angular_momentum()).length() < 1e-11);
    }

    /// Momentum theorem: with constant force and torque every method integrates dP/dt = F,
    /// dL/dt = tau exactly: P(T) = P0 + T (F + M g), L(T) = L0 + T tau.
    #[test]
    fn constant_wrench_changes_momenta_exactly(
        inertia in arb_inertia(), q in arb_quat(), v in arb_vec(2.0), w in arb_vec(4.0),
        f in arb_vec(3.0), tau in arb_vec(1.0), integrator in arb_integrator(),
    ) {
        let g = DVec3::new(0.0, 0.0, -9.81);
        let mut bodies = [make(inertia, DVec3::ZERO, q, v, w, f, tau)];
        let (p0, l0) = (bodies[0].linear_momentum(), bodies[0].angular_momentum());
        let (h, n) = (0.01, 30);
        for _ in 0..n {
            integrate(&mut bodies, g, h, integrator).unwrap();
        }
        let t = h * n as f64;
        let b = &bodies[0];
        prop_assert!((b.linear_momentum() - (p0 + (f + g * 1.7) * t)).length() < 1e-12);
        prop_assert!((b.angular_momentum() - (l0 + tau * t)).length() < 1e-12);
        prop_assert!((b.orientation().length() - 1.0).abs() < 1e-15);
    }
}
