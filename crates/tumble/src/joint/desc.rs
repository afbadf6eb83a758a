//! Joint descriptions: what the user hands to
//! [`World::add_joint`](crate::world::World::add_joint). Plain data, in
//! world coordinates at creation (the anchor point, the axis), validated
//! when added and turned into a frame on each body; the pose the bodies
//! have then is the joint's zero (angle 0, offset 0).

use crate::world::{within_position_limit, BodyId, WorldError, MAX_POSITION};
use serde::{Deserialize, Serialize};
use tumble_collide::{DQuat, DVec3};

/// What a joint lets the two bodies do relative to each other.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum JointKind {
    /// Weld: no relative motion at all.
    Fixed,
    /// Spherical: the anchors coincide, any rotation; an optional swing
    /// cone about the axis (`swing_limit`), twist limits about it
    /// (`limits`, rad) and a spring-damper towards the orientation at
    /// creation.
    Ball,
    /// Revolute: rotation about the axis only; angle limits (rad), a
    /// motor (rad/s, N m) and a spring-damper.
    Hinge,
    /// Prismatic: translation along the axis only; offset limits (m), a
    /// motor (m/s, N) and a spring-damper.
    Slider,
    /// The anchors keep a distance: a rod at `length` by default, a rope
    /// with `limits = [0, max]`, a spring with `spring`.
    Distance,
}

impl JointKind {
    /// Every kind, in the order of the docs.
    pub const ALL: [JointKind; 5] = [
        JointKind::Fixed,
        JointKind::Ball,
        JointKind::Hinge,
        JointKind::Slider,
        JointKind::Distance,
    ];

    /// The kind's name in scene files and Python ("fixed", "ball", ...).
    pub fn name(self) -> &'static str {
        match self {
            JointKind::Fixed => "fixed",
            JointKind::Ball => "ball",
            JointKind::Hinge => "hinge",
            JointKind::Slider => "slider",
            JointKind::Distance => "distance",
        }
    }

    /// The kind with this name.
    pub fn from_name(name: &str) -> Option<JointKind> {
        JointKind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Units of the joint's coordinate (angle or offset or length).
    pub fn unit(self) -> &'static str {
        match self {
            JointKind::Ball | JointKind::Hinge => "rad",
            JointKind::Fixed => "-",
            JointKind::Slider | JointKind::Distance => "m",
        }
    }
}

/// A joint motor: drives the joint coordinate (hinge angle, slider offset)
/// with at most `max_force` (N m for a hinge, N for a slider), or a ball
/// joint's relative rotation with a torque at most `max_force` long (N m,
/// whichever way it turns).
///
/// A ball joint's targets are vectors in world axes at the joint's creation,
/// carried with body B afterwards (fixed in B's joint frame; the world's
/// axes when B is the world), and they act on A relative to B: `AngularVelocity`
/// holds `wA - wB` at the target, `Orientation` turns A from its orientation
/// relative to B at creation by the target rotation vector (Jolt's
/// swing-twist motor, PhysX's slerp drive). Hinges and sliders take
/// `Velocity` and `Position` motors (`velocity`, `position` in scene
/// files), ball joints `AngularVelocity` and `Orientation`
/// (`angular_velocity`, `orientation`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case", tag = "type", deny_unknown_fields)]
pub enum Motor {
    /// Holds the rate at `target` (rad/s or m/s) as hard as `max_force` allows.
    Velocity {
        /// Target rate (rad/s for a hinge, m/s for a slider).
        target: f64,
        /// Largest torque (N m) or force (N) the motor gives, >= 0
        /// (infinity: unbounded).
        max_force: f64,
    },
    /// A PD servo towards `target` (rad or m): force = stiffness (target -
    /// x) - damping x', integrated implicitly (stable for any gains).
    Position {
        /// Target angle (rad) or offset (m).
        target: f64,
        /// Proportional gain, >= 0 (N m/rad or N/m).
        stiffness: f64,
        /// Derivative gain, >= 0 (N m s/rad or N s/m).
        damping: f64,
        /// Largest torque (N m) or force (N), >= 0.
        max_force: f64,
    },
    /// Ball joint: holds the angular velocity of A relative to B at
    /// `target` as hard as `max_force` allows.
    AngularVelocity {
        /// Target relative angular velocity `wA - wB` (rad/s; world axes at
        /// creation, turning with B).
        target: [f64; 3],
        /// Largest torque (N m), >= 0 (infinity: unbounded): the length of
        /// the motor's torque, whichever way it acts.
        max_force: f64,
    },
    /// Ball joint: a PD servo turning A relative to B towards the rotation
    /// `target` from their relative orientation at creation: torque =
    /// stiffness theta - damping (wA - wB), `theta` the rotation vector from
    /// A's present orientation to the target (the short way round),
    /// integrated implicitly (stable for any gains).
    Orientation {
        /// Target rotation vector (axis times angle, rad; world axes at
        /// creation, turning with B); its length is the angle, any finite
        /// length (beyond pi the same orientation as the shorter turn the
        /// other way).
        target: [f64; 3],
        /// Proportional gain, >= 0 (N m/rad).
        stiffness: f64,
        /// Derivative gain, >= 0 (N m s/rad).
        damping: f64,
        /// Largest torque (N m), >= 0: the length of the motor's torque.
        max_force: f64,
    },
}

impl Motor {
    /// Largest torque (N m) or force (N).
    pub fn max_force(&self) -> f64 {
        match *self {
            Motor::Velocity { max_force, .. }
            | Motor::Position { max_force, .. }
            | Motor::AngularVelocity { max_force, .. }
            | Motor::Orientation { max_force, .. } => max_force,
        }
    }

    /// Whether this is a ball joint's motor (`AngularVelocity`, `Orientation`).
    pub fn is_ball(&self) -> bool {
        matches!(self, Motor::AngularVelocity { .. } | Motor::Orientation { .. })
    }

    /// The same motor with a ball joint's vector target turned by
    /// `rotation` (from world axes at creation into B's joint frame, where
    /// the solver keeps it); a hinge's or slider's unchanged.
    pub fn turned(self, rotation: DQuat) -> Motor {
        let turn = |t: [f64; 3]| (rotation * DVec3::from(t)).to_array();
        match self {
            Motor::AngularVelocity { target, max_force } => Motor::AngularVelocity {
                target: turn(target),
                max_force,
            },
            Motor::Orientation {
                target,
                stiffness,
                damping,
                max_force,
            } => Motor::Orientation {
                target: turn(target),
                stiffness,
                damping,
                max_force,
            },
            m => m,
        }
    }
}

/// Serde of [`JointDesc::motor`]: the motor as scene files write it
/// (tagged by a `type` field) in human-readable formats, and as the
/// externally tagged [`MotorRecord`] in binary ones. A binary snapshot
/// (postcard) cannot read an enum tagged by a field, which needs a
/// self-describing format: a snapshot of a world with any motor failed to
/// decode ("a feature that PostCard will never implement"), so a robot
/// under its servos could not be pickled or sent to a Ray worker.
mod motor_serde {
    use super::{Motor, MotorRecord};
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub fn serialize<S: Serializer>(motor: &Option<Motor>, s: S) -> Result<S::Ok, S::Error> {
        if s.is_human_readable() {
            motor.serialize(s)
        } else {
            motor.map(MotorRecord::from).serialize(s)
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Motor>, D::Error> {
        if d.is_human_readable() {
            Option::<Motor>::deserialize(d)
        } else {
            Ok(Option::<MotorRecord>::deserialize(d)?.map(Motor::from))
        }
    }
}

/// [`Motor`] in binary formats (`motor_serde`): the same variants and
/// fields, tagged by the variant's index instead of a `type` field.
#[derive(Serialize, Deserialize)]
enum MotorRecord {
    Velocity([f64; 2]),
    Position([f64; 4]),
    AngularVelocity([f64; 3], f64),
    Orientation([f64; 3], [f64; 3]),
}

impl From<Motor> for MotorRecord {
    fn from(m: Motor) -> MotorRecord {
        match m {
            Motor::Velocity { target, max_force } => MotorRecord::Velocity([target, max_force]),
            Motor::Position {
                target,
                stiffness,
                damping,
                max_force,
            } => MotorRecord::Position([target, stiffness, damping, max_force]),
            Motor::AngularVelocity { target, max_force } => MotorRecord::AngularVelocity(target, max_force),
            Motor::Orientation {
                target,
                stiffness,
                damping,
                max_force,
            } => MotorRecord::Orientation(target, [stiffness, damping, max_force]),
        }
    }
}

impl From<MotorRecord> for Motor {
    fn from(m: MotorRecord) -> Motor {
        match m {
            MotorRecord::Velocity([target, max_force]) => Motor::Velocity { target, max_force },
            MotorRecord::Position([target, stiffness, damping, max_force]) => Motor::Position {
                target,
                stiffness,
                damping,
                max_force,
            },
            MotorRecord::AngularVelocity(target, max_force) => Motor::AngularVelocity { target, max_force },
            MotorRecord::Orientation(target, [stiffness, damping, max_force]) => Motor::Orientation {
                target,
                stiffness,
                damping,
                max_force,
            },
        }
    }
}

/// A passive spring-damper on the joint's coordinate: on a distance joint
/// towards its `length` (N/m, N s/m); on a hinge towards the angle it was
/// made at, the short way round (the angle is measured within +-pi; N m/rad,
/// N m s/rad); on a slider towards the offset it was made
/// at (N/m, N s/m); on a ball joint towards the relative orientation it was
/// made at, a torque `-k theta - c w` with `theta` the rotation vector that
/// takes the bodies back (the short way round) and `w` their relative
/// angular velocity (N m/rad, N m s/rad, the same about every axis: a
/// ragdoll's damped shoulders and hips, MuJoCo's ball `stiffness` and
/// `damping`). It acts beside a hinge's or slider's motor (a damped
/// robot joint under its servo; URDF's `<dynamics damping>` is a spring of
/// stiffness 0) and is never bounded by the motor's force.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Spring {
    /// Stiffness (N/m; N m/rad on a hinge or ball joint), >= 0.
    pub stiffness: f64,
    /// Damping (N s/m; N m s/rad on a hinge or ball joint), >= 0.
    pub damping: f64,
}

/// A joint between two bodies, or a body and the world.
///
/// ```
/// use tumble::collide::{Cuboid, DVec3};
/// use tumble::joint::{JointDesc, Motor};
/// use tumble::world::{BodyDesc, World, WorldSettings};
///
/// let mut world = World::new(WorldSettings { gravity: DVec3::ZERO, ..WorldSettings::default() })?;
/// // A door 1 m wide hinged to the world along its left edge (the z axis),
/// // driven at 1 rad/s by a motor of at most 50 N m, opening at most 90 degrees.
/// let door = world.add_body(
///     &BodyDesc::dynamic(Cuboid::new(DVec3::new(0.5, 0.02, 1.0))?)
///         .at(DVec3::new(0.5, 0.0, 1.0))
///         .with_mass(20.0),
/// )?;
/// let hinge = world.add_joint(
///     &JointDesc::hinge(door, None, DVec3::new(0.0, 0.0, 1.0), DVec3::Z)
///         .with_limits(0.0, std::f64::consts::FRAC_PI_2)
///         .with_motor(Motor::Velocity { target: 1.0, max_force: 50.0 }),
/// )?;
/// for _ in 0..60 {
///     world.step();
/// }
/// // Up to speed after 0.13 s (50 N m on the door's 6.7 kg m^2 about its edge).
/// let state = world.joint_state(hinge)?;
/// assert!((state.rate - 1.0).abs() < 1e-3);
/// assert!((state.position - (1.0 - 0.5 * 1.0 * 6.67 / 50.0)).abs() < 0.01);
/// for _ in 0..120 {
///     world.step();
/// }
/// // Stopped at its limit; the hinge still holds the door's edge in place.
/// let state = world.joint_state(hinge)?;
/// assert!((state.position - std::f64::consts::FRAC_PI_2).abs() < 0.01);
/// assert!(state.linear_error < 1e-4);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// The bodies are named by `B`: a [`BodyId`] for a world, an index into
/// the body list for a [`Scene`](crate::scenes::Scene).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointDesc<B = BodyId> {
    /// What the joint allows.
    pub kind: JointKind,
    /// The first body.
    pub body_a: B,
    /// The second body, or `None` for the world.
    pub body_b: Option<B>,
    /// The joint's anchor point in world coordinates at creation (m); on a
    /// distance joint, the anchor on body A.
    pub anchor: DVec3,
    /// Distance joint: the anchor on body B (m, world, at creation).
    /// Default: `anchor`.
    pub anchor_b: Option<DVec3>,
    /// The joint axis in world coordinates at creation (hinge: rotation
    /// axis; slider: direction of travel; ball: the axis of the swing cone
    /// and of twist). Any length but zero. Default +z.
    pub axis: DVec3,
    /// Limits of the joint coordinate `[lower, upper]`: hinge angle or ball
    /// twist (rad, within [-pi, pi]), slider offset (m), distance (m, >= 0).
    pub limits: Option<[f64; 2]>,
    /// Ball joint: half-angle of the cone the axis may swing in (rad, in (0, pi]).
    pub swing_limit: Option<f64>,
    /// Hinge, slider or ball joint motor ([`Motor`]).
    #[serde(default, with = "motor_serde")]
    pub motor: Option<Motor>,
    /// A spring-damper ([`Spring`]): on a distance joint towards `length`
    /// instead of a rod; on a hinge or slider towards its position at
    /// creation, beside its motor; on a ball joint towards its relative
    /// orientation at creation.
    pub spring: Option<Spring>,
    /// Distance joint: rest length (m, >= 0). Default: the anchors'
    /// distance at creation.
    pub length: Option<f64>,
    /// Coulomb friction on the joint's coordinate (N m on a hinge or ball
    /// joint, N on a slider or distance joint; finite, >= 0): the joint
    /// holds still while the torque or force that would move it stays
    /// within the friction, and moving it is opposed by exactly the
    /// friction. On a ball joint it bounds the friction torque's length,
    /// whichever way the joint turns. It acts beside the motor and the
    /// spring (a robot joint's friction under its servo; URDF's `<dynamics
    /// friction>`, MuJoCo's `frictionloss`). Not on a weld, nor on a
    /// distance joint that is a rod (no limits, no spring); 0 is none.
    #[serde(default)]
    pub friction: Option<f64>,
    /// Contacts between the two bodies (default off: jointed bodies
    /// usually overlap at the joint).
    pub collide_connected: bool,
    /// A name for reports and the viewer.
    pub name: String,
}

impl<B: Copy + PartialEq> JointDesc<B> {
    /// A joint of `kind` at `anchor` with `axis` (world, at creation).
    pub fn new(kind: JointKind, body_a: B, body_b: Option<B>, anchor: DVec3, axis: DVec3) -> JointDesc<B> {
        JointDesc {
            kind,
            body_a,
            body_b,
            anchor,
            anchor_b: None,
            axis,
            limits: None,
            swing_limit: None,
            motor: None,
            spring: None,
            length: None,
            friction: None,
            collide_connected: false,
            name: String::new(),
        }
    }

    /// A weld at `anchor`.
    pub fn fixed(body_a: B, body_b: Option<B>, anchor: DVec3) -> JointDesc<B> {
        JointDesc::new(JointKind::Fixed, body_a, body_b, anchor, DVec3::Z)
    }

    /// A ball joint at `anchor`.
    pub fn ball(body_a: B, body_b: Option<B>, anchor: DVec3) -> JointDesc<B> {
        JointDesc::new(JointKind::Ball, body_a, body_b, anchor, DVec3::Z)
    }

    /// A hinge at `anchor` turning about `axis`.
    pub fn hinge(body_a: B, body_b: Option<B>, anchor: DVec3, axis: DVec3) -> JointDesc<B> {
        JointDesc::new(JointKind::Hinge, body_a, body_b, anchor, axis)
    }

    /// A slider at `anchor` along `axis`.
    pub fn slider(body_a: B, body_b: Option<B>, anchor: DVec3, axis: DVec3) -> JointDesc<B> {
        JointDesc::new(JointKind::Slider, body_a, body_b, anchor, axis)
    }

    /// A distance joint between `anchor_a` on A and `anchor_b` on B (a rod
    /// at their present distance unless limits or a spring say otherwise).
    pub fn distance(body_a: B, body_b: Option<B>, anchor_a: DVec3, anchor_b: DVec3) -> JointDesc<B> {
        let mut d = JointDesc::new(JointKind::Distance, body_a, body_b, anchor_a, DVec3::Z);
        d.anchor_b = Some(anchor_b);
        d
    }

    /// With limits `[lower, upper]` (rad or m, by kind).
    pub fn with_limits(mut self, lower: f64, upper: f64) -> JointDesc<B> {
        self.limits = Some([lower, upper]);
        self
    }

    /// With a swing cone (ball joint), half-angle in rad.
    pub fn with_swing_limit(mut self, angle: f64) -> JointDesc<B> {
        self.swing_limit = Some(angle);
        self
    }

    /// With a motor (hinge, slider, ball joint: [`Motor`]).
    pub fn with_motor(mut self, motor: Motor) -> JointDesc<B> {
        self.motor = Some(motor);
        self
    }

    /// With Coulomb friction on the joint ([`JointDesc::friction`]: N m or N).
    pub fn with_friction(mut self, friction: f64) -> JointDesc<B> {
        self.friction = Some(friction);
        self
    }

    /// With a spring-damper ([`Spring`]: distance, ball, hinge or slider joint).
    pub fn with_spring(mut self, stiffness: f64, damping: f64) -> JointDesc<B> {
        self.spring = Some(Spring { stiffness, damping });
        self
    }

    /// With a rest length (distance joint, m).
    pub fn with_length(mut self, length: f64) -> JointDesc<B> {
        self.length = Some(length);
        self
    }

    /// With contacts between the two bodies on or off.
    pub fn colliding(mut self, collide_connected: bool) -> JointDesc<B> {
        self.collide_connected = collide_connected;
        self
    }

    /// With a name.
    pub fn named(mut self, name: impl Into<String>) -> JointDesc<B> {
        self.name = name.into();
        self
    }

    /// The same joint between other bodies (`map` turns each body
    /// reference into the new kind, e.g. scene indices into handles).
    pub fn with_bodies<C>(self, map: impl Fn(B) -> C) -> JointDesc<C> {
        JointDesc {
            kind: self.kind,
            body_a: map(self.body_a),
            body_b: self.body_b.map(&map),
            anchor: self.anchor,
            anchor_b: self.anchor_b,
            axis: self.axis,
            limits: self.limits,
            swing_limit: self.swing_limit,
            motor: self.motor,
            spring: self.spring,
            length: self.length,
            friction: self.friction,
            collide_connected: self.collide_connected,
            name: self.name,
        }
    }

    /// Checks every value that does not depend on the world (finite,
    /// ranges, which options apply to the kind). The bodies are checked by
    /// the world.
    pub fn validate(&self) -> Result<(), WorldError> {
        let bad = |field: &'static str, message: String| Err(WorldError::BadValue { field, message });
        let kind = self.kind.name();
        let not_on_a_weld = || format!("applies to distance, ball, hinge and slider joints, not {kind}");
        // Anchors, lengths and linear limits within the coordinate limit
        // every body is held to (`MAX_POSITION`): a distance joint anchored
        // at 1.8e308 m (finite) was accepted and its island's impulses
        // turned NaN (libFuzzer's `joints` target).
        if !within_position_limit(self.anchor) {
            return bad(
                "joint.anchor",
                format!(
                    "must be finite and within {MAX_POSITION:e} m of the origin, got {:?}",
                    self.anchor
                ),
            );
        }
        if let Some(b) = self.anchor_b {
            if !within_position_limit(b) {
                return bad(
                    "joint.anchor_b",
                    format!("must be finite and within {MAX_POSITION:e} m of the origin, got {b:?}"),
                );
            }
            if self.kind != JointKind::Distance {
                return bad(
                    "joint.anchor_b",
                    format!("applies to distance joints only, not {kind}"),
                );
            }
        }
        let len = self.axis.length();
        if !(len.is_finite() && len > 1e-12) {
            return bad(
                "joint.axis",
                format!("must be a finite, non-zero vector, got {:?}", self.axis),
            );
        }
        if let Some([lo, hi]) = self.limits {
            if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                return bad(
                    "joint.limits",
                    format!("must be finite with lower <= upper, got [{lo}, {hi}]"),
                );
            }
            if lo.abs().max(hi.abs()) > MAX_POSITION {
                return bad(
                    "joint.limits",
                    format!("must lie within +-{MAX_POSITION:e}, got [{lo}, {hi}]"),
                );
            }
            match self.kind {
                JointKind::Fixed => return bad("joint.limits", "a fixed joint has no limits".into()),
                JointKind::Hinge | JointKind::Ball => {
                    let pi = std::f64::consts::PI;
                    if lo < -pi || hi > pi {
                        return bad(
                            "joint.limits",
                            format!("{kind} angle limits must lie within [-pi, pi] rad, got [{lo}, {hi}]"),
                        );
                    }
                }
                JointKind::Distance if lo < 0.0 => {
                    return bad(
                        "joint.limits",
                        format!("distances must be >= 0 m, got [{lo}, {hi}]"),
                    )
                }
                _ => {}
            }
        }
        if let Some(angle) = self.swing_limit {
            if self.kind != JointKind::Ball {
                return bad(
                    "joint.swing_limit",
                    format!("applies to ball joints only, not {kind}"),
                );
            }
            if !(angle > 0.0 && angle <= std::f64::consts::PI) {
                return bad(
                    "joint.swing_limit",
                    format!("must be in (0, pi] rad, got {angle}"),
                );
            }
        }
        if let Some(m) = self.motor {
            match self.kind {
                JointKind::Hinge | JointKind::Slider if m.is_ball() => {
                    return bad(
                        "joint.motor",
                        format!(
                            "a {kind} takes a \"velocity\" or \"position\" motor (its coordinate is \
                             a number), not a ball joint's vector target"
                        ),
                    )
                }
                JointKind::Ball if !m.is_ball() => {
                    return bad(
                        "joint.motor",
                        "a ball joint takes an \"angular_velocity\" or \"orientation\" motor \
                         (a vector target, rad/s or rad)"
                            .into(),
                    )
                }
                JointKind::Hinge | JointKind::Slider | JointKind::Ball => {}
                _ => {
                    return bad(
                        "joint.motor",
                        format!("applies to hinges, sliders and ball joints only, not {kind}"),
                    )
                }
            }
            let (target, gains) = match m {
                Motor::Velocity { target, .. } => ([target; 3], [0.0, 0.0]),
                Motor::AngularVelocity { target, .. } => (target, [0.0, 0.0]),
                Motor::Position {
                    target,
                    stiffness,
                    damping,
                    ..
                } => ([target; 3], [stiffness, damping]),
                Motor::Orientation {
                    target,
                    stiffness,
                    damping,
                    ..
                } => (target, [stiffness, damping]),
            };
            // (Finite components, and a finite length: a rotation vector
            // whose length overflows has no orientation.)
            if !(target.iter().all(|t| t.is_finite())
                && (!m.is_ball() || DVec3::from(target).length().is_finite()))
            {
                let shown = if m.is_ball() {
                    format!("{target:?}")
                } else {
                    format!("{}", target[0])
                };
                return bad("joint.motor.target", format!("must be finite, got {shown}"));
            }
            if !(gains.iter().all(|g| g.is_finite() && *g >= 0.0)) {
                return bad(
                    "joint.motor",
                    format!("stiffness and damping must be finite and >= 0, got {gains:?}"),
                );
            }
            if let Motor::Position {
                stiffness, damping, ..
            }
            | Motor::Orientation {
                stiffness, damping, ..
            } = m
            {
                if stiffness == 0.0 && damping == 0.0 {
                    return bad(
                        "joint.motor",
                        "a position or orientation motor needs stiffness or damping > 0".into(),
                    );
                }
            }
            let f = m.max_force();
            if f.is_nan() || f < 0.0 {
                return bad(
                    "joint.motor.max_force",
                    format!("must be >= 0 (N m or N; infinity for no bound), got {f}"),
                );
            }
        }
        if let Some(s) = self.spring {
            if self.kind == JointKind::Fixed {
                return bad("joint.spring", not_on_a_weld());
            }
            if !(s.stiffness.is_finite() && s.stiffness >= 0.0 && s.damping.is_finite() && s.damping >= 0.0) {
                return bad(
                    "joint.spring",
                    format!(
                        "stiffness and damping must be finite and >= 0, got {} and {}",
                        s.stiffness, s.damping
                    ),
                );
            }
            if s.stiffness == 0.0 && s.damping == 0.0 {
                return bad("joint.spring", "needs stiffness or damping > 0".into());
            }
        }
        if let Some(f) = self.friction {
            if self.kind == JointKind::Fixed {
                return bad("joint.friction", not_on_a_weld());
            }
            if self.kind == JointKind::Distance && self.spring.is_none() && self.limits.is_none() {
                return bad(
                    "joint.friction",
                    "a rod's length cannot change: friction on a distance joint needs limits (a rope) \
                     or a spring"
                        .into(),
                );
            }
            if !(f.is_finite() && f >= 0.0) {
                return bad(
                    "joint.friction",
                    format!("must be finite and >= 0 (N m or N), got {f}"),
                );
            }
        }
        if let Some(l) = self.length {
            if self.kind != JointKind::Distance {
                return bad(
                    "joint.length",
                    format!("applies to distance joints only, not {kind}"),
                );
            }
            if !(l.is_finite() && (0.0..=MAX_POSITION).contains(&l)) {
                return bad(
                    "joint.length",
                    format!("must be finite, >= 0 and at most {MAX_POSITION:e} m, got {l}"),
                );
            }
        }
        if self.body_b == Some(self.body_a) {
            return bad("joint.body_b", "a joint links two different bodies".into());
        }
        Ok(())
    }
}
