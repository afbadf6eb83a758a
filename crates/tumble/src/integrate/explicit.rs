//! Explicit Runge-Kutta methods on the full state (thesis 3.4.2-3.4.3): forward Euler,
//! explicit midpoint and classical RK4. Each returns the unnormalised state at `t + h`.
//!
//! `euler`, `midpoint` and `rk4` share their `(p, y, t, h, field)` head with
//! `semi_implicit_euler` (symplectic.rs) and `semi_implicit_splitting`
//! (splitting.rs): the one signature `Integrator` dispatches on (mod.rs).

use super::ode::{advance, rates, Params, Rates};
use super::ForceField;
use crate::body::BodyState;

/// `y1 = y + h f(y, t)`.
#[inline(always)]
pub(crate) fn euler<F: ForceField + ?Sized>(
    p: &Params,
    y: &BodyState,
    t: f64,
    h: f64,
    field: &F,
) -> BodyState {
    advance(y, &rates(p, y, t, field), h)
}

/// `y1 = y + h f(y + h/2 f(y, t), t + h/2)`.
#[inline(always)]
pub(crate) fn midpoint<F: ForceField + ?Sized>(
    p: &Params,
    y: &BodyState,
    t: f64,
    h: f64,
    field: &F,
) -> BodyState {
    let k1 = rates(p, y, t, field);
    let mid = advance(y, &k1, 0.5 * h);
    advance(y, &rates(p, &mid, t + 0.5 * h, field), h)
}

/// Classical RK4: `y1 = y + h/6 (k1 + 2 k2 + 2 k3 + k4)`.
#[inline(always)]
pub(crate) fn rk4<F: ForceField + ?Sized>(p: &Params, y: &BodyState, t: f64, h: f64, field: &F) -> BodyState {
    let half = 0.5 * h;
    let k1 = rates(p, y, t, field);
    let k2 = rates(p, &advance(y, &k1, half), t + half, field);
    let k3 = rates(p, &advance(y, &k2, half), t + half, field);
    let k4 = rates(p, &advance(y, &k3, h), t + h, field);
    advance(y, &Rates::rk4_sum(&k1, &k2, &k3, &k4), h / 6.0)
}
