use tumble::scenes;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(50);
    let steps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(150);
    let mut scene = scenes::concave_pile(n);
    scene.settings.threads = 1;
    let (mut world, ids) = scene.build().unwrap();
    let (mut worst, mut over) = (0.0f64, 0);
    for step in 0..steps {
        let r = world.step();
        worst = worst.max(r.max_penetration);
        if r.max_penetration > 0.002 {
            over += 1;
            let c = world
                .contacts()
                .iter()
                .min_by(|a, b| a.contact.distance.total_cmp(&b.contact.distance))
                .unwrap();
            let ia = ids.iter().position(|&i| i == c.body_a).unwrap();
            let ib = ids.iter().position(|&i| i == c.body_b).unwrap();
            if std::env::var("V").is_ok() {
                eprintln!("step {step}: {:.4} {ia} {ib}", r.max_penetration);
            }
        }
    }
    println!("n {n}: worst {worst:.4}, steps over 2 mm {over}");
}
