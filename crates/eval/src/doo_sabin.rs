//! Doo-Sabin (work in progress).

use crate::local::{Local, Refined};
use crate::patch::{Lattice, PatchKind, RegularSpec};
use crate::surface::EvalError;
use subdiv_mesh::{FaceId, Mesh};
use subdiv_stencil::Options;

/// The regular Doo-Sabin patch.
pub(crate) const SPEC: RegularSpec = RegularSpec {
    lattice: Lattice::Square,
    face_size: 4,
    valence: 4,
    crease_sector: 2,
    corner_sector: None,
    corners: &[(0, 0), (1, 0), (1, 1), (0, 1)],
    frames: &FRAMES,
    dirs: &[(1, 0), (0, 1), (-1, 0), (0, -1)],
    points: &[],
    kind: PatchKind::Biquadratic,
};

/// Corner frames.
pub(crate) const FRAMES: [((i32, i32), (i32, i32)); 4] =
    [((1, 0), (0, 1)), ((0, 1), (-1, 0)), ((-1, 0), (0, -1)), ((0, -1), (1, 0))];

pub(crate) fn check(_mesh: &Mesh, _options: &Options) -> Result<(), EvalError> {
    Err(EvalError::Unsupported { scheme: "doo-sabin", reason: "not implemented yet".into() })
}

pub(crate) fn child(u: f64, v: f64) -> (usize, [[f64; 2]; 2], [f64; 2]) {
    crate::catmull_clark::child(u, v)
}

pub(crate) fn corner_at(u: f64, v: f64) -> Option<usize> {
    crate::catmull_clark::corner_at(u, v)
}

pub(crate) fn nearest_corner(u: f64, v: f64) -> usize {
    crate::catmull_clark::nearest_corner(u, v)
}

pub(crate) fn child_face(_local: &Local, _refined: &Refined, face: FaceId, _k: usize) -> FaceId {
    face
}

pub(crate) fn domain_start(
    local: &Local,
    _options: &Options,
    face: FaceId,
    _corner: usize,
) -> Result<(Local, FaceId), EvalError> {
    Ok((local.clone(), face))
}

pub(crate) fn vertex_limit(
    _local: &Local,
    _options: &Options,
    _face: FaceId,
    _k: usize,
) -> Result<[Vec<f64>; 3], EvalError> {
    Err(EvalError::Unsupported { scheme: "doo-sabin", reason: "not implemented yet".into() })
}
