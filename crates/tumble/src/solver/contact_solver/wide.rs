//! Four contact patches at once: the passes of `passes` (sub-step start with
//! warm start, velocity solve, push-out) over a [`WidePatch`], a bundle of
//! four patches of one colour stored as structure of arrays, one patch per
//! SIMD lane ([`Lane`]). Patches of one colour share no dynamic body, so the
//! four lanes update four disjoint pairs of bodies: their velocities are
//! gathered into lanes, the rows solved lane-parallel, and the velocities of
//! the dynamic bodies scattered back.
//!
//! Each lane computes exactly what the scalar kernel of `passes` computes for
//! its patch (the same operations in the same order, branches turned into
//! lane selects, a lane's early exit into a frozen lane): the wide kernels
//! are a faster layout of the same solver, not a second one, and a test holds
//! them to the scalar kernels' bits. Patches of up to four points (the
//! block-solved ones: box faces, edges, lone points) travel in bundles,
//! a small problem's too, by the levels of its patch order (`coloring`);
//! larger patches, the overflow batch and a small problem too thin for
//! levels (a column of boxes) stay on the scalar kernels.
//!
//! Why: scalar, the velocity passes were bound by f64 arithmetic on one
//! patch at a time (a 3-vector fills no register); four patches per lane set
//! fill the vector unit with independent work.
//!
//! Each function here names its scalar twin (`passes`, `constraint`) and
//! reads like it on purpose, so that the two can be checked line by line;
//! the twins stay because the scalar kernels also run the patches the
//! bundles do not take, on the records, where a lane type of one lane would
//! cost the layout conversion for every patch of a small scene.

use super::body::SolverBody;
use super::coloring::{Coloring, Shared};
use super::constraint::{ManifoldConstraint, PointConstraint, SolverParams, BLOCK_REFRESH};
use super::lanes::{self, eq, gt, le, lt, recip_or_zero, select, Lane, LANES, M3, V3};
use super::rolling::Rolling;
use super::solved::{SolvedPatch, SolvedPoint, SolvedWriter};
use std::ops::Range;
use tumble_collide::DVec3;

/// Marks a lane that holds no patch (padding of a colour's last bundle).
pub(super) const EMPTY: u32 = u32::MAX;

/// The angular part of one row in every lane (`RowJacobian`, widened).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct WideRow {
    ra_x_d: V3,
    rb_x_d: V3,
    ia_ra_x_d: V3,
    ib_rb_x_d: V3,
}

impl WideRow {
    /// `RowJacobian::new`: the row of an impulse along `d` at lever arms `ra`, `rb`.
    #[inline(always)]
    fn new(ia: &M3, ib: &M3, ra: V3, rb: V3, d: V3) -> WideRow {
        let ra_x_d = ra.cross(d);
        let rb_x_d = rb.cross(d);
        WideRow {
            ra_x_d,
            rb_x_d,
            ia_ra_x_d: ia.mul_vec(ra_x_d),
            ib_rb_x_d: ib.mul_vec(rb_x_d),
        }
    }

    /// `RowJacobian::twist`: a pure torque row about `axis`.
    #[inline(always)]
    fn twist(ia: &M3, ib: &M3, axis: V3) -> WideRow {
        WideRow {
            ra_x_d: axis,
            rb_x_d: axis,
            ia_ra_x_d: ia.mul_vec(axis),
            ib_rb_x_d: ib.mul_vec(axis),
        }
    }

    /// `RowJacobian::inverse_mass`.
    #[inline(always)]
    fn inverse_mass(&self, d: V3, ima: Lane, imb: Lane) -> Lane {
        d.dot(d) * (ima + imb) + self.ra_x_d.dot(self.ia_ra_x_d) + self.rb_x_d.dot(self.ib_rb_x_d)
    }

    #[inline(always)]
    fn select(mask: Lane, yes: WideRow, no: WideRow) -> WideRow {
        WideRow {
            ra_x_d: V3::select(mask, yes.ra_x_d, no.ra_x_d),
            rb_x_d: V3::select(mask, yes.rb_x_d, no.rb_x_d),
            ia_ra_x_d: V3::select(mask, yes.ia_ra_x_d, no.ia_ra_x_d),
            ib_rb_x_d: V3::select(mask, yes.ib_rb_x_d, no.ib_rb_x_d),
        }
    }
}

/// Point `i` of every lane's patch (`PointConstraint`, widened), what the
/// velocity passes read of it; lanes whose patch has fewer points hold
/// zeros there, which change nothing.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct WidePoint {
    normal: V3,
    row: WideRow,
    separation_now: Lane,
    normal_mass: Lane,
    normal_impulse: Lane,
    max_normal_impulse: Lane,
}

/// The rest of point `i` of every lane's patch: what only the sub-step
/// starts and the push-out passes read (kept apart from [`WidePoint`], see
/// [`WidePatch`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct PointFrame {
    /// All bits set in lanes where the patch has this point.
    real: Lane,
    r_a: V3,
    r_b: V3,
    separation: Lane,
    push_impulse: Lane,
    half_gap: Lane,
}

/// Four patches of one colour, one per lane, each of at most `N` points
/// (`ManifoldConstraint`s of one, two, or three and four points: a lone
/// point, an edge, a face). A patch of fewer points than `N` is padded with
/// zero rows; the scalar kernel pads its block to
/// [`BLOCK_POINTS`](super::constraint::BLOCK_POINTS) points the same
/// way, so that an `N`-point kernel drops only terms that are exact zeros
/// there, and gives the same bits at a fraction of the work.
///
/// Laid out in two parts: first what the velocity passes read (`solve`,
/// twice a sub-step), then the rest (the sub-step start, the push-out), so
/// that those passes stream 5.2 of a face bundle's 7.3 KB. The bundles of
/// a pile of 1,000 boxes at rest (2.4 MB, of which those passes read 1.35,
/// with 0.4 MB of solver bodies) outgrow a core's 1 MB second-level cache,
/// and each pass reads much of them from the shared third level.
///
/// The twist row comes last of the first part: a bundle of lone points
/// leaves it out and never touches its lines, so that its passes stream
/// 1.9 of its 3.6 KB rather than 2.4. A lone point's twist row is bounded
/// by `mu` times its normal impulse times its twist radius, which is zero;
/// started at zero (the only lone points bundled, [`BundleKind::for_patch`]), it
/// only ever adds a signed zero to the angular velocities, which changes
/// none unless a component is exactly `-0.0` (so the bits are the scalar
/// kernels' in every scene measured).
#[derive(Debug, Clone, PartialEq)]
#[repr(C)]
pub(crate) struct WidePatch<const N: usize> {
    /// Solver bodies A of the lanes (0, the immovable body, in empty lanes).
    pub(super) a: [u32; LANES],
    /// Solver bodies B.
    pub(super) b: [u32; LANES],
    friction: Lane,
    inv_mass: [Lane; 2],
    directions: [V3; 2],
    /// The two tangent rows of patch friction.
    rows: [WideRow; 2],
    masses: [Lane; 2],
    impulses: [Lane; 2],
    block: Block<N>,
    block_inverse: Block<N>,
    points: [WidePoint; N],
    /// The twist row, where `N > 1` (unused and never touched in bundles
    /// of lone points: see above).
    twist: TwistLanes,
    // What the velocity passes do not read.
    /// Index of each lane's patch in the patch array, [`EMPTY`] for none.
    source: [u32; LANES],
    /// Each lane's first point and point count in the records
    /// (`ManifoldConstraint::first_point`, `point_count`).
    first_point: [u32; LANES],
    point_count: [u32; LANES],
    /// Whether any lane has a round side.
    any_rolling: bool,
    /// Each lane's `rolling::Rolling` in lanes (`ManifoldConstraint::rolling`).
    roll: RollLanes,
    /// Each lane's `ManifoldConstraint::half_gap`.
    half_gap: Lane,
    normal: V3,
    r_a: V3,
    r_b: V3,
    /// All bits set in lanes whose patch holds an anchor
    /// (`ManifoldConstraint::anchored`), its lever arms and offset.
    anchored: Lane,
    anchor_ra: V3,
    anchor_rb: V3,
    anchor_offset: V3,
    frames: [PointFrame; N],
}

/// The twist row of four patches (`ManifoldConstraint::rows[2]`, its mass,
/// impulse and `twist_radius`, widened).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct TwistLanes {
    row: WideRow,
    mass: Lane,
    impulse: Lane,
    radius: Lane,
}

/// `rolling::Rolling` of four patches, one per lane (zero in lanes without
/// a round side, whose `mask` is clear): the values its arithmetic reads,
/// each computed as the scalar kernel computes it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct RollLanes {
    mask: Lane,
    /// Lanes whose side A (B) is round.
    round_a: Lane,
    round_b: Lane,
    radius_a: Lane,
    radius_b: Lane,
    share_a: Lane,
    /// `1 - share_a`, as `Rolling::shared_lever_arms` computes it.
    share_b: Lane,
}

/// The bundle a patch travels in, by the point count of its kernel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BundleKind {
    /// Bundles of lone points.
    Ones,
    /// Bundles of two-point patches.
    Twos,
    /// Bundles of three- and four-point patches.
    Fours,
    /// No bundle: a patch of more than
    /// [`BLOCK_POINTS`](super::constraint::BLOCK_POINTS) points, a curved
    /// one, or a lone point that starts with a twist (scalar kernels).
    Large,
}

impl BundleKind {
    /// The bundle of record `m` (the tests' way to it).
    #[cfg(test)]
    pub fn of(m: &ManifoldConstraint) -> BundleKind {
        BundleKind::for_patch(m.point_count, m.is_curved(), m.impulses[2])
    }

    /// The bundle of a patch of `points` points, `curved` or not, whose
    /// warm start carries the twist impulse `twist`, as its record will
    /// hold them.
    #[inline]
    pub fn for_patch(points: u32, curved: bool, twist: f64) -> BundleKind {
        if curved {
            // Its normals turn every sub-step: rare, and scalar.
            return BundleKind::Large;
        }
        match points {
            // A lone point's twist row only ever holds zero (its bound is
            // zero) and the bundles of lone points leave it out; one that
            // starts with a twist (carried over from a larger patch, and
            // taken back by its first pass) is left to the scalar kernels.
            0 | 1 if twist == 0.0 => BundleKind::Ones,
            0 | 1 => BundleKind::Large,
            2 => BundleKind::Twos,
            3 | 4 => BundleKind::Fours,
            _ => BundleKind::Large,
        }
    }
}

impl<const N: usize> WidePatch<N> {
    /// A bundle for the patches `source` (each lane's index into the patch
    /// array, [`EMPTY`] for none), to be [`filled`](WidePatch::fill) from
    /// their records.
    fn planned(source: [u32; LANES]) -> WidePatch<N> {
        WidePatch {
            a: [0; LANES],
            b: [0; LANES],
            source,
            first_point: [0; LANES],
            point_count: [0; LANES],
            friction: Lane::ZERO,
            twist: TwistLanes::default(),
            roll: RollLanes::default(),
            any_rolling: false,
            half_gap: Lane::ZERO,
            normal: V3::ZERO,
            directions: [V3::ZERO; 2],
            r_a: V3::ZERO,
            r_b: V3::ZERO,
            rows: [WideRow::default(); 2],
            masses: [Lane::ZERO; 2],
            impulses: [Lane::ZERO; 2],
            inv_mass: [Lane::ZERO; 2],
            block: [[Lane::ZERO; N]; N],
            block_inverse: [[Lane::ZERO; N]; N],
            points: [WidePoint::default(); N],
            frames: [PointFrame::default(); N],
            anchored: Lane::ZERO,
            anchor_ra: V3::ZERO,
            anchor_rb: V3::ZERO,
            anchor_offset: V3::ZERO,
        }
    }

    /// Sets every lane from its patch's record, the lanes' patches being
    /// `source` (as [`WideBatches::plan`] planned them) and `records` each
    /// lane's record and its points (`None` in the empty lanes, which stay
    /// zero, as do the points a patch does not have). The rows, their
    /// masses and the normal block are not read from the records but
    /// computed here from `bodies` at the step start, as
    /// `constraint::prepare_patch` computes them (see [`prepare_rows`]).
    ///
    /// Every field is written once, whole lanes from the four records at a
    /// time. Why: zeroing the bundle first and then setting its lanes value
    /// by value wrote each line twice, and the rows' computation then read
    /// whole lanes that had just been written in quarters (a store the
    /// core cannot forward to the wider load).
    pub(super) fn fill(
        &mut self,
        source: [u32; LANES],
        records: [Option<(&ManifoldConstraint, &[PointConstraint])>; LANES],
        bodies: &[SolverBody],
    ) {
        let m = records.map(|r| r.map(|(m, _)| m));
        let w = self;
        w.source = source;
        w.a = m.map(|m| m.map_or(0, |m| m.a));
        w.b = m.map(|m| m.map_or(0, |m| m.b));
        w.first_point = m.map(|m| m.map_or(0, |m| m.first_point));
        w.point_count = m.map(|m| m.map_or(0, |m| m.point_count));
        debug_assert!(w.point_count.iter().all(|&c| c as usize <= N));
        debug_assert!(
            N > 1 || m.iter().flatten().all(|m| m.impulses[2] == 0.0),
            "a lone point bundled with a twist"
        );
        w.friction = lanes_of(&m, |m| m.friction);
        w.half_gap = lanes_of(&m, |m| m.half_gap);
        w.normal = v3_of(&m, |m| m.normal);
        w.directions = [0, 1].map(|i| v3_of(&m, |m| m.directions[i]));
        w.r_a = v3_of(&m, |m| m.r_a);
        w.r_b = v3_of(&m, |m| m.r_b);
        w.impulses = [0, 1].map(|i| lanes_of(&m, |m| m.impulses[i]));
        w.inv_mass = [0, 1].map(|i| lanes_of(&m, |m| m.inv_mass[i]));
        // The parts `prepare_rows` writes where the lanes are real, zero in
        // the others.
        w.masses = [Lane::ZERO; 2];
        w.block = [[Lane::ZERO; N]; N];
        w.block_inverse = [[Lane::ZERO; N]; N];
        w.twist = TwistLanes {
            row: WideRow::default(),
            mass: Lane::ZERO,
            impulse: lanes_of(&m, |m| m.impulses[2]),
            radius: lanes_of(&m, |m| m.twist_radius),
        };
        // `rolling::Rolling` of each lane with a round side.
        let roll = m.map(|m| m.and_then(|m| Rolling::of(m.rolling)).map(|r| r.parts()));
        w.any_rolling = roll.iter().any(Option::is_some);
        let rolled = |f: &dyn Fn([f64; 2], f64) -> f64| {
            Lane::new(roll.map(|r| r.map_or(0.0, |([ra, rb], share)| f([ra, rb], share))))
        };
        w.roll = if w.any_rolling {
            RollLanes {
                mask: lanes::mask(roll.map(|r| r.is_some())),
                round_a: lanes::mask(roll.map(|r| r.is_some_and(|([ra, _], _)| ra > 0.0))),
                round_b: lanes::mask(roll.map(|r| r.is_some_and(|([_, rb], _)| rb > 0.0))),
                radius_a: rolled(&|[ra, _], _| ra),
                radius_b: rolled(&|[_, rb], _| rb),
                share_a: rolled(&|_, share| share),
                share_b: rolled(&|_, share| 1.0 - share),
            }
        } else {
            RollLanes::default()
        };
        // The anchor's parts in the anchored lanes only.
        let anchored = m.map(|m| m.filter(|m| m.anchored));
        w.anchored = lanes::mask(anchored.map(|m| m.is_some()));
        w.anchor_ra = v3_of(&anchored, |m| m.anchor_r[0]);
        w.anchor_rb = v3_of(&anchored, |m| m.anchor_r[1]);
        w.anchor_offset = v3_of(&anchored, |m| m.anchor_offset);
        for (i, (wp, f)) in w.points.iter_mut().zip(&mut w.frames).enumerate() {
            let p = records.map(|r| r.and_then(|(_, pts)| pts.get(i)));
            *f = PointFrame {
                real: lanes::mask(p.map(|p| p.is_some())),
                r_a: v3_of(&p, |p| p.r_a),
                r_b: v3_of(&p, |p| p.r_b),
                separation: lanes_of(&p, |p| p.separation),
                push_impulse: lanes_of(&p, |p| p.push_impulse),
                half_gap: lanes_of(&p, |p| p.half_gap),
            };
            wp.normal = v3_of(&p, |p| p.normal);
            wp.separation_now = lanes_of(&p, |p| p.separation_now);
            wp.normal_impulse = lanes_of(&p, |p| p.normal_impulse);
            wp.max_normal_impulse = lanes_of(&p, |p| p.max_normal_impulse);
            wp.normal_mass = Lane::ZERO;
        }
        prepare_rows(w, bodies);
    }

    /// Writes every lane's solved parts ([`SolvedPatch::from_parts`]):
    /// what the step reads after the sub-steps (warm-start cache, reported
    /// impulses, contact events). The records themselves keep the step
    /// start's impulses.
    ///
    /// # Safety
    /// No other thread writes this bundle's patches' solved parts meanwhile.
    pub(super) unsafe fn unpack(&self, solved: &SolvedWriter) {
        let directions = self.directions.map(V3::to_lanes);
        for l in 0..LANES {
            let k = self.source[l];
            if k == EMPTY {
                continue;
            }
            let points: [SolvedPoint; N] = std::array::from_fn(|i| {
                let p = &self.points[i];
                SolvedPoint::new(get(p.normal_impulse, l), get(p.max_normal_impulse, l))
            });
            let points = &points[..self.point_count[l] as usize];
            let patch = SolvedPatch::from_parts(
                [directions[0][l], directions[1][l]],
                [
                    get(self.impulses[0], l),
                    get(self.impulses[1], l),
                    // A bundle of lone points keeps its records' twist
                    // impulse (zero) untouched: `BundleKind::for_patch`.
                    get(self.twist.impulse, l),
                ],
                get(self.friction, l),
                self.first_point[l],
                [self.a[l], self.b[l]],
                points.iter().map(|p| p.normal_impulse),
            );
            // SAFETY: the caller's promise.
            unsafe { solved.put(k as usize, patch, points) };
        }
    }
}

#[inline(always)]
fn get(x: Lane, l: usize) -> f64 {
    x.as_array()[l]
}

/// One value per lane from each lane's item (0 where it has none).
#[inline(always)]
fn lanes_of<T>(items: &[Option<&T>; LANES], value: impl Fn(&T) -> f64) -> Lane {
    Lane::new(items.map(|t| t.map_or(0.0, &value)))
}

/// One vector per lane from each lane's item (zero where it has none).
#[inline(always)]
fn v3_of<T>(items: &[Option<&T>; LANES], value: impl Fn(&T) -> DVec3) -> V3 {
    V3::from_lanes(items.map(|t| t.map_or(DVec3::ZERO, &value)))
}

#[cfg(test)]
fn get_row(w: &WideRow, l: usize) -> super::constraint::RowJacobian {
    super::constraint::RowJacobian {
        ra_x_d: w.ra_x_d.to_lanes()[l],
        rb_x_d: w.rb_x_d.to_lanes()[l],
        ia_ra_x_d: w.ia_ra_x_d.to_lanes()[l],
        ib_rb_x_d: w.ib_rb_x_d.to_lanes()[l],
    }
}

/// What one item costs in a sub-step, in quarters of a bundle of lone
/// points: a bundle of lone points, of two-point patches, of three- and
/// four-point patches, and one large patch (scalar); by these a colour is
/// judged worth a second thread ([`MIN_WEIGHT_TO_SPLIT`]). Measured
/// (`profile_stages pile1000` and `concave_pile`, one thread, each kind of
/// item timed over the run, a sub-step being one start, two velocity
/// passes and a push-out pass): a bundle of two-point patches costs 1.5
/// bundles of lone points, a bundle of faces 2.65, a large patch 1.2.
const WEIGHTS: [usize; 4] = [4, 6, 11, 5];

/// Colours lighter than this (in [`WEIGHTS`] units: sixteen bundles of
/// lone points) are not worth a second thread; a run of them at the end of
/// the colouring goes to one thread without barriers between them.
pub const MIN_WEIGHT_TO_SPLIT: usize = 64;

/// The bundles of one colour: ranges of [`WideBatches`]' arrays.
#[derive(Debug, Clone, Default)]
pub(crate) struct ColorBundles {
    /// Bundles of lone points.
    pub ones: Range<usize>,
    /// Bundles of two-point patches.
    pub twos: Range<usize>,
    /// Bundles of three- and four-point patches.
    pub fours: Range<usize>,
    /// Patches of more than four points (range of `large`).
    pub large: Range<usize>,
}

impl ColorBundles {
    fn ranges(&self) -> [&Range<usize>; 4] {
        [&self.ones, &self.twos, &self.fours, &self.large]
    }

    /// The colour's runs: ranges into the arrays of ones, twos, fours and
    /// `large`, in that order.
    pub fn all(&self) -> [Range<usize>; 4] {
        self.ranges().map(Range::clone)
    }

    /// The colour's work in [`WEIGHTS`] units.
    pub fn weight(&self) -> usize {
        self.ranges().iter().zip(WEIGHTS).map(|(r, w)| r.len() * w).sum()
    }
}

/// The colour batches of a step in bundles: each colour's patches of up to
/// four points, four to a [`WidePatch`] of their point count in patch order,
/// and its larger patches, which the scalar kernels solve beside the bundles.
#[derive(Debug, Default)]
pub(crate) struct WideBatches {
    /// Bundles of lone points, colour after colour.
    pub ones: Vec<WidePatch<1>>,
    /// Bundles of two-point patches.
    pub twos: Vec<WidePatch<2>>,
    /// Bundles of three- and four-point patches.
    pub fours: Vec<WidePatch<4>>,
    /// The lanes' patches (indices into the patch array, [`EMPTY`] for
    /// none) of each bundle of `ones`, `twos` and `fours`, by index: set
    /// by [`Self::plan`], copied into each bundle as it is filled.
    pub sources: [Vec<[u32; LANES]>; 3],
    /// Per colour of the colouring: its bundles and large patches.
    pub colors: Vec<ColorBundles>,
    /// Patches of more than four points, colour after colour (indices into
    /// the patch array).
    pub large: Vec<u32>,
    /// Per patch: whether it travels in a bundle (not large, not in the
    /// overflow batch).
    pub in_bundle: Vec<bool>,
    /// Colours from this one on are all lighter than
    /// [`MIN_WEIGHT_TO_SPLIT`]: one thread runs them, back to back.
    pub split: usize,
    /// Per bundle of `ones`, `twos` and `fours`: the key body of its
    /// first lane's patch (see [`Self::plan`]), by which a team deals the
    /// bundles (`batches::ThreadFlow`).
    pub keys: [Vec<u32>; 3],
    /// The key body of each patch of `large`.
    pub large_keys: Vec<u32>,
    /// Per solver body `b`, the work of the colours' patches whose key is
    /// a body before `b` (in sixteenths of a bundle of lone points, by
    /// [`WEIGHTS`]; one more entry than bodies): where
    /// [`Self::body_run`] cuts the bodies.
    work_before: Vec<u32>,
}

impl WideBatches {
    /// Plans the bundles of the colours of `coloring` (the overflow batch
    /// stays out), reusing this value's buffers, from each patch record's
    /// [`BundleKind`], in record order.
    ///
    /// Only the lanes' sources are set here; each bundle is then
    /// [`filled`](WidePatch::fill) from the records, by the solver's team
    /// (`SolverArrays::fill`).
    ///
    /// `keys` holds each record's key body: the solver index of a dynamic
    /// body of its patch (the first, where both are), below `bodies`.
    pub fn plan(&mut self, coloring: &Coloring, kinds: &[BundleKind], keys: &[u32], bodies: usize) {
        // From each record's bundle kind alone (written with the records,
        // on the pool), writing only the small lists of sources: the
        // records (some 200 bytes each) and the bundles (about 7 KB each
        // for faces) are touched by the team that fills them, not here
        // (this serial pass read every record twice and wrote into every
        // bundle: 1.3-1.8 ms a step of the pile of 10,000).
        self.colors.clear();
        self.large.clear();
        self.sources.iter_mut().for_each(Vec::clear);
        self.keys.iter_mut().for_each(Vec::clear);
        self.large_keys.clear();
        self.work_before.clear();
        self.work_before.resize(bodies + 1, 0);
        let mut by_size: [Vec<u32>; 3] = Default::default();
        for range in &coloring.colors {
            by_size.iter_mut().for_each(Vec::clear);
            let first_large = self.large.len();
            for k in range.clone() {
                // A patch's share of its bundle's work (a quarter of it in
                // `WEIGHTS` units), a large patch's whole (four quarters).
                let bundled = |by_size: &mut [Vec<u32>; 3], kind: usize| {
                    by_size[kind].push(k as u32);
                    WEIGHTS[kind]
                };
                let work = match kinds[k] {
                    BundleKind::Ones => bundled(&mut by_size, 0),
                    BundleKind::Twos => bundled(&mut by_size, 1),
                    BundleKind::Fours => bundled(&mut by_size, 2),
                    BundleKind::Large => {
                        self.large.push(k as u32);
                        self.large_keys.push(keys[k]);
                        4 * WEIGHTS[3]
                    }
                };
                self.work_before[keys[k] as usize + 1] += work as u32;
            }
            let [ones, twos, fours] = std::array::from_fn(|kind| {
                let sources = &mut self.sources[kind];
                let first = sources.len();
                sources.extend(by_size[kind].chunks(LANES).map(lane_sources));
                let firsts = by_size[kind].chunks(LANES).map(|c| keys[c[0] as usize]);
                self.keys[kind].extend(firsts);
                first..sources.len()
            });
            self.colors.push(ColorBundles {
                ones,
                twos,
                fours,
                large: first_large..self.large.len(),
            });
        }
        // The bundle arrays keep last step's bundles (`fill` rewrites each
        // whole); grown, sized first: bundles are large, and a vector that
        // doubles its way up moves them several times.
        fn size<const N: usize>(bundles: &mut Vec<WidePatch<N>>, n: usize) {
            bundles.truncate(n);
            bundles.reserve(n - bundles.len());
            bundles.resize_with(n, || WidePatch::planned([EMPTY; LANES]));
        }
        self.in_bundle.clear();
        self.in_bundle.resize(kinds.len(), false);
        for &k in self.sources.iter().flatten().flatten().filter(|&&k| k != EMPTY) {
            self.in_bundle[k as usize] = true;
        }
        for b in 1..self.work_before.len() {
            self.work_before[b] += self.work_before[b - 1];
        }
        size(&mut self.ones, self.sources[0].len());
        size(&mut self.twos, self.sources[1].len());
        size(&mut self.fours, self.sources[2].len());
        // Levels of a small problem run on one thread (`coloring`).
        self.split = if coloring.levels {
            0
        } else {
            self.colors
                .iter()
                .rposition(|c| c.weight() >= MIN_WEIGHT_TO_SPLIT)
                .map_or(0, |c| c + 1)
        };
    }

    /// Thread `index` of `size`'s run of the solver bodies: the bodies cut
    /// in `size` contiguous runs whose patches (by their key bodies) carry
    /// near-equal work. A team deals the patches by it and integrates the
    /// bodies by it (`batches::ThreadFlow`).
    ///
    /// Why by work and not by count: the bodies low in a pile or a pyramid
    /// (lower indices) touch more patches; cut by count, the first of two
    /// threads had 10 % more of the pile of 1,000's patch work and 20 %
    /// more of the pyramid's, and the other waited for it every pass.
    pub fn body_run(&self, index: usize, size: usize) -> Range<usize> {
        let n = self.work_before.len().saturating_sub(1);
        let total = self.work_before.last().copied().unwrap_or(0) as u64;
        let cut = |i: usize| {
            if i == 0 {
                0
            } else if i >= size {
                n
            } else {
                let target = total * i as u64 / size as u64;
                self.work_before[..n].partition_point(|&w| (w as u64) < target)
            }
        };
        cut(index)..cut(index + 1)
    }
}

/// The patch of each lane: `sources` in order, then [`EMPTY`].
fn lane_sources(sources: &[u32]) -> [u32; LANES] {
    std::array::from_fn(|l| sources.get(l).copied().unwrap_or(EMPTY))
}

/// The velocities of the lanes' body pairs while their rows are solved
/// (`passes::PairVelocity`, widened).
#[derive(Clone, Copy)]
struct PairLanes {
    va: V3,
    wa: V3,
    vb: V3,
    wb: V3,
}

impl PairLanes {
    /// # Safety
    /// No other thread writes the lanes' bodies meanwhile.
    #[inline(always)]
    unsafe fn load<const N: usize>(bodies: &Shared<SolverBody>, w: &WidePatch<N>) -> PairLanes {
        // SAFETY: the caller's promise.
        let (a, b) = unsafe { lane_bodies(bodies, w) };
        PairLanes {
            va: V3::from_lanes(a.map(|b| b.v)),
            wa: V3::from_lanes(a.map(|b| b.w)),
            vb: V3::from_lanes(b.map(|b| b.v)),
            wb: V3::from_lanes(b.map(|b| b.w)),
        }
    }

    /// Writes the velocities of the dynamic bodies back (the others are
    /// never changed by impulses and may be shared between lanes).
    ///
    /// # Safety
    /// The lanes' dynamic bodies are this thread's alone meanwhile.
    #[inline(always)]
    unsafe fn store<const N: usize>(&self, bodies: &Shared<SolverBody>, w: &WidePatch<N>) {
        // SAFETY: the caller's promise.
        unsafe {
            scatter(
                bodies,
                w,
                [self.va, self.wa, self.vb, self.wb],
                |body, v, omega| {
                    body.v = v;
                    body.w = omega;
                },
            )
        };
    }

    #[inline(always)]
    fn along(&self, d: V3, ra_x_d: V3, rb_x_d: V3) -> Lane {
        d.dot(self.va - self.vb) + ra_x_d.dot(self.wa) - rb_x_d.dot(self.wb)
    }

    #[inline(always)]
    fn apply(&mut self, d: V3, ia: V3, ib: V3, inv_mass: [Lane; 2], lambda: Lane) {
        self.va += d.scale(lambda * inv_mass[0]);
        self.wa += ia.scale(lambda);
        self.vb -= d.scale(lambda * inv_mass[1]);
        self.wb -= ib.scale(lambda);
    }

    /// [`PairLanes::apply`] for a pure torque row (its linear direction is
    /// zero, which would add nothing to the linear velocities).
    #[inline(always)]
    fn apply_angular(&mut self, ia: V3, ib: V3, lambda: Lane) {
        self.wa += ia.scale(lambda);
        self.wb -= ib.scale(lambda);
    }

    #[inline(always)]
    fn lerp(&self, to: &PairLanes, t: Lane) -> PairLanes {
        PairLanes {
            va: self.va + (to.va - self.va).scale(t),
            wa: self.wa + (to.wa - self.wa).scale(t),
            vb: self.vb + (to.vb - self.vb).scale(t),
            wb: self.wb + (to.wb - self.wb).scale(t),
        }
    }

    #[inline(always)]
    fn select(mask: Lane, yes: &PairLanes, no: &PairLanes) -> PairLanes {
        PairLanes {
            va: V3::select(mask, yes.va, no.va),
            wa: V3::select(mask, yes.wa, no.wa),
            vb: V3::select(mask, yes.vb, no.vb),
            wb: V3::select(mask, yes.wb, no.wb),
        }
    }
}

/// `passes::begin_patch` on four patches: separations for the current
/// poses, rows re-aimed at the contacts as they are now (lanes whose bodies
/// moved), masses and blocks refreshed, and with `warm` the warm start,
/// scaled down where it would add energy.
///
/// # Safety
/// The lanes' dynamic bodies are this thread's alone meanwhile.
pub(super) unsafe fn begin<const N: usize>(w: &mut WidePatch<N>, bodies: &Shared<SolverBody>, warm: bool) {
    // SAFETY: the caller's promise.
    let (a, b) = unsafe { lane_bodies(bodies, w) };
    let (dpa, dpb) = (V3::from_lanes(a.map(|b| b.dp)), V3::from_lanes(b.map(|b| b.dp)));
    let (ta, tb) = (
        M3::from_lanes(a.map(|b| b.turn)),
        M3::from_lanes(b.map(|b| b.turn)),
    );
    // The lanes whose bodies moved since the step start (`dp != 0` or
    // `turn != I` on either side, as `passes::begin_patch` asks), compared
    // on the lanes just gathered: the same answer as 96 compares and
    // branches body by body (a tenth of this function's instructions), in
    // 24 lane compares.
    let at_start = dpa.eq_mask(&V3::ZERO)
        & dpb.eq_mask(&V3::ZERO)
        & ta.eq_mask(&M3::IDENTITY)
        & tb.eq_mask(&M3::IDENTITY);
    let moved = !at_start;
    let any_moved = moved.any();
    // Where every lane moved (the usual case) the new rows replace the old
    // whole: a lane select written back to memory becomes a masked store,
    // which is slow on some cores.
    let all_moved = moved.all();
    let pick = |new: WideRow, old: WideRow| {
        if all_moved {
            new
        } else {
            WideRow::select(moved, new, old)
        }
    };
    let (ia, ib) = (
        M3::from_lanes(a.map(|b| b.inv_inertia)),
        M3::from_lanes(b.map(|b| b.inv_inertia)),
    );
    // Lanes with a round side (`ManifoldConstraint::rolling`) are re-aimed
    // as `rolling::Rolling` re-aims them, by the same operations in the same
    // order (so the same bits), and selected into those lanes only.
    let roll = w.any_rolling.then_some(&w.roll);
    // Where every lane rolls (a bundle of spheres' points), the plain
    // anchors and arms would only be selected away: not computed.
    let all_roll = roll.is_some_and(|k| k.mask.all());
    let anchors = |r_a: V3, r_b: V3, n: V3, half_gap: Lane| {
        let plain = || (ta.mul_vec(r_a), tb.mul_vec(r_b));
        match roll {
            Some(k) => {
                // `Rolling::reach`, then `anchors`' `n * reach[0]`, `n * -reach[1]`
                // (x * -1 is the exact negation, signed zeros included).
                let reach_a = select(k.round_a, k.radius_a + half_gap, Lane::ZERO);
                let reach_b = select(k.round_b, k.radius_b + half_gap, Lane::ZERO);
                let (ca, cb) = (n.scale(reach_a), n.scale(reach_b * Lane::splat(-1.0)));
                let rolled = (ta.mul_vec(r_a + ca) - ca, tb.mul_vec(r_b + cb) - cb);
                if all_roll {
                    return rolled;
                }
                let plain = plain();
                (
                    V3::select(k.mask, rolled.0, plain.0),
                    V3::select(k.mask, rolled.1, plain.1),
                )
            }
            None => plain(),
        }
    };
    let lever_arms = |r_a: V3, r_b: V3, ra_now: V3, rb_now: V3| {
        let plain = || shared_lever_arms(r_a, r_b, ra_now, rb_now, dpa, dpb);
        match roll {
            Some(k) => {
                let ab = r_a - r_b + dpb - dpa;
                let shared = ra_now.scale(k.share_a) + (rb_now + ab).scale(k.share_b);
                if all_roll {
                    return (shared, shared - ab);
                }
                let plain = plain();
                (
                    V3::select(k.mask, shared, plain.0),
                    V3::select(k.mask, shared - ab, plain.1),
                )
            }
            None => plain(),
        }
    };
    for (p, f) in w.points.iter_mut().zip(&mut w.frames) {
        let (ra_now, rb_now) = anchors(f.r_a, f.r_b, p.normal, f.half_gap);
        let d = (dpa + ra_now - f.r_a) - (dpb + rb_now - f.r_b);
        p.separation_now = f.separation + p.normal.dot(d);
        f.push_impulse = Lane::ZERO;
        if any_moved {
            let (ra, rb) = lever_arms(f.r_a, f.r_b, ra_now, rb_now);
            p.row = pick(WideRow::new(&ia, &ib, ra, rb, p.normal), p.row);
        }
    }
    let mut turned = Lane::ZERO;
    if any_moved {
        let (ra_now, rb_now) = anchors(w.r_a, w.r_b, w.normal, w.half_gap);
        let (ra, rb) = lever_arms(w.r_a, w.r_b, ra_now, rb_now);
        for i in 0..2 {
            w.rows[i] = pick(WideRow::new(&ia, &ib, ra, rb, w.directions[i]), w.rows[i]);
        }
        if N > 1 {
            w.twist.row = pick(WideRow::twist(&ia, &ib, w.normal), w.twist.row);
        }
    }
    if any_moved {
        turned = refresh_masses(w, moved, all_moved, Lane::ZERO);
    }
    if warm {
        // SAFETY: the caller's promise.
        let before = unsafe { PairLanes::load(bodies, w) };
        let mut vel = before;
        let any_turned = turned.any();
        let work_before = if any_turned { work(&vel, w) } else { Lane::ZERO };
        for p in w.points.iter() {
            vel.apply(
                p.normal,
                p.row.ia_ra_x_d,
                p.row.ib_rb_x_d,
                w.inv_mass,
                p.normal_impulse,
            );
        }
        for (i, row) in w.rows.iter().enumerate() {
            vel.apply(
                w.directions[i],
                row.ia_ra_x_d,
                row.ib_rb_x_d,
                w.inv_mass,
                w.impulses[i],
            );
        }
        if N > 1 {
            let t = &w.twist;
            vel.apply_angular(t.row.ia_ra_x_d, t.row.ib_rb_x_d, t.impulse);
        }
        if any_turned {
            let scale = select(turned, energy_safe_scale(work_before, work(&vel, w)), Lane::ONE);
            let shrink = lt(scale, Lane::ONE);
            if shrink.any() {
                vel = PairLanes::select(shrink, &before.lerp(&vel, scale), &vel);
                for p in w.points.iter_mut() {
                    p.normal_impulse = select(shrink, p.normal_impulse * scale, p.normal_impulse);
                }
                for impulse in &mut w.impulses {
                    *impulse = select(shrink, *impulse * scale, *impulse);
                }
                if N > 1 {
                    let t = &mut w.twist.impulse;
                    *t = select(shrink, *t * scale, *t);
                }
            }
        }
        // SAFETY: the caller's promise.
        unsafe { vel.store(bodies, w) };
    }
}

/// `constraint::prepare_patch`'s rows on four patches: each point's normal
/// row, the friction and twist rows at the patch's centroid, their masses
/// and the normal block with its inverse, from the lanes' bodies at the
/// step start (empty lanes stay zero).
fn prepare_rows<const N: usize>(w: &mut WidePatch<N>, bodies: &[SolverBody]) {
    let real_lanes = w.source.map(|k| k != EMPTY);
    let real = lanes::mask(real_lanes);
    let (ia, ib) = (
        M3::from_lanes(w.a.map(|k| bodies[k as usize].inv_inertia)),
        M3::from_lanes(w.b.map(|k| bodies[k as usize].inv_inertia)),
    );
    for (p, f) in w.points.iter_mut().zip(&w.frames) {
        p.row = WideRow::new(&ia, &ib, f.r_a, f.r_b, p.normal);
    }
    for i in 0..2 {
        w.rows[i] = WideRow::new(&ia, &ib, w.r_a, w.r_b, w.directions[i]);
    }
    if N > 1 {
        w.twist.row = WideRow::twist(&ia, &ib, w.normal);
    }
    refresh_masses(w, real, !real_lanes.contains(&false), real);
}

/// `sum lambda_i u_i` over a bundle's rows (`passes::begin_patch`'s `work`).
#[inline(always)]
fn work<const N: usize>(vel: &PairLanes, w: &WidePatch<N>) -> Lane {
    let p = &w.points;
    let term = |i: usize| p[i].normal_impulse * vel.along(p[i].normal, p[i].row.ra_x_d, p[i].row.rb_x_d);
    let normal = (1..N).fold(term(0), |sum, i| sum + term(i));
    let row = |i: usize| w.impulses[i] * vel.along(w.directions[i], w.rows[i].ra_x_d, w.rows[i].rb_x_d);
    let friction = row(0) + row(1);
    if N > 1 {
        let t = &w.twist;
        normal + (friction + t.impulse * vel.along(V3::ZERO, t.row.ra_x_d, t.row.rb_x_d))
    } else {
        normal + friction
    }
}

/// The bodies A and B of every lane.
///
/// # Safety
/// No other thread writes the lanes' bodies while the references live.
#[inline(always)]
unsafe fn lane_bodies<'a, const N: usize>(
    bodies: &'a Shared<SolverBody>,
    w: &WidePatch<N>,
) -> ([&'a SolverBody; LANES], [&'a SolverBody; LANES]) {
    // SAFETY: the caller's promise.
    unsafe {
        (
            std::array::from_fn(|l| bodies.get(w.a[l] as usize)),
            std::array::from_fn(|l| bodies.get(w.b[l] as usize)),
        )
    }
}

/// Writes a linear and an angular value per lane to the lanes' dynamic
/// bodies (`[A linear, A angular, B linear, B angular]`) with `set`; static,
/// kinematic and sleeping bodies are never written (impulses do not move
/// them, and they may be shared between lanes).
///
/// # Safety
/// The lanes' dynamic bodies are this thread's alone meanwhile.
#[inline(always)]
unsafe fn scatter<const N: usize>(
    bodies: &Shared<SolverBody>,
    w: &WidePatch<N>,
    values: [V3; 4],
    set: impl Fn(&mut SolverBody, DVec3, DVec3),
) {
    let [al, aa, bl, ba] = values.map(V3::to_lanes);
    for l in 0..LANES {
        for (body, linear, angular) in [(w.a[l], al[l], aa[l]), (w.b[l], bl[l], ba[l])] {
            // SAFETY: the caller's promise; only dynamic bodies are written.
            unsafe {
                if bodies.get(body as usize).dynamic {
                    set(bodies.get_mut(body as usize), linear, angular);
                }
            }
        }
    }
}

/// `passes::energy_safe_scale`, lane by lane.
#[inline(always)]
fn energy_safe_scale(work_before: Lane, work_after: Lane) -> Lane {
    let b = work_after - work_before;
    let partial = (Lane::splat(-2.0) * work_before / b).min(Lane::ONE);
    let shrinks = lt(work_before, Lane::ZERO) & gt(b, Lane::ZERO);
    let scale = select(shrinks, partial, Lane::ZERO);
    select(le(work_before + work_after, Lane::ZERO), Lane::ONE, scale)
}

/// `passes::shared_lever_arms`, lane by lane.
#[inline(always)]
fn shared_lever_arms(ra0: V3, rb0: V3, ra: V3, rb: V3, dpa: V3, dpb: V3) -> (V3, V3) {
    let ab = ra0 - rb0 + dpb - dpa;
    let ra_mid = (ra + rb + ab).scale(Lane::splat(0.5));
    (ra_mid, ra_mid - ab)
}

/// `constraint::refresh_masses` in the lanes of `moved`, forced in the lanes
/// of `forced` (within `moved`); returns the lanes whose block was rebuilt:
/// those forced and those whose points' masses moved by more than
/// [`BLOCK_REFRESH`].
#[inline(always)]
fn refresh_masses<const N: usize>(w: &mut WidePatch<N>, moved: Lane, all_moved: bool, forced: Lane) -> Lane {
    let pick = |new: Lane, old: Lane| if all_moved { new } else { select(moved, new, old) };
    let [ima, imb] = w.inv_mass;
    let mut turned = Lane::ZERO;
    for (i, p) in w.points.iter_mut().enumerate() {
        let k = p.row.inverse_mass(p.normal, ima, imb);
        let reference = w.block[i][i];
        turned |= gt((k - reference).abs(), Lane::splat(BLOCK_REFRESH) * reference);
        p.normal_mass = pick(recip_or_zero(k), p.normal_mass);
    }
    let turned = (turned & moved) | forced;
    for i in 0..2 {
        let m = recip_or_zero(w.rows[i].inverse_mass(w.directions[i], ima, imb));
        w.masses[i] = pick(m, w.masses[i]);
    }
    if N > 1 {
        let m = recip_or_zero(w.twist.row.inverse_mass(V3::ZERO, ima, imb));
        w.twist.mass = pick(m, w.twist.mass);
    }
    if turned.any() {
        let mut block = [[Lane::ZERO; N]; N];
        for (i, pi) in w.points.iter().enumerate() {
            for (j, pj) in w.points.iter().enumerate() {
                block[i][j] = pi.normal.dot(pj.normal) * (ima + imb)
                    + pi.row.ra_x_d.dot(pj.row.ia_ra_x_d)
                    + pi.row.rb_x_d.dot(pj.row.ib_rb_x_d);
            }
        }
        let inverse = regularised_inverse(&block);
        if turned.all() {
            w.block = block;
            w.block_inverse = inverse;
        } else {
            for i in 0..N {
                for j in 0..N {
                    w.block[i][j] = select(turned, block[i][j], w.block[i][j]);
                    w.block_inverse[i][j] = select(turned, inverse[i][j], w.block_inverse[i][j]);
                }
            }
        }
    }
    turned
}

/// An `N` x `N` block of the Delassus matrix, or its inverse, per lane.
type Block<const N: usize> = [[Lane; N]; N];

/// `constraint::regularised_cholesky`, lane by lane, on the leading `N`
/// rows (the padding rows beyond them factor apart, as zero rows with the
/// pivot `eps`, and leave the rest alone).
#[allow(clippy::needless_range_loop)] // index form mirrors the scalar version
#[inline(always)]
fn regularised_cholesky<const N: usize>(k: &Block<N>) -> Block<N> {
    let mut largest = Lane::ZERO;
    for i in 0..N {
        largest = largest.max(k[i][i]);
    }
    let eps = Lane::splat(1e-9) * largest + Lane::splat(f64::MIN_POSITIVE);
    let mut l = [[Lane::ZERO; N]; N];
    for j in 0..N {
        let mut diag = k[j][j] + eps;
        for p in 0..j {
            diag -= l[j][p] * l[j][p];
        }
        let pivot = diag.max(eps).sqrt();
        l[j][j] = Lane::ONE / pivot;
        for i in j + 1..N {
            let mut v = k[i][j];
            for p in 0..j {
                v -= l[i][p] * l[j][p];
            }
            l[i][j] = v / pivot;
        }
    }
    l
}

/// `constraint::regularised_inverse`, lane by lane.
#[allow(clippy::needless_range_loop)]
#[inline(always)]
fn regularised_inverse<const N: usize>(k: &Block<N>) -> Block<N> {
    let l = regularised_cholesky(k);
    let mut inv = [[Lane::ZERO; N]; N];
    for j in 0..N {
        // The forward and backward substitutions of `cholesky_solve` on the
        // unit column j.
        let mut y = [Lane::ZERO; N];
        for i in 0..N {
            let mut v = if i == j { Lane::ONE } else { Lane::ZERO };
            for p in 0..i {
                v -= l[i][p] * y[p];
            }
            y[i] = v * l[i][i];
        }
        let mut x = [Lane::ZERO; N];
        for i in (0..N).rev() {
            let mut v = y[i];
            for p in i + 1..N {
                v -= l[p][i] * x[p];
            }
            x[i] = v * l[i][i];
        }
        for i in 0..N {
            inv[i][j] = x[i];
        }
    }
    inv
}

/// `constraint::mat4_mul`, lane by lane: `(r0 x0 + r1 x1) + (r2 x2 + r3 x3)`
/// with the padding's zero terms left out.
#[inline(always)]
fn mat_mul<const N: usize>(m: &Block<N>, x: &[Lane; N]) -> [Lane; N] {
    std::array::from_fn(|i| {
        let r = &m[i];
        match N {
            1 => r[0] * x[0],
            2 => r[0] * x[0] + r[1] * x[1],
            _ => (r[0] * x[0] + r[1] * x[1]) + (r[2] * x[2] + r[3] * x[3]),
        }
    })
}

/// `passes::solve_patch` on four patches: patch friction, then the normal
/// rows as one block.
///
/// # Safety
/// The lanes' dynamic bodies are this thread's alone meanwhile.
pub(super) unsafe fn solve<const N: usize>(w: &mut WidePatch<N>, bodies: &Shared<SolverBody>, inv_h: f64) {
    // SAFETY: the caller's promise.
    let mut vel = unsafe { PairLanes::load(bodies, w) };
    let p = &w.points;
    let total = (1..N).fold(p[0].normal_impulse, |sum, i| sum + p[i].normal_impulse);
    solve_friction(w, total, &mut vel);
    solve_block(w, &mut vel, Lane::splat(inv_h));
    // SAFETY: the caller's promise.
    unsafe { vel.store(bodies, w) };
}

/// `passes::solve_patch_friction`, lane by lane.
#[inline(always)]
fn solve_friction<const N: usize>(w: &mut WidePatch<N>, total: Lane, vel: &mut PairLanes) {
    let limit = w.friction * total;
    let mut t = [w.impulses[0], w.impulses[1]];
    for (i, ti) in t.iter_mut().enumerate() {
        let (d, row) = (w.directions[i], &w.rows[i]);
        let before = *ti;
        *ti = before - w.masses[i] * vel.along(d, row.ra_x_d, row.rb_x_d);
        vel.apply(d, row.ia_ra_x_d, row.ib_rb_x_d, w.inv_mass, *ti - before);
    }
    let len2 = t[0] * t[0] + t[1] * t[1];
    let clamp = gt(len2, limit * limit);
    if clamp.any() {
        let scale = select(gt(len2, Lane::ZERO), limit / len2.sqrt(), Lane::ZERO);
        for (i, ti) in t.iter_mut().enumerate() {
            let clamped = *ti * scale;
            let row = &w.rows[i];
            let change = select(clamp, clamped - *ti, Lane::ZERO);
            vel.apply(w.directions[i], row.ia_ra_x_d, row.ib_rb_x_d, w.inv_mass, change);
            *ti = select(clamp, clamped, *ti);
        }
    }
    w.impulses[0] = t[0];
    w.impulses[1] = t[1];
    if N == 1 {
        return;
    }
    let twist = &mut w.twist;
    let row = &twist.row;
    let twist_limit = limit * twist.radius;
    let before = twist.impulse;
    let spin = row.ra_x_d.dot(vel.wa) - row.rb_x_d.dot(vel.wb);
    let after = (before - twist.mass * spin).max(-twist_limit).min(twist_limit);
    vel.apply_angular(row.ia_ra_x_d, row.ib_rb_x_d, after - before);
    twist.impulse = after;
}

/// `passes::solve_block`, lane by lane: the direct solve with every point
/// pressing, and the block's sweeps in the lanes where that fails.
#[inline(always)]
fn solve_block<const N: usize>(w: &mut WidePatch<N>, vel: &mut PairLanes, inv_h: Lane) {
    let mut b = [Lane::ZERO; N];
    let mut lambda = [Lane::ZERO; N];
    let mut mass = [Lane::ZERO; N];
    for (i, p) in w.points.iter().enumerate() {
        let s = p.separation_now;
        let bias = select(gt(s, Lane::ZERO), s * inv_h, Lane::ZERO);
        b[i] = vel.along(p.normal, p.row.ra_x_d, p.row.rb_x_d) + bias;
        lambda[i] = p.normal_impulse;
        mass[i] = p.normal_mass;
    }
    let (direct, ok) = direct_block(w, &b, &lambda);
    let d = if ok.all() {
        direct
    } else {
        let swept = swept_block(w, &b, &lambda, &mass, !ok);
        std::array::from_fn(|i| select(ok, direct[i], swept[i]))
    };
    for (i, p) in w.points.iter_mut().enumerate() {
        let new_impulse = lambda[i] + d[i];
        p.normal_impulse = new_impulse;
        p.max_normal_impulse = p.max_normal_impulse.max(new_impulse);
        vel.apply(p.normal, p.row.ia_ra_x_d, p.row.ib_rb_x_d, w.inv_mass, d[i]);
    }
}

/// `passes::direct_block`, lane by lane: the answer, and the lanes where it
/// stands.
#[inline(always)]
fn direct_block<const N: usize>(w: &WidePatch<N>, b: &[Lane; N], lambda: &[Lane; N]) -> ([Lane; N], Lane) {
    let residual = |d: &[Lane; N]| {
        let kd = mat_mul(&w.block, d);
        std::array::from_fn::<Lane, N, _>(|i| b[i] + kd[i])
    };
    let mut d = mat_mul(&w.block_inverse, &b.map(|x| -x));
    let fix = mat_mul(&w.block_inverse, &residual(&d).map(|x| -x));
    for i in 0..N {
        d[i] += fix[i];
    }
    let largest = b.iter().fold(Lane::ZERO, |x, &y| x.max(y.abs()));
    let tolerance = Lane::splat(1e-9) * (Lane::ONE + largest);
    let r = residual(&d);
    let mut fails = Lane::ZERO;
    for i in 0..N {
        fails |= lt(lambda[i] + d[i], Lane::ZERO) | lt(r[i], -tolerance);
    }
    (d, !fails)
}

/// `passes::swept_block`, lane by lane, in the lanes of `active`: a lane
/// stops sweeping where the scalar loop would break.
#[inline(always)]
fn swept_block<const N: usize>(
    w: &WidePatch<N>,
    b: &[Lane; N],
    lambda: &[Lane; N],
    mass: &[Lane; N],
    mut active: Lane,
) -> [Lane; N] {
    let mut d = [Lane::ZERO; N];
    let largest = lambda.iter().fold(Lane::ZERO, |x, &y| x.max(y));
    let scale = Lane::splat(1e-9) * (Lane::ONE + largest);
    // One row of a sweep; the two orders are spelled out so that every
    // index is a constant and `d` stays in registers. (The scalar sweep also
    // visits the padding rows, which change nothing.) The maximum against
    // zero is the machine's bare `max` (`fast_max`: the second operand
    // where the two are equal or either is NaN), which gives `f64::max`'s
    // bits against zero, never NaN, without `Lane::max`'s NaN test and
    // blend: the pyramid's velocity passes 3-5 % faster (a third of its face
    // bundles' solves fall back to these sweeps, seven sweeps each).
    let row = |i: usize, d: &mut [Lane; N], change: &mut Lane, active: Lane| {
        let k = &w.block[i];
        let r = (0..N).fold(b[i], |r, j| r + k[j] * d[j]);
        let new = (lambda[i] + d[i] - mass[i] * r).fast_max(Lane::ZERO) - lambda[i];
        *change = change.max((new - d[i]).abs());
        d[i] = select(active, new, d[i]);
    };
    for sweep in 0..super::passes::BLOCK_SWEEPS {
        let mut change = Lane::ZERO;
        if sweep % 2 == 0 {
            for i in 0..N {
                row(i, &mut d, &mut change, active);
            }
        } else {
            for i in (0..N).rev() {
                row(i, &mut d, &mut change, active);
            }
        }
        active &= !le(change, scale);
        if !active.any() {
            break;
        }
    }
    d
}

/// `passes::push_patch` on four patches (its `push_block`, lane by lane:
/// directly where the patch is flat and every point takes part, else point
/// after point; then with `hold` its `hold_anchor`); whether any lane pushed.
///
/// # Safety
/// The lanes' dynamic bodies are this thread's alone meanwhile.
pub(super) unsafe fn push<const N: usize>(
    w: &mut WidePatch<N>,
    bodies: &Shared<SolverBody>,
    params: &SolverParams,
    inv_h: f64,
    hold: bool,
) -> bool {
    let allowed = Lane::splat(params.allowed_penetration);
    // `passes::push_target`: a real point takes part where it overlaps
    // beyond the allowance or has pushed in this sub-step.
    let mut taking_part = [Lane::ZERO; N];
    let mut pushing = Lane::ZERO;
    for ((t, p), f) in taking_part.iter_mut().zip(&w.points).zip(&w.frames) {
        let excess = p.separation_now + allowed;
        *t = f.real & !(le(Lane::ZERO, excess) & eq(f.push_impulse, Lane::ZERO));
        pushing |= *t;
    }
    let holding = hold && w.anchored.any();
    if !pushing.any() && !holding {
        return false;
    }
    // SAFETY: the caller's promise.
    let (a, b) = unsafe { lane_bodies(bodies, w) };
    let mut vel = PairLanes {
        va: V3::from_lanes(a.map(|b| b.push_v)),
        wa: V3::from_lanes(a.map(|b| b.push_w)),
        vb: V3::from_lanes(b.map(|b| b.push_v)),
        wb: V3::from_lanes(b.map(|b| b.push_w)),
    };
    if pushing.any() {
        push_rows(w, &mut vel, params, inv_h, &taking_part, pushing);
    }
    if holding {
        hold_anchor(w, (&a, &b), &mut vel, inv_h);
    }
    // SAFETY: the caller's promise.
    unsafe {
        scatter(bodies, w, [vel.va, vel.wa, vel.vb, vel.wb], |body, v, omega| {
            body.push_v = v;
            body.push_w = omega;
        })
    };
    pushing.any()
}

/// The push-out rows of [`push`]: `passes::push_block` where it applies,
/// else `passes::push_points`, in the lanes where a point takes part.
#[inline(always)]
fn push_rows<const N: usize>(
    w: &mut WidePatch<N>,
    vel: &mut PairLanes,
    params: &SolverParams,
    inv_h: f64,
    taking_part: &[Lane; N],
    pushing: Lane,
) {
    let allowed = Lane::splat(params.allowed_penetration);
    let (fraction, max_speed, inv_h) = (
        Lane::splat(-params.push_out_fraction),
        Lane::splat(params.max_push_out_speed),
        Lane::splat(inv_h),
    );
    let target = |p: &WidePoint| {
        let excess = p.separation_now + allowed;
        select(
            lt(excess, Lane::ZERO),
            (fraction * excess * inv_h).min(max_speed),
            Lane::ZERO,
        )
    };
    let mut b = [Lane::ZERO; N];
    let mut lambda = [Lane::ZERO; N];
    // Lanes where every real point takes part (and lanes without a patch,
    // whose padding takes none: all their rows are zero).
    let mut all = lanes::mask([true; LANES]);
    for (i, (p, f)) in w.points.iter().zip(&w.frames).enumerate() {
        lambda[i] = f.push_impulse;
        b[i] = select(
            taking_part[i],
            vel.along(p.normal, p.row.ra_x_d, p.row.rb_x_d) - target(p),
            Lane::ZERO,
        );
        all &= (taking_part[i] & p.normal.eq_mask(&w.points[0].normal)) | !f.real;
    }
    let (direct, ok) = direct_block(w, &b, &lambda);
    let ok = ok & all & pushing;
    if ok.any() {
        let mut solved = *vel;
        for (i, (p, f)) in w.points.iter().zip(&mut w.frames).enumerate() {
            f.push_impulse = select(ok, lambda[i] + direct[i], f.push_impulse);
            solved.apply(p.normal, p.row.ia_ra_x_d, p.row.ib_rb_x_d, w.inv_mass, direct[i]);
        }
        *vel = PairLanes::select(ok, &solved, vel);
    }
    // The other lanes point after another (`passes::push_points`).
    if !ok.all() {
        for (i, (p, f)) in w.points.iter().zip(&mut w.frames).enumerate() {
            let act = taking_part[i] & !ok;
            if !act.any() {
                continue;
            }
            let vn = vel.along(p.normal, p.row.ra_x_d, p.row.rb_x_d);
            // `fast_max` against zero, never NaN: `f64::max`'s bits (see
            // `swept_block`).
            let new_impulse = (f.push_impulse + p.normal_mass * (target(p) - vn)).fast_max(Lane::ZERO);
            let applied = select(act, new_impulse - f.push_impulse, Lane::ZERO);
            f.push_impulse = select(act, new_impulse, f.push_impulse);
            vel.apply(p.normal, p.row.ia_ra_x_d, p.row.ib_rb_x_d, w.inv_mass, applied);
        }
    }
}

/// `passes::hold_anchor` in the lanes whose patch holds an anchor and has
/// friction left.
#[inline(always)]
fn hold_anchor<const N: usize>(
    w: &WidePatch<N>,
    (a, b): (&[&SolverBody; LANES], &[&SolverBody; LANES]),
    vel: &mut PairLanes,
    inv_h: f64,
) {
    let mut total = Lane::ZERO;
    for p in &w.points {
        total += p.normal_impulse;
    }
    let used = (w.impulses[0] * w.impulses[0] + w.impulses[1] * w.impulses[1]).sqrt();
    let budget = w.friction * total - used;
    let act = w.anchored & lt(Lane::ZERO, budget);
    if !act.any() {
        return;
    }
    let (dpa, dpb) = (V3::from_lanes(a.map(|b| b.dp)), V3::from_lanes(b.map(|b| b.dp)));
    let (ta, tb) = (
        M3::from_lanes(a.map(|b| b.turn)),
        M3::from_lanes(b.map(|b| b.turn)),
    );
    let (ra, rb) = (w.anchor_ra, w.anchor_rb);
    let offset = w.anchor_offset + ((dpa + ta.mul_vec(ra)) - ra) - ((dpb + tb.mul_vec(rb)) - rb);
    let gain = Lane::splat(-super::passes::HOLD_FRACTION * inv_h);
    let mut lambda = [Lane::ZERO; 2];
    for (i, l) in lambda.iter_mut().enumerate() {
        let (d, row) = (w.directions[i], &w.rows[i]);
        *l = w.masses[i] * (gain * offset.dot(d) - vel.along(d, row.ra_x_d, row.rb_x_d));
    }
    let len = (lambda[0] * lambda[0] + lambda[1] * lambda[1]).sqrt();
    let over = lt(budget, len);
    let scale = budget / len;
    lambda = lambda.map(|l| select(over, l * scale, l));
    let mut held = *vel;
    for (i, &l) in lambda.iter().enumerate() {
        let row = &w.rows[i];
        held.apply(w.directions[i], row.ia_ra_x_d, row.ib_rb_x_d, w.inv_mass, l);
    }
    *vel = PairLanes::select(act, &held, vel);
}

/// `passes::residual` over a bundle's real points: the largest violation
/// of the non-penetration rows by the current velocities (m/s).
pub(super) fn residual<const N: usize>(w: &WidePatch<N>, bodies: &[SolverBody], inv_h: f64) -> f64 {
    let a: [&SolverBody; LANES] = std::array::from_fn(|l| &bodies[w.a[l] as usize]);
    let b: [&SolverBody; LANES] = std::array::from_fn(|l| &bodies[w.b[l] as usize]);
    let vel = PairLanes {
        va: V3::from_lanes(a.map(|b| b.v)),
        wa: V3::from_lanes(a.map(|b| b.w)),
        vb: V3::from_lanes(b.map(|b| b.v)),
        wb: V3::from_lanes(b.map(|b| b.w)),
    };
    let mut worst: f64 = 0.0;
    for (p, f) in w.points.iter().zip(&w.frames) {
        let s = p.separation_now;
        let bias = select(gt(s, Lane::ZERO), s * Lane::splat(inv_h), Lane::ZERO);
        let r = vel.along(p.normal, p.row.ra_x_d, p.row.rb_x_d) + bias;
        let violation = select(f.real, -r, Lane::ZERO).to_array();
        worst = violation.iter().fold(worst, |x, &y| x.max(y));
    }
    worst
}

/// One of the sub-step's passes, as run over bundles.
#[derive(Clone, Copy)]
pub(crate) enum BundlePass<'a> {
    /// [`begin`]: separations, re-aimed rows, and with `warm` the warm start.
    Begin {
        /// Apply the accumulated impulses.
        warm: bool,
    },
    /// [`solve`]: one velocity pass.
    Solve {
        /// `1 / h`.
        inv_h: f64,
    },
    /// [`push`]: one push-out pass.
    Push {
        /// The solver's settings.
        params: &'a SolverParams,
        /// `1 / h`.
        inv_h: f64,
        /// Hold the anchors of sticking patches (the sub-step's first pass).
        hold: bool,
    },
    /// [`solve`], then [`push`] as the sub-step's first push-out pass
    /// (`batches::VelocityPass::then_push`).
    SolveThenPush {
        /// The solver's settings.
        params: &'a SolverParams,
        /// `1 / h`.
        inv_h: f64,
    },
}

impl BundlePass<'_> {
    /// Runs this pass on bundle `w`; whether it pushed (push-out only).
    ///
    /// # Safety
    /// The lanes' dynamic bodies are this thread's alone meanwhile.
    #[inline(always)]
    pub unsafe fn run<const N: usize>(&self, w: &mut WidePatch<N>, bodies: &Shared<SolverBody>) -> bool {
        // SAFETY: the caller's promise.
        unsafe {
            match *self {
                BundlePass::Begin { warm } => {
                    begin(w, bodies, warm);
                    false
                }
                BundlePass::Solve { inv_h } => {
                    solve(w, bodies, inv_h);
                    false
                }
                BundlePass::Push { params, inv_h, hold } => push(w, bodies, params, inv_h, hold),
                BundlePass::SolveThenPush { params, inv_h } => {
                    solve(w, bodies, inv_h);
                    push(w, bodies, params, inv_h, true)
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    //! The wide kernels against the scalar ones: the same sub-steps over the
    //! same coloured patches give the same bits, on any thread count.
    use super::super::constraint::BLOCK_POINTS;
    use super::super::solved::{SolvedPatch, SolvedPatches, SolvedPoint};
    use super::super::{
        begin_substep, color_patches, integrate_positions, prepare, push_out, solve, SolverArrays,
        VelocityPass,
    };
    use super::*;
    use crate::pool::WorkerPool;
    use std::sync::atomic::AtomicUsize;
    use tumble_collide::{DMat3, DQuat};
    use tumble_testkit::{RandomSource, SplitMix64};

    /// Bodies, the patches' body pairs, patches and points, in colour order.
    type Problem = (
        Vec<SolverBody>,
        Vec<(u32, u32)>,
        Vec<ManifoldConstraint>,
        Vec<PointConstraint>,
    );

    /// Bodies (0 static, a few kinematic, the rest dynamic with unequal
    /// inertia, moving and spinning) and ~400 patches of one to six points
    /// between random pairs, with gaps and overlaps, friction, warm starts.
    fn problem(seed: u64) -> Problem {
        problem_with(seed, 400, false).0
    }

    /// [`problem`] with `tries` patches tried, the records in colour order
    /// or (`in_patch_order`) in the patches' own order; with the colour
    /// order (patch indices in the records' order).
    fn problem_with(seed: u64, tries: usize, in_patch_order: bool) -> (Problem, Vec<u32>) {
        let mut rng = SplitMix64(seed);
        let n = 120;
        let mut bodies = vec![SolverBody::fixed()];
        for i in 1..n {
            let inv_i = DVec3::new(rng.range(0.5, 4.0), rng.range(0.5, 4.0), rng.range(0.5, 4.0));
            // A quarter spin fast: their rows turn far enough within the
            // step for the blocks to be rebuilt.
            let spin = if i % 4 == 0 { 80.0 } else { 2.0 };
            let mut b = SolverBody::new(
                rng.vec3(1.0),
                rng.vec3(spin),
                rng.range(0.2, 3.0),
                inv_i,
                rng.rotation(),
            );
            if i % 17 == 0 {
                b = SolverBody::new(rng.vec3(1.0), rng.vec3(1.0), 0.0, DVec3::ZERO, rng.rotation());
                b.kinematic = true;
            }
            bodies.push(b);
        }
        let mut pairs = Vec::new();
        let mut patches = Vec::new();
        for _ in 0..tries {
            let a = 1 + rng.below(n - 1) as u32;
            let b = if rng.next_f64() < 0.3 {
                0
            } else {
                1 + rng.below(n - 1) as u32
            };
            // The world pairs a dynamic body with anything (two bodies the
            // solver never moves make no patch).
            if a == b || !(bodies[a as usize].dynamic || bodies[b as usize].dynamic) {
                continue;
            }
            pairs.push((a, b));
            patches.push(rng.next_u64());
        }
        let (coloring, order) = color_patches(&pairs, &bodies);
        assert!(coloring.colors.len() > 3, "the test needs colours");
        let layout: Vec<u32> = if in_patch_order {
            (0..pairs.len() as u32).collect()
        } else {
            order.clone()
        };
        let (mut manifolds, mut points) = (Vec::new(), Vec::new());
        for &k in &layout {
            let mut rng = SplitMix64(patches[k as usize]);
            // Normals mostly up, against the pull of `pull`: most points press.
            let normal = (rng.vec3(0.6) + DVec3::Z).normalize();
            let count = 1 + rng.below(6) as u32;
            let first = points.len() as u32;
            for _ in 0..count {
                let (ra, rb) = (rng.vec3(0.6), rng.vec3(0.6));
                let warm = if rng.next_f64() < 0.5 {
                    rng.range(0.0, 0.3)
                } else {
                    0.0
                };
                points.push(PointConstraint::new(normal, ra, rb, rng.range(-0.03, 0.02), warm));
            }
            let (a, b) = pairs[k as usize];
            let (mu, tangent) = (rng.range(0.0, 0.6), rng.vec3(0.1));
            // Most lone points start without a twist (bundled), some with
            // one carried over from a larger patch (scalar kernels).
            let twist = rng.range(-0.01, 0.01);
            let twist = if count > 1 || rng.next_f64() < 0.3 {
                twist
            } else {
                0.0
            };
            // Every third patch bounces (restitution before the sub-steps:
            // `bounce`), bundled with others that do not.
            let restitution = if k % 3 == 0 { 0.4 } else { 0.0 };
            let mut m = ManifoldConstraint::new(a, b, first, count, normal, mu, restitution, tangent, twist);
            // Round sides (re-aimed by the scalar `Rolling` in the lanes)
            // and curved patches (scalar kernels only) among the others.
            let radius = rng.range(0.05, 0.5);
            match rng.below(8) {
                0 => m.rolling = [radius, 0.0],
                1 => m.rolling = [0.0, radius],
                2 => m.rolling = [radius, 0.5 * radius],
                3 => {
                    m.rolling = [radius, 0.0];
                    let across = DMat3::IDENTITY
                        - DMat3::from_cols(normal * normal.x, normal * normal.y, normal * normal.z);
                    m.curvature = across * (-1.0 / (3.0 * radius));
                }
                // Most of the others stuck last step and hold an anchor.
                4..=6 => {
                    m.anchored = true;
                    m.anchor_r = [rng.vec3(0.6), rng.vec3(0.6)];
                    m.anchor_offset = rng.vec3(0.002);
                }
                _ => {}
            }
            prepare(&mut m, &mut points, &bodies);
            manifolds.push(m);
        }
        let sorted_pairs = layout.iter().map(|&k| pairs[k as usize]).collect();
        ((bodies, sorted_pairs, manifolds, points), order)
    }

    fn params() -> SolverParams {
        SolverParams {
            push_out_fraction: 0.2,
            allowed_penetration: 0.0005,
            max_push_out_speed: 3.0,
            restitution_threshold: 0.5,
        }
    }

    const SUBSTEPS: usize = 4;
    const H: f64 = 1.0 / 240.0;

    /// Gravity on the dynamic bodies for one sub-step.
    fn pull(bodies: &mut [SolverBody]) {
        for b in bodies.iter_mut().filter(|b| b.dynamic) {
            b.v.z -= 9.81 * H;
        }
    }

    /// Restitution on the prepared patches, as the step applies it
    /// between preparing the records and the sub-steps.
    fn bounce(manifolds: &[ManifoldConstraint], points: &mut [PointConstraint], bodies: &mut [SolverBody]) {
        let accel = vec![DVec3::new(0.0, 0.0, -9.81); bodies.len()];
        let dt = H * SUBSTEPS as f64;
        super::super::resolve_collisions(manifolds, points, bodies, &accel, &params(), dt, H);
    }

    /// The reference: restitution, then the scalar whole-array passes in
    /// colour order.
    fn scalar(
        bodies: &mut [SolverBody],
        manifolds: &mut [ManifoldConstraint],
        points: &mut [PointConstraint],
    ) {
        bounce(manifolds, points, bodies);
        let q0: Vec<DQuat> = bodies.iter().map(|b| b.q).collect();
        for _ in 0..SUBSTEPS {
            pull(bodies);
            begin_substep(manifolds, points, bodies, true);
            for _ in 0..2 {
                solve(manifolds, points, bodies, H);
            }
            push_out(manifolds, points, bodies, &params(), H, true);
            integrate_positions(bodies, &q0, H);
        }
    }

    /// Records the tests built, given again as they were built.
    struct KeptRecords(Vec<ManifoldConstraint>, Vec<PointConstraint>);

    impl super::super::batches::RecordSource for KeptRecords {
        fn points(&self, k: usize) -> std::ops::Range<usize> {
            self.0[k].range()
        }

        fn restitution(&self, k: usize) -> f64 {
            self.0[k].restitution
        }

        fn renew(&self, k: usize, m: &mut ManifoldConstraint, points: &mut [PointConstraint]) {
            *m = self.0[k];
            points.copy_from_slice(&self.1[m.range()]);
        }
    }

    /// The same passes by a team of `threads`, bundled; with `fused`, the
    /// push-out pass made with the last velocity pass, as the step makes it
    /// (`VelocityPass::then_push`).
    fn bundled(
        fused: bool,
        threads: u32,
        bodies: &mut [SolverBody],
        pairs: &[(u32, u32)],
        manifolds: &mut [ManifoldConstraint],
        points: &mut [PointConstraint],
    ) -> (WideBatches, SolvedPatches) {
        let (coloring, order) = color_patches(pairs, bodies);
        assert!(
            order.iter().enumerate().all(|(i, &k)| i == k as usize),
            "already in colour order"
        );
        let q0: Vec<DQuat> = bodies.iter().map(|b| b.q).collect();
        let mut wide = WideBatches::default();
        let kinds: Vec<BundleKind> = manifolds.iter().map(BundleKind::of).collect();
        let keys: Vec<u32> = pairs
            .iter()
            .map(|&(a, b)| if bodies[a as usize].dynamic { a } else { b })
            .collect();
        wide.plan(&coloring, &kinds, &keys, bodies.len());
        let (mut ones, mut twos, mut fours) = (
            std::mem::take(&mut wide.ones),
            std::mem::take(&mut wide.twos),
            std::mem::take(&mut wide.fours),
        );
        let empty = super::super::Coloring::default();
        let mut flows: Vec<super::super::batches::ThreadFlow> =
            (0..threads).map(|_| Default::default()).collect();
        let owners: Vec<std::sync::atomic::AtomicU32> = (0..bodies.len())
            .map(|_| std::sync::atomic::AtomicU32::new(0))
            .collect();
        let mut solved = SolvedPatches::default();
        solved.resize(manifolds.len(), points.len());
        // The records as built are what the team writes them from; the
        // arrays start with stale ones (last step's, here out of range and
        // bouncing), which it must write over or mark empty before
        // restitution looks at every record.
        let records = KeptRecords(manifolds.to_vec(), points.to_vec());
        for m in manifolds.iter_mut() {
            m.first_point = u32::MAX / 2;
            m.restitution = 0.7;
        }
        let arrays = SolverArrays {
            manifolds: Shared::new(manifolds),
            points: Shared::new(points),
            bodies: Shared::new(bodies),
            joints: Shared::new(&mut []),
            joint_islands: Shared::new(&mut []),
            ones: Shared::new(&mut ones),
            twos: Shared::new(&mut twos),
            fours: Shared::new(&mut fours),
            wide: &wide,
            coloring: &coloring,
            joint_coloring: &empty,
            gears: Shared::new(&mut []),
            loose_gears: false,
            flows: Shared::new(&mut flows),
            owners: &owners,
            solved: solved.writer(),
        };
        let pushed = AtomicUsize::new(0);
        WorkerPool::new(threads).team(|team| {
            // SAFETY: the whole team runs it. (The patches are prepared
            // again, from the same bodies: the same values.)
            unsafe {
                arrays.prepare(team, &records, |arrays| {
                    // SAFETY: thread 0 alone, between two barriers.
                    bounce(
                        arrays.manifolds.as_slice(),
                        arrays.points.range_mut(0..arrays.points.len()),
                        arrays.bodies.range_mut(0..arrays.bodies.len()),
                    )
                })
            };
            for sub in 0..SUBSTEPS {
                if team.index() == 0 {
                    // SAFETY: the others wait at the barrier below.
                    pull(unsafe { arrays.bodies.range_mut(0..arrays.bodies.len()) });
                }
                team.barrier();
                // SAFETY: the whole team runs the same passes.
                unsafe {
                    arrays.begin_substep(team, H, true);
                    let params = params();
                    for k in 0..2 {
                        let visit = VelocityPass {
                            begin_islands: (k == 0).then_some(true),
                            then_push: (fused && k == 1).then_some((&params, sub + 1, &pushed)),
                        };
                        arrays.solve(team, H, visit);
                    }
                    if !fused {
                        arrays.push_out(team, &params, H, sub + 1, true, &pushed);
                    }
                }
                if team.index() == 0 {
                    // SAFETY: the others wait at the barrier below.
                    let bodies = unsafe { arrays.bodies.range_mut(0..arrays.bodies.len()) };
                    integrate_positions(bodies, &q0, H);
                }
                team.barrier();
            }
            // SAFETY: as above.
            unsafe { arrays.unpack(team) };
        });
        (wide.ones, wide.twos, wide.fours) = (ones, twos, fours);
        // A bundled patch that does not bounce has no record this step
        // (marked empty); the one built stands for it, its bundle's state
        // written over it below.
        for (k, m) in manifolds.iter_mut().enumerate() {
            if wide.in_bundle[k] && records.0[k].restitution == 0.0 {
                assert_eq!(
                    (m.point_count, m.restitution),
                    (0, 0.0),
                    "record {k} not marked empty"
                );
                *m = records.0[k];
            }
        }
        wide.ones.iter().for_each(|w| unpack_rows(w, manifolds, points));
        wide.twos.iter().for_each(|w| unpack_rows(w, manifolds, points));
        wide.fours.iter().for_each(|w| unpack_rows(w, manifolds, points));
        (wide, solved)
    }

    /// What the team kept of each record at the end of the solve
    /// (`SolverArrays::unpack`: a bundle's patches from its lanes, the
    /// others from their records) is what the scalar reference's records
    /// give, patch `order[k]` of the reference being record `k` (the levels
    /// reorder), every record and point: the same bits.
    fn solved_as_the_reference(
        solved: &SolvedPatches,
        manifolds: &[ManifoldConstraint],
        reference: (&[ManifoldConstraint], &[PointConstraint]),
        order: &[u32],
        seed: u64,
        threads: u32,
    ) {
        for (k, m) in manifolds.iter().enumerate() {
            let r = &reference.0[order[k] as usize];
            let points = &reference.1[r.range()];
            let ours = solved.patch(k as u32);
            assert_eq!(
                ours.first, m.first_point,
                "patch {k} (seed {seed}, {threads} threads)"
            );
            let expected = SolvedPatch {
                first: m.first_point,
                ..SolvedPatch::of(r, points)
            };
            assert_eq!(
                *ours, expected,
                "solved patch {k} (seed {seed}, {threads} threads)"
            );
            let expected: Vec<SolvedPoint> = points.iter().map(SolvedPoint::of).collect();
            assert_eq!(
                solved.points_of(ours, m.point_count),
                &expected[..],
                "solved points of patch {k} (seed {seed}, {threads} threads)"
            );
        }
    }

    /// The rest of a bundle's state written to its records (impulses, rows,
    /// masses, blocks, separations, push impulses), so that every field can
    /// be compared with the scalar kernels'.
    fn unpack_rows<const N: usize>(
        w: &WidePatch<N>,
        manifolds: &mut [ManifoldConstraint],
        points: &mut [PointConstraint],
    ) {
        for l in (0..LANES).filter(|&l| w.source[l] != EMPTY) {
            let m = &mut manifolds[w.source[l] as usize];
            for r in 0..2 {
                m.impulses[r] = get(w.impulses[r], l);
                m.rows[r] = get_row(&w.rows[r], l);
                m.masses[r] = get(w.masses[r], l);
            }
            if N > 1 {
                m.impulses[2] = get(w.twist.impulse, l);
                m.rows[2] = get_row(&w.twist.row, l);
                m.masses[2] = get(w.twist.mass, l);
            }
            for i in 0..N {
                for j in 0..N {
                    m.block[i][j] = get(w.block[i][j], l);
                    m.block_inverse[i][j] = get(w.block_inverse[i][j], l);
                }
            }
            for ((wp, f), p) in w.points.iter().zip(&w.frames).zip(&mut points[m.range()]) {
                p.normal_impulse = get(wp.normal_impulse, l);
                p.max_normal_impulse = get(wp.max_normal_impulse, l);
                p.row = get_row(&wp.row, l);
                p.separation_now = get(wp.separation_now, l);
                p.normal_mass = get(wp.normal_mass, l);
                p.push_impulse = get(f.push_impulse, l);
            }
        }
    }

    /// The block inverse's entries beyond a patch's points: the scalar
    /// kernel keeps a 4 x 4 inverse whose padding diagonal (`1 / eps`)
    /// follows the block's scale, where a bundle of `N` points keeps `N x
    /// N`; no kernel reads those entries (they meet zero rows), so they are
    /// set aside before comparing. So is a lone point's twist row and its
    /// mass, which a bundle of lone points leaves out (its impulse stays
    /// zero either way: compared with `==`, whatever its sign).
    fn inert_padding(mut m: Vec<ManifoldConstraint>) -> Vec<ManifoldConstraint> {
        for m in &mut m {
            if m.point_count <= 1 {
                m.rows[2] = Default::default();
                m.masses[2] = 0.0;
            }
            let n = m.point_count as usize;
            for i in 0..BLOCK_POINTS {
                for j in 0..BLOCK_POINTS {
                    if i >= n || j >= n {
                        m.block_inverse[i][j] = 0.0;
                    }
                }
            }
        }
        m
    }

    fn first_difference<T: PartialEq + std::fmt::Debug>(
        a: &[T],
        b: &[T],
        what: &str,
        seed: u64,
        threads: u32,
    ) {
        assert_eq!(a.len(), b.len());
        if let Some(i) = (0..a.len()).find(|&i| a[i] != b[i]) {
            panic!(
                "{what} {i} differs (seed {seed}, {threads} threads):\n wide   {:?}\n scalar {:?}",
                a[i], b[i]
            );
        }
    }

    /// A team's runs of bodies cover every body once, in order, and cut
    /// the colours' patch work near-evenly: each run's work is within one
    /// body's work of its share, also where the work piles up on the first
    /// bodies (the bottom of a pile).
    #[test]
    fn body_runs_cover_the_bodies_and_share_the_patch_work_evenly() {
        let n = 300;
        let kinds_cycle = [
            BundleKind::Ones,
            BundleKind::Twos,
            BundleKind::Fours,
            BundleKind::Large,
        ];
        let (mut keys, mut kinds) = (Vec::new(), Vec::new());
        let mut work = vec![0u64; n];
        for b in 0..n {
            for p in 0..if b < 60 { 6 } else { 1 } {
                let kind = kinds_cycle[(b + p) % 4];
                keys.push(b as u32);
                kinds.push(kind);
                // A patch's share of its bundle's work, a large patch's whole.
                work[b] += match kind {
                    BundleKind::Ones => 4,
                    BundleKind::Twos => 6,
                    BundleKind::Fours => 11,
                    BundleKind::Large => 20,
                };
            }
        }
        let patches = keys.len();
        // Two colours, the patches dealt alternately (a colour's order is
        // the patch order, whatever the keys).
        let coloring = Coloring {
            colors: vec![0..patches / 2, patches / 2..patches],
            overflow: patches..patches,
            levels: false,
        };
        let mut wide = WideBatches::default();
        wide.plan(&coloring, &kinds, &keys, n);
        let total: u64 = work.iter().sum();
        let heaviest = *work.iter().max().unwrap();
        for size in 1..=5 {
            let mut next = 0;
            for index in 0..size {
                let run = wide.body_run(index, size);
                assert_eq!(run.start, next, "{size} threads: contiguous");
                next = run.end;
                let mine: u64 = work[run.clone()].iter().sum();
                let share = total / size as u64;
                assert!(
                    mine.abs_diff(share) <= heaviest,
                    "{size} threads, run {index} {run:?}: work {mine} against a share of {share}"
                );
            }
            assert_eq!(next, n, "{size} threads: every body");
        }
    }

    /// Also with the push-out pass made together with the last velocity
    /// pass, patch by patch, as the step makes it: the push-out reads and
    /// writes only pseudo-velocities, separations and push impulses, which
    /// the velocity passes never touch, so the bits are those of the two
    /// passes one after the other (the scalar reference's).
    #[test]
    fn bundles_give_the_scalar_kernels_bits_on_any_thread_count() {
        // Bundles whose every lane rolls (re-aimed without the plain
        // anchors) must be among them.
        let mut all_rolling = 0;
        for (seed, fused) in (1..4).flat_map(|seed| [(seed, false), (seed, true)]) {
            let (bodies, pairs, manifolds, points) = problem(seed);
            let (mut b0, mut m0, mut p0) = (bodies.clone(), manifolds.clone(), points.clone());
            scalar(&mut b0, &mut m0, &mut p0);
            for threads in [1, 2, 3] {
                let (mut b1, mut m1, mut p1) = (bodies.clone(), manifolds.clone(), points.clone());
                let (wide, solved) = bundled(fused, threads, &mut b1, &pairs, &mut m1, &mut p1);
                let order: Vec<u32> = (0..m1.len() as u32).collect();
                solved_as_the_reference(&solved, &m1, (&m0, &p0), &order, seed, threads);
                // Colours heavy enough to split: more than one thread
                // runs them in flows (`batches::ThreadFlow`).
                assert!(
                    wide.split > 1,
                    "heavy colours: {} of {}",
                    wide.split,
                    wide.colors.len()
                );
                let sizes = [
                    wide.ones.len(),
                    wide.twos.len(),
                    wide.fours.len(),
                    wide.large.len(),
                ];
                assert!(
                    sizes.iter().all(|&n| n > 0),
                    "every kind of bundle and large patches: {sizes:?}"
                );
                let twisting_lone_point = |&k: &u32| {
                    let m = &manifolds[k as usize];
                    m.point_count == 1 && m.impulses[2] != 0.0
                };
                assert!(
                    wide.large.iter().any(twisting_lone_point),
                    "a lone point with a twist, on the scalar kernels"
                );
                // Bundles whose lanes bounce and do not (filled from the
                // records restitution wrote, and from records written
                // afresh).
                let bounces = |k: u32| k != EMPTY && manifolds[k as usize].restitution != 0.0;
                let mixed = |source: &[u32; LANES]| {
                    source.iter().any(|&k| bounces(k)) && source.iter().any(|&k| k != EMPTY && !bounces(k))
                };
                assert!(
                    wide.fours.iter().any(|w| mixed(&w.source)) && wide.ones.iter().any(|w| mixed(&w.source)),
                    "bundles of patches that bounce and that do not"
                );
                all_rolling += wide.ones.iter().filter(|w| w.roll.mask.all()).count()
                    + wide.twos.iter().filter(|w| w.roll.mask.all()).count()
                    + wide.fours.iter().filter(|w| w.roll.mask.all()).count();
                first_difference(&b1, &b0, "body", seed, threads);
                first_difference(
                    &inert_padding(m1),
                    &inert_padding(m0.clone()),
                    "patch",
                    seed,
                    threads,
                );
                first_difference(&p1, &p0, "point", seed, threads);
            }
        }
        assert!(all_rolling > 0, "no bundle whose every lane rolls");
    }

    /// A small problem (under `MIN_PATCHES_TO_COLOR` patches) keeps its
    /// patch order, cut into levels whose small patches go into bundles:
    /// on any thread count, the bodies and every patch's impulses come out
    /// as the scalar kernels leave them in one serial pass in patch order.
    #[test]
    fn a_small_problem_in_levels_gives_the_serial_patch_orders_bits() {
        for seed in 1..4 {
            let ((bodies, pairs, manifolds, points), _) = problem_with(seed, 90, true);
            assert!(pairs.len() < super::super::coloring::MIN_PATCHES_TO_COLOR);
            let (mut b0, mut m0, mut p0) = (bodies.clone(), manifolds, points);
            scalar(&mut b0, &mut m0, &mut p0);
            let ((_, pairs, manifolds, points), order) = problem_with(seed, 90, false);
            let (coloring, _) = color_patches(&pairs, &bodies);
            assert!(
                coloring.levels && coloring.colors.len() > 2,
                "levels: {coloring:?}"
            );
            assert!(
                order.iter().enumerate().any(|(i, &k)| i != k as usize),
                "levels reorder"
            );
            for threads in [1, 2, 3] {
                let (mut b1, mut m1, mut p1) = (bodies.clone(), manifolds.clone(), points.clone());
                let (wide, solved) = bundled(false, threads, &mut b1, &pairs, &mut m1, &mut p1);
                solved_as_the_reference(&solved, &m1, (&m0, &p0), &order, seed, threads);
                assert!(!wide.ones.is_empty() || !wide.twos.is_empty() || !wide.fours.is_empty());
                first_difference(&b1, &b0, "body", seed, threads);
                // Patch k of the levels is patch order[k] of the patch order.
                for (k, &original) in order.iter().enumerate() {
                    let (m, r) = (&m1[k], &m0[original as usize]);
                    assert_eq!(
                        m.impulses, r.impulses,
                        "patch {original} (seed {seed}, {threads} threads)"
                    );
                    let (ours, theirs) = (&p1[m.range()], &p0[r.range()]);
                    for (x, y) in ours.iter().zip(theirs) {
                        assert_eq!(
                            (x.normal_impulse, x.push_impulse),
                            (y.normal_impulse, y.push_impulse),
                            "a point of patch {original} (seed {seed}, {threads} threads)"
                        );
                    }
                }
            }
        }
    }

    /// The test above must reach the lanes' divergent paths: corners that
    /// lift (block sweeps), friction on the rim of its cone, pushes, and
    /// blocks rebuilt after a turn.
    #[test]
    fn the_problem_reaches_every_branch() {
        let (mut bodies, _, mut manifolds, mut points) = problem(1);
        let before = manifolds.clone();
        pull(&mut bodies);
        scalar(&mut bodies, &mut manifolds, &mut points);
        let sliding = manifolds.iter().filter(|m| {
            let total: f64 = points[m.range()].iter().map(|p| p.normal_impulse).sum();
            let t = m.impulses[0].hypot(m.impulses[1]);
            total > 0.0 && t >= 0.99 * m.friction * total
        });
        assert!(sliding.count() > 10);
        let lifted = points.iter().filter(|p| p.normal_impulse == 0.0).count();
        assert!(lifted > 10 && lifted < points.len() - 10);
        assert!(points.iter().any(|p| p.push_impulse > 0.0));
        // Flat push-out blocks where every point takes part (the direct
        // solve) and blocks where some do not (point after point).
        let allowed = params().allowed_penetration;
        let takes_part = |p: &PointConstraint| p.push_impulse != 0.0 || p.separation_now + allowed < 0.0;
        let (mut whole, mut mixed) = (0, 0);
        for m in &manifolds {
            let pts = &points[m.range()];
            if pts.iter().all(|p| takes_part(p) && p.normal == pts[0].normal) {
                whole += 1;
            } else if pts.iter().any(takes_part) {
                mixed += 1;
            }
        }
        assert!(whole > 10 && mixed > 10, "{whole} whole, {mixed} mixed");
        let rebuilt = manifolds.iter().zip(&before).filter(|(m, b)| m.block != b.block);
        assert!(rebuilt.count() > 10);
        // Anchored patches with friction left to hold their anchor, and
        // without.
        let left = |m: &&ManifoldConstraint| {
            let total: f64 = points[m.range()].iter().map(|p| p.normal_impulse).sum();
            m.friction * total > m.impulses[0].hypot(m.impulses[1])
        };
        let anchored: Vec<_> = manifolds.iter().filter(|m| m.anchored).collect();
        let holding = anchored.iter().filter(|m| left(m)).count();
        assert!(
            holding > 10 && anchored.len() - holding > 10,
            "{holding} of {}",
            anchored.len()
        );
    }
}
