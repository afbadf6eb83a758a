//! Edge topology of a triangle mesh: neighbour triangles across each edge,
//! and the checks that a mesh is closed, manifold and consistently wound.
//!
//! Built by sorting directed edges by their undirected key (deterministic, no
//! hashing): each undirected edge of a closed, consistently wound 2-manifold
//! appears exactly twice, once in each direction.

use super::{MeshError, TriMesh};

/// Counts of the edge defects found in a mesh.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct EdgeReport {
    /// Undirected edges in total.
    pub edges: usize,
    /// Edges used by one triangle only (holes).
    pub boundary: Vec<[u32; 2]>,
    /// Edges shared by three or more triangles.
    pub non_manifold: Vec<[u32; 2]>,
    /// Edges traversed twice in the same direction (flipped neighbour).
    pub inconsistent: Vec<[u32; 2]>,
}

/// Neighbour triangle across each triangle edge.
#[derive(Debug, Clone)]
pub struct Topology {
    /// `neighbors[t][k]` is the triangle sharing edge `k` (from corner `k` to
    /// corner `k + 1`) of triangle `t`, or `u32::MAX` if there is none (boundary
    /// or non-manifold edge).
    pub neighbors: Vec<[u32; 3]>,
    /// Edge defects.
    pub report: EdgeReport,
}

/// Marker for "no neighbour".
pub const NO_NEIGHBOR: u32 = u32::MAX;

impl Topology {
    /// Computes adjacency and edge defects in O(n log n).
    pub fn new(mesh: &TriMesh) -> Topology {
        let tris = mesh.triangles();
        // (lo, hi, forward, triangle, edge index)
        let mut edges: Vec<(u32, u32, bool, u32, u8)> = Vec::with_capacity(tris.len() * 3);
        for (t, tri) in tris.iter().enumerate() {
            for k in 0..3 {
                let a = tri[k];
                let b = tri[(k + 1) % 3];
                if a == b {
                    continue; // collapsed edge of a degenerate triangle
                }
                edges.push((a.min(b), a.max(b), a < b, t as u32, k as u8));
            }
        }
        edges.sort_unstable();
        let mut neighbors = vec![[NO_NEIGHBOR; 3]; tris.len()];
        let mut report = EdgeReport::default();
        let mut i = 0;
        while i < edges.len() {
            let mut j = i + 1;
            while j < edges.len() && edges[j].0 == edges[i].0 && edges[j].1 == edges[i].1 {
                j += 1;
            }
            let key = [edges[i].0, edges[i].1];
            report.edges += 1;
            match j - i {
                1 => report.boundary.push(key),
                2 => {
                    let (e0, e1) = (edges[i], edges[i + 1]);
                    if e0.2 == e1.2 {
                        report.inconsistent.push(key);
                    }
                    neighbors[e0.3 as usize][e0.4 as usize] = e1.3;
                    neighbors[e1.3 as usize][e1.4 as usize] = e0.3;
                }
                _ => report.non_manifold.push(key),
            }
            i = j;
        }
        Topology { neighbors, report }
    }

    /// `Ok` when every edge is shared by exactly two triangles traversing it in
    /// opposite directions; otherwise the first kind of defect as a typed error.
    pub fn check_closed(&self) -> Result<(), MeshError> {
        let r = &self.report;
        if let Some(&example) = r.boundary.first() {
            return Err(MeshError::Open {
                boundary_edges: r.boundary.len(),
                example,
            });
        }
        if let Some(&example) = r.non_manifold.first() {
            return Err(MeshError::NonManifold {
                count: r.non_manifold.len(),
                example,
            });
        }
        if let Some(&example) = r.inconsistent.first() {
            return Err(MeshError::InconsistentWinding {
                count: r.inconsistent.len(),
                example,
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::DVec3;

    fn tet(tris: Vec<[u32; 3]>) -> TriMesh {
        TriMesh::new(vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z], tris).unwrap()
    }

    #[test]
    fn closed_tetrahedron_has_full_adjacency() {
        let m = tet(vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]);
        let topo = Topology::new(&m);
        topo.check_closed().unwrap();
        assert_eq!(topo.report.edges, 6);
        assert!(topo.neighbors.iter().flatten().all(|&n| n != NO_NEIGHBOR));
    }

    #[test]
    fn open_and_flipped_meshes_are_reported() {
        let open = tet(vec![[0, 2, 1], [0, 1, 3], [0, 3, 2]]);
        assert!(matches!(
            Topology::new(&open).check_closed(),
            Err(MeshError::Open {
                boundary_edges: 3,
                ..
            })
        ));
        let flipped = tet(vec![[0, 1, 2], [0, 1, 3], [0, 3, 2], [1, 2, 3]]);
        assert!(matches!(
            Topology::new(&flipped).check_closed(),
            Err(MeshError::InconsistentWinding { .. })
        ));
    }
}
