//! Primitive collision shapes (design map: `shape`): sphere, cuboid, capsule,
//! convex hull and half-space, each validated at construction, with world
//! bounding boxes for a pose and support functions (Ericson, "Real-Time
//! Collision Detection", 3.8 and 9.2) used by the narrow phase; and triangle
//! meshes with their OBBTrees ([`MeshShape`]), optionally with the smooth
//! surface they tessellate ([`SmoothSurface`]).
//!
//! Every shape is described in its own body frame; a [`crate::Pose`] places
//! it in the world. Cuboids and convex hulls share the [`Polytope`] view so
//! that the SAT, clipping and GJK routines in [`crate::narrow`] are written
//! once for both.

mod aabb;
mod capsule;
mod convex_hull;
mod cuboid;
mod halfspace;
mod mesh_shape;
mod polytope;
mod serde_parts;
mod smooth_surface;
mod sphere;

pub use aabb::Aabb;
pub use capsule::Capsule;
pub use convex_hull::{ConvexHull, HullEdge, HullFace, MAX_FACE_VERTICES};
pub use cuboid::Cuboid;
pub use halfspace::HalfSpace;
pub use mesh_shape::MeshShape;
pub use polytope::Polytope;
pub use smooth_surface::SmoothSurface;
pub use sphere::Sphere;

#[cfg(test)]
pub(crate) mod tests;

use crate::hull::HullError;
use crate::math::DVec3;
use crate::mesh::MeshError;
use crate::pose::Pose;

/// Why a shape could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShapeError {
    /// A dimension is NaN, infinite, zero or negative (or negative where zero
    /// is allowed), or beyond [`MAX_DIMENSION`].
    #[error("{shape}: {name} must be finite and {expected}, got {value}")]
    BadDimension {
        /// Which shape.
        shape: &'static str,
        /// Which parameter.
        name: &'static str,
        /// What was expected ("> 0", ">= 0", "<= 1e36 (MAX_DIMENSION)", ...).
        expected: &'static str,
        /// The value given.
        value: f64,
    },
    /// A direction that must be a unit vector is not finite or not of unit length.
    #[error("{shape}: {name} must be a finite unit vector, got {value:?} (length {length})")]
    NotUnit {
        /// Which shape.
        shape: &'static str,
        /// Which parameter.
        name: &'static str,
        /// The value given.
        value: DVec3,
        /// Its length.
        length: f64,
    },
    /// The mesh given to a convex hull is not a valid closed solid.
    #[error("convex hull: mesh is not a closed solid: {0}")]
    Mesh(#[from] MeshError),
    /// A triangle of the mesh has (almost) no area, so its plane is undefined.
    #[error("convex hull: triangle {triangle} is degenerate (zero area); remove it first")]
    DegenerateTriangle {
        /// Index of the triangle in the mesh.
        triangle: usize,
    },
    /// A vertex lies outside the plane of a face by more than the tolerance.
    #[error("convex hull: mesh is not convex: vertex {vertex} is {excess:e} m outside the plane of face {face} (tolerance {tolerance:e} m)")]
    NotConvex {
        /// Face (merged polygon) whose plane is violated.
        face: usize,
        /// Mesh vertex outside it.
        vertex: usize,
        /// Distance outside the plane (m).
        excess: f64,
        /// The tolerance used (m).
        tolerance: f64,
    },
    /// A merged face has more corners than the narrow phase's fixed buffers hold.
    #[error("convex hull: face {face} has {count} corners, at most {max} are supported")]
    FaceTooLarge {
        /// Face index.
        face: usize,
        /// Its number of corners.
        count: usize,
        /// [`MAX_FACE_VERTICES`].
        max: usize,
    },
    /// Merging coplanar triangles did not give a simple polygon boundary.
    #[error("convex hull: the coplanar triangles of face {face} do not form a single polygon")]
    BadFace {
        /// Face index.
        face: usize,
    },
    /// The OBBTree of a mesh shape could not be built.
    #[error("mesh shape: {0}")]
    Bvh(String),
    /// Building the hull of a point set failed.
    #[error("convex hull of points failed: {0}")]
    Hull(#[from] HullError),
}

/// Largest dimension of a shape (m): a radius, half extent, half height,
/// a hull's vertex coordinate or a half-space's offset. The OBBTree's
/// coordinate limit ([`crate::bvh::MAX_COORDINATE`], which bounds a mesh's
/// vertices): beyond it a shape's boxes, mass and contact distances
/// overflow (a sphere of radius 1.8e308 m gave contacts at 1e307 m,
/// 1.8e308 m deep; libFuzzer's `world_step`).
pub const MAX_DIMENSION: f64 = crate::bvh::MAX_COORDINATE;

/// Whether `x` is finite and at most [`MAX_DIMENSION`] from 0: the one
/// test of the limit (dimensions, hull coordinates, half-space offsets).
pub(crate) fn within_dimension_limit(x: f64) -> bool {
    x.is_finite() && x.abs() <= MAX_DIMENSION
}

// `mass::primitives::dim` and `mesh::generators::dim` make the same test but
// return `MassError` / `GeneratorError`: those modules take bare numbers, not
// shapes, and each reports in its own error type (a generated mesh beyond
// the limit is refused when its tree is built).
pub(crate) fn check_positive(shape: &'static str, name: &'static str, value: f64) -> Result<(), ShapeError> {
    check_dimension(shape, name, value, value > 0.0, "> 0")
}

/// [`check_positive`]'s `>= 0` form (a capsule's half height, a tolerance:
/// zero is valid).
pub(crate) fn check_non_negative(
    shape: &'static str,
    name: &'static str,
    value: f64,
) -> Result<(), ShapeError> {
    check_dimension(shape, name, value, value >= 0.0, ">= 0")
}

fn check_dimension(
    shape: &'static str,
    name: &'static str,
    value: f64,
    in_range: bool,
    expected: &'static str,
) -> Result<(), ShapeError> {
    if in_range && within_dimension_limit(value) {
        Ok(())
    } else {
        Err(ShapeError::BadDimension {
            shape,
            name,
            // Named by the bound it breaks.
            expected: if value.is_finite() && in_range {
                "<= 1e36 (MAX_DIMENSION)"
            } else {
                expected
            },
            value,
        })
    }
}

/// A collision shape: the primitives, convex hulls, the half-space and
/// triangle meshes. Non-exhaustive (new kinds may come), so matches outside
/// this crate need a wildcard arm.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Shape {
    /// A ball.
    Sphere(Sphere),
    /// A box.
    Cuboid(Cuboid),
    /// A capsule along the body z axis.
    Capsule(Capsule),
    /// A convex polyhedron.
    ConvexHull(ConvexHull),
    /// An infinite solid below a plane (ground).
    HalfSpace(HalfSpace),
    /// A triangle mesh with its OBBTree (concave allowed).
    Mesh(MeshShape),
}

// The matches below repeat one arm per variant on purpose: plain enum
// dispatch to each shape's own method, with the exceptions (a half-space has
// no support point) visible where they apply.
impl Shape {
    /// A short name of the variant, for error messages.
    pub fn kind_name(&self) -> &'static str {
        match self {
            Shape::Sphere(_) => "sphere",
            Shape::Cuboid(_) => "cuboid",
            Shape::Capsule(_) => "capsule",
            Shape::ConvexHull(_) => "convex_hull",
            Shape::HalfSpace(_) => "half_space",
            Shape::Mesh(_) => "mesh",
        }
    }

    /// World-space bounding box of the shape placed at `pose` (unbounded axes of
    /// a half-space are infinite).
    pub fn aabb(&self, pose: &Pose) -> Aabb {
        match self {
            Shape::Sphere(s) => s.aabb(pose),
            Shape::Cuboid(s) => s.aabb(pose),
            Shape::Capsule(s) => s.aabb(pose),
            Shape::ConvexHull(s) => s.aabb(pose),
            Shape::HalfSpace(s) => s.aabb(pose),
            Shape::Mesh(s) => s.aabb(pose),
        }
    }

    /// Support point in the body frame: a point of the shape farthest along the
    /// body-frame direction `dir`. `None` for a half-space (unbounded).
    pub fn support(&self, dir: DVec3) -> Option<DVec3> {
        match self {
            Shape::Sphere(s) => Some(s.support(dir)),
            Shape::Cuboid(s) => Some(s.support(dir)),
            Shape::Capsule(s) => Some(s.support(dir)),
            Shape::ConvexHull(s) => Some(s.support(dir)),
            Shape::HalfSpace(_) => None,
            Shape::Mesh(s) => Some(s.support(dir)),
        }
    }

    /// The radius of the round surface every contact of the shape lies on
    /// (m): a sphere's or a capsule's radius, 0 for shapes whose contacts
    /// are at faces, edges and corners. A round shape rolls: the point it
    /// touches with is not a material point but the one nearest the other
    /// body, a radius from a centre of curvature fixed in it (the solver
    /// follows that point within a step).
    pub fn rolling_radius(&self) -> f64 {
        match self {
            Shape::Sphere(s) => s.radius(),
            Shape::Capsule(s) => s.radius(),
            Shape::Cuboid(_) | Shape::ConvexHull(_) | Shape::HalfSpace(_) | Shape::Mesh(_) => 0.0,
        }
    }
}

// One `From` per variant, alike by design: each wraps a different type in a
// different variant, which no blanket impl can express; a macro would save
// a dozen trivial lines and hide the list of shapes.
impl From<Sphere> for Shape {
    fn from(s: Sphere) -> Shape {
        Shape::Sphere(s)
    }
}
impl From<Cuboid> for Shape {
    fn from(s: Cuboid) -> Shape {
        Shape::Cuboid(s)
    }
}
impl From<Capsule> for Shape {
    fn from(s: Capsule) -> Shape {
        Shape::Capsule(s)
    }
}
impl From<ConvexHull> for Shape {
    fn from(s: ConvexHull) -> Shape {
        Shape::ConvexHull(s)
    }
}
impl From<MeshShape> for Shape {
    fn from(s: MeshShape) -> Shape {
        Shape::Mesh(s)
    }
}
impl From<HalfSpace> for Shape {
    fn from(s: HalfSpace) -> Shape {
        Shape::HalfSpace(s)
    }
}
