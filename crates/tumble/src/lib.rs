//! # tumble
//!
//! Rigid body dynamics with exact triangle-mesh contact, built on
//! [`tumble_collide`].
//!
//! - [`world`]: the [`World`](world::World): bodies described by
//!   [`BodyDesc`](world::BodyDesc), stepped by [`World::step`](world::World::step).
//! - [`scene`]: scene files (TOML/JSON) to worlds; [`scenes`]: the standard scenes.
//! - [`batch`]: many independent worlds stepped at once on every core;
//!   [`sweep`]: parameter sweeps over scene files.
//! - [`export`]: recordings, animated glTF, CSV and NumPy trajectories.
//! - [`analytic`]: closed-form references (elliptic integrals, the
//!   torque-free top) shared by tests, demos and benchmarks.
//! - [`body`]: rigid body state, mass properties, material, force accumulators.
//! - [`mod@integrate`]: explicit Euler, midpoint, RK4 and semi-implicit Euler steps.
//! - [`solver`]: the contact solvers (sub-stepped PGS, Lemke, dense LCPs).
//!
//! The user manual is `docs/manual` (an mdBook; `bash scripts/manual.sh`).
//!
//! # Quick start
//!
//! A ball dropped from 1 m onto the ground: it falls freely, as
//! `z = z0 - g t^2 / 2`, until it lands, then rests on the ground.
//!
//! ```
//! use tumble::collide::{DVec3, HalfSpace, Sphere};
//! use tumble::world::{BodyDesc, World, WorldSettings};
//!
//! let mut world = World::new(WorldSettings::default())?;
//! world.add_body(&BodyDesc::fixed(HalfSpace::new(DVec3::Z, 0.0)?).named("ground"))?;
//! let ball = world.add_body(
//!     &BodyDesc::dynamic(Sphere::new(0.1)?)
//!         .at(DVec3::new(0.0, 0.0, 1.0))
//!         .with_mass(1.0)
//!         .named("ball"),
//! )?;
//!
//! for _ in 0..12 {
//!     world.step(); // 0.2 s of free fall
//! }
//! let t = world.time();
//! let z = world.center_of_mass(ball)?.z;
//! assert!((z - (1.0 - 0.5 * 9.81 * t * t)).abs() < 0.01);
//!
//! for _ in 0..108 {
//!     world.step(); // 1.8 s more: landed and at rest
//! }
//! let z = world.center_of_mass(ball)?.z;
//! assert!((z - 0.1).abs() < 1e-3, "resting on the ground at z = {z}");
//! assert!(world.linear_velocity(ball)?.length() < 1e-3);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![warn(missing_docs)]

pub mod analytic;
pub mod batch;
pub mod body;
pub mod integrate;

pub use body::{BodyError, BodyKind, BodyState, Material, RigidBody};
pub use integrate::{
    integrate, integrate_with_field, ForceField, IntegrateError, IntegrateReport, Integrator,
};
pub use tumble_collide as collide;

pub mod export;
pub(crate) mod pool;
pub mod scene;
pub mod scenes;
pub mod sweep;
// The module's own docs link `lemke` and `pgs`, each both a module and a
// function (rustdoc: ambiguous link). The solver is being reworked; until its
// docs say `mod@lemke` / `mod@pgs`, the ambiguity is allowed here so that
// `RUSTDOCFLAGS=-D warnings cargo doc` (make doc) passes.
pub mod joint;
#[allow(rustdoc::broken_intra_doc_links)]
pub mod solver;
pub mod world;
