//! Body descriptions: what the user hands to [`World::add_body`](super::World::add_body).
//! Descriptions in, handles out: a `BodyDesc` is plain data with a `Default`,
//! validated when added, never referenced by the world afterwards.

use crate::body::BodyKind;
use serde::{Deserialize, Serialize};
use tumble_collide::shape::Shape;
use tumble_collide::{DVec3, Pose};

/// One shape of a body, placed in the body's model frame.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeDesc {
    /// The geometry.
    pub shape: Shape,
    /// Pose of the shape in the body's model frame. Default identity.
    pub local_pose: Pose,
}

impl ShapeDesc {
    /// A shape at the model frame's origin.
    pub fn new(shape: impl Into<Shape>) -> ShapeDesc {
        ShapeDesc {
            shape: shape.into(),
            local_pose: Pose::IDENTITY,
        }
    }

    /// The same shape at `local_pose` in the model frame.
    pub fn at(mut self, local_pose: Pose) -> ShapeDesc {
        self.local_pose = local_pose;
        self
    }
}

/// How the mass of a dynamic body is given.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MassDesc {
    /// Uniform density of every shape (kg/m^3); mass, centre of mass and
    /// inertia follow from the geometry.
    Density(f64),
    /// Total mass (kg), spread over the shapes in proportion to their volume.
    Mass(f64),
    /// Given outright (as URDF `<inertial>` gives it): mass (kg), centre of
    /// mass (m) and inertia about it (kg m^2), in the model frame; the
    /// shapes then only collide.
    Inertial(tumble_collide::mass::MassProperties),
}

impl Default for MassDesc {
    fn default() -> Self {
        MassDesc::Density(1000.0)
    }
}

/// Surface material. Pair values combine as: friction = sqrt(mu_a mu_b)
/// (geometric mean: equal values give that value, a frictionless surface
/// makes the pair frictionless), restitution = max(e_a, e_b) (a bouncy ball
/// bounces on any floor).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct MaterialDesc {
    /// Coulomb friction coefficient (dimensionless, >= 0). Default 0.5.
    pub friction: f64,
    /// Coefficient of restitution (dimensionless, in [0, 1]). Default 0.
    pub restitution: f64,
}

impl Default for MaterialDesc {
    fn default() -> Self {
        MaterialDesc {
            friction: 0.5,
            restitution: 0.0,
        }
    }
}

impl MaterialDesc {
    /// Friction of a pair (geometric mean).
    pub fn combine_friction(a: f64, b: f64) -> f64 {
        (a * b).sqrt()
    }

    /// Restitution of a pair (maximum).
    pub fn combine_restitution(a: f64, b: f64) -> f64 {
        a.max(b)
    }
}

/// Everything needed to add a body: plain data with a `Default`, usually
/// built with the constructors ([`BodyDesc::dynamic`], [`BodyDesc::fixed`],
/// [`BodyDesc::kinematic`]) and builders.
///
/// ```
/// use tumble::collide::{Capsule, DQuat, DVec3, Pose, Sphere};
/// use tumble::world::{BodyDesc, MassDesc, ShapeDesc, World, WorldSettings};
///
/// let ball = BodyDesc::dynamic(Sphere::new(0.1)?)
///     .at(DVec3::new(0.0, 0.0, 2.0))
///     .with_mass(0.5) // kg; or .with_density(kg/m^3), default 1000
///     .with_material(0.8, 0.6) // friction, restitution
///     .with_velocity(DVec3::new(1.0, 0.0, 0.0), DVec3::ZERO)
///     .named("ball");
/// assert_eq!(ball.mass, MassDesc::Mass(0.5));
///
/// // A compound body: a capsule handle with a ball on its end, lying along x.
/// let lying = Pose::new(DVec3::ZERO, DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2))?;
/// let mut mace = BodyDesc::dynamic(Capsule::new(0.03, 0.3)?).with_pose(lying).named("mace");
/// mace.shapes.push(ShapeDesc::new(Sphere::new(0.1)?).at(Pose::from_translation(DVec3::new(0.0, 0.0, 0.35))));
///
/// let mut world = World::new(WorldSettings::default())?;
/// let ball = world.add_body(&ball)?;
/// let mace = world.add_body(&mace)?;
/// assert_eq!(world.name(ball)?, "ball");
/// // The ball end (model-frame +z) points along world +x: the centre of mass is on that side.
/// assert!(world.center_of_mass(mace)?.x > 0.1);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct BodyDesc {
    /// Dynamic (pushed by forces and contacts), static (never moves, infinite
    /// mass) or kinematic (follows its prescribed velocity, pushes others,
    /// is never pushed). Default dynamic.
    pub kind: BodyKind,
    /// The shapes, each with its pose in the model frame. At least one,
    /// except on a kinematic body or a dynamic one whose mass properties
    /// are given (`MassDesc::Inertial`): a body without shapes touches
    /// nothing and carries its joints (a robot link with an inertia and no
    /// geometry).
    pub shapes: Vec<ShapeDesc>,
    /// Mass or density (dynamic bodies only). Default density 1000 kg/m^3.
    pub mass: MassDesc,
    /// Pose of the model frame in the world. Default identity.
    pub pose: Pose,
    /// Linear velocity of the centre of mass (m/s). Default zero.
    pub linear_velocity: DVec3,
    /// Angular velocity, world frame (rad/s). Default zero.
    pub angular_velocity: DVec3,
    /// Surface material. Default friction 0.5, restitution 0.
    pub material: MaterialDesc,
    /// Linear damping (1/s, >= 0): velocity scaled by 1/(1 + c dt) per step. Default 0.
    pub linear_damping: f64,
    /// Angular damping (1/s, >= 0). Default 0.
    pub angular_damping: f64,
    /// A bullet: always swept by continuous collision, however slowly it
    /// moves, and against dynamic bodies as well as static and kinematic
    /// ones (other bodies that move more than half their thickness in a
    /// step are swept against static and kinematic bodies while
    /// `WorldSettings::continuous` is on). Default false.
    pub ccd: bool,
    /// Bodies that share a nonzero group never touch each other (they still
    /// touch every other body): the links of one robot, whose shapes
    /// overlap where they are jointed and often beyond (`joint::urdf`
    /// gives each robot a group of its own unless asked for self-collision,
    /// as PyBullet does). Default 0: no group.
    pub non_colliding_group: u32,
    /// Optional name (scene files, exports). Default empty.
    pub name: String,
}

impl Default for BodyDesc {
    fn default() -> Self {
        BodyDesc {
            kind: BodyKind::Dynamic,
            shapes: Vec::new(),
            mass: MassDesc::default(),
            pose: Pose::IDENTITY,
            linear_velocity: DVec3::ZERO,
            angular_velocity: DVec3::ZERO,
            material: MaterialDesc::default(),
            linear_damping: 0.0,
            angular_damping: 0.0,
            ccd: false,
            non_colliding_group: 0,
            name: String::new(),
        }
    }
}

impl BodyDesc {
    /// A dynamic body made of one shape.
    pub fn dynamic(shape: impl Into<Shape>) -> BodyDesc {
        BodyDesc {
            shapes: vec![ShapeDesc::new(shape)],
            ..BodyDesc::default()
        }
    }

    /// A static body made of one shape.
    pub fn fixed(shape: impl Into<Shape>) -> BodyDesc {
        BodyDesc {
            kind: BodyKind::Static,
            ..BodyDesc::dynamic(shape)
        }
    }

    /// A kinematic body made of one shape.
    pub fn kinematic(shape: impl Into<Shape>) -> BodyDesc {
        BodyDesc {
            kind: BodyKind::Kinematic,
            ..BodyDesc::dynamic(shape)
        }
    }

    /// Builder: place the model frame at `position` (identity orientation kept).
    pub fn at(mut self, position: DVec3) -> BodyDesc {
        self.pose.position = position;
        self
    }

    /// Builder: the whole pose.
    pub fn with_pose(mut self, pose: Pose) -> BodyDesc {
        self.pose = pose;
        self
    }

    /// Builder: total mass (kg).
    pub fn with_mass(mut self, mass: f64) -> BodyDesc {
        self.mass = MassDesc::Mass(mass);
        self
    }

    /// Builder: density (kg/m^3).
    pub fn with_density(mut self, density: f64) -> BodyDesc {
        self.mass = MassDesc::Density(density);
        self
    }

    /// Builder: friction and restitution.
    pub fn with_material(mut self, friction: f64, restitution: f64) -> BodyDesc {
        self.material = MaterialDesc {
            friction,
            restitution,
        };
        self
    }

    /// Builder: initial velocities (m/s, rad/s world frame).
    pub fn with_velocity(mut self, linear: DVec3, angular: DVec3) -> BodyDesc {
        self.linear_velocity = linear;
        self.angular_velocity = angular;
        self
    }

    /// Builder: always sweep the body for continuous collision.
    pub fn with_ccd(mut self, ccd: bool) -> BodyDesc {
        self.ccd = ccd;
        self
    }

    /// Builder: name.
    pub fn named(mut self, name: impl Into<String>) -> BodyDesc {
        self.name = name.into();
        self
    }
}
