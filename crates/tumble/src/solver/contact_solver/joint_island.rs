//! Joint islands solved directly: the equality rows of a group of joints
//! linked through shared bodies (a chain, a ragdoll, a robot) as one linear
//! system `K dl = rhs`, `K = J M^-1 J^T`, factored once per sub-step.
//!
//! Relaxing joint by joint (Gauss-Seidel) carries a load along a chain one
//! link per pass: a heavy weight on light links stretches the chain (a
//! 1:100 mass ratio pulls a 20-link rope apart within a second). Solved as
//! one system the chain is exact in every pass whatever the mass ratio (the
//! maximal-coordinate answer of Baraff's "Linear-time dynamics using
//! Lagrange multipliers", 1996).
//!
//! A joint's motor joins its equality rows in the system (a soft row:
//! `K + gamma` on its diagonal): the motors of a robot arm hold against each
//! other through the chain, which a pass per joint only approaches (an arm
//! under stiff PD motors oscillated about its targets with 2 iterations).
//! A motor that would exceed its force is clamped after the solve.
//!
//! `K` is sparse: rows of two joints couple only when the joints share a
//! dynamic body. With the joints ordered breadth-first through the island,
//! a row couples only with rows a few joints back, so `K` has a narrow
//! *profile* (skyline) and its Cholesky factor keeps it: a chain costs
//! O(rows x block^2), not O(rows^3). Islands whose profile would be too
//! large for a sub-step budget stay with the joint-by-joint passes. `K`
//! is assembled only where it is not zero, block by block over the pairs of
//! joints that share a dynamic body (found once per step), and an island's
//! joints are begun, relaxed and pushed together (their limits after the
//! system), so that a thread works through one island's rows at a time.

use super::body::SolverBody;
use super::coloring::Shared;
use super::joint::{
    begin_joint, push_joint, solve_joint, JointConstraint, Pair, JOINT_PUSH_FRACTION, LOWER, MOTOR, SWING,
    UPPER,
};
use tumble_collide::DVec3;

/// Largest ratio of the heaviest to the lightest body of an island whose
/// equality rows are aimed at the end of the sub-step.
pub const AIM_MASS_RATIO: f64 = 4.0;

/// Largest factor (stored profile entries) an island may have; beyond it
/// the island is relaxed joint by joint. 200,000 entries is about a
/// millisecond per factorization on one core.
pub const MAX_PROFILE: usize = 200_000;

/// One row of an island's system by body side (A, B): the body, its
/// Jacobian, and the Jacobian times the body's inverse mass and inertia.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct SideRow {
    body: [u32; 2],
    lin: [DVec3; 2],
    ang: [DVec3; 2],
    m_lin: [DVec3; 2],
    m_ang: [DVec3; 2],
    gamma: f64,
}

/// Two joints of an island that share a dynamic body: the rows of joint
/// `p` couple with those of joint `q` (`q <= p` in the island's order)
/// through side `side_p` of `p` and side `side_q` of `q`. A joint couples
/// with itself once per dynamic side.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Coupling {
    p: u32,
    q: u32,
    side_p: u8,
    side_q: u8,
}

/// One island of joints whose equality rows are solved together.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct JointIsland {
    /// The joints (indices into the solver's joint array), breadth-first.
    pub joints: Vec<u32>,
    /// First row of each joint in the island's system (and the total last).
    offsets: Vec<usize>,
    /// The blocks of `K` that are not zero, as pairs of joints.
    couplings: Vec<Coupling>,
    /// Whether a row of the system has bounds (a motor).
    bounded: bool,
    /// The right-hand side of the system (reused between passes).
    rhs: Vec<f64>,
    /// Per row: the first column of its profile.
    first: Vec<usize>,
    /// Per row: where its profile starts in `factor`.
    start: Vec<usize>,
    /// The Cholesky factor, row by row over each row's profile.
    factor: Vec<f64>,
    /// The reciprocals of the factor's diagonal.
    inv_diagonal: Vec<f64>,
    /// Per row of the system, its Jacobian by side (reused between sub-steps).
    scratch: Vec<SideRow>,
    /// The equality rows are aimed at the end of the sub-step (see
    /// `JointConstraint::aim_equality_rows`): only where the island's
    /// masses are within [`AIM_MASS_RATIO`] of each other.
    aim: bool,
}

impl JointIsland {
    /// Rows of the system.
    pub fn rows(&self) -> usize {
        self.first.len()
    }

    /// The start of a sub-step for the island's joints (`begin_joint`,
    /// joint by joint in the island's order), then `K` factored: while the
    /// rows just built are still in the cache.
    ///
    /// # Safety
    /// The island's joints and bodies are this thread's alone meanwhile.
    pub unsafe fn begin(
        &mut self,
        joints: &Shared<JointConstraint>,
        bodies: &Shared<SolverBody>,
        h: f64,
        warm: bool,
    ) {
        for &ji in &self.joints {
            // SAFETY: the caller's promise.
            unsafe { begin_joint(joints.get_mut(ji as usize), bodies, h, warm) };
        }
        self.factor(joints, bodies);
    }

    /// One velocity pass: the equality rows (and motors) together, then
    /// each joint's limits (`solve_joint`) in the island's order.
    ///
    /// # Safety
    /// As [`JointIsland::begin`].
    pub unsafe fn solve(&mut self, joints: &Shared<JointConstraint>, bodies: &Shared<SolverBody>) {
        // SAFETY: the caller's promise.
        unsafe {
            self.relax(joints, bodies, None);
            for &ji in &self.joints {
                solve_joint(joints.get_mut(ji as usize), bodies);
            }
        }
    }

    /// One push-out pass, as [`JointIsland::solve`] (`push_joint` for the
    /// limits); whether any row had an error to remove.
    ///
    /// # Safety
    /// As [`JointIsland::begin`].
    pub unsafe fn push(
        &mut self,
        joints: &Shared<JointConstraint>,
        bodies: &Shared<SolverBody>,
        inv_h: f64,
    ) -> bool {
        // SAFETY: the caller's promise.
        unsafe {
            let mut any = self.relax(joints, bodies, Some((JOINT_PUSH_FRACTION, inv_h)));
            for &ji in &self.joints {
                any |= push_joint(joints.get_mut(ji as usize), bodies, inv_h);
            }
            any
        }
    }

    /// Factors `K` for the joints' rows of this sub-step (after their
    /// `begin_joint`).
    #[allow(clippy::needless_range_loop)] // profile indices (i, j) address K, rows and owners at once
    fn factor(&mut self, joints: &Shared<JointConstraint>, bodies: &Shared<SolverBody>) {
        // Each row as its two sides: (body, linear and angular Jacobian,
        // the same times the body's inverse mass and inertia). Immovable
        // bodies have zero inverse mass and inertia, so they add nothing.
        // SAFETY (all accesses): the island's joints and bodies are this
        // thread's alone during the call (islands share no dynamic body).
        let n = self.rows();
        let rows = &mut self.scratch;
        rows.clear();
        for &ji in &self.joints {
            let j = unsafe { joints.get(ji as usize) };
            let (ma, mb) = unsafe {
                (
                    bodies.get(j.a as usize).inv_mass,
                    bodies.get(j.b as usize).inv_mass,
                )
            };
            for slot in island_slots(j) {
                let r = &j.rows[slot];
                rows.push(SideRow {
                    body: [j.a, j.b],
                    lin: [r.lin, -r.lin],
                    ang: [r.ang_a, r.ang_b],
                    m_lin: [r.lin * ma, -r.lin * mb],
                    m_ang: [r.ia, r.ib],
                    gamma: r.gamma,
                });
            }
        }
        // K block by block: only joints sharing a dynamic body couple
        // (the profile holds zeros between them).
        self.factor.fill(0.0);
        for c in &self.couplings {
            let (s, t) = (c.side_p as usize, c.side_q as usize);
            let rows_q = self.offsets[c.q as usize]..self.offsets[c.q as usize + 1];
            for i in self.offsets[c.p as usize]..self.offsets[c.p as usize + 1] {
                let ri = &rows[i];
                let (fi, si) = (self.first[i], self.start[i]);
                // Within one joint, the lower triangle only.
                let end = if c.p == c.q { i + 1 } else { rows_q.end };
                for j in rows_q.start..end {
                    let rj = &rows[j];
                    self.factor[si + j - fi] += ri.lin[s].dot(rj.m_lin[t]) + ri.ang[s].dot(rj.m_ang[t]);
                }
            }
        }
        for (i, r) in rows.iter().enumerate() {
            let d = &mut self.factor[self.start[i] + i - self.first[i]];
            *d += r.gamma + 1e-12 * d.abs() + 1e-300;
        }
        // Profile Cholesky, in place: entries before a row's first column
        // are zero and stay zero in the factor. Row i's entries p >= first[i]
        // lie at start[i] + p - first[i].
        for i in 0..n {
            let (fi, si) = (self.first[i], self.start[i]);
            for j in fi..=i {
                let (fj, sj) = (self.first[j], self.start[j]);
                let lo = fi.max(fj);
                let dot: f64 = self.factor[si + lo - fi..si + j - fi]
                    .iter()
                    .zip(&self.factor[sj + lo - fj..sj + j - fj])
                    .map(|(x, y)| x * y)
                    .sum();
                let s = self.factor[si + j - fi] - dot;
                self.factor[si + j - fi] = if i == j {
                    let d = s.max(1e-300).sqrt();
                    self.inv_diagonal[i] = 1.0 / d;
                    d
                } else {
                    s * self.inv_diagonal[j]
                };
            }
        }
    }

    /// Solves `K x = rhs` in place with the factor.
    #[allow(clippy::needless_range_loop)] // the profile's index form
    fn solve_in_place(&self, x: &mut [f64]) {
        let n = self.rows();
        for i in 0..n {
            let (fi, si) = (self.first[i], self.start[i]);
            let row = &self.factor[si..si + i - fi];
            let dot: f64 = row.iter().zip(&x[fi..i]).map(|(l, v)| l * v).sum();
            x[i] = (x[i] - dot) * self.inv_diagonal[i];
        }
        for i in (0..n).rev() {
            let (fi, si) = (self.first[i], self.start[i]);
            x[i] *= self.inv_diagonal[i];
            let xi = x[i];
            for (v, l) in x[fi..i].iter_mut().zip(&self.factor[si..si + i - fi]) {
                *v -= l * xi;
            }
        }
        for v in x.iter_mut() {
            if !v.is_finite() {
                *v = 0.0;
            }
        }
    }

    /// One pass over the island's equality rows: velocities (the rows
    /// aimed as in `JointConstraint::aim_equality_rows`), or with `push`
    /// the push-out pseudo-velocities towards `fraction` of each row's
    /// position error over `h`. Returns whether any row had an error to
    /// push.
    ///
    /// # Safety
    /// The island's joints and bodies are this thread's alone meanwhile.
    unsafe fn relax(
        &mut self,
        joints: &Shared<JointConstraint>,
        bodies: &Shared<SolverBody>,
        push: Option<(f64, f64)>,
    ) -> bool {
        let mut rhs = std::mem::take(&mut self.rhs);
        rhs.clear();
        rhs.resize(self.rows(), 0.0);
        let mut any = false;
        for (k, &ji) in self.joints.iter().enumerate() {
            // SAFETY: the caller's promise.
            let j = unsafe { joints.get_mut(ji as usize) };
            let p = unsafe { Pair::load(j, bodies, push.is_some()) };
            if push.is_none() && self.aim {
                j.aim_equality_rows(&p);
            }
            for (e, slot) in island_slots(j).enumerate() {
                let r = &j.rows[slot];
                let jv = r.lin.dot(p.va - p.vb) + r.ang_a.dot(p.wa) + r.ang_b.dot(p.wb);
                rhs[self.offsets[k] + e] = match push {
                    None => -jv - r.bias - r.gamma * r.impulse,
                    // A motor does not push: its row only keeps the push-out
                    // off the joint's free axis.
                    Some(_) if slot == MOTOR => -jv - r.gamma * r.push,
                    Some((fraction, inv_h)) => {
                        any |= r.c.abs() > 1e-9;
                        -fraction * r.c * inv_h - jv
                    }
                };
            }
        }
        self.solve_in_place(&mut rhs);
        if self.bounded {
            self.hold_at_bounds(joints, &mut rhs, push.is_some());
        }
        // Apply joint by joint: each body's velocity is read and written
        // through its joints in turn.
        for (k, &ji) in self.joints.iter().enumerate() {
            // SAFETY: the caller's promise.
            let j = unsafe { joints.get_mut(ji as usize) };
            let mut p = unsafe { Pair::load(j, bodies, push.is_some()) };
            for (e, slot) in island_slots(j).enumerate() {
                // Within the bounds (re-solved above; a last clamp for what
                // the re-solve could not hold).
                let (acc, lo, hi) = bounds(j, slot, push.is_some());
                let dl = crate::solver::clamp_impulse(acc + rhs[self.offsets[k] + e], lo, hi) - acc;
                j.accumulate(slot, dl, push.is_some());
                p.apply(&j.rows[slot], dl);
            }
            unsafe { p.store(j, bodies, push.is_some()) };
        }
        self.rhs = rhs;
        any
    }
}

impl JointIsland {
    /// Rows (motors) whose solved impulse `x` would pass a bound are
    /// held at the bound and the rest of the system re-solved around them: with
    /// `u_c = K^-1 e_c` for each such row `c`, `x + sum_c u_c mu_c` with the
    /// `mu` that puts each held row on its bound (a small dense system). A
    /// plain clamp would leave the other rows' impulses computed for the
    /// unclamped motor: an arm whose wrist motors saturated blew up.
    fn hold_at_bounds(&self, joints: &Shared<JointConstraint>, x: &mut [f64], push: bool) {
        const MAX_HELD: usize = 16;
        const ROUNDS: usize = 4;
        let x0 = x.to_vec();
        let mut held: Vec<(usize, f64)> = Vec::new();
        let mut columns: Vec<Vec<f64>> = Vec::new();
        // Rounds of an active set: hold what passes a bound, re-solve, and
        // again for what the re-solve pushed past its bound.
        for _ in 0..ROUNDS {
            let before = held.len();
            for (k, &ji) in self.joints.iter().enumerate() {
                // SAFETY: the island's joints are this thread's (caller of relax).
                let j = unsafe { joints.get(ji as usize) };
                for (e, slot) in island_slots(j).enumerate() {
                    let i = self.offsets[k] + e;
                    let (acc, lo, hi) = bounds(j, slot, push);
                    let total = acc + x[i];
                    if (total > hi || total < lo) && !held.iter().any(|&(h, _)| h == i) {
                        held.push((i, crate::solver::clamp_impulse(total, lo, hi) - acc));
                        let mut u = vec![0.0; self.rows()];
                        u[i] = 1.0;
                        self.solve_in_place(&mut u);
                        columns.push(u);
                    }
                }
            }
            if held.len() == before || held.len() > MAX_HELD {
                return;
            }
            let Some(mu) = solve_dense(&held, &columns, &x0) else {
                return;
            };
            x.copy_from_slice(&x0);
            for (u, &mu) in columns.iter().zip(&mu) {
                for (xi, ui) in x.iter_mut().zip(u) {
                    *xi += ui * mu;
                }
            }
        }
    }
}

/// The `mu` with `x0[c] + sum_b u_b[c] mu_b = target_c` at every held row
/// `c` (Gaussian elimination with partial pivoting on the held block of
/// `K^-1`, which is positive definite).
#[allow(clippy::needless_range_loop)] // elimination reads best indexed
fn solve_dense(held: &[(usize, f64)], columns: &[Vec<f64>], x0: &[f64]) -> Option<Vec<f64>> {
    let m = held.len();
    let mut g: Vec<Vec<f64>> = (0..m)
        .map(|a| {
            let mut row: Vec<f64> = (0..m).map(|b| columns[b][held[a].0]).collect();
            row.push(held[a].1 - x0[held[a].0]);
            row
        })
        .collect();
    for col in 0..m {
        let pivot = (col..m).max_by(|&a, &b| g[a][col].abs().total_cmp(&g[b][col].abs()))?;
        g.swap(col, pivot);
        if g[col][col].abs() < 1e-300 {
            return None;
        }
        for r in col + 1..m {
            let f = g[r][col] / g[col][col];
            for c in col..=m {
                g[r][c] -= f * g[col][c];
            }
        }
    }
    let mut mu = vec![0.0; m];
    for a in (0..m).rev() {
        let s: f64 = (a + 1..m).map(|b| g[a][b] * mu[b]).sum();
        mu[a] = (g[a][m] - s) / g[a][a];
    }
    mu.iter().all(|v| v.is_finite()).then_some(mu)
}

/// Row `slot`'s accumulated impulse (or push-out impulse) and its bounds.
fn bounds(j: &JointConstraint, slot: usize, push: bool) -> (f64, f64, f64) {
    let r = &j.rows[slot];
    match (push, slot) {
        (false, _) => (r.impulse, r.lo, r.hi),
        (true, LOWER | UPPER | SWING) => (r.push, 0.0, f64::INFINITY),
        (true, _) => (r.push, f64::NEG_INFINITY, f64::INFINITY),
    }
}

/// The row slots of joint `j` in its island's system: its equality rows,
/// then its motor.
fn island_slots(j: &JointConstraint) -> impl Iterator<Item = usize> + use<> {
    let (n_eq, mask) = (j.n_eq, j.island_rows);
    (0..n_eq).chain(
        [MOTOR, LOWER, UPPER, SWING]
            .into_iter()
            .filter(move |&s| mask & (1 << s) != 0),
    )
}

/// The scalar rows of `j` its island solves: the motor. (Limits stay with
/// the joint-by-joint pass: solved with the island through the same
/// held-at-bound step, a quadruped crouching off its knee limits collapsed;
/// that needs a proper active-set loop, not yet written.)
fn island_mask(j: &JointConstraint) -> u16 {
    if j.law.motor.is_some() {
        1 << MOTOR
    } else {
        0
    }
}

/// The islands of joints worth a direct solve: joints linked through
/// shared dynamic bodies, at least two per island with equality rows, a
/// profile within [`MAX_PROFILE`]. Marks their joints `direct`. Joints in
/// the returned islands are listed breadth-first from the island's first
/// joint (in joint order), so the result is deterministic.
pub fn joint_islands(joints: &mut [JointConstraint], bodies: &[SolverBody]) -> Vec<JointIsland> {
    let n_bodies = bodies.len();
    // Joints of each dynamic body, in joint order.
    let mut of_body: Vec<Vec<u32>> = vec![Vec::new(); n_bodies];
    for (k, j) in joints.iter().enumerate() {
        for b in [j.a, j.b] {
            if bodies[b as usize].dynamic {
                of_body[b as usize].push(k as u32);
            }
        }
    }
    let mut seen = vec![false; joints.len()];
    // Position of each joint in its island's order (each joint is in one island).
    let mut position = vec![usize::MAX; joints.len()];
    let mut islands = Vec::new();
    for root in 0..joints.len() {
        if seen[root] {
            continue;
        }
        // Breadth-first over joints sharing a dynamic body.
        let mut order = vec![root as u32];
        seen[root] = true;
        let mut head = 0;
        while head < order.len() {
            let j = &joints[order[head] as usize];
            for b in [j.a, j.b] {
                for &k in &of_body[b as usize] {
                    if !seen[k as usize] {
                        seen[k as usize] = true;
                        order.push(k);
                    }
                }
            }
            head += 1;
        }
        // Leaves first (the breadth-first order reversed): a joint's rows
        // then reach back only to joints further out on the same bodies, and
        // a tree's hub (a ragdoll's torso) comes last, so the profile stays
        // narrow (a chain is banded either way).
        order.reverse();
        let masks: Vec<u16> = order.iter().map(|&k| island_mask(&joints[k as usize])).collect();
        // Rows of the joint at position p of the order.
        let rows: Vec<usize> = order
            .iter()
            .zip(&masks)
            .map(|(&k, m)| joints[k as usize].law.equality_rows() + m.count_ones() as usize)
            .collect();
        if order.len() < 2 || rows.iter().all(|&r| r == 0) {
            continue;
        }
        // Profile: each row reaches back to the first row of the earliest
        // joint (in this order) that shares a dynamic body with its joint.
        for (p, &k) in order.iter().enumerate() {
            position[k as usize] = p;
        }
        let mut offsets = Vec::with_capacity(order.len() + 1);
        let mut total = 0;
        for &r in &rows {
            offsets.push(total);
            total += r;
        }
        offsets.push(total);
        let mut first = Vec::with_capacity(total);
        let mut start = Vec::with_capacity(total);
        let mut size = 0usize;
        let mut couplings = Vec::new();
        for (p, &k) in order.iter().enumerate() {
            let j = &joints[k as usize];
            let mut earliest = p;
            for (side_p, b) in [j.a, j.b].into_iter().enumerate() {
                if !bodies[b as usize].dynamic {
                    continue;
                }
                for &other in &of_body[b as usize] {
                    let q = position[other as usize];
                    if q > p || (q == p && other != k) {
                        continue;
                    }
                    let o = &joints[other as usize];
                    let side_q = if o.a == b { 0 } else { 1 };
                    // A joint meets itself on this side only.
                    if q == p && side_q != side_p {
                        continue;
                    }
                    couplings.push(Coupling {
                        p: p as u32,
                        q: q as u32,
                        side_p: side_p as u8,
                        side_q: side_q as u8,
                    });
                }
            }
            for b in [j.a, j.b] {
                if bodies[b as usize].dynamic {
                    for &other in &of_body[b as usize] {
                        earliest = earliest.min(position[other as usize]);
                    }
                }
            }
            for e in 0..rows[p] {
                let i = offsets[p] + e;
                first.push(offsets[earliest]);
                start.push(size);
                size += i - offsets[earliest] + 1;
            }
        }
        if size > MAX_PROFILE {
            continue;
        }
        // The aim is a fixed-point iteration through the whole island; its
        // gain grows with the mass ratio across it: a 20-link rope of 0.1 kg
        // links holding 10 kg came apart with it (and holds without), while
        // a double pendulum of equal masses keeps its energy only with it.
        let masses: Vec<f64> = order
            .iter()
            .flat_map(|&k| [joints[k as usize].a, joints[k as usize].b])
            .filter(|&b| bodies[b as usize].dynamic && bodies[b as usize].inv_mass > 0.0)
            .map(|b| 1.0 / bodies[b as usize].inv_mass)
            .collect();
        let (lightest, heaviest) = masses
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), &m| (lo.min(m), hi.max(m)));
        let aim = heaviest <= AIM_MASS_RATIO * lightest;
        for (&k, &mask) in order.iter().zip(&masks) {
            joints[k as usize].direct = true;
            joints[k as usize].island_rows = mask;
        }
        islands.push(JointIsland {
            joints: order,
            offsets,
            first,
            start,
            factor: vec![0.0; size],
            inv_diagonal: vec![0.0; total],
            couplings,
            bounded: masks.iter().any(|&m| m != 0),
            rhs: Vec::new(),
            scratch: Vec::new(),
            aim,
        });
    }
    islands
}
