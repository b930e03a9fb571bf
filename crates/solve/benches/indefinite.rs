//! MINRES on Cheng's Catmull-Clark limit matrices with interior valence-2
//! vertices against CG on the same mesh without them, at ≥ 500k rows.
//!
//! Meshes (procedural, `subdiv_mesh::shapes`): a quad torus of
//! `SUBDIV_BENCH_TORUS` = 1024 × 512 = 524,288 vertices (every valence 4), and
//! copies with valence-2 vertices inserted by splitting edges shared by two
//! quads (`shapes::split_edges`: the edge (a, b) becomes (a, v, b) in both faces):
//! - **single**: 4 separate split edges. Measured on small tori: A stays
//!   positive definite (λ_min ≈ 0.098), although the mesh is flagged
//!   `Degeneracy::Indefinite`;
//! - **adjacent**: 2 separate split edges plus 2 edges split twice (a–w–v–b:
//!   two adjacent valence-2 vertices), 6 valence-2 vertices; each pair gives
//!   one negative eigenvalue (λ_min ≈ −0.023): CG refuses, MINRES solves.
//!
//! The system is the interpolation problem of `subdiv interpolate --method
//! cheng` on a closed mesh: A·X = P with P the vertex positions, tol 1e-6
//! relative to the bounding-box diagonal, X₀ = P. The target (issue 13):
//! MINRES on the valence-2 mesh needs at most 2× the products of CG (the
//! method's default, Jacobi-preconditioned) on the clean mesh.
//!
//! Before the criterion groups a summary table goes to stderr: iterations,
//! matvecs and the median wall time of 3 runs per solver, and LDLᵀ once
//! (`SUBDIV_BENCH_SKIP_LDL=1` skips it).

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use subdiv_mesh::{shapes, EdgeId, Mesh};
use subdiv_solve::{FactoredMatrix, Solution, SolveOptions, Solver};

fn torus_size() -> (usize, usize) {
    std::env::var("SUBDIV_BENCH_TORUS")
        .ok()
        .and_then(|v| {
            let (a, b) = v.split_once('x')?;
            Some((a.parse().ok()?, b.parse().ok()?))
        })
        .unwrap_or((1024, 512))
}

/// `mesh` with the edges `singles` split once and `doubles` split twice.
fn with_valence_two(mesh: &Mesh, singles: &[EdgeId], doubles: &[EdgeId]) -> Mesh {
    let t = mesh.topology();
    let first: Vec<EdgeId> = singles.iter().chain(doubles).copied().collect();
    let once = shapes::split_edges(mesh, &first, 0.05);
    let t1 = once.topology();
    let second: Vec<EdgeId> = doubles
        .iter()
        .enumerate()
        .map(|(k, &e)| {
            let a = t.edge_vertices(e).0 .0;
            let v = (t.vertex_count() + singles.len() + k) as u32;
            t1.edges()
                .find(|&f| {
                    let (x, y) = t1.edge_vertices(f);
                    (x.0 == a && y.0 == v) || (x.0 == v && y.0 == a)
                })
                .expect("the first split made (a, v)")
        })
        .collect();
    shapes::split_edges(&once, &second, 0.05)
}

struct Case {
    name: String,
    a: FactoredMatrix,
    p: Vec<[f64; 3]>,
    scale: f64,
    valence_two: usize,
}

/// Deterministic noise in [−1, 1) (SplitMix64).
fn noise(i: u64) -> f64 {
    let mut z = i.wrapping_add(1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// The system of `mesh`; `jitter` moves every data point by up to that
/// fraction of the mean edge length (x, y, z independently), so that the data
/// are not already nearly a smooth limit surface.
fn case(name: &str, mesh: &Mesh, valence_two: usize, jitter: f64) -> Case {
    let lm = subdiv_stencil::limit_matrix_catmull_clark(mesh.topology());
    let a = FactoredMatrix::new(lm.d, lm.s).expect("limit matrices are valid");
    let h = jitter * shapes::mean_edge_length(mesh);
    let p = mesh
        .positions()
        .iter()
        .enumerate()
        .map(|(i, q)| std::array::from_fn(|c| q[c] + h * noise(3 * i as u64 + c as u64)))
        .collect();
    let name = if jitter > 0.0 { format!("{name}, jittered") } else { format!("{name}, smooth") };
    Case { name, a, p, scale: mesh.bbox_diagonal(), valence_two }
}

fn cases() -> Vec<Case> {
    let (nu, nv) = torus_size();
    let torus = shapes::torus(nu, nv);
    let m = torus.topology().edge_count() as u32;
    // Spread over the torus: edge ids follow the faces, row by row.
    let at = |f: f64| EdgeId((f * m as f64) as u32);
    let single = with_valence_two(&torus, &[at(0.1), at(0.35), at(0.6), at(0.85)], &[]);
    let adjacent = with_valence_two(&torus, &[at(0.1), at(0.6)], &[at(0.35), at(0.85)]);
    let mut out = Vec::new();
    for jitter in [0.0, JITTER] {
        out.push(case("clean", &torus, 0, jitter));
        out.push(case("single", &single, 4, jitter));
        out.push(case("adjacent", &adjacent, 6, jitter));
    }
    out
}

fn opts(c: &Case) -> SolveOptions {
    SolveOptions::default().with_tol(1e-6).with_scale(c.scale).with_history(false)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn timed(s: Solver, c: &Case, runs: usize) -> Result<(Solution, f64), String> {
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..runs {
        let t = Instant::now();
        let sol = s.solve(&c.a, black_box(&c.p), &opts(c)).map_err(|e| e.to_string())?;
        times.push(t.elapsed().as_secs_f64());
        last = Some(sol);
    }
    Ok((last.expect("runs ≥ 1"), median(times)))
}

/// Data noise of the second set of cases, as a fraction of the mean edge length.
const JITTER: f64 = 0.2;

const SOLVERS: [Solver; 3] = [Solver::Cg { jacobi: true }, Solver::Cg { jacobi: false }, Solver::Minres];

fn summary(cases: &[Case]) {
    eprintln!(
        "\n## Cheng's A with valence-2 vertices (tol 1e-6 · d, X₀ = P, {} threads)\n",
        rayon::current_num_threads()
    );
    eprintln!("| mesh | rows | valence-2 | solver | iterations | matvecs | seconds (median of 3) |");
    eprintln!("|---|---:|---:|---|---:|---:|---:|");
    let mut cg_clean = std::collections::HashMap::new();
    let mut minres_matvecs = Vec::new();
    for c in cases {
        for s in SOLVERS {
            match timed(s, c, 3) {
                Ok((sol, t)) => {
                    eprintln!(
                        "| {} | {} | {} | {s} | {} | {} | {t:.3} |",
                        c.name,
                        c.a.n(),
                        c.valence_two,
                        sol.iterations,
                        sol.matvecs
                    );
                    let data = c.name.split_once(", ").map_or("", |t| t.1).to_owned();
                    if c.name.starts_with("clean") && s == (Solver::Cg { jacobi: true }) {
                        cg_clean.insert(data, sol.matvecs);
                    } else if !c.name.starts_with("clean") && s == Solver::Minres {
                        minres_matvecs.push((c.name.clone(), data, sol.matvecs));
                    }
                }
                Err(e) => eprintln!("| {} | {} | {} | {s} | — | — | {e} |", c.name, c.a.n(), c.valence_two),
            }
        }
        let skip_ldl = std::env::var("SUBDIV_BENCH_SKIP_LDL").is_ok_and(|v| v == "1");
        if c.name.starts_with("adjacent") && !skip_ldl {
            match timed(Solver::Ldl, c, 1) {
                Ok((sol, t)) => eprintln!(
                    "| {} | {} | {} | ldl | 1 | {} | {t:.3} (one run; {} negative pivots) |",
                    c.name,
                    c.a.n(),
                    c.valence_two,
                    sol.matvecs,
                    sol.negative_pivots.unwrap_or(0)
                ),
                Err(e) => eprintln!("| {} | {} | {} | ldl | — | — | {e} |", c.name, c.a.n(), c.valence_two),
            }
        }
    }
    eprintln!();
    for (name, data, m) in minres_matvecs {
        if let Some(cg) = cg_clean.get(&data) {
            eprintln!(
                "MINRES on `{name}` / CG-Jacobi on `clean, {data}`: {m} / {cg} = {:.2} matvecs (target ≤ 2)",
                m as f64 / *cg as f64
            );
        }
    }
    eprintln!();
}

fn solvers(c: &mut Criterion) {
    let cases = cases();
    summary(&cases);
    let mut group = c.benchmark_group("indefinite");
    group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(4));
    for case in &cases {
        for s in SOLVERS {
            if s.solve(&case.a, &case.p, &opts(case)).is_err() {
                continue;
            }
            group.bench_with_input(
                BenchmarkId::new(format!("{}/{}", s.name(), case.name), case.a.n()),
                case,
                |b, c| b.iter(|| s.solve(&c.a, black_box(&c.p), &opts(c)).unwrap().iterations),
            );
        }
    }
    group.finish();
}

criterion_group!(benches, solvers);
criterion_main!(benches);
