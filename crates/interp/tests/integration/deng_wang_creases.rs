//! Deng-Wang with tags and UVs: the control mesh M¹, *with its tags* (the
//! input's decayed by one level), has the data as its Loop limit points on
//! every tagged case (closed and open, infinitely sharp and semi-sharp under
//! both crease methods, corners, darts, `edge-only`, polygon and triangle
//! input) — measured by `Interpolant::error` and by brute force (refining
//! the written control mesh with its tags and watching the data points'
//! descendants converge onto the data); without its tags it misses them.
//! Untagged input gives the bits it gave before tags existed (hashes
//! recorded from the code before the change), and tags change nothing away
//! from them. UVs: the control mesh and the surface carry the input's
//! channel, with its seams exactly where the input has them.
//!
//! Run with `--nocapture` to see the tables.

use crate::support::fixture;
use glam::{DVec2, DVec3};
use subdiv_interp::*;
use subdiv_mesh::refine::triangle_split;
use subdiv_mesh::{shapes, triangulate, FaceVarying, Mesh, Tags, Topology};
use subdiv_mesh::{VertexId, SHARPNESS_INFINITE};
use subdiv_stencil::{subdivide, BoundaryInterpolation, CreaseMethod, FVarInterpolation, LoopBeta};

use crate::support::tagged::*;

// ---- the tagged cases (as `tests/integration/creases.rs`, plus triangle input) --------

/// The jittered icosahedron (a triangle mesh: no triangulation) with the
/// pentagon around vertex 0 as a crease loop at `s` and a dart at vertex 0's
/// antipode's edge.
fn icosahedron_case(s: f32) -> Mesh {
    let ico = jittered(&shapes::icosahedron(), 0.1);
    let t = ico.topology();
    let ring: Vec<u32> = t.vertex_neighbors(VertexId(0)).map(|v| v.0).collect();
    let mut creases: Vec<(u32, u32, f32)> = (0..ring.len()).map(|k| (ring[k], ring[(k + 1) % ring.len()], s)).collect();
    let far = (0..12u32).max_by(|&a, &b| {
        let d = |v: u32| ico.positions()[v as usize].distance(ico.positions()[0]);
        d(a).total_cmp(&d(b))
    });
    let far = far.expect("12 vertices");
    let next = t.vertex_neighbors(VertexId(far)).next().expect("a neighbour").0;
    creases.push((far, next, INF));
    tagged(&ico, &creases, &[])
}

/// Every tagged case, with a name and whether it has semi-sharp values:
/// the common ones and two on a triangle mesh.
fn cases() -> Vec<(&'static str, Mesh, bool)> {
    let mut cases = common_cases();
    cases.extend([
        ("icosahedron (triangles), crease loop and dart", icosahedron_case(INF), false),
        ("icosahedron (triangles), crease loop at 0.5 and dart", icosahedron_case(0.5), true),
        (
            "octahedron (triangles, fixture), corner with four edges at 1.5",
            fixture("peer/creases/octahedron_corner_creases/octahedron_corner_creases.obj"),
            true,
        ),
    ]);
    cases
}

/// The crease methods a case is run with: Chaikin differs only with semi-sharp values.
fn methods(semi: bool) -> &'static [CreaseMethod] {
    if semi {
        &[CreaseMethod::Uniform, CreaseMethod::Chaikin]
    } else {
        &[CreaseMethod::Uniform]
    }
}

fn options(method: CreaseMethod) -> DengWangOptions {
    let mut opts = DengWangOptions::default();
    opts.common.surface.crease_method = method;
    opts.common.tol = 1e-10;
    opts
}

fn max_rel(result: &Interpolant, mesh: &Mesh) -> f64 {
    result.error(mesh.positions(), &result.interpolated, mesh.bbox_diagonal()).max_rel
}

/// The `limit_rows` counts of a result: smooth, crease, corner, general.
fn limit_rows(result: &Interpolant) -> [usize; 4] {
    let rows = result.parameters.limit_rows.expect("Deng-Wang counts its limit rows");
    [rows.smooth, rows.crease, rows.corner, rows.general]
}

// ---- interpolation with tags ------------------------------------------------

/// Every case, both crease methods where they differ: the measured error is
/// round-off; the control mesh is the tagged Loop split of the (triangulated)
/// input — same topology and the tags one level of `subdivide` gives, i.e.
/// the input's decayed by one level; without its tags the control mesh
/// misses the data by far more than round-off.
#[test]
fn every_tagged_case_is_interpolated_by_the_control_mesh_with_its_tags() {
    println!("{:<64} {:>8} {:>10} {:>10}  rows s/c/k/g", "case", "method", "error", "untagged");
    for (name, mesh, semi) in cases() {
        let tri = triangulate(&mesh).unwrap().mesh;
        for &method in methods(semi) {
            let opts = options(method);
            let r = deng_wang::interpolate(&mesh, &opts).unwrap_or_else(|e| panic!("{name}, {method:?}: {e}"));
            let err = max_rel(&r, &mesh);
            assert!(err <= 1e-10, "{name}, {method:?}: error {err:e}");
            assert_eq!(r.surface_options.crease_method, method);
            // The one-level decay of the input's tags, on the triangle split of M⁰.
            let one = subdivide(&tri, r.options(), 1, false).unwrap();
            assert_eq!(r.control.topology().faces(), one.topology().faces(), "{name}: M¹ is the triangle split");
            assert_eq!(r.control.tags(), one.tags(), "{name}, {method:?}: the control tags are the decayed input tags");
            assert!(!r.control.tags().is_empty(), "{name}: every case keeps a tag after one level");
            // Without its tags the control mesh misses the data (by 1e-3·d and more; a loop at
            // sharpness 0.5 by 9.8e-4·d): the tags matter.
            let mut plain = r.clone();
            plain.control = r.control.clone().with_tags(Tags::none());
            let untagged = max_rel(&plain, &mesh);
            assert!(untagged > 1e-4, "{name}, {method:?}: the tags make no difference ({untagged:e})");
            // Every interpolated vertex has one row, and the report counts them.
            let rows = limit_rows(&r);
            assert_eq!(rows.iter().sum::<usize>(), mesh.topology().vertex_count(), "{name}");
            if semi {
                assert!(rows[3] > 0, "{name}: semi-sharp values leave general rows ({rows:?})");
            }
            println!("{name:<64} {:>8} {err:>10.2e} {untagged:>10.2e}  {rows:?}", format!("{method:?}").to_lowercase());
        }
    }
}

/// Why no coupled system is solved: in M¹'s tagged limit matrix the row of
/// every old vertex — general rows (darts, semi-sharp values left) included —
/// reads no other old vertex, only edge points (the closed 1-ring), and its
/// own weight is far from 0 (≥ 0.1 here; the method refuses below 1e-6).
#[test]
fn old_vertex_limit_rows_read_only_edge_points() {
    let mut smallest = f64::INFINITY;
    for (name, mesh, semi) in cases() {
        for &method in methods(semi) {
            let r = deng_wang::interpolate(&mesh, &options(method)).unwrap();
            let sharp = r.surface_options.sharpness(r.control.tags());
            let a = subdiv_stencil::limit_matrix_loop_sharp(r.control.topology(), &sharp, LoopBeta::Warren).unwrap();
            let nv = mesh.topology().vertex_count();
            for v in 0..nv {
                let row = a.s.outer_view(v).unwrap();
                for (c, &w) in row.iter() {
                    assert!(c == v || c >= nv, "{name}: row {v} reads old vertex {c}");
                    if c == v {
                        smallest = smallest.min(a.d[v] * w);
                    }
                }
            }
        }
    }
    println!("smallest centre weight of an old vertex's limit row: {smallest}");
    assert!(smallest >= 0.1);
}

/// The interior vertices of `mesh` with exactly one sharp edge, infinitely
/// sharp, and no other sharpness: darts for ever.
fn darts(mesh: &Mesh) -> Vec<bool> {
    let t = mesh.topology();
    t.vertices()
        .map(|v| {
            let sharp: Vec<f32> = t
                .vertex_neighbors(v)
                .map(|u| mesh.tags().edge_sharpness(t.find_edge(v, u).expect("a neighbour")))
                .filter(|&s| s > 0.0)
                .collect();
            !t.is_boundary_vertex(v) && mesh.tags().vertex_sharpness(v) == 0.0 && sharp == [INF]
        })
        .collect()
}

/// Brute force, independent of every limit mask: refine the written control
/// mesh with its tags (`subdivide`, no limit) level by level; input vertex i
/// is vertex i of every Loop level and must converge onto data point i at
/// the scheme's rate (the gap falls by ~4 per level; ≥ 8 over two levels
/// asserted), within 2e-3·d at level 6.
///
/// Darts too, but more slowly: the limit that `Interpolant::error` and the
/// method use there is the dart's exact limit (`DartLimit::Exact`, the left
/// eigenvector of the dart's own subdivision matrix), the point refinement
/// converges to, and the dart's asymmetry leaves the subdominant eigenvalue
/// ½ in its centre: the gap falls by ≥ 1.8× per level (measured 1.9-2.1×)
/// and is within 2e-4·d at level 6 (measured ≤ 8.4e-5·d). Under
/// `DartLimit::SmoothMask` (OpenSubdiv's smooth mask, which is no left
/// eigenvector of the dart's matrix) the gap would stall instead, at
/// 2e-4·d on the torus and 1e-3·d on the coarse icosahedron.
#[test]
fn refining_the_control_mesh_converges_onto_the_data() {
    println!(
        "{:<64} {:>8} {:>9} {:>9} {:>9} {:>6} {:>9}",
        "case", "method", "gap L4", "gap L5", "gap L6", "L5/L6", "darts L6"
    );
    for (name, mesh, semi) in cases() {
        let dart = darts(&triangulate(&mesh).unwrap().mesh);
        for &method in methods(semi) {
            let r = deng_wang::interpolate(&mesh, &options(method)).unwrap();
            let d = mesh.bbox_diagonal();
            let n = mesh.topology().vertex_count();
            let mut level = r.control.clone();
            let mut history: Vec<Vec<DVec3>> = Vec::new();
            for _ in 0..6 {
                // One level at a time: the refined mesh carries its decayed tags to the next.
                level = subdivide(&level, r.options(), 1, false).unwrap();
                history.push(level.positions()[..n].to_vec());
            }
            let gap = |k: usize, darts: bool| {
                (0..n)
                    .filter(|&i| dart[i] == darts)
                    .map(|i| history[k - 1][i].distance(mesh.positions()[i]) / d)
                    .fold(0.0, f64::max)
            };
            let (g4, g5, g6) = (gap(4, false), gap(5, false), gap(6, false));
            println!(
                "{name:<64} {:>8} {g4:>9.2e} {g5:>9.2e} {g6:>9.2e} {:>6.2} {:>9.2e}",
                format!("{method:?}").to_lowercase(),
                g5 / g6,
                gap(6, true)
            );
            assert!(g6 <= 2e-3, "{name}, {method:?}: level 6 is still {g6:e}·d away");
            assert!(g6 <= g4 / 8.0 || g6 <= 1e-12, "{name}, {method:?}: no convergence ({g4:e} → {g6:e})");
            for i in (0..n).filter(|&i| dart[i]) {
                let gap_at = |k: usize| history[k - 1][i].distance(mesh.positions()[i]) / d;
                // The dart's asymmetry gives the centre a component of the subdominant eigenvalue ½.
                assert!(
                    gap_at(6) <= gap_at(5) / 1.8,
                    "{name}: dart {i} does not converge ({:e}, {:e})",
                    gap_at(5),
                    gap_at(6)
                );
                assert!(gap_at(6) <= 2e-4, "{name}: dart {i} is still {:e}·d away", gap_at(6));
            }
        }
    }
}

/// `--boundary edge-only`: one-face boundary corners are no longer kept, the
/// boundary is one B-spline loop; the control mesh interpolates under the
/// option it was made for and not under the other. Also untagged: the
/// option alone takes the tagged path (the plain masks no longer fit).
#[test]
fn the_boundary_option_is_honoured() {
    for mesh in [grid_case(INF), grid_case(1.5), bumpy_grid()] {
        let mut opts = options(CreaseMethod::Uniform);
        opts.common.surface.boundary = BoundaryInterpolation::EdgeOnly;
        let r = deng_wang::interpolate(&mesh, &opts).unwrap();
        assert!(max_rel(&r, &mesh) <= 1e-10);
        let mut other = r.clone();
        other.surface_options.boundary = BoundaryInterpolation::EdgeAndCorner;
        assert!(max_rel(&other, &mesh) > 1e-4, "edge-and-corner would keep the corners elsewhere");
    }
}

/// A vertex outside the subset gets the tagged Loop vertex point of M⁰,
/// re-computed here from the rules: a corner stays, a crease vertex is
/// (p₋ + 6p + p₊)/8 along its crease; the subset is still interpolated.
#[test]
fn vertices_outside_the_subset_follow_the_tagged_loop_rule() {
    let cube = jittered(&shapes::cube(), 0.1);
    let mesh = tagged(&cube, &with_sharpness(&CUBE_TOP, INF), &[(1, INF)]);
    let mut opts = options(CreaseMethod::Uniform);
    opts.common.subset = Some(vec![0, 2, 3, 5, 6, 7]);
    let r = deng_wang::interpolate(&mesh, &opts).unwrap();
    assert!(max_rel(&r, &mesh) <= 1e-10);
    let p = mesh.positions();
    assert_eq!(r.control.positions()[1], p[1], "corner 1 keeps its place");
    let crease = (p[5] + 6.0 * p[4] + p[6]) / 8.0;
    assert!(r.control.positions()[4].distance(crease) <= 1e-15, "crease vertex 4");
}

// ---- untagged input: the bits of before -------------------------------------

/// FNV-1a of the bits of every coordinate.
fn fnv(points: &[DVec3]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for p in points {
        for x in p.to_array() {
            for b in x.to_bits().to_le_bytes() {
                h = (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
            }
        }
    }
    h
}

/// Untagged meshes with the options they are run with, and the FNV-1a hash
/// of their control points as the code before tags existed computed them
/// (commit 2e196a3, this file's `untagged_cases` with a printing test), with
/// Warren's β, the default then.
fn untagged_cases() -> Vec<(&'static str, Mesh, DengWangOptions, u64)> {
    let d = || DengWangOptions::default().with_beta(LoopBeta::Warren);
    let torus = jittered(&shapes::torus(12, 8), 0.05);
    let mut torus_opts = d().with_mu(0.25).with_beta(LoopBeta::Loop);
    torus_opts.common.subset = Some((0..torus.topology().vertex_count() as u32).step_by(2).collect());
    let tri_grid = jittered(&shapes::triangle_grid(5, 4), 0.05);
    let mut grid_opts = d();
    grid_opts.common.subset = Some((0..tri_grid.topology().vertex_count() as u32).step_by(3).collect());
    vec![
        ("icosahedron", shapes::icosahedron(), d(), 0xaf63_b1ec_06d6_b298),
        ("jittered cube", jittered(&shapes::cube(), 0.1), d(), 0x14e4_3847_dbd4_054b),
        ("bumpy open grid", bumpy_grid(), d(), 0x6457_50d7_22d2_cf20),
        ("jittered torus, subset, Loop beta, mu 1/4", torus, torus_opts, 0x07bf_b8e8_ff59_bb38),
        ("jittered triangle grid, subset", tri_grid, grid_opts, 0xe8b0_e67f_270d_998a),
    ]
}

#[test]
fn untagged_input_gives_the_bits_of_before() {
    for (name, mesh, opts, hash) in untagged_cases() {
        let r = deng_wang::interpolate(&mesh, &opts).unwrap();
        assert_eq!(fnv(r.control.positions()), hash, "{name}: the control points changed");
        assert!(r.control.tags().is_empty(), "{name}");
        assert_eq!(r.parameters.control_creases, Some(0));
    }
}

/// Tags change nothing away from them, bit for bit: an edge point whose two
/// ends no tag touches, and the vertex point of a vertex that no tag touches
/// and none of whose neighbours does, are the untagged run's — the tagged
/// path uses the plain formulas there (also outside a subset).
#[test]
fn tags_change_no_bit_away_from_them() {
    let mut subset = options(CreaseMethod::Uniform);
    for (name, mesh, _) in cases() {
        let tri = triangulate(&mesh).unwrap().mesh;
        let t = tri.topology();
        let mut touched = vec![false; t.vertex_count()];
        for e in t.edges().filter(|&e| tri.tags().edge_sharpness(e) > 0.0) {
            let (a, b) = t.edge_vertices(e);
            touched[a.index()] = true;
            touched[b.index()] = true;
        }
        t.vertices().filter(|&v| tri.tags().vertex_sharpness(v) > 0.0).for_each(|v| touched[v.index()] = true);
        let untagged = mesh.clone().with_tags(Tags::none());
        subset.common.subset = Some((0..t.vertex_count() as u32).filter(|v| v % 3 != 1).collect());
        for opts in [options(CreaseMethod::Uniform), subset.clone()] {
            let (a, b) =
                (deng_wang::interpolate(&mesh, &opts).unwrap(), deng_wang::interpolate(&untagged, &opts).unwrap());
            let (pa, pb) = (a.control.positions(), b.control.positions());
            let mut compared = 0;
            for v in t.vertices() {
                if !touched[v.index()] && t.vertex_neighbors(v).all(|u| !touched[u.index()]) {
                    assert_eq!(pa[v.index()].to_array().map(f64::to_bits), pb[v.index()].to_array().map(f64::to_bits));
                    compared += 1;
                }
            }
            for e in t.edges() {
                let (i, j) = t.edge_vertices(e);
                if !touched[i.index()] && !touched[j.index()] {
                    let k = t.vertex_count() + e.index();
                    assert_eq!(pa[k].to_array().map(f64::to_bits), pb[k].to_array().map(f64::to_bits), "{name}");
                    compared += 1;
                }
            }
            let everything_touched = name.starts_with("cube, all") || name.starts_with("octahedron");
            assert!(compared > 0 || everything_touched, "{name}: nothing was away from the tags");
        }
    }
}

// ---- crease edge points -------------------------------------------------------

/// A crease ring sampled from a circle (the ring i = 0 of a torus: radius ¾
/// about (2, 0, 0) in the plane y = 0) gets a limit curve on the circle to
/// O(h⁴) at the default μ — the curve analogue of Eq. 9 with the ⁸⁄₉ factor,
/// as on the boundary — and to O(h²) only at μ = ¼: measured on the
/// level-3 surface's vertices on the crease (the limit positions), for 16, 32
/// and 64 ring vertices. The crease curve depends on the ring's points only,
/// so a torus of 3 segments around its axis is enough.
#[test]
fn crease_limit_curve_follows_a_circle() {
    let mut previous: Option<(f64, f64)> = None;
    println!("| ring vertices | max deviation from the circle, μ = ⅜ | μ = ¼ |");
    println!("|---|---|---|");
    for n in [16u32, 32, 64] {
        let ring: Vec<(u32, u32, f32)> = (0..n).map(|j| (j, (j + 1) % n, INF)).collect();
        let torus = tagged(&shapes::torus(3, n as usize), &ring, &[]);
        let deviation = |mu: f64| {
            let r = deng_wang::interpolate(&torus, &DengWangOptions::default().with_mu(mu)).unwrap();
            let surface = r.surface(3).unwrap();
            let t = surface.topology();
            let on_crease = t.edges().filter(|&e| surface.tags().edge_sharpness(e) > 0.0);
            let ends: Vec<VertexId> = on_crease.flat_map(|e| [t.edge_vertices(e).0, t.edge_vertices(e).1]).collect();
            assert_eq!(ends.len(), 2 * 2 * 8 * n as usize, "the ring's crease edges at level 1 + 3");
            ends.iter()
                .map(|&v| {
                    let p = surface.position(v);
                    (DVec2::new(p.x - 2.0, p.z).length() - 0.75).abs().max(p.y.abs())
                })
                .fold(0.0, f64::max)
        };
        let (best, quarter) = (deviation(deng_wang::DEFAULT_MU), deviation(0.25));
        println!("| {n} | {best:.2e} | {quarter:.2e} |");
        assert!(best <= 0.1 * quarter, "n = {n}: {best:.2e} vs {quarter:.2e}");
        if let Some((b, q)) = previous {
            assert!(b / best >= 12.0, "μ = ⅜: {b:.2e} → {best:.2e} is not O(h⁴)");
            assert!((3.0..5.0).contains(&(q / quarter)), "μ = ¼: {q:.2e} → {quarter:.2e} is not O(h²)");
        }
        previous = Some((best, quarter));
    }
}

/// Normals steer only the smooth edges: crease edge points are the same with
/// any normal at their ends; at a crease vertex the user's normal changes
/// its smooth edges' points and the result still interpolates.
#[test]
fn crease_edges_do_not_read_normals() {
    let mesh = torus_case(INF);
    let n = mesh.topology().vertex_count();
    let mut normals = vec![None; n];
    normals[3] = Some(DVec3::new(0.3, -1.0, 0.2)); // vertex 3 lies on the ring
    let opts = options(CreaseMethod::Uniform).with_normals(normals);
    let (a, b) = (
        deng_wang::interpolate(&mesh, &opts).unwrap(),
        deng_wang::interpolate(&mesh, &options(CreaseMethod::Uniform)).unwrap(),
    );
    assert!(max_rel(&a, &mesh) <= 1e-10);
    let tri = triangulate(&mesh).unwrap().mesh;
    let t = tri.topology();
    let (mut same, mut moved) = (0, 0);
    for e in t.edges() {
        let (i, j) = t.edge_vertices(e);
        if i.0 != 3 && j.0 != 3 {
            continue;
        }
        let k = t.vertex_count() + e.index();
        let sharp = tri.tags().edge_sharpness(e) > 0.0;
        if sharp {
            assert_eq!(a.control.positions()[k], b.control.positions()[k], "crease edge ({i}, {j})");
            same += 1;
        } else if a.control.positions()[k] != b.control.positions()[k] {
            moved += 1;
        }
    }
    assert_eq!(same, 2, "vertex 3 has two crease edges");
    assert!(moved > 0, "the normal steers the smooth edges at vertex 3");
}

// ---- UVs ------------------------------------------------------------------------

/// The edges of `t` whose two faces use different UV values at either end
/// (by value, to 1e-12), as sorted vertex pairs.
fn seam_edges(t: &Topology, uvs: &FaceVarying) -> Vec<(u32, u32)> {
    let uv = |h: subdiv_mesh::HalfEdgeId| uvs.values[uvs.indices[h.index()] as usize];
    let mut out: Vec<(u32, u32)> = t
        .edges()
        .filter(|&e| {
            let h = t.edge_half_edge(e);
            t.he_twin(h)
                .is_some_and(|g| uv(h).distance(uv(t.he_next(g))) > 1e-12 || uv(t.he_next(h)).distance(uv(g)) > 1e-12)
        })
        .map(|e| {
            let (a, b) = t.edge_vertices(e);
            (a.0.min(b.0), a.0.max(b.0))
        })
        .collect();
    out.sort_unstable();
    out
}

/// The seam edges of the triangle split of `parent` that its seams give:
/// both halves of every seam edge (old vertex, edge point), none inside a face.
fn split_seams(parent: &Topology, seams: &[(u32, u32)]) -> Vec<(u32, u32)> {
    let nv = parent.vertex_count() as u32;
    let mut out: Vec<(u32, u32)> = seams
        .iter()
        .flat_map(|&(a, b)| {
            let e = parent.find_edge(VertexId(a), VertexId(b)).expect("a seam is an edge");
            let mid = nv + e.0;
            [(a, mid), (b, mid)]
        })
        .collect();
    out.sort_unstable();
    out
}

/// The uv grid (no seams, non-affine UVs, one value per vertex): the control
/// mesh carries V + E values (value = vertex), under `linear-all` the input's
/// at old vertices and edge midpoints' at edge points; with a crease row too.
#[test]
fn control_mesh_and_surface_carry_the_uvs_of_a_seamless_grid() {
    let grid = fixture("peer/creases/uv_grid/uv_grid.obj");
    let row: Vec<(u32, u32, f32)> = (0..8).map(|i| (9 * 4 + i, 9 * 4 + i + 1, 2.0)).collect();
    for mesh in [grid.clone(), tagged(&grid, &row, &[])] {
        let r = deng_wang::interpolate(&mesh, &options(CreaseMethod::Uniform)).unwrap();
        assert!(max_rel(&r, &mesh) <= 1e-10);
        let tri = triangulate(&mesh).unwrap().mesh;
        let (t0, t1) = (tri.topology(), r.control.topology());
        let uv0 = tri.uvs().expect("the fixture has UVs");
        let uv1 = r.control.uvs().expect("the control mesh carries UVs");
        assert_eq!(uv1.values.len(), t0.vertex_count() + t0.edge_count());
        assert_eq!(uv1.indices.len(), t1.half_edge_count());
        // Without seams the value of a corner is its vertex's (every level).
        let value_of = |t: &Topology, c: &FaceVarying, v: usize| {
            let h = t.vertex_fan(VertexId(v as u32))[0];
            c.values[c.indices[h.index()] as usize]
        };
        for v in 0..t0.vertex_count() {
            assert_eq!(value_of(t1, uv1, v), value_of(t0, uv0, v), "linear-all keeps vertex {v}'s value");
        }
        for e in t0.edges() {
            let (a, b) = t0.edge_vertices(e);
            let mid = (value_of(t0, uv0, a.index()) + value_of(t0, uv0, b.index())) / 2.0;
            let got = value_of(t1, uv1, t0.vertex_count() + e.index());
            assert!(got.distance(mid) <= 1e-15, "edge ({a}, {b}): {got} vs {mid}");
        }
        let surface = r.surface(2).unwrap();
        let uv2 = surface.uvs().expect("the surface carries UVs");
        assert_eq!(uv2.indices.len(), surface.topology().half_edge_count());
        assert!(seam_edges(surface.topology(), uv2).is_empty());
    }
}

/// Spot (polygons with seams): the control mesh and the surface have UVs
/// whose seams are exactly the halves, level by level, of the input's seams
/// (the triangulation adds none: its diagonals lie inside faces) — so their
/// number doubles per level — in every face-varying mode; the value count of
/// the control channel is one per (vertex, span) plus one per edge side.
#[test]
fn uv_seams_follow_the_input_seams_exactly() {
    let spot = fixture("peer/creases/spot_uv/spot_uv.obj");
    let input_seams = seam_edges(spot.topology(), spot.uvs().expect("spot has UVs"));
    assert!(!input_seams.is_empty(), "spot has seams");
    for fvar in [FVarInterpolation::LinearAll, FVarInterpolation::LinearNone, FVarInterpolation::LinearCornersOnly] {
        let mut opts = DengWangOptions::default();
        opts.common.surface.fvar = fvar;
        let r = deng_wang::interpolate(&spot, &opts).unwrap();
        let tri = triangulate(&spot).unwrap().mesh;
        let t0 = tri.topology();
        let uv0 = tri.uvs().unwrap();
        let seams0 = seam_edges(t0, uv0);
        assert_eq!(seams0, input_seams, "the triangulation adds no seam");
        // Values: one per distinct value around each old vertex, one per non-seam edge, two per seam edge.
        let per_vertex: usize = t0
            .vertices()
            .map(|v| {
                let mut ids: Vec<u32> = t0.vertex_fan(v).iter().map(|&h| uv0.indices[h.index()]).collect();
                ids.sort_unstable();
                ids.dedup();
                ids.len()
            })
            .sum();
        let uv1 = r.control.uvs().expect("the control mesh carries UVs");
        assert_eq!(uv1.values.len(), per_vertex + t0.edge_count() + seams0.len(), "{fvar:?}");
        let seams1 = seam_edges(r.control.topology(), uv1);
        assert_eq!(seams1, split_seams(t0, &seams0), "{fvar:?}: control seams");
        let surface = r.surface(2).unwrap();
        let mut t = r.control.topology().clone();
        let mut seams = seams1;
        for _ in 0..2 {
            let child = triangle_split(&t).unwrap();
            seams = split_seams(&t, &seams);
            t = child;
        }
        assert_eq!(t.faces(), surface.topology().faces());
        let surface_seams = seam_edges(surface.topology(), surface.uvs().expect("the surface carries UVs"));
        assert_eq!(surface_seams, seams, "{fvar:?}: surface seams");
        assert_eq!(surface_seams.len(), 8 * input_seams.len());
    }
}

/// Determinism: the same bits (control points, tags, UVs) whatever the thread count.
#[test]
fn tagged_results_do_not_depend_on_the_thread_count() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut out = Vec::new();
            for (_, mesh, semi) in cases() {
                for &method in methods(semi) {
                    let r = deng_wang::interpolate(&mesh, &options(method)).unwrap();
                    out.push((fnv(r.control.positions()), r.control.tags().clone()));
                }
            }
            let spot = fixture("peer/creases/spot_uv/spot_uv.obj");
            let r = deng_wang::interpolate(&spot, &DengWangOptions::default()).unwrap();
            out.push((fnv(r.control.positions()), r.control.tags().clone()));
            (out, r.control.uvs().cloned())
        })
    };
    assert_eq!(run(1), run(4));
}

/// A roof — a grid folded along a crease — is two planes, and Deng-Wang's
/// surface keeps it two planes: the smooth edges next to the crease take
/// the normal of their own side (a crease vertex's sector normal), so their
/// Eq. 9 offsets vanish like every other in-plane edge's. With one normal
/// for the whole vertex (both sides averaged), they bulge off the planes.
#[test]
fn a_creased_roof_stays_two_planes() {
    let (nx, ny) = (6u32, 4u32);
    let grid = shapes::quad_grid(nx as usize, ny as usize);
    let ridge = grid.positions()[3].x; // column i = 3
    let height = |x: f64| 0.8 * (ridge - (x - ridge).abs());
    let roof = grid.with_positions(grid.positions().iter().map(|p| DVec3::new(p.x, p.y, height(p.x))).collect());
    let fold: Vec<(u32, u32, f32)> =
        (0..ny).map(|j| (j * (nx + 1) + 3, (j + 1) * (nx + 1) + 3, SHARPNESS_INFINITE)).collect();
    let mesh = tagged(&roof, &fold, &[]);
    let r = deng_wang::interpolate(&mesh, &DengWangOptions::default()).unwrap();
    assert!(max_rel(&r, &mesh) <= 1e-14);
    let off_plane = |s: &Mesh| s.positions().iter().map(|p| (p.z - height(p.x)).abs()).fold(0.0, f64::max);
    let surface = r.surface(3).unwrap();
    assert!(off_plane(&surface) <= 1e-12, "tagged: {:e} off the roof", off_plane(&surface));
    // Untagged, the ridge rounds off: the same measure is far from 0.
    let plain = deng_wang::interpolate(&roof, &DengWangOptions::default()).unwrap().surface(3).unwrap();
    assert!(off_plane(&plain) > 1e-3, "untagged: {:e}", off_plane(&plain));
}
