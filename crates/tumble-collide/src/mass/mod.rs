//! Mass properties: mass, centre of mass and inertia tensor of rigid bodies.
//!
//! - [`MassProperties`]: move, rotate, parallel-axis shift, combine parts,
//!   diagonalise into a [`PrincipalFrame`]; [`to_principal_frame`] re-expresses
//!   a mesh in it (the dynamics' body frame).
//! - [`primitives`]: closed forms for box, sphere, cylinder, capsule, cone and
//!   torus (thesis 3.1), in the frames of the mesh generators.
//! - [`solid_mass_properties`]: exact integrals over a closed mesh (Mirtich
//!   1996, in Eberly's 2002 signed-tetrahedron form).
//! - [`shell_mass_properties`]: thin shells over open or closed surfaces.
//! - [`mesh_mass_properties`] / [`mesh_mass_report`]: the entry point, with an
//!   explicit [`MassFallback`] for meshes that are not solids.

mod error;
mod integrals;
mod mesh_mass;
mod polyhedron;
pub mod primitives;
mod properties;
mod shell;
mod spec;

#[cfg(test)]
mod convergence_tests;
#[cfg(test)]
mod invariance_tests;

pub use error::MassError;
pub use mesh_mass::{mesh_mass_properties, mesh_mass_report, MassFallback, MassMethod, MassReport};
pub use polyhedron::solid_mass_properties;
pub use primitives::{solid_box, solid_capsule, solid_cone, solid_cylinder, solid_sphere, solid_torus};
pub use properties::{to_principal_frame, MassProperties, PrincipalFrame};
pub use shell::shell_mass_properties;
pub use spec::MassSpec;
