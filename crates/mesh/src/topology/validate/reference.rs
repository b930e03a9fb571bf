//! The construction [`Topology::new`] had before its buckets held
//! everything a vertex needs (two more counting sorts, an incoming CSR,
//! stamps over all vertices): the reference its results and errors are
//! compared with, on random valid and invalid face lists.

use super::super::{HalfEdgeFaces, Topology, NONE};
use crate::error::MeshError;
use crate::ids::HalfEdgeId;
use crate::soup::FaceList;
use std::sync::OnceLock;

pub(super) fn build(faces: FaceList, vertex_count: usize) -> Result<Topology, MeshError> {
    if faces.is_empty() {
        return Err(MeshError::NoFaces);
    }
    check_faces(&faces, vertex_count)?;
    let nv = vertex_count;
    let nh = faces.corner_count();
    if nh >= NONE as usize {
        return Err(MeshError::TooLarge { what: "more than 2³² − 2 corners" });
    }
    let offsets = faces.offsets();
    let idx = faces.indices();

    let mut he_face = vec![0u32; nh];
    for f in 0..faces.len() {
        he_face[offsets[f] as usize..offsets[f + 1] as usize].fill(f as u32);
    }
    // End vertex of every half-edge, computed once (it is needed three
    // times per half-edge below, and a closure would chase he_face each time).
    let mut he_to = vec![0u32; nh];
    for f in 0..faces.len() {
        let (a, b) = (offsets[f] as usize, offsets[f + 1] as usize);
        he_to[a..b - 1].copy_from_slice(&idx[a + 1..b]);
        he_to[b - 1] = idx[a];
    }
    let to = |h: usize| -> u32 { he_to[h] };

    // Outgoing and incoming half-edges per vertex, by counting sort (CSR).
    let out_offsets = csr_offsets(nv, idx.iter().copied());
    let out = csr_fill(&out_offsets, (0..nh).map(|h| (idx[h], h as u32)));
    let in_offsets = csr_offsets(nv, (0..nh).map(to));
    let incoming = csr_fill(&in_offsets, (0..nh).map(|h| (to(h), h as u32)));

    // Twins: for each vertex a, stamp its outgoing half-edges by target, then
    // every incoming half-edge x→a finds its twin a→x in O(1).
    let mut stamp = vec![NONE; nv];
    let mut slot = vec![NONE; nv];
    let mut he_twin = vec![NONE; nh];
    for a in 0..nv {
        for &h in &out[out_offsets[a] as usize..out_offsets[a + 1] as usize] {
            let b = to(h as usize) as usize;
            if stamp[b] == a as u32 {
                let other = slot[b];
                return Err(same_direction_error(&he_face, a as u32, b as u32, other, h, &out, &out_offsets, &to));
            }
            stamp[b] = a as u32;
            slot[b] = h;
        }
        for &g in &incoming[in_offsets[a] as usize..in_offsets[a + 1] as usize] {
            let x = idx[g as usize] as usize;
            if stamp[x] == a as u32 {
                he_twin[g as usize] = slot[x];
            }
        }
    }

    // Fans: walk h ← twin(prev(h)) from the boundary half-edge (or any one).
    let prev = |h: usize| -> usize {
        let f = he_face[h] as usize;
        if h == offsets[f] as usize {
            offsets[f + 1] as usize - 1
        } else {
            h - 1
        }
    };
    let mut fan = Vec::with_capacity(nh);
    let mut fan_offsets = Vec::with_capacity(nv + 1);
    let mut vertex_on_boundary = vec![false; nv];
    fan_offsets.push(0u32);
    for v in 0..nv {
        let outs = &out[out_offsets[v] as usize..out_offsets[v + 1] as usize];
        if !outs.is_empty() {
            let mut boundary_starts = outs.iter().copied().filter(|&h| he_twin[h as usize] == NONE);
            let first_boundary = boundary_starts.next();
            if boundary_starts.next().is_some() {
                // Each open fan starts at a boundary half-edge: two of them, two fans at least.
                let fans = count_fans(outs, &he_twin, &prev, nh);
                return Err(MeshError::NonManifoldVertex { vertex: v as u32, fans });
            }
            vertex_on_boundary[v] = first_boundary.is_some();
            let start = first_boundary.unwrap_or(outs[0]);
            let mut h = start;
            let mut visited = 0usize;
            loop {
                fan.push(HalfEdgeId(h));
                visited += 1;
                let t = he_twin[prev(h as usize)];
                if t == NONE || t == start || visited > outs.len() {
                    break;
                }
                h = t;
            }
            if visited != outs.len() {
                // One fan reached only part of the faces at v: several fans.
                let fans = count_fans(outs, &he_twin, &prev, nh);
                return Err(MeshError::NonManifoldVertex { vertex: v as u32, fans });
            }
        }
        fan_offsets.push(fan.len() as u32);
    }

    // Boundary loops: after boundary half-edge a→b comes b's boundary half-edge.
    let mut loop_offsets = vec![0u32];
    let mut loop_he = Vec::new();
    let mut seen = vec![false; nh];
    for h0 in 0..nh {
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

    // Connected components over faces, by breadth-first search through twins.
    let nf = faces.len();
    let mut face_component = vec![NONE; nf];
    let mut component_count = 0u32;
    let mut queue = Vec::new();
    for f0 in 0..nf {
        if face_component[f0] != NONE {
            continue;
        }
        face_component[f0] = component_count;
        queue.push(f0);
        while let Some(f) = queue.pop() {
            for h in offsets[f] as usize..offsets[f + 1] as usize {
                let t = he_twin[h];
                if t != NONE {
                    let g = he_face[t as usize] as usize;
                    if face_component[g] == NONE {
                        face_component[g] = component_count;
                        queue.push(g);
                    }
                }
            }
        }
        component_count += 1;
    }

    Ok(Topology {
        vertex_count: nv as u32,
        faces,
        he_face: HalfEdgeFaces::Table(he_face),
        he_twin,
        edges: OnceLock::new(),
        diagonal_conflicts: OnceLock::new(),
        fan_offsets,
        fan,
        vertex_on_boundary,
        loop_offsets,
        loop_he,
        face_component,
        component_count,
    })
}

/// CSR offsets of a bucket count: `keys` yields the bucket of every item.
fn csr_offsets(buckets: usize, keys: impl Iterator<Item = u32>) -> Vec<u32> {
    let mut offsets = vec![0u32; buckets + 1];
    for k in keys {
        offsets[k as usize + 1] += 1;
    }
    for i in 0..buckets {
        offsets[i + 1] += offsets[i];
    }
    offsets
}

/// Fills CSR buckets in item order (a stable counting sort).
fn csr_fill(offsets: &[u32], items: impl Iterator<Item = (u32, u32)>) -> Vec<u32> {
    let mut cursor: Vec<u32> = offsets[..offsets.len() - 1].to_vec();
    let mut out = vec![0u32; *offsets.last().unwrap_or(&0) as usize];
    for (bucket, item) in items {
        let c = &mut cursor[bucket as usize];
        out[*c as usize] = item;
        *c += 1;
    }
    out
}

/// Two half-edges a→b exist: either the undirected edge has more than two
/// faces (non-manifold) or exactly two that agree in direction (orientation).
#[allow(clippy::too_many_arguments)]
fn same_direction_error(
    he_face: &[u32],
    a: u32,
    b: u32,
    first: u32,
    second: u32,
    out: &[u32],
    out_offsets: &[u32],
    to: &dyn Fn(usize) -> u32,
) -> MeshError {
    let count = |from: u32, target: u32| {
        out[out_offsets[from as usize] as usize..out_offsets[from as usize + 1] as usize]
            .iter()
            .filter(|&&h| to(h as usize) == target)
            .count()
    };
    let faces = count(a, b) + count(b, a);
    if faces > 2 {
        let (lo, hi) = (a.min(b), a.max(b));
        MeshError::NonManifoldEdge { a: lo, b: hi, faces }
    } else {
        MeshError::InconsistentOrientation { a, b, face_a: he_face[first as usize], face_b: he_face[second as usize] }
    }
}

/// Number of separate fans among a vertex's outgoing half-edges `outs`, in
/// time linear in their number (a vertex may join 10⁵ fans).
///
/// The fan successor of h is twin(prev(h)), again outgoing from the vertex,
/// and no two half-edges share a successor, so the fans are disjoint chains:
/// open ones, each starting at a boundary half-edge (nothing precedes a
/// half-edge without twin), and closed cycles. Walking the open ones from
/// their starts, then the cycles from any unvisited half-edge, visits every
/// half-edge once. `half_edge_count` sizes the visited marks.
fn count_fans(outs: &[u32], he_twin: &[u32], prev: &dyn Fn(usize) -> usize, half_edge_count: usize) -> usize {
    let mut visited = vec![false; half_edge_count];
    let open_starts = outs.iter().filter(|&&h| he_twin[h as usize] == NONE);
    let mut fans = 0;
    for &start in open_starts.chain(outs) {
        if visited[start as usize] {
            continue;
        }
        fans += 1;
        let mut h = start;
        while !visited[h as usize] {
            visited[h as usize] = true;
            h = he_twin[prev(h as usize)];
            if h == NONE {
                break;
            }
        }
    }
    fans
}

/// Per-face checks that need no connectivity: size, index range, repeats.
/// One pass over the corners, whatever the face sizes (a face of 10⁶
/// corners costs 10⁶ steps, not 10¹²/2).
fn check_faces(faces: &FaceList, vertex_count: usize) -> Result<(), MeshError> {
    if vertex_count >= NONE as usize {
        return Err(MeshError::TooLarge { what: "more than 2³² − 2 vertices" });
    }
    // The last face each vertex was seen in: a second sighting in the same face is a repeat.
    let mut seen_in = vec![NONE; vertex_count];
    for (f, face) in faces.iter().enumerate() {
        if face.len() < 3 {
            return Err(MeshError::FaceTooSmall { face: f as u32, size: face.len() });
        }
        for &v in face {
            let Some(seen) = seen_in.get_mut(v as usize) else {
                return Err(MeshError::IndexOutOfRange { face: f as u32, vertex: v, vertex_count });
            };
            if *seen == f as u32 {
                return Err(MeshError::RepeatedIndex { face: f as u32, vertex: v });
            }
            *seen = f as u32;
        }
    }
    Ok(())
}
