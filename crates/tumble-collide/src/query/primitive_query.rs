//! Primitive-versus-mesh queries in the modes of the mesh-mesh ones: the
//! mesh's OBBTree is walked against the primitive's bounding volume (sphere,
//! oriented box, or plane), candidate triangles go through the exact
//! primitive-triangle tests of [`super::primitive`], and contacts come from
//! the narrow phase's primitive-mesh routines (`contact_sphere_mesh`,
//! `contact_polytope_mesh`, `contact_capsule_mesh`, `contact_mesh_halfspace`).
//!
//! Each public query here opens like its mesh-mesh twin (same header and
//! checks, a `Shape` for A): public API kept apart by A's type, as the note
//! in query/mod.rs says; the walk and the exact tests are the primitive's.

use super::error::QueryError;
use super::input::{checked_args, QueryArgs};
use super::options::{bad_nonneg, CollideOptions, DistanceOptions, ReportMode};
use super::primitive::{Placed, PrimDistance};
use super::report::{DistanceResult, QueryStats, Report};
use crate::bvh::{self, TraversalError, TraversalStats, Traverse};
use crate::contact::Contact;
use crate::narrow;
use crate::pose::Pose;
use crate::shape::{MeshShape, Shape};

/// Walks the mesh's tree against the primitive (world frame) grown by
/// `margin` (m), handing every candidate triangle to `on_tri`.
// Its signature echoes `bvh::query_obb` (bvh/query.rs) because it only picks
// which of the tree's queries fits the primitive: `bvh` knows nothing of
// shapes, and `collide_primitive` and `within_tolerance_primitive` share it.
fn walk(
    prim: &Placed,
    mesh: &MeshShape,
    pose_m: &Pose,
    margin: f64,
    on_tri: impl FnMut(u32) -> Traverse,
) -> Result<TraversalStats, TraversalError> {
    let tree = mesh.tree();
    match *prim {
        Placed::Ball { c, r } => bvh::query_sphere(tree, pose_m, c, r + margin, on_tri),
        Placed::Capsule { obb, .. } | Placed::Box { obb, .. } => {
            bvh::query_obb(tree, pose_m, &obb, margin, on_tri)
        }
        Placed::Plane { n, d } => bvh::query_halfspace(tree, pose_m, n, d, margin, on_tri),
    }
}

/// Collision query between primitive A (a sphere, cuboid, capsule or
/// half-space [`Shape`]) at `pose_a` and mesh B at `pose_b`, in the modes
/// of [`super::collide`](fn@super::collide). `pairs` holds `(0, triangle of B)` for
/// every triangle that shares a point with the solid primitive. In
/// [`ReportMode::Contacts`] the contacts are the narrow phase's manifold for
/// the pair (normals from the mesh to the primitive), computed whole even with
/// `stop_at_first`.
///
/// # Errors
/// [`QueryError::BadPose`], [`QueryError::BadOption`] (`contact_margin`),
/// [`QueryError::NotPrimitive`] for a convex hull or a mesh as A.
pub fn collide_primitive(
    a: &Shape,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
    options: &CollideOptions,
) -> Result<Report, QueryError> {
    let (pose_a, pose_b) = checked_args(pose_a, pose_b, QueryArgs::Collide(options))?;
    let mode = options.report;
    let stop_first = options.stops_at_first();
    let prim = Placed::new(a, &pose_a, "collide_primitive")?;
    let mut report = Report::default();
    let mut tests = 0u64;
    let traversal = walk(&prim, b, &pose_b, 0.0, |t| {
        tests += 1;
        if !prim.intersects(&b.mesh().placed_triangle(t as usize, &pose_b)) {
            return Traverse::Continue;
        }
        report.record_hit((0, t), mode, stop_first)
    })
    .map_err(|_| bad_nonneg("margin", 0.0))?;
    // Unlike `collide`'s per triangle pair, the contacts are the narrow
    // phase's manifold of the whole primitive.
    if mode == ReportMode::Contacts {
        primitive_contacts(
            a,
            &pose_a,
            b,
            &pose_b,
            options.contact_margin,
            &mut report.contacts,
        );
    }
    report.finish(&traversal, tests, "collide_primitive")
}

/// The narrow phase's contacts of primitive A against mesh B.
fn primitive_contacts(a: &Shape, pa: &Pose, b: &MeshShape, pb: &Pose, margin: f64, out: &mut Vec<Contact>) {
    match a {
        Shape::Sphere(s) => narrow::contact_sphere_mesh(s, pa, b, pb, margin, out),
        Shape::Cuboid(c) => narrow::contact_polytope_mesh(c, pa, b, pb, margin, out),
        Shape::Capsule(c) => narrow::contact_capsule_mesh(c, pa, b, pb, margin, out),
        Shape::HalfSpace(h) => {
            let start = out.len();
            narrow::contact_mesh_halfspace(b, pb, h, pa, margin, out);
            for c in &mut out[start..] {
                *c = c.flipped();
            }
        }
        // Refused by `Placed::new` before any contact is sought.
        Shape::ConvexHull(_) | Shape::Mesh(_) => {}
    }
}

/// Minimum distance between primitive A at `pose_a` and mesh B at `pose_b`
/// with the closest points (`tri_a` is 0), exact with the default options,
/// within PQP's error bound otherwise (see [`DistanceOptions`]).
///
/// # Errors
/// [`QueryError::BadPose`], [`QueryError::BadOption`],
/// [`QueryError::NotFinite`], [`QueryError::NotPrimitive`].
pub fn distance_primitive(
    a: &Shape,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
    options: &DistanceOptions,
) -> Result<DistanceResult, QueryError> {
    let (pose_a, pose_b) = checked_args(pose_a, pose_b, QueryArgs::Distance(options))?;
    let world = Placed::new(a, &pose_a, "distance_primitive")?;
    // The primitive in the mesh frame, for the node lower bounds.
    let local = Placed::new(a, &pose_b.inverse().mul_pose(&pose_a), "distance_primitive")?;
    let mut best: Option<(u32, PrimDistance)> = None;
    let mut tests = 0u64;
    let traversal = bvh::volume_distance(
        b.tree(),
        f64::INFINITY,
        &options.tolerance(),
        |node| local.node_lower_bound(node),
        |t, best_so_far| {
            tests += 1;
            let d = world.distance(&b.mesh().placed_triangle(t as usize, &pose_b));
            if d.distance < best_so_far {
                best = Some((t, d));
            }
            d.distance
        },
    )
    .map_err(|_| bad_nonneg("DistanceOptions", options.rel_err))?;
    // The tail of `distance` (distance.rs) with a primitive for A: the walk is
    // one tree against a volume (`bvh::volume_distance`), not two trees, and
    // the best pair's type differs (`PrimDistance`, not `TriDistance`).
    let (tri_b, d) = best.ok_or(QueryError::NotFinite("distance_primitive"))?;
    DistanceResult {
        distance: d.distance,
        point_a: d.on_primitive,
        point_b: d.on_triangle,
        tri_a: 0,
        tri_b,
        stats: QueryStats::from_traversal(&traversal.stats, tests),
    }
    .finite("distance_primitive")
}

/// `true` when primitive A at `pose_a` and mesh B at `pose_b` come within
/// `tol` (m, finite, >= 0); consistent with [`distance_primitive`] in its
/// exact mode.
///
/// # Errors
/// [`QueryError::BadPose`]; [`QueryError::BadOption`] for a bad `tol`;
/// [`QueryError::NotPrimitive`].
pub fn within_tolerance_primitive(
    a: &Shape,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
    tol: f64,
) -> Result<bool, QueryError> {
    let (pose_a, pose_b) = checked_args(pose_a, pose_b, QueryArgs::Tolerance(tol))?;
    let prim = Placed::new(a, &pose_a, "within_tolerance_primitive")?;
    let mut within = false;
    // `within_tolerance`'s stop-at-first-close loop (tolerance.rs), around
    // one tree against the primitive's volume instead of two trees.
    walk(&prim, b, &pose_b, tol, |t| {
        if prim
            .distance(&b.mesh().placed_triangle(t as usize, &pose_b))
            .distance
            <= tol
        {
            within = true;
            Traverse::Stop
        } else {
            Traverse::Continue
        }
    })
    .map_err(|_| bad_nonneg("margin", tol))?;
    Ok(within)
}
