//! One axis of sweep-and-prune: its sorted endpoint list, where each slot's
//! two endpoints sit in it, and the pair changes its last insertion sort
//! found. The three axes share nothing they write, so an update sorts them
//! side by side (`jobs`); each axis's work is what it was in one loop.

use super::aabb::Aabb;
use super::endpoint::Endpoint;
use super::incremental::{self, SortOutcome};
use super::pairs::Changes;
use super::proxy::{EndIndex, Slot, SlotState};

/// The endpoint list of one axis and its index (see the module header).
#[derive(Debug, Clone, Default)]
pub(crate) struct AxisList {
    /// Sorted after every update: `2 * (live + removed)` endpoints.
    pub list: Vec<Endpoint>,
    /// Position of each slot's min and max endpoint in `list`.
    pub ends: Vec<EndIndex>,
    /// Scratch: candidate begins and ends of this axis's insertion sort.
    pub changes: Changes,
    /// What this axis's insertion sort did in the running update (`None`:
    /// no insertion sort, the list was sorted from scratch).
    pub outcome: Option<SortOutcome>,
}

impl AxisList {
    /// Appends slot `index`'s endpoints `[min, max]` after everything (as
    /// if the box came from +infinity; the next sort moves them in).
    pub fn append(&mut self, index: u32, min: f64, max: f64) {
        let at = self.list.len() as u32;
        self.list.push(Endpoint::new(min, index, false));
        self.list.push(Endpoint::new(max, index, true));
        if self.ends.len() <= index as usize {
            self.ends.resize(index as usize + 1, [0; 2]);
        }
        self.ends[index as usize] = [at, at + 1];
    }

    /// Writes the boxes of the live slots of `moved` (this axis's
    /// coordinates) into their endpoints, where `set_aabb` left them for
    /// the update (slots removed since are skipped).
    pub fn write_moved(&mut self, axis: usize, moved: &[u32], boxes: &[Aabb], slots: &[Slot]) {
        for &index in moved {
            if slots[index as usize].state != SlotState::Live {
                continue;
            }
            let (b, [lo, hi]) = (&boxes[index as usize], self.ends[index as usize]);
            self.list[lo as usize].value = b.min()[axis];
            self.list[hi as usize].value = b.max()[axis];
        }
    }

    /// Drops the endpoints of slots no longer live (order kept).
    pub fn purge(&mut self, slots: &[Slot]) {
        self.list
            .retain(|e| slots[e.slot() as usize].state == SlotState::Live);
        self.reindex();
    }

    /// The incremental sort of this axis (`incremental::sort_axis`) within
    /// `budget` swaps, its candidate pair changes in `changes`.
    pub fn sort_incremental(
        &mut self,
        boxes: &[Aabb],
        old_pairs: &[u64],
        pair_counts: &[u32],
        budget: u64,
    ) -> SortOutcome {
        self.changes.clear();
        let out = incremental::sort_axis(
            &mut self.list,
            boxes,
            old_pairs,
            pair_counts,
            &mut self.changes,
            budget,
        );
        if out.finished && out.swaps > 0 {
            self.reindex();
        }
        out
    }

    /// Sorts the list from scratch by the total endpoint order.
    pub fn sort_full(&mut self) {
        self.list.sort_unstable_by_key(Endpoint::sort_key);
        self.reindex();
    }

    /// Refreshes `ends` from the positions in `list`.
    fn reindex(&mut self) {
        for (pos, e) in self.list.iter().enumerate() {
            self.ends[e.slot() as usize][e.end()] = pos as u32;
        }
    }
}
