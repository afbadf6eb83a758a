//! The linear complementarity problem (LCP) shared by all contact solvers:
//! find `z` with `w = A z + q`, `w >= 0`, `z >= 0`, `z . w = 0`
//! (thesis 7.2 eq. 7.1 with `f = z`, `a = w`, `b = q`; Baraff 1994;
//! Cottle, Pang & Stone, "The Linear Complementarity Problem", 1992, ch. 1).
//!
//! This file holds the types every solver returns ([`LcpSolution`],
//! [`LcpError`]), the input validation they share, and the independent
//! checker [`check`] that tests and callers use to verify any answer.

use super::dense::{dot, DenseMatrix};

/// What a solver returns: the unknowns `z`, the slacks `w = A z + q`, and how
/// the solve went.
#[derive(Debug, Clone, PartialEq)]
pub struct LcpSolution {
    /// The unknowns (for contacts: impulses, N s, or forces, N).
    pub z: Vec<f64>,
    /// `w = A z + q`, recomputed from the original data (for contacts: the
    /// relative velocities after the impulses, m/s, or accelerations).
    pub w: Vec<f64>,
    /// Pivots (Lemke) or sweeps (projected Gauss-Seidel) performed.
    pub iterations: usize,
    /// Natural-map residual `max_i |z_i - proj_i(z_i - w_i)|` (`proj` onto the
    /// row's bounds; `[0, inf)` for a plain LCP). Zero exactly at a solution.
    /// It compares `z` and `w` directly, so it is in mixed units and scales
    /// with the problem: choose tolerances accordingly.
    pub residual: f64,
    /// Whether the solver met its stopping criterion (always `true` for Lemke;
    /// `false` when projected Gauss-Seidel ran out of sweeps).
    pub converged: bool,
}

/// Why an LCP could not be solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LcpError {
    /// An input entry is NaN or infinite.
    #[error("{what}: entry {index} is not finite ({value})")]
    NonFinite {
        /// Which input (`"A"`, `"q"`, `"warm start"`, ...).
        what: &'static str,
        /// Flat index of the entry (row-major for matrices).
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// Inputs of incompatible sizes.
    #[error("{what}: expected {expected} entries, found {found}")]
    SizeMismatch {
        /// Which input.
        what: &'static str,
        /// Entries required by the matrix size.
        expected: usize,
        /// Entries given.
        found: usize,
    },
    /// Lemke's algorithm left along an unbounded ray. For a copositive-plus
    /// matrix (every PSD contact matrix is one) this proves the LCP has no
    /// solution (Cottle, Pang & Stone, Theorem 4.4.13).
    #[error("Lemke ray termination after {pivots} pivots (entering column {entering}): no solution found")]
    RayTermination {
        /// Pivots done before the ray was found.
        pivots: usize,
        /// Tableau column that could not be blocked.
        entering: usize,
    },
    /// Lemke's algorithm did not finish within its pivot budget.
    #[error("Lemke stopped at its pivot limit of {limit}")]
    PivotLimit {
        /// The budget that was exhausted.
        limit: usize,
    },
    /// Projected Gauss-Seidel needs `A_ii > 0` to update row `row`.
    #[error("row {row}: diagonal A_ii = {value} must be > 0 for Gauss-Seidel")]
    NonPositiveDiagonal {
        /// The row.
        row: usize,
        /// Its diagonal entry.
        value: f64,
    },
    /// A solver parameter or row bound is out of range.
    #[error("{what}: {value} is invalid, expected {expected}")]
    BadParameter {
        /// Which parameter (and row, if any).
        what: String,
        /// The value given.
        value: f64,
        /// What was expected.
        expected: &'static str,
    },
}

/// How far a candidate `z` is from solving the LCP (all three are zero at an
/// exact solution).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Residuals {
    /// `min_i w_i` with `w = A z + q` (negative: a constraint is violated).
    pub min_w: f64,
    /// `min_i z_i` (negative: a pulling, "glue" impulse).
    pub min_z: f64,
    /// Complementarity `max_i |z_i w_i|` (non-zero: a row both pushes and separates).
    pub comp: f64,
}

impl Residuals {
    /// `true` when `min_w >= -tol`, `min_z >= -tol` and `comp <= tol`.
    pub fn within(&self, tol: f64) -> bool {
        self.min_w >= -tol && self.min_z >= -tol && self.comp <= tol
    }
}

/// Measures how well `z` solves `w = A z + q, w >= 0, z >= 0, z . w = 0`.
///
/// Independent of every solver: it only multiplies. For an empty problem all
/// residuals are zero.
pub fn check(a: &DenseMatrix, q: &[f64], z: &[f64]) -> Result<Residuals, LcpError> {
    validate(a, q)?;
    validate_vec("z", z, a.n())?;
    let w = a.mul_vec(z)?;
    let mut r = Residuals {
        min_w: 0.0,
        min_z: 0.0,
        comp: 0.0,
    };
    for i in 0..a.n() {
        let wi = w[i] + q[i];
        r.min_w = r.min_w.min(wi);
        r.min_z = r.min_z.min(z[i]);
        r.comp = r.comp.max((z[i] * wi).abs());
    }
    Ok(r)
}

/// Checks that `A` is finite and `q` is finite with `n` entries.
pub(crate) fn validate(a: &DenseMatrix, q: &[f64]) -> Result<(), LcpError> {
    if let Some((i, j)) = a.first_non_finite() {
        return Err(LcpError::NonFinite {
            what: "A",
            index: i * a.n() + j,
            value: a.get(i, j),
        });
    }
    validate_vec("q", q, a.n())
}

/// Checks that `v` is finite with `n` entries.
pub(crate) fn validate_vec(what: &'static str, v: &[f64], n: usize) -> Result<(), LcpError> {
    if v.len() != n {
        return Err(LcpError::SizeMismatch {
            what,
            expected: n,
            found: v.len(),
        });
    }
    if let Some(index) = v.iter().position(|x| !x.is_finite()) {
        return Err(LcpError::NonFinite {
            what,
            index,
            value: v[index],
        });
    }
    Ok(())
}

/// `w = A z + q` recomputed from the original data.
pub(crate) fn slacks(a: &DenseMatrix, q: &[f64], z: &[f64]) -> Vec<f64> {
    (0..a.n()).map(|i| dot(a.row(i), z) + q[i]).collect()
}

/// Natural-map residual of the plain LCP: `max_i |min(z_i, w_i)|`.
pub(crate) fn natural_residual(z: &[f64], w: &[f64]) -> f64 {
    z.iter()
        .zip(w)
        .fold(0.0f64, |m, (zi, wi)| m.max(zi.min(*wi).abs()))
}
