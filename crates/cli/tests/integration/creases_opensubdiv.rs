//! The acceptance check of interpolation with tags against OpenSubdiv
//! (`fixtures/peer/creases-interpolation/README.md`): OpenSubdiv's limit
//! positions of the control meshes `subdiv interpolate` writes for tagged
//! inputs — evaluated by OpenSubdiv from the written files and their `t`
//! lines alone — are the input vertices; and the command still writes those
//! control meshes.

use crate::common::{assert_no_panic, fixtures, read, subdiv, Scratch};
use std::path::{Path, PathBuf};
use subdiv_mesh::DVec3;

fn read_points(path: &Path) -> Vec<DVec3> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let c: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            DVec3::new(c[0], c[1], c[2])
        })
        .collect()
}

fn diagonal(points: &[DVec3]) -> f64 {
    let (lo, hi) = points.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    lo.distance(hi)
}

/// (case, method, flags, control file, OpenSubdiv's limit file).
fn cases() -> Vec<(String, &'static str, Vec<&'static str>, &'static str, &'static str)> {
    let root = fixtures().join("peer/creases-interpolation");
    let mut out = Vec::new();
    for entry in std::fs::read_dir(&root).unwrap() {
        let dir = entry.unwrap().path();
        if !dir.is_dir() {
            continue;
        }
        let name = dir.file_name().unwrap().to_string_lossy().to_string();
        let flags = match name.as_str() {
            n if n.ends_with("-chaikin") => vec!["--crease-method", "chaikin"],
            n if n.ends_with("-edge-only") => vec!["--boundary", "edge-only"],
            _ => vec![],
        };
        let methods = [
            ("cheng", vec![], "cheng-control.obj", "opensubdiv-catmull-clark-limit.txt"),
            ("deng-wang", vec!["--beta", "loop"], "deng-wang-control.obj", "opensubdiv-loop-origbeta-limit.txt"),
        ];
        for (method, extra, control, limit) in methods {
            if dir.join(control).exists() {
                out.push((name.clone(), method, [flags.clone(), extra].concat(), control, limit));
            }
        }
    }
    out.sort();
    assert!(out.len() >= 8, "the fixtures are missing");
    out
}

fn case_dir(name: &str) -> PathBuf {
    fixtures().join("peer/creases-interpolation").join(name)
}

#[test]
fn opensubdiv_limits_of_the_written_control_meshes_are_the_input_vertices() {
    for (name, method, _, control, limit) in cases() {
        let dir = case_dir(&name);
        let input = read(&dir.join("input.obj")).positions;
        assert!(!read(&dir.join(control)).tags.creases.is_empty() || name.contains("corners"), "{name}: no tags");
        let theirs = read_points(&dir.join(limit));
        assert!(theirs.len() >= input.len(), "{name}");
        let d = diagonal(&input);
        let gap = input.iter().zip(&theirs).map(|(p, l)| p.distance(*l)).fold(0.0, f64::max) / d;
        assert!(gap <= 1e-9, "{name}, {method}: OpenSubdiv's limit misses the data by {gap:e}·d");
    }
}

#[test]
fn interpolate_still_writes_the_checked_control_meshes() {
    let scratch = Scratch::new("creases-osd");
    for (name, method, flags, control, _) in cases() {
        let dir = case_dir(&name);
        let written = scratch.path(&format!("{name}-{control}"));
        let input = dir.join("input.obj");
        let mut args = vec!["interpolate", input.to_str().unwrap(), "--method", method, "--tol", "1e-12"];
        args.extend(&flags);
        args.extend(["-o", written.to_str().unwrap()]);
        let run = subdiv(&args);
        assert_no_panic(&run);
        assert_eq!(run.status.code(), Some(0), "{name}: {}", String::from_utf8_lossy(&run.stderr));
        let (ours, fixture) = (read(&written), read(&dir.join(control)));
        assert_eq!(ours.faces, fixture.faces, "{name}, {method}");
        let sharp = |t: &subdiv_mesh::TagList| (t.creases.clone(), t.corners.clone(), t.holes.clone());
        assert_eq!(sharp(&ours.tags), sharp(&fixture.tags), "{name}, {method}: the tags written");
        // The options the surface needs are written as OpenSubdiv's option tags (crease method
        // with semi-sharp tags, boundary option on open meshes), which the fixtures predate.
        let semi = ours.tags.creases.iter().map(|t| t.sharpness).chain(ours.tags.corners.iter().map(|t| t.sharpness));
        let has_semi = semi.into_iter().any(|s| s > 0.0 && s < 10.0);
        assert_eq!(ours.tags.options.crease_method.is_some(), has_semi, "{name}, {method}");
        let d = diagonal(&fixture.positions);
        let gap = ours.positions.iter().zip(&fixture.positions).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max) / d;
        assert!(gap <= 1e-9, "{name}, {method}: the control mesh moved by {gap:e}·d since the fixture was made");
    }
}
