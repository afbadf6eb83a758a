//! Convex polyhedron with polygonal faces, built from a closed convex
//! triangle mesh by merging coplanar triangles (so that a box made of 12
//! triangles becomes 6 quads and its contact manifolds have 4 points, not a
//! triangle's 3).
//!
//! Construction: triangles are flood-filled across shared edges into groups
//! lying within a tolerance of the seed triangle's plane; each group's
//! boundary edges are chained into one counter-clockwise polygon; every
//! vertex must then lie below every face plane (convexity). Interior vertices
//! of merged faces are dropped. Edges keep their two faces for the Gauss-map
//! pruning of SAT edge pairs (Gregorius, "The Separating Axis Test between
//! Convex Polyhedra", GDC 2013).

use super::{check_non_negative, Aabb, Polytope, ShapeError};
use crate::contact::Feature;
use crate::math::DVec3;
use crate::mesh::{Topology, TriMesh};
use crate::pose::Pose;

/// Largest number of corners a face may have (fixed-size clipping buffers in
/// the narrow phase avoid heap allocation per query).
pub const MAX_FACE_VERTICES: usize = 64;

/// A planar convex face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HullFace {
    /// Outward unit normal (body frame).
    pub normal: DVec3,
    /// Plane offset: `normal . x = offset` on the face (m).
    pub offset: f64,
    /// First corner in `ConvexHull::corners`.
    pub start: u32,
    /// Number of corners.
    pub len: u32,
}

/// An edge between two faces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HullEdge {
    /// End vertices, as `faces[0]` traverses the edge.
    pub vertices: [u32; 2],
    /// The two faces meeting at the edge.
    pub faces: [u32; 2],
}

/// A convex polyhedron (body frame). Serialised as its vertices, faces,
/// corners and edges, checked on the way back in.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(
    try_from = "super::serde_parts::HullParts",
    into = "super::serde_parts::HullParts"
)]
pub struct ConvexHull {
    vertices: Vec<DVec3>,
    faces: Vec<HullFace>,
    corners: Vec<u32>,
    edges: Vec<HullEdge>,
    vertex_features: Vec<Feature>,
    centroid: DVec3,
}

impl ConvexHull {
    /// Default planarity/convexity tolerance, relative to the bounding-box
    /// diagonal of the mesh.
    pub const DEFAULT_RELATIVE_TOLERANCE: f64 = 1e-7;

    /// Builds from a closed, outward-wound convex mesh with the default tolerance.
    pub fn from_mesh(mesh: &TriMesh) -> Result<ConvexHull, ShapeError> {
        Self::from_mesh_with_tolerance(mesh, Self::DEFAULT_RELATIVE_TOLERANCE)
    }

    /// Builds the convex hull of a point set (via [`crate::hull::convex_hull`]).
    pub fn from_points(points: &[DVec3]) -> Result<ConvexHull, ShapeError> {
        let mesh = crate::hull::convex_hull(points)?;
        Self::from_mesh(&mesh)
    }

    /// Builds from a closed, outward-wound convex mesh; triangles within
    /// `relative_tolerance` x (bounding-box diagonal) of a common plane are
    /// merged, and a vertex farther than that outside any face is an error.
    pub fn from_mesh_with_tolerance(
        mesh: &TriMesh,
        relative_tolerance: f64,
    ) -> Result<ConvexHull, ShapeError> {
        // Zero is a valid tolerance (exact coplanarity).
        check_non_negative("convex_hull", "relative_tolerance", relative_tolerance)?;
        let (lo, hi) = mesh.bounds();
        if let Some(value) = [lo, hi]
            .iter()
            .flat_map(|v| v.to_array())
            .find(|&x| !super::within_dimension_limit(x))
        {
            return Err(ShapeError::BadDimension {
                shape: "convex_hull",
                name: "vertex coordinate",
                expected: "within 1e36 of 0",
                value,
            });
        }
        mesh.check_solid()?;
        let tol = relative_tolerance * (hi - lo).length();
        let verts = mesh.vertices();
        let tris = mesh.triangles();

        let mut normals = Vec::with_capacity(tris.len());
        for t in 0..tris.len() {
            let [a, b, c] = mesh.triangle(t);
            let n = (b - a).cross(c - a);
            let l2 = (b - a).length_squared().max((c - a).length_squared());
            if n.length() <= 1e-12 * l2 {
                return Err(ShapeError::DegenerateTriangle { triangle: t });
            }
            normals.push(n);
        }

        // Flood fill coplanar groups (deterministic: seeds in triangle order).
        let topo = Topology::new(mesh);
        const NONE: u32 = u32::MAX;
        let mut group = vec![NONE; tris.len()];
        let mut group_seed: Vec<usize> = Vec::new();
        let mut stack = Vec::new();
        for seed in 0..tris.len() {
            if group[seed] != NONE {
                continue;
            }
            let g = group_seed.len() as u32;
            group_seed.push(seed);
            let n0 = normals[seed].normalize();
            let d0 = n0.dot(verts[tris[seed][0] as usize]);
            group[seed] = g;
            stack.push(seed);
            while let Some(t) = stack.pop() {
                for &u in &topo.neighbors[t] {
                    let u = u as usize;
                    if group[u] != NONE || normals[u].dot(n0) <= 0.0 {
                        continue;
                    }
                    let coplanar = tris[u]
                        .iter()
                        .all(|&v| (n0.dot(verts[v as usize]) - d0).abs() <= tol);
                    if coplanar {
                        group[u] = g;
                        stack.push(u);
                    }
                }
            }
        }

        // Boundary loop of each group.
        let mut faces = Vec::with_capacity(group_seed.len());
        let mut corners: Vec<u32> = Vec::new();
        let mut members: Vec<Vec<usize>> = vec![Vec::new(); group_seed.len()];
        for (t, &g) in group.iter().enumerate() {
            members[g as usize].push(t);
        }
        let mut boundary: Vec<[u32; 2]> = Vec::new();
        for (g, tlist) in members.iter().enumerate() {
            boundary.clear();
            let mut nsum = DVec3::ZERO;
            for &t in tlist {
                nsum += normals[t];
                for k in 0..3 {
                    if group[topo.neighbors[t][k] as usize] != g as u32 {
                        boundary.push([tris[t][k], tris[t][(k + 1) % 3]]);
                    }
                }
            }
            if boundary.is_empty() {
                return Err(ShapeError::BadFace { face: g });
            }
            let normal = nsum.normalize();
            let start = corners.len();
            let mut cur = boundary[0];
            corners.push(cur[0]);
            for _ in 1..boundary.len() {
                match boundary.iter().find(|e| e[0] == cur[1]) {
                    Some(&next) => {
                        corners.push(next[0]);
                        cur = next;
                    }
                    None => return Err(ShapeError::BadFace { face: g }),
                }
            }
            if cur[1] != boundary[0][0] {
                return Err(ShapeError::BadFace { face: g });
            }
            let len = corners.len() - start;
            if len > MAX_FACE_VERTICES {
                return Err(ShapeError::FaceTooLarge {
                    face: g,
                    count: len,
                    max: MAX_FACE_VERTICES,
                });
            }
            let offset = corners[start..]
                .iter()
                .map(|&v| normal.dot(verts[v as usize]))
                .fold(f64::NEG_INFINITY, f64::max);
            faces.push(HullFace {
                normal,
                offset,
                start: start as u32,
                len: len as u32,
            });
        }

        // Convexity: every vertex below every face plane.
        for (f, face) in faces.iter().enumerate() {
            for (v, p) in verts.iter().enumerate() {
                let excess = face.normal.dot(*p) - face.offset;
                if excess > tol {
                    return Err(ShapeError::NotConvex {
                        face: f,
                        vertex: v,
                        excess,
                        tolerance: tol,
                    });
                }
            }
        }

        // Keep only the vertices on face boundaries, in original order.
        let mut remap = vec![NONE; verts.len()];
        for &c in &corners {
            remap[c as usize] = 0;
        }
        let mut vertices = Vec::new();
        for (v, r) in remap.iter_mut().enumerate() {
            if *r != NONE {
                *r = vertices.len() as u32;
                vertices.push(verts[v]);
            }
        }
        for c in corners.iter_mut() {
            *c = remap[*c as usize];
        }

        // Edges: each directed face edge meets its reverse in the other face.
        let mut directed: Vec<(u32, u32, u32, u32, u32)> = Vec::new(); // (lo, hi, face, from, to)
        for (f, face) in faces.iter().enumerate() {
            let s = face.start as usize;
            let n = face.len as usize;
            for k in 0..n {
                let a = corners[s + k];
                let b = corners[s + (k + 1) % n];
                directed.push((a.min(b), a.max(b), f as u32, a, b));
            }
        }
        directed.sort_unstable();
        let mut edges = Vec::with_capacity(directed.len() / 2);
        for pair in directed.chunks(2) {
            if pair.len() != 2 || pair[0].0 != pair[1].0 || pair[0].1 != pair[1].1 || pair[0].3 == pair[1].3 {
                return Err(ShapeError::BadFace {
                    face: pair[0].2 as usize,
                });
            }
            edges.push(HullEdge {
                vertices: [pair[0].3, pair[0].4],
                faces: [pair[0].2, pair[1].2],
            });
        }

        Ok(Self::from_validated_parts(vertices, faces, corners, edges))
    }

    /// The hull from its parts (indices already checked), with the derived
    /// vertex features and centroid computed.
    pub(crate) fn from_validated_parts(
        vertices: Vec<DVec3>,
        faces: Vec<HullFace>,
        corners: Vec<u32>,
        edges: Vec<HullEdge>,
    ) -> ConvexHull {
        let mut vertex_features = vec![Feature::vertex_edge_fallback(0); vertices.len()];
        let mut seen = vec![false; vertices.len()];
        for (f, face) in faces.iter().enumerate() {
            for k in 0..face.len as usize {
                let v = corners[face.start as usize + k] as usize;
                if !seen[v] {
                    seen[v] = true;
                    vertex_features[v] = Feature::vertex(f as u32, k as u8);
                }
            }
        }
        let centroid = vertices.iter().copied().sum::<DVec3>() / vertices.len() as f64;
        ConvexHull {
            vertices,
            faces,
            corners,
            edges,
            vertex_features,
            centroid,
        }
    }

    /// Corner vertex indices of all faces, face after face (see
    /// [`HullFace::start`]).
    pub fn corners(&self) -> &[u32] {
        &self.corners
    }

    /// The hull's surface as a closed triangle mesh: each (convex, outward)
    /// face fanned from its first corner, over the hull's own vertices (for
    /// mass properties and drawing).
    pub fn surface_mesh(&self) -> Result<TriMesh, crate::mesh::MeshError> {
        let mut triangles = Vec::new();
        for f in 0..self.faces().len() {
            let c = self.face_corners(f);
            for k in 1..c.len().saturating_sub(1) {
                triangles.push([c[0], c[k], c[k + 1]]);
            }
        }
        TriMesh::new(self.vertices.clone(), triangles)
    }

    /// Vertices (m, body frame).
    pub fn vertices(&self) -> &[DVec3] {
        &self.vertices
    }

    /// Faces.
    pub fn faces(&self) -> &[HullFace] {
        &self.faces
    }

    /// Corner vertex indices of face `f`, counter-clockwise seen from outside.
    pub fn face_corners(&self, f: usize) -> &[u32] {
        let face = &self.faces[f];
        &self.corners[face.start as usize..(face.start + face.len) as usize]
    }

    /// Edges.
    pub fn edges(&self) -> &[HullEdge] {
        &self.edges
    }

    /// Farthest vertex along `dir` (body frame).
    pub fn support(&self, dir: DVec3) -> DVec3 {
        self.vertices[self.support_vertex(dir)]
    }

    /// World bounding box at `pose` (exact: over the transformed vertices).
    pub fn aabb(&self, pose: &Pose) -> Aabb {
        let mut min = DVec3::splat(f64::INFINITY);
        let mut max = DVec3::splat(f64::NEG_INFINITY);
        for &v in &self.vertices {
            let p = pose.transform_point(v);
            min = min.min(p);
            max = max.max(p);
        }
        Aabb { min, max }
    }
}

impl Polytope for ConvexHull {
    fn vertex_count(&self) -> usize {
        self.vertices.len()
    }
    fn vertex(&self, i: usize) -> DVec3 {
        self.vertices[i]
    }
    fn face_count(&self) -> usize {
        self.faces.len()
    }
    fn face_normal(&self, f: usize) -> DVec3 {
        self.faces[f].normal
    }
    fn face_offset(&self, f: usize) -> f64 {
        self.faces[f].offset
    }
    fn face_len(&self, f: usize) -> usize {
        self.faces[f].len as usize
    }
    fn face_vertex(&self, f: usize, k: usize) -> usize {
        self.corners[self.faces[f].start as usize + k] as usize
    }
    fn edge_count(&self) -> usize {
        self.edges.len()
    }
    fn edge(&self, e: usize) -> ([u32; 2], [u32; 2]) {
        (self.edges[e].vertices, self.edges[e].faces)
    }
    fn interior_point(&self) -> DVec3 {
        self.centroid
    }
    fn vertex_feature(&self, v: usize) -> Feature {
        self.vertex_features[v]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{box_mesh, cylinder_mesh, icosphere_mesh, torus_mesh};

    #[test]
    fn box_mesh_merges_into_six_quads() {
        let h = DVec3::new(0.5, 1.0, 1.5);
        let hull = ConvexHull::from_mesh(&box_mesh(h).unwrap()).unwrap();
        assert_eq!(hull.vertices().len(), 8);
        assert_eq!(hull.faces().len(), 6);
        assert_eq!(hull.edges().len(), 12);
        for f in 0..6 {
            assert_eq!(hull.face_len(f), 4);
            let n = hull.face_normal(f);
            // Axis-aligned unit normal with offset = half extent along it.
            assert!((n.abs().max_element() - 1.0).abs() < 1e-12);
            assert!((hull.face_offset(f) - n.abs().dot(h)).abs() < 1e-12);
        }
    }

    #[test]
    fn euler_characteristic_and_caps() {
        let hull = ConvexHull::from_mesh(&cylinder_mesh(1.0, 0.5, 12).unwrap()).unwrap();
        // 12 sides + 2 caps; V - E + F = 2.
        assert_eq!(hull.faces().len(), 14);
        let (v, e, f) = (hull.vertices().len(), hull.edges().len(), hull.faces().len());
        assert_eq!(v as i64 - e as i64 + f as i64, 2);
        let ico = ConvexHull::from_mesh(&icosphere_mesh(1.0, 1).unwrap()).unwrap();
        let (v, e, f) = (ico.vertices().len(), ico.edges().len(), ico.faces().len());
        assert_eq!(v as i64 - e as i64 + f as i64, 2);
        // Every vertex is below or on every face plane.
        for face in ico.faces() {
            for p in ico.vertices() {
                assert!(face.normal.dot(*p) - face.offset < 1e-9);
            }
        }
    }

    #[test]
    fn rejects_non_convex_and_open() {
        let torus = torus_mesh(1.0, 0.3, 12, 8).unwrap();
        assert!(matches!(
            ConvexHull::from_mesh(&torus),
            Err(ShapeError::NotConvex { .. })
        ));
        let open = TriMesh::new(vec![DVec3::ZERO, DVec3::X, DVec3::Y], vec![[0, 1, 2]]).unwrap();
        assert!(matches!(ConvexHull::from_mesh(&open), Err(ShapeError::Mesh(_))));
        assert!(matches!(
            ConvexHull::from_points(&[DVec3::ZERO]),
            Err(ShapeError::Hull(_))
        ));
    }
}
