//! Face-clipping contact manifolds for polytope pairs (Sutherland-Hodgman
//! clipping of the incident face against the side planes of the reference
//! face, as in Box2D's `b2ClipPolygons` lifted to 3D; Ericson 8.3.4 for the
//! clipping itself) and the reduction of a manifold to at most 4 points.
//!
//! Feature ids are carried through the clipping so that every output point
//! names what produced it: an incident corner (`vertex(inc, k)` against
//! `face(ref)`), an incident edge cut by a reference side (`edge(inc, i)`
//! against `edge(ref, j)`), or a reference corner inside the incident face
//! (`face(inc)` against `vertex(ref, k)`). These ids do not change under small
//! motions, which is what warm starting needs.

use super::reduce::reduce_to_four;
use crate::contact::{Contact, ContactKind, Feature};
use crate::math::DVec3;
use crate::pose::Pose;
use crate::shape::{Polytope, MAX_FACE_VERTICES};

const CAP: usize = 2 * MAX_FACE_VERTICES + 2;

/// Distance from a reference side plane, relative to the side's length,
/// within which an incident point counts as on the plane (kept, and no cut
/// made next to it).
///
/// Why: where an incident edge lies along a reference side (two boxes of
/// one width stacked, their side faces flush), rounding puts its ends a
/// few 1e-16 m either side of the plane, and a cut made between them lands
/// anywhere along the edge: a box on two boxes got a corner point 16 cm
/// inside its face on one side and none on the other, so that a pyramid
/// one box thick turned out of its plane (`narrow/tests_flush.rs`).
const ON_SIDE_PLANE: f64 = 1e-9;

/// Which line the polygon edge leaving a point lies on.
#[derive(Clone, Copy, PartialEq)]
enum Label {
    Incident(u8),
    Side(u8),
}

#[derive(Clone, Copy)]
struct ClipPoint {
    p: DVec3,
    /// Feature on the reference polytope.
    f_ref: Feature,
    /// Feature on the incident polytope.
    f_inc: Feature,
    /// Label of the edge from this point to the next.
    label: Label,
}

const EMPTY: ClipPoint = ClipPoint {
    p: DVec3::ZERO,
    f_ref: Feature::WHOLE,
    f_inc: Feature::WHOLE,
    label: Label::Side(0),
};

/// Contacts between reference face `ref_face` of `refp` and the most
/// anti-parallel face of `incp`; `ref_is_a` tells which of the two is shape A
/// (for the normal direction and feature order). Pushes at most 4 contacts
/// with `distance <= margin`; returns how many.
#[allow(clippy::too_many_arguments)]
pub(crate) fn face_manifold<R: Polytope + ?Sized, I: Polytope + ?Sized>(
    refp: &R,
    ref_pose: &Pose,
    ref_face: usize,
    incp: &I,
    inc_pose: &Pose,
    ref_is_a: bool,
    margin: f64,
    out: &mut Vec<Contact>,
) -> usize {
    let n_ref = ref_pose.transform_vector(refp.face_normal(ref_face));
    let d_ref = refp.face_offset(ref_face) + n_ref.dot(ref_pose.position);
    let inc_face = incp.best_face(inc_pose.rotation.inverse() * -n_ref);
    // Clipping an n-gon against m planes gives at most n + m points. Small
    // faces (boxes) get small stack buffers: initialising the large ones
    // would dominate the cost of a box-box query.
    let need = incp.face_len(inc_face) + refp.face_len(ref_face);
    let f = Faces {
        n_ref,
        d_ref,
        ref_face,
        inc_face,
    };
    if need <= SMALL {
        clip::<SMALL, R, I>(refp, ref_pose, incp, inc_pose, f, ref_is_a, margin, out)
    } else {
        clip::<CAP, R, I>(refp, ref_pose, incp, inc_pose, f, ref_is_a, margin, out)
    }
}

const SMALL: usize = 16;

#[derive(Clone, Copy)]
struct Faces {
    n_ref: DVec3,
    d_ref: f64,
    ref_face: usize,
    inc_face: usize,
}

#[allow(clippy::too_many_arguments)]
fn clip<const N: usize, R: Polytope + ?Sized, I: Polytope + ?Sized>(
    refp: &R,
    ref_pose: &Pose,
    incp: &I,
    inc_pose: &Pose,
    faces: Faces,
    ref_is_a: bool,
    margin: f64,
    out: &mut Vec<Contact>,
) -> usize {
    let Faces {
        n_ref,
        d_ref,
        ref_face,
        inc_face,
    } = faces;
    let mut buf_a = [EMPTY; N];
    let mut buf_b = [EMPTY; N];
    let mut len = incp.face_len(inc_face);
    for (k, slot) in buf_a.iter_mut().enumerate().take(len) {
        *slot = ClipPoint {
            p: inc_pose.transform_point(incp.vertex(incp.face_vertex(inc_face, k))),
            f_ref: Feature::face(ref_face as u32),
            f_inc: Feature::vertex(inc_face as u32, k as u8),
            label: Label::Incident(k as u8),
        };
    }
    let nr = refp.face_len(ref_face);
    // The reference face's corners, placed once (each begins one side and
    // ends the one before).
    let mut corners = [DVec3::ZERO; N];
    for (j, corner) in corners.iter_mut().enumerate().take(nr) {
        *corner = ref_pose.transform_point(refp.vertex(refp.face_vertex(ref_face, j)));
    }
    // Each point's distance from the current side plane, computed once.
    let mut side = [0.0f64; N];
    let (mut src, mut dst) = (&mut buf_a, &mut buf_b);
    for j in 0..nr {
        let v0 = corners[j];
        let v1 = corners[if j + 1 == nr { 0 } else { j + 1 }];
        // Outward side-plane normal: the face is counter-clockwise around n_ref,
        // so its interior is to the left of each edge and (v1 - v0) x n points out.
        let s = (v1 - v0).cross(n_ref);
        let c = s.dot(v0);
        // Points within ON_SIDE_PLANE of the side plane (relative to the
        // reference edge's length; `s` is as long as the edge) lie on it.
        let on = ON_SIDE_PLANE * s.length_squared();
        for (d, pt) in side.iter_mut().zip(src.iter()).take(len) {
            *d = s.dot(pt.p) - c;
        }
        let mut m = 0;
        for i in 0..len {
            let pt = src[i];
            let next = if i + 1 == len { 0 } else { i + 1 };
            let q = src[next];
            let (dp, dq) = (side[i], side[next]);
            let p_in = dp <= on;
            if p_in {
                dst[m] = pt;
                if dp >= -on && dq > on {
                    // On the plane and leaving: the polygon's edge from here
                    // runs along the reference side.
                    dst[m].label = Label::Side(j as u8);
                }
                m += 1;
            }
            // Cut only where the edge passes from one side of the plane to
            // the other; a point on the plane is its own cut.
            if (dp < -on && dq > on) || (dp > on && dq < -on) {
                let t = dp / (dp - dq);
                let (f_ref, f_inc) = match pt.label {
                    Label::Incident(e) => (
                        Feature::edge(ref_face as u32, j as u8),
                        Feature::edge(inc_face as u32, e),
                    ),
                    Label::Side(jj) => {
                        // Two reference sides meet at a reference corner.
                        let corner = if (jj as usize + 1) % nr == j {
                            j
                        } else {
                            jj as usize
                        };
                        (
                            Feature::vertex(ref_face as u32, corner as u8),
                            Feature::face(inc_face as u32),
                        )
                    }
                };
                dst[m] = ClipPoint {
                    p: pt.p + (q.p - pt.p) * t,
                    f_ref,
                    f_inc,
                    label: if p_in { Label::Side(j as u8) } else { pt.label },
                };
                m += 1;
            }
        }
        len = m;
        std::mem::swap(&mut src, &mut dst);
        if len == 0 {
            return 0;
        }
    }

    // Keep points within the margin of the reference plane.
    let mut m = 0;
    let mut dist = [0.0f64; N];
    for i in 0..len {
        let d = n_ref.dot(src[i].p) - d_ref;
        if d <= margin {
            src[m] = src[i];
            dist[m] = d;
            m += 1;
        }
    }
    let (keep, count) = reduce_to_four(m, n_ref, |i| (src[i].p, dist[i]));
    let normal = if ref_is_a { -n_ref } else { n_ref };
    for &i in &keep[..count] {
        let cp = &src[i];
        let (feature_a, feature_b) = if ref_is_a {
            (cp.f_ref, cp.f_inc)
        } else {
            (cp.f_inc, cp.f_ref)
        };
        out.push(Contact {
            point: cp.p - n_ref * (0.5 * dist[i]),
            normal,
            distance: dist[i],
            kind: ContactKind::FaceFace,
            feature_a,
            feature_b,
        });
    }
    count
}
