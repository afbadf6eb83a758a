//! # tumble
//!
//! Rigid body dynamics with exact triangle-mesh contact, built on
//! [`tumble_collide`].
//!
//! - [`body`]: rigid body state, mass properties, material, force accumulators.
//! - [`mod@integrate`]: explicit Euler, midpoint, RK4 and semi-implicit Euler steps.

#![warn(missing_docs)]

pub mod body;
pub mod integrate;

pub use body::{BodyError, BodyKind, BodyState, Material, RigidBody};
pub use integrate::{
    integrate, integrate_with_field, ForceField, IntegrateError, IntegrateReport, Integrator,
};
pub use tumble_collide as collide;

pub mod export;
pub mod scene;
pub mod scenes;
pub mod solver;
pub mod world;
