//! Limit-point matrices in the factored form **A = D·S** ([limit matrices]).
//!
//! Row v of A maps the control points X to the limit point of vertex v on
//! the scheme's surface; interpolation solves A·X = P (the methods that do
//! live in `subdiv-interp`, which builds its matrices on these). Every matrix is
//! built directly from the topology as a diagonal D (positive) and a sparse S
//! that is **exactly symmetric** (entry by entry, bit for bit) on closed
//! untagged meshes — assembled from symmetric per-face / per-edge
//! contributions (each entry sums the same multiset of face/edge
//! contributions in a canonical order), never by symmetrising afterwards.
//!
//! | builder | scheme, first step | D | S (interior vertex v, valence n, faces fᵢ of size mᵢ) |
//! |---|---|---|---|
//! | [`limit_matrix_doo_sabin`] | Doo-Sabin, standard (C) | 1/n | Σ_f Circ(α_{m_f}) (Zheng-Cai Eq. 1; [correction Z8]) |
//! | [`limit_matrix_doo_sabin_sharp`] | Doo-Sabin, first step with any symmetric [`CornerMask`] | 1/n | Σ_f Circ(w_f), w_f the mask's row of face f |
//! | [`limit_matrix_catmull_clark`] | Catmull-Clark (Cheng's A) | 4/(n(n+5)) | appendix Eq. 5 bracket ([corrections C1, C2]) |
//! | [`limit_matrix_loop`] | Loop | γ = 1/(k + 3/(8β)) | 3/(8β) on the diagonal, 1 per neighbour (Deng-Wang Eq. 5-6, [correction W4]) |
//! | [`limit_matrix_sqrt3`] | √3 (Kobbelt 2000) | βₙ/n | n(1 − βₙ)/βₙ on the diagonal, 1 per neighbour ([`crate::sqrt3`]) |
//!
//! The interpolation methods' Doo-Sabin matrices (Nasri's C, Zheng-Cai's Z,
//! Fan-Cheng-Lai's B(λ)) are [`limit_matrix_doo_sabin_sharp`] with their
//! first steps' masks, in `subdiv-interp`.
//!
//! Catmull-Clark's A and Loop's L also come with creases and corners
//! ([`limit_matrix_catmull_clark_sharp`], [`limit_matrix_loop_sharp`], on a
//! [`LevelSharpness`]: tags, boundary option, crease method), and so does the
//! Doo-Sabin family ([`limit_matrix_doo_sabin_sharp`], on
//! [`Tags`]: Doo-Sabin has infinitely sharp creases and corners only, no
//! boundary option and no crease method; "Doo-Sabin with creases and
//! corners" below). √3 has corners only ([`limit_matrix_sqrt3_sharp`]:
//! corner tags and the boundary option).
//!
//! **Row kinds.** Every row is of one [`RowKind`], listed in
//! [`LimitMatrix::row_kinds`], decided per vertex by its sharpness
//! ([`LevelSharpness`], the rules' own view: boundary edges infinitely sharp,
//! one-face boundary vertices corners under `edge-and-corner`; for Doo-Sabin
//! [`DualFeatures`], the view of the tagged split):
//!
//! - [`RowKind::Smooth`]: no sharp edge at v, vertex sharpness 0 — the
//!   symmetric assembly of the table above, unchanged by tags elsewhere.
//! - [`RowKind::Crease`]: exactly two incident edges sharp, both infinitely,
//!   no other sharpness at v — the cubic B-spline point (p₋ + 4p + p₊)/6 of
//!   the crease polygon (D = 1/6, S = (1, 4, 1)); a boundary vertex is one
//!   (Doo-Sabin: the quadratic (B₋ + 6V + B₊)/8, D = 1/8, S = (1, 6, 1), or
//!   (2, 5, 1) next to a corner and (2, 4, 2) between two).
//! - [`RowKind::Corner`]: infinitely sharp vertex, ≥ 3 infinitely sharp
//!   edges, or an isolated vertex — the identity row (D = S = 1).
//! - [`RowKind::General`]: everything else — darts (one sharp edge) and every
//!   vertex whose limit involves a semi-sharp value: the row of the composed
//!   limit L·R_k⋯R_1 that [`crate::SubdivisionPlan::limit_stencil`] gives
//!   (the limit masks after ⌈largest semi-sharp value⌉ levels, at least one,
//!   as OpenSubdiv's `Limit`; at a dart whose edge is infinitely sharp the
//!   dart's exact mask, or OpenSubdiv's smooth one under
//!   [`crate::DartLimit::SmoothMask`], as `sharp` says), D = 1, S = that
//!   row. Such rows break the symmetric D·S form; and the Doo-Sabin rows
//!   of darts (D = 1) and of interior valence-2 vertices (D = 1/n = ½,
//!   S = 2 × the mask) are of this kind too.
//!
//! **Blocks.** Crease and corner rows depend only on their crease polygon's
//! vertices. [`LimitMatrix::boundary_rows`] is the **sharp block**: the
//! crease and corner rows whose columns all lie in the block, so A is block
//! lower-triangular with the sharp block first. A polygon that runs into a
//! general row (a dart at its end, a semi-sharp vertex on it) leaves the
//! block from there up to its corners — under `edge-only` a whole boundary
//! loop without corner tags. A solve can take the blocks in order:
//! corners (X = P), then the crease polygons (symmetric (1, 4, 1) blocks —
//! Doo-Sabin (1, 6, 1) —, coupled to corners only), then the interior (smooth rows, symmetric among
//! themselves bit for bit, and the general rows and polygons that left);
//! [`LimitMatrix::asymmetric_rows`] tells where a block lost its symmetry.
//!
//! **Valence 2 (Doo-Sabin).** An interior vertex of valence 2 has no V-face
//! after the first step (it would be a digon); its row is the centroid of the
//! second-level E-face of the edge between its two images,
//! ⅜(v₀ + v₁) + 1/16·(a₀ + a₁ + b₀ + b₁) on the first step's images
//! (`subdiv_rules::doo_sabin`, "Interior vertices of valence 2"). That row is
//! not of the Circ form, so S is not symmetric when such vertices exist and
//! the solvers need a nonsymmetric method for the interior block.
//!
//! **Boundaries** are creases: on open meshes the rows of boundary
//! vertices follow the boundary curve, which depends on boundary vertices
//! only: Catmull-Clark and Loop (p₋ + 4p + p₊)/6, one-face corners p under
//! `edge-and-corner`; Doo-Sabin (B₋ + 6V + B₊)/8 at every untagged boundary vertex —
//! the point of the quadratic B-spline boundary at V, which the Chaikin
//! boundary rule of [`crate::doo_sabin`] produces whatever the first step's
//! corner mask. Untagged, the sharp block is the boundary:
//! the boundary block and the interior block are each of the symmetric D·S
//! form, and solvers handle open meshes in two symmetric stages (boundary
//! first, then the interior with the boundary known).
//!
//! **Spectra of the blocks with creases.** A closed crease loop of m
//! vertices is the circulant (1, 4, 1)/6, eigenvalues (4 + 2cos(2πk/m))/6 ∈
//! [⅓, 1] (m = 3: 1, ½, ½); an open polygon between corners the tridiagonal
//! (4 + 2cos(πk/(m+1)))/6 ∈ (⅓, 1): never singular. The smooth block's
//! D^½SD^½ is a principal submatrix of the untagged one (Cheng's quadratic
//! form, Loop's L), so its eigenvalues interlace the untagged ones (⊂ [0, 1]
//! when every valence is ≥ 3), and it is singular only on a kernel vector of
//! the untagged matrix supported on the smooth vertices alone: the cube's
//! checkerboard needs every vertex, so a crease vertex or a corner makes
//! Cheng's A on the cube nonsingular (its crease row maps the checkerboard
//! to ±(4 − 2)/6 ≠ 0). Blocks with general rows have no such bound, and a
//! **dart** keeps the singularity: the first step maps the checkerboard to 0
//! (face points, smooth edge points, the dart's crease midpoint and the
//! valence-3 vertex points all vanish), so the cube with one crease edge is
//! as singular as the plain cube (`subdiv-interp` tests A·c = 0 itself,
//! `preconditions::cheng_kernel`). Otherwise measured nonsingular on every
//! case of `tests/integration/limit_matrices_creases.rs`.
//! Doo-Sabin's blocks: below.
//!
//! **Doo-Sabin with creases and corners** ([`limit_matrix_doo_sabin_sharp`]).
//! Row v is the limit point of input vertex v on the surface whose first step
//! uses a corner mask ([`CornerMask`]: the standard Eq. 1, or a method's
//! first step) and whose later steps are standard Doo-Sabin with the tags
//! ([`crate::doo_sabin`], "Creases and corners"): a point of the first
//! refined mesh M¹ that is a limit point of the standard tagged scheme;
//! [`doo_sabin_limit_sites`] names it in M¹ for every vertex. A sharp edge is
//! a crease (≥ 10) or a boundary edge; a corner has a tag ≥ 10 or ≥ 3 sharp
//! edges.
//!
//! | vertex | its limit point in M¹ | kind | D | S |
//! |---|---|---|---|---|
//! | smooth (no sharp edge), valence ≥ 3 | centroid of its V-face, its n corner images | Smooth | 1/n | the untagged Circ row |
//! | smooth, interior valence 2 | no V-face: centroid of the E-face one level on (the valence-2 mask) | General | ½ | 2 × the mask |
//! | crease or boundary (two sharp edges, to B₋ and B₊) | midpoint of its two sharp points, `sharp_curve_point`: (B₋ + 6V + B₊)/8, ¼B₋ + ⅝V + ⅛B₊ next to a corner B₋, ¼B₋ + ½V + ¼B₊ between two | Crease | ⅛ | (1, 6, 1), (2, 5, 1), (2, 4, 2) |
//! | dart (one sharp edge V–W, interior) | centroid of its one V-face: its n corner images and ¾V + ¼W (½V + ½W when W is a corner) | General | 1 | the row |
//! | corner, isolated vertex | itself (its kept point) | Corner | 1 | 1 |
//!
//! Why: the corner images of the first step do not depend on the tags
//! (step 1 of the construction in [`crate::doo_sabin`]), so a smooth
//! vertex's V-face — its corner images in fan order — is the untagged one
//! even next to a crease, and its centroid, a face centroid of M¹, is a limit
//! point (face centroids are, sharp faces included); so is the centroid of a
//! dart's V-face, its one sector closed by its crease's point near it. The
//! sharp points depend on the old sharp vertices only, not on the corner
//! rule, and from M¹ on the sharp polygon refines by Chaikin's rule, which
//! keeps the midpoint of each segment's middle part: a crease vertex's point
//! is its segment's midpoint whatever rule made M¹. The valence-2 mask reads
//! corner images in the quad E-faces of v's two (smooth) edges only, which
//! the tags do not change either. Without creases and corners (no tags, or
//! all zero) every row is the untagged one, bit for bit.
//!
//! Crease rows keep the crease block symmetric: a corner neighbour's weight
//! is 2, but corners are solved first (X = P) and their columns go to the
//! right-hand side; between two crease vertices S\[v\]\[B\] = 1 = S\[B\]\[v\].
//! A piece of the sharp polygon that ends at a dart leaves the sharp block
//! (its rows lean on a general row), as for Catmull-Clark.
//!
//! **Spectra, Doo-Sabin.** A is block lower triangular (corners, crease
//! pieces, interior), so its spectrum is the union of the blocks'. *Crease
//! pieces:* a closed loop of m vertices is the circulant (1, 6, 1)/8,
//! eigenvalues (6 + 2cos(2πk/m))/8 ∈ [½, 1] (½ iff m is even); a piece of k
//! crease vertices between corners (both ends clamped: diagonal 5, or 4 for
//! k = 1) is (4I + Q)/8 with Q the signless Laplacian of the path
//! (eigenvalues 2 − 2cos(πj/k)), eigenvalues (6 − 2cos(πj/k))/8, j = 0..k−1:
//! ½ exactly (the alternating vector) up to < 1. Every crease block lies in
//! [½, 1]: never singular, condition number ≤ 2. *Smooth block:* for x on
//! the smooth vertices xᵀSx = Σ_f x_fᵀ W_f x_f, W_f the face's symmetric
//! block — Circ(α_m), eigenvalues 1, ½, ¼ ([correction Z8]), or λ_f I + (1 − λ_f)J/m,
//! eigenvalues 1, λ_f ([correction F6]) — and Σ_f |x_f|² = xᵀD⁻¹x; so the smooth
//! block's D^½SD^½ lies in [¼, 1] (C), [½, 1] (Z), [min λ, 1] (B(λ)), on
//! open meshes too. Hence without darts and interior valence-2 vertices
//! spec(A) ⊂ [¼, 1] (C), [½, 1] (Z), [min(½, min λ), 1] (B(λ)): A is never
//! singular. *General rows* break those bounds and have none of their own:
//! on 4000 random tagged polygon mixes (`subdiv-interp`'s `tests/integration/limit_matrices_doo_sabin_creases.rs`)
//! the interior block's smallest |λ| was 0.262 (C), 0.493 (Z, below ½),
//! 1.62·min λ (B(λ)) with darts, 0.207, 0.383, 1.16·min λ with interior
//! valence-2 vertices too; every eigenvalue had a positive real part, no
//! block was singular, but nothing proves that one cannot be.
//!
//! [correction Z8]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#z8
//! [corrections C1, C2]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c1
//! [correction W4]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w4
//! [correction F6]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#f6
//! [limit matrices]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-limit-matrices-and-the-stopping-rule

use crate::doo_sabin::{CornerMask, StandardCorners};
use crate::sharpness::LevelSharpness;
use crate::{apply, face_ring_size, RowBuilder, Scheme, SparseMatrix, StencilError, Summation};
use glam::DVec3;
use rayon::prelude::*;
use std::collections::HashMap;
use subdiv_mesh::refine::{DualFace, DualFeatures, SharpDualProvenance};
use subdiv_mesh::{FaceId, FaceList, HalfEdgeId, Tags, Topology, VertexId};
use subdiv_rules::crease::{is_infinite, is_sharp};
use subdiv_rules::doo_sabin::{sharp_curve_point, BoundaryEdgePoint, BOUNDARY_EDGE_POINT, CLAMPED_EDGE_POINT};
use subdiv_rules::{LoopBeta, Rule};

/// How a row of a limit matrix is made (module docs, "Row kinds").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RowKind {
    /// The method's symmetric D·S assembly (a smooth vertex): S\[v\]\[u\] =
    /// S\[u\]\[v\] bit for bit for every smooth u.
    Smooth,
    /// The curve point of a crease or boundary polygon at v: v and its two
    /// neighbours along the polygon only.
    Crease,
    /// The identity (a corner, or an isolated vertex): X_v = P_v.
    Corner,
    /// Any other row (darts, semi-sharp limits, Doo-Sabin valence 2): D = 1
    /// and S the row itself (Doo-Sabin valence 2: D = ½, S twice the row),
    /// not of the symmetric form.
    General,
}

/// A limit matrix A = D·S with its rows' kinds and its sharp block marked.
///
/// `#[non_exhaustive]`: made by the `limit_matrix_*` functions, or from its
/// parts by [`LimitMatrix::new`]; read through its public fields (a new
/// field is not a breaking change).
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct LimitMatrix {
    /// The positive diagonal D, one entry per vertex.
    pub d: Vec<f64>,
    /// S: symmetric among the [`RowKind::Smooth`] rows bit for bit (and on
    /// closed untagged meshes without Doo-Sabin valence-2 vertices, whole).
    pub s: SparseMatrix,
    /// The sharp block, solved first: vertices (ascending) whose rows are
    /// [`RowKind::Crease`] or [`RowKind::Corner`] and whose columns all lie
    /// in this set. Untagged: the boundary, corner and isolated-vertex rows.
    pub boundary_rows: Vec<u32>,
    /// The kind of every row.
    pub row_kinds: Vec<RowKind>,
}

impl LimitMatrix {
    /// A limit matrix from its parts (a method that assembles its own A =
    /// D·S, a test): `d` and `row_kinds` one per row of the square `s`,
    /// `boundary_rows` as the field says.
    ///
    /// # Errors
    /// [`StencilError::InvalidParameter`] naming the first violated
    /// condition: lengths that differ, a non-square S, a D entry that is not
    /// positive and finite, `boundary_rows` not strictly ascending or out of
    /// range, a boundary row that is not [`RowKind::Crease`] or
    /// [`RowKind::Corner`] or has a column outside `boundary_rows`.
    pub fn new(
        d: Vec<f64>,
        s: SparseMatrix,
        boundary_rows: Vec<u32>,
        row_kinds: Vec<RowKind>,
    ) -> Result<Self, StencilError> {
        let invalid = |what: String| Err(StencilError::InvalidParameter(format!("limit matrix: {what}")));
        let n = d.len();
        if s.rows() != n || s.cols() != n || row_kinds.len() != n || !s.is_csr() {
            return invalid(format!(
                "{n} D entries, {} row kinds and a {} × {} {} S",
                row_kinds.len(),
                s.rows(),
                s.cols(),
                if s.is_csr() { "CSR" } else { "CSC" }
            ));
        }
        if let Some(i) = d.iter().position(|&x| !(x > 0.0 && x.is_finite())) {
            return invalid(format!("D[{i}] = {} is not positive and finite", d[i]));
        }
        let mut sharp = vec![false; n];
        for (k, &v) in boundary_rows.iter().enumerate() {
            if v as usize >= n || (k > 0 && boundary_rows[k - 1] >= v) {
                return invalid(format!("boundary row {v} (entry {k}) out of range or not ascending"));
            }
            sharp[v as usize] = true;
        }
        for &v in &boundary_rows {
            let kind = row_kinds[v as usize];
            if !matches!(kind, RowKind::Crease | RowKind::Corner) {
                return invalid(format!("boundary row {v} is of kind {kind:?}"));
            }
            let row = s.outer_view(v as usize).expect("a row per vertex");
            if let Some((j, _)) = row.iter().find(|&(j, _)| !sharp[j]) {
                return invalid(format!("boundary row {v} has column {j} outside the boundary rows"));
            }
        }
        Ok(Self { d, s, boundary_rows, row_kinds })
    }

    /// Number of rows (= vertices).
    pub fn size(&self) -> usize {
        self.d.len()
    }
    /// The materialised A = D·S (CSR).
    pub fn to_csr(&self) -> SparseMatrix {
        let indptr = self.s.indptr().raw_storage().to_vec();
        let mut data = self.s.data().to_vec();
        for i in 0..self.size() {
            data[indptr[i] as usize..indptr[i + 1] as usize].iter_mut().for_each(|x| *x *= self.d[i]);
        }
        SparseMatrix::new(self.s.shape(), indptr, self.s.indices().to_vec(), data)
    }
    /// A·X: the limit points of control points `x`.
    pub fn apply(&self, x: &[DVec3]) -> Vec<DVec3> {
        let mut y = apply(&self.s, x);
        y.iter_mut().zip(&self.d).for_each(|(p, d)| *p *= *d);
        y
    }
    /// True when S equals its transpose entry by entry (exactly).
    pub fn is_symmetric(&self) -> bool {
        let t = self.s.transpose_view().to_csr();
        t.indptr().raw_storage() == self.s.indptr().raw_storage()
            && t.indices() == self.s.indices()
            && t.data().iter().zip(self.s.data()).all(|(a, b)| a.to_bits() == b.to_bits())
    }

    /// The rows of one kind, ascending.
    pub fn rows_of(&self, kind: RowKind) -> Vec<u32> {
        (self.row_kinds.iter().enumerate()).filter(|&(_, &k)| k == kind).map(|(v, _)| v as u32).collect()
    }

    /// The rows of `block` (vertex ids) with an entry S\[i\]\[j\], j also in
    /// the block, that differs from S\[j\]\[i\] (bit for bit; a missing entry
    /// is 0), both i and j listed, ascending: empty when the block's S is
    /// symmetric. Time linear in the block's entries (times a binary search).
    pub fn asymmetric_rows(&self, block: &[u32]) -> Vec<u32> {
        let mut inside = vec![false; self.size()];
        block.iter().for_each(|&v| inside[v as usize] = true);
        let mut flagged = vec![false; self.size()];
        for &i in block {
            let row = self.s.outer_view(i as usize).expect("a row per vertex");
            for (j, &x) in row.iter().filter(|&(j, _)| inside[j]) {
                let mirror = self.s.get(j, i as usize).copied().unwrap_or(0.0);
                if x.to_bits() != mirror.to_bits() {
                    flagged[i as usize] = true;
                    flagged[j] = true;
                }
            }
        }
        (0..self.size() as u32).filter(|&v| flagged[v as usize]).collect()
    }
}

/// The row rule of a vertex, from its sharpness (module docs, "Row kinds").
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum RowRule {
    Smooth,
    /// The crease ends: v's neighbours along its two infinitely sharp edges.
    Crease(VertexId, VertexId),
    Corner,
    General,
}

/// The row rule of `v`. Only values that never change decide a stable rule:
/// 0 and ≥ 10 stay what they are at every level, under both crease methods,
/// and the edges at v's descendants are halves of v's edges; so a vertex
/// with no semi-sharp value at it keeps its rule (and crease ends) for ever,
/// and its limit mask on this level is exact. A semi-sharp value changes the
/// rule on the way (a general row), except where ≥ 3 infinitely sharp edges
/// or an infinitely sharp vertex make a corner whatever the others do.
pub(crate) fn row_rule(t: &Topology, sharp: &LevelSharpness, v: VertexId) -> RowRule {
    if t.is_isolated(v) {
        return RowRule::Corner;
    }
    // A smooth row is one step composed with the limit mask: not with the
    // smooth-triangle edge points (`LevelSharpness::smooth_triangle_at`), a general row then.
    let smooth = || if sharp.smooth_triangle_at(t, v) { RowRule::General } else { RowRule::Smooth };
    if sharp.is_untagged() && !t.is_boundary_vertex(v) {
        return smooth(); // fast path: nothing sharp can be at v
    }
    let vertex = sharp.vertex(t, v);
    // The incoming boundary edge (not in the fan) is infinitely sharp.
    let (mut infinite, mut semi) = (usize::from(t.is_boundary_vertex(v)), 0usize);
    for &h in t.vertex_fan(v) {
        let s = sharp.edge(t, t.he_edge(h));
        if is_infinite(s) {
            infinite += 1;
        } else if is_sharp(s) {
            semi += 1;
        }
    }
    if is_infinite(vertex) || infinite >= 3 {
        return RowRule::Corner;
    }
    if is_sharp(vertex) || semi > 0 {
        return RowRule::General;
    }
    match (infinite, sharp.limit_rule(t, v)) {
        (0, _) => smooth(),
        (2, (Rule::Crease, Some((a, b)))) => RowRule::Crease(a, b),
        _ => RowRule::General, // a dart: its limit row after the first step
    }
}

/// The D entry and S weights of a curve point (p₋·end + p·centre + p₊·end)·d.
#[derive(Clone, Copy)]
struct Curve {
    d: f64,
    end: f64,
    centre: f64,
}

/// Catmull-Clark and Loop: the cubic B-spline point (p₋ + 4p + p₊)/6.
const CUBIC_B_SPLINE: Curve = Curve { d: 1.0 / 6.0, end: 1.0, centre: 4.0 };

/// Rows that do not come from the symmetric assembly, with their D entry.
struct SpecialRows {
    d: Vec<(u32, f64)>,
    rows: Vec<(u32, Vec<(u32, f64)>)>,
}

/// The kinds of every row and the rows other than the symmetric assembly:
/// crease rows on `curve`, identity rows, and the general rows, taken from
/// the composed limit of `scheme` ([`composed_rows`]).
fn special_rows(
    t: &Topology,
    sharp: &LevelSharpness,
    curve: Curve,
    scheme: Scheme,
) -> Result<(SpecialRows, Vec<RowKind>), StencilError> {
    let mut out = SpecialRows { d: Vec::new(), rows: Vec::new() };
    let mut kinds = Vec::with_capacity(t.vertex_count());
    let mut general = Vec::new();
    for v in t.vertices() {
        kinds.push(match row_rule(t, sharp, v) {
            RowRule::Smooth => RowKind::Smooth,
            RowRule::Crease(a, b) => {
                out.d.push((v.0, curve.d));
                let mut row = vec![(a.0, curve.end), (v.0, curve.centre), (b.0, curve.end)];
                row.sort_by_key(|&(c, _)| c);
                out.rows.push((v.0, row));
                RowKind::Crease
            }
            RowRule::Corner => {
                out.d.push((v.0, 1.0));
                out.rows.push((v.0, vec![(v.0, 1.0)]));
                RowKind::Corner
            }
            RowRule::General => {
                general.push(v.0);
                RowKind::General
            }
        });
    }
    if !general.is_empty() {
        let composed = composed_rows(t, sharp, scheme, &general)?;
        for (&v, row) in general.iter().zip(composed.outer_iterator()) {
            out.d.push((v, 1.0));
            out.rows.push((v, row.iter().map(|(c, &w)| (c as u32, w)).collect()));
        }
    }
    Ok((out, kinds))
}

/// The rule of every row of a limit matrix before any row is stored: D, the
/// kinds of the rows, the rows that do not come from the symmetric assembly,
/// and the assembly rule of the others. [`LimitOperator::assemble`] stores
/// S as the `limit_matrix_*` functions return it; [`LimitOperator::for_each_row`]
/// produces the same rows, bit for bit, one at a time without storing them —
/// for a product with S that is needed once (the check of an initial guess
/// on a mesh of millions of vertices, where S would be the largest array).
///
/// Made by [`limit_operator_catmull_clark_sharp`]; borrows the topology.
pub struct LimitOperator<'a> {
    t: &'a Topology,
    d: Vec<f64>,
    special: SpecialRows,
    /// Per vertex, its entry in `special.rows` (`u32::MAX`: assembled); empty
    /// when there are no special rows.
    special_of: Vec<u32>,
    row_kinds: Vec<RowKind>,
    row: Box<RowRuleFn<'a>>,
}

/// The assembly rule of a row: adds vertex v's contributions.
type RowRuleFn<'a> = dyn Fn(VertexId, &mut RowBuilder) + Sync + 'a;

/// What [`LimitOperator::for_each_row`] calls with each row: (row, columns, values).
pub type RowVisitor<'f> = dyn FnMut(usize, &[u32], &[f64]) + 'f;

impl std::fmt::Debug for LimitOperator<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LimitOperator")
            .field("size", &self.size())
            .field("special_rows", &self.special.rows.len())
            .finish()
    }
}

impl<'a> LimitOperator<'a> {
    fn new(
        t: &'a Topology,
        mut d: Vec<f64>,
        special: SpecialRows,
        row_kinds: Vec<RowKind>,
        row: impl Fn(VertexId, &mut RowBuilder) + Sync + 'a,
    ) -> Self {
        let mut special_of = Vec::new();
        if !special.rows.is_empty() {
            special_of = vec![u32::MAX; t.vertex_count()];
            for (k, (v, _)) in special.rows.iter().enumerate() {
                special_of[*v as usize] = k as u32;
            }
        }
        for &(v, dv) in &special.d {
            d[v as usize] = dv;
        }
        Self { t, d, special, special_of, row_kinds, row: Box::new(row) }
    }

    /// Number of rows (= vertices).
    pub fn size(&self) -> usize {
        self.d.len()
    }

    /// The positive diagonal D, one entry per vertex (as [`LimitMatrix::d`]).
    pub fn d(&self) -> &[f64] {
        &self.d
    }

    /// The kind of every row (as [`LimitMatrix::row_kinds`]).
    pub fn row_kinds(&self) -> &[RowKind] {
        &self.row_kinds
    }

    /// True when every row is [`RowKind::Smooth`]: S is then symmetric bit
    /// for bit and the sharp block ([`LimitMatrix::boundary_rows`]) is empty.
    pub fn all_smooth(&self) -> bool {
        self.row_kinds.iter().all(|&k| k == RowKind::Smooth)
    }

    fn special_row(&self, v: usize) -> Option<&[(u32, f64)]> {
        match self.special_of.get(v) {
            Some(&k) if k != u32::MAX => Some(&self.special.rows[k as usize].1),
            _ => None,
        }
    }

    fn fill(&self, v: usize, rows: &mut RowBuilder) {
        match self.special_row(v) {
            None => (self.row)(VertexId(v as u32), rows),
            Some(row) => row.iter().for_each(|&(c, w)| rows.add(c, w)),
        }
    }

    /// Every row's columns lie in its vertex's face ring.
    fn max_len(&self, v: usize) -> usize {
        match self.special_row(v) {
            None => face_ring_size(self.t, VertexId(v as u32)),
            Some(row) => row.len(),
        }
    }

    /// Calls `f(v, columns, values)` for every row v of S in `rows`, in
    /// order: the columns ascending and the values exactly those
    /// [`Self::assemble`] stores (the same contributions, merged the same
    /// way). Nothing is stored between rows.
    ///
    /// # Panics
    /// If `rows` reaches beyond [`Self::size`] (a caller bug).
    pub fn for_each_row(&self, rows: std::ops::Range<usize>, f: &mut RowVisitor<'_>) {
        assert!(rows.end <= self.size(), "rows {rows:?} of a {0} × {0} limit matrix", self.size());
        let mut builder = RowBuilder::default();
        let (mut columns, mut values) = (Vec::new(), Vec::new());
        for v in rows {
            self.fill(v, &mut builder);
            builder.merge_pending(Summation::Canonical, &mut columns, &mut values);
            f(v, &columns, &values);
        }
    }

    /// The limit matrix: S stored row by row (in parallel, deterministically,
    /// `RowBuilder::build_parallel_bounded`), each row's contributions
    /// summed in ascending order of their bits (`Summation::Canonical`), so
    /// an entry's value depends only on the multiset of its contributions:
    /// S\[i\]\[j\] and S\[j\]\[i\], which receive the same contributions (a
    /// face or an edge containing both), are equal bit for bit.
    pub fn assemble(self) -> LimitMatrix {
        let n = self.size();
        let s = RowBuilder::build_parallel_bounded(
            n,
            n,
            Summation::Canonical,
            |v| self.max_len(v),
            |v, rows, _: &mut ()| self.fill(v, rows),
        );
        let boundary_rows = sharp_block(&s, &self.row_kinds);
        LimitMatrix { d: self.d, s, boundary_rows, row_kinds: self.row_kinds }
    }
}

/// Builds A = D·S row by row (in parallel, deterministically): `row(v, rows)`
/// adds the contributions of vertex v's row; rows listed in `special` are
/// taken from there instead ([`LimitOperator::assemble`]).
fn assemble(
    t: &Topology,
    d: Vec<f64>,
    special: SpecialRows,
    row_kinds: Vec<RowKind>,
    row: impl Fn(VertexId, &mut RowBuilder) + Sync,
) -> LimitMatrix {
    LimitOperator::new(t, d, special, row_kinds, row).assemble()
}

/// The crease and corner rows whose columns all lie in the set (the largest
/// such set): a crease row with a column outside — a dart or a semi-sharp
/// vertex at the polygon's end — leaves, and the rows that lean on it are
/// checked again, so a polygon leaves up to its corners. Linear time.
fn sharp_block(s: &SparseMatrix, kinds: &[RowKind]) -> Vec<u32> {
    let mut inside: Vec<bool> = kinds.iter().map(|k| matches!(k, RowKind::Crease | RowKind::Corner)).collect();
    let mut pending: Vec<usize> = (0..kinds.len()).filter(|&v| inside[v]).collect();
    while let Some(v) = pending.pop() {
        let row = s.outer_view(v).expect("a row per vertex");
        if inside[v] && row.indices().iter().any(|&c| !inside[c as usize]) {
            inside[v] = false;
            // A crease polygon is symmetric: the rows with column v are v's columns.
            pending.extend(row.indices().iter().map(|&c| c as usize).filter(|&c| inside[c]));
        }
    }
    (0..kinds.len() as u32).filter(|&v| inside[v as usize]).collect()
}

/// A neighbourhood of some vertices cut out of a level, with the sharpness
/// it has there.
struct Crop {
    topology: Topology,
    sharpness: LevelSharpness,
    /// The level's vertex of each crop vertex.
    to_level: Vec<u32>,
}

/// The faces at `tracked` and at their neighbours, as a mesh of its own with
/// the level's tags: `tracked` numbered first (crop vertex i = `tracked[i]`),
/// the faces in the level's order.
///
/// Everything the composed limit row of a tracked vertex g uses keeps its
/// value here: the rows it composes are g's vertex point, the edge points of
/// g's edges and the face points of g's faces, at every level; they read the
/// corners of g's faces and the sharpness at g and at its neighbours
/// (Chaikin halves, the boundary), whose fans are whole in the crop, in the
/// level's fan order (the first outgoing half-edge in face order), so even
/// the f32 sharpness sums are the same. The rim (the other vertices) gets
/// other rules, unused; a rim vertex whose kept faces are not one fan is
/// split into one crop vertex per piece, which keeps the crop manifold.
fn crop(t: &Topology, sharp: &LevelSharpness, tracked: &[u32]) -> Crop {
    let mut near = vec![false; t.vertex_count()];
    for &g in tracked {
        near[g as usize] = true;
        t.vertex_neighbors(VertexId(g)).for_each(|u| near[u.index()] = true);
    }
    let mut faces: Vec<u32> = Vec::new();
    for (v, _) in near.iter().enumerate().filter(|&(_, &n)| n) {
        faces.extend(t.vertex_fan(VertexId(v as u32)).iter().map(|&h| t.he_face(h).0));
    }
    faces.sort_unstable();
    faces.dedup();
    let mut kept = vec![false; t.face_count()];
    faces.iter().for_each(|&f| kept[f as usize] = true);

    // Crop vertex of each vertex near the tracked ones, and of each kept
    // corner (half-edge) of a rim vertex: one per run of kept faces in its fan.
    let mut id_of = vec![u32::MAX; t.vertex_count()];
    let mut to_level: Vec<u32> = Vec::with_capacity(8 * faces.len());
    for &g in tracked {
        id_of[g as usize] = to_level.len() as u32;
        to_level.push(g);
    }
    let mut rim_corner: HashMap<u32, u32> = HashMap::new();
    let mut indices = Vec::with_capacity(4 * faces.len());
    let mut offsets = Vec::with_capacity(faces.len() + 1);
    offsets.push(0u32);
    for &f in &faces {
        for h in t.face_half_edges(FaceId(f)) {
            let w = t.he_from(h);
            let id = if near[w.index()] {
                if id_of[w.index()] == u32::MAX {
                    id_of[w.index()] = to_level.len() as u32;
                    to_level.push(w.0);
                }
                id_of[w.index()]
            } else {
                if !rim_corner.contains_key(&h.0) {
                    // Number the runs of w's kept faces: a run ends at a face not kept.
                    let fan = t.vertex_fan(w);
                    let closed = !t.is_boundary_vertex(w);
                    let start = if closed { fan.iter().position(|&g| !kept[t.he_face(g).index()]) } else { None };
                    let start = start.map_or(0, |s| s + 1);
                    let mut run = None;
                    for k in 0..fan.len() {
                        let g = fan[(start + k) % fan.len()];
                        if kept[t.he_face(g).index()] {
                            let id = *run.get_or_insert_with(|| {
                                to_level.push(w.0);
                                to_level.len() as u32 - 1
                            });
                            rim_corner.insert(g.0, id);
                        } else {
                            run = None;
                        }
                    }
                }
                rim_corner[&h.0]
            };
            indices.push(id);
        }
        offsets.push(indices.len() as u32);
    }
    let topology = Topology::new(FaceList::from_raw(offsets, indices), to_level.len())
        .expect("a crop of a valid level, its rim split into fan pieces, is valid");

    // The level's tags on the crop: edge by edge through the kept corners.
    let tags = sharp.tags(t);
    let edges = if tags.edge_values().is_empty() {
        Vec::new()
    } else {
        let mut edges = vec![0.0f32; topology.edge_count()];
        for (i, &f) in faces.iter().enumerate() {
            for (h, g) in topology.face_half_edges(FaceId(i as u32)).zip(t.face_half_edges(FaceId(f))) {
                edges[topology.he_edge(h).index()] = tags.edge_sharpness(t.he_edge(g));
            }
        }
        edges
    };
    let vertices = if tags.vertex_values().is_empty() {
        Vec::new()
    } else {
        to_level.iter().map(|&v| tags.vertex_sharpness(VertexId(v))).collect()
    };
    let tags = Tags::from_arrays(&topology, edges, vertices).expect("the level's tags are valid values");
    let sharpness = LevelSharpness::new(&tags, sharp.boundary(), sharp.method())
        .with_triangle_rule(sharp.triangle_rule())
        .with_dart_limit(sharp.dart_limit());
    Crop { topology, sharpness, to_level }
}

/// `m` with column c renamed `map[c]` (columns that meet are summed), `columns` wide.
fn relabel_columns(m: &SparseMatrix, map: &[u32], columns: usize) -> SparseMatrix {
    let mut out = RowBuilder::with_capacity(m.rows(), m.nnz());
    for row in m.outer_iterator() {
        row.iter().for_each(|(c, &w)| out.add(map[c], w));
        out.finish_row();
    }
    out.build(columns)
}

/// Tracked rows per crop in [`composed_rows`]. One chunk's crops and their
/// refinement stencils, at every level, are what the composition holds at
/// once (a few kilobytes per row and level: semi-sharp tags on a mesh of
/// 10⁵ vertices held gigabytes when all rows shared one crop), so the memory
/// stays bounded whatever the number of rows, and the chunks run in parallel.
const COMPOSED_ROWS_PER_CROP: usize = 2048;

/// Rows `rows` of the plan's limit stencil on `t` with `sharp`
/// (`SubdivisionPlan::with_tags(t, tags, options, 0).limit_stencil()`: the
/// limit rows after the levels the masks need, composed with those levels'
/// refinement stencils), as a `rows.len()` × V matrix, row i for vertex
/// `rows[i]`.
///
/// Computed on a [`crop`] around the rows' vertices at every level rather
/// than on the whole mesh: the same rows (up to the order of the sums), in
/// time linear in the rows and the levels instead of the mesh's size × 4^levels.
/// The rows are taken [`COMPOSED_ROWS_PER_CROP`] at a time, in parallel;
/// each chunk's result depends on the chunk alone, so the bits do not
/// depend on the thread count.
pub(crate) fn composed_rows(
    t: &Topology,
    sharp: &LevelSharpness,
    scheme: Scheme,
    rows: &[u32],
) -> Result<SparseMatrix, StencilError> {
    let rules = scheme.rules();
    rules.check(t, sharp)?;
    let levels = rules.levels_before_limit(t, sharp, true);
    let chunks: Vec<SparseMatrix> = rows
        .par_chunks(COMPOSED_ROWS_PER_CROP)
        .map(|chunk| composed_chunk(t, sharp, scheme, levels, chunk))
        .collect::<Result<_, _>>()?;
    if chunks.len() == 1 {
        return Ok(chunks.into_iter().next().expect("one chunk"));
    }
    let mut out = RowBuilder::with_capacity(rows.len(), chunks.iter().map(SparseMatrix::nnz).sum());
    for row in chunks.iter().flat_map(|m| m.outer_iterator()) {
        row.iter().for_each(|(c, &w)| out.add(c as u32, w));
        out.finish_row();
    }
    Ok(out.build(t.vertex_count()))
}

/// [`composed_rows`] of one chunk of rows, `levels` levels deep.
fn composed_chunk(
    t: &Topology,
    sharp: &LevelSharpness,
    scheme: Scheme,
    levels: usize,
    rows: &[u32],
) -> Result<SparseMatrix, StencilError> {
    let rules = scheme.rules();
    // The tracked vertices, in every crop.
    let first: Vec<u32> = (0..rows.len() as u32).collect();
    // Per level: the vertex count of the level, its crop, and the crop's stencil.
    let mut steps: Vec<(usize, Vec<u32>, SparseMatrix)> = Vec::with_capacity(levels);
    let mut level_size = t.vertex_count();
    let mut current = crop(t, sharp, rows);
    for _ in 0..levels {
        let split = rules.split(&current.topology, &current.sharpness)?;
        let stencil = (rules.stencil(&current.topology, &current.sharpness)?)
            .expect("the schemes with limit masks have stencils");
        steps.push((level_size, current.to_level, stencil));
        level_size = split.topology.vertex_count();
        current = crop(&split.topology, &split.sharpness, &first);
    }
    let limit = (rules.limit_stencil(&current.topology, &current.sharpness, rows.len()))
        .expect("the schemes with limit matrices have limit masks")?;
    let mut composed = relabel_columns(&limit, &current.to_level, level_size);
    for (size, to_level, stencil) in steps.iter().rev() {
        composed = relabel_columns(&(&composed * stencil), to_level, *size);
    }
    Ok(composed)
}

/// Doo-Sabin's plain limit matrix C: every step standard (Eq. 1), row v
/// the centroid of v's V-face after one step ([`limit_matrix_doo_sabin_sharp`]
/// with [`StandardCorners`] and no tags). Spectrum ⊂ [¼, 1] on closed
/// manifold meshes without interior valence-2 vertices ([correction Z8]).
///
/// [correction Z8]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#z8
pub fn limit_matrix_doo_sabin(t: &Topology) -> LimitMatrix {
    limit_matrix_doo_sabin_sharp(t, &StandardCorners, &Tags::none()).expect("the standard mask has no parameters")
}

/// The Doo-Sabin limit rule of a vertex (module docs, "Doo-Sabin with
/// creases and corners"), from the level's [`DualFeatures`] — the
/// classification of the tagged split (`subdiv_mesh::refine::dual_split_tagged`)
/// and of [`crate::doo_sabin::limit_stencil_tagged`].
#[derive(Clone, Copy, Debug, PartialEq)]
enum DualRow {
    /// No sharp edge, no V-face lost: the centroid of v's V-face of corner images.
    Smooth,
    /// Interior valence 2, no sharp edge: the valence-2 mask on its corners.
    ValenceTwo([(HalfEdgeId, f64); 6]),
    /// Exactly two sharp edges (a crease or boundary vertex): its sharp
    /// neighbours B₋, B₊, each with whether it is a corner.
    Crease([(VertexId, bool); 2]),
    /// Exactly one sharp edge (interior): the edge's other end W, and whether
    /// W is a corner.
    Dart(VertexId, bool),
    /// A corner (tag ≥ 10 or ≥ 3 sharp edges) or an isolated vertex.
    Corner,
}

fn dual_row(t: &Topology, features: &DualFeatures, v: VertexId) -> DualRow {
    if t.is_isolated(v) || features.is_corner(v) {
        return DualRow::Corner;
    }
    let end = |b: VertexId| (b, features.is_corner(b));
    if let Some((prev, next)) = t.boundary_neighbors(v) {
        // Not a corner: the boundary's two edges are its only sharp ones.
        return DualRow::Crease([end(prev), end(next)]);
    }
    match features.sharp_edge_count(t, v) {
        0 => crate::doo_sabin::valence_two_corners(t, v).map_or(DualRow::Smooth, DualRow::ValenceTwo),
        1 => {
            let w = features.sharp_neighbors(t, v).next().expect("one sharp edge");
            DualRow::Dart(w, features.is_corner(w))
        }
        _ => {
            // Two (three or more make a corner).
            let mut ends = features.sharp_neighbors(t, v);
            let (a, b) = (ends.next().expect("two sharp edges"), ends.next().expect("two sharp edges"));
            DualRow::Crease([end(a), end(b)])
        }
    }
}

/// The Doo-Sabin family's matrix with the infinitely sharp creases and
/// corners of `tags`, for a first step with the corner mask `rule`
/// ([`StandardCorners`]: Doo-Sabin's own, [`limit_matrix_doo_sabin`]; the
/// interpolation methods supply theirs): V × V, row v the limit
/// point of input vertex v on the surface whose first step uses `rule` and
/// whose later steps are standard Doo-Sabin with the tags
/// ([`crate::doo_sabin::first_step_tagged`], [`dual_split_tagged`](subdiv_mesh::refine::dual_split_tagged)):
///
/// - smooth vertex (no sharp edge, valence ≥ 3): the centroid of its V-face,
///   its n corner images — the untagged Circ row, D = 1/n, even next to a
///   crease (corner images do not depend on the tags), [`RowKind::Smooth`];
/// - interior valence 2 without sharp edge: the valence-2 mask, unchanged
///   ([`RowKind::General`], D = ½, S = 2 × the mask);
/// - crease or boundary vertex (exactly two sharp edges, no corner): the
///   midpoint of its two sharp points, `sharp_curve_point`:
///   (B₋ + 6V + B₊)/8, ¼B₋ + ⅝V + ⅛B₊ next to a corner B₋, ¼B₋ + ½V + ¼B₊
///   between two, whatever the rule ([`RowKind::Crease`], D = ⅛);
/// - dart (one crease edge V–W): the centroid of its one V-face, its n
///   corner images and the crease's point ¾V + ¼W (½V + ½W when W is a
///   corner), ([`RowKind::General`], D = 1);
/// - corner (tag ≥ 10 or ≥ 3 sharp edges) and isolated vertex: the identity
///   ([`RowKind::Corner`]).
///
/// With no crease and no corner this is the untagged matrix bit for bit
/// (boundary rows (1, 6, 1)/8). [`doo_sabin_limit_sites`] tells where each
/// row's point sits in the first refined mesh.
///
/// ```
/// use subdiv_mesh::{shapes, EdgeTag, TagList, Tags};
/// use subdiv_stencil::{doo_sabin::StandardCorners, limit_matrix_doo_sabin, limit_matrix_doo_sabin_sharp, RowKind};
/// let cube = shapes::cube();
/// let t = cube.topology();
/// // The top loop 4-5-7-6 sharp: a closed crease of four vertices.
/// let loop_edges = [(4, 5), (5, 7), (7, 6), (6, 4)];
/// let creases = loop_edges.iter().map(|&(a, b)| EdgeTag { a, b, sharpness: 10.0 }).collect();
/// let tags = Tags::from_list(t, &TagList { creases, corners: Vec::new(), ..Default::default() }).unwrap();
/// let c = limit_matrix_doo_sabin_sharp(t, &StandardCorners, &tags).unwrap();
/// assert_eq!(c.rows_of(RowKind::Crease), [4, 5, 6, 7]);
/// // Crease rows (B₋ + 6V + B₊)/8 along the loop, whatever the first step.
/// assert_eq!((c.d[4], c.s.get(4, 4), c.s.get(4, 5), c.s.get(4, 0)), (0.125, Some(&6.0), Some(&1.0), None));
/// // The smooth rows are the untagged ones.
/// let plain = limit_matrix_doo_sabin(t);
/// assert_eq!(c.rows_of(RowKind::Smooth), [0, 1, 2, 3]);
/// assert_eq!(c.s.outer_view(0).unwrap().data(), plain.s.outer_view(0).unwrap().data());
/// ```
///
/// # Errors
/// [`StencilError::SemiSharpDooSabin`] for a semi-sharp tag (Doo-Sabin has
/// infinitely sharp creases and corners only), the mask's
/// [`CornerMask::validate`] error for its bad parameters.
///
/// # Panics
/// If `tags` were made for another topology (a caller bug).
pub fn limit_matrix_doo_sabin_sharp(
    t: &Topology,
    rule: &impl CornerMask,
    tags: &Tags,
) -> Result<LimitMatrix, StencilError> {
    rule.validate(t)?;
    crate::doo_sabin::check_tags(t, tags)?;
    let features = DualFeatures::new(t, tags);
    let rows: Vec<DualRow> = t.vertices().map(|v| dual_row(t, &features, v)).collect();
    let mut d: Vec<f64> = t.vertices().map(|v| 1.0 / t.vertex_face_count(v).max(1) as f64).collect(); // Σ = diag(1/n)
    let mut special = SpecialRows { d: Vec::new(), rows: Vec::new() };
    let mut kinds = Vec::with_capacity(rows.len());
    for (v, row) in rows.iter().enumerate() {
        kinds.push(match *row {
            DualRow::Smooth => RowKind::Smooth,
            DualRow::ValenceTwo(_) => RowKind::General, // D = 1/n = ½ (the row is scaled by 2)
            DualRow::Dart(..) => {
                d[v] = 1.0;
                RowKind::General
            }
            DualRow::Crease([(a, a_corner), (b, b_corner)]) => {
                // The midpoint of v's two sharp points: ⅛·(8w), exact (dyadic weights).
                let [wa, wv, wb] = sharp_curve_point(a_corner, b_corner);
                let mut s = vec![(a.0, 8.0 * wa), (v as u32, 8.0 * wv), (b.0, 8.0 * wb)];
                s.sort_by_key(|&(c, _)| c);
                special.d.push((v as u32, 0.125));
                special.rows.push((v as u32, s));
                RowKind::Crease
            }
            DualRow::Corner => {
                special.d.push((v as u32, 1.0));
                special.rows.push((v as u32, vec![(v as u32, 1.0)]));
                RowKind::Corner
            }
        });
    }
    Ok(assemble(t, d, special, kinds, |v, out| match rows[v.index()] {
        DualRow::Smooth => {
            // Σ_f of the mask's face block Circ(w) (Eq. 1: α depends on cos
            // only): symmetric when w[k] = w[m − k], as CornerMask asks.
            add_fan_row(t, v, out, 0.0, 0.0, |face, w| rule.weights(face, w));
        }
        DualRow::ValenceTwo(corners) => {
            // No V-face: the valence-2 mask on the first step's images (the
            // second-level E-face centroid), ×n = 2 since D = 1/n. Not of the
            // Circ form: S loses its symmetry in this row.
            crate::doo_sabin::add_valence_two_row(t, &corners, rule, 2.0, out, &mut Vec::new());
        }
        DualRow::Dart(w, w_corner) => {
            // The V-face of the dart's one sector: its n corner images (the
            // rule's rows) and the crease's Chaikin point near it, closed by
            // the same point at both ends of the sector.
            let n = (t.vertex_face_count(v) + 1) as f64;
            let mut weights = Vec::new();
            for c in t.vertex_corners(v) {
                let face = t.face(c.face);
                weights.resize(face.len(), 0.0);
                rule.weights(c.face, &mut weights);
                let (before, from_v) = face.split_at(c.index as usize);
                for (&column, &wj) in from_v.iter().chain(before).zip(&weights) {
                    out.add(column, wj / n);
                }
            }
            let BoundaryEdgePoint { near, far } = if w_corner { CLAMPED_EDGE_POINT } else { BOUNDARY_EDGE_POINT };
            out.add(v.0, near / n);
            out.add(w.0, far / n);
        }
        DualRow::Crease(_) | DualRow::Corner => unreachable!("crease and corner rows are special"),
    }))
}

/// Where the limit point of an input vertex (row v of
/// [`limit_matrix_doo_sabin_sharp`]) sits in the first refined mesh M¹ of
/// [`dual_split_tagged`](subdiv_mesh::refine::dual_split_tagged) (ids of M¹), whatever the first step's corner rule:
/// the limit point is a function of M¹'s positions, which is what the
/// interpolation methods evaluate on their control mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DualLimitSite {
    /// The centroid of this face of M¹: the V-face of a smooth vertex (its
    /// corner images) or of a dart (its corner images and its crease's point).
    FaceCentroid(FaceId),
    /// The midpoint of these two vertices of M¹: the sharp points next to a
    /// crease or boundary vertex, on its sharp edges to B₋ and to B₊ (the
    /// ends of its segment of the refined sharp polygon).
    SharpMidpoint(VertexId, VertexId),
    /// This vertex of M¹: the point that keeps a corner.
    Corner(VertexId),
    /// The limit point of the edge of M¹ between these two vertices, the two
    /// images of an interior valence-2 vertex
    /// ([`crate::doo_sabin::edge_limit_point`]).
    ValenceTwoEdge(VertexId, VertexId),
    /// An isolated vertex: nothing of it is in M¹.
    Isolated,
}

impl DualLimitSite {
    /// The limit point on M¹ (`m1`, positions `x1`); `None` for an isolated
    /// vertex, or a valence-2 edge that `m1` does not have (not the M¹ the
    /// site was made for).
    ///
    /// # Panics
    /// If an id is out of range of `m1` or `x1` (not the M¹ of the site).
    pub fn point(&self, m1: &Topology, x1: &[DVec3]) -> Option<DVec3> {
        match *self {
            DualLimitSite::FaceCentroid(f) => {
                let face = m1.face(f);
                Some(face.iter().map(|&c| x1[c as usize]).sum::<DVec3>() / face.len() as f64)
            }
            DualLimitSite::SharpMidpoint(a, b) => Some((x1[a.index()] + x1[b.index()]) / 2.0),
            DualLimitSite::Corner(c) => Some(x1[c.index()]),
            DualLimitSite::ValenceTwoEdge(a, b) => {
                let h = m1.vertex_fan(a).iter().find(|&&h| m1.he_to(h) == b)?;
                Some(crate::doo_sabin::edge_limit_point(m1, *h, x1))
            }
            DualLimitSite::Isolated => None,
        }
    }
}

/// Per input vertex of `t`, where its limit point sits in M¹ =
/// `dual_split_tagged(t, tags)` with provenance `provenance`
/// ([`DualLimitSite`]; the rows of [`limit_matrix_doo_sabin_sharp`], module
/// docs "Doo-Sabin with creases and corners"). Linear time. Untagged, the
/// V-faces are [`subdiv_mesh::refine::DualProvenance::vertex_face`] and the
/// sharp points the two Chaikin points next to each boundary vertex.
///
/// # Errors
/// [`StencilError::SemiSharpDooSabin`] for a semi-sharp tag.
///
/// # Panics
/// If `provenance` is not that of `dual_split_tagged(t, tags)` (a caller
/// bug): a smooth vertex or a dart without its V-face, a sharp edge without
/// its points.
pub fn doo_sabin_limit_sites(
    t: &Topology,
    tags: &Tags,
    provenance: &SharpDualProvenance,
) -> Result<Vec<DualLimitSite>, StencilError> {
    crate::doo_sabin::check_tags(t, tags)?;
    let features = DualFeatures::new(t, tags);
    assert_eq!(provenance.edge_points.len(), t.edge_count(), "the provenance of another topology");
    // The (first) V-face of every vertex: smooth vertices and darts have one.
    let mut v_face = vec![None; t.vertex_count()];
    for (f, origin) in provenance.face_origin.iter().enumerate() {
        if let DualFace::V(v) = *origin {
            v_face[v.index()].get_or_insert(FaceId(f as u32));
        }
    }
    // The sharp point next to v on its sharp edge to b.
    let near = |v: VertexId, b: VertexId| -> VertexId {
        let h = t.vertex_fan(v).iter().copied().find(|&h| t.he_to(h) == b);
        // On the boundary, the incoming edge b → v is not in v's fan.
        let h = h.unwrap_or_else(|| t.vertex_fan(b).iter().copied().find(|&h| t.he_to(h) == v).expect("an edge v-b"));
        let e = t.he_edge(h);
        let [at_start, _, at_end] = provenance.edge_points[e.index()];
        let id = if t.he_from(t.edge_half_edge(e)) == v { at_start } else { at_end };
        assert_ne!(id, u32::MAX, "sharp edge {e} has no point near {v}: not the provenance of these tags");
        VertexId(id)
    };
    let face_of = |v: VertexId| v_face[v.index()].expect("a smooth vertex or a dart has a V-face");
    Ok(t.vertices()
        .map(|v| match dual_row(t, &features, v) {
            _ if t.is_isolated(v) => DualLimitSite::Isolated,
            DualRow::Corner => DualLimitSite::Corner(VertexId(provenance.corner_point[v.index()])),
            DualRow::Smooth | DualRow::Dart(..) => DualLimitSite::FaceCentroid(face_of(v)),
            DualRow::ValenceTwo(corners) => {
                DualLimitSite::ValenceTwoEdge(VertexId(corners[0].0 .0), VertexId(corners[1].0 .0))
            }
            DualRow::Crease([(a, _), (b, _)]) => DualLimitSite::SharpMidpoint(near(v, a), near(v, b)),
        })
        .collect())
}

/// Adds the row of interior vertex `v` that sums, over its fan faces
/// fᵢ = (V, Eᵢ, …, Eᵢ₊₁), a per-face row `face_row(fᵢ, w)` (w\[j\] is the
/// weight of the corner j places after V, w\[j\] = w\[m − j\]), plus `edge`
/// per edge V Eᵢ and `centre` on the diagonal.
///
/// Each edge neighbour's two face terms are added together first and the
/// edge term after, (w_{fᵢ₋₁}\[m − 1\] + w_{fᵢ}\[1\]) + edge: the same value,
/// bit for bit, that row Eᵢ computes for V (a + b = b + a exactly). So an
/// entry S\[v\]\[u\] receives one contribution per edge or per far corner
/// joining v and u, equal to its mirror's, and the builder's canonical sum of
/// a column that repeats (u both a neighbour and a far corner, on coarse
/// meshes) keeps S symmetric. The diagonal is summed in fan order.
fn add_fan_row(
    t: &Topology,
    v: VertexId,
    rows: &mut RowBuilder,
    edge: f64,
    centre: f64,
    mut face_row: impl FnMut(subdiv_mesh::FaceId, &mut [f64]),
) {
    let fan = t.vertex_fan(v);
    let mut small = [0.0; 16];
    let mut big = Vec::new();
    let mut centre = centre;
    // w_{fᵢ₋₁}[m − 1] for E₀ comes from the last face of the (closed) fan.
    let (mut previous, mut first) = (0.0, 0.0);
    for (i, &h) in fan.iter().enumerate() {
        let corner = t.he_corner(h);
        let face = t.face(corner.face);
        let m = face.len();
        let w: &mut [f64] = if m <= small.len() {
            &mut small[..m]
        } else {
            big.resize(m, 0.0);
            &mut big[..]
        };
        face_row(corner.face, w);
        let k = corner.index as usize;
        let ring = |j: usize| face[if k + j >= m { k + j - m } else { k + j }];
        centre += w[0];
        if i == 0 {
            first = w[1];
        } else {
            rows.add(ring(1), (previous + w[1]) + edge); // Eᵢ ∈ fᵢ₋₁, fᵢ
        }
        for j in 2..m - 1 {
            rows.add(ring(j), w[j]); // far corners of fᵢ
        }
        previous = w[m - 1];
        if i + 1 == fan.len() {
            debug_assert_eq!(ring(m - 1), t.he_to(fan[0]).0, "the fan of an interior vertex is closed");
            rows.add(ring(m - 1), (previous + first) + edge); // E₀ ∈ f_{n−1}, f₀
        }
    }
    rows.add(v.0, centre);
}

/// Cheng's Catmull-Clark A: D = 4/(n(n+5)), S from appendix Eq. 5 ([corrections C1,
/// C2]), assembled as the quadratic form Σ_faces (Σx)²/m + Σ_edges
/// (xᵢ + xⱼ)²/2 + Σ_v n(n−3)/4 x_v² (correct as printed: [Cheng's corrections]).
/// Spectrum ⊂ [0, 1] only when every valence is ≥ 3 (`subdiv_interp::catmull_clark_degeneracy`).
///
/// [corrections C1, C2]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c1
/// [Cheng's corrections]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#cheng-et-al-cfl
pub fn limit_matrix_catmull_clark(t: &Topology) -> LimitMatrix {
    limit_matrix_catmull_clark_sharp(t, &LevelSharpness::plain()).expect("an untagged level has no composed rows")
}

/// Cheng's A with the creases, corners, boundary option and crease method of
/// `sharp` (module docs, "Row kinds"): V × V, row v the limit point of
/// vertex v as [`crate::SubdivisionPlan::limit_stencil`] gives it (to
/// round-off), crease rows (p₋ + 4p + p₊)/6, corners p, general rows composed.
///
/// Smooth rows keep Eq. 5 even next to creases, exactly: Eq. 5 is one step
/// composed with the quad limit mask at v's image, and that step only uses
/// smooth rules at v — v's vertex point (v smooth), the points of its edges
/// (all smooth) and of its faces (centroids, whatever the tags). After it,
/// v's image and its ring (v′, the edge points, the face points) are mapped
/// by the next step onto the next ring by the same smooth rules only, level
/// after level, so the limit of v is the left eigenvector of the smooth
/// ring's subdivision matrix — the quad mask — applied after the first step.
///
/// # Errors
/// Those of refining the levels the general rows compose (as
/// [`crate::SubdivisionPlan::with_tags`]; Catmull-Clark takes every mesh and
/// tag, so none in practice).
pub fn limit_matrix_catmull_clark_sharp(t: &Topology, sharp: &LevelSharpness) -> Result<LimitMatrix, StencilError> {
    Ok(limit_operator_catmull_clark_sharp(t, sharp)?.assemble())
}

/// [`limit_matrix_catmull_clark_sharp`] before assembly: the same D, row
/// kinds and rows ([`LimitOperator::assemble`] gives that matrix bit for
/// bit), S not yet stored.
///
/// # Errors
/// As [`limit_matrix_catmull_clark_sharp`].
pub fn limit_operator_catmull_clark_sharp<'a>(
    t: &'a Topology,
    sharp: &LevelSharpness,
) -> Result<LimitOperator<'a>, StencilError> {
    let d = t
        .vertices()
        .map(|v| {
            let n = t.valence(v) as f64;
            if n > 0.0 {
                4.0 / (n * (n + 5.0))
            } else {
                1.0
            } // D = diag(4/(n(n+5)))
        })
        .collect();
    let (special, kinds) = special_rows(t, sharp, CUBIC_B_SPLINE, Scheme::CatmullClark)?;
    Ok(LimitOperator::new(t, d, special, kinds, move |v, rows| {
        let n = t.valence(v) as f64;
        // Eq. (5): Σᵢ (Fⁱ…)/mᵢ and the 1/mᵢ of the E and V terms; the ½ of
        // (½ + 1/mᵢ + 1/mᵢ₋₁) Eᵢ; n(n−1)/4 V = n(n−3)/4 + n·½ (the edges' ½ at V).
        add_fan_row(t, v, rows, 0.5, n * (n - 1.0) / 4.0, |_, w| w.fill(1.0 / w.len() as f64));
    }))
}

/// The Loop limit matrix L: (1 − kγ) on the diagonal, γ per neighbour, with
/// γ = 1/(k + 3/(8β)) (Deng-Wang Eq. 5-6, [correction W4]): D = γ, S = 3/(8β) on the
/// diagonal and 1 per edge.
///
/// # Errors
/// [`StencilError::NotTriangles`] on a mesh with a non-triangle.
///
/// [correction W4]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w4
pub fn limit_matrix_loop(t: &Topology, beta: LoopBeta) -> Result<LimitMatrix, StencilError> {
    limit_matrix_loop_sharp(t, &LevelSharpness::plain(), beta)
}

/// Loop's L with the creases, corners, boundary option and crease method of
/// `sharp`, as [`limit_matrix_catmull_clark_sharp`]: crease rows
/// (p₋ + 4p + p₊)/6, corners p, general rows composed. Smooth rows keep the
/// limit mask of v's 1-ring: the step maps the ring (v and its neighbours)
/// onto the next ring with v's smooth vertex rule and the smooth edge rule
/// of v's edges only, which read the ring and the triangles at v.
///
/// # Errors
/// [`StencilError::NotTriangles`] on a mesh with a non-triangle.
pub fn limit_matrix_loop_sharp(
    t: &Topology,
    sharp: &LevelSharpness,
    beta: LoopBeta,
) -> Result<LimitMatrix, StencilError> {
    crate::loop_subdivision::require_triangles(t)?;
    let d = t.vertices().map(|v| if t.valence(v) > 0 { beta.gamma(t.valence(v)) } else { 1.0 }).collect(); // W4: γ = 1/(k + 3/(8β))
    let (special, kinds) = special_rows(t, sharp, CUBIC_B_SPLINE, Scheme::Loop(beta))?;
    Ok(assemble(t, d, special, kinds, |v, rows| {
        rows.add(v.0, 3.0 / (8.0 * beta.beta(t.valence(v)))); // (1 − kγ)/γ = 3/(8β)
        t.vertex_neighbors(v).for_each(|e| rows.add(e.0, 1.0));
    }))
}

/// The √3 limit matrix of a control mesh (a base level, whose next step is
/// odd): row v is the limit point (1 − βₙ)v + βₙ/n Σvᵢ of an interior vertex
/// of valence n, D = βₙ/n and S = n(1 − βₙ)/βₙ on the diagonal, 1 per
/// neighbour — symmetric, as Loop's L; boundary rows (p₋ + 4p + p₊)/6 and
/// corner rows p (one-face boundary vertices) as every scheme's. Exact on
/// every vertex of a base level ([`crate::sqrt3`], "Limit points").
///
/// # Errors
/// As [`crate::sqrt3::check`] (triangles, interior valence ≥ 3).
pub fn limit_matrix_sqrt3(t: &Topology) -> Result<LimitMatrix, StencilError> {
    limit_matrix_sqrt3_sharp(t, &LevelSharpness::plain())
}

/// [`limit_matrix_sqrt3`] with the corners and the boundary option of
/// `sharp`, the sharpness of a base level (built by [`LevelSharpness::new`]:
/// its next step is odd): a corner tag (≥ 10 on a boundary vertex) or,
/// under `edge-and-corner`, a one-face boundary vertex gives the identity
/// row; under `edge-only` a one-face boundary vertex keeps the boundary
/// row (p₋ + 4p + p₊)/6, as [`crate::sqrt3`]'s limit stencil. Every row is
/// the limit point of its vertex exactly ([`crate::sqrt3`], "Limit points"),
/// and no row is general: √3 refuses the tags that would make one.
///
/// # Errors
/// As [`crate::sqrt3::check`] (triangles, interior valence ≥ 3, tags other
/// than corners).
pub fn limit_matrix_sqrt3_sharp(t: &Topology, sharp: &LevelSharpness) -> Result<LimitMatrix, StencilError> {
    debug_assert!(!sharp.trisects_next(), "a base level: the masks of an even step's level are not exact");
    crate::sqrt3::check(t, sharp)?;
    let beta = |v: VertexId| subdiv_rules::sqrt3::beta(t.valence(v));
    let d = t.vertices().map(|v| if t.valence(v) > 0 { beta(v) / t.valence(v) as f64 } else { 1.0 }).collect();
    let (special, kinds) = special_rows(t, sharp, CUBIC_B_SPLINE, Scheme::Sqrt3)?;
    Ok(assemble(t, d, special, kinds, |v, rows| {
        let b = beta(v);
        rows.add(v.0, t.valence(v) as f64 * (1.0 - b) / b); // (1 − βₙ)/(βₙ/n)
        t.vertex_neighbors(v).for_each(|e| rows.add(e.0, 1.0));
    }))
}

/// Some rows of a limit matrix, for methods that need the rows of a few
/// vertices only (Deng-Wang reads those of the tagged old vertices of M¹):
/// row i is vertex `vertices[i]`, with its kind, its D entry and its S row
/// (`vertices.len()` × V), equal to those rows of the whole matrix.
///
/// `#[non_exhaustive]`: made by [`limit_rows_loop_sharp`], read through its
/// public fields (a new field is not a breaking change).
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct LimitRows {
    /// The vertices, in the order asked for.
    pub vertices: Vec<u32>,
    /// The kind of each row.
    pub kinds: Vec<RowKind>,
    /// The D entry of each row.
    pub d: Vec<f64>,
    /// The S rows.
    pub s: SparseMatrix,
}

/// Rows `vertices` of [`limit_matrix_loop_sharp`]`(t, sharp, beta)`, built
/// alone: time linear in the rows (and the levels their composed rows need),
/// not in the mesh.
///
/// # Errors
/// [`StencilError::NotTriangles`] on a mesh with a non-triangle.
///
/// # Panics
/// If a vertex is out of range (a caller bug).
pub fn limit_rows_loop_sharp(
    t: &Topology,
    sharp: &LevelSharpness,
    beta: LoopBeta,
    vertices: &[u32],
) -> Result<LimitRows, StencilError> {
    crate::loop_subdivision::require_triangles(t)?;
    let rules: Vec<RowRule> = vertices.iter().map(|&v| row_rule(t, sharp, VertexId(v))).collect();
    let general: Vec<u32> =
        vertices.iter().zip(&rules).filter(|(_, r)| matches!(r, RowRule::General)).map(|(&v, _)| v).collect();
    let composed = if general.is_empty() { None } else { Some(composed_rows(t, sharp, Scheme::Loop(beta), &general)?) };
    let mut next_general = 0;
    let mut rows = RowBuilder::with_capacity(vertices.len(), 8 * vertices.len());
    let (mut kinds, mut d) = (Vec::with_capacity(vertices.len()), Vec::with_capacity(vertices.len()));
    for (&v, rule) in vertices.iter().zip(&rules) {
        let vid = VertexId(v);
        let (kind, dv) = match *rule {
            RowRule::Smooth => {
                // As limit_matrix_loop_sharp's assembly: 3/(8β) on the diagonal, 1 per neighbour.
                rows.add(v, 3.0 / (8.0 * beta.beta(t.valence(vid))));
                t.vertex_neighbors(vid).for_each(|e| rows.add(e.0, 1.0));
                (RowKind::Smooth, beta.gamma(t.valence(vid)))
            }
            RowRule::Crease(a, b) => {
                let mut row = [(a.0, CUBIC_B_SPLINE.end), (v, CUBIC_B_SPLINE.centre), (b.0, CUBIC_B_SPLINE.end)];
                row.sort_by_key(|&(c, _)| c);
                row.iter().for_each(|&(c, w)| rows.add(c, w));
                (RowKind::Crease, CUBIC_B_SPLINE.d)
            }
            RowRule::Corner => {
                rows.add(v, 1.0);
                (RowKind::Corner, 1.0)
            }
            RowRule::General => {
                let m = composed.as_ref().expect("general rows were composed");
                let row = m.outer_view(next_general).expect("one composed row per general vertex");
                row.iter().for_each(|(c, &w)| rows.add(c as u32, w));
                next_general += 1;
                (RowKind::General, 1.0)
            }
        };
        rows.finish_row();
        kinds.push(kind);
        d.push(dv);
    }
    Ok(LimitRows { vertices: vertices.to_vec(), kinds, d, s: rows.build(t.vertex_count()) })
}

/// A basis of the kernel of Cheng's A that the structure gives: one ±1
/// checkerboard vector per closed component whose vertices all have valence
/// 3 and whose vertex graph is bipartite ([correction C3]: A·c = 0 exactly), as
/// (vertex, ±1) over that component's vertices. The range of A is then
/// orthogonal to D⁻¹c (S is symmetric): data P are interpolable only if
/// Σ_v c_v P_v / d_v = 0 for every such c.
///
/// [correction C3]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c3
pub fn catmull_clark_kernel(t: &Topology) -> Vec<Vec<(VertexId, f64)>> {
    // Per component: closed, all valence 3, 2-colourable. One pass marks the
    // components with a boundary or a valence other than 3 (almost all); only
    // the others are walked to test the colouring.
    // The scan stops once no candidate is left (at the first vertex of
    // valence 4 in a one-component mesh).
    let mut candidate = vec![true; t.component_count()];
    let mut left = candidate.len();
    for v in t.vertices().filter(|&v| !t.is_isolated(v)) {
        if t.is_boundary_vertex(v) || t.valence(v) != 3 {
            let c = &mut candidate[t.face_component(t.he_face(t.vertex_fan(v)[0])) as usize];
            left -= usize::from(std::mem::replace(c, false));
            if left == 0 {
                break;
            }
        }
    }
    let mut kernel = Vec::new();
    if left == 0 {
        return kernel;
    }
    let mut colour = vec![u8::MAX; t.vertex_count()];
    let mut stack = Vec::new();
    for start in t.vertices() {
        if colour[start.index()] != u8::MAX
            || t.is_isolated(start)
            || !candidate[t.face_component(t.he_face(t.vertex_fan(start)[0])) as usize]
        {
            continue;
        }
        let mut bipartite = true;
        let mut component = Vec::new();
        colour[start.index()] = 0;
        stack.push(start);
        while let Some(v) = stack.pop() {
            component.push((v, if colour[v.index()] == 0 { 1.0 } else { -1.0 }));
            for w in t.vertex_neighbors(v) {
                if colour[w.index()] == u8::MAX {
                    colour[w.index()] = 1 - colour[v.index()];
                    stack.push(w);
                } else if colour[w.index()] == colour[v.index()] {
                    bipartite = false;
                }
            }
        }
        if bipartite {
            component.sort_by_key(|&(v, _)| v);
            kernel.push(component);
        }
    }
    kernel
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::shapes;

    /// The rows the operator streams are the stored rows, bit for bit: on a
    /// closed mesh of mixed polygons (assembled rows only) and on an open
    /// grid with a semi-sharp crease and a corner (crease, corner and
    /// composed rows too).
    #[test]
    fn streamed_rows_are_the_assembled_rows_bit_for_bit() {
        use subdiv_mesh::{EdgeTag, TagList, Tags, VertexTag};
        let mix = shapes::polygon_mix(&shapes::torus(9, 7), 3, 0.2, 0.2, 0.1);
        let grid = shapes::quad_grid(6, 5);
        let list = TagList {
            creases: vec![
                EdgeTag { a: id(1, 2), b: id(2, 2), sharpness: 1.5 },
                EdgeTag { a: id(2, 2), b: id(3, 2), sharpness: 10.0 },
            ],
            corners: vec![VertexTag { vertex: id(4, 4), sharpness: 10.0 }],
            ..Default::default()
        };
        let tags = Tags::from_list(grid.topology(), &list).unwrap();
        let cases = [
            (mix.topology(), LevelSharpness::plain()),
            (grid.topology(), LevelSharpness::new(&tags, Default::default(), Default::default())),
        ];
        for (t, sharp) in cases {
            let op = limit_operator_catmull_clark_sharp(t, &sharp).unwrap();
            let (d, kinds) = (op.d().to_vec(), op.row_kinds().to_vec());
            let mut streamed = Vec::new();
            op.for_each_row(0..op.size(), &mut |v, c, w| streamed.push((v, c.to_vec(), w.to_vec())));
            let a = op.assemble();
            let stored = limit_matrix_catmull_clark_sharp(t, &sharp).unwrap();
            assert_eq!(a.d, stored.d);
            assert_eq!((d, kinds), (stored.d.clone(), stored.row_kinds.clone()));
            assert_eq!(streamed.len(), stored.size());
            for (v, columns, values) in streamed {
                let row = stored.s.outer_view(v).unwrap();
                assert_eq!(columns, row.indices(), "row {v}");
                let bits = |w: &[f64]| w.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&values), bits(row.data()), "row {v}");
            }
        }
    }

    /// Vertex (i, j) of `shapes::quad_grid(6, 5)`.
    fn id(i: u32, j: u32) -> u32 {
        j * 7 + i
    }

    /// Regression: of the faces of vertex (2, 2), the crop around (1, 0) and
    /// (4, 3) keeps two that meet at that vertex alone; it becomes two crop
    /// vertices (Topology::new refuses the pinched one), and the tracked
    /// vertices and their neighbours keep their whole fans in their order.
    #[test]
    fn crop_splits_a_pinched_rim_vertex() {
        let grid = shapes::quad_grid(6, 5);
        let t = grid.topology();
        let tracked = [id(1, 0), id(4, 3)];
        let crop = crop(t, &LevelSharpness::plain(), &tracked);
        assert_eq!(&crop.to_level[..2], &tracked);
        let copies = crop.to_level.iter().filter(|&&v| v == id(2, 2)).count();
        assert_eq!(copies, 2, "(2, 2) is split into its two pieces");
        for (c, &v) in crop.to_level.iter().enumerate() {
            let near = tracked.iter().any(|&g| g == v || t.vertex_neighbors(VertexId(g)).any(|u| u.0 == v));
            if near {
                let (crop_fan, fan) = (crop.topology.vertex_fan(VertexId(c as u32)), t.vertex_fan(VertexId(v)));
                let ends = |t: &Topology, to: &dyn Fn(u32) -> u32, fan: &[subdiv_mesh::HalfEdgeId]| -> Vec<u32> {
                    fan.iter().map(|&h| to(t.he_to(h).0)).collect()
                };
                let in_level = |x: u32| crop.to_level[x as usize];
                assert_eq!(ends(&crop.topology, &in_level, crop_fan), ends(t, &|x| x, fan), "fan of {v}");
            }
        }
    }
}
