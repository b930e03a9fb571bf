//! Doo-Sabin: the parameterisation and the regular patches.
//!
//! **Domains.** One domain per face corner, and on open or creased meshes
//! two per side of every sharp edge (the strips below). Corner domains: `(face, K)` is the quarter of
//! the face at corner K, (u, v) ∈ \[0,1\]², (0,0) at corner K's vertex V,
//! (1,0) toward the midpoint of edge K → K+1, (0,1) toward the midpoint of
//! edge K−1 → K, (1,1) at the face's centre. On a regular quad lattice this
//! is the biquadratic B-spline's own parameterisation (the patch centred on
//! V, a quarter of it per face around V). Where the points are:
//! * (0,0): the limit point of V — the centroid of V's V-face after one step
//!   (what `subdivide --levels 0 --limit` gives for V);
//! * (1,1): the face's centroid (every later F-face keeps it and shrinks to it);
//! * (½,½): the limit point of the level-1 vertex that is the image of
//!   corner K (the centre of its biquadratic patch).
//!
//! **Refinement of a domain.** After one step the image x of corner K has
//! four faces: the F-face of the face, the V-face of V and the E-faces of
//! the face's edges at V. The domain splits into the four quarters of those
//! faces at x, each a level-1 domain of the same kind with (0,0) at x (at the
//! domain's (½,½)):
//!
//! | quarter of (u, v) | face at x | its (u′, v′) |
//! |---|---|---|
//! | u < ½, v < ½ | V-face of V | (1 − 2u, 1 − 2v) |
//! | u ≥ ½, v < ½ | E-face of edge K → K+1 | (1 − 2v, 2u − 1) |
//! | u ≥ ½, v ≥ ½ | F-face | (2u − 1, 2v − 1) |
//! | u < ½, v ≥ ½ | E-face of edge K−1 → K | (2v − 1, 1 − 2u) |
//!
//! (the orientations follow from the faces' counter-clockwise corner order:
//! from x, the V-face's next corner lies toward −u, the next E-face's toward
//! −v, the previous E-face's toward +v).
//!
//! **Regular patches.** A domain whose corner vertex has four faces, all
//! quads, is the quarter toward the face of the biquadratic B-spline patch of
//! the 3×3 points around the vertex: patch parameters (½ + u/2, ½ + v/2).
//! Every vertex has valence 4 after one step, so the irregular points are the
//! centres of non-quad faces (the (1,1) corner of a domain). There the
//! position is the face's centroid; the derivatives come from the face's own
//! points, which refine among themselves (the F-face's images are a circulant
//! combination of its corners with eigenvalues 1, ½ (twice), ¼): with Π the
//! projector on the eigenvalue-½ modes, ∂S/∂a = (ΠP)\[next\] − (ΠP)\[corner\]
//! per unit of the level's lattice — the exact derivative at a regular
//! face's centre, and the tangent masks' value at an extraordinary one.
//!
//! **Boundaries: strip domains.** On an open mesh the face corners do not
//! reach the boundary curve (the quadratic B-spline of the boundary
//! polygon, `subdiv_rules::doo_sabin`, "Boundary rule"): after one step the
//! Chaikin points and their quarters lie outside every corner domain. The
//! boundary rule is exactly the closed rule on the mesh extended by a
//! degenerate quad q = (B, A, A′, B′) beyond every boundary half-edge
//! A → B of a face f, with A′ = A and B′ = B (the repeated boundary row:
//! Eq. 1 on q gives A's Chaikin point ¾A + ¼B, the V-face of A is its
//! images closed by its two Chaikin points, the E-face of A → B its two
//! images and Chaikin points, and the images of q's corners are again such
//! a strip one level down). The two quarters of q at its real corners are
//! domains too:
//! * `(f, n + 2K)`: the quarter of q at A = corner K (half-edge K → K+1 a
//!   boundary), (0,0) at A, u outward (toward A′), v along the edge toward B;
//! * `(f, n + 2K + 1)`: the quarter at B = corner K+1, u along the edge
//!   toward A, v outward (toward B′);
//!
//! (n the face's size), parameterised and refined as any domain (q's corner
//! order gives the frames). Where the points are: the boundary curve is
//! u = 1 of the first and v = 1 of the second; (1,1) of both is the curve's
//! point at the edge's midpoint, (A + B)/2; A's point of the curve,
//! (B₋ + 6A + B₊)/8 (what `subdivide --limit` gives for a boundary vertex),
//! is (1,0) of the strip at the start of A's outgoing boundary half-edge and
//! (0,1) of the strip at the end of its incoming one; A's level-1 Chaikin
//! point on A → B is (1,½) of the first strip, B's is (½,1) of the second.
//! The strip at A meets the corner domain (f, K) along u = 0 ≡ v = 0 of
//! (f, K), the strip at B meets (f, K+1) along v = 0 ≡ u = 0, the two strips
//! of an edge meet along v = 1 ≡ u = 1, and consecutive boundary edges'
//! strips meet along v = 0 of the next one's start strip ≡ u = 0 of the end
//! strip. Across the boundary curve the derivative is zero (a repeated
//! row): the normal there is the limit of the normals inside, from the
//! second derivative (`surface` module). Regular patches: a vertex with two
//! sharp edges and two quads on a side is the biquadratic patch whose row
//! beyond the curve repeats the row on it.
//!
//! **Creases.** An infinitely sharp crease is a boundary for the faces on
//! each side (`subdiv-stencil`'s Doo-Sabin module): without corners and
//! darts the tagged step is exactly the boundary rule on the mesh cut along
//! its creases, so the surface is evaluated on that cut mesh
//! ([`cut_along_creases`]), each side of a crease with its strips; the two
//! sides' strips meet on the sharp curve (G⁰ there).
//!
//! **Interior vertices of valence 2.** They have no V-face: after one step
//! the E-faces of their two edges meet along the edge between the two
//! images, and the quarter u, v < ½ of each of their domains has no surface.
//! It is folded onto that edge: S(u, v) = S(½, min(u, v)), so (0,0) is the
//! vertex's limit point (the valence-2 mask of `subdivide --limit`, the
//! centroid of the next level's E-face of that edge), the derivatives are
//! those of the fold (one of them zero) and the normal is the surface's.
//! The points of such a quarter have other parameters too: projection
//! continues its iterates across the fold (`LimitSurface::unfold`).
//!
//! Not handled (typed [`EvalError::Unsupported`], from [`check`]): corners
//! (a corner tag, or three or more boundary and crease edges at a vertex, as
//! where a crease meets the boundary) and darts (one crease edge). There the
//! sharp curve is clamped or fades, the refined mesh is not a strip of
//! repeated rows, and the cut-mesh identity above fails; they need their own
//! cells (the corner point's sectors, the dart's single Chaikin point).

use crate::local::{Local, Refined};
use crate::patch::{sector, Combo, Lattice, PatchKind, RegularSpec};
use crate::surface::EvalError;
use subdiv_mesh::refine::DualFeatures;
use subdiv_mesh::{FaceId, FaceList, HalfEdgeId, Mesh, Topology, VertexId, SHARPNESS_INFINITE};
use subdiv_stencil::{LevelSharpness, Options, Scheme, SchemeTraits};

/// The scheme's table row: the regular face size and valence of [`SPEC`].
const TRAITS: SchemeTraits = Scheme::DooSabin.traits();

/// The regular Doo-Sabin patch (its kind and lattice; the points are
/// gathered around a vertex by [`regular`]).
pub(crate) const SPEC: RegularSpec = RegularSpec {
    lattice: Lattice::Square,
    face_size: TRAITS.regular_face_size,
    valence: TRAITS.regular_valence,
    crease_sector: 2,
    corner_sector: None,
    corners: &[(0, 0)],
    frames: &FRAMES,
    dirs: &DIRS,
    points: &[],
    kind: PatchKind::Biquadratic,
};

/// Lattice directions of the edges around a regular vertex, counter-clockwise.
const DIRS: [(i32, i32); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];

/// Per corner of a domain: the (u, v) directions toward its neighbours along
/// the domain's edges (only the centre, corner 2, is ever an irregular point).
pub(crate) const FRAMES: [crate::patch::Frame; 4] =
    [((1, 0), (0, 1)), ((0, 1), (-1, 0)), ((-1, 0), (0, -1)), ((0, -1), (1, 0))];

/// Marks a phantom cell in a cell code (the rest: `2·half-edge + end`).
const PHANTOM: u32 = 1 << 31;

/// A cell of the parameterisation at some level (module docs), as the half-edges
/// of a local submesh name it. Passed around as a `u32` code ([`Cell::code`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Cell {
    /// The quarter of a face at a corner: the half-edge leaving the corner in the face.
    Corner(HalfEdgeId),
    /// The quarter of the phantom quad beyond a sharp half-edge A → B at A
    /// (`at_end` false) or at B.
    Phantom { h: HalfEdgeId, at_end: bool },
}

impl Cell {
    fn of(code: u32) -> Self {
        if code & PHANTOM == 0 {
            Cell::Corner(HalfEdgeId(code))
        } else {
            let c = code & !PHANTOM;
            Cell::Phantom { h: HalfEdgeId(c >> 1), at_end: c & 1 == 1 }
        }
    }

    fn code(self) -> u32 {
        match self {
            Cell::Corner(h) => h.0,
            Cell::Phantom { h, at_end } => PHANTOM | (h.0 << 1) | u32::from(at_end),
        }
    }
}

/// Whether the edge of `h` is sharp: a boundary or an infinitely sharp crease.
fn is_sharp(t: &Topology, sharp: &LevelSharpness, h: HalfEdgeId) -> bool {
    t.he_twin(h).is_none() || sharp.edge(t, t.he_edge(h)) >= SHARPNESS_INFINITE
}

/// Sharp edges at `v` (creases, and a boundary vertex's two boundary edges).
fn sharp_edges_at(t: &Topology, sharp: &LevelSharpness, v: VertexId) -> usize {
    t.vertex_fan(v).iter().filter(|&&h| is_sharp(t, sharp, h)).count() + usize::from(t.is_boundary_vertex(v))
}

/// Refuses what the domains here do not cover (module docs).
pub(crate) fn check(mesh: &Mesh, _options: &Options) -> Result<(), EvalError> {
    let t = mesh.topology();
    let unsupported = |reason: String| Err(EvalError::Unsupported { scheme: "doo-sabin", reason });
    let features = DualFeatures::new(t, mesh.tags());
    for v in t.vertices() {
        if features.is_corner(v) {
            return unsupported(format!(
                "vertex {} is a corner (a corner tag, or three or more boundary and crease edges): \
                 limit evaluation at Doo-Sabin corners is not implemented",
                v.0
            ));
        }
        if !t.is_boundary_vertex(v) && features.sharp_edge_count(t, v) == 1 {
            return unsupported(format!(
                "vertex {} is a dart (one crease edge): limit evaluation at Doo-Sabin darts is not implemented",
                v.0
            ));
        }
    }
    Ok(())
}

/// The mesh cut along its creases: every vertex gets one copy per sector
/// (its faces between two consecutive crease edges), so the creases become
/// boundaries. With no corner and no dart ([`check`]) the tagged Doo-Sabin
/// step is exactly the boundary rule on the cut mesh (`subdiv-stencil`'s
/// Doo-Sabin module, "Creases and corners": the sharp points depend only on
/// the edge's ends, corner images are untouched, a V-face per sector), so
/// the two limit surfaces are one. Faces keep their ids and corner order.
/// Returns the cut connectivity and the original vertex of every copy;
/// `None` without creases.
pub(crate) fn cut_along_creases(mesh: &Mesh) -> Result<Option<(Topology, Vec<u32>)>, EvalError> {
    let t = mesh.topology();
    let features = DualFeatures::new(t, mesh.tags());
    if !t.edges().any(|e| features.is_crease(e)) {
        return Ok(None);
    }
    let crease = |h: HalfEdgeId| features.is_crease(t.he_edge(h));
    let mut copy = vec![u32::MAX; t.half_edge_count()];
    let mut original = Vec::with_capacity(t.vertex_count());
    for v in t.vertices() {
        let fan = t.vertex_fan(v);
        let k = fan.len();
        // Counter-clockwise, face i + 1 follows face i across the edge of fan[i + 1].
        let start = (0..k).find(|&i| crease(fan[i])).unwrap_or(0);
        for j in 0..k {
            let h = fan[(start + j) % k];
            if j == 0 || crease(h) {
                original.push(v.0);
            }
            copy[h.index()] = original.len() as u32 - 1;
        }
    }
    let mut faces = FaceList::with_capacity(t.face_count(), t.half_edge_count());
    let mut buf = Vec::new();
    for f in t.face_ids() {
        buf.clear();
        buf.extend(t.face_half_edges(f).map(|h| copy[h.index()]));
        faces.push(&buf);
    }
    let cut =
        Topology::new(faces, original.len()).map_err(|e| EvalError::Internal(format!("cut along creases: {e}")))?;
    Ok(Some((cut, original)))
}

/// The domains of face `f` (module docs): its corners `0..n`, then per
/// sharp edge K → K+1 the two phantom quarters `n + 2K` (at corner K) and
/// `n + 2K + 1` (at corner K+1).
pub(crate) fn face_domains(t: &Topology, sharp: &LevelSharpness, f: FaceId) -> Vec<u32> {
    let n = t.face_size(f) as u32;
    let mut out: Vec<u32> = (0..n).collect();
    for (k, h) in t.face_half_edges(f).enumerate() {
        if is_sharp(t, sharp, h) {
            out.extend([n + 2 * k as u32, n + 2 * k as u32 + 1]);
        }
    }
    out
}

/// The quarter of a domain holding (u, v): 0 V-face, 1 E-face of the next
/// edge, 2 F-face, 3 E-face of the previous edge; its parameters `A·(u, v) + b`.
pub(crate) fn child(u: f64, v: f64) -> (usize, [[f64; 2]; 2], [f64; 2]) {
    match (u >= 0.5, v >= 0.5) {
        (false, false) => (0, [[-2.0, 0.0], [0.0, -2.0]], [1.0, 1.0]),
        (true, false) => (1, [[0.0, -2.0], [2.0, 0.0]], [1.0, -1.0]),
        (true, true) => (2, [[2.0, 0.0], [0.0, 2.0]], [-1.0, -1.0]),
        (false, true) => (3, [[0.0, 2.0], [-2.0, 0.0]], [-1.0, 1.0]),
    }
}

/// The face centre (1,1), the only point that can be irregular.
pub(crate) fn corner_at(u: f64, v: f64) -> Option<usize> {
    (u == 1.0 && v == 1.0).then_some(2)
}

/// The irregular point nearest to (u, v) within a cell: its centre.
pub(crate) fn nearest_corner(_u: f64, _v: f64) -> usize {
    2
}

/// The refined face holding half-edge `h` and the cell code in that face's
/// ring (face 0 of the ring, so its half-edges are its corner indices).
fn in_ring(t: &Topology, h: HalfEdgeId, phantom: Option<bool>) -> (FaceId, u32) {
    let c = t.he_corner(h);
    let j = HalfEdgeId(c.index);
    let cell = match phantom {
        None => Cell::Corner(j),
        Some(at_end) => Cell::Phantom { h: j, at_end },
    };
    (c.face, cell.code())
}

/// Child `k` of the cell `cell` (a [`FaceId`] holding its code) after one
/// step: the refined face at the cell's image and the child's code in that
/// face's ring (module docs, "Refinement of a domain"). Found on the refined
/// connectivity alone: the image of corner h is new vertex h, the F-face
/// keeps the face's half-edge numbers, and every point of the refined sharp
/// polygon near an end of a sharp half-edge is two steps along its side's E-face.
pub(crate) fn child_cell(
    _local: &Local,
    refined: &Refined,
    cell: FaceId,
    k: usize,
) -> Result<(FaceId, u32), EvalError> {
    let r = &refined.t;
    let broken = || EvalError::Internal("the Doo-Sabin step lacks a face around an image".into());
    let twin = |h: HalfEdgeId| r.he_twin(h).ok_or_else(broken);
    let (h, phantom) = match Cell::of(cell.0) {
        Cell::Corner(h) => {
            // Around the image x = h, counter-clockwise: F-face, E-face of the
            // previous edge, V-face, E-face of the next edge.
            let next_e = r.he_next(twin(h)?);
            let prev_e = twin(r.he_prev(h))?;
            match k {
                0 => {
                    let v = twin(r.he_prev(prev_e))?;
                    if v == next_e {
                        return Err(broken());
                    }
                    (v, None)
                }
                1 => (next_e, None),
                2 => (h, None),
                _ => (prev_e, None),
            }
        }
        Cell::Phantom { h, at_end } => {
            // The E-face of h's side runs image(B) → image(A) → (point near A)
            // → … → (point near B) → image(B).
            let e = twin(h)?;
            if !at_end {
                let out = r.he_next(r.he_next(e)); // x = point near A → along the sharp polygon
                let v_face = twin(r.he_prev(out))?; // leaving x in A's V-face
                let into = r.he_prev(v_face); // the sharp polygon into x
                match k {
                    0 => (v_face, None),
                    1 => (into, Some(true)),
                    2 => (out, Some(false)),
                    _ => (out, None),
                }
            } else {
                let e_face = r.he_prev(e); // leaving x = point near B in the E-face
                let into = r.he_prev(e_face);
                let out = r.he_next(twin(e_face)?); // leaving x in B's V-face, along the sharp polygon
                match k {
                    0 => (out, None),
                    1 => (e_face, None),
                    2 => (into, Some(true)),
                    _ => (out, Some(false)),
                }
            }
        }
    };
    Ok(in_ring(r, h, phantom))
}

/// Whether the image of a corner cell has a V-face after one step (not at
/// an interior vertex of valence 2: the E-faces of its two edges meet there).
pub(crate) fn has_v_face(refined: &Refined, cell: FaceId) -> bool {
    let r = &refined.t;
    match Cell::of(cell.0) {
        Cell::Corner(h) => {
            let next_e = r.he_twin(h).map(|e| r.he_next(e));
            let prev_e = r.he_twin(r.he_prev(h));
            let v = prev_e.and_then(|p| r.he_twin(r.he_prev(p)));
            v.is_some() && v != next_e
        }
        Cell::Phantom { .. } => true,
    }
}

/// The domain `(face 0 of the root, corner)`: its cell.
pub(crate) fn domain_start(
    local: &Local,
    _options: &Options,
    face: FaceId,
    corner: usize,
) -> Result<(Local, FaceId), EvalError> {
    let t = &local.t;
    let n = t.face_size(face);
    let first = t.faces().offsets()[face.index()];
    let cell = if corner < n {
        Cell::Corner(HalfEdgeId(first + corner as u32))
    } else {
        let (k, at_end) = ((corner - n) / 2, (corner - n) % 2 == 1);
        let h = HalfEdgeId(first + k as u32);
        if k >= n || !is_sharp(t, &local.sharp, h) {
            return Err(EvalError::NoSuchDomain { face: face.0, corner: corner as u32 });
        }
        Cell::Phantom { h, at_end }
    };
    Ok((local.clone(), FaceId(cell.code())))
}

/// Lattice coordinates in a cell's frame → in a half-edge's frame.
type ToFrame = fn(i32, i32) -> (i32, i32);

/// The 3×3 points of the regular patch around the corner vertex x of `cell`
/// (index `3j + i`, i along the cell's u), if x has four faces, all quads,
/// and no sharp edge, or lies on a straight sharp curve (exactly two sharp
/// edges, no corner tag) with two quads on the cell's side: then the row
/// beyond the curve repeats the row on it (the boundary rule's phantom
/// quads, module docs).
pub(crate) fn regular(t: &Topology, sharp: &LevelSharpness, cell: FaceId) -> Option<Vec<Combo>> {
    // The vertex, a real half-edge leaving it, and the map from cell
    // coordinates to that half-edge's frame (u along it, v toward its face's
    // previous corner).
    let (x, h0, to_frame): (VertexId, HalfEdgeId, ToFrame) = match Cell::of(cell.0) {
        Cell::Corner(h) => (t.he_from(h), h, |a, b| (a, b)),
        // At A: u outward (−v of h's frame), v along h.
        Cell::Phantom { h, at_end: false } => (t.he_from(h), h, |a, b| (b, -a)),
        // At B: u back along h (+v of next(h)'s frame), v outward (−u).
        Cell::Phantom { h, at_end: true } => (t.he_to(h), t.he_next(h), |a, b| (-b, a)),
    };
    let (faces, closed) = sector(t, sharp, h0);
    if closed {
        if faces.len() != 4 || t.vertex_face_count(x) != 4 {
            return None;
        }
    } else if faces.len() != 2 || sharp_edges_at(t, sharp, x) != 2 || sharp.vertex(t, x) >= SHARPNESS_INFINITE {
        return None;
    }
    let mut grid: [[Option<u32>; 3]; 3] = [[None; 3]; 3];
    grid[1][1] = Some(x.0);
    let mut lo = 0;
    for &(i, h) in &faces {
        let g = t.he_face(h);
        if t.face_size(g) != 4 {
            return None;
        }
        lo = lo.min(i);
        let k = t.he_corner(h).index as usize;
        let ring = t.face(g);
        let (d0, d1) = (DIRS[i.rem_euclid(4) as usize], DIRS[(i + 1).rem_euclid(4) as usize]);
        for (d, vtx) in
            [(d0, ring[(k + 1) % 4]), ((d0.0 + d1.0, d0.1 + d1.1), ring[(k + 2) % 4]), (d1, ring[(k + 3) % 4])]
        {
            grid[(d.1 + 1) as usize][(d.0 + 1) as usize] = Some(vtx);
        }
    }
    if !closed {
        // The sharp line through x along DIRS[lo]: a point beyond it repeats its foot on it.
        let along_u = DIRS[lo.rem_euclid(4) as usize].1 == 0;
        for y in 0..3 {
            for xx in 0..3 {
                if grid[y][xx].is_none() {
                    grid[y][xx] = if along_u { grid[1][xx] } else { grid[y][1] };
                }
            }
        }
    }
    let mut out = Vec::with_capacity(9);
    for b in -1..=1 {
        for a in -1..=1 {
            let (p, q) = to_frame(a, b);
            out.push(vec![(grid[(q + 1) as usize][(p + 1) as usize]?, 1.0)]);
        }
    }
    Some(out)
}

/// At the centre of the face of `cell` (a phantom quad: (B, A, A, B) for
/// (B, A, A′, B′)): its centroid and the derivatives along the domain's −u
/// and −v directions (module docs).
pub(crate) fn vertex_limit(
    local: &Local,
    _options: &Options,
    cell: FaceId,
    _k: usize,
) -> Result<[Vec<f64>; 3], EvalError> {
    let t = &local.t;
    let (ring, j): (Vec<u32>, usize) = match Cell::of(cell.0) {
        Cell::Corner(h) => {
            let c = t.he_corner(h);
            (t.face(c.face).to_vec(), c.index as usize)
        }
        Cell::Phantom { h, at_end } => {
            let (a, b) = (t.he_from(h).0, t.he_to(h).0);
            (vec![b, a, a, b], usize::from(!at_end))
        }
    };
    let m = ring.len();
    let mf = m as f64;
    // Π[a][b] = (2/m)·cos(2π(a − b)/m): the projector on the eigenvalue-½ modes.
    let pi = |a: usize, b: usize| 2.0 / mf * (std::f64::consts::TAU * (a as f64 - b as f64) / mf).cos();
    let mut pos = vec![0.0; local.root];
    let mut ta = vec![0.0; local.root];
    let mut tb = vec![0.0; local.root];
    let (next, prev) = ((j + 1) % m, (j + m - 1) % m);
    let centroid: Combo = ring.iter().map(|&v| (v, 1.0 / mf)).collect();
    // Along −u′ (−½ per lattice unit toward the next corner), likewise −v′.
    let along = |e: usize| -> Combo { (0..m).map(|b| (ring[b], -0.5 * (pi(e, b) - pi(j, b)))).collect() };
    local.combine(&centroid, &mut pos);
    local.combine(&along(next), &mut ta);
    local.combine(&along(prev), &mut tb);
    Ok([pos, ta, tb])
}
