//! Unit tests of the body record: validation, derived quantities, accumulators.

use super::*;
use proptest::prelude::*;
use tumble_collide::math::{DMat3, DQuat, DVec3};
use tumble_collide::Pose;

fn pose() -> Pose {
    Pose::new(
        DVec3::new(1.0, -2.0, 0.5),
        DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1),
    )
    .unwrap()
}

fn body() -> RigidBody {
    let mut b = RigidBody::new_dynamic(2.5, DVec3::new(0.4, 0.7, 0.9), pose()).unwrap();
    b.set_linear_momentum(DVec3::new(1.0, 2.0, -3.0)).unwrap();
    b.set_angular_momentum(DVec3::new(-0.3, 0.8, 0.2)).unwrap();
    b
}

#[test]
fn constructors_reject_bad_mass_and_inertia() {
    let i = DVec3::new(1.0, 1.0, 1.0);
    for m in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-320] {
        let e = RigidBody::new_dynamic(m, i, pose()).unwrap_err();
        assert!(
            matches!(
                e,
                BodyError::NonPositiveMass(_) | BodyError::NonFiniteScalar { .. }
            ),
            "mass {m}: {e:?}"
        );
    }
    for bad in [
        DVec3::new(0.0, 1.0, 1.0),
        DVec3::new(1.0, -1.0, 1.0),
        DVec3::new(1.0, f64::NAN, 1.0),
    ] {
        assert!(RigidBody::new_dynamic(1.0, bad, pose()).is_err());
    }
    assert!(matches!(
        RigidBody::new_dynamic(1.0, DVec3::new(1.0, 1.0, 5.0), pose()),
        Err(BodyError::InertiaTriangleInequality(_))
    ));
    // A flat plate sits exactly on the triangle inequality (I3 = I1 + I2).
    assert!(RigidBody::new_dynamic(1.0, DVec3::new(0.1, 0.2, 0.3), pose()).is_ok());
}

#[test]
fn failed_setters_leave_the_body_unchanged() {
    let mut b = body();
    b.apply_force(DVec3::new(1.0, 0.0, 0.0)).unwrap();
    let before = b.clone();
    let nan = DVec3::new(f64::NAN, 0.0, 0.0);
    let inf = DVec3::new(0.0, f64::INFINITY, 0.0);
    assert!(b.set_mass(-2.0).is_err());
    assert!(b.set_mass(f64::NAN).is_err());
    assert!(b.set_principal_inertia(DVec3::new(1.0, 1.0, 3.0)).is_err());
    assert!(b.set_position(nan).is_err());
    assert!(b.set_orientation(DQuat::from_xyzw(1.0, 1.0, 1.0, 1.0)).is_err());
    assert!(b
        .set_orientation(DQuat::from_xyzw(f64::NAN, 0.0, 0.0, 1.0))
        .is_err());
    assert!(b.set_linear_velocity(inf).is_err());
    assert!(b.set_angular_velocity(nan).is_err());
    assert!(b.set_linear_momentum(nan).is_err());
    assert!(b.set_angular_momentum(inf).is_err());
    assert!(b.set_damping(-0.1, 0.0).is_err());
    assert!(b.set_damping(0.1, f64::NAN).is_err());
    assert!(b.set_kinematic_velocity(DVec3::X, DVec3::Y).is_err()); // wrong kind
    let mut bad_state = *b.state();
    bad_state.angular_momentum = nan;
    assert!(b.set_state(bad_state).is_err());
    assert!(b.apply_force(nan).is_err());
    assert!(b.apply_force(DVec3::splat(f64::MAX)).is_ok());
    let after_big = b.clone();
    // Adding another huge force would overflow the accumulator to infinity.
    assert!(b.apply_force(DVec3::splat(f64::MAX)).is_err());
    assert_eq!(b, after_big);
    b.clear_forces();
    let mut b = before.clone();
    assert!(b.apply_force_at_point(DVec3::X, inf).is_err());
    assert!(b.apply_torque(nan).is_err());
    assert!(b.apply_impulse_at_point(nan, DVec3::ZERO).is_err());
    assert!(b.apply_central_impulse(inf).is_err());
    assert!(b.apply_angular_impulse(nan).is_err());
    assert_eq!(b, before);
}

#[test]
fn material_is_validated() {
    assert!(Material::new(0.5, 0.3).is_ok());
    assert!(matches!(
        Material::new(-0.1, 0.3),
        Err(BodyError::Negative { .. })
    ));
    assert!(matches!(
        Material::new(0.5, f64::INFINITY),
        Err(BodyError::NonFiniteScalar { .. })
    ));
}

#[test]
fn wrong_kind_operations_are_errors() {
    let mut s = RigidBody::new_static(pose());
    assert!(matches!(
        s.set_mass(1.0),
        Err(BodyError::WrongKind {
            expected: BodyKind::Dynamic,
            found: BodyKind::Static,
            ..
        })
    ));
    assert!(s.set_linear_velocity(DVec3::X).is_err());
    assert!(s.set_kinematic_velocity(DVec3::X, DVec3::ZERO).is_err());
    let mut st = *s.state();
    st.linear_momentum = DVec3::X;
    assert!(s.set_state(st).is_err());
    assert_eq!(s, RigidBody::new_static(pose()));
}

#[test]
fn static_and_kinematic_bodies_ignore_pushes() {
    for mut b in [RigidBody::new_static(pose()), RigidBody::new_kinematic(pose())] {
        let before = b.clone();
        b.apply_force(DVec3::new(3.0, 0.0, 0.0)).unwrap();
        b.apply_force_at_point(DVec3::Z, DVec3::X).unwrap();
        b.apply_torque(DVec3::Y).unwrap();
        b.apply_impulse_at_point(DVec3::Z, DVec3::X).unwrap();
        b.apply_central_impulse(DVec3::Z).unwrap();
        b.apply_angular_impulse(DVec3::Z).unwrap();
        assert_eq!(b, before);
        assert_eq!(b.mass(), f64::INFINITY);
        assert_eq!(b.inv_inertia_world(), DMat3::ZERO);
    }
}

#[test]
fn velocity_setters_round_trip_through_momenta() {
    let mut b = body();
    let v = DVec3::new(0.3, -1.0, 2.0);
    let w = DVec3::new(-1.5, 0.2, 0.9);
    b.set_linear_velocity(v).unwrap();
    b.set_angular_velocity(w).unwrap();
    assert!((b.velocity() - v).length() < 1e-14);
    assert!((b.angular_velocity() - w).length() < 1e-13);
    assert!((b.linear_momentum() - v * 2.5).length() < 1e-14);
    // L = I(t) omega with I(t) = R diag(I) R^T built as a matrix.
    let r = DMat3::from_quat(b.orientation());
    let i_world = r * DMat3::from_diagonal(DVec3::new(0.4, 0.7, 0.9)) * r.transpose();
    assert!((b.angular_momentum() - i_world * w).length() < 1e-13);
}

#[test]
fn kinematic_velocity_is_reported() {
    let mut k = RigidBody::new_kinematic(pose());
    k.set_kinematic_velocity(DVec3::X, DVec3::Z).unwrap();
    assert_eq!(k.velocity(), DVec3::X);
    assert_eq!(k.angular_velocity(), DVec3::Z);
    // omega x (p - x): the point one metre along +y from the centre moves along -x.
    let p = k.position() + DVec3::Y;
    assert!((k.velocity_at_point(p) - DVec3::ZERO).length() < 1e-15);
}

#[test]
fn angular_velocity_ignores_quaternion_scale() {
    // RK stages evaluate omega at non-unit quaternions; the scale must not matter.
    let q = DQuat::from_euler(glam::EulerRot::XYZ, 0.4, -1.2, 2.2);
    let inv_i = DVec3::new(2.0, 1.5, 1.1);
    let l = DVec3::new(0.3, -2.0, 1.2);
    let w = angular_velocity_of(q, inv_i, l);
    for s in [0.9, 1.0 + 1e-7, 1.3] {
        let ws = angular_velocity_of(q * s, inv_i, l);
        assert!((ws - w).length() < 1e-14 * w.length(), "scale {s}");
    }
    let r = DMat3::from_quat(q);
    let expected = r * DMat3::from_diagonal(inv_i) * r.transpose() * l;
    assert!((w - expected).length() < 1e-14 * w.length());
}

#[test]
fn tensor_constructor_rejects_bad_tensors() {
    let mut m = DMat3::from_diagonal(DVec3::new(1.0, 2.0, 2.5));
    m.x_axis.y = 0.5; // not mirrored in y_axis.x
    assert!(matches!(
        RigidBody::new_dynamic_from_tensor(1.0, m, pose()),
        Err(BodyError::AsymmetricInertia(_))
    ));
    let nan = DMat3::from_diagonal(DVec3::new(1.0, f64::NAN, 1.0));
    assert!(RigidBody::new_dynamic_from_tensor(1.0, nan, pose()).is_err());
    let indefinite = DMat3::from_diagonal(DVec3::new(1.0, -1.0, 1.0));
    assert!(matches!(
        RigidBody::new_dynamic_from_tensor(1.0, indefinite, pose()),
        Err(BodyError::NonPositiveInertia(_))
    ));
}

fn arb_vec(r: f64) -> impl Strategy<Value = DVec3> {
    (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

proptest! {
    #[test]
    fn inverse_inertia_world_inverts_the_inertia_tensor(
        a in -3.0f64..3.0, b in -3.0f64..3.0, c in -3.0f64..3.0,
        i1 in 0.2f64..1.0, i2 in 0.2f64..1.0, i3 in 0.2f64..1.0, l in arb_vec(5.0),
    ) {
        prop_assume!(i1 + i2 >= i3 && i1 + i3 >= i2 && i2 + i3 >= i1);
        let q = DQuat::from_euler(glam::EulerRot::ZYX, a, b, c);
        let mut body = RigidBody::new_dynamic(1.0, DVec3::new(i1, i2, i3),
                                              Pose::new(DVec3::ZERO, q).unwrap()).unwrap();
        body.set_angular_momentum(l).unwrap();
        let r = DMat3::from_quat(q);
        let i_world = r * DMat3::from_diagonal(DVec3::new(i1, i2, i3)) * r.transpose();
        let prod = body.inv_inertia_world() * i_world;
        prop_assert!(tumble_collide::math::max_abs_diff_mat(&prod, &DMat3::IDENTITY) < 1e-12);
        // omega by the quaternion path == I^-1(t) L by the matrix path.
        let w = body.angular_velocity();
        prop_assert!((w - body.inv_inertia_world() * l).length() < 1e-12 * (1.0 + l.length()));
        // Kinetic energy 1/2 omega . I omega.
        let e = 0.5 * w.dot(i_world * w);
        prop_assert!((body.kinetic_energy() - e).abs() < 1e-12 * (1.0 + e));
    }

    /// A tensor given in an arbitrary frame gives the same physics as the principal
    /// body: same moments, same L = I omega and kinetic energy for any omega, and the
    /// returned V maps principal axes into the given frame.
    #[test]
    fn tensor_constructor_matches_principal_body(
        a in -3.0f64..3.0, b in -3.0f64..3.0, c in -3.0f64..3.0,
        i1 in 0.2f64..1.0, i2 in 0.2f64..1.0, i3 in 0.2f64..1.0, w in arb_vec(5.0),
    ) {
        prop_assume!(i1 + i2 >= i3 && i1 + i3 >= i2 && i2 + i3 >= i1);
        let r = DMat3::from_quat(DQuat::from_euler(glam::EulerRot::ZYX, a, b, c));
        let tensor = r * DMat3::from_diagonal(DVec3::new(i1, i2, i3)) * r.transpose();
        let frame = pose();
        let (mut body, v) = RigidBody::new_dynamic_from_tensor(2.0, tensor, frame).unwrap();
        let mut sorted = [i1, i2, i3];
        sorted.sort_by(f64::total_cmp);
        prop_assert!((body.principal_inertia() - DVec3::from(sorted)).length() < 1e-12);
        let diag = DMat3::from_diagonal(body.principal_inertia());
        let back = DMat3::from_quat(v) * diag * DMat3::from_quat(v).transpose();
        prop_assert!(tumble_collide::math::max_abs_diff_mat(&back, &tensor) < 1e-12);
        body.set_angular_velocity(w).unwrap();
        let rf = DMat3::from_quat(frame.rotation);
        let l_expected = rf * tensor * rf.transpose() * w;
        prop_assert!((body.angular_momentum() - l_expected).length() < 1e-12 * (1.0 + w.length()));
        prop_assert!((body.kinetic_energy() - 0.5 * w.dot(l_expected)).abs() < 1e-12 * (1.0 + w.length_squared()));
    }

    #[test]
    fn force_at_point_adds_moment_arm_torque(f in arb_vec(10.0), p in arb_vec(10.0)) {
        let mut b = body();
        b.apply_force_at_point(f, p).unwrap();
        prop_assert_eq!(b.force(), f);
        prop_assert_eq!(b.torque(), (p - b.position()).cross(f));
        let l0 = b.angular_momentum();
        let p0 = b.linear_momentum();
        b.apply_impulse_at_point(f, p).unwrap();
        prop_assert!((b.linear_momentum() - (p0 + f)).length() < 1e-12 * (1.0 + f.length()));
        let dl = (p - b.position()).cross(f);
        prop_assert!((b.angular_momentum() - (l0 + dl)).length() < 1e-12 * (1.0 + dl.length()));
    }
}
