//! Contacts that roll and turn within a step (see `passes::begin_patch`):
//! a round side's contact follows its centre of curvature (`Rolling`: a
//! ball touches straight below its centre, not with a material point),
//! and a curved patch's friction plane turns with its normal
//! (`turn_friction_plane`). Used by the scalar kernels and, operation for
//! operation, by the wide lanes (`wide::begin`).

use super::constraint::{tangent_basis, ManifoldConstraint};
use tumble_collide::{DMat3, DVec3};

/// Turns a curved patch's friction plane to the normal `n`: its normal, and
/// its step-start directions by the smallest rotation taking the step-start
/// normal `a` to `n` (for `v` normal to `a`:
/// `v - (v . n) / (1 + a . n) (a + n)`, exactly unit and normal to `n`), so
/// that the friction impulses accumulated along them turn with the surface.
pub(super) fn turn_friction_plane(m: &mut ManifoldConstraint, n: DVec3) {
    let a = m.normal_start;
    let along = a + n;
    let denominator = 1.0 + a.dot(n);
    m.normal = n;
    // The step start's directions are `tangent_basis` of its normal, as
    // `ManifoldConstraint::new` made them.
    for (direction, v) in m.directions.iter_mut().zip(tangent_basis(a)) {
        *direction = v - along * (v.dot(n) / denominator);
    }
}

/// The round sides of a patch (`ManifoldConstraint::rolling`), for
/// `passes::begin_patch`: `None` when neither side is round.
#[derive(Debug, Clone, Copy)]
pub(super) struct Rolling {
    radius: [f64; 2],
    /// Weight of A's anchor in the shared point: 1 when only A is round, 0
    /// when only B is, 1/2 for two round sides (two balls touch on the line
    /// of their centres, where both anchors are).
    share_a: f64,
}

impl Rolling {
    #[inline(always)]
    pub(super) fn of(radius: [f64; 2]) -> Option<Rolling> {
        let share_a = match (radius[0] > 0.0, radius[1] > 0.0) {
            (false, false) => return None,
            (true, false) => 1.0,
            (false, true) => 0.0,
            (true, true) => 0.5,
        };
        Some(Rolling { radius, share_a })
    }

    /// How far a point's centres of curvature lie from it along the normal
    /// (m): a round side's radius plus half the gap (`half_gap`, the contact
    /// point lies midway across it), 0 for a side that is not round.
    #[inline(always)]
    pub(super) fn reach(&self, half_gap: f64) -> [f64; 2] {
        let side = |r: f64| if r > 0.0 { r + half_gap } else { 0.0 };
        [side(self.radius[0]), side(self.radius[1])]
    }

    /// The anchors of a point (step-start lever arms `ra0`, `rb0`, normal
    /// `n` from B to A, centres of curvature `reach` away along it) for
    /// bodies turned by `ta`, `tb` since the step start, relative to their
    /// current centres: a round side's anchor is its centre of curvature
    /// (`ra0 + reach n` on A, `rb0 - reach n` on B, carried by the body)
    /// offset back along the normal. (Without the half gap, the pivot of a
    /// ball a gap g above the ground sits g / 2 off its centre, and as the
    /// ball turns by w the anchor rises by g w^2 / 4: a gap that is not
    /// there, closed by sinking and pushed back out, a little energy per
    /// step.)
    #[inline(always)]
    pub(super) fn anchors(
        &self,
        ta: DMat3,
        tb: DMat3,
        ra0: DVec3,
        rb0: DVec3,
        n: DVec3,
        reach: [f64; 2],
    ) -> (DVec3, DVec3) {
        let (ca, cb) = (n * reach[0], n * -reach[1]);
        (ta * (ra0 + ca) - ca, tb * (rb0 + cb) - cb)
    }

    /// The anchors where the round sides touch now: the [`anchors`](Rolling::anchors)
    /// (found with the step-start normal `n0`) moved to `reach` from their
    /// centres of curvature along the current normal `n` (on a curved patch
    /// the normal turns within the step; a ball touches straight below its
    /// centre along it, and a lever arm left along `n0` would turn its spin
    /// into a normal velocity).
    #[inline(always)]
    pub(super) fn touching(
        &self,
        ra: DVec3,
        rb: DVec3,
        n0: DVec3,
        n: DVec3,
        reach: [f64; 2],
    ) -> (DVec3, DVec3) {
        if n == n0 {
            return (ra, rb);
        }
        let turned = n0 - n;
        (ra + turned * reach[0], rb - turned * reach[1])
    }

    /// The radii and A's share of the shared point (the wide kernels' lanes).
    pub(super) fn parts(&self) -> ([f64; 2], f64) {
        (self.radius, self.share_a)
    }

    /// `passes::shared_lever_arms` with the shared point weighted by `share_a`.
    #[inline(always)]
    pub(super) fn shared_lever_arms(
        &self,
        ra0: DVec3,
        rb0: DVec3,
        ra: DVec3,
        rb: DVec3,
        dpa: DVec3,
        dpb: DVec3,
    ) -> (DVec3, DVec3) {
        let ab = ra0 - rb0 + dpb - dpa;
        let shared = ra * self.share_a + (rb + ab) * (1.0 - self.share_a);
        (shared, shared - ab)
    }
}
