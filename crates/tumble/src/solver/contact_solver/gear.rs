//! Gears in the solver (`joint::Gear`): one scalar row over the four
//! bodies of two joints, `J = J_follower - ratio J_leader`, where each
//! joint's part is the rate of its coordinate (`JointPose::coordinate_rows`:
//! a hinge's angle, a slider's offset) on its two bodies. Built at each
//! sub-step's start from the joints' frames where the bodies are then (as
//! the joints' own rows are), relaxed after each pass over the joints and
//! contacts, and pushed with the joints' push-out towards
//! `q_follower = ratio q_leader + offset`.
//!
//! A gear whose two joints are in a joint island solved directly
//! (`joint_island`) is a row of that island's system (`direct`): relaxed
//! beside the island, a gear of a light follower (a robot's 2 mg finger
//! geared to its 5 kg body's hand) and the island's contacts undo each
//! other, the contact turning the finger as if nothing held it and the
//! gear turning it back, and the robot blew apart. In the system, the
//! finger's contact moves the hand it is geared to.
//!
//! Other gears run on one thread between two barriers, in gear order (a
//! row of four bodies fits no colour batch, two bodies a row): a robot has
//! a handful, and their cost is a few dozen operations each. Bodies that
//! appear twice (two joints on one parent, the usual gripper) are merged
//! first, so that the effective mass counts their two parts together.

use super::body::SolverBody;
use super::coloring::Shared;
use super::island_factor::SideRow;
use super::joint::{JointConstraint, JOINT_PUSH_FRACTION};
use crate::joint::{unwrap_coordinate, Gear, JointKind, JointPose};
use tumble_collide::DVec3;

/// A gear between two of the solver's joints.
#[derive(Debug, Clone, PartialEq)]
pub struct GearConstraint {
    /// The leader's and the follower's index in the solver's joints.
    pub joints: [u32; 2],
    /// Their kinds (hinge or slider).
    kinds: [JointKind; 2],
    /// What is held.
    gear: Gear,
    /// Each joint's coordinate at the last sub-step's start (the step's
    /// before the first), followed across a hinge's wrap since the gear
    /// was made.
    start: [f64; 2],
    /// The row's distinct bodies (solver indices, at most four) with its
    /// linear and angular parts on each, and the angular part through the
    /// body's inverse inertia.
    parts: Vec<Part>,
    /// `1 / (J M^-1 J^T)` (0 where the row moves nothing).
    inv_k: f64,
    /// Position error at the sub-step's start (rad or m).
    c: f64,
    /// Accumulated impulse (warm-started from the last step).
    pub impulse: f64,
    /// Accumulated push-out impulse of the sub-step.
    push: f64,
    /// The row is in its joints' island's system (`joint_island`), which
    /// begins, relaxes and pushes it; the gear passes leave it alone.
    pub direct: bool,
}

/// The row on one body.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Part {
    body: u32,
    /// The body moves under impulses; a kinematic body's part only reads
    /// its velocity (zero inverse mass, nothing applied).
    dynamic: bool,
    lin: DVec3,
    ang: DVec3,
    inv_mass: f64,
    /// `I^-1 ang`.
    ia: DVec3,
}

impl GearConstraint {
    /// A gear of solver joints `joints` (leader, follower) of `kinds`, with
    /// the coordinates at the step's start `start` (followed) and the
    /// impulse of the last step.
    pub fn new(joints: [u32; 2], kinds: [JointKind; 2], gear: Gear, start: [f64; 2], warm: f64) -> Self {
        GearConstraint {
            joints,
            kinds,
            gear,
            start,
            parts: Vec::with_capacity(4),
            inv_k: 0.0,
            c: 0.0,
            impulse: if warm.is_finite() { warm } else { 0.0 },
            push: 0.0,
            direct: false,
        }
    }

    /// The leader's and the follower's coordinates at the last sub-step's
    /// start, followed across a hinge's wrap (for the world to follow on).
    pub fn followed(&self) -> [f64; 2] {
        self.start
    }

    /// The sub-step's start: the row for the joints' poses now, the error,
    /// and (`warm`) the impulse so far applied again.
    ///
    /// # Safety
    /// No other thread touches the joints or their bodies meanwhile.
    pub(super) unsafe fn begin(
        &mut self,
        joints: &Shared<JointConstraint>,
        bodies: &Shared<SolverBody>,
        warm: bool,
    ) {
        self.parts.clear();
        let mut coordinate = [0.0; 2];
        for (k, &ji) in self.joints.iter().enumerate() {
            // SAFETY: the caller's promise (the joints are only read).
            let j = unsafe { joints.get(ji as usize) };
            // SAFETY: the caller's promise.
            let pose: JointPose = unsafe { j.pose_now(bodies) };
            // Followed from the last sub-step's start: a wheel may turn by
            // up to pi a sub-step, not only a step.
            coordinate[k] = unwrap_coordinate(self.kinds[k], self.start[k], pose.coordinate(self.kinds[k]));
            self.start[k] = coordinate[k];
            let scale = if k == 0 { -self.gear.ratio } else { 1.0 };
            for ((lin, ang), body) in pose.coordinate_rows(self.kinds[k]).into_iter().zip([j.a, j.b]) {
                // SAFETY: the caller's promise.
                let b = unsafe { bodies.get(body as usize) };
                // A kinematic body's velocity counts in the rate (a wheel
                // hinged to a turning base is measured against it; it is
                // only read); a static body's is zero.
                if !b.dynamic && !b.kinematic {
                    continue;
                }
                let (lin, ang) = (lin * scale, ang * scale);
                match self.parts.iter_mut().find(|p| p.body == body) {
                    Some(p) => {
                        p.lin += lin;
                        p.ang += ang;
                    }
                    None => self.parts.push(Part {
                        body,
                        dynamic: b.dynamic,
                        lin,
                        ang,
                        // (0 for a kinematic body, as the solver keeps it.)
                        inv_mass: b.inv_mass,
                        ia: DVec3::ZERO,
                    }),
                }
            }
        }
        let mut k = 0.0;
        for p in self.parts.iter_mut().filter(|p| p.dynamic) {
            // SAFETY: the caller's promise.
            let b = unsafe { bodies.get(p.body as usize) };
            p.ia = b.inv_inertia * p.ang;
            k += p.inv_mass * p.lin.length_squared() + p.ang.dot(p.ia);
        }
        self.inv_k = if k > 1e-300 && k.is_finite() { 1.0 / k } else { 0.0 };
        // (A ratio so large that the error overflows pushes nothing: an
        // infinite error times a zero effective mass would be NaN.)
        let c = self.gear.error(coordinate[0], coordinate[1]);
        self.c = if c.is_finite() { c } else { 0.0 };
        self.push = 0.0;
        if warm {
            // SAFETY: the caller's promise.
            unsafe { self.apply(bodies, self.impulse, false) };
        } else {
            self.impulse = 0.0;
        }
    }

    /// The row's rate over the bodies' velocities (`push`: pseudo-velocities).
    pub(super) unsafe fn rate(&self, bodies: &Shared<SolverBody>, push: bool) -> f64 {
        self.parts
            .iter()
            .map(|p| {
                // SAFETY: the caller's promise.
                let b = unsafe { bodies.get(p.body as usize) };
                let (v, w) = if push { (b.push_v, b.push_w) } else { (b.v, b.w) };
                p.lin.dot(v) + p.ang.dot(w)
            })
            .sum()
    }

    /// Applies impulse `l` along the row.
    pub(super) unsafe fn apply(&self, bodies: &Shared<SolverBody>, l: f64, push: bool) {
        for p in self.parts.iter().filter(|p| p.dynamic) {
            // SAFETY: the caller's promise.
            let b = unsafe { bodies.get_mut(p.body as usize) };
            let (dv, dw) = (p.lin * (p.inv_mass * l), p.ia * l);
            if push {
                b.push_v += dv;
                b.push_w += dw;
            } else {
                b.v += dv;
                b.w += dw;
            }
        }
    }

    /// The row on each of its bodies, as one-sided rows of an island's
    /// system (`joint_island`): (body, row on side 0).
    pub(super) fn side_rows(&self) -> impl Iterator<Item = (u32, SideRow<f64>)> + '_ {
        self.parts
            .iter()
            .filter(|p| p.dynamic)
            .map(|p| (p.body, SideRow::one_side(p.lin, p.ang, p.inv_mass, p.ia)))
    }

    /// The right-hand side of the row in its island's system: the rate to
    /// remove, or (`push`: `fraction` and `1 / h`) the push-out towards
    /// that fraction of the error over `h`; and whether there is an error
    /// to push.
    ///
    /// # Safety
    /// As [`GearConstraint::begin`].
    pub(super) unsafe fn island_rhs(
        &self,
        bodies: &Shared<SolverBody>,
        push: Option<(f64, f64)>,
    ) -> (f64, bool) {
        // SAFETY: the caller's promise.
        let rate = unsafe { self.rate(bodies, push.is_some()) };
        match push {
            None => (-rate, false),
            Some((fraction, inv_h)) => (-fraction * self.c * inv_h - rate, self.c.abs() > 1e-9),
        }
    }

    /// Adds `dl` (solved by its island) to the row's impulse (`push`: its
    /// push-out impulse) and applies it to the bodies.
    ///
    /// # Safety
    /// As [`GearConstraint::begin`].
    pub(super) unsafe fn take(&mut self, bodies: &Shared<SolverBody>, dl: f64, push: bool) {
        if push {
            self.push += dl;
        } else {
            self.impulse += dl;
        }
        // SAFETY: the caller's promise.
        unsafe { self.apply(bodies, dl, push) };
    }

    /// One velocity pass: the coordinates' rates brought to the ratio.
    ///
    /// # Safety
    /// As [`GearConstraint::begin`].
    pub(super) unsafe fn solve(&mut self, bodies: &Shared<SolverBody>) {
        // SAFETY: the caller's promise.
        unsafe {
            let dl = -self.rate(bodies, false) * self.inv_k;
            self.impulse += dl;
            self.apply(bodies, dl, false);
        }
    }

    /// One push-out pass towards [`JOINT_PUSH_FRACTION`] of the error over
    /// `h` (`inv_h`); whether there was an error to remove.
    ///
    /// # Safety
    /// As [`GearConstraint::begin`].
    pub(super) unsafe fn push(&mut self, bodies: &Shared<SolverBody>, inv_h: f64) -> bool {
        // SAFETY: the caller's promise.
        unsafe {
            let dl = (-JOINT_PUSH_FRACTION * self.c * inv_h - self.rate(bodies, true)) * self.inv_k;
            self.push += dl;
            self.apply(bodies, dl, true);
        }
        self.c.abs() > 1e-9
    }
}

/// [`GearConstraint::begin`] over the gears not in an island's system
/// (`direct`), in order (one thread).
///
/// # Safety
/// No other thread touches the gears' bodies meanwhile.
pub(crate) unsafe fn begin_gears(
    gears: &mut [GearConstraint],
    joints: &Shared<JointConstraint>,
    bodies: &Shared<SolverBody>,
    warm: bool,
) {
    for g in gears.iter_mut().filter(|g| !g.direct) {
        // SAFETY: the caller's promise.
        unsafe { g.begin(joints, bodies, warm) };
    }
}

/// [`GearConstraint::solve`] over the gears not in an island's system,
/// in order (one thread).
///
/// # Safety
/// As [`begin_gears`].
pub(crate) unsafe fn solve_gears(gears: &mut [GearConstraint], bodies: &Shared<SolverBody>) {
    for g in gears.iter_mut().filter(|g| !g.direct) {
        // SAFETY: the caller's promise.
        unsafe { g.solve(bodies) };
    }
}

/// [`GearConstraint::push`] over the gears not in an island's system, in
/// order (one thread); whether any had an error to remove.
///
/// # Safety
/// As [`begin_gears`].
pub(crate) unsafe fn push_gears(
    gears: &mut [GearConstraint],
    bodies: &Shared<SolverBody>,
    inv_h: f64,
) -> bool {
    let mut any = false;
    for g in gears.iter_mut().filter(|g| !g.direct) {
        // SAFETY: the caller's promise.
        any |= unsafe { g.push(bodies, inv_h) };
    }
    any
}
