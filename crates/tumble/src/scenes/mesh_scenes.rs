//! Scenes made of concave triangle meshes: the torus chain (plain and cut
//! into convex pieces for the peers) and the tori pass-through of
//! shared/scenes.md.

use super::{ten_seconds_without_sleep, Scene};
use crate::body::BodyKind;
use crate::world::{BodyDesc, MassDesc, ShapeDesc, WorldSettings};
use tumble_collide::mesh::{torus_mesh, TriMesh};
use tumble_collide::shape::{ConvexHull, HalfSpace, MeshShape, Shape};
use tumble_collide::{DQuat, DVec3, Pose};

/// chain: 21 interlocked torus links (`torus_mesh(1, 0.2, 32, 12)`), link 0
/// static, hanging at 60 degrees from the vertical; dt 1/60, 600 steps. Links
/// carry the mass of the solid torus, m = 2 pi^2 R r^2 (density 1).
pub fn chain() -> Scene {
    let link = Shape::Mesh(MeshShape::new(chain_link_mesh()).expect("tree builds"));
    chain_of("chain", vec![ShapeDesc::new(link)])
}

/// chain_decomposed: the chain with each link cut into 32 convex pieces,
/// piece `i` the hull of the link mesh's rings `i` and `i + 1` (its tube
/// segment): the form the peers without dynamic concave meshes need
/// (scenes.md), with the same links, poses and mass.
pub fn chain_decomposed() -> Scene {
    let mesh = chain_link_mesh();
    let (n_major, n_minor) = (CHAIN_LINK_RINGS, CHAIN_LINK_RING_VERTICES);
    let pieces = (0..n_major)
        .map(|i| {
            let next = (i + 1) % n_major;
            let points: Vec<DVec3> = [i, next]
                .iter()
                .flat_map(|&ring| {
                    mesh.vertices()[ring * n_minor..(ring + 1) * n_minor]
                        .iter()
                        .copied()
                })
                .collect();
            ShapeDesc::new(Shape::ConvexHull(
                ConvexHull::from_points(&points).expect("a tube segment spans a volume"),
            ))
        })
        .collect();
    chain_of("chain_decomposed", pieces)
}

/// Rings of the chain's link mesh (the torus' major resolution).
const CHAIN_LINK_RINGS: usize = 32;
/// Vertices per ring of the link mesh (the torus' minor resolution).
const CHAIN_LINK_RING_VERTICES: usize = 12;

/// The chain's link: `torus_mesh(1, 0.2, 32, 12)`, vertex `i * 12 + j` on ring `i`.
fn chain_link_mesh() -> TriMesh {
    torus_mesh(1.0, 0.2, CHAIN_LINK_RINGS, CHAIN_LINK_RING_VERTICES).expect("valid torus")
}

/// The chain's 21 links, each made of `link`'s shapes (in the link frame).
fn chain_of(name: &str, link: Vec<ShapeDesc>) -> Scene {
    let theta = 60f64.to_radians();
    let e = DVec3::new(-theta.sin(), 0.0, -theta.cos());
    let tilt = DQuat::from_rotation_y(theta);
    let mass = 2.0 * std::f64::consts::PI.powi(2) * 1.0 * 0.2 * 0.2;
    let bodies = (0..21)
        .map(|k| {
            let rotation = if k % 2 == 0 {
                tilt * DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2)
            } else {
                tilt * DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2)
                    * DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2)
            };
            let kind = if k == 0 {
                BodyKind::Static
            } else {
                BodyKind::Dynamic
            };
            BodyDesc {
                kind,
                shapes: link.clone(),
                mass: MassDesc::Mass(mass),
                ..BodyDesc::default()
            }
            .with_pose(Pose {
                position: e * (1.5 * k as f64),
                rotation,
            })
            .named(format!("link{k}"))
        })
        .collect();
    ten_seconds_without_sleep(name, bodies)
}

/// A torus (R 1, r 0.3, 50 x 50: the thesis' 5,000 triangles) lying on the
/// ground: the resting half of the tori pass-through scene.
pub fn torus_on_ground() -> Scene {
    let torus =
        Shape::Mesh(MeshShape::new(torus_mesh(1.0, 0.3, 50, 50).expect("valid torus")).expect("tree builds"));
    Scene {
        name: "torus_on_ground".into(),
        settings: WorldSettings::default(),
        bodies: vec![
            BodyDesc::fixed(Shape::HalfSpace(HalfSpace::ground())).named("ground"),
            BodyDesc::dynamic(torus)
                .at(DVec3::new(0.0, 0.0, 0.35))
                .named("torus"),
        ],
        steps: 240,
        joints: Vec::new(),
        no_contact: Vec::new(),
        gears: Vec::new(),
    }
}

/// tori_pass: the thesis' two tori (`torus_mesh(1, 0.3, 50, 50)`, 5,000
/// triangles each) as dynamics. Torus A lies flat on the ground (centre
/// (0, 0, 0.3)), dynamic with density 1000; torus B is kinematic with the
/// orientation of the tori query scene, `Rz(0.1) * Rx(pi/2)` (ring nearly
/// in the xz plane), and moves at 1 m/s along x from (-3, 0.05, 1.32) to
/// (3, 0.05, 1.32) over 6 s (360 steps of 1/60 s). Its lower arc sweeps
/// through the height of A's hole (0.02 m above A's mid-plane, as in the
/// query scene), where it meets A's tube and drags A along; B's centre is
/// raised by 1 m from the query path so that B's ring clears the ground.
pub fn tori_pass() -> Scene {
    let torus =
        Shape::Mesh(MeshShape::new(torus_mesh(1.0, 0.3, 50, 50).expect("valid torus")).expect("tree builds"));
    let b_rotation = DQuat::from_rotation_z(0.1) * DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2);
    Scene {
        name: "tori_pass".into(),
        settings: WorldSettings {
            sleeping: false,
            ..WorldSettings::default()
        },
        bodies: vec![
            BodyDesc::fixed(Shape::HalfSpace(HalfSpace::ground())).named("ground"),
            BodyDesc::dynamic(torus.clone())
                .at(DVec3::new(0.0, 0.0, 0.3))
                .named("torus_a"),
            BodyDesc::kinematic(torus)
                .with_pose(Pose {
                    position: DVec3::new(-3.0, 0.05, 1.32),
                    rotation: b_rotation,
                })
                .with_velocity(DVec3::new(1.0, 0.0, 0.0), DVec3::ZERO)
                .named("torus_b"),
        ],
        steps: 360,
        joints: Vec::new(),
        no_contact: Vec::new(),
        gears: Vec::new(),
    }
}
