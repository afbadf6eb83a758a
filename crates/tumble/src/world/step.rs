//! One step of the world, stage by stage (see [`Stage`] and docs/pipeline.md):
//! forces, broad, narrow, islands, solve, integrate, events.
//!
//! Determinism: bodies are visited in slot order, broad-phase pairs in sorted
//! order, contacts in the order the narrow phase produces them; nothing
//! iterates a hash map. The same world stepped twice gives the same bits.

use super::manifold::{self, CachedContact, CachedPatch};
use super::patches::{add_pair, PairInfo, PatchScratch, PreparedPatch, PreparedPoint};
use super::report::{ContactEvent, Quarantined, Stage, StepReport};
use super::{BodyEntry, BodyId, MaterialDesc, SolverKind, World, WorldContact};
use crate::body::{BodyKind, BodyState};
use crate::integrate::{integrate, Integrator};
use crate::solver::contact_solver::{self, ManifoldConstraint, PointConstraint, SolverBody, SolverParams};
use std::time::Instant;
use tumble_collide::broad::Aabb;
use tumble_collide::narrow::contact_shapes;
use tumble_collide::{Contact, DQuat, DVec3, Pose};

/// Speed (m/s) beyond which a body counts as a runaway: a third of the speed
/// of light, which no rigid-body simulation means. A body whose centre or
/// surface would move faster (after a force of 1e308 N, say) is treated like
/// one whose state is not finite: frozen for the step, restored to its state
/// before it, stopped and reported in [`StepReport::quarantined`]. Finite but
/// absurd speeds would otherwise grow the broad-phase boxes and contact
/// margins over the whole world and overflow a few steps later.
pub const RUNAWAY_SPEED: f64 = 1e8;

/// `true` when a body with velocity `v`, angular velocity `w` and bounding
/// radius `radius` moves some point faster than [`RUNAWAY_SPEED`] (or its
/// velocities are not finite).
fn runaway(v: DVec3, w: DVec3, radius: f64) -> bool {
    let speed = v.length() + w.length() * radius;
    // NaN compares false: a NaN speed is a runaway too.
    speed.is_nan() || speed > RUNAWAY_SPEED
}

/// Fattened world AABB of a body: the union of its colliders' boxes, grown
/// by `fatten` (m) on every side.
pub(crate) fn body_aabb(e: &BodyEntry, fatten: f64) -> Aabb {
    let pose = e.body.pose();
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for c in &e.colliders {
        let b = c.shape.aabb(&pose.mul_pose(&c.local));
        lo = lo.min(b.min);
        hi = hi.max(b.max);
    }
    Aabb::new(lo - DVec3::splat(fatten), hi + DVec3::splat(fatten))
        .unwrap_or_else(|_| Aabb::new(DVec3::ZERO, DVec3::ZERO).expect("zero box is valid"))
}

/// Largest distance of a collider point from the centre of mass (m): bounds
/// how far rotation can move a surface point. Computed once when the body is
/// added (the colliders are fixed in the body frame).
pub(crate) fn bounding_radius(colliders: &[super::Collider]) -> f64 {
    colliders
        .iter()
        .map(|c| {
            let b = c.shape.aabb(&c.local);
            b.min.abs().max(b.max.abs()).length()
        })
        .filter(|r| r.is_finite())
        .fold(0.0, f64::max)
}

/// Bound on the speed at which a point of A approaches a point of B, for the
/// points where the two can touch during the step (m/s).
///
/// Where A and B can meet is inside both swept boxes; around the centre `p0`
/// of their intersection the relative velocity of coincident material points
/// is `v_rel(p) = v_rel(p0) + (wA - wB) x (p - p0)`, so within the
/// intersection's half diagonal `rho` it is at most
/// `|v_rel(p0)| + |wA - wB| rho`. For bodies that turn together (the links
/// of a swinging chain) this is far tighter than each body's own speed
/// bound `|vA - vB| + |wA| rA + |wB| rB`, which is kept as the cap.
fn relative_motion_bound(ea: &BodyEntry, eb: &BodyEntry, box_a: Option<Aabb>, box_b: Option<Aabb>) -> f64 {
    let (va, wa) = velocities(ea);
    let (vb, wb) = velocities(eb);
    let coarse = (va - vb).length() + wa.length() * ea.radius + wb.length() * eb.radius;
    let region = match (box_a, box_b) {
        (Some(x), Some(y)) => {
            let (lo, hi) = (x.min().max(y.min()), x.max().min(y.max()));
            // Disjoint boxes (cannot happen for a broad-phase pair): no bound.
            lo.cmple(hi).all().then_some((lo, hi))
        }
        (Some(x), None) | (None, Some(x)) => Some((x.min(), x.max())),
        (None, None) => None,
    };
    let Some((lo, hi)) = region else { return coarse };
    let p0 = (lo + hi) * 0.5;
    let rho = ((hi - lo) * 0.5).length();
    let v_rel = (va + wa.cross(p0 - ea.body.position())) - (vb + wb.cross(p0 - eb.body.position()));
    (v_rel.length() + (wa - wb).length() * rho).min(coarse)
}

/// Per body slot, an estimate of how much the body's velocity can change in
/// this step through its contacts (m/s): its largest closing speed towards
/// a broad-phase neighbour along the line of their centres, times `1 + e`
/// (stopped by that neighbour, or bounced back). Zero for static and
/// kinematic bodies, whose velocity is imposed.
///
/// Why: the margin of a pair must cover the pair's relative motion over
/// the whole step, and that motion changes when a third body stops one of
/// the two. In a falling column every pair moves together until the bottom
/// body lands; the body above then closes its 0.1 m gap at the full fall
/// speed within the same step, which the pair's own relative velocity
/// (zero) never announced. The centre line, not the full relative speed,
/// because bodies that slide or swing against each other (a chain's links)
/// do not stop each other, and a margin grown by their sliding speed would
/// only multiply the triangle pairs to test. Pairs with a concave mesh are
/// left out: interlocked rings touch where their centres move apart, so
/// the centre line says nothing about their contact normal (a column of
/// mesh bodies dropped together can still overlap by one step's fall).
fn velocity_change_bounds(
    bodies: &super::handles::Arena<BodyEntry>,
    pairs: &[(u32, u32)],
    n_slots: usize,
) -> Vec<f64> {
    let mut shock = vec![0.0f64; n_slots];
    for &(a, b) in pairs {
        let (ea, eb) = (bodies.at(a).expect("live"), bodies.at(b).expect("live"));
        if !is_active(ea) && !is_active(eb) {
            continue;
        }
        let e = MaterialDesc::combine_restitution(
            ea.body.material().restitution(),
            eb.body.material().restitution(),
        );
        if has_mesh(ea) || has_mesh(eb) {
            continue;
        }
        let (va, _) = velocities(ea);
        let (vb, _) = velocities(eb);
        let line = (eb.body.position() - ea.body.position()).normalize_or_zero();
        let change = (va - vb).dot(line).max(0.0) * (1.0 + e);
        for (slot, entry) in [(a, ea), (b, eb)] {
            if entry.body.kind() == BodyKind::Dynamic {
                shock[slot as usize] = shock[slot as usize].max(change);
            }
        }
    }
    shock
}

fn has_mesh(e: &BodyEntry) -> bool {
    e.colliders
        .iter()
        .any(|c| matches!(c.shape, tumble_collide::Shape::Mesh(_)))
}

fn is_active(e: &BodyEntry) -> bool {
    match e.body.kind() {
        BodyKind::Dynamic => !e.sleeping,
        BodyKind::Kinematic => {
            let (v, w) = e.body.kinematic_velocity();
            v != DVec3::ZERO || w != DVec3::ZERO
        }
        BodyKind::Static => false,
    }
}

fn velocities(e: &BodyEntry) -> (DVec3, DVec3) {
    match e.body.kind() {
        BodyKind::Dynamic if !e.sleeping => (e.body.velocity(), e.body.angular_velocity()),
        BodyKind::Kinematic => e.body.kinematic_velocity(),
        _ => (DVec3::ZERO, DVec3::ZERO),
    }
}

impl World {
    /// Advances the world by `settings.dt` and reports what happened.
    pub fn step(&mut self) -> StepReport {
        let mut report = StepReport::default();
        let s = self.settings.clone();
        let dt = s.dt;
        let mut clock = Instant::now();
        let mut lap = |report: &mut StepReport, stage: Stage| {
            let now = Instant::now();
            report.stage_time[stage as usize] += now - clock;
            clock = now;
        };

        // -- Stage::Forces: keep the state for quarantine; forces are read in solve.
        let n_slots = self.bodies.slot_count();
        let before: Vec<Option<BodyState>> = (0..n_slots as u32)
            .map(|i| self.bodies.at(i).map(|e| *e.body.state()))
            .collect();
        lap(&mut report, Stage::Forces);

        // -- Stage::Broad
        let mut events = Vec::new();
        // Swept boxes: where each bounded body can be during the step
        // (`None` for unbounded shapes, which are everywhere).
        let mut swept: Vec<Option<Aabb>> = vec![None; n_slots];
        for i in 0..n_slots as u32 {
            let Some(e) = self.bodies.at(i) else { continue };
            let Some(proxy) = e.proxy else { continue };
            let (v, w) = velocities(e);
            let fatten = s.contact_margin + (v.length() + w.length() * e.radius) * dt;
            let aabb = body_aabb(e, fatten);
            swept[i as usize] = Some(aabb);
            if !is_active(e) {
                continue;
            }
            if let Err(err) = self.broad.set_aabb(proxy, aabb) {
                report.warnings.push(format!("body slot {i}: broad phase: {err}"));
            }
        }
        self.broad.update(&mut events);
        let broad = &self.broad;
        let mut pairs: Vec<(u32, u32)> = broad
            .pairs()
            .filter_map(|(a, b)| Some((broad.user_id(a).ok()?, broad.user_id(b).ok()?)))
            .map(|(a, b)| if a < b { (a, b) } else { (b, a) })
            .collect();
        for &u in &self.unbounded {
            for i in 0..n_slots as u32 {
                if i != u
                    && self
                        .bodies
                        .at(i)
                        .is_some_and(|e| e.body.kind() != BodyKind::Static)
                {
                    pairs.push((u.min(i), u.max(i)));
                }
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
        report.broad_pairs = pairs.len();
        // Wake sleeping islands that an active body has come close to.
        loop {
            let mut woke = false;
            for &(a, b) in &pairs {
                let (ea, eb) = (self.bodies.at(a).expect("live"), self.bodies.at(b).expect("live"));
                let group = match (is_active(ea), is_active(eb)) {
                    (true, false) if eb.sleeping => Some(b),
                    (false, true) if ea.sleeping => Some(a),
                    _ => None,
                };
                if let Some(slot) = group {
                    self.wake_island_of(slot);
                    woke = true;
                }
            }
            if !woke {
                break;
            }
        }
        lap(&mut report, Stage::Broad);

        // -- Stage::Narrow
        // Sized from the last step's contacts: no growth in a steady scene.
        let mut prepared: Vec<PreparedPoint> =
            Vec::with_capacity(self.cache.len() + self.cache.len() / 4 + 16);
        let mut patches: Vec<PreparedPatch> =
            Vec::with_capacity(self.patch_cache.len() + self.patch_cache.len() / 4 + 16);
        let mut scratch = PatchScratch::default();
        let mut buffer: Vec<Contact> = Vec::new();
        let mut warned_unsupported = false;
        let shock = velocity_change_bounds(&self.bodies, &pairs, n_slots);
        for &(a, b) in &pairs {
            let (ea, eb) = (self.bodies.at(a).expect("live"), self.bodies.at(b).expect("live"));
            if !is_active(ea) && !is_active(eb) {
                continue;
            }
            if ea.body.kind() != BodyKind::Dynamic && eb.body.kind() != BodyKind::Dynamic {
                continue;
            }
            let now = relative_motion_bound(ea, eb, swept[a as usize], swept[b as usize]);
            let motion = (now + shock[a as usize] + shock[b as usize]) * dt;
            let margin = s.contact_margin + motion;
            let (pa, pb) = (ea.body.pose(), eb.body.pose());
            let ids = (
                self.bodies.id_at(a).expect("live"),
                self.bodies.id_at(b).expect("live"),
            );
            let friction =
                MaterialDesc::combine_friction(ea.body.material().friction(), eb.body.material().friction());
            let restitution = MaterialDesc::combine_restitution(
                ea.body.material().restitution(),
                eb.body.material().restitution(),
            );
            for (ia, ca) in ea.colliders.iter().enumerate() {
                for (ib, cb) in eb.colliders.iter().enumerate() {
                    buffer.clear();
                    let (wpa, wpb) = (pa.mul_pose(&ca.local), pb.mul_pose(&cb.local));
                    if let Err(err) = contact_shapes(&ca.shape, &wpa, &cb.shape, &wpb, margin, &mut buffer) {
                        if !warned_unsupported {
                            report.warnings.push(format!("bodies {a} and {b}: {err}"));
                            warned_unsupported = true;
                        }
                        continue;
                    }
                    // Meshes rest a hair apart (see WorldSettings::allowed_penetration).
                    let is_mesh = |c: &super::Collider| matches!(c.shape, tumble_collide::Shape::Mesh(_));
                    let skin = if is_mesh(ca) || is_mesh(cb) {
                        2.0 * s.allowed_penetration
                    } else {
                        0.0
                    };
                    let pair = PairInfo {
                        ids,
                        key: (a, b, ia as u16, ib as u16),
                        pose_a: &pa,
                        pose_b: &pb,
                        friction,
                        restitution,
                        skin,
                    };
                    report.warm_started += add_pair(
                        &buffer,
                        &pair,
                        &self.cache,
                        &self.patch_cache,
                        &mut scratch,
                        &mut prepared,
                        &mut patches,
                    );
                    for contact in &buffer {
                        report.max_penetration = report.max_penetration.max(-contact.distance);
                    }
                }
            }
        }
        report.contacts = prepared.len();
        lap(&mut report, Stage::Narrow);

        // -- Stage::Islands: contacts link dynamic bodies; wake what touches the active.
        let mut links: Vec<(u32, u32)> = prepared.iter().map(|p| (p.key.0, p.key.1)).collect();
        links.dedup();
        let dynamic_awake: Vec<bool> = (0..n_slots as u32)
            .map(|i| {
                self.bodies
                    .at(i)
                    .is_some_and(|e| e.body.kind() == BodyKind::Dynamic && !e.sleeping)
            })
            .collect();
        let labels = super::islands::label_islands(&dynamic_awake, &links);
        let mut roots: Vec<u32> = labels.iter().copied().filter(|&l| l != u32::MAX).collect();
        roots.sort_unstable();
        roots.dedup();
        report.islands = roots.len();
        lap(&mut report, Stage::Islands);

        // -- Stage::Solve
        // Solver body 0 is the shared immovable body (static or asleep).
        let mut slot_to_solver = vec![0u32; n_slots];
        let mut solver_bodies = Vec::with_capacity(n_slots + 1);
        solver_bodies.push(SolverBody::fixed());
        let mut solver_slots = Vec::with_capacity(n_slots + 1);
        solver_slots.push(u32::MAX);
        let mut has_contact = vec![false; n_slots];
        for p in &patches {
            has_contact[p.key.0 as usize] = true;
            has_contact[p.key.1 as usize] = true;
        }
        let semi_implicit = s.integrator == Integrator::SemiImplicitEuler;
        for i in 0..n_slots as u32 {
            let Some(e) = self.bodies.at(i) else { continue };
            if !is_active(e) {
                continue;
            }
            // Free bodies of a world with an explicit integrator are advanced by
            // that integrator in the integrate stage, not by the solver.
            if e.body.kind() == BodyKind::Dynamic && !semi_implicit && !has_contact[i as usize] {
                continue;
            }
            let (v, w) = velocities(e);
            let dynamic = e.body.kind() == BodyKind::Dynamic;
            slot_to_solver[i as usize] = solver_bodies.len() as u32;
            solver_slots.push(i);
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
            solver_bodies.push(body);
        }
        report.awake_bodies = solver_bodies.len() - 1;
        let q0: Vec<DQuat> = solver_bodies.iter().map(|b| b.q).collect();
        let mut points: Vec<PointConstraint> = prepared.iter().map(|p| p.point).collect();
        let mut manifolds: Vec<ManifoldConstraint> = patches
            .iter()
            .map(|p| {
                let mut m = ManifoldConstraint::new(
                    slot_to_solver[p.key.0 as usize],
                    slot_to_solver[p.key.1 as usize],
                    p.first,
                    p.count,
                    p.normal,
                    p.friction,
                    p.restitution,
                    p.warm_tangent,
                    p.warm_twist,
                );
                contact_solver::prepare(&mut m, &mut points, &solver_bodies);
                m
            })
            .collect();
        let substeps = if semi_implicit { s.substeps } else { 1 };
        let h = dt / substeps as f64;
        let params = SolverParams {
            push_out_fraction: s.push_out_fraction,
            allowed_penetration: s.allowed_penetration,
            max_push_out_speed: s.max_push_out_speed,
            restitution_threshold: s.restitution_threshold,
        };
        // Forces and damping per solver body, constant over the step.
        let accel: Vec<(DVec3, DVec3, f64, f64)> = solver_slots
            .iter()
            .map(|&slot| match self.bodies.at(slot) {
                Some(e) if e.body.kind() == BodyKind::Dynamic => (
                    s.gravity + e.body.force() * e.body.inv_mass(),
                    e.body.torque(),
                    e.body.linear_damping(),
                    e.body.angular_damping(),
                ),
                _ => (DVec3::ZERO, DVec3::ZERO, 0.0, 0.0),
            })
            .collect();
        // Quarantine before solving: a body whose forces or velocities are not
        // finite is frozen for this step (immovable in the solver) and restored
        // afterwards, so NaN cannot travel through contacts to its neighbours.
        // Runaways (see RUNAWAY_SPEED) are frozen the same way.
        let mut frozen = vec![false; solver_bodies.len()];
        for k in 1..solver_bodies.len() {
            let b = &solver_bodies[k];
            let (a, tau, _, _) = accel[k];
            let finite = b.v.is_finite() && b.w.is_finite() && a.is_finite() && tau.is_finite();
            let next_v = b.v + a * dt;
            let next_w = b.w + b.inv_inertia * tau * dt;
            let radius = self.bodies.at(solver_slots[k]).map_or(0.0, |e| e.radius);
            if !finite || runaway(next_v, next_w, radius) {
                frozen[k] = true;
                solver_bodies[k].freeze();
                for m in manifolds
                    .iter_mut()
                    .filter(|m| m.a as usize == k || m.b as usize == k)
                {
                    contact_solver::prepare(m, &mut points, &solver_bodies);
                }
            }
        }
        // With no contacts there is nothing to solve (and the dense solver
        // has no 0 x 0 case).
        let mut exact = s.solver == SolverKind::Lemke && !points.is_empty();
        if exact && points.len() > contact_solver::EXACT_MAX_CONTACTS {
            report.warnings.push(format!(
                "solver = lemke: {} contacts exceed the exact solver's limit of {}; PGS ran instead",
                points.len(),
                contact_solver::EXACT_MAX_CONTACTS
            ));
            exact = false;
        }
        let linear_accel: Vec<DVec3> = accel.iter().map(|a| a.0).collect();
        contact_solver::resolve_collisions(
            &manifolds,
            &mut points,
            &mut solver_bodies,
            &linear_accel,
            &params,
            dt,
            h,
        );
        for sub in 0..substeps {
            for (b, &(a, tau, ld, ad)) in solver_bodies.iter_mut().zip(&accel) {
                if !b.dynamic {
                    continue;
                }
                b.v = (b.v + a * h) / (1.0 + ld * h);
                b.w = (b.w + b.inv_inertia * tau * h) / (1.0 + ad * h);
            }
            if exact {
                contact_solver::begin_substep(&mut manifolds, &mut points, &mut solver_bodies, false);
                for p in points.iter_mut() {
                    p.normal_impulse = 0.0;
                }
                for m in manifolds.iter_mut() {
                    m.impulses = [0.0; 3];
                }
                match contact_solver::solve_normals_exactly(&manifolds, &mut points, &mut solver_bodies, h) {
                    Ok(()) => {
                        for _ in 0..s.iterations {
                            contact_solver::solve_friction(&mut manifolds, &points, &mut solver_bodies);
                        }
                    }
                    Err(e) => {
                        report
                            .warnings
                            .push(format!("solver = lemke failed ({e}); PGS ran instead"));
                        exact = false;
                    }
                }
            } else {
                contact_solver::begin_substep(&mut manifolds, &mut points, &mut solver_bodies, true);
            }
            if !exact {
                for _ in 0..s.iterations {
                    contact_solver::solve(&mut manifolds, &mut points, &mut solver_bodies, h);
                }
            }
            if sub + 1 == substeps {
                report.solver_residual = contact_solver::residual(&manifolds, &points, &solver_bodies, h);
            }
            for _ in 0..s.push_out_iterations {
                if !contact_solver::push_out(&manifolds, &mut points, &mut solver_bodies, &params, h) {
                    break;
                }
            }
            contact_solver::integrate_positions(&mut solver_bodies, &q0, h);
        }
        report.substeps = substeps;
        report.iterations = s.iterations;
        lap(&mut report, Stage::Solve);

        // -- Stage::Integrate
        for (k, &slot) in solver_slots.iter().enumerate().skip(1) {
            let sb = solver_bodies[k];
            let e = self.bodies.at_mut(slot).expect("live");
            let finite = sb.v.is_finite() && sb.w.is_finite() && sb.dp.is_finite() && sb.q.is_finite();
            if frozen[k] || !finite {
                // Restored to the state before the step, stopped, reported.
                if let Some(old) = &before[slot as usize] {
                    let mut restored = *old;
                    restored.linear_momentum = DVec3::ZERO;
                    restored.angular_momentum = DVec3::ZERO;
                    let _ = e.body.set_state(restored);
                }
                e.body.clear_forces();
                report.quarantined.push(Quarantined {
                    body: self.bodies.id_at(slot).expect("live"),
                });
                continue;
            }
            if sb.dynamic {
                let state = BodyState {
                    position: e.body.position() + sb.dp,
                    orientation: sb.q,
                    linear_momentum: sb.v * e.body.mass(),
                    angular_momentum: sb.inv_inertia.inverse() * sb.w,
                };
                let _ = e.body.set_state(state);
            } else {
                let pose = e.body.pose();
                e.body.set_pose(Pose {
                    position: pose.position + sb.dp,
                    rotation: sb.q,
                });
            }
            e.body.clear_forces();
        }
        if !semi_implicit {
            for i in 0..n_slots as u32 {
                let Some(e) = self.bodies.at_mut(i) else { continue };
                if e.body.kind() == BodyKind::Dynamic && !e.sleeping && !has_contact[i as usize] {
                    let _ = integrate(std::slice::from_mut(&mut e.body), s.gravity, dt, s.integrator);
                    e.body.clear_forces();
                }
            }
        }
        lap(&mut report, Stage::Integrate);

        // -- Stage::Events: contacts, cache, quarantine, sleep.
        self.cache.clear();
        self.patch_cache.clear();
        self.contacts.clear();
        let mut touching: Vec<(BodyId, BodyId)> = Vec::with_capacity(self.touching.len() + 16);
        for (patch, m) in patches.iter().zip(&manifolds) {
            let tangent = m.tangent_impulse();
            self.patch_cache.push(CachedPatch {
                key: patch.key,
                normal: patch.normal,
                tangent_impulse: tangent,
                twist_impulse: m.impulses[2],
            });
            // The patch's friction is reported on its points in proportion
            // to their normal impulses.
            let total: f64 = points[m.range()].iter().map(|c| c.normal_impulse).sum();
            for (p, c) in prepared[m.range()].iter().zip(&points[m.range()]) {
                let share = if total > 0.0 {
                    c.normal_impulse / total
                } else {
                    0.0
                };
                self.cache.push(CachedContact {
                    key: p.key,
                    feature_a: p.contact.feature_a,
                    feature_b: p.contact.feature_b,
                    local_a: p.local_a,
                    normal_impulse: c.normal_impulse,
                });
                self.contacts.push(WorldContact {
                    body_a: p.ids.0,
                    body_b: p.ids.1,
                    contact: p.contact,
                    normal_impulse: c.normal_impulse * substeps as f64,
                    tangent_impulse: tangent * (share * substeps as f64),
                });
                if c.max_normal_impulse > 0.0 || p.contact.distance <= 0.0 {
                    touching.push(p.ids);
                }
            }
        }
        manifold::finish(&mut self.cache, &mut self.patch_cache);
        touching.sort_unstable();
        touching.dedup();
        let (mut i, mut j) = (0, 0);
        while i < touching.len() || j < self.touching.len() {
            match (touching.get(i), self.touching.get(j)) {
                (Some(a), Some(b)) if a == b => {
                    i += 1;
                    j += 1;
                }
                (Some(a), Some(b)) if a < b => {
                    report.events.push(ContactEvent::Begin(a.0, a.1));
                    i += 1;
                }
                (Some(a), None) => {
                    report.events.push(ContactEvent::Begin(a.0, a.1));
                    i += 1;
                }
                (_, Some(b)) => {
                    report.events.push(ContactEvent::End(b.0, b.1));
                    j += 1;
                }
                (None, None) => break,
            }
        }
        report.events.sort_unstable();
        self.touching = touching;

        // Bodies advanced by an explicit integrator are checked here (the
        // integrator already refuses non-finite states; this is the backstop,
        // also for runaways that solver impulses made).
        for (i, old) in before.iter().enumerate() {
            let Some(e) = self.bodies.at(i as u32) else {
                continue;
            };
            let dynamic = e.body.kind() == BodyKind::Dynamic;
            if e.body.state().is_finite()
                && !(dynamic && runaway(e.body.velocity(), e.body.angular_velocity(), e.radius))
            {
                continue;
            }
            let Some(e) = self.bodies.at_mut(i as u32) else {
                continue;
            };
            if let Some(old) = old {
                let mut restored = *old;
                restored.linear_momentum = DVec3::ZERO;
                restored.angular_momentum = DVec3::ZERO;
                let _ = e.body.set_state(restored);
            }
            e.body.clear_forces();
            report.quarantined.push(Quarantined {
                body: self.bodies.id_at(i as u32).expect("live"),
            });
        }
        if s.sleeping {
            self.update_sleep(&labels, dt);
        }
        report.sleeping_bodies = self.bodies.iter().filter(|(_, e)| e.sleeping).count();
        self.time += dt;
        self.step_count += 1;
        lap(&mut report, Stage::Events);
        report
    }

    /// Wakes every body of the sleeping island that contains `slot`.
    fn wake_island_of(&mut self, slot: u32) {
        let group = self.bodies.at(slot).map(|e| e.sleep_group).unwrap_or(u32::MAX);
        for i in 0..self.bodies.slot_count() as u32 {
            if let Some(e) = self.bodies.at_mut(i) {
                if e.sleeping && (i == slot || (group != u32::MAX && e.sleep_group == group)) {
                    e.sleeping = false;
                    e.rest_time = 0.0;
                }
            }
        }
    }

    /// Accumulates rest time per body and puts islands to sleep whose every
    /// body has rested long enough.
    fn update_sleep(&mut self, labels: &[u32], dt: f64) {
        let s = &self.settings;
        let n = self.bodies.slot_count();
        let mut island_min_rest = vec![f64::INFINITY; n];
        for i in 0..n as u32 {
            let Some(e) = self.bodies.at_mut(i) else { continue };
            if e.body.kind() != BodyKind::Dynamic || e.sleeping {
                continue;
            }
            let slow = e.body.velocity().length() < s.sleep_linear_speed
                && e.body.angular_velocity().length() < s.sleep_angular_speed;
            e.rest_time = if slow { e.rest_time + dt } else { 0.0 };
            let l = labels[i as usize];
            if l != u32::MAX {
                island_min_rest[l as usize] = island_min_rest[l as usize].min(e.rest_time);
            }
        }
        for i in 0..n as u32 {
            let l = labels.get(i as usize).copied().unwrap_or(u32::MAX);
            if l == u32::MAX || island_min_rest[l as usize] < s.time_to_sleep {
                continue;
            }
            let Some(e) = self.bodies.at_mut(i) else { continue };
            e.sleeping = true;
            e.sleep_group = l;
            let mut state = *e.body.state();
            state.linear_momentum = DVec3::ZERO;
            state.angular_momentum = DVec3::ZERO;
            let _ = e.body.set_state(state);
        }
    }
}
