//! Graph colouring of the contact patches (Box2D v3's constraint graph):
//! patches of one colour share no dynamic body, so a pass can update them
//! in any order, or all at once on many threads, and get the same bits.
//! Static, kinematic and sleeping bodies do not count (the solver never
//! writes them).
//!
//! Greedy, in patch order: each patch takes the lowest colour that neither
//! of its dynamic bodies has yet (a bit mask per body). Small problems
//! (fewer than [`MIN_PATCHES_TO_COLOR`] patches) are not coloured at all. Patches that find
//! none of the [`MAX_COLORS`] free go to an overflow batch, solved serially
//! after the colours (a body touching more than that many others). The
//! patch rows are then built sorted by colour, stably, and their points
//! with them (a colour's rows lie together in memory), so that every pass
//! walks the colours in a fixed order whatever the thread count.

use super::body::SolverBody;
use std::ops::Range;

/// Colours before the overflow batch (one bit each in a body's mask).
pub const MAX_COLORS: usize = 64;

/// Fewer patches than this are not coloured: they form one serial batch in
/// patch order. Splitting them over threads would not pay, and the patch
/// order (pairs in body order) carries a push or a pull along a chain or up
/// a stack in one pass, where colours (every other link, then the rest)
/// carry it one link per colour: the torus chain's deepest penetration grew
/// from 1.6 mm to 2.0 mm coloured. Above it (the 210-box pyramid's 400
/// patches) the colour order did as well as the patch order or better.
pub const MIN_PATCHES_TO_COLOR: usize = 128;

/// The patches in colour order: `colors[c]` is the range of colour `c` in
/// the sorted patch array, `overflow` the range solved serially last.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Coloring {
    /// Ranges of the colours, in order (none empty).
    pub colors: Vec<Range<usize>>,
    /// Patches that found no free colour.
    pub overflow: Range<usize>,
}

impl Coloring {
    /// Every batch in pass order: the colours, then the overflow, with a
    /// flag saying whether its patches are independent (parallel-safe).
    pub fn batches(&self) -> impl Iterator<Item = (Range<usize>, bool)> + '_ {
        self.colors
            .iter()
            .map(|r| (r.clone(), true))
            .chain(std::iter::once((self.overflow.clone(), false)).filter(|(r, _)| !r.is_empty()))
    }
}

/// Colours patches given as the solver-body pairs they link, in patch
/// order; returns the colouring and the patch order sorted by colour
/// (stable: patch indices ascending within a colour). Build the patch rows
/// in that order, each patch's points together.
pub fn color_patches(pairs: &[(u32, u32)], bodies: &[SolverBody]) -> (Coloring, Vec<u32>) {
    if pairs.len() < MIN_PATCHES_TO_COLOR {
        let coloring = Coloring {
            colors: Vec::new(),
            overflow: 0..pairs.len(),
        };
        return (coloring, (0..pairs.len() as u32).collect());
    }
    let mut used = vec![0u64; bodies.len()];
    let mut color_of = Vec::with_capacity(pairs.len());
    for &(a, b) in pairs {
        let (a, b) = (a as usize, b as usize);
        let dynamic = |i: usize| bodies[i].dynamic;
        let mut taken = 0u64;
        if dynamic(a) {
            taken |= used[a];
        }
        if dynamic(b) {
            taken |= used[b];
        }
        let color = (!taken).trailing_zeros() as usize; // 64 when all are taken
        if color < MAX_COLORS {
            let bit = 1u64 << color;
            if dynamic(a) {
                used[a] |= bit;
            }
            if dynamic(b) {
                used[b] |= bit;
            }
        }
        color_of.push(color.min(MAX_COLORS) as u8);
    }
    // Counting sort by colour (stable), the overflow (colour MAX_COLORS) last.
    let mut count = [0usize; MAX_COLORS + 1];
    for &c in &color_of {
        count[c as usize] += 1;
    }
    let mut start = [0usize; MAX_COLORS + 2];
    for c in 0..=MAX_COLORS {
        start[c + 1] = start[c] + count[c];
    }
    let mut next = start;
    let mut order = vec![0u32; pairs.len()];
    for (i, &c) in color_of.iter().enumerate() {
        order[next[c as usize]] = i as u32;
        next[c as usize] += 1;
    }
    let colors = (0..MAX_COLORS)
        .filter(|&c| count[c] > 0)
        .map(|c| start[c]..start[c + 1])
        .collect();
    let overflow = start[MAX_COLORS]..start[MAX_COLORS + 1];
    (Coloring { colors, overflow }, order)
}

/// [`color_patches`] over the patches not `owned`; the owned ones (the
/// patches joint islands solve with their joints) follow them in the
/// order, in patch order, outside every batch.
pub fn color_patches_except(
    pairs: &[(u32, u32)],
    bodies: &[SolverBody],
    owned: &[bool],
) -> (Coloring, Vec<u32>) {
    if !owned.contains(&true) {
        return color_patches(pairs, bodies);
    }
    let free: Vec<u32> = (0..pairs.len() as u32).filter(|&k| !owned[k as usize]).collect();
    let free_pairs: Vec<(u32, u32)> = free.iter().map(|&k| pairs[k as usize]).collect();
    let (coloring, order) = color_patches(&free_pairs, bodies);
    let order = order
        .iter()
        .map(|&k| free[k as usize])
        .chain((0..pairs.len() as u32).filter(|&k| owned[k as usize]))
        .collect();
    (coloring, order)
}

/// A slice that several threads update at once, each at indices no other
/// thread touches in the same pass (the colouring's guarantee). A thin
/// raw-pointer view: the safety of each access is the caller's.
pub struct Shared<'a, T> {
    ptr: *mut T,
    len: usize,
    _borrow: std::marker::PhantomData<&'a mut [T]>,
}

// SAFETY: `Shared` hands out access to distinct elements to distinct
// threads only (see the `unsafe fn`s); the elements themselves are `Send`.
unsafe impl<T: Send> Send for Shared<'_, T> {}
// SAFETY: as above; shared reads of elements nobody writes are fine.
unsafe impl<T: Send + Sync> Sync for Shared<'_, T> {}

impl<'a, T> Shared<'a, T> {
    /// A view of `items`, borrowed mutably for as long as the view lives.
    pub fn new(items: &'a mut [T]) -> Shared<'a, T> {
        Shared {
            ptr: items.as_mut_ptr(),
            len: items.len(),
            _borrow: std::marker::PhantomData,
        }
    }

    /// Number of elements.
    #[allow(clippy::len_without_is_empty)]
    pub fn len(&self) -> usize {
        self.len
    }

    /// The element at `i`.
    ///
    /// # Safety
    /// No other thread may write element `i` while the reference lives.
    #[inline(always)]
    pub unsafe fn get(&self, i: usize) -> &T {
        assert!(i < self.len);
        // SAFETY: in bounds; no concurrent writer (the caller's promise).
        unsafe { &*self.ptr.add(i) }
    }

    /// The element at `i`, mutably.
    ///
    /// # Safety
    /// No other reference to element `i` may exist while this one lives.
    #[inline(always)]
    #[allow(clippy::mut_from_ref)]
    pub unsafe fn get_mut(&self, i: usize) -> &mut T {
        assert!(i < self.len);
        // SAFETY: in bounds; exclusive (the caller's promise).
        unsafe { &mut *self.ptr.add(i) }
    }

    /// All elements, shared.
    ///
    /// # Safety
    /// No thread may write any element while the slice lives.
    #[inline(always)]
    pub unsafe fn as_slice(&self) -> &[T] {
        // SAFETY: in bounds; no concurrent writer (the caller's promise).
        unsafe { std::slice::from_raw_parts(self.ptr, self.len) }
    }

    /// The elements in `r`, mutably.
    ///
    /// # Safety
    /// No other reference to an element of `r` may exist while this one lives.
    #[inline(always)]
    #[allow(clippy::mut_from_ref)]
    pub unsafe fn range_mut(&self, r: Range<usize>) -> &mut [T] {
        assert!(r.start <= r.end && r.end <= self.len);
        // SAFETY: in bounds; exclusive (the caller's promise).
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(r.start), r.end - r.start) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_collide::{DQuat, DVec3};

    fn bodies(n: usize) -> Vec<SolverBody> {
        // Body 0 is static; the rest dynamic.
        (0..n)
            .map(|i| {
                let inv_mass = if i == 0 { 0.0 } else { 1.0 };
                SolverBody::new(DVec3::ZERO, DVec3::ZERO, inv_mass, DVec3::ONE, DQuat::IDENTITY)
            })
            .collect()
    }

    /// Brute force: within a colour no dynamic body appears twice; the
    /// order is a permutation, ascending within each colour; overflow only
    /// when a body has more than MAX_COLORS patches.
    #[test]
    fn colours_share_no_dynamic_body_and_keep_patch_order() {
        let n = 100;
        let b = bodies(n);
        // A pseudo-random graph, every body also on the static body 0.
        let mut pairs = Vec::new();
        let mut x: u64 = 12345;
        for i in 1..n as u32 {
            pairs.push((i, 0));
            for _ in 0..3 {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let j = 1 + (x >> 33) as u32 % (n as u32 - 1);
                if j != i {
                    pairs.push((i, j));
                }
            }
        }
        let (coloring, order) = color_patches(&pairs, &b);
        let mut seen = order.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..pairs.len() as u32).collect::<Vec<_>>());
        assert!(coloring.overflow.is_empty());
        for r in &coloring.colors {
            let batch = &order[r.clone()];
            assert!(batch.windows(2).all(|w| w[0] < w[1]), "stable within a colour");
            let mut used = std::collections::BTreeSet::new();
            for &k in batch {
                let (a, c) = pairs[k as usize];
                for body in [a, c] {
                    if b[body as usize].dynamic {
                        assert!(used.insert(body), "body {body} twice in one colour");
                    }
                }
            }
        }
    }

    /// Owned patches follow every batch, in patch order; the batches hold
    /// exactly the others, coloured as `color_patches` colours them alone.
    #[test]
    fn owned_patches_follow_every_batch() {
        let n = 200;
        let b = bodies(n);
        let pairs: Vec<(u32, u32)> = (1..n as u32)
            .map(|i| (i, 0))
            .chain((2..n as u32).map(|i| (i - 1, i)))
            .collect();
        let owned: Vec<bool> = (0..pairs.len()).map(|k| k % 7 == 3).collect();
        let (coloring, order) = color_patches_except(&pairs, &b, &owned);
        let free: Vec<u32> = (0..pairs.len() as u32).filter(|&k| !owned[k as usize]).collect();
        let free_pairs: Vec<(u32, u32)> = free.iter().map(|&k| pairs[k as usize]).collect();
        let (alone, alone_order) = color_patches(&free_pairs, &b);
        assert_eq!(coloring, alone);
        assert!(!coloring.colors.is_empty());
        let batched: usize = coloring.batches().map(|(r, _)| r.len()).sum();
        assert_eq!(batched, free.len());
        assert_eq!(
            &order[..free.len()],
            &alone_order.iter().map(|&k| free[k as usize]).collect::<Vec<_>>()[..]
        );
        let owned_in_order: Vec<u32> = (0..pairs.len() as u32).filter(|&k| owned[k as usize]).collect();
        assert_eq!(&order[free.len()..], &owned_in_order[..]);
    }

    #[test]
    fn few_patches_stay_in_patch_order_in_one_serial_batch() {
        let b = bodies(10);
        let pairs: Vec<(u32, u32)> = (1..10)
            .map(|i| (i, 0))
            .chain((2..10).map(|i| (i - 1, i)))
            .collect();
        let (coloring, order) = color_patches(&pairs, &b);
        assert!(coloring.colors.is_empty());
        assert_eq!(coloring.overflow, 0..pairs.len());
        assert_eq!(order, (0..pairs.len() as u32).collect::<Vec<_>>());
    }

    #[test]
    fn a_body_with_too_many_contacts_overflows_into_a_serial_batch() {
        let b = bodies(MAX_COLORS + MIN_PATCHES_TO_COLOR + 10);
        // Body 1 touches every other dynamic body: one patch per colour,
        // until the colours run out.
        let pairs: Vec<(u32, u32)> = (2..b.len() as u32).map(|j| (1, j)).collect();
        let (coloring, order) = color_patches(&pairs, &b);
        assert_eq!(coloring.colors.len(), MAX_COLORS);
        assert_eq!(coloring.overflow.len(), pairs.len() - MAX_COLORS);
        assert_eq!(
            &order[coloring.overflow.clone()],
            &(MAX_COLORS as u32..pairs.len() as u32).collect::<Vec<_>>()[..]
        );
        assert_eq!(
            coloring.batches().filter(|(_, independent)| !independent).count(),
            1
        );
    }
}
