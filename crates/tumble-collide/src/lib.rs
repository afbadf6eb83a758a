//! # tumble-collide
//!
//! Geometry and collision detection for rigid bodies, usable on its own: the
//! modern form of the thesis' JAOC library (thesis ch. 4-5). It knows nothing of
//! dynamics or time.
//!
//! - [`math`]: glam f64 types and the helpers glam lacks (symmetric eigen, skew).
//! - [`pose`]: validated rigid poses.
//! - [`mesh`]: validated triangle meshes, topology, generators, OBJ/STL loaders.
//! - [`contact`]: the contact record shared by every narrow-phase routine.
//! - [`drift`]: a small rigid displacement, for queries that look ahead over a step.
//! - [`hull`]: convex hulls of point sets.
//! - [`bvh`]: the OBBTree: build, box tests, tree-tree and tree-volume traversal.
//! - [`broad`]: sweep-and-prune broad phase over AABBs with persistent pairs.
//! - [`mass`]: mass properties of primitives, meshes and composite bodies.
//! - [`triangle`]: triangle-level narrow phase (overlap, distance, contacts, merging).
//! - [`shape`]: primitive shapes (sphere, cuboid, capsule, convex hull, half-space).
//! - [`narrow`]: contact manifolds between shape pairs, one dispatch table.
//! - [`query`]: the public collision, distance and tolerance queries on meshes
//!   and primitives, and the time of impact of moving shapes (see `docs/collision.md`).

#![warn(missing_docs)]

pub mod broad;
pub mod bvh;
pub mod contact;
pub mod drift;
pub mod hull;
pub mod mass;
pub mod math;
pub mod mesh;
pub mod narrow;
pub mod pose;
pub mod query;
pub mod shape;
pub mod triangle;

pub use broad::{Aabb, PairEvent, ProxyId, SweepAndPrune};
pub use bvh::{ObbTree, TraversalStats, Traverse};
pub use contact::{Contact, ContactKind, Feature, SubFeature};
pub use drift::Drift;
pub use mass::{mesh_mass_properties, MassError, MassFallback, MassProperties, MassSpec, PrincipalFrame};
pub use math::{DMat3, DQuat, DVec3};
pub use mesh::TriMesh;
pub use narrow::{contact_shapes, NarrowError};
pub use pose::{Pose, PoseError};
pub use query::{
    collide, collide_primitive, distance, distance_primitive, time_of_impact, within_tolerance,
    within_tolerance_primitive, CollideOptions, DistanceOptions, DistanceResult, Impact, Motion, QueryError,
    QueryStats, Report, ReportMode, ToiOptions, ToiStats,
};
pub use shape::{Capsule, ConvexHull, Cuboid, HalfSpace, MeshShape, Shape, ShapeError, Sphere};
