//! Limit-point matrices in the factored form **A = D·S** (SPEC §3).
//!
//! Row v of A maps the control points X to the limit point that the method
//! associates with vertex v; interpolation solves A·X = P. Every matrix is
//! built directly from the topology as a diagonal D (positive) and a sparse S
//! that is **exactly symmetric** (entry by entry, bit for bit) on closed
//! meshes — assembled from symmetric per-face / per-edge contributions
//! (each entry sums the same multiset of face/edge contributions in a
//! canonical order), never by symmetrising afterwards.
//!
//! | builder | method, first step | D | S (interior vertex v, valence n, faces fᵢ of size mᵢ) |
//! |---|---|---|---|
//! | [`limit_matrix_nasri`] | Nasri, standard Doo-Sabin | 1/n | Σ_f Circ(α_{m_f}) (Zheng-Cai Eq. 1; ERRATA Z8) |
//! | [`limit_matrix_zheng_cai`] | Zheng-Cai Eq. 4 | 1/n | B(½): Eq. 6 divided by 2n (ERRATA Z7) |
//! | [`limit_matrix_two_phase`] | Fan-Cheng-Lai Eq. 1, λ per face | 1/n | Σ_f [λ_f I + (1 − λ_f) J/m_f] (Eq. 2 with ERRATA F1, Eq. 5) |
//! | [`limit_matrix_catmull_clark`] | Cheng, Catmull-Clark | 4/(n(n+5)) | appendix Eq. 5 bracket (ERRATA C1, C2) |
//! | [`limit_matrix_loop`] | Loop | γ = 1/(k + 3/(8β)) | 3/(8β) on the diagonal, 1 per neighbour (Deng-Wang Eq. 5-6, ERRATA W4) |
//!
//! **Valence 2 (Doo-Sabin).** An interior vertex of valence 2 has no V-face
//! after the first step (it would be a digon); its row is the centroid of the
//! second-level E-face of the edge between its two images,
//! ⅜(v₀ + v₁) + 1/16·(a₀ + a₁ + b₀ + b₁) on the first step's images
//! (`subdiv_rules::doo_sabin`, "Interior vertices of valence 2"). That row is
//! not of the Circ form, so S is not symmetric when such vertices exist and
//! the solvers need a nonsymmetric method for the interior block.
//!
//! **Boundaries.** On open meshes the rows of boundary vertices follow the
//! boundary curve, which depends on boundary vertices only: Catmull-Clark and
//! Loop (p₋ + 4p + p₊)/6 (D = 1/6, S = (1, 4, 1)), corners p (D = S = 1);
//! Doo-Sabin (B₋ + 6V + B₊)/8 (D = 1/8, S = (1, 6, 1)) — the point of the
//! quadratic B-spline boundary at V, which the Chaikin boundary rule of
//! [`crate::doo_sabin`] produces for the standard and the two-phase first
//! steps alike. Such rows are listed in [`LimitMatrix::boundary_rows`]; they
//! make S unsymmetric only in the coupling *from* interior rows *to*
//! boundary columns, so A is block lower-triangular after ordering boundary
//! vertices first: the boundary block and the interior block are each of the
//! symmetric D·S form, and solvers handle open meshes in two symmetric stages
//! (boundary first, then the interior with the boundary known).

use crate::doo_sabin::CornerRule;
use crate::{apply, face_ring_size, RowBuilder, SparseMatrix, StencilError, Summation};
use glam::DVec3;
use subdiv_mesh::{Topology, VertexId};
use subdiv_rules::doo_sabin::BOUNDARY_CURVE_POINT;
use subdiv_rules::LoopBeta;

/// A limit matrix A = D·S with its boundary rows marked.
#[derive(Clone, Debug)]
pub struct LimitMatrix {
    /// The positive diagonal D, one entry per vertex.
    pub d: Vec<f64>,
    /// S: symmetric among rows not listed in `boundary_rows`, except, in the
    /// Doo-Sabin matrices, the rows of interior vertices of valence 2 (their
    /// limit point is a second-level E-face centroid, not a V-face's: see
    /// [`crate::doo_sabin::valence_two_corners`]).
    pub s: SparseMatrix,
    /// Vertices (ascending) whose rows are boundary, corner or isolated-vertex
    /// rules rather than the symmetric assembly.
    pub boundary_rows: Vec<u32>,
}

impl LimitMatrix {
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
}

/// Rows that do not come from the symmetric assembly, with their D entry.
struct SpecialRows {
    d: Vec<(u32, f64)>,
    rows: Vec<(u32, Vec<(u32, f64)>)>,
}

/// Boundary rows (w₋, w, w₊)·scale with D = 1/scale, corners (when
/// `corner_fixed`) and isolated vertices as identity rows.
fn special_rows(t: &Topology, curve: [f64; 3], curve_d: f64, corner_fixed: bool) -> SpecialRows {
    let mut out = SpecialRows { d: Vec::new(), rows: Vec::new() };
    for v in t.vertices() {
        let identity = t.is_isolated(v) || (corner_fixed && t.is_boundary_vertex(v) && t.vertex_face_count(v) == 1);
        if identity {
            out.d.push((v.0, 1.0));
            out.rows.push((v.0, vec![(v.0, 1.0)]));
        } else if let Some((prev, next)) = t.boundary_neighbors(v) {
            out.d.push((v.0, curve_d));
            let mut row = vec![(prev.0, curve[0]), (v.0, curve[1]), (next.0, curve[2])];
            row.sort_by_key(|&(c, _)| c);
            out.rows.push((v.0, row));
        }
    }
    out
}

/// Builds A = D·S row by row (in parallel, deterministically): `row(v, rows)`
/// adds the contributions of vertex v's row; rows listed in `special` are
/// taken from there instead. Each row's contributions are summed in ascending
/// order of their bits ([`Summation::Canonical`]), so an entry's value depends
/// only on the multiset of its contributions: S\[i\]\[j\] and S\[j\]\[i\],
/// which receive the same contributions (a face or an edge containing both),
/// are equal bit for bit.
fn assemble(
    t: &Topology,
    mut d: Vec<f64>,
    special: SpecialRows,
    row: impl Fn(VertexId, &mut RowBuilder) + Sync,
) -> LimitMatrix {
    let n = t.vertex_count();
    let mut special_of = vec![u32::MAX; n];
    for (k, (v, _)) in special.rows.iter().enumerate() {
        special_of[*v as usize] = k as u32;
    }
    // Every row's columns lie in its vertex's face ring.
    let max_len = |v: usize| match special_of[v] {
        u32::MAX => face_ring_size(t, VertexId(v as u32)),
        k => special.rows[k as usize].1.len(),
    };
    let s =
        RowBuilder::build_parallel_bounded(n, n, Summation::Canonical, max_len, |v, rows, _: &mut ()| match special_of
            [v]
        {
            u32::MAX => row(VertexId(v as u32), rows),
            k => special.rows[k as usize].1.iter().for_each(|&(c, w)| rows.add(c, w)),
        });
    for &(v, dv) in &special.d {
        d[v as usize] = dv;
    }
    let boundary_rows = special.rows.iter().map(|(v, _)| *v).collect();
    LimitMatrix { d, s, boundary_rows }
}

/// Doo-Sabin family: row v = (1/n)·Σ over v's faces of that face's first-step
/// row at v's corner, i.e. the centroid of v's V-face after the first step.
fn limit_matrix_doo_sabin(t: &Topology, rule: CornerRule<'_>) -> Result<LimitMatrix, StencilError> {
    rule.validate(t)?;
    let d = t.vertices().map(|v| 1.0 / t.vertex_face_count(v).max(1) as f64).collect(); // Σ = diag(1/n)
    let [a, b, c] = BOUNDARY_CURVE_POINT;
    let special = special_rows(t, [a * 8.0, b * 8.0, c * 8.0], 0.125, false);
    Ok(assemble(t, d, special, |v, rows| {
        if let Some(corners) = crate::doo_sabin::valence_two_corners(t, v) {
            // No V-face: the valence-2 mask on the first step's images (the
            // second-level E-face centroid), ×n = 2 since D = 1/n. Not of the
            // Circ form: S loses its symmetry in this row.
            crate::doo_sabin::add_valence_two_row(t, &corners, rule, 2.0, rows, &mut Vec::new());
            return;
        }
        // Zheng-Cai Eq. (1) / (4), Fan-Cheng-Lai Eq. (1). Face block Circ(w):
        // symmetric because w[k] = w[m − k] (α depends on cos only).
        add_fan_row(t, v, rows, 0.0, 0.0, |face, w| rule.weights(face.index(), w));
    }))
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

/// Nasri's C: standard Doo-Sabin, limit of vertex v = centroid of its V-face
/// after one step. Spectrum ⊂ [¼, 1] on closed manifold meshes (ERRATA Z8).
pub fn limit_matrix_nasri(t: &Topology) -> LimitMatrix {
    limit_matrix_doo_sabin(t, CornerRule::Standard).expect("the standard rule has no parameters")
}

/// Zheng-Cai's Z: first step Eq. 4, V' = (V + A)/2; Eq. 6 divided by 2n,
/// equal to B(½). Strictly diagonally dominant, spectrum ⊂ [½, 1] (ERRATA Z7).
pub fn limit_matrix_zheng_cai(t: &Topology) -> LimitMatrix {
    limit_matrix_doo_sabin(t, CornerRule::Uniform(0.5)).expect("λ = ½ is valid")
}

/// Fan-Cheng-Lai's B(λ): two-phase first step with λ per face (Eq. 2, Eq. 5).
/// Spectrum ⊂ [min λ, 1] (ERRATA F6).
pub fn limit_matrix_two_phase(t: &Topology, rule: CornerRule<'_>) -> Result<LimitMatrix, StencilError> {
    limit_matrix_doo_sabin(t, rule)
}

/// Cheng's Catmull-Clark A: D = 4/(n(n+5)), S from appendix Eq. 5 (ERRATA C1,
/// C2), assembled as the quadratic form Σ_faces (Σx)²/m + Σ_edges
/// (xᵢ + xⱼ)²/2 + Σ_v n(n−3)/4 x_v² (ERRATA, "correct as printed").
/// Spectrum ⊂ [0, 1] only when every valence is ≥ 3 ([`catmull_clark_degeneracy`]).
pub fn limit_matrix_catmull_clark(t: &Topology) -> LimitMatrix {
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
    let special = special_rows(t, [1.0, 4.0, 1.0], 1.0 / 6.0, true);
    assemble(t, d, special, |v, rows| {
        let n = t.valence(v) as f64;
        // Eq. (5): Σᵢ (Fⁱ…)/mᵢ and the 1/mᵢ of the E and V terms; the ½ of
        // (½ + 1/mᵢ + 1/mᵢ₋₁) Eᵢ; n(n−1)/4 V = n(n−3)/4 + n·½ (the edges' ½ at V).
        add_fan_row(t, v, rows, 0.5, n * (n - 1.0) / 4.0, |_, w| w.fill(1.0 / w.len() as f64));
    })
}

/// The Loop limit matrix L: (1 − kγ) on the diagonal, γ per neighbour, with
/// γ = 1/(k + 3/(8β)) (Deng-Wang Eq. 5-6, ERRATA W4): D = γ, S = 3/(8β) on the
/// diagonal and 1 per edge.
pub fn limit_matrix_loop(t: &Topology, beta: LoopBeta) -> Result<LimitMatrix, StencilError> {
    if let Some(f) = t.face_ids().find(|&f| t.face_size(f) != 3) {
        return Err(StencilError::NotTriangles { face: f.0, size: t.face_size(f) });
    }
    let d = t.vertices().map(|v| if t.valence(v) > 0 { beta.gamma(t.valence(v)) } else { 1.0 }).collect(); // W4: γ = 1/(k + 3/(8β))
    let special = special_rows(t, [1.0, 4.0, 1.0], 1.0 / 6.0, true);
    Ok(assemble(t, d, special, |v, rows| {
        rows.add(v.0, 3.0 / (8.0 * beta.beta(t.valence(v)))); // (1 − kγ)/γ = 3/(8β)
        t.vertex_neighbors(v).for_each(|e| rows.add(e.0, 1.0));
    }))
}

/// Why Cheng's A cannot be inverted safely on a mesh (SPEC §3, ERRATA C3).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Degeneracy {
    /// A closed component whose vertices all have valence 3 and whose vertex
    /// graph is bipartite (the cube, even prisms): the ±1 checkerboard vector
    /// on that component is in the kernel of A, exactly.
    Singular {
        /// A vertex of the component.
        vertex: VertexId,
    },
    /// An interior vertex of valence 2: the term n(n−3)/4 of S is negative
    /// there, which voids the proof that A is positive definite, and A may be
    /// indefinite. Measured: a lone valence-2 vertex between two quads leaves
    /// it definite (λ_min ≈ 0.098 on a 24 × 16 torus), two adjacent ones give
    /// a negative eigenvalue (≈ −0.023), the pillow λ_min = −1/7; solvers
    /// must treat A as possibly indefinite (MINRES, LDLᵀ).
    Indefinite {
        /// The valence-2 vertex.
        vertex: VertexId,
    },
}

/// Structural test for the two known ways Cheng's A fails to be positive
/// definite. `None` means every interior valence is ≥ 3 and no closed
/// component is an all-valence-3 bipartite mesh (A is then nonsingular in
/// every case we know; its spectrum lies in (0, 1]).
pub fn catmull_clark_degeneracy(t: &Topology) -> Option<Degeneracy> {
    if let Some(v) = t.vertices().find(|&v| !t.is_boundary_vertex(v) && t.vertex_face_count(v) == 2) {
        return Some(Degeneracy::Indefinite { vertex: v });
    }
    catmull_clark_kernel(t).first().map(|c| Degeneracy::Singular { vertex: c[0].0 })
}

/// A basis of the kernel of Cheng's A that the structure gives: one ±1
/// checkerboard vector per closed component whose vertices all have valence
/// 3 and whose vertex graph is bipartite (ERRATA C3: A·c = 0 exactly), as
/// (vertex, ±1) over that component's vertices. The range of A is then
/// orthogonal to D⁻¹c (S is symmetric): data P are interpolable only if
/// Σ_v c_v P_v / d_v = 0 for every such c.
pub fn catmull_clark_kernel(t: &Topology) -> Vec<Vec<(VertexId, f64)>> {
    // Per component: closed, all valence 3, 2-colourable. One pass marks the
    // components with a boundary or a valence other than 3 (almost all); only
    // the others are walked to test the colouring.
    let mut candidate = vec![true; t.component_count()];
    for v in t.vertices().filter(|&v| !t.is_isolated(v)) {
        if t.is_boundary_vertex(v) || t.valence(v) != 3 {
            candidate[t.face_component(t.he_face(t.vertex_fan(v)[0])) as usize] = false;
        }
    }
    let mut kernel = Vec::new();
    if !candidate.contains(&true) {
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
