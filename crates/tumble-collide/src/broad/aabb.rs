//! Axis-aligned bounding boxes, the broad phase's bounding volume (thesis 4.7).
//!
//! Boxes are closed: two boxes that only touch (equal endpoints on some axis)
//! *do* overlap, and a zero-size box (a point, or a flat box) is valid. The
//! sweep-and-prune uses exactly this rule, so the broad phase never drops a pair
//! that a narrow phase with a zero margin could still report as touching.

use crate::math::DVec3;

/// Why a box was rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AabbError {
    /// A corner has a NaN or infinite component.
    #[error("AABB corners must be finite, got min {min:?}, max {max:?}")]
    NonFinite {
        /// The lower corner that was passed.
        min: DVec3,
        /// The upper corner that was passed.
        max: DVec3,
    },
    /// `min > max` on one axis.
    #[error("AABB is inverted on axis {axis}: min {min} > max {max} (expected min <= max)")]
    Inverted {
        /// The axis (0 = x, 1 = y, 2 = z).
        axis: usize,
        /// Lower bound found on that axis (m).
        min: f64,
        /// Upper bound found on that axis (m).
        max: f64,
    },
    /// An inflation margin that is NaN or infinite.
    #[error("AABB margin must be finite, got {0}")]
    NonFiniteMargin(f64),
    /// [`Aabb::from_points`] was given no points.
    #[error("cannot bound an empty point set")]
    NoPoints,
}

/// A validated axis-aligned box: finite corners with `min <= max` on each axis.
///
/// `-0.0` is stored as `+0.0` so that sorting endpoints by value never separates
/// two boxes that touch at zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    min: DVec3,
    max: DVec3,
}

impl Aabb {
    /// The box `[min, max]` (m); an error if a component is not finite or `min > max`.
    pub fn new(min: DVec3, max: DVec3) -> Result<Aabb, AabbError> {
        if !min.is_finite() || !max.is_finite() {
            return Err(AabbError::NonFinite { min, max });
        }
        for axis in 0..3 {
            if min[axis] > max[axis] {
                return Err(AabbError::Inverted {
                    axis,
                    min: min[axis],
                    max: max[axis],
                });
            }
        }
        // Adding +0.0 maps -0.0 to +0.0 and leaves every other value unchanged.
        Ok(Aabb {
            min: min + DVec3::ZERO,
            max: max + DVec3::ZERO,
        })
    }

    /// The box centred at `center` with the given half extents (m, each >= 0).
    pub fn from_center_half_extents(center: DVec3, half: DVec3) -> Result<Aabb, AabbError> {
        Aabb::new(center - half, center + half)
    }

    /// The zero-size box at `p`.
    pub fn from_point(p: DVec3) -> Result<Aabb, AabbError> {
        Aabb::new(p, p)
    }

    /// The smallest box containing all `points`; an error if there are none or one
    /// is not finite.
    pub fn from_points(points: &[DVec3]) -> Result<Aabb, AabbError> {
        let first = *points.first().ok_or(AabbError::NoPoints)?;
        let (min, max) = points
            .iter()
            .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        // min/max of glam ignore NaN in one operand, so check every point.
        if let Some(&bad) = points.iter().find(|p| !p.is_finite()) {
            return Err(AabbError::NonFinite { min: bad, max: bad });
        }
        Aabb::new(min, max)
    }

    /// Lower corner (m).
    #[inline]
    pub fn min(&self) -> DVec3 {
        self.min
    }

    /// Upper corner (m).
    #[inline]
    pub fn max(&self) -> DVec3 {
        self.max
    }

    /// Centre (m).
    pub fn center(&self) -> DVec3 {
        0.5 * (self.min + self.max)
    }

    /// Edge lengths `max - min` (m, each >= 0).
    pub fn size(&self) -> DVec3 {
        self.max - self.min
    }

    /// `true` when the closed boxes share at least one point (touching counts).
    #[inline]
    pub fn overlaps(&self, other: &Aabb) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    /// [`Self::overlaps`] without a branch (for filters whose outcome a
    /// branch predictor cannot guess).
    #[inline]
    pub(crate) fn overlaps_branchless(&self, other: &Aabb) -> bool {
        (self.min.cmple(other.max) & other.min.cmple(self.max)).all()
    }

    /// `true` when `other` lies in the closed box.
    pub fn contains(&self, other: &Aabb) -> bool {
        self.min.cmple(other.min).all() && other.max.cmple(self.max).all()
    }

    /// `true` when `p` lies in the closed box.
    pub fn contains_point(&self, p: DVec3) -> bool {
        self.min.cmple(p).all() && p.cmple(self.max).all()
    }

    /// The smallest box containing both boxes.
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// The box grown by `margin` (m) on every side. A negative margin shrinks it;
    /// an error if the margin is not finite, the result would be inverted, or it
    /// overflows to infinity.
    pub fn inflate(&self, margin: f64) -> Result<Aabb, AabbError> {
        if !margin.is_finite() {
            return Err(AabbError::NonFiniteMargin(margin));
        }
        let m = DVec3::splat(margin);
        Aabb::new(self.min - m, self.max + m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn b(min: [f64; 3], max: [f64; 3]) -> Aabb {
        Aabb::new(DVec3::from(min), DVec3::from(max)).unwrap()
    }

    #[test]
    fn rejects_nan_inf_and_inverted() {
        let nan = DVec3::new(0.0, f64::NAN, 0.0);
        assert!(matches!(
            Aabb::new(nan, DVec3::ONE),
            Err(AabbError::NonFinite { .. })
        ));
        let inf = DVec3::new(0.0, 0.0, f64::INFINITY);
        assert!(matches!(
            Aabb::new(DVec3::ZERO, inf),
            Err(AabbError::NonFinite { .. })
        ));
        assert_eq!(
            Aabb::new(DVec3::new(0.0, 2.0, 0.0), DVec3::ONE),
            Err(AabbError::Inverted {
                axis: 1,
                min: 2.0,
                max: 1.0
            })
        );
        assert_eq!(Aabb::from_points(&[]), Err(AabbError::NoPoints));
        assert!(Aabb::from_points(&[DVec3::ZERO, nan]).is_err());
        assert!(matches!(
            b([0.0; 3], [1.0; 3]).inflate(f64::NAN),
            Err(AabbError::NonFiniteMargin(_))
        ));
        assert!(matches!(
            b([0.0; 3], [1.0; 3]).inflate(-0.6),
            Err(AabbError::Inverted { .. })
        ));
        assert!(matches!(
            b([0.0; 3], [1e308; 3]).inflate(1e308),
            Err(AabbError::NonFinite { .. })
        ));
    }

    #[test]
    fn touching_and_degenerate_boxes_overlap() {
        let a = b([0.0; 3], [1.0; 3]);
        let touching = b([1.0, 0.5, 0.5], [2.0, 2.0, 2.0]);
        let apart = b([1.0 + 1e-12, 0.0, 0.0], [2.0, 1.0, 1.0]);
        let corner_point = Aabb::from_point(DVec3::ONE).unwrap();
        assert!(a.overlaps(&touching) && touching.overlaps(&a));
        assert!(!a.overlaps(&apart) && !apart.overlaps(&a));
        assert!(a.overlaps(&corner_point) && corner_point.overlaps(&corner_point));
        // -0.0 and +0.0 are the same coordinate.
        let neg = b([-1.0, -1.0, -1.0], [-0.0, -0.0, -0.0]);
        assert_eq!(neg.max().x.to_bits(), 0.0f64.to_bits());
        assert!(neg.overlaps(&a));
    }

    #[test]
    fn union_contains_both_and_inflate_grows_every_side() {
        let a = b([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]);
        let c = b([-2.0, 0.5, 3.0], [-1.0, 4.0, 5.0]);
        let u = a.union(&c);
        for p in [a.min(), a.max(), c.min(), c.max()] {
            assert!(u.contains_point(p));
        }
        assert_eq!(u, b([-2.0, 0.0, 0.0], [1.0, 4.0, 5.0]));
        let g = a.inflate(0.25).unwrap();
        assert_eq!(g.size(), DVec3::splat(1.5));
        assert_eq!(g.center(), a.center());
        let pts = [DVec3::new(1.0, -1.0, 2.0), DVec3::new(-3.0, 4.0, 0.0)];
        assert_eq!(
            Aabb::from_points(&pts).unwrap(),
            b([-3.0, -1.0, 0.0], [1.0, 4.0, 2.0])
        );
    }
}
