//! Conjugate gradients on a symmetric positive semidefinite operator given
//! as a closure, three columns (x, y, z) at once, Jacobi-preconditioned:
//! the normal equations of the fair method's least-squares problems
//! (`GᵀG·y = −Gᵀg₀`, `(AᵀA + w·BᵀB)·X = AᵀP`), which are never assembled.
//!
//! Hestenes-Stiefel CG with a diagonal preconditioner (Saad, *Iterative
//! methods for sparse linear systems*, Alg. 9.1); each column has its own
//! step lengths, so the three solves are independent and only share the
//! products. Stops when every column's residual is at most `rtol` times its
//! right-hand side's norm. Unlike `subdiv_solve`'s solvers, whose stopping
//! quantity is the interpolation residual of a limit matrix, the stopping
//! quantity here is the residual of an optimality condition: the fair
//! method's interpolation error does not depend on it (the constraints are
//! eliminated exactly), only how close the energy is to its minimum.

use glam::DVec3;
use rayon::prelude::*;

/// The end of a CG run.
pub(crate) struct CgRun {
    /// The last iterate.
    pub x: Vec<DVec3>,
    /// Iterations done.
    pub iterations: usize,
    /// Operator products (one per iteration, one for the initial residual).
    pub products: usize,
    /// max over the columns of ‖r‖ / ‖b‖ at the end.
    pub residual: f64,
    /// The same after every iteration.
    pub history: Vec<f64>,
    /// True when `residual ≤ rtol`.
    pub converged: bool,
}

/// The rows of one parallel task in the vector operations: sums are taken
/// per fixed chunk and the partial sums added in order, so every result is
/// the same bit for bit whatever the thread count.
const CHUNK: usize = 8192;

fn dot(a: &[DVec3], b: &[DVec3]) -> DVec3 {
    let partials: Vec<DVec3> = a
        .par_chunks(CHUNK)
        .zip(b.par_chunks(CHUNK))
        .map(|(a, b)| a.iter().zip(b).fold(DVec3::ZERO, |acc, (u, v)| acc + *u * *v))
        .collect();
    partials.into_iter().fold(DVec3::ZERO, |acc, p| acc + p)
}

/// Per column: a / b, 0 where b is 0 (a column that is already solved).
fn ratio(a: DVec3, b: DVec3) -> DVec3 {
    let f = |a: f64, b: f64| if b != 0.0 { a / b } else { 0.0 };
    DVec3::new(f(a.x, b.x), f(a.y, b.y), f(a.z, b.z))
}

/// Solves `apply(x) = b` from `x` (`apply(x, out)` writes the product into
/// `out`), preconditioned by the diagonal `diag`
/// (entries ≤ 0 are treated as 1).
pub(crate) fn pcg(
    mut apply: impl FnMut(&[DVec3], &mut [DVec3]),
    diag: &[f64],
    b: &[DVec3],
    mut x: Vec<DVec3>,
    rtol: f64,
    max_iter: usize,
) -> CgRun {
    let inv: Vec<f64> = diag.iter().map(|&d| if d > 0.0 { 1.0 / d } else { 1.0 }).collect();
    let b_norm = {
        let s = dot(b, b);
        DVec3::new(s.x.sqrt(), s.y.sqrt(), s.z.sqrt())
    };
    let rel = |r: &[DVec3]| -> f64 {
        let s = dot(r, r);
        let f = |s: f64, n: f64| {
            if n > 0.0 {
                s.sqrt() / n
            } else if s == 0.0 {
                0.0
            } else {
                f64::INFINITY
            }
        };
        f(s.x, b_norm.x).max(f(s.y, b_norm.y)).max(f(s.z, b_norm.z))
    };
    let mut q = vec![DVec3::ZERO; x.len()];
    apply(&x, &mut q);
    let mut r: Vec<DVec3> = b.iter().zip(&q).map(|(b, a)| *b - *a).collect();
    let mut z: Vec<DVec3> = r.iter().zip(&inv).map(|(r, w)| *r * *w).collect();
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let mut residual = rel(&r);
    let mut history = Vec::new();
    let mut iterations = 0;
    while residual > rtol && iterations < max_iter {
        apply(&p, &mut q);
        let alpha = ratio(rz, dot(&p, &q));
        x.par_iter_mut().zip(r.par_iter_mut()).zip(p.par_iter().zip(&q)).for_each(|((x, r), (p, q))| {
            *x += alpha * *p;
            *r -= alpha * *q;
        });
        z.par_iter_mut().zip(&r).zip(&inv).for_each(|((z, r), w)| *z = *r * *w);
        let rz_next = dot(&r, &z);
        let beta = ratio(rz_next, rz);
        rz = rz_next;
        p.par_iter_mut().zip(&z).for_each(|(p, z)| *p = *z + beta * *p);
        iterations += 1;
        residual = rel(&r);
        history.push(residual);
        if !residual.is_finite() {
            break;
        }
    }
    CgRun { x, iterations, products: iterations + 1, residual, history, converged: residual <= rtol }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_small_spd_system_column_by_column() {
        // The 1D Laplacian plus identity, n = 50, three different right-hand sides.
        let n = 50;
        let apply = |x: &[DVec3], out: &mut [DVec3]| {
            for (i, o) in out.iter_mut().enumerate() {
                let left = if i > 0 { x[i - 1] } else { DVec3::ZERO };
                let right = if i + 1 < n { x[i + 1] } else { DVec3::ZERO };
                *o = 3.0 * x[i] - left - right;
            }
        };
        let b: Vec<DVec3> = (0..n).map(|i| DVec3::new(1.0, i as f64, if i == 7 { 1.0 } else { 0.0 })).collect();
        let run = pcg(apply, &[3.0; 50], &b, vec![DVec3::ZERO; n], 1e-12, 200);
        assert!(run.converged);
        let mut back = vec![DVec3::ZERO; n];
        apply(&run.x, &mut back);
        for (u, v) in back.iter().zip(&b) {
            assert!((*u - *v).length() < 1e-9 * (1.0 + v.length()));
        }
    }
}
