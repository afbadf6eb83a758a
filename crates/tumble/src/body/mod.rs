//! Rigid bodies: state, mass properties, material, force accumulators.
//!
//! Follows the thesis' rigid body library (ch. 3.2 and 6.1.1) and Baraff & Witkin,
//! "Physically Based Modeling" (SIGGRAPH 97), "Rigid Body Dynamics" notes: the state is
//! `(x, q, P, L)` in the world frame, mass and body-frame inertia are constants stored as
//! inverses (inverse mass 0 = infinite mass), and velocities are derived from momenta.
//!
//! - [`BodyState`]: the ODE state `(x, q, P, L)` that integrators advance.
//! - [`RigidBody`]: state + constants + accumulators, with validated constructors and setters.
//! - [`Material`]: restitution and friction coefficients.
//! - [`BodyError`]: why a constructor or setter rejected its input.

mod error;
mod forces;
mod material;
mod rigid_body;
mod setters;
mod state;
mod validate;

#[cfg(test)]
mod tests;

pub use error::BodyError;
pub use material::Material;
pub(crate) use rigid_body::angular_velocity_of;
pub use rigid_body::RigidBody;
pub use state::{BodyKind, BodyState};
