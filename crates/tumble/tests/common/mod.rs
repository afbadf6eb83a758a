//! Analytic oracles and small helpers shared by the integration tests.
#![allow(dead_code)] // each test binary uses a different subset

pub mod falling_pile;
pub mod leaning_bar;

use tumble::collide::math::{DQuat, DVec3};
use tumble::collide::Pose;
use tumble::integrate::{integrate_with_field, ForceField, Integrator, NoField};
use tumble::{BodyState, RigidBody};

/// The deterministic random source of the randomised tests (xorshift64*,
/// from `tumble-testkit`: the same numbers on every machine).
#[allow(unused_imports)] // each test binary uses a different subset
pub use tumble_testkit::{RandomSource, XorShift64Star as Rng};

/// The complete elliptic integral of the first kind (one home: `tumble::analytic`).
#[allow(unused_imports)] // each test binary uses a different subset
pub use tumble::analytic::elliptic_k;

/// A world without gravity or sleeping, with the continuous stage (and the
/// end-overlap stage in it) on or off: bodies move only as a test sets them.
pub fn weightless_world(continuous: bool) -> tumble::world::World {
    tumble::world::World::new(tumble::world::WorldSettings {
        gravity: DVec3::ZERO,
        sleeping: false,
        continuous,
        ..tumble::world::WorldSettings::default()
    })
    .unwrap()
}

/// Standard gravity (m/s^2), as the joint tests' worlds have it.
pub const G: f64 = 9.81;

/// A world for joint and gear tests: gravity `G` along -z or none,
/// sleeping off (a test's pendulum must not fall asleep at a turning
/// point), stepped on `threads` threads.
pub fn joint_world(gravity: bool, threads: u32) -> tumble::world::World {
    tumble::world::World::new(tumble::world::WorldSettings {
        gravity: if gravity {
            DVec3::new(0.0, 0.0, -G)
        } else {
            DVec3::ZERO
        },
        sleeping: false,
        threads,
        ..tumble::world::WorldSettings::default()
    })
    .unwrap()
}

/// A test pose with a generic orientation.
pub fn tilted_pose() -> Pose {
    Pose::new(
        DVec3::new(0.5, -1.0, 2.0),
        DQuat::from_euler(glam::EulerRot::ZYX, 0.7, -0.4, 1.3),
    )
    .unwrap()
}

/// A dynamic body with principal moments `inertia` at `pose`, spinning with body-frame
/// angular velocity `omega_body`.
pub fn spinning_body(inertia: DVec3, omega_body: DVec3, pose: Pose) -> RigidBody {
    let mut b = RigidBody::new_dynamic(1.0, inertia, pose).unwrap();
    b.set_angular_velocity(pose.rotation * omega_body).unwrap();
    b
}

/// Body-frame angular velocity `R^T omega`.
pub fn omega_body(b: &RigidBody) -> DVec3 {
    b.orientation().conjugate() * b.angular_velocity()
}

/// Rotation angle (rad) between two orientations, insensitive to the quaternion sign and
/// accurate for small angles.
pub fn rotation_error(q: DQuat, exact: DQuat) -> f64 {
    let d = exact.conjugate() * q;
    let s = DVec3::new(d.x, d.y, d.z).length();
    2.0 * s.atan2(d.w.abs())
}

/// Analytic orientation of a torque-free axisymmetric body (`I1 = I2`, symmetry axis
/// body z) with world angular momentum `l` and initial orientation `q0`.
///
/// omega = L / I1 + (1/I3 - 1/I1) L3 e3 with e3 the world symmetry axis and L3 = L . e3
/// constant. Both terms are uniform rotations that commute with the motion they generate,
/// so R(t) = Rot(L t / I1) R0 Rot_body(z, (1/I3 - 1/I1) L3 t): differentiating,
/// dR/dt = [L/I1]x R + R [c L3 z]x = [L/I1 + c L3 R z]x R = [omega]x R.
pub fn axisymmetric_top_orientation(i1: f64, i3: f64, l: DVec3, q0: DQuat, t: f64) -> DQuat {
    let l3 = l.dot(q0 * DVec3::Z);
    let spin = (1.0 / i3 - 1.0 / i1) * l3 * t;
    DQuat::from_scaled_axis(l * (t / i1)) * q0 * DQuat::from_scaled_axis(DVec3::Z * spin)
}

/// Steps `bodies` `steps` times by `dt` with `field`, no gravity; panics on a refused
/// step or a roll-back.
pub fn run_with<F: ForceField + ?Sized>(
    bodies: &mut [RigidBody],
    integrator: Integrator,
    dt: f64,
    steps: usize,
    field: &F,
) {
    for n in 0..steps {
        let r = integrate_with_field(bodies, DVec3::ZERO, n as f64 * dt, dt, integrator, field).unwrap();
        assert_eq!(r.rolled_back, 0);
    }
}

/// Torque-free, force-free steps.
pub fn run_free(body: &mut RigidBody, integrator: Integrator, dt: f64, steps: usize) {
    run_with(std::slice::from_mut(body), integrator, dt, steps, &NoField);
}

/// Observed order `log2(e(h) / e(h/2))`.
pub fn observed_order(coarse: f64, fine: f64) -> f64 {
    (coarse / fine).log2()
}

/// Unused-state helper so the type is named in every binary.
pub fn state_of(b: &RigidBody) -> BodyState {
    *b.state()
}

/// A world without sleeping holding only the ground plane z = 0 (body 0).
pub fn ground_world() -> tumble::world::World {
    use tumble::world::{BodyDesc, World, WorldSettings};
    use tumble_collide::shape::{HalfSpace, Shape};
    let mut world = World::new(WorldSettings {
        sleeping: false,
        ..WorldSettings::default()
    })
    .unwrap();
    world
        .add_body(&BodyDesc::fixed(Shape::HalfSpace(HalfSpace::ground())))
        .unwrap();
    world
}
