//! Flat-shaded vertex streams for a triangle mesh: every triangle gets its own
//! three vertices carrying the face normal, so that renderers which interpolate
//! normals across a triangle still draw crisp facets (a shared vertex would
//! average the normals of its faces and round the edges off).

use tumble_collide::{DVec3, TriMesh};

/// Non-indexed positions and normals, three per triangle, in the body frame.
pub(crate) struct FlatMesh {
    /// Vertex positions (m), `3 * triangle count` of them.
    pub positions: Vec<[f32; 3]>,
    /// Unit face normals, one per vertex.
    pub normals: Vec<[f32; 3]>,
    /// Component-wise minimum of `positions` (glTF requires it for POSITION).
    pub min: [f32; 3],
    /// Component-wise maximum of `positions`.
    pub max: [f32; 3],
}

pub(crate) fn flat_mesh(mesh: &TriMesh) -> FlatMesh {
    let n = 3 * mesh.triangles().len();
    let mut positions = Vec::with_capacity(n);
    let mut normals = Vec::with_capacity(n);
    for t in 0..mesh.triangles().len() {
        let [a, b, c] = mesh.triangle(t);
        // CCW seen from outside, so (b - a) x (c - a) points out. glTF requires
        // unit normals; a zero-area triangle has none, and any unit vector draws
        // it (invisibly) the same.
        let normal = (b - a).cross(c - a).try_normalize().unwrap_or(DVec3::Z);
        for p in [a, b, c] {
            positions.push(p.as_vec3().to_array());
            normals.push(normal.as_vec3().to_array());
        }
    }
    let mut min = [f32::INFINITY; 3];
    let mut max = [f32::NEG_INFINITY; 3];
    for p in &positions {
        for k in 0..3 {
            min[k] = min[k].min(p[k]);
            max[k] = max[k].max(p[k]);
        }
    }
    FlatMesh {
        positions,
        normals,
        min,
        max,
    }
}
