//! Mesh mass properties under rigid motions, splitting into parts, and
//! re-expression in the principal frame: physics that must hold whatever the
//! mesh.

use super::integrals::{integrate, Domain};
use super::*;
use crate::math::{max_abs_diff_mat, sym_eigen, DMat3, DQuat, DVec3};
use crate::mesh::{box_mesh, cone_mesh, TriMesh};
use crate::pose::Pose;
use proptest::prelude::*;

fn solid(mesh: &TriMesh, spec: MassSpec) -> MassProperties {
    mesh_mass_properties(mesh, spec, MassFallback::None).unwrap()
}

fn scale(m: &DMat3) -> f64 {
    m.to_cols_array().iter().fold(0.0f64, |s, x| s.max(x.abs()))
}

/// A box with its corners pushed about: closed, no symmetry, all products of
/// inertia non-zero.
fn lumpy() -> TriMesh {
    box_mesh(DVec3::new(0.5, 1.0, 1.5))
        .unwrap()
        .map_vertices(|v| {
            DVec3::new(
                v.x + 0.3 * v.y + 0.1 * v.z * v.z,
                v.y + 0.2 * v.z + 0.05 * v.x * v.y,
                v.z + 0.15 * v.x,
            )
        })
        .unwrap()
}

#[test]
fn rigid_motion_moves_com_and_rotates_inertia() {
    let mesh = lumpy();
    let p = solid(&mesh, MassSpec::Density(2700.0));
    assert!(
        p.inertia.y_axis.x.abs() > 1e-3 * scale(&p.inertia),
        "test body too symmetric"
    );
    let pose = Pose::new(
        DVec3::new(3.0, -7.5, 12.0),
        DQuat::from_euler(glam::EulerRot::ZXY, 0.9, -0.4, 2.2),
    )
    .unwrap();
    let moved = solid(
        &mesh.map_vertices(|v| pose.transform_point(v)).unwrap(),
        MassSpec::Density(2700.0),
    );
    let want = p.transformed(&pose);
    assert!((moved.mass - p.mass).abs() < 1e-12 * p.mass);
    assert!((moved.com - want.com).length() < 1e-12 * 15.0);
    assert!(max_abs_diff_mat(&moved.inertia, &want.inertia) < 1e-12 * scale(&p.inertia));
    // Explicit R I R^T, independent of `rotated`.
    let r = DMat3::from_quat(pose.rotation);
    assert!(max_abs_diff_mat(&moved.inertia, &(r * p.inertia * r.transpose())) < 1e-12 * scale(&p.inertia));
}

#[test]
fn parallel_axis_agrees_with_direct_integration_about_a_point() {
    // Two methods: (a) integrate x x^T about q directly over the mesh,
    // I_q = rho (tr(S) E - S); (b) inertia about the centre of mass shifted by
    // the parallel-axis theorem.
    let mesh = cone_mesh(0.6, 1.4, 24).unwrap();
    let rho = 3.0;
    let p = solid(&mesh, MassSpec::Density(rho));
    for q in [
        DVec3::ZERO,
        DVec3::new(2.0, -1.0, 0.5),
        DVec3::new(-0.3, 0.0, 4.0),
    ] {
        let m = integrate(&mesh, Domain::Solid, q);
        let tr = m.second.x_axis.x + m.second.y_axis.y + m.second.z_axis.z;
        let direct = (DMat3::from_diagonal(DVec3::splat(tr)) - m.second) * rho;
        let shifted = p.inertia_about(q);
        assert!(
            max_abs_diff_mat(&direct, &shifted) < 1e-12 * scale(&direct),
            "about {q:?}"
        );
    }
}

#[test]
fn two_halves_make_the_whole_box() {
    // Box 2 x 4 x 6 split at x = 0.4 into widths 1.4 and 0.6.
    let whole = solid_box(DVec3::new(1.0, 2.0, 3.0), MassSpec::Density(5.0)).unwrap();
    let left = solid(
        &box_mesh(DVec3::new(0.7, 2.0, 3.0)).unwrap(),
        MassSpec::Density(5.0),
    )
    .translated(DVec3::new(-0.3, 0.0, 0.0));
    let right = solid(
        &box_mesh(DVec3::new(0.3, 2.0, 3.0)).unwrap(),
        MassSpec::Density(5.0),
    )
    .translated(DVec3::new(0.7, 0.0, 0.0));
    let c = MassProperties::combine(&[left, right]).unwrap();
    assert!((c.mass - whole.mass).abs() < 1e-12 * whole.mass);
    assert!(c.com.length() < 1e-14);
    assert!(max_abs_diff_mat(&c.inertia, &whole.inertia) < 1e-12 * scale(&whole.inertia));
    // The same composite rotated is the rotated whole (combine commutes with rotation).
    let q = DQuat::from_rotation_y(0.8);
    let cr = MassProperties::combine(&[left.rotated(q), right.rotated(q)]).unwrap();
    assert!(max_abs_diff_mat(&cr.inertia, &whole.rotated(q).inertia) < 1e-12 * scale(&whole.inertia));
}

#[test]
fn principal_frame_diagonalises_and_centres() {
    let q = DQuat::from_euler(glam::EulerRot::XYZ, 0.3, 1.1, -0.6);
    let mesh = lumpy()
        .map_vertices(|v| q * v + DVec3::new(1.0, 2.0, 3.0))
        .unwrap();
    let p = solid(&mesh, MassSpec::Mass(4.0));
    let f = p.principal();
    // R diag(moments) R^T == I.
    assert!(max_abs_diff_mat(&f.inertia_tensor(), &p.inertia) < 1e-13 * scale(&p.inertia));
    let r = DMat3::from_quat(f.rotation);
    assert!((r.determinant() - 1.0).abs() < 1e-13);
    // The re-expressed mesh: com at the origin, diagonal inertia = moments.
    let body = to_principal_frame(&mesh, &f).unwrap();
    let b = solid(&body, MassSpec::Mass(4.0));
    assert!(b.com.length() < 1e-12);
    let diag = DMat3::from_diagonal(f.moments);
    assert!(max_abs_diff_mat(&b.inertia, &diag) < 1e-12 * scale(&diag));
    assert!(max_abs_diff_mat(&b.inertia, &f.to_properties().inertia) < 1e-12 * scale(&diag));
    // Mapping back with the frame's pose recovers the original mesh.
    let back = body.map_vertices(|v| f.pose().transform_point(v)).unwrap();
    for (a, b) in back.vertices().iter().zip(mesh.vertices()) {
        assert!((*a - *b).length() < 1e-12);
    }
}

#[test]
fn same_input_same_bits() {
    let a = solid(&lumpy(), MassSpec::Density(1.0));
    let b = solid(&lumpy(), MassSpec::Density(1.0));
    assert_eq!(a.mass.to_bits(), b.mass.to_bits());
    assert_eq!(
        a.inertia.to_cols_array().map(f64::to_bits),
        b.inertia.to_cols_array().map(f64::to_bits)
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn random_boxes_under_random_motions(
        hx in 0.05f64..5.0, hy in 0.05f64..5.0, hz in 0.05f64..5.0,
        a in -3.2f64..3.2, b in -1.5f64..1.5, c in -3.2f64..3.2,
        tx in -50.0f64..50.0, ty in -50.0f64..50.0, tz in -50.0f64..50.0,
        rho in 0.1f64..1e4,
    ) {
        let h = DVec3::new(hx, hy, hz);
        let q = DQuat::from_euler(glam::EulerRot::ZYX, a, b, c);
        let t = DVec3::new(tx, ty, tz);
        let mesh = box_mesh(h).unwrap().map_vertices(|v| q * v + t).unwrap();
        let p = solid(&mesh, MassSpec::Density(rho));
        let want = solid_box(h, MassSpec::Density(rho)).unwrap();
        prop_assert!((p.mass - want.mass).abs() < 1e-11 * want.mass);
        prop_assert!((p.com - t).length() < 1e-11 * (1.0 + t.length()));
        let f = p.principal();
        let (sorted, _) = sym_eigen(&want.inertia);
        prop_assert!((f.moments - sorted).abs().max_element() < 1e-10 * sorted.z,
            "{:?} vs {:?}", f.moments, sorted);
        prop_assert!(max_abs_diff_mat(&f.inertia_tensor(), &p.inertia) < 1e-10 * sorted.z);
    }
}
