//! Where `subdiv info` spends its time on one file: reading, validation
//! (connectivity, then the warnings), the counts, each method's check.
//!
//! `cargo run --release -p subdiv-job --example info_phases -- MESH [RUNS]`
//! prints the median of RUNS (default 3) per phase, in milliseconds.

use std::time::Instant;
use subdiv_interp::Method;
use subdiv_mesh::{Mesh, Topology};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args.next().ok_or("usage: info_phases MESH [RUNS]")?;
    let runs: usize = args.next().map(|r| r.parse()).transpose()?.unwrap_or(3);
    let mut phases: Vec<(String, Vec<f64>)> = Vec::new();
    let mut record = |name: &str, ms: f64| match phases.iter_mut().find(|(n, _)| n == name) {
        Some((_, v)) => v.push(ms),
        None => phases.push((name.to_string(), vec![ms])),
    };
    for _ in 0..runs {
        let clock = Instant::now();
        let soup = subdiv_io::read_mesh(std::path::Path::new(&path))?;
        record("read", clock.elapsed().as_secs_f64() * 1e3);
        let clock = Instant::now();
        let topology = Topology::new(soup.faces.clone(), soup.positions.len())?;
        record("Topology::new (on a copy)", clock.elapsed().as_secs_f64() * 1e3);
        drop(topology);
        let clock = Instant::now();
        let (mesh, _) = Mesh::from_soup(soup)?;
        record("Mesh::from_soup", clock.elapsed().as_secs_f64() * 1e3);
        let clock = Instant::now();
        let warnings = mesh.warnings();
        record("Mesh::warnings", clock.elapsed().as_secs_f64() * 1e3);
        for m in Method::ALL {
            let clock = Instant::now();
            let _ = m.check(&mesh);
            record(&format!("check {m}"), clock.elapsed().as_secs_f64() * 1e3);
        }
        let clock = Instant::now();
        let summary = subdiv_job::info::summarize_with_warnings(&mesh, Some(&path), &warnings);
        record("summarize_with_warnings", clock.elapsed().as_secs_f64() * 1e3);
        let clock = Instant::now();
        let _ = serde_json::to_string(&summary)?;
        record("json", clock.elapsed().as_secs_f64() * 1e3);
    }
    for (name, mut ms) in phases {
        ms.sort_by(f64::total_cmp);
        println!("{name:<28} {:>9.1} ms", ms[ms.len() / 2]);
    }
    Ok(())
}
