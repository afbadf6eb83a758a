//! Integrator behaviour on simple exactly-solvable cases: constant gravity, one step under
//! an off-centre force, static and kinematic bodies, damping, bad input and roll-back.

mod common;

use common::*;
use tumble::collide::math::{DQuat, DVec3};
use tumble::collide::Pose;
use tumble::integrate::{integrate, integrate_with_field, IntegrateError, Integrator};
use tumble::{BodyState, RigidBody};

const G: DVec3 = DVec3::new(0.0, 0.0, -9.81);

fn thrown(mass: f64) -> RigidBody {
    let mut b = RigidBody::new_dynamic(
        mass,
        DVec3::new(0.2, 0.3, 0.4),
        Pose::from_translation(DVec3::new(1.0, 2.0, 3.0)),
    )
    .unwrap();
    b.set_linear_velocity(DVec3::new(2.0, -1.0, 6.0)).unwrap();
    b
}

/// x(T) = x0 + v0 T + g T²/2. Midpoint and RK4 integrate a constant force exactly (the
/// solution is a quadratic polynomial). Forward Euler uses the old velocity for the whole
/// step: x_N = x0 + v0 T + g h² N(N-1)/2 = exact - g h T/2; semi-implicit Euler uses the
/// new one: x_N = exact + g h T/2. Velocities are exact for all four.
#[test]
fn projectile_follows_the_parabola() {
    let (h, n) = (0.01, 100);
    let t = h * n as f64;
    for integrator in Integrator::ALL {
        let mut bodies = [thrown(3.0)];
        let x0 = bodies[0].position();
        let v0 = bodies[0].velocity();
        for _ in 0..n {
            integrate(&mut bodies, G, h, integrator).unwrap();
        }
        let exact = x0 + v0 * t + G * (0.5 * t * t);
        let offset = match integrator {
            Integrator::Euler => -G * (0.5 * h * t),
            Integrator::SemiImplicitEuler | Integrator::SemiImplicitSplitting => G * (0.5 * h * t),
            Integrator::Midpoint | Integrator::Rk4 => DVec3::ZERO,
        };
        let b = &bodies[0];
        assert!(
            (b.position() - (exact + offset)).length() < 1e-12,
            "{integrator:?}: {:?} vs {:?}",
            b.position(),
            exact + offset
        );
        assert!((b.velocity() - (v0 + G * t)).length() < 1e-12);
        // Gravity is applied as M g: no spin, no torque.
        assert_eq!(b.angular_momentum(), DVec3::ZERO);
    }
}

/// A force F at world point p on a body at rest: after one step of any method,
/// P = h F and L = h (p - x) x F (the torque is constant during the step and no torque
/// arises from the motion itself).
#[test]
fn off_centre_force_gives_moment_arm_torque() {
    let f = DVec3::new(0.0, 4.0, -1.0);
    let arm = DVec3::new(0.5, 0.0, 0.25);
    let h = 0.01;
    for integrator in Integrator::ALL {
        let mut b = RigidBody::new_dynamic(2.0, DVec3::new(0.3, 0.5, 0.6), tilted_pose()).unwrap();
        b.apply_force_at_point(f, b.position() + arm).unwrap();
        let mut bodies = [b];
        integrate(&mut bodies, DVec3::ZERO, h, integrator).unwrap();
        let b = &bodies[0];
        assert!((b.linear_momentum() - f * h).length() < 1e-15);
        let expected = arm.cross(f) * h;
        assert!(
            (b.angular_momentum() - expected).length() < 1e-15,
            "{integrator:?}: {:?} vs {expected:?}",
            b.angular_momentum()
        );
        assert!(b.angular_velocity().length() > 0.0);
    }
}

#[test]
fn static_body_never_moves() {
    for integrator in Integrator::ALL {
        let mut s = RigidBody::new_static(tilted_pose());
        s.apply_force(DVec3::new(1e3, 0.0, 0.0)).unwrap();
        s.apply_force_at_point(DVec3::Z, DVec3::X).unwrap();
        s.apply_torque(DVec3::new(0.0, 50.0, 0.0)).unwrap();
        s.apply_impulse_at_point(DVec3::new(0.0, 0.0, 10.0), DVec3::Y)
            .unwrap();
        let before = s.clone();
        let mut bodies = [s];
        for _ in 0..100 {
            integrate(&mut bodies, G, 0.01, integrator).unwrap();
        }
        assert_eq!(bodies[0], before, "{integrator:?}");
        assert_eq!(bodies[0].velocity(), DVec3::ZERO);
    }
}

/// A kinematic body moves along x0 + v t, q = exp(ω t / 2) q0, whatever gravity, forces
/// or impulses are thrown at it.
#[test]
fn kinematic_body_follows_prescribed_motion() {
    let v = DVec3::new(0.5, -0.2, 1.0);
    let w = DVec3::new(0.3, 1.2, -0.7);
    for integrator in Integrator::ALL {
        let mut k = RigidBody::new_kinematic(tilted_pose());
        k.set_kinematic_velocity(v, w).unwrap();
        let (x0, q0) = (k.position(), k.orientation());
        let mut bodies = [k];
        let (h, n) = (0.01, 300);
        for _ in 0..n {
            bodies[0].apply_force(DVec3::new(0.0, 0.0, 100.0)).unwrap();
            bodies[0].apply_impulse_at_point(DVec3::X, DVec3::Y).unwrap();
            integrate(&mut bodies, G, h, integrator).unwrap();
        }
        let t = h * n as f64;
        let k = &bodies[0];
        assert!((k.position() - (x0 + v * t)).length() < 1e-12);
        let exact = DQuat::from_scaled_axis(w * t) * q0;
        assert!(rotation_error(k.orientation(), exact) < 1e-12);
        assert_eq!(k.velocity(), v);
        assert_eq!(k.angular_velocity(), w);
        assert_eq!(k.linear_momentum(), DVec3::ZERO);
    }
}

/// With no forces, damping scales the momenta by exactly 1/(1 + c h) per step.
#[test]
fn damping_scales_momenta_per_step() {
    let (h, n, cl, ca) = (0.02, 50, 0.8, 2.5);
    for integrator in Integrator::ALL {
        let mut b = spinning_body(
            DVec3::new(0.4, 0.6, 0.9),
            DVec3::new(1.0, 2.0, 0.5),
            tilted_pose(),
        );
        b.set_linear_velocity(DVec3::new(1.0, -2.0, 0.5)).unwrap();
        b.set_damping(cl, ca).unwrap();
        let (p0, l0) = (b.linear_momentum(), b.angular_momentum());
        run_free(&mut b, integrator, h, n);
        let fl = (1.0 / (1.0 + cl * h)).powi(n as i32);
        let fa = (1.0 / (1.0 + ca * h)).powi(n as i32);
        assert!((b.linear_momentum() - p0 * fl).length() < 1e-13);
        assert!((b.angular_momentum() - l0 * fa).length() < 1e-13);
    }
}

#[test]
fn bad_step_input_is_refused_without_touching_bodies() {
    let mut bodies = [thrown(1.0)];
    let before = bodies.clone();
    assert!(matches!(
        integrate(&mut bodies, G, -0.01, Integrator::Rk4),
        Err(IntegrateError::BadTimeStep(_))
    ));
    assert!(matches!(
        integrate(&mut bodies, G, f64::NAN, Integrator::Euler),
        Err(IntegrateError::BadTimeStep(_))
    ));
    assert!(matches!(
        integrate(
            &mut bodies,
            DVec3::new(0.0, f64::INFINITY, 0.0),
            0.01,
            Integrator::Euler
        ),
        Err(IntegrateError::NonFiniteGravity(_))
    ));
    assert_eq!(bodies, before);
}

/// A force field that returns NaN for one body: that body keeps its old state and is
/// reported; the others step normally.
#[test]
fn non_finite_field_result_is_rolled_back_and_reported() {
    for integrator in Integrator::ALL {
        let mut bodies = [thrown(1.0), thrown(2.0), thrown(3.0)];
        let before = bodies.clone();
        let field = |i: usize, _: &BodyState, _: f64| {
            if i == 1 {
                (DVec3::new(f64::NAN, 0.0, 0.0), DVec3::ZERO)
            } else {
                (DVec3::ZERO, DVec3::ZERO)
            }
        };
        let report = integrate_with_field(&mut bodies, G, 0.0, 0.01, integrator, &field).unwrap();
        assert_eq!(report.rolled_back, 1);
        assert_eq!(report.first_rolled_back, Some(1));
        assert_eq!(bodies[1], before[1]);
        assert_ne!(bodies[0].position(), before[0].position());
        assert_ne!(bodies[2].position(), before[2].position());
    }
}

/// Same input, same bits.
#[test]
fn stepping_is_deterministic() {
    let make = || {
        (0..20)
            .map(|i| {
                let mut b = spinning_body(
                    DVec3::new(0.3, 0.5, 0.7),
                    DVec3::new(i as f64 * 0.1, 1.0, -0.5),
                    tilted_pose(),
                );
                b.apply_torque(DVec3::new(0.1, 0.0, i as f64 * 0.01)).unwrap();
                b
            })
            .collect::<Vec<_>>()
    };
    for integrator in Integrator::ALL {
        let (mut a, mut b) = (make(), make());
        for _ in 0..50 {
            integrate(&mut a, G, 0.01, integrator).unwrap();
            integrate(&mut b, G, 0.01, integrator).unwrap();
        }
        assert_eq!(a, b);
    }
}
