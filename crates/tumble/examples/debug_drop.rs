use tumble::world::{BodyDesc, World, WorldSettings};
use tumble_collide::shape::{Cuboid, Shape};
use tumble_collide::DVec3;
fn main() {
    let mut world = World::new(WorldSettings { gravity: DVec3::ZERO, sleeping: false, ..WorldSettings::default() }).unwrap();
    let cube = || Shape::Cuboid(Cuboid::new(DVec3::new(0.3, 0.2, 0.1)).unwrap());
    let a = world.add_body(&BodyDesc::dynamic(cube()).at(DVec3::new(-1.0, 0.15, 0.05)).with_mass(2.0).with_material(0.3, 0.5)
        .with_velocity(DVec3::new(3.0, 0.0, 0.0), DVec3::new(0.0, 0.0, 1.0))).unwrap();
    let _b = world.add_body(&BodyDesc::dynamic(cube()).at(DVec3::new(1.0, 0.0, 0.0)).with_mass(1.0).with_material(0.3, 0.5)).unwrap();
    let mut e_prev = world.kinetic_energy();
    for i in 0..120 {
        let r = world.step();
        let e = world.kinetic_energy();
        if (e - e_prev).abs() > 1e-12 {
            println!("step {i}: E {e_prev:.9} -> {e:.9} ({:+.3e}) contacts {} pen {:.5} w_a {:.4?}", e - e_prev, r.contacts, r.max_penetration, world.angular_velocity(a).unwrap());
        }
        e_prev = e;
    }
}
