//! Simultaneous traversal of two OBBTrees (Gottschalk, Lin & Manocha 1996,
//! section 3; thesis 4.6 and 5.1; PQP's `CollideRecurse` / `DistanceRecurse`).
//!
//! [`collide`] walks node pairs depth-first, testing box pairs with the
//! separating axis test and descending the larger box of a pair (by half
//! diagonal) so both trees shrink at a similar rate; every overlapping leaf
//! pair hands its triangle index pairs to a callback, which can stop the walk
//! (first-contact queries). [`distance`] orders and prunes node pairs by the
//! SAT lower bound on box distance against the best distance found so far
//! (branch and bound). Both use an explicit, non-allocating stack and return
//! their statistics.
//!
//! The public walks (`collide`, `collide_moving`, `collide_leaves`,
//! `distance_with`, and `front`'s `collide_leaves_front`) open with the
//! same header, two trees and their poses then a bound (checked by `check_nonneg` in `walk_from`, which all but
//! `distance_with` run on, and in `distance_with`): public API whose extra
//! arguments and callbacks differ.

use super::build::ObbTree;
use super::node::Node;
use super::sat::{axis_lanes, obb_disjoint_axes, obb_distance_lower_bound_axes, AxisLanes, LaneBox};
use super::stack::SmallStack;
use crate::drift::Drift;
use crate::math::{DMat3, DQuat, DVec3};
use crate::pose::Pose;
use wide::f64x4;

/// What a callback asks the traversal to do next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Traverse {
    /// Keep going.
    Continue,
    /// Stop now (e.g. the first contact is all that was needed).
    Stop,
}

/// Work counters of one traversal (PQP-style query statistics).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TraversalStats {
    /// Box-box (or box-query) tests performed.
    pub bv_tests: u64,
    /// Leaf pairs (or leaves, for single-tree queries) whose boxes passed.
    pub leaf_pairs: u64,
    /// Triangle index pairs (or triangles) handed to the callback.
    pub triangle_pairs: u64,
    /// `true` when the callback stopped the walk early.
    pub stopped: bool,
}

/// Why a traversal refused its arguments.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum TraversalError {
    /// A margin, radius or distance bound that is negative or not a number.
    #[error("{what} must be >= 0 and not NaN, got {value}")]
    BadParameter {
        /// Which parameter.
        what: &'static str,
        /// The value given.
        value: f64,
    },
}

pub(crate) fn check_nonneg(what: &'static str, value: f64) -> Result<(), TraversalError> {
    if value >= 0.0 {
        Ok(())
    } else {
        Err(TraversalError::BadParameter { what, value })
    }
}

/// Pose of mesh B in mesh A's frame, precomputed once per query.
#[derive(Clone, Copy)]
pub(super) struct Relative {
    rot: DQuat,
    trans: DVec3,
}

impl Relative {
    pub(super) fn new(pose_a: &Pose, pose_b: &Pose) -> Relative {
        let qa_inv = pose_a.rotation.conjugate();
        Relative {
            rot: (qa_inv * pose_b.rotation).normalize(),
            trans: qa_inv * (pose_b.position - pose_a.position),
        }
    }

    /// Box `nb` of mesh B placed in mesh A's frame, grown by `grow` (m).
    #[inline]
    fn place_b(&self, nb: &Node, grow: f64) -> Placed {
        let axes = DMat3::from_quat(self.rot * nb.quat_f64());
        Placed {
            axes,
            lanes: axis_lanes(&axes),
            c: self.rot * nb.center_f64() + self.trans,
            h: nb.half_f64().map(|h| h + grow),
        }
    }

    /// [`Self::place_b`], then made to hold every position of the box
    /// while B drifts by `drift` (A's frame): stretched along its centre's
    /// displacement (centre moved halfway, each half extent grown by half
    /// the move along its axis) and grown on every side by the rotation's
    /// reach over its half diagonal.
    #[inline]
    pub(super) fn place_b_drifting(&self, nb: &Node, grow: f64, drift: &Drift) -> Placed {
        let mut placed = self.place_b(nb, grow);
        if drift.is_none() {
            return placed;
        }
        let turn = drift.rotation.length() * DVec3::from(nb.half_f64()).length();
        let shift = drift.displacement(placed.c);
        placed.c += 0.5 * shift;
        for k in 0..3 {
            placed.h[k] += 0.5 * placed.axes.col(k).dot(shift).abs() + turn;
        }
        placed
    }

    /// How far any point of B's box `nb` can move while B drifts by
    /// `drift` (A's frame, m): the drift's reach over the box's half
    /// diagonal about its centre (no orientation needed).
    #[inline]
    fn reach_of_b(&self, nb: &Node, drift: &Drift) -> f64 {
        let center = self.rot * nb.center_f64() + self.trans;
        drift.reach(center, DVec3::from(nb.half_f64()).length())
    }
}

/// A box in mesh A's frame. When a pair is split, the unsplit side is placed
/// once and shared by the two child tests.
#[derive(Clone, Copy)]
pub(super) struct Placed {
    /// The box's axes (columns).
    axes: DMat3,
    /// The same by component (`sat::axis_lanes`).
    lanes: AxisLanes,
    c: DVec3,
    h: [f64; 3],
}

impl Placed {
    /// A placeholder (an empty cache slot).
    const EMPTY: Placed = Placed {
        axes: DMat3::IDENTITY,
        lanes: [f64x4::ZERO; 3],
        c: DVec3::ZERO,
        h: [0.0; 3],
    };

    /// Box `na` of mesh A (already in A's frame), grown by `grow` (m).
    #[inline]
    pub(super) fn a(na: &Node, grow: f64) -> Placed {
        let axes = DMat3::from_quat(na.quat_f64());
        Placed {
            axes,
            lanes: axis_lanes(&axes),
            c: na.center_f64(),
            h: na.half_f64().map(|h| h + grow),
        }
    }

    /// This box for the lane tests.
    #[inline]
    fn lane_box(&self) -> LaneBox<'_> {
        LaneBox {
            axes: &self.axes,
            lanes: &self.lanes,
            center: self.c,
            half: self.h,
        }
    }

    #[inline(always)]
    pub(super) fn overlaps(&self, b: &Placed) -> bool {
        !obb_disjoint_axes(self.lane_box(), b.lane_box())
    }

    #[inline]
    fn lower_bound(&self, b: &Placed) -> f64 {
        obb_distance_lower_bound_axes(self.lane_box(), b.lane_box())
    }
}

/// `true` when the pair should be split on A's side.
#[inline]
pub(super) fn descend_a(na: &Node, nb: &Node) -> bool {
    !na.is_leaf() && (nb.is_leaf() || na.size() >= nb.size())
}

/// Reports every pair of triangles `(ta, tb)` of meshes A and B (placed by
/// `pose_a`, `pose_b`) whose leaf boxes overlap after growing each box by
/// `margin / 2` (m): a superset of the triangle pairs closer than `margin`.
/// The callback decides per pair whether to continue.
pub fn collide(
    a: &ObbTree,
    pose_a: &Pose,
    b: &ObbTree,
    pose_b: &Pose,
    margin: f64,
    mut on_pair: impl FnMut(u32, u32) -> Traverse,
) -> Result<TraversalStats, TraversalError> {
    collide_moving(a, pose_a, b, pose_b, margin, &Drift::NONE, |ta, tb, _| {
        on_pair(ta, tb)
    })
}

/// [`collide`] while mesh B drifts by `drift` (world frame) relative to A:
/// every pair of triangles that comes within `margin` of each other
/// somewhere along the drift is reported (a superset, as for [`collide`]),
/// with how far B's leaf can move (m), which bounds how far the pair's
/// gap can close. Each of B's boxes is stretched along its own centre's
/// displacement and grown by the rotation's reach over its own size, not
/// by the largest motion of the whole body: a spinning body's small boxes
/// near its axis barely move, and a falling body tests the triangles below
/// it rather than every triangle within a fall's length around it.
pub fn collide_moving(
    a: &ObbTree,
    pose_a: &Pose,
    b: &ObbTree,
    pose_b: &Pose,
    margin: f64,
    drift: &Drift,
    mut on_pair: impl FnMut(u32, u32, f64) -> Traverse,
) -> Result<TraversalStats, TraversalError> {
    let rel = Relative::new(pose_a, pose_b);
    let local = drift.in_frame_of(pose_a);
    let mut triangle_pairs = 0;
    let mut stats = collide_leaves(a, pose_a, b, pose_b, margin, drift, |ia, ib| {
        let (x, y) = (&a.nodes()[ia as usize], &b.nodes()[ib as usize]);
        let moves = if local.is_none() {
            0.0
        } else {
            rel.reach_of_b(y, &local)
        };
        for &ta in a.leaf_triangles(x) {
            for &tb in b.leaf_triangles(y) {
                triangle_pairs += 1;
                if on_pair(ta, tb, moves) == Traverse::Stop {
                    return Traverse::Stop;
                }
            }
        }
        Traverse::Continue
    })?;
    stats.triangle_pairs = triangle_pairs;
    Ok(stats)
}

/// The walk of [`collide_moving`] at the level of leaves: every pair of
/// leaf nodes `(of A, of B)` (indices into `nodes()`) whose boxes overlap
/// after growing each by `margin / 2` and stretching B's along the drift,
/// in depth-first order. That order is the trees' own: the walk descends
/// into the larger box first and its left child before its right, whatever
/// the poses, so the leaf pairs of two walks of the same trees come in the
/// same relative order (what lets a pair remember a walk,
/// `narrow::MeshPairMemory`).
pub fn collide_leaves(
    a: &ObbTree,
    pose_a: &Pose,
    b: &ObbTree,
    pose_b: &Pose,
    margin: f64,
    drift: &Drift,
    mut on_leaves: impl FnMut(u32, u32) -> Traverse,
) -> Result<TraversalStats, TraversalError> {
    walk_from(
        a,
        pose_a,
        b,
        pose_b,
        (margin, drift),
        &[ROOT_PAIR],
        None,
        |x, y, _| on_leaves(x, y),
    )
}

/// The root pair of two trees: where a walk from the top begins.
pub(super) const ROOT_PAIR: (u32, u32) = (0, 0);

/// The walk of [`collide_leaves`] begun at each node pair of `cut` in turn
/// instead of at the roots (`bvh::front`): each is tested as the walk
/// tests a pair it reaches, and the walk goes on below it as from the
/// roots, so that a cut of the roots' pair tree gives the leaf pairs of the
/// walk from the roots in its order, with perhaps some whose ancestors
/// above the cut are apart. With `terminals`, the node pairs where each
/// walk below the cut ended (apart, or a leaf pair) are appended in the
/// same depth-first order: a cut again. `[ROOT_PAIR]` is the walk from the
/// roots; node indices outside the trees are refused as a bad parameter.
///
/// `on_leaves` gets with each leaf pair a question it may ask: whether the
/// walk from the roots reaches the pair's cut entry, that is whether the
/// boxes of every node pair above it on its path from the roots overlap,
/// tested as that walk tests them (answered once per entry; `bvh::front`
/// on why a caller asks).
#[allow(clippy::too_many_arguments)]
pub(super) fn walk_from(
    a: &ObbTree,
    pose_a: &Pose,
    b: &ObbTree,
    pose_b: &Pose,
    (margin, drift): (f64, &Drift),
    cut: &[(u32, u32)],
    mut terminals: Option<&mut Vec<(u32, u32)>>,
    mut on_leaves: impl FnMut(u32, u32, &mut dyn FnMut() -> bool) -> Traverse,
) -> Result<TraversalStats, TraversalError> {
    check_nonneg("collide margin", margin)?;
    if !drift.is_finite() {
        return Err(TraversalError::BadParameter {
            what: "collide drift",
            value: f64::NAN,
        });
    }
    let (na, nb) = (a.nodes(), b.nodes());
    for &(x, y) in cut {
        for (what, node, nodes) in [
            ("walk cut node of A", x, na.len()),
            ("walk cut node of B", y, nb.len()),
        ] {
            if node as usize >= nodes.max(1) {
                return Err(TraversalError::BadParameter {
                    what,
                    value: node as f64,
                });
            }
        }
    }
    let rel = Relative::new(pose_a, pose_b);
    let drift = drift.in_frame_of(pose_a);
    let grow = 0.5 * margin;
    let mut stats = TraversalStats::default();
    if na.is_empty() || nb.is_empty() {
        stats.bv_tests = 1;
        return Ok(stats);
    }
    // B's boxes placed in A's frame, and A's with their axes as matrices,
    // each once per walk (a box meets many of the other tree's as the walk
    // descends under it): the same bits as placing it at every meeting. A
    // callback that walks again on this thread finds the caches taken and
    // places its boxes afresh (so does a walk while the thread's storage is
    // being torn down).
    let mut walk = |placed: &mut PlacedBoxes, placed_a: &mut PlacedBoxes| {
        placed.begin(nb.len());
        placed_a.begin(na.len());
        let place_b = |i: u32| rel.place_b_drifting(&nb[i as usize], grow, &drift);
        let place_a = |i: u32| Placed::a(&na[i as usize], grow);
        // (node of A, node of B, whether the boxes overlap): a pair apart
        // is on the stack only to be handed to `terminals` in its turn.
        let mut stack = SmallStack::<(u32, u32, bool)>::new();
        // The path from the roots to the last entry asked about, each pair
        // with its test (entries come in depth-first order, and neighbours
        // share most of their paths).
        let mut path: Vec<((u32, u32), bool)> = Vec::new();
        for &entry in cut {
            let (ia, ib) = entry;
            let mut entry_reached = (entry == ROOT_PAIR).then_some(true);
            stats.bv_tests += 1;
            let overlaps = placed_a
                .get(ia, || place_a(ia))
                .overlaps(placed.get(ib, || place_b(ib)));
            stack.push((ia, ib, overlaps));
            while let Some((ia, ib, overlaps)) = stack.pop() {
                if !overlaps {
                    if let Some(t) = terminals.as_deref_mut() {
                        t.push((ia, ib));
                    }
                    continue;
                }
                let (x, y) = (&na[ia as usize], &nb[ib as usize]);
                if x.is_leaf() && y.is_leaf() {
                    if let Some(t) = terminals.as_deref_mut() {
                        t.push((ia, ib));
                    }
                    stats.leaf_pairs += 1;
                    stats.triangle_pairs += (a.leaf_triangles(x).len() * b.leaf_triangles(y).len()) as u64;
                    let mut reached = || {
                        *entry_reached.get_or_insert_with(|| {
                            let mut overlaps = |x: u32, y: u32| {
                                let pb = placed.get(y, || place_b(y));
                                placed_a.get(x, || place_a(x)).overlaps(pb)
                            };
                            path_overlaps(na, nb, entry, &mut path, &mut overlaps)
                        })
                    };
                    if on_leaves(ia, ib, &mut reached) == Traverse::Stop {
                        stats.stopped = true;
                        return;
                    }
                    continue;
                }
                // Test the children before pushing; push the second child
                // first so the first is visited first (depth-first, left to
                // right). A child apart is pushed only when the walk keeps
                // its terminals.
                let keep_apart = terminals.is_some();
                if descend_a(x, y) {
                    let pb = placed.get(ib, || place_b(ib));
                    let c = x.first_child();
                    for child in [c + 1, c] {
                        stats.bv_tests += 1;
                        let overlaps = placed_a.get(child, || place_a(child)).overlaps(pb);
                        if overlaps || keep_apart {
                            stack.push((child, ib, overlaps));
                        }
                    }
                } else {
                    let pa = placed_a.get(ia, || place_a(ia));
                    let c = y.first_child();
                    for child in [c + 1, c] {
                        stats.bv_tests += 1;
                        let overlaps = pa.overlaps(placed.get(child, || place_b(child)));
                        if overlaps || keep_apart {
                            stack.push((ia, child, overlaps));
                        }
                    }
                }
            }
        }
    };
    with_placed_boxes(&mut walk);
    Ok(stats)
}

/// Whether every node pair above `entry` on the walk's path from the
/// roots' pair passes `overlaps` (the entry's own test is the caller's).
/// `path` holds the last path asked about, with its tests, and is reused
/// where the new one begins alike. An entry the walk from the roots cannot
/// meet (no cut a walk leaves holds one) is not reached.
fn path_overlaps(
    na: &[Node],
    nb: &[Node],
    entry: (u32, u32),
    path: &mut Vec<((u32, u32), bool)>,
    overlaps: &mut impl FnMut(u32, u32) -> bool,
) -> bool {
    let first_leaf = |nodes: &[Node], mut n: u32| {
        while !nodes[n as usize].is_leaf() {
            n = nodes[n as usize].first_child();
        }
        nodes[n as usize].leaf_range().0
    };
    let (ta, tb) = (first_leaf(na, entry.0), first_leaf(nb, entry.1));
    // The child of `node` whose subtree holds the node whose first leaf's
    // run starts at `target`: leaves hold consecutive runs of the tree's
    // triangle index array, left subtree before right.
    let towards = |nodes: &[Node], node: u32, target: u32| {
        let c = nodes[node as usize].first_child();
        if target >= first_leaf(nodes, c + 1) {
            c + 1
        } else {
            c
        }
    };
    let (mut x, mut y) = ROOT_PAIR;
    let mut depth = 0;
    while (x, y) != entry {
        let ok = match path.get(depth) {
            Some(&(pair, ok)) if pair == (x, y) => ok,
            _ => {
                path.truncate(depth);
                let ok = overlaps(x, y);
                path.push(((x, y), ok));
                ok
            }
        };
        if !ok {
            return false;
        }
        let (nx, ny) = (&na[x as usize], &nb[y as usize]);
        if descend_a(nx, ny) {
            if x == entry.0 {
                return false;
            }
            x = towards(na, x, ta);
        } else {
            if y == entry.1 || ny.is_leaf() {
                return false;
            }
            y = towards(nb, y, tb);
        }
        depth += 1;
    }
    true
}

/// Runs `walk` with this thread's caches of placed boxes (B's, then A's),
/// or fresh ones where they are taken (a walk inside a walk's callback) or
/// being torn down.
pub(super) fn with_placed_boxes(walk: &mut impl FnMut(&mut PlacedBoxes, &mut PlacedBoxes)) {
    let cached = PLACED_B.try_with(|cell_b| {
        PLACED_A.with(
            |cell_a| match (cell_b.try_borrow_mut(), cell_a.try_borrow_mut()) {
                (Ok(mut placed_b), Ok(mut placed_a)) => {
                    walk(&mut placed_b, &mut placed_a);
                    true
                }
                _ => false,
            },
        )
    });
    if cached != Ok(true) {
        walk(&mut PlacedBoxes::default(), &mut PlacedBoxes::default());
    }
}

/// Boxes of one walk's tree B placed in A's frame, by node (valid where
/// `stamp` holds the walk's `generation`): kept per thread so that a walk
/// neither allocates nor clears them.
#[derive(Default)]
pub(super) struct PlacedBoxes {
    boxes: Vec<Placed>,
    stamp: Vec<u32>,
    generation: u32,
}

impl PlacedBoxes {
    /// Starts a walk of a tree of `nodes` nodes: nothing placed yet.
    pub(super) fn begin(&mut self, nodes: usize) {
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            // Wrapped: old stamps could read as current.
            self.stamp.fill(0);
            self.generation = 1;
        }
        if self.stamp.len() < nodes {
            self.stamp.resize(nodes, 0);
            self.boxes.resize(nodes, Placed::EMPTY);
        }
    }

    /// Node `i`'s box, placed by `place` the first time it is asked for.
    #[inline]
    pub(super) fn get(&mut self, i: u32, place: impl FnOnce() -> Placed) -> &Placed {
        let i = i as usize;
        if self.stamp[i] != self.generation {
            self.boxes[i] = place();
            self.stamp[i] = self.generation;
        }
        &self.boxes[i]
    }
}

thread_local! {
    static PLACED_B: std::cell::RefCell<PlacedBoxes> = std::cell::RefCell::new(PlacedBoxes::default());
    static PLACED_A: std::cell::RefCell<PlacedBoxes> = std::cell::RefCell::new(PlacedBoxes::default());
}

/// Result of a [`distance`] traversal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DistanceResult {
    /// Smallest value returned by the callback, or the initial bound if no
    /// pair beat it (m).
    pub distance: f64,
    /// Work counters.
    pub stats: TraversalStats,
}

/// PQP-style pruning tolerances of a distance traversal (Larsen, Gottschalk,
/// Lin & Manocha 1999, "Fast proximity queries with swept sphere volumes":
/// the `rel_err` / `abs_err` of PQP's distance query).
///
/// A node pair is skipped when its box lower bound `lb` satisfies
/// `lb * (1 + rel_err) >= best` or `lb + abs_err >= best`. The pair holding
/// the true minimum `d` is then skipped only when `best <= (1 + rel_err) d` or
/// `best <= d + abs_err`, so the returned distance lies in
/// `[d, max((1 + rel_err) d, d + abs_err)]`. `(0, 0)` is the exact search.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DistanceTolerance {
    /// Relative error allowed (dimensionless, >= 0, finite). Default 0.
    pub rel_err: f64,
    /// Absolute error allowed (m, >= 0, finite). Default 0.
    pub abs_err: f64,
}

impl DistanceTolerance {
    /// The exact search.
    pub const EXACT: DistanceTolerance = DistanceTolerance {
        rel_err: 0.0,
        abs_err: 0.0,
    };

    /// Checks both fields (finite and >= 0).
    pub fn check(&self) -> Result<(), TraversalError> {
        for (what, value) in [
            ("distance rel_err", self.rel_err),
            ("distance abs_err", self.abs_err),
        ] {
            check_nonneg(what, value)?;
            if !value.is_finite() {
                return Err(TraversalError::BadParameter { what, value });
            }
        }
        Ok(())
    }

    /// `true` when a node pair with lower bound `lb` cannot improve `best`
    /// by more than the allowed error.
    #[inline]
    pub fn prunes(&self, lb: f64, best: f64) -> bool {
        lb >= best || lb * (1.0 + self.rel_err) >= best || lb + self.abs_err >= best
    }
}

/// Branch-and-bound distance traversal: visits leaf pairs nearest-first (by
/// the box lower bound) and skips every node pair whose lower bound is not
/// below the best distance so far. `on_pair(ta, tb, best)` must return the
/// distance of triangles `ta`, `tb` (or any value not below it, e.g. `best`
/// when it can tell early that the pair cannot win); the best is the minimum
/// of the returned values. Start with `upper_bound = f64::INFINITY` or a
/// known distance (m); the walk ends early when the best reaches 0.
pub fn distance(
    a: &ObbTree,
    pose_a: &Pose,
    b: &ObbTree,
    pose_b: &Pose,
    upper_bound: f64,
    on_pair: impl FnMut(u32, u32, f64) -> f64,
) -> Result<DistanceResult, TraversalError> {
    distance_with(
        a,
        pose_a,
        b,
        pose_b,
        upper_bound,
        &DistanceTolerance::EXACT,
        on_pair,
    )
}

/// [`distance`] with PQP-style approximate pruning ([`DistanceTolerance`]).
pub fn distance_with(
    a: &ObbTree,
    pose_a: &Pose,
    b: &ObbTree,
    pose_b: &Pose,
    upper_bound: f64,
    tolerance: &DistanceTolerance,
    mut on_pair: impl FnMut(u32, u32, f64) -> f64,
) -> Result<DistanceResult, TraversalError> {
    check_nonneg("distance upper bound", upper_bound)?;
    tolerance.check()?;
    let tol = *tolerance;
    let rel = Relative::new(pose_a, pose_b);
    let (na, nb) = (a.nodes(), b.nodes());
    let mut best = upper_bound;
    let mut stats = TraversalStats {
        bv_tests: 1,
        ..TraversalStats::default()
    };
    if na.is_empty() || nb.is_empty() {
        return Ok(DistanceResult {
            distance: best,
            stats,
        });
    }
    let mut stack = SmallStack::<(u32, u32, f64)>::new();
    let lb = Placed::a(&na[0], 0.0).lower_bound(&rel.place_b(&nb[0], 0.0));
    if !tol.prunes(lb, best) {
        stack.push((0, 0, lb));
    }
    while let Some((ia, ib, lb)) = stack.pop() {
        if tol.prunes(lb, best) {
            continue; // the best improved since this pair was pushed
        }
        // The leaf step of `collide` above, but folding distances into `best`
        // where `collide` obeys a stop flag, and the walks around it differ
        // (pruned nearest-first vs depth-first): each hot loop keeps its own.
        // `volume_distance` (volume_distance.rs) repeats this fold over the
        // triangles of one leaf, its walk being over one tree, not pairs.
        let (x, y) = (&na[ia as usize], &nb[ib as usize]);
        if x.is_leaf() && y.is_leaf() {
            stats.leaf_pairs += 1;
            for &ta in a.leaf_triangles(x) {
                for &tb in b.leaf_triangles(y) {
                    stats.triangle_pairs += 1;
                    let d = on_pair(ta, tb, best);
                    if d < best {
                        best = d;
                    }
                }
            }
            if best <= 0.0 {
                stats.stopped = true;
                break;
            }
            continue;
        }
        let (pairs, lbs) = if descend_a(x, y) {
            let c = x.first_child();
            let pb = rel.place_b(y, 0.0);
            let lb = |i: u32| Placed::a(&na[i as usize], 0.0).lower_bound(&pb);
            ([(c, ib), (c + 1, ib)], [lb(c), lb(c + 1)])
        } else {
            let c = y.first_child();
            let pa = Placed::a(x, 0.0);
            let lb = |j: u32| pa.lower_bound(&rel.place_b(&nb[j as usize], 0.0));
            ([(ia, c), (ia, c + 1)], [lb(c), lb(c + 1)])
        };
        stats.bv_tests += 2;
        // Push the farther pair first so the nearer one is explored first.
        let order = if lbs[0] <= lbs[1] { [1, 0] } else { [0, 1] };
        for k in order {
            if !tol.prunes(lbs[k], best) {
                stack.push((pairs[k].0, pairs[k].1, lbs[k]));
            }
        }
    }
    Ok(DistanceResult {
        distance: best,
        stats,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::math::DQuat;
    use crate::mesh::{icosphere_mesh, torus_mesh, TriMesh};
    use std::collections::BTreeSet;

    pub(crate) use tumble_testkit::splitmix_f64 as rng;

    pub(crate) fn random_pose(r: &mut impl FnMut() -> f64, spread: f64) -> Pose {
        let q = DQuat::from_xyzw(r() - 0.5, r() - 0.5, r() - 0.5, r() - 0.5).normalize();
        Pose::new(DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * spread, q).unwrap()
    }

    fn world_tri(m: &TriMesh, pose: &Pose, t: u32) -> [DVec3; 3] {
        m.triangle(t as usize).map(|v| pose.transform_point(v))
    }

    /// Exact (up to round-off) triangle-triangle intersection oracle by the
    /// separating axis theorem: two triangles are disjoint iff one of the two
    /// normals, the nine edge-edge cross products or the six in-plane edge
    /// normals separates them. Independent of the tree and of any tri-tri code.
    fn triangles_intersect(p: &[DVec3; 3], q: &[DVec3; 3]) -> bool {
        let np = (p[1] - p[0]).cross(p[2] - p[0]);
        let nq = (q[1] - q[0]).cross(q[2] - q[0]);
        let mut axes = vec![np, nq];
        for i in 0..3 {
            let ep = p[(i + 1) % 3] - p[i];
            let eq = q[(i + 1) % 3] - q[i];
            axes.push(np.cross(ep));
            axes.push(nq.cross(eq));
            for j in 0..3 {
                axes.push(ep.cross(q[(j + 1) % 3] - q[j]));
            }
        }
        for l in axes {
            if l.length_squared() < 1e-24 {
                continue;
            }
            let l = l.normalize();
            let (pmin, pmax) = p
                .iter()
                .map(|v| v.dot(l))
                .fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)));
            let (qmin, qmax) = q
                .iter()
                .map(|v| v.dot(l))
                .fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)));
            if pmax < qmin - 1e-12 || qmax < pmin - 1e-12 {
                return false;
            }
        }
        true
    }

    fn reported(
        a: &ObbTree,
        pa: &Pose,
        b: &ObbTree,
        pb: &Pose,
        margin: f64,
    ) -> (BTreeSet<(u32, u32)>, TraversalStats) {
        let mut set = BTreeSet::new();
        let stats = collide(a, pa, b, pb, margin, |i, j| {
            assert!(set.insert((i, j)), "pair reported twice");
            Traverse::Continue
        })
        .unwrap();
        (set, stats)
    }

    #[test]
    fn traversal_finds_every_intersecting_triangle_pair() {
        let ma = torus_mesh(1.0, 0.35, 16, 10).unwrap();
        let mb = icosphere_mesh(0.6, 2).unwrap();
        let ta = ObbTree::build(&ma).unwrap();
        let tb = ObbTree::build_with(&mb, &crate::bvh::BuildOptions { leaf_size: 3 }).unwrap();
        let mut r = rng(21);
        let mut total_hits = 0;
        for _ in 0..40 {
            let pa = random_pose(&mut r, 0.5);
            let pb = random_pose(&mut r, 2.5);
            let (set, stats) = reported(&ta, &pa, &tb, &pb, 0.0);
            let all = ma.triangles().len() as u64 * mb.triangles().len() as u64;
            assert!(stats.triangle_pairs <= all);
            for i in 0..ma.triangles().len() as u32 {
                let p = world_tri(&ma, &pa, i);
                for j in 0..mb.triangles().len() as u32 {
                    let q = world_tri(&mb, &pb, j);
                    // AABB overlap is necessary for intersection: a cheap
                    // prefilter for the exact oracle.
                    let lo = |t: &[DVec3; 3]| t[0].min(t[1]).min(t[2]);
                    let hi = |t: &[DVec3; 3]| t[0].max(t[1]).max(t[2]);
                    if !(lo(&p).cmple(hi(&q)).all() && lo(&q).cmple(hi(&p)).all()) {
                        continue;
                    }
                    if triangles_intersect(&p, &q) {
                        total_hits += 1;
                        assert!(set.contains(&(i, j)), "missed intersecting pair ({i}, {j})");
                    }
                }
            }
        }
        assert!(total_hits > 100, "test scenes too sparse: {total_hits}");
    }

    /// The thesis' torus pair (shared/scenes.md, "tori"): over the 200 poses
    /// the tree walk plus an exact SAT triangle test must find the published
    /// ground truth, 122 colliding poses and 36,782 intersecting pairs (two
    /// pairs miss by ~1e-6 m, so the count may differ by at most two).
    #[test]
    fn tori_scene_matches_ground_truth() {
        let m = torus_mesh(1.0, 0.3, 50, 50).unwrap();
        let t = ObbTree::build(&m).unwrap();
        let id = Pose::IDENTITY;
        let q = DQuat::from_rotation_z(0.1) * DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2);
        let (mut poses_hit, mut pairs) = (0, 0i64);
        for k in 0..200 {
            let pb = Pose::new(DVec3::new(-3.0 + 6.0 * k as f64 / 199.0, 0.05, 0.02), q).unwrap();
            let mut n = 0;
            collide(&t, &id, &t, &pb, 0.0, |i, j| {
                if triangles_intersect(&world_tri(&m, &id, i), &world_tri(&m, &pb, j)) {
                    n += 1;
                }
                Traverse::Continue
            })
            .unwrap();
            poses_hit += (n > 0) as i32;
            pairs += n;
        }
        assert_eq!(poses_hit, 122);
        assert!((pairs - 36_782).abs() <= 2, "{pairs}");
    }

    /// A coarse sphere and a thin ring with their trees: small enough for
    /// brute-force oracles over every triangle pair.
    fn sphere_and_ring() -> (TriMesh, TriMesh, ObbTree, ObbTree) {
        with_trees(
            icosphere_mesh(1.0, 2).unwrap(),
            torus_mesh(0.8, 0.2, 12, 8).unwrap(),
        )
    }

    /// Two meshes with their trees; each test picks its own sizes.
    fn with_trees(ma: TriMesh, mb: TriMesh) -> (TriMesh, TriMesh, ObbTree, ObbTree) {
        let (ta, tb) = (ObbTree::build(&ma).unwrap(), ObbTree::build(&mb).unwrap());
        (ma, mb, ta, tb)
    }

    #[test]
    fn margin_reports_pairs_with_close_vertices() {
        let (ma, mb, ta, tb) = sphere_and_ring();
        let mut r = rng(8);
        let margin = 0.15;
        for _ in 0..20 {
            let pa = random_pose(&mut r, 0.2);
            let pb = random_pose(&mut r, 3.5);
            let (set, _) = reported(&ta, &pa, &tb, &pb, margin);
            for i in 0..ma.triangles().len() as u32 {
                let p = world_tri(&ma, &pa, i);
                for j in 0..mb.triangles().len() as u32 {
                    let q = world_tri(&mb, &pb, j);
                    let close = p.iter().any(|u| q.iter().any(|v| (*u - *v).length() <= margin));
                    if close {
                        assert!(set.contains(&(i, j)));
                    }
                }
            }
        }
    }

    #[test]
    fn a_drifting_walk_reports_every_pair_that_comes_close_along_the_drift() {
        // Brute force: B's triangles moved along the first-order drift
        // (x -> x + t displacement(x)) at t = 0, 1/8, ..., 1; every pair
        // that comes within the margin at one of those times must be
        // reported, with a motion bound that covers its B triangle's move.
        // The drift is large against the gap (up to 0.6 m across, and
        // turns of up to 0.3 rad), so the walk's stretched boxes matter.
        use crate::triangle::triangle_distance;
        let (ma, mb, ta, tb) = sphere_and_ring();
        let mut r = rng(31);
        let margin = 0.02;
        let mut checked = 0;
        for _ in 0..6 {
            let pa = random_pose(&mut r, 0.2);
            let pb = random_pose(&mut r, 3.0);
            let drift = Drift {
                origin: DVec3::new(r(), r(), r()) - 0.5,
                translation: (pa.position - pb.position).normalize() * 0.6 * r()
                    + DVec3::new(r(), r(), r()) * 0.1,
                rotation: DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 0.6,
            };
            let mut moves_of = std::collections::BTreeMap::new();
            collide_moving(&ta, &pa, &tb, &pb, margin, &drift, |i, j, moves| {
                assert!(moves_of.insert((i, j), moves).is_none(), "pair reported twice");
                Traverse::Continue
            })
            .unwrap();
            for j in 0..mb.triangles().len() as u32 {
                let q0 = world_tri(&mb, &pb, j);
                let shifts = q0.map(|v| drift.displacement(v));
                for i in 0..ma.triangles().len() as u32 {
                    let p = world_tri(&ma, &pa, i);
                    let close = (0..=8).any(|k| {
                        let t = k as f64 / 8.0;
                        let q = [0, 1, 2].map(|c| q0[c] + shifts[c] * t);
                        triangle_distance(&p, &q).distance <= margin
                    });
                    if close {
                        checked += 1;
                        let moves = *moves_of
                            .get(&(i, j))
                            .unwrap_or_else(|| panic!("pair {i}, {j} missed"));
                        let moved = shifts.iter().map(|s| s.length()).fold(0.0, f64::max);
                        assert!(moved <= moves + 1e-9, "moves {moves} < {moved}");
                    }
                }
            }
        }
        assert!(
            checked > 100,
            "only {checked} close pairs: the cases test nothing"
        );
    }

    #[test]
    fn a_walk_inside_another_walks_callback_reports_what_it_reports_alone() {
        // Each walk keeps its placed boxes of B per thread; a callback that
        // walks other trees meanwhile must neither see nor spoil them.
        let (_, _, ta, tb) = sphere_and_ring();
        let (_, _, tc, td) = {
            let mc = torus_mesh(1.0, 0.35, 16, 10).unwrap();
            let md = icosphere_mesh(0.6, 2).unwrap();
            let (tc, td) = (ObbTree::build(&mc).unwrap(), ObbTree::build(&md).unwrap());
            (mc, md, tc, td)
        };
        let mut r = rng(41);
        let drift = Drift {
            origin: DVec3::ZERO,
            translation: DVec3::new(0.1, -0.05, 0.2),
            rotation: DVec3::new(0.0, 0.2, 0.1),
        };
        let mut nested_walks = 0;
        for _ in 0..10 {
            let (pa, pb) = (random_pose(&mut r, 0.2), random_pose(&mut r, 1.0));
            let (pc, pd) = (random_pose(&mut r, 0.2), random_pose(&mut r, 1.0));
            let leaves = |t1, p1, t2, p2| {
                let mut out = Vec::new();
                collide_leaves(t1, p1, t2, p2, 0.05, &drift, |x, y| {
                    out.push((x, y));
                    Traverse::Continue
                })
                .unwrap();
                out
            };
            let (outer_alone, inner_alone) = (leaves(&ta, &pa, &tb, &pb), leaves(&tc, &pc, &td, &pd));
            let mut outer = Vec::new();
            collide_leaves(&ta, &pa, &tb, &pb, 0.05, &drift, |x, y| {
                outer.push((x, y));
                // (A few per walk: the inner walk is the costly part.)
                if outer.len() <= 4 {
                    assert_eq!(leaves(&tc, &pc, &td, &pd), inner_alone);
                    nested_walks += 1;
                }
                Traverse::Continue
            })
            .unwrap();
            assert_eq!(outer, outer_alone);
            // And the cache is whole again for the next walk.
            assert_eq!(leaves(&ta, &pa, &tb, &pb), outer_alone);
        }
        assert!(nested_walks > 10, "the walks met too rarely: {nested_walks}");
    }

    #[test]
    fn a_drift_tests_fewer_pairs_than_a_margin_as_long_as_the_move() {
        // A sphere falling 0.3 m onto a torus: the walk along the fall
        // reports a fraction of the pairs that a margin of 0.3 m on every
        // side would.
        let (_, _, ta, tb) = with_trees(
            torus_mesh(1.0, 0.3, 48, 24).unwrap(),
            icosphere_mesh(0.5, 3).unwrap(),
        );
        let pa = Pose::IDENTITY;
        let pb = Pose::from_translation(DVec3::new(1.0, 0.0, 0.85));
        let fall = Drift {
            origin: DVec3::ZERO,
            translation: DVec3::new(0.0, 0.0, -0.3),
            rotation: DVec3::ZERO,
        };
        let mut along = 0;
        collide_moving(&ta, &pa, &tb, &pb, 0.005, &fall, |_, _, _| {
            along += 1;
            Traverse::Continue
        })
        .unwrap();
        let (around, _) = reported(&ta, &pa, &tb, &pb, 0.305);
        assert!(
            along > 0 && 3 * along < around.len(),
            "{along} along the fall, {} around",
            around.len()
        );
    }

    #[test]
    fn stop_at_first_returns_after_one_pair() {
        let m = torus_mesh(1.0, 0.3, 20, 12).unwrap();
        let t = ObbTree::build(&m).unwrap();
        let p = Pose::IDENTITY;
        let mut calls = 0;
        let stats = collide(&t, &p, &t, &p, 0.0, |_, _| {
            calls += 1;
            Traverse::Stop
        })
        .unwrap();
        assert_eq!(calls, 1);
        assert!(stats.stopped);
        assert_eq!(stats.leaf_pairs, 1);
        assert_eq!(stats.triangle_pairs, 1);
        // Separated meshes: only the root test.
        let far = Pose::new(DVec3::new(10.0, 0.0, 0.0), DQuat::IDENTITY).unwrap();
        let stats = collide(&t, &p, &t, &far, 0.0, |_, _| Traverse::Stop).unwrap();
        assert_eq!(
            stats,
            TraversalStats {
                bv_tests: 1,
                ..Default::default()
            }
        );
        assert!(collide(&t, &p, &t, &far, -1.0, |_, _| Traverse::Stop).is_err());
        assert!(collide(&t, &p, &t, &far, f64::NAN, |_, _| Traverse::Stop).is_err());
    }

    #[test]
    fn distance_traversal_matches_brute_force_vertex_distance() {
        // Callback distance: closest vertex pair of the two triangles, which is
        // never below the true triangle distance, so pruning by the box lower
        // bound must keep the exact brute-force minimum over all vertex pairs.
        let (ma, mb, ta, tb) = with_trees(
            torus_mesh(1.0, 0.3, 14, 8).unwrap(),
            icosphere_mesh(0.5, 1).unwrap(),
        );
        let mut r = rng(4);
        for _ in 0..30 {
            let pa = random_pose(&mut r, 1.0);
            let pb = random_pose(&mut r, 8.0);
            let va: Vec<DVec3> = ma.vertices().iter().map(|&v| pa.transform_point(v)).collect();
            let vb: Vec<DVec3> = mb.vertices().iter().map(|&v| pb.transform_point(v)).collect();
            let brute = va
                .iter()
                .flat_map(|u| vb.iter().map(move |v| (*u - *v).length()))
                .fold(f64::INFINITY, f64::min);
            let (va, vb) = (&va, &vb);
            let res = distance(&ta, &pa, &tb, &pb, f64::INFINITY, |i, j, _| {
                let (x, y) = (ma.triangles()[i as usize], mb.triangles()[j as usize]);
                x.iter()
                    .flat_map(|&u| y.iter().map(move |&v| (va[u as usize] - vb[v as usize]).length()))
                    .fold(f64::INFINITY, f64::min)
            })
            .unwrap();
            assert_eq!(res.distance, brute);
            // Pruning works: far fewer leaf pairs than all of them.
            let leaves = (ta.stats().leaves * tb.stats().leaves) as u64;
            if brute > 0.5 {
                assert!(res.stats.leaf_pairs * 4 < leaves, "{:?}", res.stats);
            }
        }
    }
}
