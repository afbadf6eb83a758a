//! Convex hull of a point set: 3D quickhull (Barber, Dobkin & Huhdanpaa, "The
//! Quickhull Algorithm for Convex Hulls", ACM TOMS 1996).
//!
//! Start from a tetrahedron of extreme points, give every point to one face it
//! lies strictly outside of (its "outside set"), then repeatedly take the point
//! farthest above some face, delete every face it sees, and close the hole with
//! a fan of new faces from the point to the horizon. Points inside or on the
//! hull (within `eps`) are dropped, so duplicate points, coplanar points on faces
//! and points on edges never become vertices; coplanar facets stay triangulated.
//!
//! Robustness: all distances are measured from a vertex of the face (not from
//! the origin) and compared against `eps = HULL_REL_EPS * diagonal`, a relative
//! tolerance, so the result does not depend on where the cloud sits in space.
//! A point must be more than `eps` above a face to see it; this keeps the
//! visible region a topological disk for all but pathologically noisy input,
//! which is detected (a pinched horizon) and reported as
//! [`HullError::Numerical`] instead of producing a broken mesh.

use crate::math::DVec3;
use crate::mesh::TriMesh;
use crate::triangle::orient::orient3d;

/// Relative tolerance of the hull predicates: points within this fraction of
/// the bounding-box diagonal of a face's plane count as on it.
pub const HULL_REL_EPS: f64 = 1e-10;

/// Why a hull could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HullError {
    /// Fewer than four points, or all points coplanar/collinear.
    #[error("convex hull is degenerate: {0}")]
    Degenerate(String),
    /// A point is not finite.
    #[error("convex hull input point {0} is not finite")]
    NonFinite(usize),
    /// More points than 32-bit indices can address.
    #[error("convex hull input too large: {0} points (at most 2^32 - 1)")]
    TooLarge(usize),
    /// Round-off made the visible region of a point non-simple (should only
    /// happen for nearly degenerate, noisy input).
    #[error("convex hull failed numerically: {0}")]
    Numerical(String),
}

/// Convex hull of `points` as a closed, outward-wound triangle mesh whose
/// vertices are (exact copies of) the extreme input points.
pub fn convex_hull(points: &[DVec3]) -> Result<TriMesh, HullError> {
    let faces = hull_triangles(points)?;
    // Compact the vertex set to the points actually used, in input order.
    let mut remap = vec![u32::MAX; points.len()];
    let mut used: Vec<u32> = faces.iter().flatten().copied().collect();
    used.sort_unstable();
    used.dedup();
    let mut vertices = Vec::with_capacity(used.len());
    for (new, &old) in used.iter().enumerate() {
        remap[old as usize] = new as u32;
        vertices.push(points[old as usize]);
    }
    let triangles = faces.iter().map(|f| f.map(|i| remap[i as usize])).collect();
    let mesh = TriMesh::new(vertices, triangles)
        .map_err(|e| HullError::Numerical(format!("hull mesh rejected: {e}")))?;
    // What round-off on extreme input could still break is refused, never
    // handed out as a hull.
    mesh.check_solid()
        .map_err(|e| HullError::Numerical(format!("hull is not a closed outward solid: {e}")))?;
    Ok(mesh)
}

/// The hull's triangles as indices into `points` (outward, counter-clockwise).
/// Used directly by the OBB fitter, which needs no compacted mesh.
pub fn hull_triangles(points: &[DVec3]) -> Result<Vec<[u32; 3]>, HullError> {
    if points.len() > u32::MAX as usize {
        return Err(HullError::TooLarge(points.len()));
    }
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(HullError::NonFinite(i));
    }
    if points.len() < 4 {
        return Err(HullError::Degenerate(format!(
            "{} point(s), need at least 4",
            points.len()
        )));
    }
    let mut hull = Quickhull::new(points)?;
    hull.run()?;
    Ok(hull.output())
}

const NONE: u32 = u32::MAX;

struct Face {
    v: [u32; 3],
    /// Unit outward normal.
    n: DVec3,
    /// `adj[k]`: face across edge `v[k] -> v[k+1]`.
    adj: [u32; 3],
    /// First point of the outside set, linked through `Quickhull::next`
    /// (an intrusive list: no allocation per face).
    outside: u32,
    /// Farthest outside point and its distance.
    far: u32,
    far_dist: f64,
    alive: bool,
    /// Visit stamp of the last visibility search that touched this face.
    stamp: u32,
    visible: bool,
}

struct Quickhull<'a> {
    p: &'a [DVec3],
    eps: f64,
    faces: Vec<Face>,
    /// Next point in the same outside set, per point.
    next: Vec<u32>,
    stamp: u32,
    /// Per point: new face whose horizon edge starts at it (during one step).
    start_face: Vec<u32>,
    start_stamp: Vec<u32>,
}

impl<'a> Quickhull<'a> {
    fn new(p: &'a [DVec3]) -> Result<Self, HullError> {
        let (lo, hi) = p.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &v| (lo.min(v), hi.max(v)),
        );
        let diag = (hi - lo).length();
        // Rounding of a distance computed relative to a face vertex is a few ulp
        // of the coordinates' magnitude; the relative term dominates it for any
        // cloud not absurdly far from the origin.
        let mag = lo.abs().max(hi.abs()).max_element();
        let eps = (HULL_REL_EPS * diag).max(64.0 * f64::EPSILON * mag);
        let mut qh = Quickhull {
            p,
            eps,
            faces: Vec::new(),
            next: vec![NONE; p.len()],
            stamp: 0,
            start_face: vec![NONE; p.len()],
            start_stamp: vec![0; p.len()],
        };
        qh.initial_simplex()?;
        Ok(qh)
    }

    fn dist(&self, f: &Face, i: u32) -> f64 {
        f.n.dot(self.p[i as usize] - self.p[f.v[0] as usize])
    }

    fn make_face(&self, v: [u32; 3]) -> Face {
        let [a, b, c] = v.map(|i| self.p[i as usize]);
        // Cross product of the two edges from the corner opposite the longest
        // edge would be marginally better; the normalised cross of any two
        // edges is accurate to O(eps / area) which the eps test absorbs.
        let n = (b - a).cross(c - a).normalize_or_zero();
        Face {
            v,
            n,
            adj: [NONE; 3],
            outside: NONE,
            far: NONE,
            far_dist: 0.0,
            alive: true,
            stamp: 0,
            visible: false,
        }
    }

    fn initial_simplex(&mut self) -> Result<(), HullError> {
        let p = self.p;
        let eps = self.eps;
        // Extreme points along the axes; the farthest pair among them spans the
        // first edge.
        let mut ext = [0usize; 6];
        for (i, v) in p.iter().enumerate() {
            for k in 0..3 {
                if v[k] < p[ext[2 * k]][k] {
                    ext[2 * k] = i;
                }
                if v[k] > p[ext[2 * k + 1]][k] {
                    ext[2 * k + 1] = i;
                }
            }
        }
        let mut best = (0usize, 0usize, -1.0f64);
        for i in 0..6 {
            for j in i + 1..6 {
                let d = (p[ext[i]] - p[ext[j]]).length_squared();
                if d > best.2 {
                    best = (ext[i], ext[j], d);
                }
            }
        }
        let (i0, i1) = (best.0, best.1);
        if best.2.sqrt() <= eps {
            return Err(HullError::Degenerate("all points coincide".into()));
        }
        let dir = (p[i1] - p[i0]).normalize();
        let (mut i2, mut d2) = (0usize, -1.0f64);
        // The base points themselves are skipped: round-off gives them a
        // distance from their own line or plane, which a cloud flat within
        // the tolerance can make the largest (the apex chosen as one of
        // the base's corners: a "tetrahedron" with a corner twice).
        for (i, v) in p.iter().enumerate().filter(|&(i, _)| i != i0 && i != i1) {
            let w = *v - p[i0];
            let d = (w - dir * w.dot(dir)).length();
            if d > d2 {
                (i2, d2) = (i, d);
            }
        }
        if d2 <= eps {
            return Err(HullError::Degenerate("all points collinear".into()));
        }
        let n = (p[i1] - p[i0]).cross(p[i2] - p[i0]).normalize();
        let (mut i3, mut d3) = (0usize, 0.0f64);
        for (i, v) in p
            .iter()
            .enumerate()
            .filter(|&(i, _)| i != i0 && i != i1 && i != i2)
        {
            let d = n.dot(*v - p[i0]);
            if d.abs() > d3.abs() {
                (i3, d3) = (i, d);
            }
        }
        // The side of the base plane i3 lies on, with its sign exact: the
        // rounded normal of a thin base triangle (one point 6e37 m away, the
        // others within 1.5e28 m of each other:
        // fuzz/regressions/stl/hull_far_sliver) can point the wrong way, and
        // the simplex came out inside out.
        let side = orient3d(p[i0], p[i1], p[i2], p[i3]);
        if d3.abs() <= eps || side == 0.0 {
            return Err(HullError::Degenerate("all points coplanar".into()));
        }
        // Base triangle wound so that its outward normal points away from i3.
        let (a, b, c, d) = if side > 0.0 {
            (i0 as u32, i2 as u32, i1 as u32, i3 as u32)
        } else {
            (i0 as u32, i1 as u32, i2 as u32, i3 as u32)
        };
        // Faces: 0 = abc, 1 = bad, 2 = cbd, 3 = acd... each outward.
        let tris = [[a, b, c], [b, a, d], [c, b, d], [a, c, d]];
        for t in tris {
            let f = self.make_face(t);
            self.faces.push(f);
        }
        self.link_all_initial();
        // Hand every point to the first face it is strictly above.
        let simplex = [a, b, c, d];
        for i in 0..p.len() as u32 {
            if simplex.contains(&i) {
                continue;
            }
            for f in 0..4 {
                let dd = self.dist(&self.faces[f], i);
                if dd > eps {
                    self.add_outside(f, i, dd);
                    break;
                }
            }
        }
        Ok(())
    }

    /// Links the four faces of the initial tetrahedron by brute force.
    fn link_all_initial(&mut self) {
        for f in 0..4 {
            for k in 0..3 {
                let (a, b) = (self.faces[f].v[k], self.faces[f].v[(k + 1) % 3]);
                for g in 0..4 {
                    if g == f {
                        continue;
                    }
                    let gv = self.faces[g].v;
                    if (0..3).any(|m| gv[m] == b && gv[(m + 1) % 3] == a) {
                        self.faces[f].adj[k] = g as u32;
                    }
                }
            }
        }
    }

    fn add_outside(&mut self, f: usize, i: u32, d: f64) {
        let face = &mut self.faces[f];
        self.next[i as usize] = face.outside;
        face.outside = i;
        if d > face.far_dist {
            face.far_dist = d;
            face.far = i;
        }
    }

    fn run(&mut self) -> Result<(), HullError> {
        let mut work: Vec<u32> = (0..self.faces.len() as u32).rev().collect();
        let mut visible: Vec<u32> = Vec::new();
        // (a, b, face across the edge beyond the horizon)
        let mut horizon: Vec<(u32, u32, u32)> = Vec::new();
        let mut dfs: Vec<u32> = Vec::new();
        let mut new_faces: Vec<u32> = Vec::new();
        let mut planes: Vec<(DVec3, f64)> = Vec::new();
        while let Some(f0) = work.pop() {
            let f0 = f0 as usize;
            if !self.faces[f0].alive || self.faces[f0].outside == NONE {
                continue;
            }
            let apex = self.faces[f0].far;
            // Visible region: faces reachable from f0 through faces that see the apex.
            self.stamp += 1;
            let stamp = self.stamp;
            visible.clear();
            horizon.clear();
            dfs.clear();
            self.faces[f0].stamp = stamp;
            self.faces[f0].visible = true;
            dfs.push(f0 as u32);
            while let Some(f) = dfs.pop() {
                visible.push(f);
                for k in 0..3 {
                    let g = self.faces[f as usize].adj[k];
                    let gf = &self.faces[g as usize];
                    if gf.stamp != stamp {
                        let sees = self.dist(gf, apex) > self.eps;
                        let gf = &mut self.faces[g as usize];
                        gf.stamp = stamp;
                        gf.visible = sees;
                        if sees {
                            dfs.push(g);
                        }
                    }
                }
            }
            for &f in &visible {
                let face = &self.faces[f as usize];
                for k in 0..3 {
                    let g = face.adj[k];
                    // Every neighbour of a visible face was stamped by the search.
                    if !self.faces[g as usize].visible {
                        horizon.push((face.v[k], face.v[(k + 1) % 3], g));
                    }
                }
            }
            // Build the fan of new faces from the apex over the horizon.
            new_faces.clear();
            for &(a, b, g) in &horizon {
                if self.start_stamp[a as usize] == stamp {
                    return Err(HullError::Numerical(format!(
                        "horizon of point {apex} passes vertex {a} twice"
                    )));
                }
                let mut face = self.make_face([a, b, apex]);
                face.adj[0] = g;
                let id = self.faces.len() as u32;
                self.faces.push(face);
                // Re-point the neighbour across the horizon edge (b -> a there).
                let gf = &mut self.faces[g as usize];
                for m in 0..3 {
                    if gf.v[m] == b && gf.v[(m + 1) % 3] == a {
                        gf.adj[m] = id;
                    }
                }
                self.start_stamp[a as usize] = stamp;
                self.start_face[a as usize] = id;
                new_faces.push(id);
            }
            // Edge b -> apex of face (a, b) borders the face whose horizon edge
            // starts at b; edge apex -> a borders the face whose edge ends at a.
            for &id in &new_faces {
                let [_, b, _] = self.faces[id as usize].v;
                if self.start_stamp[b as usize] != stamp {
                    return Err(HullError::Numerical(format!(
                        "horizon of point {apex} is not a closed loop at vertex {b}"
                    )));
                }
                let next = self.start_face[b as usize];
                self.faces[id as usize].adj[1] = next;
                self.faces[next as usize].adj[2] = id;
            }
            // Redistribute the outside points of the deleted faces. This is
            // the hot loop of the whole hull: the new planes are copied into a
            // contiguous array (normal, offset) so the test is one dot product
            // over cache-resident data; the offset form loses only ~ulp(|x|),
            // which the magnitude term of eps covers.
            planes.clear();
            planes.extend(new_faces.iter().map(|&nf| {
                let f = &self.faces[nf as usize];
                (f.n, f.n.dot(self.p[f.v[0] as usize]))
            }));
            for &f in &visible {
                self.faces[f as usize].alive = false;
                let mut cursor = std::mem::replace(&mut self.faces[f as usize].outside, NONE);
                while cursor != NONE {
                    let i = cursor;
                    cursor = self.next[i as usize];
                    if i == apex {
                        continue;
                    }
                    let x = self.p[i as usize];
                    for (k, &(n, off)) in planes.iter().enumerate() {
                        let d = n.dot(x) - off;
                        if d > self.eps {
                            self.add_outside(new_faces[k] as usize, i, d);
                            break;
                        }
                    }
                }
            }
            for &nf in new_faces.iter().rev() {
                if self.faces[nf as usize].outside != NONE {
                    work.push(nf);
                }
            }
        }
        Ok(())
    }

    fn output(&self) -> Vec<[u32; 3]> {
        self.faces.iter().filter(|f| f.alive).map(|f| f.v).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{box_mesh, cylinder_mesh, icosphere_mesh, Topology};
    use proptest::prelude::*;

    /// Deterministic pseudo-random generator (SplitMix64) for test clouds.
    use tumble_testkit::splitmix_f64 as rng;

    fn check_hull(points: &[DVec3], hull: &TriMesh) {
        hull.check_solid().unwrap();
        // Every point on the inner side of every face.
        let (lo, hi) = points.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &v| (lo.min(v), hi.max(v)),
        );
        let tol = 1e-9 * (hi - lo).length();
        for t in 0..hull.triangles().len() {
            let [a, b, c] = hull.triangle(t);
            let n = (b - a).cross(c - a).normalize();
            for &p in points {
                assert!(n.dot(p - a) <= tol, "point {p} outside face {t}");
            }
        }
        // Every hull vertex is an input point (bitwise).
        for v in hull.vertices() {
            assert!(points.iter().any(|p| p == v));
        }
        // Euler characteristic of a sphere.
        let topo = Topology::new(hull);
        let (v, e, f) = (
            hull.vertices().len() as i64,
            topo.report.edges as i64,
            hull.triangles().len() as i64,
        );
        assert_eq!(v - e + f, 2);
    }

    #[test]
    fn cube_corners_with_interior_points() {
        let mut r = rng(7);
        let mut pts = Vec::new();
        for i in 0..8 {
            pts.push(DVec3::new(
                if i & 1 == 0 { -1.0 } else { 1.0 },
                if i & 2 == 0 { -1.0 } else { 1.0 },
                if i & 4 == 0 { -1.0 } else { 1.0 },
            ));
        }
        for _ in 0..200 {
            pts.push(DVec3::new(r() * 2.0 - 1.0, r() * 2.0 - 1.0, r() * 2.0 - 1.0) * 0.999);
        }
        // Points on faces and edges, and duplicates, must not become vertices.
        pts.push(DVec3::new(1.0, 0.2, -0.3));
        pts.push(DVec3::new(0.0, 1.0, 1.0));
        pts.push(DVec3::new(1.0, 1.0, 1.0));
        let hull = convex_hull(&pts).unwrap();
        check_hull(&pts, &hull);
        assert_eq!(hull.vertices().len(), 8);
        assert_eq!(hull.triangles().len(), 12);
        assert!((hull.signed_volume() - 8.0).abs() < 1e-12);
    }

    #[test]
    fn hull_of_convex_generators_keeps_volume() {
        for mesh in [
            box_mesh(DVec3::new(0.5, 1.0, 2.0)).unwrap(),
            icosphere_mesh(1.3, 2).unwrap(),
            cylinder_mesh(0.4, 1.1, 24).unwrap(),
        ] {
            let hull = convex_hull(mesh.vertices()).unwrap();
            check_hull(mesh.vertices(), &hull);
            let (a, b) = (hull.signed_volume(), mesh.signed_volume());
            assert!((a - b).abs() <= 1e-12 * b, "{a} vs {b}");
        }
    }

    #[test]
    fn far_from_origin_cloud() {
        let mut r = rng(3);
        let off = DVec3::new(1e5, -2e5, 3e4);
        let pts: Vec<DVec3> = (0..300).map(|_| off + DVec3::new(r(), r(), r())).collect();
        let hull = convex_hull(&pts).unwrap();
        check_hull(&pts, &hull);
    }

    /// A sliver 6e37 m long whose other three corners lie within 1.5e28 m
    /// of each other (libFuzzer, `fuzz/regressions/stl/hull_far_sliver`):
    /// the apex search took a corner of the base for the apex (its distance
    /// from its own plane was round-off, and the largest) and the hull came
    /// out an inside-out "tetrahedron" with a corner twice. It is the
    /// tetrahedron of the four points, outward, of the exact volume
    /// (computed in rationals: 4.5464369807174845e64 / 6 m^3).
    #[test]
    fn a_far_thin_sliver_is_wound_outward() {
        let pts = [
            DVec3::new(
                -1.0695807010028086e37,
                -4.2201683186052844e37,
                -4.2201683186052844e37,
            ),
            DVec3::new(
                2.2009032374370463e-9,
                1.4564867919235908e28,
                1.2971819884254832e-41,
            ),
            DVec3::new(-6.499999761581421e-1, 1.1258330345153809, 0.0),
            DVec3::new(-0.5, 8.660215735435486e-1, 3.0000001192092896e-1),
        ];
        let hull = convex_hull(&pts).unwrap();
        hull.check_solid().unwrap();
        assert_eq!((hull.vertices().len(), hull.triangles().len()), (4, 4));
        let exact = 4.5464369807174845e64 / 6.0;
        assert!(
            (hull.signed_volume() - exact).abs() <= 1e-9 * exact,
            "{}",
            hull.signed_volume()
        );
    }

    #[test]
    fn degenerate_inputs_are_errors() {
        let flat: Vec<DVec3> = (0..20)
            .map(|i| DVec3::new(i as f64 % 5.0, (i / 5) as f64, 0.0))
            .collect();
        assert!(matches!(convex_hull(&flat), Err(HullError::Degenerate(_))));
        let line: Vec<DVec3> = (0..10).map(|i| DVec3::X * i as f64).collect();
        assert!(matches!(convex_hull(&line), Err(HullError::Degenerate(_))));
        let same = vec![DVec3::ONE; 6];
        assert!(matches!(convex_hull(&same), Err(HullError::Degenerate(_))));
        assert!(matches!(
            convex_hull(&[DVec3::ZERO, DVec3::X, DVec3::Y]),
            Err(HullError::Degenerate(_))
        ));
        let bad = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(0.0, f64::NAN, 1.0)];
        assert_eq!(convex_hull(&bad), Err(HullError::NonFinite(3)));
    }

    #[test]
    fn grid_points_with_many_coplanar_and_duplicate_points() {
        let mut pts = Vec::new();
        for i in 0..5 {
            for j in 0..5 {
                for k in 0..5 {
                    let p = DVec3::new(i as f64, j as f64, k as f64) * 0.25;
                    pts.push(p);
                    pts.push(p);
                }
            }
        }
        let hull = convex_hull(&pts).unwrap();
        check_hull(&pts, &hull);
        assert!((hull.signed_volume() - 1.0).abs() < 1e-12);
        assert_eq!(hull.vertices().len(), 8);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]
        #[test]
        fn random_clouds(seed in 0u64..u64::MAX, n in 4usize..400, sphere in any::<bool>()) {
            let mut r = rng(seed);
            let pts: Vec<DVec3> = (0..n)
                .map(|_| {
                    let v = DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5);
                    if sphere { v.normalize_or(DVec3::X) } else { v }
                })
                .collect();
            let hull = convex_hull(&pts).unwrap();
            check_hull(&pts, &hull);
        }
    }
}
