//! √3 (Kobbelt 2000) against an independent reference written from the
//! paper with plain `Vec`s and a map of directed edges — no code shared with
//! the crates: refinement (positions and connectivity up to relabelling),
//! limit points against the brute-force limit of many levels, rows summing
//! to 1, counts per level, the limit matrix's D·S form, refusals.

use crate::common;

use glam::DVec3;
use proptest::prelude::*;
use std::collections::{HashMap, HashSet};
use subdiv_mesh::refine::{sqrt3_split, Sqrt3Provenance, Sqrt3Vertex};
use subdiv_mesh::{shapes, FaceList, Mesh, PolygonSoup, Tags, Topology, VertexId};
use subdiv_stencil::size::{refined_sizes, LevelSize};
use subdiv_stencil::{
    limit_matrix_sqrt3, limit_points_with_options, row_sums, subdivide, LevelSharpness, Options, Scheme, StencilError,
    SubdivisionPlan,
};

// ---- the reference ----------------------------------------------------------

/// A triangle mesh as plain arrays, with its corners (boundary vertices the
/// curve ends at) and the parity of its next step.
#[derive(Clone)]
struct Reference {
    points: Vec<[f64; 3]>,
    triangles: Vec<[usize; 3]>,
    corners: HashSet<usize>,
    even_next: bool,
}

fn add(a: [f64; 3], b: [f64; 3], wa: f64, wb: f64) -> [f64; 3] {
    [wa * a[0] + wb * b[0], wa * a[1] + wb * b[1], wa * a[2] + wb * b[2]]
}

fn combo(terms: &[(f64, [f64; 3])]) -> [f64; 3] {
    terms.iter().fold([0.0; 3], |s, &(w, p)| add(s, p, 1.0, w))
}

impl Reference {
    /// From a mesh: corners are the boundary vertices in one triangle
    /// (`edge-and-corner`), the first step is odd.
    fn new(mesh: &Mesh) -> Self {
        let points = mesh.positions().iter().map(|p| p.to_array()).collect();
        let triangles: Vec<[usize; 3]> =
            mesh.topology().faces().iter().map(|f| [f[0] as usize, f[1] as usize, f[2] as usize]).collect();
        let mut r = Self { points, triangles, corners: HashSet::new(), even_next: false };
        let (boundary, _) = r.boundary();
        let mut faces_of = HashMap::new();
        for t in &r.triangles {
            for &v in t {
                *faces_of.entry(v).or_insert(0) += 1;
            }
        }
        r.corners = boundary.keys().copied().filter(|v| faces_of[v] == 1).collect();
        r
    }

    /// Directed boundary edges a → b (b's successor of a) and their inverse.
    fn boundary(&self) -> (HashMap<usize, usize>, HashMap<usize, usize>) {
        let directed: HashSet<(usize, usize)> =
            self.triangles.iter().flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3]))).collect();
        let mut next = HashMap::new();
        let mut prev = HashMap::new();
        for &(a, b) in &directed {
            if !directed.contains(&(b, a)) {
                next.insert(a, b);
                prev.insert(b, a);
            }
        }
        (next, prev)
    }

    /// One √3 step from the paper: a point per triangle (its centroid, or in
    /// an even step on a boundary triangle the two trisection points of its
    /// boundary edge), old vertices smoothed, every old interior edge flipped.
    /// Returns the step and, per new vertex, its key: old vertex, face, or
    /// second trisection point of directed boundary edge (a, b).
    fn step(&self) -> (Reference, Vec<Key>) {
        let (next, prev) = self.boundary();
        let n = self.points.len();
        let p = &self.points;
        let mut neighbours: Vec<HashSet<usize>> = vec![HashSet::new(); n];
        for t in &self.triangles {
            for k in 0..3 {
                neighbours[t[k]].insert(t[(k + 1) % 3]);
                neighbours[t[(k + 1) % 3]].insert(t[k]);
            }
        }
        let mut points = Vec::with_capacity(n + self.triangles.len());
        let mut keys: Vec<Key> = (0..n).map(Key::Old).collect();
        for v in 0..n {
            let nb = &neighbours[v];
            points.push(if nb.is_empty() {
                p[v]
            } else if let (Some(&b), Some(&a)) = (next.get(&v), prev.get(&v)) {
                if self.even_next && !self.corners.contains(&v) {
                    combo(&[(4.0 / 27.0, p[a]), (19.0 / 27.0, p[v]), (4.0 / 27.0, p[b])])
                } else {
                    p[v]
                }
            } else {
                let k = nb.len() as f64;
                let alpha = (4.0 - 2.0 * (2.0 * std::f64::consts::PI / k).cos()) / 9.0;
                let mut q = [0.0; 3];
                for &u in nb {
                    q = add(q, p[u], 1.0, alpha / k);
                }
                add(q, p[v], 1.0, 1.0 - alpha)
            });
        }
        // The phantom beyond a corner c, seen from its neighbour b: 2c − b.
        let outer = |c: usize, b: usize, beyond: Option<&usize>| -> [f64; 3] {
            if self.corners.contains(&c) {
                add(p[c], p[b], 2.0, -1.0)
            } else {
                p[*beyond.expect("a boundary vertex has two boundary neighbours")]
            }
        };
        let mut sub: Vec<[usize; 3]> = Vec::with_capacity(3 * self.triangles.len());
        let mut second = Vec::new();
        for (f, t) in self.triangles.iter().enumerate() {
            let boundary_edge = (0..3).find(|&k| next.get(&t[k]) == Some(&t[(k + 1) % 3]));
            let m = n + f;
            keys.push(Key::Face(f));
            match boundary_edge {
                Some(k) if self.even_next => {
                    let (a, b, x) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
                    let pa =
                        combo(&[(1.0 / 27.0, outer(a, b, prev.get(&a))), (16.0 / 27.0, p[a]), (10.0 / 27.0, p[b])]);
                    let pb =
                        combo(&[(10.0 / 27.0, p[a]), (16.0 / 27.0, p[b]), (1.0 / 27.0, outer(b, a, next.get(&b)))]);
                    points.push(pa);
                    second.push((a, b, pb));
                    // q's index is fixed once all faces are placed.
                    sub.push([a, m, x]);
                    sub.push([m, usize::MAX - second.len() + 1, x]);
                    sub.push([usize::MAX - second.len() + 1, b, x]);
                }
                _ => {
                    points.push(combo(&[(1.0 / 3.0, p[t[0]]), (1.0 / 3.0, p[t[1]]), (1.0 / 3.0, p[t[2]])]));
                    for k in 0..3 {
                        sub.push([t[k], t[(k + 1) % 3], m]);
                    }
                }
            }
        }
        for (i, &(a, b, q)) in second.iter().enumerate() {
            let id = points.len();
            points.push(q);
            keys.push(Key::Second(a, b));
            for tri in sub.iter_mut() {
                for v in tri.iter_mut() {
                    if *v == usize::MAX - i {
                        *v = id;
                    }
                }
            }
        }
        // Flip every old interior edge {a, b}: the sub-triangles (a, b, o₁)
        // and (b, a, o₂) become (a, o₂, o₁) and (b, o₁, o₂).
        let mut at: HashMap<(usize, usize), usize> = HashMap::new();
        for (i, tri) in sub.iter().enumerate() {
            for k in 0..3 {
                if tri[k] < n && tri[(k + 1) % 3] < n {
                    at.insert((tri[k], tri[(k + 1) % 3]), i);
                }
            }
        }
        for (&(a, b), &i) in &at {
            if a < b {
                if let Some(&j) = at.get(&(b, a)) {
                    let third = |tri: [usize; 3]| tri.into_iter().find(|&v| v != a && v != b).unwrap();
                    let (o1, o2) = (third(sub[i]), third(sub[j]));
                    sub[i] = [a, o2, o1];
                    sub[j] = [b, o1, o2];
                }
            }
        }
        let child = Reference { points, triangles: sub, corners: self.corners.clone(), even_next: !self.even_next };
        (child, keys)
    }
}

/// What a new vertex is, in the parent's reference numbering.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Key {
    Old(usize),
    Face(usize),
    Second(usize, usize),
}

// ---- comparison ---------------------------------------------------------------

fn diagonal(points: &[DVec3]) -> f64 {
    let (lo, hi) = points.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), &p| (l.min(p), h.max(p)));
    (hi - lo).length()
}

/// The reference id of each of our vertices, from our provenance mapped
/// through the parent's correspondence `parent` (ours → reference).
fn correspondence(t: &Topology, trisect: bool, parent: &[usize], reference: &Reference, keys: &[Key]) -> Vec<usize> {
    let p = Sqrt3Provenance::new(t, trisect).unwrap();
    let by_key: HashMap<Key, usize> = keys.iter().enumerate().map(|(i, &k)| (k, i)).collect();
    let face_of: HashMap<[usize; 3], usize> = reference
        .triangles
        .iter()
        .enumerate()
        .map(|(f, tri)| {
            let mut s = *tri;
            s.sort_unstable();
            (s, f)
        })
        .collect();
    (0..p.vertex_count())
        .map(|v| {
            let face_key = |f: subdiv_mesh::FaceId| {
                let mut s = [0; 3];
                for (k, &c) in t.face(f).iter().enumerate() {
                    s[k] = parent[c as usize];
                }
                s.sort_unstable();
                Key::Face(face_of[&s])
            };
            let key = match p.origin(VertexId(v as u32)) {
                Sqrt3Vertex::Old(u) => Key::Old(parent[u.index()]),
                Sqrt3Vertex::Centroid(f) => face_key(f),
                Sqrt3Vertex::Trisection { half_edge, near_start: true } => face_key(t.he_face(half_edge)),
                Sqrt3Vertex::Trisection { half_edge, near_start: false } => {
                    Key::Second(parent[t.he_from(half_edge).index()], parent[t.he_to(half_edge).index()])
                }
            };
            by_key[&key]
        })
        .collect()
}

/// Our triangles in reference ids, each rotated to start at its smallest id.
fn canonical(triangles: impl Iterator<Item = [usize; 3]>) -> Vec<[usize; 3]> {
    let mut out: Vec<[usize; 3]> = triangles
        .map(|t| {
            let k = (0..3).min_by_key(|&k| t[k]).unwrap();
            [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
        })
        .collect();
    out.sort_unstable();
    out
}

/// `levels` steps of ours (`subdivide`, the plan, and the split level by
/// level) against the reference: same points (1e-12·d) and the same
/// triangles up to relabelling.
fn compare(mesh: &Mesh, levels: usize) {
    let d = diagonal(mesh.positions());
    let mut reference = Reference::new(mesh);
    let mut t = mesh.topology().clone();
    let mut ids: Vec<usize> = (0..t.vertex_count()).collect();
    for level in 1..=levels {
        let (child, keys) = reference.step();
        let trisect = level % 2 == 0;
        let map = correspondence(&t, trisect, &ids, &reference, &keys);
        let (next, _) = sqrt3_split(&t, trisect).unwrap();
        let ours = canonical(next.faces().iter().map(|f| [map[f[0] as usize], map[f[1] as usize], map[f[2] as usize]]));
        assert_eq!(ours, canonical(child.triangles.iter().copied()), "level {level}: connectivity");
        let refined = subdivide(mesh, Scheme::Sqrt3, level, false).unwrap();
        assert_eq!(refined.topology().faces(), next.faces(), "level {level}: subdivide's connectivity");
        let plan = SubdivisionPlan::new(mesh.topology(), Scheme::Sqrt3, level).unwrap();
        let planned = plan.apply(mesh.positions());
        for (v, (&ours, &theirs)) in refined.positions().iter().zip(&map).enumerate() {
            let want = DVec3::from_array(child.points[theirs]);
            assert!(ours.distance(want) <= 1e-12 * d, "level {level}, vertex {v}: {ours} vs {want}");
            assert!(planned[v].distance(want) <= 1e-12 * d, "level {level}, vertex {v}: plan");
        }
        (reference, t, ids) = (child, next, map);
    }
}

// ---- meshes -------------------------------------------------------------------

/// Moves every vertex by a deterministic pseudo-random offset of `amount`
/// of the mean edge length, so that no two points coincide by symmetry.
fn jittered(mesh: &Mesh, seed: u64, amount: f64) -> Mesh {
    let h = shapes::mean_edge_length(mesh) * amount;
    let mut rng = shapes::SplitMix64(seed);
    let mut mesh = mesh.clone();
    for p in mesh.positions_mut() {
        *p += h * DVec3::new(rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5);
    }
    mesh
}

fn triangulated(mesh: &Mesh) -> Mesh {
    subdiv_mesh::triangulate(mesh).unwrap().mesh
}

/// A fan of n triangles round an apex of valence n (a pyramid without its
/// base): an open mesh with an interior vertex of each valence asked for.
fn open_fan(n: usize) -> Mesh {
    let pyramid = shapes::pyramid(n);
    let faces: Vec<Vec<u32>> =
        pyramid.topology().faces().iter().filter(|f| f.len() == 3).map(<[u32]>::to_vec).collect();
    let soup = PolygonSoup::new(pyramid.positions().to_vec(), FaceList::from_faces(faces));
    Mesh::from_soup(soup).unwrap().0
}

fn closed_meshes() -> Vec<(String, Mesh)> {
    let mut out = vec![
        ("tetrahedron".to_string(), jittered(&shapes::tetrahedron(), 1, 0.1)),
        ("octahedron".to_string(), jittered(&shapes::octahedron(), 2, 0.1)),
        ("icosahedron".to_string(), jittered(&shapes::icosahedron(), 3, 0.1)),
    ];
    for n in [3, 7, 8] {
        out.push((format!("bipyramid {n}"), jittered(&triangulated(&shapes::pyramid(n)), n as u64, 0.1)));
    }
    out
}

fn open_meshes() -> Vec<(String, Mesh)> {
    let mut out = vec![
        ("triangle grid".to_string(), jittered(&shapes::triangle_grid(3, 3), 4, 0.2)),
        (
            "plate with a hole".to_string(),
            jittered(&triangulated(&shapes::plate_with_holes(4, 4, &[(1, 1)], false)), 5, 0.2),
        ),
    ];
    for n in 3..=8 {
        out.push((format!("open fan {n}"), jittered(&open_fan(n), 10 + n as u64, 0.2)));
    }
    out
}

// ---- tests -------------------------------------------------------------------------

#[test]
fn refinement_equals_the_reference() {
    for (name, mesh) in closed_meshes().into_iter().chain(open_meshes()) {
        eprintln!("{name}");
        compare(&mesh, 4);
    }
}

/// The limit of a sequence converging geometrically, from three terms
/// (vector Aitken: the ratio from the two differences).
fn aitken(a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let (d1, d2) = (b - a, c - b);
    if d1.length_squared() == 0.0 {
        return c;
    }
    let ratio = d2.dot(d1) / d1.dot(d1);
    c + d2 * (ratio / (1.0 - ratio))
}

/// Our limit points of the input against the reference refined 8 levels:
/// an interior vertex reaches its limit geometrically from the first step
/// (ratio λₙ per step), a boundary vertex every second step (ratio 1/9), so
/// three terms give the limit of the brute-force sequence.
#[test]
fn limit_points_equal_the_limit_of_eight_levels() {
    for (name, mesh) in closed_meshes().into_iter().chain(open_meshes()) {
        let t = mesh.topology();
        let d = diagonal(mesh.positions());
        let limits = limit_points_with_options(t, &Tags::none(), Scheme::Sqrt3, mesh.positions()).unwrap().unwrap();
        let mut levels = vec![Reference::new(&mesh)];
        for _ in 0..8 {
            levels.push(levels.last().unwrap().step().0);
        }
        let at = |k: usize, v: usize| DVec3::from_array(levels[k].points[v]);
        let mut worst = 0.0f64;
        for v in t.vertices() {
            let i = v.index();
            let brute = if t.is_boundary_vertex(v) {
                aitken(at(4, i), at(6, i), at(8, i))
            } else {
                aitken(at(6, i), at(7, i), at(8, i))
            };
            worst = worst.max(brute.distance(limits[i]) / d);
            // The refined point itself is close already, and never further than the first.
            assert!(at(8, i).distance(limits[i]) <= at(0, i).distance(limits[i]).max(1e-15 * d), "{name} {v}");
        }
        assert!(worst <= 1e-9, "{name}: {worst:e}");
    }
}

/// The limit is the same from every level: after 1, 2, 3 levels the old
/// vertices' limit points (`subdivide` with `limit`, one extra level taken
/// before an even step on an open mesh) are the input's.
#[test]
fn limit_points_are_the_same_at_both_parities() {
    for (name, mesh) in closed_meshes().into_iter().chain(open_meshes()) {
        let d = diagonal(mesh.positions());
        let base = limit_points_with_options(mesh.topology(), &Tags::none(), Scheme::Sqrt3, mesh.positions())
            .unwrap()
            .unwrap();
        for levels in 1..=3 {
            let refined = subdivide(&mesh, Scheme::Sqrt3, levels, true).unwrap();
            let plan = SubdivisionPlan::new(mesh.topology(), Scheme::Sqrt3, levels).unwrap();
            let stencil = plan.limit_stencil().unwrap().unwrap();
            let via_stencil = subdiv_stencil::apply(&stencil, &plan.apply(mesh.positions()));
            for (v, want) in base.iter().enumerate() {
                assert!(refined.positions()[v].distance(*want) <= 1e-12 * d, "{name}, {levels} levels, vertex {v}");
                assert!(via_stencil[v].distance(*want) <= 1e-12 * d, "{name}, {levels} levels, vertex {v}: stencil");
            }
        }
    }
}

#[test]
fn rows_sum_to_one_at_both_parities() {
    for (name, mesh) in closed_meshes().into_iter().chain(open_meshes()) {
        let plan = SubdivisionPlan::new(mesh.topology(), Scheme::Sqrt3, 3).unwrap();
        for (k, level) in plan.levels().iter().enumerate() {
            let r = level.stencil.as_ref().unwrap();
            assert!(row_sums(r).iter().all(|s| (s - 1.0).abs() < 1e-14), "{name} level {}", k + 1);
        }
        for levels in 0..=3 {
            let plan = SubdivisionPlan::new(mesh.topology(), Scheme::Sqrt3, levels).unwrap();
            let l = plan.limit_stencil().unwrap().unwrap();
            assert!(row_sums(&l).iter().all(|s| (s - 1.0).abs() < 1e-13), "{name} limit after {levels}");
        }
    }
}

#[test]
fn counts_per_level_are_as_predicted() {
    for (name, mesh) in closed_meshes().into_iter().chain(open_meshes()) {
        let t = mesh.topology();
        let predicted = refined_sizes(t, Scheme::Sqrt3, 4);
        let (v, f, b) = (t.vertex_count() as u64, t.face_count() as u64, t.boundary_edge_count() as u64);
        // Closed form: F·3ᵏ faces; V + F after one step, + 3F + B after two (1-to-9).
        assert_eq!((predicted[0].vertices, predicted[0].faces), (v + f, 3 * f), "{name}");
        assert_eq!((predicted[1].vertices, predicted[1].faces), (v + 4 * f + b, 9 * f), "{name}");
        assert_eq!(predicted[1].boundary_edges, 3 * b, "{name}: the boundary trisected once");
        for (k, want) in predicted.iter().enumerate() {
            let got = LevelSize::of(subdivide(&mesh, Scheme::Sqrt3, k + 1, false).unwrap().topology());
            assert_eq!(&got, want, "{name} level {}", k + 1);
        }
    }
}

#[test]
fn the_limit_matrix_is_d_times_a_symmetric_s() {
    for (name, mesh) in closed_meshes().into_iter().chain(open_meshes()) {
        let t = mesh.topology();
        let a = limit_matrix_sqrt3(t).unwrap();
        if t.is_closed() {
            assert!(a.is_symmetric(), "{name}: S symmetric bit for bit");
        }
        let limits = limit_points_with_options(t, &Tags::none(), Scheme::Sqrt3, mesh.positions()).unwrap().unwrap();
        let d = diagonal(mesh.positions());
        for (v, (x, y)) in a.apply(mesh.positions()).iter().zip(&limits).enumerate() {
            assert!(x.distance(*y) <= 1e-13 * d, "{name} row {v}");
        }
        assert!(row_sums(&a.to_csr()).iter().all(|s| (s - 1.0).abs() < 1e-13), "{name}");
    }
}

/// With corner tags and either boundary option, every row of the limit
/// matrix is the limit point `limit_points_with_options` gives (itself
/// checked against eight levels of the reference above), a tagged corner's
/// row is the identity, and the blocks stay of the D·S form.
#[test]
fn the_limit_matrix_with_corners_and_boundary_options() {
    use subdiv_stencil::{limit_matrix_sqrt3_sharp, BoundaryInterpolation, CreaseMethod, RowKind};
    for (name, mesh) in open_meshes() {
        let t = mesh.topology();
        // A corner tag on the first boundary vertex in more than one face.
        let mut vertices = vec![0.0; t.vertex_count()];
        let Some(tagged) = t.vertices().find(|&v| t.is_boundary_vertex(v) && t.vertex_face_count(v) > 1) else {
            continue; // "open fan 3" keeps the pyramid's triangular base: closed
        };
        vertices[tagged.index()] = 10.0;
        let tags = Tags::from_arrays(t, Vec::new(), vertices).unwrap();
        for boundary in [BoundaryInterpolation::EdgeOnly, BoundaryInterpolation::EdgeAndCorner] {
            let sharp = LevelSharpness::new(&tags, boundary, CreaseMethod::Uniform);
            let a = limit_matrix_sqrt3_sharp(t, &sharp).unwrap();
            let options = Options::new(Scheme::Sqrt3).with_boundary(boundary);
            let limits = limit_points_with_options(t, &tags, options, mesh.positions()).unwrap().unwrap();
            let d = diagonal(mesh.positions());
            for (v, (x, y)) in a.apply(mesh.positions()).iter().zip(&limits).enumerate() {
                assert!(x.distance(*y) <= 1e-13 * d, "{name}, {boundary:?}: row {v}");
            }
            assert_eq!(a.row_kinds[tagged.index()], RowKind::Corner, "{name}");
            assert!(!a.row_kinds.contains(&RowKind::General), "{name}");
            let blocks = common::solve_blocks(&a);
            assert!(a.asymmetric_rows(&blocks.creases).is_empty() && a.asymmetric_rows(&blocks.interior).is_empty());
        }
    }
}

#[test]
fn corners_stay_and_are_carried_as_tags() {
    let mesh = jittered(&shapes::triangle_grid(2, 2), 7, 0.2);
    let t = mesh.topology();
    let corners: Vec<VertexId> =
        t.vertices().filter(|&v| t.is_boundary_vertex(v) && t.vertex_face_count(v) == 1).collect();
    assert!(!corners.is_empty());
    let refined = subdivide(&mesh, Scheme::Sqrt3, 3, false).unwrap();
    let limit = subdivide(&mesh, Scheme::Sqrt3, 3, true).unwrap();
    for &c in &corners {
        assert_eq!(refined.positions()[c.index()], mesh.positions()[c.index()]);
        assert_eq!(limit.positions()[c.index()], mesh.positions()[c.index()]);
        assert!(refined.tags().vertex_values()[c.index()] >= 10.0, "corner {c} tagged");
    }
    // Under edge-only the corners move with the boundary curve.
    let options = Options::new(Scheme::Sqrt3).with_boundary(subdiv_stencil::BoundaryInterpolation::EdgeOnly);
    let smooth = subdiv_stencil::subdivide(&mesh, options, 2, false).unwrap();
    assert!(corners.iter().any(|c| smooth.positions()[c.index()] != mesh.positions()[c.index()]));
}

#[test]
fn refusals_are_typed() {
    let cube = shapes::cube();
    assert!(matches!(subdivide(&cube, Scheme::Sqrt3, 1, false), Err(StencilError::NotTriangles { .. })));
    let ico = shapes::icosahedron();
    let t = ico.topology();
    let crease = Tags::from_arrays(t, vec![10.0; t.edge_count()], Vec::new()).unwrap();
    let creased = ico.clone().with_tags(crease);
    assert!(matches!(subdivide(&creased, Scheme::Sqrt3, 1, false), Err(StencilError::TagsNotSupported { .. })));
    let mut semi = vec![0.0; t.vertex_count()];
    semi[0] = 2.0;
    let tagged = ico.clone().with_tags(Tags::from_arrays(t, Vec::new(), semi).unwrap());
    assert!(matches!(subdivide(&tagged, Scheme::Sqrt3, 1, false), Err(StencilError::TagsNotSupported { .. })));
    // A closed pair of triangles: interior valence 2.
    let soup = PolygonSoup::new(
        vec![DVec3::ZERO, DVec3::X, DVec3::Y],
        FaceList::from_faces(vec![vec![0, 1, 2], vec![0, 2, 1]]),
    );
    if let Ok((pillow, _)) = Mesh::from_soup(soup) {
        assert!(matches!(subdivide(&pillow, Scheme::Sqrt3, 1, false), Err(StencilError::MeshNotSupported { .. })));
    }
    // The rules object refuses what `subdivide` refuses.
    assert!(Scheme::Sqrt3.rules().check(cube.topology(), &LevelSharpness::plain()).is_err());
}

fn generated_mesh() -> impl Strategy<Value = Mesh> {
    (3usize..6, 3usize..6, 0usize..2, any::<bool>(), any::<u64>(), 0.0f64..0.4, 0.0f64..0.4).prop_map(
        |(nx, ny, nholes, closed, seed, merge, split)| {
            let nx = nx + 2 * nholes;
            let holes: Vec<(usize, usize)> = (0..nholes).map(|k| (1 + 2 * k, 1)).collect();
            let base = shapes::plate_with_holes(nx, ny, &holes, closed);
            jittered(&triangulated(&shapes::polygon_mix(&base, seed, merge, split, 0.1)), seed, 0.1)
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    #[test]
    fn generated_meshes_refine_as_the_reference(mesh in generated_mesh()) {
        compare(&mesh, 3);
        let sums_ok = SubdivisionPlan::new(mesh.topology(), Scheme::Sqrt3, 2).unwrap().levels().iter()
            .all(|l| row_sums(l.stencil.as_ref().unwrap()).iter().all(|s| (s - 1.0).abs() < 1e-14));
        prop_assert!(sums_ok);
    }
}
