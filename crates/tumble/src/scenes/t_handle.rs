//! The Dzhanibekov effect: a steel T-handle in zero gravity, spun about its
//! intermediate principal axis with a 1 % perturbation, flips over and back
//! with the period of Euler's equations ([`crate::analytic::torque_free_period`]).
//! A free rigid body without contacts, integrated by RK4: the `tumble demo`
//! showpiece (the scene file `examples/scenes/dzhanibekov.toml` is the same
//! effect through the world).
//!
//! The handle is a composite of two boxes (shaft along z, cross bar along x
//! on top); its mass properties come from the composite rule, its body frame
//! from the principal axes.

use crate::analytic::torque_free_period;
use crate::body::RigidBody;
use crate::integrate::{integrate, IntegrateError, Integrator};
use tumble_collide::mass::{solid_box, MassProperties, MassSpec};
use tumble_collide::{DMat3, DVec3, Pose};

/// The spinning handle and what theory says of it.
#[derive(Debug, Clone)]
pub struct THandle {
    /// The body at t = 0 (body frame: centre of mass, principal axes).
    pub body: RigidBody,
    /// Principal moments, ascending (kg m^2).
    pub moments: DVec3,
    /// The analytic flip period (s).
    pub period: f64,
}

/// The steel T-handle (density 7800 kg/m^3; shaft 2 x 2 x 10 cm, bar
/// 8 x 2 x 2 cm centred 6 cm up), spinning at 3 rad/s about its
/// intermediate axis plus 0.03 rad/s about its major one.
pub fn t_handle() -> THandle {
    let density = MassSpec::Density(7800.0);
    let shaft = solid_box(DVec3::new(0.01, 0.01, 0.05), density).expect("valid box");
    let bar = solid_box(DVec3::new(0.04, 0.01, 0.01), density)
        .expect("valid box")
        .translated(DVec3::new(0.0, 0.0, 0.06));
    let frame = MassProperties::combine(&[shaft, bar])
        .expect("two solids")
        .principal();
    let axes = DMat3::from_quat(frame.rotation);
    // Moments ascending: column 1 is the intermediate axis, column 2 the major.
    let omega = 3.0 * axes.y_axis + 0.03 * axes.z_axis;
    let pose = Pose::new(frame.com, frame.rotation).expect("unit rotation");
    let mut body = RigidBody::new_dynamic(frame.mass, frame.moments, pose).expect("valid mass");
    body.set_angular_velocity(omega).expect("finite");
    THandle {
        body,
        moments: frame.moments,
        period: torque_free_period(frame.moments, axes.transpose() * omega),
    }
}

/// What a flip run measured.
#[derive(Debug, Clone, PartialEq)]
pub struct FlipRun {
    /// Steps integrated.
    pub steps: usize,
    /// Mean time between downward zero crossings of the body-frame
    /// intermediate angular velocity (s), if there were two.
    pub measured_period: Option<f64>,
    /// Half-turns of the handle (two per period).
    pub flips: usize,
    /// |E - E0| / E0 at the end.
    pub energy_drift: f64,
    /// ||L| - |L0|| / |L0| at the end.
    pub momentum_drift: f64,
}

/// Integrates the handle for `duration` s in RK4 steps of `dt`, calling
/// `sample(step, t, body, body_frame_omega)` before each step and after the
/// last.
pub fn run_flips(
    handle: &THandle,
    duration: f64,
    dt: f64,
    mut sample: impl FnMut(usize, f64, &RigidBody, DVec3),
) -> Result<FlipRun, IntegrateError> {
    let steps = (duration / dt).round() as usize;
    let mut bodies = [handle.body.clone()];
    let (e0, l0) = (bodies[0].kinetic_energy(), bodies[0].angular_momentum().length());
    let mut crossings = Vec::new();
    let mut last_w2 = 0.0f64;
    for step in 0..=steps {
        let b = &bodies[0];
        let t = step as f64 * dt;
        let wb = b.orientation().inverse() * b.angular_velocity();
        if step > 0 && last_w2 > 0.0 && wb.y <= 0.0 {
            // The downward zero crossing of the intermediate component,
            // interpolated linearly: one per period.
            crossings.push(t - dt * wb.y / (wb.y - last_w2));
        }
        last_w2 = wb.y;
        sample(step, t, b, wb);
        if step < steps {
            integrate(&mut bodies, DVec3::ZERO, dt, Integrator::Rk4)?;
        }
    }
    let b = &bodies[0];
    Ok(FlipRun {
        steps,
        measured_period: (crossings.len() >= 2)
            .then(|| (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64),
        flips: 2 * crossings.len(),
        energy_drift: (b.kinetic_energy() - e0).abs() / e0,
        momentum_drift: (b.angular_momentum().length() - l0).abs() / l0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_handle_flips_with_the_period_of_eulers_equations() {
        let handle = t_handle();
        assert!(handle.moments.x < handle.moments.y && handle.moments.y < handle.moments.z);
        let run = run_flips(&handle, 6.0 * handle.period, 1e-3, |_, _, _, _| {}).unwrap();
        let measured = run.measured_period.expect("several flips");
        assert!(
            (measured - handle.period).abs() < 2e-3 * handle.period,
            "{measured} vs {}",
            handle.period
        );
        assert!(run.energy_drift < 1e-6 && run.momentum_drift < 1e-6, "{run:?}");
    }
}
