//! Mesh contacts against brute force and against the primitive routines.

use super::*;
use crate::mesh::{box_mesh, icosphere_mesh};
use crate::pose::Pose;
use crate::shape::{Capsule, ConvexHull, Cuboid, HalfSpace, MeshShape, Shape, Sphere};
use crate::triangle::triangle_distance;
use crate::DQuat;

fn mesh_box(h: f64) -> MeshShape {
    MeshShape::new(box_mesh(DVec3::splat(h)).unwrap()).unwrap()
}

fn min_distance(out: &[Contact]) -> f64 {
    out.iter().map(|c| c.distance).fold(f64::INFINITY, f64::min)
}

/// Brute-force minimum distance between two meshes (all triangle pairs).
fn brute_distance(a: &MeshShape, pa: &Pose, b: &MeshShape, pb: &Pose) -> f64 {
    let mut best = f64::INFINITY;
    for ta in 0..a.mesh().triangles().len() {
        let wa = a.mesh().triangle(ta).map(|v| pa.transform_point(v));
        for tb in 0..b.mesh().triangles().len() {
            let wb = b.mesh().triangle(tb).map(|v| pb.transform_point(v));
            best = best.min(triangle_distance(&wa, &wb).distance);
        }
    }
    best
}

/// The contacts of mesh A against mesh B within `margin` (the dispatch
/// every world pair goes through).
fn mesh_contacts(a: &MeshShape, pa: &Pose, b: &MeshShape, pb: &Pose, margin: f64) -> Vec<Contact> {
    let mut out = Vec::new();
    contact_shapes(
        &Shape::Mesh(a.clone()),
        pa,
        &Shape::Mesh(b.clone()),
        pb,
        margin,
        &mut out,
    )
    .unwrap();
    out
}

#[test]
fn mesh_cube_on_box_matches_the_primitive_manifold() {
    let gap = 0.003;
    let ground = Shape::Cuboid(Cuboid::new(DVec3::new(2.0, 2.0, 0.5)).unwrap());
    let ground_pose = Pose::from_translation(DVec3::new(0.0, 0.0, -0.5));
    let pose = Pose::from_translation(DVec3::new(0.1, -0.2, 0.5 + gap));
    let mut mesh_out = Vec::new();
    contact_shapes(
        &Shape::Mesh(mesh_box(0.5)),
        &pose,
        &ground,
        &ground_pose,
        0.01,
        &mut mesh_out,
    )
    .unwrap();
    let mut prim_out = Vec::new();
    let cube = Shape::Cuboid(Cuboid::new(DVec3::splat(0.5)).unwrap());
    contact_shapes(&cube, &pose, &ground, &ground_pose, 0.01, &mut prim_out).unwrap();
    assert!((min_distance(&mesh_out) - gap).abs() < 1e-12);
    assert!((min_distance(&prim_out) - gap).abs() < 1e-12);
    // After merging, the four bottom corners remain (one contact each).
    let corners: Vec<_> = mesh_out
        .iter()
        .filter(|c| (c.distance - gap).abs() < 1e-9)
        .collect();
    assert_eq!(corners.len(), 4, "{mesh_out:#?}");
    for c in &mesh_out {
        assert!(
            (c.normal - DVec3::Z).length() < 1e-12,
            "normal from the ground (B) up to the cube (A)"
        );
    }
}

#[test]
fn mesh_mesh_distance_matches_brute_force() {
    let a = MeshShape::new(icosphere_mesh(0.5, 1).unwrap()).unwrap();
    let b = mesh_box(0.3);
    for k in 0..20 {
        let t = k as f64 * 0.37;
        let pa = Pose::new(
            DVec3::ZERO,
            DQuat::from_euler(glam::EulerRot::XYZ, t, 0.5 * t, 0.2),
        )
        .unwrap();
        let dir = DVec3::new(t.cos(), t.sin(), 0.3 * (2.0 * t).sin()).normalize();
        let pb = Pose::new(dir * 0.82, DQuat::from_euler(glam::EulerRot::ZYX, 0.3 * t, t, -t)).unwrap();
        let truth = brute_distance(&a, &pa, &b, &pb);
        let margin = 0.05;
        let out = mesh_contacts(&a, &pa, &b, &pb, margin);
        if truth > margin {
            assert!(out.iter().all(|c| c.distance <= margin));
            continue;
        }
        assert!(
            !out.is_empty(),
            "pose {k}: distance {truth} within the margin but no contact"
        );
        if truth > 0.0 {
            // No contact claims to be closer than the true distance, and the
            // closest pair is found (vertex-face or edge-edge realises it).
            assert!(min_distance(&out) >= truth - 1e-9, "pose {k}");
            assert!(
                min_distance(&out) <= truth + 1e-9,
                "pose {k}: {} vs {truth}",
                min_distance(&out)
            );
        }
        for c in &out {
            assert!((c.normal.length() - 1.0).abs() < 1e-9);
        }
    }
}

/// The closest points of two separated convex meshes are found whatever
/// features they lie on: at random orientations (boxes against boxes and
/// against a coarse ball, brought to a random gap within the margin along
/// a random direction), the smallest contact distance is the brute-force
/// distance over all triangle pairs when the closest features are a vertex
/// and a face or two edges, and otherwise (a corner pointing at an edge or
/// a corner) the gap's component along the nearest face normal of the two
/// features, which is at most the gap and at least half of it
/// (`triangle::tri_vertex_edge`, `FACE_AXIS_COS`); every such contact's
/// normal is a face normal of one of the meshes. No contact claims less
/// than half the true distance. Without vertex/edge and vertex/vertex
/// contacts the smallest distance reported in those poses is that of
/// farther features.
#[test]
fn the_closest_features_of_two_convex_meshes_are_found_at_random_poses() {
    let boxy = MeshShape::new(box_mesh(DVec3::new(0.3, 0.2, 0.1)).unwrap()).unwrap();
    let kinds = closest_features_are_found(&Shape::Mesh(boxy.clone()), &boxy, 23);
    every_kind_met(&kinds, &["VertexVertex"]);
}

/// The same for a box or a convex hull against a mesh (the polytope-mesh
/// routine, which fans the polytope's faces into triangles): A is a
/// `Cuboid` of the mesh box's size, or the convex hull of the mesh ball,
/// and the oracle is the brute-force distance from the same surface as a
/// mesh.
#[test]
fn the_closest_features_of_a_polytope_and_a_mesh_are_found_at_random_poses() {
    let half = DVec3::new(0.3, 0.2, 0.1);
    let boxy = MeshShape::new(box_mesh(half).unwrap()).unwrap();
    let mut kinds = closest_features_are_found(&Shape::Cuboid(Cuboid::new(half).unwrap()), &boxy, 29);
    let ball_mesh = icosphere_mesh(0.25, 1).unwrap();
    let hull = ConvexHull::from_mesh(&ball_mesh).unwrap();
    let ball = MeshShape::new(ball_mesh).unwrap();
    for (kind, n) in closest_features_are_found(&Shape::ConvexHull(hull), &ball, 31) {
        *kinds.entry(kind).or_insert(0) += n;
    }
    // A corner closest to a corner was met in none of these 600 poses
    // (once in the mesh-mesh test's 300):
    // `a_corner_pointing_at_a_corner_gives_a_vertex_vertex_contact` has it.
    every_kind_met(&kinds, &[]);
}

/// 300 random poses of `a` (whose surface is `a_mesh`) against a mesh box
/// and a coarse mesh ball (`the_closest_features_of_two_convex_meshes_are_found_at_random_poses`).
fn closest_features_are_found(
    a: &Shape,
    a_mesh: &MeshShape,
    seed: u64,
) -> std::collections::BTreeMap<String, usize> {
    use tumble_testkit::RandomSource;
    let boxy = MeshShape::new(box_mesh(DVec3::new(0.3, 0.2, 0.1)).unwrap()).unwrap();
    let ball = MeshShape::new(icosphere_mesh(0.25, 1).unwrap()).unwrap();
    let mut rng = tumble_testkit::SplitMix64(seed);
    let margin = 0.02;
    let mut kinds = std::collections::BTreeMap::new();
    let face_normals = |m: &MeshShape, pose: &Pose| -> Vec<DVec3> {
        (0..m.mesh().triangles().len())
            .map(|t| (pose.rotation * m.mesh().triangle_normal_scaled(t)).normalize())
            .collect()
    };
    for case in 0..300 {
        let b = if case % 3 == 2 { &ball } else { &boxy };
        let pa = Pose::new(DVec3::ZERO, random_turn(&mut rng)).unwrap();
        let turn_b = random_turn(&mut rng);
        let dir = random_turn(&mut rng) * DVec3::X;
        let target = rng.range(1e-4, margin);
        // The distance changes by at most the move along `dir`, so each
        // step keeps B apart and converges on the target gap.
        let mut at = dir * 1.0;
        for _ in 0..30 {
            let d = brute_distance(a_mesh, &pa, b, &Pose::new(at, turn_b).unwrap());
            at -= dir * (d - target);
        }
        let pb = Pose::new(at, turn_b).unwrap();
        let truth = brute_distance(a_mesh, &pa, b, &pb);
        assert!(truth > 0.0 && truth < margin, "case {case}: {truth}");
        let mut out = Vec::new();
        contact_shapes(a, &pa, &Shape::Mesh(b.clone()), &pb, margin, &mut out).unwrap();
        let closest = out
            .iter()
            .min_by(|x, y| x.distance.total_cmp(&y.distance))
            .unwrap_or_else(|| panic!("case {case}: no contact at {truth}"));
        let corner = |k: ContactKind| {
            matches!(
                k,
                ContactKind::VertexEdge | ContactKind::EdgeVertex | ContactKind::VertexVertex
            )
        };
        if corner(closest.kind) {
            assert!(
                closest.distance <= truth + 1e-12 && closest.distance >= 0.5 * truth,
                "case {case}: closest contact {closest:?}, true distance {truth}"
            );
        } else {
            assert!(
                (closest.distance - truth).abs() <= 1e-9,
                "case {case}: closest contact {closest:?}, true distance {truth}"
            );
        }
        *kinds.entry(format!("{:?}", closest.kind)).or_insert(0) += 1;
        let faces: Vec<DVec3> = face_normals(a_mesh, &pa)
            .into_iter()
            .map(|n| -n)
            .chain(face_normals(b, &pb))
            .collect();
        for c in &out {
            assert!(
                (c.normal.length() - 1.0).abs() < 1e-9 && c.distance >= 0.5 * truth - 1e-12,
                "case {case}: {c:?}"
            );
            if corner(c.kind) {
                assert!(
                    faces.iter().any(|f| (*f - c.normal).length() < 1e-9),
                    "case {case}: {c:?} not along a face normal"
                );
            }
        }
    }
    kinds
}

/// Every kind of closest pair was met (of 300 mesh boxes against meshes:
/// about 290 vertex/face, face/vertex and edge/edge, 11 vertex/edge and
/// edge/vertex, 1 vertex/vertex), and the kinds in `rare` too.
fn every_kind_met(kinds: &std::collections::BTreeMap<String, usize>, rare: &[&str]) {
    for &kind in ["VertexFace", "FaceVertex", "EdgeEdge", "VertexEdge", "EdgeVertex"]
        .iter()
        .chain(rare)
    {
        assert!(kinds.contains_key(kind), "{kinds:?}");
    }
}

/// A corner of a box pointing at a corner of a mesh box, diagonally apart
/// by `g` along each axis (true distance `g * sqrt(3)`): a vertex/vertex
/// contact, along a face normal (the nearest face to the gap is at
/// `acos(1 / sqrt(3))`, within the face axis's reach), at the gap's
/// component along it, `g`. The same from a mesh box, and mirrored.
#[test]
fn a_corner_pointing_at_a_corner_gives_a_vertex_vertex_contact() {
    let h = 0.1;
    let g = 0.004;
    let mesh = MeshShape::new(box_mesh(DVec3::splat(h)).unwrap()).unwrap();
    let cuboid = Shape::Cuboid(Cuboid::new(DVec3::splat(h)).unwrap());
    let pa = Pose::IDENTITY;
    let pb = Pose::from_translation(DVec3::splat(2.0 * h + g));
    for (a, b, sign) in [
        (cuboid.clone(), Shape::Mesh(mesh.clone()), 1.0),
        (Shape::Mesh(mesh.clone()), Shape::Mesh(mesh.clone()), 1.0),
    ] {
        for (x, y, pose_x, pose_y, s) in [(&a, &b, pa, pb, sign), (&b, &a, pb, pa, -sign)] {
            let mut out = Vec::new();
            contact_shapes(x, &pose_x, y, &pose_y, 0.01, &mut out).unwrap();
            let vv: Vec<&Contact> = out
                .iter()
                .filter(|c| c.kind == ContactKind::VertexVertex)
                .collect();
            assert_eq!(vv.len(), 1, "{out:?}");
            let c = vv[0];
            assert!((c.distance - g).abs() < 1e-12, "{c:?}");
            assert!((c.point - DVec3::splat(h + 0.5 * g)).length() < 1e-12, "{c:?}");
            // From B to A: towards the origin for A at the origin.
            let n = -s * c.normal;
            assert!(
                [DVec3::X, DVec3::Y, DVec3::Z]
                    .iter()
                    .any(|&e| (n - e).length() < 1e-12),
                "{c:?}"
            );
        }
    }
}

/// Two identical mesh boxes side by side, tilted towards each other about
/// their long horizontal axis so that their lower edges are level,
/// parallel and closest: each lower corner projects just outside the other
/// box's side face and parallel edges have no edge/edge normal, so only
/// corner contacts can see the gap there (the links of two chains hung
/// from one palm met so, and crossed 6 mm in one step). Both lower ends
/// are reported, along a side face, at the brute-force distance to within
/// the tilt's cosine; and so for a box against a mesh box (a chain of
/// cuboid links beside a chain of mesh links crossed 1.5 mm into it).
#[test]
fn level_parallel_edges_of_boxes_side_by_side_are_seen_at_both_ends() {
    let half = DVec3::new(0.008, 0.005, 0.015);
    let link = MeshShape::new(box_mesh(half).unwrap()).unwrap();
    let tilt: f64 = 0.017410;
    let pa = Pose::new(DVec3::new(0.0, -0.0057215, 0.474), DQuat::from_rotation_x(tilt)).unwrap();
    let pb = Pose::new(DVec3::new(0.0, 0.0057215, 0.474), DQuat::from_rotation_x(-tilt)).unwrap();
    let truth = brute_distance(&link, &pa, &link, &pb);
    assert!(truth > 0.0 && truth < 0.002, "{truth}");
    // Two mesh links, and a `Cuboid` of the link's size against a mesh
    // link either way round (the polytope-mesh routine); `sign` turns the
    // normal (from B to A) to point from +y to -y.
    for (a, pa, b, pb, sign) in [
        (Shape::Mesh(link.clone()), pa, Shape::Mesh(link.clone()), pb, 1.0),
        (
            Shape::Cuboid(Cuboid::new(half).unwrap()),
            pa,
            Shape::Mesh(link.clone()),
            pb,
            1.0,
        ),
        (
            Shape::Mesh(link.clone()),
            pb,
            Shape::Cuboid(Cuboid::new(half).unwrap()),
            pa,
            -1.0,
        ),
    ] {
        let mut out = Vec::new();
        contact_shapes(&a, &pa, &b, &pb, 0.01, &mut out).unwrap();
        for end in [-0.008, 0.008] {
            let near = out
                .iter()
                .filter(|c| {
                    (c.point.x - end).abs() < 1e-6
                        && c.distance <= truth + 1e-12
                        && c.distance >= truth * (2.0 * tilt).cos()
                        && sign * c.normal.y <= -(2.0 * tilt).cos()
                })
                .count();
            assert!(near >= 1, "end x = {end}: none at {truth} among {out:?}");
        }
    }
}

#[test]
fn mesh_on_half_space_reports_the_lowest_vertices() {
    let m = Shape::Mesh(mesh_box(0.5));
    let ground = Shape::HalfSpace(HalfSpace::ground());
    let mut out = Vec::new();
    contact_shapes(
        &m,
        &Pose::from_translation(DVec3::new(0.0, 0.0, 0.51)),
        &ground,
        &Pose::IDENTITY,
        0.02,
        &mut out,
    )
    .unwrap();
    assert_eq!(out.len(), 4);
    for c in &out {
        assert!((c.distance - 0.01).abs() < 1e-12);
        assert_eq!(c.normal, DVec3::Z);
    }
    let mut mirrored = Vec::new();
    contact_shapes(
        &ground,
        &Pose::IDENTITY,
        &m,
        &Pose::from_translation(DVec3::new(0.0, 0.0, 0.51)),
        0.02,
        &mut mirrored,
    )
    .unwrap();
    assert_eq!(mirrored.len(), 4);
    assert!(mirrored.iter().all(|c| c.normal == -DVec3::Z));
}

#[test]
fn sphere_on_mesh_face_has_the_analytic_distance() {
    let m = Shape::Mesh(mesh_box(0.5));
    let s = Shape::Sphere(Sphere::new(0.2).unwrap());
    let mut out = Vec::new();
    let centre = DVec3::new(0.1, 0.05, 0.5 + 0.2 + 0.004);
    contact_shapes(
        &s,
        &Pose::from_translation(centre),
        &m,
        &Pose::IDENTITY,
        0.01,
        &mut out,
    )
    .unwrap();
    assert!(!out.is_empty());
    assert!((min_distance(&out) - 0.004).abs() < 1e-12);
    assert!(out.iter().all(|c| (c.normal - DVec3::Z).length() < 1e-12));
}

#[test]
fn sphere_over_the_diagonal_of_a_mesh_face_touches_it_once() {
    // The centre straight above the edge shared by the two triangles of a
    // square face: the closest point is on that (flat) edge for both, and
    // the face must still be reported (it once was by neither, and a ball
    // fired at the middle of a mesh slab went straight through).
    let m = Shape::Mesh(mesh_box(0.5));
    let s = Shape::Sphere(Sphere::new(0.2).unwrap());
    for (x, y) in [(0.0, 0.0), (0.2, 0.2), (-0.3, -0.3), (0.3, -0.3)] {
        let mut out = Vec::new();
        let centre = DVec3::new(x, y, 0.5 + 0.2 + 0.05);
        contact_shapes(
            &s,
            &Pose::from_translation(centre),
            &m,
            &Pose::IDENTITY,
            0.1,
            &mut out,
        )
        .unwrap();
        assert_eq!(out.len(), 1, "above ({x}, {y}): {out:?}");
        assert!((out[0].distance - 0.05).abs() < 1e-12);
        assert!((out[0].normal - DVec3::Z).length() < 1e-12);
    }
}

#[test]
fn capsule_against_mesh_is_routed_to_its_routine() {
    // Capsule core 0.02 above the top face of a half-unit box mesh.
    let m = Shape::Mesh(mesh_box(0.5));
    let c = Shape::Capsule(Capsule::new(0.1, 0.3).unwrap());
    let pc = Pose::from_translation(DVec3::new(0.1, 0.05, 0.5 + 0.3 + 0.1 + 0.02));
    let mut out = Vec::new();
    contact_shapes(&c, &pc, &m, &Pose::IDENTITY, 0.05, &mut out).unwrap();
    assert!((min_distance(&out) - 0.02).abs() < 1e-12);
    assert!(out.iter().all(|c| (c.normal - DVec3::Z).length() < 1e-12));
}

#[test]
fn a_drift_finds_the_contacts_its_move_can_close_and_only_those() {
    // A above B with a 0.3 m gap between the top face of B and the bottom
    // of A. B rising 0.5 m relative to A closes it: the face contacts at
    // 0.3 m are reported; rising 0.1 m does not. For two meshes the drift's
    // direction counts: 0.5 m sideways closes nothing, where a margin of
    // 0.5 m on every side would report the face.
    use crate::Drift;
    let rise = |dz: f64| Drift {
        origin: DVec3::ZERO,
        translation: DVec3::new(0.0, 0.0, dz),
        rotation: DVec3::ZERO,
    };
    let sideways = Drift {
        translation: DVec3::new(0.5, 0.0, 0.0),
        ..rise(0.0)
    };
    let (pa, pb) = (Pose::from_translation(DVec3::new(0.0, 0.0, 0.9)), Pose::IDENTITY);
    let cube = Shape::Mesh(mesh_box(0.3));
    let sphere = Shape::Sphere(Sphere::new(0.3).unwrap());
    let margin = 0.01;
    for a in [&cube, &sphere] {
        let found = |drift: &Drift| {
            let mut out = Vec::new();
            contact_shapes_moving(a, &pa, &cube, &pb, margin, drift, &mut out).unwrap();
            out
        };
        let closing = found(&rise(0.5));
        assert!(!closing.is_empty(), "{}: the rise closes the gap", a.kind_name());
        // The gap itself, straight down, is the deepest of them (the ball
        // also sees the cube's edges farther off within the reach).
        let deepest = closing
            .iter()
            .min_by(|x, y| x.distance.total_cmp(&y.distance))
            .unwrap();
        assert!(
            (deepest.distance - 0.3).abs() < 1e-9 && deepest.normal.z > 0.999,
            "{deepest:?}"
        );
        assert!(
            found(&rise(0.1)).is_empty(),
            "{}: 0.1 m cannot close 0.3 m",
            a.kind_name()
        );
    }
    let mut out = Vec::new();
    contact_shapes_moving(&cube, &pa, &cube, &pb, margin, &sideways, &mut out).unwrap();
    assert!(out.is_empty(), "a sideways move closes no gap: {out:?}");
    contact_shapes(&cube, &pa, &cube, &pb, 0.5, &mut out).unwrap();
    assert!(!out.is_empty(), "an isotropic margin of 0.5 m reports the face");
    // A drift that is not finite is refused and appends nothing.
    let mut out = Vec::new();
    let bad = Drift {
        translation: DVec3::new(f64::NAN, 0.0, 0.0),
        ..rise(0.0)
    };
    assert_eq!(
        contact_shapes_moving(&cube, &pa, &sphere, &pb, margin, &bad, &mut out),
        Err(NarrowError::BadDrift)
    );
    assert!(out.is_empty());
}

#[test]
fn a_mesh_against_a_plane_gets_every_vertex_within_the_margin_once_in_index_order() {
    // A torus tilted at random over the ground, its lowest point within the
    // margin: the contacts are exactly the vertices within the margin (a
    // scan of every vertex is the oracle), each once, named by its first
    // corner, in vertex order; the tree only spares the visits.
    use crate::mesh::torus_mesh;
    use tumble_testkit::{RandomSource, SplitMix64};
    let torus = MeshShape::new(torus_mesh(0.4, 0.1, 48, 24).unwrap()).unwrap();
    let ground = HalfSpace::ground();
    let mut rng = SplitMix64(31);
    let margin = 0.004;
    let mut seen = 0;
    for case in 0..60 {
        // Every tenth pose lies almost flat: a whole ring of vertices near
        // the plane.
        let tilt = if case % 10 == 0 { 0.002 } else { 0.4 };
        let turn = DQuat::from_scaled_axis(DVec3::new(
            rng.range(-tilt, tilt),
            rng.range(-tilt, tilt),
            rng.range(-3.0, 3.0),
        ));
        let unlifted = Pose::new(DVec3::ZERO, turn).unwrap();
        let lowest = torus
            .mesh()
            .vertices()
            .iter()
            .map(|&v| unlifted.transform_point(v).z)
            .fold(f64::INFINITY, f64::min);
        let pose = Pose::new(DVec3::new(0.3, -0.2, -lowest + rng.range(-0.002, 0.003)), turn).unwrap();
        let mut out = Vec::new();
        contact_mesh_halfspace(&torus, &pose, &ground, &Pose::IDENTITY, margin, &mut out);
        let expected: Vec<(DVec3, f64, Feature)> = torus
            .mesh()
            .vertices()
            .iter()
            .enumerate()
            .filter_map(|(v, &p)| {
                let (t, k) = torus.first_corner(v as u32)?;
                let p = pose.transform_point(p);
                (p.z <= margin).then_some((p - DVec3::Z * (0.5 * p.z), p.z, Feature::vertex(t, k)))
            })
            .collect();
        seen += usize::from(expected.len() > 16);
        let got: Vec<(DVec3, f64, Feature)> =
            out.iter().map(|c| (c.point, c.distance, c.feature_a)).collect();
        assert_eq!(got, expected);
    }
    assert!(seen >= 5, "only {seen} poses with many vertices near the plane");
}

/// A ball carried over a tessellated sphere (UV, 32 x 16) at a fixed height
/// touches its smooth surface: one contact at every pose, its normal the
/// radial direction to second order in the facet angle and turning
/// continuously from pose to pose, its distance the true one to a fraction
/// of the facets' sagitta. Against the flat facets the same path rises and
/// falls by the sagitta.
#[test]
fn a_ball_over_a_smooth_tessellated_sphere_touches_the_sphere() {
    let (big_r, r, gap) = (1.0, 0.1, 0.002);
    let mesh = crate::mesh::uv_sphere_mesh(big_r, 32, 16).unwrap();
    let smooth = MeshShape::new(mesh.clone())
        .unwrap()
        .with_smooth_surface(0.5)
        .unwrap();
    let flat = MeshShape::new(mesh).unwrap();
    let sphere = Sphere::new(r).unwrap();
    let pose_b = Pose::new(DVec3::new(0.3, -0.2, 0.1), DQuat::from_rotation_z(0.4)).unwrap();
    let sagitta = big_r * (1.0 - (std::f64::consts::PI / 32.0).cos());
    let mut prev = None::<DVec3>;
    let mut worst_turn = 0.0f64;
    let (mut flat_lo, mut flat_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..=400 {
        // Along a path over facet edges and vertices alike.
        let a = 0.3 + 1.2 * i as f64 / 400.0;
        let dir = DVec3::new(a.cos() * 0.9, a.sin() * 0.9, 0.2 + 0.1 * a).normalize();
        let centre = pose_b.transform_point(dir * (big_r + r + gap));
        let pose_a = Pose::from_translation(centre);
        let mut out = Vec::new();
        contact_sphere_mesh(&sphere, &pose_a, &smooth, &pose_b, 0.01, &mut out);
        assert_eq!(out.len(), 1, "pose {i}: {out:?}");
        let radial = pose_b.rotation * dir;
        // (pi / 16)^2 / 8 = 5e-3.
        assert!(
            (out[0].normal - radial).length() < 5e-3,
            "pose {i}: {:?} vs {radial:?}",
            out[0].normal
        );
        assert!(
            (out[0].distance - gap).abs() < 0.1 * sagitta,
            "pose {i}: {}",
            out[0].distance
        );
        if let Some(p) = prev {
            worst_turn = worst_turn.max((out[0].normal - p).length());
        }
        prev = Some(out[0].normal);
        let mut flat_out = Vec::new();
        contact_sphere_mesh(&sphere, &pose_a, &flat, &pose_b, 0.05, &mut flat_out);
        let nearest = min_distance(&flat_out);
        (flat_lo, flat_hi) = (flat_lo.min(nearest), flat_hi.max(nearest));
    }
    // Samples 3 mrad apart: the smooth normal turns by about that per sample.
    assert!(
        worst_turn < 0.006,
        "smooth normal turned {worst_turn} between samples"
    );
    assert!(
        flat_hi - flat_lo > sagitta,
        "flat facets rose and fell by {}",
        flat_hi - flat_lo
    );
}

/// Sharp features stay sharp: against a box mesh with a smooth surface
/// (every edge a crease at 30 degrees) spheres and capsules get the
/// contacts of the plain box mesh, at random poses with their centres (core
/// ends) outside the box. (With a centre inside, the plain mesh's unsigned
/// distance pushes it on inwards, the smooth surface back out.)
#[test]
fn a_smooth_surface_keeps_a_box_sharp() {
    let plain = mesh_box(0.5);
    let smooth = mesh_box(0.5).with_smooth_surface(30f64.to_radians()).unwrap();
    let mut rng = crate::bvh::traverse::tests::rng(5);
    let (sphere, capsule) = (Sphere::new(0.2).unwrap(), Capsule::new(0.1, 0.3).unwrap());
    let mut touching = 0;
    for _ in 0..300 {
        let pose = crate::bvh::traverse::tests::random_pose(&mut rng, 2.0);
        let inside = |p: DVec3| p.abs().max_element() < 0.5;
        let [p, q] = capsule.world_segment(&pose);
        for shape in [Shape::Sphere(sphere), Shape::Capsule(capsule)] {
            if inside(pose.position) || (matches!(shape, Shape::Capsule(_)) && (inside(p) || inside(q))) {
                continue;
            }
            let (mut a, mut b) = (Vec::new(), Vec::new());
            contact_shapes(
                &shape,
                &pose,
                &Shape::Mesh(plain.clone()),
                &Pose::IDENTITY,
                0.02,
                &mut a,
            )
            .unwrap();
            contact_shapes(
                &shape,
                &pose,
                &Shape::Mesh(smooth.clone()),
                &Pose::IDENTITY,
                0.02,
                &mut b,
            )
            .unwrap();
            // The same deepest contact, and for spheres no contact the
            // plain mesh lacks (where two triangles report one corner as an
            // edge and as a vertex, the smooth surface may keep only one of
            // the two). A tilted capsule's core ends over a face are
            // contacts on the smooth surface, on the plain mesh only when it
            // lies along the face.
            assert_eq!(a.is_empty(), b.is_empty(), "{pose:?}: {a:?} vs {b:?}");
            touching += !a.is_empty() as usize;
            assert!((min_distance(&a) - min_distance(&b)).abs() < 1e-9 || a.is_empty());
            for y in b.iter().filter(|_| matches!(shape, Shape::Sphere(_))) {
                assert!(
                    a.iter().any(|x| (x.distance - y.distance).abs() < 1e-9
                        && (x.normal - y.normal).length() < 1e-9
                        && (x.point - y.point).length() < 1e-9),
                    "{y:?} is not among {a:?}"
                );
            }
        }
    }
    assert!(touching > 50, "too few touching poses: {touching}");
}

/// A mesh's smooth surface is refused for a crease angle outside (0, pi).
#[test]
fn bad_crease_angles_are_refused() {
    for angle in [0.0, -0.1, std::f64::consts::PI, f64::NAN, f64::INFINITY] {
        assert!(mesh_box(0.5).with_smooth_surface(angle).is_err(), "{angle}");
    }
}

/// The smooth surface is the same whichever side of the pair the mesh is:
/// the contacts of mesh against ball are those of ball against mesh,
/// flipped, at random poses around a tessellated sphere.
#[test]
fn smooth_contacts_are_mirrored_when_the_mesh_is_a() {
    let mesh = Shape::Mesh(
        MeshShape::new(crate::mesh::uv_sphere_mesh(1.0, 24, 12).unwrap())
            .unwrap()
            .with_smooth_surface(0.6)
            .unwrap(),
    );
    let mut rng = crate::bvh::traverse::tests::rng(11);
    let mut touching = 0;
    for _ in 0..100 {
        let pose_b = crate::bvh::traverse::tests::random_pose(&mut rng, 0.2);
        let dir = DVec3::new(rng() - 0.5, rng() - 0.5, rng() - 0.5).normalize();
        let pose_a = Pose::from_translation(pose_b.transform_point(dir * (1.1 + 0.02 * (rng() - 0.5))));
        for round in [
            Shape::Sphere(Sphere::new(0.1).unwrap()),
            Shape::Capsule(Capsule::new(0.1, 0.2).unwrap()),
        ] {
            let (mut ab, mut ba) = (Vec::new(), Vec::new());
            contact_shapes(&round, &pose_a, &mesh, &pose_b, 0.02, &mut ab).unwrap();
            contact_shapes(&mesh, &pose_b, &round, &pose_a, 0.02, &mut ba).unwrap();
            touching += !ab.is_empty() as usize;
            assert_eq!(ab.iter().map(|c| c.flipped()).collect::<Vec<_>>(), ba);
        }
    }
    assert!(touching > 100, "too few touching poses: {touching}");
}

/// A mesh with a face wound the wrong way (one triangle of a sphere
/// flipped) still gets its smooth surface: the flipped face's edges are
/// creases, even at a crease angle that blends everything else.
#[test]
fn a_flipped_face_is_a_crease_not_a_loop() {
    let sphere = crate::mesh::uv_sphere_mesh(1.0, 16, 8).unwrap();
    let mut triangles = sphere.triangles().to_vec();
    triangles[40].swap(1, 2);
    // A mesh is not refused for its winding (only solids for mass are).
    let flipped = crate::mesh::TriMesh::new(sphere.vertices().to_vec(), triangles).unwrap();
    let shape = MeshShape::new(flipped)
        .unwrap()
        .with_smooth_surface(179f64.to_radians())
        .unwrap();
    let s = shape.smooth_surface().unwrap();
    assert!((0..3).all(|k| s.is_crease(40, k)));
}

/// Re-evaluating the features of a search's contacts at the same poses
/// gives those contacts again, vertex and edge contacts with the same names
/// (the same triangle test
/// on the same coordinates, to round-off: the search tests every feature of
/// every pair and the re-evaluation each shared one through its owner, so
/// an edge may run the other way), for two meshes touching at random poses
/// and for a mesh over a plane, in either order; other shape pairs are not
/// re-evaluated, and a bad margin is refused.
#[test]
fn contacts_re_evaluated_at_their_features_are_the_contacts_found() {
    use crate::mesh::torus_mesh;
    use tumble_testkit::{RandomSource, SplitMix64};
    let torus = Shape::Mesh(MeshShape::new(torus_mesh(0.3, 0.1, 32, 16).unwrap()).unwrap());
    let ball = Shape::Mesh(MeshShape::new(icosphere_mesh(0.15, 2).unwrap()).unwrap());
    let ground = Shape::HalfSpace(HalfSpace::ground());
    let mut rng = SplitMix64(17);
    let margin = 0.004;
    let mut checked = 0;
    for case in 0..40 {
        let turn = random_turn(&mut rng);
        let pose_a = torus_pose();
        // The ball on the tube (a gap of -3 to 3 mm), or the torus over the ground.
        let (a, pa, b, pb) = if case % 2 == 0 {
            let on_tube = pose_a.transform_point(DVec3::new(0.3, 0.0, 0.25 + rng.range(-0.003, 0.003)));
            (&torus, pose_a, &ball, Pose::new(on_tube, turn).unwrap())
        } else {
            let flat =
                DQuat::from_scaled_axis(DVec3::new(rng.range(-0.05, 0.05), rng.range(-0.05, 0.05), 0.0));
            let lifted = Pose::new(DVec3::new(0.0, 0.0, 0.1 + rng.range(-0.002, 0.003)), flat).unwrap();
            if case % 4 == 1 {
                (&torus, lifted, &ground, Pose::IDENTITY)
            } else {
                (&ground, Pose::IDENTITY, &torus, lifted)
            }
        };
        let mut found = Vec::new();
        contact_shapes(a, &pa, b, &pb, margin, &mut found).unwrap();
        let features = found.iter().map(|c| (c.feature_a, c.feature_b));
        let mut again = Vec::new();
        assert!(contact_at_features(a, &pa, b, &pb, margin, features, &mut again).unwrap());
        // A push-out contact keeps the names of whichever intersecting
        // pair came first (the walk's order and the re-evaluation's differ).
        let same = |c: &Contact, d: &Contact| {
            c.kind == d.kind
                && (c.kind == ContactKind::Penetrating
                    || (c.feature_a, c.feature_b) == (d.feature_a, d.feature_b))
                && (c.point - d.point).length() <= 1e-12
                && (c.normal - d.normal).length() <= 1e-12
                && (c.distance - d.distance).abs() <= 1e-12
        };
        for c in &found {
            assert!(
                again.iter().any(|d| same(c, d)),
                "case {case}: {c:?} not found again in {again:?}"
            );
        }
        checked += found.len();
    }
    assert!(checked > 100, "only {checked} contacts checked");
    let sphere = Shape::Sphere(Sphere::new(0.1).unwrap());
    let mut out = Vec::new();
    let none = std::iter::empty();
    assert!(!contact_at_features(
        &sphere,
        &Pose::IDENTITY,
        &ground,
        &Pose::IDENTITY,
        margin,
        none,
        &mut out
    )
    .unwrap());
    let none = std::iter::empty();
    assert!(contact_at_features(
        &torus,
        &Pose::IDENTITY,
        &ground,
        &Pose::IDENTITY,
        f64::NAN,
        none,
        &mut out
    )
    .is_err());
    assert!(out.is_empty());
}

/// `x` and `y` hold the same contacts, in any order, to round-off: the same
/// kinds and features, points and distances within 1e-12 m, normals within
/// 1e-12.
pub(super) fn same_contacts(x: &[Contact], y: &[Contact]) -> Result<(), String> {
    if x.len() != y.len() {
        return Err(format!("{} contacts against {}", x.len(), y.len()));
    }
    match x.iter().find(|c| !y.iter().any(|d| twins(c, d))) {
        Some(c) => Err(format!("no twin of {c:?}")),
        None => Ok(()),
    }
}

fn twins(c: &Contact, d: &Contact) -> bool {
    d.kind == c.kind
        && d.feature_a == c.feature_a
        && d.feature_b == c.feature_b
        && (d.point - c.point).length() <= 1e-12
        && (d.distance - c.distance).abs() <= 1e-12
        && (d.normal - c.normal).length() <= 1e-12
}

/// Two push-out contacts at the same place (to round-off), whichever
/// intersecting pair names them: the copies of one push-out from two
/// pairs differ in the last bits, so which survives the merge is
/// round-off (the oracle moves B's corners by quaternion, the walk by
/// matrix).
fn same_push_out(c: &Contact, d: &Contact) -> bool {
    c.kind == ContactKind::Penetrating
        && twins(
            c,
            &Contact {
                feature_a: c.feature_a,
                feature_b: c.feature_b,
                ..*d
            },
        )
}

/// Every feature of every triangle pair that the walk along `drift`
/// reaches, each pair within the margin plus the look-ahead of B's leaf
/// (the mesh narrow phase before shared features were tested once, and
/// before each feature took its own look-ahead): the oracle of the owned
/// answer.
fn every_feature_walk(
    a: &MeshShape,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
    margin: f64,
    drift: &crate::drift::Drift,
) -> Vec<Contact> {
    let rel = pose_a.inverse().mul_pose(pose_b);
    let mut out = Vec::new();
    crate::bvh::collide_moving(
        a.tree(),
        pose_a,
        b.tree(),
        pose_b,
        margin,
        drift,
        |ta, tb, moves| {
            let wa = a.mesh().triangle(ta as usize);
            let wb = b.mesh().triangle(tb as usize).map(|v| rel.transform_point(v));
            crate::triangle::triangle_contacts(&wa, ta, &wb, tb, margin + moves, &mut out).unwrap();
            crate::bvh::Traverse::Continue
        },
    )
    .unwrap();
    super::contact_mesh::finish_mesh_mesh(&mut out, 0, a, pose_a, b, pose_b);
    out
}

/// Testing each shared vertex and edge once, through the triangle that owns
/// it, gives the contacts of testing every feature of every triangle pair,
/// for a torus against a ball and against another torus, linked or side by
/// side, at random poses near contact, separated and intersecting, through
/// the plain walk and through a resting pair's list
/// (`contact_mesh_mesh_recalled`): an owner reports a feature of an
/// intersecting pair, or an edge/edge contact its own faces reject, only
/// when a pair of the triangles around it would have. (Besides, owners
/// report the vertex/edge and vertex/vertex contacts no single pair can
/// judge: `the_closest_features_of_two_convex_meshes_are_found_at_random_poses`
/// checks those.)
#[test]
fn shared_features_tested_once_give_every_pairs_contacts() {
    use crate::drift::Drift;
    let torus = MeshShape::new(crate::mesh::torus_mesh(0.3, 0.1, 32, 16).unwrap()).unwrap();
    let ball = MeshShape::new(icosphere_mesh(0.15, 2).unwrap()).unwrap();
    let mut rng = tumble_testkit::SplitMix64(5);
    let margin = 0.004;
    let (mut separated, mut intersecting) = (0, 0);
    for case in 0..90 {
        let (b, pose_a, pose_b) = near_contact(&torus, &ball, case, &mut rng);
        let every = every_feature_walk(&torus, &pose_a, b, &pose_b, margin, &Drift::NONE);
        let mut walked = Vec::new();
        contact_mesh_mesh(&torus, &pose_a, b, &pose_b, margin, &mut walked);
        let mut listed = Vec::new();
        contact_mesh_mesh_recalled(
            &torus,
            &pose_a,
            b,
            &pose_b,
            margin,
            &Drift::NONE,
            None,
            &mut listed,
        )
        .unwrap();
        for (owned, how) in [(&walked, "walk"), (&listed, "list")] {
            // Vertex/edge and vertex/vertex contacts come from the owners
            // alone (`triangle::tri_vertex_edge`): the every-pair answer
            // has none of them to compare with.
            let owned: Vec<Contact> = owned
                .iter()
                .filter(|c| {
                    !matches!(
                        c.kind,
                        ContactKind::VertexEdge | ContactKind::EdgeVertex | ContactKind::VertexVertex
                    )
                })
                .copied()
                .collect();
            if let Err(why) = same_but_push_out_names(&owned, &every) {
                panic!("case {case}, {how}: {why}");
            }
        }
        if every.iter().all(|c| c.kind != ContactKind::Penetrating) {
            separated += usize::from(!every.is_empty());
        } else {
            intersecting += 1;
        }
    }
    // Both kinds of case were met, with contacts to compare.
    assert!(
        separated >= 30 && intersecting >= 30,
        "{separated} separated, {intersecting} intersecting"
    );
}

/// [`same_contacts`], except that a push-out contact may carry the names
/// of another intersecting pair at the same place ([`same_push_out`]).
fn same_but_push_out_names(x: &[Contact], y: &[Contact]) -> Result<(), String> {
    if x.len() != y.len() {
        return Err(format!("{} contacts against {}", x.len(), y.len()));
    }
    for (p, q) in [(x, y), (y, x)] {
        if let Some(c) = p
            .iter()
            .find(|c| !q.iter().any(|d| twins(c, d) || same_push_out(c, d)))
        {
            return Err(format!("no twin of {c:?}"));
        }
    }
    Ok(())
}

/// Case `case % 3` of the random poses near contact: the ball on the
/// torus's tube, a second torus linked through the first with its tube on
/// the inside of the first's, or a second torus beside the first, tubes
/// touching; each within 4 mm of touching either way.
fn near_contact<'m>(
    torus: &'m MeshShape,
    ball: &'m MeshShape,
    case: usize,
    rng: &mut tumble_testkit::SplitMix64,
) -> (&'m MeshShape, Pose, Pose) {
    use tumble_testkit::RandomSource;
    let turn = random_turn(rng);
    let pose_a = torus_pose();
    let gap = rng.range(-0.004, 0.004);
    let small = DQuat::from_scaled_axis(turn.to_scaled_axis() * 0.03);
    let (b, pose_b) = match case % 3 {
        0 => (
            ball,
            Pose::new(pose_a.transform_point(DVec3::new(0.3, 0.0, 0.25 + gap)), turn),
        ),
        1 => (
            torus,
            Pose::new(
                pose_a.transform_point(DVec3::new(0.4 + gap, 0.0, 0.0)),
                pose_a.rotation * small * DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2),
            ),
        ),
        _ => (
            torus,
            Pose::new(
                pose_a.transform_point(DVec3::new(0.8 + gap, 0.0, 0.0)),
                pose_a.rotation * small,
            ),
        ),
    };
    (b, pose_a, pose_b.unwrap())
}

/// Along a drift, the walk that tests each shared feature once, within its
/// own look-ahead, loses no contact that matters: every contact of every
/// feature of every reached pair (each within its leaf's look-ahead) that
/// is within the margin already, or intersecting, is there, to round-off;
/// what it drops are far look-ahead contacts of features that move less
/// than their leaf's fastest point, and each of its own is within the
/// margin plus its feature's look-ahead (computed here from B's corners'
/// world displacements).
#[test]
fn along_a_drift_each_feature_takes_its_own_look_ahead_and_close_contacts_stay() {
    use crate::contact::SubFeature;
    use crate::drift::Drift;
    use tumble_testkit::RandomSource;
    let torus = MeshShape::new(crate::mesh::torus_mesh(0.3, 0.1, 32, 16).unwrap()).unwrap();
    let ball = MeshShape::new(icosphere_mesh(0.15, 2).unwrap()).unwrap();
    let mut rng = tumble_testkit::SplitMix64(11);
    let margin = 0.004;
    let (mut close, mut dropped, mut look_ahead) = (0, 0, 0);
    for case in 0..90 {
        let (b, pose_a, pose_b) = near_contact(&torus, &ball, case, &mut rng);
        let mut r = || DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let drift = Drift {
            origin: pose_b.position,
            translation: r() * 0.003,
            rotation: r() * 0.02,
        };
        let every = every_feature_walk(&torus, &pose_a, b, &pose_b, margin, &drift);
        let mut owned = Vec::new();
        contact_mesh_mesh_moving(&torus, &pose_a, b, &pose_b, margin, &drift, &mut owned);
        for c in every
            .iter()
            .filter(|c| c.kind == ContactKind::Penetrating || c.distance <= margin)
        {
            close += 1;
            assert!(
                owned.iter().any(|d| twins(c, d) || same_push_out(c, d)),
                "case {case}: {c:?} missing"
            );
        }
        dropped += every.len().saturating_sub(owned.len());
        // How far B's corner `k` of triangle `t` moves along the drift.
        let moves = |t: u32, k: usize| {
            let v = b.mesh().triangles()[t as usize][k % 3];
            drift
                .displacement(pose_b.transform_point(b.mesh().vertices()[v as usize]))
                .length()
        };
        for d in owned.iter().filter(|d| d.kind != ContactKind::Penetrating) {
            let (t, sub) = (d.feature_b.index, d.feature_b.sub);
            let own = match sub {
                SubFeature::Vertex(k) => moves(t, k as usize),
                SubFeature::Edge(k) => moves(t, k as usize).max(moves(t, k as usize + 1)),
                _ => moves(t, 0).max(moves(t, 1)).max(moves(t, 2)),
            };
            assert!(
                d.distance <= margin + own + 1e-12,
                "case {case}: {d:?} beyond {own}"
            );
            look_ahead += usize::from(d.distance > margin);
        }
    }
    assert!(
        close >= 400 && look_ahead >= 200 && dropped >= 50,
        "{close} close, {look_ahead} look-ahead contacts kept, {dropped} dropped"
    );
}

/// A turn by a random rotation vector of up to 3 rad per component.
fn random_turn(rng: &mut tumble_testkit::SplitMix64) -> DQuat {
    use tumble_testkit::RandomSource;
    DQuat::from_scaled_axis(DVec3::new(
        rng.range(-3.0, 3.0),
        rng.range(-3.0, 3.0),
        rng.range(-3.0, 3.0),
    ))
}

/// Where the random-pose tests put their torus (A).
fn torus_pose() -> Pose {
    Pose::new(DVec3::new(0.01, -0.02, 0.1), DQuat::from_rotation_z(0.3)).unwrap()
}

/// A vertex above a face whose every triangle crosses that face (a cube's
/// corner poking 1 mm out through a slab's top) has no vertex contact of
/// its own, from its owner or any pair: every pair holding it intersects,
/// and the push-out contacts carry the overlap. Beside it, a corner of the
/// same cube 1 mm above the slab with its triangles clear of it (the cube
/// turned the other way, resting on the corner) gets one; either mesh as A.
#[test]
fn a_vertex_whose_every_triangle_crosses_the_face_has_no_contact_of_its_own() {
    use crate::drift::Drift;
    let slab = mesh_box(0.5);
    let slab_pose = Pose::from_translation(DVec3::new(0.0, 0.0, -0.5));
    let cube = mesh_box(0.05);
    let up = DQuat::from_rotation_arc(DVec3::ONE.normalize(), DVec3::Z);
    let tip = 0.05 * 3f64.sqrt();
    let margin = 0.004;
    for (turn, centre_z, poking) in [
        (up, 0.001 - tip, true),
        (
            up * DQuat::from_rotation_x(std::f64::consts::PI),
            0.001 + tip,
            false,
        ),
    ] {
        let pose = Pose::new(DVec3::new(0.1, 0.05, centre_z), turn).unwrap();
        let every = every_feature_walk(&cube, &pose, &slab, &slab_pose, margin, &Drift::NONE);
        let mut owned = Vec::new();
        contact_mesh_mesh(&cube, &pose, &slab, &slab_pose, margin, &mut owned);
        same_but_push_out_names(&owned, &every).unwrap();
        // The same with the roles swapped (the corner on B's side).
        let every_swapped = every_feature_walk(&slab, &slab_pose, &cube, &pose, margin, &Drift::NONE);
        let mut swapped = Vec::new();
        contact_mesh_mesh(&slab, &slab_pose, &cube, &pose, margin, &mut swapped);
        same_but_push_out_names(&swapped, &every_swapped).unwrap();
        let tip_swapped = swapped
            .iter()
            .filter(|c| c.kind == ContactKind::FaceVertex && (c.distance - 0.001).abs() < 1e-9)
            .count();
        let at_tip = owned
            .iter()
            .filter(|c| c.kind == ContactKind::VertexFace && (c.distance - 0.001).abs() < 1e-9)
            .count();
        let pushed = owned
            .iter()
            .filter(|c| c.kind == ContactKind::Penetrating)
            .count();
        if poking {
            assert!(
                at_tip == 0 && pushed > 0,
                "poking: {at_tip} tip contacts, {pushed} push-outs"
            );
            assert_eq!(tip_swapped, 0, "poking, swapped");
        } else {
            assert!(
                at_tip == 1 && pushed == 0,
                "resting: {at_tip} tip contacts, {pushed} push-outs"
            );
            assert_eq!(tip_swapped, 1, "resting, swapped");
        }
    }
}
