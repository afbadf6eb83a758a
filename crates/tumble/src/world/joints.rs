//! The world's joints: added from a [`JointDesc`], held as a frame on each
//! body (so the pose at creation is the joint's zero), solved with the
//! contacts in the solve stage, and read back as a [`JointState`].

use super::step::velocities as body_velocities;
use super::{BodyId, JointId, World, WorldError};
use crate::body::BodyKind;
use crate::joint::{frame_rotation, unwrap_coordinate, Gear, JointDesc, JointKind, JointPose, JointState};
use crate::solver::contact_solver::{JointLaw, JOINT_ROWS};
use tumble_collide::{DQuat, DVec3, Pose};

/// A joint as the world keeps it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct JointEntry {
    /// The description it was made from (anchors and axis at creation).
    pub desc: JointDesc,
    /// The joint frame in each body's body frame (B: in the world when
    /// `desc.body_b` is `None`).
    pub local: [Pose; 2],
    /// What the solver constrains.
    pub law: JointLaw,
    /// Row impulses of the last sub-step (warm start of the next step).
    pub impulses: [f64; JOINT_ROWS],
    /// Force on A over the last step (N, world).
    pub force: DVec3,
    /// Torque on A about its anchor over the last step (N m, world).
    pub torque: DVec3,
    /// The gear that holds this joint's coordinate at a ratio of another's.
    pub gear: Option<GearState>,
}

/// A follower joint's gear as the world keeps it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct GearState {
    /// What it holds.
    pub gear: Gear,
    /// Its impulse over the last sub-step (warm start of the next step).
    pub impulse: f64,
    /// The leader's and the follower's coordinates after the last step,
    /// followed across a hinge's wrap (`unwrap_coordinate`).
    pub coordinates: [f64; 2],
}

/// Where a joint's side is when the joint is made.
struct BodyFrame {
    position: DVec3,
    orientation: DQuat,
    dynamic: bool,
}

impl BodyFrame {
    /// The world as a joint's side.
    const WORLD: BodyFrame = BodyFrame {
        position: DVec3::ZERO,
        orientation: DQuat::IDENTITY,
        dynamic: false,
    };
}

impl JointEntry {
    /// Slots of the two bodies (`None`: the world).
    pub fn slots(&self) -> (u32, Option<u32>) {
        (self.desc.body_a.index, self.desc.body_b.map(|b| b.index))
    }

    /// Whether the joint holds body slot `slot` (either side).
    pub fn holds(&self, slot: u32) -> bool {
        let (a, b) = self.slots();
        a == slot || b == Some(slot)
    }
}

impl World {
    /// Adds a joint. The description is validated completely (values, the
    /// bodies exist, at least one is dynamic) before anything changes; on
    /// error the world is unchanged. Both bodies wake.
    pub fn add_joint(&mut self, desc: &JointDesc) -> Result<JointId, WorldError> {
        desc.validate()?;
        let frame_of = |id: BodyId| -> Result<BodyFrame, WorldError> {
            let e = self.entry(id)?;
            Ok(BodyFrame {
                position: e.body.position(),
                orientation: e.body.orientation(),
                dynamic: e.body.kind() == BodyKind::Dynamic,
            })
        };
        let a = frame_of(desc.body_a)?;
        let b = match desc.body_b {
            Some(id) => frame_of(id)?,
            None => BodyFrame::WORLD,
        };
        if !a.dynamic && !b.dynamic {
            return Err(WorldError::BadValue {
                field: "joint.body_a",
                message: "a joint needs at least one dynamic body (both are static, kinematic or the world)"
                    .into(),
            });
        }
        let rotation = frame_rotation(desc.axis.normalize());
        let anchor_b = desc.anchor_b.unwrap_or(desc.anchor);
        let in_body = |f: &BodyFrame, point: DVec3| {
            let inv = f.orientation.conjugate();
            Pose {
                position: inv * (point - f.position),
                rotation: (inv * rotation).normalize(),
            }
        };
        let law = JointLaw::of(
            desc,
            desc.length.unwrap_or_else(|| (desc.anchor - anchor_b).length()),
        );
        let entry = JointEntry {
            desc: desc.clone(),
            local: [in_body(&a, desc.anchor), in_body(&b, anchor_b)],
            law,
            impulses: [0.0; JOINT_ROWS],
            force: DVec3::ZERO,
            torque: DVec3::ZERO,
            gear: None,
        };
        let id = self.joints.insert(entry);
        for body in [Some(desc.body_a), desc.body_b].into_iter().flatten() {
            self.wake(body)?;
        }
        Ok(id)
    }

    /// Holds joint `follower`'s coordinate at a ratio of another joint's
    /// ([`Gear`]: gear pairs, racks and pinions, URDF's mimic joints), or
    /// with `None` lets it go. Both joints are hinges or sliders, and
    /// distinct; the gear holds the coordinates as they are now (measured
    /// from each joint's creation: a hinge's angle followed across its wrap
    /// from here on) to `q_follower = ratio q_leader + offset`, closing any
    /// difference as the push-out closes a joint's drift. Removing either
    /// joint removes the gear. Refused at its field, the world unchanged;
    /// the joints' bodies wake.
    pub fn set_joint_gear(&mut self, follower: JointId, gear: Option<Gear>) -> Result<(), WorldError> {
        let entry = self
            .joints
            .get(follower)
            .ok_or(WorldError::StaleJoint(follower))?;
        let state = match gear {
            None => None,
            Some(gear) => {
                gear.validate()?;
                let leader = self
                    .joints
                    .get(gear.leader)
                    .ok_or(WorldError::StaleJoint(gear.leader))?;
                if gear.leader == follower {
                    return Err(WorldError::BadValue {
                        field: "gear.leader",
                        message: "a joint cannot follow itself".into(),
                    });
                }
                for (field, e) in [("gear.leader", leader), ("gear.follower", entry)] {
                    if !matches!(e.desc.kind, JointKind::Hinge | JointKind::Slider) {
                        return Err(WorldError::BadValue {
                            field,
                            message: format!(
                                "a gear joins hinges and sliders, not a {:?} joint",
                                e.desc.kind
                            ),
                        });
                    }
                }
                let coordinate = |e: &JointEntry| self.place(e).coordinate(e.desc.kind);
                Some(GearState {
                    gear,
                    impulse: 0.0,
                    coordinates: [coordinate(leader), coordinate(entry)],
                })
            }
        };
        let mut wake = vec![entry.desc.body_a];
        wake.extend(entry.desc.body_b);
        if let Some(leader) = gear.and_then(|g| self.joints.get(g.leader)) {
            wake.push(leader.desc.body_a);
            wake.extend(leader.desc.body_b);
        }
        self.joints.get_mut(follower).expect("checked above").gear = state;
        for body in wake {
            self.wake(body)?;
        }
        Ok(())
    }

    /// The gear of joint `id` (see [`World::set_joint_gear`]).
    pub fn joint_gear(&self, id: JointId) -> Result<Option<Gear>, WorldError> {
        let entry = self.joints.get(id).ok_or(WorldError::StaleJoint(id))?;
        Ok(entry.gear.map(|g| g.gear))
    }

    /// How far joint `id`'s coordinate is from where its gear holds it (rad
    /// or m; 0 without a gear).
    pub fn gear_error(&self, id: JointId) -> Result<f64, WorldError> {
        let entry = self.joints.get(id).ok_or(WorldError::StaleJoint(id))?;
        Ok(self.gear_error_of(entry))
    }

    /// [`World::gear_error`] of an entry (0 where its leader is gone).
    fn gear_error_of(&self, entry: &JointEntry) -> f64 {
        let Some(state) = entry.gear else { return 0.0 };
        let Some(leader) = self.joints.get(state.gear.leader) else {
            return 0.0;
        };
        let [q_leader, q_follower] = self.gear_coordinates(leader, entry, &state);
        state.gear.error(q_leader, q_follower).abs()
    }

    /// The leader's and follower's coordinates now, followed from those the
    /// gear kept after the last step.
    pub(crate) fn gear_coordinates(
        &self,
        leader: &JointEntry,
        follower: &JointEntry,
        state: &GearState,
    ) -> [f64; 2] {
        let now = |e: &JointEntry, last: f64| {
            unwrap_coordinate(e.desc.kind, last, self.place(e).coordinate(e.desc.kind))
        };
        [
            now(leader, state.coordinates[0]),
            now(follower, state.coordinates[1]),
        ]
    }

    /// After a step: each gear's coordinates followed to the bodies' poses
    /// (so that a hinge's turn is counted across its wrap).
    pub(crate) fn follow_gear_coordinates(&mut self) {
        for k in 0..self.joints.slot_count() as u32 {
            let Some(follower) = self.joints.at(k) else {
                continue;
            };
            let Some(state) = follower.gear else { continue };
            let Some(leader) = self.joints.get(state.gear.leader) else {
                continue;
            };
            let coordinates = self.gear_coordinates(leader, follower, &state);
            if let Some(g) = self.joints.at_mut(k).and_then(|e| e.gear.as_mut()) {
                g.coordinates = coordinates;
            }
        }
    }

    /// Removes the gears that follow joint `leader` (it is being removed).
    fn remove_gears_led_by(&mut self, leader: JointId) {
        for k in 0..self.joints.slot_count() as u32 {
            if let Some(e) = self.joints.at_mut(k) {
                if e.gear.is_some_and(|g| g.gear.leader == leader) {
                    e.gear = None;
                }
            }
        }
    }

    /// Removes a joint (and the gears that follow it); its bodies wake.
    pub fn remove_joint(&mut self, id: JointId) -> Result<(), WorldError> {
        let entry = self.joints.remove(id).ok_or(WorldError::StaleJoint(id))?;
        self.remove_gears_led_by(id);
        for body in [Some(entry.desc.body_a), entry.desc.body_b].into_iter().flatten() {
            // The body may have gone first (removing a body removes its joints).
            let _ = self.wake(body);
        }
        Ok(())
    }

    /// Replaces a joint's motor (`None` switches it off; a hinge's, slider's
    /// or ball joint's, [`Motor`](crate::joint::Motor)), e.g. to move a PD
    /// servo's target each step. Validated as in
    /// [`World::add_joint`]; the joint's bodies wake.
    pub fn set_joint_motor(
        &mut self,
        id: JointId,
        motor: Option<crate::joint::Motor>,
    ) -> Result<(), WorldError> {
        self.change_joint(id, |desc| desc.motor = motor)
    }

    /// Replaces a joint's spring-damper (`None` takes it off): a hinge's,
    /// slider's or ball joint's passive spring, or a distance joint's spring (without one
    /// the distance joint is a rod again, or a rope with limits), e.g. to
    /// vary a robot's joint damping between rollouts. Validated as in
    /// [`World::add_joint`]; the joint's bodies wake.
    pub fn set_joint_spring(
        &mut self,
        id: JointId,
        spring: Option<crate::joint::Spring>,
    ) -> Result<(), WorldError> {
        self.change_joint(id, |desc| desc.spring = spring)
    }

    /// Replaces a joint's Coulomb friction (`None` takes it off; see
    /// [`JointDesc::friction`]), e.g. to vary a robot's joint friction
    /// between rollouts. Validated as in [`World::add_joint`]; the joint's
    /// bodies wake.
    pub fn set_joint_friction(&mut self, id: JointId, friction: Option<f64>) -> Result<(), WorldError> {
        self.change_joint(id, |desc| desc.friction = friction)
    }

    /// A joint's motor, spring or friction changed by `edit` on its description,
    /// validated first (the world unchanged on an error), then copied into
    /// the law the solver reads; the joint's bodies wake.
    fn change_joint(&mut self, id: JointId, edit: impl FnOnce(&mut JointDesc)) -> Result<(), WorldError> {
        let entry = self.joints.get(id).ok_or(WorldError::StaleJoint(id))?;
        let mut desc = entry.desc.clone();
        edit(&mut desc);
        desc.validate()?;
        let entry = self.joints.get_mut(id).ok_or(WorldError::StaleJoint(id))?;
        entry.law = JointLaw::of(&desc, entry.law.length);
        let bodies = [Some(desc.body_a), desc.body_b];
        entry.desc = desc;
        for body in bodies.into_iter().flatten() {
            self.wake(body)?;
        }
        Ok(())
    }

    /// Number of joints.
    pub fn joint_count(&self) -> usize {
        self.joints.len()
    }

    /// Handles of all joints, in slot order.
    pub fn joint_ids(&self) -> Vec<JointId> {
        self.joints.iter().map(|(id, _)| id).collect()
    }

    /// The description a joint was made from.
    pub fn joint(&self, id: JointId) -> Result<&JointDesc, WorldError> {
        Ok(&self.joints.get(id).ok_or(WorldError::StaleJoint(id))?.desc)
    }

    /// Where the joint's frames are now (both anchors, both axes).
    pub fn joint_pose(&self, id: JointId) -> Result<JointPose, WorldError> {
        let entry = self.joints.get(id).ok_or(WorldError::StaleJoint(id))?;
        Ok(self.place(entry))
    }

    pub(crate) fn place(&self, entry: &JointEntry) -> JointPose {
        let side = |id: Option<BodyId>| match id.and_then(|id| self.bodies.get(id)) {
            Some(e) => (e.body.position(), e.body.orientation()),
            None => (DVec3::ZERO, DQuat::IDENTITY),
        };
        let (xa, qa) = side(Some(entry.desc.body_a));
        let (xb, qb) = side(entry.desc.body_b);
        JointPose::new(xa, qa, &entry.local[0], xb, qb, &entry.local[1])
    }

    /// The joint's coordinate, rate, errors and reaction (see [`JointState`]).
    pub fn joint_state(&self, id: JointId) -> Result<JointState, WorldError> {
        let entry = self.joints.get(id).ok_or(WorldError::StaleJoint(id))?;
        let p = self.place(entry);
        let vel = |id: Option<BodyId>| {
            id.and_then(|id| self.bodies.get(id))
                .map_or((DVec3::ZERO, DVec3::ZERO), body_velocities)
        };
        let (va, wa) = vel(Some(entry.desc.body_a));
        let (vb, wb) = vel(entry.desc.body_b);
        let d = p.pa - p.pb;
        let axis = p.axis_b(0);
        // Velocity of A's anchor relative to B's.
        let dv = va + wa.cross(p.ra) - vb - wb.cross(p.rb);
        let law = &entry.law;
        let outside = |x: f64| match law.limits {
            Some([lo, hi]) => (lo - x).max(x - hi).max(0.0),
            None => 0.0,
        };
        let (position, rate, linear_error, angular_error) = match law.kind {
            JointKind::Fixed => (0.0, 0.0, d.length(), p.rotation_error().length()),
            JointKind::Ball => {
                let twist = p.twist();
                let beyond = law.swing_limit.map_or(0.0, |c| (p.swing() - c).max(0.0));
                (twist, (wa - wb).dot(axis), d.length(), beyond.max(outside(twist)))
            }
            JointKind::Hinge => {
                let angle = p.twist();
                (
                    angle,
                    (wa - wb).dot(axis),
                    d.length(),
                    p.swing().max(outside(angle)),
                )
            }
            JointKind::Slider => {
                let offset = p.offset();
                let off_axis = (d - axis * offset).length();
                // n fixed in B: d/dt (n . d) = n . dv + (wB x n) . d.
                let rate = axis.dot(dv) + wb.cross(axis).dot(d);
                (
                    offset,
                    rate,
                    off_axis.max(outside(offset)),
                    p.rotation_error().length(),
                )
            }
            JointKind::Distance => {
                let len = d.length();
                let rate = if len > 0.0 { dv.dot(d) / len } else { 0.0 };
                let error = match (law.spring, law.limits) {
                    (None, None) => (len - law.length).abs(),
                    _ => outside(len),
                };
                (len, rate, error, 0.0)
            }
        };
        // A follower off its gear is off where it is held, along its coordinate.
        let off_gear = self.gear_error_of(entry);
        let (linear_error, angular_error) = match law.kind {
            JointKind::Slider => (linear_error.max(off_gear), angular_error),
            _ => (linear_error, angular_error.max(off_gear)),
        };
        Ok(JointState {
            position,
            rate,
            linear_error,
            angular_error,
            force: entry.force,
            torque: entry.torque,
            anchor_a: p.pa,
            anchor_b: p.pb,
            axis,
            // From B's joint frame into the world's axes at creation (both
            // frames were `frame_rotation(axis)` then).
            rotation: frame_rotation(entry.desc.axis.normalize()) * p.relative_rotation(),
        })
    }

    /// Largest linear (m) and angular (rad) error over all joints.
    pub fn max_joint_error(&self) -> (f64, f64) {
        self.joints.iter().fold((0.0, 0.0), |(l, a), (id, _)| {
            let s = self.joint_state(id).expect("live joint");
            (f64::max(l, s.linear_error), f64::max(a, s.angular_error))
        })
    }

    /// Body slot pairs linked by a joint (both bodies, not the world), in
    /// joint order: they share an island.
    pub(crate) fn joint_links(&self) -> Vec<(u32, u32)> {
        let mut links: Vec<(u32, u32)> = self
            .joints
            .iter()
            .filter_map(|(_, j)| {
                let (a, b) = j.slots();
                b.map(|b| (a, b))
            })
            .collect();
        // A gear links its follower's bodies with its leader's (every pair:
        // a link with a static end is dropped, and either side may be one).
        for (_, j) in self.joints.iter() {
            if let Some(leader) = j.gear.and_then(|g| self.joints.get(g.gear.leader)) {
                let sides = |(a, b): (u32, Option<u32>)| [Some(a), b].into_iter().flatten();
                for l in sides(leader.slots()) {
                    links.extend(sides(j.slots()).map(|f| (l, f)));
                }
            }
        }
        links
    }

    /// The body slots of every joint (`None`: the world).
    pub(crate) fn joint_slots(&self) -> impl Iterator<Item = (u32, Option<u32>)> + '_ {
        self.joints.iter().map(|(_, j)| j.slots())
    }

    /// Per body slot (of `n_slots`): some joint holds the body. The
    /// continuous stage leaves such bodies where the solver put them:
    /// moving one alone would pull it from the bodies it is jointed to.
    pub(crate) fn jointed_flags(&self, n_slots: usize) -> Vec<bool> {
        let mut jointed = vec![false; n_slots];
        for (a, b) in self.joint_slots() {
            jointed[a as usize] = true;
            if let Some(b) = b {
                jointed[b as usize] = true;
            }
        }
        jointed
    }

    /// Removes the joints attached to body slot `slot` (with the body).
    /// Forgets what the joints of body slot `slot` did in the step (their
    /// warm-start impulses and reported reactions, back to zero): the
    /// quarantine restored the body to its state before the step, and a
    /// runaway solve leaves impulses of 1e308 or NaN that the next step
    /// would warm start from.
    pub(crate) fn reset_joints_of(&mut self, slot: u32) {
        // A gear's impulse acts on its leader's bodies too: forgotten where
        // either joint holds the body.
        let held: Vec<JointId> = self
            .joints
            .iter()
            .filter(|(_, e)| e.holds(slot))
            .map(|(id, _)| id)
            .collect();
        for k in 0..self.joints.slot_count() as u32 {
            if let Some(g) = self.joints.at_mut(k).and_then(|e| e.gear.as_mut()) {
                if held.contains(&g.gear.leader) {
                    g.impulse = 0.0;
                }
            }
        }
        for k in 0..self.joints.slot_count() as u32 {
            if let Some(entry) = self.joints.at_mut(k) {
                if entry.holds(slot) {
                    entry.impulses = [0.0; JOINT_ROWS];
                    entry.force = DVec3::ZERO;
                    entry.torque = DVec3::ZERO;
                    if let Some(g) = entry.gear.as_mut() {
                        g.impulse = 0.0;
                    }
                }
            }
        }
    }

    pub(crate) fn remove_joints_of(&mut self, slot: u32) {
        let attached: Vec<JointId> = self
            .joints
            .iter()
            .filter(|(_, j)| j.holds(slot))
            .map(|(id, _)| id)
            .collect();
        for id in attached {
            self.joints.remove(id);
            self.remove_gears_led_by(id);
        }
    }
}
