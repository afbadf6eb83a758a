//! The pyramid, pile and cradle of `shared/scenes.md` built in Rapier (rapier3d, f32,
//! one thread), shared by the `peer-rapier` binary and the in-process
//! criterion bench `dynamics_vs_rapier`.
//!
//! Settings mirror the other peers: dt 1/60 s, gravity -9.81 z, friction 0.5 on
//! every collider (Rapier's default combine rule, Average, yields 0.5),
//! restitution 0, sleeping off (`can_sleep(false)`), Rapier's default solver
//! iterations and substeps.

use crate::scenes::{self, PileShape};
use rapier3d::prelude::*;

/// Friction coefficient of every collider.
pub const FRICTION: f32 = 0.5;

/// A point or vector of the scene data as Rapier's f32 vector.
pub fn v(p: [f64; 3]) -> Vector {
    Vector::new(p[0] as f32, p[1] as f32, p[2] as f32)
}

/// An empty world with the scenes' gravity and time step.
pub fn world() -> PhysicsWorld {
    let mut w = PhysicsWorld::new();
    w.gravity = Vector::new(0.0, 0.0, -9.81);
    w.integration_parameters.dt = scenes::DT as f32;
    w
}

/// Adds a fixed box with half extents `half` centred at `centre`.
pub fn add_static_box(w: &mut PhysicsWorld, half: [f64; 3], centre: [f64; 3]) {
    w.insert(
        RigidBodyBuilder::fixed().translation(v(centre)),
        ColliderBuilder::cuboid(half[0] as f32, half[1] as f32, half[2] as f32)
            .friction(FRICTION)
            .restitution(0.0),
    );
}

/// Adds a dynamic body of density 1 with `collider`, at rest at `centre`.
pub fn add_dynamic(w: &mut PhysicsWorld, collider: ColliderBuilder, centre: [f64; 3]) -> RigidBodyHandle {
    w.insert(
        RigidBodyBuilder::dynamic()
            .translation(v(centre))
            .can_sleep(false),
        collider.friction(FRICTION).restitution(0.0).density(1.0),
    )
    .0
}

/// The 20-row pyramid: the world, its boxes' handles and start centres (top
/// box last).
pub fn pyramid() -> (PhysicsWorld, Vec<RigidBodyHandle>, Vec<[f64; 3]>) {
    pyramid_with_base(20, scenes::PYRAMID_GROUND)
}

/// The 100-row large pyramid (5,050 boxes), as [`pyramid`].
pub fn large_pyramid() -> (PhysicsWorld, Vec<RigidBodyHandle>, Vec<[f64; 3]>) {
    pyramid_with_base(100, scenes::LARGE_PYRAMID_GROUND)
}

fn pyramid_with_base(
    base: usize,
    ground: ([f64; 3], [f64; 3]),
) -> (PhysicsWorld, Vec<RigidBodyHandle>, Vec<[f64; 3]>) {
    let mut w = world();
    add_static_box(&mut w, ground.0, ground.1);
    let starts = scenes::pyramid_boxes_with_base(base);
    let h = scenes::PYRAMID_HALF as f32;
    let ids = starts
        .iter()
        .map(|&c| add_dynamic(&mut w, ColliderBuilder::cuboid(h, h, h), c))
        .collect();
    (w, ids, starts)
}

/// The pile of `n` bodies (a positive multiple of 100) in its container, or
/// `None` for another `n`.
pub fn pile(n: usize) -> Option<(PhysicsWorld, Vec<RigidBodyHandle>)> {
    let bodies = scenes::pile_bodies(n)?;
    let mut w = world();
    for (half, centre) in scenes::pile_container(n) {
        add_static_box(&mut w, half, centre);
    }
    let s = scenes::PILE_SIZE as f32;
    let ids = bodies
        .iter()
        .map(|&(shape, c)| {
            let col = match shape {
                PileShape::Sphere => ColliderBuilder::ball(s),
                PileShape::Cube => ColliderBuilder::cuboid(s, s, s),
            };
            add_dynamic(&mut w, col, c)
        })
        .collect();
    Some((w, ids))
}

/// Newton's cradle: zero gravity, dt 1/240 s, six spheres of 1 kg with
/// restitution 1 and friction 0 (Rapier's default combine rules, Average,
/// keep both), the striker last.
pub fn cradle() -> (PhysicsWorld, Vec<RigidBodyHandle>) {
    let mut w = world();
    w.gravity = Vector::ZERO;
    w.integration_parameters.dt = scenes::CRADLE_DT as f32;
    let ids = scenes::cradle_spheres()
        .into_iter()
        .map(|(c, vel)| {
            w.insert(
                RigidBodyBuilder::dynamic()
                    .translation(v(c))
                    .linvel(v(vel))
                    .can_sleep(false),
                ColliderBuilder::ball(scenes::CRADLE_R as f32)
                    .mass(1.0)
                    .friction(0.0)
                    .restitution(1.0),
            )
            .0
        })
        .collect();
    (w, ids)
}

/// The Rapier collider of a tumble shape (its own frame): balls, boxes,
/// capsules, convex hulls (from the hull's vertices) and triangle meshes
/// (`TriMesh`, default flags; give a dynamic mesh body its mass properties,
/// a mesh has no volume of its own in Rapier). Half-spaces have no twin.
pub fn collider(shape: &tumble::collide::shape::Shape) -> Result<ColliderBuilder, String> {
    use tumble::collide::shape::Shape;
    let f = |p: &tumble::collide::DVec3| v(p.to_array());
    Ok(match shape {
        Shape::Sphere(s) => ColliderBuilder::ball(s.radius() as f32),
        Shape::Cuboid(c) => {
            let h = c.half_extents();
            ColliderBuilder::cuboid(h.x as f32, h.y as f32, h.z as f32)
        }
        Shape::Capsule(c) => ColliderBuilder::capsule_z(c.half_height() as f32, c.radius() as f32),
        Shape::ConvexHull(h) => {
            let points: Vec<Vector> = h.vertices().iter().map(f).collect();
            ColliderBuilder::convex_hull(&points).ok_or("Rapier rejected a convex hull")?
        }
        Shape::Mesh(m) => {
            let vertices: Vec<Vector> = m.mesh().vertices().iter().map(f).collect();
            ColliderBuilder::trimesh(vertices, m.mesh().triangles().to_vec())
                .map_err(|e| format!("Rapier rejected a mesh: {e:?}"))?
        }
        other => return Err(format!("shape {} has no Rapier twin here", other.kind_name())),
    })
}

/// A jointed scene of `tumble::scenes` (heavy chain, ragdoll pile) built in
/// Rapier from the same descriptions: spheres, boxes and capsules with the
/// same masses and poses; ball joints as spherical joints, hinges as
/// revolute joints with the same limits (body 1 = the joint's body B, so
/// the angle is A's relative to B as in tumble); joints to the world hang
/// from one fixed body at the origin; contacts between jointed bodies off
/// (tumble's default). `multibody`: the joints as Rapier's
/// reduced-coordinate multibody joints instead of impulse joints.
pub struct JointedWorld {
    /// The world.
    pub world: PhysicsWorld,
    /// Handle of each body of the scene, in order.
    pub bodies: Vec<RigidBodyHandle>,
    /// Per joint: (body 1, local anchor 1, body 2, local anchor 2).
    pub anchors: Vec<(RigidBodyHandle, Vector, RigidBodyHandle, Vector)>,
}

/// Builds `scene` in Rapier (see [`JointedWorld`]).
pub fn jointed(scene: &tumble::scenes::Scene, multibody: bool) -> Result<JointedWorld, String> {
    use tumble::world::MassDesc;
    let mut w = world();
    let anchor_body = w
        .insert(
            RigidBodyBuilder::fixed(),
            ColliderBuilder::ball(0.01).sensor(true),
        )
        .0;
    let mut bodies = Vec::new();
    let mut frames = Vec::new();
    for b in &scene.bodies {
        let [shape] = b.shapes.as_slice() else {
            return Err(format!("{}: one shape per body expected", b.name));
        };
        let collider = collider(&shape.shape)
            .map_err(|e| format!("{}: {e}", b.name))?
            .friction(FRICTION)
            .restitution(0.0);
        let p = b.pose.position.to_array();
        let r = b.pose.rotation.to_scaled_axis().to_array();
        let builder = match b.kind {
            tumble::BodyKind::Dynamic => RigidBodyBuilder::dynamic().can_sleep(false),
            _ => RigidBodyBuilder::fixed(),
        };
        let builder = builder.translation(v(p)).rotation(v(r));
        let collider = match b.mass {
            MassDesc::Mass(m) => collider.mass(m as f32),
            _ => collider.density(1000.0),
        };
        bodies.push(w.insert(builder, collider).0);
        frames.push(b.pose);
    }
    let mut anchors = Vec::new();
    for j in &scene.joints {
        // Rapier's body 1 is tumble's body B (the world: the fixed body at
        // the origin), body 2 is A.
        let (h1, f1) = match j.body_b {
            Some(b) => (bodies[b], frames[b]),
            None => (anchor_body, tumble::collide::Pose::IDENTITY),
        };
        let (h2, f2) = (bodies[j.body_a], frames[j.body_a]);
        let a1 = f1.inverse_transform_point(j.anchor);
        let a2 = f2.inverse_transform_point(j.anchor);
        let axis1 = f1.rotation.conjugate() * j.axis.normalize();
        let axis2 = f2.rotation.conjugate() * j.axis.normalize();
        let data: GenericJoint = match j.kind {
            tumble::joint::JointKind::Ball => SphericalJointBuilder::new()
                .local_anchor1(v(a1.to_array()))
                .local_anchor2(v(a2.to_array()))
                .into(),
            tumble::joint::JointKind::Hinge => {
                let mut b = RevoluteJointBuilder::new(v(axis1.to_array()))
                    .local_anchor1(v(a1.to_array()))
                    .local_anchor2(v(a2.to_array()));
                if let Some([lo, hi]) = j.limits {
                    b = b.limits([lo as f32, hi as f32]);
                }
                let mut g: GenericJoint = b.into();
                g.set_local_axis2(v(axis2.to_array()));
                g
            }
            other => return Err(format!("joint kind {other:?} has no Rapier twin here")),
        };
        // As in tumble: no contacts between the two bodies of a joint.
        let mut data = data;
        data.set_contacts_enabled(j.collide_connected);
        if multibody {
            w.multibody_joints
                .insert(h1, h2, data, true)
                .ok_or("Rapier refused a multibody joint (not a tree?)")?;
        } else {
            w.impulse_joints.insert(h1, h2, data, true);
        }
        anchors.push((h1, v(a1.to_array()), h2, v(a2.to_array())));
    }
    Ok(JointedWorld {
        world: w,
        bodies,
        anchors,
    })
}

impl JointedWorld {
    /// The largest distance between the two anchors of a joint (m).
    pub fn largest_joint_error(&self) -> f64 {
        let at = |h: RigidBodyHandle, local: Vector| {
            let b = &self.world.bodies[h];
            b.rotation() * local + b.translation()
        };
        self.anchors
            .iter()
            .map(|&(h1, a1, h2, a2)| (at(h1, a1) - at(h2, a2)).length() as f64)
            .fold(0.0, f64::max)
    }
}
