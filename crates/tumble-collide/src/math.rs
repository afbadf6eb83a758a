//! Math layer: glam's f64 types re-exported, plus the few things glam lacks.
//!
//! - [`sym_eigen`]: eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi
//!   rotations (Golub & Van Loan, "Matrix Computations", section 8.5), used to find
//!   principal axes of inertia tensors and OBB axes from covariance matrices.
//! - [`skew`]: the cross-product matrix `a* b = a x b` (thesis 2.1.4).
//! - [`quat_derivative`]: `dq/dt = 1/2 [0, omega] q` (thesis 3.3).
//! - `first_max`: the first index of the largest score (deterministic ties).
//! - tolerance helpers for comparing floats in tests and algorithms.

pub use glam::{DMat3, DQuat, DVec3, Mat3, Quat, Vec3, Vec3A};

/// The first `i` in `0..count` with the largest `score(i)`, and that score:
/// ties go to the lowest index, so the choice is deterministic; `(0,
/// -infinity)` when no score is above -infinity (`count` 0, or all NaN).
/// The scan behind `Polytope::support_vertex`, `Polytope::best_face` and the
/// contact reduction's picks.
#[inline]
pub(crate) fn first_max(count: usize, score: impl Fn(usize) -> f64) -> (usize, f64) {
    let mut best = 0;
    let mut best_score = f64::NEG_INFINITY;
    for i in 0..count {
        let s = score(i);
        if s > best_score {
            best_score = s;
            best = i;
        }
    }
    (best, best_score)
}

/// Default absolute tolerance for geometric predicates in metres-scale scenes.
pub const EPS: f64 = 1e-12;

/// `true` when `a` and `b` differ by at most `tol` absolutely or relatively
/// (whichever is looser), so that the test works at any scale.
pub fn approx_eq(a: f64, b: f64, tol: f64) -> bool {
    let diff = (a - b).abs();
    diff <= tol || diff <= tol * a.abs().max(b.abs())
}

/// Component-wise [`approx_eq`] for vectors.
pub fn approx_eq_vec(a: DVec3, b: DVec3, tol: f64) -> bool {
    approx_eq(a.x, b.x, tol) && approx_eq(a.y, b.y, tol) && approx_eq(a.z, b.z, tol)
}

/// Largest absolute entry of `a - b`.
pub fn max_abs_diff_mat(a: &DMat3, b: &DMat3) -> f64 {
    let d = *a - *b;
    d.to_cols_array().iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// `true` when every component of the vector is finite.
pub fn is_finite_vec(v: DVec3) -> bool {
    v.is_finite()
}

/// The skew-symmetric cross-product matrix: `skew(a) * b == a.cross(b)`.
pub fn skew(a: DVec3) -> DMat3 {
    DMat3::from_cols(
        DVec3::new(0.0, a.z, -a.y),
        DVec3::new(-a.z, 0.0, a.x),
        DVec3::new(a.y, -a.x, 0.0),
    )
}

/// Time derivative of an orientation quaternion under world-frame angular
/// velocity `omega`: `dq/dt = 1/2 [0, omega] q` (thesis eq. 3.12). The result
/// is not a unit quaternion; integrators renormalise after adding it.
pub fn quat_derivative(omega: DVec3, q: DQuat) -> DQuat {
    let w = DQuat::from_xyzw(omega.x, omega.y, omega.z, 0.0);
    let p = w * q;
    DQuat::from_xyzw(0.5 * p.x, 0.5 * p.y, 0.5 * p.z, 0.5 * p.w)
}

/// Symmetric part `(m + m^T) / 2`: removes round-off asymmetry.
pub fn symmetrize(m: &DMat3) -> DMat3 {
    let t = m.transpose();
    DMat3::from_cols(
        (m.x_axis + t.x_axis) * 0.5,
        (m.y_axis + t.y_axis) * 0.5,
        (m.z_axis + t.z_axis) * 0.5,
    )
}

/// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations.
///
/// Returns `(values, vectors)` with `m = V diag(values) V^T`, the eigenvalues in
/// ascending order and the eigenvectors as the orthonormal, right-handed
/// columns of `V` (`det V = +1`, so `V` is a rotation). Only the symmetric part
/// of `m` is used.
///
/// Why Jacobi: for 3x3 it is short, unconditionally convergent and accurate to
/// working precision even for clustered eigenvalues (an analytic cubic solve
/// loses digits when two moments of inertia nearly coincide, which is the
/// common case for symmetric bodies).
#[allow(clippy::needless_range_loop)] // index form mirrors the textbook algorithm
pub fn sym_eigen(m: &DMat3) -> (DVec3, DMat3) {
    let s = symmetrize(m);
    // a[row][col]
    let mut a = [[0.0f64; 3]; 3];
    for (c, col) in [s.x_axis, s.y_axis, s.z_axis].iter().enumerate() {
        a[0][c] = col.x;
        a[1][c] = col.y;
        a[2][c] = col.z;
    }
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let scale = a
        .iter()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()))
        .max(f64::MIN_POSITIVE);
    for _sweep in 0..64 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off <= scale * 1e-17 {
            break;
        }
        for (p, q) in [(0usize, 1usize), (0, 2), (1, 2)] {
            if a[p][q].abs() <= scale * 1e-300 {
                continue;
            }
            // Rotation angle that zeroes a[p][q] (Golub & Van Loan, Alg. 8.5.1),
            // choosing the smaller root for stability.
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let sn = t * c;
            // A' = J^T A J with J the rotation in the (p, q) plane.
            for k in 0..3 {
                let akp = a[k][p];
                let akq = a[k][q];
                a[k][p] = c * akp - sn * akq;
                a[k][q] = sn * akp + c * akq;
            }
            for k in 0..3 {
                let apk = a[p][k];
                let aqk = a[q][k];
                a[p][k] = c * apk - sn * aqk;
                a[q][k] = sn * apk + c * aqk;
            }
            for row in v.iter_mut() {
                let vkp = row[p];
                let vkq = row[q];
                row[p] = c * vkp - sn * vkq;
                row[q] = sn * vkp + c * vkq;
            }
        }
    }
    let mut idx = [0usize, 1, 2];
    idx.sort_by(|&i, &j| a[i][i].total_cmp(&a[j][j]));
    let col = |i: usize| DVec3::new(v[0][i], v[1][i], v[2][i]).normalize();
    let values = DVec3::new(a[idx[0]][idx[0]], a[idx[1]][idx[1]], a[idx[2]][idx[2]]);
    let c0 = col(idx[0]);
    let c1 = col(idx[1]);
    // Right-handed by construction; also re-orthogonalises against round-off.
    let c1 = (c1 - c0 * c0.dot(c1)).normalize();
    let c2 = c0.cross(c1);
    (values, DMat3::from_cols(c0, c1, c2))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn reconstruct(values: DVec3, vectors: DMat3) -> DMat3 {
        vectors * DMat3::from_diagonal(values) * vectors.transpose()
    }

    #[test]
    fn eigen_of_diagonal_is_sorted_identity_permutation() {
        let m = DMat3::from_diagonal(DVec3::new(3.0, 1.0, 2.0));
        let (vals, vecs) = sym_eigen(&m);
        assert_eq!(vals, DVec3::new(1.0, 2.0, 3.0));
        assert!((vecs.determinant() - 1.0).abs() < 1e-14);
        assert!(max_abs_diff_mat(&reconstruct(vals, vecs), &m) < 1e-14);
    }

    #[test]
    fn eigen_handles_repeated_eigenvalues() {
        let r = DMat3::from_quat(DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 0.7));
        let m = r * DMat3::from_diagonal(DVec3::new(2.0, 2.0, 5.0)) * r.transpose();
        let (vals, vecs) = sym_eigen(&m);
        assert!(approx_eq_vec(vals, DVec3::new(2.0, 2.0, 5.0), 1e-13));
        assert!(max_abs_diff_mat(&reconstruct(vals, vecs), &m) < 1e-13);
    }

    #[test]
    fn skew_is_cross_product() {
        let a = DVec3::new(1.0, -2.0, 3.5);
        let b = DVec3::new(-0.5, 4.0, 2.0);
        assert!(approx_eq_vec(skew(a) * b, a.cross(b), 1e-15));
    }

    #[test]
    fn quat_derivative_matches_finite_difference_of_rotation() {
        // q(t) = exp(omega t / 2) q0 for constant world-frame omega.
        let omega = DVec3::new(0.3, -1.2, 2.0);
        let q0 = DQuat::from_euler(glam::EulerRot::ZYX, 0.4, 0.2, -0.9);
        let h = 1e-6;
        let q = |t: f64| DQuat::from_scaled_axis(omega * t) * q0;
        let fd = (q(h) - q(-h)) * (1.0 / (2.0 * h));
        let d = quat_derivative(omega, q0);
        assert!((fd - d).length() < 1e-9);
    }

    fn arb_f() -> impl Strategy<Value = f64> {
        -100.0f64..100.0
    }

    proptest! {
        #[test]
        fn eigen_reconstructs_random_symmetric(a in arb_f(), b in arb_f(), c in arb_f(),
                                              d in arb_f(), e in arb_f(), f in arb_f()) {
            let m = DMat3::from_cols(DVec3::new(a, d, e), DVec3::new(d, b, f), DVec3::new(e, f, c));
            let (vals, vecs) = sym_eigen(&m);
            let scale = m.to_cols_array().iter().fold(1.0f64, |s, x| s.max(x.abs()));
            prop_assert!(max_abs_diff_mat(&reconstruct(vals, vecs), &m) < 1e-12 * scale);
            prop_assert!(max_abs_diff_mat(&(vecs.transpose() * vecs), &DMat3::IDENTITY) < 1e-12);
            prop_assert!((vecs.determinant() - 1.0).abs() < 1e-12);
            prop_assert!(vals.x <= vals.y && vals.y <= vals.z);
        }

        #[test]
        fn skew_antisymmetric_and_cross(ax in arb_f(), ay in arb_f(), az in arb_f(),
                                        bx in arb_f(), by in arb_f(), bz in arb_f()) {
            let a = DVec3::new(ax, ay, az);
            let b = DVec3::new(bx, by, bz);
            let s = skew(a);
            prop_assert!(max_abs_diff_mat(&s, &(-s.transpose())) == 0.0);
            prop_assert!(approx_eq_vec(s * b, a.cross(b), 1e-12));
        }

        #[test]
        fn quat_derivative_keeps_unit_norm_to_first_order(ox in arb_f(), oy in arb_f(), oz in arb_f(),
                                                          r1 in -3.0f64..3.0, r2 in -3.0f64..3.0) {
            // d/dt |q|^2 = 2 q . dq/dt = 0 for a unit quaternion.
            let q = DQuat::from_euler(glam::EulerRot::XYZ, r1, r2, r1 * r2);
            let d = quat_derivative(DVec3::new(ox, oy, oz), q);
            prop_assert!(q.dot(d).abs() < 1e-12 * (1.0 + DVec3::new(ox, oy, oz).length()));
        }

        #[test]
        fn approx_eq_is_symmetric(a in arb_f(), b in arb_f()) {
            prop_assert_eq!(approx_eq(a, b, 1e-9), approx_eq(b, a, 1e-9));
        }
    }
}
