//! The limit matrices with creases and corners (Cheng's A, Loop's L on a
//! `LevelSharpness`): rows sum to 1, crease and corner rows depend on their
//! crease polygon only (the sharp block comes first: A block
//! lower-triangular), S symmetric on the smooth block bit for bit (the
//! untagged rows there, unchanged), every row equal to the plan's limit
//! stencil (to 1e-14) and the limits equal to OpenSubdiv's; the blocks'
//! spectra (printed with --nocapture); a proptest over generated meshes with
//! random crease loops and values. Brute-force convergence:
//! `limit_matrices_creases_brute_force.rs`.

use crate::common::solve_blocks;
use crate::sharp_cases;
use crate::sharp_cases::{all_cases, constructed_cases, pinched_crop_case, Case};
use nalgebra::{DMatrix, SymmetricEigen};
use proptest::prelude::*;
use std::collections::{HashMap, HashSet};
use subdiv_mesh::{shapes, EdgeId, Mesh, Tags, Topology, VertexId};
use subdiv_rules::crease::is_infinite;
use subdiv_stencil::doo_sabin::StandardCorners;
use subdiv_stencil::limit_matrix::{
    limit_matrix_catmull_clark_sharp, limit_matrix_doo_sabin_sharp, limit_matrix_loop_sharp, RowKind,
};
use subdiv_stencil::{
    limit_matrix_catmull_clark, limit_matrix_loop, BoundaryInterpolation, CreaseMethod, LevelSharpness, LimitMatrix,
    LoopBeta, Options, Scheme, SparseMatrix, StencilError, SubdivisionPlan,
};

/// The neighbours of `v` along infinitely sharp edges (boundary edges included).
fn infinite_neighbours(t: &Topology, sharp: &LevelSharpness, v: VertexId) -> HashSet<u32> {
    let mut out = HashSet::new();
    for e in t.edges() {
        let (a, b) = t.edge_vertices(e);
        if is_infinite(sharp.edge(t, e)) {
            if a == v {
                out.insert(b.0);
            } else if b == v {
                out.insert(a.0);
            }
        }
    }
    out
}

fn row_of(s: &SparseMatrix, i: usize) -> Vec<(usize, f64)> {
    s.outer_view(i).unwrap().iter().map(|(j, &x)| (j, x)).collect()
}

fn untagged(c: &Case) -> LimitMatrix {
    let t = c.mesh.topology();
    match c.options.scheme {
        Scheme::CatmullClark => limit_matrix_catmull_clark(t),
        Scheme::Loop(beta) => limit_matrix_loop(t, beta).unwrap(),
        _ => unreachable!(),
    }
}

/// Rows sum to 1.
fn check_row_sums(name: &str, a: &LimitMatrix) {
    for (i, row) in a.to_csr().outer_iterator().enumerate() {
        let sum: f64 = row.data().iter().sum();
        assert!((sum - 1.0).abs() < 1e-13, "{name}: row {i} sums to {sum}");
    }
}

/// Crease rows are (p₋ + 4p + p₊)/6 along infinitely sharp edges, corner
/// rows the identity, and the sharp block is the largest set of crease and
/// corner rows closed under their columns.
fn check_sharp_rows(c: &Case, a: &LimitMatrix) {
    let (t, sharp) = (c.mesh.topology(), c.sharpness());
    for v in a.rows_of(RowKind::Corner) {
        assert_eq!(row_of(&a.s, v as usize), vec![(v as usize, 1.0)], "{}: corner {v}", c.name);
        assert_eq!(a.d[v as usize], 1.0);
    }
    for v in a.rows_of(RowKind::Crease) {
        let row = row_of(&a.s, v as usize);
        let ends = infinite_neighbours(t, &sharp, VertexId(v));
        assert_eq!(ends.len(), 2, "{}: crease vertex {v} has {ends:?}", c.name);
        assert_eq!(a.d[v as usize], 1.0 / 6.0);
        for (j, x) in row {
            let expected = if j == v as usize { 4.0 } else { 1.0 };
            assert!(j == v as usize || ends.contains(&(j as u32)), "{}: crease row {v} has column {j}", c.name);
            assert_eq!(x, expected, "{}: crease row {v}", c.name);
        }
    }
    // The largest closed set, by the plain fixpoint.
    let mut inside: HashSet<u32> = a.rows_of(RowKind::Crease).into_iter().chain(a.rows_of(RowKind::Corner)).collect();
    loop {
        let leaving: Vec<u32> = (inside.iter().copied())
            .filter(|&v| row_of(&a.s, v as usize).iter().any(|&(j, _)| !inside.contains(&(j as u32))))
            .collect();
        if leaving.is_empty() {
            break;
        }
        leaving.iter().for_each(|v| {
            inside.remove(v);
        });
    }
    let mut expected: Vec<u32> = inside.into_iter().collect();
    expected.sort_unstable();
    assert_eq!(a.boundary_rows, expected, "{}: the sharp block", c.name);
    // Block lower-triangular: no sharp row reaches outside; the blocks partition the rows.
    let blocks = solve_blocks(a);
    assert_eq!(blocks.corners.len() + blocks.creases.len() + blocks.interior.len(), a.size());
    let mut sharp_block: Vec<u32> = blocks.corners.iter().chain(&blocks.creases).copied().collect();
    sharp_block.sort_unstable();
    assert_eq!(sharp_block, a.boundary_rows, "{}", c.name);
    assert!(a.asymmetric_rows(&blocks.creases).is_empty(), "{}: the crease block is symmetric", c.name);
}

/// Smooth rows: the untagged rows, bit for bit, and symmetric among themselves.
fn check_smooth_block(c: &Case, a: &LimitMatrix) {
    let plain = untagged(c);
    let smooth = a.rows_of(RowKind::Smooth);
    let is_smooth: HashSet<u32> = smooth.iter().copied().collect();
    for &v in &smooth {
        let (x, y) = (row_of(&a.s, v as usize), row_of(&plain.s, v as usize));
        assert_eq!(x.len(), y.len(), "{}: smooth row {v}", c.name);
        for ((j, p), (k, q)) in x.iter().zip(&y) {
            assert!(j == k && p.to_bits() == q.to_bits(), "{}: smooth row {v}", c.name);
        }
        assert_eq!(a.d[v as usize].to_bits(), plain.d[v as usize].to_bits());
        for (j, x) in x.into_iter().filter(|(j, _)| is_smooth.contains(&(*j as u32))) {
            assert_eq!(x.to_bits(), a.s.get(j, v as usize).unwrap().to_bits(), "{}: S[{v}][{j}]", c.name);
        }
    }
    assert!(a.asymmetric_rows(&smooth).is_empty(), "{}", c.name);
}

/// Largest |A − B| over all entries, and the largest row ℓ¹ norm of B.
fn max_difference(a: &SparseMatrix, b: &SparseMatrix) -> (f64, f64) {
    let (mut worst, mut norm) = (0.0f64, 0.0f64);
    for i in 0..a.rows() {
        let mut entries: HashMap<usize, f64> = HashMap::new();
        row_of(a, i).into_iter().for_each(|(j, x)| *entries.entry(j).or_default() += x);
        let rb = row_of(b, i);
        norm = norm.max(rb.iter().map(|(_, x)| x.abs()).sum());
        rb.into_iter().for_each(|(j, x)| *entries.entry(j).or_default() -= x);
        worst = entries.values().fold(worst, |m, x| m.max(x.abs()));
    }
    (worst, norm)
}

fn check_equals_plan(c: &Case, a: &LimitMatrix) {
    let plan = c.plan_stencil();
    let (worst, norm) = max_difference(&a.to_csr(), &plan);
    assert!(worst <= 1e-14 * norm.max(1.0), "{}: A differs from the plan's limit stencil by {worst:e}", c.name);
}

#[test]
fn rows_sum_to_one() {
    for c in all_cases() {
        check_row_sums(&c.name, &c.matrix());
    }
}

#[test]
fn crease_and_corner_rows_depend_on_their_polygon_only_and_come_first() {
    for c in all_cases() {
        check_sharp_rows(&c, &c.matrix());
    }
}

#[test]
fn s_is_symmetric_on_the_smooth_block_bit_for_bit() {
    for c in all_cases() {
        check_smooth_block(&c, &c.matrix());
    }
}

#[test]
fn rows_equal_the_plans_limit_stencil() {
    for c in all_cases() {
        check_equals_plan(&c, &c.matrix());
    }
}

/// A·P equals OpenSubdiv's limit points of the input vertices
/// (`fixtures/peer/creases/*/…-limit.txt`: `Limit` after ⌈s⌉ levels).
#[test]
fn limit_points_equal_opensubdiv() {
    let mut worst = 0.0f64;
    for c in sharp_cases::peer_cases() {
        let expected = sharp_cases::read_points(c.peer_limit.as_ref().unwrap());
        let got = c.matrix().apply(c.mesh.positions());
        let d = c.mesh.bbox_diagonal();
        assert_eq!(got.len(), expected.len(), "{}", c.name);
        let dev = got.iter().zip(&expected).map(|(p, q)| p.distance(*q)).fold(0.0, f64::max) / d;
        assert!(dev <= 1e-12, "{}: {dev:e}·d from OpenSubdiv", c.name);
        worst = worst.max(dev);
    }
    eprintln!("A·P vs OpenSubdiv's limits, 15 cases: max {worst:.1e}·d");
}

/// What each kind covers on the cases whose classes are known.
#[test]
fn row_kinds_follow_the_vertex_rules() {
    let by_name = |name: &str| all_cases().into_iter().find(|c| c.name == name).unwrap();
    let kinds = |c: &Case| {
        let a = c.matrix();
        [RowKind::Smooth, RowKind::Crease, RowKind::Corner, RowKind::General].map(|k| a.rows_of(k))
    };
    // Top loop at 10: the 4 top vertices are a closed crease polygon, the rest smooth.
    let [smooth, crease, corner, general] = kinds(&by_name("cube, top loop s=10"));
    assert_eq!((smooth, crease.clone(), corner.len(), general.len()), (vec![0, 1, 2, 3], vec![4, 5, 6, 7], 0, 0));
    // All 12 edges at 10: three sharp edges everywhere, the identity.
    let c = by_name("cube_crease_all10 (catmull-clark)");
    assert_eq!(kinds(&c)[2], (0..8).collect::<Vec<u32>>());
    assert!(c.matrix().to_csr().outer_iterator().enumerate().all(|(i, r)| r.nnz() == 1 && r.get(i) == Some(&1.0)));
    // Semi-sharp values: their vertices are general rows, the others smooth.
    let [smooth, _, _, general] = kinds(&by_name("cube, top loop s=1/2.5 (uniform)"));
    assert_eq!((smooth, general), (vec![0, 1, 2, 3], vec![4, 5, 6, 7]));
    // A crease with a semi-sharp branch: 5 is general (corner, then crease), its ends too.
    let [_, crease, _, general] = kinds(&by_name("cube, crease with a semi-sharp branch"));
    assert!(crease.is_empty() && general == vec![1, 4, 5, 7], "{general:?}");
    // The grid's crease row at 10 ends on the boundary: 3 sharp edges, corners.
    let n = 4;
    let id = |i, j| sharp_cases::grid_id(n, i, j);
    for boundary in ["edge-and-corner", "edge-only"] {
        let name = format!("grid 4×4, crease row s=10 to the boundary, corner tag ({boundary})");
        let [smooth, crease, corner, general] = kinds(&by_name(&name));
        assert!(general.is_empty(), "{name}");
        for v in [id(0, 2), id(n, 2), id(1, 0)] {
            assert!(corner.contains(&v), "{name}: {v}");
        }
        for i in 1..n {
            assert!(crease.contains(&id(i, 2)), "{name}");
        }
        // The grid corners: fixed under edge-and-corner, boundary crease points under edge-only.
        let grid_corners = [id(0, 0), id(n, 0), id(0, n), id(n, n)];
        let (fixed, curve) = if boundary == "edge-only" { (&crease, &corner) } else { (&corner, &crease) };
        assert!(grid_corners.iter().all(|v| fixed.contains(v) && !curve.contains(v)), "{name}");
        assert_eq!(smooth.len(), (n - 1) * (n - 1) - (n - 1), "{name}");
    }
    // Darts: the segment's ends are general, its middle a crease — which leans on them.
    let c = by_name("grid 4×4, interior crease segment s=10 (darts)");
    let [_, crease, _, general] = kinds(&c);
    let t = c.mesh.topology();
    let interior_crease: Vec<u32> = crease.into_iter().filter(|&v| !t.is_boundary_vertex(VertexId(v))).collect();
    assert_eq!((interior_crease, general), (vec![id(2, 2)], vec![id(1, 2), id(3, 2)]));
    let a = c.matrix();
    assert!(!a.boundary_rows.contains(&id(2, 2)), "a crease row next to darts leaves the sharp block");
    assert!(solve_blocks(&a).interior.contains(&id(2, 2)));
}

/// Where the general rows break the symmetry, `asymmetric_rows` says so; the
/// interior of a matrix without general rows stays symmetric.
#[test]
fn asymmetric_rows_find_the_general_rows() {
    for c in all_cases() {
        let a = c.matrix();
        let interior = solve_blocks(&a).interior;
        let asym: HashSet<u32> = a.asymmetric_rows(&interior).into_iter().collect();
        let general: HashSet<u32> = a.rows_of(RowKind::General).into_iter().collect();
        if general.is_empty() && interior.iter().all(|&v| a.row_kinds[v as usize] == RowKind::Smooth) {
            assert!(asym.is_empty(), "{}: {asym:?}", c.name);
        }
        // Every asymmetry involves a general row or a crease row of the interior.
        for &v in &asym {
            let row = row_of(&a.s, v as usize);
            let involved = a.row_kinds[v as usize] != RowKind::Smooth
                || row.iter().any(|&(j, _)| a.row_kinds[j] != RowKind::Smooth && asym.contains(&(j as u32)));
            assert!(involved, "{}: smooth row {v} asymmetric", c.name);
        }
        if !general.is_empty() {
            assert!(!asym.is_empty(), "{}: general rows {general:?} left the interior symmetric", c.name);
        }
    }
}

/// Untagged sharpness (any crease method) gives the untagged matrices bit
/// for bit; `edge-only` makes the one-face corners boundary crease points.
#[test]
fn untagged_sharpness_gives_the_untagged_matrices() {
    let same = |a: &LimitMatrix, b: &LimitMatrix| {
        a.d.iter().zip(&b.d).all(|(x, y)| x.to_bits() == y.to_bits())
            && a.s.indptr() == b.s.indptr()
            && a.s.indices() == b.s.indices()
            && a.s.data().iter().zip(b.s.data()).all(|(x, y)| x.to_bits() == y.to_bits())
            && a.boundary_rows == b.boundary_rows
            && a.row_kinds == b.row_kinds
    };
    let plate = shapes::plate_with_holes(5, 4, &[(2, 1)], false);
    let tri = shapes::triangle_grid(3, 2);
    let none = Tags::none();
    for method in [CreaseMethod::Uniform, CreaseMethod::Chaikin] {
        let sharp = LevelSharpness::new(&none, BoundaryInterpolation::EdgeAndCorner, method);
        let t = plate.topology();
        assert!(same(&limit_matrix_catmull_clark_sharp(t, &sharp).unwrap(), &limit_matrix_catmull_clark(t)));
        let t = tri.topology();
        for beta in [LoopBeta::Warren, LoopBeta::Loop] {
            assert!(same(&limit_matrix_loop_sharp(t, &sharp, beta).unwrap(), &limit_matrix_loop(t, beta).unwrap()));
        }
    }
    let grid = sharp_cases::curved_grid(3, 3);
    let c = Case {
        name: "grid edge-only".into(),
        mesh: grid.clone(),
        tags: Tags::none(),
        options: sharp_cases::options(Scheme::CatmullClark, BoundaryInterpolation::EdgeOnly, CreaseMethod::Uniform),
        peer_limit: None,
    };
    let a = c.matrix();
    assert_eq!(row_of(&a.s, 0), vec![(0, 4.0), (1, 1.0), (4, 1.0)], "corner 0: (p₁ + 4p₀ + p₄)/6");
    assert!(a.rows_of(RowKind::Corner).is_empty());
    check_equals_plan(&c, &a);
    let untagged_plain = limit_matrix_catmull_clark(grid.topology());
    assert_eq!(row_of(&untagged_plain.s, 0), vec![(0, 1.0)]);
}

/// (The Doo-Sabin matrices with infinitely sharp tags:
/// `limit_matrices_doo_sabin_creases.rs`.)
#[test]
fn doo_sabin_matrices_refuse_semi_sharp_tags_and_loop_refuses_polygons() {
    let cube = shapes::cube();
    let t = cube.topology();
    let semi = sharp_cases::tags(&cube, &[(4, 5, 2.0)], &[]);
    let err = limit_matrix_doo_sabin_sharp(t, &StandardCorners, &semi).unwrap_err();
    assert!(matches!(err, StencilError::SemiSharpDooSabin { .. }), "{err}");
    let plain = limit_matrix_doo_sabin_sharp(t, &StandardCorners, &Tags::none()).unwrap();
    assert_eq!(plain.s, subdiv_stencil::limit_matrix_doo_sabin(t).s);
    let tags = sharp_cases::tags(&cube, &[(4, 5, 10.0)], &[]);
    let sharp = LevelSharpness::new(&tags, BoundaryInterpolation::EdgeAndCorner, CreaseMethod::Uniform);
    let err = limit_matrix_loop_sharp(t, &sharp, LoopBeta::Loop).unwrap_err();
    assert!(matches!(err, StencilError::NotTriangles { .. }), "{err}");
}

/// Regression (the crop around general rows): a rim vertex whose kept faces
/// meet at it alone must not make the crop non-manifold; the rows still
/// equal the plan's.
#[test]
fn crop_pinching_a_rim_vertex_keeps_the_rows() {
    let c = pinched_crop_case();
    let a = c.matrix();
    assert_eq!(a.rows_of(RowKind::General).len(), 2);
    check_equals_plan(&c, &a);
    check_row_sums(&c.name, &a);
}

/// A guard against composing on the whole mesh: one dart on a 256 × 256
/// grid (65 536 faces) with a semi-sharp edge of 5.5 elsewhere needs 6
/// levels; on the whole mesh that is 2.7·10⁸ faces, on the crops a few hundred.
#[test]
fn general_rows_are_composed_locally() {
    let n = 256;
    let grid = shapes::quad_grid(n, n);
    let id = |i, j| sharp_cases::grid_id(n, i, j);
    let tags = sharp_cases::tags(&grid, &[(id(10, 10), id(11, 10), 10.0), (id(200, 200), id(200, 201), 5.5)], &[]);
    let sharp = LevelSharpness::new(&tags, BoundaryInterpolation::EdgeAndCorner, CreaseMethod::Uniform);
    let a = limit_matrix_catmull_clark_sharp(grid.topology(), &sharp).unwrap();
    assert_eq!(a.rows_of(RowKind::General).len(), 4);
    check_row_sums("big grid", &a);
}

/// More general rows than one crop takes (the rows are composed a chunk of
/// crops at a time, in parallel): a 100 × 100 grid with a semi-sharp crease
/// of 2.5 on every other row of edges (the vertices of those rows general). A's rows, the plan's composed stencil on crops
/// ([`SubdivisionPlan::limit_stencil_local`], what `fair` takes) and the
/// plan's stencil by refining the whole mesh agree, and the rows do not
/// depend on the thread count.
#[test]
fn many_general_rows_are_composed_in_chunks() {
    let n = 100;
    let grid = shapes::quad_grid(n, n);
    let creases: Vec<(u32, u32, f32)> = (0..=n)
        .step_by(2)
        .flat_map(|j| (0..n).map(move |i| (sharp_cases::grid_id(n, i, j), sharp_cases::grid_id(n, i + 1, j), 2.5)))
        .collect();
    let tags = sharp_cases::tags(&grid, &creases, &[]);
    let sharp = LevelSharpness::new(&tags, BoundaryInterpolation::EdgeAndCorner, CreaseMethod::Uniform);
    let a = limit_matrix_catmull_clark_sharp(grid.topology(), &sharp).unwrap();
    let general = a.rows_of(RowKind::General).len();
    assert!(general > 2 * 2048, "{general} general rows: fewer than three chunks");
    check_row_sums("grid with many semi-sharp creases", &a);
    let plan = SubdivisionPlan::with_tags(grid.topology(), &tags, Options::new(Scheme::CatmullClark), 0).unwrap();
    let global = plan.limit_stencil().unwrap().unwrap();
    let local = plan.limit_stencil_local().unwrap().unwrap();
    for (what, m) in [("A", a.to_csr()), ("the local stencil", local.clone())] {
        let (worst, norm) = max_difference(&m, &global);
        assert!(worst <= 1e-14 * norm.max(1.0), "{what} differs from the whole-mesh stencil by {worst:e}");
    }
    let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let serial = one_thread.install(|| plan.limit_stencil_local().unwrap().unwrap());
    assert_eq!(serial, local, "the composed rows depend on the thread count");
}

/// Eigenvalues of D^½ S D^½ restricted to `block` (symmetric when S is there).
fn block_eigenvalues(a: &LimitMatrix, block: &[u32]) -> Vec<f64> {
    let m = block_dense(a, block, true);
    let mut ev: Vec<f64> = SymmetricEigen::new(m).eigenvalues.iter().copied().collect();
    ev.sort_by(f64::total_cmp);
    ev
}

/// A restricted to `block`, dense; `similar`: as D^½ S D^½.
fn block_dense(a: &LimitMatrix, block: &[u32], similar: bool) -> DMatrix<f64> {
    let at: HashMap<u32, usize> = block.iter().enumerate().map(|(k, &v)| (v, k)).collect();
    let mut m = DMatrix::zeros(block.len(), block.len());
    for (k, &v) in block.iter().enumerate() {
        for (j, x) in row_of(&a.s, v as usize) {
            if let Some(&l) = at.get(&(j as u32)) {
                let (di, dj) = (a.d[v as usize], a.d[j]);
                m[(k, l)] = if similar { di.sqrt() * x * dj.sqrt() } else { di * x };
            }
        }
    }
    m
}

/// Gershgorin interval of the symmetric D^½ S D^½ on `block`.
fn gershgorin(a: &LimitMatrix, block: &[u32]) -> (f64, f64) {
    let m = block_dense(a, block, true);
    (0..m.nrows()).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), i| {
        let r: f64 = (0..m.ncols()).filter(|&j| j != i).map(|j| m[(i, j)].abs()).sum();
        (lo.min(m[(i, i)] - r), hi.max(m[(i, i)] + r))
    })
}

/// Spectra of the blocks with creases (observations, printed): the crease
/// block within [⅓, 1] (circulant and tridiagonal (1, 4, 1)/6: never
/// singular), the smooth block within the untagged spectrum and positive
/// (the cube's checkerboard kernel needs every vertex: any crease removes
/// it), the interior with general rows nonsingular on every case.
#[test]
fn spectra_of_the_blocks_with_creases() {
    const EPS: f64 = 1e-12;
    for c in all_cases().into_iter().filter(|c| c.mesh.topology().vertex_count() <= 300) {
        let a = c.matrix();
        let blocks = solve_blocks(&a);
        let mut line = format!("{}:", c.name);
        if !blocks.creases.is_empty() {
            let ev = block_eigenvalues(&a, &blocks.creases);
            let (lo, hi) = gershgorin(&a, &blocks.creases);
            line += &format!(" crease λ ∈ [{:.4}, {:.4}] (Gershgorin [{lo:.3}, {hi:.3}])", ev[0], ev[ev.len() - 1]);
            assert!(ev[0] >= 1.0 / 3.0 - EPS && ev[ev.len() - 1] <= 1.0 + EPS, "{}: crease block {ev:?}", c.name);
        }
        let smooth = a.rows_of(RowKind::Smooth);
        if !smooth.is_empty() {
            let ev = block_eigenvalues(&a, &smooth);
            let (lo, hi) = gershgorin(&a, &smooth);
            line += &format!("; smooth λ ∈ [{:.4}, {:.4}] (Gershgorin [{lo:.3}, {hi:.3}])", ev[0], ev[ev.len() - 1]);
            let all_valence_3_or_more = smooth.iter().all(|&v| c.mesh.topology().valence(VertexId(v)) >= 3);
            if all_valence_3_or_more {
                assert!(ev[0] > EPS && ev[ev.len() - 1] <= 1.0 + EPS, "{}: smooth block {ev:?}", c.name);
            }
        }
        if blocks.interior.iter().any(|&v| a.row_kinds[v as usize] != RowKind::Smooth) {
            let m = block_dense(&a, &blocks.interior, false);
            let schur = nalgebra::linalg::Schur::try_new(m, 1e-14, 100_000).expect("Schur converges");
            let ev = schur.complex_eigenvalues();
            let min_re = ev.iter().map(|z| z.re).fold(f64::INFINITY, f64::min);
            let min_abs = ev.iter().map(|z| z.norm()).fold(f64::INFINITY, f64::min);
            let max_abs = ev.iter().map(|z| z.norm()).fold(0.0, f64::max);
            line += &format!("; interior with general rows: min Re λ {min_re:.4}, |λ| ∈ [{min_abs:.4}, {max_abs:.4}]");
            assert!(min_abs > 1e-6, "{}: the interior block is (nearly) singular: {min_abs:e}", c.name);
        }
        eprintln!("{line}");
    }
    // The circulant of a closed crease loop of m vertices: (4 + 2cos(2πk/m))/6.
    for (name, m) in [("tetrahedron (CC), 3-vertex crease loop", 3), ("torus 6×4, ring s=10", 4)] {
        let c = constructed_cases().into_iter().find(|c| c.name == name).unwrap();
        let a = c.matrix();
        let ev = block_eigenvalues(&a, &solve_blocks(&a).creases);
        let mut expected: Vec<f64> =
            (0..m).map(|k| (4.0 + 2.0 * (std::f64::consts::TAU * k as f64 / m as f64).cos()) / 6.0).collect();
        expected.sort_by(f64::total_cmp);
        assert_eq!(ev.len(), m, "{name}");
        assert!(ev.iter().zip(&expected).all(|(x, y)| (x - y).abs() < 1e-14), "{name}: {ev:?} vs {expected:?}");
    }
    // The cube: singular untagged (checkerboard), nonsingular with its top loop sharp.
    let c = constructed_cases().into_iter().find(|c| c.name == "cube, top loop s=10").unwrap();
    let all: Vec<u32> = (0..8).collect();
    assert!(block_eigenvalues(&untagged(&c), &all)[0].abs() < 1e-14);
    assert!(block_eigenvalues(&c.matrix(), &c.matrix().rows_of(RowKind::Smooth))[0] > 0.05);
}

/// Generated meshes (`subdiv_mesh::shapes`) with random crease walks and
/// loops, random semi-sharp and infinite values, random corners, random
/// boundary option and crease method.
fn generated_case(choice: usize, seed: u64) -> Case {
    let mut rng = shapes::SplitMix64(seed);
    let cc = Scheme::CatmullClark;
    let lp = Scheme::Loop(if rng.below(2) == 0 { LoopBeta::Warren } else { LoopBeta::Loop });
    let (mesh, scheme): (Mesh, Scheme) = match choice {
        0 => (shapes::torus(6, 4), cc),
        1 => (shapes::torus(5, 3), cc),
        2 => (sharp_cases::curved_grid(4, 3), cc),
        3 => (shapes::polygon_mix(&shapes::torus(6, 5), seed, 0.2, 0.2, 0.05), cc),
        4 => (shapes::polygon_mix(&shapes::plate_with_holes(5, 4, &[(2, 1)], false), seed, 0.2, 0.2, 0.05), cc),
        5 => (shapes::pyramid(5), cc),
        6 => (shapes::icosahedron(), lp),
        7 => (shapes::triangle_grid(3, 3), lp),
        _ => (shapes::octahedron(), lp),
    };
    let mesh = sharp_cases::jittered(&mesh, seed ^ 0x5eed);
    let t = mesh.topology();
    let value = |rng: &mut shapes::SplitMix64| -> f32 {
        match rng.below(4) {
            0 => 10.0,
            1 => [0.5f32, 1.0, 1.5, 2.0, 2.5][rng.below(5)],
            _ => (rng.next_f64() * 3.4) as f32 + 0.05,
        }
    };
    let mut edges = vec![0.0f32; t.edge_count()];
    for _ in 0..1 + rng.below(3) {
        // A walk along edges, closed when it comes back to its start.
        let start = VertexId(rng.below(t.vertex_count()) as u32);
        let (mut v, s) = (start, value(&mut rng));
        for _ in 0..2 + rng.below(6) {
            let neighbours: Vec<VertexId> = t.vertex_neighbors(v).collect();
            let next = neighbours[rng.below(neighbours.len())];
            let e: EdgeId = t.find_edge(v, next).unwrap();
            edges[e.index()] = if rng.below(4) == 0 { value(&mut rng) } else { s };
            v = next;
            if v == start {
                break;
            }
        }
    }
    let mut vertices = vec![0.0f32; t.vertex_count()];
    for _ in 0..rng.below(3) {
        vertices[rng.below(t.vertex_count())] = value(&mut rng);
    }
    let tags = Tags::from_arrays(t, edges, vertices).unwrap();
    let boundary = BoundaryInterpolation::ALL[rng.below(3)];
    let method = if rng.below(2) == 0 { CreaseMethod::Uniform } else { CreaseMethod::Chaikin };
    let options: Options = sharp_cases::options(scheme, boundary, method);
    Case { name: format!("generated {choice}/{seed:#x}"), mesh, tags, options, peer_limit: None }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn generated_tagged_meshes_keep_the_properties(choice in 0usize..9, seed in any::<u64>()) {
        let c = generated_case(choice, seed);
        let a = c.matrix();
        check_row_sums(&c.name, &a);
        check_sharp_rows(&c, &a);
        check_smooth_block(&c, &a);
        check_equals_plan(&c, &a);
    }
}

/// `limit_rows_loop_sharp` gives the rows of `limit_matrix_loop_sharp`,
/// kinds and D entries equal, S rows equal to round-off, for any subset of
/// vertices in any order (here: every vertex, reversed).
#[test]
fn loop_rows_alone_equal_the_whole_matrix() {
    let mut checked = 0;
    for c in all_cases() {
        let Scheme::Loop(beta) = c.options.scheme else { continue };
        let (t, sharp) = (c.mesh.topology(), c.sharpness());
        let a = limit_matrix_loop_sharp(t, &sharp, beta).unwrap();
        let vertices: Vec<u32> = (0..t.vertex_count() as u32).rev().collect();
        let rows = subdiv_stencil::limit_rows_loop_sharp(t, &sharp, beta, &vertices).unwrap();
        for (i, &v) in vertices.iter().enumerate() {
            assert_eq!(rows.kinds[i], a.row_kinds[v as usize], "{}: vertex {v}", c.name);
            assert_eq!(rows.d[i], a.d[v as usize], "{}: vertex {v}", c.name);
            let (mine, whole) = (row_of(&rows.s, i), row_of(&a.s, v as usize));
            assert_eq!(mine.len(), whole.len(), "{}: vertex {v}", c.name);
            for ((c1, w1), (c2, w2)) in mine.iter().zip(&whole) {
                assert!(c1 == c2 && (w1 - w2).abs() <= 1e-15 * w2.abs().max(1.0), "{}: vertex {v}", c.name);
            }
        }
        checked += 1;
    }
    assert!(checked >= 3, "Loop cases: {checked}");
}

/// `limit_points_with_options` (no plan, no copy of the connectivity) gives
/// the plan's limit points bit for bit, on every tagged case (peer files and
/// constructed: semi-sharp ones refine first) and untagged meshes of both
/// schemes.
#[test]
fn limit_points_without_a_plan_are_the_plans() {
    for c in &all_cases() {
        let t = c.mesh.topology();
        let plan = SubdivisionPlan::with_tags(t, &c.tags, c.options, 0).unwrap();
        let expected = plan.limit_points(c.mesh.positions()).unwrap();
        let direct = subdiv_stencil::limit_points_with_options(t, &c.tags, c.options, c.mesh.positions()).unwrap();
        assert_eq!(direct.as_deref(), Some(&expected[..]), "{}", c.name);
    }
    for (mesh, scheme) in [
        (shapes::torus(7, 5), Scheme::CatmullClark),
        (subdiv_mesh::shapes::icosahedron(), Scheme::Loop(LoopBeta::Warren)),
    ] {
        let plan = SubdivisionPlan::new(mesh.topology(), scheme, 0).unwrap();
        let expected = plan.limit_points(mesh.positions()).unwrap();
        let direct =
            subdiv_stencil::limit_points_with_options(mesh.topology(), &Tags::none(), scheme, mesh.positions())
                .unwrap();
        assert_eq!(direct, Some(expected));
    }
    let deng_ma = Scheme::DengMa(subdiv_stencil::Tension::Global(1.0));
    let cube = shapes::cube();
    assert_eq!(
        subdiv_stencil::limit_points_with_options(cube.topology(), &Tags::none(), deng_ma, cube.positions()).unwrap(),
        None
    );
}
