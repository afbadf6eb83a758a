//! A point against the smooth surface that a triangle with corner normals
//! stands for: Phong normal interpolation (Phong 1975) to find where the point
//! lies over the triangle, and Phong tessellation (Boubekeur & Alexa,
//! "Phong Tessellation", SIGGRAPH Asia 2008) for how far it is.
//!
//! A tessellated sphere or cylinder has its vertices on the curved surface
//! and its flat triangles a little inside it (a chord, the sagitta
//! `h^2 / 8R` deep for edges of length h). Measured against the flat
//! triangles, a ball rolling over the facets meets a small step at every
//! edge: its contact normal turns abruptly there, and the velocity into the
//! next facet is lost as in an inelastic impact (a tenth of its energy per
//! swing in a 96 x 48 facet bowl). Measured against the smooth surface, the
//! normal turns continuously and the surface is where the curved one is.
//!
//! - **Where**: the triangle's points `P(u) = sum u_i p_i` carry the normals
//!   `N(u) = sum u_i n_i`. The point `c` lies over `P(u)` when `c = P(u) + t
//!   N(u)`: three equations in the barycentric coordinates and the height
//!   `t`, bilinear in the products `t u_i`, solved by Newton's method from
//!   the flat projection (quadratic convergence; the normals vary by a few
//!   degrees across a facet, so four steps reach round-off). The normals
//!   at a shared edge are the edge's own, so the points over neighbouring
//!   triangles meet along the edge without a gap or an overlap (for heights
//!   below the surface's radius of curvature).
//! - **How far**: Phong tessellation moves `P(u)` to `sum u_i proj_i(P(u))`,
//!   the barycentric mean of its projections onto the corners' tangent
//!   planes, blended with the flat point by a shape factor alpha. With
//!   alpha = 1/2 a triangle whose corners lie on a sphere (or a cylinder)
//!   with their normals radial is moved onto the sphere to second order in
//!   the edge length, at its edges' midpoints and at its centroid alike
//!   (for the sphere: the offset is `|e|^2 / 4R` at alpha 1, the sagitta
//!   `|e|^2 / 8R`); Boubekeur and Alexa's 3/4 is chosen for looks.

use crate::math::{DMat3, DVec3};

/// The shape factor alpha of Phong tessellation: 1/2 puts the facets of a
/// tessellated sphere or cylinder onto it (see the module note).
pub const PHONG_SHAPE_FACTOR: f64 = 0.5;

/// A foot counts as over its triangle down to this barycentric coordinate
/// (round-off: a point over a shared edge is then over both triangles
/// rather than over neither).
pub const OVER_TRIANGLE_TOLERANCE: f64 = 1e-9;

/// Newton steps from the flat projection (each squares the error; the
/// first leaves about (t |n_i - n_j| / h)^2 of it).
const NEWTON_STEPS: usize = 4;

/// Where a point lies over a triangle's smooth surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhongPoint {
    /// Barycentric coordinates `(u0, u1, u2)` of the foot on the flat
    /// triangle; all >= 0 when the point lies over this triangle.
    pub barycentric: [f64; 3],
    /// The foot moved onto the smooth surface (Phong tessellation).
    pub surface: DVec3,
    /// Unit interpolated normal at the foot.
    pub normal: DVec3,
    /// Signed distance from the smooth surface along `normal` (negative
    /// below it).
    pub height: f64,
}

impl PhongPoint {
    /// The most negative barycentric coordinate and its corner: the point
    /// lies over the triangle when it is >= 0 (to [`OVER_TRIANGLE_TOLERANCE`]),
    /// else it lies beyond the edge opposite that corner (edge `(k + 1) % 3`,
    /// from corner `k + 1` to `k + 2`).
    pub fn worst_corner(&self) -> (usize, f64) {
        let u = self.barycentric;
        let k = if u[0] <= u[1] && u[0] <= u[2] {
            0
        } else if u[1] <= u[2] {
            1
        } else {
            2
        };
        (k, u[k])
    }

    /// `true` when the point lies over the triangle, edges included.
    pub fn is_over(&self) -> bool {
        self.worst_corner().1 >= -OVER_TRIANGLE_TOLERANCE
    }
}

/// Where `c` lies over the smooth surface of triangle `p` with unit corner
/// normals `n` (same frame), or `None` when the triangle has no area or the
/// normals do not define a foot for `c` (Newton failed to converge: `c` is
/// farther away than the surface's radius of curvature, or the normals are
/// turned against the face).
pub fn phong_point(c: DVec3, p: &[DVec3; 3], n: &[DVec3; 3]) -> Option<PhongPoint> {
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let face = e1.cross(e2);
    let area2 = face.length_squared();
    if area2.is_nan() || area2 <= 0.0 {
        return None;
    }
    let (d1, d2) = (n[1] - n[0], n[2] - n[0]);
    // Start from the flat projection along the face normal.
    let rel = c - p[0];
    let mut t = rel.dot(face) / area2.sqrt();
    let in_plane = rel - face * (rel.dot(face) / area2);
    let mut v = in_plane.cross(e2).dot(face) / area2;
    let mut w = e1.cross(in_plane).dot(face) / area2;
    let scale = e1.length().max(e2.length()).max(t.abs());
    for _ in 0..NEWTON_STEPS {
        let normal = n[0] + d1 * v + d2 * w;
        let residual = e1 * v + e2 * w + normal * t - rel;
        let jacobian = DMat3::from_cols(e1 + d1 * t, e2 + d2 * t, normal);
        let det = jacobian.determinant();
        let limit = 1e-12 * scale * scale;
        if det.is_nan() || det.abs() <= limit {
            return None;
        }
        let step = jacobian.inverse() * residual;
        (v, w, t) = (v - step.x, w - step.y, t - step.z);
    }
    let interpolated = n[0] + d1 * v + d2 * w;
    let residual = e1 * v + e2 * w + interpolated * t - rel;
    let length = interpolated.length();
    if !(residual.length() <= 1e-9 * scale && length > 0.5 && length.is_finite()) {
        return None;
    }
    let normal = interpolated / length;
    let u = [1.0 - v - w, v, w];
    let flat = p[0] + e1 * v + e2 * w;
    // Phong tessellation: the barycentric mean of the flat point's
    // projections onto the three corner tangent planes, blended by alpha.
    let mut offset = DVec3::ZERO;
    for i in 0..3 {
        offset -= n[i] * (u[i] * (flat - p[i]).dot(n[i]));
    }
    let surface = flat + offset * PHONG_SHAPE_FACTOR;
    Some(PhongPoint {
        barycentric: u,
        surface,
        normal,
        height: (c - surface).dot(normal),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::DQuat;

    fn on_sphere(radius: f64, polar: f64, azimuth: f64) -> DVec3 {
        DVec3::new(
            polar.sin() * azimuth.cos(),
            polar.sin() * azimuth.sin(),
            polar.cos(),
        ) * radius
    }

    /// A facet of a sphere of radius 2 about the origin, normals radial.
    fn sphere_facet() -> ([DVec3; 3], [DVec3; 3]) {
        let p = [
            on_sphere(2.0, 0.50, 0.10),
            on_sphere(2.0, 0.56, 0.12),
            on_sphere(2.0, 0.52, 0.18),
        ];
        (p, p.map(|x| x.normalize()))
    }

    /// Over a sphere's facet, the foot, normal and height are the sphere's
    /// own to second order in the facet size: normal radial, surface on the
    /// sphere, height = |c| - R.
    #[test]
    fn a_sphere_facet_stands_for_the_sphere() {
        let (p, n) = sphere_facet();
        let edge = (p[1] - p[0]).length();
        for (a, b, h) in [
            (0.3, 0.3, 0.1),
            (0.1, 0.7, -0.05),
            (0.6, 0.2, 0.4),
            (0.0, 0.5, 0.0),
        ] {
            let inside = p[0] * (1.0 - a - b) + p[1] * a + p[2] * b;
            let c = inside.normalize() * (2.0 + h);
            let hit = phong_point(c, &p, &n).unwrap();
            assert!(hit.barycentric.iter().all(|&u| u >= -1e-9), "{hit:?}");
            assert!((hit.normal - c.normalize()).length() < 1e-12, "{hit:?}");
            // The sagitta of this facet is edge^2 / 8R = 3.8e-4; the smooth
            // surface is on the sphere to a few percent of that.
            assert!(
                (hit.surface.length() - 2.0).abs() < 0.05 * edge * edge / 16.0,
                "{hit:?}"
            );
            assert!((hit.height - h).abs() < 0.05 * edge * edge / 16.0, "{hit:?}");
        }
    }

    /// The feet over two triangles that share an edge meet there: a point
    /// over the edge gets the same surface point, normal and height from
    /// both, and every point is over exactly one of them.
    #[test]
    fn neighbouring_facets_meet_along_their_edge() {
        let a = [
            on_sphere(2.0, 0.50, 0.10),
            on_sphere(2.0, 0.56, 0.12),
            on_sphere(2.0, 0.52, 0.18),
        ];
        let b = [a[0], on_sphere(2.0, 0.47, 0.15), a[2]];
        let (na, nb) = (a.map(|x| x.normalize()), b.map(|x| x.normalize()));
        let (mut only_a, mut only_b) = (0, 0);
        for i in 0..=40 {
            // Points along a path crossing the shared edge a[0]-a[2].
            let s = i as f64 / 40.0;
            let c = (on_sphere(2.0, 0.545 - 0.07 * s, 0.13 + 0.02 * s)).normalize() * 1.8;
            let (ha, hb) = (phong_point(c, &a, &na).unwrap(), phong_point(c, &b, &nb).unwrap());
            let over_a = ha.worst_corner().1 >= 0.0;
            let over_b = hb.worst_corner().1 >= 0.0;
            assert!(over_a || over_b, "step {i}: over neither");
            if over_a && over_b {
                assert!((ha.surface - hb.surface).length() < 1e-12);
                assert!((ha.normal - hb.normal).length() < 1e-12);
            }
            if over_a != over_b {
                // Just off the edge, the other triangle's answer continues it.
                let (on, off) = if over_a { (ha, hb) } else { (hb, ha) };
                assert!((on.normal - off.normal).length() < 0.05);
                if over_a {
                    only_a += 1;
                } else {
                    only_b += 1;
                }
            }
        }
        assert!(
            only_a > 5 && only_b > 5,
            "the path crosses the edge: {only_a} {only_b}"
        );
    }

    /// Flat corner normals give the flat answer: the face normal, the plane
    /// distance, the plain projection.
    #[test]
    fn face_normals_give_the_flat_triangle() {
        let turn = DQuat::from_rotation_x(0.4) * DQuat::from_rotation_z(1.1);
        let p = [DVec3::ZERO, DVec3::new(1.0, 0.0, 0.0), DVec3::new(0.2, 0.9, 0.0)].map(|x| turn * x);
        let face = turn * DVec3::Z;
        let c = turn * DVec3::new(0.4, 0.3, 0.25);
        let hit = phong_point(c, &p, &[face; 3]).unwrap();
        assert!((hit.normal - face).length() < 1e-15);
        assert!((hit.height - 0.25).abs() < 1e-14);
        assert!((hit.surface - turn * DVec3::new(0.4, 0.3, 0.0)).length() < 1e-14);
    }

    #[test]
    fn degenerate_triangles_and_opposed_normals_have_no_foot() {
        let p = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
        assert!(phong_point(DVec3::Z, &p, &[DVec3::Z; 3]).is_none());
        let p = [DVec3::ZERO, DVec3::X, DVec3::Y];
        // Corner normals that cancel at the centroid.
        let n = [DVec3::Z, -DVec3::Z, DVec3::X];
        assert!(phong_point(DVec3::new(0.3, 0.3, 0.1), &p, &n).is_none());
    }
}
