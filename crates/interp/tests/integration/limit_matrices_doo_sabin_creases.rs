//! The Doo-Sabin limit matrices (Nasri's C, Zheng-Cai's Z, Fan-Cheng-Lai's
//! B(λ)) with infinitely sharp creases and corners
//! (`limit_matrix_doo_sabin_sharp`), checked against what the refined meshes
//! say, never against the matrices' own output:
//!
//! - row by row, A·X equals the limit point read off the first refined mesh
//!   M¹ = `first_step_tagged(t, tags, rule, X)` on `dual_split_tagged`'s
//!   connectivity, found here from the tags and the provenance alone (a
//!   vertex's V-faces and the sharp points in them, its kept corner point, a
//!   valence-2 vertex's E-face one level further), and `doo_sabin_limit_sites`
//!   names the same places;
//! - for the standard rule, A equals `doo_sabin::limit_stencil_tagged`;
//! - brute force: 8 levels of tagged Doo-Sabin (`subdivide`) after the
//!   method's first step, every predicted point stays the centroid of its
//!   tracked face (the midpoint of its sharp segment, the corner itself) and
//!   the face shrinks onto it, followed on that face alone to 1e-6·d;
//! - the row kinds, D and S of every kind, symmetry where the docs promise
//!   it, the sharp block and the solve order, and the spectra of the blocks
//!   (dense nalgebra): crease blocks exactly the documented cosines, smooth
//!   blocks in [¼, 1] (C), [½, 1] (Z), [min λ, 1] (B(λ)), the interior with
//!   general rows measured (printed with --nocapture);
//! - without tags (or with all-zero tags) the untagged matrices bit for bit,
//!   and smooth rows next to creases bit for bit the untagged rows;
//!   semi-sharp tags and bad λ are typed errors.

use glam::DVec3;
use nalgebra::{DMatrix, SymmetricEigen};
use std::collections::{BTreeSet, HashMap};
use subdiv_interp::{limit_matrix_nasri, limit_matrix_two_phase, limit_matrix_zheng_cai, solve_blocks, CornerRule};
use subdiv_mesh::refine::{dual_split_tagged, DualFace, SharpPoint};
use subdiv_mesh::{shapes, EdgeId, EdgeTag, FaceId, Mesh, TagList, Tags, Topology, VertexId, VertexTag};
use subdiv_stencil::doo_sabin;
use subdiv_stencil::{
    doo_sabin_limit_sites, limit_matrix_doo_sabin_sharp, subdivide, DualLimitSite, LimitMatrix, RowKind, Scheme,
    StencilError,
};

// ---------------------------------------------------------------- fixtures

const INFINITE: f32 = 10.0;

/// Tags with the given creases (vertex pairs) and corners, all at 10.
fn tags(t: &Topology, creases: &[(u32, u32)], corners: &[u32]) -> Tags {
    let list = TagList {
        creases: creases.iter().map(|&(a, b)| EdgeTag { a, b, sharpness: INFINITE }).collect(),
        corners: corners.iter().map(|&vertex| VertexTag { vertex, sharpness: INFINITE }).collect(),
        ..Default::default()
    };
    Tags::from_list(t, &list).expect("the test tags name edges and vertices of the mesh")
}

fn edge_between(t: &Topology, a: u32, b: u32) -> EdgeId {
    t.edges()
        .find(|&e| {
            let (x, y) = t.edge_vertices(e);
            (x.0, y.0) == (a, b) || (x.0, y.0) == (b, a)
        })
        .unwrap_or_else(|| panic!("no edge {a}-{b}"))
}

/// An n×n grid on [0, 1]² (vertex (n+1)r + c at (c/n, r/n)) lifted to a
/// non-polynomial height, so that no rule is exact by accident.
fn bumpy_grid(n: usize) -> Mesh {
    let grid = shapes::quad_grid(n, n);
    let p = grid.positions().iter().map(|p| {
        let (x, y) = (p.x / n as f64, p.y / n as f64);
        DVec3::new(x, y, 0.2 * (6.3 * x + 0.5).sin() * (4.1 * y).cos() + 0.15 * x * x * y)
    });
    grid.with_positions(p.collect())
}

/// The cube's vertex i sits at (i & 1, i >> 1 & 1, i >> 2 & 1); its top face (z = 1) is 4 5 7 6.
const CUBE_EDGES: [(u32, u32); 12] =
    [(0, 1), (2, 3), (4, 5), (6, 7), (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7)];
const CUBE_TOP: [(u32, u32); 4] = [(4, 5), (5, 7), (7, 6), (6, 4)];

/// Torus vertex (i around the axis, j around the tube) of `shapes::torus(nu, nv)`.
fn tid(nv: usize, i: usize, j: usize, nu: usize) -> u32 {
    ((i % nu) * nv + (j % nv)) as u32
}

/// The cube with one more, isolated vertex.
fn cube_with_isolated_vertex() -> Mesh {
    let cube = shapes::cube();
    let mut p = cube.positions().to_vec();
    p.push(DVec3::splat(3.0));
    let t = Topology::new(cube.topology().faces().clone(), p.len()).unwrap();
    Mesh::from_topology(t, p)
}

struct Case {
    name: &'static str,
    mesh: Mesh,
    tags: Tags,
}

fn case(name: &'static str, mesh: Mesh, creases: &[(u32, u32)], corners: &[u32]) -> Case {
    let tags = tags(mesh.topology(), creases, corners);
    Case { name, mesh, tags }
}

/// A tube ring (closed crease loop), a crease polygon between two corner
/// tags and, on split edges, a valence-2 crease vertex, a valence-2 dart and
/// a smooth valence-2 vertex next to the ring: torus (nu, nv).
fn torus_case(name: &'static str, nu: usize, nv: usize, ring: bool, polyline: bool, valence_two: bool) -> Case {
    let id = |i, j| tid(nv, i, j, nu);
    let mut mesh = shapes::torus(nu, nv);
    let mut creases: Vec<(u32, u32)> = Vec::new();
    let mut corners = Vec::new();
    let n = mesh.topology().vertex_count() as u32;
    let mut ring_edges: Vec<(u32, u32)> = (0..nv).map(|j| (id(0, j), id(0, j + 1))).collect();
    if valence_two {
        let t = mesh.topology();
        // New vertices n, n + 1, n + 2 (split_edges numbers them in list order).
        let split = [
            edge_between(t, id(0, 0), id(0, 1)),
            edge_between(t, id(3, 0), id(3, 1)),
            edge_between(t, id(0, 2), id(1, 2)),
        ];
        mesh = shapes::split_edges(&mesh, &split, 0.1);
        // The ring through the valence-2 vertex n; a dart at the valence-2 vertex n + 1.
        ring_edges[0] = (id(0, 0), n);
        ring_edges.push((n, id(0, 1)));
        creases.push((id(3, 0), n + 1));
    }
    if ring {
        creases.extend(ring_edges);
    }
    if polyline {
        let j = nv / 2;
        creases.extend((1..nu - 1).map(|i| (id(i, j), id(i + 1, j))));
        corners.extend([id(1, j), id(nu - 1, j)]);
    }
    case(name, mesh, &creases, &corners)
}

/// The tagged test meshes: every row kind (smooth, crease between smooth /
/// corner neighbours, dart with a smooth or a corner end, corners by tag, by
/// three sharp edges and without sharp edge, isolated, valence 2 smooth /
/// crease / dart), closed loops and open pieces of every length, pieces that
/// end at darts, open and closed meshes.
fn cases() -> Vec<Case> {
    let cube = shapes::cube();
    // 5×5 grid, vertex 6r + c: row r = 2 boundary to boundary (corners 12
    // and 17 there), a vertical crease from 15 (a corner: three sharp edges)
    // up to the dart 27, and the dart 25 whose crease ends at the boundary
    // corner 31; a corner tag with no sharp edge at 8 (a cone).
    let grid = bumpy_grid(5);
    let mut grid_creases: Vec<(u32, u32)> = (0..5).map(|c| (12 + c, 13 + c)).collect();
    grid_creases.extend([(15, 21), (21, 27), (25, 31)]);
    // An open polygon mix with creases on every 4th interior edge (darts,
    // crease vertices and corners at random), a corner tag on a smooth
    // vertex and one on the boundary.
    let mix = shapes::polygon_mix(&shapes::plate_with_holes(6, 5, &[(2, 2)], false), 5, 0.3, 0.3, 0.05);
    let mt = mix.topology();
    let mix_creases: Vec<(u32, u32)> = mt
        .edges()
        .filter(|&e| !mt.is_boundary_edge(e) && e.0 % 4 == 0)
        .map(|e| {
            let (a, b) = mt.edge_vertices(e);
            (a.0, b.0)
        })
        .collect();
    let mix_tags_probe = tags(mt, &mix_creases, &[]);
    let features = subdiv_mesh::refine::DualFeatures::new(mt, &mix_tags_probe);
    let smooth = mt.vertices().find(|&v| features.sharp_edge_count(mt, v) == 0).unwrap().0;
    let on_boundary = mt.vertices().find(|&v| mt.is_boundary_vertex(v) && !features.is_corner(v)).unwrap().0;
    vec![
        case("cube, all 12 edges sharp", cube.clone(), &CUBE_EDGES, &[]),
        case("cube, top loop sharp", cube.clone(), &CUBE_TOP, &[]),
        case("cube, top loop, a cone corner and an isolated vertex", cube_with_isolated_vertex(), &CUBE_TOP, &[0]),
        case("grid, crease row to the boundary and darts", grid, &grid_creases, &[8]),
        case("open polygon mix, random creases", mix, &mix_creases, &[smooth, on_boundary]),
        torus_case("torus, a ring crease", 8, 6, true, false, false),
        torus_case("torus, a crease polygon between two corner tags", 8, 6, false, true, false),
        torus_case("torus, valence 2 on, next to and at the end of creases", 6, 5, true, true, true),
    ]
}

/// Smaller cases for the brute force (8 levels stay below a million faces).
fn small_cases() -> Vec<Case> {
    let cube = shapes::cube();
    // 3×3 grid, vertex 4r + c: row r = 1 boundary to boundary (corners 4,
    // 7), the crease 9-10-14 from the dart 9 to the boundary corner 14.
    let grid = bumpy_grid(3);
    let mix = shapes::polygon_mix(&shapes::plate_with_holes(4, 3, &[(1, 1)], false), 7, 0.4, 0.4, 0.05);
    let mt = mix.topology();
    let mix_creases: Vec<(u32, u32)> = mt
        .edges()
        .filter(|&e| !mt.is_boundary_edge(e) && e.0 % 3 == 0)
        .map(|e| {
            let (a, b) = mt.edge_vertices(e);
            (a.0, b.0)
        })
        .collect();
    vec![
        case("cube, all 12 edges sharp", cube.clone(), &CUBE_EDGES, &[]),
        case("cube, top loop, a cone corner", cube, &CUBE_TOP, &[0]),
        case("grid 3×3, crease row and a dart", grid, &[(4, 5), (5, 6), (6, 7), (9, 10), (10, 14)], &[]),
        case("open polygon mix, random creases", mix, &mix_creases, &[]),
        torus_case("torus 4×3, ring, polyline between corner tags", 4, 3, true, true, false),
        torus_case("torus 4×3, valence 2", 4, 3, true, false, true),
    ]
}

/// λ per face in [0.2, 0.8], not uniform.
fn lambdas(t: &Topology) -> Vec<f64> {
    (0..t.face_count()).map(|f| 0.2 + 0.6 * ((f * 7) % 5) as f64 / 4.0).collect()
}

/// The three first-step rules of the family, named.
fn rules(l: &[f64]) -> [(&'static str, CornerRule<'_>); 3] {
    [("C", CornerRule::Standard), ("Z", CornerRule::Uniform(0.5)), ("B(λ)", CornerRule::PerFace(l))]
}

/// Random points near the mesh (SplitMix64), so no rule is exact by accident.
fn random_points(mesh: &Mesh, seed: u64) -> Vec<DVec3> {
    let mut rng = shapes::SplitMix64(seed);
    let scale = shapes::mean_edge_length(mesh);
    let mut r = || rng.next_f64() - 0.5;
    mesh.positions().iter().map(|&p| p + 0.3 * scale * DVec3::new(r(), r(), r())).collect()
}

fn bbox_diagonal(p: &[DVec3]) -> f64 {
    let (lo, hi) = p.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &q| (lo.min(q), hi.max(q)));
    lo.distance(hi)
}

// ------------------------------------------- independent classification

/// What the tags make of a vertex, counted here from the tags: its sharp
/// neighbours (crease edges ≥ 10 and boundary edges) and whether it is a
/// corner (tag ≥ 10 or ≥ 3 sharp edges).
struct Sharpness {
    neighbours: Vec<Vec<u32>>,
    corner: Vec<bool>,
}

fn sharpness(t: &Topology, tags: &Tags) -> Sharpness {
    let mut neighbours = vec![Vec::new(); t.vertex_count()];
    for e in t.edges() {
        if t.is_boundary_edge(e) || tags.edge_sharpness(e) >= INFINITE {
            let (a, b) = t.edge_vertices(e);
            neighbours[a.index()].push(b.0);
            neighbours[b.index()].push(a.0);
        }
    }
    let corner = t
        .vertices()
        .map(|v| !t.is_isolated(v) && (tags.vertex_sharpness(v) >= INFINITE || neighbours[v.index()].len() >= 3))
        .collect();
    Sharpness { neighbours, corner }
}

/// The row kind the docs promise for v.
fn expected_kind(t: &Topology, s: &Sharpness, v: VertexId) -> RowKind {
    let sharp = s.neighbours[v.index()].len();
    if t.is_isolated(v) || s.corner[v.index()] {
        RowKind::Corner
    } else if sharp == 2 {
        RowKind::Crease
    } else if sharp == 1 || t.vertex_face_count(v) == 2 {
        RowKind::General // a dart, or an interior valence-2 vertex
    } else {
        RowKind::Smooth
    }
}

// ---------------------------------------------- limits read off M¹

/// The limit point of every input vertex (NaN for an isolated one), read off
/// the refined meshes: a corner's kept point (the sharp point naming it); a
/// crease or boundary vertex's two sharp points, found as the points of the
/// refined sharp polygon in its V-faces (its sectors share that segment);
/// the centroid of the one V-face of a smooth vertex or a dart; for an
/// interior valence-2 vertex (no V-face), the centroid of the E-face of the
/// edge between its two images in M² (a face centroid of M², hence a limit
/// point). Also returns the M¹ places found, to compare with the sites.
fn read_off_refined(
    t: &Topology,
    tags: &Tags,
    rule: CornerRule<'_>,
    x: &[DVec3],
) -> (Vec<DVec3>, Vec<Option<DualLimitSite>>) {
    let (t1, prov, tags1) = dual_split_tagged(t, tags);
    let x1 = doo_sabin::first_step_tagged(t, tags, &rule, x).unwrap();
    let s = sharpness(t, tags);
    let nh = t.half_edge_count() as u32;
    let mut v_faces: Vec<Vec<FaceId>> = vec![Vec::new(); t.vertex_count()];
    for (f, o) in prov.face_origin.iter().enumerate() {
        if let DualFace::V(v) = *o {
            v_faces[v.index()].push(FaceId(f as u32));
        }
    }
    let centroid = |t: &Topology, x: &[DVec3], f: FaceId| {
        t.face(f).iter().map(|&c| x[c as usize]).sum::<DVec3>() / t.face_size(f) as f64
    };
    let mut second = None;
    let mut out = Vec::new();
    let mut sites = Vec::new();
    for v in t.vertices() {
        let (p, site) = if t.is_isolated(v) {
            (DVec3::NAN, None)
        } else if s.corner[v.index()] {
            let i = prov.sharp_points.iter().position(|&q| q == SharpPoint::Corner { vertex: v }).unwrap();
            let id = VertexId(nh + i as u32);
            (x1[id.index()], Some(DualLimitSite::Corner(id)))
        } else if s.neighbours[v.index()].len() == 2 {
            let points: BTreeSet<u32> =
                v_faces[v.index()].iter().flat_map(|&f| t1.face(f).iter().copied()).filter(|&c| c >= nh).collect();
            assert_eq!(points.len(), 2, "crease vertex {v}: sharp points {points:?} in its V-faces");
            let [a, b]: [u32; 2] = points.into_iter().collect::<Vec<_>>().try_into().unwrap();
            ((x1[a as usize] + x1[b as usize]) / 2.0, Some(DualLimitSite::SharpMidpoint(VertexId(a), VertexId(b))))
        } else if let [f] = v_faces[v.index()][..] {
            let sharp_corners = t1.face(f).iter().filter(|&&c| c >= nh).count();
            let dart = s.neighbours[v.index()].len() == 1;
            assert_eq!(sharp_corners, usize::from(dart), "vertex {v}: V-face with {sharp_corners} sharp points");
            assert_eq!(t1.face_size(f), t.vertex_face_count(v) + usize::from(dart), "vertex {v}: V-face size");
            (centroid(&t1, &x1, f), Some(DualLimitSite::FaceCentroid(f)))
        } else {
            assert!(v_faces[v.index()].is_empty() && t.vertex_face_count(v) == 2, "vertex {v}");
            // The images of v are its corners (M¹ vertex = old half-edge id).
            let fan = t.vertex_fan(v);
            let (a, b) = (fan[0].0, fan[1].0);
            let (t2, prov2, x2) = second.get_or_insert_with(|| {
                let (t2, prov2, _) = dual_split_tagged(&t1, &tags1);
                let x2 = doo_sabin::first_step_tagged(&t1, &tags1, &CornerRule::Standard, &x1).unwrap();
                (t2, prov2, x2)
            });
            let e = edge_between(&t1, a, b);
            let f = prov2.face_origin.iter().position(|&o| o == DualFace::E(e)).unwrap();
            (centroid(t2, x2, FaceId(f as u32)), Some(DualLimitSite::ValenceTwoEdge(VertexId(a), VertexId(b))))
        };
        out.push(p);
        sites.push(site);
    }
    (out, sites)
}

/// A site with its sharp pair in ascending order.
fn unordered(site: DualLimitSite) -> DualLimitSite {
    match site {
        DualLimitSite::SharpMidpoint(a, b) => DualLimitSite::SharpMidpoint(a.min(b), a.max(b)),
        other => other,
    }
}

fn max_gap(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter().zip(b).filter(|(p, _)| p.is_finite()).map(|(p, q)| p.distance(*q)).fold(0.0, f64::max)
}

fn row_of(a: &LimitMatrix, v: usize) -> Vec<(usize, f64)> {
    a.s.outer_view(v).unwrap().iter().map(|(j, &x)| (j, x)).collect()
}

// ------------------------------------------------------------------ tests

/// Row by row A·X = the limit points read off M¹ (and M² at valence 2), for
/// the three rules on every case; the sites name the same M¹ places and
/// evaluate to the same points; rows sum to 1; with the standard rule A is
/// the tagged limit stencil.
#[test]
fn rows_are_the_limit_points_read_off_the_first_refined_mesh() {
    for c in cases() {
        let t = c.mesh.topology();
        let l = lambdas(t);
        let d = c.mesh.bbox_diagonal();
        let (t1, prov, _) = dual_split_tagged(t, &c.tags);
        let sites = doo_sabin_limit_sites(t, &c.tags, &prov).unwrap();
        for (m, rule) in rules(&l) {
            let a = limit_matrix_doo_sabin_sharp(t, &rule, &c.tags).unwrap();
            for (i, row) in a.to_csr().outer_iterator().enumerate() {
                let sum: f64 = row.data().iter().sum();
                assert!((sum - 1.0).abs() < 1e-14, "{m} on {}: row {i} sums to {sum}", c.name);
            }
            for seed in 0..3 {
                let x = random_points(&c.mesh, seed);
                let (read, found) = read_off_refined(t, &c.tags, rule, &x);
                let predicted = a.apply(&x);
                for v in 0..t.vertex_count() {
                    if t.is_isolated(VertexId(v as u32)) {
                        assert_eq!(sites[v], DualLimitSite::Isolated);
                        assert_eq!(predicted[v], x[v], "{m} on {}: isolated {v}", c.name);
                        continue;
                    }
                    let gap = predicted[v].distance(read[v]);
                    assert!(gap <= 1e-14 * d, "{m} on {}: vertex {v} is {gap:e} off M¹'s limit", c.name);
                    assert_eq!(Some(unordered(sites[v])), found[v], "{m} on {}: site of {v}", c.name);
                }
                let x1 = doo_sabin::first_step_tagged(t, &c.tags, &rule, &x).unwrap();
                let at_sites: Vec<DVec3> = sites.iter().map(|s| s.point(&t1, &x1).unwrap_or(DVec3::NAN)).collect();
                let gap = max_gap(&read, &at_sites);
                assert!(gap <= 1e-14 * d, "{m} on {}: sites' points {gap:e} off", c.name);
            }
            if matches!(rule, CornerRule::Standard) {
                let stencil = doo_sabin::limit_stencil_tagged(t, &c.tags).unwrap();
                let dense = |m: &subdiv_stencil::SparseMatrix, i: usize| -> HashMap<usize, f64> {
                    m.outer_view(i).unwrap().iter().map(|(j, &x)| (j, x)).collect()
                };
                let csr = a.to_csr();
                for i in 0..t.vertex_count() {
                    let (p, q) = (dense(&csr, i), dense(&stencil, i));
                    for j in p.keys().chain(q.keys()) {
                        let (x, y) = (p.get(j).copied().unwrap_or(0.0), q.get(j).copied().unwrap_or(0.0));
                        assert!((x - y).abs() <= 1e-15, "C on {}: [{i}][{j}] {x} vs stencil {y}", c.name);
                    }
                }
            }
        }
    }
}

/// Kinds, D and S per kind: corners the identity; crease rows D = ⅛, S = 6,
/// 5 or 4 on the diagonal, 1 per smooth sharp neighbour and 2 per corner
/// neighbour (`sharp_curve_point` ×8); darts D = 1; smooth rows the untagged
/// rows bit for bit (D too), even next to creases.
#[test]
fn row_kinds_and_rows_follow_the_tags() {
    for c in cases() {
        let t = c.mesh.topology();
        let l = lambdas(t);
        let s = sharpness(t, &c.tags);
        for (m, rule) in rules(&l) {
            let a = limit_matrix_doo_sabin_sharp(t, &rule, &c.tags).unwrap();
            let plain = limit_matrix_doo_sabin_sharp(t, &rule, &Tags::none()).unwrap();
            let mut count = HashMap::new();
            for v in t.vertices() {
                let i = v.index();
                let kind = a.row_kinds[i];
                *count.entry(format!("{kind:?}")).or_insert(0) += 1;
                assert_eq!(kind, expected_kind(t, &s, v), "{m} on {}: kind of {v}", c.name);
                let row = row_of(&a, i);
                match kind {
                    RowKind::Corner => {
                        assert_eq!((a.d[i], row), (1.0, vec![(i, 1.0)]), "{m} on {}: corner {v}", c.name);
                    }
                    RowKind::Crease => {
                        assert_eq!(a.d[i], 0.125);
                        let ends = &s.neighbours[i];
                        let corners = ends.iter().filter(|&&b| s.corner[b as usize]).count();
                        let mut expected: Vec<(usize, f64)> = vec![(i, 6.0 - corners as f64)];
                        expected
                            .extend(ends.iter().map(|&b| (b as usize, if s.corner[b as usize] { 2.0 } else { 1.0 })));
                        expected.sort_by_key(|&(j, _)| j);
                        assert_eq!(row, expected, "{m} on {}: crease row {v}", c.name);
                    }
                    RowKind::General if s.neighbours[i].len() == 1 => assert_eq!(a.d[i], 1.0, "dart {v}"),
                    RowKind::General | RowKind::Smooth => {
                        // Smooth (and smooth valence-2) rows: unchanged by the tags, bit for bit.
                        assert_eq!(a.d[i].to_bits(), plain.d[i].to_bits(), "{m} on {}: D of {v}", c.name);
                        let bits =
                            |r: Vec<(usize, f64)>| r.into_iter().map(|(j, x)| (j, x.to_bits())).collect::<Vec<_>>();
                        assert_eq!(bits(row), bits(row_of(&plain, i)), "{m} on {}: row {v} moved", c.name);
                    }
                }
            }
            if m == "C" {
                eprintln!("{}: {count:?}", c.name);
            }
        }
    }
}

/// The solve order: corners, then crease blocks whose columns are crease or
/// corner rows (the sharp block: every piece of the sharp polygon that ends
/// at corners or closes, none that reaches a dart), then the interior; S
/// symmetric bit for bit on the crease block and on the smooth rows.
#[test]
fn blocks_are_triangular_and_symmetric_where_promised() {
    for c in cases() {
        let t = c.mesh.topology();
        let l = lambdas(t);
        let s = sharpness(t, &c.tags);
        // Pieces of the sharp polygon: crease vertices joined by sharp edges.
        let is_crease = |v: u32| !s.corner[v as usize] && s.neighbours[v as usize].len() == 2;
        let mut piece = vec![usize::MAX; t.vertex_count()];
        let mut reaches_dart = Vec::new();
        for start in (0..t.vertex_count() as u32).filter(|&v| is_crease(v)) {
            if piece[start as usize] != usize::MAX {
                continue;
            }
            let id = reaches_dart.len();
            reaches_dart.push(false);
            let mut stack = vec![start];
            piece[start as usize] = id;
            while let Some(v) = stack.pop() {
                for &b in &s.neighbours[v as usize] {
                    if is_crease(b) && piece[b as usize] == usize::MAX {
                        piece[b as usize] = id;
                        stack.push(b);
                    } else if !is_crease(b) && !s.corner[b as usize] {
                        reaches_dart[id] = true;
                    }
                }
            }
        }
        let expected_creases: Vec<u32> =
            (0..t.vertex_count() as u32).filter(|&v| is_crease(v) && !reaches_dart[piece[v as usize]]).collect();
        for (m, rule) in rules(&l) {
            let a = limit_matrix_doo_sabin_sharp(t, &rule, &c.tags).unwrap();
            let blocks = solve_blocks(&a);
            assert_eq!(blocks.corners, a.rows_of(RowKind::Corner), "{m} on {}", c.name);
            assert_eq!(blocks.creases, expected_creases, "{m} on {}: the crease block", c.name);
            let mut sharp_block: Vec<u32> = blocks.corners.iter().chain(&blocks.creases).copied().collect();
            sharp_block.sort_unstable();
            assert_eq!(a.boundary_rows, sharp_block, "{m} on {}", c.name);
            for &v in &blocks.creases {
                for (j, _) in row_of(&a, v as usize) {
                    assert!(
                        sharp_block.binary_search(&(j as u32)).is_ok(),
                        "{m} on {}: crease row {v} col {j}",
                        c.name
                    );
                }
            }
            assert!(a.asymmetric_rows(&blocks.creases).is_empty(), "{m} on {}: crease block", c.name);
            assert!(a.asymmetric_rows(&a.rows_of(RowKind::Smooth)).is_empty(), "{m} on {}: smooth rows", c.name);
            // The interior loses its symmetry only at its general rows and
            // the crease rows of pieces that end at a dart (their smooth
            // neighbours have them as columns, they do not have those): every
            // flagged row is one of them or shares an entry with one.
            let special: BTreeSet<u32> =
                (blocks.interior.iter().copied()).filter(|&v| a.row_kinds[v as usize] != RowKind::Smooth).collect();
            for v in a.asymmetric_rows(&blocks.interior) {
                let near = special.contains(&v)
                    || row_of(&a, v as usize).iter().any(|&(j, _)| special.contains(&(j as u32)))
                    || special.iter().any(|&g| a.s.get(g as usize, v as usize).is_some());
                assert!(near, "{m} on {}: row {v} asymmetric away from the general rows", c.name);
            }
        }
    }
}

/// Dense eigenvalues of the symmetric D^½ S D^½ on `rows`.
fn symmetric_block_eigenvalues(a: &LimitMatrix, rows: &[u32]) -> Vec<f64> {
    if rows.is_empty() {
        return Vec::new();
    }
    let index: HashMap<u32, usize> = rows.iter().enumerate().map(|(k, &v)| (v, k)).collect();
    let mut m = DMatrix::zeros(rows.len(), rows.len());
    for (k, &v) in rows.iter().enumerate() {
        for (j, x) in row_of(a, v as usize) {
            if let Some(&l) = index.get(&(j as u32)) {
                m[(k, l)] = a.d[v as usize].sqrt() * x * a.d[j].sqrt();
            }
        }
    }
    let mut ev: Vec<f64> = SymmetricEigen::new(m).eigenvalues.iter().copied().collect();
    ev.sort_by(f64::total_cmp);
    ev
}

/// Dense complex eigenvalues of A on `rows` (real Schur form).
fn block_eigenvalues(a: &LimitMatrix, rows: &[u32]) -> Vec<nalgebra::Complex<f64>> {
    let index: HashMap<u32, usize> = rows.iter().enumerate().map(|(k, &v)| (v, k)).collect();
    let mut m = DMatrix::zeros(rows.len(), rows.len());
    for (k, &v) in rows.iter().enumerate() {
        for (j, x) in row_of(a, v as usize) {
            if let Some(&l) = index.get(&(j as u32)) {
                m[(k, l)] = a.d[v as usize] * x;
            }
        }
    }
    let schur = nalgebra::linalg::Schur::try_new(m, 1e-14, 100_000).expect("Schur converges");
    schur.complex_eigenvalues().iter().copied().collect()
}

/// The connected pieces of the crease block (S's off-diagonal entries inside
/// it), each with whether it is a closed loop (no corner column).
fn crease_pieces(a: &LimitMatrix, creases: &[u32]) -> Vec<(Vec<u32>, bool)> {
    let inside: BTreeSet<u32> = creases.iter().copied().collect();
    let mut seen = BTreeSet::new();
    let mut out = Vec::new();
    for &start in creases {
        if !seen.insert(start) {
            continue;
        }
        let (mut piece, mut stack, mut closed) = (vec![start], vec![start], true);
        while let Some(v) = stack.pop() {
            for (j, _) in row_of(a, v as usize).into_iter().filter(|&(j, _)| j != v as usize) {
                if !inside.contains(&(j as u32)) {
                    closed = false; // a corner column: a clamped end
                } else if seen.insert(j as u32) {
                    piece.push(j as u32);
                    stack.push(j as u32);
                }
            }
        }
        piece.sort_unstable();
        out.push((piece, closed));
    }
    out
}

/// The spectra: every crease piece's eigenvalues are the documented
/// cosines — a closed loop of m, (6 + 2cos(2πk/m))/8; an open piece of k
/// between corners, (6 − 2cos(πj/k))/8, j = 0..k−1 (so ½ exactly, never
/// singular) —, the smooth rows' D^½SD^½ lies in [¼, 1] (C), [½, 1] (Z),
/// [min λ, 1] (B(λ)), and the interior with general rows (darts, valence
/// 2, pieces ending at darts) is measured: nonsingular here, with the
/// real parts of its eigenvalues positive and moduli ≤ 1.
#[test]
fn block_spectra() {
    const EPS: f64 = 1e-12;
    for c in cases() {
        let t = c.mesh.topology();
        let l = lambdas(t);
        let lmin = l.iter().copied().fold(1.0, f64::min);
        for (m, rule) in rules(&l) {
            let a = limit_matrix_doo_sabin_sharp(t, &rule, &c.tags).unwrap();
            let blocks = solve_blocks(&a);
            for (piece, closed) in crease_pieces(&a, &blocks.creases) {
                let n = piece.len();
                let mut expected: Vec<f64> = (0..n)
                    .map(|k| {
                        if closed {
                            (6.0 + 2.0 * (2.0 * std::f64::consts::PI * k as f64 / n as f64).cos()) / 8.0
                        } else {
                            (6.0 - 2.0 * (std::f64::consts::PI * k as f64 / n as f64).cos()) / 8.0
                        }
                    })
                    .collect();
                expected.sort_by(f64::total_cmp);
                let ev = symmetric_block_eigenvalues(&a, &piece);
                for (x, y) in ev.iter().zip(&expected) {
                    assert!((x - y).abs() < EPS, "{m} on {}: piece {piece:?}: {ev:?} vs {expected:?}", c.name);
                }
                assert!(ev[0] >= 0.5 - EPS && ev[n - 1] <= 1.0 + EPS);
            }
            let smooth = a.rows_of(RowKind::Smooth);
            if !smooth.is_empty() {
                let ev = symmetric_block_eigenvalues(&a, &smooth);
                let bound = match rule {
                    CornerRule::Standard => 0.25,
                    CornerRule::Uniform(x) => x,
                    CornerRule::PerFace(_) => lmin,
                };
                let (lo, hi) = (ev[0], ev[ev.len() - 1]);
                eprintln!(
                    "{m} on {}: smooth block ({} rows) in [{lo:.4}, {hi:.4}], bound {bound}",
                    c.name,
                    smooth.len()
                );
                assert!(lo >= bound - EPS && hi <= 1.0 + EPS, "{m} on {}: smooth block [{lo}, {hi}]", c.name);
            }
            // A is block lower triangular: its eigenvalues are its blocks'.
            let all: Vec<u32> = (0..a.size() as u32).collect();
            let whole = block_eigenvalues(&a, &all);
            let mut blocks_ev: Vec<nalgebra::Complex<f64>> = vec![1.0.into(); blocks.corners.len()];
            blocks_ev.extend(symmetric_block_eigenvalues(&a, &blocks.creases).into_iter().map(nalgebra::Complex::from));
            if !blocks.interior.is_empty() {
                blocks_ev.extend(block_eigenvalues(&a, &blocks.interior));
            }
            let min_abs = |ev: &[nalgebra::Complex<f64>]| ev.iter().map(|z| z.norm()).fold(f64::INFINITY, f64::min);
            let (w, b) = (min_abs(&whole), min_abs(&blocks_ev));
            assert!((w - b).abs() < 1e-9, "{m} on {}: A's smallest |λ| {w} vs its blocks' {b}", c.name);
            let general = a.rows_of(RowKind::General);
            if general.is_empty() {
                // The interior is the smooth block: A's spectrum is the blocks'.
                assert_eq!(blocks.interior, smooth, "{m} on {}", c.name);
                continue;
            }
            let ev = block_eigenvalues(&a, &blocks.interior);
            let min_re = ev.iter().map(|z| z.re).fold(f64::INFINITY, f64::min);
            let min_abs = ev.iter().map(|z| z.norm()).fold(f64::INFINITY, f64::min);
            let max_abs = ev.iter().map(|z| z.norm()).fold(0.0, f64::max);
            eprintln!(
                "{m} on {}: interior with {} general rows: min Re λ {min_re:.4}, |λ| in [{min_abs:.4}, {max_abs:.4}]",
                c.name,
                general.len()
            );
            assert!(
                min_re > 0.0 && max_abs <= 1.0 + EPS,
                "{m} on {}: interior min Re {min_re}, max |λ| {max_abs}",
                c.name
            );
        }
    }
}

/// No tags, all-zero tags: the untagged matrices bit for bit.
#[test]
fn untagged_and_zero_tags_give_the_untagged_matrices_bit_for_bit() {
    let same = |a: &LimitMatrix, b: &LimitMatrix| {
        a.d.iter().zip(&b.d).all(|(x, y)| x.to_bits() == y.to_bits())
            && a.s.indptr().raw_storage() == b.s.indptr().raw_storage()
            && a.s.indices() == b.s.indices()
            && a.s.data().iter().zip(b.s.data()).all(|(x, y)| x.to_bits() == y.to_bits())
            && a.row_kinds == b.row_kinds
            && a.boundary_rows == b.boundary_rows
    };
    let grid = shapes::quad_grid(5, 4);
    let interior: Vec<EdgeId> = grid.topology().edges().filter(|&e| !grid.topology().is_boundary_edge(e)).collect();
    let meshes = [
        shapes::cube(),
        shapes::pillow(),
        shapes::torus(6, 5),
        bumpy_grid(4),
        shapes::polygon_mix(&shapes::plate_with_holes(7, 5, &[(1, 1), (3, 3)], false), 3, 0.5, 0.3, 0.1),
        shapes::split_edges(&grid, &[interior[2], interior[9]], 0.2),
        cube_with_isolated_vertex(),
    ];
    for mesh in &meshes {
        let t = mesh.topology();
        let l = lambdas(t);
        let zero = Tags::from_arrays(t, vec![0.0; t.edge_count()], vec![0.0; t.vertex_count()]).unwrap();
        for (m, rule, plain) in [
            ("C", CornerRule::Standard, limit_matrix_nasri(t)),
            ("Z", CornerRule::Uniform(0.5), limit_matrix_zheng_cai(t)),
            ("B(λ)", CornerRule::PerFace(&l), limit_matrix_two_phase(t, CornerRule::PerFace(&l)).unwrap()),
        ] {
            for tags in [Tags::none(), zero.clone()] {
                let a = limit_matrix_doo_sabin_sharp(t, &rule, &tags).unwrap();
                assert!(same(&a, &plain), "{m}: tags {:?}", tags.edge_values().len());
            }
        }
        // Untagged sites: the V-faces and the boundary's Chaikin pairs of the plain split.
        let (_, prov) = subdiv_mesh::refine::dual_split(t);
        let (_, sharp_prov, _) = dual_split_tagged(t, &Tags::none());
        let sites = doo_sabin_limit_sites(t, &Tags::none(), &sharp_prov).unwrap();
        for v in t.vertices() {
            match sites[v.index()] {
                DualLimitSite::FaceCentroid(f) => assert_eq!(prov.vertex_face[v.index()], Some(f)),
                DualLimitSite::SharpMidpoint(..) => assert!(t.is_boundary_vertex(v)),
                DualLimitSite::ValenceTwoEdge(..) => assert_eq!(t.valence(v), 2),
                DualLimitSite::Isolated => assert!(t.is_isolated(v)),
                DualLimitSite::Corner(_) => panic!("no corner without tags"),
            }
        }
    }
}

#[test]
fn semi_sharp_tags_and_bad_lambdas_are_typed_errors() {
    let cube = shapes::cube();
    let t = cube.topology();
    let semi_edge = Tags::from_list(
        t,
        &TagList { creases: vec![EdgeTag { a: 4, b: 5, sharpness: 2.5 }], corners: Vec::new(), ..Default::default() },
    )
    .unwrap();
    let semi_vertex = Tags::from_list(
        t,
        &TagList { creases: Vec::new(), corners: vec![VertexTag { vertex: 3, sharpness: 9.5 }], ..Default::default() },
    )
    .unwrap();
    let l = lambdas(t);
    for tags in [&semi_edge, &semi_vertex] {
        for (m, rule) in rules(&l) {
            let err = limit_matrix_doo_sabin_sharp(t, &rule, tags).unwrap_err();
            assert!(matches!(err, StencilError::SemiSharpDooSabin { .. }), "{m}: {err}");
        }
        let (_, prov, _) = dual_split_tagged(t, tags);
        assert!(matches!(doo_sabin_limit_sites(t, tags, &prov), Err(StencilError::SemiSharpDooSabin { .. })));
    }
    let sharp = tags(t, &CUBE_TOP, &[]);
    for bad in [CornerRule::Uniform(1.0), CornerRule::PerFace(&l[..3])] {
        let err = limit_matrix_doo_sabin_sharp(t, &bad, &sharp).unwrap_err();
        assert!(matches!(err, StencilError::InvalidParameter(_)), "{err}");
    }
}

// ------------------------------------------------------------ brute force

/// What a predicted point is tracked by through the levels.
enum Track {
    /// A face of every level from this one on (F-faces keep their id).
    Face(FaceId),
    /// The segment of the refined sharp polygon centred on it.
    Segment,
    /// A kept corner.
    Corner,
}

/// Brute force: the method's first step (`first_step_tagged` with its rule
/// on `dual_split_tagged`'s connectivity), then standard tagged Doo-Sabin by
/// `subdivide`, one level at a time, 8 levels in all. Every predicted point
/// A·X stays, at every level, the centroid of its tracked face (a V-face of
/// M¹, or the E-face of M² of a valence-2 vertex), the midpoint of a sharp
/// edge (a crease vertex), or a vertex (a corner, exactly); the tracked
/// faces' corners and the sharp segments close in geometrically; the faces
/// are then followed alone (their F-face rule) until they are within
/// 1e-6·d of the point.
#[test]
fn brute_force_limits_of_all_rules() {
    const LEVELS: usize = 8;
    for c in small_cases() {
        let t = c.mesh.topology();
        let l = lambdas(t);
        let x = random_points(&c.mesh, 11);
        let d = bbox_diagonal(&x);
        let (t1, prov, tags1) = dual_split_tagged(t, &c.tags);
        let sites = doo_sabin_limit_sites(t, &c.tags, &prov).unwrap();
        let (_, prov2, _) = dual_split_tagged(&t1, &tags1);
        let tracks: Vec<Track> = sites
            .iter()
            .map(|site| match *site {
                DualLimitSite::FaceCentroid(f) => Track::Face(f),
                DualLimitSite::ValenceTwoEdge(a, b) => {
                    let e = edge_between(&t1, a.0, b.0);
                    Track::Face(FaceId(prov2.face_origin.iter().position(|&o| o == DualFace::E(e)).unwrap() as u32))
                }
                DualLimitSite::SharpMidpoint(..) => Track::Segment,
                DualLimitSite::Corner(_) | DualLimitSite::Isolated => Track::Corner,
            })
            .collect();
        for (m, rule) in rules(&l) {
            let predicted = limit_matrix_doo_sabin_sharp(t, &rule, &c.tags).unwrap().apply(&x);
            let x1 = doo_sabin::first_step_tagged(t, &c.tags, &rule, &x).unwrap();
            let mut mesh = Mesh::from_topology(t1.clone(), x1).with_tags(tags1.clone());
            let mut gaps: Vec<Vec<f64>> = vec![Vec::new(); t.vertex_count()];
            // The ends of each crease vertex's sharp segment on the last level.
            let mut segment = vec![(DVec3::ZERO, DVec3::ZERO); t.vertex_count()];
            for level in 1..=LEVELS {
                if level > 1 {
                    mesh = subdivide(&mesh, Scheme::DooSabin, 1, false).unwrap();
                }
                let (tl, xl) = (mesh.topology(), mesh.positions());
                let features = subdiv_mesh::refine::DualFeatures::new(tl, mesh.tags());
                let sharp_edges: Vec<(DVec3, DVec3)> = tl
                    .edges()
                    .filter(|&e| features.is_sharp(tl, e))
                    .map(|e| {
                        let (a, b) = tl.edge_vertices(e);
                        (xl[a.index()], xl[b.index()])
                    })
                    .collect();
                for (v, track) in tracks.iter().enumerate() {
                    let p = predicted[v];
                    let gap = match *track {
                        Track::Face(f) if level == 1 && f.index() >= tl.face_count() => continue, // an M² face
                        Track::Face(f) => {
                            let corners: Vec<DVec3> = tl.face(f).iter().map(|&k| xl[k as usize]).collect();
                            let centroid = corners.iter().sum::<DVec3>() / corners.len() as f64;
                            let drift = centroid.distance(p);
                            assert!(
                                drift <= 1e-13 * d,
                                "{m} on {}: level {level}: vertex {v}'s face drifted {drift:e}",
                                c.name
                            );
                            corners.iter().map(|q| q.distance(p)).fold(0.0, f64::max)
                        }
                        Track::Segment => {
                            let (drift, ends) = sharp_edges
                                .iter()
                                .map(|&(a, b)| (((a + b) / 2.0).distance(p), (a, b)))
                                .fold((f64::INFINITY, segment[v]), |a, b| if b.0 < a.0 { b } else { a });
                            assert!(
                                drift <= 1e-13 * d,
                                "{m} on {}: level {level}: no sharp edge centred on {v}: {drift:e}",
                                c.name
                            );
                            segment[v] = ends;
                            ends.0.distance(p).max(ends.1.distance(p))
                        }
                        Track::Corner if t.is_isolated(VertexId(v as u32)) => continue,
                        Track::Corner => {
                            let nearest = xl.iter().map(|q| q.distance(p)).fold(f64::INFINITY, f64::min);
                            assert_eq!(nearest, 0.0, "{m} on {}: corner {v} moved", c.name);
                            0.0
                        }
                    };
                    gaps[v].push(gap / d);
                }
            }
            // Continue each tracked face alone: its F-face is Eq. 1 within the face;
            // a sharp segment [a, b] refines to [¾a + ¼b, ¼a + ¾b] (its ends are no corners).
            let (tl, xl) = (mesh.topology(), mesh.positions());
            let mut worst_final = 0.0f64;
            for (v, track) in tracks.iter().enumerate() {
                let p = predicted[v];
                if let Track::Face(f) = *track {
                    let mut face: Vec<DVec3> = tl.face(f).iter().map(|&k| xl[k as usize]).collect();
                    let mut w = vec![0.0; face.len()];
                    subdiv_rules::doo_sabin_weights(face.len(), &mut w);
                    while gaps[v].last().unwrap() * d > 1e-6 * d && gaps[v].len() < LEVELS + 30 {
                        let k = face.len();
                        face = (0..k).map(|i| (0..k).map(|j| w[j] * face[(i + j) % k]).sum()).collect();
                        gaps[v].push(face.iter().map(|q| q.distance(p)).fold(0.0, f64::max) / d);
                    }
                } else if let Track::Segment = *track {
                    let (mut a, mut b) = segment[v];
                    while gaps[v].last().unwrap() * d > 1e-6 * d && gaps[v].len() < LEVELS + 30 {
                        // The segment's part at the next level: Chaikin's two points.
                        (a, b) = (0.75 * a + 0.25 * b, 0.25 * a + 0.75 * b);
                        gaps[v].push(a.distance(p).max(b.distance(p)) / d);
                    }
                }
                if gaps[v].is_empty() {
                    continue;
                }
                let g = &gaps[v];
                let last = *g.last().unwrap();
                worst_final = worst_final.max(last);
                assert!(last <= 1e-6, "{m} on {}: vertex {v} still {last:e}·d away", c.name);
                if g[0] > 0.0 {
                    // Geometric: the mean contraction per level is at most ¾.
                    let ratio = (last / g[0]).powf(1.0 / (g.len() - 1) as f64);
                    assert!(ratio <= 0.75, "{m} on {}: vertex {v} contracts by {ratio:.3} per level", c.name);
                }
                // The whole-mesh levels alone already halve (¼ at least, at a corner of a face).
                if g.len() > LEVELS - 1 && g[0] > 0.0 {
                    let ratio = (g[LEVELS - 2] / g[0]).powf(1.0 / (LEVELS - 2) as f64);
                    assert!(ratio <= 0.75, "{m} on {}: vertex {v}: {ratio:.3} over the mesh levels", c.name);
                }
            }
            eprintln!(
                "{m} on {}: {LEVELS} levels, {} faces; every point on its tracked face or segment, \
                 within {worst_final:.1e}·d after following it alone",
                c.name,
                mesh.topology().face_count()
            );
        }
    }
}

/// The spectral claims on 4000 random tagged polygon mixes (tori, open
/// plates, grids, icosahedra; every third with interior valence-2
/// vertices from split edges; creases on 5–45 % of the edges, corner tags
/// on 5 % of the vertices, λ ∈ [0.05, 0.95] per face): each crease piece in
/// [½, 1], the smooth block in [¼, 1] (C), [½, 1] (Z), [min λ, 1] (B(λ));
/// the interiors with general rows are measured — the minima are printed,
/// and every eigenvalue has a positive real part above 0.1 (no singular
/// block was found; no theorem covers them). Every 8th mesh also has its
/// rows checked against the limit points read off M¹.
#[test]
fn spectra_of_random_tagged_meshes() {
    const EPS: f64 = 1e-12;
    // Smallest |λ| (/ min λ for B(λ)) of the interiors with general rows: darts only, with valence 2.
    let mut worst = [[f64::INFINITY; 3]; 2];
    for seed in 0..4000u64 {
        let mut rng = shapes::SplitMix64(seed * 7919 + 1);
        let base = match seed % 4 {
            0 => shapes::torus(5 + rng.below(3), 4 + rng.below(3)),
            1 => shapes::plate_with_holes(5, 4, &[(2, 1)], false),
            2 => shapes::quad_grid(4, 4),
            _ => shapes::icosahedron(),
        };
        let mut mesh = shapes::polygon_mix(&base, seed, 0.3 * rng.next_f64(), 0.4 * rng.next_f64(), 0.05);
        let valence_two = seed % 3 == 0;
        if valence_two {
            let t = mesh.topology();
            let interior: Vec<EdgeId> = t.edges().filter(|&e| !t.is_boundary_edge(e)).collect();
            let mut picks: Vec<EdgeId> = (0..1 + rng.below(4)).map(|_| interior[rng.below(interior.len())]).collect();
            picks.sort_unstable();
            picks.dedup();
            mesh = shapes::split_edges(&mesh, &picks, 0.1);
        }
        let t = mesh.topology();
        let p = 0.05 + 0.4 * rng.next_f64();
        let edges: Vec<f32> = t.edges().map(|_| if rng.next_f64() < p { INFINITE } else { 0.0 }).collect();
        let vertices: Vec<f32> = t.vertices().map(|_| if rng.next_f64() < 0.05 { INFINITE } else { 0.0 }).collect();
        let tags = Tags::from_arrays(t, edges, vertices).unwrap();
        let l: Vec<f64> = (0..t.face_count()).map(|_| 0.05 + 0.9 * rng.next_f64()).collect();
        let lmin = l.iter().copied().fold(1.0, f64::min);
        for (k, (m, rule)) in rules(&l).into_iter().enumerate() {
            let a = limit_matrix_doo_sabin_sharp(t, &rule, &tags).unwrap();
            if seed % 8 == 0 {
                // The rows, again: the limit points read off M¹.
                let x = random_points(&mesh, seed);
                let (read, _) = read_off_refined(t, &tags, rule, &x);
                let gap = max_gap(&read, &a.apply(&x));
                assert!(gap <= 1e-14 * mesh.bbox_diagonal(), "{m}, seed {seed}: rows {gap:e} off M¹'s limits");
            }
            let blocks = solve_blocks(&a);
            for (piece, _) in crease_pieces(&a, &blocks.creases) {
                let ev = symmetric_block_eigenvalues(&a, &piece);
                assert!(ev[0] >= 0.5 - EPS && ev[ev.len() - 1] <= 1.0 + EPS, "{m}, seed {seed}: piece {ev:?}");
            }
            let smooth = a.rows_of(RowKind::Smooth);
            let bound = [0.25, 0.5, lmin][k];
            if !smooth.is_empty() {
                let ev = symmetric_block_eigenvalues(&a, &smooth);
                assert!(ev[0] >= bound - EPS && ev[ev.len() - 1] <= 1.0 + EPS, "{m}, seed {seed}: smooth {}", ev[0]);
            }
            if a.rows_of(RowKind::General).is_empty() {
                assert_eq!(blocks.interior, smooth);
                continue;
            }
            let ev = block_eigenvalues(&a, &blocks.interior);
            let min_re = ev.iter().map(|z| z.re).fold(f64::INFINITY, f64::min);
            let min_abs = ev.iter().map(|z| z.norm()).fold(f64::INFINITY, f64::min);
            assert!(min_re > 0.1, "{m}, seed {seed}: interior min Re λ {min_re}");
            let w = &mut worst[usize::from(valence_two)][k];
            *w = w.min(min_abs / if k == 2 { lmin } else { 1.0 });
        }
    }
    eprintln!(
        "interiors with darts: min |λ| C {:.3}, Z {:.3}, B(λ) {:.3}·min λ",
        worst[0][0], worst[0][1], worst[0][2]
    );
    eprintln!(
        "and valence 2:        min |λ| C {:.3}, Z {:.3}, B(λ) {:.3}·min λ",
        worst[1][0], worst[1][1], worst[1][2]
    );
}

/// Same bits whatever the thread count, on a mesh large enough for many
/// parallel chunks: a 120 × 100 grid with crease rows, darts and corner tags.
#[test]
fn results_do_not_depend_on_the_thread_count() {
    let mesh = shapes::quad_grid(120, 100);
    let t = mesh.topology();
    let row = |r: u32, c0: u32, c1: u32| (c0..c1).map(move |c| (121 * r + c, 121 * r + c + 1));
    let creases: Vec<(u32, u32)> = row(50, 0, 120).chain(row(20, 10, 70)).chain(row(80, 30, 31)).collect();
    let tags = tags(t, &creases, &[121 * 20 + 40, 121 * 60 + 60]);
    let l = lambdas(t);
    let build = || {
        let (_, prov, _) = dual_split_tagged(t, &tags);
        let sites = doo_sabin_limit_sites(t, &tags, &prov).unwrap();
        let matrices: Vec<LimitMatrix> =
            rules(&l).iter().map(|&(_, rule)| limit_matrix_doo_sabin_sharp(t, &rule, &tags).unwrap()).collect();
        (sites, matrices)
    };
    let (sites, many) = build();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let (sites_one, one) = pool.install(build);
    assert_eq!(sites, sites_one);
    for (a, b) in many.iter().zip(&one) {
        assert_eq!(
            a.d.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
            b.d.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
        );
        assert_eq!(a.s.indptr().raw_storage(), b.s.indptr().raw_storage());
        assert_eq!(a.s.indices(), b.s.indices());
        assert!(a.s.data().iter().zip(b.s.data()).all(|(x, y)| x.to_bits() == y.to_bits()));
        assert_eq!((&a.row_kinds, &a.boundary_rows), (&b.row_kinds, &b.boundary_rows));
    }
    assert!(many[0].rows_of(RowKind::General).len() >= 4, "darts at the ends of rows 20 and 80");
}
