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
//! - [`hull`]: convex hulls of point sets.
//! - [`bvh`]: the OBBTree: build, box tests, tree-tree and tree-volume traversal.

#![warn(missing_docs)]

pub mod bvh;
pub mod contact;
pub mod hull;
pub mod math;
pub mod mesh;
pub mod pose;

pub use bvh::{ObbTree, TraversalStats, Traverse};
pub use contact::{Contact, ContactKind, Feature, SubFeature};
pub use math::{DMat3, DQuat, DVec3};
pub use mesh::TriMesh;
pub use pose::{Pose, PoseError};
