//! Shared helpers for the solver tests: a tiny deterministic RNG, random
//! contact configurations, random matrices, and a brute-force LCP oracle.
#![allow(dead_code)]

use tumble::collide::math::{DMat3, DQuat, DVec3};
use tumble::solver::{BodyState, ContactRow, DenseMatrix};

/// The random source of the LCP tests: SplitMix64 (`tumble-testkit`) from
/// a scrambled seed, so that neighbouring seeds give unrelated problems.
pub use tumble_testkit::{RandomSource, SplitMix64 as Rng};

/// The generator for test case `seed`.
pub fn rng(seed: u64) -> Rng {
    tumble_testkit::SplitMix64(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0xD1B5_4A32_D192_ED03)
}

/// World inverse inertia `R diag(1/I) R^T`.
pub fn world_inv_inertia(principal: DVec3, rot: DQuat) -> DMat3 {
    let r = DMat3::from_quat(rot);
    r * DMat3::from_diagonal(DVec3::ONE / principal) * r.transpose()
}

/// `nb` bodies (body 0 static) with random masses, inertias and velocities,
/// and `m` random contacts between distinct bodies, never static-static.
pub fn random_contacts(rng: &mut Rng, nb: usize, m: usize) -> (Vec<BodyState>, Vec<ContactRow>) {
    let mut bodies = vec![BodyState::fixed()];
    for _ in 1..nb {
        let mass = rng.range(0.5, 5.0);
        let principal = DVec3::new(rng.range(0.1, 2.0), rng.range(0.1, 2.0), rng.range(0.1, 2.0));
        bodies.push(BodyState {
            inv_mass: 1.0 / mass,
            inv_inertia: world_inv_inertia(principal, rng.rotation()),
            linear_velocity: rng.vec3(2.0),
            angular_velocity: rng.vec3(2.0),
        });
    }
    let contacts = (0..m)
        .map(|_| {
            let a = 1 + rng.below(nb - 1);
            let mut b = rng.below(nb);
            while b == a {
                b = rng.below(nb);
            }
            ContactRow {
                body_a: a,
                body_b: b,
                r_a: rng.vec3(1.0),
                r_b: rng.vec3(1.0),
                normal: rng.unit_vector(),
                bias: 0.0,
                friction: rng.range(0.0, 1.0),
            }
        })
        .collect();
    (bodies, contacts)
}

pub fn random_matrix(rng: &mut Rng, n: usize, s: f64) -> DenseMatrix {
    let data = (0..n * n).map(|_| rng.range(-s, s)).collect();
    DenseMatrix::from_row_major(n, data).unwrap()
}

/// Symmetric positive definite: `B B^T + delta I`.
pub fn random_spd(rng: &mut Rng, n: usize, delta: f64) -> DenseMatrix {
    let b = random_matrix(rng, n, 1.0);
    let mut a = DenseMatrix::zeros(n);
    for i in 0..n {
        for j in 0..n {
            let v: f64 = (0..n).map(|k| b.get(i, k) * b.get(j, k)).sum();
            a.set(i, j, v + if i == j { delta } else { 0.0 });
        }
    }
    a
}

/// Non-symmetric positive definite: SPD plus a skew-symmetric part
/// (`x.Ax = x.Sx > 0`), hence a P-matrix.
pub fn random_pd_nonsym(rng: &mut Rng, n: usize) -> DenseMatrix {
    let mut a = random_spd(rng, n, 0.5);
    for i in 0..n {
        for j in i + 1..n {
            let s = rng.range(-2.0, 2.0);
            a.set(i, j, a.get(i, j) + s);
            a.set(j, i, a.get(j, i) - s);
        }
    }
    a
}

/// P-matrix that is not positive definite in general: strictly row
/// diagonally dominant with a positive diagonal (every principal submatrix
/// is then also such a matrix, with a positive determinant).
pub fn random_p_matrix(rng: &mut Rng, n: usize) -> DenseMatrix {
    let mut a = random_matrix(rng, n, 3.0);
    for i in 0..n {
        let off: f64 = (0..n).filter(|&j| j != i).map(|j| a.get(i, j).abs()).sum();
        a.set(i, i, off + rng.range(0.1, 1.0));
    }
    a
}

/// Solves the dense system `m x = r` by Gaussian elimination with partial
/// pivoting; `None` if singular.
#[allow(clippy::needless_range_loop)] // textbook elimination
pub fn solve_dense(mut m: Vec<Vec<f64>>, mut r: Vec<f64>) -> Option<Vec<f64>> {
    let n = r.len();
    for k in 0..n {
        let p = (k..n).max_by(|&i, &j| m[i][k].abs().total_cmp(&m[j][k].abs()))?;
        if m[p][k].abs() < 1e-13 {
            return None;
        }
        m.swap(k, p);
        r.swap(k, p);
        for i in k + 1..n {
            let f = m[i][k] / m[k][k];
            for j in k..n {
                m[i][j] -= f * m[k][j];
            }
            r[i] -= f * r[k];
        }
    }
    let mut x = vec![0.0; n];
    for k in (0..n).rev() {
        let s: f64 = (k + 1..n).map(|j| m[k][j] * x[j]).sum();
        x[k] = (r[k] - s) / m[k][k];
    }
    Some(x)
}

/// Brute-force oracle: every complementary basis (which `z_i` may be
/// non-zero), solved directly; returns all solutions found.
pub fn brute_force_lcp(a: &DenseMatrix, q: &[f64], tol: f64) -> Vec<Vec<f64>> {
    let n = a.n();
    let mut out = Vec::new();
    for mask in 0u32..(1 << n) {
        let act: Vec<usize> = (0..n).filter(|i| mask & (1 << i) != 0).collect();
        let m = act
            .iter()
            .map(|&i| act.iter().map(|&j| a.get(i, j)).collect())
            .collect();
        let r = act.iter().map(|&i| -q[i]).collect();
        let Some(x) = solve_dense(m, r) else { continue };
        let mut z = vec![0.0; n];
        for (k, &i) in act.iter().enumerate() {
            z[i] = x[k];
        }
        let ok = (0..n).all(|i| {
            let w: f64 = (0..n).map(|j| a.get(i, j) * z[j]).sum::<f64>() + q[i];
            z[i] >= -tol && w >= -tol
        });
        if ok {
            out.push(z);
        }
    }
    out
}

pub fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

pub fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}
