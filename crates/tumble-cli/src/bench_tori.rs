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
use std::path::PathBuf;
use std::time::Instant;

use tumble_collide::query::{self, CollideOptions, DistanceOptions, MeshShape, ReportMode};
use tumble_collide::Pose;

pub use tumble::scenes::{tori_pose, tori_pose_indices, TORI_POSES};

/// The ground-truth pairs per pose, if the file can be found and read.
fn truth() -> Option<Vec<u64>> {
    let path = std::env::var_os("TORI_TRUTH").map(PathBuf::from).or_else(|| {
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .ancestors()
            .map(|a| a.join("shared/data/tori_pairs.json"))
            .find(|p| p.exists())
    })?;
    let v: Value = serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()?;
    let t: Option<Vec<u64>> = v["pairs_per_pose"]
        .as_array()?
        .iter()
        .map(|x| x.as_u64())
        .collect();
    t.filter(|t| t.len() == TORI_POSES)
}

/// Timing summary in microseconds, as `tumble_bench::Stats` (median of the
/// middle two for an even count; nearest-rank `int(q (n - 1) + 0.5)` for
/// the 10th and 90th percentiles). `null` for no samples.
fn stats_us(seconds: &[f64]) -> Value {
    if seconds.is_empty() {
        return Value::Null;
    }
    let mut s: Vec<f64> = seconds.iter().map(|x| x * 1e6).collect();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    let median = if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    };
    let pct = |q: f64| s[((q * (n - 1) as f64 + 0.5) as usize).min(n - 1)];
    json!({"unit": "us", "count": n, "median": median, "mean": s.iter().sum::<f64>() / n as f64,
           "p10": pct(0.1), "p90": pct(0.9), "min": s[0], "max": s[n - 1]})
}

fn split(times: &[f64], colliding: &[bool]) -> Value {
    let pick = |want: bool| -> Vec<f64> {
        times
            .iter()
            .zip(colliding)
            .filter(|(_, &c)| c == want)
            .map(|(t, _)| *t)
            .collect()
    };
    json!({"all": stats_us(times), "colliding": stats_us(&pick(true)), "separated": stats_us(&pick(false))})
}

/// Pair counts against the truth (`null` truth fields when it is missing).
fn check(counts: &[usize], truth: Option<&[u64]>) -> Value {
    let total: usize = counts.iter().sum();
    let colliding = counts.iter().filter(|&&c| c > 0).count();
    let Some(truth) = truth else {
        return json!({"total_pairs": total, "truth_total_pairs": null, "colliding_poses": colliding,
                      "truth_colliding_poses": null});
    };
    let ttotal: u64 = truth.iter().sum();
    let diff = |(c, t): (&usize, &u64)| (*c as i64 - *t as i64).abs();
    json!({
        "total_pairs": total,
        "truth_total_pairs": ttotal,
        "colliding_poses": colliding,
        "truth_colliding_poses": truth.iter().filter(|&&t| t > 0).count(),
        "poses_differing": counts.iter().zip(truth).filter(|p| diff(*p) != 0).count(),
        "max_abs_pose_difference": counts.iter().zip(truth).map(diff).max().unwrap_or(0),
        "within_two_pairs": (total as i64 - ttotal as i64).abs() <= 2,
    })
}

/// Runs the tori queries at `poses` poses and returns the record's
/// `(settings, figures)`.
pub fn run(poses: usize) -> Result<(Value, Value), CliError> {
    let internal = |e: &dyn std::fmt::Display| CliError::Internal(e.to_string());
    let mesh = tumble::scenes::tori_torus().map_err(|e| internal(&e))?;
    let build = Instant::now();
    let torus = MeshShape::new(mesh).map_err(|e| internal(&e))?;
    let build_s = build.elapsed().as_secs_f64();
    let truth_all = truth();
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
        "first_contact": split(&t_first, &colliding),
        "first_contact_colliding_poses": hits,
        "all_pairs": split(&t_all, &colliding),
        "all_pairs_check": check(&counts, truth.as_deref()),
        "all_pairs_with_contacts": split(&t_contacts, &colliding),
        "all_pairs_with_contacts_check": check(&contact_counts, truth.as_deref()),
        "contact_points": points,
        "distance_separated": stats_us(&t_dist),
        "distance_min_m": dists.iter().copied().reduce(f64::min),
        "distance_negative_at_separated_poses": dists.iter().filter(|&&d| d < 0.0).count(),
        // Two tori, one tree each (this run shares one object for both).
        "tree_memory_bytes": 2 * tree.memory_bytes,
        "tree_bytes_per_triangle": tree.bytes_per_triangle,
        "tree_nodes": tree.nodes,
        "tree_depth": tree.depth,
        "tree_build_ms": build_s * 1e3,
    });
    Ok((settings, figures))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_match_the_harness_definitions() {
        let xs: Vec<f64> = [7, 1, 11, 3, 9, 5, 2, 10, 4, 8, 6]
            .iter()
            .map(|&k| k as f64 * 1e-6)
            .collect();
        let s = stats_us(&xs);
        assert!((s["median"].as_f64().unwrap() - 6.0).abs() < 1e-9);
        assert!((s["p10"].as_f64().unwrap() - 2.0).abs() < 1e-9);
        assert!((s["p90"].as_f64().unwrap() - 10.0).abs() < 1e-9);
        assert!(stats_us(&[]).is_null());
    }
}
