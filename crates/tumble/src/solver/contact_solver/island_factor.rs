//! The numbers of a joint island's direct solve (`joint_island`): the
//! system `K = J M^-1 J^T` assembled block by block over the pairs of
//! joints that share a dynamic body, its Cholesky factor over the system's
//! profile (skyline), and solves with that factor.
//!
//! Written once over the number type [`Num`]: `f64` for one island, and
//! the solver's [`Lane`] for four islands of the same shape at once (a pile
//! of ragdolls: the same joints between the same limbs), one per lane.
//! Every lane performs the IEEE operations of the `f64` code in the same
//! order, nothing fused into a multiply-add, so an island factored in a
//! lane gets the bits it gets alone.

use super::joint::JointRow;
use super::lanes::{Lane, LANES};
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

/// One row of an island's system by body side (A, B): its Jacobian, and
/// the Jacobian times the side's inverse mass and inertia; the row's
/// softness (motors).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct SideRow<N> {
    lin: [P3<N>; 2],
    ang: [P3<N>; 2],
    m_lin: [P3<N>; 2],
    m_ang: [P3<N>; 2],
    gamma: N,
}

impl SideRow<f64> {
    /// The sides of joint row `r` (`lin . (vA - vB) + ang_a . wA + ang_b .
    /// wB`) between bodies of inverse masses `ma` and `mb`.
    pub fn new(r: &JointRow, ma: f64, mb: f64) -> SideRow<f64> {
        SideRow {
            lin: [r.lin.into(), (-r.lin).into()],
            ang: [r.ang_a.into(), r.ang_b.into()],
            m_lin: [(r.lin * ma).into(), (-r.lin * mb).into()],
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
            m_lin: [(lin * inv_mass).into(), P3::default()],
            m_ang: [ia.into(), P3::default()],
            gamma: 0.0,
        }
    }

    /// `K`'s entry between this row on side `s` and `other` on side `t`
    /// of the same body (`J_s M^-1 J_t^T`).
    pub fn meets(&self, s: usize, other: &SideRow<f64>, t: usize) -> f64 {
        self.lin[s].dot(other.m_lin[t]) + self.ang[s].dot(other.m_ang[t])
    }
}

impl SideRow<f64> {
    /// The velocity a unit impulse of this row gives, on side `s`, to a
    /// contact row of normal `n` and angular part `r_x_n` on that body
    /// (`n . dv + (r x n) . dw`).
    pub fn moves(&self, s: usize, n: DVec3, r_x_n: DVec3) -> f64 {
        P3::from(n).dot(self.m_lin[s]) + P3::from(r_x_n).dot(self.m_ang[s])
    }

    /// This row's velocity from a change `dv`, `dw` of side `s`'s body.
    pub fn measures(&self, s: usize, dv: DVec3, dw: DVec3) -> f64 {
        self.lin[s].dot(dv.into()) + self.ang[s].dot(dw.into())
    }
}

impl SideRow<Lane> {
    /// One row per lane.
    #[inline(always)]
    pub fn from_lanes(rows: [&SideRow<f64>; LANES]) -> SideRow<Lane> {
        #[inline(always)]
        fn pick<F: Fn(&SideRow<f64>) -> P3<f64>>(rows: &[&SideRow<f64>; LANES], f: F) -> P3<Lane> {
            let v = rows.map(f);
            P3 {
                x: Lane::new(v.map(|p| p.x)),
                y: Lane::new(v.map(|p| p.y)),
                z: Lane::new(v.map(|p| p.z)),
            }
        }
        SideRow {
            lin: [pick(&rows, |r| r.lin[0]), pick(&rows, |r| r.lin[1])],
            ang: [pick(&rows, |r| r.ang[0]), pick(&rows, |r| r.ang[1])],
            m_lin: [pick(&rows, |r| r.m_lin[0]), pick(&rows, |r| r.m_lin[1])],
            m_ang: [pick(&rows, |r| r.m_ang[0]), pick(&rows, |r| r.m_ang[1])],
            gamma: Lane::new(rows.map(|r| r.gamma)),
        }
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

/// The shape of an island's system: which rows belong to which joint,
/// which blocks are not zero, and the profile of the factor. Islands of
/// the same shape can share a lane set.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(super) struct Profile {
    /// First row of each joint (and the number of rows last).
    pub offsets: Vec<usize>,
    /// The blocks of `K` that are not zero.
    pub couplings: Vec<Coupling>,
    /// Per row: the first column of its profile.
    pub first: Vec<usize>,
    /// Per row: where its profile starts in the factor.
    pub start: Vec<usize>,
    /// Entries of the factor.
    pub size: usize,
}

impl Profile {
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
                    *kij = *kij + (ri_lin.dot(rj.m_lin[t]) + ri_ang.dot(rj.m_ang[t]));
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
        // start[i] (`done`).
        for i in 0..n {
            let (fi, si) = (first[i], start[i]);
            let (done, row_i) = k.split_at_mut(si);
            let row_i = &mut row_i[..i + 1 - fi];
            for j in fi..i {
                let (fj, sj) = (first[j], start[j]);
                let lo = fi.max(fj);
                let (ours, theirs) = row_i.split_at_mut(j - fi);
                let mut dot = N::default();
                for (a, b) in ours[lo - fi..].iter().zip(&done[sj + lo - fj..sj + j - fj]) {
                    dot = dot + *a * *b;
                }
                theirs[0] = (theirs[0] - dot) * self.inv_diagonal[j];
            }
            let (ours, diagonal) = row_i.split_at_mut(i - fi);
            let mut dot = N::default();
            for a in ours.iter() {
                dot = dot + *a * *a;
            }
            let d = (diagonal[0] - dot).max(N::splat(1e-300)).sqrt();
            self.inv_diagonal[i] = N::splat(1.0) / d;
            diagonal[0] = d;
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
        let (first, start, l) = (&profile.first, &profile.start, &self.values);
        for i in 0..profile.rows() {
            let (fi, si) = (first[i], start[i]);
            let mut dot = X::default();
            for (v, w) in l[si..si + i - fi].iter().zip(&x[fi..i]) {
                dot = dot + *w * *v;
            }
            x[i] = (x[i] - dot) * self.inv_diagonal[i];
        }
        for i in (0..profile.rows()).rev() {
            let (fi, si) = (first[i], start[i]);
            x[i] = x[i] * self.inv_diagonal[i];
            let xi = x[i];
            for (v, w) in x[fi..i].iter_mut().zip(&l[si..si + i - fi]) {
                *v = *v - xi * *w;
            }
        }
    }
}
