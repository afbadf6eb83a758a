//! Separating axis test between two oriented boxes (Gottschalk, Lin & Manocha
//! 1996, section 5; thesis 4.5.2; Ericson, "Real-Time Collision Detection",
//! section 4.4.1), and a lower bound on their distance from the same 15 axes.
//!
//! Box B is given in A's frame: `r` holds B's axes as columns (`r[i][j] =
//! A_i . B_j`) and `t` is B's centre. Two convex sets are disjoint exactly when
//! some axis separates their projections; for boxes the 15 candidates are A's
//! three face normals, B's three, and the nine cross products `A_i x B_j`.
//!
//! Why [`PARALLEL_EPS`]: when an edge of A is nearly parallel to an edge of B
//! the cross product axis is nearly zero and both sides of the test are
//! round-off; adding a small epsilon to every `|r[i][j]|` makes such an axis
//! never report separation (the face axes still do) and also absorbs the
//! slight non-orthonormality of f32-stored axes.
//!
//! The tree walks' test, [`obb_disjoint_axes`], and the distance walk's
//! bound, [`obb_distance_lower_bound_axes`], run each group of three axes
//! in SIMD lanes (`wide::f64x4`) with the numbers of their scalar twins
//! ([`obb_disjoint`], [`obb_distance_lower_bound`]) in their order: the same
//! answers, faster.

use super::obb::Obb;
use crate::math::{DMat3, DVec3};
use wide::f64x4;

/// Added to every `|r[i][j]|` (dimensionless, entries are direction cosines).
pub const PARALLEL_EPS: f64 = 1e-6;

/// Rotation (row-major, `r[i][j] = A_i . B_j`) and translation of box B in
/// box A's frame.
#[derive(Debug, Clone, Copy)]
pub struct RelFrame {
    /// `r[i][j] = A_i . B_j`.
    pub r: [[f64; 3]; 3],
    /// Centre of B in A's frame (m).
    pub t: [f64; 3],
}

impl RelFrame {
    /// From B's axes as columns of `rot` and B's centre `t`, both in A's frame.
    #[inline]
    pub fn new(rot: &DMat3, t: DVec3) -> RelFrame {
        let c = rot.to_cols_array_2d(); // c[j][i] = column j, row i
        RelFrame {
            r: [
                [c[0][0], c[1][0], c[2][0]],
                [c[0][1], c[1][1], c[2][1]],
                [c[0][2], c[1][2], c[2][2]],
            ],
            t: t.to_array(),
        }
    }

    /// `|r[i][j]| + PARALLEL_EPS`: the absolute rotation both box tests use,
    /// padded so that nearly parallel edges (cross products near zero) do
    /// not report a false separation.
    #[inline]
    pub fn abs_padded(&self) -> [[f64; 3]; 3] {
        self.r.map(|row| row.map(|x| x.abs() + PARALLEL_EPS))
    }

    /// Frame of box `b` relative to box `a`, both given in the same frame.
    pub fn between(a: &Obb, b: &Obb) -> RelFrame {
        let at = a.axes.transpose();
        RelFrame::new(&(at * b.axes), at * (b.center - a.center))
    }
}

/// `true` when boxes with half extents `a` and `b` (m), B placed by `f` in
/// A's frame, are separated by one of the 15 axes (conservative: nearly
/// touching or nearly parallel cases report overlap).
#[inline]
pub fn obb_disjoint(a: [f64; 3], b: [f64; 3], f: &RelFrame) -> bool {
    let ar = f.abs_padded();
    (0..3).any(|i| a_face_separates(i, a, b, &ar[i], f.t[i])) || other_axes_separate(a, b, &f.r, &ar, &f.t)
}

/// A box's axes by component, for [`obb_disjoint_axes`]: lane `k` of
/// entry `c` is component `c` (x, y, z) of axis `k` (lane 3 is zero).
pub type AxisLanes = [f64x4; 3];

/// The [`AxisLanes`] of the axes that are the columns of `axes`.
#[inline]
pub fn axis_lanes(axes: &DMat3) -> AxisLanes {
    let (x, y, z) = (axes.x_axis, axes.y_axis, axes.z_axis);
    [
        f64x4::new([x.x, y.x, z.x, 0.0]),
        f64x4::new([x.y, y.y, z.y, 0.0]),
        f64x4::new([x.z, y.z, z.z, 0.0]),
    ]
}

/// A box for the lane tests: its axes as columns and by component
/// ([`axis_lanes`]), centre and half extents, in the frame of the test.
#[derive(Clone, Copy)]
pub struct LaneBox<'a> {
    /// The box's axes (columns).
    pub axes: &'a DMat3,
    /// The same by component.
    pub lanes: &'a AxisLanes,
    /// Centre (m).
    pub center: DVec3,
    /// Half extents along the axes (m).
    pub half: [f64; 3],
}

/// [`obb_disjoint`] for boxes `a` and `b` given in one frame, each group of
/// axes tested in SIMD lanes: A's three faces, then B's three, then the
/// three edges of each of A's axes. Every lane computes what
/// [`obb_disjoint`] computes for its axis, in the same order (`r[i][j] =
/// A_i . B_j` and `t[i] = A_i . (cB - cA)` as glam's dot orders them; a
/// product is the same either way round), so the answer is the same bit for
/// bit in every intermediate (a test holds the two together). A's faces,
/// which reject most pairs of a tree walk that are apart, need only the
/// columns `A^T B_j` and `A^T (cB - cA)`. Why lanes: a tree walk spends its
/// time here (the torus chain's step, 45 % of it in this test scalar, took
/// 1.20 ms instead of 1.43 on one thread, the same trajectory).
#[inline(always)]
pub fn obb_disjoint_axes(a: LaneBox, b: LaneBox) -> bool {
    let (t, rb) = a_face_terms(a, b);
    if t.abs().simd_gt(lanes_of(a.half) + rb).any() {
        return true;
    }
    let (r, ar, ra, tl) = b_face_terms(a, b, t);
    if tl.abs().simd_gt(ra + lanes_of(b.half)).any() {
        return true;
    }
    (0..3).any(|i| {
        let (ra, rb, tl) = edge_terms(i, a.half, b.half, &r, &ar, t.to_array());
        tl.abs().simd_gt(ra + rb).any()
    })
}

/// [`obb_distance_lower_bound`] for boxes given as to [`obb_disjoint_axes`],
/// each group of axes in SIMD lanes with that function's numbers in its
/// order (the same bound; a test holds the two together).
pub fn obb_distance_lower_bound_axes(a: LaneBox, b: LaneBox) -> f64 {
    let (t, rb) = a_face_terms(a, b);
    let faces_a = (t.abs() - lanes_of(a.half)) - rb;
    let (r, ar, ra, tl) = b_face_terms(a, b, t);
    let faces_b = (tl.abs() - ra) - lanes_of(b.half);
    // The largest gap, at least 0, over the three lanes of each group (lane
    // 3 pads).
    let mut best = 0.0f64;
    let mut fold = |gaps: f64x4| {
        for x in &gaps.to_array()[..3] {
            best = best.max(*x);
        }
    };
    fold(faces_a);
    fold(faces_b);
    for (i, r_i) in r.iter().enumerate() {
        // |A_i x B_j| = sin(angle); nearly parallel axes carry no reliable
        // information and are left out (0 never raises the bound).
        let len2 = f64x4::ONE - *r_i * *r_i;
        let (ra, rb, tl) = edge_terms(i, a.half, b.half, &r, &ar, t.to_array());
        let gap = ((tl.abs() - ra) - rb) / len2.sqrt();
        fold(len2.simd_ge(f64x4::splat(1e-6)).select(gap, f64x4::ZERO));
    }
    best
}

/// A's face axes, lane i: `t[i] = A_i . (cB - cA)` and B's projected half
/// extent `sum_j b_j (|A_i . B_j| + PARALLEL_EPS)` (`A_i . x` as glam's dot
/// orders it, `A_i.x x.x + A_i.y x.y + A_i.z x.z`; a product is the same
/// either way round).
#[inline(always)]
fn a_face_terms(a: LaneBox, b: LaneBox) -> (f64x4, f64x4) {
    let [ax, ay, az] = *a.lanes;
    let column = |v: DVec3| ax * f64x4::splat(v.x) + ay * f64x4::splat(v.y) + az * f64x4::splat(v.z);
    let eps = f64x4::splat(PARALLEL_EPS);
    let ar = [b.axes.x_axis, b.axes.y_axis, b.axes.z_axis].map(|bj| column(bj).abs() + eps);
    let h = b.half;
    let rb = f64x4::splat(h[0]) * ar[0] + f64x4::splat(h[1]) * ar[1] + f64x4::splat(h[2]) * ar[2];
    (column(b.center - a.center), rb)
}

/// B's face axes, lane j: the rows `r[i] = A_i . B_j` (the same products as
/// [`a_face_terms`]) and the same padded (`|r| + PARALLEL_EPS`), A's
/// projected half extent and B's centre along `B_j` (from `t`).
#[inline(always)]
fn b_face_terms(a: LaneBox, b: LaneBox, t: f64x4) -> ([f64x4; 3], [f64x4; 3], f64x4, f64x4) {
    let [bx, by, bz] = *b.lanes;
    let row = |ai: DVec3| bx * f64x4::splat(ai.x) + by * f64x4::splat(ai.y) + bz * f64x4::splat(ai.z);
    let r = [row(a.axes.x_axis), row(a.axes.y_axis), row(a.axes.z_axis)];
    let eps = f64x4::splat(PARALLEL_EPS);
    let ar = r.map(|row| row.abs() + eps);
    let (h, t) = (a.half, t.to_array());
    let ra = f64x4::splat(h[0]) * ar[0] + f64x4::splat(h[1]) * ar[1] + f64x4::splat(h[2]) * ar[2];
    let tl = f64x4::splat(t[0]) * r[0] + f64x4::splat(t[1]) * r[1] + f64x4::splat(t[2]) * r[2];
    (r, ar, ra, tl)
}

/// The edge axes `A_i x B_j`, lane j: the projected half extents of A and
/// of B and of B's centre, as the scalar tests compute them (B's entries
/// j + 1 and j + 2, mod 3, turned into lane j).
#[inline(always)]
fn edge_terms(
    i: usize,
    a: [f64; 3],
    b: [f64; 3],
    r: &[f64x4; 3],
    ar: &[f64x4; 3],
    t: [f64; 4],
) -> (f64x4, f64x4, f64x4) {
    let turn = |v: [f64; 4], k: usize| f64x4::new([v[k], v[(k + 1) % 3], v[(k + 2) % 3], v[3]]);
    let b4 = [b[0], b[1], b[2], 0.0];
    let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
    let ra = f64x4::splat(a[i1]) * ar[i2] + f64x4::splat(a[i2]) * ar[i1];
    let row = ar[i].to_array();
    let rb = turn(b4, 1) * turn(row, 2) + turn(b4, 2) * turn(row, 1);
    let tl = f64x4::splat(t[i2]) * r[i1] - f64x4::splat(t[i1]) * r[i2];
    (ra, rb, tl)
}

/// Half extents in lanes 0-2.
#[inline(always)]
fn lanes_of(h: [f64; 3]) -> f64x4 {
    f64x4::new([h[0], h[1], h[2], 0.0])
}

/// Whether A's face axis `i` separates the boxes, given row `i` of the
/// padded absolute rotation and B's centre along the axis.
#[inline(always)]
fn a_face_separates(i: usize, a: [f64; 3], b: [f64; 3], ar_i: &[f64; 3], t_i: f64) -> bool {
    let rb = b[0] * ar_i[0] + b[1] * ar_i[1] + b[2] * ar_i[2];
    t_i.abs() > a[i] + rb
}

/// Whether one of B's face axes or the nine edge-edge axes separates the
/// boxes (the twelve axes after A's faces).
#[inline(always)]
fn other_axes_separate(
    a: [f64; 3],
    b: [f64; 3],
    r: &[[f64; 3]; 3],
    ar: &[[f64; 3]; 3],
    t: &[f64; 3],
) -> bool {
    // B's face axes.
    for j in 0..3 {
        let ra = a[0] * ar[0][j] + a[1] * ar[1][j] + a[2] * ar[2][j];
        let tl = t[0] * r[0][j] + t[1] * r[1][j] + t[2] * r[2][j];
        if tl.abs() > ra + b[j] {
            return true;
        }
    }
    // Edge-edge axes A_i x B_j: projections of the half extents onto the
    // unnormalised axis (A_i1 . (A_i x B_j) = -r[i2][j], etc.).
    for i in 0..3 {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        for j in 0..3 {
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            let ra = a[i1] * ar[i2][j] + a[i2] * ar[i1][j];
            let rb = b[j1] * ar[i][j2] + b[j2] * ar[i][j1];
            let tl = t[i2] * r[i1][j] - t[i1] * r[i2][j];
            if tl.abs() > ra + rb {
                return true;
            }
        }
    }
    false
}

/// `true` when the boxes overlap (or nearly touch).
#[inline]
pub fn obb_overlap(a: [f64; 3], b: [f64; 3], f: &RelFrame) -> bool {
    !obb_disjoint(a, b, f)
}

/// Overlap of the two boxes each grown by `margin` (m) along every axis: true
/// whenever the boxes are within `2 margin` of each other (a growth by margin
/// contains the Minkowski sum with a ball of that radius).
#[inline]
pub fn obb_overlap_margin(a: [f64; 3], b: [f64; 3], f: &RelFrame, margin: f64) -> bool {
    let a = [a[0] + margin, a[1] + margin, a[2] + margin];
    let b = [b[0] + margin, b[1] + margin, b[2] + margin];
    !obb_disjoint(a, b, f)
}

/// A lower bound on the Euclidean distance between the boxes (m), 0 when they
/// overlap: the largest gap between their projections on any of the 15 axes
/// (each normalised). Any unit direction's projection gap is at most the
/// distance, because projection onto a unit vector does not lengthen segments.
#[inline]
pub fn obb_distance_lower_bound(a: [f64; 3], b: [f64; 3], f: &RelFrame) -> f64 {
    let r = &f.r;
    let t = &f.t;
    let ar = f.abs_padded();
    let mut best = 0.0f64;
    for i in 0..3 {
        let rb = b[0] * ar[i][0] + b[1] * ar[i][1] + b[2] * ar[i][2];
        best = best.max(t[i].abs() - a[i] - rb);
    }
    for j in 0..3 {
        let ra = a[0] * ar[0][j] + a[1] * ar[1][j] + a[2] * ar[2][j];
        let tl = t[0] * r[0][j] + t[1] * r[1][j] + t[2] * r[2][j];
        best = best.max(tl.abs() - ra - b[j]);
    }
    for i in 0..3 {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        for j in 0..3 {
            // |A_i x B_j| = sin(angle); near-parallel axes carry no reliable
            // information and are skipped (the bound stays valid, only looser).
            let len2 = 1.0 - r[i][j] * r[i][j];
            if len2 < 1e-6 {
                continue;
            }
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            let ra = a[i1] * ar[i2][j] + a[i2] * ar[i1][j];
            let rb = b[j1] * ar[i][j2] + b[j2] * ar[i][j1];
            let tl = t[i2] * r[i1][j] - t[i1] * r[i2][j];
            best = best.max((tl.abs() - ra - rb) / len2.sqrt());
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::DQuat;

    use tumble_testkit::splitmix_f64 as rng;

    fn random_box(r: &mut impl FnMut() -> f64, spread: f64) -> Obb {
        let q = DQuat::from_xyzw(r() - 0.5, r() - 0.5, r() - 0.5, r() - 0.5).normalize();
        Obb {
            center: DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * spread,
            axes: DMat3::from_quat(q),
            half_extents: DVec3::new(r(), r(), r()) * 0.8 + DVec3::splat(0.05),
        }
    }

    /// Reference: project all 16 corners on all 15 (normalised) axes, f64.
    /// Returns the largest separation gap found (> 0 means disjoint).
    fn reference_gap(a: &Obb, b: &Obb) -> f64 {
        let (ca, cb) = (a.corners(), b.corners());
        let mut axes = Vec::new();
        for i in 0..3 {
            axes.push(a.axes.col(i));
            axes.push(b.axes.col(i));
            for j in 0..3 {
                let c = a.axes.col(i).cross(b.axes.col(j));
                if c.length() > 1e-9 {
                    axes.push(c.normalize());
                }
            }
        }
        let mut best = f64::NEG_INFINITY;
        for l in axes {
            let pa = ca.iter().map(|p| p.dot(l));
            let pb = cb.iter().map(|p| p.dot(l));
            let (amin, amax) = pa.fold((f64::MAX, f64::MIN), |(lo, hi), x| (lo.min(x), hi.max(x)));
            let (bmin, bmax) = pb.fold((f64::MAX, f64::MIN), |(lo, hi), x| (lo.min(x), hi.max(x)));
            best = best.max((bmin - amax).max(amin - bmax));
        }
        best
    }

    /// Independent distance between two boxes: alternating projections
    /// (closest point of A to a point of B and back) converge to the closest
    /// pair for two convex sets; the result is an upper bound that approaches
    /// the true distance from above.
    fn brute_distance(a: &Obb, b: &Obb) -> f64 {
        let clamp = |o: &Obb, p: DVec3| {
            let u = o.axes.transpose() * (p - o.center);
            o.center + o.axes * u.clamp(-o.half_extents, o.half_extents)
        };
        let mut best = f64::INFINITY;
        // Several starts (centres and corners) guard against slow convergence.
        let mut starts = vec![b.center];
        starts.extend(b.corners());
        for s in starts {
            let mut pb = s;
            for _ in 0..400 {
                let pa = clamp(a, pb);
                let next = clamp(b, pa);
                best = best.min((pa - next).length());
                let moved = (next - pb).length();
                pb = next;
                if moved < 1e-13 {
                    break;
                }
            }
        }
        best
    }

    #[test]
    fn sat_agrees_with_corner_projection_reference() {
        let mut r = rng(11);
        let mut disagreements = 0;
        for _ in 0..20_000 {
            let a = random_box(&mut r, 4.0);
            let b = random_box(&mut r, 4.0);
            let fast = obb_disjoint(
                a.half_extents.to_array(),
                b.half_extents.to_array(),
                &RelFrame::between(&a, &b),
            );
            let (lanes_a, lanes_b) = (axis_lanes(&a.axes), axis_lanes(&b.axes));
            let box_a = LaneBox {
                axes: &a.axes,
                lanes: &lanes_a,
                center: a.center,
                half: a.half_extents.to_array(),
            };
            let box_b = LaneBox {
                axes: &b.axes,
                lanes: &lanes_b,
                center: b.center,
                half: b.half_extents.to_array(),
            };
            let by_axes = obb_disjoint_axes(box_a, box_b);
            // The lanes compute the frame's numbers in the frame's order.
            assert_eq!(by_axes, fast);
            let bound = obb_distance_lower_bound(
                a.half_extents.to_array(),
                b.half_extents.to_array(),
                &RelFrame::between(&a, &b),
            );
            let bound_by_axes = obb_distance_lower_bound_axes(box_a, box_b);
            assert_eq!(bound_by_axes, bound);
            let gap = reference_gap(&a, &b);
            // Identical answers except within a tiny band around touching
            // (the parallel epsilon widens the boxes by ~1e-6 * size), for
            // the frame given whole and for the frame built a row at a time.
            for (what, answer) in [("frame", fast), ("axes", by_axes)] {
                if answer != (gap > 0.0) {
                    assert!(gap.abs() < 1e-5, "{what}: {answer} but reference gap {gap}");
                    disagreements += 1;
                }
            }
        }
        assert!(disagreements < 40);
    }

    #[test]
    fn margin_overlap_covers_distance_up_to_twice_the_margin() {
        let mut r = rng(5);
        for _ in 0..3_000 {
            let a = random_box(&mut r, 5.0);
            let b = random_box(&mut r, 5.0);
            let f = RelFrame::between(&a, &b);
            let d = brute_distance(&a, &b);
            let m = 0.3;
            if d <= 2.0 * m {
                assert!(obb_overlap_margin(
                    a.half_extents.to_array(),
                    b.half_extents.to_array(),
                    &f,
                    m
                ));
            }
        }
    }

    // The seeded random loop of `sat_agrees_with_corner_projection_reference`
    // (and of tri_contact.rs's `penetrating_pair_is_pushed_out_by_its_contact`)
    // again: seed, count, box size and tallies are tuned per property.
    #[test]
    fn lower_bound_never_exceeds_true_distance() {
        let mut r = rng(99);
        let mut tight = 0;
        for _ in 0..3_000 {
            let a = random_box(&mut r, 6.0);
            let b = random_box(&mut r, 6.0);
            let f = RelFrame::between(&a, &b);
            let lb = obb_distance_lower_bound(a.half_extents.to_array(), b.half_extents.to_array(), &f);
            let d = brute_distance(&a, &b);
            assert!(lb <= d + 1e-9, "lower bound {lb} > distance {d}");
            assert!(lb >= 0.0);
            if d > 0.0 && lb > 0.5 * d {
                tight += 1;
            }
            // Overlapping boxes (reference) have bound 0.
            if reference_gap(&a, &b) < -1e-6 {
                assert_eq!(lb, 0.0);
            }
        }
        // The bound is useful, not just valid: usually within 2x of the truth.
        assert!(tight > 1_000, "{tight}");
    }

    #[test]
    fn parallel_touching_boxes_overlap() {
        let a = Obb::from_aabb(DVec3::ZERO, DVec3::ONE);
        let b = Obb::from_aabb(DVec3::new(1.0, 0.0, 0.0), DVec3::new(2.0, 1.0, 1.0));
        let f = RelFrame::between(&a, &b);
        assert!(obb_overlap(
            a.half_extents.to_array(),
            b.half_extents.to_array(),
            &f
        ));
        let c = Obb::from_aabb(DVec3::new(1.5, 0.0, 0.0), DVec3::new(2.0, 1.0, 1.0));
        let f = RelFrame::between(&a, &c);
        assert!(!obb_overlap(
            a.half_extents.to_array(),
            c.half_extents.to_array(),
            &f
        ));
        let lb = obb_distance_lower_bound(a.half_extents.to_array(), c.half_extents.to_array(), &f);
        assert!((lb - 0.5).abs() < 1e-5);
    }
}
