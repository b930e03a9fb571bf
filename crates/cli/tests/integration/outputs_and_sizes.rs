//! Issue #14, classes 5 and 6: refinements too large for memory are refused
//! with their true size (never an abort), and a command's outputs are checked
//! before any work and written all together or not at all, with documented
//! exit codes.

use crate::common::{assert_no_panic, fixtures, subdiv, Scratch};
use std::fs;
use std::path::{Path, PathBuf};

/// A fresh scratch directory (removed when the guard drops) with a copy of the cube.
fn with_cube(name: &str) -> (Scratch, PathBuf) {
    let scratch = Scratch::new(name);
    let cube = scratch.path("cube.obj");
    fs::copy(fixtures().join("canonical/cube_quad.obj"), &cube).unwrap();
    (scratch, cube)
}

fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<_> = fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    names.sort();
    names
}

fn run(args: &[&str]) -> (i32, String) {
    let out = subdiv(args);
    assert_no_panic(&out);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    (out.status.code().unwrap_or(-1), stderr)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn an_unusable_output_is_refused_before_any_other_output_is_written() {
    let (scratch, cube) = with_cube("plan");
    let dir = scratch.dir();
    let control = dir.join("control.obj");
    // Unknown extension on --surface: exit 2, -o not written.
    let (code, err) =
        run(&["interpolate", s(&cube), "--method", "cheng", "-o", s(&control), "--surface", s(&dir.join("s.xyz"))]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--surface") && err.contains("s.xyz"), "{err}");
    // A directory that does not exist: exit 4 (cannot write there), nothing written.
    let missing = dir.join("no/such/dir/s.obj");
    let (code, err) = run(&["interpolate", s(&cube), "--method", "cheng", "-o", s(&control), "--surface", s(&missing)]);
    assert_eq!(code, 4, "{err}");
    assert!(err.contains("--surface") && err.contains("no/such/dir"), "{err}");
    // A report that is a device, not a file.
    let (code, err) = run(&["interpolate", s(&cube), "--method", "cheng", "-o", s(&control), "--report", "/dev/full"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("/dev/full") && err.contains("not a regular file"), "{err}");
    assert_eq!(listing(dir), ["cube.obj"], "no output and no temporary");
}

#[test]
fn outputs_never_overwrite_an_input_or_each_other() {
    let (scratch, cube) = with_cube("same");
    let dir = scratch.dir();
    let before = fs::read(&cube).unwrap();
    for flag in ["-o", "--surface", "--report"] {
        let (code, err) = run(&["interpolate", s(&cube), "--method", "cheng", flag, s(&cube)]);
        assert_eq!(code, 2, "{flag}: {err}");
        assert!(err.contains("input"), "{flag}: {err}");
    }
    // The same file through another spelling, a hard link and a symbolic link.
    let dotted = dir.join(".").join("cube.obj");
    fs::hard_link(&cube, dir.join("hard.obj")).unwrap();
    std::os::unix::fs::symlink(&cube, dir.join("soft.obj")).unwrap();
    for alias in [dotted, dir.join("hard.obj"), dir.join("soft.obj")] {
        let (code, err) = run(&["subdivide", s(&cube), "--scheme", "loop", "--levels", "1", "-o", s(&alias)]);
        assert_eq!(code, 2, "{}: {err}", alias.display());
    }
    // A parameter file is an input too.
    let subset = dir.join("subset.txt");
    fs::write(&subset, "0 1 2\n").unwrap();
    let (code, _) =
        run(&["interpolate", s(&cube), "--method", "cheng", "--subset", s(&subset), "--report", s(&subset)]);
    assert_eq!(code, 2);
    // Two outputs naming one file.
    let out = dir.join("out.obj");
    let (code, err) = run(&["interpolate", s(&cube), "--method", "cheng", "-o", s(&out), "--surface", s(&out)]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("both"), "{err}");
    assert_eq!(fs::read(&cube).unwrap(), before);
    assert_eq!(fs::read_to_string(&subset).unwrap(), "0 1 2\n");
}

#[test]
fn every_output_appears_together_when_the_command_succeeds() {
    let (scratch, cube) = with_cube("all");
    let dir = scratch.dir();
    let (control, surface, report) = (dir.join("c.off"), dir.join("s.ply"), dir.join("r.json"));
    let (code, err) = run(&[
        "interpolate",
        s(&cube),
        "--method",
        "cheng",
        "-o",
        s(&control),
        "--surface",
        s(&surface),
        "--levels",
        "2",
        "--report",
        s(&report),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(listing(dir), ["c.off", "cube.obj", "r.json", "s.ply"]);
    let report: serde_json::Value = serde_json::from_str(&fs::read_to_string(&report).unwrap()).unwrap();
    assert!(report["error"]["max_rel"].as_f64().unwrap() <= 1e-6);
}

#[cfg(unix)]
#[test]
fn an_unwritable_directory_is_exit_4_before_any_work() {
    // Root ignores directory permissions: the probe then succeeds and there is nothing to test.
    let (scratch, cube) = with_cube("perm");
    let dir = scratch.dir();
    let locked = dir.join("locked");
    fs::create_dir(&locked).unwrap();
    use std::os::unix::fs::PermissionsExt;
    fs::set_permissions(&locked, fs::Permissions::from_mode(0o555)).unwrap();
    let writable_anyway = fs::write(locked.join("probe"), "").is_ok();
    if !writable_anyway {
        let (code, err) =
            run(&["subdivide", s(&cube), "--scheme", "loop", "--levels", "1", "-o", s(&locked.join("x.obj"))]);
        assert_eq!(code, 4, "{err}");
        assert!(err.contains("cannot create files"), "{err}");
    }
    fs::set_permissions(&locked, fs::Permissions::from_mode(0o755)).unwrap();
}

#[test]
fn refinements_beyond_the_memory_budget_are_refused_with_their_true_size() {
    let (scratch, cube) = with_cube("size");
    let dir = scratch.dir();
    let out = dir.join("o.obj");
    // Cube: 6·4^L faces after L Catmull-Clark steps; each level quotes its own count.
    for (levels, faces) in [(9, "1,572,864"), (11, "25,165,824"), (13, "402,653,184")] {
        let (code, err) = run(&[
            "subdivide",
            s(&cube),
            "--scheme",
            "catmull-clark",
            "--levels",
            &levels.to_string(),
            "--max-memory",
            "64M",
            "-o",
            s(&out),
        ]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(&format!("{faces} faces")) && err.contains("memory budget"), "{levels}: {err}");
    }
    // Far too many for 32-bit ids, whatever the budget.
    let (code, err) =
        run(&["subdivide", s(&cube), "--scheme", "loop", "--levels", "40", "--triangulate", "-o", s(&out)]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("32-bit"), "{err}");
    // interpolate --surface and deng-ma's -o are guarded the same way, after the (cheap) solve.
    let (code, err) = run(&["interpolate", s(&cube), "--method", "cheng", "--surface", s(&out), "--levels", "20"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--surface"), "{err}");
    let (code, err) = run(&["interpolate", s(&cube), "--method", "deng-ma", "-o", s(&out), "--levels", "14"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--output"), "{err}");
    // Within budget: works.
    let (code, err) = run(&[
        "subdivide",
        s(&cube),
        "--scheme",
        "catmull-clark",
        "--levels",
        "3",
        "--max-memory",
        "64M",
        "-o",
        s(&out),
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, err) =
        run(&["subdivide", s(&cube), "--scheme", "loop", "--levels", "1", "--max-memory", "lots", "-o", s(&out)]);
    assert_eq!(code, 2, "{err}");
}

#[test]
fn quiet_prints_nothing_but_errors_and_os_text_appears_once() {
    let (scratch, cube) = with_cube("quiet");
    let dir = scratch.dir();
    let out = subdiv(&["interpolate", s(&cube), "--method", "cheng", "--quiet"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(out.stdout.is_empty() && out.stderr.is_empty(), "{out:?}");
    let loud = subdiv(&["interpolate", s(&cube), "--method", "cheng"]);
    assert!(String::from_utf8_lossy(&loud.stdout).contains("vertices interpolated"));
    let (code, err) = run(&["info", s(&dir.join("missing.obj")), "-q"]);
    assert_eq!(code, 2);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert_eq!(err.matches("No such file").count(), 1, "{err}");
}

#[test]
fn a_closed_stdout_is_not_a_panic() {
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_subdiv"))
        .args(["info", fixtures().join("canonical/cube_quad.obj").to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // the reader goes away before anything is printed
    let out = child.wait_with_output().unwrap();
    assert_no_panic(&out);
    assert!(matches!(out.status.code(), Some(0 | 141)), "{out:?}");
}

#[test]
fn help_documents_the_exit_codes() {
    let out = subdiv(&["--help"]);
    let help = String::from_utf8_lossy(&out.stdout);
    for code in ["0 success", "2 bad input", "3 no acceptable result", "4 an output could not be written"] {
        assert!(help.contains(code), "{code}: {help}");
    }
}

#[test]
fn sigterm_during_a_write_removes_the_temporary() {
    use std::process::{Command, Stdio};
    use std::time::{Duration, Instant};
    let (scratch, cube) = with_cube("sigterm");
    let dir = scratch.dir();
    let out = dir.join("big.obj");
    // ≈ 400k faces: the write takes long enough to be caught in the middle.
    let mut child = Command::new(env!("CARGO_BIN_EXE_subdiv"))
        .args(["subdivide", s(&cube), "--scheme", "catmull-clark", "--levels", "8", "--normals", "-o", s(&out)])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let mut caught = false;
    while start.elapsed() < Duration::from_secs(60) {
        if listing(dir).iter().any(|n| n.ends_with(".tmp")) {
            Command::new("kill").args(["-TERM", &child.id().to_string()]).status().unwrap();
            caught = true;
            break;
        }
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    let status = child.wait().unwrap();
    if caught {
        // Killed while writing (exit 143), or finished just before the signal (exit 0, file complete).
        match status.code() {
            Some(143) => assert_eq!(listing(dir), ["cube.obj"], "temporary removed, no output"),
            Some(0) => assert_eq!(listing(dir), ["big.obj", "cube.obj"]),
            other => panic!("unexpected exit {other:?}"),
        }
    } else {
        eprintln!("the write finished before a temporary was seen; nothing to check");
    }
}
