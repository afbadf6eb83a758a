//! Settings of the collision and distance queries, each with its unit,
//! effect and default (PQP's query flags: `PQP_FIRST_CONTACT`, `rel_err`,
//! `abs_err`), and their validation.

use super::error::QueryError;
use crate::bvh::DistanceTolerance;
use serde::{Deserialize, Serialize};

/// What a collision query reports besides the boolean.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum ReportMode {
    /// Only whether the meshes intersect. Always stops at the first
    /// intersecting triangle pair (there is nothing else to find).
    Boolean,
    /// Every intersecting triangle pair (closed triangles: touching counts),
    /// sorted. The default.
    #[default]
    TrianglePairs,
    /// The triangle pairs and the contacts of every candidate pair: exact
    /// vertex/face and edge/edge contacts within `contact_margin`, push-out
    /// contacts of intersecting pairs, duplicates merged.
    Contacts,
}

/// Options of [`super::collide`](fn@super::collide) and [`super::collide_primitive`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CollideOptions {
    /// Stop at the first intersecting triangle pair (a first-contact query):
    /// the report then holds that one pair and the contacts found so far.
    /// Default `false`.
    pub stop_at_first: bool,
    /// What to report. Default [`ReportMode::TrianglePairs`].
    pub report: ReportMode,
    /// Largest gap (m, finite, >= 0) at which [`ReportMode::Contacts`] still
    /// reports a contact (speculative contacts); raising it reports pairs
    /// that are close but not touching, and costs more triangle tests. No
    /// effect in the other modes. Default 0: touching and intersecting only.
    pub contact_margin: f64,
}

impl Default for CollideOptions {
    fn default() -> Self {
        CollideOptions {
            stop_at_first: false,
            report: ReportMode::TrianglePairs,
            contact_margin: 0.0,
        }
    }
}

impl CollideOptions {
    /// Checks the fields.
    pub fn validate(&self) -> Result<(), QueryError> {
        nonneg_finite("CollideOptions::contact_margin", self.contact_margin)
    }

    /// `true` when the walk ends at the first intersecting pair.
    pub(crate) fn stops_at_first(&self) -> bool {
        self.stop_at_first || self.report == ReportMode::Boolean
    }
}

/// Options of [`super::distance`](fn@super::distance) and [`super::distance_primitive`]: PQP's
/// approximate distance. A node pair is skipped when its box lower bound
/// `lb` satisfies `lb * (1 + rel_err) >= best` or `lb + abs_err >= best`, so
/// the answer lies in `[d, max((1 + rel_err) d, d + abs_err)]` for the true
/// distance `d`; larger values prune more and answer faster. Both 0 (the
/// default) is the exact distance.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct DistanceOptions {
    /// Relative error allowed (dimensionless, finite, >= 0). Default 0.
    pub rel_err: f64,
    /// Absolute error allowed (m, finite, >= 0). Default 0.
    pub abs_err: f64,
}

impl DistanceOptions {
    /// Checks the fields.
    pub fn validate(&self) -> Result<(), QueryError> {
        nonneg_finite("DistanceOptions::rel_err", self.rel_err)?;
        nonneg_finite("DistanceOptions::abs_err", self.abs_err)
    }

    /// The traversal's pruning rule.
    pub(crate) fn tolerance(&self) -> DistanceTolerance {
        DistanceTolerance {
            rel_err: self.rel_err,
            abs_err: self.abs_err,
        }
    }
}

/// `Ok` for a finite value >= 0.
pub(crate) fn nonneg_finite(option: &'static str, value: f64) -> Result<(), QueryError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(bad_nonneg(option, value))
    }
}

/// The error for `option` = `value` where a finite value >= 0 was due: what
/// [`nonneg_finite`] returns, and what every query makes of a tree walk's
/// refusal of its margin or tolerance.
pub(crate) fn bad_nonneg(option: &'static str, value: f64) -> QueryError {
    QueryError::BadOption {
        option,
        expected: "finite and >= 0",
        value,
    }
}
