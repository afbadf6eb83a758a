//! OBB axes from the area-weighted covariance of a triangle set (Gottschalk,
//! Lin & Manocha 1996, section 4; thesis 4.5.1).
//!
//! Why the hull and why areas: the covariance of the bare vertices depends on
//! how densely each region is sampled, so a finely meshed corner would swing
//! the box. Integrating over the surface of the convex hull removes both the
//! sampling and the interior points. For a triangle (p, q, r) with area A and
//! centroid m the surface second moment is
//! `A / 12 (9 m m^T + p p^T + q q^T + r r^T)`; summing, dividing by the total
//! area and subtracting `mu mu^T` gives the covariance whose eigenvectors are
//! the box axes.

use crate::hull::hull_triangles;
use crate::math::{sym_eigen, DMat3, DVec3};

/// Area-weighted covariance of a set of triangles: `(total area, mean, C)`,
/// or `None` when the total area is zero relative to the triangles' size.
pub fn triangle_covariance(tris: impl IntoIterator<Item = [DVec3; 3]>) -> Option<(f64, DVec3, DMat3)> {
    let mut iter = tris.into_iter().peekable();
    // Work relative to one vertex: the moments then do not lose digits when the
    // mesh sits far from the origin.
    let origin = iter.peek()?[0];
    let mut area = 0.0;
    let mut first = DVec3::ZERO;
    let mut second = DMat3::ZERO;
    let mut len2 = 0.0f64;
    for [p, q, r] in iter {
        let (p, q, r) = (p - origin, q - origin, r - origin);
        let a = 0.5 * (q - p).cross(r - p).length();
        let m = (p + q + r) / 3.0;
        len2 = len2.max((q - p).length_squared()).max((r - p).length_squared());
        area += a;
        first += m * a;
        let outer = |v: DVec3| DMat3::from_cols(v * v.x, v * v.y, v * v.z);
        second += (outer(m) * 9.0 + outer(p) + outer(q) + outer(r)) * (a / 12.0);
    }
    // Written so that a NaN area also counts as degenerate.
    if area.is_nan() || area <= 1e-14 * len2 {
        return None;
    }
    let mu = first / area;
    let outer_mu = DMat3::from_cols(mu * mu.x, mu * mu.y, mu * mu.z);
    let cov = second * (1.0 / area) - outer_mu;
    // Coordinates near f64::MAX overflow the second moments: treat as degenerate
    // rather than hand NaN axes to the box.
    if !cov.is_finite() || !mu.is_finite() {
        return None;
    }
    Some((area, mu + origin, cov))
}

/// Where the box axes came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxesSource {
    /// Covariance of the convex hull's surface (the normal case).
    Hull,
    /// The hull was flat or failed: covariance of the node's own triangles.
    Triangles,
    /// Everything degenerate: the identity frame.
    Identity,
}

/// OBB axes for the triangles `tris` whose distinct vertices are `points`:
/// eigenvectors of the hull covariance, falling back to the triangles
/// themselves and then to the identity (a rotation in every case).
pub fn fit_axes(points: &[DVec3], tris: impl IntoIterator<Item = [DVec3; 3]>) -> (DMat3, AxesSource) {
    if let Ok(hull) = hull_triangles(points) {
        let cov = triangle_covariance(hull.iter().map(|t| t.map(|i| points[i as usize])));
        if let Some((_, _, c)) = cov {
            return (sym_eigen(&c).1, AxesSource::Hull);
        }
    }
    match triangle_covariance(tris) {
        Some((_, _, c)) => (sym_eigen(&c).1, AxesSource::Triangles),
        None => (DMat3::IDENTITY, AxesSource::Identity),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{approx_eq, DQuat};
    use crate::mesh::box_mesh;

    #[test]
    fn covariance_of_a_square_matches_the_integral() {
        // Unit square [0,1]^2 in z = 0 as two triangles: variance 1/12 in x and y.
        let t = [
            [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0)],
            [DVec3::ZERO, DVec3::new(1.0, 1.0, 0.0), DVec3::Y],
        ];
        let (area, mu, c) = triangle_covariance(t).unwrap();
        assert!(approx_eq(area, 1.0, 1e-15));
        assert!((mu - DVec3::new(0.5, 0.5, 0.0)).length() < 1e-15);
        assert!(approx_eq(c.x_axis.x, 1.0 / 12.0, 1e-14));
        assert!(approx_eq(c.y_axis.y, 1.0 / 12.0, 1e-14));
        assert!(c.x_axis.y.abs() < 1e-15 && c.z_axis.z.abs() < 1e-15);
    }

    #[test]
    fn axes_of_a_rotated_box_are_its_edges() {
        let q = DQuat::from_euler(glam::EulerRot::XYZ, 0.4, -0.9, 1.3);
        let m = box_mesh(DVec3::new(0.5, 1.0, 3.0))
            .unwrap()
            .map_vertices(|v| q * v + DVec3::new(10.0, -4.0, 2.0))
            .unwrap();
        let tris = (0..m.triangles().len()).map(|t| m.triangle(t));
        let (axes, src) = fit_axes(m.vertices(), tris);
        assert_eq!(src, AxesSource::Hull);
        // Distinct extents: each box edge direction is an eigenvector.
        for k in 0..3 {
            let e = q * DVec3::AXES[k];
            let best = (0..3).map(|j| axes.col(j).dot(e).abs()).fold(0.0, f64::max);
            assert!(best > 1.0 - 1e-10, "axis {k}: {best}");
        }
    }

    #[test]
    fn flat_and_empty_inputs_fall_back() {
        let pts = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let (axes, src) = fit_axes(&pts, [[pts[0], pts[1], pts[2]]]);
        assert_eq!(src, AxesSource::Triangles);
        // The smallest-variance axis is the triangle's normal.
        assert!(axes.col(0).z.abs() > 1.0 - 1e-12);
        let line = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
        let (axes, src) = fit_axes(&line, [[line[0], line[1], line[2]]]);
        assert_eq!(src, AxesSource::Identity);
        assert_eq!(axes, DMat3::IDENTITY);
    }
}
