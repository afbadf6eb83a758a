//! Semi-implicit (symplectic) Euler (Hairer, Lubich & Wanner, "Geometric Numerical
//! Integration", I.1.2): kick the momenta with the forces at the old state, then drift
//! the pose with the new velocities.
//!
//! Why this order: the position update sees the velocity that the contact solver will
//! have corrected, and on oscillators the method conserves a modified energy instead of
//! spiralling out like forward Euler.
//!
//! `semi_implicit_splitting` (splitting.rs) is this method with another turn:
//! both call `kick_and_drift`, and their heads read alike because each
//! keeps the one signature `Integrator` dispatches on (mod.rs).

use super::ode::Params;
use super::ForceField;
use crate::body::angular_velocity_of;
use crate::body::BodyState;
use tumble_collide::math::{quat_derivative, DQuat, DVec3};

/// `P1 = P + h F(y)`, `L1 = L + h tau(y)`, `x1 = x + h P1 / M`,
/// `q1 = q + h/2 [0, omega(q, L1)] q`.
#[inline(always)]
pub(crate) fn semi_implicit_euler<F: ForceField + ?Sized>(
    p: &Params,
    y: &BodyState,
    t: f64,
    h: f64,
    field: &F,
) -> BodyState {
    kick_and_drift(p, y, t, h, field, |q, angular_momentum| {
        let omega = angular_velocity_of(q, p.inv_inertia, angular_momentum);
        q + quat_derivative(omega, q) * h
    })
}

/// The step both semi-implicit methods share (this one and
/// `semi_implicit_splitting` in splitting.rs): kick the momenta with the
/// wrench at `y`, drift the position with the new `P1`, and turn the body by
/// `turn(q, L1)`, the one part in which the two methods differ. Its head is
/// their dispatch signature (mod.rs) plus `turn`.
#[inline(always)]
pub(super) fn kick_and_drift<F: ForceField + ?Sized>(
    p: &Params,
    y: &BodyState,
    t: f64,
    h: f64,
    field: &F,
    turn: impl FnOnce(DQuat, DVec3) -> DQuat,
) -> BodyState {
    let (f_ext, tau_ext) = field.wrench(p.index, y, t);
    let linear_momentum = y.linear_momentum + (p.force + f_ext) * h;
    let angular_momentum = y.angular_momentum + (p.torque + tau_ext) * h;
    BodyState {
        position: y.position + linear_momentum * (p.inv_mass * h),
        orientation: turn(y.orientation, angular_momentum),
        linear_momentum,
        angular_momentum,
    }
}
