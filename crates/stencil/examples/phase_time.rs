//! Where one Catmull-Clark plan spends its time: refined topology, stencil
//! construction and the sparse products, each summed over four levels and
//! timed on its own rather than overlapped as in a plan (minimum of 10 runs):
//! `cargo run --release -p subdiv-stencil --example phase_time -- fixtures/quad/horse_quad.obj`.
use std::time::Instant;
use subdiv_mesh::{refine, Mesh};
use subdiv_stencil::{apply, catmull_clark};
fn main() {
    let path = std::env::args().nth(1).unwrap_or_else(|| "fixtures/quad/horse_quad.obj".into());
    let soup = subdiv_io::read_mesh(std::path::Path::new(&path)).expect("a readable mesh");
    let mesh = Mesh::from_soup(soup).expect("a valid mesh").0;
    let mut best = [f64::MAX; 3];
    for _ in 0..10 {
        let mut t = mesh.topology().clone();
        let mut p = mesh.positions().to_vec();
        let (mut tt, mut ts, mut ta) = (0.0, 0.0, 0.0);
        for _ in 0..4 {
            let s = Instant::now();
            let nt = refine::quad_split(&t);
            tt += s.elapsed().as_secs_f64();
            let s = Instant::now();
            let r = catmull_clark::refinement_stencil(&t);
            ts += s.elapsed().as_secs_f64();
            let s = Instant::now();
            p = apply(&r, &p);
            ta += s.elapsed().as_secs_f64();
            t = nt;
        }
        best = [best[0].min(tt), best[1].min(ts), best[2].min(ta)];
    }
    println!(
        "min of 10: topology {:.1} ms stencil {:.1} ms apply {:.1} ms",
        best[0] * 1e3,
        best[1] * 1e3,
        best[2] * 1e3
    );
}
