//! Shape classes: `Box`, `Sphere`, `Capsule`, `ConvexHull`, `HalfSpace`
//! (and `TriMesh` in [`crate::trimesh`]), the `Placed` wrapper that poses a
//! shape inside a compound body, and the conversion of whatever
//! `World.add_body` is given (a shape, a `trimesh.Trimesh`-like object, or a
//! list of those) into `ShapeDesc`s.
//!
//! Shapes are immutable values: validated once in the constructor, shared
//! by every body made from them, picklable through `__reduce__`.
//! pyo3 methods belong to one class each, so every shape class repeats the
//! same frame: a struct around its Rust shape, `new`, one-line getters, the
//! one-line `at` (placing it: `Placed::new`, written once), `__reduce__` and
//! `__repr__` (as `TriMesh` does in trimesh.rs). A shared Python base class
//! would remove some of those lines and is not worth the change of the
//! classes' identity (pickles, `isinstance`).

use crate::convert::{self, describe, quat_out, vec3, vec_out};
use crate::errors::{guard, invalid, OrRaise};
use crate::trimesh::{mesh_from_object, TriMesh};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyList, PyTuple};
use tumble::world::ShapeDesc;
use tumble_collide::shape::{Capsule as RCapsule, ConvexHull as RHull, Cuboid, HalfSpace as RHalfSpace};
use tumble_collide::shape::{MeshShape, Shape, Sphere as RSphere};
use tumble_collide::{DVec3, Pose};

fn fmt3(v: DVec3) -> String {
    format!("({}, {}, {})", v.x, v.y, v.z)
}

/// A box (cuboid) centred on its frame's origin, axis-aligned in it.
///
/// Args:
///     half_extents: half the side lengths (hx, hy, hz) in m, each finite and > 0.
#[pyclass(module = "tumble", name = "Box", frozen)]
pub struct PyBox {
    pub(crate) inner: Cuboid,
}

#[pymethods]
impl PyBox {
    #[new]
    #[pyo3(signature = (half_extents))]
    fn new(half_extents: &Bound<'_, PyAny>) -> PyResult<Self> {
        let h = vec3(half_extents, "half_extents")?;
        Ok(PyBox {
            inner: Cuboid::new(h).or_raise()?,
        })
    }

    /// Half the side lengths (m), shape (3,).
    #[getter]
    fn half_extents<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec_out(py, self.inner.half_extents())
    }

    /// This shape placed at `position` with `orientation` (x, y, z, w) in the
    /// body's model frame, for compound bodies.
    #[pyo3(signature = (position=None, orientation=None))]
    fn at(
        slf: &Bound<'_, Self>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Placed> {
        Placed::new(slf.as_any(), position, orientation)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let h = slf.get().inner.half_extents().to_array();
        PyTuple::new(
            slf.py(),
            [slf.get_type().into_any(), PyTuple::new(slf.py(), [h])?.into_any()],
        )
    }

    fn __repr__(&self) -> String {
        format!("tumble.Box(half_extents={})", fmt3(self.inner.half_extents()))
    }
}

/// A ball centred on its frame's origin.
///
/// Args:
///     radius: radius in m, finite and > 0.
#[pyclass(module = "tumble", name = "Sphere", frozen)]
pub struct PySphere {
    pub(crate) inner: RSphere,
}

#[pymethods]
impl PySphere {
    #[new]
    #[pyo3(signature = (radius))]
    fn new(radius: f64) -> PyResult<Self> {
        Ok(PySphere {
            inner: RSphere::new(radius).or_raise()?,
        })
    }

    /// Radius (m).
    #[getter]
    fn radius(&self) -> f64 {
        self.inner.radius()
    }

    /// This shape placed at `position` with `orientation` (x, y, z, w) in the
    /// body's model frame, for compound bodies.
    #[pyo3(signature = (position=None, orientation=None))]
    fn at(
        slf: &Bound<'_, Self>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Placed> {
        Placed::new(slf.as_any(), position, orientation)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let args = PyTuple::new(slf.py(), [slf.get().inner.radius()])?;
        PyTuple::new(slf.py(), [slf.get_type().into_any(), args.into_any()])
    }

    fn __repr__(&self) -> String {
        format!("tumble.Sphere(radius={})", self.inner.radius())
    }
}

/// A capsule: the points within `radius` of the segment from
/// (0, 0, -half_height) to (0, 0, +half_height), along the frame's z axis.
///
/// Args:
///     radius: radius in m, finite and > 0.
///     half_height: half the length of the core segment in m, finite and >= 0.
#[pyclass(module = "tumble", name = "Capsule", frozen)]
pub struct PyCapsule {
    pub(crate) inner: RCapsule,
}

#[pymethods]
impl PyCapsule {
    #[new]
    #[pyo3(signature = (radius, half_height))]
    fn new(radius: f64, half_height: f64) -> PyResult<Self> {
        Ok(PyCapsule {
            inner: RCapsule::new(radius, half_height).or_raise()?,
        })
    }

    /// Radius (m).
    #[getter]
    fn radius(&self) -> f64 {
        self.inner.radius()
    }

    // One-line getters, a method per attribute for pyo3, as on TriMesh
    // (trimesh.rs `volume`, `area`) and World (world.rs `time`, `step_count`).
    /// Half the length of the core segment (m).
    #[getter]
    fn half_height(&self) -> f64 {
        self.inner.half_height()
    }

    /// This shape placed at `position` with `orientation` (x, y, z, w) in the
    /// body's model frame, for compound bodies.
    #[pyo3(signature = (position=None, orientation=None))]
    fn at(
        slf: &Bound<'_, Self>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Placed> {
        Placed::new(slf.as_any(), position, orientation)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let c = &slf.get().inner;
        let args = PyTuple::new(slf.py(), [c.radius(), c.half_height()])?;
        PyTuple::new(slf.py(), [slf.get_type().into_any(), args.into_any()])
    }

    fn __repr__(&self) -> String {
        format!(
            "tumble.Capsule(radius={}, half_height={})",
            self.inner.radius(),
            self.inner.half_height()
        )
    }
}

/// The convex hull of a point set, as a convex polyhedron shape.
///
/// Args:
///     points: (N, 3) array of numbers (m), or an object with a `.vertices`
///         attribute such as a `trimesh.Trimesh`. At least 4 points not in
///         one plane.
#[pyclass(module = "tumble", name = "ConvexHull", frozen)]
pub struct PyConvexHull {
    pub(crate) inner: RHull,
}

#[pymethods]
impl PyConvexHull {
    #[new]
    #[pyo3(signature = (points))]
    fn new(points: &Bound<'_, PyAny>) -> PyResult<Self> {
        guard(|| {
            let source = points.getattr_opt("vertices")?.unwrap_or_else(|| points.clone());
            let pts = convert::points(&source, "points")?;
            Ok(PyConvexHull {
                inner: RHull::from_points(&pts).or_raise()?,
            })
        })
    }

    /// Hull vertices (m), shape (N, 3).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let data = self.inner.vertices().iter().flat_map(|v| v.to_array()).collect();
        convert::matrix_out(py, data, 3)
    }

    /// Number of (merged, polygonal) faces.
    #[getter]
    fn face_count(&self) -> usize {
        self.inner.faces().len()
    }

    /// This shape placed at `position` with `orientation` (x, y, z, w) in the
    /// body's model frame, for compound bodies.
    #[pyo3(signature = (position=None, orientation=None))]
    fn at(
        slf: &Bound<'_, Self>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Placed> {
        Placed::new(slf.as_any(), position, orientation)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let v = slf.get().vertices(py);
        let args = PyTuple::new(py, [v])?;
        PyTuple::new(py, [slf.get_type().into_any(), args.into_any()])
    }

    fn __repr__(&self) -> String {
        format!(
            "tumble.ConvexHull(<{} vertices, {} faces>)",
            self.inner.vertices().len(),
            self.inner.faces().len()
        )
    }
}

/// The solid `normal . x <= offset`: an infinite ground or wall. Only static
/// bodies can hold a half-space.
///
/// Args:
///     normal: unit outward normal (pointing out of the solid), default +z.
///     offset: plane offset along the normal (m), default 0: the ground z <= 0.
#[pyclass(module = "tumble", name = "HalfSpace", frozen)]
pub struct PyHalfSpace {
    pub(crate) inner: RHalfSpace,
}

#[pymethods]
impl PyHalfSpace {
    #[new]
    #[pyo3(signature = (normal=None, offset=0.0))]
    fn new(normal: Option<&Bound<'_, PyAny>>, offset: f64) -> PyResult<Self> {
        let n = convert::vec3_or(normal, "normal", DVec3::Z)?;
        Ok(PyHalfSpace {
            inner: RHalfSpace::new(n, offset).or_raise()?,
        })
    }

    /// Unit outward normal, shape (3,).
    #[getter]
    fn normal<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec_out(py, self.inner.normal())
    }

    /// Offset along the normal (m).
    #[getter]
    fn offset(&self) -> f64 {
        self.inner.offset()
    }

    /// This shape placed at `position` with `orientation` (x, y, z, w) in the
    /// body's model frame, for compound bodies.
    #[pyo3(signature = (position=None, orientation=None))]
    fn at(
        slf: &Bound<'_, Self>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Placed> {
        Placed::new(slf.as_any(), position, orientation)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let h = &slf.get().inner;
        let args = PyTuple::new(
            py,
            [
                PyTuple::new(py, h.normal().to_array())?.into_any(),
                h.offset().into_pyobject(py)?.into_any(),
            ],
        )?;
        PyTuple::new(py, [slf.get_type().into_any(), args.into_any()])
    }

    fn __repr__(&self) -> String {
        format!(
            "tumble.HalfSpace(normal={}, offset={})",
            fmt3(self.inner.normal()),
            self.inner.offset()
        )
    }
}

/// A shape with a pose in the body's model frame: one part of a compound
/// body. Made by `shape.at(position, orientation)` or directly.
///
/// Args:
///     shape: any tumble shape, or a `trimesh.Trimesh`-like object.
///     position: offset in the model frame (m), default origin.
///     orientation: rotation (x, y, z, w) in the model frame, default identity.
#[pyclass(module = "tumble", name = "Placed", frozen)]
pub struct Placed {
    shape: Py<PyAny>,
    local: Pose,
}

#[pymethods]
impl Placed {
    #[new]
    #[pyo3(signature = (shape, position=None, orientation=None))]
    fn new(
        shape: &Bound<'_, PyAny>,
        position: Option<&Bound<'_, PyAny>>,
        orientation: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        if shape.is_instance_of::<Placed>() {
            return Err(invalid("Placed: the shape is already placed"));
        }
        // Validate the shape now so that errors point here.
        single_shape(shape, "shape")?;
        Ok(Placed {
            shape: shape.clone().unbind(),
            local: convert::pose(position, orientation)?,
        })
    }

    /// The shape.
    #[getter]
    fn shape(&self, py: Python<'_>) -> Py<PyAny> {
        self.shape.clone_ref(py)
    }

    /// Position in the model frame (m), shape (3,).
    #[getter]
    fn position<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec_out(py, self.local.position)
    }

    /// Orientation in the model frame (x, y, z, w), shape (4,).
    #[getter]
    fn orientation<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        quat_out(py, self.local.rotation)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let shape = self
            .shape
            .bind(py)
            .repr()
            .map(|r| r.to_string())
            .unwrap_or_default();
        let q = self.local.rotation;
        format!(
            "tumble.Placed({shape}, position={}, orientation=({}, {}, {}, {}))",
            fmt3(self.local.position),
            q.x,
            q.y,
            q.z,
            q.w
        )
    }
}

/// The geometry of a `Box`, `Sphere`, `Capsule` or `HalfSpace`, `None` for
/// any other object: the solid primitives that both bodies
/// ([`single_shape`]) and the collision queries (query.rs `object`) take.
pub(crate) fn primitive(obj: &Bound<'_, PyAny>) -> Option<Shape> {
    if let Ok(s) = obj.cast::<PyBox>() {
        return Some(Shape::Cuboid(s.get().inner));
    }
    if let Ok(s) = obj.cast::<PySphere>() {
        return Some(Shape::Sphere(s.get().inner));
    }
    if let Ok(s) = obj.cast::<PyCapsule>() {
        return Some(Shape::Capsule(s.get().inner));
    }
    if let Ok(s) = obj.cast::<PyHalfSpace>() {
        return Some(Shape::HalfSpace(s.get().inner));
    }
    None
}

// query.rs `object` shares `primitive` but refuses ConvexHull and Placed,
// with a hint of its own (the queries take meshes and solid primitives).
/// The geometry of one shape-like object (not a list, not `Placed`).
pub fn single_shape(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Shape> {
    if let Some(s) = primitive(obj) {
        return Ok(s);
    }
    if let Ok(s) = obj.cast::<PyConvexHull>() {
        return Ok(Shape::ConvexHull(s.get().inner.clone()));
    }
    if let Ok(s) = obj.cast::<TriMesh>() {
        return Ok(Shape::Mesh(s.get().mesh_shape()?));
    }
    if obj.hasattr("vertices")? && obj.hasattr("faces")? {
        // A trimesh.Trimesh (or anything shaped like one): duck-typed, so
        // trimesh is not a dependency.
        let mesh = mesh_from_object(obj, name)?;
        return MeshShape::new(mesh).map(Shape::Mesh).or_raise();
    }
    Err(invalid(format!(
        "{name}: expected a tumble shape (Box, Sphere, Capsule, ConvexHull, TriMesh, HalfSpace), \
         a Placed shape or an object with .vertices and .faces (e.g. trimesh.Trimesh), got {}",
        describe(obj)
    )))
}

fn one_desc(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<ShapeDesc> {
    if let Ok(p) = obj.cast::<Placed>() {
        let p = p.get();
        let shape = single_shape(p.shape.bind(obj.py()), name)?;
        return Ok(ShapeDesc {
            shape,
            local_pose: p.local,
        });
    }
    Ok(ShapeDesc::new(single_shape(obj, name)?))
}

/// The shapes of a body: one shape-like object or a list/tuple of them.
pub fn shape_descs(obj: &Bound<'_, PyAny>) -> PyResult<Vec<ShapeDesc>> {
    // None or an empty list: a body without shapes (kinematic, or dynamic
    // with its inertia given), which the world checks.
    if obj.is_none() {
        return Ok(Vec::new());
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let mut out = Vec::new();
        for (i, item) in obj.try_iter()?.enumerate() {
            out.push(one_desc(&item?, &format!("shapes[{i}]"))?);
        }
        return Ok(out);
    }
    Ok(vec![one_desc(obj, "shape")?])
}
