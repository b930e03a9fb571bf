//! Doo-Sabin with infinitely sharp creases and corners: the claims of
//! `subdiv_stencil::doo_sabin` ("Creases and corners"), each checked against
//! an independent derivation — curve rules of `subdiv_rules::curves`, a
//! de Boor evaluator of quadratic B-splines written here, and 8 levels of
//! brute-force refinement — never against the operators' own output.

use crate::common::Mask;

use glam::DVec3;
use std::sync::OnceLock;
use subdiv_mesh::refine::{dual_split_tagged, DualFeatures};
use subdiv_mesh::{shapes, EdgeTag, Mesh, TagList, Tags, Topology, VertexId, VertexTag, SHARPNESS_INFINITE};
use subdiv_rules::curves;
use subdiv_stencil::doo_sabin;
use subdiv_stencil::{apply, row_sums, StencilError};

// ---------------------------------------------------------------- fixtures

/// Tags with the given creases (vertex pairs) and corners, all at 10.
fn tags(t: &Topology, creases: &[(u32, u32)], corners: &[u32]) -> Tags {
    let list = TagList {
        creases: creases.iter().map(|&(a, b)| EdgeTag { a, b, sharpness: SHARPNESS_INFINITE }).collect(),
        corners: corners.iter().map(|&vertex| VertexTag { vertex, sharpness: SHARPNESS_INFINITE }).collect(),
        ..Default::default()
    };
    Tags::from_list(t, &list).expect("the test tags name edges and vertices of the mesh")
}

/// The cube's vertex i sits at (i & 1, i >> 1 & 1, i >> 2 & 1); its top face (z = 1) is 4 5 7 6.
const CUBE_EDGES: [(u32, u32); 12] =
    [(0, 1), (2, 3), (4, 5), (6, 7), (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7)];
const CUBE_TOP: [(u32, u32); 4] = [(4, 5), (5, 7), (7, 6), (6, 4)];

/// An n×n grid on [0, 1]² (vertex (n+1)r + c at (c/n, r/n)) lifted to a
/// non-polynomial height, so that no rule is exact by accident.
fn bumpy_grid(n: usize) -> Mesh {
    let grid = shapes::quad_grid(n, n);
    let p = grid.positions().iter().map(|p| {
        let (x, y) = (p.x / n as f64, p.y / n as f64);
        DVec3::new(
            x,
            y,
            0.2 * (2.0 * std::f64::consts::PI * x + 0.5).sin() * (1.3 * std::f64::consts::PI * y).cos()
                + 0.15 * x * x * y,
        )
    });
    grid.with_positions(p.collect())
}

/// The tagged test meshes: each kind of sharp piece (closed loop, corner to
/// corner, dart to dart, corner to dart) and each kind of corner (three
/// sharp edges, tagged on a crease or a boundary, tagged with no sharp edge).
fn cases() -> Vec<(&'static str, Mesh, Tags)> {
    let cube = shapes::cube();
    let ct = cube.topology();
    let cases_cube = [
        ("cube, all 12 edges sharp", tags(ct, &CUBE_EDGES, &[])),
        ("cube, top loop sharp", tags(ct, &CUBE_TOP, &[])),
        ("cube, one sharp edge", tags(ct, &[(4, 5)], &[])),
    ];
    let mut out: Vec<_> = cases_cube.into_iter().map(|(name, tags)| (name, cube.clone(), tags)).collect();
    // 6×6 grid: vertex 7r + c. Row r = 3 boundary to boundary (its ends are
    // corners: three sharp edges); row r = 1 from the boundary (a corner) to
    // c = 4 (a dart); row r = 5 from c = 1 to c = 5 (darts at both ends);
    // tagged corners on the boundary (vertex 3), on row 3 (vertex 24) and
    // with no sharp edge (vertex 16, a cone).
    let grid = bumpy_grid(6);
    let row = |r: u32, c0: u32, c1: u32| (c0..c1).map(move |c| (7 * r + c, 7 * r + c + 1));
    let creases: Vec<(u32, u32)> = row(3, 0, 6).chain(row(1, 0, 4)).chain(row(5, 1, 5)).collect();
    out.push(("grid, crease rows", grid.clone(), tags(grid.topology(), &creases, &[])));
    out.push(("grid, crease rows and tagged corners", grid.clone(), tags(grid.topology(), &creases, &[3, 24, 16])));
    out
}

/// Positions and tags of one level of a tagged refinement.
struct Level {
    topology: Topology,
    tags: Tags,
    positions: Vec<DVec3>,
}

/// Brute force: `levels` tagged Doo-Sabin steps (topology by
/// `dual_split_tagged`, positions by `first_step_tagged`), level 0 first.
fn refine_levels(mesh: &Mesh, tags: &Tags, levels: usize) -> Vec<Level> {
    let mut out =
        vec![Level { topology: mesh.topology().clone(), tags: tags.clone(), positions: mesh.positions().to_vec() }];
    for _ in 0..levels {
        let last = out.last().expect("level 0");
        let (topology, _, tags) = dual_split_tagged(&last.topology, &last.tags);
        let positions =
            doo_sabin::first_step_tagged(&last.topology, &last.tags, &Mask::Standard, &last.positions).unwrap();
        assert_eq!(positions.len(), topology.vertex_count());
        out.push(Level { topology, tags, positions });
    }
    out
}

/// Brute-force levels shared by the tests: 8 levels of each cube case, 7 of
/// each grid case (8 would be 2.4 M faces; 7 already refines each grid edge
/// 128 times).
fn deep(case: usize) -> &'static [Level] {
    static DEEP: OnceLock<Vec<OnceLock<Vec<Level>>>> = OnceLock::new();
    let all = DEEP.get_or_init(|| cases().iter().map(|_| OnceLock::new()).collect());
    all[case].get_or_init(|| {
        let (_, mesh, tags) = &cases()[case];
        refine_levels(mesh, tags, if mesh.topology().face_count() <= 6 { 8 } else { 7 })
    })
}

fn bbox_diagonal(p: &[DVec3]) -> f64 {
    let (lo, hi) = p.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &q| (lo.min(q), hi.max(q)));
    lo.distance(hi)
}

// ---------------------------------------------------------------- sharp pieces

/// How a piece of the sharp polygon ends.
#[derive(Clone, Copy, Debug, PartialEq)]
enum End {
    Corner,
    Dart,
}

/// A piece of the sharp (crease or boundary) polygon between corners or
/// darts, or a closed loop through crease vertices only.
#[derive(Debug)]
struct Piece {
    vertices: Vec<VertexId>,
    ends: Option<(End, End)>,
}

/// The pieces of the sharp polygon of a level, walked along its sharp edges.
fn sharp_pieces(t: &Topology, tags: &Tags) -> Vec<Piece> {
    let f = DualFeatures::new(t, tags);
    let neighbours = |v: VertexId| -> Vec<VertexId> { f.sharp_neighbors(t, v).collect() };
    let end_kind = |v: VertexId| match (f.is_corner(v), neighbours(v).len()) {
        (true, _) => Some(End::Corner),
        (false, 1) => Some(End::Dart),
        _ => None,
    };
    let mut used = std::collections::HashSet::new();
    let key = |a: VertexId, b: VertexId| (a.0.min(b.0), a.0.max(b.0));
    let walk = |start: VertexId, first: VertexId, used: &mut std::collections::HashSet<(u32, u32)>| {
        let mut vertices = vec![start];
        let (mut prev, mut at) = (start, first);
        used.insert(key(start, first));
        loop {
            vertices.push(at);
            if at == start || end_kind(at).is_some() {
                break;
            }
            let next = *neighbours(at).iter().find(|&&n| n != prev).expect("a crease vertex has two sharp edges");
            used.insert(key(at, next));
            (prev, at) = (at, next);
        }
        vertices
    };
    let mut pieces = Vec::new();
    for v in t.vertices().filter(|&v| end_kind(v).is_some()) {
        for n in neighbours(v) {
            if !used.contains(&key(v, n)) {
                let vertices = walk(v, n, &mut used);
                let ends = (end_kind(v).unwrap(), end_kind(*vertices.last().unwrap()).unwrap());
                pieces.push(Piece { vertices, ends: Some(ends) });
            }
        }
    }
    for v in t.vertices() {
        for n in neighbours(v) {
            if !used.contains(&key(v, n)) {
                let mut vertices = walk(v, n, &mut used);
                vertices.pop(); // back at the start
                pieces.push(Piece { vertices, ends: None });
            }
        }
    }
    pieces
}

/// One step of a piece by the documented curve rules, from `subdiv_rules::curves`:
/// closed Chaikin for a loop, open (clamped) Chaikin between corners, and at a
/// dart end Chaikin's pair of the last edge (no end rule).
fn expected_step(p: &[DVec3], ends: Option<(End, End)>) -> Vec<DVec3> {
    let pts: Vec<[f64; 3]> = p.iter().map(|q| q.to_array()).collect();
    let to_vec = |v: Vec<[f64; 3]>| v.into_iter().map(DVec3::from_array).collect::<Vec<_>>();
    let Some((start, end)) = ends else { return to_vec(curves::chaikin(&pts, true)) };
    // Chaikin's pairs of the open edges (closed Chaikin without the closing edge).
    let mut free = to_vec(curves::chaikin(&pts, true));
    free.truncate(2 * (p.len() - 1));
    let n = p.len();
    match (start, end) {
        (End::Corner, End::Corner) => to_vec(curves::chaikin(&pts, false)),
        (End::Dart, End::Dart) => free,
        (corner_end, _) => {
            // One corner: the clamped rule at that end only (the point near the
            // other end of a one-edge piece is the midpoint too).
            let (c, other) = if corner_end == End::Corner { (0, 1) } else { (n - 1, n - 2) };
            let mid = (p[c] + p[other]) / 2.0;
            let mut out = free;
            if c == 0 {
                out[0] = p[0];
                out[1] = mid;
            } else {
                out[2 * n - 3] = p[n - 1];
                out[2 * n - 4] = mid;
            }
            out
        }
    }
}

/// Whether `a` equals `b` pointwise within `tol`, up to the reversal (and for
/// a closed piece the rotation) of `a`.
fn same_polyline(a: &[DVec3], b: &[DVec3], closed: bool, tol: f64) -> bool {
    if a.len() != b.len() {
        return false;
    }
    let n = a.len();
    let shifts = if closed { n } else { 1 };
    (0..shifts).any(|s| {
        let fwd = (0..n).all(|i| a[(i + s) % n].distance(b[i]) <= tol);
        let back = (0..n).all(|i| a[(s + n - i) % n].distance(b[i]) <= tol)
            || (!closed && (0..n).all(|i| a[n - 1 - i].distance(b[i]) <= tol));
        fwd || back
    })
}

fn positions_of(level: &Level, piece: &Piece) -> Vec<DVec3> {
    piece.vertices.iter().map(|v| level.positions[v.index()]).collect()
}

// ---------------------------------------------------------------- quadratic B-splines

/// A quadratic B-spline by de Boor's algorithm on integer knots, tripled at
/// each corner end (clamped) and uniform at a dart end or on a closed curve.
struct QuadraticBSpline {
    control: Vec<DVec3>,
    knots: Vec<f64>,
}

impl QuadraticBSpline {
    fn new(p: &[DVec3], ends: Option<(End, End)>) -> Self {
        let Some((start, end)) = ends else {
            // Closed: wrap two points, uniform knots.
            let n = p.len();
            let control: Vec<DVec3> = (0..n + 2).map(|i| p[i % n]).collect();
            let knots = (0..control.len() + 3).map(|k| k as f64).collect();
            return Self { control, knots };
        };
        let n = p.len();
        let mut knots: Vec<f64> = (0..n + 3).map(|k| k as f64).collect();
        if start == End::Corner {
            for k in &mut knots {
                *k = (*k - 2.0).max(0.0);
            }
        }
        if end == End::Corner {
            let last = knots[n];
            for k in &mut knots[n..] {
                *k = last;
            }
        }
        Self { control: p.to_vec(), knots }
    }

    /// Points of the curve, `per_span` per knot span of its domain [t₂, t_n].
    fn samples(&self, per_span: usize) -> Vec<DVec3> {
        let n = self.control.len();
        let mut out = Vec::new();
        for span in 2..n {
            let (a, b) = (self.knots[span], self.knots[span + 1]);
            if b <= a {
                continue;
            }
            for s in 0..=per_span {
                out.push(self.eval(span, a + (b - a) * s as f64 / per_span as f64));
            }
        }
        out
    }

    fn eval(&self, span: usize, x: f64) -> DVec3 {
        let mut d: Vec<DVec3> = (0..=2).map(|j| self.control[span - 2 + j]).collect();
        for r in 1..=2 {
            for j in (r..=2).rev() {
                let i = span - 2 + j;
                let (lo, hi) = (self.knots[i], self.knots[i + 3 - r]);
                let alpha = if hi > lo { (x - lo) / (hi - lo) } else { 0.0 };
                d[j] = d[j - 1] * (1.0 - alpha) + d[j] * alpha;
            }
        }
        d[2]
    }
}

/// Largest distance from the points `a` to the polyline `b` (closed or not).
fn distance_to_polyline(a: &[DVec3], b: &[DVec3], closed: bool) -> f64 {
    let segments = if closed { b.len() } else { b.len() - 1 };
    let to_segment = |p: DVec3, i: usize| {
        let (s, e) = (b[i], b[(i + 1) % b.len()]);
        let t = ((p - s).dot(e - s) / (e - s).length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        p.distance(s + t * (e - s))
    };
    a.iter().map(|&p| (0..segments).map(|i| to_segment(p, i)).fold(f64::INFINITY, f64::min)).fold(0.0, f64::max)
}

// ---------------------------------------------------------------- tests

#[test]
fn stencil_rows_sum_to_one_and_the_step_is_the_stencil() {
    for (name, mesh, tags) in cases() {
        let levels = refine_levels(&mesh, &tags, 2);
        for (k, level) in levels.iter().enumerate() {
            let (t, x) = (&level.topology, &level.positions);
            let d = bbox_diagonal(x);
            let lambdas: Vec<f64> = (0..t.face_count()).map(|f| 0.3 + 0.4 * (f % 5) as f64 / 5.0).collect();
            for rule in [Mask::Standard, Mask::Uniform(0.5), Mask::PerFace(&lambdas)] {
                let r = doo_sabin::refinement_stencil_tagged(t, &level.tags, &rule).unwrap();
                assert_eq!(r.rows(), dual_split_tagged(t, &level.tags).0.vertex_count(), "{name} L{k}");
                for (i, s) in row_sums(&r).iter().enumerate() {
                    assert!((s - 1.0).abs() <= 1e-14, "{name} L{k} {rule:?}: row {i} sums to {s:.17}");
                }
                let step = doo_sabin::first_step_tagged(t, &level.tags, &rule, x).unwrap();
                let product = apply(&r, x);
                let gap = step.iter().zip(&product).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
                assert!(gap <= 1e-15 * d, "{name} L{k} {rule:?}: step vs R·x {gap:e}");
            }
            let limit = doo_sabin::limit_stencil_tagged(t, &level.tags).unwrap();
            for (i, s) in row_sums(&limit).iter().enumerate() {
                assert!((s - 1.0).abs() <= 1e-14, "{name} L{k}: limit row {i} sums to {s:.17}");
            }
            let points = doo_sabin::limit_points_tagged(t, &level.tags, x).unwrap();
            let gap = points.iter().zip(&apply(&limit, x)).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
            assert!(gap <= 1e-15 * d, "{name} L{k}: limit points vs stencil {gap:e}");
        }
    }
}

#[test]
fn empty_tags_give_the_untagged_operators_bit_for_bit() {
    let mut meshes = vec![shapes::cube(), bumpy_grid(5), shapes::torus(6, 4)];
    meshes.push(shapes::polygon_mix(&shapes::plate_with_holes(7, 6, &[(2, 1), (4, 3)], false), 5, 0.3, 0.2, 0.1));
    let bits = |p: &[DVec3]| p.iter().map(|q| q.to_array().map(f64::to_bits)).collect::<Vec<_>>();
    for mesh in &meshes {
        let (t, x) = (mesh.topology(), mesh.positions());
        let zero = Tags::from_arrays(t, vec![0.0; t.edge_count()], vec![0.0; t.vertex_count()]).unwrap();
        for tags in [Tags::none(), zero] {
            for rule in [Mask::Standard, Mask::Uniform(0.5)] {
                let (a, b) = (
                    doo_sabin::refinement_stencil(t, &rule).unwrap(),
                    doo_sabin::refinement_stencil_tagged(t, &tags, &rule).unwrap(),
                );
                assert_eq!((a.indptr().raw_storage(), a.indices()), (b.indptr().raw_storage(), b.indices()));
                assert!(a.data().iter().zip(b.data()).all(|(p, q)| p.to_bits() == q.to_bits()));
                let (p, q) = (
                    doo_sabin::first_step(t, &rule, x).unwrap(),
                    doo_sabin::first_step_tagged(t, &tags, &rule, x).unwrap(),
                );
                assert_eq!(bits(&p), bits(&q));
            }
            let (p, q) = (doo_sabin::limit_points(t, x), doo_sabin::limit_points_tagged(t, &tags, x).unwrap());
            assert_eq!(bits(&p), bits(&q));
            let (a, b) = (doo_sabin::limit_stencil(t), doo_sabin::limit_stencil_tagged(t, &tags).unwrap());
            assert_eq!(a.indices(), b.indices());
            assert!(a.data().iter().zip(b.data()).all(|(p, q)| p.to_bits() == q.to_bits()));
            let (plain, _, _) = doo_sabin::refine(t, &Mask::Standard).unwrap();
            let (tagged, _, new_tags, _) = doo_sabin::refine_tagged(t, &tags, &Mask::Standard).unwrap();
            assert_eq!(format!("{plain:?}"), format!("{tagged:?}"));
            assert!(new_tags.is_empty());
        }
    }
}

#[test]
fn semi_sharp_tags_are_a_typed_error() {
    let cube = shapes::cube();
    let t = cube.topology();
    let e = t.find_edge(VertexId(4), VertexId(5)).unwrap();
    let mut edges = vec![0.0; t.edge_count()];
    edges[e.index()] = 2.5;
    let edge_tags = Tags::from_arrays(t, edges, vec![]).unwrap();
    let mut vertices = vec![0.0; t.vertex_count()];
    vertices[7] = 9.99;
    let vertex_tags = Tags::from_arrays(t, vec![], vertices).unwrap();
    for (tags, what) in [(edge_tags, format!("edge {}", e.0)), (vertex_tags, "vertex 7".to_string())] {
        let results = [
            doo_sabin::refinement_stencil_tagged(t, &tags, &Mask::Standard).err(),
            doo_sabin::first_step_tagged(t, &tags, &Mask::Standard, cube.positions()).err(),
            doo_sabin::limit_stencil_tagged(t, &tags).err(),
            doo_sabin::limit_points_tagged(t, &tags, cube.positions()).err(),
            doo_sabin::refine_tagged(t, &tags, &Mask::Standard).err(),
        ];
        for err in results {
            match err {
                Some(StencilError::SemiSharpDooSabin { what: w, .. }) => assert!(w.starts_with(&what), "{w}"),
                other => panic!("expected a semi-sharp error for {what}, got {other:?}"),
            }
        }
    }
    // Infinitely sharp values of any size are accepted.
    let inf = Tags::from_arrays(t, vec![f32::INFINITY; t.edge_count()], vec![10.0; t.vertex_count()]).unwrap();
    assert!(doo_sabin::limit_points_tagged(t, &inf, cube.positions()).is_ok());
}

#[test]
fn face_centroids_are_limit_points() {
    // Brute force: after 7-8 levels the F-face descendant of every face of
    // levels 0 and 1 (F-faces keep their face's id) has that face's centroid
    // and has shrunk to a point.
    for (case, (name, _, _)) in cases().iter().enumerate() {
        let levels = deep(case);
        let last = levels.last().unwrap();
        let d = bbox_diagonal(&levels[0].positions);
        let depth = levels.len() - 1;
        for (k, level) in levels[..2].iter().enumerate() {
            for f in level.topology.face_ids() {
                let corners =
                    |l: &Level| -> Vec<DVec3> { l.topology.face(f).iter().map(|&v| l.positions[v as usize]).collect() };
                let (old, new) = (corners(level), corners(last));
                assert_eq!(old.len(), new.len(), "{name}: F-faces keep their size");
                let centroid = |p: &[DVec3]| p.iter().sum::<DVec3>() / p.len() as f64;
                let moved = centroid(&old).distance(centroid(&new));
                assert!(moved <= 1e-14 * d, "{name}: level-{k} face {f}'s centroid moved {moved:e}");
                let size = new.iter().map(|p| p.distance(centroid(&new))).fold(0.0, f64::max);
                let shrink = 2f64.powi(-((depth - k) as i32) + 1);
                assert!(size <= shrink * d, "{name}: level-{k} face {f} still {size:e} wide after {depth} levels");
            }
        }
    }
}

#[test]
fn sharp_polygon_refines_by_chaikin_level_by_level() {
    for (case, (name, _, _)) in cases().iter().enumerate() {
        let levels = &deep(case)[..4];
        let d = bbox_diagonal(&levels[0].positions);
        for k in 0..levels.len() - 1 {
            let (coarse, fine) = (&levels[k], &levels[k + 1]);
            let fine_pieces = sharp_pieces(&fine.topology, &fine.tags);
            let coarse_pieces = sharp_pieces(&coarse.topology, &coarse.tags);
            assert_eq!(coarse_pieces.len(), fine_pieces.len(), "{name} L{k}: every piece has one successor");
            for piece in &coarse_pieces {
                let expect = expected_step(&positions_of(coarse, piece), piece.ends);
                let found = fine_pieces.iter().any(|p| {
                    p.ends.is_none() == piece.ends.is_none()
                        && same_polyline(&positions_of(fine, p), &expect, piece.ends.is_none(), 1e-15 * d)
                });
                assert!(found, "{name} L{k}: no refined piece is the curve rule's step of {piece:?}");
            }
        }
    }
}

#[test]
fn limit_sharp_curve_is_the_quadratic_bspline_of_the_sharp_polygon() {
    for (case, (name, _, _)) in cases().iter().enumerate() {
        let levels = deep(case);
        let (first, last) = (&levels[0], levels.last().unwrap());
        let d = bbox_diagonal(&first.positions);
        let fine: Vec<Vec<DVec3>> =
            sharp_pieces(&last.topology, &last.tags).iter().map(|p| positions_of(last, p)).collect();
        for piece in sharp_pieces(&first.topology, &first.tags) {
            let control = positions_of(first, &piece);
            if control.len() < 3 && piece.ends.is_some() {
                continue; // a one-edge piece: a segment or a point, no quadratic
            }
            // 37 samples per span: not at the fine levels' knots (dyadic
            // parameters), where the curve touches its refined polygon.
            let curve = QuadraticBSpline::new(&control, piece.ends).samples(37);
            // The curve's samples lie on some piece of the fine sharp polygon,
            // which approaches it quadratically: within 4^-levels of the
            // coarse spacing.
            let spacing = control.windows(2).map(|w| w[0].distance(w[1])).fold(0.0, f64::max);
            let tol = spacing * 4f64.powi(-(levels.len() as i32 - 1));
            let best = fine
                .iter()
                .map(|p| distance_to_polyline(&curve, p, piece.ends.is_none()))
                .fold(f64::INFINITY, f64::min);
            assert!(best <= tol, "{name}: {piece:?}: the limit curve is {best:e} off the B-spline (tol {tol:e})");
            assert!(best <= 1e-3 * d, "{name}");
        }
    }
}

#[test]
fn limit_points_are_points_of_the_brute_force_surface() {
    for (case, (name, _, _)) in cases().iter().enumerate() {
        let levels = deep(case);
        let (first, last) = (&levels[0], levels.last().unwrap());
        let d = bbox_diagonal(&first.positions);
        let features = DualFeatures::new(&first.topology, &first.tags);
        let limit = doo_sabin::limit_points_tagged(&first.topology, &first.tags, &first.positions).unwrap();
        let depth = levels.len() as i32 - 1;
        for v in first.topology.vertices() {
            let l = limit[v.index()];
            let nearest = last.positions.iter().map(|p| p.distance(l)).fold(f64::INFINITY, f64::min);
            if features.is_corner(v) {
                // Corners are kept exactly, at every level.
                assert_eq!(l, first.positions[v.index()], "{name}: corner {v}");
                assert_eq!(nearest, 0.0, "{name}: corner {v} is a vertex of every level");
            } else {
                assert!(nearest <= 2f64.powi(2 - depth) * d, "{name}: limit of {v} is {nearest:e} off the surface");
            }
        }
        // A smooth vertex's or a dart's limit is the centroid of a face of
        // level 1 (its V-face), hence a limit point (face centroids are).
        let one = &levels[1];
        let centroids: Vec<DVec3> = one
            .topology
            .face_ids()
            .map(|f| {
                let face = one.topology.face(f);
                face.iter().map(|&c| one.positions[c as usize]).sum::<DVec3>() / face.len() as f64
            })
            .collect();
        for v in first.topology.vertices() {
            let sharp = features.sharp_neighbors(&first.topology, v).count();
            if features.is_corner(v) || sharp == 2 || first.topology.valence(v) == 2 {
                continue; // kept, on the sharp curve, or the valence-2 mask
            }
            let gap = centroids.iter().map(|c| c.distance(limit[v.index()])).fold(f64::INFINITY, f64::min);
            assert!(gap <= 1e-14 * d, "{name}: limit of vertex {v} ({sharp} sharp edges) is no face centroid: {gap:e}");
        }
        // A crease vertex's limit is the midpoint of its segment of the sharp
        // polygon, at every level: some fine sharp edge has that midpoint and
        // has shrunk.
        let fine = DualFeatures::new(&last.topology, &last.tags);
        let sharp_edges: Vec<(DVec3, f64)> = last
            .topology
            .edges()
            .filter(|&e| fine.is_sharp(&last.topology, e))
            .map(|e| {
                let (a, b) = last.topology.edge_vertices(e);
                let (pa, pb) = (last.positions[a.index()], last.positions[b.index()]);
                ((pa + pb) / 2.0, pa.distance(pb))
            })
            .collect();
        for v in first.topology.vertices() {
            if features.is_corner(v) || features.sharp_neighbors(&first.topology, v).count() != 2 {
                continue;
            }
            let l = limit[v.index()];
            let (gap, length) = sharp_edges
                .iter()
                .map(|&(m, len)| (m.distance(l), len))
                .fold((f64::INFINITY, 0.0), |a, b| if b.0 < a.0 { b } else { a });
            assert!(
                gap <= 1e-14 * d,
                "{name}: no fine sharp segment is centred on crease vertex {v}'s limit ({gap:e})"
            );
            assert!(length <= 2f64.powi(1 - depth) * d, "{name}: vertex {v}'s segment is still {length:e} long");
        }
    }
}

#[test]
fn all_sharp_cube_stays_on_the_cube() {
    // What holds: every face of every level lies in one face of the cube (a
    // face's corner images are convex combinations of its corners, all in one
    // cube face, and the sharp points lie on the cube's edges), so every
    // refined point is on the cube's surface; the corners stay exactly, points
    // on the edges keep two coordinates exactly 0 or 1 (the edges stay
    // straight: the clamped quadratic of two points is the segment), and the
    // sheets fill the faces: the limit surface is the cube itself.
    let levels = deep(0);
    for (k, level) in levels.iter().enumerate() {
        let features = DualFeatures::new(&level.topology, &level.tags);
        for v in level.topology.vertices() {
            let p = level.positions[v.index()];
            let inside = p.cmpge(DVec3::splat(-1e-15)).all() && p.cmple(DVec3::splat(1.0 + 1e-15)).all();
            assert!(inside, "L{k}: {p} outside the cube");
            let on_planes = p.to_array().iter().filter(|&&c| c == 0.0 || c == 1.0).count();
            let off_surface = p.to_array().iter().map(|&c| c.min(1.0 - c)).fold(f64::INFINITY, f64::min);
            assert!(off_surface <= 1e-15, "L{k}: vertex {v} at {p} is {off_surface:e} off the surface");
            if features.sharp_neighbors(&level.topology, v).count() > 0 {
                assert!(on_planes >= 2, "L{k}: sharp vertex {v} at {p} is not exactly on a cube edge");
            }
            if features.is_corner(v) {
                assert_eq!(on_planes, 3, "L{k}: corner {v} at {p}");
            }
        }
    }
    // The sheets fill the faces: every point of a 17×17 sample of each face
    // is within a few spacings of a vertex of level 5.
    let last = &levels[5];
    let mut worst: f64 = 0.0;
    for axis in 0..3 {
        for side in [0.0, 1.0] {
            for i in 0..=16 {
                for j in 0..=16 {
                    let mut p = [0.0; 3];
                    p[axis] = side;
                    p[(axis + 1) % 3] = i as f64 / 16.0;
                    p[(axis + 2) % 3] = j as f64 / 16.0;
                    let p = DVec3::from_array(p);
                    worst = worst.max(last.positions.iter().map(|q| q.distance(p)).fold(f64::INFINITY, f64::min));
                }
            }
        }
    }
    assert!(worst <= 2f64.powi(-5), "a sample point of the cube is {worst:e} from the refined mesh");
    let cube = shapes::cube();
    let limit = doo_sabin::limit_points_tagged(cube.topology(), &levels[0].tags, cube.positions()).unwrap();
    assert_eq!(limit, cube.positions(), "the limit of every corner is the corner");
}

#[test]
fn tagged_corner_splits_the_sharp_curve_and_is_kept() {
    // Grid case with tagged corners: the boundary curve and crease row 3 are
    // split at vertices 3 and 24 into end-interpolating pieces; vertex 16 (no
    // sharp edge) is a cone point of the surface.
    let case = 4;
    let levels = deep(case);
    let first = &levels[0];
    for v in [3, 24, 16] {
        let p = first.positions[v];
        for (k, level) in levels.iter().enumerate() {
            assert!(level.positions.contains(&p), "level {k}: tagged corner {v} is not kept");
        }
    }
    let untagged = sharp_pieces(&deep(3)[0].topology, &deep(3)[0].tags);
    let tagged = sharp_pieces(&first.topology, &first.tags);
    // Vertex 3 splits a piece of the boundary (between the corners that the
    // crease rows make on it), vertex 24 splits row 3: two more pieces.
    assert_eq!(tagged.len(), untagged.len() + 2);
    for piece in &tagged {
        for &v in &piece.vertices[1..piece.vertices.len() - 1] {
            assert!(![3, 24].contains(&v.0), "a piece runs through tagged corner {v}");
        }
    }
}
