//! Scenes with joints, for the benchmark harness and the tests: the heavy
//! chain (a 1:100 mass ratio on ball joints), a pile of 100 ragdolls, and a
//! net of ball joints dropped onto a box.
//! Defined once here; the Rapier peer builds its world from these
//! descriptions (`tumble-bench`), so both engines run the same bodies and
//! joints.

use super::{no_sleep, Scene};
use crate::joint::JointDesc;
use crate::world::BodyDesc;
use tumble_collide::shape::{Capsule, Cuboid, HalfSpace, Shape, Sphere};
use tumble_collide::{DQuat, DVec3, Pose};

fn sphere(r: f64) -> Shape {
    Shape::Sphere(Sphere::new(r).expect("positive radius"))
}

fn cuboid(h: [f64; 3]) -> Shape {
    Shape::Cuboid(Cuboid::new(DVec3::from_array(h)).expect("positive half extents"))
}

/// A capsule along z of total length `length` (caps included) and radius `r`.
fn capsule(length: f64, r: f64) -> Shape {
    Shape::Capsule(Capsule::new(r, length / 2.0 - r).expect("positive dimensions"))
}

/// heavy_chain: 20 links (spheres of radius 0.03 m, 0.1 kg) 0.1 m apart
/// along +x on ball joints at their midpoints, the first jointed to the
/// world at (0, 0, 2), and a 10 kg sphere (radius 0.1 m) on a ball joint
/// 0.1 m beyond the last link; released horizontal, no ground; dt 1/60,
/// 600 steps. The weight is the last body.
pub fn heavy_chain() -> Scene {
    let top = DVec3::new(0.0, 0.0, 2.0);
    let mut bodies = Vec::new();
    let mut joints = Vec::new();
    for i in 0..21 {
        let centre = top + DVec3::X * (0.1 * i as f64 + 0.05);
        let (shape, mass, name) = if i < 20 {
            (sphere(0.03), 0.1, format!("link{i}"))
        } else {
            (sphere(0.1), 10.0, "weight".to_string())
        };
        bodies.push(BodyDesc::dynamic(shape).at(centre).with_mass(mass).named(name));
        let before = (i > 0).then(|| i - 1);
        joints.push(JointDesc::ball(i, before, centre - DVec3::X * 0.05));
    }
    Scene {
        name: "heavy_chain".into(),
        settings: no_sleep(),
        bodies,
        steps: 600,
        joints,
        no_contact: Vec::new(),
        gears: Vec::new(),
    }
}

/// One ragdoll of 11 bodies and 10 joints standing with its feet at the
/// origin, z up: pelvis, torso, head, and per side an upper arm, forearm,
/// thigh and shin (capsules); ball joints at the spine, neck, shoulders and
/// hips, hinges at the elbows (bending forward, 0..2.5 rad) and knees
/// (backward, 0..2.4 rad). Masses 10, 25, 5, 2.5, 1.5, 7, 4 kg (70 kg).
/// Joint bodies are indices into the returned bodies.
pub fn ragdoll() -> (Vec<BodyDesc>, Vec<JointDesc<usize>>) {
    let mut bodies = vec![
        BodyDesc::dynamic(cuboid([0.15, 0.1, 0.08]))
            .at(DVec3::new(0.0, 0.0, 0.95))
            .with_mass(10.0)
            .named("pelvis"),
        BodyDesc::dynamic(cuboid([0.17, 0.1, 0.22]))
            .at(DVec3::new(0.0, 0.0, 1.25))
            .with_mass(25.0)
            .named("torso"),
        BodyDesc::dynamic(sphere(0.11))
            .at(DVec3::new(0.0, 0.0, 1.62))
            .with_mass(5.0)
            .named("head"),
    ];
    let (pelvis, torso, head) = (0, 1, 2);
    let mut joints = vec![
        JointDesc::ball(torso, Some(pelvis), DVec3::new(0.0, 0.0, 1.02)),
        JointDesc::ball(head, Some(torso), DVec3::new(0.0, 0.0, 1.49)),
    ];
    for side in [-1.0, 1.0] {
        let mut limb = |name: &str, shape: Shape, mass: f64, top: DVec3, length: f64| {
            bodies.push(
                BodyDesc::dynamic(shape)
                    .at(top - DVec3::Z * (length / 2.0))
                    .with_mass(mass)
                    .named(name),
            );
            bodies.len() - 1
        };
        let (shoulder, elbow) = (
            DVec3::new(0.0, 0.24 * side, 1.45),
            DVec3::new(0.0, 0.24 * side, 1.15),
        );
        let (hip, knee) = (
            DVec3::new(0.0, 0.1 * side, 0.9),
            DVec3::new(0.0, 0.1 * side, 0.45),
        );
        let upper = limb("upper_arm", capsule(0.3, 0.05), 2.5, shoulder, 0.3);
        let fore = limb("forearm", capsule(0.28, 0.045), 1.5, elbow, 0.28);
        let thigh = limb("thigh", capsule(0.45, 0.07), 7.0, hip, 0.45);
        let shin = limb("shin", capsule(0.45, 0.055), 4.0, knee, 0.45);
        joints.push(JointDesc::ball(upper, Some(torso), shoulder));
        joints.push(JointDesc::hinge(fore, Some(upper), elbow, DVec3::Y * side).with_limits(0.0, 2.5));
        joints.push(JointDesc::ball(thigh, Some(pelvis), hip));
        joints.push(JointDesc::hinge(shin, Some(thigh), knee, -DVec3::Y * side).with_limits(0.0, 2.4));
    }
    (bodies, joints)
}

/// The lowest z of any shape's bounding box of `bodies`, all placed by
/// `frame` (m).
fn lowest_z(bodies: &[BodyDesc], frame: &Pose) -> f64 {
    bodies
        .iter()
        .flat_map(|b| {
            let pose = frame.mul_pose(&b.pose);
            b.shapes
                .iter()
                .map(move |s| s.shape.aabb(&pose.mul_pose(&s.local_pose)).min.z)
        })
        .fold(f64::INFINITY, f64::min)
}

/// ragdoll_pile: 100 [`ragdoll`]s standing in a 10 x 10 grid 1 m apart on a
/// static ground box (half extents 20 x 20 x 0.5, top at z = 0), each
/// tipped by 0.3 rad about the midpoint of its feet (about x in even rows, y
/// in odd ones) so that they topple onto each other, and raised so that its
/// lowest point is 1 mm above the ground (tipped about x, one shin would
/// start 3 cm into it); dt 1/60, 600 steps. The ground is body 0; ragdoll
/// `k` is bodies `1 + 11 k ..`.
pub fn ragdoll_pile() -> Scene {
    let mut bodies = vec![BodyDesc::fixed(cuboid([20.0, 20.0, 0.5]))
        .at(DVec3::new(0.0, 0.0, -0.5))
        .named("ground")];
    let mut joints = Vec::new();
    let (one, one_joints) = ragdoll();
    for row in 0..10 {
        for col in 0..10 {
            let tilt = if row % 2 == 0 {
                DQuat::from_rotation_x(0.3)
            } else {
                DQuat::from_rotation_y(0.3)
            };
            let tipped = Pose {
                position: DVec3::ZERO,
                rotation: tilt,
            };
            let lowest = lowest_z(&one, &tipped);
            let feet = DVec3::new(col as f64 - 4.5, row as f64 - 4.5, 0.001 - lowest);
            let place = Pose {
                position: feet,
                rotation: tilt,
            };
            let first = bodies.len();
            for b in &one {
                let mut b = b.clone();
                b.pose = place.mul_pose(&b.pose);
                bodies.push(b);
            }
            for j in &one_joints {
                let mut j = j.clone().with_bodies(|i| first + i);
                j.anchor = place.transform_point(j.anchor);
                j.axis = tilt * j.axis;
                joints.push(j);
            }
        }
    }
    Scene {
        name: "ragdoll_pile".into(),
        settings: no_sleep(),
        bodies,
        steps: 600,
        joints,
        no_contact: Vec::new(),
        gears: Vec::new(),
    }
}

/// net_drop: an `n` x `n` net of spheres (radius 0.04 m, 0.1 kg) 0.1 m
/// apart, centred over the origin at z = 0.8 m, each on a ball joint to its
/// neighbour in +x and in +y at their midpoint (`2 n (n - 1)` joints,
/// `(n - 1)^2` loops), dropped onto a static ground half-space at z = 0 and,
/// `on_box`, onto a static 0.6 m cube standing on it under the net's middle;
/// dt 1/60, 300 steps. The net is the last `n * n` bodies, row by row
/// (sphere `(i, k)` at x = `0.1 i - half`, y = `0.1 k - half`). A net's
/// in-plane rows outnumber its bodies' in-plane freedoms, which is the case
/// that sizes `MAX_OWNED_SUBSTITUTION` (docs/pipeline.md).
pub fn net_drop(n: usize, on_box: bool) -> Scene {
    let mut bodies = vec![BodyDesc::fixed(Shape::HalfSpace(
        HalfSpace::new(DVec3::Z, 0.0).expect("unit normal"),
    ))
    .named("ground")];
    if on_box {
        bodies.push(
            BodyDesc::fixed(cuboid([0.3; 3]))
                .at(DVec3::new(0.0, 0.0, 0.3))
                .named("box"),
        );
    }
    let first = bodies.len();
    let gap = 0.1;
    let half = n.saturating_sub(1) as f64 * gap / 2.0;
    let centre = |i: usize, k: usize| DVec3::new(i as f64 * gap - half, k as f64 * gap - half, 0.8);
    for i in 0..n {
        for k in 0..n {
            bodies.push(
                BodyDesc::dynamic(sphere(0.04))
                    .at(centre(i, k))
                    .with_mass(0.1)
                    .named(format!("node{i}_{k}")),
            );
        }
    }
    let mut joints = Vec::new();
    for i in 0..n {
        for k in 0..n {
            let a = first + i * n + k;
            if i + 1 < n {
                joints.push(JointDesc::ball(
                    a,
                    Some(a + n),
                    centre(i, k) + DVec3::X * gap / 2.0,
                ));
            }
            if k + 1 < n {
                joints.push(JointDesc::ball(
                    a,
                    Some(a + 1),
                    centre(i, k) + DVec3::Y * gap / 2.0,
                ));
            }
        }
    }
    Scene {
        name: "net_drop".into(),
        settings: no_sleep(),
        bodies,
        steps: 300,
        joints,
        no_contact: Vec::new(),
        gears: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_joint_scenes_build_with_their_counts() {
        let (w, ids) = heavy_chain().build().unwrap();
        assert_eq!((ids.len(), w.joint_count()), (21, 21));
        for (n, on_box) in [(3, false), (10, true)] {
            let (w, ids) = net_drop(n, on_box).build().unwrap();
            let fixed = 1 + usize::from(on_box);
            assert_eq!((ids.len(), w.joint_count()), (fixed + n * n, 2 * n * (n - 1)));
            assert!(w.max_joint_error().0 < 1e-12);
        }
        let pile = ragdoll_pile();
        assert_eq!((pile.bodies.len(), pile.joints.len()), (1 + 1100, 1000));
        let (w, _) = pile.build().unwrap();
        assert_eq!(w.joint_count(), 1000);
        // Every joint starts closed (anchors coincide on both bodies).
        assert!(w.max_joint_error().0 < 1e-12);
        // Every ragdoll's lowest point starts 1 mm above the ground.
        let ground = pile.bodies[0].shapes[0].shape.aabb(&pile.bodies[0].pose).max.z;
        let lowest = |k: usize| lowest_z(&pile.bodies[1 + 11 * k..12 + 11 * k], &Pose::IDENTITY);
        for k in 0..100 {
            assert!(
                (lowest(k) - ground - 0.001).abs() < 1e-9,
                "ragdoll {k}: {}",
                lowest(k)
            );
        }
        let mass: f64 = ragdoll()
            .0
            .iter()
            .map(|b| match b.mass {
                crate::world::MassDesc::Mass(m) => m,
                _ => 0.0,
            })
            .sum();
        assert!((mass - 70.0).abs() < 1e-12);
    }
}
