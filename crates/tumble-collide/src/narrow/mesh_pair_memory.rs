//! Temporal coherence for two meshes (issue 15, "contacts re-validated
//! rather than re-found"): a pair that barely moves keeps the leaf pairs of
//! one walk of the two OBB-trees and, step after step, tests only the
//! triangle pairs of that list that its motion since then could have
//! brought within the margin; a pair that moves more keeps where its last
//! walk along the drift ended, and begins the next one there
//! (`bvh::front`; the same contacts, about half the box tests where two
//! meshes stay entangled, as the torus chain's links).
//!
//! The idea is the Verlet list of molecular dynamics (neighbours within a
//! cutoff plus a skin, valid while no particle has moved half the skin)
//! applied to triangle pairs: the walk collects the leaf pairs within the
//! margin plus a slack `s`; later, while every point of B has moved (in A's
//! frame) less than what is left of `s`, no triangle pair outside the list
//! can have come within the margin. The list holds the triangle pairs of
//! those leaf pairs that are within the walk's reach, each with its
//! distance at the walk, and a pair is skipped while that distance, less
//! the motion since, stays beyond the margin: in a settled pile most listed
//! pairs are, and the tests left are about those that give contacts (each
//! shared vertex and edge tested once, through its owner).
//!
//! Both the skips and the list are exact in the sense that matters: a
//! skipped or unlisted pair provably gives no contact, and the listed pairs
//! are tested in the walk's depth-first order, which depends on the trees
//! alone (`bvh::traverse` descends by box size, not by pose). So the contacts
//! are the same bits whether the list is reused or found again this step:
//! they are every contact the triangle test gives for any pair of the two
//! meshes, a function of the poses, the margin and the drift only. That is
//! what keeps a step independent of the memory's history (thread counts,
//! snapshots, sleeping).

use super::contact_mesh::{finish_mesh_mesh, PlacedPair, VERTEX_CACHE};
use super::dispatch::{check_margin_and_drift, refuse_non_finite};
use super::NarrowError;
use crate::bvh::{self, ObbTree, Traverse, WalkFront};
use crate::contact::Contact;
use crate::drift::Drift;
use crate::math::{DMat3, DQuat, DVec3};
use crate::pose::Pose;
use crate::shape::MeshShape;
use crate::triangle::triangle_distance;
use std::sync::Arc;

/// A pair qualifies while no point of B can move farther than this (m)
/// relative to A within the look-ahead: resting and slowly sliding pairs.
/// Faster pairs walk their trees along the drift every step, from their
/// last walk's front (`contact_mesh::contact_mesh_mesh_front`), which
/// follows a fast part's own path instead of a list grown around all of it.
pub const RECALL_MAX_REACH: f64 = 0.002;

/// The slack (m) a new list is found with beyond the margin and the
/// look-ahead: how far B may then move against A before the list must be
/// found again. A resting pair moves microns per step and keeps its list
/// for hundreds of steps; a larger slack lists (and bounds) more pairs.
pub const RECALL_SLACK: f64 = 0.002;

/// Round-off allowance (m) of the bounds below: far above the error of the
/// coordinates' arithmetic (1e-15 relative), far below any margin.
const ROUND_OFF: f64 = 1e-9;

/// What one walk of two OBB-trees found, kept for the following steps: a
/// resting pair's list of triangle pairs, or a moving pair's front (where
/// its walk along the drift ended, `bvh::front`).
#[derive(Debug, Clone)]
pub struct MeshPairMemory {
    /// The trees the memory indexes: it is only ever used for them (held,
    /// so that no other tree can take their place in memory).
    trees: (Arc<ObbTree>, Arc<ObbTree>),
    kept: Kept,
}

#[derive(Debug, Clone)]
enum Kept {
    /// A resting pair's triangle pairs (module docs).
    List {
        /// B's pose in A's frame at the walk.
        rel: Pose,
        /// The margin the walk used (m): the step's margin plus B's
        /// look-ahead reach plus [`RECALL_SLACK`].
        reach: f64,
        /// The triangle pairs `(A's, B's)` of the leaf pairs within
        /// `reach`, in walk order (A's triangles outer within a leaf pair),
        /// with their distance at the walk (m): only those within `reach`
        /// (and round-off), since the list is given up before B has moved
        /// far enough to bring a farther one within the margin.
        pairs: Vec<(u32, u32, f64)>,
    },
    /// A moving pair's walk front.
    Front(WalkFront),
}

impl MeshPairMemory {
    /// How many triangle pairs the list holds (0 for a front).
    pub fn triangle_pairs(&self) -> usize {
        match &self.kept {
            Kept::List { pairs, .. } => pairs.len(),
            Kept::Front(_) => 0,
        }
    }

    /// The walk front kept for trees `a` and `b`, if this memory is one.
    pub fn front_for(&self, a: &Arc<ObbTree>, b: &Arc<ObbTree>) -> Option<&WalkFront> {
        match &self.kept {
            Kept::Front(front) if Arc::ptr_eq(&self.trees.0, a) && Arc::ptr_eq(&self.trees.1, b) => {
                Some(front)
            }
            _ => None,
        }
    }
}

/// What [`contact_mesh_mesh_recalled`] did with the pair's memory.
#[derive(Debug)]
pub enum Recall {
    /// The memory was still valid and was used: keep it.
    Reused,
    /// A new list was found (no memory, or it had run out): keep this one.
    Found(MeshPairMemory),
    /// The pair moves too fast for a list: it walked its trees along the
    /// drift, from its last walk's front if it kept one; keep the new front.
    Walked(MeshPairMemory),
}

/// [`contact_mesh_mesh_moving`](super::contact_mesh_mesh_moving) for a pair
/// that may remember its last walk: when B can move less than
/// [`RECALL_MAX_REACH`] against A, the contacts come from `memory` if it is
/// still valid (else from a new walk, returned to be kept); faster pairs
/// walk along the drift as `contact_mesh_mesh_moving` does.
///
/// The contacts of a remembered pair are those of every triangle pair of the
/// two meshes under the triangle test with `margin` plus each feature's
/// look-ahead over the drift, each shared vertex and edge tested through
/// the triangle that owns it (`contact_mesh::PlacedPair::owned_contacts`),
/// whatever the memory: a memory changes the cost, never the answer
/// (module docs). A margin that is not finite and `>= 0` is
/// [`NarrowError::BadMargin`], a drift that is not finite
/// [`NarrowError::BadDrift`], and contacts whose arithmetic overflowed
/// [`NarrowError::NotFinite`]; nothing is appended then.
// Opens with `contact_mesh_mesh_moving`'s arguments (the narrow phase's
// common six and the drift, module docs of `narrow`), then the memory.
#[allow(clippy::too_many_arguments)]
pub fn contact_mesh_mesh_recalled(
    a: &MeshShape,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
    margin: f64,
    drift: &Drift,
    memory: Option<&MeshPairMemory>,
    out: &mut Vec<Contact>,
) -> Result<Recall, NarrowError> {
    check_margin_and_drift(margin, drift)?;
    let start = out.len();
    let recall = 'recall: {
        let (tree_a, tree_b) = (a.tree_arc(), b.tree_arc());
        let (na, nb) = (tree_a.nodes(), tree_b.nodes());
        if na.is_empty() || nb.is_empty() {
            super::contact_mesh_mesh_moving(a, pose_a, b, pose_b, margin, drift, out);
            break 'recall Recall::Walked(MeshPairMemory {
                trees: (tree_a.clone(), tree_b.clone()),
                kept: Kept::Front(WalkFront::new()),
            });
        }
        let rel = pose_a.inverse().mul_pose(pose_b);
        let rot = DMat3::from_quat(rel.rotation);
        let local_drift = drift.in_frame_of(pose_a);
        // Every leaf box of B lies within `leaf_reach` of its root's centre, so
        // no leaf's reach exceeds the drift's reach over that ball.
        let root_b = nb[0].center_f64();
        let root_in_a = rot * root_b + rel.position;
        let reach_max = if drift.is_none() {
            0.0
        } else {
            local_drift.reach(root_in_a, tree_b.leaf_reach()) * (1.0 + 1e-12) + ROUND_OFF
        };
        if reach_max > RECALL_MAX_REACH {
            let last = memory.and_then(|m| m.front_for(tree_a, tree_b));
            let mut next = WalkFront::new();
            super::contact_mesh::contact_mesh_mesh_front(
                (a, pose_a),
                (b, pose_b),
                (margin, drift),
                last.unwrap_or(&WalkFront::new()),
                &mut next,
                out,
            );
            break 'recall Recall::Walked(MeshPairMemory {
                trees: (tree_a.clone(), tree_b.clone()),
                kept: Kept::Front(next),
            });
        }
        let remembered = memory.and_then(|m| match &m.kept {
            Kept::List {
                rel: then,
                reach,
                pairs,
            } if Arc::ptr_eq(&m.trees.0, tree_a)
                && Arc::ptr_eq(&m.trees.1, tree_b)
                && margin + reach_max + moved_since(then, &rel, root_b, tree_b.leaf_reach()) <= *reach =>
            {
                Some((then, pairs.as_slice()))
            }
            _ => None,
        });
        let recall = VERTEX_CACHE.with_borrow_mut(|cache| {
            cache.begin(b.mesh().vertices().len(), &local_drift);
            let mut placed = PlacedPair {
                a,
                b,
                rot: &rot,
                trans: rel.position,
                cache,
            };
            match remembered {
                Some((then, pairs)) => {
                    let moved = moved_since(then, &rel, root_b, tree_b.leaf_reach());
                    let listed = Listed {
                        pairs,
                        moved,
                        margin,
                        reach_max,
                    };
                    listed.contacts(&mut placed, out);
                    Recall::Reused
                }
                None => {
                    let reach = margin + reach_max + RECALL_SLACK;
                    let pairs = walk(&mut placed, pose_a, pose_b, reach);
                    let listed = Listed {
                        pairs: &pairs,
                        moved: 0.0,
                        margin,
                        reach_max,
                    };
                    listed.contacts(&mut placed, out);
                    Recall::Found(MeshPairMemory {
                        trees: (tree_a.clone(), tree_b.clone()),
                        kept: Kept::List { rel, reach, pairs },
                    })
                }
            }
        });
        finish_mesh_mesh(out, start, a, pose_a, b, pose_b);
        recall
    };
    refuse_non_finite(out, start, "mesh", "mesh")?;
    Ok(recall)
}

/// [`contact_mesh_mesh`](super::contact_mesh_mesh) for a pair that may
/// have kept a front of this same query (a second walk of the pair within
/// a step, at other poses and another margin than the narrow phase's: the
/// end-of-step overlaps): the walk begins at the front `memory` holds if it
/// is one for these two trees, else at the roots, and the front where it
/// ended is returned to keep. The contacts are the same bits either way.
/// Errors as [`contact_shapes`](super::contact_shapes).
pub fn contact_mesh_mesh_from_front(
    a: &MeshShape,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
    margin: f64,
    memory: Option<&MeshPairMemory>,
    out: &mut Vec<Contact>,
) -> Result<MeshPairMemory, NarrowError> {
    check_margin_and_drift(margin, &Drift::NONE)?;
    let start = out.len();
    let (tree_a, tree_b) = (a.tree_arc(), b.tree_arc());
    let mut next = WalkFront::new();
    super::contact_mesh::contact_mesh_mesh_front(
        (a, pose_a),
        (b, pose_b),
        (margin, &Drift::NONE),
        memory
            .and_then(|m| m.front_for(tree_a, tree_b))
            .unwrap_or(&WalkFront::new()),
        &mut next,
        out,
    );
    refuse_non_finite(out, start, "mesh", "mesh")?;
    Ok(MeshPairMemory {
        trees: (tree_a.clone(), tree_b.clone()),
        kept: Kept::Front(next),
    })
}

/// A new list: the triangle pairs of the leaf pairs of the two trees within
/// `reach` (no drift: the reach covers it) that are themselves within it,
/// each with its distance.
fn walk(placed: &mut PlacedPair, pose_a: &Pose, pose_b: &Pose, reach: f64) -> Vec<(u32, u32, f64)> {
    let (tree_a, tree_b) = (placed.a.tree_arc(), placed.b.tree_arc());
    let mut leaf_pairs = Vec::new();
    let _ = bvh::traverse::collide_leaves(tree_a, pose_a, tree_b, pose_b, reach, &Drift::NONE, |x, y| {
        leaf_pairs.push((x, y));
        Traverse::Continue
    });
    let (na, nb) = (tree_a.nodes(), tree_b.nodes());
    let mut pairs = Vec::new();
    for &(x, y) in &leaf_pairs {
        for &ta in tree_a.leaf_triangles(&na[x as usize]) {
            for &tb in tree_b.leaf_triangles(&nb[y as usize]) {
                let (wa, wb) = placed.triangles(ta, tb);
                // A pair beyond the list's reach is never tested while the
                // list is valid (`Listed::contacts` tests a pair once its
                // distance less the motion since is within the margin and
                // the look-ahead, and the list is given up before those
                // and the motion add up to more than `reach`). The cheap
                // bound drops most; the exact distance about half of the
                // rest (a settled pile of concave bodies).
                // (With the tests' round-off allowance, so that a list
                // drops exactly the pairs it would never test.)
                let cheap = gap_lower_bound(&wa, &wb);
                if cheap > reach + ROUND_OFF {
                    continue;
                }
                let gap = triangle_distance(&wa, &wb).distance.max(cheap);
                if gap <= reach + ROUND_OFF {
                    pairs.push((ta, tb, gap));
                }
            }
        }
    }
    pairs
}

/// A list with how far B has moved since it was found.
struct Listed<'m> {
    /// The list's triangle pairs, with their distances at the walk.
    pairs: &'m [(u32, u32, f64)],
    /// A bound on any point of B's move in A's frame since the walk (m).
    moved: f64,
    /// The step's margin (m).
    margin: f64,
    /// No leaf of B reaches farther than this over the drift (m).
    reach_max: f64,
}

impl Listed<'_> {
    /// The triangle test on the features each triangle owns, each within
    /// the margin plus its own look-ahead (`PlacedPair::owned_contacts`), for every
    /// listed pair that the motion since the walk could have brought within
    /// the margin and the largest look-ahead, in the list's order.
    fn contacts(&self, placed: &mut PlacedPair, out: &mut Vec<Contact>) {
        let reach = self.margin + self.reach_max;
        for &(ta, tb, gap) in self.pairs {
            if gap - self.moved - ROUND_OFF > reach {
                continue;
            }
            placed.owned_contacts((ta, tb), self.margin, out);
        }
    }
}

/// A bound (m) on how far any point within `radius` of `center` (B's own
/// frame) has moved in A's frame between B's relative poses `then` and
/// `now`: the centre's move plus the turn's chord over the radius (the
/// rotation `q = now then^-1` moves a point at distance `r` from its axis
/// by `2 sin(angle / 2) r = 2 |q.xyz| r`), with a round-off allowance.
pub fn moved_since(then: &Pose, now: &Pose, center: DVec3, radius: f64) -> f64 {
    let shift = (now.transform_point(center) - then.transform_point(center)).length();
    let turn: DQuat = (now.rotation * then.rotation.conjugate()).normalize();
    let chord = 2.0 * DVec3::new(turn.x, turn.y, turn.z).length() * radius;
    (shift + chord) * (1.0 + 1e-12) + ROUND_OFF
}

/// A lower bound (m) of the distance between triangles `a` and `b`: the
/// larger of their bounding spheres' gap (about the centroids) and the
/// separation by either triangle's plane; 0 when neither separates them.
fn gap_lower_bound(a: &[DVec3; 3], b: &[DVec3; 3]) -> f64 {
    let sphere = |t: &[DVec3; 3]| {
        let c = (t[0] + t[1] + t[2]) / 3.0;
        let r2 = (t[0] - c)
            .length_squared()
            .max((t[1] - c).length_squared())
            .max((t[2] - c).length_squared());
        (c, r2.sqrt())
    };
    let ((ca, ra), (cb, rb)) = (sphere(a), sphere(b));
    let mut best = (ca - cb).length() - ra - rb;
    // The plane of `q` separates `p` by the smallest height of `p`'s
    // corners on one side of it.
    let by_plane = |p: &[DVec3; 3], q: &[DVec3; 3]| {
        let n = (q[1] - q[0]).cross(q[2] - q[0]);
        let len = n.length();
        if len == 0.0 || !len.is_finite() {
            return 0.0;
        }
        let h = p.map(|v| n.dot(v - q[0]) / len);
        let (lo, hi) = (h[0].min(h[1]).min(h[2]), h[0].max(h[1]).max(h[2]));
        if lo > 0.0 {
            lo
        } else if hi < 0.0 {
            -hi
        } else {
            0.0
        }
    };
    best = best.max(by_plane(a, b)).max(by_plane(b, a));
    best.max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::ContactKind;
    use crate::mesh::{box_mesh, grid_mesh, icosphere_mesh, torus_mesh};
    use crate::narrow::{contact_mesh_mesh, contact_mesh_mesh_moving};
    use tumble_testkit::{RandomSource, SplitMix64};

    /// A point of the cube `[-half, half]^3`, uniformly.
    fn within(rng: &mut SplitMix64, half: f64) -> DVec3 {
        DVec3::new(
            rng.range(-half, half),
            rng.range(-half, half),
            rng.range(-half, half),
        )
    }

    /// A pose within the unit cube, turned by up to 1.7 rad.
    fn random_pose(rng: &mut SplitMix64) -> Pose {
        let turn = DQuat::from_scaled_axis(within(rng, 1.0));
        Pose::new(within(rng, 1.0), turn).unwrap()
    }

    fn torus() -> MeshShape {
        MeshShape::new(torus_mesh(0.3, 0.1, 32, 16).unwrap()).unwrap()
    }

    fn ball() -> MeshShape {
        MeshShape::new(icosphere_mesh(0.15, 2).unwrap()).unwrap()
    }

    /// A ball resting on a torus's tube, then walking in small random steps
    /// (0.3 mm and 2 mrad at most, with a steady 0.1 mm per step along x,
    /// so that the list runs out along the way).
    fn wander(steps: usize, seed: u64) -> Vec<Pose> {
        let mut rng = SplitMix64(seed);
        let mut pose = Pose::from_translation(DVec3::new(0.3, 0.0, 0.1 + 0.15 + 0.0005));
        let mut poses = Vec::new();
        for _ in 0..steps {
            poses.push(pose);
            let shift = within(&mut rng, 1.0) * 0.0003;
            let turn = within(&mut rng, 1.0) * 0.002;
            pose = Pose::new(
                pose.position + shift + DVec3::new(0.0001, 0.0, 0.0),
                (DQuat::from_scaled_axis(turn) * pose.rotation).normalize(),
            )
            .unwrap();
        }
        poses
    }

    fn bits(out: &[Contact]) -> String {
        format!("{out:?}")
    }

    /// Runs the poses with the memory carried from step to step, and
    /// checks every step against no memory at all (the same contacts, bit
    /// for bit) and, without drift, against the plain walk, which finds
    /// its triangle pairs anew from the trees (the same contacts, in
    /// another order, to round-off).
    fn carried_equals_fresh(drift: impl Fn(usize) -> Drift) -> (usize, usize) {
        let (a, b) = (torus(), ball());
        let pose_a = Pose::new(DVec3::new(0.01, -0.02, 0.0), DQuat::from_rotation_z(0.3)).unwrap();
        let (mut memory, mut reused, mut found, mut touching) = (None, 0, 0, 0);
        for (k, pose_b) in wander(60, 5).iter().enumerate() {
            let drift = drift(k);
            let margin = 0.004;
            let mut carried = Vec::new();
            match contact_mesh_mesh_recalled(
                &a,
                &pose_a,
                &b,
                pose_b,
                margin,
                &drift,
                memory.as_ref(),
                &mut carried,
            )
            .unwrap()
            {
                Recall::Reused => reused += 1,
                Recall::Found(m) => {
                    found += 1;
                    memory = Some(m);
                }
                Recall::Walked(_) => panic!("a slow pair walks along its drift"),
            }
            let mut fresh = Vec::new();
            let again = contact_mesh_mesh_recalled(&a, &pose_a, &b, pose_b, margin, &drift, None, &mut fresh);
            assert!(matches!(again, Ok(Recall::Found(_))));
            touching += usize::from(!carried.is_empty());
            assert_eq!(
                bits(&carried),
                bits(&fresh),
                "step {k}: memory changed the contacts"
            );
            if drift.is_none() {
                let mut walked = Vec::new();
                contact_mesh_mesh(&a, &pose_a, &b, pose_b, margin, &mut walked);
                if let Err(why) = crate::narrow::tests_mesh::same_contacts(&carried, &walked) {
                    panic!("step {k}: the plain walk differs: {why}");
                }
            }
        }
        // The comparison means something: the ball stays in contact.
        assert!(touching >= 45, "in contact at {touching} of 60 steps");
        (reused, found)
    }

    #[test]
    fn a_remembered_walk_gives_a_fresh_walks_contacts_bit_for_bit_until_it_runs_out() {
        let (reused, found) = carried_equals_fresh(|_| Drift::NONE);
        // The list served most steps, and was found again when the ball had
        // wandered farther than the slack.
        assert!(reused >= 30, "reused {reused} of 60");
        assert!(found >= 2, "found {found} times");
    }

    #[test]
    fn with_a_drift_the_contacts_do_not_depend_on_the_memory() {
        let (reused, found) = carried_equals_fresh(|k| Drift {
            origin: DVec3::new(0.3, 0.0, 0.25),
            translation: DVec3::new(0.0002, -0.0001 * (k % 3) as f64, -0.0003),
            rotation: DVec3::new(0.0, 0.001, 0.0005),
        });
        assert!(reused >= 20 && found >= 2, "reused {reused}, found {found}");
    }

    #[test]
    fn a_fast_pair_walks_along_its_drift_and_a_memory_of_other_trees_is_not_used() {
        let (a, b) = (torus(), ball());
        let pose_a = Pose::IDENTITY;
        let pose_b = wander(1, 3)[0];
        // 5 mm along the normal within the look-ahead: the drift walk.
        let fast = Drift {
            origin: pose_b.position,
            translation: DVec3::new(0.0, 0.0, -0.005),
            rotation: DVec3::ZERO,
        };
        let (mut recalled, mut moving) = (Vec::new(), Vec::new());
        let got = contact_mesh_mesh_recalled(&a, &pose_a, &b, &pose_b, 0.004, &fast, None, &mut recalled);
        assert!(matches!(got, Ok(Recall::Walked(_))));
        contact_mesh_mesh_moving(&a, &pose_a, &b, &pose_b, 0.004, &fast, &mut moving);
        assert_eq!(bits(&recalled), bits(&moving));
        // A memory of the ball against another torus (same shape, other
        // tree) is found anew, not reused.
        let other = torus();
        let mut out = Vec::new();
        let Ok(Recall::Found(m)) =
            contact_mesh_mesh_recalled(&other, &pose_a, &b, &pose_b, 0.004, &Drift::NONE, None, &mut out)
        else {
            panic!("a first walk is found");
        };
        assert!(m.triangle_pairs() > 0);
        let mut again = Vec::new();
        let got = contact_mesh_mesh_recalled(
            &a,
            &pose_a,
            &b,
            &pose_b,
            0.004,
            &Drift::NONE,
            Some(&m),
            &mut again,
        );
        assert!(matches!(got, Ok(Recall::Found(_))));
        assert_eq!(bits(&again), bits(&out));
    }

    #[test]
    fn bad_margins_and_drifts_are_refused_and_append_nothing() {
        let (a, b) = (torus(), ball());
        let pose_b = wander(1, 3)[0];
        let mut out = Vec::new();
        let nan = Drift {
            translation: DVec3::new(f64::NAN, 0.0, 0.0),
            ..Drift::NONE
        };
        for (margin, drift, what) in [
            (-1.0, Drift::NONE, "margin"),
            (f64::INFINITY, Drift::NONE, "margin"),
            (0.004, nan, "drift"),
        ] {
            let got =
                contact_mesh_mesh_recalled(&a, &Pose::IDENTITY, &b, &pose_b, margin, &drift, None, &mut out);
            match (got, what) {
                (Err(NarrowError::BadMargin(_)), "margin") | (Err(NarrowError::BadDrift), "drift") => {}
                (other, _) => panic!("{what}: {other:?}"),
            }
            assert!(out.is_empty());
        }
    }

    #[test]
    fn the_distance_bound_never_exceeds_the_distance() {
        let mut rng = SplitMix64(17);
        for _ in 0..2000 {
            let mut tri = || {
                let c = within(&mut rng, 1.0);
                [0, 1, 2].map(|_| c + within(&mut rng, 0.3))
            };
            let (a, b) = (tri(), tri());
            let exact = crate::triangle::triangle_distance(&a, &b).distance;
            assert!(gap_lower_bound(&a, &b) <= exact + 1e-12, "{a:?} {b:?}");
        }
    }

    #[test]
    fn moved_since_bounds_every_points_move() {
        let mut rng = SplitMix64(23);
        for _ in 0..200 {
            let (then, now) = (random_pose(&mut rng), random_pose(&mut rng));
            let (center, radius) = (DVec3::new(0.1, -0.2, 0.3), 0.5);
            let bound = moved_since(&then, &now, center, radius);
            for _ in 0..20 {
                let d = within(&mut rng, 1.0);
                let x = center + d.normalize_or_zero() * radius * rng.range(0.0, 1.0);
                let moved = (now.transform_point(x) - then.transform_point(x)).length();
                assert!(moved <= bound, "{moved} > {bound}");
            }
        }
    }

    /// A corner of A over a face of B takes the margin plus the look-ahead
    /// of that face's own corners, not the largest of B's: a sheet of fine
    /// triangles (B) turns about one end, by 1.8 mm at the far end and a
    /// tenth of a millimetre near the pivot, and a small box (A) holds a
    /// corner 1 mm beyond the margin above it. Near the far end the corner
    /// is a contact; near the pivot it is not (it would be with one margin
    /// for the pair: checked).
    #[test]
    fn a_corner_over_a_face_takes_the_look_ahead_of_the_faces_leaf() {
        let sheet = MeshShape::new(grid_mesh(0.5, 0.05, 50, 5).unwrap()).unwrap();
        let cube = MeshShape::new(box_mesh(DVec3::splat(0.01)).unwrap()).unwrap();
        // The cube's corner (-h, -h, -h) turned to point straight down.
        let down = DQuat::from_rotation_arc(DVec3::splat(-1.0).normalize(), -DVec3::Z);
        let lowest = 0.01 * 3f64.sqrt();
        let margin = 0.004;
        let drift = Drift {
            origin: DVec3::new(-0.5, 0.0, 0.0),
            translation: DVec3::ZERO,
            rotation: DVec3::new(0.0, 0.0, 0.0018),
        };
        let corner_contact = |x: f64| {
            let pose_a = Pose::new(DVec3::new(x, 0.0, lowest + margin + 0.001), down).unwrap();
            let mut out = Vec::new();
            let recall = contact_mesh_mesh_recalled(
                &cube,
                &pose_a,
                &sheet,
                &Pose::IDENTITY,
                margin,
                &drift,
                None,
                &mut out,
            )
            .unwrap();
            assert!(matches!(recall, Recall::Found(_)), "a slow pair lists its walk");
            out.iter()
                .filter(|c| c.kind == ContactKind::VertexFace)
                .map(|c| c.distance)
                .collect::<Vec<_>>()
        };
        let far = corner_contact(0.45);
        assert!(
            far.len() == 1 && (far[0] - (margin + 0.001)).abs() < 1e-9,
            "far end: {far:?}"
        );
        let near = corner_contact(-0.45);
        assert!(near.is_empty(), "near the pivot: {near:?}");
    }
}
