//! Limit evaluation throughput: building the patch table
//! (`LimitSurface::new`), binding positions (`bind`, one sparse product over
//! the table), and evaluations per second on a regular patch, near an
//! extraordinary vertex (inside the table) and at / very near one (the
//! on-demand path), for the unbound and the bound surface.
//!
//! Mesh: a Catmull-Clark torus of 100 × 100 quads with a few faces merged
//! (10⁴ faces, extraordinary vertices), and the icosahedron refined three
//! times for Loop. `cargo bench -p subdiv-eval --bench evaluate`.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::time::Duration;
use subdiv_eval::{LimitSurface, SurfaceParam};
use subdiv_mesh::{shapes, FaceId, Mesh, VertexId};
use subdiv_stencil::{LoopBeta, Options, Scheme};

/// 10⁴ faces with some extraordinary vertices (polygon mix of a torus).
fn mesh() -> Mesh {
    shapes::polygon_mix(&shapes::torus(100, 100), 1, 0.01, 0.0, 0.0)
}

/// A quad far from any extraordinary vertex, and a quad at one, with the
/// corner index of that vertex.
fn faces(mesh: &Mesh) -> (u32, (u32, usize)) {
    let t = mesh.topology();
    let regular = |v: u32| t.valence(VertexId(v)) == 4;
    let quads = || t.face_ids().filter(|&f| t.face_size(f) == 4);
    let far = quads()
        .find(|&f| {
            subdiv_mesh::Topology::face(t, f).iter().all(|&v| {
                t.vertex_fan(VertexId(v)).iter().all(|&h| {
                    let g = t.he_face(h);
                    t.face_size(g) == 4 && t.face(g).iter().all(|&w| regular(w))
                })
            })
        })
        .expect("a regular quad");
    let near = quads()
        .find_map(|f| t.face(f).iter().position(|&v| !regular(v)).map(|k| (f.0, k)))
        .expect("a quad at an extraordinary vertex");
    (far.0, near)
}

fn bench(c: &mut Criterion) {
    let mesh = mesh();
    eprintln!("CONFIG faces {}", mesh.topology().face_count());
    let options = Options::new(Scheme::CatmullClark);
    let mut g = c.benchmark_group("catmull-clark");
    g.sample_size(10);
    g.bench_function("build", |b| b.iter(|| LimitSurface::new(black_box(&mesh), &options).unwrap()));
    let surface = LimitSurface::new(&mesh, &options).unwrap();
    eprintln!("CONFIG patches {}", surface.patch_count());
    let x = mesh.positions();
    g.bench_function("bind", |b| b.iter(|| surface.bind(black_box(x)).unwrap()));
    let bound = surface.bind(x).unwrap();
    let (far, (near, k)) = faces(&mesh);
    let corner_uv = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)][k];
    let toward = |e: f64| {
        // A point at distance ~e (in u, v) from the extraordinary corner.
        let (cu, cv) = corner_uv;
        SurfaceParam::new(near, 0, (cu - e).abs().min(1.0), (cv - e).abs().min(1.0))
    };
    let regular = SurfaceParam::new(far, 0, 0.3, 0.6);
    g.sample_size(20);
    g.bench_function("evaluate/regular", |b| b.iter(|| surface.evaluate(x, black_box(regular)).unwrap()));
    g.bench_function("bound/regular", |b| b.iter(|| bound.evaluate_jet(black_box(regular)).unwrap()));
    g.bench_function("bound/near-ev-2^-5", |b| b.iter(|| bound.evaluate_jet(black_box(toward(1.0 / 32.0))).unwrap()));
    g.bench_function("bound/near-ev-2^-12", |b| {
        b.iter(|| bound.evaluate_jet(black_box(toward(1.0 / 4096.0))).unwrap())
    });
    // 32 levels of on-demand refinement below the table: the steps' cache at work.
    g.bench_function("bound/near-ev-2^-40", |b| {
        b.iter(|| bound.evaluate_jet(black_box(toward(2f64.powi(-40)))).unwrap())
    });
    let at = SurfaceParam::new(near, 0, corner_uv.0, corner_uv.1);
    g.bench_function("bound/at-ev", |b| b.iter(|| bound.evaluate_jet(black_box(at)).unwrap()));
    g.bench_function("stencil/regular", |b| b.iter(|| surface.stencil(black_box(regular)).unwrap()));
    g.finish();

    let ico =
        subdiv_stencil::subdivide(&shapes::icosahedron(), Options::new(Scheme::Loop(LoopBeta::default())), 3, false)
            .unwrap();
    let options = Options::new(Scheme::Loop(LoopBeta::default()));
    let mut g = c.benchmark_group("loop");
    g.sample_size(10);
    g.bench_function("build", |b| b.iter(|| LimitSurface::new(black_box(&ico), &options).unwrap()));
    let surface = LimitSurface::new(&ico, &options).unwrap();
    let bound = surface.bind(ico.positions()).unwrap();
    let t = ico.topology();
    let regular = t
        .face_ids()
        .find(|&f| t.face(f).iter().all(|&v| t.valence(VertexId(v)) == 6))
        .map(|f: FaceId| SurfaceParam::new(f.0, 0, 0.2, 0.3))
        .unwrap();
    g.sample_size(20);
    g.bench_function("bound/regular", |b| b.iter(|| bound.evaluate_jet(black_box(regular)).unwrap()));
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(Duration::from_secs(1)).measurement_time(Duration::from_secs(3));
    targets = bench
}
criterion_main!(benches);
