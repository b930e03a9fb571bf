//! Triangulation over a face's own corners: every face of m > 3 corners
//! becomes m − 2 triangles, with no vertex added or moved, and the result
//! stays a manifold mesh.
//!
//! Fan triangulation from the first corner fails twice over: a diagonal can
//! already be an edge of the mesh (one quad and two triangles closing a
//! tetrahedron-like shape: the fan diagonal is the triangles' shared edge,
//! and the result is non-manifold), and in a non-convex face it leaves the
//! polygon, flipping triangles. [`triangulate`] avoids both:
//!
//! 1. Every face is projected on its best-fit plane, the one normal to its
//!    Newell vector N = Σ Vᵢ × Vᵢ₊₁ (Newell's method; Zheng & Cai 2005,
//!    Eq. 10). A triangle of the face is *valid* when its projected area is
//!    positive — it keeps the face's orientation — and not negligible (doubled
//!    area > `DEGENERATE_REL` · longest edge²). For a planar face whose
//!    projection is a simple polygon, triangles that are all valid tile it
//!    exactly (the winding number of a simple polygon is 1 inside, 0 outside,
//!    and it is the sum of the triangles' winding numbers).
//! 2. A diagonal is *allowed* unless it is already an edge of the mesh or of
//!    the triangles of an earlier face (one hash set of vertex pairs); the
//!    diagonals of one face are distinct by construction.
//! 3. Quads: the shorter diagonal, unless it is not allowed or one of its
//!    triangles is not valid; then the other.
//! 4. Larger faces: ear clipping in the projection (Meisters 1975: every
//!    simple polygon with more than three corners has two non-overlapping
//!    ears). An ear (Vᵢ₋₁, Vᵢ, Vᵢ₊₁) qualifies when it is valid, contains no
//!    other remaining corner, and its diagonal Vᵢ₋₁Vᵢ₊₁ is allowed; of the
//!    qualifying ears the best-shaped is clipped (the largest smallest angle).
//! 5. When a face has no such choice — a non-simple or zero-area projection,
//!    or ears blocked by existing edges — every triangulation of the face is
//!    searched (dynamic programming over corner intervals, O(m³), faces of at
//!    most `EXHAUSTIVE_MAX_CORNERS` corners; a greedy ear clipping that
//!    ignores geometry beyond that) for the one with allowed diagonals whose
//!    worst triangle is best (valid triangles first). Only when no
//!    triangulation has allowed diagonals does the face fail, with
//!    [`MeshError::NoTriangulation`].
//!
//! Faces are processed in order and each face's diagonals are final, so the
//! result is deterministic. An earlier face's diagonal can rule out a later
//! face's choice only where two faces share two corners adjacent in neither
//! (the pillow's two quads: the second takes the other diagonal). A quad is
//! left with no diagonal only when both of its diagonals are joined outside
//! it, by edges or other faces' diagonals; those two arcs have interleaved
//! ends on the quad's boundary and do not cross, which needs a handle (on a
//! sphere or a disk with holes they would cross).
//!
//! The triangles are validated into a [`Mesh`] by [`Mesh::from_soup`], like
//! any other face list. Time is linear in the number of corners for faces of
//! bounded size (per face, ear clipping costs O(m²) to O(m³) and the search
//! O(m³)).

use crate::error::MeshError;
use crate::geometry::{scaled_newell, PowerOfTwoScale};
use crate::ids::FaceId;
use crate::mesh::Mesh;
use crate::soup::{FaceGroups, FaceList, PolygonSoup};
use crate::tags::FaceVarying;
use crate::topology::Topology;
use glam::{DVec2, DVec3};
use std::collections::HashSet;
use std::hash::{BuildHasherDefault, Hasher};

/// A triangle is degenerate when its doubled area, projected on its face's
/// best-fit plane, is at most this times the square of its longest edge
/// (the sine of its smallest angle is then about this small or less). A face
/// whose Newell vector is this small against its longest edge² has no
/// best-fit plane (zero area) and is triangulated by shape alone.
const DEGENERATE_REL: f64 = 1e-12;

/// Largest face searched exhaustively (O(m³) time, O(m²) memory) when ear
/// clipping finds no valid ear; larger faces fall back to greedy ear
/// clipping that ignores geometry.
const EXHAUSTIVE_MAX_CORNERS: usize = 256;

/// A triangulated mesh and where its triangles come from ([`triangulate`]).
/// `#[non_exhaustive]`: read through its public fields (a new field is not
/// a breaking change).
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Triangulation {
    /// The triangles, validated: the input's vertices (same order, same
    /// positions, isolated ones kept), each input face replaced by its
    /// triangles in place, orientation kept. Face groups follow their faces.
    pub mesh: Mesh,
    /// For every triangle of `mesh`, the input face it comes from; the
    /// triangles of one face are consecutive, faces in input order, so this
    /// is non-decreasing. A triangle of the input maps to itself.
    pub source_face: Vec<FaceId>,
    /// Number of input faces with more than three corners (each became
    /// m − 2 triangles).
    pub split_faces: usize,
}

/// Splits every face of more than three corners into triangles over its
/// own corners (no vertex added or moved), choosing diagonals that keep the
/// mesh manifold and, where the face allows it, triangles that are neither
/// degenerate nor flipped against the face's Newell normal (module docs).
///
/// A triangle mesh is returned unchanged (sharing its topology). Fails with
/// [`MeshError::NoTriangulation`], naming the face, when a face has no
/// triangulation whose diagonals are all new edges.
///
/// ```
/// use subdiv_mesh::{shapes, triangulate};
/// let cube = shapes::cube();
/// let tri = triangulate(&cube).unwrap();
/// assert_eq!((tri.split_faces, tri.mesh.topology().face_count()), (6, 12));
/// assert_eq!(tri.mesh.positions(), cube.positions());
/// assert_eq!(tri.mesh.topology().euler_characteristic(), 2);
/// ```
pub fn triangulate(mesh: &Mesh) -> Result<Triangulation, MeshError> {
    let t = mesh.topology();
    let split_faces = t.face_ids().filter(|&f| t.face_size(f) > 3).count();
    if split_faces == 0 {
        return Ok(Triangulation { mesh: mesh.clone(), source_face: t.face_ids().collect(), split_faces });
    }
    let positions = mesh.positions();
    let mut edges = EdgeSet::new(mesh);
    let triangles = t.half_edge_count() - 2 * t.face_count();
    let mut corners = Vec::with_capacity(3 * triangles);
    let mut source_face = Vec::with_capacity(triangles);
    let mut polygon = Polygon::default();
    for f in t.face_ids() {
        let face = t.face(f);
        let before = corners.len();
        if face.len() == 3 {
            corners.extend_from_slice(face);
        } else if !split_face(face, positions, &mut edges, &mut polygon, &mut corners) {
            return Err(MeshError::NoTriangulation { face: f.0, size: face.len() });
        }
        source_face.extend(std::iter::repeat_n(f, (corners.len() - before) / 3));
    }
    let groups = mesh.groups();
    let groups = if groups.face_group.len() == t.face_count() {
        let face_group = source_face.iter().map(|f| groups.face_group[f.index()]).collect();
        FaceGroups { names: groups.names.clone(), face_group }
    } else {
        groups.clone()
    };
    // Tags name vertex pairs, which stay edges; each triangle corner is a
    // corner of its source face and keeps that corner's texture coordinate;
    // the triangles of a hole are holes.
    let mut tags = mesh.tags().to_list(t);
    if !tags.holes.is_empty() {
        let hole = |f: &FaceId| mesh.tags().is_hole(*f);
        tags.holes = (source_face.iter().enumerate()).filter(|(_, f)| hole(f)).map(|(k, _)| k as u32).collect();
    }
    let uvs = mesh.uvs().map(|uvs| {
        let offsets = t.faces().offsets();
        let indices = (corners.chunks_exact(3).zip(&source_face))
            .flat_map(|(triangle, &f)| {
                let start = offsets[f.index()] as usize;
                let face = t.face(f);
                triangle.iter().map(move |&v| {
                    let k = face.iter().position(|&c| c == v).expect("a triangle corner is a corner of its face");
                    uvs.indices[start + k]
                })
            })
            .collect();
        FaceVarying { values: uvs.values.clone(), indices }
    });
    let faces = FaceList::from_uniform(3, corners);
    let soup = PolygonSoup { positions: positions.to_vec(), faces, groups, tags, uvs };
    let (mesh, _warnings) = Mesh::from_soup(soup)?;
    Ok(Triangulation { mesh, source_face, split_faces })
}

/// Whether [`triangulate`] succeeds on `mesh`, without building the
/// triangles: `Ok` exactly when [`triangulate`] returns a triangulation, and
/// otherwise its error ([`MeshError::NoTriangulation`] for the same face).
/// What the `deng-wang` method's precondition asks.
///
/// A face fails only when diagonals it could take are blocked: by an edge
/// of the mesh or by the diagonal an earlier face took. A diagonal (a, w)
/// of face f — a and w corners of f, not adjacent in it — can only be
/// blocked when it is an edge at a or a diagonal at a of another face
/// around a too. One pass over the vertices finds these *conflicting*
/// faces (at each vertex a, its neighbours and the far corners of its faces
/// are compared, and a far corner seen twice is a conflict), in time linear
/// in the corners for faces of bounded size; for an all-quad mesh the
/// topology's construction has found them already. Faces without conflicts always split
/// (nothing blocks them, and nothing they take is asked by another face),
/// so only the conflicting ones are split, in order, exactly as
/// [`triangulate`] splits them (the same diagonal choice, `split_face`):
/// their choices can block one another only. An all-quad mesh whose quads'
/// diagonals are not edges (any fine quad mesh) needs no split at all.
///
/// ```
/// use subdiv_mesh::{check_triangulation, shapes, triangulate};
/// let torus = shapes::torus(64, 32);
/// assert!(check_triangulation(&torus).is_ok() && triangulate(&torus).is_ok());
/// ```
///
/// # Errors
/// [`MeshError::NoTriangulation`], naming the first face in order that
/// [`triangulate`] cannot split.
pub fn check_triangulation(mesh: &Mesh) -> Result<(), MeshError> {
    let t = mesh.topology();
    let faces = t.faces();
    let polygon_cost: usize = faces.iter().map(|f| if f.len() > 3 { f.len() * (f.len() - 3) } else { 0 }).sum();
    if polygon_cost == 0 {
        return Ok(());
    }
    // The conflict scan costs Σ m(m − 3) over faces of m > 3 corners: for
    // huge polygons, every polygon face is split instead (as triangulate does).
    let conflicting: Vec<bool> = if polygon_cost <= CONFLICT_SCAN_PER_CORNER * faces.corner_count() {
        let conflicts = t.diagonal_conflicts();
        if conflicts.is_empty() {
            return Ok(());
        }
        let mut conflicting = vec![false; faces.len()];
        conflicts.iter().for_each(|&f| conflicting[f as usize] = true);
        conflicting
    } else {
        faces.iter().map(|f| f.len() > 3).collect()
    };
    let positions = mesh.positions();
    let mut edges = EdgeSet::among(t, &conflicting);
    let mut polygon = Polygon::default();
    let mut corners = Vec::new();
    for f in t.face_ids().filter(|f| conflicting[f.index()]) {
        let face = t.face(f);
        corners.clear();
        if !split_face(face, positions, &mut edges, &mut polygon, &mut corners) {
            return Err(MeshError::NoTriangulation { face: f.0, size: face.len() });
        }
    }
    Ok(())
}

/// Budget of [`check_triangulation`]'s diagonal conflict scan per corner of the
/// mesh (Σ m(m − 3) over the polygons; 4 for an all-quad mesh, 28 for
/// heptagons).
const CONFLICT_SCAN_PER_CORNER: usize = 64;

/// Steps 3-5 of the module docs for one face of four or more corners:
/// appends its triangles (vertex ids) to `corners` and records its
/// diagonals in `edges`; false when no triangulation has allowed diagonals.
/// The one place [`triangulate`] and [`check_triangulation`] choose
/// diagonals, so that they decide alike.
fn split_face(
    face: &[u32],
    positions: &[DVec3],
    edges: &mut EdgeSet,
    polygon: &mut Polygon,
    corners: &mut Vec<u32>,
) -> bool {
    if let Some(a) = quad_diagonal(face, positions, edges) {
        let (b, c, d) = (a + 1, (a + 2) % 4, (a + 3) % 4);
        corners.extend_from_slice(&[face[a], face[b], face[c], face[a], face[c], face[d]]);
        edges.insert(face[a], face[c]);
        return true;
    }
    polygon.load(face, positions);
    let local = match face.len() {
        4 => polygon.split_quad(edges),
        _ => polygon.split(edges),
    };
    let Some(local) = local else { return false };
    for &[a, b, c] in &local {
        corners.extend_from_slice(&[face[a], face[b], face[c]]);
    }
    edges.claim_diagonals(face, &local);
    true
}

/// Rule 3 of the module docs without the projection, for the common case:
/// the first diagonal in order of length (from corner 0 or 1) that is
/// allowed and makes two valid triangles, judged against the quad's Newell
/// vector N = (V₂ − V₀) × (V₃ − V₁). `None` for other faces and when
/// neither diagonal qualifies (the general path then takes the least bad).
///
/// The tests are homogeneous (degree 2 and 3 in the coordinates), so they
/// are evaluated on the corners scaled by the power of two that brings the
/// largest |coordinate| into [½, 1): exact, the same decisions as unscaled
/// wherever those do not overflow or underflow, and no overflow at 1e300.
/// A quad tiny against its distance from the origin may underflow to no
/// valid diagonal here; the general path, which scales by the face's own
/// size, then decides.
fn quad_diagonal(face: &[u32], positions: &[DVec3], edges: &EdgeSet) -> Option<usize> {
    let &[i0, i1, i2, i3] = face else { return None };
    let p = [i0, i1, i2, i3].map(|v| positions[v as usize]);
    let s = PowerOfTwoScale::normalizing(p);
    let p = p.map(|x| s.apply_point(x));
    let n = (p[2] - p[0]).cross(p[3] - p[1]); // Newell: N = Σ Vᵢ × Vᵢ₊₁ (Zheng-Cai Eq. 10) of a quad
    let valid = |a: usize, b: usize, c: usize| {
        let (u, v, w) = (p[b] - p[a], p[c] - p[a], p[c] - p[b]);
        let longest2 = u.length_squared().max(v.length_squared()).max(w.length_squared());
        u.cross(v).dot(n) > DEGENERATE_REL * longest2 * n.length()
    };
    let by_length = if p[1].distance_squared(p[3]) < p[0].distance_squared(p[2]) { [1, 0] } else { [0, 1] };
    by_length.into_iter().find(|&a| {
        let (c, d) = ((a + 2) % 4, (a + 3) % 4);
        !edges.contains(face[a], face[c]) && valid(a, a + 1, c) && valid(a, c, d)
    })
}

/// Hashes a vertex-pair key by the SplitMix64 finaliser (Steele, Lea &
/// Flood 2014): three multiply-xorshift rounds, a fraction of SipHash's
/// cost. Only membership is ever asked, so the result does not depend on
/// the hash.
#[derive(Clone, Copy, Default)]
struct PairHasher(u64);

impl Hasher for PairHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64((self.0 << 8) | u64::from(b));
        }
    }

    fn write_u64(&mut self, key: u64) {
        let mut z = key;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        self.0 = z ^ (z >> 31);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

/// The undirected edges a new diagonal must not duplicate: the mesh's edges
/// between corners of faces that get split, and every diagonal created so far.
struct EdgeSet(HashSet<u64, BuildHasherDefault<PairHasher>>);

impl EdgeSet {
    fn key(a: u32, b: u32) -> u64 {
        let (lo, hi) = if a < b { (a, b) } else { (b, a) };
        (u64::from(lo) << 32) | u64::from(hi)
    }

    fn new(mesh: &Mesh) -> Self {
        let t = mesh.topology();
        // A diagonal joins two corners of a face of four or more corners: only
        // edges between such vertices can be duplicated.
        let mut in_polygon = vec![false; t.vertex_count()];
        for face in t.faces().iter().filter(|face| face.len() > 3) {
            face.iter().for_each(|&v| in_polygon[v as usize] = true);
        }
        let diagonals: usize = t.faces().iter().map(|face| face.len().saturating_sub(3)).sum();
        let mut set = HashSet::with_capacity_and_hasher(t.edge_count() + diagonals, Default::default());
        for e in t.edges() {
            let (a, b) = t.edge_vertices(e);
            if in_polygon[a.index()] && in_polygon[b.index()] {
                set.insert(Self::key(a.0, b.0));
            }
        }
        Self(set)
    }

    /// The mesh's edges between corners of the `selected` faces (the only
    /// diagonals [`check_triangulation`] asks about).
    fn among(t: &Topology, selected: &[bool]) -> Self {
        let mut in_selected = vec![false; t.vertex_count()];
        let mut corners = 0;
        for (face, _) in t.faces().iter().zip(selected).filter(|&(_, &s)| s) {
            face.iter().for_each(|&v| in_selected[v as usize] = true);
            corners += face.len();
        }
        let mut set = HashSet::with_capacity_and_hasher(4 * corners, Default::default());
        for a in t.vertices().filter(|a| in_selected[a.index()]) {
            for b in t.vertex_neighbors(a).filter(|b| a < *b && in_selected[b.index()]) {
                set.insert(Self::key(a.0, b.0));
            }
        }
        Self(set)
    }

    fn contains(&self, a: u32, b: u32) -> bool {
        self.0.contains(&Self::key(a, b))
    }

    fn insert(&mut self, a: u32, b: u32) {
        self.0.insert(Self::key(a, b));
    }

    /// Records the diagonals of a face's triangles (local corner indices): the
    /// sides that join corners not adjacent on the face.
    fn claim_diagonals(&mut self, face: &[u32], triangles: &[[usize; 3]]) {
        let m = face.len();
        for tri in triangles {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                if (a + 1) % m != b && (b + 1) % m != a {
                    self.insert(face[a], face[b]);
                }
            }
        }
    }
}

/// One face being triangulated: its corners in 3D and projected on the
/// best-fit plane. Buffers are reused from face to face.
#[derive(Default)]
struct Polygon {
    /// Vertex ids of the corners.
    ids: Vec<u32>,
    /// Corner positions relative to the first corner (round-off relative to
    /// the face), scaled by the power of two that brings the largest offset
    /// component into [½, 1): every test is a ratio of homogeneous
    /// expressions, which the exact scaling leaves unchanged, and none then
    /// overflows or underflows whatever the face's size.
    p: Vec<DVec3>,
    /// Corners in the plane ⟂ the Newell vector, (u, v, n̂) right-handed.
    q: Vec<DVec2>,
    /// False when the face has zero area (no best-fit plane).
    oriented: bool,
}

impl Polygon {
    fn load(&mut self, face: &[u32], positions: &[DVec3]) {
        let corners = face.iter().map(|&v| positions[v as usize]);
        // Offsets in coordinates scaled to at most 1 (no overflow), then scaled to the face's size.
        let outer = PowerOfTwoScale::normalizing(corners.clone());
        let origin = outer.apply_point(positions[face[0] as usize]);
        self.ids.clear();
        self.ids.extend_from_slice(face);
        self.p.clear();
        self.p.extend(corners.map(|p| outer.apply_point(p) - origin));
        PowerOfTwoScale::normalizing(self.p.iter().copied()).apply_points(&mut self.p);
        let longest =
            (0..face.len()).map(|k| self.p[k].distance_squared(self.p[(k + 1) % face.len()])).fold(0.0, f64::max);
        // Newell: N = Σ Vᵢ × Vᵢ₊₁ (Zheng-Cai Eq. 10), of offsets already scaled to [½, 1) (its scaling is 2⁰).
        let (n, _) = scaled_newell(self.p.iter().copied());
        self.oriented = n.length() > DEGENERATE_REL * longest;
        self.q.clear();
        if self.oriented {
            let n = n.normalize();
            let u = n.any_orthonormal_vector();
            let v = n.cross(u);
            self.q.extend(self.p.iter().map(|p| DVec2::new(p.dot(u), p.dot(v))));
        } else {
            self.q.resize(face.len(), DVec2::ZERO); // never read: scores fall back to shape alone
        }
    }

    fn len(&self) -> usize {
        self.ids.len()
    }

    fn allowed(&self, edges: &EdgeSet, a: usize, b: usize) -> bool {
        !edges.contains(self.ids[a], self.ids[b])
    }

    /// Doubled signed area of corners (a, b, c) in the projection.
    fn orient(&self, a: usize, b: usize, c: usize) -> f64 {
        (self.q[b] - self.q[a]).perp_dot(self.q[c] - self.q[a])
    }

    /// Shape of triangle (a, b, c): the sine of its smallest angle (in 3D) when
    /// it is valid — positively oriented in the projection and not degenerate —
    /// and otherwise a negative number, larger the less bad the triangle is
    /// (for a face with no best-fit plane: by shape alone).
    fn score(&self, a: usize, b: usize, c: usize) -> f64 {
        let (pa, pb, pc) = (self.p[a], self.p[b], self.p[c]);
        let mut l = [pa.distance(pb), pb.distance(pc), pc.distance(pa)];
        l.sort_by(f64::total_cmp);
        let longest2 = l[2] * l[2];
        // The smallest angle lies between the two longest sides: sin = |cross| / (l₁ l₂).
        let sine = if l[1] > 0.0 { (pb - pa).cross(pc - pa).length() / (l[1] * l[2]) } else { 0.0 };
        if !self.oriented {
            return sine - 2.0;
        }
        let s = self.orient(a, b, c);
        if s > DEGENERATE_REL * longest2 {
            sine
        } else {
            s / longest2.max(f64::MIN_POSITIVE) - 2.0
        }
    }

    /// Rule 3 of the module docs.
    fn split_quad(&self, edges: &EdgeSet) -> Option<Vec<[usize; 3]>> {
        let diagonal = |a: usize| [[a, a + 1, (a + 2) % 4], [a, (a + 2) % 4, (a + 3) % 4]];
        let by_length =
            if self.p[1].distance_squared(self.p[3]) < self.p[0].distance_squared(self.p[2]) { [1, 0] } else { [0, 1] };
        let worst =
            |tris: &[[usize; 3]; 2]| tris.iter().map(|&[a, b, c]| self.score(a, b, c)).fold(f64::INFINITY, f64::min);
        let candidates = by_length.iter().filter(|&&a| self.allowed(edges, a, a + 2)).map(|&a| diagonal(a));
        // The first valid one, else the least bad: max_by keeps the last of equals, so scan reversed.
        let first_valid = candidates.clone().find(|tris| worst(tris) > 0.0);
        first_valid.or_else(|| candidates.rev().max_by(|x, y| worst(x).total_cmp(&worst(y)))).map(|t| t.to_vec())
    }

    /// Rules 4 and 5 of the module docs, for faces of five or more corners.
    fn split(&self, edges: &EdgeSet) -> Option<Vec<[usize; 3]>> {
        self.ear_clip(edges, true).or_else(|| {
            if self.len() <= EXHAUSTIVE_MAX_CORNERS {
                self.best_triangulation(edges)
            } else {
                self.ear_clip(edges, false)
            }
        })
    }

    /// The score of the ear at remaining corner `i`, or `None` when it does
    /// not qualify. `strict`: valid, containing no other remaining corner,
    /// with an allowed diagonal; otherwise any ear with an allowed diagonal.
    fn ear(&self, edges: &EdgeSet, ring: &Ring, i: usize, strict: bool) -> Option<f64> {
        let (a, c) = (ring.prev[i], ring.next[i]);
        // The last triangle adds no diagonal: its sides are sides or earlier diagonals.
        if ring.remaining > 3 && !self.allowed(edges, a, c) {
            return None;
        }
        let score = self.score(a, i, c);
        if !strict {
            return Some(score);
        }
        if score <= 0.0 {
            return None;
        }
        let inside =
            |k: usize| self.orient(a, i, k) >= 0.0 && self.orient(i, c, k) >= 0.0 && self.orient(c, a, k) >= 0.0;
        let blocked = ring.corners().any(|k| k != a && k != i && k != c && inside(k));
        (!blocked).then_some(score)
    }

    /// Ear clipping, always clipping the best-scoring qualifying ear (the
    /// first in corner order among equals). `None` when it gets stuck.
    fn ear_clip(&self, edges: &EdgeSet, strict: bool) -> Option<Vec<[usize; 3]>> {
        let m = self.len();
        let mut ring = Ring::new(m);
        let mut scores: Vec<Option<f64>> = (0..m).map(|k| self.ear(edges, &ring, k, strict)).collect();
        let mut triangles = Vec::with_capacity(m - 2);
        // Removing a corner can unblock an ear elsewhere: cached scores of ears
        // not next to it may be stale `None`s, refreshed before giving up.
        let mut fresh = true;
        while ring.remaining > 3 {
            let best = ring.corners().filter_map(|k| scores[k].map(|s| (k, s))).fold(
                None,
                |best: Option<(usize, f64)>, (k, s)| match best {
                    Some((_, b)) if b >= s => best,
                    _ => Some((k, s)),
                },
            );
            let Some((i, _)) = best else {
                if fresh {
                    return None;
                }
                for k in ring.corners().collect::<Vec<_>>() {
                    scores[k] = self.ear(edges, &ring, k, strict);
                }
                fresh = true;
                continue;
            };
            let (a, c) = ring.remove(i);
            triangles.push([a, i, c]);
            scores[a] = self.ear(edges, &ring, a, strict);
            scores[c] = self.ear(edges, &ring, c, strict);
            fresh = false;
        }
        let a = ring.corners().next().expect("three corners remain");
        let (b, c) = (ring.next[a], ring.next[ring.next[a]]);
        // Collinear corners can leave a degenerate last triangle.
        if strict && self.score(a, b, c) <= 0.0 {
            return None;
        }
        triangles.push([a, b, c]);
        Some(triangles)
    }

    /// Rule 5: among all triangulations whose diagonals are allowed, the one
    /// whose worst triangle scores best (interval dynamic programming: the
    /// triangle on side (i, j) of sub-polygon i..j has its apex k in between).
    fn best_triangulation(&self, edges: &EdgeSet) -> Option<Vec<[usize; 3]>> {
        let m = self.len();
        let at = |i: usize, j: usize| i * m + j;
        let mut best = vec![f64::NEG_INFINITY; m * m];
        let mut apex = vec![0usize; m * m];
        for i in 0..m - 1 {
            best[at(i, i + 1)] = f64::INFINITY; // a side of the face: nothing to triangulate
        }
        // Sides (i, j) with j − i ≥ 2 are diagonals, except (0, m − 1).
        let side_ok = |i: usize, j: usize| j - i < 2 || (i == 0 && j == m - 1) || self.allowed(edges, i, j);
        for span in 2..m {
            for i in 0..m - span {
                let j = i + span;
                if !side_ok(i, j) {
                    continue;
                }
                for k in i + 1..j {
                    let worst = best[at(i, k)].min(best[at(k, j)]);
                    if worst == f64::NEG_INFINITY {
                        continue;
                    }
                    let worst = worst.min(self.score(i, k, j));
                    if worst > best[at(i, j)] {
                        best[at(i, j)] = worst;
                        apex[at(i, j)] = k;
                    }
                }
            }
        }
        if best[at(0, m - 1)] == f64::NEG_INFINITY {
            return None;
        }
        let mut triangles = Vec::with_capacity(m - 2);
        let mut stack = vec![(0, m - 1)];
        while let Some((i, j)) = stack.pop() {
            if j - i >= 2 {
                let k = apex[at(i, j)];
                triangles.push([i, k, j]);
                stack.extend([(k, j), (i, k)]);
            }
        }
        Some(triangles)
    }
}

/// The corners of a polygon not yet clipped, as a doubly linked cycle.
struct Ring {
    next: Vec<usize>,
    prev: Vec<usize>,
    alive: Vec<bool>,
    remaining: usize,
}

impl Ring {
    fn new(m: usize) -> Self {
        Self {
            next: (0..m).map(|k| (k + 1) % m).collect(),
            prev: (0..m).map(|k| (k + m - 1) % m).collect(),
            alive: vec![true; m],
            remaining: m,
        }
    }

    /// The remaining corners, in corner order.
    fn corners(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.alive.len()).filter(|&k| self.alive[k])
    }

    /// Unlinks corner `i`; returns its neighbours (now adjacent).
    fn remove(&mut self, i: usize) -> (usize, usize) {
        let (a, c) = (self.prev[i], self.next[i]);
        self.alive[i] = false;
        self.next[a] = c;
        self.prev[c] = a;
        self.remaining -= 1;
        (a, c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn polygon(points: &[DVec3]) -> Polygon {
        let ids: Vec<u32> = (0..points.len() as u32).collect();
        let mut p = Polygon::default();
        p.load(&ids, points);
        p
    }

    fn no_edges() -> EdgeSet {
        EdgeSet(HashSet::default())
    }

    #[test]
    fn scores_rank_valid_above_degenerate_above_flipped() {
        let square = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let p = polygon(&square);
        let right = p.score(0, 1, 2);
        assert!((right - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-15, "45° smallest angle: {right}");
        assert!(p.score(0, 2, 1) < -2.0 + 1e-12, "flipped");
        let collinear = polygon(&[DVec3::ZERO, DVec3::X, 2.0 * DVec3::X, DVec3::Y]);
        let s = collinear.score(0, 1, 2);
        assert!((-2.0..0.0).contains(&s), "degenerate, not flipped: {s}");
    }

    #[test]
    fn dart_quad_takes_the_diagonal_through_the_reflex_corner() {
        // Corner 2 is reflex; diagonal (0, 2) is the longer one but the only valid one.
        let dart = [DVec3::ZERO, DVec3::new(2.0, -1.0, 0.0), DVec3::new(0.5, 0.0, 0.0), DVec3::new(2.0, 1.0, 0.0)];
        let tris = polygon(&dart).split_quad(&no_edges()).unwrap();
        assert_eq!(tris, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn collinear_corners_fall_back_to_the_exhaustive_search() {
        // Face 6 of fixtures/poly/mpi.off: corners 3, 4, 7, 8 are collinear,
        // with a thin notch 4-5-6-7 beside them. Greedy ear clipping can end
        // on the zero-area triangle (3, 4, 7); the search finds a valid split.
        let corners = [
            [-10.0321, -6.02409, -10.0321],
            [-10.0321, -6.02409, -6.02409],
            [-10.01, -6.02406, 5.02005],
            [-6.01926, -6.01926, 5.01605],
            [-6.01926, -6.01926, 4.01284],
            [-6.0072, -6.01925, 4.01284],
            [-6.01685, -6.01926, -4.01284],
            [-6.01926, -6.01926, -4.01284],
            [-6.01926, -6.01926, -6.01926],
            [-6.02409, -6.01927, -10.0321],
        ]
        .map(DVec3::from_array);
        let p = polygon(&corners);
        assert!(p.ear_clip(&no_edges(), true).is_none());
        let tris = p.split(&no_edges()).unwrap();
        assert_eq!(tris.len(), 8);
        assert!(tris.iter().all(|&[a, b, c]| p.score(a, b, c) > 0.0), "{tris:?}");
    }

    #[test]
    fn exhaustive_search_matches_ear_clipping_on_a_convex_polygon_where_both_apply() {
        let hexagon: Vec<DVec3> = (0..6)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 6.0;
                DVec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let p = polygon(&hexagon);
        let worst = |tris: &[[usize; 3]]| tris.iter().map(|&[a, b, c]| p.score(a, b, c)).fold(f64::INFINITY, f64::min);
        let ears = p.ear_clip(&no_edges(), true).unwrap();
        let best = p.best_triangulation(&no_edges()).unwrap();
        assert_eq!((ears.len(), best.len()), (4, 4));
        // The exhaustive search is optimal, so never worse than the greedy choice.
        assert!(worst(&best) >= worst(&ears) - 1e-15);
        assert!(worst(&best) > 0.0);
    }
}
