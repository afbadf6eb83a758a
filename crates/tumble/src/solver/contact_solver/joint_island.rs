//! Joint islands solved directly: the equality rows of a group of joints
//! linked through shared bodies (a chain, a ragdoll, a robot) as one linear
//! system `K dl = rhs`, `K = J M^-1 J^T`, factored once per sub-step.
//!
//! Relaxing joint by joint (Gauss-Seidel) carries a load along a chain one
//! link per pass: a heavy weight on light links stretches the chain (a
//! 1:100 mass ratio pulls a 20-link rope apart within a second). Solved as
//! one system the chain is exact in every pass whatever the mass ratio (the
//! maximal-coordinate answer of Baraff's "Linear-time dynamics using
//! Lagrange multipliers", 1996).
//!
//! A joint's position motor and spring join its equality rows in the
//! system (soft rows: `K + gamma` on the diagonal): the motors of a robot
//! arm hold against each other through the chain, which a pass per joint
//! only approaches (an arm under stiff PD motors oscillated about its
//! targets with 2 iterations). A motor that would exceed its force is held
//! at it and the system re-solved around it (`hold_at_bounds`). Velocity
//! motors (rigid rows) stay with the pass per joint (`island_mask`).
//!
//! `K` is sparse: rows of two joints couple only when the joints share a
//! dynamic body. With the joints ordered breadth-first through the island,
//! a row couples only with rows a few joints back, so `K` has a narrow
//! *profile* (skyline) and its Cholesky factor keeps it: a chain costs
//! O(rows x block^2), not O(rows^3). Islands whose profile would be too
//! large for a sub-step budget stay with the joint-by-joint passes. `K`
//! is assembled only where it is not zero, block by block over the pairs of
//! joints that share a dynamic body (found with the island's shape, which
//! is kept from step to step while its joints and bodies stay the same:
//! `keep_joint_islands`), and an island's joints are begun, relaxed and
//! pushed together (their limits after the system), so that a thread works
//! through one island's rows at a time.
//!
//! An island's joints with equality rows form a tree: a joint that closes
//! a loop (a rope bridge's second anchor, a net's cross links, a door's
//! second hinge) is left out of it and relaxed beside it in its colour, as
//! a joint of no island is (`spanning_tree`). A loop's rows can depend on each other
//! (a taut chain between two fixed points has one row along it too many, a
//! net's in-plane rows outnumber its bodies' in-plane freedoms), and `K`
//! is then singular or nearly so: solved directly, any error in the
//! right-hand side (the push-out's targets, the aim) became an impulse
//! without bound. A tree's rows never depend on each other.
//!
//! Consecutive islands of the same shape (the same joints between the same
//! kinds of bodies: a pile of ragdolls) without motors share one unit and
//! are factored and solved four at a time, one per SIMD lane
//! (`island_factor`), and relaxed on their bodies gathered as lane sets
//! (`island_lanes`), with the bits each would get alone.
//!
//! A contact patch between two bodies of one island (a loop the contact
//! closes) is the island's own: begun, relaxed and pushed with its system
//! (`island_contacts`), in its island's lane.
//!
//! A gear between two joints (`gear`) links their islands into one, and
//! its row, on up to four bodies, is one of the system's last rows (the
//! unit then has one lane): a light follower (a robot's 2 mg finger geared
//! to its hand) is then held by the whole chain, contacts included.

use super::body::SolverBody;
use super::coloring::Shared;
use super::constraint::{SolverParams, BLOCK_POINTS};
use super::gear::GearConstraint;
use super::island_contacts::{OwnedPatch, PatchArrays, LIGHTEST_OWNER};
use super::island_factor::{Coupling, Factor, Profile, SideRow, REACH_JOINTS};
use super::island_lanes::UnitBodies;
use super::joint::{
    begin_joint, push_joint, solve_joint, JointConstraint, JointRow, Pair, BALL_SPRING, BALL_SPRING_LAST,
    BALL_SPRING_MASK, JOINT_PUSH_FRACTION, LOWER, MOTOR, SPRING, SWING, UPPER,
};
use super::lanes::{Lane, LANES};
use super::passes::{begin_patch, friction_patch, solve_owned_normals, OwnedPass};
use crate::joint::{JointKind, Motor};

/// Largest ratio of the heaviest to the lightest body of an island whose
/// equality rows are aimed at the end of the sub-step.
pub const AIM_MASS_RATIO: f64 = 4.0;

/// Largest factor (stored profile entries) an island may have; beyond it
/// the island is relaxed joint by joint. 200,000 entries is about a
/// millisecond per factorization on one core.
pub const MAX_PROFILE: usize = 200_000;

/// Largest work of the forward substitutions of an island's owned patches
/// in a sub-step, in factor entries: each owned point's column of `V =
/// L^-1 W` is a substitution over the profile from the first row on the
/// patch's bodies to the end (and its later passes read as many rows). The
/// patches between two of an island's bodies are owned whatever they cost
/// (`island_contacts`: beside the island they add energy); an island whose
/// patches on immovable bodies would cost more than what those leave owns
/// the cheapest of them that fit (`own_patches`), the others solved beside
/// it as plain patches. `MAX_PROFILE` bounds the factor but not this: a 30
/// x 30 net of ball joints lying on a box, one island of 2,697 rows, owned
/// up to 3,384 points a sub-step, 313 million entries (132 ms a step; 38
/// within this budget, 75 with its nodes' patches on each other owned
/// beyond it). A ragdoll owns at most 32,000 in the ragdoll pile, NAO with
/// self-collision 385,000 (docs/pipeline.md, 2026-12-04, night).
pub const MAX_OWNED_SUBSTITUTION: usize = 5 * MAX_PROFILE;

/// A contact patch a joint island may own (`own_patches`): on a dynamic
/// body and another body, dynamic or immovable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OwnableContact {
    /// The patch (index into the step's patches).
    pub patch: u32,
    /// Its dynamic body (solver index).
    pub body: u32,
    /// Its other body (solver index): dynamic, static or kinematic.
    pub other: u32,
    /// Its contact points (between two of an island's bodies any number,
    /// owned in blocks of up to [`BLOCK_POINTS`]; on an immovable body at
    /// most that many are owned).
    pub points: u32,
}

/// One to four islands of joints of the same shape whose equality rows are
/// solved together, each island in its own lane.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct JointIsland {
    /// Per lane, the island's joints (indices into the solver's joint
    /// array), in the order of the shape (breadth-first, leaves first).
    lanes: Vec<Vec<u32>>,
    /// The system's shape, which the lanes share.
    profile: Profile,
    /// Whether the system has scalar rows (motors, springs): one lane only.
    single: bool,
    /// Whether a row of the system has a force bound (a position motor's
    /// finite `max_force`), held by [`JointIsland::hold_at_bounds`].
    bounded: bool,
    /// Per lane: the equality rows are aimed at the end of the sub-step
    /// (see `JointConstraint::aim_equality_rows`): only where the island's
    /// masses are within [`AIM_MASS_RATIO`] of each other.
    aim: Vec<bool>,
    /// The factor of a unit of one lane.
    factor: Factor<f64>,
    /// The factors of a unit of more lanes.
    factor_lanes: Factor<Lane>,
    /// A unit of one lane: the rows of its system by side (reused between
    /// sub-steps).
    rows: Vec<SideRow<f64>>,
    /// A unit of more lanes: the same, a lane set per row.
    rows_lanes: Vec<SideRow<Lane>>,
    /// The right-hand side of each lane's system, row by row with the
    /// lanes of a row side by side (reused between passes).
    rhs: Vec<f64>,
    /// The same, a lane set per row.
    rhs_lanes: Vec<Lane>,
    /// The rows the owned points' columns solved together can reach
    /// (`solve_columns`; reused).
    reach_runs: Vec<(usize, usize)>,
    /// Contact patches between two bodies of one of the unit's islands,
    /// solved with its system in its lane.
    owned: Vec<OwnedPatch>,
    /// With owned patches: each row's two solver bodies.
    row_bodies: Vec<[u32; 2]>,
    /// `1 / h` of the sub-step (the owned patches' speculative bias).
    inv_h: f64,
    /// Gears between the island's joints (indices into the solver's
    /// gears), the system's last rows in this order (one lane).
    gears: Vec<u32>,
    /// Per lane, the mass of the island's heaviest body (kg): patches on
    /// a body lighter than [`LIGHTEST_OWNER`] of it are not owned.
    heaviest: Vec<f64>,
    /// Per sub-step, each gear's row on each of its bodies: (row of the
    /// system, body, the row on that body as side 0).
    gear_sides: Vec<(usize, u32, SideRow<f64>)>,
    /// A unit of more lanes: its bodies as lane sets, for its passes.
    unit_bodies: UnitBodies,
}

impl JointIsland {
    /// Rows of one lane's system.
    pub fn rows(&self) -> usize {
        self.profile.rows()
    }

    /// Islands in this unit (lanes in use).
    pub fn lanes(&self) -> usize {
        self.lanes.len()
    }

    /// Patches owned by this unit (indices into the solver's patch array).
    pub fn owned_patches(&self) -> impl Iterator<Item = u32> + '_ {
        self.owned.iter().map(|o| o.patch)
    }

    /// Renumbers the owned patches (`new_index` of each old index), once
    /// the patch array is laid out.
    pub fn renumber_patches(&mut self, new_index: impl Fn(u32) -> u32) {
        for o in &mut self.owned {
            o.patch = new_index(o.patch);
        }
    }

    /// The start of a sub-step for the islands' joints (`begin_joint`,
    /// joint by joint in the shape's order) and owned patches
    /// (`begin_patch`), then `K` factored (while the rows just built are
    /// still in the cache) and the owned patches coupled to it.
    ///
    /// # Safety
    /// The islands' joints, owned patches and bodies are this thread's
    /// alone meanwhile; `patches` is given when patches are owned.
    pub(super) unsafe fn begin(
        &mut self,
        joints: &Shared<JointConstraint>,
        gears: &Shared<GearConstraint>,
        bodies: &Shared<SolverBody>,
        patches: Option<&PatchArrays>,
        h: f64,
        warm: bool,
    ) {
        for lane in &self.lanes {
            for (k, &ji) in lane.iter().enumerate() {
                if let Some(&next) = lane.get(k + 1) {
                    // SAFETY: the caller's promise.
                    unsafe { joints.get(next as usize) }.prefetch_start();
                }
                // SAFETY: the caller's promise.
                unsafe { begin_joint(joints.get_mut(ji as usize), bodies, h, warm) };
            }
        }
        for &g in &self.gears {
            // SAFETY: the caller's promise (the island's gears are its own).
            unsafe { gears.get_mut(g as usize).begin(joints, bodies, warm) };
        }
        self.inv_h = 1.0 / h;
        let patches = patches.filter(|_| !self.owned.is_empty());
        if let Some(c) = patches {
            for o in self.owned.iter().filter(|o| o.leads()) {
                // SAFETY: the caller's promise.
                unsafe {
                    let m = c.manifolds.get_mut(o.patch as usize);
                    begin_patch(m, c.points.range_mut(m.range()), bodies, warm);
                }
            }
        }
        self.factor(joints, gears, bodies);
        if let Some(c) = patches {
            // SAFETY (all accesses): the caller's promise.
            let patch = |o: &OwnedPatch| unsafe {
                let m = c.manifolds.get(o.patch as usize);
                (m, &*c.points.range_mut(o.points_in(m.range())))
            };
            let n = self.rows();
            let single = self.lanes.len() == 1;
            let (rows, rows_lanes, row_bodies) = (&self.rows, &self.rows_lanes, &self.row_bodies);
            let (joints, gear_sides) = (&self.profile.offsets, &self.gear_sides);
            for o in &mut self.owned {
                let (m, pts) = patch(o);
                let lane = o.lane;
                let sides = &row_bodies[lane * n..(lane + 1) * n];
                if single {
                    let side = |r: usize, s| rows[r].side(s);
                    o.couple(m, pts, n, side, sides, joints, gear_sides);
                } else {
                    let side = |r: usize, s| rows_lanes[r].side_lane(lane, s);
                    o.couple(m, pts, n, side, sides, joints, gear_sides);
                }
            }
            self.solve_responses();
            for o in &mut self.owned {
                let (m, pts) = patch(o);
                o.finish(m, pts);
            }
        }
    }

    /// `V = L^-1 W` for the owned patches' points (`island_contacts`): in a unit of one lane,
    /// four points a solve, one a lane (`Factor::solve` on lanes: NAO's hands
    /// own 200-390 points a sub-step, a solve each took 28 % of its step);
    /// in a unit of more, the lanes' points taken side by side, a lane set
    /// per solve (a lane with no point left solves zeros). Either way each
    /// point gets the bits a solve of its own gives it.
    fn solve_responses(&mut self) {
        if self.lanes.len() == 1 {
            // (owned patch, point), in patch order, up to four at a time.
            let mut four = [None; LANES];
            let mut filled = 0;
            for k in 0..self.owned.len() {
                for i in 0..self.owned[k].points() {
                    four[filled] = Some((k, i));
                    filled += 1;
                    if filled == LANES {
                        self.solve_columns(four);
                        four = [None; LANES];
                        filled = 0;
                    }
                }
            }
            if filled > 0 {
                self.solve_columns(four);
            }
            return;
        }
        // Each lane's points in patch order: (owned patch, point).
        let mut queue: [Vec<(usize, usize)>; LANES] = Default::default();
        for (k, o) in self.owned.iter().enumerate() {
            queue[o.lane].extend((0..o.points()).map(|i| (k, i)));
        }
        let rounds = queue.iter().map(Vec::len).max().unwrap_or(0);
        for round in 0..rounds {
            self.solve_columns(std::array::from_fn(|l| queue[l].get(round).copied()));
        }
    }

    /// The responses of up to four owned points `(patch, point)`, one a
    /// lane, solved at once in place: with the factor of a unit of one lane
    /// (four points of its island), or with each lane's own factor (a point
    /// of each lane's island). A lane without a point solves zeros.
    fn solve_columns(&mut self, points: [Option<(usize, usize)>; LANES]) {
        let n = self.rows();
        let mut x = std::mem::take(&mut self.rhs_lanes);
        x.clear();
        let columns: [Option<&[f64]>; LANES] = points.map(|p| p.map(|(k, i)| self.owned[k].response(i)));
        // Rows before the first on any point's body are zero in every column
        // (and stay zero, so they are neither read nor written back).
        let from = points
            .iter()
            .flatten()
            .map(|&(k, _)| self.owned[k].first_row())
            .min()
            .unwrap_or(n);
        x.resize(from, Lane::splat(0.0));
        x.extend((from..n).map(|r| Lane::new(std::array::from_fn(|l| columns[l].map_or(0.0, |c| c[r])))));
        // Only the rows some point's column can reach are worked out (in
        // every lane: a lane's rows that only another lane's point reaches
        // come out as its exact zeros); the others stay zero.
        let mut runs = std::mem::take(&mut self.reach_runs);
        let reach = points
            .iter()
            .flatten()
            .try_fold(0, |all, &(k, _)| Some(all | self.owned[k].reach()?));
        match reach {
            Some(joints) => self.profile.rows_of(joints, &mut runs),
            None => {
                runs.clear();
                runs.push((from, n));
            }
        }
        if self.lanes.len() == 1 {
            self.factor.forward_runs(&self.profile, &mut x, &runs);
        } else {
            self.factor_lanes.forward_runs(&self.profile, &mut x, &runs);
        }
        for (l, point) in points.into_iter().enumerate() {
            if let Some((k, i)) = point {
                let u = self.owned[k].response_mut(i);
                for &(from, to) in &runs {
                    let u = &mut u[from..to];
                    for (u, x) in u.iter_mut().zip(&x[from..to]) {
                        *u = x.as_array()[l];
                    }
                    clear_non_finite(u);
                }
            }
        }
        self.rhs_lanes = x;
        self.reach_runs = runs;
    }

    /// One velocity pass: the owned patches' friction, the equality rows
    /// (and position motors and springs) together with the owned patches'
    /// normal rows, then each joint's velocity motor and limits
    /// (`solve_joint`) in the shape's order.
    ///
    /// # Safety
    /// As [`JointIsland::begin`].
    pub(super) unsafe fn solve(
        &mut self,
        joints: &Shared<JointConstraint>,
        gears: &Shared<GearConstraint>,
        bodies: &Shared<SolverBody>,
        patches: Option<&PatchArrays>,
    ) {
        // SAFETY: the caller's promise.
        unsafe {
            if let Some(c) = patches {
                for o in self.owned.iter().filter(|o| o.leads()) {
                    let m = c.manifolds.get_mut(o.patch as usize);
                    friction_patch(m, c.points.range_mut(m.range()), bodies);
                }
            }
            let pass = OwnedPass::Velocity { inv_h: self.inv_h };
            self.relax(joints, gears, bodies, patches.map(|c| (c, pass)), None);
            for lane in &self.lanes {
                for &ji in lane {
                    solve_joint(joints.get_mut(ji as usize), bodies);
                }
            }
        }
    }

    /// One push-out pass, as [`JointIsland::solve`] (`push_joint` for the
    /// limits); whether any row had an error to remove.
    ///
    /// # Safety
    /// As [`JointIsland::begin`].
    pub(super) unsafe fn push(
        &mut self,
        joints: &Shared<JointConstraint>,
        gears: &Shared<GearConstraint>,
        bodies: &Shared<SolverBody>,
        patches: Option<(&PatchArrays, &SolverParams)>,
        inv_h: f64,
    ) -> bool {
        // SAFETY: the caller's promise.
        unsafe {
            let mut any = self.relax(
                joints,
                gears,
                bodies,
                patches.map(|(c, params)| (c, OwnedPass::Push { params, inv_h })),
                Some((JOINT_PUSH_FRACTION, inv_h)),
            );
            for lane in &self.lanes {
                for &ji in lane {
                    any |= push_joint(joints.get_mut(ji as usize), bodies, inv_h);
                }
            }
            any
        }
    }

    /// Factors `K` of each lane for the joints' rows of this sub-step
    /// (after their `begin_joint`) and the gears' (after their `begin`).
    #[allow(clippy::needless_range_loop)] // the shape's joint k of every lane at once
    fn factor(
        &mut self,
        joints: &Shared<JointConstraint>,
        gears: &Shared<GearConstraint>,
        bodies: &Shared<SolverBody>,
    ) {
        // Each row as its two sides. Immovable bodies have zero inverse
        // mass and inertia, so they add nothing.
        // SAFETY (all accesses): the islands' joints, gears and bodies are
        // this thread's alone during the call (islands share no dynamic body).
        if !self.owned.is_empty() || !self.gears.is_empty() {
            self.row_bodies.clear();
            for lane in &self.lanes {
                for &ji in lane {
                    let j = unsafe { joints.get(ji as usize) };
                    self.row_bodies.extend(island_slots(j).map(|_| [j.a, j.b]));
                }
            }
            self.row_bodies.extend(self.gears.iter().map(|_| [NO_BODY; 2]));
        }
        if self.lanes.len() > 1 {
            // Each row's lane set gathered straight from the lanes' joints:
            // the islands of a unit share their shape (the same joints in
            // the same order, each with its equality rows alone in the
            // system). Lanes beyond the islands repeat the last (and are
            // never read).
            let last = self.lanes.len() - 1;
            let lanes = &self.lanes;
            self.rows_lanes.clear();
            for k in 0..lanes[0].len() {
                let js: [&JointConstraint; LANES] =
                    std::array::from_fn(|l| unsafe { joints.get(lanes[l.min(last)][k] as usize) });
                debug_assert!(js.iter().all(|j| j.n_eq == js[0].n_eq && j.island_rows == 0));
                let ma = Lane::new(js.map(|j| unsafe { bodies.get(j.a as usize).inv_mass }));
                let mb = Lane::new(js.map(|j| unsafe { bodies.get(j.b as usize).inv_mass }));
                for slot in island_slots(js[0]) {
                    self.rows_lanes
                        .push(SideRow::new_lanes(js.map(|j| &j.rows[slot]), ma, mb));
                }
            }
            debug_assert_eq!(self.rows_lanes.len(), self.rows());
            self.factor_lanes.factor(&self.profile, &self.rows_lanes);
            return;
        }
        self.rows.clear();
        for &ji in &self.lanes[0] {
            let j = unsafe { joints.get(ji as usize) };
            let (ma, mb) = unsafe {
                (
                    bodies.get(j.a as usize).inv_mass,
                    bodies.get(j.b as usize).inv_mass,
                )
            };
            for slot in island_slots(j) {
                self.rows.push(SideRow::new(&j.rows[slot], ma, mb));
            }
        }
        let joint_rows = self.rows.len();
        // A gear's row is on up to four bodies: a placeholder here, its
        // parts in `gear_sides`.
        self.gear_sides.clear();
        for (e, &g) in self.gears.iter().enumerate() {
            let g = unsafe { gears.get(g as usize) };
            self.rows.push(SideRow::default());
            self.gear_sides
                .extend(g.side_rows().map(|(body, side)| (joint_rows + e, body, side)));
        }
        let (profile, rows, row_bodies, gear_sides) =
            (&self.profile, &self.rows, &self.row_bodies, &self.gear_sides);
        self.factor.factor_adding(profile, rows, |k| {
            add_gear_entries(k, profile, rows, row_bodies, gear_sides, joint_rows)
        });
    }

    /// One pass over the islands' equality rows: velocities (the rows
    /// aimed as in `JointConstraint::aim_equality_rows`), or with `push`
    /// the push-out pseudo-velocities towards `fraction` of each row's
    /// position error over `h`; the owned patches' normal rows with them
    /// (`island_contacts`; `patches` carries the pass they are solved in,
    /// which matches `push`). Returns whether any row had an error to push.
    ///
    /// # Safety
    /// The islands' joints, owned patches and bodies are this thread's
    /// alone meanwhile.
    unsafe fn relax(
        &mut self,
        joints: &Shared<JointConstraint>,
        gears: &Shared<GearConstraint>,
        bodies: &Shared<SolverBody>,
        patches: Option<(&PatchArrays, OwnedPass)>,
        push: Option<(f64, f64)>,
    ) -> bool {
        let n = self.rows();
        // Row i of lane l at i * stride + l: a unit of more lanes reads
        // each row's lanes as one lane set (lanes without an island hold 0).
        let stride = if self.lanes.len() == 1 { 1 } else { LANES };
        let mut rhs = std::mem::take(&mut self.rhs);
        rhs.clear();
        rhs.resize(n * stride, 0.0);
        let mut any = false;
        // A unit of more lanes: its bodies as lane sets (`island_lanes`).
        let in_lanes = self.lanes.len() > 1 && self.unit_bodies.is_built();
        if in_lanes {
            // SAFETY: the caller's promise.
            unsafe { any |= self.rhs_in_lanes(joints, bodies, push, &mut rhs) };
        }
        for (l, lane) in self.lanes.iter().enumerate().filter(|_| !in_lanes) {
            for (&ji, &at) in lane.iter().zip(&self.profile.offsets) {
                // SAFETY: the caller's promise.
                let j = unsafe { joints.get_mut(ji as usize) };
                let p = unsafe { Pair::load(j, bodies, push.is_some()) };
                if push.is_none() && self.aim[l] {
                    j.aim_equality_rows(&p);
                }
                for (e, slot) in island_slots(j).enumerate() {
                    let r = &j.rows[slot];
                    let jv = r.lin.dot(p.va - p.vb) + r.ang_a.dot(p.wa) + r.ang_b.dot(p.wb);
                    rhs[(at + e) * stride + l] = row_rhs(r, jv, push, is_soft(j, slot), &mut any);
                }
            }
        }
        // The gears' rows, last (a unit with gears has one lane).
        debug_assert!(self.gears.is_empty() || self.lanes.len() == 1);
        let joint_rows = n - self.gears.len();
        for (e, &g) in self.gears.iter().enumerate() {
            // SAFETY: the caller's promise.
            let (r, pushes) = unsafe { gears.get(g as usize).island_rhs(bodies, push) };
            rhs[joint_rows + e] = r;
            any |= pushes;
        }
        let patches = patches.filter(|_| !self.owned.is_empty());
        if patches.is_none() {
            self.substitute(&mut rhs, true, true);
            clear_non_finite(&mut rhs);
            if self.bounded {
                self.hold_at_bounds(joints, &mut rhs, push.is_some());
            }
        } else {
            // The owned patches work on z = L^-1 rhs (`island_contacts`).
            self.substitute(&mut rhs, true, false);
            clear_non_finite(&mut rhs);
            if self.bounded {
                // Bounds hold on the impulses: to x and back (one lane).
                self.factor.backward(&self.profile, &mut rhs);
                clear_non_finite(&mut rhs);
                self.hold_at_bounds(joints, &mut rhs, push.is_some());
                self.factor.multiply_transposed(&self.profile, &mut rhs);
            }
        }
        if let Some((c, pass)) = patches {
            for o in &self.owned {
                // SAFETY: the caller's promise.
                let (d, pushed) = unsafe {
                    let m = c.manifolds.get(o.patch as usize);
                    let coupled = o.coupled(&rhs, stride);
                    solve_owned_normals(
                        m,
                        c.points.range_mut(o.points_in(m.range())),
                        bodies,
                        o.block(),
                        &coupled,
                        pass,
                    )
                };
                any |= pushed;
                o.take_back(&d, &mut rhs, stride);
            }
            self.substitute(&mut rhs, false, true);
            clear_non_finite(&mut rhs);
        }
        if in_lanes {
            // SAFETY: the caller's promise.
            unsafe { self.apply_in_lanes(joints, bodies, push.is_some(), patches.is_some(), &rhs) };
        }
        // Apply joint by joint: each body's velocity is read and written
        // through its joints in turn.
        for (l, lane) in self.lanes.iter().enumerate().filter(|_| !in_lanes) {
            for (&ji, &at) in lane.iter().zip(&self.profile.offsets) {
                // SAFETY: the caller's promise.
                let j = unsafe { joints.get_mut(ji as usize) };
                let mut p = unsafe { Pair::load(j, bodies, push.is_some()) };
                for (e, slot) in island_slots(j).enumerate() {
                    let dl = take_impulse(j, slot, rhs[(at + e) * stride + l], push.is_some());
                    p.apply(&j.rows[slot], dl);
                }
                unsafe { p.store(j, bodies, push.is_some()) };
            }
        }
        for (e, &g) in self.gears.iter().enumerate() {
            // SAFETY: the caller's promise.
            unsafe {
                gears
                    .get_mut(g as usize)
                    .take(bodies, rhs[joint_rows + e], push.is_some())
            };
        }
        self.rhs = rhs;
        any
    }

    /// [`JointIsland::relax`]'s right-hand sides for a unit of more lanes,
    /// the rows' velocities four islands at a time (`island_lanes`), each
    /// lane's the bits of the joint-by-joint loop; whether a row had an
    /// error to push.
    ///
    /// # Safety
    /// As [`JointIsland::relax`].
    unsafe fn rhs_in_lanes(
        &mut self,
        joints: &Shared<JointConstraint>,
        bodies: &Shared<SolverBody>,
        push: Option<(f64, f64)>,
        rhs: &mut [f64],
    ) -> bool {
        let mut any = false;
        // SAFETY (all accesses): the caller's promise.
        unsafe { self.unit_bodies.gather(bodies, push.is_some()) };
        for (k, &at) in self.profile.offsets[..self.lanes[0].len()].iter().enumerate() {
            for (l, lane) in self.lanes.iter().enumerate() {
                if push.is_none() && self.aim[l] {
                    let j = unsafe { joints.get_mut(lane[k] as usize) };
                    j.aim_equality_rows(&self.unit_bodies.pair(k, l));
                }
            }
            let n_eq = unsafe { joints.get(self.lanes[0][k] as usize) }.n_eq;
            for e in 0..n_eq {
                let jv = self.unit_bodies.velocity(k, &self.rows_lanes[at + e]).to_array();
                for (l, lane) in self.lanes.iter().enumerate() {
                    let j = unsafe { joints.get(lane[k] as usize) };
                    debug_assert!(j.n_eq == n_eq && j.island_rows == 0);
                    rhs[(at + e) * LANES + l] = row_rhs(&j.rows[e], jv[l], push, false, &mut any);
                }
            }
        }
        any
    }

    /// [`JointIsland::relax`]'s impulses `x` (row by row, the lanes side
    /// by side) accumulated and applied for a unit of more lanes, four
    /// islands at a time (`island_lanes`), each lane's the bits of the
    /// joint-by-joint loop; after [`JointIsland::rhs_in_lanes`] (and the
    /// owned patches, if `patches`) in the same pass.
    ///
    /// # Safety
    /// As [`JointIsland::relax`].
    unsafe fn apply_in_lanes(
        &mut self,
        joints: &Shared<JointConstraint>,
        bodies: &Shared<SolverBody>,
        push: bool,
        patches: bool,
        x: &[f64],
    ) {
        // SAFETY (all accesses): the caller's promise.
        if patches {
            // The owned patches moved the bodies since the right-hand
            // sides read them.
            unsafe { self.unit_bodies.gather(bodies, push) };
        }
        for (k, &at) in self.profile.offsets[..self.lanes[0].len()].iter().enumerate() {
            let n_eq = unsafe { joints.get(self.lanes[0][k] as usize) }.n_eq;
            for e in 0..n_eq {
                let mut dl = [0.0; LANES];
                for (l, lane) in self.lanes.iter().enumerate() {
                    let j = unsafe { joints.get_mut(lane[k] as usize) };
                    dl[l] = take_impulse(j, e, x[(at + e) * LANES + l], push);
                }
                self.unit_bodies.apply(k, &self.rows_lanes[at + e], Lane::new(dl));
            }
        }
        unsafe { self.unit_bodies.scatter(bodies, push) };
    }

    /// The forward (`L^-1`) and/or backward (`L^-T`) substitution of
    /// [`Factor::solve`] over right-hand sides laid out row by row with the
    /// unit's lanes side by side.
    fn substitute(&mut self, x: &mut [f64], forward: bool, backward: bool) {
        if self.lanes.len() == 1 {
            if forward {
                self.factor.forward(&self.profile, x);
            }
            if backward {
                self.factor.backward(&self.profile, x);
            }
            return;
        }
        self.rhs_lanes.clear();
        self.rhs_lanes.extend(
            x.chunks_exact(LANES)
                .map(|row| Lane::new([row[0], row[1], row[2], row[3]])),
        );
        if forward {
            self.factor_lanes.forward(&self.profile, &mut self.rhs_lanes);
        }
        if backward {
            self.factor_lanes.backward(&self.profile, &mut self.rhs_lanes);
        }
        for (row, v) in x.chunks_exact_mut(LANES).zip(&self.rhs_lanes) {
            row.copy_from_slice(&v.to_array());
        }
    }

    /// `K x = rhs` for a unit of one lane, entries that are not finite
    /// cleared.
    fn solve_one(&self, x: &mut [f64]) {
        self.factor.solve(&self.profile, x);
        clear_non_finite(x);
    }
}

impl JointIsland {
    /// Rows (motors) whose solved impulse `x` would pass a bound are
    /// held at the bound and the rest of the system re-solved around them: with
    /// `u_c = K^-1 e_c` for each such row `c`, `x + sum_c u_c mu_c` with the
    /// `mu` that puts each held row on its bound (a small dense system). A
    /// plain clamp would leave the other rows' impulses computed for the
    /// unclamped motor: an arm whose wrist motors saturated blew up.
    /// (Units with bounds have one lane.)
    ///
    /// Where the rounds do not settle ([`HELD_ROUNDS`], [`MAX_HELD`]),
    /// every bounded row is held where the unbounded solve put it, clamped
    /// (Gauss-Seidel's answer for the motors, the other rows consistent
    /// with it); with more bounded rows than [`MAX_HELD`] allows, the pass
    /// changes nothing. Bailing out with the clamp alone (16 rows held at
    /// most, no row let go) had let MuJoCo's humanoid, its 21 joints' friction
    /// motors then in the system, gain 2e8 J in 10 s, and a chain of 30 such
    /// joints 54 J in its first step.
    fn hold_at_bounds(&self, joints: &Shared<JointConstraint>, x: &mut [f64], push: bool) {
        let x0 = x.to_vec();
        let column = |i: usize| {
            let mut u = vec![0.0; self.rows()];
            u[i] = 1.0;
            self.solve_one(&mut u);
            u
        };
        // Each bounded row of the system: (row, accumulated impulse, lo, hi).
        let bounded: Vec<(usize, f64, f64, f64)> = self.lanes[0]
            .iter()
            .enumerate()
            .flat_map(|(k, &ji)| {
                // SAFETY: the island's joints are this thread's (caller of relax).
                let j = unsafe { joints.get(ji as usize) };
                island_slots(j).enumerate().filter_map(move |(e, slot)| {
                    let (acc, lo, hi) = bounds(j, slot, push);
                    (lo > f64::NEG_INFINITY || hi < f64::INFINITY)
                        .then(|| (self.profile.offsets[k] + e, acc, lo, hi))
                })
            })
            .collect();
        // Rounds of an active set: hold what passes a bound, re-solve; let
        // go of a held row the others now push back inside its bounds (its
        // multiplier pulls towards the bound it is held at), and again. A
        // row never let go could end a round held at a bound the solution
        // no longer presses it against: a motor at its force pushing the
        // joint on the way it already turns (with friction rows, then
        // velocity motors towards 0, in the system, a chain slipping on
        // every joint gained energy so).
        let mut held: Vec<Held> = Vec::new();
        let mut settled = false;
        for _ in 0..HELD_ROUNDS {
            let mut changed = false;
            for &(i, acc, lo, hi) in &bounded {
                let total = acc + x[i];
                if (total > hi || total < lo) && !held.iter().any(|h| h.row == i) {
                    held.push(Held {
                        row: i,
                        target: crate::solver::clamp_impulse(total, lo, hi) - acc,
                        at_lower: total < lo,
                        fixed: lo == hi,
                        column: column(i),
                    });
                    changed = true;
                }
            }
            if held.is_empty() {
                return;
            }
            if held.len() > MAX_HELD {
                break;
            }
            let Some(mu) = solve_held(&held, &x0) else {
                break;
            };
            // The row held the wrong way hardest is let go (one a round, so
            // that the set does not swing back and forth), and the round
            // starts again, whether or not it added a row.
            let wrong = held
                .iter()
                .zip(&mu)
                .enumerate()
                .filter(|(_, (h, _))| !h.fixed)
                .map(|(k, (h, &m))| (k, if h.at_lower { -m } else { m }))
                .filter(|&(_, pull)| pull > 0.0)
                .max_by(|a, b| a.1.total_cmp(&b.1));
            if let Some((k, _)) = wrong {
                held.remove(k);
                let Some(mu) = solve_held(&held, &x0) else {
                    break;
                };
                apply_held(x, &x0, &held, &mu);
                continue;
            }
            apply_held(x, &x0, &held, &mu);
            if !changed {
                // Every held row pressed the right way, every other within
                // its bounds (checked on this same answer above).
                settled = true;
                break;
            }
        }
        if settled {
            return;
        }
        // Not settled: every bounded row held at its unbounded value, clamped.
        let all: Vec<Held> = if bounded.len() <= MAX_HELD {
            bounded
                .iter()
                .map(|&(i, acc, lo, hi)| Held {
                    row: i,
                    target: crate::solver::clamp_impulse(acc + x0[i], lo, hi) - acc,
                    at_lower: false,
                    fixed: true,
                    column: column(i),
                })
                .collect()
        } else {
            Vec::new()
        };
        match solve_held(&all, &x0).filter(|_| !all.is_empty()) {
            Some(mu) => apply_held(x, &x0, &all, &mu),
            None => x.fill(0.0),
        }
    }
}

/// A row [`JointIsland::hold_at_bounds`] holds at a bound.
struct Held {
    /// Its index in the system.
    row: usize,
    /// The change of its impulse that puts it on the bound.
    target: f64,
    /// Held at its lower bound (else its upper).
    at_lower: bool,
    /// Its bounds are one value (held whatever the multiplier's sign).
    fixed: bool,
    /// `K^-1 e_row`.
    column: Vec<f64>,
}

/// The multipliers that put every held row on its target (`solve_dense`).
fn solve_held(held: &[Held], x0: &[f64]) -> Option<Vec<f64>> {
    let targets: Vec<(usize, f64)> = held.iter().map(|h| (h.row, h.target)).collect();
    let columns: Vec<&[f64]> = held.iter().map(|h| h.column.as_slice()).collect();
    solve_dense(&targets, &columns, x0)
}

/// `x = x0 + sum_c u_c mu_c` over the held rows.
fn apply_held(x: &mut [f64], x0: &[f64], held: &[Held], mu: &[f64]) {
    x.copy_from_slice(x0);
    for (h, &mu) in held.iter().zip(mu) {
        for (xi, ui) in x.iter_mut().zip(&h.column) {
            *xi += ui * mu;
        }
    }
}

/// Most rows [`JointIsland::hold_at_bounds`] holds in one solve (a dense
/// system of that size, and a solve of the island's system per row).
const MAX_HELD: usize = 64;

/// Most rounds of [`JointIsland::hold_at_bounds`]'s active set: a row
/// held at its bound can push others past theirs (a robot whose joints
/// all slip on their friction at once).
const HELD_ROUNDS: usize = 16;

/// The `mu` with `x0[c] + sum_b u_b[c] mu_b = target_c` at every held row
/// `c` (Gaussian elimination with partial pivoting on the held block of
/// `K^-1`, which is positive definite).
#[allow(clippy::needless_range_loop)] // elimination reads best indexed
fn solve_dense(held: &[(usize, f64)], columns: &[&[f64]], x0: &[f64]) -> Option<Vec<f64>> {
    let m = held.len();
    let mut g: Vec<Vec<f64>> = (0..m)
        .map(|a| {
            let mut row: Vec<f64> = (0..m).map(|b| columns[b][held[a].0]).collect();
            row.push(held[a].1 - x0[held[a].0]);
            row
        })
        .collect();
    for col in 0..m {
        let pivot = (col..m).max_by(|&a, &b| g[a][col].abs().total_cmp(&g[b][col].abs()))?;
        g.swap(col, pivot);
        if g[col][col].abs() < 1e-300 {
            return None;
        }
        for r in col + 1..m {
            let f = g[r][col] / g[col][col];
            for c in col..=m {
                g[r][c] -= f * g[col][c];
            }
        }
    }
    let mut mu = vec![0.0; m];
    for a in (0..m).rev() {
        let s: f64 = (a + 1..m).map(|b| g[a][b] * mu[b]).sum();
        mu[a] = (g[a][m] - s) / g[a][a];
    }
    mu.iter().all(|v| v.is_finite()).then_some(mu)
}

/// Entries of a solution that are not finite (a degenerate system) set
/// to zero: no impulse rather than a NaN one.
fn clear_non_finite(x: &mut [f64]) {
    for v in x.iter_mut() {
        if !v.is_finite() {
            *v = 0.0;
        }
    }
}

/// Stands for no body in a row's pair of bodies (a gear's part is on one).
const NO_BODY: u32 = u32::MAX;

/// Adds the gears' rows to `K` (stored as `profile` lays it out): each
/// gear part (row `g`, on body `b`) against every joint row on `b` and
/// every part of the same or an earlier gear on `b` (the rows before
/// `joint_rows` are joint rows, by side, with their two bodies in
/// `row_bodies`).
fn add_gear_entries(
    k: &mut [f64],
    profile: &Profile,
    rows: &[SideRow<f64>],
    row_bodies: &[[u32; 2]],
    gear_sides: &[(usize, u32, SideRow<f64>)],
    joint_rows: usize,
) {
    for (p, (g, body, side)) in gear_sides.iter().enumerate() {
        for (i, (row, pair)) in rows[..joint_rows].iter().zip(row_bodies).enumerate() {
            for (s, &b) in pair.iter().enumerate() {
                if b == *body {
                    k[profile.at(*g, i)] += side.meets(0, row, s);
                }
            }
        }
        // Parts of one gear are on distinct bodies: a part meets only
        // itself within its gear.
        for (h, other_body, other) in &gear_sides[..=p] {
            if other_body == body {
                k[profile.at(*g, *h)] += side.meets(0, other, 0);
            }
        }
    }
}

/// A row's right-hand side in [`JointIsland::relax`], given its velocity
/// `jv`: towards its target (velocity pass), or with `push` towards
/// `fraction` of its position error over `h` (`any` set where there is an
/// error to push); a `soft` row (a motor, a spring) does not push, it only
/// keeps the push-out off the joint's free axis.
#[inline(always)]
fn row_rhs(r: &JointRow, jv: f64, push: Option<(f64, f64)>, soft: bool, any: &mut bool) -> f64 {
    match push {
        None => -jv - r.bias - r.gamma * r.impulse,
        Some(_) if soft => -jv - r.gamma * r.push,
        Some((fraction, inv_h)) => {
            *any |= r.c.abs() > 1e-9;
            -fraction * r.c * inv_h - jv
        }
    }
}

/// Impulse `x` solved for row `slot` of `j` added to its accumulated
/// impulse (or push-out impulse) within the row's bounds (re-solved by
/// `hold_at_bounds`; a last clamp for what the re-solve could not hold);
/// the change applied.
#[inline(always)]
fn take_impulse(j: &mut JointConstraint, slot: usize, x: f64, push: bool) -> f64 {
    let (acc, lo, hi) = bounds(j, slot, push);
    let dl = crate::solver::clamp_impulse(acc + x, lo, hi) - acc;
    j.accumulate(slot, dl, push);
    dl
}

/// Row `slot`'s accumulated impulse (or push-out impulse) and its bounds.
fn bounds(j: &JointConstraint, slot: usize, push: bool) -> (f64, f64, f64) {
    let r = &j.rows[slot];
    match (push, slot) {
        (false, _) => (r.impulse, r.lo, r.hi),
        (true, LOWER | UPPER | SWING) => (r.push, 0.0, f64::INFINITY),
        (true, _) => (r.push, f64::NEG_INFINITY, f64::INFINITY),
    }
}

/// The row slots of joint `j` in its island's system: its equality rows,
/// then its scalar rows the island solves (`island_mask`), in the order of
/// [`ISLAND_SCALAR_SLOTS`].
#[inline]
fn island_slots(j: &JointConstraint) -> impl Iterator<Item = usize> + use<> {
    let (n_eq, mask) = (j.n_eq, j.island_rows);
    // Most joints of an island have no scalar row in it (a ragdoll's): the
    // candidates are then not looked at, in a walk done three times a pass.
    let scalar: &'static [usize] = if mask == 0 { &[] } else { &ISLAND_SCALAR_SLOTS };
    // (`island_mask` sets a ball's spring slots on balls alone, whose
    // equality rows end below them.)
    (0..n_eq).chain(scalar.iter().copied().filter(move |&s| mask & (1 << s) != 0))
}

/// The scalar slots a joint's rows may have in its island's system, in
/// the system's order.
const ISLAND_SCALAR_SLOTS: [usize; 8] = [
    MOTOR,
    SPRING,
    BALL_SPRING,
    BALL_SPRING + 1,
    BALL_SPRING_LAST,
    LOWER,
    UPPER,
    SWING,
];

/// Whether row `slot` of `j` is soft (a motor's or a spring's): it takes
/// part in the push-out only to keep it off the joint's free axes. (A
/// ball's spring slots hold other kinds' equality rows.)
fn is_soft(j: &JointConstraint, slot: usize) -> bool {
    slot == MOTOR || slot == SPRING || (slot >= j.n_eq && BALL_SPRING_MASK & (1 << slot) != 0)
}

/// The scalar rows of `j` its island solves: a hinge's or slider's position
/// (PD) motor and the spring (soft rows: a damped arm's dampers and its servos act through the
/// whole chain's inertia). A velocity motor and the joint's friction are
/// rigid rows with bounds (a speed servo; Coulomb friction on the joint)
/// and stay with the joint-by-joint pass, as does a ball joint's motor
/// (its three rows bounded together in length, not row by row), with the equality rows held: in the system, a chain
/// of 30 links slipping on the friction of every joint (all 30 rows held at
/// their bounds, each solve exact to 1e-14) blew up as its end whipped
/// round at 2.3 s, where with the pass it loses energy and holds (the
/// joints open 1.1 mm at the whip, 1.3 mm without friction). (Limits stay
/// with the joint-by-joint pass. As rows of the system held one-sided by
/// `hold_at_bounds`, a quadruped crouching off its knee limits collapsed
/// and NAO blew apart; on the system's Schur complement, as the owned
/// contacts are, NAO's ungeared fingers came apart: the limits and the
/// owned contacts need one LCP together; docs/pipeline.md, "Measured and
/// not kept".)
fn island_mask(j: &JointConstraint) -> u16 {
    let motor = match j.law.motor {
        Some(Motor::Position { .. }) => 1 << MOTOR,
        _ => 0,
    };
    let spring = match (j.law.spring, j.law.kind) {
        (None, _) => 0,
        (Some(_), JointKind::Ball) => BALL_SPRING_MASK,
        (Some(_), _) => 1 << SPRING,
    };
    motor | spring
}

/// The islands of joints worth a direct solve: joints linked through
/// shared dynamic bodies, at least two per island with equality rows, a
/// profile within [`MAX_PROFILE`]. Marks their joints `direct`. Joints in
/// the returned islands are listed breadth-first from the island's first
/// joint (in joint order), so the result is deterministic; consecutive
/// islands of the same shape without rows of their own in the system (a
/// position motor, a spring: `island_mask`; velocity and ball motors are
/// relaxed joint by joint) share a unit, up to one per lane of the
/// solver's SIMD type.
///
/// `contacts` lists the patches an island may own: it owns those whose two
/// bodies are both its own, and those between one of its own and an
/// immovable body (static or kinematic; see `island_contacts`), within
/// [`MAX_OWNED_SUBSTITUTION`].
///
/// A gear links its two joints as a shared body does; the gears of an
/// island's joints are rows of its system, marked `direct`.
pub fn joint_islands(
    joints: &mut [JointConstraint],
    gears: &mut [GearConstraint],
    bodies: &[SolverBody],
    contacts: &[OwnableContact],
) -> Vec<JointIsland> {
    joint_islands_in_lanes(joints, gears, bodies, contacts, LANES)
}

/// [`joint_islands`] for this step, into `islands`, which hold last step's:
/// where the islands' shapes would be found from the same joints, gears
/// and bodies (`key`, what they were found from last time, is the same),
/// last step's units are kept (their joints marked `direct` again) and only
/// the patches they own are found anew. The same islands as
/// [`joint_islands`] gives, so the same bits; the shapes' search, a
/// breadth-first walk with lists per body and joint, was 2 % of the ragdoll
/// pile's instructions and a seventh of its step's serial prepare (0.98-1.04
/// -> 0.86-0.90 ms, `profile_stages ragdoll_pile 200 1`, builds alternated).
pub fn keep_joint_islands(
    islands: &mut Vec<JointIsland>,
    key: &mut Vec<u64>,
    joints: &mut [JointConstraint],
    gears: &mut [GearConstraint],
    bodies: &[SolverBody],
    contacts: &[OwnableContact],
) {
    let now = shape_key(joints, gears, bodies);
    if now == *key {
        for unit in islands.iter() {
            for &k in unit.lanes.iter().flatten() {
                let j = &mut joints[k as usize];
                j.direct = true;
                j.island_rows = island_mask(j);
            }
            for &g in &unit.gears {
                gears[g as usize].direct = true;
            }
        }
        own_patches(islands, joints, bodies, contacts);
    } else {
        *islands = joint_islands(joints, gears, bodies, contacts);
        *key = now;
    }
}

/// Everything the shapes of the joint islands are found from (the units
/// of [`joint_islands`] without the patches they own): per joint its two
/// bodies, rows and kind of row in the system, whether a motor bounds its
/// force, and whether each body is dynamic and its mass; per gear its two
/// joints.
fn shape_key(joints: &[JointConstraint], gears: &[GearConstraint], bodies: &[SolverBody]) -> Vec<u64> {
    let mut key = Vec::with_capacity(2 + 4 * joints.len() + gears.len());
    key.push(joints.len() as u64);
    key.push(gears.len() as u64);
    for j in joints {
        let bounded = j.law.motor.is_some_and(|m| m.max_force().is_finite());
        key.push(((j.a as u64) << 32) | j.b as u64);
        key.push(((j.law.equality_rows() as u64) << 32) | ((island_mask(j) as u64) << 1) | bounded as u64);
        for b in [j.a, j.b] {
            let b = &bodies[b as usize];
            key.push(if b.dynamic { b.inv_mass.to_bits() } else { u64::MAX });
        }
    }
    for g in gears {
        key.push(((g.joints[0] as u64) << 32) | g.joints[1] as u64);
    }
    key
}

/// [`joint_islands`], at most `max_lanes` islands to a unit.
fn joint_islands_in_lanes(
    joints: &mut [JointConstraint],
    gears: &mut [GearConstraint],
    bodies: &[SolverBody],
    contacts: &[OwnableContact],
    max_lanes: usize,
) -> Vec<JointIsland> {
    let mut islands = island_shapes(joints, gears, bodies, max_lanes);
    // The bodies of a unit of more lanes as lane sets (kept with the unit
    // while its joints and bodies stay the same: `keep_joint_islands`).
    for unit in islands.iter_mut().filter(|u| u.lanes.len() > 1) {
        let ends = |k: u32| [joints[k as usize].a, joints[k as usize].b];
        let body = |b: u32| (bodies[b as usize].dynamic, bodies[b as usize].inv_mass);
        let built = unit.unit_bodies.build(&unit.lanes, ends, body);
        debug_assert!(built, "the lanes of a unit link their bodies alike");
    }
    own_patches(&mut islands, joints, bodies, contacts);
    islands
}

/// The units of [`joint_islands`] without the patches they own; marks
/// their joints and gears `direct`.
fn island_shapes(
    joints: &mut [JointConstraint],
    gears: &mut [GearConstraint],
    bodies: &[SolverBody],
    max_lanes: usize,
) -> Vec<JointIsland> {
    let n_bodies = bodies.len();
    // Joints of each dynamic body, in joint order.
    let mut of_body: Vec<Vec<u32>> = vec![Vec::new(); n_bodies];
    for (k, j) in joints.iter().enumerate() {
        for b in [j.a, j.b] {
            if bodies[b as usize].dynamic {
                of_body[b as usize].push(k as u32);
            }
        }
    }
    // Gears of each joint (leader or follower), in gear order.
    let mut gears_of: Vec<Vec<u32>> = vec![Vec::new(); joints.len()];
    for (g, gear) in gears.iter().enumerate() {
        for k in gear.joints {
            gears_of[k as usize].push(g as u32);
        }
    }
    let mut seen = vec![false; joints.len()];
    // Position of each joint in its island's order (each joint is in one island).
    let mut position = vec![usize::MAX; joints.len()];
    let mut islands = Vec::new();
    // Dynamic bodies reached by the joints of the islands so far (islands
    // share none).
    let mut reached = vec![false; n_bodies];
    for root in 0..joints.len() {
        if seen[root] {
            continue;
        }
        // Breadth-first over joints sharing a dynamic body.
        let mut order = vec![root as u32];
        seen[root] = true;
        let mut head = 0;
        while head < order.len() {
            let j = &joints[order[head] as usize];
            let geared = gears_of[order[head] as usize]
                .iter()
                .flat_map(|&g| gears[g as usize].joints);
            for k in [j.a, j.b]
                .into_iter()
                .flat_map(|b| of_body[b as usize].iter().copied())
                .chain(geared)
            {
                if !seen[k as usize] {
                    seen[k as usize] = true;
                    order.push(k);
                }
            }
            head += 1;
        }
        let mut order = spanning_tree(order, joints, bodies, &gears_of, &mut reached);
        // Leaves first (the breadth-first order reversed): a joint's rows
        // then reach back only to joints further out on the same bodies, and
        // a tree's hub (a ragdoll's torso) comes last, so the profile stays
        // narrow (a chain is banded either way).
        order.reverse();
        let masks: Vec<u16> = order.iter().map(|&k| island_mask(&joints[k as usize])).collect();
        // Rows of the joint at position p of the order.
        let rows: Vec<usize> = order
            .iter()
            .zip(&masks)
            .map(|(&k, m)| joints[k as usize].law.equality_rows() + m.count_ones() as usize)
            .collect();
        if order.len() < 2 || rows.iter().all(|&r| r == 0) {
            continue;
        }
        // Profile: each row reaches back to the first row of the earliest
        // joint (in this order) that shares a dynamic body with its joint.
        for (p, &k) in order.iter().enumerate() {
            position[k as usize] = p;
        }
        let mut offsets = Vec::with_capacity(order.len() + 1);
        let mut total = 0;
        for &r in &rows {
            offsets.push(total);
            total += r;
        }
        offsets.push(total);
        // The island's gears, in gear order (both joints are here: the
        // search follows gears).
        let mut island_gears: Vec<u32> = order
            .iter()
            .flat_map(|&k| gears_of[k as usize].iter().copied())
            .collect();
        island_gears.sort_unstable();
        island_gears.dedup();
        let total = total + island_gears.len();
        let mut first = Vec::with_capacity(total);
        let mut start = Vec::with_capacity(total);
        let mut size = 0usize;
        let mut couplings = Vec::new();
        for (p, &k) in order.iter().enumerate() {
            let j = &joints[k as usize];
            let mut earliest = p;
            for (side_p, b) in [j.a, j.b].into_iter().enumerate() {
                if !bodies[b as usize].dynamic {
                    continue;
                }
                for &other in &of_body[b as usize] {
                    let q = position[other as usize];
                    if q > p || (q == p && other != k) {
                        continue;
                    }
                    let o = &joints[other as usize];
                    let side_q = if o.a == b { 0 } else { 1 };
                    // A joint meets itself on this side only.
                    if q == p && side_q != side_p {
                        continue;
                    }
                    couplings.push(Coupling {
                        p: p as u32,
                        q: q as u32,
                        side_p: side_p as u8,
                        side_q: side_q as u8,
                    });
                }
            }
            for b in [j.a, j.b] {
                if bodies[b as usize].dynamic {
                    for &other in &of_body[b as usize] {
                        earliest = earliest.min(position[other as usize]);
                    }
                }
            }
            for e in 0..rows[p] {
                let i = offsets[p] + e;
                first.push(offsets[earliest]);
                start.push(size);
                size += i - offsets[earliest] + 1;
            }
        }
        // A gear's row reaches back to the earliest joint on any of its
        // bodies (and holds every row after it, earlier gears' included).
        for (e, &g) in island_gears.iter().enumerate() {
            let i = offsets[order.len()] + e;
            let earliest = gears[g as usize]
                .joints
                .iter()
                .flat_map(|&k| [joints[k as usize].a, joints[k as usize].b])
                .filter(|&b| bodies[b as usize].dynamic)
                .flat_map(|b| of_body[b as usize].iter().map(|&other| position[other as usize]))
                .min()
                .unwrap_or(order.len());
            let from = offsets[earliest];
            first.push(from);
            start.push(size);
            size += i - from + 1;
        }
        debug_assert_eq!(first.len(), total);
        if size > MAX_PROFILE {
            continue;
        }
        // The island's lightest and heaviest bodies (for the owned patches
        // and the aim, below).
        let masses: Vec<f64> = order
            .iter()
            .flat_map(|&k| [joints[k as usize].a, joints[k as usize].b])
            .filter(|&b| bodies[b as usize].dynamic && bodies[b as usize].inv_mass > 0.0)
            .map(|b| 1.0 / bodies[b as usize].inv_mass)
            .collect();
        let (lightest, heaviest) = masses
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), &m| (lo.min(m), hi.max(m)));
        // The aim is a fixed-point iteration through the whole island; its
        // gain grows with the mass ratio across it: a 20-link rope of 0.1 kg
        // links holding 10 kg came apart with it (and holds without), while
        // a double pendulum of equal masses keeps its energy only with it.
        let aim = heaviest <= AIM_MASS_RATIO * lightest;
        for (&k, &mask) in order.iter().zip(&masks) {
            joints[k as usize].direct = true;
            joints[k as usize].island_rows = mask;
        }
        for &g in &island_gears {
            gears[g as usize].direct = true;
        }
        let profile = Profile::new(offsets, couplings, first, start, size);
        // Scalar rows in the system (motors, springs) keep the island in a
        // unit of its own; only a motor's force bound is held.
        let single = masks.iter().any(|&m| m != 0) || !island_gears.is_empty();
        let bounded = order.iter().zip(&masks).any(|(&k, &m)| {
            m & (1 << MOTOR) != 0
                && joints[k as usize]
                    .law
                    .motor
                    .is_some_and(|m| m.max_force().is_finite())
        });
        // The island joins the last unit where it is of the same shape,
        // neither has a motor or spring and a lane is free.
        if let Some(unit) = islands.last_mut().filter(|u: &&mut JointIsland| {
            !single && !u.single && u.lanes.len() < max_lanes && u.profile == profile
        }) {
            unit.lanes.push(order);
            unit.aim.push(aim);
            unit.heaviest.push(heaviest);
            continue;
        }
        islands.push(JointIsland {
            lanes: vec![order],
            profile,
            single,
            bounded,
            aim: vec![aim],
            gears: island_gears,
            heaviest: vec![heaviest],
            ..JointIsland::default()
        });
    }
    islands
}

/// The joints of `order` (an island's, breadth-first) whose equality rows
/// form a tree: in order, each joint with equality rows that reaches a
/// body the joints kept before it have not (the world, every immovable
/// body, counting as one body), a joint with a gear (whose row the gear's
/// coupling needs in the system), and every joint without equality rows (a
/// rope, a spring: its rows in the system, if any, are soft, and cannot
/// depend on others). The others close loops and are left out, to be
/// relaxed beside the island (module header). `reached` marks the
/// dynamic bodies the kept joints with equality rows reach.
fn spanning_tree(
    order: Vec<u32>,
    joints: &[JointConstraint],
    bodies: &[SolverBody],
    gears_of: &[Vec<u32>],
    reached: &mut [bool],
) -> Vec<u32> {
    let mut world = false;
    let mut tree = Vec::with_capacity(order.len());
    for k in order {
        let j = &joints[k as usize];
        if j.law.equality_rows() == 0 {
            tree.push(k);
            continue;
        }
        let sides = [j.a, j.b].map(|b| (b, bodies[b as usize].dynamic));
        let seen = |&(b, dynamic): &(u32, bool)| if dynamic { reached[b as usize] } else { world };
        if sides.iter().all(seen) && gears_of[k as usize].is_empty() {
            continue;
        }
        for (b, dynamic) in sides {
            if dynamic {
                reached[b as usize] = true;
            } else {
                world = true;
            }
        }
        tree.push(k);
    }
    tree
}

/// Gives each island the patches it owns this step (`contacts`, as in
/// [`joint_islands`]): those between two of its bodies and those between
/// one of its bodies and an immovable one, neither body lighter than
/// [`LIGHTEST_OWNER`] of the island's heaviest, the latter of at most
/// [`BLOCK_POINTS`] points and within what the former leave of
/// [`MAX_OWNED_SUBSTITUTION`]; each as blocks of up to [`BLOCK_POINTS`]
/// points; in a unit, lane by lane, each lane's in patch order.
fn own_patches(
    islands: &mut [JointIsland],
    joints: &[JointConstraint],
    bodies: &[SolverBody],
    contacts: &[OwnableContact],
) {
    own_patches_within(islands, joints, bodies, contacts, MAX_OWNED_SUBSTITUTION);
}

/// [`own_patches`] with a budget of `budget` factor entries of forward
/// substitution a sub-step per island: where its candidates on immovable
/// bodies would cost more ([`owned_cost`]) than the budget less its own
/// patches' cost, it owns the cheapest of them (ties in patch order) while
/// their sum stays within that. Cheapest first owns the most points
/// for the work; which of a net's patches matter most is not known here.
fn own_patches_within(
    islands: &mut [JointIsland],
    joints: &[JointConstraint],
    bodies: &[SolverBody],
    contacts: &[OwnableContact],
    budget: usize,
) {
    for unit in islands.iter_mut() {
        unit.owned.clear();
    }
    if contacts.is_empty() {
        return;
    }
    // The candidate patches by their dynamic body, in candidate order: body
    // `b`'s are `by_body[start[b]..start[b] + left[b]]` (`left[b]` is zeroed
    // once they are taken). One list, not a `Vec` per body: those were
    // about a thousand allocations a step on a pile of ragdolls.
    let mut left = vec![0u32; bodies.len()];
    for contact in contacts {
        left[contact.body as usize] += 1;
    }
    let mut start = Vec::with_capacity(bodies.len());
    let mut next = 0u32;
    for &count in &left {
        start.push(next);
        next += count;
    }
    let mut by_body = vec![0u32; contacts.len()];
    let mut fill = start.clone();
    for (c, contact) in contacts.iter().enumerate() {
        let at = &mut fill[contact.body as usize];
        by_body[*at as usize] = c as u32;
        *at += 1;
    }
    let contacts_of = |b: u32, left: &[u32]| {
        let from = start[b as usize] as usize;
        &by_body[from..from + left[b as usize] as usize]
    };
    // Each dynamic body's island, numbered in unit and lane order, and its
    // first row in that island's system.
    let mut member = vec![usize::MAX; bodies.len()];
    let mut first_row = vec![usize::MAX; bodies.len()];
    // The same body's joints (bit `p` for joint `p` of the island's
    // order, islands of up to `REACH_JOINTS` joints: `Profile::reach`).
    let mut touching = vec![0u64; bodies.len()];
    let mut island = 0;
    // Scratch, cleared for each island: its candidates on immovable bodies
    // and its own patches (cost, patch, first row, points, reach), then its
    // blocks (patch, first point, points, first row, reach) in patch order.
    let (mut candidates, mut own, mut blocks) = (Vec::new(), Vec::new(), Vec::new());
    for unit in islands.iter_mut() {
        let offsets = &unit.profile.offsets;
        for (lane, order) in unit.lanes.iter().enumerate() {
            let heaviest = unit.heaviest[lane];
            let dynamic_bodies = || {
                order
                    .iter()
                    .flat_map(|&k| [joints[k as usize].a, joints[k as usize].b])
                    .filter(|&b| bodies[b as usize].dynamic)
            };
            dynamic_bodies().for_each(|b| member[b as usize] = island);
            for (p, &k) in order.iter().enumerate() {
                let j = &joints[k as usize];
                // The rows of any joint on either body, an immovable one's
                // too (`OwnedPatch::couple` adds its rows, zeros there):
                // where the patch's substitutions start.
                if offsets[p] < offsets[p + 1] {
                    for b in [j.a, j.b] {
                        first_row[b as usize] = first_row[b as usize].min(offsets[p]);
                        if p < REACH_JOINTS {
                            touching[b as usize] |= 1 << p;
                        }
                    }
                }
            }
            // A dynamic body far lighter than the island's heaviest, where
            // the owned solve runs away (`island_contacts::LIGHTEST_OWNER`).
            let light = |b: u32| {
                bodies[b as usize].dynamic && bodies[b as usize].inv_mass * heaviest * LIGHTEST_OWNER > 1.0
            };
            // (cost, patch, first row, points) of each patch it may own
            // on an immovable body; its own patches (between two of its
            // bodies) apart, owned whatever they cost.
            candidates.clear();
            own.clear();
            for b in dynamic_bodies() {
                for &c in contacts_of(b, &left) {
                    let OwnableContact {
                        patch, other, points, ..
                    } = contacts[c as usize];
                    // Between two of its bodies, or one of its bodies and
                    // an immovable one (the ground under a ragdoll's forearm:
                    // a loop through the world, island_contacts), neither
                    // of them light.
                    if (member[other as usize] == island || !bodies[other as usize].dynamic)
                        && !light(b)
                        && !light(other)
                    {
                        let first = first_row[b as usize].min(first_row[other as usize]);
                        let cost = owned_cost(&unit.profile, first, points);
                        let reach = unit
                            .profile
                            .reach(touching[b as usize] | touching[other as usize]);
                        let candidate = (cost, patch, first, points, reach);
                        // On the world, a patch of more points than a block
                        // stays beside the island: owned, a car's wheels on a
                        // mesh terrain rolled 19 % slower than their motors
                        // drive them (examples/python/car.py).
                        if bodies[other as usize].dynamic {
                            own.push(candidate);
                        } else if points as usize <= BLOCK_POINTS {
                            candidates.push(candidate);
                        }
                    }
                }
                // A body is met once per joint: its patches are taken once.
                left[b as usize] = 0;
            }
            let cost = |c: &[(usize, u32, usize, u32, Option<u64>)]| c.iter().map(|c| c.0).sum::<usize>();
            let left = budget.saturating_sub(cost(&own));
            if cost(&candidates) > left {
                candidates.sort_unstable();
                let mut spent = 0;
                let fit = candidates
                    .iter()
                    .take_while(|&&(cost, ..)| {
                        spent += cost;
                        spent <= left
                    })
                    .count();
                candidates.truncate(fit);
            }
            // A patch of more points than a block, block after block (in
            // point order: the sort below is stable).
            blocks.clear();
            for &(_, patch, first, points, reach) in own.iter().chain(&candidates) {
                for start in (0..points).step_by(BLOCK_POINTS) {
                    let count = (points - start).min(BLOCK_POINTS as u32);
                    blocks.push((patch, start, count, first, reach));
                }
            }
            blocks.sort_by_key(|&(patch, ..)| patch);
            // Built once, in place: an owned block is some 370 bytes, and
            // building them first, then sorting and moving them, cost a pile of
            // ragdolls 0.1 ms a step.
            unit.owned
                .extend(blocks.iter().map(|&(patch, start, count, first, reach)| {
                    OwnedPatch::new(patch, start, count, lane, first, reach)
                }));
            for &k in order {
                for b in [joints[k as usize].a, joints[k as usize].b] {
                    first_row[b as usize] = usize::MAX;
                    touching[b as usize] = 0;
                }
            }
            island += 1;
        }
    }
}

/// The forward substitutions an owned patch of `points` points costs its
/// island each sub-step, in factor entries: one per point over the rows
/// from `first_row` (the first on the patch's bodies) to the end
/// (`JointIsland::solve_columns`).
fn owned_cost(profile: &Profile, first_row: usize, points: u32) -> usize {
    let from = profile.start.get(first_row).copied().unwrap_or(profile.size);
    points as usize * (profile.size - from)
}

#[cfg(test)]
mod tests {
    use super::super::body::integrate_positions;
    use super::super::constraint::{ManifoldConstraint, PointConstraint};
    use super::super::island_contacts::COMPLIANCE_SHARE;
    use super::super::joint::{begin_joints, push_joints, solve_joints, JointLaw, JOINT_ROWS};
    use super::*;
    use crate::joint::{JointKind, Spring};
    use tumble_collide::{DQuat, DVec3, Pose};
    use tumble_testkit::{RandomSource, SplitMix64};

    fn vector(rng: &mut SplitMix64, size: f64) -> DVec3 {
        DVec3::new(
            rng.range(-size, size),
            rng.range(-size, size),
            rng.range(-size, size),
        )
    }

    /// A joint of `kind` without limits, motor, spring or friction.
    fn plain_law(kind: JointKind) -> JointLaw {
        JointLaw {
            kind,
            limits: None,
            swing_limit: None,
            motor: None,
            spring: None,
            friction: None,
            length: 0.0,
        }
    }

    fn rotation(rng: &mut SplitMix64) -> DQuat {
        DQuat::from_scaled_axis(vector(rng, 2.0))
    }

    /// `count` trees of five bodies of random masses, poses and velocities
    /// (body 0 is the immovable world): a ball joint to the world, a hinge
    /// and a slider with limits, a ball joint with a swing cone, a weld and
    /// a rod, each anchor placed at random in its body (so the joints start
    /// apart and the push-out has work).
    fn trees(rng: &mut SplitMix64, count: usize) -> (Vec<SolverBody>, Vec<JointConstraint>) {
        let mut bodies = vec![SolverBody::fixed()];
        let mut x0 = vec![DVec3::ZERO];
        let mut joints = Vec::new();
        let law = |kind, limits, swing_limit, length| JointLaw {
            kind,
            limits,
            swing_limit,
            motor: None,
            spring: None,
            friction: None,
            length,
        };
        for t in 0..count {
            let first = bodies.len() as u32;
            for _ in 0..5 {
                let inertia = DVec3::new(rng.range(0.2, 3.0), rng.range(0.2, 3.0), rng.range(0.2, 3.0));
                bodies.push(SolverBody::new(
                    vector(rng, 1.0),
                    vector(rng, 3.0),
                    1.0 / rng.range(0.5, 5.0),
                    inertia,
                    rotation(rng),
                ));
                x0.push(DVec3::new(3.0 * t as f64, 0.0, 0.0) + vector(rng, 0.5));
            }
            let links = [
                (0, None, law(JointKind::Ball, None, None, 0.0)),
                (1, Some(0), law(JointKind::Hinge, Some([-0.5, 0.5]), None, 0.0)),
                (2, Some(0), law(JointKind::Ball, None, Some(0.4), 0.0)),
                (3, Some(1), law(JointKind::Fixed, None, None, 0.0)),
                (4, Some(2), law(JointKind::Distance, None, None, 0.3)),
                (4, Some(3), law(JointKind::Slider, Some([-0.1, 0.1]), None, 0.0)),
            ];
            for (a, b, law) in links {
                let a = first + a;
                let b = b.map_or(0, |b| first + b);
                let side = |i: u32| (x0[i as usize], bodies[i as usize].q);
                let ((xa, qa), (xb, qb)) = (side(a), side(b));
                let local = |rng: &mut SplitMix64| Pose {
                    position: vector(rng, 0.3),
                    rotation: rotation(rng),
                };
                joints.push(JointConstraint::new(
                    (a, b),
                    [xa, xb],
                    [qa, qb],
                    [local(rng), local(rng)],
                    law,
                    &[0.0; JOINT_ROWS],
                ));
            }
        }
        (bodies, joints)
    }

    /// The rest of a sub-step after its start: two velocity passes, a
    /// push-out pass and the position update.
    fn passes(
        joints: &mut [JointConstraint],
        islands: &mut [JointIsland],
        bodies: &mut [SolverBody],
        q0: &[DQuat],
        h: f64,
    ) {
        solve_joints(joints, &mut [], islands, bodies);
        solve_joints(joints, &mut [], islands, bodies);
        push_joints(joints, &mut [], islands, bodies, h);
        integrate_positions(bodies, q0, h);
    }

    /// An island keeps a tree of its joints: of [`trees`]' six joints on
    /// five bodies and the world (body 4 jointed to both 2 and 3 closes the
    /// loop 0-2-4-3-1-0), the last one the breadth-first walk meets is left
    /// to be relaxed beside the island, and the five kept reach every body
    /// and the world once each; a joint to the world from a body the
    /// island has reached closes a loop through the world; a rope (no
    /// equality rows) closes none.
    #[test]
    fn an_island_keeps_a_tree_and_leaves_the_joint_that_closes_a_loop() {
        let (bodies, mut joints) = trees(&mut SplitMix64(3), 1);
        let islands = joint_islands(&mut joints, &mut [], &bodies, &[]);
        assert_eq!(islands.len(), 1);
        let kept = &islands[0].lanes[0];
        assert_eq!(kept.len(), 5);
        let relaxed: Vec<usize> = (0..joints.len()).filter(|&k| !joints[k].direct).collect();
        assert_eq!(relaxed, vec![5], "the slider from 4 to 3 closes the loop");
        let mut reached: Vec<u32> = kept
            .iter()
            .flat_map(|&k| [joints[k as usize].a, joints[k as usize].b])
            .collect();
        reached.sort_unstable();
        reached.dedup();
        assert_eq!(reached, vec![0, 1, 2, 3, 4, 5]);

        // Without the slider, a ball joint from the leaf 5 (body 4 of the
        // tree) to the world, which the root's joint reached.
        let (bodies, mut joints) = trees(&mut SplitMix64(3), 1);
        let mut to_world = joints[0].clone();
        to_world.a = 5;
        joints.truncate(5);
        joints.push(to_world);
        let islands = joint_islands(&mut joints, &mut [], &bodies, &[]);
        assert_eq!(islands[0].lanes[0].len(), 5);
        assert!(!joints[5].direct && joints[..5].iter().all(|j| j.direct));

        // Without the slider, a rope (a distance joint with limits: no
        // equality rows) from 5 to 4 (bodies 4 and 3 of the tree): no loop
        // of rows, the island keeps it.
        let (bodies, mut joints) = trees(&mut SplitMix64(3), 1);
        let mut rope = joints[4].clone();
        rope.b = 4;
        rope.law.limits = Some([0.0, 0.5]);
        assert_eq!(rope.law.equality_rows(), 0);
        joints.truncate(5);
        joints.push(rope);
        let islands = joint_islands(&mut joints, &mut [], &bodies, &[]);
        assert_eq!(islands[0].lanes[0].len(), 6);
        assert!(joints.iter().all(|j| j.direct));
    }

    /// Four islands of one shape solved in the lanes of one unit give the    /// Four islands of one shape solved in the lanes of one unit give the
    /// bits each gets in a unit of its own: sub-steps of the joints' start,
    /// two velocity passes, a push-out pass and the position update.
    #[test]
    fn islands_in_lanes_get_the_bits_they_get_alone() {
        let (bodies, joints) = trees(&mut SplitMix64(5), 5);
        let run = |max_lanes: usize| {
            let (mut bodies, mut joints) = (bodies.clone(), joints.clone());
            let mut islands = joint_islands_in_lanes(&mut joints, &mut [], &bodies, &[], max_lanes);
            let q0: Vec<DQuat> = bodies.iter().map(|b| b.q).collect();
            let h = 1.0 / 480.0;
            for _ in 0..6 {
                begin_joints(&mut joints, &mut [], &mut islands, &mut bodies, h, true);
                passes(&mut joints, &mut islands, &mut bodies, &q0, h);
            }
            let lanes: Vec<usize> = islands.iter().map(JointIsland::lanes).collect();
            // A unit of more lanes relaxes its bodies as lane sets.
            assert!(islands
                .iter()
                .all(|u| (u.lanes() > 1) == u.unit_bodies.is_built()));
            let state: Vec<[DVec3; 3]> = bodies.iter().map(|b| [b.v, b.w, b.dp]).collect();
            let impulses: Vec<[f64; JOINT_ROWS]> = joints.iter().map(JointConstraint::impulses).collect();
            (lanes, state, impulses)
        };
        let (lanes, state, impulses) = run(LANES);
        let (alone, state_alone, impulses_alone) = run(1);
        assert_eq!((lanes, alone), (vec![4, 1], vec![1; 5]));
        // The passes moved the bodies and the joints pushed.
        assert!(state
            .iter()
            .zip(&bodies)
            .skip(1)
            .all(|(s, b)| s[0] != b.v && s[2] != DVec3::ZERO));
        assert!(impulses.iter().all(|i| i.iter().any(|&x| x != 0.0)));
        for (k, (a, b)) in state.iter().zip(&state_alone).enumerate() {
            for (u, v) in a.iter().zip(b) {
                assert_eq!(
                    u.to_array().map(f64::to_bits),
                    v.to_array().map(f64::to_bits),
                    "body {k}"
                );
            }
        }
        for (k, (a, b)) in impulses.iter().zip(&impulses_alone).enumerate() {
            assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits), "joint {k}");
        }
    }

    /// A record renewed in place (`JointConstraint::renew`) gives the bits
    /// of one made afresh (`JointConstraint::new`) with the same joint and
    /// warm start: each record first served another joint of another kind
    /// for three sub-steps (its slots active, its impulses and push-out
    /// impulses not zero), then six sub-steps of the trees in islands, with
    /// warm starts of zeros, negative zeros, NaN and numbers.
    #[test]
    fn renewed_records_get_the_bits_of_new_ones() {
        let (bodies, joints) = trees(&mut SplitMix64(7), 5);
        let h = 1.0 / 480.0;
        let q0: Vec<DQuat> = bodies.iter().map(|b| b.q).collect();
        let mut used = joints.clone();
        {
            let mut bodies = bodies.clone();
            let mut islands = joint_islands_in_lanes(&mut used, &mut [], &bodies, &[], LANES);
            for _ in 0..3 {
                begin_joints(&mut used, &mut [], &mut islands, &mut bodies, h, true);
                passes(&mut used, &mut islands, &mut bodies, &q0, h);
            }
        }
        used.rotate_left(1);
        let rng = &mut SplitMix64(8);
        let warm: Vec<[f64; JOINT_ROWS]> = joints
            .iter()
            .map(|_| {
                std::array::from_fn(|_| match rng.range(0.0, 4.0) as u32 {
                    0 => 0.0,
                    1 => -0.0,
                    2 => f64::NAN,
                    _ => rng.range(-1.0, 1.0),
                })
            })
            .collect();
        // The renewed records held impulses where the new joint starts at
        // zero.
        assert!(used.iter().zip(&warm).any(|(u, w)| (0..JOINT_ROWS)
            .any(|i| (u.rows[i].impulse != 0.0 || u.rows[i].push != 0.0) && w[i] == 0.0)));
        let args = |j: &JointConstraint| ((j.a, j.b), j.x0, j.q0, j.local, j.law);
        let fresh: Vec<JointConstraint> = joints
            .iter()
            .zip(&warm)
            .map(|(j, w)| {
                let (pair, x0, q0, local, law) = args(j);
                JointConstraint::new(pair, x0, q0, local, law, w)
            })
            .collect();
        let mut renewed = used;
        for ((r, j), w) in renewed.iter_mut().zip(&joints).zip(&warm) {
            let (pair, x0, q0, local, law) = args(j);
            r.renew(pair, x0, q0, local, law, w);
        }
        let run = |mut joints: Vec<JointConstraint>| {
            let mut bodies = bodies.clone();
            let mut islands = joint_islands_in_lanes(&mut joints, &mut [], &bodies, &[], LANES);
            for _ in 0..6 {
                begin_joints(&mut joints, &mut [], &mut islands, &mut bodies, h, true);
                passes(&mut joints, &mut islands, &mut bodies, &q0, h);
            }
            let state: Vec<[u64; 9]> = bodies
                .iter()
                .map(|b| {
                    let mut s = [0; 9];
                    for (k, v) in [b.v, b.w, b.dp].iter().enumerate() {
                        s[3 * k..3 * k + 3].copy_from_slice(&v.to_array().map(f64::to_bits));
                    }
                    s
                })
                .collect();
            let rows: Vec<[(u64, u64); JOINT_ROWS]> = joints
                .iter()
                .map(|j| std::array::from_fn(|i| (j.rows[i].impulse.to_bits(), j.rows[i].push.to_bits())))
                .collect();
            (state, rows)
        };
        let (state, rows) = run(fresh);
        let (state_renewed, rows_renewed) = run(renewed);
        assert!(
            state.iter().skip(1).all(|s| s[6..] != [0; 3]),
            "the joints pushed"
        );
        assert_eq!(state_renewed, state);
        assert_eq!(rows_renewed, rows);
    }

    /// `n` random patches (up to four points) from one of bodies 1..=`bodies`
    /// to the ground (body 0) or another of them.
    fn random_contacts(rng: &mut SplitMix64, n: usize, bodies: u32) -> Vec<OwnableContact> {
        (0..n as u32)
            .map(|patch| {
                let body = 1 + (rng.range(0.0, bodies as f64 - 0.001) as u32);
                let other = if rng.range(0.0, 1.0) < 0.4 {
                    0
                } else {
                    1 + (rng.range(0.0, bodies as f64 - 0.001) as u32)
                };
                // Up to eight points: a mesh patch's are owned in blocks.
                let points = 1 + (rng.range(0.0, 7.999) as u32);
                OwnableContact {
                    patch,
                    body,
                    other,
                    points,
                }
            })
            .filter(|c| c.body != c.other)
            .collect()
    }

    /// Within a budget of substitution work, an island owns every patch
    /// between two of its bodies and the cheapest of its patches on an
    /// immovable body, as many as fit in what its own leave of the budget:
    /// a patch's cost counted here by brute force over the island's rows
    /// (its points times the factor's entries from the first row of a joint
    /// on either of its bodies), against the owners with no budget. Every
    /// patch it owns is one it owns without a budget, none it leaves out is
    /// its own or costs less than one on the world it owns, their cost is
    /// within what is left and one more would not be. Each owned patch is
    /// owned as blocks of up to four of its points, in order, covering
    /// them all.
    #[test]
    fn an_island_over_its_substitution_budget_owns_its_cheapest_patches() {
        let (bodies, mut joints) = trees(&mut SplitMix64(5), 6);
        let contacts = random_contacts(&mut SplitMix64(23), 120, 30);
        let free = joint_islands(&mut joints, &mut [], &bodies, &contacts);
        assert!(free.iter().map(|u| u.owned.len()).sum::<usize>() > 20);
        let mut tight = free.clone();
        // Per island (unit, lane): each owned patch's cost without a budget.
        let cost_of = |unit: &JointIsland, lane: usize, patch: u32| {
            let c = contacts.iter().find(|c| c.patch == patch).unwrap();
            let mut first = usize::MAX;
            for (p, &k) in unit.lanes[lane].iter().enumerate() {
                let j = &joints[k as usize];
                let rows = unit.profile.offsets[p]..unit.profile.offsets[p + 1];
                if !rows.is_empty() && [j.a, j.b].iter().any(|&b| b == c.body || b == c.other) {
                    first = first.min(rows.start);
                }
            }
            // A body reached by a rope alone has no row in the system.
            unit.profile
                .start
                .get(first)
                .map_or(0, |&from| c.points as usize * (unit.profile.size - from))
        };
        let owned_by = |unit: &JointIsland, lane: usize| -> Vec<u32> {
            unit.owned
                .iter()
                .filter(|o| o.lane == lane && o.leads())
                .map(|o| o.patch)
                .collect()
        };
        let between_own =
            |p: u32| bodies[contacts.iter().find(|c| c.patch == p).unwrap().other as usize].dynamic;
        for unit in &free {
            for o in &unit.owned {
                let c = contacts.iter().find(|c| c.patch == o.patch).unwrap();
                let blocks: Vec<_> = unit.owned.iter().filter(|b| b.patch == o.patch).collect();
                let points = c.points as usize;
                assert_eq!(blocks.len(), points.div_ceil(BLOCK_POINTS), "patch {}", o.patch);
                for (k, b) in blocks.iter().enumerate() {
                    // The patch's points at 10.. among the solver's.
                    let start = 10 + k * BLOCK_POINTS;
                    assert_eq!(
                        b.points_in(10..10 + points),
                        start..(start + BLOCK_POINTS).min(10 + points)
                    );
                    assert_eq!(b.leads(), k == 0);
                }
            }
        }
        for budget in [usize::MAX, 2_000, 700, 150, 0] {
            own_patches_within(&mut tight, &joints, &bodies, &contacts, budget);
            let mut cut = 0;
            for (unit, whole) in tight.iter().zip(&free) {
                for lane in 0..unit.lanes.len() {
                    let (kept, all) = (owned_by(unit, lane), owned_by(whole, lane));
                    assert!(kept.iter().all(|p| all.contains(p)));
                    assert!(kept.windows(2).all(|w| w[0] < w[1]), "in patch order");
                    let own: usize = all
                        .iter()
                        .filter(|&&p| between_own(p))
                        .map(|&p| cost_of(unit, lane, p))
                        .sum();
                    let left = budget.saturating_sub(own);
                    let on_world = || kept.iter().filter(|&&p| !between_own(p));
                    let spent: usize = on_world().map(|&p| cost_of(unit, lane, p)).sum();
                    assert!(spent <= left, "{spent} > {left}");
                    let dearest_kept = on_world().map(|&p| cost_of(unit, lane, p)).max().unwrap_or(0);
                    for &p in all.iter().filter(|p| !kept.contains(p)) {
                        let cost = cost_of(unit, lane, p);
                        assert!(!between_own(p), "{p} is between two of the island's bodies");
                        assert!(cost >= dearest_kept && spent + cost > left, "{p}: {cost}");
                        cut += 1;
                    }
                }
            }
            assert_eq!(cut == 0, budget == usize::MAX, "budget {budget}: {cut} left out");
        }
        // Back to no budget: the owners as found afresh.
        own_patches_within(&mut tight, &joints, &bodies, &contacts, usize::MAX);
        assert_eq!(tight, free);
    }

    /// Islands kept from the last step are the islands found afresh: the
    /// same units, joints marked `direct` alike, and this step's patches
    /// owned (contacts that change from step to step with the same joints;
    /// then a body's mass and a joint's kind changed, which change the
    /// shapes).
    #[test]
    fn kept_islands_are_the_islands_found_afresh() {
        let (bodies, joints) = trees(&mut SplitMix64(9), 6);
        let mut rng = SplitMix64(17);
        // Random patches from a dynamic body to the ground or another body.
        let mut contacts = |n: usize| random_contacts(&mut rng, n, 30);
        // Kept islands against fresh ones; the patches owned.
        fn check(
            (kept, key): (&mut Vec<JointIsland>, &mut Vec<u64>),
            bodies: &[SolverBody],
            joints: &[JointConstraint],
            contacts: &[OwnableContact],
        ) -> usize {
            let (mut fresh_joints, mut kept_joints) = (joints.to_vec(), joints.to_vec());
            let fresh = joint_islands(&mut fresh_joints, &mut [], bodies, contacts);
            keep_joint_islands(kept, key, &mut kept_joints, &mut [], bodies, contacts);
            assert_eq!(*kept, fresh);
            for (a, b) in kept_joints.iter().zip(&fresh_joints) {
                assert_eq!((a.direct, a.island_rows), (b.direct, b.island_rows));
            }
            kept.iter().map(|u| u.owned.len()).sum()
        }
        let (mut kept, mut key) = (Vec::new(), Vec::new());
        let mut owned = Vec::new();
        for _ in 0..4 {
            owned.push(check((&mut kept, &mut key), &bodies, &joints, &contacts(40)));
        }
        // Each step owned patches of its own, with the shapes kept.
        assert!(owned.iter().all(|&n| n > 0), "{owned:?}");
        assert!(owned.windows(2).any(|w| w[0] != w[1]), "{owned:?}");
        let shape = key.clone();
        let mut heavier = bodies.clone();
        heavier[7].inv_mass *= 0.01;
        check((&mut kept, &mut key), &heavier, &joints, &contacts(40));
        assert_ne!(key, shape);
        let mut springy = joints.clone();
        springy[3].law.spring = Some(Spring {
            stiffness: 100.0,
            damping: 1.0,
        });
        check((&mut kept, &mut key), &bodies, &springy, &contacts(40));
        check((&mut kept, &mut key), &bodies, &joints[..20], &contacts(40));
        check((&mut kept, &mut key), &bodies, &joints, &contacts(40));
        assert_eq!(key, shape);
    }

    /// A gear in its island's system is solved exactly with the joints'
    /// equality rows: after one pass every hinge row and the gear's row
    /// meet their targets (`J v + bias = 0`, the gear's rate 0), where one
    /// pass with the gear relaxed after the island leaves the joints open
    /// again. A frame on a hinge to the world carries two wheels on hinges,
    /// the second geared to the first; random masses 20:1 apart (so the
    /// island does not aim its rows), poses and velocities.
    #[test]
    fn a_gear_in_its_islands_system_is_solved_exactly_with_the_joints() {
        use super::super::gear::{begin_gears, solve_gears};
        use crate::joint::Gear;
        use crate::world::JointId;
        // The largest miss of a target over the joints' equality rows,
        // and the gear's rate.
        let misses = |joints: &[JointConstraint], gear: &GearConstraint, bodies: &mut [SolverBody]| {
            let rows = joints
                .iter()
                .flat_map(|j| {
                    let (a, b) = (&bodies[j.a as usize], &bodies[j.b as usize]);
                    j.rows[..j.n_eq].iter().map(move |r| {
                        (r.lin.dot(a.v - b.v) + r.ang_a.dot(a.w) + r.ang_b.dot(b.w) + r.bias).abs()
                    })
                })
                .fold(0.0, f64::max);
            let bs = Shared::new(bodies);
            // SAFETY: one thread.
            (rows, unsafe { gear.rate(&bs, false) }.abs())
        };
        for seed in 0..5 {
            let mut rng = SplitMix64(40 + seed);
            let mut bodies = vec![SolverBody::fixed()];
            for inv_mass in [0.1, 1.0, 2.0] {
                let inv_inertia =
                    DVec3::new(rng.range(0.5, 2.0), rng.range(0.5, 2.0), rng.range(0.5, 2.0)) * inv_mass;
                bodies.push(SolverBody::new(
                    vector(&mut rng, 1.0),
                    vector(&mut rng, 3.0),
                    inv_mass,
                    inv_inertia,
                    rotation(&mut rng),
                ));
            }
            let x0 = [
                DVec3::ZERO,
                vector(&mut rng, 0.2),
                vector(&mut rng, 0.5),
                vector(&mut rng, 0.5),
            ];
            let hinge = plain_law(JointKind::Hinge);
            let mut joints: Vec<JointConstraint> = [(2, 1), (3, 1), (1, 0)]
                .into_iter()
                .map(|(a, b): (u32, u32)| {
                    let local = |rng: &mut SplitMix64| Pose {
                        position: vector(rng, 0.3),
                        rotation: rotation(rng),
                    };
                    JointConstraint::new(
                        (a, b),
                        [x0[a as usize], x0[b as usize]],
                        [bodies[a as usize].q, bodies[b as usize].q],
                        [local(&mut rng), local(&mut rng)],
                        hinge,
                        &[0.0; JOINT_ROWS],
                    )
                })
                .collect();
            let leader = JointId {
                index: 0,
                generation: 0,
            };
            let ratio = rng.range(-2.0, 2.0);
            let mut gears = vec![GearConstraint::new(
                [0, 1],
                [JointKind::Hinge; 2],
                Gear::new(leader, ratio),
                [0.0; 2],
                0.0,
            )];
            let h = 1.0 / 240.0;
            // The gear relaxed after the island (its joints' island alone).
            let (mut beside, mut beside_joints, mut beside_gears) =
                (bodies.clone(), joints.clone(), gears.clone());
            let mut islands = joint_islands(&mut beside_joints, &mut [], &beside, &[]);
            begin_joints(&mut beside_joints, &mut [], &mut islands, &mut beside, h, false);
            let (js, bs) = (Shared::new(&mut beside_joints), Shared::new(&mut beside));
            // SAFETY: one thread.
            unsafe { begin_gears(&mut beside_gears, &js, &bs, false) };
            solve_joints(&mut beside_joints, &mut [], &mut islands, &mut beside);
            let bs = Shared::new(&mut beside);
            // SAFETY: one thread.
            unsafe { solve_gears(&mut beside_gears, &bs) };
            let (open, _) = misses(&beside_joints, &beside_gears[0], &mut beside);
            assert!(
                open > 1e-3,
                "seed {seed}: the gear beside left the joints within {open}"
            );
            // In the system: one pass.
            let mut islands = joint_islands(&mut joints, &mut gears, &bodies, &[]);
            assert_eq!(islands.len(), 1);
            assert!(gears[0].direct && joints.iter().all(|j| j.direct));
            assert_eq!(islands[0].rows(), 3 * 5 + 1);
            begin_joints(&mut joints, &mut gears, &mut islands, &mut bodies, h, false);
            let (before, rate_before) = misses(&joints, &gears[0], &mut bodies);
            assert!(
                before > 0.1 && rate_before > 0.1,
                "seed {seed}: {before}, {rate_before}"
            );
            solve_joints(&mut joints, &mut gears, &mut islands, &mut bodies);
            let (rows, rate) = misses(&joints, &gears[0], &mut bodies);
            assert!(
                rows < 1e-9 && rate < 1e-9,
                "seed {seed}: rows {rows}, gear {rate}"
            );
        }
    }

    /// A joint solved with its island holds its own equality block (the
    /// effective masses of its limits with the equality rows held) only in
    /// the sub-steps where one of its limits acts; holding it at every
    /// sub-step's start instead gives the same bits, and the lazy run does
    /// skip it where no limit is pressed.
    #[test]
    fn limits_held_only_where_they_act_give_the_bits_of_limits_held_always() {
        let (bodies, joints) = trees(&mut SplitMix64(11), 4);
        let run = |eager: bool| {
            let (mut bodies, mut joints) = (bodies.clone(), joints.clone());
            let mut islands = joint_islands_in_lanes(&mut joints, &mut [], &bodies, &[], LANES);
            let q0: Vec<DQuat> = bodies.iter().map(|b| b.q).collect();
            let h = 1.0 / 480.0;
            let (mut held, mut skipped) = (0, 0);
            for _ in 0..8 {
                begin_joints(&mut joints, &mut [], &mut islands, &mut bodies, h, true);
                if eager {
                    for j in joints.iter_mut().filter(|j| j.direct) {
                        let m_sum = bodies[j.a as usize].inv_mass + bodies[j.b as usize].inv_mass;
                        j.hold_equality_rows(m_sum);
                    }
                }
                passes(&mut joints, &mut islands, &mut bodies, &q0, h);
                for j in joints.iter().filter(|j| j.direct && j.law.limits.is_some()) {
                    if j.held {
                        held += 1;
                    } else {
                        skipped += 1;
                    }
                }
            }
            let state: Vec<[[u64; 3]; 3]> = bodies
                .iter()
                .map(|b| [b.v, b.w, b.dp].map(|x| x.to_array().map(f64::to_bits)))
                .collect();
            let impulses: Vec<[u64; JOINT_ROWS]> =
                joints.iter().map(|j| j.impulses().map(f64::to_bits)).collect();
            (state, impulses, held, skipped)
        };
        let (state, impulses, held, skipped) = run(false);
        let (state_eager, impulses_eager, _, _) = run(true);
        assert!(joints_with_limits_in_islands(&bodies, &joints) > 0);
        assert!(
            held > 0 && skipped > 0,
            "limits held {held}, skipped {skipped}: the test needs both"
        );
        assert_eq!(state, state_eager);
        assert_eq!(impulses, impulses_eager);
    }

    /// How many joints with limits [`joint_islands`] solves with an island.
    fn joints_with_limits_in_islands(bodies: &[SolverBody], joints: &[JointConstraint]) -> usize {
        let mut joints = joints.to_vec();
        joint_islands_in_lanes(&mut joints, &mut [], bodies, &[], LANES);
        joints
            .iter()
            .filter(|j| j.direct && j.law.limits.is_some())
            .count()
    }

    /// `count` chains of three bodies on ball joints (world - A - B - C,
    /// masses 1 : 0.1 : 10, random velocities) whose ends A and C touch:
    /// a patch of two overlapping points closes the loop A - B - C. The
    /// patches are the chains' candidates for ownership.
    #[allow(clippy::type_complexity)]
    fn looped_chains(
        rng: &mut SplitMix64,
        count: usize,
    ) -> (
        Vec<SolverBody>,
        Vec<JointConstraint>,
        Vec<ManifoldConstraint>,
        Vec<PointConstraint>,
        Vec<OwnableContact>,
    ) {
        let mut bodies = vec![SolverBody::fixed()];
        let (mut joints, mut manifolds, mut points, mut contacts) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let law = plain_law(JointKind::Ball);
        for t in 0..count {
            let first = bodies.len() as u32;
            let origin = DVec3::new(3.0 * t as f64, 0.0, 0.0);
            // Folded: A beside the pivot, B beyond and above it, C back over A.
            let centres = [
                DVec3::new(0.1, 0.0, 0.0),
                DVec3::new(0.15, 0.0, 0.1),
                DVec3::new(0.1, 0.0, 0.2),
            ];
            for mass in [1.0, 0.1, 10.0] {
                let inertia = DVec3::splat(1.0 / (0.4 * mass * 0.05 * 0.05));
                bodies.push(SolverBody::new(
                    vector(rng, 1.0),
                    vector(rng, 3.0),
                    1.0 / mass,
                    inertia,
                    rotation(rng),
                ));
            }
            let anchors = [
                DVec3::ZERO,
                DVec3::new(0.15, 0.0, 0.05),
                DVec3::new(0.12, 0.0, 0.15),
            ];
            for k in 0..3u32 {
                let (a, b) = (first + k, if k == 0 { 0 } else { first + k - 1 });
                let place = |i: u32| {
                    if i == 0 {
                        (DVec3::ZERO, DQuat::IDENTITY)
                    } else {
                        (origin + centres[(i - first) as usize], bodies[i as usize].q)
                    }
                };
                let ((xa, qa), (xb, qb)) = (place(a), place(b));
                let anchor = origin + anchors[k as usize];
                let local = |x: DVec3, q: DQuat| Pose {
                    position: q.inverse() * (anchor - x),
                    rotation: DQuat::IDENTITY,
                };
                joints.push(JointConstraint::new(
                    (a, b),
                    [xa, xb],
                    [qa, qb],
                    [local(xa, qa), local(xb, qb)],
                    law,
                    &[0.0; JOINT_ROWS],
                ));
            }
            // A (first) below C (first + 2): the normal from C to A.
            let (a, c) = (first, first + 2);
            let normal = (DVec3::new(0.0, 0.0, -1.0) + vector(rng, 0.2)).normalize();
            // C moves into A.
            bodies[c as usize].v += normal * 2.0;
            let at = points.len() as u32;
            for _ in 0..2 {
                let r_a = -normal * 0.05 + vector(rng, 0.02);
                let r_b = normal * 0.05 + vector(rng, 0.02);
                points.push(PointConstraint::new(normal, r_a, r_b, -0.002, 0.0));
            }
            let mut m = ManifoldConstraint::new(a, c, at, 2, normal, 0.0, 0.0, DVec3::ZERO, 0.0);
            super::super::constraint::prepare(&mut m, &mut points, &bodies);
            contacts.push(OwnableContact {
                patch: manifolds.len() as u32,
                body: a,
                other: c,
                points: 2,
            });
            manifolds.push(m);
        }
        (bodies, joints, manifolds, points, contacts)
    }

    /// One looped chain drawn from `rng`, its island found and begun as a
    /// sub-step of 1/480 s begins it: bodies, joints, patches, points and
    /// islands.
    #[allow(clippy::type_complexity)]
    fn begun_looped_chain(
        rng: &mut SplitMix64,
    ) -> (
        Vec<SolverBody>,
        Vec<JointConstraint>,
        Vec<ManifoldConstraint>,
        Vec<PointConstraint>,
        Vec<JointIsland>,
    ) {
        let (mut bodies, mut joints, mut manifolds, mut points, contacts) = looped_chains(rng, 1);
        let mut islands = joint_islands(&mut joints, &mut [], &bodies, &contacts);
        with_views(
            &mut joints,
            &mut bodies,
            &mut manifolds,
            &mut points,
            |js, gs, bs, cs| {
                // SAFETY: one thread.
                unsafe { islands[0].begin(js, gs, bs, Some(cs), 1.0 / 480.0, false) };
            },
        );
        (bodies, joints, manifolds, points, islands)
    }

    /// Runs `f` with the shared views the island passes take of one
    /// thread's joints, bodies and contact arrays (no gears).
    fn with_views(
        joints: &mut [JointConstraint],
        bodies: &mut [SolverBody],
        manifolds: &mut [ManifoldConstraint],
        points: &mut [PointConstraint],
        f: impl FnOnce(&Shared<JointConstraint>, &Shared<GearConstraint>, &Shared<SolverBody>, &PatchArrays),
    ) {
        let (js, bs) = (Shared::new(joints), Shared::new(bodies));
        let no_gears = Shared::new(&mut [] as &mut [GearConstraint]);
        let (ms, ps) = (Shared::new(manifolds), Shared::new(points));
        let patches = PatchArrays {
            manifolds: &ms,
            points: &ps,
        };
        f(&js, &no_gears, &bs, &patches);
    }

    /// After one velocity pass of an island that owns the patch closing its
    /// loop, the joints and the contact together satisfy the conditions
    /// that define the exact answer: every joint row at its target, and at
    /// every contact point `lambda >= 0`, `w + c lambda >= 0` and
    /// `lambda (w + c lambda) = 0`, with `w = v_n` and `c` the point's compliance
    /// (`COMPLIANCE_SHARE` of its own inverse mass; the pass starts from no
    /// impulse, so its change is all of `lambda`). (Relaxed one after the
    /// other, the contact's last update leaves the joint rows off by what it
    /// moved the light link.)
    #[test]
    fn an_owned_patch_and_its_islands_joints_are_solved_exactly() {
        for seed in 0..20 {
            let (mut bodies, mut joints, mut manifolds, mut points, mut islands) =
                begun_looped_chain(&mut SplitMix64(seed));
            assert_eq!(islands.len(), 1);
            assert_eq!(islands[0].owned_patches().collect::<Vec<_>>(), vec![0]);
            with_views(
                &mut joints,
                &mut bodies,
                &mut manifolds,
                &mut points,
                |js, gs, bs, cs| {
                    // SAFETY: one thread.
                    unsafe { islands[0].solve(js, gs, bs, Some(cs)) };
                },
            );
            let scale = bodies.iter().map(|b| b.v.length()).fold(1.0, f64::max);
            for j in &joints {
                let (a, b) = (&bodies[j.a as usize], &bodies[j.b as usize]);
                for r in &j.rows[..j.n_eq] {
                    let jv = r.lin.dot(a.v - b.v) + r.ang_a.dot(a.w) + r.ang_b.dot(b.w);
                    assert!(
                        (jv + r.bias).abs() < 1e-9 * scale,
                        "seed {seed}: joint row off by {}",
                        jv + r.bias
                    );
                }
            }
            let m = &manifolds[0];
            let (a, c) = (&bodies[m.a as usize], &bodies[m.b as usize]);
            let mut pressed = 0.0;
            for p in &points {
                let own = p.row.inverse_mass(p.normal, m.inv_mass[0], m.inv_mass[1]);
                let w = p.normal.dot(a.v - c.v) + p.row.ra_x_d.dot(a.w) - p.row.rb_x_d.dot(c.w)
                    + COMPLIANCE_SHARE * own * p.normal_impulse;
                assert!(
                    p.normal_impulse >= 0.0 && w > -1e-9 * scale,
                    "seed {seed}: {} {w}",
                    p.normal_impulse
                );
                assert!((p.normal_impulse * w).abs() < 1e-9 * scale * scale, "seed {seed}");
                pressed += p.normal_impulse;
            }
            assert!(pressed > 0.0, "seed {seed}: the contact did not act");
        }
    }

    /// Solves of three columns at once (`Factor::solve` on lanes, the fourth
    /// lane padding) give each column the bits of a solve of its own, with
    /// the factor of a real island (a looped chain's, begun as a sub-step
    /// begins it).
    #[test]
    fn columns_solved_side_by_side_get_the_bits_of_one_solve_each() {
        for seed in 0..10 {
            let mut rng = SplitMix64(seed);
            let islands = begun_looped_chain(&mut rng).4;
            let island = &islands[0];
            let n = island.rows();
            assert!(n >= 9, "three ball joints make nine rows");
            let columns: Vec<Vec<f64>> = (0..3)
                .map(|_| (0..n).map(|_| rng.range(-5.0, 5.0)).collect())
                .collect();
            let mut side_by_side: Vec<Lane> = (0..n)
                .map(|r| Lane::new([columns[0][r], columns[1][r], columns[2][r], 0.0]))
                .collect();
            island.factor.solve(&island.profile, &mut side_by_side);
            for (l, column) in columns.iter().enumerate() {
                let mut alone = column.clone();
                island.factor.solve(&island.profile, &mut alone);
                for (r, x) in alone.iter().enumerate() {
                    assert_eq!(
                        side_by_side[r].to_array()[l].to_bits(),
                        x.to_bits(),
                        "seed {seed}, row {r}"
                    );
                }
            }
            assert!(
                side_by_side.iter().all(|x| x.to_array()[3] == 0.0),
                "zeros solve to zeros"
            );
        }
    }

    /// Islands that own patches get, in the lanes of one unit, the bits
    /// they get alone (velocity passes and push-out, several sub-steps).
    #[test]
    fn islands_owning_patches_get_the_same_bits_in_lanes() {
        let (bodies, joints, manifolds, points, contacts) = looped_chains(&mut SplitMix64(11), 5);
        let params = SolverParams {
            push_out_fraction: 0.2,
            allowed_penetration: 0.0005,
            max_push_out_speed: 3.0,
            restitution_threshold: 1.0,
        };
        let run = |max_lanes: usize| {
            let (mut bodies, mut joints) = (bodies.clone(), joints.clone());
            let (mut manifolds, mut points) = (manifolds.clone(), points.clone());
            let mut islands = joint_islands_in_lanes(&mut joints, &mut [], &bodies, &contacts, max_lanes);
            let q0: Vec<DQuat> = bodies.iter().map(|b| b.q).collect();
            let h = 1.0 / 480.0;
            for sub in 0..6 {
                with_views(
                    &mut joints,
                    &mut bodies,
                    &mut manifolds,
                    &mut points,
                    |js, gs, bs, cs| {
                        for island in &mut islands {
                            // SAFETY: one thread.
                            unsafe {
                                island.begin(js, gs, bs, Some(cs), h, sub > 0);
                                island.solve(js, gs, bs, Some(cs));
                                island.solve(js, gs, bs, Some(cs));
                                island.push(js, gs, bs, Some((cs, &params)), 1.0 / h);
                            }
                        }
                    },
                );
                integrate_positions(&mut bodies, &q0, h);
            }
            let lanes: Vec<usize> = islands.iter().map(JointIsland::lanes).collect();
            let state: Vec<[u64; 9]> = bodies
                .iter()
                .map(|b| {
                    let [v, w, dp] = [b.v, b.w, b.dp].map(|x| x.to_array().map(f64::to_bits));
                    [v[0], v[1], v[2], w[0], w[1], w[2], dp[0], dp[1], dp[2]]
                })
                .collect();
            let impulses: Vec<u64> = points.iter().map(|p| p.normal_impulse.to_bits()).collect();
            (lanes, state, impulses)
        };
        let (lanes, state, impulses) = run(LANES);
        let (alone, state_alone, impulses_alone) = run(1);
        assert_eq!((lanes, alone), (vec![4, 1], vec![1; 5]));
        assert!(impulses.iter().any(|&i| f64::from_bits(i) > 0.0));
        assert_eq!(state, state_alone);
        assert_eq!(impulses, impulses_alone);
    }
}
