//! concave_pile (issue 15): closed concave bodies of five kinds dropped into
//! a concave static bin, every body a plain triangle mesh (no convex
//! decomposition): tori, cups made by revolving a wall profile, L-brackets
//! and six-armed jacks made of cubes, and a lumpy organic blob of about
//! 4,000 triangles. The meshes are built here (the jack and the bracket as
//! the outer faces of a set of cubes, the cup as a surface of revolution,
//! the blob as a displaced UV sphere), so every engine gets the same ones
//! through the scene export.

use super::{ten_seconds_without_sleep, Scene};
use crate::world::BodyDesc;
use std::collections::HashMap;
use tumble_collide::mesh::{revolved_mesh, torus_mesh, uv_sphere_mesh, TriMesh};
use tumble_collide::shape::{MeshShape, Shape};
use tumble_collide::{DQuat, DVec3, Pose};

/// Bodies in the standard concave pile.
pub const CONCAVE_PILE_BODIES: usize = 200;
/// Half width of the bin's inside (m): its inner walls stand at x, y = +-0.8.
pub const CONCAVE_BIN_INNER_HALF_WIDTH: f64 = 0.8;
/// Height of the bin's walls above its floor (m); the floor's top is z = 0.
pub const CONCAVE_BIN_WALL_HEIGHT: f64 = 1.2;

/// The kinds of body, in the order the pile cycles through them.
pub const CONCAVE_KINDS: [&str; 5] = ["torus", "cup", "bracket", "jack", "blob"];

/// concave_pile: `n` bodies (kinds in [`CONCAVE_KINDS`] order, body `k` of
/// kind `k mod 5`, density 1000 kg/m^3, friction 0.5) in layers of 5 x 5 on
/// a 0.3 m grid from z = 0.3 m up, each turned by `x(0.7 k) z(1.3 k)`,
/// above the bin ([`concave_bin`], static, body 0); dt 1/60, sleeping off,
/// 600 steps. A body has escaped when its centre leaves the bin's inside or
/// drops below its floor.
pub fn concave_pile(n: usize) -> Scene {
    let kinds: Vec<Shape> = concave_kind_meshes()
        .into_iter()
        .map(|m| Shape::Mesh(MeshShape::new(m).expect("a valid closed mesh")))
        .collect();
    let bin = Shape::Mesh(MeshShape::new(concave_bin()).expect("a valid closed bin"));
    let mut bodies = vec![BodyDesc::fixed(bin).named("bin")];
    for k in 0..n {
        let (layer, cell) = (k / 25, k % 25);
        let at = DVec3::new(
            -0.6 + 0.3 * (cell % 5) as f64,
            -0.6 + 0.3 * (cell / 5) as f64,
            0.3 + 0.3 * layer as f64,
        );
        let turn = DQuat::from_rotation_x(0.7 * k as f64) * DQuat::from_rotation_z(1.3 * k as f64);
        bodies.push(
            BodyDesc::dynamic(kinds[k % kinds.len()].clone())
                .with_pose(Pose {
                    position: at,
                    rotation: turn,
                })
                .with_density(1000.0)
                .named(CONCAVE_KINDS[k % CONCAVE_KINDS.len()]),
        );
    }
    ten_seconds_without_sleep("concave_pile", bodies)
}

/// Dynamic bodies whose centre is outside the bin's inside: beyond its inner
/// walls, or below its floor (or not finite).
pub fn concave_pile_escaped(centres: &[DVec3]) -> usize {
    let w = CONCAVE_BIN_INNER_HALF_WIDTH;
    centres
        .iter()
        .filter(|c| !c.is_finite() || c.x.abs() > w || c.y.abs() > w || c.z < 0.0)
        .count()
}

/// The five body meshes, in [`CONCAVE_KINDS`] order, each in its own frame.
pub fn concave_kind_meshes() -> Vec<TriMesh> {
    // A torus: 0.1 m ring of 0.035 m tube (576 triangles).
    let torus = torus_mesh(0.1, 0.035, 24, 12).expect("valid torus");
    // A cup: outer radius 0.09 m, height 0.18 m, wall and bottom 0.012 m.
    let (r, h, t) = (0.09, 0.18, 0.012);
    // (Centred on half its height, so that it turns within the drop grid.)
    let z = |z: f64| z - 0.5 * h;
    let cup = revolved_mesh(
        &[
            (0.0, z(0.0)),
            (r, z(0.0)),
            (r, z(h)),
            (r - t, z(h)),
            (r - t, z(t)),
            (0.0, z(t)),
        ],
        24,
    )
    .expect("a valid cup profile");
    // An L-bracket of 0.05 m cubes: a 4-long foot and a 3-high upright, 2 deep.
    let mut bracket = Vec::new();
    for y in 0..2 {
        for x in 0..4 {
            bracket.push([x, y, 0]);
        }
        for z in 1..4 {
            bracket.push([0, y, z]);
        }
    }
    let bracket = voxel_mesh(&bracket, 0.05);
    // A jack: a centre cube and six arms of two cubes, 0.045 m cubes.
    let mut jack = vec![[0, 0, 0]];
    for axis in 0..3 {
        for sign in [-1, 1] {
            for len in 1..=2 {
                let mut c = [0, 0, 0];
                c[axis] = sign * len;
                jack.push(c);
            }
        }
    }
    let jack = voxel_mesh(&jack, 0.045);
    vec![torus, cup, bracket, jack, blob_mesh()]
}

/// The bin: a box with a square cavity open at the top, walls and floor
/// 0.1 m thick (floor top at z = 0, walls [`CONCAVE_BIN_WALL_HEIGHT`] high,
/// inside 2 x [`CONCAVE_BIN_INNER_HALF_WIDTH`] square), as 14 quads (28
/// triangles), world frame. Few, large triangles: a wall is one face.
pub fn concave_bin() -> TriMesh {
    let (w, t, h) = (CONCAVE_BIN_INNER_HALF_WIDTH, 0.1, CONCAVE_BIN_WALL_HEIGHT);
    let a = w + t;
    let p = DVec3::new;
    // Each quad counter-clockwise seen from the side it faces.
    let quads = [
        // Outside: bottom, +x, -x, +y, -y.
        [p(-a, -a, -t), p(-a, a, -t), p(a, a, -t), p(a, -a, -t)],
        [p(a, -a, -t), p(a, a, -t), p(a, a, h), p(a, -a, h)],
        [p(-a, -a, -t), p(-a, -a, h), p(-a, a, h), p(-a, a, -t)],
        [p(-a, a, -t), p(-a, a, h), p(a, a, h), p(a, a, -t)],
        [p(-a, -a, -t), p(a, -a, -t), p(a, -a, h), p(-a, -a, h)],
        // The rim, facing up: +x, -x, +y, -y.
        [p(w, -w, h), p(a, -a, h), p(a, a, h), p(w, w, h)],
        [p(-w, w, h), p(-a, a, h), p(-a, -a, h), p(-w, -w, h)],
        [p(w, w, h), p(a, a, h), p(-a, a, h), p(-w, w, h)],
        [p(-w, -w, h), p(-a, -a, h), p(a, -a, h), p(w, -w, h)],
        // Inside walls, facing the cavity: at +x, -x, +y, -y.
        [p(w, -w, 0.0), p(w, -w, h), p(w, w, h), p(w, w, 0.0)],
        [p(-w, -w, 0.0), p(-w, w, 0.0), p(-w, w, h), p(-w, -w, h)],
        [p(-w, w, 0.0), p(w, w, 0.0), p(w, w, h), p(-w, w, h)],
        [p(-w, -w, 0.0), p(-w, -w, h), p(w, -w, h), p(w, -w, 0.0)],
        // The floor inside, facing up.
        [p(-w, -w, 0.0), p(w, -w, 0.0), p(w, w, 0.0), p(-w, w, 0.0)],
    ];
    let mut index: HashMap<[u64; 3], u32> = HashMap::new();
    let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
    for q in quads {
        let ids: Vec<u32> = q
            .iter()
            .map(|v| {
                *index.entry(v.to_array().map(f64::to_bits)).or_insert_with(|| {
                    vertices.push(*v);
                    (vertices.len() - 1) as u32
                })
            })
            .collect();
        triangles.push([ids[0], ids[1], ids[2]]);
        triangles.push([ids[0], ids[2], ids[3]]);
    }
    TriMesh::new(vertices, triangles).expect("the bin's quads close")
}

/// The outer faces of a set of face-connected cubes of edge `size` (cell
/// `[i, j, k]` spans `[i, i+1] x [j, j+1] x [k, k+1]` times `size`), centred
/// on the cells' bounding box.
fn voxel_mesh(cells: &[[i32; 3]], size: f64) -> TriMesh {
    let (mut lo, mut hi) = ([i32::MAX; 3], [i32::MIN; 3]);
    for c in cells {
        for a in 0..3 {
            lo[a] = lo[a].min(c[a]);
            hi[a] = hi[a].max(c[a] + 1);
        }
    }
    let centre = DVec3::new(
        (lo[0] + hi[0]) as f64,
        (lo[1] + hi[1]) as f64,
        (lo[2] + hi[2]) as f64,
    ) * (0.5 * size);
    // Each face's corners, counter-clockwise seen from outside (its
    // outward axis and sign first).
    const FACES: [([i32; 3], [[i32; 3]; 4]); 6] = [
        ([1, 0, 0], [[1, 0, 0], [1, 1, 0], [1, 1, 1], [1, 0, 1]]),
        ([-1, 0, 0], [[0, 0, 0], [0, 0, 1], [0, 1, 1], [0, 1, 0]]),
        ([0, 1, 0], [[0, 1, 0], [0, 1, 1], [1, 1, 1], [1, 1, 0]]),
        ([0, -1, 0], [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]]),
        ([0, 0, 1], [[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]]),
        ([0, 0, -1], [[0, 0, 0], [0, 1, 0], [1, 1, 0], [1, 0, 0]]),
    ];
    let filled: std::collections::HashSet<[i32; 3]> = cells.iter().copied().collect();
    // Vertices numbered in the order the faces first meet them (the map is
    // only looked up, never iterated: the mesh does not depend on hashing).
    let mut index: HashMap<[i32; 3], u32> = HashMap::new();
    let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
    for c in cells {
        for (dir, corners) in FACES {
            if filled.contains(&[c[0] + dir[0], c[1] + dir[1], c[2] + dir[2]]) {
                continue;
            }
            let ids: Vec<u32> = corners
                .iter()
                .map(|k| {
                    let p = [c[0] + k[0], c[1] + k[1], c[2] + k[2]];
                    *index.entry(p).or_insert_with(|| {
                        vertices.push(DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64) * size - centre);
                        (vertices.len() - 1) as u32
                    })
                })
                .collect();
            triangles.push([ids[0], ids[1], ids[2]]);
            triangles.push([ids[0], ids[2], ids[3]]);
        }
    }
    TriMesh::new(vertices, triangles).expect("the faces of face-connected cubes close")
}

/// A lumpy blob: a UV sphere of radius 0.1 m (64 x 32, 3,968 triangles)
/// with each vertex moved along its direction by up to 40 %, by a smooth
/// function of the direction: lobes and dents, concave between them, and
/// still star-shaped about the centre (so closed and not self-crossing).
fn blob_mesh() -> TriMesh {
    let sphere = uv_sphere_mesh(0.1, 64, 32).expect("valid sphere");
    let vertices = sphere
        .vertices()
        .iter()
        .map(|&v| {
            let d = v / v.length();
            let bump = (4.0 * d.x + 0.4).sin() * (3.0 * d.y + 1.1).sin() * (4.0 * d.z).cos()
                + 0.5 * (6.0 * d.z + 0.3).sin() * (5.0 * d.x).cos();
            v * (1.0 + 0.4 * bump / 1.5)
        })
        .collect();
    TriMesh::new(vertices, sphere.triangles().to_vec()).expect("the displaced sphere stays closed")
}
