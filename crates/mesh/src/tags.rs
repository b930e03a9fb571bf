//! Sharp features and face-varying data on a mesh: OpenSubdiv's topology tags
//! (per-edge crease sharpness, per-vertex corner sharpness) and one
//! face-varying channel (texture coordinates, with seams).
//!
//! Sharpness follows OpenSubdiv (`Sdc::Crease`): 0 is smooth, a value ≥
//! [`SHARPNESS_INFINITE`] (10) is infinitely sharp and never decays, values in
//! between are semi-sharp and decay by one per level. Values are `f32`, as
//! OpenSubdiv stores them, so the decay (and Chaikin's averaging) rounds as
//! it does there.
//!
//! As read from a file, tags name vertices ([`TagList`], unvalidated); on a
//! validated mesh they are [`Tags`], indexed by [`EdgeId`] and [`VertexId`].
//! Boundary edges and boundary corners are not stored here: the boundary
//! option decides how they are treated (they are *implied* sharp, never
//! written back as tags).

use crate::error::MeshError;
use crate::ids::{EdgeId, FaceId, VertexId};
use crate::topology::Topology;
use glam::DVec2;
use subdiv_rules::{BoundaryInterpolation, CreaseMethod, FVarInterpolation, TriangleRule};

/// Sharpness of a smooth edge or vertex.
pub const SHARPNESS_SMOOTH: f32 = 0.0;
/// Sharpness from which an edge or vertex is infinitely sharp (OpenSubdiv's
/// `Sdc::Crease::SHARPNESS_INFINITE`).
pub const SHARPNESS_INFINITE: f32 = 10.0;

/// A crease tag as read: the edge between vertices `a` and `b` gets `sharpness`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeTag {
    /// One end (0-based vertex index).
    pub a: u32,
    /// The other end.
    pub b: u32,
    /// Crease sharpness (0 smooth, ≥ 10 infinitely sharp).
    pub sharpness: f32,
}

/// A corner tag as read: `vertex` gets corner sharpness `sharpness`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexTag {
    /// The vertex (0-based).
    pub vertex: u32,
    /// Corner sharpness (0 smooth, ≥ 10 infinitely sharp).
    pub sharpness: f32,
}

/// Subdivision options a mesh file sets for itself, as OpenSubdiv's shapes
/// do with `t` lines (`interpolateboundary`, `creasemethod`,
/// `facevaryinginterpolateboundary`, `smoothtriangles`): `None` where the
/// file says nothing. They travel with the mesh so that a command applies
/// them (an option given on the command line wins) and a writer keeps them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FileOptions {
    /// Boundary interpolation.
    pub boundary: Option<BoundaryInterpolation>,
    /// Semi-sharp crease decay.
    pub crease_method: Option<CreaseMethod>,
    /// Face-varying interpolation.
    pub fvar: Option<FVarInterpolation>,
    /// Catmull-Clark's triangle rule.
    pub triangle_rule: Option<TriangleRule>,
}

impl FileOptions {
    /// Whether the file sets no option.
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }
}

/// Tags by vertex and face indices, as a file or a tag file gives them
/// (unvalidated; [`crate::Mesh::from_soup`] checks them). A later tag of the
/// same edge or vertex replaces an earlier one.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TagList {
    /// Crease tags.
    pub creases: Vec<EdgeTag>,
    /// Corner tags.
    pub corners: Vec<VertexTag>,
    /// Faces tagged as holes (OpenSubdiv's `t hole`, 0-based): refined for
    /// their neighbours' sake, not part of the surface.
    pub holes: Vec<u32>,
    /// The subdivision options the file sets.
    pub options: FileOptions,
}

impl TagList {
    /// Whether there is no tag at all (no crease, corner, hole or option).
    pub fn is_empty(&self) -> bool {
        self.creases.is_empty() && self.corners.is_empty() && self.holes.is_empty() && self.options.is_empty()
    }
}

/// Validated tags of a topology: sharpness, one value per edge and per
/// vertex (stored only when some value is non-zero), the faces that are
/// holes, and the subdivision options the file set.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tags {
    /// Per edge, or empty when every edge is smooth.
    edges: Vec<f32>,
    /// Per vertex, or empty when every vertex is smooth.
    vertices: Vec<f32>,
    /// Per face, or empty when no face is a hole.
    holes: Vec<bool>,
    /// The file's subdivision options.
    options: FileOptions,
    /// Vertices that `edge-and-corner` does not sharpen although they are
    /// in one face, ascending: copies, in a manifold cover, of a vertex
    /// inside an interior non-manifold crease ([`crate::nonmanifold`]), which
    /// OpenSubdiv gives the crease rule.
    crease_copies: Vec<u32>,
}

fn check_sharpness(value: f32, what: impl FnOnce() -> String) -> Result<f32, MeshError> {
    if value.is_nan() || value < 0.0 {
        return Err(MeshError::InvalidSharpness { what: what(), value });
    }
    Ok(value)
}

impl Tags {
    /// No tags: every edge and vertex smooth.
    pub fn none() -> Self {
        Self::default()
    }

    /// Tags from per-edge and per-vertex sharpness arrays (either may be
    /// empty: all smooth). Values must be ≥ 0 and not NaN (+∞ is infinitely
    /// sharp, as any value ≥ 10).
    ///
    /// # Errors
    /// [`MeshError::TagCount`] when a non-empty array has the wrong length,
    /// [`MeshError::InvalidSharpness`] for a negative or NaN value.
    pub fn from_arrays(t: &Topology, edges: Vec<f32>, vertices: Vec<f32>) -> Result<Self, MeshError> {
        for (values, count, what) in [(&edges, t.edge_count(), "edges"), (&vertices, t.vertex_count(), "vertices")] {
            if !values.is_empty() && values.len() != count {
                return Err(MeshError::TagCount { what, expected: count, found: values.len() });
            }
        }
        for (e, &s) in edges.iter().enumerate() {
            check_sharpness(s, || format!("edge {e}"))?;
        }
        for (v, &s) in vertices.iter().enumerate() {
            check_sharpness(s, || format!("vertex {v}"))?;
        }
        Ok(Self::compact(edges, vertices))
    }

    /// Drops an array whose values are all smooth.
    fn compact(mut edges: Vec<f32>, mut vertices: Vec<f32>) -> Self {
        if edges.iter().all(|&s| s <= 0.0) {
            edges = Vec::new();
        }
        if vertices.iter().all(|&s| s <= 0.0) {
            vertices = Vec::new();
        }
        Self { edges, vertices, holes: Vec::new(), options: FileOptions::default(), crease_copies: Vec::new() }
    }

    /// The same tags with the faces where `holes` is true as holes (`holes`
    /// empty, or one flag per face of the topology the tags belong to).
    pub fn with_holes(mut self, mut holes: Vec<bool>) -> Self {
        if !holes.contains(&true) {
            holes = Vec::new();
        }
        self.holes = holes;
        self
    }

    /// The same tags with the file's subdivision options `options`.
    pub fn with_options(mut self, options: FileOptions) -> Self {
        self.options = options;
        self
    }

    /// Resolves tags by vertex indices on `t`: each crease pair must be an
    /// edge, each corner an existing vertex. A later tag of the same element
    /// replaces an earlier one. Time linear in the tags times the valences.
    ///
    /// # Errors
    /// [`MeshError::TagNotAnEdge`], [`MeshError::TagVertexOutOfRange`],
    /// [`MeshError::InvalidSharpness`].
    pub fn from_list(t: &Topology, list: &TagList) -> Result<Self, MeshError> {
        if list.is_empty() {
            return Ok(Self::none());
        }
        let nv = t.vertex_count();
        let in_range = |v: u32| -> Result<VertexId, MeshError> {
            if (v as usize) < nv {
                Ok(VertexId(v))
            } else {
                Err(MeshError::TagVertexOutOfRange { vertex: v, vertex_count: nv })
            }
        };
        let mut edges = if list.creases.is_empty() { Vec::new() } else { vec![SHARPNESS_SMOOTH; t.edge_count()] };
        for tag in &list.creases {
            let (a, b) = (in_range(tag.a)?, in_range(tag.b)?);
            let e = t.find_edge(a, b).ok_or(MeshError::TagNotAnEdge { a: tag.a, b: tag.b })?;
            edges[e.index()] = check_sharpness(tag.sharpness, || format!("crease {}-{}", tag.a, tag.b))?;
        }
        let mut vertices = if list.corners.is_empty() { Vec::new() } else { vec![SHARPNESS_SMOOTH; nv] };
        for tag in &list.corners {
            let v = in_range(tag.vertex)?;
            vertices[v.index()] = check_sharpness(tag.sharpness, || format!("corner {}", tag.vertex))?;
        }
        let mut holes = if list.holes.is_empty() { Vec::new() } else { vec![false; t.face_count()] };
        for &face in &list.holes {
            let flag = (holes.get_mut(face as usize))
                .ok_or(MeshError::TagFaceOutOfRange { face, face_count: t.face_count() })?;
            *flag = true;
        }
        Ok(Self::compact(edges, vertices).with_holes(holes).with_options(list.options))
    }

    /// Whether every edge and vertex is smooth: the subdivision rules are the
    /// untagged ones (holes and file options do not change them).
    pub fn is_empty(&self) -> bool {
        self.edges.is_empty() && self.vertices.is_empty()
    }

    /// Whether there is nothing a file would carry: no sharpness, no hole,
    /// no option.
    pub fn is_blank(&self) -> bool {
        self.is_empty() && self.holes.is_empty() && self.options.is_empty()
    }

    /// The same tags with `vertices` (ascending) exempt from the one-face
    /// corner of `edge-and-corner` ([`Self::crease_copies`]).
    pub fn with_crease_copies(mut self, vertices: Vec<u32>) -> Self {
        debug_assert!(vertices.windows(2).all(|w| w[0] < w[1]), "ascending");
        self.crease_copies = vertices;
        self
    }

    /// Vertices in one face that `edge-and-corner` does not make corners,
    /// ascending: copies of a vertex inside an interior non-manifold crease
    /// in a manifold cover ([`crate::nonmanifold`]). Empty for every other mesh.
    pub fn crease_copies(&self) -> &[u32] {
        &self.crease_copies
    }

    /// Whether face `f` is a hole.
    #[inline]
    pub fn is_hole(&self, f: FaceId) -> bool {
        self.holes.get(f.index()).copied().unwrap_or(false)
    }

    /// Per-face hole flags, or an empty slice when no face is a hole.
    pub fn holes(&self) -> &[bool] {
        &self.holes
    }

    /// Number of faces that are holes.
    pub fn hole_count(&self) -> usize {
        self.holes.iter().filter(|&&h| h).count()
    }

    /// The subdivision options the file set.
    pub fn options(&self) -> FileOptions {
        self.options
    }

    /// Sharpness of edge `e` (0 when untagged).
    #[inline]
    pub fn edge_sharpness(&self, e: EdgeId) -> f32 {
        self.edges.get(e.index()).copied().unwrap_or(SHARPNESS_SMOOTH)
    }

    /// Corner sharpness of vertex `v` (0 when untagged).
    #[inline]
    pub fn vertex_sharpness(&self, v: VertexId) -> f32 {
        self.vertices.get(v.index()).copied().unwrap_or(SHARPNESS_SMOOTH)
    }

    /// Per-edge sharpness, or an empty slice when every edge is smooth.
    pub fn edge_values(&self) -> &[f32] {
        &self.edges
    }

    /// Per-vertex sharpness, or an empty slice when every vertex is smooth.
    pub fn vertex_values(&self) -> &[f32] {
        &self.vertices
    }

    /// Number of edges with sharpness > 0.
    pub fn crease_count(&self) -> usize {
        self.edges.iter().filter(|&&s| s > 0.0).count()
    }

    /// Number of vertices with corner sharpness > 0.
    pub fn corner_count(&self) -> usize {
        self.vertices.iter().filter(|&&s| s > 0.0).count()
    }

    /// The tags as a list by vertex indices, in edge and vertex order (each
    /// edge as its first half-edge's ends), with only the non-zero values:
    /// what a writer puts in a file.
    pub fn to_list(&self, t: &Topology) -> TagList {
        let creases = (self.edges.iter().enumerate())
            .filter(|&(_, &s)| s > 0.0)
            .map(|(e, &sharpness)| {
                let (a, b) = t.edge_vertices(EdgeId(e as u32));
                EdgeTag { a: a.0, b: b.0, sharpness }
            })
            .collect();
        let corners = (self.vertices.iter().enumerate())
            .filter(|&(_, &s)| s > 0.0)
            .map(|(v, &sharpness)| VertexTag { vertex: v as u32, sharpness })
            .collect();
        let holes = (self.holes.iter().enumerate()).filter(|&(_, &h)| h).map(|(f, _)| f as u32).collect();
        TagList { creases, corners, holes, options: self.options }
    }
}

/// One face-varying channel (texture coordinates): a pool of values and, for
/// every face corner, the index of its value. Two faces meeting at a vertex
/// may use different values there: a seam.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FaceVarying {
    /// The values (u, v).
    pub values: Vec<DVec2>,
    /// One value index per face corner, in face-list order (parallel to
    /// [`crate::FaceList::indices`]).
    pub indices: Vec<u32>,
}

impl FaceVarying {
    /// Checks the channel against a face list of `corners` corners.
    ///
    /// # Errors
    /// [`MeshError::FaceVaryingCount`], [`MeshError::FaceVaryingIndexOutOfRange`],
    /// [`MeshError::NonFiniteFaceVarying`].
    pub fn validate(&self, corners: usize) -> Result<(), MeshError> {
        if self.indices.len() != corners {
            return Err(MeshError::FaceVaryingCount { corners, indices: self.indices.len() });
        }
        if let Some((corner, &index)) = self.indices.iter().enumerate().find(|&(_, &i)| i as usize >= self.values.len())
        {
            return Err(MeshError::FaceVaryingIndexOutOfRange { corner, index, values: self.values.len() });
        }
        if let Some((value, uv)) = self.values.iter().enumerate().find(|(_, uv)| !uv.is_finite()) {
            return Err(MeshError::NonFiniteFaceVarying { value: value as u32, u: uv.x, v: uv.y });
        }
        Ok(())
    }
}
