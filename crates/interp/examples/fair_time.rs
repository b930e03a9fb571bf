//! Times `fair` against `cheng` on one mesh, optionally subdivided first
//! (release): `cargo run --release -p subdiv-interp --example fair_time [-- mesh.obj [levels [refine]]]`.
//! Without a file, `fixtures/quad/horse_quad.obj` subdivided 3 times by
//! Catmull-Clark (its refined control points as data: 153 602 vertices), the
//! 10⁵-vertex case of issue #18 (target: fair ≤ 5× cheng). The first run also
//! prints the thin-plate energy of both surfaces on the level-`refine` limit
//! points (fair's objective): with `levels` 0 and `refine` 3, Table 7's
//! measure and its lower bound (`fair_time -- mesh.obj 0 3`).
use std::time::Instant;
use subdiv_interp::fair::{self, FairOptions};
use subdiv_interp::{cheng, ChengOptions, SurfaceOptions};
use subdiv_mesh::Mesh;
use subdiv_stencil::Scheme;

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/quad/horse_quad.obj").into());
    let levels: usize = args.next().map_or(3, |l| l.parse().expect("a level count"));
    let refine: usize = args.next().map_or(1, |l| l.parse().expect("a refine count"));
    let soup = subdiv_io::read_mesh(std::path::Path::new(&path)).expect("readable mesh");
    let (base, _) = Mesh::from_soup(soup).expect("valid mesh");
    let mesh = subdiv_stencil::subdivide(&base, Scheme::CatmullClark, levels, false).expect("subdivided");
    let n = mesh.topology().vertex_count();
    for run in 0..3 {
        let start = Instant::now();
        let c = cheng::interpolate(&mesh, &ChengOptions::default()).expect("cheng");
        let tc = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let f = fair::interpolate(&mesh, &FairOptions::default().with_refine(refine)).expect("fair");
        let tf = start.elapsed().as_secs_f64();
        println!(
            "run {run}: n = {n}: cheng {:.3} s (setup {:.3}, solve {:.3}, {}), fair {:.3} s (setup {:.3}, solve {:.3}, {}), ratio {:.2}, errors {:.1e} / {:.1e}",
            tc,
            c.setup_seconds,
            c.solve_seconds,
            c.solve.as_ref().unwrap(),
            tf,
            f.setup_seconds,
            f.solve_seconds,
            f.solve.as_ref().unwrap(),
            tf / tc,
            c.measured_error.unwrap().max_rel,
            f.measured_error.unwrap().max_rel,
        );
        if run == 0 {
            let d = mesh.bbox_diagonal();
            let ec = fair::thin_plate_energy(
                &c.surface(refine).expect("surface"),
                SurfaceOptions::default(),
                refine as u32,
                d,
            );
            let ef = f.parameters.energy.expect("fair reports its energy");
            println!("thin-plate energy on the level-{refine} limit points: cheng {ec:.6e}, fair {ef:.6e}, fair / cheng {:.3}", ef / ec);
        }
    }
}
