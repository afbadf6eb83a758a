//! Test oracles, written independently of the routines under test and as
//! plainly as possible: brute force over all features and all candidate
//! axes, ternary searches instead of closed-form closest points.

use crate::math::DVec3;
use crate::pose::Pose;
use crate::shape::{Polytope, Shape};

/// A shape placed in the world, in the simplest form for brute force.
pub(crate) enum OShape {
    /// Points within `r` of the segment (a sphere when both ends coincide).
    Round { core: [DVec3; 2], r: f64 },
    /// A convex polytope with world-space faces (normal, offset, corners).
    Poly {
        verts: Vec<DVec3>,
        faces: Vec<(DVec3, f64, Vec<DVec3>)>,
        edges: Vec<(DVec3, DVec3)>,
    },
    /// The solid `n . x <= d`.
    Plane { n: DVec3, d: f64 },
}

fn poly<P: Polytope>(p: &P, pose: &Pose) -> OShape {
    let verts: Vec<DVec3> = (0..p.vertex_count())
        .map(|i| pose.transform_point(p.vertex(i)))
        .collect();
    let faces = (0..p.face_count())
        .map(|f| {
            let n = pose.transform_vector(p.face_normal(f));
            let c: Vec<DVec3> = (0..p.face_len(f)).map(|k| verts[p.face_vertex(f, k)]).collect();
            let d = n.dot(c[0]);
            (n, d, c)
        })
        .collect();
    let edges = (0..p.edge_count())
        .map(|e| {
            let ([a, b], _) = p.edge(e);
            (verts[a as usize], verts[b as usize])
        })
        .collect();
    OShape::Poly { verts, faces, edges }
}

pub(crate) fn oshape(s: &Shape, pose: &Pose) -> OShape {
    match s {
        Shape::Sphere(x) => OShape::Round {
            core: [pose.position, pose.position],
            r: x.radius(),
        },
        Shape::Capsule(x) => OShape::Round {
            core: x.world_segment(pose),
            r: x.radius(),
        },
        Shape::Cuboid(x) => poly(x, pose),
        Shape::ConvexHull(x) => poly(x, pose),
        Shape::HalfSpace(x) => {
            let (n, d) = x.world_plane(pose);
            OShape::Plane { n, d }
        }
        Shape::Mesh(_) => unreachable!("the convex oracle is not used for meshes"),
    }
}

/// Minimum of a convex function on [0, 1] by ternary search.
fn ternary(f: impl Fn(f64) -> f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for _ in 0..70 {
        let m1 = lo + (hi - lo) / 3.0;
        let m2 = hi - (hi - lo) / 3.0;
        if f(m1) < f(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    f(0.5 * (lo + hi)).min(f(0.0)).min(f(1.0))
}

fn point_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - p).length()
}

fn segment_segment(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    ternary(|s| point_segment(a + (b - a) * s, c, d))
}

/// Distance from `p` to a convex polygon (coplanar corners, counter-clockwise
/// around `n`).
fn point_polygon(p: DVec3, n: DVec3, c: &[DVec3]) -> f64 {
    let h = n.dot(p - c[0]);
    let q = p - n * h;
    let inside = (0..c.len()).all(|k| (c[(k + 1) % c.len()] - c[k]).cross(q - c[k]).dot(n) >= 0.0);
    if inside {
        return h.abs();
    }
    (0..c.len())
        .map(|k| point_segment(p, c[k], c[(k + 1) % c.len()]))
        .fold(f64::INFINITY, f64::min)
}

fn support(verts: &[DVec3], u: DVec3) -> (f64, f64) {
    verts
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v.dot(u)), hi.max(v.dot(u)))
        })
}

/// Largest separation over the given axes (positive: separated along it).
fn sat(va: &[DVec3], vb: &[DVec3], axes: &[DVec3]) -> f64 {
    axes.iter()
        .filter(|u| u.length() > 1e-9)
        .map(|u| {
            let u = u.normalize();
            let (a0, a1) = support(va, u);
            let (b0, b1) = support(vb, u);
            (b0 - a1).max(a0 - b1)
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Signed distance between two placed shapes (m): the gap when apart, minus
/// the penetration depth when overlapping.
pub(crate) fn signed_distance(a: &OShape, b: &OShape) -> f64 {
    use OShape::*;
    match (a, b) {
        (Round { core: c1, r: r1 }, Round { core: c2, r: r2 }) => {
            segment_segment(c1[0], c1[1], c2[0], c2[1]) - r1 - r2
        }
        (Round { core, r }, Poly { verts, faces, edges })
        | (Poly { verts, faces, edges }, Round { core, r }) => {
            let dir = core[1] - core[0];
            let mut axes: Vec<DVec3> = faces.iter().map(|f| f.0).collect();
            axes.extend(edges.iter().map(|(p, q)| (*q - *p).cross(dir)));
            let s = sat(&core[..], verts, &axes);
            if s <= 0.0 {
                return s - r;
            }
            let d = faces
                .iter()
                .map(|(n, _, c)| ternary(|t| point_polygon(core[0] + dir * t, *n, c)))
                .fold(f64::INFINITY, f64::min);
            d - r
        }
        (
            Poly {
                verts: va,
                faces: fa,
                edges: ea,
            },
            Poly {
                verts: vb,
                faces: fb,
                edges: eb,
            },
        ) => {
            let mut axes: Vec<DVec3> = fa.iter().chain(fb.iter()).map(|f| f.0).collect();
            for (p, q) in ea {
                for (s, t) in eb {
                    axes.push((*q - *p).cross(*t - *s));
                }
            }
            let s = sat(va, vb, &axes);
            if s <= 0.0 {
                return s;
            }
            let mut d = f64::INFINITY;
            for v in va {
                for (n, _, c) in fb {
                    d = d.min(point_polygon(*v, *n, c));
                }
            }
            for v in vb {
                for (n, _, c) in fa {
                    d = d.min(point_polygon(*v, *n, c));
                }
            }
            for (p, q) in ea {
                for (s, t) in eb {
                    d = d.min(segment_segment(*p, *q, *s, *t));
                }
            }
            d
        }
        (Round { core, r }, Plane { n, d }) | (Plane { n, d }, Round { core, r }) => {
            (n.dot(core[0]) - d).min(n.dot(core[1]) - d) - r
        }
        (Poly { verts, .. }, Plane { n, d }) | (Plane { n, d }, Poly { verts, .. }) => {
            verts.iter().map(|v| n.dot(*v) - d).fold(f64::INFINITY, f64::min)
        }
        (Plane { .. }, Plane { .. }) => f64::NAN,
    }
}

/// Unsigned distance from `p` to the boundary of the placed shape (m).
pub(crate) fn boundary_distance(s: &OShape, p: DVec3) -> f64 {
    match s {
        OShape::Round { core, r } => (point_segment(p, core[0], core[1]) - r).abs(),
        OShape::Poly { faces, .. } => {
            let inside = faces
                .iter()
                .map(|(n, d, _)| n.dot(p) - d)
                .fold(f64::NEG_INFINITY, f64::max);
            if inside <= 0.0 {
                -inside
            } else {
                faces
                    .iter()
                    .map(|(n, _, c)| point_polygon(p, *n, c))
                    .fold(f64::INFINITY, f64::min)
            }
        }
        OShape::Plane { n, d } => (n.dot(p) - d).abs(),
    }
}
