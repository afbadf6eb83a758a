//! bowl: a 5 cm ball let go 25 degrees up the side of a 0.5 m hemispherical
//! bowl of 96 x 48 facets (friction 0.8, dt 1/240 s, 4 s), issue 15's
//! rolling test as a standard scene. Read with `SwingMeter` (swing_meter.rs)
//! against `analytic::rolling_period`.

use super::Scene;
use crate::world::BodyDesc;
use tumble_collide::mesh::bowl_mesh;
use tumble_collide::shape::{MeshShape, Shape, Sphere};
use tumble_collide::DVec3;

/// Inner radius of the bowl (m).
pub const BOWL_RADIUS: f64 = 0.5;
/// Radius of the ball (m).
pub const BOWL_BALL_RADIUS: f64 = 0.05;
/// Where the ball is let go, from straight down (degrees).
pub const BOWL_START_DEG: f64 = 25.0;
/// The smooth surface's crease angle (degrees): blends the 3.75 degree
/// facets, keeps the rim sharp.
pub const BOWL_CREASE_DEG: f64 = 30.0;

/// The bowl scene: the bowl (static, facets 96 x 48, with a smooth surface
/// when `smooth`) and the ball (1 kg) at rest on its inside, both friction
/// 0.8, restitution 0; 960 steps of 1/240 s, sleeping off.
pub fn bowl_swing(smooth: bool) -> Scene {
    let mut bowl =
        MeshShape::new(bowl_mesh(BOWL_RADIUS, 0.05, 96, 48).expect("valid bowl")).expect("bowl tree");
    if smooth {
        bowl = bowl
            .with_smooth_surface(BOWL_CREASE_DEG.to_radians())
            .expect("valid crease angle");
    }
    let path = BOWL_RADIUS - BOWL_BALL_RADIUS;
    let phi0 = BOWL_START_DEG.to_radians();
    let bodies = vec![
        BodyDesc::fixed(Shape::Mesh(bowl))
            .with_material(0.8, 0.0)
            .named("bowl"),
        BodyDesc::dynamic(Shape::Sphere(
            Sphere::new(BOWL_BALL_RADIUS).expect("valid radius"),
        ))
        .at(DVec3::new(path * phi0.sin(), 0.0, -path * phi0.cos()))
        .with_mass(1.0)
        .with_material(0.8, 0.0)
        .named("ball"),
    ];
    let mut scene = super::ten_seconds_without_sleep(if smooth { "bowl" } else { "bowl-facets" }, bodies);
    scene.settings.dt = 1.0 / 240.0;
    scene.steps = 960;
    scene
}
