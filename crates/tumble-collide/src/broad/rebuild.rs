//! Full rebuild: sort the three endpoint lists from scratch and find every
//! overlapping pair by one sweep along a single axis (thesis 4.7, figure 4.2:
//! the "active list" sweep). Used for the first build, for large batches of
//! insertions, and when incoherent motion (teleports) would make the insertion
//! sort quadratic. O(n log n + n * a + k) with `a` the mean active-list length on
//! the sweep axis, which is chosen as the axis of largest spread of box centres
//! to keep `a` small. The active list is tested four boxes to a SIMD compare
//! (the `wide` crate): a branch per box test mispredicted about as often as
//! not, and the sweep of the 10,000-body pile took 5.5-7 ms a step where it
//! now takes 1.8-2.2 (`profile_stages pile10000 80 1`, the broad stage 8.2 ->
//! 5.2 ms with the skipped wake pass of the world's broad stage). The sweep
//! can be cut into consecutive parts of the sorted list, each run on its own
//! thread: a part starts by replaying the endpoints before it without tests,
//! and the parts' pairs, joined and sorted, are the one sweep's.

use super::aabb::Aabb;
use super::endpoint::Endpoint;
use super::pairs::pair_key;
use std::ops::Range;
use wide::f64x4;

/// Axis (0..3) along which the box centres in `list`'s owner slots spread most.
pub(crate) fn widest_axis(list: &[Endpoint], boxes: &[Aabb]) -> usize {
    let n = (list.len() / 2).max(1) as f64;
    let mut sum = [0.0f64; 3];
    let mut sum_sq = [0.0f64; 3];
    for e in list.iter().filter(|e| !e.is_max()) {
        let c = boxes[e.slot() as usize].center();
        for k in 0..3 {
            sum[k] += c[k];
            sum_sq[k] += c[k] * c[k];
        }
    }
    let var = |k: usize| sum_sq[k] / n - (sum[k] / n).powi(2);
    // Strict comparisons: ties go to the lower axis, deterministically.
    let mut best = 0;
    for k in 1..3 {
        if var(k) > var(best) {
            best = k;
        }
    }
    best
}

/// The active list of the sweep: the boxes open at the sweep's position,
/// each with its slot and its interval on the two axes other than the sweep
/// axis, stored axis by axis so that a new box is tested against four open
/// ones in one SIMD compare. Padded to a multiple of four with empty
/// intervals (`lo = +inf`, `hi = -inf`), which overlap nothing.
#[derive(Debug, Clone, Default)]
pub(crate) struct ActiveList {
    slots: Vec<u32>,
    /// `lo[k][i]`, `hi[k][i]`: box `i`'s interval on the `k`-th other axis.
    lo: [Vec<f64>; 2],
    hi: [Vec<f64>; 2],
    /// Position of each slot's entry (valid only while the slot is open).
    pos: Vec<u32>,
}

impl ActiveList {
    /// Empties the list, for sweeps over slots `0..slots`.
    fn reset(&mut self, slots: usize) {
        self.slots.clear();
        for k in 0..2 {
            self.lo[k].clear();
            self.hi[k].clear();
        }
        self.pos.resize(slots, 0);
    }

    fn len(&self) -> usize {
        self.slots.len()
    }

    fn push(&mut self, slot: u32, lo: [f64; 2], hi: [f64; 2]) {
        let at = self.len();
        self.pos[slot as usize] = at as u32;
        self.slots.push(slot);
        // The entry takes the first padding lane, or opens a new group of
        // four (every axis's arrays have the same length).
        let open_group = self.lo[0].len() == at;
        for k in 0..2 {
            if open_group {
                self.lo[k].extend([f64::INFINITY; 4]);
                self.hi[k].extend([f64::NEG_INFINITY; 4]);
            }
            self.lo[k][at] = lo[k];
            self.hi[k][at] = hi[k];
        }
    }

    /// Removes `slot` in O(1): the last entry takes its place.
    fn remove(&mut self, slot: u32) {
        let at = self.pos[slot as usize] as usize;
        let last = self.len() - 1;
        self.slots.swap_remove(at);
        for k in 0..2 {
            self.lo[k][at] = self.lo[k][last];
            self.hi[k][at] = self.hi[k][last];
            self.lo[k][last] = f64::INFINITY;
            self.hi[k][last] = f64::NEG_INFINITY;
        }
        if let Some(&moved) = self.slots.get(at) {
            self.pos[moved as usize] = at as u32;
        }
        // Drop a group of four left all padding.
        if last.is_multiple_of(4) {
            for k in 0..2 {
                self.lo[k].truncate(last);
                self.hi[k].truncate(last);
            }
        }
    }

    /// Appends the key of every open box overlapping `[lo, hi]` on the two
    /// other axes (touching included) to `out`, pairs with `slot`.
    fn overlaps(&self, slot: u32, lo: [f64; 2], hi: [f64; 2], out: &mut Vec<u64>) {
        let (lo0, lo1) = (f64x4::splat(lo[0]), f64x4::splat(lo[1]));
        let (hi0, hi1) = (f64x4::splat(hi[0]), f64x4::splat(hi[1]));
        let lanes = |v: &[f64]| f64x4::from([v[0], v[1], v[2], v[3]]);
        for (group, at) in (0..self.lo[0].len()).step_by(4).enumerate() {
            let hit = lo0.simd_le(lanes(&self.hi[0][at..]))
                & lanes(&self.lo[0][at..]).simd_le(hi0)
                & lo1.simd_le(lanes(&self.hi[1][at..]))
                & lanes(&self.lo[1][at..]).simd_le(hi1);
            let mut bits = hit.to_bitmask();
            while bits != 0 {
                let i = group * 4 + bits.trailing_zeros() as usize;
                out.push(pair_key(slot, self.slots[i]));
                bits &= bits - 1;
            }
        }
    }
}

/// One part of a rebuild's sweep and what it found (scratch, reused).
#[derive(Debug, Clone, Default)]
pub(crate) struct SweepPart {
    active: ActiveList,
    /// The keys of the pairs found (unsorted, each once).
    pub pairs: Vec<u64>,
    /// Box tests done, the part's cost.
    pub tests: u64,
}

impl SweepPart {
    /// Finds every overlapping pair whose later-starting box has its min
    /// endpoint in `list[range]`, by sweeping the sorted `list` of axis
    /// `axis` over `range` (the parts of one list cut into consecutive
    /// ranges find every pair once between them). The boxes open where the
    /// range starts are found first by replaying the endpoints before it,
    /// which opens and closes boxes without testing them.
    pub fn sweep(&mut self, list: &[Endpoint], axis: usize, boxes: &[Aabb], range: Range<usize>) {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let others = |s: u32| {
            let b = &boxes[s as usize];
            ([b.min()[u], b.min()[v]], [b.max()[u], b.max()[v]])
        };
        let active = &mut self.active;
        active.reset(boxes.len());
        self.pairs.clear();
        self.tests = 0;
        for e in &list[..range.start] {
            if e.is_max() {
                active.remove(e.slot());
            } else {
                let (lo, hi) = others(e.slot());
                active.push(e.slot(), lo, hi);
            }
        }
        for e in &list[range] {
            let s = e.slot();
            if e.is_max() {
                active.remove(s);
            } else {
                // Every active box starts at or before this one and has not
                // ended, so they overlap on the sweep axis (touching included,
                // as min endpoints sort before max endpoints); test the other
                // two axes.
                let (lo, hi) = others(s);
                self.tests += active.len() as u64;
                active.overlaps(s, lo, hi, &mut self.pairs);
                active.push(s, lo, hi);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The SIMD active list against a plain list of open boxes, through
    /// pushes and removals that cross every padding boundary: the same
    /// overlapping slots for every query (touching included).
    #[test]
    fn active_list_reports_what_a_plain_list_does() {
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = |k: u64| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) % k
        };
        let mut list = ActiveList::default();
        list.reset(64);
        let mut open: Vec<(u32, [f64; 2], [f64; 2])> = Vec::new();
        let mut checked = 0;
        for _ in 0..2000 {
            let slot = next(64) as u32;
            if let Some(i) = open.iter().position(|o| o.0 == slot) {
                open.swap_remove(i);
                list.remove(slot);
            } else {
                // Integer coordinates: many boxes touch exactly.
                let lo = [next(8) as f64, next(8) as f64];
                let hi = [lo[0] + next(3) as f64, lo[1] + next(3) as f64];
                let mut got = Vec::new();
                list.overlaps(slot, lo, hi, &mut got);
                let mut want: Vec<u64> = open
                    .iter()
                    .filter(|o| lo[0] <= o.2[0] && o.1[0] <= hi[0] && lo[1] <= o.2[1] && o.1[1] <= hi[1])
                    .map(|o| pair_key(slot, o.0))
                    .collect();
                got.sort_unstable();
                want.sort_unstable();
                assert_eq!(got, want, "query {slot} against {} open boxes", open.len());
                checked += want.len();
                open.push((slot, lo, hi));
                list.push(slot, lo, hi);
            }
            assert_eq!(list.len(), open.len());
            assert_eq!(list.lo[0].len(), open.len().div_ceil(4) * 4);
        }
        assert!(checked > 1000, "the queries found overlaps ({checked})");
    }
}
