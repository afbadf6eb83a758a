//! The validated triangle mesh type shared by mass properties, the OBBTree and
//! the dynamics. Triangles are wound counter-clockwise seen from outside.

use crate::math::DVec3;
use crate::pose::Pose;
use serde::{Deserialize, Serialize};

/// Why a mesh was rejected (or, for the closedness checks, why it cannot be
/// used where a solid is needed).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// No vertices or no triangles.
    #[error("mesh is empty: {vertices} vertices, {triangles} triangles (need at least 3 and 1)")]
    Empty {
        /// Vertex count found.
        vertices: usize,
        /// Triangle count found.
        triangles: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("mesh vertex {index} is not finite: {value:?}")]
    NonFiniteVertex {
        /// Index of the offending vertex.
        index: usize,
        /// Its coordinates.
        value: DVec3,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error(
        "mesh triangle {triangle} refers to vertex {vertex}, but there are only {vertex_count} vertices"
    )]
    IndexOutOfRange {
        /// Index of the offending triangle.
        triangle: usize,
        /// The out-of-range vertex index.
        vertex: u64,
        /// How many vertices the mesh has.
        vertex_count: usize,
    },
    /// More vertices or triangles than 32-bit indices can address.
    #[error("mesh too large: {0} elements (at most 2^32 - 1)")]
    TooLarge(usize),
    /// An edge is used by only one triangle: the mesh has a hole.
    #[error("mesh is open: {boundary_edges} boundary edge(s), e.g. between vertices {example:?}; a closed mesh is needed here")]
    Open {
        /// Number of edges used by one triangle only.
        boundary_edges: usize,
        /// One such edge.
        example: [u32; 2],
    },
    /// An edge is shared by more than two triangles.
    #[error("mesh is not manifold: {count} edge(s) shared by more than two triangles, e.g. {example:?}")]
    NonManifold {
        /// Number of such edges.
        count: usize,
        /// One such edge.
        example: [u32; 2],
    },
    /// Two triangles sharing an edge traverse it in the same direction.
    #[error("mesh winding is inconsistent: {count} edge(s) traversed twice in the same direction, e.g. {example:?}")]
    InconsistentWinding {
        /// Number of such edges.
        count: usize,
        /// One such edge.
        example: [u32; 2],
    },
    /// A closed mesh whose signed volume is zero or negative.
    #[error("mesh encloses no positive volume (signed volume {volume:e} m^3): flat, or wound inside out")]
    NonPositiveVolume {
        /// Signed volume found.
        volume: f64,
    },
}

/// A triangle mesh with finite vertices and in-range indices.
///
/// Construction validates; the fields are read-only afterwards so that every
/// `TriMesh` in the program is known to be valid. Degenerate (zero-area)
/// triangles are allowed (they occur in real files) and reported by
/// [`TriMesh::degenerate_triangles`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "RawMesh", into = "RawMesh")]
pub struct TriMesh {
    vertices: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
}

#[derive(Serialize, Deserialize)]
struct RawMesh {
    vertices: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
}

impl TryFrom<RawMesh> for TriMesh {
    type Error = MeshError;
    fn try_from(raw: RawMesh) -> Result<Self, MeshError> {
        TriMesh::new(raw.vertices, raw.triangles)
    }
}

impl From<TriMesh> for RawMesh {
    fn from(m: TriMesh) -> Self {
        RawMesh {
            vertices: m.vertices,
            triangles: m.triangles,
        }
    }
}

impl TriMesh {
    /// Validates and builds a mesh.
    pub fn new(vertices: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Result<TriMesh, MeshError> {
        if vertices.len() < 3 || triangles.is_empty() {
            return Err(MeshError::Empty {
                vertices: vertices.len(),
                triangles: triangles.len(),
            });
        }
        if vertices.len() > u32::MAX as usize {
            return Err(MeshError::TooLarge(vertices.len()));
        }
        if triangles.len() > u32::MAX as usize {
            return Err(MeshError::TooLarge(triangles.len()));
        }
        if let Some((index, &value)) = vertices.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(MeshError::NonFiniteVertex { index, value });
        }
        let n = vertices.len();
        for (t, tri) in triangles.iter().enumerate() {
            for &i in tri {
                if i as usize >= n {
                    return Err(MeshError::IndexOutOfRange {
                        triangle: t,
                        vertex: i as u64,
                        vertex_count: n,
                    });
                }
            }
        }
        Ok(TriMesh { vertices, triangles })
    }

    /// Builds from flat arrays with any integer index type (as loaders and
    /// bindings deliver them), checking that indices fit.
    pub fn from_indices<I>(vertices: Vec<DVec3>, indices: &[[I; 3]]) -> Result<TriMesh, MeshError>
    where
        I: Copy + TryInto<u64>,
    {
        let n = vertices.len();
        let mut triangles = Vec::with_capacity(indices.len());
        for (t, tri) in indices.iter().enumerate() {
            let mut out = [0u32; 3];
            for k in 0..3 {
                let i: u64 = tri[k].try_into().unwrap_or(u64::MAX);
                if i >= n as u64 {
                    return Err(MeshError::IndexOutOfRange {
                        triangle: t,
                        vertex: i,
                        vertex_count: n,
                    });
                }
                out[k] = i as u32;
            }
            triangles.push(out);
        }
        TriMesh::new(vertices, triangles)
    }

    /// Vertex positions (m).
    pub fn vertices(&self) -> &[DVec3] {
        &self.vertices
    }

    /// Triangles as vertex index triples, counter-clockwise seen from outside.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The three corners of triangle `t` placed by `pose` (each through
    /// `Pose::transform_point`): the one way a triangle is put in the world,
    /// so that the narrow phase, every query and their brute-force oracles
    /// evaluate the exact predicates on the same coordinates, bit for bit.
    #[inline]
    pub fn placed_triangle(&self, t: usize, pose: &Pose) -> [DVec3; 3] {
        // Written out: `triangle(t).map(..)` made the tori's contacts query
        // a quarter slower (array `map` is not always unrolled in place).
        let [a, b, c] = self.triangles[t];
        [
            pose.transform_point(self.vertices[a as usize]),
            pose.transform_point(self.vertices[b as usize]),
            pose.transform_point(self.vertices[c as usize]),
        ]
    }

    /// The three corners of triangle `t`.
    #[inline]
    pub fn triangle(&self, t: usize) -> [DVec3; 3] {
        let [a, b, c] = self.triangles[t];
        [
            self.vertices[a as usize],
            self.vertices[b as usize],
            self.vertices[c as usize],
        ]
    }

    /// Area-weighted normal of triangle `t` (length = 2 x area).
    #[inline]
    pub fn triangle_normal_scaled(&self, t: usize) -> DVec3 {
        let [a, b, c] = self.triangle(t);
        (b - a).cross(c - a)
    }

    /// Triangles whose area is at most `tol` times the square of their longest edge
    /// (zero-area triangles and slivers).
    pub fn degenerate_triangles(&self, tol: f64) -> Vec<usize> {
        (0..self.triangles.len())
            .filter(|&t| {
                let [a, b, c] = self.triangle(t);
                let l2 = (b - a)
                    .length_squared()
                    .max((c - b).length_squared())
                    .max((a - c).length_squared());
                let area2 = (b - a).cross(c - a).length();
                area2 <= 2.0 * tol * l2
            })
            .collect()
    }

    /// Total surface area (m^2).
    pub fn surface_area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| 0.5 * self.triangle_normal_scaled(t).length())
            .sum()
    }

    /// Bytes the mesh holds: its vertices and triangles and the struct
    /// itself (what a benchmark counts as a collision model's geometry).
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + self.vertices.len() * std::mem::size_of::<DVec3>()
            + self.triangles.len() * std::mem::size_of::<[u32; 3]>()
    }

    /// Signed enclosed volume by the divergence theorem (m^3); positive for a
    /// closed mesh wound outward. Meaningless for an open mesh.
    pub fn signed_volume(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.triangle(t);
                a.dot(b.cross(c))
            })
            .sum::<f64>()
            / 6.0
    }

    /// Axis-aligned bounds `(min, max)`.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.vertices.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &v| (lo.min(v), hi.max(v)),
        )
    }

    /// A copy with every vertex mapped by `f` (validated again).
    pub fn map_vertices(&self, f: impl Fn(DVec3) -> DVec3) -> Result<TriMesh, MeshError> {
        TriMesh::new(
            self.vertices.iter().map(|&v| f(v)).collect(),
            self.triangles.clone(),
        )
    }

    /// A copy with every triangle's winding reversed (inside out).
    pub fn flipped(&self) -> TriMesh {
        TriMesh {
            vertices: self.vertices.clone(),
            triangles: self.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect(),
        }
    }

    /// Checks that the mesh bounds a solid: closed, manifold, consistently and
    /// outward wound, positive volume. Needed before deriving mass from density.
    pub fn check_solid(&self) -> Result<(), MeshError> {
        crate::mesh::Topology::new(self).check_closed()?;
        let volume = self.signed_volume();
        if volume.is_nan() || volume <= 0.0 {
            return Err(MeshError::NonPositiveVolume { volume });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tet() -> (Vec<DVec3>, Vec<[u32; 3]>) {
        (
            vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z],
            vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        )
    }

    #[test]
    fn valid_tetrahedron() {
        let (v, t) = tet();
        let m = TriMesh::new(v, t).unwrap();
        assert!((m.signed_volume() - 1.0 / 6.0).abs() < 1e-15);
        m.check_solid().unwrap();
        assert!(matches!(
            m.flipped().check_solid(),
            Err(MeshError::NonPositiveVolume { .. })
        ));
    }

    #[test]
    fn rejects_bad_meshes() {
        let (mut v, t) = tet();
        assert!(matches!(
            TriMesh::new(vec![], vec![]),
            Err(MeshError::Empty { .. })
        ));
        assert!(matches!(
            TriMesh::new(v.clone(), vec![[0, 1, 9]]),
            Err(MeshError::IndexOutOfRange {
                triangle: 0,
                vertex: 9,
                ..
            })
        ));
        v[2].y = f64::NAN;
        assert!(matches!(
            TriMesh::new(v, t),
            Err(MeshError::NonFiniteVertex { index: 2, .. })
        ));
        assert!(matches!(
            TriMesh::from_indices(tet().0, &[[0i64, -1, 2]]),
            Err(MeshError::IndexOutOfRange { .. })
        ));
    }

    #[test]
    fn degenerate_triangles_reported() {
        let v = vec![DVec3::ZERO, DVec3::X, DVec3::new(2.0, 0.0, 0.0), DVec3::Y];
        let m = TriMesh::new(v, vec![[0, 1, 2], [0, 1, 3]]).unwrap();
        assert_eq!(m.degenerate_triangles(1e-12), vec![0]);
    }

    #[test]
    fn serde_validates() {
        let bad = r#"{"vertices":[[0,0,0],[1,0,0],[0,1,0]],"triangles":[[0,1,7]]}"#;
        assert!(serde_json::from_str::<TriMesh>(bad).is_err());
    }
}
