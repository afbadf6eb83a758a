//! How much a body weighs: a density or a total mass, validated at the
//! boundary.

use super::MassError;
use serde::{Deserialize, Serialize};

/// The mass of a body, given either as a uniform density or as a total.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum MassSpec {
    /// Uniform density (kg/m^3); the mass follows from the volume. For shells
    /// the mass is `density * thickness * area`.
    Density(f64),
    /// Total mass (kg); the density follows from the volume (or area).
    Mass(f64),
}

impl MassSpec {
    /// `Ok` when the value is finite and positive.
    pub fn validate(self) -> Result<(), MassError> {
        let (what, value) = match self {
            MassSpec::Density(v) => ("density (kg/m^3)", v),
            MassSpec::Mass(v) => ("mass (kg)", v),
        };
        if value.is_finite() && value > 0.0 {
            Ok(())
        } else {
            Err(MassError::BadSpec { what, value })
        }
    }

    /// Total mass (kg) of a body of `measure` (m^3 for solids; for shells,
    /// `thickness * area`).
    pub fn mass_for(self, measure: f64) -> Result<f64, MassError> {
        self.validate()?;
        let m = match self {
            MassSpec::Density(rho) => rho * measure,
            MassSpec::Mass(m) => m,
        };
        if m.is_finite() && m > 0.0 {
            Ok(m)
        } else {
            Err(MassError::NonFiniteResult { what: "mass" })
        }
    }
}
