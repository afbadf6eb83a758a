//! Prints the mean time per step and per stage of a standard scene:
//! `cargo run --release -p tumble --example profile_stages -- pyramid 300 [threads [substeps iterations [push_out_iterations]]]`
//! (scenes: pyramid, large_pyramid, pile100, pile1000, pile10000, chain, heavy_chain,
//! ragdoll_pile, concave_pile[N], tower[N]: a column of N unit cubes); also
//! prints how far the last body moved, the deepest penetration seen and, with
//! joints, the largest joint error after any step
//! (with `TRACE_DEPTH=N` in the environment, also the deepest of every N steps;
//! with `JITTER=seed`, every moving body after the first starts up to 2 cm and 0.1 rad
//! from its place, an independent sample of a chaotic scene for each seed;
//! with `ENSEMBLE_RUN=k`, the start of run k of `ensemble_depth` (to trace it);
//! with `RAGDOLLS=k`, the ragdoll pile's first k ragdolls only;
//! with `FRICTION=mu`, every body's friction set to `mu`; with
//! `RESTING_MOTION=m`, `CONTACT_MARGIN=m`, `MESH_CONTACT_MARGIN=m` or
//! `ALLOWED_PENETRATION=m`, that
//! `WorldSettings` field set to `m`; with `PIN_THREADS=1`, `adaptive_threads`
//! off (every step with work for the threads on them); with `TRACE_THREADS=1`,
//! each step's thread count (the adaptive choice's) and time; with `NO_CCD=1`,
//! the continuous stage off; with `TRACE_ENERGY=1`, each step's change of
//! total energy, kinetic energy and deepest penetration; with `TRACE_DEEPEST=N`, every N steps
//! the deepest contact: its depth, height, the two bodies' names, normal,
//! impulse and the two bodies' speeds; with `TRACE_PAIR=depth` (m; any other
//! value: 1 cm), after every step whose deepest contact is over it, that pair's contacts then and at
//! the step before (a pair with none before met features its speculative
//! contacts never saw), the contacts either body had with a third at the
//! step before, the two bodies' centres and velocities before the step
//! before and before this step (a spin taken on within the step) and
//! after it; with `TRACE_MOVING` set, the
//! six fastest bodies at the end (`#k`: the body's index, for `TRACE_BODY`) (what keeps a pile from rest); with `TRACE_JOINTS=N`, every N steps the
//! largest joint error and which joint has it; with `TRACE_SINK=N`, every N
//! steps how far a pyramid's layers sank and its flanks moved in; with
//! `TRACE_LEAN=N`, every N steps how far they leaned out of its plane; with
//! `TRACE_TOWER=N`, every N steps a tower's interface loads against the
//! weight they carry, its boxes' vertical speeds and the gaps between them; with
//! `EARLY_ITERATIONS=steps:iterations`, that many iterations for the first
//! steps only; with `PUSH_FRACTION=f` or `PUSH_SPEED=v`, the push-out's
//! fraction or speed limit; with `TRACE_BODY=name`, after every step that
//! body's motion and the contacts on it; with `TRACE_LIFT=1`, after every
//! step the three bodies whose potential energy changed most in it, how far
//! each rose and its speed at the end: where a settled pile's energy goes up
//! and down while its kinetic energy stays small); with `TRACE_HASH=1`, a hash
//! of every body's state bits at the end (two builds that should step alike
//! give the same hash); with `FLUSH_SUBNORMALS=1` (x86-64), subnormal
//! operands and results taken as zero on the main thread (MXCSR's DAZ and
//! FTZ; run it with one thread): where that makes a scene faster, some
//! arithmetic meets subnormal numbers, which Intel cores handle in microcode
//! (a diagnostic only: the engine never sets these flags, and the
//! trajectory may differ).
use tumble::scenes;
use tumble::world::{SolveStage, Stage};
use tumble_collide::DVec3;

fn main() {
    if std::env::var("TRAP_SUBNORMALS").is_ok() {
        trap_subnormals();
    }
    if std::env::var("FLUSH_SUBNORMALS").is_ok() {
        flush_subnormals();
    }
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map(String::as_str).unwrap_or("pyramid");
    let steps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(300);
    let trace_sink: usize = std::env::var("TRACE_SINK")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    let trace_body: Option<String> = std::env::var("TRACE_BODY").ok();
    let trace_lean: usize = std::env::var("TRACE_LEAN")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    // A depth (m) to trace beyond; 1 cm when the value is not a number.
    let trace_pair: Option<f64> = std::env::var("TRACE_PAIR")
        .ok()
        .map(|v| v.parse().unwrap_or(0.01));
    let trace_tower: usize = std::env::var("TRACE_TOWER")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    let mut scene = match name {
        "pyramid" => scenes::pyramid(),
        "pile100" => scenes::pile(1),
        "pile1000" => scenes::pile(10),
        "pile10000" => scenes::pile(100),
        "large_pyramid" => scenes::large_pyramid(),
        "chain" => scenes::chain(),
        "heavy_chain" => scenes::heavy_chain(),
        "ragdoll_pile" => scenes::ragdoll_pile(),
        "concave_pile" => scenes::concave_pile(scenes::CONCAVE_PILE_BODIES),
        other if other.starts_with("concave_pile") => {
            scenes::concave_pile(other[12..].parse().expect("concave_pileN"))
        }
        other if other.starts_with("tower") => scenes::tower(other[5..].parse().expect("towerN")),
        other if other.starts_with("pyramid") => {
            scenes::pyramid_of_base(other[7..].parse().expect("pyramidN"))
        }
        other => panic!("unknown scene {other}"),
    };
    // RAGDOLLS=k: the ragdoll pile's first k ragdolls only (how its cost
    // scales with the pile's size).
    if let Some(k) = std::env::var("RAGDOLLS")
        .ok()
        .and_then(|s| s.parse::<usize>().ok())
    {
        assert_eq!(name, "ragdoll_pile", "RAGDOLLS is for the ragdoll pile");
        scene.bodies.truncate(1 + 11 * k);
        scene.joints.truncate(10 * k);
    }
    // ENSEMBLE_RUN=k: the start of run k of `ensemble_depth` (x moved by
    // 1e-5 k ((i mod 3) - 1) m for body i).
    if let Some(k) = std::env::var("ENSEMBLE_RUN")
        .ok()
        .and_then(|s| s.parse::<u32>().ok())
    {
        for (i, b) in scene.bodies.iter_mut().enumerate() {
            b.pose.position.x += 1e-5 * k as f64 * ((i % 3) as f64 - 1.0);
        }
    }
    if let Some(seed) = std::env::var("JITTER").ok().and_then(|s| s.parse::<u64>().ok()) {
        // A small LCG (Knuth's MMIX constants): uniform in [-1, 1).
        let mut state = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        };
        for body in scene.bodies.iter_mut().skip(1) {
            let shift = tumble_collide::DVec3::new(next(), next(), next()) * 0.02;
            let turn = tumble_collide::DQuat::from_scaled_axis(
                tumble_collide::DVec3::new(next(), next(), next()) * 0.1,
            );
            // Fixed bodies (a pile's walls) stay: a wall 60 m high turned
            // by 0.1 rad would cut through the pile. The draws are made
            // for them all the same, so each seed's sample of the moving
            // bodies does not depend on which bodies are fixed.
            if body.kind == tumble::body::BodyKind::Static {
                continue;
            }
            body.pose.position += shift;
            body.pose.rotation = (turn * body.pose.rotation).normalize();
        }
    }
    scene.settings.sleeping = false;
    if std::env::var("NO_CCD").is_ok() {
        scene.settings.continuous = false;
    }
    if std::env::var("PIN_THREADS").is_ok() {
        scene.settings.adaptive_threads = false;
    }
    if let Some(mu) = std::env::var("FRICTION").ok().and_then(|s| s.parse::<f64>().ok()) {
        for body in scene.bodies.iter_mut() {
            body.material.friction = mu;
        }
    }
    if let Some(m) = std::env::var("CONTACT_MARGIN")
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
    {
        scene.settings.contact_margin = m;
    }
    if let Some(m) = std::env::var("MESH_CONTACT_MARGIN")
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
    {
        scene.settings.mesh_contact_margin = m;
    }
    if let Some(m) = std::env::var("RESTING_MOTION")
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
    {
        scene.settings.resting_motion = m;
    }
    if let Some(m) = std::env::var("ALLOWED_PENETRATION")
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
    {
        scene.settings.allowed_penetration = m;
    }
    scene.settings.threads = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    if let Some(n) = args.get(4).and_then(|s| s.parse().ok()) {
        scene.settings.substeps = n;
    }
    if let Some(n) = args.get(5).and_then(|s| s.parse().ok()) {
        scene.settings.iterations = n;
    }
    if let Some(n) = args.get(6).and_then(|s| s.parse().ok()) {
        scene.settings.push_out_iterations = n;
    }
    let (mut world, ids) = scene.build().unwrap();
    let last = *ids.last().unwrap();
    let start = world.center_of_mass(last).unwrap();
    let mut deepest = 0.0f64;
    let mut sum = [0.0f64; Stage::ALL.len()];
    let mut parts = [0.0f64; 8];
    let (mut late_sum, mut late_parts) = ([0.0f64; Stage::ALL.len()], [0.0f64; 8]);
    let mut total = 0.0;
    // The last third of the steps alone: a pile's settled cost.
    let mut late = 0.0;
    let mut swept_back = 0;
    // Mesh pairs re-evaluated and recalled over the last third.
    let mut late_pairs = (0usize, 0usize);
    // Contact colours per step over the last third.
    let mut late_colors = 0usize;
    let trace: usize = std::env::var("TRACE_DEPTH")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    let mut window = 0.0f64;
    let trace_deepest: usize = std::env::var("TRACE_DEEPEST")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    // Largest joint error (m, rad) after any step.
    let mut joint_error = (0.0f64, 0.0f64);
    let trace_joints: usize = std::env::var("TRACE_JOINTS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    // Total energy (kinetic plus potential) step to step: contacts and
    // friction may only take it away, so a gain is a defect to chase.
    let mut energy = world.kinetic_energy() + world.potential_energy();
    let trace_energy = std::env::var("TRACE_ENERGY").is_ok();
    let trace_threads = std::env::var("TRACE_THREADS").is_ok();
    // TRACE_LIFT: each dynamic body's potential energy (J) after the last
    // step, by its index among the world's bodies.
    let trace_lift = std::env::var("TRACE_LIFT").is_ok();
    let potential = |world: &tumble::world::World| -> Vec<f64> {
        let g = world.settings().gravity;
        world
            .body_ids()
            .into_iter()
            .map(|id| match world.body(id) {
                Ok(b) if b.kind() == tumble::BodyKind::Dynamic => -b.mass() * g.dot(b.position()),
                _ => 0.0,
            })
            .collect()
    };
    let mut lift_before = if trace_lift { potential(&world) } else { Vec::new() };
    let (mut largest_gain, mut gain_step, mut gaining_steps) = (f64::NEG_INFINITY, 0, 0);
    let mut threaded_steps = 0usize;
    let mut prev: Vec<tumble::world::WorldContact> = Vec::new();
    let mut motion_before_prev = Vec::new();
    // EARLY_ITERATIONS=steps:iterations: that many solver iterations for the
    // first steps (what a cold start, without warm-start impulses, needs).
    let early: Option<(usize, u32)> = std::env::var("EARLY_ITERATIONS").ok().and_then(|v| {
        v.split_once(':')
            .and_then(|(a, b)| Some((a.parse().ok()?, b.parse().ok()?)))
    });
    // PUSH_FRACTION / PUSH_SPEED: the push-out's fraction and speed limit;
    // DT: the step (s).
    {
        let mut s = world.settings().clone();
        if let Some(dt) = std::env::var("DT").ok().and_then(|v| v.parse().ok()) {
            s.dt = dt;
        }
        if let Some(f) = std::env::var("PUSH_FRACTION").ok().and_then(|v| v.parse().ok()) {
            s.push_out_fraction = f;
        }
        if let Some(v) = std::env::var("PUSH_SPEED").ok().and_then(|v| v.parse().ok()) {
            s.max_push_out_speed = v;
        }
        world.set_settings(s).unwrap();
    }
    let usual = world.settings().clone();
    for step in 0..steps {
        if let Some((until, iterations)) = early {
            let mut s = usual.clone();
            if step < until {
                s.iterations = iterations;
            }
            world.set_settings(s).unwrap();
        }
        // For TRACE_PAIR: every body's centre and velocities before the step.
        let motion_before: Vec<_> = if trace_pair.is_some() {
            world
                .body_ids()
                .into_iter()
                .map(|id| {
                    let (x, v, w) = (
                        world.center_of_mass(id).unwrap(),
                        world.linear_velocity(id).unwrap(),
                        world.angular_velocity(id).unwrap(),
                    );
                    (id, x, v, w)
                })
                .collect()
        } else {
            Vec::new()
        };
        let r = world.step();
        threaded_steps += usize::from(r.threads > 1);
        if trace_threads {
            eprintln!(
                "step {step}: {} thread(s), {:.3} ms",
                r.threads,
                r.total_time().as_secs_f64() * 1e3
            );
        }
        let now = world.kinetic_energy() + world.potential_energy();
        if now - energy > largest_gain {
            (largest_gain, gain_step) = (now - energy, step);
        }
        gaining_steps += usize::from(now - energy > 1e-3);
        if trace_energy {
            eprintln!(
                "step {step}: energy change {:+.4e} J, kinetic {:.3e} J, deepest {:.4} m, solver residual {:.2e} m/s",
                now - energy,
                world.kinetic_energy(),
                r.max_penetration,
                r.solver_residual
            );
        }
        energy = now;
        if trace_lift {
            let lift_now = potential(&world);
            let mut changes: Vec<(usize, f64)> = lift_now
                .iter()
                .zip(&lift_before)
                .map(|(now, before)| now - before)
                .enumerate()
                .collect();
            changes.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()).then(a.0.cmp(&b.0)));
            let ids = world.body_ids();
            let g = world.settings().gravity.length().max(f64::MIN_POSITIVE);
            let top: Vec<String> = changes
                .iter()
                .filter(|c| c.1 != 0.0)
                .take(3)
                .map(|&(k, de)| {
                    let b = world.body(ids[k]).expect("live");
                    format!(
                        "#{k} {de:+.2e} J (rose {:+.1} um, {:.2} mm/s)",
                        de / (b.mass() * g) * 1e6,
                        b.velocity().length() * 1e3
                    )
                })
                .collect();
            let total: f64 = changes.iter().map(|c| c.1).sum();
            eprintln!(
                "step {step}: potential energy {total:+.3e} J; most: {}",
                top.join(", ")
            );
            lift_before = lift_now;
        }
        deepest = deepest.max(r.max_penetration);
        if let Some(threshold) = trace_pair {
            let depth = |c: &tumble::world::WorldContact| c.contact.depth();
            if let Some(c) = world
                .contacts()
                .iter()
                .max_by(|a, b| depth(a).total_cmp(&depth(b)))
            {
                if depth(c) > threshold {
                    let (a, b) = (c.body_a, c.body_b);
                    eprintln!(
                        "step {step}: deep pair {a:?} {b:?} depth {:.4}; its contacts now:",
                        depth(c)
                    );
                    let show = |when: &str, k: &tumble::world::WorldContact| {
                        eprintln!(
                            "   {when} d {:+.4} n {:.3?} p {:.3?} imp {:.4} kind {:?}",
                            k.contact.distance,
                            k.contact.normal.to_array(),
                            k.contact.point.to_array(),
                            k.normal_impulse,
                            k.contact.kind
                        )
                    };
                    let of_pair = |k: &&tumble::world::WorldContact| {
                        (k.body_a, k.body_b) == (a, b) || (k.body_a, k.body_b) == (b, a)
                    };
                    world
                        .contacts()
                        .iter()
                        .filter(of_pair)
                        .for_each(|k| show("now ", k));
                    prev.iter().filter(of_pair).for_each(|k| show("prev", k));
                    // What else touched the two at the step before (a third
                    // body that struck one of them within the step).
                    let with_third = |k: &&tumble::world::WorldContact| {
                        !of_pair(k) && [a, b].into_iter().any(|x| x == k.body_a || x == k.body_b)
                    };
                    for k in prev.iter().filter(with_third) {
                        eprintln!(
                            "   prev, third body: {}-{} d {:+.4} n {:.3?} imp {:.4} kind {:?}",
                            k.body_a.index,
                            k.body_b.index,
                            k.contact.distance,
                            k.contact.normal.to_array(),
                            k.normal_impulse,
                            k.contact.kind
                        );
                    }
                    // How the two moved into it: their motion before the
                    // step before and before this one.
                    for (when, motion) in [
                        ("before the step before", &motion_before_prev),
                        ("before this step", &motion_before),
                    ] {
                        for (id, x, v, w) in motion.iter().filter(|m| m.0 == a || m.0 == b) {
                            eprintln!(
                                "   {when}: body {} x {:.4?} v {:.3?} w {:.3?}",
                                id.index,
                                x.to_array(),
                                v.to_array(),
                                w.to_array()
                            );
                        }
                    }
                    eprintln!(
                        "   v {:.3?} {:.3?} w {:.3?} {:.3?}",
                        world.linear_velocity(a).unwrap().to_array(),
                        world.linear_velocity(b).unwrap().to_array(),
                        world.angular_velocity(a).unwrap().to_array(),
                        world.angular_velocity(b).unwrap().to_array()
                    );
                }
            }
            prev = world.contacts().to_vec();
            motion_before_prev = motion_before;
        }
        if trace_deepest > 0 && step % trace_deepest == 0 {
            let depth = |c: &tumble::world::WorldContact| c.contact.depth();
            if let Some(c) = world
                .contacts()
                .iter()
                .max_by(|a, b| depth(a).total_cmp(&depth(b)))
            {
                let speed = |id| world.linear_velocity(id).unwrap_or_default().length();
                let deep = world.contacts().iter().filter(|k| depth(k) > 0.02).count();
                eprintln!(
                    "step {step}: deepest contact {:.4} m at height {:.2} m between {} and {}, normal {:.2?}, impulse {:.3} N s, speeds {:.2} / {:.2} m/s; {deep} contacts deeper than 2 cm",
                    depth(c),
                    c.contact.point.z,
                    world.name(c.body_a).unwrap_or("?"),
                    world.name(c.body_b).unwrap_or("?"),
                    c.contact.normal.to_array(),
                    c.normal_impulse,
                    speed(c.body_a),
                    speed(c.body_b)
                );
            }
        }
        if trace_sink > 0 && (step + 1) % trace_sink == 0 {
            trace_sink_line(&world, step + 1, r.warm_started);
        }
        if trace_lean > 0 && (step + 1) % trace_lean == 0 {
            trace_lean_line(&world, step + 1);
        }
        if let Some(name) = &trace_body {
            trace_body_line(&world, step + 1, name);
        }
        if trace_tower > 0 && (step + 1) % trace_tower == 0 {
            trace_tower_line(&world, step + 1);
        }
        let (linear, angular) = world.max_joint_error();
        joint_error = (joint_error.0.max(linear), joint_error.1.max(angular));
        if trace_joints > 0 && step % trace_joints == 0 {
            let errors: Vec<f64> = world
                .joint_ids()
                .into_iter()
                .map(|id| world.joint_state(id).map_or(f64::NAN, |s| s.linear_error))
                .collect();
            let (worst, _) = errors
                .iter()
                .enumerate()
                .fold((0, 0.0f64), |(k, e), (i, &x)| if x > e { (i, x) } else { (k, e) });
            eprintln!(
                "step {step}: largest joint error {:.3} mm at joint {worst} of {}",
                linear * 1e3,
                errors.len()
            );
        }
        window = window.max(r.max_penetration);
        if trace > 0 && (step + 1) % trace == 0 {
            eprintln!("steps {}..{}: deepest {window:.4} m", step + 1 - trace, step + 1);
            window = 0.0;
        }
        swept_back += r.continuous;
        let late_step = step >= steps - steps / 3;
        for s in Stage::ALL {
            sum[s as usize] += r.time(s).as_secs_f64();
            if late_step {
                late_sum[s as usize] += r.time(s).as_secs_f64();
            }
        }
        for p in SolveStage::ALL {
            parts[p as usize] += r.solve_time(p).as_secs_f64();
            if late_step {
                late_parts[p as usize] += r.solve_time(p).as_secs_f64();
            }
        }
        total += r.total_time().as_secs_f64();
        if step >= steps - steps / 3 {
            late += r.total_time().as_secs_f64();
            late_pairs.0 += r.revalidated_mesh_pairs;
            late_pairs.1 += r.recalled_mesh_pairs;
            late_colors += r.colors;
        }
    }
    let ms = |t: f64| t / steps as f64 * 1e3;
    let moved = (world.center_of_mass(last).unwrap() - start).length();
    println!(
        "{name}: {:.3} ms/step on {} threads ({threaded_steps} steps on more than one), {} substeps x {} iterations; last body moved {moved:.4} m, deepest {deepest:.4} m",
        ms(total),
        world.threads(),
        world.settings().substeps,
        world.settings().iterations
    );
    if std::env::var("TRACE_HASH").is_ok() {
        // FNV-1a over the bits of every body's position, orientation and
        // momenta, in body order.
        let mut hash = 0xcbf2_9ce4_8422_2325u64;
        for id in world.body_ids() {
            let s = world.body(id).unwrap().state();
            let numbers = s
                .position
                .to_array()
                .into_iter()
                .chain(s.orientation.to_array())
                .chain(s.linear_momentum.to_array())
                .chain(s.angular_momentum.to_array());
            for x in numbers {
                for byte in x.to_bits().to_le_bytes() {
                    hash = (hash ^ byte as u64).wrapping_mul(0x0100_0000_01b3);
                }
            }
        }
        println!("state hash {hash:016x}");
    }
    if std::env::var("TRACE_MOVING").is_ok() {
        let mut v: Vec<(f64, String, DVec3, DVec3, DVec3)> = world
            .body_ids()
            .into_iter()
            .enumerate()
            .map(|(k, id)| {
                let (lv, av) = (
                    world.linear_velocity(id).unwrap(),
                    world.angular_velocity(id).unwrap(),
                );
                // Ranked by the speed of a point 0.1 m from the centre.
                let at = world.center_of_mass(id).unwrap();
                (
                    lv.length() + av.length() * 0.1,
                    format!("#{k} {}", world.name(id).unwrap_or("?")),
                    lv,
                    av,
                    at,
                )
            })
            .collect();
        v.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (_, name, v, w, at) in v.iter().take(6) {
            eprintln!(
                "moving {name} at {:.3?}: v {:.4?} m/s, w {:.4?} rad/s",
                at.to_array(),
                v.to_array(),
                w.to_array()
            );
        }
    }
    println!(
        "  last third of the steps: {:.3} ms/step; kinetic energy at the end {:.3e} J",
        late / (steps / 3).max(1) as f64 * 1e3,
        world.kinetic_energy()
    );
    println!("  bodies put back by continuous collision: {swept_back}");
    if world.joint_count() > 0 {
        println!(
            "  largest joint error after any step: {:.3} mm, {:.4} rad",
            joint_error.0 * 1e3,
            joint_error.1
        );
    }
    println!(
        "  total energy: largest change in one step {largest_gain:+.3e} J (step {gain_step}), {gaining_steps} steps gaining more than 1 mJ"
    );
    if name.starts_with("concave_pile") {
        let centres: Vec<_> = ids[1..]
            .iter()
            .map(|&id| world.center_of_mass(id).unwrap())
            .collect();
        println!(
            "  bodies escaped from the bin: {}",
            scenes::concave_pile_escaped(&centres)
        );
    }
    let late_steps = (steps / 3).max(1) as f64;
    println!(
        "  mesh pairs per step over the last third: {:.1} re-evaluated their kept points, {:.1} recalled their walk",
        late_pairs.0 as f64 / late_steps,
        late_pairs.1 as f64 / late_steps
    );
    println!(
        "  contact colours per step over the last third: {:.1}",
        late_colors as f64 / late_steps
    );
    // Per stage: the mean over all steps, then over the last third.
    let late_ms = |t: f64| t / late_steps * 1e3;
    println!("  stage mean ms over all steps / the last third:");
    for s in Stage::ALL {
        println!(
            "  {:<10} {:.3} / {:.3} ms",
            s.name(),
            ms(sum[s as usize]),
            late_ms(late_sum[s as usize])
        );
    }
    for p in SolveStage::ALL {
        println!(
            "    {:<20} {:.3} / {:.3} ms",
            p.name(),
            ms(parts[p as usize]),
            late_ms(late_parts[p as usize])
        );
    }
}

/// A pyramid's boxes (bodies named `box_{layer}_{k}`) by layer, each
/// layer's in order of `k`.
fn pyramid_layers(
    world: &tumble::world::World,
) -> std::collections::BTreeMap<usize, Vec<tumble::world::BodyId>> {
    let mut layers: std::collections::BTreeMap<usize, Vec<(usize, tumble::world::BodyId)>> =
        Default::default();
    for id in world.body_ids() {
        let name = world.name(id).unwrap_or("");
        let Some((layer, k)) = name.strip_prefix("box_").and_then(|r| r.split_once('_')) else {
            continue;
        };
        let (Ok(layer), Ok(k)) = (layer.parse::<usize>(), k.parse::<usize>()) else {
            continue;
        };
        layers.entry(layer).or_default().push((k, id));
    }
    layers
        .into_iter()
        .map(|(layer, mut boxes)| {
            boxes.sort_unstable_by_key(|&(k, _)| k);
            (layer, boxes.into_iter().map(|(_, id)| id).collect())
        })
        .collect()
}

/// `TRACE_LEAN`: for every tenth layer of a pyramid (bodies named
/// `box_{layer}_{k}`), how far its middle box has moved out of the
/// pyramid's plane (y, mm) and its turn about the pyramid's long axis
/// (x, mrad): a one-box-thick wall leaning over sideways.
fn trace_lean_line(world: &tumble::world::World, step: usize) {
    let layers = pyramid_layers(world);
    let top = layers.keys().next_back().copied().unwrap_or(0);
    let mut line = String::new();
    for (&layer, boxes) in &layers {
        if layer % 10 != 0 && layer != top {
            continue;
        }
        let id = boxes[boxes.len() / 2];
        let y = world.center_of_mass(id).unwrap().y;
        let turn = world.orientation(id).unwrap().to_scaled_axis().x;
        line += &format!("  {layer}: {:+.1} mm {:+.2} mrad", y * 1e3, turn * 1e3);
    }
    eprintln!("step {step}: out of plane (y) and turn about x of each tenth layer's middle box{line}");
}

/// `TRACE_SINK`: for every tenth layer of a pyramid (bodies named
/// `box_{layer}_{k}`), how far its middle and end boxes sank below where they
/// began (mm), how far its end box moved towards the middle (mm) and its tilt
/// about y (mrad); and how many contact points were warm-started.
fn trace_sink_line(world: &tumble::world::World, step: usize, warm_started: usize) {
    let layers: std::collections::BTreeMap<usize, Vec<(usize, DVec3, f64)>> = pyramid_layers(world)
        .into_iter()
        .map(|(layer, ids)| {
            let boxes = ids
                .into_iter()
                .enumerate()
                .map(|(k, id)| {
                    let x = world.center_of_mass(id).unwrap();
                    let tilt = world.orientation(id).unwrap().to_scaled_axis().y;
                    (k, x, tilt)
                })
                .collect();
            (layer, boxes)
        })
        .collect();
    let line: Vec<String> = layers
        .iter()
        .filter(|(l, _)| *l % 10 == 0)
        .map(|(&l, boxes)| {
            let n = boxes.len();
            let at = |k: usize| boxes.iter().find(|b| b.0 == k).copied().unwrap();
            let (mid, end) = (at(n / 2), at(n - 1));
            let sink = |x: DVec3| (0.5 + l as f64 - x.z) * 1e3;
            let end_x0 = (n as f64 - 1.0) / 2.0 * 1.05;
            format!(
                "{l}: {:.1}/{:.1}/{:+.1} tilt {:+.1}",
                sink(mid.1),
                sink(end.1),
                (end_x0 - end.1.x) * 1e3,
                end.2 * 1e3
            )
        })
        .collect();
    eprintln!(
        "step {step}: {warm_started} of {} points warm-started; sink mid/end/inwards (mm), end tilt about y (mrad) {}",
        world.contacts().len(),
        line.join("  ")
    );
}

/// `TRACE_TOWER`: for a tower of boxes (ground first, then the boxes from
/// the bottom), each of five interfaces' normal impulse over the step
/// against the weight above it times dt, and the vertical speed of the box
/// resting on it.
fn trace_tower_line(world: &tumble::world::World, step: usize) {
    let ids = world.body_ids();
    let n = ids.len() - 1;
    let dt = world.settings().dt;
    let gravity = world.settings().gravity.length();
    let mut line = String::new();
    for k in [0, n / 4, n / 2, 3 * n / 4, n - 1] {
        let (lower, upper) = (ids[k], ids[k + 1]);
        let load: f64 = world
            .contacts()
            .iter()
            .filter(|c| (c.body_a, c.body_b) == (lower, upper) || (c.body_a, c.body_b) == (upper, lower))
            .map(|c| c.normal_impulse)
            .sum();
        let weight = (n - k) as f64 * gravity * dt;
        let vz = world.linear_velocity(upper).unwrap().z;
        // The gap between the two boxes' faces (mm; negative: overlap).
        // Body 0 is the ground, whose top face is at z = 0.
        let z = |id| world.center_of_mass(id).unwrap().z;
        let gap = if k == 0 {
            z(upper) - 0.5
        } else {
            z(upper) - z(lower) - 1.0
        };
        line += &format!("  {k}: {:.3} vz {:+.4} gap {:+.2}", load / weight, vz, gap * 1e3);
    }
    eprintln!("step {step}: load / weight above and speed at interfaces{line}");
}

/// `TRACE_BODY=name`: after every step, that body's position, velocity and
/// turn, and each contact point on it: the other body, the point's height
/// and gap, its normal and the friction it carries against its normal
/// impulse (what slides: `|t| / n` at the friction coefficient).
fn trace_body_line(world: &tumble::world::World, step: usize, name: &str) {
    // `#k`: the k-th body (names repeat in the ragdoll pile).
    let found = match name.strip_prefix('#').and_then(|k| k.parse::<usize>().ok()) {
        Some(k) => world.body_ids().get(k).copied(),
        None => world
            .body_ids()
            .into_iter()
            .find(|&id| world.name(id) == Ok(name)),
    };
    let Some(id) = found else {
        return;
    };
    let (x, v) = (
        world.center_of_mass(id).unwrap(),
        world.linear_velocity(id).unwrap(),
    );
    let turn = world.orientation(id).unwrap().to_scaled_axis();
    eprintln!(
        "step {step}: {name} at {:.4?} v {:.4?} m/s w {:.3?} rad/s turned {:.2?} mrad",
        x.to_array(),
        v.to_array(),
        world.angular_velocity(id).unwrap().to_array(),
        (turn * 1e3).to_array()
    );
    for c in world
        .contacts()
        .iter()
        .filter(|c| c.body_a == id || c.body_b == id)
    {
        let other = if c.body_a == id { c.body_b } else { c.body_a };
        let n = c.normal_impulse;
        let t = c.tangent_impulse.length();
        eprintln!(
            "    with {} at z {:.3} x {:.3}: gap {:+.2} mm, normal {:.3?}, n {:.4} N s, |t| / n {:.3}",
            world.name(other).unwrap_or("?"),
            c.contact.point.z,
            c.contact.point.x,
            c.contact.distance * 1e3,
            c.contact.normal.to_array(),
            n,
            if n > 0.0 { t / n } else { 0.0 }
        );
    }
}

/// Sets MXCSR's DAZ (bit 6) and FTZ (bit 15) on this thread (`FLUSH_SUBNORMALS`).
#[cfg(target_arch = "x86_64")]
#[allow(deprecated)] // `_mm_setcsr`: the one way to set the flags from Rust
fn flush_subnormals() {
    use std::arch::x86_64::{_mm_getcsr, _mm_setcsr};
    // SAFETY: the flags change how this thread rounds subnormals, nothing else.
    unsafe { _mm_setcsr(_mm_getcsr() | 0x8040) };
}

/// Unmasks MXCSR's denormal-operand (bit 8) and underflow (bit 11)
/// exceptions on this thread, its sticky flags cleared (`TRAP_SUBNORMALS`).
#[cfg(target_arch = "x86_64")]
#[allow(deprecated)] // `_mm_setcsr`: the one way to set the flags from Rust
fn trap_subnormals() {
    use std::arch::x86_64::{_mm_getcsr, _mm_setcsr};
    // SAFETY: an unmasked exception raises SIGFPE, which ends the run.
    unsafe { _mm_setcsr(_mm_getcsr() & !((1 << 8) | (1 << 11) | 0x3f)) };
}

#[cfg(not(target_arch = "x86_64"))]
fn trap_subnormals() {
    eprintln!("TRAP_SUBNORMALS: x86-64 only, ignored");
}

#[cfg(not(target_arch = "x86_64"))]
fn flush_subnormals() {
    eprintln!("FLUSH_SUBNORMALS: x86-64 only, ignored");
}
