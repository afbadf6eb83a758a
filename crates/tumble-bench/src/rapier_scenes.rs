//! The standard scenes of `shared/scenes.md` built in Rapier (rapier3d, f32)
//! from their one definition in `tumble::scenes`, shared by the
//! `peer-rapier` binary, `ccd-matrix` and the in-process criterion bench
//! `dynamics_vs_rapier`.
//!
//! [`build`] reads a scene's plain form (`Scene::plain`): every body in its
//! body frame with the mass and principal inertia tumble computed, its
//! shapes posed in that frame. Materials combine as tumble combines them:
//! friction by the geometric mean, restitution by the maximum (Rapier's
//! `GeometricMean` and `Max` rules). Sleeping off (`can_sleep(false)`),
//! Rapier's default solver iterations and sub-steps.

use rapier3d::prelude::*;
use tumble::scenes::Scene;

/// Friction coefficient of the standard scenes' colliders (scenes.md).
pub const FRICTION: f32 = 0.5;

/// A point or vector of the scene data as Rapier's f32 vector.
pub fn v(p: [f64; 3]) -> Vector {
    Vector::new(p[0] as f32, p[1] as f32, p[2] as f32)
}

/// An empty world with the standard scenes' gravity and time step (scenes.md).
pub fn world() -> PhysicsWorld {
    let mut w = PhysicsWorld::new();
    w.gravity = Vector::new(0.0, 0.0, -9.81);
    w.integration_parameters.dt = 1.0 / 60.0;
    w
}

/// A tumble pose as Rapier's (f32).
fn pose(p: &tumble::collide::Pose) -> Pose {
    let q = p.rotation;
    Pose::from_parts(
        v(p.position.to_array()),
        Rotation::from_xyzw(q.x as f32, q.y as f32, q.z as f32, q.w as f32),
    )
}

/// The Rapier collider of a tumble shape (its own frame): balls, boxes,
/// capsules, convex hulls (from the hull's vertices) and triangle meshes
/// (`TriMesh`, default flags, or `FIX_INTERNAL_EDGES` for a mesh with a
/// smooth surface; give a dynamic mesh body its mass properties,
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
            // A mesh that tumble touches as a smooth surface gets Rapier's
            // nearest option: normals corrected at internal edges.
            let flags = if m.crease_angle().is_some() {
                TriMeshFlags::FIX_INTERNAL_EDGES
            } else {
                TriMeshFlags::empty()
            };
            ColliderBuilder::trimesh_with_flags(vertices, m.mesh().triangles().to_vec(), flags)
                .map_err(|e| format!("Rapier rejected a mesh: {e:?}"))?
        }
        other => return Err(format!("shape {} has no Rapier twin here", other.kind_name())),
    })
}

/// A scene of `tumble::scenes` built in Rapier (see [`build`]).
pub struct SceneWorld {
    /// The world.
    pub world: PhysicsWorld,
    /// Handle of each body of the scene, in order.
    pub bodies: Vec<RigidBodyHandle>,
    /// Per joint: (body 1, local anchor 1, body 2, local anchor 2).
    pub anchors: Vec<(RigidBodyHandle, Vector, RigidBodyHandle, Vector)>,
    /// The scene's plain form the world was built from (masses, start velocities).
    pub plain: tumble::scenes::PlainScene,
}

/// Builds `scene` in Rapier from its plain form: spheres, boxes, capsules,
/// hulls, meshes and half-spaces with tumble's masses, inertias, poses,
/// velocities and materials (see the module documentation). Ball joints
/// become spherical joints, hinges revolute joints with the same limits
/// (body 1 = the joint's body B, so the angle is A's relative to B as in
/// tumble); joints to the world hang from one fixed body at the origin;
/// contacts between jointed bodies as the joint says (off by default, as
/// in tumble). `multibody`: the joints as Rapier's reduced-coordinate
/// multibody joints instead of impulse joints.
pub fn build(scene: &Scene, multibody: bool) -> Result<SceneWorld, String> {
    build_with(scene, multibody, false)
}

/// [`build`], with `decompose` the triangle meshes of dynamic bodies as
/// Rapier's own convex decomposition (`ColliderBuilder::convex_decomposition`,
/// parry's V-HACD with its default parameters) instead of `TriMesh`es;
/// static meshes stay `TriMesh`es (Rapier collides convex shapes with them).
pub fn build_with(scene: &Scene, multibody: bool, decompose: bool) -> Result<SceneWorld, String> {
    if !scene.no_contact.is_empty() {
        return Err(format!(
            "{}: pairs kept apart (no_contact) have no Rapier twin here",
            scene.name
        ));
    }
    if !scene.gears.is_empty() {
        return Err(format!(
            "{}: gears (a joint held at a ratio of another's coordinate) have no Rapier twin here",
            scene.name
        ));
    }
    let plain = scene.plain().map_err(|e| format!("{}: {e}", scene.name))?;
    let mut w = world();
    w.gravity = v(plain.gravity.to_array());
    w.integration_parameters.dt = plain.dt as f32;
    let mut bodies = Vec::with_capacity(plain.bodies.len());
    let mut frames = Vec::with_capacity(plain.bodies.len());
    // Each distinct mesh's convex decomposition (`decompose`).
    let mut pieces: Vec<(Vec<tumble::collide::DVec3>, Vec<[u32; 3]>, SharedShape)> = Vec::new();
    for b in &plain.bodies {
        let linvel = v(b.linear_velocity.to_array());
        let angvel = v(b.angular_velocity.to_array());
        let builder = match b.kind {
            tumble::BodyKind::Dynamic => RigidBodyBuilder::dynamic()
                .can_sleep(false)
                .additional_mass_properties(MassProperties::new(
                    Vector::ZERO,
                    b.mass as f32,
                    v(b.principal_inertia.to_array()),
                )),
            tumble::BodyKind::Kinematic => RigidBodyBuilder::kinematic_velocity_based(),
            _ => RigidBodyBuilder::fixed(),
        };
        let handle = w
            .bodies
            .insert(builder.pose(pose(&b.pose)).linvel(linvel).angvel(angvel));
        for s in &b.shapes {
            // The body's mass properties are tumble's (above): colliders add none.
            let c = match &s.shape {
                tumble::collide::shape::Shape::Mesh(m)
                    if decompose && b.kind == tumble::BodyKind::Dynamic =>
                {
                    // Decomposed once per distinct mesh (V-HACD takes a
                    // quarter of a second per body of the concave pile).
                    let mesh = m.mesh();
                    let known = pieces
                        .iter()
                        .find(|(v, t, _)| v == mesh.vertices() && t == mesh.triangles());
                    let shape = match known {
                        Some((_, _, shape)) => shape.clone(),
                        None => {
                            let vertices: Vec<Vector> =
                                mesh.vertices().iter().map(|p| v(p.to_array())).collect();
                            let shape = SharedShape::convex_decomposition(&vertices, mesh.triangles());
                            pieces.push((mesh.vertices().to_vec(), mesh.triangles().to_vec(), shape.clone()));
                            shape
                        }
                    };
                    ColliderBuilder::new(shape)
                }
                shape => collider(shape).map_err(|e| format!("{}: {e}", b.name))?,
            }
            .position(pose(&s.local))
            .density(0.0)
            .friction(b.friction as f32)
            .friction_combine_rule(CoefficientCombineRule::GeometricMean)
            .restitution(b.restitution as f32)
            .restitution_combine_rule(CoefficientCombineRule::Max);
            w.colliders.insert_with_parent(c, handle, &mut w.bodies);
        }
        bodies.push(handle);
        frames.push(b.pose);
    }
    let anchors = joints(&mut w, scene, &bodies, &frames, multibody)?;
    Ok(SceneWorld {
        world: w,
        bodies,
        anchors,
        plain,
    })
}

/// The scene's joints in `w` (see [`build`]); `frames`: each body's frame.
fn joints(
    w: &mut PhysicsWorld,
    scene: &Scene,
    bodies: &[RigidBodyHandle],
    frames: &[tumble::collide::Pose],
    multibody: bool,
) -> Result<Vec<(RigidBodyHandle, Vector, RigidBodyHandle, Vector)>, String> {
    let mut anchors = Vec::new();
    if scene.joints.is_empty() {
        return Ok(anchors);
    }
    let anchor_body = w
        .insert(
            RigidBodyBuilder::fixed(),
            ColliderBuilder::ball(0.01).sensor(true),
        )
        .0;
    for j in &scene.joints {
        // What the twin does not translate is refused, not dropped: the
        // peers must run the same work.
        let untranslated = [
            ("a motor", j.motor.is_some()),
            ("a spring", j.spring.is_some()),
            ("a friction", j.friction.is_some()),
            ("a swing limit", j.swing_limit.is_some()),
            (
                "ball twist limits",
                j.kind == tumble::joint::JointKind::Ball && j.limits.is_some(),
            ),
        ];
        if let Some((what, _)) = untranslated.iter().find(|(_, has)| *has) {
            return Err(format!("joint `{}`: {what} has no Rapier twin here", j.name));
        }
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
    Ok(anchors)
}

impl SceneWorld {
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

    /// Centre of mass of the scene's body `i` (m; NaN if it is gone).
    pub fn centre(&self, i: usize) -> [f64; 3] {
        match self.world.bodies.get(self.bodies[i]) {
            Some(b) => {
                let c = b.center_of_mass();
                [c.x as f64, c.y as f64, c.z as f64]
            }
            None => [f64::NAN; 3],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::build_with;
    use tumble::scenes::{self, SceneGear};

    #[test]
    fn gears_and_pairs_kept_apart_are_refused_not_left_out() {
        let mut geared = scenes::heavy_chain();
        geared.gears.push(SceneGear {
            follower: 1,
            leader: 0,
            ratio: 2.0,
            offset: 0.0,
        });
        let mut apart = scenes::heavy_chain();
        apart.no_contact.push((1, 3));
        for (scene, what) in [(geared, "gears"), (apart, "no_contact")] {
            for multibody in [false, true] {
                let err = build_with(&scene, multibody, false).err().expect("refused");
                assert!(err.contains(what), "{err}");
            }
        }
        assert!(build_with(&scenes::heavy_chain(), false, false).is_ok());
    }

    /// The ragdoll pile on Rapier's multibody joints (the harness's
    /// `ragdoll_pile-multibody`): each ragdoll is a tree, so Rapier takes
    /// it as one multibody of eleven links, and its joints, in reduced
    /// coordinates, stay closed through the first steps to f32 rounding.
    #[test]
    fn the_ragdoll_pile_is_a_hundred_multibodies_with_closed_joints() {
        let mut sw = build_with(&scenes::ragdoll_pile(), true, false).unwrap();
        assert_eq!(sw.world.impulse_joints.len(), 0);
        assert_eq!(sw.world.multibody_joints.multibodies().count(), 100);
        assert!(sw
            .world
            .multibody_joints
            .multibodies()
            .all(|m| m.num_links() == 11));
        assert!(sw.largest_joint_error() < 1e-5, "{}", sw.largest_joint_error());
        for _ in 0..5 {
            sw.world.step();
        }
        assert!(sw.largest_joint_error() < 1e-4, "{}", sw.largest_joint_error());
    }
}
