//! Times every method on one mesh: median total, setup and solve over the
//! runs, iterations and error (release):
//! `cargo run --release -p subdiv-interp --example method_time [-- mesh.obj [runs [method]]]`.
//! Without a file (or with `-`), a generated closed polygon mesh of about 10⁶ vertices.
//! `method` is a name of `subdiv_interp::Method` (`nasri`, `zheng-cai`, …); each
//! method runs with its defaults, and one that refuses the mesh prints its error.
use std::time::Instant;
use subdiv_interp::{interpolate, Method, MethodOptions};
use subdiv_mesh::Mesh;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let mut args = std::env::args().skip(1);
    let mesh = match args.next().filter(|p| p != "-") {
        Some(path) => {
            let soup = subdiv_io::read_mesh(std::path::Path::new(&path)).expect("readable mesh");
            Mesh::new(soup.positions, soup.faces).expect("valid mesh")
        }
        None => {
            let base = subdiv_mesh::shapes::torus(1414, 707);
            subdiv_mesh::shapes::polygon_mix(&base, 7, 0.1, 0.1, 0.05)
        }
    };
    let n = mesh.topology().vertex_count();
    let runs: usize = args.next().map_or(if n < 100_000 { 100 } else { 3 }, |r| r.parse().expect("a run count"));
    let only: Option<Method> = args.next().map(|m| m.parse().expect("a method name"));
    let all = vec![true; n];
    let d = mesh.bbox_diagonal();
    for method in Method::ALL.into_iter().filter(|&m| only.is_none_or(|o| o == m)) {
        let (name, options) = (method.name(), MethodOptions::new(method));
        let (mut total, mut setup, mut solve) = (Vec::new(), Vec::new(), Vec::new());
        let mut last = None;
        for _ in 0..runs {
            let start = Instant::now();
            match interpolate(&mesh, &options) {
                Ok(r) => {
                    total.push(start.elapsed().as_secs_f64());
                    setup.push(r.setup_seconds);
                    solve.push(r.solve_seconds);
                    last = Some(r);
                }
                Err(e) => {
                    println!("{name}: {e}");
                    break;
                }
            }
        }
        let Some(r) = last else { continue };
        let s = r.solve.clone().unwrap_or_default();
        println!(
            "{name:>13}: n = {n}, total {:.3} ms (setup {:.3}, solve {:.3}), {} iterations, error {:.2e}·d",
            1e3 * median(total),
            1e3 * median(setup),
            1e3 * median(solve),
            s.iterations,
            r.error(mesh.positions(), &all, d).max_rel
        );
    }
}
