//! Times the limit-matrix builds on a generated 10⁶-vertex polygon torus:
//! `cargo run --release -p subdiv-stencil --example limit_time`.
use std::time::Instant;

fn main() {
    let base = subdiv_mesh::shapes::torus(1414, 707);
    let mesh = subdiv_mesh::shapes::polygon_mix(&base, 7, 0.1, 0.1, 0.05);
    let t = mesh.topology();
    for _ in 0..3 {
        let s = Instant::now();
        let a = subdiv_stencil::limit_matrix_catmull_clark(t);
        let t_a = s.elapsed().as_secs_f64();
        let s = Instant::now();
        let c = subdiv_stencil::limit_matrix_nasri(t);
        let t_c = s.elapsed().as_secs_f64();
        println!("n = {}: A {:.3} s (nnz {}), C {:.3} s (nnz {})", t.vertex_count(), t_a, a.s.nnz(), t_c, c.s.nnz());
    }
}
