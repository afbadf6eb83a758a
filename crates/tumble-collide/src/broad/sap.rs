//! The sweep-and-prune broad phase object: proxies in, sorted pair events out.
//! See the [module documentation](super) for the algorithm and its two modes.

use super::aabb::Aabb;
use super::axis::AxisList;
use super::endpoint::MAX_SLOTS;
use super::error::BroadPhaseError;
use super::incremental::SortOutcome;
use super::jobs::{BroadJobs, InOrder};
use super::pairs::{merge_set, replace_set, split_key, Changes, PairEvent};
use super::proxy::{ProxyId, Slot, SlotState};
use super::rebuild::{self, SweepPart};

/// Default of [`SweepAndPrune::with_swap_budget_factor`].
pub const DEFAULT_SWAP_BUDGET_FACTOR: u32 = 1;

/// Swaps always allowed, so that tiny scenes never rebuild for nothing.
const MIN_SWAP_BUDGET: u64 = 64;

/// Fewest endpoints in a part of a rebuild's sweep that runs on its own.
const SWEEP_PART_ENDPOINTS: usize = 4096;

/// What one [`SweepAndPrune::update`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct UpdateReport {
    /// Swaps predicted before sorting from the motion since the last update
    /// (see the module documentation); above the budget the update rebuilds
    /// without trying the insertion sort.
    pub estimated_swaps: u64,
    /// Endpoint swaps done by the insertion sorts (including the ones of an
    /// attempt that ran out of budget on some axis).
    pub swaps: u64,
    /// `true` when the lists were re-sorted and the pairs found by a sweep
    /// (first build, large batch of insertions, swap budget exceeded, or
    /// soon after an update whose insertion sorts exceeded it).
    pub rebuilt: bool,
    /// Number of [`PairEvent::Begin`] events emitted.
    pub begins: usize,
    /// Number of [`PairEvent::End`] events emitted.
    pub ends: usize,
    /// Overlapping pairs after the update.
    pub pairs: usize,
}

/// Incremental sweep-and-prune over axis-aligned boxes with a persistent set of
/// overlapping pairs (thesis 4.7 and 5.3; Baraff 1992; Cohen et al. 1995).
#[derive(Debug, Clone)]
pub struct SweepAndPrune {
    /// One record per slot ever used (live, removed or free).
    slots: Vec<Slot>,
    /// The box in the endpoint lists per slot (from the next update on for
    /// the slots of `moved`): the box last set, or with an enlargement the
    /// enlarged box that holds it.
    boxes: Vec<Aabb>,
    /// The box last set per slot (see [`SweepAndPrune::with_enlargement`]).
    exact: Vec<Aabb>,
    /// How much a box set is enlarged by in the lists, as a fraction of its
    /// largest side (0: not enlarged).
    enlargement: f64,
    /// Slots whose box `set_aabb` changed since the last update.
    moved: Vec<u32>,
    /// The endpoint lists of x, y, z and each slot's positions in them.
    axes: [AxisList; 3],
    /// Slots ready for reuse.
    free: Vec<u32>,
    /// Slots removed since the last update.
    removed: Vec<u32>,
    /// Proxies inserted since the last update.
    inserted: usize,
    /// Sum over `set_aabb` calls since the last update of the centre displacement
    /// per axis divided by the extent of the scene on that axis.
    travel: f64,
    /// `1 / extent` of the scene per axis at the last update (0 if flat).
    inv_extent: [f64; 3],
    /// Live proxies.
    live: usize,
    /// Overlapping pairs of the lists' boxes as of the last update: sorted,
    /// unique pair keys.
    pairs: Vec<u64>,
    /// With an enlargement: those of `pairs` whose boxes as set overlap,
    /// the pairs reported (empty and unused without one).
    exact_pairs: Vec<u64>,
    /// Number of pairs of each slot as of the last update, plus pairs of removed
    /// partners not yet purged (an upper bound used to skip membership searches).
    pair_counts: Vec<u32>,
    /// Scratch: begins and ends of the running update.
    changes: Changes,
    /// Scratch: the next pair set.
    next_pairs: Vec<u64>,
    /// Scratch: the parts of the rebuild sweep.
    sweeps: Vec<SweepPart>,
    /// Box tests done by the last rebuild sweep, a measure of what a rebuild costs.
    last_sweep_tests: u64,
    /// Updates in a row whose insertion sorts ran out of budget.
    aborts_in_a_row: u32,
    /// Updates left that rebuild without trying the insertion sorts.
    rebuilds_ahead: u32,
    swap_budget_factor: u32,
}

impl Default for SweepAndPrune {
    fn default() -> Self {
        Self::new()
    }
}

impl SweepAndPrune {
    /// An empty broad phase with the default swap budget.
    pub fn new() -> SweepAndPrune {
        Self::with_swap_budget_factor(DEFAULT_SWAP_BUDGET_FACTOR)
    }

    /// An empty broad phase whose updates fall back to a full rebuild once the
    /// insertion sorts exceed `factor * (n * ceil(log2(n + 2)) + t / 8) + 64` swaps
    /// in total, with `n` live proxies and `t` the box tests done by the last
    /// rebuild sweep: about what a rebuild (full sorts + sweep) would cost, as a
    /// swap costs several times a sweep box test (measured). Raising the
    /// factor keeps the incremental path longer under incoherent motion; `0`
    /// rebuilds on almost any large motion. Default [`DEFAULT_SWAP_BUDGET_FACTOR`].
    pub fn with_swap_budget_factor(factor: u32) -> SweepAndPrune {
        SweepAndPrune {
            slots: Vec::new(),
            boxes: Vec::new(),
            exact: Vec::new(),
            enlargement: 0.0,
            moved: Vec::new(),
            axes: Default::default(),
            free: Vec::new(),
            removed: Vec::new(),
            inserted: 0,
            travel: 0.0,
            inv_extent: [0.0; 3],
            live: 0,
            pairs: Vec::new(),
            exact_pairs: Vec::new(),
            pair_counts: Vec::new(),
            changes: Changes::default(),
            next_pairs: Vec::new(),
            sweeps: Vec::new(),
            last_sweep_tests: 0,
            aborts_in_a_row: 0,
            rebuilds_ahead: 0,
            swap_budget_factor: factor,
        }
    }

    /// This broad phase with its boxes enlarged in the endpoint lists by
    /// `fraction` of each box's largest side on every side (clamped to
    /// `[0, 1]`; a non-finite fraction counts as 0), the fat boxes of Bullet's
    /// and Box2D's broad phases. A box set within its enlarged box leaves
    /// the lists alone, so bodies that rest or jitter cost no sorting (a
    /// stack's layers, whose equal values any jitter reorders, otherwise
    /// make the insertion sorts fail and rebuild every update). The pairs
    /// and events reported are still those of the boxes as set: the lists'
    /// pairs, a superset, are filtered by them at every update.
    ///
    /// On a broad phase that holds boxes already, every box is listed
    /// again and the next update rebuilds; its events are the changes
    /// from the pairs reported before (none for boxes that did not move).
    pub fn with_enlargement(mut self, fraction: f64) -> SweepAndPrune {
        let fraction = if fraction.is_finite() {
            fraction.clamp(0.0, 1.0)
        } else {
            0.0
        };
        if fraction == self.enlargement {
            return self;
        }
        let reported = self.reported().to_vec();
        self.enlargement = fraction;
        for index in 0..self.slots.len() {
            if self.slots[index].state != SlotState::Live {
                continue;
            }
            self.boxes[index] = self.listed(self.exact[index]);
            if !self.slots[index].moved {
                self.slots[index].moved = true;
                self.moved.push(index as u32);
            }
        }
        // The old pairs the rebuild's changes are found from: those
        // reported so far (the per-slot counts stay an upper bound).
        self.rebuilds_ahead = self.rebuilds_ahead.max(1);
        self.pairs.clone_from(&reported);
        self.exact_pairs = reported;
        self
    }

    /// The box that goes into the lists for `aabb` set.
    fn listed(&self, aabb: Aabb) -> Aabb {
        if self.enlargement == 0.0 {
            return aabb;
        }
        let side = aabb.size().max_element();
        // A box too large to grow in f64 goes in as it is.
        aabb.inflate(self.enlargement * side).unwrap_or(aabb)
    }

    /// The pair keys reported: the lists' pairs, or with an enlargement the
    /// pairs of the boxes as set.
    fn reported(&self) -> &[u64] {
        if self.enlargement == 0.0 {
            &self.pairs
        } else {
            &self.exact_pairs
        }
    }

    /// Number of live (inserted and not removed) proxies.
    pub fn len(&self) -> usize {
        self.live
    }

    /// `true` when no proxy is live.
    pub fn is_empty(&self) -> bool {
        self.live == 0
    }

    /// The swap budget of the next update (see [`Self::with_swap_budget_factor`]).
    pub fn swap_budget(&self) -> u64 {
        let n = self.live as u64;
        let log2 = u64::from(64 - (n + 1).leading_zeros());
        u64::from(self.swap_budget_factor)
            .saturating_mul(n.saturating_mul(log2).saturating_add(self.last_sweep_tests / 8))
            .saturating_add(MIN_SWAP_BUDGET)
    }

    /// Adds a box tagged with the caller's `user_id` (not required to be unique).
    /// Its pairs appear at the next [`Self::update`].
    pub fn insert(&mut self, user_id: u32, aabb: Aabb) -> Result<ProxyId, BroadPhaseError> {
        let index = match self.free.pop() {
            Some(index) => {
                let slot = &mut self.slots[index as usize];
                slot.generation = slot.generation.wrapping_add(1);
                index
            }
            None => {
                if self.slots.len() >= MAX_SLOTS as usize {
                    return Err(BroadPhaseError::TooManyProxies { max: MAX_SLOTS });
                }
                self.boxes.push(aabb);
                self.exact.push(aabb);
                self.slots.push(Slot {
                    user_id,
                    generation: 0,
                    state: SlotState::Free,
                    moved: false,
                });
                self.pair_counts.push(0);
                (self.slots.len() - 1) as u32
            }
        };
        let listed = self.listed(aabb);
        self.boxes[index as usize] = listed;
        self.exact[index as usize] = aabb;
        let slot = &mut self.slots[index as usize];
        slot.user_id = user_id;
        slot.state = SlotState::Live;
        // Appended after everything: as if the box had been at +infinity, separated
        // from all others, so the old pair set (without it) matches the list order.
        for (axis, a) in self.axes.iter_mut().enumerate() {
            a.append(index, listed.min()[axis], listed.max()[axis]);
        }
        self.inserted += 1;
        self.live += 1;
        Ok(ProxyId::new(index, slot.generation))
    }

    /// Removes a proxy; its pairs end at the next [`Self::update`]. Removing twice,
    /// or an id from another broad phase, is an error.
    pub fn remove(&mut self, id: ProxyId) -> Result<(), BroadPhaseError> {
        let index = self.check_live(id)?;
        self.slots[index].state = SlotState::Removed;
        self.removed.push(index as u32);
        self.live -= 1;
        Ok(())
    }

    /// Moves or resizes a proxy's box; takes effect at the next [`Self::update`].
    pub fn set_aabb(&mut self, id: ProxyId, aabb: Aabb) -> Result<(), BroadPhaseError> {
        let index = self.check_live(id)?;
        self.exact[index] = aabb;
        let listed = self.listed(aabb);
        let held = &self.boxes[index];
        // Within its enlarged box, and that box not more than twice the
        // size it would be given now (a body that fell fast and stopped
        // would otherwise keep the long box of its fall): the lists stay.
        if self.enlargement > 0.0 && held.contains(&aabb) && !held.size().cmpgt(2.0 * listed.size()).any() {
            return Ok(());
        }
        let moved = (listed.center() - self.boxes[index].center()).abs();
        self.travel +=
            moved.x * self.inv_extent[0] + moved.y * self.inv_extent[1] + moved.z * self.inv_extent[2];
        self.boxes[index] = listed;
        // Written into the axes' lists by the update, each axis on its own.
        if !self.slots[index].moved {
            self.slots[index].moved = true;
            self.moved.push(index as u32);
        }
        Ok(())
    }

    /// The box last set of a live proxy.
    pub fn aabb(&self, id: ProxyId) -> Result<Aabb, BroadPhaseError> {
        Ok(self.exact[self.check_live(id)?])
    }

    /// The `user_id` given at insertion.
    pub fn user_id(&self, id: ProxyId) -> Result<u32, BroadPhaseError> {
        Ok(self.slots[self.check_live(id)?].user_id)
    }

    /// `true` when `id` names a live proxy.
    pub fn contains(&self, id: ProxyId) -> bool {
        self.check_live(id).is_ok()
    }

    /// Overlapping pairs as of the last update, sorted, each as (smaller id,
    /// larger id). Touching boxes count as overlapping.
    pub fn pairs(&self) -> impl ExactSizeIterator<Item = (ProxyId, ProxyId)> + '_ {
        self.reported().iter().map(move |&key| self.ids(key))
    }

    /// The overlapping pairs as of the last update by the `user_id`s of
    /// their proxies, each as (smaller, larger), appended to `out` in the
    /// order of [`Self::pairs`] (sorted when user ids grow with slots, as a
    /// world's body slots do).
    pub fn user_pairs(&self, out: &mut Vec<(u32, u32)>) {
        let pairs = self.reported();
        out.reserve(pairs.len());
        out.extend(pairs.iter().map(|&key| {
            let (a, b) = split_key(key);
            let (a, b) = (self.slots[a as usize].user_id, self.slots[b as usize].user_id);
            if a < b {
                (a, b)
            } else {
                (b, a)
            }
        }));
    }

    /// Number of overlapping pairs as of the last update.
    pub fn pair_count(&self) -> usize {
        self.reported().len()
    }

    /// Applies the insertions, removals and box changes made since the last call,
    /// and replaces the contents of `events` with the changes of the pair set,
    /// sorted by pair (each pair at most once).
    pub fn update(&mut self, events: &mut Vec<PairEvent>) -> UpdateReport {
        self.update_on(events, &InOrder)
    }

    /// [`Self::update`] with its independent jobs (each axis's sort, the parts
    /// of a rebuild's sweep) run by `jobs`, side by side if it has threads:
    /// the same pairs and events, in the same order, however they are run.
    ///
    /// Each axis's insertion sort has the whole swap budget to itself, and
    /// the update rebuilds if any axis runs out of it.
    pub fn update_on<J: BroadJobs>(&mut self, events: &mut Vec<PairEvent>, jobs: &J) -> UpdateReport {
        events.clear();
        self.changes.clear();
        if !self.removed.is_empty() {
            self.purge_removed(jobs);
        }
        let purged = self.changes.ends.len();
        let budget = self.swap_budget();
        let estimate = self.estimated_swaps();
        // After insertion sorts that ran out of budget, the next updates
        // rebuild at once, 1, 3, 7 then 15 of them while the sorts keep
        // failing: the prediction assumes evenly spread endpoints, and a
        // stack's layers (many equal values, reordered by any jitter) break
        // that every step, where each failed attempt costs a rebuild's work.
        // Nothing moved, came or went (boxes that rest within their enlarged
        // boxes): the lists and the pairs stay as they are.
        let still = self.moved.is_empty() && self.inserted == 0 && self.removed.is_empty();
        let batch = !still && (estimate > budget as f64 || self.rebuilds_ahead > 0);
        self.rebuilds_ahead = self.rebuilds_ahead.saturating_sub(1);
        if still {
            for a in &mut self.axes {
                a.changes.clear();
                a.outcome = Some(SortOutcome {
                    swaps: 0,
                    finished: true,
                });
            }
        }
        let (boxes, slots, moved) = (&self.boxes, &self.slots, &self.moved);
        let (old_pairs, pair_counts) = (&self.pairs, &self.pair_counts);
        jobs.each(if still { &mut [] } else { &mut self.axes[..] }, |axis, a| {
            a.write_moved(axis, moved, boxes, slots);
            a.outcome = if batch {
                a.sort_full();
                None
            } else {
                Some(a.sort_incremental(boxes, old_pairs, pair_counts, budget))
            };
        });
        for &index in &self.moved {
            self.slots[index as usize].moved = false;
        }
        self.moved.clear();
        let outcomes = self.axes.each_ref().map(|a| a.outcome);
        let swaps = outcomes.iter().flatten().map(|o| o.swaps).sum();
        let aborted = outcomes.iter().flatten().any(|o| !o.finished);
        if aborted {
            self.aborts_in_a_row = (self.aborts_in_a_row + 1).min(4);
            self.rebuilds_ahead = (1 << self.aborts_in_a_row) - 1;
        } else if !batch {
            self.aborts_in_a_row = 0;
        }
        let rebuilt = batch || aborted;
        if rebuilt {
            // Drop what an aborted insertion sort found; keep removal ends.
            self.changes.begins.clear();
            self.changes.ends.truncate(purged);
            self.rebuild(jobs, !batch);
            self.changes.normalize();
        } else {
            for a in &self.axes {
                self.changes.begins.extend_from_slice(&a.changes.begins);
                self.changes.ends.extend_from_slice(&a.changes.ends);
            }
            self.changes.normalize();
            if !self.changes.begins.is_empty() || !self.changes.ends.is_empty() {
                merge_set(
                    &self.pairs,
                    &self.changes.ends,
                    &self.changes.begins,
                    &mut self.next_pairs,
                );
                std::mem::swap(&mut self.pairs, &mut self.next_pairs);
            }
        }
        self.count_changes();
        if self.enlargement > 0.0 {
            self.filter_exact();
        }
        self.emit(events);
        for index in self.removed.drain(..) {
            self.slots[index as usize].state = SlotState::Free;
            self.free.push(index);
        }
        self.inserted = 0;
        self.travel = 0.0;
        for (axis, a) in self.axes.iter().enumerate() {
            let extent = match (a.list.first(), a.list.last()) {
                (Some(lo), Some(hi)) => hi.value - lo.value,
                _ => 0.0,
            };
            self.inv_extent[axis] = if extent > 0.0 { 1.0 / extent } else { 0.0 };
        }
        UpdateReport {
            estimated_swaps: estimate.min(u64::MAX as f64) as u64,
            swaps,
            rebuilt,
            begins: self.changes.begins.len(),
            ends: self.changes.ends.len(),
            pairs: self.reported().len(),
        }
    }

    /// With an enlargement: the lists' pairs whose boxes as set overlap
    /// become the reported pairs, and the update's changes become theirs
    /// (what [`Self::emit`] reports; the lists' own changes have already
    /// gone into `pair_counts`).
    fn filter_exact(&mut self) {
        let exact = &self.exact;
        // Each key written and kept by advancing past it or not: the test
        // fails for about a third of the pairs, unpredictably, and a branch
        // on it cost more than the test.
        self.next_pairs.resize(self.pairs.len(), 0);
        let mut kept = 0;
        for &key in &self.pairs {
            let (a, b) = split_key(key);
            self.next_pairs[kept] = key;
            kept += usize::from(exact[a as usize].overlaps_branchless(&exact[b as usize]));
        }
        self.next_pairs.truncate(kept);
        self.changes.clear();
        replace_set(&mut self.exact_pairs, &mut self.next_pairs, &mut self.changes);
    }

    /// Swaps the insertion sorts are expected to need, predicted before sorting.
    ///
    /// An endpoint moving by `d` on an axis of extent `L` with `2n` endpoints
    /// spread over it passes about `2n d / L` others; with two endpoints per box
    /// and each swap shared by two movers this is `2n` times the summed relative
    /// displacement `travel`. A new proxy comes from the end of the lists and
    /// passes about `n` endpoints. The prediction assumes an even spread; when it
    /// is wrong the swap budget still stops the sort.
    fn estimated_swaps(&self) -> f64 {
        let n = self.live as f64;
        2.0 * n * self.travel + self.inserted as f64 * n
    }

    /// Index of the live slot named by `id`.
    fn check_live(&self, id: ProxyId) -> Result<usize, BroadPhaseError> {
        let index = id.index() as usize;
        match self.slots.get(index) {
            Some(slot) if slot.generation == id.generation() => match slot.state {
                SlotState::Live => Ok(index),
                SlotState::Removed | SlotState::Free => Err(BroadPhaseError::AlreadyRemoved(id)),
            },
            _ => Err(BroadPhaseError::UnknownProxy(id)),
        }
    }

    /// The ids of a pair key (slots still hold the generations of its proxies:
    /// removed slots are released only at the end of the update).
    fn ids(&self, key: u64) -> (ProxyId, ProxyId) {
        let (a, b) = split_key(key);
        (
            ProxyId::new(a, self.slots[a as usize].generation),
            ProxyId::new(b, self.slots[b as usize].generation),
        )
    }

    /// Drops the endpoints of removed proxies (O(n) per list, order kept) and
    /// ends their pairs.
    fn purge_removed<J: BroadJobs>(&mut self, jobs: &J) {
        let slots = &self.slots;
        jobs.each(&mut self.axes, |_, a| a.purge(slots));
        let ends = &mut self.changes.ends;
        self.pairs.retain(|&key| {
            let (a, b) = split_key(key);
            let keep =
                slots[a as usize].state == SlotState::Live && slots[b as usize].state == SlotState::Live;
            if !keep {
                ends.push(key);
            }
            keep
        });
    }

    /// Full sort of the three lists (unless `sort` is false: already
    /// sorted) and a sweep along a single axis, in parts that each start
    /// where the last ends (`SweepPart::sweep`); the events are the
    /// difference between the old and the new pair set.
    fn rebuild<J: BroadJobs>(&mut self, jobs: &J, sort: bool) {
        if sort {
            jobs.each(&mut self.axes, |_, a| a.sort_full());
        }
        let axis = rebuild::widest_axis(&self.axes[0].list, &self.boxes);
        let (list, boxes) = (&self.axes[axis].list, &self.boxes);
        // Parts of at least `SWEEP_PART_ENDPOINTS` endpoints: a part's start
        // replays the endpoints before it (no box tests, but not free).
        let parts = jobs.width().min(list.len() / SWEEP_PART_ENDPOINTS).max(1);
        self.sweeps.resize_with(parts, SweepPart::default);
        let cuts = |k: usize| k * list.len() / parts;
        jobs.each(&mut self.sweeps[..parts], |k, part| {
            part.sweep(list, axis, boxes, cuts(k)..cuts(k + 1));
        });
        self.next_pairs.clear();
        self.last_sweep_tests = 0;
        for part in &self.sweeps[..parts] {
            self.next_pairs.extend_from_slice(&part.pairs);
            self.last_sweep_tests += part.tests;
        }
        self.next_pairs.sort_unstable();
        replace_set(&mut self.pairs, &mut self.next_pairs, &mut self.changes);
    }

    /// Applies the begins and ends of this update to the per-slot pair counts.
    fn count_changes(&mut self) {
        for &key in &self.changes.begins {
            let (a, b) = split_key(key);
            self.pair_counts[a as usize] += 1;
            self.pair_counts[b as usize] += 1;
        }
        for &key in &self.changes.ends {
            let (a, b) = split_key(key);
            self.pair_counts[a as usize] -= 1;
            self.pair_counts[b as usize] -= 1;
        }
    }

    /// Writes the sorted begins and ends as events, in pair order.
    fn emit(&self, events: &mut Vec<PairEvent>) {
        let (begins, ends) = (&self.changes.begins, &self.changes.ends);
        let (mut i, mut j) = (0, 0);
        while i < begins.len() || j < ends.len() {
            if j == ends.len() || (i < begins.len() && begins[i] < ends[j]) {
                let (a, b) = self.ids(begins[i]);
                events.push(PairEvent::Begin(a, b));
                i += 1;
            } else {
                let (a, b) = self.ids(ends[j]);
                events.push(PairEvent::End(a, b));
                j += 1;
            }
        }
    }
}
