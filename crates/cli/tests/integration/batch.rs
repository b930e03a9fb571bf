//! `subdiv batch`: a record per input, failures isolated with the single
//! command's message and exit code, outputs identical to the single
//! command's, resuming, name collisions, option checks.

use crate::common::{assert_no_panic, fixtures, subdiv, Scratch};
use serde_json::Value;
use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

/// Small good meshes of each kind, and every bad fixture.
fn mixed_inputs() -> Vec<String> {
    let f = fixtures();
    let mut inputs: Vec<String> = ["quad/3torus.off", "quad/cross_quad.off", "poly/cube_poly.off", "tri/eight.off"]
        .iter()
        .map(|p| f.join(p).display().to_string())
        .collect();
    inputs.push(f.join("bad").display().to_string());
    inputs
}

/// Runs a batch; returns the exit code and the records of stdout.
fn batch(args: &[&str]) -> (Option<i32>, Vec<Value>, String) {
    let out = subdiv(args);
    assert_no_panic(&out);
    let stdout = String::from_utf8(out.stdout).unwrap();
    let records = stdout.lines().map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}"))).collect();
    (out.status.code(), records, String::from_utf8_lossy(&out.stderr).into_owned())
}

fn mtimes(dir: &Path) -> BTreeMap<PathBuf, SystemTime> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| (p.clone(), p.metadata().unwrap().modified().unwrap()))
        .collect()
}

/// Every record against the single command on the same input: the same
/// bytes for each output, the same message and exit code for each failure.
fn compare_with_single_command(records: &[Value], single: impl Fn(&str, &Path) -> Vec<String>, scratch: &Scratch) {
    for (i, r) in records.iter().enumerate() {
        assert_eq!(r["index"], i);
        let input = r["input"].as_str().unwrap();
        let dir = scratch.path(&format!("single-{i}"));
        fs::create_dir_all(&dir).unwrap();
        let args = single(input, &dir);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = subdiv(&args);
        assert_no_panic(&out);
        match r["error"].as_object() {
            Some(error) => {
                let stderr = String::from_utf8_lossy(&out.stderr);
                assert_eq!(out.status.code(), Some(error["exit_code"].as_i64().unwrap() as i32), "{input}: {stderr}");
                let message = error["message"].as_str().unwrap();
                assert!(stderr.contains(&format!("subdiv: error: {message}\n")), "{input}:\n{stderr}\nvs {message}");
                assert!(r["outputs"].as_array().unwrap().is_empty());
            }
            None => {
                assert_eq!(out.status.code(), Some(0), "{input}: {}", String::from_utf8_lossy(&out.stderr));
                let outputs = r["outputs"].as_array().unwrap();
                assert!(!outputs.is_empty());
                for output in outputs {
                    let batch_file = Path::new(output.as_str().unwrap());
                    let suffix = batch_file.file_name().unwrap().to_string_lossy();
                    let suffix = suffix.split_once('.').unwrap().1;
                    let single_file = dir.join(format!("single.{suffix}"));
                    assert!(
                        fs::read(batch_file).unwrap() == fs::read(&single_file).unwrap(),
                        "{} differs from {}",
                        batch_file.display(),
                        single_file.display()
                    );
                }
            }
        }
    }
}

#[test]
fn interpolate_over_the_fixtures_matches_the_single_command() {
    let scratch = Scratch::new("batch-interp");
    let out_dir = scratch.path("out");
    let inputs = mixed_inputs();
    let mut args = vec!["batch", "interpolate"];
    args.extend(inputs.iter().map(String::as_str));
    let out = out_dir.display().to_string();
    args.extend(["--out-dir", &out, "--method", "cheng", "--levels", "1", "--jobs", "2"]);
    let (code, records, stderr) = batch(&args);
    let bad = fs::read_dir(fixtures().join("bad")).unwrap().count();
    assert_eq!(records.len(), 4 + bad, "{stderr}");
    assert_eq!(code, Some(5), "some failed: {stderr}");
    assert!(records[..4].iter().all(|r| r["error"].is_null()), "{stderr}");
    assert!(records.iter().filter(|r| !r["error"].is_null()).count() > bad / 2);
    compare_with_single_command(
        &records,
        |input, dir| {
            let ext = Path::new(input).extension().unwrap().to_string_lossy().to_string();
            let control = dir.join(format!("single.control.{ext}")).display().to_string();
            let surface = dir.join(format!("single.surface.{ext}")).display().to_string();
            ["interpolate", input, "--method", "cheng", "-o", &control, "--surface", &surface, "--levels", "1"]
                .map(String::from)
                .to_vec()
        },
        &scratch,
    );
    // The record file is the line printed.
    let stored: Value = serde_json::from_str(&fs::read_to_string(out_dir.join("3torus.record.json")).unwrap()).unwrap();
    assert_eq!(stored, records[0]);
    assert_eq!(records[0]["report"]["method"], "cheng");
}

#[test]
fn subdivide_and_info_match_the_single_commands() {
    let scratch = Scratch::new("batch-subd");
    let out_dir = scratch.path("out").display().to_string();
    let inputs = mixed_inputs();
    let mut args = vec!["batch", "subdivide"];
    args.extend(inputs.iter().map(String::as_str));
    args.extend(["--out-dir", &out_dir, "--scheme", "loop", "--levels", "1", "--triangulate", "--normals"]);
    let (_, records, _) = batch(&args);
    compare_with_single_command(
        &records,
        |input, dir| {
            let ext = Path::new(input).extension().unwrap().to_string_lossy().to_string();
            let o = dir.join(format!("single.subdivided.{ext}")).display().to_string();
            ["subdivide", input, "--scheme", "loop", "--levels", "1", "--triangulate", "--normals", "-o", &o]
                .map(String::from)
                .to_vec()
        },
        &scratch,
    );

    let info_dir = scratch.path("info").display().to_string();
    let mut args = vec!["batch", "info"];
    args.extend(inputs.iter().map(String::as_str));
    args.extend(["--out-dir", &info_dir]);
    let (_, records, _) = batch(&args);
    for r in &records {
        let single = subdiv(&["info", r["input"].as_str().unwrap(), "--json"]);
        let stdout = String::from_utf8_lossy(&single.stdout);
        if let Ok(summary) = serde_json::from_str::<Value>(&stdout) {
            assert_eq!(r["report"], summary, "{}", r["input"]);
        } else {
            assert!(r["report"].is_null(), "a file no reader takes has no summary");
        }
        assert_eq!(r["error"].is_null(), single.status.success(), "{}", r["input"]);
    }
}

#[test]
fn a_second_run_skips_everything_and_a_touched_input_reruns_alone() {
    let scratch = Scratch::new("batch-resume");
    let input_dir = scratch.path("in");
    fs::create_dir_all(&input_dir).unwrap();
    for name in ["quad/3torus.off", "poly/cube_poly.off", "bad/nonmanifold_edge_3faces.obj"] {
        let from = fixtures().join(name);
        fs::copy(&from, input_dir.join(from.file_name().unwrap())).unwrap();
    }
    let out_dir = scratch.path("out");
    let (input, out) = (input_dir.display().to_string(), out_dir.display().to_string());
    let args = ["batch", "interpolate", &input, "--out-dir", &out, "--method", "zheng-cai", "--levels", "1"];
    let (code, first, _) = batch(&args);
    assert_eq!(code, Some(5));
    assert_eq!(first.len(), 3);
    assert!(first.iter().all(|r| r["skipped"] == false));
    // Only the bad mesh failed: the jobs running at once do not trip over each other's checks.
    assert_eq!(first.iter().filter(|r| r["error"].is_null()).count(), 2, "{first:?}");
    let before = mtimes(&out_dir);
    std::thread::sleep(Duration::from_millis(20));

    let (code, second, _) = batch(&args);
    assert_eq!(code, Some(5), "the failure is still one");
    assert!(second.iter().all(|r| r["skipped"] == true), "{second:?}");
    for (a, b) in first.iter().zip(&second) {
        let mut b = b.clone();
        b["skipped"] = Value::Bool(false);
        assert_eq!(*a, b);
    }
    assert_eq!(mtimes(&out_dir), before, "no file rewritten");

    // Touch one input: it alone runs again.
    let touched = input_dir.join("cube_poly.off");
    fs::File::options().append(true).open(&touched).unwrap().set_modified(SystemTime::now()).unwrap();
    let (_, third, _) = batch(&args);
    let skipped: Vec<(&str, bool)> =
        third.iter().map(|r| (r["name"].as_str().unwrap(), r["skipped"].as_bool().unwrap())).collect();
    assert_eq!(skipped, [("3torus", true), ("cube_poly", false), ("nonmanifold_edge_3faces", true)]);

    // --no-resume runs everything.
    let mut all = args.to_vec();
    all.push("--no-resume");
    let (_, fourth, _) = batch(&all);
    assert!(fourth.iter().all(|r| r["skipped"] == false));
}

#[test]
fn inputs_sharing_a_stem_get_distinct_outputs() {
    let scratch = Scratch::new("batch-names");
    let a = scratch.path("a");
    let b = scratch.path("b");
    fs::create_dir_all(&a).unwrap();
    fs::create_dir_all(&b).unwrap();
    fs::copy(fixtures().join("quad/3torus.off"), a.join("mesh.off")).unwrap();
    fs::copy(fixtures().join("poly/cube_poly.off"), b.join("mesh.off")).unwrap();
    let out = scratch.path("out").display().to_string();
    let (pa, pb) = (a.join("mesh.off").display().to_string(), b.join("mesh.off").display().to_string());
    let (code, records, stderr) =
        batch(&["batch", "subdivide", &pa, &pb, "--out-dir", &out, "--scheme", "catmull-clark", "--levels", "1"]);
    assert_eq!(code, Some(0), "{stderr}");
    let names: Vec<&str> = records.iter().map(|r| r["name"].as_str().unwrap()).collect();
    assert_ne!(names[0], names[1]);
    assert!(names.iter().all(|n| n.starts_with("mesh-")), "{names:?}");
    let output = |r: &Value| fs::read(r["outputs"][0].as_str().unwrap()).unwrap();
    assert_ne!(output(&records[0]), output(&records[1]));
    // The same names on a second run: everything resumes.
    let (_, again, _) =
        batch(&["batch", "subdivide", &pa, &pb, "--out-dir", &out, "--scheme", "catmull-clark", "--levels", "1"]);
    assert!(again.iter().all(|r| r["skipped"] == true));
}

#[test]
fn misspelled_or_misapplied_options_are_refused_before_anything_runs() {
    let scratch = Scratch::new("batch-options");
    let out = scratch.path("out");
    let o = out.display().to_string();
    let input = fixtures().join("quad/3torus.off").display().to_string();
    for (args, expected) in [
        (vec!["--method", "chen"], "unknown method 'chen'"),
        (vec!["--method", "nasri", "--scheme", "loop"], "--scheme applies to --method cheng and --method fair only"),
        (vec!["--method", "cheng", "--omega", "0.5"], "--omega applies to --method deng-ma only"),
        (vec!["--method", "cheng", "--limit"], "unknown option `limit`"),
        (vec!["--method", "cheng", "--boundary", "edges"], "unknown boundary interpolation `edges`"),
        (vec!["--tol", "1e-9"], "missing option `method`"),
        (vec!["--method", "cheng", "--tolerance", "1e-9"], "--tolerance"),
    ] {
        let mut all = vec!["batch", "interpolate", &input, "--out-dir", &o];
        all.extend(args);
        let run = subdiv(&all);
        assert_no_panic(&run);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{all:?}: {stderr}");
        assert!(stderr.contains(expected), "{all:?}: {stderr}");
        assert!(run.stdout.is_empty());
    }
    assert!(!out.exists(), "nothing ran");
    let run = subdiv(&["batch", "info", &fixtures().join("quad/*.stl").display().to_string(), "--out-dir", &o]);
    assert_eq!(run.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&run.stderr).contains("no mesh file matches"));
}

#[test]
fn globs_select_mesh_files_and_all_good_exits_zero() {
    let scratch = Scratch::new("batch-glob");
    let out = scratch.path("out").display().to_string();
    let pattern = fixtures().join("quad/*.off").display().to_string();
    let (code, records, stderr) = batch(&["batch", "info", &pattern, "--out-dir", &out, "--quiet"]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stderr.is_empty(), "--quiet: {stderr}");
    let mut expected: Vec<String> = fs::read_dir(fixtures().join("quad"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "off"))
        .map(|p| p.display().to_string())
        .collect();
    expected.sort();
    let got: Vec<&str> = records.iter().map(|r| r["input"].as_str().unwrap()).collect();
    assert_eq!(got, expected);
}
