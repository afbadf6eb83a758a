//! Contact persistence between steps: the impulses of each contact point are
//! remembered under (body pair, collider pair, feature pair) so that the next
//! step's solver starts from them (warm starting; Catto 2005). A flat vector
//! sorted by key, rebuilt every step and searched by bisection: deterministic
//! and allocation-free once warm.

use tumble_collide::{DVec3, Feature};

/// (body slot A, body slot B, collider index in A, collider index in B).
pub(crate) type PairKey = (u32, u32, u16, u16);

/// Impulses remembered for one contact point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CachedContact {
    pub key: PairKey,
    pub feature_a: Feature,
    pub feature_b: Feature,
    /// Accumulated normal impulse of the sub-step (N s).
    pub normal_impulse: f64,
    /// Accumulated friction impulse of the sub-step as a world vector (N s),
    /// re-projected on the next step's tangents (they follow the normal).
    pub tangent_impulse: DVec3,
}

impl CachedContact {
    fn order(&self) -> (PairKey, Feature, Feature) {
        (self.key, self.feature_a, self.feature_b)
    }
}

/// Finds the remembered impulses of a contact, if it existed last step.
pub(crate) fn lookup(cache: &[CachedContact], key: PairKey, fa: Feature, fb: Feature) -> Option<&CachedContact> {
    cache
        .binary_search_by(|c| c.order().cmp(&(key, fa, fb)))
        .ok()
        .map(|i| &cache[i])
}

/// Sorts a freshly built cache so that [`lookup`] works.
pub(crate) fn finish(cache: &mut [CachedContact]) {
    cache.sort_unstable_by(|a, b| a.order().cmp(&b.order()));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookup_finds_exact_feature_pairs_only() {
        let c = |key: PairKey, t: u32, j: f64| CachedContact {
            key,
            feature_a: Feature::vertex(t, 0),
            feature_b: Feature::face(1),
            normal_impulse: j,
            tangent_impulse: DVec3::ZERO,
        };
        let mut cache = vec![c((3, 4, 0, 0), 7, 1.0), c((1, 2, 0, 0), 5, 2.0), c((1, 2, 0, 1), 5, 3.0)];
        finish(&mut cache);
        assert_eq!(lookup(&cache, (1, 2, 0, 1), Feature::vertex(5, 0), Feature::face(1)).unwrap().normal_impulse, 3.0);
        assert!(lookup(&cache, (1, 2, 0, 1), Feature::vertex(5, 1), Feature::face(1)).is_none());
        assert!(lookup(&cache, (9, 9, 0, 0), Feature::vertex(5, 0), Feature::face(1)).is_none());
    }
}
