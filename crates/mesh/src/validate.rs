//! Best-effort statistics for any soup, valid or not (what `subdiv info` shows
//! for a mesh that [`crate::Mesh::from_soup`] rejects).

use crate::error::MeshError;
use crate::geometry::Aabb;
use crate::soup::PolygonSoup;
use std::collections::BTreeMap;

/// Counts of every defect class in a soup, plus the statistics that do not need
/// valid connectivity. Produced by [`diagnose`]; `#[non_exhaustive]`, read
/// through its public fields (a new statistic is not a breaking change).
///
/// ```
/// let d = subdiv_mesh::diagnose(&subdiv_mesh::shapes::cube().into_soup());
/// assert_eq!((d.vertices, d.faces, d.edges, d.components), (8, 6, 12, 1));
/// ```
///
/// A struct literal does not compile outside the crate (results of this
/// crate are made by it):
///
/// ```compile_fail,E0639
/// let d = subdiv_mesh::Diagnosis { vertices: 8, ..Default::default() };
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct Diagnosis {
    /// Vertices stored.
    pub vertices: usize,
    /// Faces stored.
    pub faces: usize,
    /// Distinct undirected edges among faces with in-range indices.
    pub edges: usize,
    /// Face size → count.
    pub face_sizes: BTreeMap<usize, usize>,
    /// Faces with fewer than 3 corners.
    pub faces_too_small: usize,
    /// Face corners referring to missing vertices.
    pub out_of_range_indices: usize,
    /// Faces that repeat a vertex.
    pub faces_with_repeated_index: usize,
    /// Vertices with a NaN or infinite coordinate.
    pub non_finite_vertices: usize,
    /// Edges with more than two faces.
    pub non_manifold_edges: usize,
    /// Edges with two faces traversing them the same way.
    pub inconsistently_oriented_edges: usize,
    /// Vertices whose faces form more than one fan.
    pub non_manifold_vertices: usize,
    /// Vertices no face uses.
    pub isolated_vertices: usize,
    /// Connected components of faces (through shared edges).
    pub components: usize,
    /// Bounding box of the finite, referenced vertices.
    pub bbox: Option<Aabb>,
    /// The first error [`crate::Mesh::from_soup`] reports, if any.
    pub first_error: Option<MeshError>,
}

/// Counts every defect of `soup` without stopping at the first, in time
/// linear in the number of corners whatever the input (duplicate faces, huge
/// fans, many faces on one edge; no per-edge or per-vertex face lists are
/// scanned per face). Meant for reports, not for the hot path.
pub fn diagnose(soup: &PolygonSoup) -> Diagnosis {
    let n = soup.positions.len();
    let faces = &soup.faces;
    let mut d = Diagnosis { vertices: n, faces: faces.len(), ..Default::default() };
    let mut used = vec![false; n];
    // The last face each vertex was seen in: a repeated index in one pass, whatever the face size.
    let mut seen_in = vec![usize::MAX; n];
    let mut out_of_range = Vec::new();
    let mut good = vec![false; faces.len()];
    for (f, face) in faces.iter().enumerate() {
        *d.face_sizes.entry(face.len()).or_insert(0) += 1;
        let mut repeated = false;
        out_of_range.clear();
        for &v in face {
            match seen_in.get_mut(v as usize) {
                Some(seen) => {
                    repeated |= *seen == f;
                    *seen = f;
                    used[v as usize] = true;
                }
                None => out_of_range.push(v),
            }
        }
        d.out_of_range_indices += out_of_range.len();
        if !repeated && out_of_range.len() > 1 {
            out_of_range.sort_unstable();
            repeated = out_of_range.windows(2).any(|w| w[0] == w[1]);
        }
        d.faces_with_repeated_index += usize::from(repeated);
        d.faces_too_small += usize::from(face.len() < 3);
        good[f] = out_of_range.is_empty() && !repeated && face.len() >= 2;
    }
    d.non_finite_vertices = soup.positions.iter().filter(|p| !p.is_finite()).count();
    d.isolated_vertices = used.iter().filter(|&&u| !u).count();
    d.bbox = Aabb::of(soup.positions.iter().zip(&used).filter(|&(p, &u)| u && p.is_finite()).map(|(p, _)| *p));

    let edges = group_edges(soup, &good);
    d.edges = edges.records.len();
    for e in &edges.records {
        let count = e.forward + e.backward;
        if count > 2 {
            d.non_manifold_edges += 1;
        } else if count == 2 && (e.forward == 2 || e.backward == 2) {
            d.inconsistently_oriented_edges += 1;
        }
    }
    let mut face_sets = edges.face_sets;
    d.components = (0..faces.len()).filter(|&f| good[f] && find(&mut face_sets, f as u32) == f as u32).count();

    // Fans per vertex: the corners at v joined through its edges are one fan
    // each; count the roots among the corners of good faces, per vertex.
    let mut corner_sets = edges.corner_sets;
    let mut fans = vec![0u32; n];
    for (f, face_range) in faces.offsets().windows(2).enumerate() {
        if good[f] {
            for c in face_range[0]..face_range[1] {
                if find(&mut corner_sets, c) == c {
                    let v = faces.indices()[c as usize] as usize;
                    fans[v] = fans[v].saturating_add(1);
                }
            }
        }
    }
    d.non_manifold_vertices = fans.iter().filter(|&&k| k > 1).count();
    d.first_error = crate::Mesh::from_soup(soup.clone()).err();
    d
}

/// One undirected edge (lo, hi), lo < hi, of the good faces.
struct EdgeRecord {
    /// Its smaller vertex (tells a current stamp from a stale one).
    lo: u32,
    /// The face of its first half-edge, and that face's corners at lo and at hi.
    first: (u32, u32, u32),
    /// Number of half-edges lo → hi.
    forward: u32,
    /// Number of half-edges hi → lo.
    backward: u32,
}

/// The undirected edges of the good faces, and what they join.
struct Edges {
    records: Vec<EdgeRecord>,
    /// Union-find over faces: faces sharing an edge are joined.
    face_sets: Vec<u32>,
    /// Union-find over corners: the corners at the same end of one edge
    /// (one per face along it) are joined.
    corner_sets: Vec<u32>,
}

/// Groups the half-edges of the good faces by undirected edge without
/// hashing: half-edges bucketed by their smaller end (a counting sort), then,
/// per bucket, a stamp per larger end finds the edge in O(1). Each half-edge
/// is joined to the first one of its edge only, which joins all of them
/// (union-find is transitive) in time linear in the half-edges, however many
/// faces share the edge.
fn group_edges(soup: &PolygonSoup, good: &[bool]) -> Edges {
    let (n, faces) = (soup.positions.len(), &soup.faces);
    let (offsets, idx) = (faces.offsets(), faces.indices());
    // Corner c of a face starts half-edge c → next(c).
    let mut next = vec![0u32; idx.len()];
    let mut bucket_size = vec![0u32; n + 1];
    for f in (0..faces.len()).filter(|&f| good[f]) {
        let (a, b) = (offsets[f], offsets[f + 1]);
        for c in a..b {
            next[c as usize] = if c + 1 == b { a } else { c + 1 };
            let lo = idx[c as usize].min(idx[next[c as usize] as usize]);
            bucket_size[lo as usize + 1] += 1;
        }
    }
    for v in 0..n {
        bucket_size[v + 1] += bucket_size[v];
    }
    let bucket_start = bucket_size;
    let mut cursor = bucket_start.clone();
    let mut by_lo = vec![0u32; bucket_start[n] as usize];
    for f in (0..faces.len()).filter(|&f| good[f]) {
        for c in offsets[f]..offsets[f + 1] {
            let lo = idx[c as usize].min(idx[next[c as usize] as usize]) as usize;
            by_lo[cursor[lo] as usize] = c;
            cursor[lo] += 1;
        }
    }

    let mut face_of = vec![0u32; idx.len()];
    for f in 0..faces.len() {
        face_of[offsets[f] as usize..offsets[f + 1] as usize].fill(f as u32);
    }
    let mut records: Vec<EdgeRecord> = Vec::new();
    let mut face_sets: Vec<u32> = (0..faces.len() as u32).collect();
    let mut corner_sets: Vec<u32> = (0..idx.len() as u32).collect();
    // Per larger end, the record of the edge it last closed (current if that edge's lo is this bucket's).
    let mut stamp = vec![u32::MAX; n];
    for lo in 0..n {
        for &c in &by_lo[bucket_start[lo] as usize..bucket_start[lo + 1] as usize] {
            let (a, b) = (idx[c as usize], idx[next[c as usize] as usize]);
            let hi = a.max(b) as usize;
            let (at_lo, at_hi) = if a < b { (c, next[c as usize]) } else { (next[c as usize], c) };
            let face = face_of[c as usize];
            let current = records.get(stamp[hi] as usize).is_some_and(|r| r.lo == lo as u32);
            if current {
                let (first_face, first_at_lo, first_at_hi) = records[stamp[hi] as usize].first;
                union(&mut face_sets, first_face, face);
                union(&mut corner_sets, first_at_lo, at_lo);
                union(&mut corner_sets, first_at_hi, at_hi);
            } else {
                stamp[hi] = records.len() as u32;
                records.push(EdgeRecord { lo: lo as u32, first: (face, at_lo, at_hi), forward: 0, backward: 0 });
            }
            let record = &mut records[stamp[hi] as usize];
            if a < b {
                record.forward += 1;
            } else {
                record.backward += 1;
            }
        }
    }
    Edges { records, face_sets, corner_sets }
}

fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        parent[x as usize] = parent[parent[x as usize] as usize];
        x = parent[x as usize];
    }
    x
}

fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        parent[ra.max(rb) as usize] = ra.min(rb);
    }
}
