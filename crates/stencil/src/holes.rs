//! Holes: faces refined for their neighbours' sake but not part of the
//! surface, as OpenSubdiv has them (`Far::TopologyRefiner`'s face holes).
//!
//! A hole changes no point: its face point, edge points and vertex points
//! are computed as if it were there (OpenSubdiv refines hole faces and
//! skips them only when it draws or makes patches), so the surface around a
//! hole is the surface of the mesh without the tag, with the hole's patch
//! cut out. Holes come from two places:
//!
//! - hole tags (`t hole` in OBJ, `holes` in a tag file, USD's `holeIndices`);
//! - boundary interpolation `none` (Catmull-Clark and Loop): every face at a
//!   boundary vertex with a boundary edge that is not tagged infinitely
//!   sharp is a hole, the boundary edges are creases
//!   (`Far::TopologyRefinerFactoryBase::prepareComponentTagsAndSharpness`),
//!   so the surface stops one face short of the boundary, where the rules of
//!   the interior still hold.
//!
//! Every child face of a hole is a hole. The quad split (Catmull-Clark,
//! Deng-Ma) and the triangle split (Loop) number their child faces by
//! parent (`subdiv_mesh::refine`), so the flags follow by index; the dual
//! and √3 splits mix their parents' faces and take no holes.

use crate::error::StencilError;
use crate::options::{Options, Scheme};
use crate::scheme::Split;
use subdiv_mesh::{HalfEdgeId, Tags, Topology};
use subdiv_rules::crease::is_infinite;
use subdiv_rules::BoundaryInterpolation;

/// The hole flags of a base level (one per face, or empty when there is no
/// hole): the hole tags of `tags`, and under boundary interpolation `none`
/// (Catmull-Clark and Loop) the faces at the boundary vertices that have a
/// boundary edge not tagged infinitely sharp (module docs).
pub fn base_holes(t: &Topology, tags: &Tags, options: &Options) -> Vec<bool> {
    let mut holes = tags.holes().to_vec();
    let boundary_none = options.boundary == BoundaryInterpolation::None
        && matches!(options.scheme, Scheme::CatmullClark | Scheme::Loop(_));
    if !boundary_none {
        return holes;
    }
    let mut excluded = vec![false; t.vertex_count()];
    for e in t.edges().filter(|&e| t.is_boundary_edge(e) && !is_infinite(tags.edge_sharpness(e))) {
        let (a, b) = t.edge_vertices(e);
        excluded[a.index()] = true;
        excluded[b.index()] = true;
    }
    if !excluded.contains(&true) {
        return holes;
    }
    holes.resize(t.face_count(), false);
    for v in t.vertices().filter(|v| excluded[v.index()]) {
        for &h in t.vertex_fan(v) {
            holes[t.he_face(h).index()] = true;
        }
    }
    holes
}

/// The hole flags after one step of `scheme` on `coarse` (empty stays
/// empty): each child face takes its parent's flag.
///
/// # Errors
/// [`StencilError::TagsNotSupported`] for holes under a split that mixes its
/// parents' faces (Doo-Sabin's dual split, √3).
pub fn child_holes(scheme: Scheme, coarse: &Topology, holes: &[bool]) -> Result<Vec<bool>, StencilError> {
    if !holes.contains(&true) {
        return Ok(Vec::new());
    }
    match scheme.traits().split {
        // Quad h of the split for old half-edge h: its parent is h's face.
        Split::Quad => {
            Ok((0..coarse.half_edge_count()).map(|h| holes[coarse.he_face(HalfEdgeId(h as u32)).index()]).collect())
        }
        // Triangles 4f..4f+3 for triangle f.
        Split::Triangle => Ok(holes.iter().flat_map(|&hole| [hole; 4]).collect()),
        Split::Dual | Split::Sqrt3 => Err(StencilError::TagsNotSupported {
            scheme: scheme.name(),
            reason: "holes are kept by the quad and triangle splits only (Catmull-Clark, Loop, Deng-Ma), as in \
                     OpenSubdiv"
                .into(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::{shapes, FaceId, TagList};

    #[test]
    fn children_of_a_hole_are_holes() {
        let cube = shapes::cube();
        let t = cube.topology();
        let mut holes = vec![false; t.face_count()];
        holes[2] = true;
        let quads = child_holes(Scheme::CatmullClark, t, &holes).unwrap();
        assert_eq!(quads.len(), 24);
        // Face 2's four quads are the quads of its half-edges 8..12.
        assert_eq!(quads.iter().enumerate().filter(|&(_, &h)| h).map(|(k, _)| k).collect::<Vec<_>>(), [8, 9, 10, 11]);
        let ico = shapes::icosahedron();
        let mut holes = vec![false; ico.topology().face_count()];
        holes[5] = true;
        let tris = child_holes(Scheme::Loop(Default::default()), ico.topology(), &holes).unwrap();
        assert_eq!(tris.iter().enumerate().filter(|&(_, &h)| h).map(|(k, _)| k).collect::<Vec<_>>(), [20, 21, 22, 23]);
        assert!(child_holes(Scheme::DooSabin, t, &[true; 6]).is_err());
        assert!(child_holes(Scheme::DooSabin, t, &[]).unwrap().is_empty());
    }

    #[test]
    fn boundary_none_makes_the_boundary_faces_holes() {
        // An open 8×8 grid: the faces touching the boundary are its outer ring of 28 faces.
        let grid = shapes::quad_grid(8, 8);
        let t = grid.topology();
        let none = Options::new(Scheme::CatmullClark).with_boundary(BoundaryInterpolation::None);
        let holes = base_holes(t, grid.tags(), &none);
        assert_eq!(holes.iter().filter(|&&h| h).count(), 64 - 36);
        for f in t.face_ids() {
            let touches = t.face(f).iter().any(|&v| t.is_boundary_vertex(subdiv_mesh::VertexId(v)));
            assert_eq!(holes[f.index()], touches, "face {f:?}");
        }
        // Tagged infinitely sharp, the boundary edges keep their faces (OpenSubdiv's exception).
        let creases = t
            .edges()
            .filter(|&e| t.is_boundary_edge(e))
            .map(|e| {
                let (a, b) = t.edge_vertices(e);
                subdiv_mesh::EdgeTag { a: a.0, b: b.0, sharpness: 10.0 }
            })
            .collect();
        let tags = Tags::from_list(t, &TagList { creases, ..TagList::default() }).unwrap();
        assert!(base_holes(t, &tags, &none).is_empty());
        // Other boundary options and schemes: only the tags' holes.
        let tagged = Tags::none().with_holes((0..64).map(|f| f == 3).collect());
        let edge_only = none.with_boundary(BoundaryInterpolation::EdgeOnly);
        assert!(base_holes(t, &tagged, &edge_only)[3]);
        assert!(tagged.is_hole(FaceId(3)));
        assert_eq!(base_holes(t, &Tags::none(), &none.with_scheme(Scheme::DooSabin)), Vec::<bool>::new());
    }
}
