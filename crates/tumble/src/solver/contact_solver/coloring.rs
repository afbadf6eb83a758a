//! Graph colouring of the contact patches (Box2D v3's constraint graph):
//! patches of one colour share no dynamic body, so a pass can update them
//! in any order, or all at once on many threads, and get the same bits.
//! Static, kinematic and sleeping bodies do not count (the solver never
//! writes them).
//!
//! Greedy, in patch order: each patch takes the lowest colour that neither
//! of its dynamic bodies has yet (a bit mask per body). Patches that find
//! none of the [`MAX_COLORS`] free go to an overflow batch, solved serially
//! after the colours (a body touching more than that many others). The
//! patch rows are then built sorted by colour, stably, and their points
//! with them (a colour's rows lie together in memory), so that every pass
//! walks the colours in a fixed order whatever the thread count.
//!
//! Small problems (fewer than [`MIN_PATCHES_TO_COLOR`] patches) keep the
//! patch order instead, cut into *levels* (`level_patches`): a patch's
//! level is one past the last level of either of its dynamic bodies, so
//! two patches that share a body keep their order and the patches of one
//! level share none. A pass over the levels one after the other then makes
//! the serial pass's updates, those of patches on different bodies merely
//! interleaved (they commute: the same bits), and a level's small patches
//! go four at a time into the SIMD bundles like a colour's. A problem
//! whose levels would hold fewer than [`MIN_PATCHES_PER_LEVEL`] patches on
//! average (a column of boxes: one patch a level) stays one serial batch.

use super::body::SolverBody;
use std::ops::Range;

/// Colours before the overflow batch (one bit each in a body's mask).
pub const MAX_COLORS: usize = 64;

/// Fewer patches than this are not coloured: they keep the patch order, in
/// levels (module docs) or one serial batch, on one thread. Splitting them
/// over threads would not pay, and the patch order (pairs in body order)
/// carries a push or a pull along a chain or up a stack in one pass, where
/// colours (every other link, then the rest) carry it one link per colour:
/// the torus chain's deepest penetration grew from 1.6 mm to 2.0 mm
/// coloured, and a column of 20 boxes' top box moved 6.9 mm in 10 s
/// instead of 4.0 (its deepest overlap 1.1 mm instead of 0.7). Above it
/// (the 210-box pyramid's 400 patches) the colour order did as well as the
/// patch order or better.
pub const MIN_PATCHES_TO_COLOR: usize = 128;

/// Fewest patches a level of a small problem must hold on average for
/// the levels to be used (below, one serial batch): a bundle of four lanes
/// with one patch in it costs more than the scalar kernel.
pub const MIN_PATCHES_PER_LEVEL: usize = 2;

/// The patches in colour order: `colors[c]` is the range of colour `c` in
/// the sorted patch array, `overflow` the range solved serially last.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Coloring {
    /// Ranges of the colours, in order (none empty).
    pub colors: Vec<Range<usize>>,
    /// Patches that found no free colour.
    pub overflow: Range<usize>,
    /// The colours are levels of the patch order (a small problem,
    /// `level_patches`): run one after the other on one thread.
    pub levels: bool,
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
/// (stable: patch indices ascending within a colour; a small problem's
/// levels, module docs). Build the patch rows in that order, each patch's
/// points together.
pub fn color_patches(pairs: &[(u32, u32)], bodies: &[SolverBody]) -> (Coloring, Vec<u32>) {
    if pairs.len() < MIN_PATCHES_TO_COLOR {
        return level_patches(pairs, bodies);
    }
    color_greedy(pairs, bodies)
}

/// [`color_patches`] for joint rows: the same colours, but a small problem
/// stays one serial batch in joint order (joints have no SIMD bundles for
/// levels to fill, only barriers to add).
pub fn color_joints(pairs: &[(u32, u32)], bodies: &[SolverBody]) -> (Coloring, Vec<u32>) {
    if pairs.len() < MIN_PATCHES_TO_COLOR {
        return serial_batch(pairs.len());
    }
    color_greedy(pairs, bodies)
}

/// `n` rows in one serial batch, in their order.
fn serial_batch(n: usize) -> (Coloring, Vec<u32>) {
    let coloring = Coloring {
        colors: Vec::new(),
        overflow: 0..n,
        levels: false,
    };
    (coloring, (0..n as u32).collect())
}

/// The greedy colouring (module docs).
fn color_greedy(pairs: &[(u32, u32)], bodies: &[SolverBody]) -> (Coloring, Vec<u32>) {
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
        color_of.push(color.min(MAX_COLORS));
    }
    // The overflow (colour MAX_COLORS) last.
    let (start, order) = sorted_by_label(&color_of, MAX_COLORS + 1);
    let colors = (0..MAX_COLORS)
        .filter(|&c| start[c + 1] > start[c])
        .map(|c| start[c]..start[c + 1])
        .collect();
    let overflow = start[MAX_COLORS]..start[MAX_COLORS + 1];
    let coloring = Coloring {
        colors,
        overflow,
        levels: false,
    };
    (coloring, order)
}

/// The levels of a small problem (module docs): each patch one level past
/// the last of either of its dynamic bodies, the patch order sorted by
/// level, stably. One serial batch in patch order instead when the levels
/// would hold fewer than [`MIN_PATCHES_PER_LEVEL`] patches on average.
fn level_patches(pairs: &[(u32, u32)], bodies: &[SolverBody]) -> (Coloring, Vec<u32>) {
    let n = pairs.len();
    // The first level each body is free in.
    let mut free = vec![0usize; bodies.len()];
    let mut level_of = Vec::with_capacity(n);
    for &(a, b) in pairs {
        let movers = [a, b].map(|i| bodies[i as usize].dynamic.then_some(i as usize));
        let level = movers.iter().flatten().map(|&i| free[i]).max().unwrap_or(0);
        for &i in movers.iter().flatten() {
            free[i] = level + 1;
        }
        level_of.push(level);
    }
    // Every level up to the highest holds a patch: a patch of level l > 0
    // follows one of level l - 1 on the same body.
    let levels = level_of.iter().max().map_or(0, |&l| l + 1);
    if n == 0 || n < MIN_PATCHES_PER_LEVEL * levels {
        return serial_batch(n);
    }
    let (start, order) = sorted_by_label(&level_of, levels);
    let colors = (0..levels).map(|l| start[l]..start[l + 1]).collect();
    let coloring = Coloring {
        colors,
        overflow: n..n,
        levels: true,
    };
    (coloring, order)
}

/// Indices `0..labels.len()` sorted by their label (`< count`), stably (a
/// counting sort), and where each label's run starts (`count + 1` entries).
fn sorted_by_label(labels: &[usize], count: usize) -> (Vec<usize>, Vec<u32>) {
    let mut start = vec![0usize; count + 1];
    for &l in labels {
        start[l + 1] += 1;
    }
    for l in 0..count {
        start[l + 1] += start[l];
    }
    let mut next = start.clone();
    let mut order = vec![0u32; labels.len()];
    for (k, &l) in labels.iter().enumerate() {
        order[next[l]] = k as u32;
        next[l] += 1;
    }
    (start, order)
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
    use tumble_testkit::RandomSource;

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
        assert_eq!(color_joints(&pairs, &b), (coloring.clone(), order.clone()));
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

    /// A small problem's levels: every patch once; no dynamic body twice
    /// in a level; two patches on one dynamic body in patch order; each
    /// level in patch order.
    #[test]
    fn small_problems_run_in_levels_that_keep_each_bodys_patch_order() {
        let n = 40;
        let b = bodies(n);
        let mut rng = tumble_testkit::SplitMix64(777);
        let mut pairs = Vec::new();
        for _ in 0..100 {
            let i = 1 + rng.below(n - 1) as u32;
            let j = rng.below(n) as u32; // 0: the static body
            if i != j {
                pairs.push((i, j));
            }
        }
        assert!(pairs.len() < MIN_PATCHES_TO_COLOR);
        let (coloring, order) = color_patches(&pairs, &b);
        assert!(coloring.levels && coloring.overflow.is_empty() && coloring.colors.len() > 2);
        // Joints of a small problem stay one serial batch.
        assert_eq!(color_joints(&pairs, &b), serial_batch(pairs.len()));
        let mut seen = order.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..pairs.len() as u32).collect::<Vec<_>>());
        assert_eq!(
            coloring.colors.iter().map(|r| r.len()).sum::<usize>(),
            pairs.len()
        );
        let mut place = vec![0usize; pairs.len()];
        for (at, &k) in order.iter().enumerate() {
            place[k as usize] = at;
        }
        for r in &coloring.colors {
            let level = &order[r.clone()];
            assert!(
                level.windows(2).all(|w| w[0] < w[1]),
                "patch order within a level"
            );
            let mut used = std::collections::BTreeSet::new();
            for &k in level {
                let (a, c) = pairs[k as usize];
                for body in [a, c].into_iter().filter(|&i| b[i as usize].dynamic) {
                    assert!(used.insert(body), "body {body} twice in one level");
                }
            }
        }
        for p in 0..pairs.len() {
            for q in p + 1..pairs.len() {
                let shares = |(a, c): (u32, u32), i: u32| b[i as usize].dynamic && (a == i || c == i);
                if [pairs[p].0, pairs[p].1].into_iter().any(|i| shares(pairs[q], i)) {
                    assert!(
                        place[p] < place[q],
                        "patches {p} and {q} share a body: order kept"
                    );
                }
            }
        }
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
