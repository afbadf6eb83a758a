//! A polytope's faces as a small triangle mesh, for the triangle contact
//! routines of the polytope-mesh pair (`contact_mesh::contact_polytope_mesh`):
//! each face fanned into triangles from its first corner, placed in the
//! world, with the corners and edges each fan triangle owns and the
//! triangles around each corner and across each edge, which the
//! vertex/edge, edge/vertex and vertex/vertex contacts need for their cones
//! of normals (`triangle::tri_vertex_edge`; the mesh side has the same from
//! its `MeshShape`).
//!
//! Ownership follows the meshes' rule ("Shared features, once",
//! `triangle::tri_contact`): a corner belongs to the first fan triangle
//! that holds it, an edge of the polytope to the fan triangle of the face
//! that runs along it from its lower vertex index to its higher (each edge
//! is run once each way by its two faces). A fan's diagonals lie inside a
//! flat face and are owned by no one: a flat edge has no normal of its own.

use super::contact_mesh::MeshAt;
use crate::math::DVec3;
use crate::pose::Pose;
use crate::shape::Polytope;
use crate::triangle::{Copies, Side};
use std::cell::RefCell;

/// The fan triangles of a polytope at a pose.
pub(super) struct PolytopeFans {
    /// Each fan triangle (world frame) and its feature name: face index
    /// << 8 | fan index `k` (the triangle of corners 0, k, k + 1).
    pub tris: Vec<([DVec3; 3], u32)>,
    /// The polytope vertex at each fan triangle's corners.
    corners: Vec<[u32; 3]>,
    /// Bits 0-2: the corners each fan triangle owns; bits 3-5: its edges.
    owned: Vec<u8>,
    /// The fan triangles at each polytope vertex: those of vertex `v` are
    /// `around[start[v]..start[v + 1]]`, in fan order.
    start: Vec<u32>,
    around: Vec<u32>,
    /// Scratch of `refill`: the vertices met so far, and where each
    /// vertex's next fan triangle goes in `around`.
    vertex_seen: Vec<bool>,
    fill: Vec<u32>,
}

thread_local! {
    /// The fans of the polytope being tested on this thread.
    pub(super) static POLYTOPE_FANS: RefCell<PolytopeFans> = const {
        RefCell::new(PolytopeFans {
            tris: Vec::new(),
            corners: Vec::new(),
            owned: Vec::new(),
            start: Vec::new(),
            around: Vec::new(),
            vertex_seen: Vec::new(),
            fill: Vec::new(),
        })
    };
}

impl PolytopeFans {
    /// Fans the faces of `p` placed at `pose`, in place of what was here
    /// (the buffers are kept: the narrow phase reuses one per thread).
    pub(super) fn refill<P: Polytope + ?Sized>(&mut self, p: &P, pose: &Pose) {
        let n = p.vertex_count();
        self.tris.clear();
        self.corners.clear();
        self.owned.clear();
        self.start.clear();
        self.start.resize(n + 1, 0);
        self.vertex_seen.clear();
        self.vertex_seen.resize(n, false);
        for f in 0..p.face_count() {
            let len = p.face_len(f);
            let corner = |k: usize| p.face_vertex(f, k) as u32;
            for k in 1..len.saturating_sub(1) {
                let c = [corner(0), corner(k), corner(k + 1)];
                // Edge j of the fan triangle runs from its corner j to
                // corner j + 1; edge 1 is always on the face's boundary,
                // edge 0 only in the first fan triangle and edge 2 only in
                // the last.
                let boundary = [k == 1, true, k + 2 == len];
                let mut bits = 0u8;
                for j in 0..3 {
                    let v = c[j] as usize;
                    if !self.vertex_seen[v] {
                        self.vertex_seen[v] = true;
                        bits |= 1 << j;
                    }
                    if boundary[j] && c[j] < c[(j + 1) % 3] {
                        bits |= 8 << j;
                    }
                    self.start[v + 1] += 1;
                }
                let placed = c.map(|v| pose.transform_point(p.vertex(v as usize)));
                self.tris.push((placed, (f as u32) << 8 | k as u32));
                self.corners.push(c);
                self.owned.push(bits);
            }
        }
        for v in 0..n {
            self.start[v + 1] += self.start[v];
        }
        // Each vertex's list filled from its start, which `fill` tracks.
        self.fill.clear();
        self.fill.extend_from_slice(&self.start[..n]);
        self.around.clear();
        self.around.resize(self.start[n] as usize, 0);
        for (t, c) in self.corners.iter().enumerate() {
            for &v in c {
                self.around[self.fill[v as usize] as usize] = t as u32;
                self.fill[v as usize] += 1;
            }
        }
    }

    /// The corners (bits 0-2) and edges (bits 3-5) fan triangle `t` owns.
    pub(super) fn owned(&self, t: usize) -> u8 {
        self.owned[t]
    }

    /// The fan triangles at polytope vertex `v`.
    fn at_vertex(&self, v: u32) -> &[u32] {
        &self.around[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
    }
}

/// The triangles around the features of a fan triangle of A (a polytope)
/// and a triangle of mesh B, both in the world (`triangle::Copies`).
pub(super) struct FanMeshCopies<'a> {
    pub fans: &'a PolytopeFans,
    pub mesh: MeshAt<'a>,
    /// The pair: fan triangle of A, triangle of B.
    pub pair: (u32, u32),
}

impl Copies for FanMeshCopies<'_> {
    fn any_around_corner(
        &mut self,
        side: Side,
        k: usize,
        visit: &mut dyn FnMut(&[DVec3; 3]) -> bool,
    ) -> bool {
        match side {
            Side::A => {
                let t = self.pair.0;
                let v = self.fans.corners[t as usize][k];
                self.fans
                    .at_vertex(v)
                    .iter()
                    .any(|&u| u != t && visit(&self.fans.tris[u as usize].0))
            }
            Side::B => self.mesh.any_around_corner(self.pair.1, k, visit),
        }
    }

    fn across(&mut self, side: Side, k: usize) -> Option<[DVec3; 3]> {
        match side {
            Side::A => {
                let t = self.pair.0;
                let c = self.fans.corners[t as usize];
                let (p, q) = (c[k], c[(k + 1) % 3]);
                self.fans
                    .at_vertex(p)
                    .iter()
                    .find(|&&u| u != t && self.fans.corners[u as usize].contains(&q))
                    .map(|&u| self.fans.tris[u as usize].0)
            }
            Side::B => self.mesh.across(self.pair.1, k),
        }
    }
}
