//! Full rebuild: sort the three endpoint lists from scratch and find every
//! overlapping pair by one sweep along a single axis (thesis 4.7, figure 4.2:
//! the "active list" sweep). Used for the first build, for large batches of
//! insertions, and when incoherent motion (teleports) would make the insertion
//! sort quadratic. O(n log n + n * a + k) with `a` the mean active-list length on
//! the sweep axis, which is chosen as the axis of largest spread of box centres
//! to keep `a` small.

use super::aabb::Aabb;
use super::endpoint::Endpoint;
use super::pairs::pair_key;
use super::proxy::EndIndex;

/// Sorts `list` by the total endpoint order and refreshes `ends[..][axis]`.
pub(crate) fn sort_full(list: &mut [Endpoint], axis: usize, ends: &mut [EndIndex]) {
    list.sort_unstable_by(Endpoint::total_cmp);
    reindex(list, axis, ends);
}

/// Refreshes `ends[..][axis]` from the positions in `list`.
pub(crate) fn reindex(list: &[Endpoint], axis: usize, ends: &mut [EndIndex]) {
    for (pos, e) in list.iter().enumerate() {
        ends[e.slot() as usize][axis][e.end()] = pos as u32;
    }
}

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

/// An entry of the active list: the slot and its box on the two axes other than
/// the sweep axis, stored inline so that the inner loop scans memory in order.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Active {
    slot: u32,
    lo: [f64; 2],
    hi: [f64; 2],
}

/// Appends the key of every overlapping pair to `out` (unsorted, each once) by
/// sweeping the sorted `list` of axis `axis`; returns the number of box tests
/// done (the sweep's cost). `active` and `active_pos` are scratch buffers;
/// `active_pos` must have one entry per slot.
pub(crate) fn sweep_pairs(
    list: &[Endpoint],
    axis: usize,
    boxes: &[Aabb],
    active: &mut Vec<Active>,
    active_pos: &mut [u32],
    out: &mut Vec<u64>,
) -> u64 {
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    let mut tests = 0u64;
    active.clear();
    for e in list {
        let s = e.slot();
        if e.is_max() {
            // Swap-remove `s` from the active list in O(1).
            let pos = active_pos[s as usize] as usize;
            active.swap_remove(pos);
            if let Some(moved) = active.get(pos) {
                active_pos[moved.slot as usize] = pos as u32;
            }
        } else {
            // Every active box starts at or before this one and has not ended,
            // so they overlap on the sweep axis (touching included, as min
            // endpoints sort before max endpoints); test the other two axes.
            let b = &boxes[s as usize];
            let me = Active {
                slot: s,
                lo: [b.min()[u], b.min()[v]],
                hi: [b.max()[u], b.max()[v]],
            };
            tests += active.len() as u64;
            for other in active.iter() {
                if me.lo[0] <= other.hi[0]
                    && other.lo[0] <= me.hi[0]
                    && me.lo[1] <= other.hi[1]
                    && other.lo[1] <= me.hi[1]
                {
                    out.push(pair_key(s, other.slot));
                }
            }
            active_pos[s as usize] = active.len() as u32;
            active.push(me);
        }
    }
    tests
}
