//! Box vs box: separating axis test over the 15 axes (3 + 3 face normals, 9
//! edge cross products; Gottschalk, Lin, Manocha 1996 and Ericson 4.4.1),
//! then the reference-face clipping manifold (up to 4 points) or one
//! edge-edge contact with the corners within the margin, sharing `clip` and the axis choice (face axes preferred
//! within a tolerance) with the generic polytope routine. Why a routine of
//! its own: a box's face normals are its axes, so the 15 axes come from one
//! 3 x 3 rotation without walking faces and edges (several times faster
//! on the stacks); both end in the same `SatResult` and `build_manifold`,
//! which is why their last lines read alike.

use super::contact_polytope_polytope::{build_manifold, SatResult};
use crate::contact::Contact;
use crate::math::{DMat3, DVec3};
use crate::pose::Pose;
use crate::shape::Cuboid;

/// Contacts between box A and box B: up to 4 face contacts, or one edge-edge
/// contact and the corners of either box within the margin of the other.
// The common narrow signature; why a box pair has its own SAT rather than
// `contact_polytope_polytope`'s: see the module docs above.
pub fn contact_cuboid_cuboid(
    a: &Cuboid,
    pose_a: &Pose,
    b: &Cuboid,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    let ha = a.half_extents();
    let hb = b.half_extents();
    let ra = DMat3::from_quat(pose_a.rotation);
    // B's axes in A's frame (columns) and B's centre in A's frame.
    let r = DMat3::from_quat(pose_a.rotation.inverse() * pose_b.rotation);
    let t = ra.transpose() * (pose_b.position - pose_a.position);
    let col = [r.x_axis, r.y_axis, r.z_axis];
    // |R| with a small epsilon against round-off when edges are parallel.
    let abs_col = [col[0].abs() + 1e-14, col[1].abs() + 1e-14, col[2].abs() + 1e-14];

    // A's faces: separation along e_i.
    let mut sep_a = f64::NEG_INFINITY;
    let mut face_a = 0;
    for i in 0..3 {
        let rb = hb.x * abs_col[0][i] + hb.y * abs_col[1][i] + hb.z * abs_col[2][i];
        let s = t[i].abs() - ha[i] - rb;
        if s > margin {
            return;
        }
        if s > sep_a {
            sep_a = s;
            face_a = 2 * i + (t[i] < 0.0) as usize;
        }
    }
    // B's faces: separation along B_j; the face of B facing A is opposite to t.
    let mut sep_b = f64::NEG_INFINITY;
    let mut face_b = 0;
    for j in 0..3 {
        let ra_j = ha.dot(abs_col[j]);
        let tj = t.dot(col[j]);
        let s = tj.abs() - ra_j - hb[j];
        if s > margin {
            return;
        }
        if s > sep_b {
            sep_b = s;
            face_b = 2 * j + (tj > 0.0) as usize;
        }
    }
    // Edge pairs e_i x B_j.
    let mut edge: Option<(f64, [usize; 2], [usize; 2])> = None;
    for i in 0..3 {
        for j in 0..3 {
            let mut e = DVec3::ZERO;
            e[i] = 1.0;
            let axis = e.cross(col[j]);
            let len = axis.length();
            if len <= 1e-6 {
                continue; // parallel edges: covered by the face axes
            }
            let mut l = axis / len;
            if l.dot(t) < 0.0 {
                l = -l; // from A towards B
            }
            let rad_a = ha.dot(l.abs());
            let lb = DVec3::new(l.dot(col[0]), l.dot(col[1]), l.dot(col[2]));
            let rad_b = hb.dot(lb.abs());
            let s = l.dot(t) - rad_a - rad_b;
            if s > margin {
                return;
            }
            if !matches!(edge, Some((best, _, _)) if best >= s) {
                // Support edge of A along +l (direction i free) and of B along
                // -l (direction j free), as vertex ids (bit k = +h along k).
                let mut va = 0usize;
                for k in 0..3 {
                    if k != i && l[k] >= 0.0 {
                        va |= 1 << k;
                    }
                }
                let mut vb = 0usize;
                for k in 0..3 {
                    if k != j && lb[k] < 0.0 {
                        vb |= 1 << k;
                    }
                }
                edge = Some((s, [va, va | 1 << i], [vb, vb | 1 << j]));
            }
        }
    }
    let scale = ha.max_element().max(hb.max_element());
    // Hand-over to the manifold shared with `contact_polytope_polytope`,
    // whose last lines read the same (see the module docs above).
    let sat = SatResult {
        sep_a,
        face_a,
        sep_b,
        face_b,
        edge,
        scale,
    };
    build_manifold(a, pose_a, b, pose_b, &sat, margin, out);
}
