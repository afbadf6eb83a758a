//! The queries over any two [`Shape`]s, for callers that hold shapes rather
//! than know which query fits (the Python binding, tools): a mesh and a mesh
//! go to [`collide`](fn@collide), [`distance`](fn@distance) and [`within_tolerance`]; a primitive
//! (sphere, cuboid, capsule, half-space) and a mesh, in either order, to the
//! primitive queries, with the answer turned back into the caller's A / B
//! order. Two shapes without a mesh are refused ([`QueryError::NoMesh`]:
//! the dynamics' narrow phase, `crate::contact_shapes`, is the routine for
//! those), as are hulls ([`QueryError::NotPrimitive`]).

use super::error::QueryError;
use super::options::{CollideOptions, DistanceOptions};
use super::report::{DistanceResult, Report};
use super::{
    collide, collide_primitive, distance, distance_primitive, within_tolerance, within_tolerance_primitive,
};
use crate::pose::Pose;
use crate::shape::{MeshShape, Shape};

/// Which query a pair of shapes goes to.
enum Pairing<'s> {
    Meshes(&'s MeshShape, &'s MeshShape),
    /// The primitive, the mesh, and whether the primitive was B.
    PrimitiveMesh(&'s Shape, &'s MeshShape, bool),
}

/// The query for `a` and `b`; `query` names the caller in errors.
fn pairing<'s>(a: &'s Shape, b: &'s Shape, query: &'static str) -> Result<Pairing<'s>, QueryError> {
    if let Some(hull) = [a, b].into_iter().find(|s| matches!(s, Shape::ConvexHull(_))) {
        return Err(QueryError::NotPrimitive {
            query,
            kind: hull.kind_name(),
        });
    }
    match (a, b) {
        (Shape::Mesh(ma), Shape::Mesh(mb)) => Ok(Pairing::Meshes(ma, mb)),
        (p, Shape::Mesh(m)) => Ok(Pairing::PrimitiveMesh(p, m, false)),
        (Shape::Mesh(m), p) => Ok(Pairing::PrimitiveMesh(p, m, true)),
        (a, b) => Err(QueryError::NoMesh {
            a: a.kind_name(),
            b: b.kind_name(),
        }),
    }
}

/// [`collide`](fn@collide) or [`collide_primitive`], whichever fits `a` and `b`; the
/// report in the caller's order (pairs `(triangle of a, triangle of b)`,
/// normals from `b` to `a`; a primitive's triangle index is 0).
///
/// # Errors
/// Those of the query chosen; [`QueryError::NoMesh`] for two primitives,
/// [`QueryError::NotPrimitive`] for a hull.
pub fn collide_shapes(
    a: &Shape,
    pose_a: &Pose,
    b: &Shape,
    pose_b: &Pose,
    options: &CollideOptions,
) -> Result<Report, QueryError> {
    match pairing(a, b, "collide_shapes")? {
        Pairing::Meshes(ma, mb) => collide(ma, pose_a, mb, pose_b, options),
        Pairing::PrimitiveMesh(p, m, false) => collide_primitive(p, pose_a, m, pose_b, options),
        Pairing::PrimitiveMesh(p, m, true) => Ok(collide_primitive(p, pose_b, m, pose_a, options)?.swapped()),
    }
}

/// [`distance`](fn@distance) or [`distance_primitive`], whichever fits; points and
/// triangles in the caller's order.
///
/// # Errors
/// Those of the query chosen; [`QueryError::NoMesh`].
pub fn distance_shapes(
    a: &Shape,
    pose_a: &Pose,
    b: &Shape,
    pose_b: &Pose,
    options: &DistanceOptions,
) -> Result<DistanceResult, QueryError> {
    // Same three arms as `collide_shapes` and `within_tolerance_shapes`: the
    // options, results and turn-back differ (`Report::swapped`,
    // `DistanceResult::swapped`, nothing for a bool), so no one helper fits.
    match pairing(a, b, "distance_shapes")? {
        Pairing::Meshes(ma, mb) => distance(ma, pose_a, mb, pose_b, options),
        Pairing::PrimitiveMesh(p, m, false) => distance_primitive(p, pose_a, m, pose_b, options),
        Pairing::PrimitiveMesh(p, m, true) => {
            Ok(distance_primitive(p, pose_b, m, pose_a, options)?.swapped())
        }
    }
}

/// [`within_tolerance`] or [`within_tolerance_primitive`], whichever fits.
///
/// # Errors
/// Those of the query chosen; [`QueryError::NoMesh`].
pub fn within_tolerance_shapes(
    a: &Shape,
    pose_a: &Pose,
    b: &Shape,
    pose_b: &Pose,
    tol: f64,
) -> Result<bool, QueryError> {
    match pairing(a, b, "within_tolerance_shapes")? {
        Pairing::Meshes(ma, mb) => within_tolerance(ma, pose_a, mb, pose_b, tol),
        Pairing::PrimitiveMesh(p, m, false) => within_tolerance_primitive(p, pose_a, m, pose_b, tol),
        Pairing::PrimitiveMesh(p, m, true) => within_tolerance_primitive(p, pose_b, m, pose_a, tol),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::DVec3;
    use crate::mesh::torus_mesh;
    use crate::query::ReportMode;
    use crate::shape::{ConvexHull, Cuboid, Sphere};

    fn torus() -> Shape {
        Shape::Mesh(MeshShape::new(torus_mesh(1.0, 0.3, 24, 12).unwrap()).unwrap())
    }

    #[test]
    fn either_order_gives_the_same_answer_seen_from_the_other_side() {
        let (mesh, ball) = (torus(), Shape::Sphere(Sphere::new(0.35).unwrap()));
        let pm = Pose::IDENTITY;
        let Shape::Mesh(m) = &mesh else { unreachable!() };
        let all = CollideOptions {
            report: ReportMode::Contacts,
            ..CollideOptions::default()
        };
        // On the ring: the ball overlaps the tube.
        let on = Pose::from_translation(DVec3::new(1.0, 0.0, 0.5));
        let forward = collide_shapes(&ball, &on, &mesh, &pm, &all).unwrap();
        let backward = collide_shapes(&mesh, &pm, &ball, &on, &all).unwrap();
        assert!(forward.intersect && backward.intersect && !forward.contacts.is_empty());
        assert_eq!(forward, collide_primitive(&ball, &on, m, &pm, &all).unwrap());
        let reversed: Vec<(u32, u32)> = forward.pairs.iter().map(|&(p, t)| (t, p)).collect();
        assert_eq!(backward.pairs, reversed);
        for (f, b) in forward.contacts.iter().zip(&backward.contacts) {
            assert_eq!(b.normal, -f.normal);
            assert_eq!(b.distance, f.distance);
        }
        // Above the ring: apart; the distance's points swap with the order.
        let above = Pose::from_translation(DVec3::new(1.0, 0.0, 1.0));
        let options = DistanceOptions::default();
        let d1 = distance_shapes(&ball, &above, &mesh, &pm, &options).unwrap();
        let d2 = distance_shapes(&mesh, &pm, &ball, &above, &options).unwrap();
        assert!((d1.distance - 0.35).abs() < 0.02, "{}", d1.distance);
        assert_eq!(
            (d1.distance, d1.point_a, d1.point_b),
            (d2.distance, d2.point_b, d2.point_a)
        );
        assert_eq!((d1.tri_b, d2.tri_a), (d2.tri_a, d1.tri_b));
        for (a, b) in [(&ball, &mesh), (&mesh, &ball)] {
            let (pa, pb) = if matches!(a, Shape::Mesh(_)) {
                (pm, above)
            } else {
                (above, pm)
            };
            assert!(within_tolerance_shapes(a, &pa, b, &pb, d1.distance + 1e-9).unwrap());
            assert!(!within_tolerance_shapes(a, &pa, b, &pb, d1.distance * 0.9).unwrap());
        }
        // Two meshes: the mesh-mesh queries themselves.
        let shifted = Pose::from_translation(DVec3::new(0.5, 0.0, 0.0));
        assert_eq!(
            collide_shapes(&mesh, &pm, &mesh, &shifted, &all).unwrap(),
            collide(m, &pm, m, &shifted, &all).unwrap()
        );
    }

    #[test]
    fn two_primitives_or_a_hull_are_refused_with_typed_errors() {
        let ball = Shape::Sphere(Sphere::new(0.5).unwrap());
        let cube = Shape::Cuboid(Cuboid::new(DVec3::splat(0.5)).unwrap());
        let id = Pose::IDENTITY;
        let e = collide_shapes(&ball, &id, &cube, &id, &CollideOptions::default()).unwrap_err();
        assert_eq!(
            e,
            QueryError::NoMesh {
                a: "sphere",
                b: "cuboid"
            }
        );
        assert_eq!(
            e.to_string(),
            "a query needs at least one mesh; got two primitives (sphere and cuboid)"
        );
        let unit = Cuboid::new(DVec3::ONE).unwrap();
        let corners: Vec<DVec3> = (0..8).map(|i| unit.corner(i)).collect();
        let hull = Shape::ConvexHull(ConvexHull::from_points(&corners).unwrap());
        assert!(matches!(
            distance_shapes(&torus(), &id, &hull, &id, &DistanceOptions::default()),
            Err(QueryError::NotPrimitive {
                query: "distance_shapes",
                kind: "convex_hull"
            })
        ));
    }
}
