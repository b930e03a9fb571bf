//! A subdivision scheme as one interface: what `subdivide`, the plans and the
//! sizes ask of a scheme, answered by one implementation per scheme (in that
//! scheme's own file). Adding a scheme is one `impl SchemeRules` and one arm
//! in [`Scheme::rules`] (checklist in `docs/ARCHITECTURE.md`).

use crate::sharpness::LevelSharpness;
use crate::{Scheme, SparseMatrix, StencilError};
use glam::DVec3;
use subdiv_mesh::refine::DualProvenance;
use subdiv_mesh::Topology;

/// One level refined: the new connectivity, the sharpness of the new level,
/// and (Doo-Sabin) the provenance of its faces and vertices.
///
/// `#[non_exhaustive]`: made by [`SchemeRules::split`], read through its
/// public fields (a new field is not a breaking change).
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Split {
    /// The refined connectivity.
    pub topology: Topology,
    /// The tags of the refined level.
    pub sharpness: LevelSharpness,
    /// Doo-Sabin provenance (dual split only).
    pub dual: Option<DualProvenance>,
}

/// What every layer asks of a scheme. `sharp` is always the sharpness of the
/// level `t` (the coarse side of a step).
pub trait SchemeRules: Sync {
    /// Refuses a mesh or tags the scheme cannot take (Loop on non-triangles,
    /// semi-sharp tags on Doo-Sabin and Deng-Ma).
    fn check(&self, t: &Topology, sharp: &LevelSharpness) -> Result<(), StencilError>;

    /// The refined connectivity and its sharpness.
    fn split(&self, t: &Topology, sharp: &LevelSharpness) -> Result<Split, StencilError>;

    /// The refinement stencil R (new × old) on [`Self::split`]'s numbering,
    /// `None` for a scheme evaluated geometrically (Deng-Ma).
    fn stencil(&self, t: &Topology, sharp: &LevelSharpness) -> Result<Option<SparseMatrix>, StencilError>;

    /// The points of one step, R·x, evaluated without storing R.
    fn step_points(&self, t: &Topology, sharp: &LevelSharpness, x: &[DVec3]) -> Result<Vec<DVec3>, StencilError>;

    /// The limit points of the first `count` vertices of level `t` from the
    /// positions `x` of that level, exact where no semi-sharp value is left
    /// (callers refine first, [`Self::levels_before_limit`]); `None` for an
    /// interpolatory scheme.
    fn limit_points(
        &self,
        t: &Topology,
        sharp: &LevelSharpness,
        x: &[DVec3],
        count: usize,
    ) -> Option<Result<Vec<DVec3>, StencilError>>;

    /// The first `rows` rows of the limit stencil of level `t` (as
    /// [`Self::limit_points`]).
    fn limit_stencil(
        &self,
        t: &Topology,
        sharp: &LevelSharpness,
        rows: usize,
    ) -> Option<Result<SparseMatrix, StencilError>>;

    /// How many more levels the limit masks need on level `t` before they
    /// are exact: 0 on an untagged mesh (the masks are exact on the
    /// control mesh), ⌈largest semi-sharp value⌉ with tags (the value has
    /// decayed to 0 then), at least 1 on a tagged base level (OpenSubdiv's
    /// `Limit` after one level: darts and the first step's rules).
    fn levels_before_limit(&self, t: &Topology, sharp: &LevelSharpness, is_base: bool) -> usize {
        if sharp.is_plain() {
            return 0;
        }
        let semi = sharp.largest_semi_sharp(t).map_or(0, |s| s.ceil() as usize);
        semi.max(usize::from(is_base))
    }
}

impl Scheme {
    /// The scheme's rules.
    pub fn rules(&self) -> Box<dyn SchemeRules> {
        match *self {
            Scheme::CatmullClark => Box::new(crate::catmull_clark::CatmullClarkRules),
            Scheme::Loop(beta) => Box::new(crate::loop_subdivision::LoopRules(beta)),
            Scheme::DooSabin => Box::new(crate::doo_sabin::DooSabinRules),
            Scheme::DengMa(tension) => Box::new(crate::deng_ma::DengMaRules(tension)),
            Scheme::Sqrt3 => Box::new(crate::sqrt3::Sqrt3Rules),
        }
    }
}
