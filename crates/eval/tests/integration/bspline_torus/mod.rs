//! A closed-form limit surface for the tests: an all-quad, valence-4 torus
//! is regular Catmull-Clark, and its limit surface is the uniform bicubic
//! B-spline surface of its control net (each face one B-spline patch).
//! Independent of the library's evaluator.
#![allow(dead_code)]

use glam::DVec3;
use subdiv_eval::{Domain, DomainShape, EvalError, LimitJet, LimitSample, PatchEvaluator, SurfaceParam};
use subdiv_mesh::Mesh;

/// Uniform cubic B-spline basis, first and second derivatives at t ∈ [0, 1].
fn basis(t: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    (
        [
            s * s * s / 6.0,
            (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
            (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
            t * t * t / 6.0,
        ],
        [-s * s / 2.0, (3.0 * t * t - 4.0 * t) / 2.0, (-3.0 * t * t + 2.0 * t + 1.0) / 2.0, t * t / 2.0],
        [s, 3.0 * t - 2.0, 1.0 - 3.0 * t, t],
    )
}

/// The B-spline torus of `subdiv_mesh::shapes::torus(nu, nv)` (vertex
/// `i·nv + j`, face `i·nv + j` with corners (i, j), (i+1, j), (i+1, j+1), (i, j+1)).
pub struct BSplineTorus {
    pub nu: usize,
    pub nv: usize,
    pub positions: Vec<DVec3>,
    pub domains: Vec<Domain>,
    /// Use the trait's finite-difference second derivatives instead of the exact ones.
    pub finite_differences: bool,
}

impl BSplineTorus {
    pub fn new(mesh: &Mesh, nu: usize, nv: usize) -> Self {
        assert_eq!(mesh.positions().len(), nu * nv);
        let domains = (0..(nu * nv) as u32).map(|face| Domain { face, corner: 0 }).collect();
        Self { nu, nv, positions: mesh.positions().to_vec(), domains, finite_differences: false }
    }

    pub fn second(&self, p: SurfaceParam) -> Result<LimitJet, EvalError> {
        if p.face as usize >= self.nu * self.nv || p.corner != 0 {
            return Err(EvalError::NoSuchDomain { face: p.face, corner: p.corner });
        }
        if !(p.u >= 0.0 && p.u <= 1.0 && p.v >= 0.0 && p.v <= 1.0) {
            return Err(EvalError::OutOfDomain { face: p.face, u: p.u, v: p.v });
        }
        let (i0, j0) = (p.face as usize / self.nv, p.face as usize % self.nv);
        let (bu, du, ddu) = basis(p.u);
        let (bv, dv, ddv) = basis(p.v);
        let mut out = [DVec3::ZERO; 6];
        for a in 0..4 {
            for b in 0..4 {
                let i = (i0 + self.nu + a - 1) % self.nu;
                let j = (j0 + self.nv + b - 1) % self.nv;
                let c = self.positions[i * self.nv + j];
                out[0] += bu[a] * bv[b] * c;
                out[1] += du[a] * bv[b] * c;
                out[2] += bu[a] * dv[b] * c;
                out[3] += ddu[a] * bv[b] * c;
                out[4] += du[a] * dv[b] * c;
                out[5] += bu[a] * ddv[b] * c;
            }
        }
        let normal = out[1].cross(out[2]).normalize();
        Ok(LimitJet {
            sample: LimitSample { position: out[0], du: out[1], dv: out[2], normal },
            duu: out[3],
            duv: out[4],
            dvv: out[5],
        })
    }
}

impl PatchEvaluator for BSplineTorus {
    fn shape(&self) -> DomainShape {
        DomainShape::Square
    }
    fn domains(&self) -> &[Domain] {
        &self.domains
    }
    fn evaluate(&self, param: SurfaceParam) -> Result<LimitSample, EvalError> {
        self.second(param).map(|s| s.sample)
    }
    fn evaluate_second(&self, param: SurfaceParam) -> Result<LimitJet, EvalError> {
        if self.finite_differences {
            // The trait's default.
            struct Plain<'a>(&'a BSplineTorus);
            impl PatchEvaluator for Plain<'_> {
                fn shape(&self) -> DomainShape {
                    DomainShape::Square
                }
                fn domains(&self) -> &[Domain] {
                    &self.0.domains
                }
                fn evaluate(&self, param: SurfaceParam) -> Result<LimitSample, EvalError> {
                    self.0.evaluate(param)
                }
            }
            return Plain(self).evaluate_second(param);
        }
        self.second(param)
    }
}
