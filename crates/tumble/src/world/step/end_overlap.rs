//! Part of [`Stage::Continuous`](crate::world::Stage::Continuous): overlaps
//! at the end of the step that the speculative contacts could not see.
//!
//! A speculative contact is a pair of closest features at the step's start.
//! When two bodies move against each other by more than the contact margin
//! within one step (a tumbling jack landing on another, a cup dropped into a
//! spinning one), the features that meet at the end may not be among them:
//! a corner swings in sideways, a vertex slides over a face it did not lie
//! above. The solver then never sees those points, and the pair ends the
//! step centimetres deep, left to the next steps' push-out.
//!
//! So after the sweeps, every pair with a triangle mesh whose bodies moved
//! against each other by more than the pair's margin (the mesh contact
//! margin for two meshes, the contact margin otherwise: what its
//! speculative contacts were found with) is collided again at
//! its end poses (two dynamic bodies only if they were closing in on each
//! other along the line of their centres by [`LANDING_CLOSING`] of the
//! pair's margin per step or more at the step's start, or closed in by that much
//! over the step, or one of them was struck within the step, its velocities
//! changed by [`STRUCK_MARGINS`] contact margins a step, or their surfaces
//! slid over each other at a contact by more than the pair's margin (the
//! contact margin if the pair began deeper than [`END_OVERLAP_CAP`] allowed
//! penetrations, being pushed out of an overlap): bodies that roll or
//! slide slowly on each other keep speculative contacts to the features
//! that meet, but a contact plane found at the step's start misses how a
//! curved surface bends away under a long slide), and so is a pair of
//! primitive shapes (no mesh) one of whose bodies was struck (a cube spun
//! by a corner's landing swings its other corners round), and where it
//! ends deeper than it began (at least the allowed penetration) by more
//! than [`END_OVERLAP_SLACK`] allowed penetrations ([`SLIDING_SLACK`] for a
//! sliding pair), or deeper than [`END_OVERLAP_CAP`] allowed penetrations
//! and a little deeper than it began, the step's addition is taken out. Left out: a pair that began deeper than two
//! margins ([`DEEP_START_MARGINS`]; two bodies spawned inside each other are
//! the push-out's to separate, along its own normals); a pair that a push
//! of this stage moves a body into is held at the depth it began the step
//! with, however deep that was. Fast bodies against static and kinematic
//! ones take part too, after the sweeps (which put back a body that passed
//! through a wall or sank deeper than the margin into it): a fast bracket
//! of the concave pile struck against the bin's floor, left to the sweeps
//! alone, ended 11 mm in it. Over the concave pile's standard start and 15 jittered ones
//! (`JITTER=seed TRACE_DEPTH=1 profile_stages concave_pile 600 1 |
//! scripts/deepest_stats.sh`): steps deeper than 5 mm 136 -> 91, deeper
//! than 10 mm 25 -> 15 with these two; the worst overlaps left were two
//! jacks spun into each other by the landing, whose centres did not close
//! in, and with the struck bodies too 39 and 6 steps, the worst overlap of
//! a run 4-11 mm (median 7) but for one 27 mm, against 8-20 mm (median 12)
//! before all three.
//!
//! The overlapping points are pushed back by a non-linear Gauss-Seidel
//! position step (Box2D v2's position solver, Catto 2009): a positional
//! impulse per point, shared by the bodies' masses and inertias there, the
//! displacements of all bodies taking part accumulated over a few sweeps of
//! all their points and applied at the end. Where a triangle mesh takes
//! part, only points that the pair's own approach made are pushed: the
//! point's motion on B against its motion on A over the step has a
//! component along the normal (B to A). The push-out normal of a triangle
//! pair deeper than a thin wall can point through the wall (a cup sunk in a
//! cup), and pushing along it sank such a pair deeper pass after pass. A
//! deep point that moved away from A along its normal, and that its
//! contact plane would put deeper at the step's start than the pair began
//! by more than [`DEEP_START_MARGINS`] margins, came in from the wall's far
//! side: it is pushed back the way it came, by its depth but at most twice
//! the thinner body's smallest half extent (a jack spinning at 29 rad/s
//! swept an arm 15 mm into another's, whose normals all ran on through the
//! arm; dropped, the points stayed). A looser test (any point that moved
//! away along its normal by less than its travel) took shallow points of
//! resting pairs for such and pushed them along their slides: a cup of the
//! concave pile's standard start left the bin through its wall. Two
//! convex shapes have no thin wall, and their normal is the shortest way out
//! however they came in: all their deep points are pushed. Each pair's
//! approach at its deepest point is then stopped by a plastic impulse
//! (removes kinetic energy, never adds it; no bounce, no friction). Up to
//! six passes, each colliding again the mesh pairs of the bodies the last
//! one moved (a body pushed out of one may be in another), the sixth's
//! pushes undone where one more collision finds them deeper than what they
//! took out. Moving positions
//! adds no kinetic energy; the potential energy of a lift is the weight
//! times the overlap taken out.
//!
//! Guards: the other pairs of the bodies a pass pushes apart take part in
//! its position step too, with their points within the contact margin,
//! each point held where it is (or at its pair's floor, if shallower): a
//! guard pushes only where the pass would sink its pair deeper. Without
//! them a body squeezed between two others went back and forth between
//! them pass after pass (a bracket of the concave pile struck against the
//! bin's floor: 12.7 mm deep in the floor, pushed out, pushed back in by
//! the body on it 11.6 mm, ... 7.5 mm after the sixth pass). Over 32
//! starts of the concave pile (`ensemble_depth concave_pile200 32 120`,
//! the landing) the median of the runs' worst overlap fell from 3.6 to
//! 3.2 mm and the worst run from 27 to 15 mm; over the torus chain's 16
//! starts (`ensemble_depth chain 16 600`) from 1.9 to 1.5 mm. It costs the
//! concave pile 0.4 ms a step over its first 300 (`profile_stages
//! concave_pile 300 1`: this stage 2.1 -> 2.5 ms) and the 10,000-body
//! pile's landing 2.7 ms a step (6.0 -> 8.7 ms over the first 300 steps
//! on two threads), nothing once they rest. Guards that held only pairs
//! touching already (no margin) did as well on the pile but let a body
//! knocked into one against a wall stay 4.7 mm in the wall
//! (`a_body_knocked_against_a_wall_is_pushed_out_of_both_its_neighbours`).
//! With the far-side points and the fast bodies against walls besides
//! (above), over 64 starts of the concave pile's landing (`ensemble_depth
//! concave_pile200 64 120`) the median of the runs' worst overlap went
//! from 3.8 to 2.6 mm, the 90th percentile from 5.9 to 4.2 and the worst
//! run from 27 to 6.8 mm; the standard start's worst step over 600 steps
//! from 3.3 to 2.6 mm (`profile_stages concave_pile 600 1`). With each
//! pair's thresholds counted in its own margin and [`END_OVERLAP_CAP`],
//! the median went to 1.75 mm (40 of the 64 runs at or under 2 mm, 6
//! before), the standard start's worst step to 1.6 mm (0 escapes, its time
//! 17.2 -> 17.6 ms a step, builds alternated; over three jittered starts
//! 15.9 ms both), and over 32 starts of the torus chain (`ensemble_depth
//! chain 32 600`) the median from 1.60 to 1.36 mm and the worst run from
//! 4.2 to 2.8 mm, its time unchanged.
//!
//! Measured on the concave pile (600 steps of 160 to 240 bodies): the
//! deepest overlap of any step 10-14 mm instead of 35-39 mm, 22-34 steps
//! deeper than 2 mm instead of 32-44 (the step counts before the review
//! mends of 75ee60f). Colliding every dynamic pair that
//! moved by the margin again (no closing test) gave 6-12 mm and 9-21 steps
//! but cost the torus chain 1.5 ms per step (now 0.1 ms). Closing in over
//! the step, besides at its start, catches a body knocked into another by a
//! third within the step (`JITTER=seed TRACE_DEPTH=1 profile_stages
//! concave_pile 600 2 | scripts/deepest_stats.sh`, the standard start and
//! seeds 1-7: the worst overlap 12-39 mm, median 25, -> 7-20 mm, median 14;
//! steps deeper than 5 mm 11-140 -> 4-13; the torus chain's trajectory and
//! cost unchanged).
//!
//! The first pass collides two meshes from the front where the pair's
//! first-pass walk ended last step (`StepScratch::end_fronts`,
//! `bvh::front`): the same contacts, with about half the box tests where
//! the two stay entangled (the torus chain's links: 700 against 1,310 from
//! the roots). The narrow phase's own fronts are no start for it: they
//! follow a walk with a margin and a look-ahead, and a concave pile's
//! pairs walked 600 box tests from them against 100 from the roots.
//!
//! Jointed bodies: a body of primitive shapes on a joint stays where the
//! solver left it, as in the sweeps (pushed alone, it would open its
//! joints). A jointed body with a triangle mesh takes part like any other.
//! Two chains of three mesh links hung side by side from one palm and
//! swung into each other (test `joints::chains_of_mesh_links_swung_into_
//! each_other_gain_no_energy`) showed why: their links cross within a
//! step, past their speculative contacts (docs/pipeline.md, 2026-12-05),
//! and left where the solver put them they ended 13-18 mm inside each
//! other. A crossing of two thin meshes has patches
//! that point every way; their push-out and warm starts fought the joints
//! through the palm, and the chains, passive, gained up to 21 J (links of
//! 100 g, which swing with about 30 mJ). Taken out here, the overlap is
//! at most 2.1 mm and no step gains energy; the joints the push opened
//! (14-18 mm, for that one step) are closed by the next step's push-out
//! (to under a micron). Cuboid links keep one normal a face and their
//! speculative contacts catch the tips (0.06 mm deep at most): they never
//! need this. The mesh links' crossing had a cause in the narrow phase,
//! mended since: their closest features were corners against corners,
//! which it did not report (`tumble_collide::triangle::tri_vertex_edge`).
//! Now the mesh links never overlap either, and jointed mesh bodies stay
//! in this pass as the safety net every other body has.
//!
//! Determinism: the contacts of a pass are computed from one set of poses
//! (on the world's threads, merged in pair order); the positions are
//! corrected on one thread in pair order.

use super::continuous::state_velocities;
use super::frame::MeshPairKey;
use super::StepFrame;
use crate::body::{BodyKind, RigidBody};
use crate::world::patches::PreparedPoint;
use crate::world::World;
use tumble_collide::narrow::{contact_mesh_mesh_from_front, contact_shapes, MeshPairMemory};
use tumble_collide::query::Motion;
use tumble_collide::{Contact, DMat3, DQuat, DVec3, Pose, Shape};

/// A pair collided again at its end poses is separated when it ends deeper
/// than its floor (its depth at the step's start, at least the allowed
/// penetration) by more than this many allowed penetrations (the solver's
/// own resting overlap is one, a mesh pair's skin two).
pub const END_OVERLAP_SLACK: f64 = 2.0;

/// A pair collided again at its end poses is also separated when it ends
/// deeper than this many allowed penetrations (1.5 mm by default) and
/// [`CAP_SLACK`] deeper than its floor, however much slack it has: a pair
/// that began the step 1.2 mm deep (the solver lifts it over a few steps)
/// may add only what takes it to 1.5 mm, not [`END_OVERLAP_SLACK`] more (a
/// blob of the concave pile rolling on the bin's floor, 2.2 mm after such
/// a step). With the pairs' own margins (`pair_margin` in
/// `separate_end_overlaps`), over 64 starts of the concave pile's landing
/// (`ensemble_depth concave_pile200 64 120`) the median of the runs' worst
/// overlap went from 2.60 to 1.75 mm (the 90th percentile stayed 4.2 mm),
/// the runs at or under 2 mm from 6 to 40; with struck counted in the mesh
/// margin too, 1.61 mm with this cap and 2.01 mm without it.
pub const END_OVERLAP_CAP: f64 = 3.0;

/// How much deeper than its floor (in allowed penetrations) a pair over
/// [`END_OVERLAP_CAP`] must end the step to be separated: a pair lifted by
/// the solver over a few steps that sinks a few microns is not worth a
/// pass.
const CAP_SLACK: f64 = 0.25;

/// A pair of dynamic bodies with a mesh whose surfaces slid over each other
/// at a contact by more than the pair's margin within the step is collided
/// again at its end too, and separated when it ends deeper than its floor
/// by more than this many allowed penetrations (not
/// [`END_OVERLAP_SLACK`]'s two).
///
/// A contact found at the step's start is a plane through two points. Two
/// links of the torus chain whipping past the vertical slide over each
/// other by 10-12 cm a step, along the inside of a ring curved at 1/0.8 m:
/// the surface rises out of that plane by s^2 / 2 rho, 6-9 mm, and a link
/// sank 0.7-0.9 mm further each step (1.3, 2.0, 2.9 mm at steps 152-154 of
/// the standard start), each step's addition under two allowed
/// penetrations and the floor rising with the depth it began at. Half an
/// allowed penetration takes each addition out: over 48 jittered starts of
/// `ensemble_depth chain 48 600` the median of the runs' deepest overlap
/// fell from 2.45 to 1.68 mm (one allowed penetration: 1.85; none: 1.68),
/// at 3.5 % more time a step on one thread (`profile_stages chain 600 1`,
/// builds alternated: 1.358 -> 1.405 ms). Only the step's addition is taken out, the
/// floor stays the depth the pair began with: pushed out to the allowed
/// penetration instead, a cup of the concave pile went through the bin's
/// floor (`profile_stages concave_pile 600 2`, one body escaped). Over 32
/// starts of the concave pile (`ensemble_depth concave_pile200`, runs 0-31)
/// the median worst overlap of a run was 3.95 and 4.66 mm over the two
/// halves against 4.58 and 4.18 without, its worst runs set by landings
/// (a cup dropped 0.86 m/s into a cup, 9-36 mm with and 7-12 mm without
/// over the same starts: the pile is chaotic, and a change moves every
/// landing).
pub const SLIDING_SLACK: f64 = 0.5;

/// Two dynamic bodies are collided again only when they closed in on each
/// other along the line of their centres by at least this fraction of the
/// contact margin per step at the step's start.
pub const LANDING_CLOSING: f64 = 0.5;

/// Two dynamic bodies that did not close in on each other are collided
/// again when one of them was struck within the step: its velocities
/// changed by enough to move its surface this many contact margins over
/// the step (change of linear velocity plus change of angular velocity
/// times its radius). One threshold for every pair, two margins:
///
/// - Mesh pairs: over the concave pile's 16 starts of `ensemble_depth
///   concave_pile200 16 600` the worst overlap of a run was 3.1-7.1 mm
///   (median 4.7) with two margins against 3.8-26 mm (median 5.7) with
///   four and 3.1-11 mm (median 4.9) with three (on the standard start two
///   bodies, one knocked down 0.6 m/s within the step by a third, met 3.8
///   mm deep at features 15-20 cm from their speculative contacts: struck
///   by 3.4 margins). It
///   costs the torus chain, whose links are jerked by their neighbours
///   every step, 0.12 ms a step on one thread (1.23 -> 1.35 ms, builds
///   alternated; two threads 0.77 -> 0.83), its trajectory unchanged. A
///   pair without a speculative contact needs it most: chain link 17
///   yanked up by link 16 at 1.06 m/s within a step (3.5 margins) sank its
///   lower tube 11 mm into link 18, which it had not been touching.
/// - Pairs without a triangle mesh (boxes, spheres, capsules, hulls) take
///   part only when one of their bodies was struck: a cube of the
///   10,000-body pile struck on a corner as it lands spins, and swings
///   another corner into a neighbour that no speculative contact held. On
///   the pile's standard start (`TRACE_DEPTH=1 profile_stages pile10000
///   200 2`) the deepest overlap after the spawn's 5 cm was 9.6 cm without
///   these pairs, 6.3 cm at eight margins, 5.5 at four and 4.5 at two. It
///   costs the landing (this stage took 41 ms a step on one thread over
///   the first 150 steps instead of 5: about 7,000 pairs collided again in
///   the first pass), and nothing once the pile rests: a body at rest is
///   struck by nothing, and a world with no mesh and no struck body leaves
///   the stage at once.
pub const STRUCK_MARGINS: f64 = 2.0;

/// Most passes of collision and separation per step (a pass runs only
/// while a pair is still deep). Six with [`SWEEPS`] sixteen, not three with
/// four: a body squeezed between two others was pushed out of one into the
/// other pass after pass, about half way each time (a bar struck into a
/// slab by a cube: 85, 39, 35 mm); over the concave pile's 16 starts the
/// steps deeper than 5 mm fell from 39 to 18 and the standard start's
/// deepest overlap from 10.6 to 3.8 mm, its time unchanged (six passes
/// with four sweeps shared the bar's overlap out between the slab and the
/// cube instead).
///
/// The sixth pass's pushes are checked by one more collision of the pairs
/// of the bodies it moved, and undone (positions and velocities as before
/// it) where they left a pair deeper than the deepest overlap they took
/// out: a cup of the concave pile squeezed between a cup it landed in and
/// a third body went 31.7, 0, 12.7, 0, 7.0, 0 mm deep in the first over the
/// passes, and the sixth, pushing it out of the third, sank it 33 mm back
/// in, which nothing checked. Over 32 starts of the concave pile
/// (`ensemble_depth concave_pile200 32 600`) the median of the runs' worst
/// overlap fell from 4.1 to 3.6 mm (that run 36 -> 27 mm; the worst run
/// but one 11 mm, p90 7.5); over the 10,000-body pile's first 300 steps
/// (`TRACE_DEPTH=1 profile_stages pile10000 300 2`) the deepest overlap
/// after the spawn fell from 4.4 to 3.9 cm. The chain never needs six passes
/// (its bits are unchanged).
const PASSES: usize = 6;

/// A pair that began the step deeper than this many contact margins is the
/// push-out's alone (module docs). Two, not one: a cube of the 10,000-body
/// pile 6.7 mm into a neighbour at the step's start, spun round by the
/// landing, swung an edge 5.7 cm into it within the step, which one margin
/// (5 mm) left to the push-out. Over the pile's standard start and jittered
/// starts 1-10 (`JITTER=seed TRACE_DEPTH=1 profile_stages pile10000 300 2`,
/// the deepest overlap after step 3) the worst overlap of a run was 3.9-8.9
/// cm (median 5.1) with one margin, 3.9-5.5 cm (median 4.5) with two, and
/// 3.9-6.6 cm (median 4.9) with no limit (holding every deep pair at its
/// start depth fought the push-out under the pile's load).
const DEEP_START_MARGINS: f64 = 2.0;

/// Largest turn (rad) one pass gives a body.
const MAX_TURN: f64 = 0.1;

/// Gauss-Seidel sweeps over the overlapping points per pass (see
/// [`PASSES`]).
const SWEEPS: usize = 16;

/// The walk fronts of a pair's mesh pairs, by collider pair.
type Fronts = Vec<(MeshPairKey, MeshPairMemory)>;

/// What colliding a pair again gives: its floor, whether it is deeper than
/// its trigger, its points within the reach, its walk fronts.
type Collided = (f64, bool, Vec<Contact>, Fronts);

/// One point of [`World::push_apart`]'s sweeps, with what stays fixed
/// over them.
struct PushRow {
    /// Entries of bodies A and B in the pass's list of bodies.
    bodies: [usize; 2],
    /// Lever arms from A's and B's centres to the point (zero for a side
    /// that does not move).
    r: [DVec3; 2],
    /// Normal, B to A.
    n: DVec3,
    /// The inverse of the point's effective mass along `n` (`sum 1/m + (r x
    /// n) . I^-1 (r x n)` over the sides that move).
    k: f64,
    /// The point's depth at the pass's start (m).
    depth: f64,
    /// How deep it may stay (m).
    floor: f64,
}

/// A pair that ended the step deeper than it began it, or a guard.
struct Overlap {
    /// Body slots, `a < b`.
    pair: (u32, u32),
    /// How deep it may stay (m): its depth at the step's start, at least the
    /// allowed penetration.
    floor: f64,
    /// Its points deeper than that, made by its approach, and its points
    /// within the guard reach (normals B to A).
    contacts: Vec<Contact>,
    /// A guard: this pair is not pushed apart, only held from sinking
    /// deeper than it is while the pairs beside it are.
    hold: bool,
}

/// One value per body pair, the smallest or the largest of its patches',
/// looked up by the pair (sorted by it: no hash order).
struct PerPair(Vec<((u32, u32), f64)>);

impl PerPair {
    fn smallest(values: impl Iterator<Item = ((u32, u32), f64)>) -> PerPair {
        PerPair::first_by(values, f64::total_cmp)
    }

    fn largest(values: impl Iterator<Item = ((u32, u32), f64)>) -> PerPair {
        PerPair::first_by(values, |x, y| y.total_cmp(x))
    }

    /// Each pair's value that comes first in `order`.
    fn first_by(
        values: impl Iterator<Item = ((u32, u32), f64)>,
        order: impl Fn(&f64, &f64) -> std::cmp::Ordering,
    ) -> PerPair {
        let mut v: Vec<_> = values.collect();
        if v.is_sorted_by(|x, y| x.0 <= y.0) {
            // In pair order already (the step's patches are): each pair's
            // run of values kept as its first in `order`, without the sort
            // (2.2 -> 0.9 ms a step of the pile of 10,000's landing, serial).
            // Values that `order` finds equal are the same bits (a total
            // order): what the sort kept.
            let mut runs: Vec<((u32, u32), f64)> = Vec::with_capacity(v.len());
            for (pair, x) in v {
                match runs.last_mut() {
                    Some(last) if last.0 == pair => {
                        if order(&x, &last.1).is_lt() {
                            last.1 = x;
                        }
                    }
                    _ => runs.push((pair, x)),
                }
            }
            return PerPair(runs);
        }
        v.sort_unstable_by(|x, y| x.0.cmp(&y.0).then(order(&x.1, &y.1)));
        v.dedup_by_key(|e| e.0);
        PerPair(v)
    }

    fn get(&self, pair: (u32, u32)) -> Option<f64> {
        self.0
            .binary_search_by(|e| e.0.cmp(&pair))
            .ok()
            .map(|i| self.0[i].1)
    }
}

/// Body slots per task of the per-body tests on the pool.
const SLOTS_PER_TASK: usize = 512;

/// Candidate pairs per task of the tests that pick the pairs to collide
/// again (a pile of 10,000 has some 100,000, and each pass tests them
/// all again).
const PAIRS_PER_TASK: usize = 4096;

/// The pairs of `pairs` for which `keep` holds, in their order, tested on
/// the pool.
fn pairs_where(
    pool: &crate::pool::WorkerPool,
    pairs: &[(u32, u32)],
    keep: impl Fn(u32, u32) -> bool + Sync + Send,
) -> Vec<(u32, u32)> {
    pool.flat_map_chunks(pairs, PAIRS_PER_TASK, |_, run| {
        run.iter().copied().filter(|&(a, b)| keep(a, b)).collect()
    })
}

impl World {
    /// Separates the pairs that ended the step deep in each other after
    /// moving against each other by more than the contact margin (module
    /// docs).
    pub(super) fn separate_end_overlaps(&mut self, f: &mut StepFrame, jointed: &[bool]) {
        let margin = f.settings.contact_margin;
        let allowed = f.settings.allowed_penetration;
        let dt = f.settings.dt;
        // Per body slot: how far its velocity change over the step moved its
        // surface (m; change of linear velocity plus change of angular
        // velocity times its radius, over dt): a body struck
        // within the step, which the speculative contacts, found with the
        // velocities the step began with, did not foresee. Two jacks spun
        // round by a landing swept their arms through each other while
        // their centres stayed apart; a cube of the 10,000-body pile struck
        // on a corner as it landed swung another corner 9 cm into a
        // neighbour.
        let struck_by: Vec<f64> = f.pool.map_indices(f.n_slots, SLOTS_PER_TASK, |slot| {
            let (Some(Some(state)), Some(e)) = (f.before.get(slot as usize), self.bodies.at(slot)) else {
                return 0.0;
            };
            if e.body.kind() != BodyKind::Dynamic {
                return 0.0;
            }
            let (v0, w0) = state_velocities(state, &e.body);
            let change =
                (e.body.velocity() - v0).length() + (e.body.angular_velocity() - w0).length() * e.radius;
            change * dt
        });
        // Without meshes only the pairs of struck bodies take part: a world
        // with neither has nothing here (and need not index its contact
        // patches every step for it).
        if !f.meshes && !struck_by.iter().any(|&s| s > STRUCK_MARGINS * margin) {
            return;
        }
        // How far any point of `b` moved against `a` over the step: the
        // relative pose's travel plus its turn times b's radius.
        let relative_travel = |a: u32, b: u32| -> f64 {
            let (Some(ea), Some(eb)) = (self.bodies.at(a), self.bodies.at(b)) else {
                return 0.0;
            };
            let before = |slot: u32, now: Pose| {
                f.before
                    .get(slot as usize)
                    .copied()
                    .flatten()
                    .map_or(now, |s| s.pose())
            };
            let (now_a, now_b) = (ea.body.pose(), eb.body.pose());
            let start = before(a, now_a).inverse().mul_pose(&before(b, now_b));
            let end = now_a.inverse().mul_pose(&now_b);
            let motion = Motion::new(start, end, DVec3::ZERO);
            motion.travel().length() + motion.turn() * eb.radius
        };
        // Per body slot: has a triangle mesh.
        let meshy: Vec<bool> = (0..f.n_slots as u32)
            .map(|slot| self.bodies.at(slot).is_some_and(super::margins::has_mesh))
            .collect();
        // Per body slot: dynamic, awake, and not jointed unless it has a
        // triangle mesh (a jointed body of primitives stays where the
        // solver left it, as in the sweeps; module docs, "Jointed bodies").
        let movable: Vec<bool> = (0..f.n_slots as u32)
            .map(|slot| {
                (!jointed[slot as usize] || meshy[slot as usize])
                    && self
                        .bodies
                        .at(slot)
                        .is_some_and(|e| e.body.kind() == BodyKind::Dynamic && !e.sleeping)
            })
            .collect();
        let movable_slots = movable;
        let movable = |slot: u32| movable_slots[slot as usize];
        let has_mesh = |slot: u32| meshy[slot as usize];
        // The margin the pair's speculative contacts were found with
        // (`mesh_contact_margin` for two meshes): the thresholds below that
        // say whether the pair may have met features its speculative
        // contacts did not hold (moved, closed in; slid, for a pair that
        // began the step shallow) count in it. Counted in the contact
        // margin (5 mm, not 2), they left alone a torus of the concave pile
        // rocking on another, which found one of its two contact regions
        // each step and swung the other 4.8 mm deep. A pair already deeper
        // than END_OVERLAP_CAP allowed penetrations is being pushed out
        // along its own normals, which slides it across the normals of its
        // overlap's other points: two tori spawned overlapping, taken for a
        // sliding pair in the mesh margin, were pushed 26 mm sideways
        // (`sliding` keeps the contact margin for them). Struck stays
        // counted in the contact margin: in the mesh margin it took the
        // median of the concave pile's 64 landings from 1.75 to 1.61 mm
        // but cost the torus chain, whose links jerk each other every step,
        // 0.27 ms a step on one thread (1.25 -> 1.55 ms).
        let pair_margin = |a: u32, b: u32| {
            if has_mesh(a) && has_mesh(b) {
                f.settings.mesh_contact_margin
            } else {
                margin
            }
        };
        // Struck within the step, by STRUCK_MARGINS contact margins.
        let struck =
            |a: u32, b: u32| struck_by[a as usize].max(struck_by[b as usize]) > STRUCK_MARGINS * margin;
        // Which pairs may take part: a body that can move, and a mesh or a
        // struck body (a pile of boxes at rest has none, and skips the
        // rest). Against a static or kinematic body too, fast or slow,
        // touching it at the step's start or not: the sweeps ran first and
        // put back a body that passed through or sank deeper than the
        // margin, and a point that came in from a wall's far side goes back
        // the way it came (`end_overlaps`). (Once a fast body that had not
        // touched the wall was left to the sweeps alone: a bracket of the
        // concave pile struck against the bin's floor ended 11 mm in it.)
        let may_take_part =
            |a: u32, b: u32| (movable(a) || movable(b)) && (has_mesh(a) || has_mesh(b) || struck(a, b));
        let candidates = pairs_where(&f.pool, &f.pairs, may_take_part);
        if candidates.is_empty() {
            return;
        }
        // How deep each pair was at the step's start: an overlap that was
        // already there is the solver's push-out's to lift (it moves bodies
        // apart without giving them speed); this stage takes out only what
        // the step added to it, down to the allowed penetration.
        let closest = PerPair::smallest(f.patches.iter().map(|patch| {
            let gap = f
                .points
                .of(patch)
                .iter()
                .map(|p| p.contact.distance)
                .fold(f64::INFINITY, f64::min);
            ((patch.key.0, patch.key.1), gap)
        }));
        let start_gap = |a: u32, b: u32| closest.get((a, b)).unwrap_or(f64::INFINITY);
        let floor = |a: u32, b: u32| (-start_gap(a, b)).max(allowed);
        // How far the surfaces of two dynamic bodies with a mesh slid over
        // each other at their contacts in the step (m): the largest motion
        // of a contact point on B against A across its normal. Along a
        // curved mesh such a pair meets features its step-start contacts
        // saw only as planes.
        let slides = PerPair::largest(
            f.patches
                .iter()
                .map(|patch| (patch.key.0, patch.key.1, patch))
                .filter(|&(a, b, _)| movable(a) && movable(b) && (has_mesh(a) || has_mesh(b)))
                .map(|(a, b, patch)| ((a, b), self.slide(f, (a, b), f.points.of(patch)))),
        );
        // In the pair's margin where the pair began the step no deeper than
        // END_OVERLAP_CAP allowed penetrations, else in the contact margin
        // (see `pair_margin`).
        let sliding = |a: u32, b: u32| {
            let reach = if floor(a, b) <= END_OVERLAP_CAP * allowed {
                pair_margin(a, b)
            } else {
                margin
            };
            slides.get((a, b)).is_some_and(|s| s > reach)
        };
        // How fast two dynamic bodies closed in on each other along the line
        // of their centres at the step's start (m per step): a landing. Two
        // bodies that roll on each other or slide by less than the margin
        // without closing in keep their speculative contacts to the
        // features that meet, and colliding every such pair again would
        // cost as much as their narrow phase (the torus chain: 1.5 ms more
        // per step; the links that slide by more, `sliding`, 0.05 ms).
        let closing = |a: u32, b: u32| {
            let (Some(Some(sa)), Some(Some(sb))) = (f.before.get(a as usize), f.before.get(b as usize))
            else {
                return 0.0;
            };
            let (Some(ea), Some(eb)) = (self.bodies.at(a), self.bodies.at(b)) else {
                return 0.0;
            };
            let (va, _) = state_velocities(sa, &ea.body);
            let (vb, _) = state_velocities(sb, &eb.body);
            let line = (sb.pose().position - sa.pose().position).normalize_or_zero();
            let announced = (-(vb - va).dot(line)).max(0.0) * f.settings.dt;
            // Or what they did close in over the step: a body struck by a
            // third within the step moves at a speed its start did not
            // announce (a jack knocked into another by a falling torus
            // sank 25 mm into it, the pair's first contacts in the step).
            let before = (sb.pose().position - sa.pose().position).length();
            let after = (eb.body.position() - ea.body.position()).length();
            announced.max(before - after)
        };
        // A pair that began the step deeper than DEEP_START_MARGINS is the
        // push-out's alone (two bodies spawned inside each other separate
        // along their own push-out normals, and the points that separation
        // crosses are no landing), unless this stage pushes a body into it
        // (below).
        let eligible = |a: u32, b: u32| may_take_part(a, b) && floor(a, b) <= DEEP_START_MARGINS * margin;
        // How deep a pair may end the step before it is separated: its
        // floor plus its slack, or at most END_OVERLAP_CAP allowed
        // penetrations if that is deeper than the floor by CAP_SLACK.
        let trigger = |floor: f64, slack: f64| {
            (floor + slack * allowed).min((floor + CAP_SLACK * allowed).max(END_OVERLAP_CAP * allowed))
        };
        let mut active = pairs_where(&f.pool, &candidates, |a, b| {
            eligible(a, b)
                && relative_travel(a, b) > pair_margin(a, b)
                && (!movable(a)
                    || !movable(b)
                    || closing(a, b) >= LANDING_CLOSING * pair_margin(a, b)
                    || struck(a, b)
                    || sliding(a, b))
        });
        let mut moved = vec![false; f.n_slots];
        // The bodies the last pass moved, as they were before it, and the
        // deepest overlap it took out.
        let mut undo: Option<(Vec<(u32, RigidBody)>, f64)> = None;
        // The first pass's walk fronts, kept for the next step in pair order.
        let mut end_fronts = Vec::new();
        for pass in 0..=PASSES {
            if active.is_empty() {
                break;
            }
            let frame: &StepFrame = f;
            // Each pair's floor, whether it is deeper than its trigger, and
            // its points within `reach` (see `end_overlaps`), in pair order
            // by runs of pairs. Read through the runs, not joined into one
            // list: the join moved every result once more (1.3 ms a step of
            // the pile of 10,000's landing on one thread, 2.7 on two,
            // serial).
            let collide = |pairs: &[(u32, u32)], reach: f64, keep: bool| -> Vec<Vec<Collided>> {
                frame
                    .pool
                    // A mesh pair can cost as much as a thousand box pairs:
                    // one pair a task where there are meshes, else runs.
                    .map_chunks(pairs, if frame.meshes { 1 } else { 32 }, |_, chunk| {
                        chunk
                            .iter()
                            .map(|&(a, b)| {
                                let before = |slot: u32| {
                                    frame
                                        .before
                                        .get(slot as usize)
                                        .copied()
                                        .flatten()
                                        .map(|s| s.pose())
                                };
                                let floor = floor(a, b);
                                let slack = if sliding(a, b) {
                                    SLIDING_SLACK
                                } else {
                                    END_OVERLAP_SLACK
                                };
                                let trigger = trigger(floor, slack);
                                let mut fronts = Vec::new();
                                let (deep, contacts) = self.end_overlaps(
                                    (a, before(a)),
                                    (b, before(b)),
                                    floor,
                                    trigger,
                                    reach,
                                    keep.then_some(&mut fronts),
                                );
                                (floor, deep, contacts, fronts)
                            })
                            .collect::<Vec<_>>()
                    })
            };
            // The first pass's walks (every pair that may have met new
            // features, at the step's end poses) begin where the last
            // step's ended, and keep where they end for the next step.
            // Without meshes, where guards follow (below), the pairs are
            // collided within the guards' reach: a guard that this pass
            // has collided already takes its points from here (most of
            // them: the stage collided pairs 112,000 times a step of the
            // pile of 10,000's landing, now 76,000, with the same bits).
            // Mesh pairs keep colliding with no reach, as their walks'
            // fronts are kept for the next step.
            let reuse = !f.meshes && pass < PASSES;
            debug_assert!(active.is_sorted(), "pairs in pair order");
            let mut collided = collide(&active, if reuse { margin } else { 0.0 }, pass == 0);
            if pass == 0 {
                end_fronts = collided
                    .iter_mut()
                    .flatten()
                    .flat_map(|c| std::mem::take(&mut c.3))
                    .collect();
            }
            // The pairs not deep, with their points within the guards'
            // reach (`reuse`), in pair order.
            let mut shallow: Vec<((u32, u32), f64, Vec<Contact>)> = Vec::new();
            let mut deep: Vec<Overlap> = Vec::new();
            for (&pair, (floor, is_deep, contacts, _)) in active.iter().zip(collided.into_iter().flatten()) {
                if is_deep {
                    deep.push(Overlap {
                        pair,
                        floor,
                        contacts,
                        hold: false,
                    });
                } else if reuse {
                    shallow.push((pair, floor, contacts));
                }
            }
            if reuse {
                // The deep pairs' points to push are those found with no
                // reach: within it, a face's points are reduced to four
                // that may leave out an overlapping one for one that only
                // nears. Whether the pair is deep rests on its deepest
                // point, which the reduction keeps (to within its tie
                // tolerance, a hundred-thousandth of the patch's size).
                let pairs: Vec<(u32, u32)> = deep.iter().map(|o| o.pair).collect();
                for (o, (_, _, contacts, _)) in deep
                    .iter_mut()
                    .zip(collide(&pairs, 0.0, false).into_iter().flatten())
                {
                    o.contacts = contacts;
                }
            }
            // Beside the pairs to push apart, as guards, the other pairs of
            // their bodies with their points within the contact margin: a
            // body squeezed between two others, pushed out of one, must not
            // be pushed into the other (without guards it went back and
            // forth between them pass after pass, as deep as it started).
            if pass < PASSES && !deep.is_empty() {
                let mut pushed = vec![false; f.n_slots];
                for o in &deep {
                    pushed[o.pair.0 as usize] |= movable(o.pair.0);
                    pushed[o.pair.1 as usize] |= movable(o.pair.1);
                }
                let mut pairs: Vec<(u32, u32)> = deep.iter().map(|o| o.pair).collect();
                pairs.sort_unstable();
                let beside = pairs_where(&f.pool, &f.pairs, |a, b| {
                    (pushed[a as usize] || pushed[b as usize])
                        && may_take_part(a, b)
                        && pairs.binary_search(&(a, b)).is_err()
                });
                // Each guard's entry in `shallow` (in pair order, as
                // `active` is), if this pass collided it; those it did not
                // are collided now, then all taken in order.
                let reused: Vec<Option<usize>> = beside
                    .iter()
                    .map(|p| shallow.binary_search_by_key(p, |s| s.0).ok())
                    .collect();
                let fresh: Vec<(u32, u32)> = beside
                    .iter()
                    .zip(&reused)
                    .filter(|(_, r)| r.is_none())
                    .map(|(&p, _)| p)
                    .collect();
                let mut fresh_collided = collide(&fresh, margin, false).into_iter().flatten();
                for (&pair, &reused) in beside.iter().zip(&reused) {
                    let (floor, contacts) = match reused {
                        Some(i) => {
                            let s = &mut shallow[i];
                            (s.1, std::mem::take(&mut s.2))
                        }
                        None => {
                            let (floor, _, contacts, _) = fresh_collided.next().expect("one per fresh pair");
                            (floor, contacts)
                        }
                    };
                    if !contacts.is_empty() {
                        deep.push(Overlap {
                            pair,
                            floor,
                            contacts,
                            hold: true,
                        });
                    }
                }
            }
            let deepest = deep
                .iter()
                .filter(|o| !o.hold)
                .flat_map(|o| &o.contacts)
                .map(|c| -c.distance)
                .fold(0.0, f64::max);
            if pass == PASSES {
                // Nothing checked the last pass's pushes: where they sank a
                // pair deeper than the deepest overlap they took out (a body
                // squeezed between two others, pushed out of one into the
                // other), they are undone.
                if let Some((bodies, took_out)) = undo.take() {
                    if deepest > took_out {
                        for (slot, body) in bodies {
                            self.bodies.at_mut(slot).expect("live").body = body;
                        }
                    }
                }
                break;
            }
            if deep.iter().all(|o| o.hold) {
                break;
            }
            if pass + 1 == PASSES {
                // Only the last pass's pushes are checked (above): the bodies
                // it moves, as they are before it.
                let mut pushed: Vec<u32> = deep
                    .iter()
                    .flat_map(|o| [o.pair.0, o.pair.1])
                    .filter(|&slot| movable(slot))
                    .collect();
                pushed.sort_unstable();
                pushed.dedup();
                undo = Some((
                    pushed
                        .into_iter()
                        .map(|slot| (slot, self.bodies.at(slot).expect("live").body.clone()))
                        .collect(),
                    deepest,
                ));
            }
            moved.iter_mut().for_each(|m| *m = false);
            for &Overlap { pair: (a, b), .. } in &deep {
                moved[a as usize] |= movable(a);
                moved[b as usize] |= movable(b);
            }
            self.push_apart(&deep, &movable_slots);
            // The next pass collides again every mesh pair that a moved
            // body is in (a body pushed out of one may now be in another),
            // a pair that began the step deep in each other too: this stage
            // may not push it deeper than it began (a jack pushed out of the
            // bin's wall sank 9 mm into a neighbour it already overlapped,
            // and two bodies tangled beside it ended 29 mm deep).
            active = pairs_where(&f.pool, &f.pairs, |a, b| {
                (moved[a as usize] || moved[b as usize]) && may_take_part(a, b)
            });
        }
        // In pair order, which is key order; sorted if ever not.
        if !end_fronts.windows(2).all(|w| w[0].0 < w[1].0) {
            end_fronts.sort_by_key(|e| e.0);
        }
        self.scratch.end_fronts = end_fronts;
    }

    /// How far a contact point of `points` (the pair's step-start contacts)
    /// moved on body `b` against body `a` over the step across the point's
    /// normal (m, the largest of the points): the two bodies' poses before
    /// the step and now.
    fn slide(&self, f: &StepFrame, (a, b): (u32, u32), points: &[PreparedPoint]) -> f64 {
        let poses = |slot: u32| {
            let now = self.bodies.at(slot)?.body.pose();
            let then = f
                .before
                .get(slot as usize)
                .copied()
                .flatten()
                .map_or(now, |s| s.pose());
            Some((then, now))
        };
        let (Some((then_a, now_a)), Some((then_b, now_b))) = (poses(a), poses(b)) else {
            return 0.0;
        };
        points
            .iter()
            .map(|p| {
                // The point in A's frame at the start, and where B's
                // material point there is in A's frame now.
                let start = then_a.inverse_transform_point(p.contact.point);
                let end = now_a.inverse_transform_point(
                    now_b.transform_point(then_b.inverse_transform_point(p.contact.point)),
                );
                let normal = then_a.rotation.inverse() * p.contact.normal;
                let moved = end - start;
                (moved - normal * normal.dot(moved)).length()
            })
            .fold(0.0, f64::max)
    }

    /// Whether bodies `a` and `b` at their current poses overlap deeper
    /// than `trigger` at one of the points below, and those points within
    /// `reach` of touching (`a` and `b` come with their poses before the
    /// step; normals from `b` to `a`): the ones deeper than `floor` that
    /// the pair's approach over the step made, or that came in from a
    /// wall's far side (their normal turned to the way they came), and all
    /// shallower ones (a shallow point's normal is the way out, whichever
    /// way it came). Where no triangle mesh takes part, every point. With
    /// `fronts`, the walks of two meshes begin at their fronts of the last
    /// step (`StepScratch::end_fronts`) and push where they ended.
    fn end_overlaps(
        &self,
        (a, before_a): (u32, Option<Pose>),
        (b, before_b): (u32, Option<Pose>),
        floor: f64,
        trigger: f64,
        reach: f64,
        mut fronts: Option<&mut Vec<(MeshPairKey, MeshPairMemory)>>,
    ) -> (bool, Vec<Contact>) {
        let (Some(ea), Some(eb)) = (self.bodies.at(a), self.bodies.at(b)) else {
            return (false, Vec::new());
        };
        let (pa, pb) = (ea.body.pose(), eb.body.pose());
        // Where a point of the pair came from: its motion on each body over
        // the step. Where a triangle mesh takes part, only overlaps that the
        // pair's approach made (B's point moved towards A along the normal)
        // are pushed back out: the normal of an overlap deeper than a thin
        // wall may point through it. Two convex shapes have no thin wall:
        // their normal is the shortest way out whichever way they came in,
        // and a corner that a spin swept down into a neighbour (the pair
        // closing along z, the shortest way out along y) must come out too:
        // a cube of the 10,000-body pile spinning at 14 rad/s as it landed
        // ended 5 cm deep in another, its points dropped here.
        let way = |before: Option<Pose>, now: &Pose, p: DVec3| {
            before.map_or(DVec3::ZERO, |then| {
                p - then.transform_point(now.inverse_transform_point(p))
            })
        };
        let through = 2.0 * ea.thickness.min(eb.thickness);
        // A point whose contact plane puts it this deep at the step's start
        // came in from the wall's far side (module docs).
        let far_side = floor + DEEP_START_MARGINS * self.settings().contact_margin;
        let mut out = Vec::new();
        for (ia, ca) in ea.colliders.iter().enumerate() {
            for (ib, cb) in eb.colliders.iter().enumerate() {
                let (wa, wb) = (pa.mul_pose(&ca.local), pb.mul_pose(&cb.local));
                let start = out.len();
                let found = match (&ca.shape, &cb.shape, fronts.as_deref_mut()) {
                    (Shape::Mesh(x), Shape::Mesh(y), Some(fronts)) => {
                        // The walk begins where this pair's last such walk
                        // ended (the same contacts, fewer box tests).
                        let key = (a, b, ia as u16, ib as u16);
                        let kept = &self.scratch.end_fronts;
                        let last = kept.binary_search_by_key(&key, |e| e.0).ok().map(|i| &kept[i].1);
                        contact_mesh_mesh_from_front(x, &wa, y, &wb, reach, last, &mut out)
                            .map(|front| fronts.push((key, front)))
                    }
                    _ => contact_shapes(&ca.shape, &wa, &cb.shape, &wb, reach, &mut out),
                };
                if found.is_err() {
                    out.truncate(start);
                    continue;
                }
                if matches!(ca.shape, Shape::Mesh(_)) || matches!(cb.shape, Shape::Mesh(_)) {
                    let mut kept = start;
                    for i in start..out.len() {
                        let mut c = out[i];
                        let came = way(before_b, &pb, c.point) - way(before_a, &pa, c.point);
                        let approach = came.dot(c.normal);
                        // Where the point was at the step's start by its
                        // contact plane: how deep.
                        let start_depth = -c.distance - approach;
                        if c.distance < -floor && -approach > floor && start_depth > far_side {
                            // Moved away from A along its normal (by more
                            // than the floor: a point sliding along a face
                            // past its edge has not), and by its plane
                            // deeper at the start than the pair began by
                            // more than a landing could make: it came in
                            // from the far side of a wall thinner than its
                            // travel. Out the way it came, by its depth,
                            // but not by more than the thinner body is
                            // thick (its depth along its normal ran through
                            // the wall; the next pass collides again).
                            c.normal = came.normalize();
                            c.distance = c.distance.max(-through);
                        } else if c.distance < -floor && approach <= 0.0 {
                            continue;
                        }
                        out[kept] = c;
                        kept += 1;
                    }
                    out.truncate(kept);
                }
            }
        }
        (out.iter().any(|c| c.distance < -trigger), out)
    }

    /// Moves the bodies of the `deep` pairs apart until none of their
    /// overlapping points is deeper than its pair's floor (to first order: a
    /// Gauss-Seidel sweep over all points of all pairs, the bodies'
    /// displacements accumulated and applied at the end), then stops each
    /// pair's approach at its deepest point.
    fn push_apart(&mut self, deep: &[Overlap], movable: &[bool]) {
        // The bodies taking part, sorted, with their displacement
        // (translation, small rotation about the centre of mass).
        let mut slots: Vec<u32> = deep.iter().flat_map(|o| [o.pair.0, o.pair.1]).collect();
        slots.sort_unstable();
        slots.dedup();
        let index = |slot: u32| slots.binary_search(&slot).expect("listed");
        let mut shift = vec![(DVec3::ZERO, DVec3::ZERO); slots.len()];
        let side = |slot: u32| -> Option<(DVec3, f64, DMat3)> {
            let e = self.bodies.at(slot)?;
            movable[slot as usize].then(|| (e.body.position(), e.body.inv_mass(), e.body.inv_inertia_world()))
        };
        let sides: Vec<Option<(DVec3, f64, DMat3)>> = slots.iter().map(|&s| side(s)).collect();
        // What a sweep needs of each point and does not change from sweep to
        // sweep (the sides' centres and inertias are the pass's): the
        // bodies' entries, the lever arms, the point's mass along its
        // normal and how deep it may stay. Found once, not once a sweep
        // (the pile of 10,000 spent 18 ms a step landing here).
        let rows: Vec<PushRow> = deep
            .iter()
            .flat_map(|o| {
                let (ia, ib) = (index(o.pair.0), index(o.pair.1));
                let sides = &sides;
                o.contacts.iter().map(move |c| {
                    // A guard holds each point where it is (or at the
                    // floor, if shallower).
                    let floor = if o.hold { o.floor.max(-c.distance) } else { o.floor };
                    let (p, n) = (c.point, c.normal);
                    let mut k = 0.0;
                    let mut r = [DVec3::ZERO; 2];
                    for (side, i) in [ia, ib].into_iter().enumerate() {
                        if let Some((center, inv_mass, inv_inertia)) = sides[i] {
                            r[side] = p - center;
                            let rn = r[side].cross(n);
                            k += inv_mass + rn.dot(inv_inertia * rn);
                        }
                    }
                    PushRow {
                        bodies: [ia, ib],
                        r,
                        n,
                        k,
                        depth: -c.distance,
                        floor,
                    }
                })
            })
            .filter(|row| row.k > 0.0 && row.k.is_finite())
            .collect();
        for _ in 0..SWEEPS {
            let mut pushed = false;
            for row in &rows {
                let mut opened = 0.0;
                for (side, sign) in [(0, 1.0), (1, -1.0)] {
                    let i = row.bodies[side];
                    if sides[i].is_some() {
                        opened += sign * (shift[i].0 + shift[i].1.cross(row.r[side])).dot(row.n);
                    }
                }
                let close = row.depth - opened - row.floor;
                if close.is_nan() || close <= 0.0 {
                    continue;
                }
                pushed = true;
                let impulse = close / row.k;
                for (side, sign) in [(0, 1.0), (1, -1.0)] {
                    let i = row.bodies[side];
                    if let Some((_, inv_mass, inv_inertia)) = sides[i] {
                        shift[i].0 += row.n * (sign * impulse * inv_mass);
                        shift[i].1 += inv_inertia * row.r[side].cross(row.n * (sign * impulse));
                    }
                }
            }
            // A sweep that pushed nothing leaves every shift as it was, and
            // so would every sweep after it.
            if !pushed {
                break;
            }
        }
        for (i, &slot) in slots.iter().enumerate() {
            if sides[i].is_none() {
                continue;
            }
            let body = &mut self.bodies.at_mut(slot).expect("live").body;
            let pose = body.pose();
            // A first-order step is no guide to a large turn: at most
            // MAX_TURN per pass (the next pass collides again).
            let angle = shift[i].1.length();
            let turn = DQuat::from_scaled_axis(shift[i].1 * (MAX_TURN / angle.max(MAX_TURN)));
            let spin = body.angular_velocity();
            body.set_pose(Pose {
                position: pose.position + shift[i].0,
                rotation: (turn * pose.rotation).normalize(),
            });
            // The angular velocity turns with the body, which keeps its
            // kinetic energy (a turned inertia with the same angular
            // momentum would change it, up or down). Finite by
            // construction; a failure leaves the momentum as it was.
            let _ = body.set_angular_velocity(turn * spin);
        }
        // Stop each pair's approach at its deepest point (plastic: no
        // bounce, no friction; removes kinetic energy, never adds it).
        for Overlap {
            pair: (a, b),
            contacts,
            hold,
            ..
        } in deep
        {
            if *hold {
                continue;
            }
            let Some(c) = contacts.iter().min_by(|x, y| x.distance.total_cmp(&y.distance)) else {
                continue;
            };
            let (ia, ib) = (index(*a), index(*b));
            // The point moved with body a (or b, if a is immovable).
            let carrier = if sides[ia].is_some() { ia } else { ib };
            let p = c.point
                + shift[carrier].0
                + shift[carrier]
                    .1
                    .cross(c.point - sides[carrier].map_or(c.point, |s| s.0));
            let n = c.normal;
            let (ea, eb) = (
                self.bodies.at(*a).expect("live"),
                self.bodies.at(*b).expect("live"),
            );
            let share = |i: usize, body: &RigidBody| {
                sides[i].map_or(0.0, |_| {
                    let rn = (p - body.position()).cross(n);
                    body.inv_mass() + rn.dot(body.inv_inertia_world() * rn)
                })
            };
            let k = share(ia, &ea.body) + share(ib, &eb.body);
            let approach = (ea.body.velocity_at_point(p) - eb.body.velocity_at_point(p)).dot(n);
            if !(approach < 0.0 && k > 0.0 && k.is_finite()) {
                continue;
            }
            let j = -approach / k;
            for (i, slot, sign) in [(ia, *a, 1.0), (ib, *b, -1.0)] {
                if sides[i].is_some() {
                    // Finite by construction; a failure leaves the momenta.
                    let _ = self
                        .bodies
                        .at_mut(slot)
                        .expect("live")
                        .body
                        .apply_impulse_at_point(n * (sign * j), p);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::{BodyDesc, WorldSettings};
    use tumble_collide::mesh::box_mesh;
    use tumble_collide::{Cuboid, MeshShape};

    /// The points `end_overlaps` would push for box B (half extent 0.25 m) swept
    /// straight down past box A's edge within a step: from 10 cm above A's
    /// top to 10 cm below it, 3 cm over A's side. The overlap is shortest
    /// to leave sideways (3 cm along y, against 10 along z), a direction
    /// the pair did not move along at all.
    fn swept_past_the_edge(shape: Shape) -> Vec<Contact> {
        let mut world = World::new(WorldSettings::default()).unwrap();
        let a = world.add_body(&BodyDesc::dynamic(shape.clone())).unwrap();
        let b = world
            .add_body(&BodyDesc::dynamic(shape).at(DVec3::new(0.0, 0.47, 0.40)))
            .unwrap();
        let before_b = Pose::from_translation(DVec3::new(0.0, 0.47, 0.60));
        let allowed = world.settings().allowed_penetration;
        let (deep, contacts) = world.end_overlaps(
            (a.index, Some(Pose::IDENTITY)),
            (b.index, Some(before_b)),
            allowed,
            (1.0 + END_OVERLAP_SLACK) * allowed,
            0.0,
            None,
        );
        // The points to push out: those deeper than the floor, if any is
        // deeper than the trigger.
        let pushed = contacts.into_iter().filter(|c| c.distance < -allowed);
        if deep {
            pushed.collect()
        } else {
            Vec::new()
        }
    }

    #[test]
    fn a_mesh_more_than_half_through_a_thin_wall_goes_back_the_way_it_came() {
        // A mesh cube (half extent 0.1 m) came straight down 21.5 cm within
        // the step onto a mesh slab 2 cm thick and ended with its bottom
        // 5 mm below the slab's underside. Where its sides cross the
        // underside, some triangle pairs' way out runs on down through the
        // slab: those points came in from the far side of a wall thinner
        // than their travel, and go back up the way they came, never on
        // down, and by no more than the slab is thick (their depth along
        // their own normal, 11 cm, ran through it).
        let mut world = World::new(WorldSettings::default()).unwrap();
        let slab = Shape::Mesh(MeshShape::new(box_mesh(DVec3::new(0.25, 0.25, 0.01)).unwrap()).unwrap());
        let cube = Shape::Mesh(MeshShape::new(box_mesh(DVec3::splat(0.1)).unwrap()).unwrap());
        let a = world.add_body(&BodyDesc::dynamic(slab)).unwrap();
        let b = world
            .add_body(&BodyDesc::dynamic(cube).at(DVec3::new(0.0, 0.0, 0.085)))
            .unwrap();
        // Straight down: the body's frame (its principal axes) then as now.
        let body_pose = |slot: u32| world.bodies.at(slot).unwrap().body.pose();
        let now_b = body_pose(b.index);
        let before_b = Pose {
            position: now_b.position + DVec3::new(0.0, 0.0, 0.215),
            ..now_b
        };
        let before_a = body_pose(a.index);
        let allowed = world.settings().allowed_penetration;
        let (deep, contacts) = world.end_overlaps(
            (a.index, Some(before_a)),
            (b.index, Some(before_b)),
            allowed,
            (1.0 + END_OVERLAP_SLACK) * allowed,
            0.0,
            Some(&mut Vec::new()),
        );
        let pushed: Vec<&Contact> = contacts.iter().filter(|c| c.distance < -allowed).collect();
        assert!(deep && !pushed.is_empty(), "no deep point: {contacts:?}");
        // Normals run from B to A, and B moves against its normal: up is
        // -z. No point where B's sides cross the slab's underside pushes B
        // down; there, the points that came in from the far side go
        // straight back up, by no more than the slab is thick. (The
        // others, kept by their own normals, show how little a triangle
        // pair's depth means this far through a wall: 11-14 cm across 2.)
        let underside = pushed.iter().filter(|c| c.point.z < -0.01 + 1e-9);
        assert!(
            underside.clone().all(|c| c.normal.z <= 0.0),
            "a point on the underside pushes B down: {pushed:?}"
        );
        let back = underside
            .filter(|c| (c.normal + DVec3::Z).length() < 1e-9 && -c.distance <= 0.02 + 1e-12)
            .count();
        assert!(back >= 2, "{back} points on the underside go back up: {pushed:?}");
    }

    #[test]
    fn convex_overlap_is_pushed_out_whichever_way_the_pair_came_in() {
        let half = DVec3::splat(0.25);
        let convex = swept_past_the_edge(Shape::Cuboid(Cuboid::new(half).unwrap()));
        let deepest = convex.iter().map(|c| c.distance).fold(0.0, f64::min);
        assert!(
            (deepest + 0.03).abs() < 1e-9,
            "deepest {deepest} m, expected the 3 cm sideways overlap"
        );
        assert!(
            convex.iter().all(|c| (c.normal + DVec3::Y).length() < 1e-9),
            "normals {:?}, expected B to A (-y)",
            convex.iter().map(|c| c.normal).collect::<Vec<_>>()
        );
        // The same boxes as closed triangle meshes: a triangle pair's normal
        // may point through a thin wall, so only points the approach made
        // are pushed, and this motion made none along -y.
        let mesh = swept_past_the_edge(Shape::Mesh(MeshShape::new(box_mesh(half).unwrap()).unwrap()));
        assert!(
            mesh.is_empty(),
            "mesh pair pushed along a normal it did not approach on: {mesh:?}"
        );
    }
}
