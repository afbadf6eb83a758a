//! Semi-implicit Euler with a symplectic splitting for the rotation (McLachlan, "Explicit
//! Lie-Poisson integration and the Euler equations", Phys. Rev. Lett. 71, 1993; Dullweber,
//! Leimkuhler & McLachlan, "Symplectic splitting methods for rigid body molecular
//! dynamics", J. Chem. Phys. 107, 1997; Reich 1994).
//!
//! Why: with `L` held fixed, both forward and semi-implicit Euler turn the body with the
//! `omega` of the start of the step; for an asymmetric body the kinetic energy
//! `1/2 L . I^-1(t) L` then grows steadily (tens of percent over a few hundred steps of
//! a fast-tumbling box). Here the kick of the momenta is the same as semi-implicit Euler,
//! but the free rotation under the new `L` is advanced by Strang splitting of the
//! free-rotor Hamiltonian `H = sum_i Pi_i² / (2 I_i)` (`Pi = R^T L`, body frame). The
//! flow of each term is exact: the body turns about its own axis `e_i` by the angle
//! `h Pi_i / I_i` (`Pi_i` is constant under it), i.e. `q <- q exp(e_i h Pi_i / (2 I_i))`.
//! The composition 1(h/2) 2(h/2) 3(h) 2(h/2) 1(h/2) is symmetric, hence second order,
//! and symplectic: the energy error stays bounded (O(h²), no drift), `L` is untouched, and
//! `q` stays unit up to round-off. A body with equal moments (sphere, cube) or two
//! equal moments (capsule, cylinder: a symmetric top) has a closed-form free rotation,
//! which is taken instead: exact, and one or two turns for five. Translation is
//! semi-implicit Euler (first order): the kick and drift are symplectic.rs's
//! `kick_and_drift`, given the turn above.

use super::ode::Params;
use super::symplectic::kick_and_drift;
use super::ForceField;
use crate::body::BodyState;
use tumble_collide::math::{DQuat, DVec3};

/// `(sin x, cos x)`. Sub-steps turn bodies by small angles, where the Taylor
/// series to x^9 / x^10 is exact to round-off (the first dropped terms are
/// below 1e-19 for |x| <= 0.1) and several times cheaper than the library
/// call; larger angles take the library call.
#[inline(always)]
fn sin_cos(x: f64) -> (f64, f64) {
    if x.abs() > SERIES_LIMIT {
        return x.sin_cos();
    }
    sin_cos_series(x)
}

/// Largest |x| for which [`sin_cos`] takes the series.
pub(crate) const SERIES_LIMIT: f64 = 0.1;

/// The series of [`sin_cos`], for `f64` and for the contact solver's SIMD
/// lanes alike (the same operations in the same order: the same bits).
#[inline(always)]
pub(crate) fn sin_cos_series<T>(x: T) -> (T, T)
where
    T: Copy + From<f64> + std::ops::Mul<Output = T> + std::ops::Sub<Output = T> + std::ops::Div<Output = T>,
{
    let k = T::from;
    let one = k(1.0);
    let x2 = x * x;
    let s = x
        * (one
            - x2 * k(1.0 / 6.0)
                * (one - x2 * k(1.0 / 20.0) * (one - x2 * k(1.0 / 42.0) * (one - x2 * k(1.0 / 72.0)))));
    let c = one
        - x2 * k(0.5)
            * (one
                - x2 * k(1.0 / 12.0)
                    * (one - x2 * k(1.0 / 30.0) * (one - x2 * k(1.0 / 56.0) * (one - x2 * k(1.0 / 90.0)))));
    (s, c)
}

/// Turns `q` about its body axis `axis` (0, 1, 2) for time `h` under the part
/// `Pi_axis² / (2 I_axis)` of the free-rotor Hamiltonian with world momentum `l`.
#[inline(always)]
fn principal_flow(q: DQuat, l: DVec3, inv_inertia: DVec3, axis: usize, h: f64) -> DQuat {
    let pi = q.conjugate() * l;
    let angle = h * pi[axis] * inv_inertia[axis];
    turn_about_body_axis(q, axis, angle)
}

/// `q` turned by `angle` (rad) about its own body axis `axis` (0, 1, 2).
#[inline(always)]
fn turn_about_body_axis(q: DQuat, axis: usize, angle: f64) -> DQuat {
    let (s, c) = sin_cos(0.5 * angle);
    // q * (s e_axis, c), written out for the one non-zero vector component.
    let (x, y, z, w) = (q.x, q.y, q.z, q.w);
    match axis {
        0 => DQuat::from_xyzw(x * c + w * s, y * c + z * s, z * c - y * s, w * c - x * s),
        1 => DQuat::from_xyzw(x * c - z * s, y * c + w * s, z * c + x * s, w * c - y * s),
        _ => DQuat::from_xyzw(x * c + y * s, y * c - x * s, z * c + w * s, w * c - z * s),
    }
}

/// The principal axis (0, 1, 2) about which a body with inverse principal
/// moments `inv_inertia` is symmetric: the one whose moment differs from the
/// two others, which are equal (a capsule, a cylinder, a cone, a box with two
/// equal sides). `None` when all three are equal or all three differ.
#[inline(always)]
pub(crate) fn symmetry_axis(inv_inertia: DVec3) -> Option<usize> {
    let DVec3 { x, y, z } = inv_inertia;
    if x == y && y != z {
        Some(2)
    } else if y == z && z != x {
        Some(0)
    } else if z == x && x != y {
        Some(1)
    } else {
        None
    }
}

/// The exact free rotation of a symmetric body (moment `I_3` about its body
/// axis `axis`, `I_1` about the two others): with `L` fixed, the body turns
/// about `L` at the rate `|L| / I_1` and about its own axis at the rate
/// `Pi_3 (1 / I_3 - 1 / I_1)`, where `Pi_3 = L . e_3` stays constant, so that
/// `w = L / I_1 + Pi_3 (1 / I_3 - 1 / I_1) e_3` (Landau & Lifshitz,
/// Mechanics, section 33). Two turns for the splitting's five, and no energy
/// error at all: neither turn changes the body-frame momentum's length or
/// its axial part.
#[inline(always)]
fn symmetric_rotation(q: DQuat, l: DVec3, inv_inertia: DVec3, axis: usize, h: f64) -> DQuat {
    let (transverse, axial) = (inv_inertia[(axis + 1) % 3], inv_inertia[axis]);
    let q = turn_by(l * (transverse * h)) * q;
    let pi = q.conjugate() * l;
    turn_about_body_axis(q, axis, h * pi[axis] * (axial - transverse))
}

/// Advances the orientation `q` of a free rotor with world angular momentum
/// `l` and inverse principal inertia `inv_inertia` over `h` by the symmetric
/// principal-axis splitting 1(h/2) 2(h/2) 3(h) 2(h/2) 1(h/2): second order,
/// symplectic, energy error bounded without drift. Used by the integrator
/// below and by the contact solver's position update.
///
/// A body with equal principal moments (sphere, cube) spins about the fixed
/// axis of `l` at the constant rate `l / I`: that exact flow is taken
/// instead, one turn for the five of the splitting; a body with two equal
/// moments (capsule, cylinder) takes its exact flow too, two turns
/// (`symmetric_rotation`).
#[inline]
pub fn free_rotation(q: DQuat, l: DVec3, inv_inertia: DVec3, h: f64) -> DQuat {
    if inv_inertia.x == inv_inertia.y && inv_inertia.y == inv_inertia.z {
        return turn_by(l * (inv_inertia.x * h)) * q;
    }
    if let Some(axis) = symmetry_axis(inv_inertia) {
        return symmetric_rotation(q, l, inv_inertia, axis, h);
    }
    let half = 0.5 * h;
    let mut q = q;
    q = principal_flow(q, l, inv_inertia, 0, half);
    q = principal_flow(q, l, inv_inertia, 1, half);
    q = principal_flow(q, l, inv_inertia, 2, h);
    q = principal_flow(q, l, inv_inertia, 1, half);
    principal_flow(q, l, inv_inertia, 0, half)
}

/// The unit quaternion of a turn by the rotation vector `angle` (rad).
#[inline(always)]
pub fn turn_by(angle: DVec3) -> DQuat {
    let theta = angle.length();
    if theta == 0.0 {
        return DQuat::IDENTITY;
    }
    let (s, c) = sin_cos(0.5 * theta);
    let axis = angle * (s / theta);
    DQuat::from_xyzw(axis.x, axis.y, axis.z, c)
}

/// `P1 = P + h F(y)`, `L1 = L + h tau(y)`, `x1 = x + h P1 / M`, and `q1` from the
/// symmetric principal-axis splitting of the free rotation under `L1`.
#[inline(always)]
pub(crate) fn semi_implicit_splitting<F: ForceField + ?Sized>(
    p: &Params,
    y: &BodyState,
    t: f64,
    h: f64,
    field: &F,
) -> BodyState {
    kick_and_drift(p, y, t, h, field, |q, l| free_rotation(q, l, p.inv_inertia, h))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_sin_cos_agrees_with_the_library() {
        for i in -1000..=1000 {
            let x = i as f64 * 1e-4;
            let (s, c) = sin_cos(x);
            assert!((s - x.sin()).abs() <= 2e-17, "sin {x}");
            assert!((c - x.cos()).abs() <= 2e-16, "cos {x}");
        }
    }

    #[test]
    fn isotropic_bodies_spin_about_their_momentum_at_l_over_i() {
        let q = DQuat::from_xyzw(0.3, -0.5, 0.2, 0.7).normalize();
        let l = DVec3::new(0.4, -1.1, 2.3);
        let turned = free_rotation(q, l, DVec3::splat(2.0), 0.01);
        let expected = DQuat::from_scaled_axis(l * 0.02) * q;
        assert!((turned - expected).length() < 1e-15);
        // The general splitting approaches the same flow as h -> 0.
        let h = 1e-4;
        let split = free_rotation(q, l, DVec3::new(2.0, 2.0 + 1e-12, 2.0 - 1e-12), h);
        let exact = free_rotation(q, l, DVec3::splat(2.0), h);
        assert!((split - exact).length() < 1e-10);
    }

    /// The five-flow splitting itself, whatever the moments.
    fn split(q: DQuat, l: DVec3, inv: DVec3, h: f64) -> DQuat {
        let mut q = q;
        for (axis, t) in [(0, 0.5 * h), (1, 0.5 * h), (2, h), (1, 0.5 * h), (0, 0.5 * h)] {
            q = principal_flow(q, l, inv, axis, t);
        }
        q
    }

    /// Same rotation, whichever sign the quaternion has.
    fn apart(p: DQuat, q: DQuat) -> f64 {
        (p - q).length().min((p + q).length())
    }

    /// A symmetric body (two equal moments, about each of the three axes)
    /// turns by its exact flow: any number of steps land where one step of
    /// the whole time does, the splitting converges to it as h shrinks
    /// (second order), the kinetic energy and the axial momentum stay what
    /// they were to round-off over 10,000 fast steps, and the body turns at
    /// w = L / I_1 + Pi_3 (1 / I_3 - 1 / I_1) e_3.
    #[test]
    fn symmetric_bodies_take_their_exact_flow() {
        let q0 = DQuat::from_xyzw(0.3, -0.5, 0.2, 0.7).normalize();
        let l = DVec3::new(0.4, -1.1, 2.3);
        for axis in 0..3 {
            let mut inv = DVec3::splat(1.7);
            inv[axis] = 0.6;
            assert_eq!(symmetry_axis(inv), Some(axis));
            // One step of 0.5 s against 500 of 1 ms (the turns are large:
            // the library's sine for the long step, the series for the short).
            let long = free_rotation(q0, l, inv, 0.5);
            let mut q = q0;
            for _ in 0..500 {
                q = free_rotation(q, l, inv, 1e-3).normalize();
            }
            assert!(apart(q, long) < 1e-12, "axis {axis}: {}", apart(q, long));
            // The splitting converges to it, at second order.
            let splitting = |h: f64| {
                let mut q = q0;
                for _ in 0..(0.5 / h).round() as usize {
                    q = split(q, l, inv, h).normalize();
                }
                apart(q, long)
            };
            let (coarse, fine) = (splitting(1e-2), splitting(5e-3));
            assert!(
                fine < 1e-3 && coarse / fine > 3.5 && coarse / fine < 4.5,
                "axis {axis}: {coarse} {fine}"
            );
            // Energy and axial momentum over 10,000 steps of 20 ms.
            let energy = |q: DQuat| {
                let pi = q.conjugate() * l;
                0.5 * pi.dot(inv * pi)
            };
            let (e0, axial0) = (energy(q0), (q0.conjugate() * l)[axis]);
            let mut q = q0;
            for _ in 0..10_000 {
                q = free_rotation(q, l, inv, 0.02).normalize();
            }
            assert!(
                (energy(q) - e0).abs() < 1e-12 * e0,
                "axis {axis}: energy {} -> {}",
                e0,
                energy(q)
            );
            assert!(((q.conjugate() * l)[axis] - axial0).abs() < 1e-12);
            // The rate of turn at the end, by a central difference.
            let d = 1e-5;
            let ahead = free_rotation(q, l, inv, d);
            let behind = free_rotation(q, l, inv, -d);
            let w = (ahead * behind.conjugate()).to_scaled_axis() / (2.0 * d);
            let mut e3 = DVec3::ZERO;
            e3[axis] = 1.0;
            let e3 = q * e3;
            let expected = l * inv[(axis + 1) % 3] + e3 * (l.dot(e3) * (inv[axis] - inv[(axis + 1) % 3]));
            assert!(
                (w - expected).length() < 1e-8,
                "axis {axis}: {w} against {expected}"
            );
        }
        // Not symmetric: all equal, or all different.
        assert_eq!(symmetry_axis(DVec3::splat(2.0)), None);
        assert_eq!(symmetry_axis(DVec3::new(1.0, 2.0, 3.0)), None);
    }

    #[test]
    fn axis_turns_equal_the_quaternion_product() {
        let q = DQuat::from_xyzw(0.3, -0.5, 0.2, 0.7).normalize();
        let l = DVec3::new(0.4, -1.1, 2.3);
        let inv = DVec3::new(1.0, 2.0, 3.0);
        for axis in 0..3 {
            let turned = principal_flow(q, l, inv, axis, 0.01);
            let angle = 0.01 * (q.conjugate() * l)[axis] * inv[axis];
            let mut e = DVec3::ZERO;
            e[axis] = 1.0;
            let expected = q * DQuat::from_axis_angle(e, angle);
            assert!((turned - expected).length() < 1e-15, "axis {axis}");
        }
    }
}
