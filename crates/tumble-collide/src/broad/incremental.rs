//! Incremental update: insertion sort of one nearly-sorted endpoint list, with
//! the pair set updated at every swap (Baraff 1992, thesis 4.7; Cohen et al.,
//! I-COLLIDE 1995, section 4.1).
//!
//! Insertion sort performs exactly one swap per inverted pair of the list, so
//! each change of relative order between a min and a max endpoint is seen once:
//! - min of `e` moves before max of `f`: the intervals may start overlapping on
//!   this axis. Instead of per-pair axis counters (memory quadratic in the worst
//!   case) the two *new* boxes are tested on all three axes; if they overlap the
//!   pair begins. Such a pair was separated on this axis before, so it cannot be
//!   in the old set, and it ends the update overlapping, so it cannot end later.
//! - max of `e` moves before min of `f`: the intervals separate on this axis; if
//!   the pair was in the old set it ends. Membership is a binary search, skipped
//!   when either slot had no pair at all (per-slot pair counts, an upper bound).
//!
//! A begin may be found on up to three axes and an end likewise, so the caller
//! sorts and de-duplicates the two lists. A pair never both begins and ends in one
//! update: every swap moves a pair towards its final (new-value) state.
//!
//! The per-slot endpoint positions are not touched during the sort (a random
//! write per swap); the caller re-indexes the list once afterwards, O(n).

use super::aabb::Aabb;
use super::endpoint::Endpoint;
use super::pairs::{pair_key, Changes};

/// Output of one list's sort.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct SortOutcome {
    /// Endpoint swaps performed.
    pub swaps: u64,
    /// `false` when the swap budget ran out before the list was sorted.
    pub finished: bool,
}

/// Insertion-sorts `list`, pushes
/// candidate begins and ends to `changes` (pair keys, possibly repeated). Stops early, with
/// `list` a valid permutation, once `swaps > budget`.
pub(crate) fn sort_axis(
    list: &mut [Endpoint],
    boxes: &[Aabb],
    old_pairs: &[u64],
    pair_counts: &[u32],
    changes: &mut Changes,
    budget: u64,
) -> SortOutcome {
    let mut swaps = 0u64;
    for i in 1..list.len() {
        let e = list[i];
        if !list[i - 1].after(e) {
            continue;
        }
        let mut j = i;
        while j > 0 && list[j - 1].after(e) {
            let f = list[j - 1];
            if !e.is_max() && f.is_max() {
                let (a, b) = (e.slot() as usize, f.slot() as usize);
                if boxes[a].overlaps(&boxes[b]) {
                    changes.begins.push(pair_key(e.slot(), f.slot()));
                }
            } else if e.is_max() && !f.is_max() {
                let (a, b) = (e.slot(), f.slot());
                if pair_counts[a as usize] > 0 && pair_counts[b as usize] > 0 {
                    let key = pair_key(a, b);
                    if old_pairs.binary_search(&key).is_ok() {
                        changes.ends.push(key);
                    }
                }
            }
            list[j] = f;
            j -= 1;
        }
        list[j] = e;
        swaps += (i - j) as u64;
        if swaps > budget {
            return SortOutcome {
                swaps,
                finished: false,
            };
        }
    }
    SortOutcome {
        swaps,
        finished: true,
    }
}
