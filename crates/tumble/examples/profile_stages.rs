//! Prints the mean time per step and per stage of a standard scene:
//! `cargo run --release -p tumble --example profile_stages -- pyramid 300 [threads]`
//! (scenes: pyramid, pile100, pile1000, chain).
use tumble::scenes;
use tumble::world::{SolveStage, Stage};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map(String::as_str).unwrap_or("pyramid");
    let steps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(300);
    let mut scene = match name {
        "pyramid" => scenes::pyramid(),
        "pile100" => scenes::pile(1),
        "pile1000" => scenes::pile(10),
        "chain" => scenes::chain(),
        other => panic!("unknown scene {other}"),
    };
    scene.settings.sleeping = false;
    scene.settings.threads = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    let (mut world, _) = scene.build().unwrap();
    let mut sum = [0.0f64; 7];
    let mut parts = [0.0f64; 8];
    let mut total = 0.0;
    for _ in 0..steps {
        let r = world.step();
        for s in Stage::ALL {
            sum[s as usize] += r.time(s).as_secs_f64();
        }
        for p in SolveStage::ALL {
            parts[p as usize] += r.solve_time(p).as_secs_f64();
        }
        total += r.total_time().as_secs_f64();
    }
    let ms = |t: f64| t / steps as f64 * 1e3;
    println!(
        "{name}: {:.3} ms/step on {} threads",
        ms(total),
        world.settings().threads
    );
    for s in Stage::ALL {
        println!("  {:<10} {:.3} ms", s.name(), ms(sum[s as usize]));
    }
    for p in SolveStage::ALL {
        println!("    {:<20} {:.3} ms", p.name(), ms(parts[p as usize]));
    }
}
