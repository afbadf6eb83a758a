//! Python values in and out: vectors, quaternions and (N, 3) arrays, checked
//! at the boundary with messages that say which argument, what was expected
//! and what was given. Vectors go out as numpy float64 arrays.

use crate::errors::invalid;
use numpy::ndarray::Array2;
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyString;
use tumble_collide::{DQuat, DVec3, Pose};

/// A short description of a Python value for error messages.
pub fn describe(obj: &Bound<'_, PyAny>) -> String {
    if let Ok(a) = obj.cast::<PyUntypedArray>() {
        return format!("array of shape {:?} and dtype {}", a.shape(), a.dtype());
    }
    let type_name = obj
        .get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "?".into());
    let repr = obj.repr().map(|r| r.to_string()).unwrap_or_default();
    let repr = if repr.chars().count() > 60 {
        format!("{}...", repr.chars().take(57).collect::<String>())
    } else {
        repr
    };
    format!("{type_name} {repr}")
}

/// Exactly `N` real numbers from a sequence or numpy array.
pub fn numbers<const N: usize>(obj: &Bound<'_, PyAny>, name: &str, what: &str) -> PyResult<[f64; N]> {
    let bad = || invalid(format!("{name}: expected {what}, got {}", describe(obj)));
    if obj.is_instance_of::<PyString>() {
        return Err(bad());
    }
    if let Ok(a) = obj.cast::<PyUntypedArray>() {
        if a.ndim() != 1 || a.len() != N || !is_real_kind(a.dtype().kind()) {
            return Err(bad());
        }
    }
    let v: Vec<f64> = obj.extract().map_err(|_| bad())?;
    v.try_into().map_err(|_| bad())
}

/// A 3-vector (x, y, z).
pub fn vec3(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<DVec3> {
    numbers::<3>(obj, name, "3 numbers (x, y, z)").map(DVec3::from_array)
}

/// An optional 3-vector, `default` when `None`.
pub fn vec3_or(obj: Option<&Bound<'_, PyAny>>, name: &str, default: DVec3) -> PyResult<DVec3> {
    match obj {
        Some(o) if !o.is_none() => vec3(o, name),
        _ => Ok(default),
    }
}

/// A quaternion given as (x, y, z, w); its norm is checked by `Pose::new`
/// where it is used.
pub fn quat(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<DQuat> {
    numbers::<4>(obj, name, "a quaternion of 4 numbers (x, y, z, w)").map(DQuat::from_array)
}

/// An optional quaternion, identity when `None`.
pub fn quat_or_identity(obj: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<DQuat> {
    match obj {
        Some(o) if !o.is_none() => quat(o, name),
        _ => Ok(DQuat::IDENTITY),
    }
}

/// A pose from optional position and orientation, validated (finite, unit
/// quaternion within `Pose`'s tolerance).
pub fn pose(position: Option<&Bound<'_, PyAny>>, orientation: Option<&Bound<'_, PyAny>>) -> PyResult<Pose> {
    let p = vec3_or(position, "position", DVec3::ZERO)?;
    let q = quat_or_identity(orientation, "orientation")?;
    Pose::new(p, q).map_err(|e| invalid(format!("pose: {e}")))
}

fn is_real_kind(kind: u8) -> bool {
    matches!(kind, b'f' | b'i' | b'u')
}

/// `numpy.asarray(obj)`.
fn as_array<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyUntypedArray>> {
    let np = obj.py().import("numpy")?;
    let a = np.call_method1("asarray", (obj,))?;
    Ok(a.cast_into::<PyUntypedArray>()?)
}

/// An (N, 3) array of real numbers (any float or integer dtype) as vectors.
pub fn points(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<DVec3>> {
    let a = as_array(obj).map_err(|_| {
        invalid(format!(
            "{name}: expected an (N, 3) array of numbers, got {}",
            describe(obj)
        ))
    })?;
    let kind = a.dtype().kind();
    if a.ndim() != 2 || a.shape()[1] != 3 || !is_real_kind(kind) {
        return Err(invalid(format!(
            "{name}: expected an (N, 3) array of float numbers, got shape {:?} and dtype {}",
            a.shape(),
            a.dtype()
        )));
    }
    let np = obj.py().import("numpy")?;
    let f = a.call_method1("astype", (np.getattr("float64")?,))?;
    let f = f.cast_into::<PyArray2<f64>>()?;
    let ro = f.readonly();
    let view = ro.as_array();
    Ok(view
        .rows()
        .into_iter()
        .map(|r| DVec3::new(r[0], r[1], r[2]))
        .collect())
}

// Checks as `points` above, but for integer dtypes and with a message that
// says "vertex indices": each error names what its argument should be.
/// An (M, 3) array of integer vertex indices (signed or unsigned dtype;
/// negative entries are rejected).
pub fn faces(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<[u64; 3]>> {
    let a = as_array(obj).map_err(|_| {
        invalid(format!(
            "{name}: expected an (M, 3) array of integer vertex indices, got {}",
            describe(obj)
        ))
    })?;
    let kind = a.dtype().kind();
    if a.ndim() != 2 || a.shape()[1] != 3 || !matches!(kind, b'i' | b'u') {
        return Err(invalid(format!(
            "{name}: expected an (M, 3) array of integer vertex indices, got shape {:?} and dtype {}",
            a.shape(),
            a.dtype()
        )));
    }
    let np = obj.py().import("numpy")?;
    if kind == b'u' {
        let u = a.call_method1("astype", (np.getattr("uint64")?,))?;
        let u = u.cast_into::<PyArray2<u64>>()?;
        let ro = u.readonly();
        return Ok(ro
            .as_array()
            .rows()
            .into_iter()
            .map(|r| [r[0], r[1], r[2]])
            .collect());
    }
    let s = a.call_method1("astype", (np.getattr("int64")?,))?;
    let s = s.cast_into::<PyArray2<i64>>()?;
    let ro = s.readonly();
    let mut out = Vec::with_capacity(ro.len() / 3);
    for (t, r) in ro.as_array().rows().into_iter().enumerate() {
        let mut tri = [0u64; 3];
        for k in 0..3 {
            tri[k] = u64::try_from(r[k]).map_err(|_| {
                invalid(format!(
                    "{name}: triangle {t} has a negative vertex index {}",
                    r[k]
                ))
            })?;
        }
        out.push(tri);
    }
    Ok(out)
}

/// A vector as a float64 array of shape (3,).
pub fn vec_out<'py>(py: Python<'py>, v: DVec3) -> Bound<'py, PyArray1<f64>> {
    v.to_array().to_vec().into_pyarray(py)
}

/// A quaternion as a float64 array (x, y, z, w).
pub fn quat_out<'py>(py: Python<'py>, q: DQuat) -> Bound<'py, PyArray1<f64>> {
    q.to_array().to_vec().into_pyarray(py)
}

/// A row-major buffer as an (rows, cols) float64 array, without copying.
pub fn matrix_out<'py>(py: Python<'py>, data: Vec<f64>, cols: usize) -> Bound<'py, PyArray2<f64>> {
    let rows = data.len().checked_div(cols).unwrap_or(0);
    Array2::from_shape_vec((rows, cols), data)
        .expect("buffer length is rows * cols by construction")
        .into_pyarray(py)
}

/// A row-major buffer as an (rows, 3) int64 array.
pub fn index_rows_out<'py>(py: Python<'py>, data: Vec<i64>) -> Bound<'py, PyArray2<i64>> {
    let rows = data.len() / 3;
    Array2::from_shape_vec((rows, 3), data)
        .expect("buffer length is rows * 3 by construction")
        .into_pyarray(py)
}
