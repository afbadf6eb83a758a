//! The `[[joints]]` of a scene file: bodies found by name, values checked
//! where they are written (the path of each field kept, so the world's
//! objections point at the file's line).

use super::error::{FieldError, FieldPath};
use super::resolve::body_named;
use super::schema::JointSpec;
use super::values::vec3;
use crate::joint::JointDesc;
use crate::scenes::SceneGear;
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
        desc.friction = spec.friction;
        desc.collide_connected = spec.collide_connected;
        desc.name = spec.name.clone();
        desc.validate()
            .map_err(|e| FieldError::new(&joint_error_path(&e, &path), joint_error_message(&e)))?;
        out.push((desc, path));
    }
    Ok(out)
}

/// The gears of the file's joints (`specs`, which are `joints[first..]`),
/// each leader found by name among all of `joints` (a robot's too).
pub(crate) fn resolve_gears(
    specs: &[JointSpec],
    joints: &[JointDesc<usize>],
    first: usize,
) -> Result<Vec<SceneGear>, FieldError> {
    let mut out = Vec::new();
    for (k, spec) in specs.iter().enumerate() {
        let Some(gear) = &spec.gear else { continue };
        let path = FieldPath::root().key("joints").index(k).key("gear").key("leader");
        let named: Vec<usize> = (0..joints.len())
            .filter(|&i| joints[i].name == gear.leader)
            .collect();
        let leader = match named[..] {
            [i] => i,
            [] => {
                let known: Vec<&str> = joints
                    .iter()
                    .map(|j| j.name.as_str())
                    .filter(|n| !n.is_empty())
                    .collect();
                return Err(FieldError::new(
                    &path,
                    format!(
                        "no joint is named `{}` (named joints: {})",
                        gear.leader,
                        known.join(", ")
                    ),
                ));
            }
            _ => {
                return Err(FieldError::new(
                    &path,
                    format!(
                        "{} joints are named `{}`: a gear's leader needs a name of its own",
                        named.len(),
                        gear.leader
                    ),
                ))
            }
        };
        out.push(SceneGear {
            follower: first + k,
            leader,
            ratio: gear.ratio,
            offset: gear.offset,
        });
    }
    Ok(out)
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
