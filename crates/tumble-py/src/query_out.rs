//! Query results for Python: the frozen dataclasses of `tumble/_query.py`
//! (`CollisionResult`, `DistanceResult`, `QueryStats`), triangle pairs as a
//! (K, 2) int64 array, and contacts as a structured array of dtype
//! `tumble.QUERY_CONTACT_DTYPE` ([`QUERY_CONTACT_FIELDS`]). The classes and
//! the dtype are looked up once and kept.
//!
//! A frozen dataclass's `__init__` sets each field through
//! `object.__setattr__`, about 0.3 us a field: a first-contact query would
//! spend a third of its time there. The records are therefore made as
//! `object.__new__(cls)` with their `__dict__` filled directly, which is what
//! `__init__` leaves behind (the classes have no defaults and no
//! `__post_init__`; a test compares both).

use crate::convert::{matrix_out, vec_out};
use crate::report::contact_kind_name;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1};
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{IntoPyDict, PyBool, PyList, PyString, PyType};
use tumble_collide::query::{DistanceResult, QueryStats, Report};
use tumble_collide::{Contact, Feature, SubFeature};

/// The numpy dtype of the contacts of `tumble.collide(..., report="contacts")`.
/// A feature is `(index, part, k)`: the triangle (or primitive face) index;
/// "vertex", "edge", "face" or "whole"; the corner or edge number within
/// the triangle (edge k joins corners k and k + 1), -1 for a face or whole.
pub const QUERY_CONTACT_FIELDS: &str = "[('point', '<f8', (3,)), ('normal', '<f8', (3,)), \
    ('distance', '<f8'), ('depth', '<f8'), ('kind', '<U16'), \
    ('feature_a', [('index', '<i8'), ('part', '<U6'), ('k', 'i1')]), \
    ('feature_b', [('index', '<i8'), ('part', '<U6'), ('k', 'i1')])]";

static COLLISION_RESULT: PyOnceLock<Py<PyType>> = PyOnceLock::new();
static DISTANCE_RESULT: PyOnceLock<Py<PyType>> = PyOnceLock::new();
static QUERY_STATS: PyOnceLock<Py<PyType>> = PyOnceLock::new();
static CONTACT_DTYPE: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
static EMPTY_PAIRS: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
static OBJECT_NEW: PyOnceLock<Py<PyAny>> = PyOnceLock::new();

const MODULE: &str = "tumble._query";

/// An instance of the dataclass `cls` with the fields `names` set to
/// `values`, as its `__init__` would leave it (see the module header).
fn record<'py, const N: usize>(
    cls: &Bound<'py, PyType>,
    names: [&Bound<'py, PyString>; N],
    values: [Bound<'py, PyAny>; N],
) -> PyResult<Bound<'py, PyAny>> {
    let py = cls.py();
    let new = OBJECT_NEW.get_or_try_init(py, || {
        Ok::<_, PyErr>(py.get_type::<PyAny>().getattr("__new__")?.unbind())
    })?;
    let obj = new.bind(py).call1((cls,))?;
    let dict = obj.getattr(intern!(py, "__dict__"))?;
    for (name, value) in names.into_iter().zip(values) {
        dict.set_item(name, value)?;
    }
    Ok(obj)
}

fn stats<'py>(py: Python<'py>, s: &QueryStats) -> PyResult<Bound<'py, PyAny>> {
    record(
        QUERY_STATS.import(py, MODULE, "QueryStats")?,
        [
            intern!(py, "bv_tests"),
            intern!(py, "triangle_tests"),
            intern!(py, "stopped_early"),
        ],
        [
            s.bv_tests.into_pyobject(py)?.into_any(),
            s.triangle_tests.into_pyobject(py)?.into_any(),
            PyBool::new(py, s.stopped_early).to_owned().into_any(),
        ],
    )
}

/// Triangle pairs as a (K, 2) int64 array. No pairs (every first-contact
/// query, every separated pose) share one read-only empty array.
fn pairs_out<'py>(py: Python<'py>, pairs: &[(u32, u32)]) -> PyResult<Bound<'py, PyAny>> {
    if pairs.is_empty() {
        return EMPTY_PAIRS
            .get_or_try_init(py, || {
                let a = Array2::<i64>::zeros((0, 2)).into_pyarray(py);
                a.call_method("setflags", (), Some(&[("write", false)].into_py_dict(py)?))?;
                Ok::<_, PyErr>(a.into_any().unbind())
            })
            .map(|a| a.bind(py).clone());
    }
    let flat: Vec<i64> = pairs
        .iter()
        .flat_map(|&(a, b)| [i64::from(a), i64::from(b)])
        .collect();
    Ok(Array2::from_shape_vec((pairs.len(), 2), flat)
        .expect("buffer length is rows * 2 by construction")
        .into_pyarray(py)
        .into_any())
}

/// The `CollisionResult`; `contacts` only when they were asked for.
pub fn collision_result<'py>(
    py: Python<'py>,
    r: &Report,
    with_contacts: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let contacts = if with_contacts {
        contacts_array(py, &r.contacts)?
    } else {
        py.None().into_bound(py)
    };
    record(
        COLLISION_RESULT.import(py, MODULE, "CollisionResult")?,
        [
            intern!(py, "intersect"),
            intern!(py, "pairs"),
            intern!(py, "contacts"),
            intern!(py, "stats"),
        ],
        [
            PyBool::new(py, r.intersect).to_owned().into_any(),
            pairs_out(py, &r.pairs)?,
            contacts,
            stats(py, &r.stats)?,
        ],
    )
}

// Names and values per dataclass, as in `collision_result` above: each
// record lists its own class's fields in the order of _query.py.
/// The `DistanceResult`.
pub fn distance_result<'py>(py: Python<'py>, d: &DistanceResult) -> PyResult<Bound<'py, PyAny>> {
    record(
        DISTANCE_RESULT.import(py, MODULE, "DistanceResult")?,
        [
            intern!(py, "distance"),
            intern!(py, "point_a"),
            intern!(py, "point_b"),
            intern!(py, "tri_a"),
            intern!(py, "tri_b"),
            intern!(py, "stats"),
        ],
        [
            d.distance.into_pyobject(py)?.into_any(),
            vec_out(py, d.point_a).into_any(),
            vec_out(py, d.point_b).into_any(),
            d.tri_a.into_pyobject(py)?.into_any(),
            d.tri_b.into_pyobject(py)?.into_any(),
            stats(py, &d.stats)?,
        ],
    )
}

fn part(f: &Feature) -> (&'static str, i8) {
    match f.sub {
        SubFeature::Vertex(k) => ("vertex", k as i8),
        SubFeature::Edge(k) => ("edge", k as i8),
        SubFeature::Face => ("face", -1),
        SubFeature::Whole => ("whole", -1),
    }
}

fn contact_dtype(py: Python<'_>) -> PyResult<&Bound<'_, PyAny>> {
    CONTACT_DTYPE
        .get_or_try_init(py, || {
            let spec = py.eval(&std::ffi::CString::new(QUERY_CONTACT_FIELDS)?, None, None)?;
            Ok::<_, PyErr>(py.import("numpy")?.call_method1("dtype", (spec,))?.unbind())
        })
        .map(|d| d.bind(py))
}

/// Sets the fields of one side's features (`feature_a` or `feature_b`).
fn set_features<'py>(
    py: Python<'py>,
    out: &Bound<'py, PyAny>,
    field: &str,
    features: impl Iterator<Item = Feature>,
) -> PyResult<()> {
    let (mut index, mut parts, mut ks) = (Vec::new(), Vec::new(), Vec::new());
    for f in features {
        let (p, k) = part(&f);
        index.push(i64::from(f.index));
        parts.push(p);
        ks.push(k);
    }
    let view = out.get_item(field)?;
    view.set_item("index", PyArray1::from_vec(py, index))?;
    view.set_item("part", PyList::new(py, parts)?)?;
    view.set_item("k", PyArray1::from_vec(py, ks))?;
    Ok(())
}

/// Contacts as a structured array of dtype [`QUERY_CONTACT_FIELDS`].
pub fn contacts_array<'py>(py: Python<'py>, contacts: &[Contact]) -> PyResult<Bound<'py, PyAny>> {
    let n = contacts.len();
    let np = py.import("numpy")?;
    let out = np.call_method1("zeros", (n, contact_dtype(py)?))?;
    if n == 0 {
        return Ok(out);
    }
    let flat = |f: fn(&Contact) -> [f64; 3]| contacts.iter().flat_map(f).collect::<Vec<f64>>();
    let distance: Vec<f64> = contacts.iter().map(|c| c.distance).collect();
    let depth: Vec<f64> = contacts.iter().map(Contact::depth).collect();
    let kinds: Vec<&str> = contacts.iter().map(|c| contact_kind_name(c.kind)).collect();
    out.set_item("point", matrix_out(py, flat(|c| c.point.to_array()), 3))?;
    out.set_item("normal", matrix_out(py, flat(|c| c.normal.to_array()), 3))?;
    out.set_item("distance", PyArray1::from_vec(py, distance))?;
    out.set_item("depth", PyArray1::from_vec(py, depth))?;
    out.set_item("kind", PyList::new(py, kinds)?)?;
    set_features(py, &out, "feature_a", contacts.iter().map(|c| c.feature_a))?;
    set_features(py, &out, "feature_b", contacts.iter().map(|c| c.feature_b))?;
    Ok(out)
}
