//! Connectivity build time: a generated 10⁶-quad grid and the largest real fixtures.
//!
//! `cargo bench -p subdiv-mesh --bench topology`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use subdiv_mesh::{shapes, Topology};

fn bench_topology(c: &mut Criterion) {
    let mut group = c.benchmark_group("topology_build");
    group.sample_size(10);
    for n in [100usize, 1000] {
        let grid = shapes::quad_grid(n, n);
        let faces = grid.topology().faces().clone();
        let nv = grid.topology().vertex_count();
        group.throughput(Throughput::Elements(faces.len() as u64));
        group.bench_with_input(BenchmarkId::new("quad_grid", n * n), &faces, |b, faces| {
            b.iter(|| Topology::new(faces.clone(), nv).expect("valid grid"))
        });
    }
    let torus = shapes::torus(1000, 1000);
    let faces = torus.topology().faces().clone();
    group.throughput(Throughput::Elements(faces.len() as u64));
    group.bench_function(BenchmarkId::new("torus", faces.len()), |b| {
        b.iter(|| Topology::new(faces.clone(), torus.topology().vertex_count()).expect("valid torus"))
    });
    group.finish();
}

criterion_group!(benches, bench_topology);
criterion_main!(benches);
