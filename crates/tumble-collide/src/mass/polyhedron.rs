//! Mass properties of the solid bounded by a closed triangle mesh (Mirtich
//! 1996 / Eberly 2002, see [`super::integrals`]).

use super::integrals::{bounds_centre, integrate, to_properties, Domain};
use super::{MassError, MassProperties, MassSpec};
use crate::mesh::TriMesh;

/// Relative size below which a closed mesh's volume is treated as round-off
/// noise (a flat or doubly covered surface), compared with the sum of the
/// absolute tetrahedron volumes.
const VOLUME_NOISE: f64 = 1e-10;

/// Volume (m^3), mass, centre of mass and inertia about it of the uniform
/// solid bounded by `mesh`.
///
/// The mesh must be closed, manifold and consistently wound counter-clockwise
/// seen from outside, and enclose positive volume; anything else is an error
/// ([`MassError::NotSolid`], [`MassError::NonPositiveVolume`]), never a wrong
/// number. Returns the properties and the volume.
pub fn solid_mass_properties(mesh: &TriMesh, spec: MassSpec) -> Result<(MassProperties, f64), MassError> {
    spec.validate()?;
    mesh.check_solid().map_err(MassError::from_solid_check)?;
    let pass1 = integrate(mesh, Domain::Solid, bounds_centre(mesh));
    let volume = pass1.measure;
    if !volume.is_finite() {
        return Err(MassError::NonFiniteResult { what: "volume" });
    }
    // A closed surface enclosing nothing (e.g. two triangles glued back to
    // back) sums to round-off; dividing by it would give garbage, not an error.
    if volume <= VOLUME_NOISE * pass1.abs_measure {
        return Err(MassError::NonPositiveVolume { volume });
    }
    let centroid = bounds_centre(mesh) + pass1.first / volume;
    let pass2 = integrate(mesh, Domain::Solid, centroid);
    let mass = spec.mass_for(volume)?;
    Ok((to_properties(centroid, &pass2, mass)?, volume))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mass::primitives::solid_box;
    use crate::math::{max_abs_diff_mat, DQuat, DVec3};
    use crate::mesh::box_mesh;

    fn rel_close(a: &MassProperties, b: &MassProperties, tol: f64) -> bool {
        let scale = b
            .inertia
            .to_cols_array()
            .iter()
            .fold(0.0f64, |m, x| m.max(x.abs()));
        (a.mass - b.mass).abs() <= tol * b.mass
            && (a.com - b.com).length() <= tol * (1.0 + b.com.length())
            && max_abs_diff_mat(&a.inertia, &b.inertia) <= tol * scale
    }

    #[test]
    fn box_mesh_equals_box_formula() {
        let h = DVec3::new(0.3, 1.7, 2.9);
        for spec in [MassSpec::Density(7800.0), MassSpec::Mass(3.5)] {
            let (m, v) = solid_mass_properties(&box_mesh(h).unwrap(), spec).unwrap();
            assert!((v - 8.0 * h.x * h.y * h.z).abs() < 1e-12 * v);
            assert!(rel_close(&m, &solid_box(h, spec).unwrap(), 1e-12), "{m:?}");
        }
    }

    #[test]
    fn tetrahedron_matches_closed_form() {
        // Unit corner tetrahedron: V = 1/6, com = (1/4, 1/4, 1/4); about the
        // origin int x^2 = 1/60, int xy = 1/120 (direct integration).
        let mesh = TriMesh::new(
            vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z],
            vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        )
        .unwrap();
        let (p, v) = solid_mass_properties(&mesh, MassSpec::Density(1.0)).unwrap();
        assert!((v - 1.0 / 6.0).abs() < 1e-15);
        assert!((p.com - DVec3::splat(0.25)).length() < 1e-15);
        let about0 = p.inertia_about(DVec3::ZERO);
        assert!((about0.x_axis.x - 2.0 / 60.0).abs() < 1e-15);
        assert!((about0.y_axis.x + 1.0 / 120.0).abs() < 1e-15);
    }

    #[test]
    fn flat_and_overflowing_meshes_are_errors() {
        // Two triangles back to back: closed, consistently wound, no volume.
        let flat = TriMesh::new(vec![DVec3::ZERO, DVec3::X, DVec3::Y], vec![[0, 1, 2], [0, 2, 1]]).unwrap();
        assert!(matches!(
            solid_mass_properties(&flat, MassSpec::Density(1.0)),
            Err(MassError::NonPositiveVolume { .. })
        ));
        let huge = box_mesh(DVec3::splat(1e200)).unwrap();
        assert!(matches!(
            solid_mass_properties(&huge, MassSpec::Density(1.0)),
            Err(MassError::NonFiniteResult { .. })
        ));
    }

    #[test]
    fn far_from_origin_keeps_precision() {
        let h = DVec3::new(0.5, 1.0, 2.0);
        let want = solid_box(h, MassSpec::Density(1.0)).unwrap();
        let q = DQuat::from_euler(glam::EulerRot::XYZ, 0.3, 0.2, -0.5);
        let off = DVec3::new(1e4, -2e4, 5e3);
        let mesh = box_mesh(h).unwrap().map_vertices(|v| q * v + off).unwrap();
        let (got, _) = solid_mass_properties(&mesh, MassSpec::Density(1.0)).unwrap();
        let want = want.rotated(q).translated(off);
        assert!(rel_close(&got, &want, 1e-9), "{got:?} vs {want:?}");
    }
}
