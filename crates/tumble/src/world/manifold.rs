//! Contact persistence between steps: the impulses of each contact point are
//! remembered under (body pair, collider pair, feature pair) so that the next
//! step's solver starts from them (warm starting; Catto 2005). A flat vector
//! sorted by key, rebuilt every step and searched by bisection: deterministic
//! and allocation-free once warm.
//!
//! Feature ids alone are not enough: where two features coincide (the
//! corners of equal boxes stacked exactly), a clipped point flips between
//! "vertex on face" and "edge crossing edge" from one step to the next, and a
//! feature id that names a corner of a clipped polygon by its position in the
//! polygon can name another corner next step. Applying one corner's impulse
//! at another injects energy (a torque that was never there). So a feature
//! match counts only if the point is also where it was, within
//! [`MATCH_DISTANCE`] in A's body frame; otherwise the point takes the
//! impulses of the nearest cached point of the same collider pair within that
//! distance (as Bullet's persistent manifolds match by position).

use tumble_collide::{DVec3, Feature};

/// (body slot A, body slot B, collider index in A, collider index in B).
pub(crate) type PairKey = (u32, u32, u16, u16);

/// Largest distance (m, in A's body frame) at which a contact inherits the
/// impulses of a cached point whose features differ.
pub(crate) const MATCH_DISTANCE: f64 = 0.01;

/// Impulses remembered for one contact point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CachedContact {
    pub key: PairKey,
    pub feature_a: Feature,
    pub feature_b: Feature,
    /// Contact point in A's body frame (m).
    pub local_a: DVec3,
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

/// Finds the remembered impulses of a contact: by features, else by position.
pub(crate) fn lookup(
    cache: &[CachedContact],
    key: PairKey,
    fa: Feature,
    fb: Feature,
    local_a: DVec3,
) -> Option<&CachedContact> {
    let near = |c: &CachedContact| (c.local_a - local_a).length_squared() <= MATCH_DISTANCE * MATCH_DISTANCE;
    if let Ok(i) = cache.binary_search_by(|c| c.order().cmp(&(key, fa, fb))) {
        // Same features but elsewhere means the ids were reused for another
        // point (a clipped polygon renumbered): do not trust them.
        if near(&cache[i]) {
            return Some(&cache[i]);
        }
    }
    let start = cache.partition_point(|c| c.key < key);
    let end = start + cache[start..].partition_point(|c| c.key == key);
    cache[start..end]
        .iter()
        .map(|c| ((c.local_a - local_a).length_squared(), c))
        .filter(|(d2, _)| *d2 <= MATCH_DISTANCE * MATCH_DISTANCE)
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, c)| c)
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
            local_a: DVec3::new(t as f64, 0.0, 0.0),
            normal_impulse: j,
            tangent_impulse: DVec3::ZERO,
        };
        let mut cache = vec![c((3, 4, 0, 0), 7, 1.0), c((1, 2, 0, 0), 5, 2.0), c((1, 2, 0, 1), 5, 3.0)];
        finish(&mut cache);
        let far = DVec3::splat(100.0);
        let found = |key, fa, p| lookup(&cache, key, fa, Feature::face(1), p).map(|c| c.normal_impulse);
        assert_eq!(found((1, 2, 0, 1), Feature::vertex(5, 0), DVec3::new(5.0, 0.0, 0.0)), Some(3.0), "by features");
        assert_eq!(found((1, 2, 0, 1), Feature::vertex(5, 0), far), None, "same features, elsewhere");
        assert_eq!(found((1, 2, 0, 1), Feature::vertex(5, 1), far), None, "features differ, far away");
        assert_eq!(
            found((1, 2, 0, 1), Feature::edge(9, 1), DVec3::new(5.005, 0.0, 0.0)),
            Some(3.0),
            "features differ, same place"
        );
        assert_eq!(found((1, 2, 0, 0), Feature::edge(9, 1), DVec3::new(5.005, 0.0, 0.0)), Some(2.0));
        assert_eq!(found((9, 9, 0, 0), Feature::vertex(5, 0), DVec3::new(5.0, 0.0, 0.0)), None, "other pair");
    }
}
