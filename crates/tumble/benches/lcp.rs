//! Lemke vs projected Gauss-Seidel on the frictionless contact LCP of a
//! tower of boxes (four corner contacts per box, box 0 on static ground),
//! for 8, 32 and 128 contacts.

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use tumble::collide::math::{DMat3, DVec3};
use tumble::solver::{build_contact_lcp, lemke, pgs, BodyState, ContactLcp, ContactRow};

const G: f64 = 9.81;
const DT: f64 = 1.0 / 60.0;

/// A tower of `boxes` unit-mass boxes, each just after a gravity step.
fn tower(boxes: usize) -> ContactLcp {
    let h = DVec3::new(0.5, 0.4, 0.25);
    let m = 1.0;
    let inertia = DVec3::new(
        h.y * h.y + h.z * h.z,
        h.x * h.x + h.z * h.z,
        h.x * h.x + h.y * h.y,
    ) * (m / 3.0);
    let mut bodies = vec![BodyState::fixed()];
    for _ in 0..boxes {
        bodies.push(BodyState {
            inv_mass: 1.0 / m,
            inv_inertia: DMat3::from_diagonal(DVec3::ONE / inertia),
            linear_velocity: DVec3::new(0.0, 0.0, -G * DT),
            angular_velocity: DVec3::ZERO,
        });
    }
    let mut contacts = Vec::new();
    for k in 0..boxes {
        let centre = DVec3::new(0.0, 0.0, h.z * (2 * k + 1) as f64);
        let below = if k == 0 {
            DVec3::ZERO
        } else {
            centre - DVec3::new(0.0, 0.0, 2.0 * h.z)
        };
        for (sx, sy) in [(1.0, 1.0), (1.0, -1.0), (-1.0, -1.0), (-1.0, 1.0)] {
            let p = DVec3::new(sx * h.x, sy * h.y, centre.z - h.z);
            contacts.push(ContactRow {
                body_a: k + 1,
                body_b: k,
                r_a: p - centre,
                r_b: p - below,
                normal: DVec3::Z,
                bias: 0.0,
                friction: 0.0,
            });
        }
    }
    build_contact_lcp(&bodies, &contacts, false).expect("valid tower")
}

fn bench_lcp(c: &mut Criterion) {
    let mut group = c.benchmark_group("contact_lcp");
    for contacts in [8usize, 32, 128] {
        let lcp = tower(contacts / 4);
        let lem = lemke(&lcp.a, &lcp.b).expect("tower is solvable");
        let it = pgs(&lcp.a, &lcp.b, 1000, 1e-9, None).expect("valid input");
        eprintln!(
            "{contacts} contacts: lemke {} pivots residual {:.1e}; pgs {} sweeps residual {:.1e} converged {}",
            lem.iterations, lem.residual, it.iterations, it.residual, it.converged
        );
        group.bench_with_input(BenchmarkId::new("lemke", contacts), &lcp, |b, lcp| {
            b.iter(|| lemke(black_box(&lcp.a), black_box(&lcp.b)).unwrap())
        });
        group.bench_with_input(BenchmarkId::new("pgs_1e-9_max1000", contacts), &lcp, |b, lcp| {
            b.iter(|| pgs(black_box(&lcp.a), black_box(&lcp.b), 1000, 1e-9, None).unwrap())
        });
        group.bench_with_input(BenchmarkId::new("pgs_20_sweeps", contacts), &lcp, |b, lcp| {
            b.iter(|| pgs(black_box(&lcp.a), black_box(&lcp.b), 20, 0.0, None).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, bench_lcp);
criterion_main!(benches);
