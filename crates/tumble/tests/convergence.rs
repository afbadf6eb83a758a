//! Measured convergence orders of every integrator, by halving the step on problems with
//! known solutions: the torque-free axisymmetric top's orientation (rotational part;
//! the splitting integrator turns a symmetric body by its exact flow, so its order is
//! measured on an asymmetric top against a converged RK4 run) and a linear spring
//! through the force-field callback (translational part).

mod common;

use common::*;
use tumble::collide::math::DVec3;
use tumble::integrate::Integrator;
use tumble::{BodyState, RigidBody};

/// Orientation error at time `t_end` of the axisymmetric top stepped with `n` steps.
fn top_error(integrator: Integrator, n: usize) -> f64 {
    let (i1, i3) = (1.0, 1.6);
    let t_end = 2.0;
    let pose = tilted_pose();
    let mut b = spinning_body(DVec3::new(i1, i1, i3), DVec3::new(0.7, -0.4, 1.5), pose);
    let l = b.angular_momentum();
    run_free(&mut b, integrator, t_end / n as f64, n);
    let exact = axisymmetric_top_orientation(i1, i3, l, pose.rotation, t_end);
    rotation_error(b.orientation(), exact)
}

/// Phase-space error of a mass on a spring F = -k (x - x_rest) (3D isotropic) after
/// `t_end` with `n` steps; exact solution x(t) = x_rest + d0 cos(wt) + v0/w sin(wt).
fn spring_error(integrator: Integrator, n: usize) -> f64 {
    let (mass, k): (f64, f64) = (0.5, 8.0);
    let w = (k / mass).sqrt();
    let rest = DVec3::new(1.0, 2.0, -1.0);
    let d0 = DVec3::new(0.3, -0.1, 0.2);
    let v0 = DVec3::new(0.5, 0.4, -0.6);
    let t_end = 1.5;
    let mut b = RigidBody::new_dynamic(
        mass,
        DVec3::splat(0.1),
        tumble::collide::Pose::from_translation(rest + d0),
    )
    .unwrap();
    b.set_linear_velocity(v0).unwrap();
    let spring = |_: usize, s: &BodyState, _: f64| (-(s.position - rest) * k, DVec3::ZERO);
    run_with(
        std::slice::from_mut(&mut b),
        integrator,
        t_end / n as f64,
        n,
        &spring,
    );
    let (s, c) = (w * t_end).sin_cos();
    let x = rest + d0 * c + v0 / w * s;
    let v = -d0 * w * s + v0 * c;
    (b.position() - x).length() + (b.velocity() - v).length() / w
}

/// Orientation error at time `t_end` of an asymmetric top (three different moments)
/// stepped with `n` steps, against RK4 with 20,000 steps (its error there is below
/// 1e-13, far under the errors measured).
fn asymmetric_top_error(integrator: Integrator, n: usize) -> f64 {
    let t_end = 2.0;
    let run = |integrator: Integrator, n: usize| {
        let mut b = spinning_body(
            DVec3::new(1.0, 1.6, 2.3),
            DVec3::new(0.7, -0.4, 1.5),
            tilted_pose(),
        );
        run_free(&mut b, integrator, t_end / n as f64, n);
        b.orientation()
    };
    rotation_error(run(integrator, n), run(Integrator::Rk4, 20_000))
}

fn check_orders(name: &str, order: impl Fn(Integrator) -> u32, error: impl Fn(Integrator, usize) -> f64) {
    check_orders_of(&Integrator::ALL, name, order, error);
}

fn check_orders_of(
    integrators: &[Integrator],
    name: &str,
    order: impl Fn(Integrator) -> u32,
    error: impl Fn(Integrator, usize) -> f64,
) {
    for &integrator in integrators {
        // Step counts inside the asymptotic range and above round-off for each method.
        let n0 = match order(integrator) {
            1 => 800,
            2 => 100,
            _ => 25,
        };
        let errors: Vec<f64> = (0..3).map(|i| error(integrator, n0 << i)).collect();
        for pair in errors.windows(2) {
            let p = observed_order(pair[0], pair[1]);
            eprintln!("{name} {integrator:?}: errors {pair:?}, order {p:.3}");
            assert!(
                (p - order(integrator) as f64).abs() < 0.15,
                "{name} {integrator:?}: observed order {p} (errors {errors:?})"
            );
        }
    }
}

#[test]
fn orders_on_torque_free_top_orientation() {
    let approximate: Vec<Integrator> = Integrator::ALL
        .into_iter()
        .filter(|&i| i != Integrator::SemiImplicitSplitting)
        .collect();
    check_orders_of(&approximate, "top", Integrator::rotation_order, top_error);
    // The splitting takes the symmetric top's exact flow: round-off at any step.
    for n in [1, 10, 100] {
        let error = top_error(Integrator::SemiImplicitSplitting, n);
        assert!(
            error < 1e-13,
            "top SemiImplicitSplitting, {n} steps: error {error}"
        );
    }
    // And its own order on an asymmetric top.
    check_orders_of(
        &[Integrator::SemiImplicitSplitting],
        "asymmetric top",
        Integrator::rotation_order,
        asymmetric_top_error,
    );
}

#[test]
fn orders_on_spring_through_force_field() {
    check_orders("spring", Integrator::order, spring_error);
}
