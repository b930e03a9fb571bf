//! The Doo-Sabin split with infinitely sharp creases and corners.
//!
//! A sharp edge is an infinitely sharp crease (sharpness ≥
//! [`SHARPNESS_INFINITE`]) or a boundary edge; a corner is a vertex with
//! corner sharpness ≥ [`SHARPNESS_INFINITE`] or with at least three sharp
//! edges ([`DualFeatures`]). The split treats every sharp edge as a boundary
//! of the faces on each side of it: each sharp edge gets the points of the
//! refined sharp polygon ([`SharpPoint`]: Chaikin's two, or, next to a
//! corner, the corner itself and the edge's midpoint), each side of it an
//! E-face through them, and every vertex one V-face per *sector* (a run of
//! its faces between two sharp edges), closed by those points. The two sides
//! of a crease share its points, so the mesh stays one manifold, glued along
//! the refined crease polygon. Why this gives Chaikin's curve and keeps face
//! centroids as limit points: `subdiv-stencil`'s Doo-Sabin module.
//!
//! Semi-sharp values (0 < s < 10) have no Doo-Sabin meaning; here they count
//! as smooth, and `subdiv-stencil` rejects them before splitting.

use super::{dual_split, DualFace, DualVertex};
use crate::ids::{EdgeId, HalfEdgeId, VertexId};
use crate::tags::{Tags, SHARPNESS_INFINITE};
use crate::topology::{SharpDualSplit, SharpPointIds, Topology};

/// Marker for "no such point" in [`SharpDualProvenance`]'s tables.
const NONE: u32 = u32::MAX;

/// The sharp features of one Doo-Sabin level, from its tags: which edges are
/// infinitely sharp creases and which vertices are corners (boundary edges
/// are always sharp and are not stored). Computed once per level; without
/// tags it stores nothing.
#[derive(Clone, Debug, Default)]
pub struct DualFeatures {
    /// Per edge: an interior edge with sharpness ≥ 10; empty if there is none.
    crease: Vec<bool>,
    /// Per vertex: a corner; empty if there is none.
    corner: Vec<bool>,
    /// Per vertex: its number of creases (saturating); empty without creases.
    creases_at: Vec<u8>,
}

impl DualFeatures {
    /// Classifies the edges and vertices of `t` under `tags`: an interior
    /// edge is a crease iff its sharpness is ≥ [`SHARPNESS_INFINITE`]; a
    /// vertex used by a face is a corner iff its corner sharpness is ≥
    /// [`SHARPNESS_INFINITE`] or it has three or more sharp (crease or
    /// boundary) edges. Smaller values count as smooth. Linear time.
    ///
    /// # Panics
    /// If `tags` were made for a topology with other edge or vertex counts (a
    /// caller bug).
    pub fn new(t: &Topology, tags: &Tags) -> Self {
        let (edges, vertices) = (tags.edge_values(), tags.vertex_values());
        assert!(edges.is_empty() || edges.len() == t.edge_count(), "tags of another topology");
        assert!(vertices.is_empty() || vertices.len() == t.vertex_count(), "tags of another topology");
        let mut crease: Vec<bool> = t
            .edges()
            .map(|e| edges.get(e.index()).is_some_and(|&s| s >= SHARPNESS_INFINITE) && !t.is_boundary_edge(e))
            .collect();
        if !crease.contains(&true) {
            crease = Vec::new();
        }
        let mut creases_at = Vec::new();
        if !crease.is_empty() {
            creases_at = vec![0u8; t.vertex_count()];
            for e in t.edges().filter(|e| crease[e.index()]) {
                let (a, b) = t.edge_vertices(e);
                creases_at[a.index()] = creases_at[a.index()].saturating_add(1);
                creases_at[b.index()] = creases_at[b.index()].saturating_add(1);
            }
        }
        let mut corner = Vec::new();
        if !crease.is_empty() || !vertices.is_empty() {
            corner = t
                .vertices()
                .map(|v| {
                    let sharp =
                        creases_at.get(v.index()).map_or(0, |&c| u32::from(c)) + 2 * u32::from(t.is_boundary_vertex(v));
                    !t.is_isolated(v) && (tags.vertex_sharpness(v) >= SHARPNESS_INFINITE || sharp >= 3)
                })
                .collect();
            if !corner.contains(&true) {
                corner = Vec::new();
            }
        }
        Self { crease, corner, creases_at }
    }

    /// Whether some edge is a crease or some vertex a corner, i.e. whether the
    /// split differs from [`dual_split`].
    pub fn has_features(&self) -> bool {
        !self.crease.is_empty() || !self.corner.is_empty()
    }

    /// Whether interior edge `e` is an infinitely sharp crease.
    #[inline]
    pub fn is_crease(&self, e: EdgeId) -> bool {
        self.crease.get(e.index()).copied().unwrap_or(false)
    }

    /// Whether edge `e` is sharp: a crease or a boundary edge.
    #[inline]
    pub fn is_sharp(&self, t: &Topology, e: EdgeId) -> bool {
        t.is_boundary_edge(e) || self.is_crease(e)
    }

    /// Number of sharp edges at `v` (saturating at 255): its creases, plus 2
    /// on the boundary. O(1).
    #[inline]
    pub fn sharp_edge_count(&self, t: &Topology, v: VertexId) -> usize {
        usize::from(self.creases_at.get(v.index()).copied().unwrap_or(0)) + 2 * usize::from(t.is_boundary_vertex(v))
    }

    /// Whether `v` is a corner.
    #[inline]
    pub fn is_corner(&self, v: VertexId) -> bool {
        self.corner.get(v.index()).copied().unwrap_or(false)
    }

    /// The other ends of the sharp edges at `v`, in fan order (on the
    /// boundary: its next boundary neighbour first, its previous one last).
    pub fn sharp_neighbors<'a>(&'a self, t: &'a Topology, v: VertexId) -> impl Iterator<Item = VertexId> + 'a {
        let fan = t.vertex_fan(v);
        let previous = t.boundary_neighbors(v).map(|(previous, _)| previous);
        fan.iter().filter(move |&&h| self.is_sharp(t, t.he_edge(h))).map(|&h| t.he_to(h)).chain(previous)
    }

    /// The new vertices of a tagged dual split after the H corner images,
    /// in order: the corner points (vertex order), then along every boundary
    /// loop and then every crease edge (edge order), per edge a→b (its first
    /// half-edge): the point near a unless a is a corner, the midpoint if both
    /// ends are, the point near b unless b is a corner. Without features
    /// these are [`dual_split`]'s two Chaikin points per boundary half-edge.
    pub fn sharp_points(&self, t: &Topology) -> Vec<SharpPoint> {
        self.layout(t, false).points
    }

    /// [`Self::sharp_points`] with, when `tables`, the new vertex of every
    /// corner point and of every sharp edge's points.
    fn layout(&self, t: &Topology, tables: bool) -> SharpLayout {
        let nh = t.half_edge_count() as u32;
        let mut points = Vec::new();
        let mut corner_point = if tables { vec![NONE; t.vertex_count()] } else { Vec::new() };
        for v in t.vertices().filter(|&v| self.is_corner(v)) {
            if tables {
                corner_point[v.index()] = nh + points.len() as u32;
            }
            points.push(SharpPoint::Corner { vertex: v });
        }
        let mut edge_points = if tables { vec![[NONE; 3]; t.edge_count()] } else { Vec::new() };
        let creases =
            (self.crease.iter().enumerate()).filter(|&(_, &c)| c).map(|(e, _)| t.edge_half_edge(EdgeId(e as u32)));
        for h in t.boundary_loops().flatten().copied().chain(creases) {
            let (a, b) = (t.he_from(h), t.he_to(h));
            let (corner_a, corner_b) = (self.is_corner(a), self.is_corner(b));
            let add = |point: SharpPoint, points: &mut Vec<SharpPoint>| {
                points.push(point);
                nh + points.len() as u32 - 1
            };
            let at_a = if corner_a {
                corner_point.get(a.index()).copied().unwrap_or(NONE)
            } else {
                add(SharpPoint::Chaikin { half_edge: h, near_start: true, far_is_corner: corner_b }, &mut points)
            };
            let mid = if corner_a && corner_b { add(SharpPoint::Midpoint { half_edge: h }, &mut points) } else { NONE };
            let at_b = if corner_b {
                corner_point.get(b.index()).copied().unwrap_or(NONE)
            } else {
                add(SharpPoint::Chaikin { half_edge: h, near_start: false, far_is_corner: corner_a }, &mut points)
            };
            if tables {
                edge_points[t.he_edge(h).index()] = [at_a, mid, at_b];
            }
        }
        SharpLayout { points, edge_points, corner_point }
    }
}

/// [`DualFeatures::layout`]'s result.
pub(crate) struct SharpLayout {
    points: Vec<SharpPoint>,
    edge_points: Vec<[u32; 3]>,
    corner_point: Vec<u32>,
}

/// A new vertex of a tagged Doo-Sabin split that lies on the refined sharp
/// polygon (the vertices after the corner images). The position rules are
/// `subdiv_rules::doo_sabin`'s: Chaikin's ¾, ¼ (`BOUNDARY_EDGE_POINT`), ½,
/// ½ next to a corner (`CLAMPED_EDGE_POINT`), the corner itself.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SharpPoint {
    /// On sharp half-edge `half_edge` a→b (a boundary half-edge, or a crease
    /// edge's first half-edge), the point near a (`near_start`) or near b:
    /// ¾·near + ¼·far, or ½·near + ½·far when the far end is a corner
    /// (`far_is_corner`).
    Chaikin {
        /// The sharp half-edge.
        half_edge: HalfEdgeId,
        /// True for the point near the half-edge's start.
        near_start: bool,
        /// Whether the far end is a corner (the clamped end rule).
        far_is_corner: bool,
    },
    /// The midpoint of sharp half-edge `half_edge`, both of whose ends are
    /// corners.
    Midpoint {
        /// The sharp half-edge.
        half_edge: HalfEdgeId,
    },
    /// Corner `vertex`, kept where it is.
    Corner {
        /// The corner.
        vertex: VertexId,
    },
}

/// Provenance of a tagged Doo-Sabin refinement ([`dual_split_tagged`]).
///
/// New vertex `x < H` is the image of old corner `x`, as in
/// [`super::DualProvenance`]; vertex `H + i` is `sharp_points[i]`.
///
/// `#[non_exhaustive]`: made by [`dual_split_tagged`], read through its
/// public fields (a new field is not a breaking change).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct SharpDualProvenance {
    /// The points of the refined sharp polygon ([`DualFeatures::sharp_points`]).
    pub sharp_points: Vec<SharpPoint>,
    /// Provenance of every new face: F-faces (one per old face, id = old
    /// face id), then per old edge its E-face, or one per side of a sharp
    /// edge (two for a crease), then per old vertex its V-faces (one per
    /// sector, or the triangles round a corner without sharp edges).
    pub face_origin: Vec<DualFace>,
    /// Per old edge, the new vertices of its points near the start of its
    /// first half-edge, at its midpoint and near its end (`u32::MAX` where
    /// there is none; all three for a smooth edge).
    pub edge_points: Vec<[u32; 3]>,
    /// Per old vertex, the new vertex that keeps it (`u32::MAX` unless it is a corner).
    pub corner_point: Vec<u32>,
}

/// The Doo-Sabin connectivity of `t` with the infinitely sharp creases and
/// the corners of `tags` ([`DualFeatures`]; the module docs give the
/// construction), the refined mesh's tags, and the provenance.
///
/// The new tags carry every crease on: each piece of an old crease keeps its
/// sharpness, the piece at a crease vertex between its two creases gets the
/// smaller of theirs, and a tagged corner's point its corner sharpness; a
/// corner by three sharp edges stays one without a tag. With no crease and
/// no corner the topology is [`dual_split`]'s, bit for bit, and the tags are
/// empty. Linear time.
///
/// # Panics
/// If `tags` were made for a topology with other counts (a caller bug), or
/// if the refined mesh would exceed the `u32` index range.
pub fn dual_split_tagged(t: &Topology, tags: &Tags) -> (Topology, SharpDualProvenance, Tags) {
    let features = DualFeatures::new(t, tags);
    if !features.has_features() {
        return untagged_split(t);
    }
    let (split, layout) = general_split(t, &features);
    let refined = &split.topology;
    let mut edges = vec![0.0; refined.edge_count()];
    for &(h, [a, b]) in &split.crease_segments {
        edges[refined.he_edge(h).index()] = tags.edge_sharpness(a).min(tags.edge_sharpness(b));
    }
    let tagged_corners =
        (t.vertices()).filter(|&v| tags.vertex_sharpness(v) >= SHARPNESS_INFINITE && features.is_corner(v));
    let mut vertices = Vec::new();
    for v in tagged_corners {
        vertices.resize(refined.vertex_count(), 0.0);
        vertices[layout.corner_point[v.index()] as usize] = tags.vertex_sharpness(v);
    }
    let new_tags = Tags::from_arrays(refined, edges, vertices).expect("refined sharpness values are valid tags");
    let provenance = SharpDualProvenance {
        sharp_points: layout.points,
        face_origin: split.face_origin,
        edge_points: layout.edge_points,
        corner_point: layout.corner_point,
    };
    (split.topology, provenance, new_tags)
}

/// The general construction of the split ([`Topology::dual_split_sharp`])
/// and the sharp points' tables it used.
pub(crate) fn general_split(t: &Topology, features: &DualFeatures) -> (SharpDualSplit, SharpLayout) {
    let sharp: Vec<bool> = t.edges().map(|e| features.is_sharp(t, e)).collect();
    let layout = features.layout(t, true);
    let touches_sharp = |v: usize| features.sharp_edge_count(t, VertexId(v as u32)) > 0;
    let ids = SharpPointIds {
        sharp: &sharp,
        touches_sharp: &touches_sharp,
        edge_points: &layout.edge_points,
        corner_point: &layout.corner_point,
        vertex_count: t.half_edge_count() + layout.points.len(),
    };
    (t.dual_split_sharp(&ids), layout)
}

/// [`dual_split_tagged`] without features: [`dual_split`] and its provenance.
fn untagged_split(t: &Topology) -> (Topology, SharpDualProvenance, Tags) {
    let (topology, provenance) = dual_split(t);
    let nh = t.half_edge_count();
    let sharp_points = provenance.vertex_origin[nh..]
        .iter()
        .map(|origin| match *origin {
            DualVertex::Boundary { half_edge, near_start } => {
                SharpPoint::Chaikin { half_edge, near_start, far_is_corner: false }
            }
            DualVertex::Corner { .. } => unreachable!("corner images come first"),
        })
        .collect();
    let mut edge_points = vec![[NONE; 3]; t.edge_count()];
    for &h in t.boundary_loops().flatten() {
        let c = provenance.boundary_point[h.index()];
        edge_points[t.he_edge(h).index()] = [c, NONE, c + 1];
    }
    let corner_point = vec![NONE; t.vertex_count()];
    let provenance =
        SharpDualProvenance { sharp_points, face_origin: provenance.face_origin, edge_points, corner_point };
    (topology, provenance, Tags::none())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    /// The general construction without features is [`dual_split`]'s, field
    /// by field: what lets [`dual_split_tagged`] take the fast path then.
    #[test]
    fn general_construction_without_features_is_the_untagged_split() {
        let holes = [(1, 1), (3, 3)];
        let meshes = [
            shapes::cube(),
            shapes::quad_grid(4, 3),
            shapes::torus(5, 4),
            shapes::pillow(),
            shapes::polygon_mix(&shapes::plate_with_holes(7, 5, &holes, false), 3, 0.5, 0.3, 0.1),
        ];
        for mesh in &meshes {
            let t = mesh.topology();
            let (general, _) = general_split(t, &DualFeatures::default());
            let (direct, provenance) = dual_split(t);
            assert_eq!(format!("{:?}", general.topology), format!("{direct:?}"));
            assert_eq!(general.face_origin, provenance.face_origin);
            assert!(general.crease_segments.is_empty());
        }
    }
}
