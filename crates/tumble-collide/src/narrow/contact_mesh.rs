//! Contacts involving triangle meshes (thesis 5.2, 7.1): both OBBTrees are
//! walked together with a tolerance (the boxes grown by the margin), and
//! every candidate triangle pair goes through the exact triangle contact
//! routine (vertex/face, edge/edge, and push-out contacts where triangles
//! already intersect) on the corners and edges its triangles own, so that
//! each shared vertex and edge is tested once (`triangle::tri_contact`,
//! "Shared features, once"); what copies remain (push-out contacts of
//! neighbouring intersecting pairs, boundary and non-manifold edges, a vertex
//! over the edge between two faces) are merged. Primitives against meshes:
//! boxes and hulls as their faces' triangles against the tree (each pair's
//! vertex/face and edge/edge contacts, and a corner against an edge or a
//! corner from the features' owners: `polytope_fans`), spheres by the
//! closest point on each nearby triangle (or their centre's foot on the
//! smooth surface the mesh stands for, when it has one:
//! `shape::SmoothSurface`), half-spaces by the mesh vertices within the
//! margin.

use super::contact_halfspace::push_vertex_on_plane;
use super::polytope_fans::{FanMeshCopies, POLYTOPE_FANS};
use super::smooth_foot::{push_foot_contact, smooth_foot, SmoothFoot};
use crate::bvh::{self, Obb, Traverse, WalkFront};
use crate::contact::{Contact, ContactKind, Feature, SubFeature};
use crate::drift::Drift;
use crate::math::{DMat3, DVec3};
use crate::pose::Pose;
use crate::shape::{HalfSpace, MeshShape, Polytope, Sphere};
use crate::triangle::{
    closest_point_on_triangle, merge_contacts, triangle_contacts_and_corners, triangle_contacts_owned,
    Copies, MergeParams, Owned, Side,
};
use std::cell::RefCell;

/// A mesh placed at a pose: its triangles, and those around a triangle's
/// corners and across its edges, in the world (the neighbours that the
/// corner contacts' cones need: `triangle::Copies`).
#[derive(Clone, Copy)]
pub(crate) struct MeshAt<'m> {
    pub mesh: &'m MeshShape,
    pub pose: &'m Pose,
}

impl MeshAt<'_> {
    /// Triangle `t` in the world.
    #[inline]
    pub(crate) fn triangle(&self, t: u32) -> [DVec3; 3] {
        self.mesh.mesh().placed_triangle(t as usize, self.pose)
    }

    /// `MeshShape::any_around_corner`, the triangles placed.
    pub(crate) fn any_around_corner(
        &self,
        t: u32,
        k: usize,
        visit: &mut dyn FnMut(&[DVec3; 3]) -> bool,
    ) -> bool {
        self.mesh.any_around_corner(t, k, |c| visit(&self.triangle(c)))
    }

    /// `MeshShape::across`, the triangle placed.
    pub(crate) fn across(&self, t: u32, k: usize) -> Option<[DVec3; 3]> {
        self.mesh.across(t, k).map(|c| self.triangle(c))
    }
}

/// A contact on an internal feature of a mesh (a flat edge or a flat vertex)
/// is valid only along the surrounding face normal: within about 2.5 degrees.
pub const INTERNAL_FEATURE_COS: f64 = 0.999;

/// `true` when the mesh side `f` of a contact is an internal feature: an
/// edge between coplanar triangles or a vertex inside a flat region. Such a
/// feature has no normal of its own (issue: no ghost bumps on flat ground
/// made of many triangles).
fn is_internal(f: Feature, m: &MeshShape) -> bool {
    match f.sub {
        SubFeature::Edge(k) => m.is_flat_edge(f.index, k),
        SubFeature::Vertex(k) => m.is_flat_vertex(f.index, k),
        _ => false,
    }
}

/// `true` when `outward` (out of the mesh at feature `f`) is the face normal
/// of `f`'s triangle, or `f` is not an internal feature.
fn valid_on(f: Feature, m: &MeshShape, pose: &Pose, outward: DVec3) -> bool {
    if !is_internal(f, m) {
        return true;
    }
    let face = pose.rotation * m.mesh().triangle_normal_scaled(f.index as usize);
    face.dot(outward) >= INTERNAL_FEATURE_COS * face.length()
}

/// Removes the ghost contacts of internal features (world frame): a contact
/// whose mesh side is a flat edge or flat vertex and whose normal is not that
/// flat region's normal, e.g. a vertex of flat ground that a sliding box's
/// side face sweeps towards. The flat region's own face contacts carry the
/// real support there. The normal points from B to A, so it leaves A along
/// `-normal` and B along `+normal`.
fn drop_internal_contacts(
    out: &mut Vec<Contact>,
    start: usize,
    a: Option<(&MeshShape, &Pose)>,
    b: Option<(&MeshShape, &Pose)>,
) {
    retain_from(out, start, |c| {
        c.kind == ContactKind::Penetrating
            || (a.is_none_or(|(m, pose)| valid_on(c.feature_a, m, pose, -c.normal))
                && b.is_none_or(|(m, pose)| valid_on(c.feature_b, m, pose, c.normal)))
    });
}

/// `Vec::retain` on `out[start..]`, keeping the order (one pass, no shifting
/// per removal).
fn retain_from(out: &mut Vec<Contact>, start: usize, keep: impl Fn(&Contact) -> bool) {
    let mut write = start;
    for read in start..out.len() {
        if keep(&out[read]) {
            out[write] = out[read];
            write += 1;
        }
    }
    out.truncate(write);
}

/// Merges duplicates; the parameters are valid constants, so merging cannot fail.
fn merge(out: &mut Vec<Contact>, start: usize, tris_a: &[[u32; 3]], tris_b: &[[u32; 3]]) {
    let mut tail = out.split_off(start);
    let _ = merge_contacts(&mut tail, tris_a, tris_b, &MergeParams::default());
    out.extend(tail);
}

/// Mesh B's vertices in mesh A's frame, each transformed once per query on
/// first use, with how far each moves over the query's drift (its
/// look-ahead). Kept per thread and reused, so the narrow phase does not
/// allocate once warmed up; a generation stamp marks the valid entries.
pub(super) struct VertexCache {
    points: Vec<DVec3>,
    moves: Vec<f64>,
    stamp: Vec<u32>,
    generation: u32,
    /// B's drift against A, in A's frame.
    drift: Drift,
}

impl VertexCache {
    /// Starts a query of a mesh B with `n` vertices drifting by `drift`
    /// (A's frame) against A.
    pub(super) fn begin(&mut self, n: usize, drift: &Drift) {
        if self.stamp.len() < n {
            self.points.resize(n, DVec3::ZERO);
            self.moves.resize(n, 0.0);
            self.stamp.resize(n, 0);
        }
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            self.stamp.fill(0);
            self.generation = 1;
        }
        self.drift = *drift;
    }

    /// Vertex `v` of B in A's frame.
    #[inline]
    pub(super) fn get(&mut self, v: u32, rot: &DMat3, trans: DVec3, vertices: &[DVec3]) -> DVec3 {
        let i = v as usize;
        if self.stamp[i] != self.generation {
            self.stamp[i] = self.generation;
            let p = *rot * vertices[i] + trans;
            self.points[i] = p;
            self.moves[i] = if self.drift.is_none() {
                0.0
            } else {
                self.drift.displacement(p).length()
            };
        }
        self.points[i]
    }

    /// How far vertex `v` of B moves over the drift (m); `v` must have been
    /// placed ([`Self::get`]) in this query.
    #[inline]
    pub(super) fn moves(&self, v: u32) -> f64 {
        self.moves[v as usize]
    }
}

/// Two meshes placed for their triangle tests: A's triangles as stored,
/// B's moved into A's frame by `rot` and `trans` through the per-thread
/// vertex cache (each of B's vertices placed once per query). Every
/// mesh-mesh search, list and re-evaluation places its triangles here.
pub(super) struct PlacedPair<'m, 'c> {
    pub a: &'m MeshShape,
    pub b: &'m MeshShape,
    pub rot: &'m DMat3,
    pub trans: DVec3,
    pub cache: &'c mut VertexCache,
}

impl PlacedPair<'_, '_> {
    /// Triangle `t` of `side`'s mesh in A's frame.
    #[inline]
    fn triangle(&mut self, side: Side, t: u32) -> [DVec3; 3] {
        match side {
            Side::A => self.a.mesh().triangle(t as usize),
            Side::B => {
                let vb = self.b.mesh().vertices();
                self.b.mesh().triangles()[t as usize].map(|v| self.cache.get(v, self.rot, self.trans, vb))
            }
        }
    }

    /// The triangles of the pair `(ta, tb)` in A's frame.
    #[inline]
    pub(super) fn triangles(&mut self, ta: u32, tb: u32) -> ([DVec3; 3], [DVec3; 3]) {
        (self.triangle(Side::A, ta), self.triangle(Side::B, tb))
    }

    /// Triangle `ta` of A against triangle `tb` of B: the contacts of the
    /// corners and edges each owns (`triangle::tri_contact`, "Shared
    /// features, once") within `margin` plus each feature's own look-ahead
    /// (how far it can move against the other mesh in the step: B's corner
    /// by its drift, B's edge by the larger of its ends', A's corner
    /// against B's face by the largest of the face's corners'; the drift is
    /// first order, so a point of an edge or face moves no farther than its
    /// farthest corner). Every mesh-mesh search and re-evaluation goes
    /// through it, so they agree to the bit.
    pub(super) fn owned_contacts(&mut self, (ta, tb): (u32, u32), margin: f64, out: &mut Vec<Contact>) {
        let (wa, wb) = self.triangles(ta, tb);
        let corners_b = self.b.mesh().triangles()[tb as usize];
        let b_margins = corners_b.map(|v| margin + self.cache.moves(v));
        let test_margin = b_margins[0].max(b_margins[1]).max(b_margins[2]);
        let (owned_a, owned_b) = (self.a.owned_features(ta), self.b.owned_features(tb));
        let mut copies = PairCopies {
            placed: self,
            pair: (ta, tb),
        };
        let mut owned = Owned {
            a: owned_a,
            b: owned_b,
            b_margins,
            copies: &mut copies,
        };
        triangle_contacts_owned(&wa, ta, &wb, tb, test_margin, &mut owned, out);
    }
}

/// The triangles around a pair's features (`triangle::tri_contact::Copies`),
/// placed as the pair's own.
struct PairCopies<'p, 'm, 'c> {
    placed: &'p mut PlacedPair<'m, 'c>,
    pair: (u32, u32),
}

impl<'m> PairCopies<'_, 'm, '_> {
    /// `side`'s mesh and the pair's triangle of it.
    fn side(&self, side: Side) -> (&'m MeshShape, u32) {
        match side {
            Side::A => (self.placed.a, self.pair.0),
            Side::B => (self.placed.b, self.pair.1),
        }
    }
}

impl Copies for PairCopies<'_, '_, '_> {
    fn any_around_corner(
        &mut self,
        side: Side,
        k: usize,
        visit: &mut dyn FnMut(&[DVec3; 3]) -> bool,
    ) -> bool {
        let (mesh, t) = self.side(side);
        mesh.any_around_corner(t, k, |c| visit(&self.placed.triangle(side, c)))
    }

    fn across(&mut self, side: Side, k: usize) -> Option<[DVec3; 3]> {
        let (mesh, t) = self.side(side);
        mesh.across(t, k).map(|c| self.placed.triangle(side, c))
    }
}

thread_local! {
    pub(super) static VERTEX_CACHE: RefCell<VertexCache> = const {
        RefCell::new(VertexCache {
            points: Vec::new(),
            moves: Vec::new(),
            stamp: Vec::new(),
            generation: 0,
            drift: Drift::NONE,
        })
    };
}

/// Mesh A against mesh B: exact triangle contacts within `margin`.
/// (`query::collide` in its contacts mode gives the geometric answer for
/// the same pair; why the two stay apart: see its `finish_contacts`.)
///
/// The triangle tests run in A's frame: A's triangles are used as stored and
/// each of B's vertices is moved into A's frame once, instead of moving both
/// triangles of every candidate pair into the world. The contacts are moved
/// to the world at the end.
// The common narrow signature (see `narrow`'s module docs); the body is the
// only two-tree walk, with the per-thread vertex cache of B's vertices.
pub fn contact_mesh_mesh(
    a: &MeshShape,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    contact_mesh_mesh_moving(a, pose_a, b, pose_b, margin, &Drift::NONE, out);
}

/// [`contact_mesh_mesh`] while B drifts by `drift` (world) relative to A,
/// besides motions within `margin`: each triangle pair that comes within
/// `margin` along the drift (`bvh::collide_moving`) gives the contacts of
/// the features its triangles own within `margin` plus each feature's
/// look-ahead (`PlacedPair::owned_contacts`). A pair the drift cannot bring
/// together is left out: no contact of it could close in the step, so the
/// solver loses nothing, and the triangles tested follow each part's own
/// motion instead of the body's fastest point. A shared vertex or edge is
/// tested in its owner's pairs alone, and loses nothing either: when it
/// comes within `margin` of the other mesh along the drift, so does its
/// owner triangle, whose leaf pair the walk then reaches.
pub fn contact_mesh_mesh_moving(
    a: &MeshShape,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
    margin: f64,
    drift: &Drift,
    out: &mut Vec<Contact>,
) {
    let mut next = WalkFront::new();
    contact_mesh_mesh_front(
        (a, pose_a),
        (b, pose_b),
        (margin, drift),
        &WalkFront::new(),
        &mut next,
        out,
    );
}

/// [`contact_mesh_mesh_moving`] with the walk begun at `front`'s cut
/// (`bvh::front`; an empty front is the roots), the front where it ended
/// written to `next`: the same contacts, bit for bit. Where a leaf
/// pair that the walk from the roots does not reach (an ancestor above the
/// cut is apart) gives contacts, they are dropped (the walk's question,
/// `bvh::front`), so the answer is that walk's, whatever front the pair kept.
pub(super) fn contact_mesh_mesh_front(
    (a, pose_a): (&MeshShape, &Pose),
    (b, pose_b): (&MeshShape, &Pose),
    (margin, drift): (f64, &Drift),
    front: &WalkFront,
    next: &mut WalkFront,
    out: &mut Vec<Contact>,
) {
    let start = out.len();
    let rel = pose_a.inverse().mul_pose(pose_b);
    let rot = DMat3::from_quat(rel.rotation);
    let (tree_a, tree_b) = (a.tree(), b.tree());
    VERTEX_CACHE.with_borrow_mut(|cache| {
        cache.begin(b.mesh().vertices().len(), &drift.in_frame_of(pose_a));
        let mut placed = PlacedPair {
            a,
            b,
            rot: &rot,
            trans: rel.position,
            cache,
        };
        let on_leaves = |x: u32, y: u32, reached: &mut dyn FnMut() -> bool| {
            let before = out.len();
            for &ta in tree_a.leaf_triangles(&tree_a.nodes()[x as usize]) {
                for &tb in tree_b.leaf_triangles(&tree_b.nodes()[y as usize]) {
                    placed.owned_contacts((ta, tb), margin, out);
                }
            }
            // Found below a cut entry the walk from the roots does not
            // reach: not its contacts (`bvh::front`).
            if out.len() > before && !reached() {
                out.truncate(before);
            }
            Traverse::Continue
        };
        // (A refused margin or drift gives no contacts; the callers check
        // both first.)
        let _ = bvh::collide_leaves_front(
            tree_a, pose_a, tree_b, pose_b, margin, drift, front, next, on_leaves,
        );
    });
    finish_mesh_mesh(out, start, a, pose_a, b, pose_b);
}

/// The end of every mesh-mesh contact query: the contacts appended since
/// `start` (A's frame) moved to the world, the ghosts of internal features
/// dropped, the duplicates of shared features merged and the survivors
/// named through the features' owners.
pub(super) fn finish_mesh_mesh(
    out: &mut Vec<Contact>,
    start: usize,
    a: &MeshShape,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
) {
    for c in &mut out[start..] {
        c.point = pose_a.transform_point(c.point);
        c.normal = pose_a.rotation * c.normal;
    }
    drop_internal_contacts(out, start, Some((a, pose_a)), Some((b, pose_b)));
    merge(out, start, a.mesh().triangles(), b.mesh().triangles());
    // A vertex or edge contact is named through the feature's owner, so
    // that every search and re-evaluation calls it the same (warm starts
    // and kept points match by name). A push-out contact belongs to its
    // intersecting triangle pair and keeps that pair's names.
    for c in out[start..]
        .iter_mut()
        .filter(|c| c.kind != ContactKind::Penetrating)
    {
        c.feature_a = a.owner_name(c.feature_a);
        c.feature_b = b.owner_name(c.feature_b);
    }
}

/// Mesh A against half-space B: every mesh vertex within `margin` of the
/// plane, in vertex order (a resting torus gives a ring of them; choosing
/// the few the solver needs is the contact reduction's job, which can keep
/// last step's choice: `reduce_patch`).
// Reads like `contact_polytope_halfspace` (contact_halfspace.rs) at the top;
// a mesh needs its vertices named through their first triangle and is not
// reduced here.
pub fn contact_mesh_halfspace(
    a: &MeshShape,
    pose_a: &Pose,
    b: &HalfSpace,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    let (n, d) = b.world_plane(pose_b);
    // The vertices within the margin lie in triangles whose leaf boxes
    // reach within it: the tree finds them without visiting every vertex
    // (a scanned mesh has millions). Each vertex is taken once, through the
    // triangle that names it, and pushed in index order, as a scan of all
    // vertices would push them.
    let tris = a.mesh().triangles();
    let mut near: Vec<u32> = Vec::new();
    let _ = bvh::query_halfspace(a.tree(), pose_a, n, d, margin, |t| {
        for (k, &v) in tris[t as usize].iter().enumerate() {
            if a.first_corner(v) == Some((t, k as u8)) {
                near.push(v);
            }
        }
        Traverse::Continue
    });
    near.sort_unstable();
    let vertices = a.mesh().vertices();
    for v in near {
        if let Some((t, k)) = a.first_corner(v) {
            let feature = Feature::vertex(t, k);
            push_vertex_on_plane(
                out,
                pose_a.transform_point(vertices[v as usize]),
                n,
                d,
                margin,
                feature,
            );
        }
    }
}

/// Polytope A (box or hull) against mesh B: the polytope's faces, fanned
/// into triangles, against the mesh triangles near the polytope's box:
/// every pair's vertex/face and edge/edge contacts (`triangle_contacts`),
/// and the vertex/edge, edge/vertex and vertex/vertex contacts of the
/// corners and edges the pair owns (`polytope_fans`; a box's corner beside
/// a mesh's edge, with the box's edges level and parallel to the mesh's,
/// is seen by nothing else).
pub fn contact_polytope_mesh<P: Polytope + ?Sized>(
    a: &P,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    // The polytope's bounding box in its own frame, placed in the world.
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for v in 0..a.vertex_count() {
        lo = lo.min(a.vertex(v));
        hi = hi.max(a.vertex(v));
    }
    let query = Obb {
        center: pose_a.transform_point((lo + hi) * 0.5),
        axes: DMat3::from_quat(pose_a.rotation),
        half_extents: (hi - lo) * 0.5,
    };
    // Polytope faces as triangles (world), named by face and fan index. The
    // fan's diagonals are internal edges: edge 0 of fan triangle k > 1 and
    // edge 2 of fan triangle k < len - 2.
    let start = out.len();
    POLYTOPE_FANS.with_borrow_mut(|fans| {
        fans.refill(a, pose_a);
        let _ = bvh::query_obb(b.tree(), pose_b, &query, margin, |tb| {
            let wb = b.mesh().placed_triangle(tb as usize, pose_b);
            let owned_b = b.owned_features(tb);
            for (t, (wa, id)) in fans.tris.iter().enumerate() {
                let mut copies = FanMeshCopies {
                    fans,
                    mesh: MeshAt {
                        mesh: b,
                        pose: pose_b,
                    },
                    pair: (t as u32, tb),
                };
                let mut owned = Owned {
                    a: fans.owned(t),
                    b: owned_b,
                    b_margins: [margin; 3],
                    copies: &mut copies,
                };
                triangle_contacts_and_corners(wa, *id, &wb, tb, margin, &mut owned, out);
            }
            Traverse::Continue
        });
    });
    let fan_diagonal = |f: Feature| {
        let (face, k) = ((f.index >> 8) as usize, (f.index & 0xff) as usize);
        let len = a.face_len(face);
        matches!(f.sub, SubFeature::Edge(0) if k > 1) || matches!(f.sub, SubFeature::Edge(2) if k + 2 < len)
    };
    retain_from(out, start, |c| {
        !(c.kind == ContactKind::EdgeEdge && fan_diagonal(c.feature_a))
    });
    drop_internal_contacts(out, start, None, Some((b, pose_b)));
    merge(out, start, &[], b.mesh().triangles());
}

/// Sphere A against mesh B: the closest point of every nearby triangle, or
/// on a mesh with a smooth surface, the foot of the centre on it.
// Same argument list as `contact_sphere_polytope` (contact_segment_polytope.rs)
// and the other narrow routines; a mesh is walked per triangle through its
// tree, where a polytope is one convex body for GJK.
pub fn contact_sphere_mesh(
    a: &Sphere,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) {
    let c = pose_a.position;
    let r = a.radius();
    let start = out.len();
    let smooth = b.smooth_surface();
    let reach = smooth.map_or(0.0, |s| s.reach());
    // The centre in the mesh's frame, where its smooth surface is.
    let local = smooth.map(|_| pose_b.inverse_transform_point(c));
    let _ = bvh::query_sphere(b.tree(), pose_b, c, r + margin + reach, |tb| {
        if let (Some(s), Some(local)) = (smooth, local) {
            match smooth_foot(s, b, tb, local, r) {
                SmoothFoot::Over(foot) => {
                    push_foot_contact(out, &foot, r, pose_b, margin, Feature::WHOLE, tb);
                    return Traverse::Continue;
                }
                SmoothFoot::Neighbour => return Traverse::Continue,
                SmoothFoot::Crease => {}
            }
        }
        let wb = b.mesh().placed_triangle(tb as usize, pose_b);
        let (q, sub) = closest_point_on_triangle(c, &wb);
        let delta = c - q;
        let dist = delta.length();
        // A closest point on an internal edge (or a vertex inside a flat
        // region) counts only where the centre is straight above it, along
        // the face normal: then it is a face contact that lies on the
        // boundary of every triangle sharing the feature (the centre of a
        // sphere over the diagonal of a square face), and `merge` keeps one
        // of the copies. Elsewhere it is a ghost: a neighbouring face holds
        // the real closest point.
        let feature = Feature { index: tb, sub };
        let outward = if dist > 1e-12 { delta / dist } else { DVec3::ZERO };
        if dist - r <= margin && (dist <= 1e-12 || valid_on(feature, b, pose_b, outward)) {
            let face_n = (wb[1] - wb[0]).cross(wb[2] - wb[0]);
            // Centre on the surface or inside: push out along the face normal.
            let normal = if dist > 1e-12 {
                delta / dist
            } else {
                face_n.normalize_or_zero()
            };
            if normal != DVec3::ZERO {
                out.push(Contact {
                    point: q + normal * (0.5 * (dist - r)),
                    normal,
                    distance: dist - r,
                    kind: ContactKind::Smooth,
                    feature_a: Feature::WHOLE,
                    feature_b: Feature { index: tb, sub },
                });
            }
        }
        Traverse::Continue
    });
    merge(out, start, &[], b.mesh().triangles());
}
