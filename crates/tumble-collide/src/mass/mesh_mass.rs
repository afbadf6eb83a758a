//! The entry point for meshes: the solid's mass properties, or an explicitly
//! requested approximation when the mesh does not bound a solid.

use super::polyhedron::solid_mass_properties;
use super::shell::shell_mass_properties;
use super::{MassError, MassProperties, MassSpec};
use crate::hull::convex_hull;
use crate::mesh::TriMesh;
use serde::{Deserialize, Serialize};

/// What to do when a mesh is not a closed, outward-wound solid (open,
/// non-manifold, inconsistently wound, or no positive volume). Never applied
/// silently: the caller chooses it and [`MassReport`] says whether it was used.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub enum MassFallback {
    /// Return the error (the default).
    #[default]
    None,
    /// Use the solid convex hull of the vertices. With a density, the mass is
    /// that of the hull (larger than the mesh's for non-convex shapes).
    ConvexHull,
    /// Treat the surface as a thin shell of `thickness` (m).
    Shell {
        /// Wall thickness (m), finite and > 0.
        thickness: f64,
    },
}

/// Which computation produced a [`MassReport`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum MassMethod {
    /// The exact solid bounded by the mesh.
    Solid,
    /// The solid convex hull of the vertices (fallback).
    ConvexHull,
    /// A thin shell over the surface (fallback).
    Shell,
}

/// Mass properties and how they were obtained.
#[derive(Debug, Clone, PartialEq)]
pub struct MassReport {
    /// The result.
    pub properties: MassProperties,
    /// Which computation gave it.
    pub method: MassMethod,
    /// Volume (m^3, `Solid` and `ConvexHull`) or area (m^2, `Shell`) used.
    pub measure: f64,
    /// Why the solid computation was refused, when a fallback was used.
    pub fallback_reason: Option<MassError>,
}

/// Mass properties of `mesh` as a uniform solid, or by `fallback` when it is
/// not one; see [`mesh_mass_report`] to learn which.
pub fn mesh_mass_properties(
    mesh: &TriMesh,
    spec: MassSpec,
    fallback: MassFallback,
) -> Result<MassProperties, MassError> {
    mesh_mass_report(mesh, spec, fallback).map(|r| r.properties)
}

/// Like [`mesh_mass_properties`], also reporting the method used and why a
/// fallback was needed. Bad specs and fallback parameters are errors even
/// when the fallback is not needed, so that they never lie in wait.
pub fn mesh_mass_report(
    mesh: &TriMesh,
    spec: MassSpec,
    fallback: MassFallback,
) -> Result<MassReport, MassError> {
    spec.validate()?;
    if let MassFallback::Shell { thickness } = fallback {
        if !(thickness.is_finite() && thickness > 0.0) {
            return Err(MassError::BadThickness(thickness));
        }
    }
    let reason = match solid_mass_properties(mesh, spec) {
        Ok((properties, measure)) => {
            return Ok(MassReport {
                properties,
                method: MassMethod::Solid,
                measure,
                fallback_reason: None,
            })
        }
        Err(e) if e.is_not_solid() && fallback != MassFallback::None => e,
        Err(e) => return Err(e),
    };
    let (properties, measure, method) = match fallback {
        MassFallback::None => unreachable!("handled above"),
        MassFallback::ConvexHull => {
            let hull = convex_hull(mesh.vertices())?;
            let (p, v) = solid_mass_properties(&hull, spec)?;
            (p, v, MassMethod::ConvexHull)
        }
        MassFallback::Shell { thickness } => {
            let (p, a) = shell_mass_properties(mesh, thickness, spec)?;
            (p, a, MassMethod::Shell)
        }
    };
    Ok(MassReport {
        properties,
        method,
        measure,
        fallback_reason: Some(reason),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mass::primitives::solid_box;
    use crate::math::{max_abs_diff_mat, DVec3};
    use crate::mesh::{box_mesh, MeshError};

    fn open_box() -> TriMesh {
        let full = box_mesh(DVec3::new(1.0, 2.0, 0.5)).unwrap();
        let tris = full.triangles()[..10].to_vec(); // drop the +x face
        TriMesh::new(full.vertices().to_vec(), tris).unwrap()
    }

    #[test]
    fn errors_for_meshes_that_are_not_solids() {
        let d = MassSpec::Density(1.0);
        let none = MassFallback::None;
        assert!(matches!(
            mesh_mass_properties(&open_box(), d, none),
            Err(MassError::NotSolid(MeshError::Open { .. }))
        ));
        let flipped = box_mesh(DVec3::ONE).unwrap().flipped();
        assert!(matches!(
            mesh_mass_properties(&flipped, d, none),
            Err(MassError::NonPositiveVolume { volume }) if volume < 0.0
        ));
        let full = box_mesh(DVec3::ONE).unwrap();
        let mut tris = full.triangles().to_vec();
        tris[5] = [tris[5][0], tris[5][2], tris[5][1]];
        let inconsistent = TriMesh::new(full.vertices().to_vec(), tris).unwrap();
        assert!(matches!(
            mesh_mass_properties(&inconsistent, d, none),
            Err(MassError::NotSolid(MeshError::InconsistentWinding { .. }))
        ));
        let mut tris = full.triangles().to_vec();
        tris.push(tris[0]);
        tris.push([tris[0][0], tris[0][2], tris[0][1]]);
        let non_manifold = TriMesh::new(full.vertices().to_vec(), tris).unwrap();
        assert!(matches!(
            mesh_mass_properties(&non_manifold, d, none),
            Err(MassError::NotSolid(MeshError::NonManifold { .. }))
        ));
    }

    #[test]
    fn errors_for_bad_specs() {
        let m = box_mesh(DVec3::ONE).unwrap();
        for spec in [
            MassSpec::Density(-1.0),
            MassSpec::Density(0.0),
            MassSpec::Density(f64::INFINITY),
            MassSpec::Mass(f64::NAN),
            MassSpec::Mass(0.0),
        ] {
            assert!(matches!(
                mesh_mass_properties(&m, spec, MassFallback::None),
                Err(MassError::BadSpec { .. })
            ));
        }
        // A bad fallback parameter is reported even for a solid mesh.
        assert_eq!(
            mesh_mass_properties(
                &m,
                MassSpec::Mass(1.0),
                MassFallback::Shell { thickness: f64::NAN }
            )
            .unwrap_err()
            .to_string(),
            MassError::BadThickness(f64::NAN).to_string()
        );
    }

    #[test]
    fn solid_mesh_ignores_fallback_and_says_so() {
        let h = DVec3::new(1.0, 2.0, 0.5);
        let r = mesh_mass_report(
            &box_mesh(h).unwrap(),
            MassSpec::Density(2.0),
            MassFallback::Shell { thickness: 0.1 },
        )
        .unwrap();
        assert_eq!(r.method, MassMethod::Solid);
        assert!(r.fallback_reason.is_none());
        let want = solid_box(h, MassSpec::Density(2.0)).unwrap();
        assert!(max_abs_diff_mat(&r.properties.inertia, &want.inertia) < 1e-12 * want.inertia.x_axis.x);
    }

    #[test]
    fn shell_fallback_on_open_mesh_is_reported() {
        let r = mesh_mass_report(
            &open_box(),
            MassSpec::Density(1000.0),
            MassFallback::Shell { thickness: 0.01 },
        )
        .unwrap();
        assert_eq!(r.method, MassMethod::Shell);
        assert!(matches!(r.fallback_reason, Some(MassError::NotSolid(_))));
        // Box 2 x 4 x 1 m: faces 8, 8, 2, 2, 4, 4 m^2; the +x face (4) is gone.
        let area = 28.0 - 4.0;
        assert!((r.measure - area).abs() < 1e-12 * area);
        assert!((r.properties.mass - 1000.0 * 0.01 * area).abs() < 1e-9);
    }

    #[test]
    fn hull_fallback_on_open_box_is_the_closed_box() {
        let h = DVec3::new(1.0, 2.0, 0.5);
        let r = mesh_mass_report(&open_box(), MassSpec::Density(3.0), MassFallback::ConvexHull).unwrap();
        assert_eq!(r.method, MassMethod::ConvexHull);
        let want = solid_box(h, MassSpec::Density(3.0)).unwrap();
        assert!((r.properties.mass - want.mass).abs() < 1e-12 * want.mass);
        assert!(r.properties.com.length() < 1e-12);
        assert!(max_abs_diff_mat(&r.properties.inertia, &want.inertia) < 1e-12 * want.inertia.z_axis.z);
    }

    #[test]
    fn hull_fallback_of_flat_points_is_a_typed_error() {
        // All vertices in one plane: no hull volume, a Hull error, not a number.
        let flat = TriMesh::new(
            vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.0)],
            vec![[0, 1, 2], [1, 3, 2]],
        )
        .unwrap();
        assert!(matches!(
            mesh_mass_properties(&flat, MassSpec::Density(1.0), MassFallback::ConvexHull),
            Err(MassError::Hull(_))
        ));
    }
}
