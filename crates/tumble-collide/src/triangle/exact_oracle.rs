//! Test-only exact oracle for triangle intersection, independent of the
//! orientation-sign logic of [`super::tri_tri_overlap`].
//!
//! Two closed triangles meet iff the origin lies in the convex hull of the nine
//! differences `a_i - b_j` (their Minkowski difference). By Caratheodory's
//! theorem the origin then lies in a non-degenerate simplex (point, segment,
//! triangle or tetrahedron) spanned by at most four of those points, so
//! checking all such subsets decides membership. Integer coordinates with i128
//! arithmetic make every step exact. Also: a small deterministic RNG for tests.

/// Integer point.
pub type IVec = [i64; 3];

fn sub(a: IVec, b: IVec) -> [i128; 3] {
    [
        (a[0] - b[0]) as i128,
        (a[1] - b[1]) as i128,
        (a[2] - b[2]) as i128,
    ]
}

fn cross(a: [i128; 3], b: [i128; 3]) -> [i128; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [i128; 3], b: [i128; 3]) -> i128 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn diff(a: [i128; 3], b: [i128; 3]) -> [i128; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

const O: [i128; 3] = [0, 0, 0];

fn det(a: [i128; 3], b: [i128; 3], c: [i128; 3]) -> i128 {
    dot(a, cross(b, c))
}

/// Origin in the closed convex hull of `pts`, exactly.
pub fn origin_in_hull(pts: &[[i128; 3]]) -> bool {
    let n = pts.len();
    if pts.contains(&O) {
        return true;
    }
    for i in 0..n {
        for j in i + 1..n {
            let (p, q) = (pts[i], pts[j]);
            // Origin on segment pq: collinear with it and between the ends.
            if cross(p, q) == O && dot(p, q) <= 0 {
                return true;
            }
            for k in j + 1..n {
                let r = pts[k];
                let nrm = cross(diff(q, p), diff(r, p));
                if nrm != O && det(p, q, r) == 0 {
                    let s = [
                        dot(nrm, cross(q, r)),
                        dot(nrm, cross(r, p)),
                        dot(nrm, cross(p, q)),
                    ];
                    if s.iter().all(|&x| x >= 0) {
                        return true;
                    }
                }
                for &w in &pts[k + 1..] {
                    let vol = det(diff(q, p), diff(r, p), diff(w, p));
                    if vol == 0 {
                        continue;
                    }
                    // Volumes with the origin replacing each corner; they sum to vol.
                    let sub_vols = [
                        det(q, r, w),
                        det(diff(q, p), diff(r, p), diff(O, p)),
                        det(diff(q, p), diff(O, p), diff(w, p)),
                        det(diff(O, p), diff(r, p), diff(w, p)),
                    ];
                    // det(q - 0, r - 0, w - 0) is the volume of (0, q, r, w).
                    if sub_vols.iter().all(|&x| x == 0 || (x > 0) == (vol > 0)) {
                        return true;
                    }
                }
            }
        }
    }
    false
}

/// Exact closed triangle-triangle intersection of integer triangles.
pub fn exact_tri_tri(a: &[IVec; 3], b: &[IVec; 3]) -> bool {
    let mut pts = [[0i128; 3]; 9];
    for i in 0..3 {
        for j in 0..3 {
            pts[3 * i + j] = sub(a[i], b[j]);
        }
    }
    origin_in_hull(&pts)
}

/// Convert an integer point to floating point (exact for small integers).
pub fn to_f(p: IVec) -> crate::math::DVec3 {
    crate::math::DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)
}
