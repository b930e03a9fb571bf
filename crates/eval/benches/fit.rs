//! Fitting (issue #42): rounds and time of the Gauss-Newton fit against the
//! previous methods (point-to-point LSPIA fixed point, tangent distance) on
//! synthetic recovery, and the scale run.
//!
//! Recovery: the 112-vertex bumpy 14 × 8 Catmull-Clark torus and the Spot
//! control mesh (188 vertices), each against its level-3 limit tessellation,
//! started from a copy with every vertex moved by 2 % of d. Every method
//! runs to its own stopping rule (30 rounds at most); the rounds and the
//! reached RMS are printed once before the timing.
//!
//! Scale (`SUBDIV_FIT_SCALE=1`, one run per method, printed, not a criterion
//! sample): a 400 × 250 Catmull-Clark torus (10⁵ control vertices) against
//! 2·10⁶ target points (its level-2 limit tessellation's 1.6·10⁶ vertices
//! plus 4·10⁵ points of its level-3 tessellation's first faces), started
//! from a smooth displacement of amplitude 2 % of d (moved independently by
//! 2 % of d, its vertices would pass their neighbours: d/50 is 5-10 edge
//! lengths there), Gauss-Newton against LSPIA, each to its own stopping rule
//! or 60 s.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::path::Path;
use std::time::Instant;
use subdiv_eval::{fit, FitMethod, FitOptions, FitTarget};
use subdiv_mesh::shapes;
use subdiv_mesh::Mesh;
use subdiv_stencil::{Options, Scheme};

fn cases() -> Vec<(&'static str, Mesh, FitTarget, Options)> {
    let options = Options::new(Scheme::CatmullClark);
    let spot =
        subdiv_io::load_mesh(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/quad/spot_control_mesh.obj"))
            .expect("the Spot fixture");
    [("torus-112", shapes::bumpy_torus(14, 8, 0.075, 42)), ("spot-188", spot)]
        .into_iter()
        .map(|(name, mesh)| {
            let target = FitTarget::from_mesh(&subdiv_stencil::subdivide(&mesh, options, 3, true).expect("limit"));
            (name, shapes::perturbed(&mesh, 0.02, 17), target, options)
        })
        .collect()
}

const METHODS: [FitMethod; 3] =
    [FitMethod::GaussNewton, FitMethod::PointToPoint, FitMethod::TangentDistance { lambda: 0.05 }];

fn scale_run() {
    let options = Options::new(Scheme::CatmullClark);
    let truth = shapes::torus(400, 250);
    let t0 = Instant::now();
    let level2 = subdiv_stencil::subdivide(&truth, options, 2, true).expect("limit");
    let mut points = level2.positions().to_vec();
    let extra = subdiv_stencil::subdivide(&truth, options, 3, true).expect("limit");
    points.extend(extra.positions().iter().skip(level2.positions().len()).take(2_000_000 - points.len()));
    let target = FitTarget::cloud(points);
    let start = shapes::smoothly_perturbed(&truth, 0.02, 17);
    eprintln!(
        "scale: {} control vertices, {} target points (setup {:.1} s)",
        truth.positions().len(),
        target.points.len(),
        t0.elapsed().as_secs_f64()
    );
    for method in [FitMethod::GaussNewton, FitMethod::PointToPoint] {
        let t1 = Instant::now();
        let options =
            FitOptions { surface: options, iterations: 30, max_time: Some(60.0), method, ..FitOptions::default() };
        let result = fit(&target, &start, &options).expect("fit");
        for it in &result.iterations {
            eprintln!(
                "scale {} round {:2}: RMS {:.3e}·d max {:.3e}·d at {:.1} s ({} {} it)",
                method.name(),
                it.iteration,
                it.rms_target_to_surface / it.scale,
                it.max_target_to_surface / it.scale,
                it.seconds,
                it.solver,
                it.solver_iterations
            );
        }
        eprintln!("scale {}: fit {:.1} s, stop {:?}", method.name(), t1.elapsed().as_secs_f64(), result.stop);
    }
}

fn bench(c: &mut Criterion) {
    if std::env::var_os("SUBDIV_FIT_SCALE").is_some() {
        scale_run();
    }
    let mut group = c.benchmark_group("fit");
    group.sample_size(10);
    for (name, start, target, options) in cases() {
        for method in METHODS {
            let fit_options = FitOptions { surface: options, iterations: 30, method, ..FitOptions::default() };
            let r = fit(&target, &start, &fit_options).expect("fit");
            let last = r.iterations.last().expect("round 0");
            eprintln!(
                "{name} {}: {} rounds, RMS {:.3e}·d, max {:.3e}·d, stop {:?}, {:.2} s",
                method.name(),
                last.iteration,
                last.rms_target_to_surface / last.scale,
                last.max_target_to_surface / last.scale,
                r.stop,
                last.seconds
            );
            group.bench_function(format!("{name}/{}", method.name()), |b| {
                b.iter(|| black_box(fit(&target, &start, &fit_options).expect("fit")))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
