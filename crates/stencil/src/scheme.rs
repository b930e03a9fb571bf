//! A subdivision scheme as one interface: what `subdivide`, the plans and the
//! sizes ask of a scheme, answered by one implementation per scheme (in that
//! scheme's own file), and the scheme's traits ([`SchemeTraits`], the table
//! in [`Scheme::traits`]). Adding a scheme is one table entry, one
//! `impl SchemeRules` and one arm in [`Scheme::rules`] (checklist in
//! `docs/ARCHITECTURE.md`).

use crate::sharpness::LevelSharpness;
use crate::{Scheme, SparseMatrix, StencilError};
use glam::DVec3;
use subdiv_mesh::refine::DualProvenance;
use subdiv_mesh::Topology;

/// What a scheme is, besides its rules: OpenSubdiv's
/// `Sdc::SchemeTypeTraits`, one row of the table in [`Scheme::traits`].
/// Every field is read by the layer its doc names.
///
/// `#[non_exhaustive]`: read through its public fields (a new trait is not a
/// breaking change).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct SchemeTraits {
    /// The parameter domain of a face's limit patch (evaluation, sampling,
    /// projection: `subdiv-eval`).
    pub domain: Domain,
    /// The topological split of one step: which vertices the child level
    /// has and how they are numbered (the sizes, `size::refined_sizes`; the
    /// face-varying channel; the child points `subdiv-eval` reads).
    pub split: Split,
    /// The valence of a regular interior vertex (`subdiv-eval`'s regular
    /// patches).
    pub regular_valence: usize,
    /// The size of a regular face (`subdiv-eval`: the star of a vertex is
    /// regular when all its faces have it).
    pub regular_face_size: usize,
    /// Whether the scheme refuses every face that is not a triangle
    /// (`SchemeRules::check`, the face-varying refinement).
    pub triangles_only: bool,
    /// Whether the surface passes through the control vertices (then there
    /// are no limit masks: the vertices are their own limit points; the
    /// interpolation report's `control_scheme` is null).
    pub interpolating: bool,
    /// Which face-varying channels the scheme refines (`fvar::refine`).
    pub face_varying: FVarSupport,
    /// Whether `subdiv-eval`'s `LimitSurface` evaluates the limit surface
    /// exactly (patches at every parameter).
    pub evaluable: bool,
    /// Resident bytes per final-level corner that [`crate::subdivide()`]
    /// needs at its peak (measured, rounded up: [`crate::size`]).
    pub bytes_per_corner: u64,
}

/// The parameter domain of a limit patch (OpenSubdiv's `Sdc::Split` decides
/// it there; here Doo-Sabin's dual split has quad domains too: a quarter of
/// the face per corner).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Domain {
    /// (u, v) ∈ [0, 1]².
    Quad,
    /// u, v ≥ 0, u + v ≤ 1.
    Triangle,
}

/// The topological split of one step (OpenSubdiv's `Sdc::Split`, with the
/// dual split besides). Each has its own child numbering and element counts
/// ([`crate::size`]). Exhaustive on purpose: a new split (√3's) must break
/// every match over splits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Split {
    /// Every n-gon into n quads: the parent's vertices, then one point per
    /// face, then one per edge (`Topology::quad_split`).
    Quad,
    /// Every triangle into 4: the parent's vertices, then one point per edge
    /// (`Topology::triangle_split`).
    Triangle,
    /// The dual split: one point per face corner (two per boundary corner),
    /// F-, E- and V-faces (`Topology::dual_split`).
    Dual,
    /// √3 (Kobbelt 2000): a vertex in every triangle, the parent's interior edges flipped; every
    /// second step trisects the boundary edges.
    Sqrt3,
}

/// Which face-varying channels (texture coordinates) a scheme refines.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FVarSupport {
    /// Every channel, seams included, with OpenSubdiv's face-varying rules
    /// of the split (Catmull-Clark's on the quad split, Loop's on the
    /// triangle split), every `FVarInterpolation` and the tags.
    Full,
    /// Channels without seams on an untagged mesh only: a function of the
    /// vertices, refined by the positions' own step.
    SeamlessUntagged,
    /// No face-varying rules: a channel is refused.
    None,
}

/// One level refined: the new connectivity, the sharpness of the new level,
/// and (Doo-Sabin) the provenance of its faces and vertices.
///
/// `#[non_exhaustive]`: made by [`SchemeRules::split`], read through its
/// public fields (a new field is not a breaking change).
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct LevelSplit {
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
    fn split(&self, t: &Topology, sharp: &LevelSharpness) -> Result<LevelSplit, StencilError>;

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
