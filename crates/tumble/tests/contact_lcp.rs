//! Contact LCP assembly and solves on scenes with hand-derived answers:
//! the thesis 7.1 impulse, statics of a resting box and a tripod, Coulomb
//! friction on a slope, energy dissipation, and typed assembly errors.

#[path = "lcp_common/mod.rs"]
mod common;

use common::{max_abs, random_contacts, rng, world_inv_inertia, RandomSource};
use tumble::collide::math::{DMat3, DQuat, DVec3};
use tumble::solver::{
    build_contact_lcp, check, lemke, pgs, pgs_boxed, BodyState, BodyVelocity, ContactLcpError, ContactRow,
};

const G: f64 = 9.81;
const DT: f64 = 1.0 / 60.0;

/// Thesis 7.1 denominator, written as in the thesis.
fn thesis_denominator(a: &BodyState, b: &BodyState, ra: DVec3, rb: DVec3, n: DVec3) -> f64 {
    a.inv_mass
        + b.inv_mass
        + n.dot((a.inv_inertia * ra.cross(n)).cross(ra))
        + n.dot((b.inv_inertia * rb.cross(n)).cross(rb))
}

#[test]
fn diagonal_is_the_thesis_impulse_denominator() {
    let mut rng = rng(20);
    for _ in 0..50 {
        let (bodies, contacts) = random_contacts(&mut rng, 4, 10);
        let lcp = build_contact_lcp(&bodies, &contacts, false).unwrap();
        for (i, c) in contacts.iter().enumerate() {
            let d = thesis_denominator(&bodies[c.body_a], &bodies[c.body_b], c.r_a, c.r_b, c.normal);
            assert!((lcp.a.get(i, i) - d).abs() < 1e-12 * (1.0 + d), "{i}");
        }
    }
}

#[test]
fn matrix_equals_explicit_jacobian_product() {
    // Cross-check: build J (rows x 6 nb) and block-diagonal M^-1 densely and
    // multiply, with no knowledge of which bodies rows share.
    let mut rng = rng(21);
    for _ in 0..20 {
        let nb = 4;
        let (bodies, contacts) = random_contacts(&mut rng, nb, 8);
        let lcp = build_contact_lcp(&bodies, &contacts, true).unwrap();
        let k = lcp.rows.len();
        let mut j = vec![vec![0.0; 6 * nb]; k];
        for (i, r) in lcp.rows.iter().enumerate() {
            for (body, s, ang) in [(r.body_a, 1.0, r.angular_a), (r.body_b, -1.0, r.angular_b)] {
                for c in 0..3 {
                    j[i][6 * body + c] += s * r.direction[c];
                    j[i][6 * body + 3 + c] += s * ang[c];
                }
            }
        }
        let minv_jt = |row: &[f64]| -> Vec<f64> {
            let mut out = vec![0.0; 6 * nb];
            for (b, body) in bodies.iter().enumerate() {
                let lin = DVec3::from_slice(&row[6 * b..6 * b + 3]) * body.inv_mass;
                let ang = body.inv_inertia * DVec3::from_slice(&row[6 * b + 3..6 * b + 6]);
                lin.write_to_slice(&mut out[6 * b..6 * b + 3]);
                ang.write_to_slice(&mut out[6 * b + 3..6 * b + 6]);
            }
            out
        };
        for col in 0..k {
            let x = minv_jt(&j[col]);
            for (row, jr) in j.iter().enumerate() {
                let v: f64 = jr.iter().zip(&x).map(|(p, q)| p * q).sum();
                assert!((lcp.a.get(row, col) - v).abs() < 1e-12 * (1.0 + v.abs()));
            }
        }
        // And b = J u.
        for (row, jr) in j.iter().enumerate() {
            let ju: f64 = bodies
                .iter()
                .enumerate()
                .map(|(b, s)| {
                    DVec3::from_slice(&jr[6 * b..6 * b + 3]).dot(s.linear_velocity)
                        + DVec3::from_slice(&jr[6 * b + 3..6 * b + 6]).dot(s.angular_velocity)
                })
                .sum();
            assert!((lcp.b[row] - ju).abs() < 1e-12 * (1.0 + ju.abs()));
        }
    }
}

#[test]
fn single_contact_gives_the_thesis_impulse() {
    // j = -(1 + e) v_rel / denominator, and v_rel+ = -e v_rel- (thesis 7.1).
    let mut rng = rng(22);
    for case in 0..100 {
        let (bodies, mut contacts) = random_contacts(&mut rng, 3, 1);
        let c = &mut contacts[0];
        let v_rel = c
            .normal
            .dot(bodies[c.body_a].point_velocity(c.r_a) - bodies[c.body_b].point_velocity(c.r_b));
        let e = rng.range(0.0, 1.0);
        c.bias = e * v_rel.min(0.0);
        let c = *c;
        let lcp = build_contact_lcp(&bodies, &contacts, false).unwrap();
        let sol = lemke(&lcp.a, &lcp.b).unwrap();
        let denom = thesis_denominator(&bodies[c.body_a], &bodies[c.body_b], c.r_a, c.r_b, c.normal);
        let expected = if v_rel < 0.0 {
            -(1.0 + e) * v_rel / denom
        } else {
            0.0
        };
        assert!(
            (sol.z[0] - expected).abs() < 1e-10 * (1.0 + expected),
            "case {case}"
        );
        let after = lcp.velocities_after(&bodies, &sol.z).unwrap();
        let v_after = c.normal.dot(
            (after[c.body_a].linear + after[c.body_a].angular.cross(c.r_a))
                - (after[c.body_b].linear + after[c.body_b].angular.cross(c.r_b)),
        );
        let want = if v_rel < 0.0 { -e * v_rel } else { v_rel };
        assert!(
            (v_after - want).abs() < 1e-10 * (1.0 + v_rel.abs()),
            "case {case}"
        );
    }
}

fn kinetic_energy(bodies: &[BodyState], v: &[BodyVelocity]) -> f64 {
    bodies
        .iter()
        .zip(v)
        .filter(|(b, _)| b.inv_mass > 0.0)
        .map(|(b, v)| {
            let inertia = b.inv_inertia.inverse();
            0.5 * v.linear.length_squared() / b.inv_mass + 0.5 * v.angular.dot(inertia * v.angular)
        })
        .sum()
}

#[test]
fn inelastic_contact_impulses_never_add_energy() {
    // With bias 0: dKE = z.Ju + 1/2 z.Az = z.(Az + q) - 1/2 z.Az = -1/2 z.Az <= 0.
    let mut rng = rng(23);
    for case in 0..100 {
        let m = 1 + rng.below(12);
        let (bodies, contacts) = random_contacts(&mut rng, 4, m);
        let lcp = build_contact_lcp(&bodies, &contacts, false).unwrap();
        let sol = lemke(&lcp.a, &lcp.b).unwrap();
        let before: Vec<BodyVelocity> = bodies
            .iter()
            .map(|b| BodyVelocity {
                linear: b.linear_velocity,
                angular: b.angular_velocity,
            })
            .collect();
        let after = lcp.velocities_after(&bodies, &sol.z).unwrap();
        let (e0, e1) = (kinetic_energy(&bodies, &before), kinetic_energy(&bodies, &after));
        assert!(e1 <= e0 * (1.0 + 1e-9) + 1e-12, "case {case}: {e0} -> {e1}");
        let za: f64 = lcp
            .a
            .mul_vec(&sol.z)
            .unwrap()
            .iter()
            .zip(&sol.z)
            .map(|(x, y)| x * y)
            .sum();
        assert!((e0 - e1 - 0.5 * za).abs() < 1e-8 * (1.0 + e0), "case {case}");
    }
}

/// A box (half extents `h`, mass `m`) with orientation `rot`, falling at
/// `g dt` after one gravity step, touching static body 0 at its four bottom
/// corners with normal `rot * z`.
fn box_on_plane(h: DVec3, m: f64, rot: DQuat, mu: f64) -> (Vec<BodyState>, Vec<ContactRow>) {
    let principal = DVec3::new(
        h.y * h.y + h.z * h.z,
        h.x * h.x + h.z * h.z,
        h.x * h.x + h.y * h.y,
    ) * (m / 3.0);
    let bodies = vec![
        BodyState::fixed(),
        BodyState {
            inv_mass: 1.0 / m,
            inv_inertia: world_inv_inertia(principal, rot),
            linear_velocity: DVec3::new(0.0, 0.0, -G * DT),
            angular_velocity: DVec3::ZERO,
        },
    ];
    let normal = rot * DVec3::Z;
    let contacts = [(1.0, 1.0), (1.0, -1.0), (-1.0, -1.0), (-1.0, 1.0)]
        .iter()
        .map(|&(sx, sy)| {
            let r_a = rot * DVec3::new(sx * h.x, sy * h.y, -h.z);
            ContactRow {
                body_a: 1,
                body_b: 0,
                r_a,
                r_b: r_a, // ground frame at the box centre; static, so unused
                normal,
                bias: 0.0,
                friction: mu,
            }
        })
        .collect();
    (bodies, contacts)
}

#[test]
fn box_resting_on_four_contacts_carries_its_weight() {
    // Statics over one step: sum z = m g dt; zero moment about the centre.
    // Four coplanar contacts leave z itself indeterminate along
    // (1, -1, 1, -1), so the split is checked up to that family: the
    // symmetric part is exactly m g dt / 4 per corner.
    let (h, m) = (DVec3::new(0.5, 0.3, 0.2), 3.0);
    let (bodies, contacts) = box_on_plane(h, m, DQuat::IDENTITY, 0.0);
    let lcp = build_contact_lcp(&bodies, &contacts, false).unwrap();
    let exact = lemke(&lcp.a, &lcp.b).unwrap();
    let iter = pgs(&lcp.a, &lcp.b, 10_000, 1e-14, None).unwrap();
    for (name, z) in [("lemke", &exact.z), ("pgs", &iter.z)] {
        let total: f64 = z.iter().sum();
        assert!((total - m * G * DT).abs() < 1e-10, "{name}: {total}");
        let twist = (z[0] - z[1] + z[2] - z[3]) / 4.0;
        for (i, zi) in z.iter().enumerate() {
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            let sym = zi - sign * twist;
            assert!((sym - m * G * DT / 4.0).abs() < 1e-10, "{name}: {z:?}");
        }
        let v = lcp.velocities_after(&bodies, z).unwrap();
        assert!(
            v[1].linear.length() < 1e-10 && v[1].angular.length() < 1e-10,
            "{name}"
        );
        assert!(check(&lcp.a, &lcp.b, z).unwrap().within(1e-10));
    }
}

#[test]
fn tripod_splits_weight_by_the_lever_rule() {
    // Three legs at p_k under a body whose centre projects inside the
    // triangle: the only statically admissible split is z_k = m g dt * lambda_k
    // with lambda the barycentric coordinates of the centre's projection.
    let m = 2.0;
    let legs = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.2, 0.9, 0.0),
    ];
    let centre = DVec3::new(0.35, 0.3, 0.4);
    let bodies = vec![
        BodyState::fixed(),
        BodyState {
            inv_mass: 1.0 / m,
            inv_inertia: world_inv_inertia(DVec3::new(0.3, 0.4, 0.5), DQuat::IDENTITY),
            linear_velocity: DVec3::new(0.0, 0.0, -G * DT),
            angular_velocity: DVec3::ZERO,
        },
    ];
    let contacts: Vec<ContactRow> = legs
        .iter()
        .map(|&p| ContactRow {
            body_a: 1,
            body_b: 0,
            r_a: p - centre,
            r_b: p,
            normal: DVec3::Z,
            bias: 0.0,
            friction: 0.0,
        })
        .collect();
    // Barycentric coordinates of (centre.x, centre.y) in the leg triangle.
    let t = DMat3::from_cols(
        DVec3::new(legs[0].x, legs[0].y, 1.0),
        DVec3::new(legs[1].x, legs[1].y, 1.0),
        DVec3::new(legs[2].x, legs[2].y, 1.0),
    );
    let lambda = t.inverse() * DVec3::new(centre.x, centre.y, 1.0);
    let lcp = build_contact_lcp(&bodies, &contacts, false).unwrap();
    let exact = lemke(&lcp.a, &lcp.b).unwrap();
    let iter = pgs(&lcp.a, &lcp.b, 10_000, 1e-14, None).unwrap();
    for k in 0..3 {
        let want = m * G * DT * lambda[k];
        assert!((exact.z[k] - want).abs() < 1e-10, "lemke leg {k}");
        assert!((iter.z[k] - want).abs() < 1e-9, "pgs leg {k}");
    }
}

fn slope(theta: f64, mu: f64) -> (Vec<BodyState>, Vec<ContactRow>) {
    box_on_plane(DVec3::new(0.4, 0.3, 0.1), 5.0, DQuat::from_rotation_y(theta), mu)
}

#[test]
fn block_on_slope_sticks_when_mu_exceeds_tan_theta() {
    let theta: f64 = 0.4; // tan = 0.42
    let (bodies, contacts) = slope(theta, 0.6);
    let lcp = build_contact_lcp(&bodies, &contacts, true).unwrap();
    let s = pgs_boxed(&lcp.a, &lcp.b, &lcp.limits, 20_000, 1e-13, None).unwrap();
    let v = lcp.velocities_after(&bodies, &s.z).unwrap();
    // Every contact point at rest: the body at rest.
    assert!(v[1].linear.length() < 1e-8 * G * DT, "{:?}", v[1]);
    assert!(v[1].angular.length() < 1e-8, "{:?}", v[1]);
    // Friction within the pyramid, normal impulses carry m g cos(theta) dt.
    let n: f64 = s.z[..4].iter().sum();
    assert!((n - 5.0 * G * DT * theta.cos()).abs() < 1e-8);
    for k in 0..4 {
        for t in [4 + 2 * k, 5 + 2 * k] {
            assert!(s.z[t].abs() <= 0.6 * s.z[k] + 1e-12);
        }
    }
}

#[test]
fn block_on_slope_slides_when_mu_is_below_tan_theta() {
    let theta: f64 = 0.5; // tan = 0.546
    let mu = 0.3;
    let m = 5.0;
    let (bodies, contacts) = slope(theta, mu);
    let lcp = build_contact_lcp(&bodies, &contacts, true).unwrap();
    let s = pgs_boxed(&lcp.a, &lcp.b, &lcp.limits, 20_000, 1e-13, None).unwrap();
    assert!(s.converged, "residual {}", s.residual);
    let normal: f64 = s.z[..4].iter().sum();
    assert!((normal - m * G * DT * theta.cos()).abs() < 1e-9);
    // Kinetic friction saturates on every contact: |friction| = mu * normal,
    // opposing the sliding direction (t1 is along the sliding velocity).
    // Across the slope (t2) the four friction impulses are indeterminate
    // (internal, self-cancelling patterns) but must add up to nothing.
    for k in 0..4 {
        assert!((s.z[4 + 2 * k] + mu * s.z[k]).abs() < 1e-9, "contact {k}");
    }
    let across: f64 = (0..4).map(|k| s.z[5 + 2 * k]).sum();
    assert!(across.abs() < 1e-9);
    let v = lcp.velocities_after(&bodies, &s.z).unwrap();
    let down = DQuat::from_rotation_y(theta) * DVec3::X;
    let n = DQuat::from_rotation_y(theta) * DVec3::Z;
    let expected = G * DT * (theta.sin() - mu * theta.cos());
    assert!((v[1].linear.dot(down) - expected).abs() < 1e-9);
    assert!(v[1].linear.dot(n).abs() < 1e-9);
    assert!(v[1].angular.length() < 1e-8);
}

#[test]
fn bad_contacts_are_typed_errors() {
    let (bodies, contacts) = box_on_plane(DVec3::ONE, 1.0, DQuat::IDENTITY, 0.5);
    let bad = |f: &dyn Fn(&mut ContactRow)| {
        let mut c = contacts.clone();
        f(&mut c[2]);
        build_contact_lcp(&bodies, &c, true).unwrap_err()
    };
    assert!(matches!(
        bad(&|c| c.body_b = 7),
        ContactLcpError::BodyIndex {
            contact: 2,
            body: 7,
            count: 2
        }
    ));
    assert!(matches!(
        bad(&|c| c.body_b = 1),
        ContactLcpError::SameBody { contact: 2, .. }
    ));
    assert!(matches!(
        bad(&|c| c.normal *= 2.0),
        ContactLcpError::NormalNotUnit { contact: 2, .. }
    ));
    assert!(matches!(
        bad(&|c| c.r_a.x = f64::NAN),
        ContactLcpError::NonFinite { field: "r_a", .. }
    ));
    assert!(matches!(
        bad(&|c| c.friction = -1.0),
        ContactLcpError::Negative {
            field: "friction",
            ..
        }
    ));
    let mut nan_body = bodies.clone();
    nan_body[1].inv_inertia.x_axis.y = f64::INFINITY;
    assert!(matches!(
        build_contact_lcp(&nan_body, &contacts, false),
        Err(ContactLcpError::NonFinite {
            what: "body",
            index: 1,
            ..
        })
    ));
    let lcp = build_contact_lcp(&bodies, &contacts, false).unwrap();
    assert!(matches!(
        lcp.velocities_after(&bodies, &[0.0; 3]),
        Err(ContactLcpError::ImpulseCount {
            expected: 4,
            found: 3
        })
    ));
    assert!(max_abs(&lcp.b) > 0.0);
}
