//! The facade's consumer program (`crates/subdiv/examples/pipeline.rs`, one
//! dependency, ≤ 30 lines) gives what the command line gives, bit for bit:
//! the surfaces it writes are the files `subdiv interpolate --surface`
//! writes, and its arrays → Deng-Wang → arrays control points are those of
//! `subdiv interpolate --method deng-wang -o` on the same mesh as a file.

use crate::common::{fixtures, read, run_ok, Scratch};

#[path = "../../../subdiv/examples/pipeline.rs"]
#[allow(dead_code)] // its `main` is the example's, not called here
mod pipeline;

#[test]
fn the_consumer_program_writes_what_the_cli_writes() {
    let scratch = Scratch::new("facade");
    let input = fixtures().join("quad/spot_control_mesh.obj");
    let dir = scratch.path("library");
    std::fs::create_dir_all(&dir).unwrap();
    let control = pipeline::run(&input, &dir).expect("the pipeline runs");

    for method in ["cheng", "zheng-cai"] {
        let cli = scratch.path(&format!("{method}-cli.ply"));
        let (i, s) = (input.to_str().unwrap(), cli.to_str().unwrap());
        run_ok(&["interpolate", i, "--method", method, "--surface", s, "--levels", "2"]);
        let library = std::fs::read(dir.join(format!("{method}.ply"))).unwrap();
        let written = std::fs::read(&cli).unwrap();
        assert!(library.len() > 10_000, "{method}: a real surface");
        assert!(library == written, "{method}: the library's surface file differs from the CLI's");
    }

    // The same tetrahedron as a file, through the CLI.
    let tetra = scratch.path("tetrahedron.obj");
    std::fs::write(&tetra, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n").unwrap();
    let cli_control = scratch.path("tetrahedron-control.obj");
    run_ok(&["interpolate", tetra.to_str().unwrap(), "--method", "deng-wang", "-o", cli_control.to_str().unwrap()]);
    let cli_points: Vec<[f64; 3]> = read(&cli_control).positions.iter().map(|p| p.to_array()).collect();
    assert_eq!(control.len(), 4 + 6, "Deng-Wang's control mesh is M¹: vertices + edges");
    assert_eq!(control, cli_points, "bit for bit (OBJ writes shortest round-trip decimals)");
}
