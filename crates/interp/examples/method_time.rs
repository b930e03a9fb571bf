//! Times every method on one mesh: median total, setup and solve over the
//! runs, iterations and error (release):
//! `cargo run --release -p subdiv-interp --example method_time [-- mesh.obj [runs [method]]]`.
//! Without a file (or with `-`), a generated closed polygon mesh of about 10⁶ vertices
//! (Loop's Deng-Wang is skipped on meshes with non-triangles).
use std::time::Instant;
use subdiv_interp::{cheng, deng_wang, fan_cheng_lai, nasri, zheng_cai, InterpError, Interpolant};
use subdiv_mesh::Mesh;

type Run = fn(&Mesh) -> Result<Interpolant, InterpError>;

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
    let only = args.next();
    let all = vec![true; n];
    let d = mesh.bbox_diagonal();
    let methods: [(&str, Run); 5] = [
        ("nasri", |m| nasri::interpolate(m, &Default::default())),
        ("zheng-cai", |m| zheng_cai::interpolate(m, &Default::default())),
        ("cheng", |m| cheng::interpolate(m, &Default::default())),
        ("fan-cheng-lai", |m| fan_cheng_lai::interpolate(m, &Default::default())),
        ("deng-wang", |m| deng_wang::interpolate(m, &Default::default())),
    ];
    for (name, run) in methods.into_iter().filter(|(name, _)| only.as_deref().is_none_or(|o| o == *name)) {
        let (mut total, mut setup, mut solve) = (Vec::new(), Vec::new(), Vec::new());
        let mut last = None;
        for _ in 0..runs {
            let start = Instant::now();
            match run(&mesh) {
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
