//! Deng-Ma with infinitely sharp creases and corners: the claims of
//! `subdiv_stencil::deng_ma` ("Creases and corners"), each checked against an
//! independent derivation — the curve rules of `subdiv_rules::curves` on the
//! input's crease polygon, the untagged scheme on the mesh cut along its
//! creases, planes and angles measured on the output — never against the
//! operator's own output. Everything goes through `subdivide` with tagged
//! meshes, as the interpolation methods and the CLI call it.

use glam::DVec3;
use proptest::prelude::*;
use subdiv_mesh::{shapes, EdgeTag, FaceList, Mesh, TagList, Tags, Topology, VertexId, VertexTag, SHARPNESS_INFINITE};
use subdiv_rules::curves;
use subdiv_rules::deng_ma::{edge_displacement_ratio, Tension};
use subdiv_stencil::deng_ma::{stencil_tagged, step_positions_tagged};
use subdiv_stencil::{apply, row_sums, subdivide, BoundaryInterpolation, LevelSharpness, Options, Scheme};
use subdiv_stencil::{CreaseMethod, StencilError, SubdivisionPlan};

// ---------------------------------------------------------------- fixtures

/// The tensions every claim is checked with: the classical ω = 1, another
/// global one, and the variable tension of §3.4 with two λ.
const TENSIONS: [Tension; 4] =
    [Tension::Global(1.0), Tension::Global(0.5), Tension::Variable { lambda: 0.5 }, Tension::Variable { lambda: 1.0 }];

/// Tags with the given creases (vertex pairs) and corners, all at `SHARPNESS_INFINITE`.
fn tags(t: &Topology, creases: &[(u32, u32)], corners: &[u32]) -> Tags {
    let list = TagList {
        creases: creases.iter().map(|&(a, b)| EdgeTag { a, b, sharpness: SHARPNESS_INFINITE }).collect(),
        corners: corners.iter().map(|&vertex| VertexTag { vertex, sharpness: SHARPNESS_INFINITE }).collect(),
        ..Default::default()
    };
    Tags::from_list(t, &list).expect("the test tags name edges and vertices of the mesh")
}

/// Positions moved by a smooth, non-polynomial field, so that no rule is exact by accident.
fn bumpy(mesh: Mesh) -> Mesh {
    let p = mesh.positions().iter().map(|p| {
        *p + DVec3::new(
            0.07 * (2.1 * p.y + 0.3).sin(),
            0.05 * (1.7 * p.z).cos(),
            0.2 * (1.3 * p.x - 0.4 * p.y * p.y).sin(),
        )
    });
    mesh.with_positions(p.collect())
}

/// The cube's vertex i sits at (i & 1, i >> 1 & 1, i >> 2 & 1); its top face (z = 1) is 4 5 7 6.
const CUBE_EDGES: [(u32, u32); 12] =
    [(0, 1), (2, 3), (4, 5), (6, 7), (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7)];
const CUBE_TOP: [u32; 4] = [4, 5, 7, 6];

/// The edges of a closed (`closed`) or open polygon through `vertices`.
fn polygon_edges(vertices: &[u32], closed: bool) -> Vec<(u32, u32)> {
    let n = vertices.len();
    let edges = if closed { n } else { n - 1 };
    (0..edges).map(|i| (vertices[i], vertices[(i + 1) % n])).collect()
}

/// Vertex (c, r) of the 6×6 grid of `shapes::quad_grid(6, 6)`.
fn g6(c: u32, r: u32) -> u32 {
    7 * r + c
}

/// Row r of the 6×6 grid from column c0 to c1 (inclusive).
fn grid_row(r: u32, c0: u32, c1: u32) -> Vec<u32> {
    (c0..=c1).map(|c| g6(c, r)).collect()
}

/// The subdivided mesh of `levels` Deng-Ma steps of `mesh` with `tags`.
fn run(mesh: &Mesh, tags: &Tags, options: Options, levels: usize) -> Mesh {
    subdivide(&mesh.clone().with_tags(tags.clone()), options, levels, false).expect("the test meshes subdivide")
}

fn deng_ma(tension: Tension) -> Options {
    Options::new(Scheme::DengMa(tension))
}

/// A tagged test mesh with the crease polygons it holds (each a vertex
/// list, closed or open from piece end to piece end).
struct Case {
    name: &'static str,
    mesh: Mesh,
    tags: Tags,
    pieces: Vec<(Vec<u32>, bool)>,
}

/// The tagged meshes: a closed crease loop on the cube and on the torus;
/// on a grid, a crease row from boundary to boundary (its ends are corners:
/// three sharp edges), a row from the boundary to a dart, a row from dart to
/// dart and the untouched bottom boundary from grid corner to grid corner;
/// the same grid with a tagged corner in the middle of the first row.
fn cases() -> Vec<Case> {
    let cube = bumpy(shapes::cube());
    let cube_tags = tags(cube.topology(), &polygon_edges(&CUBE_TOP, true), &[]);
    let torus = bumpy(shapes::torus(6, 8));
    let meridian: Vec<u32> = (0..8).collect(); // vertices (0, j) of the torus
    let torus_tags = tags(torus.topology(), &polygon_edges(&meridian, true), &[]);
    let grid = bumpy(shapes::quad_grid(6, 6));
    let (across, to_dart, darts) = (grid_row(3, 0, 6), grid_row(1, 0, 4), grid_row(5, 1, 5));
    let creases: Vec<(u32, u32)> =
        [&across, &to_dart, &darts].iter().flat_map(|row| polygon_edges(row, false)).collect();
    let grid_tags = tags(grid.topology(), &creases, &[]);
    let grid_corner_tags = tags(grid.topology(), &creases, &[g6(3, 3)]);
    let bottom = grid_row(0, 0, 6);
    vec![
        Case { name: "cube, top loop", mesh: cube, tags: cube_tags, pieces: vec![(CUBE_TOP.to_vec(), true)] },
        Case { name: "torus, a meridian", mesh: torus, tags: torus_tags, pieces: vec![(meridian, true)] },
        Case {
            name: "grid, crease rows",
            mesh: grid.clone(),
            tags: grid_tags,
            pieces: vec![
                (across.clone(), false),
                (to_dart.clone(), false),
                (darts.clone(), false),
                (bottom.clone(), false),
            ],
        },
        Case {
            name: "grid, crease rows, a corner inside one",
            mesh: grid,
            tags: grid_corner_tags,
            pieces: vec![
                (grid_row(3, 0, 3), false),
                (grid_row(3, 3, 6), false),
                (to_dart, false),
                (darts, false),
                (bottom, false),
            ],
        },
    ]
}

/// FNV-1a over the bits of every coordinate.
fn hash(points: &[DVec3]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for c in points.iter().flat_map(|p| p.to_array()) {
        for b in c.to_bits().to_le_bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    }
    h
}

// ---------------------------------------------------------------- sharp polygon of a level

/// Whether edge `e` of a level is sharp: a boundary edge or a tag ≥ 10.
fn sharp_edge(mesh: &Mesh, e: subdiv_mesh::EdgeId) -> bool {
    mesh.topology().is_boundary_edge(e) || mesh.tags().edge_sharpness(e) >= SHARPNESS_INFINITE
}

/// The other ends of the sharp edges at `v`.
fn sharp_neighbours(mesh: &Mesh, v: VertexId) -> Vec<VertexId> {
    let t = mesh.topology();
    let fan = t.vertex_fan(v);
    let mut out: Vec<VertexId> = fan.iter().filter(|&&h| sharp_edge(mesh, t.he_edge(h))).map(|&h| t.he_to(h)).collect();
    if t.is_boundary_vertex(v) {
        out.push(t.he_from(t.he_prev(fan[fan.len() - 1])));
    }
    out
}

/// The refined piece of the sharp polygon of a level-k mesh that follows the
/// input piece `piece` (vertex ids of level 0, which keep their ids: old
/// vertices are numbered first at every level): from `piece[0]` along the
/// sharp edges, in the direction whose first old vertex is `piece[1]`, to
/// the last vertex (open) or back to the start (closed, not repeated).
fn refined_piece(mesh: &Mesh, piece: &[u32], closed: bool, n0: usize) -> Vec<VertexId> {
    let start = VertexId(piece[0]);
    let step = |prev: VertexId, cur: VertexId| -> VertexId {
        let next: Vec<VertexId> = sharp_neighbours(mesh, cur).into_iter().filter(|&u| u != prev).collect();
        assert_eq!(next.len(), 1, "vertex {cur} inside a sharp piece has two sharp edges");
        next[0]
    };
    let first_old = |mut prev: VertexId, mut cur: VertexId| {
        while cur.index() >= n0 {
            (prev, cur) = (cur, step(prev, cur));
        }
        cur
    };
    let first = sharp_neighbours(mesh, start)
        .into_iter()
        .find(|&u| first_old(start, u) == VertexId(piece[1]))
        .expect("the piece's direction exists at every level");
    let end = if closed { start } else { VertexId(*piece.last().unwrap()) };
    let mut out = vec![start];
    let (mut prev, mut cur) = (start, first);
    while cur != end {
        out.push(cur);
        (prev, cur) = (cur, step(prev, cur));
    }
    if !closed {
        out.push(end);
    }
    out
}

/// The input piece refined `levels` times by the 4-point rule with the
/// curve tension of `tension` (ω/16, [correction D4]; variable: ω_P of §3.4 on the
/// polygon, the piece ends as corners) and linear phantoms at open ends.
///
/// [correction D4]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d4
fn four_point_levels(points: &[DVec3], closed: bool, tension: Tension, levels: usize) -> Vec<DVec3> {
    let mut p: Vec<[f64; 3]> = points.iter().map(|q| q.to_array()).collect();
    for _ in 0..levels {
        p = match tension {
            Tension::Global(omega) => curves::four_point(&p, closed, omega / 16.0),
            Tension::Variable { .. } => {
                let n = p.len();
                let w: Vec<f64> = (0..n)
                    .map(|i| {
                        let inner = closed || (i > 0 && i + 1 < n);
                        let neighbours = inner.then(|| (p[(i + n - 1) % n], p[(i + 1) % n]));
                        tension.curve_tension(p[i], neighbours)
                    })
                    .collect();
                curves::four_point_variable(&p, closed, &w)
            }
        };
    }
    p.into_iter().map(DVec3::from_array).collect()
}

// ---------------------------------------------------------------- untagged: the same bits

/// The untagged meshes of the bit-identity check.
fn untagged_meshes() -> Vec<(&'static str, Mesh)> {
    let plate = shapes::plate_with_holes(6, 5, &[(2, 2)], false);
    vec![
        ("cube", bumpy(shapes::cube())),
        ("torus 6x8", bumpy(shapes::torus(6, 8))),
        ("quad grid 4x3", bumpy(shapes::quad_grid(4, 3))),
        ("triangle grid 3x3", bumpy(shapes::triangle_grid(3, 3))),
        ("plate mix", bumpy(shapes::polygon_mix(&plate, 7, 0.3, 0.3, 0.2))),
        ("one quad", bumpy(shapes::quad_grid(1, 1))),
        ("pyramid 5", bumpy(shapes::pyramid(5))),
        ("icosahedron", bumpy(shapes::icosahedron())),
    ]
}

/// Hashes ([`hash`]) of the positions of 3 levels of `subdivide` (one per
/// tension of [`BEFORE_TENSIONS`]) and of one level of `deng_ma::stencil(t, ω)`
/// applied to the input (ω = 1, 0.4), printed by this file's meshes on main
/// at afd3ed4, before Deng-Ma took tags.
#[allow(clippy::type_complexity)]
const BEFORE: [(&str, [u64; 4], [u64; 2]); 8] = [
    (
        "cube",
        [0xecddf1a459d9c75c, 0x492a869fc5097f0c, 0x28d60d0061d493ba, 0xee55803b51b5350d],
        [0x9a208433ba411c6b, 0x3d80c9dcae9b467c],
    ),
    (
        "torus 6x8",
        [0x9671b82c90044d43, 0xfe772149df81c943, 0x87456697ee35a032, 0x82948d93bf82a9e4],
        [0x199224f354d7d697, 0x22f317ee0964a4d8],
    ),
    (
        "quad grid 4x3",
        [0xe3463ba47241a1ec, 0x6051ef55236c00e2, 0x9c5b8bcaf60f124d, 0x5f97bc254cc5232f],
        [0x0084eb162fe12364, 0x9d5769767940b831],
    ),
    (
        "triangle grid 3x3",
        [0x331e74abd9738d59, 0x1552f5bdc4425a31, 0x020c6fbccd21fcc2, 0x851b52ed6bb299d9],
        [0x09c7f5e73c865f46, 0x0783291c9112df01],
    ),
    (
        "plate mix",
        [0x473edff211e96dbf, 0xbb46f40bacdd3c4c, 0xa525983b73541a46, 0x9b02db311c7c5482],
        [0x579098a620998911, 0x60fb6db6357305d1],
    ),
    (
        "one quad",
        [0x5994372505f2100c, 0x7a0eb518b7e91079, 0xf92875dec68dee5d, 0xa07d84221d0bc536],
        [0xd9dc0cd8b577bde3, 0x40dc1aebe9a82afc],
    ),
    (
        "pyramid 5",
        [0xa8d04c055637e7ed, 0xfb59c537b07ec55a, 0xe5357a77b32a1516, 0x334e4842e12319fb],
        [0x74ff75ae587f4ea6, 0xd7bc24dccda33089],
    ),
    (
        "icosahedron",
        [0xfdb98c56f6e17035, 0x2c14eae753ade25b, 0x19b1f5b6a46c36c1, 0xa7eab7223ac31693],
        [0x3b6ea2a8bc7376ca, 0xf1095cef7d36cd13],
    ),
];

/// The tensions of [`BEFORE`]'s `subdivide` hashes, in order.
const BEFORE_TENSIONS: [Tension; 4] =
    [Tension::Global(1.0), Tension::Global(0.4), Tension::Variable { lambda: 0.5 }, Tension::Variable { lambda: 1.0 }];

#[test]
fn untagged_output_is_bit_identical_to_before_creases() {
    for ((name, mesh), (before_name, steps, stencils)) in untagged_meshes().into_iter().zip(BEFORE) {
        assert_eq!(name, before_name);
        for (tension, expected) in BEFORE_TENSIONS.into_iter().zip(steps) {
            let out = subdivide(&mesh, deng_ma(tension), 3, false).unwrap();
            assert_eq!(hash(out.positions()), expected, "{name}, {tension:?}: the untagged surface moved");
            assert!(out.tags().is_empty(), "{name}: an untagged mesh stays untagged");
        }
        for (omega, expected) in [1.0, 0.4].into_iter().zip(stencils) {
            let r = subdiv_stencil::deng_ma::stencil(mesh.topology(), omega).unwrap();
            assert_eq!(hash(&apply(&r, mesh.positions())), expected, "{name}, ω = {omega}: the untagged stencil moved");
        }
    }
}

#[test]
fn untagged_plans_take_the_same_path() {
    // SubdivisionPlan and subdivide evaluate the same step: the same bits.
    for (name, mesh) in untagged_meshes() {
        for tension in TENSIONS {
            let plan = SubdivisionPlan::new(mesh.topology(), Scheme::DengMa(tension), 2).unwrap();
            let by_plan = plan.apply(mesh.positions());
            let direct = subdivide(&mesh, deng_ma(tension), 2, false).unwrap();
            assert_eq!(hash(&by_plan), hash(direct.positions()), "{name}, {tension:?}");
        }
    }
}

// ---------------------------------------------------------------- old vertices, tags

#[test]
fn old_vertices_stay_bit_for_bit_at_every_level() {
    for case in cases() {
        for tension in TENSIONS {
            let mut level = case.mesh.clone().with_tags(case.tags.clone());
            for k in 1..=4 {
                let next = subdivide(&level, deng_ma(tension), 1, false).unwrap();
                let n = level.positions().len();
                assert!(
                    next.positions()[..n].iter().zip(level.positions()).all(|(a, b)| a.to_array() == b.to_array()),
                    "{}, {tension:?}: an old vertex moved at level {k}",
                    case.name
                );
                assert!(next.positions().iter().all(|p| p.is_finite()), "{}, level {k}", case.name);
                level = next;
            }
            // One level at a time (tags carried by the mesh) is the 4-level run.
            let at_once = run(&case.mesh, &case.tags, deng_ma(tension), 4);
            assert_eq!(hash(at_once.positions()), hash(level.positions()), "{}, {tension:?}", case.name);
            assert_eq!(at_once.tags(), level.tags(), "{}", case.name);
        }
    }
}

#[test]
fn refined_tags_keep_creases_infinitely_sharp_and_corners_tagged() {
    for case in cases() {
        let t = case.mesh.topology();
        let refined = run(&case.mesh, &case.tags, deng_ma(Tension::default()), 1);
        let rt = refined.topology();
        let (nv, nf) = (t.vertex_count(), t.face_count());
        for e in t.edges().filter(|&e| case.tags.edge_sharpness(e) > 0.0) {
            // quad_split numbering: the edge point of e is vertex V + F + e.
            let mid = VertexId((nv + nf + e.index()) as u32);
            let (a, b) = t.edge_vertices(e);
            for end in [a, b] {
                let half = rt.find_edge(end, mid).expect("the edge's halves are edges of the refined mesh");
                assert!(refined.tags().edge_sharpness(half) >= SHARPNESS_INFINITE, "{}: half {end}-{mid}", case.name);
            }
            assert_eq!(sharp_neighbours(&refined, mid).len(), 2, "{}: edge point {mid} is a crease vertex", case.name);
        }
        for v in t.vertices() {
            assert_eq!(refined.tags().vertex_sharpness(v), case.tags.vertex_sharpness(v), "{}: vertex {v}", case.name);
        }
        // Only the halves of sharp edges are sharp.
        let sharp_count = |m: &Mesh| m.topology().edges().filter(|&e| m.tags().edge_sharpness(e) > 0.0).count();
        assert_eq!(sharp_count(&refined), 2 * sharp_count(&case.mesh.clone().with_tags(case.tags.clone())));
    }
}

// ---------------------------------------------------------------- the crease polygon is the 4-point curve

#[test]
fn refined_crease_polygon_is_the_four_point_refinement_of_the_input_polygon() {
    for case in cases() {
        let n0 = case.mesh.positions().len();
        for tension in TENSIONS {
            for k in 1..=4 {
                let refined = run(&case.mesh, &case.tags, deng_ma(tension), k);
                for (piece, closed) in &case.pieces {
                    let input: Vec<DVec3> = piece.iter().map(|&v| case.mesh.positions()[v as usize]).collect();
                    let expected = four_point_levels(&input, *closed, tension, k);
                    let got: Vec<DVec3> = refined_piece(&refined, piece, *closed, n0)
                        .iter()
                        .map(|v| refined.positions()[v.index()])
                        .collect();
                    assert_eq!(got.len(), expected.len(), "{}: piece {piece:?} at level {k}", case.name);
                    // The same operations on the same numbers: the same bits.
                    for (i, (g, e)) in got.iter().zip(&expected).enumerate() {
                        assert_eq!(
                            g.to_array(),
                            e.to_array(),
                            "{}, {tension:?}: point {i} of piece {piece:?} at level {k}",
                            case.name
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn edge_only_boundaries_have_no_corners() {
    // Under `edge-only` a one-face boundary vertex is no corner: the grid's
    // boundary is one closed 4-point loop through its four corners.
    let grid = bumpy(shapes::quad_grid(4, 3));
    // Vertex (i, j) is 5j + i: the bottom row, the right column, the top row back, the left column down.
    let ring: Vec<u32> = (0..5).chain([9, 14]).chain((15..20).rev()).chain([10, 5]).collect();
    assert_eq!(ring.len(), 14);
    let input: Vec<DVec3> = ring.iter().map(|&v| grid.positions()[v as usize]).collect();
    for tension in TENSIONS {
        let options = deng_ma(tension).with_boundary(BoundaryInterpolation::EdgeOnly);
        for k in 1..=3 {
            let refined = subdivide(&grid, options, k, false).unwrap();
            let got: Vec<[f64; 3]> = refined_piece(&refined, &ring, true, grid.positions().len())
                .iter()
                .map(|v| refined.positions()[v.index()].to_array())
                .collect();
            let expected: Vec<[f64; 3]> =
                four_point_levels(&input, true, tension, k).into_iter().map(|p| p.to_array()).collect();
            assert_eq!(got, expected, "{tension:?}, level {k}");
        }
        // The default keeps the corners: the boundary differs.
        let default = subdivide(&grid, deng_ma(tension), 1, false).unwrap();
        let edge_only = subdivide(&grid, options, 1, false).unwrap();
        assert_ne!(hash(default.positions()), hash(edge_only.positions()));
    }
}

// ---------------------------------------------------------------- the surface is creased

/// Angle (degrees) between the normals of the two faces of every interior
/// edge of `m` that `keep` selects.
fn dihedral_angles(m: &Mesh, keep: impl Fn(subdiv_mesh::EdgeId) -> bool) -> Vec<f64> {
    let t = m.topology();
    t.edges()
        .filter(|&e| keep(e))
        .filter_map(|e| match t.edge_faces(e) {
            (f, Some(g)) => Some(m.face_normal(f).angle_between(m.face_normal(g)).to_degrees()),
            _ => None,
        })
        .collect()
}

/// The faces of level k + 1 that descend from `faces` of level k: the quad
/// split makes one quad per half-edge, numbered by it.
fn child_faces(t: &Topology, faces: &[subdiv_mesh::FaceId]) -> Vec<subdiv_mesh::FaceId> {
    faces.iter().flat_map(|&f| t.face_half_edges(f).map(|h| subdiv_mesh::FaceId(h.0))).collect()
}

/// A roof: a 6×6 grid folded along row 3 into two planes, the grid moved
/// within its planes (rows and columns unevenly spaced, the fold row along
/// its line only) so that no rule is exact by accident.
fn roof() -> (Mesh, [(DVec3, f64); 2]) {
    let grid = shapes::quad_grid(6, 6);
    // Plane A (y ≤ 3): z = 0.6(3 − y) + 0.3x; plane B (y ≥ 3): z = 1.1(y − 3) + 0.3x.
    let planes = [(DVec3::new(0.3, -0.6, -1.0), 1.8), (DVec3::new(0.3, 1.1, -1.0), -3.3)];
    let p = grid.positions().iter().map(|p| {
        let x = p.x + 0.23 * (1.7 * p.x + 2.3 * p.y).sin();
        let y = if p.y == 3.0 { 3.0 } else { p.y + 0.21 * (2.9 * p.x - 0.7 * p.y).cos() };
        let z = if y <= 3.0 { 0.6 * (3.0 - y) + 0.3 * x } else { 1.1 * (y - 3.0) + 0.3 * x };
        DVec3::new(x, y, z)
    });
    // Plane (n, d): n·p + d = 0.
    (grid.with_positions(p.collect()), planes.map(|(n, d)| (n / n.length(), d / n.length())))
}

#[test]
fn a_roof_creased_along_its_fold_keeps_both_planes_and_the_angle() {
    let (mesh, planes) = roof();
    let fold = grid_row(3, 0, 6);
    let creased = tags(mesh.topology(), &polygon_edges(&fold, false), &[]);
    let input_angle = planes[0].0.angle_between(planes[1].0).to_degrees();
    let input = dihedral_angles(&mesh, |e| creased.edge_sharpness(e) > 0.0);
    assert!(input.iter().all(|a| (a - input_angle).abs() < 1e-9));
    for tension in TENSIONS {
        let mut level = mesh.clone().with_tags(creased.clone());
        // Faces below the fold are the first 3 rows of cells, 0..18.
        let mut below: Vec<subdiv_mesh::FaceId> = (0..18).map(subdiv_mesh::FaceId).collect();
        for k in 1..=4 {
            let next = subdivide(&level, deng_ma(tension), 1, false).unwrap();
            below = child_faces(level.topology(), &below);
            level = next;
            let t = level.topology();
            let is_below: std::collections::HashSet<u32> = below.iter().map(|f| f.0).collect();
            let mut worst: f64 = 0.0;
            for f in t.face_ids() {
                let (n, d) = planes[usize::from(!is_below.contains(&f.0))];
                for &v in t.face(f) {
                    worst = worst.max((n.dot(level.positions()[v as usize]) + d).abs());
                }
            }
            assert!(worst < 1e-13, "{tension:?}, level {k}: a vertex is {worst:e} off its side's plane");
            let across = dihedral_angles(&level, |e| level.tags().edge_sharpness(e) > 0.0);
            assert_eq!(across.len(), 6 << k);
            for a in across {
                assert!(
                    (a - input_angle).abs() < 1e-8,
                    "{tension:?}, level {k}: {a}° across the fold, {input_angle}° in"
                );
            }
        }
        // Without the crease the fold is smoothed out (measured: the largest
        // angle at level 4 is 17°-62°, against 76.4° in).
        let smooth = subdivide(&mesh, deng_ma(tension), 4, false).unwrap();
        let largest = dihedral_angles(&smooth, |_| true).into_iter().fold(0.0, f64::max);
        assert!(largest < input_angle - 10.0, "{tension:?}: untagged, {largest}° vs {input_angle}°");
    }
}

#[test]
fn a_box_with_every_edge_sharp_stays_the_box() {
    // A box [0, 2] × [0, 1] × [0, 0.5]: every vertex has three sharp edges (a
    // corner), every edge is a piece between two corners (linear phantoms:
    // the midpoint), so each face is an open planar mesh bounded by its edges.
    let cube = shapes::cube();
    let size = DVec3::new(2.0, 1.0, 0.5);
    let boxed = cube.with_positions(cube.positions().iter().map(|p| *p * size).collect());
    let sharp = tags(boxed.topology(), &CUBE_EDGES, &[]);
    for tension in TENSIONS {
        let refined = run(&boxed, &sharp, deng_ma(tension), 4);
        for (v, p) in refined.positions().iter().enumerate() {
            let q = *p / size; // the unit cube
            let inside = q.to_array().iter().all(|&c| (-1e-14..=1.0 + 1e-14).contains(&c));
            let on_a_face = q.to_array().iter().any(|&c| c.abs() < 1e-14 || (c - 1.0).abs() < 1e-14);
            assert!(inside && on_a_face, "{tension:?}: vertex {v} at {p} is off the box");
        }
        // Every face lies in one face plane of the box: it stays planar.
        let t = refined.topology();
        for f in t.face_ids() {
            let corners: Vec<DVec3> = t.face(f).iter().map(|&v| refined.positions()[v as usize] / size).collect();
            let planar = (0..3)
                .any(|axis| [0.0, 1.0].iter().any(|&c| corners.iter().all(|q| (q.to_array()[axis] - c).abs() < 1e-14)));
            assert!(planar, "{tension:?}: face {f} leaves its plane");
        }
    }
}

#[test]
fn a_cube_with_its_top_loop_sharp_keeps_a_flat_top_and_a_crease() {
    let cube = shapes::cube();
    let top = tags(cube.topology(), &polygon_edges(&CUBE_TOP, true), &[]);
    for tension in TENSIONS {
        let mut level = cube.clone().with_tags(top.clone());
        let mut top_faces = vec![subdiv_mesh::FaceId(1)]; // face 4 5 7 6
        let mut crease_min = f64::INFINITY;
        for k in 1..=4 {
            let next = subdivide(&level, deng_ma(tension), 1, false).unwrap();
            top_faces = child_faces(level.topology(), &top_faces);
            level = next;
            // The top (its face's descendants, the crease loop among them) stays in z = 1.
            for &f in &top_faces {
                for &v in level.topology().face(f) {
                    let z = level.positions()[v as usize].z;
                    assert!((z - 1.0).abs() < 1e-15, "{tension:?}, level {k}: top vertex {v} at z = {z}");
                }
            }
            let across = dihedral_angles(&level, |e| level.tags().edge_sharpness(e) > 0.0);
            assert_eq!(across.len(), 4 << k);
            for a in across {
                assert!((85.0..95.0).contains(&a), "{tension:?}, level {k}: {a}° across the crease (90° in)");
                crease_min = crease_min.min(a);
            }
        }
        // Untagged, the same edges smooth out: the largest angle anywhere
        // at level 4 is well below the crease's (measured: 29°-66° vs ≥ 86°).
        let smooth = subdivide(&cube, deng_ma(tension), 4, false).unwrap();
        let largest = dihedral_angles(&smooth, |_| true).into_iter().fold(0.0, f64::max);
        assert!(largest < crease_min - 15.0, "{tension:?}: untagged {largest}°, creased ≥ {crease_min}°");
    }
}

// ---------------------------------------------------------------- a crease is a cut

/// Mesh from positions and faces (the cut meshes below).
fn mesh_of(positions: Vec<DVec3>, faces: Vec<Vec<u32>>) -> Mesh {
    Mesh::new(positions, FaceList::from_faces(faces)).expect("a valid cut mesh")
}

/// Rows r0..=r1 of the 6×6 grid `grid` as a mesh of their own.
fn grid_rows(grid: &Mesh, r0: u32, r1: u32) -> Mesh {
    let id = |c: u32, r: u32| 7 * (r - r0) + c;
    let positions = (r0..=r1).flat_map(|r| (0..7).map(move |c| g6(c, r))).map(|v| grid.positions()[v as usize]);
    let faces =
        (r0..r1).flat_map(|r| (0..6).map(move |c| vec![id(c, r), id(c + 1, r), id(c + 1, r + 1), id(c, r + 1)]));
    mesh_of(positions.collect(), faces.collect())
}

/// A tagged mesh and the untagged meshes (with their options) it is cut into.
type Cut<'a> = (&'a str, &'a Mesh, &'a Tags, Vec<(Mesh, Options)>);

/// Every point of `a` has a point of `b` within `tol`, and conversely.
fn same_point_sets(a: &[DVec3], b: &[DVec3], tol: f64) -> Result<(), String> {
    for (from, to, name) in [(a, b, "tagged"), (b, a, "cut")] {
        for (i, p) in from.iter().enumerate() {
            let d = to.iter().map(|q| q.distance(*p)).fold(f64::INFINITY, f64::min);
            if d > tol {
                return Err(format!("{name} point {i} at {p} is {d:e} from the other set"));
            }
        }
    }
    Ok(())
}

#[test]
fn a_crease_refines_as_the_mesh_cut_along_it() {
    // A mesh creased along a closed loop or along a piece between corners is
    // refined as the untagged meshes it is cut into, each with its boundary
    // there: the tagged surface is the cut surfaces glued along the shared
    // 4-point curve (variable tension included: ω per sector).
    let grid = bumpy(shapes::quad_grid(6, 6));
    let across = tags(grid.topology(), &polygon_edges(&grid_row(3, 0, 6), false), &[]);
    let cube = bumpy(shapes::cube());
    let top = tags(cube.topology(), &polygon_edges(&CUBE_TOP, true), &[]);
    let (box_faces, top_face): (Vec<_>, Vec<_>) =
        cube.topology().faces().iter().map(<[u32]>::to_vec).enumerate().partition(|&(f, _)| f != 1);
    let open_box = mesh_of(cube.positions().to_vec(), box_faces.into_iter().map(|(_, f)| f).collect());
    let lid = mesh_of(cube.positions()[4..8].to_vec(), vec![top_face[0].1.iter().map(|v| v - 4).collect()]);
    // The torus cut along the meridian i = 0: a tube, the meridian doubled as i = 6.
    let torus = bumpy(shapes::torus(6, 8));
    let meridian = tags(torus.topology(), &polygon_edges(&(0..8).collect::<Vec<u32>>(), true), &[]);
    let tube_positions: Vec<DVec3> = (0..56).map(|v| torus.positions()[v % 48]).collect();
    let tube_faces = (0..6u32).flat_map(|i| {
        (0..8u32).map(move |j| {
            let id = |i: u32, j: u32| 8 * i + j % 8;
            vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]
        })
    });
    let tube = mesh_of(tube_positions, tube_faces.collect());
    for tension in TENSIONS {
        let edge_only = deng_ma(tension).with_boundary(BoundaryInterpolation::EdgeOnly);
        let cuts: [Cut; 3] = [
            (
                "grid across row 3",
                &grid,
                &across,
                vec![(grid_rows(&grid, 0, 3), deng_ma(tension)), (grid_rows(&grid, 3, 6), deng_ma(tension))],
            ),
            // The lid's corners are crease vertices of the loop, not corners: edge-only.
            ("cube's top loop", &cube, &top, vec![(open_box.clone(), deng_ma(tension)), (lid.clone(), edge_only)]),
            ("torus meridian", &torus, &meridian, vec![(tube.clone(), deng_ma(tension))]),
        ];
        for (name, mesh, tags, parts) in cuts {
            for k in 1..=3 {
                let tagged = run(mesh, tags, deng_ma(tension), k);
                let cut: Vec<DVec3> = parts
                    .iter()
                    .flat_map(|(part, options)| subdivide(part, *options, k, false).unwrap().positions().to_vec())
                    .collect();
                if let Err(e) = same_point_sets(tagged.positions(), &cut, 1e-13) {
                    panic!("{name}, {tension:?}, level {k}: {e}");
                }
            }
        }
    }
}

// ---------------------------------------------------------------- darts and corners

#[test]
fn a_dart_ends_its_crease_and_is_smooth_itself() {
    // Row 1 creased from the boundary (a corner: three sharp edges) to the
    // dart (4, 1). Its piece ends there with the linear phantom (the crease
    // polygon test), and the dart's own moved images are the smooth ones:
    // the points that read the dart and no crease vertex are the untagged
    // points, bit for bit; a corner tag at the dart changes them.
    let grid = bumpy(shapes::quad_grid(6, 6));
    let creases = polygon_edges(&grid_row(1, 0, 4), false);
    let dart = tags(grid.topology(), &creases, &[]);
    let dart_as_corner = tags(grid.topology(), &creases, &[g6(4, 1)]);
    let t = grid.topology();
    let (nv, nf) = (t.vertex_count(), t.face_count());
    // Cells (4, 0) and (4, 1) hold the dart and no crease vertex; so does the E-face of edge (4,1)-(5,1).
    let edge = t.find_edge(VertexId(g6(4, 1)), VertexId(g6(5, 1))).unwrap();
    let untouched = [nv + 4, nv + 6 + 4, nv + nf + edge.index()];
    for tension in TENSIONS {
        let plain = run(&grid, &Tags::none(), deng_ma(tension), 1);
        let with_dart = run(&grid, &dart, deng_ma(tension), 1);
        let with_corner = run(&grid, &dart_as_corner, deng_ma(tension), 1);
        for i in untouched {
            assert_eq!(with_dart.positions()[i].to_array(), plain.positions()[i].to_array(), "{tension:?}: point {i}");
            assert_ne!(with_corner.positions()[i], plain.positions()[i], "{tension:?}: point {i}");
        }
        // Finite and interpolating down to level 4, the dart a dart at every level.
        let deep = run(&grid, &dart, deng_ma(tension), 4);
        assert!(deep.positions().iter().all(|p| p.is_finite()));
        assert_eq!(&deep.positions()[..nv], grid.positions());
        assert_eq!(sharp_neighbours(&deep, VertexId(g6(4, 1))).len(), 1);
    }
}

#[test]
fn a_corner_without_sharp_edges_stays_a_tip() {
    // The apex of a pyramid tagged as a corner: G = P there, and the surface
    // keeps a tip as Catmull-Clark's corner does (measured at level 5, mean
    // slope from the apex to its refined neighbours: Deng-Ma 1.10-1.80,
    // Catmull-Clark's limit 2.64; untagged Deng-Ma flattens to 0.10-0.52).
    let pyramid = shapes::pyramid(5);
    let apex = VertexId(5);
    let corner = tags(pyramid.topology(), &[], &[apex.0]);
    let slope = |m: &Mesh| {
        let p = m.positions()[apex.index()];
        let ring: Vec<DVec3> = m.topology().vertex_neighbors(apex).map(|v| m.positions()[v.index()]).collect();
        ring.iter().map(|q| (p.z - q.z) / (q.x - p.x).hypot(q.y - p.y)).sum::<f64>() / ring.len() as f64
    };
    assert!((slope(&pyramid) - 1.0).abs() < 1e-12);
    for tension in TENSIONS {
        let tip = run(&pyramid, &corner, deng_ma(tension), 5);
        let smooth = run(&pyramid, &Tags::none(), deng_ma(tension), 5);
        assert_eq!(tip.tags().vertex_sharpness(apex), SHARPNESS_INFINITE, "the corner tag is carried");
        assert!(slope(&tip) > 1.0, "{tension:?}: the tip flattened to slope {}", slope(&tip));
        assert!(slope(&smooth) < 0.6, "{tension:?}: untagged slope {}", slope(&smooth));
    }
}

// ---------------------------------------------------------------- tags Deng-Ma refuses or ignores

#[test]
fn semi_sharp_tags_are_refused_naming_the_element() {
    let grid = shapes::quad_grid(6, 6);
    let t = grid.topology();
    let (a, b) = (g6(2, 3), g6(3, 3));
    let e = t.find_edge(VertexId(a), VertexId(b)).unwrap();
    let semi_edge = Tags::from_list(
        t,
        &TagList { creases: vec![EdgeTag { a, b, sharpness: 2.5 }], corners: vec![], ..Default::default() },
    );
    let semi_vertex = Tags::from_list(
        t,
        &TagList { creases: vec![], corners: vec![VertexTag { vertex: 24, sharpness: 1.0 }], ..Default::default() },
    );
    let (ea, eb) = t.edge_vertices(e); // the edge's own direction, as the message names it
    let cases = [
        (semi_edge.unwrap(), format!("edge {} (vertices {ea}-{eb})", e.0), 2.5),
        (semi_vertex.unwrap(), "vertex 24".into(), 1.0),
    ];
    for (tags, what, sharpness) in cases {
        for tension in TENSIONS {
            let err = subdivide(&grid.clone().with_tags(tags.clone()), deng_ma(tension), 1, false).unwrap_err();
            assert_eq!(err, StencilError::SemiSharpDengMa { what: what.clone(), sharpness }, "{err}");
            let message = err.to_string();
            for needle in [what.as_str(), "cannot take these tags", "use sharpness ≥ 10", "Catmull-Clark/Loop"] {
                assert!(message.contains(needle), "{message}");
            }
            let planned = SubdivisionPlan::with_tags(t, &tags, Scheme::DengMa(tension), 2).unwrap_err();
            assert_eq!(planned, err);
            // Zero levels check too: the same mesh cannot be planned either way.
            assert!(subdivide(&grid.clone().with_tags(tags.clone()), deng_ma(tension), 0, false).is_err());
        }
    }
}

#[test]
fn what_does_not_change_the_rules_does_not_change_the_surface() {
    let grid = bumpy(shapes::quad_grid(6, 6));
    let t = grid.topology();
    let row = polygon_edges(&grid_row(3, 0, 6), false);
    let at = |sharpness: f32, corner: f32| {
        let list = TagList {
            creases: row.iter().map(|&(a, b)| EdgeTag { a, b, sharpness }).collect(),
            corners: vec![VertexTag { vertex: g6(2, 5), sharpness: corner }],
            ..Default::default()
        };
        Tags::from_list(t, &list).unwrap()
    };
    // A semi-sharp tag on a boundary edge: boundary edges are sharp anyway.
    let on_boundary = Tags::from_list(
        t,
        &TagList { creases: vec![EdgeTag { a: 0, b: 1, sharpness: 2.5 }], corners: vec![], ..Default::default() },
    )
    .unwrap();
    for tension in TENSIONS {
        let reference = hash(run(&grid, &at(10.0, 10.0), deng_ma(tension), 3).positions());
        // Any value ≥ 10 is infinitely sharp; the crease method decays semi-sharp values only.
        assert_eq!(hash(run(&grid, &at(f32::INFINITY, 12.5), deng_ma(tension), 3).positions()), reference);
        let chaikin = deng_ma(tension).with_crease_method(CreaseMethod::Chaikin);
        assert_eq!(hash(run(&grid, &at(10.0, 10.0), chaikin, 3).positions()), reference);
        let plain = hash(run(&grid, &Tags::none(), deng_ma(tension), 3).positions());
        assert_eq!(hash(run(&grid, &on_boundary, deng_ma(tension), 3).positions()), plain);
    }
}

// ---------------------------------------------------------------- the linear stencil, displacement safety

#[test]
fn the_tagged_stencil_is_the_tagged_step() {
    for case in cases() {
        let t = case.mesh.topology();
        let sharp = LevelSharpness::new(&case.tags, BoundaryInterpolation::EdgeAndCorner, CreaseMethod::Uniform);
        let x = case.mesh.positions();
        for omega in [1.0, 0.5, 0.125] {
            let r = stencil_tagged(t, &sharp, omega).unwrap();
            let linear = apply(&r, x);
            let geometric = step_positions_tagged(t, &sharp, x, Tension::Global(omega)).unwrap();
            let worst = linear.iter().zip(&geometric).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
            assert!(worst <= 1e-14, "{}, ω = {omega}: stencil and step differ by {worst:e}", case.name);
            assert!(row_sums(&r).iter().all(|s| (s - 1.0).abs() < 1e-14), "{}: not affine", case.name);
            // A sharp edge's point reads the sharp polygon only.
            let tagged = case.mesh.clone().with_tags(case.tags.clone());
            for e in t.edges().filter(|&e| sharp_edge(&tagged, e)) {
                let row = r.outer_view(t.vertex_count() + t.face_count() + e.index()).unwrap();
                for (col, _) in row.iter() {
                    let v = VertexId(col as u32);
                    assert!(!sharp_neighbours(&tagged, v).is_empty(), "{}: edge {e:?} reads vertex {v}", case.name);
                }
            }
        }
    }
}

#[test]
fn the_variable_tension_is_displacement_safe_next_to_creases() {
    // §3.4's bound d_E ≤ (λ/4)‖P₁ − P₂‖ for every new edge point, sharp or
    // smooth, at the first two levels: per-sector ω keeps it where the sharp
    // edges cut a fan.
    for case in cases() {
        for lambda in [0.25, 0.5, 1.0] {
            let mut level = case.mesh.clone().with_tags(case.tags.clone());
            for k in 1..=2 {
                let next = subdivide(&level, deng_ma(Tension::Variable { lambda }), 1, false).unwrap();
                let t = level.topology();
                let base = t.vertex_count() + t.face_count();
                for e in t.edges() {
                    let (a, b) = t.edge_vertices(e);
                    let (p, q) = (level.positions()[a.index()].to_array(), level.positions()[b.index()].to_array());
                    let ratio = edge_displacement_ratio(next.positions()[base + e.index()].to_array(), p, q);
                    assert!(
                        ratio <= lambda / 4.0 + 1e-12,
                        "{}, λ = {lambda}, level {k}: edge {e:?} strays {ratio}",
                        case.name
                    );
                }
                level = next;
            }
        }
    }
}

// ---------------------------------------------------------------- determinism, degenerate and random meshes

#[test]
fn same_bits_whatever_the_thread_count() {
    // Large enough for the parallel chunks (more than 8192 rows per pass).
    let torus = bumpy(shapes::torus(48, 40));
    let meridian: Vec<u32> = (0..40).collect();
    let longitude: Vec<u32> = (0..48).map(|i| 40 * i + 7).collect();
    let creases: Vec<(u32, u32)> =
        polygon_edges(&meridian, true).into_iter().chain(polygon_edges(&longitude, true)).collect();
    let sharp = tags(torus.topology(), &creases, &[40 * 20 + 20]);
    for tension in [Tension::Global(1.0), Tension::Variable { lambda: 0.5 }] {
        let hashes: Vec<u64> = [1, 2]
            .into_iter()
            .map(|threads| {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                pool.install(|| hash(run(&torus, &sharp, deng_ma(tension), 2).positions()))
            })
            .collect();
        assert_eq!(hashes[0], hashes[1], "{tension:?}");
    }
}

/// Subdivides `levels` times one level at a time and checks what every
/// tagged mesh must give: no error, old vertices bit for bit, finite points.
fn check_levels(name: &str, mesh: &Mesh, tension: Tension, levels: usize) -> Result<(), String> {
    let mut level = mesh.clone();
    for k in 1..=levels {
        let next = subdivide(&level, deng_ma(tension), 1, false).map_err(|e| format!("{name}, level {k}: {e}"))?;
        let n = level.positions().len();
        if next.positions()[..n].iter().zip(level.positions()).any(|(a, b)| a.to_array() != b.to_array()) {
            return Err(format!("{name}, {tension:?}: an old vertex moved at level {k}"));
        }
        if let Some(v) = next.positions().iter().position(|p| !p.is_finite()) {
            return Err(format!("{name}, {tension:?}: vertex {v} is not finite at level {k}"));
        }
        level = next;
    }
    Ok(())
}

#[test]
fn small_and_degenerate_tagged_meshes_do_not_panic() {
    let triangle = mesh_of(vec![DVec3::ZERO, DVec3::X, DVec3::Y], vec![vec![0, 1, 2]]);
    let two_triangles = mesh_of(vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE], vec![vec![0, 1, 2], vec![2, 1, 3]]);
    // An isolated vertex (4) tagged as a corner.
    let with_isolated = mesh_of(
        vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.3), DVec3::Y, DVec3::splat(5.0)],
        vec![vec![0, 1, 2, 3]],
    );
    let pillow = shapes::pillow();
    let cases: Vec<(&str, Mesh, Tags)> = vec![
        ("a triangle, corners tagged", triangle.clone(), tags(triangle.topology(), &[], &[0, 1, 2])),
        ("a triangle, its boundary tagged", triangle.clone(), tags(triangle.topology(), &[(0, 1), (1, 2)], &[])),
        ("two triangles creased between", two_triangles.clone(), tags(two_triangles.topology(), &[(1, 2)], &[])),
        ("a quad and an isolated corner", with_isolated.clone(), tags(with_isolated.topology(), &[], &[4, 2])),
        ("a pillow, every edge sharp", pillow.clone(), tags(pillow.topology(), &[(0, 1), (1, 2), (2, 3), (3, 0)], &[])),
        ("a pillow, one dart", pillow.clone(), tags(pillow.topology(), &[(0, 1)], &[])),
        ("a tetrahedron, all sharp", shapes::tetrahedron(), {
            let t = shapes::tetrahedron();
            tags(t.topology(), &[(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)], &[])
        }),
    ];
    for (name, mesh, tags) in cases {
        for tension in TENSIONS {
            check_levels(name, &mesh.clone().with_tags(tags.clone()), tension, 3).unwrap();
        }
    }
}

/// A base shape for the random meshes.
#[derive(Clone, Debug)]
enum Shape {
    Plate { nx: usize, ny: usize, closed: bool },
    Torus { nu: usize, nv: usize },
    TriangleGrid { n: usize },
    Pyramid { n: usize },
    Prism { n: usize },
    Icosahedron,
}

impl Shape {
    fn mesh(&self) -> Mesh {
        match *self {
            Shape::Plate { nx, ny, closed } => shapes::plate_with_holes(nx, ny, &[(1, 1)], closed),
            Shape::Torus { nu, nv } => shapes::torus(nu, nv),
            Shape::TriangleGrid { n } => shapes::triangle_grid(n, n),
            Shape::Pyramid { n } => shapes::pyramid(n),
            Shape::Prism { n } => shapes::prism(n),
            Shape::Icosahedron => shapes::icosahedron(),
        }
    }
}

fn shape() -> impl Strategy<Value = Shape> {
    prop_oneof![
        (3usize..6, 3usize..6, any::<bool>()).prop_map(|(nx, ny, closed)| Shape::Plate { nx, ny, closed }),
        (3usize..7, 3usize..7).prop_map(|(nu, nv)| Shape::Torus { nu, nv }),
        (1usize..5).prop_map(|n| Shape::TriangleGrid { n }),
        (3usize..9).prop_map(|n| Shape::Pyramid { n }),
        (3usize..9).prop_map(|n| Shape::Prism { n }),
        Just(Shape::Icosahedron),
    ]
}

fn tension() -> impl Strategy<Value = Tension> {
    prop_oneof![
        (0.05..=1.0f64).prop_map(Tension::Global),
        (0.05..=1.0f64).prop_map(|lambda| Tension::Variable { lambda })
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// Random shapes, mixed into polygons, with random infinitely sharp
    /// edges (10 or +∞) and corners: never a panic or an error, old vertices
    /// kept bit for bit, every point finite, over three levels.
    #[test]
    fn random_tagged_meshes_subdivide(
        shape in shape(),
        seed in any::<u64>(),
        merge in 0.0..0.4f64,
        edge_picks in proptest::collection::vec((any::<prop::sample::Index>(), any::<bool>()), 0..12),
        corner_picks in proptest::collection::vec(any::<prop::sample::Index>(), 0..4),
        tension in tension(),
    ) {
        let mesh = shapes::polygon_mix(&shape.mesh(), seed, merge, 0.3, 0.1);
        let t = mesh.topology();
        let mut edges = vec![0.0f32; t.edge_count()];
        for (pick, infinite) in edge_picks {
            edges[pick.index(t.edge_count())] = if infinite { f32::INFINITY } else { SHARPNESS_INFINITE };
        }
        let mut vertices = vec![0.0f32; t.vertex_count()];
        for pick in corner_picks {
            vertices[pick.index(t.vertex_count())] = SHARPNESS_INFINITE;
        }
        let tags = Tags::from_arrays(t, edges, vertices).unwrap();
        let levels = if t.face_count() > 60 { 2 } else { 3 };
        if let Err(e) = check_levels(&format!("{shape:?}"), &mesh.with_tags(tags), tension, levels) {
            return Err(TestCaseError::fail(e));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// A semi-sharp value on a random edge or vertex: the typed refusal
    /// where the rules would see it (an interior edge, a vertex that is not
    /// a one-face boundary corner already), else the surface of the tag
    /// left out; never a panic.
    #[test]
    fn random_semi_sharp_tags_are_refused_or_inert(
        shape in shape(),
        pick in any::<prop::sample::Index>(),
        on_edge in any::<bool>(),
        sharpness in 0.01f32..9.99,
        tension in tension(),
    ) {
        let mesh = shape.mesh();
        let t = mesh.topology();
        let (mut edges, mut vertices) = (vec![0.0f32; t.edge_count()], vec![0.0f32; t.vertex_count()]);
        let seen = if on_edge {
            let e = subdiv_mesh::EdgeId(pick.index(t.edge_count()) as u32);
            edges[e.index()] = sharpness;
            !t.is_boundary_edge(e)
        } else {
            let v = VertexId(pick.index(t.vertex_count()) as u32);
            vertices[v.index()] = sharpness;
            !(t.is_boundary_vertex(v) && t.vertex_face_count(v) == 1)
        };
        let tagged = mesh.clone().with_tags(Tags::from_arrays(t, edges, vertices).unwrap());
        match subdivide(&tagged, deng_ma(tension), 2, false) {
            Err(StencilError::SemiSharpDengMa { sharpness: s, .. }) => prop_assert!(seen && s == sharpness),
            Err(e) => prop_assert!(false, "unexpected error {e}"),
            Ok(out) => {
                prop_assert!(!seen);
                let plain = subdivide(&mesh, deng_ma(tension), 2, false).unwrap();
                prop_assert_eq!(hash(out.positions()), hash(plain.positions()));
            }
        }
    }
}
