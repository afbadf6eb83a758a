//! The polyhedral view shared by [`super::Cuboid`] and [`super::ConvexHull`]:
//! vertices, polygonal faces (counter-clockwise seen from outside, with outward
//! unit normals and plane offsets) and edges with their two faces. The SAT,
//! clipping and GJK routines of the narrow phase are written against it.
//!
//! Feature ids (used in [`crate::Contact`] for warm starting), as for
//! triangle meshes: `Feature::face(f)` is face `f`; `Feature::vertex(f, k)` is
//! corner `k` of face `f`; `Feature::edge(f, k)` the edge from corner `k` to
//! corner `k + 1` of face `f`. A vertex or edge shared by several faces is
//! named through the first face (in face order) that has it, so the id does not
//! depend on the query.

use crate::contact::Feature;
use crate::math::{first_max, DVec3};

/// A convex polyhedron described in its body frame.
pub trait Polytope {
    /// Number of vertices.
    fn vertex_count(&self) -> usize;
    /// Vertex `i` (m, body frame).
    fn vertex(&self, i: usize) -> DVec3;
    /// Number of faces.
    fn face_count(&self) -> usize;
    /// Outward unit normal of face `f` (body frame).
    fn face_normal(&self, f: usize) -> DVec3;
    /// Plane offset of face `f`: `normal . x = offset` on the face (m).
    fn face_offset(&self, f: usize) -> f64;
    /// Number of corners of face `f` (at most [`super::MAX_FACE_VERTICES`]).
    fn face_len(&self, f: usize) -> usize;
    /// Vertex index of corner `k` of face `f` (counter-clockwise from outside).
    fn face_vertex(&self, f: usize, k: usize) -> usize;
    /// Number of edges.
    fn edge_count(&self) -> usize;
    /// Edge `e`: its end vertices and the two faces that meet there, the
    /// first being the face that traverses it from `v[0]` to `v[1]`.
    fn edge(&self, e: usize) -> ([u32; 2], [u32; 2]);
    /// A point strictly inside (used to orient edge-edge axes outward).
    fn interior_point(&self) -> DVec3;
    /// Feature id of vertex `v` (corner of its first face).
    fn vertex_feature(&self, v: usize) -> Feature;
    /// Feature id of the edge from vertex `a` to vertex `b` (either order).
    fn edge_feature(&self, a: usize, b: usize) -> Feature {
        for f in 0..self.face_count() {
            let n = self.face_len(f);
            for k in 0..n {
                let p = self.face_vertex(f, k);
                let q = self.face_vertex(f, (k + 1) % n);
                if (p == a && q == b) || (p == b && q == a) {
                    return Feature::edge(f as u32, k as u8);
                }
            }
        }
        Feature::vertex_edge_fallback(a)
    }

    /// Index of a vertex farthest along `dir` (body frame); ties go to the
    /// lowest index, so the answer is deterministic.
    fn support_vertex(&self, dir: DVec3) -> usize {
        first_max(self.vertex_count(), |i| self.vertex(i).dot(dir)).0
    }

    /// The face whose normal is most aligned with `dir` (body frame); ties
    /// go to the lowest index.
    fn best_face(&self, dir: DVec3) -> usize {
        first_max(self.face_count(), |f| self.face_normal(f).dot(dir)).0
    }

    /// The point of the solid nearest to `p` (body frame); `p` itself when
    /// inside. By GJK from the point; a box clamps instead.
    fn closest_point(&self, p: DVec3) -> DVec3 {
        use crate::narrow::gjk::{gjk_distance, PolytopeSupport, SegmentSupport};
        let solid = PolytopeSupport {
            poly: self,
            rot: crate::math::DMat3::IDENTITY,
            trans: DVec3::ZERO,
        };
        let scale = (0..self.face_count())
            .map(|f| self.face_offset(f).abs())
            .fold(0.0, f64::max);
        let g = gjk_distance(&SegmentSupport([p, p]), &solid, scale);
        if g.overlap {
            p
        } else {
            g.point_b
        }
    }
}

impl Feature {
    /// Used only if an edge lookup fails (cannot happen for valid polytopes):
    /// an id that cannot collide with a face-based id.
    pub(crate) fn vertex_edge_fallback(a: usize) -> Feature {
        Feature {
            index: u32::MAX - a as u32,
            sub: crate::contact::SubFeature::Whole,
        }
    }
}
