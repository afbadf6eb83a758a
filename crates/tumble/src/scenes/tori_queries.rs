//! The tori query scene of shared/scenes.md ("tori"): the thesis' two tori
//! (`torus_mesh(1, 0.3, 50, 50)`, 5,000 triangles each), A at the origin and
//! B at 200 poses along a path through A's hole. Defined once here for
//! `tumble bench --scene tori`, the Rust peers (`peer-parry`, the criterion
//! benchmark) and the tests; the ground truth is shared/data/tori_pairs.json.

use tumble_collide::mesh::{torus_mesh, GeneratorError, TriMesh};
use tumble_collide::{DQuat, DVec3, Pose};

/// Poses along the path.
pub const TORI_POSES: usize = 200;

/// The torus of both bodies: `torus_mesh(1, 0.3, 50, 50)`.
pub fn tori_torus() -> Result<TriMesh, GeneratorError> {
    torus_mesh(1.0, 0.3, 50, 50)
}

/// Pose of torus B at pose `k` (0..200): `Rz(0.1) * Rx(pi/2)` at
/// `(-3 + 6 k / 199, 0.05, 0.02)`; torus A stays at the identity.
pub fn tori_pose(k: usize) -> Pose {
    let q = DQuat::from_rotation_z(0.1) * DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2);
    Pose {
        position: DVec3::new(-3.0 + 6.0 * k as f64 / 199.0, 0.05, 0.02),
        rotation: q,
    }
}

/// `count` pose indices spread evenly over 0..200,
/// `k = floor(i 199 / (count - 1) + 0.5)` (all of them for 200).
pub fn tori_pose_indices(count: usize) -> Vec<usize> {
    let count = count.clamp(1, TORI_POSES);
    if count == 1 {
        return vec![0];
    }
    let mut ks: Vec<usize> = (0..count)
        .map(|i| (i as f64 * 199.0 / (count - 1) as f64 + 0.5).floor() as usize)
        .collect();
    ks.dedup();
    ks
}

// tumble-collide/tests/query_oracle.rs (`tori_truth`) keeps a copy of this
// reader: the query crate's tests cannot depend on tumble.
/// The ground truth of the tori queries, intersecting triangle pairs per
/// pose (exact predicates), from `tori_pairs.json`: the file `TORI_TRUTH`
/// names, else `shared/data/tori_pairs.json` in the first ancestor of this
/// crate's directory that holds one (the repository's neighbour, as on
/// CI). `None` when no such file can be read or it does not hold one count
/// per pose.
pub fn tori_truth() -> Option<Vec<u64>> {
    let path = std::env::var_os("TORI_TRUTH")
        .map(std::path::PathBuf::from)
        .or_else(|| {
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .ancestors()
                .map(|a| a.join("shared/data/tori_pairs.json"))
                .find(|p| p.exists())
        })?;
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()?;
    let counts: Option<Vec<u64>> = v["pairs_per_pose"]
        .as_array()?
        .iter()
        .map(|x| x.as_u64())
        .collect();
    counts.filter(|t| t.len() == TORI_POSES)
}

/// Pair counts of a tori run (`counts[i]` at the i-th pose run) against
/// the truth at those poses: totals, colliding poses, the poses that
/// differ and by how much, and whether the totals agree within the two
/// near-miss pairs a tolerance may move (the harness's pass mark). The
/// truth fields are `null` without a truth.
pub fn tori_pair_check(counts: &[usize], truth: Option<&[u64]>) -> serde_json::Value {
    let total: usize = counts.iter().sum();
    let colliding = counts.iter().filter(|&&c| c > 0).count();
    let Some(truth) = truth else {
        return serde_json::json!({"total_pairs": total, "truth_total_pairs": null,
                                  "colliding_poses": colliding, "truth_colliding_poses": null});
    };
    let truth_total: u64 = truth.iter().sum();
    let diff = |(c, t): (&usize, &u64)| (*c as i64 - *t as i64).abs();
    serde_json::json!({
        "total_pairs": total,
        "truth_total_pairs": truth_total,
        "colliding_poses": colliding,
        "truth_colliding_poses": truth.iter().filter(|&&t| t > 0).count(),
        "poses_differing": counts.iter().zip(truth).filter(|p| diff(*p) != 0).count(),
        "max_abs_pose_difference": counts.iter().zip(truth).map(diff).max().unwrap_or(0),
        "within_two_pairs": (total as i64 - truth_total as i64).abs() <= 2,
    })
}

/// The `format` field of [`tori_plain_json`].
pub const TORI_PLAIN_FORMAT: &str = "tumble-tori-queries/1";

/// The tori query scene as plain data for other libraries: `{format, mesh:
/// {vertices, triangles}, poses: [{index, position, rotation}]}` for the
/// `count` poses of [`tori_pose_indices`] (quaternions `[x, y, z, w]`; torus
/// A at the identity). What `tumble bench --scene tori --poses P
/// --export-scene FILE` writes.
pub fn tori_plain_json(count: usize) -> Result<serde_json::Value, GeneratorError> {
    let mesh = tori_torus()?;
    let poses: Vec<serde_json::Value> = tori_pose_indices(count)
        .into_iter()
        .map(|k| {
            let p = tori_pose(k);
            serde_json::json!({"index": k, "position": p.position.to_array(), "rotation": p.rotation.to_array()})
        })
        .collect();
    Ok(serde_json::json!({
        "format": TORI_PLAIN_FORMAT,
        "mesh": {
            "vertices": mesh.vertices().iter().map(|v| v.to_array()).collect::<Vec<_>>(),
            "triangles": mesh.triangles(),
        },
        "poses": poses,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_path_runs_from_minus_three_to_three_through_every_pose() {
        assert_eq!(tori_pose(0).position.x, -3.0);
        assert_eq!(tori_pose(199).position.x, 3.0);
        assert_eq!(tori_pose_indices(200), (0..200).collect::<Vec<_>>());
        assert_eq!(tori_pose_indices(3), vec![0, 100, 199]);
        assert_eq!(tori_pose_indices(5), vec![0, 50, 100, 149, 199]);
        // Ring axis of B: Rx(pi/2) maps z to -y, Rz(0.1) turns it.
        let axis = tori_pose(0).transform_vector(DVec3::Z);
        assert!((axis - DVec3::new(0.1f64.sin(), -(0.1f64.cos()), 0.0)).length() < 1e-12);
        assert_eq!(tori_pose_indices(1), vec![0]);
        assert_eq!(tori_torus().unwrap().triangles().len(), 5000);
    }

    #[test]
    fn pair_counts_are_judged_against_the_truth_pose_by_pose() {
        let c = tori_pair_check(&[0, 5, 7], Some(&[0, 5, 6]));
        assert_eq!(
            (c["total_pairs"].as_u64(), c["truth_total_pairs"].as_u64()),
            (Some(12), Some(11))
        );
        assert_eq!(
            (
                c["poses_differing"].as_u64(),
                c["max_abs_pose_difference"].as_u64()
            ),
            (Some(1), Some(1))
        );
        assert_eq!(
            (c["colliding_poses"].as_u64(), c["within_two_pairs"].as_bool()),
            (Some(2), Some(true))
        );
        assert_eq!(tori_pair_check(&[0, 9], Some(&[0, 5]))["within_two_pairs"], false);
        assert!(tori_pair_check(&[1], None)["truth_total_pairs"].is_null());
        // The shared truth file (beside the repository): 122 colliding poses, 36,782 pairs.
        let truth = tori_truth().expect("shared/data/tori_pairs.json beside the repository");
        assert_eq!(truth.iter().sum::<u64>(), 36_782);
        assert_eq!(truth.iter().filter(|&&t| t > 0).count(), 122);
    }

    #[test]
    fn the_plain_form_carries_the_poses_asked_for_and_the_torus() {
        let j = tori_plain_json(5).unwrap();
        assert_eq!(j["format"], TORI_PLAIN_FORMAT);
        let poses = j["poses"].as_array().unwrap();
        let ks: Vec<u64> = poses.iter().map(|p| p["index"].as_u64().unwrap()).collect();
        assert_eq!(ks, vec![0, 50, 100, 149, 199]);
        for p in poses {
            let pose = tori_pose(p["index"].as_u64().unwrap() as usize);
            let floats = |v: &serde_json::Value| -> Vec<f64> {
                v.as_array()
                    .unwrap()
                    .iter()
                    .map(|x| x.as_f64().unwrap())
                    .collect()
            };
            assert_eq!(floats(&p["position"]), pose.position.to_array());
            assert_eq!(floats(&p["rotation"]), pose.rotation.to_array());
        }
        assert_eq!(j["mesh"]["triangles"].as_array().unwrap().len(), 5000);
        assert_eq!(j["mesh"]["vertices"].as_array().unwrap().len(), 2500);
    }
}
