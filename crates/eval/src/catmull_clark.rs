//! Catmull-Clark: regular patches are uniform bicubic B-splines on quads
//! whose corners are regular (valence 4 inside, two faces on a crease or
//! boundary, one face at a corner), a quad's (u, v) domain is split into its
//! four level-1 quads (children in the quad split's corner order), and an
//! n-gon (n ≠ 4) is OpenSubdiv's ptex split: domain `(face, K)` is the
//! level-1 quad at corner K, (0,0) at corner K, (1,0) at the midpoint of
//! edge K → K+1, (0,1) at the midpoint of edge K−1 → K, (1,1) at the face
//! point.

use crate::patch::{Lattice, PatchKind, RegularSpec};
use subdiv_stencil::{Scheme, SchemeTraits};

/// The scheme's table row: the regular face size and valence of [`SPEC`].
const TRAITS: SchemeTraits = Scheme::CatmullClark.traits();

/// The regular Catmull-Clark patch: the 4×4 points around a quad, corner 0
/// at lattice (0,0), u toward corner 1.
#[rustfmt::skip]
pub(crate) const SPEC: RegularSpec = RegularSpec {
    lattice: Lattice::Square,
    face_size: TRAITS.regular_face_size,
    valence: TRAITS.regular_valence,
    crease_sector: 2,
    corner_sector: Some(1),
    corners: &[(0, 0), (1, 0), (1, 1), (0, 1)],
    frames: &FRAMES,
    dirs: &[(1, 0), (0, 1), (-1, 0), (0, -1)],
    points: &[
        (-1, -1), (0, -1), (1, -1), (2, -1),
        (-1, 0), (0, 0), (1, 0), (2, 0),
        (-1, 1), (0, 1), (1, 1), (2, 1),
        (-1, 2), (0, 2), (1, 2), (2, 2),
    ],
    kind: PatchKind::Bicubic,
};

/// Per corner of a quad: the (u, v) directions of its edges toward the next
/// and the previous corner.
pub(crate) const FRAMES: [((i32, i32), (i32, i32)); 4] =
    [((1, 0), (0, 1)), ((0, 1), (-1, 0)), ((-1, 0), (0, -1)), ((0, -1), (1, 0))];

/// The level-1 quad of a quad holding (u, v) (its corner index, the quad
/// split's child at that corner) and the child's parameters as
/// `A·(u, v) + b`: (k, A, b). Ties go to the higher corner.
pub(crate) fn child(u: f64, v: f64) -> (usize, [[f64; 2]; 2], [f64; 2]) {
    match (u >= 0.5, v >= 0.5) {
        (false, false) => (0, [[2.0, 0.0], [0.0, 2.0]], [0.0, 0.0]),
        (true, false) => (1, [[0.0, 2.0], [-2.0, 0.0]], [0.0, 2.0]),
        (true, true) => (2, [[-2.0, 0.0], [0.0, -2.0]], [2.0, 2.0]),
        (false, true) => (3, [[0.0, -2.0], [2.0, 0.0]], [2.0, 0.0]),
    }
}

/// The corner of the quad at (u, v), if (u, v) is one.
pub(crate) fn corner_at(u: f64, v: f64) -> Option<usize> {
    match (u, v) {
        (0.0, 0.0) => Some(0),
        (1.0, 0.0) => Some(1),
        (1.0, 1.0) => Some(2),
        (0.0, 1.0) => Some(3),
        _ => None,
    }
}

/// The corner nearest to (u, v).
pub(crate) fn nearest_corner(u: f64, v: f64) -> usize {
    child(u, v).0
}
