//! Input checks shared by constructors and setters; each returns the value or a typed error.

use super::error::BodyError;
use tumble_collide::math::{DQuat, DVec3};
use tumble_collide::Pose;

/// Relative slack on the inertia triangle inequality: mass-property code that computes
/// a flat plate (`I3 = I1 + I2` exactly) must not be rejected for round-off.
const TRIANGLE_SLACK: f64 = 1e-6;

pub(crate) fn finite_vec(what: &'static str, value: DVec3) -> Result<DVec3, BodyError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(BodyError::NonFiniteVector { what, value })
    }
}

pub(crate) fn finite(what: &'static str, value: f64) -> Result<f64, BodyError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(BodyError::NonFiniteScalar { what, value })
    }
}

pub(crate) fn non_negative(what: &'static str, value: f64) -> Result<f64, BodyError> {
    let value = finite(what, value)?;
    if value < 0.0 {
        Err(BodyError::Negative { what, value })
    } else {
        Ok(value)
    }
}

/// Returns `1 / mass`.
pub(crate) fn inverse_mass(mass: f64) -> Result<f64, BodyError> {
    let mass = finite("mass", mass)?;
    if mass <= 0.0 {
        return Err(BodyError::NonPositiveMass(mass));
    }
    let inv = 1.0 / mass;
    // A subnormal mass would give an infinite inverse.
    finite("inverse mass", inv)
}

/// Returns the component-wise inverse of the principal moments.
pub(crate) fn inverse_inertia(moments: DVec3) -> Result<DVec3, BodyError> {
    let moments = finite_vec("principal inertia", moments)?;
    if moments.min_element() <= 0.0 {
        return Err(BodyError::NonPositiveInertia(moments));
    }
    let (a, b, c) = (moments.x, moments.y, moments.z);
    let slack = TRIANGLE_SLACK * moments.max_element();
    if a + b < c - slack || a + c < b - slack || b + c < a - slack {
        return Err(BodyError::InertiaTriangleInequality(moments));
    }
    finite_vec("inverse principal inertia", moments.recip())
}

/// Validates an orientation the way [`Pose::new`] does (finite, unit within
/// [`Pose::UNIT_TOLERANCE`], then renormalised exactly).
pub(crate) fn orientation(rotation: DQuat) -> Result<DQuat, BodyError> {
    Pose::new(DVec3::ZERO, rotation)
        .map(|p| p.rotation)
        .map_err(|source| BodyError::Orientation { rotation, source })
}
