//! The crate's error type.

use thiserror::Error;

/// Why an operator cannot be built for a mesh.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum StencilError {
    /// The scheme needs triangles (Loop, √3) and the mesh has another polygon.
    #[error(
        "face {face} has {size} vertices; Loop subdivision needs a triangle mesh, as does √3 (use Catmull-Clark or \
         Doo-Sabin)"
    )]
    NotTriangles {
        /// Offending face.
        face: u32,
        /// Its size.
        size: usize,
    },
    /// The scheme needs a closed mesh.
    #[error("{scheme} needs a closed mesh, but this one has {loops} boundary loop(s) (use Catmull-Clark, Loop or Doo-Sabin, which handle boundaries)")]
    NotClosed {
        /// Scheme name.
        scheme: &'static str,
        /// Number of boundary loops.
        loops: usize,
    },
    /// The scheme cannot refine this mesh (√3: an interior vertex of
    /// valence < 3, whose flips would double an edge).
    #[error("{scheme} cannot refine this mesh: {reason}")]
    MeshNotSupported {
        /// Scheme name.
        scheme: &'static str,
        /// Why, naming the element.
        reason: String,
    },
    /// A per-face parameter array has the wrong length or an out-of-range value.
    #[error("invalid shape parameter: {0}")]
    InvalidParameter(String),
    /// A scheme parameter given to a scheme it does not belong to (Loop's β to Catmull-Clark):
    /// the message names the option and the scheme it belongs to.
    #[error("{0}")]
    ParameterNotApplicable(String),
    /// The scheme cannot honour the mesh's tags.
    #[error("{scheme} cannot take these tags: {reason}")]
    TagsNotSupported {
        /// Scheme name.
        scheme: &'static str,
        /// Why.
        reason: String,
    },
    /// The mesh's texture coordinates cannot be refined with this scheme
    /// (Deng-Ma; Doo-Sabin on a channel with seams or with tags): drop them
    /// (`Mesh::with_uvs(None)`) to subdivide the positions.
    #[error("texture coordinates: {0}")]
    FaceVarying(String),
    /// A tag with semi-sharp sharpness (0 < s < 10) on a Doo-Sabin mesh:
    /// Doo-Sabin keeps infinitely sharp creases and corners only.
    #[error(
        "{what} has sharpness {sharpness}; Doo-Sabin creases and corners are infinitely sharp only \
         (0 or ≥ 10; use Catmull-Clark or Loop for semi-sharp features)"
    )]
    SemiSharpDooSabin {
        /// The tagged element, e.g. "edge 12 (vertices 3-7)" or "vertex 5".
        what: String,
        /// Its sharpness.
        sharpness: f32,
    },
    /// A tag with semi-sharp sharpness (0 < s < 10) on a Deng-Ma mesh:
    /// the interpolatory scheme keeps infinitely sharp creases and corners
    /// only (the 4-point rule along them has no semi-sharp blend).
    #[error(
        "deng-ma cannot take these tags: {what} has sharpness {sharpness}, but Deng-Ma creases and corners \
         are infinitely sharp only (0 or ≥ 10); use sharpness ≥ 10, or a Catmull-Clark/Loop method for \
         semi-sharp creases"
    )]
    SemiSharpDengMa {
        /// The tagged element, e.g. "edge 12 (vertices 3-7)" or "vertex 5".
        what: String,
        /// Its sharpness.
        sharpness: f32,
    },
    /// A scheme name that is none of [`crate::Scheme::ALL`]'s.
    #[error("unknown scheme `{name}` (expected one of: {})", crate::Scheme::ALL.map(|s| s.name()).join(", "))]
    UnknownScheme {
        /// The name given.
        name: String,
    },
    /// The refined mesh would exceed the `u32` index range.
    #[error("the refined mesh would have more than 2³² elements")]
    TooLarge,
    /// A refined or limit position is not a finite `f64`: the surface leaves
    /// the range of f64 (|coordinate| > 1.8e308), or the input already had a
    /// non-finite coordinate. The reason names the vertex and the magnitude.
    #[error("{scheme}: {reason}")]
    NotRepresentable {
        /// Scheme name.
        scheme: &'static str,
        /// What cannot be represented, e.g. "the refined surface leaves the
        /// range of f64: vertex 12 would have a coordinate of about -2.1e308".
        reason: String,
    },
}
