//! Deng & Wang 2010: explicit, local interpolation by Loop surfaces
//! (Deng & Wang 2010, Eq. 1-9, DW10 in [references]; the text is
//! garbled and cut off after Eq. 9, reconstructed in [corrections W1-W9]).
//!
//! Only the **first** Loop step is modified (Eq. 7: 1Ḡ 1T 2G 2T …,
//! [correction W9]): its edge points are chosen freely (one degree of freedom per edge,
//! [correction W8]) and its vertex points are then solved so that the plain Loop
//! limit point of every old vertex of M¹ is the data point (Eq. 5). Nothing
//! global is solved: every new point is an explicit formula over a 1-ring,
//! so moving one data point changes the surface only near it.
//!
//! # Algorithm
//! 1. Normals n_i (Eq. 8, [correction W5]): the angle-weighted unit normal
//!    Σⱼ θⱼ nⱼ / ‖Σⱼ θⱼ nⱼ‖ ([`Mesh::vertex_normals`]), or the user's normal
//!    where [`DengWangOptions::normals`] gives one.
//! 2. Edge points (Eq. 9, [correction W6]), for an interior edge (i, j) with
//!    midpoint m = (p_i + p_j)/2:
//!    p_e = m + μ(d_i n_i + d_j n_j), d_i = (p_i − m)·n_i, d_j = (p_j − m)·n_j.
//! 3. Vertex points ([correction W7]): in M¹ the neighbours of old vertex i are
//!    exactly the edge points of its edges, so its plain Loop limit mask
//!    w·p_i¹ + Σ wⱼ p_{e(ij)} can be solved for the centre:
//!    p_i¹ = (p_i⁰ − Σⱼ wⱼ p_{e(ij)}) / w. Interior vertex of valence k:
//!    p_i¹ = (p_i⁰ − γ Σⱼ p_{e(ij)}) / (1 − kγ), γ = 1/(k + 3/(8β)) (Eq. 5-6,
//!    [correction W4]).
//! 4. Output M¹: the [`triangle_split`] connectivity of the input (old
//!    vertices keep their indices, then one edge point per edge in edge
//!    order), scheme Loop(β), with the input's tags decayed by one level and
//!    its UVs refined by one level ("Creases, corners and UVs" below).
//!    Control vertex i of M¹
//!    has input vertex i as its Loop limit point with M¹'s tags
//!    ([`LimitAssociation::ControlVertex`]).
//!
//! Steps 2-4 run on the triangulation M⁰ of the input ([`triangulate`]:
//! every polygon split over its own corners, no vertex added or moved), so
//! on a triangle mesh M⁰ is the input itself.
//!
//! # Deviations from the paper and choices it leaves open
//! - μ: the admissible range is cut off in the text. [Correction W6] proposes
//!   μ = ¼, which puts the edge points of points sampled from a sphere (with
//!   radial normals) **on** the sphere to O(h⁴). That is not what makes the
//!   *limit surface* close to the sphere: Loop's limit of points on a
//!   surface lies inside it by about h²κ/4 (h the edge length of M¹, κ the
//!   curvature). On a regular lattice sampling a quadric with curvature κ,
//!   step 2 offsets the edge points by (2μ − ½)κh² along the normal and
//!   step 3 then offsets the vertex points by (1 − 2μ)κh² (independent of
//!   the valence for Warren's β); at **μ = ⅜** both offsets equal κh²/4,
//!   exactly cancelling the shrinkage, so the limit surface deviates by
//!   O(h⁴) away from extraordinary vertices (and by O(h²) with a small
//!   constant near them, where Loop reproduces only linear functions). The
//!   test `mu_experiment_sphere_and_fairness` confirms it: on points of the
//!   unit sphere the level-4 limit surface's RMS distance from the sphere is
//!   3.3e-3 at μ = ¼ and 2.9e-4 at μ = ⅜ (icosphere_2), and the gap widens
//!   under refinement of the data (icospheres of 42 to 2562 vertices: ¼
//!   falls 4× per halving of h, ⅜ falls 12×, 8×, 5× — tending to the O(h²)
//!   of the extraordinary vertices with a ~25× smaller constant).
//!   Hence the default [`DEFAULT_MU`] = ⅜. Any finite μ interpolates in exact
//!   arithmetic (round-off grows with |μ|, and the measured-error check
//!   refuses what exceeds the tolerance); values
//!   outside [0, ½] give a warning.
//! - Open meshes (the paper restricts itself to closed meshes, "extension
//!   to open meshes is straightforward"):
//!   - boundary edges use the same formula with the boundary **curve's**
//!     normal plane in place of the surface's normal line, and μ scaled by
//!     [`BOUNDARY_MU_SCALE`] = 8/9:
//!     p_e = m + ⁸⁄₉μ(Π_i(p_i − m) + Π_j(p_j − m)), Π_v = I − t_v t_vᵀ, t_v
//!     the unit tangent of the boundary polygon at v (sum of the unit
//!     vectors along its two boundary edges; at a corner — a vertex in one
//!     triangle — the edge itself, so the corner contributes nothing). For a
//!     planar boundary curve Π_v(p_v − m) = d_v n_v with n_v the curve's
//!     principal normal. The boundary limit is the cubic B-spline of M¹'s
//!     boundary polygon, whose shrinkage the same computation as above
//!     cancels at ⅓ instead of ⅜ — hence the factor: at the default μ = ⅜
//!     a boundary sampled from a circle has its limit curve on the circle to
//!     O(h⁴), as the interior of a sphere (test
//!     `boundary_limit_curve_reproduces_circles`); μ = 0 gives the plain
//!     midpoint. The surface normal is not used on the boundary: it sees
//!     only the normal curvature of the boundary curve, not its geodesic
//!     curvature;
//!   - boundary vertices solve the plain boundary limit rule of M¹,
//!     (e₋ + 4p¹ + e₊)/6 = p⁰ over the two boundary edge points:
//!     p¹ = (6p⁰ − e₋ − e₊)/4; corners keep p¹ = p⁰ (their limit).
//! - Polygon meshes (the paper takes triangle meshes): faces of more than
//!   three corners are triangulated first — quads along the shorter valid
//!   diagonal, larger faces by ear clipping in their best-fit plane, never
//!   duplicating an edge (see [`triangulate`]). The data points stay the
//!   input's vertices with their indices, so subsets and normals refer to
//!   input vertices and the limit surface of M¹ (the modified first step of
//!   that triangulation) passes through every input vertex. A warning says
//!   how many faces were triangulated and the report's parameters carry
//!   `triangulated_faces`; a face with no triangulation that keeps the mesh
//!   manifold is refused, naming the face. Eq. 8 is evaluated on the
//!   triangles, as the paper writes it; on a planar face this is the
//!   polygon's own angle-weighted normal with its interior angles (a reflex
//!   corner counts with its angle above π). The Loop rule class of a
//!   boundary vertex follows the triangulation: a corner of one quad lies in
//!   one or two triangles.
//! - Vertex subset (beyond the paper): vertices not interpolated get the
//!   plain Loop vertex rule (Eq. 1, boundary (p₋ + 6p + p₊)/8); edge points
//!   are computed by Eq. 9 everywhere.
//! - Of [`CommonOptions`] only `subset`, `tol` and `surface` are read: the
//!   method is explicit, so iteration cap and solver do not apply; `tol` bounds the
//!   measured error of the result (the numeric rule, [`crate`] docs), which
//!   is round-off for moderate μ and grows with |μ| (μ = 1e300 fails it).
//!
//!
//! # Creases, corners and UVs
//! The paper has no sharp features; they follow OpenSubdiv's rules
//! (tags of [`Mesh::tags`], the boundary option and crease method of
//! [`CommonOptions::surface`], [`crate::SurfaceOptions`]). The contract is
//! the crate's: the control mesh, **with its tags** and those options, has
//! the data as its Loop limit points (the limit of
//! `subdiv_stencil::SubdivisionPlan::with_tags`: OpenSubdiv's `Limit` after
//! the levels the semi-sharp values need, at least one).
//! 1. M⁰ is the triangulation (it keeps the tags; its diagonals are smooth)
//!    and s⁰ its sharpness. M¹ is Loop's split of M⁰ with s⁰ — the
//!    [`triangle_split`] numbering above — and carries the tags of that
//!    split, the input's **decayed by one level** as OpenSubdiv hands them
//!    down (infinitely sharp values stay, semi-sharp ones lose 1, or
//!    Chaikin's average; corners likewise). So every later level of the
//!    surface refines M¹ exactly as if the input had been refined once.
//! 2. Edge points, by the step rule of the edge in s⁰
//!    ([`edge_points_sharp`]): a smooth edge by Eq. 9 — at an end with an
//!    interior sharp edge with the normal of the edge's own *sector* (Eq. 8
//!    over the faces between two sharp edges; both sides averaged would tilt
//!    each by half the crease's angle and bulge the surface next to it: test
//!    `a_creased_roof_stays_two_planes`); an edge that stays
//!    sharp through the step (infinitely sharp, semi-sharp with s ≥ 1 under
//!    uniform decay — the standard step would take its midpoint) by the
//!    **curve analogue** of the boundary: offsets projected on the normal
//!    plane of the sharp polygon's tangent at each end, μ scaled by
//!    [`BOUNDARY_MU_SCALE`] — an infinitely sharp crease's limit is the cubic
//!    B-spline of M¹'s crease polygon, as the boundary's, so the same ⁸⁄₉
//!    cancels its shrinkage (test `crease_limit_curve_follows_a_circle`: a
//!    crease ring sampled from a circle, 16/32/64 points, deviates 2.9e-4,
//!    1.8e-5, 1.2e-6 at μ = ⅜, O(h⁴), and 3.4e-3, 8.2e-4, 2.0e-4 at μ = ¼).
//!    The tangent at an end is that of its two sharp edges when it is a
//!    crease vertex (exactly two sharp edges, no vertex sharpness), else —
//!    corner, dart, three or more sharp edges, a tagged vertex — the edge's
//!    own direction, so that end adds nothing: corners are fixed, a dart's
//!    edge is straight at its free end. An edge whose sharpness runs out in
//!    the step (the standard step's blend s·midpoint + (1 − s)·smooth, s < 1)
//!    gets the same blend of the two choices, s·curve + (1 − s)·Eq. 9: the
//!    edge point moves continuously from the smooth to the sharp choice as
//!    the tag grows (under Chaikin a blend with s > 1 is taken as the curve).
//!    Normals (Eq. 8, or [`DengWangOptions::normals`]) are accepted at crease
//!    vertices too: the sharp edges do not read them, the smooth edges there
//!    do, with the normal of their sector where the vertex is on a crease.
//! 3. Vertex points: the limit row of old vertex i in M¹ (with M¹'s tags)
//!    is taken from `subdiv_stencil::limit_rows_loop_sharp` (the rows of
//!    `limit_matrix_loop_sharp` for the vertices a tag touches; the others
//!    keep the plain masks), by its
//!    [`RowKind`]: smooth as above; crease (an M¹ vertex with exactly two
//!    infinitely sharp edges and no other sharpness) the boundary's
//!    p¹ = (6p⁰ − e₋ − e₊)/4 over its two crease edge points; corner p¹ = p⁰;
//!    **general** (semi-sharp values left at i in M¹, darts: the composed
//!    limit after more levels) w_i p¹ + Σ_c w_c x_c = p⁰. A Loop limit row
//!    reads only the closed 1-ring of its vertex at every level (a vertex
//!    point reads its 1-ring, the edge points of its edges their ends and
//!    opposite corners, all in that ring), and in the triangle split the
//!    neighbours of an old vertex are edge points: so every row, general
//!    ones included, has the unknown p¹ alone among known edge points and is
//!    solved explicitly, p¹ = (p⁰ − Σ_c w_c x_c)/w_i — no coupled system. The
//!    report's `limit_rows` counts the interpolated vertices by row kind
//!    (`smooth`, `crease`, `corner`, `general`). Vertices outside the subset
//!    get the tagged Loop vertex point of M⁰ (crease (p₋ + 6p + p₊)/8,
//!    corner p, semi-sharp blends).
//! 4. UVs: M¹ carries the input's (triangulated) face-varying channel
//!    refined by one Loop level with s⁰ and the face-varying mode of the
//!    options (`subdiv_stencil::fvar::refine`), so [`Interpolant::surface`]
//!    writes UVs, with the input's seams (their halves, level by level). Under
//!    `linear-all` (the default) an old vertex keeps its UV at every level,
//!    so the surface's point of data point i has input vertex i's UV.
//!
//! Untagged input with `edge-and-corner` boundaries takes the plain masks of
//! M⁰'s topology and gives the bits it gave before tags existed; on tagged
//! input, vertex and edge points away from the tags use the same formulas
//! and are bit-identical to the untagged run. Darts (an infinitely sharp
//! crease ending inside): the limit this contract uses is the dart's exact
//! limit (`DartLimit::Exact`, the left eigenvector of the dart's own
//! subdivision matrix), so refining M¹ converges onto the data there too,
//! at ½ per level (test `refining_the_control_mesh_converges_onto_the_data`);
//! [`crate::SurfaceOptions::dart_limit`] = `DartLimit::SmoothMask` takes
//! OpenSubdiv's smooth limit mask instead, which misses the limit of
//! refinement by ~2e-4·d on a 12 × 8 torus.
//!
//! ```
//! use subdiv_interp::{deng_wang, DengWangOptions};
//! use subdiv_mesh::shapes;
//! let ico = shapes::icosahedron();
//! let result = deng_wang::interpolate(&ico, &DengWangOptions::default()).unwrap();
//! // M¹: 12 old vertices + 30 edge points, 80 triangles.
//! assert_eq!(result.control.topology().face_count(), 80);
//! let all = vec![true; 12];
//! let err = result.error(ico.positions(), &all, ico.bbox_diagonal());
//! assert!(err.max_rel <= 1e-14);
//! // Polygons are triangulated first: the cube's 6 quads become 12 triangles.
//! let cube = shapes::cube();
//! let result = deng_wang::interpolate(&cube, &DengWangOptions::default()).unwrap();
//! assert_eq!(result.control.topology().face_count(), 48);
//! assert_eq!(result.parameters.triangulated_faces, Some(6));
//! assert!(result.error(cube.positions(), &[true; 8], cube.bbox_diagonal()).max_rel <= 1e-14);
//!
//! // Tagged: the cube's top loop as an infinitely sharp crease, a corner below.
//! use subdiv_mesh::{EdgeTag, TagList, Tags, VertexTag, SHARPNESS_INFINITE};
//! let creases = [(4, 5), (5, 7), (7, 6), (6, 4)]
//!     .map(|(a, b)| EdgeTag { a, b, sharpness: SHARPNESS_INFINITE })
//!     .to_vec();
//! let corners = vec![VertexTag { vertex: 0, sharpness: SHARPNESS_INFINITE }];
//! let tags = Tags::from_list(cube.topology(), &TagList { creases, corners, ..Default::default() }).unwrap();
//! let cube = cube.with_tags(tags);
//! let result = deng_wang::interpolate(&cube, &DengWangOptions::default()).unwrap();
//! // The 4 crease edges became 8 halves in M¹, the corner stays.
//! assert_eq!((result.control.tags().crease_count(), result.control.tags().corner_count()), (8, 1));
//! assert_eq!(result.control.positions()[0], cube.positions()[0]);
//! assert_eq!(result.parameters.limit_rows.map(|rows| rows.crease), Some(4));
//! assert!(result.error(cube.positions(), &[true; 8], cube.bbox_diagonal()).max_rel <= 1e-14);
//! ```
//!
//! [`triangle_split`]: subdiv_mesh::refine::triangle_split
//! [corrections W1-W9]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w1
//! [correction W9]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w9
//! [correction W8]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w8
//! [correction W5]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w5
//! [correction W6]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w6
//! [correction W7]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w7
//! [correction W4]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w4
//! [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md

use crate::numeric::unit_direction;
use crate::report::RowCounts;
use crate::{seconds_since, CommonOptions, InterpError, Interpolant, LimitAssociation, Method, Parameter};
use glam::DVec3;
use subdiv_mesh::{triangulate, EdgeId, Mesh, Topology, VertexId};
use subdiv_rules::loop_scheme::{limit_mask, vertex_point_mask};
use subdiv_rules::{LoopBeta, VertexKind, VertexMask};
use subdiv_stencil::{
    fvar, limit_rows_loop_sharp, loop_subdivision, BoundaryInterpolation, EdgeStep, LevelSharpness, LimitRows, RowKind,
    Rule, Scheme, StencilError,
};

/// Default edge parameter μ of Eq. 9: ⅜, the value at which the first step
/// cancels Loop's shrinkage on a regular lattice (module docs; [correction W6]'s
/// ¼ puts the edge points, not the limit surface, on a sphere).
///
/// [correction W6]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w6
pub const DEFAULT_MU: f64 = 0.375;

/// Boundary and crease edges use BOUNDARY_MU_SCALE·μ: the cubic B-spline
/// curve's shrinkage is cancelled at ⅓ where Loop's interior is at ⅜ (module
/// docs).
pub const BOUNDARY_MU_SCALE: f64 = 8.0 / 9.0;

/// Range of μ the tests and the μ experiment cover; outside it a warning is given.
pub const TESTED_MU: (f64, f64) = (0.0, 0.5);

/// Smallest weight of the centre in a general limit row that the vertex
/// point is solved from (module docs, "Creases, corners and UVs"); the
/// weights of every row in the tests are ≥ 0.4 (the smooth row's 1 − kγ at
/// valence 3; test `old_vertex_limit_rows_read_only_edge_points`).
const MIN_CENTRE_WEIGHT: f64 = 1e-6;

/// Options of [`interpolate`].
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct DengWangOptions {
    /// Vertex subset, the bound `tol` on the measured error and the surface
    /// options (boundary, crease method, face-varying mode); the method
    /// solves nothing: `max_iter` and `solver` are not read.
    pub common: CommonOptions,
    /// The free parameter μ of Eq. 9 (default [`DEFAULT_MU`] = ⅜).
    pub mu: f64,
    /// Loop's β for the control mesh's scheme (Warren's by default).
    pub beta: LoopBeta,
    /// Per-vertex normals replacing Eq. 8 where `Some` (need not be unit
    /// length; must be finite and non-zero). One entry per input vertex.
    /// Crease and boundary edge points do not use normals; at a crease
    /// vertex its normal still steers the smooth edges (module docs).
    pub normals: Option<Vec<Option<DVec3>>>,
}

crate::options::common_setters!(DengWangOptions);

impl DengWangOptions {
    /// Sets μ of Eq. 9.
    pub fn with_mu(mut self, mu: f64) -> Self {
        self.mu = mu;
        self
    }

    /// Sets Loop's β.
    pub fn with_beta(mut self, beta: LoopBeta) -> Self {
        self.beta = beta;
        self
    }

    /// Sets the prescribed normals (one entry per input vertex; `None`: Eq. 8 everywhere).
    pub fn with_normals(mut self, normals: impl Into<Option<Vec<Option<DVec3>>>>) -> Self {
        self.normals = normals.into();
        self
    }
}

impl Default for DengWangOptions {
    fn default() -> Self {
        Self { common: CommonOptions::default(), mu: DEFAULT_MU, beta: LoopBeta::default(), normals: None }
    }
}

/// The Loop rule class of a vertex (`EDGE_AND_CORNER` boundaries).
fn kind(t: &Topology, v: VertexId) -> VertexKind {
    VertexKind::classify(t.is_boundary_vertex(v), t.vertex_face_count(v))
}

/// The edges at `v`, in fan order; on the boundary the closing edge last,
/// so the first and last are the two boundary edges.
fn edges_at(t: &Topology, v: VertexId) -> impl Iterator<Item = EdgeId> + '_ {
    let fan = t.vertex_fan(v);
    let closing = (t.is_boundary_vertex(v) && !fan.is_empty()).then(|| t.he_edge(t.he_prev(fan[fan.len() - 1])));
    fan.iter().map(|&h| t.he_edge(h)).chain(closing)
}

/// The other end of edge `e` seen from `v`.
fn other_end(t: &Topology, e: EdgeId, v: VertexId) -> VertexId {
    let (a, b) = t.edge_vertices(e);
    if a == v {
        b
    } else {
        a
    }
}

/// Σ over the edges at `v` of the mask's neighbour weight (interior or
/// boundary, by the edge's kind) times `point(edge)`.
fn ring_sum(t: &Topology, v: VertexId, mask: &VertexMask, point: impl Fn(EdgeId) -> DVec3) -> DVec3 {
    edges_at(t, v)
        .map(|e| {
            let w = if t.is_boundary_edge(e) { mask.boundary_neighbor } else { mask.interior_neighbor };
            w * point(e)
        })
        .sum()
}

/// Unit tangent at `v` of the sharp polygon through its crease ends `a` and
/// `b`: the sum of the unit vectors along its two sharp edges, from a to v
/// and from v to b (zero if they cancel). For a boundary vertex, whose ends
/// the rules give as (next, previous), this is the boundary polygon's
/// tangent (up to its sign, which no projection sees).
fn crease_tangent(p: &[DVec3], v: VertexId, (a, b): (VertexId, VertexId)) -> DVec3 {
    let pv = p[v.index()];
    ((p[a.index()] - pv).normalize_or_zero() + (pv - p[b.index()]).normalize_or_zero()).normalize_or_zero()
}

/// The normals of step 1: Eq. 8, replaced by the user's where given.
fn normals(mesh: &Mesh, user: Option<&[Option<DVec3>]>) -> Result<Vec<DVec3>, InterpError> {
    // Eq. (8), correction W5 (docs/REFERENCES.md): nᵢ = Σⱼ θⱼ nⱼ / ‖Σⱼ θⱼ nⱼ‖.
    let mut n = mesh.vertex_normals();
    let Some(user) = user else { return Ok(n) };
    if user.len() != n.len() {
        return Err(InterpError::invalid(
            Parameter::Normals,
            format!("{} normals given for a mesh of {} vertices", user.len(), n.len()),
        ));
    }
    for (v, given) in user.iter().enumerate() {
        if let Some(u) = *given {
            let unit = unit_direction(u).ok_or_else(|| {
                InterpError::invalid(
                    Parameter::Normals,
                    format!("the normal of vertex {v} ({u}) is zero or not finite"),
                )
            })?;
            n[v] = unit;
        }
    }
    Ok(n)
}

/// The normals the smooth edges of a tagged mesh see at their ends: Eq. 8 at
/// vertices without a crease; at a vertex with an interior sharp edge (a
/// crease or a semi-sharp edge that is sharp in the step) one normal **per
/// sector** — the run of its faces between two sharp edges —, Eq. 8 over
/// that sector's faces only. A crease vertex has two tangent planes, one per
/// side, and Eq. 8 over all its faces would tilt both by half the crease's
/// angle, bulging the smooth edge points next to the crease (measured on
/// fandisk: the surface's turning across the creases fell to 0.72 of the
/// input's, median, against 1.0 with sector normals). A user's normal at the
/// vertex is used for every sector. A dart has one sector: its Eq. 8 normal.
struct SectorNormals {
    /// Per vertex.
    vertex: Vec<DVec3>,
    /// Per half-edge leaving a vertex with sectors: the normal of the sector
    /// of its face (empty without any).
    sector: Vec<Option<DVec3>>,
}

impl SectorNormals {
    fn new(mesh: &Mesh, sharp: &LevelSharpness, vertex: Vec<DVec3>, user: Option<&[Option<DVec3>]>) -> Self {
        let t = mesh.topology();
        let sharp_edge = |e: EdgeId| !t.is_boundary_edge(e) && !matches!(sharp.edge_step(t, e), EdgeStep::Smooth);
        let mut sector = Vec::new();
        if sharp.is_untagged() {
            return Self { vertex, sector };
        }
        let p = mesh.positions();
        let mut local: Vec<(subdiv_mesh::HalfEdgeId, usize)> = Vec::new(); // fan half-edge, sector
        for v in t.vertices() {
            let fan = t.vertex_fan(v);
            let given = user.and_then(|u| u[v.index()]).is_some();
            if given || !fan.iter().any(|&h| sharp_edge(t.he_edge(h))) {
                continue;
            }
            if sector.is_empty() {
                sector = vec![None; t.half_edge_count()];
            }
            // Walk the fan: face k and face k + 1 share the other edge of face k at v
            // (the fan is in face order); a sharp one starts a new sector. A closed fan's
            // last run joins its first unless the edge between them is sharp.
            local.clear();
            let mut sums = vec![DVec3::ZERO; fan.len()];
            let mut current = 0;
            for (k, &h) in fan.iter().enumerate() {
                let (prev, next) = (t.he_from(t.he_prev(h)), t.he_to(h));
                let angle = subdiv_mesh::corner_angle(p[prev.index()], p[v.index()], p[next.index()]);
                sums[current] += angle * mesh.face_normal(t.he_face(h)); // Eq. (8) over the sector
                local.push((h, current));
                if k + 1 < fan.len() && sharp_edge(t.he_edge(t.he_prev(h))) {
                    current += 1;
                }
            }
            let closed = !t.is_boundary_vertex(v) && !sharp_edge(t.he_edge(t.he_prev(fan[fan.len() - 1])));
            if closed && current > 0 {
                let last = sums[current];
                sums[0] += last;
                local.iter_mut().filter(|(_, r)| *r == current).for_each(|(_, r)| *r = 0);
            }
            for &(h, r) in &local {
                sector[h.index()] = Some(unit_direction(sums[r]).unwrap_or(vertex[v.index()]));
            }
        }
        Self { vertex, sector }
    }

    /// The normal at end `v` of smooth edge `e`.
    fn at(&self, t: &Topology, e: EdgeId, v: VertexId) -> DVec3 {
        if !self.sector.is_empty() {
            let h = t.edge_half_edge(e);
            let h = if t.he_from(h) == v { Some(h) } else { t.he_twin(h) };
            if let Some(n) = h.and_then(|h| self.sector[h.index()]) {
                return n;
            }
        }
        self.vertex[v.index()]
    }
}

/// The E edge points of the modified first step (Eq. 9; boundary edges by
/// the curve analogue described in the module docs), in edge order, from
/// V positions and V unit normals, on an untagged mesh with `edge-and-corner`
/// boundaries: [`edge_points_sharp`] with [`LevelSharpness::plain`].
pub fn edge_points(t: &Topology, p: &[DVec3], normals: &[DVec3], mu: f64) -> Vec<DVec3> {
    edge_points_sharp(t, &LevelSharpness::plain(), p, normals, mu)
}

/// The E edge points of the modified first step on a level with the
/// sharpness `sharp` (its tags and boundary option), in edge order, from V
/// positions and V unit normals: smooth edges by Eq. 9; boundary and sharp
/// edges whose halves stay sharp by the curve analogue (module docs), with
/// the tangent of the sharp polygon at each end (at a corner, dart or
/// junction of three sharp edges the edge itself, so that end adds nothing);
/// an edge whose sharpness s runs out in the step (s < 1 under uniform
/// decay) by the blend min(s, 1)·curve + (1 − min(s, 1))·Eq. 9 (module docs,
/// "Creases, corners and UVs").
///
/// # Panics
/// If `p` or `normals` has fewer entries than `t` has vertices (a caller bug).
pub fn edge_points_sharp(t: &Topology, sharp: &LevelSharpness, p: &[DVec3], normals: &[DVec3], mu: f64) -> Vec<DVec3> {
    edge_points_with(t, sharp, p, |_, v| normals[v.index()], mu)
}

/// [`edge_points_sharp`] with the normal at end v of smooth edge e given by
/// `normal(e, v)` (a crease vertex's sector normal, [`SectorNormals`]).
fn edge_points_with(
    t: &Topology,
    sharp: &LevelSharpness,
    p: &[DVec3],
    normal: impl Fn(EdgeId, VertexId) -> DVec3,
    mu: f64,
) -> Vec<DVec3> {
    t.edges()
        .map(|e| {
            let (i, j) = t.edge_vertices(e);
            let (pi, pj) = (p[i.index()], p[j.index()]);
            let m = (pi + pj) / 2.0;
            let smooth = || {
                let (ni, nj) = (normal(e, i), normal(e, j));
                let (di, dj) = ((pi - m).dot(ni), (pj - m).dot(nj)); // Eq. (9): dᵢ = (pᵢ − (pᵢ+pⱼ)/2)·nᵢ
                m + mu * (di * ni + dj * nj) // Eq. (9): p = (pᵢ+pⱼ)/2 + μ(dᵢnᵢ + dⱼnⱼ)
            };
            let curve = || {
                // Curve analogue of Eq. (9): the offsets projected on each end's normal plane.
                let project = |v: VertexId, pv: DVec3| {
                    let tangent = match sharp.limit_rule(t, v) {
                        (Rule::Crease, Some(ends)) => crease_tangent(p, v, ends),
                        _ => (pj - pi).normalize_or_zero(),
                    };
                    let d = pv - m;
                    d - d.dot(tangent) * tangent
                };
                m + BOUNDARY_MU_SCALE * mu * (project(i, pi) + project(j, pj))
            };
            match sharp.edge_step(t, e) {
                EdgeStep::Smooth => smooth(),
                EdgeStep::Midpoint => curve(),
                EdgeStep::Blend(s) if s >= 1.0 => curve(),
                EdgeStep::Blend(s) => {
                    let s = s.max(0.0);
                    s * curve() + (1.0 - s) * smooth()
                }
            }
        })
        .collect()
}

/// Counts a row of kind `kind` (the report's `limit_rows`).
fn count_row(counts: &mut RowCounts, kind: RowKind) {
    match kind {
        RowKind::Smooth => counts.smooth += 1,
        RowKind::Crease => counts.crease += 1,
        RowKind::Corner => counts.corner += 1,
        RowKind::General => counts.general += 1,
    }
}

/// What the vertex points of M¹ are solved against: M¹'s tagged limit rows
/// of the touched vertices (`None` on an untagged `edge-and-corner` mesh,
/// whose rows are the plain masks of M⁰'s topology), and M⁰'s sharpness.
struct Level0<'a> {
    t: &'a Topology,
    sharp: &'a LevelSharpness,
    /// Per vertex of M⁰: touched by the tags or the boundary option (the
    /// plain masks do not fit it); empty when nothing is.
    touched: &'a [bool],
    /// M¹'s tagged limit rows of the touched interpolated vertices, and the
    /// row of each vertex (`u32::MAX` for none).
    limit: Option<(&'a LimitRows, &'a [u32])>,
}

/// Per vertex of M⁰: whether its limit row in M¹ or its vertex point may
/// differ from the plain masks — a tag on it or on one of its edges, or,
/// under a boundary option other than `edge-and-corner`, a boundary vertex.
/// Empty for a plain level.
fn touched_vertices(t: &Topology, sharp: &LevelSharpness) -> Vec<bool> {
    if sharp.is_plain() {
        return Vec::new();
    }
    let other_boundary = sharp.boundary() != BoundaryInterpolation::EdgeAndCorner;
    t.vertices().map(|v| !sharp.untouched(t, v) || (other_boundary && t.is_boundary_vertex(v))).collect()
}

/// M¹'s vertex points (the first V points of M¹), given M¹'s edge points:
/// solved so that the Loop limit of each interpolated vertex is its data
/// point ([correction W7], with M¹'s tags: module docs), the plain tagged Loop
/// vertex point elsewhere; with the kinds of the rows used.
///
/// [correction W7]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w7
fn vertex_points(
    level: &Level0<'_>,
    p: &[DVec3],
    edge: &[DVec3],
    interpolated: &[bool],
    beta: LoopBeta,
) -> Result<(Vec<DVec3>, RowCounts), InterpError> {
    let t = level.t;
    let nv = t.vertex_count();
    // Vertex points by the tagged rules, for the vertices the plain mask does not fit.
    let mut tagged_step: Option<Vec<DVec3>> = None;
    let mut counts = RowCounts::default();
    let mut positions = Vec::with_capacity(nv + edge.len());
    // A control point of M¹: old vertex c < V is unknown (it never enters a row but its own), edge point c ≥ V.
    let known = |c: usize| edge[c - nv];
    for v in t.vertices() {
        let p0 = p[v.index()];
        let k = t.valence(v);
        let untouched_plain = !level.touched.get(v.index()).copied().unwrap_or(false);
        let limit_row =
            level.limit.and_then(|(rows, of)| (of[v.index()] != u32::MAX).then(|| (rows, of[v.index()] as usize)));
        positions.push(if t.is_isolated(v) {
            p0
        } else if interpolated[v.index()] {
            // W7: solve the limit row of M¹ at v for p¹. Plain masks (Eq. 5; boundary (e₋ + 4p + e₊)/6; corner p):
            // interior p¹ = (p⁰ − γ Σ p_e) / (1 − kγ), boundary p¹ = (6p⁰ − e₋ − e₊)/4, corner p¹ = p⁰.
            let row_kind = match limit_row {
                None => match kind(t, v) {
                    VertexKind::Interior => RowKind::Smooth,
                    VertexKind::Boundary => RowKind::Crease,
                    VertexKind::Corner => RowKind::Corner,
                },
                Some((rows, i)) => rows.kinds[i],
            };
            count_row(&mut counts, row_kind);
            match (limit_row, row_kind) {
                (None, _) | (Some(_), RowKind::Smooth) => {
                    let mask = limit_mask(kind(t, v), k, beta);
                    (p0 - ring_sum(t, v, &mask, |e| edge[e.index()])) / mask.vertex
                }
                (Some(_), RowKind::Corner) => p0,
                (Some((rows, i)), RowKind::Crease) => {
                    // The crease ends in M¹ are the edge points of v's two sharp edges.
                    let mask = limit_mask(VertexKind::Boundary, k, beta);
                    let row = rows.s.outer_view(i).expect("a row per listed vertex");
                    let ends = row.indices().iter().map(|&c| c as usize).filter(|&c| c != v.index());
                    (p0 - ends.map(|c| mask.boundary_neighbor * known(c)).sum::<DVec3>()) / mask.vertex
                }
                (Some((rows, i)), RowKind::General) => general_vertex_point(rows, i, v, p0, nv, known)?,
            }
        } else if untouched_plain {
            // Not interpolated: the plain Loop vertex point on M⁰ (Eq. 1; boundary (p₋ + 6p + p₊)/8).
            let mask = vertex_point_mask(kind(t, v), k, beta);
            mask.vertex * p0 + ring_sum(t, v, &mask, |e| p[other_end(t, e, v).index()])
        } else {
            // Not interpolated, touched by a tag: the tagged Loop vertex point on M⁰.
            if tagged_step.is_none() {
                tagged_step = Some(loop_subdivision::step_points_sharp(t, level.sharp, beta, p)?);
            }
            tagged_step.as_ref().expect("just computed")[v.index()]
        });
    }
    positions.extend_from_slice(edge);
    Ok((positions, counts))
}

/// The vertex point of old vertex `v` from its general limit row in M¹
/// (the limit masks after the levels its semi-sharp values or its dart
/// need): w_v p¹ + Σ_c w_c x_c = p⁰ over M¹'s closed 1-ring of v, whose
/// other vertices are all edge points (known); so p¹ = (p⁰ − Σ_c w_c x_c)/w_v.
fn general_vertex_point(
    rows: &LimitRows,
    i: usize,
    v: VertexId,
    p0: DVec3,
    nv: usize,
    known: impl Fn(usize) -> DVec3,
) -> Result<DVec3, InterpError> {
    let row = rows.s.outer_view(i).expect("a row per listed vertex");
    let d = rows.d[i];
    let mut centre = 0.0;
    let mut rest = DVec3::ZERO;
    for (c, &w) in row.iter() {
        if c == v.index() {
            centre = d * w;
        } else if c < nv {
            // Cannot happen: a Loop limit row reads only the closed 1-ring of its vertex, and in the
            // triangle split an old vertex has edge points as its only neighbours.
            return Err(InterpError::UnsupportedMesh {
                method: Method::DengWang.name(),
                reason: format!("the limit row of vertex {v} in M¹ reads old vertex {c}, outside its 1-ring"),
                suggestion: "cheng, which solves the whole tagged limit matrix".into(),
            });
        } else {
            rest += (d * w) * known(c);
        }
    }
    if centre.is_nan() || centre.abs() < MIN_CENTRE_WEIGHT {
        return Err(InterpError::UnsupportedMesh {
            method: Method::DengWang.name(),
            reason: format!(
                "the limit of vertex {v} in M¹ with its tags does not depend on its own control point (weight \
                 {centre:e}), so no vertex point interpolates it"
            ),
            suggestion: "other sharpness values at that vertex".into(),
        });
    }
    Ok((p0 - rest) / centre)
}

/// A face-varying error of the control mesh's UVs, as the crate reports stencil errors.
fn uv_error(e: fvar::FVarError) -> InterpError {
    match e {
        fvar::FVarError::Stencil(e) => InterpError::Stencil(e),
        other => InterpError::Stencil(StencilError::FaceVarying(other.to_string())),
    }
}

/// Interpolates the vertices of `mesh` (any polygons, open or closed, with
/// or without tags and UVs; non-triangles are triangulated first, module
/// docs) with the Loop limit surface of the modified first refined mesh M¹
/// with its tags.
///
/// With M⁰ the triangulation of `mesh` (the input itself for a triangle
/// mesh; same vertices), the control mesh has V + E vertices
/// ([`triangle_split`](subdiv_mesh::refine::triangle_split) numbering, E the
/// edges of M⁰) and 4F triangles (F the triangles of M⁰), the tags of M⁰
/// decayed by one level and M⁰'s UVs refined by one level; vertex i < V has
/// input vertex i as its Loop limit point with those tags and
/// [`CommonOptions::surface`] ("Creases, corners and UVs").
///
/// # Errors
/// As every method ([`crate`] docs, "The numeric rule": an extreme μ fails
/// the measured-error check); [`InterpError::InvalidParameter`] for a μ that
/// is not finite or a bad normal; [`InterpError::UnsupportedMesh`] for a
/// polygon without a valid triangulation, or a vertex whose tagged limit
/// does not depend on its own control point (none is known).
pub fn interpolate(mesh: &Mesh, opts: &DengWangOptions) -> Result<Interpolant, InterpError> {
    if !opts.mu.is_finite() {
        return Err(InterpError::invalid(Parameter::Mu, format!("Deng-Wang μ = {} is not finite", opts.mu)));
    }
    crate::numeric::run(Method::DengWang, mesh, Some(&opts.common), |mesh, interpolated| {
        interpolate_prepared(mesh, interpolated, opts)
    })
}

/// [`interpolate`] on the prepared (scaled) mesh and interpolated set.
pub(crate) fn interpolate_prepared(
    mesh: &Mesh,
    interpolated: Vec<bool>,
    opts: &DengWangOptions,
) -> Result<Interpolant, InterpError> {
    let start = std::time::Instant::now();
    let triangulation =
        triangulate(mesh).map_err(|e| crate::preconditions::unsupported(Method::DengWang, mesh, e.to_string()))?;
    let triangulate_seconds = seconds_since(start);
    let t = triangulation.mesh.topology();
    let mut warnings = Vec::new();
    if triangulation.split_faces > 0 {
        let triangles = t.face_count() - (mesh.topology().face_count() - triangulation.split_faces);
        warnings.push(format!(
            "the mesh has {} non-triangular faces; they were triangulated ({triangles} triangles) before Loop \
             interpolation",
            triangulation.split_faces
        ));
    }
    if !(TESTED_MU.0..=TESTED_MU.1).contains(&opts.mu) {
        warnings.push(format!(
            "μ = {} is outside [{}, {}], the range tested for fair surfaces (the surface still interpolates)",
            opts.mu, TESTED_MU.0, TESTED_MU.1
        ));
    }

    // M¹'s connectivity and tags, and with tags M¹'s limit rows (setup, with the triangulation), do
    // not depend on the geometry: built on one core while the other computes the normals and the edge
    // points (solve).
    let sharp = opts.common.surface.sharpness(triangulation.mesh.tags());
    let plain = sharp.is_plain();
    let touched = touched_vertices(t, &sharp);
    let scheme = Scheme::Loop(opts.beta);
    let start = std::time::Instant::now();
    let (level1, edges) = rayon::join(
        || -> Result<_, InterpError> {
            let split = scheme.rules().split(t, &sharp)?;
            // The tagged limit rows of M¹, for the interpolated vertices the tags or the boundary
            // option touch only (old vertex v is vertex v of M¹); the others take the plain masks.
            let rows: Vec<u32> = (0..t.vertex_count() as u32)
                .filter(|&v| touched.get(v as usize).copied().unwrap_or(false) && interpolated[v as usize])
                .filter(|&v| !t.is_isolated(VertexId(v)))
                .collect();
            let limit = if plain || rows.is_empty() {
                None
            } else {
                Some(limit_rows_loop_sharp(&split.topology, &split.sharpness, opts.beta, &rows)?)
            };
            Ok((split, limit, seconds_since(start)))
        },
        || -> Result<_, InterpError> {
            let start = std::time::Instant::now();
            let n = normals(&triangulation.mesh, opts.normals.as_deref())?;
            let n = SectorNormals::new(&triangulation.mesh, &sharp, n, opts.normals.as_deref());
            let edge = edge_points_with(t, &sharp, mesh.positions(), |e, v| n.at(t, e, v), opts.mu);
            Ok((edge, seconds_since(start)))
        },
    );
    let ((split, limit, split_seconds), (edge, edge_seconds)) = (level1?, edges?);
    let start = std::time::Instant::now();
    let mut row_of = Vec::new();
    if let Some(rows) = &limit {
        row_of = vec![u32::MAX; t.vertex_count()];
        rows.vertices.iter().enumerate().for_each(|(i, &v)| row_of[v as usize] = i as u32);
    }
    let level = Level0 { t, sharp: &sharp, touched: &touched, limit: limit.as_ref().map(|rows| (rows, &row_of[..])) };
    let (positions, rows) = vertex_points(&level, mesh.positions(), &edge, &interpolated, opts.beta)?;
    // The input's UVs (triangulated) refined by one Loop level with M⁰'s tags, as every level after it.
    let uvs = match triangulation.mesh.uvs() {
        Some(channel) => Some(
            fvar::refine(t, &sharp, &split.topology, scheme, opts.common.surface.fvar, channel).map_err(uv_error)?,
        ),
        None => None,
    };
    let solve_seconds = edge_seconds + seconds_since(start);
    let setup_seconds = triangulate_seconds + split_seconds;
    let tags = split.sharpness.tags(&split.topology);
    let user_normals = opts.normals.as_ref().map_or(0, |u| u.iter().flatten().count());
    let beta = match opts.beta {
        LoopBeta::Warren => "warren",
        LoopBeta::Loop => "loop",
    };
    let parameters = crate::Parameters {
        mu: Some(opts.mu),
        beta: Some(beta.to_string()),
        user_normals: Some(user_normals),
        triangulated_faces: Some(triangulation.split_faces),
        limit_rows: Some(rows),
        control_creases: Some(tags.crease_count()),
        control_corners: Some(tags.corner_count()),
        ..Default::default()
    };
    let control = Mesh::from_topology(split.topology, positions)
        .with_tags(tags)
        .with_uvs(uvs)
        .expect("the refined channel has one value per face corner of M¹");
    Ok(Interpolant {
        surface_options: opts.common.surface,
        method: Method::DengWang,
        control,
        scheme: Scheme::Loop(opts.beta),
        interpolated,
        association: LimitAssociation::ControlVertex,
        solve: None,
        setup_seconds,
        solve_seconds,
        warnings,
        parameters,
        measured_error: None,
    })
}
