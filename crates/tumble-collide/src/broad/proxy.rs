//! Proxy handles and the per-proxy record kept by the sweep-and-prune.
//!
//! A [`ProxyId`] is a slot index plus a generation (as Box2D's ids): a slot is
//! reused only after the update that follows its removal, and reuse bumps the
//! generation, so a stale id is detected instead of silently naming a new box.

use std::fmt;

/// Handle of one box in a [`super::SweepAndPrune`].
///
/// Ordered by slot index first; two live proxies never share an index, so the
/// order of live ids is the order of their indices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ProxyId {
    index: u32,
    generation: u32,
}

impl ProxyId {
    pub(crate) fn new(index: u32, generation: u32) -> ProxyId {
        ProxyId { index, generation }
    }

    /// Slot index (dense, small; reused after removal).
    pub fn index(self) -> u32 {
        self.index
    }

    /// How many times the slot had been reused when this id was issued.
    pub fn generation(self) -> u32 {
        self.generation
    }
}

impl fmt::Display for ProxyId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "proxy {}#{}", self.index, self.generation)
    }
}

/// Life cycle of a slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SlotState {
    /// In the sweep lists.
    Live,
    /// Removed by the user; its endpoints and pairs go at the next update.
    Removed,
    /// On the free list, waiting for reuse.
    Free,
}

/// Position of a slot's min (`[0]`) and max (`[1]`) endpoint in one axis's
/// list.
pub(crate) type EndIndex = [u32; 2];

/// Identity and life cycle of a slot (its box and endpoint positions live in
/// separate dense arrays, which the sorts touch far more often).
#[derive(Debug, Clone)]
pub(crate) struct Slot {
    /// The caller's tag.
    pub user_id: u32,
    /// Generation of the id that owns the slot now.
    pub generation: u32,
    /// Life cycle state.
    pub state: SlotState,
    /// Listed among the boxes moved since the last update (listed once,
    /// however often `set_aabb` is called).
    pub moved: bool,
}
