//! Diagonal conflicts: the faces of four or more corners one of whose
//! diagonals at a corner a — (a, w), w a corner of the face not adjacent to
//! a — is also an edge at a or a diagonal at a of another face. Only these
//! faces can find a diagonal blocked when the mesh is triangulated over its
//! own corners (`check_triangulation`).
//!
//! All-quad meshes get the list from [`Topology::new`]'s fan walk, which
//! reads every corner's face row anyway ([`QuadConflicts`]: one more corner
//! from the same cache line). Other meshes get it at the first query, from a
//! scan over the vertices ([`ConflictScan`]).

use super::Topology;
use crate::ids::{HalfEdgeId, VertexId};
use rayon::prelude::*;
use std::collections::HashMap;

impl Topology {
    /// The faces with a diagonal conflict (module docs), ascending, each
    /// once; empty for a triangle mesh and for any fine quad mesh. Time
    /// linear in Σ m(m − 3) over the faces of m > 3 corners at the first
    /// query (none for an all-quad mesh: the construction found them).
    pub(crate) fn diagonal_conflicts(&self) -> &[u32] {
        self.diagonal_conflicts.get_or_init(|| ConflictScan { t: self }.faces())
    }
}

/// Sorted, without repeats.
fn sorted_unique(mut marks: Vec<u32>) -> Vec<u32> {
    marks.sort_unstable();
    marks.dedup();
    marks
}

/// The conflicts of an all-quad mesh, vertex by vertex, from what the fan
/// walk gathers for each corner at a: its end vertex and its previous
/// vertex (together, a's neighbours), and its far corner (the end of the
/// face's diagonal at a: half-edge h ^ 2 starts there).
#[derive(Default)]
pub(super) struct QuadConflicts {
    marks: Vec<u32>,
    /// For buckets too big to compare pairwise: first face by far corner.
    by_far: HashMap<u32, u32>,
}

impl QuadConflicts {
    /// Marks the faces around one vertex whose diagonal there is blocked:
    /// `fan` are the vertex's corners (in any order; face = half-edge / 4),
    /// `ends`, `prevs` and `fars` their end, previous and far vertices,
    /// `is_neighbour` whether a vertex is one of the ends or prevs.
    #[inline]
    pub(super) fn vertex(
        &mut self,
        fan: &[HalfEdgeId],
        (ends, prevs, fars): (&[u32], &[u32], &[u32]),
        is_neighbour: impl Fn(u32) -> bool,
    ) {
        let face = |i: usize| fan[i].0 / 4;
        let k = fars.len();
        if let (Ok(ends), Ok(prevs), Ok(fars)) = (ends.try_into(), prevs.try_into(), fars.try_into()) {
            // The usual valence, without a branch per comparison.
            if !any_conflict_of_four(ends, prevs, fars) {
                return;
            }
        }
        for i in 0..k {
            if is_neighbour(fars[i]) {
                self.marks.push(face(i));
            }
        }
        // Far corners repeated: pairwise for small fans, hashed for big ones.
        const PAIRWISE: usize = 16;
        if k <= PAIRWISE {
            for i in 0..k {
                for j in i + 1..k {
                    if fars[i] == fars[j] {
                        self.marks.extend([face(i), face(j)]);
                    }
                }
            }
            return;
        }
        self.by_far.clear();
        for (i, &w) in fars.iter().enumerate() {
            match self.by_far.get(&w) {
                Some(&first) => self.marks.extend([first, face(i)]),
                None => {
                    self.by_far.insert(w, face(i));
                }
            }
        }
    }

    /// The marks of several vertex ranges, in order, as the conflict list.
    pub(super) fn merge(parts: impl IntoIterator<Item = QuadConflicts>) -> Vec<u32> {
        sorted_unique(parts.into_iter().flat_map(|p| p.marks).collect())
    }
}

/// Whether a vertex of four quads has a conflict: a far corner equal to a
/// neighbour or to another far corner (or-ed, no early exit).
#[inline]
fn any_conflict_of_four(ends: &[u32; 4], prevs: &[u32; 4], fars: &[u32; 4]) -> bool {
    let mut hit = false;
    for (i, &w) in fars.iter().enumerate() {
        for j in 0..4 {
            hit |= (w == ends[j]) | (w == prevs[j]) | ((j > i) & (w == fars[j]));
        }
    }
    hit
}

/// The conflict scan for any mesh: at every vertex a, its neighbours and
/// the far corners of its faces are compared (pairwise on the stack for
/// small fans, by stamping vertices for big ones), and a far corner seen
/// twice marks every face that has it.
struct ConflictScan<'a> {
    t: &'a Topology,
}

/// Per-thread marks for big fans: `stamp[w] == a`: w seen at a, as a
/// neighbour (owner [`Stamps::EDGE`]) or as the far corner of face `owner[w]`.
#[derive(Default)]
struct Stamps {
    stamp: Vec<u32>,
    owner: Vec<u32>,
}

impl Stamps {
    const EDGE: u32 = u32::MAX;
}

impl ConflictScan<'_> {
    /// Vertices in blocks across threads, each block listing the faces it
    /// marks; the marks are merged into one list (the same whatever the
    /// order: a mark is a mark).
    fn faces(&self) -> Vec<u32> {
        let t = self.t;
        const BLOCK: usize = 1 << 14;
        let blocks: Vec<Vec<u32>> = (0..t.vertex_count().div_ceil(BLOCK))
            .into_par_iter()
            .map_init(Stamps::default, |stamps, block| {
                let mut marks = Vec::new();
                let end = ((block + 1) * BLOCK).min(t.vertex_count());
                for a in block * BLOCK..end {
                    self.vertex(VertexId(a as u32), stamps, &mut marks);
                }
                marks
            })
            .collect();
        sorted_unique(blocks.concat())
    }

    /// The corners of the face of fan half-edge h: (face, its first corner,
    /// size, h's position).
    #[inline]
    fn corner(&self, h: HalfEdgeId) -> (usize, usize, usize, usize) {
        let (start, end) = self.t.he_face_half_edges(h);
        (self.t.he_face(h).index(), start, end - start, h.index() - start)
    }

    /// The faces around `a` whose diagonals at `a` are blocked, pushed to
    /// `marks` (possibly repeated).
    fn vertex(&self, a: VertexId, stamps: &mut Stamps, marks: &mut Vec<u32>) {
        let t = self.t;
        let idx = t.faces().indices();
        let fan = t.vertex_fan(a);
        // Small fans compare their corners on the stack; others stamp vertices.
        const SMALL: usize = 16;
        if fan.len() <= SMALL {
            // Each face's corners once: (face, first corner, size, position of a).
            let mut corners = [(0, 0, 0, 0); SMALL];
            for (c, &h) in corners.iter_mut().zip(fan) {
                *c = self.corner(h);
            }
            let corners = &corners[..fan.len()];
            if !corners.iter().any(|c| c.2 > 3) {
                return;
            }
            let far_count: usize = corners.iter().map(|c| c.2 - 3).sum();
            if far_count <= 2 * SMALL {
                // Neighbours: the corners before and after a in each of its faces
                // (on the boundary, that includes the closing neighbour).
                let mut neighbours = [0u32; 2 * SMALL];
                let mut far = [(0u32, 0u32); 2 * SMALL];
                let (mut n, mut nf) = (0, 0);
                for &(f, start, m, k) in corners {
                    let face = &idx[start..start + m];
                    neighbours[n] = face[wrap(k + 1, m)];
                    neighbours[n + 1] = face[wrap(k + m - 1, m)];
                    n += 2;
                    for j in 2..m.saturating_sub(1) {
                        far[nf] = (face[wrap(k + j, m)], f as u32);
                        nf += 1;
                    }
                }
                for i in 0..nf {
                    let (w, f) = far[i];
                    if neighbours[..n].contains(&w) {
                        marks.push(f);
                    }
                    for &(x, g) in &far[i + 1..nf] {
                        if x == w {
                            marks.extend([f, g]);
                        }
                    }
                }
                return;
            }
        } else if !fan.iter().any(|&h| self.corner(h).2 > 3) {
            return;
        }
        let Stamps { stamp, owner } = stamps;
        if stamp.is_empty() {
            *stamp = vec![u32::MAX; t.vertex_count()];
            *owner = vec![Stamps::EDGE; t.vertex_count()];
        }
        for &h in fan {
            let (_, start, m, k) = self.corner(h);
            let face = &idx[start..start + m];
            for w in [face[wrap(k + 1, m)], face[wrap(k + m - 1, m)]] {
                stamp[w as usize] = a.0;
                owner[w as usize] = Stamps::EDGE;
            }
        }
        for &h in fan {
            let (f, start, m, k) = self.corner(h);
            for j in 2..m.saturating_sub(1) {
                let w = idx[start + wrap(k + j, m)] as usize;
                if stamp[w] == a.0 {
                    marks.push(f as u32);
                    if owner[w] != Stamps::EDGE {
                        marks.push(owner[w]);
                    }
                } else {
                    stamp[w] = a.0;
                    owner[w] = f as u32;
                }
            }
        }
    }
}

/// `i mod m` for `i < 2m`: a compare instead of a division.
#[inline(always)]
fn wrap(i: usize, m: usize) -> usize {
    if i >= m {
        i - m
    } else {
        i
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// One vertex's marks, on random corner data (vertices from a small
        /// range, so that repeats are common): face i is marked exactly when
        /// its far corner is a neighbour or another corner's far corner —
        /// for four corners (the branch-free test), small and hashed buckets.
        #[test]
        fn quad_vertex_marks_are_the_definition(
            corners in prop_oneof![
                proptest::collection::vec((0u32..12, 0u32..12, 0u32..12), 4),
                proptest::collection::vec((0u32..12, 0u32..12, 0u32..12), 1..40),
            ],
        ) {
            let ends: Vec<u32> = corners.iter().map(|c| c.0).collect();
            let prevs: Vec<u32> = corners.iter().map(|c| c.1).collect();
            let fars: Vec<u32> = corners.iter().map(|c| c.2).collect();
            // Face i is the quad of half-edges 4(i + 3)..: any order of faces.
            let fan: Vec<HalfEdgeId> = (0..fars.len()).map(|i| HalfEdgeId(4 * (i as u32 + 3) + (i as u32 % 4))).collect();
            let mut conflicts = QuadConflicts::default();
            let is_neighbour = |w| ends.contains(&w) || prevs.contains(&w);
            conflicts.vertex(&fan, (&ends, &prevs, &fars), is_neighbour);
            let marked = QuadConflicts::merge([conflicts]);
            let expected: Vec<u32> = (0..fars.len())
                .filter(|&i| is_neighbour(fars[i]) || (0..fars.len()).any(|j| j != i && fars[j] == fars[i]))
                .map(|i| i as u32 + 3)
                .collect();
            prop_assert_eq!(marked, expected);
        }
    }
}
