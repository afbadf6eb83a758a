//! A walk's front, kept from one walk of two OBB-trees to the next: front
//! tracking in the tree of node pairs a walk tests (the "BVTT front" of
//! Ehmann & Lin 2001, "Accurate and fast proximity queries between
//! polyhedra using convex surface decomposition", section 4.2).
//!
//! A walk of two trees (`traverse::collide_leaves`) tests node pairs from
//! the roots down and ends at pairs whose boxes are apart and at leaf
//! pairs: those terminals form a cut of the pair tree (every path from the
//! roots' pair to a leaf pair crosses exactly one of them). Two meshes that
//! move a little from one step to the next end their walks at nearly the
//! same cut, so the next walk starts from the last cut instead of the
//! roots: it tests each pair of the cut and walks on below those that now
//! overlap, and the pairs above the cut, about half of a walk's box tests
//! (two interlocked links of the torus chain: 1,600 tests a walk, 800
//! terminals), are not tested again.
//!
//! Exactness. A walk from a cut reaches every leaf pair that the walk from
//! the roots reaches, in the same order (below each pair of the cut the
//! walk is the roots' walk, and the cut is kept in depth-first order), but
//! it may also reach a leaf pair whose ancestor above the cut is apart,
//! where the walk from the roots stops (a child's box can reach out of its
//! parent's). So the walk hands each leaf pair over with a question:
//! whether the walk from the roots reaches the pair's cut entry, answered
//! by testing the pairs on the entry's path from the roots with the walk's
//! own arithmetic, once per entry. A caller that found something in a leaf
//! pair asks, and drops it where the answer is no (walks through a stale
//! cut met such leaf pairs in most of 200 trials, see the tests). Its
//! answer is then the walk from the roots', bit for bit, whatever cut it
//! began from: a front changes what a walk costs, never what it finds.
//!
//! When it pays. A cut only deepens (two sibling pairs apart again stay
//! two entries, though their parent's test would now do), so [`WalkFront`]
//! starts from the roots again once its cut has grown to [`REGROWTH`]
//! times the cut that the last walk from the roots left, and every
//! [`WALKS_FROM_A_CUT`] walks. It keeps a cut only where walks from the
//! roots cost [`LEAST_ROOTS_COST`] or more, and a walk from the cut that
//! cost more than [`PAYS_BELOW`] of the last from the roots sends the
//! next walks to the roots (1, 2, 4, ... up to [`MOST_WAIT`] of them). A
//! front pays where two meshes stay entangled: the torus chain's links
//! walk 830 box tests from their fronts against 1,570 from the roots (the
//! narrow phase; the end-of-step overlaps 700 against 1,310), while most
//! pairs of a landing concave pile never keep one.

use super::build::ObbTree;
use super::traverse::{walk_from, TraversalError, TraversalStats, Traverse, ROOT_PAIR};
use crate::drift::Drift;
use crate::pose::Pose;

/// A cut grown to this many times the last fresh one (from the roots) is
/// given up: the next walk starts from the roots.
pub const REGROWTH: f64 = 1.5;

/// Most walks from the roots after a front walk that did not pay, before
/// the front is tried again (the wait doubles from one at each such walk).
pub const MOST_WAIT: u32 = 64;

/// Walks from a cut between two from the roots: a cut found while two
/// bodies met fast lies deep in both trees, and walks from it keep costing
/// less than that meeting's walk from the roots long after one from the
/// roots would cost far less (in the concave pile's landing, walks from
/// such cuts cost 1.6 times what walks from the roots did); a walk from
/// the roots every so often finds the cut and the cost to beat again.
/// Instructions over the concave pile's first 60 steps and the torus
/// chain's first 120 (`scripts/instructions.sh`) against walks from the
/// roots alone: with 8, -1.2 % and -29.7 %; with 4, -4.6 % and -28.0 %.
pub const WALKS_FROM_A_CUT: u32 = 4;

/// Least cost ([`FrontWalk::cost`]) of a pair's last walk from the roots
/// for its next to keep a cut (so a cut of the two trees is kept, and
/// tried, only where walks from the roots are long: the torus chain's
/// links, 1,400; a landing concave pile's pairs, 500 at the mean, most far
/// less, pay more for keeping cuts than they save).
pub const LEAST_ROOTS_COST: u64 = 1024;

/// A walk from a cut pays when it costs less than this fraction of the last
/// walk from the roots (a margin for that walk's age: the roots' walk
/// would cost something else by now).
pub const PAYS_BELOW: f64 = 0.8;

/// What one triangle pair handed to the caller costs, in box tests (the
/// torus chain: a leaf pair's triangle pairs take about twice a box test's
/// time each), for weighing a front walk against one from the roots.
const TRIANGLE_PAIR_COST: u64 = 2;

/// The cut where the last walk of two trees ended, to start the next walk
/// of the same two trees from (module docs), and what walks from it and
/// from the roots cost. An empty front starts from the roots.
#[derive(Debug, Clone, Default)]
pub struct WalkFront {
    /// Node pairs (of A, of B), in depth-first order.
    cut: Vec<(u32, u32)>,
    /// The cut's length after the last walk from the roots.
    fresh: usize,
    /// Node counts of the trees the cut was found in.
    nodes: (usize, usize),
    /// What the last walk from the roots cost ([`FrontWalk::cost`]).
    roots_cost: u64,
    /// Walks from the roots still to go before the cut is tried again, and
    /// the wait after the next walk from the cut that does not pay.
    wait: (u32, u32),
    /// Walks since the last from the roots.
    since_roots: u32,
    /// Whether cuts are kept however little walks from the roots cost.
    keeps_any: bool,
}

/// What a walk from a front did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrontWalk {
    /// Its work counters (the cut's pairs count as box tests).
    pub stats: TraversalStats,
    /// `true` when it began at the roots: every leaf pair it reported is
    /// one the walk from the roots reaches.
    pub from_roots: bool,
}

impl FrontWalk {
    /// The walk's work in box tests: its box tests and its triangle pairs
    /// (a walk from a cut hands over some that the walk from the roots
    /// does not reach).
    pub fn cost(&self) -> u64 {
        self.stats.bv_tests + TRIANGLE_PAIR_COST * self.stats.triangle_pairs
    }
}

impl WalkFront {
    /// A front that starts the next walk from the roots.
    pub fn new() -> WalkFront {
        WalkFront::default()
    }

    /// A front that keeps its cuts however little walks from the roots
    /// cost ([`LEAST_ROOTS_COST`] does not apply; a caller that knows its
    /// two meshes stay entangled).
    pub fn keeping() -> WalkFront {
        WalkFront {
            keeps_any: true,
            ..WalkFront::default()
        }
    }

    /// How many node pairs the cut holds.
    pub fn len(&self) -> usize {
        self.cut.len()
    }

    /// `true` when the next walk starts from the roots.
    pub fn is_empty(&self) -> bool {
        self.cut.is_empty()
    }

    /// Where a walk of trees `a` and `b` begins: this cut, or the roots'
    /// pair when there is none, it belongs to other trees (by their sizes;
    /// the caller keeps a front with its own trees), it has regrown,
    /// walks from it have not paid lately, or [`WALKS_FROM_A_CUT`] have
    /// begun at cuts since the last from the roots.
    fn start(&self, a: &ObbTree, b: &ObbTree) -> (&[(u32, u32)], bool) {
        let fits = !self.cut.is_empty()
            && self.nodes == (a.nodes().len(), b.nodes().len())
            && (self.cut.len() as f64) <= REGROWTH * self.fresh as f64
            && self.wait.0 == 0
            && self.since_roots < WALKS_FROM_A_CUT;
        if fits {
            (&self.cut, false)
        } else {
            (&[ROOT_PAIR], true)
        }
    }

    /// The front after `walked` (from this one's start) ended at `cut`.
    /// A walk from the cut that cost more than [`PAYS_BELOW`] of the last
    /// from the roots (bodies that move far in a step, whose cut holds
    /// pairs the roots' test would have left alone) sends the next walks
    /// to the roots, for twice as many each time it happens (up to
    /// [`MOST_WAIT`]).
    fn after(&self, walked: &FrontWalk, cut: Vec<(u32, u32)>, nodes: (usize, usize)) -> WalkFront {
        let cost = walked.cost();
        let (roots_cost, fresh) = if walked.from_roots {
            (cost, cut.len())
        } else {
            (self.roots_cost, self.fresh)
        };
        let pays = !walked.from_roots && (cost as f64) < PAYS_BELOW * self.roots_cost as f64;
        let wait = match (walked.from_roots, pays) {
            (true, _) => (self.wait.0.saturating_sub(1), self.wait.1),
            (false, true) => (0, 0),
            (false, false) => {
                let next = (self.wait.1 * 2).clamp(1, MOST_WAIT);
                (next, next)
            }
        };
        let since_roots = if walked.from_roots {
            0
        } else {
            self.since_roots + 1
        };
        WalkFront {
            cut,
            fresh,
            nodes,
            roots_cost,
            wait,
            since_roots,
            keeps_any: self.keeps_any,
        }
    }
}

/// [`collide_leaves`](super::collide_leaves) from `front`'s cut, with the
/// cut where this walk ended written to `next` (unless the callback stopped
/// it: `next` is then left as it was). The leaf pairs come in the order of
/// the walk from the roots, with perhaps some that walk does not reach
/// (unless the result says it began at the roots), each with the question
/// that tells (module docs).
#[allow(clippy::too_many_arguments)]
pub fn collide_leaves_front(
    a: &ObbTree,
    pose_a: &Pose,
    b: &ObbTree,
    pose_b: &Pose,
    margin: f64,
    drift: &Drift,
    front: &WalkFront,
    next: &mut WalkFront,
    on_leaves: impl FnMut(u32, u32, &mut dyn FnMut() -> bool) -> Traverse,
) -> Result<FrontWalk, TraversalError> {
    let (cut, from_roots) = front.start(a, b);
    // A pair whose walks from the roots are short keeps no cut (and never
    // begins at one): there is little above a cut to save.
    let keep = !from_roots || front.keeps_any || front.roots_cost >= LEAST_ROOTS_COST;
    let mut terminals = Vec::with_capacity(if keep { cut.len() + cut.len() / 4 + 1 } else { 0 });
    let stats = walk_from(
        a,
        pose_a,
        b,
        pose_b,
        (margin, drift),
        cut,
        keep.then_some(&mut terminals),
        on_leaves,
    )?;
    let walked = FrontWalk { stats, from_roots };
    if !stats.stopped {
        *next = front.after(&walked, terminals, (a.nodes().len(), b.nodes().len()));
    }
    Ok(walked)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::collide_leaves;
    use crate::bvh::traverse::tests::random_pose;
    use crate::math::{DQuat, DVec3};
    use crate::mesh::torus_mesh;
    use tumble_testkit::{RandomSource, SplitMix64};

    fn walk_from_roots(
        t: &ObbTree,
        pa: &Pose,
        pb: &Pose,
        margin: f64,
        drift: &Drift,
    ) -> (Vec<(u32, u32)>, TraversalStats) {
        let mut leaves = Vec::new();
        let stats = collide_leaves(t, pa, t, pb, margin, drift, |x, y| {
            leaves.push((x, y));
            Traverse::Continue
        })
        .unwrap();
        (leaves, stats)
    }

    /// A leaf pair callback of the front walks, as a trait object.
    type OnLeaves<'q> = dyn FnMut(u32, u32, &mut dyn FnMut() -> bool) -> Traverse + 'q;

    /// A walk from `front`'s start that keeps nothing.
    fn through(
        t: &ObbTree,
        (pa, pb): (&Pose, &Pose),
        margin: f64,
        drift: &Drift,
        front: &WalkFront,
        on: &mut OnLeaves,
    ) -> FrontWalk {
        collide_leaves_front(t, pa, t, pb, margin, drift, front, &mut WalkFront::new(), on).unwrap()
    }

    /// The cut a walk of `t` against itself from the roots leaves.
    fn front_of(t: &ObbTree, pa: &Pose, pb: &Pose, margin: f64) -> WalkFront {
        let mut front = WalkFront::new();
        let fresh = WalkFront::keeping();
        collide_leaves_front(
            t,
            pa,
            t,
            pb,
            margin,
            &Drift::NONE,
            &fresh,
            &mut front,
            |_, _, _| Traverse::Continue,
        )
        .unwrap();
        assert!(!front.is_empty());
        front
    }

    /// The leaf pairs a walk from a front reports, those whose question
    /// says the walk from the roots does not reach them dropped (the
    /// question asked for every one), and how many were dropped.
    fn kept_of(walk: impl FnOnce(&mut OnLeaves) -> FrontWalk) -> (Vec<(u32, u32)>, usize, FrontWalk) {
        let (mut kept, mut dropped) = (Vec::new(), 0);
        let walked = walk(&mut |x, y, reached| {
            if reached() {
                kept.push((x, y));
            } else {
                dropped += 1;
            }
            Traverse::Continue
        });
        (kept, dropped, walked)
    }

    /// Two tori linked as a chain's links, B moving along a random path
    /// step by step: the walk from the kept front, its leaf pairs that the
    /// walk from the roots does not reach dropped, gives that walk's leaf
    /// pairs in their order at every step, and so does a walk through the
    /// front that keeps no cut; the front walks test a third fewer boxes.
    #[test]
    fn a_walk_from_the_front_finds_what_the_walk_from_the_roots_finds() {
        let tree = ObbTree::build(&torus_mesh(1.0, 0.2, 32, 12).unwrap()).unwrap();
        let mut rng = SplitMix64(7);
        let (mut front_tests, mut root_tests) = (0u64, 0u64);
        for run in 0..6 {
            let pa = random_pose(&mut || rng.next_f64(), 0.0);
            let mut front = WalkFront::keeping();
            // B through A's hole.
            let mut offset = DVec3::new(1.0, 0.0, 0.0);
            let mut angle: f64 = 0.0;
            for step in 0..120 {
                offset += DVec3::new(
                    rng.range(-0.01, 0.01),
                    rng.range(-0.01, 0.01),
                    rng.range(-0.01, 0.01),
                );
                angle += rng.range(-0.02, 0.02);
                let pb = Pose {
                    position: pa.transform_point(offset),
                    rotation: pa.rotation
                        * DQuat::from_rotation_z(angle)
                        * DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2),
                };
                let margin = [0.0, 0.002, 0.01][step % 3];
                let drift = Drift {
                    origin: pa.position,
                    translation: DVec3::new(rng.range(-0.02, 0.02), 0.0, rng.range(-0.02, 0.02)),
                    rotation: DVec3::new(0.0, rng.range(-0.05, 0.05), 0.0),
                };
                let (expected, stats) = walk_from_roots(&tree, &pa, &pb, margin, &drift);
                root_tests += stats.bv_tests;
                let (kept, dropped, walked) =
                    kept_of(|on| through(&tree, (&pa, &pb), margin, &drift, &front, on));
                assert_eq!(kept, expected, "run {run} step {step}");
                assert!(!walked.from_roots || dropped == 0);
                let mut next = WalkFront::new();
                let (kept, dropped, walked) = kept_of(|on| {
                    collide_leaves_front(&tree, &pa, &tree, &pb, margin, &drift, &front, &mut next, on)
                        .unwrap()
                });
                assert_eq!(kept, expected, "run {run} step {step}");
                assert!(!walked.from_roots || dropped == 0);
                front_tests += walked.stats.bv_tests;
                front = next;
            }
        }
        assert!(
            (front_tests as f64) < 0.8 * root_tests as f64,
            "front {front_tests} box tests against {root_tests} from the roots"
        );
    }

    /// A front found at one pose, walked through at another: the walk from
    /// the roots' leaf pairs, and beside them leaf pairs that the question
    /// must drop (so the question is needed, and answers no there).
    #[test]
    fn a_stale_front_meets_leaf_pairs_that_the_question_drops() {
        let tree = ObbTree::build(&torus_mesh(1.0, 0.2, 16, 8).unwrap()).unwrap();
        let mut rng = SplitMix64(3);
        let mut dropped_in_all = 0;
        for _ in 0..200 {
            let pa = random_pose(&mut || rng.next_f64(), 0.5);
            let pb = random_pose(&mut || rng.next_f64(), 0.5);
            let front = front_of(&tree, &pa, &pb, 0.05);
            let pb = random_pose(&mut || rng.next_f64(), 0.5);
            let (expected, _) = walk_from_roots(&tree, &pa, &pb, 0.0, &Drift::NONE);
            let (kept, dropped, walked) =
                kept_of(|on| through(&tree, (&pa, &pb), 0.0, &Drift::NONE, &front, on));
            assert!(!walked.from_roots);
            assert_eq!(kept, expected);
            dropped_in_all += dropped;
        }
        assert!(
            dropped_in_all > 0,
            "no walk through a stale front met a leaf pair to drop"
        );
    }

    /// Two meshes whose walks from the roots are short keep no cut: there
    /// is little above one to save.
    #[test]
    fn a_pair_with_short_walks_keeps_no_cut() {
        let tree = ObbTree::build(&torus_mesh(1.0, 0.2, 8, 6).unwrap()).unwrap();
        let (pa, pb) = (Pose::IDENTITY, Pose::from_translation(DVec3::new(2.3, 0.0, 0.0)));
        let mut front = WalkFront::new();
        for _ in 0..3 {
            let mut next = WalkFront::new();
            let walked = collide_leaves_front(
                &tree,
                &pa,
                &tree,
                &pb,
                0.01,
                &Drift::NONE,
                &front,
                &mut next,
                |_, _, _| Traverse::Continue,
            )
            .unwrap();
            assert!(
                walked.from_roots && walked.cost() > 1 && walked.cost() < LEAST_ROOTS_COST,
                "{walked:?}"
            );
            front = next;
            assert!(front.is_empty());
        }
    }

    /// A cut naming nodes the trees do not have is refused, not followed.
    #[test]
    fn a_cut_of_other_trees_starts_from_the_roots_or_is_refused() {
        let small = ObbTree::build(&torus_mesh(1.0, 0.2, 8, 6).unwrap()).unwrap();
        let large = ObbTree::build(&torus_mesh(1.0, 0.2, 32, 12).unwrap()).unwrap();
        let (pa, pb) = (Pose::IDENTITY, Pose::IDENTITY);
        let front = front_of(&large, &pa, &pb, 0.01);
        // Another pair of trees: the front is not theirs, the walk starts
        // from the roots.
        let walked = through(&small, (&pa, &pb), 0.01, &Drift::NONE, &front, &mut |_, _, _| {
            Traverse::Continue
        });
        assert!(walked.from_roots);
        let bad = walk_from(
            &small,
            &pa,
            &small,
            &pb,
            (0.01, &Drift::NONE),
            &[(0, 10_000)],
            None,
            |_, _, _| Traverse::Continue,
        );
        assert!(matches!(
            bad,
            Err(TraversalError::BadParameter {
                what: "walk cut node of B",
                ..
            })
        ));
    }
}
