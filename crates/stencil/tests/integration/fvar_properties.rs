//! Properties of face-varying refinement (`subdiv_stencil::fvar`), in
//! particular for the modes without OpenSubdiv reference files
//! (`linear-corners-plus1`, `linear-corners-plus2`, `linear-boundaries`):
//!
//! - a channel without seams under `linear-none` is refined exactly as the
//!   positions would be (UVs as positions, any boundary option, any tags:
//!   semi-sharp creases, infinitely sharp creases, corners, Chaikin) — the
//!   channel inherits the vertex tags; under `linear-corners-only` it is the
//!   surface with `edge-and-corner` corners whatever the boundary option;
//! - `plus1` and `plus2` equal `corners-only` where no seams meet and no seam
//!   ends inside (a straight seam), `plus1` also at a bend of a seam, where
//!   `plus2` keeps the other value too; at a junction of three charts both
//!   keep every value, `corners-only` does not; at the tip of a slit (a dart)
//!   `plus2` and `linear-boundaries` keep the value;
//! - `linear-boundaries` keeps boundaries and seams piecewise linear (the
//!   values of `linear-all` there) and is smooth inside (`linear-none`'s
//!   values one level down); `linear-all` is bilinear;
//! - semi-sharp edges inside a value's span: kept while sharp, then the
//!   fractional blend s·v + (1 − s)·crease, by the partner's span for a
//!   dependent value (`plus1`);
//! - every mode keeps the seams (the children of seam edges and no other
//!   edge are seams), weights sum to one (a constant channel stays constant),
//!   the value counts are one per vertex value, face and edge side;
//! - Doo-Sabin refines a seamless channel like positions and refuses seams;
//!   errors are typed; results do not depend on the thread count; a vertex of
//!   2·10⁵ faces with a value per face is refined in linear time.

use glam::{DVec2, DVec3};
use std::collections::BTreeMap;
use subdiv_mesh::{
    shapes, EdgeTag, FaceId, FaceVarying, HalfEdgeId, Mesh, MeshError, TagList, Tags, Topology, VertexTag,
};
use subdiv_rules::FVarInterpolation::{self, *};
use subdiv_stencil::fvar::{self, FVarError};
use subdiv_stencil::{
    subdivide, BoundaryInterpolation, CreaseMethod, LevelSharpness, LoopBeta, Options, Scheme, StencilError,
    SubdivisionPlan, Tension,
};

/// A smooth, non-affine UV map of a position.
fn uv_of(p: DVec3) -> DVec2 {
    DVec2::new(p.x + 0.15 * (0.7 * p.y).sin() * p.y, p.y + 0.1 * p.x * p.x - 0.05 * p.z)
}

/// A channel with charts: face f belongs to chart `chart(f)`; corners of the
/// same vertex and chart share a value, charts are placed apart in UV space.
fn charted(mesh: &Mesh, chart: impl Fn(FaceId) -> u32) -> FaceVarying {
    let t = mesh.topology();
    let mut index = BTreeMap::new();
    let mut values = Vec::new();
    let mut indices = Vec::with_capacity(t.half_edge_count());
    for f in t.face_ids() {
        let c = chart(f);
        for &v in t.face(f) {
            let k = *index.entry((v, c)).or_insert_with(|| {
                values.push(uv_of(mesh.positions()[v as usize]) + DVec2::new(10.0 * c as f64, 0.0));
                values.len() as u32 - 1
            });
            indices.push(k);
        }
    }
    FaceVarying { values, indices }
}

fn seamless(mesh: &Mesh) -> FaceVarying {
    charted(mesh, |_| 0)
}

/// `levels` steps of `options` on `mesh` with its tags: the final topology and channel.
fn refine(mesh: &Mesh, options: Options, levels: usize, channel: &FaceVarying) -> (Topology, FaceVarying) {
    let plan = SubdivisionPlan::with_tags(mesh.topology(), mesh.tags(), options, levels).unwrap();
    let base = LevelSharpness::new(mesh.tags(), options.boundary, options.crease_method);
    let steps = plan.levels().iter().map(|r| (&r.topology, &r.sharpness));
    let refined = fvar::refine_levels(mesh.topology(), &base, steps, options.scheme, options.fvar, channel).unwrap();
    (plan.topology().clone(), refined)
}

fn corner_value(channel: &FaceVarying, h: usize) -> DVec2 {
    channel.values[channel.indices[h] as usize]
}

/// Largest difference between two channels on the same topology, per face corner.
fn corner_gap(a: &FaceVarying, b: &FaceVarying) -> f64 {
    assert_eq!(a.indices.len(), b.indices.len());
    (0..a.indices.len()).map(|h| corner_value(a, h).distance(corner_value(b, h))).fold(0.0, f64::max)
}

/// The face corners whose values differ between two channels.
fn differing_corners(a: &FaceVarying, b: &FaceVarying) -> Vec<usize> {
    (0..a.indices.len()).filter(|&h| corner_value(a, h) != corner_value(b, h)).collect()
}

/// A 6 × 6 quad grid (vertex (i, j) = 7j + i) with creases and corners of
/// every kind: a row of semi-sharp edges, an infinitely sharp crease ending
/// inside (darts), a semi-sharp and an infinitely sharp corner.
fn tagged(mesh: Mesh) -> Mesh {
    let id = |i: u32, j: u32| 7 * j + i;
    let mut list = TagList::default();
    for i in 0..6 {
        let sharpness = [0.5, 1.5, 2.5, 2.5, 1.0, 3.0][i as usize];
        list.creases.push(EdgeTag { a: id(i, 3), b: id(i + 1, 3), sharpness });
    }
    for j in 1..4 {
        list.creases.push(EdgeTag { a: id(4, j), b: id(4, j + 1), sharpness: 10.0 });
    }
    list.corners.push(VertexTag { vertex: id(2, 1), sharpness: 1.5 });
    list.corners.push(VertexTag { vertex: id(1, 5), sharpness: 10.0 });
    let tags = Tags::from_list(mesh.topology(), &list).unwrap();
    mesh.with_tags(tags)
}

/// The test surfaces: Catmull-Clark and Loop grids with tags, a closed mesh.
fn surfaces() -> Vec<(&'static str, Mesh, Scheme)> {
    let loop_beta = Scheme::Loop(LoopBeta::Loop);
    vec![
        ("quad grid", tagged(shapes::quad_grid(6, 6)), Scheme::CatmullClark),
        ("triangle grid", tagged(shapes::triangle_grid(6, 6)), loop_beta),
        ("mixed polygons", shapes::polygon_mix(&shapes::quad_grid(5, 4), 3, 0.3, 0.3, 0.1), Scheme::CatmullClark),
        ("icosahedron", shapes::icosahedron(), Scheme::Loop(LoopBeta::Warren)),
    ]
}

#[test]
fn seamless_channel_under_linear_none_is_refined_as_positions() {
    for (name, mesh, scheme) in surfaces() {
        // The same surface whose positions are the UVs.
        let channel = seamless(&mesh);
        let uv_positions =
            (mesh.topology().vertices()).map(|v| uv_of(mesh.positions()[v.index()]).extend(0.0)).collect::<Vec<_>>();
        let as_positions = mesh.with_positions(uv_positions);
        for boundary in BoundaryInterpolation::ALL.iter().copied().filter(|&b| b != BoundaryInterpolation::None) {
            for method in [CreaseMethod::Uniform, CreaseMethod::Chaikin] {
                let options =
                    Options::new(scheme).with_boundary(boundary).with_crease_method(method).with_fvar(LinearNone);
                let (t, refined) = refine(&mesh, options, 3, &channel);
                let surface = subdivide(&as_positions, options, 3, false).unwrap();
                let gap = (0..t.half_edge_count())
                    .map(|h| {
                        corner_value(&refined, h)
                            .distance(surface.positions()[t.he_from(HalfEdgeId(h as u32)).index()].truncate())
                    })
                    .fold(0.0, f64::max);
                assert!(gap <= 1e-14, "{name}, {boundary}, {method}: UVs and positions differ by {gap:.2e}");
                // Without seams, the values stay one per vertex.
                assert_eq!(refined.values.len(), t.referenced_vertex_count(), "{name}: values");
            }
        }
    }
}

#[test]
fn seamless_channel_under_corners_only_keeps_the_one_face_corners() {
    for (name, mesh, scheme) in surfaces() {
        let channel = seamless(&mesh);
        let options = |boundary, mode| Options::new(scheme).with_boundary(boundary).with_fvar(mode);
        let corners = options(BoundaryInterpolation::EdgeAndCorner, LinearCornersOnly);
        let (_, reference) = refine(&mesh, options(BoundaryInterpolation::EdgeAndCorner, LinearNone), 2, &channel);
        // Under edge-and-corner the one-face corners are corners of the channel in every mode.
        assert_eq!(refine(&mesh, corners, 2, &channel).1, reference, "{name}");
        // Under edge-only the channel still keeps them: the edge-and-corner surface.
        let edge_only = refine(&mesh, options(BoundaryInterpolation::EdgeOnly, LinearCornersOnly), 2, &channel).1;
        assert!(corner_gap(&edge_only, &reference) <= 1e-14, "{name}: edge-only corners-only");
        let smooth = refine(&mesh, options(BoundaryInterpolation::EdgeOnly, LinearNone), 2, &channel).1;
        assert_eq!(smooth == reference, mesh.topology().is_closed(), "{name}: edge-only linear-none moves the corners");
    }
}

/// A 6 × 6 quad grid (or its triangles) cut into charts by `chart(i, j)` of
/// the cell (i, j).
fn grid_with_charts(triangles: bool, chart: impl Fn(usize, usize) -> u32) -> (Mesh, FaceVarying, Scheme) {
    let (mesh, scheme, per_cell) = if triangles {
        (shapes::triangle_grid(6, 6), Scheme::Loop(LoopBeta::Loop), 2)
    } else {
        (shapes::quad_grid(6, 6), Scheme::CatmullClark, 1)
    };
    let channel = charted(&mesh, |f| {
        let cell = f.index() / per_cell;
        chart(cell % 6, cell / 6)
    });
    (mesh, channel, scheme)
}

fn one_level(mesh: &Mesh, channel: &FaceVarying, scheme: Scheme, mode: FVarInterpolation) -> FaceVarying {
    refine(mesh, Options::new(scheme).with_fvar(mode), 1, channel).1
}

#[test]
fn plus1_and_plus2_equal_corners_only_along_a_straight_seam() {
    for triangles in [false, true] {
        // Two charts split at x = 3, the seam running from boundary to boundary.
        let (mesh, channel, scheme) = grid_with_charts(triangles, |i, _| u32::from(i >= 3));
        for levels in [1, 2] {
            let run = |mode| refine(&mesh, Options::new(scheme).with_fvar(mode), levels, &channel);
            let (t, corners) = run(LinearCornersOnly);
            assert_eq!(run(LinearCornersPlus1).1, corners, "triangles {triangles}, L{levels}: plus1");
            let plus2 = run(LinearCornersPlus2).1;
            if !triangles {
                assert_eq!(plus2, corners, "L{levels}: plus2");
            } else if levels == 1 {
                // The seam's ends (3, 0) and (3, 6) on the boundary have one face on one side
                // (the triangles' diagonals): plus2 keeps the other side's value there, and only there.
                let differ = differing_corners(&corners, &plus2);
                assert!(!differ.is_empty());
                for c in differ {
                    let v = t.he_from(HalfEdgeId(c as u32)).0;
                    assert!(v == 3 || v == 45, "plus2 differs at vertex {v}");
                }
            }
            // A seam is not a boundary of the surface: linear-boundaries keeps it linear, corners-only does not.
            assert_ne!(run(LinearBoundaries).1, corners, "triangles {triangles}, L{levels}: boundaries");
        }
    }
}

/// The value at face corner 4h of the first level (Catmull-Clark): the
/// refined value of parent corner h's vertex on h's side.
fn vertex_child(channel: &FaceVarying, h: usize) -> DVec2 {
    corner_value(channel, 4 * h)
}

/// A parent half-edge leaving `v` in a face of the cell (i, j) of a 6 × 6 quad grid.
fn corner_in_cell(mesh: &Mesh, v: u32, (i, j): (usize, usize)) -> usize {
    let f = FaceId((6 * j + i) as u32);
    mesh.topology().face_half_edges(f).find(|&h| mesh.topology().he_from(h).0 == v).unwrap().index()
}

#[test]
fn plus2_keeps_both_values_at_a_bend_of_a_seam_plus1_only_the_corner() {
    // Chart 1 is the 3 × 3 block of cells i, j ≥ 3: the seam bends at vertex (3, 3) = 24,
    // where chart 1 has one face (a corner of the channel) and chart 0 three.
    let (mesh, channel, scheme) = grid_with_charts(false, |i, j| u32::from(i >= 3 && j >= 3));
    let corners = one_level(&mesh, &channel, scheme, LinearCornersOnly);
    assert_eq!(one_level(&mesh, &channel, scheme, LinearCornersPlus1), corners);
    let plus2 = one_level(&mesh, &channel, scheme, LinearCornersPlus2);
    let bend = 24;
    let (inside, outside) = (corner_in_cell(&mesh, bend, (3, 3)), corner_in_cell(&mesh, bend, (2, 2)));
    let kept = |h: usize| channel.values[channel.indices[h] as usize];
    assert_eq!(vertex_child(&corners, inside), kept(inside), "the one-face value is a corner");
    assert_ne!(vertex_child(&corners, outside), kept(outside), "corners-only smooths the other value");
    assert_eq!(vertex_child(&plus2, outside), kept(outside), "plus2 keeps it");
    // Nothing else differs: every other value of level 1 depends on level 0 alone.
    let differ = differing_corners(&corners, &plus2);
    assert!(!differ.is_empty());
    assert!(differ.iter().all(|&c| corner_value(&plus2, c) == kept(outside)), "only the bend's other value");
}

#[test]
fn plus1_and_plus2_keep_every_value_where_three_charts_meet() {
    // Charts left (i < 3), bottom right and top right: a T junction at vertex (3, 3).
    for triangles in [false, true] {
        let (mesh, channel, scheme) = grid_with_charts(triangles, |i, j| match (i >= 3, j >= 3) {
            (false, _) => 0,
            (true, false) => 1,
            (true, true) => 2,
        });
        let junction = 24u32;
        let t = mesh.topology();
        let corners = one_level(&mesh, &channel, scheme, LinearCornersOnly);
        // (On the triangles, plus2 also sharpens the seams' ends on the boundary, where one side has one face.)
        let modes: &[FVarInterpolation] =
            if triangles { &[LinearCornersPlus1] } else { &[LinearCornersPlus1, LinearCornersPlus2] };
        for &mode in modes {
            let (child, sharp) = refine(&mesh, Options::new(scheme).with_fvar(mode), 1, &channel);
            // The junction's refined values: the corners of its children at the vertex.
            let at_junction: Vec<usize> =
                (0..child.half_edge_count()).filter(|&c| child.he_from(HalfEdgeId(c as u32)).0 == junction).collect();
            assert!(!at_junction.is_empty());
            for &c in &at_junction {
                let v = corner_value(&sharp, c);
                assert!(channel.values.contains(&v), "triangles {triangles}, {mode}: junction value {v} moved");
            }
            let differ = differing_corners(&corners, &sharp);
            assert!(!differ.is_empty(), "corners-only smooths the junction");
            assert!(differ.iter().all(|c| at_junction.contains(c)), "triangles {triangles}, {mode}: only the junction");
        }
        assert_eq!(t.vertex_count(), 49);
    }
}

#[test]
fn a_dart_is_kept_by_plus2_and_linear_boundaries_and_smoothed_by_corners_only() {
    // A slit: the edges from (3, 0) up to (3, 3) are a seam (cells left and right of x = 3, j < 3, in
    // different charts that join above): its tip (3, 3) = 24 has one value, a dart.
    let mesh = shapes::quad_grid(6, 6);
    let channel = {
        let t = mesh.topology();
        // Start from per-vertex values, then give the right side of the slit its own values.
        let mut channel = seamless(&mesh);
        let slit: Vec<u32> = (0..3).map(|j| 7 * j + 3).collect(); // (3, 0), (3, 1), (3, 2)
        for f in t.face_ids() {
            let (i, j) = (f.index() % 6, f.index() / 6);
            if i == 3 && j < 3 {
                for h in t.face_half_edges(f) {
                    let v = t.he_from(h).0;
                    if slit.contains(&v) {
                        let shifted = channel.values[v as usize] + DVec2::new(0.0, 0.5);
                        channel.values.push(shifted);
                        channel.indices[h.index()] = channel.values.len() as u32 - 1;
                    }
                }
            }
        }
        // The cells right of the slit share their new values with each other.
        let mut first = BTreeMap::new();
        for h in 0..channel.indices.len() {
            let v = t.he_from(HalfEdgeId(h as u32)).0;
            if channel.indices[h] as usize >= t.vertex_count() {
                let k = *first.entry(v).or_insert(channel.indices[h]);
                channel.indices[h] = k;
            }
        }
        channel
    };
    let tip = 24u32;
    let t = mesh.topology();
    let h = t.vertex_fan(subdiv_mesh::VertexId(tip))[0].index();
    let own = corner_value(&channel, h);
    for (mode, kept) in [
        (LinearNone, false),
        (LinearCornersOnly, false),
        (LinearCornersPlus1, false),
        (LinearCornersPlus2, true),
        (LinearBoundaries, true),
        (LinearAll, true),
    ] {
        let refined = one_level(&mesh, &channel, Scheme::CatmullClark, mode);
        assert_eq!(vertex_child(&refined, h) == own, kept, "{mode}: dart kept");
    }
    // The crease rule along the slit: ¾v + ⅛ of the two values of (3, 2) across the seam.
    let refined = one_level(&mesh, &channel, Scheme::CatmullClark, LinearCornersOnly);
    let below = 17usize;
    let sides: Vec<DVec2> = (0..t.half_edge_count())
        .filter(|&c| t.he_from(HalfEdgeId(c as u32)).index() == below)
        .map(|c| corner_value(&channel, c))
        .fold(Vec::new(), |mut acc, v| {
            if !acc.contains(&v) {
                acc.push(v);
            }
            acc
        });
    assert_eq!(sides.len(), 2);
    let expected = 0.125 * sides[0] + 0.125 * sides[1] + 0.75 * own;
    assert!(vertex_child(&refined, h).distance(expected) < 1e-13);
}

#[test]
fn linear_boundaries_keeps_boundaries_and_seams_linear_and_is_smooth_inside() {
    for triangles in [false, true] {
        // An L-shaped seam and the grid boundary.
        let (mesh, channel, scheme) = grid_with_charts(triangles, |i, j| u32::from(i >= 3 && j >= 3));
        for levels in [1, 2] {
            let run = |mode| refine(&mesh, Options::new(scheme).with_fvar(mode), levels, &channel);
            let (t, boundaries) = run(LinearBoundaries);
            let (_, all) = run(LinearAll);
            let (_, smooth) = run(LinearNone);
            // Which refined vertices lie on a boundary or a seam.
            let mut on_seam = vec![false; t.vertex_count()];
            for e in t.edges() {
                let h = t.edge_half_edge(e);
                let seam = t.he_twin(h).is_none_or(|g| {
                    let at = |x: HalfEdgeId| boundaries.indices[x.index()];
                    at(h) != at(t.he_next(g)) || at(t.he_next(h)) != at(g)
                });
                if seam {
                    let (a, b) = t.edge_vertices(e);
                    on_seam[a.index()] = true;
                    on_seam[b.index()] = true;
                }
            }
            let mut inside = 0;
            for h in 0..t.half_edge_count() {
                let v = t.he_from(HalfEdgeId(h as u32)).index();
                let (ours, linear) = (corner_value(&boundaries, h), corner_value(&all, h));
                if on_seam[v] {
                    assert!(ours.distance(linear) < 1e-13, "triangles {triangles}, L{levels}: corner {h} not linear");
                } else if levels == 1 {
                    // Inside, level 1 only uses level 0's values: the smooth rules.
                    assert_eq!(ours, corner_value(&smooth, h), "triangles {triangles}: corner {h} not smooth");
                    inside += 1;
                }
            }
            assert!(levels > 1 || inside > 0);
        }
    }
}

#[test]
fn linear_all_is_bilinear() {
    for triangles in [false, true] {
        let (mesh, channel, scheme) = grid_with_charts(triangles, |i, j| u32::from(i >= 3) + 2 * u32::from(j >= 4));
        let refined = one_level(&mesh, &channel, scheme, LinearAll);
        let t = mesh.topology();
        let at = |h: HalfEdgeId| corner_value(&channel, h.index());
        let mid = |h: HalfEdgeId| 0.5 * at(h) + 0.5 * at(t.he_next(h));
        for f in t.face_ids() {
            let hs: Vec<HalfEdgeId> = t.face_half_edges(f).collect();
            for (k, &h) in hs.iter().enumerate() {
                let prev = hs[(k + hs.len() - 1) % hs.len()];
                let child: Vec<DVec2> = if triangles {
                    (0..3).map(|j| corner_value(&refined, 3 * (4 * f.index() + k) + j)).collect()
                } else {
                    (0..4).map(|j| corner_value(&refined, 4 * h.index() + j)).collect()
                };
                assert_eq!(child[0], at(h), "vertex value kept");
                assert_eq!(child[1], mid(h), "edge value: the midpoint of this side");
                if triangles {
                    assert_eq!(child[2], mid(prev));
                } else {
                    let mean = hs.iter().map(|&x| 0.25 * at(x)).fold(DVec2::ZERO, |a, b| a + b);
                    assert!(child[2].distance(mean) < 1e-13, "face value: the mean");
                    assert_eq!(child[3], mid(prev));
                }
            }
        }
    }
}

/// A 4 × 4 quad grid (vertex (i, j) = 5j + i), two charts split at x = 2, and
/// the edge from (1, 2) to (2, 2) — inside the left value's span at the seam
/// vertex (2, 2) = 12 — at `sharpness`.
fn seam_with_crease(sharpness: f32) -> (Mesh, FaceVarying) {
    let mesh = shapes::quad_grid(4, 4);
    let channel = charted(&mesh, |f| u32::from(f.index() % 4 >= 2));
    let list = TagList { creases: vec![EdgeTag { a: 11, b: 12, sharpness }], corners: vec![], ..Default::default() };
    let tags = Tags::from_list(mesh.topology(), &list).unwrap();
    (mesh.with_tags(tags), channel)
}

/// The values of (2, 1) = 7 and (2, 3) = 17, the ends of the seam vertex
/// 12's span, on the side of the chart of corner `h` (cells with i ≥ 2 are chart 1).
fn span_ends(mesh: &Mesh, channel: &FaceVarying, h: usize) -> (DVec2, DVec2) {
    let t = mesh.topology();
    let chart = |c: usize| t.he_face(HalfEdgeId(c as u32)).index() % 4 >= 2;
    let side = |v: u32| {
        let c = (0..t.half_edge_count()).find(|&c| t.he_from(HalfEdgeId(c as u32)).0 == v && chart(c) == chart(h));
        corner_value(channel, c.unwrap())
    };
    (side(7), side(17))
}

#[test]
fn semi_sharp_edges_inside_a_span_keep_the_value_then_blend() {
    // (sharpness, weight of the left value's parent mask: None = kept).
    for (sharpness, left_weight) in [(10.0f32, None), (2.5, None), (1.0, Some(1.0)), (0.5, Some(0.5)), (0.0, Some(0.0))]
    {
        let (mesh, channel) = seam_with_crease(sharpness);
        let left = corner_in_cell_4(&mesh, 12, (1, 2)); // a face of the left chart at the seam vertex
        let right = corner_in_cell_4(&mesh, 12, (2, 2));
        for mode in [LinearCornersOnly, LinearCornersPlus1] {
            let refined = one_level(&mesh, &channel, Scheme::CatmullClark, mode);
            let check = |h: usize, weight: Option<f64>, what: &str| {
                let own = corner_value(&channel, h);
                let (a, b) = span_ends(&mesh, &channel, h);
                let expected = weight.map_or(own, |w| w * own + (1.0 - w) * (0.75 * own + 0.125 * (a + b)));
                let got = vertex_child(&refined, h);
                assert!(got.distance(expected) < 1e-13, "s = {sharpness}, {mode}, {what}: {got} ≠ {expected}");
            };
            check(left, left_weight, "left value");
            // The right span holds no crease: a crease, except under plus1, where it depends on the
            // left one while that is semi-sharp, and both are corners next to an infinitely sharp edge.
            let right_weight = match (mode, sharpness) {
                (LinearCornersPlus1, s) if s >= 10.0 => None,
                (LinearCornersPlus1, s) if s > 0.0 => left_weight,
                _ => Some(0.0),
            };
            check(right, right_weight, "right value");
        }
    }
}

/// A parent half-edge leaving `v` in the cell (i, j) of a 4 × 4 quad grid.
fn corner_in_cell_4(mesh: &Mesh, v: u32, (i, j): (usize, usize)) -> usize {
    let f = FaceId((4 * j + i) as u32);
    mesh.topology().face_half_edges(f).find(|&h| mesh.topology().he_from(h).0 == v).unwrap().index()
}

#[test]
fn a_semi_sharp_span_blends_at_the_level_where_its_sharpness_ends() {
    // s = 1.5: sharp through level 1 (0.5 left), the blend with w = 0.5 at level 2.
    let (mesh, channel) = seam_with_crease(1.5);
    let (above, below) = (corner_in_cell_4(&mesh, 12, (1, 2)), corner_in_cell_4(&mesh, 12, (1, 1)));
    let options = Options::new(Scheme::CatmullClark).with_fvar(LinearCornersOnly);
    let (_, one) = refine(&mesh, options, 1, &channel);
    let own = corner_value(&channel, above);
    assert_eq!(vertex_child(&one, above), own, "kept at level 1");
    // Level 2: the crease ends are level 1's edge points of the seam edges 12-17 and 7-12 on the left.
    let (_, two) = refine(&mesh, options, 2, &channel);
    let (a, b) = (corner_value(&one, 4 * above + 1), corner_value(&one, 4 * below + 3));
    let expected = 0.5 * own + 0.5 * (0.75 * own + 0.125 * (a + b));
    assert!(corner_value(&two, 16 * above).distance(expected) < 1e-13, "blended at level 2");
    // refine_levels is refine applied level by level.
    let plan = SubdivisionPlan::with_tags(mesh.topology(), mesh.tags(), options, 2).unwrap();
    let [first, second] = plan.levels() else { unreachable!() };
    let direct =
        fvar::refine(&first.topology, &first.sharpness, &second.topology, options.scheme, options.fvar, &one).unwrap();
    assert_eq!(direct, two);
}

#[test]
fn seams_are_kept_and_values_counted_in_every_mode() {
    for triangles in [false, true] {
        let (mesh, channel, scheme) =
            grid_with_charts(triangles, |i, j| [0, 0, 1, 1, 2, 0][i] + 3 * u32::from(j == 2 || j == 5));
        let mesh = if triangles { mesh } else { tagged(mesh) };
        let t = mesh.topology();
        let is_seam = |t: &Topology, ch: &FaceVarying, h: HalfEdgeId| {
            t.he_twin(h).is_some_and(|g| {
                let at = |x: HalfEdgeId| ch.indices[x.index()];
                at(h) != at(t.he_next(g)) || at(t.he_next(h)) != at(g)
            })
        };
        for &mode in FVarInterpolation::ALL {
            let (child, refined) = refine(&mesh, Options::new(scheme).with_fvar(mode), 1, &channel);
            // A child half-edge from an old vertex along an old edge is half of that edge.
            for ph in 0..t.half_edge_count() {
                let ph = HalfEdgeId(ph as u32);
                // The halves of ph's edge from from(ph) and of prev(ph)'s edge to from(ph), and two edges inside the face.
                let (halves, inside) = if triangles {
                    let tri = 4 * (ph.index() / 3) + ph.index() % 3;
                    ([3 * tri, 3 * tri + 2], [3 * tri + 1, 3 * (4 * (ph.index() / 3) + 3) + ph.index() % 3])
                } else {
                    ([4 * ph.index(), 4 * ph.index() + 3], [4 * ph.index() + 1, 4 * ph.index() + 2])
                };
                for (half, of) in halves.into_iter().zip([ph, t.he_prev(ph)]) {
                    let seam = is_seam(t, &channel, of);
                    assert_eq!(is_seam(&child, &refined, HalfEdgeId(half as u32)), seam, "{mode}: half of {of:?}");
                }
                for c in inside {
                    assert!(!is_seam(&child, &refined, HalfEdgeId(c as u32)), "{mode}: an edge inside a face");
                }
            }
            // One value per vertex value, face point and edge side.
            let vertex_values: usize = t
                .vertices()
                .map(|v| {
                    let mut seen: Vec<u32> = t.vertex_fan(v).iter().map(|h| channel.indices[h.index()]).collect();
                    seen.sort_unstable();
                    seen.dedup();
                    seen.len()
                })
                .sum();
            let seams = t.edges().filter(|&e| is_seam(t, &channel, t.edge_half_edge(e))).count();
            let faces = if triangles { 0 } else { t.face_count() };
            assert_eq!(refined.values.len(), vertex_values + faces + t.edge_count() + seams, "{mode}");
        }
    }
}

#[test]
fn weights_sum_to_one_a_constant_channel_stays_constant() {
    for (name, mesh, scheme) in surfaces() {
        // Seams in the index topology, one value everywhere.
        let mut channel = charted(&mesh, |f| (f.0 * 7 % 5) / 2);
        let c = DVec2::new(0.3125, -1.75);
        channel.values.iter_mut().for_each(|v| *v = c);
        for method in [CreaseMethod::Uniform, CreaseMethod::Chaikin] {
            for &mode in FVarInterpolation::ALL {
                let options = Options::new(scheme).with_fvar(mode).with_crease_method(method);
                let (_, refined) = refine(&mesh, options, 3, &channel);
                let worst = refined.values.iter().map(|v| v.distance(c)).fold(0.0, f64::max);
                assert!(worst <= 4e-15, "{name}, {mode}, {method}: a constant moved by {worst:.1e}");
            }
        }
    }
}

#[test]
fn doo_sabin_refines_a_seamless_channel_as_positions_and_refuses_seams() {
    let mesh = shapes::polygon_mix(&shapes::quad_grid(5, 4), 11, 0.3, 0.3, 0.1);
    let channel = seamless(&mesh);
    let uv_positions = (mesh.positions().iter()).map(|&p| uv_of(p).extend(0.0)).collect::<Vec<_>>();
    let surface = subdivide(&mesh.with_positions(uv_positions), Scheme::DooSabin, 2, false).unwrap();
    for &mode in FVarInterpolation::ALL {
        let (t, refined) = refine(&mesh, Options::new(Scheme::DooSabin).with_fvar(mode), 2, &channel);
        assert_eq!(refined.indices, t.faces().indices(), "{mode}: one value per vertex");
        let gap =
            (refined.values.iter().zip(surface.positions())).map(|(a, b)| a.distance(b.truncate())).fold(0.0, f64::max);
        assert!(gap <= 1e-14, "{mode}: {gap:.1e}");
    }
    let cut = charted(&mesh, |f| u32::from(f.0 % 2 == 0));
    let plan = SubdivisionPlan::new(mesh.topology(), Scheme::DooSabin, 1).unwrap();
    let error = fvar::refine(
        mesh.topology(),
        &LevelSharpness::plain(),
        &plan.levels()[0].topology,
        Scheme::DooSabin,
        LinearAll,
        &cut,
    )
    .unwrap_err();
    assert!(matches!(error, FVarError::Seam { scheme: "doo-sabin", .. }), "{error}");
}

#[test]
fn bad_channels_and_schemes_are_typed_errors() {
    let grid = shapes::quad_grid(3, 2);
    let t = grid.topology();
    let child = subdiv_mesh::refine::quad_split(t);
    let sharp = LevelSharpness::plain();
    let run = |scheme, channel: &FaceVarying| fvar::refine(t, &sharp, &child, scheme, LinearNone, channel);
    let good = seamless(&grid);
    let mut short = good.clone();
    short.indices.pop();
    assert!(matches!(run(Scheme::CatmullClark, &short), Err(FVarError::Channel(MeshError::FaceVaryingCount { .. }))));
    let mut out_of_range = good.clone();
    out_of_range.indices[5] = 99;
    assert!(matches!(
        run(Scheme::CatmullClark, &out_of_range),
        Err(FVarError::Channel(MeshError::FaceVaryingIndexOutOfRange { corner: 5, index: 99, .. }))
    ));
    let mut nan = good.clone();
    nan.values[2].y = f64::NAN;
    assert!(matches!(run(Scheme::CatmullClark, &nan), Err(FVarError::Channel(MeshError::NonFiniteFaceVarying { .. }))));
    assert!(matches!(
        run(Scheme::Loop(LoopBeta::Warren), &good),
        Err(FVarError::Stencil(StencilError::NotTriangles { face: 0, size: 4 }))
    ));
    // Deng-Ma refines on Catmull-Clark's split: the channel follows Catmull-Clark's rules.
    let deng_ma = run(Scheme::DengMa(Tension::default()), &good).unwrap();
    assert_eq!(deng_ma, run(Scheme::CatmullClark, &good).unwrap());
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    // 120 × 100 cells: several parallel chunks of vertices, edges and faces.
    let mesh = tagged_big();
    let channel = charted(&mesh, |f| ((f.index() % 120) / 17 + 3 * ((f.index() / 120) / 23)) as u32);
    let options = Options::new(Scheme::CatmullClark).with_fvar(LinearCornersPlus1);
    let many = refine(&mesh, options, 1, &channel).1;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let one = pool.install(|| refine(&mesh, options, 1, &channel).1);
    assert_eq!(many, one);
}

fn tagged_big() -> Mesh {
    let mesh = shapes::quad_grid(120, 100);
    let list = TagList {
        creases: (0..60).map(|i| EdgeTag { a: 121 * 50 + i, b: 121 * 50 + i + 1, sharpness: 1.5 }).collect(),
        corners: vec![VertexTag { vertex: 121 * 20 + 30, sharpness: 2.0 }],
        ..Default::default()
    };
    let tags = Tags::from_list(mesh.topology(), &list).unwrap();
    mesh.with_tags(tags)
}

#[test]
fn a_vertex_of_200_000_faces_with_a_value_each_is_refined_in_linear_time() {
    // A fan of n triangles around vertex 0, every face with its own three values: the
    // centre has n values. Numbering them by a scan would take n²/2 = 2·10¹⁰ steps (about a minute here, against 1 s).
    let n = 200_000u32;
    let positions: Vec<DVec3> = std::iter::once(DVec3::ZERO)
        .chain((0..n).map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            DVec3::new(a.cos(), a.sin(), 0.0)
        }))
        .collect();
    let faces: Vec<[u32; 3]> = (0..n).map(|k| [0, 1 + k, 1 + (k + 1) % n]).collect();
    let mesh = Mesh::new(positions, subdiv_mesh::FaceList::from_faces(faces)).unwrap();
    let t = mesh.topology();
    let channel =
        FaceVarying { values: (0..3 * n).map(|k| DVec2::new(k as f64, 0.5)).collect(), indices: (0..3 * n).collect() };
    let child = subdiv_mesh::refine::quad_split(t);
    for mode in [LinearCornersOnly, LinearNone] {
        let refined = fvar::refine(t, &LevelSharpness::plain(), &child, Scheme::CatmullClark, mode, &channel).unwrap();
        // Every face's value at the centre is a corner of the channel (one face each) and stays,
        // except under linear-none, where it is the crease ¾v + ⅛(a + b) of its own face.
        for (f, &h) in t.vertex_fan(subdiv_mesh::VertexId(0)).iter().enumerate().step_by(9973) {
            let own = corner_value(&channel, h.index());
            let got = corner_value(&refined, 4 * h.index());
            if mode == LinearNone {
                let (a, b) =
                    (corner_value(&channel, t.he_next(h).index()), corner_value(&channel, t.he_prev(h).index()));
                assert!(got.distance(0.75 * own + 0.125 * (a + b)) < 1e-9, "face {f}");
            } else {
                assert_eq!(got, own, "{mode}: face {f}");
            }
        }
    }
}
