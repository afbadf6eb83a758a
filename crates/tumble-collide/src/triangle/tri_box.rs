//! Triangle vs oriented box overlap by the separating axis theorem
//! (Akenine-Moller, "Fast 3D triangle-box overlap testing", 2001), written from
//! the paper.
//!
//! The triangle is moved into the box frame, where the box is the axis-aligned
//! `[-h, h]`. Thirteen candidate axes: the 3 box axes (an AABB test of the
//! triangle), the triangle normal (a plane-box test), and the 9 cross products
//! of box axes with triangle edges. Both sets are closed: touching counts as
//! overlapping. Order follows cost and rejection power in a BVH traversal:
//! the AABB test first, then the plane, then the 9 edge axes.

use crate::math::{DMat3, DVec3};

/// `true` when the closed triangle `tri` and the closed oriented box overlap.
///
/// The box has centre `centre` (m), half extents `half_extents` (m, per box
/// axis; negative values are taken by absolute value) and orientation `axes`,
/// whose columns are the box's unit x, y, z axes in the triangle's frame (a
/// rotation matrix). Zero-area triangles are handled (a zero axis never
/// separates, and the remaining axes are those of a segment or point). If any
/// input is not finite the answer is `false`.
#[inline]
pub fn tri_box_overlap(tri: &[DVec3; 3], centre: DVec3, half_extents: DVec3, axes: &DMat3) -> bool {
    let finite = tri.iter().all(|p| p.is_finite())
        && centre.is_finite()
        && half_extents.is_finite()
        && axes.is_finite();
    if !finite {
        return false;
    }
    let h = half_extents.abs();
    // Into the box frame: v = R^T (p - c).
    let local = |p: DVec3| {
        let d = p - centre;
        DVec3::new(axes.x_axis.dot(d), axes.y_axis.dot(d), axes.z_axis.dot(d))
    };
    let v = [local(tri[0]), local(tri[1]), local(tri[2])];
    let lo = v[0].min(v[1]).min(v[2]);
    let hi = v[0].max(v[1]).max(v[2]);
    if lo.x > h.x || lo.y > h.y || lo.z > h.z || hi.x < -h.x || hi.y < -h.y || hi.z < -h.z {
        return false;
    }
    let e = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
    // Plane of the triangle against the box: the box's projection radius on n
    // versus the plane offset.
    let n = e[0].cross(e[1]);
    let r = h.dot(n.abs());
    let s = n.dot(v[0]);
    if s > r || s < -r {
        return false;
    }
    // Axes a = unit_k x e_i. For unit x: (0, -e.z, e.y), and so on. Two of the
    // three vertices project to the same value on each such axis, but taking
    // all three keeps the code uniform and costs little.
    for ei in e {
        for a in [
            DVec3::new(0.0, -ei.z, ei.y),
            DVec3::new(ei.z, 0.0, -ei.x),
            DVec3::new(-ei.y, ei.x, 0.0),
        ] {
            let p0 = a.dot(v[0]);
            let p1 = a.dot(v[1]);
            let p2 = a.dot(v[2]);
            let r = h.dot(a.abs());
            if p0.min(p1).min(p2) > r || p0.max(p1).max(p2) < -r {
                return false;
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::super::exact_oracle::to_f;
    use super::super::tri_tri_overlap::tri_tri_overlap;
    use super::*;
    use crate::mesh::box_mesh;
    use tumble_testkit::{RandomSource, XorShift64Star as Rng};

    /// Reference: the triangle meets the solid box iff it meets one of the 12
    /// surface triangles or lies inside (then its first vertex is inside).
    fn reference(tri: &[DVec3; 3], centre: DVec3, h: DVec3, axes: &DMat3) -> bool {
        let mesh = box_mesh(h).unwrap();
        let world = |p: DVec3| centre + *axes * p;
        let hit_surface = mesh.triangles().iter().any(|t| {
            let bt = [
                world(mesh.vertices()[t[0] as usize]),
                world(mesh.vertices()[t[1] as usize]),
                world(mesh.vertices()[t[2] as usize]),
            ];
            tri_tri_overlap(tri, &bt)
        });
        let d = tri[0] - centre;
        let l = DVec3::new(axes.x_axis.dot(d), axes.y_axis.dot(d), axes.z_axis.dot(d));
        let inside = l.abs().cmple(h).all();
        hit_surface || inside
    }

    /// Signed permutation matrices: rotations that keep integer points integer,
    /// so the reference and the SAT test see exact coordinates.
    fn signed_permutation(rng: &mut Rng) -> DMat3 {
        let perms = [[0, 1, 2], [1, 2, 0], [2, 0, 1], [1, 0, 2], [0, 2, 1], [2, 1, 0]];
        let p = perms[rng.int(0, 5) as usize];
        let mut cols = [DVec3::ZERO; 3];
        for (c, &k) in cols.iter_mut().zip(&p) {
            let mut v = DVec3::ZERO;
            v[k] = if rng.int(0, 1) == 0 { 1.0 } else { -1.0 };
            *c = v;
        }
        let m = DMat3::from_cols(cols[0], cols[1], cols[2]);
        if m.determinant() < 0.0 {
            DMat3::from_cols(-cols[0], cols[1], cols[2])
        } else {
            m
        }
    }

    #[test]
    fn integer_boxes_match_box_triangle_reference() {
        let mut rng = Rng(2024);
        let mut hits = 0;
        let n = 20_000;
        for _ in 0..n {
            let mut p = || {
                DVec3::new(
                    rng.int(-3, 3) as f64,
                    rng.int(-3, 3) as f64,
                    rng.int(-3, 3) as f64,
                )
            };
            let tri = [p(), p(), p()];
            let centre = p() * 0.5;
            let h = DVec3::new(rng.int(1, 2) as f64, rng.int(1, 2) as f64, rng.int(1, 2) as f64) * 0.5;
            let axes = signed_permutation(&mut rng);
            let want = reference(&tri, centre, h, &axes);
            assert_eq!(
                tri_box_overlap(&tri, centre, h, &axes),
                want,
                "{tri:?} {centre} {h} {axes}"
            );
            hits += want as usize;
        }
        assert!(hits > n / 10 && hits < n * 9 / 10, "hits {hits}");
    }

    #[test]
    fn rotated_boxes_match_reference_away_from_touching() {
        use crate::math::DQuat;
        let mut rng = Rng(11);
        for _ in 0..3_000 {
            let mut p = || DVec3::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
            let tri = [p(), p(), p()];
            let centre = p() * 0.5;
            let q = DQuat::from_xyzw(p().x, p().y, p().z, 1.0).normalize();
            let axes = DMat3::from_quat(q);
            let h = DVec3::new(rng.range(0.1, 1.0), rng.range(0.1, 1.0), rng.range(0.1, 1.0));
            // Shrinking and growing the box by a little must not change the
            // answer unless the pair is nearly touching; skip those.
            let small = reference(&tri, centre, h * (1.0 - 1e-9), &axes);
            let big = reference(&tri, centre, h * (1.0 + 1e-9), &axes);
            if small != big {
                continue;
            }
            assert_eq!(tri_box_overlap(&tri, centre, h, &axes), small);
        }
        let _ = to_f;
    }

    #[test]
    fn face_touching_and_contained_triangles_overlap() {
        let axes = DMat3::IDENTITY;
        let h = DVec3::ONE;
        // Lying on the top face.
        let top = [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(3.0, 0.0, 1.0),
            DVec3::new(0.0, 3.0, 1.0),
        ];
        assert!(tri_box_overlap(&top, DVec3::ZERO, h, &axes));
        let above = top.map(|p| p + DVec3::Z * 1e-9);
        assert!(!tri_box_overlap(&above, DVec3::ZERO, h, &axes));
        // Entirely inside.
        let inner = [
            DVec3::splat(0.1),
            DVec3::new(0.2, 0.1, 0.1),
            DVec3::new(0.1, 0.2, 0.1),
        ];
        assert!(tri_box_overlap(&inner, DVec3::ZERO, h, &axes));
        // A vertical triangle just past a vertical box edge, and one cutting it.
        let past = [
            DVec3::new(2.1, 0.0, -5.0),
            DVec3::new(0.0, 2.1, -5.0),
            DVec3::new(1.05, 1.05, 5.0),
        ];
        assert!(!tri_box_overlap(&past, DVec3::ZERO, h, &axes));
        let cut = [
            DVec3::new(1.9, 0.0, -5.0),
            DVec3::new(0.0, 1.9, -5.0),
            DVec3::new(0.95, 0.95, 5.0),
        ];
        assert!(tri_box_overlap(&cut, DVec3::ZERO, h, &axes));
    }

    #[test]
    fn non_finite_input_returns_false() {
        let tri = [DVec3::ZERO, DVec3::X, DVec3::new(f64::NAN, 0.0, 0.0)];
        assert!(!tri_box_overlap(&tri, DVec3::ZERO, DVec3::ONE, &DMat3::IDENTITY));
        let ok = [DVec3::ZERO, DVec3::X, DVec3::Y];
        assert!(!tri_box_overlap(
            &ok,
            DVec3::ZERO,
            DVec3::splat(f64::NAN),
            &DMat3::IDENTITY
        ));
        assert!(!tri_box_overlap(
            &ok,
            DVec3::splat(f64::INFINITY),
            DVec3::ONE,
            &DMat3::IDENTITY
        ));
    }
}
