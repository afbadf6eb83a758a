//! The exact normal solve: the contact LCP of thesis 7.2 for every point of
//! a sub-step, by Lemke's method (the reference the iterative solver is
//! checked against, and a setting for small systems).

use super::body::SolverBody;
use super::constraint::{ManifoldConstraint, PointConstraint};
use crate::solver::{build_contact_lcp, lemke, BodyState, ContactLcpError, ContactRow, LcpError};

/// Why the exact normal solve failed (the caller falls back to PGS).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ExactSolveError {
    /// The contact rows could not be assembled into an LCP.
    #[error("contact LCP assembly: {0}")]
    Assembly(#[from] ContactLcpError),
    /// Lemke's method failed (ray termination, pivot limit, bad input).
    #[error("Lemke: {0}")]
    Lcp(#[from] LcpError),
}

/// Largest number of contact points solved exactly by [`solve_normals_exactly`]
/// (Lemke's method costs O(n^3)); the world falls back to PGS above it.
pub const EXACT_MAX_CONTACTS: usize = 256;

/// Solves the normal impulses of all points of the sub-step `h` exactly as
/// the LCP of thesis 7.2 (`w = A z + b >= 0, z >= 0, z.w = 0` with
/// `A = J M^-1 J^T` and `b` the relative normal velocities plus the
/// speculative allowance) by Lemke's method, and applies them. The bodies'
/// velocities must not contain any impulse of this sub-step yet (no warm
/// start). Friction is left to `solve_friction`.
pub fn solve_normals_exactly(
    manifolds: &[ManifoldConstraint],
    points: &mut [PointConstraint],
    bodies: &mut [SolverBody],
    h: f64,
) -> Result<(), ExactSolveError> {
    let states: Vec<BodyState> = bodies.iter().map(SolverBody::lcp_state).collect();
    let mut rows: Vec<ContactRow> = Vec::with_capacity(points.len());
    for m in manifolds {
        for p in &points[m.range()] {
            rows.push(ContactRow {
                body_a: m.a as usize,
                body_b: m.b as usize,
                // The lever arms of the rows the impulses are applied through.
                r_a: p.r_a,
                r_b: p.r_b,
                normal: p.normal,
                bias: if p.separation_now > 0.0 {
                    p.separation_now / h
                } else {
                    0.0
                },
                friction: m.friction,
            });
        }
    }
    let mut lcp = build_contact_lcp(&states, &rows, false)?;
    // Redundant contacts (four corners of a box face) make A only positive
    // semi-definite; a compliance far below any physical one keeps Lemke's
    // pivots away from ray termination without changing the answer visibly.
    let n = lcp.a.n().max(1);
    let mean_diagonal = (0..n).map(|i| lcp.a.get(i, i)).sum::<f64>() / n as f64;
    lcp.a.add_diagonal(1e-9 * mean_diagonal)?;
    let solution = lemke(&lcp.a, &lcp.b)?;
    let mut z = solution.z.iter();
    for m in manifolds {
        for p in &mut points[m.range()] {
            let lambda = *z.next().expect("one impulse per row");
            let (a, b) = (m.a as usize, m.b as usize);
            bodies[a].v += p.normal * (lambda * m.inv_mass[0]);
            bodies[a].w += p.row.ia_ra_x_d * lambda;
            bodies[b].v -= p.normal * (lambda * m.inv_mass[1]);
            bodies[b].w -= p.row.ib_rb_x_d * lambda;
            p.normal_impulse = lambda;
            p.max_normal_impulse = p.max_normal_impulse.max(lambda);
        }
    }
    Ok(())
}
