//! The error type of mass-property computations: every way the input can be
//! unfit for a mass, with what was found and what was expected.

use crate::hull::HullError;
use crate::mesh::MeshError;

/// Why mass properties could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MassError {
    /// The mesh does not bound a solid: open, non-manifold or inconsistently
    /// wound (the inner [`MeshError`] says which edge).
    #[error("mesh is not a closed, consistently outward-wound solid: {0}; use MassFallback::ConvexHull or MassFallback::Shell to approximate it")]
    NotSolid(#[source] MeshError),
    /// The closed mesh encloses zero or negative volume (flat, or wound inside
    /// out: triangles must be counter-clockwise seen from outside).
    #[error("mesh encloses no positive volume (signed volume {volume:e} m^3): flat, or wound inside out")]
    NonPositiveVolume {
        /// Signed volume found (m^3).
        volume: f64,
    },
    /// A density or total mass that is NaN, infinite, zero or negative.
    #[error("{what} must be finite and > 0, got {value}")]
    BadSpec {
        /// `"density (kg/m^3)"` or `"mass (kg)"`.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// A primitive dimension that is NaN, infinite or out of range.
    #[error("{shape}: {name} must be finite and {expected} (m), got {value}")]
    BadDimension {
        /// Which primitive.
        shape: &'static str,
        /// Which parameter.
        name: &'static str,
        /// What was expected, e.g. `"> 0"`.
        expected: &'static str,
        /// The value given.
        value: f64,
    },
    /// Dimensions that are each valid but inconsistent (torus with r >= R).
    #[error("{shape}: {message}")]
    Constraint {
        /// Which primitive.
        shape: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A shell thickness that is NaN, infinite, zero or negative.
    #[error("shell thickness must be finite and > 0 (m), got {0}")]
    BadThickness(f64),
    /// A shell over a surface without area.
    #[error("shell surface has no area ({area:e} m^2)")]
    ZeroArea {
        /// Total surface area found (m^2).
        area: f64,
    },
    /// The convex-hull fallback could not build a hull.
    #[error("convex hull fallback failed: {0}")]
    Hull(#[from] HullError),
    /// [`MassProperties::combine`](super::MassProperties::combine) of no parts.
    #[error("a composite body needs at least one part, got none")]
    EmptyComposite,
    /// One part of a composite is invalid.
    #[error("part {index} of the composite body is invalid: {source}")]
    BadPart {
        /// Index of the part in the slice.
        index: usize,
        /// What is wrong with it.
        source: Box<MassError>,
    },
    /// Mass properties that no physical body has (non-finite values, mass
    /// <= 0, asymmetric tensor, negative moments, triangle inequality broken).
    #[error("invalid mass properties: {reason}")]
    Invalid {
        /// What check failed, with the values.
        reason: String,
    },
    /// The result overflowed or underflowed f64 (inputs of absurd scale).
    #[error("mass properties are not finite ({what}): input scale out of range for f64")]
    NonFiniteResult {
        /// Which quantity.
        what: &'static str,
    },
    /// The re-expressed mesh failed validation.
    #[error(transparent)]
    Mesh(MeshError),
}

impl MassError {
    /// `true` for the errors that say "this mesh is not a solid" (open,
    /// non-manifold, inconsistently wound, no positive volume): the cases a
    /// [`MassFallback`](super::MassFallback) may handle.
    pub fn is_not_solid(&self) -> bool {
        matches!(self, MassError::NotSolid(_) | MassError::NonPositiveVolume { .. })
    }

    /// Sorts a mesh closedness error into [`MassError::NotSolid`] or
    /// [`MassError::NonPositiveVolume`].
    pub(crate) fn from_solid_check(e: MeshError) -> MassError {
        match e {
            MeshError::NonPositiveVolume { volume } if !volume.is_finite() => {
                MassError::NonFiniteResult { what: "volume" }
            }
            MeshError::NonPositiveVolume { volume } => MassError::NonPositiveVolume { volume },
            other => MassError::NotSolid(other),
        }
    }
}
