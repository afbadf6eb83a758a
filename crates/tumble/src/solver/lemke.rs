//! Lemke's complementary pivoting algorithm for the dense LCP
//! `w = A z + q, w >= 0, z >= 0, z . w = 0`
//! (Cottle, Pang & Stone, "The Linear Complementarity Problem", sections 4.4
//! and 4.9; Baraff 1994 motivates pivoting for contact).
//!
//! The problem is augmented with an artificial variable `z0` and the
//! covering vector `e = (1, ..., 1)`:  `w - A z - e z0 = q`. Starting from
//! the basis `{w}`, `z0` enters just far enough to make every `w_i >= 0`,
//! then the algorithm keeps a complementary basis (never both `z_i` and `w_i`
//! basic) and always brings in the complement of the variable that just left,
//! until `z0` leaves (a solution) or no row blocks the entering column (a
//! ray).
//!
//! Anti-cycling: the lexicographic minimum ratio rule (CPS 4.9). Rows of
//! `[B^-1 q | B^-1]` are kept lexicographically positive; the leaving row is
//! the lexicographic minimum of `[B^-1 q | B^-1]_i / (B^-1 d)_i` over rows
//! with a positive pivot. Since `B^-1` is nonsingular no two rows tie in full,
//! so the choice is unique and no basis repeats: the algorithm terminates.
//! This matters for contact: a box on four symmetric contacts gives exactly
//! equal `q_i`, which is the degenerate case where plain Lemke can cycle.
//!
//! Termination guarantees (CPS 4.4.12-4.4.13): for a P-matrix Lemke always
//! finds the unique solution; for a copositive-plus matrix (every symmetric
//! PSD matrix, so every frictionless contact matrix `J M^-1 J^T`) a ray
//! proves the LCP infeasible. The thesis (7.2) calls the contact LCP
//! NP-hard; that holds for general matrices, not for these.

use super::dense::DenseMatrix;
use super::lcp::{natural_residual, slacks, validate, LcpError, LcpSolution};

/// Settings for [`lemke_with`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LemkeOptions {
    /// Maximum number of pivots before [`LcpError::PivotLimit`]. `None`
    /// (default) uses `100 + 20 n`, far above the `O(n)` pivots contact
    /// problems take, while still bounding pathological inputs.
    pub max_pivots: Option<usize>,
    /// A tableau entry is an admissible pivot only if it exceeds this fraction
    /// of the largest entry in its column (dimensionless, default `1e-12`).
    /// Raising it skips ill-conditioned pivots at the risk of reporting a ray.
    pub pivot_tolerance: f64,
}

impl Default for LemkeOptions {
    fn default() -> Self {
        LemkeOptions {
            max_pivots: None,
            pivot_tolerance: 1e-12,
        }
    }
}

/// Solves the LCP `(A, q)` by Lemke's method with default [`LemkeOptions`].
///
/// Returns `z`, `w = A z + q` (recomputed from the inputs) and the pivot
/// count in [`LcpSolution::iterations`]. Errors: non-finite `A` or `q`,
/// `q.len() != n`, ray termination (no solution for PSD / copositive-plus
/// `A`), pivot limit.
pub fn lemke(a: &DenseMatrix, q: &[f64]) -> Result<LcpSolution, LcpError> {
    lemke_with(a, q, &LemkeOptions::default())
}

/// [`lemke`] with explicit options.
pub fn lemke_with(a: &DenseMatrix, q: &[f64], options: &LemkeOptions) -> Result<LcpSolution, LcpError> {
    validate(a, q)?;
    let tol = options.pivot_tolerance;
    if !(tol.is_finite() && (0.0..1.0).contains(&tol)) {
        return Err(LcpError::BadParameter {
            what: "pivot_tolerance".into(),
            value: tol,
            expected: "finite, in [0, 1)",
        });
    }
    let n = a.n();
    let limit = options.max_pivots.unwrap_or(100 + 20 * n);

    // z = 0 already solves it when q >= 0 (the usual case of separating contacts).
    if q.iter().all(|&qi| qi >= 0.0) {
        return Ok(finish(a, q, vec![0.0; n], 0));
    }

    let mut t = Tableau::new(a, q);
    let z0 = 2 * n;

    // First pivot: z0 enters at the most negative q_r. Among exact ties the
    // largest index keeps every row lexicographically positive (the rows
    // become (q_i - q_r, e_i - e_r), whose first non-zero is +1 iff i < r).
    let mut r = 0;
    for i in 0..n {
        if q[i] <= q[r] {
            r = i;
        }
    }
    let mut entering = z0;
    let mut pivots = 0;
    let mut row = r;
    loop {
        let leaving = t.basis[row];
        t.pivot(row, entering);
        pivots += 1;
        if leaving == z0 {
            break;
        }
        // Complementary rule: bring in the partner of the variable that left.
        entering = if leaving < n { leaving + n } else { leaving - n };
        if pivots >= limit {
            return Err(LcpError::PivotLimit { limit });
        }
        row = match t.lex_ratio_test(entering, tol) {
            Some(i) => i,
            None => return Err(LcpError::RayTermination { pivots, entering }),
        };
    }

    let mut z = vec![0.0; n];
    for (i, &b) in t.basis.iter().enumerate() {
        if (n..2 * n).contains(&b) {
            // Basic values are >= 0 in exact arithmetic; clamp round-off.
            z[b - n] = t.rhs(i).max(0.0);
        }
    }
    Ok(finish(a, q, z, pivots))
}

fn finish(a: &DenseMatrix, q: &[f64], z: Vec<f64>, pivots: usize) -> LcpSolution {
    let w = slacks(a, q, &z);
    let residual = natural_residual(&z, &w);
    LcpSolution {
        z,
        w,
        iterations: pivots,
        residual,
        converged: true,
    }
}

/// Dense tableau `B^-1 [I | -A | -e | q]`. Columns `0..n` are the `w`s (and,
/// since they start as the identity, always hold `B^-1`), `n..2n` the `z`s,
/// `2n` is `z0`, `2n + 1` the right-hand side.
struct Tableau {
    n: usize,
    width: usize,
    data: Vec<f64>,
    basis: Vec<usize>,
}

impl Tableau {
    fn new(a: &DenseMatrix, q: &[f64]) -> Tableau {
        let n = a.n();
        let width = 2 * n + 2;
        let mut data = vec![0.0; n * width];
        for i in 0..n {
            let row = &mut data[i * width..(i + 1) * width];
            row[i] = 1.0;
            for j in 0..n {
                row[n + j] = -a.get(i, j);
            }
            row[2 * n] = -1.0;
            row[2 * n + 1] = q[i];
        }
        Tableau {
            n,
            width,
            data,
            basis: (0..n).collect(),
        }
    }

    fn at(&self, i: usize, j: usize) -> f64 {
        self.data[i * self.width + j]
    }

    fn rhs(&self, i: usize) -> f64 {
        self.at(i, self.width - 1)
    }

    /// Gauss-Jordan pivot on `(r, c)`; records the entering variable `c`.
    fn pivot(&mut self, r: usize, c: usize) {
        let w = self.width;
        let p = self.at(r, c);
        let (before, rest) = self.data.split_at_mut(r * w);
        let (prow, after) = rest.split_at_mut(w);
        for x in prow.iter_mut() {
            *x /= p;
        }
        prow[c] = 1.0;
        for row in before.chunks_exact_mut(w).chain(after.chunks_exact_mut(w)) {
            let f = row[c];
            if f != 0.0 {
                for (x, y) in row.iter_mut().zip(prow.iter()) {
                    *x -= f * y;
                }
                row[c] = 0.0;
            }
        }
        self.basis[r] = c;
    }

    /// Leaving row for entering column `c` by the lexicographic minimum ratio
    /// rule; `None` if no entry of the column is an admissible pivot (a ray).
    fn lex_ratio_test(&self, c: usize, tol: f64) -> Option<usize> {
        let n = self.n;
        let col_max = (0..n).fold(0.0f64, |m, i| m.max(self.at(i, c).abs()));
        if col_max == 0.0 {
            return None;
        }
        let min_pivot = tol * col_max;
        let mut candidates: Vec<usize> = (0..n).filter(|&i| self.at(i, c) > min_pivot).collect();
        if candidates.is_empty() {
            return None;
        }
        // Key 0: the ratio rhs_i / d_i. Rows within round-off of the minimum
        // count as tied (degenerate rows have rhs that should be exactly 0).
        let ratio = |i: usize| self.rhs(i).max(0.0) / self.at(i, c);
        let theta = candidates.iter().map(|&i| ratio(i)).fold(f64::INFINITY, f64::min);
        let scale = candidates.iter().map(|&i| self.rhs(i).abs()).fold(0.0, f64::max);
        let slack = 1e-12 * (theta.abs() + scale);
        candidates.retain(|&i| ratio(i) <= theta + slack);
        // If z0 can leave now, let it: this ends the algorithm at once.
        if let Some(&i) = candidates.iter().find(|&&i| self.basis[i] == 2 * n) {
            return Some(i);
        }
        // Keys 1..=n: columns of B^-1 divided by the pivot column.
        let mut k = 0;
        while candidates.len() > 1 && k < n {
            let key = |i: usize| self.at(i, k) / self.at(i, c);
            let m = candidates.iter().map(|&i| key(i)).fold(f64::INFINITY, f64::min);
            candidates.retain(|&i| key(i) <= m);
            k += 1;
        }
        candidates.first().copied()
    }
}
