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
//!
//! ```
//! use tumble_collide::mass::{mesh_mass_properties, solid_box, MassFallback, MassSpec};
//! use tumble_collide::mesh::box_mesh;
//! use tumble_collide::DVec3;
//!
//! let half = DVec3::new(0.5, 0.25, 0.1); // m
//! let steel = MassSpec::Density(7850.0); // kg/m^3
//! let mesh = box_mesh(half)?;
//! let props = mesh_mass_properties(&mesh, steel, MassFallback::None)?;
//! let exact = solid_box(half, steel)?;
//! assert!((props.mass - exact.mass).abs() < 1e-9 * exact.mass); // 785 kg
//! // Body frame for the dynamics: centre of mass + principal axes.
//! let frame = props.principal();
//! assert!(frame.moments.x <= frame.moments.y && frame.moments.y <= frame.moments.z);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

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
