//! A LIFO stack that lives on the call stack up to a fixed depth and spills to
//! the heap only beyond it, so tree traversals do not allocate in practice
//! (the pair stack of a depth-first walk holds at most about
//! `depth_a + depth_b` entries).

const INLINE: usize = 96;

/// Stack with `INLINE` entries in place and a heap overflow.
pub(crate) struct SmallStack<T: Copy + Default> {
    inline: [T; INLINE],
    len: usize,
    spill: Vec<T>,
}

impl<T: Copy + Default> SmallStack<T> {
    pub(crate) fn new() -> Self {
        SmallStack {
            inline: [T::default(); INLINE],
            len: 0,
            spill: Vec::new(),
        }
    }

    #[inline]
    pub(crate) fn push(&mut self, v: T) {
        if self.len < INLINE {
            self.inline[self.len] = v;
            self.len += 1;
        } else {
            self.spill.push(v);
        }
    }

    #[inline]
    pub(crate) fn pop(&mut self) -> Option<T> {
        if let Some(v) = self.spill.pop() {
            return Some(v);
        }
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        Some(self.inline[self.len])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lifo_across_the_spill_boundary() {
        let mut s = SmallStack::<u32>::new();
        for i in 0..300 {
            s.push(i);
        }
        for i in (0..300).rev() {
            assert_eq!(s.pop(), Some(i));
        }
        assert_eq!(s.pop(), None);
    }
}
