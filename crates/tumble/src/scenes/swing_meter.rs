//! The meter of a swing: its period from the crossings of the bottom and
//! its amplitude at the turning points, from one angle per step. The tests,
//! `tumble bench` and the Rapier peer read the bowl scene with it
//! (bench/peers/common.py has its Python twin for the Python peers).

use tumble_collide::DVec3;

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
    }
}
