//! World snapshots: everything that affects the future of a [`World`] (as
//! MuJoCo's `mjData` is to its model), saved and restored exactly, so that a
//! restored world steps to the very same bits as the original would have.
//!
//! What is in a snapshot: the settings, the time and step count, every slot
//! of the body arena with its generation and the free list (so handles stay
//! valid and stale handles stay stale), each body's state, mass properties,
//! force and torque accumulators, damping, kinematic velocity, material,
//! colliders (primitives by value, triangle meshes in a table, each mesh
//! stored once however many bodies share it), name and sleep state, the
//! broad-phase box of each body (the fattened box of its last active step:
//! it decides which pairs are tested), the warm-start contact cache and the
//! touching pairs of the last step (they decide the next step's begin/end
//! events), the body pairs kept apart by `World::set_contacts_between`,
//! and every joint slot with its joint (description, frames on
//! the bodies, warm-start impulses, last reaction). Not in it: the contact list of the last step ([`World::contacts`]
//! is empty after a restore until the next step) and the broad phase's
//! internal sort order (rebuilt; its pair set, the only thing the step reads,
//! is a function of the boxes).
//!
//! Formats: compact binary (`postcard`, behind a magic header) and JSON for
//! debugging. Both carry [`SNAPSHOT_FORMAT_VERSION`] first; a snapshot of any
//! other version is rejected with [`SnapshotError::UnsupportedVersion`]
//! before the rest is read, never misread. Every value is checked on the way
//! in (a corrupt or hand-edited file gives a typed error, never a world that
//! panics or holds NaN).

use super::handles::{Arena, BodyId, JointId};
use super::joints::{GearState, JointEntry};
use super::manifold::{self, CachedContact, CachedPatch, SearchedPair};
use super::{check_settings, BodyEntry, Collider, World, WorldSettings};
use crate::body::{BodyKind, BodyState, Material, RigidBody};
use crate::joint::{Gear, JointDesc, JointKind};
use crate::solver::contact_solver::{JointLaw, JOINT_ROWS};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use tumble_collide::broad::Aabb;
use tumble_collide::mesh::TriMesh;
use tumble_collide::shape::{Capsule, ConvexHull, Cuboid, HalfSpace, MeshShape, Shape, Sphere};
use tumble_collide::{DVec3, Pose};

/// The snapshot format this build writes and reads. Raised whenever the
/// layout of [`Snapshot`] changes; older snapshots are then rejected.
pub const SNAPSHOT_FORMAT_VERSION: u32 = 12;

/// First bytes of a binary snapshot.
pub const SNAPSHOT_MAGIC: &[u8; 8] = b"TMBLSNAP";

/// Why a snapshot could not be read, written or restored.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SnapshotError {
    /// The snapshot was written in another format version.
    #[error(
        "snapshot format version {found} is not supported: this build reads version {supported} \
         only (save the world again with a matching tumble)"
    )]
    UnsupportedVersion {
        /// The version in the snapshot.
        found: u32,
        /// [`SNAPSHOT_FORMAT_VERSION`].
        supported: u32,
    },
    /// The bytes do not start with [`SNAPSHOT_MAGIC`] (not a binary snapshot).
    #[error("not a tumble snapshot: {0}")]
    NotASnapshot(String),
    /// The bytes or text could not be decoded (truncated, corrupt).
    #[error("corrupt snapshot: {0}")]
    Decode(String),
    /// The snapshot decodes but describes an impossible world (a value out
    /// of range, an index past the end, ...).
    #[error("invalid snapshot: {0}")]
    Invalid(String),
    /// A file could not be read or written.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's reason.
        message: String,
    },
}

fn invalid(message: impl Into<String>) -> SnapshotError {
    SnapshotError::Invalid(message.into())
}

/// The full state of a [`World`] at one instant (see the module docs for
/// what it holds). Make one with [`World::snapshot`], continue from it with
/// [`World::from_snapshot`] or [`World::restore`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Snapshot {
    /// Layout version, [`SNAPSHOT_FORMAT_VERSION`] when written by this build.
    pub format_version: u32,
    settings: WorldSettings,
    time: f64,
    step_count: u64,
    /// Triangle meshes, each once; colliders refer to them by index.
    meshes: Vec<TriMesh>,
    /// The crease angle of each mesh's smooth surface (rad), if it has one
    /// (`MeshShape::with_smooth_surface`).
    mesh_crease_angles: Vec<Option<f64>>,
    /// Arena slots in order: generation and body (None for a free slot).
    slots: Vec<SlotRecord>,
    /// Free slots, in the arena's reuse order.
    free: Vec<u32>,
    /// Slots of bodies with unbounded shapes (outside the broad phase).
    unbounded: Vec<u32>,
    /// Warm-start normal impulses of the last step's points, sorted by key.
    cache: Vec<CachedContact>,
    /// Warm-start friction impulses of the last step's patches, sorted by key.
    patch_cache: Vec<CachedPatch>,
    /// Where each mesh collider pair was at its last contact search, sorted
    /// by key (a resting pair re-evaluates its kept points until it has
    /// moved from there). Absent: every pair searches at the next step.
    #[serde(default)]
    searches: Vec<SearchedPair>,
    /// Body pairs touching at the last step, sorted.
    touching: Vec<(BodyId, BodyId)>,
    /// Body pairs kept apart by `World::set_contacts_between`, the lower
    /// slot first, sorted.
    contact_exclusions: Vec<(BodyId, BodyId)>,
    /// Live bodies in the order the owner wants them listed (e.g. the rows
    /// of the Python arrays); slot order unless set with
    /// [`Snapshot::set_body_order`].
    body_order: Vec<BodyId>,
    /// Joint arena slots in order: generation and joint (None when free).
    joint_slots: Vec<JointSlotRecord>,
    /// Free joint slots, in reuse order.
    joint_free: Vec<u32>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct JointSlotRecord {
    generation: u32,
    joint: Option<JointRecord>,
}

/// A joint: its description, its frames on the bodies (bit for bit) and
/// its warm-start impulses and last reaction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct JointRecord {
    desc: JointDesc,
    local: [Pose; 2],
    rest_length: f64,
    impulses: Vec<f64>,
    reaction: [DVec3; 2],
    /// The gear that holds this joint's coordinate, with its warm-start
    /// impulse and the coordinates it followed.
    #[serde(default)]
    gear: Option<GearRecord>,
}

/// A follower's gear in a snapshot (`GearState`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct GearRecord {
    gear: Gear,
    impulse: f64,
    coordinates: [f64; 2],
}

impl JointRecord {
    fn of(j: &JointEntry) -> JointRecord {
        JointRecord {
            desc: j.desc.clone(),
            local: j.local,
            rest_length: j.law.length,
            impulses: j.impulses.to_vec(),
            reaction: [j.force, j.torque],
            gear: j.gear.map(|g| GearRecord {
                gear: g.gear,
                impulse: g.impulse,
                coordinates: g.coordinates,
            }),
        }
    }

    fn entry(&self, bodies: &Arena<BodyEntry>) -> Result<JointEntry, String> {
        let desc = self.desc.clone();
        desc.validate().map_err(|e| e.to_string())?;
        for id in [Some(desc.body_a), desc.body_b].into_iter().flatten() {
            if bodies.get(id).is_none() {
                return Err(format!("body {id:?} is not live"));
            }
        }
        for p in &self.local {
            Pose::new(p.position, p.rotation).map_err(|e| format!("joint frame: {e}"))?;
        }
        let impulses: [f64; JOINT_ROWS] = self
            .impulses
            .clone()
            .try_into()
            .map_err(|_| format!("{} impulses, expected {JOINT_ROWS}", self.impulses.len()))?;
        let finite = impulses.iter().all(|x| x.is_finite())
            && self.reaction.iter().all(|v| v.is_finite())
            && self.rest_length.is_finite()
            && self.rest_length >= 0.0;
        if !finite {
            return Err("impulses, reaction and rest length must be finite".into());
        }
        let gear = match self.gear {
            None => None,
            Some(g) => {
                g.gear.validate().map_err(|e| e.to_string())?;
                if !(g.impulse.is_finite() && g.coordinates.iter().all(|c| c.is_finite())) {
                    return Err("gear impulse and coordinates must be finite".into());
                }
                // (Its leader is checked once every joint is in.)
                Some(GearState {
                    gear: g.gear,
                    impulse: g.impulse,
                    coordinates: g.coordinates,
                })
            }
        };
        Ok(JointEntry {
            law: JointLaw::of(&desc, self.rest_length),
            desc,
            local: self.local,
            impulses,
            force: self.reaction[0],
            torque: self.reaction[1],
            gear,
        })
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SlotRecord {
    generation: u32,
    body: Option<BodyRecord>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct BodyRecord {
    kind: BodyKind,
    state: BodyState,
    /// Inverse mass and inverse principal inertia; `None` for zero (static
    /// and kinematic bodies).
    inverse_mass: Option<(f64, DVec3)>,
    /// Pending force and torque; `None` when both are +0.
    loads: Option<[DVec3; 2]>,
    damping: [f64; 2],
    /// Prescribed velocity and angular velocity; `None` when both are +0.
    kinematic_velocity: Option<[DVec3; 2]>,
    /// (restitution, friction).
    material: [f64; 2],
    /// `None` for the identity (bit for bit).
    body_in_model: Option<Pose>,
    colliders: Vec<ColliderRecord>,
    /// The body's box in the broad phase (min, max); `None` for bodies with
    /// an unbounded shape.
    proxy_box: Option<[DVec3; 2]>,
    name: String,
    sleeping: bool,
    rest_time: f64,
    sleep_group: u32,
    /// Always swept by continuous collision.
    ccd: bool,
    /// `BodyDesc::non_colliding_group` (0: none).
    #[serde(default)]
    non_colliding_group: u32,
}

/// `None` when every component is +0.0 (not -0.0: the bits must come back).
fn unless_zero(v: [DVec3; 2]) -> Option<[DVec3; 2]> {
    let zero = v.iter().all(|x| x.to_array().iter().all(|c| c.to_bits() == 0));
    (!zero).then_some(v)
}

/// `None` for a pose whose bits are the identity's.
fn unless_identity(p: Pose) -> Option<Pose> {
    let bits = |p: &Pose| {
        (
            p.position.to_array().map(f64::to_bits),
            p.rotation.to_array().map(f64::to_bits),
        )
    };
    (bits(&p) != bits(&Pose::IDENTITY)).then_some(p)
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ColliderRecord {
    shape: ShapeRecord,
    /// `None` for the identity.
    local: Option<Pose>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
enum ShapeRecord {
    Sphere(Sphere),
    Cuboid(Cuboid),
    Capsule(Capsule),
    ConvexHull(ConvexHull),
    HalfSpace(HalfSpace),
    /// Index into [`Snapshot::meshes`].
    Mesh(u32),
}

/// Only the version, read before the rest so that another layout is never
/// misread as this one.
#[derive(Deserialize)]
struct VersionHeader {
    format_version: u32,
}

fn check_version(found: u32) -> Result<(), SnapshotError> {
    if found == SNAPSHOT_FORMAT_VERSION {
        Ok(())
    } else {
        Err(SnapshotError::UnsupportedVersion {
            found,
            supported: SNAPSHOT_FORMAT_VERSION,
        })
    }
}

impl Snapshot {
    /// Simulated time at the snapshot (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps taken at the snapshot.
    pub fn step_count(&self) -> u64 {
        self.step_count
    }

    /// The settings of the world.
    pub fn settings(&self) -> &WorldSettings {
        &self.settings
    }

    /// Number of live bodies.
    pub fn body_count(&self) -> usize {
        self.slots.iter().filter(|s| s.body.is_some()).count()
    }

    /// Number of distinct triangle meshes stored (each once, however many
    /// bodies share it).
    pub fn mesh_count(&self) -> usize {
        self.meshes.len()
    }

    /// Live bodies in their listing order (slot order unless set).
    pub fn body_order(&self) -> &[BodyId] {
        &self.body_order
    }

    /// Sets the listing order of the live bodies (kept in the snapshot for
    /// the owner, e.g. the Python array rows; the world itself is
    /// unaffected). `order` must hold every live body exactly once.
    pub fn set_body_order(&mut self, order: Vec<BodyId>) -> Result<(), SnapshotError> {
        let mut sorted = order.clone();
        sorted.sort_unstable();
        let mut live: Vec<BodyId> = self.live_ids().collect();
        live.sort_unstable();
        if sorted != live {
            return Err(invalid(format!(
                "body order must list the {} live bodies once each, got {} entries",
                live.len(),
                order.len()
            )));
        }
        self.body_order = order;
        Ok(())
    }

    fn live_ids(&self) -> impl Iterator<Item = BodyId> + '_ {
        self.slots.iter().enumerate().filter_map(|(i, s)| {
            s.body.as_ref().map(|_| BodyId {
                index: i as u32,
                generation: s.generation,
            })
        })
    }

    /// Compact binary form: [`SNAPSHOT_MAGIC`], then the snapshot in
    /// `postcard` (the version first).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = SNAPSHOT_MAGIC.to_vec();
        // Plain data (numbers, vectors, strings) always serialises.
        out.extend(postcard::to_stdvec(self).unwrap_or_default());
        out
    }

    /// Reads the binary form; checks the magic and the version first.
    pub fn from_bytes(bytes: &[u8]) -> Result<Snapshot, SnapshotError> {
        let body = bytes
            .strip_prefix(SNAPSHOT_MAGIC.as_slice())
            .ok_or_else(|| SnapshotError::NotASnapshot("the header bytes are missing".into()))?;
        let (version, _) =
            postcard::take_from_bytes::<u32>(body).map_err(|e| SnapshotError::Decode(e.to_string()))?;
        check_version(version)?;
        let (snapshot, rest) =
            postcard::take_from_bytes::<Snapshot>(body).map_err(|e| SnapshotError::Decode(e.to_string()))?;
        if !rest.is_empty() {
            return Err(SnapshotError::Decode(format!(
                "{} trailing bytes after the snapshot",
                rest.len()
            )));
        }
        Ok(snapshot)
    }

    /// JSON form, for reading and debugging (larger than the binary one;
    /// numbers round-trip exactly).
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).unwrap_or_default()
    }

    /// Reads the JSON form; checks the version first.
    pub fn from_json(text: &str) -> Result<Snapshot, SnapshotError> {
        let header: VersionHeader =
            serde_json::from_str(text).map_err(|e| SnapshotError::Decode(e.to_string()))?;
        check_version(header.format_version)?;
        serde_json::from_str(text).map_err(|e| SnapshotError::Decode(e.to_string()))
    }

    /// Writes the snapshot to `path`: JSON for a `.json` file, the binary
    /// form otherwise. The file is written whole or not at all (a temporary
    /// file renamed into place).
    pub fn save(&self, path: impl AsRef<Path>) -> Result<(), SnapshotError> {
        let path = path.as_ref();
        let data = if is_json(path) {
            self.to_json().into_bytes()
        } else {
            self.to_bytes()
        };
        let io = |e: std::io::Error| SnapshotError::Io {
            path: path.to_path_buf(),
            message: e.to_string(),
        };
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(".tmp");
        let tmp = PathBuf::from(tmp);
        std::fs::write(&tmp, data).map_err(io)?;
        std::fs::rename(&tmp, path).map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            io(e)
        })
    }

    /// Reads a snapshot file written by [`Snapshot::save`] (JSON for a
    /// `.json` file, binary otherwise).
    pub fn load(path: impl AsRef<Path>) -> Result<Snapshot, SnapshotError> {
        let path = path.as_ref();
        let data = std::fs::read(path).map_err(|e| SnapshotError::Io {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        if data.is_empty() {
            return Err(SnapshotError::Io {
                path: path.to_path_buf(),
                message: "file is empty".into(),
            });
        }
        if is_json(path) {
            let text = std::str::from_utf8(&data).map_err(|e| SnapshotError::Decode(e.to_string()))?;
            Snapshot::from_json(text)
        } else {
            Snapshot::from_bytes(&data)
        }
    }
}

fn is_json(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

fn shape_record(shape: &Shape, meshes: &mut Vec<MeshShape>) -> ShapeRecord {
    match shape {
        Shape::Sphere(s) => ShapeRecord::Sphere(*s),
        Shape::Cuboid(s) => ShapeRecord::Cuboid(*s),
        Shape::Capsule(s) => ShapeRecord::Capsule(*s),
        Shape::ConvexHull(s) => ShapeRecord::ConvexHull(s.clone()),
        Shape::HalfSpace(s) => ShapeRecord::HalfSpace(*s),
        Shape::Mesh(m) => {
            let index = match meshes.iter().position(|k| k.shares_mesh_with(m)) {
                Some(i) => i,
                None => {
                    meshes.push(m.clone());
                    meshes.len() - 1
                }
            };
            ShapeRecord::Mesh(index as u32)
        }
        // Every variant of today is handled above; a new one must get a
        // record before it can be used in a world (the snapshot tests build
        // every kind).
        other => unreachable!("snapshot: no record for a {} shape", other.kind_name()),
    }
}

impl World {
    /// The complete state of the world (see [`Snapshot`]); cheap enough to
    /// take every step of a small world.
    pub fn snapshot(&self) -> Snapshot {
        let mut meshes: Vec<MeshShape> = Vec::new();
        let slots = (0..self.bodies.slot_count() as u32)
            .map(|i| {
                let generation = self.bodies.generation_at(i).unwrap_or(0);
                let body = self.bodies.at(i).map(|e| {
                    let b = &e.body;
                    BodyRecord {
                        kind: b.kind,
                        state: b.state,
                        inverse_mass: (b.inv_mass != 0.0 || b.inv_inertia != DVec3::ZERO)
                            .then_some((b.inv_mass, b.inv_inertia)),
                        loads: unless_zero([b.force, b.torque]),
                        damping: [b.linear_damping, b.angular_damping],
                        kinematic_velocity: unless_zero([b.kinematic_velocity, b.kinematic_angular_velocity]),
                        material: [b.material.restitution(), b.material.friction()],
                        body_in_model: unless_identity(e.body_in_model),
                        colliders: e
                            .colliders
                            .iter()
                            .map(|c| ColliderRecord {
                                shape: shape_record(&c.shape, &mut meshes),
                                local: unless_identity(c.local),
                            })
                            .collect(),
                        proxy_box: e
                            .proxy
                            .and_then(|p| self.broad.aabb(p).ok())
                            .map(|a| [a.min(), a.max()]),
                        name: e.name.clone(),
                        sleeping: e.sleeping,
                        rest_time: e.rest_time,
                        sleep_group: e.sleep_group,
                        ccd: e.ccd,
                        non_colliding_group: e.non_colliding_group,
                    }
                });
                SlotRecord { generation, body }
            })
            .collect();
        Snapshot {
            format_version: SNAPSHOT_FORMAT_VERSION,
            settings: self.settings.clone(),
            time: self.time,
            step_count: self.step_count,
            meshes: meshes.iter().map(|m| m.mesh().clone()).collect(),
            mesh_crease_angles: meshes.iter().map(MeshShape::crease_angle).collect(),
            slots,
            free: self.bodies.free_slots().to_vec(),
            unbounded: self.unbounded.clone(),
            cache: self.cache.clone(),
            patch_cache: self.patch_cache.clone(),
            searches: self.searches.clone(),
            touching: self.touching.clone(),
            contact_exclusions: self.contact_exclusions.clone(),
            body_order: self.body_ids(),
            joint_slots: (0..self.joints.slot_count() as u32)
                .map(|i| JointSlotRecord {
                    generation: self.joints.generation_at(i).unwrap_or(0),
                    joint: self.joints.at(i).map(JointRecord::of),
                })
                .collect(),
            joint_free: self.joints.free_slots().to_vec(),
        }
    }

    /// A world continuing exactly from `snapshot`: stepping it gives the
    /// same bits as stepping the world the snapshot was taken of. Handles
    /// of that world stay valid in this one.
    pub fn from_snapshot(snapshot: &Snapshot) -> Result<World, SnapshotError> {
        check_version(snapshot.format_version)?;
        check_settings(&snapshot.settings).map_err(|e| invalid(e.to_string()))?;
        if !snapshot.time.is_finite() {
            return Err(invalid(format!("time must be finite, got {}", snapshot.time)));
        }
        let meshes = snapshot
            .meshes
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let shape = MeshShape::new(m.clone()).map_err(|e| invalid(format!("meshes[{i}]: {e}")))?;
                match snapshot.mesh_crease_angles.get(i).copied().flatten() {
                    Some(angle) => shape
                        .with_smooth_surface(angle)
                        .map_err(|e| invalid(format!("mesh_crease_angles[{i}]: {e}"))),
                    None => Ok(shape),
                }
            })
            .collect::<Result<Vec<_>, _>>()?;
        if snapshot.mesh_crease_angles.len() != snapshot.meshes.len() {
            return Err(invalid(format!(
                "{} mesh crease angles for {} meshes",
                snapshot.mesh_crease_angles.len(),
                snapshot.meshes.len()
            )));
        }
        let mut slots = Vec::with_capacity(snapshot.slots.len());
        let mut boxes = Vec::new();
        for (i, slot) in snapshot.slots.iter().enumerate() {
            let entry = match &slot.body {
                None => None,
                Some(r) => {
                    let (entry, aabb) =
                        body_entry(r, &meshes).map_err(|m| invalid(format!("slots[{i}]: {m}")))?;
                    if let Some(aabb) = aabb {
                        boxes.push((i as u32, aabb));
                    }
                    Some(entry)
                }
            };
            slots.push((slot.generation, entry));
        }
        let bodies = Arena::from_raw_parts(slots, snapshot.free.clone()).map_err(invalid)?;
        let is_unbounded = |slot: u32| {
            bodies
                .at(slot)
                .is_some_and(|e| e.colliders.iter().any(|c| matches!(c.shape, Shape::HalfSpace(_))))
        };
        let mut unbounded = snapshot.unbounded.clone();
        unbounded.sort_unstable();
        unbounded.dedup();
        let expected: Vec<u32> = (0..bodies.slot_count() as u32)
            .filter(|&s| is_unbounded(s))
            .collect();
        if unbounded != expected || unbounded.len() != snapshot.unbounded.len() {
            return Err(invalid(
                "the unbounded body list does not match the half-space bodies",
            ));
        }
        let mut broad = super::step::new_broad_phase();
        let mut bodies = bodies;
        for (slot, aabb) in boxes {
            let proxy = broad
                .insert(slot, aabb)
                .map_err(|e| invalid(format!("slots[{slot}]: broad phase: {e}")))?;
            if let Some(e) = bodies.at_mut(slot) {
                e.proxy = Some(proxy);
            }
        }
        // A cache key names two live bodies' colliders.
        let live = |slot: u32, collider: u16| {
            bodies
                .at(slot)
                .is_some_and(|e| (collider as usize) < e.colliders.len())
        };
        for c in &snapshot.cache {
            let (a, b, ca, cb) = c.key;
            let finite = c.local_a.is_finite() && c.normal_impulse.is_finite();
            if a >= b || !live(a, ca) || !live(b, cb) || !finite {
                return Err(invalid(format!(
                    "contact cache entry {:?} is inconsistent",
                    c.key
                )));
            }
        }
        for c in &snapshot.patch_cache {
            let (a, b, ca, cb) = c.key;
            let finite = c.normal.is_finite() && c.tangent_impulse.is_finite() && c.twist_impulse.is_finite();
            if a >= b || !live(a, ca) || !live(b, cb) || !finite {
                return Err(invalid(format!(
                    "contact patch cache entry {:?} is inconsistent",
                    c.key
                )));
            }
        }
        for c in &snapshot.searches {
            let (a, b, ca, cb) = c.key;
            let pose = Pose::new(c.rel.position, c.rel.rotation);
            if a >= b || !live(a, ca) || !live(b, cb) || pose.is_err() {
                return Err(invalid(format!(
                    "contact search entry {:?} is inconsistent",
                    c.key
                )));
            }
        }
        if !snapshot.searches.windows(2).all(|w| w[0].key < w[1].key) {
            return Err(invalid("contact search entries must be sorted and unique"));
        }
        let mut cache = snapshot.cache.clone();
        let mut patch_cache = snapshot.patch_cache.clone();
        manifold::finish(&mut cache, &mut patch_cache);
        for &(a, b) in &snapshot.touching {
            if a >= b || bodies.get(a).is_none() || bodies.get(b).is_none() {
                return Err(invalid(format!(
                    "touching pair ({a:?}, {b:?}) is not a pair of live bodies"
                )));
            }
        }
        if !snapshot.touching.windows(2).all(|w| w[0] < w[1]) {
            return Err(invalid("touching pairs must be sorted and unique"));
        }
        if let Some(k) = snapshot.contact_exclusions.windows(2).position(|w| w[0] >= w[1]) {
            return Err(invalid(format!(
                "contact_exclusions[{}]: pairs must be sorted and unique",
                k + 1
            )));
        }
        for (i, &(a, b)) in snapshot.contact_exclusions.iter().enumerate() {
            if a.index >= b.index || bodies.get(a).is_none() || bodies.get(b).is_none() {
                return Err(invalid(format!(
                    "contact_exclusions[{i}]: ({a:?}, {b:?}) must be two live bodies, the lower slot first"
                )));
            }
        }
        let joint_slots = snapshot
            .joint_slots
            .iter()
            .enumerate()
            .map(|(i, r)| match &r.joint {
                None => Ok((r.generation, None)),
                Some(j) => j
                    .entry(&bodies)
                    .map(|e| (r.generation, Some(e)))
                    .map_err(|m| invalid(format!("joint_slots[{i}]: {m}"))),
            })
            .collect::<Result<Vec<_>, _>>()?;
        let joints: Arena<JointEntry, JointId> =
            Arena::from_raw_parts(joint_slots, snapshot.joint_free.clone())
                .map_err(|m| invalid(format!("joints: {m}")))?;
        // A gear's leader: another live hinge or slider, as `set_joint_gear` asks.
        for (id, e) in joints.iter() {
            let Some(g) = e.gear else { continue };
            let leader = joints.get(g.gear.leader);
            let kinds = |e: &JointEntry| matches!(e.desc.kind, JointKind::Hinge | JointKind::Slider);
            if g.gear.leader == id || !leader.is_some_and(kinds) || !kinds(e) {
                return Err(invalid(format!(
                    "joint_slots[{}]: its gear's leader {:?} must be another live hinge or slider, and it one",
                    id.index, g.gear.leader
                )));
            }
        }
        Ok(World {
            settings: snapshot.settings.clone(),
            bodies,
            joints,
            broad,
            unbounded: snapshot.unbounded.clone(),
            cache,
            patch_cache,
            searches: snapshot.searches.clone(),
            contacts: Vec::new(),
            touching: snapshot.touching.clone(),
            contact_exclusions: snapshot.contact_exclusions.clone(),
            time: snapshot.time,
            step_count: snapshot.step_count,
            pool: crate::pool::WorkerPool::new(snapshot.settings.threads),
            scratch: Default::default(),
        })
    }

    /// Replaces this world by the one in `snapshot` (see
    /// [`World::from_snapshot`]); unchanged on error.
    pub fn restore(&mut self, snapshot: &Snapshot) -> Result<(), SnapshotError> {
        *self = World::from_snapshot(snapshot)?;
        Ok(())
    }
}

/// A body entry from its record, every value checked; with its broad-phase
/// box for bounded bodies.
fn body_entry(r: &BodyRecord, meshes: &[MeshShape]) -> Result<(BodyEntry, Option<Aabb>), String> {
    let s = &r.state;
    if !s.is_finite() {
        return Err(format!("state is not finite: {s:?}"));
    }
    Pose::new(s.position, s.orientation).map_err(|e| format!("state orientation: {e}"))?;
    // Within the coordinate limit `World::add_body` and `set_pose` hold
    // every body to (`MAX_POSITION`): beyond it boxes overflow.
    let placed = |what: &str, p: DVec3| {
        if super::within_position_limit(p) {
            Ok(())
        } else {
            Err(format!(
                "{what} must lie within {:e} m of the origin on every axis, got {p:?}",
                super::MAX_POSITION
            ))
        }
    };
    placed("state position", s.position)?;
    let finite = |what: &str, v: DVec3| {
        if v.is_finite() {
            Ok(())
        } else {
            Err(format!("{what} must be finite, got {v:?}"))
        }
    };
    let [force, torque] = r.loads.unwrap_or([DVec3::ZERO; 2]);
    let [kin_v, kin_w] = r.kinematic_velocity.unwrap_or([DVec3::ZERO; 2]);
    finite("force", force)?;
    finite("torque", torque)?;
    finite("kinematic velocity", kin_v)?;
    finite("kinematic angular velocity", kin_w)?;
    let (inv_mass, inv_inertia) = r.inverse_mass.unwrap_or((0.0, DVec3::ZERO));
    let mass_ok = match r.kind {
        BodyKind::Dynamic => {
            inv_mass.is_finite()
                && inv_mass > 0.0
                && inv_inertia.is_finite()
                && inv_inertia.min_element() > 0.0
        }
        BodyKind::Static | BodyKind::Kinematic => {
            r.inverse_mass.is_none() && s.linear_momentum == DVec3::ZERO && s.angular_momentum == DVec3::ZERO
        }
    };
    if !mass_ok {
        return Err(format!(
            "mass properties do not fit a {:?} body: inverse mass {inv_mass}, inverse inertia {inv_inertia:?}",
            r.kind
        ));
    }
    let material = Material::new(r.material[0], r.material[1]).map_err(|e| e.to_string())?;
    if r.material[0] > 1.0 {
        return Err(format!("restitution must be in [0, 1], got {}", r.material[0]));
    }
    let mut body = RigidBody::new_static(Pose::IDENTITY);
    body.set_damping(r.damping[0], r.damping[1])
        .map_err(|e| e.to_string())?;
    body.state = r.state;
    body.kind = r.kind;
    body.inv_mass = inv_mass;
    body.inv_inertia = inv_inertia;
    body.force = force;
    body.torque = torque;
    body.kinematic_velocity = kin_v;
    body.kinematic_angular_velocity = kin_w;
    body.material = material;
    let body_in_model = r.body_in_model.unwrap_or(Pose::IDENTITY);
    Pose::new(body_in_model.position, body_in_model.rotation).map_err(|e| format!("body_in_model: {e}"))?;
    placed("body_in_model position", body_in_model.position)?;
    if r.colliders.is_empty() && r.kind == BodyKind::Static {
        return Err("a static body needs at least one collider".into());
    }
    let mut colliders = Vec::with_capacity(r.colliders.len());
    for (k, c) in r.colliders.iter().enumerate() {
        let local = c.local.unwrap_or(Pose::IDENTITY);
        Pose::new(local.position, local.rotation).map_err(|e| format!("colliders[{k}].local: {e}"))?;
        placed(&format!("colliders[{k}].local position"), local.position)?;
        let shape = match &c.shape {
            ShapeRecord::Sphere(s) => Shape::Sphere(*s),
            ShapeRecord::Cuboid(s) => Shape::Cuboid(*s),
            ShapeRecord::Capsule(s) => Shape::Capsule(*s),
            ShapeRecord::ConvexHull(s) => Shape::ConvexHull(s.clone()),
            ShapeRecord::HalfSpace(s) => {
                if r.kind != BodyKind::Static {
                    return Err("a half-space can only belong to a static body".into());
                }
                Shape::HalfSpace(*s)
            }
            ShapeRecord::Mesh(i) => Shape::Mesh(
                meshes
                    .get(*i as usize)
                    .ok_or_else(|| format!("colliders[{k}]: mesh {i} of {} does not exist", meshes.len()))?
                    .clone(),
            ),
        };
        colliders.push(Collider { shape, local });
    }
    let unbounded = colliders.iter().any(|c| matches!(c.shape, Shape::HalfSpace(_)));
    let aabb = match (r.proxy_box, unbounded || colliders.is_empty()) {
        (Some([lo, hi]), false) => Some(Aabb::new(lo, hi).map_err(|e| format!("broad-phase box: {e}"))?),
        (None, true) => None,
        _ => {
            return Err("a body has a broad-phase box exactly when it has colliders and no half-space".into())
        }
    };
    if !(r.rest_time.is_finite() && r.rest_time >= 0.0) {
        return Err(format!("rest time must be finite and >= 0, got {}", r.rest_time));
    }
    let entry = BodyEntry {
        body,
        radius: super::step::bounding_radius(&colliders),
        thickness: super::step::thickness(&colliders),
        core: super::step::core_radius(&colliders),
        ccd: r.ccd,
        non_colliding_group: r.non_colliding_group,
        colliders,
        body_in_model,
        proxy: None,
        name: r.name.clone(),
        sleeping: r.sleeping,
        rest_time: r.rest_time,
        sleep_group: r.sleep_group,
    };
    Ok((entry, aabb))
}
