//! Every generator's mesh against its closed form: the polyhedral integrals
//! of the inscribed mesh must converge to the analytic solid as the
//! resolution rises (monotonically, at second order, and to a small error).

use super::*;
use crate::math::{max_abs_diff_mat, DVec3};
use crate::mesh::{
    box_mesh, capsule_mesh, cone_mesh, cylinder_mesh, icosphere_mesh, torus_mesh, uv_sphere_mesh, TriMesh,
};

/// Worst relative error over mass, centre of mass (relative to `size`) and
/// the inertia entries (relative to the largest).
fn error(mesh: &TriMesh, want: &MassProperties, size: f64) -> f64 {
    let got = mesh_mass_properties(mesh, MassSpec::Density(1.0), MassFallback::None).unwrap();
    let scale = want
        .inertia
        .to_cols_array()
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let e_mass = (got.mass - want.mass).abs() / want.mass;
    let e_com = (got.com - want.com).length() / size;
    let e_inertia = max_abs_diff_mat(&got.inertia, &want.inertia) / scale;
    e_mass.max(e_com).max(e_inertia)
}

fn assert_converges(name: &str, errs: &[f64], final_tol: f64) {
    assert!(
        errs.windows(2).all(|w| w[1] < w[0]),
        "{name}: error does not fall with resolution: {errs:?}"
    );
    // Inscribed polyhedra err by O(h^2): halving the edge length must divide
    // the error by about 4 once in the asymptotic range.
    let n = errs.len();
    assert!(
        errs[n - 2] / errs[n - 1] > 3.5,
        "{name}: convergence is not second order: {errs:?}"
    );
    assert!(
        *errs.last().unwrap() < final_tol,
        "{name}: final error too large: {errs:?}"
    );
}

const D: MassSpec = MassSpec::Density(1.0);

#[test]
fn box_is_exact() {
    let h = DVec3::new(0.2, 1.1, 0.7);
    assert!(error(&box_mesh(h).unwrap(), &solid_box(h, D).unwrap(), 1.0) < 1e-13);
}

// One test per generator, each the same five lines: the resolution ladders,
// sizes and final tolerances differ per solid, and a failure should name
// the solid (a loop over a table would report one test for all of them).
#[test]
fn uv_sphere_converges() {
    let r = 0.9;
    let want = solid_sphere(r, D).unwrap();
    let errs: Vec<f64> = [8, 16, 32, 64, 128]
        .iter()
        .map(|&n| error(&uv_sphere_mesh(r, n, n / 2).unwrap(), &want, r))
        .collect();
    assert_converges("uv_sphere", &errs, 2e-3);
}

#[test]
fn icosphere_converges() {
    let r = 1.7;
    let want = solid_sphere(r, D).unwrap();
    let errs: Vec<f64> = (0..=5)
        .map(|s| error(&icosphere_mesh(r, s).unwrap(), &want, r))
        .collect();
    assert_converges("icosphere", &errs, 2e-3);
}

#[test]
fn cylinder_converges() {
    let (r, h) = (0.5, 1.3);
    let want = solid_cylinder(r, h, D).unwrap();
    let errs: Vec<f64> = [6, 12, 24, 48, 96, 192]
        .iter()
        .map(|&n| error(&cylinder_mesh(r, h, n).unwrap(), &want, h))
        .collect();
    assert_converges("cylinder", &errs, 1e-3);
}

#[test]
fn capsule_converges() {
    let (r, h) = (0.4, 0.8);
    let want = solid_capsule(r, h, D).unwrap();
    let errs: Vec<f64> = [(6, 2), (12, 4), (24, 8), (48, 16), (96, 32), (192, 64)]
        .iter()
        .map(|&(s, k)| error(&capsule_mesh(r, h, s, k).unwrap(), &want, h + r))
        .collect();
    assert_converges("capsule", &errs, 1e-3);
}

#[test]
fn cone_converges() {
    let (r, hc) = (0.6, 1.4);
    let want = solid_cone(r, hc, D).unwrap();
    let errs: Vec<f64> = [6, 12, 24, 48, 96, 192]
        .iter()
        .map(|&n| error(&cone_mesh(r, hc, n).unwrap(), &want, hc))
        .collect();
    assert_converges("cone", &errs, 1e-3);
}

#[test]
fn torus_converges() {
    let (big, small) = (1.0, 0.3);
    let want = solid_torus(big, small, D).unwrap();
    let errs: Vec<f64> = [8, 16, 32, 64, 128]
        .iter()
        .map(|&n| error(&torus_mesh(big, small, n, n).unwrap(), &want, big))
        .collect();
    assert_converges("torus", &errs, 2e-3);
}
