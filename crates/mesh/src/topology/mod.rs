//! Validated half-edge connectivity of a polygon mesh.
//!
//! Half-edge `h` is corner `k` of face `f`, directed from that corner's vertex
//! to the next corner's; half-edges of a face are numbered contiguously, so a
//! half-edge id is the corner's position in [`FaceList::indices`] and `next`,
//! `prev`, `from` and `to` need no storage. Stored per half-edge: its face, its
//! twin and its undirected edge. Stored per vertex: its outgoing half-edges in
//! cyclic order (a CSR "fan"), which is exactly the neighbourhood of the
//! papers' Fig. 2: faces f₀…f_{k−1} around V where face fᵢ = (V, Eᵢ, …, Eᵢ₊₁).
//!
//! What can be derived is not stored: the face of a half-edge is `h / m`
//! when every face has m corners (a table only for mixed faces), and the
//! undirected edge numbering (edge of every half-edge, a half-edge of every
//! edge) is built from the twins at the first query that needs it, so that
//! a caller who only counts (`subdiv info`) never pays for it.
//!
//! Construction and its checks live in `validate`, the three refinements
//! built by index arithmetic (quad, triangle and dual split) in `refine`;
//! this module holds the type and its queries.

mod diagonals;
mod refine;
mod validate;

pub(crate) use refine::{SharpDualSplit, SharpPointIds};

use crate::ids::{EdgeId, FaceId, HalfEdgeId, VertexId};
use crate::soup::FaceList;
use std::collections::BTreeMap;
use std::sync::OnceLock;

/// Marker for "no half-edge" (boundary twin).
const NONE: u32 = u32::MAX;

/// A face corner: face `face`, position `index` in that face's vertex list.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Corner {
    /// The face.
    pub face: FaceId,
    /// 0-based position of the corner in the face.
    pub index: u32,
}

/// Validated connectivity: every edge has one or two faces, two faces traverse a
/// shared edge in opposite directions, and the faces around every vertex form a
/// single fan. Isolated vertices (in no face) are allowed and have valence 0.
///
/// `Debug` prints what the queries see, not how it is stored (the face of
/// every half-edge, the edge numbering): two topologies with the same
/// connectivity print the same.
#[derive(Clone)]
pub struct Topology {
    vertex_count: u32,
    faces: FaceList,
    he_face: HalfEdgeFaces,
    he_twin: Vec<u32>,
    edges: OnceLock<EdgeNumbering>,
    /// The faces with a diagonal conflict (`diagonals`): from the
    /// construction for an all-quad mesh, else at the first query.
    diagonal_conflicts: OnceLock<Vec<u32>>,
    fan_offsets: Vec<u32>,
    fan: Vec<HalfEdgeId>,
    vertex_on_boundary: Vec<bool>,
    loop_offsets: Vec<u32>,
    loop_he: Vec<HalfEdgeId>,
    face_component: Vec<u32>,
    component_count: u32,
}

impl std::fmt::Debug for Topology {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let he_face: Vec<u32> = (0..self.half_edge_count()).map(|h| self.he_face.get(h)).collect();
        let edges = self.edge_numbering();
        f.debug_struct("Topology")
            .field("vertex_count", &self.vertex_count)
            .field("faces", &self.faces)
            .field("he_face", &he_face)
            .field("he_twin", &self.he_twin)
            .field("he_edge", &edges.he_edge)
            .field("edge_he", &edges.edge_he)
            .field("fan_offsets", &self.fan_offsets)
            .field("fan", &self.fan)
            .field("vertex_on_boundary", &self.vertex_on_boundary)
            .field("loop_offsets", &self.loop_offsets)
            .field("loop_he", &self.loop_he)
            .field("face_component", &self.face_component)
            .field("component_count", &self.component_count)
            .finish()
    }
}

impl Topology {
    // ---- sizes -------------------------------------------------------------

    /// Number of vertices, isolated ones included.
    pub fn vertex_count(&self) -> usize {
        self.vertex_count as usize
    }
    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }
    /// Number of undirected edges.
    pub fn edge_count(&self) -> usize {
        // One per twin pair, one per boundary half-edge (each in one loop).
        (self.half_edge_count() + self.loop_he.len()) / 2
    }
    /// Number of edges with a single face.
    pub fn boundary_edge_count(&self) -> usize {
        self.loop_he.len()
    }
    /// Number of half-edges (= face corners).
    pub fn half_edge_count(&self) -> usize {
        self.he_twin.len()
    }
    /// All vertex ids.
    pub fn vertices(&self) -> impl ExactSizeIterator<Item = VertexId> + use<> {
        (0..self.vertex_count).map(VertexId)
    }
    /// All face ids.
    pub fn face_ids(&self) -> impl ExactSizeIterator<Item = FaceId> + use<> {
        (0..self.faces.len() as u32).map(FaceId)
    }
    /// All edge ids.
    pub fn edges(&self) -> impl ExactSizeIterator<Item = EdgeId> + use<> {
        (0..self.edge_count() as u32).map(EdgeId)
    }

    // ---- faces -------------------------------------------------------------

    /// The face list (CSR).
    pub fn faces(&self) -> &FaceList {
        &self.faces
    }
    /// The face list, giving up the rest.
    pub(crate) fn into_faces(self) -> FaceList {
        self.faces
    }
    /// Vertex indices of face `f`, in order.
    #[inline]
    pub fn face(&self, f: FaceId) -> &[u32] {
        self.faces.face(f.index())
    }
    /// Number of corners of face `f`.
    #[inline]
    pub fn face_size(&self, f: FaceId) -> usize {
        self.faces.face_size(f.index())
    }
    /// The half-edges of face `f` (corner `k` → corner `k + 1`), in order.
    pub fn face_half_edges(&self, f: FaceId) -> impl ExactSizeIterator<Item = HalfEdgeId> + use<> {
        let o = self.faces.offsets();
        (o[f.index()]..o[f.index() + 1]).map(HalfEdgeId)
    }
    /// The half-edges `start..end` of the face of half-edge `h`: arithmetic
    /// when every face has the same size, from the offsets otherwise.
    #[inline]
    pub(crate) fn he_face_half_edges(&self, h: HalfEdgeId) -> (usize, usize) {
        self.he_face.face_half_edges(self.faces.offsets(), h.index())
    }
    /// The connected component (0-based) that face `f` belongs to.
    pub fn face_component(&self, f: FaceId) -> u32 {
        self.face_component[f.index()]
    }

    // ---- half-edges --------------------------------------------------------

    /// The face a half-edge belongs to.
    #[inline]
    pub fn he_face(&self, h: HalfEdgeId) -> FaceId {
        FaceId(self.he_face.get(h.index()))
    }
    /// The corner a half-edge starts at.
    #[inline]
    pub fn he_corner(&self, h: HalfEdgeId) -> Corner {
        let (start, _) = self.he_face_half_edges(h);
        Corner { face: self.he_face(h), index: h.0 - start as u32 }
    }
    /// Start vertex.
    #[inline]
    pub fn he_from(&self, h: HalfEdgeId) -> VertexId {
        VertexId(self.faces.indices()[h.index()])
    }
    /// End vertex.
    #[inline]
    pub fn he_to(&self, h: HalfEdgeId) -> VertexId {
        self.he_from(self.he_next(h))
    }
    /// Next half-edge in the same face.
    #[inline]
    pub fn he_next(&self, h: HalfEdgeId) -> HalfEdgeId {
        HalfEdgeId(self.he_face.next(self.faces.offsets(), h.index()) as u32)
    }
    /// Previous half-edge in the same face.
    #[inline]
    pub fn he_prev(&self, h: HalfEdgeId) -> HalfEdgeId {
        HalfEdgeId(self.he_face.prev(self.faces.offsets(), h.index()) as u32)
    }
    /// The opposite half-edge, or `None` on the boundary.
    #[inline]
    pub fn he_twin(&self, h: HalfEdgeId) -> Option<HalfEdgeId> {
        let t = self.he_twin[h.index()];
        (t != NONE).then_some(HalfEdgeId(t))
    }
    /// The undirected edge of a half-edge.
    #[inline]
    pub fn he_edge(&self, h: HalfEdgeId) -> EdgeId {
        EdgeId(self.edge_numbering().he_edge[h.index()])
    }

    // ---- edges -------------------------------------------------------------

    /// A half-edge of edge `e`; for a boundary edge, its only one.
    #[inline]
    pub fn edge_half_edge(&self, e: EdgeId) -> HalfEdgeId {
        HalfEdgeId(self.edge_numbering().edge_he[e.index()])
    }
    /// The two end vertices of edge `e` (in the direction of [`Self::edge_half_edge`]).
    pub fn edge_vertices(&self, e: EdgeId) -> (VertexId, VertexId) {
        let h = self.edge_half_edge(e);
        (self.he_from(h), self.he_to(h))
    }
    /// The one or two faces of edge `e`.
    pub fn edge_faces(&self, e: EdgeId) -> (FaceId, Option<FaceId>) {
        let h = self.edge_half_edge(e);
        (self.he_face(h), self.he_twin(h).map(|t| self.he_face(t)))
    }
    /// True when edge `e` has a single face.
    pub fn is_boundary_edge(&self, e: EdgeId) -> bool {
        self.he_twin[self.edge_numbering().edge_he[e.index()] as usize] == NONE
    }

    /// The undirected edge numbering, built from the twins at the first call.
    #[inline]
    fn edge_numbering(&self) -> &EdgeNumbering {
        self.edges.get_or_init(|| EdgeNumbering::from_twins(&self.he_twin))
    }

    // ---- vertices ----------------------------------------------------------

    /// The edge between `a` and `b`, if they share one (O(valence of a and b)).
    pub fn find_edge(&self, a: VertexId, b: VertexId) -> Option<EdgeId> {
        let from = |x: VertexId, y: VertexId| self.vertex_fan(x).iter().find(|&&h| self.he_to(h) == y).copied();
        from(a, b).or_else(|| from(b, a)).map(|h| self.he_edge(h))
    }

    /// Outgoing half-edges of `v` in cyclic order: the i-th one, V→Eᵢ, lies in
    /// face fᵢ = (V, Eᵢ, …, Eᵢ₊₁). On the boundary the first one is the
    /// boundary half-edge, and the fan is open. Empty for isolated vertices.
    #[inline]
    pub fn vertex_fan(&self, v: VertexId) -> &[HalfEdgeId] {
        &self.fan[self.fan_offsets[v.index()] as usize..self.fan_offsets[v.index() + 1] as usize]
    }
    /// The corners of `v`: its faces in cyclic order with its position in each.
    #[inline]
    pub fn vertex_corners(&self, v: VertexId) -> impl ExactSizeIterator<Item = Corner> + '_ {
        self.vertex_fan(v).iter().map(|&h| self.he_corner(h))
    }
    /// Number of faces around `v`.
    #[inline]
    pub fn vertex_face_count(&self, v: VertexId) -> usize {
        (self.fan_offsets[v.index() + 1] - self.fan_offsets[v.index()]) as usize
    }
    /// Valence: number of edges at `v` (faces + 1 on the boundary).
    #[inline]
    pub fn valence(&self, v: VertexId) -> usize {
        self.vertex_face_count(v) + usize::from(self.vertex_on_boundary[v.index()])
    }
    /// True when `v` lies on the boundary.
    #[inline]
    pub fn is_boundary_vertex(&self, v: VertexId) -> bool {
        self.vertex_on_boundary[v.index()]
    }
    /// True when no face uses `v`.
    #[inline]
    pub fn is_isolated(&self, v: VertexId) -> bool {
        self.vertex_face_count(v) == 0
    }
    /// Edge neighbours E₀…E_{n−1} of `v` in cyclic order (E_i = end of the i-th
    /// fan half-edge); on the boundary, the closing neighbour E_n last, so the
    /// first and last are the two boundary neighbours.
    #[inline]
    pub fn vertex_neighbors(&self, v: VertexId) -> impl Iterator<Item = VertexId> + '_ {
        let fan = self.vertex_fan(v);
        let closing = (self.is_boundary_vertex(v)).then(|| self.he_from(self.he_prev(fan[fan.len() - 1])));
        fan.iter().map(|&h| self.he_to(h)).chain(closing)
    }
    /// The two boundary neighbours (previous, next along the boundary loop) of a boundary vertex.
    #[inline]
    pub fn boundary_neighbors(&self, v: VertexId) -> Option<(VertexId, VertexId)> {
        if !self.is_boundary_vertex(v) {
            return None;
        }
        let fan = self.vertex_fan(v);
        let next = self.he_to(fan[0]);
        let prev = self.he_from(self.he_prev(fan[fan.len() - 1]));
        Some((prev, next))
    }

    // ---- global ------------------------------------------------------------

    /// True when the mesh has no boundary edge.
    pub fn is_closed(&self) -> bool {
        self.loop_he.is_empty()
    }
    /// Number of boundary loops.
    pub fn boundary_loop_count(&self) -> usize {
        self.loop_offsets.len() - 1
    }
    /// The boundary loops, each as its boundary half-edges in order.
    pub fn boundary_loops(&self) -> impl ExactSizeIterator<Item = &[HalfEdgeId]> + '_ {
        self.loop_offsets.windows(2).map(|w| &self.loop_he[w[0] as usize..w[1] as usize])
    }
    /// Number of connected components (isolated vertices not counted).
    pub fn component_count(&self) -> usize {
        self.component_count as usize
    }
    /// Number of vertices used by at least one face.
    pub fn referenced_vertex_count(&self) -> usize {
        self.vertices().filter(|&v| !self.is_isolated(v)).count()
    }
    /// Euler characteristic V − E + F over the vertices faces use.
    pub fn euler_characteristic(&self) -> i64 {
        self.referenced_vertex_count() as i64 - self.edge_count() as i64 + self.face_count() as i64
    }
    /// Genus summed over components, from χ_c = 2 − 2g_c − b_c per component
    /// (b_c its boundary loops). `None` if some component gives a non-integral
    /// or negative genus (impossible for a valid oriented manifold).
    pub fn genus(&self) -> Option<u32> {
        let nc = self.component_count();
        if nc == 1 {
            // χ + b of the one component, without looking up components.
            let two_g = 2 - (self.euler_characteristic() + self.boundary_loop_count() as i64);
            return (two_g >= 0 && two_g % 2 == 0).then_some((two_g / 2) as u32);
        }
        let mut chi = vec![0i64; nc];
        for v in self.vertices() {
            if let Some(&h) = self.vertex_fan(v).first() {
                chi[self.face_component(self.he_face(h)) as usize] += 1;
            }
        }
        // One edge per twin pair (at its smaller half-edge) and per boundary half-edge.
        for (h, &t) in self.he_twin.iter().enumerate() {
            if t == NONE || (h as u32) < t {
                chi[self.face_component(self.he_face(HalfEdgeId(h as u32))) as usize] -= 1;
            }
        }
        for f in self.face_ids() {
            chi[self.face_component(f) as usize] += 1;
        }
        for lp in self.boundary_loops() {
            chi[self.face_component(self.he_face(lp[0])) as usize] += 1; // χ + b
        }
        let mut genus = 0u32;
        for c in chi {
            let two_g = 2 - c;
            if two_g < 0 || two_g % 2 != 0 {
                return None;
            }
            genus += (two_g / 2) as u32;
        }
        Some(genus)
    }
    /// Histogram valence → number of vertices (isolated vertices under 0).
    pub fn valence_histogram(&self) -> BTreeMap<usize, usize> {
        histogram(self.vertex_count(), |v| self.valence(VertexId(v as u32)))
    }
}

/// Histogram value → count of `value(i)` over `0..n`, counted across
/// threads (sums: the same whatever the split). Values below 64 are
/// counted in an array, the rare others in a map.
pub(crate) fn histogram(n: usize, value: impl Fn(usize) -> usize + Sync) -> BTreeMap<usize, usize> {
    use rayon::prelude::*;
    const DENSE: usize = 64;
    type Counts = ([usize; DENSE], BTreeMap<usize, usize>);
    let add = |(mut dense, mut sparse): Counts, (other_dense, other_sparse): Counts| {
        dense.iter_mut().zip(other_dense).for_each(|(a, b)| *a += b);
        for (k, c) in other_sparse {
            *sparse.entry(k).or_insert(0) += c;
        }
        (dense, sparse)
    };
    const BLOCK: usize = 1 << 16;
    let (dense, mut sparse) = (0..n.div_ceil(BLOCK))
        .into_par_iter()
        .map(|block| {
            let (mut dense, mut sparse): Counts = ([0usize; DENSE], BTreeMap::new());
            for i in block * BLOCK..((block + 1) * BLOCK).min(n) {
                match value(i) {
                    k if k < DENSE => dense[k] += 1,
                    k => *sparse.entry(k).or_insert(0) += 1,
                }
            }
            (dense, sparse)
        })
        .reduce(|| ([0usize; DENSE], BTreeMap::new()), add);
    sparse.extend(dense.iter().enumerate().filter(|&(_, &c)| c > 0).map(|(k, &c)| (k, c)));
    sparse
}

/// The face of every half-edge: `h / m` when every face has m corners,
/// else looked up in a table (one entry per half-edge).
#[derive(Clone, Debug, PartialEq, Eq)]
enum HalfEdgeFaces {
    /// Every face has this many corners.
    Uniform(u32),
    /// The face of every half-edge.
    Table(Vec<u32>),
}

impl HalfEdgeFaces {
    /// The face of half-edge `h`.
    #[inline]
    fn get(&self, h: usize) -> u32 {
        // Division by a constant for the usual sizes, not a `div` instruction.
        match self {
            HalfEdgeFaces::Uniform(4) => (h / 4) as u32,
            HalfEdgeFaces::Uniform(3) => (h / 3) as u32,
            HalfEdgeFaces::Uniform(m) => (h / *m as usize) as u32,
            HalfEdgeFaces::Table(table) => table[h],
        }
    }

    /// The half-edges `start..end` of the face of half-edge `h`; `offsets`
    /// are the face list's (read only for mixed faces: for uniform ones the
    /// range is arithmetic, no load from a face-sized array).
    #[inline]
    fn face_half_edges(&self, offsets: &[u32], h: usize) -> (usize, usize) {
        match self {
            HalfEdgeFaces::Uniform(4) => (h / 4 * 4, h / 4 * 4 + 4),
            HalfEdgeFaces::Uniform(3) => (h / 3 * 3, h / 3 * 3 + 3),
            HalfEdgeFaces::Uniform(m) => {
                let m = *m as usize;
                (h / m * m, h / m * m + m)
            }
            HalfEdgeFaces::Table(table) => {
                let f = table[h] as usize;
                (offsets[f] as usize, offsets[f + 1] as usize)
            }
        }
    }

    /// The next half-edge in `h`'s face (see [`Self::face_half_edges`]).
    #[inline]
    fn next(&self, offsets: &[u32], h: usize) -> usize {
        let (start, end) = self.face_half_edges(offsets, h);
        if h + 1 == end {
            start
        } else {
            h + 1
        }
    }

    /// The previous half-edge in `h`'s face (see [`Self::face_half_edges`]).
    #[inline]
    fn prev(&self, offsets: &[u32], h: usize) -> usize {
        let (start, end) = self.face_half_edges(offsets, h);
        if h == start {
            end - 1
        } else {
            h - 1
        }
    }
}

/// Undirected edges from twins, in half-edge order: one per twin pair (at
/// its smaller half-edge), one per boundary half-edge.
#[derive(Clone, Debug, PartialEq, Eq)]
struct EdgeNumbering {
    /// The edge of every half-edge.
    he_edge: Vec<u32>,
    /// A half-edge of every edge: its smaller one (its only one on the boundary).
    edge_he: Vec<u32>,
}

impl EdgeNumbering {
    #[cold]
    fn from_twins(he_twin: &[u32]) -> Self {
        let mut he_edge = vec![NONE; he_twin.len()];
        let mut edge_he = Vec::with_capacity(he_twin.len() / 2 + 1);
        for (h, &t) in he_twin.iter().enumerate() {
            if t == NONE || (h as u32) < t {
                he_edge[h] = edge_he.len() as u32;
                if t != NONE {
                    he_edge[t as usize] = edge_he.len() as u32;
                }
                edge_he.push(h as u32);
            }
        }
        Self { he_edge, edge_he }
    }
}
