//! Assembly of the contact LCP `w = A z + b` from bodies and contact points
//! (thesis 7.1-7.2; Baraff 1994; Catto 2005 for the velocity-level form).
//!
//! Notation (thesis 7.1): contact `i` touches body A at `p` with arm
//! `r_a = p - x_a` and body B with arm `r_b = p - x_b`; the unit normal `n`
//! points from B to A; an impulse `z_i n` acts on A and `-z_i n` on B. The
//! relative normal velocity is
//! `v_rel = n . ((v_a + w_a x r_a) - (v_b + w_b x r_b)) = J_i u`, with the
//! Jacobian row over the velocities `u = (v_a, w_a, v_b, w_b)`:
//! `J_i = [ n, r_a x n, -n, -(r_b x n) ]`
//! (since `n . (w x r) = w . (r x n)`). Impulses change velocities by
//! `du = M^-1 J^T z` (`dv = z n / M`, `dw = I^-1 (r x z n)`), so after the
//! impulses `w = J (u + M^-1 J^T z) = A z + b` with
//! `A = J M^-1 J^T` and `b = J u (+ bias)`. Entry `A_ij` sums, over each body
//! that rows `i` and `j` share, `(1/M) d_i.d_j + (r_i x d_i).I^-1 (r_j x d_j)`
//! with the sign of each side. On the diagonal this is exactly the thesis 7.1
//! impulse denominator
//! `1/M_a + 1/M_b + n.(I_a^-1 (r_a x n)) x r_a + n.(I_b^-1 (r_b x n)) x r_b`,
//! because `n.(u x r) = u.(r x n)`. `A` is symmetric PSD (rank <= 6 per body),
//! so the frictionless contact LCP is the one Lemke solves or proves infeasible.
//!
//! Friction (optional): two tangent rows per contact with the same Jacobian
//! form and directions `t1, t2` (`n, t1, t2` right-handed). `t1` follows the
//! current sliding direction when there is one, so that pyramid friction
//! opposes sliding exactly; otherwise a fixed axis rule keeps it deterministic.
//!
//! Row layout: normal rows `0..m` in contact order, then for contact `c` the
//! tangent rows `m + 2c` and `m + 2c + 1`.

use super::dense::DenseMatrix;
use super::pgs::RowLimit;
use crate::collide::math::{DMat3, DVec3};

/// Sliding speeds below this (m/s) do not orient the tangent basis.
pub const TANGENT_VELOCITY_EPS: f64 = 1e-9;

/// Largest accepted deviation of `|normal|` from 1.
pub const NORMAL_UNIT_TOLERANCE: f64 = 1e-6;

/// What the contact assembly needs to know about one body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyState {
    /// Inverse mass (1/kg); 0 for a static body.
    pub inv_mass: f64,
    /// Inverse inertia tensor in world axes about the centre of mass
    /// (1/(kg m^2)); zero for a static body.
    pub inv_inertia: DMat3,
    /// Velocity of the centre of mass (m/s).
    pub linear_velocity: DVec3,
    /// Angular velocity, world frame (rad/s).
    pub angular_velocity: DVec3,
}

impl BodyState {
    /// A static body: infinite mass, at rest.
    pub fn fixed() -> BodyState {
        BodyState {
            inv_mass: 0.0,
            inv_inertia: DMat3::ZERO,
            linear_velocity: DVec3::ZERO,
            angular_velocity: DVec3::ZERO,
        }
    }

    /// Velocity of the material point at arm `r` from the centre of mass (m/s).
    pub fn point_velocity(&self, r: DVec3) -> DVec3 {
        self.linear_velocity + self.angular_velocity.cross(r)
    }
}

/// One contact point between bodies `body_a` and `body_b`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactRow {
    /// Index of body A (the one pushed along `+normal`).
    pub body_a: usize,
    /// Index of body B (pushed along `-normal`).
    pub body_b: usize,
    /// Contact point minus A's centre of mass, world frame (m).
    pub r_a: DVec3,
    /// Contact point minus B's centre of mass, world frame (m).
    pub r_b: DVec3,
    /// Unit normal from B towards A.
    pub normal: DVec3,
    /// Added to this contact's normal row of `b` (m/s). Zero for plain
    /// resting contact; `e * v_rel` (with `v_rel < 0` the approach speed)
    /// asks for Newton restitution `v_rel+ >= -e v_rel-` (thesis 7.1); a
    /// positive `gap/dt` lets a speculative gap close within the step
    /// (`v_rel+ >= -gap/dt`); a negative `-depth/dt` pushes penetration out.
    pub bias: f64,
    /// Coulomb friction coefficient (dimensionless, >= 0); used only when
    /// friction rows are requested.
    pub friction: f64,
}

/// Velocities of one body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyVelocity {
    /// Centre-of-mass velocity (m/s).
    pub linear: DVec3,
    /// Angular velocity, world frame (rad/s).
    pub angular: DVec3,
}

/// Why the contact LCP could not be assembled.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ContactLcpError {
    /// A contact names a body that does not exist.
    #[error("contact {contact}: body index {body} out of range (have {count} bodies)")]
    BodyIndex {
        /// Contact index.
        contact: usize,
        /// The bad body index.
        body: usize,
        /// Number of bodies given.
        count: usize,
    },
    /// A contact between a body and itself.
    #[error("contact {contact}: body_a and body_b are both {body}")]
    SameBody {
        /// Contact index.
        contact: usize,
        /// The body.
        body: usize,
    },
    /// A non-finite value in a body or contact.
    #[error("{what} {index}: non-finite {field}")]
    NonFinite {
        /// `"body"` or `"contact"`.
        what: &'static str,
        /// Its index.
        index: usize,
        /// Which field.
        field: &'static str,
    },
    /// A contact normal that is not unit length.
    #[error("contact {contact}: normal has length {length}, expected 1")]
    NormalNotUnit {
        /// Contact index.
        contact: usize,
        /// Its length.
        length: f64,
    },
    /// A negative inverse mass or friction coefficient.
    #[error("{what} {index}: {field} = {value} must be >= 0")]
    Negative {
        /// `"body"` or `"contact"`.
        what: &'static str,
        /// Its index.
        index: usize,
        /// Which field.
        field: &'static str,
        /// The value given.
        value: f64,
    },
    /// The number of impulses does not match the number of rows.
    #[error("expected {expected} impulses, found {found}")]
    ImpulseCount {
        /// Rows in the LCP.
        expected: usize,
        /// Impulses given.
        found: usize,
    },
}

/// One Jacobian row: a direction applied at two arms.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JacobianRow {
    /// Body A index.
    pub body_a: usize,
    /// Body B index.
    pub body_b: usize,
    /// Direction of the impulse on A (unit; B receives the opposite).
    pub direction: DVec3,
    /// Angular part on A: `r_a x direction` (m).
    pub angular_a: DVec3,
    /// Angular part on B: `r_b x direction` (m), entered with a minus sign.
    pub angular_b: DVec3,
}

/// The assembled contact LCP `w = A z + b`.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactLcp {
    /// `A = J M^-1 J^T` (units m/s per N s).
    pub a: DenseMatrix,
    /// `b = J u + bias` (m/s): relative velocities if no impulse were applied.
    pub b: Vec<f64>,
    /// Bounds for [`super::pgs::pgs_boxed`]: `z >= 0` on normal rows, the
    /// friction pyramid on tangent rows.
    pub limits: Vec<RowLimit>,
    /// The Jacobian rows, in LCP row order.
    pub rows: Vec<JacobianRow>,
    /// Number of contacts (= number of normal rows).
    pub contacts: usize,
}

// `solve_friction_cone` (friction_cone.rs) starts alike from the same
// `validate` and `jacobian_row`, then builds the polyhedral-cone LCP instead.
/// Builds `A`, `b` and the row bounds for `contacts` between `bodies`;
/// `with_friction` adds two tangent rows per contact.
pub fn build_contact_lcp(
    bodies: &[BodyState],
    contacts: &[ContactRow],
    with_friction: bool,
) -> Result<ContactLcp, ContactLcpError> {
    validate(bodies, contacts)?;
    let m = contacts.len();
    let mut rows = Vec::with_capacity(if with_friction { 3 * m } else { m });
    let mut b = Vec::with_capacity(rows.capacity());
    let mut limits = Vec::with_capacity(rows.capacity());
    for c in contacts {
        let row = jacobian_row(c, c.normal);
        b.push(row_velocity(&row, bodies) + c.bias);
        rows.push(row);
        limits.push(RowLimit::NON_NEGATIVE);
    }
    if with_friction {
        for (k, c) in contacts.iter().enumerate() {
            let v_rel = bodies[c.body_a].point_velocity(c.r_a) - bodies[c.body_b].point_velocity(c.r_b);
            let (t1, t2) = tangent_basis(c.normal, v_rel);
            for t in [t1, t2] {
                let row = jacobian_row(c, t);
                b.push(row_velocity(&row, bodies));
                rows.push(row);
                limits.push(RowLimit::Friction {
                    normal_row: k,
                    mu: c.friction,
                });
            }
        }
    }
    let a = delassus(&rows, bodies);
    Ok(ContactLcp {
        a,
        b,
        limits,
        rows,
        contacts: m,
    })
}

impl ContactLcp {
    /// Body velocities after applying impulses `z` (one per row):
    /// `u + M^-1 J^T z`.
    pub fn velocities_after(
        &self,
        bodies: &[BodyState],
        z: &[f64],
    ) -> Result<Vec<BodyVelocity>, ContactLcpError> {
        if z.len() != self.rows.len() {
            return Err(ContactLcpError::ImpulseCount {
                expected: self.rows.len(),
                found: z.len(),
            });
        }
        Ok(apply_impulses(&self.rows, bodies, z))
    }
}

/// Body velocities after impulses `z` along `rows` (one per row, as many
/// as rows): `u + M^-1 J^T z`.
pub(crate) fn apply_impulses(rows: &[JacobianRow], bodies: &[BodyState], z: &[f64]) -> Vec<BodyVelocity> {
    let mut out: Vec<BodyVelocity> = bodies
        .iter()
        .map(|s| BodyVelocity {
            linear: s.linear_velocity,
            angular: s.angular_velocity,
        })
        .collect();
    for (row, &zi) in rows.iter().zip(z) {
        let (a, b) = (&bodies[row.body_a], &bodies[row.body_b]);
        out[row.body_a].linear += a.inv_mass * zi * row.direction;
        out[row.body_a].angular += a.inv_inertia * (zi * row.angular_a);
        out[row.body_b].linear -= b.inv_mass * zi * row.direction;
        out[row.body_b].angular -= b.inv_inertia * (zi * row.angular_b);
    }
    out
}

/// Right-handed tangents `(t1, t2)` with `t1 x t2 = n`. `t1` points along the
/// tangential part of `v_rel` when that exceeds [`TANGENT_VELOCITY_EPS`];
/// otherwise it is `n` crossed with the coordinate axis least aligned with `n`.
pub fn tangent_basis(n: DVec3, v_rel: DVec3) -> (DVec3, DVec3) {
    let vt = v_rel - n * n.dot(v_rel);
    let t1 = if vt.length() > TANGENT_VELOCITY_EPS {
        vt.normalize()
    } else {
        let a = n.abs();
        let axis = if a.x <= a.y && a.x <= a.z {
            DVec3::X
        } else if a.y <= a.z {
            DVec3::Y
        } else {
            DVec3::Z
        };
        n.cross(axis).normalize()
    };
    (t1, n.cross(t1))
}

pub(crate) fn jacobian_row(c: &ContactRow, d: DVec3) -> JacobianRow {
    JacobianRow {
        body_a: c.body_a,
        body_b: c.body_b,
        direction: d,
        angular_a: c.r_a.cross(d),
        angular_b: c.r_b.cross(d),
    }
}

/// `J_i u`: relative velocity of the two contact points along the row.
pub(crate) fn row_velocity(row: &JacobianRow, bodies: &[BodyState]) -> f64 {
    let (a, b) = (&bodies[row.body_a], &bodies[row.body_b]);
    row.direction.dot(a.linear_velocity) + row.angular_a.dot(a.angular_velocity)
        - row.direction.dot(b.linear_velocity)
        - row.angular_b.dot(b.angular_velocity)
}

/// `A = J M^-1 J^T`, filled in the upper triangle and mirrored so that it is
/// exactly symmetric.
pub(crate) fn delassus(rows: &[JacobianRow], bodies: &[BodyState]) -> DenseMatrix {
    let k = rows.len();
    // Each row as two (body, sign, linear, angular) sides.
    let sides = |r: &JacobianRow| {
        [
            (r.body_a, 1.0, r.direction, r.angular_a),
            (r.body_b, -1.0, r.direction, r.angular_b),
        ]
    };
    let mut a = DenseMatrix::zeros(k);
    for (i, ri) in rows.iter().enumerate() {
        let si = sides(ri);
        for (j, rj) in rows.iter().enumerate().skip(i) {
            let sj = sides(rj);
            let mut v = 0.0;
            for &(bi, gi, li, ai) in &si {
                for &(bj, gj, lj, aj) in &sj {
                    if bi == bj {
                        let body = &bodies[bi];
                        v += gi * gj * (body.inv_mass * li.dot(lj) + ai.dot(body.inv_inertia * aj));
                    }
                }
            }
            a.set(i, j, v);
            a.set(j, i, v);
        }
    }
    a
}

pub(crate) fn validate(bodies: &[BodyState], contacts: &[ContactRow]) -> Result<(), ContactLcpError> {
    // One check per field, each naming it in its error: the bodies' checks
    // here and the contacts' below read alike but check different records.
    for (index, s) in bodies.iter().enumerate() {
        let nf = |field| ContactLcpError::NonFinite {
            what: "body",
            index,
            field,
        };
        if !s.inv_mass.is_finite() {
            return Err(nf("inv_mass"));
        }
        if !s.inv_inertia.is_finite() {
            return Err(nf("inv_inertia"));
        }
        if !s.linear_velocity.is_finite() {
            return Err(nf("linear_velocity"));
        }
        if !s.angular_velocity.is_finite() {
            return Err(nf("angular_velocity"));
        }
        if s.inv_mass < 0.0 {
            return Err(ContactLcpError::Negative {
                what: "body",
                index,
                field: "inv_mass",
                value: s.inv_mass,
            });
        }
    }
    let count = bodies.len();
    for (index, c) in contacts.iter().enumerate() {
        for body in [c.body_a, c.body_b] {
            if body >= count {
                return Err(ContactLcpError::BodyIndex {
                    contact: index,
                    body,
                    count,
                });
            }
        }
        if c.body_a == c.body_b {
            return Err(ContactLcpError::SameBody {
                contact: index,
                body: c.body_a,
            });
        }
        // One check per field, as for the bodies above: the fields differ in
        // type (DVec3, f64) and the error names the one that failed.
        let nf = |field| ContactLcpError::NonFinite {
            what: "contact",
            index,
            field,
        };
        if !c.r_a.is_finite() {
            return Err(nf("r_a"));
        }
        if !c.r_b.is_finite() {
            return Err(nf("r_b"));
        }
        if !c.normal.is_finite() {
            return Err(nf("normal"));
        }
        if !c.bias.is_finite() {
            return Err(nf("bias"));
        }
        if !c.friction.is_finite() {
            return Err(nf("friction"));
        }
        let length = c.normal.length();
        if (length - 1.0).abs() > NORMAL_UNIT_TOLERANCE {
            return Err(ContactLcpError::NormalNotUnit {
                contact: index,
                length,
            });
        }
        if c.friction < 0.0 {
            return Err(ContactLcpError::Negative {
                what: "contact",
                index,
                field: "friction",
                value: c.friction,
            });
        }
    }
    Ok(())
}
