//! Measures of one triangle that several triangle tests share: its
//! axis-aligned bounding box and its longest edge (squared), the scale
//! against which an area counts as round-off.

use glam::DVec3;

/// Lowest and highest corners of the axis-aligned box of `t`.
#[inline(always)]
pub(crate) fn bounds(t: &[DVec3; 3]) -> (DVec3, DVec3) {
    (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]))
}

/// Squared length of the longest edge of `t`.
#[inline(always)]
pub(crate) fn longest_edge_squared(t: &[DVec3; 3]) -> f64 {
    (t[1] - t[0])
        .length_squared()
        .max((t[2] - t[1]).length_squared())
        .max((t[0] - t[2]).length_squared())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_and_longest_edge_of_a_right_triangle() {
        let t = [
            DVec3::new(1.0, -2.0, 0.5),
            DVec3::new(4.0, -2.0, 0.5),
            DVec3::new(1.0, 2.0, 0.5),
        ];
        assert_eq!(
            bounds(&t),
            (DVec3::new(1.0, -2.0, 0.5), DVec3::new(4.0, 2.0, 0.5))
        );
        // Legs 3 and 4: the hypotenuse, 5, is the longest edge.
        assert_eq!(longest_edge_squared(&t), 25.0);
    }
}
