//! [`Stage::Solve`](crate::world::Stage::Solve): the contact constraints of
//! the step, in the timed parts of [`SolveStage`]: prepare (solver bodies,
//! rows, quarantine), restitution, then per sub-step integrate velocities,
//! warm start, iterate, relax (push-out) and integrate positions; finally
//! the impulses are stored for the next step's warm start and reported with
//! the contacts. The solver itself lives in `crate::solver::contact_solver`.

use super::margins::{is_active, velocities};
use super::quarantine;
use super::StepFrame;
use crate::body::BodyKind;
use crate::integrate::Integrator;
use crate::pool::WorkerPool;
use crate::solver::contact_solver::{
    self, begin_gears, push_gears, solve_gears, BundleKind, Coloring, GearConstraint, JointConstraint,
    ManifoldConstraint, OwnableContact, PointConstraint, RecordSource, Shared, SolvedPatch, SolvedPoint,
    SolverArrays, SolverBody, SolverParams, ThreadFlow, VelocityPass, BODIES_PER_BLOCK,
};
use crate::world::manifold::{self, CachedContact, CachedPatch};
use crate::world::patches::{ContactPoints, PatchExtras, PreparedPatch};
use crate::world::report::{SolveStage, StepReport};
use crate::world::step::frame::SolverFrame;
use crate::world::{Arena, BodyEntry, SolverKind, World, WorldContact};
use std::sync::atomic::{AtomicU32, AtomicU64, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;
use tumble_collide::{DMat3, DQuat, DVec3};

/// Overlap (m) that earns a step one more velocity iteration and one more
/// push-out pass per sub-step, per whole multiple, up to
/// [`MAX_DEEP_ITERATIONS`] and [`MAX_DEEP_PASSES`] ([`deep_load`]).
pub const DEEP_OVERLAP_UNIT: f64 = 0.005;

/// Most velocity iterations per sub-step added for deep overlap.
pub const MAX_DEEP_ITERATIONS: u32 = 2;

/// Most push-out passes per sub-step added for deep overlap.
pub const MAX_DEEP_PASSES: u32 = 3;

/// What a step adds per sub-step for deep overlap ([`deep_load`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DeepLoad {
    /// Velocity iterations added to `WorldSettings::iterations`.
    pub iterations: u32,
    /// Push-out passes added to `WorldSettings::push_out_iterations`.
    pub push_out_passes: u32,
}

/// The load of a step whose deepest overlap at its start (the narrow
/// phase's) is `deepest`: one more velocity iteration and one more push-out
/// pass per sub-step per whole [`DEEP_OVERLAP_UNIT`], at most
/// [`MAX_DEEP_ITERATIONS`] and [`MAX_DEEP_PASSES`]. Load where it is deep
/// (issue 13): one Gauss-Seidel pass carries a correction one contact layer
/// further. With one push-out pass the 10,000-body pile, settled, held
/// 17 cm overlaps for 300 steps (with these it settles to 5 mm); with two
/// velocity iterations its layers landing on each other sank 19-31 cm into
/// one another (three jittered starts; 11-12 cm with the extra iterations,
/// which also settle it sooner and so cost nothing:
/// `JITTER=seed profile_stages pile10000 200 2`). More passes or more
/// iterations than these did not go shallower. A resting stack within the
/// unit pays nothing.
pub fn deep_load(deepest: f64) -> DeepLoad {
    let units = if deepest >= DEEP_OVERLAP_UNIT {
        (deepest / DEEP_OVERLAP_UNIT).min(f64::from(u32::MAX)) as u32
    } else {
        0
    };
    DeepLoad {
        iterations: units.min(MAX_DEEP_ITERATIONS),
        push_out_passes: units.min(MAX_DEEP_PASSES),
    }
}

/// Times the parts of the solve stage into the report.
struct PartClock(Instant);

impl PartClock {
    fn lap(&mut self, report: &mut StepReport, part: SolveStage) {
        let now = Instant::now();
        report.solve_time[part as usize] += now - self.0;
        self.0 = now;
    }
}

/// Per solver body: linear acceleration (gravity and force / mass), torque,
/// linear and angular damping, constant over the step.
type Drive = (DVec3, DVec3, f64, f64);

impl World {
    pub(super) fn solve_stage(&mut self, f: &mut StepFrame) {
        let mut clock = PartClock(Instant::now());
        let s = f.settings.clone();
        let dt = s.dt;
        let semi_implicit = s.integrator == Integrator::SemiImplicitEuler;
        let (drive, coloring, keys, layout) = self.prepare_solver(f, semi_implicit);
        let records = PatchRecords {
            layout: &layout,
            patches: &f.patches,
            prepared: &f.points,
            extras: &f.patch_extras,
        };
        let sf = &mut f.solver;
        // Before any row is built: contact rows and joint rows must see the
        // same inertia (see `geometric_stiffness`).
        apply_geometric_stiffness(&mut sf.bodies, &sf.geometric);
        let report = &mut f.report;
        report.colors = coloring.colors.len() + usize::from(!coloring.overflow.is_empty());
        report.joints = sf.joints.len();
        let q0: Vec<DQuat> = sf.bodies.iter().map(|b| b.q).collect();
        let substeps = if semi_implicit { s.substeps } else { 1 };
        // A world without push-out (0 passes) stays without.
        let deep = deep_load(report.max_penetration);
        let iterations = s.iterations + deep.iterations;
        let push_out_iterations = match s.push_out_iterations {
            0 => 0,
            n => n + deep.push_out_passes,
        };
        let h = dt / substeps as f64;
        let params = SolverParams {
            push_out_fraction: s.push_out_fraction,
            allowed_penetration: s.allowed_penetration,
            max_push_out_speed: s.max_push_out_speed,
            restitution_threshold: s.restitution_threshold,
        };
        // With no contacts there is nothing to solve (and the dense solver
        // has no 0 x 0 case).
        let mut exact = s.solver == SolverKind::Lemke && !sf.points.is_empty();
        if exact && sf.points.len() > contact_solver::EXACT_MAX_CONTACTS {
            report.warnings.push(format!(
                "solver = lemke: {} contacts exceed the exact solver's limit of {}; PGS ran instead",
                sf.points.len(),
                contact_solver::EXACT_MAX_CONTACTS
            ));
            exact = false;
        }
        clock.lap(report, SolveStage::Prepare);

        let linear_accel: Vec<DVec3> = drive.iter().map(|a| a.0).collect();
        // The serial end of the prepare part (after the patches are
        // prepared): restitution (Newton's law on colliding contacts).
        let bounce =
            |manifolds: &[ManifoldConstraint], points: &mut [PointConstraint], bodies: &mut [SolverBody]| {
                contact_solver::resolve_collisions(manifolds, points, bodies, &linear_accel, &params, dt, h);
            };

        if exact {
            // Each record written, then prepared (its rows read its points only).
            for (k, m) in sf.manifolds.iter_mut().enumerate() {
                records.renew(k, m, &mut sf.points[records.points(k)]);
                contact_solver::prepare(m, &mut sf.points, &sf.bodies);
            }
            clock.lap(report, SolveStage::Prepare);
            bounce(&sf.manifolds, &mut sf.points, &mut sf.bodies);
            clock.lap(report, SolveStage::Restitution);
            exact_substeps(
                sf,
                report,
                &mut clock,
                &drive,
                &q0,
                substeps,
                h,
                (iterations, push_out_iterations),
                &params,
            );
            self.scratch.solved.gather(&sf.manifolds, &sf.points);
        } else {
            let joint_coloring = std::mem::take(&mut sf.joint_coloring);
            let mut wide = std::mem::take(&mut self.scratch.wide);
            wide.plan(&coloring, &sf.bundle_kinds, &keys, sf.bodies.len());
            let (mut ones, mut twos, mut fours) = (
                std::mem::take(&mut wide.ones),
                std::mem::take(&mut wide.twos),
                std::mem::take(&mut wide.fours),
            );
            let loose_gears = sf.gears.iter().any(|g| !g.direct);
            let threads = f.pool.threads();
            let mut flows = std::mem::take(&mut self.scratch.flows);
            flows.resize_with(threads, ThreadFlow::default);
            let owners: Vec<AtomicU32> = if threads > 1 {
                (0..sf.bodies.len()).map(|_| AtomicU32::new(0)).collect()
            } else {
                Vec::new()
            };
            let mut solved = std::mem::take(&mut self.scratch.solved);
            solved.resize(sf.manifolds.len(), sf.points.len());
            let arrays = SolverArrays {
                ones: Shared::new(&mut ones),
                twos: Shared::new(&mut twos),
                fours: Shared::new(&mut fours),
                wide: &wide,
                manifolds: Shared::new(&mut sf.manifolds),
                points: Shared::new(&mut sf.points),
                bodies: Shared::new(&mut sf.bodies),
                joints: Shared::new(&mut sf.joints),
                joint_islands: Shared::new(&mut sf.joint_islands),
                coloring: &coloring,
                joint_coloring: &joint_coloring,
                gears: Shared::new(&mut sf.gears),
                loose_gears,
                flows: Shared::new(&mut flows),
                owners: &owners,
                solved: solved.writer(),
            };
            let lead_only = Mutex::new((&mut clock, &mut *report));
            let pushed = AtomicUsize::new(0);
            let largest_residual = AtomicU64::new(0);
            // Nothing to split (no colour batch or only a small problem's
            // levels, few bodies): one thread.
            let pool = if (coloring.colors.is_empty() || coloring.levels)
                && joint_coloring.colors.is_empty()
                && arrays.joint_islands.len() < 2
                && arrays.bodies.len() < 2 * BODIES_PER_BLOCK
            {
                WorkerPool::serial()
            } else {
                f.pool.clone()
            };
            pool.team(|team| {
                let lead = team.index() == 0;
                let lap = |part: SolveStage| {
                    if lead {
                        let mut held = lead_only.lock().unwrap_or_else(|e| e.into_inner());
                        let (clock, report) = &mut *held;
                        clock.lap(report, part);
                    }
                };
                // SAFETY (here and in every pass): the whole team calls it;
                // nothing else touches the arrays.
                unsafe {
                    arrays.prepare(team, &records, |arrays| {
                        lap(SolveStage::Prepare);
                        // SAFETY: thread 0 alone, between two barriers.
                        let (manifolds, points, bodies) = (
                            arrays.manifolds.as_slice(),
                            arrays.points.range_mut(0..arrays.points.len()),
                            arrays.bodies.range_mut(0..arrays.bodies.len()),
                        );
                        bounce(manifolds, points, bodies);
                        lap(SolveStage::Restitution);
                    })
                };
                lap(SolveStage::Prepare);
                for sub in 0..substeps {
                    for r in arrays.body_blocks(team) {
                        // SAFETY: the blocks of bodies are disjoint between threads.
                        let bodies = unsafe { arrays.bodies.range_mut(r.clone()) };
                        for (b, &(a, tau, ld, ad)) in bodies.iter_mut().zip(&drive[r]) {
                            if !b.dynamic {
                                continue;
                            }
                            b.v = (b.v + a * h) / (1.0 + ld * h);
                            b.w = (b.w + b.inv_inertia * tau * h) / (1.0 + ad * h);
                        }
                    }
                    team.barrier();
                    lap(SolveStage::IntegrateVelocities);
                    // SAFETY (every pass): the whole team calls it with the
                    // same colouring; nothing else touches the arrays.
                    unsafe {
                        arrays.begin_substep(team, h, true);
                        arrays.gear_pass(team, |g| begin_gears(g, &arrays.joints, &arrays.bodies, true));
                    }
                    lap(SolveStage::WarmStart);
                    // The islands are begun in the first velocity pass, and
                    // the sub-step's first push-out pass is made with the
                    // last (`VelocityPass`), as pass number `first_push`.
                    let first_push = (sub * push_out_iterations + 1) as usize;
                    let push_gears_as = |pass: usize| {
                        // SAFETY: as every pass (the team calls it).
                        unsafe {
                            arrays.gear_pass(team, |g| {
                                if push_gears(g, &arrays.bodies, 1.0 / h) {
                                    pushed.fetch_max(pass, Ordering::Relaxed);
                                }
                            })
                        };
                    };
                    for k in 0..iterations {
                        let then_push = k + 1 == iterations && push_out_iterations > 0;
                        let visit = VelocityPass {
                            begin_islands: (k == 0).then_some(true),
                            then_push: then_push.then_some((&params, first_push, &pushed)),
                        };
                        unsafe {
                            arrays.solve(team, h, visit);
                            arrays.gear_pass(team, |g| solve_gears(g, &arrays.bodies));
                        }
                        if then_push {
                            push_gears_as(first_push);
                        }
                    }
                    if sub + 1 == substeps {
                        // SAFETY: the whole team reads; nothing writes.
                        let residual = unsafe { arrays.residual(team, h, &largest_residual) };
                        if lead {
                            lead_only
                                .lock()
                                .unwrap_or_else(|e| e.into_inner())
                                .1
                                .solver_residual = residual;
                        }
                    }
                    lap(SolveStage::Iterate);
                    for pass in 1..=push_out_iterations {
                        let first = pass == 1;
                        let pass = (sub * push_out_iterations + pass) as usize;
                        // (The first was made with the last velocity pass.)
                        if !first {
                            unsafe { arrays.push_out(team, &params, h, pass, false, &pushed) };
                            push_gears_as(pass);
                        }
                        // `<`, not `!=`: a thread that went on may already
                        // have raised `pushed` to `pass + 1` while a slower
                        // one reads it; only a thread that saw `pass` goes
                        // on, so "at least `pass`" is the same answer on
                        // every thread (with `!=` the slow one stopped and
                        // the team waited for it forever).
                        if pushed.load(Ordering::Relaxed) < pass {
                            break;
                        }
                    }
                    lap(SolveStage::Relax);
                    for r in arrays.body_blocks(team) {
                        // SAFETY: the blocks of bodies are disjoint between threads.
                        let bodies = unsafe { arrays.bodies.range_mut(r.clone()) };
                        contact_solver::integrate_positions(bodies, &q0[r], h);
                    }
                    team.barrier();
                    lap(SolveStage::IntegratePositions);
                }
                // SAFETY: as above.
                unsafe { arrays.unpack(team) };
            });
            sf.joint_coloring = joint_coloring;
            (wide.ones, wide.twos, wide.fours) = (ones, twos, fours);
            self.scratch.wide = wide;
            self.scratch.flows = flows;
            self.scratch.solved = solved;
        }
        report.substeps = substeps;
        report.iterations = iterations;
        self.store_impulses(f, substeps);
        self.store_joint_impulses(f, h);
        clock.lap(&mut f.report, SolveStage::StoreImpulses);
    }

    /// [`SolveStage::Prepare`]: one solver body per active body (entry 0 is
    /// the shared immovable body for static and sleeping ones), the forces
    /// of the step; bodies whose forces or velocities are not finite, or
    /// would run away, are frozen (quarantine before solving, so NaN cannot
    /// travel through contacts); the patches coloured, and the layout of
    /// one record per patch and point in colour order ([`RecordLayout`]:
    /// the solve's team writes each record and prepares its rows, or fills
    /// a bundle's lane from it, `SolverArrays::prepare`).
    fn prepare_solver(
        &self,
        f: &mut StepFrame,
        semi_implicit: bool,
    ) -> (Vec<Drive>, Coloring, Vec<u32>, RecordLayout) {
        let n_slots = f.n_slots;
        let sf = &mut f.solver;
        sf.slot_to_solver = vec![0u32; n_slots];
        sf.bodies.clear();
        sf.bodies.reserve(n_slots + 1);
        sf.bodies.push(SolverBody::fixed());
        sf.slots = Vec::with_capacity(n_slots + 1);
        sf.slots.push(u32::MAX);
        sf.has_contact = vec![false; n_slots];
        for p in &f.patches {
            sf.has_contact[p.key.0 as usize] = true;
            sf.has_contact[p.key.1 as usize] = true;
        }
        for (_, j) in self.joints.iter() {
            let (a, b) = j.slots();
            for slot in [Some(a), b].into_iter().flatten() {
                sf.has_contact[slot as usize] = true;
            }
        }
        // Each solver body with its forces and quarantine's first check (see
        // `quarantine`: frozen before solving), in one pass over the slots:
        // three passes read each body's entry three times (0.5 % of the
        // large pyramid's data misses at a 1 MiB last level).
        let (gravity, dt) = (f.settings.gravity, f.settings.dt);
        let mut drive: Vec<Drive> = Vec::with_capacity(n_slots + 1);
        drive.push((DVec3::ZERO, DVec3::ZERO, 0.0, 0.0));
        sf.frozen.clear();
        sf.frozen.push(false);
        for i in 0..n_slots as u32 {
            let Some(e) = self.bodies.at(i) else { continue };
            if !is_active(e) {
                continue;
            }
            // Free bodies of a world with an explicit integrator are advanced by
            // that integrator in the integrate stage, not by the solver.
            if e.body.kind() == BodyKind::Dynamic && !semi_implicit && !sf.has_contact[i as usize] {
                continue;
            }
            let (v, w) = velocities(e);
            let dynamic = e.body.kind() == BodyKind::Dynamic;
            sf.slot_to_solver[i as usize] = sf.bodies.len() as u32;
            sf.slots.push(i);
            let mut body = if dynamic {
                SolverBody::new(
                    v,
                    w,
                    e.body.inv_mass(),
                    e.body.inv_principal_inertia(),
                    e.body.orientation(),
                )
            } else {
                SolverBody::new(v, w, 0.0, DVec3::ZERO, e.body.orientation())
            };
            body.kinematic = !dynamic;
            let (a, tau, linear_damping, angular_damping) = if dynamic {
                (
                    gravity + e.body.force() * e.body.inv_mass(),
                    e.body.torque(),
                    e.body.linear_damping(),
                    e.body.angular_damping(),
                )
            } else {
                (DVec3::ZERO, DVec3::ZERO, 0.0, 0.0)
            };
            let frozen = quarantine::must_freeze(body.v, body.w, a, body.inv_inertia * tau, e.radius, dt);
            if frozen {
                body.freeze();
            }
            sf.bodies.push(body);
            drive.push((a, tau, linear_damping, angular_damping));
            sf.frozen.push(frozen);
        }
        f.report.awake_bodies = sf.bodies.len() - 1;
        // The joints, and the patches their islands own: those between two
        // bodies of one island, of a block's points at most (the exact
        // solver runs every patch itself).
        let slot_to_solver = &sf.slot_to_solver;
        let pairs: Vec<(u32, u32)> = f
            .patches
            .iter()
            .map(|p| (slot_to_solver[p.key.0 as usize], slot_to_solver[p.key.1 as usize]))
            .collect();
        let candidates: Vec<OwnableContact> =
            if f.settings.solver == SolverKind::Lemke || self.joints.is_empty() {
                Vec::new()
            } else {
                let dynamic = |b: u32| sf.bodies[b as usize].dynamic;
                // A patch an island may own (of any number of points:
                // `joint_island::own_patches` decides): on two dynamic bodies, or on a
                // dynamic body and a static or kinematic one (which then comes
                // second: the island looks a patch up by its dynamic body).
                (0..pairs.len())
                    .filter(|&k| {
                        let (a, b) = pairs[k];
                        dynamic(a) || dynamic(b)
                    })
                    .map(|k| {
                        let (body, other) = match pairs[k] {
                            (a, b) if dynamic(a) => (a, b),
                            (a, b) => (b, a),
                        };
                        OwnableContact {
                            patch: k as u32,
                            body,
                            other,
                            points: f.patches[k].count,
                        }
                    })
                    .collect()
            };
        self.prepare_joints(sf, &candidates, &f.pool);
        let mut owned = vec![false; pairs.len()];
        for island in &sf.joint_islands {
            island.owned_patches().for_each(|k| owned[k as usize] = true);
        }
        // The other patches coloured (frozen bodies count as static), their
        // rows built in colour order with each patch's points together.
        let (coloring, order) = contact_solver::color_patches_except(&pairs, &sf.bodies, &owned);
        // Each patch's first point in colour order.
        sf.position = vec![0; f.patches.len()];
        let mut firsts = Vec::with_capacity(order.len() + 1);
        let mut total = 0u32;
        for (k, &i) in order.iter().enumerate() {
            sf.position[i as usize] = k as u32;
            firsts.push(total);
            total += f.patches[i as usize].count;
        }
        firsts.push(total);
        // The records are written where they are prepared
        // (`SolverArrays::prepare`, from `PatchRecords`; a bundled patch
        // that does not bounce only into its bundle's lane); here only each
        // one's bundle, which the plan of the wide batches reads first. The
        // arrays keep their length from the last step (`StepFrame::recycle`)
        // and are only cut or grown to this step's, so that each record is
        // written once.
        let (placeholder_point, placeholder_patch) = placeholders();
        sf.points.resize(total as usize, placeholder_point);
        sf.manifolds.resize(order.len(), placeholder_patch);
        sf.bundle_kinds.clear();
        sf.bundle_kinds.extend(order.iter().map(|&i| {
            let p = &f.patches[i as usize];
            let curved = p
                .extras(&f.patch_extras)
                .is_some_and(|x| x.curvature != DMat3::ZERO);
            BundleKind::for_patch(p.count, curved, p.warm_twist)
        }));
        let position = &sf.position;
        for island in &mut sf.joint_islands {
            island.renumber_patches(|k| position[k as usize]);
        }
        // Each record's key body, by which a team deals the patches
        // (`WideBatches::plan`): a dynamic body of its pair.
        let keys = order
            .iter()
            .map(|&i| match pairs[i as usize] {
                (a, _) if sf.bodies[a as usize].dynamic => a,
                (_, b) => b,
            })
            .collect();
        (drive, coloring, keys, RecordLayout { order, firsts, pairs })
    }

    /// The joint rows: one record per joint that has a body the solver
    /// moves (a joint between two resting bodies waits), with the sides'
    /// step-start poses, coloured like the patches.
    fn prepare_joints(&self, sf: &mut SolverFrame, contacts: &[OwnableContact], pool: &WorkerPool) {
        // Coloured first, from the body pairs alone, so that each record is
        // built once, in colour order, into the kept array (a joint record
        // is large: built and then copied into place, they cost a ragdoll
        // pile more than its joint islands' factorisations).
        let mut pairs = Vec::new();
        let mut sides = Vec::new();
        for (id, j) in self.joints.iter() {
            let (a, b) = j.slots();
            let side = |slot: Option<u32>| match slot.and_then(|s| self.bodies.at(s).map(|e| (s, e))) {
                Some((s, e)) => (
                    sf.slot_to_solver[s as usize],
                    e.body.position(),
                    e.body.orientation(),
                ),
                None => (0, DVec3::ZERO, DQuat::IDENTITY),
            };
            let (ia, xa, qa) = side(Some(a));
            let (ib, xb, qb) = side(b);
            if !(sf.bodies[ia as usize].dynamic || sf.bodies[ib as usize].dynamic) {
                continue;
            }
            pairs.push((ia, ib));
            sides.push((id.index, [xa, xb], [qa, qb]));
        }
        let (coloring, order) = contact_solver::color_joints(&pairs, &sf.bodies);
        // The last step's records renewed in place (`JointConstraint::renew`:
        // whichever joint each was), new ones added after them.
        // Renewed on the pool a run of records at a time (a record depends
        // on its joint alone, so the same bits however they are cut).
        let listed: Vec<u32> = order
            .into_iter()
            .filter(|&k| self.joints.at(sides[k as usize].0).is_some())
            .collect();
        sf.joint_slots.clear();
        sf.joint_slots.extend(listed.iter().map(|&k| sides[k as usize].0));
        sf.joints.truncate(listed.len());
        let record_of = |k: u32| {
            let (slot, x0, q0) = sides[k as usize];
            let j = self.joints.at(slot).expect("listed above");
            (pairs[k as usize], x0, q0, j)
        };
        let run = (listed.len() / (pool.threads() * LAYOUT_RUNS_PER_THREAD)).max(LAYOUT_MIN_RUN);
        let mut runs: Vec<(&[u32], &mut [JointConstraint])> =
            listed.chunks(run).zip(sf.joints.chunks_mut(run)).collect();
        pool.for_each_mut(&mut runs, |_, (keys, records)| {
            for (&k, record) in keys.iter().zip(records.iter_mut()) {
                let (pair, x0, q0, j) = record_of(k);
                record.renew(pair, x0, q0, j.local, j.law, &j.impulses);
            }
        });
        for &k in &listed[sf.joints.len()..] {
            let (pair, x0, q0, j) = record_of(k);
            sf.joints
                .push(JointConstraint::new(pair, x0, q0, j.local, j.law, &j.impulses));
        }
        sf.joint_coloring = coloring;
        self.prepare_gears(sf);
        contact_solver::keep_joint_islands(
            &mut sf.joint_islands,
            &mut sf.joint_island_key,
            &mut sf.joints,
            &mut sf.gears,
            &sf.bodies,
            contacts,
        );
        self.geometric_stiffness(sf);
    }

    /// One gear record per follower joint whose gear's leader is among the
    /// solver's joints too (their bodies share an island, so both are there
    /// or neither, unless the leader moves no dynamic body: a gear does
    /// not follow a static or kinematic leader), with the coordinates at
    /// the step's start.
    fn prepare_gears(&self, sf: &mut SolverFrame) {
        sf.gears.clear();
        sf.gear_slots.clear();
        let mut record_of = vec![u32::MAX; self.joints.slot_count()];
        for (k, &slot) in sf.joint_slots.iter().enumerate() {
            record_of[slot as usize] = k as u32;
        }
        for (id, follower) in self.joints.iter() {
            let Some(state) = follower.gear else { continue };
            let Some(leader) = self.joints.get(state.gear.leader) else {
                continue;
            };
            let records = [
                record_of[state.gear.leader.index as usize],
                record_of[id.index as usize],
            ];
            if records.contains(&u32::MAX) {
                continue;
            }
            sf.gears.push(GearConstraint::new(
                records,
                [leader.desc.kind, follower.desc.kind],
                state.gear,
                self.gear_coordinates(leader, follower, &state),
                state.impulse,
            ));
            sf.gear_slots.push(id.index);
        }
    }

    /// Geometric stiffness (Andrews, Teichmann and Kry, "Geometric stiffness
    /// for real-time constrained multibody dynamics", 2017), diagonal form:
    /// a joint force `f` at lever `r` on a body makes its rotation stiff by
    /// about `|f| |r| + |torque|` (the force turns with the body), which the
    /// velocity-level rows treat explicitly. A light link between heavy ones
    /// then has transverse modes of `sqrt(f / (m l))` that a sub-step cannot
    /// follow: a 20-link chain of 0.1 kg links holding a swinging 10 kg
    /// weight blew up within a second at 8 sub-steps. Adding `h^2` times
    /// that stiffness to the body's rotational inertia in the solver (from
    /// the last step's joint forces) keeps those modes stable; it vanishes
    /// as `h^2` and is not applied to the momentum written back.
    ///
    /// This sets the added inertia per solver body (`SolverFrame::geometric`);
    /// [`apply_geometric_stiffness`] adds it to the bodies before any row is
    /// built. Every row of the solve must see the same inertia: until
    /// 2026-11-28 it was added after the contact patches were prepared, so
    /// the first sub-step's contact rows (rebuilt at later sub-steps) applied
    /// their impulses through the plain inertia while the joint rows used the
    /// stiffened one. The passes are then no longer projections in one
    /// metric, and where a contact closes a loop in a joint island (its
    /// block `S` built from both) they can diverge: at one sub-step per step
    /// (every sub-step a first one) the ragdoll pile gained 1e16 J within 70
    /// steps at 8 iterations and 1e11 J at 2 (`profile_stages ragdoll_pile
    /// 300 1 1 8`).
    fn geometric_stiffness(&self, sf: &mut SolverFrame) {
        let h = self.settings.dt / self.settings.substeps as f64;
        sf.geometric = vec![0.0; sf.bodies.len()];
        for (j, &slot) in sf.joints.iter().zip(&sf.joint_slots) {
            let Some(entry) = self.joints.at(slot) else {
                continue;
            };
            let (f, t) = (entry.force.length(), entry.torque.length());
            for (body, local) in [(j.a, &entry.local[0]), (j.b, &entry.local[1])] {
                if body != 0 {
                    sf.geometric[body as usize] += h * h * (f * local.position.length() + t);
                }
            }
        }
    }

    /// The joints' row impulses kept for the next step's warm start, and
    /// their reactions (from the last sub-step, of length `h`).
    fn store_joint_impulses(&mut self, f: &StepFrame, h: f64) {
        let sf = &f.solver;
        for (j, &slot) in sf.joints.iter().zip(&sf.joint_slots) {
            let Some(entry) = self.joints.at_mut(slot) else {
                continue;
            };
            entry.impulses = j.impulses();
            (entry.force, entry.torque) = j.reaction(h);
        }
        // The coordinates as the last sub-step followed them (the step's
        // end is followed from there, `follow_gear_coordinates`).
        for (g, &slot) in sf.gears.iter().zip(&sf.gear_slots) {
            if let Some(state) = self.joints.at_mut(slot).and_then(|e| e.gear.as_mut()) {
                state.impulse = g.impulse;
                if g.followed().iter().all(|c| c.is_finite()) {
                    state.coordinates = g.followed();
                }
            }
        }
    }

    /// [`SolveStage::StoreImpulses`]: every point's normal impulse and every
    /// patch's friction go to the warm-start cache (sorted by pair), and the
    /// step's contacts are reported with the impulses of the whole step.
    ///
    /// Reads what the solve kept of its records (`StepScratch::solved`, a
    /// patch in 56 bytes and a point in 16, written by the thread that
    /// solved each: `contact_solver::SolvedPatches`) and writes the cache
    /// and the contacts in patch order, which is the records' order
    /// shuffled: read there directly, a patch record (about 1 KB) and each
    /// of its points (about 250 bytes) was a miss from memory on the large
    /// pyramid, most of this stage's time. Written by the pool a run at a
    /// time, each run its own stretch of the arrays it writes (a record
    /// depends on its patch alone); the arrays keep their length from the
    /// last step and are only cut or grown, so that each record is written
    /// once.
    fn store_impulses(&mut self, f: &StepFrame, substeps: u32) {
        let sf = &f.solver;
        let solved = &self.scratch.solved;
        let n_points: usize = f.patches.iter().map(|p| p.count as usize).sum();
        let (point, patch, contact) = cache_placeholders();
        self.cache.resize(n_points, point);
        self.patch_cache.resize(f.patches.len(), patch);
        self.contacts.resize(n_points, contact);
        // The runs: (first patch, its patches' cache and contact records).
        let run = (f.patches.len() / (f.pool.threads() * LAYOUT_RUNS_PER_THREAD)).max(LAYOUT_MIN_RUN);
        let mut runs = Vec::with_capacity(f.patches.len().div_ceil(run));
        let (mut cache, mut patch_cache, mut contacts) = (
            &mut self.cache[..],
            &mut self.patch_cache[..],
            &mut self.contacts[..],
        );
        for (c, patches) in f.patches.chunks(run).enumerate() {
            let count: usize = patches.iter().map(|p| p.count as usize).sum();
            let (run_cache, rest) = std::mem::take(&mut cache).split_at_mut(count);
            cache = rest;
            let (run_contacts, rest) = std::mem::take(&mut contacts).split_at_mut(count);
            contacts = rest;
            let (run_patches, rest) = std::mem::take(&mut patch_cache).split_at_mut(patches.len());
            patch_cache = rest;
            runs.push((c * run, run_patches, run_cache, run_contacts));
        }
        let scale = substeps as f64;
        let bodies = &self.bodies;
        f.pool
            .for_each_mut(&mut runs, |_, (first, run_patches, run_cache, run_contacts)| {
                let mut at = 0;
                for (j, cached) in run_patches.iter_mut().enumerate() {
                    let patch = &f.patches[*first + j];
                    let s = solved.patch(sf.position[*first + j]);
                    *cached = CachedPatch {
                        key: patch.key,
                        normal: patch.normal,
                        tangent_impulse: s.tangent,
                        twist_impulse: s.twist,
                        anchor: anchor_to_keep(bodies, f, patch, s),
                    };
                    // The patch's friction is reported on its points in
                    // proportion to their normal impulses.
                    let points = f.points.of(patch).iter().zip(solved.points_of(s, patch.count));
                    for (k, (p, &SolvedPoint { normal_impulse, .. })) in points.enumerate() {
                        let share = if s.total > 0.0 {
                            normal_impulse / s.total
                        } else {
                            0.0
                        };
                        run_cache[at + k] = CachedContact {
                            key: patch.key,
                            feature_a: p.contact.feature_a,
                            feature_b: p.contact.feature_b,
                            local_a: p.local_a,
                            normal_impulse,
                        };
                        run_contacts[at + k] = WorldContact {
                            body_a: patch.ids.0,
                            body_b: patch.ids.1,
                            contact: p.contact,
                            normal_impulse: normal_impulse * scale,
                            tangent_impulse: s.tangent * (share * scale),
                        };
                    }
                    at += patch.count as usize;
                }
            });
        manifold::finish(&mut self.cache, &mut self.patch_cache);
    }
}

/// What a patch remembers of where it stuck (`CachedPatch::anchor`):
/// the anchor it held, while it sticks (its friction impulse inside
/// [`contact_solver::STICKING`] of the Coulomb disc); a new one where its two bodies
/// meet at the patch's centre at the step's end, when it began to
/// stick in this step; none while it slides, does not press, or rolls.
fn anchor_to_keep(
    bodies: &Arena<BodyEntry>,
    f: &StepFrame,
    patch: &PreparedPatch,
    solved: &SolvedPatch,
) -> Option<[DVec3; 2]> {
    if !solved.sticks || !patch.holds {
        return None;
    }
    if let Some(anchor) = patch.anchor(&f.patch_extras) {
        return Some(anchor.local);
    }
    let sf = &f.solver;
    let points = f.points.of(patch);
    let centre = points.iter().map(|p| p.contact.point).sum::<DVec3>() / points.len() as f64;
    let poses = [
        bodies.at(patch.key.0)?.body.pose(),
        bodies.at(patch.key.1)?.body.pose(),
    ];
    let moved = solved.bodies.map(|k| &sf.bodies[k as usize]);
    // Each body's copy of the centre at the step's end, and their midpoint.
    let ends = [0, 1].map(|k| poses[k].position + moved[k].dp + moved[k].turn * (centre - poses[k].position));
    let meet = 0.5 * (ends[0] + ends[1]);
    Some([0, 1].map(|k| {
        let arm = moved[k].turn.transpose() * (meet - poses[k].position - moved[k].dp);
        poses[k].rotation.inverse() * arm
    }))
}

/// The sub-steps with the exact normal solve (`SolverKind::Lemke`): serial,
/// small systems; falls back to the PGS passes if Lemke fails.
#[allow(clippy::too_many_arguments)]
fn exact_substeps(
    sf: &mut SolverFrame,
    report: &mut StepReport,
    clock: &mut PartClock,
    drive: &[Drive],
    q0: &[DQuat],
    substeps: u32,
    h: f64,
    (iterations, push_out_iterations): (u32, u32),
    params: &SolverParams,
) {
    let mut exact = true;
    for sub in 0..substeps {
        for (b, &(a, tau, ld, ad)) in sf.bodies.iter_mut().zip(drive) {
            if !b.dynamic {
                continue;
            }
            b.v = (b.v + a * h) / (1.0 + ld * h);
            b.w = (b.w + b.inv_inertia * tau * h) / (1.0 + ad * h);
        }
        clock.lap(report, SolveStage::IntegrateVelocities);
        contact_solver::begin_joints(
            &mut sf.joints,
            &mut sf.gears,
            &mut sf.joint_islands,
            &mut sf.bodies,
            h,
            true,
        );
        contact_solver::begin_substep(&mut sf.manifolds, &mut sf.points, &mut sf.bodies, !exact);
        if exact {
            for p in sf.points.iter_mut() {
                p.normal_impulse = 0.0;
            }
            for m in sf.manifolds.iter_mut() {
                m.impulses = [0.0; 3];
            }
        }
        clock.lap(report, SolveStage::WarmStart);
        if exact {
            match contact_solver::solve_normals_exactly(&sf.manifolds, &mut sf.points, &mut sf.bodies, h) {
                Ok(()) => {
                    for _ in 0..iterations {
                        contact_solver::solve_joints(
                            &mut sf.joints,
                            &mut sf.gears,
                            &mut sf.joint_islands,
                            &mut sf.bodies,
                        );
                        contact_solver::solve_friction(&mut sf.manifolds, &sf.points, &mut sf.bodies);
                    }
                }
                Err(e) => {
                    report
                        .warnings
                        .push(format!("solver = lemke failed ({e}); PGS ran instead"));
                    exact = false;
                }
            }
        }
        if !exact {
            for _ in 0..iterations {
                contact_solver::solve_joints(
                    &mut sf.joints,
                    &mut sf.gears,
                    &mut sf.joint_islands,
                    &mut sf.bodies,
                );
                contact_solver::solve(&mut sf.manifolds, &mut sf.points, &mut sf.bodies, h);
            }
        }
        if sub + 1 == substeps {
            report.solver_residual = contact_solver::residual(&sf.manifolds, &sf.points, &sf.bodies, h);
        }
        clock.lap(report, SolveStage::Iterate);
        for pass in 0..push_out_iterations {
            let joints = contact_solver::push_joints(
                &mut sf.joints,
                &mut sf.gears,
                &mut sf.joint_islands,
                &mut sf.bodies,
                h,
            );
            let first = pass == 0;
            if !contact_solver::push_out(&sf.manifolds, &mut sf.points, &mut sf.bodies, params, h, first)
                && !joints
            {
                break;
            }
        }
        clock.lap(report, SolveStage::Relax);
        contact_solver::integrate_positions(&mut sf.bodies, q0, h);
        clock.lap(report, SolveStage::IntegratePositions);
    }
}

/// Adds the joints' geometric stiffness `geometric` (per solver body, see
/// `World::geometric_stiffness`) to the bodies' rotational inertia.
fn apply_geometric_stiffness(bodies: &mut [SolverBody], geometric: &[f64]) {
    for (b, &g) in bodies.iter_mut().zip(geometric) {
        if g > 0.0 && b.dynamic && g.is_finite() {
            b.inv_inertia_body = b
                .inv_inertia_body
                .map(|i| if i > 0.0 { 1.0 / (1.0 / i + g) } else { i });
            b.inv_inertia = SolverBody::world_inverse_inertia(b.q, b.inv_inertia_body);
        }
    }
}

/// Where each solver record of a step comes from: record `k` is patch
/// `order[k]` of the narrow stage, its points `firsts[k]..firsts[k + 1]`
/// of the point array, its bodies `pairs[order[k]]` (solver indices).
struct RecordLayout {
    order: Vec<u32>,
    firsts: Vec<u32>,
    pairs: Vec<(u32, u32)>,
}

/// The step's records as the solver's team writes them
/// (`SolverArrays::prepare`): from the narrow stage's patches and points,
/// laid out by a [`RecordLayout`].
struct PatchRecords<'a> {
    layout: &'a RecordLayout,
    patches: &'a [PreparedPatch],
    prepared: &'a ContactPoints,
    extras: &'a [PatchExtras],
}

impl RecordSource for PatchRecords<'_> {
    fn points(&self, k: usize) -> std::ops::Range<usize> {
        self.layout.firsts[k] as usize..self.layout.firsts[k + 1] as usize
    }

    fn restitution(&self, k: usize) -> f64 {
        self.patches[self.layout.order[k] as usize].restitution
    }

    fn prefetch(&self, k: usize) {
        let p = &self.patches[self.layout.order[k] as usize];
        contact_solver::prefetch(p, usize::MAX);
    }

    fn prefetch_points(&self, k: usize) {
        let p = &self.patches[self.layout.order[k] as usize];
        contact_solver::prefetch(self.prepared.of(p), usize::MAX);
    }

    fn renew(&self, k: usize, m: &mut ManifoldConstraint, points: &mut [PointConstraint]) {
        let i = self.layout.order[k] as usize;
        let p = &self.patches[i];
        for (dst, q) in points.iter_mut().zip(self.prepared.of(p)) {
            q.renew_constraint(dst);
        }
        let (a, b) = self.layout.pairs[i];
        m.renew(
            a,
            b,
            self.layout.firsts[k],
            p.count,
            p.normal,
            p.friction,
            p.restitution,
            p.warm_tangent,
            p.warm_twist,
        );
        m.rolling = p.rolling;
        if let Some(x) = p.extras(self.extras) {
            m.curvature = x.curvature;
            if let Some(anchor) = &x.anchor {
                m.anchored = true;
                m.anchor_r = anchor.r;
                m.anchor_offset = anchor.offset;
            }
        }
    }
}

/// Runs per thread the step's records are written in (the solver's joint
/// records in `World::prepare_joints`, the warm-start cache and the
/// contacts in `store_impulses`): a few, so that a thread slowed by
/// another process leaves its last run to the others.
const LAYOUT_RUNS_PER_THREAD: usize = 4;

/// Fewest records in one run of a layout (below it a run costs more to
/// hand over than to write).
const LAYOUT_MIN_RUN: usize = 64;

/// Records that fill the warm-start cache and the reported contacts where
/// they grow (`World::store_impulses`), each overwritten before it is read.
fn cache_placeholders() -> (CachedContact, CachedPatch, WorldContact) {
    let contact = tumble_collide::Contact {
        point: DVec3::ZERO,
        normal: DVec3::Z,
        distance: 0.0,
        kind: tumble_collide::ContactKind::Smooth,
        feature_a: tumble_collide::Feature::WHOLE,
        feature_b: tumble_collide::Feature::WHOLE,
    };
    let nobody = crate::world::BodyId {
        index: u32::MAX,
        generation: 0,
    };
    (
        CachedContact {
            key: (0, 0, 0, 0),
            feature_a: contact.feature_a,
            feature_b: contact.feature_b,
            local_a: DVec3::ZERO,
            normal_impulse: 0.0,
        },
        CachedPatch {
            key: (0, 0, 0, 0),
            normal: DVec3::Z,
            tangent_impulse: DVec3::ZERO,
            twist_impulse: 0.0,
            anchor: None,
        },
        WorldContact {
            body_a: nobody,
            body_b: nobody,
            contact,
            normal_impulse: 0.0,
            tangent_impulse: DVec3::ZERO,
        },
    )
}

/// Records that fill the solver's arrays where they grow, each overwritten
/// before it is read.
fn placeholders() -> (PointConstraint, ManifoldConstraint) {
    let z = DVec3::Z;
    (
        PointConstraint::new(z, DVec3::ZERO, DVec3::ZERO, 0.0, 0.0),
        ManifoldConstraint::new(0, 0, 0, 0, z, 0.0, 0.0, DVec3::ZERO, 0.0),
    )
}
