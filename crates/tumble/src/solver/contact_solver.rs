//! Sub-stepped contact solver: non-penetration, Coulomb friction and
//! restitution by sequential impulses (projected Gauss-Seidel on the contact
//! LCP of thesis 7.2), sub-stepped as in E. Catto's "soft step" (Solver2D
//! 2024, Box2D v3), with position correction by split impulses (Catto 2006;
//! Bullet's split-impulse mode).
//!
//! One step of `dt` is split into `n` sub-steps of `h = dt / n`. The contact
//! points, normals and effective masses are computed once per step; within
//! each sub-step the separation of every point is updated from the bodies'
//! motion since the start of the step (`s = s0 + n . (dA - dB)` with `d` the
//! displacement of each anchor), so the narrow phase runs once per step while
//! the solver sees the contact close and open. Per sub-step:
//!
//! 1. integrate velocities (gravity, forces),
//! 2. warm start: apply the impulses accumulated so far,
//! 3. velocity passes: `v_n >= 0` on touching points, `v_n >= -s/h` on points
//!    with a gap `s` (speculative: the gap may close, never go negative),
//!    friction in the Coulomb cone,
//! 4. push-out: overlap beyond the allowance is removed by pseudo-velocities
//!    that move the bodies but are then discarded, so correcting position
//!    never adds kinetic energy and never depends on the load (a stack does
//!    not sag under its own weight, as it does with Baumgarte or spring bias),
//! 5. integrate positions with the velocities plus the pseudo-velocities.
//!
//! Before the sub-steps, colliding contacts get Newton's restitution law
//! `v_n+ = -e v_n-` (thesis 7.1) by [`resolve_collisions`]; the sub-steps then
//! treat every contact as resting (the LCP of thesis 7.2, `e = 0`). Normals
//! point from B to A; an impulse `lambda n` acts on A and `-lambda n` on B.
//!
//! Sign conventions: `v_n = n . (v_A + w_A x r_A - v_B - w_B x r_B)` is the
//! separating speed; the accumulated normal impulse stays >= 0 (the LCP's
//! z >= 0); friction impulses are clamped to the Coulomb cone of radius
//! `mu * normal impulse`.

use tumble_collide::{DMat3, DQuat, DVec3};

/// Per-body solver state (a contiguous array; static bodies have zero inverse
/// mass and inertia and never change).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverBody {
    /// Linear velocity (m/s).
    pub v: DVec3,
    /// Angular velocity, world frame (rad/s).
    pub w: DVec3,
    /// Inverse mass (1/kg); 0 for static and kinematic bodies.
    pub inv_mass: f64,
    /// Inverse principal inertia in the body frame (1/(kg m^2)).
    pub inv_inertia_body: DVec3,
    /// Inverse inertia in the world frame for the current orientation.
    pub inv_inertia: DMat3,
    /// Orientation (body to world).
    pub q: DQuat,
    /// Displacement of the centre of mass since the start of the step (m).
    pub dp: DVec3,
    /// Pseudo-velocity of the push-out pass (m/s), discarded every sub-step.
    pub push_v: DVec3,
    /// Pseudo angular velocity of the push-out pass (rad/s).
    pub push_w: DVec3,
    /// `true` for dynamic bodies (integrated and pushed by impulses).
    pub dynamic: bool,
    /// `true` for kinematic bodies: moved by their velocity, never pushed.
    pub kinematic: bool,
}

impl SolverBody {
    /// World-frame inverse inertia `R diag(I^-1) R^T`.
    pub fn world_inverse_inertia(q: DQuat, inv_inertia_body: DVec3) -> DMat3 {
        let r = DMat3::from_quat(q);
        r * DMat3::from_diagonal(inv_inertia_body) * r.transpose()
    }

    #[inline]
    fn velocity_at(&self, r: DVec3) -> DVec3 {
        self.v + self.w.cross(r)
    }

    #[inline]
    fn apply_impulse(&mut self, impulse: DVec3, r: DVec3) {
        self.v += impulse * self.inv_mass;
        self.w += self.inv_inertia * r.cross(impulse);
    }
}

/// One contact point prepared for the solver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactConstraint {
    /// Index of body A in the solver body array.
    pub a: u32,
    /// Index of body B.
    pub b: u32,
    /// Unit normal from B to A.
    pub normal: DVec3,
    /// Two unit tangents completing a right-handed frame with the normal.
    pub tangents: [DVec3; 2],
    /// Anchor relative to A's centre of mass, A's body frame.
    pub local_a: DVec3,
    /// Anchor relative to B's centre of mass, B's body frame.
    pub local_b: DVec3,
    /// Anchor relative to A's centre of mass at the step start, world frame.
    pub r_a: DVec3,
    /// Anchor relative to B's centre of mass at the step start, world frame.
    pub r_b: DVec3,
    /// Signed separation at the start of the step (m), < 0 when overlapping.
    pub separation: f64,
    /// Effective mass along the normal (kg): 1 / (thesis 7.1 denominator).
    pub normal_mass: f64,
    /// Effective masses along the tangents (kg).
    pub tangent_mass: [f64; 2],
    /// Coulomb friction coefficient of the pair.
    pub friction: f64,
    /// Restitution coefficient of the pair.
    pub restitution: f64,
    /// Normal velocity before the solve (m/s), for restitution.
    pub approach_speed: f64,
    /// Accumulated normal impulse (N s), warm-started across steps.
    pub normal_impulse: f64,
    /// Accumulated tangent impulses (N s), warm-started across steps.
    pub tangent_impulse: [f64; 2],
    /// Largest normal impulse seen during the step (N s).
    pub max_normal_impulse: f64,
    /// Accumulated push-out pseudo-impulse of the current sub-step.
    pub push_impulse: f64,
    /// Anchor on A for the current sub-step's poses (world frame offset).
    pub ra_now: DVec3,
    /// Anchor on B for the current sub-step's poses.
    pub rb_now: DVec3,
    /// Separation for the current sub-step's poses (m).
    pub separation_now: f64,
    /// Jacobian rows for the current sub-step: `r x d` and `I^-1 (r x d)`
    /// on A and B for d = normal, tangent 1, tangent 2 (precomputed so that a
    /// row costs dot products only).
    pub rows: [RowJacobian; 3],
    /// Inverse masses of A and B (1/kg).
    pub inv_mass: [f64; 2],
}

/// The angular part of one constraint row on both bodies.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RowJacobian {
    /// `r_A x d`.
    pub ra_x_d: DVec3,
    /// `r_B x d`.
    pub rb_x_d: DVec3,
    /// `I_A^-1 (r_A x d)`.
    pub ia_ra_x_d: DVec3,
    /// `I_B^-1 (r_B x d)`.
    pub ib_rb_x_d: DVec3,
}

/// Two unit tangents orthogonal to the unit `n`, right-handed (t1 x t2 = n).
pub fn tangent_basis(n: DVec3) -> [DVec3; 2] {
    // Pick the axis least aligned with n (Frisvad/Duff-style branch-free basis
    // would also do; this one is deterministic and well conditioned).
    let t1 = if n.x.abs() < 0.57735 {
        DVec3::new(0.0, n.z, -n.y)
    } else {
        DVec3::new(n.y, -n.x, 0.0)
    }
    .normalize();
    [t1, n.cross(t1)]
}

/// Inverse effective mass of an impulse along `dir` at anchors `ra`, `rb`:
/// `1/Ma + 1/Mb + dir . (Ia^-1 (ra x dir)) x ra + dir . (Ib^-1 (rb x dir)) x rb`
/// (thesis 7.1).
pub fn inverse_effective_mass(a: &SolverBody, b: &SolverBody, ra: DVec3, rb: DVec3, dir: DVec3) -> f64 {
    let rna = ra.cross(dir);
    let rnb = rb.cross(dir);
    a.inv_mass + b.inv_mass + rna.dot(a.inv_inertia * rna) + rnb.dot(b.inv_inertia * rnb)
}

/// Settings the solver reads (a subset of the world settings).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverParams {
    /// Fraction of the overlap beyond the allowance removed per sub-step.
    pub push_out_fraction: f64,
    /// Overlap left uncorrected (m).
    pub allowed_penetration: f64,
    /// Largest push-out speed (m/s).
    pub max_push_out_speed: f64,
    /// Approach speed below which restitution is ignored (m/s).
    pub restitution_threshold: f64,
}

/// Fills the derived fields of a constraint (tangents, world anchors,
/// effective masses, approach speed) from the bodies at the step start.
pub fn prepare(c: &mut ContactConstraint, bodies: &[SolverBody]) {
    let a = &bodies[c.a as usize];
    let b = &bodies[c.b as usize];
    c.tangents = tangent_basis(c.normal);
    c.r_a = a.q * c.local_a;
    c.r_b = b.q * c.local_b;
    let k = inverse_effective_mass(a, b, c.r_a, c.r_b, c.normal);
    c.normal_mass = if k > 0.0 { 1.0 / k } else { 0.0 };
    for i in 0..2 {
        let k = inverse_effective_mass(a, b, c.r_a, c.r_b, c.tangents[i]);
        c.tangent_mass[i] = if k > 0.0 { 1.0 / k } else { 0.0 };
    }
    c.approach_speed = c.normal.dot(a.velocity_at(c.r_a) - b.velocity_at(c.r_b));
    c.max_normal_impulse = 0.0;
    c.ra_now = c.r_a;
    c.rb_now = c.r_b;
    c.separation_now = c.separation;
    fill_rows(c, a, b);
}

#[inline]
fn pair(bodies: &mut [SolverBody], a: u32, b: u32) -> (SolverBody, SolverBody) {
    (bodies[a as usize], bodies[b as usize])
}

#[inline]
fn store(bodies: &mut [SolverBody], c: &ContactConstraint, ba: SolverBody, bb: SolverBody) {
    if ba.dynamic {
        bodies[c.a as usize] = ba;
    }
    if bb.dynamic {
        bodies[c.b as usize] = bb;
    }
}

/// Pseudo-velocity of the point at offset `r` of body `i`.
#[inline(always)]
fn push_velocity(bodies: &[SolverBody], i: u32, r: DVec3) -> DVec3 {
    let b = &bodies[i as usize];
    b.push_v + b.push_w.cross(r)
}

/// Applies a push-out pseudo-impulse at offset `r` of body `i`.
#[inline(always)]
fn push_at(bodies: &mut [SolverBody], i: u32, impulse: DVec3, r: DVec3) {
    let b = &mut bodies[i as usize];
    if b.dynamic {
        b.push_v += impulse * b.inv_mass;
        b.push_w += b.inv_inertia * r.cross(impulse);
    }
}

/// Refreshes each point's separation for the bodies' current poses; called
/// once per sub-step before the passes (the poses do not change until
/// positions are integrated):
/// `s = s0 + n . ((dpA + rA(t) - rA0) - (dpB + rB(t) - rB0))`.
///
/// The Jacobian rows (lever arms, inverse inertia) stay those of the step
/// start, as in Box2D v3: the bodies turn little within a step, and keeping
/// them fixed halves the cost of a sub-step; the separation, which decides
/// whether a point is active, follows the rotation exactly.
pub fn begin_substep(constraints: &mut [ContactConstraint], bodies: &[SolverBody]) {
    for c in constraints.iter_mut() {
        let (ba, bb) = (&bodies[c.a as usize], &bodies[c.b as usize]);
        c.ra_now = ba.q * c.local_a;
        c.rb_now = bb.q * c.local_b;
        let d = (ba.dp + c.ra_now - c.r_a) - (bb.dp + c.rb_now - c.r_b);
        c.separation_now = c.separation + c.normal.dot(d);
        c.push_impulse = 0.0;
    }
}

fn fill_rows(c: &mut ContactConstraint, ba: &SolverBody, bb: &SolverBody) {
    let dirs = [c.normal, c.tangents[0], c.tangents[1]];
    for (row, d) in c.rows.iter_mut().zip(dirs) {
        let ra_x_d = c.ra_now.cross(d);
        let rb_x_d = c.rb_now.cross(d);
        *row = RowJacobian {
            ra_x_d,
            rb_x_d,
            ia_ra_x_d: ba.inv_inertia * ra_x_d,
            ib_rb_x_d: bb.inv_inertia * rb_x_d,
        };
    }
    c.inv_mass = [ba.inv_mass, bb.inv_mass];
}

/// Relative velocity of the row: `d . (vA - vB) + (rA x d) . wA - (rB x d) . wB`.
#[inline(always)]
fn row_velocity(bodies: &[SolverBody], c: &ContactConstraint, row: usize, d: DVec3) -> f64 {
    let (a, b) = (&bodies[c.a as usize], &bodies[c.b as usize]);
    let j = &c.rows[row];
    d.dot(a.v - b.v) + j.ra_x_d.dot(a.w) - j.rb_x_d.dot(b.w)
}

/// Applies `lambda` along the row: `+lambda d` on A, `-lambda d` on B.
#[inline(always)]
fn row_impulse(bodies: &mut [SolverBody], c: &ContactConstraint, row: usize, d: DVec3, lambda: f64) {
    let j = &c.rows[row];
    let a = &mut bodies[c.a as usize];
    a.v += d * (lambda * c.inv_mass[0]);
    a.w += j.ia_ra_x_d * lambda;
    let b = &mut bodies[c.b as usize];
    b.v -= d * (lambda * c.inv_mass[1]);
    b.w -= j.ib_rb_x_d * lambda;
}

/// Applies the accumulated impulses (warm start).
pub fn warm_start(constraints: &[ContactConstraint], bodies: &mut [SolverBody]) {
    for c in constraints {
        row_impulse(bodies, c, 0, c.normal, c.normal_impulse);
        row_impulse(bodies, c, 1, c.tangents[0], c.tangent_impulse[0]);
        row_impulse(bodies, c, 2, c.tangents[1], c.tangent_impulse[1]);
    }
}

/// One Gauss-Seidel pass over all contact points on the real velocities:
/// touching points may not approach, points with a gap may close it within
/// the sub-step `h` (s) but not more, friction stays in the Coulomb cone.
pub fn solve(constraints: &mut [ContactConstraint], bodies: &mut [SolverBody], h: f64) {
    let inv_h = 1.0 / h;
    for c in constraints.iter_mut() {
        let s = c.separation_now;
        let bias = if s > 0.0 { s * inv_h } else { 0.0 };

        // Normal: the LCP row  v_n + bias >= 0, lambda >= 0, complementary.
        let vn = row_velocity(bodies, c, 0, c.normal);
        let new_impulse = (c.normal_impulse - c.normal_mass * (vn + bias)).max(0.0);
        let applied = new_impulse - c.normal_impulse;
        c.normal_impulse = new_impulse;
        c.max_normal_impulse = c.max_normal_impulse.max(new_impulse);
        row_impulse(bodies, c, 0, c.normal, applied);

        solve_friction_row(c, bodies);
    }
}

/// Friction of one point: Coulomb cone |lambda_t| <= mu lambda_n. The two
/// tangent rows are solved one after the other (Gauss-Seidel: they are
/// coupled through the rotation), then the pair is projected onto the disc.
#[inline]
fn solve_friction_row(c: &mut ContactConstraint, bodies: &mut [SolverBody]) {
    let limit = c.friction * c.normal_impulse;
    let mut t = c.tangent_impulse;
    for (i, ti) in t.iter_mut().enumerate() {
        let d = c.tangents[i];
        let before = *ti;
        *ti = before - c.tangent_mass[i] * row_velocity(bodies, c, i + 1, d);
        row_impulse(bodies, c, i + 1, d, *ti - before);
    }
    let len2 = t[0] * t[0] + t[1] * t[1];
    if len2 > limit * limit {
        let scale = if len2 > 0.0 { limit / len2.sqrt() } else { 0.0 };
        for (i, ti) in t.iter_mut().enumerate() {
            let clamped = *ti * scale;
            row_impulse(bodies, c, i + 1, c.tangents[i], clamped - *ti);
            *ti = clamped;
        }
    }
    c.tangent_impulse = t;
}

/// One Gauss-Seidel pass over the friction rows only, the normal impulses
/// held fixed (used after an exact normal solve).
pub fn solve_friction(constraints: &mut [ContactConstraint], bodies: &mut [SolverBody]) {
    for c in constraints.iter_mut() {
        solve_friction_row(c, bodies);
    }
}

/// Why the exact normal solve failed (the caller falls back to PGS).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ExactSolveError {
    /// The contact rows could not be assembled into an LCP.
    #[error("contact LCP assembly: {0}")]
    Assembly(#[from] super::ContactLcpError),
    /// Lemke's method failed (ray termination, pivot limit, bad input).
    #[error("Lemke: {0}")]
    Lcp(#[from] super::LcpError),
}

/// Largest number of contact points solved exactly by [`solve_normals_exactly`]
/// (Lemke's method costs O(n^3)); the world falls back to PGS above it.
pub const EXACT_MAX_CONTACTS: usize = 256;

/// Solves the normal impulses of all points of the sub-step `h` exactly as
/// the LCP of thesis 7.2 (`w = A z + b >= 0, z >= 0, z.w = 0` with
/// `A = J M^-1 J^T` and `b` the relative normal velocities plus the
/// speculative allowance) by Lemke's method, and applies them. The bodies'
/// velocities must not contain any impulse of this sub-step yet (no warm
/// start). Friction is left to [`solve_friction`].
pub fn solve_normals_exactly(
    constraints: &mut [ContactConstraint],
    bodies: &mut [SolverBody],
    h: f64,
) -> Result<(), ExactSolveError> {
    let states: Vec<super::BodyState> = bodies
        .iter()
        .map(|b| super::BodyState {
            inv_mass: b.inv_mass,
            inv_inertia: b.inv_inertia,
            linear_velocity: b.v,
            angular_velocity: b.w,
        })
        .collect();
    let rows: Vec<super::ContactRow> = constraints
        .iter()
        .map(|c| super::ContactRow {
            body_a: c.a as usize,
            body_b: c.b as usize,
            // The lever arms of the rows the impulses are applied through.
            r_a: c.r_a,
            r_b: c.r_b,
            normal: c.normal,
            bias: if c.separation_now > 0.0 {
                c.separation_now / h
            } else {
                0.0
            },
            friction: c.friction,
        })
        .collect();
    let mut lcp = super::build_contact_lcp(&states, &rows, false)?;
    // Redundant contacts (four corners of a box face) make A only positive
    // semi-definite; a compliance far below any physical one keeps Lemke's
    // pivots away from ray termination without changing the answer visibly.
    let n = lcp.a.n().max(1);
    let mean_diagonal = (0..n).map(|i| lcp.a.get(i, i)).sum::<f64>() / n as f64;
    lcp.a.add_diagonal(1e-9 * mean_diagonal)?;
    let solution = super::lemke(&lcp.a, &lcp.b)?;
    for (c, &z) in constraints.iter_mut().zip(&solution.z) {
        row_impulse(bodies, c, 0, c.normal, z);
        c.normal_impulse = z;
        c.max_normal_impulse = c.max_normal_impulse.max(z);
    }
    Ok(())
}

/// One Gauss-Seidel pass of position correction by pseudo-velocities: each
/// point overlapping by more than the allowance gets a pseudo-impulse that
/// removes `push_out_fraction` of the excess in this sub-step (at most
/// `max_push_out_speed`). Pseudo-velocities move the bodies in
/// [`integrate_positions`] and are then discarded.
pub fn push_out(
    constraints: &mut [ContactConstraint],
    bodies: &mut [SolverBody],
    params: &SolverParams,
    h: f64,
) {
    let inv_h = 1.0 / h;
    for c in constraints.iter_mut() {
        let excess = c.separation_now + params.allowed_penetration;
        if excess >= 0.0 && c.push_impulse == 0.0 {
            continue;
        }
        let target = if excess < 0.0 {
            (-params.push_out_fraction * excess * inv_h).min(params.max_push_out_speed)
        } else {
            0.0
        };
        let (ra, rb) = (c.ra_now, c.rb_now);
        let vn = c
            .normal
            .dot(push_velocity(bodies, c.a, ra) - push_velocity(bodies, c.b, rb));
        let new_impulse = (c.push_impulse + c.normal_mass * (target - vn)).max(0.0);
        let applied = new_impulse - c.push_impulse;
        c.push_impulse = new_impulse;
        let p = c.normal * applied;
        push_at(bodies, c.a, p, ra);
        push_at(bodies, c.b, -p, rb);
    }
}

/// Largest number of sweeps of [`resolve_collisions`].
pub const MAX_COLLISION_SWEEPS: usize = 32;

/// Colliding contact (thesis 7.1): before the resting-contact solve, every
/// point of a pair with restitution `e > 0` that approaches faster than the
/// threshold and will touch within `dt` gets the impulse that reverses its
/// normal velocity by Newton's law. Sweeps repeat until nothing approaches,
/// so an impact travels down a row of touching bodies in one step (Newton's
/// cradle; Guendelman, Bridson & Fedkiw 2003 process collisions the same way).
///
/// The impact happens a gap `g` before the surfaces meet. So that the bounce
/// loses nothing to that shift, the outgoing speed is the one the body would
/// have at `g` after bouncing at the surface under the pair's relative normal
/// acceleration `a` (gravity, forces): with `v_i^2 = v_n^2 - 2 a g` the speed
/// at impact, `v_out = sqrt(e^2 v_i^2 + 2 a g)`. For `e = 1` this is `|v_n|`
/// exactly; for a ball dropped on the ground it gives the apex `e^2` times the
/// drop height.
///
/// Semi-implicit Euler stores the velocity of the middle of the last
/// sub-step `h`, not of its end: the impact is computed with the velocity at
/// the step start, `v_n + a h / 2`, and the result is stored back half a
/// sub-step earlier, so that a perfectly elastic ball returns to its height.
///
/// `accel[i]` is body i's linear acceleration. Collision impulses are not
/// accumulated into the warm-start impulses. Returns the sweeps used.
pub fn resolve_collisions(
    constraints: &mut [ContactConstraint],
    bodies: &mut [SolverBody],
    accel: &[DVec3],
    params: &SolverParams,
    dt: f64,
    h: f64,
) -> usize {
    for sweep in 0..MAX_COLLISION_SWEEPS {
        let mut any = false;
        for c in constraints.iter_mut() {
            if c.restitution == 0.0 || c.normal_mass == 0.0 {
                continue;
            }
            let (mut ba, mut bb) = pair(bodies, c.a, c.b);
            let vn = c.normal.dot(ba.velocity_at(c.r_a) - bb.velocity_at(c.r_b));
            if vn >= -params.restitution_threshold {
                continue;
            }
            let a_n = c.normal.dot(accel[c.a as usize] - accel[c.b as usize]);
            let gap = c.separation.max(0.0);
            if gap + vn * dt + 0.5 * a_n.min(0.0) * dt * dt > 0.0 {
                continue; // will not touch during this step
            }
            let v_start = vn + 0.5 * a_n * h;
            let vi2 = v_start * v_start - 2.0 * a_n * gap;
            let e = c.restitution;
            let v_out = (e * e * vi2 + 2.0 * a_n * gap).max(0.0).sqrt() - 0.5 * a_n * h;
            let magnitude = c.normal_mass * (v_out - vn);
            // A bounce is a touch: contact events see it like a resting impulse.
            c.max_normal_impulse = c.max_normal_impulse.max(magnitude);
            let p = c.normal * magnitude;
            ba.apply_impulse(p, c.r_a);
            bb.apply_impulse(-p, c.r_b);
            store(bodies, c, ba, bb);
            any = true;
        }
        if !any {
            return sweep;
        }
    }
    MAX_COLLISION_SWEEPS
}

/// Advances orientation and displacement of dynamic bodies by one sub-step
/// with their current velocities (semi-implicit Euler), keeping angular
/// momentum: `L = I(t) w` is carried across the rotation, so a free body
/// precesses correctly (gyroscopic effect) instead of keeping `w` fixed.
/// The push-out pseudo-velocities move the body too and are then cleared.
pub fn integrate_positions(bodies: &mut [SolverBody], h: f64) {
    for b in bodies.iter_mut() {
        if b.kinematic {
            b.dp += b.v * h;
            b.q = (DQuat::from_scaled_axis(b.w * h) * b.q).normalize();
            continue;
        }
        if !b.dynamic {
            continue;
        }
        let r_old = DMat3::from_quat(b.q);
        let inertia_body = DVec3::new(
            recip_or_zero(b.inv_inertia_body.x),
            recip_or_zero(b.inv_inertia_body.y),
            recip_or_zero(b.inv_inertia_body.z),
        );
        let l = r_old * (inertia_body * (r_old.transpose() * b.w));
        b.dp += (b.v + b.push_v) * h;
        // Free rotation under the constant L by the symplectic principal-axis
        // splitting: no energy drift for tumbling bodies (a plain exponential
        // map with the step's w gains energy steadily on asymmetric bodies).
        b.q = crate::integrate::free_rotation(b.q, l, b.inv_inertia_body, h).normalize();
        b.inv_inertia = SolverBody::world_inverse_inertia(b.q, b.inv_inertia_body);
        b.w = b.inv_inertia * l;
        if b.push_w != DVec3::ZERO {
            // The push-out turns the body as a whole, its motion with it: the
            // body-frame angular velocity is kept, so the push-out changes
            // neither the kinetic energy nor |L| (only L's direction, by the
            // small correction angle).
            let turn = DQuat::from_scaled_axis(b.push_w * h);
            b.q = (turn * b.q).normalize();
            b.w = turn * b.w;
            b.inv_inertia = SolverBody::world_inverse_inertia(b.q, b.inv_inertia_body);
        }
        b.push_v = DVec3::ZERO;
        b.push_w = DVec3::ZERO;
    }
}

fn recip_or_zero(x: f64) -> f64 {
    if x > 0.0 {
        1.0 / x
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn body(inv_mass: f64, v: DVec3) -> SolverBody {
        let iib = DVec3::splat(if inv_mass > 0.0 { 6.0 } else { 0.0 });
        SolverBody {
            v,
            w: DVec3::ZERO,
            inv_mass,
            inv_inertia_body: iib,
            inv_inertia: DMat3::from_diagonal(iib),
            q: DQuat::IDENTITY,
            dp: DVec3::ZERO,
            push_v: DVec3::ZERO,
            push_w: DVec3::ZERO,
            dynamic: inv_mass > 0.0,
            kinematic: false,
        }
    }

    fn contact(a: u32, b: u32, local_a: DVec3, local_b: DVec3, separation: f64) -> ContactConstraint {
        ContactConstraint {
            a,
            b,
            normal: DVec3::Z,
            tangents: [DVec3::X, DVec3::Y],
            local_a,
            local_b,
            r_a: DVec3::ZERO,
            r_b: DVec3::ZERO,
            separation,
            normal_mass: 0.0,
            tangent_mass: [0.0; 2],
            friction: 0.5,
            restitution: 0.0,
            approach_speed: 0.0,
            normal_impulse: 0.0,
            tangent_impulse: [0.0; 2],
            max_normal_impulse: 0.0,
            push_impulse: 0.0,
            ra_now: DVec3::ZERO,
            rb_now: DVec3::ZERO,
            separation_now: 0.0,
            rows: [RowJacobian::default(); 3],
            inv_mass: [0.0; 2],
        }
    }

    fn params() -> SolverParams {
        SolverParams {
            push_out_fraction: 0.2,
            allowed_penetration: 0.0,
            max_push_out_speed: 3.0,
            restitution_threshold: 0.5,
        }
    }

    #[test]
    fn collisions_propagate_down_a_row_of_touching_balls() {
        // Newton's cradle: balls 0..4 touching along x, ball 5 hits ball 0 at 1 m/s.
        let mut bodies: Vec<SolverBody> = (0..6).map(|_| body(1.0, DVec3::ZERO)).collect();
        bodies[5].v = DVec3::new(1.0, 0.0, 0.0);
        let mut cs = vec![];
        for i in 0..4u32 {
            let mut c = contact(
                i + 1,
                i,
                DVec3::new(-0.1, 0.0, 0.0),
                DVec3::new(0.1, 0.0, 0.0),
                0.0,
            );
            c.normal = DVec3::X;
            c.restitution = 1.0;
            cs.push(c);
        }
        let mut c = contact(0, 5, DVec3::new(-0.1, 0.0, 0.0), DVec3::new(0.1, 0.0, 0.0), 0.001);
        c.normal = DVec3::X;
        c.restitution = 1.0;
        cs.push(c);
        for c in cs.iter_mut() {
            prepare(c, &bodies);
        }
        let h = 1.0 / 240.0;
        let sweeps = resolve_collisions(&mut cs, &mut bodies, &[DVec3::ZERO; 6], &params(), h, h);
        assert!(sweeps <= 6);
        assert!((bodies[4].v.x - 1.0).abs() < 1e-12, "last ball leaves at 1 m/s");
        for b in &bodies[..4] {
            assert!(b.v.length() < 1e-12);
        }
        assert!(bodies[5].v.length() < 1e-12);
    }

    #[test]
    fn bounce_from_a_gap_keeps_the_apex_of_newtons_law() {
        // Ball falling at 4 m/s (at the step start), 1 cm above the ground,
        // e = 0.5, gravity 9.81: the true impact speed is sqrt(16 + 2 g 0.01);
        // bouncing at the surface with half of it, the ball passes 1 cm with
        // the speed that reaches the same apex. Velocities are stored half a
        // sub-step early (semi-implicit Euler), hence the +- g h / 2.
        let g = 9.81;
        let h = 1.0 / 240.0;
        let stored = |v: f64| v + 0.5 * g * h;
        let mut bodies = vec![
            body(1.0, DVec3::new(0.0, 0.0, stored(-4.0))),
            body(0.0, DVec3::ZERO),
        ];
        let mut c = contact(0, 1, DVec3::new(0.0, 0.0, -0.1), DVec3::ZERO, 0.01);
        c.restitution = 0.5;
        let mut cs = [c];
        prepare(&mut cs[0], &bodies);
        let accel = [DVec3::new(0.0, 0.0, -g), DVec3::ZERO];
        resolve_collisions(&mut cs, &mut bodies, &accel, &params(), 4.0 * h, h);
        let v_out = bodies[0].v.z - 0.5 * g * h;
        let vi = (16.0 + 2.0 * g * 0.01f64).sqrt();
        let apex_true = (0.5 * vi).powi(2) / (2.0 * g);
        let apex = 0.01 + v_out.powi(2) / (2.0 * g);
        assert!((apex - apex_true).abs() < 1e-12, "{apex} vs {apex_true}");
    }

    #[test]
    fn tangent_basis_is_orthonormal_right_handed() {
        for n in [
            DVec3::X,
            DVec3::Y,
            DVec3::Z,
            DVec3::new(1.0, 2.0, -3.0).normalize(),
            -DVec3::Z,
        ] {
            let [t1, t2] = tangent_basis(n);
            assert!((t1.length() - 1.0).abs() < 1e-14 && (t2.length() - 1.0).abs() < 1e-14);
            assert!(t1.dot(n).abs() < 1e-14 && t2.dot(n).abs() < 1e-14);
            assert!((t1.cross(t2) - n).length() < 1e-14);
        }
    }

    #[test]
    fn head_on_impulse_matches_thesis_formula_and_conserves_momentum() {
        // A (above, moving down) hits B (below, moving up) at its centre:
        // with e = 1 the velocities exchange along the normal (equal masses).
        let mut bodies = vec![
            body(1.0, DVec3::new(0.0, 0.0, -2.0)),
            body(1.0, DVec3::new(0.0, 0.0, 1.0)),
        ];
        let mut c = contact(0, 1, DVec3::new(0.0, 0.0, -0.5), DVec3::new(0.0, 0.0, 0.5), 0.0);
        c.restitution = 1.0;
        c.friction = 0.0;
        let mut cs = [c];
        prepare(&mut cs[0], &bodies);
        assert!(
            (cs[0].normal_mass - 0.5).abs() < 1e-15,
            "1/(1/ma + 1/mb) for central impact"
        );
        let p0 = bodies[0].v + bodies[1].v;
        let h = 1.0 / 60.0;
        resolve_collisions(&mut cs, &mut bodies, &[DVec3::ZERO; 2], &params(), h, h);
        assert!((bodies[0].v - DVec3::new(0.0, 0.0, 1.0)).length() < 1e-12);
        assert!((bodies[1].v - DVec3::new(0.0, 0.0, -2.0)).length() < 1e-12);
        assert!((bodies[0].v + bodies[1].v - p0).length() < 1e-12);
    }

    #[test]
    fn off_centre_impulse_conserves_linear_and_angular_momentum() {
        let mut bodies = vec![
            body(0.5, DVec3::new(0.3, -0.2, -1.5)),
            body(0.25, DVec3::new(-0.1, 0.4, 0.7)),
        ];
        bodies[0].w = DVec3::new(0.2, -0.7, 0.1);
        let xa = DVec3::new(0.1, 0.2, 1.0);
        let xb = DVec3::new(-0.2, 0.1, -0.3);
        let point = DVec3::new(0.15, 0.05, 0.4);
        let mut c = contact(0, 1, point - xa, point - xb, 0.0);
        c.normal = DVec3::new(0.2, -0.1, 1.0).normalize();
        c.restitution = 0.6;
        let mut cs = [c];
        prepare(&mut cs[0], &bodies);
        let momentum = |bs: &[SolverBody]| {
            let mass = |b: &SolverBody| 1.0 / b.inv_mass;
            let inertia = |b: &SolverBody| b.inv_inertia.inverse();
            let p = bs[0].v * mass(&bs[0]) + bs[1].v * mass(&bs[1]);
            let l = xa.cross(bs[0].v * mass(&bs[0]))
                + inertia(&bs[0]) * bs[0].w
                + xb.cross(bs[1].v * mass(&bs[1]))
                + inertia(&bs[1]) * bs[1].w;
            let e = 0.5 * (mass(&bs[0]) * bs[0].v.length_squared() + mass(&bs[1]) * bs[1].v.length_squared())
                + 0.5 * (bs[0].w.dot(inertia(&bs[0]) * bs[0].w) + bs[1].w.dot(inertia(&bs[1]) * bs[1].w));
            (p, l, e)
        };
        let (p0, l0, e0) = momentum(&bodies);
        let h = 1.0 / 60.0;
        resolve_collisions(&mut cs, &mut bodies, &[DVec3::ZERO; 2], &params(), h, h);
        solve(&mut cs, &mut bodies, h);
        let (p1, l1, e1) = momentum(&bodies);
        assert!((p1 - p0).length() < 1e-12);
        assert!((l1 - l0).length() < 1e-12);
        assert!(e1 <= e0 + 1e-12, "energy grew: {e0} -> {e1}");
    }

    #[test]
    fn resting_box_on_static_ground_needs_m_g_h_per_substep() {
        // A unit-mass box resting on 4 contacts: after gravity adds -g h, the
        // solve must remove exactly that, with impulses summing to m g h.
        let h = 1.0 / 240.0;
        let g = 9.81;
        let mut bodies = vec![body(1.0, DVec3::new(0.0, 0.0, -g * h)), body(0.0, DVec3::ZERO)];
        let mut cs: Vec<ContactConstraint> = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
            .iter()
            .map(|&(x, y)| contact(0, 1, DVec3::new(x, y, -0.5), DVec3::new(x, y, 0.0), 0.0))
            .collect();
        for c in cs.iter_mut() {
            prepare(c, &bodies);
        }
        for _ in 0..50 {
            solve(&mut cs, &mut bodies, h);
        }
        assert!(bodies[0].v.length() < 1e-9);
        assert!(bodies[0].w.length() < 1e-9);
        let total: f64 = cs.iter().map(|c| c.normal_impulse).sum();
        assert!((total - g * h).abs() < 1e-9);
        // The split among 4 coplanar contacts is not unique (the LCP matrix is
        // only semi-definite); only the total and the zero torque are physical.
        let torque: DVec3 = cs
            .iter()
            .map(|c| c.local_a.cross(DVec3::Z * c.normal_impulse))
            .sum();
        assert!(torque.length() < 1e-9);
    }

    #[test]
    fn speculative_contact_lets_the_gap_close_but_not_more() {
        // Body 1 cm above the ground falling at 10 m/s: in one step of 1/60 s it
        // would travel 16.7 cm; the speculative constraint allows 1 cm.
        let h = 1.0 / 60.0;
        let mut bodies = vec![body(1.0, DVec3::new(0.0, 0.0, -10.0)), body(0.0, DVec3::ZERO)];
        let mut cs = [contact(0, 1, DVec3::new(0.0, 0.0, -0.5), DVec3::ZERO, 0.01)];
        prepare(&mut cs[0], &bodies);
        solve(&mut cs, &mut bodies, h);
        assert!((bodies[0].v.z * h + 0.01).abs() < 1e-12, "v h = -gap");
    }

    #[test]
    fn friction_holds_below_the_cone_and_slides_on_it() {
        // A body pressed onto the ground by a unit normal impulse, sliding.
        let h = 1.0 / 60.0;
        for (mu, sticks) in [(1.0, true), (0.05, false)] {
            let vx = if sticks { 0.5 } else { 1.0 };
            let mut bodies = vec![body(1.0, DVec3::new(vx, 0.0, -1.0)), body(0.0, DVec3::ZERO)];
            bodies[0].inv_inertia_body = DVec3::ZERO; // translation only: clean test
            bodies[0].inv_inertia = DMat3::ZERO;
            let mut c = contact(0, 1, DVec3::ZERO, DVec3::ZERO, 0.0);
            c.friction = mu;
            let mut cs = [c];
            prepare(&mut cs[0], &bodies);
            for _ in 0..20 {
                solve(&mut cs, &mut bodies, h);
            }
            let t = (cs[0].tangent_impulse[0].powi(2) + cs[0].tangent_impulse[1].powi(2)).sqrt();
            if sticks {
                assert!(bodies[0].v.length() < 1e-9);
                assert!(t < mu * cs[0].normal_impulse);
            } else {
                assert!((t - mu * cs[0].normal_impulse).abs() < 1e-12, "saturated");
                assert!(
                    (bodies[0].v.x - (1.0 - mu * 1.0)).abs() < 1e-9,
                    "kinetic: dv = mu * jn / m"
                );
            }
        }
    }

    #[test]
    fn free_rotation_conserves_angular_momentum() {
        let mut b = body(1.0, DVec3::ZERO);
        b.inv_inertia_body = DVec3::new(1.0, 0.5, 0.25);
        b.inv_inertia = SolverBody::world_inverse_inertia(b.q, b.inv_inertia_body);
        b.w = DVec3::new(0.1, 2.0, 0.3);
        let l0 = b.inv_inertia.inverse() * b.w;
        let mut bodies = [b];
        for _ in 0..1000 {
            integrate_positions(&mut bodies, 1e-3);
        }
        let l1 = bodies[0].inv_inertia.inverse() * bodies[0].w;
        assert!((l1 - l0).length() < 1e-12 * l0.length().max(1.0));
    }
}
