//! [`Stage::Continuous`](crate::world::Stage::Continuous): continuous
//! collision for fast bodies (Box2D v3's continuous stage, Jolt's linear
//! cast), so that a fast body meets the first surface in its path, never
//! the deepest or the far one.
//!
//! The speculative contacts of the narrow phase stop most fast bodies: they
//! see every feature within the step's motion. They fail where the closest
//! features at the start of the step are not the ones hit (a box turned
//! against a thin slab, a plate's far face, a mesh's back triangles) and
//! where the solver sends a body through a thin shape in one sub-step.
//! After the solve, a body whose motion over the step exceeds
//! [`FAST_FRACTION`] of its own thickness (or whose `ccd` flag is set) is
//! swept from its pose before the step to its pose after it against the
//! static and kinematic bodies its swept box met in the broad phase, and
//! against dynamic ones too when its `ccd` flag is set ([`time_of_impact`],
//! by conservative advancement, rotation included). Where it came within
//! reach of one on the way and the solver did not leave the pair touching
//! at the end (it passed through, or sank in deeper than the contact
//! margin), the body is put back at that time of impact, its velocities
//! interpolated to the same time, and Newton's restitution law acts at the
//! contact there; the next step's speculative contact then meets that
//! surface. The rest of the step is lost for that body, never energy.
//!
//! Each fast body is swept against the others' whole motions, on the
//! world's threads, reading the world only; the poses are put back in slot
//! order afterwards, so the result does not depend on the thread count.

use super::StepFrame;
use crate::body::{BodyKind, BodyState};
use crate::world::{BodyEntry, MaterialDesc, World};
use tumble_collide::narrow::contact_shapes;
use tumble_collide::query::{time_of_impact, Impact, Motion, ToiOptions};
use tumble_collide::shape::Sphere;
use tumble_collide::{DMat3, DVec3, Pose, Shape};

/// A body is fast, and swept, when its motion over one step (centre
/// travel plus turn times radius) exceeds this fraction of its thickness
/// (its smallest half extent): a slower body cannot cross a surface with
/// its centre within one step.
pub const FAST_FRACTION: f64 = 0.5;

/// Body slots per task of the test for fast bodies on the pool.
const SLOTS_PER_TASK: usize = 512;

/// Most advancement steps of one sweep; a sweep that runs out stops the
/// body early (still in front of the surface), never late.
const MAX_ITERATIONS: u32 = 64;

impl World {
    pub(super) fn continuous_stage(&mut self, f: &mut StepFrame) {
        if !f.settings.continuous {
            return;
        }
        // Jointed bodies stay where the solver left them in the sweeps, and
        // in the end-overlap pass unless they have a triangle mesh
        // (end_overlap.rs, "Jointed bodies").
        let jointed = self.jointed_flags(f.n_slots);
        self.sweep_fast_bodies(f, &jointed);
        self.separate_end_overlaps(f, &jointed);
    }

    /// Sweeps the fast bodies (module docs) and puts each back at its
    /// first impact that the step did not resolve.
    fn sweep_fast_bodies(&mut self, f: &mut StepFrame, jointed: &[bool]) {
        // Jointed bodies are swept only when asked: putting one back along
        // its path would pull it away from the bodies it is jointed to.
        let fast = f.pool.filter_indices(f.n_slots, SLOTS_PER_TASK, |slot| {
            let (Some(e), Some(Some(before))) = (self.bodies.at(slot), f.before.get(slot as usize)) else {
                return false;
            };
            if e.body.kind() != BodyKind::Dynamic || e.sleeping {
                return false;
            }
            let motion = body_motion(&before.pose(), &e.body.pose());
            let travel = motion.travel().length() + motion.turn() * e.radius;
            e.ccd || (!jointed[slot as usize] && travel > FAST_FRACTION * e.thickness)
        });
        if fast.is_empty() {
            return;
        }
        // Each fast body's partners: the bodies its swept box met.
        let mut partners: Vec<Vec<u32>> = vec![Vec::new(); fast.len()];
        // Static and kinematic partners only, unless the body has `ccd` set
        // (a bullet, in Box2D's word): a dynamic partner has already taken
        // the solver's impulses from this body, and putting one of the two
        // back alone would leave them unanswered (a falling pile gained
        // energy that way).
        let sweeps_dynamic = |slot: u32| self.bodies.at(slot).is_some_and(|e| e.ccd);
        let immovable = |slot: u32| {
            self.bodies
                .at(slot)
                .is_some_and(|e| e.body.kind() != BodyKind::Dynamic)
        };
        for &(a, b) in &f.pairs {
            for (me, other) in [(a, b), (b, a)] {
                if let Ok(k) = fast.binary_search(&me) {
                    if immovable(other) || sweeps_dynamic(me) {
                        partners[k].push(other);
                    }
                }
            }
        }
        let work: Vec<(u32, Vec<u32>)> = fast.into_iter().zip(partners).collect();
        let frame: &StepFrame = f;
        let impacts = frame.pool.map_chunks(&work, 1, |_, chunk| {
            chunk
                .iter()
                .map(|(slot, partners)| self.first_impact(frame, *slot, partners))
                .collect::<Vec<_>>()
        });
        for ((slot, _), impact) in work.iter().zip(impacts.into_iter().flatten()) {
            let Some(impact) = impact else { continue };
            let state = f.before[*slot as usize].expect("fast bodies existed before the step");
            let e = self.bodies.at_mut(*slot).expect("live");
            let t = impact.time;
            // The velocities go back with the pose, to the same fraction of
            // the way between the step's start and end: a body put back up
            // its fall keeping its final speed would gain the potential
            // energy of the height it regained. Interpolated, its energy
            // at the impact lies between the step's start and end values
            // (kinetic energy is convex in the velocity, potential linear
            // along the path).
            let (v0, w0) = state_velocities(&state, &e.body);
            let (v1, w1) = (e.body.velocity(), e.body.angular_velocity());
            e.body
                .set_pose(body_motion(&state.pose(), &e.body.pose()).pose_at(t));
            // Finite by construction (finite start and end); a failure
            // leaves the end's velocities.
            let _ = e.body.set_linear_velocity(v0.lerp(v1, t));
            let _ = e.body.set_angular_velocity(w0.lerp(w1, t));
            self.collide_at_impact(*slot, &impact, f.settings.restitution_threshold);
            f.report.continuous += 1;
        }
    }

    /// The collision at a time of impact: Newton's restitution law at the
    /// impact's contact points along their normals (thesis 7.1), impulses
    /// between the fast body and its partner (the partner takes its share
    /// only if it is dynamic), in a few Gauss-Seidel passes, so that the next
    /// step does not start by driving the body into the surface again. Never
    /// adds kinetic energy (restitution at most 1, applied only to
    /// approaching points; no friction).
    fn collide_at_impact(&mut self, slot: u32, impact: &SweptImpact, restitution_threshold: f64) {
        const PASSES: usize = 4;
        for pass in 0..PASSES {
            for &(p, n) in &impact.contacts {
                let (ea, eb) = (
                    self.bodies.at(slot).expect("live"),
                    self.bodies.at(impact.partner).expect("live"),
                );
                let approach = (ea.body.velocity_at_point(p) - eb.body.velocity_at_point(p)).dot(n);
                if approach >= 0.0 || approach.is_nan() {
                    continue;
                }
                let share = |body: &crate::body::RigidBody| {
                    let rn = (p - body.position()).cross(n);
                    body.inv_mass() + rn.dot(body.inv_inertia_world() * rn)
                };
                let k = share(&ea.body) + share(&eb.body);
                // Bounce once, on the first pass at the first point.
                let e = if pass == 0 && -approach > restitution_threshold {
                    MaterialDesc::combine_restitution(
                        ea.body.material().restitution(),
                        eb.body.material().restitution(),
                    )
                } else {
                    0.0
                };
                let j = -(1.0 + e) * approach / k;
                let partner_moves = eb.body.kind() == BodyKind::Dynamic;
                if !(j.is_finite() && k > 0.0) {
                    continue;
                }
                // Kinetic energy in the frame moving with the partner's
                // surface at the point when the partner is kinematic: a
                // moving kinematic body (a paddle) does work on what it
                // strikes, so only there can an impulse be held to never
                // add energy (libFuzzer's `world_step`: a body struck by a
                // kinematic one went from 5.09 to 5.22 MJ in the world
                // frame). Against a dynamic partner the impulse is internal
                // and the world frame's total serves.
                let frame = if partner_moves {
                    DVec3::ZERO
                } else {
                    eb.body.velocity_at_point(p)
                };
                let energy = |a: &crate::body::RigidBody, b: &crate::body::RigidBody| {
                    let shifted = |body: &crate::body::RigidBody| {
                        body.kinetic_energy() - 0.5 * body.mass() * body.velocity().length_squared()
                            + 0.5 * body.mass() * (body.velocity() - frame).length_squared()
                    };
                    shifted(a) + if partner_moves { shifted(b) } else { 0.0 }
                };
                let energy_before = energy(&ea.body, &eb.body);
                // Failures leave the momenta as they were (a non-finite
                // impulse cannot come from finite bodies; checked anyway).
                let _ = self
                    .bodies
                    .at_mut(slot)
                    .expect("live")
                    .body
                    .apply_impulse_at_point(n * j, p);
                if partner_moves {
                    let _ = self
                        .bodies
                        .at_mut(impact.partner)
                        .expect("live")
                        .body
                        .apply_impulse_at_point(-n * j, p);
                }
                // (Speeds near 1e154 m/s overflow the energy itself: no
                // check there; a state that turns non-finite is quarantined.)
                if cfg!(debug_assertions) && energy_before.is_finite() {
                    let (ea, eb) = (
                        self.bodies.at(slot).expect("live"),
                        self.bodies.at(impact.partner).expect("live"),
                    );
                    let after = energy(&ea.body, &eb.body);
                    debug_assert!(
                        after <= energy_before * (1.0 + 1e-9) + 1e-12,
                        "an impact impulse added energy: {energy_before} J -> {after} J"
                    );
                }
            }
        }
    }

    /// Where body `slot` goes back to, if anywhere: the earliest impact with
    /// one of `partners` on its way that the step did not resolve.
    fn first_impact(&self, f: &StepFrame, slot: u32, partners: &[u32]) -> Option<SweptImpact> {
        let e = self.bodies.at(slot).expect("live");
        let margin = f.settings.contact_margin;
        let reach = ToiOptions {
            target: 0.5 * margin,
            tolerance: 0.25 * margin,
            max_iterations: MAX_ITERATIONS,
        };
        let mine = (
            f.before[slot as usize].expect("swept bodies existed").pose(),
            e.body.pose(),
        );
        // Sides are told by the centre; a ring's centre is in its hole.
        let center = (e.core > 0.0).then_some(mine.1.position);
        let mut first: Option<SweptImpact> = None;
        for &p in partners {
            let other = self.bodies.at(p).expect("live");
            let theirs = (
                f.before[p as usize].map_or(other.body.pose(), |s| s.pose()),
                other.body.pose(),
            );
            // How deep the pair may end inside each other and still count as
            // resting: no deeper than the partner is (half) thick, never less
            // than the solver's own allowance (3 mm into a 1 mm slab is
            // through most of it).
            let through = other.thickness.max(f.settings.allowed_penetration);
            for ca in &e.colliders {
                for cb in &other.colliders {
                    let (ma, mb) = (
                        collider_motion(&mine, &ca.local),
                        collider_motion(&theirs, &cb.local),
                    );
                    let Ok(Some(hit)) = time_of_impact(&ca.shape, &ma, &cb.shape, &mb, &reach) else {
                        continue;
                    };
                    // Overlapping at the start with no direction to tell the
                    // sides apart: the discrete contact's job.
                    if hit.normal == DVec3::ZERO || first.as_ref().is_some_and(|i| i.time <= hit.time) {
                        continue;
                    }
                    let clear = |depth| {
                        ends_clear(
                            margin, depth, &hit, center, &ca.shape, &ma.end, &cb.shape, &mb.end,
                        )
                    };
                    let impact = if hit.time > 0.0 {
                        // It came within reach on the way: back to there
                        // unless it ended clear, within the contact margin.
                        (!clear(margin.min(through))).then(|| SweptImpact::new(p, &hit))
                    } else if clear(through.min(margin.max(0.5 * through))) {
                        // Within reach at the start and ended clear: the
                        // speculative contacts held it, and an overlap is
                        // the push-out's to lift. Not past half of a thin
                        // partner's half thickness (and the margin): a
                        // mesh ball spinning at 200 rad/s turned its
                        // contacts' corners away within the step, sank 9
                        // mm into a 20 mm slab and stuck in it. Anything
                        // shallower is left to the push-out, as is every
                        // overlap with a thick partner: a tumbling box
                        // squeezed 5-10 mm into a pile's wall by the
                        // layers landing on it, put back where it began
                        // the step, had the layer above crash into it (the
                        // 10,000-body pile's deepest overlap doubled).
                        None
                    } else {
                        back_from_contact(
                            e,
                            p,
                            &hit,
                            &mine,
                            (&ca.shape, &ma),
                            (&cb.shape, &mb),
                            margin,
                            through,
                        )
                    };
                    if let Some(impact) = impact {
                        if first.as_ref().is_none_or(|i| impact.time < i.time) {
                            first = Some(impact);
                        }
                    }
                }
            }
        }
        first
    }
}

/// Where a body that began the step within reach of partner `p` (`hit`
/// at time 0) and did not end it clear goes back to. First the next
/// contact on the way: the time the pair came within half its starting
/// gap (a tumbling body's corner swinging in), where that corner takes
/// the impulse. Else the body's core, a ball inside it about its centre
/// of mass, may not cross the surface (Box2D's fallback): the body goes
/// back to where its core met the surface, or stays where it began if
/// its core was there already and went on inwards. Where the core never
/// reached the surface, a body that began the step resting on its side
/// stays there too, the points that would have sunk in taking the
/// impulses, carried back to that pose (else the same step would repeat
/// from the same state); one that began deep inside is left to the
/// push-out.
#[allow(clippy::too_many_arguments)]
fn back_from_contact(
    e: &BodyEntry,
    p: u32,
    hit: &Impact,
    mine: &(Pose, Pose),
    (shape_a, ma): (&Shape, &Motion),
    (shape_b, mb): (&Shape, &Motion),
    margin: f64,
    through: f64,
) -> Option<SweptImpact> {
    if hit.distance > 0.0 {
        let closer = ToiOptions {
            target: 0.5 * hit.distance,
            tolerance: 0.25 * hit.distance,
            max_iterations: MAX_ITERATIONS,
        };
        if let Ok(Some(next)) = time_of_impact(shape_a, ma, shape_b, mb, &closer) {
            if next.time > 0.0 && next.normal != DVec3::ZERO {
                return Some(SweptImpact::new(p, &next));
            }
        }
    }
    let core_motion = Motion::new(mine.0, mine.1, DVec3::ZERO);
    let core_tolerance = (0.1 * e.core).min(0.25 * margin);
    let core_hit = (e.core > 0.0)
        .then(|| Sphere::new(e.core).ok())
        .flatten()
        .and_then(|core| {
            let core_options = ToiOptions {
                target: 0.0,
                tolerance: core_tolerance,
                max_iterations: MAX_ITERATIONS,
            };
            time_of_impact(&Shape::Sphere(core), &core_motion, shape_b, mb, &core_options).ok()?
        });
    match core_hit {
        Some(h) if h.time > 0.0 => Some(SweptImpact::new(p, &h)),
        Some(h) => {
            let inwards = -(core_motion.end.position - core_motion.start.position).dot(h.normal);
            (inwards > core_tolerance).then(|| SweptImpact::new(p, &h))
        }
        None => (hit.distance >= -through.min(margin)).then(|| {
            let mut impact = SweptImpact::new(p, hit);
            impact
                .contacts
                .extend(sunk_points(margin, hit.normal, shape_a, ma, shape_b, &mb.end));
            impact
        }),
    }
}

/// Where a fast body is put back: the time of impact (fraction of the
/// step), the partner, and the contacts there (normals from the partner to
/// the body).
struct SweptImpact {
    time: f64,
    partner: u32,
    /// Contact points and normals (world, at the pose the body is put
    /// back to) that take the restitution law's impulses.
    contacts: Vec<(DVec3, DVec3)>,
}

impl SweptImpact {
    fn new(partner: u32, hit: &Impact) -> SweptImpact {
        SweptImpact {
            time: hit.time,
            partner,
            contacts: vec![(hit.point, hit.normal)],
        }
    }
}

/// The contacts of A at the end of its motion with B that face the side it
/// came from (`normal`, B to A), carried back to A's start pose (a point
/// moves with A; the normal is B's surface, left as it is).
fn sunk_points(
    margin: f64,
    normal: DVec3,
    a: &Shape,
    motion_a: &Motion,
    b: &Shape,
    pose_b: &Pose,
) -> Vec<(DVec3, DVec3)> {
    let mut out = Vec::new();
    if contact_shapes(a, &motion_a.end, b, pose_b, margin, &mut out).is_err() {
        return Vec::new();
    }
    let back = motion_a.start.mul_pose(&motion_a.end.inverse());
    out.iter()
        .filter(|c| c.distance < 0.0 && c.normal.dot(normal) > 0.0)
        .map(|c| (back.transform_point(c.point), c.normal))
        .collect()
}

/// Whether a body that met a surface on its way ends the step clear of
/// it: no deeper in than `depth` (contacts searched within `margin`), its
/// centre `center` still on the side of the impact point where
/// `hit.normal` (B to A) points, and not touching the partner from the far
/// side only. A body that flew on ends with its centre beyond, one beside
/// the far face of a thin slab touches it with the opposite normal: both
/// passed through. A body whose centre is not in its material (a
/// ring, `center` is `None`) touches others at points that say nothing of
/// sides (a ring hung on another is touched from inside its hole): for it,
/// only the depth counts.
#[allow(clippy::too_many_arguments)]
fn ends_clear(
    margin: f64,
    depth: f64,
    hit: &Impact,
    center: Option<DVec3>,
    a: &Shape,
    pose_a: &Pose,
    b: &Shape,
    pose_b: &Pose,
) -> bool {
    let mut out = Vec::new();
    if contact_shapes(a, pose_a, b, pose_b, margin, &mut out).is_err() {
        return false;
    }
    if out.iter().any(|c| c.distance < -depth) {
        return false;
    }
    let Some(center) = center else {
        return true;
    };
    // Touching only from the far side: beside the back face of a thin slab.
    // (A body in a crevice touches faces of every slant, some facing it.)
    let far_side = out.iter().any(|c| c.normal.dot(hit.normal) < -0.5)
        && out.iter().all(|c| c.normal.dot(hit.normal) <= 0.0);
    (center - hit.point).dot(hit.normal) >= 0.0 && !far_side
}

/// Linear and angular velocity (world frame) of `body` in the state
/// `state` it had before the step.
pub(super) fn state_velocities(state: &BodyState, body: &crate::body::RigidBody) -> (DVec3, DVec3) {
    let r = DMat3::from_quat(state.orientation);
    let omega = r * (body.inv_principal_inertia() * (r.transpose() * state.angular_momentum));
    (state.linear_momentum * body.inv_mass(), omega)
}

/// A body's motion over the step: its frame is the principal frame at the
/// centre of mass, which is also the point it turns about.
fn body_motion(before: &Pose, after: &Pose) -> Motion {
    Motion::new(*before, *after, DVec3::ZERO)
}

/// A collider's motion, given its body's poses before and after the step
/// and its pose in the body frame: the collider turns about the body's
/// centre of mass (the body frame's origin).
fn collider_motion((before, after): &(Pose, Pose), local: &Pose) -> Motion {
    Motion::new(
        before.mul_pose(local),
        after.mul_pose(local),
        local.inverse_transform_point(DVec3::ZERO),
    )
}
