//! Vertex/edge and vertex/vertex contacts of two triangle meshes: the
//! closest features that vertex/face and edge/edge contacts
//! (`tri_contact`) do not cover.
//!
//! The closest points of two separated polyhedra lie on one of five feature
//! pairs: vertex/face, edge/edge, vertex/edge, edge/vertex or
//! vertex/vertex (the Voronoi regions of features, as in Lin and Canny's
//! closest-feature tracking, 1991). The first two are found per triangle
//! pair (thesis 5.2). The last three are not, and they are not rare: a
//! corner pointing at an edge or at another corner is in them for a whole
//! open set of poses, and two identical boxes side by side with level,
//! parallel edges (links of two chains hung from one palm) meet there
//! exactly, where each lower corner projects just outside the other's
//! side face and parallel edges have no edge/edge normal. Without them the
//! speculative contacts of such a pair were those of the far ends of the
//! faces, and the near ends crossed 6 mm into each other in one step.
//!
//! Two features whose closest points are `gap` apart (from B's to A's,
//! within the margin) give a contact when the gap's direction `u` lies in
//! both features' cones of normals: B's point is the highest point along
//! `u` of every triangle of B around its feature, A's the lowest along `u`
//! of every triangle of A around its own (for an edge: the two triangles
//! that hold it; for a vertex: its fan), and at least one of those
//! triangles on each side faces the other mesh (along `u` out of B,
//! against it out of A), which rules out the inside of a concave edge or
//! corner. An edge's point must be interior to it: at an end the pair is
//! vertex/vertex. The contact's normal is the outward normal of the face,
//! among those triangles, nearest `u`, and its distance the gap's
//! component along it (`face_axis` says why not `u` itself). Those tests
//! need the triangles around a feature, so the contacts come from the
//! owners of the features alone (`Owned`, `Copies`): the every-pair answer
//! of `triangle_contacts`, which sees one pair at a time, has none of
//! them. Two meshes give them from every owned pair; a box or hull against
//! a mesh gives them from its faces' fan triangles, which have owners and
//! neighbours too (`narrow::polytope_fans`).
//!
//! In a feature's cone of normals its point is outside both neighbouring
//! faces' prisms (a vertex/face contact there would have the face normal
//! instead), so these contacts never repeat a vertex/face or edge/edge one;
//! a flat edge or flat vertex has no cone beyond its face normal, where the
//! vertex/face contacts are. They are reported whether or not the two
//! triangles intersect elsewhere: the features are apart, and their own
//! distance is what the speculative solver needs.

use super::tri_contact::{face, Copies, Owned, Side};
use super::tri_distance::closest_point_on_finite_triangle;
use crate::contact::{Contact, ContactKind, Feature, SubFeature};
use crate::math::DVec3;

/// A point within this fraction of its distance beyond the cone test's
/// plane still passes it: parallel edges and a corner level with a
/// neighbour are exactly on that plane but for round-off.
const CONE_EPS: f64 = 1e-9;
/// The face axis is used when its cosine with the gap is at least this
/// (at a box's edge or corner, whatever the gap in its cone, the nearest
/// face is within 55 degrees of it); a blade sharper than that keeps the
/// gap itself.
const FACE_AXIS_COS: f64 = 0.5;

/// Appends the vertex/edge, edge/vertex and vertex/vertex contacts of the
/// features that `a` and `b` own (`owned`'s bits; B's feature within its
/// own margin, `owned.b_margins`, an edge by the larger of its ends').
/// `da` and `db` are the heights of each triangle's corners over the
/// other's plane (`None` for a triangle with no area): a corner farther
/// from the other's plane than the margin is farther from its edges and
/// corners too, which leaves most pairs with nothing to test.
///
/// Each owned corner near the other triangle is tested once: the other
/// triangle's point closest to it (Ericson 5.1.5) lies on an edge's
/// interior or on a corner exactly when the corner is beyond that edge or
/// corner within that triangle's plane, which the cone test asks of it
/// anyway; over the face there is nothing to report here. A corner of A
/// closest to a corner of B is the vertex/vertex candidate; from B's side
/// only edges of A are, so the pair is tested once.
pub(super) fn vertex_edge_contacts(
    (a, id_a, da): (&[DVec3; 3], u32, Option<[f64; 3]>),
    (b, id_b, db): (&[DVec3; 3], u32, Option<[f64; 3]>),
    owned: &mut Owned,
    out: &mut Vec<Contact>,
) {
    // Every contact here has a corner on one side: a pair that owns no
    // corner has none.
    if owned.a & 7 == 0 && owned.b & 7 == 0 {
        return;
    }
    let margins = owned.b_margins;
    let widest = margins[0].max(margins[1]).max(margins[2]);
    for k in 0..3 {
        if owned.a & (1 << k) == 0 || da.is_some_and(|d| d[k].abs() > widest) {
            continue;
        }
        let v = a[k];
        let (near, on) = closest_point_on_finite_triangle(v, b);
        let gap = v - near;
        match on {
            // A's corner against B's owned edge.
            SubFeature::Edge(j) if owned.b & (8 << j) != 0 => {
                let j = j as usize;
                let Some(up) = direction_within(gap, margins[j].max(margins[(j + 1) % 3])) else {
                    continue;
                };
                let ends = (b[j], b[(j + 1) % 3]);
                let (Some(axis_b), Some(axis_a)) = (
                    edge_cone(owned.copies, Side::B, (b, j), ends, up),
                    vertex_cone(owned.copies, Side::A, (a, k), -up),
                ) else {
                    continue;
                };
                let (n, d) = face_axis(gap, axis_b, axis_a);
                let (fa, fb) = (Feature::vertex(id_a, k as u8), Feature::edge(id_b, j as u8));
                out.push(contact((v + near) * 0.5, n, d, ContactKind::VertexEdge, fa, fb));
            }
            // A's corner against B's owned corner.
            SubFeature::Vertex(l) if owned.b & (1 << l) != 0 => {
                let l = l as usize;
                let Some(up) = direction_within(gap, margins[l]) else {
                    continue;
                };
                let (Some(axis_b), Some(axis_a)) = (
                    vertex_cone(owned.copies, Side::B, (b, l), up),
                    vertex_cone(owned.copies, Side::A, (a, k), -up),
                ) else {
                    continue;
                };
                let (n, d) = face_axis(gap, axis_b, axis_a);
                let (fa, fb) = (Feature::vertex(id_a, k as u8), Feature::vertex(id_b, l as u8));
                out.push(contact((v + near) * 0.5, n, d, ContactKind::VertexVertex, fa, fb));
            }
            _ => {}
        }
    }
    // B's owned corners against A's owned edges.
    for l in 0..3 {
        if owned.b & (1 << l) == 0 || db.is_some_and(|d| d[l].abs() > margins[l]) {
            continue;
        }
        let w = b[l];
        let (near, on) = closest_point_on_finite_triangle(w, a);
        let SubFeature::Edge(i) = on else {
            continue;
        };
        let i = i as usize;
        // From B's corner to A's edge: the contact's normal runs from B to A.
        let gap = near - w;
        let Some(up) = direction_within(gap, margins[l]).filter(|_| owned.a & (8 << i) != 0) else {
            continue;
        };
        let ends = (a[i], a[(i + 1) % 3]);
        let (Some(axis_b), Some(axis_a)) = (
            vertex_cone(owned.copies, Side::B, (b, l), up),
            edge_cone(owned.copies, Side::A, (a, i), ends, -up),
        ) else {
            continue;
        };
        let (n, d) = face_axis(gap, axis_b, axis_a);
        let (fa, fb) = (Feature::edge(id_a, i as u8), Feature::vertex(id_b, l as u8));
        out.push(contact((w + near) * 0.5, n, d, ContactKind::EdgeVertex, fa, fb));
    }
}

#[inline]
fn contact(
    point: DVec3,
    normal: DVec3,
    distance: f64,
    kind: ContactKind,
    fa: Feature,
    fb: Feature,
) -> Contact {
    Contact {
        point,
        normal,
        distance,
        kind,
        feature_a: fa,
        feature_b: fb,
    }
}

/// The unit direction of `gap` if it is not zero and no longer than
/// `margin`.
#[inline]
fn direction_within(gap: DVec3, margin: f64) -> Option<DVec3> {
    let d2 = gap.length_squared();
    (d2 <= margin * margin && d2 > 0.0).then(|| gap / d2.sqrt())
}

/// The contact's normal (from B to A) and distance for the gap `gap`
/// (from B's closest point to A's) between two features whose nearest
/// faces to it are `axis_b` (B's outward unit normal, with its cosine
/// to the gap) and `axis_a` (A's, outward from A).
///
/// Why a face normal and not the gap itself: the gap's direction turns
/// with the features' offset, by 45 degrees when a corner resting a
/// millimetre from an edge moves a millimetre across it, so a body
/// resting on a corner or an edge at the solver's skin would lie on a
/// rounded edge of that radius and rock on it (docs/pipeline.md,
/// "Measured and not kept", 2026-12-05: a concave pile settled far less
/// well so).
/// Each face's plane separates the features too, by the gap's component
/// along its normal, so the contact takes the face nearest the gap, as a
/// separating-axis test would (Gottschalk's and Ericson's face axes),
/// and that component as its distance: never more than the true gap, a
/// normal that holds still while the features move, and the distance
/// continuous where the nearest face changes. A blade sharper than
/// [`FACE_AXIS_COS`] allows keeps the gap.
#[inline]
fn face_axis(gap: DVec3, axis_b: (f64, DVec3), axis_a: (f64, DVec3)) -> (DVec3, f64) {
    let (cos, n) = if axis_b.0 >= axis_a.0 {
        axis_b
    } else {
        (axis_a.0, -axis_a.1)
    };
    if cos >= FACE_AXIS_COS {
        (n, n.dot(gap))
    } else {
        let d = gap.length();
        (gap / d, d)
    }
}

/// `point` is the highest point along `up` of triangle `t` (within the
/// cone tolerance of each corner's distance from it).
#[inline]
fn highest(t: &[DVec3; 3], point: DVec3, up: DVec3) -> bool {
    t.iter().all(|&c| {
        let r = c - point;
        up.dot(r) <= CONE_EPS * r.length()
    })
}

/// The faces of a feature seen so far that face along `up`: whether any
/// does (a triangle with no area faces every way), and the one nearest
/// `up` (its cosine with `up` and its outward unit normal).
struct Facing {
    any: bool,
    nearest: (f64, DVec3),
}

impl Facing {
    fn new() -> Self {
        Facing {
            any: false,
            nearest: (f64::NEG_INFINITY, DVec3::ZERO),
        }
    }

    fn see(&mut self, t: &[DVec3; 3], up: DVec3) {
        // A triangle without a usable normal (the contact routine's rule:
        // a sliver's cross product is round-off) faces every way.
        let Some(f) = face(t) else {
            self.any = true;
            return;
        };
        let cos = f.unit.dot(up);
        if cos < 0.0 {
            return;
        }
        self.any = true;
        if cos > self.nearest.0 {
            self.nearest = (cos, f.unit);
        }
    }

    /// The nearest face, if one faces along `up` (a feature of faces with
    /// no area has the gap itself).
    fn result(self, up: DVec3) -> Option<(f64, DVec3)> {
        self.any.then(|| {
            if self.nearest.0.is_finite() {
                self.nearest
            } else {
                (1.0, up)
            }
        })
    }
}

/// `up` (out of `side`'s mesh) is in the cone of normals of edge `j` of
/// `t`, whose ends are `ends`: the edge is the highest along `up` of `t`
/// and of the triangle across it, and one of them faces along `up`.
/// Returns that face nearest `up` ([`Facing`]).
#[cold]
fn edge_cone(
    copies: &mut dyn Copies,
    side: Side,
    (t, j): (&[DVec3; 3], usize),
    ends: (DVec3, DVec3),
    up: DVec3,
) -> Option<(f64, DVec3)> {
    let mid = (ends.0 + ends.1) * 0.5;
    if !highest(t, mid, up) {
        return None;
    }
    let mut facing = Facing::new();
    facing.see(t, up);
    if let Some(c) = copies.across(side, j) {
        if !highest(&c, mid, up) {
            return None;
        }
        facing.see(&c, up);
    }
    facing.result(up)
}

/// `up` (out of `side`'s mesh) is in the cone of normals of corner `k` of
/// `t`: the corner is the highest along `up` of every triangle around it,
/// and one of them faces along `up`. Returns that face nearest `up`
/// ([`Facing`]).
#[cold]
fn vertex_cone(
    copies: &mut dyn Copies,
    side: Side,
    (t, k): (&[DVec3; 3], usize),
    up: DVec3,
) -> Option<(f64, DVec3)> {
    let v = t[k];
    if !highest(t, v, up) {
        return None;
    }
    let mut facing = Facing::new();
    facing.see(t, up);
    let below = copies.any_around_corner(side, k, &mut |x| {
        if !highest(x, v, up) {
            return true;
        }
        facing.see(x, up);
        false
    });
    if below {
        return None;
    }
    facing.result(up)
}
