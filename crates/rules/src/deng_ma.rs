//! Deng-Ma's interpolatory scheme derived from Doo-Sabin: the moved vertices
//! and the tension ω_P (global or displacement-safe variable), on closed and
//! open meshes, with infinitely sharp creases and corners.
//!
//! Source: Deng & Ma 2011 as reproduced in Mahalingam & Koneru's report (DM11 in [references]) §3.3 (moved
//! vertices) and §3.4 (variable tension), with [correction D2] (Q̄ᵢ = **P** + …) and
//! [correction D5] (the missing constant C and the cyclic index).
//!
//! # The rule at one old vertex P (§3.3)
//! 1. Qᵢ, i = 1…m: the Doo-Sabin images of P in its m faces, in fan order
//!    ([`crate::doo_sabin_weights`]); G = (Q₁ + … + Q_m)/m.
//! 2. Moved vertices Q̄ᵢ = P + ω_P(Qᵢ − G) ([`moved_images`]). Their centroid
//!    is P itself, which is why the scheme keeps every old vertex.
//! 3. The refined mesh connects like Catmull-Clark: the new face point of a
//!    face is the centroid of the moved vertices of its corners; the new edge
//!    point of an edge is the centroid of the four moved vertices of its
//!    E-face (the images of both endpoints in both faces); old vertices stay
//!    ([`crate::centroid`]).
//!
//! ω_P = 1 is the surface analogue of the 4-point curve scheme with ω = 1/16
//! ([correction D4]: in the curve picture Q − G = (P_{2i} − P_{2i−1})/2, so
//! ω_P = 16ω); the test `regular_grid_reproduces_four_point` checks it.
//!
//! # Variable tension (§3.4)
//! Number P's neighbours P₁…P_m so that face i contains the edges PPᵢ and
//! PPᵢ₊₁ (the report does not define Pᵢ; this is the reading under which its
//! formula bounds the moved vertices by the face's own edges). Then, with
//! indices mod m ([correction D5]: the printed `(i+1)%4` / `%m` with 1-based
//! indices means the cyclic successor) and the inner minimum over i = 1…m,
//!
//! ω_P = min{ 1, λ/max(m, 4) · minᵢ [ min(‖Pᵢ − P‖, ‖Pᵢ₊₁ − P‖) / ‖Qᵢ − G‖ ] },  0 < λ ≤ 1
//!
//! ([`variable_omega`]). Consequently every moved vertex satisfies
//! ω_P‖Qᵢ − G‖ ≤ λ/4 · min(‖Pᵢ − P‖, ‖Pᵢ₊₁ − P‖).
//!
//! # Displacement safety
//! The report calls the scheme displacement-safe if, for a constant
//! 0 < C < 1, every new edge point E and face point F satisfy
//! d_E = ‖E − (P₁+P₂)/2‖ ≤ C‖P₁ − P₂‖ and d_F = ‖F − centroid‖ ≤ C·min (edge
//! lengths of the face). The printed face condition lacks C ([correction D5]); here
//! C is explicit ([`DisplacementBound`]). From the bound above, the variable
//! ω_P gives d_E ≤ (λ/4)‖P₁ − P₂‖, so the edge condition holds with C = λ/4;
//! for faces it gives d_F ≤ (λ/4)·(longest edge of the face), which implies
//! the face condition only when the face's edges are comparable in length —
//! the report's face condition is not guaranteed by its own ω_P.
//!
//! # Open meshes (our construction, beyond the report)
//! The report treats closed meshes only. On an open mesh every boundary loop
//! is refined by the 4-point curve rule with the surface's tension, and only
//! the moved images of boundary vertices change; every other point is the
//! report's rule. The boundary vertices stay, like all old vertices.
//!
//! 1. **Corners cut the loops into pieces.** A boundary vertex in one face
//!    (valence 2) is a corner. Each boundary loop is cut at its corners into
//!    open pieces (a loop without corners stays a closed polygon).
//! 2. **Boundary edge points: the 4-point rule along the piece** (Dyn, Levin &
//!    Gregory 1987; Deng & Ma §3.1 step 4 and §3.1.1 with the sign of
//!    [correction D1]): the new point of a boundary edge PᵢPᵢ₊₁ is
//!    ½(Pᵢ + Pᵢ₊₁) + ωᵢ(Pᵢ₊₁ − Pᵢ₋₁) + ωᵢ₊₁(Pᵢ − Pᵢ₊₂), the curve tension
//!    ωᵢ = ω_P/16 ([correction D4]). At a piece end P₀ (a corner) the missing
//!    neighbour is the linear phantom P₋₁ = 2P₀ − P₁, the open end rule of
//!    [`crate::curves::four_point`]. The point depends on the piece's
//!    vertices only, so the boundary of the level-k surface is the boundary
//!    polygon refined k times by the curve rule.
//! 3. **Moved images of a boundary vertex.** For P on the boundary with
//!    boundary neighbours P₋, P₊, the centre G is not the centroid of its
//!    images in its faces (the fan is open: that centroid lies inside the
//!    surface), but the centre the curve scheme uses, the centroid of P's two
//!    Chaikin images ¾P + ¼P₋ and ¾P + ¼P₊ on the boundary polygon:
//!    G = (P₋ + 6P + P₊)/8 ([`boundary_centre`]). At a corner both pieces end
//!    at P and the phantom stands for the missing neighbour, which gives
//!    G = (2P − P₊ + 6P + P₊)/8 = P. The moved images are Q̄ᵢ = P + ω_P(Qᵢ − G)
//!    in every face of P ([`moved_images_about`]); the face points of faces at
//!    the boundary and the edge points of interior edges with a boundary end
//!    are the report's centroids of these moved images.
//!
//! **Why this G.** (a) It is the curve's own: the 4-point scheme is derived
//! (§3.1) from the moved Chaikin points P + ω_P(c± − G) with G their centroid,
//! and the boundary edge point of step 2 is the mean of the two curve moved
//! images of its ends with exactly this G. A boundary vertex has one centre
//! for its curve images and its face images. (b) On a regular quad grid it is
//! the report's closed rule on the grid extended across the boundary by one
//! ring of ghost vertices, linearly extrapolated (P(i, −1) = 2P(i, 0) − P(i, 1);
//! corner ghosts extrapolated in both directions): the images around a vertex
//! are tensor products cₛ ⊗ c_t of Chaikin points, so their centroid is m ⊗ m
//! with m = (P₋ + 6P + P₊)/8 in each direction; across the boundary the ghost
//! gives m = (2P₀ − P₁ + 6P₀ + P₁)/8 = P₀, hence G = (P₋ + 6P + P₊)/8 along
//! the boundary, and G = P at a corner. Across a boundary edge the two ghost
//! images average with the real ones to the boundary row's Chaikin points, so
//! the ghost grid's boundary edge point is step 2's 4-point point. This holds
//! for any data (test `open_grid_is_the_closed_rule_on_a_ghost_extended_grid`),
//! and where the report's rule on a regular grid is the tensor product of
//! 4-point rules — data additive over the grid, P(i, j) = Aᵢ + Bⱼ, e.g. a
//! planar grid with arbitrary row and column spacing plus heights aᵢ + bⱼ —
//! the open rule is the tensor product of the open 4-point rules with their
//! phantom ends, up to the boundary. (c) Only boundary data enters G, so the
//! boundary rule of step 2 and the moved images agree without the curve
//! seeing the interior.
//!
//! **Smoothness.** At a piece end the 4-point rule with the linear phantom has
//! the local subdivision matrix (P₀, P₁, P₂, P₃ → P₀, edge point, P₁, edge
//! point) with eigenvalues 1, ½, 2ω and −ω (⅛ and −1/16 for ω = 1/16): for
//! every ω ∈ (0, 1/8) a simple subdominant ½ with a linear eigenvector, so the
//! curve is C¹ up to the corner and reaches it with a tangent. Next to the
//! boundary the surface is measured, not proved
//! (`crates/interp/tests/integration/deng_ma.rs`, `smoothness_next_to_the_boundary`): with
//! ω = 1 the max dihedral angle between faces at the boundary shrinks by
//! 0.56-0.74 per level on the open fixtures, as inside, where a crease along
//! the boundary would keep it constant. The report's own G, the centroid of
//! the open fan's images, fails this: its offsets all point into the surface
//! and fold it over at the boundary (dihedral angles near 180° at every level
//! on the Nefertiti scan).
//!
//! **Variable tension.** A boundary vertex plays two roles. As a vertex of the
//! boundary curve its tension may depend on the boundary only (step 2): we
//! apply §3.4 to the boundary polygon seen as a 1-D mesh — its edges are the
//! faces and the Chaikin points the Doo-Sabin images (Chaikin's scheme is
//! the 1-D Doo-Sabin), m = 2 so max(m, 4) = 4 — which gives
//! ω_P = min{1, 2λ·min(‖P₋ − P‖, ‖P₊ − P‖)/‖P₊ − P₋‖}, and λ at a corner (with
//! the phantom the spread is a quarter of the reach for any edge length)
//! ([`curve_omega`]); the curve tension is ω_P/16. Then every boundary edge
//! point satisfies d_E ≤ ωᵢ‖Pᵢ₊₁ − Pᵢ₋₁‖ + ωᵢ₊₁‖Pᵢ₊₂ − Pᵢ‖ ≤ (λ/4)‖Pᵢ − Pᵢ₊₁‖,
//! the interior edges' C = λ/4. As the centre of moved images in its faces
//! the vertex takes ω_P = min(curve ω_P, §3.4 over its faces about the G of
//! step 3) ([`Tension::boundary_omega`]): the surface is never tenser than its
//! boundary there, and each moved image keeps ω_P‖Qᵢ − G‖ ≤ (λ/4)·(shorter
//! edge of face i at P), so every interior edge point keeps d_E ≤ (λ/4)‖P₁ −
//! P₂‖ next to the boundary too.
//!
//! # Creases and corners (our construction, beyond the report)
//! The open-mesh rule above, generalised from the boundary to the **sharp
//! polygon**: the boundary edges and the infinitely sharp creases (sharpness
//! ≥ 10). Conceptually the mesh is cut along its creases and each side gets
//! the open-mesh rule, with its boundary there; the sides share the crease's
//! points, so the refined mesh stays one, glued along the crease.
//!
//! 1. **Classes.** A vertex is a **corner** if its corner sharpness is ≥ 10
//!    (a tag, or, under OpenSubdiv's `edge-and-corner` boundaries, a boundary
//!    vertex in one face: the corner of "Open meshes") or it has three or
//!    more sharp edges (a crease ending on the boundary makes one); a
//!    **crease vertex** if it has two (a boundary vertex with its two
//!    boundary edges is one); a **dart** with one; smooth with none. Under
//!    `edge-only` (and `none`) a boundary vertex in one face is a crease
//!    vertex of its loop, so a loop without other corners stays closed.
//! 2. **Sharp edge points.** Corners and darts cut the sharp polygon into
//!    open pieces; a closed loop through crease vertices only stays closed.
//!    The new point of a sharp edge is the 4-point point of its piece
//!    ("Open meshes", step 2), with the linear phantom 2P₀ − P₁ beyond a
//!    piece end. It reads the piece's vertices only, so both sides of a
//!    crease get the same point, and the sharp polygon of level k is the
//!    input's sharp polygon refined k times by the curve rule (exactly:
//!    `crates/stencil/tests/integration/deng_ma_creases.rs`,
//!    `refined_crease_polygon_is_the_four_point_refinement_of_the_input_polygon`).
//! 3. **Centres.** A crease vertex's moved images, in every face at it, are
//!    taken about the centre of its curve, G = (P₋ + 6P + P₊)/8 with P₋, P₊
//!    its two sharp neighbours ([`boundary_centre`]); a corner's about
//!    G = P; a smooth vertex's and a dart's about the centroid of its images
//!    (§3.3). Face points and the points of smooth edges are the report's
//!    centroids of moved images.
//! 4. **Darts.** The crease piece ends at the dart as at a corner (linear
//!    phantom, the curve tension of a piece end), but the dart's own images
//!    are the smooth vertex's: one sharp edge does not cut the fan (the faces
//!    on its two sides are still joined round the dart), so there is no side
//!    whose boundary the dart would be. The crease curve reaches the dart
//!    along the tangent of its last leg and fades into the smooth surface.
//! 5. **Variable tension, per sector.** The sharp edges at a vertex cut its
//!    fan into sectors, the faces between two consecutive sharp edges (an
//!    interior fan with fewer than two sharp edges is one closed sector). The
//!    moved images in a sector take the boundary vertex's ω_P of "Open
//!    meshes" on that sector alone, min([`curve_omega`] on the sharp polygon,
//!    §3.4 over the sector's faces about G) ([`Tension::boundary_omega`] with
//!    the sector's neighbours and images): the ω_P the vertex has as a
//!    boundary vertex of the cut mesh. The curve tension is [`curve_omega`]/16
//!    on the sharp polygon, λ/16 at piece ends (corners and darts).
//! 6. **Refined tags.** The two halves of a sharp edge stay infinitely sharp,
//!    corner tags stay, so each sharp edge's new point is a crease vertex and
//!    the rules apply again at every level; face points and the points of
//!    smooth edges are smooth.
//!
//! **Why.** (a) *A crease is a cut.* Every new point reads either one piece of
//! the sharp polygon (sharp edge points) or the faces of one side, with moved
//! images about centres taken from the sharp polygon and, with the variable
//! tension, ω_P from that side's sector. So the tagged step is the untagged
//! step on the mesh cut along its sharp edges, each side an open mesh, glued
//! along the shared curve points (test `a_crease_refines_as_the_mesh_cut_along_it`:
//! a grid cut along a row, the cube's top loop, a torus meridian, to 1e-13).
//! Everything "Open meshes" shows holds on each side: the ghost-grid
//! equivalence, the C¹ end rule of the curve, displacement safety (d_E ≤
//! (λ/4)‖P₁ − P₂‖ for every edge point, sharp or smooth). (b) *The surface is
//! creased*: the sides meet along the 4-point curve, each with its own
//! tangent plane. A roof folded along a crease keeps both planes and its
//! dihedral angle exactly at every level; a cube with its top loop sharp
//! keeps a flat top and 86°-92° across the crease at levels 1-4, where the
//! untagged cube's largest angle falls to 29°-66°. (c) *Untagged meshes do not
//! move*: the sharp polygon is the boundary and the rules are "Open meshes",
//! bit for bit under `edge-and-corner`.
//!
//! A corner with no sharp edge is a tip (G = P keeps its images' offsets
//! from P instead of their spread about their centroid): at a pyramid's
//! tagged apex the mean slope to its refined neighbours grows from 1 to
//! 1.1-1.8 in five levels, as Catmull-Clark's corner grows to 2.6, where the
//! untagged apex flattens to 0.1-0.5.
//!
//! **Semi-sharp creases** (0 < s < 10) have no rule here. OpenSubdiv blends
//! the smooth and the crease masks for the first ⌈s⌉ levels; the same could
//! be defined here (a sharp edge point s·(4-point point) + (1 − s)·(E-face
//! centroid), a centre between the curve's and the centroid), but neither
//! the report nor a peer has it to check against, so the stencil crate
//! refuses such tags rather than give them a meaning of its own.
//!
//! [correction D2]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d2
//! [correction D4]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d4
//! [correction D5]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d5
//! [correction D1]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d1
//! [references]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md

use crate::constants::DEFAULT_DENG_MA_OMEGA;
use crate::doo_sabin::BOUNDARY_EDGE_POINT;
use crate::vec3::{add, centroid, dist, lin2, scale, sub, Point3};

/// The 4-point tension ω that corresponds to the surface tension ω_P = 1:
/// ω = ω_P/16 ([correction D4]).
///
/// [correction D4]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d4
pub const CURVE_TENSION_PER_OMEGA: f64 = 1.0 / 16.0;

/// Weights `[P₋, P, P₊]` of the centre G of a boundary vertex P in two or
/// more faces (module docs, "Open meshes", step 3): the mean of P's Chaikin
/// images ¾P + ¼P₋ and ¾P + ¼P₊ on the boundary polygon, (P₋ + 6P + P₊)/8 —
/// the same weights as the Doo-Sabin boundary curve point.
pub const BOUNDARY_CENTRE: [f64; 3] =
    [BOUNDARY_EDGE_POINT.far / 2.0, BOUNDARY_EDGE_POINT.near, BOUNDARY_EDGE_POINT.far / 2.0];

/// The tension of the Deng-Ma scheme.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tension {
    /// One ω for every vertex, 0 < ω ≤ 1 (§3.3). ω = 1 is the default.
    Global(f64),
    /// The displacement-safe ω_P of §3.4 with shape parameter λ ∈ (0, 1].
    Variable {
        /// λ of §3.4: smaller values pull the surface towards the mesh.
        lambda: f64,
    },
}

impl Default for Tension {
    fn default() -> Self {
        Self::Global(DEFAULT_DENG_MA_OMEGA)
    }
}

impl Tension {
    /// ω_P at vertex P with neighbours `ring` and Doo-Sabin images `images`
    /// (see [`variable_omega`] for the layout).
    pub fn omega(&self, p: Point3, ring: &[Point3], images: &[Point3]) -> f64 {
        match *self {
            Self::Global(omega) => omega,
            Self::Variable { lambda } => variable_omega(p, ring, images, lambda),
        }
    }

    /// The 4-point tension of boundary (or crease) vertex P on its curve
    /// (module docs, "Open meshes", "Creases and corners"): ω/16 with the
    /// global ω, [`curve_omega`]/16 with the variable one ([correction D4]).
    /// `neighbours` as in [`boundary_centre`] (`None` at a piece end: a
    /// corner or a dart).
    ///
    /// [correction D4]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d4
    pub fn curve_tension(&self, p: Point3, neighbours: Option<(Point3, Point3)>) -> f64 {
        CURVE_TENSION_PER_OMEGA
            * match *self {
                Self::Global(omega) => omega,
                Self::Variable { lambda } => curve_omega(p, neighbours, lambda),
            }
    }

    /// ω_P of the moved images of boundary vertex P in its faces: the global
    /// ω, or min([`curve_omega`], [`variable_omega_about`] about `g`), g the
    /// vertex's [`boundary_centre`] (module docs, "Variable tension" under
    /// "Open meshes"). `ring` and `images` as in [`variable_omega`] (open fan:
    /// one more neighbour than images); for a vertex whose sharp edges cut its
    /// fan, those of one sector ("Creases and corners", step 5).
    pub fn boundary_omega(
        &self,
        p: Point3,
        neighbours: Option<(Point3, Point3)>,
        ring: &[Point3],
        images: &[Point3],
        g: Point3,
    ) -> f64 {
        match *self {
            Self::Global(omega) => omega,
            Self::Variable { lambda } => {
                curve_omega(p, neighbours, lambda).min(variable_omega_about(p, ring, images, g, lambda))
            }
        }
    }
}

/// The centre G of boundary vertex P (module docs, "Open meshes", step 3),
/// or of a crease vertex ("Creases and corners", step 3): (P₋ + 6P + P₊)/8
/// with `neighbours = Some((P₋, P₊))`, its neighbours along the boundary loop
/// or the crease; P itself at a corner (`None`: every piece through P ends
/// at it).
///
/// ```
/// use subdiv_rules::deng_ma::boundary_centre;
/// let (prev, p, next) = ([-1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.8]);
/// assert_eq!(boundary_centre(p, Some((prev, next))), [0.0, 0.0, 0.1]);
/// assert_eq!(boundary_centre(p, None), p);
/// ```
pub fn boundary_centre(p: Point3, neighbours: Option<(Point3, Point3)>) -> Point3 {
    match neighbours {
        None => p, // both pieces end at P: G = (2P − P₊ + 6P + P₊)/8 = P
        Some((prev, next)) => {
            let [w_prev, w_p, w_next] = BOUNDARY_CENTRE;
            add(lin2(w_prev, prev, w_p, p), scale(next, w_next)) // G = ½(¾P + ¼P₋ + ¾P + ¼P₊)
        }
    }
}

/// ω_P of boundary (or crease) vertex P as a vertex of its curve: §3.4
/// applied to the boundary polygon (the sharp polygon) as a 1-D mesh, its
/// edges as faces and P's two Chaikin images as the Doo-Sabin images (module
/// docs, "Variable tension" under "Open meshes"):
/// ω_P = min{1, 2λ·min(‖P₋ − P‖, ‖P₊ − P‖)/‖P₊ − P₋‖}, or λ at a piece end
/// (`neighbours = None`: a corner or a dart). It reads the curve only.
pub fn curve_omega(p: Point3, neighbours: Option<(Point3, Point3)>, lambda: f64) -> f64 {
    let Some((prev, next)) = neighbours else {
        // A piece end with the phantom 2P − P₊: reach ‖P₊ − P‖, spread ‖P₊ − P‖/4.
        return lambda.min(1.0);
    };
    // Chaikin images ¾P + ¼P±: their spread about G is ‖P₊ − P₋‖/8.
    let spread = dist(next, prev) / 8.0;
    if spread == 0.0 {
        return 1.0; // Qᵢ = G: no constraint (as in variable_omega)
    }
    let reach = dist(prev, p).min(dist(next, p));
    (lambda / 4.0 * reach / spread).min(1.0) // §3.4 with m = 2: max(m, 4) = 4
}

/// The variable tension ω_P of §3.4 (formula in the module docs, indices as
/// corrected by [correction D5]).
///
/// `images[i]` is Qᵢ, the Doo-Sabin image of P in face i, and face i contains
/// the edges P–`ring[i]` and P–`ring[i+1]`. For an interior vertex
/// `ring.len() == images.len()` and the index wraps; for a boundary vertex
/// (open fan) `ring.len() == images.len() + 1` and it does not. m in
/// max(m, 4) is the number of faces. Faces whose image coincides with G
/// (Qᵢ = G) do not constrain ω_P.
///
/// # Panics
/// If `images` is empty or `ring` has neither length.
///
/// [correction D5]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d5
pub fn variable_omega(p: Point3, ring: &[Point3], images: &[Point3], lambda: f64) -> f64 {
    assert!(!images.is_empty(), "a vertex with no faces");
    variable_omega_about(p, ring, images, centroid(images), lambda)
}

/// [`variable_omega`] with the spreads ‖Qᵢ − G‖ measured about a given centre
/// `g` instead of the images' centroid: the §3.4 formula for moved images
/// Q̄ᵢ = P + ω_P(Qᵢ − g), such as those of a boundary vertex about its
/// [`boundary_centre`]. Each moved image then satisfies
/// ω_P‖Qᵢ − g‖ ≤ λ/4 · min(‖Pᵢ − P‖, ‖Pᵢ₊₁ − P‖).
///
/// # Panics
/// As [`variable_omega`].
pub fn variable_omega_about(p: Point3, ring: &[Point3], images: &[Point3], g: Point3, lambda: f64) -> f64 {
    let m = images.len();
    assert!(m > 0, "a vertex with no faces");
    assert!(ring.len() == m || ring.len() == m + 1, "{} neighbours do not fit {m} faces", ring.len());
    let mut ratio = f64::INFINITY;
    for (i, &q) in images.iter().enumerate() {
        let spread = dist(q, g);
        if spread == 0.0 {
            continue;
        }
        let next = ring[(i + 1) % ring.len()]; // D5: P_{(i mod m)+1}, cyclic
        let reach = dist(ring[i], p).min(dist(next, p)); // §3.4: min{‖P_i − P‖, ‖P_{i+1} − P‖}
        ratio = ratio.min(reach / spread); // §3.4: min over i = 1..m of the quotients
    }
    let m_eff = m.max(4) as f64;
    (lambda / m_eff * ratio).min(1.0) // §3.4: ω_P = min{1, λ/max(m,4) · min{…}}
}

/// Writes the moved vertices Q̄ᵢ = P + ω(Qᵢ − G), G the centroid of `images`
/// (§3.3 with [correction D2]: the printed "Pᵢ +" is P).
///
/// ```
/// use subdiv_rules::deng_ma::moved_images;
/// let p = [0.0, 0.0, 1.0];
/// let q = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]];
/// let mut moved = [[0.0; 3]; 4];
/// moved_images(p, &q, 0.5, &mut moved);
/// assert_eq!(moved[0], [0.5, 0.0, 1.0]);
/// assert_eq!(subdiv_rules::centroid(&moved), p);
/// ```
///
/// # Panics
/// If `images` is empty or `out.len() != images.len()`.
///
/// [correction D2]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d2
pub fn moved_images(p: Point3, images: &[Point3], omega: f64, out: &mut [Point3]) {
    moved_images_about(p, images, centroid(images), omega, out); // §3.3: G = (Q_1 + … + Q_m)/m
}

/// Writes the moved vertices Q̄ᵢ = P + ω(Qᵢ − g) about a given centre `g`:
/// [`moved_images`] with g = G, or a boundary vertex's images about its
/// [`boundary_centre`] (module docs, "Open meshes").
///
/// # Panics
/// If `out.len() != images.len()`.
pub fn moved_images_about(p: Point3, images: &[Point3], g: Point3, omega: f64, out: &mut [Point3]) {
    assert_eq!(out.len(), images.len(), "one moved vertex per image");
    for (o, &q) in out.iter_mut().zip(images) {
        *o = add(p, scale(sub(q, g), omega)); // §3.3 (D2): Q̄_i = P + ω_P(Q_i − G)
    }
}

/// d_E / ‖P₁ − P₂‖: how far a new edge point strays from the edge midpoint,
/// relative to the edge length (§3.4).
pub fn edge_displacement_ratio(edge_point: Point3, p1: Point3, p2: Point3) -> f64 {
    let mid = scale(add(p1, p2), 0.5);
    dist(edge_point, mid) / dist(p1, p2) // §3.4: d_E = ‖E^{k+1} − (P_1 + P_2)/2‖
}

/// d_F / (shortest edge): how far a new face point strays from the centroid
/// of the face's corners, relative to the face's shortest edge (§3.4, for a
/// face of any size).
///
/// # Panics
/// If `corners` has fewer than 3 points.
pub fn face_displacement_ratio(face_point: Point3, corners: &[Point3]) -> f64 {
    let m = corners.len();
    assert!(m >= 3, "a face has at least 3 corners, got {m}");
    let shortest = (0..m).map(|i| dist(corners[i], corners[(i + 1) % m])).fold(f64::INFINITY, f64::min); // D5: min over cyclic edges P_i P_{(i mod m)+1}
    dist(face_point, centroid(corners)) / shortest // §3.4: d_F = ‖F^{k+1} − centroid‖
}

/// The displacement-safety conditions of §3.4 with the constant C made
/// explicit ([correction D5]).
///
/// [correction D5]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#d5
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DisplacementBound {
    /// The constant C, 0 < C < 1.
    pub c: f64,
}

impl DisplacementBound {
    /// d_E ≤ C‖P₁ − P₂‖.
    pub fn edge_ok(&self, edge_point: Point3, p1: Point3, p2: Point3) -> bool {
        edge_displacement_ratio(edge_point, p1, p2) <= self.c
    }

    /// d_F ≤ C·(shortest edge of the face).
    pub fn face_ok(&self, face_point: Point3, corners: &[Point3]) -> bool {
        face_displacement_ratio(face_point, corners) <= self.c
    }
}

#[cfg(test)]
#[path = "deng_ma_tests.rs"]
mod tests;
