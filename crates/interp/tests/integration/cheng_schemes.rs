//! Cheng's interpolation with Loop and √3 as the control scheme
//! (`ChengOptions::with_scheme`, issue #39): on closed and open triangle
//! meshes with interior valences 3 to 8, corners and (Loop) creases, the
//! control mesh's limit points pass through the data within 10⁻⁶·d, measured
//! two ways that never read the solver's matrix or residual — the stencil
//! crate's limit points of the control mesh as written to a file and read
//! back, and two levels of refinement followed by the limit masks of the
//! refined mesh. Also: the positive definiteness the automatic choice of
//! CG rests on (LDLᵀ's inertia), the solvers picked, typed refusals that
//! agree with `Method::check_with_scheme`, and Catmull-Clark unchanged.

use crate::support;

use crate::support::tagged::{tagged, torus_case, INF};
use crate::support::{bumpy, fixture};
use glam::DVec3;
use std::collections::BTreeSet;
use subdiv_interp::{
    cheng, ChengOptions, InterpError, Interpolant, LoopBeta, Method, Parameter, Report, Scheme, SolverChoice,
    SurfaceOptions,
};
use subdiv_mesh::{shapes, FaceList, Mesh, PolygonSoup, Tags};
use subdiv_solve::Solver;
use subdiv_stencil::{BoundaryInterpolation, Options};

const TOL: f64 = 1e-6;

/// A fan of n triangles round an apex of valence n (a pyramid without its
/// base): an open mesh whose interior vertex has valence n.
fn open_fan(n: usize) -> Mesh {
    let pyramid = shapes::pyramid(n);
    let apex = n as u32;
    let faces: Vec<Vec<u32>> =
        pyramid.topology().faces().iter().filter(|f| f.contains(&apex)).map(<[u32]>::to_vec).collect();
    let mut p = pyramid.positions().to_vec();
    p.iter_mut().filter(|q| q.z == 0.0).for_each(|q| q.z = 0.1 * q.x * q.y); // not planar
    Mesh::from_soup(PolygonSoup::new(p, FaceList::from_faces(faces))).unwrap().0
}

fn triangulated(mesh: &Mesh) -> Mesh {
    subdiv_mesh::triangulate(mesh).unwrap().mesh
}

/// A bumpy open triangle grid (two one-face boundary vertices: corners
/// under `edge-and-corner`).
fn grid() -> Mesh {
    let g = shapes::triangle_grid(7, 5);
    let p = g.positions().iter().map(|&p| DVec3::new(p.x, p.y, 0.4 * (1.3 * p.x).sin() * (0.9 * p.y).cos())).collect();
    bumpy(g.with_positions(p), 0.01, 3)
}

fn closed_meshes() -> Vec<(String, Mesh)> {
    let mut out = vec![
        ("tetrahedron".to_string(), bumpy(shapes::tetrahedron(), 0.05, 1)),
        ("octahedron".to_string(), bumpy(shapes::octahedron(), 0.05, 2)),
        ("icosahedron".to_string(), bumpy(shapes::icosahedron(), 0.05, 3)),
        ("icosphere_2".to_string(), bumpy(fixture("canonical/icosphere_2.obj"), 0.01, 4)),
        ("triangle torus".to_string(), bumpy(triangulated(&shapes::torus(12, 8)), 0.02, 5)),
    ];
    for n in [6, 7, 8] {
        out.push((format!("bipyramid {n}"), bumpy(triangulated(&shapes::pyramid(n)), 0.05, n as u64)));
    }
    out
}

fn open_meshes() -> Vec<(String, Mesh)> {
    let mut out =
        vec![("triangle grid".to_string(), grid()), ("hemisphere".to_string(), fixture("open/hemisphere.off"))];
    for n in 3..=8 {
        out.push((format!("open fan {n}"), bumpy(open_fan(n), 0.02, 10 + n as u64)));
    }
    out
}

/// The schemes under test.
fn schemes() -> [Scheme; 3] {
    [Scheme::Sqrt3, Scheme::Loop(LoopBeta::Warren), Scheme::Loop(LoopBeta::Loop)]
}

fn run(mesh: &Mesh, scheme: Scheme, surface: SurfaceOptions) -> Result<Interpolant, InterpError> {
    let options = ChengOptions::default().with_scheme(scheme).unwrap().with_surface(surface);
    cheng::interpolate(mesh, &options)
}

/// max_i |L_i − P_i| / d over `limits` (the first vertices' limit points).
fn max_rel(limits: &[DVec3], data: &Mesh) -> f64 {
    let d = data.bbox_diagonal();
    data.positions().iter().zip(limits).map(|(p, l)| p.distance(*l) / d).fold(0.0, f64::max)
}

/// The two independent measures of the module docs, on `result`'s control
/// mesh as written (OBJ keeps f64 digits and the tags). At a dart too: its
/// limit row is its exact limit (`DartLimit::Exact`), the same point at
/// every level.
fn independent_errors(name: &str, result: &Interpolant, data: &Mesh, surface: SurfaceOptions) -> (f64, f64) {
    let options: Options = surface.for_scheme(result.scheme);
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cheng_schemes");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{}-{}.obj", name.replace(' ', "_"), result.scheme));
    subdiv_io::write_mesh(&path, &result.control, &Default::default()).unwrap();
    let written = subdiv_io::load_mesh(&path).unwrap();
    assert_eq!(written.tags().to_list(written.topology()), result.control.tags().to_list(result.control.topology()));
    let t = written.topology();
    let limits = subdiv_stencil::limit_points_with_options(t, written.tags(), options, written.positions())
        .unwrap()
        .expect("an approximating scheme has limit masks");
    let from_file = max_rel(&limits, data);
    // Two levels of the scheme's refinement rules, then the refined mesh's
    // limit masks; the old vertices keep their indices in both splits.
    let refined = subdiv_stencil::subdivide(&written, options, 2, false).unwrap();
    let fine =
        subdiv_stencil::limit_points_with_options(refined.topology(), refined.tags(), options, refined.positions())
            .unwrap()
            .unwrap();
    (from_file, max_rel(&fine[..data.positions().len()], data))
}

fn interior_valences(mesh: &Mesh) -> BTreeSet<usize> {
    let t = mesh.topology();
    t.vertices().filter(|&v| !t.is_boundary_vertex(v)).map(|v| t.valence(v)).collect()
}

#[test]
fn the_limit_surface_passes_through_the_data_on_closed_and_open_meshes() {
    let (mut closed, mut open) = (BTreeSet::new(), BTreeSet::new());
    for (name, mesh) in closed_meshes().into_iter().chain(open_meshes()) {
        let is_closed = mesh.topology().is_closed();
        let valences = interior_valences(&mesh);
        if is_closed { &mut closed } else { &mut open }.extend(valences);
        for scheme in schemes() {
            let what = format!("{name}, cheng --scheme {scheme} ({scheme:?})");
            let result = run(&mesh, scheme, SurfaceOptions::default()).unwrap_or_else(|e| panic!("{what}: {e}"));
            assert_eq!(result.scheme, scheme, "{what}");
            assert_eq!(result.method, Method::Cheng);
            assert_eq!(result.control.topology().faces(), mesh.topology().faces(), "{what}: the input's topology");
            let (from_file, refined) = independent_errors(&name, &result, &mesh, SurfaceOptions::default());
            assert!(from_file <= TOL && refined <= TOL * (1.0 + 1e-9), "{what}: {from_file:e}, {refined:e}");
            // The solve did something: the control mesh is not the data.
            assert!(max_rel(result.control.positions(), &mesh) > 1e-4, "{what}");
            // Symmetric positive definite blocks: CG, by the automatic choice.
            assert_eq!(result.solve.as_ref().unwrap().solver, "cg-jacobi", "{what}");
            let report = Report::new(&mesh, &result, result.error_all(&mesh));
            assert_eq!(report.control_scheme.as_deref(), Some(scheme.name()), "{what}");
            let json = serde_json::to_value(&report).unwrap();
            assert_eq!(json["control_scheme"], scheme.name());
            assert_eq!(json["method"], "cheng");
        }
    }
    assert!((3..=8).all(|n| closed.contains(&n)), "closed valences {closed:?}");
    assert!((3..=8).all(|n| open.contains(&n)), "open valences {open:?}");
}

/// √3's corners: a corner tag on a boundary vertex with two faces, under
/// both boundary options (edge-only: the one-face vertices follow the
/// boundary curve). The control mesh keeps the tag and the corners their
/// data.
#[test]
fn sqrt3_corners_and_boundary_options() {
    let mesh = grid();
    let t = mesh.topology();
    let corner = t.vertices().find(|&v| t.is_boundary_vertex(v) && t.vertex_face_count(v) == 3).unwrap();
    let mesh = tagged(&mesh, &[], &[(corner.0, INF)]);
    for boundary in [BoundaryInterpolation::EdgeAndCorner, BoundaryInterpolation::EdgeOnly] {
        let surface = SurfaceOptions::default().with_boundary(boundary);
        for scheme in schemes() {
            let what = format!("{scheme} with a corner tag, {boundary:?}");
            let result = run(&mesh, scheme, surface).unwrap_or_else(|e| panic!("{what}: {e}"));
            let (from_file, refined) = independent_errors("grid corner", &result, &mesh, surface);
            assert!(from_file <= TOL && refined <= TOL * (1.0 + 1e-9), "{what}: {from_file:e}, {refined:e}");
            assert_eq!(result.control.positions()[corner.index()], mesh.positions()[corner.index()], "{what}");
            assert!(result.control.tags().vertex_values()[corner.index()] >= INF, "{what}");
        }
    }
}

/// Loop with creases: an infinitely sharp ring, a dart, semi-sharp values
/// (composed rows: GMRES for the block they make nonsymmetric).
#[test]
fn loop_with_creases_and_darts() {
    for s in [INF, 2.5] {
        let mesh = triangulated(&torus_case(s));
        assert!(!mesh.tags().is_empty());
        let result = run(&mesh, Scheme::Loop(LoopBeta::Warren), SurfaceOptions::default()).unwrap();
        // The dart of `torus_case` (its two ends) is measured like every other vertex.
        let (from_file, refined) = independent_errors(&format!("torus crease {s}"), &result, &mesh, Default::default());
        assert!(from_file <= TOL && refined <= TOL * (1.0 + 1e-9), "sharpness {s}: {from_file:e}, {refined:e}");
        assert!(result.solve.as_ref().unwrap().solver.contains("gmres"), "{:?}", result.solve);
    }
}

/// Sylvester's law of inertia: LDLᵀ's negative pivots count the negative
/// eigenvalues of S (congruent to D^½SD^½, similar to A). None on every
/// closed mesh, valences 3 to 8: the positive definiteness of the module
/// docs' proof. And progressive iteration (spec(A) ⊂ (0, 1]) converges.
#[test]
fn the_matrices_are_positive_definite_and_progressive_iteration_converges() {
    for (name, mesh) in closed_meshes() {
        for scheme in schemes() {
            let options =
                |solver| ChengOptions::default().with_scheme(scheme).unwrap().with_solver(SolverChoice::Use(solver));
            let ldl = cheng::interpolate(&mesh, &options(Solver::Ldl)).unwrap();
            assert_eq!(ldl.solve.as_ref().unwrap().negative_pivots, Some(0), "{name}, {scheme}");
            let pia = cheng::interpolate(&mesh, &options(Solver::Pia)).unwrap();
            assert!(pia.error_all(&mesh).max_rel <= TOL, "{name}, {scheme}");
        }
    }
}

fn invalid_scheme(e: InterpError) -> String {
    match e {
        InterpError::InvalidParameter { parameter: Parameter::Scheme, reason } => reason,
        other => panic!("not an invalid --scheme: {other}"),
    }
}

#[test]
fn refusals_are_typed_and_checks_predict_them() {
    // Schemes without a limit matrix on the control mesh's vertices, naming the method that takes them.
    let reason = invalid_scheme(ChengOptions::default().with_scheme(Scheme::DooSabin).unwrap_err());
    assert!(reason.contains("--method nasri") && reason.contains("sqrt3"), "{reason}");
    let deng_ma: Scheme = "deng-ma".parse().unwrap();
    let reason = invalid_scheme(ChengOptions::default().with_scheme(deng_ma).unwrap_err());
    assert!(reason.contains("--method deng-ma"), "{reason}");
    // Set on the field, the same refusal from `interpolate`.
    let mut options = ChengOptions::default();
    options.scheme = Scheme::DooSabin;
    invalid_scheme(cheng::interpolate(&shapes::icosahedron(), &options).unwrap_err());

    // Meshes the triangle schemes cannot take.
    let ico = shapes::icosahedron();
    let t = ico.topology();
    let creased = ico.clone().with_tags(Tags::from_arrays(t, vec![INF; t.edge_count()], Vec::new()).unwrap());
    let pillow = PolygonSoup::new(
        vec![DVec3::ZERO, DVec3::X, DVec3::Y],
        FaceList::from_faces(vec![vec![0, 1, 2], vec![0, 2, 1]]),
    );
    let pillow = Mesh::from_soup(pillow).map(|(m, _)| m).ok();
    assert!(pillow.is_some(), "a closed pair of triangles is a valid mesh");
    let mut cases: Vec<(&str, Mesh, Scheme, &[&str])> = vec![
        ("cube", shapes::cube(), Scheme::Sqrt3, &["triangles", "deng-wang", "--triangulate", "catmull-clark"]),
        ("cube", shapes::cube(), Scheme::Loop(LoopBeta::Warren), &["triangles", "deng-wang", "--triangulate"]),
        ("creased icosahedron", creased.clone(), Scheme::Sqrt3, &["sharpness", "--scheme loop"]),
    ];
    if let Some(pillow) = &pillow {
        cases.push(("triangle pillow", pillow.clone(), Scheme::Sqrt3, &["valence 2", "--scheme loop"]));
    }
    for (name, mesh, scheme, needles) in cases {
        let e = run(&mesh, scheme, SurfaceOptions::default()).unwrap_err();
        let message = e.to_string();
        assert!(matches!(e, InterpError::UnsupportedMesh { method: "cheng", .. }), "{name}, {scheme}: {message}");
        for needle in needles {
            assert!(message.contains(needle), "{name}, {scheme}: {message} lacks {needle:?}");
        }
        let reason = Method::Cheng.check_with_scheme(&mesh, scheme).unwrap_err();
        assert!(message.contains(&reason), "{name}, {scheme}: the check's reason {reason:?} is the refusal's");
    }
    // What the checks accept succeeds: Loop takes the creases and the pillow.
    let mut accepted = vec![("creased icosahedron", creased, Scheme::Loop(LoopBeta::Warren))];
    accepted.extend(pillow.map(|p| ("triangle pillow", p, Scheme::Loop(LoopBeta::Warren))));
    for (name, mesh, scheme) in accepted {
        assert_eq!(Method::Cheng.check_with_scheme(&mesh, scheme), Ok(()), "{name}");
        let result = run(&mesh, scheme, SurfaceOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
        let (from_file, refined) = independent_errors(name, &result, &mesh, Default::default());
        assert!(from_file <= TOL && refined <= TOL * (1.0 + 1e-9), "{name}: {from_file:e}, {refined:e}");
    }
    for (_, mesh) in closed_meshes().into_iter().chain(open_meshes()) {
        for scheme in schemes() {
            assert_eq!(Method::Cheng.check_with_scheme(&mesh, scheme), Ok(()));
        }
        assert_eq!(Method::Cheng.check_with_scheme(&mesh, Scheme::CatmullClark), Method::Cheng.check(&mesh));
        assert!(Method::Cheng.check_with_scheme(&mesh, Scheme::DooSabin).is_err());
    }
}

/// The default scheme is Catmull-Clark, and naming it changes nothing: the
/// same control mesh, bit for bit, the same solver and warnings, on a closed
/// mesh, an open tagged one, the pillow (valence 2: MINRES) and the cube.
#[test]
fn catmull_clark_is_unchanged() {
    assert_eq!(ChengOptions::default().scheme, Scheme::CatmullClark);
    let cases = [
        bumpy(shapes::torus(10, 7), 0.02, 9),
        support::tagged::grid_case(INF),
        support::tagged::grid_case(1.5),
        shapes::pillow(),
        shapes::cube(),
    ];
    for mesh in cases {
        let plain = cheng::interpolate(&mesh, &ChengOptions::default()).unwrap();
        let named = ChengOptions::default().with_scheme(Scheme::CatmullClark).unwrap();
        let named = cheng::interpolate(&mesh, &named).unwrap();
        let bits = |r: &Interpolant| {
            r.control.positions().iter().flat_map(|p| p.to_array()).map(f64::to_bits).collect::<Vec<_>>()
        };
        assert_eq!(bits(&plain), bits(&named));
        assert_eq!(plain.scheme, Scheme::CatmullClark);
        assert_eq!(plain.solve.as_ref().unwrap().solver, named.solve.as_ref().unwrap().solver);
        assert_eq!(plain.warnings, named.warnings);
        assert_eq!(plain.parameters, named.parameters);
    }
}
