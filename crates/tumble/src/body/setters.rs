//! Validated setters. Each checks all of its input before writing anything, so a body
//! is never left half-updated by an error.

use super::error::BodyError;
use super::material::Material;
use super::rigid_body::RigidBody;
use super::state::{BodyKind, BodyState};
use super::validate::{finite_vec, inverse_inertia, inverse_mass, non_negative, orientation};
use tumble_collide::math::{DQuat, DVec3};
use tumble_collide::Pose;

impl RigidBody {
    fn require(&self, operation: &'static str, expected: BodyKind) -> Result<(), BodyError> {
        if self.kind == expected {
            Ok(())
        } else {
            Err(BodyError::WrongKind {
                operation,
                expected,
                found: self.kind,
            })
        }
    }

    /// Sets the mass (kg, > 0) of a dynamic body, keeping its momentum `P` (so the
    /// velocity changes as `P / M`).
    pub fn set_mass(&mut self, mass: f64) -> Result<(), BodyError> {
        self.require("set_mass", BodyKind::Dynamic)?;
        self.inv_mass = inverse_mass(mass)?;
        Ok(())
    }

    /// Sets the principal moments of inertia (kg m^2, each > 0, triangle inequality) of
    /// a dynamic body, keeping its angular momentum `L`.
    pub fn set_principal_inertia(&mut self, principal_inertia: DVec3) -> Result<(), BodyError> {
        self.require("set_principal_inertia", BodyKind::Dynamic)?;
        self.inv_inertia = inverse_inertia(principal_inertia)?;
        Ok(())
    }

    /// Moves the body frame to `pose` (already validated by [`Pose::new`]); momenta are
    /// kept.
    pub fn set_pose(&mut self, pose: Pose) {
        self.state.position = pose.position;
        self.state.orientation = pose.rotation;
    }

    /// Sets the centre-of-mass position (m).
    pub fn set_position(&mut self, position: DVec3) -> Result<(), BodyError> {
        self.state.position = finite_vec("position", position)?;
        Ok(())
    }

    /// Sets the orientation; it must be a finite unit quaternion within
    /// [`Pose::UNIT_TOLERANCE`] (it is then renormalised exactly).
    pub fn set_orientation(&mut self, rotation: DQuat) -> Result<(), BodyError> {
        self.state.orientation = orientation(rotation)?;
        Ok(())
    }

    /// Replaces the whole state (e.g. from a snapshot). Momenta of static and kinematic
    /// bodies must be zero.
    pub fn set_state(&mut self, state: BodyState) -> Result<(), BodyError> {
        let position = finite_vec("position", state.position)?;
        let rotation = orientation(state.orientation)?;
        let p = finite_vec("linear momentum", state.linear_momentum)?;
        let l = finite_vec("angular momentum", state.angular_momentum)?;
        if self.kind != BodyKind::Dynamic && (p != DVec3::ZERO || l != DVec3::ZERO) {
            self.require("set_state with non-zero momentum", BodyKind::Dynamic)?;
        }
        self.state = BodyState {
            position,
            orientation: rotation,
            linear_momentum: p,
            angular_momentum: l,
        };
        Ok(())
    }

    /// Sets the linear velocity (m/s): `P = M v` for a dynamic body, the prescribed
    /// velocity for a kinematic one; an error for a static body.
    pub fn set_linear_velocity(&mut self, velocity: DVec3) -> Result<(), BodyError> {
        let velocity = finite_vec("linear velocity", velocity)?;
        match self.kind {
            BodyKind::Dynamic => self.state.linear_momentum = velocity / self.inv_mass,
            BodyKind::Kinematic => self.kinematic_velocity = velocity,
            BodyKind::Static => self.require("set_linear_velocity", BodyKind::Dynamic)?,
        }
        Ok(())
    }

    /// Sets the world-frame angular velocity (rad/s): `L = I(t) omega` for a dynamic
    /// body, the prescribed one for a kinematic body; an error for a static body.
    pub fn set_angular_velocity(&mut self, omega: DVec3) -> Result<(), BodyError> {
        let omega = finite_vec("angular velocity", omega)?;
        match self.kind {
            BodyKind::Dynamic => {
                // L = R diag(I_body) R^T omega.
                let q = self.state.orientation;
                let l = q * ((q.conjugate() * omega) / self.inv_inertia);
                self.state.angular_momentum = finite_vec("angular momentum", l)?;
            }
            BodyKind::Kinematic => self.kinematic_angular_velocity = omega,
            BodyKind::Static => self.require("set_angular_velocity", BodyKind::Dynamic)?,
        }
        Ok(())
    }

    /// Sets the linear momentum `P` (kg m/s) of a dynamic body.
    pub fn set_linear_momentum(&mut self, momentum: DVec3) -> Result<(), BodyError> {
        self.require("set_linear_momentum", BodyKind::Dynamic)?;
        self.state.linear_momentum = finite_vec("linear momentum", momentum)?;
        Ok(())
    }

    /// Sets the world-frame angular momentum `L` (kg m^2/s) of a dynamic body.
    pub fn set_angular_momentum(&mut self, momentum: DVec3) -> Result<(), BodyError> {
        self.require("set_angular_momentum", BodyKind::Dynamic)?;
        self.state.angular_momentum = finite_vec("angular momentum", momentum)?;
        Ok(())
    }

    /// Prescribes the motion of a kinematic body: world velocity of the centre of mass
    /// `velocity` (m/s) and world angular velocity `omega` (rad/s), held constant by the
    /// integrator (the pose advances exactly along this screw motion).
    pub fn set_kinematic_velocity(&mut self, velocity: DVec3, omega: DVec3) -> Result<(), BodyError> {
        self.require("set_kinematic_velocity", BodyKind::Kinematic)?;
        let velocity = finite_vec("kinematic velocity", velocity)?;
        let omega = finite_vec("kinematic angular velocity", omega)?;
        self.kinematic_velocity = velocity;
        self.kinematic_angular_velocity = omega;
        Ok(())
    }

    /// Stops the body: both momenta zero (its pose is kept). Cannot fail.
    pub fn stop(&mut self) {
        self.state.linear_momentum = DVec3::ZERO;
        self.state.angular_momentum = DVec3::ZERO;
    }

    /// Sets the surface material.
    pub fn set_material(&mut self, material: Material) {
        self.material = material;
    }

    /// Sets linear and angular damping rates `c` (1/s, each >= 0; default 0).
    ///
    /// After each integration step the momenta are scaled by `1 / (1 + c dt)`: the
    /// implicit-Euler solution of `dv/dt = -c v`, which is unconditionally stable and never
    /// reverses the velocity, and for small `c dt` approaches the exact decay `exp(-c dt)`.
    pub fn set_damping(&mut self, linear: f64, angular: f64) -> Result<(), BodyError> {
        let linear = non_negative("linear damping", linear)?;
        let angular = non_negative("angular damping", angular)?;
        self.linear_damping = linear;
        self.angular_damping = angular;
        Ok(())
    }
}
