//! Closed triangle-triangle intersection test (Guigue & Devillers, "Faster
//! triangle-triangle intersection tests", 2003), written from the paper.
//!
//! Triangles are closed sets: touching at a point or along an edge counts as
//! intersecting. Every decision is the sign of an [`orient3d`] or [`orient2d`]
//! determinant (no divisions), so for small-integer coordinates the answer is
//! exact. Cases:
//! - general position: each triangle must straddle the other's plane; then the
//!   two segments cut from the line where the planes meet overlap iff two
//!   orientation determinants are <= 0 (paper, sec. 3);
//! - coplanar: projection onto the coordinate plane most aligned with the
//!   triangles and an exact 2D test (edge crossings and containment);
//! - degenerate (zero-area) triangles, which the paper excludes: a zero-area
//!   triangle is the union of its edges, tested as segments against the other
//!   triangle (or segments against segments); so is a sliver whose area is
//!   below the round-off of its edges (its plane is noise).

use super::orient::{orient2d, orient3d};
use super::tri_measure::{bounds, longest_edge_squared};
use crate::math::DVec3;
use glam::DVec2;

/// `true` when the closed triangles `a` and `b` share at least one point.
///
/// Every side decision is an exact orientation sign ([`orient3d`],
/// [`orient2d`]), but for triangles whose area is round-off (tested as
/// their edges, `sliver`) and segment ends within round-off of a plane
/// (on it, `segment_proper_triangle`): those rules keep two frames of one
/// configuration answering alike. Zero-area triangles (repeated or collinear
/// vertices) are handled as segments or points. If any coordinate is not finite
/// the answer is `false` (nothing is reported for a NaN triangle).
#[inline]
pub fn tri_tri_overlap(a: &[DVec3; 3], b: &[DVec3; 3]) -> bool {
    if !all_finite(a) || !all_finite(b) {
        return false;
    }
    // Closed triangles that share a point have overlapping bounding boxes, and
    // min / max are exact: this rejection is exact where the determinants
    // below are not (zero-area triangles far from the origin whose corners
    // miss each other by less than an ulp of their coordinates were reported
    // as touching; found by libFuzzer against the query's own exact box test).
    if !boxes_overlap(a, b) {
        return false;
    }
    let nb = (b[1] - b[0]).cross(b[2] - b[0]);
    let na = (a[1] - a[0]).cross(a[2] - a[0]);
    let (flat_a, flat_b) = (sliver(a, na), sliver(b, nb));
    if flat_a || flat_b {
        return degenerate_overlap((a, flat_a, na), (b, flat_b, nb));
    }
    // Sides of A's vertices relative to B's plane and of B's relative to
    // A's, their signs exact (`orient3d`).
    let da = a.map(|x| orient3d(b[0], b[1], b[2], x));
    if strictly_one_side(da) {
        return false;
    }
    let db = b.map(|x| orient3d(a[0], a[1], a[2], x));
    if strictly_one_side(db) {
        return false;
    }
    let Some((ia, flip_b)) = lone_vertex(da) else {
        return coplanar_overlap(a, b, na);
    };
    // Canonical form (paper, sec. 3): A's vertex p1 alone on the non-negative
    // side of B's plane, q1 and r1 on the non-positive side. Rotations keep the
    // winding; when p1 is on the negative side B's winding is reversed instead,
    // which flips its normal and so the side.
    let (p1, mut q1, mut r1) = rotate(a, ia);
    let (p2, q2, r2, db) = if flip_b {
        (b[0], b[2], b[1], [db[0], db[2], db[1]])
    } else {
        (b[0], b[1], b[2], db)
    };
    let Some((ib, flip_a)) = lone_vertex(db) else {
        // Only reachable through round-off (A is flat in B's plane but B is not
        // in A's): treat as coplanar.
        return coplanar_overlap(a, b, na);
    };
    let (p2, q2, r2) = rotate(&[p2, q2, r2], ib);
    if flip_a {
        std::mem::swap(&mut q1, &mut r1);
    }
    // Now p2 is alone on the non-negative side of A's plane as well. Each
    // triangle cuts a segment [i, j] (A) and [k, l] (B) from the line where the
    // planes meet, with i on edge p1q1, j on p1r1, k on p2q2, l on p2r2. The
    // orientations above fix the order along the line to j <= i and k <= l, so
    // the segments overlap iff k <= i and j <= l, and the sign of each of these
    // comparisons is the sign of one orientation determinant.
    orient3d(p1, q1, p2, q2) <= 0.0 && orient3d(p1, r1, r2, p2) <= 0.0
}

/// `true` when the closed segment `p q` and the closed triangle `t` share a
/// point. The triangle may be degenerate (then it is tested as its edges).
/// Same exactness and NaN behaviour as [`tri_tri_overlap`].
pub fn segment_triangle_overlap(p: DVec3, q: DVec3, t: &[DVec3; 3]) -> bool {
    if !all_finite(t) || !p.is_finite() || !q.is_finite() {
        return false;
    }
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    if sliver(t, n) {
        return (0..3).any(|k| segment_segment_overlap(p, q, t[k], t[(k + 1) % 3]));
    }
    segment_proper_triangle(p, q, t, n)
}

/// The axis-aligned bounding boxes of two triangles overlap (closed).
#[inline]
fn boxes_overlap(a: &[DVec3; 3], b: &[DVec3; 3]) -> bool {
    let ((lo_a, hi_a), (lo_b, hi_b)) = (bounds(a), bounds(b));
    lo_a.cmple(hi_b).all() && lo_b.cmple(hi_a).all()
}

#[inline]
fn all_finite(t: &[DVec3; 3]) -> bool {
    t[0].is_finite() && t[1].is_finite() && t[2].is_finite()
}

#[inline]
fn strictly_one_side(d: [f64; 3]) -> bool {
    (d[0] > 0.0 && d[1] > 0.0 && d[2] > 0.0) || (d[0] < 0.0 && d[1] < 0.0 && d[2] < 0.0)
}

/// For side values `d` that are not all of one strict sign: the index of the
/// vertex that is alone on its side (the other two being on the other closed
/// side), and whether the other triangle must be reversed so that this vertex
/// counts as the non-negative one. `None` when all three are zero (coplanar).
/// This is the decision tree of the paper's sec. 3, as a table.
#[inline]
fn lone_vertex(d: [f64; 3]) -> Option<(usize, bool)> {
    let [p, q, r] = d;
    Some(if p > 0.0 {
        if q > 0.0 {
            (2, true)
        } else if r > 0.0 {
            (1, true)
        } else {
            (0, false)
        }
    } else if p < 0.0 {
        if q < 0.0 {
            (2, false)
        } else if r < 0.0 {
            (1, false)
        } else {
            (0, true)
        }
    } else if q < 0.0 {
        if r >= 0.0 {
            (1, true)
        } else {
            (0, false)
        }
    } else if q > 0.0 {
        if r > 0.0 {
            (0, true)
        } else {
            (1, false)
        }
    } else if r > 0.0 {
        (2, false)
    } else if r < 0.0 {
        (2, true)
    } else {
        return None;
    })
}

/// Cyclic rotation starting at vertex `i` (keeps the winding).
#[inline]
fn rotate(t: &[DVec3; 3], i: usize) -> (DVec3, DVec3, DVec3) {
    match i {
        0 => (t[0], t[1], t[2]),
        1 => (t[1], t[2], t[0]),
        _ => (t[2], t[0], t[1]),
    }
}

/// Drops the coordinate along which `n` is largest, so that the projection of
/// the plane with normal `n` onto the remaining two is one-to-one. Dropping a
/// coordinate is exact.
#[inline]
fn projector(n: DVec3) -> impl Fn(DVec3) -> DVec2 {
    let m = n.abs();
    let axis = if m.x >= m.y && m.x >= m.z {
        0
    } else if m.y >= m.z {
        1
    } else {
        2
    };
    move |v: DVec3| match axis {
        0 => DVec2::new(v.y, v.z),
        1 => DVec2::new(v.z, v.x),
        _ => DVec2::new(v.x, v.y),
    }
}

/// Both triangles lie in the plane with normal `n` (non-zero).
#[cold]
fn coplanar_overlap(a: &[DVec3; 3], b: &[DVec3; 3], n: DVec3) -> bool {
    let proj = projector(n);
    let a2 = [proj(a[0]), proj(a[1]), proj(a[2])];
    let b2 = [proj(b[0]), proj(b[1]), proj(b[2])];
    triangles_overlap_2d(&a2, &b2)
}

/// Closed 2D triangles (both non-degenerate) overlap: some edge pair crosses
/// or one triangle contains a vertex of the other.
fn triangles_overlap_2d(a: &[DVec2; 3], b: &[DVec2; 3]) -> bool {
    for i in 0..3 {
        for j in 0..3 {
            if segments_overlap_2d(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]) {
                return true;
            }
        }
    }
    point_in_triangle_2d(a[0], b) || point_in_triangle_2d(b[0], a)
}

/// Closed point-in-triangle for a non-degenerate triangle of either winding.
#[inline]
fn point_in_triangle_2d(p: DVec2, t: &[DVec2; 3]) -> bool {
    let s0 = orient2d(t[0], t[1], p);
    let s1 = orient2d(t[1], t[2], p);
    let s2 = orient2d(t[2], t[0], p);
    (s0 >= 0.0 && s1 >= 0.0 && s2 >= 0.0) || (s0 <= 0.0 && s1 <= 0.0 && s2 <= 0.0)
}

/// Closed 2D segments `p1 p2` and `q1 q2` share a point (either may be a point).
#[inline]
fn segments_overlap_2d(p1: DVec2, p2: DVec2, q1: DVec2, q2: DVec2) -> bool {
    let o1 = orient2d(p1, p2, q1);
    let o2 = orient2d(p1, p2, q2);
    if (o1 > 0.0 && o2 > 0.0) || (o1 < 0.0 && o2 < 0.0) {
        return false;
    }
    let o3 = orient2d(q1, q2, p1);
    let o4 = orient2d(q1, q2, p2);
    if (o3 > 0.0 && o4 > 0.0) || (o3 < 0.0 && o4 < 0.0) {
        return false;
    }
    if o1 == 0.0 && o2 == 0.0 && o3 == 0.0 && o4 == 0.0 {
        // All four collinear: the intervals must overlap on both axes (one of
        // the two projections is one-to-one on the common line).
        return intervals_overlap(p1.x, p2.x, q1.x, q2.x) && intervals_overlap(p1.y, p2.y, q1.y, q2.y);
    }
    true
}

#[inline]
fn intervals_overlap(a0: f64, a1: f64, b0: f64, b1: f64) -> bool {
    a0.min(a1) <= b0.max(b1) && b0.min(b1) <= a0.max(a1)
}

/// Closed 3D segments share a point: they must be coplanar, and then they
/// intersect iff their projections onto all three coordinate planes do (at
/// least one projection is one-to-one on their common plane or line).
fn segment_segment_overlap(p1: DVec3, p2: DVec3, q1: DVec3, q2: DVec3) -> bool {
    if orient3d(p1, p2, q1, q2) != 0.0 {
        return false;
    }
    let yz = |v: DVec3| DVec2::new(v.y, v.z);
    let zx = |v: DVec3| DVec2::new(v.z, v.x);
    let xy = |v: DVec3| DVec2::new(v.x, v.y);
    segments_overlap_2d(yz(p1), yz(p2), yz(q1), yz(q2))
        && segments_overlap_2d(zx(p1), zx(p2), zx(q1), zx(q2))
        && segments_overlap_2d(xy(p1), xy(p2), xy(q1), xy(q2))
}

/// Closed segment against a non-degenerate closed triangle with normal `n`.
fn segment_proper_triangle(p: DVec3, q: DVec3, t: &[DVec3; 3], n: DVec3) -> bool {
    // Sides within round-off of the plane are on it: a segment lying in
    // the plane (a collapsed triangle's edge in the face it rests on) got
    // sides of 1e-17 of either sign from the rounding of n, and through them
    // was taken to cross the plane once and then to pass through a triangle
    // a metre away (libFuzzer, `fuzz/regressions/collide/in_plane_segment`).
    let on_plane = |d: f64, x: DVec3| {
        if d.abs() <= PLANE_EPS * n.length() * (x - t[0]).length() {
            0.0
        } else {
            d
        }
    };
    let dp = on_plane(n.dot(p - t[0]), p);
    let dq = on_plane(n.dot(q - t[0]), q);
    if (dp > 0.0 && dq > 0.0) || (dp < 0.0 && dq < 0.0) {
        return false;
    }
    if dp == 0.0 && dq == 0.0 {
        let proj = projector(n);
        let t2 = [proj(t[0]), proj(t[1]), proj(t[2])];
        let (p2, q2) = (proj(p), proj(q));
        return point_in_triangle_2d(p2, &t2)
            || (0..3).any(|k| segments_overlap_2d(p2, q2, t2[k], t2[(k + 1) % 3]));
    }
    // The segment meets the plane in one point; the line p q passes through the
    // closed triangle iff it turns the same way around all three edges.
    let s0 = orient3d(p, q, t[0], t[1]);
    let s1 = orient3d(p, q, t[1], t[2]);
    let s2 = orient3d(p, q, t[2], t[0]);
    (s0 >= 0.0 && s1 >= 0.0 && s2 >= 0.0) || (s0 <= 0.0 && s1 <= 0.0 && s2 <= 0.0)
}

/// A point whose side of a plane is at most this times the plane normal's
/// length times its distance from the plane's corner is on the plane (in
/// `segment_proper_triangle`): ten times the round-off of the side, and for
/// integer coordinates below 10^4 (the exact cases) under 1, so never a
/// non-zero side there.
const PLANE_EPS: f64 = 1e-14;

/// A triangle whose normal (twice its area) is at most this times its
/// longest edge squared is tested as its edges ([`sliver`]).
const SLIVER_EPS: f64 = 1e-12;

/// `true` when triangle `t` (normal `n`, unnormalised) has no area, or an
/// area below the round-off of its edges: a sliver whose plane is noise.
/// The signs of points against such a plane are round-off, and the general
/// test then answered by its frame: a sliver 2e-16 of its length wide,
/// crossing a triangle's plane outside the triangle, was reported as
/// touching it in the world frame and not in the triangle's mesh frame
/// (found by libFuzzer, `fuzz/regressions/collide/sliver_plane_noise`).
/// Tested as its edges, a sliver loses at most what lies within its width.
/// Integer coordinates (the exact cases) never make one: a non-zero integer
/// normal is at least 1 long.
#[inline]
fn sliver(t: &[DVec3; 3], n: DVec3) -> bool {
    let longest2 = longest_edge_squared(t);
    n == DVec3::ZERO || n.length_squared() <= (SLIVER_EPS * longest2) * (SLIVER_EPS * longest2)
}

/// At least one triangle has no area, or is a sliver (`flat`, [`sliver`]):
/// it is tested as its edges.
#[cold]
fn degenerate_overlap(
    (a, flat_a, na): (&[DVec3; 3], bool, DVec3),
    (b, flat_b, nb): (&[DVec3; 3], bool, DVec3),
) -> bool {
    let edges = |t: &[DVec3; 3]| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])];
    match (flat_a, flat_b) {
        (true, true) => edges(a)
            .iter()
            .any(|&(p, q)| edges(b).iter().any(|&(r, s)| segment_segment_overlap(p, q, r, s))),
        (true, false) => edges(a)
            .iter()
            .any(|&(p, q)| segment_proper_triangle(p, q, b, nb)),
        _ => edges(b)
            .iter()
            .any(|&(p, q)| segment_proper_triangle(p, q, a, na)),
    }
}

#[cfg(test)]
mod tests {
    use super::super::exact_oracle::{exact_tri_tri, to_f, IVec};
    use super::*;
    use tumble_testkit::{RandomSource, XorShift64Star as Rng};

    fn check(a: &[IVec; 3], b: &[IVec; 3]) -> bool {
        let fa = [to_f(a[0]), to_f(a[1]), to_f(a[2])];
        let fb = [to_f(b[0]), to_f(b[1]), to_f(b[2])];
        let want = exact_tri_tri(a, b);
        let got = tri_tri_overlap(&fa, &fb);
        assert_eq!(got, want, "a = {a:?}, b = {b:?}");
        // Symmetric in A/B and invariant under re-ordering of the corners.
        assert_eq!(tri_tri_overlap(&fb, &fa), want, "swapped: a = {a:?}, b = {b:?}");
        let ra = [fa[1], fa[0], fa[2]];
        let rb = [fb[2], fb[0], fb[1]];
        assert_eq!(tri_tri_overlap(&ra, &rb), want, "reordered: a = {a:?}, b = {b:?}");
        want
    }

    #[test]
    fn a_sliver_crossing_a_plane_outside_the_triangle_does_not_touch_it() {
        // Found by libFuzzer (fuzz/regressions/collide/sliver_plane_noise):
        // B is 2e-16 of its length wide; its long edge crosses A's plane at
        // (-2.3555, -0.4664, -1.3366), outside A (in exact rationals, one
        // of the three edge tests there is -0.44 against +0.48 and +1.2).
        // The general test, with B's plane made of round-off, said touching.
        let a = [
            DVec3::new(-1.840115968566415, -0.9781643396658275, -1.3728236820019837),
            DVec3::new(-0.5826199740596627, -1.9168688487067977, -2.0),
            DVec3::new(-2.0, -0.5308613717860684, -1.8630655374990464),
        ];
        let b = [
            DVec3::new(-1.5489597353142117, 0.5916242432891508, -0.8789041194760416),
            DVec3::new(-2.028021646875973, -0.03675566668147123, -1.1507313839015354),
            DVec3::new(-2.6506044254820766, -0.8533902204375289, -1.5039946459196054),
        ];
        assert!(sliver(&b, (b[1] - b[0]).cross(b[2] - b[0])));
        assert!(!tri_tri_overlap(&a, &b));
        assert!(!tri_tri_overlap(&b, &a));
        // The distance, which asks this test first, is then not zero either.
        let d = super::super::tri_distance::triangle_distance(&a, &b);
        assert!(d.distance > 0.0, "{d:?}");
        // The same sliver moved onto A's face (its middle corner on A's
        // centroid) touches it.
        let shift = (a[0] + a[1] + a[2]) / 3.0 - b[1];
        let on = b.map(|p| p + shift);
        assert!(tri_tri_overlap(&a, &on) && tri_tri_overlap(&on, &a));
    }

    #[test]
    fn copies_of_a_long_triangle_slid_apart_along_its_edge_do_not_touch() {
        // Found by libFuzzer (fuzz/regressions/collide/coplanar_far_slide):
        // one triangle a million metres long, and its copy slid along its
        // own edge (the x axis) by 1,152,941 m, more than the edge's
        // 1,000,001 m: the two lie in one plane exactly (every corner of B
        // has the y and z of one of A's), and apart (the copy of a triangle
        // slid along an edge meets it only while the slide is shorter than
        // that edge). Plain determinants of these coordinates gave sides of
        // round-off and said touching.
        let (y, z) = (-152942.1764705882, -152942.1764705882);
        let (y1, z1) = (-485511.5587090868, -486274.50980392157);
        let a = [
            DVec3::new(999999.0, y, z),
            DVec3::new(41657.1297779812, y1, z1),
            DVec3::new(2000000.0, y, z),
        ];
        let b = [
            DVec3::new(-152942.1764705882, y, z),
            DVec3::new(-1111284.046692607, y1, z1),
            DVec3::new(847058.8235294118, y, z),
        ];
        assert!(!tri_tri_overlap(&a, &b) && !tri_tri_overlap(&b, &a));
        // Slid by less than the edge, the copy overlaps it.
        let near = a.map(|p| p - DVec3::new(900_000.0, 0.0, 0.0));
        assert!(tri_tri_overlap(&a, &near) && tri_tri_overlap(&near, &a));
        // Slid by exactly the edge, the two share one corner.
        let end = a.map(|p| p + (a[2] - a[0]));
        assert!(tri_tri_overlap(&a, &end) && tri_tri_overlap(&end, &a));
    }

    fn point(rng: &mut Rng, r: i64) -> IVec {
        [rng.int(-r, r), rng.int(-r, r), rng.int(-r, r)]
    }

    /// Runs `n` cases from `gen`, returning how many intersected.
    fn run(n: usize, seed: u64, mut gen: impl FnMut(&mut Rng) -> ([IVec; 3], [IVec; 3])) -> usize {
        let mut rng = Rng(seed);
        (0..n)
            .filter(|_| {
                let (a, b) = gen(&mut rng);
                check(&a, &b)
            })
            .count()
    }

    #[test]
    fn random_small_integer_triangles_match_exact_oracle() {
        let n = 40_000;
        let hits = run(n, 0x1234_5678, |rng| {
            let a = [point(rng, 2), point(rng, 2), point(rng, 2)];
            let b = [point(rng, 2), point(rng, 2), point(rng, 2)];
            (a, b)
        });
        assert!(hits > n / 10 && hits < n * 9 / 10, "hits {hits}");
    }

    #[test]
    fn coplanar_triangles_match_exact_oracle() {
        let n = 20_000;
        // Both in one tilted plane through integer points: z = x + 2y.
        let hits = run(n, 99, |rng| {
            let mut p = || {
                let (x, y) = (rng.int(-3, 3), rng.int(-3, 3));
                [x, y, x + 2 * y]
            };
            ([p(), p(), p()], [p(), p(), p()])
        });
        assert!(hits > n / 10 && hits < n * 9 / 10, "hits {hits}");
    }

    #[test]
    fn shared_vertex_and_shared_edge_always_intersect() {
        let n = 5_000;
        let hits = run(n, 7, |rng| {
            let a = [point(rng, 3), point(rng, 3), point(rng, 3)];
            let k = rng.int(0, 2) as usize;
            let b = [a[k], point(rng, 3), point(rng, 3)];
            (a, b)
        });
        assert_eq!(hits, n);
        let hits = run(n, 8, |rng| {
            let a = [point(rng, 3), point(rng, 3), point(rng, 3)];
            let b = [a[2], a[1], point(rng, 3)];
            (a, b)
        });
        assert_eq!(hits, n);
    }

    #[test]
    fn near_touching_triangles_match_exact_oracle() {
        // B placed one unit step from A's features, so that most pairs touch or
        // just miss, the hardest cases for sign logic.
        let n = 20_000;
        run(n, 4242, |rng| {
            let a = [point(rng, 4), point(rng, 4), point(rng, 4)];
            let k = rng.int(0, 2) as usize;
            let mid = [
                (a[k][0] + a[(k + 1) % 3][0]) / 2,
                (a[k][1] + a[(k + 1) % 3][1]) / 2,
                (a[k][2] + a[(k + 1) % 3][2]) / 2,
            ];
            let o = point(rng, 1);
            let c = [mid[0] + o[0], mid[1] + o[1], mid[2] + o[2]];
            (a, [c, point(rng, 4), point(rng, 4)])
        });
    }

    #[test]
    fn large_integer_coordinates_stay_exact() {
        // Coordinates up to 10^4 (the documented exact range): B's first
        // vertex at the midpoint of one of A's edges, offset by at most one unit,
        // so the answer hinges on single-unit differences.
        let n = 5_000;
        run(n, 2718, |rng| {
            let mut even = || {
                [
                    2 * rng.int(-5_000, 5_000),
                    2 * rng.int(-5_000, 5_000),
                    2 * rng.int(-5_000, 5_000),
                ]
            };
            let a = [even(), even(), even()];
            let (p, q) = (even(), even());
            let k = rng.int(0, 2) as usize;
            let (u, v) = (a[k], a[(k + 1) % 3]);
            let o = [rng.int(-1, 1), rng.int(-1, 1), rng.int(-1, 1)];
            let m = [
                (u[0] + v[0]) / 2 + o[0],
                (u[1] + v[1]) / 2 + o[1],
                (u[2] + v[2]) / 2 + o[2],
            ];
            (a, [m, p, q])
        });
    }

    #[test]
    fn degenerate_triangles_match_exact_oracle() {
        let n = 20_000;
        let hits = run(n, 31337, |rng| {
            let a = [point(rng, 3), point(rng, 3), point(rng, 3)];
            // Collinear (sliver of zero area), repeated vertex, or single point.
            let p = point(rng, 3);
            let d = point(rng, 1);
            let s = rng.int(-2, 2);
            let b = match rng.int(0, 3) {
                // Sliver: nearly collinear, small but non-zero area.
                3 => [
                    p,
                    [p[0] + 3 * d[0], p[1] + 3 * d[1], p[2] + 3 * d[2]],
                    [p[0] + 6 * d[0] + 1, p[1] + 6 * d[1], p[2] + 6 * d[2]],
                ],
                0 => [
                    p,
                    [p[0] + d[0], p[1] + d[1], p[2] + d[2]],
                    [p[0] + s * d[0], p[1] + s * d[1], p[2] + s * d[2]],
                ],
                1 => [p, p, point(rng, 3)],
                _ => [p, p, p],
            };
            if rng.int(0, 1) == 0 {
                (a, b)
            } else {
                // Both degenerate.
                let q = point(rng, 3);
                (b, [q, q, point(rng, 3)])
            }
        });
        assert!(hits > 100, "hits {hits}");
    }

    #[test]
    fn segment_triangle_overlap_agrees_with_degenerate_triangle_test() {
        let mut rng = Rng(5);
        for _ in 0..5_000 {
            let t = [point(&mut rng, 3), point(&mut rng, 3), point(&mut rng, 3)];
            let (p, q) = (point(&mut rng, 3), point(&mut rng, 3));
            let want = exact_tri_tri(&t, &[p, q, q]);
            let ft = [to_f(t[0]), to_f(t[1]), to_f(t[2])];
            assert_eq!(segment_triangle_overlap(to_f(p), to_f(q), &ft), want);
        }
    }

    #[test]
    fn a_collapsed_triangle_in_a_faces_plane_but_outside_it_does_not_touch_it() {
        // Found by libFuzzer (fuzz/regressions/collide/in_plane_segment): A
        // collapsed to a segment lying in B's plane (y = z, up to the
        // rounding of B's normal, whose x is 4e-17), a metre from B. The
        // segment's sides of the plane were +-1e-17, taken to cross it.
        let a = [
            DVec3::new(-1.3411764705882354, -2.0, -2.0),
            DVec3::new(-0.5725490196078431, -1.231372549019608, -1.231372549019608),
            DVec3::new(-0.5725490196078431, -1.231372549019608, -1.231372549019608),
        ];
        let b = [
            DVec3::new(-1.231372549019608, -0.4627450980392156, -0.4627450980392156),
            DVec3::new(-2.0, -0.46274509803921565, -0.4627450980392156),
            DVec3::new(-2.0, -1.231372549019608, -1.231372549019608),
        ];
        assert!(!tri_tri_overlap(&a, &b) && !tri_tri_overlap(&b, &a));
        assert!(!segment_triangle_overlap(a[0], a[1], &b));
        let d = super::super::tri_distance::triangle_distance(&a, &b);
        assert!(d.distance > 0.9, "{d:?}");
        // Slid along the plane to begin at B's centroid, it touches.
        let shift = (b[0] + b[1] + b[2]) / 3.0 - a[0];
        let on = a.map(|p| p + shift);
        assert!(tri_tri_overlap(&on, &b) && tri_tri_overlap(&b, &on));
    }

    #[test]
    fn non_finite_input_returns_false() {
        let a = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let b = [DVec3::new(f64::NAN, 0.0, 0.0), DVec3::X, DVec3::Y];
        assert!(!tri_tri_overlap(&a, &b));
        assert!(!tri_tri_overlap(&b, &a));
        let c = [DVec3::ZERO, DVec3::splat(f64::INFINITY), DVec3::Y];
        assert!(!tri_tri_overlap(&a, &c));
    }

    #[test]
    fn large_offset_float_pair_agrees_with_scaled_integer_pair() {
        // Scaling by a power of two is exact: the answer must not change.
        let mut rng = Rng(77);
        for _ in 0..2_000 {
            let a = [point(&mut rng, 2), point(&mut rng, 2), point(&mut rng, 2)];
            let b = [point(&mut rng, 2), point(&mut rng, 2), point(&mut rng, 2)];
            let s = 0.125;
            let fa = [to_f(a[0]) * s, to_f(a[1]) * s, to_f(a[2]) * s];
            let fb = [to_f(b[0]) * s, to_f(b[1]) * s, to_f(b[2]) * s];
            assert_eq!(tri_tri_overlap(&fa, &fb), exact_tri_tri(&a, &b));
        }
    }
}
