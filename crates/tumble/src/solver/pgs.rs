//! Projected Gauss-Seidel (PGS) for the LCP and its boxed form
//! `lo_i <= z_i <= hi_i`, `w_i >= 0` where `z_i = lo_i`, `w_i <= 0` where
//! `z_i = hi_i`, `w_i = 0` in between (a mixed LCP; Cottle, Pang & Stone
//! section 5.2 "projected SOR"; Erleben 2007 "Velocity-based shock
//! propagation" and Catto 2005 "Iterative dynamics with temporal coherence"
//! for its use as the sequential-impulse contact solver).
//!
//! One sweep visits the rows in order and solves each for its own unknown with
//! the others frozen, then projects onto the row's bounds:
//! `z_i <- clamp(z_i - w_i / A_ii, lo_i, hi_i)`, `w_i = (A z + q)_i`.
//! For a symmetric positive definite `A` the sweeps converge to the unique
//! solution (CPS section 5.2: the iteration minimises `1/2 z.A z + q.z`
//! over the box one coordinate at a time); for PSD contact matrices `A z`,
//! and hence the post-solve velocities, still converge.
//!
//! Friction rows ([`RowLimit::Friction`]) have bounds `+-mu z_n` that move
//! with the current normal impulse of their contact: the friction pyramid,
//! re-read every time the row is visited, as sequential impulses do.

use super::dense::{dot, DenseMatrix};
use super::lcp::{validate, validate_vec, LcpError, LcpSolution};

/// Bounds on one unknown of a boxed LCP.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RowLimit {
    /// Fixed bounds `lo <= z_i <= hi` (may be infinite; `lo <= hi`).
    /// A non-penetration row is `Box { lo: 0.0, hi: f64::INFINITY }`.
    Box {
        /// Lower bound (impulse units, e.g. N s).
        lo: f64,
        /// Upper bound.
        hi: f64,
    },
    /// A friction row: `-mu z_n <= z_i <= mu z_n` where `z_n` is the current
    /// value of row `normal_row` (Coulomb's law, one side of the pyramid).
    Friction {
        /// The normal row of the same contact.
        normal_row: usize,
        /// Friction coefficient (dimensionless, >= 0).
        mu: f64,
    },
}

impl RowLimit {
    /// The plain LCP bound `0 <= z_i`.
    pub const NON_NEGATIVE: RowLimit = RowLimit::Box {
        lo: 0.0,
        hi: f64::INFINITY,
    };

    /// Current `(lo, hi)` given the current unknowns.
    fn bounds(&self, z: &[f64]) -> (f64, f64) {
        match *self {
            RowLimit::Box { lo, hi } => (lo, hi),
            RowLimit::Friction { normal_row, mu } => {
                let h = mu * z[normal_row].max(0.0);
                (-h, h)
            }
        }
    }
}

/// Projected Gauss-Seidel on the plain LCP `w = A z + q >= 0, z >= 0, z.w = 0`.
///
/// Runs at most `max_iterations` sweeps and stops after the first sweep whose
/// natural-map residual (see [`LcpSolution::residual`]) is `<= tolerance`.
/// `warm_start` (e.g. last step's impulses) is projected onto `z >= 0` and
/// used as the initial guess; `None` starts from zero. Not converging is not
/// an error: check [`LcpSolution::converged`].
///
/// Errors: size mismatch, non-finite input, `A_ii <= 0`, bad tolerance.
pub fn pgs(
    a: &DenseMatrix,
    q: &[f64],
    max_iterations: usize,
    tolerance: f64,
    warm_start: Option<&[f64]>,
) -> Result<LcpSolution, LcpError> {
    let limits = vec![RowLimit::NON_NEGATIVE; a.n()];
    pgs_boxed(a, q, &limits, max_iterations, tolerance, warm_start)
}

/// Projected Gauss-Seidel on the boxed LCP with per-row [`RowLimit`]s,
/// including friction rows whose bounds follow their normal row.
///
/// Same stopping rule and warm start as [`pgs`]; the residual is
/// `max_i |z_i - clamp(z_i - w_i, lo_i, hi_i)|` with the bounds at the final
/// `z`. Errors additionally on a limit list of the wrong length, `lo > hi`,
/// NaN bounds, a negative or non-finite `mu`, or a friction row pointing at
/// itself or out of range.
pub fn pgs_boxed(
    a: &DenseMatrix,
    q: &[f64],
    limits: &[RowLimit],
    max_iterations: usize,
    tolerance: f64,
    warm_start: Option<&[f64]>,
) -> Result<LcpSolution, LcpError> {
    validate(a, q)?;
    let n = a.n();
    validate_limits(limits, n)?;
    if !(tolerance.is_finite() && tolerance >= 0.0) {
        return Err(LcpError::BadParameter {
            what: "tolerance".into(),
            value: tolerance,
            expected: "finite and >= 0",
        });
    }
    let mut inv_diag = Vec::with_capacity(n);
    for i in 0..n {
        let d = a.get(i, i);
        if d <= 0.0 {
            return Err(LcpError::NonPositiveDiagonal { row: i, value: d });
        }
        inv_diag.push(1.0 / d);
    }
    let mut z = match warm_start {
        Some(z0) => {
            validate_vec("warm start", z0, n)?;
            z0.to_vec()
        }
        None => vec![0.0; n],
    };
    // Project the guess: normal rows first so friction bounds see valid normals.
    for i in 0..n {
        if let RowLimit::Box { lo, hi } = limits[i] {
            z[i] = super::clamp_impulse(z[i], lo, hi);
        }
    }
    for i in 0..n {
        let (lo, hi) = limits[i].bounds(&z);
        z[i] = super::clamp_impulse(z[i], lo, hi);
    }

    let mut w = vec![0.0; n];
    let mut residual = boxed_residual(a, q, limits, &z, &mut w);
    let mut iterations = 0;
    while residual > tolerance && iterations < max_iterations {
        // Each row's residual at the moment it is visited costs nothing
        // extra; only when all of them pass is the exact residual (another
        // O(n^2) product) computed, so most sweeps cost one product, not two.
        let mut visit_residual = 0.0f64;
        for i in 0..n {
            let wi = dot(a.row(i), &z) + q[i];
            let (lo, hi) = limits[i].bounds(&z);
            visit_residual = visit_residual.max((z[i] - super::clamp_impulse(z[i] - wi, lo, hi)).abs());
            z[i] = super::clamp_impulse(z[i] - wi * inv_diag[i], lo, hi);
        }
        iterations += 1;
        if visit_residual <= tolerance || iterations == max_iterations {
            residual = boxed_residual(a, q, limits, &z, &mut w);
        }
    }
    Ok(LcpSolution {
        z,
        w,
        iterations,
        residual,
        converged: residual <= tolerance,
    })
}

/// Fills `w = A z + q` and returns `max_i |z_i - clamp(z_i - w_i, lo_i, hi_i)|`.
fn boxed_residual(a: &DenseMatrix, q: &[f64], limits: &[RowLimit], z: &[f64], w: &mut [f64]) -> f64 {
    let mut r = 0.0f64;
    for i in 0..a.n() {
        w[i] = dot(a.row(i), z) + q[i];
        let (lo, hi) = limits[i].bounds(z);
        r = r.max((z[i] - super::clamp_impulse(z[i] - w[i], lo, hi)).abs());
    }
    r
}

fn validate_limits(limits: &[RowLimit], n: usize) -> Result<(), LcpError> {
    if limits.len() != n {
        return Err(LcpError::SizeMismatch {
            what: "row limits",
            expected: n,
            found: limits.len(),
        });
    }
    for (i, l) in limits.iter().enumerate() {
        match *l {
            RowLimit::Box { lo, hi } => {
                if lo.is_nan() || hi.is_nan() || lo > hi || lo == f64::INFINITY || hi == f64::NEG_INFINITY {
                    return Err(LcpError::BadParameter {
                        what: format!("row {i} bounds [{lo}, {hi}]"),
                        value: lo,
                        expected: "lo <= hi, neither NaN, lo < +inf, hi > -inf",
                    });
                }
            }
            RowLimit::Friction { normal_row, mu } => {
                if !(mu.is_finite() && mu >= 0.0) {
                    return Err(LcpError::BadParameter {
                        what: format!("row {i} friction coefficient"),
                        value: mu,
                        expected: "finite and >= 0",
                    });
                }
                if normal_row >= n || normal_row == i {
                    return Err(LcpError::BadParameter {
                        what: format!("row {i} normal_row"),
                        value: normal_row as f64,
                        expected: "another row index < n",
                    });
                }
            }
        }
    }
    Ok(())
}
