//! The world's iterative contact solver (sub-step passes with block-solved
//! patches) against the direct pivoting solver (Lemke) on random small
//! contact problems: both must end at the same velocities, the M-metric
//! projection of the free velocities onto the non-penetration cone, which is
//! unique even where the impulses are not (four coplanar corners).

mod common;

use common::{RandomSource, Rng};
use tumble::collide::{DQuat, DVec3};
use tumble::solver::contact_solver::{
    prepare, residual, solve, solve_normals_exactly, ManifoldConstraint, PointConstraint, SolverBody,
};

/// Body 0 is fixed; bodies 1..=3 are dynamic with random mass, inertia,
/// orientation and velocity. Patches of 1-4 points with one normal join
/// random pairs (at least one dynamic).
fn problem(rng: &mut Rng) -> (Vec<SolverBody>, Vec<ManifoldConstraint>, Vec<PointConstraint>) {
    let mut bodies = vec![SolverBody::fixed()];
    for _ in 0..3 {
        let q = DQuat::from_scaled_axis(rng.vec3(3.0));
        let inv_i = DVec3::new(rng.range(0.5, 4.0), rng.range(0.5, 4.0), rng.range(0.5, 4.0));
        bodies.push(SolverBody::new(
            rng.vec3(2.0),
            rng.vec3(1.0),
            rng.range(0.2, 2.0),
            inv_i,
            q,
        ));
    }
    let (mut manifolds, mut points) = (Vec::new(), Vec::new());
    for _ in 0..(2 + (rng.next_f64() * 3.0) as usize) {
        let a = 1 + (rng.next_f64() * 3.0) as u32;
        let mut b = (rng.next_f64() * 4.0) as u32;
        if b == a {
            b = 0;
        }
        let n = rng.vec3(1.0).normalize();
        let count = 1 + (rng.next_f64() * 4.0) as u32;
        let first = points.len() as u32;
        for _ in 0..count {
            points.push(PointConstraint::new(n, rng.vec3(0.6), rng.vec3(0.6), 0.0, 0.0));
        }
        manifolds.push(ManifoldConstraint::new(
            a,
            b,
            first,
            count,
            n,
            0.0,
            0.0,
            DVec3::ZERO,
            0.0,
        ));
    }
    for m in manifolds.iter_mut() {
        prepare(m, &mut points, &bodies);
    }
    (bodies, manifolds, points)
}

#[test]
fn iterative_and_direct_solvers_reach_the_same_velocities() {
    let mut rng = Rng(0x5eed_1234_abcd_0001);
    let h = 1.0 / 240.0;
    for case in 0..200 {
        let (bodies, manifolds, points) = problem(&mut rng);
        let (mut pgs_bodies, mut pgs_m, mut pgs_p) = (bodies.clone(), manifolds.clone(), points.clone());
        for _ in 0..400 {
            solve(&mut pgs_m, &mut pgs_p, &mut pgs_bodies, h);
        }
        let (mut lcp_bodies, mut lcp_p) = (bodies.clone(), points.clone());
        solve_normals_exactly(&manifolds, &mut lcp_p, &mut lcp_bodies, h).unwrap();
        // Both satisfy the rows: no approaching point, impulses >= 0.
        assert!(
            residual(&manifolds, &lcp_p, &lcp_bodies, h) < 1e-6,
            "case {case}: Lemke"
        );
        assert!(
            residual(&pgs_m, &pgs_p, &pgs_bodies, h) < 1e-6,
            "case {case}: PGS"
        );
        assert!(pgs_p.iter().chain(&lcp_p).all(|p| p.normal_impulse >= 0.0));
        for (k, (x, y)) in pgs_bodies.iter().zip(&lcp_bodies).enumerate() {
            let scale = 1.0 + bodies[k].v.length() + bodies[k].w.length();
            assert!(
                (x.v - y.v).length() < 1e-5 * scale && (x.w - y.w).length() < 1e-5 * scale,
                "case {case}, body {k}: PGS {:?} {:?} vs Lemke {:?} {:?}",
                x.v,
                x.w,
                y.v,
                y.w
            );
        }
    }
}

#[test]
fn residual_falls_as_iterations_rise() {
    let mut rng = Rng(0x0dd5_eed5_0000_0042);
    let h = 1.0 / 240.0;
    let mut checked = 0;
    for _ in 0..50 {
        let (mut bodies, mut manifolds, mut points) = problem(&mut rng);
        let before = residual(&manifolds, &points, &bodies, h);
        if before < 1e-3 {
            continue; // nothing approaches: nothing to solve
        }
        solve(&mut manifolds, &mut points, &mut bodies, h);
        let one = residual(&manifolds, &points, &bodies, h);
        for _ in 0..200 {
            solve(&mut manifolds, &mut points, &mut bodies, h);
        }
        let many = residual(&manifolds, &points, &bodies, h);
        assert!(
            one < before && many <= one + 1e-12 && many < 1e-6,
            "{before} -> {one} -> {many}"
        );
        checked += 1;
    }
    assert!(checked > 10);
}
