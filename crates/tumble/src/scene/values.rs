//! Checked conversions of scene file values: finite vectors, positive
//! numbers, orientations (quaternion or a product of rotations in degrees)
//! and poses. Each error names the field it came from.

use super::error::{FieldError, FieldPath};
use super::schema::RotationSpec;
use tumble_collide::{DQuat, DVec3, Pose};

/// How far |q| may be from 1 before a quaternion is rejected (it is
/// normalised otherwise, so that `[0, 0, 0.7071, 0.7071]` is accepted).
pub const QUATERNION_TOLERANCE: f64 = 1e-3;

fn fmt3(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
}

/// A finite vector.
pub fn vec3(path: &FieldPath, v: [f64; 3]) -> Result<DVec3, FieldError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(DVec3::from_array(v))
    } else {
        Err(FieldError::new(path, format!("must be finite, got {}", fmt3(v))))
    }
}

/// An optional finite vector, zero by default.
pub fn vec3_or_zero(path: &FieldPath, v: Option<[f64; 3]>) -> Result<DVec3, FieldError> {
    v.map_or(Ok(DVec3::ZERO), |v| vec3(path, v))
}

/// A finite vector with every component > 0.
pub fn positive3(path: &FieldPath, v: [f64; 3], unit: &str) -> Result<DVec3, FieldError> {
    if v.iter().all(|x| x.is_finite() && *x > 0.0) {
        Ok(DVec3::from_array(v))
    } else {
        Err(FieldError::new(
            path,
            format!("each component must be finite and > 0 {unit}, got {}", fmt3(v)),
        ))
    }
}

/// A finite number > 0.
pub fn positive(path: &FieldPath, x: f64, unit: &str) -> Result<f64, FieldError> {
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(FieldError::new(
            path,
            format!("must be finite and > 0 {unit}, got {x}"),
        ))
    }
}

/// A finite number >= 0.
pub fn non_negative(path: &FieldPath, x: f64, unit: &str) -> Result<f64, FieldError> {
    if x.is_finite() && x >= 0.0 {
        Ok(x)
    } else {
        Err(FieldError::new(
            path,
            format!("must be finite and >= 0 {unit}, got {x}"),
        ))
    }
}

/// Checks that exactly one of the alternatives `given` is present at
/// `path`; otherwise the error "give exactly one of {what} (got N)".
pub fn exactly_one(path: &FieldPath, given: &[bool], what: &str) -> Result<(), FieldError> {
    match given.iter().filter(|&&b| b).count() {
        1 => Ok(()),
        n => Err(FieldError::new(
            path,
            format!("give exactly one of {what} (got {n})"),
        )),
    }
}

/// One factor of a `rotation` product.
fn rotation_factor(path: &FieldPath, r: &RotationSpec) -> Result<DQuat, FieldError> {
    exactly_one(
        path,
        &[
            r.x.is_some(),
            r.y.is_some(),
            r.z.is_some(),
            r.axis.is_some() || r.angle.is_some(),
        ],
        "x, y, z (degrees) or axis with angle (degrees)",
    )?;
    let degrees = |key: &str, a: f64| {
        if a.is_finite() {
            Ok(a.to_radians())
        } else {
            Err(FieldError::new(
                &path.key(key),
                format!("must be finite degrees, got {a}"),
            ))
        }
    };
    if let Some(a) = r.x {
        return Ok(DQuat::from_rotation_x(degrees("x", a)?));
    }
    if let Some(a) = r.y {
        return Ok(DQuat::from_rotation_y(degrees("y", a)?));
    }
    if let Some(a) = r.z {
        return Ok(DQuat::from_rotation_z(degrees("z", a)?));
    }
    let (Some(axis), Some(angle)) = (r.axis, r.angle) else {
        return Err(FieldError::new(path, "axis and angle go together"));
    };
    let axis = vec3(&path.key("axis"), axis)?;
    let unit = axis
        .try_normalize()
        .ok_or_else(|| FieldError::new(&path.key("axis"), "must have a length > 0"))?;
    Ok(DQuat::from_axis_angle(unit, degrees("angle", angle)?))
}

/// The orientation given by `orientation` (quaternion) or `rotation`
/// (product in written order), identity when neither is given; `parent` is
/// the table holding both keys.
pub fn orientation(
    parent: &FieldPath,
    quaternion: Option<[f64; 4]>,
    rotation: Option<&[RotationSpec]>,
) -> Result<DQuat, FieldError> {
    match (quaternion, rotation) {
        (Some(_), Some(_)) => Err(FieldError::new(
            &parent.key("rotation"),
            "give either orientation (quaternion) or rotation (degrees), not both",
        )),
        (Some(q), None) => {
            let path = parent.key("orientation");
            let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            if !q.iter().all(|x| x.is_finite()) || (len - 1.0).abs() > QUATERNION_TOLERANCE {
                return Err(FieldError::new(
                    &path,
                    format!(
                        "must be a finite unit quaternion [x, y, z, w] (|q| within {QUATERNION_TOLERANCE} of 1), got [{}, {}, {}, {}]",
                        q[0], q[1], q[2], q[3]
                    ),
                ));
            }
            Ok(DQuat::from_array(q).normalize())
        }
        (None, Some(list)) => {
            let path = parent.key("rotation");
            let mut q = DQuat::IDENTITY;
            for (i, r) in list.iter().enumerate() {
                q *= rotation_factor(&path.index(i), r)?;
            }
            Ok(q)
        }
        (None, None) => Ok(DQuat::IDENTITY),
    }
}

/// A pose from the optional `position`, `orientation` and `rotation` keys of `parent`.
pub fn pose(
    parent: &FieldPath,
    position: Option<[f64; 3]>,
    quaternion: Option<[f64; 4]>,
    rotation: Option<&[RotationSpec]>,
) -> Result<Pose, FieldError> {
    let position = vec3_or_zero(&parent.key("position"), position)?;
    let rotation = orientation(parent, quaternion, rotation)?;
    Ok(Pose { position, rotation })
}
