//! Mesh-mesh collision query (Gottschalk, Lin & Manocha 1996; thesis 4.6,
//! 5.1, 5.2; PQP's `PQP_Collide` with its first-contact and all-contacts
//! flags): both OBBTrees are walked together and every candidate triangle
//! pair goes through the exact closed triangle-triangle test
//! ([`tri_tri_overlap`](fn@tri_tri_overlap)), and, for contacts, through the triangle contact
//! routine (every pair's vertex/face and edge/edge contacts, and the corner
//! contacts of the corners and edges each pair owns) and [`merge_contacts`].
//!
//! Its head (signature, then `checked_args`) reads like `distance`'s and the
//! `_primitive` twins': one public shape in PQP's order, kept per query
//! because A's type and the options differ (query/mod.rs says more).

use super::error::QueryError;
use super::input::{checked_args, QueryArgs};
use super::options::{bad_nonneg, CollideOptions, ReportMode};
use super::report::Report;
use crate::bvh::{self, Traverse};
use crate::contact::{Contact, ContactKind, SubFeature};
use crate::math::DVec3;
use crate::narrow::MeshAt;
use crate::pose::Pose;
use crate::shape::MeshShape;
use crate::triangle::{
    merge_contacts, tri_tri_overlap, triangle_contacts_and_corners, Copies, MergeParams, Owned, Side,
};

/// Collision query between mesh A at `pose_a` and mesh B at `pose_b`
/// (meshes are surfaces: a mesh entirely inside another does not intersect
/// it).
///
/// - `intersect`: some closed triangle of A shares a point with some closed
///   triangle of B (touching counts), decided by the exact predicates of
///   [`tri_tri_overlap`](fn@tri_tri_overlap).
/// - [`ReportMode::TrianglePairs`] and [`ReportMode::Contacts`]: all such
///   pairs, sorted; with `stop_at_first` only the first one found (the walk
///   really ends there: a first-contact query costs one root-to-leaf descent
///   when the meshes clearly intersect).
/// - [`ReportMode::Contacts`]: the contacts of every candidate pair within
///   `contact_margin` ([`triangle_contacts`](crate::triangle::triangle_contacts):
///   vertex/face and edge/edge contacts with exact closest points, push-out
///   contacts for intersecting pairs), without edge/edge contacts on
///   internal edges between coplanar triangles (the faces' vertex contacts
///   carry those points), and with the duplicates of shared vertices and
///   edges merged; and, within a margin, a corner closest to an edge or a
///   corner of the other mesh (vertex/edge, edge/vertex and vertex/vertex
///   contacts, which no single triangle pair can judge: each is found from
///   the pair that owns both features, with the triangles around them,
///   `triangle::tri_vertex_edge`), so that the nearest contact of two meshes
///   apart within the margin is never farther than they are.
///
/// # Errors
/// [`QueryError::BadPose`] for a non-finite pose or a quaternion that is not
/// unit; [`QueryError::BadOption`] for a negative or non-finite
/// `contact_margin`.
///
/// # Example
/// Two unit cubes, B 0.9 m above A (so they overlap by 0.1 m), shifted
/// sideways so that no faces are coplanar:
/// ```
/// use tumble_collide::mesh::box_mesh;
/// use tumble_collide::query::{collide, distance, CollideOptions, DistanceOptions, ReportMode};
/// use tumble_collide::{DQuat, DVec3, MeshShape, Pose};
///
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let cube = MeshShape::new(box_mesh(DVec3::splat(0.5))?)?;
/// let pose_a = Pose::IDENTITY;
/// let pose_b = Pose::new(DVec3::new(0.3, 0.2, 0.9), DQuat::IDENTITY)?;
///
/// // First contact only: stops at the first intersecting triangle pair.
/// let first = CollideOptions { stop_at_first: true, report: ReportMode::Boolean, ..Default::default() };
/// assert!(collide(&cube, &pose_a, &cube, &pose_b, &first)?.intersect);
///
/// // All intersecting triangle pairs, with contacts.
/// let all = CollideOptions { report: ReportMode::Contacts, ..Default::default() };
/// let report = collide(&cube, &pose_a, &cube, &pose_b, &all)?;
/// assert!(!report.pairs.is_empty());
/// // The deepest contact: 0.1 m along -z (normals point from B to A).
/// let deepest = report.contacts.iter().max_by(|x, y| x.depth().total_cmp(&y.depth())).unwrap();
/// assert!((deepest.depth() - 0.1).abs() < 1e-9);
/// assert!((deepest.normal - DVec3::new(0.0, 0.0, -1.0)).length() < 1e-9);
///
/// // Lift B to 1.5 m: the gap is 0.5 m.
/// let lifted = Pose::from_translation(DVec3::new(0.3, 0.2, 1.5));
/// let d = distance(&cube, &pose_a, &cube, &lifted, &DistanceOptions::default())?;
/// assert!((d.distance - 0.5).abs() < 1e-12);
/// assert!((d.point_b.z - d.point_a.z - 0.5).abs() < 1e-12);
/// # Ok(())
/// # }
/// ```
pub fn collide(
    a: &MeshShape,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
    options: &CollideOptions,
) -> Result<Report, QueryError> {
    let (pose_a, pose_b) = checked_args(pose_a, pose_b, QueryArgs::Collide(options))?;
    let mode = options.report;
    let stop_first = options.stops_at_first();
    let margin = if mode == ReportMode::Contacts {
        options.contact_margin
    } else {
        0.0
    };
    let (ma, mb) = (a.mesh(), b.mesh());
    let mut report = Report::default();
    let mut tests = 0u64;
    let traversal = bvh::collide(a.tree(), &pose_a, b.tree(), &pose_b, margin, |ta, tb| {
        let wa = ma.placed_triangle(ta as usize, &pose_a);
        let wb = mb.placed_triangle(tb as usize, &pose_b);
        tests += 1;
        // Closed triangles that share a point have overlapping bounding
        // boxes (min / max are exact): a cheap, exact first rejection.
        let hit = aabbs_overlap(&wa, &wb) && tri_tri_overlap(&wa, &wb);
        // Disjoint closed triangles are apart by a positive distance, so
        // with no margin they have no contacts.
        if mode == ReportMode::Contacts && (hit || margin > 0.0) {
            let mut copies = WorldPairCopies {
                a: MeshAt {
                    mesh: a,
                    pose: &pose_a,
                },
                b: MeshAt {
                    mesh: b,
                    pose: &pose_b,
                },
                pair: (ta, tb),
            };
            let mut owned = Owned {
                a: a.owned_features(ta),
                b: b.owned_features(tb),
                b_margins: [margin; 3],
                copies: &mut copies,
            };
            triangle_contacts_and_corners(&wa, ta, &wb, tb, margin, &mut owned, &mut report.contacts);
        }
        if hit {
            report.record_hit((ta, tb), mode, stop_first)
        } else {
            Traverse::Continue
        }
    })
    .map_err(|_| bad_nonneg("CollideOptions::contact_margin", margin))?;
    if mode == ReportMode::Contacts {
        finish_contacts(&mut report.contacts, a, b);
    }
    // Each triangle sits in exactly one leaf, so every pair came once.
    report.finish(&traversal, tests, "collide")
}

/// Drops edge/edge contacts on internal edges (an edge between coplanar
/// triangles defines no normal of its own) and merges duplicates.
///
/// Why this is not `narrow::contact_mesh_mesh`: both walk the trees with
/// `bvh::collide` and end in `triangle_contacts` and `merge_contacts`, but
/// the query's contacts are a geometric answer, checked contact for contact
/// against brute force (tests/query_oracle.rs; a corner contact against its
/// two features): world-frame triangles (the frame the exact pair
/// predicates and the truth file use), contacts only for intersecting pairs
/// at margin 0, only internal *edge* contacts dropped. The narrow phase's are a physics manifold: triangles in A's
/// frame through a per-thread vertex cache (speed), every candidate pair
/// within the margin, and ghost contacts on flat edges *and* vertices
/// dropped unless they act along the face normal. Sharing the walk would
/// change one contract or the other.
fn finish_contacts(contacts: &mut Vec<Contact>, a: &MeshShape, b: &MeshShape) {
    let internal = |m: &MeshShape, f: crate::contact::Feature| match f.sub {
        SubFeature::Edge(k) => m.is_flat_edge(f.index, k),
        _ => false,
    };
    contacts.retain(|c| {
        !(c.kind == ContactKind::EdgeEdge && (internal(a, c.feature_a) || internal(b, c.feature_b)))
    });
    // The default parameters are valid: merging cannot fail.
    let _ = merge_contacts(
        contacts,
        a.mesh().triangles(),
        b.mesh().triangles(),
        &MergeParams::default(),
    );
}

/// Two meshes in the world, around one pair of their triangles: the
/// neighbours of the pair's corners and edges (`triangle::Copies`).
struct WorldPairCopies<'m> {
    a: MeshAt<'m>,
    b: MeshAt<'m>,
    pair: (u32, u32),
}

impl Copies for WorldPairCopies<'_> {
    fn any_around_corner(
        &mut self,
        side: Side,
        k: usize,
        visit: &mut dyn FnMut(&[DVec3; 3]) -> bool,
    ) -> bool {
        match side {
            Side::A => self.a.any_around_corner(self.pair.0, k, visit),
            Side::B => self.b.any_around_corner(self.pair.1, k, visit),
        }
    }

    fn across(&mut self, side: Side, k: usize) -> Option<[DVec3; 3]> {
        match side {
            Side::A => self.a.across(self.pair.0, k),
            Side::B => self.b.across(self.pair.1, k),
        }
    }
}

/// The axis-aligned bounding boxes of two triangles overlap (closed).
#[inline]
fn aabbs_overlap(a: &[DVec3; 3], b: &[DVec3; 3]) -> bool {
    let (lo_a, hi_a) = (a[0].min(a[1]).min(a[2]), a[0].max(a[1]).max(a[2]));
    let (lo_b, hi_b) = (b[0].min(b[1]).min(b[2]), b[0].max(b[1]).max(b[2]));
    lo_a.cmple(hi_b).all() && lo_b.cmple(hi_a).all()
}
