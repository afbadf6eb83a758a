//! Errors of the world API. Every one leaves the world unchanged.

use super::handles::{BodyId, JointId};

/// Why a world call was rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WorldError {
    /// The handle does not refer to a live body (removed, or from another world).
    #[error("body {0:?} does not exist (removed, or never added)")]
    StaleBody(BodyId),
    /// The handle does not refer to a live joint (removed, or its body was).
    #[error("joint {0:?} does not exist (removed, or one of its bodies was)")]
    StaleJoint(JointId),
    /// A numeric field is out of range or not finite.
    #[error("{field}: {message}")]
    BadValue {
        /// Field name (e.g. "settings.dt", "body.linear_velocity").
        field: &'static str,
        /// What was expected and what was given.
        message: String,
    },
    /// A body description has no shapes where it needs one: a static body,
    /// or a dynamic one whose mass properties are not given.
    #[error(
        "body has no shapes: a static body needs one, and a dynamic one without shapes needs \
         its mass properties (MassDesc::Inertial)"
    )]
    NoShapes,
    /// A shape cannot be used as given.
    #[error("shapes[{index}]: {message}")]
    BadShape {
        /// Index of the shape in the description.
        index: usize,
        /// What is wrong.
        message: String,
    },
    /// The operation does not apply to this kind of body.
    #[error("body {body:?}: {message}")]
    WrongKind {
        /// Which body.
        body: BodyId,
        /// What was attempted.
        message: &'static str,
    },
}
