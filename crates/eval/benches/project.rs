//! Closest-point projection throughput (issue #17: ≥ 10⁵ queries/s on 2
//! cores against a 10⁴-face control mesh).
//!
//! Control mesh: the Spot fixture (`fixtures/quad/spot_control_mesh.obj`,
//! 180 faces, valences 3-5, triangles and pentagons) subdivided 3 times by
//! Catmull-Clark without limit positions: 11,520 quads with extraordinary
//! vertices. Queries: 20,000 points sampled by area on the limit surface and
//! moved along the normal by up to ±1 % of d, plus 1 in 10 uniform in the
//! bounding box. Groups: building the projector (bounds, BVH, start grid),
//! and projecting all queries (rayon over queries, all threads).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::DVec3;
use std::hint::black_box;
use std::path::Path;
use std::time::Instant;
use subdiv_eval::project::{projector, BoundLimitSurface};
use subdiv_eval::{sample_by_area, LimitSurface, ProjectOptions};
use subdiv_mesh::shapes::SplitMix64;
use subdiv_stencil::{Options, Scheme};

fn setup() -> (subdiv_mesh::Mesh, Options, Vec<DVec3>) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/quad/spot_control_mesh.obj");
    let spot = subdiv_io::load_mesh(&path).expect("the Spot fixture");
    let options = Options::new(Scheme::CatmullClark);
    let mesh = subdiv_stencil::subdivide(&spot, options, 3, false).expect("subdivides");
    let surface = LimitSurface::new(&mesh, &options).expect("a surface");
    let bound = BoundLimitSurface::new(&surface, mesh.positions()).unwrap();
    let samples = sample_by_area(&bound, 20_000, 1).expect("samples");
    let bbox = mesh.bbox();
    let d = bbox.diagonal();
    let mut rng = SplitMix64(2);
    let queries = samples
        .iter()
        .enumerate()
        .map(|(k, s)| {
            if k % 10 == 9 {
                bbox.min + (bbox.max - bbox.min) * DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64())
            } else {
                s.position + (rng.next_f64() - 0.5) * 0.02 * d * s.normal
            }
        })
        .collect();
    (mesh, options, queries)
}

fn bench(c: &mut Criterion) {
    let (mesh, options, queries) = setup();
    let surface = LimitSurface::new(&mesh, &options).unwrap();
    let popts = ProjectOptions::default();
    let t = Instant::now();
    let p = projector(&surface, &mesh, &options, &popts).unwrap();
    let build = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let found = p.project_all(&queries).unwrap();
    let run = t.elapsed().as_secs_f64();
    eprintln!(
        "project: {} faces, {} queries: build {:.1} ms, {:.0} queries/s on {} threads (max distance {:.3e})",
        mesh.topology().face_count(),
        queries.len(),
        build * 1e3,
        queries.len() as f64 / run,
        rayon::current_num_threads(),
        found.iter().map(|f| f.distance).fold(0.0, f64::max)
    );
    let mut g = c.benchmark_group("project");
    g.sample_size(10);
    g.bench_function("build", |b| b.iter(|| black_box(projector(&surface, &mesh, &options, &popts).unwrap())));
    g.throughput(Throughput::Elements(queries.len() as u64));
    g.bench_function("queries", |b| b.iter(|| black_box(p.project_all(&queries).unwrap())));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
