//! Loop: regular patches are quartic box splines on triangles whose corners
//! are regular (valence 6 inside, three triangles on a crease or boundary);
//! a triangle's barycentric (u, v) domain (corner 0 at (0,0), 1 at (1,0), 2
//! at (0,1)) is split into the triangle split's four children: the corner
//! triangles 0, 1, 2 (corner 0 of each at the old corner, 1 toward the next
//! corner) and the centre triangle 3 (corners at the midpoints of edges
//! 0→1, 1→2, 2→0).

use crate::patch::{Lattice, PatchKind, RegularSpec, BOX_POINTS};
use subdiv_stencil::{LoopBeta, Scheme, SchemeTraits};

/// The scheme's table row: the regular face size and valence of [`SPEC`].
const TRAITS: SchemeTraits = Scheme::Loop(LoopBeta::Warren).traits();

/// The regular Loop patch: twelve points around a triangle, corner 0 at
/// lattice (0,0), u toward corner 1, v toward corner 2.
pub(crate) const SPEC: RegularSpec = RegularSpec {
    lattice: Lattice::Hex,
    face_size: TRAITS.regular_face_size,
    valence: TRAITS.regular_valence,
    crease_sector: 3,
    corner_sector: None,
    corners: &[(0, 0), (1, 0), (0, 1)],
    frames: &FRAMES,
    dirs: &[(1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1)],
    points: &BOX_POINTS,
    kind: PatchKind::BoxSpline,
};

/// Per corner of a triangle: the (u, v) directions of its edges toward the
/// next and the previous corner.
pub(crate) const FRAMES: [((i32, i32), (i32, i32)); 3] = [((1, 0), (0, 1)), ((-1, 1), (-1, 0)), ((0, -1), (1, -1))];

/// The child triangle holding (u, v) and its parameters `A·(u, v) + b`.
pub(crate) fn child(u: f64, v: f64) -> (usize, [[f64; 2]; 2], [f64; 2]) {
    if u + v <= 0.5 {
        (0, [[2.0, 0.0], [0.0, 2.0]], [0.0, 0.0])
    } else if u >= 0.5 {
        (1, [[0.0, 2.0], [-2.0, -2.0]], [0.0, 2.0])
    } else if v >= 0.5 {
        (2, [[-2.0, -2.0], [2.0, 0.0]], [2.0, 0.0])
    } else {
        (3, [[2.0, 2.0], [-2.0, 0.0]], [-1.0, 1.0])
    }
}

/// The corner of the triangle at (u, v), if (u, v) is one.
pub(crate) fn corner_at(u: f64, v: f64) -> Option<usize> {
    match (u, v) {
        (0.0, 0.0) => Some(0),
        (1.0, 0.0) => Some(1),
        (0.0, 1.0) => Some(2),
        _ => None,
    }
}

/// The corner nearest to (u, v).
pub(crate) fn nearest_corner(u: f64, v: f64) -> usize {
    if u >= v.max(1.0 - u - v) {
        1
    } else if v >= 1.0 - u - v {
        2
    } else {
        0
    }
}
