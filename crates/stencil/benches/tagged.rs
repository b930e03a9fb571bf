//! What creases and corners cost: the same mesh subdivided untagged and
//! tagged, in the same run (the "within 1.2× of untagged").
//!
//! Tags: every 10th edge (by a fixed hash of its id) creased — a third each
//! infinitely sharp (10), 2.5 and 1.0 — and every 50th vertex a corner (10):
//! ~10 % of the edges sharp, so most vertices near a crease take the general
//! rule path. Measured: [`subdivide`] (the one-shot path `subdiv subdivide`
//! takes) at the peers' levels, and the plan (`topology` + `geometry`).
//! `cargo bench -p subdiv-stencil --bench tagged`.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;
use subdiv_mesh::Mesh;
use subdiv_stencil::{subdivide, CreaseMethod, LoopBeta, Options, Scheme, SubdivisionPlan};

fn load(rel: &str) -> Mesh {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures").join(rel);
    let soup = subdiv_io::read_mesh(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    Mesh::from_soup(soup).unwrap_or_else(|e| panic!("{}: {e}", path.display())).0
}

#[path = "support/tagging.rs"]
mod tagging;
use tagging::tagged;

fn bench(c: &mut Criterion) {
    let cases: [(&str, &str, Scheme, usize); 4] = [
        ("horse_quad", "quad/horse_quad.obj", Scheme::CatmullClark, 4),
        ("bunny_npm", "tri/bunny_npm.obj", Scheme::CatmullClark, 3),
        ("bunny_npm", "tri/bunny_npm.obj", Scheme::Loop(LoopBeta::Loop), 3),
        ("armadillo", "tri/armadillo.obj", Scheme::CatmullClark, 2),
    ];
    for (name, rel, scheme, levels) in cases {
        let plain = load(rel);
        let sharp = tagged(&plain);
        eprintln!(
            "CONFIG {name} {} L{levels}: {} creases, {} corners",
            scheme.name(),
            sharp.tags().crease_count(),
            sharp.tags().corner_count()
        );
        let mut g = c.benchmark_group(format!("{name}/{}/L{levels}", scheme.name()));
        g.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3));
        for (label, mesh, method) in [
            ("untagged", &plain, CreaseMethod::Uniform),
            ("tagged", &sharp, CreaseMethod::Uniform),
            ("tagged-chaikin", &sharp, CreaseMethod::Chaikin),
        ] {
            let options = Options::new(scheme).with_crease_method(method);
            g.bench_function(format!("subdivide/{label}"), |b| {
                b.iter(|| subdivide(black_box(mesh), options, levels, false).unwrap())
            });
            g.bench_function(format!("plan/{label}"), |b| {
                b.iter(|| {
                    let plan = SubdivisionPlan::with_tags(mesh.topology(), mesh.tags(), options, levels).unwrap();
                    plan.apply(black_box(mesh.positions()))
                })
            });
        }
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
