//! Test oracles, for this workspace's own tests and benches (hidden from the
//! documentation; always compiled, so that the tests' build of this crate is
//! the build every other command uses, with no feature to tell them apart).
//!
//! **Not covered by semver**: anything here may change or go in any
//! release.
//!
//! Each refinement of [`crate::refine`] builds the refined connectivity
//! directly, by index arithmetic on the parent; the functions here build the
//! same refinement the slow, obviously right way — the refined face list,
//! validated from scratch by [`Topology::new`] — so that tests can compare
//! the two field by field (`tests/integration/topology.rs`, `tests/integration/doo_sabin_creases.rs`)
//! and benches can time the direct construction against it.

use crate::error::MeshError;
use crate::ids::{EdgeId, FaceId, HalfEdgeId};
use crate::refine::{dual_split_tagged, general_split, DualFace, DualFeatures, DualProvenance, SharpDualProvenance};
use crate::soup::FaceList;
use crate::tags::Tags;
use crate::topology::Topology;

/// [`quad_split`](crate::refine::quad_split) the slow way: the quad face list validated by
/// [`Topology::new`]. The oracle the direct construction is tested against.
pub fn quad_split_by_validation(t: &Topology) -> Topology {
    let nv = t.vertex_count() as u32;
    let nf = t.face_count() as u32;
    let face_point = |f: FaceId| nv + f.0;
    let edge_point = |e: EdgeId| nv + nf + e.0;
    let mut quads = Vec::with_capacity(4 * t.half_edge_count());
    for f in t.face_ids() {
        for h in t.face_half_edges(f) {
            quads.extend_from_slice(&[
                t.he_from(h).0,
                edge_point(t.he_edge(h)),
                face_point(f),
                edge_point(t.he_edge(t.he_prev(h))),
            ]);
        }
    }
    let n_new = (nv + nf) as usize + t.edge_count();
    Topology::new(FaceList::from_uniform(4, quads), n_new).expect("the quad split of a valid mesh is valid")
}

/// [`triangle_split`](crate::refine::triangle_split) the slow way: the triangle list validated by
/// [`Topology::new`]. The oracle the direct construction is tested against.
pub fn triangle_split_by_validation(t: &Topology) -> Result<Topology, MeshError> {
    crate::refine::require_triangles(t)?;
    let nv = t.vertex_count() as u32;
    let edge_point = |h: HalfEdgeId| nv + t.he_edge(h).0;
    let mut tris = Vec::with_capacity(12 * t.face_count());
    for f in t.face_ids() {
        let h: Vec<HalfEdgeId> = t.face_half_edges(f).collect();
        for k in 0..3 {
            tris.extend_from_slice(&[t.he_from(h[k]).0, edge_point(h[k]), edge_point(h[(k + 2) % 3])]);
        }
        tris.extend_from_slice(&[edge_point(h[0]), edge_point(h[1]), edge_point(h[2])]);
    }
    let n_new = nv as usize + t.edge_count();
    Ok(Topology::new(FaceList::from_uniform(3, tris), n_new).expect("the triangle split of a valid mesh is valid"))
}

/// [`dual_split`](crate::refine::dual_split) the slow way: the face list validated by [`Topology::new`].
/// The oracle the direct construction is tested against.
pub fn dual_split_by_validation(t: &Topology) -> (Topology, DualProvenance) {
    let nh = t.half_edge_count();
    let (vertex_origin, boundary_point) = crate::refine::dual_vertices(t);
    let mut faces = FaceList::with_capacity(t.face_count() + t.edge_count() + t.vertex_count(), 4 * nh);
    let mut face_origin = Vec::with_capacity(faces.len());
    for f in t.face_ids() {
        faces.push(&t.face_half_edges(f).map(|h| h.0).collect::<Vec<_>>());
        face_origin.push(DualFace::F(f));
    }
    for e in t.edges() {
        let h = t.edge_half_edge(e);
        let quad = match t.he_twin(h) {
            Some(g) => [t.he_next(h).0, h.0, t.he_next(g).0, g.0],
            None => {
                let c = boundary_point[h.index()];
                [t.he_next(h).0, h.0, c, c + 1]
            }
        };
        faces.push(&quad);
        face_origin.push(DualFace::E(e));
    }
    let mut vertex_face = vec![None; t.vertex_count()];
    let mut corners = Vec::new();
    for v in t.vertices() {
        let fan = t.vertex_fan(v);
        if fan.is_empty() {
            continue;
        }
        corners.clear();
        if t.is_boundary_vertex(v) {
            corners.push(boundary_point[fan[0].index()]);
            corners.extend(fan.iter().map(|h| h.0));
            let incoming = t.he_prev(fan[fan.len() - 1]);
            corners.push(boundary_point[incoming.index()] + 1);
        } else if fan.len() == 2 {
            // Valence 2: the V-face would be a digon; its two E-faces already
            // share the edge between v's two images, so it is left out.
            continue;
        } else {
            corners.extend(fan.iter().map(|h| h.0));
        }
        vertex_face[v.index()] = Some(FaceId(faces.len() as u32));
        faces.push(&corners);
        face_origin.push(DualFace::V(v));
    }
    let topology = Topology::new(faces, vertex_origin.len()).expect("the Doo-Sabin split of a valid mesh is valid");
    (topology, DualProvenance { vertex_origin, face_origin, vertex_face, boundary_point })
}

/// [`dual_split_tagged`](crate::refine::dual_split_tagged) the slow way: the face list of the construction
/// validated by [`Topology::new`] (which also checks that it is a manifold).
/// The oracle the direct construction is tested against; its provenance and tags
/// are the direct split's.
///
/// # Errors
/// The validation error, if the construction were not a valid mesh (a bug).
pub fn dual_split_tagged_by_validation(
    t: &Topology,
    tags: &Tags,
) -> Result<(Topology, SharpDualProvenance, Tags), MeshError> {
    let features = DualFeatures::new(t, tags);
    // The direct construction of the general case (also without features)
    // gives the face list; `new` re-derives everything from it.
    let (split, _) = general_split(t, &features);
    let faces: FaceList = split.topology.faces().clone();
    let topology = Topology::new(faces, split.topology.vertex_count())?;
    let (_, provenance, new_tags) = dual_split_tagged(t, tags);
    Ok((topology, provenance, new_tags))
}

/// [`sqrt3_split`](crate::refine::sqrt3_split) the slow way: the triangle
/// list, one per old half-edge as [`crate::refine::Sqrt3Provenance`]
/// describes it, validated by [`Topology::new`]. The oracle the direct
/// construction is tested against.
///
/// # Errors
/// As [`crate::refine::sqrt3_split`].
pub fn sqrt3_split_by_validation(t: &Topology, trisect: bool) -> Result<Topology, MeshError> {
    let provenance = crate::refine::Sqrt3Provenance::new(t, trisect)?;
    let nv = t.vertex_count() as u32;
    let second = provenance.second_points();
    // The new point of x's face next to x: the second trisection point of
    // the boundary edge before x when trisecting, else the face's point.
    let c = |x: HalfEdgeId| -> u32 {
        let p = t.he_prev(x);
        if trisect && t.he_twin(p).is_none() {
            second[p.index()]
        } else {
            nv + t.he_face(x).0
        }
    };
    let mut tris = Vec::with_capacity(9 * t.face_count());
    for f in t.face_ids() {
        for x in t.face_half_edges(f) {
            let tri = match t.he_twin(x) {
                Some(y) => [t.he_from(x).0, c(y), c(x)],
                None if trisect => [nv + f.0, second[x.index()], t.he_from(t.he_prev(x)).0],
                None => [t.he_from(x).0, t.he_to(x).0, nv + f.0],
            };
            tris.extend_from_slice(&tri);
        }
    }
    Topology::new(FaceList::from_uniform(3, tris), provenance.vertex_count())
}
