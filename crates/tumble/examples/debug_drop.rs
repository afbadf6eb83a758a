use tumble::scenes;
use tumble_collide::DVec3;
fn main() {
    for off in [0.0, 0.01, 0.05] {
        let mut scene = scenes::tower(10);
        for (k, b) in scene.bodies.iter_mut().enumerate().skip(1) { b.pose.position += DVec3::new(if k % 2 == 0 { off } else { -off }, 0.0, 0.0); }
        scene.settings.substeps = 8; scene.settings.iterations = 2;
        let (mut world, ids) = scene.build().unwrap();
        let top = *ids.last().unwrap();
        let start = world.pose(top).unwrap().position;
        for _ in 0..600 { world.step(); }
        println!("offset {off}: top drift {:.4}", (world.pose(top).unwrap().position - start).length());
    }
}
