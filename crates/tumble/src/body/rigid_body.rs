//! The rigid body record: constructors and derived quantities (thesis 3.2, 6.1.1).
//!
//! Derived quantities follow thesis 3.2: `v = P / M`, `I^-1(t) = R I_body^-1 R^T`,
//! `omega = I^-1(t) L`. Because the body frame is the principal frame, `I_body^-1` is
//! the diagonal `inv_inertia`, and `I^-1(t) L` is evaluated as `q (inv_inertia * (q^-1 L))`
//! (two quaternion rotations, no 3x3 matrix).

use super::error::BodyError;
use super::material::Material;
use super::state::{BodyKind, BodyState};
use super::validate::{finite_vec, inverse_inertia, inverse_mass};
use tumble_collide::math::{sym_eigen, DMat3, DQuat, DVec3};
use tumble_collide::Pose;

/// A rigid body: state `(x, q, P, L)`, constant mass properties, material, damping and
/// force accumulators.
///
/// Fields are private so that every value that gets in is validated; read them through
/// the accessors. The hot fields used by the integrators come first.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidBody {
    pub(crate) state: BodyState,
    /// `1 / M` (1/kg); 0 for static and kinematic bodies.
    pub(crate) inv_mass: f64,
    /// Inverse principal moments `1 / I_i` (1/(kg m^2)); zero for static/kinematic.
    pub(crate) inv_inertia: DVec3,
    /// Accumulated force through the centre of mass (N).
    pub(crate) force: DVec3,
    /// Accumulated torque about the centre of mass (N m).
    pub(crate) torque: DVec3,
    /// Linear damping rate (1/s).
    pub(crate) linear_damping: f64,
    /// Angular damping rate (1/s).
    pub(crate) angular_damping: f64,
    /// Prescribed world velocity of a kinematic body (m/s).
    pub(crate) kinematic_velocity: DVec3,
    /// Prescribed world angular velocity of a kinematic body (rad/s).
    pub(crate) kinematic_angular_velocity: DVec3,
    pub(crate) kind: BodyKind,
    pub(crate) material: Material,
}

impl RigidBody {
    fn with_kind(kind: BodyKind, pose: Pose, inv_mass: f64, inv_inertia: DVec3) -> RigidBody {
        RigidBody {
            state: BodyState::at_rest(pose),
            inv_mass,
            inv_inertia,
            force: DVec3::ZERO,
            torque: DVec3::ZERO,
            linear_damping: 0.0,
            angular_damping: 0.0,
            kinematic_velocity: DVec3::ZERO,
            kinematic_angular_velocity: DVec3::ZERO,
            kind,
            material: Material::default(),
        }
    }

    /// A dynamic body at rest with mass `mass` (kg, > 0) and principal moments of inertia
    /// `principal_inertia` (kg m^2, each > 0, satisfying the triangle inequality) about
    /// the axes of the body frame, whose origin is the centre of mass at `pose`.
    pub fn new_dynamic(mass: f64, principal_inertia: DVec3, pose: Pose) -> Result<RigidBody, BodyError> {
        let inv_mass = inverse_mass(mass)?;
        let inv_inertia = inverse_inertia(principal_inertia)?;
        Ok(Self::with_kind(BodyKind::Dynamic, pose, inv_mass, inv_inertia))
    }

    /// A dynamic body at rest from a full inertia tensor `inertia` (kg m^2, about the
    /// centre of mass, expressed in the axes of the frame `frame`, whose origin is the
    /// centre of mass).
    ///
    /// The tensor is diagonalised (Jacobi, [`sym_eigen`]) and the body frame becomes the
    /// principal frame: the body's orientation is `frame.rotation * V`, with `V` the
    /// rotation whose columns are the principal axes in `frame`'s axes. `V` is returned
    /// too, so that geometry given in `frame` can be re-expressed in the body frame as
    /// `V^-1 p`. The tensor must be finite and symmetric (relative asymmetry <= 1e-9),
    /// with eigenvalues that pass the checks of [`RigidBody::new_dynamic`].
    pub fn new_dynamic_from_tensor(
        mass: f64,
        inertia: DMat3,
        frame: Pose,
    ) -> Result<(RigidBody, DQuat), BodyError> {
        for (what, col) in [
            ("inertia tensor column 0", inertia.x_axis),
            ("inertia tensor column 1", inertia.y_axis),
            ("inertia tensor column 2", inertia.z_axis),
        ] {
            finite_vec(what, col)?;
        }
        let asym = tumble_collide::math::max_abs_diff_mat(&inertia, &inertia.transpose());
        let scale = inertia.to_cols_array().iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if asym > 1e-9 * scale {
            return Err(BodyError::AsymmetricInertia(asym));
        }
        let (moments, axes) = sym_eigen(&inertia);
        let v = DQuat::from_mat3(&axes).normalize();
        let pose = Pose {
            position: frame.position,
            rotation: (frame.rotation * v).normalize(),
        };
        Ok((Self::new_dynamic(mass, moments, pose)?, v))
    }

    /// A static body (infinite mass, never moves) at `pose`.
    pub fn new_static(pose: Pose) -> RigidBody {
        Self::with_kind(BodyKind::Static, pose, 0.0, DVec3::ZERO)
    }

    /// A kinematic body at `pose`, initially at rest; give it a motion with
    /// [`RigidBody::set_kinematic_velocity`].
    pub fn new_kinematic(pose: Pose) -> RigidBody {
        Self::with_kind(BodyKind::Kinematic, pose, 0.0, DVec3::ZERO)
    }

    /// How the body moves.
    pub fn kind(&self) -> BodyKind {
        self.kind
    }

    /// The integrated state `(x, q, P, L)`.
    pub fn state(&self) -> &BodyState {
        &self.state
    }

    /// Pose of the body (principal) frame.
    pub fn pose(&self) -> Pose {
        self.state.pose()
    }

    /// Position of the centre of mass (m).
    pub fn position(&self) -> DVec3 {
        self.state.position
    }

    /// Orientation of the principal frame, unit quaternion (x, y, z, w).
    pub fn orientation(&self) -> DQuat {
        self.state.orientation
    }

    /// Linear momentum `P` (kg m/s); zero for static and kinematic bodies.
    pub fn linear_momentum(&self) -> DVec3 {
        self.state.linear_momentum
    }

    /// Angular momentum about the centre of mass `L` (kg m^2/s, world frame); zero for
    /// static and kinematic bodies.
    pub fn angular_momentum(&self) -> DVec3 {
        self.state.angular_momentum
    }

    /// Inverse mass (1/kg); 0 for static and kinematic bodies.
    pub fn inv_mass(&self) -> f64 {
        self.inv_mass
    }

    /// Mass (kg); `f64::INFINITY` for static and kinematic bodies.
    pub fn mass(&self) -> f64 {
        if self.inv_mass > 0.0 {
            1.0 / self.inv_mass
        } else {
            f64::INFINITY
        }
    }

    /// Inverse principal moments of inertia (1/(kg m^2)), body frame; zero for static and
    /// kinematic bodies.
    pub fn inv_principal_inertia(&self) -> DVec3 {
        self.inv_inertia
    }

    /// Principal moments of inertia (kg m^2), body frame; infinite for static and
    /// kinematic bodies.
    pub fn principal_inertia(&self) -> DVec3 {
        let inv = self.inv_inertia;
        let f = |i: f64| if i > 0.0 { 1.0 / i } else { f64::INFINITY };
        DVec3::new(f(inv.x), f(inv.y), f(inv.z))
    }

    /// World-frame inverse inertia tensor `I^-1(t) = R diag(I_body^-1) R^T` (1/(kg m^2)).
    pub fn inv_inertia_world(&self) -> DMat3 {
        let r = DMat3::from_quat(self.state.orientation);
        r * DMat3::from_diagonal(self.inv_inertia) * r.transpose()
    }

    /// Linear velocity of the centre of mass `v = P / M` (m/s); the prescribed velocity
    /// for kinematic bodies, zero for static ones.
    pub fn velocity(&self) -> DVec3 {
        match self.kind {
            BodyKind::Dynamic => self.state.linear_momentum * self.inv_mass,
            BodyKind::Static => DVec3::ZERO,
            BodyKind::Kinematic => self.kinematic_velocity,
        }
    }

    /// World-frame angular velocity `omega = I^-1(t) L` (rad/s); the prescribed one for
    /// kinematic bodies, zero for static ones.
    pub fn angular_velocity(&self) -> DVec3 {
        match self.kind {
            BodyKind::Dynamic => angular_velocity_of(
                self.state.orientation,
                self.inv_inertia,
                self.state.angular_momentum,
            ),
            BodyKind::Static => DVec3::ZERO,
            BodyKind::Kinematic => self.kinematic_angular_velocity,
        }
    }

    /// Velocity of the material point currently at world point `p`: `v + omega x (p - x)`
    /// (m/s).
    pub fn velocity_at_point(&self, p: DVec3) -> DVec3 {
        self.velocity() + self.angular_velocity().cross(p - self.state.position)
    }

    /// Kinetic energy `|P|^2 / 2M + L . omega / 2` (J); zero for static and kinematic
    /// bodies (their energy is not part of the simulated system).
    pub fn kinetic_energy(&self) -> f64 {
        if self.kind != BodyKind::Dynamic {
            return 0.0;
        }
        let p = self.state.linear_momentum;
        let l = self.state.angular_momentum;
        0.5 * (p.length_squared() * self.inv_mass + l.dot(self.angular_velocity()))
    }

    /// Accumulated force through the centre of mass (N), not including gravity.
    pub fn force(&self) -> DVec3 {
        self.force
    }

    /// Accumulated torque about the centre of mass (N m).
    pub fn torque(&self) -> DVec3 {
        self.torque
    }

    /// Linear damping rate (1/s); see [`RigidBody::set_damping`].
    pub fn linear_damping(&self) -> f64 {
        self.linear_damping
    }

    /// Angular damping rate (1/s); see [`RigidBody::set_damping`].
    pub fn angular_damping(&self) -> f64 {
        self.angular_damping
    }

    /// Surface material.
    pub fn material(&self) -> Material {
        self.material
    }

    /// Prescribed `(velocity (m/s), angular velocity (rad/s))` of a kinematic body; zero
    /// for other kinds.
    pub fn kinematic_velocity(&self) -> (DVec3, DVec3) {
        (self.kinematic_velocity, self.kinematic_angular_velocity)
    }
}

/// `omega = R diag(inv_inertia) R^T L` for a possibly non-unit quaternion `q` (RK
/// stages are not unit).
///
/// Why no normalisation: the sandwich `q v q*`, which glam evaluates as
/// `(w² - b·b) v + 2 (b·v) b + 2 w (b × v)` for `q = (b, w)`, equals `|q|² R v` for any
/// quaternion, so two sandwiches give `|q|⁴ R diag R^T L`, and one division by `|q|⁴`
/// (no square root) recovers omega.
#[inline(always)]
pub(crate) fn angular_velocity_of(q: DQuat, inv_inertia: DVec3, l: DVec3) -> DVec3 {
    let len2 = q.length_squared();
    (q * (inv_inertia * (q.conjugate() * l))) * (1.0 / (len2 * len2))
}
