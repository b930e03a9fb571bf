//! The sharpness of one level as the rules see it, and the rule of every
//! vertex and edge point of a step: the one place where boundaries, creases
//! and corners are decided (OpenSubdiv's `Vtr` tags and `Sdc::Crease` logic).
//!
//! A [`LevelSharpness`] holds the user's tags at that level (decayed level by
//! level with the crease method) and the boundary option. Boundary edges are
//! infinitely sharp in every boundary mode and, under `edge-and-corner`, a
//! boundary vertex in one face is an infinitely sharp corner: these are
//! derived from the topology when asked, not stored, so an untagged mesh
//! costs nothing and follows exactly the rules it always had (interior
//! vertices smooth, boundary vertices on the cubic B-spline crease, one-face
//! corners fixed).
//!
//! Everything a step needs is a function of the parent level alone: the
//! child sharpness of an edge half at vertex v is
//! `CreaseMethod::subdivide_edge_sharpness` of the parent values at v, so a
//! row can be computed before (or while) the child connectivity is built.

use crate::Options;
use std::sync::OnceLock;
use subdiv_mesh::{EdgeId, HalfEdgeId, Tags, Topology, VertexId};
use subdiv_rules::crease::{
    decrement, fractional_weight, is_infinite, is_sharp, is_smooth, vertex_rule, SHARPNESS_INFINITE,
};
use subdiv_rules::{BoundaryInterpolation, CreaseMethod, DartLimit, Rule, TriangleRule};

/// Largest valence whose incident sharpness fits the stack buffers below;
/// larger valences use a heap buffer.
const STACK_VALENCE: usize = 16;

/// Sharpness of one level: the tags at that level, the boundary option and
/// the crease method that decays them. It belongs to that level's topology:
/// every query passes the same `Topology` (a per-vertex cache is built from
/// the first one).
#[derive(Clone, Debug)]
pub struct LevelSharpness {
    /// Per edge (tag values at this level), or empty: all smooth.
    edges: Vec<f32>,
    /// Per vertex, or empty: all smooth.
    vertices: Vec<f32>,
    boundary: BoundaryInterpolation,
    method: CreaseMethod,
    /// Which limit point a dart gets (read by the limit rows only).
    dart_limit: DartLimit,
    /// Per vertex: whether a tag touches it (its own, or one of an edge at
    /// it), computed on first use from the sharp edges alone, so the rows of
    /// the many untouched vertices of a tagged level cost one lookup.
    touched: OnceLock<Vec<bool>>,
    /// √3 only: whether the next step trisects the boundary (Kobbelt's even
    /// steps, `crate::sqrt3`); false on a base level, flipped by each √3
    /// split. The one piece of level state that is not a tag.
    trisects_next: bool,
    /// Catmull-Clark's triangle rule on this level (OpenSubdiv's
    /// `TriangleSubdivision`); a refined level is [`TriangleRule::Catmark`]
    /// (the quad split leaves no triangle).
    triangle_rule: TriangleRule,
    /// Vertices in one face that `edge-and-corner` leaves on the crease rule
    /// ([`Tags::crease_copies`]), ascending; kept by the vertex points.
    crease_copies: Vec<u32>,
}

impl PartialEq for LevelSharpness {
    fn eq(&self, other: &Self) -> bool {
        (self.edges == other.edges)
            && (self.vertices == other.vertices)
            && (self.boundary == other.boundary)
            && (self.method == other.method)
            && (self.dart_limit == other.dart_limit)
            && (self.trisects_next == other.trisects_next)
            && (self.triangle_rule == other.triangle_rule)
            && (self.crease_copies == other.crease_copies)
    }
}

/// The new vertex point of an old vertex: the rule before the step
/// (`parent`), after it (`child`), and the weight of the parent mask where they
/// differ (OpenSubdiv's fractional transition).
///
/// `#[non_exhaustive]`: made by [`LevelSharpness::vertex_step`], read through
/// its public fields (a new field is not a breaking change).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct VertexStep {
    /// Rule from the sharpness before the step.
    pub parent: Rule,
    /// Rule from the sharpness after it.
    pub child: Rule,
    /// Weight of the parent mask, w·parent + (1 − w)·child, when the rules differ.
    pub parent_weight: f64,
    /// The two neighbours along the sharp edges when `parent` is a crease.
    pub parent_ends: Option<(VertexId, VertexId)>,
    /// The two neighbours along the edges still sharp after the step, when
    /// `child` is a crease.
    pub child_ends: Option<(VertexId, VertexId)>,
}

/// One vertex mask of a step: its rule, the crease ends when it is a
/// crease, and its weight in the new point.
pub type WeightedMask = (Rule, Option<(VertexId, VertexId)>, f64);

impl VertexStep {
    /// The masks that make the new vertex point: the parent's alone (weight
    /// 1) where the rule does not change, else w·parent then (1 − w)·child.
    pub fn masks(&self) -> impl Iterator<Item = WeightedMask> + use<> {
        let changes = self.parent != self.child;
        let w = if changes { self.parent_weight } else { 1.0 };
        let child = changes.then_some((self.child, self.child_ends, 1.0 - w));
        std::iter::once((self.parent, self.parent_ends, w)).chain(child)
    }
}

/// The new point of an edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EdgeStep {
    /// A smooth edge: the scheme's edge mask.
    Smooth,
    /// A sharp edge that stays sharp on both halves: the midpoint.
    Midpoint,
    /// A sharp edge whose halves do not both stay sharp: s·midpoint +
    /// (1 − s)·smooth with s the edge's sharpness, not clamped (OpenSubdiv:
    /// under Chaikin an edge with s > 1 can get here, an extrapolation).
    Blend(f64),
}

/// Sharpness of the edges at a vertex, in fan order (with a boundary vertex's
/// incoming boundary edge last), and their far ends.
struct Incident {
    sharpness: smallvec_free::Buffer<f32>,
    ends: smallvec_free::Buffer<u32>,
}

/// A tiny inline-or-heap buffer (no dependency for one use).
mod smallvec_free {
    use super::STACK_VALENCE;

    pub(super) enum Buffer<T: Copy + Default> {
        Inline([T; STACK_VALENCE], usize),
        Heap(Vec<T>),
    }

    impl<T: Copy + Default> Buffer<T> {
        pub(super) fn with_capacity(n: usize) -> Self {
            if n <= STACK_VALENCE {
                Self::Inline([T::default(); STACK_VALENCE], 0)
            } else {
                Self::Heap(Vec::with_capacity(n))
            }
        }
        pub(super) fn push(&mut self, x: T) {
            match self {
                Self::Inline(a, n) => {
                    a[*n] = x;
                    *n += 1;
                }
                Self::Heap(v) => v.push(x),
            }
        }
        pub(super) fn as_slice(&self) -> &[T] {
            match self {
                Self::Inline(a, n) => &a[..*n],
                Self::Heap(v) => v,
            }
        }
    }
}

/// How many of the incident edges are sharp.
fn sharp_count(sharpness: &[f32]) -> usize {
    sharpness.iter().filter(|&&s| is_sharp(s)).count()
}

/// The far ends of the first and last sharp incident edge (OpenSubdiv's
/// `GetSharpEdgePairOfCrease`) when `rule` is a crease.
fn crease_ends(rule: Rule, sharpness: &[f32], ends: &[u32]) -> Option<(VertexId, VertexId)> {
    if rule != Rule::Crease {
        return None;
    }
    let first = sharpness.iter().position(|&s| is_sharp(s))?;
    let last = sharpness.iter().rposition(|&s| is_sharp(s))?;
    Some((VertexId(ends[first]), VertexId(ends[last])))
}

impl LevelSharpness {
    /// The base level of a mesh with `tags` under the given options (darts
    /// with [`DartLimit::Exact`]; [`Self::with_dart_limit`] to change it).
    pub fn new(tags: &Tags, boundary: BoundaryInterpolation, method: CreaseMethod) -> Self {
        Self {
            crease_copies: tags.crease_copies().to_vec(),
            ..Self::from_values(tags.edge_values().to_vec(), tags.vertex_values().to_vec(), boundary, method)
        }
    }

    /// The base level of a mesh with `tags` under `options` (boundary
    /// option, crease method, dart limit, triangle rule).
    pub fn from_options(tags: &Tags, options: &Options) -> Self {
        Self::new(tags, options.boundary, options.crease_method)
            .with_dart_limit(options.dart_limit)
            .with_triangle_rule(options.triangle_rule)
    }

    /// With another dart limit; kept by every level refined from this one.
    pub fn with_dart_limit(self, dart_limit: DartLimit) -> Self {
        Self { dart_limit, ..self }
    }

    /// The rules of an untagged mesh with `edge-and-corner` boundaries.
    pub fn plain() -> Self {
        Self::untagged(BoundaryInterpolation::EdgeAndCorner, CreaseMethod::Uniform)
    }

    /// An untagged level (only what the boundary option implies).
    pub fn untagged(boundary: BoundaryInterpolation, method: CreaseMethod) -> Self {
        Self::from_values(Vec::new(), Vec::new(), boundary, method)
    }

    fn from_values(edges: Vec<f32>, vertices: Vec<f32>, boundary: BoundaryInterpolation, method: CreaseMethod) -> Self {
        Self {
            edges,
            vertices,
            boundary,
            method,
            dart_limit: DartLimit::default(),
            touched: OnceLock::new(),
            trisects_next: false,
            triangle_rule: TriangleRule::Catmark,
            crease_copies: Vec::new(),
        }
    }

    /// The same level with Catmull-Clark's triangle rule `rule` (the other
    /// schemes ignore it).
    pub fn with_triangle_rule(self, rule: TriangleRule) -> Self {
        Self { triangle_rule: rule, ..self }
    }

    /// Catmull-Clark's triangle rule on this level.
    pub fn triangle_rule(&self) -> TriangleRule {
        self.triangle_rule
    }

    /// Whether `v` is in a triangle whose edges take
    /// [`TriangleRule::Smooth`]'s weights on this level: the one-step limit
    /// rows (Cheng's Eq. 5) do not hold there, the limit needs a step first.
    pub fn smooth_triangle_at(&self, t: &Topology, v: VertexId) -> bool {
        self.triangle_rule == TriangleRule::Smooth && t.vertex_fan(v).iter().any(|&h| t.face_size(t.he_face(h)) == 3)
    }

    /// √3: a level with these vertex values (no edge tags) whose next step
    /// trisects the boundary or not (`crate::sqrt3`).
    pub(crate) fn sqrt3_level(
        vertices: Vec<f32>,
        boundary: BoundaryInterpolation,
        method: CreaseMethod,
        trisects_next: bool,
    ) -> Self {
        let vertices = if vertices.iter().all(|&s| is_smooth(s)) { Vec::new() } else { vertices };
        Self { trisects_next, ..Self::from_values(Vec::new(), vertices, boundary, method) }
    }

    /// √3: whether the next step trisects the boundary (an even step).
    pub(crate) fn trisects_next(&self) -> bool {
        self.trisects_next
    }

    /// Whether no edge or vertex carries a tag (boundaries may still be sharp).
    pub fn is_untagged(&self) -> bool {
        self.edges.is_empty() && self.vertices.is_empty()
    }

    /// Whether the rules are those of an untagged mesh with OpenSubdiv's
    /// `EDGE_AND_CORNER` boundary: the schemes' plain masks apply as they are.
    pub fn is_plain(&self) -> bool {
        self.is_untagged()
            && self.boundary == BoundaryInterpolation::EdgeAndCorner
            && self.triangle_rule == TriangleRule::Catmark
    }

    /// The boundary option.
    pub fn boundary(&self) -> BoundaryInterpolation {
        self.boundary
    }

    /// The crease method.
    pub fn method(&self) -> CreaseMethod {
        self.method
    }

    /// Which limit point a dart gets.
    pub fn dart_limit(&self) -> DartLimit {
        self.dart_limit
    }

    /// Sharpness of edge `e` as the rules see it: infinite on the boundary,
    /// else its tag.
    #[inline]
    pub fn edge(&self, t: &Topology, e: EdgeId) -> f32 {
        if t.is_boundary_edge(e) {
            SHARPNESS_INFINITE
        } else {
            self.edges.get(e.index()).copied().unwrap_or(0.0)
        }
    }

    /// Sharpness of vertex `v` as the rules see it: its tag, or infinite for
    /// a boundary vertex in one face under `edge-and-corner`.
    #[inline]
    pub fn vertex(&self, t: &Topology, v: VertexId) -> f32 {
        if self.boundary == BoundaryInterpolation::EdgeAndCorner
            && t.is_boundary_vertex(v)
            && t.vertex_face_count(v) == 1
            && (self.crease_copies.is_empty() || self.crease_copies.binary_search(&v.0).is_err())
        {
            SHARPNESS_INFINITE
        } else {
            self.vertices.get(v.index()).copied().unwrap_or(0.0)
        }
    }

    /// The edges at `v` and their other ends, in fan order, the incoming
    /// boundary edge last.
    fn incident(&self, t: &Topology, v: VertexId) -> Incident {
        let fan = t.vertex_fan(v);
        let boundary = t.is_boundary_vertex(v);
        let n = fan.len() + usize::from(boundary);
        let mut out = Incident {
            sharpness: smallvec_free::Buffer::with_capacity(n),
            ends: smallvec_free::Buffer::with_capacity(n),
        };
        for &h in fan {
            out.sharpness.push(self.edge(t, t.he_edge(h)));
            out.ends.push(t.he_to(h).0);
        }
        if boundary {
            let incoming: HalfEdgeId = t.he_prev(fan[fan.len() - 1]);
            out.sharpness.push(SHARPNESS_INFINITE);
            out.ends.push(t.he_from(incoming).0);
        }
        out
    }

    /// Whether no tag touches `v`: its own sharpness and that of every edge
    /// at it are 0 (boundary edges aside, which are sharp by topology). Then
    /// its rule is the untagged one and stays so in the step. One lookup in
    /// a bitmap built once per level: most vertices of a tagged mesh are like this.
    #[inline]
    pub fn untouched(&self, t: &Topology, v: VertexId) -> bool {
        if self.is_untagged() {
            return true;
        }
        let touched = self.touched.get_or_init(|| {
            let mut touched: Vec<bool> =
                (0..t.vertex_count()).map(|v| self.vertices.get(v).is_some_and(|&s| s > 0.0)).collect();
            for (e, _) in self.edges.iter().enumerate().filter(|&(_, &s)| s > 0.0) {
                let (a, b) = t.edge_vertices(EdgeId(e as u32));
                touched[a.index()] = true;
                touched[b.index()] = true;
            }
            touched
        });
        !touched[v.index()]
    }

    /// The rule of an untouched vertex ([`Self::untouched`]), the same before
    /// and after the step: smooth inside, the boundary crease, or a corner.
    fn untagged_rule(&self, t: &Topology, v: VertexId) -> (Rule, Option<(VertexId, VertexId)>) {
        if !t.is_boundary_vertex(v) {
            (Rule::Smooth, None)
        } else if self.vertex(t, v) > 0.0 {
            (Rule::Corner, None)
        } else {
            // The two boundary edges: the next neighbour along the outgoing
            // one first, as the general path orders them.
            let (prev, next) = t.boundary_neighbors(v).expect("a boundary vertex");
            (Rule::Crease, Some((next, prev)))
        }
    }

    /// The rule of the new vertex point of old vertex `v`.
    pub fn vertex_step(&self, t: &Topology, v: VertexId) -> VertexStep {
        if self.untouched(t, v) {
            let (rule, ends) = self.untagged_rule(t, v);
            return VertexStep { parent: rule, child: rule, parent_weight: 0.0, parent_ends: ends, child_ends: ends };
        }
        let vertex = self.vertex(t, v);
        let incident = self.incident(t, v);
        let sharp = incident.sharpness.as_slice();
        let ends = incident.ends.as_slice();
        let mut child = smallvec_free::Buffer::with_capacity(sharp.len());
        for &s in sharp {
            child.push(self.method.subdivide_edge_sharpness(s, sharp));
        }
        let child = child.as_slice();
        let child_vertex = decrement(vertex);
        let parent_rule = vertex_rule(vertex, sharp_count(sharp));
        let child_rule = vertex_rule(child_vertex, sharp_count(child));
        let parent_weight = if parent_rule == child_rule || parent_rule.is_smooth_mask() {
            0.0
        } else {
            fractional_weight(self.method, vertex, child_vertex, sharp, child) as f64
        };
        VertexStep {
            parent: parent_rule,
            child: child_rule,
            parent_weight,
            parent_ends: crease_ends(parent_rule, sharp, ends),
            child_ends: crease_ends(child_rule, child, ends),
        }
    }

    /// The rule of vertex `v` at this level, for its limit point
    /// (OpenSubdiv's `Limit` takes it from the sharpness left, so a limit is
    /// exact only where no semi-sharp value remains), with the crease ends.
    pub fn limit_rule(&self, t: &Topology, v: VertexId) -> (Rule, Option<(VertexId, VertexId)>) {
        if self.untouched(t, v) {
            return self.untagged_rule(t, v);
        }
        let incident = self.incident(t, v);
        let sharp = incident.sharpness.as_slice();
        let rule = vertex_rule(self.vertex(t, v), sharp_count(sharp));
        (rule, crease_ends(rule, sharp, incident.ends.as_slice()))
    }

    /// Where `v`'s limit is the exact dart limit
    /// ([`subdiv_rules::catmull_clark::dart_limit_mask`],
    /// [`subdiv_rules::loop_scheme::dart_limit_mask`]): the position in
    /// `v`'s fan of its one sharp edge when `v` is a dart ([`Self::limit_rule`])
    /// whose edge is infinitely sharp and the dart limit is
    /// [`DartLimit::Exact`]; `None` otherwise (a dart whose edge is still
    /// semi-sharp changes its rule on the way: it keeps the smooth mask).
    pub fn exact_dart_edge(&self, t: &Topology, v: VertexId) -> Option<usize> {
        if self.dart_limit != DartLimit::Exact || self.untouched(t, v) || t.is_boundary_vertex(v) {
            return None; // a boundary vertex has two sharp edges at least: never a dart
        }
        if self.limit_rule(t, v).0 != Rule::Dart {
            return None;
        }
        let fan = t.vertex_fan(v);
        let at = fan.iter().position(|&h| is_sharp(self.edge(t, t.he_edge(h))))?;
        is_infinite(self.edge(t, t.he_edge(fan[at]))).then_some(at)
    }

    /// Sharpness of the half of edge `e` at its end `v` after the step.
    fn child_half(&self, t: &Topology, e: EdgeId, v: VertexId) -> f32 {
        let s = self.edge(t, e);
        if self.method == CreaseMethod::Uniform || is_smooth(s) || s >= SHARPNESS_INFINITE {
            return decrement(s);
        }
        let incident = self.incident(t, v);
        self.method.subdivide_edge_sharpness(s, incident.sharpness.as_slice())
    }

    /// The rule of the new point of edge `e`.
    pub fn edge_step(&self, t: &Topology, e: EdgeId) -> EdgeStep {
        let s = self.edge(t, e);
        if is_smooth(s) {
            return EdgeStep::Smooth;
        }
        let (a, b) = t.edge_vertices(e);
        if is_sharp(self.child_half(t, e, a)) && is_sharp(self.child_half(t, e, b)) {
            EdgeStep::Midpoint
        } else {
            EdgeStep::Blend(s as f64)
        }
    }

    /// The sharpness of the next level, on `child` = the primal split of
    /// `parent` where the half of parent half-edge h's edge at from(h) is the
    /// child half-edge `child_half_edge(h)` (quad split: 4h; triangle split:
    /// 3(4f + k) for h = 3f + k). Edges inside a parent face are smooth;
    /// vertex sharpness decays on the old vertices (numbered first).
    pub(crate) fn refine(
        &self,
        parent: &Topology,
        child: &Topology,
        child_half_edge: impl Fn(usize) -> usize,
    ) -> LevelSharpness {
        // Only the sharp interior edges have sharp children: their two halves.
        let mut edges = Vec::new();
        for (e, &s) in self.edges.iter().enumerate() {
            let e = EdgeId(e as u32);
            if is_smooth(s) || parent.is_boundary_edge(e) {
                continue; // boundary edges are sharp by topology at every level
            }
            let h = parent.edge_half_edge(e);
            let g = parent.he_twin(h).expect("an interior edge has two half-edges");
            for x in [h, g] {
                let half = self.child_half(parent, e, parent.he_from(x));
                if is_sharp(half) {
                    if edges.is_empty() {
                        edges = vec![0.0f32; child.edge_count()];
                    }
                    edges[child.he_edge(HalfEdgeId(child_half_edge(x.index()) as u32)).index()] = half;
                }
            }
        }
        let vertices = if self.vertices.is_empty() {
            Vec::new()
        } else {
            let mut vertices = vec![0.0f32; child.vertex_count()];
            for (c, &p) in vertices.iter_mut().zip(&self.vertices) {
                *c = decrement(p);
            }
            vertices
        };
        let compact = |v: Vec<f32>| if v.iter().all(|&s| is_smooth(s)) { Vec::new() } else { v };
        // Old vertices keep their numbers: the crease copies stay what they are.
        LevelSharpness {
            crease_copies: self.crease_copies.clone(),
            ..Self::from_values(edges, compact(vertices), self.boundary, self.method)
        }
        .with_dart_limit(self.dart_limit)
    }

    /// The tags of this level as a user sees them (what a file stores):
    /// the tag values, without what the boundary option implies.
    pub fn tags(&self, t: &Topology) -> Tags {
        self.clone().into_tags(t)
    }

    /// [`Self::tags`], moving the values instead of copying them.
    pub fn into_tags(self, t: &Topology) -> Tags {
        Tags::from_arrays(t, self.edges, self.vertices)
            .expect("decayed tags keep their lengths and stay ≥ 0")
            .with_crease_copies(self.crease_copies)
    }

    /// The largest semi-sharp value left (edges of the interior and
    /// vertices), if any: a limit needs ⌈that⌉ more levels.
    pub fn largest_semi_sharp(&self, t: &Topology) -> Option<f32> {
        let edges =
            (self.edges.iter().enumerate()).filter(|(e, _)| !t.is_boundary_edge(EdgeId(*e as u32))).map(|(_, &s)| s);
        edges
            .chain(self.vertices.iter().copied())
            .filter(|&s| s > 0.0 && s < SHARPNESS_INFINITE)
            .fold(None, |m: Option<f32>, s| Some(m.map_or(s, |m| m.max(s))))
    }
}
