//! [`Stage::Narrow`](crate::world::Stage::Narrow): contact generation for
//! every candidate pair within its margin (the speculative margin plus a
//! bound on the pair's motion over the step), the points grouped into
//! patches and matched to the previous step's for warm starting.
//!
//! The pairs are cut into chunks that run on the world's threads; each
//! chunk reads the world and the warm-start cache only and writes its own
//! points and patches, and the chunks are joined in pair order. A pair's
//! contacts do not depend on the chunk it falls in, so the result is the
//! same bits for any thread count.
//!
//! Mesh pairs also read the tree walks they remembered last step (a list
//! of triangle pairs, or a moving pair's walk front: `StepScratch::mesh_memory`,
//! `narrow::contact_mesh_mesh_recalled`) and say what to keep; the kept list is rebuilt in pair order at the join. A
//! memory changes what a pair costs, never its contacts.

use super::frame::MeshPairKey;
use super::margins::{
    neighbour_speeds, relative_motion_bound, slot_motions, velocity_change_bounds, SlotMotion,
};
use super::StepFrame;
use crate::pool::WorkerPool;
use crate::world::manifold::{self, SearchedPair};
use crate::world::patches::{
    add_pair, ContactPoints, PairInfo, PatchExtras, PatchScratch, PatchSink, PreparedPatch, PreparedPoint,
    NO_EXTRAS,
};
use crate::world::{Collider, MaterialDesc, World};
use std::sync::Mutex;
use tumble_collide::narrow::{
    contact_at_features, contact_mesh_mesh_recalled, contact_shapes, moved_since, MeshPairMemory, Recall,
};
use tumble_collide::{Contact, Drift, Pose, Shape};

/// What the narrow stage finds of every body slot once a step, for its
/// pairs: its motion and what else a pair reads of it, bounds on how much
/// a neighbour can change its velocity and on its neighbours' speeds
/// (`margins`), and its colliders' world poses.
type StepMotion<'a, 'w> = (&'a [SlotMotion<'w>], &'a [f64], &'a [f64], &'a ColliderPoses);

/// Every collider's world pose at the step's start (its body's pose times
/// its own local pose), body slot after body slot: found once a step, not
/// once per pair (a body of a pile is in about eight).
struct ColliderPoses {
    /// Index in `poses` of each slot's first collider (one more entry at the end).
    first: Vec<u32>,
    poses: Vec<Pose>,
}

impl ColliderPoses {
    /// From the step's body slots (their poses and collider lists).
    fn of(slots: &[SlotMotion]) -> ColliderPoses {
        let mut first = Vec::with_capacity(slots.len() + 1);
        let mut poses = Vec::with_capacity(slots.len());
        for s in slots {
            first.push(poses.len() as u32);
            poses.extend(s.colliders.iter().map(|c| s.pose.mul_pose(&c.local)));
        }
        first.push(poses.len() as u32);
        ColliderPoses { first, poses }
    }

    /// Collider `index` of the body in `slot`.
    fn get(&self, slot: u32, index: usize) -> &Pose {
        &self.poses[self.first[slot as usize] as usize + index]
    }
}

/// What one chunk of candidate pairs produced.
#[derive(Default)]
struct ChunkContacts {
    points: Vec<PreparedPoint>,
    /// Patches; their `first` indexes this chunk's `points`, and their
    /// `extras` its `extras`, until joined.
    patches: Vec<PreparedPatch>,
    extras: Vec<PatchExtras>,
    warm_started: usize,
    max_penetration: f64,
    /// The first error of the chunk: (index in the step's pair list, message).
    error: Option<(usize, String)>,
    /// What each remembering mesh pair did with its memory, in pair order.
    recalls: Vec<(MeshPairKey, Recalled)>,
    /// Where each mesh collider pair was last searched, in pair order.
    searches: Vec<SearchedPair>,
    /// Mesh collider pairs that re-evaluated their kept points.
    revalidated: usize,
}

/// A mesh pair's memory after this step: the last step's (by its index in
/// the kept list), used or only held (the pair was re-evaluated at its
/// kept points), or a new one.
enum Recalled {
    Kept(usize),
    Held(usize),
    New(MeshPairMemory),
}

/// Pairs per task when the narrow phase runs on several threads: each task
/// fills one set of buffers, and a few hundred microseconds of box pairs
/// per task keep the hand-over cost small. A mesh pair costs far more, so
/// mesh scenes are cut by [`MESH_TASKS_PER_THREAD`] instead.
const PAIRS_PER_TASK: usize = 128;

/// Tasks per thread in a scene with meshes: one mesh pair can cost
/// milliseconds, so the pairs are cut into this many tasks per thread (at
/// least one pair each) and the threads balance by taking the next. Single
/// pairs as tasks cost the hand-over on each of a settled pile's 2,200
/// pairs (`profile_stages concave_pile 600 2`: 45-47 ms per step against
/// 42.7 with eight pairs per task); a chain's 20 pairs stay single.
const MESH_TASKS_PER_THREAD: usize = 16;

/// How many steps of their current motion two meshes look ahead for
/// contacts. Two, not one: a body's velocity can change within the step by
/// as much as it is (stopped by a third body, or thrown back), which the
/// velocities at the step's start do not announce; a chain's links are
/// jerked so by their neighbours. Measured over ensembles of the torus
/// chain (examples/ensemble_depth): one step's look-ahead let links sink
/// 4.6 mm (median of the runs' worst, 13.5 mm at worst), two 2.6 mm (2.7),
/// three 2.5 mm (2.7) at a fifth more time.
const LOOK_AHEAD_STEPS: f64 = 2.0;

impl World {
    pub(super) fn narrow_stage(&mut self, f: &mut StepFrame) {
        let slots = slot_motions(&self.bodies, f.n_slots, f.meshes);
        let poses = ColliderPoses::of(&slots);
        let shock = velocity_change_bounds(&slots, &f.pairs, f.meshes);
        // Only mesh pairs re-evaluate (`resting_pair`).
        let stirred = if f.meshes {
            neighbour_speeds(&slots, &f.pairs, &f.swept)
        } else {
            vec![0.0; f.n_slots]
        };
        let chunk = if f.meshes {
            (f.pairs.len() / (f.pool.threads() * MESH_TASKS_PER_THREAD)).max(1)
        } else {
            PAIRS_PER_TASK
        };
        // The frame's arrays, kept from the last step (emptied).
        let (mut runs, mut patches, mut extras) = (
            f.points.take_runs(),
            std::mem::take(&mut f.patches),
            std::mem::take(&mut f.patch_extras),
        );
        let mut memory = std::mem::take(&mut self.scratch.mesh_memory);
        // Each chunk's buffers on several threads, kept from the last step:
        // allocated afresh every step (and freed by the join, on another
        // thread than the one that filled them), they cost the pyramid 8 %
        // of its step on two threads (`profile_stages pyramid 300 2`: 1.03-1.06
        // against 0.96-0.97 ms, three interleaved runs each), as much as
        // keeping the allocator from handing memory back to the system
        // (`MALLOC_TRIM_THRESHOLD_`) gained.
        let mut spare = std::mem::take(&mut self.scratch.narrow_chunks);
        let frame: &StepFrame = f;
        let memory_read = &memory;
        // Buffers sized from the last step's contacts, in proportion to the
        // chunk's share of the pairs: no growth in a steady scene.
        let per_pair = (self.cache.len() + self.cache.len() / 4) as f64 / frame.pairs.len().max(1) as f64;
        let patches_per_pair =
            (self.patch_cache.len() + self.patch_cache.len() / 4) as f64 / frame.pairs.len().max(1) as f64;
        let run = |first: usize, pairs: &[(u32, u32)], out: &mut ChunkContacts| {
            let mut scratch = PatchScratch::default();
            let mut buffer = Vec::new();
            for (k, &pair) in pairs.iter().enumerate() {
                self.pair_contacts(
                    frame,
                    (&slots, &shock, &stirred, &poses),
                    memory_read,
                    first + k,
                    pair,
                    &mut buffer,
                    &mut scratch,
                    out,
                );
            }
        };
        let several = frame.pool.threads() > 1 && frame.pairs.len() > chunk;
        let mut chunks = if several {
            let n_chunks = frame.pairs.len().div_ceil(chunk);
            spare.resize_with(n_chunks, Default::default);
            // Each chunk's points into the run it filled last step.
            runs.resize_with(n_chunks, Vec::new);
            let buffers: Vec<Mutex<_>> = runs
                .drain(..)
                .zip(spare.drain(..))
                .map(|(points, (patches, extras))| Mutex::new((points, patches, extras)))
                .collect();
            frame.pool.map_chunks(&frame.pairs, chunk, |first, pairs| {
                let (mut points, mut patches, extras) =
                    std::mem::take(&mut *buffers[first / chunk].lock().unwrap_or_else(|e| e.into_inner()));
                points.reserve((per_pair * pairs.len() as f64) as usize + 16);
                patches.reserve((patches_per_pair * pairs.len() as f64) as usize + 16);
                let mut out = ChunkContacts {
                    points,
                    patches,
                    extras,
                    ..ChunkContacts::default()
                };
                run(first, pairs, &mut out);
                out
            })
        } else {
            // One chunk, on this thread: straight into the frame's arrays
            // (kept from the last step).
            let mut out = ChunkContacts {
                points: runs.first_mut().map(std::mem::take).unwrap_or_default(),
                patches: std::mem::take(&mut patches),
                extras: std::mem::take(&mut extras),
                ..ChunkContacts::default()
            };
            run(0, &frame.pairs, &mut out);
            vec![out]
        };

        // Join in pair order, into the kept arrays (a lone chunk is them).
        (f.patches, f.patch_extras) = (patches, extras);
        let mut warned = false;
        let mut kept = Vec::new();
        let mut searches = Vec::new();
        for chunk in &mut chunks {
            searches.append(&mut chunk.searches);
            f.report.revalidated_mesh_pairs += chunk.revalidated;
            for (key, recalled) in chunk.recalls.drain(..) {
                let memory = match recalled {
                    Recalled::Kept(i) => {
                        f.report.recalled_mesh_pairs += 1;
                        memory[i].1.take()
                    }
                    Recalled::Held(i) => memory[i].1.take(),
                    Recalled::New(m) => Some(m),
                };
                kept.push((key, memory));
            }
        }
        self.scratch.mesh_memory = kept;
        // In pair order, which is key order; sorted if ever not.
        if !searches.windows(2).all(|w| w[0].key < w[1].key) {
            searches.sort_by_key(|s| s.key);
        }
        self.searches = searches;
        for chunk in &chunks {
            if let (false, Some((k, err))) = (warned, &chunk.error) {
                let (a, b) = f.pairs[*k];
                f.report.warnings.push(format!("bodies {a} and {b}: {err}"));
                warned = true;
            }
            f.report.warm_started += chunk.warm_started;
            f.report.max_penetration = f.report.max_penetration.max(chunk.max_penetration);
        }
        if let [chunk] = &mut chunks[..] {
            if !several {
                // The lone chunk's arrays are the frame's.
                runs.clear();
                runs.push(std::mem::take(&mut chunk.points));
                std::mem::swap(&mut f.patches, &mut chunk.patches);
                std::mem::swap(&mut f.patch_extras, &mut chunk.extras);
            }
        }
        if several {
            join_chunks(&f.pool, &mut chunks, &mut f.patches, &mut f.patch_extras);
            // The chunks' points stay where they are, one run each.
            for c in chunks {
                runs.push(c.points);
                spare.push((c.patches, c.extras));
            }
        }
        self.scratch.narrow_chunks = spare;
        f.points = ContactPoints::from_runs(runs);
        f.report.contacts = f.points.len();
    }

    /// The contacts of candidate pair number `k`, body slots `(a, b)`,
    /// within the pair's margin, as points and patches appended to `out`.
    /// Reads the world and the cache only (safe to run for many pairs at once).
    #[allow(clippy::too_many_arguments)]
    fn pair_contacts(
        &self,
        f: &StepFrame,
        (slots, shock, stirred, poses): StepMotion,
        memory: &[(MeshPairKey, Option<MeshPairMemory>)],
        k: usize,
        (a, b): (u32, u32),
        buffer: &mut Vec<Contact>,
        scratch: &mut PatchScratch,
        out: &mut ChunkContacts,
    ) {
        let (sa, sb) = (&slots[a as usize], &slots[b as usize]);
        if !sa.active && !sb.active {
            return;
        }
        if !sa.dynamic && !sb.dynamic {
            return;
        }
        let now = relative_motion_bound(sa, sb, f.swept[a as usize], f.swept[b as usize]);
        let dt = f.settings.dt;
        let motion = (now + shock[a as usize] + shock[b as usize]) * dt;
        let margin = f.settings.contact_margin + motion;
        // Two meshes look ahead along B's own motion relative to A (a rigid
        // velocity field: vB + wB x (x - cB) - vA - wA x (x - cA) at x),
        // part by part, instead of by the pair's fastest point.
        let ((va, wa), (vb, wb)) = (sa.velocity(), sb.velocity());
        let (pa, pb) = (sa.pose, sb.pose);
        let drift = Drift {
            origin: pa.position,
            translation: (vb + wb.cross(pa.position - pb.position) - va) * dt * LOOK_AHEAD_STEPS,
            rotation: (wb - wa) * dt * LOOK_AHEAD_STEPS,
        };
        let mesh_margin = f.settings.mesh_contact_margin + (shock[a as usize] + shock[b as usize]) * dt;
        let ids = (
            self.bodies.id_at(a).expect("live"),
            self.bodies.id_at(b).expect("live"),
        );
        let friction = MaterialDesc::combine_friction(sa.friction, sb.friction);
        let restitution = MaterialDesc::combine_restitution(sa.restitution, sb.restitution);
        for (ia, ca) in sa.colliders.iter().enumerate() {
            for (ib, cb) in sb.colliders.iter().enumerate() {
                buffer.clear();
                let (wpa, wpb) = (*poses.get(a, ia), *poses.get(b, ib));
                let key = (a, b, ia as u16, ib as u16);
                // Struck by a neighbour within the look-ahead, either body
                // moves by about the neighbour's approach (twice, for a
                // bounce) over it: an estimate, not a bound (a blow passed
                // on through a stack is not counted); what is guaranteed
                // rests on the motion measured since the search.
                let struck = 2.0 * (stirred[a as usize] + stirred[b as usize]) * dt * LOOK_AHEAD_STEPS;
                let resting = self.resting_pair(key, (ca, &wpa), (cb, &wpb), (&drift, motion, struck), out);
                let found = if let Some(reach) = resting {
                    // Barely moved since the last search: last step's kept
                    // points, re-evaluated where the bodies are now.
                    let cached = manifold::points_of(&self.cache, key, &mut scratch.feature_cursor);
                    let m = if is_mesh(ca) && is_mesh(cb) {
                        mesh_margin + reach
                    } else {
                        margin
                    };
                    let features = cached.iter().map(|c| (c.feature_a, c.feature_b));
                    let found = contact_at_features(&ca.shape, &wpa, &cb.shape, &wpb, m, features, buffer);
                    if let Ok(i) = memory.binary_search_by_key(&key, |e| e.0) {
                        out.recalls.push((key, Recalled::Held(i)));
                    }
                    out.revalidated += 1;
                    found.map(|_| ())
                } else if let (Shape::Mesh(ma), Shape::Mesh(mb)) = (&ca.shape, &cb.shape) {
                    // The last step's walk of this pair, if it kept one.
                    let index = memory.binary_search_by_key(&key, |e| e.0).ok();
                    let remembered = index.and_then(|i| memory[i].1.as_ref());
                    contact_mesh_mesh_recalled(ma, &wpa, mb, &wpb, mesh_margin, &drift, remembered, buffer)
                        .map(|recall| match (recall, index) {
                            // Reused only when there was a memory, so it has an index.
                            (Recall::Reused, Some(i)) => out.recalls.push((key, Recalled::Kept(i))),
                            (Recall::Found(m), _) | (Recall::Walked(m), _) => {
                                out.recalls.push((key, Recalled::New(m)))
                            }
                            (Recall::Reused, None) => {}
                        })
                } else {
                    contact_shapes(&ca.shape, &wpa, &cb.shape, &wpb, margin, buffer)
                };
                if let Err(err) = found {
                    out.error.get_or_insert_with(|| (k, err.to_string()));
                    // A failed search is no search: the pair searches again.
                    if out.searches.last().is_some_and(|s| s.key == key) {
                        out.searches.pop();
                    }
                    continue;
                }
                // Meshes rest a hair apart (see WorldSettings::allowed_penetration).
                let skin = if is_mesh(ca) || is_mesh(cb) {
                    2.0 * f.settings.allowed_penetration
                } else {
                    0.0
                };
                let pair = PairInfo {
                    ids,
                    key,
                    pose_a: &pa,
                    pose_b: &pb,
                    friction,
                    restitution,
                    skin,
                    rolling: [ca.shape.rolling_radius(), cb.shape.rolling_radius()],
                    anchors: is_mesh(ca) || is_mesh(cb),
                    smooth: match (&ca.shape, &cb.shape) {
                        (Shape::Mesh(m), round)
                            if round.rolling_radius() > 0.0 && m.smooth_surface().is_some() =>
                        {
                            Some((m, wpa, true))
                        }
                        (round, Shape::Mesh(m))
                            if round.rolling_radius() > 0.0 && m.smooth_surface().is_some() =>
                        {
                            Some((m, wpb, false))
                        }
                        _ => None,
                    },
                    velocity_a: sa.velocity(),
                    velocity_b: sb.velocity(),
                    dt: f.settings.dt,
                };
                out.warm_started += add_pair(
                    buffer,
                    &pair,
                    &self.cache,
                    &self.patch_cache,
                    scratch,
                    PatchSink {
                        points: &mut out.points,
                        patches: &mut out.patches,
                        extras: &mut out.extras,
                    },
                );
                for contact in buffer.iter() {
                    out.max_penetration = out.max_penetration.max(-contact.distance);
                }
            }
        }
    }
}

/// Moves the chunks' patches, in chunk order, into `patches` (emptied
/// first), each patch's `run` made its chunk's index (its points stay in
/// the chunk's list, a run of [`ContactPoints`]) and its `extras` an index
/// of `extras` (joined the same way); the chunks keep their emptied patch
/// buffers for the next step. The chunks are copied on the pool, each into
/// its own run of the joined array: copied by one thread while the points
/// were joined too, the pile of 1,000's 1,500 patches and 3,000 points,
/// about a megabyte, took 0.3-0.4 ms of its 1.2 ms narrow phase on two
/// threads.
fn join_chunks(
    pool: &WorkerPool,
    chunks: &mut [ChunkContacts],
    patches: &mut Vec<PreparedPatch>,
    extras: &mut Vec<PatchExtras>,
) {
    let n_patches: usize = chunks.iter().map(|c| c.patches.len()).sum();
    patches.clear();
    patches.reserve(n_patches);
    {
        // Each chunk with its slots in the joined array, its index and the
        // index of its first extra there.
        let mut patch_slots = &mut patches.spare_capacity_mut()[..n_patches];
        let mut runs = Vec::with_capacity(chunks.len());
        let mut extras_offset = 0u32;
        for (index, chunk) in chunks.iter_mut().enumerate() {
            let (run_patches, rest) = std::mem::take(&mut patch_slots).split_at_mut(chunk.patches.len());
            patch_slots = rest;
            let next_extras = extras_offset + chunk.extras.len() as u32;
            runs.push((chunk, run_patches, (index as u32, extras_offset)));
            extras_offset = next_extras;
        }
        pool.for_each_mut(&mut runs, |_, (chunk, run_patches, (index, extras_offset))| {
            for (slot, mut patch) in run_patches.iter_mut().zip(chunk.patches.drain(..)) {
                patch.run = *index;
                if patch.extras != NO_EXTRAS {
                    patch.extras += *extras_offset;
                }
                slot.write(patch);
            }
        });
    }
    // SAFETY: every slot below the length was written above: the runs
    // cover them end to end, each as long as its chunk's list, which
    // `drain` yields whole.
    unsafe {
        patches.set_len(n_patches);
    }
    // The extras are few (mesh patches that stuck, round bodies on smooth
    // meshes): appended here, in the chunk order the patches' indices were
    // moved by above.
    extras.clear();
    for chunk in chunks.iter_mut() {
        extras.append(&mut chunk.extras);
    }
}

fn is_mesh(c: &Collider) -> bool {
    matches!(c.shape, Shape::Mesh(_))
}

impl World {
    /// Whether collider pair `key` (a triangle mesh against a mesh or a
    /// half-space) has moved, together with its look-ahead (`drift` for two
    /// meshes, `motion` otherwise, plus `struck`: an estimate of how far a
    /// blow from a neighbour can move it), less than
    /// `WorldSettings::resting_motion` (at most half the contact margin)
    /// since its contacts were last searched for; records in `out` where
    /// that search was (kept) or that this step searches (the poses now).
    /// Other shape pairs are always searched and not recorded. Gives the
    /// look-ahead's reach (m) of a pair that rests.
    fn resting_pair(
        &self,
        key: MeshPairKey,
        (ca, wpa): (&Collider, &Pose),
        (cb, wpb): (&Collider, &Pose),
        (drift, motion, struck): (&Drift, f64, f64),
        out: &mut ChunkContacts,
    ) -> Option<f64> {
        // One side's collider pose in the other's frame; the smaller
        // bounding sphere (own frame) of the two bounds how far its points
        // move against the other. A half-space has none: the mesh moves.
        let sphere = |shape: &Shape| {
            let bounds = shape.aabb(&Pose::IDENTITY);
            (
                (bounds.min + bounds.max) * 0.5,
                (bounds.max - bounds.min).length() * 0.5,
            )
        };
        let a_moves = match (&ca.shape, &cb.shape) {
            (Shape::Mesh(_), Shape::Mesh(_)) => sphere(&ca.shape).1 < sphere(&cb.shape).1,
            (Shape::Mesh(_), Shape::HalfSpace(_)) => true,
            (Shape::HalfSpace(_), Shape::Mesh(_)) => false,
            _ => return None,
        };
        let (rel, (center, radius), world) = if a_moves {
            (wpb.inverse().mul_pose(wpa), sphere(&ca.shape), wpa)
        } else {
            (wpa.inverse().mul_pose(wpb), sphere(&cb.shape), wpb)
        };
        // B's motion against A's is A's against B's, the same reach.
        let ahead = struck
            + if is_mesh(ca) && is_mesh(cb) {
                drift.reach(world.transform_point(center), radius)
            } else {
                motion
            };
        // At most half the pair's contact margin: a pair apart at its
        // search (nothing kept) must not come into contact unseen.
        let pair_margin = if is_mesh(ca) && is_mesh(cb) {
            self.settings.mesh_contact_margin
        } else {
            self.settings.contact_margin
        };
        let limit = self.settings.resting_motion.min(0.5 * pair_margin);
        let then = manifold::searched_at(&self.searches, key).copied();
        let held = then.filter(|then| moved_since(then, &rel, center, radius) + ahead <= limit);
        out.searches.push(SearchedPair {
            key,
            rel: held.unwrap_or(rel),
        });
        held.map(|_| ahead)
    }
}
