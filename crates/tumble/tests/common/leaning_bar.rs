//! The leaning bar of the end-overlap tests (`concave_pile.rs` with closed
//! triangle meshes, `continuous.rs` with box primitives): a thin bar whose
//! near end touches a wall or a slab and whose far end stands off it, swung
//! into it within one step, where its speculative contacts held only the
//! near end.

use tumble::world::{BodyDesc, BodyId, World};
use tumble_collide::shape::Shape;
use tumble_collide::{DQuat, DVec3, Pose};

/// Half extents of the bar (m).
pub const BAR_HALF: DVec3 = DVec3::new(0.02, 0.3, 0.02);

/// A world without gravity holding `wall` (a body whose face is the plane
/// x = 0, the body behind it) and a thin bar of [`BAR_HALF`] made by
/// `shape` (a box of given half extents) leaning on it: turned about z, one
/// end touches the wall (1 mm away), the other stands 8 cm out. Gives the
/// world, the bar, the bar's centre and the x of its far end's outer face.
pub fn leaning_bar(
    wall: &BodyDesc,
    shape: &dyn Fn(DVec3) -> Shape,
    continuous: bool,
) -> (World, BodyId, DVec3, f64) {
    let mut world = super::weightless_world(continuous);
    world.add_body(wall).unwrap();
    let theta = (0.08f64 / 0.6).asin();
    let lean = BAR_HALF.x * theta.cos() + BAR_HALF.y * theta.sin();
    let centre = DVec3::new(0.001 + lean, 0.0, 0.0);
    let bar = world
        .add_body(
            &BodyDesc::dynamic(shape(BAR_HALF))
                .with_pose(Pose {
                    position: centre,
                    rotation: DQuat::from_rotation_z(-theta),
                })
                .with_density(1000.0)
                .with_material(0.0, 0.0),
        )
        .unwrap();
    (world, bar, centre, centre.x + lean)
}

/// How deep the bar's deepest corner lies behind the plane x = 0 (m).
pub fn bar_depth(world: &World, bar: BodyId) -> f64 {
    let pose = world.pose(bar).unwrap();
    (0..8)
        .map(|k| {
            let sign = |bit: usize| if k & bit == 0 { -1.0 } else { 1.0 };
            -pose
                .transform_point(DVec3::new(sign(1), sign(2), sign(4)) * BAR_HALF)
                .x
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The bar, leaning with its near end 1 mm from a heavy dynamic slab (both
/// made by `shape`), spun about its own centre by a torque during one step
/// up to `spin` (rad/s; the speculative contacts are found with the
/// velocities the step starts with, zero): its far end swings into the
/// slab within the step while the two centres stay where they were, so the
/// pair is no landing. Gives the bar's depth behind the slab's face after
/// the step (m), how far its centre moved (m) and the contact margin (m).
pub fn bar_spun_into_a_slab(shape: &dyn Fn(DVec3) -> Shape, spin: f64, continuous: bool) -> (f64, f64, f64) {
    let slab = BodyDesc::dynamic(shape(DVec3::new(0.1, 1.0, 1.0)))
        .at(DVec3::new(-0.1, 0.0, 0.0))
        .with_density(20000.0)
        .with_material(0.0, 0.0);
    let (mut world, bar, centre, _) = leaning_bar(&slab, shape, continuous);
    // The torque that spins the free bar up to `spin` about z in a step.
    let inertia_z =
        world.body(bar).unwrap().mass() * 4.0 * (BAR_HALF.y * BAR_HALF.y + BAR_HALF.x * BAR_HALF.x) / 12.0;
    world
        .apply_torque(bar, DVec3::Z * (inertia_z * spin / world.settings().dt))
        .unwrap();
    world.step();
    let moved = (world.center_of_mass(bar).unwrap() - centre).length();
    (bar_depth(&world, bar), moved, world.settings().contact_margin)
}

/// [`bar_spun_into_a_slab`] at 36, 45 and 55 rad/s: the centres stay put
/// (no landing), the bar ends more than two contact margins inside the slab
/// without the continuous stage (so the test tests it), and within one
/// margin with it (the end-overlap stage collided the pair again and took
/// the overlap out).
pub fn assert_spun_bar_is_pushed_back_out(shape: &dyn Fn(DVec3) -> Shape) {
    for spin in [36.0, 45.0, 55.0] {
        let (with, _, margin) = bar_spun_into_a_slab(shape, spin, true);
        let (without, moved, _) = bar_spun_into_a_slab(shape, spin, false);
        assert!(
            moved < 0.5 * margin,
            "{spin} rad/s: the bar's centre moved {moved} m: the pair would be a landing"
        );
        assert!(
            without > 2.0 * margin,
            "{spin} rad/s: {without} m deep without the continuous stage: the test no longer tests it"
        );
        assert!(
            with <= margin,
            "{spin} rad/s: the bar ended {with} m inside the slab"
        );
    }
}
