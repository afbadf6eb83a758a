//! The contact record every narrow-phase routine produces (thesis 5.2, 7.1).
//!
//! Conventions, shared by the mesh and primitive paths and by the solver:
//! - `normal` is a unit vector pointing from body B towards body A, so that
//!   pushing A along `+normal` and B along `-normal` separates them;
//! - `distance` is the signed separation along the normal: positive is a gap,
//!   negative is penetration depth (speculative contacts have `distance > 0`);
//! - `point` is the world-space midpoint of the two closest points;
//! - features identify what touched on each body so that the solver can match
//!   contacts from one step to the next for warm starting.

use crate::math::DVec3;
use serde::{Deserialize, Serialize};

/// Which pair of features produced a contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum ContactKind {
    /// A vertex of A against a face of B; normal = B's face normal.
    VertexFace,
    /// A face of A against a vertex of B; normal = minus A's face normal.
    FaceVertex,
    /// An edge of A against an edge of B; normal = edge A x edge B, oriented B to A.
    EdgeEdge,
    /// A vertex of A against an edge of B (meshes); normal = the face
    /// normal at the two features nearest the gap between them, distance
    /// = the gap along it (`triangle::tri_vertex_edge`).
    VertexEdge,
    /// An edge of A against a vertex of B (meshes); normal and distance as
    /// for `VertexEdge`.
    EdgeVertex,
    /// A vertex of A against a vertex of B (meshes); normal and distance as
    /// for `VertexEdge`.
    VertexVertex,
    /// Face against face (primitive manifolds: clipped polygon points).
    FaceFace,
    /// Triangles that intersect; the normal is a push-out direction.
    Penetrating,
    /// Smooth primitives (sphere, capsule) where no polyhedral feature applies.
    Smooth,
}

/// A feature of one body: what kind of element, and its index.
///
/// For triangle meshes `index` is the triangle and `sub` the corner (vertex
/// `k`), the edge from corner `k` to `k + 1`, or the face. For primitives the
/// shape defines `index` (e.g. box face 0..6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Feature {
    /// Triangle, face, edge or vertex index within the shape.
    pub index: u32,
    /// What part of `index` is meant.
    pub sub: SubFeature,
}

/// The part of a triangle (or polygon) that a [`Feature`] refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum SubFeature {
    /// Corner `k` (0..3 for triangles).
    Vertex(u8),
    /// Edge from corner `k` to corner `k + 1`.
    Edge(u8),
    /// The face itself.
    Face,
    /// The whole shape (spheres and other smooth primitives).
    Whole,
}

impl Feature {
    /// Corner `k` of triangle `t`.
    pub fn vertex(t: u32, k: u8) -> Feature {
        Feature {
            index: t,
            sub: SubFeature::Vertex(k),
        }
    }
    /// Edge `k` (corner `k` to `k + 1`) of triangle `t`.
    pub fn edge(t: u32, k: u8) -> Feature {
        Feature {
            index: t,
            sub: SubFeature::Edge(k),
        }
    }
    /// Face of triangle or polygon `t`.
    pub fn face(t: u32) -> Feature {
        Feature {
            index: t,
            sub: SubFeature::Face,
        }
    }
    /// The whole of a smooth shape.
    pub const WHOLE: Feature = Feature {
        index: 0,
        sub: SubFeature::Whole,
    };
}

/// One contact point between shape A and shape B, in world coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Contact {
    /// Midpoint of the closest points (m, world frame).
    pub point: DVec3,
    /// Unit normal from B towards A.
    pub normal: DVec3,
    /// Signed separation along `normal` (m): > 0 gap, < 0 penetration.
    pub distance: f64,
    /// Feature pair type.
    pub kind: ContactKind,
    /// Feature on shape A.
    pub feature_a: Feature,
    /// Feature on shape B.
    pub feature_b: Feature,
}

impl Contact {
    /// Penetration depth (m): `-distance`, positive when overlapping.
    pub fn depth(&self) -> f64 {
        -self.distance
    }

    /// The same contact seen from the other side (A and B swapped).
    pub fn flipped(&self) -> Contact {
        let kind = match self.kind {
            ContactKind::VertexFace => ContactKind::FaceVertex,
            ContactKind::FaceVertex => ContactKind::VertexFace,
            ContactKind::VertexEdge => ContactKind::EdgeVertex,
            ContactKind::EdgeVertex => ContactKind::VertexEdge,
            k => k,
        };
        Contact {
            point: self.point,
            normal: -self.normal,
            distance: self.distance,
            kind,
            feature_a: self.feature_b,
            feature_b: self.feature_a,
        }
    }
}
