//! Primitive shapes as query partners of a mesh: which [`Shape`]s are
//! primitives (sphere, cuboid, capsule, half-space) and the exact
//! primitive-triangle tests the primitive queries end in (Ericson,
//! Real-Time Collision Detection: 5.1.5 closest point on a triangle for the
//! sphere, 5.1.9 for the capsule's core segment, 5.2.9 / Akenine-Moller 2001
//! for the box, and vertex heights for the half-space).
//!
//! Primitives are solids, meshes are surfaces: a triangle intersects a
//! sphere when it has a point inside the closed ball, whereas a ball entirely
//! inside a closed mesh touches no triangle.

use super::error::QueryError;
use crate::bvh::query::box_height_above;
use crate::bvh::sat::{obb_distance_lower_bound, RelFrame};
use crate::bvh::{Node, Obb};
use crate::math::{DMat3, DVec3};
use crate::pose::Pose;
use crate::shape::{Polytope, Shape};
use crate::triangle::{closest_point_on_triangle, tri_box_overlap, triangle_distance};

/// A primitive placed in one frame (the world, or a mesh's own frame).
// One per query, on the stack: the box's face triangles inline cost nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy)]
pub(crate) enum Placed {
    /// Centre and radius.
    Ball { c: DVec3, r: f64 },
    /// Core segment `p q` and radius.
    Capsule { p: DVec3, q: DVec3, r: f64, obb: Obb },
    /// The box, and its 12 face triangles for distances.
    Box { obb: Obb, faces: [[DVec3; 3]; 12] },
    /// The solid `n . x <= d`.
    Plane { n: DVec3, d: f64 },
}

/// Distance of a primitive to one triangle, with the closest points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PrimDistance {
    /// Distance (m), 0 when they intersect.
    pub distance: f64,
    /// Closest point on the primitive (a common point when intersecting).
    pub on_primitive: DVec3,
    /// Closest point on the triangle.
    pub on_triangle: DVec3,
}

impl PrimDistance {
    fn touching(p: DVec3) -> PrimDistance {
        PrimDistance {
            distance: 0.0,
            on_primitive: p,
            on_triangle: p,
        }
    }
}

impl Placed {
    /// `prim` placed by `pose`; [`QueryError::NotPrimitive`] (naming
    /// `query`) for a convex hull or a mesh.
    pub(crate) fn new(prim: &Shape, pose: &Pose, query: &'static str) -> Result<Placed, QueryError> {
        let axes = DMat3::from_quat(pose.rotation);
        Ok(match prim {
            Shape::Sphere(s) => Placed::Ball {
                c: pose.position,
                r: s.radius(),
            },
            Shape::Capsule(c) => {
                let [p, q] = c.world_segment(pose);
                let r = c.radius();
                Placed::Capsule {
                    p,
                    q,
                    r,
                    obb: Obb {
                        center: pose.position,
                        axes,
                        half_extents: DVec3::new(r, r, c.half_height() + r),
                    },
                }
            }
            Shape::Cuboid(b) => {
                let mut faces = [[DVec3::ZERO; 3]; 12];
                let mut k = 0;
                for f in 0..b.face_count() {
                    let corner = |i: usize| pose.transform_point(b.vertex(b.face_vertex(f, i)));
                    for i in 1..b.face_len(f) - 1 {
                        faces[k] = [corner(0), corner(i), corner(i + 1)];
                        k += 1;
                    }
                }
                Placed::Box {
                    obb: Obb {
                        center: pose.position,
                        axes,
                        half_extents: b.half_extents(),
                    },
                    faces,
                }
            }
            Shape::HalfSpace(h) => {
                let (n, d) = h.world_plane(pose);
                Placed::Plane { n, d }
            }
            Shape::ConvexHull(_) | Shape::Mesh(_) => {
                return Err(QueryError::NotPrimitive {
                    query,
                    kind: prim.kind_name(),
                })
            }
        })
    }

    /// Distance to the closed triangle `t` (same frame), 0 when they share a
    /// point.
    pub(crate) fn distance(&self, t: &[DVec3; 3]) -> PrimDistance {
        match *self {
            Placed::Ball { c, r } => {
                let (q, _) = closest_point_on_triangle(c, t);
                let d = (c - q).length();
                if d <= r {
                    PrimDistance::touching(q)
                } else {
                    PrimDistance {
                        distance: d - r,
                        on_primitive: c + (q - c) * (r / d),
                        on_triangle: q,
                    }
                }
            }
            Placed::Capsule { p, q, r, .. } => {
                // The core segment as a zero-area triangle (handled exactly).
                let td = triangle_distance(&[p, q, q], t);
                if td.distance <= r {
                    PrimDistance::touching(td.point_b)
                } else {
                    PrimDistance {
                        distance: td.distance - r,
                        on_primitive: td.point_a + (td.point_b - td.point_a) * (r / td.distance),
                        on_triangle: td.point_b,
                    }
                }
            }
            Placed::Box { obb, ref faces } => {
                // Disjoint convex sets are closest at the box's surface.
                let mut best = triangle_distance(&faces[0], t);
                for f in &faces[1..] {
                    let td = triangle_distance(f, t);
                    if td.distance < best.distance {
                        best = td;
                    }
                }
                if tri_box_overlap(t, obb.center, obb.half_extents, &obb.axes) {
                    // Crossing the surface, or wholly inside the box.
                    let p = if best.distance == 0.0 { best.point_b } else { t[0] };
                    PrimDistance::touching(p)
                } else {
                    PrimDistance {
                        distance: best.distance,
                        on_primitive: best.point_a,
                        on_triangle: best.point_b,
                    }
                }
            }
            Placed::Plane { n, d } => {
                let h = t.map(|v| n.dot(v) - d);
                let k = (0..3).fold(0, |k, i| if h[i] < h[k] { i } else { k });
                if h[k] <= 0.0 {
                    PrimDistance::touching(t[k])
                } else {
                    PrimDistance {
                        distance: h[k],
                        on_primitive: t[k] - n * h[k],
                        on_triangle: t[k],
                    }
                }
            }
        }
    }

    /// `true` when the closed triangle `t` shares a point with the solid;
    /// the same decision as `distance(t).distance == 0`.
    pub(crate) fn intersects(&self, t: &[DVec3; 3]) -> bool {
        match self {
            Placed::Box { obb, .. } => tri_box_overlap(t, obb.center, obb.half_extents, &obb.axes),
            _ => self.distance(t).distance == 0.0,
        }
    }

    /// A lower bound (m) on the distance from anything inside `node`'s
    /// stored box to the primitive; `self` must be placed in the mesh frame.
    pub(crate) fn node_lower_bound(&self, node: &Node) -> f64 {
        // Round-off guard: a bound a hair too low only costs a visit.
        const SHRINK: f64 = 1.0 - 1e-9;
        match self {
            Placed::Ball { c, r } => {
                let u = node.axes_f64().transpose() * (*c - node.center_f64());
                let e = (u.abs() - DVec3::from_array(node.half_f64())).max(DVec3::ZERO);
                ((e.length() - r) * SHRINK).max(0.0)
            }
            Placed::Capsule { obb, .. } | Placed::Box { obb, .. } => {
                // The capsule lies inside its box, so the box distance bounds it.
                let at = node.axes_f64().transpose();
                let f = RelFrame::new(&(at * obb.axes), at * (obb.center - node.center_f64()));
                (obb_distance_lower_bound(node.half_f64(), obb.half_extents.to_array(), &f) * SHRINK).max(0.0)
            }
            Placed::Plane { n, d } => (box_height_above(node, *n, *d) * SHRINK).max(0.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::traverse::tests::{random_pose, rng};
    use crate::shape::{Capsule, Cuboid, HalfSpace, Sphere};

    fn random_triangle(r: &mut impl FnMut() -> f64) -> [DVec3; 3] {
        [(); 3].map(|_| DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 3.0)
    }

    /// Independent check of every primitive-triangle distance: sample points
    /// on the triangle and on the primitive's surface; no sample pair may be
    /// closer than the reported distance, and the reported closest points
    /// must lie on (or in) their shapes at that distance.
    #[test]
    fn distances_are_attained_and_not_beaten_by_samples() {
        let mut r = rng(41);
        let prims: [Shape; 4] = [
            Sphere::new(0.4).unwrap().into(),
            Cuboid::new(DVec3::new(0.3, 0.5, 0.2)).unwrap().into(),
            Capsule::new(0.25, 0.4).unwrap().into(),
            HalfSpace::new(DVec3::new(0.0, 0.6, 0.8), 0.1).unwrap().into(),
        ];
        for _ in 0..200 {
            let t = random_triangle(&mut r);
            let pose = random_pose(&mut r, 1.0);
            for prim in &prims {
                let placed = Placed::new(prim, &pose, "test").unwrap();
                let res = placed.distance(&t);
                assert_eq!(placed.intersects(&t), res.distance == 0.0);
                assert!(
                    ((res.on_primitive - res.on_triangle).length() - res.distance).abs() < 1e-9,
                    "{prim:?}"
                );
                // The triangle point is on the triangle.
                let (q, _) = closest_point_on_triangle(res.on_triangle, &t);
                assert!((q - res.on_triangle).length() < 1e-9);
                // Sampled triangle points are never closer to the primitive.
                let inside = |x: DVec3| signed_distance(prim, &pose, x);
                assert!(inside(res.on_primitive) < 1e-9, "{prim:?}: point_a off the solid");
                for i in 0..=12 {
                    for j in 0..=(12 - i) {
                        let (u, v) = (i as f64 / 12.0, j as f64 / 12.0);
                        let x = t[0] + (t[1] - t[0]) * u + (t[2] - t[0]) * v;
                        assert!(inside(x).max(0.0) >= res.distance - 1e-9, "{prim:?}");
                    }
                }
            }
        }
    }

    /// Signed distance of `x` to the solid primitive (independent formulas).
    fn signed_distance(prim: &Shape, pose: &Pose, x: DVec3) -> f64 {
        let l = pose.inverse_transform_point(x);
        match prim {
            Shape::Sphere(s) => l.length() - s.radius(),
            Shape::Capsule(c) => {
                let z = l.z.clamp(-c.half_height(), c.half_height());
                (l - DVec3::new(0.0, 0.0, z)).length() - c.radius()
            }
            Shape::Cuboid(b) => {
                let q = l.abs() - b.half_extents();
                q.max(DVec3::ZERO).length() + q.max_element().min(0.0)
            }
            Shape::HalfSpace(h) => h.normal().dot(l) - h.offset(),
            other => panic!("{} is not a primitive", other.kind_name()),
        }
    }
}
