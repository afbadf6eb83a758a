//! `tumble bench --scene tori`: the thesis' torus pair (shared/scenes.md,
//! "tori") through the query API, in the JSON record of the benchmark
//! harness (docs/benchmarks.md; the same figures as `peer-parry`).
//!
//! Per pose, each query from scratch and timed alone: (1) first contact
//! (boolean, stop at the first pair), (2) all intersecting triangle pairs,
//! (3) all pairs with contacts, (4) exact minimum distance at the poses that
//! the ground truth calls separated. Pair counts are checked against
//! `shared/data/tori_pairs.json`, found through `TORI_TRUTH` or beside the
//! repository (the first ancestor of this crate holding `shared/data/`).

use crate::CliError;
use serde_json::{json, Value};
use std::time::Instant;

use tumble_collide::query::{self, CollideOptions, DistanceOptions, MeshShape, ReportMode};
use tumble_collide::Pose;

pub use tumble::scenes::TORI_POSES;
use tumble::scenes::{tori_pair_check, tori_pose, tori_pose_indices, tori_truth, TimingStats};

/// Runs the tori queries at `poses` poses and returns the record's
/// `(settings, figures)`.
pub fn run(poses: usize) -> Result<(Value, Value), CliError> {
    let internal = |e: &dyn std::fmt::Display| CliError::Internal(e.to_string());
    let mesh = tumble::scenes::tori_torus().map_err(|e| internal(&e))?;
    let build = Instant::now();
    let torus = MeshShape::new(mesh).map_err(|e| internal(&e))?;
    let build_s = build.elapsed().as_secs_f64();
    let truth_all = tori_truth();
    let ks = tori_pose_indices(poses);
    let truth: Option<Vec<u64>> = truth_all.as_ref().map(|t| ks.iter().map(|&k| t[k]).collect());
    let pa = Pose::IDENTITY;
    let first = CollideOptions {
        stop_at_first: true,
        report: ReportMode::Boolean,
        contact_margin: 0.0,
    };
    let pairs = CollideOptions::default();
    let contacts = CollideOptions {
        report: ReportMode::Contacts,
        ..CollideOptions::default()
    };
    let q = |e: query::QueryError| internal(&e);
    let (mut t_first, mut t_all, mut t_contacts, mut t_dist) = (vec![], vec![], vec![], vec![]);
    let (mut hits, mut counts, mut contact_counts, mut points, mut dists) = (0, vec![], vec![], 0, vec![]);
    let mut colliding = vec![];
    for (i, &k) in ks.iter().enumerate() {
        let pb = tori_pose(k);
        let t = Instant::now();
        let r = query::collide(&torus, &pa, &torus, &pb, &first).map_err(q)?;
        t_first.push(t.elapsed().as_secs_f64());
        hits += r.intersect as usize;

        let t = Instant::now();
        let r = query::collide(&torus, &pa, &torus, &pb, &pairs).map_err(q)?;
        t_all.push(t.elapsed().as_secs_f64());
        counts.push(r.pairs.len());

        let t = Instant::now();
        let r = query::collide(&torus, &pa, &torus, &pb, &contacts).map_err(q)?;
        t_contacts.push(t.elapsed().as_secs_f64());
        contact_counts.push(r.pairs.len());
        points += r.contacts.len();

        let separated = match &truth {
            Some(t) => t[i] == 0,
            None => counts[i] == 0,
        };
        colliding.push(!separated);
        if separated {
            let t = Instant::now();
            let d = query::distance(&torus, &pa, &torus, &pb, &DistanceOptions::default()).map_err(q)?;
            t_dist.push(t.elapsed().as_secs_f64());
            dists.push(d.distance);
        }
    }
    let tree = torus.tree().stats();
    let settings = json!({
        "bv": "OBB (OBBTree, f32 nodes, leaf size 2)",
        "precision": "f64 (boxes stored in f32, rounded outward)",
        "poses": ks.len(),
        "mesh": "torus_mesh(1.0, 0.3, 50, 50), 5000 triangles",
        "notes": "first contact = collide Boolean with stop_at_first; all pairs = collide TrianglePairs \
                  (exact closed triangle test); contacts = collide Contacts, margin 0, merged; \
                  distance = exact (rel_err = abs_err = 0)",
        "truth_file_found": truth_all.is_some(),
    });
    let figures = json!({
        "first_contact": TimingStats::us_split(&t_first, &colliding),
        "first_contact_colliding_poses": hits,
        "all_pairs": TimingStats::us_split(&t_all, &colliding),
        "all_pairs_check": tori_pair_check(&counts, truth.as_deref()),
        "all_pairs_with_contacts": TimingStats::us_split(&t_contacts, &colliding),
        "all_pairs_with_contacts_check": tori_pair_check(&contact_counts, truth.as_deref()),
        "contact_points": points,
        "distance_separated": TimingStats::us(&t_dist),
        "distance_min_m": dists.iter().copied().reduce(f64::min),
        "distance_negative_at_separated_poses": dists.iter().filter(|&&d| d < 0.0).count(),
        // Two tori, one model each (this run shares one object for both),
        // geometry included as every peer counts it (docs/benchmarks.md);
        // the tree alone beside it.
        "tree_memory_bytes": 2 * torus.memory_bytes(),
        "tree_only_bytes": 2 * tree.memory_bytes,
        "tree_bytes_per_triangle": tree.bytes_per_triangle,
        "tree_nodes": tree.nodes,
        "tree_depth": tree.depth,
        "tree_build_ms": build_s * 1e3,
    });
    Ok((settings, figures))
}
