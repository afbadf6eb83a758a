//! Narrow phase for primitive shapes: contact manifolds for every supported
//! shape pair, routed through one table ([`contact_shapes`] in `dispatch`).
//!
//! Every routine is speculative: it takes a `margin` (m) and reports the
//! contacts whose signed distance is at most `margin` (positive = gap), with
//! the conventions of [`crate::contact`] (normal from B to A, `point` the
//! midpoint of the closest points, stable feature ids). Nothing is allocated
//! per call besides pushing into the caller's `out` vector.
//!
//! Files are named for the shape pair they handle; the polytope routines
//! (cuboid and convex hull) share the SAT and clipping code in `clip` and
//! `contact_polytope_polytope`, the round shapes share `geometry` and `gjk`.
//!
//! Every routine opens with the same six arguments (`a, pose_a, b, pose_b,
//! margin, out`) so that the `dispatch` table and its `mirror` call them all
//! alike; only the two shape types differ, and they stay concrete (or a
//! `Polytope` generic) so each pair compiles to its own specialised code.
//! A trait over shape pairs would save those first lines and nothing else.

mod clip;
mod contact_capsule_capsule;
mod contact_capsule_mesh;
mod contact_cuboid_cuboid;
mod contact_features;
mod contact_halfspace;
mod contact_mesh;
mod contact_polytope_polytope;
mod contact_segment_polytope;
mod contact_sphere_capsule;
mod contact_sphere_cuboid;
mod contact_sphere_sphere;
mod dispatch;
mod geometry;
pub(crate) mod gjk;
mod mesh_pair_memory;
mod polytope_fans;
mod reduce;
mod smooth_foot;

#[cfg(test)]
mod oracle;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_flush;
#[cfg(test)]
pub(crate) mod tests_mesh;

pub use contact_capsule_capsule::contact_capsule_capsule;
pub use contact_capsule_mesh::contact_capsule_mesh;
pub use contact_cuboid_cuboid::contact_cuboid_cuboid;
pub use contact_features::contact_at_features;
pub use contact_halfspace::{
    contact_capsule_halfspace, contact_polytope_halfspace, contact_sphere_halfspace,
};
pub(crate) use contact_mesh::MeshAt;
pub use contact_mesh::{
    contact_mesh_halfspace, contact_mesh_mesh, contact_mesh_mesh_moving, contact_polytope_mesh,
    contact_sphere_mesh,
};
pub use contact_polytope_polytope::contact_polytope_polytope;
pub use contact_segment_polytope::{contact_capsule_polytope, contact_sphere_polytope};
pub use contact_sphere_capsule::contact_sphere_capsule;
pub use contact_sphere_cuboid::contact_sphere_cuboid;
pub use contact_sphere_sphere::contact_sphere_sphere;
pub use dispatch::{contact_shapes, contact_shapes_moving};
pub use mesh_pair_memory::{
    contact_mesh_mesh_from_front, contact_mesh_mesh_recalled, moved_since, MeshPairMemory, Recall,
    RECALL_MAX_REACH, RECALL_SLACK,
};
pub use reduce::{
    reduce_patch, reduce_to_four, KEEP_AREA_FRACTION, KEEP_DEPTH_SLACK, PATCH_DEPTH_BAND, PATCH_MAX_POINTS,
};

use crate::contact::{Contact, ContactKind, Feature};
use crate::math::DVec3;

/// Why a narrow-phase query failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NarrowError {
    /// No routine handles this pair of shapes.
    #[error("no contact routine for the shape pair ({a}, {b})")]
    Unsupported {
        /// Kind of shape A.
        a: &'static str,
        /// Kind of shape B.
        b: &'static str,
    },
    /// The margin is negative, NaN or infinite.
    #[error("contact margin must be finite and >= 0 m, got {0}")]
    BadMargin(f64),
    /// A drift with a NaN or infinite component (origin or translation in
    /// m, rotation vector in rad).
    #[error("contact drift must be finite (origin and translation in m, rotation in rad)")]
    BadDrift,
    /// The contact arithmetic overflowed (dimensions or coordinates near the
    /// limit of f64, e.g. a capsule 1e300 m long): no contact is returned
    /// for the pair rather than a non-finite one.
    #[error("contacts of the shape pair ({a}, {b}) are not finite (dimensions or coordinates beyond the range of f64 arithmetic)")]
    NotFinite {
        /// Kind of shape A.
        a: &'static str,
        /// Kind of shape B.
        b: &'static str,
    },
}

/// Contact between two balls: centres `ca`, `cb` with radii `ra`, `rb` (any
/// of them may be the closest point of a capsule's core segment). Pushes it
/// if the gap is at most `margin`. `fallback` is the normal used when the
/// centres coincide (it must separate the cores, e.g. the common
/// perpendicular of two crossing segments).
#[allow(clippy::too_many_arguments)]
pub(crate) fn push_ball_ball(
    ca: DVec3,
    ra: f64,
    cb: DVec3,
    rb: f64,
    feature_a: Feature,
    feature_b: Feature,
    fallback: DVec3,
    margin: f64,
    out: &mut Vec<Contact>,
) -> bool {
    let d = ca - cb;
    let len = d.length();
    let distance = len - ra - rb;
    if distance > margin {
        return false;
    }
    let normal = if len > 1e-12 * (ra + rb) {
        d / len
    } else {
        fallback
    };
    let pa = ca - normal * ra;
    let pb = cb + normal * rb;
    out.push(Contact {
        point: (pa + pb) * 0.5,
        normal,
        distance,
        kind: ContactKind::Smooth,
        feature_a,
        feature_b,
    });
    true
}

/// Feature of a capsule's core point at segment parameter `t` in [0, 1]:
/// `vertex(0, 0)` / `vertex(0, 1)` for the end spheres, `edge(0, 0)` between.
pub(crate) fn capsule_feature(t: f64) -> Feature {
    if t <= 0.0 {
        Feature::vertex(0, 0)
    } else if t >= 1.0 {
        Feature::vertex(0, 1)
    } else {
        Feature::edge(0, 0)
    }
}
