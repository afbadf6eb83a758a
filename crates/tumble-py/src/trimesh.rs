//! `TriMesh`: a validated triangle mesh from numpy arrays, files, the
//! generators of `tumble_collide::mesh`, or any `trimesh.Trimesh`-like
//! object (duck-typed on `.vertices` / `.faces`, so trimesh is optional).
//! Its OBBTree is built on first use as a body shape and shared by every
//! body made from it. Its getters, `__reduce__` and `__repr__` follow the
//! shape classes' (see shapes.rs): pyo3 methods belong to one class each.

use crate::convert::{self, describe, vec3};
use crate::errors::{guard, invalid, OrRaise};
use numpy::PyArray2;
use pyo3::prelude::*;
use pyo3::types::{PyTuple, PyType};
use std::path::PathBuf;
use std::sync::{Arc, OnceLock};
use tumble_collide::mesh::{self, Topology};
use tumble_collide::shape::MeshShape;
use tumble_collide::TriMesh as RMesh;

/// A mesh from vertex and face arrays.
pub fn mesh_from_arrays(vertices: &Bound<'_, PyAny>, faces: &Bound<'_, PyAny>) -> PyResult<RMesh> {
    let v = convert::points(vertices, "vertices")?;
    let f = convert::faces(faces, "faces")?;
    RMesh::from_indices(v, &f).or_raise()
}

/// A mesh from a `TriMesh` or from any object with `.vertices` and `.faces`.
pub fn mesh_from_object(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<RMesh> {
    if let Ok(m) = obj.cast::<TriMesh>() {
        return Ok((*m.get().mesh).clone());
    }
    match (obj.getattr_opt("vertices")?, obj.getattr_opt("faces")?) {
        (Some(v), Some(f)) => mesh_from_arrays(&v, &f),
        _ => Err(invalid(format!(
            "{name}: expected a TriMesh or an object with .vertices and .faces (e.g. trimesh.Trimesh), got {}",
            describe(obj)
        ))),
    }
}

/// A triangle mesh (m), triangles wound counter-clockwise seen from outside.
/// Used as a body shape it collides exactly, triangle against triangle
/// (concave meshes allowed); mass from a density needs a closed mesh. Its
/// OBBTree is built on first use (as a body shape or by `tumble.collide`,
/// `distance`, `within_tolerance`) and kept: reuse the object.
///
/// Args:
///     vertices: (N, 3) array of numbers (m).
///     faces: (M, 3) array of integer vertex indices (0 <= index < N).
///     crease_angle_deg: when given, spheres and capsules touch the smooth
///         surface the mesh tessellates, blended across every edge whose
///         faces meet at no more than this angle (degrees, in (0, 180)), as
///         `TriMesh.smooth` makes it.
#[pyclass(module = "tumble", name = "TriMesh", frozen)]
pub struct TriMesh {
    pub(crate) mesh: Arc<RMesh>,
    /// The smooth surface's crease angle as given (degrees, checked), if
    /// any: kept in degrees so that a pickle gives back the same angle.
    crease_angle_deg: Option<f64>,
    shape: OnceLock<MeshShape>,
}

/// A crease angle in degrees, checked.
fn checked_crease(degrees: Option<f64>) -> PyResult<Option<f64>> {
    match degrees {
        Some(d) if !(d.is_finite() && d > 0.0 && d < 180.0) => Err(invalid(format!(
            "crease_angle_deg must be an angle in (0, 180) degrees, got {d}"
        ))),
        other => Ok(other),
    }
}

impl TriMesh {
    pub(crate) fn from_mesh(mesh: RMesh) -> TriMesh {
        TriMesh {
            mesh: Arc::new(mesh),
            crease_angle_deg: None,
            shape: OnceLock::new(),
        }
    }

    /// A `TriMesh` of the mesh `make` builds, under the panic guard: every
    /// constructor (arrays, file, trimesh object, generators) ends here.
    fn built(make: impl FnOnce() -> PyResult<RMesh>) -> PyResult<TriMesh> {
        guard(|| make().map(TriMesh::from_mesh))
    }

    /// The collision shape (OBBTree built once, then shared).
    pub(crate) fn mesh_shape(&self) -> PyResult<MeshShape> {
        self.mesh_shape_ref().cloned()
    }

    /// The collision shape, borrowed (OBBTree built on first use).
    pub(crate) fn mesh_shape_ref(&self) -> PyResult<&MeshShape> {
        if let Some(s) = self.shape.get() {
            return Ok(s);
        }
        let mut built = MeshShape::new((*self.mesh).clone()).or_raise()?;
        if let Some(degrees) = self.crease_angle_deg {
            built = built.with_smooth_surface(degrees.to_radians()).or_raise()?;
        }
        Ok(self.shape.get_or_init(|| built))
    }
}

#[pymethods]
impl TriMesh {
    #[new]
    #[pyo3(signature = (vertices, faces, crease_angle_deg=None))]
    fn new(
        vertices: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
        crease_angle_deg: Option<f64>,
    ) -> PyResult<Self> {
        let crease = checked_crease(crease_angle_deg)?;
        let mut mesh = TriMesh::built(|| mesh_from_arrays(vertices, faces))?;
        mesh.crease_angle_deg = crease;
        Ok(mesh)
    }

    /// The same mesh (shared, not copied), touched by spheres and capsules
    /// as the smooth surface it tessellates: corner normals blended across
    /// every edge whose faces meet at no more than `crease_angle_deg`
    /// (degrees, in (0, 180); 30 blends a tessellated bowl or sphere and
    /// keeps a box's or a rim's edges sharp). A ball then rolls in a
    /// faceted bowl as in a smooth one instead of losing speed at every
    /// edge. Mesh-mesh contacts stay exact, triangle against triangle.
    #[pyo3(signature = (crease_angle_deg=30.0))]
    fn smooth(&self, crease_angle_deg: f64) -> PyResult<TriMesh> {
        Ok(TriMesh {
            mesh: Arc::clone(&self.mesh),
            crease_angle_deg: checked_crease(Some(crease_angle_deg))?,
            shape: OnceLock::new(),
        })
    }

    /// The crease angle of its smooth surface (degrees), or None when
    /// bodies touch its facets as they are.
    #[getter]
    fn crease_angle_deg(&self) -> Option<f64> {
        self.crease_angle_deg
    }

    /// Loads a `.obj` or `.stl` file (ASCII or binary); all objects in the file
    /// are merged into one mesh.
    #[classmethod]
    fn from_file(_cls: &Bound<'_, PyType>, path: PathBuf) -> PyResult<Self> {
        TriMesh::built(|| mesh::load_mesh(&path).or_raise())
    }

    /// Converts a `trimesh.Trimesh` (or any object with `.vertices` and
    /// `.faces`).
    #[classmethod]
    fn from_trimesh(_cls: &Bound<'_, PyType>, mesh: &Bound<'_, PyAny>) -> PyResult<Self> {
        TriMesh::built(|| mesh_from_object(mesh, "mesh"))
    }

    /// A box with the given half extents (m): 8 vertices, 12 triangles.
    #[classmethod]
    #[pyo3(signature = (half_extents))]
    fn r#box(_cls: &Bound<'_, PyType>, half_extents: &Bound<'_, PyAny>) -> PyResult<Self> {
        let h = vec3(half_extents, "half_extents")?;
        TriMesh::built(|| mesh::box_mesh(h).or_raise())
    }

    /// A geodesic sphere of `radius` (m): an icosahedron subdivided
    /// `subdivisions` times (20 * 4^s triangles, s <= 8).
    #[classmethod]
    #[pyo3(signature = (radius, subdivisions=3))]
    fn sphere(_cls: &Bound<'_, PyType>, radius: f64, subdivisions: usize) -> PyResult<Self> {
        TriMesh::built(|| mesh::icosphere_mesh(radius, subdivisions).or_raise())
    }

    /// A UV sphere of `radius` (m): `segments` around z (>= 3), `rings` from
    /// pole to pole (>= 2).
    #[classmethod]
    #[pyo3(signature = (radius, segments=32, rings=16))]
    fn uv_sphere(_cls: &Bound<'_, PyType>, radius: f64, segments: usize, rings: usize) -> PyResult<Self> {
        TriMesh::built(|| mesh::uv_sphere_mesh(radius, segments, rings).or_raise())
    }

    /// A capped cylinder along z from -half_height to +half_height (m).
    #[classmethod]
    #[pyo3(signature = (radius, half_height, segments=32))]
    fn cylinder(_cls: &Bound<'_, PyType>, radius: f64, half_height: f64, segments: usize) -> PyResult<Self> {
        TriMesh::built(|| mesh::cylinder_mesh(radius, half_height, segments).or_raise())
    }

    // The generators are one #[classmethod] each (a Python constructor per
    // solid, with its own defaults, like `torus` below); each is a call of `built`.
    /// A capsule along z: cylinder of `radius` and `half_height` (m) with
    /// hemispherical caps of `rings` latitude bands each.
    #[classmethod]
    #[pyo3(signature = (radius, half_height, segments=24, rings=6))]
    fn capsule(
        _cls: &Bound<'_, PyType>,
        radius: f64,
        half_height: f64,
        segments: usize,
        rings: usize,
    ) -> PyResult<Self> {
        TriMesh::built(|| mesh::capsule_mesh(radius, half_height, segments, rings).or_raise())
    }

    /// A cone of base `radius` and `height` (m): base at z = -height/2, apex
    /// at +height/2.
    #[classmethod]
    #[pyo3(signature = (radius, height, segments=32))]
    fn cone(_cls: &Bound<'_, PyType>, radius: f64, height: f64, segments: usize) -> PyResult<Self> {
        TriMesh::built(|| mesh::cone_mesh(radius, height, segments).or_raise())
    }

    /// A torus around z with major radius `major_radius` and tube radius
    /// `minor_radius` (m), `major_segments` x `minor_segments` vertices (the
    /// layout of shared/scenes.md; 50 x 50 gives 5,000 triangles).
    #[classmethod]
    #[pyo3(signature = (major_radius, minor_radius, major_segments=48, minor_segments=24))]
    fn torus(
        _cls: &Bound<'_, PyType>,
        major_radius: f64,
        minor_radius: f64,
        major_segments: usize,
        minor_segments: usize,
    ) -> PyResult<Self> {
        TriMesh::built(|| {
            mesh::torus_mesh(major_radius, minor_radius, major_segments, minor_segments).or_raise()
        })
    }

    /// A hemispherical bowl: the lower half of the sphere of `inner_radius`
    /// about the origin (m), `thickness` thick, open at the top (rim at
    /// z = 0), `segments` facets around z and `rings` from rim to bottom
    /// (default segments / 2, as in scene files). A ball of radius r rests
    /// in it at z = -(inner_radius - r).
    #[classmethod]
    #[pyo3(signature = (inner_radius, thickness, segments=96, rings=None))]
    fn bowl(
        _cls: &Bound<'_, PyType>,
        inner_radius: f64,
        thickness: f64,
        segments: usize,
        rings: Option<usize>,
    ) -> PyResult<Self> {
        let rings = rings.unwrap_or((segments / 2).max(1));
        TriMesh::built(|| mesh::bowl_mesh(inner_radius, thickness, segments, rings).or_raise())
    }

    /// A half-pipe along x: the lower half of the cylinder of
    /// `inner_radius` about the x axis (m), `thickness` thick and `length`
    /// long, open at the top (rims at z = 0), `segments` facets across.
    #[classmethod]
    #[pyo3(signature = (inner_radius, thickness, length, segments=64))]
    fn half_pipe(
        _cls: &Bound<'_, PyType>,
        inner_radius: f64,
        thickness: f64,
        length: f64,
        segments: usize,
    ) -> PyResult<Self> {
        TriMesh::built(|| mesh::half_pipe_mesh(inner_radius, thickness, length, segments).or_raise())
    }

    /// Vertex positions (m), float64 array of shape (N, 3) (a copy).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let data = self.mesh.vertices().iter().flat_map(|v| v.to_array()).collect();
        convert::matrix_out(py, data, 3)
    }

    /// Triangles as vertex indices, int64 array of shape (M, 3) (a copy).
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<i64>> {
        let data = self
            .mesh
            .triangles()
            .iter()
            .flat_map(|t| t.map(i64::from))
            .collect();
        convert::index_rows_out(py, data)
    }

    /// Number of vertices.
    #[getter]
    fn vertex_count(&self) -> usize {
        self.mesh.vertices().len()
    }

    /// Number of triangles.
    #[getter]
    fn face_count(&self) -> usize {
        self.mesh.triangles().len()
    }

    // pyo3 wants one getter per attribute: these read like Capsule's
    // (shapes.rs) and World's `time`/`step_count` (world.rs), each its own class.
    /// Signed volume (m^3); the volume of the solid when the mesh is closed
    /// and wound outward.
    #[getter]
    fn volume(&self) -> f64 {
        self.mesh.signed_volume()
    }

    /// Surface area (m^2).
    #[getter]
    fn area(&self) -> f64 {
        self.mesh.surface_area()
    }

    /// Axis-aligned bounds: float64 array of shape (2, 3), rows min and max (m).
    #[getter]
    fn bounds<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let (lo, hi) = self.mesh.bounds();
        convert::matrix_out(py, [lo.to_array(), hi.to_array()].concat(), 3)
    }

    /// `True` when the mesh bounds a solid: closed, manifold, consistently
    /// and outward wound, with positive volume (needed for mass from density).
    #[getter]
    fn is_solid(&self) -> bool {
        self.mesh.check_solid().is_ok()
    }

    /// `True` when every edge is shared by exactly two triangles.
    #[getter]
    fn is_closed(&self) -> bool {
        Topology::new(&self.mesh).check_closed().is_ok()
    }

    /// A `trimesh.Trimesh` with the same vertices and faces (needs trimesh).
    fn to_trimesh<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let trimesh = py.import("trimesh")?;
        let kwargs = pyo3::types::PyDict::new(py);
        kwargs.set_item("vertices", self.vertices(py))?;
        kwargs.set_item("faces", self.faces(py))?;
        kwargs.set_item("process", false)?;
        trimesh.getattr("Trimesh")?.call((), Some(&kwargs))
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let m = slf.get();
        let crease = m.crease_angle_deg().into_pyobject(py)?.into_any();
        let args = PyTuple::new(py, [m.vertices(py).into_any(), m.faces(py).into_any(), crease])?;
        PyTuple::new(py, [slf.get_type().into_any(), args.into_any()])
    }

    fn __repr__(&self) -> String {
        let smooth = match self.crease_angle_deg() {
            Some(d) => format!(", smooth at {d} deg"),
            None => String::new(),
        };
        format!(
            "tumble.TriMesh(<{} vertices, {} faces{smooth}>)",
            self.mesh.vertices().len(),
            self.mesh.triangles().len()
        )
    }
}
