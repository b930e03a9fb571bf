//! Untagged vs tagged subdivision, alternating in one process so drifting
//! machine load hits both alike; prints medians and their ratio.
//!
//! `cargo run --release -p subdiv-stencil --example tagged_time -- MESH SCHEME LEVELS [RUNS]`
//! (SCHEME `cc` or `loop`; tags as in `benches/tagged.rs`: 10 % of the edges
//! creased at 10 / 2.5 / 1.0, 2 % of the vertices corners).

use std::time::Instant;
use subdiv_mesh::Mesh;
use subdiv_stencil::{subdivide, CreaseMethod, LoopBeta, Options, Scheme, SubdivisionPlan};

#[path = "../benches/support/tagging.rs"]
mod tagging;
use tagging::tagged;

fn median(mut x: Vec<f64>) -> f64 {
    x.sort_by(f64::total_cmp);
    x[x.len() / 2]
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let [_, path, scheme, levels, rest @ ..] = args.as_slice() else {
        eprintln!("usage: tagged_time MESH cc|loop LEVELS [RUNS]");
        std::process::exit(2);
    };
    let runs: usize = rest.first().map_or(15, |r| r.parse().expect("RUNS"));
    let levels: usize = levels.parse().expect("LEVELS");
    let scheme = if scheme == "loop" { Scheme::Loop(LoopBeta::Loop) } else { Scheme::CatmullClark };
    let soup = subdiv_io::read_mesh(std::path::Path::new(path)).expect("readable mesh");
    let plain = Mesh::from_soup(soup).expect("valid mesh").0;
    let sharp = tagged(&plain);
    let cases = [
        ("untagged", &plain, CreaseMethod::Uniform),
        ("tagged", &sharp, CreaseMethod::Uniform),
        ("tagged-chaikin", &sharp, CreaseMethod::Chaikin),
    ];
    let mut direct = vec![Vec::new(); cases.len()];
    let mut planned = vec![Vec::new(); cases.len()];
    for _ in 0..runs {
        for (k, &(_, mesh, method)) in cases.iter().enumerate() {
            let options = Options::new(scheme).with_crease_method(method);
            let start = Instant::now();
            std::hint::black_box(subdivide(mesh, options, levels, false).expect("subdivides"));
            direct[k].push(start.elapsed().as_secs_f64());
            let start = Instant::now();
            let plan = SubdivisionPlan::with_tags(mesh.topology(), mesh.tags(), options, levels).expect("plans");
            std::hint::black_box(plan.apply(mesh.positions()));
            planned[k].push(start.elapsed().as_secs_f64());
        }
    }
    println!(
        "{path} {} L{levels}: {} creases, {} corners, {runs} alternating runs, medians",
        scheme.name(),
        sharp.tags().crease_count(),
        sharp.tags().corner_count()
    );
    let (d0, p0) = (median(direct[0].clone()), median(planned[0].clone()));
    for (k, &(label, ..)) in cases.iter().enumerate() {
        let (d, p) = (median(direct[k].clone()), median(planned[k].clone()));
        println!(
            "  {label:15} subdivide {:8.2} ms ({:.2}×)   plan {:8.2} ms ({:.2}×)",
            d * 1e3,
            d / d0,
            p * 1e3,
            p / p0
        );
    }
}
