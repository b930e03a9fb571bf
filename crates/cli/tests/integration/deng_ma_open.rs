//! `subdiv subdivide --scheme deng-ma` and `subdiv interpolate --method
//! deng-ma` on open meshes (our 4-point boundary rule): exit 0, the written
//! surface starts with the input's vertices bit for bit (read back from the
//! file), and its boundary loops are 2^levels times as long.

use crate::common::{assert_no_panic, fixtures, subdiv, Scratch};
use serde_json::Value;
use subdiv_mesh::Mesh;

fn load(path: &std::path::Path) -> Mesh {
    Mesh::from_soup(subdiv_io::read_mesh(path).unwrap()).unwrap().0
}

/// Boundary loop lengths, sorted.
fn loop_lengths(mesh: &Mesh) -> Vec<usize> {
    let mut lengths: Vec<usize> = mesh.topology().boundary_loops().map(<[_]>::len).collect();
    lengths.sort_unstable();
    lengths
}

#[test]
fn subdivide_deng_ma_takes_open_meshes() {
    let scratch = Scratch::new("deng-ma-open");
    for (input, extra) in [
        ("open/nefertiti_small.off", vec![]),
        ("open/halftunnel.off", vec!["--omega", "0.5"]),
        ("canonical/grid_quad_8x8_open.obj", vec!["--variable-tension", "0.5"]),
    ] {
        let path = fixtures().join(input);
        let out = scratch.path(&format!("{}.obj", input.replace('/', "-")));
        let mut args = vec!["subdivide", path.to_str().unwrap(), "--scheme", "deng-ma", "--levels", "2"];
        args.extend(extra.iter().copied());
        args.extend(["-o", out.to_str().unwrap()]);
        let run = subdiv(&args);
        assert_no_panic(&run);
        assert_eq!(run.status.code(), Some(0), "{input}: {}", String::from_utf8_lossy(&run.stderr));
        let (data, surface) = (load(&path), load(&out));
        let n = data.topology().vertex_count();
        assert_eq!(&surface.positions()[..n], data.positions(), "{input}: input vertices moved");
        let quadrupled: Vec<usize> = loop_lengths(&data).iter().map(|l| 4 * l).collect();
        assert_eq!(loop_lengths(&surface), quadrupled, "{input}");
    }
}

#[test]
fn interpolate_deng_ma_takes_open_meshes() {
    let scratch = Scratch::new("deng-ma-open");
    let path = fixtures().join("open/halftunnel.off");
    let (out, report) = (scratch.path("halftunnel-surface.obj"), scratch.path("halftunnel-report.json"));
    let run = subdiv(&[
        "interpolate",
        path.to_str().unwrap(),
        "--method",
        "deng-ma",
        "--levels",
        "2",
        "-o",
        out.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
    ]);
    assert_no_panic(&run);
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    let r: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(r["method"], "deng-ma");
    assert_eq!(r["error"]["max_abs"], 0.0, "{}", r["error"]);
    let (data, surface) = (load(&path), load(&out));
    assert_eq!(&surface.positions()[..data.topology().vertex_count()], data.positions());
}
