//! The smooth surface a tessellated mesh stands for: a unit normal at every
//! triangle corner, the angle-weighted mean (Thürmer & Wüthrich 1998) of the
//! face normals around its vertex that are reached without crossing a
//! crease. An edge is a crease when its two faces meet at more than the
//! crease angle (a box's edges, a cup's rim) or it has one face only; the
//! corners on either side of a crease keep their own normals, so sharp
//! features stay sharp while a bowl's or a sphere's facets blend into one
//! curved surface. Spheres and capsules touch that surface
//! (`narrow::contact_sphere_mesh`, `contact_capsule_mesh`, through
//! `triangle::phong`); meshes still touch meshes triangle against triangle.

use crate::math::{DMat3, DVec3};
use crate::mesh::topology::{Topology, NO_NEIGHBOR};
use crate::mesh::TriMesh;
use crate::triangle::{phong_point, PHONG_SHAPE_FACTOR};

/// Corner normals and creases of one mesh (shape frame).
#[derive(Debug, Clone, PartialEq)]
pub struct SmoothSurface {
    crease_angle: f64,
    /// `normals[t][k]`: the unit normal at corner `k` of triangle `t`.
    normals: Vec<[DVec3; 3]>,
    /// Bit `k` of entry `t`: edge `k` of triangle `t` is a crease (or a
    /// boundary): the smooth surface ends there.
    creases: Vec<u8>,
    /// The farthest the smooth surface lies from the flat triangles (m): a
    /// bound, for searches that find triangles by their flat distance.
    reach: f64,
}

impl SmoothSurface {
    /// The corner normals of `mesh` blended across every edge whose faces
    /// meet at no more than `crease_angle` (radians, in (0, pi)); the caller
    /// checks the angle.
    pub(crate) fn new(mesh: &TriMesh, topology: &Topology, crease_angle: f64) -> SmoothSurface {
        let tris = mesh.triangles();
        let face: Vec<DVec3> = (0..tris.len())
            .map(|t| mesh.triangle_normal_scaled(t).normalize_or_zero())
            .collect();
        let min_cos = crease_angle.cos();
        // An edge is blended only between consistently wound neighbours
        // (the neighbour runs it the other way): across a flipped face the
        // fan walk below would never come round.
        let consistent = |t: usize, k: usize, other: usize| {
            let (a, b) = (tris[t][k], tris[t][(k + 1) % 3]);
            (0..3).any(|j| tris[other][j] == b && tris[other][(j + 1) % 3] == a)
        };
        let creases: Vec<u8> = topology
            .neighbors
            .iter()
            .enumerate()
            .map(|(t, nb)| {
                let mut bits = 0;
                for (k, &other) in nb.iter().enumerate() {
                    if other == NO_NEIGHBOR
                        || !consistent(t, k, other as usize)
                        || face[t].dot(face[other as usize]) < min_cos
                    {
                        bits |= 1 << k;
                    }
                }
                bits
            })
            .collect();
        // The corner's angle weighs its face (a fan of thin triangles counts
        // as much as one wide one over the same angle).
        let weighted = |t: usize, k: usize| {
            let p = mesh.triangle(t);
            let (a, b) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
            face[t] * a.angle_between(b)
        };
        let corner_of = |t: usize, v: u32| tris[t].iter().position(|&x| x == v);
        let mut normals = Vec::with_capacity(tris.len());
        for t in 0..tris.len() {
            let mut corners = [DVec3::ZERO; 3];
            for (k, corner) in corners.iter_mut().enumerate() {
                let v = tris[t][k];
                let mut sum = weighted(t, k);
                // Walk the fan of v both ways from t: forward across the
                // edge leaving v (edge k of the current triangle), back
                // across the edge arriving at v (edge k + 2), stopping at a
                // crease or when the walk comes round to t.
                let mut closed = false;
                for forward in [true, false] {
                    if closed {
                        break;
                    }
                    let (mut at, mut ck) = (t, k);
                    // A fan has fewer triangles than the mesh: the bound
                    // only guards against a walk that cannot come round.
                    for _ in 0..tris.len() {
                        let edge = if forward { ck } else { (ck + 2) % 3 };
                        if creases[at] & (1 << edge) != 0 {
                            break;
                        }
                        let next = topology.neighbors[at][edge] as usize;
                        if next == t {
                            closed = true;
                            break;
                        }
                        let Some(nk) = corner_of(next, v) else { break };
                        sum += weighted(next, nk);
                        (at, ck) = (next, nk);
                    }
                }
                let n = sum.normalize_or_zero();
                *corner = if n == DVec3::ZERO { face[t] } else { n };
            }
            normals.push(corners);
        }
        // |proj_i(P) - P| = |(P - p_i).(n_i - f)| <= longest edge x |n_i - f|.
        let reach = (0..tris.len())
            .map(|t| {
                let p = mesh.triangle(t);
                let longest = (0..3)
                    .map(|k| (p[(k + 1) % 3] - p[k]).length())
                    .fold(0.0, f64::max);
                let tilt = normals[t]
                    .iter()
                    .map(|n| (*n - face[t]).length())
                    .fold(0.0, f64::max);
                PHONG_SHAPE_FACTOR * longest * tilt
            })
            .fold(0.0, f64::max);
        SmoothSurface {
            crease_angle,
            normals,
            creases,
            reach,
        }
    }

    /// Edges whose faces meet at more than this are creases (radians).
    pub fn crease_angle(&self) -> f64 {
        self.crease_angle
    }

    /// The unit normals at the three corners of triangle `t` (shape frame).
    pub fn corner_normals(&self, t: u32) -> &[DVec3; 3] {
        &self.normals[t as usize]
    }

    /// `true` when edge `k` of triangle `t` is a crease or a boundary.
    pub fn is_crease(&self, t: u32, k: usize) -> bool {
        self.creases
            .get(t as usize)
            .is_some_and(|&bits| bits & (1 << k) != 0)
    }

    /// A bound on how far the smooth surface lies from the flat triangles (m).
    pub fn reach(&self) -> f64 {
        self.reach
    }

    /// How the contact normal and gap of a round body turn as it moves over
    /// the smooth surface of triangle `t` of `mesh` (this surface's mesh):
    /// for a centre of curvature at `centre` (shape frame) the symmetric
    /// matrix `K` (1/m, shape frame, zero along the normal) with which a
    /// displacement `d` of that centre gives the normal `normalize(n + K d)`
    /// and the gap `gap + n . d + d . K d / 2`, to second order in `d`.
    /// `None` when `centre` has no foot over `t` (the contact belongs to a
    /// neighbour or to a crease, whose flat contact does not turn) or lies
    /// beyond a focal point of the surface.
    ///
    /// The surface's shape operator `W` (the Weingarten map, `dn = W dp`
    /// along it; do Carmo, Differential Geometry of Curves and Surfaces,
    /// 3-2) comes from the interpolated normals over the flat triangle:
    /// `dn/du_i = (I - n n^T)(n_i - n_0) / |N|` over its edge vectors. The
    /// centre lies `h` along the normal from its foot `p` (`c = p + h n`),
    /// so it moves `(I + h W) dp` when the foot moves `dp`, and
    /// `K = W (I + h W)^-1`: a ball of radius r in a bowl of radius R gets
    /// `-1 / (R - r)` across its tangent plane, the curvature of the sphere
    /// its centre runs on.
    pub fn path_curvature(&self, mesh: &TriMesh, t: u32, centre: DVec3) -> Option<DMat3> {
        let n = self.normals.get(t as usize)?;
        let p = mesh.triangle(t as usize);
        let foot = phong_point(centre, &p, n)?;
        if !foot.is_over() {
            return None;
        }
        let [_, v, w] = foot.barycentric;
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        let flat = p[0] + e1 * v + e2 * w;
        let interpolated = n[0] + (n[1] - n[0]) * v + (n[2] - n[0]) * w;
        let (unit, length) = (foot.normal, interpolated.length());
        let along = |d: DVec3| (d - unit * unit.dot(d)) / length;
        let (dn_v, dn_w) = (along(n[1] - n[0]), along(n[2] - n[0]));
        let (g11, g12, g22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let det = g11 * g22 - g12 * g12;
        if det.is_nan() || det <= 0.0 {
            return None;
        }
        // W on the tangent basis (t1, t2): the normal's change for a unit
        // move along t_j, read along t_i.
        let (t1, t2) = unit.any_orthonormal_pair();
        let turn = |dir: DVec3| {
            let (a, b) = (e1.dot(dir), e2.dot(dir));
            let (dv, dw) = ((g22 * a - g12 * b) / det, (g11 * b - g12 * a) / det);
            dn_v * dv + dn_w * dw
        };
        let (w1, w2) = (turn(t1), turn(t2));
        let off = 0.5 * (t1.dot(w2) + t2.dot(w1));
        let w = [[t1.dot(w1), off], [off, t2.dot(w2)]];
        // K = W (I + h W)^-1; the two commute, so K is symmetric. h is the
        // centre's height over the flat foot W was taken along (not over
        // the tessellated surface: c = p + h n holds for the flat p).
        let h = (centre - flat).dot(unit);
        let m = [[1.0 + h * w[0][0], h * w[0][1]], [h * w[1][0], 1.0 + h * w[1][1]]];
        let det_m = m[0][0] * m[1][1] - m[0][1] * m[1][0];
        if det_m.is_nan() || det_m <= 1e-6 {
            return None;
        }
        let inv = [
            [m[1][1] / det_m, -m[0][1] / det_m],
            [-m[1][0] / det_m, m[0][0] / det_m],
        ];
        let k = |i: usize, j: usize| w[i][0] * inv[0][j] + w[i][1] * inv[1][j];
        let (k11, k12, k22) = (k(0, 0), 0.5 * (k(0, 1) + k(1, 0)), k(1, 1));
        let outer = |a: DVec3, b: DVec3| DMat3::from_cols(a * b.x, a * b.y, a * b.z);
        Some(outer(t1, t1) * k11 + (outer(t1, t2) + outer(t2, t1)) * k12 + outer(t2, t2) * k22)
    }

    /// Bytes held (the corner normals and crease flags).
    pub fn memory_bytes(&self) -> usize {
        self.normals.len() * std::mem::size_of::<[DVec3; 3]>() + self.creases.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{bowl_mesh, box_mesh, uv_sphere_mesh};

    fn surface(mesh: &TriMesh, degrees: f64) -> SmoothSurface {
        SmoothSurface::new(mesh, &Topology::new(mesh), degrees.to_radians())
    }

    /// A UV sphere's corner normals are radial (to the facets' size), and
    /// no edge is a crease.
    #[test]
    fn a_tessellated_sphere_blends_into_radial_normals() {
        let mesh = uv_sphere_mesh(1.0, 32, 16).unwrap();
        let s = surface(&mesh, 30.0);
        for t in 0..mesh.triangles().len() {
            for (k, &v) in mesh.triangles()[t].iter().enumerate() {
                let radial = mesh.vertices()[v as usize].normalize();
                assert!((s.corner_normals(t as u32)[k] - radial).length() < 0.01);
                assert!(!s.is_crease(t as u32, k));
            }
        }
        // The facets span 11 degrees: the sagitta bound is a few mm.
        assert!(s.reach() > 0.0 && s.reach() < 0.02, "{}", s.reach());
    }

    /// A box keeps its faces flat: every corner normal is its face's, the
    /// twelve outer edges are creases and the diagonals are not.
    #[test]
    fn a_box_stays_sharp() {
        let mesh = box_mesh(DVec3::new(1.0, 2.0, 0.5)).unwrap();
        let s = surface(&mesh, 30.0);
        let mut creases = 0;
        for t in 0..12u32 {
            let face = mesh.triangle_normal_scaled(t as usize).normalize();
            for k in 0..3 {
                assert!((s.corner_normals(t)[k] - face).length() < 1e-15);
                creases += s.is_crease(t, k) as usize;
            }
        }
        assert_eq!(creases, 12 * 2, "each triangle has two outer edges");
        assert_eq!(s.reach(), 0.0);
    }

    /// Inside a tessellated bowl a ball's centre runs on the sphere of
    /// radius R - h: K is -1 / (R - h) across the tangent plane; in a
    /// half-pipe that holds across the trough and is zero along it; over
    /// a flat face it is zero.
    #[test]
    fn path_curvature_is_that_of_the_centre_s_sphere_or_cylinder() {
        let mesh = bowl_mesh(0.5, 0.05, 96, 48).unwrap();
        let s = surface(&mesh, 30.0);
        let mut checked = 0;
        for t in (0..mesh.triangles().len() as u32).step_by(97) {
            let p = mesh.triangle(t as usize);
            let mid = (p[0] + p[1] + p[2]) / 3.0;
            if (mid.length() - 0.5).abs() > 0.01 || mid.z > -0.05 {
                continue; // outside, or the rim
            }
            let centre = mid.normalize() * 0.45;
            let k = s.path_curvature(&mesh, t, centre).unwrap();
            let n = -centre.normalize();
            let want = (DMat3::IDENTITY - DMat3::from_cols(n * n.x, n * n.y, n * n.z)) * (-1.0 / 0.45);
            let err = (0..3)
                .map(|i| (k.col(i) - want.col(i)).length())
                .fold(0.0, f64::max);
            assert!(err < 0.05 * (1.0 / 0.45), "triangle {t}: {k:?} vs {want:?}");
            checked += 1;
        }
        assert!(checked > 50, "{checked}");
        let pipe = crate::mesh::half_pipe_mesh(0.5, 0.05, 1.0, 64).unwrap();
        let s = surface(&pipe, 30.0);
        let t = (0..pipe.triangles().len() as u32)
            .find(|&t| {
                let p = pipe.triangle(t as usize);
                let mid = (p[0] + p[1] + p[2]) / 3.0;
                mid.z < -0.45 && mid.y.abs() < 0.1 && mid.x.abs() < 0.3
            })
            .unwrap();
        let p = pipe.triangle(t as usize);
        let mid = (p[0] + p[1] + p[2]) / 3.0;
        let centre = DVec3::new(mid.x, 0.0, 0.0) + DVec3::new(0.0, mid.y, mid.z).normalize() * 0.45;
        let k = s.path_curvature(&pipe, t, centre).unwrap();
        assert!((k * DVec3::X).length() < 1e-9, "none along the axis: {k:?}");
        let across = DVec3::X.cross(DVec3::new(0.0, centre.y, centre.z).normalize());
        assert!((across.dot(k * across) + 1.0 / 0.45).abs() < 0.05 / 0.45, "{k:?}");
        // A flat face: no curvature.
        let cube = box_mesh(DVec3::splat(1.0)).unwrap();
        let s = surface(&cube, 30.0);
        let k = s.path_curvature(&cube, 0, DVec3::new(0.1, 0.2, -1.3)).unwrap();
        assert!((0..3).all(|i| k.col(i).length() < 1e-12), "{k:?}");
    }

    /// The bowl's rim is a crease: the inside's top corners keep the
    /// sphere's horizontal normal, the rim's corners its +z.
    #[test]
    fn a_bowl_blends_inside_and_keeps_its_rim() {
        let mesh = bowl_mesh(0.5, 0.05, 24, 6).unwrap();
        let s = surface(&mesh, 30.0);
        for t in 0..mesh.triangles().len() {
            let face = mesh.triangle_normal_scaled(t).normalize();
            for (k, &v) in mesh.triangles()[t].iter().enumerate() {
                let p = mesh.vertices()[v as usize];
                let n = s.corner_normals(t as u32)[k];
                if (p.length() - 0.5).abs() < 1e-12 && face.dot(-p.normalize()) > 0.5 {
                    // Inside: towards the sphere's centre; on the rim, the
                    // mean of the top ring's faces only, tilted up by half
                    // a ring (7.5 degrees).
                    let within = if p.z.abs() < 1e-12 { 0.14 } else { 0.02 };
                    assert!((n + p.normalize()).length() < within, "{t} {k}: {n:?} at {p:?}");
                } else if face.z > 0.999 {
                    assert!((n - DVec3::Z).length() < 1e-12);
                }
            }
        }
    }
}
