//! Joint rows in the sub-stepped solver: each joint is a handful of scalar
//! constraint rows `J v` on its two bodies (velocity level, as contacts),
//! rebuilt at the start of every sub-step from the bodies' current poses,
//! warm-started from the last sub-step and the last step, and relaxed in
//! the same coloured passes as the contact patches.
//!
//! - *Equality rows* (the anchors coincide, the axes align, the rotation is
//!   locked, the rod keeps its length: up to six per joint) are solved
//!   together, as one block `K dl = -J v` with `K = J M^-1 J^T` factored
//!   once per sub-step (Cholesky): a lone joint is exact in one pass, and
//!   the rows of a joint never fight each other (Box2D and Jolt solve the
//!   point part of a joint as one 3x3 block the same way). A joint whose
//!   island solves its equality rows (`joint_island`) factors its own block
//!   only for the sub-steps in which one of its limits acts, for the
//!   limit's effective mass with the equality rows held (below).
//! - *Limit rows* (hinge angle, slider offset, rope length, swing cone,
//!   twist) push only (`l >= 0`) and are speculative like contacts: a limit
//!   still `C` away lets the joint approach it at `C / h` per sub-step.
//! - *Friction rows* (Coulomb friction on the joint's coordinate) are
//!   velocity rows towards 0 bounded by the friction times the sub-step.
//! - *Motor and spring rows* are soft constraints (implicit spring-damper,
//!   Erin Catto's "soft step"): for stiffness `k` and damping `c` the row
//!   solves `dl = -m' (J v + b + gamma l)` with `gamma = 1 / (h (c + h k))`,
//!   `b = k C / (c + h k)`, `m' = 1 / (K + gamma)`, stable for any gains;
//!   the impulse is bounded by the motor's force times `h`. A velocity motor
//!   is the rigid case (`gamma = 0`, `b = -target`). A ball joint's motor is
//!   three such rows about B's frame axes (its targets are kept in B's
//!   frame), relaxed one by one and then scaled together into the ball of
//!   radius `max_force h`, as a ball's friction: a torque bounded in length.
//!
//! Drift (the error left by integrating positions with velocities that only
//! satisfy `J v = 0`) is removed in the push-out pass with pseudo-velocities
//! that move the bodies and are then discarded, as for contact overlap:
//! position correction adds no energy (split impulses).
//!
//! Sign conventions: every row is `J v = lin . (vA - vB) + ang_a . wA +
//! ang_b . wB`, an impulse `l` acts as `+lin l` on A and `-lin l` on B.

use super::body::SolverBody;
use super::coloring::Shared;
use super::prefetch::prefetch;
use crate::joint::{frame_rotation, wrap_angle, JointKind, JointPose, Motor, Spring};
use tumble_collide::{DQuat, DVec3, Pose};

/// Rows of a joint: six equality slots, then the limits, motor, spring,
/// swing cone, friction and a ball motor's third row. A row keeps its slot
/// for the joint's life, so its impulse is warm-started across sub-steps
/// and steps by slot.
pub const JOINT_ROWS: usize = 15;

/// Every row slot's bit.
const ALL_SLOTS: u16 = (1 << JOINT_ROWS) - 1;

/// A ball joint's spring: three soft angular rows about the world axes, in
/// the slots its three equality rows leave free (`BALL_SPRING..BALL_SPRING
/// + 3`). Every other kind with equality rows fills these slots with them.
pub(super) const BALL_SPRING: usize = 3;
/// The last of a ball's spring rows.
pub(super) const BALL_SPRING_LAST: usize = BALL_SPRING + 2;
/// A ball's spring slots as a mask of slot bits.
pub(super) const BALL_SPRING_MASK: u16 = 0b111 << BALL_SPRING;
/// The first slot that can hold a scalar row (limit, motor, spring): a
/// ball's spring rows.
const FIRST_SCALAR: usize = BALL_SPRING;
/// The scalar row slots, in the order a pass relaxes them: springs first,
/// then the motor, the friction (which then has the last word on what the
/// motor and springs leave moving), the limits and the swing cone (hard
/// bounds last). A slot below a joint's `n_eq` is one of its equality
/// rows, not a scalar row.
pub(super) const SCALAR_SLOTS: [usize; 12] = [
    BALL_SPRING,
    BALL_SPRING + 1,
    BALL_SPRING_LAST,
    SPRING,
    MOTOR,
    BALL_MOTOR_LAST,
    FRICTION,
    FRICTION + 1,
    FRICTION_LAST,
    LOWER,
    UPPER,
    SWING,
];
pub(super) const LOWER: usize = 6;
pub(super) const UPPER: usize = 7;
pub(super) const MOTOR: usize = 8;
pub(super) const SPRING: usize = 9;
pub(super) const SWING: usize = 10;
/// Coulomb friction on the joint's coordinate: one row (hinge, slider,
/// distance joint), a velocity row towards 0 bounded by the friction, or
/// three about A's joint frame axes (ball joint) whose impulse together is
/// bounded by it in length (`FRICTION..FRICTION + 3`): a friction torque
/// of at most `f` whichever way the joint turns.
pub(super) const FRICTION: usize = 11;
/// The last of a ball's friction rows.
const FRICTION_LAST: usize = FRICTION + 2;
/// A ball joint's motor: three rows about B's joint frame axes, in the
/// slots a hinge's motor and spring take (a ball's spring has slots of its
/// own) and one more, relaxed in this order (`SCALAR_SLOTS`) and then
/// bounded together in length (`bound_ball_rows`): a torque of at most
/// the motor's force whichever way it turns.
pub(super) const BALL_MOTOR: [usize; 3] = [SPRING, MOTOR, BALL_MOTOR_LAST];
/// The last of a ball motor's rows, the slot of its own.
pub(super) const BALL_MOTOR_LAST: usize = 14;

/// Fraction of a joint's position error removed per push-out pass. The
/// push velocities are discarded after each sub-step, so a large fraction
/// costs no energy; below 1 because the correction is linearized.
pub const JOINT_PUSH_FRACTION: f64 = 0.8;

/// Angle (rad) a body may turn in a sub-step for the equality rows to be
/// fully aimed at the end of the sub-step (see `aim_equality_rows`): 0.05
/// rad is 24 rad/s at the default 480 sub-steps a second.
pub const AIM_TURN: f64 = 0.05;

/// One scalar row.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct JointRow {
    /// Linear Jacobian of A (B's is its negative).
    pub lin: DVec3,
    /// Angular Jacobian of A.
    pub ang_a: DVec3,
    /// Angular Jacobian of B.
    pub ang_b: DVec3,
    /// A's inverse inertia times `ang_a`.
    pub(super) ia: DVec3,
    /// B's inverse inertia times `ang_b`.
    pub(super) ib: DVec3,
    /// Effective mass of a scalar row, `1 / (K + gamma)`.
    mass: f64,
    /// Position error at the start of the sub-step (m or rad).
    pub(super) c: f64,
    /// Softness (soft rows: motors, springs).
    pub(super) gamma: f64,
    /// Velocity target offset: `J v + bias` is driven to 0 (equality rows).
    pub(super) bias: f64,
    pub(super) lo: f64,
    pub(super) hi: f64,
    /// Accumulated impulse of the sub-step (N s or N m s).
    pub impulse: f64,
    pub(super) push: f64,
}

impl JointRow {
    fn linear(e: DVec3, ra: DVec3, rb: DVec3, c: f64) -> JointRow {
        JointRow {
            lin: e,
            ang_a: ra.cross(e),
            ang_b: -rb.cross(e),
            c,
            ..JointRow::default()
        }
    }

    fn angular(u: DVec3, c: f64) -> JointRow {
        JointRow {
            ang_a: u,
            ang_b: -u,
            c,
            ..JointRow::default()
        }
    }

    fn negated(mut self) -> JointRow {
        self.lin = -self.lin;
        self.ang_a = -self.ang_a;
        self.ang_b = -self.ang_b;
        self
    }

    #[inline]
    fn velocity(&self, va: DVec3, wa: DVec3, vb: DVec3, wb: DVec3) -> f64 {
        self.lin.dot(va - vb) + self.ang_a.dot(wa) + self.ang_b.dot(wb)
    }
}

/// What a joint constrains, copied from its description.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointLaw {
    /// The kind.
    pub kind: JointKind,
    /// Limits of the coordinate (rad or m).
    pub limits: Option<[f64; 2]>,
    /// Ball joint: swing cone half-angle (rad).
    pub swing_limit: Option<f64>,
    /// Hinge, slider or ball motor (a ball motor's target in B's joint
    /// frame).
    pub motor: Option<Motor>,
    /// Spring-damper (distance, ball, hinge, slider joint).
    pub spring: Option<Spring>,
    /// Coulomb friction on the joint's coordinate (N m or N).
    pub friction: Option<f64>,
    /// Distance joint rest length (m).
    pub length: f64,
}

impl JointLaw {
    /// The law of a joint described by `desc` whose rest length (distance
    /// joint) is `length`: the one place a description's options reach the
    /// solver (a joint added, changed or restored from a snapshot).
    pub fn of<B>(desc: &crate::joint::JointDesc<B>, length: f64) -> JointLaw {
        JointLaw {
            kind: desc.kind,
            limits: desc.limits,
            swing_limit: desc.swing_limit,
            // A ball motor's targets from world axes at creation into B's
            // joint frame (both frames were `frame_rotation(axis)` then).
            motor: desc
                .motor
                .map(|m| m.turned(frame_rotation(desc.axis.normalize()).conjugate())),
            spring: desc.spring,
            // (A friction of 0 is no friction: no rows.)
            friction: desc.friction.filter(|&f| f > 0.0),
            length,
        }
    }

    /// Equality rows of a joint with this law (fixed by the kind and
    /// options, so an island's system keeps its shape).
    pub fn equality_rows(&self) -> usize {
        match self.kind {
            JointKind::Fixed => 6,
            JointKind::Ball => 3,
            JointKind::Hinge | JointKind::Slider => 5,
            JointKind::Distance => usize::from(self.spring.is_none() && self.limits.is_none()),
        }
    }
}

/// A joint in the solver: its two solver bodies, its frames, its law and
/// its rows.
///
/// Laid out in this order (`repr(C)`): what every pass reads (the bodies,
/// which rows are in use, then the rows from the equality rows on) first,
/// so that a pass over a joint's first rows touches adjacent cache lines.
#[derive(Debug, Clone, PartialEq)]
#[repr(C)]
pub struct JointConstraint {
    /// Solver body of A (0: immovable).
    pub a: u32,
    /// Solver body of B (0: immovable, or the world).
    pub b: u32,
    /// Bit `i`: row slot `i` is in use this sub-step.
    pub active: u16,
    /// Scalar row slots solved in the island's system (a position motor,
    /// springs: `joint_island::island_mask`).
    pub(super) island_rows: u16,
    /// The equality rows are solved with the joint's island
    /// (`joint_island`), not joint by joint.
    pub direct: bool,
    /// Equality rows in use (slots `0..n_eq`).
    pub(super) n_eq: usize,
    /// The rows, by slot.
    pub(super) rows: [JointRow; JOINT_ROWS],
    /// Per scalar row slot (from [`FIRST_SCALAR`]): `K_ee^-1 K_e,row`, the
    /// equality impulses that keep the equality rows' velocities unchanged
    /// when the row acts.
    coupling: [[f64; 6]; JOINT_ROWS - FIRST_SCALAR],
    /// Centre of mass of each side at the step's start (the world: origin).
    pub x0: [DVec3; 2],
    /// Orientation of each side at the step's start.
    pub q0: [DQuat; 2],
    /// The joint frame of each side in its body frame.
    pub local: [Pose; 2],
    /// What is constrained.
    pub law: JointLaw,
    /// Cholesky factor of the equality block (lower triangle), with the
    /// reciprocal of each pivot on the diagonal.
    chol: [[f64; 6]; 6],
    /// Centre of mass and orientation of each side at the sub-step's start.
    start: [(DVec3, DQuat); 2],
    /// The sub-step's length (s).
    h: f64,
    /// A's lever arm to its anchor as the rows were built (for the reaction).
    lever_a: DVec3,
    /// The scalar rows' effective masses with the equality rows held, and
    /// their couplings, are this sub-step's (see `hold_equality_rows`).
    pub(super) held: bool,
    /// Bit `i`: slot `i`'s impulse and push-out impulse are known to be
    /// +0 (its warm start was, or it was inactive at the last build and
    /// cleared then: nothing writes an inactive slot outside the island's
    /// rows), so neither a build nor [`JointConstraint::renew`] need
    /// write them.
    cleared: u16,
}

impl JointConstraint {
    /// Centre of mass and orientation of each side where the bodies `a` and
    /// `b` (the joint's) are now: the step's start moved by the body's
    /// displacement since (solver body 0, immovable, stays put).
    fn sides_now(&self, a: &SolverBody, b: &SolverBody) -> [(DVec3, DQuat); 2] {
        let side = |k: usize, i: u32, body: &SolverBody| {
            if i == 0 {
                (self.x0[k], self.q0[k])
            } else {
                (self.x0[k] + body.dp, body.q)
            }
        };
        [side(0, self.a, a), side(1, self.b, b)]
    }

    /// Asks the cache for the parts of the record that
    /// [`begin_joint`] reads first (its bodies, its step-start poses and
    /// frames: these lie past the rows, a few KB into the record).
    #[inline(always)]
    pub(super) fn prefetch_start(&self) {
        prefetch(self, 1);
        prefetch(&self.x0, 1);
        prefetch(&self.local, 1);
        prefetch(&self.law, 1);
    }

    /// The joint's frames where its bodies are now.
    ///
    /// # Safety
    /// No other thread writes the joint's bodies meanwhile.
    pub(super) unsafe fn pose_now(&self, bodies: &Shared<SolverBody>) -> JointPose {
        // SAFETY: the caller's promise.
        let (a, b) = unsafe { (bodies.get(self.a as usize), bodies.get(self.b as usize)) };
        let [(xa, qa), (xb, qb)] = self.sides_now(a, b);
        JointPose::new(xa, qa, &self.local[0], xb, qb, &self.local[1])
    }

    /// A joint between solver bodies `a` and `b` with their step-start
    /// poses, its frames and law, and the impulses of the last step: a
    /// blank record renewed ([`JointConstraint::renew`]).
    pub fn new(
        pair: (u32, u32),
        x0: [DVec3; 2],
        q0: [DQuat; 2],
        local: [Pose; 2],
        law: JointLaw,
        warm: &[f64; JOINT_ROWS],
    ) -> JointConstraint {
        let mut blank = JointConstraint {
            a: 0,
            b: 0,
            x0,
            q0,
            local,
            law,
            rows: [JointRow::default(); JOINT_ROWS],
            active: 0,
            n_eq: 0,
            chol: [[0.0; 6]; 6],
            coupling: [[0.0; 6]; JOINT_ROWS - FIRST_SCALAR],
            start: [(DVec3::ZERO, DQuat::IDENTITY); 2],
            h: 0.0,
            direct: false,
            island_rows: 0,
            lever_a: DVec3::ZERO,
            held: false,
            // Every slot's impulses are +0.
            cleared: ALL_SLOTS,
        };
        blank.renew(pair, x0, q0, local, law, warm);
        blank
    }

    /// This record made ready for a step of the joint these arguments
    /// describe (as [`JointConstraint::new`]), in place, whatever joint it
    /// served before, with the bits a new record gets: the joint's rows are
    /// built at its first sub-step (`build`), whose rows are then whole,
    /// and an inactive slot is read for its impulses alone, so only the
    /// impulses of slots not known to be zero are written; the equality
    /// block's factor and couplings are written (`hold_equality_rows`)
    /// before they are read in every sub-step.
    ///
    /// Why: a record is about 4 KB (fifteen row slots), and a pile of a
    /// hundred ragdolls' thousand joints built afresh every step wrote 4
    /// MB that no core's cache holds, of which a ball joint's sub-steps
    /// touch about half.
    pub fn renew(
        &mut self,
        (a, b): (u32, u32),
        x0: [DVec3; 2],
        q0: [DQuat; 2],
        local: [Pose; 2],
        law: JointLaw,
        warm: &[f64; JOINT_ROWS],
    ) {
        let zero = zero_slots(warm);
        for (i, (r, &w)) in self.rows.iter_mut().zip(warm).enumerate() {
            if (self.cleared & zero) & (1 << i) == 0 {
                r.impulse = warm_impulse(w);
                r.push = 0.0;
            }
        }
        self.cleared = zero;
        (self.a, self.b, self.x0, self.q0, self.local, self.law) = (a, b, x0, q0, local, law);
        (self.active, self.n_eq, self.direct, self.island_rows, self.held) = (0, 0, false, 0, false);
        self.start = [(DVec3::ZERO, DQuat::IDENTITY); 2];
        (self.h, self.lever_a) = (0.0, DVec3::ZERO);
    }

    /// The accumulated impulse of every row slot (0 for unused slots).
    pub fn impulses(&self) -> [f64; JOINT_ROWS] {
        let mut out = [0.0; JOINT_ROWS];
        for (i, r) in self.rows.iter().enumerate() {
            if self.active & (1 << i) != 0 {
                out[i] = r.impulse;
            }
        }
        out
    }

    /// The force (N) and torque about A's anchor (N m) the joint applied to
    /// A in the last sub-step of length `h` (world frame).
    pub fn reaction(&self, h: f64) -> (DVec3, DVec3) {
        let ra = self.lever_a;
        let (mut f, mut t) = (DVec3::ZERO, DVec3::ZERO);
        for (i, r) in self.rows.iter().enumerate() {
            if self.active & (1 << i) != 0 {
                f += r.lin * r.impulse;
                t += r.ang_a * r.impulse;
            }
        }
        (f / h, (t - ra.cross(f)) / h)
    }

    /// Builds the rows for the bodies' current poses (in place: a row
    /// keeps its accumulated impulse; an unused slot's is forgotten).
    fn build(&mut self, pose: &JointPose) {
        self.lever_a = pose.ra;
        let (active, n_eq) = rows_for(&self.law, pose, &mut self.rows);
        self.n_eq = n_eq;
        self.active = active;
        // Why not every inactive slot: the slots lie over some 40 cache
        // lines of the record, and a pile of ragdolls' joints do not fit in
        // a core's cache; a slot left inactive stays untouched.
        let inactive = !active & ALL_SLOTS;
        for i in slots(inactive & !self.cleared) {
            let slot = &mut self.rows[i];
            slot.impulse = 0.0;
            slot.push = 0.0;
        }
        // The island's own rows (`island_rows`) are written by its solve
        // whatever their state: never taken as cleared.
        self.cleared = inactive & !self.island_rows;
    }

    /// Effective masses, bounds and soft coefficients for the bodies'
    /// inverse masses; the equality block factored, unless the joint's
    /// island solves its equality rows (then `hold_equality_rows` when a
    /// scalar row first acts in the sub-step).
    fn condition(&mut self, ma: f64, ia: &glam::DMat3, mb: f64, ib: &glam::DMat3, h: f64) {
        let m_sum = ma + mb;
        for i in slots(self.active) {
            let r = &mut self.rows[i];
            r.ia = *ia * r.ang_a;
            r.ib = *ib * r.ang_b;
            r.push = 0.0;
            if i < self.n_eq {
                // Equality rows are solved as a block (the joint's or its
                // island's): unbounded, rigid, no effective mass of their own.
                (r.lo, r.hi, r.gamma, r.bias) = (f64::NEG_INFINITY, f64::INFINITY, 0.0, 0.0);
                continue;
            }
            let k = m_sum * r.lin.length_squared() + r.ang_a.dot(r.ia) + r.ang_b.dot(r.ib);
            let (lo, hi, gamma, bias) = scalar_row_law(&self.law, i, r.c, k, h);
            r.lo = lo;
            r.hi = hi;
            r.gamma = gamma;
            r.bias = bias;
            let denom = k + gamma;
            r.mass = if denom > 1e-300 && denom.is_finite() {
                1.0 / denom
            } else {
                0.0
            };
        }
        // A joint whose equality rows its island solves uses its own block
        // only for the scalar rows the island leaves to it (limits, a
        // velocity motor, friction), and a limit only when it acts: most
        // sub-steps of a ragdoll's elbows and knees need none.
        self.held = false;
        if !self.direct {
            self.hold_equality_rows(m_sum);
        }
    }

    /// The equality block `K` factored, and each scalar row's effective
    /// mass and coupling with the equality rows held, for the rows of this
    /// sub-step (`m_sum`: the two bodies' inverse masses added).
    pub(super) fn hold_equality_rows(&mut self, m_sum: f64) {
        self.held = true;
        // K = J M^-1 J^T over the equality rows, a small regularization on
        // its diagonal (a degenerate pose makes rows dependent).
        let n = self.n_eq;
        let mut k = [[0.0; 6]; 6];
        #[allow(clippy::needless_range_loop)] // (i, j) index two rows and K at once
        for i in 0..n {
            for j in 0..=i {
                let (ri, rj) = (&self.rows[i], &self.rows[j]);
                k[i][j] = m_sum * ri.lin.dot(rj.lin) + ri.ang_a.dot(rj.ia) + ri.ang_b.dot(rj.ib);
            }
        }
        let scale = (0..n).map(|i| k[i][i]).fold(0.0, f64::max);
        for (i, row) in k.iter_mut().enumerate().take(n) {
            row[i] += 1e-12 * scale + 1e-300;
        }
        self.chol = cholesky(&k, n);
        // The scalar rows act with the equality rows held (their effective
        // mass is the Schur complement K_rr - K_re K_ee^-1 K_er): a hinge
        // limit or motor on a pendulum then feels the pendulum's inertia
        // about the pivot, not only the bob's own, and converges in a pass.
        for i in FIRST_SCALAR.max(n)..JOINT_ROWS {
            if self.active & (1 << i) == 0 || n == 0 {
                continue;
            }
            if i == UPPER && self.active & (1 << LOWER) != 0 {
                // Every kind builds its upper limit as the lower limit's row
                // negated: the same effective mass and the coupling negated,
                // bit for bit (IEEE arithmetic is symmetric in sign). Checked
                // where the rows are numbers: a runaway's (NaN, for the
                // quarantine) compare unequal to themselves.
                let (lower, upper) = (&self.rows[LOWER], &self.rows[UPPER]);
                let finite = lower.ang_a.is_finite() && lower.lin.is_finite();
                debug_assert!(!finite || upper.ang_a == -lower.ang_a);
                debug_assert!(!finite || upper.lin == -lower.lin);
                self.coupling[UPPER - FIRST_SCALAR] = self.coupling[LOWER - FIRST_SCALAR].map(|c| -c);
                self.rows[UPPER].mass = self.rows[LOWER].mass;
                continue;
            }
            let r = self.rows[i];
            let mut k_er = [0.0; 6];
            for (e, x) in k_er.iter_mut().enumerate().take(n) {
                let re = &self.rows[e];
                *x = m_sum * re.lin.dot(r.lin) + re.ang_a.dot(r.ia) + re.ang_b.dot(r.ib);
            }
            let coupling = self.block_solve(k_er);
            let k_rr = m_sum * r.lin.length_squared() + r.ang_a.dot(r.ia) + r.ang_b.dot(r.ib);
            let schur = k_rr - (0..n).map(|e| k_er[e] * coupling[e]).sum::<f64>();
            let denom = schur.max(1e-12 * k_rr) + r.gamma;
            let row = &mut self.rows[i];
            self.coupling[i - FIRST_SCALAR] = coupling;
            row.mass = if denom > 1e-300 && denom.is_finite() {
                1.0 / denom
            } else {
                0.0
            };
        }
    }

    /// The targets of the equality rows for the pair's present velocities.
    ///
    /// Bodies that turn carry their anchors on arcs, so `J v = 0` alone
    /// lets a pendulum's anchor drift outwards by `w^2 r h^2 / 2` per
    /// sub-step, and projecting the velocity back onto the constraint at
    /// the next sub-step bleeds kinetic energy (9 % in 10 s for a pendulum
    /// spinning at 8 rad/s, 8 sub-steps). Each equality row instead aims
    /// at zero error at the *end* of the sub-step: its target is the error
    /// the poses advanced by the present velocities would have, less the
    /// first-order part `h J v` the row itself controls (and less the
    /// error at the start, which the push-out removes without adding
    /// energy). Re-aimed on every pass, this is a Newton iteration on the
    /// end-of-sub-step position constraint, as SHAKE solves it; the same
    /// pendulum then keeps its energy to 1e-4.
    pub(super) fn aim_equality_rows(&mut self, p: &Pair) {
        if self.n_eq == 0 {
            return;
        }
        let h = self.h;
        // Re-aiming is a fixed-point iteration whose gain grows with the
        // angle a body turns in a sub-step: fast-spinning light links of a
        // loaded chain made it diverge. Full aim up to AIM_TURN rad per
        // sub-step, none beyond twice that (the push-out alone then).
        let turn = p.wa.length().max(p.wb.length()) * h;
        let weight = (2.0 - turn / AIM_TURN).clamp(0.0, 1.0);
        if weight == 0.0 {
            for e in 0..self.n_eq {
                self.rows[e].bias = 0.0;
            }
            return;
        }
        let advance = |(x, q): (DVec3, DQuat), v: DVec3, w: DVec3, i: u32| {
            if i == 0 {
                (x, q)
            } else {
                (x + v * h, (DQuat::from_scaled_axis(w * h) * q).normalize())
            }
        };
        let (xa, qa) = advance(self.start[0], p.va, p.wa, self.a);
        let (xb, qb) = advance(self.start[1], p.vb, p.wb, self.b);
        let ahead = equality_errors(
            &self.law,
            &JointPose::new(xa, qa, &self.local[0], xb, qb, &self.local[1]),
        );
        for (r, &end) in self.rows.iter_mut().zip(&ahead).take(self.n_eq) {
            let drift = end - r.c - h * r.velocity(p.va, p.wa, p.vb, p.wb);
            r.bias = if drift.is_finite() {
                weight * drift / h
            } else {
                0.0
            };
        }
    }

    /// A ball joint's friction impulses (its three friction rows) scaled
    /// into the ball of radius `f h`, keeping their direction: isotropic
    /// Coulomb friction, a torque of at most `f` about any axis (a box
    /// bound per row would allow `sqrt 3 f` across the frame's diagonal,
    /// and so depend on how the frame was chosen). Returns the impulse each
    /// row gained (0 when within the bound, or for another kind).
    fn bound_ball_friction(&mut self, h: f64) -> [f64; 3] {
        if self.law.kind != JointKind::Ball || self.active & (1 << FRICTION) == 0 {
            return [0.0; 3];
        }
        let limit = self.law.friction.unwrap_or(0.0) * h;
        self.bound_ball_rows([FRICTION, FRICTION + 1, FRICTION_LAST], limit)
    }

    /// A ball joint's motor impulses (its three motor rows) scaled into the
    /// ball of radius `max_force h`, as [`Self::bound_ball_friction`] bounds
    /// friction: a motor torque of at most `max_force` about any axis.
    fn bound_ball_motor(&mut self, h: f64) -> [f64; 3] {
        match self.law.motor {
            Some(m) if m.is_ball() && self.law.kind == JointKind::Ball && self.active & (1 << MOTOR) != 0 => {
                self.bound_ball_rows(BALL_MOTOR, m.max_force() * h)
            }
            _ => [0.0; 3],
        }
    }

    /// The impulses of rows `slots` scaled, keeping their direction, into
    /// the ball of radius `limit` (N m s); the impulse each row gained.
    fn bound_ball_rows(&mut self, slots: [usize; 3], limit: f64) -> [f64; 3] {
        let mut change = [0.0; 3];
        let length = slots
            .iter()
            .map(|&i| self.rows[i].impulse * self.rows[i].impulse)
            .sum::<f64>()
            .sqrt();
        if length > limit {
            let scale = limit / length;
            for (&i, c) in slots.iter().zip(&mut change) {
                let r = &mut self.rows[i];
                let bounded = r.impulse * scale;
                *c = bounded - r.impulse;
                r.impulse = bounded;
            }
        }
        change
    }

    /// Adds `dl` to row `e`'s impulse (or push-out impulse).
    #[inline]
    pub(super) fn accumulate(&mut self, e: usize, dl: f64, push: bool) {
        if push {
            self.rows[e].push += dl;
        } else {
            self.rows[e].impulse += dl;
        }
    }

    /// Applies impulse `dl` on scalar row `i` with the equality impulses
    /// that keep the equality rows' velocities (`push`: to the push-out
    /// accumulators and pseudo-velocities).
    #[inline]
    fn apply_scalar(&mut self, p: &mut Pair, i: usize, dl: f64, push: bool) {
        // A limit away from its bound (most of them, most of the time)
        // stays at zero: nothing to apply.
        if dl == 0.0 {
            return;
        }
        p.apply(&self.rows[i], dl);
        for e in 0..self.n_eq {
            let de = -self.coupling[i - FIRST_SCALAR][e] * dl;
            if push {
                self.rows[e].push += de;
            } else {
                self.rows[e].impulse += de;
            }
            p.apply(&self.rows[e], de);
        }
    }

    /// Solves the equality block `K x = rhs` with the factor of this sub-step.
    fn block_solve(&self, rhs: [f64; 6]) -> [f64; 6] {
        let (n, l) = (self.n_eq, &self.chol);
        let mut y = [0.0; 6];
        for i in 0..n {
            let mut s = rhs[i];
            for j in 0..i {
                s -= l[i][j] * y[j];
            }
            y[i] = s * l[i][i];
        }
        let mut x = [0.0; 6];
        for i in (0..n).rev() {
            let mut s = y[i];
            for j in i + 1..n {
                s -= l[j][i] * x[j];
            }
            x[i] = s * l[i][i];
        }
        x.map(|v| if v.is_finite() { v } else { 0.0 })
    }
}

/// The position errors of a joint's equality rows (slots `0..n_eq`, in
/// [`rows_for`]'s order) at `pose`, without the rows: what each relax pass
/// re-aims them by (`JointConstraint::aim_equality_rows`), which needs no
/// Jacobian, limit or twist axis. [`rows_for`] takes its equality rows'
/// errors from here.
fn equality_errors(law: &JointLaw, pose: &JointPose) -> [f64; 6] {
    let mut c = [0.0; 6];
    let d = pose.pa - pose.pb;
    // Slots `at..at + 3`: the anchors coincide, along the world axes.
    let point = |c: &mut [f64; 6], at: usize| {
        for (k, e) in DVec3::AXES.into_iter().enumerate() {
            c[at + k] = d.dot(e);
        }
    };
    // Slots `at..at + 3`: the frames keep their relative rotation, about
    // the world axes.
    let locked = |c: &mut [f64; 6], at: usize| {
        let err = pose.rotation_error();
        for (k, e) in DVec3::AXES.into_iter().enumerate() {
            c[at + k] = err.dot(e);
        }
    };
    match law.kind {
        JointKind::Fixed => {
            point(&mut c, 0);
            locked(&mut c, 3);
        }
        JointKind::Ball => point(&mut c, 0),
        JointKind::Hinge => {
            point(&mut c, 0);
            // A's axis keeps perpendicular to B's two other axes.
            let ax = pose.axis_a(0);
            for (k, i) in [1, 2].into_iter().enumerate() {
                c[3 + k] = ax.dot(pose.axis_b(i));
            }
        }
        JointKind::Slider => {
            locked(&mut c, 0);
            // No offset across B's two other axes.
            for (k, i) in [1, 2].into_iter().enumerate() {
                c[3 + k] = pose.axis_b(i).dot(d);
            }
        }
        JointKind::Distance => {
            if law.spring.is_none() && law.limits.is_none() {
                c[0] = d.length() - law.length;
            }
        }
    }
    c
}

/// The rows of a joint with law `law` at `pose`, Jacobians and errors,
/// written into their slots of `rows` (each keeps its impulses); returns
/// the slots in use (bit by slot) and the number of equality rows.
fn rows_for(law: &JointLaw, pose: &JointPose, rows: &mut [JointRow; JOINT_ROWS]) -> (u16, usize) {
    let mut set = RowSet {
        rows,
        active: 0,
        n_eq: 0,
    };
    let d = pose.pa - pose.pb;
    let c = equality_errors(law, pose);

    // The twist axis: half-way between the two frames' axes (they agree
    // where the joint holds). Only rows about the joint axis need it.
    let twist_axis = || {
        let s = pose.axis_a(0) + pose.axis_b(0);
        if s.length_squared() > 1e-12 {
            s.normalize()
        } else {
            pose.axis_b(0)
        }
    };
    match law.kind {
        JointKind::Fixed => {
            set.point(pose, &c[..3]);
            set.locked(&c[3..]);
        }
        JointKind::Ball => {
            set.point(pose, &c[..3]);
            if let Some(cone) = law.swing_limit {
                // d(swing)/dt = (wA - wB) . s with s = (bx x ax) / |bx x ax|.
                let s = pose.axis_b(0).cross(pose.axis_a(0));
                if s.length_squared() > 1e-18 {
                    set.set(SWING, JointRow::angular(-s.normalize(), cone - pose.swing()));
                }
            }
            if let Some([lo, hi]) = law.limits {
                let (twist, axis) = (pose.twist(), twist_axis());
                set.set(LOWER, JointRow::angular(axis, twist - lo));
                set.set(UPPER, JointRow::angular(axis, hi - twist).negated());
            }
            if law.spring.is_some() {
                // Towards the relative rotation at creation: the rotation
                // vector's components about the world axes, as a weld's
                // angular rows, but soft (a torque `-k theta - c w`).
                let err = pose.rotation_error();
                for (k, e) in DVec3::AXES.into_iter().enumerate() {
                    set.set(BALL_SPRING + k, JointRow::angular(e, err.dot(e)));
                }
            }
            if law.friction.is_some() {
                for k in 0..3 {
                    set.set(FRICTION + k, JointRow::angular(pose.axis_a(k), 0.0));
                }
            }
            match law.motor {
                // About B's frame axes, where the targets are given: the
                // velocity rows' rates are the target's components.
                Some(Motor::AngularVelocity { .. }) => {
                    for (k, slot) in BALL_MOTOR.into_iter().enumerate() {
                        set.set(slot, JointRow::angular(pose.axis_b(k), 0.0));
                    }
                }
                Some(Motor::Orientation { target, .. }) => {
                    let err = pose.rotation_error_from(DQuat::from_scaled_axis(DVec3::from(target)));
                    for (k, slot) in BALL_MOTOR.into_iter().enumerate() {
                        let e = pose.axis_b(k);
                        set.set(slot, JointRow::angular(e, err.dot(e)));
                    }
                }
                _ => {}
            }
        }
        JointKind::Hinge => {
            set.point(pose, &c[..3]);
            // The axes stay aligned: A's axis keeps perpendicular to
            // B's two other axes; d(ax . by)/dt = (wA - wB) . (ax x by).
            let ax = pose.axis_a(0);
            for (k, i) in [1, 2].into_iter().enumerate() {
                let bi = pose.axis_b(i);
                let mut row = JointRow::angular(ax.cross(bi), c[3 + k]);
                row.ang_b = -row.ang_a;
                set.eq(row);
            }
            if law.limits.is_some() || law.motor.is_some() || law.spring.is_some() {
                let (angle, axis) = (pose.twist(), twist_axis());
                if let Some([lo, hi]) = law.limits {
                    set.set(LOWER, JointRow::angular(axis, angle - lo));
                    set.set(UPPER, JointRow::angular(axis, hi - angle).negated());
                }
                if let Some(m) = law.motor {
                    let c = match m {
                        Motor::Position { target, .. } => wrap_angle(angle - target),
                        _ => 0.0,
                    };
                    set.set(MOTOR, JointRow::angular(axis, c));
                }
                if law.spring.is_some() {
                    // Towards the angle at creation (0), the short way round.
                    set.set(SPRING, JointRow::angular(axis, wrap_angle(angle)));
                }
            }
            if law.friction.is_some() {
                set.set(FRICTION, JointRow::angular(twist_axis(), 0.0));
            }
        }
        JointKind::Slider => {
            set.locked(&c[..3]);
            // B's axes turn with B: the lever of B's rows reaches A's
            // anchor (d/dt (n . d) with n fixed in B).
            let rb = pose.rb + d;
            for (k, i) in [1, 2].into_iter().enumerate() {
                set.eq(JointRow::linear(pose.axis_b(i), pose.ra, rb, c[3 + k]));
            }
            let n = pose.axis_b(0);
            let offset = n.dot(d);
            if let Some([lo, hi]) = law.limits {
                set.set(LOWER, JointRow::linear(n, pose.ra, rb, offset - lo));
                set.set(UPPER, JointRow::linear(n, pose.ra, rb, hi - offset).negated());
            }
            if let Some(m) = law.motor {
                let c = match m {
                    Motor::Position { target, .. } => offset - target,
                    _ => 0.0,
                };
                set.set(MOTOR, JointRow::linear(n, pose.ra, rb, c));
            }
            if law.spring.is_some() {
                set.set(SPRING, JointRow::linear(n, pose.ra, rb, offset));
            }
            if law.friction.is_some() {
                set.set(FRICTION, JointRow::linear(n, pose.ra, rb, 0.0));
            }
        }
        JointKind::Distance => {
            let len = d.length();
            let n = if len > 1e-9 { d / len } else { pose.axis_b(0) };
            let along = |c: f64| JointRow::linear(n, pose.ra, pose.rb, c);
            if law.spring.is_none() && law.limits.is_none() {
                set.eq(along(c[0]));
            }
            if let Some([lo, hi]) = law.limits {
                set.set(LOWER, along(len - lo));
                set.set(UPPER, along(hi - len).negated());
            }
            if law.spring.is_some() {
                set.set(SPRING, along(len - law.length));
            }
            if law.friction.is_some() {
                set.set(FRICTION, along(0.0));
            }
        }
    }
    (set.active, set.n_eq)
}

/// A slot's impulse at the step's start from the last step's (none if it
/// was not finite).
fn warm_impulse(w: f64) -> f64 {
    if w.is_finite() {
        w
    } else {
        0.0
    }
}

/// The slots whose warm start leaves their impulse +0.
fn zero_slots(warm: &[f64; JOINT_ROWS]) -> u16 {
    (0..JOINT_ROWS)
        .filter(|&i| warm_impulse(warm[i]).to_bits() == 0)
        .fold(0, |m, i| m | 1 << i)
}

/// The rows of a joint being built, in place: equality rows fill slots
/// from 0.
struct RowSet<'a> {
    rows: &'a mut [JointRow; JOINT_ROWS],
    active: u16,
    n_eq: usize,
}

impl RowSet<'_> {
    /// Row `slot` is `row`, with the slot's accumulated impulses.
    fn set(&mut self, slot: usize, row: JointRow) {
        let r = &mut self.rows[slot];
        let (impulse, push) = (r.impulse, r.push);
        *r = row;
        r.impulse = impulse;
        r.push = push;
        self.active |= 1 << slot;
    }

    fn eq(&mut self, row: JointRow) {
        self.set(self.n_eq, row);
        self.n_eq += 1;
    }

    /// The anchors coincide: three linear rows along the world axes, with
    /// their errors `c` (`equality_errors`).
    fn point(&mut self, pose: &JointPose, c: &[f64]) {
        for (e, &c) in DVec3::AXES.into_iter().zip(c) {
            self.eq(JointRow::linear(e, pose.ra, pose.rb, c));
        }
    }

    /// The frames keep their relative rotation: three angular rows, with
    /// their errors `c` (`equality_errors`).
    fn locked(&mut self, c: &[f64]) {
        for (e, &c) in DVec3::AXES.into_iter().zip(c) {
            self.eq(JointRow::angular(e, c));
        }
    }
}

/// The slots whose bits are set in `mask`, in increasing order.
#[inline]
fn slots(mut mask: u16) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (mask != 0).then(|| {
            let i = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            i
        })
    })
}

/// The bounds, softness and bias of scalar row slot `i` (not an equality
/// row) of a joint with `law`, for the row's position error `c`, effective
/// inverse mass `k` and the sub-step `h` (`JointConstraint::condition`).
///
/// Not inlined, on purpose: inlined into `condition`'s loop over the rows,
/// the compiler computed every arm's arithmetic for every row, the equality
/// rows that skip it included, from the fields of motors and springs the
/// joint does not have, and kept at most one; some of those values were
/// subnormal, and an operation on a subnormal costs a microcode assist of
/// some 150 cycles on Intel cores (every joint of the heavy chain and the
/// ragdoll pile, every sub-step: a third of the heavy chain's step on a
/// Xeon). Called, it computes one arm, for the rows that need it.
#[inline(never)]
fn scalar_row_law(law: &JointLaw, i: usize, c: f64, k: f64, h: f64) -> (f64, f64, f64, f64) {
    let (mut lo, mut hi, mut gamma, mut bias) = (f64::NEG_INFINITY, f64::INFINITY, 0.0, 0.0);
    match i {
        // A ball's motor: bounded together (`bound_ball_rows`).
        SPRING | MOTOR | BALL_MOTOR_LAST if law.kind == JointKind::Ball => {
            let axis = BALL_MOTOR
                .iter()
                .position(|&s| s == i)
                .expect("a ball motor slot");
            match law.motor.expect("ball motor row without a motor") {
                Motor::AngularVelocity { target, .. } => bias = -target[axis],
                Motor::Orientation {
                    stiffness, damping, ..
                } => {
                    (gamma, bias) = soft(stiffness, damping, c, h, MOTOR_STIFFNESS_AT);
                }
                Motor::Velocity { .. } | Motor::Position { .. } => {}
            }
        }
        LOWER | UPPER | SWING => {
            lo = 0.0;
            // Speculative: a limit C away may be approached at C / h.
            bias = c.max(0.0) / h;
        }
        MOTOR => {
            let m = law.motor.expect("motor row without a motor");
            let f = m.max_force() * h;
            (lo, hi) = (-f, f);
            match m {
                Motor::Velocity { target, .. } => bias = -target,
                Motor::Position {
                    stiffness, damping, ..
                } => {
                    (gamma, bias) = soft(stiffness, damping, c, h, MOTOR_STIFFNESS_AT);
                }
                // (A ball's, above.)
                Motor::AngularVelocity { .. } | Motor::Orientation { .. } => {}
            }
        }
        // (Slots below `n_eq` were equality rows, above: a ball's.)
        SPRING | BALL_SPRING..=BALL_SPRING_LAST => {
            let s = law.spring.expect("spring row without a spring");
            let at = spring_at(s.stiffness, k, h);
            (gamma, bias) = soft(s.stiffness, s.damping, c, h, at);
        }
        // Held at rest up to the friction, opposed by it in motion:
        // a rigid row towards no relative motion, bounded by it
        // (MuJoCo's `frictionloss`, per degree of freedom).
        // (A ball's three rows are bounded together, by
        // `bound_ball_friction`.)
        FRICTION..=FRICTION_LAST if law.kind != JointKind::Ball => {
            let f = law.friction.expect("friction row without a friction") * h;
            (lo, hi) = (-f, f);
        }
        _ => {}
    }
    (lo, hi, gamma, bias)
}

/// Soft-constraint coefficients `(gamma, bias)` of a spring-damper of
/// stiffness `k` and damping `c` at error `err` over a sub-step `h`, its
/// stiffness acting at the error `at` of the way through the sub-step.
///
/// The impulse is `l = -h (k (err + at h J v) + c J v)` with `v` the
/// velocity at the sub-step's end (which the positions then move by), so
/// `J v + b + gamma l = 0` with `gamma = 1 / (h (c + at h k))` and `b = k
/// err / (c + at h k)`. At `at` = 1 (implicit Euler: Catto's soft step)
/// it is stable for any gains, and the stiffness damps as if `c` were
/// larger by `h k`. `gamma` is held finite (a subnormal stiffness without
/// damping gave an infinite one, and `inf * 0` a NaN that cleared a whole
/// joint island's solve) and `b` computed as `err (k / ...)` (a stiffness
/// near `f64::MAX` times an error over 1 overflowed).
fn soft(k: f64, c: f64, err: f64, h: f64, at: f64) -> (f64, f64) {
    let denom = c + at * h * k;
    if denom <= 0.0 {
        return (f64::INFINITY, 0.0);
    }
    let bias = err * (k / denom);
    (
        (1.0 / (h * denom)).min(MAX_SOFTNESS),
        if bias.is_finite() { bias } else { 0.0 },
    )
}

/// Largest `gamma` of a soft row (`soft`): beyond it the row takes no
/// impulse worth a bit of any other row's.
const MAX_SOFTNESS: f64 = 1e300;

/// Where in a sub-step a motor's PD stiffness acts (`soft`): at its end.
/// A servo may settle a little sooner than its gains say.
const MOTOR_STIFFNESS_AT: f64 = 1.0;

/// Where in a sub-step a passive spring's stiffness acts (`soft`), for a
/// row of effective inverse mass `kk` (`K`, the row's own: for a hinge the
/// bodies' inertias about their centres, which overstates the frequency).
///
/// With the positions moved by the end velocity, a stiffness taken at `at`
/// shrinks the oscillator's phase-space area by `1 / (1 + at x)` per
/// sub-step (`x = h^2 k K`, the spring's angular frequency times `h`,
/// squared): at 1 an undamped hinge spring ringing at 3 rad/s lost 9 % of
/// its swing in 9 s. At 0 (the stiffness explicit, as gravity is:
/// symplectic Euler) the spring keeps its energy, but the bodies' springs
/// together are stable only while their combined `x` stays under 4, and
/// several springs on one body add up (three collinear springs at 1.9 each
/// make 5.7). So a spring is explicit (but for [`SPRING_AT_LEAST`]) only
/// far inside that bound, `x <= EXPLICIT_SPRING` on its own (80 such
/// springs on one body stay under 4), and beyond it is Catto's soft step.
fn spring_at(k: f64, kk: f64, h: f64) -> f64 {
    let x = h * h * k * kk;
    if x <= EXPLICIT_SPRING {
        SPRING_AT_LEAST
    } else {
        1.0
    }
}

/// Largest `h^2 k K` of a spring taken explicitly (`spring_at`): 107 rad/s
/// at 480 sub-steps a second.
const EXPLICIT_SPRING: f64 = 0.05;

/// The least `at` of a spring's stiffness (`spring_at`): not 0, so that a
/// spring without damping keeps a finite `gamma`; its loss, `1 - 1 / (1 +
/// at x)` of the phase-space area per sub-step, is 2e-4 over 10 s for a
/// spring ringing at 3 rad/s (480 sub-steps a second).
const SPRING_AT_LEAST: f64 = 1e-3;

/// Cholesky factor (lower) of the leading `n x n` block of `k`, each pivot
/// stored as its reciprocal (the solves then multiply: a division has
/// several times the latency, and the pivots chain).
#[allow(clippy::needless_range_loop)] // the textbook index form reads best here
fn cholesky(k: &[[f64; 6]; 6], n: usize) -> [[f64; 6]; 6] {
    let mut l = [[0.0; 6]; 6];
    for i in 0..n {
        for j in 0..=i {
            let mut s = k[i][j];
            for p in 0..j {
                s -= l[i][p] * l[j][p];
            }
            if i == j {
                l[i][i] = 1.0 / s.max(1e-300).sqrt();
            } else {
                l[i][j] = s * l[j][j];
            }
        }
    }
    l
}

/// Velocities of a joint's two bodies, held while its rows are relaxed.
pub(super) struct Pair {
    pub va: DVec3,
    pub wa: DVec3,
    pub vb: DVec3,
    pub wb: DVec3,
    ma: f64,
    mb: f64,
}

impl Pair {
    /// The pair of velocities `[va, wa, vb, wb]` between bodies of inverse
    /// masses `[ma, mb]`.
    pub fn new([va, wa, vb, wb]: [DVec3; 4], [ma, mb]: [f64; 2]) -> Pair {
        Pair {
            va,
            wa,
            vb,
            wb,
            ma,
            mb,
        }
    }

    /// [`load`] as a method.
    ///
    /// # Safety
    /// As [`load`].
    pub unsafe fn load(j: &JointConstraint, bodies: &Shared<SolverBody>, push: bool) -> Pair {
        // SAFETY: the caller's promise.
        unsafe { load(j, bodies, push) }
    }

    /// [`store`] as a method.
    ///
    /// # Safety
    /// As [`store`].
    pub unsafe fn store(&self, j: &JointConstraint, bodies: &Shared<SolverBody>, push: bool) {
        // SAFETY: the caller's promise.
        unsafe { store(j, bodies, self, push) }
    }

    #[inline]
    pub fn apply(&mut self, r: &JointRow, l: f64) {
        self.va += r.lin * (l * self.ma);
        self.wa += r.ia * l;
        self.vb -= r.lin * (l * self.mb);
        self.wb += r.ib * l;
    }
}

/// Reads the pair's velocities (`push`: the push-out pseudo-velocities).
///
/// # Safety
/// No other thread writes bodies `a` or `b` meanwhile.
unsafe fn load(j: &JointConstraint, bodies: &Shared<SolverBody>, push: bool) -> Pair {
    // SAFETY: the caller's promise.
    let (a, b) = unsafe { (bodies.get(j.a as usize), bodies.get(j.b as usize)) };
    let (va, wa, vb, wb) = if push {
        (a.push_v, a.push_w, b.push_v, b.push_w)
    } else {
        (a.v, a.w, b.v, b.w)
    };
    Pair {
        va,
        wa,
        vb,
        wb,
        ma: a.inv_mass,
        mb: b.inv_mass,
    }
}

/// Writes the pair's velocities back to its dynamic bodies.
///
/// # Safety
/// As [`load`], and no other reference to the bodies lives.
unsafe fn store(j: &JointConstraint, bodies: &Shared<SolverBody>, p: &Pair, push: bool) {
    for (i, v, w) in [(j.a, p.va, p.wa), (j.b, p.vb, p.wb)] {
        // SAFETY: the caller's promise.
        let body = unsafe { bodies.get_mut(i as usize) };
        if body.dynamic {
            if push {
                body.push_v = v;
                body.push_w = w;
            } else {
                body.v = v;
                body.w = w;
            }
        }
    }
}

/// Start of a sub-step: the rows for the current poses, and the impulses
/// so far applied again (`warm`) or forgotten.
///
/// # Safety
/// No other thread touches bodies `a` or `b` meanwhile.
pub(super) unsafe fn begin_joint(j: &mut JointConstraint, bodies: &Shared<SolverBody>, h: f64, warm: bool) {
    // SAFETY: the caller's promise. (Only what is read here is copied, not
    // the two bodies whole: copying them was 6 % of this function's work.)
    let (a, b) = unsafe { (bodies.get(j.a as usize), bodies.get(j.b as usize)) };
    let [(xa, qa), (xb, qb)] = j.sides_now(a, b);
    let (ma, ia, mb, ib) = (a.inv_mass, a.inv_inertia, b.inv_mass, b.inv_inertia);
    let pose = JointPose::new(xa, qa, &j.local[0], xb, qb, &j.local[1]);
    j.build(&pose);
    j.condition(ma, &ia, mb, &ib, h);
    // SAFETY: the caller's promise.
    let mut p = unsafe { load(j, bodies, false) };
    if warm {
        j.bound_ball_motor(h);
        j.bound_ball_friction(h);
    }
    for i in slots(j.active) {
        let r = &mut j.rows[i];
        if warm {
            r.impulse = crate::solver::clamp_impulse(r.impulse, r.lo, r.hi);
            let l = r.impulse;
            p.apply(&j.rows[i], l);
        } else {
            r.impulse = 0.0;
        }
    }
    j.start = [(xa, qa), (xb, qb)];
    j.h = h;
    // SAFETY: the caller's promise.
    unsafe { store(j, bodies, &p, false) };
}

/// One velocity pass over the joint: the equality block, then the springs,
/// motor, friction and limits (`SCALAR_SLOTS`), each with the equality rows
/// held.
///
/// # Safety
/// As [`begin_joint`].
pub(super) unsafe fn solve_joint(j: &mut JointConstraint, bodies: &Shared<SolverBody>) {
    // Rows solved with the joint's island are not solved again here (nor
    // are the equality rows, in the slots below `n_eq`).
    let scalar = j.active & !j.island_rows & !((1u16 << j.n_eq) - 1);
    if scalar == 0 && (j.n_eq == 0 || j.direct) {
        // Nothing to solve (most joints of a ragdoll's islands, most
        // passes): the bodies are not read.
        return;
    }
    // SAFETY: the caller's promise.
    let mut p = unsafe { load(j, bodies, false) };
    if j.n_eq > 0 && !j.direct {
        j.aim_equality_rows(&p);
        let mut rhs = [0.0; 6];
        for (i, x) in rhs.iter_mut().enumerate().take(j.n_eq) {
            let r = &j.rows[i];
            *x = -r.velocity(p.va, p.wa, p.vb, p.wb) - r.bias;
        }
        let dl = j.block_solve(rhs);
        for (i, &d) in dl.iter().enumerate().take(j.n_eq) {
            j.rows[i].impulse += d;
            p.apply(&j.rows[i], d);
        }
    }
    for i in SCALAR_SLOTS.into_iter().filter(|_| scalar != 0) {
        if scalar & (1 << i) == 0 {
            continue;
        }
        let r = &j.rows[i];
        let residual = r.velocity(p.va, p.wa, p.vb, p.wb) + r.bias + r.gamma * r.impulse;
        if r.lo == 0.0 && r.impulse == 0.0 && residual >= 0.0 {
            // A limit that is not pressed stays at zero, whatever its
            // effective mass: the block need not be held for it.
            continue;
        }
        if !j.held {
            j.hold_equality_rows(p.ma + p.mb);
        }
        let r = &mut j.rows[i];
        let new = crate::solver::clamp_impulse(r.impulse - r.mass * residual, r.lo, r.hi);
        let dl = new - r.impulse;
        r.impulse = new;
        j.apply_scalar(&mut p, i, dl, false);
        if i == FRICTION_LAST {
            // A ball's friction rows, relaxed one by one, then bounded
            // together (as a contact patch's two tangent rows are).
            let change = j.bound_ball_friction(j.h);
            for (k, dl) in change.into_iter().enumerate() {
                j.apply_scalar(&mut p, FRICTION + k, dl, false);
            }
        }
        if i == BALL_MOTOR_LAST {
            // A ball motor's rows, the same way.
            let change = j.bound_ball_motor(j.h);
            for (slot, dl) in BALL_MOTOR.into_iter().zip(change) {
                j.apply_scalar(&mut p, slot, dl, false);
            }
        }
    }
    // SAFETY: the caller's promise.
    unsafe { store(j, bodies, &p, false) };
}

/// One push-out pass over the joint: pseudo-velocities that remove
/// [`JOINT_PUSH_FRACTION`] of the position error of its equality rows and
/// violated limits. Returns whether there was an error to remove.
///
/// # Safety
/// As [`begin_joint`].
pub(super) unsafe fn push_joint(j: &mut JointConstraint, bodies: &Shared<SolverBody>, inv_h: f64) -> bool {
    /// Errors below this (m or rad) are not worth another pass.
    const SLOP: f64 = 1e-9;
    let limits = j.active & !j.island_rows & ((1 << LOWER) | (1 << UPPER) | (1 << SWING));
    if limits == 0 && (j.n_eq == 0 || j.direct) {
        // Nothing to push (the bodies are not read).
        return false;
    }
    // SAFETY: the caller's promise.
    let mut p = unsafe { load(j, bodies, true) };
    let mut any = false;
    if j.n_eq > 0 && !j.direct {
        let mut rhs = [0.0; 6];
        for (i, x) in rhs.iter_mut().enumerate().take(j.n_eq) {
            let r = &j.rows[i];
            any |= r.c.abs() > SLOP;
            *x = -JOINT_PUSH_FRACTION * r.c * inv_h - r.velocity(p.va, p.wa, p.vb, p.wb);
        }
        let dl = j.block_solve(rhs);
        for (i, &d) in dl.iter().enumerate().take(j.n_eq) {
            j.rows[i].push += d;
            p.apply(&j.rows[i], d);
        }
    }
    for i in [LOWER, UPPER, SWING] {
        if j.active & (1 << i) == 0 || j.island_rows & (1 << i) != 0 {
            continue;
        }
        let r = &j.rows[i];
        if r.c >= 0.0 && r.push == 0.0 {
            continue;
        }
        any |= r.c < -SLOP;
        let target = if r.c < 0.0 {
            -JOINT_PUSH_FRACTION * r.c * inv_h
        } else {
            0.0
        };
        let jp = r.velocity(p.va, p.wa, p.vb, p.wb);
        if !j.held {
            j.hold_equality_rows(p.ma + p.mb);
        }
        let r = &mut j.rows[i];
        let new = (r.push + r.mass * (target - jp)).max(0.0);
        let dl = new - r.push;
        r.push = new;
        j.apply_scalar(&mut p, i, dl, true);
    }
    // SAFETY: the caller's promise.
    unsafe { store(j, bodies, &p, true) };
    any
}

/// The islands (`JointIsland::begin`, their gears with them), then
/// `begin_joint` over every other joint, then the other gears, in order
/// (serial).
pub fn begin_joints(
    joints: &mut [JointConstraint],
    gears: &mut [super::GearConstraint],
    islands: &mut [super::JointIsland],
    bodies: &mut [SolverBody],
    h: f64,
    warm: bool,
) {
    let bodies = Shared::new(bodies);
    let joints = Shared::new(joints);
    let gears = Shared::new(gears);
    for island in islands {
        // SAFETY: one thread.
        unsafe { island.begin(&joints, &gears, &bodies, None, h, warm) };
    }
    for k in 0..joints.len() {
        // SAFETY: one thread, one joint at a time.
        let j = unsafe { joints.get_mut(k) };
        if !j.direct {
            unsafe { begin_joint(j, &bodies, h, warm) };
        }
    }
    // SAFETY: one thread; the gears in no island's system.
    unsafe { super::gear::begin_gears(gears.range_mut(0..gears.len()), &joints, &bodies, warm) };
}

/// The islands (`JointIsland::solve`, their gears with them), then
/// `solve_joint` over every other joint, then the other gears, in order
/// (serial).
pub fn solve_joints(
    joints: &mut [JointConstraint],
    gears: &mut [super::GearConstraint],
    islands: &mut [super::JointIsland],
    bodies: &mut [SolverBody],
) {
    let bodies = Shared::new(bodies);
    let joints = Shared::new(joints);
    let gears = Shared::new(gears);
    for island in islands {
        // SAFETY: one thread.
        unsafe { island.solve(&joints, &gears, &bodies, None) };
    }
    for k in 0..joints.len() {
        // SAFETY: one thread, one joint at a time.
        let j = unsafe { joints.get_mut(k) };
        if !j.direct {
            unsafe { solve_joint(j, &bodies) };
        }
    }
    // SAFETY: one thread; the gears in no island's system.
    unsafe { super::gear::solve_gears(gears.range_mut(0..gears.len()), &bodies) };
}

/// The islands (`JointIsland::push`, their gears with them), then
/// `push_joint` over every other joint, then the other gears, in order
/// (serial); whether any pushed.
pub fn push_joints(
    joints: &mut [JointConstraint],
    gears: &mut [super::GearConstraint],
    islands: &mut [super::JointIsland],
    bodies: &mut [SolverBody],
    h: f64,
) -> bool {
    let bodies = Shared::new(bodies);
    let joints = Shared::new(joints);
    let gears = Shared::new(gears);
    let mut any = false;
    for island in islands {
        // SAFETY: one thread.
        any |= unsafe { island.push(&joints, &gears, &bodies, None, 1.0 / h) };
    }
    for k in 0..joints.len() {
        // SAFETY: one thread, one joint at a time.
        let j = unsafe { joints.get_mut(k) };
        if !j.direct {
            any |= unsafe { push_joint(j, &bodies, 1.0 / h) };
        }
    }
    // SAFETY: one thread; the gears in no island's system.
    any |= unsafe { super::gear::push_gears(gears.range_mut(0..gears.len()), &bodies, 1.0 / h) };
    any
}
