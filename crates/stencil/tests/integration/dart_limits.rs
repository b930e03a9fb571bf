//! Darts get their exact limit: brute force against the limit stencils of
//! Catmull-Clark and Loop at darts (a vertex with one infinitely sharp edge),
//! and OpenSubdiv's smooth mask ([`DartLimit::SmoothMask`]) measurably off.
//!
//! Two refinements of each tagged mesh, with `subdivide` alone (no limit
//! masks), follow the dart, which keeps its number at every primal level:
//!
//! - **the whole mesh, 8 levels**: the distance to the limit row falls by
//!   about ½ per level — the dart's asymmetry leaves the subdominant
//!   eigenvalue ½ in its own position (a smooth or crease vertex falls by
//!   ¼) — so level 8 is still ~10⁻⁴·d away, and the limit row taken at
//!   level 8 is the same point as at level 0;
//! - **the dart's faces alone, 40 levels**: the new points of the dart's
//!   1-ring (the dart, its edge points, its face points) depend on its
//!   faces only, so each level is cropped back to the faces around the dart
//!   and refined again: the same positions as the whole mesh (checked at
//!   level 8), as deep as wanted. At level 40 the dart is within 10⁻⁶·d of
//!   its limit row (in fact at round-off), and the smooth mask is > 10⁻⁵·d
//!   away.
//!
//! Printed with --nocapture: the distances per level and the gaps.

use crate::sharp_cases::{jittered, tags};
use glam::DVec3;
use subdiv_mesh::{shapes, EdgeTag, FaceList, Mesh, TagList, Tags, VertexId, VertexTag};
use subdiv_stencil::{catmull_clark, subdivide, DartLimit, LevelSharpness, LoopBeta, Options, Scheme};

const GLOBAL_LEVELS: usize = 8;
const LOCAL_LEVELS: usize = 40;

/// A tagged mesh and the darts to follow.
struct DartCase {
    name: &'static str,
    mesh: Mesh,
    options: Options,
    darts: Vec<u32>,
}

fn case(
    name: &'static str,
    mesh: Mesh,
    creases: &[(u32, u32, f32)],
    corners: &[(u32, f32)],
    scheme: Scheme,
) -> DartCase {
    let tags = tags(&mesh, creases, corners);
    let mesh = mesh.with_tags(tags);
    let options = Options::new(scheme);
    let sharp = LevelSharpness::from_options(mesh.tags(), &options);
    let t = mesh.topology();
    let darts = (0..t.vertex_count() as u32).filter(|&v| sharp.exact_dart_edge(t, VertexId(v)).is_some()).collect();
    DartCase { name, mesh, options, darts }
}

fn cases() -> Vec<DartCase> {
    const CC: Scheme = Scheme::CatmullClark;
    // shapes::torus(4, 3): vertex (i, j) = 3i + j; the crease (0,0)-(1,0)-(2,0) from a corner tag to a dart.
    let torus = jittered(&shapes::torus(4, 3), 21);
    // shapes::triangle_grid(3, 3): vertex (i, j) = 4j + i; (0, 1) = 4 on the boundary, (1, 1) = 5 inside (valence 6).
    let tri = jittered(&shapes::triangle_grid(3, 3), 22);
    vec![
        case("cube, edge 0-2 s=10 (CC, valence 3)", jittered(&shapes::cube(), 7), &[(0, 2, 10.0)], &[], CC),
        case(
            "torus 4×3, crease from a corner to a dart (CC, valence 4)",
            torus,
            &[(0, 3, 10.0), (3, 6, 10.0)],
            &[(0, 10.0)],
            CC,
        ),
        // Apex 5 (five triangles) and base vertex 0 (a pentagon and two triangles).
        case(
            "pyramid 5, apex edge s=10 (CC, non-quad fans)",
            jittered(&shapes::pyramid(5), 23),
            &[(5, 0, 10.0)],
            &[],
            CC,
        ),
        case(
            "pyramid 12, apex edge s=10 (CC, valence 12)",
            jittered(&shapes::pyramid(12), 24),
            &[(12, 0, 10.0)],
            &[],
            CC,
        ),
        case(
            "octahedron, edge 4-0 s=10 (Loop, Warren's β, valence 4)",
            jittered(&shapes::octahedron(), 25),
            &[(4, 0, 10.0)],
            &[],
            Scheme::Loop(LoopBeta::Warren),
        ),
        case(
            "icosahedron, edge 0-11 s=10 (Loop, Loop's β, valence 5)",
            jittered(&shapes::icosahedron(), 26),
            &[(0, 11, 10.0)],
            &[],
            Scheme::Loop(LoopBeta::Loop),
        ),
        case(
            "triangle grid 3×3, crease from the boundary to a dart (Loop, valence 6)",
            tri,
            &[(4, 5, 10.0)],
            &[],
            Scheme::Loop(LoopBeta::Warren),
        ),
    ]
}

/// The faces around `v` as a mesh of their own, `v` first (vertex 0), with
/// the tags of their edges and vertices: one step of it gives the same
/// 1-ring of `v` (the new points of `v`, of its edges and of its faces) as
/// one step of the whole mesh.
fn faces_around(mesh: &Mesh, v: u32) -> Mesh {
    let t = mesh.topology();
    let mut local: Vec<u32> = vec![v];
    let mut index = |p: u32| match local.iter().position(|&q| q == p) {
        Some(i) => i as u32,
        None => {
            local.push(p);
            (local.len() - 1) as u32
        }
    };
    let mut faces = FaceList::new();
    for &h in t.vertex_fan(VertexId(v)) {
        let face: Vec<u32> = t.face(t.he_face(h)).iter().map(|&p| index(p)).collect();
        faces.push(&face);
    }
    let positions = local.iter().map(|&p| mesh.positions()[p as usize]).collect();
    let out = Mesh::new(positions, faces).expect("the faces of a manifold vertex");
    let (ot, tags) = (out.topology(), mesh.tags());
    let mut list = TagList::default();
    for e in ot.edges() {
        let (a, b) = ot.edge_vertices(e);
        let parent = t.find_edge(VertexId(local[a.index()]), VertexId(local[b.index()])).expect("a parent edge");
        let sharpness = tags.edge_sharpness(parent);
        if sharpness > 0.0 {
            list.creases.push(EdgeTag { a: a.0, b: b.0, sharpness });
        }
    }
    for (i, &p) in local.iter().enumerate() {
        let sharpness = tags.vertex_sharpness(VertexId(p));
        if sharpness > 0.0 {
            list.corners.push(VertexTag { vertex: i as u32, sharpness });
        }
    }
    let tags = Tags::from_list(ot, &list).expect("tags of the parent's edges");
    out.with_tags(tags)
}

/// The dart's position after each level 0..=`levels`, refining its faces
/// alone (cropped back to them after every level).
fn local_levels(mesh: &Mesh, options: Options, dart: u32, levels: usize) -> Vec<DVec3> {
    let mut ring = faces_around(mesh, dart);
    let mut out = vec![ring.positions()[0]];
    for _ in 0..levels {
        let refined = subdivide(&ring, options, 1, false).unwrap();
        out.push(refined.positions()[0]); // old vertices keep their numbers
        ring = faces_around(&refined, 0);
    }
    out
}

/// The limit point of every vertex with `dart_limit`.
fn limits(mesh: &Mesh, options: Options, dart_limit: DartLimit) -> Vec<DVec3> {
    subdivide(mesh, options.with_dart_limit(dart_limit), 0, true).unwrap().positions().to_vec()
}

#[test]
fn darts_converge_to_the_exact_limit_rows_and_not_to_the_smooth_mask() {
    for c in cases() {
        assert!(!c.darts.is_empty(), "{}: no dart", c.name);
        let d = c.mesh.bbox_diagonal();
        let (exact, smooth) =
            (limits(&c.mesh, c.options, DartLimit::Exact), limits(&c.mesh, c.options, DartLimit::SmoothMask));
        // The whole mesh, level by level.
        let mut global = vec![c.mesh.clone()];
        for _ in 0..GLOBAL_LEVELS {
            let next = subdivide(global.last().unwrap(), c.options, 1, false).unwrap();
            global.push(next);
        }
        let fine = global.last().unwrap();
        let fine_exact = limits(fine, c.options, DartLimit::Exact);
        for &v in &c.darts {
            let i = v as usize;
            let gaps: Vec<f64> = global.iter().map(|m| m.positions()[i].distance(exact[i]) / d).collect();
            let local = local_levels(&c.mesh, c.options, v, LOCAL_LEVELS);
            let deep = local[LOCAL_LEVELS].distance(exact[i]) / d;
            let old = local[LOCAL_LEVELS].distance(smooth[i]) / d;
            let show: Vec<String> = gaps[4..].iter().map(|g| format!("{g:.2e}")).collect();
            eprintln!(
                "{}: dart {v}: levels 4..8 {}; level {LOCAL_LEVELS} (its faces alone) {deep:.1e}·d from the exact \
                 row, {old:.2e}·d from the smooth mask",
                c.name,
                show.join(" ")
            );
            // The crop refines exactly as the whole mesh does.
            let crop = local[GLOBAL_LEVELS].distance(fine.positions()[i]) / d;
            assert!(crop < 1e-13, "{}: dart {v}: its faces alone differ from the mesh by {crop:e}·d", c.name);
            // The distance falls by about ½ per level.
            for k in 4..GLOBAL_LEVELS {
                assert!(gaps[k + 1] <= 0.7 * gaps[k], "{}: dart {v}: levels 4..8 {}", c.name, show.join(" "));
            }
            assert!(gaps[GLOBAL_LEVELS] < 1e-2 * gaps[0], "{}: dart {v}: {gaps:?}", c.name);
            assert!(deep <= 1e-6, "{}: dart {v}: {deep:e}·d from its limit row after {LOCAL_LEVELS} levels", c.name);
            assert!(old > 1e-5, "{}: dart {v}: the smooth mask is only {old:e}·d off", c.name);
            // The limit row at level 8 is the same point (lᵀS = lᵀ).
            let again = fine_exact[i].distance(exact[i]) / d;
            assert!(again < 1e-12, "{}: dart {v}: the level-8 limit row moved by {again:e}·d", c.name);
        }
    }
}

#[test]
fn a_dart_on_a_non_quad_fan_is_exact_on_the_base_level() {
    // The limit row on the unrefined pyramid composes one step with the dart
    // mask: the same point as the plan's (one level first, then the mask).
    for n in [3, 5, 12] {
        let mesh = jittered(&shapes::pyramid(n), 30 + n as u64);
        let tags = tags(&mesh, &[(n as u32, 0, 10.0)], &[]);
        let options = Options::new(Scheme::CatmullClark);
        let sharp = LevelSharpness::from_options(&tags, &options);
        let t = mesh.topology();
        let base = catmull_clark::limit_points_sharp(t, &sharp, mesh.positions(), t.vertex_count());
        let planned = limits(&mesh.clone().with_tags(tags), options, DartLimit::Exact);
        let d = mesh.bbox_diagonal();
        for v in [0, n] {
            let gap = base[v].distance(planned[v]) / d;
            assert!(gap < 1e-14, "pyramid {n}, dart {v}: base row vs plan {gap:e}·d");
        }
    }
}

#[test]
fn semi_sharp_darts_and_the_smooth_mask_option_keep_opensubdivs_rows() {
    // A dart whose edge is semi-sharp changes its rule on the way: the
    // smooth mask, whatever the option. An infinitely sharp one under
    // `SmoothMask`: OpenSubdiv's row, the smooth mask, bit for bit.
    let cube = jittered(&shapes::cube(), 7);
    for scheme in [Scheme::CatmullClark, Scheme::Loop(LoopBeta::Warren)] {
        let mesh = if scheme == Scheme::CatmullClark { cube.clone() } else { jittered(&shapes::octahedron(), 3) };
        let t = mesh.topology();
        let (a, b) = t.edge_vertices(subdiv_mesh::EdgeId(0));
        let rows = |s: f32, dart_limit| {
            let tags = tags(&mesh, &[(a.0, b.0, s)], &[]);
            let options = Options::new(scheme).with_dart_limit(dart_limit);
            let sharp = LevelSharpness::from_options(&tags, &options);
            scheme.rules().limit_stencil(t, &sharp, t.vertex_count()).unwrap().unwrap()
        };
        let untagged = scheme.rules().limit_stencil(t, &LevelSharpness::plain(), t.vertex_count()).unwrap().unwrap();
        let row = |m: &subdiv_stencil::SparseMatrix, v: VertexId| {
            let r = m.outer_view(v.index()).unwrap();
            r.indices().iter().copied().zip(r.data().iter().map(|w| w.to_bits())).collect::<Vec<_>>()
        };
        for v in [a, b] {
            assert_eq!(row(&rows(2.5, DartLimit::Exact), v), row(&untagged, v), "{scheme}: semi-sharp dart {v:?}");
            let smooth = rows(10.0, DartLimit::SmoothMask);
            let exact = rows(10.0, DartLimit::Exact);
            if scheme == Scheme::CatmullClark {
                // Valence 3 quads: the smooth quad mask, as before.
                let mask = subdiv_rules::catmull_clark::limit_mask(subdiv_rules::VertexKind::Interior, 3);
                let weights: Vec<f64> = smooth.outer_view(v.index()).unwrap().data().to_vec();
                assert!(weights.contains(&mask.vertex) && weights.contains(&mask.face), "{scheme}: {weights:?}");
            } else {
                assert_eq!(row(&smooth, v), row(&untagged, v), "{scheme}: smooth mask at dart {v:?}");
            }
            assert_ne!(row(&exact, v), row(&smooth, v), "{scheme}: dart {v:?}");
        }
    }
}
