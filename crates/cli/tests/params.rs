//! `subdiv interpolate` with bad parameter files (`--subset`, `--normals`,
//! `--handles`, `--shape-file`): exit 2, one line on stderr naming the
//! parameter file (never the mesh), nothing written. The details of every
//! message are unit-tested in subdiv-interp's `params` module.

mod common;
use common::{assert_no_panic, fixtures, subdiv};
use serde_json::Value;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("subdiv-params-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn cube() -> String {
    fixtures().join("canonical/cube_quad.obj").to_str().unwrap().to_owned()
}

#[test]
fn bad_parameter_files_exit_2_naming_the_parameter_file() {
    let cases: &[(&str, &str, &str, &str, &str)] = &[
        // (method, flag, file, contents, message after "FILE:")
        ("fan-cheng-lai", "--shape-file", "null.json", "null", "1: shape file sets nothing"),
        ("fan-cheng-lai", "--shape-file", "array.json", "[]", "1: expected a JSON object"),
        ("fan-cheng-lai", "--shape-file", "empty.json", "{}", "1: shape file sets nothing"),
        (
            "fan-cheng-lai",
            "--shape-file",
            "typo.json",
            "{\"default\": 0.5,\n\"facez\": {\"0\": 0.2}}",
            "2: unknown key \"facez\" (allowed: default, faces, groups)",
        ),
        (
            "fan-cheng-lai",
            "--shape-file",
            "faces.json",
            "{\"faces\": [0.2]}",
            "1: \"faces\" must be an object {\"face index\": λ}, not an array",
        ),
        (
            "fan-cheng-lai",
            "--shape-file",
            "lambda.json",
            "{\"faces\": {\"2\": 1.5}}",
            "1: face 2: λ = 1.5 is outside (0, 1)",
        ),
        (
            "fan-cheng-lai",
            "--shape-file",
            "string.json",
            "{\"default\": \"0.5\"}",
            "1: \"default\": \"0.5\" is a string",
        ),
        ("nasri", "--subset", "empty-subset.txt", "# none\n", " the subset is empty"),
        ("nasri", "--subset", "empty-subset.json", "[]", " the subset is empty"),
        ("nasri", "--subset", "twice.txt", "0 1\n2 1\n", "2: vertex 1 is listed twice (first on line 1)"),
        (
            "nasri",
            "--subset",
            "negative.json",
            "[0, -1]",
            "1: -1 is not a vertex index (0-based, non-negative integers)",
        ),
        (
            "nasri",
            "--subset",
            "huge.txt",
            "99999999999999999999",
            "1: vertex 99999999999999999999 is out of range (the mesh has 8 vertices, 0-based)",
        ),
        (
            "zheng-cai",
            "--normals",
            "normals.json",
            "{\"1\": [0, 0, 1],\n\"1\": [0, 1, 0]}",
            "2: vertex 1 is listed twice (first on line 1)",
        ),
        ("zheng-cai", "--normals", "zero-normal.txt", "\n3 0 0 0\n", "2: vertex 3: the normal is zero"),
        ("zheng-cai", "--handles", "handles.txt", "1 2\n1 3\n", "2: vertex 1 is listed twice (first on line 1)"),
        ("zheng-cai", "--handles", "handle-string.json", "{\"1\": \"2\"}", "1: vertex 1: \"2\" is a string"),
    ];
    let out = tmp("control.obj");
    for (method, flag, file, contents, message) in cases {
        let param = tmp(file);
        std::fs::write(&param, contents).unwrap();
        let param = param.to_str().unwrap();
        let result = subdiv(&["interpolate", &cube(), "--method", method, flag, param, "-o", out.to_str().unwrap()]);
        assert_no_panic(&result);
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert_eq!(result.status.code(), Some(2), "{file}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{file}: one line: {stderr}");
        assert!(stderr.contains(&format!("subdiv: error: {param}:{message}")), "{file}: {stderr}");
        assert!(!stderr.contains("cube_quad"), "{file}: names the mesh file: {stderr}");
        assert!(!out.exists(), "{file}: wrote output");
    }
}

/// A named pipe nobody writes to would block `read` forever: refused at once.
#[cfg(unix)]
#[test]
fn fifo_parameter_file_is_refused_without_blocking() {
    let fifo = tmp("subset.fifo");
    let _ = std::fs::remove_file(&fifo);
    assert!(Command::new("mkfifo").arg(&fifo).status().expect("run mkfifo").success());
    let mut child = Command::new(env!("CARGO_BIN_EXE_subdiv"))
        .args(["interpolate", &cube(), "--method", "nasri", "--subset", fifo.to_str().unwrap()])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > Duration::from_secs(60) {
            child.kill().unwrap();
            panic!("subdiv blocked on a FIFO parameter file");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut stderr = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr).unwrap();
    assert_eq!(status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("a FIFO (named pipe), not a regular file"), "{stderr}");
    std::fs::remove_file(&fifo).unwrap();
}

/// A strict shape file still works: OBJ groups, per-face overrides and a BOM.
#[test]
fn shape_file_with_groups_applies() {
    let mesh = tmp("grouped_cube.obj");
    let cube_text = std::fs::read_to_string(cube()).unwrap();
    let (vertices, faces): (Vec<&str>, Vec<&str>) =
        cube_text.lines().filter(|l| !l.starts_with('#')).partition(|l| l.starts_with("v "));
    let grouped = format!("{}\ng top\n{}\ng sides\n{}\n", vertices.join("\n"), faces[0], faces[1..].join("\n"));
    std::fs::write(&mesh, grouped).unwrap();
    let shape = tmp("groups.json");
    std::fs::write(&shape, "\u{FEFF}{\"default\": 0.3,\n \"groups\": {\"top\": 0.8},\n \"faces\": {\"5\": 0.6}}")
        .unwrap();
    let report = tmp("groups-report.json");
    let result = subdiv(&[
        "interpolate",
        mesh.to_str().unwrap(),
        "--method",
        "fan-cheng-lai",
        "--shape-file",
        shape.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
    ]);
    assert_no_panic(&result);
    assert_eq!(result.status.code(), Some(0), "{}", String::from_utf8_lossy(&result.stderr));
    let r: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(r["parameters"]["lambda"]["per_face"], 6);
    assert_eq!(r["parameters"]["lambda"]["min"], 0.3);
    assert_eq!(r["parameters"]["lambda"]["max"], 0.8);
}
