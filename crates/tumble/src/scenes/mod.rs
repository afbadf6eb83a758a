//! The standard scenes of shared/scenes.md, defined once in code and shared by
//! tests, benchmarks, the CLI and the examples. Each function returns a
//! [`Scene`]: world settings plus body descriptions in insertion order.

mod bowl_swing;
mod concave_pile;
mod joint_scenes;
mod mesh_scenes;
mod plain_data;
mod primitives_scenes;
mod projectile_scenes;
mod swing_meter;
mod t_handle;
mod timing;
mod tori_queries;

pub use bowl_swing::{bowl_swing, BOWL_BALL_RADIUS, BOWL_CREASE_DEG, BOWL_RADIUS, BOWL_START_DEG};
pub use concave_pile::{
    concave_bin, concave_kind_meshes, concave_pile, concave_pile_escaped, CONCAVE_BIN_INNER_HALF_WIDTH,
    CONCAVE_BIN_WALL_HEIGHT, CONCAVE_KINDS, CONCAVE_PILE_BODIES,
};
pub use joint_scenes::{heavy_chain, net_drop, ragdoll, ragdoll_pile};
pub use mesh_scenes::{chain, chain_decomposed, tori_pass, torus_on_ground};
pub use plain_data::{
    pile_outside, PlainBody, PlainScene, PlainShape, CHAIN_MAX_CENTRE_DISTANCE, PILE_INSIDE_HALF_WIDTH,
    PLAIN_SCENE_FORMAT,
};
pub use primitives_scenes::{
    ball_drop, cradle, domino, incline, large_pyramid, pile, pyramid, pyramid_of_base, tower,
};
pub use projectile_scenes::{
    fire_projectile, projectile_cases, Fault, Flight, Projectile, ProjectileCase, PROJECTILE_STEPS,
};
pub use swing_meter::{swing_angle, SwingMeter};
pub use t_handle::{run_flips, t_handle, FlipRun, THandle};
pub use timing::TimingStats;
pub use tori_queries::{
    tori_pair_check, tori_plain_json, tori_pose, tori_pose_indices, tori_torus, tori_truth,
    TORI_PLAIN_FORMAT, TORI_POSES,
};

use crate::joint::{Gear, JointDesc};
use crate::world::{BodyDesc, BodyId, JointId, World, WorldError, WorldSettings};

/// The standard scenes' settings: the defaults with sleeping off (a
/// benchmark times every body in every step).
fn no_sleep() -> WorldSettings {
    WorldSettings {
        sleeping: false,
        ..WorldSettings::default()
    }
}

/// The shape most standard scenes share: [`no_sleep`] settings, 600 steps
/// (10 s at the default dt of 1/60 s) and no joints.
fn ten_seconds_without_sleep(name: impl Into<String>, bodies: Vec<BodyDesc>) -> Scene {
    Scene {
        name: name.into(),
        settings: no_sleep(),
        bodies,
        steps: 600,
        joints: Vec::new(),
        no_contact: Vec::new(),
        gears: Vec::new(),
    }
}

/// A scene: settings and bodies, in the order they are added.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Name (as in shared/scenes.md).
    pub name: String,
    /// World settings.
    pub settings: WorldSettings,
    /// Bodies in insertion order.
    pub bodies: Vec<BodyDesc>,
    /// Suggested number of steps.
    pub steps: usize,
    /// Joints, their bodies named by index into `bodies`.
    pub joints: Vec<JointDesc<usize>>,
    /// Body pairs (indices into `bodies`, the lower first) that never touch
    /// (`World::set_contacts_between`): a scene file's `[[no_contact]]`
    /// pairs, and a self-colliding robot's links that overlap in its file's
    /// pose (`UrdfParts::no_contact`).
    pub no_contact: Vec<(usize, usize)>,
    /// Gears: a joint (the follower, an index into `joints`) held at a
    /// ratio of another's coordinate (`World::set_joint_gear`): a scene
    /// file's `gear` of a joint, a robot's `<mimic>` joints.
    pub gears: Vec<SceneGear>,
}

/// A gear of a [`Scene`]: joint `follower`'s coordinate held at `ratio`
/// times joint `leader`'s plus `offset` (indices into [`Scene::joints`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneGear {
    /// The joint that follows.
    pub follower: usize,
    /// The joint followed.
    pub leader: usize,
    /// Follower coordinate per unit of the leader's.
    pub ratio: f64,
    /// The follower's coordinate where the leader's is 0 (rad or m).
    pub offset: f64,
}

impl Scene {
    /// Builds the world; returns it with the body handles in insertion
    /// order (joints are added after the bodies, in order, then the
    /// `no_contact` pairs kept apart).
    pub fn build(&self) -> Result<(World, Vec<BodyId>), WorldError> {
        let mut world = World::new(self.settings.clone())?;
        let ids = self
            .bodies
            .iter()
            .map(|b| world.add_body(b))
            .collect::<Result<Vec<_>, _>>()?;
        let mut joints = Vec::with_capacity(self.joints.len());
        for joint in &self.joints {
            joints.push(world.add_joint(&self.joint_desc(joint, &ids)?)?);
        }
        self.keep_apart(&mut world, &ids)?;
        self.set_gears(&mut world, &joints)?;
        Ok((world, ids))
    }

    /// Sets the scene's gears between its joints `joints` (the handles of
    /// [`Scene::joints`] in order; an index past them is refused).
    pub fn set_gears(&self, world: &mut World, joints: &[JointId]) -> Result<(), WorldError> {
        (0..self.gears.len()).try_for_each(|k| self.set_gear(world, joints, k))
    }

    /// Sets gear `k` of the scene (see [`Scene::set_gears`]).
    pub fn set_gear(&self, world: &mut World, joints: &[JointId], k: usize) -> Result<(), WorldError> {
        let Some(g) = self.gears.get(k) else {
            return Err(WorldError::BadValue {
                field: "scene.gears",
                message: format!("no gear {k} (the scene has {})", self.gears.len()),
            });
        };
        let bad = |message: String| WorldError::BadValue {
            field: "scene.gears",
            message: format!(
                "gear {k} (joint {} follows joint {}): {message}",
                g.follower, g.leader
            ),
        };
        let id = |i: usize| {
            joints.get(i).copied().ok_or_else(|| {
                bad(format!(
                    "joint index {i} is out of range (the scene has {} joints)",
                    joints.len()
                ))
            })
        };
        let gear = Gear::new(id(g.leader)?, g.ratio).with_offset(g.offset);
        world
            .set_joint_gear(id(g.follower)?, Some(gear))
            .map_err(|e| bad(e.to_string()))
    }

    /// Keeps the `no_contact` pairs of the scene's bodies `ids` apart in
    /// `world` (an index past the bodies is refused).
    pub fn keep_apart(&self, world: &mut World, ids: &[BodyId]) -> Result<(), WorldError> {
        for (k, &(a, b)) in self.no_contact.iter().enumerate() {
            let bad = |message: String| WorldError::BadValue {
                field: "scene.no_contact",
                message: format!("pair {k} ({a}, {b}): {message}"),
            };
            let id = |i: usize| {
                ids.get(i).copied().ok_or_else(|| {
                    bad(format!(
                        "body index {i} is out of range (the scene has {} bodies)",
                        ids.len()
                    ))
                })
            };
            world
                .set_contacts_between(id(a)?, id(b)?, false)
                .map_err(|e| bad(e.to_string()))?;
        }
        Ok(())
    }

    /// A scene joint with its body indices turned into the handles `ids`
    /// (an index past the bodies is refused).
    pub fn joint_desc(&self, joint: &JointDesc<usize>, ids: &[BodyId]) -> Result<JointDesc, WorldError> {
        let bad = |i: usize| WorldError::BadValue {
            field: "joint.body_a",
            message: format!(
                "body index {i} is out of range (the scene has {} bodies)",
                ids.len()
            ),
        };
        for i in [Some(joint.body_a), joint.body_b].into_iter().flatten() {
            if i >= ids.len() {
                return Err(bad(i));
            }
        }
        Ok(joint.clone().with_bodies(|i| ids[i]))
    }
}
