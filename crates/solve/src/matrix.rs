//! The input type: a limit matrix in factored form A = D·S.
//!
//! Every limit matrix of the project is A = D·S with D diagonal positive and
//! S symmetric ([limit matrices]; Cheng's appendix, Fan-Cheng-Lai §4). The symmetric
//! form is what makes CG, LDLᵀ and Lanczos applicable: A·x = p ⇔ S·x = D⁻¹p,
//! and D^{1/2}·S·D^{1/2} is a symmetric matrix similar to A.
//!
//! [limit matrices]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-limit-matrices-and-the-stopping-rule

use crate::error::SolveError;
use crate::kernels::{self, Csr, Row};
use crate::tolerances::{JACOBI_FALLBACK_RTOL, SYMMETRY_RTOL};

/// Sparse matrix type of the workspace: CSR, `f64` values, `u32` indices
/// (the alias `subdiv-stencil` uses).
pub type SparseMatrix = sprs::CsMatI<f64, u32>;

/// A validated square matrix A = D·S: D diagonal with finite positive
/// entries, S sparse (CSR) with finite entries, plus whether S is symmetric.
///
/// n × n; row i gives the limit point of control point i:
/// (A·X)_i = d_i · Σ_j s_ij X_j.
///
/// The fields are private so that a `FactoredMatrix` that exists is valid
/// ("validate once, then trust the type"); [`into_parts`](Self::into_parts)
/// gives them back.
#[derive(Clone, Debug)]
pub struct FactoredMatrix {
    d: Vec<f64>,
    s: SparseMatrix,
    /// `None` when S is symmetric; otherwise why it is not.
    asymmetry: Option<String>,
}

impl FactoredMatrix {
    /// Validates and wraps A = diag(d)·S.
    ///
    /// S is converted to CSR if it is stored as CSC. Symmetry of S is checked
    /// entry by entry (relative tolerance
    /// 10⁻¹⁰ of the largest |s_kl|, `SYMMETRY_RTOL`); a non-symmetric S is accepted —
    /// open-mesh limit matrices have non-symmetric boundary rows — but flagged,
    /// and the solvers that need symmetry (CG, LDLᵀ, Lanczos and the ones that
    /// use it: weighted PIA, Chebyshev) then return
    /// [`SolveError::NotSymmetric`].
    ///
    /// # Errors
    /// [`SolveError::InvalidInput`] when S is not square, `d.len()` differs
    /// from its size, a d_i is not finite and positive, or an entry of S is
    /// not finite.
    pub fn new(d: Vec<f64>, s: SparseMatrix) -> Result<Self, SolveError> {
        let s = canonical(s)?;
        let n = s.rows();
        if d.len() != n {
            return Err(SolveError::InvalidInput(format!("d has {} entries but S is {n} × {n}", d.len())));
        }
        if let Some(i) = d.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(SolveError::InvalidInput(format!("d[{i}] = {} must be finite and > 0", d[i])));
        }
        let asymmetry =
            first_asymmetry(&s, SYMMETRY_RTOL).map(|(i, j, a, b)| format!("s[{i},{j}] = {a:e} but s[{j},{i}] = {b:e}"));
        Ok(FactoredMatrix { d, s, asymmetry })
    }

    /// Wraps a matrix with no known factorisation: d = 1, S = A, flagged
    /// non-symmetric (whatever its entries), so that only PIA, Jacobi,
    /// Gauss-Seidel and dense LU accept it.
    ///
    /// # Errors
    /// [`SolveError::InvalidInput`] when A is not square or has a non-finite entry.
    pub fn from_general(a: SparseMatrix) -> Result<Self, SolveError> {
        let s = canonical(a)?;
        let d = vec![1.0; s.rows()];
        Ok(FactoredMatrix { d, s, asymmetry: Some("the matrix was built with from_general".to_owned()) })
    }

    /// Number of rows (= columns).
    pub fn n(&self) -> usize {
        self.d.len()
    }

    /// The diagonal of D.
    pub fn d(&self) -> &[f64] {
        &self.d
    }

    /// The matrix S (CSR).
    pub fn s(&self) -> &SparseMatrix {
        &self.s
    }

    /// Number of stored entries of S (= of A).
    pub fn nnz(&self) -> usize {
        self.s.nnz()
    }

    /// Whether S passed the symmetry check (always `false` after
    /// [`from_general`](Self::from_general)).
    pub fn symmetric(&self) -> bool {
        self.asymmetry.is_none()
    }

    /// Re-checks the symmetry of S with a caller-chosen relative tolerance:
    /// |s_ij − s_ji| ≤ tol · max |s_kl| for every stored entry.
    pub fn is_symmetric(&self, tol: f64) -> bool {
        is_symmetric(&self.s, tol)
    }

    /// Gives back (d, S).
    pub fn into_parts(self) -> (Vec<f64>, SparseMatrix) {
        (self.d, self.s)
    }

    /// out = A·x (n × 3), parallel over fixed row chunks (deterministic).
    ///
    /// # Panics
    /// When `x` or `out` does not have n rows (a caller bug).
    pub fn apply(&self, x: &[[f64; 3]], out: &mut [[f64; 3]]) {
        assert_eq!(x.len(), self.n(), "apply: x has {} rows, A is {} × {}", x.len(), self.n(), self.n());
        assert_eq!(out.len(), self.n(), "apply: out has {} rows, A is {} × {}", out.len(), self.n(), self.n());
        let mut partials = vec![(); kernels::n_chunks(self.n())];
        kernels::apply_ds(self.csr(), &self.d, x, out, &mut partials);
    }

    /// max_i ‖P_i − (A·X)_i‖₂, the absolute stopping quantity (divide by the
    /// caller's scale for the relative one).
    ///
    /// # Panics
    /// When `x` or `p` does not have n rows (a caller bug).
    pub fn max_residual(&self, x: &[[f64; 3]], p: &[[f64; 3]]) -> f64 {
        assert_eq!(x.len(), self.n(), "max_residual: x has {} rows, A has {}", x.len(), self.n());
        assert_eq!(p.len(), self.n(), "max_residual: p has {} rows, A has {}", p.len(), self.n());
        let mut partials = vec![0.0; kernels::n_chunks(self.n())];
        kernels::max_residual_sq(self.csr(), &self.d, x, p, &mut partials).sqrt()
    }

    /// The materialised A = D·S (CSR, same pattern as S).
    pub fn to_csr(&self) -> SparseMatrix {
        let indptr = self.s.indptr().raw_storage().to_vec();
        let mut data = self.s.data().to_vec();
        for i in 0..self.n() {
            for v in &mut data[indptr[i] as usize..indptr[i + 1] as usize] {
                *v *= self.d[i];
            }
        }
        SparseMatrix::new(self.s.shape(), indptr, self.s.indices().to_vec(), data)
    }

    /// The raw CSR slices of S.
    pub(crate) fn csr(&self) -> Csr<'_> {
        Csr::new(&self.s)
    }

    /// Diagonal of S (0 where not stored).
    pub(crate) fn s_diagonal(&self) -> Vec<f64> {
        let c = self.csr();
        (0..self.n()).map(|i| c.diag(i)).collect()
    }

    /// Per row, the Jacobi scaling of S: s_ii (|s_ii| unless `keep_sign`),
    /// or the row's 1-norm Σ_j |s_ij| when |s_ii| is not usable
    /// ([`JACOBI_FALLBACK_RTOL`]), 1 for an empty row. Never 0.
    pub(crate) fn jacobi_diagonal(&self, keep_sign: bool) -> Vec<f64> {
        let c = self.csr();
        (0..self.n())
            .map(|i| {
                let norm1: f64 = c.data[c.indptr[i] as usize..c.indptr[i + 1] as usize].iter().map(|v| v.abs()).sum();
                let sii = c.diag(i);
                if sii.abs() > JACOBI_FALLBACK_RTOL * norm1 {
                    if keep_sign {
                        sii
                    } else {
                        sii.abs()
                    }
                } else if norm1 > 0.0 {
                    norm1
                } else {
                    1.0
                }
            })
            .collect()
    }

    /// `Err(NotSymmetric)` for solvers that need a symmetric S.
    pub(crate) fn require_symmetric(&self, solver: &'static str) -> Result<(), SolveError> {
        match &self.asymmetry {
            None => Ok(()),
            Some(detail) => Err(SolveError::NotSymmetric { solver, detail: detail.clone() }),
        }
    }
}

/// Whether S is symmetric entry by entry: |s_ij − s_ji| ≤ tol · max |s_kl|
/// for every stored entry (a missing transpose entry counts as 0).
/// Non-square matrices are not symmetric.
pub fn is_symmetric(s: &SparseMatrix, tol: f64) -> bool {
    if s.rows() != s.cols() {
        return false;
    }
    let s = if s.is_csr() { s.clone() } else { s.to_csr() };
    let s = if s.indptr().raw_storage().first().is_some_and(|&p| p != 0) { rebase(&s) } else { s };
    first_asymmetry(&s, tol).is_none()
}

/// First (in row order) entry violating symmetry: (i, j, s_ij, s_ji).
///
/// Fast path: every entry above the diagonal is compared with its mirror,
/// and the entries below it are counted; when every upper entry has a close
/// mirror and the mirrors found are all the lower entries, S is symmetric.
/// Otherwise every entry is compared with its mirror (a missing one counts
/// as 0) to report the first violation in row order.
fn first_asymmetry(s: &SparseMatrix, tol: f64) -> Option<(usize, usize, f64, f64)> {
    let c = Csr::new(s);
    let n = s.rows();
    let scale = s.data().iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let bound = tol * scale;
    let mirror = |i: usize, j: usize| -> Option<f64> {
        let (lo, hi) = (c.indptr[j] as usize, c.indptr[j + 1] as usize);
        find_sorted(&c.indices[lo..hi], i as u32).map(|q| c.data[lo + q])
    };
    // Per chunk: (every upper entry has a close mirror, mirrors found, lower entries).
    let mut partials = vec![(true, 0usize, 0usize); kernels::n_chunks(n)];
    kernels::reduce_chunks(n, &mut partials, |rows| {
        let (mut found, mut lower) = (0, 0);
        for i in rows {
            for k in c.indptr[i] as usize..c.indptr[i + 1] as usize {
                let j = c.indices[k] as usize;
                if j < i {
                    lower += 1;
                } else if j > i {
                    match mirror(i, j) {
                        Some(b) if (c.data[k] - b).abs() <= bound => found += 1,
                        _ => return (false, found, lower),
                    }
                }
            }
        }
        (true, found, lower)
    });
    let (all_close, found, lower) =
        partials.iter().fold((true, 0, 0), |(ok, f, l), &(o, fc, lc)| (ok && o, f + fc, l + lc));
    if all_close && found == lower {
        return None;
    }
    let mut partials = vec![None; kernels::n_chunks(n)];
    kernels::reduce_chunks(n, &mut partials, |rows| {
        for i in rows {
            for k in c.indptr[i] as usize..c.indptr[i + 1] as usize {
                let j = c.indices[k] as usize;
                let (a, b) = (c.data[k], mirror(i, j).unwrap_or(0.0));
                if (a - b).abs() > bound {
                    return Some((i, j, a, b));
                }
            }
        }
        None
    });
    partials.into_iter().flatten().next()
}

/// Position of `column` in a row's sorted column list: a linear scan for the
/// short rows of limit matrices (a handful of entries: fewer instructions
/// than bisection), bisection for long ones.
fn find_sorted(row: &[u32], column: u32) -> Option<usize> {
    if row.len() <= 16 {
        let q = row.iter().take_while(|&&c| c < column).count();
        (row.get(q) == Some(&column)).then_some(q)
    } else {
        row.binary_search(&column).ok()
    }
}

/// CSR with indptr starting at 0, square, finite.
fn canonical(s: SparseMatrix) -> Result<SparseMatrix, SolveError> {
    if s.rows() != s.cols() {
        return Err(SolveError::InvalidInput(format!("the matrix is {} × {}, not square", s.rows(), s.cols())));
    }
    let s = if s.is_csr() { s } else { s.to_csr() };
    let s = if s.indptr().raw_storage().first().is_some_and(|&p| p != 0) { rebase(&s) } else { s };
    if let Some(k) = s.data().iter().position(|v| !v.is_finite()) {
        let c = Csr::new(&s);
        let row = c.indptr.partition_point(|&p| p as usize <= k) - 1;
        return Err(SolveError::InvalidInput(format!(
            "entry ({row}, {}) of the matrix is {}",
            c.indices[k],
            s.data()[k]
        )));
    }
    Ok(s)
}

/// Copy with indptr rebased to start at 0 (sprs allows offset views).
fn rebase(s: &SparseMatrix) -> SparseMatrix {
    let ip = s.indptr();
    let raw = ip.raw_storage();
    let base = raw[0] as usize;
    let end = raw[raw.len() - 1] as usize;
    let indptr: Vec<u32> = raw.iter().map(|&p| p - raw[0]).collect();
    let indices = s.indices()[..end - base].to_vec();
    let data = s.data()[..end - base].to_vec();
    SparseMatrix::new(s.shape(), indptr, indices, data)
}

/// Checks shared by every solver: right-hand side and options.
pub(crate) fn validate(a: &FactoredMatrix, p: &[Row], opts: &crate::SolveOptions) -> Result<(), SolveError> {
    validate_parts(a.n(), p, opts)
}

/// [`validate`] for an n × n matrix that is not stored.
pub(crate) fn validate_parts(n: usize, p: &[Row], opts: &crate::SolveOptions) -> Result<(), SolveError> {
    if p.len() != n {
        return Err(SolveError::InvalidInput(format!("the right-hand side has {} rows, the matrix {n}", p.len())));
    }
    if let Some(i) = p.iter().position(|r| !r.iter().all(|v| v.is_finite())) {
        return Err(SolveError::InvalidInput(format!("right-hand side row {i} = {:?} is not finite", p[i])));
    }
    if !(opts.tol.is_finite() && opts.tol > 0.0) {
        return Err(SolveError::InvalidInput(format!("tol = {} must be finite and > 0", opts.tol)));
    }
    if !(opts.scale.is_finite() && opts.scale > 0.0) {
        return Err(SolveError::InvalidInput(format!("scale = {} must be finite and > 0", opts.scale)));
    }
    if let Some(x0) = &opts.initial {
        if x0.len() != n {
            return Err(SolveError::InvalidInput(format!("the initial guess has {} rows, the matrix {n}", x0.len())));
        }
        if let Some(i) = x0.iter().position(|r| !r.iter().all(|v| v.is_finite())) {
            return Err(SolveError::InvalidInput(format!("initial guess row {i} = {:?} is not finite", x0[i])));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use sprs::TriMatI;

    fn mat(n: usize, entries: &[(usize, usize, f64)]) -> SparseMatrix {
        let mut t = TriMatI::<f64, u32>::new((n, n));
        for &(i, j, v) in entries {
            t.add_triplet(i, j, v);
        }
        t.to_csr()
    }

    #[test]
    fn validation_rejects_bad_d_and_shapes() {
        let s = mat(2, &[(0, 0, 2.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 2.0)]);
        assert!(FactoredMatrix::new(vec![1.0, 0.0], s.clone()).is_err());
        assert!(FactoredMatrix::new(vec![1.0, f64::NAN], s.clone()).is_err());
        assert!(FactoredMatrix::new(vec![1.0], s.clone()).is_err());
        let a = FactoredMatrix::new(vec![1.0, 2.0], s).unwrap();
        assert!(a.symmetric());
        let rect = SparseMatrix::new((2, 3), vec![0, 1, 1], vec![0], vec![1.0]);
        assert!(matches!(FactoredMatrix::from_general(rect), Err(SolveError::InvalidInput(_))));
        let nan = mat(2, &[(0, 0, f64::NAN), (1, 1, 1.0)]);
        let e = FactoredMatrix::from_general(nan).unwrap_err();
        assert!(e.to_string().contains("(0, 0)"), "{e}");
    }

    #[test]
    fn symmetry_is_checked_entry_by_entry() {
        let s = mat(3, &[(0, 0, 2.0), (0, 1, 1.0), (1, 0, 1.0 + 1e-6), (1, 1, 2.0), (2, 2, 1.0)]);
        let a = FactoredMatrix::new(vec![1.0; 3], s).unwrap();
        assert!(!a.symmetric());
        assert!(a.is_symmetric(1e-5));
        assert!(!a.is_symmetric(1e-8));
        // A structurally missing transpose entry is a violation.
        let s = mat(2, &[(0, 0, 1.0), (0, 1, 0.5), (1, 1, 1.0)]);
        assert!(!is_symmetric(&s, 1e-3));
        // Below the diagonal too, unless the lone entry is within the tolerance.
        assert!(!is_symmetric(&mat(2, &[(0, 0, 1.0), (1, 0, 0.5), (1, 1, 1.0)]), 1e-3));
        assert!(is_symmetric(&mat(2, &[(0, 0, 1.0), (1, 0, 1e-20), (1, 1, 1.0)]), 1e-3));
        // The first violation in row order is reported, wherever the fast check stops.
        let s = mat(3, &[(0, 0, 1.0), (0, 2, 0.5), (1, 0, 0.3), (1, 1, 1.0), (2, 0, 0.5), (2, 2, 1.0)]);
        assert_eq!(first_asymmetry(&s, 1e-12), Some((1, 0, 0.3, 0.0)));
        let g = FactoredMatrix::from_general(mat(1, &[(0, 0, 1.0)])).unwrap();
        assert!(!g.symmetric());
    }

    #[test]
    fn apply_and_to_csr_agree() {
        let s = mat(3, &[(0, 0, 4.0), (0, 2, 1.0), (1, 1, 3.0), (2, 0, 1.0), (2, 2, 5.0)]);
        let a = FactoredMatrix::new(vec![0.5, 2.0, 0.25], s).unwrap();
        let x = [[1.0, 2.0, 3.0], [-1.0, 0.0, 1.0], [0.5, 0.5, 0.5]];
        let mut out = [[0.0; 3]; 3];
        a.apply(&x, &mut out);
        let dense = a.to_csr().to_dense();
        for i in 0..3 {
            for c in 0..3 {
                let want: f64 = (0..3).map(|j| dense[[i, j]] * x[j][c]).sum();
                assert!((out[i][c] - want).abs() < 1e-14);
            }
        }
        assert_eq!(out[0], [0.5 * (4.0 + 0.5), 0.5 * (8.0 + 0.5), 0.5 * (12.0 + 0.5)]);
        assert!(a.max_residual(&x, &out) < 1e-15);
    }

    #[test]
    fn csc_input_is_converted() {
        let s = mat(2, &[(0, 0, 2.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 2.0)]).to_csc();
        let a = FactoredMatrix::new(vec![1.0, 1.0], s).unwrap();
        assert!(a.s().is_csr());
    }
}
