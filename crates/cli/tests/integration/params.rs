//! `subdiv interpolate` with bad parameter files (`--subset`, `--normals`,
//! `--handles`, `--shape-file`): exit 2, one line on stderr naming the
//! parameter file (never the mesh), nothing written. The details of every
//! message are unit-tested in subdiv-interp's `params` module (the text) and
//! subdiv-io's `text_file` module (the file). The other text inputs
//! (`evaluate --at`, `project --points` .xyz) are read the same way: a FIFO or
//! a file in another encoding is refused for every one of them.

use crate::common::{assert_no_panic, fixtures, run_bounded, subdiv, Scratch};
use serde_json::Value;
use std::path::Path;
use std::process::Command;
use std::time::Duration;

fn cube() -> String {
    fixtures().join("canonical/cube_quad.obj").to_str().unwrap().to_owned()
}

#[test]
fn bad_parameter_files_exit_2_naming_the_parameter_file() {
    let scratch = Scratch::new("params");
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
    let out = scratch.path("control.obj");
    for (method, flag, file, contents, message) in cases {
        let param = scratch.path(file);
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

/// The command lines that read `file` as a text input other than the mesh:
/// the parameter files of `interpolate`, `evaluate --at`, `project --points`
/// (`.xyz`). Each names the flag, for the messages.
/// `out` is the output's path without an extension (`.obj` for the
/// control mesh, `.txt` for the others).
fn text_inputs(file: &str, out: &Path) -> Vec<(&'static str, Vec<String>)> {
    let cube = cube();
    let args = |flag: &'static str, words: &[&str]| {
        let mut v: Vec<String> = words.iter().map(|w| w.to_string()).collect();
        let ext = if words[0] == "interpolate" { "obj" } else { "txt" };
        v.extend(["-o".to_string(), out.with_extension(ext).to_str().unwrap().to_string()]);
        (flag, v)
    };
    vec![
        args("--subset", &["interpolate", &cube, "--method", "nasri", "--subset", file]),
        args("--normals", &["interpolate", &cube, "--method", "zheng-cai", "--normals", file]),
        args("--handles", &["interpolate", &cube, "--method", "zheng-cai", "--handles", file]),
        args("--shape-file", &["interpolate", &cube, "--method", "fan-cheng-lai", "--shape-file", file]),
        args("--at", &["evaluate", &cube, "--scheme", "catmull-clark", "--at", file]),
        args("--points", &["project", &cube, "--scheme", "catmull-clark", "--points", file]),
    ]
}

/// A named pipe nobody writes to would block `read` forever: every text
/// input (parameter files, `--at`, `--points` .xyz) is refused at once,
/// exit 2, naming the FIFO.
#[cfg(unix)]
#[test]
fn a_fifo_as_any_text_input_is_refused_without_blocking() {
    let scratch = Scratch::new("params");
    let fifo = scratch.path("input.fifo.xyz");
    let _ = std::fs::remove_file(&fifo);
    assert!(Command::new("mkfifo").arg(&fifo).status().expect("run mkfifo").success());
    let out = scratch.path("fifo-out");
    for (flag, args) in text_inputs(fifo.to_str().unwrap(), &out) {
        let (code, stderr) = run_bounded(&args, flag, Duration::from_secs(60));
        assert!(!stderr.contains("panicked"), "{flag}: {stderr}");
        assert_eq!(code, Some(2), "{flag}: {stderr}");
        assert!(stderr.contains("not a regular file (it is a FIFO)"), "{flag}: {stderr}");
        assert!(stderr.contains("input.fifo.xyz"), "{flag}: does not name the file: {stderr}");
        assert!(!out.with_extension("obj").exists() && !out.with_extension("txt").exists(), "{flag}: wrote output");
    }
    std::fs::remove_file(&fifo).unwrap();
}

/// A text input in the wrong encoding is one clean line (exit 2) naming the
/// file and what to do, for every flag: UTF-16 with its BOM, Latin-1 bytes,
/// binary data.
#[test]
fn a_text_input_in_another_encoding_is_a_clean_error() {
    let scratch = Scratch::new("params");
    let out = scratch.path("encoding-out");
    let cases: [(&str, &[u8], &str); 3] = [
        ("utf16.xyz", b"\xFF\xFE0\x00 \x001\x00\n\x00", "UTF-16 text is not supported; save the file as UTF-8"),
        ("latin1.xyz", b"0 1\n# caf\xE9\n", ":2: not UTF-8 text (byte 0xE9); save the file as UTF-8"),
        ("binary.xyz", b"0 1 2\n\x00\x01\x02", ":2: NUL byte: binary data, not a text file"),
    ];
    for (name, bytes, message) in cases {
        let file = scratch.path(name);
        std::fs::write(&file, bytes).unwrap();
        for (flag, args) in text_inputs(file.to_str().unwrap(), &out) {
            let result = Command::new(env!("CARGO_BIN_EXE_subdiv")).args(&args).output().unwrap();
            assert_no_panic(&result);
            let stderr = String::from_utf8_lossy(&result.stderr);
            assert_eq!(result.status.code(), Some(2), "{name} as {flag}: {stderr}");
            assert_eq!(stderr.trim_end().lines().count(), 1, "{name} as {flag}: one line: {stderr}");
            assert!(stderr.contains(&format!("{}", file.display())), "{name} as {flag}: {stderr}");
            assert!(stderr.contains(message), "{name} as {flag}: {stderr}");
            let wrote = out.with_extension("obj").exists() || out.with_extension("txt").exists();
            assert!(!wrote, "{name} as {flag}: wrote output");
        }
    }
}

/// A strict shape file still works: OBJ groups, per-face overrides and a BOM.
#[test]
fn shape_file_with_groups_applies() {
    let scratch = Scratch::new("params");
    let mesh = scratch.path("grouped_cube.obj");
    let cube_text = std::fs::read_to_string(cube()).unwrap();
    let (vertices, faces): (Vec<&str>, Vec<&str>) =
        cube_text.lines().filter(|l| !l.starts_with('#')).partition(|l| l.starts_with("v "));
    let grouped = format!("{}\ng top\n{}\ng sides\n{}\n", vertices.join("\n"), faces[0], faces[1..].join("\n"));
    std::fs::write(&mesh, grouped).unwrap();
    let shape = scratch.path("groups.json");
    std::fs::write(&shape, "\u{FEFF}{\"default\": 0.3,\n \"groups\": {\"top\": 0.8},\n \"faces\": {\"5\": 0.6}}")
        .unwrap();
    let report = scratch.path("groups-report.json");
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
