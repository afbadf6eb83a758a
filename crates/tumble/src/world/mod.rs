//! The world: the thesis' Simulator, RigidBodyManager and contact manager
//! (thesis 6.1.3, 6.1.4, ch. 7) in one facade. Descriptions in
//! ([`BodyDesc`], [`WorldSettings`]), handles out ([`BodyId`]), a
//! [`StepReport`] back from every [`World::step`].
//!
//! Frames: a body's *model frame* is the frame its description places shapes
//! in; its *body frame* is the centre of mass with principal axes, where the
//! momentum state (x, q, P, L) lives. Poses read and written through the API
//! are model-frame poses; velocities are those of the centre of mass.
//!
//! ```
//! use tumble::collide::{Cuboid, DVec3, HalfSpace};
//! use tumble::world::{BodyDesc, World, WorldError, WorldSettings};
//!
//! // Settings are validated: a world with a negative time step is refused.
//! let bad = WorldSettings { dt: -0.01, ..WorldSettings::default() };
//! assert!(matches!(World::new(bad), Err(WorldError::BadValue { field: "settings.dt", .. })));
//!
//! let mut world = World::new(WorldSettings { sleeping: false, ..WorldSettings::default() })?;
//! world.add_body(&BodyDesc::fixed(HalfSpace::new(DVec3::Z, 0.0)?))?;
//! // A 2 kg crate resting on the ground, its model frame at its centre.
//! let crate_id = world.add_body(
//!     &BodyDesc::dynamic(Cuboid::new(DVec3::new(0.4, 0.3, 0.2))?)
//!         .at(DVec3::new(0.0, 0.0, 0.2))
//!         .with_mass(2.0),
//! )?;
//! // A bad description leaves the world unchanged.
//! assert!(world.add_body(&BodyDesc::dynamic(Cuboid::new(DVec3::ONE)?).with_mass(-1.0)).is_err());
//! assert_eq!(world.body_count(), 2);
//!
//! let mut report = world.step();
//! for _ in 0..59 {
//!     report = world.step();
//! }
//! assert!(report.contacts >= 4 && report.quarantined.is_empty());
//! // At rest, the ground carries the weight: the normal impulses of one step
//! // add up to m g dt.
//! let impulse: f64 = world.contacts().iter().map(|c| c.normal_impulse).sum();
//! let weight = 2.0 * 9.81 * world.settings().dt;
//! assert!((impulse - weight).abs() < 1e-3 * weight);
//! assert!((world.pose(crate_id)?.position.z - 0.2).abs() < 1e-3);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub(crate) mod body_mass;
mod contact_filter;
mod desc;
mod error;
mod handles;
mod islands;
mod joints;
mod manifold;
mod patches;
mod report;
mod settings;
mod snapshot;
mod step;

pub use desc::{BodyDesc, MassDesc, MaterialDesc, ShapeDesc};
pub use error::WorldError;
pub use handles::{Arena, BodyId, Handle, JointId};
pub use islands::{label_islands, UnionFind};
pub use report::{ContactEvent, Quarantined, SolveStage, Stage, StepReport};
pub use settings::{SolverKind, WorldSettings};
pub use snapshot::{Snapshot, SnapshotError, SNAPSHOT_FORMAT_VERSION, SNAPSHOT_MAGIC};
pub use step::{END_OVERLAP_SLACK, FAST_FRACTION, RUNAWAY_SPEED, STRUCK_MARGINS};

use crate::body::{BodyKind, Material, RigidBody};
use manifold::{CachedContact, CachedPatch, SearchedPair};
use tumble_collide::broad::{ProxyId, SweepAndPrune};
use tumble_collide::shape::Shape;
use tumble_collide::{DQuat, DVec3, Pose};

/// A shape attached to a body, posed in the body frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Collider {
    /// The geometry.
    pub shape: Shape,
    /// Pose of the shape in the body frame (centre of mass, principal axes).
    pub local: Pose,
}

#[derive(Debug, Clone)]
pub(crate) struct BodyEntry {
    pub body: RigidBody,
    pub colliders: Vec<Collider>,
    /// The body frame expressed in the model frame (centre of mass and
    /// principal axes); identity for static and kinematic bodies.
    pub body_in_model: Pose,
    /// Sweep-and-prune proxy; `None` for bodies with an unbounded shape
    /// (half-space), which are tested against every body instead, and for
    /// bodies without shapes, which touch nothing.
    pub proxy: Option<ProxyId>,
    pub name: String,
    pub sleeping: bool,
    /// Time the body has been slow enough to sleep (s).
    pub rest_time: f64,
    /// Island label when it fell asleep: the island wakes together.
    pub sleep_group: u32,
    /// Largest distance of a collider point from the centre of mass (m).
    pub radius: f64,
    /// Smallest half extent of the colliders (m): the scale of a fast motion.
    pub thickness: f64,
    /// Radius of the ball about the centre of mass that continuous
    /// collision keeps from crossing surfaces (m, may be 0).
    pub core: f64,
    /// Always swept by continuous collision.
    pub ccd: bool,
    /// `BodyDesc::non_colliding_group`.
    pub non_colliding_group: u32,
}

/// One contact point of the last step, with the impulses the solver applied.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorldContact {
    /// Body A (normal points from B towards A).
    pub body_a: BodyId,
    /// Body B.
    pub body_b: BodyId,
    /// The geometric contact (world frame) at the start of the step.
    pub contact: tumble_collide::Contact,
    /// Normal impulse applied over the step (N s).
    pub normal_impulse: f64,
    /// Friction impulse applied over the step, world frame (N s).
    pub tangent_impulse: DVec3,
}

/// A simulated world of rigid bodies.
#[derive(Debug, Clone)]
pub struct World {
    settings: WorldSettings,
    bodies: Arena<BodyEntry>,
    joints: Arena<joints::JointEntry, JointId>,
    broad: SweepAndPrune,
    /// Slots of bodies with unbounded shapes (kept out of the broad phase).
    unbounded: Vec<u32>,
    cache: Vec<CachedContact>,
    patch_cache: Vec<CachedPatch>,
    /// Mesh collider pairs by where their contacts were last searched for,
    /// sorted by key (`manifold::SearchedPair`).
    searches: Vec<SearchedPair>,
    contacts: Vec<WorldContact>,
    touching: Vec<(BodyId, BodyId)>,
    /// Body pairs kept apart by `set_contacts_between`, the lower slot
    /// first, sorted (`contact_filter`).
    contact_exclusions: Vec<(BodyId, BodyId)>,
    time: f64,
    step_count: u64,
    /// Worker threads for `settings.threads` (not state: results do not depend on it).
    pool: crate::pool::WorkerPool,
    /// Buffers reused from step to step (not state).
    scratch: step::StepScratch,
}

fn check_vec(field: &'static str, v: DVec3) -> Result<(), WorldError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(WorldError::BadValue {
            field,
            message: format!("must be finite, got {v:?}"),
        })
    }
}

/// Farthest a body or shape may be placed from the origin (m): the OBBTree's
/// coordinate limit (`tumble_collide::bvh::MAX_COORDINATE`). Beyond it a
/// body's mass frame and boxes overflow (a shape placed 1.8e308 m from its
/// body put the body at infinity; libFuzzer, `fuzz/regressions/world_step/
/// far_shape_offset`).
pub const MAX_POSITION: f64 = tumble_collide::bvh::MAX_COORDINATE;

/// Whether `p` is finite and within [`MAX_POSITION`] of the origin on every
/// axis: the one test of the limit (bodies, snapshots, joint anchors).
pub(crate) fn within_position_limit(p: DVec3) -> bool {
    p.is_finite() && p.abs().max_element() <= MAX_POSITION
}

/// `field` within [`MAX_POSITION`] of the origin on every axis.
fn check_position(field: &'static str, p: DVec3) -> Result<(), WorldError> {
    if within_position_limit(p) {
        Ok(())
    } else {
        Err(WorldError::BadValue {
            field,
            message: format!("must lie within {MAX_POSITION:e} m of the origin on every axis, got {p:?}"),
        })
    }
}

/// Shortest accepted `WorldSettings::dt` (s): a nanosecond, far below any
/// time scale of rigid bodies. A step of 5e-324 s (the smallest f64) was
/// accepted, its sub-step's inverse overflowed, and the joints reported
/// reactions of NaN (impulse / step; libFuzzer's `joints` target).
pub const MIN_DT: f64 = 1e-9;

/// The checks `World::new` makes of its settings.
pub(crate) fn check_settings(s: &WorldSettings) -> Result<(), WorldError> {
    let positive = |field: &'static str, x: f64| {
        if x.is_finite() && x > 0.0 {
            Ok(())
        } else {
            Err(WorldError::BadValue {
                field,
                message: format!("must be finite and > 0, got {x}"),
            })
        }
    };
    let non_negative = |field: &'static str, x: f64| {
        if x.is_finite() && x >= 0.0 {
            Ok(())
        } else {
            Err(WorldError::BadValue {
                field,
                message: format!("must be finite and >= 0, got {x}"),
            })
        }
    };
    check_vec("settings.gravity", s.gravity)?;
    positive("settings.dt", s.dt)?;
    if s.dt > 1.0 {
        return Err(WorldError::BadValue {
            field: "settings.dt",
            message: format!("must be at most 1 s, got {}", s.dt),
        });
    }
    if s.dt < MIN_DT {
        return Err(WorldError::BadValue {
            field: "settings.dt",
            message: format!("must be at least {MIN_DT:e} s, got {:e}", s.dt),
        });
    }
    if s.substeps == 0 || s.substeps > 64 {
        return Err(WorldError::BadValue {
            field: "settings.substeps",
            message: format!("must be in 1..=64, got {}", s.substeps),
        });
    }
    if s.iterations == 0 || s.iterations > 1000 {
        return Err(WorldError::BadValue {
            field: "settings.iterations",
            message: format!("must be in 1..=1000, got {}", s.iterations),
        });
    }
    if s.push_out_iterations > 1000 {
        return Err(WorldError::BadValue {
            field: "settings.push_out_iterations",
            message: format!("must be at most 1000, got {}", s.push_out_iterations),
        });
    }
    if !(s.push_out_fraction > 0.0 && s.push_out_fraction <= 1.0) {
        return Err(WorldError::BadValue {
            field: "settings.push_out_fraction",
            message: format!("must be in (0, 1], got {}", s.push_out_fraction),
        });
    }
    non_negative("settings.contact_margin", s.contact_margin)?;
    non_negative("settings.mesh_contact_margin", s.mesh_contact_margin)?;
    non_negative("settings.resting_motion", s.resting_motion)?;
    non_negative("settings.allowed_penetration", s.allowed_penetration)?;
    positive("settings.max_push_out_speed", s.max_push_out_speed)?;
    non_negative("settings.restitution_threshold", s.restitution_threshold)?;
    non_negative("settings.sleep_linear_speed", s.sleep_linear_speed)?;
    non_negative("settings.sleep_angular_speed", s.sleep_angular_speed)?;
    non_negative("settings.time_to_sleep", s.time_to_sleep)?;
    if s.threads > crate::pool::MAX_THREADS {
        return Err(WorldError::BadValue {
            field: "settings.threads",
            message: format!(
                "must be at most {} (0 means every core), got {}",
                crate::pool::MAX_THREADS,
                s.threads
            ),
        });
    }
    Ok(())
}

impl World {
    /// An empty world. Settings are validated.
    pub fn new(settings: WorldSettings) -> Result<World, WorldError> {
        check_settings(&settings)?;
        Ok(World {
            pool: crate::pool::WorkerPool::new(settings.threads),
            settings,
            bodies: Arena::new(),
            joints: Arena::new(),
            broad: step::new_broad_phase(),
            unbounded: Vec::new(),
            cache: Vec::new(),
            patch_cache: Vec::new(),
            searches: Vec::new(),
            contacts: Vec::new(),
            touching: Vec::new(),
            contact_exclusions: Vec::new(),
            time: 0.0,
            step_count: 0,
            scratch: step::StepScratch::default(),
        })
    }

    /// The settings.
    pub fn settings(&self) -> &WorldSettings {
        &self.settings
    }

    /// Replaces the settings (validated; unchanged on error).
    pub fn set_settings(&mut self, settings: WorldSettings) -> Result<(), WorldError> {
        check_settings(&settings)?;
        if settings.threads != self.settings.threads {
            self.pool = crate::pool::WorkerPool::new(settings.threads);
        }
        // A new margin or resting motion: every mesh pair searches again.
        // Not for another thread count alone, which changes no bit of the
        // step (a benchmark switching between one thread and two keeps the
        // work of the run it times).
        let threads_only = WorldSettings {
            threads: self.settings.threads,
            adaptive_threads: self.settings.adaptive_threads,
            ..settings.clone()
        } == self.settings;
        self.settings = settings;
        if !threads_only {
            self.searches.clear();
        }
        Ok(())
    }

    /// Puts in `pool` for the world's steps and gives back the one it had
    /// (a batch steps each of its worlds serially on one of its threads).
    pub(crate) fn swap_pool(&mut self, pool: crate::pool::WorkerPool) -> crate::pool::WorkerPool {
        std::mem::replace(&mut self.pool, pool)
    }

    /// Threads a step runs on: `settings.threads`, with 0 resolved to the
    /// machine's cores (or 1 where threads cannot be started).
    pub fn threads(&self) -> usize {
        self.pool.threads()
    }

    /// Simulated time (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps taken.
    pub fn step_count(&self) -> u64 {
        self.step_count
    }

    /// Number of bodies.
    pub fn body_count(&self) -> usize {
        self.bodies.len()
    }

    /// Handles of all bodies, in slot order (deterministic).
    pub fn body_ids(&self) -> Vec<BodyId> {
        self.bodies.iter().map(|(id, _)| id).collect()
    }

    /// Adds a body. The description is validated completely before anything
    /// changes; on error the world is unchanged.
    pub fn add_body(&mut self, desc: &BodyDesc) -> Result<BodyId, WorldError> {
        // A body without shapes touches nothing: a kinematic one carries
        // joints, a dynamic one its given mass (a robot's link that has an
        // inertia but no geometry). A static one would be the world.
        let shapeless_allowed = match desc.kind {
            BodyKind::Kinematic => true,
            BodyKind::Dynamic => matches!(desc.mass, MassDesc::Inertial(_)),
            BodyKind::Static => false,
        };
        if desc.shapes.is_empty() && !shapeless_allowed {
            return Err(WorldError::NoShapes);
        }
        check_vec("body.linear_velocity", desc.linear_velocity)?;
        check_vec("body.angular_velocity", desc.angular_velocity)?;
        let pose = Pose::new(desc.pose.position, desc.pose.rotation).map_err(|e| WorldError::BadValue {
            field: "body.pose",
            message: e.to_string(),
        })?;
        check_position("body.pose.position", pose.position)?;
        for (index, s) in desc.shapes.iter().enumerate() {
            Pose::new(s.local_pose.position, s.local_pose.rotation).map_err(|e| WorldError::BadShape {
                index,
                message: format!("local_pose: {e}"),
            })?;
            check_position("shape.local_pose.position", s.local_pose.position).map_err(|e| {
                WorldError::BadShape {
                    index,
                    message: e.to_string(),
                }
            })?;
        }
        let material = Material::new(desc.material.restitution, desc.material.friction).map_err(|e| {
            WorldError::BadValue {
                field: "body.material",
                message: e.to_string(),
            }
        })?;
        if desc.material.restitution > 1.0 {
            return Err(WorldError::BadValue {
                field: "body.material.restitution",
                message: format!("must be in [0, 1], got {}", desc.material.restitution),
            });
        }
        let (mut body, body_in_model) = match desc.kind {
            BodyKind::Dynamic => {
                let frame = body_mass::body_mass(&desc.shapes, desc.mass)?;
                let body_in_model =
                    Pose::new(frame.com, frame.rotation).map_err(|e| WorldError::BadShape {
                        index: 0,
                        message: e.to_string(),
                    })?;
                let body_pose = pose.mul_pose(&body_in_model);
                check_position("body.pose.position (centre of mass)", body_pose.position)?;
                let body = RigidBody::new_dynamic(frame.mass, frame.moments, body_pose).map_err(|e| {
                    WorldError::BadShape {
                        index: 0,
                        message: e.to_string(),
                    }
                })?;
                (body, body_in_model)
            }
            BodyKind::Static => (RigidBody::new_static(pose), Pose::IDENTITY),
            BodyKind::Kinematic => (RigidBody::new_kinematic(pose), Pose::IDENTITY),
        };
        let inv = body_in_model.inverse();
        let colliders: Vec<Collider> = desc
            .shapes
            .iter()
            .map(|s| Collider {
                shape: s.shape.clone(),
                local: inv.mul_pose(&s.local_pose),
            })
            .collect();
        body.set_material(material);
        let bad = |field: &'static str| {
            move |e: crate::body::BodyError| WorldError::BadValue {
                field,
                message: e.to_string(),
            }
        };
        body.set_damping(desc.linear_damping, desc.angular_damping)
            .map_err(bad("body.damping"))?;
        match desc.kind {
            BodyKind::Dynamic => {
                body.set_linear_velocity(desc.linear_velocity)
                    .map_err(bad("body.linear_velocity"))?;
                body.set_angular_velocity(desc.angular_velocity)
                    .map_err(bad("body.angular_velocity"))?;
            }
            BodyKind::Kinematic => body
                .set_kinematic_velocity(desc.linear_velocity, desc.angular_velocity)
                .map_err(bad("body.linear_velocity"))?,
            BodyKind::Static => {
                if desc.linear_velocity != DVec3::ZERO || desc.angular_velocity != DVec3::ZERO {
                    return Err(WorldError::BadValue {
                        field: "body.linear_velocity",
                        message: "a static body cannot move: use a kinematic body".into(),
                    });
                }
            }
        }
        let unbounded = colliders.iter().any(|c| matches!(c.shape, Shape::HalfSpace(_)));
        if unbounded && desc.kind != BodyKind::Static {
            return Err(WorldError::BadShape {
                index: 0,
                message: "a half-space can only belong to a static body".into(),
            });
        }
        let entry = BodyEntry {
            body,
            radius: step::bounding_radius(&colliders),
            thickness: step::thickness(&colliders),
            core: step::core_radius(&colliders),
            ccd: desc.ccd,
            non_colliding_group: desc.non_colliding_group,
            colliders,
            body_in_model,
            proxy: None,
            name: desc.name.clone(),
            sleeping: false,
            rest_time: 0.0,
            sleep_group: u32::MAX,
        };
        let id = self.bodies.insert(entry);
        if unbounded {
            self.unbounded.push(id.index);
        } else if !self.bodies.get(id).expect("just inserted").colliders.is_empty() {
            let aabb = step::body_aabb(self.bodies.get(id).expect("just inserted"), 0.0);
            match self.broad.insert(id.index, aabb) {
                Ok(proxy) => self.bodies.get_mut(id).expect("just inserted").proxy = Some(proxy),
                Err(e) => {
                    self.bodies.remove(id);
                    return Err(WorldError::BadShape {
                        index: 0,
                        message: e.to_string(),
                    });
                }
            }
        }
        Ok(id)
    }

    /// Removes a body and its joints (its contacts end with the next step).
    pub fn remove_body(&mut self, id: BodyId) -> Result<(), WorldError> {
        let entry = self.bodies.get(id).ok_or(WorldError::StaleBody(id))?;
        if let Some(proxy) = entry.proxy {
            self.broad.remove(proxy).map_err(|e| WorldError::BadValue {
                field: "body",
                message: e.to_string(),
            })?;
        }
        self.bodies.remove(id);
        self.remove_joints_of(id.index);
        self.unbounded.retain(|&s| s != id.index);
        self.cache.retain(|c| c.key.0 != id.index && c.key.1 != id.index);
        self.patch_cache
            .retain(|c| c.key.0 != id.index && c.key.1 != id.index);
        self.searches
            .retain(|c| c.key.0 != id.index && c.key.1 != id.index);
        self.contacts.retain(|c| c.body_a != id && c.body_b != id);
        self.contact_exclusions.retain(|&(a, b)| a != id && b != id);
        Ok(())
    }

    fn entry(&self, id: BodyId) -> Result<&BodyEntry, WorldError> {
        self.bodies.get(id).ok_or(WorldError::StaleBody(id))
    }

    fn entry_mut(&mut self, id: BodyId) -> Result<&mut BodyEntry, WorldError> {
        self.bodies.get_mut(id).ok_or(WorldError::StaleBody(id))
    }

    /// A nonzero `BodyDesc::non_colliding_group` that no body of the world
    /// is in: one more than the largest in use, or, if that is `u32::MAX`,
    /// the smallest free one.
    pub fn unused_non_colliding_group(&self) -> u32 {
        unused_non_colliding_group(self.bodies.iter().map(|(_, e)| e.non_colliding_group))
    }

    /// The rigid body (state in the body frame: centre of mass, principal axes).
    pub fn body(&self, id: BodyId) -> Result<&RigidBody, WorldError> {
        Ok(&self.entry(id)?.body)
    }

    /// The colliders of a body (shapes posed in the body frame).
    pub fn colliders(&self, id: BodyId) -> Result<&[Collider], WorldError> {
        Ok(&self.entry(id)?.colliders)
    }

    /// The body's `BodyDesc::non_colliding_group` (0: none).
    pub fn non_colliding_group(&self, id: BodyId) -> Result<u32, WorldError> {
        Ok(self.entry(id)?.non_colliding_group)
    }

    /// The body's name from its description.
    pub fn name(&self, id: BodyId) -> Result<&str, WorldError> {
        Ok(&self.entry(id)?.name)
    }

    /// Pose of the body's model frame in the world.
    pub fn pose(&self, id: BodyId) -> Result<Pose, WorldError> {
        let e = self.entry(id)?;
        Ok(e.body.pose().mul_pose(&e.body_in_model.inverse()))
    }

    /// Position of the centre of mass (m).
    pub fn center_of_mass(&self, id: BodyId) -> Result<DVec3, WorldError> {
        Ok(self.entry(id)?.body.position())
    }

    /// Linear velocity of the centre of mass (m/s).
    pub fn linear_velocity(&self, id: BodyId) -> Result<DVec3, WorldError> {
        let e = self.entry(id)?;
        Ok(match e.body.kind() {
            BodyKind::Kinematic => e.body.kinematic_velocity().0,
            _ => e.body.velocity(),
        })
    }

    /// Angular velocity, world frame (rad/s).
    pub fn angular_velocity(&self, id: BodyId) -> Result<DVec3, WorldError> {
        let e = self.entry(id)?;
        Ok(match e.body.kind() {
            BodyKind::Kinematic => e.body.kinematic_velocity().1,
            _ => e.body.angular_velocity(),
        })
    }

    /// `true` when the body is asleep.
    pub fn is_sleeping(&self, id: BodyId) -> Result<bool, WorldError> {
        Ok(self.entry(id)?.sleeping)
    }

    /// Wakes a body (and, at the next step, its island).
    pub fn wake(&mut self, id: BodyId) -> Result<(), WorldError> {
        let e = self.entry_mut(id)?;
        e.sleeping = false;
        e.rest_time = 0.0;
        Ok(())
    }

    /// Moves the model frame to `pose` (teleport; velocities kept).
    pub fn set_pose(&mut self, id: BodyId, pose: Pose) -> Result<(), WorldError> {
        let pose = Pose::new(pose.position, pose.rotation).map_err(|e| WorldError::BadValue {
            field: "pose",
            message: e.to_string(),
        })?;
        check_position("pose.position", pose.position)?;
        let e = self.entry_mut(id)?;
        let body_pose = pose.mul_pose(&e.body_in_model);
        check_position("pose.position (centre of mass)", body_pose.position)?;
        e.body.set_pose(body_pose);
        e.sleeping = false;
        e.rest_time = 0.0;
        Ok(())
    }

    /// Sets the velocities of a dynamic body (centre of mass, world frame) or
    /// the prescribed velocities of a kinematic one.
    pub fn set_velocity(&mut self, id: BodyId, linear: DVec3, angular: DVec3) -> Result<(), WorldError> {
        check_vec("linear_velocity", linear)?;
        check_vec("angular_velocity", angular)?;
        let e = self.entry_mut(id)?;
        let err = |e: crate::body::BodyError| WorldError::BadValue {
            field: "velocity",
            message: e.to_string(),
        };
        match e.body.kind() {
            BodyKind::Static => {
                return Err(WorldError::WrongKind {
                    body: id,
                    message: "a static body has no velocity",
                })
            }
            BodyKind::Kinematic => e.body.set_kinematic_velocity(linear, angular).map_err(err)?,
            BodyKind::Dynamic => {
                let before = e.body.clone();
                if let Err(x) = e
                    .body
                    .set_linear_velocity(linear)
                    .and_then(|_| e.body.set_angular_velocity(angular))
                {
                    e.body = before;
                    return Err(err(x));
                }
            }
        }
        e.sleeping = false;
        e.rest_time = 0.0;
        Ok(())
    }

    /// Adds a force (N) at the centre of mass for the next step; wakes the body.
    pub fn apply_force(&mut self, id: BodyId, force: DVec3) -> Result<(), WorldError> {
        self.with_dynamic(id, |b| b.apply_force(force))
    }

    /// Adds a force (N) at a world point for the next step (torque (p - x) x F).
    pub fn apply_force_at_point(&mut self, id: BodyId, force: DVec3, point: DVec3) -> Result<(), WorldError> {
        self.with_dynamic(id, |b| b.apply_force_at_point(force, point))
    }

    /// Adds a torque (N m, world frame) for the next step.
    pub fn apply_torque(&mut self, id: BodyId, torque: DVec3) -> Result<(), WorldError> {
        self.with_dynamic(id, |b| b.apply_torque(torque))
    }

    /// Applies an impulse (N s) at a world point now.
    pub fn apply_impulse_at_point(
        &mut self,
        id: BodyId,
        impulse: DVec3,
        point: DVec3,
    ) -> Result<(), WorldError> {
        self.with_dynamic(id, |b| b.apply_impulse_at_point(impulse, point))
    }

    fn with_dynamic(
        &mut self,
        id: BodyId,
        f: impl FnOnce(&mut RigidBody) -> Result<(), crate::body::BodyError>,
    ) -> Result<(), WorldError> {
        let e = self.entry_mut(id)?;
        if e.body.kind() != BodyKind::Dynamic {
            return Err(WorldError::WrongKind {
                body: id,
                message: "forces and impulses act on dynamic bodies only",
            });
        }
        f(&mut e.body).map_err(|x| WorldError::BadValue {
            field: "force",
            message: x.to_string(),
        })?;
        e.sleeping = false;
        e.rest_time = 0.0;
        Ok(())
    }

    /// Forgets the warm-start impulses of the last step: the next step's
    /// solver starts from zero (as after teleporting bodies far).
    pub fn clear_contact_cache(&mut self) {
        self.cache.clear();
        self.patch_cache.clear();
        self.searches.clear();
    }

    /// Contact points of the last step with their impulses.
    pub fn contacts(&self) -> &[WorldContact] {
        &self.contacts
    }

    /// A fingerprint of the dynamic state: FNV-1a over the raw bits of every
    /// live body's x, P, L and q, in slot order. Two worlds with the same
    /// hash followed the same trajectory to the last bit (as far as a 64-bit
    /// hash tells); used to check determinism across runs, thread counts,
    /// snapshots and machines.
    pub fn state_hash(&self) -> u64 {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for (_, e) in self.bodies.iter() {
            let s = e.body.state();
            let words = [s.position, s.linear_momentum, s.angular_momentum]
                .into_iter()
                .flat_map(|v| v.to_array())
                .chain(s.orientation.to_array());
            for word in words {
                for byte in word.to_bits().to_le_bytes() {
                    h ^= byte as u64;
                    h = h.wrapping_mul(0x0000_0100_0000_01b3);
                }
            }
        }
        h
    }

    /// Total kinetic energy of the dynamic bodies (J).
    pub fn kinetic_energy(&self) -> f64 {
        self.bodies
            .iter()
            .filter(|(_, e)| e.body.kind() == BodyKind::Dynamic)
            .map(|(_, e)| e.body.kinetic_energy())
            .sum()
    }

    /// Total gravitational potential energy of the dynamic bodies relative to
    /// the origin (J): `-m g . x`.
    pub fn potential_energy(&self) -> f64 {
        self.bodies
            .iter()
            .filter(|(_, e)| e.body.kind() == BodyKind::Dynamic)
            .map(|(_, e)| -e.body.mass() * self.settings.gravity.dot(e.body.position()))
            .sum()
    }

    /// Orientation helper: the model-frame orientation of a body.
    pub fn orientation(&self, id: BodyId) -> Result<DQuat, WorldError> {
        Ok(self.pose(id)?.rotation)
    }
}

/// A nonzero non-colliding group that none of `used` is: one more than the
/// largest, or, if that is `u32::MAX`, the smallest free one (the world's
/// bodies, `World::unused_non_colliding_group`, or a scene file's so far).
pub fn unused_non_colliding_group(used: impl IntoIterator<Item = u32>) -> u32 {
    let used: std::collections::BTreeSet<u32> = used.into_iter().collect();
    let largest = used.last().copied().unwrap_or(0);
    // (More groups than bodies exist, so a free one is always found.)
    largest
        .checked_add(1)
        .unwrap_or_else(|| (1..).find(|g| !used.contains(g)).unwrap_or(1))
}
