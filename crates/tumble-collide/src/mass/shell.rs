//! Mass properties of a thin shell (a lamina of uniform thickness over a
//! triangulated surface, open or closed): the thin-shell limit, with all mass
//! on the surface. Exact triangle integrals, see [`super::integrals`].

use super::integrals::{bounds_centre, integrate, to_properties, Domain};
use super::{MassError, MassProperties, MassSpec};
use crate::mesh::TriMesh;

/// Mass properties of a shell of `thickness` (m) over `mesh`.
///
/// With [`MassSpec::Density`] the mass is `density * thickness * area`; with
/// [`MassSpec::Mass`] the thickness only has to be valid. The mass is placed on
/// the surface itself (error O(thickness / size) against a real slab). Any
/// winding and open meshes are fine. Returns the properties and the area (m^2).
pub fn shell_mass_properties(
    mesh: &TriMesh,
    thickness: f64,
    spec: MassSpec,
) -> Result<(MassProperties, f64), MassError> {
    spec.validate()?;
    if !(thickness.is_finite() && thickness > 0.0) {
        return Err(MassError::BadThickness(thickness));
    }
    let reference = bounds_centre(mesh);
    let pass1 = integrate(mesh, Domain::Surface, reference);
    let area = pass1.measure;
    if !(area.is_finite() && area > 0.0) {
        return Err(MassError::ZeroArea { area });
    }
    let centroid = reference + pass1.first / area;
    let pass2 = integrate(mesh, Domain::Surface, centroid);
    let mass = spec.mass_for(thickness * area)?;
    Ok((to_properties(centroid, &pass2, mass)?, area))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{max_abs_diff_mat, DMat3, DVec3};
    use crate::mesh::{box_mesh, icosphere_mesh};

    #[test]
    fn hollow_cube_matches_lamina_formula() {
        // Six square laminae of side 2a: I = 10/9 m a^2 about every axis
        // (= 5/18 m s^2 for side s).
        let a = 0.7;
        let mesh = box_mesh(DVec3::splat(a)).unwrap();
        let (p, area) = shell_mass_properties(&mesh, 0.01, MassSpec::Density(1000.0)).unwrap();
        assert!((area - 24.0 * a * a).abs() < 1e-13);
        assert!((p.mass - 1000.0 * 0.01 * area).abs() < 1e-10);
        assert!(p.com.length() < 1e-15);
        let want = DMat3::from_diagonal(DVec3::splat(10.0 / 9.0 * p.mass * a * a));
        assert!(max_abs_diff_mat(&p.inertia, &want) < 1e-12 * want.x_axis.x);
    }

    #[test]
    fn open_box_without_lid() {
        // Five faces of a cube of half side a (top removed): the four walls
        // have their centroid at z = 0, the floor at z = -a, so com.z = -a/5.
        let a = 1.0;
        let full = box_mesh(DVec3::splat(a)).unwrap();
        // Triangles 2 and 3 are the +z face in box_mesh.
        let tris: Vec<[u32; 3]> = full
            .triangles()
            .iter()
            .enumerate()
            .filter(|(t, _)| *t != 2 && *t != 3)
            .map(|(_, &t)| t)
            .collect();
        let open = TriMesh::new(full.vertices().to_vec(), tris).unwrap();
        assert!(open.check_solid().is_err());
        let (p, area) = shell_mass_properties(&open, 0.002, MassSpec::Mass(5.0)).unwrap();
        assert!((area - 20.0 * a * a).abs() < 1e-13);
        assert!((p.com - DVec3::new(0.0, 0.0, -a / 5.0)).length() < 1e-14);
        // Izz: floor lamina m_f (2a)^2 / 6 = 2/3 m_f a^2; each wall m_w (a^2/3 + a^2).
        let (mf, mw) = (1.0, 1.0); // 5 kg over 5 equal faces
        let izz = mf * 2.0 / 3.0 * a * a + 4.0 * mw * 4.0 / 3.0 * a * a;
        assert!((p.inertia.z_axis.z - izz).abs() < 1e-12 * izz);
    }

    #[test]
    fn spherical_shell_converges_to_two_thirds_m_r2() {
        let (r, m) = (1.3, 2.0);
        let err = |s: usize| {
            let mesh = icosphere_mesh(r, s).unwrap();
            let (p, _) = shell_mass_properties(&mesh, 1e-3, MassSpec::Mass(m)).unwrap();
            let want = DMat3::from_diagonal(DVec3::splat(2.0 / 3.0 * m * r * r));
            max_abs_diff_mat(&p.inertia, &want) / want.x_axis.x
        };
        let errs: Vec<f64> = (1..=5).map(err).collect();
        assert!(errs.windows(2).all(|w| w[1] < w[0]), "{errs:?}");
        assert!(errs[4] < 2e-3, "{errs:?}");
    }

    #[test]
    fn bad_thickness_and_spec() {
        let mesh = box_mesh(DVec3::ONE).unwrap();
        assert_eq!(
            shell_mass_properties(&mesh, -1.0, MassSpec::Density(1.0)).unwrap_err(),
            MassError::BadThickness(-1.0)
        );
        assert!(matches!(
            shell_mass_properties(&mesh, 0.1, MassSpec::Density(f64::NAN)),
            Err(MassError::BadSpec { .. })
        ));
    }
}
