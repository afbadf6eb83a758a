//! The rigid body state derivative `f(y, t)` and the stage update `y + h f`
//! (thesis 3.2: dx/dt = v, dq/dt = 1/2 omega q, dP/dt = F, dL/dt = tau).

use super::ForceField;
use crate::body::angular_velocity_of;
use crate::body::BodyState;
use tumble_collide::math::{quat_derivative, DQuat, DVec3};

/// The per-body constants of one step.
pub(crate) struct Params {
    /// Index of the body in the slice (passed to the force field).
    pub index: usize,
    /// 1 / M (1/kg).
    pub inv_mass: f64,
    /// Inverse principal moments (1/(kg m^2)).
    pub inv_inertia: DVec3,
    /// Accumulated force plus gravity `M g` (N), constant over the step.
    pub force: DVec3,
    /// Accumulated torque (N m), constant over the step.
    pub torque: DVec3,
}

/// `dy/dt` at one stage.
#[derive(Clone, Copy)]
pub(crate) struct Rates {
    pub dx: DVec3,
    pub dq: DQuat,
    pub dp: DVec3,
    pub dl: DVec3,
}

impl Rates {
    /// `a + 2 b + 2 c + d`, the RK4 weights (before the h/6 factor).
    #[inline(always)]
    pub fn rk4_sum(a: &Rates, b: &Rates, c: &Rates, d: &Rates) -> Rates {
        Rates {
            dx: a.dx + (b.dx + c.dx) * 2.0 + d.dx,
            dq: a.dq + (b.dq + c.dq) * 2.0 + d.dq,
            dp: a.dp + (b.dp + c.dp) * 2.0 + d.dp,
            dl: a.dl + (b.dl + c.dl) * 2.0 + d.dl,
        }
    }
}

/// Evaluates `f(y, t)`; omega is recomputed from the stage's `(q, L)`.
#[inline(always)]
pub(crate) fn rates<F: ForceField + ?Sized>(p: &Params, y: &BodyState, t: f64, field: &F) -> Rates {
    let (f_ext, tau_ext) = field.wrench(p.index, y, t);
    let omega = angular_velocity_of(y.orientation, p.inv_inertia, y.angular_momentum);
    Rates {
        dx: y.linear_momentum * p.inv_mass,
        dq: quat_derivative(omega, y.orientation),
        dp: p.force + f_ext,
        dl: p.torque + tau_ext,
    }
}

/// `y + h r` (the quaternion is not renormalised here).
#[inline(always)]
pub(crate) fn advance(y: &BodyState, r: &Rates, h: f64) -> BodyState {
    BodyState {
        position: y.position + r.dx * h,
        orientation: y.orientation + r.dq * h,
        linear_momentum: y.linear_momentum + r.dp * h,
        angular_momentum: y.angular_momentum + r.dl * h,
    }
}
