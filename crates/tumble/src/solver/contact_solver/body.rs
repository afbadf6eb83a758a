//! The solver's view of a body: velocities, inverse mass properties and the
//! motion accumulated over the step, in one contiguous array (static and
//! sleeping bodies share the immovable entry 0).

use super::lanes::{self, Lane, LANES, M3, Q4, V3};
use crate::integrate::{sin_cos_series, symmetry_axis, SERIES_LIMIT};
use tumble_collide::{DMat3, DQuat, DVec3};

/// Per-body solver state. Static and kinematic bodies have zero inverse mass
/// and inertia, so impulses never change their velocities.
///
/// Laid out by when the passes read it, one cache line per use: the
/// velocity passes read a body's velocities and whether it is dynamic
/// (the first line), the push-out passes its pseudo-velocities too (the
/// second), the sub-step starts and the integration the rest. Each body
/// starts a line of its own (`align(64)`), so that a pass over a bundle of
/// patches fetches one line per body, not the two or three that a field
/// order chosen by the compiler, with the flag last, spread them over.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(64))]
pub struct SolverBody {
    /// Linear velocity (m/s).
    pub v: DVec3,
    /// Angular velocity, world frame (rad/s).
    pub w: DVec3,
    /// Inverse mass (1/kg); 0 for static and kinematic bodies.
    pub inv_mass: f64,
    /// `true` for dynamic bodies (integrated and pushed by impulses).
    pub dynamic: bool,
    /// `true` for kinematic bodies: moved by their velocity, never pushed.
    pub kinematic: bool,
    /// Pseudo-velocity of the push-out pass (m/s), discarded every sub-step.
    pub push_v: DVec3,
    /// Pseudo angular velocity of the push-out pass (rad/s).
    pub push_w: DVec3,
    /// Displacement of the centre of mass since the start of the step (m).
    pub dp: DVec3,
    /// Rotation since the start of the step as a matrix, `R(q) R(q0)^T`: it
    /// carries the step-start lever arms to the current pose.
    pub turn: DMat3,
    /// Inverse inertia in the world frame for the current orientation.
    pub inv_inertia: DMat3,
    /// Orientation (body to world), current.
    pub q: DQuat,
    /// Inverse principal inertia in the body frame (1/(kg m^2)).
    pub inv_inertia_body: DVec3,
}

impl SolverBody {
    /// An immovable body (the shared entry for static and sleeping bodies).
    pub fn fixed() -> SolverBody {
        SolverBody::new(DVec3::ZERO, DVec3::ZERO, 0.0, DVec3::ZERO, DQuat::IDENTITY)
    }

    /// A body at the start of a step: orientation `q`, velocities, inverse
    /// mass and inverse principal inertia (zero for bodies that are not
    /// pushed). It is dynamic when its inverse mass is positive.
    pub fn new(v: DVec3, w: DVec3, inv_mass: f64, inv_inertia_body: DVec3, q: DQuat) -> SolverBody {
        SolverBody {
            v,
            w,
            inv_mass,
            inv_inertia_body,
            inv_inertia: SolverBody::world_inverse_inertia(q, inv_inertia_body),
            q,
            turn: DMat3::IDENTITY,
            dp: DVec3::ZERO,
            push_v: DVec3::ZERO,
            push_w: DVec3::ZERO,
            dynamic: inv_mass > 0.0,
            kinematic: false,
        }
    }

    /// World-frame inverse inertia `R diag(I^-1) R^T`.
    pub fn world_inverse_inertia(q: DQuat, inv_inertia_body: DVec3) -> DMat3 {
        let r = DMat3::from_quat(q);
        r * DMat3::from_diagonal(inv_inertia_body) * r.transpose()
    }

    /// The body as the dense LCP assembly sees it (`solver::delassus`).
    pub fn lcp_state(&self) -> crate::solver::BodyState {
        crate::solver::BodyState {
            inv_mass: self.inv_mass,
            inv_inertia: self.inv_inertia,
            linear_velocity: self.v,
            angular_velocity: self.w,
        }
    }

    /// Velocity of the point at offset `r` from the centre of mass.
    #[inline]
    pub fn velocity_at(&self, r: DVec3) -> DVec3 {
        self.v + self.w.cross(r)
    }

    /// Applies an impulse (N s) at offset `r`.
    #[inline]
    pub fn apply_impulse(&mut self, impulse: DVec3, r: DVec3) {
        self.v += impulse * self.inv_mass;
        self.w += self.inv_inertia * r.cross(impulse);
    }

    /// Makes the body immovable (quarantine): no velocity, no mass.
    pub fn freeze(&mut self) {
        self.v = DVec3::ZERO;
        self.w = DVec3::ZERO;
        self.inv_mass = 0.0;
        self.inv_inertia_body = DVec3::ZERO;
        self.inv_inertia = DMat3::ZERO;
        self.dynamic = false;
        self.kinematic = false;
    }
}

/// Advances orientation and displacement of dynamic and kinematic bodies by
/// one sub-step with their current velocities (semi-implicit Euler), keeping
/// angular momentum: `L = I(t) w` is carried across the rotation, so a free
/// body precesses correctly (gyroscopic effect) instead of keeping `w` fixed.
/// The push-out pseudo-velocities move the body too and are then cleared.
/// `q0` holds each body's orientation at the step start (for [`SolverBody::turn`]).
///
/// Four bodies at a time in SIMD lanes, grouped by how they turn (equal
/// moments, symmetric about each axis, all moments different): a group of
/// one kind computes one flow, where four neighbours in the array (a
/// ragdoll's torso among its limbs) would compute every kind they hold. A
/// body's result does not depend on its group (the lanes give the bits of
/// one body at a time), so neither does the grouping change a bit.
pub fn integrate_positions(bodies: &mut [SolverBody], q0: &[DQuat], h: f64) {
    let n = bodies.len().min(q0.len());
    let (bodies, q0) = (&mut bodies[..n], &q0[..n]);
    for (window, q_window) in bodies.chunks_mut(GROUPING_WINDOW).zip(q0.chunks(GROUPING_WINDOW)) {
        // Slots of the window by kind: 0 equal moments, 1-3 symmetric about
        // x, y, z, 4 all different, 5 one at a time (kinematic, static).
        let mut kinds = [[0u8; GROUPING_WINDOW]; 6];
        let mut counts = [0usize; 6];
        for (i, b) in window.iter().enumerate() {
            let kind = if !b.dynamic || b.kinematic {
                5
            } else {
                let inv = b.inv_inertia_body;
                if inv.x == inv.y && inv.y == inv.z {
                    0
                } else {
                    symmetry_axis(inv).map_or(4, |axis| 1 + axis)
                }
            };
            kinds[kind][counts[kind]] = i as u8;
            counts[kind] += 1;
        }
        for kind in 0..6 {
            let slots = &kinds[kind][..counts[kind]];
            let mut groups = slots.chunks_exact(LANES);
            if kind < 5 {
                for g in &mut groups {
                    let idx: [usize; LANES] = std::array::from_fn(|l| g[l] as usize);
                    let q: [DQuat; LANES] = idx.map(|i| q_window[i]);
                    // The slots of a window are distinct, so the four are
                    // always disjoint; one at a time otherwise, not a panic.
                    match window.get_disjoint_mut(idx) {
                        Ok(mut four) => {
                            if !turn_four(&mut four, &q, h) {
                                for (b, &q) in four.into_iter().zip(&q) {
                                    integrate_one(b, q, h);
                                }
                            }
                        }
                        Err(_) => {
                            for (&i, &q) in idx.iter().zip(&q) {
                                integrate_one(&mut window[i], q, h);
                            }
                        }
                    }
                }
            }
            let rest = if kind < 5 { groups.remainder() } else { slots };
            for &i in rest {
                integrate_one(&mut window[i as usize], q_window[i as usize], h);
            }
        }
    }
}

/// Bodies grouped at a time by [`integrate_positions`] (at most 256, its
/// slots are bytes): the solver's blocks of bodies per thread hold 64.
const GROUPING_WINDOW: usize = 64;

/// [`integrate_positions`] for four dynamic bodies, one per SIMD lane: the
/// scalar path's operations in the same order (the same bits), bodies of
/// equal principal moments (spheres, cubes) turning by the exact flow and
/// the others as [`turn_freely`] turns them (symmetric bodies by their exact
/// flow, the rest by the splitting), each lane computing every kind the
/// four need and keeping its own; the push-out's turn, where a body has
/// one, body by body in between. Returns `false`, having changed nothing, when one of
/// the four is not a dynamic body or turns by more than the series of
/// `sin_cos` covers.
#[inline(always)]
fn turn_four(b: &mut [&mut SolverBody; LANES], q0: &[DQuat; LANES], h: f64) -> bool {
    if !b.iter().all(|b| b.dynamic && !b.kinematic) {
        return false;
    }
    let equal_flags: [bool; LANES] = std::array::from_fn(|l| {
        let i = b[l].inv_inertia_body;
        i.x == i.y && i.y == i.z
    });
    let equal = lanes::mask(equal_flags);
    let any_free = equal_flags.contains(&false);
    let h_lane = Lane::splat(h);
    let w = V3::from_lanes(std::array::from_fn(|l| b[l].w));
    let angle = w.scale(h_lane);
    let theta = angle.dot(angle).sqrt();
    let half = Lane::splat(0.5) * theta;
    let limit = |x: Lane, lanes: Lane| {
        lanes::select(lanes, x.abs(), Lane::ZERO)
            .to_array()
            .iter()
            .any(|&x| x > SERIES_LIMIT)
    };
    if limit(half, equal) {
        return false;
    }
    let q_start = Q4::from_lanes(std::array::from_fn(|l| b[l].q));
    let inv = V3::from_lanes(std::array::from_fn(|l| b[l].inv_inertia_body));
    let free = if any_free {
        let unequal = lanes::mask(equal_flags.map(|e| !e));
        let axes = std::array::from_fn(|l| symmetry_axis(b[l].inv_inertia_body));
        let Some(turned) = turn_freely_four(q_start, w, inv, h, (unequal, axes), &limit) else {
            return false;
        };
        Some(turned)
    } else {
        None
    };
    let v = V3::from_lanes(std::array::from_fn(|l| b[l].v + b[l].push_v)).scale(h_lane);
    let dp = (V3::from_lanes(std::array::from_fn(|l| b[l].dp)) + v).to_lanes();
    let q_equal = turn_by_four(angle, theta, half).mul(q_start).normalize();
    let (q, w_free, inv_world) = match free {
        Some((q_free, w_free)) => {
            let q = Q4 {
                x: lanes::select(equal, q_equal.x, q_free.x),
                y: lanes::select(equal, q_equal.y, q_free.y),
                z: lanes::select(equal, q_equal.z, q_free.z),
                w: lanes::select(equal, q_equal.w, q_free.w),
            };
            // `SolverBody::world_inverse_inertia`: R diag(I^-1) R^T.
            let r = q_free.to_mat3();
            let world = r.mul(&M3::diagonal(inv)).mul(&r.transpose());
            (q, Some(w_free.to_lanes()), Some(world.to_lanes()))
        }
        None => (q_equal, None, None),
    };
    let q = q.to_lanes();
    for l in 0..LANES {
        b[l].dp = dp[l];
        b[l].q = q[l];
        if !equal_flags[l] {
            // `turn_freely`: w follows L to the new pose, and the world
            // inverse inertia too unless a push-out turn follows.
            if let (Some(w), Some(world)) = (&w_free, &inv_world) {
                b[l].w = w[l];
                if b[l].push_w == DVec3::ZERO {
                    b[l].inv_inertia = world[l];
                }
            }
        }
    }
    push_turn_four(b, h);
    let q = Q4::from_lanes(std::array::from_fn(|l| b[l].q));
    let start = Q4::from_lanes(std::array::from_fn(|l| q0[l]));
    let turned = q.mul(start.conjugate()).to_mat3().to_lanes();
    for l in 0..LANES {
        b[l].turn = turned[l];
        b[l].push_v = DVec3::ZERO;
        b[l].push_w = DVec3::ZERO;
    }
    true
}

/// [`turn_freely`]'s orientation and angular velocity on four lanes (every
/// lane computed; only those in the mask `checked`, whose answer is used,
/// are held to the series' limit): lanes of a symmetric body (`axes[l]`,
/// its symmetry axis) turn by the exact flow of
/// `integrate::free_rotation`, two turns, and the others by its splitting,
/// five; each kind is computed only where a checked lane needs it. `None`
/// when a checked lane turns by more than the series covers in one of its
/// flows.
#[inline(always)]
fn turn_freely_four(
    q: Q4,
    w: V3,
    inv: V3,
    h: f64,
    (checked, axes): (Lane, [Option<usize>; LANES]),
    limit: &impl Fn(Lane, Lane) -> bool,
) -> Option<(Q4, V3)> {
    let inertia = V3 {
        x: lanes::recip_or_zero(inv.x),
        y: lanes::recip_or_zero(inv.y),
        z: lanes::recip_or_zero(inv.z),
    };
    let l = q.rotate(inertia.mul_each(q.conjugate().rotate(w)));
    let symmetric = checked & lanes::mask(axes.map(|a| a.is_some()));
    let general = checked & lanes::mask(axes.map(|a| a.is_none()));
    let split = if any_lane(general) {
        Some(split_four(q, l, inv, h, general, limit)?)
    } else {
        None
    };
    let exact = if any_lane(symmetric) {
        Some(symmetric_four(q, l, inv, h, (symmetric, axes), limit)?)
    } else {
        None
    };
    let q = match (split, exact) {
        (Some(split), Some(exact)) => Q4::select(symmetric, exact, split),
        (Some(q), None) | (None, Some(q)) => q,
        (None, None) => q,
    };
    let q = q.normalize();
    let w = q.rotate(inv.mul_each(q.conjugate().rotate(l)));
    Some((q, w))
}

/// `true` when some lane of the mask is set.
#[inline(always)]
fn any_lane(mask: Lane) -> bool {
    mask.to_array().iter().any(|&x| x.to_bits() != 0)
}

/// `integrate::free_rotation`'s splitting, 1(h/2) 2(h/2) 3(h) 2(h/2) 1(h/2),
/// on four lanes (not normalized).
#[inline(always)]
fn split_four(
    q: Q4,
    l: V3,
    inv: V3,
    h: f64,
    checked: Lane,
    limit: &impl Fn(Lane, Lane) -> bool,
) -> Option<Q4> {
    let half = 0.5 * h;
    let mut q = q;
    for (axis, t) in [(0, half), (1, half), (2, h), (1, half), (0, half)] {
        // `splitting::principal_flow`, lane by lane.
        let pi = q.conjugate().rotate(l);
        let angle = Lane::splat(t) * pi.component(axis) * inv.component(axis);
        q = turn_about_body_axis_four(q, axis, angle, checked, limit)?;
    }
    Some(q)
}

/// `splitting::symmetric_rotation` on four lanes, lane `l` about its own
/// symmetry axis `axes[l]` (not normalized): the turn about the momentum,
/// then the turn about the body's axis.
#[inline(always)]
fn symmetric_four(
    q: Q4,
    l: V3,
    inv: V3,
    h: f64,
    (checked, axes): (Lane, [Option<usize>; LANES]),
    limit: &impl Fn(Lane, Lane) -> bool,
) -> Option<Q4> {
    let inv_lanes = inv.to_lanes();
    let axis_of = |k: usize| axes[k].unwrap_or(2);
    let transverse = Lane::new(std::array::from_fn(|k| inv_lanes[k][(axis_of(k) + 1) % 3]));
    let axial = Lane::new(std::array::from_fn(|k| inv_lanes[k][axis_of(k)]));
    // `turn_by(l * (transverse * h)) * q`.
    let angle = l.scale(transverse * Lane::splat(h));
    let theta = angle.dot(angle).sqrt();
    let half = Lane::splat(0.5) * theta;
    if limit(half, checked) {
        return None;
    }
    let q = turn_by_four(angle, theta, half).mul(q);
    // The turn about the body's own axis by `h pi_3 (axial - transverse)`.
    let pi = q.conjugate().rotate(l);
    let mut turned = q;
    for axis in 0..3 {
        let on = checked & lanes::mask(std::array::from_fn(|k| axes[k] == Some(axis)));
        if !any_lane(on) {
            continue;
        }
        let angle = Lane::splat(h) * pi.component(axis) * (axial - transverse);
        let about = turn_about_body_axis_four(q, axis, angle, on, limit)?;
        turned = Q4::select(on, about, turned);
    }
    Some(turned)
}

/// `integrate::turn_by` on four lanes: the turn by the rotation vector
/// `angle` of length `theta` (`half` = `theta / 2`, within the series'
/// limit): the identity for no turn, else (axis sin, cos) of half the angle.
#[inline(always)]
fn turn_by_four(angle: V3, theta: Lane, half: Lane) -> Q4 {
    let (s, c) = sin_cos_series(half);
    let axis = angle.scale(s / theta);
    let still = lanes::eq(theta, Lane::ZERO);
    Q4 {
        x: lanes::select(still, Lane::ZERO, axis.x),
        y: lanes::select(still, Lane::ZERO, axis.y),
        z: lanes::select(still, Lane::ZERO, axis.z),
        w: lanes::select(still, Lane::ONE, c),
    }
}

/// `splitting::turn_about_body_axis` on four lanes: `q` turned by `angle`
/// about its body axis `axis`; `None` when a lane of `checked` turns by more
/// than the series covers.
#[inline(always)]
fn turn_about_body_axis_four(
    q: Q4,
    axis: usize,
    angle: Lane,
    checked: Lane,
    limit: &impl Fn(Lane, Lane) -> bool,
) -> Option<Q4> {
    let x = Lane::splat(0.5) * angle;
    if limit(x, checked) {
        return None;
    }
    let (s, c) = sin_cos_series(x);
    let (qx, qy, qz, qw) = (q.x, q.y, q.z, q.w);
    Some(match axis {
        0 => Q4 {
            x: qx * c + qw * s,
            y: qy * c + qz * s,
            z: qz * c - qy * s,
            w: qw * c - qx * s,
        },
        1 => Q4 {
            x: qx * c - qz * s,
            y: qy * c + qw * s,
            z: qz * c + qx * s,
            w: qw * c - qy * s,
        },
        _ => Q4 {
            x: qx * c + qy * s,
            y: qy * c - qx * s,
            z: qz * c + qw * s,
            w: qw * c - qz * s,
        },
    })
}

/// [`integrate_positions`], body by body.
#[cfg(test)]
fn integrate_each(bodies: &mut [SolverBody], q0: &[DQuat], h: f64) {
    for (b, &q_start) in bodies.iter_mut().zip(q0) {
        integrate_one(b, q_start, h);
    }
}

/// [`integrate_positions`] for one body, `q_start` its orientation at the
/// step's start.
fn integrate_one(b: &mut SolverBody, q_start: DQuat, h: f64) {
    if b.kinematic {
        b.dp += b.v * h;
        b.q = (DQuat::from_scaled_axis(b.w * h) * b.q).normalize();
        b.turn = DMat3::from_quat(b.q * q_start.conjugate());
        return;
    }
    if !b.dynamic {
        return;
    }
    b.dp += (b.v + b.push_v) * h;
    let inv_i = b.inv_inertia_body;
    if inv_i.x == inv_i.y && inv_i.y == inv_i.z {
        // Equal principal moments: w stays constant during the free turn
        // and the world inverse inertia is the same diagonal.
        b.q = (crate::integrate::turn_by(b.w * h) * b.q).normalize();
    } else {
        turn_freely(b, h);
    }
    push_turn(b, h);
    b.turn = DMat3::from_quat(b.q * q_start.conjugate());
    b.push_v = DVec3::ZERO;
    b.push_w = DVec3::ZERO;
}

/// [`push_turn`] on four bodies: each turn's quaternion lane by lane
/// (glam's `from_scaled_axis`, for its `sin_cos`), the rest four lanes at a
/// time by the scalar path's operations in its order (the same bits); a
/// jointed body is pushed in most sub-steps.
#[inline(always)]
fn push_turn_four(b: &mut [&mut SolverBody; LANES], h: f64) {
    let pushed: [bool; LANES] = std::array::from_fn(|l| b[l].push_w != DVec3::ZERO);
    if pushed.iter().filter(|&&p| p).count() < 2 {
        for body in b.iter_mut() {
            push_turn(body, h);
        }
        return;
    }
    let turn = Q4::from_lanes(std::array::from_fn(|l| {
        if pushed[l] {
            DQuat::from_scaled_axis(b[l].push_w * h)
        } else {
            DQuat::IDENTITY
        }
    }));
    let q = turn
        .mul(Q4::from_lanes(std::array::from_fn(|l| b[l].q)))
        .normalize();
    let w = turn.rotate(V3::from_lanes(std::array::from_fn(|l| b[l].w)));
    // `SolverBody::world_inverse_inertia`: R diag(I^-1) R^T.
    let r = q.to_mat3();
    let inv = V3::from_lanes(std::array::from_fn(|l| b[l].inv_inertia_body));
    let world = r.mul(&M3::diagonal(inv)).mul(&r.transpose());
    let (q, w, world) = (q.to_lanes(), w.to_lanes(), world.to_lanes());
    for l in 0..LANES {
        if pushed[l] {
            b[l].q = q[l];
            b[l].w = w[l];
            b[l].inv_inertia = world[l];
        }
    }
}

/// The push-out's turn of a body by its pseudo angular velocity over `h`
/// (none when it is zero).
#[inline(always)]
fn push_turn(b: &mut SolverBody, h: f64) {
    if b.push_w != DVec3::ZERO {
        // The push-out turns the body as a whole, its motion with it: the
        // body-frame angular velocity is kept, so the push-out changes
        // neither the kinetic energy nor |L| (only L's direction, by the
        // small correction angle).
        let turn = DQuat::from_scaled_axis(b.push_w * h);
        b.q = (turn * b.q).normalize();
        b.w = turn * b.w;
        b.inv_inertia = SolverBody::world_inverse_inertia(b.q, b.inv_inertia_body);
    }
}

/// Free rotation under the constant L (`integrate::free_rotation`: the exact
/// flow of a symmetric body, else the symplectic principal-axis splitting),
/// with w updated to the new pose, and the world inverse inertia too unless
/// a push-out turn follows (which sets it).
fn turn_freely(b: &mut SolverBody, h: f64) {
    let inertia_body = DVec3::new(
        recip_or_zero(b.inv_inertia_body.x),
        recip_or_zero(b.inv_inertia_body.y),
        recip_or_zero(b.inv_inertia_body.z),
    );
    // L = R I R^T w and w = R I^-1 R^T L through the quaternion (two
    // rotations each, no 3 x 3 matrices built).
    let l = b.q * (inertia_body * (b.q.conjugate() * b.w));
    // Free rotation under the constant L, exact for a symmetric body and by
    // the symplectic principal-axis splitting otherwise: no energy drift for
    // tumbling bodies (a plain exponential map with the step's w gains
    // energy steadily on asymmetric bodies).
    b.q = crate::integrate::free_rotation(b.q, l, b.inv_inertia_body, h).normalize();
    b.w = b.q * (b.inv_inertia_body * (b.q.conjugate() * l));
    // A push-out turn follows and sets the world inverse inertia itself.
    if b.push_w == DVec3::ZERO {
        b.inv_inertia = SolverBody::world_inverse_inertia(b.q, b.inv_inertia_body);
    }
}

fn recip_or_zero(x: f64) -> f64 {
    if x > 0.0 {
        1.0 / x
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{align_of, offset_of, size_of};
    use tumble_testkit::{RandomSource, SplitMix64};

    /// The layout `SolverBody` promises: a velocity pass finds all it reads
    /// of a body in the body's first cache line, a push-out pass the rest
    /// of what it reads in the second, and every body starts a line.
    #[test]
    fn a_pass_reads_one_line_of_a_body() {
        assert_eq!(align_of::<SolverBody>(), 64);
        assert_eq!(size_of::<SolverBody>() % 64, 0);
        let end = |offset: usize, size: usize| offset + size;
        let first = [
            end(offset_of!(SolverBody, v), size_of::<DVec3>()),
            end(offset_of!(SolverBody, w), size_of::<DVec3>()),
            end(offset_of!(SolverBody, inv_mass), size_of::<f64>()),
            end(offset_of!(SolverBody, dynamic), size_of::<bool>()),
            end(offset_of!(SolverBody, kinematic), size_of::<bool>()),
        ];
        assert!(first.iter().all(|&e| e <= 64), "{first:?}");
        for (offset, size) in [
            (offset_of!(SolverBody, push_v), size_of::<DVec3>()),
            (offset_of!(SolverBody, push_w), size_of::<DVec3>()),
        ] {
            assert!(offset >= 64 && offset + size <= 128, "{offset}");
        }
    }

    /// Four bodies at a time give the body-by-body path's bits: spheres and
    /// cubes (equal moments, the exact flow), symmetric bodies about each of
    /// their three axes (two equal moments, their exact flow) and bodies of
    /// unequal moments (the splitting), alone and mixed in one group of
    /// four, spinning slow
    /// and fast (the series' limit), at rest, with and without a push-out
    /// turn, among kinematic ones (which send their group of four to the
    /// scalar path).
    #[test]
    fn four_at_a_time_is_body_by_body() {
        let mut rng = SplitMix64(11);
        let mut bodies = vec![SolverBody::fixed()];
        for i in 0..403 {
            let inv = match i % 7 {
                0 | 1 => DVec3::new(rng.range(0.5, 3.0), rng.range(0.5, 3.0), rng.range(0.5, 3.0)),
                2 if i % 3 == 0 => DVec3::new(1.0, 2.0, 2.0),
                2 => DVec3::new(1.5, 0.7, 1.5),
                3 => DVec3::new(2.5, 2.5, rng.range(0.5, 3.0)),
                _ => DVec3::splat(rng.range(0.5, 3.0)),
            };
            let spin = match i % 23 {
                0 => 0.0,
                1 => 150.0,
                _ => 8.0,
            };
            let mut b = SolverBody::new(rng.vec3(2.0), rng.vec3(spin), 1.0, inv, rng.rotation());
            if i % 3 == 0 {
                b.push_v = rng.vec3(0.5);
                b.push_w = rng.vec3(2.0);
            }
            if i % 31 == 0 {
                b = SolverBody::new(rng.vec3(1.0), rng.vec3(1.0), 0.0, DVec3::ZERO, rng.rotation());
                b.kinematic = true;
            }
            bodies.push(b);
        }
        let q0: Vec<DQuat> = bodies.iter().map(|b| b.q).collect();
        let mut each = bodies.clone();
        let mut probe = bodies.clone();
        let (mut wide, mut mixed, mut symmetric, mut pushed) = (0, 0, [0; 3], 0);
        for (b, q) in probe.chunks_exact_mut(LANES).zip(q0.chunks_exact(LANES)) {
            let equal = |b: &SolverBody| {
                let i = b.inv_inertia_body;
                i.x == i.y && i.y == i.z
            };
            let kinds = b.iter().filter(|b| equal(b)).count();
            let axes: Vec<usize> = b
                .iter()
                .filter_map(|b| symmetry_axis(b.inv_inertia_body))
                .collect();
            let [b0, b1, b2, b3] = b else {
                unreachable!("chunks of four")
            };
            let q: [DQuat; LANES] = q.try_into().expect("chunks of four");
            let pushes = [&*b0, &*b1, &*b2, &*b3]
                .iter()
                .filter(|b| b.push_w != DVec3::ZERO)
                .count();
            if turn_four(&mut [b0, b1, b2, b3], &q, 1.0 / 480.0) {
                wide += 1;
                // (`push_turn_four` takes two pushed bodies or more.)
                pushed += usize::from(pushes >= 2);
                mixed += usize::from(kinds > 0 && kinds < LANES);
                for axis in axes {
                    symmetric[axis] += 1;
                }
            }
        }
        assert!(
            wide > 40 && wide < 100 && mixed > 20 && symmetric.iter().all(|&n| n > 10) && pushed > 10,
            "every path runs: {wide} groups of four wide, {mixed} of them mixed, \
             symmetric bodies about x, y, z in them: {symmetric:?}, {pushed} with pushed turns"
        );
        let h = 1.0 / 480.0;
        for _ in 0..3 {
            integrate_positions(&mut bodies, &q0, h);
            integrate_each(&mut each, &q0, h);
        }
        assert_eq!(bodies, each);
    }
}
