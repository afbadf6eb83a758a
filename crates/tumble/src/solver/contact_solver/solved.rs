//! What the rest of the step reads of the solve's patch records, kept
//! compact: per record its friction impulses, the sum of its normal
//! impulses, its bodies and whether it stuck (56 bytes, where a record is
//! about 1 KB), per point its normal impulse and whether it pressed. The
//! warm-start cache, the reported contacts and the contact events read
//! these in patch order, which is the records' colour order shuffled: read
//! from the records themselves, each was a miss from memory.
//!
//! The team writes them at the end of the solve (`SolverArrays::unpack`),
//! each record's by the thread that solved it, while the record is still in
//! that core's cache: a bundle's patches from its lanes (their records are
//! not written back), the others from their records. The exact solver's
//! serial path gathers them after its sub-steps ([`SolvedPatches::gather`]).
//! Both go through [`SolvedPatch::from_parts`] and [`SolvedPoint::new`].

use super::coloring::Shared;
use super::constraint::{ManifoldConstraint, PointConstraint};
use tumble_collide::DVec3;

/// A patch sticks while its friction impulse stays within this fraction of
/// the Coulomb disc's radius (`mu` times its normal impulse).
pub const STICKING: f64 = 0.95;

/// What the write-back reads of a patch's solver record.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SolvedPatch {
    /// The tangential friction impulse as a world vector (N s).
    pub tangent: DVec3,
    /// The twist friction impulse (N m s).
    pub twist: f64,
    /// The sum of the points' normal impulses (N s).
    pub total: f64,
    /// The first of the patch's points in [`SolvedPatches`]'s points (the
    /// records' layout).
    pub first: u32,
    /// Solver bodies A and B.
    pub bodies: [u32; 2],
    /// The friction impulse stayed within [`STICKING`] of the Coulomb disc
    /// while the patch pressed.
    pub sticks: bool,
}

impl SolvedPatch {
    /// The solved parts of record `m` with its points.
    pub fn of(m: &ManifoldConstraint, points: &[PointConstraint]) -> SolvedPatch {
        SolvedPatch::from_parts(
            [m.directions[0], m.directions[1]],
            m.impulses,
            m.friction,
            m.first_point,
            [m.a, m.b],
            points.iter().map(|c| c.normal_impulse),
        )
    }

    /// The solved parts of a patch given by its friction directions, its
    /// friction impulses (two tangent, one twist), its friction
    /// coefficient, its first point, its bodies and its points' normal
    /// impulses in order: what a record holds ([`SolvedPatch::of`]) or a
    /// bundle's lane (`WidePatch::unpack`), the same bits from either.
    pub fn from_parts(
        directions: [DVec3; 2],
        impulses: [f64; 3],
        friction: f64,
        first: u32,
        bodies: [u32; 2],
        normal_impulses: impl Iterator<Item = f64>,
    ) -> SolvedPatch {
        let total: f64 = normal_impulses.sum();
        let used = impulses[0].hypot(impulses[1]);
        SolvedPatch {
            tangent: ManifoldConstraint::tangent_along(directions, [impulses[0], impulses[1]]),
            twist: impulses[2],
            total,
            first,
            bodies,
            sticks: total > 0.0 && used < STICKING * friction * total,
        }
    }
}

/// What the write-back and the events read of a solver point.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SolvedPoint {
    /// Its normal impulse at the end of the solve (N s, per sub-step).
    pub normal_impulse: f64,
    /// It carried a normal impulse at some moment of the step (it touched).
    pub pressed: bool,
}

impl SolvedPoint {
    /// The solved parts of point `p`.
    pub fn of(p: &PointConstraint) -> SolvedPoint {
        SolvedPoint::new(p.normal_impulse, p.max_normal_impulse)
    }

    /// A point whose normal impulse is `normal_impulse` at the end of the
    /// solve and whose largest in the step was `max_normal_impulse`.
    pub fn new(normal_impulse: f64, max_normal_impulse: f64) -> SolvedPoint {
        SolvedPoint {
            normal_impulse,
            pressed: max_normal_impulse > 0.0,
        }
    }
}

/// The solved patches and points, in the records' order (a patch per
/// solver patch record, a point per solver point). Scratch kept from step
/// to step.
#[derive(Debug, Default, PartialEq)]
pub struct SolvedPatches {
    patches: Vec<SolvedPatch>,
    points: Vec<SolvedPoint>,
}

impl SolvedPatches {
    /// The solved record of the patch at `position` in the solver's order.
    pub fn patch(&self, position: u32) -> &SolvedPatch {
        &self.patches[position as usize]
    }

    /// The `count` points of patch `s`.
    pub fn points_of(&self, s: &SolvedPatch, count: u32) -> &[SolvedPoint] {
        &self.points[s.first as usize..][..count as usize]
    }

    /// Room for `patches` records and `points` points, to be written by a
    /// team (`SolvedPatches::writer`); kept from the last step and only
    /// cut or grown.
    pub fn resize(&mut self, patches: usize, points: usize) {
        self.patches.resize(patches, SolvedPatch::default());
        self.points.resize(points, SolvedPoint::default());
    }

    /// Every record's solved parts, in order, on this thread.
    pub fn gather(&mut self, manifolds: &[ManifoldConstraint], points: &[PointConstraint]) {
        self.resize(manifolds.len(), points.len());
        for (m, out) in manifolds.iter().zip(&mut self.patches) {
            *out = solved_record(m, &points[m.range()], &mut self.points[m.range()]);
        }
    }

    /// The arrays as a team writes them, each record by one thread.
    pub(crate) fn writer(&mut self) -> SolvedWriter<'_> {
        SolvedWriter {
            patches: Shared::new(&mut self.patches),
            points: Shared::new(&mut self.points),
        }
    }
}

/// [`SolvedPatches`] shared by a team (`SolverArrays::solved`).
pub(crate) struct SolvedWriter<'a> {
    patches: Shared<'a, SolvedPatch>,
    points: Shared<'a, SolvedPoint>,
}

impl SolvedWriter<'_> {
    /// Writes record `k`'s solved parts.
    ///
    /// # Safety
    /// No other thread writes record `k`, and none writes `m` or its points
    /// meanwhile.
    pub(super) unsafe fn write(&self, k: usize, m: &ManifoldConstraint, points: &[PointConstraint]) {
        // SAFETY: the caller's promise.
        unsafe { *self.patches.get_mut(k) = solved_record(m, points, self.points.range_mut(m.range())) };
    }

    /// Writes record `k`'s solved parts as `patch` and `points` (its
    /// points, from `patch.first` on).
    ///
    /// # Safety
    /// No other thread writes record `k` or its points meanwhile.
    pub(super) unsafe fn put(&self, k: usize, patch: SolvedPatch, points: &[SolvedPoint]) {
        let first = patch.first as usize;
        // SAFETY: the caller's promise; each record owns its run of points.
        unsafe {
            self.points
                .range_mut(first..first + points.len())
                .copy_from_slice(points);
            *self.patches.get_mut(k) = patch;
        }
    }
}

/// Record `m`'s solved parts, those of its `points` written to `out`.
fn solved_record(m: &ManifoldConstraint, points: &[PointConstraint], out: &mut [SolvedPoint]) -> SolvedPatch {
    for (p, out) in points.iter().zip(out) {
        *out = SolvedPoint::of(p);
    }
    SolvedPatch::of(m, points)
}
