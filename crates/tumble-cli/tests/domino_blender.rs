//! The animation demo: the domino run exported for Blender
//! (`tumble run examples/scenes/domino.toml --out domino.glb`, manual chapter
//! "Demos"). The glTF has a node and an animation channel per domino, and
//! the trajectory written alongside shows the chain reaction: every domino
//! falls, each after the one before it.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn every_domino_falls_in_order_and_the_glb_animates_them() {
    let dir = std::env::temp_dir().join(format!("tumble-domino-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (glb, csv) = (dir.join("domino.glb"), dir.join("domino.csv"));
    let status = Command::new(env!("CARGO_BIN_EXE_tumble"))
        .args(["run", "--quiet"])
        .arg(repo().join("examples/scenes/domino.toml"))
        .arg("--out")
        .arg(&glb)
        .arg("--trajectory")
        .arg(&csv)
        .status()
        .unwrap();
    assert!(status.success());

    // A domino (half extents 0.05 x 0.4 x 0.8 m) stands with its centre at
    // 0.8 m; tipped 45 degrees about a bottom edge the centre is at
    // 0.8 cos 45 + 0.05 sin 45 = 0.60 m. It has fallen when it is below that.
    let fallen_height = 0.8 * std::f64::consts::FRAC_1_SQRT_2 + 0.05 * std::f64::consts::FRAC_1_SQRT_2;
    let mut fall_time: BTreeMap<usize, f64> = BTreeMap::new();
    let mut seen = BTreeMap::new();
    let text = std::fs::read_to_string(&csv).unwrap();
    for line in text.lines().skip(1) {
        let cols: Vec<&str> = line.split(',').collect();
        let Some(k) = cols[1].strip_prefix("domino") else {
            continue;
        };
        let k: usize = k.parse().unwrap();
        let (t, z): (f64, f64) = (cols[0].parse().unwrap(), cols[4].parse().unwrap());
        seen.insert(k, ());
        if t == 0.0 {
            assert!((z - 0.8).abs() < 1e-12, "domino{k} starts upright");
        }
        if z < fallen_height {
            fall_time.entry(k).or_insert(t);
        }
    }
    assert_eq!(seen.len(), 30);
    assert_eq!(
        fall_time.len(),
        30,
        "fallen: {:?}",
        fall_time.keys().collect::<Vec<_>>()
    );
    let times: Vec<f64> = fall_time.values().copied().collect();
    for k in 1..times.len() {
        assert!(
            times[k] > times[k - 1],
            "domino{k} fell at {} s, not after domino{} ({} s)",
            times[k],
            k - 1,
            times[k - 1]
        );
    }

    // The glTF Blender imports: one node per body under the z-up root, one
    // animation with a rotation channel for every domino.
    let g = gltf::Gltf::open(&glb).unwrap();
    let names: Vec<String> = g.nodes().filter_map(|n| n.name().map(String::from)).collect();
    for k in 0..30 {
        assert!(names.contains(&format!("domino{k}")), "no node domino{k}");
    }
    let anim = g.animations().next().expect("an animation");
    let rotated = anim
        .channels()
        .filter(|c| c.target().property() == gltf::animation::Property::Rotation)
        .filter(|c| c.target().node().name().is_some_and(|n| n.starts_with("domino")))
        .count();
    assert_eq!(rotated, 30);
    std::fs::remove_dir_all(&dir).unwrap();
}
