//! Deepest penetration of a scene over an ensemble of runs whose initial
//! positions differ by up to 1e-5 m per run (`ensemble_depth SCENE RUNS
//! STEPS`, scenes chain and concave_pileN). The chain and the piles are
//! chaotic: one run's worst step says little, and a change that moves the
//! trajectory moves it at random; compare medians over an ensemble. With
//! `DIAG=1`, every step deeper than 1 mm names the pair and its point; with
//! `FIRST_RUN=k`, the ensemble starts at run k (profile_stages traces run k
//! with `ENSEMBLE_RUN=k`); `PUSH_FRACTION=f`, `SUBSTEPS=n` and `ITERATIONS=n` set those
//! `WorldSettings` fields for every run. For the concave pile each run
//! also counts the bodies out of the bin at its end.
use tumble::scenes;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map(String::as_str).unwrap_or("chain");
    let runs: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(6);
    let steps: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(600);
    let mut all = Vec::new();
    let mut total = 0.0;
    let mut escapes = 0;
    // FIRST_RUN=k starts the ensemble at run k (to look again at one run).
    let first: usize = std::env::var("FIRST_RUN")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    for k in first..runs {
        let mut scene = match name {
            "chain" => scenes::chain(),
            n if n.starts_with("concave_pile") => scenes::concave_pile(n[12..].parse().unwrap()),
            other => panic!("unknown scene {other}: chain or concave_pileN"),
        };
        scene.settings.sleeping = false;
        if let Some(f) = std::env::var("PUSH_FRACTION").ok().and_then(|v| v.parse().ok()) {
            scene.settings.push_out_fraction = f;
        }
        if let Some(n) = std::env::var("SUBSTEPS").ok().and_then(|v| v.parse().ok()) {
            scene.settings.substeps = n;
        }
        if let Some(n) = std::env::var("ITERATIONS").ok().and_then(|v| v.parse().ok()) {
            scene.settings.iterations = n;
        }
        for (i, b) in scene.bodies.iter_mut().enumerate() {
            b.pose.position.x += 1e-5 * k as f64 * ((i % 3) as f64 - 1.0);
        }
        let (mut world, ids) = scene.build().unwrap();
        let mut deepest = 0.0f64;
        let mut over1 = 0;
        for _ in 0..steps {
            let r = world.step();
            deepest = deepest.max(r.max_penetration);
            if r.max_penetration > 0.001 {
                over1 += 1;
            }
            if std::env::var("DIAG").is_ok() && r.max_penetration > 0.001 {
                let c = world
                    .contacts()
                    .iter()
                    .min_by(|x, y| x.contact.distance.total_cmp(&y.contact.distance))
                    .unwrap();
                let n = world
                    .contacts()
                    .iter()
                    .filter(|d| d.body_a == c.body_a && d.body_b == c.body_b)
                    .count();
                eprintln!(
                    "  step {} pen {:.4} reported {:.4} kind {:?} bodies {:?} {:?} points {} impulse {:.4}",
                    world.step_count(),
                    r.max_penetration,
                    -c.contact.distance,
                    c.contact.kind,
                    world.name(c.body_a),
                    world.name(c.body_b),
                    n,
                    c.normal_impulse
                );
            }
            total += r.total_time().as_secs_f64();
        }
        all.push(deepest);
        // The concave pile's bodies out of the bin (its first body).
        let escaped = if name.starts_with("concave_pile") {
            let centres: Vec<_> = ids[1..]
                .iter()
                .map(|&id| world.center_of_mass(id).unwrap())
                .collect();
            scenes::concave_pile_escaped(&centres)
        } else {
            0
        };
        escapes += escaped;
        eprintln!(
            "run {k}: deepest {:.4} mm, steps over 1 mm {over1}, escaped {escaped}",
            deepest * 1e3
        );
    }
    all.sort_by(f64::total_cmp);
    println!(
        "{name}: median deepest {:.3} mm, max {:.3} mm, {:.2} ms/step, {escapes} escaped",
        all[all.len() / 2] * 1e3,
        all[all.len() - 1] * 1e3,
        total / (runs * steps) as f64 * 1e3
    );
}
