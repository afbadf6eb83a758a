//! Orientation predicates as plain determinants (Guigue & Devillers 2003, sec. 2;
//! Shewchuk's `orient3d` without the adaptive precision).
//!
//! Every sign decision of the overlap tests goes through these two functions.
//! They are evaluated as differences followed by products, so for coordinates
//! that are integers of magnitude below about 5 * 10^4 every intermediate value
//! is an integer below 2^53 and the result is exact: the tests of this module
//! rely on that to compare against an exact oracle. For general floating-point
//! input the sign is only as good as the conditioning of the determinant.

use crate::math::DVec3;
use glam::DVec2;

/// Signed volume (times 6) of the tetrahedron `a b c d`:
/// `((b - a) x (c - a)) . (d - a)`.
///
/// Positive when `d` lies on the side of the plane `a b c` that the
/// counter-clockwise normal `(b - a) x (c - a)` points to, negative on the other
/// side, zero when the four points are coplanar (units: m^3).
#[inline]
pub fn orient3d(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    (b - a).cross(c - a).dot(d - a)
}

/// Signed area (times 2) of the triangle `a b c` in the plane:
/// positive when `a b c` turn counter-clockwise, zero when collinear (m^2).
#[inline]
pub fn orient2d(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    let u = b - a;
    let v = c - a;
    u.x * v.y - u.y * v.x
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
