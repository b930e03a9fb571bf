//! Polygon meshes for subdiv.
//!
//! - [`PolygonSoup`]: positions and a compact CSR [`FaceList`] as read from a
//!   file, untrusted.
//! - [`Topology`]: validated connectivity — manifold, consistently oriented,
//!   faces of any size ≥ 3 — with the half-edge queries every subdivision rule
//!   and limit matrix needs in O(1) or O(valence).
//! - [`Mesh`]: a topology plus `f64` positions, with geometric queries, and
//!   optionally sharpness [`Tags`] (OpenSubdiv's creases and corners) and
//!   texture coordinates ([`FaceVarying`]).
//! - [`features`]: feature edges by dihedral angle, as infinitely sharp
//!   crease tags ([`feature_edges`]).
//! - [`triangulate`]: every polygon split into triangles over its own corners,
//!   the mesh kept manifold ([`Triangulation`] records each triangle's face).
//!
//! Validate once, then trust the type: a `Topology` that exists is manifold and
//! oriented. Defects that do not break connectivity (isolated vertices,
//! zero-area faces) are [`Warning`]s. Validation and [`diagnose`] take time
//! linear in the number of corners whatever the input (duplicate faces,
//! vertices in 10⁶ faces or 10⁵ fans, faces of 10⁶ corners).
//!
//! Geometry — the bounding-box diagonal *d*, Newell normals, areas, angles,
//! centroids, the zero-area check — is computed without overflow or
//! underflow for any finite coordinates (±1.7e308 to subnormals) by exact
//! power-of-two scalings ([`PowerOfTwoScale`], which other crates use to
//! normalise a mesh before refining or solving and map the result back).
//!
//! From plain arrays ([`Mesh::from_arrays`]: `&[[u32; N]]`, `&[Vec<usize>]`,
//! CSR offsets and indices, … — see [`FaceArrays`]) to topology queries and
//! back:
//!
//! ```
//! use subdiv_mesh::{Mesh, MeshError, VertexId};
//! // A unit cube: 8 corners, 6 quads, counter-clockwise seen from outside.
//! let positions: Vec<[f64; 3]> =
//!     (0..8).map(|i| [f64::from(i & 1), f64::from((i >> 1) & 1), f64::from(i >> 2)]).collect();
//! let quads = [[0u32, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
//! let mesh = Mesh::from_arrays(&positions, &quads)?;
//!
//! let t = mesh.topology();
//! assert_eq!((t.vertex_count(), t.edge_count(), t.face_count()), (8, 12, 6));
//! assert!(t.is_closed() && t.genus() == Some(0));
//! let neighbours: Vec<VertexId> = t.vertex_neighbors(VertexId(0)).collect();
//! assert_eq!(neighbours.len(), 3); // 1, 2 and 4, in cyclic order
//! assert!(neighbours.contains(&VertexId(4)));
//! assert_eq!(mesh.face_area(subdiv_mesh::FaceId(0)), 1.0);
//!
//! // Back to plain data.
//! assert_eq!(mesh.positions_to_arrays(), positions);
//! let (offsets, indices) = mesh.faces_as_csr();
//! assert_eq!((offsets.len(), indices.len()), (7, 24));
//!
//! // A flipped face is a typed error naming it, not a panic.
//! let mut flipped = quads;
//! flipped[5].reverse();
//! assert!(matches!(Mesh::from_arrays(&positions, &flipped), Err(MeshError::InconsistentOrientation { .. })));
//! # Ok::<(), MeshError>(())
//! ```
//!
//! ```
//! use subdiv_mesh::{shapes, Mesh};
//! let mesh = shapes::cube();
//! let t = mesh.topology();
//! assert_eq!((t.vertex_count(), t.edge_count(), t.face_count()), (8, 12, 6));
//! assert_eq!(t.euler_characteristic(), 2);
//! assert_eq!(t.genus(), Some(0));
//! assert!(t.vertices().all(|v| t.valence(v) == 3));
//! ```
#![warn(missing_docs)]

mod arrays;
mod error;
pub mod features;
mod geometry;
mod ids;
#[doc(hidden)]
pub mod internals;
mod mesh;
pub mod nonmanifold;
pub mod refine;
pub mod shapes;
mod soup;
mod tags;
mod topology;
mod triangulate;
mod validate;

pub use arrays::{FaceArrays, IndexSlice};
pub use error::{MeshError, Warning};
pub use features::{dihedral_turning_angle, feature_edges, FeatureEdges};
pub use geometry::{
    centroid, corner_angle, distance, newell_normal, unit_newell_normal, unit_vector, Aabb, PowerOfTwoScale,
};
pub use ids::{EdgeId, FaceId, HalfEdgeId, VertexId};
pub use mesh::{Mesh, Rejected, ZERO_AREA_REL};
pub use nonmanifold::{NonManifoldReport, Welds};
pub use soup::{FaceGroups, FaceList, PolygonSoup};
pub use tags::{EdgeTag, FaceVarying, FileOptions, TagList, Tags, VertexTag, SHARPNESS_INFINITE, SHARPNESS_SMOOTH};
pub use topology::{Corner, Topology};
pub use triangulate::{check_triangulation, triangulate, Triangulation};
pub use validate::{diagnose, Diagnosis};

/// Re-exported vector types: positions ([`DVec3`]) and texture coordinates ([`DVec2`]).
pub use glam::{DVec2, DVec3};
