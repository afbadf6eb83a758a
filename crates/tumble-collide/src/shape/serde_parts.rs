//! Serde forms of the primitive shapes and convex hulls, for world
//! snapshots: each shape is written as its defining numbers and read back
//! through the same checks as its constructor, so a corrupt or hand-edited
//! file gives a typed error, never an invalid shape. Values are kept bit for
//! bit (no renormalisation on the way back in), so that a restored world
//! continues exactly as the saved one would have.
//!
//! The Parts types and their `From` / `TryFrom` pairs read alike, one per
//! shape, on purpose: each shape's serde attribute must name a type of its
//! own, and the fields and the checks on the way in differ per shape.

use super::convex_hull::{HullEdge, HullFace, MAX_FACE_VERTICES};
use super::{Capsule, ConvexHull, Cuboid, HalfSpace, ShapeError, Sphere};
use crate::math::DVec3;
use serde::{Deserialize, Serialize};

#[derive(Serialize, Deserialize)]
pub(crate) struct SphereParts {
    radius: f64,
}

impl From<Sphere> for SphereParts {
    fn from(s: Sphere) -> Self {
        SphereParts { radius: s.radius() }
    }
}

impl TryFrom<SphereParts> for Sphere {
    type Error = ShapeError;
    fn try_from(p: SphereParts) -> Result<Sphere, ShapeError> {
        Sphere::new(p.radius)
    }
}

#[derive(Serialize, Deserialize)]
pub(crate) struct CuboidParts {
    half_extents: DVec3,
}

impl From<Cuboid> for CuboidParts {
    fn from(c: Cuboid) -> Self {
        CuboidParts {
            half_extents: c.half_extents(),
        }
    }
}

impl TryFrom<CuboidParts> for Cuboid {
    type Error = ShapeError;
    fn try_from(p: CuboidParts) -> Result<Cuboid, ShapeError> {
        Cuboid::new(p.half_extents)
    }
}

#[derive(Serialize, Deserialize)]
pub(crate) struct CapsuleParts {
    radius: f64,
    half_height: f64,
}

impl From<Capsule> for CapsuleParts {
    fn from(c: Capsule) -> Self {
        CapsuleParts {
            radius: c.radius(),
            half_height: c.half_height(),
        }
    }
}

impl TryFrom<CapsuleParts> for Capsule {
    type Error = ShapeError;
    fn try_from(p: CapsuleParts) -> Result<Capsule, ShapeError> {
        Capsule::new(p.radius, p.half_height)
    }
}

#[derive(Serialize, Deserialize)]
pub(crate) struct HalfSpaceParts {
    normal: DVec3,
    offset: f64,
}

// The same From / TryFrom pair as `CapsuleParts` above (see the module
// note), but the way in keeps the normal as stored, not renormalised.
impl From<HalfSpace> for HalfSpaceParts {
    fn from(h: HalfSpace) -> Self {
        HalfSpaceParts {
            normal: h.normal(),
            offset: h.offset(),
        }
    }
}

impl TryFrom<HalfSpaceParts> for HalfSpace {
    type Error = ShapeError;
    fn try_from(p: HalfSpaceParts) -> Result<HalfSpace, ShapeError> {
        // Same checks as `HalfSpace::new`, but the stored (already unit)
        // normal is kept as it is: dividing it by its length again could
        // change its last bit.
        HalfSpace::new(p.normal, p.offset)?;
        Ok(HalfSpace::from_raw(p.normal, p.offset))
    }
}

/// A convex hull as its vertices, faces (plane + corner range), corner
/// indices and edges; the derived vertex features and centroid are
/// recomputed on the way in.
#[derive(Serialize, Deserialize)]
pub(crate) struct HullParts {
    vertices: Vec<DVec3>,
    /// `(normal, offset, start, len)` per face.
    faces: Vec<(DVec3, f64, u32, u32)>,
    corners: Vec<u32>,
    /// `(vertices, faces)` per edge.
    edges: Vec<([u32; 2], [u32; 2])>,
}

impl From<ConvexHull> for HullParts {
    fn from(h: ConvexHull) -> Self {
        HullParts {
            vertices: h.vertices().to_vec(),
            faces: h
                .faces()
                .iter()
                .map(|f| (f.normal, f.offset, f.start, f.len))
                .collect(),
            corners: h.corners().to_vec(),
            edges: h.edges().iter().map(|e| (e.vertices, e.faces)).collect(),
        }
    }
}

impl TryFrom<HullParts> for ConvexHull {
    type Error = ShapeError;
    fn try_from(p: HullParts) -> Result<ConvexHull, ShapeError> {
        let bad = |name: &'static str, value: f64| ShapeError::BadDimension {
            shape: "convex_hull",
            name,
            expected: "consistent with the hull (index in range, finite)",
            value,
        };
        let nv = p.vertices.len();
        if nv < 4 || p.faces.len() < 4 || p.edges.len() < 6 {
            return Err(bad("vertex count", nv as f64));
        }
        if let Some(v) = p.vertices.iter().find(|v| !v.is_finite()) {
            return Err(bad("vertex", v.max_element()));
        }
        if let Some(&c) = p.corners.iter().find(|&&c| c as usize >= nv) {
            return Err(bad("corner index", c as f64));
        }
        let mut faces = Vec::with_capacity(p.faces.len());
        for &(normal, offset, start, len) in &p.faces {
            let length = normal.length();
            if !normal.is_finite() || (length - 1.0).abs() > 1e-6 || !offset.is_finite() {
                return Err(ShapeError::NotUnit {
                    shape: "convex_hull",
                    name: "face normal",
                    value: normal,
                    length,
                });
            }
            let end = start as u64 + len as u64;
            if len < 3 || len as usize > MAX_FACE_VERTICES || end > p.corners.len() as u64 {
                return Err(bad("face corner range", end as f64));
            }
            faces.push(HullFace {
                normal,
                offset,
                start,
                len,
            });
        }
        let nf = faces.len() as u32;
        let mut edges = Vec::with_capacity(p.edges.len());
        for &(vertices, ef) in &p.edges {
            if vertices.iter().any(|&v| v as usize >= nv) || ef.iter().any(|&f| f >= nf) {
                return Err(bad("edge index", vertices[0].max(vertices[1]) as f64));
            }
            edges.push(HullEdge { vertices, faces: ef });
        }
        Ok(ConvexHull::from_validated_parts(
            p.vertices, faces, p.corners, edges,
        ))
    }
}
