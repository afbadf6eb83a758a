//! Poses given to the query functions: `(position, orientation)` with a
//! quaternion (x, y, z, w), 7 numbers `(x, y, z, qx, qy, qz, qw)` (a row of
//! `World.poses()`), a 4x4 homogeneous matrix, or `None` for the identity.
//!
//! A matrix must hold a proper rotation: orthonormal within
//! [`Pose::UNIT_TOLERANCE`] (the tolerance of the quaternion length, so that
//! float32 matrices pass), determinant +1 (a reflection is refused), bottom
//! row (0, 0, 0, 1). Its quaternion is glam's (Shepperd's method, stable for
//! every angle), normalised.
//!
//! Quaternions are checked here with `Pose::new`'s message, so that an error
//! names the Python argument even when the query swaps A and B, but handed
//! on as given: the query re-checks them and uses a unit quaternion bit for
//! bit, exactly as a Rust caller's.

use crate::convert::{describe, numbers, quat, vec3};
use crate::errors::invalid;
use numpy::{PyArray1, PyArray2, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyFloat, PyInt, PyList, PyTuple};
use tumble_collide::{DMat3, DQuat, DVec3, Pose};

/// Largest deviation of the bottom row from (0, 0, 0, 1) that is accepted.
const BOTTOM_ROW_TOLERANCE: f64 = 1e-9;

fn expected(obj: &Bound<'_, PyAny>, name: &str) -> PyErr {
    invalid(format!(
        "{name}: expected a pose: (position, orientation) with 3 numbers and a quaternion \
         (x, y, z, w), 7 numbers (x, y, z, qx, qy, qz, qw), or a 4x4 homogeneous matrix; got {}",
        describe(obj)
    ))
}

/// The pose argument `name` (see the module header).
pub fn pose_arg(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Pose> {
    if obj.is_none() {
        return Ok(Pose::IDENTITY);
    }
    // Fast paths for float64 arrays (a row of World.poses(), a matrix).
    if let Ok(a) = obj.cast::<PyArray1<f64>>() {
        if a.len() == 7 {
            let v = a.readonly();
            let s = v.as_array();
            return checked(
                DVec3::new(s[0], s[1], s[2]),
                DQuat::from_xyzw(s[3], s[4], s[5], s[6]),
                name,
            );
        }
        return Err(expected(obj, name));
    }
    if let Ok(a) = obj.cast::<PyArray2<f64>>() {
        if a.shape() == [4, 4] {
            let m = a.readonly();
            let m = m.as_array();
            let rows = std::array::from_fn(|r| std::array::from_fn(|c| m[[r, c]]));
            return from_matrix(&rows, name);
        }
        return Err(expected(obj, name));
    }
    let pair = obj.cast::<PyTuple>().map(|t| t.len() == 2).unwrap_or(false)
        || obj.cast::<PyList>().map(|l| l.len() == 2).unwrap_or(false);
    if pair {
        let (p, q) = (obj.get_item(0)?, obj.get_item(1)?);
        let p = match floats::<3>(&p) {
            Some(v) => DVec3::from_array(v),
            None => vec3(&p, &format!("{name} position"))?,
        };
        let q = match floats::<4>(&q) {
            Some(v) => DQuat::from_array(v),
            None => quat(&q, &format!("{name} orientation"))?,
        };
        return checked(p, q, name);
    }
    // Anything else: 7 numbers or a 4x4 nested sequence / array of another dtype.
    let np = obj.py().import("numpy")?;
    let a = np
        .call_method1("asarray", (obj,))
        .and_then(|a| Ok(a.cast_into::<PyUntypedArray>()?))
        .map_err(|_| expected(obj, name))?;
    let real = matches!(a.dtype().kind(), b'f' | b'i' | b'u');
    match a.shape() {
        [7] if real => {
            let v = numbers::<7>(a.as_any(), name, "7 numbers (x, y, z, qx, qy, qz, qw)")?;
            checked(
                DVec3::new(v[0], v[1], v[2]),
                DQuat::from_xyzw(v[3], v[4], v[5], v[6]),
                name,
            )
        }
        [4, 4] if real => {
            let f = a.call_method1("astype", (np.getattr("float64")?,))?;
            let f = f.cast_into::<PyArray2<f64>>()?;
            let m = f.readonly();
            let m = m.as_array();
            let rows = std::array::from_fn(|r| std::array::from_fn(|c| m[[r, c]]));
            from_matrix(&rows, name)
        }
        _ => Err(expected(obj, name)),
    }
}

/// Exactly `N` numbers from a float64 array or a tuple / list of Python
/// floats or ints, read without a round trip through numpy (a query's pose
/// is parsed at every call); `None` for anything else, which then takes the
/// general, checked path of [`crate::convert`].
fn floats<const N: usize>(obj: &Bound<'_, PyAny>) -> Option<[f64; N]> {
    if let Ok(a) = obj.cast::<PyArray1<f64>>() {
        let v = a.readonly();
        let s = v.as_slice().ok()?;
        return s.try_into().ok();
    }
    let items = |i: usize| -> Option<f64> {
        let x = obj.get_item(i).ok()?;
        (x.is_instance_of::<PyFloat>() || x.is_instance_of::<PyInt>())
            .then(|| x.extract::<f64>().ok())
            .flatten()
    };
    let len = if let Ok(t) = obj.cast::<PyTuple>() {
        t.len()
    } else if let Ok(l) = obj.cast::<PyList>() {
        l.len()
    } else {
        return None;
    };
    if len != N {
        return None;
    }
    let mut out = [0.0; N];
    for (i, o) in out.iter_mut().enumerate() {
        *o = items(i)?;
    }
    Some(out)
}

/// `Pose { p, q }` after `Pose::new`'s checks (finite, unit quaternion
/// within tolerance), with its message prefixed by the argument's name.
fn checked(p: DVec3, q: DQuat, name: &str) -> PyResult<Pose> {
    Pose::new(p, q).map_err(|e| invalid(format!("{name}: {e}")))?;
    Ok(Pose {
        position: p,
        rotation: q,
    })
}

/// The pose of a 4x4 homogeneous matrix `m[row][column]` (rotation in the
/// upper-left block, translation in the last column).
pub fn from_matrix(m: &[[f64; 4]; 4], name: &str) -> PyResult<Pose> {
    if m.iter().flatten().any(|x| !x.is_finite()) {
        return Err(invalid(format!(
            "{name}: the 4x4 pose matrix must be finite, got {m:?}"
        )));
    }
    let bottom = m[3];
    let off = (0..4)
        .map(|c| (bottom[c] - if c == 3 { 1.0 } else { 0.0 }).abs())
        .fold(0.0, f64::max);
    if off > BOTTOM_ROW_TOLERANCE {
        return Err(invalid(format!(
            "{name}: the last row of a 4x4 pose matrix must be (0, 0, 0, 1), got {bottom:?}"
        )));
    }
    let col = |c: usize| DVec3::new(m[0][c], m[1][c], m[2][c]);
    let r = DMat3::from_cols(col(0), col(1), col(2));
    let gram = r.transpose() * r;
    let mut dev: f64 = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            let identity = if i == j { 1.0 } else { 0.0 };
            dev = dev.max((gram.col(j)[i] - identity).abs());
        }
    }
    if dev > Pose::UNIT_TOLERANCE {
        return Err(invalid(format!(
            "{name}: the upper-left 3x3 block of the pose matrix must be a rotation, but R^T R \
             differs from the identity by {dev:.3e} (scale or shear?; tolerance {:e})",
            Pose::UNIT_TOLERANCE
        )));
    }
    let det = r.determinant();
    if det < 0.0 {
        return Err(invalid(format!(
            "{name}: the upper-left 3x3 block of the pose matrix is a reflection (determinant \
             {det:.6}), not a proper rotation"
        )));
    }
    let q = DQuat::from_mat3(&r).normalize();
    checked(DVec3::new(m[0][3], m[1][3], m[2][3]), q, name)
}
