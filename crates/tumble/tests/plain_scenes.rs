//! The standard scenes as plain data (`Scene::plain`, `Scene::to_plain_json`),
//! the one description the benchmark's peers build from: layouts as
//! scenes.md states them, mass properties equal to the closed forms of the
//! solids, the decomposed chain the same chain, and the JSON form saying the
//! same thing as the Rust form.

use std::f64::consts::PI;
use tumble::body::BodyKind;
use tumble::collide::shape::Shape;
use tumble::collide::DVec3;
use tumble::scenes::{self, PlainScene, CHAIN_MAX_CENTRE_DISTANCE, PLAIN_SCENE_FORMAT};

fn dynamic(plain: &PlainScene) -> Vec<&scenes::PlainBody> {
    plain
        .bodies
        .iter()
        .filter(|b| b.kind == BodyKind::Dynamic)
        .collect()
}

/// A JSON array of numbers.
fn floats(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs().max(1e-300)
}

#[test]
fn pyramid_boxes_stand_in_layers_0_05_m_apart_with_unit_mass() {
    let plain = scenes::pyramid().plain().unwrap();
    let boxes = dynamic(&plain);
    assert_eq!(boxes.len(), 210);
    assert_eq!(boxes.last().unwrap().pose.position, DVec3::new(0.0, 0.0, 19.5));
    assert!((boxes[1].pose.position.x - boxes[0].pose.position.x - 1.05).abs() < 1e-12);
    assert!((boxes[0].pose.position.x + boxes[19].pose.position.x).abs() < 1e-12);
    for b in &boxes {
        // A unit cube of 1 kg: I = m (1^2 + 1^2) / 12 about every axis.
        assert!(close(b.mass, 1.0, 1e-12));
        for i in b.principal_inertia.to_array() {
            assert!(close(i, 1.0 / 6.0, 1e-12), "{i}");
        }
        assert!(matches!(b.shapes[0].shape, Shape::Cuboid(_)));
    }
    assert_eq!(plain.dt, 1.0 / 60.0);
    assert_eq!(plain.gravity, DVec3::new(0.0, 0.0, -9.81));
}

#[test]
fn pile_bodies_start_inside_their_container_with_the_solids_mass_properties() {
    for layers in [1, 10, 100] {
        let plain = scenes::pile(layers).plain().unwrap();
        let bodies = dynamic(&plain);
        assert_eq!(bodies.len(), 100 * layers);
        let wall_top = plain
            .bodies
            .iter()
            .filter(|b| b.kind == BodyKind::Static)
            .map(|b| match &b.shapes[0].shape {
                Shape::Cuboid(c) => b.pose.position.z + c.half_extents().z,
                _ => f64::NEG_INFINITY,
            })
            .fold(f64::NEG_INFINITY, f64::max);
        // The walls reach 8 m, or 1 m above the top layer's centre.
        let top_centre = 1.0 + 0.6 * (layers - 1) as f64;
        assert!(
            (wall_top - f64::max(8.0, top_centre + 1.0)).abs() < 1e-12,
            "{wall_top}"
        );
        let centres: Vec<DVec3> = bodies.iter().map(|b| b.pose.position).collect();
        assert_eq!(scenes::pile_outside(&centres), 0);
        let mut spheres = 0;
        for b in &bodies {
            let c = b.pose.position;
            // scenes.md as written: the odd layers' offset puts the outermost
            // bodies 0.05 m into the +x / +y walls (inner faces at 3 m).
            assert!(c.x.abs() + 0.25 <= 3.05 + 1e-9 && c.y.abs() + 0.25 <= 3.05 + 1e-9);
            assert!(c.z + 0.25 < wall_top, "a body starts above the walls");
            let (m, i) = match &b.shapes[0].shape {
                Shape::Sphere(_) => {
                    spheres += 1;
                    let m = 4.0 / 3.0 * PI * 0.25f64.powi(3);
                    (m, 0.4 * m * 0.0625)
                }
                _ => (0.125, 0.125 * 0.25 / 6.0),
            };
            assert!(close(b.mass, m, 1e-12), "{} vs {m}", b.mass);
            for got in b.principal_inertia.to_array() {
                assert!(close(got, i, 1e-9), "{got} vs {i}");
            }
        }
        assert_eq!(spheres * 2, bodies.len());
    }
    // A body that left: beyond the walls, under the floor or NaN.
    let out = [
        DVec3::new(3.2, 0.0, 1.0),
        DVec3::new(0.0, 0.0, -0.1),
        DVec3::NAN,
        DVec3::new(1.0, 1.0, 1.0),
    ];
    assert_eq!(scenes::pile_outside(&out), 3);
}

#[test]
fn chain_links_interlock_with_the_solid_torus_mass_and_the_decomposed_chain_is_the_same_chain() {
    let plain = scenes::chain().plain().unwrap();
    let cut = scenes::chain_decomposed().plain().unwrap();
    let (big_r, r) = (1.0f64, 0.2f64);
    let m = 2.0 * PI * PI * big_r * r * r;
    // Solid torus about its centre: Ixx = Iyy = m (R^2/2 + 5 r^2/8), Izz = m (R^2 + 3 r^2/4).
    let (i_side, i_axis) = (
        m * (big_r * big_r / 2.0 + 5.0 * r * r / 8.0),
        m * (big_r * big_r + 0.75 * r * r),
    );
    for p in [&plain, &cut] {
        assert_eq!(p.bodies.len(), 21);
        assert_eq!(p.bodies[0].kind, BodyKind::Static);
        for pair in p.bodies.windows(2) {
            let d = (pair[0].pose.position - pair[1].pose.position).length();
            assert!((d - 1.5).abs() < 1e-9 && d < CHAIN_MAX_CENTRE_DISTANCE, "{d}");
        }
        for link in &p.bodies[1..] {
            assert!(close(link.mass, m, 1e-12));
            let mut inertia = link.principal_inertia.to_array();
            inertia.sort_by(f64::total_cmp);
            // The tessellation (32 x 12) is within 1 % of the solid.
            assert!(
                close(inertia[0], i_side, 0.01) && close(inertia[1], i_side, 0.01),
                "{inertia:?}"
            );
            assert!(close(inertia[2], i_axis, 0.01), "{inertia:?}");
        }
    }
    // Each piece (a tube segment between two rings, bounded by planar
    // quads) is convex, so the pieces tile the link mesh exactly: the same
    // volume distribution, the same inertia.
    for (a, b) in plain.bodies.iter().zip(&cut.bodies) {
        assert!((a.pose.position - b.pose.position).length() < 1e-9);
        for (x, y) in a
            .principal_inertia
            .to_array()
            .iter()
            .zip(b.principal_inertia.to_array())
        {
            assert!(close(*x, y, 1e-9) || (*x == 0.0 && y == 0.0), "{x} vs {y}");
        }
    }
    assert!(matches!(
        plain.bodies[1].shapes[..],
        [scenes::PlainShape {
            shape: Shape::Mesh(_),
            ..
        }]
    ));
    assert_eq!(cut.bodies[1].shapes.len(), 32);
    assert!(cut.bodies[1]
        .shapes
        .iter()
        .all(|s| matches!(s.shape, Shape::ConvexHull(_))));
}

#[test]
fn cradle_keeps_its_striker_and_elastic_frictionless_spheres() {
    let plain = scenes::cradle().plain().unwrap();
    assert_eq!(plain.bodies.len(), 6);
    assert_eq!(plain.gravity, DVec3::ZERO);
    for (k, b) in plain.bodies.iter().enumerate() {
        assert_eq!((b.friction, b.restitution, b.mass), (0.0, 1.0, 1.0));
        let v = if k == 5 { 1.0 } else { 0.0 };
        assert_eq!(b.linear_velocity, DVec3::new(v, 0.0, 0.0));
    }
}

#[test]
fn json_form_says_what_the_plain_form_says() {
    let scene = scenes::chain();
    let plain = scene.plain().unwrap();
    let j = scene.to_plain_json().unwrap();
    assert_eq!(j["format"], PLAIN_SCENE_FORMAT);
    assert_eq!(j["name"], "chain");
    assert_eq!(j["steps"], 600);
    assert_eq!(
        j["limits"]["max_adjacent_centre_distance"],
        CHAIN_MAX_CENTRE_DISTANCE
    );
    // The link mesh is written once and named by every link.
    let meshes = j["meshes"].as_array().unwrap();
    assert_eq!(meshes.len(), 1);
    assert_eq!(meshes[0]["triangles"].as_array().unwrap().len(), 768);
    let bodies = j["bodies"].as_array().unwrap();
    for (b, p) in bodies.iter().zip(&plain.bodies) {
        assert_eq!(b["shapes"][0]["type"], "mesh");
        assert_eq!(b["shapes"][0]["mesh"], 0);
        assert_eq!(floats(&b["position"]), p.pose.position.to_array());
        assert_eq!(floats(&b["rotation"]), p.pose.rotation.to_array());
        assert_eq!(b["mass"].as_f64().unwrap(), p.mass);
    }
    assert_eq!(bodies[0]["kind"], "static");
    // Every standard scene without joints has a plain JSON form.
    for s in [
        scenes::pyramid(),
        scenes::pile(1),
        scenes::cradle(),
        scenes::domino(),
        scenes::chain_decomposed(),
    ] {
        let j = s.to_plain_json().unwrap();
        assert_eq!(
            j["bodies"].as_array().unwrap().len(),
            s.bodies.len(),
            "{}",
            s.name
        );
    }
    let pile = scenes::pile(1).to_plain_json().unwrap();
    assert_eq!(
        pile["limits"]["inside_half_width"],
        scenes::PILE_INSIDE_HALF_WIDTH
    );
    assert_eq!(pile["bodies"][0]["shapes"][0]["type"], "box");
    assert_eq!(pile["bodies"][5]["shapes"][0]["type"], "sphere");
    // The concave pile's bin, which the peers count escapes from.
    let concave = scenes::concave_pile(10).to_plain_json().unwrap();
    assert_eq!(
        concave["limits"]["inside_half_width"],
        scenes::CONCAVE_BIN_INNER_HALF_WIDTH
    );
}

#[test]
fn json_form_carries_gears_and_pairs_kept_apart_by_index() {
    let mut s = scenes::heavy_chain();
    s.gears.push(scenes::SceneGear {
        follower: 1,
        leader: 0,
        ratio: -2.0,
        offset: 0.25,
    });
    s.no_contact.push((1, 3));
    let j = s.to_plain_json().unwrap();
    let gear = &j["gears"][0];
    assert_eq!(
        (
            &gear["follower"],
            &gear["leader"],
            &gear["ratio"],
            &gear["offset"]
        ),
        (&1.into(), &0.into(), &(-2.0).into(), &0.25.into())
    );
    assert_eq!(j["no_contact"], serde_json::json!([[1, 3]]));
    // The standard scenes have neither: empty lists, which the peers accept.
    let pyramid = scenes::pyramid().to_plain_json().unwrap();
    assert_eq!(pyramid["gears"], serde_json::json!([]));
    assert_eq!(pyramid["no_contact"], serde_json::json!([]));
}
