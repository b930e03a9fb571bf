//! Fitting (issue #17): the Spot acceptance pair from a naive start, and
//! synthetic recovery of known control meshes from perturbed copies.

use glam::DVec3;
use std::path::Path;
use subdiv_eval::bvh::TargetIndex;
use subdiv_eval::{fit, FitOptions, FitTarget};
use subdiv_mesh::shapes::{self, SplitMix64};
use subdiv_mesh::{Mesh, Tags};
use subdiv_stencil::{Options, Scheme};

fn fixture(name: &str) -> Mesh {
    subdiv_io::load_mesh(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures").join(name)).unwrap()
}

fn print_rounds(what: &str, r: &subdiv_eval::FitResult) {
    for it in &r.iterations {
        let d = it.scale;
        eprintln!(
            "{what} round {:2}: target→surface RMS {:.4e}·d max {:.4e}·d; surface→target RMS {:.4e}·d max {:.4e}·d",
            it.iteration,
            it.rms_target_to_surface / d,
            it.max_target_to_surface / d,
            it.rms_surface_to_target / d,
            it.max_surface_to_target / d
        );
    }
}

#[test]
fn spot_from_a_naive_start_reaches_the_designers_quality() {
    let target_mesh = fixture("tri/spot_triangulated.obj");
    let designed = fixture("quad/spot_control_mesh.obj");
    assert_eq!(target_mesh.positions().len(), 2930);
    let target = FitTarget::from_mesh(&target_mesh);
    // Naive start: every control vertex moved to its nearest target vertex.
    let cloud = TargetIndex::new(target.points.clone(), Vec::new());
    let naive = designed.with_positions(designed.positions().iter().map(|&p| cloud.nearest(p).unwrap().0).collect());
    let options = FitOptions { iterations: 30, ..FitOptions::default() };
    let measure_only = FitOptions { iterations: 0, ..options.clone() };
    let designer = fit(&target, &designed, &measure_only).unwrap();
    print_rounds("designer", &designer);
    let result = fit(&target, &naive, &options).unwrap();
    print_rounds("naive start", &result);
    let start = result.iterations[0];
    let end = *result.iterations.last().unwrap();
    let d = end.scale;
    assert!(start.rms_target_to_surface > 5e-3 * d, "the naive start is far: {}", start.rms_target_to_surface / d);
    assert!(end.rms_target_to_surface <= 1.0e-3 * d, "RMS {:.4e}·d", end.rms_target_to_surface / d);
    assert!(end.max_target_to_surface <= 4.0e-3 * d, "max {:.4e}·d", end.max_target_to_surface / d);
    // Topology and tags kept.
    assert_eq!(result.mesh.topology().faces(), designed.topology().faces());
}

/// Fits the limit points of a refined level of `mesh` from a copy perturbed
/// by 2 % of d, and requires the fitted surface within 1e-6·d of them.
fn recover(what: &str, mesh: &Mesh, options: Options) {
    let target_mesh = subdiv_stencil::subdivide(mesh, options, 2, true).unwrap();
    let target = FitTarget::from_mesh(&target_mesh);
    let d = target_mesh.bbox_diagonal();
    let mut rng = SplitMix64(17);
    let perturbed = mesh.with_positions(
        mesh.positions()
            .iter()
            .map(|&p| {
                p + 0.02 * d * DVec3::new(rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5).normalize()
            })
            .collect(),
    );
    let fit_options = FitOptions { surface: options, iterations: 40, tolerance: 1e-9, ..FitOptions::default() };
    let result = fit(&target, &perturbed, &fit_options).unwrap();
    print_rounds(what, &result);
    eprintln!("{what}: stop {:?}", result.stop);
    let end = *result.iterations.last().unwrap();
    assert!(result.iterations[0].max_target_to_surface > 1e-3 * d);
    assert!(end.max_target_to_surface <= 1e-6 * d, "{what}: max {:.3e}·d", end.max_target_to_surface / d);
    // Surface → target is measured against the target's triangles (chords of
    // the exact surface): the known mesh's own value is the floor.
    let exact = fit(&target, mesh, &FitOptions { iterations: 0, ..fit_options }).unwrap().iterations[0];
    assert!(exact.max_target_to_surface <= 1e-12 * d);
    assert!(
        end.max_surface_to_target <= exact.max_surface_to_target + 1e-6 * d,
        "{what}: back {:.3e}·d, the known mesh's {:.3e}·d",
        end.max_surface_to_target / d,
        exact.max_surface_to_target / d
    );
}

#[test]
fn recovers_a_cube_with_extraordinary_vertices() {
    recover("cube", &shapes::cube(), Options::new(Scheme::CatmullClark));
}

#[test]
fn recovers_an_open_grid_with_boundary() {
    let grid = shapes::quad_grid(5, 4);
    let mut rng = SplitMix64(3);
    let bumped = grid.with_positions(grid.positions().iter().map(|&p| p + DVec3::Z * rng.next_f64()).collect());
    recover("grid", &bumped, Options::new(Scheme::CatmullClark));
}

#[test]
fn recovers_a_polygon_mix() {
    let mix = shapes::polygon_mix(&shapes::torus(8, 6), 5, 0.2, 0.1, 0.1);
    assert!(mix.topology().face_ids().any(|f| mix.topology().face_size(f) != 4));
    recover("polygon mix", &mix, Options::new(Scheme::CatmullClark));
}

#[test]
fn recovers_a_loop_icosahedron() {
    recover("loop icosahedron", &shapes::icosahedron(), Options::new(Scheme::Loop(Default::default())));
}

#[test]
fn keeps_tags_and_recovers_a_creased_cube() {
    let cube = shapes::cube();
    let t = cube.topology();
    let list = subdiv_mesh::TagList {
        creases: t
            .face(subdiv_mesh::FaceId(0))
            .iter()
            .zip(t.face(subdiv_mesh::FaceId(0)).iter().cycle().skip(1))
            .map(|(&a, &b)| subdiv_mesh::EdgeTag { a, b, sharpness: 2.0 })
            .collect(),
        corners: Vec::new(),
        ..Default::default()
    };
    let tags = Tags::from_list(t, &list).unwrap();
    let tagged = cube.clone().with_tags(tags);
    recover("creased cube", &tagged, Options::new(Scheme::CatmullClark));
}

#[test]
fn bad_targets_are_typed_errors() {
    let cube = shapes::cube();
    assert!(fit(&FitTarget::default(), &cube, &FitOptions::default()).is_err());
    let nan = FitTarget::cloud(vec![DVec3::NAN]);
    assert!(fit(&nan, &cube, &FitOptions::default()).is_err());
    let bad = FitTarget { points: vec![DVec3::ZERO], triangles: vec![[0, 1, 2]] };
    assert!(fit(&bad, &cube, &FitOptions::default()).is_err());
}
