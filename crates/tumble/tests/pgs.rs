//! Projected Gauss-Seidel: agreement with Lemke (unique z on SPD problems,
//! unique w and velocities on redundant PSD contact problems), box KKT
//! conditions, warm starting, typed errors.

#[path = "lcp_common/mod.rs"]
mod common;

use common::{max_abs, max_abs_diff, random_contacts, random_spd, rng, RandomSource};
use tumble::solver::{build_contact_lcp, check, lemke, pgs, pgs_boxed, DenseMatrix, LcpError, RowLimit};

#[test]
fn pgs_converges_to_lemke_on_spd_problems() {
    // Symmetric positive definite: one solution, which both must find.
    let mut rng = rng(10);
    for case in 0..100 {
        let n = 1 + rng.below(12);
        let a = random_spd(&mut rng, n, 1.0);
        let q: Vec<f64> = (0..n).map(|_| rng.range(-3.0, 3.0)).collect();
        let exact = lemke(&a, &q).unwrap();
        let iter = pgs(&a, &q, 20_000, 1e-12, None).unwrap();
        assert!(iter.converged, "case {case}: residual {}", iter.residual);
        let scale = 1.0 + max_abs(&exact.z);
        assert!(
            max_abs_diff(&iter.z, &exact.z) < 1e-8 * scale,
            "case {case}: {:?} vs {:?}",
            iter.z,
            exact.z
        );
        assert!(check(&a, &q, &iter.z).unwrap().within(1e-9 * scale));
    }
}

#[test]
fn pgs_matches_lemke_velocities_on_redundant_contacts() {
    // More contacts than degrees of freedom: z is not unique, but w = A z + q
    // and the body velocities u + M^-1 J^T z are (A(z1 - z2) = 0 implies
    // M^-1 J^T (z1 - z2) = 0 for PSD A = J M^-1 J^T).
    let mut rng = rng(11);
    for case in 0..60 {
        let nb = 2 + rng.below(2);
        let m = 6 * (nb - 1) + 1 + rng.below(6);
        let (bodies, mut contacts) = random_contacts(&mut rng, nb, m);
        for c in &mut contacts {
            c.bias = rng.range(1e-2, 1e-1); // robustly feasible, see lemke.rs
        }
        let lcp = build_contact_lcp(&bodies, &contacts, false).unwrap();
        let Ok(exact) = lemke(&lcp.a, &lcp.b) else {
            panic!("case {case}: Lemke failed")
        };
        let iter = pgs(&lcp.a, &lcp.b, 50_000, 1e-10, None).unwrap();
        assert!(iter.converged, "case {case}: residual {}", iter.residual);
        let scale = 1.0 + max_abs(&lcp.b);
        assert!(max_abs_diff(&iter.w, &exact.w) < 1e-6 * scale, "case {case}");
        let ve = lcp.velocities_after(&bodies, &exact.z).unwrap();
        let vi = lcp.velocities_after(&bodies, &iter.z).unwrap();
        for (e, i) in ve.iter().zip(&vi) {
            assert!((e.linear - i.linear).length() < 1e-6 * scale, "case {case}");
            assert!((e.angular - i.angular).length() < 1e-6 * scale, "case {case}");
        }
    }
}

#[test]
fn warm_start_at_the_solution_needs_no_sweep() {
    let mut rng = rng(12);
    let a = random_spd(&mut rng, 8, 1.0);
    let q: Vec<f64> = (0..8).map(|_| rng.range(-3.0, 3.0)).collect();
    let exact = lemke(&a, &q).unwrap();
    let warm = pgs(&a, &q, 100, 1e-9, Some(&exact.z)).unwrap();
    assert_eq!(warm.iterations, 0);
    assert!(warm.converged);
    let cold = pgs(&a, &q, 10_000, 1e-9, None).unwrap();
    assert!(cold.iterations > 0);
}

#[test]
fn boxed_pgs_satisfies_the_box_kkt_conditions() {
    // For SPD A the boxed LCP is the optimality condition of
    // min 1/2 z.Az + q.z over the box: w_i >= 0 at lo, w_i <= 0 at hi,
    // w_i = 0 strictly inside.
    // Random SPD problems as in pgs_converges_to_lemke_on_spd_problems, with
    // their own seed and range: each test owns its draws, so a case reproduces.
    let mut rng = rng(13);
    for case in 0..100 {
        let n = 1 + rng.below(10);
        let a = random_spd(&mut rng, n, 1.0);
        let q: Vec<f64> = (0..n).map(|_| rng.range(-5.0, 5.0)).collect();
        let limits: Vec<RowLimit> = (0..n)
            .map(|_| {
                let lo = rng.range(-1.0, 0.5);
                RowLimit::Box {
                    lo,
                    hi: lo + rng.range(0.0, 1.0),
                }
            })
            .collect();
        let s = pgs_boxed(&a, &q, &limits, 20_000, 1e-12, None).unwrap();
        assert!(s.converged, "case {case}");
        for (i, limit) in limits.iter().enumerate() {
            let RowLimit::Box { lo, hi } = *limit else {
                unreachable!()
            };
            let (z, w) = (s.z[i], s.w[i]);
            assert!(z >= lo && z <= hi, "case {case} row {i}: bounds");
            if z > lo + 1e-9 && z < hi - 1e-9 {
                assert!(w.abs() < 1e-8, "case {case} row {i}: interior w = {w}");
            } else if z <= lo + 1e-9 && hi - lo > 1e-9 {
                assert!(w > -1e-8, "case {case} row {i}: at lo, w = {w}");
            } else if hi - lo > 1e-9 {
                assert!(w < 1e-8, "case {case} row {i}: at hi, w = {w}");
            }
        }
    }
}

#[test]
fn boxed_with_nonnegative_limits_is_plain_pgs() {
    let mut rng = rng(14);
    let a = random_spd(&mut rng, 6, 1.0);
    let q: Vec<f64> = (0..6).map(|_| rng.range(-3.0, 3.0)).collect();
    let plain = pgs(&a, &q, 500, 0.0, None).unwrap();
    let boxed = pgs_boxed(&a, &q, &[RowLimit::NON_NEGATIVE; 6], 500, 0.0, None).unwrap();
    assert_eq!(plain, boxed); // bit-identical: same arithmetic in the same order
}

#[test]
fn bad_inputs_are_typed_errors() {
    let a = DenseMatrix::identity(2);
    assert!(matches!(
        pgs(&a, &[1.0], 10, 1e-9, None),
        Err(LcpError::SizeMismatch { .. })
    ));
    assert!(matches!(
        pgs(&a, &[1.0, 1.0], 10, 1e-9, Some(&[f64::NAN, 0.0])),
        Err(LcpError::NonFinite {
            what: "warm start",
            ..
        })
    ));
    assert!(matches!(
        pgs(&a, &[1.0, 1.0], 10, f64::NAN, None),
        Err(LcpError::BadParameter { .. })
    ));
    let mut singular = DenseMatrix::identity(2);
    singular.set(1, 1, 0.0);
    assert!(matches!(
        pgs(&singular, &[1.0, 1.0], 10, 1e-9, None),
        Err(LcpError::NonPositiveDiagonal { row: 1, .. })
    ));
    let bad_box = [RowLimit::NON_NEGATIVE, RowLimit::Box { lo: 1.0, hi: 0.0 }];
    assert!(matches!(
        pgs_boxed(&a, &[1.0, 1.0], &bad_box, 10, 1e-9, None),
        Err(LcpError::BadParameter { .. })
    ));
    // Two bad friction rows, each written out with its own fault (a row
    // bounded by itself, a negative mu) so a failing assert names one.
    let self_ref = [
        RowLimit::NON_NEGATIVE,
        RowLimit::Friction {
            normal_row: 1,
            mu: 0.5,
        },
    ];
    assert!(matches!(
        pgs_boxed(&a, &[1.0, 1.0], &self_ref, 10, 1e-9, None),
        Err(LcpError::BadParameter { .. })
    ));
    let neg_mu = [
        RowLimit::NON_NEGATIVE,
        RowLimit::Friction {
            normal_row: 0,
            mu: -0.5,
        },
    ];
    assert!(matches!(
        pgs_boxed(&a, &[1.0, 1.0], &neg_mu, 10, 1e-9, None),
        Err(LcpError::BadParameter { .. })
    ));
    assert!(matches!(
        pgs_boxed(&a, &[1.0, 1.0], &[RowLimit::NON_NEGATIVE], 10, 1e-9, None),
        Err(LcpError::SizeMismatch { .. })
    ));
}

#[test]
fn solvers_are_bit_deterministic() {
    let mut rng = rng(15);
    let (bodies, contacts) = random_contacts(&mut rng, 4, 12);
    let lcp = build_contact_lcp(&bodies, &contacts, true).unwrap();
    let run = || {
        let n = contacts.len();
        let normal = tumble::solver::DenseMatrix::from_row_major(
            n,
            (0..n * n).map(|k| lcp.a.get(k / n, k % n)).collect(),
        )
        .unwrap();
        (
            lemke(&normal, &lcp.b[..n]).unwrap(),
            pgs_boxed(&lcp.a, &lcp.b, &lcp.limits, 300, 0.0, None).unwrap(),
        )
    };
    let (l1, p1) = run();
    let (l2, p2) = run();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&l1.z), bits(&l2.z));
    assert_eq!(bits(&p1.z), bits(&p2.z));
    assert_eq!(bits(&p1.w), bits(&p2.w));
}
