//! Prints the mean time per step and per stage of a standard scene:
//! `cargo run --release -p tumble --example profile_stages -- pyramid 300`.
use tumble::scenes;
use tumble::world::Stage;

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
    let (mut world, _) = scene.build().unwrap();
    let mut sum = [0.0f64; 7];
    let mut total = 0.0;
    for _ in 0..steps {
        let r = world.step();
        for s in Stage::ALL {
            sum[s as usize] += r.time(s).as_secs_f64();
        }
        total += r.total_time().as_secs_f64();
    }
    println!("{name}: {:.3} ms/step", total / steps as f64 * 1e3);
    for s in Stage::ALL {
        println!("  {:?}: {:.3} ms", s, sum[s as usize] / steps as f64 * 1e3);
    }
}
