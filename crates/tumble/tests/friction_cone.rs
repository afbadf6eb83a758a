//! The exact reference with friction (the polyhedral-cone LCP of
//! Stewart-Trinkle / Anitescu-Potra, solved by Lemke) against analytic
//! answers, and the world's fast solver (patch friction, sequential
//! impulses) against the reference on random single-contact problems:
//! - sticking contacts: both stop the contact point, and the impulses agree;
//! - sliding contacts whose effective mass is isotropic (the contact at the
//!   centre of mass): both slide the same way, within the polygon's
//!   approximation of the Coulomb disc (elsewhere the fast solver's
//!   sequential tangent rows, projected on the disc afterwards, need not
//!   oppose the sliding exactly, so only the rim and the energy are checked);
//! - every sliding contact: both put the friction on the rim of the cone
//!   (`|f| = mu n`) and both dissipate energy.

mod common;

use common::{RandomSource, Rng};
use tumble::collide::{DMat3, DQuat, DVec3};
use tumble::solver::contact_solver::{prepare, solve, ManifoldConstraint, PointConstraint, SolverBody};
use tumble::solver::{solve_friction_cone, BodyState, ContactRow, FrictionConeError};

fn point_mass(m: f64, v: DVec3) -> BodyState {
    BodyState {
        inv_mass: 1.0 / m,
        inv_inertia: DMat3::from_diagonal(DVec3::splat(1.0)),
        linear_velocity: v,
        angular_velocity: DVec3::ZERO,
    }
}

/// A block on a slope of angle theta, after gravity acted for h: it sticks
/// when mu >= tan(theta) and slides with (g sin - mu g cos) h otherwise.
#[test]
fn block_on_a_slope_sticks_or_slides_as_coulomb_says() {
    let (g, h, m) = (9.81, 1.0 / 60.0, 2.0);
    for theta in [0.2f64, 0.5, 0.9] {
        let n = DVec3::new(theta.sin(), 0.0, theta.cos());
        for mu in [0.1, 0.3, 0.6, 1.0, 1.5] {
            let body = point_mass(m, DVec3::new(0.0, 0.0, -g * h));
            let contact = ContactRow {
                body_a: 1,
                body_b: 0,
                r_a: DVec3::ZERO,
                r_b: DVec3::ZERO,
                normal: n,
                bias: 0.0,
                friction: mu,
            };
            let sol = solve_friction_cone(&[BodyState::fixed(), body], &[contact], 8).unwrap();
            let v = sol.velocities[1].linear;
            assert!((sol.normal[0] - m * g * theta.cos() * h).abs() < 1e-9);
            assert!(v.dot(n).abs() < 1e-9, "no motion into the slope");
            if mu >= theta.tan() {
                assert!(v.length() < 1e-9, "theta {theta}, mu {mu}: sticks, v {v:?}");
                assert!((sol.friction[0].length() - m * g * theta.sin() * h).abs() < 1e-9);
            } else {
                // Down the slope is an edge of the 8-sided cone here (t2).
                let slide = (g * theta.sin() - mu * g * theta.cos()) * h;
                assert!(
                    (v.length() - slide).abs() < 1e-9,
                    "theta {theta}, mu {mu}: {v:?} vs {slide}"
                );
                assert!(
                    (sol.friction[0].length() - mu * sol.normal[0]).abs() < 1e-9,
                    "on the rim"
                );
                assert!((sol.sliding_speed[0] - slide).abs() < 1e-9);
            }
        }
    }
}

#[test]
fn bad_cones_are_typed_errors() {
    let contact = ContactRow {
        body_a: 1,
        body_b: 0,
        r_a: DVec3::ZERO,
        r_b: DVec3::ZERO,
        normal: DVec3::Z,
        bias: 0.0,
        friction: 0.5,
    };
    let bodies = [BodyState::fixed(), point_mass(1.0, DVec3::ZERO)];
    assert!(matches!(
        solve_friction_cone(&bodies, &[contact], 2),
        Err(FrictionConeError::Directions(2))
    ));
    let bad = ContactRow {
        friction: f64::NAN,
        ..contact
    };
    assert!(matches!(
        solve_friction_cone(&bodies, &[bad], 8),
        Err(FrictionConeError::Contacts(_))
    ));
}

/// One random contact between a dynamic body and the static body or a
/// second dynamic body, approaching, with friction mu. `isotropic` puts
/// the contact at A's centre of mass against the static body, so that an
/// impulse there only translates A: its effective mass is the same in
/// every direction.
struct Problem {
    bodies: Vec<SolverBody>,
    contact: ContactRow,
}

fn problem(rng: &mut Rng, isotropic: bool) -> Problem {
    let mut bodies = vec![SolverBody::fixed()];
    for _ in 0..2 {
        bodies.push(SolverBody::new(
            rng.vec3(2.0),
            rng.vec3(1.5),
            rng.range(0.3, 2.0),
            DVec3::new(rng.range(0.5, 4.0), rng.range(0.5, 4.0), rng.range(0.5, 4.0)),
            DQuat::from_scaled_axis(rng.vec3(3.0)),
        ));
    }
    let n = rng.vec3(1.0).normalize();
    let b = if isotropic || rng.next_f64() < 0.5 { 0 } else { 2 };
    let r_a = if isotropic { DVec3::ZERO } else { rng.vec3(0.6) };
    let r_b = rng.vec3(0.6);
    // Make the point approach along the normal.
    let vrel = bodies[1].velocity_at(r_a) - bodies[b].velocity_at(r_b);
    let vn = vrel.dot(n);
    bodies[1].v -= n * (vn + rng.range(0.2, 2.0));
    let contact = ContactRow {
        body_a: 1,
        body_b: b,
        r_a,
        r_b,
        normal: n,
        bias: 0.0,
        friction: rng.range(0.05, 1.5),
    };
    Problem { bodies, contact }
}

/// The fast solver on the problem: a one-point patch, converged passes.
fn fast(p: &Problem) -> (Vec<SolverBody>, f64, DVec3) {
    let c = &p.contact;
    let mut bodies = p.bodies.clone();
    let mut points = vec![PointConstraint::new(c.normal, c.r_a, c.r_b, 0.0, 0.0)];
    let mut patches = vec![ManifoldConstraint::new(
        c.body_a as u32,
        c.body_b as u32,
        0,
        1,
        c.normal,
        c.friction,
        0.0,
        DVec3::ZERO,
        0.0,
    )];
    prepare(&mut patches[0], &mut points, &bodies);
    for _ in 0..500 {
        solve(&mut patches, &mut points, &mut bodies, 1.0 / 240.0);
    }
    (bodies, points[0].normal_impulse, patches[0].tangent_impulse())
}

fn reference(p: &Problem, k: usize) -> tumble::solver::FrictionConeSolution {
    let states: Vec<BodyState> = p.bodies.iter().map(SolverBody::lcp_state).collect();
    solve_friction_cone(&states, &[p.contact], k).unwrap()
}

fn energy(bodies: &[SolverBody], v: impl Fn(usize) -> (DVec3, DVec3)) -> f64 {
    (1..bodies.len())
        .map(|i| {
            let b = &bodies[i];
            let (lin, ang) = v(i);
            let inertia = b.inv_inertia.inverse();
            0.5 * lin.length_squared() / b.inv_mass + 0.5 * ang.dot(inertia * ang)
        })
        .sum()
}

#[test]
fn fast_solver_agrees_with_the_friction_cone_reference() {
    let mut rng = Rng(0xf21c_7104_0000_0001);
    let k = 128;
    // The 128-gon's edges are pi/128 apart: a friction direction chosen
    // among them is off by at most that angle.
    let polygon = (std::f64::consts::PI / k as f64).sin();
    let (mut sticking, mut sliding_iso, mut sliding) = (0, 0, 0);
    for case in 0..240 {
        let isotropic = case % 2 == 0;
        let p = problem(&mut rng, isotropic);
        let (after, normal, friction) = fast(&p);
        let r = reference(&p, k);
        let c = &p.contact;
        let scale = 1.0 + p.bodies[1].v.length() + p.bodies[1].w.length() + p.bodies[2].v.length();
        // Both stop the approach; the normal impulses carry the same sign of work.
        let rel = |v: &dyn Fn(usize) -> (DVec3, DVec3)| {
            let (va, wa) = v(c.body_a);
            let (vb, wb) = v(c.body_b);
            (va + wa.cross(c.r_a)) - (vb + wb.cross(c.r_b))
        };
        let fast_rel = rel(&|i| (after[i].v, after[i].w));
        let ref_rel = rel(&|i| (r.velocities[i].linear, r.velocities[i].angular));
        assert!(
            fast_rel.dot(c.normal) > -1e-9 * scale,
            "case {case}: fast approaches"
        );
        assert!(
            ref_rel.dot(c.normal) > -1e-9 * scale,
            "case {case}: reference approaches"
        );
        let e0 = energy(&p.bodies, |i| (p.bodies[i].v, p.bodies[i].w));
        let e_fast = energy(&p.bodies, |i| (after[i].v, after[i].w));
        let e_ref = energy(&p.bodies, |i| (r.velocities[i].linear, r.velocities[i].angular));
        assert!(
            e_fast <= e0 * (1.0 + 1e-12) && e_ref <= e0 * (1.0 + 1e-12),
            "case {case}: energy gained"
        );
        let ref_slides = r.sliding_speed[0] > 1e-7 * scale;
        let fast_tangent = (fast_rel - c.normal * fast_rel.dot(c.normal)).length();
        if !ref_slides {
            // Sticking: unique answer; the fast solver stops the point too.
            sticking += 1;
            assert!(
                fast_tangent < 1e-6 * scale,
                "case {case}: reference sticks, fast slides {fast_tangent}"
            );
            for (i, (x, y)) in after.iter().zip(&r.velocities).enumerate().skip(1) {
                let (dv, dw) = (x.v - y.linear, x.w - y.angular);
                assert!(dv.length() + dw.length() < 1e-6 * scale, "case {case}, body {i}");
            }
            assert!((normal - r.normal[0]).abs() < 1e-6 * (1.0 + normal));
            assert!((friction - r.friction[0]).length() < 1e-6 * (1.0 + normal));
            continue;
        }
        // Sliding: friction on the rim of the cone for both.
        let rim = c.friction * r.normal[0];
        assert!(
            r.friction[0].length() <= rim * (1.0 + 1e-9) && r.friction[0].length() >= rim * (1.0 - polygon)
        );
        assert!(
            (friction.length() - c.friction * normal).abs() < 1e-6 * (1.0 + normal),
            "case {case}: fast friction {} off the rim {}",
            friction.length(),
            c.friction * normal
        );
        if isotropic {
            // Then the sequential tangent rows and the disc projection are
            // exact: the two differ only by the polygon.
            sliding_iso += 1;
            let tol = 2.0 * polygon * (rim * p.bodies[1].inv_mass) + 1e-7 * scale;
            assert!(
                (after[1].v - r.velocities[1].linear).length() < tol,
                "case {case}: fast {:?} vs reference {:?} (tolerance {tol})",
                after[1].v,
                r.velocities[1].linear
            );
        } else {
            sliding += 1;
        }
    }
    assert!(
        sticking > 20 && sliding_iso > 20 && sliding > 20,
        "{sticking} / {sliding_iso} / {sliding}"
    );
}
