//! Times `read_mesh` on a file: the median of five reads.
//!
//! ```text
//! cargo run --release -p subdiv-io --example read_time -- ../shared/meshes/tri/dragon_vrip_full_binary.ply
//! ```

use std::path::PathBuf;
use std::time::Instant;

fn main() {
    let default =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/meshes/tri/dragon_vrip_full_binary.ply");
    let path = std::env::args_os().nth(1).map_or(default, PathBuf::from);
    let mut times = Vec::new();
    let mut counts = (0, 0);
    for _ in 0..5 {
        let start = Instant::now();
        let soup = match subdiv_io::read_mesh(&path) {
            Ok(soup) => soup,
            Err(e) => {
                eprintln!("{e}");
                std::process::exit(2);
            }
        };
        times.push(start.elapsed().as_secs_f64() * 1e3);
        counts = (soup.positions.len(), soup.faces.len());
    }
    times.sort_by(f64::total_cmp);
    println!(
        "{}: {} vertices, {} faces; read times (ms) {:.1?}; median {:.1} ms",
        path.display(),
        counts.0,
        counts.1,
        times,
        times[2]
    );
}
