//! `triangulate` on 10⁶ quads (a torus), on a polygon mix with faces of up to
//! eight corners, and the validation of the result alone for comparison
//! (`Topology::new` on the triangles: the floor under any triangulation that
//! returns a validated mesh).
//!
//! `cargo bench -p subdiv-mesh --bench triangulate`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use subdiv_mesh::{shapes, triangulate, Topology};

fn bench_triangulate(c: &mut Criterion) {
    let mut group = c.benchmark_group("triangulate");
    group.sample_size(10);
    let meshes = [
        ("torus_quads", shapes::torus(1000, 1000)),
        ("polygon_mix", shapes::polygon_mix(&shapes::torus(600, 600), 7, 0.3, 0.2, 0.05)),
    ];
    for (name, mesh) in &meshes {
        let t = mesh.topology();
        group.throughput(Throughput::Elements(t.half_edge_count() as u64));
        group.bench_with_input(BenchmarkId::new(format!("{name}/triangulate"), t.face_count()), mesh, |b, mesh| {
            b.iter(|| triangulate(mesh).expect("triangulable"))
        });
        let triangles = triangulate(mesh).expect("triangulable").mesh;
        let faces = triangles.topology().faces().clone();
        group.bench_with_input(
            BenchmarkId::new(format!("{name}/validate_result"), t.face_count()),
            &faces,
            |b, faces| b.iter(|| Topology::new(faces.clone(), t.vertex_count()).expect("valid")),
        );
    }
    group.finish();
}

criterion_group!(benches, bench_triangulate);
criterion_main!(benches);
