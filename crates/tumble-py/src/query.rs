//! `tumble.collide`, `tumble.distance`, `tumble.within_tolerance`: the
//! collision query API of `tumble_collide::query` (docs/collision.md; the
//! thesis' JAOC queries after PQP), without any world.
//!
//! A query object is a `TriMesh` (its OBBTree is built on first use and kept
//! in the object, so repeated queries cost no rebuild), any
//! `trimesh.Trimesh`-like object (converted and its tree built at every
//! call), or a primitive `Sphere`, `Box`, `Capsule`, `HalfSpace` against a
//! mesh. A mesh against a primitive runs the primitive query with A and B
//! swapped and swaps the answer back (pairs, contact normals and features,
//! closest points), so results always read "A, then B". The GIL is released
//! while Rust walks the trees.

use crate::convert::describe;
use crate::errors::{error, guard, invalid, Kind, OrRaise, ToPyErr};
use crate::pose_arg::pose_arg;
use crate::query_out::{collision_result, distance_result};
use crate::shapes::{primitive, Placed, PyConvexHull};
use crate::trimesh::{mesh_from_object, TriMesh};
use pyo3::prelude::*;
use tumble_collide::query::{self, CollideOptions, DistanceOptions, MeshShape, QueryError, ReportMode};
use tumble_collide::{Pose, Shape};

impl ToPyErr for QueryError {
    fn to_py(&self) -> PyErr {
        match self {
            QueryError::NotFinite(_) => error(Kind::Tumble, self.to_string()),
            _ => invalid(self.to_string()),
        }
    }
}

// Not `shapes::single_shape` (shapes.rs), which casts the same classes for
// bodies: the queries refuse ConvexHull and Placed, with a hint of their own.
// The primitives are read by `shapes::primitive`, for both.
/// The query shape of argument `name`: a mesh (borrowed from a `TriMesh`
/// or built for this call from a trimesh-like object) or a solid primitive.
fn object(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Shape> {
    if let Ok(m) = obj.cast::<TriMesh>() {
        return Ok(Shape::Mesh(m.get().mesh_shape_ref()?.clone()));
    }
    if let Some(s) = primitive(obj) {
        return Ok(s);
    }
    if obj.is_instance_of::<PyConvexHull>() || obj.is_instance_of::<Placed>() {
        return Err(invalid(format!(
            "{name}: the queries take a TriMesh (or trimesh.Trimesh) or a Sphere, Box, Capsule or \
             HalfSpace; got {} (for a convex hull, query TriMesh(vertices, faces) of its surface)",
            describe(obj)
        )));
    }
    if obj.hasattr("vertices")? && obj.hasattr("faces")? {
        let mesh = mesh_from_object(obj, name)?;
        return Ok(Shape::Mesh(MeshShape::new(mesh).or_raise()?));
    }
    Err(invalid(format!(
        "{name}: expected a TriMesh, a trimesh.Trimesh-like object (.vertices, .faces), or a \
         Sphere, Box, Capsule or HalfSpace; got {}",
        describe(obj)
    )))
}

/// The two shapes and poses of a query, checked as Python objects.
fn arguments(
    a: &Bound<'_, PyAny>,
    pose_a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    pose_b: &Bound<'_, PyAny>,
) -> PyResult<(Shape, Pose, Shape, Pose)> {
    Ok((
        object(a, "a")?,
        pose_arg(pose_a, "pose_a")?,
        object(b, "b")?,
        pose_arg(pose_b, "pose_b")?,
    ))
}

fn report_mode(report: &str) -> PyResult<ReportMode> {
    match report {
        "bool" => Ok(ReportMode::Boolean),
        "pairs" => Ok(ReportMode::TrianglePairs),
        "contacts" => Ok(ReportMode::Contacts),
        other => Err(invalid(format!(
            "report: expected \"bool\", \"pairs\" or \"contacts\", got {other:?}"
        ))),
    }
}

/// Collision query between shape `a` at `pose_a` and shape `b` at `pose_b`.
///
/// Meshes are surfaces: two meshes intersect when some closed triangle of A
/// shares a point with some closed triangle of B (touching counts; a mesh
/// entirely inside another does not intersect it), decided by exact
/// predicates. Primitives (Sphere, Box, Capsule, HalfSpace) are solids and
/// can be queried against a mesh, in either order.
///
/// Args:
///     a, b: a ``TriMesh`` (its OBBTree is built once and kept), a
///         ``trimesh.Trimesh``-like object (converted at every call: pass
///         ``TriMesh.from_trimesh(m)`` to reuse it), or a ``Sphere``, ``Box``,
///         ``Capsule`` or ``HalfSpace`` (at most one of the two).
///     pose_a, pose_b: ``(position, orientation)`` with a quaternion
///         (x, y, z, w), 7 numbers ``(x, y, z, qx, qy, qz, qw)`` (a row of
///         ``World.poses()``), a 4x4 homogeneous matrix holding a proper
///         rotation, or ``None`` (identity).
///     report: ``"bool"`` (whether they intersect; stops at the first
///         intersecting pair), ``"pairs"`` (every intersecting triangle pair,
///         the default) or ``"contacts"`` (the pairs and contact points).
///     stop_at_first: stop at the first intersecting pair (then ``pairs``
///         holds that one pair).
///     contact_margin: largest gap (m, >= 0) at which ``"contacts"`` still
///         reports a contact; 0 gives touching and intersecting pairs only.
///
/// Returns:
///     CollisionResult: ``intersect`` (also its truth value), ``pairs``
///     ((K, 2) int64: triangle of A, triangle of B, sorted; the index of a
///     primitive is 0; empty for ``"bool"``), ``contacts`` (structured array
///     of dtype ``tumble.QUERY_CONTACT_DTYPE``, world frame, normals from B
///     to A, ``depth > 0`` for penetration; ``None`` unless
///     ``report="contacts"``) and ``stats`` (QueryStats).
///
/// Raises:
///     InvalidArgument: a bad shape, pose (not finite, quaternion not unit,
///         matrix not a rotation), report or margin; two primitives.
// The arguments are the Python signature's.
#[allow(clippy::too_many_arguments)]
#[pyfunction]
#[pyo3(signature = (a, pose_a, b, pose_b, *, report = "pairs", stop_at_first = false, contact_margin = 0.0))]
pub fn collide<'py>(
    py: Python<'py>,
    a: &Bound<'py, PyAny>,
    pose_a: &Bound<'py, PyAny>,
    b: &Bound<'py, PyAny>,
    pose_b: &Bound<'py, PyAny>,
    report: &str,
    stop_at_first: bool,
    contact_margin: f64,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let mode = report_mode(report)?;
        let options = CollideOptions {
            stop_at_first,
            report: mode,
            contact_margin,
        };
        let (sa, pa, sb, pb) = arguments(a, pose_a, b, pose_b)?;
        let r = py
            .detach(|| query::collide_shapes(&sa, &pa, &sb, &pb, &options))
            .or_raise()?;
        collision_result(py, &r, mode == ReportMode::Contacts)
    })
}

/// Minimum distance between shape `a` at `pose_a` and shape `b` at
/// `pose_b`, with the closest points.
///
/// Branch and bound over the OBBTrees with the exact triangle-triangle
/// distance at the leaves (PQP). With ``rel_err = abs_err = 0`` (the default)
/// the answer is the exact minimum over all triangle pairs; otherwise it lies
/// in ``[d, max((1 + rel_err) d, d + abs_err)]`` for the true distance ``d``
/// and is found faster. Intersecting shapes are at distance 0.
///
/// Args:
///     a, b, pose_a, pose_b: as for :func:`collide`.
///     rel_err: relative error allowed (>= 0).
///     abs_err: absolute error allowed (m, >= 0).
///
/// Returns:
///     DistanceResult: ``distance`` (m), ``point_a``, ``point_b`` (closest
///     points, world frame, shape (3,)), ``tri_a``, ``tri_b`` (the triangles
///     holding them; 0 for a primitive) and ``stats``.
///
/// Raises:
///     InvalidArgument: bad shapes, poses or errors; two primitives.
///     TumbleError: coordinates so large that no distance is finite.
// The `(py, a, pose_a, b, pose_b)` head and guard/arguments/detach body are
// `collide`'s: each query is its own #[pyfunction] with its own keywords and
// docstring (also `within_tolerance`); `arguments` holds the shared parsing.
#[pyfunction]
#[pyo3(signature = (a, pose_a, b, pose_b, *, rel_err = 0.0, abs_err = 0.0))]
pub fn distance<'py>(
    py: Python<'py>,
    a: &Bound<'py, PyAny>,
    pose_a: &Bound<'py, PyAny>,
    b: &Bound<'py, PyAny>,
    pose_b: &Bound<'py, PyAny>,
    rel_err: f64,
    abs_err: f64,
) -> PyResult<Bound<'py, PyAny>> {
    guard(|| {
        let options = DistanceOptions { rel_err, abs_err };
        let (sa, pa, sb, pb) = arguments(a, pose_a, b, pose_b)?;
        let d = py
            .detach(|| query::distance_shapes(&sa, &pa, &sb, &pb, &options))
            .or_raise()?;
        distance_result(py, &d)
    })
}

/// ``True`` when shape `a` at `pose_a` and shape `b` at `pose_b` come within
/// `tol` (m) of each other: exactly ``distance(a, pose_a, b, pose_b).distance
/// <= tol``, but cheaper (the walk ends at the first pair close enough).
///
/// Args:
///     a, b, pose_a, pose_b: as for :func:`collide`.
///     tol: the distance (m, finite, >= 0).
///
/// Raises:
///     InvalidArgument: bad shapes, poses or tolerance; two primitives.
#[pyfunction]
#[pyo3(signature = (a, pose_a, b, pose_b, tol))]
pub fn within_tolerance(
    py: Python<'_>,
    a: &Bound<'_, PyAny>,
    pose_a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    pose_b: &Bound<'_, PyAny>,
    tol: f64,
) -> PyResult<bool> {
    guard(|| {
        let (sa, pa, sb, pb) = arguments(a, pose_a, b, pose_b)?;
        py.detach(|| query::within_tolerance_shapes(&sa, &pa, &sb, &pb, tol))
            .or_raise()
    })
}
