//! Solver benchmarks on the regular model problems (b) bicubic torus and
//! (c) Loop grid at 10⁴, 10⁵ and 10⁶ rows, to tol 1e-6 (scale 1):
//! PIA, weighted PIA, Chebyshev, CG (plain and Jacobi) and LDLᵀ (LDLᵀ up
//! to 10⁵ rows; 10⁶ once in the summary when `SUBDIV_BENCH_LDL_1E6=1`).
//!
//! Before the criterion groups a summary table is printed to stderr:
//! iterations, matvecs and the median wall time of a few runs per solver, and
//! the **effective memory bandwidth** of one sparse product beside a
//! STREAM-style triad on arrays moving the same number of bytes.
//!
//! Traffic model of one product out = D·S·x (3 columns, CSR, u32 indices):
//! nnz·(8 value + 4 index) + rows·(4 indptr + 8 d + 24 out) + cols·24 x
//! (x read once: assumes the gathers hit cache after the first touch, which
//! holds for mesh-ordered rows). Triad a = b + s·c: 24 bytes per element
//! (STREAM's convention, no write-allocate traffic counted).
//!
//! `SUBDIV_BENCH_MAX_N` (default 1,000,000) caps the sizes for a quick run.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use rayon::prelude::*;
use subdiv_solve::{internals::model_problems, FactoredMatrix, SolveOptions, Solver};

const SOLVERS: [Solver; 6] = [
    Solver::Pia,
    Solver::WeightedPia,
    Solver::Chebyshev,
    Solver::Cg { jacobi: false },
    Solver::Cg { jacobi: true },
    Solver::Ldl,
];

fn max_n() -> usize {
    std::env::var("SUBDIV_BENCH_MAX_N").ok().and_then(|v| v.parse().ok()).unwrap_or(1_000_000)
}

fn matrices() -> Vec<(&'static str, FactoredMatrix)> {
    let all: [(&str, usize, usize, bool); 6] = [
        ("torus", 100, 100, true),
        ("torus", 400, 250, true),
        ("torus", 1000, 1000, true),
        ("loop", 99, 101, false),
        ("loop", 300, 333, false),
        ("loop", 999, 1001, false),
    ];
    all.iter()
        .filter(|(_, nx, ny, _)| nx * ny <= max_n())
        .map(|&(name, nx, ny, torus)| {
            (name, if torus { model_problems::bicubic_torus(nx, ny) } else { model_problems::loop_regular(nx, ny) })
        })
        .collect()
}

fn data(n: usize) -> Vec<[f64; 3]> {
    (0..n).map(|i| [((i * 37) % 101) as f64 / 101.0, ((i * 13) % 7) as f64 / 7.0, (i % 2) as f64]).collect()
}

fn opts() -> SolveOptions {
    SolveOptions::default().with_tol(1e-6).with_scale(1.0).with_history(false)
}

fn ldl_allowed(n: usize) -> bool {
    n <= 200_000 || std::env::var("SUBDIV_BENCH_LDL_1E6").is_ok_and(|v| v == "1")
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Bytes moved by one product under the model in the crate docs.
fn spmv_bytes(a: &FactoredMatrix) -> u64 {
    let (nnz, n) = (a.nnz() as u64, a.n() as u64);
    nnz * 12 + n * (4 + 8 + 24) + n * 24
}

fn triad(a: &mut [f64], b: &[f64], c: &[f64], s: f64) {
    a.par_chunks_mut(1 << 16).enumerate().for_each(|(k, chunk)| {
        let off = k << 16;
        for (i, ai) in chunk.iter_mut().enumerate() {
            *ai = b[off + i] + s * c[off + i];
        }
    });
}

fn summary() {
    eprintln!("\n## subdiv-solve benchmark summary (tol 1e-6, scale 1, {} threads)\n", rayon::current_num_threads());
    eprintln!("| matrix | rows | nnz | solver | iterations | matvecs | seconds (median of runs) |");
    eprintln!("|---|---:|---:|---|---:|---:|---:|");
    for (name, a) in matrices() {
        let p = data(a.n());
        for s in SOLVERS {
            if s == Solver::Ldl && !ldl_allowed(a.n()) {
                eprintln!("| {name} | {} | {} | {s} | — | — | skipped (set SUBDIV_BENCH_LDL_1E6=1) |", a.n(), a.nnz());
                continue;
            }
            let runs = if a.n() >= 1_000_000 || s == Solver::Ldl { 1 } else { 5 };
            let mut times = Vec::new();
            let mut last = None;
            for _ in 0..runs {
                let t = Instant::now();
                let sol = s.solve(&a, &p, &opts()).expect("model problems converge");
                times.push(t.elapsed().as_secs_f64());
                last = Some(sol);
            }
            let sol = last.unwrap();
            eprintln!(
                "| {name} | {} | {} | {s} | {} | {} | {:.4} |",
                a.n(),
                a.nnz(),
                sol.iterations,
                sol.matvecs,
                median(times)
            );
        }
    }
    eprintln!("\n| matrix | rows | bytes/product | SpMV GB/s | triad GB/s | ratio |");
    eprintln!("|---|---:|---:|---:|---:|---:|");
    for (name, a) in matrices() {
        let x = data(a.n());
        let mut out = vec![[0.0; 3]; a.n()];
        let bytes = spmv_bytes(&a);
        let reps = (2_000_000_000 / bytes).clamp(5, 200) as usize;
        let t_spmv = median(
            (0..reps)
                .map(|_| {
                    let t = Instant::now();
                    a.apply(black_box(&x), &mut out);
                    t.elapsed().as_secs_f64()
                })
                .collect(),
        );
        let len = (bytes / 24) as usize;
        let (mut ta, tb, tc) = (vec![0.0; len], vec![1.0; len], vec![2.0; len]);
        let t_triad = median(
            (0..reps)
                .map(|_| {
                    let t = Instant::now();
                    triad(&mut ta, black_box(&tb), black_box(&tc), 3.0);
                    t.elapsed().as_secs_f64()
                })
                .collect(),
        );
        let (bw_spmv, bw_triad) = (bytes as f64 / t_spmv / 1e9, (24 * len) as f64 / t_triad / 1e9);
        eprintln!("| {name} | {} | {bytes} | {bw_spmv:.2} | {bw_triad:.2} | {:.2} |", a.n(), bw_spmv / bw_triad);
    }
    eprintln!();
}

fn solvers(c: &mut Criterion) {
    summary();
    for (name, a) in matrices() {
        let p = data(a.n());
        let mut group = c.benchmark_group(format!("solve/{name}"));
        group.sample_size(10).warm_up_time(Duration::from_millis(300)).measurement_time(Duration::from_secs(2));
        for s in SOLVERS {
            if s == Solver::Ldl && a.n() > 200_000 {
                continue;
            }
            group.bench_with_input(BenchmarkId::new(s.name(), a.n()), &a, |b, a| {
                b.iter(|| s.solve(a, black_box(&p), &opts()).unwrap().iterations)
            });
        }
        group.finish();
    }
}

fn bandwidth(c: &mut Criterion) {
    let mut group = c.benchmark_group("bandwidth");
    group.sample_size(20).warm_up_time(Duration::from_millis(300)).measurement_time(Duration::from_secs(2));
    for (name, a) in matrices() {
        let x = data(a.n());
        let mut out = vec![[0.0; 3]; a.n()];
        let bytes = spmv_bytes(&a);
        group.throughput(Throughput::Bytes(bytes));
        group.bench_function(BenchmarkId::new(format!("spmv/{name}"), a.n()), |b| {
            b.iter(|| a.apply(black_box(&x), &mut out))
        });
        let len = (bytes / 24) as usize;
        let (mut ta, tb, tc) = (vec![0.0; len], vec![1.0; len], vec![2.0; len]);
        group.throughput(Throughput::Bytes(24 * len as u64));
        group.bench_function(BenchmarkId::new(format!("triad/{name}"), a.n()), |b| {
            b.iter(|| triad(&mut ta, black_box(&tb), black_box(&tc), 3.0))
        });
    }
    group.finish();
}

criterion_group!(benches, solvers, bandwidth);
criterion_main!(benches);
