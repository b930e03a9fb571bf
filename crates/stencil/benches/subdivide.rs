//! Subdivision throughput, split into its two phases.
//!
//! For every mesh × scheme × {1, 4} levels ({1, 3} for armadillo, as in the
//! peers' table) three measurements:
//! - `topology`: [`SubdivisionPlan::new`] — refined connectivity and stencils,
//!   computed once per topology;
//! - `geometry`: [`SubdivisionPlan::apply`] — one sparse product per level,
//!   the cost of every re-evaluation on fixed topology;
//! - `full`: both, what a one-shot `subdiv subdivide` pays (the figure to set
//!   beside the peers' times in `fixtures/peer/TIMINGS.md`).
//!
//! Meshes: `fixtures/quad/horse_quad.obj`, `fixtures/tri/bunny_npm.obj`,
//! `fixtures/tri/armadillo.obj` (Loop and Catmull-Clark only),
//! `fixtures/peer/timing-meshes/{icosphere3,torus48x24}.obj`, and a generated
//! 10⁶-face torus (one level: four would need ~256 M faces). Loop runs on
//! triangle meshes only. Sample sizes are small (10) so the whole bench runs
//! in a few minutes: `cargo bench -p subdiv-stencil --bench subdivide`.
//! Each configuration prints `CONFIG mesh scheme levels out_faces` on stderr
//! for the tables.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;
use subdiv_mesh::{shapes, Mesh};
use subdiv_stencil::{LoopBeta, Scheme, SubdivisionPlan, Tension};

fn load(rel: &str) -> Mesh {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures").join(rel);
    let soup = subdiv_io::read_mesh(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    Mesh::from_soup(soup).unwrap_or_else(|e| panic!("{}: {e}", path.display())).0
}

fn scheme_id(s: Scheme) -> &'static str {
    match s {
        Scheme::CatmullClark => "cc",
        Scheme::Loop(_) => "loop",
        Scheme::DooSabin => "ds",
        Scheme::DengMa(_) => "dengma",
        Scheme::Sqrt3 => "sqrt3",
    }
}

fn bench_mesh(c: &mut Criterion, name: &str, mesh: &Mesh, schemes: &[Scheme], levels: &[usize]) {
    let t = mesh.topology();
    for &scheme in schemes {
        for &l in levels {
            let mut g = c.benchmark_group(format!("{name}/{}/L{l}", scheme_id(scheme)));
            g.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));
            g.bench_function("topology", |b| b.iter(|| SubdivisionPlan::new(black_box(t), scheme, l).unwrap()));
            g.bench_function("geometry", |b| {
                // Planned here, so that a filtered run only plans what it measures.
                let plan = SubdivisionPlan::new(t, scheme, l).expect("scheme applies");
                eprintln!("CONFIG {name} {} {l} {}", scheme_id(scheme), plan.topology().face_count());
                b.iter(|| plan.apply(black_box(mesh.positions())))
            });
            g.bench_function("full", |b| {
                b.iter(|| SubdivisionPlan::new(black_box(t), scheme, l).unwrap().apply(black_box(mesh.positions())))
            });
            g.finish();
        }
    }
}

const CC: Scheme = Scheme::CatmullClark;
const LOOP: Scheme = Scheme::Loop(LoopBeta::Warren);
const DS: Scheme = Scheme::DooSabin;
const DM: Scheme = Scheme::DengMa(Tension::Global(1.0));

fn subdivide(c: &mut Criterion) {
    // Levels as in the peers' table (armadillo: 1-3 there; its level 4 has 22 M faces).
    let fixtures: [(&str, &str, &[Scheme], &[usize]); 5] = [
        ("horse_quad", "quad/horse_quad.obj", &[CC, DS, DM], &[1, 4]),
        ("bunny_npm", "tri/bunny_npm.obj", &[CC, LOOP, DS, DM], &[1, 4]),
        ("armadillo", "tri/armadillo.obj", &[CC, LOOP], &[1, 3]),
        ("icosphere3", "peer/timing-meshes/icosphere3.obj", &[CC, LOOP, DS, DM], &[1, 4]),
        ("torus48x24", "peer/timing-meshes/torus48x24.obj", &[CC, DS, DM], &[1, 4]),
    ];
    for (name, rel, schemes, levels) in fixtures {
        bench_mesh(c, name, &load(rel), schemes, levels);
    }
    bench_mesh(c, "torus1000x1000", &shapes::torus(1000, 1000), &[CC, DS, DM], &[1]);
}

criterion_group!(benches, subdivide);
criterion_main!(benches);
