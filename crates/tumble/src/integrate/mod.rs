//! Time integration of rigid body states (thesis 3.4; Baraff & Witkin, "Differential
//! Equation Basics" and "Rigid Body Dynamics", SIGGRAPH 97; Hairer, Lubich & Wanner,
//! "Geometric Numerical Integration", ch. I.1 for the symplectic Euler method).
//!
//! Each dynamic body is the ODE `y = (x, q, P, L)` with
//! `dx/dt = P / M`, `dq/dt = 1/2 [0, omega] q`, `dP/dt = F + M g`, `dL/dt = tau`,
//! where `omega = R I_body^-1 R^T L` is recomputed from `(q, L)` at every stage.
//! `F` and `tau` are the body's accumulators (constant over the step) plus an optional
//! [`ForceField`] evaluated at every stage, so that state-dependent forces get the full
//! order of the method.
//!
//! Every method is a free function of one signature `(params, state, t, h,
//! field)`, so that [`Integrator`] can select any of them; their first lines
//! read alike by design (a `duplicates` listing of them is that signature).
//!
//! - [`Integrator`]: which method.
//! - [`integrate`] / [`integrate_with_field`]: advance a slice of bodies by one step.
//!
//! After every step the quaternion is renormalised, damping is applied to the momenta,
//! and a body whose new state is not finite is rolled back and counted in the
//! [`IntegrateReport`]. Static bodies never move; kinematic bodies advance exactly along
//! their prescribed screw motion. Accumulators are not cleared.

mod explicit;
mod kinematic;
mod ode;
mod splitting;
pub use splitting::{free_rotation, turn_by};
pub(crate) use splitting::{sin_cos_series, symmetry_axis, SERIES_LIMIT};
mod symplectic;

use crate::body::{BodyKind, BodyState, RigidBody};
use ode::Params;
use serde::{Deserialize, Serialize};
use tumble_collide::math::DVec3;

/// Which integration method advances dynamic bodies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Integrator {
    /// Explicit (forward) Euler, thesis 3.4.2: one derivative evaluation, global order 1.
    /// Gains energy on oscillations; kept as a reference.
    Euler,
    /// Explicit midpoint (RK2): two evaluations, global order 2.
    Midpoint,
    /// Classical fourth-order Runge-Kutta, thesis 3.4.3: four evaluations, global order 4.
    Rk4,
    /// Semi-implicit (symplectic) Euler: momenta first, then positions and orientation
    /// with the new velocities. One evaluation, global order 1, but no secular energy
    /// drift on oscillations; the default, and the one that suits velocity-level contact
    /// solvers.
    #[default]
    SemiImplicitEuler,
    /// Semi-implicit Euler for the momenta and translation, with the rotation under the
    /// new `L` advanced by a symmetric, symplectic splitting about the principal axes
    /// (McLachlan 1993). Order 1 overall, order 2 for torque-free rotation, and no energy
    /// drift for tumbling asymmetric bodies, at the price of five sine/cosine pairs per
    /// body and step.
    SemiImplicitSplitting,
}

impl Integrator {
    /// All methods, for tests and benchmarks that loop over them.
    pub const ALL: [Integrator; 5] = [
        Integrator::Euler,
        Integrator::Midpoint,
        Integrator::Rk4,
        Integrator::SemiImplicitEuler,
        Integrator::SemiImplicitSplitting,
    ];

    /// Global order of accuracy on smooth problems.
    pub fn order(self) -> u32 {
        match self {
            Integrator::Euler | Integrator::SemiImplicitEuler | Integrator::SemiImplicitSplitting => 1,
            Integrator::Midpoint => 2,
            Integrator::Rk4 => 4,
        }
    }

    /// Global order of accuracy for the orientation of a torque-free body.
    pub fn rotation_order(self) -> u32 {
        match self {
            Integrator::SemiImplicitSplitting => 2,
            other => other.order(),
        }
    }
}

/// A state-dependent force and torque, evaluated at every integrator stage.
///
/// `wrench(index, state, t)` returns `(force (N), torque (N m))` on body `bodies[index]`,
/// both world frame, the force acting through the centre of mass, given the (stage)
/// state and time `t` (s). Any `Fn(usize, &BodyState, f64) -> (DVec3, DVec3)` is one.
/// It is called only for dynamic bodies. Stage quaternions are not exactly unit.
pub trait ForceField {
    /// Force and torque on body `index` in state `state` at time `t`.
    fn wrench(&self, index: usize, state: &BodyState, t: f64) -> (DVec3, DVec3);
}

impl<F> ForceField for F
where
    F: Fn(usize, &BodyState, f64) -> (DVec3, DVec3) + ?Sized,
{
    #[inline]
    fn wrench(&self, index: usize, state: &BodyState, t: f64) -> (DVec3, DVec3) {
        self(index, state, t)
    }
}

/// The empty force field (used by [`integrate`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct NoField;

impl ForceField for NoField {
    #[inline(always)]
    fn wrench(&self, _index: usize, _state: &BodyState, _t: f64) -> (DVec3, DVec3) {
        (DVec3::ZERO, DVec3::ZERO)
    }
}

/// Why a step was refused (no body was touched).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IntegrateError {
    /// The time step is NaN, infinite or negative.
    #[error("time step must be finite and >= 0 s, got {0}")]
    BadTimeStep(f64),
    /// The start time is NaN or infinite.
    #[error("start time must be finite, got {0}")]
    BadTime(f64),
    /// A gravity component is NaN or infinite.
    #[error("gravity must be finite, got {0:?}")]
    NonFiniteGravity(DVec3),
}

/// What happened during a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct IntegrateReport {
    /// Number of bodies whose new state was not finite (e.g. a force field returned
    /// NaN); they were left in their state from before the step.
    pub rolled_back: usize,
    /// Index of the first such body.
    pub first_rolled_back: Option<usize>,
}

/// Advances every body by `dt` (s) under uniform gravity `gravity` (m/s^2, applied as
/// `M g`) and the bodies' accumulated forces and torques.
///
/// ```
/// use tumble::collide::{math::DVec3, Pose};
/// use tumble::{integrate, Integrator, RigidBody};
///
/// let mut bodies = vec![RigidBody::new_dynamic(1.0, DVec3::splat(0.1), Pose::IDENTITY)?];
/// bodies[0].set_linear_velocity(DVec3::new(0.0, 0.0, 5.0))?;
/// let gravity = DVec3::new(0.0, 0.0, -9.81);
/// for _ in 0..100 {
///     integrate(&mut bodies, gravity, 0.01, Integrator::Rk4)?;
/// }
/// // RK4 is exact on constant forces: z(1 s) = 5 - 9.81 / 2.
/// assert!((bodies[0].position().z - (5.0 - 4.905)).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn integrate(
    bodies: &mut [RigidBody],
    gravity: DVec3,
    dt: f64,
    integrator: Integrator,
) -> Result<IntegrateReport, IntegrateError> {
    integrate_with_field(bodies, gravity, 0.0, dt, integrator, &NoField)
}

/// Like [`integrate`], plus the force field `field` evaluated at every stage; `time` (s)
/// is the time at the start of the step, passed on to the field.
///
/// ```
/// use tumble::collide::{math::DVec3, Pose};
/// use tumble::{integrate_with_field, BodyState, Integrator, RigidBody};
///
/// // A unit mass on a spring of stiffness 4 N/m: x(t) = cos(2 t).
/// let start = Pose::from_translation(DVec3::X);
/// let mut bodies = vec![RigidBody::new_dynamic(1.0, DVec3::splat(0.1), start)?];
/// let spring = |_: usize, s: &BodyState, _t: f64| (-4.0 * s.position, DVec3::ZERO);
/// let dt = 0.001;
/// for n in 0..1000 {
///     let t = n as f64 * dt;
///     integrate_with_field(&mut bodies, DVec3::ZERO, t, dt, Integrator::Rk4, &spring)?;
/// }
/// assert!((bodies[0].position().x - 2.0f64.cos()).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn integrate_with_field<F: ForceField + ?Sized>(
    bodies: &mut [RigidBody],
    gravity: DVec3,
    time: f64,
    dt: f64,
    integrator: Integrator,
    field: &F,
) -> Result<IntegrateReport, IntegrateError> {
    if !dt.is_finite() || dt < 0.0 {
        return Err(IntegrateError::BadTimeStep(dt));
    }
    if !time.is_finite() {
        return Err(IntegrateError::BadTime(time));
    }
    if !gravity.is_finite() {
        return Err(IntegrateError::NonFiniteGravity(gravity));
    }
    let mut report = IntegrateReport::default();
    // One loop per method so that the match is outside the hot loop; `run`'s
    // arguments are the same for every method but the step function.
    macro_rules! run_with {
        ($step:path) => {
            run(bodies, gravity, time, dt, field, &mut report, $step)
        };
    }
    match integrator {
        Integrator::Euler => run_with!(explicit::euler),
        Integrator::Midpoint => run_with!(explicit::midpoint),
        Integrator::Rk4 => run_with!(explicit::rk4),
        Integrator::SemiImplicitEuler => run_with!(symplectic::semi_implicit_euler),
        Integrator::SemiImplicitSplitting => run_with!(splitting::semi_implicit_splitting),
    }
    Ok(report)
}

/// The per-body loop shared by all methods; `step` maps the state at `time` to the
/// unnormalised state at `time + dt`.
#[inline(always)]
fn run<F: ForceField + ?Sized>(
    bodies: &mut [RigidBody],
    gravity: DVec3,
    time: f64,
    dt: f64,
    field: &F,
    report: &mut IntegrateReport,
    step: impl Fn(&Params, &BodyState, f64, f64, &F) -> BodyState,
) {
    for (index, body) in bodies.iter_mut().enumerate() {
        let next = match body.kind {
            BodyKind::Static => continue,
            BodyKind::Kinematic => kinematic::advance(body, dt),
            BodyKind::Dynamic => {
                let params = Params {
                    index,
                    inv_mass: body.inv_mass,
                    inv_inertia: body.inv_inertia,
                    force: body.force + gravity / body.inv_mass,
                    torque: body.torque,
                };
                let mut next = step(&params, &body.state, time, dt, field);
                next.orientation = next.orientation.normalize();
                // Implicit-Euler damping, see RigidBody::set_damping.
                next.linear_momentum *= 1.0 / (1.0 + body.linear_damping * dt);
                next.angular_momentum *= 1.0 / (1.0 + body.angular_damping * dt);
                next
            }
        };
        if next.is_finite() {
            body.state = next;
        } else {
            report.rolled_back += 1;
            report.first_rolled_back.get_or_insert(index);
        }
    }
}
