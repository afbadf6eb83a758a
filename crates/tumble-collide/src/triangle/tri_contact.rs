//! Exact contact generation for one triangle pair within a margin (thesis 5.2
//! and 7.1: vertex/face contacts with the face normal, edge/edge contacts with
//! the cross product of the edges, normals from B to A).
//!
//! Separated (or touching-free) pairs give feature contacts, each a candidate
//! for the speculative-contact solver:
//! - `VertexFace`: a vertex of A at signed height `0 <= d <= margin` above B's
//!   plane whose projection falls inside B; normal = B's unit face normal.
//!   Vertices behind the face (`d < 0`) are not reported: on a closed mesh they
//!   belong to the far side of the body (a vertex resting on a thin plate would
//!   otherwise be pushed through by the plate's bottom face); real penetration
//!   shows up as intersecting triangle pairs instead.
//! - `FaceVertex`: the same with the roles swapped; normal = -(A's face normal).
//! - `EdgeEdge`: two edges whose closest points are interior to both and no
//!   farther apart than `margin`; normal = unit `edge_a x edge_b`, oriented from
//!   B's closest point to A's. A pair whose gap points into the solids
//!   (against B's outward face normal and along A's: the edges have passed
//!   each other) is not reported, for the same reason as vertices behind a face.
//!
//! Intersecting pairs (touching included, decided exactly by
//! [`tri_tri_overlap`]) give `Penetrating` contacts along the axis of minimum
//! push-out among the two face normals and the 9 edge cross products (the
//! complete separating-axis set of two triangles), so moving A by the deepest
//! contact's `-distance` along the normal separates the pair. Each axis is
//! oriented out of the solids (A in front of B's face, B in front of A's;
//! edge axes by the faces' outward sense), as the triangles are pieces of
//! closed, outward-wound surfaces: pushing A through B's triangle to its
//! back would push it deeper into B. For an edge axis
//! that is one contact at the edges' closest points; for a face axis it is the
//! deepest corner of the other triangle plus every other corner that is past
//! the face and projects inside it (up to 3 contacts, same normal). Face axes win ties against
//! edge axes unless an edge axis is clearly shallower (by
//! [`FACE_PREFERENCE`]), which keeps resting contacts on face normals.
//!
//! Shared features, once: a mesh vertex belongs to about six triangles and an
//! edge to two, so testing every triangle pair near a contact reports a
//! vertex/face contact about six times and an edge/edge contact up to four
//! times (thesis 5.4), and the duplicates are merged afterwards. Given which
//! corners and edges each triangle owns (`Owned`: every vertex of a mesh, and
//! every edge between two triangles, has exactly one owner),
//! `triangle_contacts_owned` reports each feature's contacts from its owner's
//! pairs only, and gives after merging the answer of testing every pair (for
//! the same triangle pairs: a walk along a drift reaches the owner's pair
//! whenever the feature comes within the margin, not always when a copy's
//! pair is reached for its look-ahead alone; and on a mesh whose vertex has
//! two fans, or behind a non-manifold edge, the triangles asked below are
//! those of the owner's fan). A vertex or edge within the margin of a face or
//! edge is within it for every triangle that holds it, so the owner sees what
//! each copy would (with a margin per feature, `Owned::b_margins`, that is
//! the same in every pair holding the feature). Where the copies' answers
//! depend on their own triangles, the owner asks the triangles around the
//! feature (`Copies`), on a cold path: a pair whose triangles intersect gives
//! only push-out contacts, so an owner whose pair intersects reports a corner
//! only if some other triangle at that corner does not intersect the other
//! triangle, and an edge/edge contact only if some pair holding both edges
//! does not intersect and passes the outward test; an edge/edge contact that
//! its own faces reject is kept when the pair with a triangle across either
//! edge passes that test and does not intersect. (An earlier rule reported an
//! owner's features from an intersecting pair regardless, and kept an edge
//! contact for a face across whatever that pair did: once the walk along a
//! drift used it too, 8 of 12 jittered concave piles settled with two bodies
//! 0.6-1 mm inside each other, held by those contacts, and pairs of brackets
//! stayed 1-3 cm deep for tens of steps.) The ghost filter of flat regions
//! (`narrow::contact_mesh`) judges a flat vertex or edge by its owner's face,
//! where the copies were judged by each of theirs (coplanar within 0.03
//! degrees, so only contacts in a hair-thin band of normals can differ), and
//! each contact is computed once, so the survivor of a group of copies that
//! differed in round-off (an edge's copies run it in both directions) may
//! differ in the last bits.

use super::tri_distance::closest_points_segments;
use super::tri_measure::{bounds, longest_edge_squared};
use super::tri_tri_overlap::tri_tri_overlap;
use super::tri_vertex_edge::vertex_edge_contacts;
use crate::contact::{Contact, ContactKind, Feature};
use crate::math::DVec3;

/// Why contacts could not be generated for a triangle pair.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum TriContactError {
    /// The margin is negative, NaN or infinite.
    #[error("contact margin must be finite and >= 0 (m), got {0}")]
    InvalidMargin(f64),
    /// A vertex coordinate of one triangle is NaN or infinite.
    #[error("triangle {id} of shape {shape} has a non-finite vertex coordinate (expected finite)")]
    NonFinite {
        /// `'A'` or `'B'`.
        shape: char,
        /// The triangle id the caller passed for that shape.
        id: u32,
    },
}

/// An edge axis must be shallower than this fraction of the best face axis to
/// be chosen for a penetrating contact.
pub const FACE_PREFERENCE: f64 = 0.95;

/// Edge parameters within this of 0 or 1 count as vertices, not edge
/// interiors: those contacts are the vertex/face ones.
const PARAM_EPS: f64 = 1e-9;
/// Barycentric tolerance of the projection-inside-face test, so that a vertex
/// exactly above a shared edge is reported by both faces (then merged) rather
/// than by neither.
const INSIDE_EPS: f64 = 1e-12;
/// A triangle whose doubled area is below this times its longest edge squared
/// has no usable face normal.
const AREA_EPS: f64 = 1e-12;
/// An edge axis whose cosine with the faces' outward sense is below this is
/// taken in whichever direction pushes less.
const AMBIGUOUS_SIDE: f64 = 0.1;
/// Heights over a plane beyond this (times 1 + the coordinates' magnitude,
/// m) are surely on that side despite round-off.
const SIDE_EPS: f64 = 1e-12;
/// A gap between two triangles' boxes beyond the margin plus this (times 1 +
/// the coordinates' magnitude, m) is surely beyond the margin (`boxes_apart`).
const BOX_EPS: f64 = 1e-9;
/// Edge pairs with `sin^2(angle)` below this are parallel: no edge/edge normal.
const PARALLEL_EPS: f64 = 1e-12;

/// Unit normal of a triangle, and its unnormalised normal, if it has an area.
#[derive(Clone, Copy)]
pub(super) struct Face {
    pub unit: DVec3,
    raw: DVec3,
}

#[inline]
pub(super) fn face(t: &[DVec3; 3]) -> Option<Face> {
    let raw = (t[1] - t[0]).cross(t[2] - t[0]);
    let len = raw.length();
    (len > AREA_EPS * longest_edge_squared(t)).then(|| Face { unit: raw / len, raw })
}

/// Signed heights of the corners of `t` over the plane of `f` through `origin`.
#[inline]
fn heights(t: &[DVec3; 3], f: Face, origin: DVec3) -> [f64; 3] {
    [
        f.unit.dot(t[0] - origin),
        f.unit.dot(t[1] - origin),
        f.unit.dot(t[2] - origin),
    ]
}

/// All heights beyond the margin on one side: the plane separates the
/// triangles by more than the margin, so no feature pair can be within it.
#[inline]
fn beyond(d: [f64; 3], margin: f64) -> bool {
    (d[0] > margin && d[1] > margin && d[2] > margin) || (d[0] < -margin && d[1] < -margin && d[2] < -margin)
}

/// `q` (in the plane of `t`) lies inside the closed triangle `t`, with a
/// relative tolerance.
#[inline]
fn inside(q: DVec3, t: &[DVec3; 3], f: Face) -> bool {
    let tol = -INSIDE_EPS * f.raw.length_squared();
    (0..3).all(|k| (t[(k + 1) % 3] - t[k]).cross(q - t[k]).dot(f.raw) >= tol)
}

/// Appends the contacts of triangle `a` (id `id_a` on shape A) and triangle `b`
/// (id `id_b` on shape B) to `out`, and returns how many were appended.
///
/// `margin` (m, >= 0) is the largest gap still reported. Both triangles must be
/// in one common frame. Contact conventions are those of [`Contact`]: normal
/// from B to A, `distance` the signed gap (negative for the one `Penetrating`
/// contact of an intersecting pair), `point` the midpoint of the two closest
/// points, features from the caller's triangle ids (`Feature::vertex(id, k)`,
/// `edge(id, k)` for corner `k` to `k + 1`, `face(id)`). Zero-area triangles
/// give no face contacts. Nothing is allocated beyond growing `out`.
///
/// Errors: [`TriContactError::InvalidMargin`] for a negative or non-finite
/// margin, [`TriContactError::NonFinite`] for a NaN/infinite coordinate; `out`
/// is unchanged then.
pub fn triangle_contacts(
    a: &[DVec3; 3],
    id_a: u32,
    b: &[DVec3; 3],
    id_b: u32,
    margin: f64,
    out: &mut Vec<Contact>,
) -> Result<usize, TriContactError> {
    if !(margin >= 0.0 && margin.is_finite()) {
        return Err(TriContactError::InvalidMargin(margin));
    }
    if !a.iter().all(|p| p.is_finite()) {
        return Err(TriContactError::NonFinite { shape: 'A', id: id_a });
    }
    if !b.iter().all(|p| p.is_finite()) {
        return Err(TriContactError::NonFinite { shape: 'B', id: id_b });
    }
    Ok(contacts_of_pair(a, id_a, b, id_b, margin, None, out))
}

/// Which of the two triangles of a pair a triangle mesh is made of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Side {
    A,
    B,
}

/// The corners and edges each triangle of a pair owns (module docs, "Shared
/// features, once"), the margins of B's corners, and the triangles around
/// them.
pub(crate) struct Owned<'f> {
    /// Bit `k` (0-2): A's triangle owns its corner `k`; bit `3 + k`: its edge `k`.
    pub a: u8,
    /// The same for B's triangle.
    pub b: u8,
    /// The margin (m, at most the test's) of each corner of B's triangle,
    /// for that corner against A's face; an edge of B takes the larger of
    /// its two ends' (A's corners against B's face take the test's margin).
    /// A margin that depends on the feature alone (its look-ahead: how far
    /// it can move in the step) is the same in every pair that holds the
    /// feature, so the owner's pair reports what every copy would have.
    pub b_margins: [f64; 3],
    /// The other triangles at the pair's corners and edges, for judging an
    /// intersecting pair's features and an edge/edge contact its own faces
    /// reject by the pairs that also hold them.
    pub copies: &'f mut dyn Copies,
}

/// The triangles of the two meshes around a pair's features, in the pair's
/// common frame (module docs, "Shared features, once").
pub(crate) trait Copies {
    /// `true` when `visit` returns `true` for one of the triangles of
    /// `side`'s mesh, other than the pair's own, around corner `k` of the
    /// pair's triangle of that side.
    fn any_around_corner(&mut self, side: Side, k: usize, visit: &mut dyn FnMut(&[DVec3; 3]) -> bool)
        -> bool;
    /// The triangle of `side`'s mesh across edge `k` of the pair's triangle
    /// of that side, if there is one.
    fn across(&mut self, side: Side, k: usize) -> Option<[DVec3; 3]>;
}

/// [`triangle_contacts`] (its checks left to the caller) reporting only the
/// corners and edges the two triangles own (module docs, "Shared features,
/// once"); push-out contacts of an intersecting pair are reported by every
/// pair, as before.
#[inline]
pub(crate) fn triangle_contacts_owned(
    a: &[DVec3; 3],
    id_a: u32,
    b: &[DVec3; 3],
    id_b: u32,
    margin: f64,
    owned: &mut Owned,
    out: &mut Vec<Contact>,
) -> usize {
    contacts_of_pair(a, id_a, b, id_b, margin, Some(owned), out)
}

/// [`triangle_contacts`] (its checks left to the caller), and besides, the
/// vertex/edge, edge/vertex and vertex/vertex contacts of the corners and
/// edges the two triangles own (`tri_vertex_edge`; `owned.b_margins` must
/// be `margin`): for a caller that keeps every pair's vertex/face and
/// edge/edge contacts and merges their copies, and has owners and
/// neighbours for the corner contacts (the polytope-mesh routine, whose
/// polytope is its faces' fan triangles, and the mesh query, whose answer
/// is checked pair by pair against [`triangle_contacts`]).
#[inline]
pub(crate) fn triangle_contacts_and_corners(
    a: &[DVec3; 3],
    id_a: u32,
    b: &[DVec3; 3],
    id_b: u32,
    margin: f64,
    owned: &mut Owned,
    out: &mut Vec<Contact>,
) -> usize {
    if boxes_apart(a, b, margin) {
        return 0;
    }
    features_of_pair(a, id_a, b, id_b, margin, (None, Some(owned)), out)
}

/// Every feature of both triangles, or (`owned`) the ones they own.
#[inline]
fn contacts_of_pair(
    a: &[DVec3; 3],
    id_a: u32,
    b: &[DVec3; 3],
    id_b: u32,
    margin: f64,
    owned: Option<&mut Owned>,
    out: &mut Vec<Contact>,
) -> usize {
    if boxes_apart(a, b, margin) {
        return 0;
    }
    features_of_pair(a, id_a, b, id_b, margin, (owned, None), out)
}

/// [`contacts_of_pair`] after its first early out. Of `(owned, corners)`,
/// `owned` limits every kind of contact to the features the pair owns;
/// `corners` (with `owned` `None`) keeps every feature for vertex/face and
/// edge/edge contacts and adds the corner contacts of the owned ones
/// ([`triangle_contacts_and_corners`]).
#[inline(always)]
fn features_of_pair<'o, 'f>(
    a: &[DVec3; 3],
    id_a: u32,
    b: &[DVec3; 3],
    id_b: u32,
    margin: f64,
    (owned, corners): (Option<&'o mut Owned<'f>>, Option<&'o mut Owned<'f>>),
    out: &mut Vec<Contact>,
) -> usize {
    let fa = face(a);
    let fb = face(b);
    // Early outs: a face plane that separates by more than the margin.
    let da = fb.map(|f| heights(a, f, b[0]));
    if da.is_some_and(|d| beyond(d, margin)) {
        return 0;
    }
    let db = fa.map(|f| heights(b, f, a[0]));
    if db.is_some_and(|d| beyond(d, margin)) {
        return 0;
    }
    let start = out.len();
    let intersecting = intersects_with_heights(a, b, da, db);
    if intersecting {
        penetrating_contacts(a, id_a, fa, b, id_b, fb, out);
        // Every pair reports all of its features, and the pairs around an
        // intersecting one report them; an owner reports a feature from an
        // intersecting pair only when one of those would have (module docs).
        if owned.is_none() {
            if let Some(c) = corners {
                vertex_edge_contacts((a, id_a, da), (b, id_b, db), c, out);
            }
            return out.len() - start;
        }
    }
    let mut owned = owned;
    let (own_a, own_b, b_margins) = owned
        .as_ref()
        .map_or((ALL, ALL, [margin; 3]), |o| (o.a, o.b, o.b_margins));
    if let (Some(f), Some(d)) = (fb, da) {
        for k in 0..3 {
            let h = d[k];
            if own_a & (1 << k) != 0
                && (0.0..=margin).contains(&h)
                && inside(a[k] - f.unit * h, b, f)
                && (!intersecting || copy_at_corner(&mut owned, Side::A, k, &mut |x| !intersects(x, b)))
            {
                out.push(Contact {
                    point: a[k] - f.unit * (0.5 * h),
                    normal: f.unit,
                    distance: h,
                    kind: ContactKind::VertexFace,
                    feature_a: Feature::vertex(id_a, k as u8),
                    feature_b: Feature::face(id_b),
                });
            }
        }
    }
    // The loop above with A and B swapped: kind, normal sign and feature roles
    // all flip, and a closure over both would blur which side is which on the
    // hot path of every candidate pair.
    if let (Some(f), Some(d)) = (fa, db) {
        for k in 0..3 {
            let h = d[k];
            if own_b & (1 << k) != 0
                && (0.0..=b_margins[k]).contains(&h)
                && inside(b[k] - f.unit * h, a, f)
                && (!intersecting || copy_at_corner(&mut owned, Side::B, k, &mut |y| !intersects(a, y)))
            {
                out.push(Contact {
                    point: b[k] - f.unit * (0.5 * h),
                    normal: -f.unit,
                    distance: h,
                    kind: ContactKind::FaceVertex,
                    feature_a: Feature::face(id_a),
                    feature_b: Feature::vertex(id_b, k as u8),
                });
            }
        }
    }
    edge_edge_contacts(
        (a, id_a, fa),
        (b, id_b, fb),
        b_margins,
        intersecting,
        owned.as_deref_mut(),
        out,
    );
    if let Some(o) = owned.or(corners) {
        vertex_edge_contacts((a, id_a, da), (b, id_b, db), o, out);
    }
    out.len() - start
}

/// `true` when the axis-aligned boxes of `a` and `b` (one frame) are
/// apart along some axis by more than `margin` and round-off: no two points
/// of the triangles are then within `margin`, so the pair has no contact
/// (every feature's margin is at most the pair's, and an intersecting pair
/// touches). The first early out because it is the cheapest (no normal, no
/// square root): of the torus chain's triangle pairs handed over by the
/// tree walk, 63 % are apart so, and half of those that pass the face
/// planes' early outs too (`profile_stages chain 600 1`, 3.56 M pairs, 2.6 %
/// with contacts). The pad is far above the round-off of the heights and
/// edge distances that decide a contact, so the contacts are the same bit
/// for bit.
#[inline(always)]
fn boxes_apart(a: &[DVec3; 3], b: &[DVec3; 3], margin: f64) -> bool {
    let ((low_a, high_a), (low_b, high_b)) = (bounds(a), bounds(b));
    let scale = 1.0 + a[0].abs().max_element().max(b[0].abs().max_element());
    let reach = DVec3::splat(margin + BOX_EPS * scale);
    (low_a - high_b).cmpgt(reach).any() || (low_b - high_a).cmpgt(reach).any()
}

/// `true` when the triangles meet (touching included): the test every
/// pair makes, with the heights of each one's corners over the other's
/// plane (`None` for a triangle with no area).
#[inline]
fn intersects_with_heights(
    a: &[DVec3; 3],
    b: &[DVec3; 3],
    da: Option<[f64; 3]>,
    db: Option<[f64; 3]>,
) -> bool {
    // A triangle strictly on one side of the other's plane cannot meet it;
    // only the rest need the exact intersection test. The tolerance covers
    // the round-off of the heights, so the exact test decides every case
    // that is close.
    let scale = 1.0 + a[0].abs().max_element().max(b[0].abs().max_element());
    let tol = SIDE_EPS * scale;
    let clear = |d: Option<[f64; 3]>| {
        d.is_some_and(|d| {
            (d[0] > tol && d[1] > tol && d[2] > tol) || (d[0] < -tol && d[1] < -tol && d[2] < -tol)
        })
    };
    !clear(da) && !clear(db) && tri_tri_overlap(a, b)
}

/// [`intersects_with_heights`] for a pair of A's and B's triangles, to the
/// bit as the pair's own test decides it.
#[cold]
fn intersects(a: &[DVec3; 3], b: &[DVec3; 3]) -> bool {
    let (fa, fb) = (face(a), face(b));
    intersects_with_heights(
        a,
        b,
        fb.map(|f| heights(a, f, b[0])),
        fa.map(|f| heights(b, f, a[0])),
    )
}

/// `true` when a triangle around corner `k` of `side`'s triangle passes
/// `visit` (an owner always has `Some` copies).
#[cold]
fn copy_at_corner(
    owned: &mut Option<&mut Owned>,
    side: Side,
    k: usize,
    visit: &mut dyn FnMut(&[DVec3; 3]) -> bool,
) -> bool {
    owned
        .as_deref_mut()
        .is_some_and(|o| o.copies.any_around_corner(side, k, visit))
}

/// Every corner and edge (bits 0-2 and 3-5 of [`Owned`]).
const ALL: u8 = 0x3f;

/// Edge/edge contacts of a non-intersecting pair, of every edge or of the
/// owned ones (of an intersecting owner's pair too, where a pair around
/// the edges would report them); edge `j` of B within the larger margin of
/// its two ends (`b_margins`).
#[inline]
fn edge_edge_contacts(
    (a, id_a, fa): (&[DVec3; 3], u32, Option<Face>),
    (b, id_b, fb): (&[DVec3; 3], u32, Option<Face>),
    b_margins: [f64; 3],
    intersecting: bool,
    mut owned: Option<&mut Owned>,
    out: &mut Vec<Contact>,
) {
    let margins2 = [0, 1, 2].map(|j| {
        let m = b_margins[j].max(b_margins[(j + 1) % 3]);
        m * m
    });
    let interior = |s: f64| s > PARAM_EPS && s < 1.0 - PARAM_EPS;
    let (edges_a, edges_b) = owned.as_ref().map_or((ALL, ALL), |o| (o.a >> 3, o.b >> 3));
    for i in 0..3 {
        if edges_a & (1 << i) == 0 {
            continue;
        }
        let (p1, q1) = (a[i], a[(i + 1) % 3]);
        let ea = q1 - p1;
        for j in 0..3 {
            if edges_b & (1 << j) == 0 {
                continue;
            }
            let (p2, q2) = (b[j], b[(j + 1) % 3]);
            let eb = q2 - p2;
            let margin2 = margins2[j];
            let c = ea.cross(eb);
            let c2 = c.length_squared();
            if c2 <= PARALLEL_EPS * ea.length_squared() * eb.length_squared() {
                continue;
            }
            // The segments are at least as far apart as their lines: skip
            // the closest points when the lines are beyond the margin
            // (|c . (p1 - p2)| / |c| > margin).
            let line_gap = c.dot(p1 - p2);
            if line_gap * line_gap > margin2 * c2 {
                continue;
            }
            // Only closest points interior to both edges make a contact, and
            // those are the closest points of the two lines (the distance is
            // convex in (s, t): an interior minimum over the square is the
            // unconstrained one). So solve for the lines' parameters and stop
            // as soon as one leaves the interior, before any clamping; the
            // expressions are those of `closest_points_segments`, which
            // returns these same values when both are interior.
            let Some((s, t)) = interior_line_parameters(ea, eb, p1 - p2, interior) else {
                continue;
            };
            let gap = (p1 + ea * s) - (p2 + eb * t);
            if gap.length_squared() > margin2 {
                continue;
            }
            let mut n = c / c2.sqrt();
            // For interior closest points the gap is perpendicular to both
            // edges, so it is parallel to n: orient n from B's point to A's.
            // When the points coincide, point away from B's interior.
            let along = n.dot(gap);
            let flip = if along != 0.0 {
                along < 0.0
            } else if let Some(f) = fb {
                n.dot(f.unit) < 0.0
            } else {
                let ca = (a[0] + a[1] + a[2]) - (b[0] + b[1] + b[2]);
                n.dot(ca) < 0.0
            };
            if flip {
                n = -n;
            }
            // A gap that points into the solids (against B's outward face
            // normal and along A's) says the edges have already passed each
            // other: the triangles are pieces of two overlapping closed
            // surfaces, and a contact along it would hold A inside B. The
            // intersecting triangle pairs nearby carry that overlap with
            // outward push-out normals instead.
            // An owner keeps the contact when some pair holding both edges
            // (its own, or one with the triangle across either edge) does
            // not intersect and passes this test with its own faces: when a
            // copy of it would have been reported.
            let passes = !intersecting && outward(n, fa, fb);
            if !passes
                && !owned
                    .as_deref_mut()
                    .is_some_and(|o| passing_copy(o, n, (i, a), (j, b)))
            {
                continue;
            }
            out.push(Contact {
                point: ((p1 + ea * s) + (p2 + eb * t)) * 0.5,
                normal: n,
                distance: n.dot(gap),
                kind: ContactKind::EdgeEdge,
                feature_a: Feature::edge(id_a, i as u8),
                feature_b: Feature::edge(id_b, j as u8),
            });
        }
    }
}

/// The outward test of an edge/edge contact along `n` (from B to A)
/// between triangles with faces `fa` and `fb` (a face with no area counts
/// as zero): false when `n` points against B's outward normal and along
/// A's, into both solids.
#[inline]
fn outward(n: DVec3, fa: Option<Face>, fb: Option<Face>) -> bool {
    n.dot(fb.map_or(DVec3::ZERO, |f| f.unit) - fa.map_or(DVec3::ZERO, |f| f.unit)) >= 0.0
}

/// `true` when a pair holding edge `i` of A's triangle and edge `j` of B's
/// other than the pair's own (the triangle across either edge in place of
/// its own) does not intersect and passes the outward test along `n` with
/// its own faces.
#[cold]
fn passing_copy(o: &mut Owned, n: DVec3, (i, a): (usize, &[DVec3; 3]), (j, b): (usize, &[DVec3; 3])) -> bool {
    let (xa, yb) = (o.copies.across(Side::A, i), o.copies.across(Side::B, j));
    let pair = |x: Option<&[DVec3; 3]>, y: Option<&[DVec3; 3]>| -> bool {
        let (Some(x), Some(y)) = (x, y) else {
            return false;
        };
        outward(n, face(x), face(y)) && !intersects(x, y)
    };
    pair(Some(a), yb.as_ref()) || pair(xa.as_ref(), Some(b)) || pair(xa.as_ref(), yb.as_ref())
}

/// The parameters `(s, t)` of the closest points of the lines `p1 + s d1`
/// and `p2 + t d2` (`r = p1 - p2`), if both pass `interior`; `None` as soon
/// as one does not. The lines must not be parallel (the caller checked).
#[inline]
fn interior_line_parameters(
    d1: DVec3,
    d2: DVec3,
    r: DVec3,
    interior: impl Fn(f64) -> bool,
) -> Option<(f64, f64)> {
    let (a, e) = (d1.length_squared(), d2.length_squared());
    let (b, c, f) = (d1.dot(d2), d1.dot(r), d2.dot(r));
    let s = (b * f - c * e) / (a * e - b * b);
    if !interior(s) {
        return None;
    }
    let t = (b * s + f) / e;
    interior(t).then_some((s, t))
}

/// Which separating axis a penetrating contact uses.
#[derive(Clone, Copy)]
enum Axis {
    FaceB,
    FaceA,
    Edges(usize, usize),
}

/// How far A must move along the unit `n` to clear B on that axis:
/// `max(n . b) - min(n . a)` (positive while the projections overlap).
#[inline]
fn push_along(n: DVec3, a: &[DVec3; 3], b: &[DVec3; 3]) -> f64 {
    let max_b = n.dot(b[0]).max(n.dot(b[1])).max(n.dot(b[2]));
    let min_a = n.dot(a[0]).min(n.dot(a[1])).min(n.dot(a[2]));
    max_b - min_a
}

/// Index of the first minimum of `n . t[k]`.
#[inline]
fn deepest(t: &[DVec3; 3], n: DVec3) -> usize {
    let mut k = 0;
    for j in 1..3 {
        if n.dot(t[j]) < n.dot(t[k]) {
            k = j;
        }
    }
    k
}

/// The push-out contacts of an intersecting pair (see the module docs);
/// returns how many were appended.
// Same argument list as `edge_edge_contacts` above (both triangles with ids
// and the faces computed once by the caller); a separate `#[cold]` function
// so that the intersecting case stays out of the separated pairs' path.
#[cold]
fn penetrating_contacts(
    a: &[DVec3; 3],
    id_a: u32,
    fa: Option<Face>,
    b: &[DVec3; 3],
    id_b: u32,
    fb: Option<Face>,
    out: &mut Vec<Contact>,
) -> usize {
    // Every axis is oriented out of the solids, not towards the shorter
    // push of the two triangles alone: on closed, outward-wound meshes the
    // triangles are pieces of two surfaces, and A belongs in front of B's
    // face (along +nB) and B in front of A's (A moves along -nA). The
    // shorter push may go through the other triangle to the back of its
    // surface, into the solid, and two such contacts of one body pair then
    // push against each other.
    let mut best: Option<(f64, DVec3, Axis)> = None;
    if let Some(f) = fb {
        best = Some((push_along(f.unit, a, b), f.unit, Axis::FaceB));
    }
    if let Some(f) = fa {
        let d = push_along(-f.unit, a, b);
        if improves(&best, d) {
            best = Some((d, -f.unit, Axis::FaceA));
        }
    }
    let face_depth = best.map_or(f64::INFINITY, |(d, _, _)| d);
    // Edge axes are oriented along the faces' outward sense (B's normal,
    // against A's); with no face to go by, from B's centroid to A's.
    let outward = match (fa, fb) {
        (Some(x), Some(y)) => y.unit - x.unit,
        (Some(x), None) => -x.unit,
        (None, Some(y)) => y.unit,
        (None, None) => (a[0] + a[1] + a[2]) - (b[0] + b[1] + b[2]),
    };
    for i in 0..3 {
        let ea = a[(i + 1) % 3] - a[i];
        for j in 0..3 {
            let eb = b[(j + 1) % 3] - b[j];
            let c = ea.cross(eb);
            let c2 = c.length_squared();
            if c2 <= PARALLEL_EPS * ea.length_squared() * eb.length_squared() || c2 == 0.0 {
                continue;
            }
            let u = c / c2.sqrt();
            // An axis nearly perpendicular to the outward sense (two walls
            // crossing edge-on, the axis along neither face normal) has no
            // preferred sign: the shorter push decides, as for a lone pair.
            let along = u.dot(outward);
            let (d, n) = if along.abs() <= AMBIGUOUS_SIDE * outward.length() {
                let (up, down) = (push_along(u, a, b), push_along(-u, a, b));
                if up <= down {
                    (up, u)
                } else {
                    (down, -u)
                }
            } else {
                let n = if along < 0.0 { -u } else { u };
                (push_along(n, a, b), n)
            };
            if d < FACE_PREFERENCE * face_depth && improves(&best, d) {
                best = Some((d, n, Axis::Edges(i, j)));
            }
        }
    }
    let Some((depth, n, axis)) = best else {
        // Both triangles are degenerate and all their edges parallel: they
        // overlap along a common line. No axis is defined; push apart along
        // the line between centroids (or +z when that is zero too).
        let ca = (a[0] + a[1] + a[2]) / 3.0;
        let cb = (b[0] + b[1] + b[2]) / 3.0;
        out.push(Contact {
            point: (ca + cb) * 0.5,
            normal: (ca - cb).try_normalize().unwrap_or(DVec3::Z),
            distance: 0.0,
            kind: ContactKind::Penetrating,
            feature_a: Feature::vertex(id_a, 0),
            feature_b: Feature::vertex(id_b, 0),
        });
        return 1;
    };
    let contact = |point, distance, feature_a, feature_b| Contact {
        point,
        normal: n,
        distance,
        kind: ContactKind::Penetrating,
        feature_a,
        feature_b,
    };
    // For a face axis every corner of the other triangle that is past the
    // face (depth >= 0) and projects inside it is a contact, not only the
    // deepest one: a triangle lying flat on another must report all of its
    // corners, or corners of a resting mesh go missing. The deepest corner is
    // always reported.
    match axis {
        Axis::FaceB => {
            let k0 = deepest(a, n);
            let level = n.dot(b[0]);
            let mut count = 0;
            for (k, &p) in a.iter().enumerate() {
                let d = level - n.dot(p);
                let report = k == k0 || (d >= 0.0 && fb.is_some_and(|f| inside(p + n * d, b, f)));
                if report {
                    let fa_k = Feature::vertex(id_a, k as u8);
                    out.push(contact(p + n * (0.5 * d), -d, fa_k, Feature::face(id_b)));
                    count += 1;
                }
            }
            count
        }
        Axis::FaceA => {
            let k0 = deepest(b, -n);
            let level = n.dot(a[0]);
            let mut count = 0;
            for (k, &p) in b.iter().enumerate() {
                let d = n.dot(p) - level;
                let report = k == k0 || (d >= 0.0 && fa.is_some_and(|f| inside(p - n * d, a, f)));
                if report {
                    let fb_k = Feature::vertex(id_b, k as u8);
                    out.push(contact(p - n * (0.5 * d), -d, Feature::face(id_a), fb_k));
                    count += 1;
                }
            }
            count
        }
        Axis::Edges(i, j) => {
            let r = closest_points_segments(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]);
            out.push(contact(
                (r.point_a + r.point_b) * 0.5,
                -depth,
                Feature::edge(id_a, i as u8),
                Feature::edge(id_b, j as u8),
            ));
            1
        }
    }
}

/// `d` is a smaller overlap than the best axis so far (ties keep the earlier axis, so the choice is deterministic).
#[inline]
fn improves(best: &Option<(f64, DVec3, Axis)>, d: f64) -> bool {
    match best {
        Some((b, _, _)) => d < *b,
        None => true,
    }
}

#[cfg(test)]
mod tests {
    use super::super::tri_distance::triangle_distance;
    use super::*;
    use crate::contact::SubFeature;
    use tumble_testkit::{RandomSource, XorShift64Star as Rng};

    fn contacts(a: &[DVec3; 3], b: &[DVec3; 3], margin: f64) -> Vec<Contact> {
        let mut out = Vec::new();
        triangle_contacts(a, 7, b, 9, margin, &mut out).unwrap();
        out
    }

    fn random_tri(rng: &mut Rng, r: f64) -> [DVec3; 3] {
        let mut p = || DVec3::new(rng.range(-r, r), rng.range(-r, r), rng.range(-r, r));
        [p(), p(), p()]
    }

    // The tests spell out their triangles corner by corner, as do those of
    // tri_distance.rs and merge.rs: the coordinates are the case pinned, and
    // a shared fixture would hide what a failing test is about.
    #[test]
    fn vertex_hovering_above_a_face_gives_one_vertex_face_contact() {
        let b = [
            DVec3::new(-2.0, -2.0, 0.0),
            DVec3::new(3.0, -2.0, 0.0),
            DVec3::new(-2.0, 3.0, 0.0),
        ];
        let h = 0.01;
        let tip = DVec3::new(0.1, 0.2, h);
        let a = [DVec3::new(1.0, 1.0, 1.0), tip, DVec3::new(-1.0, 0.5, 1.0)];
        let c = contacts(&a, &b, 0.05);
        assert_eq!(c.len(), 1, "{c:?}");
        let c = c[0];
        assert_eq!(c.kind, ContactKind::VertexFace);
        assert_eq!(c.normal, DVec3::Z);
        assert!((c.distance - h).abs() < 1e-15);
        assert!((c.point - DVec3::new(0.1, 0.2, h / 2.0)).length() < 1e-15);
        assert_eq!(c.feature_a, Feature::vertex(7, 1));
        assert_eq!(c.feature_b, Feature::face(9));
        assert!((c.distance - triangle_distance(&a, &b).distance).abs() < 1e-15);
        // Beyond the margin: nothing.
        assert!(contacts(&a, &b, 0.009).is_empty());
        // Seen from the other side it is a face/vertex contact, flipped.
        let d = contacts(&b, &a, 0.05);
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].kind, ContactKind::FaceVertex);
        assert_eq!(d[0].normal, -DVec3::Z);
        assert!((d[0].distance - h).abs() < 1e-15);
    }

    #[test]
    fn vertex_behind_a_face_is_not_a_contact() {
        // A thin plate's bottom face (normal -z, at z = -0.001) must not pull a
        // vertex resting on the top down through the plate.
        let bottom = [
            DVec3::new(-2.0, -2.0, -0.001),
            DVec3::new(-2.0, 3.0, -0.001),
            DVec3::new(3.0, -2.0, -0.001),
        ];
        let a = [
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(0.1, 0.2, 0.0005),
            DVec3::new(-1.0, 0.5, 1.0),
        ];
        assert!(contacts(&a, &bottom, 0.01).is_empty());
    }

    #[test]
    fn crossed_edges_give_an_edge_edge_contact_along_the_cross_product() {
        let h = 0.1;
        // A: vertical triangle in y = 0 with its lower edge along x at height h.
        let a = [
            DVec3::new(-1.0, 0.0, h),
            DVec3::new(1.0, 0.0, h),
            DVec3::new(0.0, 0.0, h + 1.0),
        ];
        // B: vertical triangle in x = 0 with its upper edge along y at height 0.
        let b = [
            DVec3::new(0.0, -1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.0, 0.3, -1.0),
        ];
        let c = contacts(&a, &b, 0.5);
        assert_eq!(c.len(), 1, "{c:?}");
        let c = c[0];
        assert_eq!(c.kind, ContactKind::EdgeEdge);
        let cross = (a[1] - a[0]).cross(b[1] - b[0]).normalize();
        assert!((c.normal.dot(cross).abs() - 1.0).abs() < 1e-15);
        // Oriented from B (below) to A (above).
        assert!((c.normal - DVec3::Z).length() < 1e-15);
        assert!((c.distance - h).abs() < 1e-15);
        assert!((c.point - DVec3::new(0.0, 0.0, h / 2.0)).length() < 1e-15);
        assert_eq!(
            (c.feature_a, c.feature_b),
            (Feature::edge(7, 0), Feature::edge(9, 0))
        );
        assert!((c.distance - triangle_distance(&a, &b).distance).abs() < 1e-15);
        // Reversing A's winding reverses the cross product but not the normal.
        let ar = [a[1], a[0], a[2]];
        let c2 = contacts(&ar, &b, 0.5);
        assert_eq!(c2.len(), 1);
        assert!((c2[0].normal - DVec3::Z).length() < 1e-15);
    }

    // Seeded random loop in the shape of bvh/sat.rs's box tests: the seed,
    // the count and the tally of interesting cases are this property's own.
    #[test]
    fn penetrating_pair_is_pushed_out_by_its_contact() {
        let mut rng = Rng(3);
        let mut seen = 0;
        for _ in 0..4_000 {
            let a = random_tri(&mut rng, 1.0);
            let b = random_tri(&mut rng, 1.0);
            if !tri_tri_overlap(&a, &b) {
                continue;
            }
            seen += 1;
            let all = contacts(&a, &b, 0.01);
            assert!((1..=3).contains(&all.len()));
            for k in &all {
                assert_eq!(k.kind, ContactKind::Penetrating);
                assert_eq!(k.normal, all[0].normal);
                assert!(k.distance <= 0.0);
            }
            let c = deepest_contact(&all);
            assert!((c.normal.length() - 1.0).abs() < 1e-12);
            // The minimum-overlap axis of a complete SAT axis set: moving A by
            // the depth (plus a hair) along the normal separates the pair.
            let eps = 1e-9;
            let moved = a.map(|p| p + c.normal * (c.depth() + eps));
            assert!(!tri_tri_overlap(&moved, &b), "{a:?} {b:?} {c:?}");
            // Swapping A and B gives the flipped contact.
            let d = deepest_contact(&contacts(&b, &a, 0.01));
            assert!((d.normal + c.normal).length() < 1e-9, "{c:?} {d:?}");
            assert!((d.distance - c.distance).abs() < 1e-12);
            assert!((d.point - c.point).length() < 1e-9);
        }
        assert!(seen > 200, "only {seen} intersecting pairs");
    }

    fn deepest_contact(c: &[Contact]) -> Contact {
        *c.iter().min_by(|x, y| x.distance.total_cmp(&y.distance)).unwrap()
    }

    #[test]
    fn triangle_lying_on_a_triangle_reports_all_its_corners() {
        let ground = [
            DVec3::new(-5.0, -5.0, 0.0),
            DVec3::new(5.0, -5.0, 0.0),
            DVec3::new(0.0, 5.0, 0.0),
        ];
        let flat = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
        ];
        let c = contacts(&flat, &ground, 0.01);
        assert_eq!(c.len(), 3, "{c:?}");
        for (k, x) in c.iter().enumerate() {
            assert_eq!(x.normal, DVec3::Z);
            assert_eq!(x.distance, 0.0);
            assert_eq!(x.feature_a, Feature::vertex(7, k as u8));
            assert_eq!(x.point, flat[k]);
        }
    }

    /// Sorts contacts into a canonical order for comparisons.
    fn canonical(mut v: Vec<Contact>) -> Vec<Contact> {
        v.sort_by_key(|x| (x.kind, x.feature_a, x.feature_b));
        v
    }

    #[test]
    fn separated_contacts_agree_with_triangle_distance_and_flip_under_swap() {
        let mut rng = Rng(99);
        let margin = 0.5;
        let mut exact_hits = 0;
        for _ in 0..4_000 {
            let a = random_tri(&mut rng, 1.0);
            let shift = DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
            let b = random_tri(&mut rng, 1.0).map(|p| p + shift);
            let td = triangle_distance(&a, &b);
            if td.distance == 0.0 {
                continue;
            }
            let c = contacts(&a, &b, margin);
            for k in &c {
                // No contact claims to be closer than the triangles are.
                assert!(k.distance >= td.distance - 1e-12, "{k:?} vs {}", td.distance);
                assert!(k.distance <= margin);
                assert!((k.normal.length() - 1.0).abs() < 1e-12);
            }
            // When the closest features are a front-side vertex/face pair or two
            // edge interiors, a contact reports exactly the triangle distance.
            let gap = td.point_a - td.point_b;
            let na = (a[1] - a[0]).cross(a[2] - a[0]);
            let nb = (b[1] - b[0]).cross(b[2] - b[0]);
            let expected = td.distance <= margin
                && match (td.feature_a, td.feature_b) {
                    (SubFeature::Vertex(_), SubFeature::Face) => nb.dot(gap) > 0.0,
                    (SubFeature::Face, SubFeature::Vertex(_)) => na.dot(gap) < 0.0,
                    // Edges count when the gap points out of the solids.
                    (SubFeature::Edge(_), SubFeature::Edge(_)) => {
                        gap.dot(nb.normalize() - na.normalize()) >= 0.0
                    }
                    _ => false,
                };
            if expected {
                exact_hits += 1;
                let best = c.iter().map(|k| k.distance).fold(f64::INFINITY, f64::min);
                assert!((best - td.distance).abs() < 1e-9, "{c:?} vs {td:?}");
                let k = c
                    .iter()
                    .find(|k| (k.distance - td.distance).abs() < 1e-9)
                    .unwrap();
                assert!((k.normal.dot(gap) - td.distance).abs() < 1e-9);
            }
            // Swapping A and B flips every contact.
            let mut d = Vec::new();
            triangle_contacts(&b, 9, &a, 7, margin, &mut d).unwrap();
            let c = canonical(c.iter().map(Contact::flipped).collect());
            let d = canonical(d);
            assert_eq!(c.len(), d.len(), "{c:?} vs {d:?}");
            for (x, y) in c.iter().zip(&d) {
                assert_eq!(
                    (x.kind, x.feature_a, x.feature_b),
                    (y.kind, y.feature_a, y.feature_b)
                );
                assert!((x.normal - y.normal).length() < 1e-9);
                assert!((x.point - y.point).length() < 1e-9);
                assert!((x.distance - y.distance).abs() < 1e-9);
            }
        }
        assert!(exact_hits > 200, "only {exact_hits} checked pairs");
    }

    #[test]
    fn pairs_whose_boxes_are_apart_have_no_contacts() {
        // Pairs placed so that their boxes' gap straddles the margin (the
        // early out's edge), and touching or crossing ones: where the early
        // out says apart, the full test finds nothing either, and the early
        // out fires on many of the pairs it could.
        let mut rng = Rng(5);
        let margin = 0.05;
        let (mut apart, mut apart_by_distance) = (0, 0);
        for _ in 0..20_000 {
            let a = random_tri(&mut rng, 1.0);
            let b = random_tri(&mut rng, 1.0);
            // Slide b along a random axis so its box is within a few margins
            // of a's (either side).
            let k = (rng.range(0.0, 3.0) as usize).min(2);
            let (lo_a, hi_a) = (a[0].min(a[1]).min(a[2])[k], a[0].max(a[1]).max(a[2])[k]);
            let (lo_b, hi_b) = (b[0].min(b[1]).min(b[2])[k], b[0].max(b[1]).max(b[2])[k]);
            let gap = rng.range(-0.5, 3.0) * margin;
            let shift = if rng.range(0.0, 1.0) < 0.5 {
                hi_a + gap - lo_b
            } else {
                lo_a - gap - hi_b
            };
            let b = b.map(|p| p + DVec3::AXES[k] * shift);
            let mut full = Vec::new();
            features_of_pair(&a, 7, &b, 9, margin, (None, None), &mut full);
            let far = triangle_distance(&a, &b).distance > margin;
            if boxes_apart(&a, &b, margin) {
                apart += 1;
                assert!(full.is_empty(), "boxes apart, yet {full:?}");
                assert!(far);
            }
            apart_by_distance += usize::from(far);
        }
        // Boxes apart by the margin along a world axis are most, not all,
        // of the pairs farther apart than the margin.
        assert!(apart > apart_by_distance / 2, "{apart} of {apart_by_distance}");
    }

    #[test]
    fn bad_input_is_an_error_and_leaves_out_unchanged() {
        let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let bad = [DVec3::ZERO, DVec3::new(f64::NAN, 0.0, 0.0), DVec3::Y];
        let mut out = Vec::new();
        assert_eq!(
            triangle_contacts(&t, 1, &bad, 2, 0.1, &mut out),
            Err(TriContactError::NonFinite { shape: 'B', id: 2 })
        );
        assert_eq!(
            triangle_contacts(&bad, 1, &t, 2, 0.1, &mut out),
            Err(TriContactError::NonFinite { shape: 'A', id: 1 })
        );
        for m in [-1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                triangle_contacts(&t, 1, &t, 2, m, &mut out),
                Err(TriContactError::InvalidMargin(_))
            ));
        }
        assert!(out.is_empty());
    }

    #[test]
    fn degenerate_triangles_do_not_panic() {
        let line = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
        let dot = [DVec3::ONE; 3];
        let t = [
            DVec3::new(-1.0, -1.0, 0.0),
            DVec3::new(3.0, -1.0, 0.0),
            DVec3::new(-1.0, 3.0, 0.0),
        ];
        for (x, y) in [
            (&line, &t),
            (&t, &line),
            (&dot, &t),
            (&line, &dot),
            (&line, &line),
        ] {
            for c in contacts(x, y, 1.5) {
                assert!(c.normal.is_finite() && c.point.is_finite() && c.distance.is_finite());
            }
        }
    }
}
