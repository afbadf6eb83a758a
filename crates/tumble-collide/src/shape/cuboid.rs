//! Box (cuboid) centred on the body origin and aligned with the body axes.
//!
//! Numbering, fixed because feature ids are built from it:
//! - vertex `i` has coordinate `+h` along axis `a` when bit `a` of `i` is set;
//! - face `2a` is the `+a` face, face `2a + 1` the `-a` face (a = x, y, z);
//! - corners of each face are listed counter-clockwise seen from outside.

use super::{check_positive, Aabb, Polytope, ShapeError};
use crate::contact::Feature;
use crate::math::{DMat3, DVec3};
use crate::pose::Pose;

/// Corners of each face, counter-clockwise seen from outside.
pub(crate) const BOX_FACES: [[usize; 4]; 6] = [
    [1, 3, 7, 5], // +x
    [0, 4, 6, 2], // -x
    [2, 6, 7, 3], // +y
    [0, 1, 5, 4], // -y
    [4, 5, 7, 6], // +z
    [0, 2, 3, 1], // -z
];

/// The 12 edges as (from, to) as the first face listing them traverses them,
/// with that face first and the other face second (derived from `BOX_FACES`,
/// checked by a test).
// Rows alike by nature: a literal table, not derived from `BOX_FACES` at run
// time, so `edge(e)` is a plain lookup in the SAT's edge loop; the test
// `tables_are_consistent` checks every row.
const BOX_EDGES: [([u32; 2], [u32; 2]); 12] = [
    ([1, 3], [0, 5]),
    ([3, 7], [0, 2]),
    ([7, 5], [0, 4]),
    ([5, 1], [0, 3]),
    ([0, 4], [1, 3]),
    ([4, 6], [1, 4]),
    ([6, 2], [1, 2]),
    ([2, 0], [1, 5]),
    ([6, 7], [2, 4]),
    ([3, 2], [2, 5]),
    ([0, 1], [3, 5]),
    ([5, 4], [3, 4]),
];

/// A box with `half_extents` (m) along the body x, y, z axes.
// As in sphere.rs and the other shapes; cannot be shared because it names
// `CuboidParts`, whose `try_from` re-runs `Cuboid::new` on the half extents.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(
    try_from = "super::serde_parts::CuboidParts",
    into = "super::serde_parts::CuboidParts"
)]
pub struct Cuboid {
    half_extents: DVec3,
}

impl Cuboid {
    /// A box; every half extent must be finite, > 0 and at most
    /// [`super::MAX_DIMENSION`] (m).
    pub fn new(half_extents: DVec3) -> Result<Cuboid, ShapeError> {
        check_positive("cuboid", "half_extents.x", half_extents.x)?;
        check_positive("cuboid", "half_extents.y", half_extents.y)?;
        check_positive("cuboid", "half_extents.z", half_extents.z)?;
        Ok(Cuboid { half_extents })
    }

    /// Half extents (m).
    pub fn half_extents(&self) -> DVec3 {
        self.half_extents
    }

    /// Vertex `i` (0..8), see the module docs for the numbering.
    pub fn corner(&self, i: usize) -> DVec3 {
        let h = self.half_extents;
        DVec3::new(
            if i & 1 != 0 { h.x } else { -h.x },
            if i & 2 != 0 { h.y } else { -h.y },
            if i & 4 != 0 { h.z } else { -h.z },
        )
    }

    /// Farthest point along `dir` (body frame); zero components pick `+h`.
    pub fn support(&self, dir: DVec3) -> DVec3 {
        self.corner(self.support_index(dir))
    }

    fn support_index(&self, dir: DVec3) -> usize {
        (dir.x >= 0.0) as usize | ((dir.y >= 0.0) as usize) << 1 | ((dir.z >= 0.0) as usize) << 2
    }

    /// World bounding box at `pose`: centre +- |R| h.
    pub fn aabb(&self, pose: &Pose) -> Aabb {
        let r = DMat3::from_quat(pose.rotation);
        let h = self.half_extents;
        let ext = r.x_axis.abs() * h.x + r.y_axis.abs() * h.y + r.z_axis.abs() * h.z;
        Aabb::from_center_half_extents(pose.position, ext)
    }
}

impl Polytope for Cuboid {
    fn closest_point(&self, p: DVec3) -> DVec3 {
        p.clamp(-self.half_extents, self.half_extents)
    }
    fn vertex_count(&self) -> usize {
        8
    }
    fn vertex(&self, i: usize) -> DVec3 {
        self.corner(i)
    }
    fn face_count(&self) -> usize {
        6
    }
    fn face_normal(&self, f: usize) -> DVec3 {
        let mut n = DVec3::ZERO;
        n[f / 2] = if f & 1 == 0 { 1.0 } else { -1.0 };
        n
    }
    fn face_offset(&self, f: usize) -> f64 {
        self.half_extents[f / 2]
    }
    fn face_len(&self, _f: usize) -> usize {
        4
    }
    fn face_vertex(&self, f: usize, k: usize) -> usize {
        BOX_FACES[f][k]
    }
    fn edge_count(&self) -> usize {
        12
    }
    fn edge(&self, e: usize) -> ([u32; 2], [u32; 2]) {
        BOX_EDGES[e]
    }
    fn interior_point(&self) -> DVec3 {
        DVec3::ZERO
    }
    fn vertex_feature(&self, v: usize) -> Feature {
        for (f, face) in BOX_FACES.iter().enumerate() {
            if let Some(k) = face.iter().position(|&c| c == v) {
                return Feature::vertex(f as u32, k as u8);
            }
        }
        Feature::vertex_edge_fallback(v)
    }
    fn support_vertex(&self, dir: DVec3) -> usize {
        self.support_index(dir)
    }
    fn best_face(&self, dir: DVec3) -> usize {
        let a = dir.abs();
        let axis = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        2 * axis + (dir[axis] < 0.0) as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_are_consistent() {
        let b = Cuboid::new(DVec3::new(1.0, 2.0, 3.0)).unwrap();
        for f in 0..6 {
            let n = b.face_normal(f);
            let c: Vec<DVec3> = (0..4).map(|k| b.vertex(b.face_vertex(f, k))).collect();
            // On the plane, and counter-clockwise around the outward normal.
            for p in &c {
                assert!((n.dot(*p) - b.face_offset(f)).abs() < 1e-15);
            }
            let area2 = (c[1] - c[0]).cross(c[2] - c[0]);
            assert!(area2.dot(n) > 0.0);
        }
        let mut keys: Vec<(u32, u32)> = (0..12)
            .map(|e| {
                let ([a, bb], _) = b.edge(e);
                (a.min(bb), a.max(bb))
            })
            .collect();
        keys.sort_unstable();
        keys.dedup();
        assert_eq!(keys.len(), 12, "edges must be distinct");
        for e in 0..12 {
            let ([a, bb], [f0, f1]) = b.edge(e);
            let on = |f: u32, v: u32| (0..4).any(|k| b.face_vertex(f as usize, k) == v as usize);
            assert!(on(f0, a) && on(f0, bb) && on(f1, a) && on(f1, bb));
            // f0 traverses a -> b.
            let k = (0..4)
                .find(|&k| b.face_vertex(f0 as usize, k) == a as usize)
                .unwrap();
            assert_eq!(b.face_vertex(f0 as usize, (k + 1) % 4), bb as usize);
        }
    }

    #[test]
    fn rejects_bad_extents() {
        assert!(Cuboid::new(DVec3::new(1.0, 0.0, 1.0)).is_err());
        assert!(Cuboid::new(DVec3::new(1.0, f64::NAN, 1.0)).is_err());
    }
}
