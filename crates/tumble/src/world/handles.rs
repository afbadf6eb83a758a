//! Generational handles: `BodyId` = slot index + generation, so that a handle
//! to a removed body is detected as stale instead of silently addressing the
//! body that reused its slot (as in Box2D's ids and Rapier's arenas).

use serde::{Deserialize, Serialize};

/// Handle of a body in a [`World`](crate::world::World).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct BodyId {
    /// Slot index.
    pub index: u32,
    /// Generation of the slot when the handle was issued.
    pub generation: u32,
}

/// Handle of a joint in a [`World`](crate::world::World).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct JointId {
    /// Slot index.
    pub index: u32,
    /// Generation of the slot when the handle was issued.
    pub generation: u32,
}

/// A generational handle type an [`Arena`] issues.
pub trait Handle: Copy {
    /// The handle of slot `index` at `generation`.
    fn from_parts(index: u32, generation: u32) -> Self;
    /// Slot index.
    fn index(self) -> u32;
    /// Generation.
    fn generation(self) -> u32;
}

macro_rules! handle {
    ($t:ty) => {
        impl Handle for $t {
            fn from_parts(index: u32, generation: u32) -> Self {
                Self { index, generation }
            }
            fn index(self) -> u32 {
                self.index
            }
            fn generation(self) -> u32 {
                self.generation
            }
        }
    };
}
handle!(BodyId);
handle!(JointId);

/// A slot arena with generational handles of type `I`; iteration is in
/// slot order, so it is deterministic.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(bound(serialize = "T: Serialize", deserialize = "T: Deserialize<'de>"))]
pub struct Arena<T, I = BodyId> {
    slots: Vec<Slot<T>>,
    free: Vec<u32>,
    len: usize,
    #[serde(skip)]
    _handle: std::marker::PhantomData<I>,
}

impl<T, I> Default for Arena<T, I> {
    fn default() -> Self {
        Arena {
            slots: Vec::new(),
            free: Vec::new(),
            len: 0,
            _handle: std::marker::PhantomData,
        }
    }
}

/// A run of consecutive slots of an [`Arena`] ([`Arena::runs_mut`]).
pub struct SlotRun<'a, T> {
    slots: &'a mut [Slot<T>],
}

impl<T> SlotRun<'_, T> {
    /// Slots in the run.
    pub fn len(&self) -> usize {
        self.slots.len()
    }

    /// `true` for a run of no slots.
    pub fn is_empty(&self) -> bool {
        self.slots.is_empty()
    }

    /// The live value in the run's slot `k` (counted from the run's first).
    pub fn at_mut(&mut self, k: usize) -> Option<&mut T> {
        self.slots.get_mut(k)?.value.as_mut()
    }
}

#[derive(Debug, Clone, Serialize, Deserialize)]
struct Slot<T> {
    generation: u32,
    value: Option<T>,
}

impl<T, I: Handle> Arena<T, I> {
    /// An empty arena.
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of live values.
    pub fn len(&self) -> usize {
        self.len
    }

    /// `true` when there are no live values.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Stores `value`, reusing the most recently freed slot.
    pub fn insert(&mut self, value: T) -> I {
        self.len += 1;
        if let Some(index) = self.free.pop() {
            let slot = &mut self.slots[index as usize];
            slot.value = Some(value);
            I::from_parts(index, slot.generation)
        } else {
            self.slots.push(Slot {
                generation: 0,
                value: Some(value),
            });
            I::from_parts(self.slots.len() as u32 - 1, 0)
        }
    }

    /// Removes and returns the value, or `None` if the handle is stale.
    pub fn remove(&mut self, id: I) -> Option<T> {
        let slot = self.slots.get_mut(id.index() as usize)?;
        if slot.generation != id.generation() || slot.value.is_none() {
            return None;
        }
        slot.generation = slot.generation.wrapping_add(1);
        self.free.push(id.index());
        self.len -= 1;
        slot.value.take()
    }

    /// The value, or `None` if the handle is stale.
    pub fn get(&self, id: I) -> Option<&T> {
        let slot = self.slots.get(id.index() as usize)?;
        if slot.generation != id.generation() {
            return None;
        }
        slot.value.as_ref()
    }

    /// Mutable access, or `None` if the handle is stale.
    pub fn get_mut(&mut self, id: I) -> Option<&mut T> {
        let slot = self.slots.get_mut(id.index() as usize)?;
        if slot.generation != id.generation() {
            return None;
        }
        slot.value.as_mut()
    }

    /// Number of slots (live or free): slot indices are below this.
    pub fn slot_count(&self) -> usize {
        self.slots.len()
    }

    /// Handle of the live value in slot `index`, if any.
    pub fn id_at(&self, index: u32) -> Option<I> {
        let slot = self.slots.get(index as usize)?;
        slot.value.as_ref().map(|_| I::from_parts(index, slot.generation))
    }

    /// The live value in slot `index`, if any.
    pub fn at(&self, index: u32) -> Option<&T> {
        self.slots.get(index as usize)?.value.as_ref()
    }

    /// Mutable access to the live value in slot `index`, if any.
    pub fn at_mut(&mut self, index: u32) -> Option<&mut T> {
        self.slots.get_mut(index as usize)?.value.as_mut()
    }

    /// The slots in runs of `run` (the last may be shorter), each with the
    /// index of its first slot: disjoint mutable access for parallel
    /// passes over the live values (`None` for a free slot).
    pub fn runs_mut(&mut self, run: usize) -> Vec<(u32, SlotRun<'_, T>)> {
        let run = run.max(1);
        self.slots
            .chunks_mut(run)
            .enumerate()
            .map(|(k, slots)| ((k * run) as u32, SlotRun { slots }))
            .collect()
    }

    /// Generation of slot `index` (live or free), if the slot exists.
    pub fn generation_at(&self, index: u32) -> Option<u32> {
        self.slots.get(index as usize).map(|s| s.generation)
    }

    /// Free slots in the order they will be reused (last first).
    pub fn free_slots(&self) -> &[u32] {
        &self.free
    }

    /// Rebuilds an arena from its slots (generation, value) and free list,
    /// as read back from a snapshot: the free list must name every empty
    /// slot exactly once and no live one.
    pub fn from_raw_parts(slots: Vec<(u32, Option<T>)>, free: Vec<u32>) -> Result<Arena<T, I>, String> {
        let mut listed = vec![false; slots.len()];
        for &f in &free {
            match slots.get(f as usize) {
                Some((_, None)) if !listed[f as usize] => listed[f as usize] = true,
                _ => return Err(format!("free slot {f} is out of range, live or listed twice")),
            }
        }
        let len = slots.iter().filter(|(_, v)| v.is_some()).count();
        if len + free.len() != slots.len() {
            return Err(format!(
                "{} empty slots but {} on the free list",
                slots.len() - len,
                free.len()
            ));
        }
        Ok(Arena {
            slots: slots
                .into_iter()
                .map(|(generation, value)| Slot { generation, value })
                .collect(),
            free,
            len,
            _handle: std::marker::PhantomData,
        })
    }

    /// Live values with their handles, in slot order.
    pub fn iter(&self) -> impl Iterator<Item = (I, &T)> {
        self.slots.iter().enumerate().filter_map(|(i, s)| {
            s.value
                .as_ref()
                .map(|v| (I::from_parts(i as u32, s.generation), v))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stale_handles_are_detected() {
        let mut a: Arena<i32> = Arena::new();
        let x = a.insert(1);
        let y = a.insert(2);
        assert_eq!(a.remove(x), Some(1));
        assert_eq!(a.remove(x), None, "removing twice");
        let z = a.insert(3);
        assert_eq!(z.index, x.index, "slot reused");
        assert_eq!(a.get(x), None, "stale handle to a reused slot");
        assert_eq!(a.get(z), Some(&3));
        assert_eq!(a.get(y), Some(&2));
        assert_eq!(a.len(), 2);
        let order: Vec<i32> = a.iter().map(|(_, &v)| v).collect();
        assert_eq!(order, vec![3, 2]);
    }
}
