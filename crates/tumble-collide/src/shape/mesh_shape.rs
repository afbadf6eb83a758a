//! A triangle-mesh shape for the dynamics: the mesh with its OBBTree, built
//! once and shared (cheap to clone), so that concave bodies collide exactly,
//! triangle against triangle, without convex decomposition. Optionally the
//! smooth surface the mesh tessellates ([`SmoothSurface`]), which spheres
//! and capsules roll on instead of the facets.

use super::{Aabb, ShapeError, SmoothSurface};
use crate::bvh::ObbTree;
use crate::contact::{Feature, SubFeature};
use crate::math::DVec3;
use crate::mesh::topology::NO_NEIGHBOR;
use crate::mesh::{Topology, TriMesh};
use crate::pose::Pose;
use std::sync::Arc;

/// Two triangles are coplanar when their unit normals' dot product is within
/// this of 1 (about 0.03 degrees).
pub const FLAT_COS_TOLERANCE: f64 = 1e-7;

/// A closed or open triangle mesh with its OBBTree, in its own frame.
#[derive(Debug, Clone)]
pub struct MeshShape {
    mesh: Arc<TriMesh>,
    tree: Arc<ObbTree>,
    /// Bit `k` of entry `t`: edge `k` of triangle `t` is flat (shared with a
    /// coplanar, consistently wound neighbour): an internal edge that can
    /// define no contact normal of its own. Bit `3 + k`: corner `k` is a flat
    /// vertex (every edge around it is flat: inside a flat region).
    flat: Arc<Vec<u8>>,
    /// Entry `v`: vertex `v` as the corner `k` of the first triangle `t`
    /// that uses it, `t << 2 | k` (`u32::MAX` for a vertex no triangle
    /// uses): the one name a vertex contact gets, step after step.
    first_corner: Arc<Vec<u32>>,
    /// Bit `k` of entry `t`: triangle `t` owns its corner `k` (the vertex's
    /// first corner); bit `3 + k`: it owns its edge `k` (no triangle across
    /// it, or one with a larger index, or itself: a degenerate triangle's
    /// edge can run back along it). Every vertex and every edge between two
    /// triangles has one owner, which alone reports its contacts in every
    /// mesh-mesh search (`triangle::tri_contact`, "Shared features, once");
    /// a boundary or non-manifold edge is owned by each triangle at it, and
    /// its copies are merged as before.
    owned: Arc<Vec<u8>>,
    /// The triangle across each edge (`Topology::neighbors`).
    neighbors: Arc<Vec<[u32; 3]>>,
    /// The smooth surface spheres and capsules touch, if asked for.
    smooth: Option<Arc<SmoothSurface>>,
    lo: DVec3,
    hi: DVec3,
}

impl PartialEq for MeshShape {
    fn eq(&self, other: &Self) -> bool {
        (Arc::ptr_eq(&self.mesh, &other.mesh) || self.mesh == other.mesh)
            && self.crease_angle() == other.crease_angle()
    }
}

impl MeshShape {
    /// Builds the OBBTree of `mesh`.
    pub fn new(mesh: TriMesh) -> Result<MeshShape, ShapeError> {
        let tree = ObbTree::build(&mesh).map_err(|e| ShapeError::Bvh(e.to_string()))?;
        let (lo, hi) = mesh.bounds();
        let topology = Topology::new(&mesh);
        let unit = |t: usize| mesh.triangle_normal_scaled(t).normalize_or_zero();
        let mut flat: Vec<u8> = topology
            .neighbors
            .iter()
            .enumerate()
            .map(|(t, nb)| {
                let mut bits = 0u8;
                for (k, &other) in nb.iter().enumerate() {
                    if other != NO_NEIGHBOR && unit(t).dot(unit(other as usize)) > 1.0 - FLAT_COS_TOLERANCE {
                        bits |= 1 << k;
                    }
                }
                bits
            })
            .collect();
        // Corner k of a triangle touches its edges k and k + 2; a vertex is
        // flat when every edge of every triangle around it is.
        let mut vertex_flat = vec![true; mesh.vertices().len()];
        for (t, tri) in mesh.triangles().iter().enumerate() {
            for k in 0..3 {
                let edges = (1 << k) | (1 << ((k + 2) % 3));
                if flat[t] & edges != edges {
                    vertex_flat[tri[k] as usize] = false;
                }
            }
        }
        for (t, tri) in mesh.triangles().iter().enumerate() {
            for k in 0..3 {
                if vertex_flat[tri[k] as usize] {
                    flat[t] |= 1 << (3 + k);
                }
            }
        }
        let mut first_corner = vec![u32::MAX; mesh.vertices().len()];
        for (t, tri) in mesh.triangles().iter().enumerate() {
            for (k, &v) in tri.iter().enumerate() {
                if first_corner[v as usize] == u32::MAX {
                    first_corner[v as usize] = (t as u32) << 2 | k as u32;
                }
            }
        }
        let owned = (0..mesh.triangles().len())
            .map(|t| {
                let mut bits = 0u8;
                for k in 0..3 {
                    let v = mesh.triangles()[t][k];
                    if first_corner[v as usize] == (t as u32) << 2 | k as u32 {
                        bits |= 1 << k;
                    }
                    let across = topology.neighbors[t][k];
                    if across == NO_NEIGHBOR || (t as u32) <= across {
                        bits |= 1 << (3 + k);
                    }
                }
                bits
            })
            .collect();
        Ok(MeshShape {
            mesh: Arc::new(mesh),
            tree: Arc::new(tree),
            flat: Arc::new(flat),
            first_corner: Arc::new(first_corner),
            owned: Arc::new(owned),
            neighbors: Arc::new(topology.neighbors),
            smooth: None,
            lo,
            hi,
        })
    }

    /// The same mesh, touched by spheres and capsules as the smooth surface
    /// it tessellates: corner normals blended across every edge whose faces
    /// meet at no more than `crease_angle` (radians, in (0, pi); 30 degrees
    /// keeps a box's or a cup rim's edges sharp and blends a sphere of 12 or
    /// more facets around). A ball rolling in a tessellated bowl then swings
    /// as in a smooth one instead of losing speed at every edge. The
    /// contacts between two meshes stay exact, triangle against triangle.
    pub fn with_smooth_surface(mut self, crease_angle: f64) -> Result<MeshShape, ShapeError> {
        if !(crease_angle > 0.0 && crease_angle < std::f64::consts::PI) {
            return Err(ShapeError::BadDimension {
                shape: "mesh",
                name: "crease_angle",
                expected: "in (0, pi) rad",
                value: crease_angle,
            });
        }
        let topology = Topology::new(&self.mesh);
        self.smooth = Some(Arc::new(SmoothSurface::new(&self.mesh, &topology, crease_angle)));
        Ok(self)
    }

    /// The smooth surface spheres and capsules touch, if the shape has one.
    pub fn smooth_surface(&self) -> Option<&SmoothSurface> {
        self.smooth.as_deref()
    }

    /// The crease angle of its smooth surface (radians), if it has one.
    pub fn crease_angle(&self) -> Option<f64> {
        self.smooth.as_ref().map(|s| s.crease_angle())
    }

    /// `true` when edge `k` (corner `k` to `k + 1`) of triangle `t` is an
    /// internal edge between coplanar triangles.
    pub fn is_flat_edge(&self, t: u32, k: u8) -> bool {
        self.flat
            .get(t as usize)
            .is_some_and(|&bits| bits & (1 << k) != 0)
    }

    /// `true` when corner `k` of triangle `t` is a vertex inside a flat
    /// region (all edges around it flat): like an internal edge, it has no
    /// contact normal of its own.
    pub fn is_flat_vertex(&self, t: u32, k: u8) -> bool {
        self.flat
            .get(t as usize)
            .is_some_and(|&bits| bits & (1 << (3 + k)) != 0)
    }

    /// Vertex `v` named as corner `k` of the first triangle `t` that uses
    /// it: `Some((t, k))`, or `None` for a vertex no triangle uses.
    pub fn first_corner(&self, v: u32) -> Option<(u32, u8)> {
        let code = *self.first_corner.get(v as usize)?;
        (code != u32::MAX).then_some((code >> 2, (code & 3) as u8))
    }

    /// The corners (bits 0-2) and edges (bits 3-5) that triangle `t` owns
    /// (see the field).
    #[inline]
    pub(crate) fn owned_features(&self, t: u32) -> u8 {
        self.owned[t as usize]
    }

    /// The triangle across edge `k` of triangle `t`, if there is one (none
    /// at a boundary or non-manifold edge).
    #[inline]
    pub(crate) fn across(&self, t: u32, k: usize) -> Option<u32> {
        let n = self.neighbors[t as usize][k];
        (n != NO_NEIGHBOR).then_some(n)
    }

    /// `true` when `visit` returns `true` for one of the triangles around
    /// corner `k` of triangle `t` other than `t` itself: its fan, walked
    /// across the edges at the corner, one way round and, at an edge with
    /// no single triangle across (a boundary or non-manifold edge), the
    /// other. At a vertex where two fans meet only in the point, or behind
    /// a non-manifold edge, triangles are not reached: the walk sees the
    /// fan of `t` alone.
    pub(crate) fn any_around_corner(&self, t: u32, k: usize, mut visit: impl FnMut(u32) -> bool) -> bool {
        let tris = self.mesh.triangles();
        let v = tris[t as usize][k];
        // Corner k of a triangle touches its edges k and k + 2.
        for edge in [k, (k + 2) % 3] {
            let (mut prev, mut here) = (t, self.across(t, edge));
            // A fan holds fewer triangles than the mesh; the bound only
            // guards against a malformed neighbour table.
            for step in 0..tris.len() {
                let Some(c) = here else { break };
                if c == t {
                    // Round the fan and back: every triangle seen. (A
                    // degenerate triangle can be its own neighbour: then
                    // the other way round.)
                    if step == 0 {
                        break;
                    }
                    return false;
                }
                if visit(c) {
                    return true;
                }
                let tri = tris[c as usize];
                let Some(m) = (0..3).find(|&m| tri[m] == v) else {
                    break;
                };
                let next = [m, (m + 2) % 3].map(|e| self.across(c, e));
                here = next.into_iter().find(|&n| n != Some(prev)).flatten();
                prev = c;
            }
        }
        false
    }

    /// The name of feature `f` through its owner: a corner through the
    /// vertex's first corner, an edge through the triangle that owns it
    /// (faces and anything else unchanged). One name per vertex and per
    /// edge between two triangles, whichever triangle pair found the
    /// contact (a non-manifold edge keeps the name it came with).
    pub fn owner_name(&self, f: Feature) -> Feature {
        let tris = self.mesh.triangles();
        let Some(tri) = tris.get(f.index as usize) else {
            return f;
        };
        match f.sub {
            SubFeature::Vertex(k) if k < 3 => self
                .first_corner(tri[k as usize])
                .map_or(f, |(t, k)| Feature::vertex(t, k)),
            SubFeature::Edge(k) if k < 3 && self.owned[f.index as usize] & (1 << (3 + k)) == 0 => {
                let (u, v) = (tri[k as usize], tri[(k as usize + 1) % 3]);
                let Some(t) = self.across(f.index, k as usize) else {
                    return f;
                };
                let other = tris[t as usize];
                (0..3u8)
                    .find(|&j| {
                        let (p, q) = (other[j as usize], other[(j as usize + 1) % 3]);
                        (p, q) == (v, u) || (p, q) == (u, v)
                    })
                    .map_or(f, |j| Feature::edge(t, j))
            }
            _ => f,
        }
    }

    /// `true` when both shapes were built from the same [`MeshShape::new`]
    /// call (clones share their mesh and tree) and have the same smooth
    /// surface, or none: world snapshots store such a mesh once.
    pub fn shares_mesh_with(&self, other: &MeshShape) -> bool {
        Arc::ptr_eq(&self.mesh, &other.mesh)
            && match (&self.smooth, &other.smooth) {
                (None, None) => true,
                (Some(a), Some(b)) => Arc::ptr_eq(a, b),
                _ => false,
            }
    }

    /// The mesh (shape frame).
    pub fn mesh(&self) -> &TriMesh {
        &self.mesh
    }

    /// Bytes of the whole collision model: the mesh (vertices and
    /// triangles), its OBBTree, the flat-edge flags, the vertices' names and
    /// the smooth surface's normals if any. The figure the benchmarks
    /// compare with other libraries' models, which hold their geometry
    /// beside their trees (FCL's and coal's `memUsage`, parry's
    /// `total_memory_size`).
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + self.mesh.memory_bytes()
            + self.tree.memory_bytes()
            + self.flat.len()
            + self.first_corner.len() * std::mem::size_of::<u32>()
            + self.owned.len()
            + self.neighbors.len() * std::mem::size_of::<[u32; 3]>()
            + self.smooth.as_ref().map_or(0, |s| s.memory_bytes())
    }

    /// Its OBBTree.
    pub fn tree(&self) -> &ObbTree {
        &self.tree
    }

    /// Its OBBTree as shared (a pair's remembered walk holds it, so that
    /// the walk is only ever applied to this tree).
    pub(crate) fn tree_arc(&self) -> &Arc<ObbTree> {
        &self.tree
    }

    /// World bounding box at `pose`: the mesh's box in its own frame, turned.
    pub fn aabb(&self, pose: &Pose) -> Aabb {
        let c = (self.lo + self.hi) * 0.5;
        let h = (self.hi - self.lo) * 0.5;
        let r = glam::DMat3::from_quat(pose.rotation);
        let abs = glam::DMat3::from_cols(r.x_axis.abs(), r.y_axis.abs(), r.z_axis.abs());
        let center = pose.transform_point(c);
        Aabb::from_center_half_extents(center, abs * h)
    }

    /// The vertex farthest along `dir` (shape frame).
    pub fn support(&self, dir: DVec3) -> DVec3 {
        self.mesh
            .vertices()
            .iter()
            .copied()
            .max_by(|a, b| a.dot(dir).total_cmp(&b.dot(dir)))
            .unwrap_or(DVec3::ZERO)
    }
}
