//! Reading and writing at disk speed, in memory (no file system in the
//! loop): OBJ, OFF, ASCII and binary PLY, binary STL of a generated
//! 10⁶-quad torus (positions jittered off the grid so that every coordinate
//! has a full 17-digit decimal), in bytes per second of the encoded file;
//! and the connectivity build of the same faces, in faces per second.
//!
//! `cargo bench -p subdiv-io --bench io -- --warm-up-time 1 --measurement-time 3`

use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion, Throughput};
use subdiv_io::{read_mesh_from_bytes, write_mesh_to_vec, Format, MeshView};
use subdiv_mesh::shapes::{self, SplitMix64};
use subdiv_mesh::{DVec3, Topology};

/// A 1000 × 1000 quad torus with jittered positions.
fn torus() -> (Vec<DVec3>, subdiv_mesh::FaceList) {
    let mesh = shapes::torus(1000, 1000);
    let mut rng = SplitMix64(19);
    let positions = mesh
        .positions()
        .iter()
        .map(|&p| p + 1e-3 * DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()))
        .collect();
    (positions, mesh.topology().faces().clone())
}

fn bench_formats(c: &mut Criterion) {
    let (positions, faces) = torus();
    let view = MeshView::new(&positions, &faces);
    let mut group = c.benchmark_group("io");
    group.sample_size(10);
    for format in [Format::Obj, Format::Off, Format::PlyAscii, Format::PlyBinary, Format::StlBinary] {
        let bytes = write_mesh_to_vec(view, format).expect("encodes");
        group.throughput(Throughput::Bytes(bytes.len() as u64));
        group.bench_function(BenchmarkId::new("write", format!("{format:?}")), |b| {
            b.iter(|| write_mesh_to_vec(view, format).expect("encodes"))
        });
        group.bench_with_input(BenchmarkId::new("read", format!("{format:?}")), &bytes, |b, bytes| {
            b.iter(|| read_mesh_from_bytes(bytes, format, "torus").expect("decodes"))
        });
    }
    group.finish();
}

fn bench_topology(c: &mut Criterion) {
    let (positions, faces) = torus();
    let mut group = c.benchmark_group("topology");
    group.sample_size(10);
    group.throughput(Throughput::Elements(faces.len() as u64));
    group.bench_function(BenchmarkId::new("new", faces.len()), |b| {
        b.iter_batched(
            || faces.clone(),
            |faces| Topology::new(faces, positions.len()).expect("valid torus"),
            BatchSize::LargeInput,
        )
    });
    group.finish();
}

criterion_group!(benches, bench_formats, bench_topology);
criterion_main!(benches);
