//! Surface material coefficients used by the contact solver (thesis 7.1; Coulomb friction).

use super::error::BodyError;
use super::validate::non_negative;
use serde::{Deserialize, Serialize};

/// Restitution and friction of a body's surface.
///
/// How two materials combine at a contact is the solver's business; this only stores
/// validated per-body coefficients.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Material {
    restitution: f64,
    friction: f64,
}

impl Default for Material {
    /// Restitution 0 (plastic impact), friction 0.5.
    fn default() -> Self {
        Material {
            restitution: 0.0,
            friction: 0.5,
        }
    }
}

impl Material {
    /// A material with coefficient of restitution `restitution` (dimensionless, >= 0;
    /// 0 = no bounce, 1 = elastic, above 1 the contact gains energy) and Coulomb friction
    /// coefficient `friction` (dimensionless, >= 0; 0 = frictionless).
    pub fn new(restitution: f64, friction: f64) -> Result<Material, BodyError> {
        Ok(Material {
            restitution: non_negative("restitution", restitution)?,
            friction: non_negative("friction", friction)?,
        })
    }

    /// Coefficient of restitution (dimensionless).
    pub fn restitution(&self) -> f64 {
        self.restitution
    }

    /// Coulomb friction coefficient (dimensionless).
    pub fn friction(&self) -> f64 {
        self.friction
    }
}
