//! Where a round body's centre stands against one triangle of a mesh's
//! smooth surface (`shape::SmoothSurface`): over it (its foot on the
//! Phong surface, `triangle::phong`), beyond a smooth edge (a neighbour
//! has the foot), or beyond a crease (the flat triangle decides). Shared by
//! the sphere and the capsule contacts with meshes.

use crate::contact::{Contact, ContactKind, Feature};
use crate::math::DVec3;
use crate::pose::Pose;
use crate::shape::{MeshShape, SmoothSurface};
use crate::triangle::{phong_point, PhongPoint};

/// Where a point (shape frame) stands against triangle `t` of a mesh's
/// smooth surface.
pub(super) enum SmoothFoot {
    /// Over the triangle: the contact is the foot's.
    Over(PhongPoint),
    /// Beyond a smooth edge: the neighbour across it has the foot.
    Neighbour,
    /// Beyond a crease (or no foot at all): the flat triangle's closest
    /// point gives the contact, as on a mesh without a smooth surface.
    Crease,
}

/// The foot of `point` (shape frame), the centre of a round body of
/// `radius`, on the smooth surface over triangle `t`. A centre more than
/// its radius behind the surface is not this triangle's to push: it is
/// inside the solid (a bowl's outer face, seen from a ball inside the
/// bowl), and the flat triangle's unsigned distance decides.
pub(super) fn smooth_foot(s: &SmoothSurface, m: &MeshShape, t: u32, point: DVec3, radius: f64) -> SmoothFoot {
    let tri = m.mesh().triangle(t as usize);
    let Some(foot) = phong_point(point, &tri, s.corner_normals(t)) else {
        return SmoothFoot::Crease;
    };
    if foot.height < -radius {
        return SmoothFoot::Crease;
    }
    // A centre over a shared edge is claimed by both triangles (`merge`
    // keeps one copy of the contact).
    let (k, _) = foot.worst_corner();
    if foot.is_over() {
        SmoothFoot::Over(foot)
    } else if s.is_crease(t, (k + 1) % 3) {
        SmoothFoot::Crease
    } else {
        SmoothFoot::Neighbour
    }
}

/// Appends the contact of a round body of `radius` (its side `feature_a`)
/// whose centre has `foot` over triangle `t` of a mesh at `pose`, when its
/// gap is within `margin`: normal along the surface's, point midway across
/// the gap (world frame).
pub(super) fn push_foot_contact(
    out: &mut Vec<Contact>,
    foot: &PhongPoint,
    radius: f64,
    pose: &Pose,
    margin: f64,
    feature_a: Feature,
    t: u32,
) {
    let distance = foot.height - radius;
    if distance <= margin {
        let normal = pose.rotation * foot.normal;
        out.push(Contact {
            point: pose.transform_point(foot.surface) + normal * (0.5 * distance),
            normal,
            distance,
            kind: ContactKind::Smooth,
            feature_a,
            feature_b: Feature::face(t),
        });
    }
}
