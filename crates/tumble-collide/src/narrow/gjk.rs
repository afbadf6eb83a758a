//! GJK distance between two convex sets given by support maps (Gilbert,
//! Johnson, Keerthi 1988; van den Bergen 2003, ch. 4; Ericson 9.5).
//!
//! The closest point of the simplex to the origin is found by Johnson's
//! sub-algorithm in its plainest form: every sub-simplex (at most 15) is
//! projected affinely and the closest projection with non-negative barycentric
//! weights wins. That is slower than the signed-volume form but short and
//! robust, and the simplices here have at most 4 points.

use crate::math::{DMat3, DVec3};
use crate::shape::Polytope;

/// Something with a support function in a common frame.
pub(crate) trait SupportMap {
    /// A point of the set farthest along `dir`.
    fn support(&self, dir: DVec3) -> DVec3;
}

/// A segment (or a point, when both ends coincide).
pub(crate) struct SegmentSupport(pub [DVec3; 2]);

impl SupportMap for SegmentSupport {
    fn support(&self, dir: DVec3) -> DVec3 {
        if (self.0[1] - self.0[0]).dot(dir) > 0.0 {
            self.0[1]
        } else {
            self.0[0]
        }
    }
}

/// A polytope seen through a rigid map `x -> rot x + trans`.
pub(crate) struct PolytopeSupport<'a, P: Polytope + ?Sized> {
    pub poly: &'a P,
    pub rot: DMat3,
    pub trans: DVec3,
}

impl<P: Polytope + ?Sized> SupportMap for PolytopeSupport<'_, P> {
    fn support(&self, dir: DVec3) -> DVec3 {
        let local = self.rot.transpose() * dir;
        self.rot * self.poly.vertex(self.poly.support_vertex(local)) + self.trans
    }
}

/// Result of [`gjk_distance`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct GjkResult {
    /// Distance between the sets (m); 0 when they overlap.
    pub distance: f64,
    /// Closest point on A.
    pub point_a: DVec3,
    /// Closest point on B.
    pub point_b: DVec3,
    /// The sets overlap (or touch within the tolerance).
    pub overlap: bool,
}

#[derive(Clone, Copy, Default)]
struct Vertex {
    w: DVec3,
    a: DVec3,
    b: DVec3,
}

/// Distance and closest points between convex sets A and B. `scale` is a
/// length typical of the shapes (m), used for the touching tolerance.
pub(crate) fn gjk_distance(a: &impl SupportMap, b: &impl SupportMap, scale: f64) -> GjkResult {
    let mut simplex = [Vertex::default(); 4];
    let mut n = 1;
    let a0 = a.support(DVec3::X);
    let b0 = b.support(-DVec3::X);
    simplex[0] = Vertex {
        w: a0 - b0,
        a: a0,
        b: b0,
    };
    let mut lambda = [1.0, 0.0, 0.0, 0.0];
    let mut v = simplex[0].w;
    let touch = 1e-10 * scale.max(f64::MIN_POSITIVE);
    let mut overlap = false;
    for _ in 0..64 {
        let vv = v.length_squared();
        if vv <= touch * touch {
            overlap = true;
            break;
        }
        let sa = a.support(-v);
        let sb = b.support(v);
        let w = sa - sb;
        // Converged: the new support point does not get closer than v
        // (relative duality gap, van den Bergen 4.3.3).
        if vv - v.dot(w) <= 1e-12 * vv {
            break;
        }
        if simplex[..n].iter().any(|s| s.w == w) {
            break;
        }
        simplex[n] = Vertex { w, a: sa, b: sb };
        n += 1;
        let Some((new_v, lam, mask)) = closest_on_simplex(&simplex[..n]) else {
            n -= 1;
            break;
        };
        if new_v.length_squared() >= vv {
            // No progress (round-off): keep the previous simplex and answer.
            n -= 1;
            break;
        }
        // Keep the vertices of the sub-simplex that holds the closest point.
        let mut m = 0;
        for i in 0..n {
            if mask & (1 << i) != 0 {
                simplex[m] = simplex[i];
                lambda[m] = lam[i];
                m += 1;
            }
        }
        n = m;
        v = new_v;
        if n == 4 {
            overlap = true;
            break;
        }
    }
    let mut pa = DVec3::ZERO;
    let mut pb = DVec3::ZERO;
    for i in 0..n {
        pa += simplex[i].a * lambda[i];
        pb += simplex[i].b * lambda[i];
    }
    GjkResult {
        distance: if overlap { 0.0 } else { v.length() },
        point_a: pa,
        point_b: pb,
        overlap,
    }
}

/// Closest point of the simplex hull to the origin: `(point, weights, mask of
/// the vertices used)`.
fn closest_on_simplex(s: &[Vertex]) -> Option<(DVec3, [f64; 4], u8)> {
    let n = s.len();
    let mut best: Option<(DVec3, [f64; 4], u8)> = None;
    let mut best_d = f64::INFINITY;
    for mask in 1u8..(1 << n) {
        let mut idx = [0usize; 4];
        let mut k = 0;
        for (i, slot) in (0..n).filter(|i| mask & (1 << i) != 0).zip(0..) {
            idx[slot] = i;
            k += 1;
        }
        let p0 = s[idx[0]].w;
        let mut lam = [0.0f64; 4];
        let ok = match k {
            1 => {
                lam[0] = 1.0;
                true
            }
            2 => {
                let e = s[idx[1]].w - p0;
                let g = e.length_squared();
                if g <= 1e-30 {
                    false
                } else {
                    let mu = -e.dot(p0) / g;
                    lam[0] = 1.0 - mu;
                    lam[1] = mu;
                    true
                }
            }
            3 => {
                let e1 = s[idx[1]].w - p0;
                let e2 = s[idx[2]].w - p0;
                let (g11, g12, g22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
                let det = g11 * g22 - g12 * g12;
                if det <= 1e-12 * g11 * g22 || det <= 0.0 {
                    false
                } else {
                    let (r1, r2) = (-e1.dot(p0), -e2.dot(p0));
                    let m1 = (r1 * g22 - r2 * g12) / det;
                    let m2 = (g11 * r2 - g12 * r1) / det;
                    lam[0] = 1.0 - m1 - m2;
                    lam[1] = m1;
                    lam[2] = m2;
                    true
                }
            }
            _ => {
                let e1 = s[idx[1]].w - p0;
                let e2 = s[idx[2]].w - p0;
                let e3 = s[idx[3]].w - p0;
                let g = DMat3::from_cols(
                    DVec3::new(e1.dot(e1), e2.dot(e1), e3.dot(e1)),
                    DVec3::new(e1.dot(e2), e2.dot(e2), e3.dot(e2)),
                    DVec3::new(e1.dot(e3), e2.dot(e3), e3.dot(e3)),
                );
                let det = g.determinant();
                let diag = g.x_axis.x * g.y_axis.y * g.z_axis.z;
                if det <= 1e-10 * diag || det <= 0.0 {
                    false
                } else {
                    let mu = g.inverse() * DVec3::new(-e1.dot(p0), -e2.dot(p0), -e3.dot(p0));
                    lam[0] = 1.0 - mu.x - mu.y - mu.z;
                    lam[1] = mu.x;
                    lam[2] = mu.y;
                    lam[3] = mu.z;
                    true
                }
            }
        };
        if !ok || lam[..k].iter().any(|&l| l < 0.0) {
            continue;
        }
        let mut p = DVec3::ZERO;
        for j in 0..k {
            p += s[idx[j]].w * lam[j];
        }
        let d = p.length_squared();
        if d < best_d {
            best_d = d;
            let mut full = [0.0; 4];
            for j in 0..k {
                full[idx[j]] = lam[j];
            }
            best = Some((p, full, mask));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::Cuboid;

    #[test]
    fn box_to_point_distance_matches_clamp() {
        let b = Cuboid::new(DVec3::new(1.0, 0.5, 0.25)).unwrap();
        let pb = PolytopeSupport {
            poly: &b,
            rot: DMat3::IDENTITY,
            trans: DVec3::ZERO,
        };
        for p in [
            DVec3::new(3.0, 0.2, 0.1),
            DVec3::new(2.0, 2.0, 0.0),
            DVec3::new(-2.0, -1.0, 3.0),
            DVec3::new(0.1, 0.1, 0.1),
        ] {
            let r = gjk_distance(&SegmentSupport([p, p]), &pb, 1.0);
            let q = p.clamp(-b.half_extents(), b.half_extents());
            assert!((r.distance - (p - q).length()).abs() < 1e-9, "{p}");
            if !r.overlap {
                assert!((r.point_b - q).length() < 1e-7);
            }
        }
    }
}
