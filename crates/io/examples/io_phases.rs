//! Times the phases of loading a big mesh, and writing it in every format:
//! read (MB/s of the file), topology build (ms per 10⁶ faces), validation,
//! and per format the write (MB/s of the output) and the read back.
//!
//! ```text
//! cargo run --release -p subdiv-io --example io_phases -- big.obj [runs]
//! ```
//! Outputs go to the system's temporary directory and are removed; with
//! `IO_PHASES_NO_WRITE` set, only the read and the topology are timed.

use std::path::PathBuf;
use std::time::Instant;
use subdiv_io::{read_mesh, write_mesh_as, Format, MeshView};
use subdiv_mesh::{Mesh, Topology};

/// The fastest of `runs` calls of `f`, in seconds, and the last result.
fn best<T>(runs: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..runs {
        let start = Instant::now();
        let value = f();
        times.push(start.elapsed().as_secs_f64());
        last = Some(value);
    }
    (times.into_iter().fold(f64::INFINITY, f64::min), last.expect("at least one run"))
}

fn main() {
    let mut args = std::env::args_os().skip(1);
    let Some(path) = args.next().map(PathBuf::from) else {
        eprintln!("usage: io_phases MESH [runs]");
        std::process::exit(2);
    };
    let runs: usize = args.next().and_then(|r| r.to_str()?.parse().ok()).unwrap_or(3);
    let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0) as f64;
    let (t, soup) = best(runs, || read_mesh(&path).expect("readable mesh"));
    let faces = soup.faces.len() as f64;
    println!(
        "read {}: {:.1} ms, {:.0} MB/s ({} vertices, {} faces)",
        path.display(),
        t * 1e3,
        size / t / 1e6,
        soup.positions.len(),
        soup.faces.len()
    );
    // Inputs cloned before the clock starts: the build alone is timed.
    let mut inputs: Vec<_> = (0..runs).map(|_| soup.faces.clone()).collect();
    let (t, _) =
        best(runs, || Topology::new(inputs.pop().expect("one per run"), soup.positions.len()).expect("valid topology"));
    println!("topology: {:.1} ms, {:.1} ms per 10^6 faces", t * 1e3, t * 1e3 / (faces / 1e6));
    let mut inputs: Vec<_> = (0..runs).map(|_| soup.clone()).collect();
    let (t, _) = best(runs, || Mesh::from_soup(inputs.pop().expect("one per run")).expect("valid mesh"));
    println!("from_soup: {:.1} ms, {:.1} ms per 10^6 faces", t * 1e3, t * 1e3 / (faces / 1e6));
    if std::env::var_os("IO_PHASES_NO_WRITE").is_some() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("io-phases-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary directory");
    let view = MeshView::new(&soup.positions, &soup.faces);
    for (format, ext) in [
        (Format::Obj, "obj"),
        (Format::PlyBinary, "ply"),
        (Format::PlyAscii, "ply"),
        (Format::Off, "off"),
        (Format::StlBinary, "stl"),
        (Format::StlAscii, "stl"),
    ] {
        let out = dir.join(format!("out-{format:?}.{ext}"));
        let (t, ()) = best(runs, || write_mesh_as(&out, view, format).expect("written"));
        let bytes = std::fs::metadata(&out).map(|m| m.len()).unwrap_or(0) as f64;
        let (r, _) = best(runs, || read_mesh(&out).expect("reads back"));
        println!(
            "{format:?}: {:.0} MB, write {:.1} ms {:.0} MB/s, read {:.1} ms {:.0} MB/s",
            bytes / 1e6,
            t * 1e3,
            bytes / t / 1e6,
            r * 1e3,
            bytes / r / 1e6
        );
    }
    std::fs::remove_dir_all(&dir).expect("cleanup");
}
