//! Best-effort statistics for any soup, valid or not (what `subdiv info` shows
//! for a mesh that [`crate::Mesh::from_soup`] rejects).

use crate::error::MeshError;
use crate::geometry::Aabb;
use crate::soup::PolygonSoup;
use std::collections::{BTreeMap, HashMap};

/// Counts of every defect class in a soup, plus the statistics that do not need
/// valid connectivity. Produced by [`diagnose`].
#[derive(Clone, Debug, Default, PartialEq)]
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

/// Counts every defect of `soup` without stopping at the first. Linear in size
/// (hash maps over edges); meant for reports, not for the hot path.
pub fn diagnose(soup: &PolygonSoup) -> Diagnosis {
    let n = soup.positions.len();
    let mut d = Diagnosis { vertices: n, faces: soup.faces.len(), ..Default::default() };
    let mut used = vec![false; n];
    let mut good_faces = Vec::new();
    for (f, face) in soup.faces.iter().enumerate() {
        *d.face_sizes.entry(face.len()).or_insert(0) += 1;
        let bad_range = face.iter().filter(|&&v| v as usize >= n).count();
        d.out_of_range_indices += bad_range;
        let repeated = (1..face.len()).any(|k| face[..k].contains(&face[k]));
        d.faces_with_repeated_index += usize::from(repeated);
        d.faces_too_small += usize::from(face.len() < 3);
        for &v in face {
            if let Some(u) = used.get_mut(v as usize) {
                *u = true;
            }
        }
        if bad_range == 0 && !repeated && face.len() >= 2 {
            good_faces.push(f);
        }
    }
    d.non_finite_vertices = soup.positions.iter().filter(|p| !p.is_finite()).count();
    d.isolated_vertices = used.iter().filter(|&&u| !u).count();
    d.bbox = Aabb::of(soup.positions.iter().zip(&used).filter(|(p, &u)| u && p.is_finite()).map(|(p, _)| *p));

    // Undirected edge → (faces traversing a→b with a < b, faces traversing b→a).
    let mut edges: HashMap<(u32, u32), (Vec<u32>, Vec<u32>)> = HashMap::new();
    for &f in &good_faces {
        let face = soup.faces.face(f);
        for k in 0..face.len() {
            let (a, b) = (face[k], face[(k + 1) % face.len()]);
            let entry = edges.entry((a.min(b), a.max(b))).or_default();
            if a < b {
                entry.0.push(f as u32)
            } else {
                entry.1.push(f as u32)
            }
        }
    }
    d.edges = edges.len();
    let mut parent: Vec<u32> = (0..soup.faces.len() as u32).collect();
    for (fwd, bwd) in edges.values() {
        let count = fwd.len() + bwd.len();
        if count > 2 {
            d.non_manifold_edges += 1;
        } else if count == 2 && (fwd.len() == 2 || bwd.len() == 2) {
            d.inconsistently_oriented_edges += 1;
        }
        let mut all = fwd.iter().chain(bwd);
        if let Some(&first) = all.next() {
            for &g in all {
                union(&mut parent, first, g);
            }
        }
    }
    d.components = good_faces.iter().filter(|&&f| find(&mut parent, f as u32) == f as u32).count();

    // Fans per vertex: faces at v joined when they share an edge at v.
    let mut corners: HashMap<u32, Vec<u32>> = HashMap::new();
    for &f in &good_faces {
        for &v in soup.faces.face(f) {
            corners.entry(v).or_default().push(f as u32);
        }
    }
    let mut local: HashMap<u32, u32> = HashMap::new();
    for (&v, faces_at_v) in &corners {
        local.clear();
        for (i, &f) in faces_at_v.iter().enumerate() {
            local.insert(f, i as u32);
        }
        let mut lp: Vec<u32> = (0..faces_at_v.len() as u32).collect();
        for &f in faces_at_v {
            let face = soup.faces.face(f as usize);
            let k = face.iter().position(|&x| x == v).unwrap_or(0);
            for other in [face[(k + 1) % face.len()], face[(k + face.len() - 1) % face.len()]] {
                if let Some((fwd, bwd)) = edges.get(&(v.min(other), v.max(other))) {
                    for &g in fwd.iter().chain(bwd) {
                        if let Some(&j) = local.get(&g) {
                            union(&mut lp, local[&f], j);
                        }
                    }
                }
            }
        }
        let fans = (0..lp.len() as u32).filter(|&i| find(&mut lp, i) == i).count();
        d.non_manifold_vertices += usize::from(fans > 1);
    }
    d.first_error = crate::Mesh::from_soup(soup.clone()).err();
    d
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
