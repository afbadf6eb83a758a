//! The one table that routes a pair of shapes to its contact routine, laid
//! out as a matrix (rows: shape A, columns: shape B) in the manner of MuJoCo's
//! collision table. Pairs below the diagonal are the mirror of a pair above
//! it: the routine runs with A and B swapped and its contacts are flipped, so
//! `contact_shapes(b, a)` is exactly the flip of `contact_shapes(a, b)`.
//! The table's rows read alike by design: one line per shape pair.
//!
//! ```text
//!  A \ B      | Sphere         Cuboid          Capsule          ConvexHull       HalfSpace          Mesh
//! ------------+----------------------------------------------------------------------------------------------
//!  Sphere     | sphere_sphere  sphere_cuboid   sphere_capsule   sphere_polytope  sphere_halfspace   sphere_mesh
//!  Cuboid     | mirror         cuboid_cuboid   mirror           mirror           polytope_halfspace polytope_mesh
//!  Capsule    | mirror         capsule_polytope capsule_capsule capsule_polytope capsule_halfspace  capsule_mesh
//!  ConvexHull | mirror         polytope_polytope mirror         polytope_polytope polytope_halfspace polytope_mesh
//!  HalfSpace  | mirror         mirror          mirror           mirror           Unsupported        mirror
//!  Mesh       | mirror         mirror          mirror           mirror           mesh_halfspace     mesh_mesh
//! ```

use super::*;
use crate::contact::Contact;
use crate::drift::Drift;
use crate::pose::Pose;
use crate::shape::Shape;

/// Contacts between shape A at `pose_a` and shape B at `pose_b` whose signed
/// distance is at most `margin` (m, >= 0), appended to `out` (normals from B
/// to A). A pair without a routine is an error, never an empty answer; so is
/// a pair whose contact arithmetic overflows ([`NarrowError::NotFinite`]:
/// nothing is appended then, so no NaN reaches a solver).
pub fn contact_shapes(
    a: &Shape,
    pose_a: &Pose,
    b: &Shape,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) -> Result<(), NarrowError> {
    contact_shapes_moving(a, pose_a, b, pose_b, margin, &Drift::NONE, out)
}

/// [`contact_shapes`] while B drifts by `drift` (world frame) relative to
/// A, besides motions within `margin`: the contacts the drift can close.
/// Two meshes follow the drift through their trees
/// ([`contact_mesh_mesh_moving`]); every other pair takes the contacts
/// within `margin` plus the drift's reach over B's bounding box (A's, when
/// B is a half-space). A drift with a non-finite component is
/// [`NarrowError::BadDrift`]; nothing is appended then.
pub fn contact_shapes_moving(
    a: &Shape,
    pose_a: &Pose,
    b: &Shape,
    pose_b: &Pose,
    margin: f64,
    drift: &Drift,
    out: &mut Vec<Contact>,
) -> Result<(), NarrowError> {
    check_margin_and_drift(margin, drift)?;
    let start = out.len();
    match (a, b) {
        (Shape::Mesh(x), Shape::Mesh(y)) => {
            contact_mesh_mesh_moving(x, pose_a, y, pose_b, margin, drift, out)
        }
        _ if drift.is_none() => dispatch(a, pose_a, b, pose_b, margin, out)?,
        _ => {
            let bounds = b.aabb(pose_b);
            let (center, radius) = (
                (bounds.min + bounds.max) * 0.5,
                (bounds.max - bounds.min).length() * 0.5,
            );
            // An unbounded B (a half-space) is reached by A's motion instead.
            let reach = if radius.is_finite() {
                drift.reach(center, radius)
            } else {
                let bounds = a.aabb(pose_a);
                let (center, radius) = (
                    (bounds.min + bounds.max) * 0.5,
                    (bounds.max - bounds.min).length() * 0.5,
                );
                drift.reach(center, radius)
            };
            dispatch(a, pose_a, b, pose_b, margin + reach, out)?
        }
    }
    refuse_non_finite(out, start, a.kind_name(), b.kind_name())
}

/// [`NarrowError::BadMargin`] unless `margin` is finite and `>= 0`,
/// [`NarrowError::BadDrift`] unless every component of `drift` is finite.
pub(super) fn check_margin_and_drift(margin: f64, drift: &Drift) -> Result<(), NarrowError> {
    if !(margin.is_finite() && margin >= 0.0) {
        return Err(NarrowError::BadMargin(margin));
    }
    if !drift.is_finite() {
        return Err(NarrowError::BadDrift);
    }
    Ok(())
}

/// [`NarrowError::NotFinite`] for shapes of kinds `a` and `b` when a contact
/// appended since `start` is not finite, and those contacts removed.
pub(super) fn refuse_non_finite(
    out: &mut Vec<Contact>,
    start: usize,
    a: &'static str,
    b: &'static str,
) -> Result<(), NarrowError> {
    let finite = out[start..]
        .iter()
        .all(|c| c.point.is_finite() && c.normal.is_finite() && c.distance.is_finite());
    if !finite {
        out.truncate(start);
        return Err(NarrowError::NotFinite { a, b });
    }
    Ok(())
}

/// The table itself.
// Opens like `contact_shapes`, which checks the margin and drift and widens
// the margin by the drift's reach before calling here; this is the bare table.
fn dispatch(
    a: &Shape,
    pose_a: &Pose,
    b: &Shape,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<Contact>,
) -> Result<(), NarrowError> {
    use Shape::*;
    let (pa, pb, m) = (pose_a, pose_b, margin);
    // One arm per cell of the matrix in the module docs, row by row: the arms
    // read alike on purpose, so each cell's routine (or its mirror) is
    // visible at a glance; a macro would hide exactly that.
    match (a, b) {
        // Row: Sphere
        (Sphere(x), Sphere(y)) => contact_sphere_sphere(x, pa, y, pb, m, out),
        (Sphere(x), Cuboid(y)) => contact_sphere_cuboid(x, pa, y, pb, m, out),
        (Sphere(x), Capsule(y)) => contact_sphere_capsule(x, pa, y, pb, m, out),
        (Sphere(x), ConvexHull(y)) => contact_sphere_polytope(x, pa, y, pb, m, out),
        (Sphere(x), HalfSpace(y)) => contact_sphere_halfspace(x, pa, y, pb, m, out),
        // Row: Cuboid
        (Cuboid(x), Sphere(y)) => mirror(out, |o| contact_sphere_cuboid(y, pb, x, pa, m, o)),
        (Cuboid(x), Cuboid(y)) => contact_cuboid_cuboid(x, pa, y, pb, m, out),
        (Cuboid(x), Capsule(y)) => mirror(out, |o| contact_capsule_polytope(y, pb, x, pa, m, o)),
        (Cuboid(x), ConvexHull(y)) => mirror(out, |o| contact_polytope_polytope(y, pb, x, pa, m, o)),
        (Cuboid(x), HalfSpace(y)) => contact_polytope_halfspace(x, pa, y, pb, m, out),
        // Row: Capsule
        (Capsule(x), Sphere(y)) => mirror(out, |o| contact_sphere_capsule(y, pb, x, pa, m, o)),
        (Capsule(x), Cuboid(y)) => contact_capsule_polytope(x, pa, y, pb, m, out),
        (Capsule(x), Capsule(y)) => contact_capsule_capsule(x, pa, y, pb, m, out),
        (Capsule(x), ConvexHull(y)) => contact_capsule_polytope(x, pa, y, pb, m, out),
        (Capsule(x), HalfSpace(y)) => contact_capsule_halfspace(x, pa, y, pb, m, out),
        // Row: ConvexHull
        (ConvexHull(x), Sphere(y)) => mirror(out, |o| contact_sphere_polytope(y, pb, x, pa, m, o)),
        (ConvexHull(x), Cuboid(y)) => contact_polytope_polytope(x, pa, y, pb, m, out),
        (ConvexHull(x), Capsule(y)) => mirror(out, |o| contact_capsule_polytope(y, pb, x, pa, m, o)),
        (ConvexHull(x), ConvexHull(y)) => contact_polytope_polytope(x, pa, y, pb, m, out),
        (ConvexHull(x), HalfSpace(y)) => contact_polytope_halfspace(x, pa, y, pb, m, out),
        // Row: HalfSpace
        (HalfSpace(x), Sphere(y)) => mirror(out, |o| contact_sphere_halfspace(y, pb, x, pa, m, o)),
        (HalfSpace(x), Cuboid(y)) => mirror(out, |o| contact_polytope_halfspace(y, pb, x, pa, m, o)),
        (HalfSpace(x), Capsule(y)) => mirror(out, |o| contact_capsule_halfspace(y, pb, x, pa, m, o)),
        (HalfSpace(x), ConvexHull(y)) => mirror(out, |o| contact_polytope_halfspace(y, pb, x, pa, m, o)),
        (HalfSpace(x), Mesh(y)) => mirror(out, |o| contact_mesh_halfspace(y, pb, x, pa, m, o)),
        // Row: Mesh
        (Mesh(x), Sphere(y)) => mirror(out, |o| contact_sphere_mesh(y, pb, x, pa, m, o)),
        (Mesh(x), Cuboid(y)) => mirror(out, |o| contact_polytope_mesh(y, pb, x, pa, m, o)),
        (Mesh(x), Capsule(y)) => mirror(out, |o| contact_capsule_mesh(y, pb, x, pa, m, o)),
        (Mesh(x), ConvexHull(y)) => mirror(out, |o| contact_polytope_mesh(y, pb, x, pa, m, o)),
        (Mesh(x), HalfSpace(y)) => contact_mesh_halfspace(x, pa, y, pb, m, out),
        (Mesh(x), Mesh(y)) => contact_mesh_mesh(x, pa, y, pb, m, out),
        // Column: Mesh
        (Sphere(x), Mesh(y)) => contact_sphere_mesh(x, pa, y, pb, m, out),
        (Cuboid(x), Mesh(y)) => contact_polytope_mesh(x, pa, y, pb, m, out),
        (Capsule(x), Mesh(y)) => contact_capsule_mesh(x, pa, y, pb, m, out),
        (ConvexHull(x), Mesh(y)) => contact_polytope_mesh(x, pa, y, pb, m, out),
        (HalfSpace(_), HalfSpace(_)) => {
            return Err(NarrowError::Unsupported {
                a: a.kind_name(),
                b: b.kind_name(),
            })
        }
    }
    Ok(())
}

/// Runs a routine for the swapped pair (B, A) and flips what it appended.
fn mirror(out: &mut Vec<Contact>, routine: impl FnOnce(&mut Vec<Contact>)) {
    let start = out.len();
    routine(out);
    for c in &mut out[start..] {
        *c = c.flipped();
    }
}
