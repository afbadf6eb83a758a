//! Narrow-phase tests against the brute-force oracles of `oracle`, and the
//! manifold, symmetry, feature-stability and dispatch properties.

use super::oracle::{boundary_distance, oshape, signed_distance, OShape};
use super::*;
use crate::math::{DQuat, DVec3};
use crate::mesh::icosphere_mesh;
use crate::pose::Pose;
use crate::shape::{Capsule, ConvexHull, Cuboid, HalfSpace, Shape, Sphere};
use proptest::prelude::*;

/// The shape tests' bounded shapes, then an icosahedral hull and the ground.
fn library() -> Vec<Shape> {
    let mut shapes = crate::shape::tests::shapes();
    shapes.push(
        ConvexHull::from_mesh(&icosphere_mesh(0.5, 0).unwrap())
            .unwrap()
            .into(),
    );
    shapes.push(HalfSpace::ground().into());
    shapes
}

fn is_poly(s: &Shape) -> bool {
    matches!(s, Shape::Cuboid(_) | Shape::ConvexHull(_))
}

fn pose(p: [f64; 3], r: [f64; 3]) -> Pose {
    Pose::new(
        DVec3::from_array(p),
        DQuat::from_euler(glam::EulerRot::ZYX, r[0], r[1], r[2]),
    )
    .unwrap()
}

pub(super) fn contacts(a: &Shape, pa: &Pose, b: &Shape, pb: &Pose, margin: f64) -> Vec<Contact> {
    let mut out = Vec::new();
    contact_shapes(a, pa, b, pb, margin, &mut out).unwrap();
    out
}

fn min_distance(cs: &[Contact]) -> Option<&Contact> {
    cs.iter().min_by(|x, y| x.distance.total_cmp(&y.distance))
}

/// Distance from `p` to the surface that produced a contact: the end sphere
/// for a capsule's end feature (the other end's contact may lie inside the
/// capsule's body when it dips steeply, by design), else the whole boundary.
fn side_distance(s: &Shape, pose: &Pose, o: &super::oracle::OShape, f: Feature, p: DVec3) -> f64 {
    if let (Shape::Capsule(c), crate::contact::SubFeature::Vertex(k)) = (s, f.sub) {
        let end = c.world_segment(pose)[k as usize];
        return ((p - end).length() - c.radius()).abs();
    }
    boundary_distance(o, p)
}

const MARGIN: f64 = 0.15;
const TOL: f64 = 1e-6;

/// Checks one configuration of one pair against the oracle; returns a
/// description of the first violation.
fn check_pair(a: &Shape, pa: &Pose, b: &Shape, pb: &Pose) -> Result<(), String> {
    let oa = oshape(a, pa);
    let ob = oshape(b, pb);
    let d = signed_distance(&oa, &ob);
    let cs = contacts(a, pa, b, pb, MARGIN);
    let both_poly = is_poly(a) && is_poly(b);
    // SAT (polytope pairs, capsule in polytope) prefers a face axis up to 5 %
    // deeper than the best axis.
    let capsule = |s: &Shape| matches!(s, Shape::Capsule(_));
    let biased = both_poly || (is_poly(a) && capsule(b)) || (capsule(a) && is_poly(b));
    let slack = if biased && d < 0.0 { 0.06 * d.abs() } else { 0.0 };
    let ctx = || {
        format!(
            "{} vs {}: oracle {d:.9}, contacts {cs:#?}",
            a.kind_name(),
            b.kind_name()
        )
    };
    if d > MARGIN + TOL && !cs.is_empty() {
        return Err(format!("reported beyond the margin: {}", ctx()));
    }
    for c in &cs {
        if (c.normal.length() - 1.0).abs() > 1e-9 {
            return Err(format!("normal not unit: {}", ctx()));
        }
        if c.distance > MARGIN + 1e-12 {
            return Err(format!("distance above margin: {}", ctx()));
        }
        if c.distance < d - slack - TOL {
            return Err(format!("contact deeper than the shapes overlap: {}", ctx()));
        }
        // The point lies between the surfaces.
        // A capsule lying along a face within PARALLEL_SIN gets contact points
        // up to r (1 - sqrt(1 - 0.05^2)) inside its surface (r = 0.25 here).
        let lim = c.distance.abs() + TOL + if c.kind == ContactKind::Smooth { 4e-4 } else { 0.0 };
        let (da, db) = (
            side_distance(a, pa, &oa, c.feature_a, c.point),
            side_distance(b, pb, &ob, c.feature_b, c.point),
        );
        // Only for shallow overlaps (a simulation's regime): when a core dives
        // deep under a polytope's edge the contact point is a stand-in.
        if d > -0.05 && (da > lim || db > lim) {
            return Err(format!(
                "point not between the surfaces ({} / {} for {:?}): {}",
                da,
                db,
                c.point,
                ctx()
            ));
        }
    }
    if d <= MARGIN - TOL {
        let Some(m) = min_distance(&cs) else {
            return Err(format!("nothing reported within the margin: {}", ctx()));
        };
        // 1e-5 x size: manifold reduction breaks depth ties (see clip.rs).
        if m.distance > d + slack + 2e-5 {
            return Err(format!("minimum distance too large: {}", ctx()));
        }
    }
    if let Some(m) = min_distance(&cs) {
        // The normal points from B to A: moving A along it separates.
        let delta = 1e-3;
        let moved = Pose::from_translation(pa.position + m.normal * delta);
        let moved = Pose {
            rotation: pa.rotation,
            ..moved
        };
        let d2 = signed_distance(&oshape(a, &moved), &ob);
        if d2 < d + 0.2 * delta - slack {
            return Err(format!(
                "normal does not point from B to A (d2 = {d2}): {}",
                ctx()
            ));
        }
        // Pushing A out by the reported depth makes the shapes touch.
        if m.distance < -1e-3 {
            let out_pose = Pose {
                position: pa.position - m.normal * m.distance,
                rotation: pa.rotation,
            };
            let d3 = signed_distance(&oshape(a, &out_pose), &ob);
            // The reported deepest point may be up to 1e-5 x size shallower
            // than the true one (clip.rs's depth tie rule, as above).
            let touches = |d: f64| (-TOL - 2e-5..=slack + 1e-6).contains(&d);
            if !touches(d3) {
                return Err(format!(
                    "push-out by the depth does not touch (d3 = {d3}): {}",
                    ctx()
                ));
            }
            // Touching: the deepest point reported there within the same
            // allowance (the tie rule can have kept a point up to 1e-5 x
            // size shallower than the deepest, which is now that much in).
            let touching = contacts(a, &out_pose, b, pb, slack + 1e-6);
            match min_distance(&touching) {
                Some(t) if touches(t.distance) => {}
                _ => {
                    let wide = contacts(a, &out_pose, b, pb, 0.1);
                    return Err(format!(
                        "touching pair not reported at zero distance: {touching:?} (margin 0.1: {wide:?}) {}",
                        ctx()
                    ));
                }
            }
        }
    }
    Ok(())
}

fn arb_pose(reach: f64) -> impl Strategy<Value = Pose> {
    (
        prop::array::uniform3(-reach..reach),
        prop::array::uniform3(-3.2f64..3.2),
    )
        .prop_map(|(p, r)| pose(p, r))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn every_pair_matches_the_oracle(pa in arb_pose(0.9), pb in arb_pose(0.2)) {
        let lib = library();
        for a in &lib {
            for b in &lib {
                if matches!((a, b), (Shape::HalfSpace(_), Shape::HalfSpace(_))) {
                    continue;
                }
                if let Err(e) = check_pair(a, &pa, b, &pb) {
                    prop_assert!(false, "{}", e);
                }
            }
        }
    }

    #[test]
    fn mirrored_pairs_give_flipped_contacts(pa in arb_pose(0.9), pb in arb_pose(0.2)) {
        let lib = library();
        for (i, a) in lib.iter().enumerate() {
            for b in &lib[i + 1..] {
                if std::mem::discriminant(a) == std::mem::discriminant(b) {
                    continue;
                }
                let ab = contacts(a, &pa, b, &pb, MARGIN);
                let ba = contacts(b, &pb, a, &pa, MARGIN);
                let flipped: Vec<Contact> = ab.iter().map(|c| c.flipped()).collect();
                prop_assert_eq!(ba, flipped);
            }
        }
    }
}

pub(super) fn unit_box() -> Shape {
    Cuboid::new(DVec3::splat(0.5)).unwrap().into()
}

/// Corners of the overlap rectangle of two unit boxes offset by (0.3, 0.3)
/// horizontally and resting with 1 cm of overlap, in any yaw and position.
#[test]
fn box_resting_on_box_gives_the_overlap_rectangle() {
    let b = unit_box();
    for (yaw, shift) in [
        (0.0, DVec3::ZERO),
        (0.7, DVec3::new(3.0, -2.0, 1.0)),
        (-2.1, DVec3::new(-1.0, 0.5, -4.0)),
    ] {
        let frame = Pose::new(shift, DQuat::from_rotation_z(yaw)).unwrap();
        let pa = frame.mul_pose(&Pose::from_translation(DVec3::new(0.3, 0.3, 0.99)));
        let pb = frame;
        let cs = contacts(&b, &pa, &b, &pb, 0.0);
        assert_eq!(cs.len(), 4, "{cs:#?}");
        let mut expected = vec![];
        for x in [-0.2, 0.5] {
            for y in [-0.2, 0.5] {
                expected.push(frame.transform_point(DVec3::new(x, y, 0.495)));
            }
        }
        for c in &cs {
            assert!((c.distance + 0.01).abs() < 1e-12, "{c:?}");
            assert!((c.normal - frame.transform_vector(DVec3::Z)).length() < 1e-12);
            assert!(expected.iter().any(|e| (*e - c.point).length() < 1e-12), "{c:?}");
            assert_eq!(c.kind, ContactKind::FaceFace);
        }
        // The manifold is the same seen from the other box.
        let ba = contacts(&b, &pb, &b, &pa, 0.0);
        assert_eq!(ba.len(), 4);
        for c in &ba {
            assert!((c.normal + frame.transform_vector(DVec3::Z)).length() < 1e-12);
            assert!(expected.iter().any(|e| (*e - c.point).length() < 1e-12));
        }
    }
}

#[test]
fn box_on_half_space_gives_its_corners() {
    let b: Shape = Cuboid::new(DVec3::new(0.5, 0.3, 0.2)).unwrap().into();
    let ground: Shape = HalfSpace::ground().into();
    let cs = contacts(
        &b,
        &Pose::from_translation(DVec3::new(1.0, 2.0, 0.19)),
        &ground,
        &Pose::IDENTITY,
        0.0,
    );
    assert_eq!(cs.len(), 4);
    for c in &cs {
        assert!((c.distance + 0.01).abs() < 1e-12);
        assert_eq!(c.normal, DVec3::Z);
        assert!(
            ((c.point.x - 1.0).abs() - 0.5).abs() < 1e-12 && ((c.point.y - 2.0).abs() - 0.3).abs() < 1e-12
        );
        assert!((c.point.z + 0.005).abs() < 1e-12);
    }
}

/// A box tilted about x by 0.3 rad: only its two lowest corners (the bottom
/// edge along x) are within a 1 cm margin, at the heights z = c - (h_y sin + h_z cos).
#[test]
fn tilted_box_on_half_space_gives_the_lowest_corners() {
    let h = DVec3::new(0.5, 0.3, 0.2);
    let b: Shape = Cuboid::new(h).unwrap().into();
    let ground: Shape = HalfSpace::ground().into();
    let th: f64 = 0.3;
    let low = h.y * th.sin() + h.z * th.cos();
    let centre_z = low - 0.004; // 4 mm deep
    let pa = Pose::new(DVec3::new(0.0, 0.0, centre_z), DQuat::from_rotation_x(th)).unwrap();
    let cs = contacts(&b, &pa, &ground, &Pose::IDENTITY, 0.01);
    assert_eq!(cs.len(), 2, "{cs:#?}");
    let second = h.z * th.cos() - h.y * th.sin(); // next corner pair is higher
    assert!(centre_z - second > 0.01);
    for c in &cs {
        assert!((c.distance + 0.004).abs() < 1e-12);
        let corner = c.point + DVec3::Z * (0.5 * c.distance);
        let local = pa.inverse_transform_point(corner);
        assert!(((local.abs() - h).length()) < 1e-12, "not a corner: {local}");
        assert!(local.y < 0.0 && local.z < 0.0);
    }
}

#[test]
fn capsule_lying_on_box_and_capsule_gives_two_contacts() {
    let cap: Shape = Capsule::new(0.1, 0.3).unwrap().into();
    let lying = Pose::new(
        DVec3::new(0.05, 0.0, 0.5 + 0.099),
        DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2),
    )
    .unwrap();
    let cs = contacts(&cap, &lying, &unit_box(), &Pose::IDENTITY, 0.0);
    assert_eq!(cs.len(), 2, "{cs:#?}");
    for c in &cs {
        assert!((c.distance + 0.001).abs() < 1e-12);
        assert!((c.normal - DVec3::Z).length() < 1e-12);
        assert!(((c.point.x - 0.05).abs() - 0.3).abs() < 1e-12);
    }
    let below = Pose::new(DVec3::new(0.0, 0.0, 0.0), lying.rotation).unwrap();
    let cs = contacts(
        &cap,
        &Pose {
            position: DVec3::new(0.1, 0.0, 0.19),
            ..lying
        },
        &cap,
        &below,
        0.0,
    );
    assert_eq!(cs.len(), 2, "{cs:#?}");
    for c in &cs {
        assert!((c.distance + 0.01).abs() < 1e-12);
        assert!((c.normal - DVec3::Z).length() < 1e-12);
    }
}

/// Face contacts keep their feature ids under a 1e-6 perturbation.
#[test]
fn feature_ids_are_stable_under_tiny_motion() {
    let lib = library();
    let resting = [
        (1usize, 1usize, DVec3::new(0.1, 0.05, 0.395)),
        (1, 5, DVec3::new(0.0, 0.0, 0.195)),
        (3, 3, DVec3::new(0.05, 0.02, 0.595)),
        (3, 1, DVec3::new(0.1, 0.0, 0.495)),
        (2, 1, DVec3::new(0.0, 0.0, 0.2 + 0.25 + 0.4 - 0.005)),
    ];
    for (ia, ib, p) in resting {
        let (a, b) = (&lib[ia], &lib[ib]);
        let base = Pose::from_translation(p);
        let ids = |pa: &Pose| -> Vec<(Feature, Feature)> {
            contacts(a, pa, b, &Pose::IDENTITY, 0.01)
                .iter()
                .map(|c| (c.feature_a, c.feature_b))
                .collect()
        };
        let before = ids(&base);
        assert!(!before.is_empty(), "{} on {}", a.kind_name(), b.kind_name());
        for k in 0..6 {
            let mut dp = DVec3::ZERO;
            dp[k % 3] = if k < 3 { 1e-6 } else { -1e-6 };
            let q = DQuat::from_scaled_axis(DVec3::new(dp.z, dp.x, dp.y));
            let moved = Pose::new(p + dp, q).unwrap();
            assert_eq!(ids(&moved), before, "{} on {}", a.kind_name(), b.kind_name());
        }
    }
}

#[test]
fn dispatch_covers_every_pair_but_half_space_pairs() {
    let lib = library();
    for a in &lib {
        for b in &lib {
            let mut out = Vec::new();
            let r = contact_shapes(
                a,
                &Pose::IDENTITY,
                b,
                &Pose::from_translation(DVec3::X),
                0.1,
                &mut out,
            );
            if matches!((a, b), (Shape::HalfSpace(_), Shape::HalfSpace(_))) {
                assert_eq!(
                    r,
                    Err(NarrowError::Unsupported {
                        a: "half_space",
                        b: "half_space"
                    })
                );
            } else {
                assert_eq!(r, Ok(()), "{} vs {}", a.kind_name(), b.kind_name());
            }
        }
    }
    let mut out = Vec::new();
    let s = &lib[0];
    for m in [-1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            contact_shapes(s, &Pose::IDENTITY, s, &Pose::IDENTITY, m, &mut out),
            Err(NarrowError::BadMargin(_))
        ));
    }
}

/// Sphere-sphere against the closed form, including the exact contact point.
#[test]
fn sphere_sphere_closed_form() {
    let a: Shape = Sphere::new(0.3).unwrap().into();
    let b: Shape = Sphere::new(0.5).unwrap().into();
    let pa = Pose::from_translation(DVec3::new(0.6, 0.0, 0.0));
    let cs = contacts(&a, &pa, &b, &Pose::IDENTITY, 0.0);
    assert_eq!(cs.len(), 1);
    assert!((cs[0].distance + 0.2).abs() < 1e-15);
    assert_eq!(cs[0].normal, DVec3::X);
    // Surface points 0.3 and 0.5 on x; midpoint 0.4.
    assert!((cs[0].point - DVec3::new(0.4, 0.0, 0.0)).length() < 1e-15);
}

/// A unit box turned 45 degrees on a larger box: the overlap is an octagon
/// (8 clipped points), reduced to 4 that lie on it, all at the same depth.
#[test]
fn turned_box_on_box_is_reduced_to_four_points_of_the_octagon() {
    let small = unit_box();
    let big: Shape = Cuboid::new(DVec3::new(0.6, 0.6, 0.5)).unwrap().into();
    let pa = Pose::new(
        DVec3::new(0.0, 0.0, 0.995),
        DQuat::from_rotation_z(std::f64::consts::FRAC_PI_4),
    )
    .unwrap();
    let cs = contacts(&small, &pa, &big, &Pose::IDENTITY, 0.0);
    assert_eq!(cs.len(), 4, "{cs:#?}");
    for c in &cs {
        assert!((c.distance + 0.005).abs() < 1e-12);
        // On the boundary of the octagon: inside both squares, on the edge of one.
        let p = c.point;
        let in_big = p.x.abs() <= 0.6 + 1e-12 && p.y.abs() <= 0.6 + 1e-12;
        let diamond = (p.x.abs() + p.y.abs()) / std::f64::consts::SQRT_2; // rotated square's "radius"
        let in_small = diamond <= 0.5 + 1e-12;
        let on_edge = (p.x.abs() - 0.6).abs() < 1e-12
            || (p.y.abs() - 0.6).abs() < 1e-12
            || (diamond - 0.5).abs() < 1e-12;
        assert!(in_big && in_small && on_edge, "{p}");
    }
    // The four points span the octagon rather than bunching on one side.
    let centroid = cs.iter().map(|c| c.point).sum::<DVec3>() / 4.0;
    assert!(centroid.truncate().length() < 0.2, "{centroid}");
}

/// Same input, same output, bit for bit (no hidden state, no hashing).
#[test]
fn results_are_deterministic() {
    let lib = library();
    let pa = pose([0.3, -0.2, 0.35], [0.4, -0.3, 1.1]);
    let pb = pose([0.0, 0.1, -0.1], [-0.2, 0.5, 0.3]);
    for a in &lib {
        for b in &lib {
            if matches!((a, b), (Shape::HalfSpace(_), Shape::HalfSpace(_))) {
                continue;
            }
            let first = contacts(a, &pa, b, &pb, MARGIN);
            let second = contacts(a, &pa, b, &pb, MARGIN);
            let bits = |cs: &[Contact]| -> Vec<u64> {
                cs.iter()
                    .flat_map(|c| {
                        [
                            c.point.x, c.point.y, c.point.z, c.normal.x, c.normal.y, c.normal.z, c.distance,
                        ]
                    })
                    .map(f64::to_bits)
                    .collect()
            };
            assert_eq!(bits(&first), bits(&second));
            assert_eq!(first, second);
        }
    }
}

/// Two polytopes (boxes, a box and a hull, two hulls) whose manifold is one
/// point (edge against edge, or two apart solids' closest points) also hold
/// every vertex of either solid that lies within the margin of the other:
/// a contact next to the vertex, no farther apart than the vertex is from
/// the other solid (brute force: the oracle's distance to its boundary).
/// Why: a manifold holds for a whole step, and a turning box brings such a
/// corner on while its edge still touches.
#[test]
fn a_one_point_polytope_manifold_holds_the_vertices_within_the_margin() {
    let small: Shape = Cuboid::new(DVec3::new(0.5, 0.3, 0.2)).unwrap().into();
    let large: Shape = Cuboid::new(DVec3::new(0.4, 0.6, 0.35)).unwrap().into();
    let hull: Shape = ConvexHull::from_mesh(&icosphere_mesh(0.5, 0).unwrap())
        .unwrap()
        .into();
    let margin = 0.15;
    use tumble_testkit::{RandomSource, SplitMix64};
    let mut rng = SplitMix64(0x2545_f491_4f6c_dd1d);
    let mut next = move || rng.range(-1.0, 1.0);
    for (a, b) in [(&small, &large), (&small, &hull), (&hull, &large), (&hull, &hull)] {
        let (mut one_point, mut held) = (0, 0);
        for _ in 0..3000 {
            let pa = pose([0.0; 3], [3.2 * next(), 3.2 * next(), 3.2 * next()]);
            let dir = DVec3::new(next(), next(), next()).normalize_or(DVec3::X);
            let pb = pose(
                (dir * (0.6 + 0.5 * next().abs())).to_array(),
                [3.2 * next(), 3.2 * next(), 3.2 * next()],
            );
            let cs = contacts(a, &pa, b, &pb, margin);
            match cs.first() {
                Some(c) if c.kind != ContactKind::FaceFace => one_point += 1,
                _ => continue,
            }
            let (oa, ob) = (oshape(a, &pa), oshape(b, &pb));
            for (p, q) in [(&oa, &ob), (&ob, &oa)] {
                let OShape::Poly { verts, .. } = p else {
                    unreachable!()
                };
                for &corner in verts {
                    let OShape::Poly { faces, .. } = q else {
                        unreachable!()
                    };
                    if faces.iter().all(|(n, d, _)| n.dot(corner) - d <= 1e-9) {
                        continue; // inside the other
                    }
                    let distance = boundary_distance(q, corner);
                    if distance > margin {
                        continue;
                    }
                    // The held point is the midpoint of the vertex and its
                    // nearest point, within `distance / 2` of the vertex.
                    let near = 0.05 * 0.6 + distance / 2.0;
                    assert!(
                        cs.iter()
                            .any(|c| (c.point - corner).length() <= near + 1e-9
                                && c.distance <= distance + 1e-9),
                        "vertex {corner:?} {distance} m from the other solid is not held: {:?}",
                        cs.iter()
                            .map(|c| (c.point, c.distance, c.kind))
                            .collect::<Vec<_>>()
                    );
                    held += 1;
                }
            }
        }
        // The draw reaches the case under test often enough to mean something.
        assert!(
            one_point > 100 && held > 100,
            "{one_point} one-point manifolds, {held} vertices"
        );
    }
}

/// A capsule slanted over a box face, its lower end touching, gets a second,
/// speculative point under its upper part: on the capsule's surface (the
/// cylinder, r / cos(slant) below the core), with the gap of that surface
/// point to the face, and none once the upper part is beyond the margin.
/// Why: a manifold holds for the whole step, and a slanted limb turning
/// down onto the ground sank its upper end 2 cm in with the lower end alone.
#[test]
fn a_slanted_capsule_holds_its_upper_end_within_the_margin() {
    let ground: Shape = Cuboid::new(DVec3::new(1.0, 1.0, 0.5)).unwrap().into();
    let (r, half) = (0.1, 0.3);
    let capsule: Shape = Capsule::new(r, half).unwrap().into();
    for (slant, margin, expect_two) in [(0.1, 0.1, true), (0.1, 0.05, false), (-0.15, 0.2, true)] {
        // Core along x turned by `slant` about y, its lower end r above the top.
        let rot = DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2 + slant);
        let axis = rot * DVec3::Z;
        let lower_z = 0.5 + r;
        let centre = DVec3::new(0.0, 0.0, lower_z + half * axis.z.abs());
        let pc = Pose::new(centre, rot).unwrap();
        let cs = contacts(&capsule, &pc, &ground, &Pose::IDENTITY, margin);
        let [s0, s1] = match &capsule {
            Shape::Capsule(c) => c.world_segment(&pc),
            _ => unreachable!(),
        };
        let upper = if s0.z > s1.z { s0 } else { s1 };
        let sink = r / (1.0 - axis.z * axis.z).sqrt();
        let gap = upper.z - 0.5 - sink;
        assert_eq!(
            cs.len(),
            if expect_two { 2 } else { 1 },
            "slant {slant}, margin {margin}: {cs:#?}"
        );
        assert!(cs[0].distance.abs() < 1e-9, "the lower end touches: {cs:#?}");
        if expect_two {
            let c = &cs[1];
            assert!((c.distance - gap).abs() < 1e-9, "{} against {gap}", c.distance);
            // The capsule's surface point: the contact point raised by half
            // the gap, at distance r from the core.
            let surface = c.point + c.normal * (0.5 * c.distance);
            let (_, _, on_core, _) = super::geometry::closest_points_segments(s0, s1, surface, surface);
            assert!(
                ((surface - on_core).length() - r).abs() < 1e-9,
                "not on the capsule"
            );
            assert!((surface.z - (0.5 + gap)).abs() < 1e-9);
        }
    }
}

/// Two boxes of random sizes nearly face to face, apart by up to the margin
/// and turned a little: the pairs whose GJK check `axis_manifold` skips (the
/// points already pin the distance) are most of them.
fn near_boxes() -> impl Strategy<Value = (Cuboid, Cuboid, Pose, f64)> {
    (
        prop::array::uniform3(0.1f64..1.0),
        prop::array::uniform3(0.1f64..1.0),
        prop::array::uniform2(-0.6f64..0.6),
        -0.02f64..0.2,
        prop::array::uniform3(-0.05f64..0.05),
    )
        .prop_map(|(ha, hb, slide, gap, turn)| {
            let (ha, hb) = (DVec3::from_array(ha), DVec3::from_array(hb));
            let z = ha.z + hb.z + gap;
            (
                Cuboid::new(ha).unwrap(),
                Cuboid::new(hb).unwrap(),
                pose([slide[0], slide[1], z], turn),
                gap,
            )
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]
    /// What GJK's check in `axis_manifold` decides for apart boxes holds of
    /// the contacts made, whether or not the check ran: nothing when GJK's
    /// distance is beyond the margin, and otherwise points no farther
    /// apart than that distance (or GJK's one closest point pair).
    #[test]
    fn apart_boxes_keep_what_the_gjk_check_keeps((a, b, pb, _gap) in near_boxes()) {
        use super::gjk::{gjk_distance, PolytopeSupport};
        let pa = Pose::IDENTITY;
        let margin = MARGIN;
        let mut out = Vec::new();
        contact_cuboid_cuboid::contact_cuboid_cuboid(&a, &pa, &b, &pb, margin, &mut out);
        let scale = a.half_extents().max_element().max(b.half_extents().max_element());
        fn support<'a>(c: &'a Cuboid, p: &Pose) -> PolytopeSupport<'a, Cuboid> {
            PolytopeSupport {
                poly: c,
                rot: crate::math::DMat3::from_quat(p.rotation),
                trans: p.position,
            }
        }
        let (sa, sb) = (support(&a, &pa), support(&b, &pb));
        let g = gjk_distance(&sa, &sb, scale);
        if g.overlap || g.distance <= 1e-9 {
            return Ok(());
        }
        if g.distance > margin + 1e-9 * scale {
            prop_assert!(out.is_empty(), "{} beyond the margin, yet {:?}", g.distance, out);
        } else if g.distance < margin - 1e-9 * scale {
            prop_assert!(!out.is_empty(), "{} within the margin, yet nothing", g.distance);
            let got = out.iter().map(|c| c.distance).fold(f64::INFINITY, f64::min);
            // A manifold of one point may trade it for a corner as near to
            // touching within `SAME_DISTANCE` (`hold_near_vertices`).
            let faces = out.iter().any(|c| c.kind == ContactKind::FaceFace);
            let slack = if faces { 1e-9 } else { super::contact_polytope_polytope::SAME_DISTANCE } * scale;
            prop_assert!(got <= g.distance + slack, "nearest point {} against GJK's {}", got, g.distance);
            prop_assert!(got >= g.distance - 1e-9 * scale, "nearest point {} nearer than GJK's {}", got, g.distance);
        }
    }
}

/// A capsule of random size and direction near a random box: its lowest
/// core point along a face normal of the box at `gap` beyond its radius
/// from that face's plane, slid along the face up to past its edges.
fn capsules_near_boxes() -> impl Strategy<Value = (Capsule, Pose, Cuboid)> {
    (
        prop::array::uniform3(0.1f64..1.0),
        (0.02f64..0.3, 0.05f64..0.8),
        (0usize..6, prop::array::uniform2(-1.3f64..1.3)),
        -0.05f64..0.3,
        prop::array::uniform3(-3.2f64..3.2),
    )
        .prop_map(|(h, (radius, half), (face, slide), gap, turn)| {
            let h = DVec3::from_array(h);
            let capsule = Capsule::new(radius, half).unwrap();
            let (axis, sign) = (face / 2, if face % 2 == 0 { 1.0 } else { -1.0 });
            let normal = DVec3::AXES[axis] * sign;
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let mut at = normal * h[axis];
            at[u] += slide[0] * h[u];
            at[v] += slide[1] * h[v];
            let turned = pose([0.0; 3], turn);
            let [s0, s1] = capsule.world_segment(&turned);
            let lowest = s0.dot(normal).min(s1.dot(normal));
            let centre = at + normal * (radius + gap - lowest);
            let p = Pose::new(centre, turned.rotation).unwrap();
            (capsule, p, Cuboid::new(h).unwrap())
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(600))]
    /// A capsule near a box gets a contact exactly when GJK puts its core
    /// within its radius plus the margin of the box, whether or not the
    /// pair was found apart along the box's axes first (the check that
    /// skips GJK): nothing beyond, something within.
    #[test]
    fn capsules_near_boxes_keep_what_gjk_finds((capsule, pc, cuboid) in capsules_near_boxes()) {
        use super::gjk::{gjk_distance, PolytopeSupport, SegmentSupport};
        let margin = 0.05;
        let mut out = Vec::new();
        contact_segment_polytope::contact_capsule_polytope(&capsule, &pc, &cuboid, &Pose::IDENTITY, margin, &mut out);
        let scale = cuboid.half_extents().max_element().max(capsule.radius());
        let core = SegmentSupport(capsule.world_segment(&pc));
        let poly = PolytopeSupport { poly: &cuboid, rot: crate::math::DMat3::IDENTITY, trans: DVec3::ZERO };
        let g = gjk_distance(&core, &poly, scale);
        if g.overlap {
            return Ok(());
        }
        let gap = g.distance - capsule.radius();
        if gap > margin + 1e-9 * scale {
            prop_assert!(out.is_empty(), "{gap} beyond the margin, yet {out:?}");
        } else if gap < margin - 1e-9 * scale {
            prop_assert!(!out.is_empty(), "{gap} within the margin, yet nothing");
        }
    }
}

/// The corners of a rock (a hull of 15 vertices) from the falling pile of
/// boxes and rocks (`a_falling_pile_of_boxes_and_rocks_never_gains_energy`).
const ROCK: [[f64; 3]; 15] = [
    [-0.03543428521579231, 0.025928594449200495, -0.05307212290443755],
    [-0.08629023679856074, 0.038501721426860744, 0.01867977132152741],
    [0.04579265831581005, 0.1219996885946937, 0.04237005794668525],
    [0.10564455732629438, -0.01558714599591725, 0.12507350896423783],
    [-0.06074880258907912, -0.07561937989310022, -0.08141977313676103],
    [-0.06606227034617203, 0.016930367797264027, 0.0405251658476205],
    [0.17771482999064947, 0.04648266936991431, 0.042438966168714086],
    [-0.00595965450063923, -0.06296213630527597, 0.030990151152421277],
    [-0.03760391103709442, 0.12402460743856326, 0.042203437332908135],
    [0.02170124376176235, -0.09214479101732594, -0.03319457309746914],
    [-0.06288858576973584, 0.07443209275072885, 0.04641568780843937],
    [0.03393021202790639, 0.048978736050887955, -0.03890472517309007],
    [0.10396829197380877, -0.007568008916610479, -0.05644061368844257],
    [-0.12038140476622798, -0.04466939104724299, -0.08353684868211153],
    [-0.11949693686535601, -0.0040371197375208044, -0.04923179216856509],
];

/// Two such rocks posed where they met in that pile, overlapping by about
/// 1.6 mm: A's best face won on the edge pair's separation by the SAT's
/// bias only, and it clips B's incident face to nothing (the rocks meet at
/// an edge of that face and one of B's, off the face). No contact came out,
/// and the rocks sank 3-6 mm into each other over the next steps. The edge
/// pair is the contact now: one at least, as deep as the oracle's signed
/// distance within the 5 % by which the SAT prefers a face.
#[test]
fn a_face_that_clips_to_nothing_gives_the_edge_pair() {
    let rock: Shape = ConvexHull::from_points(&ROCK.map(DVec3::from_array))
        .unwrap()
        .into();
    let posed = |p: [f64; 3], q: [f64; 4]| Pose::new(DVec3::from_array(p), DQuat::from_array(q)).unwrap();
    let pa = posed(
        [-0.06377796751392219, -0.03646340220630654, 0.133382202156154],
        [
            -0.6074670692896281,
            -0.5112195790872701,
            0.12730648869349537,
            0.5945009332398374,
        ],
    );
    let pb = posed(
        [-0.05703121775975513, 0.11965064988265767, 0.3000183555913724],
        [
            -0.04169674520219047,
            -0.49058283522829804,
            0.41263712609148656,
            0.7663683614227998,
        ],
    );
    let depth = signed_distance(&oshape(&rock, &pa), &oshape(&rock, &pb));
    assert!(depth < -1e-3, "the rocks overlap: {depth}");
    let cs = contacts(&rock, &pa, &rock, &pb, 0.005);
    let deepest = min_distance(&cs).expect("overlapping rocks get a contact");
    assert!(
        (deepest.distance - depth).abs() <= 0.05 * depth.abs(),
        "contact {} m deep, the oracle's {depth}",
        deepest.distance
    );
}
