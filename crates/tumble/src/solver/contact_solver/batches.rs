//! The solver's passes over coloured batches, run by a team of threads
//! (`WorkerPool::team`): every thread walks the same passes and colours and
//! takes, of each contact colour, the patches of its run of bodies
//! ([`ThreadFlow`]: patches of one colour share no dynamic body, so they
//! can be updated at once), waiting before a colour only for the patches
//! of the others' that share its bodies; joints' colours and islands meet
//! at a barrier each, and the overflow batch is thread 0's alone. The work
//! of a patch never depends on which thread does it, so the result is the
//! same bits for any thread count, one thread included.

use super::body::SolverBody;
use super::coloring::{Coloring, Shared};
use super::constraint::{ManifoldConstraint, PointConstraint, SolverParams, BLOCK_POINTS};
use super::gear::GearConstraint;
use super::island_contacts::PatchArrays;
use super::joint::{begin_joint, push_joint, solve_joint, JointConstraint};
use super::joint_island::JointIsland;
use super::lanes::LANES;
use super::passes::{begin_patch, push_patch, solve_patch};
use super::solved::SolvedWriter;
use super::wide::{self, BundlePass, WideBatches, WidePatch};
use crate::pool::Team;
use std::sync::atomic::{AtomicU32, AtomicU64, AtomicUsize, Ordering};

/// Bodies per block of the per-body parts of a sub-step (velocity and
/// position updates, in blocks within each thread's run of bodies:
/// [`SolverArrays::body_blocks`]). Small enough that a pile of 200 meshes (their
/// turns by the splitting cost about 0.1 us each) is shared by two
/// threads: with 256 one thread took all of it.
pub const BODIES_PER_BLOCK: usize = 64;

/// Fewest patches (or joints) of a colour worth splitting over the team:
/// a pass over a patch costs a fraction of a microsecond, and a smaller
/// colour is not worth a second thread's cache misses.
pub const MIN_PATCHES_TO_SPLIT: usize = 32;

/// What a velocity pass ([`SolverArrays::solve`]) does besides relaxing
/// the rows, each part in the same visit as the relax.
///
/// Why: a pass reads what it works on from memory, and a sub-step passed
/// over everything four times (its start, two velocity passes, its first
/// push-out pass). A joint island's pass alone reads its joints' rows,
/// its factor, the columns of its owned points and their patches: about
/// 2 MB for the ragdoll pile's hundred islands, beyond a core's 2 MB of
/// L2 on the Intel Xeon (a ragdoll cost 0.183 ms a step among 100 and
/// 0.127 among 16 for 16 % more instructions). Begun in the first
/// velocity pass and pushed in the last, each island is visited twice a
/// sub-step and each joint and patch three times, each time working on
/// what the visit just brought into the cache, and the push-out's colours
/// need no barriers of their own. (A patch's or a joint's start stays a
/// pass of its own: begun in its colour's turn of the first velocity pass,
/// it would be relaxed before the later colours' warm starts reach the
/// bodies it shares with them, a cold start for a stack.)
///
/// The push is the same bits either way: a sub-step's first push-out pass
/// reads and writes only pseudo-velocities, the position errors and
/// separations found at the sub-step's start and the push impulses, which
/// no velocity pass reads or writes, and it keeps its own order (the
/// islands, the joints' colours, the patches' colours, the gears). The
/// islands' begin is not: the patches' warm starts now come before the
/// islands' instead of after (the same impulses, added in another order).
#[derive(Clone, Copy)]
pub(crate) struct VelocityPass<'p> {
    /// The sub-step's first velocity pass: each joint island is begun
    /// first ([`JointIsland::begin`]; `Some(warm)`: warm-started or not),
    /// for sub-steps of the pass's `h` (its joints and patches are not
    /// begun by [`SolverArrays::begin_substep`]).
    pub begin_islands: Option<bool>,
    /// The last velocity pass of a sub-step with a push-out: each island,
    /// joint and patch then makes its part of the sub-step's first push-out
    /// pass ([`SolverArrays::push_out`]'s, which is not run again) with
    /// these parameters, as pass number `pass` of `pushed`.
    pub then_push: Option<(&'p SolverParams, usize, &'p AtomicUsize)>,
}

/// The solver's arrays, shared by a team. Each pass runs over the joints'
/// colours, then the patches' colours: in each colour first its bundles of
/// four small patches (`wide`), then its larger patches.
pub(crate) struct SolverArrays<'a> {
    /// Patch rows, sorted by colour.
    pub manifolds: Shared<'a, ManifoldConstraint>,
    /// The colours' lone points in bundles of four (their records in
    /// `manifolds` and `points` keep the step start's impulses: what the
    /// step reads of them is [`SolverArrays::solved`]).
    pub ones: Shared<'a, WidePatch<1>>,
    /// The colours' two-point patches in bundles of four.
    pub twos: Shared<'a, WidePatch<2>>,
    /// The colours' three- and four-point patches in bundles of four.
    pub fours: Shared<'a, WidePatch<4>>,
    /// Which bundles and large patches make each colour.
    pub wide: &'a WideBatches,
    /// Normal rows; each patch owns its run.
    pub points: Shared<'a, PointConstraint>,
    /// Solver bodies.
    pub bodies: Shared<'a, SolverBody>,
    /// Joint rows, sorted by colour.
    pub joints: Shared<'a, JointConstraint>,
    /// Joint islands whose equality rows are solved directly.
    pub joint_islands: Shared<'a, JointIsland>,
    /// The patches' colours.
    pub coloring: &'a Coloring,
    /// The joints' colours.
    pub joint_coloring: &'a Coloring,
    /// Gears between joints (`super::gear`).
    pub gears: Shared<'a, GearConstraint>,
    /// Some gear is in no joint island's system (`GearConstraint::direct`),
    /// so the gear passes have work.
    pub loose_gears: bool,
    /// Per member of a team of more than one thread, its items of the
    /// colours in the order it runs them ([`ThreadFlow`], written by
    /// [`SolverArrays::prepare`]); one element or none on one thread.
    pub flows: Shared<'a, ThreadFlow>,
    /// Per solver body, [`SHARED`] where an item of the colours of a member
    /// other than the one whose run of bodies ([`WideBatches::body_run`])
    /// holds it touches it, so wherever the items of two members do; 0
    /// otherwise (as many as the bodies on a team of more than one thread,
    /// zeroed; empty otherwise).
    pub owners: &'a [AtomicU32],
    /// What the rest of the step reads of the records, written by
    /// [`SolverArrays::unpack`] (as long as `manifolds` and `points`).
    pub solved: SolvedWriter<'a>,
}

/// [`SolverArrays::owners`] of a body that the items of a team member
/// outside its run touch.
const SHARED: u32 = u32::MAX;

/// One team member's items of the colours, colour by colour, and in
/// each colour those that touch a body another member's items touch too
/// (its *border*) first.
///
/// Why: with a barrier after each colour, every colour waited for its
/// slowest share (the pile of 1,000 on two threads: 0.2-0.25 ms a step a
/// thread; with flows 0.07-0.15, and the step 4 % faster). A colour's items only need the earlier colours' items that
/// touch their bodies; of another member's, those are its border items.
/// So a member signals once its border of a colour is done and goes on
/// with the colour's interior, and before a colour waits only until every
/// other member has signalled the colours before it
/// ([`Team::await_peers`]), mostly long done: the members meet at a
/// barrier once a pass. Each body still sees its patches in colour order,
/// and the patches of one colour share no dynamic body, so the updates
/// are those of the colour-by-colour passes: the same bits.
#[derive(Debug, Default)]
pub(crate) struct ThreadFlow {
    /// Items, colour after colour.
    items: Vec<FlowItem>,
    /// Per colour: where its items start in `items` and where its
    /// border ends.
    colors: Vec<(u32, u32)>,
    /// The items' dynamic bodies as the fill found them, item after item
    /// in dealt order (a body may come twice), item `k`'s ending at
    /// `body_ends[k]`: what [`SolverArrays::borders_first`] reads instead of
    /// the bundles again.
    bodies: Vec<u32>,
    body_ends: Vec<u32>,
}

/// A bundle (by its array) or a large patch, as a [`ThreadFlow`] lists it.
#[derive(Debug, Clone, Copy)]
enum FlowItem {
    One(u32),
    Two(u32),
    Four(u32),
    Large(u32),
}

/// `$bundle` for a bundle item of `$arrays`, with `$w` its bundle and
/// `$kind` its array (0 ones, 1 twos, 2 fours, as `WideBatches::sources`)
/// and `$i` its index there; `$large` for a large patch, with `$i` its
/// index in `WideBatches::large`. The bundles are lane types of three
/// sizes, so one closure cannot take them all.
///
/// Unsafe to expand: `$w` is the bundle from `Shared::get_mut`, which the
/// caller must hold alone.
macro_rules! on_item {
    ($arrays:expr, $item:expr, |$w:ident, $kind:ident, $i:ident| $bundle:expr, |$j:ident| $large:expr) => {
        match $item {
            FlowItem::One(i) => {
                let ($w, $kind, $i) = ($arrays.ones.get_mut(i as usize), 0usize, i as usize);
                $bundle
            }
            FlowItem::Two(i) => {
                let ($w, $kind, $i) = ($arrays.twos.get_mut(i as usize), 1usize, i as usize);
                $bundle
            }
            FlowItem::Four(i) => {
                let ($w, $kind, $i) = ($arrays.fours.get_mut(i as usize), 2usize, i as usize);
                $bundle
            }
            FlowItem::Large(j) => {
                let $j = j as usize;
                $large
            }
        }
    };
}

/// Runs `kernel` on every item of `items`, colour by colour, this
/// thread's run of each, with a barrier after each colour.
///
/// # Safety
/// Every thread of `team` calls this with the same `coloring`, and no
/// other code touches the arrays meanwhile.
unsafe fn each<T, F>(team: &Team, coloring: &Coloring, items: &Shared<T>, kernel: F)
where
    F: Fn(&mut T),
{
    for (range, independent) in coloring.batches() {
        // An independent colour in one contiguous run per thread: patches
        // are in body order, so a thread keeps to the same bodies from
        // colour to colour (dealt round-robin in small blocks, the bodies'
        // cache lines moved between the cores at every colour, and two
        // threads solved the pile of 1,000 no faster than one).
        let block = if independent {
            team.share(range.len(), MIN_PATCHES_TO_SPLIT)
        } else if team.index() == 0 {
            0..range.len()
        } else {
            0..0
        };
        let r = range.start + block.start..range.start + block.end;
        // SAFETY: the runs of one colour are disjoint between threads.
        for item in unsafe { items.range_mut(r) } {
            kernel(item);
        }
        team.barrier();
    }
}

/// Runs `kernel` on the bundles `range`; whether it returned `true` for any.
///
/// # Safety
/// No other thread touches these bundles or their dynamic bodies meanwhile.
#[inline(always)]
unsafe fn bundles<const N: usize>(
    items: &Shared<WidePatch<N>>,
    range: std::ops::Range<usize>,
    kernel: impl Fn(&mut WidePatch<N>) -> bool,
) -> bool {
    let mut any = false;
    // SAFETY: the caller's promise.
    for w in unsafe { items.range_mut(range) } {
        any |= kernel(w);
    }
    any
}

/// Asks the cache for the narrow stage's patches of the bundle after next
/// (`two`), then for the points of the next bundle (`one`), whose patches
/// were asked for one bundle earlier: a bundle's four records are written
/// from patches and points scattered over the narrow stage's arrays (the
/// large pyramid's 10,000 a step); asked for ahead, their reads overlap.
fn prefetch_ahead(records: &impl RecordSource, one: Option<[u32; LANES]>, two: Option<[u32; LANES]>) {
    let real = |source: Option<[u32; LANES]>| source.into_iter().flatten().filter(|&k| k != wide::EMPTY);
    for k in real(two) {
        records.prefetch(k as usize);
    }
    for k in real(one) {
        records.prefetch_points(k as usize);
    }
}

/// A record and its points written afresh for each of a bundle's lanes
/// (`SolverArrays::fill_bundle`): every field a lane reads is written for
/// each patch, so the same four serve every bundle in turn.
#[derive(Default)]
struct LaneScratch([(ManifoldConstraint, [PointConstraint; BLOCK_POINTS]); LANES]);

/// Where the solver's records come from: the step writes each record and
/// its points ([`RecordSource::renew`]) on the thread that prepares it, just
/// before it is prepared ([`SolverArrays::prepare`]), or, for a bundled
/// patch that does not bounce, into a scratch record that fills its
/// bundle's lane and is not kept (`SolverArrays::fill_bundle`).
///
/// Why: written by one pass and prepared by another, each record (about a
/// kilobyte with its points) went out to memory and came back, and on two
/// threads it was often written on one core and prepared on the other.
pub(crate) trait RecordSource: Sync {
    /// The points of record `k` (colour order): its run of the point array.
    fn points(&self, k: usize) -> std::ops::Range<usize>;
    /// The restitution of record `k`'s patch (`ManifoldConstraint::restitution`).
    fn restitution(&self, k: usize) -> f64;
    /// Writes record `k` and its points (`points` is its run).
    fn renew(&self, k: usize, m: &mut ManifoldConstraint, points: &mut [PointConstraint]);
    /// Asks for what [`RecordSource::renew`] of record `k` reads first.
    fn prefetch(&self, _k: usize) {}
    /// Asks for what it reads next (after [`RecordSource::prefetch`]).
    fn prefetch_points(&self, _k: usize) {}
}

impl SolverArrays<'_> {
    /// The patch arrays, for the patches joint islands own.
    fn patch_arrays(&self) -> PatchArrays<'_, '_> {
        PatchArrays {
            manifolds: &self.manifolds,
            points: &self.points,
        }
    }

    /// The start of the solve, by the team: every patch's record written
    /// from `records` and prepared from the bodies at the step start
    /// (`constraint::prepare`; on a team that flows, each thread the
    /// patches of its [`ThreadFlow`], dealt here, and its run of the rest;
    /// else each thread its run of the patches), except a bundled patch's
    /// that does not bounce, which is only marked empty; then, on thread 0,
    /// `serial` (restitution, which reads every prepared patch with
    /// restitution and changes bodies' velocities), then the bundles filled
    /// (each thread those of its flow, or its run of each array: from the
    /// records, or from records written afresh, `fill_bundle`), and a
    /// flow's border put first.
    ///
    /// A patch in a bundle gets its rows, masses and normal block there,
    /// four lanes at a time (`WidePatch::fill`), and not in its record,
    /// unless restitution reads them (its points' masses): computed one
    /// patch at a time in the record and then copied, they took a fifth of
    /// the pile of 1,000's prepare part (0.77-0.79 ms a step that way,
    /// 0.59-0.65 in the lanes; `profile_stages pile1000 300 1`).
    ///
    /// # Safety
    /// Every thread of `team` calls this; nothing else touches the arrays.
    pub unsafe fn prepare(&self, team: &Team, records: &impl RecordSource, serial: impl FnOnce(&Self)) {
        let flowing = self.flowing(team);
        // SAFETY: the bodies are read only until the barrier; each patch owns
        // its run of points, and the threads' patches are disjoint (runs of
        // the records, or the flows, which partition the colours' records,
        // and runs of the rest).
        unsafe {
            let bodies = self.bodies.as_slice();
            // A bundled patch that does not bounce needs no record: its
            // bundle's lane is filled from a record written afresh
            // (`fill_bundle`). Its record is only marked empty, for the
            // passes that look at every record (restitution).
            let prepare = |k: usize| {
                let m = self.manifolds.get_mut(k);
                if self.wide.in_bundle[k] && records.restitution(k) == 0.0 {
                    m.leave_empty();
                    return;
                }
                let points = self.points.range_mut(records.points(k));
                records.renew(k, m, points);
                // Every record written needs its rows: a patch outside the
                // bundles is solved from them, a bouncing one's restitution
                // reads its points' masses.
                super::constraint::prepare_patch(m, points, bodies, true);
            };
            if flowing {
                // Each thread the records of the patches it will solve, so
                // that it fills its bundles from its own cache.
                let flow = self.flows.get_mut(team.index());
                self.deal(team, flow);
                for &item in &flow.items {
                    on_item!(
                        self,
                        item,
                        |_w, kind, i| {
                            let lanes = self.wide.sources[kind][i];
                            lanes
                                .iter()
                                .filter(|&&k| k != wide::EMPTY)
                                .for_each(|&k| prepare(k as usize))
                        },
                        |j| prepare(self.wide.large[j] as usize)
                    );
                }
                // The overflow batch and the joint islands' patches follow
                // the colours.
                let colored = self.coloring.colors.last().map_or(0, |r| r.end);
                let rest = team.share(self.manifolds.len() - colored, MIN_PATCHES_TO_SPLIT);
                (colored + rest.start..colored + rest.end).for_each(prepare);
            } else {
                team.share(self.manifolds.len(), MIN_PATCHES_TO_SPLIT)
                    .for_each(prepare);
            }
        }
        team.barrier();
        if team.index() == 0 {
            serial(self);
        }
        team.barrier();
        if !flowing {
            // SAFETY: the records are only read until the barrier; each
            // thread writes its own run of bundles.
            unsafe {
                let mut scratch = LaneScratch::default();
                let [ones, twos, fours] = &self.wide.sources;
                self.fill_share(team, &self.ones, ones, records, &mut scratch);
                self.fill_share(team, &self.twos, twos, records, &mut scratch);
                self.fill_share(team, &self.fours, fours, records, &mut scratch);
            }
            team.barrier();
            return;
        }
        // SAFETY: each member fills the bundles of its own flow (the flows
        // partition the bundles); the records and bodies are only read
        // until the barrier.
        unsafe {
            let flow = self.flows.get_mut(team.index());
            let mut scratch = LaneScratch::default();
            flow.bodies.clear();
            flow.body_ends.clear();
            let run = self.wide.body_run(team.index(), team.size());
            let source_of = |j: usize| match flow.items.get(j)? {
                FlowItem::One(i) => Some(self.wide.sources[0][*i as usize]),
                FlowItem::Two(i) => Some(self.wide.sources[1][*i as usize]),
                FlowItem::Four(i) => Some(self.wide.sources[2][*i as usize]),
                FlowItem::Large(_) => None,
            };
            for (j, &item) in flow.items.iter().enumerate() {
                prefetch_ahead(records, source_of(j + 1), source_of(j + 2));
                on_item!(
                    self,
                    item,
                    |w, kind, i| self.fill_bundle(w, self.wide.sources[kind][i], records, &mut scratch),
                    |_j| {}
                );
                // While the bundle is in the cache.
                self.mark_shared(&run, item, &mut flow.bodies);
                flow.body_ends.push(flow.bodies.len() as u32);
            }
        }
        team.barrier();
        // SAFETY: each member reorders its own flow; the owners are
        // complete and only read.
        unsafe { self.borders_first(self.flows.get_mut(team.index())) };
    }

    /// Fills this thread's share of the bundles of one array, `sources`
    /// their lanes' patches, asking for each bundle's records ahead.
    ///
    /// # Safety
    /// As [`SolverArrays::fill_bundle`]; the team's shares are disjoint.
    unsafe fn fill_share<const N: usize>(
        &self,
        team: &Team,
        bundles: &Shared<WidePatch<N>>,
        sources: &[[u32; LANES]],
        records: &impl RecordSource,
        scratch: &mut LaneScratch,
    ) {
        let r = team.share(bundles.len(), 1);
        let sources = &sources[r.clone()];
        // SAFETY: the caller's promise.
        for (j, w) in unsafe { bundles.range_mut(r) }.iter_mut().enumerate() {
            prefetch_ahead(records, sources.get(j + 1).copied(), sources.get(j + 2).copied());
            // SAFETY: as above.
            unsafe { self.fill_bundle(w, sources[j], records, scratch) };
        }
    }

    /// Fills bundle `w` for the patches `source`: a lane whose patch
    /// bounces from its record (prepared, and its points since written by
    /// restitution); any other from its record written afresh into
    /// `scratch` and prepared there (`RecordSource::renew`, then
    /// `constraint::prepare_patch` without rows, which the bundle computes
    /// itself), the same values that the record arrays would have held,
    /// which are left unwritten.
    ///
    /// Why: such a record was only ever read to fill its lane. Written to
    /// the arrays (about a kilobyte with its points) and read back, the
    /// large pyramid's 10,000 took 2 ms a step on one thread to write.
    ///
    /// # Safety
    /// The bundle is this thread's; the records of bouncing patches and
    /// the bodies are only read meanwhile.
    unsafe fn fill_bundle<const N: usize>(
        &self,
        w: &mut WidePatch<N>,
        source: [u32; LANES],
        records: &impl RecordSource,
        scratch: &mut LaneScratch,
    ) {
        // SAFETY: the caller's promise.
        let (manifolds, points, bodies) = unsafe {
            (
                self.manifolds.as_slice(),
                self.points.as_slice(),
                self.bodies.as_slice(),
            )
        };
        // Each lane's record: a bouncing patch's from the arrays, the
        // others written into the lane's scratch record; none in an empty lane.
        let mut lanes = scratch.0.iter_mut().zip(source).map(|((m, pts), k)| {
            if k == wide::EMPTY {
                return None;
            }
            let k = k as usize;
            if records.restitution(k) != 0.0 {
                let m = &manifolds[k];
                return Some((m, &points[m.range()]));
            }
            let pts = &mut pts[..records.points(k).len()];
            records.renew(k, m, pts);
            super::constraint::prepare_patch(m, pts, bodies, false);
            Some((&*m, &*pts))
        });
        let lane_records = std::array::from_fn(|_| lanes.next().flatten());
        w.fill(source, lane_records, bodies);
    }

    /// Whether the team runs the colours in flows ([`ThreadFlow`]): more
    /// than one thread and some colour heavy enough to split (not a small
    /// problem's levels, which run on thread 0). Then every colour flows,
    /// the light ones too: without a barrier of their own they cost a
    /// second thread nothing to share.
    fn flowing(&self, team: &Team) -> bool {
        team.size() > 1 && self.wide.split > 0
    }

    /// Writes into `flow` this thread's items, colour by colour in array
    /// order: the bundles and large patches whose key body
    /// ([`WideBatches::plan`]) is in this thread's run of bodies
    /// ([`SolverArrays::body_blocks`]), the run it integrates.
    fn deal(&self, team: &Team, flow: &mut ThreadFlow) {
        flow.items.clear();
        flow.colors.clear();
        let run = self.wide.body_run(team.index(), team.size());
        let mine = |key: u32| run.contains(&(key as usize));
        let [ones, twos, fours] = &self.wide.keys;
        for color in &self.wide.colors {
            let start = flow.items.len() as u32;
            let mut take = |range: std::ops::Range<usize>, keys: &[u32], item: fn(u32) -> FlowItem| {
                flow.items
                    .extend(range.filter(|&i| mine(keys[i])).map(|i| item(i as u32)));
            };
            take(color.ones.clone(), ones, FlowItem::One);
            take(color.twos.clone(), twos, FlowItem::Two);
            take(color.fours.clone(), fours, FlowItem::Four);
            take(color.large.clone(), &self.wide.large_keys, FlowItem::Large);
            flow.colors.push((start, start));
        }
    }

    /// This thread's blocks of [`BODIES_PER_BLOCK`] solver bodies for the
    /// per-body parts of a sub-step (velocity and position updates): where
    /// the team flows, its run of the bodies whose patches it solves
    /// ([`WideBatches::body_run`]), else [`Team::block_run`].
    pub fn body_blocks(&self, team: &Team) -> impl Iterator<Item = std::ops::Range<usize>> {
        let run = if self.flowing(team) {
            self.wide.body_run(team.index(), team.size())
        } else {
            team.block_run(self.bodies.len(), BODIES_PER_BLOCK)
        };
        Team::blocks_of(run, BODIES_PER_BLOCK)
    }

    /// The dynamic bodies of an item (a body may come twice).
    ///
    /// # Safety
    /// The item is this thread's and its bundle filled; nothing else
    /// touches the bundle, and nothing writes the records meanwhile.
    unsafe fn item_bodies(&self, item: FlowItem, mut visit: impl FnMut(u32)) {
        // SAFETY: the caller's promise; only read.
        let bodies = unsafe { self.bodies.as_slice() };
        let mut dynamic = |k: u32| {
            if bodies[k as usize].dynamic {
                visit(k);
            }
        };
        // SAFETY: as above.
        unsafe {
            on_item!(
                self,
                item,
                |w, _kind, _i| w.a.iter().chain(&w.b).for_each(|&k| dynamic(k)),
                |j| {
                    let m = self.manifolds.get(self.wide.large[j] as usize);
                    dynamic(m.a);
                    dynamic(m.b);
                }
            )
        }
    }

    /// Appends the dynamic bodies of `item` (this thread's) to `found`, and
    /// marks those outside this thread's run of bodies `run` as [`SHARED`]
    /// in [`SolverArrays::owners`].
    ///
    /// Why by the run: a body that the items of two members touch is
    /// outside the run of at least one of them, which marks it. A body
    /// whose own member's items never touch it is marked too, and its
    /// items only go to the border, which changes no bit (a colour's items
    /// share no dynamic body). Each member marking what it touched as its
    /// own or shared, an atomic compare-and-swap per body of every item,
    /// cost each of two threads 24 us of the pile of 1,000's 210 us fill.
    ///
    /// # Safety
    /// The item's bundle is filled; nothing writes it, the records or the
    /// bodies meanwhile.
    unsafe fn mark_shared(&self, run: &std::ops::Range<usize>, item: FlowItem, found: &mut Vec<u32>) {
        // SAFETY: the caller's promise.
        unsafe {
            self.item_bodies(item, |k| {
                found.push(k);
                if !run.contains(&(k as usize)) {
                    self.owners[k as usize].store(SHARED, Ordering::Relaxed);
                }
            })
        };
    }

    /// Reorders each colour of `flow` its border first (the items on a
    /// [`SHARED`] body, from the bodies the fill found:
    /// [`ThreadFlow::bodies`]), and records where each border ends. Called
    /// after [`SolverArrays::mark_owners`] on every member and a barrier.
    fn borders_first(&self, flow: &mut ThreadFlow) {
        let mut interior = Vec::new();
        for c in 0..flow.colors.len() {
            let start = flow.colors[c].0 as usize;
            let end = flow
                .colors
                .get(c + 1)
                .map_or(flow.items.len(), |next| next.0 as usize);
            interior.clear();
            let mut border = start;
            for k in start..end {
                // Items before `k` of this colour may have moved, never
                // those at `k` and after: `k`'s bodies are those found
                // for `flow.items[k]`.
                let first = if k == 0 { 0 } else { flow.body_ends[k - 1] as usize };
                let shared = flow.bodies[first..flow.body_ends[k] as usize]
                    .iter()
                    .any(|&b| self.owners[b as usize].load(Ordering::Relaxed) == SHARED);
                let item = flow.items[k];
                if shared {
                    flow.items[border] = item;
                    border += 1;
                } else {
                    interior.push(item);
                }
            }
            flow.items[border..end].copy_from_slice(&interior);
            flow.colors[c].1 = border as u32;
        }
    }

    /// The end of the solve, by the team: every record's solved parts
    /// ([`SolverArrays::solved`]) written, a bundle's patches' from its
    /// lanes, the others' from their records. On a team that flows, each
    /// colour's by the thread that solved them, from its cache, and the
    /// overflow's and the islands' in runs; else the bundles and the other
    /// records in runs.
    ///
    /// # Safety
    /// As [`SolverArrays::prepare`].
    pub unsafe fn unpack(&self, team: &Team) {
        // SAFETY: a bundle's lanes are distinct patches, each in one bundle,
        // and the threads' runs of bundles and records are disjoint; no
        // record is written any more.
        unsafe {
            let record = |k: usize| {
                let m = self.manifolds.get(k);
                self.solved.write(k, m, &self.points.as_slice()[m.range()]);
            };
            if self.flowing(team) {
                let large = |j: usize| record(self.wide.large[j] as usize);
                for &item in &self.flows.get(team.index()).items {
                    on_item!(self, item, |w, _kind, _i| w.unpack(&self.solved), |j| large(j));
                }
                // The overflow batch and the joint islands' patches follow
                // the colours (as in `prepare`).
                let colored = self.coloring.colors.last().map_or(0, |r| r.end);
                let rest = team.share(self.manifolds.len() - colored, MIN_PATCHES_TO_SPLIT);
                (colored + rest.start..colored + rest.end).for_each(record);
            } else {
                for w in self.ones.range_mut(team.share(self.ones.len(), 1)) {
                    w.unpack(&self.solved);
                }
                for w in self.twos.range_mut(team.share(self.twos.len(), 1)) {
                    w.unpack(&self.solved);
                }
                for w in self.fours.range_mut(team.share(self.fours.len(), 1)) {
                    w.unpack(&self.solved);
                }
                team.share(self.manifolds.len(), MIN_PATCHES_TO_SPLIT)
                    .filter(|&k| !self.wide.in_bundle[k])
                    .for_each(record);
            }
        }
        team.barrier();
    }

    /// Runs `kernel` on every joint island, the islands dealt over the
    /// team (they share no dynamic body), then a barrier; whether the
    /// kernel returned `true` for any of this thread's islands.
    ///
    /// # Safety
    /// As [`each`].
    unsafe fn each_island<F>(&self, team: &Team, kernel: F) -> bool
    where
        F: Fn(&mut JointIsland) -> bool,
    {
        let n = self.joint_islands.len();
        if n == 0 {
            return false;
        }
        let mut any = false;
        // Islands cost unequally (by their rows and the points they own):
        // taken as the threads are free.
        team.slices(n, |k| {
            // SAFETY: each island is taken by one thread.
            any |= kernel(unsafe { self.joint_islands.get_mut(k) });
        });
        team.barrier();
        any
    }

    /// Runs `kernel` on every patch with its points, and `pass` on every
    /// bundle: colour by colour, on a team that flows this thread's
    /// [`ThreadFlow`] and one barrier after the colours, else every
    /// colour's bundles and large patches with a barrier after each heavy
    /// colour and the light ones back to back on thread 0; then the
    /// overflow batch on thread 0. `pushed` is called once per colour by a
    /// thread for which `kernel` or `pass` returned `true` on a patch or
    /// bundle of it.
    ///
    /// Why once per colour: a shared counter raised for every bundle that
    /// pushed bounced its cache line between the cores hundreds of times a
    /// pass; the pile of 1,000's push-out passes took 0.27-0.28 ms a step on
    /// two threads so, 0.20-0.21 now, against 0.23 on one
    /// (`profile_stages pile1000 300 2`, four interleaved runs each).
    ///
    /// # Safety
    /// As [`each`].
    unsafe fn each_patch<F, P>(&self, team: &Team, kernel: F, pass: BundlePass, pushed: P)
    where
        F: Fn(&mut ManifoldConstraint, &mut [PointConstraint]) -> bool,
        P: Fn(),
    {
        let run = |k: usize| {
            // SAFETY: each patch owns its run of points, and the runs of one
            // colour are disjoint between threads (the caller's promise).
            unsafe {
                let m = self.manifolds.get_mut(k);
                kernel(m, self.points.range_mut(m.range()))
            }
        };
        let run_color = |[ones, twos, fours, large]: [std::ops::Range<usize>; 4]| {
            // SAFETY (each array): the runs of one colour are disjoint
            // between threads and share no dynamic body.
            let mut any = unsafe {
                bundles(&self.ones, ones, |w| pass.run(w, &self.bodies))
                    | bundles(&self.twos, twos, |w| pass.run(w, &self.bodies))
                    | bundles(&self.fours, fours, |w| pass.run(w, &self.bodies))
            };
            for &k in &self.wide.large[large] {
                any |= run(k as usize);
            }
            any
        };
        let flowing = self.flowing(team);
        let (heavy, light) = self.wide.colors.split_at(if flowing {
            self.wide.colors.len()
        } else {
            self.wide.split
        });
        if flowing {
            // SAFETY: each member reads its own flow, written in `prepare`.
            let flow = unsafe { self.flows.get(team.index()) };
            let run_item = |item: &FlowItem| {
                // SAFETY: as `run_color`'s, and the border items of other
                // members that touch an item's bodies are done before it
                // (`ThreadFlow`).
                unsafe {
                    on_item!(self, *item, |w, _kind, _i| pass.run(w, &self.bodies), |j| run(
                        self.wide.large[j] as usize
                    ))
                }
            };
            for (c, &(start, border)) in flow.colors.iter().enumerate() {
                let end = flow
                    .colors
                    .get(c + 1)
                    .map_or(flow.items.len(), |next| next.0 as usize);
                // The colour's interior needs nothing from the others:
                // run from it while they finish the borders before.
                let mut any = false;
                let mut interior = border as usize;
                while !team.peers_ready() {
                    if interior == end {
                        team.await_peers();
                        break;
                    }
                    any |= run_item(&flow.items[interior]);
                    interior += 1;
                }
                for item in &flow.items[start as usize..border as usize] {
                    any |= run_item(item);
                }
                team.signal();
                for item in &flow.items[interior..end] {
                    any |= run_item(item);
                }
                if any {
                    pushed();
                }
            }
            team.barrier();
        } else {
            // One thread (or no heavy colour: `flowing`).
            debug_assert!(team.size() == 1 || heavy.is_empty());
            for color in heavy {
                if run_color(color.all()) {
                    pushed();
                }
                team.barrier();
            }
        }
        // The light colours, then the overflow batch, on thread 0 in colour
        // order: the same updates in the same order as with a barrier
        // between each.
        let overflow = self.coloring.overflow.clone();
        if team.index() == 0 {
            let mut any = false;
            for color in light {
                any |= run_color(color.all());
            }
            for k in overflow.clone() {
                any |= run(k);
            }
            if any {
                pushed();
            }
        }
        if !light.is_empty() || !overflow.is_empty() {
            team.barrier();
        }
    }

    /// [`super::begin_substep`] and the joints' sub-step start, by the team.
    ///
    /// # Safety
    /// As [`each`]; patches and joints that run at once share no dynamic
    /// body (colouring).
    pub unsafe fn begin_substep(&self, team: &Team, h: f64, warm: bool) {
        // SAFETY: the caller's promise.
        unsafe {
            // Joints in an island are begun with it, in the sub-step's first
            // velocity pass (`VelocityPass`).
            each(team, self.joint_coloring, &self.joints, |j| {
                if !j.direct {
                    begin_joint(j, &self.bodies, h, warm)
                }
            });
            self.each_patch(
                team,
                |m, pts| {
                    begin_patch(m, pts, &self.bodies, warm);
                    false
                },
                BundlePass::Begin { warm },
                || {},
            );
        }
    }

    /// [`super::solve`] (and the joints) by the team, with what `visit`
    /// adds to it (islands begun, the first push-out pass).
    ///
    /// # Safety
    /// As [`SolverArrays::begin_substep`].
    pub unsafe fn solve(&self, team: &Team, h: f64, visit: VelocityPass) {
        let inv_h = 1.0 / h;
        // SAFETY: the caller's promise.
        unsafe {
            self.each_island(team, |island| {
                let patches = self.patch_arrays();
                if let Some(warm) = visit.begin_islands {
                    island.begin(&self.joints, &self.gears, &self.bodies, Some(&patches), h, warm);
                }
                island.solve(&self.joints, &self.gears, &self.bodies, Some(&patches));
                if let Some((params, pass, pushed)) = visit.then_push {
                    let owned = (&patches, params);
                    if island.push(&self.joints, &self.gears, &self.bodies, Some(owned), inv_h) {
                        pushed.fetch_max(pass, Ordering::Relaxed);
                    }
                }
                false
            });
            each(team, self.joint_coloring, &self.joints, |j| {
                if !j.direct {
                    solve_joint(j, &self.bodies);
                    if let Some((_, pass, pushed)) = visit.then_push {
                        if push_joint(j, &self.bodies, inv_h) {
                            pushed.fetch_max(pass, Ordering::Relaxed);
                        }
                    }
                }
            });
            match visit.then_push {
                None => self.each_patch(
                    team,
                    |m, pts| {
                        solve_patch(m, pts, &self.bodies, inv_h);
                        false
                    },
                    BundlePass::Solve { inv_h },
                    || {},
                ),
                // The sub-step's first push-out pass: it holds the anchors.
                Some((params, pass, pushed)) => self.each_patch(
                    team,
                    |m, pts| {
                        solve_patch(m, pts, &self.bodies, inv_h);
                        push_patch(m, pts, &self.bodies, params, inv_h, true)
                    },
                    BundlePass::SolveThenPush { params, inv_h },
                    || {
                        pushed.fetch_max(pass, Ordering::Relaxed);
                    },
                ),
            }
        }
    }

    /// [`super::push_out`] (and the joints) by the team, as its pass number
    /// `pass` (from 1, counted over the step), the sub-step's `first` or a
    /// later one: a thread whose patches or joints pushed raises `pushed`
    /// to `pass`. After the call every thread sees whether any pushed
    /// (`pushed == pass`). The step makes a sub-step's first pass with its
    /// last velocity pass (`VelocityPass::then_push`) and this one for the
    /// others; `first` (the anchors held) is for a first pass made alone.
    ///
    /// # Safety
    /// As [`SolverArrays::begin_substep`].
    pub unsafe fn push_out(
        &self,
        team: &Team,
        params: &SolverParams,
        h: f64,
        pass: usize,
        first: bool,
        pushed: &AtomicUsize,
    ) {
        let inv_h = 1.0 / h;
        // SAFETY: the caller's promise.
        unsafe {
            let owned = (&self.patch_arrays(), params);
            if self.each_island(team, |island| {
                island.push(&self.joints, &self.gears, &self.bodies, Some(owned), inv_h)
            }) {
                pushed.fetch_max(pass, Ordering::Relaxed);
            }
            each(team, self.joint_coloring, &self.joints, |j| {
                if !j.direct && push_joint(j, &self.bodies, inv_h) {
                    pushed.fetch_max(pass, Ordering::Relaxed);
                }
            });
            self.each_patch(
                team,
                |m, pts| push_patch(m, pts, &self.bodies, params, inv_h, first),
                BundlePass::Push {
                    params,
                    inv_h,
                    hold: first,
                },
                || {
                    pushed.fetch_max(pass, Ordering::Relaxed);
                },
            );
        }
    }

    /// The gears' part of a pass (`super::gear`): thread 0 runs `pass` over
    /// the gears (which skips those in an island's system), in order, while
    /// the others wait at the barriers around it (a gear's four bodies fit
    /// no colour). Nothing, and no barrier, when every gear is in an
    /// island's system.
    ///
    /// # Safety
    /// Every thread of `team` calls this after the same pass.
    pub unsafe fn gear_pass(&self, team: &Team, pass: impl FnOnce(&mut [GearConstraint])) {
        if !self.loose_gears {
            return;
        }
        team.barrier();
        if team.index() == 0 {
            // SAFETY: the other threads wait at the barrier meanwhile.
            pass(unsafe { self.gears.range_mut(0..self.gears.len()) });
        }
        team.barrier();
    }

    /// The largest violation of the non-penetration rows by the current
    /// velocities (m/s), over every patch (`super::residual`), by the team:
    /// each thread takes its share of the bundles and large patches (thread
    /// 0 the overflow batch too), and the largest is met in `largest` (f64
    /// bits of a positive number or zero: their order is the numbers'
    /// order, so the maximum does not depend on which thread got there
    /// first). Every thread returns the whole maximum.
    ///
    /// # Safety
    /// Every thread of `team` calls this; nothing writes the arrays meanwhile.
    pub unsafe fn residual(&self, team: &Team, h: f64, largest: &AtomicU64) -> f64 {
        // SAFETY: the caller's promise: the arrays are only read.
        let (manifolds, points, bodies, ones, twos, fours) = unsafe {
            (
                self.manifolds.as_slice(),
                self.points.as_slice(),
                self.bodies.as_slice(),
                self.ones.as_slice(),
                self.twos.as_slice(),
                self.fours.as_slice(),
            )
        };
        let inv_h = 1.0 / h;
        let part = |n: usize| team.share(n, MIN_PATCHES_TO_SPLIT);
        let bundled = ones[part(ones.len())]
            .iter()
            .map(|w| wide::residual(w, bodies, inv_h));
        let bundled = bundled.chain(
            twos[part(twos.len())]
                .iter()
                .map(|w| wide::residual(w, bodies, inv_h)),
        );
        let bundled = bundled.chain(
            fours[part(fours.len())]
                .iter()
                .map(|w| wide::residual(w, bodies, inv_h)),
        );
        let bundled = bundled.fold(0.0f64, f64::max);
        let loose = |k: u32| {
            let m = &manifolds[k as usize];
            super::residual(std::slice::from_ref(m), points, bodies, h)
        };
        let large = &self.wide.large[part(self.wide.large.len())];
        let mut mine = bundled.max(large.iter().map(|&k| loose(k)).fold(0.0f64, f64::max));
        if team.index() == 0 {
            let overflow = self.coloring.overflow.clone().map(|k| loose(k as u32));
            mine = mine.max(overflow.fold(0.0f64, f64::max));
        }
        // Zero for -0.0 (whose bits would outrank every positive number),
        // and for no violation at all.
        let bits = if mine > 0.0 { mine.to_bits() } else { 0 };
        largest.fetch_max(bits, Ordering::Relaxed);
        team.barrier();
        f64::from_bits(largest.load(Ordering::Relaxed))
    }
}
