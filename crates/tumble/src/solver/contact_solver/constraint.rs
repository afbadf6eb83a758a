//! The solver's contact data: one [`ManifoldConstraint`] per contact patch
//! (a body pair's points that share a normal direction) holding the patch
//! friction, and one [`PointConstraint`] per point holding its normal row.
//!
//! Patch friction (as PhysX's patch friction model and Bullet's friction
//! anchors): instead of two tangent rows at every point, the patch gets two
//! tangent rows at its centroid and one twist row about its normal, bounded
//! by `mu` times the patch's total normal impulse (and, for twist, times the
//! patch's mean radius). Per-point friction solved point after point makes
//! a sliding box yaw (each Gauss-Seidel update sees the others' residual
//! and the order is never symmetric); the patch rows see the whole patch at
//! once, cost three rows instead of eight for a four-point face, and give the
//! same Coulomb limit for sliding and sticking.
//!
//! Normals are fixed for the step (as in Box2D v3's soft step); the
//! separations, the lever arms and with them the effective masses follow
//! the bodies' motion from sub-step to sub-step (see
//! `passes::begin_substep` and [`refresh_masses`]).

use super::body::SolverBody;
use super::lanes::{Lane, LANES};
use tumble_collide::{DMat3, DVec3};

/// The angular part of one constraint row on both bodies, with the inverse
/// inertia applied (so that a row costs dot products only).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RowJacobian {
    /// `r_A x d`.
    pub ra_x_d: DVec3,
    /// `r_B x d`.
    pub rb_x_d: DVec3,
    /// `I_A^-1 (r_A x d)`.
    pub ia_ra_x_d: DVec3,
    /// `I_B^-1 (r_B x d)`.
    pub ib_rb_x_d: DVec3,
}

impl RowJacobian {
    /// The row of an impulse along `d` at lever arms `ra`, `rb`.
    #[inline]
    pub fn new(a: &SolverBody, b: &SolverBody, ra: DVec3, rb: DVec3, d: DVec3) -> RowJacobian {
        let ra_x_d = ra.cross(d);
        let rb_x_d = rb.cross(d);
        RowJacobian {
            ra_x_d,
            rb_x_d,
            ia_ra_x_d: a.inv_inertia * ra_x_d,
            ib_rb_x_d: b.inv_inertia * rb_x_d,
        }
    }

    /// A pure torque row about the unit `axis` (A turns about `+axis`, B
    /// about `-axis`): the twist row of patch friction.
    #[inline]
    pub fn twist(a: &SolverBody, b: &SolverBody, axis: DVec3) -> RowJacobian {
        RowJacobian {
            ra_x_d: axis,
            rb_x_d: axis,
            ia_ra_x_d: a.inv_inertia * axis,
            ib_rb_x_d: b.inv_inertia * axis,
        }
    }

    /// Inverse effective mass of the row for linear direction `d` (zero for
    /// a twist row) and inverse masses `ima`, `imb`.
    #[inline]
    pub fn inverse_mass(&self, d: DVec3, ima: f64, imb: f64) -> f64 {
        d.length_squared() * (ima + imb) + self.ra_x_d.dot(self.ia_ra_x_d) + self.rb_x_d.dot(self.ib_rb_x_d)
    }
}

/// One contact point: the normal row of the contact LCP (thesis 7.2).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[repr(C)]
pub struct PointConstraint {
    /// Unit normal from B to A (for the current sub-step: on a curved
    /// patch it turns within the step, see `ManifoldConstraint::curvature`).
    pub normal: DVec3,
    /// The normal at the step start.
    pub normal_start: DVec3,
    /// Anchor relative to A's centre of mass at the step start, world frame.
    pub r_a: DVec3,
    /// Anchor relative to B's centre of mass at the step start, world frame.
    pub r_b: DVec3,
    /// Signed separation at the start of the step (m), < 0 when overlapping.
    pub separation: f64,
    /// Separation for the current sub-step's poses (m).
    pub separation_now: f64,
    /// Accumulated normal impulse (N s), warm-started across steps.
    pub normal_impulse: f64,
    /// Largest normal impulse seen during the step (N s), bounces included.
    pub max_normal_impulse: f64,
    /// Accumulated push-out pseudo-impulse of the current sub-step.
    pub push_impulse: f64,
    /// Half the contact's gap at the step start (m; the narrow phase's
    /// distance, before any skin): the point lies this far from each
    /// surface, so a round side's centre of curvature is its radius plus
    /// this away (`rolling::Rolling::reach`). Default 0.
    pub half_gap: f64,
    // The row: written by `prepare` (or by the point's bundle, see
    // `prepare_patch`) before anything reads it, so that laying out the
    // records (`PointConstraint::renew`) need not touch its lines.
    /// Angular Jacobian of the normal row.
    pub row: RowJacobian,
    /// Effective mass along the normal (kg): 1 / (thesis 7.1 denominator).
    pub normal_mass: f64,
}

impl PointConstraint {
    /// This record made the point [`PointConstraint::new`] makes (which
    /// calls this on a zero record), with `half_gap`, except for its row
    /// and effective mass (`row`, `normal_mass`, last in the record), which
    /// keep whatever they held: `prepare_patch` writes them before anything
    /// reads them, or, for a point in a bundle, leaves them unread
    /// (`wide::WidePatch::fill`). (Like [`ManifoldConstraint::renew`]: the
    /// step lays its records out anew every step.)
    pub fn renew(
        &mut self,
        normal: DVec3,
        r_a: DVec3,
        r_b: DVec3,
        separation: f64,
        normal_impulse: f64,
        half_gap: f64,
    ) {
        self.normal = normal;
        self.normal_start = normal;
        self.r_a = r_a;
        self.r_b = r_b;
        self.separation = separation;
        self.separation_now = separation;
        self.normal_impulse = normal_impulse;
        self.max_normal_impulse = 0.0;
        self.push_impulse = 0.0;
        self.half_gap = half_gap;
    }

    /// A point at lever arms `r_a`, `r_b` (world, from the centres of mass)
    /// with unit `normal` (B to A) and signed `separation` (m), carrying a
    /// warm-start `normal_impulse`. Derived fields are filled by [`prepare`].
    pub fn new(
        normal: DVec3,
        r_a: DVec3,
        r_b: DVec3,
        separation: f64,
        normal_impulse: f64,
    ) -> PointConstraint {
        let mut point = PointConstraint::default();
        point.renew(normal, r_a, r_b, separation, normal_impulse, 0.0);
        point
    }
}

/// One contact patch of a body pair: its points and its friction.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[repr(C)]
pub struct ManifoldConstraint {
    /// Index of body A in the solver body array.
    pub a: u32,
    /// Index of body B.
    pub b: u32,
    /// First point of the patch in the point array.
    pub first_point: u32,
    /// Number of points (at least 1).
    pub point_count: u32,
    /// Coulomb friction coefficient of the pair.
    pub friction: f64,
    /// Restitution coefficient of the pair.
    pub restitution: f64,
    /// Unit patch normal (B to A): the friction plane is normal to it.
    pub normal: DVec3,
    /// Tangents of the friction plane and a zero vector for the twist row:
    /// the linear directions of the three friction rows.
    pub directions: [DVec3; 3],
    /// How the patch's normals and gaps turn as A's centres of curvature
    /// move relative to B within the step (1/m, symmetric, world frame at
    /// the step start; zero for a flat patch): a displacement `d` gives the
    /// normal `normalize(n + K d)` and the gap `s + n . d + d . K d / 2`
    /// (`SmoothSurface::path_curvature`: a ball in a tessellated bowl).
    /// Such a patch is re-aimed every sub-step by the scalar kernels.
    pub curvature: DMat3,
    /// The patch normal at the step start.
    pub normal_start: DVec3,
    /// Radii of the round surfaces of A and of B at the patch (m): a
    /// sphere's or a capsule's radius, 0 for faces, edges and corners. Its
    /// contacts roll with the round side within the step instead of staying
    /// on the bodies' material points (see `passes::begin_patch`). Default 0.
    pub rolling: [f64; 2],
    /// The points' mean `half_gap` (m), for the friction anchor's rolling.
    pub half_gap: f64,
    /// Friction anchor (the patch centroid) relative to A's centre of mass.
    pub r_a: DVec3,
    /// Friction anchor relative to B's centre of mass.
    pub r_b: DVec3,
    /// Mean distance of the points from the anchor in the friction plane
    /// (m): the lever of the twist friction.
    pub twist_radius: f64,
    /// Accumulated friction impulses: two tangential (N s) and the twist
    /// (N m s), warm-started across steps.
    pub impulses: [f64; 3],
    /// Inverse masses of A and B (1/kg).
    pub inv_mass: [f64; 2],
    /// Whether the patch holds an anchor from the last step (it stuck):
    /// the push-out then also pulls its two anchor points back together
    /// across the normal, within what friction has left (`passes::hold_anchor`).
    pub anchored: bool,
    /// The anchor points' lever arms from A's and B's centres of mass at the
    /// step start (world, m).
    pub anchor_r: [DVec3; 2],
    /// A's anchor point less B's at the step start (world, m).
    pub anchor_offset: DVec3,
    // The rows: written by `prepare` (or by the patch's bundle, see
    // `prepare_patch`) before anything reads them, so that laying out the
    // records (`ManifoldConstraint::renew`) need not touch their lines.
    /// Angular Jacobians of the two tangent rows and the twist row.
    pub rows: [RowJacobian; 3],
    /// Effective masses of the three friction rows (kg, kg m^2).
    pub masses: [f64; 3],
    /// The patch's block of the Delassus matrix `K = J M^-1 J^T` over its
    /// normal rows (`K[i][j]`: relative normal velocity change at point `i`
    /// per unit impulse at point `j`), filled for patches of at most
    /// [`BLOCK_POINTS`] points; the solver then solves the patch's normal
    /// rows together (see `passes::solve_block`).
    pub block: [[f64; BLOCK_POINTS]; BLOCK_POINTS],
    /// The inverse of `block + eps I` (`regularised_inverse`), for the
    /// direct all-points-pressing solve that `passes::solve_block` tries
    /// before its sweeps.
    pub block_inverse: [[f64; BLOCK_POINTS]; BLOCK_POINTS],
}

/// Patches with at most this many points solve their normal rows as one
/// block (a box face has four).
pub const BLOCK_POINTS: usize = 4;

/// A patch's block of normal rows, padded with zero rows to
/// [`BLOCK_POINTS`].
pub type PatchBlock = [[f64; BLOCK_POINTS]; BLOCK_POINTS];

impl ManifoldConstraint {
    /// A patch of `point_count` points from `first_point` between solver
    /// bodies `a` and `b`, with the pair's material, its friction plane
    /// normal to `normal`, and warm-start friction impulses given as a world
    /// vector (N s) and a twist (N m s). Derived fields are filled by
    /// [`prepare`].
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        a: u32,
        b: u32,
        first_point: u32,
        point_count: u32,
        normal: DVec3,
        friction: f64,
        restitution: f64,
        warm_tangent: DVec3,
        warm_twist: f64,
    ) -> ManifoldConstraint {
        let mut m = ManifoldConstraint::default();
        m.renew(
            a,
            b,
            first_point,
            point_count,
            normal,
            friction,
            restitution,
            warm_tangent,
            warm_twist,
        );
        m
    }

    /// This record made the patch [`ManifoldConstraint::new`] makes (which
    /// calls this on a zero record), except for the rows, their masses and
    /// the normal block (`rows`, `masses`, `block`, `block_inverse`, last
    /// in the record), which keep whatever they held:
    /// `prepare_patch` writes them before anything reads them, or, for a
    /// patch in a bundle, leaves them unread (`wide::WidePatch::fill`).
    ///
    /// Why: the step lays its records out anew every step, and those
    /// fields are over half of a record's lines.
    #[allow(clippy::too_many_arguments)]
    pub fn renew(
        &mut self,
        a: u32,
        b: u32,
        first_point: u32,
        point_count: u32,
        normal: DVec3,
        friction: f64,
        restitution: f64,
        warm_tangent: DVec3,
        warm_twist: f64,
    ) {
        let [t1, t2] = tangent_basis(normal);
        self.a = a;
        self.b = b;
        self.first_point = first_point;
        self.point_count = point_count;
        self.friction = friction;
        self.restitution = restitution;
        self.normal = normal;
        self.directions = [t1, t2, DVec3::ZERO];
        self.curvature = DMat3::ZERO;
        self.normal_start = normal;
        self.rolling = [0.0; 2];
        self.half_gap = 0.0;
        self.r_a = DVec3::ZERO;
        self.r_b = DVec3::ZERO;
        self.twist_radius = 0.0;
        self.impulses = [warm_tangent.dot(t1), warm_tangent.dot(t2), warm_twist];
        self.inv_mass = [0.0; 2];
        self.anchored = false;
        self.anchor_r = [DVec3::ZERO; 2];
        self.anchor_offset = DVec3::ZERO;
    }

    /// Marks a record that is not written this step (a bundled patch that
    /// does not bounce: `SolverArrays::prepare`) as a patch of no points,
    /// without restitution, between the immovable body and itself: what a
    /// pass over every record then finds there is nothing to do. Only the
    /// record's first cache line is written.
    pub fn leave_empty(&mut self) {
        self.a = 0;
        self.b = 0;
        self.first_point = 0;
        self.point_count = 0;
        self.restitution = 0.0;
    }

    /// The points of this patch.
    #[inline]
    pub fn range(&self) -> std::ops::Range<usize> {
        self.first_point as usize..(self.first_point + self.point_count) as usize
    }

    /// `true` when the patch's normals turn within the step (a non-zero
    /// [`curvature`](ManifoldConstraint::curvature)).
    #[inline]
    pub fn is_curved(&self) -> bool {
        self.curvature != DMat3::ZERO
    }

    /// The tangential friction impulse as a world vector (N s).
    pub fn tangent_impulse(&self) -> DVec3 {
        ManifoldConstraint::tangent_along(
            [self.directions[0], self.directions[1]],
            [self.impulses[0], self.impulses[1]],
        )
    }

    /// The tangential friction impulse of `impulses` along the friction
    /// `directions`, as a world vector (N s): [`ManifoldConstraint::tangent_impulse`]
    /// of a record, or of a bundle's lane.
    pub fn tangent_along(directions: [DVec3; 2], impulses: [f64; 2]) -> DVec3 {
        directions[0] * impulses[0] + directions[1] * impulses[1]
    }
}

/// Settings the solver reads (a subset of the world settings).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverParams {
    /// Fraction of the overlap beyond the allowance removed per sub-step.
    pub push_out_fraction: f64,
    /// Overlap left uncorrected (m).
    pub allowed_penetration: f64,
    /// Largest push-out speed (m/s).
    pub max_push_out_speed: f64,
    /// Approach speed below which restitution is ignored (m/s).
    pub restitution_threshold: f64,
}

/// Two unit tangents orthogonal to the unit `n`, right-handed (t1 x t2 = n).
pub fn tangent_basis(n: DVec3) -> [DVec3; 2] {
    // Pick the axis least aligned with n: deterministic and well conditioned.
    let t1 = if n.x.abs() < 0.57735 {
        DVec3::new(0.0, n.z, -n.y)
    } else {
        DVec3::new(n.y, -n.x, 0.0)
    }
    .normalize();
    [t1, n.cross(t1)]
}

/// Inverse effective mass of an impulse along `dir` at anchors `ra`, `rb`:
/// `1/Ma + 1/Mb + dir . (Ia^-1 (ra x dir)) x ra + dir . (Ib^-1 (rb x dir)) x rb`
/// (thesis 7.1).
pub fn inverse_effective_mass(a: &SolverBody, b: &SolverBody, ra: DVec3, rb: DVec3, dir: DVec3) -> f64 {
    let rna = ra.cross(dir);
    let rnb = rb.cross(dir);
    a.inv_mass + b.inv_mass + rna.dot(a.inv_inertia * rna) + rnb.dot(b.inv_inertia * rnb)
}

#[inline]
fn recip_or_zero(k: f64) -> f64 {
    if k > 0.0 {
        1.0 / k
    } else {
        0.0
    }
}

/// Fills the derived fields of a patch and its points from the bodies at the
/// step start: normal rows and masses, the friction anchor (centroid of the
/// points), the twist radius, and the friction rows and masses.
pub fn prepare(m: &mut ManifoldConstraint, points: &mut [PointConstraint], bodies: &[SolverBody]) {
    let range = m.range();
    prepare_patch(m, &mut points[range], bodies, true);
}

/// [`prepare`] given the patch's own points `pts`; without `rows`, only
/// what is not a row: the rows, their masses and the normal block are left
/// as they were, for a patch whose bundle computes them itself
/// (`wide::WidePatch::fill`, the same values lane by lane).
pub(super) fn prepare_patch(
    m: &mut ManifoldConstraint,
    pts: &mut [PointConstraint],
    bodies: &[SolverBody],
    rows: bool,
) {
    let a = &bodies[m.a as usize];
    let b = &bodies[m.b as usize];
    m.inv_mass = [a.inv_mass, b.inv_mass];
    let count = pts.len().max(1) as f64;
    let (mut ca, mut cb, mut gap) = (DVec3::ZERO, DVec3::ZERO, 0.0);
    for p in pts.iter_mut() {
        if rows {
            p.row = RowJacobian::new(a, b, p.r_a, p.r_b, p.normal);
        }
        p.separation_now = p.separation;
        p.max_normal_impulse = 0.0;
        p.push_impulse = 0.0;
        ca += p.r_a;
        cb += p.r_b;
        gap += p.half_gap;
    }
    m.r_a = ca / count;
    m.r_b = cb / count;
    m.half_gap = gap / count;
    let n = m.normal;
    m.twist_radius = pts
        .iter()
        .map(|p| {
            let d = p.r_a - m.r_a;
            (d - n * n.dot(d)).length()
        })
        .sum::<f64>()
        / count;
    if rows {
        for i in 0..2 {
            m.rows[i] = RowJacobian::new(a, b, m.r_a, m.r_b, m.directions[i]);
        }
        m.rows[2] = RowJacobian::twist(a, b, n);
        refresh_masses(m, pts, true);
    }
}

/// Effective masses of a patch's rows and its normal block (with its
/// inverse) for the rows' present Jacobians. `prepare` calls it once; a
/// sub-step that re-aims the lever arms calls it again, because an impulse
/// sized with the masses of other lever arms overshoots: where a row's
/// inverse mass has grown (a fast body whose anchor has travelled far from
/// the contact turns far more easily about it) the update `-m (v + bias)`
/// reverses the velocity by more than it removed, which feeds energy in
/// (a 10 cm box at 120 m/s gained a factor 10^6 in one step).
///
/// The row masses cost a division each and are always refreshed; the block
/// and its inverse (most of the cost) only when some point's inverse mass
/// has moved by more than [`BLOCK_REFRESH`] of the one the block was built
/// with, or when `force`. A block that far
/// behind its rows over-relaxes the solve by at most that fraction, which
/// converges (Gauss-Seidel converges up to twice the exact step).
///
/// Returns whether some point's mass moved that far (the rows have turned
/// with the bodies since the block was built or, for a larger patch, since
/// the last sub-step).
pub fn refresh_masses(m: &mut ManifoldConstraint, pts: &mut [PointConstraint], force: bool) -> bool {
    let [ima, imb] = m.inv_mass;
    let blocked = pts.len() <= BLOCK_POINTS;
    let mut turned = false;
    for (i, p) in pts.iter_mut().enumerate() {
        let k = p.row.inverse_mass(p.normal, ima, imb);
        // The block's diagonal holds each point's inverse mass as it was
        // when the block was built.
        let reference = if blocked {
            m.block[i][i]
        } else {
            recip_or_zero(p.normal_mass)
        };
        turned |= (k - reference).abs() > BLOCK_REFRESH * reference;
        p.normal_mass = recip_or_zero(k);
    }
    let stale = force || turned;
    for i in 0..3 {
        m.masses[i] = recip_or_zero(m.rows[i].inverse_mass(m.directions[i], ima, imb));
    }
    if stale && blocked {
        // K_ij = (n_i . n_j)(1/mA + 1/mB) + (rA_i x n_i) . IA^-1 (rA_j x n_j)
        //      + (rB_i x n_i) . IB^-1 (rB_j x n_j), zero beyond the points
        // (whatever the record held there: `ManifoldConstraint::renew`).
        let mut block = [[0.0; BLOCK_POINTS]; BLOCK_POINTS];
        for (i, pi) in pts.iter().enumerate() {
            for (j, pj) in pts.iter().enumerate() {
                block[i][j] = pi.normal.dot(pj.normal) * (ima + imb)
                    + pi.row.ra_x_d.dot(pj.row.ia_ra_x_d)
                    + pi.row.rb_x_d.dot(pj.row.ib_rb_x_d);
            }
        }
        m.block = block;
        m.block_inverse = regularised_inverse(&m.block);
    }
    turned
}

/// Relative change of a point's effective mass beyond which a sub-step
/// rebuilds its patch's normal block (see [`refresh_masses`]).
pub const BLOCK_REFRESH: f64 = 0.1;

/// Cholesky factor of `k + eps I`, `eps` a billionth of the largest
/// diagonal entry, with reciprocal pivots on the diagonal.
///
/// Why regularise: the four corners of a face see only three independent
/// motions (along the normal and two tilts), so a face's block is singular
/// and a plain factorisation breaks down. With `eps` the solve returns the
/// least-norm split of the load over the corners, which is the symmetric
/// one; velocities differ from the exact answer by `eps` relative.
/// Padding rows (all zero) get the pivot `eps` and a zero solution.
///
/// `wide::regularised_cholesky` is this routine lane by lane, written alike
/// line for line so that the two can be checked to give the same bits.
#[allow(clippy::needless_range_loop)] // index form mirrors the textbook algorithm
pub fn regularised_cholesky(k: &[[f64; BLOCK_POINTS]; BLOCK_POINTS]) -> [[f64; BLOCK_POINTS]; BLOCK_POINTS] {
    let largest = (0..BLOCK_POINTS).fold(0.0f64, |x, i| x.max(k[i][i]));
    let eps = 1e-9 * largest + f64::MIN_POSITIVE;
    let mut l = [[0.0; BLOCK_POINTS]; BLOCK_POINTS];
    for j in 0..BLOCK_POINTS {
        let mut diag = k[j][j] + eps;
        for p in 0..j {
            diag -= l[j][p] * l[j][p];
        }
        // Rounding can only shrink a pivot of a positive definite matrix to
        // around eps; never let it reach zero or below.
        let pivot = diag.max(eps).sqrt();
        l[j][j] = 1.0 / pivot;
        for i in j + 1..BLOCK_POINTS {
            let mut v = k[i][j];
            for p in 0..j {
                v -= l[i][p] * l[j][p];
            }
            l[i][j] = v / pivot;
        }
    }
    l
}

/// The inverse of `k + eps I` (as [`regularised_cholesky`] regularises),
/// from the factor: [`cholesky_solve`] on the four unit columns side by
/// side, column `j` in lane `j`, each lane by the scalar solve's operations
/// in its order (the bits of one column at a time, a quarter of the work).
///
/// Why an explicit inverse: the solver applies it once or twice per patch
/// per pass, and a product with a 4 x 4 matrix is four independent dot
/// products, where the two triangular solves are a chain of dependent
/// steps (a patch's direct solve was bound by that chain's latency).
#[allow(clippy::needless_range_loop)] // index form mirrors `cholesky_solve`
pub fn regularised_inverse(k: &[[f64; BLOCK_POINTS]; BLOCK_POINTS]) -> [[f64; BLOCK_POINTS]; BLOCK_POINTS] {
    const _: () = assert!(BLOCK_POINTS == LANES, "one unit column a lane");
    let l = regularised_cholesky(k);
    let mut y = [Lane::ZERO; BLOCK_POINTS];
    for i in 0..BLOCK_POINTS {
        let mut v = Lane::new(std::array::from_fn(|j| if i == j { 1.0 } else { 0.0 }));
        for p in 0..i {
            v -= Lane::splat(l[i][p]) * y[p];
        }
        y[i] = v * Lane::splat(l[i][i]);
    }
    let mut x = [Lane::ZERO; BLOCK_POINTS];
    for i in (0..BLOCK_POINTS).rev() {
        let mut v = y[i];
        for p in i + 1..BLOCK_POINTS {
            v -= Lane::splat(l[p][i]) * x[p];
        }
        x[i] = v * Lane::splat(l[i][i]);
    }
    // Row i of the inverse is the lanes of x[i] (column j in lane j).
    x.map(|row| row.to_array())
}

/// `m x` for a 4 x 4 matrix, each row's dot product on its own.
#[inline(always)]
pub fn mat4_mul(m: &[[f64; BLOCK_POINTS]; BLOCK_POINTS], x: &[f64; BLOCK_POINTS]) -> [f64; BLOCK_POINTS] {
    std::array::from_fn(|i| {
        let r = &m[i];
        (r[0] * x[0] + r[1] * x[1]) + (r[2] * x[2] + r[3] * x[3])
    })
}

/// Solves `(k + eps I) x = rhs` with the factor from [`regularised_cholesky`]:
/// the one-column solve that [`regularised_inverse`] runs on four columns at
/// once (the tests hold the two to the same bits).
#[cfg(test)]
#[allow(clippy::needless_range_loop)]
pub fn cholesky_solve(
    l: &[[f64; BLOCK_POINTS]; BLOCK_POINTS],
    rhs: [f64; BLOCK_POINTS],
) -> [f64; BLOCK_POINTS] {
    let mut y = [0.0; BLOCK_POINTS];
    for i in 0..BLOCK_POINTS {
        let mut v = rhs[i];
        for p in 0..i {
            v -= l[i][p] * y[p];
        }
        y[i] = v * l[i][i];
    }
    let mut x = [0.0; BLOCK_POINTS];
    for i in (0..BLOCK_POINTS).rev() {
        let mut v = y[i];
        for p in i + 1..BLOCK_POINTS {
            v -= l[p][i] * x[p];
        }
        x[i] = v * l[i][i];
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_testkit::{RandomSource, SplitMix64};

    /// `regularised_inverse` gives, column by column, the bits of
    /// `cholesky_solve` on the unit columns, and is the inverse of the
    /// regularised block: on the blocks a patch makes (`G M^-1 G^T` of up to
    /// four points, a face's singular one included, padding rows of zeros)
    /// and on random positive definite ones. Checked to fail with a lane's
    /// column taken from its neighbour.
    #[test]
    #[allow(clippy::needless_range_loop)] // (i, j) index k, inv and the columns at once
    fn the_inverse_in_lanes_is_the_column_by_column_inverse() {
        let mut rng = SplitMix64(7);
        for case in 0..400 {
            let points = 1 + case % BLOCK_POINTS;
            // Rows of a patch's Jacobian on one body's six velocities (a
            // face's four corners see only three motions: a singular block).
            let normal = rng.vec3(1.0).normalize();
            let rows: Vec<[f64; 6]> = (0..points)
                .map(|_| {
                    let r = if case % 2 == 0 {
                        rng.vec3(0.5) - normal * 0.5
                    } else {
                        DVec3::new(rng.range(-0.5, 0.5), rng.range(-0.5, 0.5), -0.5)
                    };
                    let n = if case % 2 == 0 { normal } else { DVec3::Z };
                    let a = r.cross(n);
                    [n.x, n.y, n.z, a.x, a.y, a.z]
                })
                .collect();
            let inv_mass = rng.range(0.1, 2.0);
            let inv_inertia = rng.range(0.1, 5.0);
            let mut k = [[0.0; BLOCK_POINTS]; BLOCK_POINTS];
            for i in 0..points {
                for j in 0..points {
                    let lin: f64 = (0..3).map(|c| rows[i][c] * rows[j][c]).sum();
                    let ang: f64 = (3..6).map(|c| rows[i][c] * rows[j][c]).sum();
                    k[i][j] = inv_mass * lin + inv_inertia * ang;
                }
            }
            if case % 5 == 0 {
                // A random positive definite block instead.
                let g: [[f64; BLOCK_POINTS]; BLOCK_POINTS] =
                    std::array::from_fn(|_| std::array::from_fn(|_| rng.range(-1.0, 1.0)));
                for i in 0..BLOCK_POINTS {
                    for j in 0..BLOCK_POINTS {
                        k[i][j] = (0..BLOCK_POINTS).map(|c| g[i][c] * g[j][c]).sum::<f64>()
                            + if i == j { 0.1 } else { 0.0 };
                    }
                }
            }
            let inv = regularised_inverse(&k);
            let l = regularised_cholesky(&k);
            for j in 0..BLOCK_POINTS {
                let column = cholesky_solve(&l, std::array::from_fn(|i| if i == j { 1.0 } else { 0.0 }));
                for i in 0..BLOCK_POINTS {
                    assert_eq!(
                        inv[i][j].to_bits(),
                        column[i].to_bits(),
                        "case {case}: entry ({i}, {j})"
                    );
                }
            }
            // (k + eps I) inv = I, to the factor's accuracy.
            let largest = (0..BLOCK_POINTS).fold(0.0f64, |x, i| x.max(k[i][i]));
            let eps = 1e-9 * largest + f64::MIN_POSITIVE;
            let size = inv.iter().flatten().fold(0.0f64, |x, y| x.max(y.abs()));
            for i in 0..BLOCK_POINTS {
                for j in 0..BLOCK_POINTS {
                    let kk = |a: usize, b: usize| k[a][b] + if a == b { eps } else { 0.0 };
                    let product: f64 = (0..BLOCK_POINTS).map(|c| kk(i, c) * inv[c][j]).sum();
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!(
                        (product - want).abs() <= 1e-6 * (1.0 + largest * size),
                        "case {case}: ((k + eps) inv)[{i}][{j}] = {product}"
                    );
                }
            }
        }
    }
}
