//! The crate's error and warning types.

use thiserror::Error;

/// Why a polygon soup is not a valid mesh. Each variant names the offending element
/// (0-based indices, as stored).
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MeshError {
    /// The soup has no faces at all.
    #[error("the mesh has no faces")]
    NoFaces,
    /// A face has fewer than three corners.
    #[error("face {face} has {size} vertices; a face needs at least 3")]
    FaceTooSmall {
        /// Offending face.
        face: u32,
        /// Its number of corners.
        size: usize,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {vertex}, but there are only {vertex_count} vertices")]
    IndexOutOfRange {
        /// Offending face.
        face: u32,
        /// The out-of-range index.
        vertex: u32,
        /// Number of vertices in the soup.
        vertex_count: usize,
    },
    /// A non-manifold configuration OpenSubdiv defines but a manifold cover
    /// cannot express ([`crate::nonmanifold`]): a vertex inside an interior
    /// non-manifold crease with a fan of faces that does not lie between its
    /// two crease edges.
    #[error("vertex {vertex}: {reason} (a non-manifold configuration this library does not refine)")]
    NonManifoldUnsupported {
        /// The vertex.
        vertex: u32,
        /// What is wrong there.
        reason: String,
    },
    /// A face visits the same vertex twice.
    #[error("face {face} uses vertex {vertex} more than once")]
    RepeatedIndex {
        /// Offending face.
        face: u32,
        /// The repeated vertex.
        vertex: u32,
    },
    /// A coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate ({x}, {y}, {z})")]
    NonFiniteCoordinate {
        /// Offending vertex.
        vertex: u32,
        /// Its coordinates as read.
        x: f64,
        /// y.
        y: f64,
        /// z.
        z: f64,
    },
    /// An edge is shared by more than two faces.
    #[error("edge ({a}, {b}) is shared by {faces} faces (non-manifold edge)")]
    NonManifoldEdge {
        /// One end.
        a: u32,
        /// Other end.
        b: u32,
        /// Number of faces using the edge.
        faces: usize,
    },
    /// Two faces traverse an edge in the same direction.
    #[error(
        "faces {face_a} and {face_b} both traverse edge ({a}, {b}) in the same direction \
         (inconsistent orientation)"
    )]
    InconsistentOrientation {
        /// Edge start.
        a: u32,
        /// Edge end.
        b: u32,
        /// First face.
        face_a: u32,
        /// Second face.
        face_b: u32,
    },
    /// The faces around a vertex form more than one fan (bow-tie).
    #[error("vertex {vertex} joins {fans} separate fans of faces (non-manifold vertex)")]
    NonManifoldVertex {
        /// Offending vertex.
        vertex: u32,
        /// Number of fans found around it.
        fans: usize,
    },
    /// Every vertex the faces use is the same point: the mesh has no extent
    /// (bounding-box diagonal 0), so no tolerance relative to its size means
    /// anything.
    #[error(
        "all vertices coincide: the {vertices} vertices the faces use are all at ({x}, {y}, {z}), so the mesh \
         has no extent (bounding-box diagonal 0)"
    )]
    AllVerticesCoincide {
        /// Number of vertices the faces use.
        vertices: usize,
        /// The common point: x.
        x: f64,
        /// y.
        y: f64,
        /// z.
        z: f64,
    },
    /// A triangle-only operation (Loop, √3) met another polygon.
    #[error(
        "face {face} has {size} vertices; Loop subdivision needs triangles, as does √3 (use Catmull-Clark or \
         Doo-Sabin, or triangulate)"
    )]
    NotTriangles {
        /// Offending face.
        face: u32,
        /// Its number of corners.
        size: usize,
    },
    /// A trisecting √3 step met a triangle with more than one boundary edge
    /// (it follows a plain step, which leaves at most one per triangle).
    #[error(
        "face {face} has {boundary_edges} boundary edges; the trisecting √3 step takes at most one per triangle \
         (it follows a plain step, which leaves that)"
    )]
    TrisectionNeedsOneBoundaryEdge {
        /// Offending face.
        face: u32,
        /// Its number of boundary edges.
        boundary_edges: usize,
    },
    /// A face cannot be split into triangles over its own corners: each way of
    /// splitting it needs a diagonal that already is an edge of the mesh (or of
    /// the triangles of an earlier face), which would make that edge
    /// non-manifold ([`crate::triangulate`]; faces of more than 256 corners are
    /// searched greedily).
    #[error(
        "face {face} ({size} vertices) cannot be triangulated without adding a vertex: every split into \
         triangles needs a diagonal that already is an edge of the mesh or of an earlier face's triangles"
    )]
    NoTriangulation {
        /// Offending face.
        face: u32,
        /// Its number of corners.
        size: usize,
    },
    /// A hole tag names a face that does not exist.
    #[error("hole tag: face {face} does not exist (the mesh has {face_count} faces)")]
    TagFaceOutOfRange {
        /// The face index given (0-based).
        face: u32,
        /// Number of faces.
        face_count: usize,
    },
    /// A crease tag names two vertices that share no edge.
    #[error("crease tag {a}-{b}: vertices {a} and {b} share no edge")]
    TagNotAnEdge {
        /// One end.
        a: u32,
        /// Other end.
        b: u32,
    },
    /// A tag names a vertex that does not exist.
    #[error("a tag refers to vertex {vertex}, but there are only {vertex_count} vertices")]
    TagVertexOutOfRange {
        /// The out-of-range index.
        vertex: u32,
        /// Number of vertices.
        vertex_count: usize,
    },
    /// A sharpness is negative or NaN.
    #[error("{what} has sharpness {value}; sharpness must be ≥ 0 (0 smooth, ≥ 10 infinitely sharp)")]
    InvalidSharpness {
        /// The tagged element.
        what: String,
        /// The value.
        value: f32,
    },
    /// A per-element sharpness array has the wrong length.
    #[error("{found} sharpness values for {expected} {what}")]
    TagCount {
        /// "edges" or "vertices".
        what: &'static str,
        /// The element count.
        expected: usize,
        /// The array length.
        found: usize,
    },
    /// A face-varying channel does not have one index per face corner.
    #[error("the texture coordinates give {indices} face-corner indices for {corners} face corners")]
    FaceVaryingCount {
        /// Face corners of the mesh.
        corners: usize,
        /// Indices given.
        indices: usize,
    },
    /// A face corner refers to a face-varying value that does not exist.
    #[error("face corner {corner} refers to texture coordinate {index}, but there are only {values}")]
    FaceVaryingIndexOutOfRange {
        /// The corner (position in the face list).
        corner: usize,
        /// The out-of-range index.
        index: u32,
        /// Number of values.
        values: usize,
    },
    /// A face-varying value is NaN or infinite.
    #[error("texture coordinate {value} is not finite ({u}, {v})")]
    NonFiniteFaceVarying {
        /// The value index.
        value: u32,
        /// u.
        u: f64,
        /// v.
        v: f64,
    },
    /// A vertex index of plain-data faces ([`crate::FaceArrays`]) does not
    /// fit the `u32` vertex ids: out of range whatever the vertex count.
    #[error("face {face} refers to vertex {index}, beyond the 2³² − 2 vertices a mesh can have")]
    IndexTooLarge {
        /// Offending face.
        face: u32,
        /// The index as given.
        index: usize,
    },
    /// A flat index array of faces of one size ([`crate::FaceArrays::uniform`])
    /// is not a whole number of faces, or the size is 0.
    #[error("{indices} vertex indices do not make faces of {size} corners each")]
    UniformIndexCount {
        /// Corners per face.
        size: usize,
        /// Length of the index array.
        indices: usize,
    },
    /// CSR face offsets ([`crate::FaceArrays::csr`]) without a single entry:
    /// m faces need m + 1 offsets, a lone 0 for none.
    #[error("the face offsets are empty; m faces need m + 1 offsets, the first 0 and the last the index count")]
    OffsetsEmpty,
    /// The first CSR face offset is not 0.
    #[error("the face offsets start at {first}, not 0")]
    OffsetsStart {
        /// The first offset.
        first: usize,
    },
    /// A CSR face offset is smaller than the one before it.
    #[error("face {face} ends at offset {end}, before its start {start}; face offsets must not decrease")]
    OffsetsDecrease {
        /// The face whose offsets decrease (its position in the offsets, 0-based).
        face: usize,
        /// `offsets[face]`.
        start: usize,
        /// `offsets[face + 1]`.
        end: usize,
    },
    /// The last CSR face offset is not the number of vertex indices.
    #[error("the face offsets end at {last}, but there are {indices} vertex indices")]
    OffsetsEnd {
        /// The last offset.
        last: usize,
        /// Length of the index array.
        indices: usize,
    },
    /// The mesh needs more than `u32::MAX` elements.
    #[error("the mesh is too large: {what}")]
    TooLarge {
        /// What overflowed.
        what: &'static str,
    },
}

/// A defect that does not stop the mesh from being used, reported to the user.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Warning {
    /// Vertices no face refers to (kept in place; removable with
    /// [`crate::PolygonSoup::without_isolated_vertices`]).
    IsolatedVertices {
        /// The isolated vertices, ascending.
        vertices: Vec<u32>,
    },
    /// Faces whose area is zero to round-off (collinear or coincident corners).
    ZeroAreaFaces {
        /// The degenerate faces, ascending.
        faces: Vec<u32>,
    },
    /// Non-manifold edges and vertices, refined as OpenSubdiv does
    /// (infinitely sharp; [`crate::nonmanifold`]).
    NonManifold(Box<crate::NonManifoldReport>),
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        fn list(items: &[u32]) -> String {
            let shown: Vec<String> = items.iter().take(8).map(u32::to_string).collect();
            let more = if items.len() > 8 { format!(", … ({} in all)", items.len()) } else { String::new() };
            format!("{}{more}", shown.join(", "))
        }
        match self {
            Warning::IsolatedVertices { vertices } => {
                write!(f, "{} isolated vertices (no face uses them): {}", vertices.len(), list(vertices))
            }
            Warning::ZeroAreaFaces { faces } => {
                write!(f, "{} zero-area faces: {}", faces.len(), list(faces))
            }
            Warning::NonManifold(report) => {
                write!(
                    f,
                    "non-manifold: {} edges and {} vertices ({}), refined as OpenSubdiv does: \
                     those edges infinitely sharp, {} of the vertices infinitely sharp corners",
                    report.edges.len(),
                    report.vertices.len(),
                    list(&report.vertices),
                    report.corners.len()
                )
            }
        }
    }
}
