//! The scene files of `examples/scenes/`: each one loads and runs, and the
//! standard scenes build the same world as their definitions in code
//! (`tumble::scenes`), so that a scene is defined once in substance.

use std::path::{Path, PathBuf};

use tumble::body::BodyKind;
use tumble::scene::load_scene;
use tumble::scenes::{self, Scene};
use tumble::world::{BodyId, World};

fn examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scenes")
}

fn example_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(examples_dir())
        .expect("examples/scenes exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("toml" | "json")))
        .collect();
    files.sort();
    files
}

#[test]
fn every_example_scene_loads_and_runs() {
    let files = example_files();
    assert!(files.len() >= 10, "expected the example scenes, found {files:?}");
    for file in files {
        let loaded = load_scene(&file).unwrap_or_else(|e| panic!("{e}"));
        let (mut world, ids) = loaded.build().unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(ids.len(), loaded.scene.bodies.len());
        assert!(loaded.scene.steps > 0);
        let before: Vec<_> = ids.iter().map(|&id| world.pose(id).unwrap()).collect();
        for _ in 0..3 {
            let report = world.step();
            assert!(
                report.quarantined.is_empty(),
                "{}: bodies quarantined",
                file.display()
            );
        }
        for (k, &id) in ids.iter().enumerate() {
            let p = world.pose(id).unwrap();
            assert!(
                p.position.is_finite() && p.rotation.is_finite(),
                "{}: body {k} pose not finite",
                file.display()
            );
            // Static bodies stay exactly where the file put them.
            if world.body(id).unwrap().kind() == BodyKind::Static {
                assert_eq!(p, before[k], "{}: static body {k} moved", file.display());
            }
        }
        // Something moves in every example (gravity, a push or a spin).
        assert!(
            ids.iter()
                .zip(&before)
                .any(|(&id, b)| world.pose(id).unwrap() != *b),
            "{}: nothing moved",
            file.display()
        );
    }
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
}

/// The two worlds hold the same bodies: kind, name, material, damping, model
/// pose, centre of mass, mass, world inertia tensor and velocities.
fn assert_same_world(what: &str, a: (&World, &[BodyId]), b: (&World, &[BodyId])) {
    let tol = 1e-12;
    assert_eq!(a.0.settings(), b.0.settings(), "{what}: settings");
    assert_eq!(a.1.len(), b.1.len(), "{what}: body count");
    for (k, (&ia, &ib)) in a.1.iter().zip(b.1).enumerate() {
        let (ba, bb) = (a.0.body(ia).unwrap(), b.0.body(ib).unwrap());
        let ctx = format!("{what}: body {k} ({})", a.0.name(ia).unwrap());
        assert_eq!(ba.kind(), bb.kind(), "{ctx}: kind");
        assert_eq!(a.0.name(ia).unwrap(), b.0.name(ib).unwrap(), "{ctx}: name");
        assert_eq!(ba.material(), bb.material(), "{ctx}: material");
        assert_eq!(ba.linear_damping(), bb.linear_damping(), "{ctx}: damping");
        assert_eq!(ba.angular_damping(), bb.angular_damping(), "{ctx}: damping");
        let (pa, pb) = (a.0.pose(ia).unwrap(), b.0.pose(ib).unwrap());
        assert!(
            (pa.position - pb.position).length() < 1e-9,
            "{ctx}: position {} vs {}",
            pa.position,
            pb.position
        );
        // q and -q are the same rotation.
        assert!(
            pa.rotation.dot(pb.rotation).abs() > 1.0 - 1e-12,
            "{ctx}: orientation"
        );
        let (ca, cb) = (a.0.center_of_mass(ia).unwrap(), b.0.center_of_mass(ib).unwrap());
        assert!((ca - cb).length() < 1e-9, "{ctx}: centre of mass");
        assert!(
            close(ba.inv_mass(), bb.inv_mass(), tol),
            "{ctx}: mass {} vs {}",
            ba.mass(),
            bb.mass()
        );
        // The inertia tensor in the world frame does not depend on how the
        // principal axes were numbered (cubes have three equal moments).
        let (ja, jb) = (ba.inv_inertia_world(), bb.inv_inertia_world());
        let scale = ja.to_cols_array().iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for (x, y) in ja.to_cols_array().iter().zip(jb.to_cols_array()) {
            assert!(
                (x - y).abs() <= 1e-9 * scale.max(1e-300),
                "{ctx}: inertia {ja} vs {jb}"
            );
        }
        assert!(
            (a.0.linear_velocity(ia).unwrap() - b.0.linear_velocity(ib).unwrap()).length() < 1e-12,
            "{ctx}: linear velocity"
        );
        assert!(
            (a.0.angular_velocity(ia).unwrap() - b.0.angular_velocity(ib).unwrap()).length() < 1e-12,
            "{ctx}: angular velocity"
        );
    }
}

#[test]
fn standard_scene_files_build_the_worlds_of_the_code() {
    let pairs: [(&str, Scene); 8] = [
        ("pyramid.toml", scenes::pyramid()),
        ("pile.toml", scenes::pile(10)),
        ("chain.toml", scenes::chain()),
        ("cradle.toml", scenes::cradle()),
        ("incline_mu0.2.toml", scenes::incline(0.2)),
        ("incline_mu0.7.toml", scenes::incline(0.7)),
        ("domino.toml", scenes::domino()),
        ("tori_pass.toml", scenes::tori_pass()),
    ];
    for (file, code) in pairs {
        let loaded = load_scene(examples_dir().join(file)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(loaded.scene.name, code.name, "{file}: name");
        assert_eq!(loaded.scene.steps, code.steps, "{file}: steps");
        assert!(loaded.initial_loads.is_empty(), "{file}: initial loads");
        let (wf, idf) = loaded.build().unwrap_or_else(|e| panic!("{e}"));
        let (wc, idc) = code.build().unwrap();
        assert_same_world(file, (&wf, &idf), (&wc, &idc));
        // Same shapes, body by body (shape kinds and geometry after placement).
        for (k, (&a, &b)) in idf.iter().zip(&idc).enumerate() {
            let (ca, cb) = (wf.colliders(a).unwrap(), wc.colliders(b).unwrap());
            assert_eq!(ca.len(), cb.len(), "{file}: body {k} collider count");
            for (x, y) in ca.iter().zip(cb) {
                assert_eq!(x.shape.kind_name(), y.shape.kind_name(), "{file}: body {k} shape");
                if let (tumble::collide::shape::Shape::Mesh(mx), tumble::collide::shape::Shape::Mesh(my)) =
                    (&x.shape, &y.shape)
                {
                    assert_eq!(mx.mesh(), my.mesh(), "{file}: body {k} mesh");
                }
            }
        }
    }
}

/// The Dzhanibekov example does what its comment says: spun about its
/// intermediate principal axis (x), the T-handle flips over (its x axis turns
/// to point against the fixed angular momentum) and back, while energy and
/// angular momentum stay constant (torque-free body, splitting integrator).
#[test]
fn dzhanibekov_example_flips_and_conserves_energy_and_momentum() {
    let loaded = load_scene(examples_dir().join("dzhanibekov.toml")).unwrap();
    let (mut world, ids) = loaded.build().unwrap();
    let id = ids[0];
    let body = |w: &World| w.body(id).unwrap().clone();
    let (e0, l0) = (body(&world).kinetic_energy(), body(&world).angular_momentum());
    let axis_along_l =
        |w: &World| (w.orientation(id).unwrap() * tumble::collide::DVec3::X).dot(l0.normalize());
    assert!(axis_along_l(&world) > 0.99, "starts spinning about x");
    let (mut lowest, mut back_up) = (1.0f64, false);
    // Largest relative energy error in each half of the run: bounded and not
    // growing (no secular drift), as for a symplectic method.
    let mut energy_error = [0.0f64; 2];
    let steps = loaded.scene.steps;
    for step in 0..steps {
        world.step();
        let c = axis_along_l(&world);
        lowest = lowest.min(c);
        back_up |= lowest < -0.9 && c > 0.9;
        let b = body(&world);
        let half = usize::from(2 * step >= steps);
        energy_error[half] = energy_error[half].max((b.kinetic_energy() - e0).abs() / e0);
        assert!(
            (b.angular_momentum() - l0).length() < 1e-9 * l0.length(),
            "L drifts"
        );
    }
    assert!(energy_error[1] < 1e-3, "energy error {energy_error:?}");
    assert!(
        energy_error[1] < 2.0 * energy_error[0] + 1e-12,
        "energy drifts: {energy_error:?}"
    );
    assert!(lowest < -0.9, "the handle never flipped (lowest cos {lowest})");
    assert!(back_up, "the handle did not flip back within {} s", world.time());
}
