//! Interpolation of tagged meshes (creases, corners, semi-sharp values):
//! every method on closed and open meshes, measured independently of the
//! solver — by the scheme's own limit rules with the control mesh's tags
//! ([`Interpolant::error`]) and by brute force (refining the written
//! control mesh with its tags and watching the data points' descendants
//! converge onto the data).

use crate::support;

use glam::DVec3;
use subdiv_interp::*;
use subdiv_mesh::{shapes, Mesh, Tags};
use subdiv_stencil::{subdivide, BoundaryInterpolation, CreaseMethod, RowKind};

use crate::support::tagged::*;

/// Every tagged case, with a name and whether it has semi-sharp values.
fn cases() -> Vec<(&'static str, Mesh, bool)> {
    common_cases()
}

fn max_rel(result: &Interpolant, mesh: &Mesh) -> f64 {
    result.error(mesh.positions(), &result.interpolated, mesh.bbox_diagonal()).max_rel
}

/// The control mesh keeps the input's tags where it has the input's topology.
fn assert_same_tags(control: &Mesh, input: &Mesh) {
    assert_eq!(control.tags().to_list(control.topology()), input.tags().to_list(input.topology()));
}

#[test]
fn cheng_interpolates_every_tagged_case_with_both_crease_methods() {
    for (name, mesh, semi) in cases() {
        for method in [CreaseMethod::Uniform, CreaseMethod::Chaikin] {
            if method == CreaseMethod::Chaikin && !semi {
                continue;
            }
            let mut opts = ChengOptions::default();
            opts.common.surface.crease_method = method;
            opts.common.tol = 1e-10;
            let r = cheng::interpolate(&mesh, &opts).unwrap_or_else(|e| panic!("{name}, {method:?}: {e}"));
            let err = max_rel(&r, &mesh);
            assert!(err <= 1e-10, "{name}, {method:?}: error {err:e}");
            assert_same_tags(&r.control, &mesh);
            assert_eq!(r.surface_options.crease_method, method);
            // Without its tags the control mesh misses the data: the tags matter.
            let mut plain = r.clone();
            plain.control = r.control.clone().with_tags(Tags::none());
            let untagged_err = max_rel(&plain, &mesh);
            assert!(untagged_err > 1e-3, "{name}: the tags make no difference ({untagged_err:e})");
        }
    }
}

/// Brute force: refine the control mesh with its tags (no limit masks) and
/// watch input vertex i (vertex i of every Catmull-Clark level) converge on
/// the data point, at the rate of the scheme (the gap falls by ~4 per level).
#[test]
fn cheng_control_meshes_converge_onto_the_data_under_refinement() {
    for (name, mesh, _) in cases().into_iter().filter(|(n, _, _)| n.starts_with("cube") || n.starts_with("open")) {
        let r = cheng::interpolate(&mesh, &ChengOptions::default()).unwrap();
        let d = mesh.bbox_diagonal();
        let gap = |levels| {
            let fine = subdivide(&r.control, r.options(), levels, false).unwrap();
            (0..mesh.topology().vertex_count())
                .map(|i| fine.positions()[i].distance(mesh.positions()[i]) / d)
                .fold(0.0, f64::max)
        };
        let (g4, g6) = (gap(4), gap(6));
        assert!(g6 <= 2e-3, "{name}: level 6 is still {g6:e}·d away");
        assert!(g6 <= g4 / 8.0 || g6 <= 1e-12, "{name}: no convergence ({g4:e} → {g6:e})");
    }
}

/// The classic singular case of Cheng's A, the cube: untagged it is singular
/// (checkerboard kernel; data outside the range are refused), with every edge
/// infinitely sharp every vertex is a corner, A = I and the control mesh is
/// the input; one crease loop (crease vertices) makes A nonsingular, while a
/// single crease edge (two darts) does not: the dart rows annihilate the
/// checkerboard too. The dart rows (their exact limit) are not symmetric, so
/// A's left null vector is no longer the checkerboard: the unit cube, whose
/// checkerboard sum is 0, is outside the range; the limit points of a
/// control mesh are in it.
#[test]
fn cube_singularity_goes_away_with_tags() {
    let cube = jittered(&shapes::cube(), 0.1);
    assert!(cheng::interpolate(&cube, &ChengOptions::default()).is_err(), "untagged jittered cube: singular");
    let all = tagged(&cube, &with_sharpness(&CUBE_EDGES, INF), &[]);
    let r = cheng::interpolate(&all, &ChengOptions::default()).unwrap();
    assert_eq!(r.control.positions(), cube.positions(), "A = I: the control mesh is the data");
    assert!(r.warnings.iter().all(|w| !w.contains("singular")), "{:?}", r.warnings);
    let sharp =
        subdiv_stencil::LevelSharpness::new(all.tags(), BoundaryInterpolation::EdgeAndCorner, CreaseMethod::Uniform);
    let a = subdiv_stencil::limit_matrix_catmull_clark_sharp(all.topology(), &sharp).unwrap();
    assert!(a.row_kinds.iter().all(|&k| k == RowKind::Corner));
    let top = tagged(&cube, &with_sharpness(&CUBE_TOP, INF), &[]);
    let r = cheng::interpolate(&top, &ChengOptions::default()).unwrap();
    assert!(max_rel(&r, &top) <= 1e-6);
    assert!(r.warnings.iter().all(|w| !w.contains("singular")), "{:?}", r.warnings);
    let one = tagged(&cube, &[(0, 1, INF)], &[]);
    match cheng::interpolate(&one, &ChengOptions::default()) {
        Err(InterpError::Unsolvable { .. }) => {}
        other => panic!("two darts keep the cube singular: {other:?}"),
    }
    let unit = tagged(&shapes::cube(), &[(0, 1, INF)], &[]);
    match cheng::interpolate(&unit, &ChengOptions::default()) {
        Err(InterpError::Unsolvable { .. }) => {}
        other => panic!("the unit cube is outside the range of the dart rows: {other:?}"),
    }
    // Data in the range (the limit points of a control mesh) are interpolated, with the warning.
    let limits = subdivide(&one, subdiv_stencil::Options::default(), 0, true).unwrap();
    let in_range = one.with_positions(limits.positions().to_vec());
    let r = cheng::interpolate(&in_range, &ChengOptions::default()).unwrap();
    assert!(max_rel(&r, &in_range) <= 1e-6);
    assert!(r.warnings.iter().any(|w| w.contains("singular")), "{:?}", r.warnings);
}

/// `--boundary edge-only`: one-face boundary corners are no longer kept, the
/// boundary is one B-spline loop; the control mesh interpolates under the
/// option it was solved for, and not under the other.
#[test]
fn cheng_honours_the_boundary_option() {
    let mesh = grid_case(INF);
    let mut opts = ChengOptions::default();
    opts.common.surface.boundary = BoundaryInterpolation::EdgeOnly;
    let r = cheng::interpolate(&mesh, &opts).unwrap();
    assert!(max_rel(&r, &mesh) <= 1e-6);
    let mut other = r.clone();
    other.surface_options.boundary = BoundaryInterpolation::EdgeAndCorner;
    assert!(max_rel(&other, &mesh) > 1e-4);
}

/// The Doo-Sabin methods and Deng-Ma on a tagged mesh, by name.
fn run_method(method: Method, mesh: &Mesh) -> Result<Interpolant, InterpError> {
    let options = match method {
        Method::FanChengLai => FanChengLaiOptions::default().with_shape(Shape::Uniform(0.4)).into(),
        method => MethodOptions::new(method),
    };
    // Deng-Ma takes no tolerance: it keeps its defaults.
    interpolate(mesh, &options.with_tol(1e-10))
}

fn plain(method: Method) -> Scheme {
    match method {
        Method::Cheng => Scheme::CatmullClark,
        Method::DengWang => Scheme::Loop(subdiv_stencil::LoopBeta::Warren),
        Method::DengMa => Scheme::DengMa(Default::default()),
        _ => Scheme::DooSabin,
    }
}

/// Nasri, Zheng-Cai and Fan-Cheng-Lai: every infinitely sharp case is
/// interpolated to round-off — measured by the limit sites of the
/// association and, knowing nothing of the method, by the candidate limit
/// points of the control mesh with its tags (`verify`); the tags matter
/// (without them the control mesh misses the data); semi-sharp values are a
/// typed refusal.
#[test]
fn doo_sabin_methods_interpolate_infinitely_sharp_cases() {
    for method in [Method::Nasri, Method::ZhengCai, Method::FanChengLai] {
        for (name, mesh, semi) in cases() {
            let run = run_method(method, &mesh);
            if semi {
                match run {
                    Err(InterpError::Stencil(subdiv_stencil::StencilError::SemiSharpDooSabin { .. })) => continue,
                    other => panic!("{}, {name}: semi-sharp must be refused, got {other:?}", method.name()),
                }
            }
            let r = run.unwrap_or_else(|e| panic!("{}, {name}: {e}", method.name()));
            let d = mesh.bbox_diagonal();
            let err = max_rel(&r, &mesh);
            assert!(err <= 1e-10, "{}, {name}: error {err:e}", method.name());
            let candidates = support::candidate_limit_points(&r.control, plain(method));
            let gap = support::nearest_gap(mesh.positions(), &candidates, d);
            assert!(gap <= 1e-10, "{}, {name}: nearest candidate {gap:e}·d", method.name());
            if method == Method::Nasri {
                assert_same_tags(&r.control, &mesh);
            } else {
                // M¹'s tags: the pieces of the refined crease polygons, all infinitely sharp.
                let tags = r.control.tags();
                assert!(tags.crease_count() >= mesh.tags().crease_count(), "{name}");
                assert!(tags.edge_values().iter().all(|&s| s == 0.0 || s >= INF), "{name}");
            }
            let untagged = r.control.clone().with_tags(Tags::none());
            let candidates = support::candidate_limit_points(&untagged, plain(method));
            let untagged_gap = support::nearest_gap(mesh.positions(), &candidates, d);
            assert!(untagged_gap > 1e-4, "{}, {name}: the tags make no difference ({untagged_gap:e})", method.name());
        }
    }
}

/// Deng-Ma: the control mesh is the input with its tags; the surface keeps
/// the input vertices and the crease polygons' curves (and differs from the
/// untagged surface); semi-sharp values are a typed refusal.
#[test]
fn deng_ma_keeps_creases_and_passes_through_the_data() {
    for (name, mesh, semi) in cases() {
        let run = deng_ma::interpolate(&mesh, &DengMaOptions::default());
        if semi {
            assert!(
                matches!(run, Err(InterpError::Stencil(subdiv_stencil::StencilError::SemiSharpDengMa { .. }))),
                "{name}: {run:?}"
            );
            continue;
        }
        let r = run.unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_same_tags(&r.control, &mesh);
        let surface = r.surface(3).unwrap();
        let n = mesh.topology().vertex_count();
        assert_eq!(&surface.positions()[..n], mesh.positions(), "{name}");
        assert!(surface.tags().crease_count() >= 8 * mesh.tags().crease_count(), "{name}");
        let mut plain = r.clone();
        plain.control = r.control.clone().with_tags(Tags::none());
        let untagged = plain.surface(3).unwrap();
        let moved = surface.positions().iter().zip(untagged.positions()).any(|(a, b)| a.distance(*b) > 1e-6);
        assert!(moved, "{name}: the tags change nothing");
    }
}

/// Every method measures the same error from the written control mesh
/// whichever way it is read: the limit sites / control vertices of the
/// association ([`Interpolant::error`]) and the nearest candidate limit
/// point of the tagged control mesh agree.
#[test]
fn cheng_control_meshes_pass_the_independent_candidate_check() {
    for (name, mesh, _) in cases() {
        let r = cheng::interpolate(&mesh, &ChengOptions::default()).unwrap();
        let candidates = support::candidate_limit_points(&r.control, plain(Method::Cheng));
        let gap = support::nearest_gap(mesh.positions(), &candidates, mesh.bbox_diagonal());
        assert!(gap <= 1e-6, "{name}: {gap:e}");
    }
}

/// Zheng-Cai near creases: a prescribed normal at a crease vertex or a corner
/// is refused (the surface has one tangent plane per side there, or none),
/// at a dart it is the dart's V-face plane; shape handles at crease
/// vertices, corners and darts scale their V-faces about the data point and
/// keep the interpolation.
#[test]
fn zheng_cai_normals_and_handles_near_creases() {
    let mesh = torus_case(INF); // ring 0..8 (crease vertices), dart edge 50-58
    let n = mesh.topology().vertex_count();
    for (v, what) in [(3usize, "crease"), (50, "dart")] {
        let mut normals = vec![None; n];
        normals[v] = Some(DVec3::new(0.3, 0.2, 1.0));
        let opts = ZhengCaiOptions::default().with_normals(normals);
        let run = zheng_cai::interpolate(&mesh, &opts);
        match what {
            "crease" => {
                let e = run.expect_err("a normal at a crease vertex is refused");
                assert!(e.to_string().contains("crease"), "{e}");
            }
            _ => {
                let r = run.unwrap();
                assert!(max_rel(&r, &mesh) <= 1e-10);
                let LimitAssociation::DualSites(sites) = &r.association else { panic!() };
                let subdiv_stencil::DualLimitSite::FaceCentroid(f) = sites[v] else {
                    panic!("a dart's site is its V-face")
                };
                let normal = r.control.face_normal(f).normalize();
                let given = DVec3::new(0.3, 0.2, 1.0).normalize();
                assert!(normal.cross(given).length() <= 1e-9, "the dart's V-face is ⟂ the given normal");
            }
        }
    }
    let cube = tagged(&jittered(&shapes::cube(), 0.1), &[(0, 1, INF), (1, 3, INF)], &[(6, INF)]);
    let handles: Vec<f64> = (0..8).map(|i| if i % 2 == 0 { 0.5 } else { 1.8 }).collect();
    let opts = ZhengCaiOptions::default().with_handles(handles);
    let r = zheng_cai::interpolate(&cube, &opts).unwrap();
    assert!(max_rel(&r, &cube) <= 1e-10);
    let plain = zheng_cai::interpolate(&cube, &ZhengCaiOptions::default()).unwrap();
    assert!(r.control.positions().iter().zip(plain.control.positions()).any(|(a, b)| a.distance(*b) > 1e-3));
}
