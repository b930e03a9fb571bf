//! Times the limit-matrix builds on a generated 10⁶-vertex polygon torus, or
//! on a mesh file given as the argument:
//! `cargo run --release -p subdiv-stencil --example limit_time [-- mesh.obj]`.
use std::time::Instant;

fn main() {
    let mesh = match std::env::args().nth(1) {
        Some(path) => {
            let soup = subdiv_io::read_mesh(std::path::Path::new(&path)).expect("readable mesh");
            subdiv_mesh::Mesh::new(soup.positions, soup.faces).expect("valid mesh")
        }
        None => {
            let base = subdiv_mesh::shapes::torus(1414, 707);
            subdiv_mesh::shapes::polygon_mix(&base, 7, 0.1, 0.1, 0.05)
        }
    };
    let t = mesh.topology();
    let runs = if t.vertex_count() < 100_000 { 200 } else { 3 };
    let (mut times_a, mut times_c) = (Vec::new(), Vec::new());
    for _ in 0..runs {
        let s = Instant::now();
        let a = subdiv_stencil::limit_matrix_catmull_clark(t);
        times_a.push(s.elapsed().as_secs_f64());
        let s = Instant::now();
        let c = subdiv_stencil::limit_matrix_doo_sabin(t);
        times_c.push(s.elapsed().as_secs_f64());
        std::hint::black_box((a, c));
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    println!(
        "n = {}: A median {:.3} ms, C median {:.3} ms ({runs} runs)",
        t.vertex_count(),
        1e3 * median(&mut times_a),
        1e3 * median(&mut times_c)
    );
}
