//! The evaluation API: [`LimitSurface`] (topology, tags, options and the
//! patch table built from them), [`LimitSurface::evaluate`] and
//! [`LimitSurface::stencil`] at a [`SurfaceParam`], and [`BoundSurface`]
//! (the patch table's control points for fixed positions, for many fast
//! evaluations with second derivatives).
//!
//! # Parameterisation
//! * **Catmull-Clark**: a quad is one domain `(face, 0)`, (u, v) ∈ \[0,1\]²,
//!   corner 0 at (0,0), corner 1 at (1,0), corner 3 at (0,1). An n-gon
//!   (n ≠ 4, triangles included) has n domains `(face, K)`, OpenSubdiv's
//!   ptex faces: the level-1 quad at corner K, (0,0) at corner K, (1,0) at the
//!   midpoint of edge K → K+1, (0,1) at the midpoint of edge K−1 → K, (1,1)
//!   at the face's centroid point (`Far::PtexIndices` numbers them in this
//!   order, one ptex face per corner, after the quads' single ones).
//! * **Loop**: a triangle is one domain `(face, 0)`, barycentric (u, v) with
//!   u, v ≥ 0, u + v ≤ 1, corner 0 at (0,0), 1 at (1,0), 2 at (0,1).
//! * **Doo-Sabin**: one domain per face corner `(face, K)`: the quarter of the face at
//!   corner K, (0,0) at the vertex's limit point, (1,0) toward the midpoint
//!   of edge K → K+1, (0,1) toward the midpoint of edge K−1 → K, (1,1) at the
//!   face's centroid (the biquadratic B-spline's own parameterisation on a
//!   regular lattice; the `doo_sabin` module docs give the refinement).
//!   Beyond every boundary edge and on each side of every crease edge
//!   K → K+1 (n the face's size), two *strip* domains reach the sharp curve:
//!   `(face, n + 2K)` at corner K (u outward, v along the edge; the curve at
//!   u = 1) and `(face, n + 2K + 1)` at corner K+1 (u along the edge, v
//!   outward; the curve at v = 1), the quarters of the degenerate quad that
//!   the boundary rule amounts to. At an interior vertex of valence 2 the
//!   quarter u, v < ½ of its domains is folded onto (½, min(u, v))
//!   ([`LimitSurface::unfold`]). Corners and darts are not evaluated.
//!
//! Boundaries follow the options' boundary interpolation as `subdivide
//! --limit` does; under `none`, the faces OpenSubdiv leaves out as holes
//! are evaluated like the others.
//!
//! Derivatives are with respect to the domain's (u, v). At an irregular
//! vertex itself (a parameter at the corner of a domain whose corner vertex
//! is extraordinary, a dart, or an irregular crease or corner) they are the
//! tangent masks' tangents at the coarsest level of the domain's
//! refinement where the limit masks are exact (the `patch_vertex` module docs: the
//! spectral projection of the star's points, equal to the parametric
//! derivatives wherever those exist); the second
//! derivatives there are reported as zero.

use crate::local::{ring_faces, Local, Root, Step, StepKey};
use crate::patch::{basis, regular_points, Basis, PatchKind, RegularSpec};
use crate::{catmull_clark, doo_sabin, loop_scheme, patch_vertex};
use glam::DVec3;
use rayon::prelude::*;
use subdiv_mesh::{FaceId, Mesh, PowerOfTwoScale, Tags, Topology, VertexId};
use subdiv_stencil::{Domain as ParamDomain, LevelSharpness, Options, Scheme, SchemeTraits, Split, StencilError};

/// A parameter on the limit surface: a domain (`face`, and for a ptex-split
/// n-gon the sub-quad `corner` K; 0 otherwise) and (u, v) in it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceParam {
    /// Face of the control mesh.
    pub face: u32,
    /// Sub-domain of the face: the corner K of a Catmull-Clark n-gon's ptex
    /// sub-quad or of a Doo-Sabin face (n + 2K, n + 2K + 1: the Doo-Sabin
    /// strips beyond its sharp edge K → K+1); 0 for a single domain.
    pub corner: u32,
    /// First parameter.
    pub u: f64,
    /// Second parameter.
    pub v: f64,
}

impl SurfaceParam {
    /// `(face, corner)` at (u, v).
    pub fn new(face: u32, corner: u32, u: f64, v: f64) -> Self {
        Self { face, corner, u, v }
    }

    /// The domain.
    pub fn domain(&self) -> Domain {
        Domain { face: self.face, corner: self.corner }
    }
}

/// One parametric domain of the surface: `(face, corner)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Domain {
    /// Face of the control mesh.
    pub face: u32,
    /// Sub-domain index within the face.
    pub corner: u32,
}

/// The limit surface and its first derivatives at one parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LimitSample {
    /// Limit position.
    pub position: DVec3,
    /// ∂S/∂u.
    pub du: DVec3,
    /// ∂S/∂v.
    pub dv: DVec3,
    /// Unit normal, oriented like the faces (du × dv normalised; zero where
    /// du × dv vanishes, on degenerate geometry).
    pub normal: DVec3,
}

/// A [`LimitSample`] with the second derivatives (for Newton steps).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LimitJet {
    /// Position, first derivatives and normal.
    pub sample: LimitSample,
    /// ∂²S/∂u².
    pub duu: DVec3,
    /// ∂²S/∂u∂v.
    pub duv: DVec3,
    /// ∂²S/∂v².
    pub dvv: DVec3,
}

/// A limit point and its derivatives as weights on the control points:
/// `position = Σ weights[i]·P[indices[i]]`, likewise `du`, `dv`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EvalStencil {
    /// Control vertices with a nonzero weight.
    pub indices: Vec<u32>,
    /// Weights of the position.
    pub position: Vec<f64>,
    /// Weights of ∂S/∂u.
    pub du: Vec<f64>,
    /// Weights of ∂S/∂v.
    pub dv: Vec<f64>,
}

impl EvalStencil {
    /// The stencil applied to `positions`: (position, du, dv).
    ///
    /// # Panics
    /// If an index is out of range for `positions` (a caller bug).
    pub fn apply(&self, positions: &[DVec3]) -> (DVec3, DVec3, DVec3) {
        let mut out = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
        for (k, &i) in self.indices.iter().enumerate() {
            let p = positions[i as usize];
            out.0 += self.position[k] * p;
            out.1 += self.du[k] * p;
            out.2 += self.dv[k] * p;
        }
        out
    }
}

/// Why a surface cannot be built or evaluated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum EvalError {
    /// A parameter names no domain of the mesh.
    #[error("no domain {face}.{corner} in this mesh")]
    NoSuchDomain {
        /// Face given.
        face: u32,
        /// Corner given.
        corner: u32,
    },
    /// A parameter outside its domain (or not finite).
    #[error("parameter ({u}, {v}) outside the domain of face {face}")]
    OutOfDomain {
        /// Face given.
        face: u32,
        /// u given.
        u: f64,
        /// v given.
        v: f64,
    },
    /// Not implemented yet (kept for compatibility; no longer returned).
    #[error("limit evaluation is not implemented yet")]
    Unimplemented,
    /// The scheme or its options cannot take this mesh (Loop on a
    /// non-triangle, a bad parameter), as the subdivision says.
    #[error(transparent)]
    Stencil(#[from] StencilError),
    /// The scheme has no limit surface to evaluate here (Deng-Ma, an
    /// interpolatory scheme without limit masks).
    #[error("{scheme}: {reason}")]
    Unsupported {
        /// Scheme name.
        scheme: &'static str,
        /// Why.
        reason: String,
    },
    /// The positions passed in do not have one point per control vertex.
    #[error("{found} positions given for a surface of {expected} control vertices")]
    PositionCount {
        /// Control vertices of the surface.
        expected: usize,
        /// Positions given.
        found: usize,
    },
    /// An internal invariant failed (a bug: please report it with the mesh).
    #[error("internal error in limit evaluation: {0}")]
    Internal(String),
    /// The surface has no domain (an empty mesh).
    #[error("the surface has no domain")]
    NoSurface,
    /// Bad input data for sampling, projection or fitting.
    #[error("{what}")]
    InvalidInput {
        /// What is wrong, naming the offending element.
        what: String,
    },
    /// Fitting could not solve its least-squares system.
    #[error("fitting: {what}")]
    Solve {
        /// The solver's message.
        what: String,
    },
}

/// Levels of the patch table below a domain: deeper parameters (within
/// 2⁻⁸ of an irregular vertex) are evaluated by refining on demand.
const TABLE_DEPTH: usize = 8;
/// Nodes of the patch table of one domain at most (a domain with one
/// irregular vertex needs 4 per level, 33 in all): the cells of a domain
/// beside a semi-sharp crease stay irregular for ⌈s⌉ levels along the crease,
/// and are refined on demand past this.
const TABLE_NODES: usize = 64;
/// Table building keeps the steps it meets from this depth on: shallower
/// levels hold the control mesh's own neighbourhoods, nearly one structure
/// per domain, which would fill the cache before the repeating rings of
/// irregular vertices that evaluation below the table meets.
const CACHED_FROM_DEPTH: usize = 2;
/// Domains whose patch trees are built (in parallel) before they are merged.
const TREE_BATCH: usize = 1024;
/// Levels of on-demand refinement: below 2⁻⁶⁰ of an irregular vertex the
/// parameter is taken as the vertex (the surface moves by ~λ⁶⁰·size there,
/// far below the rounding of any coordinate).
const MAX_DEPTH: usize = 60;
/// A first derivative this small against the other is zero to rounding (a
/// Doo-Sabin boundary curve): the normal comes from the second derivative.
const DEGENERATE_DERIVATIVE: f64 = 1e-10;
/// How far u + v may exceed 1 on a Loop triangle by rounding (then scaled back).
const BARYCENTRIC_SLACK: f64 = 1e-12;

/// The child of (u, v) after one step, with the affine map's P and q.
type Child = (usize, [[f64; 2]; 2], [f64; 2]);
/// A child of a cell after one step: the refined face and the cell in its ring.
type ChildCell = Result<(FaceId, u32), EvalError>;

/// What evaluation needs of an evaluable scheme
/// ([`subdiv_stencil::SchemeTraits::evaluable`]): its regular patch, the
/// children of a cell after one step, the corners of a domain and their
/// tangent frames. One row per scheme ([`patching`]), made of its module's
/// functions.
struct Patching {
    spec: &'static RegularSpec,
    /// The child of (u, v) after one step, and the affine map to its (u, v).
    child: fn(f64, f64) -> Child,
    /// The domain corner at (u, v), if it is one.
    corner_at: fn(f64, f64) -> Option<usize>,
    /// The domain corner nearest (u, v).
    nearest_corner: fn(f64, f64) -> usize,
    /// Per corner: the lattice directions toward the next and the previous corner.
    frames: &'static [crate::patch::Frame],
    /// Child `k` of the cell `face` after one step of the scheme: the
    /// refined face, and the cell within that face's ring (the face itself,
    /// 0, for Catmull-Clark and Loop; its corner for a Doo-Sabin cell).
    child_cell: fn(&Local, &crate::local::Refined, FaceId, usize) -> ChildCell,
    /// The control points of the regular patch of a cell (a face; a
    /// Doo-Sabin face corner), if it is one.
    regular: fn(&Topology, &LevelSharpness, FaceId) -> Option<Vec<crate::patch::Combo>>,
    /// The patch parameters (s, t) = P·(u, v) + q of a regular patch of the level.
    patch_frame: Affine,
}

/// The identity: a primal patch's parameters are its domain's.
const IDENTITY_FRAME: Affine = ([[1.0, 0.0], [0.0, 1.0]], [0.0, 0.0]);

const CATMULL_CLARK: Patching = Patching {
    spec: &catmull_clark::SPEC,
    child: catmull_clark::child,
    corner_at: catmull_clark::corner_at,
    nearest_corner: catmull_clark::nearest_corner,
    frames: &catmull_clark::FRAMES,
    // The quad split: child k of face f is the quad at its corner k.
    child_cell: |local, _, face, k| Ok((FaceId(local.t.faces().offsets()[face.index()] + k as u32), 0)),
    regular: |t, sharp, cell| regular_points(&catmull_clark::SPEC, t, sharp, cell),
    patch_frame: IDENTITY_FRAME,
};

const LOOP: Patching = Patching {
    spec: &loop_scheme::SPEC,
    child: loop_scheme::child,
    corner_at: loop_scheme::corner_at,
    nearest_corner: loop_scheme::nearest_corner,
    frames: &loop_scheme::FRAMES,
    // The triangle split: child k of face f is triangle 4f + k.
    child_cell: |_, _, face, k| Ok((FaceId(4 * face.0 + k as u32), 0)),
    regular: |t, sharp, cell| regular_points(&loop_scheme::SPEC, t, sharp, cell),
    patch_frame: IDENTITY_FRAME,
};

const DOO_SABIN: Patching = Patching {
    spec: &doo_sabin::SPEC,
    child: doo_sabin::child,
    corner_at: doo_sabin::corner_at,
    nearest_corner: doo_sabin::nearest_corner,
    frames: &doo_sabin::FRAMES,
    child_cell: doo_sabin::child_cell,
    regular: doo_sabin::regular,
    // A corner domain is the quarter (½, 1)² of its biquadratic patch.
    patch_frame: ([[0.5, 0.0], [0.0, 0.5]], [0.5, 0.5]),
};

/// The evaluation row of an evaluable scheme.
///
/// # Panics
/// For a scheme that is not evaluable: [`LimitSurface::new`] refuses those.
fn patching(scheme: Scheme) -> &'static Patching {
    match scheme {
        Scheme::CatmullClark => &CATMULL_CLARK,
        Scheme::Loop(_) => &LOOP,
        Scheme::DooSabin => &DOO_SABIN,
        Scheme::DengMa(_) | Scheme::Sqrt3 => unreachable!("not evaluable: refused by LimitSurface::new"),
    }
}

impl std::fmt::Debug for Patching {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Patching").field("kind", &self.spec.kind).finish_non_exhaustive()
    }
}

impl Patching {
    /// The domain corner nearest (u, v) and its parameters.
    fn nearest_corner(&self, domain: ParamDomain, u: f64, v: f64) -> (usize, f64, f64) {
        let k = (self.nearest_corner)(u, v);
        let corners: &[(f64, f64)] = match domain {
            ParamDomain::Triangle => &[(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)],
            ParamDomain::Quad => &[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)],
        };
        (k, corners[k].0, corners[k].1)
    }
}

/// A node of a domain's patch tree.
#[derive(Clone, Copy, Debug)]
enum Node {
    /// A regular patch (index into the patch arrays).
    Patch(u32),
    /// Four children in the scheme's child order (node indices).
    Split([u32; 4]),
    /// Not regular within the table's depth: evaluated by refining on
    /// demand from the level kept in the deep entry (index), or from the
    /// domain's root (`u32::MAX`: the placeholder while building).
    Deep(u32),
}

/// Where on-demand refinement resumes below the table: the local level of
/// a deep node, its cell, and the domain's root vertices.
#[derive(Clone, Debug)]
struct DeepEntry {
    local: Local,
    cell: FaceId,
    ids: std::sync::Arc<Vec<u32>>,
}

/// Affine map (u', v') = A·(u, v) + b.
type Affine = ([[f64; 2]; 2], [f64; 2]);

fn compose(a: &[[f64; 2]; 2], b: &[[f64; 2]; 2]) -> [[f64; 2]; 2] {
    let mut c = [[0.0; 2]; 2];
    for i in 0..2 {
        for j in 0..2 {
            c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j];
        }
    }
    c
}

fn apply_affine((a, b): &Affine, u: f64, v: f64) -> (f64, f64) {
    let cl = |x: f64| x.clamp(0.0, 1.0);
    (cl(a[0][0] * u + a[0][1] * v + b[0]), cl(a[1][0] * u + a[1][1] * v + b[1]))
}

/// One domain's patch tree, as built (merged into the surface's arrays).
#[derive(Default)]
struct Tree {
    nodes: Vec<Node>,
    deep: Vec<DeepEntry>,
    kinds: Vec<PatchKind>,
    /// The patch points' (control vertex, weight) lists, one after the
    /// other (16 slots per patch, empty past the kind's point count)…
    entries: Vec<(u32, f64)>,
    /// …and where each ends in `entries`.
    ends: Vec<u32>,
}

impl Tree {
    /// Appends one patch point: `pairs` sorted by vertex, repeated vertices
    /// merged (summed in order).
    fn push_point(&mut self, pairs: impl IntoIterator<Item = (u32, f64)>) {
        let start = self.entries.len();
        self.entries.extend(pairs);
        self.entries[start..].sort_by_key(|p| p.0);
        let mut kept = start;
        for read in start..self.entries.len() {
            let pair = self.entries[read];
            if kept > start && self.entries[kept - 1].0 == pair.0 {
                self.entries[kept - 1].1 += pair.1;
            } else {
                self.entries[kept] = pair;
                kept += 1;
            }
        }
        self.entries.truncate(kept);
        self.ends.push(self.entries.len() as u32);
    }

    /// The pairs of patch point `slot` of patch `patch`.
    fn point(&self, patch: usize, slot: usize) -> &[(u32, f64)] {
        let i = patch * 16 + slot;
        let start = if i == 0 { 0 } else { self.ends[i - 1] as usize };
        &self.entries[start..self.ends[i] as usize]
    }
}

/// Dense weights on a root (6 rows: position, du, dv, duu, duv, dvv).
struct DenseJet {
    rows: [Vec<f64>; 6],
}

/// The limit surface of a control mesh's topology, tags and options, ready
/// to evaluate (built once; positions are given per call).
#[derive(Clone, Debug)]
pub struct LimitSurface {
    vertex_count: usize,
    options: Options,
    /// The scheme's table row ([`Scheme::traits`]).
    traits: SchemeTraits,
    /// The scheme's evaluation row.
    patching: &'static Patching,
    /// The connectivity the domains are refined on: the mesh's, or for
    /// Doo-Sabin with creases the mesh cut along them (`vertex_map` then
    /// gives the control vertex of every copy).
    topology: Topology,
    tags: Tags,
    vertex_map: Option<std::sync::Arc<Vec<u32>>>,
    /// Per domain: a Doo-Sabin corner domain at an interior vertex of
    /// valence 2, whose quarter toward the vertex is folded.
    folded: Vec<bool>,
    domains: Vec<Domain>,
    /// First domain of every face (and the total at the end).
    face_domains: Vec<u32>,
    /// Root node of every domain.
    roots: Vec<u32>,
    nodes: Vec<NodeRepr>,
    /// The levels where on-demand refinement resumes.
    deep: Vec<DeepEntry>,
    /// Kind of every patch.
    patch_kinds: Vec<PatchKind>,
    /// First point of every patch (16 slots per patch).
    /// CSR of the patch points' weights: point p is
    /// `point_offsets[p]..point_offsets[p+1]` of `point_vertices`/`point_weights`.
    point_offsets: Vec<u32>,
    point_vertices: Vec<u32>,
    point_weights: Vec<f64>,
    /// The face ring of every face (CSR): the domain supports.
    ring_offsets: Vec<u32>,
    ring_vertices: Vec<u32>,
    /// The steps of on-demand refinement met so far, by structure
    /// ([`crate::local::Step`]), shared by the surface's clones.
    steps: std::sync::Arc<StepCache>,
}

/// Steps of on-demand refinement by structure, at most [`MAX_CACHED_STEPS`]
/// (past that, steps are computed and not kept). Whether a step was cached
/// does not change a bit of the result: a cached step is the one computed.
#[derive(Default)]
struct StepCache(std::sync::RwLock<std::collections::HashMap<StepKey, std::sync::Arc<Step>>>);

/// How many steps a surface keeps: a few kilobytes each; near an irregular
/// vertex one per valence, tag pattern and child.
const MAX_CACHED_STEPS: usize = 4096;

impl std::fmt::Debug for StepCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let len = self.0.read().map_or(0, |map| map.len());
        f.debug_struct("StepCache").field("steps", &len).finish()
    }
}

/// [`Node`] as stored (public derive-friendly copy).
#[derive(Clone, Copy, Debug)]
struct NodeRepr(Node);

impl LimitSurface {
    /// Builds the surface of `mesh`'s topology and tags under `options`.
    ///
    /// # Errors
    /// [`EvalError::Stencil`] when the scheme refuses the mesh (Loop on a
    /// non-triangle, semi-sharp tags on Doo-Sabin), [`EvalError::Unsupported`]
    /// for Deng-Ma (interpolatory, no limit masks), for √3 (no evaluation
    /// here) and for Doo-Sabin meshes
    /// with a corner (a corner tag, or three or more boundary and crease
    /// edges at a vertex) or a dart (a vertex with one crease edge).
    pub fn new(mesh: &Mesh, options: &Options) -> Result<Self, EvalError> {
        options.validate()?;
        let traits = options.scheme.traits();
        if !traits.evaluable {
            let reason = if traits.interpolating {
                "an interpolatory scheme without limit masks; evaluate a refined mesh instead"
            } else {
                "no patches for its split here; subdivide, or take its limit points"
            };
            return Err(EvalError::Unsupported { scheme: options.scheme.name(), reason: reason.into() });
        }
        let t = mesh.topology();
        let tags = mesh.tags().clone();
        let sharp = options.sharpness(&tags);
        options.scheme.rules().check(t, &sharp)?;
        let (mut topology, mut local_tags, mut vertex_map) = (t.clone(), tags.clone(), None);
        if traits.split == Split::Dual {
            doo_sabin::check(mesh, options)?;
            if let Some((cut, original)) = doo_sabin::cut_along_creases(mesh)? {
                (topology, local_tags, vertex_map) = (cut, Tags::none(), Some(std::sync::Arc::new(original)));
            }
        }
        // Holes (tags, boundary `none`) are no part of the surface: no domains.
        let holes = subdiv_stencil::holes::base_holes(t, &tags, options);
        let mut domains = Vec::new();
        let mut face_domains = Vec::with_capacity(t.face_count() + 1);
        for f in t.face_ids() {
            face_domains.push(domains.len() as u32);
            if holes.get(f.index()) == Some(&true) {
                continue;
            }
            let n = match traits.split {
                // An n-gon of the quad split: one ptex quad per corner.
                Split::Quad if t.face_size(f) != 4 => t.face_size(f),
                Split::Quad | Split::Triangle | Split::Sqrt3 => 1,
                Split::Dual => {
                    let corners = doo_sabin::face_domains(t, &sharp, f);
                    domains.extend(corners.into_iter().map(|corner| Domain { face: f.0, corner }));
                    continue;
                }
            };
            domains.extend((0..n as u32).map(|corner| Domain { face: f.0, corner }));
        }
        face_domains.push(domains.len() as u32);
        let mut surface = Self {
            vertex_count: mesh.positions().len(),
            options: *options,
            traits,
            patching: patching(options.scheme),
            topology,
            tags: local_tags,
            vertex_map,
            folded: Vec::new(),
            domains,
            face_domains,
            roots: Vec::new(),
            nodes: Vec::new(),
            deep: Vec::new(),
            patch_kinds: Vec::new(),
            point_offsets: vec![0],
            point_vertices: Vec::new(),
            point_weights: Vec::new(),
            ring_offsets: vec![0],
            ring_vertices: Vec::new(),
            steps: std::sync::Arc::default(),
        };
        if traits.split == Split::Dual {
            let t = &surface.topology;
            surface.folded = (surface.domains.iter())
                .map(|d| {
                    let f = FaceId(d.face);
                    let n = t.face_size(f) as u32;
                    d.corner < n && {
                        let v = VertexId(t.face(f)[d.corner as usize]);
                        !t.is_boundary_vertex(v) && t.vertex_face_count(v) == 2
                    }
                })
                .collect();
        }
        // Face rings (the supports).
        for f in t.face_ids() {
            let mut ring: Vec<u32> = ring_faces(t, f).iter().flat_map(|&g| t.face(g).iter().copied()).collect();
            ring.sort_unstable();
            ring.dedup();
            surface.ring_vertices.extend(ring);
            surface.ring_offsets.push(surface.ring_vertices.len() as u32);
        }
        // Patch trees, a domain per task, merged a batch at a time: a tree's patch points are
        // small vectors each (a triangle mesh under Catmull-Clark has ~43 patches per domain, 11
        // weights per point), so holding every tree before merging took three times the table.
        let domains = surface.domains.clone();
        for batch in domains.chunks(TREE_BATCH) {
            let trees: Vec<Result<Tree, EvalError>> =
                batch.par_iter().map(|&d| surface.build_tree(d, &sharp)).collect();
            surface.merge_trees(trees)?;
        }
        surface.point_vertices.shrink_to_fit();
        surface.point_weights.shrink_to_fit();
        Ok(surface)
    }

    /// Appends built patch trees (in domain order) to the surface's arrays.
    fn merge_trees(&mut self, trees: Vec<Result<Tree, EvalError>>) -> Result<(), EvalError> {
        let surface = self;
        for tree in trees {
            let mut tree = tree?;
            let (node_base, patch_base) = (surface.nodes.len() as u32, surface.patch_kinds.len() as u32);
            let deep_base = surface.deep.len() as u32;
            surface.roots.push(node_base);
            surface.nodes.extend(tree.nodes.iter().map(|n| {
                NodeRepr(match *n {
                    Node::Patch(p) => Node::Patch(p + patch_base),
                    Node::Split(c) => Node::Split(c.map(|c| c + node_base)),
                    Node::Deep(i) => Node::Deep(if i == u32::MAX { i } else { i + deep_base }),
                })
            }));
            surface.deep.extend(std::mem::take(&mut tree.deep));
            surface.patch_kinds.extend(&tree.kinds);
            for (k, kind) in tree.kinds.iter().enumerate() {
                for slot in 0..16 {
                    if slot < kind.len() {
                        for &(v, w) in tree.point(k, slot) {
                            surface.point_vertices.push(v);
                            surface.point_weights.push(w);
                        }
                    }
                    surface.point_offsets.push(surface.point_vertices.len() as u32);
                }
            }
            // The offsets are u32 (half the table's index memory).
            if u32::try_from(surface.point_vertices.len()).is_err() {
                return Err(EvalError::Unsupported {
                    scheme: surface.options.scheme.name(),
                    reason: "the mesh's patch table would exceed 2³² weights (a very large mesh with \
                             irregular faces everywhere)"
                        .into(),
                });
            }
        }
        Ok(())
    }

    /// Where a parameter in a folded quarter continues on the surface: a
    /// Doo-Sabin domain at an interior vertex of valence 2 has no surface
    /// toward the vertex, and its quarter (u, v) < (½, ½) is folded onto the
    /// edge (½, s) ≡ (s, ½) between the two E-faces' quarters (`doo_sabin`
    /// module docs). A point a little past that edge on one side is the point
    /// as far past it on the other, so the quarter is turned a quarter turn
    /// about (½, ½): (u, v) ↦ (v, 1 − u) for v ≤ u, (1 − v, u) otherwise.
    /// Projection moves its iterates there (so Newton steps cross the fold
    /// instead of stalling on it); every other parameter is returned as it is.
    pub fn unfold(&self, param: SurfaceParam) -> SurfaceParam {
        let (u, v) = (param.u, param.v);
        match self.domain_index(param.domain()).ok().and_then(|d| self.fold(d, u, v)) {
            Some(_) if v <= u => SurfaceParam { u: v, v: 1.0 - u, ..param },
            Some(_) => SurfaceParam { u: 1.0 - v, v: u, ..param },
            None => param,
        }
    }

    /// The control vertex count the positions passed in must have.
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    /// The options the surface was built with.
    pub fn options(&self) -> &Options {
        &self.options
    }

    /// Every parametric domain, in face order.
    pub fn domains(&self) -> &[Domain] {
        &self.domains
    }

    /// The domains of `face` (empty for a face the mesh does not have).
    pub fn face_domains(&self, face: u32) -> &[Domain] {
        let f = face as usize;
        if f + 1 >= self.face_domains.len() {
            return &[];
        }
        &self.domains[self.face_domains[f] as usize..self.face_domains[f + 1] as usize]
    }

    /// Number of regular patches in the table (a measure of its size).
    pub fn patch_count(&self) -> usize {
        self.patch_kinds.len()
    }

    /// The control vertices whose convex hull contains the limit patch of
    /// `domain` (for conservative bounds; `None` when the rules have
    /// negative weights and the hull property does not hold).
    ///
    /// Every rule here has non-negative weights (the schemes' masks and
    /// their semi-sharp blends), so the surface over a domain lies in the
    /// hull of its face's ring: the vertices of every face sharing a vertex
    /// with the face. `None` only for a domain the mesh does not have.
    pub fn domain_support(&self, domain: Domain) -> Option<&[u32]> {
        self.domain_index(domain).ok()?;
        let f = domain.face as usize;
        Some(&self.ring_vertices[self.ring_offsets[f] as usize..self.ring_offsets[f + 1] as usize])
    }

    /// Position, derivatives and normal at `param`.
    ///
    /// # Errors
    /// [`EvalError::NoSuchDomain`], [`EvalError::OutOfDomain`] (NaN, outside
    /// \[0,1\]², u + v > 1 on a Loop triangle), [`EvalError::PositionCount`].
    pub fn evaluate(&self, positions: &[DVec3], param: SurfaceParam) -> Result<LimitSample, EvalError> {
        self.check_positions(positions)?;
        Ok(self.evaluate_jet_with(positions, param, None)?.sample)
    }

    /// [`Self::evaluate`] at every parameter of `params`, in order, computed
    /// on `positions` scaled by the exact power of two that brings their
    /// largest coordinate into [½, 1) ([`PowerOfTwoScale::normalizing`]) and
    /// mapped back (positions and derivatives; the normal does not change
    /// with the scale): a surface at 1e-300 or 1e300 evaluates as it does
    /// at scale one. A value beyond the range of `f64` once mapped back
    /// (derivatives of a surface near ±1.8e308) comes back infinite, for the
    /// caller to refuse.
    ///
    /// # Errors
    /// The index in `params` of the first parameter that fails, with its
    /// error ([`EvalError::PositionCount`] at index 0 for the positions).
    pub fn evaluate_all(
        &self,
        positions: &[DVec3],
        params: &[SurfaceParam],
    ) -> Result<Vec<LimitSample>, (usize, EvalError)> {
        let scale = PowerOfTwoScale::normalizing(positions.iter().copied());
        let scaled = scale.scaled_points(positions);
        let bound = self.bind(&scaled).map_err(|e| (0, e))?;
        let back = scale.inverse();
        params
            .par_iter()
            .enumerate()
            .with_min_len(64)
            .map(|(i, &p)| {
                let s = bound.evaluate(p).map_err(|e| (i, e))?;
                let map = |x: DVec3| back.apply_point(x);
                Ok(LimitSample { position: map(s.position), du: map(s.du), dv: map(s.dv), normal: s.normal })
            })
            .collect::<Vec<_>>()
            .into_iter()
            .collect()
    }

    /// [`Self::evaluate`] with the second derivatives.
    ///
    /// # Errors
    /// As [`Self::evaluate`].
    pub fn evaluate_jet(&self, positions: &[DVec3], param: SurfaceParam) -> Result<LimitJet, EvalError> {
        self.check_positions(positions)?;
        self.evaluate_jet_with(positions, param, None)
    }

    /// The same as weights on the control points.
    ///
    /// # Errors
    /// As [`Self::evaluate`] (but no positions).
    pub fn stencil(&self, param: SurfaceParam) -> Result<EvalStencil, EvalError> {
        let (d, u, v) = self.check_param(param)?;
        let folded = self.fold(d, u, v);
        let (u, v) = folded.map_or((u, v), |(fu, fv, _)| (fu, fv));
        let mut out = self.stencil_at(d, u, v)?;
        if let Some((_, _, along_u)) = folded {
            // As in evaluate: only ∂/∂v of the folded point survives, in one direction.
            let g_v = std::mem::take(&mut out.dv);
            out.du = if along_u { g_v.clone() } else { vec![0.0; g_v.len()] };
            out.dv = if along_u { vec![0.0; g_v.len()] } else { g_v };
        }
        Ok(out)
    }

    fn stencil_at(&self, d: usize, u: f64, v: f64) -> Result<EvalStencil, EvalError> {
        let mut acc: Vec<(u32, [f64; 3])> = Vec::new();
        match self.locate(d, u, v) {
            Located::Patch { patch, s, t, j } => {
                let b = basis(self.patch_kinds[patch as usize], s, t);
                let (bu, bv) = first_derivatives(&b, &j);
                for slot in 0..self.patch_kinds[patch as usize].len() {
                    let (vs, ws) = self.point(patch, slot);
                    for (&i, &w) in vs.iter().zip(ws) {
                        acc.push((i, [w * b.w[slot], w * bu[slot], w * bv[slot]]));
                    }
                }
            }
            Located::Deep { entry, u: du, v: dv, a } => {
                let (ids, jet) = self.resume(d, u, v, entry, du, dv, a)?;
                for (k, &i) in ids.iter().enumerate() {
                    let w = [jet.rows[0][k], jet.rows[1][k], jet.rows[2][k]];
                    if w != [0.0; 3] {
                        acc.push((i, w));
                    }
                }
            }
        }
        acc.sort_by_key(|a| a.0);
        let mut out = EvalStencil::default();
        for (i, w) in acc {
            if out.indices.last() == Some(&i) {
                let k = out.indices.len() - 1;
                out.position[k] += w[0];
                out.du[k] += w[1];
                out.dv[k] += w[2];
            } else {
                out.indices.push(i);
                out.position.push(w[0]);
                out.du.push(w[1]);
                out.dv.push(w[2]);
            }
        }
        Ok(out)
    }

    /// The patch table's control points for `positions`, for fast repeated
    /// evaluation (one sparse product over the table).
    ///
    /// # Errors
    /// [`EvalError::PositionCount`].
    pub fn bind<'a>(&'a self, positions: &'a [DVec3]) -> Result<BoundSurface<'a>, EvalError> {
        self.check_positions(positions)?;
        let n = self.point_offsets.len() - 1;
        let mut points = vec![DVec3::ZERO; n];
        points.par_chunks_mut(1024).enumerate().for_each(|(c, chunk)| {
            for (j, p) in chunk.iter_mut().enumerate() {
                let k = c * 1024 + j;
                let (s, e) = (self.point_offsets[k] as usize, self.point_offsets[k + 1] as usize);
                *p = (s..e).fold(DVec3::ZERO, |acc, q| {
                    acc + self.point_weights[q] * positions[self.point_vertices[q] as usize]
                });
            }
        });
        Ok(BoundSurface { surface: self, positions, points })
    }

    fn check_positions(&self, positions: &[DVec3]) -> Result<(), EvalError> {
        if positions.len() != self.vertex_count {
            return Err(EvalError::PositionCount { expected: self.vertex_count, found: positions.len() });
        }
        Ok(())
    }

    fn domain_index(&self, d: Domain) -> Result<usize, EvalError> {
        let f = d.face as usize;
        let err = EvalError::NoSuchDomain { face: d.face, corner: d.corner };
        if f + 1 >= self.face_domains.len() {
            return Err(err);
        }
        let (s, e) = (self.face_domains[f] as usize, self.face_domains[f + 1] as usize);
        let k = d.corner as usize;
        if s + k < e && self.domains[s + k].corner == d.corner {
            return Ok(s + k);
        }
        // Doo-Sabin's phantom quarters are numbered after the corners, sparsely.
        match self.domains[s..e].iter().position(|x| x.corner == d.corner) {
            Some(k) => Ok(s + k),
            None => Err(err),
        }
    }

    /// The domain index and the (checked, clamped) parameters.
    fn check_param(&self, p: SurfaceParam) -> Result<(usize, f64, f64), EvalError> {
        let d = self.domain_index(p.domain())?;
        let bad = EvalError::OutOfDomain { face: p.face, u: p.u, v: p.v };
        let (mut u, mut v) = (p.u, p.v);
        if !((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v)) {
            return Err(bad);
        }
        if self.traits.domain == ParamDomain::Triangle && u + v > 1.0 {
            if u + v > 1.0 + BARYCENTRIC_SLACK {
                return Err(bad);
            }
            let s = u + v;
            (u, v) = (u / s, v / s);
        }
        Ok((d, u, v))
    }

    fn point(&self, patch: u32, slot: usize) -> (&[u32], &[f64]) {
        let k = patch as usize * 16 + slot;
        let (s, e) = (self.point_offsets[k] as usize, self.point_offsets[k + 1] as usize);
        (&self.point_vertices[s..e], &self.point_weights[s..e])
    }

    /// The table's patch holding (u, v) of domain `d`, with the patch
    /// parameters and the Jacobian ∂(s,t)/∂(u,v).
    fn locate(&self, d: usize, mut u: f64, mut v: f64) -> Located {
        let mut node = self.roots[d];
        let mut a = [[1.0, 0.0], [0.0, 1.0]];
        loop {
            match self.nodes[node as usize].0 {
                Node::Patch(patch) => {
                    let (p, q) = self.patching.patch_frame;
                    let s = p[0][0] * u + p[0][1] * v + q[0];
                    let t = p[1][0] * u + p[1][1] * v + q[1];
                    return Located::Patch { patch, s, t, j: compose(&p, &a) };
                }
                Node::Split(children) => {
                    // A corner of an irregular domain (where the irregular
                    // vertices are): the general path evaluates it at the
                    // coarsest level whose masks are exact, so the tangents
                    // there do not depend on the table's depth.
                    let primal = self.traits.split != Split::Dual;
                    if node == self.roots[d] && primal && (self.patching.corner_at)(u, v).is_some() {
                        return Located::Deep { entry: u32::MAX, u, v, a };
                    }
                    let (k, ak, bk) = (self.patching.child)(u, v);
                    (u, v) = apply_affine(&(ak, bk), u, v);
                    a = compose(&ak, &a);
                    node = children[k];
                }
                Node::Deep(i) => return Located::Deep { entry: i, u, v, a },
            }
        }
    }

    fn evaluate_jet_with(
        &self,
        positions: &[DVec3],
        param: SurfaceParam,
        points: Option<&[DVec3]>,
    ) -> Result<LimitJet, EvalError> {
        let (d, u, v) = self.check_param(param)?;
        let Some((fu, fv, along_u)) = self.fold(d, u, v) else {
            return self.jet_at(positions, d, u, v, points);
        };
        // S(u, v) = G(½, min(u, v)): only the derivatives in the direction
        // of the minimum survive; the normal is the surface's, G_u × G_v.
        let jet = self.jet_at(positions, d, fu, fv, points)?;
        let (g_v, g_vv) = (jet.sample.dv, jet.dvv);
        let pick = |x: DVec3, here: bool| if here { x } else { DVec3::ZERO };
        Ok(LimitJet {
            sample: LimitSample { du: pick(g_v, along_u), dv: pick(g_v, !along_u), ..jet.sample },
            duu: pick(g_vv, along_u),
            duv: DVec3::ZERO,
            dvv: pick(g_vv, !along_u),
        })
    }

    /// Where an interior vertex of valence 2 of the control mesh has no
    /// V-face, the quarter (u, v) < (½, ½) of its domains has no surface: it
    /// is folded onto the edge between the two E-faces, (½, min(u, v))
    /// (`doo_sabin` module docs). The folded parameters and whether the
    /// minimum is u.
    fn fold(&self, d: usize, u: f64, v: f64) -> Option<(f64, f64, bool)> {
        if self.traits.split != Split::Dual || u >= 0.5 || v >= 0.5 || !self.folded[d] {
            return None;
        }
        Some((0.5, u.min(v), u <= v))
    }

    fn jet_at(
        &self,
        positions: &[DVec3],
        d: usize,
        u: f64,
        v: f64,
        points: Option<&[DVec3]>,
    ) -> Result<LimitJet, EvalError> {
        let mut out = [DVec3::ZERO; 6];
        match self.locate(d, u, v) {
            Located::Patch { patch, s, t, j } => {
                let kind = self.patch_kinds[patch as usize];
                let b = basis(kind, s, t);
                let mut cp = [DVec3::ZERO; 16];
                match points {
                    Some(points) => cp[..kind.len()].copy_from_slice(&points[patch as usize * 16..][..kind.len()]),
                    None => {
                        for (slot, c) in cp.iter_mut().enumerate().take(kind.len()) {
                            let (vs, ws) = self.point(patch, slot);
                            *c = vs.iter().zip(ws).fold(DVec3::ZERO, |acc, (&i, &w)| acc + w * positions[i as usize]);
                        }
                    }
                }
                out = jet_of(&b, &cp[..kind.len()], &j);
            }
            Located::Deep { entry, u: du, v: dv, a } => {
                let (ids, jet) = self.resume(d, u, v, entry, du, dv, a)?;
                for (r, o) in jet.rows.iter().zip(out.iter_mut()) {
                    *o = ids.iter().zip(r).fold(DVec3::ZERO, |acc, (&i, &w)| acc + w * positions[i as usize]);
                }
            }
        }
        let normal = degenerate_normal(&out, u, v).unwrap_or_else(|| unit_normal(out[1], out[2]));
        Ok(LimitJet {
            sample: LimitSample { position: out[0], du: out[1], dv: out[2], normal },
            duu: out[3],
            duv: out[4],
            dvv: out[5],
        })
    }

    /// The root of domain `d` and the first local level its (u, v) refer to
    /// (a Catmull-Clark n-gon's ptex quad is a level-1 face).
    fn domain_start(&self, d: usize) -> Result<(Vec<u32>, Local, FaceId), EvalError> {
        let dom = self.domains[d];
        let root = Root::new(&self.topology, &self.tags, &self.options, FaceId(dom.face))?;
        let (mut ids, local, face) = (root.ids, root.local, root.face);
        if let Some(map) = &self.vertex_map {
            ids.iter_mut().for_each(|i| *i = map[*i as usize]);
        }
        match self.traits.split {
            Split::Quad if self.topology.face_size(FaceId(dom.face)) != 4 => {
                let refined = local.refine(&self.options)?;
                let child = FaceId(local.t.faces().offsets()[face.index()] + dom.corner);
                let (local, face) = refined.ring(&self.options, child)?;
                Ok((ids, local, face))
            }
            Split::Quad | Split::Triangle | Split::Sqrt3 => Ok((ids, local, face)),
            Split::Dual => {
                let (local, face) = doo_sabin::domain_start(&local, &self.options, face, dom.corner as usize)?;
                Ok((ids, local, face))
            }
        }
    }

    fn build_tree(&self, d: Domain, sharp: &LevelSharpness) -> Result<Tree, EvalError> {
        let index = self.domain_index(d)?;
        let mut tree = Tree::default();
        // Most faces are regular on the control mesh itself: their patch
        // points are control vertices (or phantom combinations of them),
        // found without building the face's ring.
        let spec = self.patching.spec;
        if self.traits.split != Split::Dual {
            if let Some(points) = regular_points(spec, &self.topology, sharp, FaceId(d.face)) {
                tree.kinds.push(spec.kind);
                for slot in 0..16 {
                    tree.push_point(points.get(slot).into_iter().flatten().copied());
                }
                tree.nodes.push(Node::Patch(0));
                return Ok(tree);
            }
        }
        let (ids, local, face) = self.domain_start(index)?;
        self.build_node(&std::sync::Arc::new(ids), &local, face, 0, &mut tree)?;
        Ok(tree)
    }

    fn build_node(
        &self,
        ids: &std::sync::Arc<Vec<u32>>,
        local: &Local,
        face: FaceId,
        depth: usize,
        tree: &mut Tree,
    ) -> Result<u32, EvalError> {
        let spec = self.patching.spec;
        let id = tree.nodes.len() as u32;
        if let Some(points) = (self.patching.regular)(&local.t, &local.sharp, face) {
            let patch = tree.kinds.len() as u32;
            tree.kinds.push(spec.kind);
            let mut dense = vec![0.0; local.root];
            for slot in 0..16 {
                if slot < points.len() {
                    dense.iter_mut().for_each(|x| *x = 0.0);
                    local.combine(&points[slot], &mut dense);
                    tree.push_point(ids.iter().zip(&dense).filter(|&(_, &w)| w != 0.0).map(|(&i, &w)| (i, w)));
                } else {
                    tree.push_point([]);
                }
            }
            tree.nodes.push(Node::Patch(patch));
            return Ok(id);
        }
        // Below TABLE_DEPTH, or once the domain's table has TABLE_NODES nodes (along a
        // semi-sharp crease every level splits the cells beside it in two, whose rings stay
        // irregular for ⌈s⌉ levels: the table would grow with 2^s per domain), the rest is
        // refined on demand.
        if depth >= TABLE_DEPTH || tree.nodes.len() >= TABLE_NODES {
            tree.nodes.push(Node::Deep(tree.deep.len() as u32));
            tree.deep.push(DeepEntry { local: local.clone(), cell: face, ids: ids.clone() });
            return Ok(id);
        }
        tree.nodes.push(Node::Deep(u32::MAX)); // placeholder, replaced below
        let folded = self.traits.split == Split::Dual && !doo_sabin::has_v_face(&local.refine(&self.options)?, face);
        let mut children = [0u32; 4];
        for (k, c) in children.iter_mut().enumerate() {
            if k == 0 && folded {
                continue; // folded away (Self::fold): never descended into; filled below
            }
            // The cached step of this structure: the child's ring with the same weights as
            // refining `local` and taking the ring, its connectivity shared with the step.
            let step = self.step(local, face, k, depth >= CACHED_FROM_DEPTH)?;
            *c = self.build_node(ids, &local.apply(&step), step.cell, depth + 1, tree)?;
        }
        if folded {
            children[0] = children[1];
        }
        tree.nodes[id as usize] = Node::Split(children);
        Ok(id)
    }

    /// The general path: refine on demand until (u, v) lies in a regular
    /// patch or is an irregular vertex; dense weights on the domain's root.
    /// [`Self::general_from`] at a deep node of the table (from the
    /// domain's root when the entry is the building placeholder).
    #[allow(clippy::too_many_arguments)]
    fn resume(
        &self,
        d: usize,
        u0: f64,
        v0: f64,
        entry: u32,
        u: f64,
        v: f64,
        a: [[f64; 2]; 2],
    ) -> Result<(std::sync::Arc<Vec<u32>>, DenseJet), EvalError> {
        // The local plans use rayon inside (joins, parallel row builds):
        // run the whole refinement on one worker, so that a caller outside
        // the pool pays one hand-over rather than one per plan.
        match self.deep.get(entry as usize) {
            Some(e) => {
                let jet = rayon::scope(|_| self.general_from(e.local.clone(), e.cell, u, v, a, TABLE_DEPTH))?;
                Ok((e.ids.clone(), jet))
            }
            None => {
                let (ids, local, face) = self.domain_start(d)?;
                let jet = rayon::scope(|_| self.general_from(local, face, u0, v0, [[1.0, 0.0], [0.0, 1.0]], 0))?;
                Ok((std::sync::Arc::new(ids), jet))
            }
        }
    }

    /// The general path from a local level `start` levels below the domain
    /// ((u, v) its parameters, `a` = ∂(u,v)/∂(domain u, v)): refine on
    /// demand until (u, v) lies in a regular patch or is an irregular
    /// vertex; dense weights on the domain's root.
    fn general_from(
        &self,
        mut local: Local,
        mut face: FaceId,
        mut u: f64,
        mut v: f64,
        mut a: [[f64; 2]; 2],
        start: usize,
    ) -> Result<DenseJet, EvalError> {
        let spec = self.patching.spec;
        for depth in start..=MAX_DEPTH {
            if let Some(points) = (self.patching.regular)(&local.t, &local.sharp, face) {
                let (p, q) = self.patching.patch_frame;
                let (s, t) = (p[0][0] * u + p[0][1] * v + q[0], p[1][0] * u + p[1][1] * v + q[1]);
                let b = basis(spec.kind, s, t);
                let j = compose(&p, &a);
                let n = points.len();
                let (bu, bv) = first_derivatives(&b, &j);
                let (buu, buv, bvv) = second_derivatives(&b, &j);
                let mut rows: [Vec<f64>; 6] = std::array::from_fn(|_| vec![0.0; local.root]);
                let mut dense = vec![0.0; local.root];
                for (slot, combo) in points.iter().enumerate().take(n) {
                    dense.iter_mut().for_each(|x| *x = 0.0);
                    local.combine(combo, &mut dense);
                    for (r, w) in rows.iter_mut().zip([b.w[slot], bu[slot], bv[slot], buu[slot], buv[slot], bvv[slot]])
                    {
                        r.iter_mut().zip(&dense).for_each(|(o, x)| *o += w * x);
                    }
                }
                return Ok(DenseJet { rows });
            }
            let corner = match (self.patching.corner_at)(u, v) {
                Some(k) => Some(k),
                None if depth == MAX_DEPTH => {
                    let (k, cu, cv) = self.patching.nearest_corner(self.traits.domain, u, v);
                    (u, v) = (cu, cv);
                    Some(k)
                }
                None => None,
            };
            if let Some(k) = corner {
                let ready = match self.traits.split {
                    Split::Quad | Split::Triangle | Split::Sqrt3 => {
                        patch_vertex::ready(&local, &self.options, VertexId(local.t.face(face)[k]))
                    }
                    Split::Dual => true,
                };
                if ready || depth == MAX_DEPTH {
                    let [pos, ta, tb] = self.vertex_limit(&local, face, k)?;
                    // [T_a T_b] = [∂u' ∂v']·D, D = [d_a d_b]; then ·A to the domain.
                    let (da, db) = self.patching.frames[k];
                    let dm = [[da.0 as f64, db.0 as f64], [da.1 as f64, db.1 as f64]];
                    let det = dm[0][0] * dm[1][1] - dm[0][1] * dm[1][0];
                    let inv = [[dm[1][1] / det, -dm[0][1] / det], [-dm[1][0] / det, dm[0][0] / det]];
                    let j = compose(&inv, &a);
                    // ∂/∂u = T_a·j[0][0] + T_b·j[1][0]; ∂/∂v = T_a·j[0][1] + T_b·j[1][1].
                    let du: Vec<f64> = ta.iter().zip(&tb).map(|(x, y)| x * j[0][0] + y * j[1][0]).collect();
                    let dv: Vec<f64> = ta.iter().zip(&tb).map(|(x, y)| x * j[0][1] + y * j[1][1]).collect();
                    let zero = vec![0.0; local.root];
                    return Ok(DenseJet { rows: [pos, du, dv, zero.clone(), zero.clone(), zero] });
                }
            }
            let (k, ak, bk) = (self.patching.child)(u, v);
            let step = self.step(&local, face, k, true)?;
            (u, v) = apply_affine(&(ak, bk), u, v);
            a = compose(&ak, &a);
            local = local.apply(&step);
            face = step.cell;
        }
        Err(EvalError::Internal("no regular patch or vertex limit within the depth cap".into()))
    }

    /// The step of on-demand refinement from `face`'s child `k` on
    /// `local`'s structure: from the cache, else computed (and kept, when
    /// `keep`, while the cache has room).
    fn step(&self, local: &Local, face: FaceId, k: usize, keep: bool) -> Result<std::sync::Arc<Step>, EvalError> {
        let key = local.step_key(face, k);
        if let Some(step) = self.steps.0.read().ok().and_then(|map| map.get(&key).cloned()) {
            return Ok(step);
        }
        let step = std::sync::Arc::new(local.step(&self.options, face, k, self.patching.child_cell)?);
        if !keep {
            return Ok(step);
        }
        if let Ok(mut map) = self.steps.0.write() {
            if map.len() < MAX_CACHED_STEPS {
                map.entry(key).or_insert_with(|| step.clone());
            }
        }
        Ok(step)
    }

    fn vertex_limit(&self, local: &Local, face: FaceId, k: usize) -> Result<[Vec<f64>; 3], EvalError> {
        match self.traits.split {
            Split::Quad | Split::Triangle | Split::Sqrt3 => patch_vertex::vertex_limit(local, &self.options, face, k),
            Split::Dual => doo_sabin::vertex_limit(local, &self.options, face, k),
        }
    }
}

enum Located {
    Patch {
        patch: u32,
        s: f64,
        t: f64,
        j: [[f64; 2]; 2],
    },
    /// Below the table: the deep entry, the parameters there and ∂(u′,v′)/∂(u,v).
    Deep {
        entry: u32,
        u: f64,
        v: f64,
        a: [[f64; 2]; 2],
    },
}

/// Basis derivatives with respect to (u, v) from those in (s, t), J = ∂(s,t)/∂(u,v).
fn first_derivatives(b: &Basis, j: &[[f64; 2]; 2]) -> ([f64; 16], [f64; 16]) {
    let mut du = [0.0; 16];
    let mut dv = [0.0; 16];
    for k in 0..16 {
        du[k] = b.ds[k] * j[0][0] + b.dt[k] * j[1][0];
        dv[k] = b.ds[k] * j[0][1] + b.dt[k] * j[1][1];
    }
    (du, dv)
}

/// Second derivatives with respect to (u, v) (the map is affine).
fn second_derivatives(b: &Basis, j: &[[f64; 2]; 2]) -> ([f64; 16], [f64; 16], [f64; 16]) {
    let mut out = ([0.0; 16], [0.0; 16], [0.0; 16]);
    let h = |k: usize, x: usize, y: usize| {
        // Σ_ab H_ab J[a][x] J[b][y]
        b.dss[k] * j[0][x] * j[0][y] + b.dst[k] * (j[0][x] * j[1][y] + j[1][x] * j[0][y]) + b.dtt[k] * j[1][x] * j[1][y]
    };
    for k in 0..16 {
        out.0[k] = h(k, 0, 0);
        out.1[k] = h(k, 0, 1);
        out.2[k] = h(k, 1, 1);
    }
    out
}

/// Position, du, dv, duu, duv, dvv of a patch.
#[inline]
fn jet_of(b: &Basis, points: &[DVec3], j: &[[f64; 2]; 2]) -> [DVec3; 6] {
    let mut st = [DVec3::ZERO; 6]; // value, s, t, ss, st, tt
    for (k, &p) in points.iter().enumerate() {
        st[0] += b.w[k] * p;
        st[1] += b.ds[k] * p;
        st[2] += b.dt[k] * p;
        st[3] += b.dss[k] * p;
        st[4] += b.dst[k] * p;
        st[5] += b.dtt[k] * p;
    }
    let du = st[1] * j[0][0] + st[2] * j[1][0];
    let dv = st[1] * j[0][1] + st[2] * j[1][1];
    let h = |x: usize, y: usize| {
        st[3] * (j[0][x] * j[0][y]) + st[4] * (j[0][x] * j[1][y] + j[1][x] * j[0][y]) + st[5] * (j[1][x] * j[1][y])
    };
    [st[0], du, dv, h(0, 0), h(0, 1), h(1, 1)]
}

/// The normal where one first derivative vanishes: on a Doo-Sabin
/// boundary curve the derivative across it is zero (the boundary rule
/// repeats the boundary row, `doo_sabin` module docs), while the surface is
/// smooth up to it. There S_u(u) ≈ (u − u₀)·S_uu toward the inside, so the
/// normal is the limit of (u − u₀)·S_uu × S_v, and likewise in v. `None`
/// where neither derivative vanishes (to rounding, [`DEGENERATE_DERIVATIVE`]).
fn degenerate_normal(jet: &[DVec3; 6], u: f64, v: f64) -> Option<DVec3> {
    let [_, du, dv, duu, _, dvv] = *jet;
    let inward = |x: f64| if x > 0.5 { -1.0 } else { 1.0 };
    // The lengths compared on one common scale (no overflow or underflow of the squares).
    let scale = PowerOfTwoScale::normalizing([du, dv]);
    let (du_length, dv_length) = (scale.apply_point(du).length(), scale.apply_point(dv).length());
    if du_length <= DEGENERATE_DERIVATIVE * dv_length {
        Some(unit_normal(inward(u) * duu, dv))
    } else if dv_length <= DEGENERATE_DERIVATIVE * du_length {
        Some(unit_normal(du, inward(v) * dvv))
    } else {
        None
    }
}

/// du × dv normalised; zero where it vanishes. Each factor is first scaled
/// by an exact power of two into [½, 1) (the direction of the cross product
/// does not change), so the normal of a surface at 1e-300 or 1e300 is as
/// accurate as at 1: the products neither underflow nor overflow.
fn unit_normal(du: DVec3, dv: DVec3) -> DVec3 {
    let scaled = |d: DVec3| PowerOfTwoScale::normalizing([d]).apply_point(d);
    let n = scaled(du).cross(scaled(dv));
    // n's largest component is at most 2; a zero or subnormal one is scaled up too.
    let n = PowerOfTwoScale::normalizing([n]).apply_point(n);
    let l = n.length();
    if l > 0.0 && l.is_finite() {
        n / l
    } else {
        DVec3::ZERO
    }
}

/// A [`LimitSurface`] with its patch table's control points computed for
/// fixed positions ([`LimitSurface::bind`]): an evaluation on a regular
/// patch is a descent of the domain's patch tree and one basis evaluation.
#[derive(Clone, Debug)]
pub struct BoundSurface<'a> {
    surface: &'a LimitSurface,
    positions: &'a [DVec3],
    /// 16 slots per patch.
    points: Vec<DVec3>,
}

impl BoundSurface<'_> {
    /// The surface.
    pub fn surface(&self) -> &LimitSurface {
        self.surface
    }

    /// The positions bound.
    pub fn positions(&self) -> &[DVec3] {
        self.positions
    }

    /// Position, derivatives and normal at `param`.
    ///
    /// # Errors
    /// As [`LimitSurface::evaluate`].
    pub fn evaluate(&self, param: SurfaceParam) -> Result<LimitSample, EvalError> {
        Ok(self.evaluate_jet(param)?.sample)
    }

    /// An axis-aligned box holding the limit surface over `domain`: the
    /// bounds of its regular patches' control points (each patch lies in
    /// their convex hull, phantom points included: the bases are
    /// non-negative) and, below the table, of the refined points around the
    /// irregular vertex (the surface there is a convex combination of them).
    /// Much tighter than the hull of [`LimitSurface::domain_support`];
    /// `None` for a domain the mesh does not have.
    pub fn domain_bounds(&self, domain: Domain) -> Option<(DVec3, DVec3)> {
        let s = self.surface;
        let d = s.domain_index(domain).ok()?;
        let first = s.roots[d] as usize;
        let end = s.roots.get(d + 1).map_or(s.nodes.len(), |&r| r as usize);
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        let mut add = |p: DVec3| {
            lo = lo.min(p);
            hi = hi.max(p);
        };
        for node in &s.nodes[first..end] {
            match node.0 {
                Node::Patch(p) => {
                    let n = s.patch_kinds[p as usize].len();
                    self.points[p as usize * 16..][..n].iter().for_each(|&q| add(q));
                }
                Node::Deep(i) => {
                    if let Some(e) = s.deep.get(i as usize) {
                        let root = e.local.root;
                        for row in e.local.rows.chunks(root) {
                            add(e
                                .ids
                                .iter()
                                .zip(row)
                                .fold(DVec3::ZERO, |acc, (&v, &w)| acc + w * self.positions[v as usize]));
                        }
                    } else {
                        for &v in s.domain_support(domain)? {
                            add(self.positions[v as usize]);
                        }
                    }
                }
                Node::Split(_) => {}
            }
        }
        Some((lo, hi))
    }

    /// [`Self::evaluate`] with the second derivatives (zero at an irregular
    /// vertex itself).
    ///
    /// # Errors
    /// As [`LimitSurface::evaluate`].
    pub fn evaluate_jet(&self, param: SurfaceParam) -> Result<LimitJet, EvalError> {
        self.surface.evaluate_jet_with(self.positions, param, Some(&self.points))
    }
}
