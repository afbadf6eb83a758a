//! The passes of one sub-step over the contact patches: separation update
//! and warm start, the velocity solve (patch friction, then normal rows), and
//! the split-impulse push-out. Each pass is a kernel over one patch (it keeps
//! the two bodies' velocities in registers across the patch's rows), run
//! over the patches in order by the whole-array functions here, or over the
//! colour batches on the world's threads by `batches`.
//!
//! The kernels read and write bodies through a [`Shared`] view: within one
//! colour no two patches share a dynamic body, and a kernel writes dynamic
//! bodies only, so patches of one colour can run at once.
//!
//! `wide` holds the four-lane twins of these kernels (its `begin`, `solve`,
//! `direct_block`, ...), written to read like them line by line so that the
//! two can be checked against each other (see its module note).

use super::body::SolverBody;
use super::coloring::Shared;
use super::constraint::{
    mat4_mul, refresh_masses, ManifoldConstraint, PatchBlock, PointConstraint, RowJacobian, SolverParams,
    BLOCK_POINTS,
};
use super::island_contacts::ArticulatedBlock;
use super::rolling::{turn_friction_plane, Rolling};
use tumble_collide::{DMat3, DVec3};

/// Velocities of a patch's two bodies while its rows are solved.
#[derive(Clone, Copy)]
struct PairVelocity {
    va: DVec3,
    wa: DVec3,
    vb: DVec3,
    wb: DVec3,
}

impl PairVelocity {
    /// # Safety
    /// No other thread writes the patch's bodies meanwhile.
    #[inline(always)]
    unsafe fn load(bodies: &Shared<SolverBody>, m: &ManifoldConstraint) -> PairVelocity {
        // SAFETY: the caller's promise.
        let (a, b) = unsafe { (bodies.get(m.a as usize), bodies.get(m.b as usize)) };
        PairVelocity::of(a, b)
    }

    #[inline(always)]
    fn of(a: &SolverBody, b: &SolverBody) -> PairVelocity {
        PairVelocity {
            va: a.v,
            wa: a.w,
            vb: b.v,
            wb: b.w,
        }
    }

    /// Writes back the velocities of the dynamic bodies (static, sleeping
    /// and kinematic bodies have zero inverse mass and inertia: impulses do
    /// not change them, and they are shared by patches of one colour).
    ///
    /// # Safety
    /// The patch's dynamic bodies are this thread's alone meanwhile.
    #[inline(always)]
    unsafe fn store(&self, bodies: &Shared<SolverBody>, m: &ManifoldConstraint) {
        // SAFETY: the caller's promise; only dynamic bodies are written.
        unsafe {
            if bodies.get(m.a as usize).dynamic {
                let a = bodies.get_mut(m.a as usize);
                a.v = self.va;
                a.w = self.wa;
            }
            if bodies.get(m.b as usize).dynamic {
                let b = bodies.get_mut(m.b as usize);
                b.v = self.vb;
                b.w = self.wb;
            }
        }
    }

    /// `self + (to - self) t`.
    #[inline(always)]
    fn lerp(&self, to: &PairVelocity, t: f64) -> PairVelocity {
        PairVelocity {
            va: self.va + (to.va - self.va) * t,
            wa: self.wa + (to.wa - self.wa) * t,
            vb: self.vb + (to.vb - self.vb) * t,
            wb: self.wb + (to.wb - self.wb) * t,
        }
    }

    /// Relative velocity along a row: `d . (vA - vB) + (rA x d) . wA - (rB x d) . wB`.
    #[inline(always)]
    fn along(&self, d: DVec3, ra_x_d: DVec3, rb_x_d: DVec3) -> f64 {
        d.dot(self.va - self.vb) + ra_x_d.dot(self.wa) - rb_x_d.dot(self.wb)
    }

    /// Applies `lambda` along a row: `+lambda d` on A, `-lambda d` on B.
    #[inline(always)]
    fn apply(&mut self, d: DVec3, ia: DVec3, ib: DVec3, inv_mass: [f64; 2], lambda: f64) {
        self.va += d * (lambda * inv_mass[0]);
        self.wa += ia * lambda;
        self.vb -= d * (lambda * inv_mass[1]);
        self.wb -= ib * lambda;
    }
}

/// Starts a sub-step: refreshes each point's separation for the bodies'
/// current poses, `s = s0 + n . ((dpA + R_A rA - rA) - (dpB + R_B rB - rB))`
/// with `R` each body's rotation since the step start, re-aims the rows'
/// lever arms at the contact as it is now (below), clears the push-out
/// impulses, and, with `warm`, applies the accumulated impulses (warm
/// start, Catto 2005).
///
/// Lever arms: a point's two anchors move apart as the bodies slide and turn
/// within the step. Each row is applied at one world point shared by both
/// bodies, the midpoint of the anchors in their current places, with the
/// current inverse inertia: an impulse and its reaction then act along one
/// line, so every impulse conserves linear and angular momentum exactly.
/// (Rows kept at the step start's lever arms would not: their error in
/// angular momentum is the bodies' relative displacement times the impulse.)
/// Normals stay those of the step start (but on a curved patch, see
/// below); the effective masses follow the re-aimed rows ([`refresh_masses`]).
///
/// Round sides (`ManifoldConstraint::rolling`): a ball does not touch the
/// ground with a material point of its own; it touches with whichever of its
/// points is lowest now, straight below its centre. Its anchor is then the
/// centre of curvature (fixed in the body) moved by the body and offset back
/// along the normal by the radius, and the shared point is that anchor alone
/// when only one side is round (the flat side's material point stays behind
/// as the ball rolls or slides on). Kept on material points, a rolling
/// ball's anchor lifts off the ground by `r (1 - cos wt)` within a step (a
/// gap that is not there), and the shared point lags half the ball's travel
/// behind its centre, so that normal impulses spin even a frictionless ball
/// (measured: a ball swinging in a bowl gained 4 % of its energy per swing).
pub fn begin_substep(
    manifolds: &mut [ManifoldConstraint],
    points: &mut [PointConstraint],
    bodies: &mut [SolverBody],
    warm: bool,
) {
    // `solve` and `push_out` drive their kernels with this same loop, and
    // `solve_patch` opens with `begin_patch`'s head: each wrapper keeps its
    // kernel's unsafe call in view instead of behind a closure-taking driver.
    let bodies = Shared::new(bodies);
    for m in manifolds.iter_mut() {
        let pts = &mut points[m.range()];
        // SAFETY: one thread.
        unsafe { begin_patch(m, pts, &bodies, warm) };
    }
}

/// [`begin_substep`] for one patch and its points.
///
/// # Safety
/// The patch's dynamic bodies are this thread's alone meanwhile.
#[inline(always)]
pub(super) unsafe fn begin_patch(
    m: &mut ManifoldConstraint,
    pts: &mut [PointConstraint],
    bodies: &Shared<SolverBody>,
    warm: bool,
) {
    // SAFETY: the caller's promise.
    let (a, b) = unsafe { (bodies.get(m.a as usize), bodies.get(m.b as usize)) };
    let (dpa, ta, dpb, tb) = (a.dp, a.turn, b.dp, b.turn);
    let moved = dpa != DVec3::ZERO || dpb != DVec3::ZERO || ta != DMat3::IDENTITY || tb != DMat3::IDENTITY;
    let roll = Rolling::of(m.rolling);
    let curved = m.is_curved();
    let mut turned = false;
    for p in pts.iter_mut() {
        // A round side's anchor and how far its centre of curvature is.
        let rolling = roll.map(|r| (r, r.reach(p.half_gap)));
        let (ra_now, rb_now) = match rolling {
            Some((r, reach)) => r.anchors(ta, tb, p.r_a, p.r_b, p.normal_start, reach),
            None => (ta * p.r_a, tb * p.r_b),
        };
        let d = (dpa + ra_now - p.r_a) - (dpb + rb_now - p.r_b);
        if curved {
            // The surface turns under the moving centre: second order in d.
            let kd = m.curvature * d;
            p.normal = (p.normal_start + kd).normalize_or(p.normal_start);
            p.separation_now = p.separation + p.normal_start.dot(d) + 0.5 * d.dot(kd);
        } else {
            p.separation_now = p.separation + p.normal.dot(d);
        }
        p.push_impulse = 0.0;
        if moved {
            let (ra, rb) = match rolling {
                Some((r, reach)) => {
                    let (ra_now, rb_now) = r.touching(ra_now, rb_now, p.normal_start, p.normal, reach);
                    r.shared_lever_arms(p.r_a, p.r_b, ra_now, rb_now, dpa, dpb)
                }
                None => shared_lever_arms(p.r_a, p.r_b, ra_now, rb_now, dpa, dpb),
            };
            p.row = RowJacobian::new(a, b, ra, rb, p.normal);
        }
    }
    if moved {
        let rolling = roll.map(|r| (r, r.reach(m.half_gap)));
        let (ra_now, rb_now) = match rolling {
            Some((r, reach)) => r.anchors(ta, tb, m.r_a, m.r_b, m.normal_start, reach),
            None => (ta * m.r_a, tb * m.r_b),
        };
        if curved {
            let d = (dpa + ra_now - m.r_a) - (dpb + rb_now - m.r_b);
            turn_friction_plane(m, (m.normal_start + m.curvature * d).normalize_or(m.normal_start));
        }
        let (ra, rb) = match rolling {
            Some((r, reach)) => {
                let (ra_now, rb_now) = r.touching(ra_now, rb_now, m.normal_start, m.normal, reach);
                r.shared_lever_arms(m.r_a, m.r_b, ra_now, rb_now, dpa, dpb)
            }
            None => shared_lever_arms(m.r_a, m.r_b, ra_now, rb_now, dpa, dpb),
        };
        for i in 0..2 {
            m.rows[i] = RowJacobian::new(a, b, ra, rb, m.directions[i]);
        }
        m.rows[2] = RowJacobian::twist(a, b, m.normal);
        turned = refresh_masses(m, pts, false);
    }
    if warm {
        // SAFETY: the caller's promise.
        let before = unsafe { PairVelocity::load(bodies, m) };
        let mut vel = before;
        // sum lambda_i u_i over the rows, u_i the row's relative velocity.
        let work = |vel: &PairVelocity, pts: &[PointConstraint], m: &ManifoldConstraint| {
            let normal: f64 = pts
                .iter()
                .map(|p| p.normal_impulse * vel.along(p.normal, p.row.ra_x_d, p.row.rb_x_d))
                .sum();
            let friction: f64 = (0..3)
                .map(|i| m.impulses[i] * vel.along(m.directions[i], m.rows[i].ra_x_d, m.rows[i].rb_x_d))
                .sum();
            normal + friction
        };
        let work_before = if turned { work(&vel, pts, m) } else { 0.0 };
        for p in pts.iter() {
            vel.apply(
                p.normal,
                p.row.ia_ra_x_d,
                p.row.ib_rb_x_d,
                m.inv_mass,
                p.normal_impulse,
            );
        }
        for (i, row) in m.rows.iter().enumerate() {
            vel.apply(
                m.directions[i],
                row.ia_ra_x_d,
                row.ib_rb_x_d,
                m.inv_mass,
                m.impulses[i],
            );
        }
        let scale = if turned {
            energy_safe_scale(work_before, work(&vel, pts, m))
        } else {
            1.0
        };
        if scale < 1.0 {
            vel = before.lerp(&vel, scale);
            for p in pts.iter_mut() {
                p.normal_impulse *= scale;
            }
            for impulse in &mut m.impulses {
                *impulse *= scale;
            }
        }
        // SAFETY: the caller's promise.
        unsafe { vel.store(bodies, m) };
    }
}

/// The largest fraction `alpha` in `[0, 1]` of a patch's warm start that
/// does not add kinetic energy to its two bodies, applied where the patch's
/// rows have turned since its impulses were accumulated (see
/// [`refresh_masses`]): a patch of a stack is left alone, since there a
/// warm start may lift a body that the next patch's holds down.
///
/// Applying impulses `lambda` along rows `J` changes the pair's kinetic
/// energy by `lambda . (u0 + u1) / 2`, with `u0` and `u1` the rows'
/// relative velocities before and after (`u1 = u0 + K lambda`); for a
/// fraction `alpha` that is `alpha a + alpha^2 b / 2` with
/// `a = lambda . u0` and `b = lambda . (u1 - u0) >= 0`, which is at most
/// zero for `alpha <= -2 a / b`. A resting contact's warm start meets the
/// bodies' approach under load (`a < 0`, `alpha` about 2: kept whole); the
/// sub-step after an impact would re-apply the whole stopping impulse to
/// bodies already at rest (`a` about 0: dropped), and where the rows have
/// turned with a fast-spinning body since they were accumulated, re-applied
/// whole they would throw it back faster than it came (a ball at 1,000 m/s
/// into a mesh slab left with 50 times its energy).
#[inline(always)]
fn energy_safe_scale(work_before: f64, work_after: f64) -> f64 {
    if work_before + work_after <= 0.0 {
        return 1.0;
    }
    let b = work_after - work_before;
    if work_before < 0.0 && b > 0.0 {
        (-2.0 * work_before / b).min(1.0)
    } else {
        0.0
    }
}

/// Lever arms from A's and B's current centres of mass to the midpoint of a
/// contact's two anchors, given the step-start lever arms `ra0`, `rb0` (one
/// world point then), their turned versions `ra`, `rb`, and the centres'
/// displacements `dpa`, `dpb` since the step start. Since `xB0 - xA0 =
/// ra0 - rb0`, the centres are now `ab = ra0 - rb0 + dpb - dpa` apart.
#[inline(always)]
fn shared_lever_arms(ra0: DVec3, rb0: DVec3, ra: DVec3, rb: DVec3, dpa: DVec3, dpb: DVec3) -> (DVec3, DVec3) {
    let ab = ra0 - rb0 + dpb - dpa;
    let ra_mid = (ra + rb + ab) * 0.5;
    (ra_mid, ra_mid - ab)
}

// The driver of `begin_substep` above with this pass's kernel: each pass keeps
// its own one-thread loop over its `*_patch` kernel (the one `batches` runs on
// colours), since the kernels take different arguments.
/// One Gauss-Seidel pass over all patches on the real velocities: first
/// the patch's friction within the Coulomb limit of its current total normal
/// impulse, then for every point the LCP row of thesis 7.2,
/// `v_n + bias >= 0, lambda >= 0`, complementary (touching points may not
/// approach; points with a gap `s` may close it within the sub-step `h` but
/// not more: `bias = s / h`).
///
/// Why friction first: the normal rows then have the last word in every
/// pass, so non-penetration is what a pass leaves most exactly satisfied,
/// and friction works with the normal impulses of the previous pass (warm
/// started, they are nearly final). Solving friction last lets its
/// correction disturb the normal rows of stacks: in the 20-row pyramid,
/// boxes then creep sideways by centimetres over 10 s at 8 x 2 iterations.
pub fn solve(
    manifolds: &mut [ManifoldConstraint],
    points: &mut [PointConstraint],
    bodies: &mut [SolverBody],
    h: f64,
) {
    let inv_h = 1.0 / h;
    let bodies = Shared::new(bodies);
    for m in manifolds.iter_mut() {
        let pts = &mut points[m.range()];
        // SAFETY: one thread.
        unsafe { solve_patch(m, pts, &bodies, inv_h) };
    }
}

/// One [`solve`] pass over one patch and its points.
///
/// # Safety
/// The patch's dynamic bodies are this thread's alone meanwhile.
#[inline(always)]
pub(super) unsafe fn solve_patch(
    m: &mut ManifoldConstraint,
    pts: &mut [PointConstraint],
    bodies: &Shared<SolverBody>,
    inv_h: f64,
) {
    // SAFETY: the caller's promise.
    let mut vel = unsafe { PairVelocity::load(bodies, m) };
    let total: f64 = pts.iter().map(|p| p.normal_impulse).sum();
    solve_patch_friction(m, total, &mut vel);
    // A lone point goes through the block too. Its plain projected row
    // update is the same answer up to the block's regularisation and took
    // the 1,000-body pile's velocity passes from 3.0 to 2.1 ms (a point that
    // lifts off sends the block to its sweeps), but with it one body of the
    // 10,000-body pile ended outside the bin: kept out until that escape is
    // understood.
    if m.point_count as usize <= BLOCK_POINTS {
        solve_block(m, pts, &mut vel, inv_h);
    } else {
        for p in pts.iter_mut() {
            let s = p.separation_now;
            let bias = if s > 0.0 { s * inv_h } else { 0.0 };
            let vn = vel.along(p.normal, p.row.ra_x_d, p.row.rb_x_d);
            let new_impulse = (p.normal_impulse - p.normal_mass * (vn + bias)).max(0.0);
            let applied = new_impulse - p.normal_impulse;
            p.normal_impulse = new_impulse;
            p.max_normal_impulse = p.max_normal_impulse.max(new_impulse);
            vel.apply(p.normal, p.row.ia_ra_x_d, p.row.ib_rb_x_d, m.inv_mass, applied);
        }
    }
    // SAFETY: the caller's promise.
    unsafe { vel.store(bodies, m) };
}

/// Most sweeps of projected Gauss-Seidel on a patch's own block per solver pass.
pub(super) const BLOCK_SWEEPS: usize = 8;

/// The normal rows of a small patch solved together: with `b_i` the
/// current relative normal velocity plus bias of point `i` and `K` the
/// patch's Delassus block, find the impulse change `d` such that
/// `lambda + d >= 0`, `w = b + K d >= 0` and `(lambda + d) . w = 0`: first
/// directly with every point pressing, else by projected Gauss-Seidel
/// sweeps on the 4 x 4 system; then apply `d` once.
///
/// Why: solved one row after another with the bodies' velocities updated in
/// between, the first point of a face takes the load the others should
/// share, and a tall stack of aligned boxes rocks from that bias. On the
/// small block the sweeps are cheap (no body data is touched) and converge
/// to an answer whose velocities do not depend on the order of the points.
#[inline(always)]
fn solve_block(m: &ManifoldConstraint, pts: &mut [PointConstraint], vel: &mut PairVelocity, inv_h: f64) {
    // Fixed-size arrays padded with inactive points (zero row, zero mass):
    // the sweeps unroll completely.
    let mut b = [0.0; BLOCK_POINTS];
    let mut lambda = [0.0; BLOCK_POINTS];
    let mut mass = [0.0; BLOCK_POINTS];
    for (i, p) in pts.iter().enumerate() {
        let s = p.separation_now;
        let bias = if s > 0.0 { s * inv_h } else { 0.0 };
        b[i] = vel.along(p.normal, p.row.ra_x_d, p.row.rb_x_d) + bias;
        lambda[i] = p.normal_impulse;
        mass[i] = p.normal_mass;
    }
    let d = direct_block(&m.block, &m.block_inverse, &b, &lambda)
        .unwrap_or_else(|| swept_block(&m.block, &b, &lambda, &mass));
    for (i, p) in pts.iter_mut().enumerate() {
        let new_impulse = lambda[i] + d[i];
        p.normal_impulse = new_impulse;
        p.max_normal_impulse = p.max_normal_impulse.max(new_impulse);
        vel.apply(p.normal, p.row.ia_ra_x_d, p.row.ib_rb_x_d, m.inv_mass, d[i]);
    }
}

/// The usual case first: every point of the patch keeps pressing. Then
/// `w = b + K d = 0`, solved directly with the patch's regularised inverse
/// (built once per refresh of the block); the answer stands if every impulse stays non-negative and no
/// point is left approaching (a patch whose gaps tilt it open, or one that
/// lifts a corner, goes to the sweeps instead).
#[inline(always)]
fn direct_block(
    block: &PatchBlock,
    inverse: &PatchBlock,
    b: &[f64; BLOCK_POINTS],
    lambda: &[f64; BLOCK_POINTS],
) -> Option<[f64; BLOCK_POINTS]> {
    let w = |d: &[f64; BLOCK_POINTS]| {
        let kd = mat4_mul(block, d);
        std::array::from_fn::<f64, BLOCK_POINTS, _>(|i| b[i] + kd[i])
    };
    let mut d = mat4_mul(inverse, &b.map(|x| -x));
    // One step of iterative refinement takes the regularisation's relative
    // error from eps to eps^2 (a lone point then lands on its row exactly).
    let fix = mat4_mul(inverse, &w(&d).map(|x| -x));
    for i in 0..BLOCK_POINTS {
        d[i] += fix[i];
    }
    let tolerance = 1e-9 * (1.0 + b.iter().fold(0.0f64, |x, &y| x.max(y.abs())));
    let w = w(&d);
    let mut ok = true;
    for i in 0..BLOCK_POINTS {
        ok &= !(lambda[i] + d[i] < 0.0 || w[i] < -tolerance);
    }
    ok.then_some(d)
}

/// The block LCP of [`direct_block`] solved exactly by trying the sets of
/// pressing points (Murty's enumeration; at most 15 for four points), the
/// larger sets first: the points `taking_part` in a set press (`w = 0`),
/// every other point is released (`lambda + d = 0`), and the first set
/// whose impulses are not negative and whose released points are not
/// approaching is the answer. `None` if none is (a block singular within
/// rounding).
///
/// Why: the sweeps stop after [`BLOCK_SWEEPS`]; on a block whose two
/// points see nearly the same motion (a loop through joints leaves a
/// patch little freedom) they leave a point approaching.
#[allow(clippy::needless_range_loop)] // elimination reads best indexed
fn enumerated_block(
    block: &PatchBlock,
    b: &[f64; BLOCK_POINTS],
    lambda: &[f64; BLOCK_POINTS],
    taking_part: &[bool; BLOCK_POINTS],
) -> Option<[f64; BLOCK_POINTS]> {
    let tolerance = 1e-9 * (1.0 + b.iter().fold(0.0f64, |x, &y| x.max(y.abs())));
    /// The sets of four points, larger sets first.
    const BY_SIZE: [u32; 16] = [15, 7, 11, 13, 14, 3, 5, 6, 9, 10, 12, 1, 2, 4, 8, 0];
    let all = taking_part
        .iter()
        .enumerate()
        .fold(0u32, |m, (i, &t)| m | (u32::from(t) << i));
    'sets: for set in BY_SIZE.into_iter().filter(|&s| s & !all == 0) {
        let mut pressing = [0usize; BLOCK_POINTS];
        let mut k = 0;
        for i in (0..BLOCK_POINTS).filter(|&i| set & (1 << i) != 0) {
            pressing[k] = i;
            k += 1;
        }
        let pressing = &pressing[..k];
        // Released points drop their impulse: d_i = -lambda_i.
        let mut d = std::array::from_fn(|i| if set & (1 << i) != 0 { 0.0 } else { -lambda[i] });
        // The pressing points: K_PP d_P = -(b_P + K_P,R d_R), by Gaussian
        // elimination with partial pivoting.
        let mut a = [[0.0; BLOCK_POINTS + 1]; BLOCK_POINTS];
        for (r, &i) in pressing.iter().enumerate() {
            for (c, &j) in pressing.iter().enumerate() {
                a[r][c] = block[i][j];
            }
            a[r][k] = -(b[i] + (0..BLOCK_POINTS).map(|j| block[i][j] * d[j]).sum::<f64>());
        }
        for col in 0..k {
            let pivot = (col..k).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
            if a[pivot][col].abs() <= 1e-12 * block[pressing[col]][pressing[col]].abs() {
                continue 'sets;
            }
            a.swap(col, pivot);
            for r in col + 1..k {
                let f = a[r][col] / a[col][col];
                for c in col..=k {
                    a[r][c] -= f * a[col][c];
                }
            }
        }
        for r in (0..k).rev() {
            let rest: f64 = (r + 1..k).map(|c| a[r][c] * d[pressing[c]]).sum();
            d[pressing[r]] = (a[r][k] - rest) / a[r][r];
        }
        let w = |i: usize| b[i] + (0..BLOCK_POINTS).map(|j| block[i][j] * d[j]).sum::<f64>();
        let holds = (0..BLOCK_POINTS).all(|i| {
            if set & (1 << i) != 0 {
                lambda[i] + d[i] >= 0.0
            } else {
                !taking_part[i] || w(i) >= -tolerance
            }
        });
        if holds {
            return Some(d);
        }
    }
    None
}

/// Symmetric projected Gauss-Seidel sweeps (forward, then backward: no
/// corner of a face is favoured by its place in the list) on the block LCP,
/// stopping once a sweep changes nothing that matters.
#[inline(always)]
fn swept_block(
    block: &PatchBlock,
    b: &[f64; BLOCK_POINTS],
    lambda: &[f64; BLOCK_POINTS],
    mass: &[f64; BLOCK_POINTS],
) -> [f64; BLOCK_POINTS] {
    let mut d = [0.0; BLOCK_POINTS];
    let scale = 1e-9 * (1.0 + lambda.iter().fold(0.0f64, |x, &y| x.max(y)));
    for sweep in 0..BLOCK_SWEEPS {
        let mut change: f64 = 0.0;
        for step in 0..BLOCK_POINTS {
            let i = if sweep % 2 == 0 {
                step
            } else {
                BLOCK_POINTS - 1 - step
            };
            let k = &block[i];
            let w = b[i] + k[0] * d[0] + k[1] * d[1] + k[2] * d[2] + k[3] * d[3];
            let new = (lambda[i] + d[i] - mass[i] * w).max(0.0) - lambda[i];
            change = change.max((new - d[i]).abs());
            d[i] = new;
        }
        if change <= scale {
            break;
        }
    }
    d
}

/// The largest violation of the non-penetration rows by the current
/// velocities (m/s): `max(0, -(v_n + bias))` over every point, with the
/// speculative `bias = s / h` for points with a gap. Zero when every row of
/// the contact LCP holds; what the iterations left unsolved otherwise.
pub fn residual(
    manifolds: &[ManifoldConstraint],
    points: &[PointConstraint],
    bodies: &[SolverBody],
    h: f64,
) -> f64 {
    let inv_h = 1.0 / h;
    let mut worst: f64 = 0.0;
    for m in manifolds {
        let vel = PairVelocity::of(&bodies[m.a as usize], &bodies[m.b as usize]);
        for p in &points[m.range()] {
            let s = p.separation_now;
            let bias = if s > 0.0 { s * inv_h } else { 0.0 };
            let w = vel.along(p.normal, p.row.ra_x_d, p.row.rb_x_d) + bias;
            worst = worst.max(-w);
        }
    }
    worst
}

/// One pass over the friction rows only, the normal impulses held fixed
/// (used after an exact normal solve).
pub fn solve_friction(
    manifolds: &mut [ManifoldConstraint],
    points: &[PointConstraint],
    bodies: &mut [SolverBody],
) {
    let bodies = Shared::new(bodies);
    for m in manifolds.iter_mut() {
        let total: f64 = points[m.range()].iter().map(|p| p.normal_impulse).sum();
        // SAFETY: one thread.
        unsafe {
            let mut vel = PairVelocity::load(&bodies, m);
            solve_patch_friction(m, total, &mut vel);
            vel.store(&bodies, m);
        }
    }
}

/// Patch friction: the two tangent rows at the patch anchor, solved one after
/// the other and then projected onto the Coulomb disc of radius
/// `mu * total` (static and kinetic friction alike: inside the disc the
/// patch sticks, on its rim it slides), then the twist row, bounded by
/// `mu * total * twist_radius`.
#[inline(always)]
fn solve_patch_friction(m: &mut ManifoldConstraint, total: f64, vel: &mut PairVelocity) {
    let limit = m.friction * total;
    let mut t = [m.impulses[0], m.impulses[1]];
    for (i, ti) in t.iter_mut().enumerate() {
        let (d, row) = (m.directions[i], &m.rows[i]);
        let before = *ti;
        *ti = before - m.masses[i] * vel.along(d, row.ra_x_d, row.rb_x_d);
        vel.apply(d, row.ia_ra_x_d, row.ib_rb_x_d, m.inv_mass, *ti - before);
    }
    let len2 = t[0] * t[0] + t[1] * t[1];
    if len2 > limit * limit {
        let scale = if len2 > 0.0 { limit / len2.sqrt() } else { 0.0 };
        for (i, ti) in t.iter_mut().enumerate() {
            let clamped = *ti * scale;
            let row = &m.rows[i];
            vel.apply(
                m.directions[i],
                row.ia_ra_x_d,
                row.ib_rb_x_d,
                m.inv_mass,
                clamped - *ti,
            );
            *ti = clamped;
        }
    }
    m.impulses[0] = t[0];
    m.impulses[1] = t[1];
    let row = &m.rows[2];
    let twist_limit = limit * m.twist_radius;
    let before = m.impulses[2];
    let spin = row.ra_x_d.dot(vel.wa) - row.rb_x_d.dot(vel.wb);
    // max/min, not clamp: a limit that is NaN (non-finite input, which the
    // quarantine catches after the solve) must not panic the step.
    let after = (before - m.masses[2] * spin).max(-twist_limit).min(twist_limit);
    vel.apply(
        DVec3::ZERO,
        row.ia_ra_x_d,
        row.ib_rb_x_d,
        m.inv_mass,
        after - before,
    );
    m.impulses[2] = after;
}

/// One Gauss-Seidel pass of position correction by pseudo-velocities: each
/// point overlapping by more than the allowance gets a pseudo-impulse that
/// removes `push_out_fraction` of the excess in this sub-step (at most
/// `max_push_out_speed`). Pseudo-velocities move the bodies in
/// `integrate_positions` and are then discarded, so correcting position
/// never adds kinetic energy and never depends on the load (a stack does
/// not sag under its own weight, as it does with Baumgarte or spring bias).
/// In the sub-step's `first` pass, patches that stuck in the last step also
/// hold their anchors (`hold_anchor`). Returns `false` when no point
/// needed it (nothing was pushed; held anchors do not count).
pub fn push_out(
    manifolds: &[ManifoldConstraint],
    points: &mut [PointConstraint],
    bodies: &mut [SolverBody],
    params: &SolverParams,
    h: f64,
    first: bool,
) -> bool {
    let inv_h = 1.0 / h;
    let bodies = Shared::new(bodies);
    let mut any = false;
    for m in manifolds {
        // SAFETY: one thread.
        any |= unsafe { push_patch(m, &mut points[m.range()], &bodies, params, inv_h, first) };
    }
    any
}

/// One [`push_out`] pass over one patch and its points, holding its anchor
/// with `hold`; `true` if it pushed.
///
/// # Safety
/// The patch's dynamic bodies are this thread's alone meanwhile.
#[inline(always)]
pub(super) unsafe fn push_patch(
    m: &ManifoldConstraint,
    pts: &mut [PointConstraint],
    bodies: &Shared<SolverBody>,
    params: &SolverParams,
    inv_h: f64,
    hold: bool,
) -> bool {
    // SAFETY: the caller's promise.
    let (a, b) = unsafe { (bodies.get(m.a as usize), bodies.get(m.b as usize)) };
    let mut vel = PairVelocity {
        va: a.push_v,
        wa: a.push_w,
        vb: b.push_v,
        wb: b.push_w,
    };
    // A flat patch: one normal for all its points (a polytope's face, edge
    // or corner).
    let flat = pts.iter().all(|p| p.normal == pts[0].normal);
    let any = if m.point_count as usize <= BLOCK_POINTS && flat {
        push_block(m, pts, &mut vel, params, inv_h)
    } else {
        push_points(m, pts, &mut vel, params, inv_h)
    };
    let held = hold && m.anchored && hold_anchor(m, pts, (a, b), &mut vel, inv_h);
    if any || held {
        for (k, v, w) in [(m.a, vel.va, vel.wa), (m.b, vel.vb, vel.wb)] {
            // SAFETY: the caller's promise; dynamic bodies only are written.
            unsafe {
                if bodies.get(k as usize).dynamic {
                    let body = bodies.get_mut(k as usize);
                    (body.push_v, body.push_w) = (v, w);
                }
            }
        }
    }
    any
}

/// Static friction held at the position level (a patch's anchor, see
/// `ManifoldConstraint::anchored`): the patch's two tangent rows get the
/// pseudo-impulse that brings its anchor points back together across the
/// normal within this sub-step ([`HOLD_FRACTION`] of their offset), within
/// what friction has left (the Coulomb disc's radius `mu` times the patch's
/// normal impulse, less its friction impulse); `true` if it applied one.
///
/// Why: the velocity passes hold a sticking patch's relative velocity at
/// zero only as far as their few iterations converge, and what they leave
/// adds up over the steps. A settled pile of 200 concave bodies crept by
/// about 25 um a second at the median, sinking as it went, its loads
/// shifting until a wedged body slipped and fell 20 cm.
#[inline(always)]
fn hold_anchor(
    m: &ManifoldConstraint,
    pts: &[PointConstraint],
    (a, b): (&SolverBody, &SolverBody),
    vel: &mut PairVelocity,
    inv_h: f64,
) -> bool {
    let mut total = 0.0;
    for p in pts {
        total += p.normal_impulse;
    }
    let used = (m.impulses[0] * m.impulses[0] + m.impulses[1] * m.impulses[1]).sqrt();
    let budget = m.friction * total - used;
    if budget.is_nan() || budget <= 0.0 {
        return false;
    }
    // Where the anchor points are now, each moved with its body since the
    // step start.
    let [ra, rb] = m.anchor_r;
    let offset = m.anchor_offset + ((a.dp + a.turn * ra) - ra) - ((b.dp + b.turn * rb) - rb);
    let gain = -HOLD_FRACTION * inv_h;
    let mut lambda = [0.0; 2];
    for (i, l) in lambda.iter_mut().enumerate() {
        let (d, row) = (m.directions[i], &m.rows[i]);
        *l = m.masses[i] * (gain * offset.dot(d) - vel.along(d, row.ra_x_d, row.rb_x_d));
    }
    let len = (lambda[0] * lambda[0] + lambda[1] * lambda[1]).sqrt();
    if len > budget {
        let scale = budget / len;
        lambda = [lambda[0] * scale, lambda[1] * scale];
    }
    for (i, &l) in lambda.iter().enumerate() {
        let row = &m.rows[i];
        vel.apply(m.directions[i], row.ia_ra_x_d, row.ib_rb_x_d, m.inv_mass, l);
    }
    true
}

/// How much of a sticking patch's anchor offset its push-out removes in one
/// sub-step ([`hold_anchor`]). All of it: in a first version of the hold,
/// a fifth (as overlaps are pushed out) left eight jittered starts of the
/// concave pile creeping by 19 um a second at the median instead of 17,
/// and two of them lost a body over the bin's wall instead of none.
pub(super) const HOLD_FRACTION: f64 = 1.0;

/// The push-out rows of a patch one point after another (projected
/// Gauss-Seidel); `true` if any point took part.
#[inline(always)]
fn push_points(
    m: &ManifoldConstraint,
    pts: &mut [PointConstraint],
    vel: &mut PairVelocity,
    params: &SolverParams,
    inv_h: f64,
) -> bool {
    let mut any = false;
    for p in pts.iter_mut() {
        let Some(target) = push_target(p, params, inv_h) else {
            continue;
        };
        any = true;
        let vn = vel.along(p.normal, p.row.ra_x_d, p.row.rb_x_d);
        let new_impulse = (p.push_impulse + p.normal_mass * (target - vn)).max(0.0);
        let applied = new_impulse - p.push_impulse;
        p.push_impulse = new_impulse;
        vel.apply(p.normal, p.row.ia_ra_x_d, p.row.ib_rb_x_d, m.inv_mass, applied);
    }
    any
}

/// The push-out pseudo-velocity a point aims its row at: `push_out_fraction`
/// of its overlap beyond the allowance over the sub-step (at most
/// `max_push_out_speed`), or 0 for a point within the allowance that has
/// pushed in this sub-step (it may let go); `None` for one within the
/// allowance that has not, which takes no part.
#[inline(always)]
fn push_target(p: &PointConstraint, params: &SolverParams, inv_h: f64) -> Option<f64> {
    let excess = p.separation_now + params.allowed_penetration;
    if excess < 0.0 {
        Some((-params.push_out_fraction * excess * inv_h).min(params.max_push_out_speed))
    } else if p.push_impulse != 0.0 {
        Some(0.0)
    } else {
        None
    }
}

/// The push-out rows of a flat patch (one normal for all its points: a
/// polytope's face, edge or corner) of at most [`BLOCK_POINTS`] points
/// solved together, directly, as [`direct_block`] solves the velocity rows,
/// when every point takes part and the answer pushes at none of them with a
/// negative impulse; otherwise point after point ([`push_points`]). `true`
/// if any point took part.
///
/// Why: pushed one point after another, the first point of a face takes
/// the push the others should share, and the box turns a little about the
/// face at every sub-step. In a column of boxes those turns add up: towers
/// of 40 unit cubes and more leaned over and fell at the default settings,
/// and stood with the push-out off. The points of a mesh patch each have
/// their own normal and lie close together: solved together, their nearly
/// dependent rows pushed two overlapping tori apart askew (1.7 mm across
/// in 0.6 m) and let the torus chain's links sink 2.4 mm (0.7 mm point
/// after point), so [`push_patch`] keeps them point after point.
#[inline(always)]
fn push_block(
    m: &ManifoldConstraint,
    pts: &mut [PointConstraint],
    vel: &mut PairVelocity,
    params: &SolverParams,
    inv_h: f64,
) -> bool {
    let mut b = [0.0; BLOCK_POINTS];
    let mut lambda = [0.0; BLOCK_POINTS];
    for (i, p) in pts.iter().enumerate() {
        let Some(target) = push_target(p, params, inv_h) else {
            return push_points(m, pts, vel, params, inv_h);
        };
        b[i] = vel.along(p.normal, p.row.ra_x_d, p.row.rb_x_d) - target;
        lambda[i] = p.push_impulse;
    }
    let Some(d) = direct_block(&m.block, &m.block_inverse, &b, &lambda) else {
        return push_points(m, pts, vel, params, inv_h);
    };
    for (i, p) in pts.iter_mut().enumerate() {
        p.push_impulse = lambda[i] + d[i];
        vel.apply(p.normal, p.row.ia_ra_x_d, p.row.ib_rb_x_d, m.inv_mass, d[i]);
    }
    true
}

/// One friction pass over one patch ([`solve_friction`]'s kernel), with the
/// normal impulses as they stand.
///
/// # Safety
/// The patch's dynamic bodies are this thread's alone meanwhile.
pub(super) unsafe fn friction_patch(
    m: &mut ManifoldConstraint,
    pts: &[PointConstraint],
    bodies: &Shared<SolverBody>,
) {
    let total: f64 = pts.iter().map(|p| p.normal_impulse).sum();
    // SAFETY: the caller's promise.
    unsafe {
        let mut vel = PairVelocity::load(bodies, m);
        solve_patch_friction(m, total, &mut vel);
        vel.store(bodies, m);
    }
}

/// The pass an island-owned patch's normal rows are solved in.
#[derive(Clone, Copy)]
pub(super) enum OwnedPass<'a> {
    /// The velocity rows (speculative bias `s / h` for points with a gap).
    Velocity { inv_h: f64 },
    /// The push-out pseudo-velocities, as [`push_patch`] aims them.
    Push { params: &'a SolverParams, inv_h: f64 },
}

/// The normal rows of a patch whose bodies belong to one joint island, solved
/// with the island's joints (`island_contacts`): `articulated` is the patch's
/// normal block as the island's joints let it act (`S = G M^-1 G^T - W^T K^-1 W`),
/// and `coupled[i]` the velocity that the island's joint impulses of this
/// pass, not yet applied, add to point `i`. The same block LCP as
/// [`solve_block`] (and, for the push-out, the same targets as
/// [`push_patch`]) on `S`; the impulse changes are applied to the bodies and
/// accumulated, and returned so that the island can take them back out of
/// its joints (`-K^-1 W d`). The second value says whether a push-out point
/// had work.
///
/// # Safety
/// The patch's dynamic bodies are this thread's alone meanwhile.
pub(super) unsafe fn solve_owned_normals(
    m: &ManifoldConstraint,
    pts: &mut [PointConstraint],
    bodies: &Shared<SolverBody>,
    articulated: &ArticulatedBlock,
    coupled: &[f64; BLOCK_POINTS],
    pass: OwnedPass,
) -> ([f64; BLOCK_POINTS], bool) {
    let ArticulatedBlock { block, inverse, mass } = articulated;
    let mut b = [0.0; BLOCK_POINTS];
    let mut lambda = [0.0; BLOCK_POINTS];
    // A push-out point within the allowance that has not pushed in this
    // sub-step takes no part (as in `push_patch`): held at zero by a zero
    // mass in the sweeps.
    let mut mass = *mass;
    let mut any = false;
    // SAFETY: the caller's promise; dynamic bodies only are written.
    unsafe {
        let (body_a, body_b) = (bodies.get(m.a as usize), bodies.get(m.b as usize));
        let vel = match pass {
            OwnedPass::Velocity { .. } => PairVelocity::of(body_a, body_b),
            OwnedPass::Push { .. } => PairVelocity {
                va: body_a.push_v,
                wa: body_a.push_w,
                vb: body_b.push_v,
                wb: body_b.push_w,
            },
        };
        for (i, p) in pts.iter().enumerate() {
            let vn = vel.along(p.normal, p.row.ra_x_d, p.row.rb_x_d) + coupled[i];
            let s = p.separation_now;
            (b[i], lambda[i]) = match pass {
                OwnedPass::Velocity { inv_h } => {
                    (vn + if s > 0.0 { s * inv_h } else { 0.0 }, p.normal_impulse)
                }
                OwnedPass::Push { params, inv_h } => {
                    let excess = s + params.allowed_penetration;
                    if excess >= 0.0 && p.push_impulse == 0.0 {
                        mass[i] = 0.0;
                    }
                    any |= excess < 0.0 || p.push_impulse != 0.0;
                    let target = if excess < 0.0 {
                        (-params.push_out_fraction * excess * inv_h).min(params.max_push_out_speed)
                    } else {
                        0.0
                    };
                    (vn - target, p.push_impulse)
                }
            };
        }
        let taking_part = std::array::from_fn(|i| mass[i] > 0.0);
        let d = match taking_part.iter().filter(|&&t| t).count() {
            0 => return ([0.0; BLOCK_POINTS], any),
            k if k == pts.len() => direct_block(block, inverse, &b, &lambda),
            _ => None,
        }
        .or_else(|| enumerated_block(block, &b, &lambda, &taking_part))
        .unwrap_or_else(|| swept_block(block, &b, &lambda, &mass));
        let mut vel = vel;
        for (i, p) in pts.iter_mut().enumerate() {
            vel.apply(p.normal, p.row.ia_ra_x_d, p.row.ib_rb_x_d, m.inv_mass, d[i]);
            match pass {
                OwnedPass::Velocity { .. } => {
                    p.normal_impulse = lambda[i] + d[i];
                    p.max_normal_impulse = p.max_normal_impulse.max(p.normal_impulse);
                }
                OwnedPass::Push { .. } => p.push_impulse = lambda[i] + d[i],
            }
        }
        for (k, (v, w)) in [(m.a, (vel.va, vel.wa)), (m.b, (vel.vb, vel.wb))] {
            if bodies.get(k as usize).dynamic {
                let body = bodies.get_mut(k as usize);
                match pass {
                    OwnedPass::Velocity { .. } => (body.v, body.w) = (v, w),
                    OwnedPass::Push { .. } => (body.push_v, body.push_w) = (v, w),
                }
            }
        }
        (d, any)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_testkit::{RandomSource, SplitMix64};

    /// The enumerated block LCP meets the conditions that define its
    /// answer on random positive definite blocks of one to four points,
    /// nearly singular ones included (points that see nearly the same
    /// motion): `lambda + d >= 0`, `w = b + K d >= 0`, `(lambda + d) w = 0`.
    #[test]
    fn the_enumerated_block_solves_the_block_lcp() {
        let mut rng = SplitMix64(7);
        for case in 0..2000 {
            let points = 1 + case % BLOCK_POINTS;
            // K = A A^T + small I from random rows; every other case has
            // rows that differ by a little only.
            let base: [f64; 6] = std::array::from_fn(|_| rng.range(-1.0, 1.0));
            let rows: Vec<[f64; 6]> = (0..points)
                .map(|_| {
                    let spread = if case % 2 == 0 { 1.0 } else { 1e-3 };
                    std::array::from_fn(|c| base[c] + spread * rng.range(-1.0, 1.0))
                })
                .collect();
            let mut k = [[0.0; BLOCK_POINTS]; BLOCK_POINTS];
            for i in 0..points {
                for j in 0..points {
                    k[i][j] = rows[i].iter().zip(&rows[j]).map(|(x, y)| x * y).sum::<f64>()
                        + if i == j { 1e-6 } else { 0.0 };
                }
            }
            let b: [f64; BLOCK_POINTS] =
                std::array::from_fn(|i| if i < points { rng.range(-1.0, 1.0) } else { 0.0 });
            let lambda: [f64; BLOCK_POINTS] =
                std::array::from_fn(|i| if i < points { rng.range(0.0, 1.0) } else { 0.0 });
            let taking_part = std::array::from_fn(|i| i < points);
            let d = enumerated_block(&k, &b, &lambda, &taking_part)
                .unwrap_or_else(|| panic!("case {case}: no set of pressing points"));
            for i in 0..points {
                let z = lambda[i] + d[i];
                let w = b[i] + (0..BLOCK_POINTS).map(|j| k[i][j] * d[j]).sum::<f64>();
                assert!(z >= 0.0, "case {case}: impulse {z}");
                assert!(w >= -1e-8, "case {case}: point {i} approaching at {w}");
                assert!((z * w).abs() < 1e-8, "case {case}: {z} x {w}");
            }
        }
    }
}
