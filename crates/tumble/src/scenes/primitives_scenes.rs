//! Scenes made of primitive shapes: pyramid, pile, cradle, incline, domino,
//! plus the small test scenes (tower, ball drop). Dimensions, materials and
//! ordering exactly as shared/scenes.md specifies.

use super::{ten_seconds_without_sleep, Scene};
use crate::world::{BodyDesc, WorldSettings};
use tumble_collide::shape::{Cuboid, HalfSpace, Shape, Sphere};
use tumble_collide::{DQuat, DVec3, Pose};

fn cuboid(hx: f64, hy: f64, hz: f64) -> Shape {
    Shape::Cuboid(Cuboid::new(DVec3::new(hx, hy, hz)).expect("positive half extents"))
}

fn sphere(r: f64) -> Shape {
    Shape::Sphere(Sphere::new(r).expect("positive radius"))
}

fn ground_box(hx: f64, hy: f64) -> BodyDesc {
    BodyDesc::fixed(cuboid(hx, hy, 0.5))
        .at(DVec3::new(0.0, 0.0, -0.5))
        .named("ground")
}

/// pyramid: 20 layers of unit cubes (210 boxes, mass 1) on a static ground box;
/// dt 1/60, 600 steps. The top box is the last body.
pub fn pyramid() -> Scene {
    pyramid_with_base("pyramid", 20, 50.0)
}

/// A pyramid with a base of `base` unit cubes (`base` layers), laid out
/// as [`pyramid`] on a ground of half extents (max(50, base), ...).
pub fn pyramid_of_base(base: usize) -> Scene {
    pyramid_with_base(&format!("pyramid{base}"), base, (base as f64).max(50.0))
}

/// large_pyramid: the pyramid with a base of 100 boxes (100 layers, 5,050
/// boxes) on a ground of half extents (100, 100, 0.5); dt 1/60, 600 steps,
/// sleeping off (Box2D v3's and Box3D's benchmark pyramid).
pub fn large_pyramid() -> Scene {
    pyramid_with_base("large_pyramid", 100, 100.0)
}

/// Layers `i = 0..base`, layer `i` holding `base - i` unit cubes 0.05 m
/// apart, each layer resting on the one below, added layer by layer.
fn pyramid_with_base(name: &str, base: usize, ground: f64) -> Scene {
    let mut bodies = vec![ground_box(ground, ground)];
    for i in 0..base {
        let n = base - i;
        for k in 0..n {
            let x = (k as f64 - (n as f64 - 1.0) / 2.0) * 1.05;
            bodies.push(
                BodyDesc::dynamic(cuboid(0.5, 0.5, 0.5))
                    .at(DVec3::new(x, 0.0, 0.5 + i as f64))
                    .with_mass(1.0)
                    .named(format!("box_{i}_{k}")),
            );
        }
    }
    ten_seconds_without_sleep(name, bodies)
}

/// A single column of `n` unit cubes (mass 1) on the ground.
pub fn tower(n: usize) -> Scene {
    let mut bodies = vec![ground_box(10.0, 10.0)];
    for i in 0..n {
        bodies.push(
            BodyDesc::dynamic(cuboid(0.5, 0.5, 0.5))
                .at(DVec3::new(0.0, 0.0, 0.5 + i as f64))
                .with_mass(1.0),
        );
    }
    ten_seconds_without_sleep(format!("tower{n}"), bodies)
}

/// pile: `layers` x 100 bodies (10 x 10 grid per layer, alternating spheres of
/// radius 0.25 and cubes of half extent 0.25, density 1) dropped into a static
/// container; `layers = 10` is the 1,000-body scene. The walls are 8 m high
/// up to 1,000 bodies and beyond reach 1 m above the top layer's centre.
pub fn pile(layers: usize) -> Scene {
    let top = 1.0 + 0.6 * (layers.max(1) - 1) as f64;
    let wall_half_height = (top + 1.0).max(8.0) / 2.0;
    let mut bodies = vec![BodyDesc::fixed(cuboid(3.5, 3.5, 0.5))
        .at(DVec3::new(0.0, 0.0, -0.5))
        .named("floor")];
    for sign in [-1.0, 1.0] {
        bodies.push(
            BodyDesc::fixed(cuboid(0.25, 3.5, wall_half_height))
                .at(DVec3::new(sign * 3.25, 0.0, wall_half_height))
                .named("wall_x"),
        );
        bodies.push(
            BodyDesc::fixed(cuboid(3.0, 0.25, wall_half_height))
                .at(DVec3::new(0.0, sign * 3.25, wall_half_height))
                .named("wall_y"),
        );
    }
    for k in 0..layers {
        let o = if k % 2 == 1 { 0.1 } else { 0.0 };
        for j in 0..10 {
            for i in 0..10 {
                let shape = if (i + j + k) % 2 == 0 {
                    sphere(0.25)
                } else {
                    cuboid(0.25, 0.25, 0.25)
                };
                bodies.push(
                    BodyDesc::dynamic(shape)
                        .at(DVec3::new(
                            -2.7 + 0.6 * i as f64 + o,
                            -2.7 + 0.6 * j as f64 + o,
                            1.0 + 0.6 * k as f64,
                        ))
                        .with_density(1.0),
                );
            }
        }
    }
    ten_seconds_without_sleep(format!("pile{}", layers * 100), bodies)
}

/// cradle: five touching spheres (r 0.1, mass 1, e = 1, mu = 0) in a row and a
/// sixth approaching at 1 m/s; zero gravity, dt 1/240, 240 steps.
pub fn cradle() -> Scene {
    let mut bodies = Vec::new();
    let ball = |x: f64| {
        BodyDesc::dynamic(sphere(0.1))
            .at(DVec3::new(x, 0.0, 0.0))
            .with_mass(1.0)
            .with_material(0.0, 1.0)
    };
    for i in 0..5 {
        bodies.push(ball(0.2 * i as f64).named(format!("ball{i}")));
    }
    bodies.push(
        ball(-0.5)
            .with_velocity(DVec3::new(1.0, 0.0, 0.0), DVec3::ZERO)
            .named("striker"),
    );
    Scene {
        name: "cradle".into(),
        settings: WorldSettings {
            gravity: DVec3::ZERO,
            dt: 1.0 / 240.0,
            sleeping: false,
            ..WorldSettings::default()
        },
        bodies,
        steps: 240,
        joints: Vec::new(),
        no_contact: Vec::new(),
        gears: Vec::new(),
    }
}

/// incline: a cube (half extent 0.25, mass 1) resting on a static slab tilted
/// by 30 degrees about y; both bodies with friction `mu`. dt 1/240, 240 steps.
pub fn incline(mu: f64) -> Scene {
    let theta = 30f64.to_radians();
    let rot = DQuat::from_rotation_y(theta);
    let normal = rot * DVec3::Z;
    let slab = BodyDesc::fixed(cuboid(10.0, 10.0, 0.5))
        .with_pose(Pose {
            position: DVec3::ZERO,
            rotation: rot,
        })
        .with_material(mu, 0.0)
        .named("slope");
    let cube = BodyDesc::dynamic(cuboid(0.25, 0.25, 0.25))
        .with_pose(Pose {
            position: normal * 0.75,
            rotation: rot,
        })
        .with_mass(1.0)
        .with_material(mu, 0.0)
        .named("cube");
    Scene {
        name: format!("incline_mu{mu}"),
        settings: WorldSettings {
            dt: 1.0 / 240.0,
            sleeping: false,
            ..WorldSettings::default()
        },
        bodies: vec![slab, cube],
        steps: 240,
        joints: Vec::new(),
        no_contact: Vec::new(),
        gears: Vec::new(),
    }
}

/// domino: 30 dominoes (half extents 0.05, 0.4, 0.8; mass 0.2) 0.8 m apart on
/// a half-space ground; the first is tipped with angular velocity (0, 2, 0).
pub fn domino() -> Scene {
    let mut bodies = vec![BodyDesc::fixed(Shape::HalfSpace(HalfSpace::ground())).named("ground")];
    for i in 0..30 {
        let mut d = BodyDesc::dynamic(cuboid(0.05, 0.4, 0.8))
            .at(DVec3::new(0.8 * i as f64, 0.0, 0.8))
            .with_mass(0.2)
            .named(format!("domino{i}"));
        if i == 0 {
            d = d.with_velocity(DVec3::ZERO, DVec3::new(0.0, 2.0, 0.0));
        }
        bodies.push(d);
    }
    ten_seconds_without_sleep("domino", bodies)
}

/// A sphere (radius 0.1, mass 1) dropped from `height` (centre above the
/// ground plane z = 0) onto a half-space, both with restitution `e`.
pub fn ball_drop(height: f64, e: f64) -> Scene {
    Scene {
        name: "ball_drop".into(),
        settings: WorldSettings {
            dt: 1.0 / 240.0,
            sleeping: false,
            ..WorldSettings::default()
        },
        bodies: vec![
            BodyDesc::fixed(Shape::HalfSpace(HalfSpace::ground()))
                .with_material(0.5, e)
                .named("ground"),
            BodyDesc::dynamic(sphere(0.1))
                .at(DVec3::new(0.0, 0.0, height))
                .with_mass(1.0)
                .with_material(0.5, e)
                .named("ball"),
        ],
        steps: 1200,
        joints: Vec::new(),
        no_contact: Vec::new(),
        gears: Vec::new(),
    }
}
