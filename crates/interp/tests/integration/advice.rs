//! Honest advice: on every fixture (and on the hard cases: valence 2, a
//! singular Catmull-Clark matrix with data outside its range), every method
//! run with its defaults either succeeds — and then `Method::check` said it
//! would — or refuses — and then `Method::check` said so too, and every
//! method its refusal names actually succeeds on that mesh.

use crate::support::{fixtures, load, torus_with_untriangulable_hexagon};
use glam::DVec3;
use std::path::Path;
use subdiv_interp::{interpolate, InterpError, Interpolant, Method, MethodOptions};
use subdiv_mesh::{shapes, EdgeId, Mesh};

/// `method` with its default options.
fn run(method: Method, mesh: &Mesh) -> Result<Interpolant, InterpError> {
    interpolate(mesh, &MethodOptions::new(method))
}

/// Succeeds within the default tolerance, measured from the output by the
/// plain scheme's rules (isolated vertices, which lie on no surface, excluded).
fn succeeds(method: Method, mesh: &Mesh, what: &str) {
    let r = run(method, mesh).unwrap_or_else(|e| panic!("{what}: {} was recommended but fails: {e}", method.name()));
    let t = mesh.topology();
    let flags: Vec<bool> = t.vertices().map(|v| !t.is_isolated(v)).collect();
    let e = r.error(mesh.positions(), &flags, mesh.bbox_diagonal());
    assert!(e.max_rel <= 1e-6 * (1.0 + 1e-9), "{what}: {} error {:e}·d", method.name(), e.max_rel);
}

fn meshes() -> Vec<(String, Mesh)> {
    let mut out = Vec::new();
    for dir in ["quad", "tri", "poly", "open", "canonical"] {
        let mut paths: Vec<_> = std::fs::read_dir(fixtures().join(dir)).unwrap().map(|e| e.unwrap().path()).collect();
        paths.sort();
        for path in paths {
            // The large scans add time, not cases.
            if std::fs::metadata(&path).unwrap().len() > 700_000 {
                continue;
            }
            out.push((format!("{dir}/{}", file_name(&path)), load(&path)));
        }
    }
    // A cube bent so its data leave the range of the singular A.
    let mut bent = shapes::cube().positions().to_vec();
    bent[0] += DVec3::new(0.1, -0.2, 0.05);
    out.push(("bent cube".into(), shapes::cube().with_positions(bent)));
    out.push(("pillow".into(), shapes::pillow()));
    out.push(("torus with an untriangulable hexagon".into(), torus_with_untriangulable_hexagon()));
    let spot = load(&fixtures().join("quad/spot_control_mesh.obj"));
    out.push(("spot, split edges".into(), shapes::split_edges(&spot, &[EdgeId(5), EdgeId(50), EdgeId(51)], 0.05)));
    out
}

fn file_name(p: &Path) -> String {
    p.file_name().unwrap().to_string_lossy().into_owned()
}

/// The methods a refusal's text names.
fn named(message: &str, except: Method) -> Vec<Method> {
    Method::ALL.into_iter().filter(|&m| m != except && message.contains(m.name())).collect()
}

#[test]
fn refusals_name_methods_that_work_and_checks_predict_every_outcome() {
    let mut refusals = 0;
    for (name, mesh) in meshes() {
        for method in Method::ALL {
            let what = format!("{} on {name}", method.name());
            match run(method, &mesh) {
                Ok(_) => {
                    assert_eq!(method.check(&mesh), Ok(()), "{what}: succeeds, so its check must accept it");
                    succeeds(method, &mesh, &what);
                }
                Err(e @ (InterpError::UnsupportedMesh { .. } | InterpError::Unsolvable { .. })) => {
                    refusals += 1;
                    let reason =
                        method.check(&mesh).expect_err(&format!("{what}: refused ({e}) but its check accepts"));
                    assert!(!reason.is_empty());
                    let message = e.to_string();
                    let suggested = named(&message, method);
                    assert_eq!(
                        suggested,
                        subdiv_interp::accepting_methods(&mesh, method),
                        "{what}: the refusal names exactly the methods that accept the mesh: {message}"
                    );
                    for other in suggested {
                        succeeds(other, &mesh, &format!("{what} (recommended {})", other.name()));
                    }
                }
                Err(e) => panic!("{what}: {e}"),
            }
        }
    }
    assert!(refusals >= 2, "cheng refuses the bent cube, deng-wang the hexagon");
}
