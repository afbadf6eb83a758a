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
//!
//! Friction lives on contact patches (see `solver::contact_solver`): each
//! patch's friction impulses are remembered under the collider pair and the
//! patch normal, and so is where a sticking mesh patch is anchored
//! (docs/pipeline.md, "Anchors").

use tumble_collide::{DVec3, Feature, Pose};

/// (body slot A, body slot B, collider index in A, collider index in B).
pub(crate) type PairKey = (u32, u32, u16, u16);

/// Largest distance (m, in A's body frame) at which a contact inherits the
/// impulses of a cached point whose features differ.
pub(crate) const MATCH_DISTANCE: f64 = 0.01;

/// Impulses remembered for one contact point.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct CachedContact {
    pub key: PairKey,
    pub feature_a: Feature,
    pub feature_b: Feature,
    /// Contact point in A's body frame (m).
    pub local_a: DVec3,
    /// Accumulated normal impulse of the sub-step (N s).
    pub normal_impulse: f64,
}

/// Friction remembered for one contact patch: patches of a collider pair
/// are told apart by their normals (a mesh pair can touch in several places).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct CachedPatch {
    pub key: PairKey,
    /// Unit patch normal, world frame.
    pub normal: DVec3,
    /// Tangential friction impulse as a world vector (N s), re-projected on
    /// the next step's tangents.
    pub tangent_impulse: DVec3,
    /// Twist friction impulse about the normal (N m s).
    pub twist_impulse: f64,
    /// Where the patch stuck: one material point of A and one of B that
    /// coincided when it began to stick, each from its body's centre of
    /// mass in its body axes (m); `None` while it slides or does not press.
    pub anchor: Option<[DVec3; 2]>,
}

/// Where a collider pair with a triangle mesh was when its contacts were
/// last searched for (`step::narrow`: while it has barely moved since, the
/// points it kept are re-evaluated instead of searched for again).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct SearchedPair {
    pub key: PairKey,
    /// The moving side's collider pose in the other collider's frame: the
    /// mesh against a half-space, the smaller of two meshes (by bounding
    /// sphere; B when equal).
    pub rel: Pose,
}

/// The pose at the last search of collider pair `key` in `searches`
/// (sorted by key), if it has one.
pub(crate) fn searched_at(searches: &[SearchedPair], key: PairKey) -> Option<&Pose> {
    searches
        .binary_search_by_key(&key, |s| s.key)
        .ok()
        .map(|i| &searches[i].rel)
}

/// Contacts of one collider pair whose normals are within this cosine of a
/// patch's seed normal belong to that patch (about 18 degrees: the facets
/// of a curved mesh surface around one contact, not the two walls of a
/// corner). A patch that finds a cached patch of the same pair within it
/// inherits its friction.
pub(crate) const PATCH_COS: f64 = 0.95;

/// The remembered friction of the patch of `key` whose normal is closest to
/// `normal` (within [`PATCH_COS`]), searched from `cursor` as
/// [`points_of`] does. The cache must be sorted by key.
pub(crate) fn lookup_patch<'a>(
    cache: &'a [CachedPatch],
    key: PairKey,
    normal: DVec3,
    cursor: &mut usize,
) -> Option<&'a CachedPatch> {
    let run = run_of(cache, |c| c.key, key, cursor);
    cache[run]
        .iter()
        .filter(|c| c.normal.dot(normal) >= PATCH_COS)
        .max_by(|x, y| x.normal.dot(normal).total_cmp(&y.normal.dot(normal)))
}

/// The cached points of one collider pair (the cache must be sorted by
/// key). The search starts at `cursor` and leaves it at the answer: asked
/// for keys in increasing order (the narrow phase walks its pairs so), it
/// gallops forward a few entries instead of bisecting the whole cache,
/// whose bisections missed the cache lines of a large pile at every pair.
/// A key before the cursor is found too, from the start.
pub(crate) fn points_of<'a>(
    cache: &'a [CachedContact],
    key: PairKey,
    cursor: &mut usize,
) -> &'a [CachedContact] {
    &cache[run_of(cache, |c| c.key, key, cursor)]
}

/// The run of entries with `key` in `cache` (sorted by `key_of`), searched
/// from `cursor` forward (from the start if `key` lies before it).
fn run_of<T>(
    cache: &[T],
    key_of: impl Fn(&T) -> PairKey,
    key: PairKey,
    cursor: &mut usize,
) -> std::ops::Range<usize> {
    let from = if *cursor <= cache.len() && (*cursor == 0 || key_of(&cache[*cursor - 1]) < key) {
        *cursor
    } else {
        0
    };
    let start = from + gallop(&cache[from..], |c| key_of(c) < key);
    let end = start + gallop(&cache[start..], |c| key_of(c) == key);
    *cursor = start;
    start..end
}

/// The first index of `items` at which `before` is false (`items` holds
/// every `before` entry first), found by doubling steps from the front and
/// a bisection of the last step: O(log d) for an answer d entries in.
fn gallop<T>(items: &[T], before: impl Fn(&T) -> bool) -> usize {
    let mut step = 1;
    while step <= items.len() && before(&items[step - 1]) {
        step *= 2;
    }
    let lo = step / 2;
    let hi = step.min(items.len());
    lo + items[lo..hi].partition_point(before)
}

/// Finds the remembered impulses of a contact among its collider pair's
/// cached points (`points_of`): by features, else by position. A pair holds
/// a handful of points, scanned linearly.
pub(crate) fn lookup(
    same: &[CachedContact],
    fa: Feature,
    fb: Feature,
    local_a: DVec3,
) -> Option<&CachedContact> {
    let near = |c: &&CachedContact| (c.local_a - local_a).length_squared() <= MATCH_DISTANCE * MATCH_DISTANCE;
    // Same features but elsewhere means the ids were reused for another point
    // (a clipped polygon renumbered): then they are not trusted.
    same.iter()
        .filter(near)
        .find(|c| c.feature_a == fa && c.feature_b == fb)
        .or_else(|| {
            same.iter().filter(near).min_by(|x, y| {
                (x.local_a - local_a)
                    .length_squared()
                    .total_cmp(&(y.local_a - local_a).length_squared())
            })
        })
}

/// Whether a contact of features `fa`, `fb` at `local_a` (A's body frame)
/// was kept last step: a cached point of its collider pair (`same`) has
/// the same features within [`MATCH_DISTANCE`] of it. Contact reduction
/// keeps such points while they still span the patch
/// (`tumble_collide::narrow::reduce_patch`).
pub(crate) fn was_kept(same: &[CachedContact], fa: Feature, fb: Feature, local_a: DVec3) -> bool {
    same.iter().any(|c| {
        c.feature_a == fa
            && c.feature_b == fb
            && (c.local_a - local_a).length_squared() <= MATCH_DISTANCE * MATCH_DISTANCE
    })
}

/// Orders a freshly built cache by key so that [`lookup`] works. The world
/// builds it in pair order already, so this is a check plus a stable sort
/// that does nothing in that case.
pub(crate) fn finish(points: &mut [CachedContact], patches: &mut [CachedPatch]) {
    if !points.windows(2).all(|w| w[0].key <= w[1].key) {
        points.sort_by_key(|c| c.key);
    }
    if !patches.windows(2).all(|w| w[0].key <= w[1].key) {
        patches.sort_by_key(|c| c.key);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The galloping search from a cursor finds what a bisection of the
    /// whole cache finds, for keys asked in order, out of order, present
    /// and absent.
    #[test]
    fn search_from_a_cursor_finds_every_run() {
        let keys: Vec<PairKey> = [(1, 2), (1, 2), (1, 5), (2, 3), (2, 3), (2, 3), (4, 9), (7, 8)]
            .iter()
            .map(|&(a, b)| (a, b, 0, 0))
            .collect();
        let bisect = |key: PairKey| {
            let start = keys.partition_point(|k| *k < key);
            start..start + keys[start..].partition_point(|k| *k == key)
        };
        let asked: Vec<PairKey> = (0..10u32)
            .flat_map(|a| (0..10u32).map(move |b| (a, b, 0, 0)))
            .collect();
        let mut cursor = 0;
        for &key in asked.iter().chain(asked.iter().rev()) {
            assert_eq!(run_of(&keys, |k| *k, key, &mut cursor), bisect(key), "{key:?}");
        }
        for i in 0..=keys.len() + 2 {
            let mut cursor = i;
            assert_eq!(run_of(&keys, |k| *k, (2, 3, 0, 0), &mut cursor), 3..6);
        }
    }

    #[test]
    fn lookup_finds_exact_feature_pairs_only() {
        let c = |key: PairKey, t: u32, j: f64| CachedContact {
            key,
            feature_a: Feature::vertex(t, 0),
            feature_b: Feature::face(1),
            local_a: DVec3::new(t as f64, 0.0, 0.0),
            normal_impulse: j,
        };
        let mut cache = vec![
            c((3, 4, 0, 0), 7, 1.0),
            c((1, 2, 0, 0), 5, 2.0),
            c((1, 2, 0, 1), 5, 3.0),
        ];
        finish(&mut cache, &mut []);
        let far = DVec3::splat(100.0);
        let found = |key, fa, p| {
            lookup(points_of(&cache, key, &mut 0), fa, Feature::face(1), p).map(|c| c.normal_impulse)
        };
        assert_eq!(
            found((1, 2, 0, 1), Feature::vertex(5, 0), DVec3::new(5.0, 0.0, 0.0)),
            Some(3.0),
            "by features"
        );
        assert_eq!(
            found((1, 2, 0, 1), Feature::vertex(5, 0), far),
            None,
            "same features, elsewhere"
        );
        assert_eq!(
            found((1, 2, 0, 1), Feature::vertex(5, 1), far),
            None,
            "features differ, far away"
        );
        assert_eq!(
            found((1, 2, 0, 1), Feature::edge(9, 1), DVec3::new(5.005, 0.0, 0.0)),
            Some(3.0),
            "features differ, same place"
        );
        assert_eq!(
            found((1, 2, 0, 0), Feature::edge(9, 1), DVec3::new(5.005, 0.0, 0.0)),
            Some(2.0)
        );
        assert_eq!(
            found((9, 9, 0, 0), Feature::vertex(5, 0), DVec3::new(5.0, 0.0, 0.0)),
            None,
            "other pair"
        );
    }
}
