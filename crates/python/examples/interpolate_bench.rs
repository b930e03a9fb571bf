//! The Rust side of `bench/bench_interpolate.py`: the same call as the Python one — arrays →
//! `Mesh::from_arrays` → `interpolate` → control points as arrays — on the same arrays (raw
//! little-endian files the script writes), timed the same way; prints every run's time and a checksum as JSON.
//!
//! `cargo run --release -p subdiv-python --example interpolate_bench -- VERTICES.f64 FACES.i64 K METHOD RUNS`

use std::time::Instant;
use subdiv::prelude::*;

fn read_le<T, const N: usize>(path: &str, from: fn([u8; N]) -> T) -> Vec<T> {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    bytes.chunks_exact(N).map(|c| from(c.try_into().expect("N bytes"))).collect()
}

fn main() -> Result<(), Error> {
    let args: Vec<String> = std::env::args().collect();
    let [_, vertices, faces, k, method, runs] = &args[..] else {
        panic!("usage: interpolate_bench VERTICES.f64 FACES.i64 K METHOD RUNS");
    };
    let k: usize = k.parse().expect("K: corners per face");
    let runs: usize = runs.parse().expect("RUNS");
    let method: Method = method.parse().expect("a method name");
    let flat = read_le(vertices, f64::from_le_bytes);
    let positions: Vec<[f64; 3]> = flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let indices: Vec<usize> = read_le(faces, i64::from_le_bytes).into_iter().map(|i| i as usize).collect();
    let options = MethodOptions::new(method);
    let mut times = Vec::new();
    let mut checksum = 0.0;
    // One untimed call first: the process is new (thread pool, first-touch pages), the Python
    // side's is not.
    for run in 0..=runs {
        let start = Instant::now();
        // The mesh and the interpolation are dropped inside the timing, as the Python call's
        // temporaries are.
        let control = {
            let mesh = Mesh::from_arrays(&positions, subdiv::mesh::FaceArrays::uniform(k, &indices))?;
            interpolate(&mesh, &options)?.control.positions_to_arrays()
        };
        if run > 0 {
            times.push(start.elapsed().as_secs_f64());
        }
        checksum = control.iter().map(|p| p[0] + p[1] + p[2]).sum();
    }
    let times_json: Vec<String> = times.iter().map(|t| format!("{t:?}")).collect();
    println!(
        "{{\"times_s\": [{}], \"runs\": {runs}, \"vertices\": {}, \"checksum\": {checksum:?}}}",
        times_json.join(", "),
        positions.len()
    );
    Ok(())
}
