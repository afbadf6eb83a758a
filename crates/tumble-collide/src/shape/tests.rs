//! Shape-level properties: constructors reject bad input; world AABBs hold
//! (and touch) the support points in every direction; supports agree with the
//! polytope view.

use super::*;
use crate::math::{DQuat, DVec3};
use crate::mesh::cylinder_mesh;
use proptest::prelude::*;

/// The bounded shapes the shape and narrow-phase tests run over (one list
/// for both: `narrow::tests::library` adds a polyhedral hull and the ground).
pub(crate) fn shapes() -> Vec<Shape> {
    vec![
        Sphere::new(0.4).unwrap().into(),
        Cuboid::new(DVec3::new(0.5, 0.3, 0.2)).unwrap().into(),
        Capsule::new(0.25, 0.4).unwrap().into(),
        ConvexHull::from_mesh(&cylinder_mesh(0.4, 0.3, 7).unwrap())
            .unwrap()
            .into(),
    ]
}

#[test]
fn constructors_reject_bad_numbers() {
    assert!(matches!(Sphere::new(0.0), Err(ShapeError::BadDimension { .. })));
    assert!(matches!(
        Sphere::new(f64::NAN),
        Err(ShapeError::BadDimension { .. })
    ));
    assert!(matches!(
        Capsule::new(1.0, -0.1),
        Err(ShapeError::BadDimension { .. })
    ));
    assert!(Capsule::new(1.0, 0.0).is_ok());
    assert!(matches!(
        Capsule::new(f64::INFINITY, 1.0),
        Err(ShapeError::BadDimension { .. })
    ));
    assert!(matches!(
        HalfSpace::new(DVec3::new(0.0, 0.0, 2.0), 0.0),
        Err(ShapeError::NotUnit { .. })
    ));
    assert!(matches!(
        HalfSpace::new(DVec3::Z, f64::NAN),
        Err(ShapeError::BadDimension { .. })
    ));
}

#[test]
fn constructors_reject_dimensions_beyond_the_coordinate_limit() {
    // Finite but past MAX_DIMENSION (a sphere of radius f64::MAX gave
    // contacts 1.8e308 m deep, libFuzzer's world_step); at the limit, kept.
    let far = 1e37;
    let too_big = |r: Result<Shape, ShapeError>, name: &str| match r {
        Err(ShapeError::BadDimension { value, .. }) => assert!(value.abs() >= far, "{name}: {value}"),
        other => panic!("{name}: {other:?}"),
    };
    too_big(Sphere::new(f64::MAX).map(Shape::from), "sphere");
    too_big(Sphere::new(far).map(Shape::from), "sphere");
    too_big(Cuboid::new(DVec3::new(1.0, far, 1.0)).map(Shape::from), "cuboid");
    too_big(Capsule::new(far, 1.0).map(Shape::from), "capsule radius");
    too_big(Capsule::new(1.0, far).map(Shape::from), "capsule half height");
    too_big(
        HalfSpace::new(DVec3::Z, -far).map(Shape::from),
        "half-space offset",
    );
    let huge = crate::mesh::box_mesh(DVec3::splat(far)).unwrap();
    too_big(ConvexHull::from_mesh(&huge).map(Shape::from), "hull vertex");
    assert!(Sphere::new(MAX_DIMENSION).is_ok());
    assert!(HalfSpace::new(DVec3::Z, -MAX_DIMENSION).is_ok());
    let message = Sphere::new(far).unwrap_err().to_string();
    assert!(
        message.contains("radius") && message.contains("1e36"),
        "{message}"
    );
}

#[test]
fn half_space_plane_moves_with_its_pose() {
    let h = HalfSpace::new(DVec3::Z, 0.5).unwrap();
    let pose = Pose::new(
        DVec3::new(1.0, 2.0, 3.0),
        DQuat::from_rotation_x(std::f64::consts::PI),
    )
    .unwrap();
    let (n, d) = h.world_plane(&pose);
    // Flipped upside down and lifted: the solid is z >= 2.5, i.e. -z <= -2.5.
    assert!((n + DVec3::Z).length() < 1e-12);
    assert!((d + 2.5).abs() < 1e-12);
    let bb = h.aabb(&pose);
    assert!((bb.min.z - 2.5).abs() < 1e-12 && bb.max.z == f64::INFINITY);
}

proptest! {
    #[test]
    fn aabb_holds_and_touches_the_support_points(
        p in prop::array::uniform3(-5.0f64..5.0),
        r in prop::array::uniform3(-3.2f64..3.2),
        d in prop::array::uniform3(-1.0f64..1.0),
    ) {
        let pose = Pose::new(DVec3::from_array(p), DQuat::from_euler(glam::EulerRot::ZYX, r[0], r[1], r[2])).unwrap();
        let dir = DVec3::from_array(d);
        prop_assume!(dir.length() > 1e-3);
        for s in shapes() {
            let bb = s.aabb(&pose);
            let local_dir = pose.rotation.inverse() * dir;
            let w = pose.transform_point(s.support(local_dir).unwrap());
            prop_assert!(bb.expanded(1e-9).contains_point(w));
            // Tight: the support along +x reaches max.x, along -x min.x.
            for axis in 0..3 {
                let mut e = DVec3::ZERO;
                e[axis] = 1.0;
                let hi = pose.transform_point(s.support(pose.rotation.inverse() * e).unwrap());
                let lo = pose.transform_point(s.support(pose.rotation.inverse() * -e).unwrap());
                prop_assert!((hi[axis] - bb.max[axis]).abs() < 1e-9);
                prop_assert!((lo[axis] - bb.min[axis]).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn polytope_support_is_the_farthest_vertex(d in prop::array::uniform3(-1.0f64..1.0)) {
        let dir = DVec3::from_array(d);
        let b = Cuboid::new(DVec3::new(0.5, 0.3, 0.2)).unwrap();
        let h = ConvexHull::from_mesh(&cylinder_mesh(0.4, 0.3, 7).unwrap()).unwrap();
        let best = |p: &dyn Polytope| (0..p.vertex_count()).map(|i| p.vertex(i).dot(dir)).fold(f64::NEG_INFINITY, f64::max);
        prop_assert!((b.vertex(Polytope::support_vertex(&b, dir)).dot(dir) - best(&b)).abs() < 1e-12);
        prop_assert!((h.support(dir).dot(dir) - best(&h)).abs() < 1e-12);
    }
}
