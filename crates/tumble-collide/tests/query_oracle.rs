//! The query API against brute force over all triangle pairs (issue 3,
//! "Tests that must exist"): random triangle soups whose vertices are snapped
//! to a coarse grid, so that coplanar, shared-vertex, edge-touching,
//! zero-area and sliver triangles occur, at random poses and at grid poses
//! (identity rotation, grid translation: exact touching between the meshes).
//! Every mode, with and without `stop_at_first`, must give the brute-force
//! boolean and pair set; distances the brute-force minimum (exactly in exact
//! mode, within the bound otherwise); the tolerance query must agree with
//! the distance. Then the thesis' tori scene against its published ground
//! truth, and bad input.

mod common;
use common::rng;
use tumble_collide::bvh::TraversalStats;
use tumble_collide::mesh::{torus_mesh, MeshError, TriMesh};
use tumble_collide::query::*;
use tumble_collide::triangle::{
    closest_point_on_triangle, closest_points_segments, tri_box_overlap, tri_tri_overlap, triangle_contacts,
    triangle_distance, MergeParams,
};
use tumble_collide::{
    Capsule, Contact, ContactKind, ConvexHull, Cuboid, DMat3, DQuat, DVec3, Feature, HalfSpace, Pose,
    PoseError, Shape, Sphere, SubFeature,
};

/// A point of the grid {-2, -1.5, ..., 2}^3.
fn grid_point(r: &mut impl FnMut() -> f64) -> DVec3 {
    let g = |x: f64| (x * 9.0).floor() * 0.5 - 2.0;
    DVec3::new(g(r()), g(r()), g(r()))
}

/// A triangle soup of `n` triangles over a shared pool of grid vertices, with
/// deliberate zero-area (repeated or collinear corners) and sliver triangles.
fn soup(r: &mut impl FnMut() -> f64, n: usize) -> TriMesh {
    let mut v: Vec<DVec3> = (0..(n + 3).min(40)).map(|_| grid_point(r)).collect();
    let mut t = Vec::with_capacity(n);
    for _ in 0..n {
        let pick = |r: &mut dyn FnMut() -> f64, len: usize| ((r() * len as f64) as u32).min(len as u32 - 1);
        let kind = r();
        if kind < 0.08 {
            // Repeated corner: a segment.
            let (a, b) = (pick(r, v.len()), pick(r, v.len()));
            t.push([a, b, a]);
        } else if kind < 0.16 {
            // Three collinear grid points.
            let p = grid_point(r);
            let d = DVec3::new(0.5, 0.0, 0.5) * if r() < 0.5 { 1.0 } else { -1.0 };
            let base = v.len() as u32;
            v.extend([p, p + d, p + 2.0 * d]);
            t.push([base, base + 2, base + 1]);
        } else if kind < 0.24 {
            // Sliver: long base, apex a little off its middle.
            let p = grid_point(r);
            let base = v.len() as u32;
            v.extend([p, p + DVec3::new(3.0, 0.0, 0.0), p + DVec3::new(1.5, 0.125, 0.0)]);
            t.push([base, base + 1, base + 2]);
        } else {
            t.push([pick(r, v.len()), pick(r, v.len()), pick(r, v.len())]);
        }
    }
    TriMesh::new(v, t).unwrap()
}

fn random_pose(r: &mut impl FnMut() -> f64, spread: f64) -> Pose {
    let q = DQuat::from_xyzw(r() - 0.5, r() - 0.5, r() - 0.5, r() - 0.5).normalize();
    Pose::new(DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * spread, q).unwrap()
}

/// Identity rotation, translation on the half grid: world coordinates stay
/// exact, so exact touching, shared points and coplanar pairs across the
/// meshes happen.
fn grid_pose(r: &mut impl FnMut() -> f64) -> Pose {
    let g = |x: f64| (x * 5.0).floor() * 0.5 - 1.0;
    Pose::from_translation(DVec3::new(g(r()), g(r()), g(r())))
}

fn world(m: &TriMesh, p: &Pose, t: usize) -> [DVec3; 3] {
    m.triangle(t).map(|v| p.transform_point(v))
}

fn brute_pairs(a: &TriMesh, pa: &Pose, b: &TriMesh, pb: &Pose) -> Vec<(u32, u32)> {
    let mut out = vec![];
    for i in 0..a.triangles().len() {
        let x = world(a, pa, i);
        for j in 0..b.triangles().len() {
            if tri_tri_overlap(&x, &world(b, pb, j)) {
                out.push((i as u32, j as u32));
            }
        }
    }
    out
}

/// (distance, triangle of A, triangle of B) minimum over all pairs.
fn brute_distance(a: &TriMesh, pa: &Pose, b: &TriMesh, pb: &Pose) -> f64 {
    let mut best = f64::INFINITY;
    for i in 0..a.triangles().len() {
        let x = world(a, pa, i);
        for j in 0..b.triangles().len() {
            best = best.min(triangle_distance(&x, &world(b, pb, j)).distance);
        }
    }
    best
}

/// Mesh-global identity of one side of a contact (vertex id or sorted edge).
fn global(f: Feature, m: &TriMesh) -> Option<(u32, u32)> {
    let t = m.triangles()[f.index as usize];
    match f.sub {
        SubFeature::Vertex(k) => Some((t[k as usize], u32::MAX)),
        SubFeature::Edge(k) => {
            let (u, v) = (t[k as usize], t[(k as usize + 1) % 3]);
            Some((u.min(v), u.max(v)))
        }
        _ => None,
    }
}

/// A vertex or an edge of a mesh's triangle as a segment (a vertex as a
/// segment of no length) in the world, and the triangles that hold it (by
/// its global vertex ids).
fn feature_in_world(f: Feature, m: &TriMesh, pose: &Pose) -> ((DVec3, DVec3), Vec<usize>) {
    let t = m.triangles()[f.index as usize];
    let (u, v) = match f.sub {
        SubFeature::Vertex(k) => (t[k as usize], t[k as usize]),
        SubFeature::Edge(k) => (t[k as usize], t[(k as usize + 1) % 3]),
        _ => panic!("not a vertex or an edge: {f:?}"),
    };
    let at = |i: u32| pose.transform_point(m.vertices()[i as usize]);
    let holders = (0..m.triangles().len())
        .filter(|&i| m.triangles()[i].contains(&u) && m.triangles()[i].contains(&v))
        .collect();
    ((at(u), at(v)), holders)
}

/// `true` when the triangles `holders` that hold a feature are one fan the
/// contact routines walk whole: none repeats a vertex, and an edge has at
/// most two of them, a vertex's are joined through edges at the vertex
/// held by exactly two triangles of the mesh (counted here over the whole
/// mesh, not read from its neighbour table). Elsewhere (two fans meeting
/// in a point, a non-manifold edge) the routines see the owner's fan alone
/// (`MeshShape::any_around_corner`), and the brute-force cone check does
/// not apply.
fn one_fan(f: Feature, m: &TriMesh, holders: &[usize]) -> bool {
    let tris = m.triangles();
    if holders.iter().any(|&i| {
        let t = tris[i];
        t[0] == t[1] || t[1] == t[2] || t[2] == t[0]
    }) {
        return false;
    }
    let SubFeature::Vertex(k) = f.sub else {
        return holders.len() <= 2;
    };
    let v = tris[f.index as usize][k as usize];
    let held_by = |u: u32| tris.iter().filter(|t| t.contains(&u) && t.contains(&v)).count();
    let mut reached = vec![holders[0]];
    let mut next = 0;
    while next < reached.len() {
        let t = tris[reached[next]];
        next += 1;
        for &u in t.iter().filter(|&&u| u != v) {
            if held_by(u) != 2 {
                continue;
            }
            for &h in holders {
                if !reached.contains(&h) && tris[h].contains(&u) {
                    reached.push(h);
                }
            }
        }
    }
    reached.len() == holders.len()
}

/// A vertex/edge, edge/vertex or vertex/vertex contact checked against its
/// two features by brute force: the gap `g` between them is within the
/// margin, the point is the middle of their closest points, the distance is
/// between half the gap and the gap (the gap along the nearest face normal,
/// or the gap itself), the normal is the gap's direction or a face normal
/// of a triangle at either feature, and, where each feature's triangles are
/// one fan ([`one_fan`]), no triangle at one feature comes nearer than `g`
/// to a triangle at the other (the gap lies in both features' cones of
/// normals, so the features are the closest points of the triangles
/// around them).
fn check_corner_contact(
    c: &Contact,
    (a, pa): (&TriMesh, &Pose),
    (b, pb): (&TriMesh, &Pose),
    margin: f64,
    what: &str,
) -> bool {
    let ((p1, q1), around_a) = feature_in_world(c.feature_a, a, pa);
    let ((p2, q2), around_b) = feature_in_world(c.feature_b, b, pb);
    let closest = closest_points_segments(p1, q1, p2, q2);
    let gap = closest.point_a - closest.point_b;
    let g = gap.length();
    let tol = 1e-9 * (1.0 + p1.abs().max_element());
    assert!(g > 0.0 && g <= margin + tol, "{what}: {c:?} at {g}");
    assert!(
        (c.point - (closest.point_a + closest.point_b) * 0.5).length() <= tol,
        "{what}: {c:?} not between its features"
    );
    assert!(
        c.distance >= 0.5 * g - tol && c.distance <= g + tol,
        "{what}: {c:?} against a gap of {g}"
    );
    let faces = around_a
        .iter()
        .map(|&t| -(pa.rotation * a.triangle_normal_scaled(t)))
        .chain(
            around_b
                .iter()
                .map(|&t| pb.rotation * b.triangle_normal_scaled(t)),
        )
        .filter_map(DVec3::try_normalize)
        .chain([gap / g]);
    assert!(
        faces.into_iter().any(|n| (n - c.normal).length() <= 1e-9),
        "{what}: {c:?} along no face at its features nor its gap"
    );
    if !(one_fan(c.feature_a, a, &around_a) && one_fan(c.feature_b, b, &around_b)) {
        return false;
    }
    for &i in &around_a {
        for &j in &around_b {
            let d = triangle_distance(&world(a, pa, i), &world(b, pb, j)).distance;
            assert!(
                d >= g - tol,
                "{what}: {c:?}: triangles {i} and {j} at its features are {d} apart, nearer than {g}"
            );
        }
    }
    true
}

/// Brute-force contacts: every pair, the same internal-edge rule, then the
/// check that the query's merged list is a subset of them and covers each
/// (a dropped contact duplicates a kept one at least as deep: same mesh
/// feature or the same point, and an agreeing normal). The corner contacts
/// (vertex/edge, edge/vertex, vertex/vertex), which no single pair can
/// judge, are checked one by one against their features
/// ([`check_corner_contact`]); and with them the smallest contact is
/// between half the meshes' brute-force distance and that distance when
/// the meshes are apart within the margin (the closest features are
/// found, whatever they are). Returns the corner contacts whose features'
/// fans were checked, by kind.
fn check_contacts(
    got: &[Contact],
    sa: &MeshShape,
    pa: &Pose,
    sb: &MeshShape,
    pb: &Pose,
    margin: f64,
    what: &str,
) -> Vec<ContactKind> {
    let (a, b) = (sa.mesh(), sb.mesh());
    let mut raw = vec![];
    for i in 0..a.triangles().len() {
        let x = world(a, pa, i);
        for j in 0..b.triangles().len() {
            let y = world(b, pb, j);
            if margin > 0.0 || tri_tri_overlap(&x, &y) {
                triangle_contacts(&x, i as u32, &y, j as u32, margin, &mut raw).unwrap();
            }
        }
    }
    let internal =
        |s: &MeshShape, f: Feature| matches!(f.sub, SubFeature::Edge(k) if s.is_flat_edge(f.index, k));
    raw.retain(|c| {
        !(c.kind == ContactKind::EdgeEdge && (internal(sa, c.feature_a) || internal(sb, c.feature_b)))
    });
    let corner = |c: &Contact| {
        matches!(
            c.kind,
            ContactKind::VertexEdge | ContactKind::EdgeVertex | ContactKind::VertexVertex
        )
    };
    let mut fans_checked = Vec::new();
    for c in got {
        if corner(c) {
            if check_corner_contact(c, (a, pa), (b, pb), margin, what) {
                fans_checked.push(c.kind);
            }
        } else {
            assert!(
                raw.contains(c),
                "{what}: reported contact not produced by any pair: {c:?}"
            );
        }
    }
    let apart = brute_distance(a, pa, b, pb);
    if apart > 0.0 && apart <= margin {
        let nearest = got.iter().map(|c| c.distance).fold(f64::INFINITY, f64::min);
        assert!(
            nearest >= 0.5 * apart - 1e-12 && nearest <= apart + 1e-9,
            "{what}: the nearest contact at {nearest}, the meshes {apart} apart"
        );
    }
    let min_cos = MergeParams::default().normal_angle.cos();
    let tol = MergeParams::default().point_tolerance;
    for c in &raw {
        let covered = got.iter().any(|k| {
            let same_feature = (global(k.feature_a, a), global(k.feature_b, b))
                == (global(c.feature_a, a), global(c.feature_b, b))
                && (global(c.feature_a, a).is_some() || global(c.feature_b, b).is_some());
            k.normal.dot(c.normal) >= min_cos
                && k.distance <= c.distance
                && (same_feature || (k.point - c.point).length() <= tol)
        });
        assert!(covered, "{what}: contact lost by merging: {c:?}");
    }
    // Merging removed duplicates only: never more contacts than the pairs gave,
    // and no two kept contacts are duplicates of each other by position.
    assert!(got.iter().filter(|c| !corner(c)).count() <= raw.len());
    for (i, x) in got.iter().enumerate() {
        for y in &got[i + 1..] {
            assert!(
                (x.point - y.point).length() > tol || x.normal.dot(y.normal) < min_cos,
                "{what}: duplicates kept: {x:?} {y:?}"
            );
        }
    }
    fans_checked
}

fn options(report: ReportMode, stop_at_first: bool, contact_margin: f64) -> CollideOptions {
    CollideOptions {
        stop_at_first,
        report,
        contact_margin,
    }
}

/// Every collide mode and `stop_at_first` against the all-pairs oracle.
fn check_collide(sa: &MeshShape, pa: &Pose, sb: &MeshShape, pb: &Pose, what: &str) -> usize {
    let want = brute_pairs(sa.mesh(), pa, sb.mesh(), pb);
    for mode in [
        ReportMode::Boolean,
        ReportMode::TrianglePairs,
        ReportMode::Contacts,
    ] {
        for stop in [false, true] {
            let rep = collide(sa, pa, sb, pb, &options(mode, stop, 0.0)).unwrap();
            let what = format!("{what} {mode:?} stop={stop}");
            assert_eq!(rep.intersect, !want.is_empty(), "{what}");
            match (mode, stop) {
                (ReportMode::Boolean, _) => assert!(rep.pairs.is_empty()),
                (_, false) => assert_eq!(rep.pairs, want, "{what}"),
                (_, true) => {
                    assert_eq!(rep.pairs.len(), want.len().min(1), "{what}");
                    assert!(rep.pairs.iter().all(|p| want.contains(p)), "{what}");
                }
            }
            if mode == ReportMode::Contacts && !stop {
                assert!(check_contacts(&rep.contacts, sa, pa, sb, pb, 0.0, &what).is_empty());
                // Every intersecting pair gives a penetrating contact before
                // merging, so intersecting meshes have contacts.
                assert_eq!(rep.contacts.is_empty(), want.is_empty(), "{what}");
            }
            if mode != ReportMode::Contacts {
                assert!(rep.contacts.is_empty());
            }
            assert!(rep.stats.triangle_tests >= rep.pairs.len() as u64);
        }
    }
    // Speculative contacts within a margin.
    let rep = collide(sa, pa, sb, pb, &options(ReportMode::Contacts, false, 0.3)).unwrap();
    assert_eq!(rep.pairs, want);
    let _ = check_contacts(&rep.contacts, sa, pa, sb, pb, 0.3, what);
    want.len()
}

/// Exact and approximate distances, closest points, and the tolerance query.
fn check_distance(
    sa: &MeshShape,
    pa: &Pose,
    sb: &MeshShape,
    pb: &Pose,
    r: &mut impl FnMut() -> f64,
    what: &str,
) {
    let (a, b) = (sa.mesh(), sb.mesh());
    let brute = brute_distance(a, pa, b, pb);
    let d = distance(sa, pa, sb, pb, &DistanceOptions::default()).unwrap();
    assert!(
        (d.distance - brute).abs() <= 1e-12 * brute,
        "{what}: {} vs brute force {brute}",
        d.distance
    );
    // The closest points lie on the named triangles, at that distance.
    let on = |p: DVec3, t: &[DVec3; 3]| (closest_point_on_triangle(p, t).0 - p).length() < 1e-9;
    assert!(on(d.point_a, &world(a, pa, d.tri_a as usize)), "{what}");
    assert!(
        on(d.point_b, &world(b, pb, d.tri_b as usize)),
        "{what}: {d:?} {:?} {:?}",
        world(a, pa, d.tri_a as usize),
        world(b, pb, d.tri_b as usize)
    );
    assert!(
        ((d.point_a - d.point_b).length() - d.distance).abs() < 1e-9,
        "{what}"
    );
    for (rel_err, abs_err) in [(0.1, 0.0), (0.0, 0.05), (0.5, 0.2)] {
        let o = DistanceOptions { rel_err, abs_err };
        let x = distance(sa, pa, sb, pb, &o).unwrap();
        let bound = ((1.0 + rel_err) * brute).max(brute + abs_err);
        assert!(
            x.distance >= brute * (1.0 - 1e-12) && x.distance <= bound * (1.0 + 1e-12),
            "{what}: {o:?} gave {} for {brute}",
            x.distance
        );
    }
    // Tolerance query: exactly `distance <= tol`, including tol == distance.
    let mut tols = vec![brute, brute + 0.1, r() * 2.0 * brute.max(0.1), 0.0];
    if brute > 0.0 {
        tols.push(brute * (1.0 - 1e-9));
    }
    for tol in tols {
        assert_eq!(
            within_tolerance(sa, pa, sb, pb, tol).unwrap(),
            d.distance <= tol,
            "{what}: tol {tol}, distance {}",
            d.distance
        );
    }
}

/// The contacts mode within a margin finds the closest features of two
/// closed convex meshes whatever they are: 300 random poses of a box
/// against a box and against a coarse ball, brought to a random gap within
/// a 2 cm margin, and one box's corner pointing at another's, checked by
/// [`check_contacts`] (the nearest contact
/// within [half, all] of the brute-force distance, each corner contact
/// against its features). Before the query reported vertex/edge,
/// edge/vertex and vertex/vertex contacts, the nearest contact in those
/// poses was that of farther features.
#[test]
fn the_closest_features_of_convex_meshes_are_found_within_the_margin() {
    use tumble_collide::mesh::{box_mesh, icosphere_mesh};
    let boxy = MeshShape::new(box_mesh(DVec3::new(0.3, 0.2, 0.1)).unwrap()).unwrap();
    let ball = MeshShape::new(icosphere_mesh(0.25, 1).unwrap()).unwrap();
    let mut r = rng(41);
    let margin = 0.02;
    let mut kinds = Vec::new();
    let turn = |r: &mut dyn FnMut() -> f64| {
        DQuat::from_scaled_axis(DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 6.0)
    };
    for case in 0..300 {
        let b = if case % 3 == 2 { &ball } else { &boxy };
        let pa = Pose::new(DVec3::ZERO, turn(&mut r)).unwrap();
        let turn_b = turn(&mut r);
        let dir = turn(&mut r) * DVec3::X;
        let target = 1e-4 + r() * (margin - 1e-4);
        // The distance changes by at most the move along `dir`, so each
        // step keeps B apart and converges on the target gap.
        let mut at = dir;
        for _ in 0..30 {
            let d = brute_distance(boxy.mesh(), &pa, b.mesh(), &Pose::new(at, turn_b).unwrap());
            at -= dir * (d - target);
        }
        let pb = Pose::new(at, turn_b).unwrap();
        let rep = collide(&boxy, &pa, b, &pb, &options(ReportMode::Contacts, false, margin)).unwrap();
        kinds.extend(check_contacts(
            &rep.contacts,
            &boxy,
            &pa,
            b,
            &pb,
            margin,
            &format!("case {case}"),
        ));
    }
    // A corner closest to a corner is rare at random poses: one box's
    // corner pointing at the other's, 4 mm apart along each axis.
    let (pa, pb) = (
        Pose::IDENTITY,
        Pose::from_translation(DVec3::new(0.604, 0.404, 0.204)),
    );
    let rep = collide(
        &boxy,
        &pa,
        &boxy,
        &pb,
        &options(ReportMode::Contacts, false, margin),
    )
    .unwrap();
    kinds.extend(check_contacts(
        &rep.contacts,
        &boxy,
        &pa,
        &boxy,
        &pb,
        margin,
        "corner to corner",
    ));
    for kind in [
        ContactKind::VertexEdge,
        ContactKind::EdgeVertex,
        ContactKind::VertexVertex,
    ] {
        assert!(kinds.contains(&kind), "{kind:?} never met: {kinds:?}");
    }
}

#[test]
fn soups_match_brute_force_in_every_mode() {
    let (mut intersecting, mut touching_grid, mut cases) = (0, 0, 0);
    for seed in 0..160u64 {
        let mut r = rng(seed);
        let na = 1 + (r() * 40.0) as usize;
        let nb = 1 + (r() * 40.0) as usize;
        let sa = MeshShape::new(soup(&mut r, na)).unwrap();
        let sb = MeshShape::new(soup(&mut r, nb)).unwrap();
        let grid = seed % 2 == 0;
        let (pa, pb) = if grid {
            (grid_pose(&mut r), grid_pose(&mut r))
        } else {
            (random_pose(&mut r, 1.0), random_pose(&mut r, 4.0))
        };
        let what = format!("seed {seed} (grid {grid}, {na} x {nb})");
        let n = check_collide(&sa, &pa, &sb, &pb, &what);
        check_distance(&sa, &pa, &sb, &pb, &mut r, &what);
        intersecting += (n > 0) as usize;
        touching_grid += (grid && n > 0) as usize;
        cases += 1;
        // A soup against itself: every triangle meets itself (coplanar,
        // identical, degenerate ones included).
        if seed % 8 == 0 {
            let pairs = check_collide(&sa, &pa, &sa, &pa, &format!("{what} self"));
            assert!(pairs >= na);
        }
    }
    // The cases are not all trivial.
    assert!(
        intersecting > cases / 4 && intersecting < cases,
        "{intersecting} of {cases}"
    );
    assert!(touching_grid > 10);
}

#[test]
fn touching_cases_on_the_grid_are_found_exactly() {
    // Two unit squares (as two triangles each) meeting exactly along an
    // edge, at a corner, and coplanar overlapping: exact predicates on exact
    // coordinates must report them; a hair apart they must not.
    let square = |z: f64| {
        TriMesh::new(
            vec![
                DVec3::new(0.0, 0.0, z),
                DVec3::new(1.0, 0.0, z),
                DVec3::new(1.0, 1.0, z),
                DVec3::new(0.0, 1.0, z),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .unwrap()
    };
    let s = MeshShape::new(square(0.0)).unwrap();
    let o = CollideOptions::default();
    let id = Pose::IDENTITY;
    for (shift, touching) in [
        (DVec3::new(1.0, 0.0, 0.0), true),         // shared edge
        (DVec3::new(1.0, 1.0, 0.0), true),         // shared corner
        (DVec3::new(0.5, 0.25, 0.0), true),        // coplanar overlap
        (DVec3::new(1.0 + 1e-9, 0.0, 0.0), false), // a hair apart
        (DVec3::new(0.25, 0.25, 1e-12), false),    // parallel, just above
    ] {
        let pb = Pose::from_translation(shift);
        let rep = collide(&s, &id, &s, &pb, &o).unwrap();
        assert_eq!(rep.intersect, touching, "{shift}");
        assert_eq!(rep.pairs, brute_pairs(s.mesh(), &id, s.mesh(), &pb));
        let d = distance(&s, &id, &s, &pb, &DistanceOptions::default()).unwrap();
        assert_eq!(d.distance == 0.0, touching);
    }
}

/// Independent brute-force distance of a primitive to one triangle.
fn primitive_triangle_distance(prim: &Shape, pose: &Pose, t: &[DVec3; 3]) -> f64 {
    match prim {
        Shape::Sphere(s) => {
            let c = pose.position;
            ((closest_point_on_triangle(c, t).0 - c).length() - s.radius()).max(0.0)
        }
        Shape::Capsule(c) => {
            let [p, q] = c.world_segment(pose);
            (triangle_distance(&[p, q, q], t).distance - c.radius()).max(0.0)
        }
        Shape::Cuboid(b) => {
            let axes = DMat3::from_quat(pose.rotation);
            if tri_box_overlap(t, pose.position, b.half_extents(), &axes) {
                return 0.0;
            }
            // Outside the box: distance to its surface, as 12 triangles.
            let h = b.half_extents();
            let corner = |i: usize| {
                pose.transform_point(DVec3::new(
                    if i & 1 != 0 { h.x } else { -h.x },
                    if i & 2 != 0 { h.y } else { -h.y },
                    if i & 4 != 0 { h.z } else { -h.z },
                ))
            };
            // Its own corner table, not mesh::box_mesh: the oracle stays apart from
            // the code it checks. (cli_queries.rs writes a 1-based OBJ cube, and
            // world_recorder.rs PALETTE is colours: alike in shape only.)
            let faces = [
                [0, 1, 3, 2],
                [4, 5, 7, 6],
                [0, 1, 5, 4],
                [2, 3, 7, 6],
                [0, 2, 6, 4],
                [1, 3, 7, 5],
            ];
            faces
                .iter()
                .flat_map(|f| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]])
                .map(|k| triangle_distance(&k.map(corner), t).distance)
                .fold(f64::INFINITY, f64::min)
        }
        Shape::HalfSpace(hs) => {
            let (n, d) = hs.world_plane(pose);
            t.iter()
                .map(|v| n.dot(*v) - d)
                .fold(f64::INFINITY, f64::min)
                .max(0.0)
        }
        other => panic!("{} is not a primitive", other.kind_name()),
    }
}

#[test]
fn primitives_against_soups_match_brute_force() {
    let prims: Vec<Shape> = vec![
        Sphere::new(0.6).unwrap().into(),
        Cuboid::new(DVec3::new(0.7, 0.4, 0.25)).unwrap().into(),
        Capsule::new(0.3, 0.8).unwrap().into(),
        HalfSpace::new(DVec3::new(0.36, 0.48, 0.8), -0.5).unwrap().into(),
    ];
    let mut hits = [0usize; 4];
    for seed in 0..120u64 {
        let mut r = rng(1000 + seed);
        let n = 1 + (r() * 40.0) as usize;
        let mesh = soup(&mut r, n);
        let shape = MeshShape::new(mesh.clone()).unwrap();
        let pm = if seed % 2 == 0 {
            grid_pose(&mut r)
        } else {
            random_pose(&mut r, 1.0)
        };
        for (k, prim) in prims.iter().enumerate() {
            let pp = random_pose(&mut r, 4.0);
            let what = format!("seed {seed} {}", prim.kind_name());
            let dists: Vec<f64> = (0..n)
                .map(|t| primitive_triangle_distance(prim, &pp, &world(&mesh, &pm, t)))
                .collect();
            let want: Vec<(u32, u32)> = (0..n as u32)
                .filter(|&t| dists[t as usize] == 0.0)
                .map(|t| (0, t))
                .collect();
            let brute = dists.iter().copied().fold(f64::INFINITY, f64::min);
            hits[k] += !want.is_empty() as usize;
            for mode in [
                ReportMode::Boolean,
                ReportMode::TrianglePairs,
                ReportMode::Contacts,
            ] {
                for stop in [false, true] {
                    let rep = collide_primitive(prim, &pp, &shape, &pm, &options(mode, stop, 0.0)).unwrap();
                    assert_eq!(rep.intersect, !want.is_empty(), "{what} {mode:?}");
                    match (mode, stop) {
                        (ReportMode::Boolean, _) => assert!(rep.pairs.is_empty()),
                        (_, false) => assert_eq!(rep.pairs, want, "{what} {mode:?}"),
                        (_, true) => {
                            assert_eq!(rep.pairs.len(), want.len().min(1));
                            assert!(rep.pairs.iter().all(|p| want.contains(p)));
                        }
                    }
                    // Contacts never claim a gap larger than the margin.
                    assert!(rep.contacts.iter().all(|c| c.distance <= 1e-12));
                }
            }
            let d = distance_primitive(prim, &pp, &shape, &pm, &DistanceOptions::default()).unwrap();
            assert!(
                (d.distance - brute).abs() <= 1e-12 * brute,
                "{what}: {} vs {brute}",
                d.distance
            );
            assert!(
                ((d.point_a - d.point_b).length() - d.distance).abs() < 1e-9,
                "{what}"
            );
            let approx = distance_primitive(
                prim,
                &pp,
                &shape,
                &pm,
                &DistanceOptions {
                    rel_err: 0.3,
                    abs_err: 0.0,
                },
            )
            .unwrap();
            assert!(
                approx.distance >= brute * (1.0 - 1e-12) && approx.distance <= 1.3 * brute * (1.0 + 1e-12)
            );
            for tol in [brute, brute * 0.5, brute + 0.2, 0.0] {
                assert_eq!(
                    within_tolerance_primitive(prim, &pp, &shape, &pm, tol).unwrap(),
                    brute <= tol,
                    "{what}: tol {tol} vs {brute}"
                );
            }
        }
    }
    // Both outcomes occur for every primitive often enough to mean something.
    assert!(hits.iter().all(|&h| h > 10) && hits[0] < 110, "{hits:?}");
}

#[test]
fn primitive_contacts_have_the_analytic_depth() {
    // A unit cube mesh (half extent 0.5) and primitives pushed into its top
    // face by 0.05 m (the half-space is the solid z >= 0.45): the deepest
    // contact is 0.05 deep along +z (from the mesh to the primitive).
    let cube = MeshShape::new(tumble_collide::mesh::box_mesh(DVec3::splat(0.5)).unwrap()).unwrap();
    let o = options(ReportMode::Contacts, false, 0.0);
    let cases: Vec<(Shape, Pose)> = vec![
        (
            Sphere::new(0.2).unwrap().into(),
            Pose::from_translation(DVec3::new(0.1, 0.05, 0.65)),
        ),
        (
            Cuboid::new(DVec3::splat(0.1)).unwrap().into(),
            Pose::from_translation(DVec3::new(0.1, 0.05, 0.55)),
        ),
        (
            Capsule::new(0.1, 0.2).unwrap().into(),
            Pose::from_translation(DVec3::new(0.1, 0.05, 0.75)),
        ),
        (
            HalfSpace::new(DVec3::new(0.0, 0.0, -1.0), -0.45).unwrap().into(),
            Pose::IDENTITY,
        ),
    ];
    for (prim, pose) in cases {
        let rep = collide_primitive(&prim, &pose, &cube, &Pose::IDENTITY, &o).unwrap();
        assert!(rep.intersect, "{prim:?}");
        let deepest = rep
            .contacts
            .iter()
            .max_by(|a, b| a.depth().total_cmp(&b.depth()))
            .unwrap();
        assert!((deepest.depth() - 0.05).abs() < 1e-9, "{prim:?}: {deepest:?}");
        assert!(
            (deepest.normal - DVec3::Z).length() < 1e-9,
            "{prim:?}: {deepest:?}"
        );
    }
}

/// shared/data/tori_pairs.json: `TORI_TRUTH`, or `shared/` beside the
/// repository (any ancestor of this crate holding `shared/data/`). The
/// home of this reader is `tumble::scenes::tori_truth`; the query crate's
/// tests cannot reach it (tumble depends on this crate, not the reverse).
fn tori_truth() -> Option<Vec<u64>> {
    let path = std::env::var("TORI_TRUTH")
        .ok()
        .map(std::path::PathBuf::from)
        .or_else(|| {
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .ancestors()
                .map(|a| a.join("shared/data/tori_pairs.json"))
                .find(|p| p.exists())
        })?;
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()?;
    v["pairs_per_pose"]
        .as_array()?
        .iter()
        .map(|x| x.as_u64())
        .collect()
}

/// The thesis' tori (shared/scenes.md): pairs per pose against the published
/// exact ground truth (122 colliding poses, 36,782 pairs; two pairs miss by
/// ~1e-6 m, so at most 2 off in total), first contact agreeing with it, and
/// distances at separated poses consistent with the tolerance query.
#[test]
fn tori_scene_matches_ground_truth() {
    let torus = MeshShape::new(torus_mesh(1.0, 0.3, 50, 50).unwrap()).unwrap();
    let q = DQuat::from_rotation_z(0.1) * DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2);
    let truth = tori_truth();
    if truth.is_none() {
        eprintln!("tori_pairs.json not found: checking the totals of scenes.md only");
    }
    let id = Pose::IDENTITY;
    let all = CollideOptions::default();
    let first = options(ReportMode::Boolean, true, 0.0);
    let (mut total, mut colliding, mut off) = (0i64, 0, 0i64);
    let mut first_cost = TraversalStats::default();
    let mut all_cost = TraversalStats::default();
    for k in 0..200 {
        let pb = Pose::new(DVec3::new(-3.0 + 6.0 * k as f64 / 199.0, 0.05, 0.02), q).unwrap();
        let rep = collide(&torus, &id, &torus, &pb, &all).unwrap();
        let n = rep.pairs.len() as i64;
        total += n;
        colliding += (n > 0) as i32;
        if let Some(t) = &truth {
            off += (n - t[k] as i64).abs();
            // Never a colliding pose missed or invented.
            assert_eq!(n > 0, t[k] > 0, "pose {k}");
        }
        let f = collide(&torus, &id, &torus, &pb, &first).unwrap();
        assert_eq!(f.intersect, n > 0, "pose {k}");
        if n > 0 {
            first_cost.bv_tests += f.stats.bv_tests;
            all_cost.bv_tests += rep.stats.bv_tests;
            assert!(f.stats.stopped_early && f.stats.triangle_tests <= rep.stats.triangle_tests);
        } else if k % 5 == 0 {
            let d = distance(&torus, &id, &torus, &pb, &DistanceOptions::default()).unwrap();
            assert!(d.distance > 0.0);
            assert!(within_tolerance(&torus, &id, &torus, &pb, d.distance).unwrap());
            assert!(!within_tolerance(&torus, &id, &torus, &pb, d.distance * (1.0 - 1e-9)).unwrap());
        }
    }
    assert_eq!(colliding, 122);
    assert!((total - 36_782).abs() <= 2, "{total} pairs");
    assert!(off <= 2, "{off} pairs differ from the per-pose truth");
    // Early exit: the first-contact walks do a small part of the work.
    assert!(
        first_cost.bv_tests * 10 < all_cost.bv_tests,
        "{first_cost:?} vs {all_cost:?}"
    );
}

#[test]
fn bad_input_gets_typed_errors() {
    let m = MeshShape::new(torus_mesh(1.0, 0.3, 8, 6).unwrap()).unwrap();
    let id = Pose::IDENTITY;
    let nan = Pose {
        position: DVec3::new(f64::NAN, 0.0, 0.0),
        rotation: DQuat::IDENTITY,
    };
    let skew = Pose {
        position: DVec3::ZERO,
        rotation: DQuat::from_xyzw(1.0, 1.0, 1.0, 1.0),
    };
    // tumble/tests/bad_input.rs `queries_reject_bad_poses_and_options` repeats
    // these through tumble for docs/validation.md; here they guard this crate alone.
    let o = CollideOptions::default();
    assert!(matches!(
        collide(&m, &nan, &m, &id, &o),
        Err(QueryError::BadPose {
            which: "pose_a",
            source: PoseError::NonFinitePosition(_)
        })
    ));
    assert!(matches!(
        collide(&m, &id, &m, &skew, &o),
        Err(QueryError::BadPose {
            which: "pose_b",
            source: PoseError::NonUnitRotation { .. }
        })
    ));
    assert!(matches!(
        distance(&m, &id, &m, &skew, &DistanceOptions::default()),
        Err(QueryError::BadPose { .. })
    ));
    assert!(matches!(
        within_tolerance(&m, &nan, &m, &id, 0.1),
        Err(QueryError::BadPose { .. })
    ));
    for tol in [-1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            within_tolerance(&m, &id, &m, &id, tol),
            Err(QueryError::BadOption { .. })
        ));
    }
    for (rel_err, abs_err) in [(-0.1, 0.0), (0.0, -1.0), (f64::NAN, 0.0), (0.0, f64::INFINITY)] {
        let e = distance(&m, &id, &m, &id, &DistanceOptions { rel_err, abs_err }).unwrap_err();
        assert!(matches!(e, QueryError::BadOption { .. }), "{e}");
    }
    let bad_margin = options(ReportMode::Contacts, false, -0.5);
    assert!(matches!(
        collide(&m, &id, &m, &id, &bad_margin),
        Err(QueryError::BadOption { .. })
    ));
    let s: Shape = Sphere::new(1.0).unwrap().into();
    // Hulls and meshes are not primitives: a typed error naming the query.
    let hull: Shape = ConvexHull::from_points(m.mesh().vertices()).unwrap().into();
    for not_prim in [hull, Shape::Mesh(m.clone())] {
        let kind = not_prim.kind_name();
        assert!(matches!(
            collide_primitive(&not_prim, &id, &m, &id, &o),
            Err(QueryError::NotPrimitive { query: "collide_primitive", kind: k }) if k == kind
        ));
        assert!(matches!(
            distance_primitive(&not_prim, &id, &m, &id, &DistanceOptions::default()),
            Err(QueryError::NotPrimitive {
                query: "distance_primitive",
                ..
            })
        ));
        assert!(matches!(
            within_tolerance_primitive(&not_prim, &id, &m, &id, 0.1),
            Err(QueryError::NotPrimitive {
                query: "within_tolerance_primitive",
                ..
            })
        ));
    }
    assert!(matches!(
        collide_primitive(&s, &nan, &m, &id, &o),
        Err(QueryError::BadPose { .. })
    ));
    assert!(matches!(
        distance_primitive(&s, &id, &m, &skew, &DistanceOptions::default()),
        Err(QueryError::BadPose { .. })
    ));
    assert!(matches!(
        within_tolerance_primitive(&s, &id, &m, &id, -1.0),
        Err(QueryError::BadOption { .. })
    ));
    // Meshes are validated where they are built, with typed errors that the
    // query error wraps.
    let nan_mesh = TriMesh::new(
        vec![DVec3::ZERO, DVec3::X, DVec3::new(f64::NAN, 0.0, 0.0)],
        vec![[0, 1, 2]],
    );
    assert!(matches!(
        nan_mesh,
        Err(MeshError::NonFiniteVertex { index: 2, .. })
    ));
    let out_of_range = TriMesh::new(vec![DVec3::ZERO, DVec3::X, DVec3::Y], vec![[0, 1, 3]]);
    assert!(matches!(
        out_of_range,
        Err(MeshError::IndexOutOfRange { vertex: 3, .. })
    ));
    let empty = TriMesh::new(vec![], vec![]);
    assert!(matches!(empty, Err(MeshError::Empty { .. })));
    let wrapped: QueryError = empty.unwrap_err().into();
    assert!(wrapped.to_string().contains("empty"));
    // The message says what, where and what was expected.
    let e = within_tolerance(&m, &id, &m, &id, -2.0).unwrap_err().to_string();
    assert!(e.contains("tol") && e.contains(">= 0") && e.contains("-2"), "{e}");
}
