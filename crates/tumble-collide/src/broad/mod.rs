//! Broad phase: sweep-and-prune over axis-aligned boxes with persistent pairs
//! (thesis 4.7 and 5.3; D. Baraff, "Dynamic simulation of non-penetrating rigid
//! bodies", 1992, ch. 6; Cohen, Lin, Manocha & Ponamgi, "I-COLLIDE", 1995, 4.1).
//!
//! Each proxy's box contributes a min and a max endpoint to a list per axis. The
//! lists stay sorted (by value; at equal values min before max, so touching
//! boxes overlap, as in [`Aabb::overlaps`]), and two boxes overlap exactly when
//! their intervals interleave on all three lists. The set of overlapping pairs is
//! kept between updates, and [`SweepAndPrune::update`] reports its changes as
//! [`PairEvent::Begin`] / [`PairEvent::End`], sorted by pair.
//!
//! # Two modes of update
//!
//! - **Incremental** (coherent motion): the new box values are written into the
//!   lists in place and each list is insertion-sorted. Every swap of a min past a
//!   max is a change of overlap on that axis, checked against the boxes on all
//!   three axes (the argument is written out in `incremental.rs`). Cost O(n + s) for
//!   `s` swaps, i.e. O(n + k) when bodies move little per step. New proxies are
//!   appended at the ends of the lists and sorted in the same way (as if coming
//!   from +infinity); removed proxies are filtered out of the lists in one O(n)
//!   pass and their pairs end.
//! - **Rebuild** (first build, large batches, incoherent motion such as
//!   teleports): the lists are fully sorted and all pairs found by one sweep
//!   along the axis of widest spread. The events are the difference between the
//!   old and the new pair set, so both modes report exactly the same events.
//!   The switch is made on the swap budget `factor * (n * ceil(log2(n + 2)) +
//!   t / 8) + 64` (`t`: box tests of the last rebuild sweep; together about the
//!   cost of a rebuild, see [`SweepAndPrune::with_swap_budget_factor`]):
//!   1. before sorting, the swaps are *predicted* from the motion: each
//!      `set_aabb` adds its centre displacement over the scene extent per axis
//!      (`2n` endpoints spread over the extent are passed in proportion), and
//!      each new proxy counts `n`; a prediction over budget rebuilds at once
//!      (teleports, first build, big batches);
//!   2. otherwise the insertion sorts run, each axis within the budget, and if
//!      one exceeds it (the prediction assumed an even spread) they stop and
//!      the update rebuilds, discarding the partial results; the next 1, 3, 7,
//!      then 15 updates rebuild at once while the sorts keep failing (a stack's
//!      layers, many equal values that any jitter reorders, fail them every
//!      step).
//!
//!   The three axes' sorts, and the parts of a rebuild's sweep, are
//!   independent jobs that [`SweepAndPrune::update_on`] hands to a
//!   [`BroadJobs`] (the world's threads), with the same results.
//!
//!   [`UpdateReport`] says which path was taken, with the predicted and actual
//!   swaps.
//!
//! # Enlarged boxes
//!
//! [`SweepAndPrune::with_enlargement`] lists each box grown by a fraction of
//! its largest side (Bullet's and Box2D's fat boxes). A box set within its
//! listed box (and not shrunk to under half of it) changes no list, and an
//! update in which no listed box changed, none came and none went sorts
//! nothing. The lists' pairs are then a superset; at every update those whose
//! boxes as set overlap become the pairs reported, and the events are their
//! set's changes. Without it, bodies resting in layers (equal values that any
//! jitter reorders) fail the insertion sorts and rebuild at every update.
//!
//! Ids are (slot, generation) handles: removing twice, or using an id after its
//! slot was reused, is a typed error. Memory: 96 bytes of endpoints and about 130
//! bytes of record per proxy, 8 bytes per overlapping pair (plus one scratch set
//! of the same size, and with an enlargement the reported set too); once the
//! buffers have grown, updates do not allocate.

mod aabb;
mod axis;
mod endpoint;
mod error;
mod incremental;
mod jobs;
mod pairs;
mod proxy;
mod rebuild;
mod sap;

pub use aabb::{Aabb, AabbError};
pub use error::BroadPhaseError;
pub use jobs::{BroadJobs, InOrder};
pub use pairs::PairEvent;
pub use proxy::ProxyId;
pub use sap::{SweepAndPrune, UpdateReport, DEFAULT_SWAP_BUDGET_FACTOR};
