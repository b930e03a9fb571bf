//! Non-manifold meshes through their manifold cover
//! ([`subdiv_mesh::nonmanifold`]): the welds of every refined level, so that
//! a refined cover is written as OpenSubdiv's refined non-manifold mesh.

use crate::error::StencilError;
use crate::scheme::Split;
use crate::Scheme;
use subdiv_mesh::{Topology, Welds};

/// Whether `scheme` can refine a non-manifold mesh (its cover): the quad and
/// triangle splits, whose new vertices each come from one element of the
/// input (Catmull-Clark, Loop, Deng-Ma), as in OpenSubdiv.
///
/// # Errors
/// [`StencilError::MeshNotSupported`] for Doo-Sabin and √3, whose new
/// vertices mix the faces around a vertex.
pub fn check_scheme(scheme: Scheme, welds: Option<&Welds>) -> Result<(), StencilError> {
    match (welds, scheme.traits().split) {
        (None, _) | (Some(_), Split::Quad | Split::Triangle) => Ok(()),
        (Some(_), Split::Dual | Split::Sqrt3) => Err(StencilError::MeshNotSupported {
            scheme: scheme.name(),
            reason: "the mesh is non-manifold; non-manifold meshes are refined by the quad and triangle splits \
                     only (Catmull-Clark, Loop, Deng-Ma), as in OpenSubdiv"
                .into(),
        }),
    }
}

/// The welds of the level one step of `scheme` makes from cover `coarse`.
///
/// # Errors
/// As [`check_scheme`].
pub fn child_welds(scheme: Scheme, coarse: &Topology, welds: Option<&Welds>) -> Result<Option<Welds>, StencilError> {
    check_scheme(scheme, welds)?;
    Ok(welds.map(|welds| match scheme.traits().split {
        Split::Triangle => welds.triangle_split(coarse),
        _ => welds.quad_split(coarse),
    }))
}
