//! Closest points and distances between points, segments and triangles.
//!
//! - [`closest_point_on_triangle`]: Ericson, Real-Time Collision Detection,
//!   sec. 5.1.5: Voronoi regions of the vertices, then edges, then the face,
//!   decided by dot products only (no normal needed).
//! - [`closest_points_segments`]: Ericson sec. 5.1.9, clamped line-line
//!   parameters with the degenerate (point, parallel) cases handled.
//! - [`triangle_distance`]: for disjoint triangles the minimum is realised by a
//!   vertex of one against the other triangle, or by an edge pair (Ericson sec.
//!   5.1.9, "closest points of two triangles"), so it is the minimum over the 6
//!   vertex-triangle and 9 edge-edge pairs; intersecting triangles (decided by
//!   [`tri_tri_overlap`]) are at distance exactly 0.
//!
//! Deviation from the book: every division is guarded so that zero-length
//! edges and zero-area triangles give a valid closest point instead of NaN.

use super::tri_tri_overlap::tri_tri_overlap;
use crate::contact::SubFeature;
use crate::math::DVec3;

/// Closest point on the closed triangle `t` to `p`, and the feature of `t` whose
/// Voronoi region contains `p`: `Vertex(k)`, `Edge(k)` (corner `k` to `k + 1`)
/// or `Face`. Zero-area triangles are handled (the answer lies on an edge or
/// vertex). A non-finite coordinate anywhere gives `(DVec3::NAN, Face)`.
pub fn closest_point_on_triangle(p: DVec3, t: &[DVec3; 3]) -> (DVec3, SubFeature) {
    if !(p.is_finite() && t[0].is_finite() && t[1].is_finite() && t[2].is_finite()) {
        return (DVec3::NAN, SubFeature::Face);
    }
    closest_point_on_finite_triangle(p, t)
}

/// [`closest_point_on_triangle`] for input known to be finite.
#[inline]
pub(crate) fn closest_point_on_finite_triangle(p: DVec3, t: &[DVec3; 3]) -> (DVec3, SubFeature) {
    let [a, b, c] = *t;
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, SubFeature::Vertex(0));
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, SubFeature::Vertex(1));
    }
    // vc, vb, va are the (scaled) barycentric coordinates of p's projection.
    let vc = d1 * d4 - d3 * d2;
    // Each edge region also needs the edge to have a length (`d1 - d3 =
    // |ab|^2` etc.): for a zero-length edge every barycentric product is 0
    // and the region test would claim points that belong to the other edge.
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0 {
        return (a + ab * ratio(d1, d1 - d3), SubFeature::Edge(0));
    }
    // The vertex and edge tests above again for corner c, unrolled as in
    // Ericson 5.1.5: each reuses the dot products d1..d6 computed once, which a
    // loop over the corners would have to recompute or index.
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, SubFeature::Vertex(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0 {
        return (a + ac * ratio(d2, d2 - d6), SubFeature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0 {
        let w = ratio(d4 - d3, (d4 - d3) + (d5 - d6));
        return (b + (c - b) * w, SubFeature::Edge(1));
    }
    let sum = va + vb + vc;
    if sum > 0.0 {
        return (a + ab * (vb / sum) + ac * (vc / sum), SubFeature::Face);
    }
    // Only a zero-area triangle gets here: its closest point is on an edge.
    closest_on_edges(p, t)
}

/// `num / den` for `0 <= num <= den`, and 0 when `den` is 0 (a zero-length edge).
#[inline]
fn ratio(num: f64, den: f64) -> f64 {
    if den > 0.0 {
        (num / den).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

#[cold]
fn closest_on_edges(p: DVec3, t: &[DVec3; 3]) -> (DVec3, SubFeature) {
    let mut best = (t[0], SubFeature::Vertex(0));
    let mut best_d2 = f64::INFINITY;
    for k in 0..3 {
        let r = closest_points_segments(p, p, t[k], t[(k + 1) % 3]);
        let d2 = (r.point_b - p).length_squared();
        if d2 < best_d2 {
            best_d2 = d2;
            best = (r.point_b, edge_feature(k, r.t));
        }
    }
    best
}

/// Feature of a triangle for parameter `s` on its edge `k`.
#[inline]
fn edge_feature(k: usize, s: f64) -> SubFeature {
    if s <= 0.0 {
        SubFeature::Vertex(k as u8)
    } else if s >= 1.0 {
        SubFeature::Vertex(((k + 1) % 3) as u8)
    } else {
        SubFeature::Edge(k as u8)
    }
}

/// Closest points of two segments (see [`closest_points_segments`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentClosest {
    /// Parameter on the first segment, in `[0, 1]`.
    pub s: f64,
    /// Parameter on the second segment, in `[0, 1]`.
    pub t: f64,
    /// Closest point on the first segment: `p1 + s (q1 - p1)` (m).
    pub point_a: DVec3,
    /// Closest point on the second segment: `p2 + t (q2 - p2)` (m).
    pub point_b: DVec3,
}

impl SegmentClosest {
    /// Distance between the two closest points (m).
    pub fn distance(&self) -> f64 {
        (self.point_a - self.point_b).length()
    }
}

/// Closest points between the closed segments `p1 q1` and `p2 q2` (Ericson
/// 5.1.9). Either segment may have zero length. For parallel segments one of
/// the (infinitely many) closest pairs is returned, with `s` chosen as 0.
/// A non-finite coordinate gives a NaN [`SegmentClosest::distance`].
/// (The narrow phase runs the same `segment_parameters` with a coarser
/// parallel test, for steady capsule contacts: see `narrow::geometry`.)
pub fn closest_points_segments(p1: DVec3, q1: DVec3, p2: DVec3, q2: DVec3) -> SegmentClosest {
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    // "Zero length" relative to the other segment, so the test is scale-free;
    // parallel when |d1 x d2|^2 <= EPSILON |d1|^2 |d2|^2.
    let zero_length = |a: f64, e: f64| f64::EPSILON * f64::EPSILON * (a + e);
    let (s, t) = segment_parameters(d1, d2, p1 - p2, zero_length, f64::EPSILON).unwrap_or((0.0, 0.0));
    SegmentClosest {
        s,
        t,
        point_a: p1 + d1 * s,
        point_b: p2 + d2 * t,
    }
}

/// The parameters `(s, t)` of the closest points `p1 + s d1`, `p2 + t d2` of
/// two closed segments (Ericson 5.1.9), given `d1`, `d2` and `r = p1 - p2`:
/// the one home of the algorithm for [`closest_points_segments`] and the
/// narrow phase's segment routine (`narrow::geometry`), which differ only in
/// the two tolerances passed here. A segment whose squared length is at most
/// `tiny(a, e)` (`a`, `e` the squared lengths of `d1`, `d2`) is a point, and
/// the segments are parallel when `|d1 x d2|^2 <= parallel * a * e` (then
/// `s` starts at 0). `None` when both segments are points.
#[inline]
pub(crate) fn segment_parameters(
    d1: DVec3,
    d2: DVec3,
    r: DVec3,
    tiny: impl FnOnce(f64, f64) -> f64,
    parallel: f64,
) -> Option<(f64, f64)> {
    let a = d1.length_squared();
    let e = d2.length_squared();
    let f = d2.dot(r);
    let tiny = tiny(a, e);
    if a <= tiny && e <= tiny {
        return None;
    }
    Some(if a <= tiny {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(r);
        if e <= tiny {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(d2);
            // denom = |d1 x d2|^2 >= 0; zero for parallel segments.
            let denom = a * e - b * b;
            let mut s = if denom > parallel * a * e {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            // Closest point on line 2 to segment-1 point, then clamp and
            // recompute s if t left [0, 1].
            let mut t = (b * s + f) / e;
            if t < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            }
            (s, t)
        }
    })
}

/// Closest points of two triangles (see [`triangle_distance`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriDistance {
    /// Euclidean distance between the triangles (m); exactly 0 when they
    /// intersect, NaN when an input coordinate is not finite.
    pub distance: f64,
    /// Closest point on triangle A (m).
    pub point_a: DVec3,
    /// Closest point on triangle B (m).
    pub point_b: DVec3,
    /// Feature of A that realises the minimum (`Vertex(k)`, `Edge(k)`, `Face`).
    pub feature_a: SubFeature,
    /// Feature of B that realises the minimum.
    pub feature_b: SubFeature,
}

/// Distance, closest points and closest features of the closed triangles `a`
/// and `b` (Ericson 5.1.9). Triangles that intersect (touching included)
/// return distance 0 with `point_a == point_b` a common point; the features
/// are then the edge that pierces the other triangle and that triangle's face,
/// or, for coplanar overlaps, the touching features. Zero-area triangles are
/// handled. A non-finite coordinate gives `distance` NaN (and NaN points):
/// check `distance.is_finite()` when the input is not trusted.
pub fn triangle_distance(a: &[DVec3; 3], b: &[DVec3; 3]) -> TriDistance {
    let finite = a.iter().chain(b.iter()).all(|p| p.is_finite());
    if !finite {
        return TriDistance {
            distance: f64::NAN,
            point_a: DVec3::NAN,
            point_b: DVec3::NAN,
            feature_a: SubFeature::Face,
            feature_b: SubFeature::Face,
        };
    }
    if !tri_tri_overlap(a, b) {
        return closest_pair_features(a, b);
    }
    // Intersecting: a crossing point of an edge through the other triangle,
    // or (coplanar, or both degenerate) the touching vertex/edge pair.
    let mut best = piercing_point(a, b).unwrap_or_else(|| closest_pair_features(a, b));
    best.distance = 0.0;
    let mid = (best.point_a + best.point_b) * 0.5;
    best.point_a = mid;
    best.point_b = mid;
    best
}

/// Minimum over the 6 vertex-triangle and 9 edge-edge pairs: the true distance
/// for disjoint triangles, an upper bound otherwise. Ties keep the first pair
/// in the order (A vertices, B vertices, edge pairs), so results are
/// deterministic.
fn closest_pair_features(a: &[DVec3; 3], b: &[DVec3; 3]) -> TriDistance {
    let mut best = TriDistance {
        distance: f64::INFINITY,
        point_a: a[0],
        point_b: b[0],
        feature_a: SubFeature::Vertex(0),
        feature_b: SubFeature::Vertex(0),
    };
    let mut best_d2 = f64::INFINITY;
    for (k, &p) in a.iter().enumerate() {
        let (q, f) = closest_point_on_finite_triangle(p, b);
        let d2 = (p - q).length_squared();
        if d2 < best_d2 {
            best_d2 = d2;
            best = TriDistance {
                distance: 0.0,
                point_a: p,
                point_b: q,
                feature_a: SubFeature::Vertex(k as u8),
                feature_b: f,
            };
        }
    }
    // B's vertices against A: the loop above with the roles swapped, written
    // out so that each side's point and feature land in the right field (a
    // shared loop would need a flag to swap them back).
    for (k, &p) in b.iter().enumerate() {
        let (q, f) = closest_point_on_finite_triangle(p, a);
        let d2 = (p - q).length_squared();
        if d2 < best_d2 {
            best_d2 = d2;
            best = TriDistance {
                distance: 0.0,
                point_a: q,
                point_b: p,
                feature_a: f,
                feature_b: SubFeature::Vertex(k as u8),
            };
        }
    }
    for i in 0..3 {
        for j in 0..3 {
            let r = closest_points_segments(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]);
            let d2 = (r.point_a - r.point_b).length_squared();
            if d2 < best_d2 {
                best_d2 = d2;
                best = TriDistance {
                    distance: 0.0,
                    point_a: r.point_a,
                    point_b: r.point_b,
                    feature_a: edge_feature(i, r.s),
                    feature_b: edge_feature(j, r.t),
                };
            }
        }
    }
    best.distance = best_d2.sqrt();
    best
}

/// For intersecting, non-coplanar triangles: the point where an edge of one
/// crosses the other (every such pair has one, since the intersection segment
/// ends on edges). Picks the crossing that lies best inside the other triangle.
#[cold]
fn piercing_point(a: &[DVec3; 3], b: &[DVec3; 3]) -> Option<TriDistance> {
    let mut best: Option<(f64, TriDistance)> = None;
    for (edges, other, a_pierces) in [(a, b, true), (b, a, false)] {
        let n = (other[1] - other[0]).cross(other[2] - other[0]);
        for k in 0..3 {
            let (p, q) = (edges[k], edges[(k + 1) % 3]);
            let dp = n.dot(p - other[0]);
            let dq = n.dot(q - other[0]);
            if dp == dq || (dp > 0.0 && dq > 0.0) || (dp < 0.0 && dq < 0.0) {
                continue;
            }
            let x = p + (q - p) * (dp / (dp - dq));
            let (y, _) = closest_point_on_finite_triangle(x, other);
            let miss = (x - y).length_squared();
            let better = match &best {
                Some((m, _)) => miss < *m,
                None => true,
            };
            if better {
                let (feature_a, feature_b) = if a_pierces {
                    (SubFeature::Edge(k as u8), SubFeature::Face)
                } else {
                    (SubFeature::Face, SubFeature::Edge(k as u8))
                };
                best = Some((
                    miss,
                    TriDistance {
                        distance: 0.0,
                        point_a: x,
                        point_b: x,
                        feature_a,
                        feature_b,
                    },
                ));
            }
        }
    }
    best.map(|(_, d)| d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::DQuat;
    use proptest::prelude::*;

    /// Barycentric grid of `n + 1` points per side on the triangle.
    fn samples(t: &[DVec3; 3], n: usize) -> Vec<DVec3> {
        let mut out = Vec::new();
        for i in 0..=n {
            for j in 0..=n - i {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                out.push(t[0] + (t[1] - t[0]) * u + (t[2] - t[0]) * v);
            }
        }
        out
    }

    fn longest_edge(t: &[DVec3; 3]) -> f64 {
        super::super::tri_measure::longest_edge_squared(t).sqrt()
    }

    fn arb_point() -> impl Strategy<Value = DVec3> {
        (-2.0f64..2.0, -2.0f64..2.0, -2.0f64..2.0).prop_map(|(x, y, z)| DVec3::new(x, y, z))
    }

    fn arb_tri() -> impl Strategy<Value = [DVec3; 3]> {
        (arb_point(), arb_point(), arb_point()).prop_map(|(a, b, c)| [a, b, c])
    }

    fn point_triangle_distance(p: DVec3, t: &[DVec3; 3]) -> f64 {
        (closest_point_on_triangle(p, t).0 - p).length()
    }

    /// Regression: a triangle with two equal corners is the segment to the
    /// third; points beside that segment used to snap to the repeated corner
    /// (the zero-length edge's region claimed them).
    #[test]
    fn repeated_corner_triangle_is_its_segment() {
        let (a, c) = (DVec3::new(0.0, -0.5, 0.0), DVec3::new(-1.5, 1.0, 0.5));
        for k in 0..=10 {
            let s = k as f64 / 10.0;
            let on = a + (c - a) * s;
            let off = on + (c - a).normalize().any_orthonormal_vector() * 0.3;
            for t in [[a, a, c], [a, c, a], [c, a, a], [a, c, c], [c, c, a], [c, a, c]] {
                for p in [on, off] {
                    let (q, _) = closest_point_on_triangle(p, &t);
                    assert!((q - on).length() < 1e-12, "{t:?} {p} -> {q}, want {on}");
                }
            }
        }
    }

    #[test]
    fn point_triangle_regions_on_the_unit_triangle() {
        let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let cases = [
            (
                DVec3::new(0.2, 0.2, 3.0),
                DVec3::new(0.2, 0.2, 0.0),
                SubFeature::Face,
            ),
            (DVec3::new(-1.0, -1.0, 0.5), DVec3::ZERO, SubFeature::Vertex(0)),
            (DVec3::new(2.0, -0.5, 0.0), DVec3::X, SubFeature::Vertex(1)),
            (
                DVec3::new(0.5, -2.0, 1.0),
                DVec3::new(0.5, 0.0, 0.0),
                SubFeature::Edge(0),
            ),
            (
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::new(0.5, 0.5, 0.0),
                SubFeature::Edge(1),
            ),
            (
                DVec3::new(-3.0, 0.25, 0.0),
                DVec3::new(0.0, 0.25, 0.0),
                SubFeature::Edge(2),
            ),
        ];
        for (p, want, f) in cases {
            let (q, g) = closest_point_on_triangle(p, &t);
            assert!((q - want).length() < 1e-15, "{p} -> {q}");
            assert_eq!(g, f);
        }
    }

    #[test]
    fn degenerate_inputs_give_finite_answers() {
        let p = DVec3::new(0.3, 2.0, -1.0);
        let line = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
        let (q, _) = closest_point_on_triangle(p, &line);
        assert!((q - DVec3::new(0.3, 0.0, 0.0)).length() < 1e-15);
        let dot = [DVec3::ONE; 3];
        assert_eq!(closest_point_on_triangle(p, &dot).0, DVec3::ONE);
        let r = closest_points_segments(p, p, DVec3::ONE, DVec3::ONE);
        assert_eq!((r.s, r.t), (0.0, 0.0));
        let d = triangle_distance(&line, &dot);
        assert!((d.distance - DVec3::ONE.distance(DVec3::X)).abs() < 1e-15);
    }

    #[test]
    fn crossed_segments_have_perpendicular_distance() {
        let r = closest_points_segments(
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.25, -1.0, 0.5),
            DVec3::new(0.25, 1.0, 0.5),
        );
        assert!((r.distance() - 0.5).abs() < 1e-15);
        assert!((r.s - 0.625).abs() < 1e-15 && (r.t - 0.5).abs() < 1e-15);
    }

    #[test]
    fn nan_input_gives_nan_distance() {
        let a = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let b = [DVec3::splat(f64::NAN), DVec3::X, DVec3::Y];
        assert!(triangle_distance(&a, &b).distance.is_nan());
        assert!(triangle_distance(&b, &a).distance.is_nan());
        let nan = DVec3::new(0.0, f64::NAN, 0.0);
        assert!(closest_point_on_triangle(nan, &a).0.is_nan());
        assert!(closest_point_on_triangle(DVec3::ONE, &b).0.is_nan());
        for k in 0..4 {
            let mut pts = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE];
            pts[k] = nan;
            let r = closest_points_segments(pts[0], pts[1], pts[2], pts[3]);
            assert!(r.distance().is_nan(), "{k}");
        }
    }

    proptest! {
        #[test]
        fn point_triangle_matches_sampling(p in arb_point(), t in arb_tri()) {
            let d = point_triangle_distance(p, &t);
            let s = samples(&t, 40);
            let sampled = s.iter().map(|x| (*x - p).length()).fold(f64::INFINITY, f64::min);
            // Exact minimum <= any sample; grid spacing bounds the gap.
            prop_assert!(d <= sampled + 1e-12);
            prop_assert!(sampled - d <= longest_edge(&t) / 40.0 + 1e-12);
        }

        #[test]
        fn segment_segment_matches_sampling(p1 in arb_point(), q1 in arb_point(),
                                            p2 in arb_point(), q2 in arb_point()) {
            let r = closest_points_segments(p1, q1, p2, q2);
            prop_assert!((0.0..=1.0).contains(&r.s) && (0.0..=1.0).contains(&r.t));
            prop_assert!((r.point_a - (p1 + (q1 - p1) * r.s)).length() < 1e-12);
            let n = 400;
            let mut sampled = f64::INFINITY;
            for i in 0..=n {
                // Exact distance from sample on segment 1 to segment 2 (a point
                // is a zero-length segment), so only one side is sampled.
                let x = p1 + (q1 - p1) * (i as f64 / n as f64);
                let y = closest_points_segments(x, x, p2, q2);
                sampled = sampled.min(y.distance());
            }
            prop_assert!(r.distance() <= sampled + 1e-12);
            prop_assert!(sampled - r.distance() <= (q1 - p1).length() / n as f64 + 1e-12);
        }

        #[test]
        fn triangle_distance_matches_brute_force(a in arb_tri(), b in arb_tri(),
                                                 shift in arb_point()) {
            let b = b.map(|p| p + shift * 1.5);
            let d = triangle_distance(&a, &b);
            let n = 24;
            // Upper bound and resolution-limited lower bound from exact
            // point-triangle distances of samples of either triangle.
            let from_a = samples(&a, n).iter().map(|&x| point_triangle_distance(x, &b)).fold(f64::INFINITY, f64::min);
            let from_b = samples(&b, n).iter().map(|&x| point_triangle_distance(x, &a)).fold(f64::INFINITY, f64::min);
            let sampled = from_a.min(from_b);
            prop_assert!(d.distance <= sampled + 1e-12, "{} > {}", d.distance, sampled);
            let res = longest_edge(&a).min(longest_edge(&b)) / n as f64;
            prop_assert!(sampled - d.distance <= res + 1e-12);
            // Witness points realise the distance and lie on their triangles.
            prop_assert!(((d.point_a - d.point_b).length() - d.distance).abs() < 1e-9);
            prop_assert!(point_triangle_distance(d.point_a, &a) < 1e-9);
            prop_assert!(point_triangle_distance(d.point_b, &b) < 1e-9);
            // Zero exactly when the triangles overlap.
            prop_assert_eq!(d.distance == 0.0, tri_tri_overlap(&a, &b));
            // Symmetric in A and B.
            let e = triangle_distance(&b, &a);
            prop_assert!((e.distance - d.distance).abs() < 1e-12);
        }

        #[test]
        fn triangle_distance_is_rigid_invariant(a in arb_tri(), b in arb_tri(),
                                                 axis in arb_point(), angle in -3.0f64..3.0,
                                                 shift in arb_point()) {
            let q = DQuat::from_axis_angle(axis.try_normalize().unwrap_or(DVec3::Z), angle);
            let m = |p: DVec3| q * p + shift;
            let d0 = triangle_distance(&a, &b).distance;
            let d1 = triangle_distance(&a.map(m), &b.map(m)).distance;
            prop_assert!((d0 - d1).abs() < 1e-9, "{} vs {}", d0, d1);
        }
    }

    // Triangles written out in full, like the cases in tri_contact.rs's tests:
    // each literal is the geometry under test.
    #[test]
    fn piercing_triangles_report_zero_and_the_crossing_point() {
        let a = [
            DVec3::new(-1.0, -1.0, 0.0),
            DVec3::new(2.0, -1.0, 0.0),
            DVec3::new(-1.0, 2.0, 0.0),
        ];
        // A thin vertical triangle whose lower edge is not in A but whose body
        // crosses A's interior: no vertex/edge pair is at distance 0.
        let b = [
            DVec3::new(0.0, -0.2, -1.0),
            DVec3::new(0.0, 0.2, -1.0),
            DVec3::new(0.0, 0.0, 1.0),
        ];
        let d = triangle_distance(&a, &b);
        assert_eq!(d.distance, 0.0);
        assert_eq!(d.point_a, d.point_b);
        assert!(d.point_a.z.abs() < 1e-15 && d.point_a.x.abs() < 1e-15);
        assert_eq!(d.feature_a, SubFeature::Face);
    }
}
