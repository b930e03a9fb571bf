//! The batch on procedural meshes written to a temporary directory.

use super::*;
use std::fs;
use std::time::SystemTime;
use subdiv_interp::{interpolate, Method, MethodOptions};
use subdiv_io::{load_mesh, write_mesh, WriteOptions};
use subdiv_mesh::Mesh;

/// A fresh directory for one test (`subdiv-batch-{test}-XXXXXX`), removed when it drops.
fn scratch(test: &str) -> tempfile::TempDir {
    tempfile::Builder::new().prefix(&format!("subdiv-batch-{test}-")).tempdir().unwrap()
}

fn write(path: &Path, mesh: &Mesh) -> PathBuf {
    fs::create_dir_all(path.parent().unwrap()).unwrap();
    write_mesh(path, mesh, &WriteOptions::default()).unwrap();
    path.to_path_buf()
}

fn mtimes(dir: &Path) -> BTreeMap<PathBuf, SystemTime> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| (p.clone(), p.metadata().unwrap().modified().unwrap()))
        .collect()
}

#[test]
fn failures_are_isolated_and_outputs_match_the_library() {
    let tmp = scratch("isolated");
    let dir = tmp.path();
    let torus = subdiv_mesh::shapes::torus(8, 6);
    let good = write(&dir.join("in/torus.obj"), &torus);
    // A face of two corners: read, but no mesh.
    let fin = dir.join("in/fin.obj");
    fs::write(&fin, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 2 1\n").unwrap();
    let missing = dir.join("in/missing.obj");
    let out = dir.join("out");
    let command = Command::Interpolate(InterpolateOptions::new(Method::Cheng).with_levels(1));
    let mut seen = Vec::new();
    let records =
        run(&[fin.clone(), good.clone(), missing], &out, &command, &BatchOptions::default().with_jobs(2), |r| {
            seen.push(r.index)
        })
        .unwrap();
    assert_eq!(seen, [0, 1, 2], "in input order");
    assert_eq!(records.len(), 3);
    let e = records[0].error.as_ref().unwrap();
    assert_eq!((e.kind, e.exit_code), (ErrorKind::BadInput, 2));
    assert!(e.message.starts_with(&format!("{}: ", fin.display())) && e.message.contains("at least 3"), "{e:?}");
    assert!(records[2].error.as_ref().unwrap().message.contains("missing.obj"));
    assert!(records[1].succeeded(), "{:?}", records[1].error);

    // The files are the library's own results, written the usual way.
    let result = interpolate(&torus, &MethodOptions::new(Method::Cheng)).unwrap();
    let expected = dir.join("expected");
    fs::create_dir_all(&expected).unwrap();
    write_mesh(expected.join("c.obj"), &result.control, &WriteOptions::default()).unwrap();
    write_mesh(expected.join("s.obj"), &result.surface(1).unwrap(), &WriteOptions::default().with_normals(true))
        .unwrap();
    assert_eq!(
        records[1].outputs,
        [out.join("torus.control.obj").display().to_string(), out.join("torus.surface.obj").display().to_string()]
    );
    assert_eq!(fs::read(out.join("torus.control.obj")).unwrap(), fs::read(expected.join("c.obj")).unwrap());
    assert_eq!(fs::read(out.join("torus.surface.obj")).unwrap(), fs::read(expected.join("s.obj")).unwrap());
    // The record file is the record.
    let stored: Record = serde_json::from_str(&fs::read_to_string(out.join("torus.record.json")).unwrap()).unwrap();
    assert_eq!(stored, records[1]);
    assert!(stored.report.unwrap()["error"]["max_rel"].as_f64().unwrap() <= subdiv_interp::DEFAULT_TOL);
}

#[test]
fn a_second_run_skips_and_a_touched_input_reruns() {
    let tmp = scratch("resume");
    let dir = tmp.path();
    let a = write(&dir.join("a.obj"), &subdiv_mesh::shapes::cube());
    let b = write(&dir.join("b.obj"), &subdiv_mesh::shapes::octahedron());
    let out = dir.join("out");
    let command =
        Command::from_json("subdivide", &serde_json::json!({"scheme": "catmull-clark", "levels": 1})).unwrap();
    let options = BatchOptions::default();
    let inputs = [dir.to_path_buf()];
    let first = run(&inputs, &out, &command, &options, |_| {}).unwrap();
    assert_eq!(first.iter().map(|r| r.name.as_str()).collect::<Vec<_>>(), ["a", "b"], "the directory, sorted");
    assert!(first.iter().all(|r| r.succeeded() && !r.skipped));
    let before = mtimes(&out);
    std::thread::sleep(std::time::Duration::from_millis(20));

    let second = run(&inputs, &out, &command, &options, |_| {}).unwrap();
    assert!(second.iter().all(|r| r.skipped));
    for (s, f) in second.iter().zip(&first) {
        assert_eq!(Record { skipped: false, ..s.clone() }, *f);
    }
    assert_eq!(mtimes(&out), before, "nothing rewritten");

    // Another command is another job; so is a changed input.
    let other = Command::from_json("subdivide", &serde_json::json!({"scheme": "catmull-clark", "levels": 2})).unwrap();
    assert!(run(std::slice::from_ref(&a), &out, &other, &options, |_| {}).unwrap().iter().all(|r| !r.skipped));
    let _ = run(&inputs, &out, &command, &options, |_| {}).unwrap();
    write(&b, &subdiv_mesh::shapes::octahedron());
    let third = run(&inputs, &out, &command, &options, |_| {}).unwrap();
    assert_eq!(third.iter().map(|r| r.skipped).collect::<Vec<_>>(), [true, false]);
    // Without resuming, everything runs.
    let fourth = run(&inputs, &out, &command, &options.with_resume(false), |_| {}).unwrap();
    assert!(fourth.iter().all(|r| !r.skipped));
    // A deleted output makes its input run again.
    fs::remove_file(out.join("a.subdivided.obj")).unwrap();
    let fifth = run(&inputs, &out, &command, &options, |_| {}).unwrap();
    assert_eq!(fifth.iter().map(|r| r.skipped).collect::<Vec<_>>(), [false, true]);
}

#[test]
fn shared_stems_write_distinct_files() {
    let tmp = scratch("stems");
    let dir = tmp.path();
    let a = write(&dir.join("a/mesh.obj"), &subdiv_mesh::shapes::cube());
    let b = write(&dir.join("b/mesh.obj"), &subdiv_mesh::shapes::octahedron());
    let out = dir.join("out");
    let command = Command::from_json("subdivide", &serde_json::json!({"scheme": "doo-sabin", "levels": 1})).unwrap();
    let records = run(&[a, b], &out, &command, &BatchOptions::default(), |_| {}).unwrap();
    assert_ne!(records[0].name, records[1].name);
    for r in &records {
        assert!(r.name.starts_with("mesh-"), "{}", r.name);
        assert!(r.succeeded());
    }
    // Cube: 6 faces → Doo-Sabin gives 6 + 12 + 8 faces; octahedron 8 + 12 + 6.
    let faces = |r: &Record| r.report.as_ref().unwrap()["output"]["faces"].as_u64().unwrap();
    assert_eq!((faces(&records[0]), faces(&records[1])), (26, 26));
    assert_ne!(fs::read(&records[0].outputs[0]).unwrap(), fs::read(&records[1].outputs[0]).unwrap());
}

#[test]
fn globs_expand_and_empty_patterns_are_errors() {
    let tmp = scratch("glob");
    let dir = tmp.path();
    write(&dir.join("x/one.obj"), &subdiv_mesh::shapes::cube());
    write(&dir.join("x/y/two.off"), &subdiv_mesh::shapes::cube());
    fs::write(dir.join("x/notes.txt"), "not a mesh").unwrap();
    let all = expand_inputs(&[dir.join("x/**/*")]).unwrap();
    assert_eq!(all, [dir.join("x/one.obj"), dir.join("x/y/two.off")]);
    let e = expand_inputs(&[dir.join("x/*.stl")]).unwrap_err();
    assert!(matches!(e, BatchError::NoMatch { .. }), "{e}");
    // A directory of subdirectories only: the message names the pattern that reaches them.
    fs::remove_file(dir.join("x/one.obj")).unwrap();
    let e = expand_inputs(&[dir.join("x")]).unwrap_err();
    assert!(matches!(e, BatchError::NoMeshInDirectory { subdirectories: true, .. }), "{e}");
    let hint = dir.join("x").join("**").join("*");
    assert!(
        e.to_string().ends_with(&format!("(subdirectories are not searched: '{}' reaches them)", hint.display())),
        "{e}"
    );
    assert_eq!(expand_inputs(&[hint]).unwrap(), [dir.join("x/y/two.off")]);
    fs::create_dir(dir.join("bare")).unwrap();
    let e = expand_inputs(&[dir.join("bare")]).unwrap_err();
    assert_eq!(e.to_string(), format!("{}: no mesh file in this directory", dir.join("bare").display()));
    write(&dir.join("x/one.obj"), &subdiv_mesh::shapes::cube());
    // The same file twice is run once.
    assert_eq!(expand_inputs(&[dir.join("x/one.obj"), dir.join("x/../x/one.obj")]).unwrap().len(), 1);
}

#[test]
fn info_records_the_summary_and_fails_invalid_meshes_with_it() {
    let tmp = scratch("info");
    let dir = tmp.path();
    let cube = write(&dir.join("cube.obj"), &subdiv_mesh::shapes::cube());
    // Three faces on edge (0, 1): non-manifold, described; a face of two corners: no mesh.
    let fin = dir.join("fin.obj");
    fs::write(&fin, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0 -1 0\nf 1 2 3\nf 2 1 4\nf 1 2 5\n").unwrap();
    let two = dir.join("two.obj");
    fs::write(&two, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 2 1\n").unwrap();
    let command = Command::from_json("info", &serde_json::json!({})).unwrap();
    let records = run(&[cube.clone(), fin, two], &dir.join("out"), &command, &BatchOptions::default(), |_| {}).unwrap();
    let summary = crate::info::summarize(&load_mesh(&cube).unwrap(), Some(&cube.display().to_string()));
    assert_eq!(records[0].report.as_ref().unwrap(), &serde_json::to_value(&summary).unwrap());
    assert!(records[0].outputs.is_empty());
    let fin = records[1].report.as_ref().unwrap();
    assert!(records[1].error.is_none(), "{:?}", records[1].error);
    assert_eq!(
        (&fin["manifold"], &fin["non_manifold"]["edges"]),
        (&serde_json::json!(false), &serde_json::json!([[0, 1]]))
    );
    assert_eq!(records[2].error.as_ref().unwrap().kind, ErrorKind::BadInput);
}

#[test]
fn solver_names_become_options() {
    assert_eq!(in_option_terms("use Solver::Minres or Solver::Dense"), "use --solver minres or --solver dense");
    assert_eq!(in_option_terms("nothing to change"), "nothing to change");
}

#[test]
fn a_panicking_job_is_an_error_record() {
    let (outputs, report, error) = guarded(Path::new("m.obj"), || panic!("index out of bounds"));
    assert!(outputs.is_empty() && report.is_none());
    let error = error.unwrap();
    assert_eq!((error.kind, error.exit_code), (ErrorKind::Panic, 1));
    assert_eq!(error.message, "m.obj: internal error (please report it): index out of bounds");
    assert!(!error.kind.is_deterministic(), "a resumed batch retries it");
}
