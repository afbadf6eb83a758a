//! OBBTree build time and memory for tori of 5k, 50k and 500k triangles
//! (`torus_mesh(1, 0.3, n, n)`, 2 n^2 triangles). Prints the tree statistics
//! (bytes per triangle, nodes, depth) once per size before timing.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use std::time::Duration;
use tumble_collide::bvh::{BuildOptions, ObbTree};
use tumble_collide::mesh::torus_mesh;

fn build(c: &mut Criterion) {
    let mut group = c.benchmark_group("obbtree_build");
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(500));
    for n in [50usize, 158, 500] {
        let mesh = torus_mesh(1.0, 0.3, n, n).unwrap();
        let tris = mesh.triangles().len();
        for leaf_size in [1usize, 2, 4] {
            let opts = BuildOptions { leaf_size };
            let st = ObbTree::build_with(&mesh, &opts).unwrap().stats();
            println!(
                "torus {tris} triangles, leaf_size {leaf_size}: {} nodes, {} leaves, depth {}, {} bytes ({:.1} bytes/triangle), flat fallbacks {}",
                st.nodes, st.leaves, st.depth, st.memory_bytes, st.bytes_per_triangle, st.flat_fallbacks
            );
        }
        if n == 500 {
            group.measurement_time(Duration::from_secs(20));
        }
        group.bench_with_input(BenchmarkId::from_parameter(tris), &mesh, |b, m| {
            b.iter(|| ObbTree::build(m).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, build);
criterion_main!(benches);
