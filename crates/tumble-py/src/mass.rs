//! `tumble.mass_properties`: volume, mass, centre of mass, inertia tensor and
//! principal frame of a closed mesh (Mirtich 1996 via
//! `tumble_collide::mass`), with the explicit fallbacks for meshes that are
//! not solids. The result is the `MassProperties` named tuple of
//! `tumble/_records.py`.

use crate::convert::{self, matrix_out, vec_out};
use crate::errors::{guard, invalid, OrRaise};
use crate::records::record;
use crate::trimesh::{mesh_from_arrays, mesh_from_object};
use pyo3::prelude::*;
use tumble_collide::mass::{mesh_mass_report, MassFallback, MassMethod, MassSpec};
use tumble_collide::DMat3;

fn mat_rows(m: &DMat3) -> Vec<f64> {
    // glam stores columns; numpy wants rows.
    let t = m.transpose();
    t.to_cols_array().to_vec()
}

fn fallback_from(obj: Option<&Bound<'_, PyAny>>, thickness: Option<f64>) -> PyResult<MassFallback> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(MassFallback::None);
    };
    let name: String = obj.extract().map_err(|_| {
        invalid(format!(
            "fallback: expected None, \"convex_hull\" or \"shell\", got {}",
            convert::describe(obj)
        ))
    })?;
    match name.as_str() {
        "convex_hull" => Ok(MassFallback::ConvexHull),
        "shell" => match thickness {
            Some(thickness) => Ok(MassFallback::Shell { thickness }),
            None => Err(invalid("fallback=\"shell\" needs shell_thickness (m)")),
        },
        other => Err(invalid(format!(
            "fallback: expected None, \"convex_hull\" or \"shell\", got {other:?}"
        ))),
    }
}

/// Mass properties of the solid bounded by a closed, outward-wound mesh.
///
/// Args:
///     vertices: (N, 3) array (m), or a TriMesh / trimesh.Trimesh (then
///         leave `faces` out).
///     faces: (M, 3) integer array of vertex indices.
///     density: uniform density (kg/m^3). Give `density` or `mass`; default
///         density 1000.
///     mass: total mass (kg) instead of a density.
///     fallback: what to do if the mesh is not a solid: None (raise
///         InvalidArgument, the default), "convex_hull" (use the hull of the
///         vertices) or "shell" (a thin shell of `shell_thickness` m).
///     shell_thickness: wall thickness for fallback="shell" (m).
///
/// Returns:
///     MassProperties(volume, mass, com, inertia, principal_moments,
///     principal_axes, method): inertia is the 3x3 tensor about the centre of
///     mass in the mesh's axes; principal_axes has the axes as columns, in
///     the order of the ascending principal_moments, so that
///     inertia = axes @ diag(moments) @ axes.T.
#[pyfunction]
#[pyo3(signature = (vertices, faces=None, *, density=None, mass=None, fallback=None, shell_thickness=None))]
pub fn mass_properties<'py>(
    py: Python<'py>,
    vertices: &Bound<'py, PyAny>,
    faces: Option<&Bound<'py, PyAny>>,
    density: Option<f64>,
    mass: Option<f64>,
    fallback: Option<&Bound<'py, PyAny>>,
    shell_thickness: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let mesh = match faces.filter(|f| !f.is_none()) {
            Some(f) => mesh_from_arrays(vertices, f)?,
            None => mesh_from_object(vertices, "vertices")?,
        };
        let spec = match (density, mass) {
            (Some(_), Some(_)) => return Err(invalid("give density or mass, not both")),
            (Some(d), None) => MassSpec::Density(d),
            (None, Some(m)) => MassSpec::Mass(m),
            (None, None) => MassSpec::Density(1000.0),
        };
        let fallback = fallback_from(fallback, shell_thickness)?;
        let report = mesh_mass_report(&mesh, spec, fallback).or_raise()?;
        let p = report.properties;
        let frame = p.principal();
        let axes = DMat3::from_quat(frame.rotation);
        let method = match report.method {
            MassMethod::Solid => "solid",
            MassMethod::ConvexHull => "convex_hull",
            MassMethod::Shell => "shell",
        };
        let inertia = matrix_out(py, mat_rows(&p.inertia), 3);
        let axes = matrix_out(py, mat_rows(&axes), 3);
        let moments = vec_out(py, frame.moments);
        let com = vec_out(py, p.com);
        record(
            py,
            "MassProperties",
            (report.measure, p.mass, com, inertia, moments, axes, method),
        )
    })
}
