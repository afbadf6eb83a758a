//! Errors of the broad phase API.

use super::aabb::AabbError;
use super::proxy::ProxyId;

/// Why a broad phase call was rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BroadPhaseError {
    /// The box was invalid (NaN, infinite or inverted).
    #[error("invalid AABB: {0}")]
    Aabb(#[from] AabbError),
    /// The id was never issued by this broad phase, or its slot has been reused.
    #[error("{0} is unknown or stale (its slot was never issued or has been reused)")]
    UnknownProxy(ProxyId),
    /// The proxy was already removed.
    #[error("{0} was already removed")]
    AlreadyRemoved(ProxyId),
    /// More proxies than the endpoint encoding allows (2^31 slots).
    #[error("too many proxies: at most {max} slots")]
    TooManyProxies {
        /// The slot limit.
        max: u32,
    },
}
