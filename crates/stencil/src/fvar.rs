//! Face-varying data (texture coordinates) refined with the surface, with
//! OpenSubdiv's six face-varying interpolation modes
//! (`Sdc::Options::FVarLinearInterpolation`, [`FVarInterpolation`]).
//!
//! A face-varying channel ([`FaceVarying`]) gives every face corner a value;
//! two faces meeting at a vertex may use different values there (a *seam*),
//! so the channel has a topology of its own: a vertex on a seam carries
//! several values (OpenSubdiv's *siblings*), each used by a run of
//! consecutive faces around it (its *span*). An edge is a **seam edge** when
//! its two faces use different values at either end; a value's **fvar
//! boundary** is made of the mesh boundary edges and the seam edges that
//! bound its span.
//!
//! [`refine`] computes the channel of the next level from the channel of one
//! level, its topology and its sharpness ([`LevelSharpness`]); [`refine_levels`]
//! chains it over the levels of a plan or a `subdivide` loop.
//!
//! # Semantics (OpenSubdiv 3.x)
//!
//! Read from `vtr/fvarLevel.cpp` (`completeTopologyFromFaceValues`,
//! `gatherValueSpans`), `vtr/fvarRefinement.cpp` and `far/primvarRefiner.h`
//! (`interpFVarFromFaces/Edges/Verts`), re-implemented here:
//!
//! 1. **Seams.** Per edge: seam when the values of its two faces differ at
//!    either end. A vertex *matches* (its channel looks like the mesh there)
//!    when no incident edge is a seam and it is not sharpened by the mode (a
//!    boundary vertex under `linear-boundaries`/`linear-all`; a one-face
//!    boundary vertex under modes other than `linear-none` when the boundary
//!    option leaves such corners smooth). A matching vertex has one value.
//!    The values of the others are numbered around the fan as OpenSubdiv
//!    numbers its siblings, with its shortcut for a fan `A B A B …` (the
//!    second run of `B` a value of its own: `assign_siblings`).
//! 2. **Matching values follow the surface:** the scheme's own rules, with
//!    the vertex's rule from the level's sharpness — boundaries, creases
//!    (semi-sharp included, with the fractional transition) and corners —
//!    applied to the channel's values instead of the positions
//!    ([`LevelSharpness::vertex_step`], [`LevelSharpness::edge_step`]). So
//!    the channel inherits the vertex tags; under `edge-and-corner` the
//!    one-face corners are corners of the channel in every mode.
//! 3. **Other values are classified** from their span: *corner* (the value
//!    stays) when the span holds a seam or another run of the same value, an
//!    infinitely sharp edge, or a single face (modes other than
//!    `linear-none`), when the vertex is infinitely sharp, or when the mode
//!    sharpens all values of the vertex: `linear-boundaries`/`linear-all`;
//!    `plus1`/`plus2` with more than two values, or two values one of whose
//!    spans holds an infinitely sharp edge or a seam (`plus2`: or a single
//!    face); `plus2` and `linear-boundaries` at a *dart* (an interior vertex
//!    with one value where one seam ends). Else *semi-sharp* (kept while a
//!    semi-sharp edge inside the span or the vertex's own sharpness lasts;
//!    under `plus1`/`plus2` the other of two values too, *dependent*), else a
//!    *crease*: ¾v + ⅛(a + b), a and b the values at the far ends of the two
//!    fvar-boundary edges of its span. Where a semi-sharp value becomes a
//!    crease in the step, w·v + (1 − w)·crease with w the fractional weight of
//!    the sharpness decaying inside the span (`Sdc::Crease`'s rule; for a
//!    dependent value, its partner's span).
//! 4. **New values:** a face value is the mean of its corners (every mode); a
//!    seam edge gets one value per side, the midpoint of that side; any other
//!    edge one value by the scheme's edge rule (the midpoint on the boundary
//!    and along sharp edges). `linear-all` is bilinear throughout: face means,
//!    midpoints, vertex values kept.
//!
//! The classification is computed from the channel at every level (a pure
//! function of the level), where OpenSubdiv classifies the base level and
//! hands the tags down; both agree because the refined channel keeps the
//! parent's seams and spans (the children of a seam edge are seam edges, a
//! vertex keeps its values and their spans) and sharpness only decays — see
//! the deviations below for the two places where the hand-down is not a
//! re-classification.
//!
//! # Numbering
//!
//! The values of the refined channel are grouped by refined vertex, in the
//! refined vertex order (as OpenSubdiv does): Catmull-Clark vertex points,
//! face points, edge points; Loop vertex points, edge points. Within a vertex
//! its values follow its fan from the first face (`Topology::vertex_fan`), an
//! edge point's from the face of `Topology::edge_half_edge`. Indices follow the
//! refined face list ([`subdiv_mesh::refine::quad_split`],
//! [`subdiv_mesh::refine::triangle_split`]). A channel without seams thus
//! keeps value = vertex index (isolated vertices aside: they get no value).
//!
//! # Doo-Sabin and Deng-Ma
//!
//! A Doo-Sabin vertex is the image of one face corner, a combination of that
//! face's corners, so a channel refines by the same weights over the face's
//! corner values (and the boundary's Chaikin points along their edge). The
//! faces around an old vertex and across an old edge join corner images of
//! different faces, so across a seam they would mix values of two charts: a
//! channel with seams is refused ([`FVarError::Seam`]). The dual split has no
//! vertex rules to make linear, so every mode gives the same values. Deng-Ma
//! (interpolatory, geometric tension: a rule for positions only) refines on
//! Catmull-Clark's split, and its channel takes Catmull-Clark's rules in the
//! chosen mode: the texture coordinates of a Deng-Ma surface are a smooth (or,
//! under `linear-all`, bilinear) parametrisation of it, seams kept.
//!
//! # Deviations from OpenSubdiv
//!
//! - *Dependent sharpness* (`plus1`/`plus2`, two values of which only one has
//!   semi-sharp edges inside its span): OpenSubdiv's hand-down can leave the
//!   partner tagged semi-sharp after the sharpness it depended on is gone, in
//!   one ordering of decays; here it becomes a crease as soon as the
//!   re-classification says so.
//! - Under `linear-boundaries`, OpenSubdiv marks a boundary edge "linear" from
//!   the first of its ends examined that has no seam; a boundary edge whose
//!   two ends both have seams stays unmarked and its edge point is later
//!   refined by the crease rule instead of being kept. Its neighbours lie on
//!   the same straight segment at uniform parameters, so both give the same
//!   value up to round-off.
//! - Isolated vertices get no value (OpenSubdiv gives each one).
//!
//! # Cost
//!
//! Linear in the corners: per edge a seam test, per vertex one pass over its
//! fan (a sort instead of a scan for vertices of more than
//! 32 faces, `LINEAR_SEARCH_MAX`, so no vertex costs valence × values), all in
//! parallel chunks of fixed size (the result does not depend on the thread
//! count); no hash map.
//!
//! ```
//! use glam::DVec2;
//! use subdiv_mesh::{refine::quad_split, shapes, FaceVarying};
//! use subdiv_stencil::{fvar, FVarInterpolation, LevelSharpness, Scheme};
//! // A 2 × 1 grid whose two quads have their own UVs: a seam along the middle edge.
//! let grid = shapes::quad_grid(2, 1);
//! let t = grid.topology();
//! let uv = |v: u32| DVec2::new(grid.positions()[v as usize].x, grid.positions()[v as usize].y);
//! let mut values = Vec::new();
//! let mut indices = Vec::new();
//! for f in t.face_ids() {
//!     for &v in t.face(f) {
//!         indices.push(values.len() as u32);
//!         values.push(uv(v) + DVec2::new(f.0 as f64, 0.0)); // face 1 shifted by one unit
//!     }
//! }
//! let channel = FaceVarying { values, indices };
//! let child = quad_split(t);
//! let refined = fvar::refine(t, &LevelSharpness::plain(), &child, Scheme::CatmullClark,
//!     FVarInterpolation::LinearAll, &channel).unwrap();
//! assert_eq!(refined.indices.len(), child.half_edge_count());
//! // 6 vertices and a second value at both ends of the seam edge (1, 4),
//! // 2 face points, 7 edges and a second value on the seam.
//! assert_eq!(refined.values.len(), (6 + 2) + 2 + (7 + 1));
//! // Bilinear: every face point is the mean of its face's UVs.
//! assert_eq!(refined.values[8], DVec2::new(0.5, 0.5));
//! assert_eq!(refined.values[9], DVec2::new(2.5, 0.5));
//! ```

use crate::doo_sabin::{self, StandardCorners};
use crate::loop_subdivision::require_triangles;
use crate::sharpness::{EdgeStep, LevelSharpness};
use crate::{FVarSupport, Scheme, Split, StencilError};
use glam::{DVec2, DVec3};
use rayon::prelude::*;
use std::borrow::Cow;
use std::ops::Range;
use subdiv_mesh::{EdgeId, FaceId, FaceVarying, HalfEdgeId, MeshError, Topology, VertexId};
use subdiv_rules::crease::{decrement, fractional_weight, is_infinite, is_semi_sharp, is_sharp, SHARPNESS_INFINITE};
use subdiv_rules::{catmull_clark, loop_scheme, BoundaryInterpolation, FVarInterpolation, Rule, VertexKind};
use thiserror::Error;

/// Vertices with at most this many faces number their values by a scan of
/// the values seen so far; larger fans sort (value, face) pairs instead, so
/// a vertex of k faces and k values costs k log k, not k².
const LINEAR_SEARCH_MAX: usize = 32;

/// Elements per parallel task: fixed, so nothing depends on the thread count.
const CHUNK: usize = 4096;

/// Why a face-varying channel cannot be refined.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum FVarError {
    /// The channel does not fit the topology (index count, an index out of
    /// range, a non-finite value).
    #[error("face-varying channel: {0}")]
    Channel(#[from] MeshError),
    /// The scheme cannot take the mesh (Loop on a non-triangle).
    #[error(transparent)]
    Stencil(#[from] StencilError),
    /// The scheme has no face-varying rule.
    #[error("{scheme} does not refine face-varying data: {reason}")]
    SchemeNotSupported {
        /// Scheme name.
        scheme: &'static str,
        /// Why.
        reason: &'static str,
    },
    /// The scheme refines only channels without seams, and this one has one.
    #[error(
        "{scheme} refines face-varying data only without seams, but the texture coordinates differ across edge ({a}, {b})"
    )]
    Seam {
        /// Scheme name.
        scheme: &'static str,
        /// One end of the first seam edge.
        a: u32,
        /// Its other end.
        b: u32,
    },
}

/// One level of face-varying refinement: the channel of the level after
/// `parent`, whose topology is `child` (the scheme's split of `parent`, as
/// [`crate::SchemeRules::split`] makes it), from the channel of `parent` with
/// the sharpness `sharp` of that level and the interpolation `mode`
/// (module docs). `child` is used for Doo-Sabin's face list and checked
/// against the split's counts for the others.
///
/// # Errors
/// [`FVarError::Channel`] when `channel` does not fit `parent`,
/// [`FVarError::Stencil`] with [`StencilError::NotTriangles`] for Loop on a
/// non-triangle, [`FVarError::Seam`] for Doo-Sabin with seams,
/// [`FVarError::SchemeNotSupported`] for Doo-Sabin with tags. Deng-Ma's
/// channel follows Catmull-Clark's rules on the same split.
///
/// # Panics
/// If `child` does not have the counts of the scheme's split of `parent` (a
/// caller bug).
pub fn refine(
    parent: &Topology,
    sharp: &LevelSharpness,
    child: &Topology,
    scheme: Scheme,
    mode: FVarInterpolation,
    channel: &FaceVarying,
) -> Result<FaceVarying, FVarError> {
    channel.validate(parent.half_edge_count())?;
    let traits = scheme.traits();
    if traits.triangles_only {
        require_triangles(parent)?;
    }
    match traits.face_varying {
        FVarSupport::Full => {}
        FVarSupport::SeamlessUntagged if !sharp.is_untagged() => {
            return Err(FVarError::SchemeNotSupported {
                scheme: scheme.name(),
                reason: "its creases and corners change the split, which the channel does not follow yet",
            })
        }
        FVarSupport::SeamlessUntagged => return refine_dual(parent, child, channel),
        FVarSupport::None => {
            return Err(FVarError::SchemeNotSupported {
                scheme: scheme.name(),
                reason: "√3 has no face-varying rules here (its flips leave no edge of the parent)",
            })
        }
    }
    let (nv, nf, ne) = (parent.vertex_count(), parent.face_count(), parent.edge_count());
    let expected = match traits.split {
        Split::Quad => (nv + nf + ne, 4 * parent.half_edge_count()),
        Split::Triangle => (nv + ne, 12 * nf),
        Split::Dual => unreachable!("{DUAL}"),
        Split::Sqrt3 => unreachable!("{NONE}"),
    };
    assert_eq!((child.vertex_count(), child.half_edge_count()), expected, "child is not the split of parent");
    let step = Step {
        t: parent,
        sharp,
        scheme,
        rules: ModeRules::new(mode, sharp.boundary()),
        indices: &channel.indices,
        values: &channel.values,
        seam: seam_edges(parent, &channel.indices),
    };
    Ok(step.refine())
}

/// [`refine`] over several levels: `levels` yields each refined level's
/// topology and sharpness in order (a plan's
/// `levels().iter().map(|r| (&r.topology, &r.sharpness))`, or the splits of a
/// `subdivide` loop), the first refining `base` with `base_sharpness`; with
/// no level, the channel as it is.
///
/// # Errors
/// As [`refine`], for the first level that fails.
pub fn refine_levels<'a>(
    base: &'a Topology,
    base_sharpness: &'a LevelSharpness,
    levels: impl IntoIterator<Item = (&'a Topology, &'a LevelSharpness)>,
    scheme: Scheme,
    mode: FVarInterpolation,
    channel: &FaceVarying,
) -> Result<FaceVarying, FVarError> {
    let (mut t, mut sharp) = (base, base_sharpness);
    let mut current = Cow::Borrowed(channel);
    for (child, child_sharpness) in levels {
        current = Cow::Owned(refine(t, sharp, child, scheme, mode, &current)?);
        (t, sharp) = (child, child_sharpness);
    }
    Ok(current.into_owned())
}

/// Per edge, whether it is a seam: its two faces use different values at
/// either end (boundary edges never are).
fn seam_edges(t: &Topology, indices: &[u32]) -> Vec<bool> {
    (0..t.edge_count())
        .into_par_iter()
        .with_min_len(CHUNK)
        .map(|e| {
            let h = t.edge_half_edge(EdgeId(e as u32));
            t.he_twin(h).is_some_and(|g| {
                let at = |x: HalfEdgeId| indices[x.index()];
                at(h) != at(t.he_next(g)) || at(t.he_next(h)) != at(g)
            })
        })
        .collect()
}

/// Doo-Sabin: a channel without seams is a function of the vertices, refined
/// by the positions' own step ([`doo_sabin::first_step`]).
fn refine_dual(t: &Topology, child: &Topology, channel: &FaceVarying) -> Result<FaceVarying, FVarError> {
    if let Some(e) = seam_edges(t, &channel.indices).iter().position(|&s| s) {
        let (a, b) = t.edge_vertices(EdgeId(e as u32));
        return Err(FVarError::Seam { scheme: Scheme::DooSabin.name(), a: a.0, b: b.0 });
    }
    let per_vertex: Vec<DVec3> = t
        .vertices()
        .map(|v| {
            let first = t.vertex_fan(v).first();
            first.map_or(DVec3::ZERO, |h| channel.values[channel.indices[h.index()] as usize].extend(0.0))
        })
        .collect();
    let points = doo_sabin::first_step(t, &StandardCorners, &per_vertex)?;
    assert_eq!(points.len(), child.vertex_count(), "child is not the Doo-Sabin split of parent");
    Ok(FaceVarying { values: points.iter().map(|p| p.truncate()).collect(), indices: child.faces().indices().to_vec() })
}

/// Why the matches below have a Doo-Sabin arm that is never taken.
const DUAL: &str = "a channel on the dual split is refined by `refine_dual`";
/// Why a scheme without face-varying rules never gets here.
const NONE: &str = "a scheme without face-varying rules is refused before refining a channel";

/// The mode decoded into OpenSubdiv's switches
/// (`FVarLevel::completeTopologyFromFaceValues`).
#[derive(Clone, Copy, Debug)]
struct ModeRules {
    /// `linear-all`: bilinear everywhere.
    linear_all: bool,
    /// `linear-boundaries` or `linear-all`: every value on a boundary or seam stays.
    linear_boundaries: bool,
    /// `plus1`, `plus2`: the sharpness of one value decides its sibling's.
    dependent: bool,
    /// Every mode but `linear-none`: a value in a single face is a corner.
    corners_sharp: bool,
    /// One-face boundary vertices are channel corners although the boundary
    /// option leaves them smooth on the surface.
    smooth_corners_sharp: bool,
    /// `plus2`: of two values, a corner sharpens the other.
    both_if_one_corner: bool,
    /// `plus2`, `linear-boundaries`, `linear-all`: a dart stays.
    sharpen_darts: bool,
}

impl ModeRules {
    fn new(mode: FVarInterpolation, boundary: BoundaryInterpolation) -> Self {
        use FVarInterpolation::*;
        let linear_boundaries = matches!(mode, LinearBoundaries | LinearAll);
        let corners_sharp = mode != LinearNone;
        let both_if_one_corner = mode == LinearCornersPlus2;
        Self {
            linear_all: mode == LinearAll,
            linear_boundaries,
            dependent: matches!(mode, LinearCornersPlus1 | LinearCornersPlus2),
            corners_sharp,
            smooth_corners_sharp: corners_sharp && boundary != BoundaryInterpolation::EdgeAndCorner,
            both_if_one_corner,
            sharpen_darts: both_if_one_corner || linear_boundaries,
        }
    }
}

/// How a value of a vertex without a match is refined (step 3 of the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Tag {
    /// Stays.
    Corner,
    /// ¾v + ⅛(a + b) along its span's ends.
    Crease,
    /// A corner until the semi-sharpness in its span (`dependent`: its
    /// partner's) has decayed.
    SemiSharp { dependent: bool },
}

/// The faces around a vertex that share one of its values.
#[derive(Clone, Copy, Debug, Default)]
struct Span {
    /// Fan index of the first face.
    start: u32,
    /// Number of faces.
    size: u32,
    /// Separate runs of faces with this value.
    runs: u32,
    /// Seam edges inside the span, plus one per extra run.
    seams: u32,
    /// Infinitely sharp edges inside the span.
    infinite: u32,
    /// Semi-sharp edges inside the span, before and after the step.
    semi: u32,
    child_semi: u32,
}

/// Working memory of one vertex's analysis, kept from vertex to vertex.
#[derive(Default)]
struct Scratch {
    /// Per fan face, the index of its value among the vertex's values.
    sibling: Vec<u32>,
    /// The vertex's values (parent value indices), in order of first face.
    distinct: Vec<u32>,
    /// (value, face) pairs and (first face, start, end) groups of a large fan.
    order: Vec<(u32, u32)>,
    groups: Vec<(u32, u32, u32)>,
    spans: Vec<Span>,
    parent_tags: Vec<Tag>,
    child_tags: Vec<Tag>,
    /// Sharpness of the edges at the vertex in fan order (boundary: the
    /// incoming edge last), and of the edges inside one span before and after.
    incident: Vec<f32>,
    span_parent: Vec<f32>,
    span_child: Vec<f32>,
}

/// What the vertex pass of one chunk produces.
struct VertexChunk {
    /// Values per vertex.
    counts: Vec<u32>,
    values: Vec<DVec2>,
    /// (half-edge, sibling) of the fan faces using a vertex's second or later value.
    siblings: Vec<(u32, u32)>,
}

/// One level's refinement of one channel.
struct Step<'a> {
    t: &'a Topology,
    sharp: &'a LevelSharpness,
    /// The scheme whose face-varying rules the channel follows (Deng-Ma's
    /// are Catmull-Clark's: its tension is a rule for positions only).
    scheme: Scheme,
    rules: ModeRules,
    indices: &'a [u32],
    values: &'a [DVec2],
    seam: Vec<bool>,
}

/// A sum of weighted values in the order they are added (as
/// `RowBuilder::evaluate_parallel_with_scratch` sums a row).
#[derive(Default)]
struct Sum(DVec2);

impl Sum {
    #[inline]
    fn add(&mut self, weight: f64, value: DVec2) {
        self.0 += weight * value;
    }
}

/// Calls `f` on consecutive index ranges of [`CHUNK`] in parallel, results in order.
fn chunked<T: Send>(n: usize, f: impl Fn(Range<usize>) -> T + Sync) -> Vec<T> {
    (0..n.div_ceil(CHUNK)).into_par_iter().map(|c| f(c * CHUNK..((c + 1) * CHUNK).min(n))).collect()
}

impl Step<'_> {
    /// The value of corner `h` (the corner half-edge `h` starts at).
    #[inline]
    fn value(&self, h: HalfEdgeId) -> DVec2 {
        self.values[self.indices[h.index()] as usize]
    }

    /// The corner `j` steps after `h`'s in its face (`j` < face size).
    #[inline]
    fn corner_after(&self, h: HalfEdgeId, j: usize) -> HalfEdgeId {
        let offsets = self.t.faces().offsets();
        let f = self.t.he_face(h).index();
        let (start, m) = (offsets[f] as usize, (offsets[f + 1] - offsets[f]) as usize);
        let at = h.index() - start + j;
        HalfEdgeId((start + if at >= m { at - m } else { at }) as u32)
    }

    fn refine(&self) -> FaceVarying {
        let t = self.t;
        let (nv, nf, ne, nh) = (t.vertex_count(), t.face_count(), t.edge_count(), t.half_edge_count());
        // 1. Vertex points: the values of every vertex, and where a vertex has several, which face uses which.
        let vertex_chunks = chunked(nv, |range| {
            let mut chunk =
                VertexChunk { counts: Vec::with_capacity(range.len()), values: Vec::new(), siblings: Vec::new() };
            let mut scratch = Scratch::default();
            for v in range {
                let count = self.vertex_values(VertexId(v as u32), &mut chunk, &mut scratch);
                chunk.counts.push(count);
            }
            chunk
        });
        // 2. Face points (Catmull-Clark): the mean of the corners, in every mode.
        let face_values: Vec<DVec2> = match self.scheme {
            Scheme::CatmullClark | Scheme::DengMa(_) => {
                (0..nf).into_par_iter().with_min_len(CHUNK).map(|f| self.face_value(FaceId(f as u32))).collect()
            }
            Scheme::Loop(_) => Vec::new(),
            Scheme::DooSabin => unreachable!("{DUAL}"),
            Scheme::Sqrt3 => unreachable!("{NONE}"),
        };
        // 3. Edge points: one value per edge, one per side of a seam.
        let edge_chunks = chunked(ne, |range| {
            let mut out = Vec::with_capacity(range.len());
            for e in range {
                self.edge_values(EdgeId(e as u32), &mut out);
            }
            out
        });
        // 4. Numbering: grouped by refined vertex, in the refined vertex order.
        let mut vertex_offset = Vec::with_capacity(nv);
        let mut total = 0u32;
        for c in vertex_chunks.iter().flat_map(|c| &c.counts) {
            vertex_offset.push(total);
            total += c;
        }
        let face_base = total;
        let edge_base = face_base + face_values.len() as u32;
        let mut edge_offset = Vec::with_capacity(ne);
        let mut next = edge_base;
        for &seam in &self.seam {
            edge_offset.push(next);
            next += 1 + u32::from(seam);
        }
        let mut values = Vec::with_capacity(next as usize);
        let mut sibling = vec![0u32; nh];
        for c in &vertex_chunks {
            values.extend_from_slice(&c.values);
            for &(h, s) in &c.siblings {
                sibling[h as usize] = s;
            }
        }
        values.extend_from_slice(&face_values);
        for c in &edge_chunks {
            values.extend_from_slice(c);
        }
        debug_assert_eq!(values.len(), next as usize);
        // 5. Indices of the refined corners.
        let vertex_value = |h: HalfEdgeId| vertex_offset[t.he_from(h).index()] + sibling[h.index()];
        let edge_value = |h: HalfEdgeId| {
            let e = t.he_edge(h);
            edge_offset[e.index()] + u32::from(self.seam[e.index()] && t.edge_half_edge(e) != h)
        };
        let indices = match self.scheme {
            Scheme::CatmullClark | Scheme::DengMa(_) => {
                // Quad h = (from(h), e(h), f(h), e(prev h)).
                let mut indices = vec![0u32; 4 * nh];
                indices.par_chunks_mut(4 * CHUNK).enumerate().for_each(|(c, out)| {
                    for (k, quad) in out.chunks_exact_mut(4).enumerate() {
                        let h = HalfEdgeId((c * CHUNK + k) as u32);
                        let face = face_base + t.he_face(h).0;
                        quad.copy_from_slice(&[vertex_value(h), edge_value(h), face, edge_value(t.he_prev(h))]);
                    }
                });
                indices
            }
            Scheme::Loop(_) => {
                // Triangle 4f + k = (v_k, e(h_k), e(h_{k−1})), centre 4f + 3 = (e(h₀), e(h₁), e(h₂)).
                let mut indices = vec![0u32; 12 * nf];
                indices.par_chunks_mut(12 * CHUNK).enumerate().for_each(|(c, out)| {
                    for (k, four) in out.chunks_exact_mut(12).enumerate() {
                        let h = |j: usize| HalfEdgeId((3 * (c * CHUNK + k) + j) as u32);
                        let e = [edge_value(h(0)), edge_value(h(1)), edge_value(h(2))];
                        four.copy_from_slice(&[
                            vertex_value(h(0)),
                            e[0],
                            e[2],
                            vertex_value(h(1)),
                            e[1],
                            e[0],
                            vertex_value(h(2)),
                            e[2],
                            e[1],
                            e[0],
                            e[1],
                            e[2],
                        ]);
                    }
                });
                indices
            }
            Scheme::DooSabin => unreachable!("{DUAL}"),
            Scheme::Sqrt3 => unreachable!("{NONE}"),
        };
        FaceVarying { values, indices }
    }

    /// The face point of `f`: the mean of its corner values.
    fn face_value(&self, f: FaceId) -> DVec2 {
        let w = catmull_clark::face_point_weight(self.t.face_size(f));
        let mut sum = Sum::default();
        for h in self.t.face_half_edges(f) {
            sum.add(w, self.value(h));
        }
        sum.0
    }

    /// The value(s) of the edge point of `e`.
    fn edge_values(&self, e: EdgeId, out: &mut Vec<DVec2>) {
        let t = self.t;
        let h = t.edge_half_edge(e);
        let midpoint = |h: HalfEdgeId, scale: f64, sum: &mut Sum| {
            sum.add(scale * 0.5, self.value(h));
            sum.add(scale * 0.5, self.value(t.he_next(h)));
        };
        let mut sum = Sum::default();
        match t.he_twin(h) {
            Some(g) if self.seam[e.index()] => {
                // One value per side of a seam: the midpoint of that side.
                for side in [h, g] {
                    let mut sum = Sum::default();
                    midpoint(side, 1.0, &mut sum);
                    out.push(sum.0);
                }
                return;
            }
            Some(g) if !self.rules.linear_all => match self.sharp.edge_step(t, e) {
                EdgeStep::Smooth => self.smooth_edge(h, g, 1.0, &mut sum),
                EdgeStep::Midpoint => midpoint(h, 1.0, &mut sum),
                EdgeStep::Blend(s) => {
                    // OpenSubdiv's semi-sharp edge: s·midpoint + (1 − s)·smooth.
                    midpoint(h, s, &mut sum);
                    self.smooth_edge(h, g, 1.0 - s, &mut sum);
                }
            },
            // Boundary edges (infinitely sharp in every boundary mode) and `linear-all`.
            _ => midpoint(h, 1.0, &mut sum),
        }
        out.push(sum.0);
    }

    /// The scheme's smooth edge rule on the values of interior edge h/g, times `scale`.
    fn smooth_edge(&self, h: HalfEdgeId, g: HalfEdgeId, scale: f64, sum: &mut Sum) {
        let t = self.t;
        match self.scheme {
            Scheme::CatmullClark | Scheme::DengMa(_) => {
                // Correction C2 (docs/REFERENCES.md): (V + E + f_left + f_right)/4, the face points expanded
                // over their corners; OpenSubdiv's weights next to a triangle under the smooth
                // triangle rule, as for the positions.
                let size = |x: HalfEdgeId| t.face_size(t.he_face(x));
                let mask = catmull_clark::edge_point_mask_with(size(h), Some(size(g)), self.sharp.triangle_rule());
                sum.add(scale * mask.end, self.value(h));
                sum.add(scale * mask.end, self.value(t.he_next(h)));
                for (side, w) in [(h, mask.left), (g, mask.right)] {
                    if w != 0.0 {
                        for j in 2..size(side) {
                            sum.add(scale * w, self.value(self.corner_after(side, j)));
                        }
                    }
                }
            }
            Scheme::Loop(_) => {
                // ⅜(a + b) + ⅛(c + d), c and d the corners opposite the edge.
                let mask = loop_scheme::edge_point_mask(false);
                sum.add(scale * mask.end, self.value(h));
                sum.add(scale * mask.end, self.value(t.he_next(h)));
                sum.add(scale * mask.left, self.value(t.he_prev(h)));
                sum.add(scale * mask.right, self.value(t.he_prev(g)));
            }
            Scheme::DooSabin => unreachable!("{DUAL}"),
            Scheme::Sqrt3 => unreachable!("{NONE}"),
        }
    }

    /// Appends the refined values of vertex `v` and returns their number;
    /// records which faces use its second and later values.
    fn vertex_values(&self, v: VertexId, chunk: &mut VertexChunk, s: &mut Scratch) -> u32 {
        let t = self.t;
        let fan = t.vertex_fan(v);
        let n = fan.len();
        if n == 0 {
            return 0; // isolated: no corner, no value
        }
        let boundary = t.is_boundary_vertex(v);
        let sharpened = boundary && (self.rules.linear_boundaries || (n == 1 && self.rules.smooth_corners_sharp));
        if !sharpened && !fan.iter().any(|&h| self.seam[t.he_edge(h).index()]) {
            // The channel matches the mesh here: one value, the surface's rule.
            chunk.values.push(self.matched_vertex_value(v));
            return 1;
        }
        let count = self.unmatched_vertex_values(v, s, &mut chunk.values);
        if count > 1 {
            let siblings = fan.iter().zip(&s.sibling).filter(|&(_, &k)| k != 0);
            chunk.siblings.extend(siblings.map(|(h, &k)| (h.0, k)));
        }
        count
    }

    /// A vertex where the channel matches the mesh: the scheme's vertex rule
    /// (smooth, crease, corner, and the semi-sharp blend) on the values.
    fn matched_vertex_value(&self, v: VertexId) -> DVec2 {
        let own = self.value(self.t.vertex_fan(v)[0]);
        if self.rules.linear_all {
            return own;
        }
        let mut sum = Sum::default();
        for (rule, ends, w) in self.sharp.vertex_step(self.t, v).masks() {
            self.vertex_mask(v, rule, ends, w, &mut sum);
        }
        sum.0
    }

    /// One vertex mask of `rule` at a matched vertex, times `scale`.
    fn vertex_mask(&self, v: VertexId, rule: Rule, ends: Option<(VertexId, VertexId)>, scale: f64, sum: &mut Sum) {
        let t = self.t;
        let fan = t.vertex_fan(v);
        let own = self.value(fan[0]);
        match (rule, ends) {
            // A boundary vertex is never smooth (its boundary edges are sharp).
            (Rule::Smooth | Rule::Dart, _) if !t.is_boundary_vertex(v) => match self.scheme {
                Scheme::CatmullClark | Scheme::DengMa(_) => self.smooth_catmull_clark(v, scale, sum),
                Scheme::Loop(beta) => {
                    // Eq. (1): (1 − kβ)p + βΣpⱼ.
                    let mask = loop_scheme::vertex_point_mask(VertexKind::Interior, fan.len(), beta);
                    sum.add(scale * mask.vertex, own);
                    for &h in fan {
                        sum.add(scale * mask.interior_neighbor, self.value(t.he_next(h)));
                    }
                }
                Scheme::DooSabin => unreachable!("{DUAL}"),
                Scheme::Sqrt3 => unreachable!("{NONE}"),
            },
            (Rule::Crease, Some((a, b))) => {
                let mask = self.crease_mask(t.valence(v));
                sum.add(scale * mask.vertex, own);
                sum.add(scale * mask.boundary_neighbor, self.neighbour_value(v, b));
                sum.add(scale * mask.boundary_neighbor, self.neighbour_value(v, a));
            }
            _ => sum.add(scale, own),
        }
    }

    /// The scheme's crease (boundary) vertex mask, (E₋ + 6V + E₊)/8.
    fn crease_mask(&self, valence: usize) -> subdiv_rules::VertexMask {
        match self.scheme {
            Scheme::CatmullClark | Scheme::DengMa(_) => catmull_clark::vertex_point_mask(VertexKind::Boundary, valence),
            Scheme::Loop(beta) => loop_scheme::vertex_point_mask(VertexKind::Boundary, valence, beta),
            Scheme::DooSabin => unreachable!("{DUAL}"),
            Scheme::Sqrt3 => unreachable!("{NONE}"),
        }
    }

    /// Eq. (4) at an interior vertex on the values, times `scale`:
    /// (n−2)/n V + 1/n² Σ Eᵢ + 1/n² Σ fᵢ with the face points expanded (the
    /// weights merged per corner as `catmull_clark`'s rows merge them).
    fn smooth_catmull_clark(&self, v: VertexId, scale: f64, sum: &mut Sum) {
        let t = self.t;
        let fan = t.vertex_fan(v);
        let mask = catmull_clark::vertex_point_mask(VertexKind::Interior, fan.len());
        let face_weight = |h: HalfEdgeId| {
            let m = t.face_size(t.he_face(h));
            (m, mask.face * catmull_clark::face_point_weight(m))
        };
        let mut previous = face_weight(fan[fan.len() - 1]).1; // E₀ is in the last face too
        let mut centre = mask.vertex;
        for &h in fan {
            let (m, w) = face_weight(h);
            centre += w;
            sum.add(scale * (mask.interior_neighbor + previous + w), self.value(t.he_next(h))); // Eᵢ ∈ fᵢ₋₁, fᵢ
            for j in 2..m - 1 {
                sum.add(scale * w, self.value(self.corner_after(h, j))); // far corners of fᵢ
            }
            previous = w;
        }
        sum.add(scale * centre, self.value(fan[0]));
    }

    /// The value at neighbour `u` of a matched vertex `v` (the same in both
    /// faces of their edge).
    fn neighbour_value(&self, v: VertexId, u: VertexId) -> DVec2 {
        let t = self.t;
        let fan = t.vertex_fan(v);
        match fan.iter().find(|&&h| t.he_to(h) == u) {
            Some(&h) => self.value(t.he_next(h)),
            None => self.value(t.he_prev(fan[fan.len() - 1])), // the incoming boundary edge's start
        }
    }

    /// The values of a vertex where the channel does not match the mesh
    /// (module docs, step 3), appended to `out`; returns their number and
    /// leaves each fan face's value in `s.sibling`.
    fn unmatched_vertex_values(&self, v: VertexId, s: &mut Scratch, out: &mut Vec<DVec2>) -> u32 {
        let t = self.t;
        let fan = t.vertex_fan(v);
        assign_siblings(fan.len(), |i| self.indices[fan[i].index()], s);
        let count = s.distinct.len();
        if self.rules.linear_all {
            out.extend(s.distinct.iter().map(|&x| self.values[x as usize]));
            return count as u32;
        }
        self.gather_spans(v, s);
        self.tag_values(v, s);
        for j in 0..count {
            let own = self.values[s.distinct[j] as usize];
            let value = match (s.parent_tags[j], s.child_tags[j]) {
                (Tag::Corner, _) | (_, Tag::Corner | Tag::SemiSharp { .. }) => own,
                (parent, Tag::Crease) => {
                    let corner_weight = match parent {
                        // A dependent value takes its partner's weight (two values only).
                        Tag::SemiSharp { dependent } => self.span_weight(v, s, if dependent { 1 - j } else { j }),
                        _ => 0.0,
                    };
                    // The far ends of the span's two fvar-boundary edges.
                    let span = s.spans[j];
                    let last = (span.start + span.size - 1) as usize % fan.len();
                    let a = self.value(t.he_next(fan[span.start as usize]));
                    let b = self.value(t.he_prev(fan[last]));
                    let mask = self.crease_mask(t.valence(v));
                    // OpenSubdiv: w·v + (1 − w)·crease, the weights combined first.
                    let crease = 1.0 - corner_weight;
                    let (vertex_weight, end_weight) =
                        (crease * mask.vertex + corner_weight, crease * mask.boundary_neighbor);
                    end_weight * a + end_weight * b + vertex_weight * own
                }
            };
            out.push(value);
        }
        count as u32
    }

    /// Whether fan edge i (between faces i − 1 and i; on the boundary i ≥ 1)
    /// lies inside a span: the value at `v` is the same on both sides.
    #[inline]
    fn inside_span(&self, fan: &[HalfEdgeId], i: usize) -> bool {
        let previous = if i == 0 { fan.len() - 1 } else { i - 1 };
        self.indices[fan[i].index()] == self.indices[fan[previous].index()]
    }

    /// The spans of `v`'s values (`s.spans`: first face, size, runs, and the
    /// seams, infinitely sharp and semi-sharp edges inside) and the sharpness
    /// of the edges at `v` (`s.incident`), from `s.sibling` (`gatherValueSpans`).
    fn gather_spans(&self, v: VertexId, s: &mut Scratch) {
        let t = self.t;
        let fan = t.vertex_fan(v);
        let n = fan.len();
        let boundary = t.is_boundary_vertex(v);
        s.spans.clear();
        s.spans.resize(s.distinct.len(), Span::default());
        for i in 0..n {
            let span = &mut s.spans[s.sibling[i] as usize];
            span.size += 1;
            // A run opens where the value changes (the fan's start on the boundary).
            if (i == 0 && boundary) || !self.inside_span(fan, i) {
                span.runs += 1;
                if span.runs == 1 {
                    span.start = i as u32;
                }
            }
        }
        s.incident.clear();
        s.incident.extend(fan.iter().map(|&h| self.sharp.edge(t, t.he_edge(h))));
        if boundary {
            s.incident.push(SHARPNESS_INFINITE);
        }
        let mut first_seam = None;
        for i in (usize::from(boundary)..n).filter(|&i| self.inside_span(fan, i)) {
            let span = &mut s.spans[s.sibling[i] as usize];
            if self.seam[t.he_edge(fan[i]).index()] {
                span.seams += 1; // a seam ending further on (OpenSubdiv: the span is disjoint)
                first_seam.get_or_insert(i);
            } else if is_infinite(s.incident[i]) {
                span.infinite += 1;
            } else if is_sharp(s.incident[i]) {
                span.semi += 1;
            }
        }
        for span in &mut s.spans {
            span.seams += span.runs.saturating_sub(1); // one value in separate runs
        }
        if s.distinct.len() == 1 && !boundary {
            // A dart: the faces all around share the value; its one seam edge opens the span.
            if let Some(i) = first_seam {
                s.spans[0].start = i as u32;
                s.spans[0].seams -= 1;
            }
        }
    }

    /// The tags of `v`'s values before the step (`s.parent_tags`) and after
    /// it (`s.child_tags`, from the sharpness decayed inside the spans; the
    /// same unless a value is semi-sharp).
    fn tag_values(&self, v: VertexId, s: &mut Scratch) {
        let t = self.t;
        let fan = t.vertex_fan(v);
        let boundary = t.is_boundary_vertex(v);
        let vertex = self.sharp.vertex(t, v);
        classify(&self.rules, &s.spans, |span| span.semi, vertex, boundary, &mut s.parent_tags);
        s.child_tags.clear();
        if !s.parent_tags.iter().any(|tag| matches!(tag, Tag::SemiSharp { .. })) {
            s.child_tags.extend_from_slice(&s.parent_tags);
            return;
        }
        let method = self.sharp.method();
        for i in (usize::from(boundary)..fan.len()).filter(|&i| self.inside_span(fan, i)) {
            let p = s.incident[i];
            if is_semi_sharp(p) && !self.seam[t.he_edge(fan[i]).index()] {
                let c = method.subdivide_edge_sharpness(p, &s.incident);
                s.spans[s.sibling[i] as usize].child_semi += u32::from(is_sharp(c));
            }
        }
        classify(&self.rules, &s.spans, |span| span.child_semi, decrement(vertex), boundary, &mut s.child_tags);
    }

    /// The fractional weight of value `j`'s span (`Sdc::Crease`'s rule over
    /// the edges inside the span and the vertex's own sharpness).
    fn span_weight(&self, v: VertexId, s: &mut Scratch, j: usize) -> f64 {
        let n = self.t.vertex_face_count(v);
        let span = s.spans[j];
        let method = self.sharp.method();
        s.span_parent.clear();
        s.span_child.clear();
        for k in 1..span.size as usize {
            let p = s.incident[(span.start as usize + k) % n];
            s.span_parent.push(p);
            s.span_child.push(method.subdivide_edge_sharpness(p, &s.incident));
        }
        let vertex = self.sharp.vertex(self.t, v);
        fractional_weight(method, vertex, decrement(vertex), &s.span_parent, &s.span_child) as f64
    }
}

/// Numbers the values `at(0..n)` of a fan in order of first face, as
/// OpenSubdiv does (`FVarLevel::completeTopologyFromFaceValues`):
/// `s.distinct` the values, `s.sibling[i]` the number of face i's.
///
/// A run of faces continues its predecessor's sibling; a new run takes the
/// sibling of its value's first run — except for OpenSubdiv's shortcut while
/// two values are known: a run whose value differs from the first is taken
/// as a new value without comparing it with the second, so in a fan
/// `A B A B …` the second run of `B` is a sibling of its own, a duplicate of
/// `B` ([`repeated_second_value`]). OpenSubdiv refines that duplicate as any
/// other value (under `linear-none` the two one-face runs of `B` are smooth
/// crease values, where one disjoint span of `B` would be a corner), so the
/// shortcut is followed here for the surfaces to agree.
fn assign_siblings(n: usize, at: impl Fn(usize) -> u32, s: &mut Scratch) {
    if n <= LINEAR_SEARCH_MAX {
        assign_siblings_by_scan(n, at, s);
        return;
    }
    s.sibling.clear();
    s.distinct.clear();
    // Sort (value, face): each value's group starts at its first face; rank the groups by it.
    s.order.clear();
    s.order.extend((0..n).map(|i| (at(i), i as u32)));
    s.order.sort_unstable();
    s.groups.clear();
    let mut start = 0;
    while start < n {
        let end = start + s.order[start..].iter().take_while(|p| p.0 == s.order[start].0).count();
        s.groups.push((s.order[start].1, start as u32, end as u32));
        start = end;
    }
    s.groups.sort_unstable();
    s.sibling.resize(n, 0);
    for (k, &(_, start, end)) in s.groups.iter().enumerate() {
        s.distinct.push(s.order[start as usize].0);
        for &(_, i) in &s.order[start as usize..end as usize] {
            s.sibling[i as usize] = k as u32;
        }
    }
    if let Some(q) = repeated_second_value(n, &at) {
        // The duplicate is the third sibling: the later ones move up by one.
        s.sibling.iter_mut().filter(|k| **k >= 2).for_each(|k| *k += 1);
        let x = at(q);
        s.distinct.insert(2, x);
        for i in (q..n).take_while(|&i| at(i) == x) {
            s.sibling[i] = 2;
        }
    }
}

/// [`assign_siblings`] by a scan of the fan, searching the values known so
/// far (OpenSubdiv's loop): O(n × values), for small fans.
fn assign_siblings_by_scan(n: usize, at: impl Fn(usize) -> u32, s: &mut Scratch) {
    s.sibling.clear();
    s.distinct.clear();
    for i in 0..n {
        let x = at(i);
        let k = if i > 0 && x == at(i - 1) {
            s.sibling[i - 1]
        } else if s.distinct.len() == 2 && s.distinct[0] != x {
            // OpenSubdiv's shortcut: new, even when x is the second value.
            s.distinct.push(x);
            2
        } else if let Some(k) = s.distinct.iter().position(|&d| d == x) {
            k as u32
        } else {
            s.distinct.push(x);
            (s.distinct.len() - 1) as u32
        };
        s.sibling.push(k);
    }
}

/// The first face of the run that OpenSubdiv's shortcut (see
/// [`assign_siblings`]) numbers as a third sibling although its value is the
/// second: the first run, while two values are known, whose value is not
/// the first; `None` when that run brings a new value (or there is none).
fn repeated_second_value(n: usize, at: impl Fn(usize) -> u32) -> Option<usize> {
    let first = at(0);
    let mut second = None;
    for i in 1..n {
        let x = at(i);
        if x == at(i - 1) || x == first {
            continue;
        }
        match second {
            None => second = Some(x),
            Some(b) => return (x == b).then_some(i),
        }
    }
    None
}

/// The tags of a vertex's values from their spans (module docs, step 3;
/// `FVarLevel::completeTopologyFromFaceValues`), with `semi` the span's
/// semi-sharp edge count and `vertex` the vertex sharpness of the level.
fn classify(
    rules: &ModeRules,
    spans: &[Span],
    semi: impl Fn(&Span) -> u32,
    vertex: f32,
    boundary: bool,
    out: &mut Vec<Tag>,
) {
    out.clear();
    let count = spans.len();
    let mut all_corners = rules.linear_boundaries
        || is_infinite(vertex)
        || (rules.dependent && count > 2)
        || (rules.sharpen_darts && count == 1 && !boundary);
    let mut dependent_pair = false;
    if !all_corners && rules.dependent && count == 2 {
        all_corners = spans.iter().any(|sp| sp.infinite > 0 || sp.seams > 0)
            || (rules.both_if_one_corner && spans.iter().any(|sp| sp.size == 1));
        // Only one of the two semi-sharp: the other is sharp by dependence on it.
        dependent_pair = (semi(&spans[0]) > 0) != (semi(&spans[1]) > 0);
    }
    out.extend(spans.iter().map(|span| {
        if span.seams > 0 || all_corners || span.infinite > 0 || (span.size == 1 && rules.corners_sharp) {
            Tag::Corner
        } else if semi(span) > 0 || is_semi_sharp(vertex) {
            Tag::SemiSharp { dependent: false }
        } else if dependent_pair {
            Tag::SemiSharp { dependent: true }
        } else {
            Tag::Crease
        }
    }));
}

#[cfg(test)]
mod tests {
    use super::*;

    fn siblings_of(values: &[u32]) -> (Vec<u32>, Vec<u32>) {
        let mut s = Scratch::default();
        assign_siblings(values.len(), |i| values[i], &mut s);
        (s.sibling, s.distinct)
    }

    #[test]
    fn siblings_are_numbered_by_first_face_by_scan_and_by_sort_alike() {
        assert_eq!(siblings_of(&[7, 7, 3, 3, 7]), (vec![0, 0, 1, 1, 0], vec![7, 3]));
        // A large fan takes the sorting path and must number the same way.
        let big: Vec<u32> = (0..200).map(|i| [9, 4, 9, 1][(i / 7) % 4]).collect();
        let (sibling, distinct) = siblings_of(&big);
        assert_eq!(distinct, vec![9, 4, 1]);
        let scanned: Vec<u32> = big.iter().map(|x| distinct.iter().position(|d| d == x).unwrap() as u32).collect();
        assert_eq!(sibling, scanned);
    }

    #[test]
    fn a_repeated_second_value_is_a_sibling_of_its_own_as_in_opensubdiv() {
        // FVarLevel::completeTopologyFromFaceValues: A B A B → siblings 0 1 0 2.
        assert_eq!(siblings_of(&[5, 8, 5, 8]), (vec![0, 1, 0, 2], vec![5, 8, 8]));
        // Only while two values are known: a third value first makes the search exact.
        assert_eq!(siblings_of(&[5, 8, 3, 5, 8]), (vec![0, 1, 2, 0, 1], vec![5, 8, 3]));
        // The duplicate's run continues it; later runs of the value find its first sibling.
        assert_eq!(siblings_of(&[5, 8, 5, 8, 8, 3, 8]), (vec![0, 1, 0, 2, 2, 3, 1], vec![5, 8, 8, 3]));
        // The sorting path of large fans numbers the same way.
        let big: Vec<u32> = (0..200).map(|i| [9, 4, 9, 4, 4, 1, 4][(i / 7) % 7]).collect();
        let (sibling, distinct) = siblings_of(&big);
        assert_eq!(distinct, vec![9, 4, 4, 1]);
        let mut scanned = Scratch::default();
        assign_siblings_by_scan(big.len(), |i| big[i], &mut scanned);
        assert_eq!((sibling, distinct), (scanned.sibling, scanned.distinct));
    }

    #[test]
    fn modes_decode_as_opensubdiv() {
        use FVarInterpolation::*;
        let edge_only = BoundaryInterpolation::EdgeOnly;
        let none = ModeRules::new(LinearNone, edge_only);
        assert!(!none.corners_sharp && !none.smooth_corners_sharp && !none.sharpen_darts);
        let corners = ModeRules::new(LinearCornersOnly, edge_only);
        assert!(corners.corners_sharp && corners.smooth_corners_sharp && !corners.dependent);
        assert!(!ModeRules::new(LinearCornersOnly, BoundaryInterpolation::EdgeAndCorner).smooth_corners_sharp);
        let plus2 = ModeRules::new(LinearCornersPlus2, edge_only);
        assert!(plus2.dependent && plus2.both_if_one_corner && plus2.sharpen_darts);
        let plus1 = ModeRules::new(LinearCornersPlus1, edge_only);
        assert!(plus1.dependent && !plus1.both_if_one_corner && !plus1.sharpen_darts);
        let boundaries = ModeRules::new(LinearBoundaries, edge_only);
        assert!(boundaries.linear_boundaries && boundaries.sharpen_darts && !boundaries.linear_all);
        assert!(ModeRules::new(LinearAll, edge_only).linear_all);
    }

    #[test]
    fn classification_of_two_values_follows_the_mode() {
        let span = |size, semi| Span { size, semi, ..Span::default() };
        let tags = |mode, spans: &[Span]| {
            let mut out = Vec::new();
            classify(
                &ModeRules::new(mode, BoundaryInterpolation::EdgeAndCorner),
                spans,
                |s| s.semi,
                0.0,
                false,
                &mut out,
            );
            out
        };
        use FVarInterpolation::*;
        // A value in one face is a corner except under linear-none.
        assert_eq!(tags(LinearNone, &[span(1, 0), span(3, 0)]), [Tag::Crease, Tag::Crease]);
        assert_eq!(tags(LinearCornersOnly, &[span(1, 0), span(3, 0)]), [Tag::Corner, Tag::Crease]);
        // plus2 sharpens the partner of a corner, plus1 does not.
        assert_eq!(tags(LinearCornersPlus1, &[span(1, 0), span(3, 0)]), [Tag::Corner, Tag::Crease]);
        assert_eq!(tags(LinearCornersPlus2, &[span(1, 0), span(3, 0)]), [Tag::Corner, Tag::Corner]);
        // Three values: corners under plus1.
        assert_eq!(tags(LinearCornersOnly, &[span(2, 0), span(2, 0), span(2, 0)]), [Tag::Crease; 3]);
        assert_eq!(tags(LinearCornersPlus1, &[span(2, 0), span(2, 0), span(2, 0)]), [Tag::Corner; 3]);
        // One semi-sharp span of two: the other depends on it under plus1 only.
        let semi = [span(2, 1), span(2, 0)];
        assert_eq!(tags(LinearCornersOnly, &semi), [Tag::SemiSharp { dependent: false }, Tag::Crease]);
        assert_eq!(
            tags(LinearCornersPlus1, &semi),
            [Tag::SemiSharp { dependent: false }, Tag::SemiSharp { dependent: true }]
        );
        assert_eq!(tags(LinearBoundaries, &semi), [Tag::Corner; 2]);
    }
}
