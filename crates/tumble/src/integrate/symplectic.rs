//! Semi-implicit (symplectic) Euler (Hairer, Lubich & Wanner, "Geometric Numerical
//! Integration", I.1.2): kick the momenta with the forces at the old state, then drift
//! the pose with the new velocities.
//!
//! Why this order: the position update sees the velocity that the contact solver will
//! have corrected, and on oscillators the method conserves a modified energy instead of
//! spiralling out like forward Euler.

use super::ode::Params;
use super::ForceField;
use crate::body::angular_velocity_of;
use crate::body::BodyState;
use tumble_collide::math::quat_derivative;

// `semi_implicit_splitting` (splitting.rs) opens with this same signature
// and kick; it differs in turning the body by the exact free-rotor flow.
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
    let (f_ext, tau_ext) = field.wrench(p.index, y, t);
    let linear_momentum = y.linear_momentum + (p.force + f_ext) * h;
    let angular_momentum = y.angular_momentum + (p.torque + tau_ext) * h;
    let omega = angular_velocity_of(y.orientation, p.inv_inertia, angular_momentum);
    BodyState {
        position: y.position + linear_momentum * (p.inv_mass * h),
        orientation: y.orientation + quat_derivative(omega, y.orientation) * h,
        linear_momentum,
        angular_momentum,
    }
}
