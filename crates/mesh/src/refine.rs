//! Refinement topology: the connectivity of one subdivision step, computed once
//! per level and independent of positions. The numbering of new vertices is a
//! contract with `subdiv-stencil`, which builds the matching stencil matrices.
//!
//! | split | new vertices, in this order | new faces |
//! |---|---|---|
//! | [`quad_split`] (Catmull-Clark, Deng-Ma) | old vertices `0..V`, face points `V..V+F`, edge points `V+F..V+F+E` | one quad per old corner `h`: face id `h` |
//! | [`triangle_split`] (Loop) | old vertices `0..V`, edge points `V..V+E` | per triangle `f`: corner triangles `4f..4f+3`, centre `4f+3` |
//! | [`sqrt3_split`] (√3) | old vertices `0..V`, per face `V..V+F` its centroid (or, trisecting, the first trisection point of its boundary edge), trisecting: the second trisection points `V+F..V+F+B` | one triangle per old half-edge `h`: face id `h` (see [`Sqrt3Provenance`]) |
//! | [`dual_split`] (Doo-Sabin) | one per old corner `h` (`0..H`), then two Chaikin points per boundary half-edge | F-faces, E-faces, V-faces (see [`DualProvenance`]) |
//! | [`dual_split_tagged`] (Doo-Sabin with creases and corners) | one per old corner, then the points of the refined sharp polygon ([`DualFeatures::sharp_points`]) | F-faces, an E-face per side of a sharp edge, a V-face per sector (see [`SharpDualProvenance`]) |
//!
//! Isolated vertices of the input stay isolated vertices (quad and triangle
//! split) or disappear (dual split, which keeps no old vertex).

use crate::error::MeshError;
use crate::ids::{EdgeId, FaceId, HalfEdgeId, VertexId};
use crate::topology::Topology;

mod sharp;
pub(crate) use sharp::general_split;
pub use sharp::{dual_split_tagged, DualFeatures, SharpDualProvenance, SharpPoint};

/// Catmull-Clark connectivity: every `m`-gon becomes `m` quads
/// `(vₖ, e(vₖvₖ₊₁), f, e(vₖ₋₁vₖ))`, keeping the orientation.
pub fn quad_split(t: &Topology) -> Topology {
    t.quad_split()
}

/// Loop connectivity: every triangle becomes four. Fails when a face is not a triangle.
pub fn triangle_split(t: &Topology) -> Result<Topology, MeshError> {
    require_triangles(t)?;
    Ok(t.triangle_split())
}

pub(crate) fn require_triangles(t: &Topology) -> Result<(), MeshError> {
    match t.face_ids().find(|&f| t.face_size(f) != 3) {
        Some(f) => Err(MeshError::NotTriangles { face: f.0, size: t.face_size(f) }),
        None => Ok(()),
    }
}

/// Where a vertex of a √3 step comes from ([`Sqrt3Provenance::origin`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sqrt3Vertex {
    /// An old vertex, same index (moved by the smoothing rule).
    Old(VertexId),
    /// The centroid of an old triangle.
    Centroid(FaceId),
    /// A trisection point of boundary half-edge `half_edge` (a→b): at a
    /// third of the way from a (`near_start`) or from b.
    Trisection {
        /// The old boundary half-edge.
        half_edge: HalfEdgeId,
        /// True for the point nearer the half-edge's start.
        near_start: bool,
    },
}

/// The numbering of a √3 step ([`sqrt3_split`]): what every new vertex is
/// made from, by index arithmetic on the parent.
///
/// New vertex `v < V` is old vertex v; `V + f` is old face f's point: its
/// centroid, or, in a trisecting step on a face with a boundary edge h, the
/// trisection point of h near from(h); `V + F + i` (trisecting only) is the
/// trisection point near to(hᵢ) of the i-th boundary half-edge hᵢ, loop by
/// loop in [`Topology::boundary_loops`] order. New face `h` is the triangle
/// of old half-edge h: (from h, c(twin h), c(h)) for an interior h — one of
/// the two triangles across the flipped edge, c(x) the new point of x's face
/// next to x —; (from h, to h, centroid) for a boundary h in a plain step;
/// the middle third (p, q, opposite corner) of its triangle for a boundary h
/// in a trisecting step.
///
/// `#[non_exhaustive]`: made by [`Sqrt3Provenance::new`] and [`sqrt3_split`].
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Sqrt3Provenance {
    /// Whether the step trisects the boundary (Kobbelt's even steps).
    pub trisects: bool,
    /// Vertex count V of the parent.
    pub old_vertex_count: usize,
    /// Face count F of the parent.
    pub old_face_count: usize,
    /// Trisecting: the boundary half-edges in loop order (hᵢ above); empty otherwise.
    pub boundary_half_edges: Vec<HalfEdgeId>,
    /// Trisecting: per old half-edge, its second trisection point (`V + F + i`), `u32::MAX` inside.
    second_point: Vec<u32>,
    /// Trisecting: per old face, its boundary half-edge, `u32::MAX` for a face without one.
    face_boundary: Vec<u32>,
}

impl Sqrt3Provenance {
    /// The numbering of a √3 step on `t`, trisecting the boundary or not.
    ///
    /// # Errors
    /// [`MeshError::NotTriangles`] for another polygon;
    /// [`MeshError::TrisectionNeedsOneBoundaryEdge`] when trisecting a face
    /// with more than one boundary edge (an even step follows an odd one,
    /// which leaves at most one per face).
    pub fn new(t: &Topology, trisects: bool) -> Result<Self, MeshError> {
        require_triangles(t)?;
        let (nv, nf) = (t.vertex_count(), t.face_count());
        let (mut boundary_half_edges, mut second_point, mut face_boundary) = (Vec::new(), Vec::new(), Vec::new());
        if trisects {
            second_point = vec![u32::MAX; t.half_edge_count()];
            face_boundary = vec![u32::MAX; nf];
            for &h in t.boundary_loops().flatten() {
                let f = t.he_face(h);
                if face_boundary[f.index()] != u32::MAX {
                    let edges = t.face_half_edges(f).filter(|&x| t.he_twin(x).is_none()).count();
                    return Err(MeshError::TrisectionNeedsOneBoundaryEdge { face: f.0, boundary_edges: edges });
                }
                face_boundary[f.index()] = h.0;
                second_point[h.index()] = (nv + nf + boundary_half_edges.len()) as u32;
                boundary_half_edges.push(h);
            }
        }
        Ok(Self {
            trisects,
            old_vertex_count: nv,
            old_face_count: nf,
            boundary_half_edges,
            second_point,
            face_boundary,
        })
    }

    /// Number of new vertices: V + F, plus B (boundary edges) when trisecting.
    pub fn vertex_count(&self) -> usize {
        self.old_vertex_count + self.old_face_count + self.boundary_half_edges.len()
    }

    /// Where new vertex `v` comes from.
    ///
    /// # Panics
    /// If `v` is not below [`Self::vertex_count`].
    pub fn origin(&self, v: VertexId) -> Sqrt3Vertex {
        let (nv, nf) = (self.old_vertex_count, self.old_face_count);
        let i = v.index();
        if i < nv {
            return Sqrt3Vertex::Old(v);
        }
        if i < nv + nf {
            let f = i - nv;
            return match self.face_boundary.get(f) {
                Some(&h) if h != u32::MAX => Sqrt3Vertex::Trisection { half_edge: HalfEdgeId(h), near_start: true },
                _ => Sqrt3Vertex::Centroid(FaceId(f as u32)),
            };
        }
        Sqrt3Vertex::Trisection { half_edge: self.boundary_half_edges[i - nv - nf], near_start: false }
    }

    /// Per old half-edge, its second trisection point (trisecting; `u32::MAX` inside).
    pub(crate) fn second_points(&self) -> &[u32] {
        &self.second_point
    }
}

/// √3 connectivity (Kobbelt 2000): a point per triangle joined to its
/// corners, every old interior edge flipped; boundary edges are kept, and a
/// trisecting step (`trisect`, Kobbelt's even steps) splits each boundary
/// edge in three and its triangle into three around the opposite corner
/// before the flips. Numbering: [`Sqrt3Provenance`].
///
/// ```text
///  plain step on boundary edge a─b        trisecting step on a─b (apex x)
///            x                                        x
///          ╱ │ ╲                                   ╱ ╱ ╲ ╲
///        ╱   m   ╲        kept, not flipped      ╱  ╱   ╲  ╲
///      ╱  ╱     ╲  ╲                           ╱  ╱       ╲  ╲
///     a ─────────── b                         a ─ p ───── q ─ b
/// ```
/// (after the flips of x─a and x─b, a─p and q─b lie in triangles with the
/// neighbouring faces' points; the middle (p, q, x) remains).
///
/// # Errors
/// As [`Sqrt3Provenance::new`].
pub fn sqrt3_split(t: &Topology, trisect: bool) -> Result<(Topology, Sqrt3Provenance), MeshError> {
    let provenance = Sqrt3Provenance::new(t, trisect)?;
    let topology = t.sqrt3_split(trisect, provenance.second_points());
    Ok((topology, provenance))
}

/// Where a vertex of a Doo-Sabin refinement comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DualVertex {
    /// The image of old vertex `vertex` in old face `face` (corner `corner` of it).
    Corner {
        /// The old face.
        face: FaceId,
        /// The old vertex.
        vertex: VertexId,
        /// Position of the vertex in the face.
        corner: u32,
    },
    /// A Chaikin point on boundary half-edge `half_edge` (a→b), at ¾a + ¼b
    /// (`near_start`) or ¼a + ¾b.
    Boundary {
        /// The old boundary half-edge.
        half_edge: HalfEdgeId,
        /// True for the point nearer the half-edge's start.
        near_start: bool,
    },
}

/// Where a face of a Doo-Sabin refinement comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DualFace {
    /// F-face: the shrunken copy of an old face (same size).
    F(FaceId),
    /// E-face: the quad across an old edge (interior edge, or a boundary edge
    /// joined to its two Chaikin points).
    E(EdgeId),
    /// V-face: around an old vertex (valence-gon; on the boundary its corners
    /// plus the two Chaikin points next to it).
    V(VertexId),
}

/// Provenance of a Doo-Sabin refinement ([`dual_split`]).
///
/// New vertex `h < H` is the image of corner `h` (old half-edge `h` starts at
/// it), so "the image of V in face f" is the half-edge of `f` leaving V. Faces
/// come in the order F-faces (one per old face, id = old face id), E-faces (one
/// per old edge, in edge order), V-faces (one per non-isolated old vertex of
/// valence ≥ 3 or on the boundary, in vertex order). The V-face of an interior vertex lists its corners in fan
/// order; the boundary rule is described in `subdiv-stencil`'s Doo-Sabin module.
///
/// `#[non_exhaustive]`: made by [`dual_split`], read through its public
/// fields (a new field is not a breaking change).
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct DualProvenance {
    /// Provenance of every new vertex.
    pub vertex_origin: Vec<DualVertex>,
    /// Provenance of every new face.
    pub face_origin: Vec<DualFace>,
    /// For every old vertex, its V-face (`None` for isolated vertices and for
    /// interior vertices of valence 2, whose V-face would be a digon).
    pub vertex_face: Vec<Option<FaceId>>,
    /// For every old boundary half-edge, the index of its first Chaikin point
    /// (`u32::MAX` for interior half-edges).
    pub boundary_point: Vec<u32>,
}

/// Doo-Sabin connectivity: F-, E- and V-faces (module table). On the boundary,
/// each boundary half-edge a→b of face f gets two Chaikin points c_a, c_b and
/// the E-face (b_f, a_f, c_a, c_b); each boundary vertex v gets the V-face
/// (c on its outgoing boundary edge, its corners in fan order, c on its
/// incoming boundary edge). The new boundary polygon is thus exactly the
/// Chaikin refinement of the old one.
pub fn dual_split(t: &Topology) -> (Topology, DualProvenance) {
    let (vertex_origin, boundary_point) = dual_vertices(t);
    let mut face_origin = Vec::with_capacity(t.face_count() + t.edge_count() + t.vertex_count());
    face_origin.extend(t.face_ids().map(DualFace::F));
    face_origin.extend(t.edges().map(DualFace::E));
    let mut vertex_face = vec![None; t.vertex_count()];
    for v in t.vertices() {
        let fan = t.vertex_fan(v).len();
        // No V-face for isolated vertices and interior vertices of valence 2.
        if fan > 0 && (fan != 2 || t.is_boundary_vertex(v)) {
            vertex_face[v.index()] = Some(FaceId(face_origin.len() as u32));
            face_origin.push(DualFace::V(v));
        }
    }
    let topology = t.dual_split(&boundary_point);
    (topology, DualProvenance { vertex_origin, face_origin, vertex_face, boundary_point })
}

/// The new vertices of a Doo-Sabin split — one per old corner, then two
/// Chaikin points per boundary half-edge, loop by loop — and, per old
/// half-edge, its first Chaikin point (`u32::MAX` inside).
pub(crate) fn dual_vertices(t: &Topology) -> (Vec<DualVertex>, Vec<u32>) {
    let nh = t.half_edge_count();
    let mut vertex_origin: Vec<DualVertex> = Vec::with_capacity(nh);
    for f in t.face_ids() {
        for (k, &v) in t.face(f).iter().enumerate() {
            vertex_origin.push(DualVertex::Corner { face: f, vertex: VertexId(v), corner: k as u32 });
        }
    }
    let mut boundary_point = vec![u32::MAX; nh];
    for &h in t.boundary_loops().flatten() {
        boundary_point[h.index()] = vertex_origin.len() as u32;
        vertex_origin.push(DualVertex::Boundary { half_edge: h, near_start: true });
        vertex_origin.push(DualVertex::Boundary { half_edge: h, near_start: false });
    }
    (vertex_origin, boundary_point)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    #[test]
    fn counts_follow_the_split_rules() {
        // pmp-library style exact combinatorics.
        let cube = shapes::cube();
        let q = quad_split(cube.topology());
        assert_eq!((q.vertex_count(), q.edge_count(), q.face_count()), (26, 48, 24));
        let ico = shapes::icosahedron();
        let l = triangle_split(ico.topology()).unwrap();
        assert_eq!((l.vertex_count(), l.face_count()), (42, 80));
        assert!(matches!(triangle_split(cube.topology()), Err(MeshError::NotTriangles { face: 0, size: 4 })));
        let (d, _) = dual_split(cube.topology());
        assert_eq!((d.vertex_count(), d.face_count()), (24, 6 + 12 + 8));
        assert!(d.vertices().all(|v| d.valence(v) == 4));
    }

    #[test]
    fn splits_keep_euler_characteristic_and_boundary_loops() {
        let holes = [(1, 1), (3, 2)];
        for closed in [true, false] {
            let base = shapes::plate_with_holes(6, 5, &holes, closed);
            let mixed = shapes::polygon_mix(&base, 7, 0.3, 0.3, 0.0);
            let t = mixed.topology();
            for refined in [quad_split(t), dual_split(t).0] {
                assert_eq!(refined.euler_characteristic(), t.euler_characteristic());
                assert_eq!(refined.boundary_loop_count(), t.boundary_loop_count());
                assert_eq!(refined.genus(), t.genus());
            }
        }
    }

    #[test]
    fn dual_split_boundary_doubles_the_boundary_polygon() {
        let grid = shapes::quad_grid(3, 2);
        let (refined, d) = dual_split(grid.topology());
        let old: usize = grid.topology().boundary_loops().map(<[_]>::len).sum();
        let new: Vec<_> = refined.boundary_loops().collect();
        assert_eq!(new.len(), 1);
        assert_eq!(new[0].len(), 2 * old);
        // Every new boundary vertex is a Chaikin point.
        for &h in new[0] {
            let v = refined.he_from(h);
            assert!(matches!(d.vertex_origin[v.index()], DualVertex::Boundary { .. }));
        }
    }
}
