//! Typed errors for body constructors, setters and force accumulators.

use super::state::BodyKind;
use tumble_collide::math::{DQuat, DVec3};
use tumble_collide::PoseError;

/// Why a rigid body constructor, setter or accumulator rejected its input.
///
/// Every variant names the offending quantity; the body is left unchanged.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BodyError {
    /// A scalar input is NaN or infinite.
    #[error("{what} must be finite, got {value}")]
    NonFiniteScalar {
        /// Which quantity (e.g. "mass", "restitution").
        what: &'static str,
        /// The value that was passed.
        value: f64,
    },
    /// A vector input has a NaN or infinite component.
    #[error("{what} must be finite, got {value:?}")]
    NonFiniteVector {
        /// Which quantity (e.g. "force", "application point").
        what: &'static str,
        /// The value that was passed.
        value: DVec3,
    },
    /// The mass is zero or negative (use [`super::RigidBody::new_static`] for infinite mass).
    #[error("mass must be > 0 kg, got {0}")]
    NonPositiveMass(f64),
    /// A principal moment of inertia is zero or negative.
    #[error("principal moments of inertia must all be > 0 kg m^2, got {0:?}")]
    NonPositiveInertia(DVec3),
    /// The principal moments violate the triangle inequality `I_a + I_b >= I_c` that every
    /// real mass distribution satisfies (most likely a typo or a swapped inverse).
    #[error("principal moments {0:?} violate the triangle inequality I_a + I_b >= I_c")]
    InertiaTriangleInequality(DVec3),
    /// The inertia tensor is not symmetric; the value is its largest `|I_ij - I_ji|`.
    #[error("inertia tensor must be symmetric, largest |I_ij - I_ji| = {0} kg m^2")]
    AsymmetricInertia(f64),
    /// A coefficient that must be non-negative is negative.
    #[error("{what} must be >= 0, got {value}")]
    Negative {
        /// Which coefficient (e.g. "friction", "linear damping").
        what: &'static str,
        /// The value that was passed.
        value: f64,
    },
    /// The orientation is not finite or not a unit quaternion.
    #[error("invalid orientation {rotation:?}: {source}")]
    Orientation {
        /// The quaternion that was passed.
        rotation: DQuat,
        /// What was wrong with it.
        source: PoseError,
    },
    /// The operation needs a body of another kind (e.g. setting the mass of a static body).
    #[error("{operation} needs a {expected:?} body, this one is {found:?}")]
    WrongKind {
        /// What was attempted.
        operation: &'static str,
        /// The kind the operation needs.
        expected: BodyKind,
        /// The kind of this body.
        found: BodyKind,
    },
}
