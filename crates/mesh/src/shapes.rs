//! Procedural shapes shared by tests, doc-tests, benches and xtask.
//!
//! Every shape is consistently oriented with outward normals and valid by
//! construction; parameters out of range are caller bugs and panic.

use crate::soup::FaceList;
use crate::{Mesh, PolygonSoup, PowerOfTwoScale};
use glam::DVec3;
use std::f64::consts::TAU;

fn build(positions: Vec<DVec3>, faces: FaceList) -> Mesh {
    Mesh::new(positions, faces).expect("procedural shapes are valid by construction")
}

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// Regular tetrahedron (4 triangles, all valences 3).
pub fn tetrahedron() -> Mesh {
    let p = vec![v(1., 1., 1.), v(1., -1., -1.), v(-1., 1., -1.), v(-1., -1., 1.)];
    build(p, FaceList::from_faces([[0u32, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]]))
}

/// Unit cube `[0,1]³` as 6 quads (all valences 3, bipartite: Catmull-Clark's
/// limit matrix is singular on it).
pub fn cube() -> Mesh {
    let p = (0..8).map(|i| v(f64::from(i & 1), f64::from((i >> 1) & 1), f64::from((i >> 2) & 1))).collect();
    let faces = [[0u32, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    build(p, FaceList::from_faces(faces))
}

/// Regular octahedron (8 triangles, valence 4).
pub fn octahedron() -> Mesh {
    let p = vec![v(1., 0., 0.), v(-1., 0., 0.), v(0., 1., 0.), v(0., -1., 0.), v(0., 0., 1.), v(0., 0., -1.)];
    let faces = [[0u32, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];
    build(p, FaceList::from_faces(faces))
}

/// Regular icosahedron with unit circumradius (20 triangles, valence 5).
pub fn icosahedron() -> Mesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let raw = [
        v(-1., t, 0.),
        v(1., t, 0.),
        v(-1., -t, 0.),
        v(1., -t, 0.),
        v(0., -1., t),
        v(0., 1., t),
        v(0., -1., -t),
        v(0., 1., -t),
        v(t, 0., -1.),
        v(t, 0., 1.),
        v(-t, 0., -1.),
        v(-t, 0., 1.),
    ];
    let faces = [
        [0u32, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    build(raw.iter().map(|p| p.normalize()).collect(), FaceList::from_faces(faces))
}

/// Flat open grid of `nx × ny` unit quads in the plane z = 0, vertex (i, j) at index j·(nx+1)+i.
pub fn quad_grid(nx: usize, ny: usize) -> Mesh {
    assert!(nx >= 1 && ny >= 1, "grid needs at least one cell");
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let p = (0..=ny).flat_map(|j| (0..=nx).map(move |i| v(i as f64, j as f64, 0.))).collect();
    let mut faces = FaceList::with_capacity(nx * ny, 4 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            faces.push(&[id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    build(p, faces)
}

/// Flat open grid of `2·nx·ny` triangles (each unit square split along the
/// same diagonal: interior valence 6, the regular Loop configuration).
pub fn triangle_grid(nx: usize, ny: usize) -> Mesh {
    assert!(nx >= 1 && ny >= 1, "grid needs at least one cell");
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let p = (0..=ny).flat_map(|j| (0..=nx).map(move |i| v(i as f64, j as f64, 0.))).collect();
    let mut faces = FaceList::with_capacity(2 * nx * ny, 6 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            faces.push(&[id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            faces.push(&[id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    build(p, faces)
}

/// Quad torus with `nu` segments around the axis and `nv` around the tube
/// (major radius 2, minor radius 0.75); genus 1, all valences 4.
pub fn torus(nu: usize, nv: usize) -> Mesh {
    assert!(nu >= 3 && nv >= 3, "torus needs at least 3 × 3 segments");
    let (r_major, r_minor) = (2.0, 0.75);
    let mut p = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        let u = TAU * i as f64 / nu as f64;
        for j in 0..nv {
            let w = TAU * j as f64 / nv as f64;
            let r = r_major + r_minor * w.cos();
            p.push(v(r * u.cos(), r * u.sin(), r_minor * w.sin()));
        }
    }
    let id = |i: usize, j: usize| ((i % nu) * nv + (j % nv)) as u32;
    let mut faces = FaceList::with_capacity(nu * nv, 4 * nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            faces.push(&[id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    build(p, faces)
}

/// Prism over a regular `n`-gon: two n-gon caps and n quads (all valences 3;
/// bipartite for even n).
pub fn prism(n: usize) -> Mesh {
    assert!(n >= 3, "prism needs an n-gon with n ≥ 3");
    let p = (0..2 * n)
        .map(|k| {
            let a = TAU * (k % n) as f64 / n as f64;
            v(a.cos(), a.sin(), if k < n { -0.5 } else { 0.5 })
        })
        .collect();
    let n32 = n as u32;
    let mut faces = FaceList::new();
    faces.push(&(0..n32).rev().collect::<Vec<_>>());
    faces.push(&(n32..2 * n32).collect::<Vec<_>>());
    for k in 0..n32 {
        let k1 = (k + 1) % n32;
        faces.push(&[k, k1, n32 + k1, n32 + k]);
    }
    build(p, faces)
}

/// Pyramid over a regular `n`-gon: the apex has valence `n` (a "fan").
pub fn pyramid(n: usize) -> Mesh {
    assert!(n >= 3, "pyramid needs an n-gon base with n ≥ 3");
    let mut p: Vec<DVec3> = (0..n)
        .map(|k| {
            let a = TAU * k as f64 / n as f64;
            v(a.cos(), a.sin(), 0.)
        })
        .collect();
    p.push(v(0., 0., 1.));
    let n32 = n as u32;
    let mut faces = FaceList::new();
    faces.push(&(0..n32).rev().collect::<Vec<_>>());
    for k in 0..n32 {
        faces.push(&[k, (k + 1) % n32, n32]);
    }
    build(p, faces)
}

/// Two quads glued along their boundary: every vertex has valence 2
/// (Catmull-Clark's limit matrix is indefinite on it, [correction C3]).
///
/// [correction C3]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c3
pub fn pillow() -> Mesh {
    let p = vec![v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.2), v(0., 1., 0.)];
    build(p, FaceList::from_faces([[0u32, 1, 2, 3], [3, 2, 1, 0]]))
}

/// A rectangular plate of `nx × ny` unit cells with a square through-hole at
/// each listed cell; `closed` gives the solid plate's surface (genus =
/// number of holes), otherwise only its top (one boundary loop per hole plus
/// the outer one).
///
/// # Panics
/// If a hole lies on the plate's border, or two holes share a cell corner.
pub fn plate_with_holes(nx: usize, ny: usize, holes: &[(usize, usize)], closed: bool) -> Mesh {
    for (k, &(i, j)) in holes.iter().enumerate() {
        assert!(i >= 1 && j >= 1 && i + 1 < nx && j + 1 < ny, "hole ({i}, {j}) touches the border");
        for &(i2, j2) in &holes[..k] {
            assert!(i.abs_diff(i2) > 1 || j.abs_diff(j2) > 1, "holes ({i}, {j}) and ({i2}, {j2}) touch");
        }
    }
    let layer = (nx + 1) * (ny + 1);
    let id = |i: usize, j: usize, top: bool| (j * (nx + 1) + i + if top { 0 } else { layer }) as u32;
    let layers = if closed { 2 } else { 1 };
    let mut p = Vec::with_capacity(layers * layer);
    for z in [0.5, -0.5].iter().take(layers) {
        p.extend((0..=ny).flat_map(|j| (0..=nx).map(move |i| v(i as f64, j as f64, *z))));
    }
    let is_hole = |i: usize, j: usize| holes.contains(&(i, j));
    let mut faces = FaceList::new();
    for j in 0..ny {
        for i in 0..nx {
            if is_hole(i, j) {
                continue;
            }
            faces.push(&[id(i, j, true), id(i + 1, j, true), id(i + 1, j + 1, true), id(i, j + 1, true)]);
            if closed {
                faces.push(&[id(i, j, false), id(i, j + 1, false), id(i + 1, j + 1, false), id(i + 1, j, false)]);
            }
        }
    }
    if closed {
        // Walls: one quad under every boundary edge of the top surface.
        let mut wall = |a: (usize, usize), b: (usize, usize)| {
            faces.push(&[id(b.0, b.1, true), id(a.0, a.1, true), id(a.0, a.1, false), id(b.0, b.1, false)]);
        };
        for i in 0..nx {
            wall((i, 0), (i + 1, 0));
            wall((i + 1, ny), (i, ny));
        }
        for j in 0..ny {
            wall((nx, j), (nx, j + 1));
            wall((0, j + 1), (0, j));
        }
        for &(i, j) in holes {
            wall((i, j + 1), (i + 1, j + 1));
            wall((i + 1, j + 1), (i + 1, j));
            wall((i + 1, j), (i, j));
            wall((i, j), (i, j + 1));
        }
    }
    build(p, faces)
}

/// A small deterministic random generator (SplitMix64) for shape mixing, so
/// shapes need no dependency and are reproducible from a seed.
#[derive(Clone, Debug)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in `0..n` (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// Turns a mesh into a polygon mix with the same topology type (genus,
/// boundary loops): about `merge_fraction` of its faces are merged with a
/// neighbour across a shared edge (making 5- to 8-gons), about `split_fraction`
/// of the quads are split into two triangles, and positions are jittered by
/// `jitter` (relative to the mean edge length). Merges that would create a
/// repeated vertex or a vertex of valence < 3 are skipped, so the mix has no
/// valence-2 vertices unless the input had them.
pub fn polygon_mix(mesh: &Mesh, seed: u64, merge_fraction: f64, split_fraction: f64, jitter: f64) -> Mesh {
    let mut rng = SplitMix64(seed);
    let t = mesh.topology();
    let nf = t.face_count();
    let mut faces: Vec<Option<Vec<u32>>> = t.faces().iter().map(|f| Some(f.to_vec())).collect();
    let mut touched = vec![false; nf];
    // Current valences: each merge removes an edge and lowers both its ends by one.
    let mut valence: Vec<usize> = t.vertices().map(|v| t.valence(v)).collect();
    let merges = (merge_fraction * nf as f64) as usize;
    for _ in 0..merges * 4 {
        let e = crate::EdgeId(rng.below(t.edge_count()) as u32);
        let (f, Some(g)) = t.edge_faces(e) else { continue };
        if touched[f.index()] || touched[g.index()] {
            continue;
        }
        let (a, b) = t.edge_vertices(e);
        // Removing edge ab lowers both valences by one; keep them ≥ 3 so no
        // vertex ends up with valence 2 (a Doo-Sabin digon, an indefinite
        // Catmull-Clark matrix).
        if valence[a.index()] < 4 || valence[b.index()] < 4 {
            continue;
        }
        let (fa, fb) = (t.face(f), t.face(g));
        // Face f contains a→b, face g contains b→a: splice g's path b…a into f.
        let ka = fa.iter().position(|&x| x == a.0).expect("edge vertex in face");
        let kb = fb.iter().position(|&x| x == a.0).expect("edge vertex in face");
        // f's corners from b round to a, then g's corners strictly between a and b.
        let mut merged: Vec<u32> = (0..fa.len()).map(|k| fa[(ka + 1 + k) % fa.len()]).collect();
        merged.extend((1..fb.len() - 1).map(|k| fb[(kb + k) % fb.len()]));
        let mut sorted = merged.clone();
        sorted.sort_unstable();
        if sorted.windows(2).any(|w| w[0] == w[1]) || merged.len() > 8 {
            continue;
        }
        touched[f.index()] = true;
        touched[g.index()] = true;
        valence[a.index()] -= 1;
        valence[b.index()] -= 1;
        faces[f.index()] = Some(merged);
        faces[g.index()] = None;
        if touched.iter().filter(|&&x| x).count() >= 2 * merges {
            break;
        }
    }
    let mut out = FaceList::new();
    for face in faces.into_iter().flatten() {
        if face.len() == 4 && rng.next_f64() < split_fraction {
            out.push(&[face[0], face[1], face[2]]);
            out.push(&[face[0], face[2], face[3]]);
        } else {
            out.push(&face);
        }
    }
    let scale = mean_edge_length(mesh);
    let positions = mesh
        .positions()
        .iter()
        .map(|&p| p + jitter * scale * DVec3::new(rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5))
        .collect();
    let (mixed, _) = Mesh::from_soup(PolygonSoup::new(positions, out)).expect("merges and splits keep the mesh valid");
    mixed
}

/// `mesh` with a new vertex inserted into each listed edge, at the edge's
/// midpoint moved by `offset` × the edge length along the mean of the two
/// adjacent faces' unit normals (outwards for positive `offset`). An interior
/// edge becomes two edges joined at an **interior vertex of valence 2** (the
/// two faces then share two consecutive edges, as DCC exports often leave
/// them); a boundary edge gets a boundary vertex in one face. Splitting two
/// edges of the same face pair makes adjacent valence-2 vertices only if the
/// edges are consecutive; splitting an edge twice is not possible (list each
/// edge once).
///
/// # Panics
/// If an edge id is out of range or listed twice (a caller bug).
pub fn split_edges(mesh: &Mesh, edges: &[crate::EdgeId], offset: f64) -> Mesh {
    let t = mesh.topology();
    let mut new_vertex = std::collections::HashMap::with_capacity(edges.len());
    let mut positions = mesh.positions().to_vec();
    for &e in edges {
        let (a, b) = t.edge_vertices(e);
        let (f, g) = t.edge_faces(e);
        let n = crate::unit_vector(mesh.face_normal(f) + g.map_or(DVec3::ZERO, |g| mesh.face_normal(g)));
        let (pa, pb) = (mesh.position(a), mesh.position(b));
        let key = (a.0.min(b.0), a.0.max(b.0));
        let fresh = positions.len() as u32;
        assert!(new_vertex.insert(key, fresh).is_none(), "edge {e:?} listed twice");
        positions.push(crate::centroid([pa, pb].into_iter()) + offset * distance(pa, pb) * n);
    }
    let mut faces = FaceList::with_capacity(t.face_count(), t.half_edge_count() + 2 * edges.len());
    let mut face = Vec::new();
    for f in t.faces().iter() {
        face.clear();
        for (k, &x) in f.iter().enumerate() {
            face.push(x);
            let y = f[(k + 1) % f.len()];
            if let Some(&w) = new_vertex.get(&(x.min(y), x.max(y))) {
                face.push(w);
            }
        }
        faces.push(&face);
    }
    build(positions, faces)
}

/// `mesh` with every vertex moved by `fraction`·d (d the bounding-box
/// diagonal) in a random direction from `seed`: the start of a synthetic
/// fitting recovery. On fine meshes 2 % of d exceeds the edge length and
/// tangles the control mesh: use [`smoothly_perturbed`] there.
pub fn perturbed(mesh: &Mesh, fraction: f64, seed: u64) -> Mesh {
    let d = mesh.bbox_diagonal();
    let mut rng = SplitMix64(seed);
    mesh.with_positions(
        mesh.positions()
            .iter()
            .map(|&p| {
                let dir = loop {
                    let v = v(rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5);
                    if v.length() > 1e-3 {
                        break v.normalize();
                    }
                };
                p + fraction * d * dir
            })
            .collect(),
    )
}

/// `mesh` with every vertex moved by a smooth displacement field of
/// amplitude `fraction`·d: a sum of three random low-frequency waves per
/// coordinate (wavelength ≥ d/2) from `seed`. Neighbours move together, so
/// the start of a fine mesh stays untangled.
pub fn smoothly_perturbed(mesh: &Mesh, fraction: f64, seed: u64) -> Mesh {
    let d = mesh.bbox_diagonal();
    let mut rng = SplitMix64(seed);
    let waves: Vec<(DVec3, f64)> = (0..9)
        .map(|_| {
            let k = v(rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5) * (8.0 / d);
            (k, rng.next_f64() * TAU)
        })
        .collect();
    let amplitude = fraction * d / 3f64.sqrt();
    mesh.with_positions(
        mesh.positions()
            .iter()
            .map(|&p| {
                let f = |i: usize| {
                    waves[3 * i..3 * i + 3].iter().map(|(k, phase)| (k.dot(p) + phase).sin()).sum::<f64>() / 3.0
                };
                p + amplitude * v(f(0), f(1), f(2))
            })
            .collect(),
    )
}

/// [`torus`]`(nu, nv)` with its control points moved radially from the
/// tube's axis by up to ±`amplitude` (random from `seed`): no symmetry left,
/// so fitting data fix its control mesh.
pub fn bumpy_torus(nu: usize, nv: usize, amplitude: f64, seed: u64) -> Mesh {
    let torus = torus(nu, nv);
    let mut rng = SplitMix64(seed);
    let moved = torus
        .positions()
        .iter()
        .map(|&p| {
            let axis = v(p.x, p.y, 0.0).normalize() * 2.0;
            p + (p - axis).normalize() * amplitude * (rng.next_f64() - 0.5) * 2.0
        })
        .collect();
    torus.with_positions(moved)
}

/// Mean edge length of a mesh, summed in coordinates scaled by a power of
/// two so that neither the differences nor the sum overflow (the naive mean,
/// bit for bit, wherever that is finite).
pub fn mean_edge_length(mesh: &Mesh) -> f64 {
    let t = mesh.topology();
    let s = PowerOfTwoScale::normalizing(mesh.positions().iter().copied());
    let total: f64 = t
        .edges()
        .map(|e| {
            let (a, b) = t.edge_vertices(e);
            s.apply_point(mesh.position(a)).distance(s.apply_point(mesh.position(b)))
        })
        .sum();
    s.inverse().apply(total / t.edge_count().max(1) as f64)
}

/// |a − b| without overflow (coordinates near ±1.7e308).
fn distance(a: DVec3, b: DVec3) -> f64 {
    let s = PowerOfTwoScale::normalizing([a, b]);
    s.inverse().apply(s.apply_point(a).distance(s.apply_point(b)))
}
