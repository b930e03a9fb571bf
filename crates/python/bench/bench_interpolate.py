"""A 100k-vertex `subdiv.interpolate` from NumPy against the same call in Rust.

Python: ``subdiv.interpolate(subdiv.Mesh(X, F), method).control.vertices``; Rust
(``examples/interpolate_bench.rs``, on the same arrays): ``interpolate(&Mesh::from_arrays(X, F),
method).control.positions_to_arrays()``. Both validate the mesh, interpolate and hand the control
points back as plain arrays. The two sides alternate in rounds (``--runs`` calls of each per round)
so that the machine's noise falls on both alike; prints the medians over all runs and their ratio
(target ≤ 1.05).

    python crates/python/bench/bench_interpolate.py [--method cheng] [--runs 7] [--rounds 5] [--rust BINARY]

``--rust`` defaults to building the example with ``cargo build --release`` first.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import subdiv

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))
from conftest import torus  # noqa: E402  (the suite's procedural torus)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--method", default="cheng")
    parser.add_argument("--runs", type=int, default=7, help="calls of each side per round")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--nu", type=int, default=400)
    parser.add_argument("--nv", type=int, default=250)
    parser.add_argument("--rust", help="the built interpolate_bench example")
    args = parser.parse_args()

    X, F = torus(args.nu, args.nv)

    rust_bin = args.rust
    if rust_bin is None:
        subprocess.run(["cargo", "build", "--release", "-p", "subdiv-python", "--example", "interpolate_bench"],
                       check=True)
        target = Path(os.environ.get("CARGO_TARGET_DIR", HERE.parents[2] / "target"))
        rust_bin = target / "release" / "examples" / "interpolate_bench"
    python_times, rust_times = [], []
    with tempfile.TemporaryDirectory() as tmp:
        vertices, faces = Path(tmp) / "vertices.f64", Path(tmp) / "faces.i64"
        X.astype("<f8").tofile(vertices)
        F.astype("<i8").tofile(faces)
        subdiv.interpolate(subdiv.Mesh(X, F), method=args.method)  # untimed, as the Rust side's first
        for _ in range(args.rounds):
            for _ in range(args.runs):
                start = time.perf_counter()
                control = subdiv.interpolate(subdiv.Mesh(X, F), method=args.method).control.vertices
                python_times.append(time.perf_counter() - start)
            done = subprocess.run([str(rust_bin), str(vertices), str(faces), str(F.shape[1]), args.method,
                                   str(args.runs)], check=True, capture_output=True, text=True)
            rust = json.loads(done.stdout)
            rust_times += rust["times_s"]
    python, rust_median = statistics.median(python_times), statistics.median(rust_times)
    checksum = 0.0
    for x, y, z in control.tolist():  # the Rust side's order of additions: bit-comparable
        checksum += x + y + z
    print(json.dumps({
        "vertices": len(X),
        "method": args.method,
        "runs": args.runs * args.rounds,
        "python_median_s": python,
        "python_min_s": min(python_times),
        "rust_median_s": rust_median,
        "rust_min_s": min(rust_times),
        "ratio_median": python / rust_median,
        "same_control_points": rust["checksum"] == checksum,
    }, indent=2))


if __name__ == "__main__":
    main()
