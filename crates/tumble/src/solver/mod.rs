//! Contact constraint solvers (thesis 7.1-7.2 "Resting Contact", which the thesis
//! left as further work; design map: `solve` stage).
//!
//! - [`contact_solver`]: the sub-stepped sequential-impulse solver with
//!   split-impulse push-out that the world runs every step;
//! - [`dense`]: the small row-major matrix the solvers share;
//! - [`lcp`]: the problem statement, solution and error types, and an
//!   independent residual checker;
//! - [`lemke`]: exact pivoting solver (reference, small islands);
//! - [`pgs`]: projected Gauss-Seidel, plain and boxed with friction pyramids
//!   (the default, warm-startable);
//! - [`delassus`]: assembly of `A = J M^-1 J^T` and `b = J u` from bodies and
//!   contact points;
//! - [`friction_cone`]: the exact reference with friction, the contact LCP
//!   with a polyhedral friction cone (Stewart-Trinkle, Anitescu-Potra) by
//!   Lemke's method.
//!
//! A ball of 2 kg falling at 1 m/s onto static ground, one contact, no
//! restitution: the impulse stops it (`j = m v`, thesis 7.1).
//!
//! ```
//! use tumble::collide::math::{DMat3, DVec3};
//! use tumble::solver::{build_contact_lcp, lemke, pgs, BodyState, ContactRow};
//!
//! let ground = BodyState::fixed();
//! let ball = BodyState {
//!     inv_mass: 0.5,
//!     inv_inertia: DMat3::from_diagonal(DVec3::splat(1.0 / 0.08)),
//!     linear_velocity: DVec3::new(0.0, 0.0, -1.0),
//!     angular_velocity: DVec3::ZERO,
//! };
//! let contact = ContactRow {
//!     body_a: 1,
//!     body_b: 0,
//!     r_a: DVec3::new(0.0, 0.0, -0.2),
//!     r_b: DVec3::ZERO,
//!     normal: DVec3::Z,
//!     bias: 0.0,
//!     friction: 0.5,
//! };
//! let lcp = build_contact_lcp(&[ground, ball], &[contact], false)?;
//! let exact = lemke(&lcp.a, &lcp.b)?;
//! let iterative = pgs(&lcp.a, &lcp.b, 50, 1e-12, None)?;
//! assert!((exact.z[0] - 2.0).abs() < 1e-12);
//! assert!((iterative.z[0] - 2.0).abs() < 1e-12);
//! let after = lcp.velocities_after(&[ground, ball], &exact.z)?;
//! assert!(after[1].linear.length() < 1e-12);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod contact_solver;
pub mod delassus;
pub mod dense;
pub mod friction_cone;
pub mod lcp;
pub mod lemke;
pub mod pgs;

pub use delassus::{
    build_contact_lcp, tangent_basis, BodyState, BodyVelocity, ContactLcp, ContactLcpError, ContactRow,
    JacobianRow,
};
pub use dense::DenseMatrix;
pub use friction_cone::{cone_directions, solve_friction_cone, FrictionConeError, FrictionConeSolution};
pub use lcp::{check, LcpError, LcpSolution, Residuals};
pub use lemke::{lemke, lemke_with, LemkeOptions};
pub use pgs::{pgs, pgs_boxed, RowLimit};

/// `x` limited to `[lo, hi]` without `f64::clamp`'s panic on a NaN or
/// crossed bound (a bound computed from a non-finite impulse reaches here
/// only as part of a body the step quarantines; it must not abort the step
/// first): a NaN bound limits nothing, crossed bounds give `hi`.
#[inline(always)]
pub(crate) fn clamp_impulse(x: f64, lo: f64, hi: f64) -> f64 {
    x.max(lo).min(hi)
}
