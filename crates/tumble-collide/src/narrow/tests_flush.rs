//! Manifolds of boxes whose sides are flush: a pyramid one box thick, every
//! box as wide as the next, every body on the plane y = 0 and turned about
//! y only. The geometry is then its own mirror image in y, and so must be
//! every manifold (each point with its mirror point, each patch centred on
//! the plane): a point the mirror lacks turns the boxes out of the plane.
//! The recorded poses are from the pyramid of base 25 and 100 on which
//! the clipping and the corner points went wrong (see `clip::ON_SIDE_PLANE`
//! and `contact_polytope_polytope::hold_near_vertices`).

use super::tests::unit_box;
use super::*;
use crate::math::{DQuat, DVec3};
use crate::pose::Pose;

/// The contacts between two unit boxes (`tests::contacts`).
fn contacts(pa: &Pose, pb: &Pose, margin: f64) -> Vec<Contact> {
    super::tests::contacts(&unit_box(), pa, &unit_box(), pb, margin)
}

/// A body of the pyramid: centre `x, z` on the plane (plus the rounding
/// the recorded poses carry in y), turned by `pitch` about y.
fn on_plane(x: f64, y: f64, z: f64, pitch: f64) -> Pose {
    Pose::new(DVec3::new(x, y, z), DQuat::from_rotation_y(pitch)).unwrap()
}

/// A pose recorded from a run: centre and quaternion (x, y, z, w).
fn recorded(position: [f64; 3], q: [f64; 4]) -> Pose {
    Pose::new(DVec3::from_array(position), DQuat::from_array(q)).unwrap()
}

/// Every point has its mirror image in y about `plane` (within `tol`), and
/// the manifold has at most four points (a box pair's patch is solved as
/// one block up to four).
fn assert_mirrored(cs: &[Contact], plane: f64, tol: f64) {
    assert!(!cs.is_empty());
    assert!(cs.len() <= 4, "{} points: {cs:#?}", cs.len());
    for c in cs {
        let mirror = DVec3::new(c.point.x, 2.0 * plane - c.point.y, c.point.z);
        assert!(
            cs.iter().any(|d| (d.point - mirror).length() < tol),
            "no mirror for {:?} in {cs:#?}",
            c.point
        );
    }
}

#[test]
fn a_box_across_two_flush_boxes_touches_at_the_corners_of_their_overlap() {
    // Recorded: a box of the pyramid of base 25 (step 7) and the one resting
    // across it; one edge's two ends lay a few 1e-16 m either side of the
    // lower box's side plane, and the cut between them put a point 16 cm
    // inside the face on one side.
    let lower = recorded(
        [-2.0994340028284677, -3.831666951490248e-16, 4.498739545060066],
        [
            4.530675253352514e-17,
            0.00013681278728869004,
            1.7714034546379925e-16,
            0.9999999906411305,
        ],
    );
    let upper = recorded(
        [-1.5744296948039658, -4.323751625656471e-16, 5.498529772895997],
        [
            -4.922418193139859e-17,
            0.00014519610568030305,
            -2.0619602434346228e-16,
            0.9999999894590454,
        ],
    );
    let cs = contacts(&lower, &upper, 0.01);
    assert_eq!(cs.len(), 4, "{cs:#?}");
    assert_mirrored(&cs, 0.0, 1e-9);
    // The overlap runs from the upper box's left side to the lower box's
    // right side (their tilts move those by 1e-4 m at most).
    for c in &cs {
        let ends = [upper.position.x - 0.5, lower.position.x + 0.5];
        assert!(ends.iter().any(|e| (c.point.x - e).abs() < 1e-3), "{:?}", c.point);
        assert!((c.point.y.abs() - 0.5).abs() < 1e-9, "{:?}", c.point);
    }
    // And over a range of tilts and of the rounding in y.
    for k in 0..40 {
        let t = k as f64;
        let (pa, pb) = (1e-4 * (t * 0.37).sin(), 1e-4 * (t * 0.61).cos());
        let (ya, yb) = (1e-16 * (t * 1.3).sin(), -1e-16 * (t * 0.7).cos());
        let lower = on_plane(0.0, ya, 0.5, pa);
        let upper = on_plane(0.525, yb, 1.4999, pb);
        assert_mirrored(&contacts(&lower, &upper, 0.01), 0.0, 1e-9);
    }
}

#[test]
fn boxes_side_by_side_touch_at_mirrored_corners() {
    // Recorded: two neighbours of a layer of the pyramid of base 100 (step
    // 15), tilted apart, their facing sides 2.5 cm apart: the corner points
    // came with GJK's closest point, 2.3e-5 m off the corner at one end.
    let left = recorded(
        [-5.719772586011764, -1.613891305376639e-13, 78.4058625263972],
        [
            8.252362326739072e-15,
            0.0011816088971207408,
            -7.26068430459506e-15,
            0.9999993018999634,
        ],
    );
    let right = recorded(
        [-4.6949017134060815, -1.571622070771267e-13, 78.40369419919813],
        [
            -4.783550190731074e-16,
            0.0009843216037140252,
            -1.4495597439767657e-14,
            0.9999995155553729,
        ],
    );
    let plane = -1.59e-13;
    assert_mirrored(&contacts(&left, &right, 0.1), plane, 1e-9);
    // Tilted towards each other: the two top edges are parallel, the
    // closest points a segment along them, and the manifold its two ends
    // (not GJK's point somewhere along it as well).
    for (tilt, gap) in [(2e-3, 0.01), (5e-3, 0.002), (1e-3, 0.03)] {
        let left = on_plane(0.0, 0.0, 0.5, tilt);
        let right = on_plane(1.0 + gap + 2.0 * 0.5 * tilt, 0.0, 0.5, -tilt);
        let cs = contacts(&left, &right, 0.1);
        assert_mirrored(&cs, 0.0, 1e-9);
        for c in &cs {
            assert!(
                (c.point.y.abs() - 0.5).abs() < 1e-9,
                "tilt {tilt}: {:?} in {cs:#?}",
                c.point
            );
        }
    }
    // Over gaps and tilts: the corners of the two boxes that face each other
    // meet within a hair of each other, and one point stands for both.
    for k in 0..60 {
        let t = k as f64;
        let gap = 0.001 + 0.03 * (0.5 + 0.5 * (t * 0.9).sin());
        let (pa, pb) = (2e-3 * (t * 0.37).sin(), 2e-3 * (t * 0.53).cos());
        let left = on_plane(0.0, 0.0, 0.5, pa);
        let right = on_plane(1.0 + gap, 0.0, 0.5 + 1e-3 * (t * 0.3).sin(), pb);
        let cs = contacts(&left, &right, 0.1);
        assert_mirrored(&cs, 0.0, 1e-9);
        for c in &cs {
            assert!(
                (c.point.y.abs() - 0.5).abs() < 1e-9,
                "gap {gap}: {:?} in {cs:#?}",
                c.point
            );
        }
    }
}
