//! bowl: a 5 cm ball let go 25 degrees up the side of a 0.5 m hemispherical
//! bowl of 96 x 48 facets (friction 0.8, dt 1/240 s, 4 s), issue 15's
//! rolling test as a standard scene; and the meter of a swing (its period
//! from the crossings of the bottom, its amplitude at the turning points)
//! that the tests, `tumble bench` and the Rapier peer read it with.
//!
//! Rolling without slipping inside a sphere of radius R, a ball of radius r
//! (k = I / m r^2 = 2/5) moves its centre on the circle of radius R - r as a
//! pendulum of length `(1 + k)(R - r)`: period `4 sqrt(L / g) K(sin^2(phi0 / 2))`.

use super::Scene;
use crate::analytic::elliptic_k;
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
    let mut scene = super::ten_seconds_without_sleep(if smooth { "bowl" } else { "bowl_facets" }, bodies);
    scene.settings.dt = 1.0 / 240.0;
    scene.steps = 960;
    scene
}

/// The period of a body rolling without slipping inside a sphere or a
/// cylinder, its centre on a circle of radius `path` (m), `k = I / (m r^2)`
/// about its rolling axis (0 for sliding without friction), let go at `phi0`
/// (rad): a pendulum of length `(1 + k) path` at that amplitude (s).
pub fn rolling_period(path: f64, k: f64, phi0: f64) -> f64 {
    let length = (1.0 + k) * path;
    4.0 * (length / 9.81).sqrt() * elliptic_k((phi0 / 2.0).sin().powi(2))
}

/// The swing angle of a centre about the origin (rad): from straight down,
/// in the plane normal to x for `about_x`, else normal to y.
pub fn swing_angle(centre: DVec3, about_x: bool) -> f64 {
    if about_x {
        centre.y.atan2(-centre.z)
    } else {
        centre.x.atan2(-centre.z)
    }
}

/// A swing's crossings of the bottom (times interpolated within the step)
/// and turning points (the angle at the step where the motion reverses),
/// from one angle per step.
#[derive(Debug, Clone)]
pub struct SwingMeter {
    dt: f64,
    time: f64,
    prev: f64,
    prev_rate: f64,
    /// Times the angle changed sign (s).
    pub crossings: Vec<f64>,
    /// Absolute angles where the motion reversed after the first crossing (rad).
    pub turns: Vec<f64>,
}

impl SwingMeter {
    /// A meter for steps of `dt` from the angle `start` (rad).
    pub fn new(dt: f64, start: f64) -> SwingMeter {
        SwingMeter {
            dt,
            time: 0.0,
            prev: start,
            prev_rate: 0.0,
            crossings: Vec::new(),
            turns: Vec::new(),
        }
    }

    /// The angle after one more step; `true` when this step was a turning point.
    pub fn observe(&mut self, angle: f64) -> bool {
        self.time += self.dt;
        if (self.prev > 0.0) != (angle > 0.0) {
            self.crossings
                .push(self.time - self.dt * angle / (angle - self.prev));
        }
        let rate = angle - self.prev;
        let turned =
            self.prev_rate != 0.0 && (rate > 0.0) != (self.prev_rate > 0.0) && !self.crossings.is_empty();
        if turned {
            self.turns.push(self.prev.abs());
        }
        (self.prev, self.prev_rate) = (angle, rate);
        turned
    }

    /// Two oscillations seen: five crossings and four turning points.
    pub fn done(&self) -> bool {
        self.crossings.len() >= 5 && self.turns.len() >= 4
    }

    /// The period from the first to the fifth crossing (s).
    pub fn period(&self) -> Option<f64> {
        (self.crossings.len() >= 5).then(|| (self.crossings[4] - self.crossings[0]) / 2.0)
    }

    /// The amplitude at the fourth turning point: two oscillations in (rad).
    pub fn amplitude_after_two(&self) -> Option<f64> {
        self.turns.get(3).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sampled cosine swing: the period and amplitude it was made with,
    /// to the sampling; turning points only after the first crossing.
    #[test]
    fn the_meter_reads_a_cosine() {
        let (phi0, period, dt) = (0.4, 1.6, 1.0 / 240.0);
        let mut meter = SwingMeter::new(dt, phi0);
        let mut k = 0;
        while !meter.done() {
            k += 1;
            meter.observe(phi0 * (std::f64::consts::TAU * k as f64 * dt / period).cos());
        }
        assert!((meter.period().unwrap() - period).abs() < 1e-4);
        assert!((meter.amplitude_after_two().unwrap() - phi0).abs() < 1e-4);
        assert_eq!(meter.turns.len(), 4);
        // Small swings: the period of a pendulum of length 7 (R - r) / 5.
        let small = rolling_period(0.45, 0.4, 1e-6);
        assert!((small - std::f64::consts::TAU * (1.4 * 0.45 / 9.81f64).sqrt()).abs() < 1e-9);
    }
}
