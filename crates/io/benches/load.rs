//! Reading and connectivity build on the largest real meshes: the bundled
//! fixtures, and the full Stanford dragon from `../shared/meshes` when present.
//!
//! `cargo bench -p subdiv-io --bench load`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::path::{Path, PathBuf};
use subdiv_mesh::{Mesh, Topology};

fn meshes() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut paths: Vec<PathBuf> =
        ["fixtures/open/stanford-bunny.obj", "fixtures/quad/sword-quad-dominant.obj", "fixtures/tri/armadillo.obj"]
            .iter()
            .map(|p| root.join(p))
            .collect();
    let dragon = root.join("../shared/meshes/tri/dragon_vrip_full_binary.ply");
    if dragon.exists() {
        paths.push(dragon);
    } else {
        eprintln!("SKIPPED: {} not present", dragon.display());
    }
    paths
}

fn bench_load(c: &mut Criterion) {
    let mut group = c.benchmark_group("load");
    group.sample_size(10);
    for path in meshes() {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let soup = subdiv_io::read_mesh(&path).expect("fixture reads");
        group.throughput(Throughput::Elements(soup.faces.len() as u64));
        group.bench_with_input(BenchmarkId::new("read", &name), &path, |b, p| {
            b.iter(|| subdiv_io::read_mesh(p).expect("fixture reads"))
        });
        group.bench_with_input(BenchmarkId::new("topology", &name), &soup, |b, s| {
            b.iter(|| Topology::new(s.faces.clone(), s.positions.len()).expect("manifold fixture"))
        });
        group.bench_with_input(BenchmarkId::new("validate", &name), &soup, |b, s| {
            b.iter(|| Mesh::from_soup(s.clone()).expect("manifold fixture"))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_load);
criterion_main!(benches);
