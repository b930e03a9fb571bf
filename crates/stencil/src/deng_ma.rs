//! The Deng-Ma interpolatory step (Deng & Ma 2011 §3.3-3.4, [corrections D2, D5]),
//! on closed and open meshes, with infinitely sharp creases and corners.
//!
//! At every old vertex P with Doo-Sabin images Qᵢ (one per face) and their
//! centroid G, the moved vertices are Q̄ᵢ = P + ω_P(Qᵢ − G); the new face point
//! of a face is the centroid of its corners' moved vertices, the new edge
//! point of an edge the centroid of the four moved vertices of its E-face, and
//! old vertices stay. Connectivity is Catmull-Clark's
//! ([`subdiv_mesh::refine::quad_split`]), so the numbering of new vertices is
//! the same as [`crate::catmull_clark`]'s.
//!
//! **Open meshes** (our construction; rules and derivation in
//! `subdiv_rules::deng_ma`, "Open meshes"). A boundary vertex in one face is a
//! corner. The new point of a boundary edge is the 4-point point of its
//! boundary piece, ½(Pᵢ + Pᵢ₊₁) + ωᵢ(Pᵢ₊₁ − Pᵢ₋₁) + ωᵢ₊₁(Pᵢ − Pᵢ₊₂) with the
//! curve tension ω_P/16 and the phantom 2P₀ − P₁ beyond a corner P₀, so it
//! reads boundary vertices only. The moved images of a boundary vertex are
//! taken about G = (P₋ + 6P + P₊)/8 (P at a corner) instead of the centroid
//! of its images; face points and interior edge points are then the report's
//! centroids.
//!
//! # Creases and corners
//!
//! The same rule on the **sharp polygon**, the boundary edges and the edges of
//! sharpness ≥ 10 (construction and why: `subdiv_rules::deng_ma`, "Creases and
//! corners"). Each vertex gets a place from the level's [`LevelSharpness`]:
//! a *corner* (corner sharpness ≥ 10 — a tag, or a one-face boundary vertex
//! under `edge-and-corner`, exactly the open-mesh corner — or three or more
//! sharp edges), a *crease vertex* (two sharp edges; every other boundary
//! vertex), a *dart* (one) or *smooth*. Then:
//!
//! 1. a sharp edge's point is the 4-point point of its piece of the sharp
//!    polygon, cut at corners and darts (phantom beyond them), closed loops
//!    without them periodic: the boundary rule, read off the sharp polygon;
//! 2. a crease vertex's images, in all its faces, are moved about
//!    (P₋ + 6P + P₊)/8, its two sharp neighbours P±; a corner's about P; a
//!    smooth vertex's and a dart's about their centroid;
//! 3. with the variable tension, the images in each *sector* (faces between
//!    two consecutive sharp edges) take the open-mesh ω_P of that sector alone,
//!    so a crease vertex is on each side what a boundary vertex of the cut
//!    mesh would be;
//! 4. the refined level's sharpness is [`LevelSharpness`]'s refinement on the
//!    quad split: the halves of sharp edges stay infinitely sharp, corner
//!    tags stay, so sharp edge points are crease vertices of the next level.
//!
//! A crease thus refines exactly as the mesh cut along it (each side an open
//! mesh, the sides sharing the crease's 4-point points), and the sharp
//! polygon of level k is the input's refined k times by the 4-point rule
//! (`tests/integration/deng_ma_creases.rs`). Without tags the sharp polygon is the
//! boundary and every point is the open-mesh rule's, bit for bit, under
//! `edge-and-corner`; under `edge-only` (and `none`) a one-face boundary
//! vertex is a crease vertex, no corner. Semi-sharp values (0 < s < 10) are
//! refused: [`StencilError::SemiSharpDengMa`], naming the element.
//!
//! ```
//! use subdiv_mesh::{shapes, EdgeTag, TagList, Tags, SHARPNESS_INFINITE};
//! use subdiv_stencil::{subdivide, Options, Scheme, Tension};
//! // The cube's top loop (z = 1) creased: it stays a planar curve, the top flat.
//! let cube = shapes::cube();
//! let creases = [(4, 5), (5, 7), (7, 6), (6, 4)].map(|(a, b)| EdgeTag { a, b, sharpness: SHARPNESS_INFINITE });
//! let tags = Tags::from_list(cube.topology(), &TagList { creases: creases.to_vec(), corners: vec![], ..Default::default() }).unwrap();
//! let options = Options::new(Scheme::DengMa(Tension::default()));
//! let refined = subdivide(&cube.with_tags(tags), options, 3, false).unwrap();
//! let t = refined.topology();
//! let crease: Vec<_> = t.edges().filter(|&e| refined.tags().edge_sharpness(e) >= SHARPNESS_INFINITE).collect();
//! assert_eq!(crease.len(), 4 * 8);
//! for e in crease {
//!     let (a, b) = t.edge_vertices(e);
//!     assert!([a, b].iter().all(|v| (refined.position(*v).z - 1.0).abs() < 1e-15));
//! }
//! ```
//!
//! **The exception to "one sparse product".** With a global ω the step is
//! linear and [`stencil`] gives its matrix. The displacement-safe variable ω_P
//! of §3.4 depends on the positions (edge lengths, image spread), so
//! [`step`] evaluates it geometrically, level by level; it cannot be
//! precomputed from topology and re-applied to other data.
//!
//! [corrections D2, D5]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d2

use crate::apply::fill_in_chunks;
use crate::doo_sabin::{first_step, refinement_stencil as doo_sabin_stencil, StandardCorners};
use crate::scheme::{LevelSplit, SchemeRules};
use crate::sharpness::LevelSharpness;
use crate::{RowBuilder, SparseMatrix, StencilError};
use glam::DVec3;
use subdiv_mesh::refine::quad_split;
use subdiv_mesh::{EdgeId, FaceId, HalfEdgeId, Topology, VertexId};
use subdiv_rules::crease::{is_infinite, is_semi_sharp};
use subdiv_rules::deng_ma::{boundary_centre, Tension, BOUNDARY_CENTRE, CURVE_TENSION_PER_OMEGA};

pub(crate) fn check_tension(tension: Tension) -> Result<(), StencilError> {
    tension.validate().map_err(|e| StencilError::InvalidParameter(e.to_string()))
}

/// Checks that the level's sharpness has a Deng-Ma meaning: every edge and
/// vertex is smooth (0) or infinitely sharp (≥ 10) as the rules see it
/// (boundary edges are infinitely sharp whatever their tag, so a tag on one
/// is not looked at).
///
/// # Errors
/// [`StencilError::SemiSharpDengMa`] naming the first semi-sharp edge, else
/// the first semi-sharp vertex.
pub fn check_sharpness(t: &Topology, sharp: &LevelSharpness) -> Result<(), StencilError> {
    if sharp.is_untagged() {
        return Ok(());
    }
    if let Some((e, s)) = t.edges().map(|e| (e, sharp.edge(t, e))).find(|&(_, s)| is_semi_sharp(s)) {
        let (a, b) = t.edge_vertices(e);
        return Err(StencilError::SemiSharpDengMa { what: format!("edge {} (vertices {a}-{b})", e.0), sharpness: s });
    }
    if let Some((v, s)) = t.vertices().map(|v| (v, sharp.vertex(t, v))).find(|&(_, s)| is_semi_sharp(s)) {
        return Err(StencilError::SemiSharpDengMa { what: format!("vertex {}", v.0), sharpness: s });
    }
    Ok(())
}

/// Where a vertex sits on the sharp polygon (boundary edges and infinitely
/// sharp creases), which decides its centre G and how the pieces of the
/// sharp polygon end (module docs, "Creases and corners").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Place {
    /// No sharp edge (or isolated): G is the centroid of its images.
    Smooth,
    /// One sharp edge: G is the centroid of its images, as for a smooth
    /// vertex, but the piece of the sharp polygon ends here (linear phantom).
    Dart,
    /// Corner sharpness ≥ 10 (a tag, or a one-face boundary vertex under
    /// `edge-and-corner`), or three or more sharp edges: G = P, and every
    /// piece of the sharp polygon through it ends here.
    Corner,
    /// Two sharp edges (not a corner), to `prev` and `next` (a boundary
    /// vertex's previous and next neighbour along its loop, an interior
    /// vertex's two sharp neighbours in fan order): G = (P₋ + 6P + P₊)/8.
    Crease { prev: VertexId, next: VertexId },
}

/// Whether edge `e` is sharp for Deng-Ma: a boundary edge, or a crease of
/// sharpness ≥ 10.
#[inline]
fn is_sharp_edge(t: &Topology, sharp: &LevelSharpness, e: EdgeId) -> bool {
    is_infinite(sharp.edge(t, e))
}

/// The [`Place`] of vertex `v` at this level: its corner sharpness, then its
/// number of sharp edges (untagged: the boundary alone, as before tags).
fn place(t: &Topology, sharp: &LevelSharpness, v: VertexId) -> Place {
    if t.is_isolated(v) {
        return Place::Smooth;
    }
    let boundary = t.is_boundary_vertex(v);
    if is_infinite(sharp.vertex(t, v)) {
        return Place::Corner;
    }
    let boundary_crease = || {
        let (prev, next) = t.boundary_neighbors(v).expect("a boundary vertex has boundary neighbours");
        Place::Crease { prev, next }
    };
    if sharp.is_untagged() {
        // Only the boundary is sharp: its vertices have their two boundary edges.
        return if boundary { boundary_crease() } else { Place::Smooth };
    }
    // The sharp edges among the fan's (a boundary vertex's incoming boundary
    // edge is not one of them: one more).
    let mut ends = [VertexId(0); 2];
    let mut count = usize::from(boundary);
    for &h in t.vertex_fan(v) {
        if is_sharp_edge(t, sharp, t.he_edge(h)) {
            if count < 2 {
                ends[count] = t.he_to(h);
            }
            count += 1;
        }
    }
    match count {
        0 => Place::Smooth,
        1 => Place::Dart,
        2 if boundary => boundary_crease(),
        2 => Place::Crease { prev: ends[0], next: ends[1] },
        _ => Place::Corner,
    }
}

/// The positions of a vertex's neighbours along the sharp polygon, as the
/// rules of `subdiv_rules::deng_ma` take them (`None` at a piece end).
fn curve_neighbours(place: Place, x: &[DVec3]) -> Option<([f64; 3], [f64; 3])> {
    match place {
        Place::Crease { prev, next } => Some((x[prev.index()].to_array(), x[next.index()].to_array())),
        _ => None,
    }
}

/// The four corners (old half-edge ids) of the E-face of the edge of half-edge `h`.
fn e_face_corners(t: &Topology, h: HalfEdgeId, g: HalfEdgeId) -> [HalfEdgeId; 4] {
    [t.he_next(h), h, t.he_next(g), g]
}

/// A neighbour of a sharp edge's end on its piece of the sharp polygon.
#[derive(Clone, Copy, Debug)]
enum Outer {
    /// The end's other neighbour along the piece.
    Vertex(VertexId),
    /// Beyond a piece end `end` (corner or dart): the linear phantom 2·end − `other`.
    Phantom { end: VertexId, other: VertexId },
}

impl Outer {
    fn point(self, x: &[DVec3]) -> DVec3 {
        match self {
            Outer::Vertex(v) => x[v.index()],
            Outer::Phantom { end, other } => 2.0 * x[end.index()] - x[other.index()], // P₋₁ = 2P₀ − P₁
        }
    }

    /// Adds `weight` × this point to a row.
    fn add_to(self, rows: &mut RowBuilder, weight: f64) {
        match self {
            Outer::Vertex(v) => rows.add(v.0, weight),
            Outer::Phantom { end, other } => {
                rows.add(end.0, 2.0 * weight);
                rows.add(other.0, -weight);
            }
        }
    }
}

/// The piece of the sharp polygon around sharp half-edge `h` = a→b: its
/// ends a, b and their outer neighbours a₋ (before a) and b₊ (after b). A
/// corner or a dart ends the piece, and beyond it stands the linear phantom
/// 2a − b (or 2b − a), the open end rule of `subdiv_rules::curves::four_point`.
fn curve_stencil(t: &Topology, sharp: &LevelSharpness, h: HalfEdgeId) -> (VertexId, VertexId, Outer, Outer) {
    let (a, b) = (t.he_from(h), t.he_to(h));
    let outer = |end: VertexId, other: VertexId| match place(t, sharp, end) {
        Place::Crease { prev, next } => Outer::Vertex(if prev == other { next } else { prev }),
        _ => Outer::Phantom { end, other },
    };
    (a, b, outer(a, b), outer(b, a))
}

/// One Deng-Ma step on an untagged mesh: refined topology and positions.
///
/// # Errors
/// As [`step_positions`].
pub fn step(t: &Topology, positions: &[DVec3], tension: Tension) -> Result<(Topology, Vec<DVec3>), StencilError> {
    let refined = step_positions(t, positions, tension)?;
    Ok((quad_split(t), refined))
}

/// The positions of one Deng-Ma step on an untagged mesh (`edge-and-corner`
/// boundaries): [`step_positions_tagged`] with [`LevelSharpness::plain`].
///
/// # Errors
/// [`StencilError::InvalidParameter`] for ω or λ outside (0, 1].
///
/// # Panics
/// If `positions.len()` differs from the vertex count (a caller bug).
pub fn step_positions(t: &Topology, positions: &[DVec3], tension: Tension) -> Result<Vec<DVec3>, StencilError> {
    step_positions_tagged(t, &LevelSharpness::plain(), positions, tension)
}

/// The positions of one Deng-Ma step with the creases and corners of
/// `sharp` (module docs), numbered as [`quad_split`] numbers the refined
/// vertices (old vertices, face points, edge points). Old vertices are
/// copied bit for bit. The refined level's sharpness (halves of sharp edges
/// infinitely sharp, corner tags kept) is the one [`SchemeRules::split`]
/// gives and [`crate::subdivide()`] carries.
///
/// # Errors
/// [`StencilError::InvalidParameter`] for ω or λ outside (0, 1],
/// [`StencilError::SemiSharpDengMa`] for a semi-sharp edge or vertex.
///
/// # Panics
/// If `positions.len()` differs from the vertex count (a caller bug).
pub fn step_positions_tagged(
    t: &Topology,
    sharp: &LevelSharpness,
    positions: &[DVec3],
    tension: Tension,
) -> Result<Vec<DVec3>, StencilError> {
    check_tension(tension)?;
    check_sharpness(t, sharp)?;
    assert_eq!(positions.len(), t.vertex_count(), "one point per vertex");
    // §3.3 step 1: the Doo-Sabin images Q of every corner (the first H points
    // of a Doo-Sabin step; its boundary Chaikin points are not used).
    let images = first_step(t, &StandardCorners, positions)?;
    // §3.3 step 2, per vertex: the centre G, ω_P and (on the sharp polygon)
    // the curve tension; then the moved images Q̄ = P + ω_P (Q − G) per corner.
    let mut centres = vec![Centre::default(); t.vertex_count()];
    fill_in_chunks(&mut centres, |first, chunk| {
        let mut scratch = Scratch::default();
        for (k, c) in chunk.iter_mut().enumerate() {
            let v = VertexId((first + k) as u32);
            *c = centre(t, sharp, v, positions, &images, tension, &mut scratch);
        }
    });
    let mut moved = vec![DVec3::ZERO; t.half_edge_count()];
    fill_in_chunks(&mut moved, |first, chunk| {
        let mut scratch = Scratch::default();
        for (k, m) in chunk.iter_mut().enumerate() {
            let h = HalfEdgeId((first + k) as u32);
            let v = t.he_from(h);
            let c = centres[v.index()];
            let omega = if c.sectors {
                sector_omega(t, sharp, v, h, positions, &images, c.g, tension, &mut scratch)
            } else {
                c.omega
            };
            // §3.3 with correction D2 (docs/REFERENCES.md): Q̄ = P + ω(Q − G).
            *m = positions[v.index()] + omega * (images[h.index()] - c.g);
        }
    });
    // §3.3 step 3: old vertices, face points, edge points (Catmull-Clark numbering).
    let (nv, nf) = (t.vertex_count(), t.face_count());
    let mut out = vec![DVec3::ZERO; nv + nf + t.edge_count()];
    let (old, new) = out.split_at_mut(nv);
    old.copy_from_slice(positions);
    let (face_points, edge_points) = new.split_at_mut(nf);
    fill_in_chunks(face_points, |first, chunk| {
        for (k, point) in chunk.iter_mut().enumerate() {
            let f = FaceId((first + k) as u32);
            *point = t.face_half_edges(f).map(|h| moved[h.index()]).sum::<DVec3>() / t.face_size(f) as f64;
        }
    });
    fill_in_chunks(edge_points, |first, chunk| {
        for (k, point) in chunk.iter_mut().enumerate() {
            let e = EdgeId((first + k) as u32);
            let h = t.edge_half_edge(e);
            *point = match t.he_twin(h) {
                Some(g) if !is_sharp_edge(t, sharp, e) => {
                    e_face_corners(t, h, g).iter().map(|c| moved[c.index()]).sum::<DVec3>() / 4.0
                }
                _ => sharp_edge_point(t, sharp, h, positions, tension, &centres),
            };
        }
    });
    Ok(out)
}

/// What the moved images of a vertex need: the centre G, ω_P, and on the
/// sharp polygon the vertex's 4-point tension on its curve (0 off it).
#[derive(Clone, Copy, Debug, Default)]
struct Centre {
    g: DVec3,
    /// ω_P of every corner of the vertex; unused when `sectors` is set.
    omega: f64,
    curve_tension: f64,
    /// The variable ω_P differs from sector to sector (a vertex whose sharp
    /// edges cut its fan in two or more): [`sector_omega`] per corner.
    sectors: bool,
}

/// Neighbours and images gathered for the variable tension.
#[derive(Default)]
struct Scratch {
    ring: Vec<[f64; 3]>,
    images: Vec<[f64; 3]>,
}

/// How many sectors the sharp edges cut `v`'s fan into: the faces between
/// two consecutive sharp edges. An interior fan with fewer than two sharp
/// edges is one closed sector; an open fan is cut by its interior sharp edges.
fn sector_count(t: &Topology, sharp: &LevelSharpness, v: VertexId) -> usize {
    let fan = t.vertex_fan(v);
    if t.is_boundary_vertex(v) {
        // fan[0] is the outgoing boundary edge: the sharp edges after it cut the open fan.
        1 + fan[1..].iter().filter(|&&h| is_sharp_edge(t, sharp, t.he_edge(h))).count()
    } else {
        fan.iter().filter(|&&h| is_sharp_edge(t, sharp, t.he_edge(h))).count().max(1)
    }
}

/// The [`Centre`] of vertex `v`.
#[allow(clippy::too_many_arguments)]
fn centre(
    t: &Topology,
    sharp: &LevelSharpness,
    v: VertexId,
    positions: &[DVec3],
    images: &[DVec3],
    tension: Tension,
    Scratch { ring, images: qs }: &mut Scratch,
) -> Centre {
    let fan = t.vertex_fan(v);
    if fan.is_empty() {
        return Centre::default(); // isolated: no corners, nothing moves
    }
    let p = positions[v.index()];
    let at = place(t, sharp, v);
    let mut gather = || {
        ring.clear();
        ring.extend(t.vertex_neighbors(v).map(|e| positions[e.index()].to_array()));
        qs.clear();
        qs.extend(fan.iter().map(|h| images[h.index()].to_array()));
    };
    if let Place::Smooth | Place::Dart = at {
        let g = fan.iter().map(|h| images[h.index()]).sum::<DVec3>() / fan.len() as f64; // §3.3: G = ΣQᵢ/m
        let omega = match tension {
            Tension::Global(w) => w,
            Tension::Variable { .. } => {
                gather();
                tension.omega(p.to_array(), ring, qs)
            }
        };
        // A dart ends its crease piece: its curve tension is a piece end's.
        let curve_tension = if at == Place::Dart { tension.curve_tension(p.to_array(), None) } else { 0.0 };
        return Centre { g, omega, curve_tension, sectors: false };
    }
    let neighbours = curve_neighbours(at, positions);
    let g = boundary_centre(p.to_array(), neighbours); // sharp polygon: G = (P₋ + 6P + P₊)/8, P at a corner
    let curve_tension = tension.curve_tension(p.to_array(), neighbours);
    let (omega, sectors) = match tension {
        Tension::Global(w) => (w, false),
        Tension::Variable { .. } if sector_count(t, sharp, v) > 1 => (0.0, true),
        Tension::Variable { .. } => {
            gather();
            (tension.boundary_omega(p.to_array(), neighbours, ring, qs, g), false)
        }
    };
    Centre { g: DVec3::from_array(g), omega, curve_tension, sectors }
}

/// The variable ω_P of corner `h` of a vertex whose fan the sharp edges cut
/// into sectors: the boundary rule on `h`'s sector alone, as if the mesh were
/// cut along its sharp edges (module docs, "Variable tension"):
/// min([`subdiv_rules::deng_ma::curve_omega`], §3.4 over the sector's faces
/// about `g`).
#[allow(clippy::too_many_arguments)]
fn sector_omega(
    t: &Topology,
    sharp: &LevelSharpness,
    v: VertexId,
    h: HalfEdgeId,
    positions: &[DVec3],
    images: &[DVec3],
    g: DVec3,
    tension: Tension,
    Scratch { ring, images: qs }: &mut Scratch,
) -> f64 {
    let fan = t.vertex_fan(v);
    let n = fan.len();
    let open = t.is_boundary_vertex(v);
    // Edge i of the fan joins v to neighbour Eᵢ = to(fan[i]); face i lies
    // between edges i and i + 1. An open fan has the closing edge n (to Eₙ)
    // and both its end edges are boundary edges, hence sharp.
    let sharp_at = |i: usize| (open && i == n) || is_sharp_edge(t, sharp, t.he_edge(fan[i % n]));
    let neighbour = |i: usize| {
        let u = if open && i == n { t.he_from(t.he_prev(fan[n - 1])) } else { t.he_to(fan[i % n]) };
        positions[u.index()].to_array()
    };
    let k = fan.iter().position(|&x| x == h).expect("h is one of its vertex's corners");
    let mut start = k;
    while !sharp_at(start) {
        start = if start == 0 { n - 1 } else { start - 1 };
    }
    let mut m = 1; // faces start, start + 1, …, start + m − 1 (mod n)
    while !sharp_at(start + m) {
        m += 1;
    }
    ring.clear();
    ring.extend((0..=m).map(|i| neighbour(start + i)));
    qs.clear();
    qs.extend((0..m).map(|i| images[fan[(start + i) % n].index()].to_array()));
    let p = positions[v.index()].to_array();
    tension.boundary_omega(p, curve_neighbours(place(t, sharp, v), positions), ring, qs, g.to_array())
}

/// The new point of sharp half-edge `h`: the 4-point rule along its piece of
/// the sharp polygon (Deng-Ma §3.1 step 4, §3.1.1 with [correction D1]), with the
/// phantom beyond a corner or a dart.
///
/// [correction D1]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d1
fn sharp_edge_point(
    t: &Topology,
    sharp: &LevelSharpness,
    h: HalfEdgeId,
    positions: &[DVec3],
    tension: Tension,
    centres: &[Centre],
) -> DVec3 {
    let (a, b, before, after) = curve_stencil(t, sharp, h);
    let (pa, pb) = (positions[a.index()], positions[b.index()]);
    let (before, after) = (before.point(positions), after.point(positions));
    let (wa, wb) = (centres[a.index()].curve_tension, centres[b.index()].curve_tension);
    match tension {
        // (½+ω)(Pᵢ + Pᵢ₊₁) − ω(Pᵢ₋₁ + Pᵢ₊₂), evaluated as `curves::four_point` does.
        Tension::Global(_) => (0.5 + wa) * (pa + pb) + (-wa) * (before + after),
        // ½(Pᵢ + Pᵢ₊₁) + ωᵢ(Pᵢ₊₁ − Pᵢ₋₁) + ωᵢ₊₁(Pᵢ − Pᵢ₊₂), as `curves::four_point_variable`.
        Tension::Variable { .. } => (0.5 * pa + 0.5 * pb) + (wa * (pb - before) + wb * (pa - after)),
    }
}

/// The (V + F + E) × V matrix of one step with a global ω on an untagged
/// mesh: [`stencil_tagged`] with [`LevelSharpness::plain`].
///
/// # Errors
/// [`StencilError::InvalidParameter`] for ω outside (0, 1].
pub fn stencil(t: &Topology, omega: f64) -> Result<SparseMatrix, StencilError> {
    stencil_tagged(t, &LevelSharpness::plain(), omega)
}

/// The (V + F + E) × V matrix of one step with a global ω (linear case), with
/// the creases and corners of `sharp`: `apply(&stencil_tagged(t, sharp, ω)?, x)`
/// equals `step_positions_tagged(t, sharp, x, Tension::Global(ω))` up to
/// round-off.
///
/// # Errors
/// [`StencilError::InvalidParameter`] for ω outside (0, 1],
/// [`StencilError::SemiSharpDengMa`] for a semi-sharp edge or vertex.
pub fn stencil_tagged(t: &Topology, sharp: &LevelSharpness, omega: f64) -> Result<SparseMatrix, StencilError> {
    check_tension(Tension::Global(omega))?;
    check_sharpness(t, sharp)?;
    let ds = doo_sabin_stencil(t, &StandardCorners)?;
    // Row of Q̄_h = P_v + ω(Q_h − G_v): G_v the mean of Q over v's corners
    // (smooth vertices and darts), (P₋ + 6P + P₊)/8 on the sharp polygon, P
    // at a corner.
    let moved_row = |h: HalfEdgeId, rows: &mut RowBuilder, scale: f64| {
        let v = t.he_from(h);
        let fan = t.vertex_fan(v);
        rows.add(v.0, scale);
        let add_q = |rows: &mut RowBuilder, c: HalfEdgeId, w: f64| {
            let row = ds.outer_view(c.index()).expect("corner row");
            for (col, &x) in row.iter() {
                rows.add(col as u32, w * x);
            }
        };
        add_q(rows, h, scale * omega);
        match place(t, sharp, v) {
            Place::Smooth | Place::Dart => {
                for &c in fan {
                    add_q(rows, c, -scale * omega / fan.len() as f64);
                }
            }
            Place::Corner => rows.add(v.0, -scale * omega),
            Place::Crease { prev, next } => {
                for (u, w) in [prev, v, next].into_iter().zip(BOUNDARY_CENTRE) {
                    rows.add(u.0, -scale * omega * w);
                }
            }
        }
    };
    let w = CURVE_TENSION_PER_OMEGA * omega;
    let mut rows = RowBuilder::with_capacity(t.vertex_count() + t.face_count() + t.edge_count(), 0);
    for v in t.vertices() {
        rows.add(v.0, 1.0);
        rows.finish_row();
    }
    for f in t.face_ids() {
        let m = t.face_size(f) as f64;
        for h in t.face_half_edges(f) {
            moved_row(h, &mut rows, 1.0 / m);
        }
        rows.finish_row();
    }
    for e in t.edges() {
        let h = t.edge_half_edge(e);
        match t.he_twin(h) {
            Some(g) if !is_sharp_edge(t, sharp, e) => {
                for c in e_face_corners(t, h, g) {
                    moved_row(c, &mut rows, 0.25);
                }
            }
            _ => {
                // (½+ω)(Pᵢ + Pᵢ₊₁) − ω(Pᵢ₋₁ + Pᵢ₊₂), phantoms expanded.
                let (a, b, before, after) = curve_stencil(t, sharp, h);
                rows.add(a.0, 0.5 + w);
                rows.add(b.0, 0.5 + w);
                before.add_to(&mut rows, -w);
                after.add_to(&mut rows, -w);
            }
        }
        rows.finish_row();
    }
    Ok(rows.build(t.vertex_count()))
}

/// Deng-Ma as a [`SchemeRules`]: the quad split, evaluated geometrically
/// (no stencil, no limit masks: the scheme interpolates), with infinitely
/// sharp creases and corners (module docs); the refined level's tags are the
/// quad split's ([`LevelSharpness`]'s refinement: sharp edges' halves stay
/// infinitely sharp, corners stay).
pub(crate) struct DengMaRules(pub(crate) Tension);

impl SchemeRules for DengMaRules {
    fn check(&self, t: &Topology, sharp: &LevelSharpness) -> Result<(), StencilError> {
        check_tension(self.0)?;
        check_sharpness(t, sharp)
    }

    fn split(&self, t: &Topology, sharp: &LevelSharpness) -> Result<LevelSplit, StencilError> {
        self.check(t, sharp)?;
        let topology = quad_split(t);
        // The half of h's edge at from(h) is corner 0 of quad h: half-edge 4h.
        let sharpness = sharp.refine(t, &topology, |h| 4 * h);
        Ok(LevelSplit { topology, sharpness, dual: None })
    }

    fn stencil(&self, t: &Topology, sharp: &LevelSharpness) -> Result<Option<SparseMatrix>, StencilError> {
        // Evaluated geometrically even for a global ω: its matrix
        // (`stencil_tagged`) is dense-ish (every moved vertex expands over
        // all corners around its vertex) and measured 3-4× slower to build
        // and apply than the direct step.
        self.check(t, sharp).map(|()| None)
    }

    fn step_points(&self, t: &Topology, sharp: &LevelSharpness, x: &[DVec3]) -> Result<Vec<DVec3>, StencilError> {
        step_positions_tagged(t, sharp, x, self.0)
    }

    fn limit_points(
        &self,
        _: &Topology,
        _: &LevelSharpness,
        _: &[DVec3],
        _: usize,
    ) -> Option<Result<Vec<DVec3>, StencilError>> {
        None
    }

    fn limit_stencil(&self, _: &Topology, _: &LevelSharpness, _: usize) -> Option<Result<SparseMatrix, StencilError>> {
        None
    }

    fn levels_before_limit(&self, _: &Topology, _: &LevelSharpness, _: bool) -> usize {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::apply;
    use subdiv_mesh::shapes;

    fn open_meshes() -> Vec<(&'static str, subdiv_mesh::Mesh)> {
        let plate = shapes::plate_with_holes(6, 5, &[(2, 2)], false);
        vec![
            ("quad grid 4×3", shapes::quad_grid(4, 3)),
            ("triangle grid 3×3", shapes::triangle_grid(3, 3)),
            ("plate with a hole", plate.clone()),
            ("plate mix", shapes::polygon_mix(&plate, 7, 0.3, 0.3, 0.2)),
            ("one quad", shapes::quad_grid(1, 1)),
        ]
    }

    #[test]
    fn stencil_equals_the_step_on_open_meshes() {
        for (name, mesh) in open_meshes() {
            let t = mesh.topology();
            // Heights make the data non-planar.
            let x: Vec<DVec3> =
                mesh.positions().iter().map(|p| *p + DVec3::Z * (p.x * 1.3 - p.y * p.y * 0.2).sin()).collect();
            for omega in [1.0, 0.5, 0.125] {
                let r = stencil(t, omega).unwrap();
                let linear = apply(&r, &x);
                let geometric = step_positions(t, &x, Tension::Global(omega)).unwrap();
                let worst = linear.iter().zip(&geometric).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
                assert!(worst <= 1e-14, "{name} ω = {omega}: stencil and step differ by {worst:e}");
                // Affine: every row sums to one.
                assert!(crate::row_sums(&r).iter().all(|s| (s - 1.0).abs() < 1e-14), "{name}");
            }
        }
    }

    #[test]
    fn boundary_edge_points_read_boundary_vertices_only() {
        for (name, mesh) in open_meshes() {
            let t = mesh.topology();
            let r = stencil(t, 1.0).unwrap();
            let base = t.vertex_count() + t.face_count();
            for e in t.edges().filter(|&e| t.is_boundary_edge(e)) {
                let row = r.outer_view(base + e.index()).unwrap();
                for (col, _) in row.iter() {
                    assert!(t.is_boundary_vertex(VertexId(col as u32)), "{name}: edge {e:?} reads vertex {col}");
                }
            }
        }
    }
}
