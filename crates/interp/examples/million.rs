//! Matrix build + solve on a generated closed polygon mesh of about 10⁶
//! vertices (median of 3 runs, release):
//! `cargo run --release -p subdiv-interp --example million`.
use std::time::Instant;
use subdiv_interp::{cheng, fan_cheng_lai, nasri, ChengOptions, FanChengLaiOptions, NasriOptions};

fn main() {
    let base = subdiv_mesh::shapes::torus(1414, 707);
    let mesh = subdiv_mesh::shapes::polygon_mix(&base, 7, 0.1, 0.1, 0.05);
    let all = vec![true; mesh.topology().vertex_count()];
    let d = mesh.bbox_diagonal();
    type Run = fn(&subdiv_mesh::Mesh) -> subdiv_interp::Interpolant;
    let runs: [(&str, Run); 3] = [
        ("cheng (A, CG-Jacobi)", |m| cheng::interpolate(m, &ChengOptions::default()).unwrap()),
        ("nasri (C, CG-Jacobi)", |m| nasri::interpolate(m, &NasriOptions::default()).unwrap()),
        ("fan-cheng-lai (B(½), PIA)", |m| fan_cheng_lai::interpolate(m, &FanChengLaiOptions::default()).unwrap()),
    ];
    for (name, run) in runs {
        let mut times = Vec::new();
        let mut last = None;
        for _ in 0..3 {
            let start = Instant::now();
            last = Some(run(&mesh));
            times.push(start.elapsed().as_secs_f64());
        }
        times.sort_by(f64::total_cmp);
        let r = last.expect("three runs");
        let s = r.solve.clone().unwrap_or_default();
        println!(
            "{name}: n = {}, total {:.3} s (setup {:.3} s, solve {:.3} s), {} iterations, {} products, error {:.2e}·d",
            all.len(),
            times[1],
            r.setup_seconds,
            r.solve_seconds,
            s.iterations,
            s.matvecs,
            r.error(mesh.positions(), &all, d).max_rel
        );
    }
}
