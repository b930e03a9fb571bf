//! Doo-Sabin: the parameterisation and the regular patches.
//!
//! **Domains.** One domain per face corner: `(face, K)` is the quarter of
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
//! Not handled here (typed [`EvalError::Unsupported`]): boundaries (the
//! Chaikin boundary rule), creases and corners, and interior vertices of
//! valence 2 (no V-face).

use crate::local::{Local, Refined};
use crate::patch::{sector, Combo, Lattice, PatchKind, RegularSpec};
use crate::surface::EvalError;
use subdiv_mesh::{FaceId, HalfEdgeId, Mesh, Topology};
use subdiv_stencil::{LevelSharpness, Options};

/// The regular Doo-Sabin patch (its kind and lattice; the points are
/// gathered around a vertex by [`regular`]).
pub(crate) const SPEC: RegularSpec = RegularSpec {
    lattice: Lattice::Square,
    face_size: 4,
    valence: 4,
    crease_sector: 2,
    corner_sector: None,
    corners: &[(0, 0)],
    frames: &FRAMES,
    dirs: &[(1, 0), (0, 1), (-1, 0), (0, -1)],
    points: &[],
    kind: PatchKind::Biquadratic,
};

/// Per corner of a domain: the (u, v) directions toward its neighbours along
/// the domain's edges (only the centre, corner 2, is ever an irregular point).
pub(crate) const FRAMES: [crate::patch::Frame; 4] =
    [((1, 0), (0, 1)), ((0, 1), (-1, 0)), ((-1, 0), (0, -1)), ((0, -1), (1, 0))];

/// Refuses what the domains here do not cover (module docs).
pub(crate) fn check(mesh: &Mesh, _options: &Options) -> Result<(), EvalError> {
    let t = mesh.topology();
    let unsupported = |reason: String| Err(EvalError::Unsupported { scheme: "doo-sabin", reason });
    if !t.is_closed() {
        return unsupported(
            "limit evaluation on meshes with a boundary is not implemented (closed meshes only)".into(),
        );
    }
    if !mesh.tags().is_empty() {
        return unsupported("limit evaluation with creases or corners is not implemented".into());
    }
    if let Some(v) = t.vertices().find(|&v| t.vertex_face_count(v) == 2) {
        return unsupported(format!("vertex {} has valence 2 (no V-face): not handled", v.0));
    }
    Ok(())
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

/// Child `k` of the domain at corner half-edge `cell` (a [`FaceId`] holding
/// the half-edge): the refined face at the corner's image and that image's
/// corner in it.
pub(crate) fn child_cell(local: &Local, refined: &Refined, cell: FaceId, k: usize) -> (FaceId, u32) {
    let t = &local.t;
    let h = HalfEdgeId(cell.0);
    let dual = refined.dual.as_ref().expect("the standard Doo-Sabin step has its provenance");
    let nf = t.face_count() as u32;
    let g = match k {
        0 => dual.vertex_face[t.he_from(h).index()].expect("checked: no valence-2 vertices"),
        1 => FaceId(nf + t.he_edge(h).0),
        2 => t.he_face(h),
        _ => FaceId(nf + t.he_edge(t.he_prev(h)).0),
    };
    // New vertex h is the image of corner h.
    let j = refined.t.face(g).iter().position(|&x| x == h.0).expect("the image is a corner of its faces");
    (g, j as u32)
}

/// The domain `(face 0 of the root, corner)`: its corner half-edge.
pub(crate) fn domain_start(
    local: &Local,
    _options: &Options,
    face: FaceId,
    corner: usize,
) -> Result<(Local, FaceId), EvalError> {
    let h = local.t.faces().offsets()[face.index()] + corner as u32;
    Ok((local.clone(), FaceId(h)))
}

/// The 3×3 points of the regular patch around the corner vertex of `cell`
/// (index `3j + i`, i along the corner's next edge), if the vertex has four
/// faces, all quads.
pub(crate) fn regular(t: &Topology, cell: FaceId) -> Option<Vec<Combo>> {
    let h0 = HalfEdgeId(cell.0);
    let x = t.he_from(h0);
    if t.is_boundary_vertex(x) || t.vertex_face_count(x) != 4 {
        return None;
    }
    let (faces, closed) = sector(t, &LevelSharpness::plain(), h0);
    if !closed || faces.len() != 4 {
        return None;
    }
    let dirs = [(1, 0), (0, 1), (-1, 0), (0, -1)];
    let mut grid: [[Option<u32>; 3]; 3] = [[None; 3]; 3];
    grid[1][1] = Some(x.0);
    for &(i, h) in &faces {
        let g = t.he_face(h);
        if t.face_size(g) != 4 {
            return None;
        }
        let k = t.he_corner(h).index as usize;
        let ring = t.face(g);
        let (d0, d1) = (dirs[i.rem_euclid(4) as usize], dirs[(i + 1).rem_euclid(4) as usize]);
        for (d, vtx) in
            [(d0, ring[(k + 1) % 4]), ((d0.0 + d1.0, d0.1 + d1.1), ring[(k + 2) % 4]), (d1, ring[(k + 3) % 4])]
        {
            grid[(d.1 + 1) as usize][(d.0 + 1) as usize] = Some(vtx);
        }
    }
    let mut out = Vec::with_capacity(9);
    for row in grid {
        for p in row {
            out.push(vec![(p?, 1.0)]);
        }
    }
    Some(out)
}

/// At the centre of the face of `cell`: its centroid and the derivatives
/// along the domain's −u and −v directions (module docs).
pub(crate) fn vertex_limit(
    local: &Local,
    _options: &Options,
    cell: FaceId,
    _k: usize,
) -> Result<[Vec<f64>; 3], EvalError> {
    let t = &local.t;
    let h = HalfEdgeId(cell.0);
    let c = t.he_corner(h);
    let ring = t.face(c.face);
    let m = ring.len();
    let j = c.index as usize;
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
