//! Connectivity build time: a generated 10⁶-quad grid and the largest real
//! fixtures; the Doo-Sabin split built directly against its validated build.
//!
//! `cargo bench -p subdiv-mesh --bench topology`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use subdiv_mesh::{refine, shapes, Topology};

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

fn bench_dual_split(c: &mut Criterion) {
    let mut group = c.benchmark_group("dual_split");
    group.sample_size(10);
    let meshes = [
        ("torus", shapes::torus(1000, 1000)),
        ("polygon_mix", shapes::polygon_mix(&shapes::torus(300, 300), 7, 0.1, 0.1, 0.05)),
    ];
    for (name, mesh) in &meshes {
        let t = mesh.topology();
        group.throughput(Throughput::Elements(t.half_edge_count() as u64));
        group.bench_with_input(BenchmarkId::new(format!("{name}/direct"), t.half_edge_count()), t, |b, t| {
            b.iter(|| refine::dual_split(t))
        });
        group.bench_with_input(BenchmarkId::new(format!("{name}/by_validation"), t.half_edge_count()), t, |b, t| {
            b.iter(|| subdiv_mesh::internals::dual_split_by_validation(t))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_topology, bench_dual_split);
criterion_main!(benches);
