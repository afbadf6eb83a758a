//! The memory-compact tree node: an f32 oriented box (44 bytes in all) whose
//! half extents are rounded outward so that the stored box provably contains
//! every vertex it bounds (thesis 5.4.2 on memory; PQP's `BV`, which spends
//! 9 floats on a rotation matrix where a quaternion needs 4).
//!
//! Conservative rounding: the orientation (a quaternion) and the centre are
//! first rounded to f32; the axes used everywhere are the f64 rotation matrix
//! of the stored quaternion normalised in f64, so they are orthonormal to f64
//! precision. The half extents are then recomputed in f64 from the *rounded*
//! centre and axes, padded by a relative `AXIS_PAD` (f64 round-off of the box
//! tests, which also see the centre's magnitude) and rounded up to the next
//! f32. Checking `|a_k . (v - c)| <= h_k` in f64 with the stored values
//! therefore holds for every vertex with no further tolerance.

use super::obb::Obb;
use crate::math::{DMat3, DQuat, DVec3};

/// Relative pad on the half extents, as a fraction of `|h| + |c|` (half
/// diagonal plus distance of the centre from the mesh origin): covers the f64
/// round-off of the relative frames computed during traversal.
pub const AXIS_PAD: f64 = 1e-9;

/// Bit marking a leaf in [`Node::link`].
const LEAF_BIT: u32 = 1 << 31;
/// Largest triangle count in one leaf (3 bits).
pub const MAX_LEAF_SIZE: usize = 7;
/// Largest triangle index range a leaf can address (28 bits).
pub const MAX_TRIANGLES: usize = 1 << 28;

/// One node of the OBBTree.
///
/// `link` packs the children or the leaf's triangles: for an internal node the
/// index of the first child (the second is the next node); for a leaf the top
/// bit is set, bits 28..31 hold the triangle count and bits 0..28 the start in
/// the tree's triangle index array.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[repr(C)]
pub struct Node {
    /// Box orientation in the mesh frame, quaternion (x, y, z, w); the box
    /// axes are the columns of its rotation matrix (normalised in f64).
    pub rot: [f32; 4],
    /// Box centre in the mesh frame (m).
    pub center: [f32; 3],
    /// Half extents along the axes (m), rounded outward.
    pub half: [f32; 3],
    /// Children or leaf triangle range, see the type docs.
    pub link: u32,
}

/// Smallest f32 not below `x` (for x >= 0).
fn round_up(x: f64) -> f32 {
    let y = x as f32;
    if (y as f64) < x {
        f32::from_bits(y.to_bits() + 1)
    } else {
        y
    }
}

impl Node {
    /// A node with the orientation and centre of `obb` (rounded to f32) and
    /// half extents recomputed so that every point of `points` is inside.
    pub fn conservative(obb: &Obb, points: impl Iterator<Item = DVec3> + Clone) -> Node {
        let q = DQuat::from_mat3(&obb.axes).normalize();
        let rot = q.to_array().map(|x| x as f32);
        let center = obb.center.to_array().map(|x| x as f32);
        let mut node = Node {
            rot,
            center,
            half: [0.0; 3],
            link: 0,
        };
        let (a, c) = (node.axes_f64(), node.center_f64());
        let mut h = DVec3::ZERO;
        for p in points {
            h = h.max((a.transpose() * (p - c)).abs());
        }
        let pad = AXIS_PAD * (h.length() + c.length());
        node.half = (h + DVec3::splat(pad)).to_array().map(round_up);
        node
    }

    /// The orientation as a unit f64 quaternion.
    ///
    /// The stored f32 quaternion has `|q|^2 = 1 + e` with `|e| < 1e-6`; one
    /// Newton step for `1 / sqrt(s)` from 1, `(3 - s) / 2`, normalises it to
    /// `O(e^2) < 1e-12` without a square root or division (this runs for every
    /// box test), and the result is deterministic, so build-time containment
    /// and traversal see the very same axes.
    #[inline]
    pub fn quat_f64(&self) -> DQuat {
        let [x, y, z, w] = self.rot.map(|v| v as f64);
        let s = x * x + y * y + z * z + w * w;
        let k = 1.5 - 0.5 * s;
        DQuat::from_xyzw(x * k, y * k, z * k, w * k)
    }

    /// The axes as an f64 rotation matrix (columns).
    #[inline]
    pub fn axes_f64(&self) -> DMat3 {
        DMat3::from_quat(self.quat_f64())
    }

    /// The centre in f64 (m).
    #[inline]
    pub fn center_f64(&self) -> DVec3 {
        DVec3::new(
            self.center[0] as f64,
            self.center[1] as f64,
            self.center[2] as f64,
        )
    }

    /// Half extents in f64 (m).
    #[inline]
    pub fn half_f64(&self) -> [f64; 3] {
        [self.half[0] as f64, self.half[1] as f64, self.half[2] as f64]
    }

    /// The box as an f64 [`Obb`].
    pub fn obb(&self) -> Obb {
        Obb {
            center: self.center_f64(),
            axes: self.axes_f64(),
            half_extents: DVec3::from_array(self.half_f64()),
        }
    }

    /// `true` when `p` satisfies `|a_k . (p - c)| <= h_k` for the stored f32
    /// values, evaluated in f64 (the containment the rounding guarantees).
    pub fn contains(&self, p: DVec3) -> bool {
        let u = self.axes_f64().transpose() * (p - self.center_f64());
        u.abs().cmple(DVec3::from_array(self.half_f64())).all()
    }

    /// `true` for a leaf.
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.link & LEAF_BIT != 0
    }

    /// Index of the first child (internal nodes; the second is `+ 1`).
    #[inline]
    pub fn first_child(&self) -> u32 {
        self.link
    }

    /// `(start, count)` of a leaf's triangles in the tree's index array.
    #[inline]
    pub fn leaf_range(&self) -> (u32, u32) {
        (self.link & (MAX_TRIANGLES as u32 - 1), (self.link >> 28) & 7)
    }

    /// Packs a leaf link (`count <= MAX_LEAF_SIZE`, `start < MAX_TRIANGLES`).
    pub(crate) fn leaf_link(start: usize, count: usize) -> u32 {
        debug_assert!(count <= MAX_LEAF_SIZE && start < MAX_TRIANGLES);
        LEAF_BIT | ((count as u32) << 28) | start as u32
    }

    /// Size used to decide which node of a pair to descend: squared half diagonal.
    #[inline]
    pub fn size(&self) -> f32 {
        self.half[0] * self.half[0] + self.half[1] * self.half[1] + self.half[2] * self.half[2]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_is_44_bytes() {
        assert_eq!(std::mem::size_of::<Node>(), 44);
    }

    #[test]
    fn link_round_trips() {
        let mut n = Node {
            link: Node::leaf_link(MAX_TRIANGLES - 1, 7),
            ..Node::default()
        };
        assert!(n.is_leaf());
        assert_eq!(n.leaf_range(), (MAX_TRIANGLES as u32 - 1, 7));
        n.link = 12345;
        assert!(!n.is_leaf());
        assert_eq!(n.first_child(), 12345);
    }

    #[test]
    fn rounding_keeps_far_points_inside() {
        // Far from the origin, f32 rounding of the centre alone moves it by
        // ~1e-3 m: the recomputed extents must absorb that.
        let axes = DMat3::from_quat(DQuat::from_euler(glam::EulerRot::XYZ, 0.1, 0.2, 0.3));
        let off = DVec3::new(12345.678, -9876.54321, 3333.3333);
        let pts: Vec<DVec3> = (0..50)
            .map(|i| off + DVec3::new((i as f64 * 0.37).sin(), (i as f64 * 0.11).cos(), i as f64 * 0.01))
            .collect();
        let obb = Obb::fit_points(axes, pts.iter().copied()).unwrap();
        let node = Node::conservative(&obb, pts.iter().copied());
        assert!(pts.iter().all(|&p| node.contains(p)));
    }
}
