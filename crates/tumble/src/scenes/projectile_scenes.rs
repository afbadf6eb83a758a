//! The projectile matrix of issue 16 ("nothing passes through a wall"),
//! defined once for the tests and for the benchmark that runs the same
//! cases in Rapier: a projectile about 10 cm across (box, sphere, capsule,
//! convex hull, triangle-mesh ball) fired without gravity at a static 2 m x
//! 2 m slab (box primitive or closed mesh, 1 mm to 10 cm thick, turned 0 to
//! 60 degrees about y) at 10 to 1,000 m/s, dt 1/60 s, watched for
//! [`PROJECTILE_STEPS`] steps and judged by [`Flight`]: no crossing of the
//! slab's plane inside its square, no kinetic energy gained, never held in
//! place while moving.

use super::Scene;
use crate::world::{BodyDesc, WorldSettings};
use tumble_collide::mesh::{box_mesh, icosphere_mesh};
use tumble_collide::shape::{Capsule, ConvexHull, Cuboid, MeshShape, Shape, Sphere};
use tumble_collide::{DQuat, DVec3, Pose};

/// Steps each case is watched for.
pub const PROJECTILE_STEPS: usize = 40;

/// What is fired.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Projectile {
    /// A 10 cm cube.
    Box,
    /// A ball of radius 5 cm.
    Sphere,
    /// A capsule of radius 3 cm and half height 2 cm.
    Capsule,
    /// The convex hull of an icosphere (80 faces) of radius 5 cm.
    Hull,
    /// An icosphere mesh (320 triangles) of radius 5 cm.
    Mesh,
}

impl Projectile {
    /// Every projectile, in the order of the matrix.
    pub const ALL: [Projectile; 5] = [
        Projectile::Box,
        Projectile::Sphere,
        Projectile::Capsule,
        Projectile::Hull,
        Projectile::Mesh,
    ];

    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Projectile::Box => "box",
            Projectile::Sphere => "sphere",
            Projectile::Capsule => "capsule",
            Projectile::Hull => "hull",
            Projectile::Mesh => "mesh",
        }
    }

    /// Its shape, centred on its centre of mass.
    pub fn shape(self) -> Shape {
        let ball = || icosphere_mesh(0.05, 1).expect("valid icosphere");
        match self {
            Projectile::Box => Shape::Cuboid(Cuboid::new(DVec3::splat(0.05)).expect("valid")),
            Projectile::Sphere => Shape::Sphere(Sphere::new(0.05).expect("valid")),
            Projectile::Capsule => Shape::Capsule(Capsule::new(0.03, 0.02).expect("valid")),
            Projectile::Hull => Shape::ConvexHull(ConvexHull::from_mesh(&ball()).expect("convex")),
            Projectile::Mesh => Shape::Mesh(
                MeshShape::new(icosphere_mesh(0.05, 2).expect("valid icosphere")).expect("valid mesh"),
            ),
        }
    }
}

/// One case of the matrix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProjectileCase {
    /// What is fired.
    pub projectile: Projectile,
    /// The slab is a closed triangle mesh (else a box primitive).
    pub mesh_slab: bool,
    /// Slab thickness (m).
    pub thickness: f64,
    /// Slab turn about y (degrees): its normal leans from z towards x.
    pub degrees: f64,
    /// Speed along -z (m/s).
    pub speed: f64,
}

/// The 720 cases: 5 projectiles x 2 slab kinds x 4 thicknesses (1 mm, 1, 2,
/// 10 cm) x 3 turns (0, 30, 60 degrees) x 6 speeds (10 to 1,000 m/s).
pub fn projectile_cases() -> Vec<ProjectileCase> {
    let mut cases = Vec::new();
    for projectile in Projectile::ALL {
        for mesh_slab in [false, true] {
            for thickness in [0.001, 0.01, 0.02, 0.1] {
                for degrees in [0.0, 30.0, 60.0] {
                    for speed in [10.0, 30.0, 120.0, 250.0, 600.0, 1000.0] {
                        cases.push(ProjectileCase {
                            projectile,
                            mesh_slab,
                            thickness,
                            degrees,
                            speed,
                        });
                    }
                }
            }
        }
    }
    cases
}

impl ProjectileCase {
    /// The slab's rotation.
    pub fn turn(&self) -> DQuat {
        DQuat::from_rotation_y(self.degrees.to_radians())
    }

    /// The slab's half extents (m).
    pub fn slab_half_extents(&self) -> DVec3 {
        DVec3::new(1.0, 1.0, self.thickness / 2.0)
    }

    /// The slab's shape (centred on the origin before its turn).
    pub fn slab_shape(&self) -> Shape {
        let half = self.slab_half_extents();
        if self.mesh_slab {
            Shape::Mesh(MeshShape::new(box_mesh(half).expect("valid box")).expect("valid mesh"))
        } else {
            Shape::Cuboid(Cuboid::new(half).expect("valid"))
        }
    }

    /// Where the projectile starts: far enough that the first step never
    /// begins at the slab, at a speed-dependent fraction of a step's travel.
    pub fn start(&self) -> DVec3 {
        DVec3::new(0.0, 0.0, 0.5 + self.speed / 60.0 * 0.37)
    }

    /// The projectile's velocity (m/s).
    pub fn velocity(&self) -> DVec3 {
        DVec3::new(0.0, 0.0, -self.speed)
    }

    /// A readable name of the case.
    pub fn label(&self) -> String {
        format!(
            "{} at {} m/s, {} m {} slab at {} deg",
            self.projectile.name(),
            self.speed,
            self.thickness,
            if self.mesh_slab { "mesh" } else { "box" },
            self.degrees
        )
    }

    /// The case as a scene: the slab, then the projectile; no gravity, no
    /// sleeping, `continuous` as given.
    pub fn scene(&self, continuous: bool) -> Scene {
        Scene {
            name: format!("projectile: {}", self.label()),
            settings: WorldSettings {
                gravity: DVec3::ZERO,
                sleeping: false,
                continuous,
                ..WorldSettings::default()
            },
            bodies: vec![
                BodyDesc::fixed(self.slab_shape())
                    .with_pose(Pose::new(DVec3::ZERO, self.turn()).expect("unit rotation")),
                BodyDesc::dynamic(self.projectile.shape())
                    .at(self.start())
                    .with_velocity(self.velocity(), DVec3::ZERO),
            ],
            steps: PROJECTILE_STEPS,
            joints: Vec::new(),
            no_contact: Vec::new(),
            gears: Vec::new(),
        }
    }

    /// Watches the flight of this case (see [`Flight`]), `energy` the
    /// projectile's kinetic energy at the start.
    pub fn flight(&self, energy: f64) -> Flight {
        let turn = self.turn();
        Flight {
            normal: turn * DVec3::Z,
            along: turn * DVec3::X,
            spinning_integrator: self.projectile == Projectile::Capsule,
            start_energy: energy,
            last_energy: energy,
            last: self.start(),
            held: 0,
            step: 0,
        }
    }
}

/// The judge of one flight, fed the projectile's centre, kinetic energy
/// and speed after every step (by any engine).
#[derive(Debug, Clone)]
pub struct Flight {
    normal: DVec3,
    along: DVec3,
    spinning_integrator: bool,
    start_energy: f64,
    last_energy: f64,
    last: DVec3,
    held: usize,
    step: usize,
}

/// How a flight went wrong.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    /// The centre crossed the slab's plane inside the slab's square.
    PassedThrough,
    /// The kinetic energy rose.
    GainedEnergy,
    /// Held in place for 3 steps while still moving.
    Held,
    /// A position or energy that is not finite.
    NotFinite,
}

impl Flight {
    /// The next step's state; `Err` names the fault and the step.
    ///
    /// Energy may only fall. A capsule's own free rotation changes its
    /// energy by a few percent at the spins these impacts give it (the
    /// integrator's error for a body with unequal moments, not the
    /// contacts'): for it, the energy may not rise above the start by more
    /// than 5 %.
    pub fn observe(&mut self, position: DVec3, energy: f64, speed: f64) -> Result<(), (Fault, String)> {
        let step = self.step;
        self.step += 1;
        if !(position.is_finite() && energy.is_finite()) {
            return Err((Fault::NotFinite, format!("step {step}: not finite")));
        }
        let (h0, h1) = (self.last.dot(self.normal), position.dot(self.normal));
        if h0 >= 0.0 && h1 < 0.0 {
            let x = self.last + (position - self.last) * (h0 / (h0 - h1));
            if x.dot(self.along).abs() < 1.0 && x.y.abs() < 1.0 {
                return Err((
                    Fault::PassedThrough,
                    format!("step {step}: passed through to {position:.3}"),
                ));
            }
        }
        let gained = if self.spinning_integrator {
            energy > self.start_energy * 1.05
        } else {
            energy > self.last_energy * (1.0 + 1e-4) + 1e-9
        };
        if gained {
            return Err((
                Fault::GainedEnergy,
                format!(
                    "step {step}: energy x{:.4} (x{:.4} of the start)",
                    energy / self.last_energy,
                    energy / self.start_energy
                ),
            ));
        }
        self.held = if position == self.last && speed > 0.1 {
            self.held + 1
        } else {
            0
        };
        if self.held >= 3 {
            return Err((
                Fault::Held,
                format!("step {step}: held at {position:.3} while moving"),
            ));
        }
        self.last = position;
        self.last_energy = energy;
        Ok(())
    }
}

/// Runs one case in tumble and judges it.
pub fn fire_projectile(case: &ProjectileCase, continuous: bool) -> Result<(), (Fault, String)> {
    let (mut world, ids) = case.scene(continuous).build().expect("a valid scene");
    let body = ids[1];
    let mut flight = case.flight(world.kinetic_energy());
    for _ in 0..PROJECTILE_STEPS {
        world.step();
        let speed = world.linear_velocity(body).expect("live").length();
        flight.observe(
            world.center_of_mass(body).expect("live"),
            world.kinetic_energy(),
            speed,
        )?;
    }
    Ok(())
}
