//! The √3 split (Kobbelt 2000) of a triangle mesh by index arithmetic: one
//! child triangle per parent half-edge, its twins from the parent's.
//!
//! Numbering (`crate::refine::sqrt3_split`'s): old vertices `0..V`, then
//! `V + f` per parent face f — its centroid, or in a trisecting step on a
//! face with a boundary edge h the trisection point of h near from(h) —,
//! then, trisecting, `V + F + i` the trisection point near to(hᵢ) of the
//! i-th boundary half-edge in loop order.
//!
//! c(x), for a parent half-edge x of face f, is the new point of f on x's
//! side: V + f, except in a trisecting step on a face with boundary
//! half-edge h, where c(next h) = the point near to(h) and c(prev h) = the
//! point near from(h) (= V + f). Child triangle x, with half-edges 3x + j:
//! - x interior, twin y: (from x, c(y), c(x)) — one of the two triangles of
//!   the flipped edge, which joins c(x) and c(y);
//! - x on the boundary, odd step: (from x, to x, V + f) — not flipped;
//! - x on the boundary, trisecting: (p, q, apex) — the middle third of the
//!   boundary triangle, p and q the trisection points near from(x), to(x).
//!
//! Twins (y = twin x; "even" = trisecting):
//! - 3x+0: boundary x: none. Interior x: even with next(y) on the boundary:
//!   none (from(x) → p is a new boundary edge); even with prev(y) on the
//!   boundary: 3·prev(y)+1; else 3·next(y)+2.
//! - 3x+1: interior x: 3y+1. Boundary x: odd 3·next(x)+2, even
//!   3·twin(next x)+0.
//! - 3x+2: odd: 3·twin(prev x)+0, or 3·prev(x)+1 when prev(x) is on the
//!   boundary. Even: boundary x: 3·prev(x)+2; interior x with next(x) on the
//!   boundary: 3·next(x)+2; with prev(x) on the boundary: none (q → to(prev x)
//!   is a new boundary edge); else 3·twin(prev x)+0.

use super::super::{HalfEdgeFaces, Topology, NONE};
use crate::soup::FaceList;

impl Topology {
    /// The √3 split (module docs). `second_point[h]` is the vertex of the
    /// trisection point near to(h) of boundary half-edge h when `trisect`
    /// (unused otherwise). The caller guarantees triangles and, when
    /// trisecting, at most one boundary edge per face.
    pub(crate) fn sqrt3_split(&self, trisect: bool, second_point: &[u32]) -> Topology {
        let nv = self.vertex_count as usize;
        let nf = self.faces.len();
        let nh = 3 * nf;
        let next = |h: usize| 3 * (h / 3) + (h + 1) % 3;
        let prev = |h: usize| 3 * (h / 3) + (h + 2) % 3;
        let twin = |h: usize| self.he_twin[h];
        let on_boundary = |h: usize| self.he_twin[h] == NONE;
        let face_point = |h: usize| (nv + h / 3) as u32;
        // c(x): the new point of x's face on x's side.
        let c = |x: usize| -> u32 {
            if trisect && on_boundary(prev(x)) {
                second_point[prev(x)] // x = next(h): the point near to(h)
            } else {
                face_point(x)
            }
        };
        let mut tris = Vec::with_capacity(3 * nh);
        let mut he_twin = vec![NONE; 3 * nh];
        let child = |x: usize, j: usize| (3 * x + j) as u32;
        for x in 0..nh {
            let from = self.faces.indices()[x];
            match (twin(x), trisect) {
                (NONE, false) => tris.extend_from_slice(&[from, self.faces.indices()[next(x)], face_point(x)]),
                (NONE, true) => {
                    tris.extend_from_slice(&[face_point(x), second_point[x], self.faces.indices()[prev(x)]])
                }
                (y, _) => tris.extend_from_slice(&[from, c(y as usize), c(x)]),
            }
            // 3x + 0
            he_twin[3 * x] = match twin(x) {
                NONE => NONE,
                y => {
                    let y = y as usize;
                    if trisect && on_boundary(next(y)) {
                        NONE
                    } else if trisect && on_boundary(prev(y)) {
                        child(prev(y), 1)
                    } else {
                        child(next(y), 2)
                    }
                }
            };
            // 3x + 1
            he_twin[3 * x + 1] = match twin(x) {
                NONE if trisect => child(twin(next(x)) as usize, 0),
                NONE => child(next(x), 2),
                y => child(y as usize, 1),
            };
            // 3x + 2
            he_twin[3 * x + 2] = if !trisect {
                match twin(prev(x)) {
                    NONE => child(prev(x), 1),
                    z => child(z as usize, 0),
                }
            } else if on_boundary(x) {
                child(prev(x), 2)
            } else if on_boundary(next(x)) {
                child(next(x), 2)
            } else if on_boundary(prev(x)) {
                NONE
            } else {
                child(twin(prev(x)) as usize, 0)
            };
        }
        let vertex_count = nv + nf + if trisect { self.loop_he.len() } else { 0 };
        let face_component = (0..nh).map(|x| self.face_component[x / 3]).collect();
        let mut topology = Topology::from_faces_and_twins(
            FaceList::from_uniform(3, tris),
            he_twin,
            vertex_count,
            (Vec::new(), vec![0]),
            face_component,
            self.component_count,
        );
        topology.he_face = HalfEdgeFaces::Uniform(3); // the face of a half-edge by arithmetic, as `new` finds it
        topology
    }
}
