//! Orientation predicates (Guigue & Devillers 2003, sec. 2): Shewchuk's
//! adaptive-precision `orient3d` and `orient2d` ("Adaptive Precision
//! Floating-Point Arithmetic and Fast Robust Geometric Predicates", 1997),
//! from the `robust` crate.
//!
//! Every sign decision of the overlap tests goes through these two functions.
//! The sign is exact for any finite input whose products neither overflow
//! nor underflow: a floating-point determinant with an error bound first,
//! and more precise stages only where the bound does not settle the sign.
//! Plain determinants were exact only for small integer coordinates: two
//! copies of one triangle a million metres long, slid along its own edge
//! and so exactly coplanar in floating point, were taken to cross each
//! other (libFuzzer, `fuzz/regressions/collide/coplanar_far_slide`).

use crate::math::DVec3;
use glam::DVec2;
use robust::{Coord, Coord3D};

/// Signed volume (times 6) of the tetrahedron `a b c d`:
/// `((b - a) x (c - a)) . (d - a)`, with its sign exact.
///
/// Positive when `d` lies on the side of the plane `a b c` that the
/// counter-clockwise normal `(b - a) x (c - a)` points to, negative on the other
/// side, zero when the four points are coplanar (units: m^3).
#[inline]
pub fn orient3d(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    let p = |v: DVec3| Coord3D {
        x: v.x,
        y: v.y,
        z: v.z,
    };
    // Shewchuk's sign convention is the opposite one (positive below).
    -robust::orient3d(p(a), p(b), p(c), p(d))
}

/// Signed area (times 2) of the triangle `a b c` in the plane, with its sign
/// exact: positive when `a b c` turn counter-clockwise, zero when collinear
/// (m^2).
#[inline]
pub fn orient2d(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    let p = |v: DVec2| Coord { x: v.x, y: v.y };
    robust::orient2d(p(a), p(b), p(c))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orient3d_sign_follows_the_right_hand_rule() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        assert_eq!(orient3d(a, b, c, DVec3::Z), 1.0);
        assert_eq!(orient3d(a, b, c, -DVec3::Z), -1.0);
        assert_eq!(orient3d(a, b, c, DVec3::new(5.0, -7.0, 0.0)), 0.0);
        // Swapping two points flips the sign.
        assert_eq!(orient3d(b, a, c, DVec3::Z), -1.0);
    }

    #[test]
    fn orient2d_is_twice_the_signed_area() {
        let a = DVec2::new(0.0, 0.0);
        let b = DVec2::new(4.0, 0.0);
        let c = DVec2::new(0.0, 3.0);
        assert_eq!(orient2d(a, b, c), 12.0);
        assert_eq!(orient2d(a, c, b), -12.0);
        assert_eq!(orient2d(a, b, DVec2::new(9.0, 0.0)), 0.0);
    }
}
