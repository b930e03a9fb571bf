//! Closest points on the limit surface: for a query point q, the parameter
//! (domain, u, v) minimising ‖S(u, v) − q‖ over the whole surface.
//!
//! # Algorithm
//! 1. **Conservative patch bounds.** Catmull-Clark and Loop weights are
//!    non-negative and local: the limit patch of a face lies in the convex
//!    hull of the control points of the faces around its corners (its
//!    *face ring*). Bounding the hull of the level-0 ring is loose (the ring
//!    is three faces wide), so the mesh is refined [`ProjectOptions::levels`]
//!    times first (the refined mesh has the same limit surface) and every
//!    refined face's ring gives the box of one piece of its ancestor's
//!    domain ([`refined_bounds`]); a regular Catmull-Clark face of an
//!    untagged mesh (four interior valence-4 corners) is a bicubic B-spline
//!    patch, bounded tighter by the box of its Bézier control points. For
//!    other schemes the boxes are the hulls of
//!    [`LimitSurface::domain_support`] ([`support_bounds`]). The boxes are
//!    inflated by [`BOUND_INFLATION`]·d for rounding.
//! 2. **BVH.** The boxes go into a [`Bvh`]; a query walks it nearest box
//!    first and prunes every box farther than the best distance so far (a
//!    box distance is a lower bound of the distance to what it holds).
//! 3. **Local solve.** The first time a box of a domain is reached, the
//!    whole domain is solved: start at the nearest of precomputed samples
//!    of the domain (cell centres, [`ProjectOptions::grid`]), then a
//!    projected Newton iteration on f(u, v) = ½‖S(u, v) − q‖² (exact
//!    gradient (S_u·r, S_v·r), Hessian with the second-derivative terms
//!    r·S_uu …, the Gauss-Newton matrix JᵀJ when that is not positive
//!    definite), an active set on the domain's edges (a constraint is held
//!    when the descent direction leaves the domain through it: the iteration
//!    slides along the edge), steps clipped to the domain, an Armijo
//!    backtracking line search, and value probes ([`CORNER_PROBE`] along both
//!    edges) where it stalls in a corner — the evaluator's derivatives at a
//!    corner come from tangent masks and need not be the patch's.
//!    Each box is a piece of its domain ([`PieceMap`]: a refined face's part
//!    of it). Where the surface folds (a sliver triangle of a scan) the first
//!    run can stop in a local minimum far from a point of another piece, so a
//!    piece of a solved domain whose box is nearer than the best foot so far
//!    (by [`RESTART_RATIO`]) and that holds no foot yet gets a run of its
//!    own, from its own nearest sample, without hand-overs (step 4). A foot
//!    handed over at an edge does not count as one: on a smooth surface the
//!    minimum often lies just inside a piece whose domain's run handed over
//!    at its edge while the neighbour's run went elsewhere (feet found
//!    2·10⁻⁵·d off on domain edges of a fitted torus, 2·10⁻⁹·d across them).
//! 4. **Hand-over at smooth edges** ([`Projector::with_smooth_edges`]): where
//!    the descent leaves through an edge the surface crosses C¹, the domain
//!    stops and leaves the rest to the neighbour, whose boxes are as near.
//!    This saves slides along edges into extraordinary corners, where the
//!    evaluation refines on demand and costs ~100× a regular patch. When a
//!    hand-over point is the best of all, its domain is finished from there
//!    without hand-overs.
//!
//! Exactness: the pruning never drops a domain that could hold a closer
//! point; each domain's solve is a local method started from its nearest
//! sample. The tests (`tests/integration/project.rs`) check the acceptance — every
//! result evaluates back to itself and is never farther than the nearest
//! vertex of the level-4 limit tessellation plus 1e-9·d — on thousands of
//! queries near, inside and far from extraordinary vertices, n-gons,
//! boundaries, creases and corners, Loop surfaces and the Spot fixture.
//!
//! Queries run in parallel with rayon; the output keeps the input order and
//! does not depend on the thread count (each query is independent).
//! Throughput (benches/project.rs, 11,712-face Catmull-Clark mesh, 2
//! threads, a loaded machine): 1.1·10⁵ queries/s (1.2-1.5·10⁵ before the piece restarts of
//! step 3, which found wrong feet), 9 in 10 queries within 1 % of d of the
//! surface.

use crate::bvh::{union, Bvh};
use crate::surface::{BoundSurface, Domain, EvalError, LimitJet, LimitSample, LimitSurface, SurfaceParam};
use glam::DVec3;
use rayon::prelude::*;
use subdiv_mesh::{Aabb, FaceId, HalfEdgeId, Mesh, PowerOfTwoScale, Topology, VertexId};
use subdiv_stencil::{Domain as ParamDomain, Options, Scheme, SubdivisionPlan};

/// Boxes are grown by this fraction of the control mesh's bbox diagonal
/// (rounding in the refined positions and in the evaluation).
pub const BOUND_INFLATION: f64 = 1e-9;
/// Newton stops when a step moves (u, v) by less than this.
pub const PARAM_TOLERANCE: f64 = 1e-14;
/// How far (in the parameter) [`Projector`] probes along the edges from a
/// corner of a domain where Newton is blocked.
pub const CORNER_PROBE: f64 = 1e-3;
/// Halvings of a Newton step before the line search gives up (a step of 2⁻²⁴ of the Newton step).
pub const LINE_SEARCH_STEPS: usize = 24;
/// Step for the finite-difference second derivatives of
/// [`PatchEvaluator::evaluate_second`]'s default (on the unit domain).
pub const HESSIAN_STEP: f64 = 1e-5;

/// The shape of every domain of a surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DomainShape {
    /// (u, v) ∈ [0, 1]² (Catmull-Clark, Doo-Sabin).
    Square,
    /// u, v ≥ 0, u + v ≤ 1 (Loop).
    Triangle,
}

impl DomainShape {
    /// The shape of `scheme`'s domains ([`subdiv_stencil::SchemeTraits::domain`]).
    pub fn of(scheme: Scheme) -> Self {
        match scheme.traits().domain {
            ParamDomain::Quad => Self::Square,
            ParamDomain::Triangle => Self::Triangle,
        }
    }

    /// The domain as half-planes a·x ≤ b.
    fn constraints(self) -> &'static [([f64; 2], f64)] {
        match self {
            Self::Square => &[([-1.0, 0.0], 0.0), ([1.0, 0.0], 1.0), ([0.0, -1.0], 0.0), ([0.0, 1.0], 1.0)],
            Self::Triangle => &[([-1.0, 0.0], 0.0), ([0.0, -1.0], 0.0), ([1.0, 1.0], 1.0)],
        }
    }

    /// The domain's centroid.
    pub fn centroid(self) -> (f64, f64) {
        match self {
            Self::Square => (0.5, 0.5),
            Self::Triangle => (1.0 / 3.0, 1.0 / 3.0),
        }
    }

    /// True when (u, v) is in the domain.
    pub fn contains(self, u: f64, v: f64) -> bool {
        self.constraints().iter().all(|(a, b)| a[0] * u + a[1] * v <= *b)
    }

    /// (u, v) moved into the domain (the nearest point; for rounding).
    pub fn clamp(self, u: f64, v: f64) -> (f64, f64) {
        let (u, v) = (u.clamp(0.0, 1.0), v.clamp(0.0, 1.0));
        match self {
            Self::Square => (u, v),
            Self::Triangle if u + v > 1.0 => {
                let excess = 0.5 * (u + v - 1.0);
                let (u, v) = ((u - excess).max(0.0), (v - excess).max(0.0));
                (u, v.min(1.0 - u))
            }
            Self::Triangle => (u, v),
        }
    }

    /// Newton's start points: the centres of the n × n cells of a square, the
    /// centroids of the n² triangles of the n-split triangle. Inside the
    /// domain, away from its corners, where an evaluation near an
    /// extraordinary vertex is expensive (refinement on demand).
    pub fn start_points(self, n: usize) -> Vec<(f64, f64)> {
        let n = n.max(1);
        match self {
            Self::Square => {
                (0..n * n).map(|k| (((k % n) as f64 + 0.5) / n as f64, ((k / n) as f64 + 0.5) / n as f64)).collect()
            }
            Self::Triangle => crate::sample::sub_triangles(self, n)
                .iter()
                .map(|[a, b, c]| ((a.0 + b.0 + c.0) / 3.0, (a.1 + b.1 + c.1) / 3.0))
                .collect(),
        }
    }

    /// The vertices of the domain split `n` times along each side: an
    /// (n+1)² grid (square) or the (n+1)(n+2)/2 barycentric grid (triangle).
    pub fn grid(self, n: usize) -> Vec<(f64, f64)> {
        let n = n.max(1);
        let t = |i: usize| i as f64 / n as f64;
        let mut out = Vec::new();
        for j in 0..=n {
            let last = match self {
                Self::Square => n,
                Self::Triangle => n - j,
            };
            for i in 0..=last {
                out.push((t(i), t(j)));
            }
        }
        out
    }
}

/// What sampling and projection need from a limit surface whose control
/// points are fixed: its domains and their shape, and evaluation.
///
/// [`BoundLimitSurface`] implements it for [`LimitSurface`]; tests implement
/// it for closed-form surfaces.
pub trait PatchEvaluator: Sync {
    /// The shape of every domain.
    fn shape(&self) -> DomainShape;
    /// Every domain, in face order.
    fn domains(&self) -> &[Domain];
    /// Position, first derivatives and normal at `param`.
    fn evaluate(&self, param: SurfaceParam) -> Result<LimitSample, EvalError>;
    /// Where an iterate at `param` continues when `param` lies in a part of
    /// a domain without surface of its own (the default: `param` itself;
    /// [`LimitSurface::unfold`] for a Doo-Sabin quarter folded at a
    /// valence-2 vertex). Projection moves its iterates there, so that Newton
    /// steps do not stall where a derivative is zero.
    fn canonical(&self, param: SurfaceParam) -> SurfaceParam {
        param
    }
    /// Also the second derivatives. The default differentiates
    /// [`Self::evaluate`]'s first derivatives (forward differences of step
    /// [`HESSIAN_STEP`], backward where the forward point leaves the domain):
    /// good enough for Newton's matrix, whose accuracy only changes the
    /// convergence rate (the gradient is exact).
    fn evaluate_second(&self, param: SurfaceParam) -> Result<LimitJet, EvalError> {
        let sample = self.evaluate(param)?;
        let shape = self.shape();
        let h = HESSIAN_STEP;
        let diff = |du: f64, dv: f64| -> Result<Option<(DVec3, DVec3)>, EvalError> {
            for sign in [1.0, -1.0] {
                let (u, v) = (param.u + sign * du, param.v + sign * dv);
                if shape.contains(u, v) {
                    let s = self.evaluate(SurfaceParam { u, v, ..param })?;
                    return Ok(Some(((s.du - sample.du) / (sign * h), (s.dv - sample.dv) / (sign * h))));
                }
            }
            Ok(None)
        };
        let along_u = diff(h, 0.0)?;
        let along_v = diff(0.0, h)?;
        let (duu, duv_a) = along_u.unwrap_or((DVec3::ZERO, DVec3::ZERO));
        let (duv_b, dvv) = along_v.map_or((DVec3::ZERO, DVec3::ZERO), |(a, b)| (a, b));
        let duv = match (along_u, along_v) {
            (Some(_), Some(_)) => 0.5 * (duv_a + duv_b),
            (Some(_), None) => duv_a,
            _ => duv_b,
        };
        Ok(LimitJet { sample, duu, duv, dvv })
    }
}

/// A [`LimitSurface`] bound to its control points ([`LimitSurface::bind`]):
/// the [`PatchEvaluator`] of sampling, projection and fitting, with the
/// evaluator's exact second derivatives.
#[derive(Clone, Debug)]
pub struct BoundLimitSurface<'a> {
    bound: BoundSurface<'a>,
    shape: DomainShape,
}

impl<'a> BoundLimitSurface<'a> {
    /// `surface` at control points `positions`.
    ///
    /// # Errors
    /// As [`LimitSurface::bind`] (a position count that does not match).
    pub fn new(surface: &'a LimitSurface, positions: &'a [DVec3]) -> Result<Self, EvalError> {
        Ok(Self { bound: surface.bind(positions)?, shape: DomainShape::of(surface.options().scheme) })
    }
}

impl PatchEvaluator for BoundLimitSurface<'_> {
    fn shape(&self) -> DomainShape {
        self.shape
    }
    fn domains(&self) -> &[Domain] {
        self.bound.surface().domains()
    }
    fn evaluate(&self, param: SurfaceParam) -> Result<LimitSample, EvalError> {
        self.bound.evaluate(param)
    }
    fn canonical(&self, param: SurfaceParam) -> SurfaceParam {
        self.bound.surface().unfold(param)
    }
    fn evaluate_second(&self, param: SurfaceParam) -> Result<LimitJet, EvalError> {
        self.bound.evaluate_jet(param)
    }
}

/// Tuning of [`Projector`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectOptions {
    /// Refinement levels before the face-ring boxes are taken (Catmull-Clark
    /// and Loop; more levels: tighter boxes, more of them). Default 2.
    pub levels: usize,
    /// Start points: every domain sampled at [`DomainShape::start_points`]`(grid)`. Default 4.
    pub grid: usize,
    /// Newton iterations per domain at most. Default 40.
    pub max_iterations: usize,
}

impl Default for ProjectOptions {
    fn default() -> Self {
        Self { levels: 2, grid: 4, max_iterations: 40 }
    }
}

/// The closest point of the surface to one query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// Where it is.
    pub param: SurfaceParam,
    /// The surface point S(param).
    pub position: DVec3,
    /// Unit normal there.
    pub normal: DVec3,
    /// ‖position − query‖.
    pub distance: f64,
}

/// Where a piece of a domain lies in it: the affine map from the piece's own
/// unit domain (the square or triangle of [`DomainShape`]) to the domain's
/// (u, v) = `origin` + s·`axes[0]` + t·`axes[1]`. A refined face's piece is
/// its ancestor domain's image of the refined face's own parameters (corner
/// 0 at (0, 0), corner 1 at (1, 0)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PieceMap {
    /// The image of the piece's (0, 0).
    pub origin: [f64; 2],
    /// The images of the piece's unit steps along s and t.
    pub axes: [[f64; 2]; 2],
}

impl PieceMap {
    /// The whole domain.
    pub const WHOLE: Self = Self { origin: [0.0, 0.0], axes: [[1.0, 0.0], [0.0, 1.0]] };

    /// The domain parameter of the piece's (s, t).
    pub fn apply(&self, s: f64, t: f64) -> (f64, f64) {
        let [o, a, b] = [self.origin, self.axes[0], self.axes[1]];
        (o[0] + s * a[0] + t * b[0], o[1] + s * a[1] + t * b[1])
    }

    /// The piece's (s, t) of the domain parameter (u, v) (the inverse of [`Self::apply`]).
    pub fn local(&self, u: f64, v: f64) -> (f64, f64) {
        let [a, b] = self.axes;
        let det = a[0] * b[1] - a[1] * b[0];
        let (x, y) = (u - self.origin[0], v - self.origin[1]);
        ((x * b[1] - y * b[0]) / det, (a[0] * y - a[1] * x) / det)
    }

    /// True when the domain parameter (u, v) lies in the piece (to `margin` in the piece's parameters).
    pub fn contains(&self, shape: DomainShape, u: f64, v: f64, margin: f64) -> bool {
        let (s, t) = self.local(u, v);
        shape.constraints().iter().all(|(a, b)| a[0] * s + a[1] * t <= b + margin)
    }

    /// The piece of this piece that the child map `(A, b)` (parent (u, v) →
    /// child A·(u, v) + b, as the schemes' `child` functions give it) covers:
    /// this map composed with the child map's inverse.
    fn child(&self, (a, b): ([[f64; 2]; 2], [f64; 2])) -> Self {
        let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
        let inverse = [[a[1][1] / det, -a[0][1] / det], [-a[1][0] / det, a[0][0] / det]];
        // Child (s, t) ↦ parent A⁻¹·((s, t) − b) ↦ this map.
        let back =
            |x: [f64; 2]| [inverse[0][0] * x[0] + inverse[0][1] * x[1], inverse[1][0] * x[0] + inverse[1][1] * x[1]];
        let o = back([-b[0], -b[1]]);
        let (e0, e1) = (back([1.0, 0.0]), back([0.0, 1.0]));
        let linear = |x: [f64; 2]| {
            [x[0] * self.axes[0][0] + x[1] * self.axes[1][0], x[0] * self.axes[0][1] + x[1] * self.axes[1][1]]
        };
        let origin = self.apply(o[0], o[1]);
        Self { origin: [origin.0, origin.1], axes: [linear(e0), linear(e1)] }
    }
}

/// One box of a piece of a domain: the piece's limit patch lies in `bounds`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DomainPiece {
    /// The domain's index (in the surface's domain list).
    pub domain: u32,
    /// Where the piece lies in the domain.
    pub map: PieceMap,
    /// A box holding the piece's limit patch.
    pub bounds: Aabb,
}

/// Boxes of pieces of domains, the union of a domain's pieces covering it.
pub type DomainBounds = Vec<DomainPiece>;

/// A closest-point index over a limit surface with fixed control points.
pub struct Projector<E: PatchEvaluator> {
    eval: E,
    bvh: Bvh,
    leaf_domain: Vec<u32>,
    leaf_map: Vec<PieceMap>,
    grid_params: Vec<(f64, f64)>,
    /// Grid sample positions, `grid_params.len()` per domain.
    grid_points: Vec<DVec3>,
    /// Per domain, per constraint of [`DomainShape`]: the surface is C¹ across that edge.
    smooth_edges: Vec<[bool; 4]>,
    options: ProjectOptions,
    /// A distance below which a foot counts as exact ([`EXACT_DISTANCE`]·d of the grid samples).
    exact_distance: f64,
}

/// A foot this close to its query (as a fraction of the surface's size) is
/// taken as exact: [`Projector::project`] starts no further Newton runs in
/// other pieces of domains it already solved.
pub const EXACT_DISTANCE: f64 = 1e-12;

/// A foot within this margin (in a piece's parameters) of a piece counts as in it.
const PIECE_MARGIN: f64 = 1e-9;

/// A piece of a solved domain gets a Newton run of its own when its box is
/// nearer than this fraction of the best squared distance (a point there
/// would be at least 1/√2 nearer). Measured on the projection bench (an
/// 11,712-face mesh, 20,000 queries near and far): restarting every piece
/// nearer than the best ran 3.5× slower, this ratio within noise (+3 %);
/// with the restarts after hand-overs too, +67 % (112 → 187 ms for 20,000
/// queries): on a smooth surface a first run often hands over at the edge
/// its minimum lies just inside of (a fitted torus: feet found 2·10⁻⁵·d
/// away on domain edges, 2·10⁻⁹·d across them).
/// On a scan whose every domain is irregular (ChineseDragon-10kv under
/// Catmull-Clark, 5,000 queries 10⁻³·d and 10⁻²·d off its vertices) the
/// queries take 1.5× as long (15 s against 10 s, beside the 28 s table) and
/// 26 and 15 of them find a nearer point, up to 1.3·10⁻⁴·d nearer; a point
/// on that surface was answered 2·10⁻⁵·d away before.
pub const RESTART_RATIO: f64 = 0.5;

impl<E: PatchEvaluator> Projector<E> {
    /// An index over `eval` with the domain boxes `bounds` (every domain
    /// covered by the union of its boxes).
    ///
    /// # Errors
    /// What evaluating the start grid returns.
    pub fn new(eval: E, bounds: DomainBounds, options: ProjectOptions) -> Result<Self, EvalError> {
        let grid_params = eval.shape().start_points(options.grid);
        let domains = eval.domains();
        let grid_points: Vec<DVec3> = (0..domains.len())
            .into_par_iter()
            .map(|k| {
                let d = domains[k];
                grid_params
                    .iter()
                    .map(|&(u, v)| {
                        eval.evaluate(SurfaceParam { face: d.face, corner: d.corner, u, v }).map(|s| s.position)
                    })
                    .collect::<Result<Vec<_>, _>>()
            })
            .collect::<Result<Vec<_>, _>>()?
            .concat();
        let d = Aabb::of(grid_points.iter().copied()).map_or(0.0, |b| b.diagonal());
        let leaf_domain = bounds.iter().map(|p| p.domain).collect();
        let leaf_map = bounds.iter().map(|p| p.map).collect();
        Ok(Self {
            bvh: Bvh::new(bounds.into_iter().map(|p| p.bounds).collect()),
            leaf_domain,
            leaf_map,
            exact_distance: EXACT_DISTANCE * d,
            grid_params,
            grid_points,
            smooth_edges: Vec::new(),
            options,
            eval,
        })
    }

    /// The same index, told which domain edges the surface crosses smoothly
    /// (per domain, per constraint in [`DomainShape`] order: square u = 0,
    /// u = 1, v = 0, v = 1; triangle u = 0, v = 0, u + v = 1;
    /// [`smooth_domain_edges`]). A domain's Newton iteration stops where its
    /// descent leaves through such an edge: the neighbour across it continues
    /// the surface, is at the same box distance and is solved too, so the
    /// slide along the edge (often into an extraordinary corner, where
    /// evaluation is slow) is not needed. When such a hand-over point is the
    /// best of all (the minimum lies on the shared edge or at its corner, and
    /// every domain around handed over), its domain is finished from there
    /// without hand-overs.
    ///
    /// # Panics
    /// When `smooth` does not have one entry per domain (a caller bug).
    pub fn with_smooth_edges(mut self, smooth: Vec<[bool; 4]>) -> Self {
        assert_eq!(smooth.len(), self.eval.domains().len(), "one entry per domain");
        self.smooth_edges = smooth;
        self
    }

    /// The evaluator.
    pub fn evaluator(&self) -> &E {
        &self.eval
    }

    /// The closest surface point to `q`.
    ///
    /// # Errors
    /// [`EvalError::NoSurface`] when the surface has no domain; what evaluation returns.
    pub fn project(&self, q: DVec3) -> Result<Projection, EvalError> {
        // Every Newton run so far: its domain, where it ended, and whether it
        // ended there by handing over at a smooth edge (not a minimum of its domain).
        let mut solved: Vec<(u32, (f64, f64), bool)> = Vec::with_capacity(16);
        let mut best: Option<(Foot, u32)> = None;
        let mut error = None;
        let m = self.grid_params.len();
        let shape = self.eval.shape();
        let exact2 = self.exact_distance * self.exact_distance;
        self.bvh.nearest(q, f64::INFINITY, |item, box_distance2| {
            let k = self.leaf_domain[item as usize];
            let current = best.as_ref().map_or(f64::INFINITY, |(f, _)| f.dist2);
            if error.is_some() {
                return current;
            }
            let grid = &self.grid_points[k as usize * m..(k as usize + 1) * m];
            let nearest = |among: &mut dyn Iterator<Item = usize>| {
                among.min_by(|&a, &b| (grid[a] - q).length_squared().total_cmp(&(grid[b] - q).length_squared()))
            };
            let domain = self.eval.domains()[k as usize];
            let map = self.leaf_map[item as usize];
            // A run restarted in this piece: from the piece's own sample
            // nearest to q (or its centre), to a minimum of the domain
            // without hand-overs.
            let piece_start = || match nearest(&mut (0..m).filter(|&i| {
                let (u, v) = self.grid_params[i];
                map.contains(shape, u, v, 0.0)
            })) {
                Some(i) => self.grid_params[i],
                None => {
                    let c = shape.centroid();
                    map.apply(c.0, c.1)
                }
            };
            // The piece wants a run of its own when its box is nearer than the
            // best foot (by RESTART_RATIO) and no run ended at a minimum in it:
            // the surface may fold there (a local minimum elsewhere in the
            // domain caught the first run), or a run handed over at one of
            // its edges while the minimum lies just inside (the neighbour's
            // run went elsewhere). A handed-over foot does not count.
            let wants_restart = |solved: &[(u32, (f64, f64), bool)], best: f64| {
                best > exact2
                    && box_distance2 < RESTART_RATIO * best
                    && !solved
                        .iter()
                        .any(|&(d, (u, v), exited)| d == k && !exited && map.contains(shape, u, v, PIECE_MARGIN))
            };
            let first = solved.iter().all(|&(d, _, _)| d != k);
            if !first && !wants_restart(&solved, current) {
                return current;
            }
            // The domain's first run starts from its sample nearest to q and
            // hands over at smooth edges; when it hands over while this piece
            // wants a run of its own, the piece's run follows.
            let (mut start, mut smooth) = if first {
                let smooth = self.smooth_edges.get(k as usize).copied().unwrap_or([false; 4]);
                (self.grid_params[nearest(&mut (0..m)).unwrap_or(0)], smooth)
            } else {
                (piece_start(), [false; 4])
            };
            let mut found: Option<Foot> = None;
            loop {
                let foot = match closest_in_domain(&self.eval, domain, q, start, smooth, self.options.max_iterations) {
                    Ok(foot) => foot,
                    Err(e) => {
                        error = Some(e);
                        return current;
                    }
                };
                solved.push((k, (foot.param.u, foot.param.v), foot.exited));
                let again =
                    first && smooth != [false; 4] && foot.exited && wants_restart(&solved, current.min(foot.dist2));
                if found.as_ref().is_none_or(|f| foot.dist2 < f.dist2) {
                    found = Some(foot);
                }
                if !again {
                    break;
                }
                (start, smooth) = (piece_start(), [false; 4]);
            }
            match found {
                Some(foot) if foot.dist2 < current => {
                    let d = foot.dist2;
                    best = Some((foot, k));
                    d
                }
                _ => current,
            }
        });
        if let Some(e) = error {
            return Err(e);
        }
        let (mut foot, k) = best.ok_or(EvalError::NoSurface)?;
        if foot.exited {
            // The best point is where a domain handed over to its neighbour,
            // and no domain did better: the minimum is on that edge or at its
            // corner. Finish the domain from there, along its edges.
            let domain = self.eval.domains()[k as usize];
            let start = (foot.param.u, foot.param.v);
            let done = closest_in_domain(&self.eval, domain, q, start, [false; 4], self.options.max_iterations)?;
            if done.dist2 <= foot.dist2 {
                foot = done;
            }
        }
        Ok(Projection {
            param: foot.param,
            position: foot.sample.position,
            normal: foot.sample.normal,
            distance: foot.dist2.sqrt(),
        })
    }

    /// [`Self::project`] for every query, in parallel, in input order.
    ///
    /// # Errors
    /// The first failing query's error (in input order).
    pub fn project_all(&self, queries: &[DVec3]) -> Result<Vec<Projection>, EvalError> {
        queries.par_iter().with_min_len(64).map(|&q| self.project(q)).collect()
    }
}

/// Margin (in the parameter) inside which a [`project_near`] foot counts as
/// interior to its domain.
pub const NEAR_MARGIN: f64 = 1e-9;

/// The closest point to `q` near `hint`: Newton in `hint`'s domain started at
/// `hint` (step 3 of the module docs, without hand-overs). `Some` when it
/// converges to a point inside the domain (a stationary point of the
/// distance: a local closest point), `None` when it ends on the domain's
/// boundary or without converging — then the caller asks a [`Projector`].
/// Cheap (a few evaluations of one patch) where the surface moved little
/// since `hint` was found: fitting re-projects its feet this way.
///
/// # Errors
/// What evaluation returns (a `hint` outside the surface's domains).
pub fn project_near<E: PatchEvaluator + ?Sized>(
    eval: &E,
    q: DVec3,
    hint: SurfaceParam,
    max_iterations: usize,
) -> Result<Option<Projection>, EvalError> {
    let domain = Domain { face: hint.face, corner: hint.corner };
    let foot = closest_in_domain(eval, domain, q, (hint.u, hint.v), [false; 4], max_iterations)?;
    let (u, v) = (foot.param.u, foot.param.v);
    let inside = eval.shape().constraints().iter().all(|(a, b)| a[0] * u + a[1] * v < b - NEAR_MARGIN);
    if !inside || !foot.converged {
        return Ok(None);
    }
    Ok(Some(Projection {
        param: foot.param,
        position: foot.sample.position,
        normal: foot.sample.normal,
        distance: foot.dist2.sqrt(),
    }))
}

/// A local minimum found on one domain.
#[derive(Clone, Copy, Debug)]
struct Foot {
    param: SurfaceParam,
    sample: LimitSample,
    dist2: f64,
    /// Stopped at a smooth edge (not converged in its domain).
    exited: bool,
    /// Stopped before the iteration limit (a step below [`PARAM_TOLERANCE`], no descent left).
    converged: bool,
}

/// Projected Newton with an active set on the domain's edges (module docs, step 3).
fn closest_in_domain<E: PatchEvaluator + ?Sized>(
    eval: &E,
    domain: Domain,
    q: DVec3,
    start: (f64, f64),
    smooth: [bool; 4],
    max_iterations: usize,
) -> Result<Foot, EvalError> {
    let shape = eval.shape();
    let constraints = shape.constraints();
    let at = |u: f64, v: f64| SurfaceParam { face: domain.face, corner: domain.corner, u, v };
    let unfold = |u: f64, v: f64| {
        let p = eval.canonical(at(u, v));
        (p.u, p.v)
    };
    let (mut u, mut v) = unfold(start.0, start.1);
    let mut s = eval.evaluate_second(at(u, v))?;
    let mut f = 0.5 * (s.sample.position - q).length_squared();
    let mut exited = false;
    let mut converged = false;
    for _ in 0..max_iterations {
        let r = s.sample.position - q;
        let (su, sv) = (s.sample.du, s.sample.dv);
        let g = [su.dot(r), sv.dot(r)];
        let gn = [su.dot(su), su.dot(sv), sv.dot(sv)];
        let full = [gn[0] + s.duu.dot(r), gn[1] + s.duv.dot(r), gn[2] + s.dvv.dot(r)];
        let h = if full[0] > 0.0 && full[0] * full[2] - full[1] * full[1] > 0.0 { full } else { gn };
        // Constraints the descent direction −g would cross.
        let crossing: Vec<usize> = (0..constraints.len())
            .filter(|&i| {
                let (a, b) = constraints[i];
                a[0] * u + a[1] * v >= b - 1e-15 && -(a[0] * g[0] + a[1] * g[1]) > 0.0
            })
            .collect();
        if crossing.iter().any(|&i| smooth[i]) {
            // The neighbour across the edge goes on (Projector::with_smooth_edges).
            exited = true;
            break;
        }
        let active: Vec<[f64; 2]> = crossing.iter().map(|&i| constraints[i].0).collect();
        let on: Vec<[f64; 2]> =
            constraints.iter().filter(|(a, b)| a[0] * u + a[1] * v >= b - 1e-15).map(|(a, _)| *a).collect();
        let leaves = |d: [f64; 2]| on.iter().any(|a| a[0] * d[0] + a[1] * d[1] > 0.0);
        let descends = |d: [f64; 2]| d[0] * g[0] + d[1] * g[1] < 0.0;
        let dir = match active.len() {
            0 => Some(newton_step(h, g)),
            1 => Some(edge_step(h, g, active[0])),
            // A corner: move along one of its edges if that descends and stays inside.
            _ => active.iter().map(|&a| edge_step(h, g, a)).find(|&d| !leaves(d) && descends(d)),
        };
        // A Newton direction that leaves through an edge the iterate lies on
        // (while −g does not) slides along that edge instead.
        let dir = match dir {
            Some(d) if leaves(d) => on.iter().map(|&a| edge_step(h, g, a)).find(|&d| !leaves(d) && descends(d)),
            other => other,
        };
        let Some(dir) = dir else {
            // Blocked in a corner of the domain, where the derivatives may be
            // degenerate (an extraordinary or boundary corner): compare values
            // a little way along both edges instead.
            match probe_corner(eval, &at, shape, &on, (u, v), q, f)? {
                Some((nu, nv, ns, nf)) => {
                    (u, v, s, f) = (nu, nv, ns, nf);
                    continue;
                }
                None => {
                    converged = true;
                    break;
                }
            }
        };
        let slope = dir[0] * g[0] + dir[1] * g[1];
        if slope.is_nan() || slope >= 0.0 || dir[0].abs().max(dir[1].abs()) < PARAM_TOLERANCE {
            match probe_corner(eval, &at, shape, &on, (u, v), q, f)? {
                Some((nu, nv, ns, nf)) => {
                    (u, v, s, f) = (nu, nv, ns, nf);
                    continue;
                }
                None => {
                    converged = true;
                    break;
                }
            }
        }
        // Longest step inside the domain.
        let mut max_step: f64 = 1.0;
        for (a, b) in constraints {
            let ad = a[0] * dir[0] + a[1] * dir[1];
            if ad > 0.0 {
                max_step = max_step.min(((b - (a[0] * u + a[1] * v)) / ad).max(0.0));
            }
        }
        let mut step = max_step;
        let mut accepted = None;
        for _ in 0..LINE_SEARCH_STEPS {
            let (nu, nv) = shape.clamp(u + step * dir[0], v + step * dir[1]);
            let (nu, nv) = unfold(nu, nv);
            let ns = eval.evaluate_second(at(nu, nv))?;
            let nf = 0.5 * (ns.sample.position - q).length_squared();
            if nf <= f + 1e-4 * step * slope || nf < f {
                accepted = Some((nu, nv, ns, nf));
                break;
            }
            step *= 0.5;
        }
        let accepted = accepted.filter(|_| max_step > 0.0);
        let Some((nu, nv, ns, nf)) = accepted else {
            // No progress along the direction; in a corner, by values instead.
            match probe_corner(eval, &at, shape, &on, (u, v), q, f)? {
                Some((nu, nv, ns, nf)) => {
                    (u, v, s, f) = (nu, nv, ns, nf);
                    continue;
                }
                None => {
                    converged = true;
                    break;
                }
            }
        };
        let moved = (nu - u).abs().max((nv - v).abs());
        (u, v, s, f) = (nu, nv, ns, nf);
        if moved < PARAM_TOLERANCE {
            converged = true;
            break;
        }
    }
    Ok(Foot { param: at(u, v), sample: s.sample, dist2: 2.0 * f, exited, converged })
}

/// At a corner of the domain (two constraints `on`): the point
/// [`CORNER_PROBE`] along either edge from it, when that is closer to `q`
/// than `f` (= ½‖S − q‖² at the corner).
#[allow(clippy::type_complexity)]
fn probe_corner<E: PatchEvaluator + ?Sized>(
    eval: &E,
    at: &dyn Fn(f64, f64) -> SurfaceParam,
    shape: DomainShape,
    on: &[[f64; 2]],
    (u, v): (f64, f64),
    q: DVec3,
    f: f64,
) -> Result<Option<(f64, f64, LimitJet, f64)>, EvalError> {
    if on.len() < 2 {
        return Ok(None);
    }
    let mut best: Option<(f64, f64, LimitJet, f64)> = None;
    for a in on {
        let len = (a[0] * a[0] + a[1] * a[1]).sqrt();
        for sign in [1.0, -1.0] {
            let t = [-sign * a[1] / len, sign * a[0] / len];
            if on.iter().any(|b| b[0] * t[0] + b[1] * t[1] > 1e-12) {
                continue;
            }
            let (nu, nv) = shape.clamp(u + CORNER_PROBE * t[0], v + CORNER_PROBE * t[1]);
            let ns = eval.evaluate_second(at(nu, nv))?;
            let nf = 0.5 * (ns.sample.position - q).length_squared();
            if nf < best.as_ref().map_or(f, |b| b.3) {
                best = Some((nu, nv, ns, nf));
            }
        }
    }
    Ok(best)
}

/// −H⁻¹g for the 2×2 symmetric positive definite H = [h0 h1; h1 h2].
fn newton_step(h: [f64; 3], g: [f64; 2]) -> [f64; 2] {
    let det = h[0] * h[2] - h[1] * h[1];
    if det > 0.0 && h[0] > 0.0 {
        [-(h[2] * g[0] - h[1] * g[1]) / det, -(h[0] * g[1] - h[1] * g[0]) / det]
    } else {
        let scale = (h[0] + h[2]).max(f64::MIN_POSITIVE);
        [-g[0] / scale, -g[1] / scale]
    }
}

/// The Newton step along the edge with outward normal `a`.
fn edge_step(h: [f64; 3], g: [f64; 2], a: [f64; 2]) -> [f64; 2] {
    let len = (a[0] * a[0] + a[1] * a[1]).sqrt();
    let t = [-a[1] / len, a[0] / len];
    let gt = g[0] * t[0] + g[1] * t[1];
    let ht = h[0] * t[0] * t[0] + 2.0 * h[1] * t[0] * t[1] + h[2] * t[1] * t[1];
    let s = if ht > 0.0 { -gt / ht } else { -gt / (h[0] + h[2]).max(f64::MIN_POSITIVE) };
    [s * t[0], s * t[1]]
}

/// Boxes of the hulls of [`LimitSurface::domain_support`], one per domain,
/// inflated by [`BOUND_INFLATION`]·d; `None` when a domain has no support
/// with the hull property.
pub fn support_bounds(surface: &LimitSurface, positions: &[DVec3]) -> Option<DomainBounds> {
    let pad = inflation(positions);
    surface
        .domains()
        .iter()
        .enumerate()
        .map(|(k, &d)| {
            let support = surface.domain_support(d)?;
            let b = Aabb::of(support.iter().map(|&i| positions[i as usize]))?;
            Some(DomainPiece {
                domain: k as u32,
                map: PieceMap::WHOLE,
                bounds: Aabb { min: b.min - pad, max: b.max + pad },
            })
        })
        .collect()
}

fn inflation(positions: &[DVec3]) -> DVec3 {
    let d = Aabb::of(positions.iter().copied()).map_or(0.0, |b| b.diagonal());
    DVec3::splat(BOUND_INFLATION * d.max(f64::MIN_POSITIVE))
}

/// For Catmull-Clark and Loop: the mesh refined `levels` times (same limit
/// surface), and for every refined face the box of its face ring (the
/// control points its limit patch depends on, with non-negative weights),
/// named by the level-0 domain the refined face lies in. `domains` is the
/// surface's domain list (quads and Loop triangles: one domain `(f, 0)`;
/// n-gons: `(f, K)` per corner, the level-1 quad at corner K).
///
/// # Errors
/// [`EvalError::Unsupported`] for other schemes; [`EvalError::Stencil`]
/// when the mesh cannot be refined.
pub fn refined_bounds(
    mesh: &Mesh,
    options: &Options,
    domains: &[Domain],
    levels: usize,
) -> Result<DomainBounds, EvalError> {
    let loop_scheme = match options.scheme {
        Scheme::CatmullClark => false,
        Scheme::Loop(_) => true,
        other @ (Scheme::DooSabin | Scheme::DengMa(_) | Scheme::Sqrt3) => {
            return Err(EvalError::Unsupported {
                scheme: other.name(),
                reason: "no refined patch bounds (Catmull-Clark and Loop only)".into(),
            })
        }
    };
    let t0 = mesh.topology();
    // Index of domain (f, K): first[f] + K.
    let mut first = vec![u32::MAX; t0.face_count()];
    for (k, d) in domains.iter().enumerate().rev() {
        first[d.face as usize] = k as u32;
    }
    let levels = levels.max(usize::from(!loop_scheme));
    let plan = SubdivisionPlan::with_tags(t0, mesh.tags(), *options, levels)?;
    let positions = plan.apply(mesh.positions());
    // Domain of every face and where it lies in it, level by level.
    let mut owner: Vec<(u32, PieceMap)> = (0..t0.face_count()).map(|f| (first[f], PieceMap::WHOLE)).collect();
    let mut coarse: &Topology = t0;
    for (level, refinement) in plan.levels().iter().enumerate() {
        let fine = &refinement.topology;
        owner = (0..fine.face_count())
            .map(|c| {
                if loop_scheme {
                    // Children 4f … 4f + 3 of triangle f, in the split's order.
                    let (domain, map) = owner[c / 4];
                    (domain, map.child(child_map(true, c % 4)))
                } else {
                    // Child quad `h` of a quad split is the parent's corner h.
                    let h = HalfEdgeId(c as u32);
                    let parent = coarse.he_face(h);
                    let corner = c as u32 - coarse.face_half_edges(parent).next().expect("a face has corners").0;
                    let (domain, map) = owner[parent.index()];
                    if level == 0 && coarse.face_size(parent) != 4 {
                        // An n-gon's domain K is its level-1 quad at corner K.
                        (domain + corner, map)
                    } else {
                        (domain, map.child(child_map(false, corner as usize)))
                    }
                }
            })
            .collect();
        coarse = fine;
    }
    let t = plan.topology();
    let pad = inflation(mesh.positions());
    let regular_patches = !loop_scheme && mesh.tags().is_empty();
    Ok((0..t.face_count())
        .into_par_iter()
        .map(|f| {
            let (domain, map) = owner[f];
            let piece = |b: Aabb| DomainPiece { domain, map, bounds: Aabb { min: b.min - pad, max: b.max + pad } };
            if regular_patches {
                if let Some(b) = bezier_bounds(t, FaceId(f as u32), &positions) {
                    return piece(b);
                }
            }
            let mut b = Aabb { min: DVec3::splat(f64::INFINITY), max: DVec3::splat(f64::NEG_INFINITY) };
            for &c in t.face(FaceId(f as u32)) {
                for &h in t.vertex_fan(VertexId(c)) {
                    for &w in t.face(t.he_face(h)) {
                        let p = positions[w as usize];
                        b = union(&b, &Aabb { min: p, max: p });
                    }
                }
            }
            piece(b)
        })
        .collect())
}

/// The map from a Catmull-Clark quad's or a Loop triangle's (u, v) to its
/// child `k`'s parameters, `(A, b)` (the schemes' `child` functions, asked at
/// a point inside child `k`).
fn child_map(loop_scheme: bool, k: usize) -> ([[f64; 2]; 2], [f64; 2]) {
    const SQUARE: [(f64, f64); 4] = [(0.25, 0.25), (0.75, 0.25), (0.75, 0.75), (0.25, 0.75)];
    const TRIANGLE: [(f64, f64); 4] = [(0.1, 0.1), (0.8, 0.1), (0.1, 0.8), (0.3, 0.3)];
    let (index, a, b) = if loop_scheme {
        let (u, v) = TRIANGLE[k];
        crate::loop_scheme::child(u, v)
    } else {
        let (u, v) = SQUARE[k];
        crate::catmull_clark::child(u, v)
    };
    debug_assert_eq!(index, k);
    (a, b)
}

/// The uniform cubic B-spline → Bézier matrix: Bézier point i = Σ_k M[i][k]·Pₖ
/// (non-negative rows summing to 1).
const BSPLINE_TO_BEZIER: [[f64; 4]; 4] = [
    [1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0, 0.0],
    [0.0, 4.0 / 6.0, 2.0 / 6.0, 0.0],
    [0.0, 2.0 / 6.0, 4.0 / 6.0, 0.0],
    [0.0, 1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0],
];

/// The 4 × 4 control grid of a regular Catmull-Clark quad (every corner
/// interior with four faces, every face around it a quad, 16 distinct
/// vertices): grid[j][i] with the face in cells i, j ∈ {1, 2}, corner 0 at
/// (1, 1), corner 1 at (2, 1), corner 3 at (1, 2). `None` otherwise.
fn regular_grid(t: &Topology, f: FaceId) -> Option<[[u32; 4]; 4]> {
    if t.face_size(f) != 4 {
        return None;
    }
    let h: Vec<HalfEdgeId> = t.face_half_edges(f).collect();
    for &e in &h {
        let c = t.he_from(e);
        if t.is_boundary_vertex(c) || t.vertex_face_count(c) != 4 {
            return None;
        }
    }
    // Across edge k (corner k → k+1): the outer vertices p (next to corner k)
    // and q (next to corner k+1); at corner k, the diagonal vertex s.
    let mut p = [0u32; 4];
    let mut q = [0u32; 4];
    let mut s = [0u32; 4];
    for k in 0..4 {
        let twin = t.he_twin(h[k])?;
        if t.face_size(t.he_face(twin)) != 4 {
            return None;
        }
        let out = t.he_next(twin);
        p[k] = t.he_to(out).0;
        q[k] = t.he_to(t.he_next(out)).0;
        let diagonal = t.he_twin(out)?;
        if t.face_size(t.he_face(diagonal)) != 4 {
            return None;
        }
        s[k] = t.he_to(t.he_next(t.he_next(diagonal))).0;
    }
    let c: Vec<u32> = h.iter().map(|&e| t.he_from(e).0).collect();
    let grid = [[s[0], p[0], q[0], s[1]], [q[3], c[0], c[1], p[1]], [p[3], c[3], c[2], q[1]], [s[3], q[2], p[2], s[2]]];
    let mut all: Vec<u32> = grid.iter().flatten().copied().collect();
    all.sort_unstable();
    all.dedup();
    (all.len() == 16).then_some(grid)
}

/// The box of the Bézier control points of a regular Catmull-Clark quad's
/// bicubic patch (tighter than its face ring: the Bézier net hugs the
/// patch, and the patch lies in its convex hull); `None` for other faces.
fn bezier_bounds(t: &Topology, f: FaceId, positions: &[DVec3]) -> Option<Aabb> {
    let grid = regular_grid(t, f)?;
    let g = |i: usize, j: usize| positions[grid[j][i] as usize];
    let m = &BSPLINE_TO_BEZIER;
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for a in 0..4 {
        for b in 0..4 {
            let mut x = DVec3::ZERO;
            for i in 0..4 {
                for j in 0..4 {
                    let w = m[a][i] * m[b][j];
                    if w != 0.0 {
                        x += w * g(i, j);
                    }
                }
            }
            lo = lo.min(x);
            hi = hi.max(x);
        }
    }
    Some(Aabb { min: lo, max: hi })
}

/// The closest points on `mesh`'s limit surface under `options` to every
/// query (a plain-data entry point): Catmull-Clark and Loop use
/// [`refined_bounds`], other schemes [`support_bounds`].
///
/// # Errors
/// As [`LimitSurface::new`], [`Projector::project_all`];
/// [`EvalError::Unsupported`] when a scheme has no conservative bounds.
pub fn project_points(
    mesh: &Mesh,
    options: &Options,
    queries: &[DVec3],
    project: &ProjectOptions,
) -> Result<Vec<Projection>, EvalError> {
    let surface = LimitSurface::new(mesh, options)?;
    project_on(&surface, mesh, options, queries, project)
}

/// [`project_points`] on a `surface` already built from `mesh` and
/// `options`. The projection runs on the mesh and the queries scaled by the
/// exact power of two that brings the mesh's largest coordinate into
/// [½, 1) ([`PowerOfTwoScale::normalizing`]), and the positions and
/// distances are mapped back: squared distances of a surface at 1e-200 or
/// 1e200 neither underflow nor overflow, so the closest point is the one
/// found at scale 1. A query so far from the surface that its scaled
/// coordinates overflow gives an infinite distance (the caller refuses to
/// write it).
///
/// # Errors
/// As [`project_points`].
pub fn project_on(
    surface: &LimitSurface,
    mesh: &Mesh,
    options: &Options,
    queries: &[DVec3],
    project: &ProjectOptions,
) -> Result<Vec<Projection>, EvalError> {
    let scale = PowerOfTwoScale::normalizing(mesh.positions().iter().copied());
    if scale.is_identity() {
        return projector(surface, mesh, options, project)?.project_all(queries);
    }
    let mut scaled = mesh.clone();
    scale.apply_points(scaled.positions_mut());
    let queries = scale.scaled_points(queries);
    let mut found = projector(surface, &scaled, options, project)?.project_all(&queries)?;
    let back = scale.inverse();
    found.par_iter_mut().for_each(|p| {
        p.position = back.apply_point(p.position);
        p.distance = back.apply(p.distance);
    });
    Ok(found)
}

/// A [`Projector`] over `surface` (built from `mesh` and `options`) at
/// `mesh`'s positions.
///
/// # Errors
/// As [`project_points`].
pub fn projector<'a>(
    surface: &'a LimitSurface,
    mesh: &'a Mesh,
    options: &Options,
    project: &ProjectOptions,
) -> Result<Projector<BoundLimitSurface<'a>>, EvalError> {
    let bounds = match options.scheme {
        Scheme::CatmullClark | Scheme::Loop(_) => refined_bounds(mesh, options, surface.domains(), project.levels)?,
        other @ (Scheme::DooSabin | Scheme::DengMa(_) | Scheme::Sqrt3) => support_bounds(surface, mesh.positions())
            .ok_or_else(|| EvalError::Unsupported {
                scheme: other.name(),
                reason: "projection needs conservative patch bounds, and a domain has none".into(),
            })?,
    };
    let smooth = smooth_domain_edges(mesh, options, surface.domains());
    Ok(Projector::new(BoundLimitSurface::new(surface, mesh.positions())?, bounds, *project)?.with_smooth_edges(smooth))
}

/// For [`Projector::with_smooth_edges`]: the domain edges across which the
/// Catmull-Clark or Loop limit surface is C¹ — interior mesh edges without a
/// crease tag whose ends are neither boundary, corner-tagged nor crease
/// vertices, and the edges between the sub-domains of an n-gon that end on
/// such an edge. All false for other schemes.
pub fn smooth_domain_edges(mesh: &Mesh, options: &Options, domains: &[Domain]) -> Vec<[bool; 4]> {
    let t = mesh.topology();
    let tags = mesh.tags();
    // Vertices where the surface may not be C¹ (or where a minimum may sit
    // in a corner of every domain around it): boundary, corner-tagged and
    // crease vertices. No edge at them counts as smooth.
    let mut rough: Vec<bool> =
        t.vertices().map(|v| t.is_boundary_vertex(v) || tags.vertex_sharpness(v) > 0.0).collect();
    for e in t.edges() {
        if tags.edge_sharpness(e) > 0.0 {
            let (a, b) = t.edge_vertices(e);
            rough[a.index()] = true;
            rough[b.index()] = true;
        }
    }
    let smooth = |h: HalfEdgeId| {
        t.he_twin(h).is_some()
            && tags.edge_sharpness(t.he_edge(h)) == 0.0
            && !rough[t.he_from(h).index()]
            && !rough[t.he_to(h).index()]
    };
    domains
        .iter()
        .map(|d| {
            let f = FaceId(d.face);
            let h: Vec<HalfEdgeId> = t.face_half_edges(f).collect();
            let n = h.len();
            match options.scheme {
                // Square order: u = 0, u = 1, v = 0, v = 1; half-edge k runs corner k → k + 1.
                Scheme::CatmullClark if n == 4 => [smooth(h[3]), smooth(h[1]), smooth(h[0]), smooth(h[2])],
                Scheme::CatmullClark => {
                    let k = d.corner as usize;
                    // u = 1 runs from the midpoint of edge K → K+1 to the centre, v = 1 from
                    // the midpoint of edge K−1 → K: smooth when that mesh edge is.
                    let (before, after) = (smooth(h[(k + n - 1) % n]), smooth(h[k]));
                    [before, after, after, before]
                }
                // Triangle order: u = 0 (corners 2, 0), v = 0 (0, 1), u + v = 1 (1, 2).
                Scheme::Loop(_) => [smooth(h[2]), smooth(h[0]), smooth(h[1]), false],
                Scheme::DooSabin | Scheme::DengMa(_) | Scheme::Sqrt3 => [false; 4],
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_and_clamp_stay_in_the_domain() {
        for shape in [DomainShape::Square, DomainShape::Triangle] {
            for (u, v) in shape.grid(5) {
                assert!(shape.contains(u, v));
            }
            for (u, v) in [(-1.0, 0.5), (2.0, 2.0), (0.7, 0.7), (0.3, -0.2), (1.5, -3.0)] {
                let (a, b) = shape.clamp(u, v);
                assert!(shape.contains(a, b), "{shape:?} ({u}, {v}) → ({a}, {b})");
            }
        }
        assert_eq!(DomainShape::Square.grid(4).len(), 25);
        assert_eq!(DomainShape::Triangle.grid(4).len(), 15);
    }

    #[test]
    fn newton_step_solves_the_system() {
        let h = [3.0, 1.0, 2.0];
        let g = [1.0, -2.0];
        let d = newton_step(h, g);
        assert!((h[0] * d[0] + h[1] * d[1] + g[0]).abs() < 1e-15);
        assert!((h[1] * d[0] + h[2] * d[1] + g[1]).abs() < 1e-15);
    }
}
