//! Contacts re-evaluated at named features (issue 15, "contacts re-validated
//! rather than re-found when motion is small"): given the features of
//! contacts found earlier, the contacts of those same triangle pairs (or
//! mesh vertices against a plane) at the current poses, without walking the
//! trees. A caller that knows a pair has barely moved since its last search
//! gets the points it kept, at their exact current distances, for the cost
//! of a few triangle tests instead of every triangle pair near the contact.
//!
//! A named triangle pair goes through the same arithmetic as a resting
//! pair's search (`mesh_pair_memory`: A's triangle as stored, B's vertices
//! moved into A's frame, the triangle test on the features each triangle
//! owns, then the common finish), so at the same margin it gives the
//! contacts a search would give for that pair, named the same way (a
//! shared vertex or edge through its owner).

use super::contact_halfspace::push_vertex_on_plane;
use super::contact_mesh::{finish_mesh_mesh, PlacedPair, VERTEX_CACHE};
use super::dispatch::{check_margin_and_drift, refuse_non_finite};
use super::NarrowError;
use crate::contact::{Contact, Feature, SubFeature};
use crate::drift::Drift;
use crate::math::DMat3;
use crate::pose::Pose;
use crate::shape::{HalfSpace, MeshShape, Shape};

/// The contacts within `margin` of the triangle pairs (two meshes) or mesh
/// vertices (a mesh and a half-space) that `features` name, `(feature of A,
/// feature of B)` as in [`Contact`], appended to `out` with the conventions
/// of [`contact_shapes`](super::contact_shapes). Each triangle pair or
/// vertex is evaluated once, in increasing order, whatever the order and
/// repetitions of `features`; features that name no triangle of the mesh
/// are skipped. Returns `Ok(false)`, appending nothing, for any other shape
/// pair (nothing to re-evaluate: their searches are cheap). A margin that
/// is not finite and `>= 0` is [`NarrowError::BadMargin`], contacts whose
/// arithmetic overflowed [`NarrowError::NotFinite`].
pub fn contact_at_features(
    a: &Shape,
    pose_a: &Pose,
    b: &Shape,
    pose_b: &Pose,
    margin: f64,
    features: impl Iterator<Item = (Feature, Feature)>,
    out: &mut Vec<Contact>,
) -> Result<bool, NarrowError> {
    check_margin_and_drift(margin, &Drift::NONE)?;
    let start = out.len();
    match (a, b) {
        (Shape::Mesh(x), Shape::Mesh(y)) => {
            let mut pairs: Vec<(u32, u32)> = features.map(|(fa, fb)| (fa.index, fb.index)).collect();
            pairs.sort_unstable();
            pairs.dedup();
            triangle_pairs(x, pose_a, y, pose_b, margin, &pairs, out);
            refuse_non_finite(out, start, "mesh", "mesh")?;
        }
        (Shape::Mesh(x), Shape::HalfSpace(y)) => {
            vertices_on_plane(x, pose_a, y, pose_b, margin, features.map(|(fa, _)| fa), out);
            refuse_non_finite(out, start, "mesh", "half-space")?;
        }
        (Shape::HalfSpace(x), Shape::Mesh(y)) => {
            vertices_on_plane(y, pose_b, x, pose_a, margin, features.map(|(_, fb)| fb), out);
            for c in &mut out[start..] {
                *c = c.flipped();
            }
            refuse_non_finite(out, start, "half-space", "mesh")?;
        }
        _ => return Ok(false),
    }
    Ok(true)
}

/// The triangle test on each of `pairs` (sorted, unique), as the tree walk
/// runs it, then the walk's finish (world frame, ghosts dropped, duplicates
/// merged).
fn triangle_pairs(
    a: &MeshShape,
    pose_a: &Pose,
    b: &MeshShape,
    pose_b: &Pose,
    margin: f64,
    pairs: &[(u32, u32)],
    out: &mut Vec<Contact>,
) {
    let start = out.len();
    let rel = pose_a.inverse().mul_pose(pose_b);
    let rot = DMat3::from_quat(rel.rotation);
    let (count_a, count_b) = (a.mesh().triangles().len(), b.mesh().triangles().len());
    VERTEX_CACHE.with_borrow_mut(|cache| {
        cache.begin(b.mesh().vertices().len(), &Drift::NONE);
        let mut placed = PlacedPair {
            a,
            b,
            rot: &rot,
            trans: rel.position,
            cache,
        };
        for &(ta, tb) in pairs {
            if (ta as usize) < count_a && (tb as usize) < count_b {
                placed.owned_contacts((ta, tb), margin, out);
            }
        }
    });
    finish_mesh_mesh(out, start, a, pose_a, b, pose_b);
}

/// The mesh vertices that `features` name (corners of triangles) against
/// the plane, each once in vertex order and named by its first corner, as
/// `contact_mesh_halfspace` names them.
fn vertices_on_plane(
    a: &MeshShape,
    pose_a: &Pose,
    b: &HalfSpace,
    pose_b: &Pose,
    margin: f64,
    features: impl Iterator<Item = Feature>,
    out: &mut Vec<Contact>,
) {
    let tris = a.mesh().triangles();
    let mut vertices: Vec<u32> = features
        .filter_map(|f| match f.sub {
            SubFeature::Vertex(k) => tris
                .get(f.index as usize)
                .and_then(|t| t.get(k as usize))
                .copied(),
            _ => None,
        })
        .collect();
    vertices.sort_unstable();
    vertices.dedup();
    let (n, d) = b.world_plane(pose_b);
    let points = a.mesh().vertices();
    for v in vertices {
        if let Some((t, k)) = a.first_corner(v) {
            let p = pose_a.transform_point(points[v as usize]);
            push_vertex_on_plane(out, p, n, d, margin, Feature::vertex(t, k));
        }
    }
}
