//! The exact reference with friction: the contact LCP with a polyhedral
//! friction cone (D. Stewart and J. Trinkle 1996; M. Anitescu and F. Potra
//! 1997), solved by Lemke's method, against which the fast solver's
//! friction is checked.
//!
//! Each contact `i` has a normal impulse `n_i >= 0`, impulses `beta_ij >= 0`
//! along `k` tangent directions `d_j` spread evenly around the normal (the
//! cone's edges), and a slack `s_i >= 0`, the sliding speed. With `N` and
//! `D` the Jacobians of the normal and tangent rows, `M^-1` the inverse
//! masses, `u` the velocities before the impulses, `E` the block matrix of
//! ones that sums a contact's tangent impulses and `U = diag(mu_i)`:
//!
//! ```text
//! | w_n |   | N M^-1 N'  N M^-1 D'  0 | | n    |   | N u + bias |
//! | w_d | = | D M^-1 N'  D M^-1 D'  E | | beta | + | D u        |
//! | w_s |   | U          -E'        0 | | s    |   | 0          |
//! ```
//!
//! all `w >= 0`, all `z >= 0`, `w . z = 0`. Read row by row: no contact
//! approaches (`w_n`), no tangent direction slides faster than the sliding
//! speed `s` (`w_d`, so the friction acts along the directions that slide
//! fastest, against the motion: maximal dissipation), and the friction sum
//! stays within `mu n` (`w_s`), reaching it while the contact slides. The
//! matrix is not symmetric, but it is copositive-plus-like enough for
//! Lemke's method to terminate with a solution (Anitescu and Potra 1997).
//! As `k` grows the polygon tends to the Coulomb disc (its inscribed radius
//! is `cos(pi / k)` of the disc's).

use super::delassus::{
    apply_impulses, delassus, jacobian_row, row_velocity, validate, BodyState, BodyVelocity, ContactLcpError,
    ContactRow, JacobianRow,
};
use super::dense::DenseMatrix;
use super::lcp::LcpError;
use super::lemke::lemke;
use crate::collide::math::DVec3;

/// Why the friction-cone reference could not be built or solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FrictionConeError {
    /// The contacts or bodies are not valid (see [`ContactLcpError`]).
    #[error("friction cone LCP: {0}")]
    Contacts(#[from] ContactLcpError),
    /// The cone needs at least 3 directions (got this many).
    #[error("friction cone LCP: the cone needs at least 3 tangent directions, got {0}")]
    Directions(usize),
    /// Lemke's method failed.
    #[error("friction cone LCP: {0}")]
    Lcp(#[from] LcpError),
}

/// The solution of the friction-cone LCP: per contact, the normal impulse
/// (N s), the friction impulse as a world vector (N s) and the sliding speed
/// (m/s); and every body's velocity after the impulses.
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionConeSolution {
    /// Normal impulse of each contact (N s), `>= 0`.
    pub normal: Vec<f64>,
    /// Friction impulse of each contact (N s), in the friction plane.
    pub friction: Vec<DVec3>,
    /// Sliding speed of each contact after the impulses (m/s).
    pub sliding_speed: Vec<f64>,
    /// Velocities of the bodies after the impulses.
    pub velocities: Vec<BodyVelocity>,
}

/// `k` unit directions spread evenly around the unit `normal`, the first
/// along a fixed tangent (deterministic).
pub fn cone_directions(normal: DVec3, k: usize) -> Vec<DVec3> {
    let [t1, t2] = crate::solver::contact_solver::tangent_basis(normal);
    (0..k)
        .map(|j| {
            let a = std::f64::consts::TAU * j as f64 / k as f64;
            t1 * a.cos() + t2 * a.sin()
        })
        .collect()
}

// Opens as `build_contact_lcp` (delassus.rs) does, with its `validate` and
// `jacobian_row`; the rows then differ (k cone edges and a slack per contact).
/// Solves the contact problem of `contacts` between `bodies` with Coulomb
/// friction on a polyhedral cone of `k` directions (the contacts' `friction`
/// is each one's `mu`; `bias` is added to the normal rows, as in
/// `build_contact_lcp`).
pub fn solve_friction_cone(
    bodies: &[BodyState],
    contacts: &[ContactRow],
    k: usize,
) -> Result<FrictionConeSolution, FrictionConeError> {
    validate(bodies, contacts)?;
    if k < 3 {
        return Err(FrictionConeError::Directions(k));
    }
    let m = contacts.len();
    // Rows: m normal rows, then k tangent rows per contact.
    let mut rows: Vec<JacobianRow> = contacts.iter().map(|c| jacobian_row(c, c.normal)).collect();
    for c in contacts {
        rows.extend(
            cone_directions(c.normal, k)
                .into_iter()
                .map(|d| jacobian_row(c, d)),
        );
    }
    let jmj = delassus(&rows, bodies);
    let (nd, n) = (m + m * k, m + m * k + m);
    let mut a = DenseMatrix::zeros(n);
    for i in 0..nd {
        for j in 0..nd {
            a.set(i, j, jmj.get(i, j));
        }
    }
    let mut q = vec![0.0; n];
    for (i, row) in rows.iter().enumerate() {
        q[i] = row_velocity(row, bodies) + if i < m { contacts[i].bias } else { 0.0 };
    }
    for (c, contact) in contacts.iter().enumerate() {
        let slack = nd + c;
        // w_s = mu n - sum_j beta_j
        a.set(slack, c, contact.friction);
        for j in 0..k {
            let t = m + c * k + j;
            a.set(slack, t, -1.0);
            // w_d gets + s
            a.set(t, slack, 1.0);
        }
    }
    let z = lemke(&a, &q)?.z;
    let velocities = apply_impulses(&rows, bodies, &z);
    let friction = (0..m)
        .map(|c| {
            (0..k)
                .map(|j| rows[m + c * k + j].direction * z[m + c * k + j])
                .fold(DVec3::ZERO, |s, f| s + f)
        })
        .collect();
    Ok(FrictionConeSolution {
        normal: z[..m].to_vec(),
        friction,
        sliding_speed: z[nd..].to_vec(),
        velocities,
    })
}
