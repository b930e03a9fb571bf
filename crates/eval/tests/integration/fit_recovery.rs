//! Fitting on meshes it was not tuned on (issue #42): synthetic recovery
//! from 2 % of d on closed and open Catmull-Clark, Loop and Doo-Sabin meshes
//! with n-gons, valence-2 vertices, creases and corners, measured against
//! the true surface independently of the solver; partial targets; noise;
//! never singular; the numeric rule; bad options.
//!
//! The measure of truth ([`deviation`]) does not use the fit's distances:
//! both limit surfaces are evaluated on the same parameter grid (recovery
//! keeps the topology), and the fitted grid is projected onto the true
//! surface and the true grid onto the fitted one.

use glam::DVec3;
use std::path::Path;
use subdiv_eval::fit::{FitLoss, FitMethod};
use subdiv_eval::{
    fit, project_points, DomainShape, FitOptions, FitTarget, LimitSurface, ProjectOptions, SurfaceParam,
};
use subdiv_mesh::shapes::{self, SplitMix64};
use subdiv_mesh::{EdgeTag, Mesh, TagList, Tags, VertexTag};
use subdiv_stencil::{Options, Scheme};

fn fixture(name: &str) -> Mesh {
    subdiv_io::load_mesh(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures").join(name)).unwrap()
}

fn loop_options() -> Options {
    Options::new(Scheme::Loop(Default::default()))
}

/// Largest distances between the limit surfaces of `truth` and `fitted`
/// (same topology and tags), relative to `d`: (parametric: the same grid
/// parameter on both; geometric: the two grids projected onto the other
/// surface, both ways). `n` grid steps per domain side.
fn deviation(truth: &Mesh, fitted: &Mesh, options: &Options, n: usize, d: f64) -> (f64, f64) {
    let a = LimitSurface::new(truth, options).unwrap();
    let shape = DomainShape::of(options.scheme);
    let grid = shape.grid(n);
    let mut ta = Vec::new();
    let mut fb = Vec::new();
    let mut param = 0.0f64;
    for dom in a.domains() {
        for &(u, v) in &grid {
            let p = SurfaceParam::new(dom.face, dom.corner, u, v);
            let x = a.evaluate(truth.positions(), p).unwrap().position;
            let y = a.evaluate(fitted.positions(), p).unwrap().position;
            param = param.max((x - y).length());
            ta.push(x);
            fb.push(y);
        }
    }
    let project = ProjectOptions::default();
    let to_truth = project_points(truth, options, &fb, &project).unwrap();
    let to_fitted = project_points(fitted, options, &ta, &project).unwrap();
    let geo = to_truth.iter().chain(&to_fitted).fold(0.0f64, |m, p| m.max(p.distance));
    (param / d, geo / d)
}

/// The limit tessellation of `mesh` at `levels` (limit positions at every vertex).
fn limit_target(mesh: &Mesh, options: Options, levels: usize) -> FitTarget {
    FitTarget::from_mesh(&subdiv_stencil::subdivide(mesh, options, levels, true).unwrap())
}

/// Recovers `mesh` from a copy perturbed by 2 % of d, against the limit
/// tessellation at `levels`: ≤ 1e-6·d from the true surface within 30 rounds.
fn recover(what: &str, mesh: &Mesh, options: Options, levels: usize) {
    recover_from(what, mesh, &shapes::perturbed(mesh, 0.02, 17), options, levels);
}

/// [`recover`] from `start`.
fn recover_from(what: &str, mesh: &Mesh, start: &Mesh, options: Options, levels: usize) {
    let target = limit_target(mesh, options, levels);
    let d = subdiv_mesh::Aabb::of(target.points.iter().copied()).unwrap().diagonal();
    let start = start.clone();
    let fit_options = FitOptions { surface: options, iterations: 30, ..FitOptions::default() };
    let result = fit(&target, &start, &fit_options).unwrap();
    for it in &result.iterations {
        eprintln!(
            "{what} round {:2}: RMS {:.3e}·d max {:.3e}·d back max {:.3e}·d μ {:.1e} retries {} {:.2}s {}",
            it.iteration,
            it.rms_target_to_surface / d,
            it.max_target_to_surface / d,
            it.max_surface_to_target / d,
            it.damping,
            it.retries,
            it.seconds,
            it.solver
        );
    }
    let (param, geo) = deviation(mesh, &result.mesh, &options, 6, d);
    let rounds = result.iterations.last().unwrap().iteration;
    eprintln!("{what}: {rounds} rounds, stop {:?}, parametric {param:.3e}·d, geometric {geo:.3e}·d", result.stop);
    assert!(result.iterations[0].max_target_to_surface > 1e-3 * d, "{what}: the start is far");
    assert!(rounds <= 30);
    assert!(geo <= 1e-6, "{what}: fitted surface {geo:.3e}·d from the true one");
    assert_eq!(result.mesh.topology().faces(), mesh.topology().faces());
    assert_eq!(result.mesh.tags(), mesh.tags());
}

fn crease_cube() -> Mesh {
    let cube = shapes::cube();
    let t = cube.topology();
    let f = t.face(subdiv_mesh::FaceId(0));
    let list = TagList {
        creases: f.iter().zip(f.iter().cycle().skip(1)).map(|(&a, &b)| EdgeTag { a, b, sharpness: 2.0 }).collect(),
        ..Default::default()
    };
    let tags = Tags::from_list(t, &list).unwrap();
    cube.clone().with_tags(tags)
}

fn bumped_grid(nx: usize, ny: usize, seed: u64) -> Mesh {
    let grid = shapes::quad_grid(nx, ny);
    let mut rng = SplitMix64(seed);
    grid.with_positions(grid.positions().iter().map(|&p| p + DVec3::Z * rng.next_f64()).collect())
}

#[test]
fn recovers_cube_catmull_clark() {
    recover("cube", &shapes::cube(), Options::new(Scheme::CatmullClark), 2);
}

#[test]
fn recovers_open_grid_catmull_clark() {
    recover("grid", &bumped_grid(5, 4, 3), Options::new(Scheme::CatmullClark), 4);
}

#[test]
fn recovers_polygon_mix_with_ngons() {
    let mix = shapes::polygon_mix(&shapes::torus(8, 6), 5, 0.2, 0.1, 0.1);
    assert!(mix.topology().face_ids().any(|f| mix.topology().face_size(f) != 4));
    recover("polygon mix", &mix, Options::new(Scheme::CatmullClark), 2);
}

#[test]
fn recovers_valence_two_vertices() {
    let torus = shapes::torus(8, 6);
    let edges: Vec<_> = torus.topology().edges().step_by(7).take(4).collect();
    let split = shapes::split_edges(&torus, &edges, 0.05);
    assert!(split.topology().vertices().any(|v| split.topology().valence(v) == 2));
    recover("valence 2", &split, Options::new(Scheme::CatmullClark), 2);
}

#[test]
fn recovers_creased_cube() {
    recover("creased cube", &crease_cube(), Options::new(Scheme::CatmullClark), 2);
}

#[test]
fn recovers_corners_on_an_open_grid() {
    let grid = bumped_grid(4, 4, 9);
    let t = grid.topology();
    let list = TagList {
        corners: vec![VertexTag { vertex: 0, sharpness: 10.0 }, VertexTag { vertex: 4, sharpness: 10.0 }],
        ..Default::default()
    };
    let tags = Tags::from_list(t, &list).unwrap();
    recover("grid with corners", &grid.clone().with_tags(tags), Options::new(Scheme::CatmullClark), 4);
}

#[test]
fn recovers_pyramid_mixed_fixture() {
    recover("pyramid_mixed", &fixture("canonical/pyramid_mixed.obj"), Options::new(Scheme::CatmullClark), 2);
}

#[test]
fn recovers_spot_control_mesh() {
    recover("spot", &fixture("quad/spot_control_mesh.obj"), Options::new(Scheme::CatmullClark), 2);
}

#[test]
fn recovers_loop_icosahedron() {
    recover("loop icosahedron", &shapes::icosahedron(), loop_options(), 2);
}

#[test]
fn recovers_loop_open_triangle_grid() {
    let grid = shapes::triangle_grid(5, 4);
    let mut rng = SplitMix64(5);
    let bumped = grid.with_positions(grid.positions().iter().map(|&p| p + DVec3::Z * rng.next_f64()).collect());
    recover("loop open grid", &bumped, loop_options(), 4);
}

#[test]
#[ignore = "1,839 control vertices (release: 30 rounds, 139 s, the surface 2.2e-11·d from the true one): \
            run with --ignored --release"]
fn recovers_loop_bunny_fixture() {
    // 1,839 control vertices (a real, closed triangle mesh), a smooth start
    // 2 % of d off (moved independently, its vertices would pass their
    // neighbours).
    let bunny = fixture("tri/bunny_npm.obj");
    recover_from("loop bunny", &bunny, &shapes::smoothly_perturbed(&bunny, 0.02, 17), loop_options(), 2);
}

#[test]
#[ignore = "a symmetric surface: its data do not fix the control mesh (measured: level 2, 9 rounds, 3.7e-6·d \
            from the true surface with every target point within 1e-8·d; see the note on symmetry)"]
fn recovers_loop_torus_fixture() {
    // The torus of revolution: turning its control mesh about the axis by a
    // fraction of a face moves the limit surface by ~1e-6·d only, so the
    // fit slides along it (1e-2·d) and its knots no longer fall where the
    // truth's do. Asymmetric shapes (the bunny, bumped tori) recover.
    let torus = fixture("tri/torus.obj");
    recover_from("loop torus", &torus, &shapes::smoothly_perturbed(&torus, 0.02, 17), loop_options(), 3);
}

#[test]
#[ignore = "every vertex moved independently by 2 % of d, more than the edge length: a tangled start \
            (measured: 21 rounds, stalled 1.2e-3·d from the true surface)"]
fn recovers_loop_torus_fixture_from_a_tangled_start() {
    recover("loop torus tangled", &fixture("tri/torus.obj"), loop_options(), 2);
}

#[test]
fn recovers_doo_sabin_cube() {
    recover("doo-sabin cube", &shapes::cube(), Options::new(Scheme::DooSabin), 2);
}

#[test]
#[ignore = "not reached (measured, release, after the projection fix of the scan's folds but before the one at \
            smooth domain edges, not measured since: 30 rounds, 775 s, \
            target→surface RMS 2.7e-5·d, max 4e-4…9e-4·d oscillating, surface→target max 2e-2·d, the surface \
            2.2e-2·d from the true one): Catmull-Clark on a triangle scan makes every domain irregular and its \
            limit surface folds at the sliver triangles; parts of the fitted surface stay away from every target \
            point once the first round's surface→target term is gone"]
fn recovers_an_open_scan_of_1e4_vertices() {
    let dragon = fixture("open/ChineseDragon-10kv.off");
    recover_from(
        "dragon",
        &dragon,
        &shapes::smoothly_perturbed(&dragon, 0.02, 17),
        Options::new(Scheme::CatmullClark),
        2,
    );
}

#[test]
#[ignore = "10⁴ control vertices, 6.4·10⁵ target points (release: 30 rounds, 137 s of rounds, the surface \
            5.6e-8·d from the true one; before main's projection fixes it looked stalled at 2.2e-5·d: the feet \
            of its worst target points were found on domain edges 2e-5·d away, 2e-9·d across them)"]
fn recovers_a_wavy_catmull_clark_torus_of_1e4_vertices() {
    // 6.4·10⁵ target points (level 3), a smooth start 2 % of d off.
    let torus = wavy(shapes::torus(100, 100), 0.1, 7);
    let start = shapes::smoothly_perturbed(&torus, 0.02, 17);
    recover_from("wavy torus 100×100", &torus, &start, Options::new(Scheme::CatmullClark), 3);
}

#[test]
#[ignore = "a local minimum (measured: 13 rounds, stalled with the surface 8.0e-4·d from the true one, every \
            target point within 2.1e-4·d): the start is 2 % of d ≈ a face width off and the shape has detail at \
            the face scale, so the feet fall on the wrong bumps"]
fn recovers_a_bumpy_catmull_clark_torus_of_1e4_vertices() {
    let torus = shapes::bumpy_torus(100, 100, 0.015, 7);
    let start = shapes::smoothly_perturbed(&torus, 0.02, 17);
    recover_from("bumpy torus 100×100", &torus, &start, Options::new(Scheme::CatmullClark), 2);
}

#[test]
#[ignore = "a symmetric surface: its data do not fix the control mesh (measured: 30 rounds, every target point \
            within 1.6e-8·d, the surface 4.3e-6·d from the true one after a 1e-2·d tangential slide)"]
fn recovers_a_large_catmull_clark_torus() {
    let torus = shapes::torus(100, 100);
    let start = shapes::smoothly_perturbed(&torus, 0.02, 17);
    recover_from("torus 100×100", &torus, &start, Options::new(Scheme::CatmullClark), 2);
}

#[test]
#[ignore = "every vertex of a 10⁴-vertex torus moved independently by 2 % of d, 2.7× its edge length: \
            a tangled start, from which the fit does not recover"]
fn recovers_a_large_torus_from_a_tangled_start() {
    recover("torus 100×100 tangled", &shapes::torus(100, 100), Options::new(Scheme::CatmullClark), 2);
}

#[test]
#[ignore = "10⁵ control vertices, 1.6·10⁶ target points (release, beside another job: 30 rounds, 1,260 s; the \
            surface 4.2e-9·d from the true one, target→surface max 1.1e-8·d after round 2 at 38 s, the later rounds \
            gaining ~1 % each)"]
fn recovers_a_wavy_catmull_clark_torus_of_1e5_vertices() {
    let torus = wavy(shapes::torus(400, 250), 0.1, 7);
    let start = shapes::smoothly_perturbed(&torus, 0.02, 17);
    recover_from("wavy torus 400×250", &torus, &start, Options::new(Scheme::CatmullClark), 2);
}

/// `torus` (of [`shapes::torus`]: major radius 2) with its tube swollen and
/// shrunk by up to ±`amplitude` in a few low-frequency waves around both
/// circles: a smooth shape without symmetry, whose detail is far coarser
/// than its faces (a fine scan of a smooth object).
fn wavy(torus: Mesh, amplitude: f64, seed: u64) -> Mesh {
    let mut rng = SplitMix64(seed);
    let waves: Vec<(f64, f64, f64)> = [(1.0, 2.0), (2.0, 3.0), (3.0, 1.0)]
        .iter()
        .map(|&(a, b)| (a, b, rng.next_f64() * std::f64::consts::TAU))
        .collect();
    torus.with_positions(
        torus
            .positions()
            .iter()
            .map(|&p| {
                let radial = DVec3::new(p.x, p.y, 0.0).normalize();
                let tube = p - 2.0 * radial;
                let (u, w) = (p.y.atan2(p.x), tube.z.atan2(tube.dot(radial)));
                let swell = waves.iter().map(|&(a, b, phase)| (a * u + b * w + phase).sin()).sum::<f64>() / 3.0;
                p + tube.normalize() * amplitude * swell
            })
            .collect(),
    )
}

/// The 112-vertex quad mesh: a 14 × 8 torus, its control points moved
/// radially by up to 10 % of the tube radius (no symmetry left).
fn bumpy_torus() -> Mesh {
    shapes::bumpy_torus(14, 8, 0.075, 42)
}

#[test]
fn recovers_the_112_vertex_torus() {
    assert_eq!(bumpy_torus().positions().len(), 112);
    recover("torus 14×8", &bumpy_torus(), Options::new(Scheme::CatmullClark), 2);
}

/// Standard normal samples (Box-Muller).
fn gaussian(rng: &mut SplitMix64) -> f64 {
    let u = rng.next_f64().max(1e-300);
    let v = rng.next_f64();
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

/// RMS distance of `fitted`'s limit surface (a grid per domain) to `truth`'s.
fn rms_to(truth: &Mesh, fitted: &Mesh, options: &Options, n: usize) -> f64 {
    let s = LimitSurface::new(fitted, options).unwrap();
    let grid = DomainShape::of(options.scheme).grid(n);
    let pts: Vec<DVec3> = s
        .domains()
        .iter()
        .flat_map(|dom| grid.iter().map(move |&(u, v)| SurfaceParam::new(dom.face, dom.corner, u, v)))
        .map(|p| s.evaluate(fitted.positions(), p).unwrap().position)
        .collect();
    let found = project_points(truth, options, &pts, &ProjectOptions::default()).unwrap();
    (found.iter().map(|p| p.distance * p.distance).sum::<f64>() / found.len() as f64).sqrt()
}

#[test]
fn noise_is_averaged_away() {
    let truth = bumpy_torus();
    let options = Options::new(Scheme::CatmullClark);
    let clean = limit_target(&truth, options, 3);
    let d = subdiv_mesh::Aabb::of(clean.points.iter().copied()).unwrap().diagonal();
    let sigma = 0.005 * d;
    let mut rng = SplitMix64(11);
    let noisy = FitTarget {
        points: clean
            .points
            .iter()
            .map(|&p| p + sigma * DVec3::new(gaussian(&mut rng), gaussian(&mut rng), gaussian(&mut rng)))
            .collect(),
        triangles: clean.triangles.clone(),
    };
    let start = shapes::perturbed(&truth, 0.02, 17);
    for loss in [FitLoss::L2, FitLoss::Huber] {
        let result = fit(&noisy, &start, &FitOptions { surface: options, loss, ..FitOptions::default() }).unwrap();
        let rms = rms_to(&truth, &result.mesh, &options, 8);
        let last = result.iterations.last().unwrap();
        eprintln!(
            "noise {loss:?}: {} rounds, stop {:?}, target→surface RMS {:.3e}·d, fitted vs clean RMS {:.3e}·d = {:.3}σ",
            last.iteration,
            result.stop,
            last.rms_target_to_surface / d,
            rms / d,
            rms / sigma
        );
        assert!(rms <= 0.5 * sigma, "{loss:?}: RMS to the clean surface {:.3}σ", rms / sigma);
    }
}

#[test]
fn a_partial_scan_fits_its_part_and_regularises_the_rest() {
    let truth = bumpy_torus();
    let options = Options::new(Scheme::CatmullClark);
    let full = limit_target(&truth, options, 3);
    // The half x > 0.3 of the torus only, as a point cloud.
    let part = FitTarget::cloud(full.points.iter().copied().filter(|p| p.x > 0.3).collect());
    let d = subdiv_mesh::Aabb::of(part.points.iter().copied()).unwrap().diagonal();
    let start = shapes::perturbed(&truth, 0.02 * truth.bbox_diagonal() / d, 17);
    let result = fit(&part, &start, &FitOptions { surface: options, ..FitOptions::default() }).unwrap();
    let last = result.iterations.last().unwrap();
    eprintln!(
        "partial: {} rounds, stop {:?}, RMS {:.3e}·d max {:.3e}·d, {} regularised: {:?}",
        last.iteration,
        result.stop,
        last.rms_target_to_surface / d,
        last.max_target_to_surface / d,
        result.regularised.len(),
        result.regularised
    );
    assert!(!result.regularised.is_empty());
    // The regularised vertices are on the side without data.
    assert!(result.regularised.iter().all(|&i| truth.positions()[i as usize].x < 0.3));
    // The regularisation of the uncovered side biases the covered side near the cut a little.
    assert!(last.rms_target_to_surface <= 1e-4 * d, "RMS {:.3e}·d", last.rms_target_to_surface / d);
    assert!(last.max_target_to_surface <= 1e-3 * d, "max {:.3e}·d", last.max_target_to_surface / d);
    assert!(result.mesh.positions().iter().all(|p| p.is_finite()));
}

/// Every fixture of up to 100 control vertices fits with the default options
/// (or is refused with a typed reason), and with an explicit smoothness too.
#[test]
fn never_singular_on_the_small_fixtures() {
    never_singular_on_fixtures_up_to(100, 57);
}

/// [`never_singular_on_the_small_fixtures`] on every fixture of up to 3,000
/// control vertices.
#[test]
#[ignore = "fixtures of up to 3,000 control vertices: 2 min in release (run with --ignored --release)"]
fn never_singular_on_the_fixtures() {
    never_singular_on_fixtures_up_to(3000, 102);
}

/// Fits every fixture with at most `max_vertices` control vertices, with
/// smoothness 0 (the default), 1e-6 and 1; asserts at least `at_least` fits.
fn never_singular_on_fixtures_up_to(max_vertices: usize, at_least: usize) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    let mut names = Vec::new();
    for dir in ["canonical", "quad", "tri", "poly", "open"] {
        for entry in std::fs::read_dir(root.join(dir)).unwrap() {
            let path = entry.unwrap().path();
            if matches!(path.extension().and_then(|e| e.to_str()), Some("obj" | "off")) {
                names.push(path);
            }
        }
    }
    names.sort();
    let mut fitted = 0;
    for path in names {
        let Ok(mesh) = subdiv_io::load_mesh(&path) else { continue };
        if mesh.positions().len() > max_vertices {
            continue;
        }
        let triangles = mesh.topology().face_ids().all(|f| mesh.topology().face_size(f) == 3);
        let options = if triangles { loop_options() } else { Options::new(Scheme::CatmullClark) };
        let Ok(target_mesh) = subdiv_stencil::subdivide(&mesh, options, 1, true) else { continue };
        let target = FitTarget::from_mesh(&target_mesh);
        let start = shapes::perturbed(&mesh, 0.02, 3);
        for smoothness in [0.0, 1e-6, 1.0] {
            // Four rounds of the default path; two show that an explicit smoothness finishes.
            let iterations = if smoothness == 0.0 { 4 } else { 2 };
            let fit_options = FitOptions { surface: options, iterations, smoothness, ..FitOptions::default() };
            match fit(&target, &start, &fit_options) {
                Ok(r) => {
                    let (a, b) = (r.iterations[0], r.iterations.last().unwrap());
                    eprintln!(
                        "{} w={smoothness}: {} rounds, RMS {:.2e}·d → {:.2e}·d, {} regularised, stop {:?}",
                        path.display(),
                        b.iteration,
                        a.rms_target_to_surface / a.scale,
                        b.rms_target_to_surface / b.scale,
                        r.regularised.len(),
                        r.stop
                    );
                    if smoothness == 0.0 {
                        assert!(b.rms_target_to_surface <= a.rms_target_to_surface);
                    }
                    assert!(r.mesh.positions().iter().all(|p| p.is_finite()));
                    fitted += 1;
                }
                Err(e) => {
                    let text = e.to_string();
                    eprintln!("{} w={smoothness}: refused: {text}", path.display());
                    assert!(!text.contains("singular"), "{}: {text}", path.display());
                    assert!(!matches!(e, subdiv_eval::EvalError::Solve { .. } | subdiv_eval::EvalError::Internal(_)));
                }
            }
        }
    }
    assert!(fitted >= at_least, "{fitted}");
}

/// The numeric rule: the same fit at 1e150 and 1e-200 as at 1, in relative terms.
#[test]
fn extreme_scales_fit_like_unit_scale() {
    let options = Options::new(Scheme::CatmullClark);
    let cube = shapes::cube();
    let start = shapes::perturbed(&cube, 0.02, 5);
    let target = limit_target(&cube, options, 3);
    let reference = fit(&target, &start, &FitOptions { surface: options, ..FitOptions::default() }).unwrap();
    let rel = |r: &subdiv_eval::FitResult| {
        let l = r.iterations.last().unwrap();
        (l.rms_target_to_surface / l.scale, l.max_target_to_surface / l.scale, l.iteration)
    };
    for s in [1e150, 1e-200] {
        let scaled =
            FitTarget { points: target.points.iter().map(|&p| p * s).collect(), triangles: target.triangles.clone() };
        let start_s = start.with_positions(start.positions().iter().map(|&p| p * s).collect());
        let r = fit(&scaled, &start_s, &FitOptions { surface: options, ..FitOptions::default() }).unwrap();
        let (a, b) = (rel(&reference), rel(&r));
        eprintln!("scale {s:e}: {b:?} (unit scale {a:?})");
        assert!(b.0.is_finite() && b.1.is_finite());
        assert!(b.1 <= 1e-6 && b.2 >= 1, "scale {s:e}: {b:?}");
        assert!(r.mesh.positions().iter().all(|p| p.is_finite()));
        assert!(r.mesh.positions() != start_s.positions());
        let back: Vec<DVec3> = r.mesh.positions().iter().map(|&p| p / s).collect();
        for (p, q) in back.iter().zip(reference.mesh.positions()) {
            assert!((*p - *q).length() <= 1e-6, "scale {s:e}: {p} vs {q}");
        }
    }
    // A target whose extent overflows f64 is refused.
    let huge = FitTarget::cloud(vec![DVec3::splat(-1.7e308), DVec3::splat(1.7e308), DVec3::new(1.7e308, 0.0, 0.0)]);
    let e = fit(&huge, &cube, &FitOptions { surface: options, ..FitOptions::default() }).unwrap_err();
    assert!(e.to_string().contains("not representable"), "{e}");
    // All points in one place: refused.
    let flat = FitTarget::cloud(vec![DVec3::ONE; 4]);
    assert!(fit(&flat, &cube, &FitOptions::default()).is_err());
}

#[test]
fn bad_options_are_refused() {
    let cube = shapes::cube();
    let target = limit_target(&cube, Options::new(Scheme::CatmullClark), 2);
    let base = FitOptions::default();
    for bad in [
        FitOptions { tolerance: f64::NAN, ..base.clone() },
        FitOptions { tolerance: -1.0, ..base.clone() },
        FitOptions { smoothness: f64::NAN, ..base.clone() },
        FitOptions { smoothness: f64::INFINITY, ..base.clone() },
        FitOptions { min_improvement: f64::NAN, ..base.clone() },
        FitOptions { max_time: Some(0.0), ..base.clone() },
        FitOptions { max_time: Some(f64::NAN), ..base.clone() },
        FitOptions { method: FitMethod::TangentDistance { lambda: f64::NAN }, ..base.clone() },
        FitOptions { samples_per_domain: 0, ..base.clone() },
    ] {
        let e = fit(&target, &cube, &bad).unwrap_err();
        assert!(matches!(e, subdiv_eval::EvalError::InvalidInput { .. }), "{e}");
    }
}

#[test]
fn the_previous_methods_stay_and_reach_less() {
    let truth = bumpy_torus();
    let options = Options::new(Scheme::CatmullClark);
    let target = limit_target(&truth, options, 3);
    let start = shapes::perturbed(&truth, 0.02, 17);
    let mut last = Vec::new();
    for method in [FitMethod::GaussNewton, FitMethod::PointToPoint, FitMethod::TangentDistance { lambda: 0.05 }] {
        let r = fit(&target, &start, &FitOptions { surface: options, method, ..FitOptions::default() }).unwrap();
        let l = *r.iterations.last().unwrap();
        eprintln!(
            "{}: {} rounds, RMS {:.3e}·d, {:.2} s, stop {:?}",
            method.name(),
            l.iteration,
            l.rms_target_to_surface / l.scale,
            l.seconds,
            r.stop
        );
        last.push(l);
    }
    assert!(last[0].rms_target_to_surface <= last[1].rms_target_to_surface);
    assert!(last[0].rms_target_to_surface <= 1e-9 * last[0].scale);
}

#[test]
fn same_bits_on_any_thread_count() {
    let truth = bumpy_torus();
    let options = Options::new(Scheme::CatmullClark);
    let target = limit_target(&truth, options, 3);
    let start = shapes::perturbed(&truth, 0.02, 17);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            fit(&target, &start, &FitOptions { surface: options, iterations: 5, ..FitOptions::default() }).unwrap()
        })
    };
    let (a, b) = (run(1), run(3));
    assert_eq!(a.mesh.positions(), b.mesh.positions());
    assert_eq!(a.stop, b.stop);
}
