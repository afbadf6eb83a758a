//! A small square, row-major dense matrix: the storage the LCP solvers work on.
//!
//! Contact LCPs in tumble are at most a few hundred rows per island, so a plain
//! `Vec<f64>` with `n * n` entries is the simplest layout that keeps each row
//! contiguous (Gauss-Seidel sweeps and Lemke's pivots both walk rows).

use super::lcp::LcpError;

/// Square `n x n` matrix of `f64`, stored row by row: entry `(i, j)` is
/// `data[i * n + j]`.
#[derive(Debug, Clone, PartialEq)]
pub struct DenseMatrix {
    n: usize,
    data: Vec<f64>,
}

impl DenseMatrix {
    /// The `n x n` zero matrix.
    pub fn zeros(n: usize) -> DenseMatrix {
        DenseMatrix {
            n,
            data: vec![0.0; n * n],
        }
    }

    /// The `n x n` identity matrix.
    pub fn identity(n: usize) -> DenseMatrix {
        let mut m = DenseMatrix::zeros(n);
        for i in 0..n {
            m.set(i, i, 1.0);
        }
        m
    }

    /// Wraps `data` (row-major, `n * n` entries) as a matrix.
    ///
    /// Errors with [`LcpError::SizeMismatch`] when `data.len() != n * n`.
    /// Entries are not checked for finiteness here; the solvers do that.
    pub fn from_row_major(n: usize, data: Vec<f64>) -> Result<DenseMatrix, LcpError> {
        let expected = n.checked_mul(n).ok_or(LcpError::SizeMismatch {
            what: "matrix data",
            expected: usize::MAX,
            found: data.len(),
        })?;
        if data.len() != expected {
            return Err(LcpError::SizeMismatch {
                what: "matrix data",
                expected,
                found: data.len(),
            });
        }
        Ok(DenseMatrix { n, data })
    }

    /// Builds a matrix from a list of rows; all rows must have `rows.len()` entries.
    pub fn from_rows(rows: &[Vec<f64>]) -> Result<DenseMatrix, LcpError> {
        let n = rows.len();
        let mut data = Vec::with_capacity(n * n);
        for row in rows {
            if row.len() != n {
                return Err(LcpError::SizeMismatch {
                    what: "matrix row",
                    expected: n,
                    found: row.len(),
                });
            }
            data.extend_from_slice(row);
        }
        Ok(DenseMatrix { n, data })
    }

    /// Number of rows (= number of columns).
    pub fn n(&self) -> usize {
        self.n
    }

    /// Entry `(i, j)`. Panics if out of range (a programming error, not user input).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.data[i * self.n + j]
    }

    /// Sets entry `(i, j)`.
    pub fn set(&mut self, i: usize, j: usize, value: f64) {
        self.data[i * self.n + j] = value;
    }

    /// Row `i` as a slice of `n` entries.
    pub fn row(&self, i: usize) -> &[f64] {
        &self.data[i * self.n..(i + 1) * self.n]
    }

    /// All entries, row-major.
    pub fn as_slice(&self) -> &[f64] {
        &self.data
    }

    /// `true` when every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.data.iter().all(|x| x.is_finite())
    }

    /// Index of the first non-finite entry as `(row, col)`, if any.
    pub fn first_non_finite(&self) -> Option<(usize, usize)> {
        self.data
            .iter()
            .position(|x| !x.is_finite())
            .map(|k| (k / self.n, k % self.n))
    }

    /// `A x`. `x` must have `n` entries (checked).
    pub fn mul_vec(&self, x: &[f64]) -> Result<Vec<f64>, LcpError> {
        if x.len() != self.n {
            return Err(LcpError::SizeMismatch {
                what: "vector",
                expected: self.n,
                found: x.len(),
            });
        }
        Ok((0..self.n).map(|i| dot(self.row(i), x)).collect())
    }

    /// Adds `value` to every diagonal entry: `A <- A + value I`.
    ///
    /// On a contact matrix this is constraint compliance ("constraint force
    /// mixing", units of `A`, e.g. m/s per N s): contacts may yield by
    /// `value * z`. Any `value > 0` turns a PSD `J M^-1 J^T` into a positive
    /// definite matrix, whose LCP has exactly one solution for every `q`;
    /// that is the cure when bodies are wedged (more contacts than degrees of
    /// freedom) and round-off makes the exact problem infeasible.
    /// Errors with [`LcpError::BadParameter`] if `value` is not finite.
    pub fn add_diagonal(&mut self, value: f64) -> Result<(), LcpError> {
        if !value.is_finite() {
            return Err(LcpError::BadParameter {
                what: "diagonal shift".into(),
                value,
                expected: "finite",
            });
        }
        for i in 0..self.n {
            self.data[i * self.n + i] += value;
        }
        Ok(())
    }

    /// The transpose.
    pub fn transpose(&self) -> DenseMatrix {
        let mut t = DenseMatrix::zeros(self.n);
        for i in 0..self.n {
            for j in 0..self.n {
                t.set(j, i, self.get(i, j));
            }
        }
        t
    }
}

/// Dot product of two equally long slices.
///
/// Four interleaved partial sums break the floating-point add dependency
/// chain (about 3x faster on long rows); the summation order is fixed, so the
/// result is still bit-reproducible run to run.
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    let tail: f64 = ra.iter().zip(rb).map(|(x, y)| x * y).sum();
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}
