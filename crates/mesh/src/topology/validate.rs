//! Construction of a [`Topology`] from a face list, with the checks that make
//! it trustworthy: face sizes and indices, manifold edges, consistent
//! orientation, one fan per vertex.

use super::diagonals::QuadConflicts;
use super::{HalfEdgeFaces, Topology, NONE};
use crate::error::MeshError;
use crate::ids::HalfEdgeId;
use crate::soup::FaceList;
use rayon::prelude::*;
use std::collections::HashMap;
use std::ops::Range;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::OnceLock;

impl Topology {
    /// Builds and validates the connectivity of `faces` over `vertex_count`
    /// vertices, in time linear in the number of corners.
    ///
    /// Errors name the first offending element: a face with fewer than three
    /// corners, an out-of-range or repeated index, an edge with more than two
    /// faces, two faces traversing an edge the same way, or a vertex whose faces
    /// form more than one fan. A face list with no faces is an error too.
    pub fn new(faces: FaceList, vertex_count: usize) -> Result<Self, MeshError> {
        Self::new_or_return(faces, vertex_count).map_err(|(error, _)| error)
    }

    /// [`Topology::new`] that gives the face list back with the error (for a
    /// caller that goes on to describe what is wrong, without a copy).
    pub(crate) fn new_or_return(faces: FaceList, vertex_count: usize) -> Result<Self, (MeshError, FaceList)> {
        match Self::connect(&faces, vertex_count) {
            Ok(topology) => Ok(Self { faces, ..topology }),
            Err(error) => Err((error, faces)),
        }
    }

    /// The connectivity of `faces`: everything [`Topology::new`] returns but
    /// the face list itself (left empty here, moved in by the caller).
    fn connect(faces: &FaceList, vertex_count: usize) -> Result<Self, MeshError> {
        if faces.is_empty() {
            return Err(MeshError::NoFaces);
        }
        let (fan_offsets, uniform_size) = check_and_count_corners(faces, vertex_count)?;
        let nv = vertex_count;
        let nh = faces.corner_count();
        if nh >= NONE as usize {
            return Err(MeshError::TooLarge { what: "more than 2³² − 2 corners" });
        }
        let offsets = faces.offsets();
        let idx = faces.indices();

        // Outgoing half-edges per vertex by counting sort (CSR, in half-edge
        // order). The fan is this CSR reordered in place. Big meshes are
        // split into vertex ranges of about equal corner counts, one per
        // thread: each owns its buckets' slots, so the result is the same
        // whatever the split (every bucket in half-edge order).
        let parts = if nh < PARALLEL_CORNERS { 1 } else { rayon::current_num_threads().max(1) };
        let vertex_parts = balanced_ranges(&fan_offsets, parts);
        let he_face = match uniform_size {
            Some(m) => HalfEdgeFaces::Uniform(m as u32),
            None => HalfEdgeFaces::Table(face_of_half_edges(faces, parts)),
        };
        let mut fan = vec![HalfEdgeId(0); nh];
        split_by_buckets(&vertex_parts, &fan_offsets, &mut fan)
            .into_par_iter()
            .for_each(|(vertices, fan)| scatter_corners(idx, &fan_offsets, vertices, fan));

        // Per vertex a, from its bucket alone: two half-edges a→b are an
        // edge error; the fan walks h ← twin(prev(h)), i.e. to the corner
        // whose end is h's previous vertex, from the boundary half-edge (or
        // the first one). Edge errors are reported before fan errors, at the
        // first vertex that has one (per range, then the first range's).
        // The walk pairs the twins too: every half-edge x→a is prev(h) for
        // one corner h at a, and its twin a→x is the corner after h in the
        // fan, so each twin is written once, by the bucket of the half-edge's
        // end (the same values whatever the split).
        let he_twin: Vec<AtomicU32> = (0..nh).into_par_iter().map(|_| AtomicU32::new(NONE)).collect();
        let mut vertex_on_boundary = vec![false; nv];
        let mut verdicts: Vec<RangeVerdict> = split_by_buckets(&vertex_parts, &fan_offsets, &mut fan)
            .into_par_iter()
            .zip(split_at_ranges(&vertex_parts, &mut vertex_on_boundary))
            .map(|((vertices, fan), on_boundary)| {
                let buckets = Buckets { fan_offsets: &fan_offsets, fan, on_boundary };
                order_fans(vertices, (faces, &he_face), buckets, &he_twin)
            })
            .collect();
        if let Some(repeated) = verdicts.iter().find_map(|v| v.repeated_edge) {
            return Err(repeated.error(faces, &he_face));
        }
        if let Some(e) = verdicts.iter_mut().find_map(|v| v.fan_error.take()) {
            return Err(e);
        }
        let diagonal_conflicts = match verdicts.iter().all(|v| v.quad_conflicts.is_some()) {
            true => OnceLock::from(QuadConflicts::merge(verdicts.into_iter().filter_map(|v| v.quad_conflicts))),
            false => OnceLock::new(),
        };
        // Same size and alignment: collected in place.
        let he_twin: Vec<u32> = he_twin.into_iter().map(AtomicU32::into_inner).collect();
        let to = |h: usize| idx[he_face.next(offsets, h)];

        // Boundary loops: after boundary half-edge a→b comes b's boundary half-edge.
        let mut loop_offsets = vec![0u32];
        let mut loop_he = Vec::new();
        // Marks for boundary half-edges, allocated only for an open mesh.
        let open = vertex_on_boundary.contains(&true);
        let mut seen = if open { vec![false; nh] } else { Vec::new() };
        for h0 in (0..nh).filter(|_| open) {
            if he_twin[h0] != NONE || seen[h0] {
                continue;
            }
            let mut h = h0;
            while !seen[h] {
                seen[h] = true;
                loop_he.push(HalfEdgeId(h as u32));
                let b = to(h) as usize;
                h = fan[fan_offsets[b] as usize].index();
            }
            loop_offsets.push(loop_he.len() as u32);
        }

        let (face_component, component_count) = components(faces, &he_twin, &he_face, parts);

        Ok(Self {
            vertex_count: nv as u32,
            faces: FaceList::default(),
            he_face,
            he_twin,
            edges: OnceLock::new(),
            diagonal_conflicts,
            fan_offsets,
            fan,
            vertex_on_boundary,
            loop_offsets,
            loop_he,
            face_component,
            component_count,
        })
    }
}

/// Per-face checks that need no connectivity (size, index range, repeats)
/// with the face size when all faces have the same, then the CSR offsets
/// of every vertex's corners. Errors name the first offending face and,
/// in it, the first offending corner (range before repeat). A repeat is
/// found by comparing with the face's earlier corners for faces of at most
/// [`SMALL_FACE`] corners (no vertex-sized array touched at random), by
/// marking vertices for bigger ones (a face of 10⁶ corners costs 10⁶ steps,
/// not 10¹²/2).
fn check_and_count_corners(faces: &FaceList, vertex_count: usize) -> Result<(Vec<u32>, Option<usize>), MeshError> {
    if vertex_count >= NONE as usize {
        return Err(MeshError::TooLarge { what: "more than 2³² − 2 vertices" });
    }
    // Every face's verdict depends on that face alone: blocks of small
    // faces are checked across threads (the first error of the first block
    // that has one), big faces after, in order, with one mark array; the
    // error of the smaller face wins.
    const BLOCK: usize = 1 << 14;
    let first_size = faces.face_size(0);
    let blocks: Vec<(Option<(usize, MeshError)>, bool)> = (0..faces.len().div_ceil(BLOCK))
        .into_par_iter()
        .map(|block| {
            let mut uniform = true;
            for f in block * BLOCK..((block + 1) * BLOCK).min(faces.len()) {
                let face = faces.face(f);
                uniform &= face.len() == first_size;
                if face.len() <= SMALL_FACE {
                    if let Some(error) = small_face_error(f, face, vertex_count) {
                        return (Some((f, error)), false);
                    }
                }
            }
            (None, uniform)
        })
        .collect();
    let small_error = blocks.iter().find_map(|(error, _)| error.clone());
    let before = small_error.as_ref().map_or(faces.len(), |&(f, _)| f);
    let mut seen_in: Vec<u32> = Vec::new();
    for f in (0..before).filter(|&f| faces.face_size(f) > SMALL_FACE) {
        if seen_in.is_empty() {
            seen_in = vec![NONE; vertex_count];
        }
        let face = faces.face(f);
        for &v in face {
            let Some(seen) = seen_in.get_mut(v as usize) else {
                return Err(MeshError::IndexOutOfRange { face: f as u32, vertex: v, vertex_count });
            };
            if std::mem::replace(seen, f as u32) == f as u32 {
                return Err(MeshError::RepeatedIndex { face: f as u32, vertex: v });
            }
        }
    }
    if let Some((_, error)) = small_error {
        return Err(error);
    }
    let uniform = blocks.iter().all(|&(_, uniform)| uniform).then_some(first_size);

    // Corners per vertex (every index is in range now), counted by vertex
    // ranges across threads, each scanning all corners; wrapping: past
    // 2³² − 2 corners the counts are discarded (`TooLarge`, after these checks).
    let mut offsets = vec![0u32; vertex_count + 1];
    let idx = faces.indices();
    let parts = if idx.len() < PARALLEL_CORNERS { 1 } else { rayon::current_num_threads().max(1) };
    let chunk = vertex_count.div_ceil(parts).max(1);
    offsets[1..].par_chunks_mut(chunk).enumerate().for_each(|(part, counts)| {
        let (first, len) = ((part * chunk) as u32, counts.len() as u32);
        for &v in idx {
            let local = v.wrapping_sub(first);
            if local < len {
                counts[local as usize] = counts[local as usize].wrapping_add(1);
            }
        }
    });
    for i in 0..vertex_count {
        offsets[i + 1] = offsets[i + 1].wrapping_add(offsets[i]);
    }
    Ok((offsets, uniform))
}

/// The error of face `f` of at most [`SMALL_FACE`] corners, if any: too
/// few corners, else its first corner out of range or repeating an earlier one.
#[inline]
fn small_face_error(f: usize, face: &[u32], vertex_count: usize) -> Option<MeshError> {
    if face.len() < 3 {
        return Some(MeshError::FaceTooSmall { face: f as u32, size: face.len() });
    }
    for (j, &v) in face.iter().enumerate() {
        if v as usize >= vertex_count {
            return Some(MeshError::IndexOutOfRange { face: f as u32, vertex: v, vertex_count });
        }
        if face[..j].contains(&v) {
            return Some(MeshError::RepeatedIndex { face: f as u32, vertex: v });
        }
    }
    None
}

/// Faces of at most this many corners are checked for repeated indices by
/// comparing their corners (see [`check_and_count_corners`]).
const SMALL_FACE: usize = 16;

/// Below this many corners the construction runs on one thread.
const PARALLEL_CORNERS: usize = 1 << 16;

/// `0..prefix.len() − 1` cut into `parts` consecutive ranges of about equal
/// weight, `prefix` being the running sum of the weights (CSR offsets).
fn balanced_ranges(prefix: &[u32], parts: usize) -> Vec<Range<usize>> {
    let n = prefix.len() - 1;
    let total = u64::from(prefix[n]);
    let mut cuts: Vec<usize> = (1..parts)
        .map(|p| prefix.partition_point(|&w| u64::from(w) * parts as u64 <= total * p as u64).saturating_sub(1))
        .collect();
    cuts.insert(0, 0);
    cuts.push(n);
    cuts.dedup();
    cuts.windows(2).map(|w| w[0]..w[1]).collect()
}

/// The face of every half-edge, face ranges filled in parallel.
fn face_of_half_edges(faces: &FaceList, parts: usize) -> Vec<u32> {
    let offsets = faces.offsets();
    let mut he_face = vec![0u32; faces.corner_count()];
    let face_parts = balanced_ranges(offsets, parts);
    let corner_parts: Vec<Range<usize>> =
        face_parts.iter().map(|r| offsets[r.start] as usize..offsets[r.end] as usize).collect();
    split_at_ranges(&corner_parts, &mut he_face).into_par_iter().zip(face_parts).for_each(|(slice, faces)| {
        let base = offsets[faces.start] as usize;
        for f in faces {
            slice[offsets[f] as usize - base..offsets[f + 1] as usize - base].fill(f as u32);
        }
    });
    he_face
}

/// `data` cut at consecutive `ranges` (which cover it from 0).
fn split_at_ranges<'a, T>(ranges: &[Range<usize>], mut data: &'a mut [T]) -> Vec<&'a mut [T]> {
    let mut slices = Vec::with_capacity(ranges.len());
    for r in ranges {
        let (head, tail) = std::mem::take(&mut data).split_at_mut(r.len());
        slices.push(head);
        data = tail;
    }
    slices
}

/// Per vertex range: the range and its buckets' slots of `fan`.
fn split_by_buckets<'a>(
    vertex_parts: &[Range<usize>],
    fan_offsets: &[u32],
    fan: &'a mut [HalfEdgeId],
) -> Vec<(Range<usize>, &'a mut [HalfEdgeId])> {
    let slots: Vec<Range<usize>> =
        vertex_parts.iter().map(|r| fan_offsets[r.start] as usize..fan_offsets[r.end] as usize).collect();
    vertex_parts.iter().cloned().zip(split_at_ranges(&slots, fan)).collect()
}

/// The counting sort's scatter for the buckets of `vertices` (whose slots
/// `fan` are): every half-edge, in order, into its start vertex's bucket
/// when that is in the range. `idx` is the start vertex of every half-edge
/// (the face list's indices).
fn scatter_corners(idx: &[u32], fan_offsets: &[u32], vertices: Range<usize>, fan: &mut [HalfEdgeId]) {
    let base = fan_offsets[vertices.start];
    let mut cursor: Vec<u32> = fan_offsets[vertices.clone()].iter().map(|&o| o - base).collect();
    let (first, count) = (vertices.start as u32, vertices.len() as u32);
    for (h, &v) in idx.iter().enumerate() {
        let a = v.wrapping_sub(first);
        if a < count {
            let slot = &mut cursor[a as usize];
            fan[*slot as usize] = HalfEdgeId(h as u32);
            *slot += 1;
        }
    }
}

/// What one vertex range's buckets say: its first edge error, its first
/// fan error, and for an all-quad mesh its vertices' diagonal conflicts.
struct RangeVerdict {
    repeated_edge: Option<RepeatedEdge>,
    fan_error: Option<MeshError>,
    quad_conflicts: Option<QuadConflicts>,
}

/// Two half-edges a→b, `first` and `second` (in half-edge order): an edge
/// error, which one told by [`RepeatedEdge::error`].
#[derive(Clone, Copy)]
struct RepeatedEdge {
    a: u32,
    b: u32,
    first: u32,
    second: u32,
}

impl RepeatedEdge {
    /// A non-manifold edge when more than two half-edges join a and b
    /// (counted over all faces: the error path, once), else two faces
    /// traversing a→b alike.
    #[cold]
    fn error(self, faces: &FaceList, he_face: &HalfEdgeFaces) -> MeshError {
        let RepeatedEdge { a, b, first, second } = self;
        let (offsets, idx) = (faces.offsets(), faces.indices());
        let joins = |h: usize| {
            let (from, to) = (idx[h], idx[he_face.next(offsets, h)]);
            (from, to) == (a, b) || (from, to) == (b, a)
        };
        let faces = (0..idx.len()).into_par_iter().filter(|&h| joins(h)).count();
        if faces > 2 {
            MeshError::NonManifoldEdge { a: a.min(b), b: a.max(b), faces }
        } else {
            MeshError::InconsistentOrientation {
                a,
                b,
                face_a: he_face.get(first as usize),
                face_b: he_face.get(second as usize),
            }
        }
    }
}

/// The buckets of one vertex range, as [`order_fans`] reads and writes
/// them: the CSR offsets of every vertex's corners, the range's slots
/// (half-edges, reordered into fans) and its vertices' boundary marks.
struct Buckets<'a> {
    fan_offsets: &'a [u32],
    fan: &'a mut [HalfEdgeId],
    on_boundary: &'a mut [bool],
}

/// Orders the fans of `vertices`, marks the boundary ones and writes the
/// twin of every half-edge ending at them into `he_twin`, stopping at the
/// first edge error. The end vertex of a corner and the start vertex of its
/// previous half-edge are read from the faces (one cache line), while the
/// bucket is still in half-edge order. In an all-quad mesh the far corner
/// comes from the same line, and the vertex's diagonal conflicts are found
/// too (`diagonals`).
fn order_fans(
    vertices: Range<usize>,
    (faces, he_face): (&FaceList, &HalfEdgeFaces),
    Buckets { fan_offsets, fan, on_boundary }: Buckets,
    he_twin: &[AtomicU32],
) -> RangeVerdict {
    let (offsets, idx) = (faces.offsets(), faces.indices());
    let prev = |h: HalfEdgeId| he_face.prev(offsets, h.index());
    let base = fan_offsets[vertices.start] as usize;
    let quads = matches!(he_face, HalfEdgeFaces::Uniform(4));
    let mut verdict = RangeVerdict { repeated_edge: None, fan_error: None, quad_conflicts: None };
    let mut conflicts = QuadConflicts::default();
    let mut bucket = Bucket::default();
    // The end vertex of every corner and the start vertex of its previous
    // half-edge, gathered for a block of vertices at a time: the loads are
    // independent (no branch between them), so their cache misses overlap.
    const BLOCK: usize = 1 << 10;
    let (mut block_ends, mut block_prevs, mut block_fars) = (Vec::new(), Vec::new(), Vec::new());
    let mut block_base = usize::MAX;
    for a in vertices.clone() {
        if (a - vertices.start) % BLOCK == 0 {
            let block_end = (a + BLOCK).min(vertices.end);
            let slots = fan_offsets[a] as usize - base..fan_offsets[block_end] as usize - base;
            block_base = slots.start;
            block_ends.clear();
            block_prevs.clear();
            block_fars.clear();
            if quads {
                // The whole face row at once: corner k of a quad at 4f + k.
                for &h in &fan[slots] {
                    let h = h.index();
                    let row: &[u32; 4] = idx[h & !3..(h & !3) + 4].try_into().expect("a quad has four corners");
                    block_ends.push(row[(h + 1) & 3]);
                    block_fars.push(row[(h + 2) & 3]);
                    block_prevs.push(row[(h + 3) & 3]);
                }
            } else {
                block_ends.extend(fan[slots.clone()].iter().map(|&h| idx[he_face.next(offsets, h.index())]));
                block_prevs.extend(fan[slots].iter().map(|&h| idx[prev(h)]));
            }
        }
        let range = fan_offsets[a] as usize..fan_offsets[a + 1] as usize;
        if range.is_empty() {
            continue;
        }
        let local = range.start - base..range.end - base;
        let in_block = local.start - block_base..local.end - block_base;
        let (to, prevs) = (&block_ends[in_block.clone()], &block_prevs[in_block.clone()]);
        let corners = if range.len() <= SMALL_BUCKET {
            if quads {
                let is_neighbour = |w| to.contains(&w) || prevs.contains(&w);
                conflicts.vertex(&fan[local.clone()], (to, prevs, &block_fars[in_block]), is_neighbour);
            }
            small_bucket(to, prevs, &mut fan[local.clone()])
        } else {
            bucket.load(to, prevs);
            if quads {
                let is_neighbour = |w| bucket.with_end(w).is_some() || bucket.with_prev_from(w).is_some();
                conflicts.vertex(&fan[local.clone()], (to, prevs, &block_fars[in_block]), is_neighbour);
            }
            bucket.fan(&mut fan[local.clone()])
        };
        match corners {
            Verdict::Fan { boundary } => {
                on_boundary[a - vertices.start] = boundary;
                // twin(prev(h)) is the corner after h; after the last, the
                // first again, unless the fan is open (prev(h) on the boundary).
                let ordered = &fan[local.clone()];
                let closing = (!boundary).then_some(ordered[0]);
                for (i, &h) in ordered.iter().enumerate() {
                    if let Some(next) = ordered.get(i + 1).copied().or(closing) {
                        he_twin[prev(h)].store(next.0, Ordering::Relaxed);
                    }
                }
            }
            Verdict::RepeatedEnd(i, j) => {
                let (first, second) = (fan[local.start + i].0, fan[local.start + j].0);
                verdict.repeated_edge = Some(RepeatedEdge { a: a as u32, b: to[i], first, second });
                return verdict;
            }
            Verdict::SeveralFans => {
                if verdict.fan_error.is_none() {
                    bucket.load(to, prevs);
                    verdict.fan_error =
                        Some(MeshError::NonManifoldVertex { vertex: a as u32, fans: bucket.count_fans() });
                }
            }
        }
    }
    verdict.quad_conflicts = quads.then_some(conflicts);
    verdict
}

/// Connected components of faces through twins, numbered in order of
/// their first face: union-find whose roots are the smallest face of their
/// set (so `parent[f] ≤ f`), then one ascending pass that labels each face
/// from its parent's label. Returns (component of every face, count).
///
/// Big meshes are split into face ranges of about equal corner counts, one
/// per thread: each joins the twin pairs inside its range in its own slice
/// of `parent` and lists the pairs that leave it, which are joined after,
/// on the whole array. The partition, hence the labelling, is the same
/// whatever the split.
fn components(faces: &FaceList, he_twin: &[u32], he_face: &HalfEdgeFaces, parts: usize) -> (Vec<u32>, u32) {
    let offsets = faces.offsets();
    let face_count = faces.len();
    let mut parent: Vec<u32> = (0..face_count as u32).collect();
    let face_parts = balanced_ranges(offsets, parts);
    let crossing: Vec<Vec<(u32, u32)>> = split_at_ranges(&face_parts, &mut parent)
        .into_par_iter()
        .zip(face_parts.par_iter())
        .map(|(parent, range)| {
            let base = range.start as u32;
            // Roots are the smallest face of their set: within the range,
            // parents stay in it.
            let mut crossing = Vec::new();
            for h in offsets[range.start] as usize..offsets[range.end] as usize {
                let t = he_twin[h];
                if t == NONE || (h as u32) > t {
                    continue;
                }
                let (a, b) = (he_face.get(h), he_face.get(t as usize));
                if (b as usize) < range.end {
                    union(parent, base, a, b);
                } else {
                    crossing.push((a, b));
                }
            }
            crossing
        })
        .collect();
    for &(a, b) in crossing.iter().flatten() {
        union(&mut parent, 0, a, b);
    }
    // parent[f] < f was labelled before f, with its root's label.
    let mut count = 0u32;
    for f in 0..face_count {
        let p = parent[f] as usize;
        parent[f] = if p == f {
            count += 1;
            count - 1
        } else {
            parent[p]
        };
    }
    (parent, count)
}

/// Joins the sets of faces `a` and `b` in a union-find forest whose roots
/// are the smallest face of their set (path halving on the way); `parent`
/// holds the parents of faces `base..`.
#[inline]
fn union(parent: &mut [u32], base: u32, a: u32, b: u32) {
    let find = |parent: &mut [u32], mut x: u32| {
        while parent[(x - base) as usize] != x {
            let grand = parent[(parent[(x - base) as usize] - base) as usize];
            parent[(x - base) as usize] = grand;
            x = grand;
        }
        x
    };
    let (a, b) = (find(parent, a), find(parent, b));
    if a != b {
        parent[(a.max(b) - base) as usize] = a.min(b);
    }
}

/// Buckets larger than this are searched through hash maps, smaller ones
/// by scanning (a vertex may have 10⁵ corners).
const SMALL_BUCKET: usize = 16;

/// What one vertex's bucket says.
enum Verdict {
    /// One fan, now in order; open when `boundary`.
    Fan { boundary: bool },
    /// Corners `i < j` end at the same vertex (two half-edges a→b), `j` the
    /// first such corner.
    RepeatedEnd(usize, usize),
    /// More than one fan.
    SeveralFans,
}

/// [`Bucket::fan`] for a bucket of at most [`SMALL_BUCKET`] corners, on the
/// stack: `ends` are the corners' end vertices, `prevs` the start vertices of
/// their previous half-edges, `fan` their half-edges, reordered into the fan
/// on success.
#[inline]
fn small_bucket(ends: &[u32], prevs: &[u32], fan: &mut [HalfEdgeId]) -> Verdict {
    const NO: u8 = u8::MAX;
    let k = fan.len();
    let (to, prev_from) = (&ends[..k], &prevs[..k]);
    for j in 1..k {
        if let Some(i) = to[..j].iter().position(|&t| t == to[j]) {
            return Verdict::RepeatedEnd(i, j);
        }
    }
    // succ[i]: the corner ending at i's previous vertex (twin(prev(h))).
    let mut succ = [NO; SMALL_BUCKET];
    let mut has_pred = [false; SMALL_BUCKET];
    for i in 0..k {
        for j in 0..k {
            if to[j] == prev_from[i] {
                succ[i] = j as u8;
                has_pred[j] = true;
            }
        }
    }
    let mut starts = (0..k).filter(|&j| !has_pred[j]);
    let boundary_start = starts.next();
    if starts.next().is_some() {
        return Verdict::SeveralFans;
    }
    let start = boundary_start.unwrap_or(0);
    // The walk writes the fan in place, from a copy of the bucket. (Not into
    // a stack array copied back after: that copy's wide load would wait for
    // every store before it, the twins' cache misses included.)
    let mut bucket = [HalfEdgeId(0); SMALL_BUCKET];
    bucket[..k].copy_from_slice(fan);
    let (mut n, mut i) = (0, start);
    loop {
        fan[n] = bucket[i];
        n += 1;
        match succ[i] {
            j if j == NO || j as usize == start || n >= k => break,
            j => i = j as usize,
        }
    }
    if n != k || (succ[i] != NO && succ[i] as usize != start) {
        // The slots are left part-walked: the caller reports the vertex
        // from `ends` and `prevs` alone.
        return Verdict::SeveralFans;
    }
    Verdict::Fan { boundary: boundary_start.is_some() }
}

/// Lookups within one vertex's bucket of corners: which corner ends at a
/// vertex, which corner's previous half-edge starts at one.
#[derive(Default)]
struct Bucket {
    to: Vec<u32>,
    prev_from: Vec<u32>,
    /// First corner by end vertex and by previous vertex, for big buckets.
    by_to: HashMap<u32, usize>,
    by_prev_from: HashMap<u32, usize>,
    /// The fan being walked.
    order: Vec<HalfEdgeId>,
}

impl Bucket {
    /// The bucket of corners with end vertices `ends` and previous
    /// half-edges starting at `prevs`.
    fn load(&mut self, ends: &[u32], prevs: &[u32]) {
        self.to.clear();
        self.to.extend_from_slice(ends);
        self.prev_from.clear();
        self.prev_from.extend_from_slice(prevs);
        if self.big() {
            self.by_to.clear();
            self.by_prev_from.clear();
            for (i, (&to, &prev_from)) in self.to.iter().zip(&self.prev_from).enumerate() {
                self.by_to.entry(to).or_insert(i);
                self.by_prev_from.entry(prev_from).or_insert(i);
            }
        }
    }

    fn big(&self) -> bool {
        self.to.len() > SMALL_BUCKET
    }

    /// The first corner `j` whose end vertex an earlier corner `i` has
    /// (two half-edges a→b): `(i, j)`.
    fn first_repeated_end(&self) -> Option<(usize, usize)> {
        if self.big() {
            return (0..self.to.len()).find_map(|j| {
                let i = self.by_to[&self.to[j]];
                (i != j).then_some((i, j))
            });
        }
        (1..self.to.len()).find_map(|j| self.to[..j].iter().position(|&t| t == self.to[j]).map(|i| (i, j)))
    }

    /// The corner ending at `v`.
    fn with_end(&self, v: u32) -> Option<usize> {
        if self.big() {
            self.by_to.get(&v).copied()
        } else {
            self.to.iter().position(|&t| t == v)
        }
    }

    /// The corner whose previous half-edge starts at `v`.
    fn with_prev_from(&self, v: u32) -> Option<usize> {
        if self.big() {
            self.by_prev_from.get(&v).copied()
        } else {
            self.prev_from.iter().position(|&p| p == v)
        }
    }

    /// Fan order of the loaded bucket (see [`small_bucket`]).
    fn fan(&mut self, fan: &mut [HalfEdgeId]) -> Verdict {
        if let Some((i, j)) = self.first_repeated_end() {
            return Verdict::RepeatedEnd(i, j);
        }
        let k = fan.len();
        let mut boundary_start = None;
        let mut boundary_count = 0;
        for i in 0..k {
            match self.with_prev_from(self.to[i]) {
                Some(_) => {}
                None => {
                    boundary_count += 1;
                    boundary_start.get_or_insert(i);
                }
            }
        }
        if boundary_count > 1 {
            return Verdict::SeveralFans;
        }
        let start = boundary_start.unwrap_or(0);
        self.order.clear();
        let mut i = start;
        loop {
            self.order.push(fan[i]);
            match self.with_end(self.prev_from[i]) {
                Some(j) if j != start && self.order.len() <= k => i = j,
                _ => break,
            }
        }
        if self.order.len() != k {
            // One fan reached only part of the faces at the vertex: several fans.
            return Verdict::SeveralFans;
        }
        fan.copy_from_slice(&self.order);
        Verdict::Fan { boundary: boundary_start.is_some() }
    }

    /// Number of separate fans among the corners, in time linear in their
    /// number (a vertex may join 10⁵ fans).
    ///
    /// The fan successor of a corner is the corner ending at its previous
    /// vertex (twin(prev(h))), and no two corners share a successor, so the
    /// fans are disjoint chains: open ones, each starting at a corner
    /// without twin (nothing precedes it), and closed cycles. Walking the
    /// open ones from their starts, then the cycles from any unvisited
    /// corner, visits every corner once.
    fn count_fans(&self) -> usize {
        let k = self.to.len();
        let mut visited = vec![false; k];
        let open_starts = (0..k).filter(|&i| self.with_prev_from(self.to[i]).is_none());
        let mut fans = 0;
        for start in open_starts.chain(0..k) {
            if visited[start] {
                continue;
            }
            fans += 1;
            let mut i = start;
            while !visited[i] {
                visited[i] = true;
                match self.with_end(self.prev_from[i]) {
                    Some(j) => i = j,
                    None => break,
                }
            }
        }
        fans
    }
}

#[cfg(test)]
mod reference;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::{self, SplitMix64};
    use proptest::prelude::*;

    fn same(new: &Topology, old: &Topology) -> bool {
        new.vertex_count == old.vertex_count
            && new.faces == old.faces
            && (0..new.half_edge_count()).all(|h| new.he_face.get(h) == old.he_face.get(h))
            && new.he_twin == old.he_twin
            && new.edge_numbering() == old.edge_numbering()
            && new.edge_count() == old.edge_numbering().edge_he.len()
            && new.fan_offsets == old.fan_offsets
            && new.fan == old.fan
            && new.vertex_on_boundary == old.vertex_on_boundary
            && new.loop_offsets == old.loop_offsets
            && new.loop_he == old.loop_he
            && new.face_component == old.face_component
            && new.component_count == old.component_count
            && new.diagonal_conflicts() == brute_force_diagonal_conflicts(new)
            && old.diagonal_conflicts() == brute_force_diagonal_conflicts(old)
    }

    /// The faces with a diagonal that is an edge or another face's diagonal
    /// (unordered vertex pairs, hashed), ascending.
    fn brute_force_diagonal_conflicts(t: &Topology) -> Vec<u32> {
        use std::collections::HashSet;
        let key = |a: u32, b: u32| (a.min(b), a.max(b));
        let faces = t.faces();
        let edges: HashSet<(u32, u32)> =
            faces.iter().flat_map(|f| (0..f.len()).map(move |i| key(f[i], f[(i + 1) % f.len()]))).collect();
        let diagonals = |f: &[u32]| {
            let m = f.len();
            let pairs = (0..m).flat_map(move |i| (i + 2..m).filter(move |&j| j - i != m - 1).map(move |j| (i, j)));
            pairs.map(|(i, j)| key(f[i], f[j])).collect::<Vec<_>>()
        };
        let mut faces_of: HashMap<(u32, u32), usize> = HashMap::new();
        for f in faces.iter() {
            for d in diagonals(f) {
                *faces_of.entry(d).or_default() += 1;
            }
        }
        (0..faces.len() as u32)
            .filter(|&f| diagonals(faces.face(f as usize)).iter().any(|d| edges.contains(d) || faces_of[d] > 1))
            .collect()
    }

    #[test]
    fn diagonal_conflicts_of_quad_meshes_agree_with_brute_force() {
        // A spindle: n quads (0, r_k, 1, r_k+1) between two poles, every one
        // with the diagonal 0-1 (conflicts at every face, in buckets of n,
        // pairwise and hashed), and a pillow's two quads sharing both.
        for n in [3u32, 4, 5, 16, 17, 40] {
            let ring = |k: u32| 2 + k % n;
            let spindle: Vec<[u32; 4]> = (0..n).map(|k| [0, ring(k), 1, ring(k + 1)]).collect();
            let t = Topology::new(FaceList::from_faces(&spindle), n as usize + 2).unwrap();
            assert_eq!(t.diagonal_conflicts(), (0..n).collect::<Vec<_>>());
            agree(FaceList::from_faces(&spindle), n as usize + 2).unwrap();
        }
        let pillow = shapes::pillow();
        assert_eq!(pillow.topology().diagonal_conflicts(), [0, 1]);
        // Fine quad meshes have none, whatever the thread split.
        assert!(shapes::torus(150, 120).topology().diagonal_conflicts().is_empty());
    }

    fn agree(faces: FaceList, vertex_count: usize) -> Result<(), String> {
        match (Topology::new(faces.clone(), vertex_count), reference::build(faces, vertex_count)) {
            (Ok(new), Ok(old)) if same(&new, &old) => Ok(()),
            (Err(new), Err(old)) if new == old => Ok(()),
            (new, old) => Err(format!("new {:?}\nold {:?}", new.map(|_| "ok"), old.map(|_| "ok"))),
        }
    }

    /// Faces of a shape, damaged at random: faces dropped (boundaries,
    /// bowtie vertices; for one seed in three nothing else), reversed (orientation errors), duplicated or
    /// repeated reversed (edges of three or four faces), vertices relabelled.
    fn damaged(faces: &FaceList, vertex_count: usize, seed: u64, rate: f64) -> (FaceList, usize) {
        let mut rng = SplitMix64(seed);
        let mut label: Vec<u32> = (0..vertex_count as u32).collect();
        for i in (1..label.len()).rev() {
            label.swap(i, rng.below(i + 1));
        }
        // One seed in three only drops faces (more of them): bowtie vertices.
        let drop_only = seed % 3 == 0;
        let mut out = FaceList::new();
        for face in faces.iter() {
            let face: Vec<u32> = face.iter().map(|&v| label[v as usize]).collect();
            let roll = rng.next_f64();
            if roll < rate || (drop_only && roll < 3.0 * rate) {
                continue;
            }
            if drop_only {
                out.push(&face);
                continue;
            }
            let reversed: Vec<u32> = face.iter().rev().copied().collect();
            if roll < 2.0 * rate {
                out.push(&reversed);
            } else if roll < 2.5 * rate {
                out.push(&face);
                out.push(&face);
            } else if roll < 3.0 * rate {
                out.push(&face);
                out.push(&reversed);
                out.push(&face);
            } else {
                out.push(&face);
            }
        }
        if out.is_empty() {
            out.push(&[0, 1, 2]);
        }
        (out, vertex_count)
    }

    fn shape(k: usize) -> crate::Mesh {
        match k % 8 {
            0 => shapes::torus(3 + k % 5, 3 + k % 4),
            1 => shapes::pyramid(3 + 7 * (k % 6)), // apex valence up to 38: big buckets
            2 => shapes::quad_grid(1 + k % 6, 1 + k % 5),
            3 => shapes::triangle_grid(1 + k % 6, 2 + k % 4),
            4 => shapes::plate_with_holes(5, 5, &[(1, 1), (3, 3)], k % 2 == 0),
            5 => shapes::pillow(),
            6 => shapes::icosahedron(),
            _ => shapes::polygon_mix(&shapes::torus(6, 5), k as u64, 0.3, 0.2, 0.0),
        }
    }

    #[test]
    fn high_valence_fans_agree_with_the_reference() {
        // One vertex in 40 triangles, closed and open, split into two fans, reversed in part.
        for n in [20u32, 40] {
            let fan: Vec<[u32; 3]> = (0..n).map(|k| [0, 1 + k, 1 + (k + 1) % n]).collect();
            agree(FaceList::from_faces(&fan), n as usize + 1).unwrap();
            agree(FaceList::from_faces(&fan[1..]), n as usize + 1).unwrap();
            let two: Vec<[u32; 3]> = fan.iter().enumerate().filter(|(k, _)| k % 10 != 0).map(|(_, f)| *f).collect();
            agree(FaceList::from_faces(&two), n as usize + 1).unwrap();
            let mut flipped = fan.clone();
            flipped[7] = [0, 1 + (7 + 1) % n, 8];
            agree(FaceList::from_faces(&flipped), n as usize + 1).unwrap();
        }
    }

    #[test]
    fn meshes_split_across_threads_agree_with_the_reference() {
        // Above PARALLEL_CORNERS: vertex ranges per thread, whatever the count.
        let big = [
            shapes::torus(150, 120),
            shapes::polygon_mix(&shapes::torus(200, 150), 7, 0.3, 0.2, 0.0),
            shapes::plate_with_holes(140, 130, &[(10, 10), (70, 40), (100, 100)], true),
        ];
        for (i, m) in big.iter().enumerate() {
            assert!(m.topology().half_edge_count() > PARALLEL_CORNERS);
            for (seed, rate) in [(0, 0.0), (1, 1e-4), (2, 1e-4), (3, 1e-3), (4, 2e-5), (5, 1e-3)] {
                let (faces, n) = damaged(m.topology().faces(), m.topology().vertex_count(), seed + 10 * i as u64, rate);
                for threads in [1, 2, 3, 7] {
                    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                    pool.install(|| agree(faces.clone(), n))
                        .unwrap_or_else(|e| panic!("shape {i}, seed {seed}, {threads} threads: {e}"));
                }
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

        /// The same topology, or the same first error, as the reference
        /// construction, on shapes damaged at random and on random soups.
        #[test]
        fn construction_agrees_with_the_reference(k in 0usize..64, seed in any::<u64>(), rate in prop_oneof![Just(0.0), 0.0..0.2f64]) {
            let m = shape(k);
            let (faces, n) = damaged(m.topology().faces(), m.topology().vertex_count(), seed, rate);
            agree(faces, n).map_err(TestCaseError::fail)?;
        }

        /// All-quad soups over few vertices: the fan walk's diagonal
        /// conflicts against the scan and brute force where they connect.
        #[test]
        fn random_quad_soups_agree_with_the_reference(faces in proptest::collection::vec(proptest::array::uniform4(0u32..7), 1..10)) {
            agree(FaceList::from_faces(&faces), 7).map_err(TestCaseError::fail)?;
        }

        #[test]
        fn random_soups_agree_with_the_reference(faces in proptest::collection::vec(proptest::collection::vec(0u32..9, 3..6), 1..12)) {
            agree(FaceList::from_faces(&faces), 8).map_err(TestCaseError::fail)?;
        }
    }
}
