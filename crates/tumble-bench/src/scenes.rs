//! The standard scenes of `shared/scenes.md` as plain f64 data, for the Rust peers
//! (Rapier, parry). The tori poses and the torus mesh come from `tumble::scenes` and
//! `tumble::collide::mesh` (one home); the pyramid, pile, cradle and chain data still
//! mirror `tumble::scenes` and `bench/peers/common.py` line for line (to be read from
//! `tumble::scenes` too: issue 17).

use std::f64::consts::PI;

/// Pyramid ground: static box (half extents, centre), top face at z = 0.
pub const PYRAMID_GROUND: ([f64; 3], [f64; 3]) = ([50.0, 50.0, 0.5], [0.0, 0.0, -0.5]);
/// Pyramid cube half extent (m); mass 1 kg, i.e. density 1 kg/m^3.
pub const PYRAMID_HALF: f64 = 0.5;
/// Time step of pyramid and pile (s).
pub const DT: f64 = 1.0 / 60.0;
/// Full length of pyramid and pile (steps).
pub const FULL_STEPS: usize = 600;
/// Pile sphere radius / cube half extent (m).
pub const PILE_SIZE: f64 = 0.25;
/// Number of tori poses.
pub use tumble::scenes::TORI_POSES;
/// Cradle sphere radius (m); every sphere has mass 1 kg.
pub const CRADLE_R: f64 = 0.1;
/// Cradle time step (s) and full length (steps): 1 s.
pub const CRADLE_DT: f64 = 1.0 / 240.0;
/// Full length of the cradle (steps).
pub const CRADLE_STEPS: usize = 240;

/// The cradle's six spheres as (centre, velocity): five at rest in a row,
/// touching, and the striker last, at 1 m/s towards them.
pub fn cradle_spheres() -> Vec<([f64; 3], [f64; 3])> {
    let mut out: Vec<_> = (0..5).map(|i| ([0.2 * i as f64, 0.0, 0.0], [0.0; 3])).collect();
    out.push(([-0.5, 0.0, 0.0], [1.0, 0.0, 0.0]));
    out
}

/// The 210 pyramid box centres, layer by layer, k ascending (top box last).
pub fn pyramid_boxes() -> Vec<[f64; 3]> {
    pyramid_boxes_with_base(20)
}

/// Ground of the large pyramid: half extents and centre (m).
pub const LARGE_PYRAMID_GROUND: ([f64; 3], [f64; 3]) = ([100.0, 100.0, 0.5], [0.0, 0.0, -0.5]);

/// Centres of the pyramid's boxes for a base of `base` boxes, layer by
/// layer (base 20: the pyramid; base 100: the large pyramid, 5,050 boxes).
pub fn pyramid_boxes_with_base(base: usize) -> Vec<[f64; 3]> {
    let mut out = Vec::with_capacity(base * (base + 1) / 2);
    for i in 0..base {
        let n = base - i;
        for k in 0..n {
            out.push([(k as f64 - (n - 1) as f64 / 2.0) * 1.05, 0.0, 0.5 + i as f64]);
        }
    }
    out
}

/// Pile body shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PileShape {
    /// Sphere of radius [`PILE_SIZE`].
    Sphere,
    /// Cube of half extent [`PILE_SIZE`].
    Cube,
}

/// Pile bodies (shape, centre) for `n` bodies; `None` unless `n` is a positive multiple of 100.
pub fn pile_bodies(n: usize) -> Option<Vec<(PileShape, [f64; 3])>> {
    if n == 0 || !n.is_multiple_of(100) {
        return None;
    }
    let mut out = Vec::with_capacity(n);
    for k in 0..n / 100 {
        let o = if k % 2 == 1 { 0.1 } else { 0.0 };
        for j in 0..10 {
            for i in 0..10 {
                let c = [
                    -2.7 + 0.6 * i as f64 + o,
                    -2.7 + 0.6 * j as f64 + o,
                    1.0 + 0.6 * k as f64,
                ];
                let shape = if (i + j + k) % 2 == 0 {
                    PileShape::Sphere
                } else {
                    PileShape::Cube
                };
                out.push((shape, c));
            }
        }
    }
    Some(out)
}

/// Static container boxes (half extents, centre) for the `n`-body pile. Walls are 8 m high
/// up to N = 1000 and raised to reach 1 m above the top layer's centre beyond (as in
/// common.py).
pub fn pile_container(n: usize) -> Vec<([f64; 3], [f64; 3])> {
    let layers = (n / 100).max(1);
    let top = 1.0 + 0.6 * (layers - 1) as f64;
    let hz = f64::max(4.0, (top + 1.0) / 2.0);
    vec![
        ([3.5, 3.5, 0.5], [0.0, 0.0, -0.5]),
        ([0.25, 3.5, hz], [3.25, 0.0, hz]),
        ([0.25, 3.5, hz], [-3.25, 0.0, hz]),
        ([3.0, 0.25, hz], [0.0, 3.25, hz]),
        ([3.0, 0.25, hz], [0.0, -3.25, hz]),
    ]
}

/// Bodies outside the container (|x| or |y| > 3.01 or z < 0).
pub fn pile_outside(positions: &[[f64; 3]]) -> usize {
    positions
        .iter()
        .filter(|p| p[0].abs() > 3.01 || p[1].abs() > 3.01 || p[2] < 0.0)
        .count()
}

/// Chain link major radius R and tube radius r (m).
pub const CHAIN_RADII: (f64, f64) = (1.0, 0.2);
/// Chain link mass (kg): 2 pi^2 R r^2 (density 1).
pub const CHAIN_MASS: f64 = 2.0 * PI * PI * CHAIN_RADII.0 * CHAIN_RADII.1 * CHAIN_RADII.1;
/// Chain interlock bound (m): adjacent centres never further apart than 2R - 2r + 0.2.
pub const CHAIN_MAX_GAP: f64 = 2.0 * CHAIN_RADII.0 - 2.0 * CHAIN_RADII.1 + 0.2;

/// Principal inertia of the solid torus link about its own axes (kg m^2):
/// Ixx = Iyy = m (R^2/2 + 5 r^2/8), Izz = m (R^2 + 3 r^2/4).
pub fn chain_inertia() -> [f64; 3] {
    let (big_r, r) = CHAIN_RADII;
    let ixx = CHAIN_MASS * (big_r * big_r / 2.0 + 5.0 * r * r / 8.0);
    [ixx, ixx, CHAIN_MASS * (big_r * big_r + 3.0 * r * r / 4.0)]
}

/// The 21 chain links (centre, quaternion x y z w); link 0 is the static anchor.
pub fn chain_links() -> Vec<([f64; 3], [f64; 4])> {
    let th = PI / 3.0;
    let e = [-th.sin(), 0.0, -th.cos()];
    let ry = quat_axis_angle([0.0, 1.0, 0.0], th);
    let rx = quat_axis_angle([1.0, 0.0, 0.0], PI / 2.0);
    let rz = quat_axis_angle([0.0, 0.0, 1.0], PI / 2.0);
    (0..21)
        .map(|k| {
            let s = 1.5 * k as f64;
            let q = if k % 2 == 0 {
                quat_mul(ry, rx)
            } else {
                quat_mul(ry, quat_mul(rz, rx))
            };
            ([s * e[0], s * e[1], s * e[2]], q)
        })
        .collect()
}

/// `torus_mesh(R, r, n_major, n_minor)` of scenes.md as plain vertices and CCW
/// triangles: `tumble_collide::mesh::torus_mesh`, the very mesh tumble uses.
pub fn torus_mesh(big_r: f64, r: f64, n_major: u32, n_minor: u32) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mesh = tumble::collide::mesh::torus_mesh(big_r, r, n_major as usize, n_minor as usize)
        .expect("the scenes' tori are valid");
    (
        mesh.vertices().iter().map(|v| v.to_array()).collect(),
        mesh.triangles().to_vec(),
    )
}

/// Quaternion (x, y, z, w) of a rotation by `angle` rad about a unit `axis`.
pub fn quat_axis_angle(axis: [f64; 3], angle: f64) -> [f64; 4] {
    let s = (angle / 2.0).sin();
    [axis[0] * s, axis[1] * s, axis[2] * s, (angle / 2.0).cos()]
}

/// Hamilton product `a * b` (applies b first), quaternions (x, y, z, w).
pub fn quat_mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let [ax, ay, az, aw] = a;
    let [bx, by, bz, bw] = b;
    [
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    ]
}

/// Pose of torus B at tori pose `k` (0..200) as (translation, quaternion x y z
/// w): `tumble::scenes::tori_pose`, the poses tumble itself is timed on.
pub fn tori_pose(k: usize) -> ([f64; 3], [f64; 4]) {
    let p = tumble::scenes::tori_pose(k);
    (p.position.to_array(), p.rotation.to_array())
}

pub use tumble::scenes::tori_pose_indices;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pyramid_has_210_boxes_resting_on_each_other() {
        let b = pyramid_boxes();
        assert_eq!(b.len(), 210);
        assert_eq!(*b.last().unwrap(), [0.0, 0.0, 19.5]);
        // Each layer is symmetric about x = 0 and the gap between neighbours is 0.05 m.
        assert!((b[1][0] - b[0][0] - 1.05).abs() < 1e-12);
        assert!((b[0][0] + b[19][0]).abs() < 1e-12);
    }

    #[test]
    fn pile_alternates_shapes_and_container_encloses_every_body() {
        for n in [100, 1000, 10000] {
            let b = pile_bodies(n).unwrap();
            assert_eq!(b.len(), n);
            let spheres = b.iter().filter(|(s, _)| *s == PileShape::Sphere).count();
            assert_eq!(spheres * 2, n);
            let walls = pile_container(n);
            let wall_top = walls[1].1[2] + walls[1].0[2];
            for (_, c) in &b {
                // scenes.md as written: the odd layers' offset o = 0.1 puts the i = 9 / j = 9
                // bodies 0.05 m into the +x / +y walls (inner faces at 3.0 m).
                assert!(c[0].abs() + PILE_SIZE <= 3.05 + 1e-9 && c[1].abs() + PILE_SIZE <= 3.05 + 1e-9);
                assert!(c[2] + PILE_SIZE < wall_top);
            }
            let pos: Vec<[f64; 3]> = b.iter().map(|(_, c)| *c).collect();
            assert_eq!(pile_outside(&pos), 0);
        }
        assert!(pile_bodies(150).is_none() && pile_bodies(0).is_none());
    }

    #[test]
    fn torus_mesh_is_outward_with_the_solid_torus_volume() {
        // Signed volume by the divergence theorem approaches 2 pi^2 R r^2 from below.
        let (v, t) = torus_mesh(1.0, 0.3, 50, 50);
        assert_eq!((v.len(), t.len()), (2500, 5000));
        let vol: f64 = t
            .iter()
            .map(|&[a, b, c]| {
                let (p, q, r) = (v[a as usize], v[b as usize], v[c as usize]);
                (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0])
                    + p[2] * (q[0] * r[1] - q[1] * r[0]))
                    / 6.0
            })
            .sum();
        let exact = 2.0 * PI * PI * 0.3 * 0.3;
        assert!(
            vol > 0.0 && vol < exact && vol > 0.99 * exact,
            "volume {vol} vs {exact}"
        );
    }

    #[test]
    fn chain_starts_interlocked_with_the_solid_torus_mass() {
        let links = chain_links();
        assert_eq!(links.len(), 21);
        for w in links.windows(2) {
            let d = ((w[0].0[0] - w[1].0[0]).powi(2) + (w[0].0[2] - w[1].0[2]).powi(2)).sqrt();
            assert!((d - 1.5).abs() < 1e-12 && d < CHAIN_MAX_GAP);
        }
        assert!((CHAIN_MASS - 0.78957).abs() < 1e-5);
        let i = chain_inertia();
        assert!((i[0] - 0.41452).abs() < 1e-5 && (i[2] - 0.81326).abs() < 1e-5);
    }

    #[test]
    fn tori_poses_span_the_path_and_rotate_the_ring_into_xz() {
        assert_eq!(tori_pose(0).0[0], -3.0);
        assert!((tori_pose(199).0[0] - 3.0).abs() < 1e-12);
        assert_eq!(tori_pose_indices(200), (0..200).collect::<Vec<_>>());
        assert_eq!(tori_pose_indices(5), vec![0, 50, 100, 149, 199]);
        // Rx(pi/2) maps the ring axis z to -y; Rz(0.1) then turns it to (sin 0.1, -cos 0.1, 0).
        let [x, y, z, w] = tori_pose(0).1;
        // Third column of the rotation matrix of (x, y, z, w) = image of the z axis.
        let axis = [
            2.0 * (x * z + y * w),
            2.0 * (y * z - x * w),
            1.0 - 2.0 * (x * x + y * y),
        ];
        let want = [0.1f64.sin(), -(0.1f64.cos()), 0.0];
        for (a, b) in axis.iter().zip(want) {
            assert!((a - b).abs() < 1e-12, "{axis:?} vs {want:?}");
        }
    }
}
