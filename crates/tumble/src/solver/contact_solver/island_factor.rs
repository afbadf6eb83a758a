//! The numbers of a joint island's direct solve (`joint_island`): the
//! system `K = J M^-1 J^T` assembled block by block over the pairs of
//! joints that share a dynamic body, its Cholesky factor over the system's
//! profile (skyline) less the blocks a symbolic factorization over joints
//! finds zero (`Pattern`), run from a list of its products compiled once
//! per shape (`Program`), and solves with that factor (whole, or its
//! forward and backward halves).
//!
//! Written once over the number type [`Num`]: `f64` for one island, and
//! the solver's [`Lane`] for four islands of the same shape at once (a pile
//! of ragdolls: the same joints between the same limbs), one per lane.
//! Every lane performs the IEEE operations of the `f64` code in the same
//! order, nothing fused into a multiply-add, so an island factored in a
//! lane gets the bits it gets alone.

use super::joint::JointRow;
use super::lanes::{Lane, LANES, V3};
use std::ops::{Add, Div, Mul, Sub};
use tumble_collide::DVec3;

/// The arithmetic the factor needs, on `f64` and lane by lane on [`Lane`].
pub(super) trait Num:
    Copy + Default + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    fn splat(x: f64) -> Self;
    fn sqrt(self) -> Self;
    /// The larger of the two (for the finite values the factor meets).
    fn max(self, other: Self) -> Self;
    fn abs(self) -> Self;
}

impl Num for f64 {
    #[inline(always)]
    fn splat(x: f64) -> f64 {
        x
    }
    #[inline(always)]
    fn sqrt(self) -> f64 {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn max(self, other: f64) -> f64 {
        f64::max(self, other)
    }
    #[inline(always)]
    fn abs(self) -> f64 {
        f64::abs(self)
    }
}

impl Num for Lane {
    #[inline(always)]
    fn splat(x: f64) -> Lane {
        Lane::splat(x)
    }
    #[inline(always)]
    fn sqrt(self) -> Lane {
        Lane::sqrt(self)
    }
    #[inline(always)]
    fn max(self, other: Lane) -> Lane {
        Lane::max(self, other)
    }
    #[inline(always)]
    fn abs(self) -> Lane {
        Lane::abs(self)
    }
}

/// A 3-vector of numbers.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct P3<N> {
    x: N,
    y: N,
    z: N,
}

impl<N: Num> P3<N> {
    /// `(x x') + (y y') + (z z')`, as glam's `dot`.
    #[inline(always)]
    fn dot(self, o: P3<N>) -> N {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Each component times `s`.
    #[inline(always)]
    fn scaled(self, s: N) -> P3<N> {
        P3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
}

impl From<P3<Lane>> for V3 {
    #[inline(always)]
    fn from(p: P3<Lane>) -> V3 {
        V3 {
            x: p.x,
            y: p.y,
            z: p.z,
        }
    }
}

impl From<DVec3> for P3<f64> {
    fn from(v: DVec3) -> P3<f64> {
        P3 {
            x: v.x,
            y: v.y,
            z: v.z,
        }
    }
}

/// One row of an island's system by body side (A, B): its Jacobian, the
/// side's inverse mass and the angular Jacobian times the side's inverse
/// inertia; the row's softness (motors).
///
/// The linear Jacobian times the inverse mass is worked out where `K` is
/// assembled (`SideRow::m_lin`, the same product) rather than kept: an
/// island's rows in lanes are rebuilt every sub-step, and a pile of
/// ragdolls' do not fit in a core's cache (four lanes' `m_lin` were 192
/// of a row's 800 bytes).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct SideRow<N> {
    lin: [P3<N>; 2],
    ang: [P3<N>; 2],
    mass: [N; 2],
    m_ang: [P3<N>; 2],
    gamma: N,
}

impl<N: Num> SideRow<N> {
    /// The linear Jacobian on side `t` times the side's inverse mass.
    #[inline(always)]
    fn m_lin(&self, t: usize) -> P3<N> {
        self.lin[t].scaled(self.mass[t])
    }
}

impl SideRow<f64> {
    /// The sides of joint row `r` (`lin . (vA - vB) + ang_a . wA + ang_b .
    /// wB`) between bodies of inverse masses `ma` and `mb`.
    pub fn new(r: &JointRow, ma: f64, mb: f64) -> SideRow<f64> {
        SideRow {
            lin: [r.lin.into(), (-r.lin).into()],
            ang: [r.ang_a.into(), r.ang_b.into()],
            mass: [ma, mb],
            m_ang: [r.ia.into(), r.ib.into()],
            gamma: r.gamma,
        }
    }
}

impl SideRow<f64> {
    /// A row on one body only (side 0; side 1 moves nothing): a gear's
    /// part on one of its bodies (`gear`), of Jacobian `lin`, `ang` on a
    /// body of inverse mass `inv_mass`, with `ia = I^-1 ang`.
    pub fn one_side(lin: DVec3, ang: DVec3, inv_mass: f64, ia: DVec3) -> SideRow<f64> {
        SideRow {
            lin: [lin.into(), P3::default()],
            ang: [ang.into(), P3::default()],
            mass: [inv_mass, 0.0],
            m_ang: [ia.into(), P3::default()],
            gamma: 0.0,
        }
    }

    /// `K`'s entry between this row on side `s` and `other` on side `t`
    /// of the same body (`J_s M^-1 J_t^T`).
    pub fn meets(&self, s: usize, other: &SideRow<f64>, t: usize) -> f64 {
        self.lin[s].dot(other.m_lin(t)) + self.ang[s].dot(other.m_ang[t])
    }
}

impl SideRow<f64> {
    /// Its Jacobian on side `s`, linear and angular: the row's velocity
    /// from a change `dv`, `dw` of the side's body is `lin . dv + ang . dw`.
    pub fn side(&self, s: usize) -> (DVec3, DVec3) {
        let v = |p: P3<f64>| DVec3::new(p.x, p.y, p.z);
        (v(self.lin[s]), v(self.ang[s]))
    }
}

impl SideRow<Lane> {
    /// Joint row `rows[l]` (between bodies of inverse masses `ma`, `mb`
    /// in lane `l`) in each lane, as [`SideRow::new`] builds it (the same
    /// bits), without the rows of `f64` in between.
    #[inline(always)]
    pub fn new_lanes(rows: [&JointRow; LANES], ma: Lane, mb: Lane) -> SideRow<Lane> {
        #[inline(always)]
        fn gather(rows: &[&JointRow; LANES], f: impl Fn(&JointRow) -> DVec3) -> P3<Lane> {
            let v = rows.map(f);
            P3 {
                x: Lane::new(v.map(|p| p.x)),
                y: Lane::new(v.map(|p| p.y)),
                z: Lane::new(v.map(|p| p.z)),
            }
        }
        let lin = gather(&rows, |r| r.lin);
        let neg = P3 {
            x: -lin.x,
            y: -lin.y,
            z: -lin.z,
        };
        SideRow {
            lin: [lin, neg],
            ang: [gather(&rows, |r| r.ang_a), gather(&rows, |r| r.ang_b)],
            mass: [ma, mb],
            m_ang: [gather(&rows, |r| r.ia), gather(&rows, |r| r.ib)],
            gamma: Lane::new(rows.map(|r| r.gamma)),
        }
    }

    /// The Jacobian in every lane: `lin` (A's; B's is its negative),
    /// `ang_a`, `ang_b`, as the joint rows hold them.
    #[inline(always)]
    pub fn jacobian_lanes(&self) -> (V3, V3, V3) {
        (self.lin[0].into(), self.ang[0].into(), self.ang[1].into())
    }

    /// `I_A^-1 ang_a` and `I_B^-1 ang_b` in every lane, as the joint rows
    /// hold them.
    #[inline(always)]
    pub fn inertia_lanes(&self) -> (V3, V3) {
        (self.m_ang[0].into(), self.m_ang[1].into())
    }

    /// Lane `l`'s Jacobian on side `s`, linear and angular.
    #[inline(always)]
    pub fn side_lane(&self, l: usize, s: usize) -> (DVec3, DVec3) {
        let pick = |p: &P3<Lane>| DVec3::new(p.x.as_array()[l], p.y.as_array()[l], p.z.as_array()[l]);
        (pick(&self.lin[s]), pick(&self.ang[s]))
    }
}

/// Two joints of an island that share a dynamic body: the rows of joint
/// `p` couple with those of joint `q` (`q <= p` in the island's order)
/// through side `side_p` of `p` and side `side_q` of `q`. A joint couples
/// with itself once per dynamic side.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Coupling {
    pub p: u32,
    pub q: u32,
    pub side_p: u8,
    pub side_q: u8,
}

/// Most joints of an island whose owned points' reach is followed
/// ([`Profile::reach`]: a bit per joint of a `u64`); a larger island's
/// points are worked out over every row from their first.
pub(super) const REACH_JOINTS: usize = 64;

/// The shape of an island's system: which rows belong to which joint,
/// which blocks are not zero, and the profile of the factor. Islands of
/// the same shape can share a lane set.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(super) struct Profile {
    /// First row of each joint (and the number of joint rows last; gear
    /// rows follow them).
    pub offsets: Vec<usize>,
    /// The blocks of `K` that are not zero.
    pub couplings: Vec<Coupling>,
    /// Per row: the first column of its profile.
    pub first: Vec<usize>,
    /// Per row: where its profile starts in the factor.
    pub start: Vec<usize>,
    /// Entries of the factor.
    pub size: usize,
    /// Which joint blocks of the factor can be other than zero within the
    /// profile.
    pattern: Pattern,
    /// Per joint `p` (islands of up to [`REACH_JOINTS`] joints): bit `q`
    /// set where block `(p, q)`, `q < p`, can be other than zero
    /// (`Profile::reach`).
    before_mask: Vec<u64>,
}

/// The joint blocks of an island's factor that can be other than zero,
/// found once per shape by a symbolic factorization over joints: block
/// `(p, q)`, `q < p`, of `L` is not zero where `K`'s is not, or where an
/// earlier block `r < q` is not zero in both `p`'s and `q`'s rows (fill).
///
/// Why: the profile holds every entry from a row's first column to its
/// diagonal, and a tree of joints leaves most of it zero: a ragdoll's
/// shoulder reaches back past the other limbs' joints to its elbow, and 126
/// of its factor's 363 entries are zeros the factorization and each solve
/// multiplied through. A skipped entry is an exact zero (a `+0` that the
/// factorization computes as `(0 - 0) / d`, every product in its dot
/// having a zero factor) and a skipped term of a dot or a solve is a
/// product with that zero, which leaves a finite sum's bits as they are
/// (the sums start at `+0`): the factor and every solve have the bits of
/// the full profile's.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
struct Pattern {
    /// Per joint `p`, a range of `before`: the earlier joints whose blocks
    /// in `p`'s rows can be other than zero, in order.
    before_at: Vec<usize>,
    /// `(q, range of segments)`: joint `q` and the columns, before `q`'s,
    /// that can be other than zero in both `p`'s and `q`'s rows (the terms
    /// of a dot product of the two rows).
    before: Vec<(usize, usize, usize)>,
    /// Per joint `p`, a range of `segments`: the columns before `p`'s own
    /// that can be other than zero in `p`'s rows.
    own: Vec<(usize, usize)>,
    /// Column ranges `[from, to)`, each list in increasing order.
    segments: Vec<(usize, usize)>,
    /// Per row, a range of `row_runs`: the row's columns before its
    /// diagonal that can be other than zero (what a solve reads).
    row_runs_at: Vec<usize>,
    /// Per run, `[from, to)` in columns.
    row_runs: Vec<(usize, usize)>,
    /// The factorization of the joints' rows written out entry by entry
    /// (`Program`), where it is small enough to keep.
    program: Option<Program>,
}

/// The numeric factorization of an island's joint rows, compiled once per
/// shape from its pattern: every entry of `L` in the order the
/// factorization computes it, each with the positions in the factor of the
/// pairs of entries its dot product sums, in the order it sums them.
///
/// Why: a chain's or a ragdoll's entries sum one to five products each,
/// and walking the pattern for them (each row's segments, their offsets in
/// two rows, the bounds of each slice) took several times the
/// instructions of the arithmetic (the heavy chain's factorization was 29 %
/// of its instructions). Run from the program, each product is two
/// positions read from a list.
/// The same operations in the same order (each dot from `+0`, term after
/// term): the factor has the bits of the pattern's walk.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
struct Program {
    /// The entries, in the order they are computed.
    steps: Vec<Step>,
    /// Each step's terms: positions `(a, b)` in the factor of the two
    /// entries a product multiplies, a step's after the one before it.
    terms: Vec<(u32, u32)>,
}

/// One entry of a [`Program`]: at position `at` of the factor, over the
/// terms up to `end`; off the diagonal divided by row `row`'s diagonal,
/// on it (`diagonal`) the square root that becomes row `row`'s.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Step {
    at: u32,
    row: u32,
    end: u32,
    diagonal: bool,
}

/// Most terms a [`Program`] may hold (8 bytes each); a larger island's
/// factor walks its pattern instead, whose runs are long enough there
/// that the walk costs little beside the products.
const MAX_PROGRAM_TERMS: usize = 1 << 18;

impl Program {
    /// The program of the joint rows of a profile (`offsets`, each row's
    /// `first` column and `start` in the factor) with pattern `pattern`:
    /// its entries in [`Pattern::for_each_entry`]'s order, positions
    /// recorded instead of computed. `None` when it would be too large.
    fn new(
        offsets: &[usize],
        first: &[usize],
        start: &[usize],
        size: usize,
        pattern: &Pattern,
    ) -> Option<Program> {
        if size > u32::MAX as usize {
            return None;
        }
        let mut program = Program::default();
        pattern.for_each_entry(offsets, |i, j, segments, tail| {
            program.entry(i, j, segments, tail, (first, start))
        })?;
        Some(program)
    }

    /// Records entry `j` of row `i` (the diagonal where `j == i`): the
    /// terms of the dot of rows `i` and `j` over the columns of
    /// `segments`, then `tail`, in increasing order, as `dot_over` sums
    /// them. `None` past [`MAX_PROGRAM_TERMS`].
    fn entry(
        &mut self,
        i: usize,
        j: usize,
        segments: &[(usize, usize)],
        tail: (usize, usize),
        (first, start): (&[usize], &[usize]),
    ) -> Option<()> {
        let (a0, b0) = (start[i] - first[i], start[j] - first[j]);
        for &(from, to) in segments.iter().chain([&tail]) {
            self.terms
                .extend((from..to).map(|k| ((a0 + k) as u32, (b0 + k) as u32)));
        }
        if self.terms.len() > MAX_PROGRAM_TERMS {
            return None;
        }
        self.steps.push(Step {
            at: (a0 + j) as u32,
            row: j as u32,
            end: self.terms.len() as u32,
            diagonal: i == j,
        });
        Some(())
    }

    /// Factors the joint rows of `k` (assembled and regularized) in place,
    /// step by step, each row's reciprocal diagonal into `inv_diagonal`.
    #[inline(always)]
    fn run<N: Num>(&self, k: &mut [N], inv_diagonal: &mut [N]) {
        let mut from = 0;
        for step in &self.steps {
            let end = step.end as usize;
            let mut dot = N::default();
            for &(a, b) in &self.terms[from..end] {
                dot = dot + k[a as usize] * k[b as usize];
            }
            from = end;
            let (at, row) = (step.at as usize, step.row as usize);
            if step.diagonal {
                let d = (k[at] - dot).max(N::splat(1e-300)).sqrt();
                inv_diagonal[row] = N::splat(1.0) / d;
                k[at] = d;
            } else {
                k[at] = (k[at] - dot) * inv_diagonal[row];
            }
        }
    }
}

impl Pattern {
    /// Calls `f(i, j, segments, tail)` for every entry of the joint rows'
    /// factor that can be other than zero, in the order the factorization
    /// computes them (row by row; in a row, the blocks of earlier joints,
    /// then its own joint's entries, then its diagonal `j == i`): the dot
    /// of rows `i` and `j` runs over the columns of `segments`, then
    /// `tail`. The one home of that order, which `Program` records and
    /// `walk_pattern` computes (the same order, so the same bits). Stops
    /// at the first `None` from `f`, and returns it.
    fn for_each_entry(
        &self,
        offsets: &[usize],
        mut f: impl FnMut(usize, usize, &[(usize, usize)], (usize, usize)) -> Option<()>,
    ) -> Option<()> {
        for p in 0..offsets.len().saturating_sub(1) {
            let own_from = offsets[p];
            let own = &self.segments[self.own[p].0..self.own[p].1];
            let before = &self.before[self.before_at[p]..self.before_at[p + 1]];
            for i in own_from..offsets[p + 1] {
                for &(q, from, to) in before {
                    let common = &self.segments[from..to];
                    for j in offsets[q]..offsets[q + 1] {
                        f(i, j, common, (offsets[q], j))?;
                    }
                }
                for j in own_from..=i {
                    f(i, j, own, (own_from, j))?;
                }
            }
        }
        Some(())
    }

    /// The pattern of a profile's joints (`offsets`, `couplings`).
    fn new(offsets: &[usize], couplings: &[Coupling]) -> Pattern {
        let joints = offsets.len().saturating_sub(1);
        // Per joint, the earlier joints whose blocks can be other than
        // zero, in increasing order.
        let mut blocks: Vec<Vec<usize>> = vec![Vec::new(); joints];
        let mut here = vec![false; joints];
        for p in 0..joints {
            for c in couplings.iter().filter(|c| c.p as usize == p && c.q < c.p) {
                here[c.q as usize] = true;
            }
            let earliest = here.iter().position(|&h| h).unwrap_or(p);
            for q in earliest..p {
                if !here[q] && blocks[q].iter().any(|&r| here[r]) {
                    here[q] = true;
                }
            }
            blocks[p] = (earliest..p).filter(|&q| here[q]).collect();
            here[earliest..p].iter_mut().for_each(|h| *h = false);
        }
        let mut pattern = Pattern::default();
        let push_runs = |segments: &mut Vec<(usize, usize)>, list: &mut dyn Iterator<Item = usize>| {
            let begin = segments.len();
            for q in list {
                let (from, to) = (offsets[q], offsets[q + 1]);
                let len = segments.len();
                match segments.last_mut() {
                    Some(last) if len > begin && last.1 == from => last.1 = to,
                    _ => segments.push((from, to)),
                }
            }
            (begin, segments.len())
        };
        for p in 0..joints {
            pattern.before_at.push(pattern.before.len());
            for &q in &blocks[p] {
                let common = &mut blocks[p]
                    .iter()
                    .copied()
                    .filter(|r| *r < q && blocks[q].contains(r));
                let (from, to) = push_runs(&mut pattern.segments, common);
                pattern.before.push((q, from, to));
            }
            let own = push_runs(&mut pattern.segments, &mut blocks[p].iter().copied());
            pattern.own.push(own);
        }
        pattern.before_at.push(pattern.before.len());
        pattern
    }
}

impl Profile {
    /// The profile of joints whose rows start at `offsets` (with the
    /// number of joint rows last), of `K` blocks `couplings`, with each
    /// row's first column and start in the factor (gear rows after the
    /// joints' rows) and `size` entries.
    pub fn new(
        offsets: Vec<usize>,
        couplings: Vec<Coupling>,
        first: Vec<usize>,
        start: Vec<usize>,
        size: usize,
    ) -> Profile {
        let mut pattern = Pattern::new(&offsets, &couplings);
        // Each row's runs: its joint's segments and its own joint's columns
        // before it, merged where they meet; a gear row's whole profile.
        let joint_rows = offsets.last().copied().unwrap_or(0);
        let mut p = 0;
        for (i, &fi) in first.iter().enumerate() {
            pattern.row_runs_at.push(pattern.row_runs.len());
            let tail = if i < joint_rows {
                while offsets[p + 1] <= i {
                    p += 1;
                }
                let (from, to) = pattern.own[p];
                pattern.row_runs.extend_from_slice(&pattern.segments[from..to]);
                (offsets[p], i)
            } else {
                (fi, i)
            };
            let this_row = pattern.row_runs.len() > pattern.row_runs_at[i];
            match pattern.row_runs.last_mut() {
                Some(last) if this_row && last.1 == tail.0 => last.1 = tail.1,
                _ if tail.0 < tail.1 => pattern.row_runs.push(tail),
                _ => {}
            }
        }
        pattern.row_runs_at.push(pattern.row_runs.len());
        pattern.program = Program::new(&offsets, &first, &start, size, &pattern);
        let joints = offsets.len().saturating_sub(1);
        let before_mask = if joints <= REACH_JOINTS {
            (0..joints)
                .map(|p| {
                    let before = &pattern.before[pattern.before_at[p]..pattern.before_at[p + 1]];
                    before.iter().fold(0u64, |mask, &(q, _, _)| mask | 1 << q)
                })
                .collect()
        } else {
            Vec::new()
        };
        Profile {
            offsets,
            couplings,
            first,
            start,
            size,
            pattern,
            before_mask,
        }
    }

    /// The joints whose rows of `L^-1 w` can be other than zero, for a
    /// column `w` that is zero outside the rows of the joints `touched`
    /// (bit `p` for joint `p`); `None` for an island of more than
    /// [`REACH_JOINTS`] joints (whose columns are then worked out whole).
    ///
    /// Why: a forward substitution carries a row's value only to the rows
    /// whose factor blocks reach back to it (the pattern): from a ragdoll's
    /// forearm on the ground, its column reaches its elbow, both shoulders
    /// (which meet on the chest) and the spine, not the other elbow, the
    /// hips or the knees, though those come after the forearm's joint in
    /// the island's order (about a third of the rows from the patches'
    /// first rows on, in the ragdoll pile). A joint is reached when it is
    /// touched or when a reached joint before it has a block in its rows
    /// that can be other than zero.
    pub fn reach(&self, touched: u64) -> Option<u64> {
        if self.offsets.len() > REACH_JOINTS + 1 {
            return None;
        }
        let mut reached = 0u64;
        for (p, &before) in self.before_mask.iter().enumerate() {
            if (touched >> p) & 1 != 0 || before & reached != 0 {
                reached |= 1 << p;
            }
        }
        Some(reached)
    }

    /// The rows of the joints `reached` (bit `p` for joint `p`) and every
    /// gear row, as runs `[from, to)` in increasing order, merged where
    /// they meet, written to `runs` (for `Factor::forward_runs`).
    pub fn rows_of(&self, reached: u64, runs: &mut Vec<(usize, usize)>) {
        runs.clear();
        let o = &self.offsets;
        for p in 0..o.len().saturating_sub(1) {
            if (reached >> p) & 1 != 0 && o[p] < o[p + 1] {
                match runs.last_mut() {
                    Some(last) if last.1 == o[p] => last.1 = o[p + 1],
                    _ => runs.push((o[p], o[p + 1])),
                }
            }
        }
        // Gear rows (after the joints' rows) have whole profiles.
        let joint_rows = o.last().copied().unwrap_or(0);
        if joint_rows < self.rows() {
            runs.push((joint_rows, self.rows()));
        }
    }

    /// Entries of the factor that can be other than zero.
    #[cfg(test)]
    pub fn entries(&self) -> usize {
        let (o, pat) = (&self.offsets, &self.pattern);
        let own_rows = |p: usize| {
            let rows = o[p + 1] - o[p];
            let before: usize = pat.segments[pat.own[p].0..pat.own[p].1]
                .iter()
                .map(|s| s.1 - s.0)
                .sum();
            rows * before + rows * (rows + 1) / 2
        };
        let joint_rows = *o.last().unwrap_or(&0);
        let gears: usize = (joint_rows..self.rows()).map(|i| i + 1 - self.first[i]).sum();
        (0..o.len().saturating_sub(1)).map(own_rows).sum::<usize>() + gears
    }

    /// Rows of the system.
    pub fn rows(&self) -> usize {
        self.first.len()
    }

    /// Where `K`'s entry (i, j), `first[i] <= j <= i`, lies in the factor.
    pub fn at(&self, i: usize, j: usize) -> usize {
        debug_assert!(self.first[i] <= j && j <= i);
        self.start[i] + j - self.first[i]
    }
}

/// The Cholesky factor of an island's system (or of one per lane).
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct Factor<N> {
    /// Row by row over each row's profile.
    values: Vec<N>,
    /// The reciprocals of the diagonal.
    inv_diagonal: Vec<N>,
}

impl<N: Num> Factor<N> {
    /// Assembles `K` from `rows` (one per row of `profile`) and factors it
    /// in place. A small regularization on the diagonal (a degenerate pose
    /// makes rows dependent).
    pub fn factor(&mut self, profile: &Profile, rows: &[SideRow<N>]) {
        self.factor_adding(profile, rows, |_| {});
    }

    /// [`Factor::factor`], with `add` adding to `K` (stored as
    /// [`Profile::at`] places it) the entries of rows that are not joint
    /// rows (gears), before the diagonal is regularized and `K` factored.
    #[allow(clippy::needless_range_loop)] // profile indices (i, j) address K and rows at once
    pub fn factor_adding(&mut self, profile: &Profile, rows: &[SideRow<N>], add: impl FnOnce(&mut [N])) {
        let n = profile.rows();
        let (first, start) = (&profile.first, &profile.start);
        self.values.clear();
        self.values.resize(profile.size, N::default());
        self.inv_diagonal.resize(n, N::default());
        // Block by block: only joints sharing a dynamic body couple (the
        // profile holds zeros between them).
        let k = &mut self.values;
        for c in &profile.couplings {
            let (s, t) = (c.side_p as usize, c.side_q as usize);
            let (q0, q1) = (profile.offsets[c.q as usize], profile.offsets[c.q as usize + 1]);
            for i in profile.offsets[c.p as usize]..profile.offsets[c.p as usize + 1] {
                let (ri_lin, ri_ang) = (rows[i].lin[s], rows[i].ang[s]);
                let at = start[i] - first[i];
                // Within one joint, the lower triangle only.
                let end = if c.p == c.q { i + 1 } else { q1 };
                for (kij, rj) in k[at + q0..at + end].iter_mut().zip(&rows[q0..end]) {
                    *kij = *kij + (ri_lin.dot(rj.m_lin(t)) + ri_ang.dot(rj.m_ang[t]));
                }
            }
        }
        add(k);
        for (i, r) in rows.iter().enumerate() {
            let d = &mut k[start[i] + i - first[i]];
            *d = *d + (r.gamma + N::splat(1e-12) * d.abs() + N::splat(1e-300));
        }
        // Profile Cholesky, in place: entries before a row's first column
        // are zero and stay zero in the factor. Row i's entry p >= first[i]
        // lies at start[i] + p - first[i]; the rows before i lie before
        // start[i] (`done`). The joints' rows skip the blocks their pattern
        // holds to be zero (left at +0), run from their compiled `Program`
        // (or, for an island too large for one, by walking the pattern);
        // gear rows take their whole profile.
        let inv_diagonal = &mut self.inv_diagonal;
        match &profile.pattern.program {
            Some(program) => program.run(k, inv_diagonal),
            None => walk_pattern(profile, k, inv_diagonal),
        }
        let offsets = &profile.offsets;
        for i in offsets.last().copied().unwrap_or(0)..n {
            let (fi, si) = (first[i], start[i]);
            let (done, row_i) = k.split_at_mut(si);
            let row_i = &mut row_i[..i + 1 - fi];
            for j in fi..i {
                let (fj, sj) = (first[j], start[j]);
                let lo = fi.max(fj);
                let dot = dot_over(row_i, fi, &done[sj..], fj, &[], (lo, j));
                row_i[j - fi] = (row_i[j - fi] - dot) * inv_diagonal[j];
            }
            let dot = dot_over(row_i, fi, row_i, fi, &[], (fi, i));
            let d = (row_i[i - fi] - dot).max(N::splat(1e-300)).sqrt();
            inv_diagonal[i] = N::splat(1.0) / d;
            row_i[i - fi] = d;
        }
    }

    /// Solves `K x = rhs` in place with the factor (entries that are not
    /// finite are the caller's to clear). `x` holds numbers of the factor's
    /// kind, or, for a factor of one island (`f64`), [`LANES`] right-hand
    /// sides at once, one a lane (`x[r]` holds row `r` of each): every lane
    /// performs the IEEE operations of the one-column solve in its order, so
    /// each column gets the bits it gets alone (an island's owned contact
    /// points are solved this way, four at a time).
    pub fn solve<X: Num + Mul<N, Output = X>>(&self, profile: &Profile, x: &mut [X]) {
        self.forward(profile, x);
        self.backward(profile, x);
    }

    /// The first half of [`Factor::solve`]: `x <- L^-1 x`.
    pub fn forward<X: Num + Mul<N, Output = X>>(&self, profile: &Profile, x: &mut [X]) {
        self.forward_runs(profile, x, &[(0, profile.rows())]);
    }

    /// [`Factor::forward`] for an `x` whose result can be other than zero
    /// only in the rows `rows` (runs `[from, to)` in increasing order:
    /// [`Profile::reach`]), which are zero elsewhere. Only those rows are
    /// worked out; the others stay zero, as the whole pass would leave
    /// them (each term of their dots multiplies a zero, and the sums start
    /// at `+0`), so the bits are the whole pass's.
    pub fn forward_runs<X: Num + Mul<N, Output = X>>(
        &self,
        profile: &Profile,
        x: &mut [X],
        rows: &[(usize, usize)],
    ) {
        let (first, start, l) = (&profile.first, &profile.start, &self.values);
        let (runs_at, runs) = (&profile.pattern.row_runs_at, &profile.pattern.row_runs);
        for i in rows.iter().flat_map(|&(from, to)| from..to) {
            let base = start[i] - first[i];
            let mut dot = X::default();
            for &(from, to) in &runs[runs_at[i]..runs_at[i + 1]] {
                for (v, w) in l[base + from..base + to].iter().zip(&x[from..to]) {
                    dot = dot + *w * *v;
                }
            }
            x[i] = (x[i] - dot) * self.inv_diagonal[i];
        }
    }

    /// The second half of [`Factor::solve`]: `x <- L^-T x`.
    pub fn backward<X: Num + Mul<N, Output = X>>(&self, profile: &Profile, x: &mut [X]) {
        let (first, start, l) = (&profile.first, &profile.start, &self.values);
        let (runs_at, runs) = (&profile.pattern.row_runs_at, &profile.pattern.row_runs);
        for i in (0..profile.rows()).rev() {
            let base = start[i] - first[i];
            x[i] = x[i] * self.inv_diagonal[i];
            let xi = x[i];
            for &(from, to) in &runs[runs_at[i]..runs_at[i + 1]] {
                for (v, w) in x[from..to].iter_mut().zip(&l[base + from..base + to]) {
                    *v = *v - xi * *w;
                }
            }
        }
    }
}

impl Factor<f64> {
    /// `x <- L^T x`, the inverse of [`Factor::backward`] (up to rounding):
    /// back from the solution of `K x = rhs` to the forward pass's `L^-1
    /// rhs`.
    pub fn multiply_transposed(&self, profile: &Profile, x: &mut [f64]) {
        let (first, start, l) = (&profile.first, &profile.start, &self.values);
        let (runs_at, runs) = (&profile.pattern.row_runs_at, &profile.pattern.row_runs);
        // Row i of L^T x sums column i of L below the diagonal: rows in
        // increasing order, each read before a later row adds to it.
        for i in 0..profile.rows() {
            let base = start[i] - first[i];
            let xi = x[i];
            x[i] = xi * l[base + i];
            for &(from, to) in &runs[runs_at[i]..runs_at[i + 1]] {
                for (v, w) in x[from..to].iter_mut().zip(&l[base + from..base + to]) {
                    *v += xi * *w;
                }
            }
        }
    }
}

/// The joint rows of [`Factor::factor_adding`]'s `k` factored by walking
/// the pattern row by row (an island too large for a [`Program`]): each
/// row's entries over the blocks its pattern can hold other than zero,
/// then its diagonal, into `inv_diagonal` as its reciprocal.
fn walk_pattern<N: Num>(profile: &Profile, k: &mut [N], inv_diagonal: &mut [N]) {
    let (first, start) = (&profile.first, &profile.start);
    let walked = profile
        .pattern
        .for_each_entry(&profile.offsets, |i, j, segments, tail| {
            let (fi, si) = (first[i], start[i]);
            let (done, row_i) = k.split_at_mut(si);
            let row_i = &mut row_i[..i + 1 - fi];
            if i == j {
                let dot = dot_over(row_i, fi, row_i, fi, segments, tail);
                let d = (row_i[i - fi] - dot).max(N::splat(1e-300)).sqrt();
                inv_diagonal[i] = N::splat(1.0) / d;
                row_i[i - fi] = d;
            } else {
                entry(row_i, fi, done, profile, inv_diagonal, j, segments, tail.0);
            }
            Some(())
        });
    debug_assert!(walked.is_some());
}

/// Entry `j` of row `i` of the factor (row `i` stored from column `fi`,
/// the rows before it in `done`): `K`'s entry less the dot of the two rows
/// over the columns `common` and `block_from..j`, over the diagonal of `j`.
/// A function, not a closure of `factor_adding`: the closure was not
/// inlined, and its call cost more than the two-term dot of a chain's entry.
#[inline(always)]
#[allow(clippy::too_many_arguments)] // the loop's state, passed through
fn entry<N: Num>(
    row_i: &mut [N],
    fi: usize,
    done: &[N],
    profile: &Profile,
    inv_diagonal: &[N],
    j: usize,
    common: &[(usize, usize)],
    block_from: usize,
) {
    let (fj, sj) = (profile.first[j], profile.start[j]);
    let dot = dot_over(row_i, fi, &done[sj..], fj, common, (block_from, j));
    row_i[j - fi] = (row_i[j - fi] - dot) * inv_diagonal[j];
}

/// `sum a[k] b[k]` over the columns `k` of `segments`, then of `tail`
/// (`[from, to)` each), in increasing order from `+0`, with row `a` stored
/// from column `fa` and row `b` from column `fb`.
#[inline(always)]
fn dot_over<N: Num>(
    a: &[N],
    fa: usize,
    b: &[N],
    fb: usize,
    segments: &[(usize, usize)],
    tail: (usize, usize),
) -> N {
    let mut dot = N::default();
    for &(from, to) in segments {
        for (x, y) in a[from - fa..to - fa].iter().zip(&b[from - fb..to - fb]) {
            dot = dot + *x * *y;
        }
    }
    let (from, to) = tail;
    for (x, y) in a[from - fa..to - fa].iter().zip(&b[from - fb..to - fb]) {
        dot = dot + *x * *y;
    }
    dot
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_testkit::{RandomSource, SplitMix64};

    /// The profile of joints `(body a, body b, rows)` in this order, every
    /// body dynamic, as `joint_island` lays one out (couplings between
    /// joints on a shared body, each row back to the earliest such joint).
    fn profile_of(joints: &[(usize, usize, usize)]) -> Profile {
        let mut offsets = vec![0];
        for &(_, _, rows) in joints {
            offsets.push(offsets.last().unwrap() + rows);
        }
        let (mut couplings, mut first, mut start, mut size) = (Vec::new(), Vec::new(), Vec::new(), 0);
        for (p, &(a, b, rows)) in joints.iter().enumerate() {
            let mut earliest = p;
            for (side_p, body) in [a, b].into_iter().enumerate() {
                for (q, &(qa, qb, _)) in joints.iter().enumerate() {
                    let side_q = match body {
                        x if x == qa => 0,
                        x if x == qb => 1,
                        _ => continue,
                    };
                    earliest = earliest.min(q);
                    if q < p || (q == p && side_q == side_p) {
                        couplings.push(Coupling {
                            p: p as u32,
                            q: q as u32,
                            side_p: side_p as u8,
                            side_q: side_q as u8,
                        });
                    }
                }
            }
            for i in offsets[p]..offsets[p] + rows {
                first.push(offsets[earliest]);
                start.push(size);
                size += i - offsets[earliest] + 1;
            }
        }
        Profile::new(offsets, couplings, first, start, size)
    }

    /// Random rows for a profile: Jacobians on each side, a body's inverse
    /// mass and (isotropic) inverse inertia per body, so that `K` is `J
    /// M^-1 J^T` of real bodies.
    fn rows_of(rng: &mut SplitMix64, joints: &[(usize, usize, usize)], bodies: usize) -> Vec<SideRow<f64>> {
        let masses: Vec<(f64, f64)> = (0..bodies)
            .map(|_| (rng.range(0.05, 5.0), rng.range(0.1, 20.0)))
            .collect();
        let mut rows = Vec::new();
        for &(a, b, n) in joints {
            for _ in 0..n {
                let p = |rng: &mut SplitMix64| {
                    P3::from(DVec3::new(
                        rng.range(-1.0, 1.0),
                        rng.range(-1.0, 1.0),
                        rng.range(-1.0, 1.0),
                    ))
                };
                let (lin, ang) = ([p(rng), p(rng)], [p(rng), p(rng)]);
                let scale = |v: P3<f64>, s: f64| P3 {
                    x: v.x * s,
                    y: v.y * s,
                    z: v.z * s,
                };
                rows.push(SideRow {
                    lin,
                    ang,
                    mass: [masses[a].0, masses[b].0],
                    m_ang: [scale(ang[0], masses[a].1), scale(ang[1], masses[b].1)],
                    gamma: 0.0,
                });
            }
        }
        rows
    }

    /// A ragdoll's joints, leaves first as `joint_island` orders them
    /// (pelvis 0, chest 1, arms 2-5, legs 6-9): elbows and knees (hinges,
    /// five rows), shoulders and hips, the spine (balls, three).
    const RAGDOLL: [(usize, usize, usize); 9] = [
        (2, 3, 5),
        (4, 5, 5),
        (6, 7, 5),
        (8, 9, 5),
        (1, 2, 3),
        (1, 4, 3),
        (0, 6, 3),
        (0, 8, 3),
        (0, 1, 3),
    ];

    /// A random tree of `joints + 1` bodies, its joints in a random order.
    fn random_tree(rng: &mut SplitMix64, joints: usize) -> Vec<(usize, usize, usize)> {
        let mut tree: Vec<(usize, usize, usize)> = (1..=joints)
            .map(|b| (rng.below(b), b, 1 + rng.below(6)))
            .collect();
        for k in (1..tree.len()).rev() {
            tree.swap(k, rng.below(k + 1));
        }
        tree
    }

    /// Case `case` of a test over islands: the ragdoll first, then random
    /// trees; its joints, bodies, profile, random rows and their factor.
    #[allow(clippy::type_complexity)] // a test case's parts, taken apart at once
    fn factored_case(
        rng: &mut SplitMix64,
        case: usize,
    ) -> (
        Vec<(usize, usize, usize)>,
        usize,
        Profile,
        Vec<SideRow<f64>>,
        Factor<f64>,
    ) {
        let size = 2 + rng.below(12);
        let joints = if case == 0 {
            RAGDOLL.to_vec()
        } else {
            random_tree(rng, size)
        };
        let bodies = joints.iter().map(|j| j.0.max(j.1)).max().unwrap() + 1;
        let profile = profile_of(&joints);
        let rows = rows_of(rng, &joints, bodies);
        let mut factor = Factor::default();
        factor.factor(&profile, &rows);
        (joints, bodies, profile, rows, factor)
    }

    /// The compiled factorization (`Program`) against the pattern's walk it
    /// replaces (kept for islands too large to compile): on the ragdoll
    /// and random trees, in one lane and in four, every entry of the
    /// factor and every reciprocal diagonal has the walk's bits.
    #[test]
    fn the_compiled_factorization_has_the_bits_of_the_patterns_walk() {
        let mut rng = SplitMix64(29);
        for case in 0..40 {
            let (joints, bodies, profile, rows, compiled) = factored_case(&mut rng, case);
            assert!(profile.pattern.program.is_some(), "case {case}: not compiled");
            let mut walked_profile = profile.clone();
            walked_profile.pattern.program = None;
            let mut walked = Factor::default();
            walked.factor(&walked_profile, &rows);
            let bits = |f: &Factor<f64>| -> Vec<u64> {
                f.values
                    .iter()
                    .chain(&f.inv_diagonal)
                    .map(|x| x.to_bits())
                    .collect()
            };
            assert_eq!(bits(&compiled), bits(&walked), "case {case}");
            // Four lanes: this case's rows and three other draws for it.
            let draws: Vec<Vec<SideRow<f64>>> = std::iter::once(rows)
                .chain((0..LANES - 1).map(|_| rows_of(&mut rng, &joints, bodies)))
                .collect();
            let lanes: Vec<SideRow<Lane>> = (0..profile.rows())
                .map(|r| {
                    let l = |f: &dyn Fn(&SideRow<f64>) -> f64| {
                        Lane::new(std::array::from_fn(|k| f(&draws[k][r])))
                    };
                    let p3 = |f: &dyn Fn(&SideRow<f64>) -> P3<f64>| P3 {
                        x: l(&|row| f(row).x),
                        y: l(&|row| f(row).y),
                        z: l(&|row| f(row).z),
                    };
                    SideRow {
                        lin: [p3(&|row| row.lin[0]), p3(&|row| row.lin[1])],
                        ang: [p3(&|row| row.ang[0]), p3(&|row| row.ang[1])],
                        mass: [l(&|row| row.mass[0]), l(&|row| row.mass[1])],
                        m_ang: [p3(&|row| row.m_ang[0]), p3(&|row| row.m_ang[1])],
                        gamma: l(&|row| row.gamma),
                    }
                })
                .collect();
            let (mut compiled, mut walked) = (Factor::<Lane>::default(), Factor::<Lane>::default());
            compiled.factor(&profile, &lanes);
            walked.factor(&walked_profile, &lanes);
            let bits = |f: &Factor<Lane>| -> Vec<u64> {
                let all = f.values.iter().chain(&f.inv_diagonal);
                all.flat_map(|x| x.to_array().map(f64::to_bits)).collect()
            };
            assert_eq!(bits(&compiled), bits(&walked), "case {case}, four lanes");
            // And each lane is the factor of its own rows alone.
            for (k, draw) in draws.iter().enumerate() {
                let mut alone = Factor::default();
                alone.factor(&profile, draw);
                let lane: Vec<u64> = compiled
                    .values
                    .iter()
                    .chain(&compiled.inv_diagonal)
                    .map(|x| x.to_array()[k].to_bits())
                    .collect();
                let alone: Vec<u64> = alone
                    .values
                    .iter()
                    .chain(&alone.inv_diagonal)
                    .map(|x| x.to_bits())
                    .collect();
                assert_eq!(lane, alone, "case {case}, lane {k}");
            }
        }
    }

    /// `Profile::reach` against brute force: for a column on one body's
    /// joints, the forward substitution over only the reached rows has the
    /// bits of the whole one, every row it skips is an exact zero of the
    /// whole one, and (for the ragdoll) a forearm's column skips the legs.
    #[test]
    fn a_forward_substitution_over_the_reached_rows_has_the_whole_ones_bits() {
        let mut rng = SplitMix64(11);
        let mut skipped = 0;
        for case in 0..40 {
            let (joints, bodies, profile, _, factor) = factored_case(&mut rng, case);
            let o = &profile.offsets;
            for body in 0..bodies {
                let on_body = |p: usize| joints[p].0 == body || joints[p].1 == body;
                let touched = (0..joints.len())
                    .filter(|&p| on_body(p))
                    .fold(0u64, |m, p| m | 1 << p);
                let reached = profile.reach(touched).unwrap();
                let mut w = vec![0.0; profile.rows()];
                for p in (0..joints.len()).filter(|&p| on_body(p)) {
                    w[o[p]..o[p + 1]]
                        .iter_mut()
                        .for_each(|x| *x = rng.range(-1.0, 1.0));
                }
                let mut whole = w.clone();
                factor.forward(&profile, &mut whole);
                let mut runs = Vec::new();
                profile.rows_of(reached, &mut runs);
                let mut part = w.clone();
                factor.forward_runs(&profile, &mut part, &runs);
                for (i, (a, b)) in whole.iter().zip(&part).enumerate() {
                    assert_eq!(a.to_bits(), b.to_bits(), "case {case}, body {body}, row {i}");
                }
                for p in (0..joints.len()).filter(|&p| (reached >> p) & 1 == 0) {
                    assert!(
                        whole[o[p]..o[p + 1]].iter().all(|&x| x.to_bits() == 0),
                        "case {case}"
                    );
                    skipped += o[p + 1] - o[p];
                }
                if case == 0 && body == 3 {
                    // The left forearm (body 3, joint 0): its elbow, both
                    // shoulders (they meet on the chest) and the spine; not
                    // the other elbow, the hips or the knees.
                    assert_eq!(reached, 1 << 0 | 1 << 4 | 1 << 5 | 1 << 8, "{reached:b}");
                }
            }
        }
        assert!(skipped > 0);
    }

    /// The pattern's symbolic factorization against a dense Cholesky of the
    /// same `K` (the brute-force oracle): every entry the pattern skips is
    /// an exact zero of the dense factor, the others agree, and solves with
    /// the factor agree with dense ones; `L^T` undoes the backward half.
    #[test]
    fn the_pattern_skips_only_zeros_of_the_factor() {
        let mut rng = SplitMix64(3);
        let mut skipped = 0;
        for case in 0..40 {
            let (joints, _, profile, rows, factor) = factored_case(&mut rng, case);
            let n = profile.rows();
            // K by brute force: rows on a shared body meet through it.
            let row_joint: Vec<usize> = (0..joints.len())
                .flat_map(|p| std::iter::repeat_n(p, joints[p].2))
                .collect();
            let mut k = vec![vec![0.0; n]; n];
            for i in 0..n {
                for j in 0..=i {
                    let (ji, jj) = (joints[row_joint[i]], joints[row_joint[j]]);
                    for (s, bi) in [ji.0, ji.1].into_iter().enumerate() {
                        for (t, bj) in [jj.0, jj.1].into_iter().enumerate() {
                            if bi == bj {
                                k[i][j] += rows[i].lin[s].dot(rows[j].m_lin(t))
                                    + rows[i].ang[s].dot(rows[j].m_ang[t]);
                            }
                        }
                    }
                }
                k[i][i] += 1e-12 * k[i][i].abs() + 1e-300;
            }
            let mut l = vec![vec![0.0; n]; n];
            for i in 0..n {
                for j in 0..=i {
                    let dot: f64 = (0..j).map(|c| l[i][c] * l[j][c]).sum();
                    l[i][j] = if i == j {
                        (k[i][i] - dot).max(1e-300).sqrt()
                    } else {
                        (k[i][j] - dot) / l[j][j]
                    };
                }
            }
            let mut live = 0;
            for i in 0..n {
                assert!(
                    (0..profile.first[i]).all(|j| l[i][j] == 0.0),
                    "case {case}: row {i} outside its profile"
                );
                let mut kept = vec![false; i + 1];
                let (at, runs) = (&profile.pattern.row_runs_at, &profile.pattern.row_runs);
                for &(from, to) in &runs[at[i]..at[i + 1]] {
                    kept[from..to].iter_mut().for_each(|k| *k = true);
                }
                kept[i] = true;
                for j in profile.first[i]..=i {
                    let ours = factor.values[profile.at(i, j)];
                    if kept[j] {
                        live += 1;
                        assert!(
                            (ours - l[i][j]).abs() <= 1e-9 * l[j][j].abs().max(1.0),
                            "case {case}: ({i}, {j})"
                        );
                    } else {
                        assert_eq!(l[i][j], 0.0, "case {case}: ({i}, {j}) skipped but not zero");
                        assert_eq!(ours.to_bits(), 0.0f64.to_bits());
                    }
                }
            }
            assert_eq!(live, profile.entries(), "case {case}");
            skipped += profile.size - live;
            // Solves against the dense factor, and L^T after L^-T.
            let rhs: Vec<f64> = (0..n).map(|_| rng.range(-1.0, 1.0)).collect();
            let mut x = rhs.clone();
            factor.solve(&profile, &mut x);
            let residual = (0..n)
                .map(|i| (0..n).map(|j| k[i.max(j)][i.min(j)] * x[j]).sum::<f64>() - rhs[i])
                .fold(0.0f64, |m, r| m.max(r.abs()));
            let scale = x.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            assert!(residual < 1e-9 * scale, "case {case}: residual {residual}");
            let mut z = rhs.clone();
            factor.backward(&profile, &mut z);
            factor.multiply_transposed(&profile, &mut z);
            for (a, b) in z.iter().zip(&rhs) {
                assert!((a - b).abs() < 1e-9, "case {case}: L^T L^-T is not the identity");
            }
        }
        assert!(skipped > 0, "no profile held a zero");
        let ragdoll = profile_of(&RAGDOLL);
        assert!(
            ragdoll.entries() * 10 < ragdoll.size * 7,
            "{} of {}",
            ragdoll.entries(),
            ragdoll.size
        );
    }
}
