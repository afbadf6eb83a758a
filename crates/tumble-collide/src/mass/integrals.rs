//! Exact integrals of 1, x and x x^T over a polyhedron (by signed tetrahedra)
//! and over a triangulated surface (by triangles), and their conversion to
//! mass properties.
//!
//! Solids follow Mirtich, "Fast and accurate computation of polyhedral mass
//! properties" (JGT 1996) in its divergence-theorem form as simplified by
//! Eberly, "Polyhedral Mass Properties (Revisited)" (2002): each outward
//! triangle (a, b, c) and the reference point span a signed tetrahedron of
//! volume D/6, `D = a . (b x c)`, and the polyhedron integrals are the sums
//! over triangles. For a tetrahedron with one vertex at the origin the second
//! moment is (Tonon, J. Math. Stat. 2004, eq. 2, with the zero vertex dropped)
//!
//!   int x x^T dV = D/120 (a a^T + b b^T + c c^T + s s^T),  s = a + b + c,
//!
//! and the first moment is D/24 s. Outside the body the signed tetrahedra
//! cancel exactly, so the sums are exact for any closed, consistently wound
//! mesh (not only convex ones).
//!
//! Surfaces (thin shells) use the same identity one dimension down: for a
//! triangle of area A, `int x dA = A s / 3` and
//! `int x x^T dA = A/12 (a a^T + b b^T + c c^T + s s^T)`.
//!
//! Why two passes: the second moment about the centre of mass equals
//! `S - V c c^T`, which cancels catastrophically when the mesh sits far from
//! the reference point. Integrating once about the bounding-box centre to find
//! `c`, then again about `c`, keeps full precision at any offset.

use super::properties::outer;
use super::{MassError, MassProperties};
use crate::math::{symmetrize, DMat3, DVec3};
use crate::mesh::TriMesh;

/// Integrals of one unit of density about a reference point.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Moments {
    /// Volume (m^3) or area (m^2).
    pub measure: f64,
    /// `int (x - ref) dV`.
    pub first: DVec3,
    /// `int (x - ref)(x - ref)^T dV`.
    pub second: DMat3,
    /// Sum of |contributions| to `measure`: the scale against which round-off
    /// in `measure` is judged.
    pub abs_measure: f64,
}

/// Which integral to take.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Domain {
    /// The solid bounded by the mesh.
    Solid,
    /// The mesh surface itself (a lamina).
    Surface,
}

fn corner_sum(a: DVec3, b: DVec3, c: DVec3) -> DMat3 {
    let s = a + b + c;
    outer(a, a) + outer(b, b) + outer(c, c) + outer(s, s)
}

/// Integrals over the solid or the surface of `mesh`, about `reference`.
pub(crate) fn integrate(mesh: &TriMesh, domain: Domain, reference: DVec3) -> Moments {
    let mut measure = 0.0;
    let mut abs_measure = 0.0;
    let mut first = DVec3::ZERO;
    let mut second = DMat3::ZERO;
    for t in 0..mesh.triangles().len() {
        let [a, b, c] = mesh.triangle(t);
        let (a, b, c) = (a - reference, b - reference, c - reference);
        // w = 6 x signed tetrahedron volume, or 2 x triangle area.
        let w = match domain {
            Domain::Solid => a.dot(b.cross(c)),
            Domain::Surface => (b - a).cross(c - a).length(),
        };
        measure += w;
        abs_measure += w.abs();
        first += (a + b + c) * w;
        second += corner_sum(a, b, c) * w;
    }
    let (m, f, s) = match domain {
        Domain::Solid => (6.0, 24.0, 120.0),
        Domain::Surface => (2.0, 6.0, 24.0),
    };
    Moments {
        measure: measure / m,
        first: first / f,
        second: second / s,
        abs_measure: abs_measure / m,
    }
}

/// Centre of the axis-aligned bounds: a reference point near the body.
pub(crate) fn bounds_centre(mesh: &TriMesh) -> DVec3 {
    let (lo, hi) = mesh.bounds();
    (lo + hi) * 0.5
}

/// Mass properties from integrals about the centroid `centroid` (second pass)
/// for a body of total `mass`.
pub(crate) fn to_properties(
    centroid: DVec3,
    moments: &Moments,
    mass: f64,
) -> Result<MassProperties, MassError> {
    let v = moments.measure;
    // Residual first moment of the second pass is round-off; fold it in
    // exactly anyway: C = S - F F^T / V about the true centroid.
    let shift = moments.first / v;
    let cov = moments.second - outer(moments.first, moments.first) / v;
    let cov = symmetrize(&(cov * (mass / v)));
    let trace = cov.x_axis.x + cov.y_axis.y + cov.z_axis.z;
    // I = int (|r|^2 E - r r^T) dm = tr(C) E - C.
    let inertia = DMat3::from_diagonal(DVec3::splat(trace)) - cov;
    let com = centroid + shift;
    if !com.is_finite() {
        return Err(MassError::NonFiniteResult {
            what: "centre of mass",
        });
    }
    if !inertia.is_finite() {
        return Err(MassError::NonFiniteResult { what: "inertia" });
    }
    Ok(MassProperties { mass, com, inertia })
}
