//! Lemke's method: answers verified by the independent residual checker, by a
//! brute-force enumeration of complementary bases, and typed errors.

#[path = "lcp_common/mod.rs"]
mod common;

use common::{
    brute_force_lcp, max_abs, max_abs_diff, random_contacts, random_p_matrix, random_pd_nonsym, random_spd,
    rng, RandomSource,
};
use proptest::prelude::*;
use tumble::solver::{build_contact_lcp, check, lemke, lemke_with, DenseMatrix, LcpError, LemkeOptions};

/// Tolerance scaled to the problem's magnitude.
fn tol_for(a: &DenseMatrix, q: &[f64]) -> f64 {
    1e-9 * (1.0 + max_abs(a.as_slice())) * (1.0 + max_abs(q))
}

#[test]
fn contact_matrices_with_any_velocities_are_solved() {
    // A = J M^-1 J^T is PSD and q = J u (static bodies at rest) is feasible:
    // y >= 0 with A y <= 0 forces A y = 0, i.e. J^T y = 0 on every dynamic
    // body, so y.q = (J^T y).u = 0 (Farkas). Lemke must then succeed.
    // (a) At most 6 contacts per dynamic body: J has full row rank in general
    //     position, so A is positive definite.
    // (b) Many contacts (bodies wedged: some y >= 0 has J^T y = 0): the
    //     feasibility above holds only with y.q = 0 exactly, which round-off
    //     can break, so each contact gets a speculative gap (bias = gap/dt > 0)
    //     that makes y.q > 0 robustly.
    let mut rng = rng(1);
    for case in 0..300 {
        let nb = 2 + rng.below(4);
        let wedged = case % 2 == 1;
        let m = if wedged {
            1 + rng.below(30)
        } else {
            1 + rng.below(6 * (nb - 1))
        };
        let (bodies, mut contacts) = random_contacts(&mut rng, nb, m);
        if wedged {
            for c in &mut contacts {
                c.bias = rng.range(1e-3, 1e-2);
            }
        }
        let lcp = build_contact_lcp(&bodies, &contacts, false).unwrap();
        let sol = lemke(&lcp.a, &lcp.b).unwrap_or_else(|e| panic!("case {case}: {e}"));
        let r = check(&lcp.a, &lcp.b, &sol.z).unwrap();
        let tol = tol_for(&lcp.a, &lcp.b) * (1.0 + max_abs(&sol.z));
        assert!(r.within(tol), "case {case}: {r:?}");
    }
}

#[test]
fn contact_matrices_with_planted_solutions_are_solved() {
    // Plant a complementary pair (z*, w*) and set q = w* - A z*; many contacts
    // per body make A rank-deficient (redundant contacts).
    let mut rng = rng(2);
    for case in 0..200 {
        let nb = 2 + rng.below(3);
        let m = 2 + rng.below(30);
        let (bodies, contacts) = random_contacts(&mut rng, nb, m);
        let a = build_contact_lcp(&bodies, &contacts, false).unwrap().a;
        let mut z_star = vec![0.0; m];
        let mut w_star = vec![0.0; m];
        for i in 0..m {
            match rng.below(3) {
                0 => z_star[i] = rng.range(0.0, 2.0),
                1 => w_star[i] = rng.range(0.0, 2.0),
                _ => {} // degenerate: both zero
            }
        }
        let az = a.mul_vec(&z_star).unwrap();
        let q: Vec<f64> = (0..m).map(|i| w_star[i] - az[i]).collect();
        let sol = lemke(&a, &q).unwrap_or_else(|e| panic!("case {case}: {e}"));
        let r = check(&a, &q, &sol.z).unwrap();
        assert!(r.within(tol_for(&a, &q)), "case {case}: {r:?}");
    }
}

#[test]
fn p_matrices_match_the_unique_brute_force_solution() {
    // A P-matrix LCP has exactly one solution for every q (CPS Thm 3.3.7).
    let mut rng = rng(3);
    for case in 0..300 {
        let n = 1 + rng.below(6);
        let a = match case % 3 {
            0 => random_p_matrix(&mut rng, n),
            1 => random_pd_nonsym(&mut rng, n),
            _ => random_spd(&mut rng, n, 0.2),
        };
        let q: Vec<f64> = (0..n).map(|_| rng.range(-3.0, 3.0)).collect();
        let sol = lemke(&a, &q).unwrap_or_else(|e| panic!("case {case}: {e}"));
        assert!(check(&a, &q, &sol.z).unwrap().within(tol_for(&a, &q)));
        let brute = brute_force_lcp(&a, &q, 1e-10);
        assert!(!brute.is_empty(), "case {case}: oracle found nothing");
        for b in &brute {
            assert!(
                max_abs_diff(b, &sol.z) < 1e-8,
                "case {case}: {b:?} vs {:?}",
                sol.z
            );
        }
    }
}

#[test]
fn nonnegative_q_gives_zero_without_pivoting() {
    let a = DenseMatrix::from_rows(&[vec![2.0, -1.0], vec![-1.0, 2.0]]).unwrap();
    let sol = lemke(&a, &[0.5, 0.0]).unwrap();
    assert_eq!(sol.z, vec![0.0, 0.0]);
    assert_eq!(sol.iterations, 0);
}

#[test]
fn degenerate_equal_q_does_not_cycle() {
    // Identical rows and identical q: every ratio test ties. A = all ones
    // (rank 1, PSD), q = -1: any z >= 0 with sum z = 1 solves it.
    for n in 1..12 {
        let a = DenseMatrix::from_row_major(n, vec![1.0; n * n]).unwrap();
        let q = vec![-1.0; n];
        let sol = lemke(&a, &q).unwrap();
        let total: f64 = sol.z.iter().sum();
        assert!((total - 1.0).abs() < 1e-12, "n {n}: sum z = {total}");
        assert!(check(&a, &q, &sol.z).unwrap().within(1e-12));
    }
}

#[test]
fn infeasible_psd_problem_ends_on_a_ray() {
    // w1 + w2 = -2 for every z: no solution; A is PSD so Lemke must say so.
    let a = DenseMatrix::from_rows(&[vec![1.0, -1.0], vec![-1.0, 1.0]]).unwrap();
    assert!(matches!(
        lemke(&a, &[-1.0, -1.0]),
        Err(LcpError::RayTermination { .. })
    ));
    // A zero row with negative q: w = q < 0 whatever z is.
    let z = DenseMatrix::zeros(1);
    assert!(matches!(lemke(&z, &[-1.0]), Err(LcpError::RayTermination { .. })));
}

#[test]
fn bad_inputs_are_typed_errors() {
    let mut a = DenseMatrix::identity(2);
    assert!(matches!(
        lemke(&a, &[1.0]),
        Err(LcpError::SizeMismatch {
            expected: 2,
            found: 1,
            ..
        })
    ));
    assert!(matches!(
        lemke(&a, &[1.0, f64::NAN]),
        Err(LcpError::NonFinite {
            what: "q",
            index: 1,
            ..
        })
    ));
    a.set(1, 0, f64::INFINITY);
    assert!(matches!(
        lemke(&a, &[1.0, 1.0]),
        Err(LcpError::NonFinite {
            what: "A",
            index: 2,
            ..
        })
    ));
    assert!(matches!(
        DenseMatrix::from_row_major(3, vec![0.0; 8]),
        Err(LcpError::SizeMismatch {
            expected: 9,
            found: 8,
            ..
        })
    ));
    assert!(matches!(
        DenseMatrix::from_rows(&[vec![1.0, 2.0], vec![3.0]]),
        Err(LcpError::SizeMismatch { .. })
    ));
    let opts = LemkeOptions {
        pivot_tolerance: f64::NAN,
        ..LemkeOptions::default()
    };
    assert!(matches!(
        lemke_with(&DenseMatrix::identity(1), &[-1.0], &opts),
        Err(LcpError::BadParameter { .. })
    ));
}

#[test]
fn pivot_limit_is_reported() {
    // An SPD problem with q < 0 everywhere needs several pivots.
    let mut rng = rng(4);
    let a = random_spd(&mut rng, 8, 0.5);
    let q = vec![-1.0; 8];
    let full = lemke(&a, &q).unwrap();
    assert!(full.iterations > 2);
    let opts = LemkeOptions {
        max_pivots: Some(2),
        ..LemkeOptions::default()
    };
    assert_eq!(lemke_with(&a, &q, &opts), Err(LcpError::PivotLimit { limit: 2 }));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]
    #[test]
    fn prop_diagonally_dominant_lcps_are_solved(
        n in 1usize..7,
        seed in any::<u64>(),
        qs in proptest::collection::vec(-5.0f64..5.0, 7),
    ) {
        let mut rng = rng(seed);
        let a = random_p_matrix(&mut rng, n);
        let q = &qs[..n];
        let sol = lemke(&a, q).unwrap();
        let r = check(&a, q, &sol.z).unwrap();
        prop_assert!(r.within(tol_for(&a, q)), "{:?}", r);
        prop_assert!(sol.converged);
    }
}

#[test]
fn compliance_makes_wedged_contacts_solvable() {
    // Many contacts on few bodies with zero bias: the exact LCP sits on the
    // edge of feasibility (see above) and may end on a ray in floating point.
    // A + eps I is positive definite, so Lemke must succeed on every case,
    // and the answer nearly solves the rigid problem: w_rigid = w - eps z.
    let eps = 1e-9;
    let mut rng = rng(5);
    for case in 0..100 {
        let nb = 2 + rng.below(3);
        let m = 6 * (nb - 1) + 1 + rng.below(12);
        let (bodies, contacts) = random_contacts(&mut rng, nb, m);
        let lcp = build_contact_lcp(&bodies, &contacts, false).unwrap();
        let mut soft = lcp.a.clone();
        soft.add_diagonal(eps).unwrap();
        let sol = lemke(&soft, &lcp.b).unwrap_or_else(|e| panic!("case {case}: {e}"));
        let tol = tol_for(&soft, &lcp.b) * (1.0 + max_abs(&sol.z));
        assert!(check(&soft, &lcp.b, &sol.z).unwrap().within(tol), "case {case}");
        let rigid = check(&lcp.a, &lcp.b, &sol.z).unwrap();
        assert!(
            rigid.min_w >= -eps * max_abs(&sol.z) - tol,
            "case {case}: {rigid:?}"
        );
    }
    let mut a = DenseMatrix::identity(2);
    assert!(matches!(
        a.add_diagonal(f64::NAN),
        Err(LcpError::BadParameter { .. })
    ));
}
