//! The f64 oriented bounding box (thesis 4.5): a centre, three orthonormal
//! axes and half extents along them. Used while fitting and as a query volume;
//! tree nodes store a compact f32 copy ([`super::Node`]).

use crate::math::{DMat3, DVec3};
use crate::pose::Pose;

/// Oriented box `{ center + axes * u : |u_k| <= half_extents_k }`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Obb {
    /// Centre (m).
    pub center: DVec3,
    /// Box axes as the orthonormal, right-handed columns of a rotation.
    pub axes: DMat3,
    /// Half extents along the three axes (m), non-negative.
    pub half_extents: DVec3,
}

impl Obb {
    /// The axis-aligned box `[min, max]` as an OBB.
    pub fn from_aabb(min: DVec3, max: DVec3) -> Obb {
        Obb {
            center: (min + max) * 0.5,
            axes: DMat3::IDENTITY,
            half_extents: ((max - min) * 0.5).abs(),
        }
    }

    /// Tight box with the given axes around `points`: the centre is the middle
    /// of the projected min/max along each axis. `None` for no points.
    pub fn fit_points(axes: DMat3, points: impl IntoIterator<Item = DVec3>) -> Option<Obb> {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for p in points {
            let u = axes.transpose() * p;
            lo = lo.min(u);
            hi = hi.max(u);
        }
        if !lo.is_finite() || !hi.is_finite() {
            return None;
        }
        Some(Obb {
            center: axes * ((lo + hi) * 0.5),
            axes,
            half_extents: (hi - lo) * 0.5,
        })
    }

    /// The eight corners.
    pub fn corners(&self) -> [DVec3; 8] {
        let mut out = [DVec3::ZERO; 8];
        for (i, c) in out.iter_mut().enumerate() {
            let s = DVec3::new(
                if i & 1 == 0 { -1.0 } else { 1.0 },
                if i & 2 == 0 { -1.0 } else { 1.0 },
                if i & 4 == 0 { -1.0 } else { 1.0 },
            );
            *c = self.center + self.axes * (s * self.half_extents);
        }
        out
    }

    /// `true` when `p` is inside the box grown by `tol` (m) along each axis.
    pub fn contains(&self, p: DVec3, tol: f64) -> bool {
        let u = self.axes.transpose() * (p - self.center);
        u.abs().cmple(self.half_extents + DVec3::splat(tol)).all()
    }

    /// The box moved by `pose` (body frame to world frame).
    pub fn transformed(&self, pose: &Pose) -> Obb {
        let r = DMat3::from_quat(pose.rotation);
        Obb {
            center: pose.transform_point(self.center),
            axes: r * self.axes,
            half_extents: self.half_extents,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::DQuat;

    #[test]
    fn fit_contains_points_and_touches_extremes() {
        let axes = DMat3::from_quat(DQuat::from_euler(glam::EulerRot::XYZ, 0.3, 0.7, -0.2));
        let pts = [DVec3::ZERO, DVec3::X, DVec3::new(0.3, 2.0, -1.0), DVec3::Z * 4.0];
        let b = Obb::fit_points(axes, pts).unwrap();
        for p in pts {
            assert!(b.contains(p, 1e-12));
        }
        // Tight: each face plane touches a point.
        for k in 0..3 {
            let a = axes.col(k);
            let hi = pts.iter().map(|p| a.dot(*p - b.center)).fold(f64::MIN, f64::max);
            assert!((hi - b.half_extents[k]).abs() < 1e-12);
        }
        assert!(Obb::fit_points(axes, []).is_none());
    }
}
