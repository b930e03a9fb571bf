//! Closest-point projection: against a dense limit tessellation (the
//! acceptance bound of issue #17), evaluation round trips, bound containment.

use crate::bspline_torus::BSplineTorus;
use glam::DVec3;
use subdiv_eval::project::{refined_bounds, DomainBounds};
use subdiv_eval::{DomainShape, PatchEvaluator, ProjectOptions, Projector, SurfaceParam};
use subdiv_mesh::shapes::{self, SplitMix64};
use subdiv_mesh::Mesh;
use subdiv_stencil::{Options, Scheme};

fn jittered_torus(nu: usize, nv: usize, amount: f64, seed: u64) -> Mesh {
    let mesh = shapes::torus(nu, nv);
    let mut rng = SplitMix64(seed);
    let p = mesh
        .positions()
        .iter()
        .map(|&p| p + amount * DVec3::new(rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5))
        .collect();
    mesh.with_positions(p)
}

/// Queries near the surface (on both sides), inside the bounding box and far away.
fn queries(mesh: &Mesh, count: usize, seed: u64) -> Vec<DVec3> {
    let bbox = mesh.bbox();
    let d = bbox.diagonal();
    let centre = 0.5 * (bbox.min + bbox.max);
    let mut rng = SplitMix64(seed);
    let mut r = || DVec3::new(rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5);
    let v = mesh.positions();
    (0..count)
        .map(|k| match k % 4 {
            0 => v[k % v.len()] + 0.01 * d * r(),
            1 => v[(7 * k) % v.len()] + 0.1 * d * r(),
            2 => centre + (bbox.max - bbox.min) * 1.2 * r(),
            _ => centre + 5.0 * d * r(),
        })
        .collect()
}

/// The acceptance check: every projection evaluates back to itself and is
/// never farther than the nearest vertex of `tessellation` (points on the
/// surface) plus 1e-9·d.
fn check_projections<E: PatchEvaluator>(projector: &Projector<E>, queries: &[DVec3], tessellation: &[DVec3], d: f64) {
    let found = projector.project_all(queries).unwrap();
    for (q, p) in queries.iter().zip(&found) {
        let back = projector.evaluator().evaluate(p.param).unwrap();
        assert!((back.position - p.position).length() <= 1e-12 * d);
        assert!(((p.position - *q).length() - p.distance).abs() <= 1e-12 * d);
        let nearest = tessellation.iter().map(|t| (*t - *q).length()).fold(f64::INFINITY, f64::min);
        assert!(
            p.distance <= nearest + 1e-9 * d,
            "query {q}: projection at {:?} is {} away, a tessellation vertex {nearest}",
            p.param,
            p.distance
        );
        assert!(DomainShape::Square.contains(p.param.u, p.param.v));
    }
}

fn torus_bounds(mesh: &Mesh, torus: &BSplineTorus, levels: usize) -> DomainBounds {
    refined_bounds(mesh, &Options::new(Scheme::CatmullClark), torus.domains(), levels).unwrap()
}

#[test]
fn the_bspline_torus_is_the_catmull_clark_limit() {
    // The test evaluator itself, against subdiv-stencil's limit points of
    // levels 0 and 1 (level-1 vertex of face (i, j): its corner (0,0),
    // edge midpoints, centre).
    let mesh = jittered_torus(6, 5, 0.2, 1);
    let torus = BSplineTorus::new(&mesh, 6, 5);
    let limit = subdiv_stencil::subdivide(&mesh, Scheme::CatmullClark, 0, true).unwrap();
    for f in 0..30u32 {
        let s = torus.evaluate(SurfaceParam { face: f, corner: 0, u: 0.0, v: 0.0 }).unwrap();
        assert!((s.position - limit.positions()[f as usize]).length() < 1e-13);
    }
    let level1 = subdiv_stencil::subdivide(&mesh, Scheme::CatmullClark, 1, true).unwrap();
    // Face points of level 1 are numbered after the 30 vertices: face f's centre.
    for f in 0..30u32 {
        let s = torus.evaluate(SurfaceParam { face: f, corner: 0, u: 0.5, v: 0.5 }).unwrap();
        assert!((s.position - level1.positions()[30 + f as usize]).length() < 1e-13);
    }
}

#[test]
fn projection_is_never_worse_than_a_level_4_tessellation() {
    let (nu, nv) = (10, 7);
    let mesh = jittered_torus(nu, nv, 0.15, 3);
    let d = mesh.bbox_diagonal();
    let torus = BSplineTorus::new(&mesh, nu, nv);
    let bounds = torus_bounds(&mesh, &torus, 2);
    let tessellation = subdiv_stencil::subdivide(&mesh, Scheme::CatmullClark, 4, true).unwrap();
    let projector = Projector::new(torus, bounds, ProjectOptions::default()).unwrap();
    check_projections(&projector, &queries(&mesh, 400, 5), tessellation.positions(), d);
}

#[test]
fn finite_difference_hessian_and_coarse_bounds_give_the_same_points() {
    let (nu, nv) = (8, 6);
    let mesh = jittered_torus(nu, nv, 0.15, 4);
    let d = mesh.bbox_diagonal();
    let exact = BSplineTorus::new(&mesh, nu, nv);
    let mut fd = BSplineTorus::new(&mesh, nu, nv);
    fd.finite_differences = true;
    let qs = queries(&mesh, 200, 9);
    let a = Projector::new(exact, torus_bounds(&mesh, &BSplineTorus::new(&mesh, nu, nv), 2), ProjectOptions::default())
        .unwrap()
        .project_all(&qs)
        .unwrap();
    let opts = ProjectOptions { levels: 1, grid: 2, ..ProjectOptions::default() };
    let b = Projector::new(fd, torus_bounds(&mesh, &BSplineTorus::new(&mesh, nu, nv), 1), opts)
        .unwrap()
        .project_all(&qs)
        .unwrap();
    for (x, y) in a.iter().zip(&b) {
        assert!((x.distance - y.distance).abs() <= 1e-9 * d, "{x:?} vs {y:?}");
    }
}

#[test]
fn refined_bounds_contain_their_patches() {
    let (nu, nv) = (7, 5);
    let mesh = jittered_torus(nu, nv, 0.3, 8);
    let torus = BSplineTorus::new(&mesh, nu, nv);
    for levels in [1, 2, 3] {
        let bounds = torus_bounds(&mesh, &torus, levels);
        assert_eq!(bounds.len(), nu * nv * 4usize.pow(levels as u32));
        for (k, dom) in torus.domains().iter().enumerate() {
            let boxes: Vec<_> = bounds.iter().filter(|p| p.domain as usize == k).map(|p| p.bounds).collect();
            for (u, v) in DomainShape::Square.grid(12) {
                let p = torus.evaluate(SurfaceParam { face: dom.face, corner: 0, u, v }).unwrap().position;
                assert!(
                    boxes.iter().any(|b| (b.min - p).max_element() <= 0.0 && (p - b.max).max_element() <= 0.0),
                    "level {levels} domain {k} ({u}, {v})"
                );
            }
        }
    }
}

/// The acceptance check on the library's evaluator (`projector`, with the
/// refined bounds and the smooth-edge exits) for one mesh.
fn check_limit_surface(what: &str, mesh: &Mesh, options: Options, count: usize) {
    check_limit_surface_seeded(what, mesh, options, count, 21);
}

fn check_limit_surface_seeded(what: &str, mesh: &Mesh, options: Options, count: usize, seed: u64) {
    let d = mesh.bbox_diagonal();
    let surface = subdiv_eval::LimitSurface::new(mesh, &options).unwrap();
    let projector = subdiv_eval::project::projector(&surface, mesh, &options, &ProjectOptions::default()).unwrap();
    let tessellation = subdiv_stencil::subdivide(mesh, options, 4, true).unwrap();
    let qs = queries(mesh, count, seed);
    check_projections(&projector, &qs, tessellation.positions(), d);
    // project_points is the same computation.
    let again = subdiv_eval::project_points(mesh, &options, &qs[..20], &ProjectOptions::default()).unwrap();
    let first = projector.project_all(&qs[..20]).unwrap();
    assert_eq!(again, first, "{what}");
}

fn bumped(mesh: Mesh, amount: f64, seed: u64) -> Mesh {
    let mut rng = SplitMix64(seed);
    let p = mesh
        .positions()
        .iter()
        .map(|&p| p + amount * DVec3::new(0.3 * rng.next_f64(), 0.2 * rng.next_f64(), rng.next_f64()))
        .collect();
    mesh.with_positions(p)
}

#[test]
fn catmull_clark_cube_extraordinary_vertices() {
    check_limit_surface("cube", &bumped(shapes::cube(), 0.2, 1), Options::new(Scheme::CatmullClark), 1000);
}

#[test]
fn catmull_clark_polygon_mix_with_n_gons() {
    let mix = shapes::polygon_mix(&shapes::torus(8, 6), 5, 0.2, 0.1, 0.1);
    assert!(mix.topology().face_ids().any(|f| mix.topology().face_size(f) != 4));
    check_limit_surface("polygon mix", &mix, Options::new(Scheme::CatmullClark), 1000);
}

#[test]
fn catmull_clark_open_grid_boundary() {
    check_limit_surface("grid", &bumped(shapes::quad_grid(5, 4), 1.0, 2), Options::new(Scheme::CatmullClark), 1000);
}

#[test]
fn catmull_clark_creases_and_corners() {
    let cube = bumped(shapes::cube(), 0.1, 3);
    let t = cube.topology();
    let f0 = t.face(subdiv_mesh::FaceId(0)).to_vec();
    let mut creases: Vec<subdiv_mesh::EdgeTag> = (0..4)
        .map(|k| subdiv_mesh::EdgeTag { a: f0[k], b: f0[(k + 1) % 4], sharpness: if k == 0 { 10.0 } else { 1.5 } })
        .collect();
    creases.truncate(3);
    let list = subdiv_mesh::TagList {
        creases,
        corners: vec![subdiv_mesh::VertexTag { vertex: f0[2], sharpness: 10.0 }],
        ..Default::default()
    };
    let tags = subdiv_mesh::Tags::from_list(t, &list).unwrap();
    check_limit_surface("creased cube", &cube.clone().with_tags(tags), Options::new(Scheme::CatmullClark), 1000);
}

#[test]
fn loop_closed_and_open() {
    let options = Options::new(Scheme::Loop(Default::default()));
    check_limit_surface("loop icosahedron", &bumped(shapes::icosahedron(), 0.2, 4), options, 600);
    check_limit_surface("loop grid", &bumped(shapes::triangle_grid(4, 4), 0.8, 5), options, 600);
}

#[test]
fn catmull_clark_spot_fixture() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/quad/spot_control_mesh.obj");
    let spot = subdiv_io::load_mesh(path).unwrap();
    check_limit_surface("spot", &spot, Options::new(Scheme::CatmullClark), 600);
}

#[test]
fn boundary_corners_over_many_seeds() {
    let loop_options = Options::new(Scheme::Loop(Default::default()));
    for seed in 30..36 {
        check_limit_surface_seeded(
            "loop grid",
            &bumped(shapes::triangle_grid(3, 4), 0.8, seed),
            loop_options,
            300,
            seed,
        );
        check_limit_surface_seeded(
            "quad grid",
            &bumped(shapes::quad_grid(3, 3), 0.8, seed),
            Options::new(Scheme::CatmullClark),
            300,
            seed,
        );
    }
}

// The Doo-Sabin cases take 200 queries (150 creased) where the primal schemes take 1,000:
// Doo-Sabin evaluates near extraordinary faces by refining locally, from the control mesh at
// every evaluation (≈ 30 ms per projection here), and 600 made these three tests 3 of the
// suite's 4 slowest (190 s of test time on a loaded machine).
#[test]
fn doo_sabin_with_support_bounds() {
    check_limit_surface("doo-sabin cube", &bumped(shapes::cube(), 0.2, 6), Options::new(Scheme::DooSabin), 200);
    let mix = shapes::polygon_mix(&shapes::torus(6, 5), 7, 0.2, 0.1, 0.05);
    check_limit_surface("doo-sabin mix", &mix, Options::new(Scheme::DooSabin), 200);
}

#[test]
fn doo_sabin_open_meshes() {
    // The strips between the face corners and the boundary curve are domains too.
    let options = Options::new(Scheme::DooSabin);
    check_limit_surface("doo-sabin grid", &bumped(shapes::quad_grid(5, 4), 1.0, 2), options, 200);
    let open_mix = shapes::polygon_mix(&bumped(shapes::quad_grid(5, 4), 0.8, 3), 5, 0.2, 0.2, 0.1);
    check_limit_surface("doo-sabin open mix", &open_mix, options, 200);
}

#[test]
fn doo_sabin_creases_and_valence_two() {
    // A crease loop round face 0 of a cube with a split edge (a valence-2 vertex).
    let cube = shapes::split_edges(&bumped(shapes::cube(), 0.2, 7), &[subdiv_mesh::EdgeId(7)], 0.1);
    let f0 = cube.topology().face(subdiv_mesh::FaceId(0)).to_vec();
    let n = f0.len();
    let creases = (0..n).map(|k| subdiv_mesh::EdgeTag { a: f0[k], b: f0[(k + 1) % n], sharpness: 10.0 }).collect();
    let tags = subdiv_mesh::Tags::from_list(
        cube.topology(),
        &subdiv_mesh::TagList { creases, corners: vec![], ..Default::default() },
    );
    let creased = cube.clone().with_tags(tags.unwrap());
    check_limit_surface("doo-sabin creased cube", &creased, Options::new(Scheme::DooSabin), 150);
}

/// Every piece of [`refined_bounds`] is the refined face of the same index,
/// and its map places the face's corners where the domain's evaluation gives
/// those vertices' limit positions (computed independently, by the stencil
/// crate's limit masks on the refined mesh) — n-gons, triangles under
/// Catmull-Clark, Loop — and each piece's box holds its part of the patch.
#[test]
fn piece_maps_place_refined_vertices_at_their_limits() {
    let mix = shapes::polygon_mix(&jittered_torus(6, 5, 0.2, 3), 7, 0.2, 0.1, 0.05);
    let tri = shapes::triangle_grid(4, 3);
    let cases = [
        ("cc polygon mix", mix.clone(), Options::new(Scheme::CatmullClark), DomainShape::Square),
        ("cc triangles", bumped(tri.clone(), 0.3, 4), Options::new(Scheme::CatmullClark), DomainShape::Square),
        ("loop triangles", bumped(tri, 0.3, 5), Options::new(Scheme::Loop(Default::default())), DomainShape::Triangle),
    ];
    for (what, mesh, options, shape) in cases {
        let d = mesh.bbox_diagonal();
        let surface = subdiv_eval::LimitSurface::new(&mesh, &options).unwrap();
        let bound = surface.bind(mesh.positions()).unwrap();
        for levels in [1, 2, 3] {
            let pieces = refined_bounds(&mesh, &options, surface.domains(), levels).unwrap();
            let refined = subdiv_stencil::subdivide(&mesh, options, levels, true).unwrap();
            let t = refined.topology();
            assert_eq!(pieces.len(), t.face_count(), "{what}");
            let corners: &[(f64, f64)] = match shape {
                DomainShape::Square => &[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)],
                DomainShape::Triangle => &[(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)],
            };
            for (f, piece) in pieces.iter().enumerate() {
                let domain = surface.domains()[piece.domain as usize];
                let at = |(s, t): (f64, f64)| {
                    let (u, v) = piece.map.apply(s, t);
                    assert!(shape.contains(u + 1e-15 * (0.5 - u), v + 1e-15 * (0.5 - v)), "{what}: ({u}, {v})");
                    bound.evaluate(SurfaceParam { face: domain.face, corner: domain.corner, u, v }).unwrap().position
                };
                let face = t.face(subdiv_mesh::FaceId(f as u32));
                assert_eq!(face.len(), corners.len(), "{what}");
                for (&c, &vertex) in corners.iter().zip(face) {
                    let want = refined.positions()[vertex as usize];
                    let got = at(c);
                    assert!((got - want).length() <= 1e-9 * d, "{what} level {levels} face {f}: {got} vs {want}");
                }
                for (s, t) in shape.grid(4) {
                    let p = at((s, t));
                    let b = piece.bounds;
                    assert!((b.min - p).max_element() <= 0.0 && (p - b.max).max_element() <= 0.0, "{what} {f}");
                }
            }
        }
    }
}

/// A sliver triangle of a real scan (`fixtures/open/dragon-fold-patch.off`,
/// from ChineseDragon-10kv) where the Catmull-Clark surface folds over within
/// a quarter of a domain: Newton from the domain's nearest sample stopped in
/// a local minimum 2·10⁻⁵·d away from a point on the surface, until every
/// piece of a solved domain whose box is nearer than the best foot got a run
/// of its own. Every level-2 limit vertex projects onto itself.
#[test]
fn a_folded_scan_patch_projects_its_own_limit_points() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/open/dragon-fold-patch.off");
    let mesh = subdiv_io::load_mesh(path).unwrap();
    let options = Options::new(Scheme::CatmullClark);
    let d = mesh.bbox_diagonal();
    let points = subdiv_stencil::subdivide(&mesh, options, 2, true).unwrap().positions().to_vec();
    let found = subdiv_eval::project_points(&mesh, &options, &points, &ProjectOptions::default()).unwrap();
    let worst = found.iter().map(|p| p.distance).fold(0.0, f64::max);
    assert!(worst <= 1e-9 * d, "a limit point projects {:e}·d away", worst / d);
}
