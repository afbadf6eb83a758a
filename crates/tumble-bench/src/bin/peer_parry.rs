//! `peer-parry`: the tori collision queries of scenes.md with parry3d (f32).
//!
//! Per pose, from scratch: (1) first contact: `query::intersection_test` on the two
//! `TriMesh`es (parry walks mesh A's tree and tests each candidate triangle against mesh B;
//! it has no two-tree first-contact traversal); (2) all intersecting triangle pairs: parry's
//! simultaneous two-tree traversal `Bvh::leaf_pairs` (AABBs of B's nodes moved into A's frame)
//! followed by a GJK triangle-triangle `intersection_test` per leaf pair; (3) contact data:
//! the composite-composite `contact_manifolds` with prediction 0 (a fresh workspace per
//! pose); (4) minimum distance (`query::distance`) at the poses the truth file says are
//! separated. Pair counts are checked against shared/data/tori_pairs.json.
//!
//! Usage: `peer-parry [--poses P]` (P poses spread evenly over the 200; default all).

use std::time::Instant;

use parry3d::bounding_volume::BoundingVolume;
use parry3d::math::Pose;
use parry3d::query::{self, ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher};
use parry3d::shape::TriMesh;
use serde_json::json;
use tumble::scenes::{tori_pair_check, tori_truth, TimingStats};
use tumble::scenes::{tori_pose_indices, TORI_POSES};
use tumble_bench::parry_scenes::{self as ps, torus};
use tumble_bench::{Args, Record};

/// All intersecting triangle pairs: two-tree traversal, then GJK per leaf pair.
fn all_pairs(a: &TriMesh, b: &TriMesh, pos12: &Pose) -> usize {
    let check = |n1: &parry3d::partitioning::BvhNode, n2: &parry3d::partitioning::BvhNode| {
        n1.aabb().intersects(&n2.aabb().transform_by(pos12))
    };
    let mut count = 0;
    for (i, j) in a.bvh().leaf_pairs(b.bvh(), check) {
        let (ta, tb) = (a.triangle(i), b.triangle(j));
        if let Ok(hit) = query::intersection_test(&Pose::identity(), &ta, pos12, &tb) {
            if hit.intersecting {
                count += 1;
            }
        }
    }
    count
}

fn run(poses: usize) -> Result<(), String> {
    let a = torus()?;
    let b = torus()?;
    let truth_all = tori_truth().ok_or(
        "cannot read the pair counts of shared/data/tori_pairs.json beside the repository (set TORI_TRUTH)",
    )?;
    let ks = tori_pose_indices(poses);
    let truth: Vec<u64> = ks.iter().map(|&k| truth_all[k]).collect();
    let colliding: Vec<bool> = truth.iter().map(|&t| t > 0).collect();
    let pa = Pose::identity();
    let (mut first, mut allp, mut withc, mut dist) = (vec![], vec![], vec![], vec![]);
    let (mut hits, mut counts, mut manifold_pairs, mut dvals) = (0usize, vec![], vec![], vec![]);
    let mut contact_points = 0usize;
    let mut unsupported = vec![];
    for (&k, &tp) in ks.iter().zip(&truth) {
        let pb = ps::tori_pose(k);

        let t0 = Instant::now();
        let r = query::intersection_test(&pa, &a, &pb, &b);
        first.push(t0.elapsed().as_secs_f64());
        match r {
            Ok(r) => hits += r.intersecting as usize,
            Err(e) => unsupported.push(format!("intersection_test: {e}")),
        }

        let t0 = Instant::now();
        let pos12 = pa.inv_mul(&pb);
        let n = all_pairs(&a, &b, &pos12);
        allp.push(t0.elapsed().as_secs_f64());
        counts.push(n);

        let mut manifolds: Vec<ContactManifold<(), ()>> = Vec::new();
        let mut workspace = None;
        let t0 = Instant::now();
        let r = DefaultQueryDispatcher.contact_manifolds(&pos12, &a, &b, 0.0, &mut manifolds, &mut workspace);
        withc.push(t0.elapsed().as_secs_f64());
        if let Err(e) = r {
            unsupported.push(format!("contact_manifolds: {e}"));
        }
        let touching: Vec<_> = manifolds
            .iter()
            .filter(|m| m.points.iter().any(|p| p.dist <= 0.0))
            .collect();
        manifold_pairs.push(touching.len());
        contact_points += touching.iter().map(|m| m.points.len()).sum::<usize>();

        if tp == 0 {
            let t0 = Instant::now();
            let r = query::distance(&pa, &a, &pb, &b);
            dist.push(t0.elapsed().as_secs_f64());
            match r {
                Ok(d) => dvals.push(d.distance as f64),
                Err(e) => unsupported.push(format!("distance: {e}")),
            }
        }
    }
    unsupported.sort();
    unsupported.dedup();
    let memory = 2 * a.total_memory_size();
    Record {
        engine: "parry3d",
        version: env!("PEER_PARRY3D_VERSION"),
        scene: "tori".into(),
        status: "ok",
        settings: json!({
            "bv": "AABB (parry Bvh)",
            "precision": "f32",
            "poses": ks.len(),
            "mesh": "torus_mesh(1.0, 0.3, 50, 50), 5000 triangles",
            "notes": "all pairs = Bvh::leaf_pairs + GJK triangle test per leaf pair; \
                      contacts = composite contact_manifolds, prediction 0",
        }),
        figures: json!({
            "first_contact": TimingStats::us_split(&first, &colliding),
            "first_contact_colliding_poses": hits,
            "all_pairs": TimingStats::us_split(&allp, &colliding),
            "all_pairs_check": tori_pair_check(&counts, Some(&truth)),
            "all_pairs_with_contacts": TimingStats::us_split(&withc, &colliding),
            "all_pairs_with_contacts_check": tori_pair_check(&manifold_pairs, Some(&truth)),
            "contact_points": contact_points,
            "distance_separated": TimingStats::us(&dist),
            "distance_min_m": dvals.iter().cloned().reduce(f64::min),
            "distance_negative_at_separated_poses": dvals.iter().filter(|&&d| d < 0.0).count(),
            "tree_memory_bytes": memory,
            "unsupported": unsupported,
        }),
        peak_rss_bytes: None,
    }
    .emit();
    Ok(())
}

fn main() {
    let args = Args::from_env_or_exit("peer-parry");
    if let Some(s) = args.scene.as_deref().filter(|s| *s != "tori") {
        eprintln!("peer-parry: only --scene tori is supported, got {s}");
        std::process::exit(2);
    }
    if let Err(e) = run(args.poses.unwrap_or(TORI_POSES)) {
        eprintln!("peer-parry: {e}");
        std::process::exit(2);
    }
}
