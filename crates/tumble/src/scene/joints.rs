//! The `[[joints]]` of a scene file, and its `[[no_contact]]` pairs:
//! bodies found by name, values checked where they are written (the path
//! of each field kept, so the world's objections point at the file's line).

use super::error::{FieldError, FieldPath};
use super::schema::{JointSpec, NoContactSpec};
use super::values::vec3;
use crate::joint::JointDesc;
use crate::world::{BodyDesc, WorldError};
use tumble_collide::DVec3;

/// Each joint of the file, its bodies as indices into `bodies`, with its path.
pub(crate) fn resolve_joints(
    specs: &[JointSpec],
    bodies: &[BodyDesc],
) -> Result<Vec<(JointDesc<usize>, FieldPath)>, FieldError> {
    let mut out = Vec::with_capacity(specs.len());
    for (k, spec) in specs.iter().enumerate() {
        let path = FieldPath::root().key("joints").index(k);
        let find = |key: &str, name: &str| body_named(bodies, &path.key(key), name);
        let a = find("body_a", &spec.body_a)?;
        let b = spec.body_b.as_deref().map(|n| find("body_b", n)).transpose()?;
        let mut desc = JointDesc::new(
            spec.kind,
            a,
            b,
            vec3(&path.key("anchor"), spec.anchor)?,
            match spec.axis {
                Some(axis) => vec3(&path.key("axis"), axis)?,
                None => DVec3::Z,
            },
        );
        desc.anchor_b = spec
            .anchor_b
            .map(|v| vec3(&path.key("anchor_b"), v))
            .transpose()?;
        desc.limits = spec.limits;
        desc.swing_limit = spec.swing_limit;
        desc.motor = spec.motor;
        desc.spring = spec.spring;
        desc.length = spec.length;
        desc.collide_connected = spec.collide_connected;
        desc.name = spec.name.clone();
        desc.validate()
            .map_err(|e| FieldError::new(&joint_error_path(&e, &path), joint_error_message(&e)))?;
        out.push((desc, path));
    }
    Ok(out)
}

/// The index of the one body of `bodies` named `name`, which field `path`
/// gives (a joint's bodies, a `no_contact` pair).
pub(crate) fn body_named(bodies: &[BodyDesc], path: &FieldPath, name: &str) -> Result<usize, FieldError> {
    let mut hits = bodies.iter().enumerate().filter(|(_, b)| b.name == name);
    match (hits.next(), hits.next()) {
        (Some((i, _)), None) => Ok(i),
        (None, _) => Err(FieldError::new(path, format!("no body is named `{name}`"))),
        (Some(_), Some(_)) => Err(FieldError::new(
            path,
            format!("more than one body is named `{name}`: give them distinct names"),
        )),
    }
}

/// Each `[[no_contact]]` pair of the file as indices into `bodies`, the
/// lower first.
pub(crate) fn resolve_no_contact(
    specs: &[NoContactSpec],
    bodies: &[BodyDesc],
) -> Result<Vec<(usize, usize)>, FieldError> {
    specs
        .iter()
        .enumerate()
        .map(|(k, spec)| {
            let path = FieldPath::root().key("no_contact").index(k).key("bodies");
            let a = body_named(bodies, &path.index(0), &spec.bodies[0])?;
            let b = body_named(bodies, &path.index(1), &spec.bodies[1])?;
            if a == b {
                return Err(FieldError::new(
                    &path.index(1),
                    format!("`{}` twice: a body never touches itself", spec.bodies[1]),
                ));
            }
            Ok((a.min(b), a.max(b)))
        })
        .collect()
}

/// The field of joint `path` a world error is about (`joint.limits` ->
/// `joints[k].limits`).
pub(crate) fn joint_error_path(e: &WorldError, path: &FieldPath) -> FieldPath {
    match e {
        WorldError::BadValue { field, .. } => match field.strip_prefix("joint.") {
            Some(rest) => rest.split('.').fold(path.clone(), |p, key| p.key(key)),
            None => path.clone(),
        },
        _ => path.clone(),
    }
}

/// The message of a world error about a joint, without the field prefix
/// the path already gives.
pub(crate) fn joint_error_message(e: &WorldError) -> String {
    match e {
        WorldError::BadValue { message, .. } => message.clone(),
        other => other.to_string(),
    }
}
