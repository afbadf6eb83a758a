//! Contact constraint solvers (thesis 7.2 "Resting Contact", which the thesis
//! left as further work; design map: `solve` stage).
//!
//! - [`dense`]: the small row-major matrix the solvers share;
//! - [`lcp`]: the problem statement, solution and error types, and an
//!   independent residual checker;
//! - [`lemke`]: exact pivoting solver (reference, small islands);
//! - [`pgs`]: projected Gauss-Seidel, plain and boxed with friction pyramids
//!   (the default, warm-startable);
//! - [`delassus`]: assembly of `A = J M^-1 J^T` and `b = J u` from bodies and
//!   contact points.

pub mod delassus;
pub mod dense;
pub mod lcp;
pub mod lemke;
pub mod pgs;

pub use delassus::{
    build_contact_lcp, tangent_basis, BodyState, BodyVelocity, ContactLcp, ContactLcpError, ContactRow,
    JacobianRow,
};
pub use dense::DenseMatrix;
pub use lcp::{check, LcpError, LcpSolution, Residuals};
pub use lemke::{lemke, lemke_with, LemkeOptions};
pub use pgs::{pgs, pgs_boxed, RowLimit};
