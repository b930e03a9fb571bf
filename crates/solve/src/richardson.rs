//! The fused Richardson sweep shared by PIA, weighted PIA and Jacobi:
//! X_{k+1,i} = X_{k,i} + w_i (P_i − (A X_k)_i), with the max row residual of
//! X_k computed in the same pass.
//!
//! One pass per iteration reads S (12 bytes per entry), gathers X_k, reads
//! P and d, and writes X_{k+1} into a second buffer (the update needs the
//! old values of every neighbour, so it cannot be in place); the buffers
//! are swapped. No allocation inside the loop.

use std::time::Instant;

use crate::error::SolveError;
use crate::kernels::{self, map_chunks, max_nan, norm2, Row};
use crate::matrix::{validate, FactoredMatrix};
use crate::report::{initial_guess, Monitor, Verdict};
use crate::{Solution, SolveOptions};

/// Per-row step length w_i.
#[derive(Clone, Copy)]
pub(crate) enum Step<'a> {
    /// The same ω on every row (PIA: ω = 1).
    Scalar(f64),
    /// w_i per row (Jacobi: 1 / a_ii).
    PerRow(&'a [f64]),
}

/// Runs the Richardson iteration to the stopping rule. `matvecs0` counts
/// products spent before (eigenvalue estimation).
pub(crate) fn run(
    solver: &'static str,
    a: &FactoredMatrix,
    p: &[Row],
    opts: &SolveOptions,
    step: Step<'_>,
    matvecs0: usize,
    start: Instant,
) -> Result<Solution, SolveError> {
    validate(a, p, opts)?;
    let mut mon = Monitor::new(solver, opts, start);
    mon.matvecs = matvecs0;
    let n = a.n();
    let mut x = initial_guess(p, opts);
    let mut next = vec![[0.0; 3]; n];
    let mut partials = vec![0.0; kernels::n_chunks(n)];
    let s = a.csr();
    let d = a.d();
    let mut k = 0;
    loop {
        let res = {
            let x = &x;
            map_chunks(&mut next, &mut partials, |lo, out| {
                let mut m = 0.0f64;
                for (q, o) in out.iter_mut().enumerate() {
                    let i = lo + q;
                    let v = s.row_times(i, x);
                    let r = [p[i][0] - d[i] * v[0], p[i][1] - d[i] * v[1], p[i][2] - d[i] * v[2]];
                    m = max_nan(m, norm2(r));
                    let w = match step {
                        Step::Scalar(w) => w,
                        Step::PerRow(w) => w[i],
                    };
                    *o = [x[i][0] + w * r[0], x[i][1] + w * r[1], x[i][2] + w * r[2]];
                }
                m
            });
            kernels::fold_max(&partials).sqrt()
        };
        mon.matvecs += 1;
        match mon.observe(k, res) {
            Verdict::Continue => {}
            v => return mon.finish(v, x, k, res),
        }
        std::mem::swap(&mut x, &mut next);
        k += 1;
    }
}
