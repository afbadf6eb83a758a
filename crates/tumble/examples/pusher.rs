//! A robotics-flavoured demo: a kinematic paddle (an end effector) driven by
//! a prescribed trapezoidal velocity profile pushes a box across a table.
//! The paddle is a kinematic body: it follows its velocity exactly, pushes
//! the box, and is never pushed back. Run it with
//! `cargo run --release -p tumble --example pusher` (writes out/pusher.glb);
//! `crates/tumble/tests/pusher_demo.rs` runs the same code and checks it.
//!
//! The velocity is set once per step to the profile's value at the middle of
//! the step. The profile is piecewise linear with its corners on step
//! boundaries, so the midpoint rule integrates it exactly: the paddle's
//! position must equal the analytic integral of the profile at every step.

use tumble::collide::{Cuboid, DQuat, DVec3};
use tumble::world::{BodyDesc, BodyId, World, WorldSettings};

/// Time step (s): the profile's corners fall on step boundaries.
pub const DT: f64 = 1.0 / 120.0;
/// Cruise speed (m/s), acceleration time (s), cruise time (s).
pub const SPEED: f64 = 0.2;
/// Time to reach the cruise speed and to stop from it (s).
pub const RAMP: f64 = 0.5;
/// Time at cruise speed (s).
pub const CRUISE: f64 = 1.5;
/// Height of the table top (m).
pub const TABLE_TOP: f64 = 0.8;
/// Half extents of the paddle (m): thin in x, the pushing direction.
pub const PADDLE_HALF: DVec3 = DVec3::new(0.02, 0.15, 0.05);
/// Half extent of the pushed cube (m).
pub const BOX_HALF: f64 = 0.05;
/// Where the paddle starts (its centre's x, m).
pub const PADDLE_X0: f64 = -0.3;
/// Friction coefficient of every surface.
pub const FRICTION: f64 = 0.5;

/// The prescribed speed along x at time t (m/s): ramp up, cruise, ramp down, stop.
pub fn profile_speed(t: f64) -> f64 {
    let (t1, t2, t3) = (RAMP, RAMP + CRUISE, 2.0 * RAMP + CRUISE);
    if t <= 0.0 || t >= t3 {
        0.0
    } else if t < t1 {
        SPEED * t / RAMP
    } else if t < t2 {
        SPEED
    } else {
        SPEED * (t3 - t) / RAMP
    }
}

/// The analytic integral of the profile: the paddle's prescribed x at time t (m).
pub fn profile_position(t: f64) -> f64 {
    let (t1, t2, t3) = (RAMP, RAMP + CRUISE, 2.0 * RAMP + CRUISE);
    let ramp_distance = 0.5 * SPEED * RAMP;
    let travelled = if t <= 0.0 {
        0.0
    } else if t < t1 {
        0.5 * SPEED * t * t / RAMP
    } else if t < t2 {
        ramp_distance + SPEED * (t - t1)
    } else if t < t3 {
        let left = t3 - t;
        2.0 * ramp_distance + SPEED * CRUISE - 0.5 * SPEED * left * left / RAMP
    } else {
        2.0 * ramp_distance + SPEED * CRUISE
    };
    PADDLE_X0 + travelled
}

/// What the demo measured, one sample per step.
pub struct PushRun {
    /// The world after the run.
    pub world: World,
    /// The paddle and the box.
    pub paddle: BodyId,
    /// The pushed cube.
    pub cube: BodyId,
    /// Time (s), paddle x (m), cube centre x (m) after each step.
    pub samples: Vec<(f64, f64, f64)>,
}

/// Builds the table, the cube and the paddle, and drives the paddle for
/// `seconds` of simulated time; `on_step` sees the world after each step.
pub fn run(seconds: f64, mut on_step: impl FnMut(&World)) -> Result<PushRun, Box<dyn std::error::Error>> {
    let settings = WorldSettings {
        dt: DT,
        sleeping: false,
        ..WorldSettings::default()
    };
    let mut world = World::new(settings)?;
    let table_half = DVec3::new(1.0, 0.5, TABLE_TOP / 2.0);
    world.add_body(
        &BodyDesc::fixed(Cuboid::new(table_half)?)
            .at(DVec3::new(0.0, 0.0, TABLE_TOP / 2.0))
            .with_material(FRICTION, 0.0)
            .named("table"),
    )?;
    let cube = world.add_body(
        &BodyDesc::dynamic(Cuboid::new(DVec3::splat(BOX_HALF))?)
            .at(DVec3::new(0.0, 0.0, TABLE_TOP + BOX_HALF))
            .with_mass(0.5)
            .with_material(FRICTION, 0.0)
            .named("cube"),
    )?;
    // The paddle hovers 2 mm above the table: it touches only the cube.
    let paddle = world.add_body(
        &BodyDesc::kinematic(Cuboid::new(PADDLE_HALF)?)
            .at(DVec3::new(PADDLE_X0, 0.0, TABLE_TOP + PADDLE_HALF.z + 0.002))
            .with_material(FRICTION, 0.0)
            .named("paddle"),
    )?;
    let steps = (seconds / DT).round() as usize;
    let mut samples = Vec::with_capacity(steps);
    for k in 0..steps {
        let mid = (k as f64 + 0.5) * DT;
        world.set_velocity(paddle, DVec3::new(profile_speed(mid), 0.0, 0.0), DVec3::ZERO)?;
        world.step();
        on_step(&world);
        samples.push((
            world.time(),
            world.pose(paddle)?.position.x,
            world.center_of_mass(cube)?.x,
        ));
    }
    Ok(PushRun {
        world,
        paddle,
        cube,
        samples,
    })
}

/// Yaw of an orientation about z (rad).
pub fn yaw(q: DQuat) -> f64 {
    let x = q * DVec3::X;
    x.y.atan2(x.x)
}

#[allow(dead_code)] // the test includes this file without calling main
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut recorder = None;
    let result = run(4.0, |world| match &mut recorder {
        // The recorder's first frame is the world when it is made.
        None => recorder = Some(tumble::export::WorldRecorder::new(world)),
        Some(Ok(r)) => r.record(world),
        Some(Err(_)) => {}
    })?;
    let (t, paddle_x, cube_x) = *result.samples.last().ok_or("no steps")?;
    println!(
        "after {t:.2} s: paddle at x = {paddle_x:.4} m (prescribed {:.4}), cube at x = {cube_x:.4} m",
        profile_position(t)
    );
    if let Some(recorder) = recorder {
        std::fs::create_dir_all("out")?;
        tumble::export::write_glb(&recorder?.finish(), "out/pusher.glb")?;
        println!("wrote out/pusher.glb (tumble view out/pusher.glb, or import it in Blender)");
    }
    Ok(())
}
