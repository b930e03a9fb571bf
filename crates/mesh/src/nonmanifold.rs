//! Non-manifold meshes as OpenSubdiv's `Vtr` refines them, through a
//! manifold cover.
//!
//! OpenSubdiv (`Vtr::Level::completeTopologyFromFaceVertices` and
//! `Far::TopologyRefinerFactory`'s sharpening) makes every non-manifold edge
//! (three or more faces, two faces traversing it the same way, a degenerate
//! edge from a vertex repeated in a row, an edge a face uses twice) an
//! infinitely sharp crease, and every non-manifold vertex (an end of such an
//! edge, or a vertex joining separate fans) an infinitely sharp corner —
//! except a vertex inside an interior non-manifold crease (exactly two
//! non-manifold edges, no boundary edge, more faces than edges), which
//! follows the crease rule. Across an infinitely sharp edge the rules of one
//! side never read the other: a non-manifold mesh is its manifold pieces
//! ("sheets") refined side by side, with those edges as their boundaries.
//!
//! So a non-manifold face list is refined here as its **manifold cover**:
//! the same faces, corner for corner, whose vertices are split into one copy
//! per fan of faces that stay connected through manifold edges (the first
//! copy keeps the vertex's index, further copies are appended); the
//! non-manifold edges are boundaries of the cover, and the sharpened
//! vertices get an infinitely sharp corner tag on every copy. The cover is
//! an ordinary [`crate::Topology`], so every scheme, limit mask and method
//! runs on it unchanged. [`Welds`] remembers which cover vertices (and, for
//! the next level's edge points, which cover edges) are one element of the
//! input, so that a refined cover is welded back into OpenSubdiv's refined
//! non-manifold mesh (one edge point per non-manifold edge, however many
//! faces share it), and writers write the input's vertices, not the copies.

use crate::error::MeshError;
use crate::ids::{HalfEdgeId, VertexId};
use crate::soup::FaceList;
use crate::tags::{EdgeTag, TagList, VertexTag, SHARPNESS_INFINITE};
use crate::topology::Topology;
use std::collections::HashMap;

/// Which elements of a manifold cover are one element of the non-manifold
/// mesh it covers: a class per cover vertex and per cover half-edge.
///
/// Classes of vertices are the non-manifold mesh's vertex indices. Classes of
/// half-edges are its edges as OpenSubdiv numbers them (two half-edges of a
/// manifold edge, or the `k` boundary half-edges of a non-manifold edge of
/// `k` faces, share a class; a degenerate edge or a second use of an edge by
/// the same face is an edge of its own).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Welds {
    /// Per cover vertex: a welded vertex (the one of its first corner). A
    /// cover vertex stands for two welded vertices only where OpenSubdiv
    /// keeps two coincident ones (two degenerate edges of two faces that the
    /// cover joins): the corners tell them apart.
    vertex_class: Vec<u32>,
    /// Per cover corner (half-edge): the welded vertex it uses.
    corner_class: Vec<u32>,
    /// Per welded vertex: a cover vertex standing for it.
    member: Vec<u32>,
    /// Per cover half-edge: the edge of the welded mesh.
    edge_class: Vec<u32>,
    /// Per welded edge: its ends (welded vertices) in the direction of its
    /// first half-edge, which tells the two halves of the edge apart at the
    /// next level.
    edge_ends: Vec<[u32; 2]>,
    /// Per welded edge of an input: whether it is non-manifold (infinitely
    /// sharp); empty on a refined cover, whose tags carry the sharpness.
    edge_non_manifold: Vec<bool>,
    /// Welded vertices whose corner tag the non-manifold rule added (not the
    /// user): left out of written tags, since a reader derives them again.
    sharpened: Vec<u32>,
    /// What is non-manifold in the input (the cover of an input only; a
    /// refined cover has `None`).
    report: Option<Box<NonManifoldReport>>,
    /// Cover vertices in one face that keep the crease rule
    /// ([`crate::Tags::crease_copies`]); on the cover of an input only.
    crease_copies: Vec<u32>,
    /// Per vertex inside an interior non-manifold crease, the far ends of its
    /// two crease edges (for [`Welds::check_creases`]); on the cover of an input only.
    crease_ends: Vec<(u32, [u32; 2])>,
}

/// What [`manifold_cover`] found and built.
pub(crate) struct Cover {
    /// The cover's face list: the input's faces, vertices replaced by copies.
    pub faces: FaceList,
    /// Number of cover vertices (input vertices, then the extra copies).
    pub vertex_count: usize,
    /// The welds of the cover onto the input.
    pub welds: Welds,
}

/// The non-manifold features of a mesh, as `subdiv info` reports them.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct NonManifoldReport {
    /// Non-manifold edges (their ends, in the input's indices), in
    /// OpenSubdiv's edge order.
    pub edges: Vec<[u32; 2]>,
    /// Non-manifold vertices, ascending.
    pub vertices: Vec<u32>,
    /// The non-manifold vertices sharpened to infinitely sharp corners (the
    /// others lie inside an interior non-manifold crease), ascending.
    pub corners: Vec<u32>,
    /// Extra vertex copies the cover needed (copies beyond the first, over
    /// all vertices).
    pub copies: usize,
}

/// OpenSubdiv's edges of a face list: per corner (half-edge) its edge, per
/// edge its ends as created, its number of uses and whether it is
/// non-manifold — `Vtr::Level::completeTopologyFromFaceVertices`, step for
/// step (a degenerate edge and a second use by the same face are new edges).
struct OsdEdges {
    of_corner: Vec<u32>,
    ends: Vec<[u32; 2]>,
    uses: Vec<u32>,
    non_manifold: Vec<bool>,
}

fn osd_edges(faces: &FaceList) -> OsdEdges {
    let mut edges = OsdEdges {
        of_corner: Vec::with_capacity(faces.corner_count()),
        ends: Vec::new(),
        uses: Vec::new(),
        non_manifold: Vec::new(),
    };
    // Edges by their (sorted) ends, in creation order: OpenSubdiv's
    // `findEdge` returns the first edge of v0 that reaches v1.
    let mut by_ends: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
    // The last face that used each edge.
    let mut last_face: Vec<u32> = Vec::new();
    for (f, face) in faces.iter().enumerate() {
        let f = f as u32;
        for (i, &v0) in face.iter().enumerate() {
            let v1 = face[(i + 1) % face.len()];
            let mut found = None;
            if v0 != v1 {
                if let Some(&e) = by_ends.get(&(v0.min(v1), v0.max(v1))).and_then(|list| list.first()) {
                    let e_ = e as usize;
                    if last_face[e_] == f {
                        // The face uses this edge again: a new instance.
                        edges.non_manifold[e_] = true;
                    } else {
                        if edges.uses[e_] > 1 || edges.ends[e_][0] == v0 {
                            edges.non_manifold[e_] = true;
                        }
                        found = Some(e);
                    }
                }
            }
            let e = match found {
                Some(e) => e,
                None => {
                    let e = edges.ends.len() as u32;
                    edges.ends.push([v0, v1]);
                    edges.uses.push(0);
                    // A degenerate edge, or the second instance of an edge in one face.
                    let repeated = v0 == v1 || by_ends.contains_key(&(v0.min(v1), v0.max(v1)));
                    edges.non_manifold.push(repeated);
                    last_face.push(u32::MAX);
                    if v0 != v1 {
                        by_ends.entry((v0.min(v1), v0.max(v1))).or_default().push(e);
                    }
                    e
                }
            };
            edges.uses[e as usize] += 1;
            last_face[e as usize] = f;
            edges.of_corner.push(e);
        }
    }
    edges
}

/// Union-find over corners, by rank-free path halving (small sets).
fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let p = parent[parent[x as usize] as usize];
        parent[x as usize] = p;
        x = p;
    }
    x
}

/// The manifold cover of `faces` over `vertex_count` vertices and what is
/// non-manifold in it (module docs). Time linear in the corners (hashing).
///
/// # Errors
/// The per-face errors of [`Topology::new`] (too few corners, an index out
/// of range); [`MeshError::RepeatedIndex`] when a vertex appears twice in a
/// face within one fan (the cover cannot separate the two corners); the
/// cover's own connectivity error, should it have one.
pub(crate) fn manifold_cover(faces: &FaceList, vertex_count: usize) -> Result<(Cover, NonManifoldReport), MeshError> {
    for (f, face) in faces.iter().enumerate() {
        if face.len() < 3 {
            return Err(MeshError::FaceTooSmall { face: f as u32, size: face.len() });
        }
        if let Some(&v) = face.iter().find(|&&v| v as usize >= vertex_count) {
            return Err(MeshError::IndexOutOfRange { face: f as u32, vertex: v, vertex_count });
        }
    }
    let osd = osd_edges(faces);
    let offsets = faces.offsets();
    let idx = faces.indices();
    let nh = idx.len();
    let face_of: Vec<u32> = (0..faces.len()).flat_map(|f| std::iter::repeat_n(f as u32, faces.face_size(f))).collect();
    let next = |h: usize| {
        let f = face_of[h] as usize;
        let (s, e) = (offsets[f] as usize, offsets[f + 1] as usize);
        if h + 1 == e {
            s
        } else {
            h + 1
        }
    };
    // Half-edges of every manifold edge (two uses, not non-manifold): twins.
    let mut first_use = vec![u32::MAX; osd.ends.len()];
    let mut parent: Vec<u32> = (0..nh as u32).collect();
    for h in 0..nh {
        let e = osd.of_corner[h] as usize;
        if osd.non_manifold[e] || osd.uses[e] != 2 {
            continue;
        }
        if first_use[e] == u32::MAX {
            first_use[e] = h as u32;
            continue;
        }
        // h and g traverse the edge in opposite directions: corner next(g)
        // is h's vertex, corner next(h) is g's.
        let g = first_use[e] as usize;
        for (a, b) in [(h, next(g)), (g, next(h))] {
            let (ra, rb) = (find(&mut parent, a as u32), find(&mut parent, b as u32));
            if ra != rb {
                parent[ra.max(rb) as usize] = ra.min(rb);
            }
        }
    }
    // One copy per fan (set of corners): the vertex's own index for the
    // fan of its first corner, new indices for the others in corner order.
    let mut copy_of_root = vec![u32::MAX; nh];
    let mut has_copy = vec![false; vertex_count];
    let mut vertex_class: Vec<u32> = (0..vertex_count as u32).collect();
    let mut cover_indices = Vec::with_capacity(nh);
    let mut fans = vec![0u32; vertex_count];
    for h in 0..nh {
        let root = find(&mut parent, h as u32) as usize;
        let v = idx[h];
        if copy_of_root[root] == u32::MAX {
            copy_of_root[root] = if has_copy[v as usize] {
                vertex_class.push(v);
                (vertex_class.len() - 1) as u32
            } else {
                has_copy[v as usize] = true;
                v
            };
            fans[v as usize] += 1;
        }
        cover_indices.push(copy_of_root[root]);
    }
    // A face with two corners in one fan cannot be separated.
    for f in 0..faces.len() {
        let face = &cover_indices[offsets[f] as usize..offsets[f + 1] as usize];
        for (i, &c) in face.iter().enumerate() {
            if face[i + 1..].contains(&c) {
                return Err(MeshError::RepeatedIndex { face: f as u32, vertex: vertex_class[c as usize] });
            }
        }
    }
    // OpenSubdiv's inventory per vertex: edges (a degenerate one twice),
    // faces (per corner), non-manifold and boundary edges among them.
    let mut edge_count = vec![0u32; vertex_count];
    let mut nm_edges = vec![0u32; vertex_count];
    let mut boundary_edges = vec![0u32; vertex_count];
    for (e, ends) in osd.ends.iter().enumerate() {
        for &v in ends {
            edge_count[v as usize] += 1;
            nm_edges[v as usize] += u32::from(osd.non_manifold[e]);
            boundary_edges[v as usize] += u32::from(osd.uses[e] < 2);
        }
    }
    let mut face_count = vec![0u32; vertex_count];
    for &v in idx {
        face_count[v as usize] += 1;
    }
    let mut report = NonManifoldReport::default();
    let mut creases: HashMap<u32, [u32; 2]> = HashMap::new();
    for v in 0..vertex_count {
        if nm_edges[v] == 0 && fans[v] <= 1 {
            continue;
        }
        report.vertices.push(v as u32);
        let interior_crease = nm_edges[v] == 2 && boundary_edges[v] == 0 && face_count[v] > edge_count[v];
        if !interior_crease {
            report.corners.push(v as u32);
        }
    }
    // The far ends of the two non-manifold edges of every interior-crease vertex.
    for (e, ends) in osd.ends.iter().enumerate() {
        if !osd.non_manifold[e] {
            continue;
        }
        for (v, far) in [(ends[0], ends[1]), (ends[1], ends[0])] {
            let interior_crease =
                report.vertices.binary_search(&v).is_ok() && report.corners.binary_search(&v).is_err();
            if interior_crease {
                creases.entry(v).and_modify(|pair| pair[1] = far).or_insert([far, u32::MAX]);
            }
        }
    }
    // Copies in one face of a vertex inside an interior non-manifold crease: the crease rule,
    // not the one-face corner of `edge-and-corner` (OpenSubdiv decides corners on the vertex).
    let mut corners_of_copy = vec![0u32; vertex_class.len()];
    for &c in &cover_indices {
        corners_of_copy[c as usize] += 1;
    }
    let crease_copies: Vec<u32> = (0..vertex_class.len() as u32)
        .filter(|&c| {
            let v = vertex_class[c as usize];
            corners_of_copy[c as usize] == 1
                && report.vertices.binary_search(&v).is_ok()
                && report.corners.binary_search(&v).is_err()
        })
        .collect();
    report.edges = (osd.ends.iter().zip(&osd.non_manifold)).filter(|&(_, &nm)| nm).map(|(ends, _)| *ends).collect();
    report.copies = vertex_class.len() - vertex_count;
    let cover_vertex_count = vertex_class.len();
    let mut welds = Welds::new(
        vertex_class,
        idx.to_vec(),
        &cover_indices,
        osd.of_corner,
        osd.ends,
        osd.non_manifold,
        report.corners.clone(),
        Some(Box::new(report.clone())),
    );
    welds.crease_copies = crease_copies;
    let mut creases: Vec<(u32, [u32; 2])> = creases.into_iter().collect();
    creases.sort_unstable();
    welds.crease_ends = creases;
    let cover_faces = FaceList::from_raw(offsets.to_vec(), cover_indices);
    Ok((Cover { faces: cover_faces, vertex_count: cover_vertex_count, welds }, report))
}

impl Welds {
    /// Welds from their classes; `cover_indices` are the cover's face
    /// corners (for the members: a cover vertex of every welded vertex).
    #[allow(clippy::too_many_arguments)]
    fn new(
        vertex_class: Vec<u32>,
        corner_class: Vec<u32>,
        cover_indices: &[u32],
        edge_class: Vec<u32>,
        edge_ends: Vec<[u32; 2]>,
        edge_non_manifold: Vec<bool>,
        sharpened: Vec<u32>,
        report: Option<Box<NonManifoldReport>>,
    ) -> Self {
        let classes = vertex_class.iter().chain(&corner_class).map(|&c| c as usize + 1).max().unwrap_or(0);
        let mut member = vec![u32::MAX; classes];
        for (v, &class) in vertex_class.iter().enumerate() {
            if member[class as usize] == u32::MAX {
                member[class as usize] = v as u32;
            }
        }
        for (&class, &v) in corner_class.iter().zip(cover_indices) {
            if member[class as usize] == u32::MAX {
                member[class as usize] = v;
            }
        }
        debug_assert!(!member.contains(&u32::MAX), "every welded vertex has a cover vertex");
        Self {
            vertex_class,
            corner_class,
            member,
            edge_class,
            edge_ends,
            edge_non_manifold,
            sharpened,
            report,
            crease_copies: Vec::new(),
            crease_ends: Vec::new(),
        }
    }

    /// Number of vertices of the welded mesh.
    pub fn vertex_count(&self) -> usize {
        self.member.len()
    }

    /// What is non-manifold in the input, for the cover of an input
    /// (`None` on a refined cover).
    pub fn report(&self) -> Option<&NonManifoldReport> {
        self.report.as_deref()
    }

    /// Cover vertices in one face that keep the crease rule under
    /// `edge-and-corner` ([`crate::Tags::crease_copies`]), ascending.
    pub fn crease_copies(&self) -> &[u32] {
        &self.crease_copies
    }

    /// Checks that every copy of a vertex inside an interior non-manifold
    /// crease lies between the two crease edges (its fan in the cover opens
    /// onto both crease ends), so that the cover's boundary rule there is
    /// OpenSubdiv's crease rule. A fan that closes on itself across one
    /// crease edge (a pocket of faces hanging from the crease) cannot be
    /// expressed and is refused.
    ///
    /// # Errors
    /// [`MeshError::NonManifoldUnsupported`] naming the vertex.
    pub(crate) fn check_creases(&self, cover: &Topology) -> Result<(), MeshError> {
        if self.crease_ends.is_empty() {
            return Ok(());
        }
        let mut copies: HashMap<u32, Vec<u32>> = self.crease_ends.iter().map(|&(v, _)| (v, Vec::new())).collect();
        for (c, class) in self.vertex_class.iter().enumerate() {
            if let Some(list) = copies.get_mut(class) {
                list.push(c as u32);
            }
        }
        for &(v, ends) in &self.crease_ends {
            for &c in &copies[&v] {
                let between = cover.boundary_neighbors(VertexId(c)).is_some_and(|(p, n)| {
                    let mut seen = [self.vertex_class[p.index()], self.vertex_class[n.index()]];
                    let mut want = ends;
                    seen.sort_unstable();
                    want.sort_unstable();
                    seen == want
                });
                if !between {
                    return Err(MeshError::NonManifoldUnsupported {
                        vertex: v,
                        reason: format!(
                            "a fan of its faces does not lie between its two non-manifold crease edges (to {} and {})",
                            ends[0], ends[1]
                        ),
                    });
                }
            }
        }
        Ok(())
    }

    /// Number of vertices of the cover.
    pub fn cover_vertex_count(&self) -> usize {
        self.vertex_class.len()
    }

    /// The welded vertex of cover vertex `v` (of its first corner).
    #[inline]
    pub fn vertex(&self, v: VertexId) -> u32 {
        self.vertex_class[v.index()]
    }

    /// Per cover vertex, its welded vertex ([`Self::vertex`]).
    pub fn vertex_classes(&self) -> &[u32] {
        &self.vertex_class
    }

    /// Whether cover vertex `v` is the one standing for its welded vertex
    /// (one per welded vertex: what a measurement counts once).
    #[inline]
    pub fn is_member(&self, v: VertexId) -> bool {
        self.member[self.vertex_class[v.index()] as usize] == v.0
    }

    /// The welded vertex that cover corner (half-edge) `h` uses.
    #[inline]
    pub fn corner(&self, h: HalfEdgeId) -> u32 {
        self.corner_class[h.index()]
    }

    /// The welded edge of cover half-edge `h`.
    #[inline]
    pub fn edge(&self, h: HalfEdgeId) -> u32 {
        self.edge_class[h.index()]
    }

    /// The welded vertices whose infinitely sharp corner the non-manifold
    /// rule added (a reader of the welded mesh derives them again).
    pub fn sharpened(&self) -> &[u32] {
        &self.sharpened
    }

    /// One value per welded vertex from one per cover vertex (copies of a
    /// vertex have the same position on every level, by the rules;
    /// [`Self::unify`] makes it so for positions that come from elsewhere).
    ///
    /// # Panics
    /// If `values` does not have one entry per cover vertex (a caller bug).
    pub fn weld<T: Copy>(&self, values: &[T]) -> Vec<T> {
        assert_eq!(values.len(), self.vertex_class.len(), "one value per cover vertex");
        self.member.iter().map(|&v| values[v as usize]).collect()
    }

    /// Gives every copy the value of its welded vertex's member.
    ///
    /// # Panics
    /// If `values` does not have one entry per cover vertex (a caller bug).
    pub fn unify<T: Copy>(&self, values: &mut [T]) {
        let welded = self.weld(values);
        for (v, &class) in self.vertex_class.iter().enumerate() {
            values[v] = welded[class as usize];
        }
    }

    /// The welded face list of cover `t`: every face, its corners welded.
    pub fn faces(&self, t: &Topology) -> FaceList {
        FaceList::from_raw(t.faces().offsets().to_vec(), self.corner_class.clone())
    }

    /// `faces` (by cover vertices, a subset of the cover's faces such as its
    /// faces without holes) by welded vertices.
    pub fn weld_faces(&self, faces: &FaceList) -> FaceList {
        let indices = faces.indices().iter().map(|&v| self.vertex_class[v as usize]).collect();
        FaceList::from_raw(faces.offsets().to_vec(), indices)
    }

    /// The cover's tags as the welded mesh's (by welded vertex indices): an
    /// edge tag once per welded edge, a corner tag once per welded vertex,
    /// the corners the non-manifold rule added left out.
    pub fn tags(&self, cover_tags: &TagList) -> TagList {
        let mut creases: Vec<EdgeTag> = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for tag in &cover_tags.creases {
            let (a, b) = (self.vertex_class[tag.a as usize], self.vertex_class[tag.b as usize]);
            if a != b && seen.insert((a.min(b), a.max(b))) {
                creases.push(EdgeTag { a, b, sharpness: tag.sharpness });
            }
        }
        let mut corners: Vec<VertexTag> = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for tag in &cover_tags.corners {
            let v = self.vertex_class[tag.vertex as usize];
            if self.sharpened.binary_search(&v).is_err() && seen.insert(v) {
                corners.push(VertexTag { vertex: v, sharpness: tag.sharpness });
            }
        }
        TagList { creases, corners, holes: cover_tags.holes.clone(), options: cover_tags.options }
    }

    /// The input's tags on the cover: an edge tag on every cover edge of the
    /// tagged edge, a corner tag on every copy, an infinitely sharp crease on
    /// every cover edge of a non-manifold edge that the cover did not make a
    /// boundary, and an infinitely sharp corner on every copy of a sharpened
    /// vertex.
    ///
    /// # Errors
    /// [`MeshError::TagVertexOutOfRange`], [`MeshError::TagNotAnEdge`].
    pub(crate) fn cover_tags(&self, cover: &Topology, list: &TagList) -> Result<TagList, MeshError> {
        let n = self.vertex_count();
        let mut copies: Vec<Vec<u32>> = vec![Vec::new(); n];
        for (v, &class) in self.vertex_class.iter().enumerate() {
            copies[class as usize].push(v as u32);
        }
        let in_range = |v: u32| {
            if (v as usize) < n {
                Ok(v)
            } else {
                Err(MeshError::TagVertexOutOfRange { vertex: v, vertex_count: n })
            }
        };
        let mut creases = Vec::new();
        if !list.creases.is_empty() {
            // Cover edges by their welded ends.
            let mut by_ends: HashMap<(u32, u32), Vec<(u32, u32)>> = HashMap::new();
            for e in cover.edges() {
                let h = cover.edge_half_edge(e);
                let (wa, wb) = (self.corner_class[h.index()], self.corner_class[cover.he_next(h).index()]);
                let (a, b) = cover.edge_vertices(e);
                by_ends.entry((wa.min(wb), wa.max(wb))).or_default().push((a.0, b.0));
            }
            for tag in &list.creases {
                let (a, b) = (in_range(tag.a)?, in_range(tag.b)?);
                let edges = by_ends.get(&(a.min(b), a.max(b))).ok_or(MeshError::TagNotAnEdge { a, b })?;
                creases.extend(edges.iter().map(|&(a, b)| EdgeTag { a, b, sharpness: tag.sharpness }));
            }
        }
        for e in cover.edges() {
            let h = cover.edge_half_edge(e);
            let twin_class = cover.he_twin(h).map(|g| self.edge_class[g.index()]);
            let class = self.edge_class[h.index()];
            let non_manifold = |c: u32| self.edge_non_manifold.get(c as usize).copied().unwrap_or(false);
            if !cover.is_boundary_edge(e) && (non_manifold(class) || twin_class.is_some_and(non_manifold)) {
                let (a, b) = cover.edge_vertices(e);
                creases.push(EdgeTag { a: a.0, b: b.0, sharpness: SHARPNESS_INFINITE });
            }
        }
        let mut corners = Vec::new();
        for tag in &list.corners {
            let v = in_range(tag.vertex)?;
            corners.extend(copies[v as usize].iter().map(|&c| VertexTag { vertex: c, sharpness: tag.sharpness }));
        }
        for &v in &self.sharpened {
            corners.extend(copies[v as usize].iter().map(|&c| VertexTag { vertex: c, sharpness: SHARPNESS_INFINITE }));
        }
        Ok(TagList { creases, corners, holes: list.holes.clone(), options: list.options })
    }

    /// The welds of one Catmull-Clark (quad split) step of cover `coarse`:
    /// welded vertices, then one per face, then one per welded edge — the
    /// numbering of [`crate::refine::quad_split`] with copies merged.
    pub fn quad_split(&self, coarse: &Topology) -> Welds {
        self.split(coarse, Split::Quad)
    }

    /// The welds of one Loop (triangle split) step of cover `coarse`:
    /// welded vertices, then one per welded edge.
    pub fn triangle_split(&self, coarse: &Topology) -> Welds {
        self.split(coarse, Split::Triangle)
    }

    fn split(&self, coarse: &Topology, split: Split) -> Welds {
        let (w, nf) = (self.vertex_count() as u32, coarse.face_count() as u32);
        let edge_base = match split {
            Split::Quad => w + nf,
            Split::Triangle => w,
        };
        let nh = coarse.half_edge_count();
        let prev = |h: usize| coarse.he_prev(HalfEdgeId(h as u32)).index();
        let next = |h: usize| coarse.he_next(HalfEdgeId(h as u32)).index();
        let edge_point = |h: usize| edge_base + self.edge_class[h];
        // The cover's own numbering of the child (for the welded vertices' members).
        let (nv, cover_edge_base) = match split {
            Split::Quad => (coarse.vertex_count() as u32, (coarse.vertex_count() + coarse.face_count()) as u32),
            Split::Triangle => (coarse.vertex_count() as u32, coarse.vertex_count() as u32),
        };
        let cover_edge_point = |h: usize| cover_edge_base + coarse.he_edge(HalfEdgeId(h as u32)).0;
        let from = |h: usize| coarse.he_from(HalfEdgeId(h as u32)).0;
        let mut child_indices = vec![0u32; 4 * nh];
        // Child cover vertices in the refinement's numbering.
        let mut vertex_class = self.vertex_class.clone();
        if split == Split::Quad {
            vertex_class.extend(w..w + nf);
        }
        vertex_class.extend(coarse.edges().map(|e| edge_point(coarse.edge_half_edge(e).index())));
        // Which half of its welded edge the part of h at h's start is.
        let first_half = |h: usize| -> u8 {
            let ends = [self.corner_class[h], self.corner_class[next(h)]];
            u8::from(ends != self.edge_ends[self.edge_class[h] as usize])
        };
        // Four child half-edges per parent half-edge in both splits: their
        // welded corner and their welded edge's key.
        let mut corner_class = vec![0u32; 4 * nh];
        let mut keys = vec![Key::Spoke(0); 4 * nh];
        match split {
            Split::Quad => {
                // Quad h = (from h, e(h), f, e(prev h)): half-edges 4h+k.
                for h in 0..nh {
                    let p = prev(h);
                    let f = coarse.he_face(HalfEdgeId(h as u32)).0;
                    child_indices[4 * h..4 * h + 4].copy_from_slice(&[
                        from(h),
                        cover_edge_point(h),
                        nv + f,
                        cover_edge_point(p),
                    ]);
                    corner_class[4 * h..4 * h + 4].copy_from_slice(&[
                        self.corner_class[h],
                        edge_point(h),
                        w + f,
                        edge_point(p),
                    ]);
                    keys[4 * h..4 * h + 4].copy_from_slice(&[
                        Key::Half(self.edge_class[h], first_half(h)),
                        Key::Spoke(h as u32),
                        Key::Spoke(p as u32),
                        Key::Half(self.edge_class[p], 1 - first_half(p)),
                    ]);
                }
            }
            Split::Triangle => {
                // Corner triangle T(h) = 4⌊h/3⌋ + h mod 3 = (from h, e(h), e(prev h)),
                // centre 4f+3 = (e(h₀), e(h₁), e(h₂)): half-edges 3t+k.
                for h in 0..nh {
                    let (t, p) = (3 * (4 * (h / 3) + h % 3), prev(h));
                    child_indices[t..t + 3].copy_from_slice(&[from(h), cover_edge_point(h), cover_edge_point(p)]);
                    corner_class[t..t + 3].copy_from_slice(&[self.corner_class[h], edge_point(h), edge_point(p)]);
                    keys[t..t + 3].copy_from_slice(&[
                        Key::Half(self.edge_class[h], first_half(h)),
                        Key::Spoke(h as u32),
                        Key::Half(self.edge_class[p], 1 - first_half(p)),
                    ]);
                }
                for f in 0..nh / 3 {
                    let t = 3 * (4 * f + 3);
                    for j in 0..3 {
                        corner_class[t + j] = edge_point(3 * f + j);
                        child_indices[t + j] = cover_edge_point(3 * f + j);
                        // e(h_j) → e(h_{j+1}): the twin of 3T(h_{j+1}) + 1.
                        keys[t + j] = Key::Spoke(next(3 * f + j) as u32);
                    }
                }
            }
        }
        let m = match split {
            Split::Quad => 4,
            Split::Triangle => 3,
        };
        let child_next = |x: usize| m * (x / m) + (x + 1) % m;
        let mut ids: HashMap<Key, u32> = HashMap::new();
        let mut edge_ends: Vec<[u32; 2]> = Vec::new();
        let edge_class = (0..4 * nh)
            .map(|x| {
                *ids.entry(keys[x]).or_insert_with(|| {
                    edge_ends.push([corner_class[x], corner_class[child_next(x)]]);
                    (edge_ends.len() - 1) as u32
                })
            })
            .collect();
        Welds::new(vertex_class, corner_class, &child_indices, edge_class, edge_ends, Vec::new(), Vec::new(), None)
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Split {
    Quad,
    Triangle,
}

/// A child edge: a half of a welded parent edge (0 at the end its first
/// half-edge starts from), or the edge inside a face that parent half-edge
/// `h` starts (Catmull-Clark: e(h) to the face point; Loop: e(h) to e(prev h)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Key {
    Half(u32, u8),
    Spoke(u32),
}

/// Whether `error` is one a manifold cover resolves (non-manifold edges and
/// vertices, inconsistent orientation, a vertex repeated in a face).
pub(crate) fn is_non_manifold(error: &MeshError) -> bool {
    matches!(
        error,
        MeshError::NonManifoldEdge { .. }
            | MeshError::NonManifoldVertex { .. }
            | MeshError::InconsistentOrientation { .. }
            | MeshError::RepeatedIndex { .. }
    )
}
