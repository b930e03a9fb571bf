//! Feature edges by dihedral angle: the creases a CAD-like mesh shows, found
//! from its geometry so that they can be tagged infinitely sharp.
//!
//! The *dihedral turning angle* of an interior edge is the angle between the
//! unit Newell normals of its two faces ([`dihedral_turning_angle`]): 0 where
//! the surface is flat across the edge, π/2 at a cube's edge, up to π where
//! the surface folds back onto itself. The topology is consistently oriented,
//! so the two normals point to the same side and the angle measures how much
//! the surface turns. [`feature_edges`] makes every interior edge whose angle
//! is at least a threshold an infinitely sharp crease ([`SHARPNESS_INFINITE`]):
//!
//! 1. For every face, its unit Newell normal ([`crate::unit_newell_normal`]).
//! 2. For every interior edge between two faces with non-zero normals, the
//!    angle θ = atan2(‖n₁ × n₂‖, n₁ · n₂) ∈ [0, π] (the two-argument form is
//!    accurate for small and for near-π angles, where `acos` of the dot
//!    product is not).
//! 3. The edge is a feature when θ ≥ the threshold.
//!
//! Boundary edges are left alone: the boundary option of the subdivision
//! makes them sharp anyway, and they are never stored as tags
//! ([`crate::Tags`]). A degenerate face — one whose Newell vector is exactly
//! zero (fewer than three distinct corners, or collinear ones) — has no
//! normal and never makes a feature; near-degenerate faces
//! ([`crate::Warning::ZeroAreaFaces`]) are measured like any other.
//!
//! No corner tags are produced: the subdivision rules (OpenSubdiv's
//! `Sdc::Crease`, which the tagged schemes follow) classify a vertex by the
//! number of sharp edges at it — one is a *dart* (smooth), two a *crease*,
//! three or more a *corner*, kept in place — so a vertex where three or more
//! features meet (the corner of a cube, a feature meeting the boundary) is a
//! corner by the rules themselves.
//!
//! ```
//! use subdiv_mesh::{features::feature_edges, shapes, Tags};
//! let cube = shapes::cube();
//! let features = feature_edges(&cube, 30.0);
//! assert_eq!(features.edges.len(), 12); // every edge turns by 90°
//! let tags = Tags::from_list(cube.topology(), &features.list).unwrap();
//! let tagged = cube.with_tags(tags);
//! assert_eq!(tagged.tags().crease_count(), 12);
//! assert_eq!(tagged.tags().corner_count(), 0); // corners by the rules
//! ```

use crate::ids::{EdgeId, FaceId};
use crate::mesh::Mesh;
use crate::tags::{EdgeTag, TagList, SHARPNESS_INFINITE};
use glam::DVec3;

/// The feature edges of a mesh at one threshold, with every edge's dihedral
/// turning angle ([`feature_edges`]). `#[non_exhaustive]`: read through its
/// public fields (a new field is not a breaking change).
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct FeatureEdges {
    /// The threshold in radians (the `angle_degrees` it was asked for,
    /// converted).
    pub threshold_radians: f64,
    /// The feature edges in edge order.
    pub edges: Vec<EdgeId>,
    /// The features as crease tags, infinitely sharp, each edge by its first
    /// half-edge's ends (as [`crate::Tags::to_list`] writes them), in edge
    /// order; no corner tags. Resolve with [`crate::Tags::from_list`].
    pub list: TagList,
    /// Per edge (indexed by [`EdgeId`]): its dihedral turning angle in
    /// radians, `None` for a boundary edge and an edge next to a degenerate
    /// face ([`dihedral_turning_angle`]).
    pub angles: Vec<Option<f64>>,
}

/// The angle θ ∈ [0, π] between two unit normals, atan2(‖n₁ × n₂‖, n₁ · n₂).
fn angle_between_normals(n1: DVec3, n2: DVec3) -> f64 {
    n1.cross(n2).length().atan2(n1.dot(n2))
}

/// The dihedral turning angle of edge `e` in radians: the angle between the
/// unit Newell normals of its two faces, 0 where the surface is flat across
/// the edge, π/2 at a cube's edge, π where it folds back. `None` for a
/// boundary edge and when either face is degenerate (zero Newell vector, no
/// normal). Time O(size of the two faces).
///
/// # Panics
/// If `e` is not an edge of `mesh` (a caller bug).
pub fn dihedral_turning_angle(mesh: &Mesh, e: EdgeId) -> Option<f64> {
    let (f1, f2) = mesh.topology().edge_faces(e);
    angle_of_faces(mesh.face_normal(f1), f2.map(|f| mesh.face_normal(f))?)
}

/// The turning angle between two faces' unit normals, `None` when either is zero.
fn angle_of_faces(n1: DVec3, n2: DVec3) -> Option<f64> {
    (n1 != DVec3::ZERO && n2 != DVec3::ZERO).then(|| angle_between_normals(n1, n2))
}

/// The interior edges of `mesh` whose dihedral turning angle
/// ([`dihedral_turning_angle`]) is at least `angle_degrees`, as infinitely
/// sharp creases (module docs: boundary edges and degenerate faces never
/// make features; vertices where three or more meet are corners by the
/// rules, with no tag).
///
/// The comparison is θ ≥ `angle_degrees`·π/180 in radians, so a threshold
/// ≤ 0 makes every measured edge a feature, flat ones included, one above
/// 180° or NaN makes none. A larger threshold gives a subset of the
/// features. Time linear in the number of corners.
pub fn feature_edges(mesh: &Mesh, angle_degrees: f64) -> FeatureEdges {
    let t = mesh.topology();
    let threshold_radians = angle_degrees.to_radians();
    // Step 1: one unit Newell normal per face.
    let normals: Vec<DVec3> = mesh.face_normals();
    let normal = |f: FaceId| normals[f.index()];
    // Step 2: the turning angle of every interior edge between non-degenerate faces.
    let angles: Vec<Option<f64>> = t
        .edges()
        .map(|e| match t.edge_faces(e) {
            (f1, Some(f2)) => angle_of_faces(normal(f1), normal(f2)),
            (_, None) => None,
        })
        .collect();
    // Step 3: θ ≥ threshold.
    let edges: Vec<EdgeId> =
        t.edges().filter(|e| angles[e.index()].is_some_and(|theta| theta >= threshold_radians)).collect();
    let creases = edges
        .iter()
        .map(|&e| {
            let (a, b) = t.edge_vertices(e);
            EdgeTag { a: a.0, b: b.0, sharpness: SHARPNESS_INFINITE }
        })
        .collect();
    FeatureEdges { threshold_radians, edges, list: TagList { creases, ..TagList::default() }, angles }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;
    use std::f64::consts::PI;

    #[test]
    fn cube_edges_turn_by_a_right_angle() {
        let cube = shapes::cube();
        for e in cube.topology().edges() {
            let theta = dihedral_turning_angle(&cube, e).expect("closed, non-degenerate");
            assert!((theta - PI / 2.0).abs() < 1e-15, "{theta}");
        }
        assert!(feature_edges(&cube, 90.0 - 1e-9).edges.len() == 12);
        assert!(feature_edges(&cube, 90.0 + 1e-9).edges.is_empty());
    }

    #[test]
    fn thresholds_outside_the_range() {
        let cube = shapes::cube();
        assert_eq!(feature_edges(&cube, 0.0).edges.len(), 12);
        assert_eq!(feature_edges(&cube, -5.0).edges.len(), 12);
        assert!(feature_edges(&cube, 181.0).edges.is_empty());
        assert!(feature_edges(&cube, f64::NAN).edges.is_empty());
    }

    #[test]
    fn boundary_edges_have_no_angle() {
        let grid = shapes::quad_grid(3, 2);
        let t = grid.topology();
        for e in t.edges() {
            assert_eq!(dihedral_turning_angle(&grid, e).is_none(), t.is_boundary_edge(e));
        }
        // Flat: every interior edge at 0, caught only by a threshold of 0.
        assert_eq!(feature_edges(&grid, 0.0).edges.len(), t.edges().filter(|&e| !t.is_boundary_edge(e)).count());
        assert!(feature_edges(&grid, 1e-6).edges.is_empty());
    }
}
