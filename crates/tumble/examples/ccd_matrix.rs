//! Fires projectiles at thin slabs and reports tunnels, energy gains and
//! panics (issue 16's matrix, for exploring; the tests hold the assertions).
//! `cargo run --release -p tumble --example ccd_matrix`

use std::panic::{catch_unwind, AssertUnwindSafe};
use tumble::world::{BodyDesc, World, WorldSettings};
use tumble_collide::mesh::{box_mesh, icosphere_mesh};
use tumble_collide::shape::{Capsule, ConvexHull, Cuboid, MeshShape, Shape, Sphere};
use tumble_collide::{DQuat, DVec3, Pose};

fn projectile(kind: &str) -> Shape {
    match kind {
        "box" => Shape::Cuboid(Cuboid::new(DVec3::splat(0.05)).unwrap()),
        "sphere" => Shape::Sphere(Sphere::new(0.05).unwrap()),
        "capsule" => Shape::Capsule(Capsule::new(0.03, 0.02).unwrap()),
        "hull" => Shape::ConvexHull(ConvexHull::from_mesh(&icosphere_mesh(0.05, 1).unwrap()).unwrap()),
        "mesh" => Shape::Mesh(MeshShape::new(icosphere_mesh(0.05, 2).unwrap()).unwrap()),
        _ => unreachable!(),
    }
}

fn slab(thick: f64, mesh: bool) -> Shape {
    let half = DVec3::new(1.0, 1.0, thick / 2.0);
    if mesh {
        Shape::Mesh(MeshShape::new(box_mesh(half).unwrap()).unwrap())
    } else {
        Shape::Cuboid(Cuboid::new(half).unwrap())
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() == 7 && args[1] == "trace" {
        let f = |i: usize| args[i].parse::<f64>().unwrap();
        return trace(&args[2], args[3] == "mesh", f(4), f(5), f(6));
    }
    let mut fails = 0;
    let mut total = 0;
    for kind in ["box", "sphere", "capsule", "hull", "mesh"] {
        for mesh in [false, true] {
            for thick in [0.001, 0.01, 0.02, 0.1] {
                for deg in [0.0f64, 30.0, 60.0] {
                    for speed in [10.0, 30.0, 120.0, 250.0, 600.0, 1000.0] {
                        total += 1;
                        let r = catch_unwind(AssertUnwindSafe(|| run(kind, mesh, thick, deg, speed)));
                        let msg = match r {
                            Ok(None) => continue,
                            Ok(Some(m)) => m,
                            Err(_) => "PANIC".to_string(),
                        };
                        fails += 1;
                        println!(
                            "{kind:8} {} {thick:6} {deg:3} {speed:6}: {msg}",
                            if mesh { "mesh" } else { "prim" }
                        );
                    }
                }
            }
        }
    }
    println!("{fails} of {total} cases fail");
}

fn run(kind: &str, mesh: bool, thick: f64, deg: f64, speed: f64) -> Option<String> {
    let mut world = World::new(WorldSettings {
        gravity: DVec3::ZERO,
        sleeping: false,
        ..WorldSettings::default()
    })
    .unwrap();
    let turn = DQuat::from_rotation_y(deg.to_radians());
    let normal = turn * DVec3::Z;
    world
        .add_body(&BodyDesc::fixed(slab(thick, mesh)).with_pose(Pose::new(DVec3::ZERO, turn).unwrap()))
        .unwrap();
    let start = DVec3::new(0.0, 0.0, 0.5 + speed / 60.0 * 0.37);
    let ball = world
        .add_body(
            &BodyDesc::dynamic(projectile(kind))
                .at(start)
                .with_velocity(DVec3::new(0.0, 0.0, -speed), DVec3::ZERO),
        )
        .unwrap();
    let e0 = world.kinetic_energy();
    for _ in 0..30 {
        world.step();
        let p = world.center_of_mass(ball).unwrap();
        let e = world.kinetic_energy();
        if !p.is_finite() {
            return Some("non-finite".into());
        }
        if p.dot(normal) < 0.0 {
            return Some(format!("tunnel (at {p:.3})"));
        }
        if e > e0 * 1.0001 {
            return Some(format!("energy x{:.2}", e / e0));
        }
    }
    None
}

/// `ccd_matrix trace KIND mesh|prim THICK DEG SPEED`: the case step by step.
#[allow(dead_code)]
pub fn trace(kind: &str, mesh: bool, thick: f64, deg: f64, speed: f64) {
    let mut world = World::new(WorldSettings {
        gravity: DVec3::ZERO,
        sleeping: false,
        ..WorldSettings::default()
    })
    .unwrap();
    let turn = DQuat::from_rotation_y(deg.to_radians());
    world
        .add_body(&BodyDesc::fixed(slab(thick, mesh)).with_pose(Pose::new(DVec3::ZERO, turn).unwrap()))
        .unwrap();
    let start = DVec3::new(0.0, 0.0, 0.5 + speed / 60.0 * 0.37);
    let ball = world
        .add_body(
            &BodyDesc::dynamic(projectile(kind))
                .at(start)
                .with_velocity(DVec3::new(0.0, 0.0, -speed), DVec3::ZERO),
        )
        .unwrap();
    for i in 0..12 {
        let r = world.step();
        let p = world.center_of_mass(ball).unwrap();
        println!(
            "{i:2} p {p:.4} v {:.3} w {:.2} E {:.3} contacts {} pen {:.4}",
            world.linear_velocity(ball).unwrap(),
            world.angular_velocity(ball).unwrap(),
            world.kinetic_energy(),
            r.contacts,
            r.max_penetration
        );
    }
}
