//! Overlapping pairs: the packed pair key, the begin/end events, and the sorted
//! merges that keep the persistent pair set without per-update allocation.
//!
//! The pair set is a sorted `Vec<u64>` of keys `(lo_slot << 32) | hi_slot`;
//! membership is a binary search. Sorted keys make the iteration order, and so
//! the event order, independent of history (determinism, DESIGN.md).

use super::proxy::ProxyId;

/// A change of the overlapping-pair set, reported by
/// [`super::SweepAndPrune::update`]. The two ids are in increasing order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PairEvent {
    /// The two boxes started to overlap (or touch).
    Begin(ProxyId, ProxyId),
    /// The two boxes stopped overlapping, or one of them was removed.
    End(ProxyId, ProxyId),
}

impl PairEvent {
    /// The pair `(smaller id, larger id)`.
    pub fn pair(&self) -> (ProxyId, ProxyId) {
        match *self {
            PairEvent::Begin(a, b) | PairEvent::End(a, b) => (a, b),
        }
    }

    /// `true` for [`PairEvent::Begin`].
    pub fn is_begin(&self) -> bool {
        matches!(self, PairEvent::Begin(..))
    }
}

/// Pair keys that begin and end during one update (scratch, reused).
#[derive(Debug, Default, Clone)]
pub(crate) struct Changes {
    /// Pairs that start overlapping.
    pub begins: Vec<u64>,
    /// Pairs that stop overlapping.
    pub ends: Vec<u64>,
}

impl Changes {
    /// Empties both lists, keeping their capacity.
    pub fn clear(&mut self) {
        self.begins.clear();
        self.ends.clear();
    }

    /// Sorts both lists and removes repeats.
    pub fn normalize(&mut self) {
        for list in [&mut self.begins, &mut self.ends] {
            list.sort_unstable();
            list.dedup();
        }
    }
}

/// Key of the unordered pair `{a, b}` of slots (`a != b`).
#[inline]
pub(crate) fn pair_key(a: u32, b: u32) -> u64 {
    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
    ((lo as u64) << 32) | hi as u64
}

/// The two slots of a key, smaller first.
#[inline]
pub(crate) fn split_key(key: u64) -> (u32, u32) {
    ((key >> 32) as u32, key as u32)
}

/// `out = (set \ remove) ∪ add`, all sorted and duplicate-free, `add` disjoint
/// from `set`; O(|set| + |remove| + |add|).
pub(crate) fn merge_set(set: &[u64], remove: &[u64], add: &[u64], out: &mut Vec<u64>) {
    out.clear();
    out.reserve(set.len() + add.len());
    let (mut r, mut a) = (0, 0);
    for &key in set {
        while r < remove.len() && remove[r] < key {
            r += 1;
        }
        if r < remove.len() && remove[r] == key {
            continue;
        }
        while a < add.len() && add[a] < key {
            out.push(add[a]);
            a += 1;
        }
        out.push(key);
    }
    out.extend_from_slice(&add[a..]);
}

/// Makes `next` the pair set `set`, its changes pushed to `changes` (both
/// sorted); `next` keeps the old set's buffer as scratch.
pub(crate) fn replace_set(set: &mut Vec<u64>, next: &mut Vec<u64>, changes: &mut Changes) {
    diff_sets(set, next, &mut changes.begins, &mut changes.ends);
    std::mem::swap(set, next);
}

/// Pushes `old \ new` to `ends` and `new \ old` to `begins` (inputs sorted).
pub(crate) fn diff_sets(old: &[u64], new: &[u64], begins: &mut Vec<u64>, ends: &mut Vec<u64>) {
    let (mut i, mut j) = (0, 0);
    while i < old.len() && j < new.len() {
        match old[i].cmp(&new[j]) {
            std::cmp::Ordering::Less => {
                ends.push(old[i]);
                i += 1;
            }
            std::cmp::Ordering::Greater => {
                begins.push(new[j]);
                j += 1;
            }
            std::cmp::Ordering::Equal => {
                i += 1;
                j += 1;
            }
        }
    }
    ends.extend_from_slice(&old[i..]);
    begins.extend_from_slice(&new[j..]);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn key_is_symmetric_and_ordered_by_low_slot() {
        assert_eq!(pair_key(3, 9), pair_key(9, 3));
        assert_eq!(split_key(pair_key(9, 3)), (3, 9));
        assert!(pair_key(1, u32::MAX >> 1) < pair_key(2, 3));
    }

    #[test]
    fn merge_and_diff_agree_with_set_algebra() {
        let set = [1, 4, 6, 9];
        let mut out = Vec::new();
        merge_set(&set, &[4, 9, 10], &[0, 5, 12], &mut out);
        assert_eq!(out, [0, 1, 5, 6, 12]);
        let (mut b, mut e) = (Vec::new(), Vec::new());
        diff_sets(&set, &out, &mut b, &mut e);
        assert_eq!(b, [0, 5, 12]);
        assert_eq!(e, [4, 9]);
    }
}
