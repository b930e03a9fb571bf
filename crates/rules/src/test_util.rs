//! Helpers shared by the unit tests: a seeded generator, point arithmetic,
//! B-spline evaluation and left-eigenvector power iteration.

use crate::vec3::{add, dist, scale, Point3};

/// xorshift64*: deterministic, dependency-free test randomness.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    /// Uniform in [0, 1).
    pub fn f64(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.f64()
    }
    /// Uniform integer in lo..=hi.
    pub fn usize(&mut self, lo: usize, hi: usize) -> usize {
        lo + (self.f64() * (hi - lo + 1) as f64) as usize
    }
    /// A point with coordinates uniform in [−s, s).
    pub fn point(&mut self, s: f64) -> Point3 {
        [self.range(-s, s), self.range(-s, s), self.range(-s, s)]
    }
    pub fn points(&mut self, n: usize, s: f64) -> Vec<Point3> {
        (0..n).map(|_| self.point(s)).collect()
    }
}

/// Σ wᵢ pᵢ.
pub fn combine(weights: &[f64], points: &[Point3]) -> Point3 {
    assert_eq!(weights.len(), points.len());
    weights.iter().zip(points).fold([0.0; 3], |s, (&w, &p)| add(s, scale(p, w)))
}

pub fn max_dist(a: &[Point3], b: &[Point3]) -> f64 {
    assert_eq!(a.len(), b.len(), "point lists differ in length");
    a.iter().zip(b).map(|(&p, &q)| dist(p, q)).fold(0.0, f64::max)
}

/// Uniform B-spline basis of degree 2 or 3 on [0, 1].
fn basis(degree: usize, t: f64) -> Vec<f64> {
    let s = 1.0 - t;
    match degree {
        2 => vec![0.5 * s * s, 0.5 + t - t * t, 0.5 * t * t],
        3 => vec![
            s * s * s / 6.0,
            (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
            (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
            t * t * t / 6.0,
        ],
        _ => unreachable!("degree 2 or 3"),
    }
}

/// A uniform B-spline curve of degree 2 or 3 over a control polygon, evaluated
/// independently of any subdivision code (explicit basis functions).
pub struct UniformBSpline {
    pub degree: usize,
    /// Control points, already extended as the caller wants; segment s uses
    /// points s..=s+degree.
    pub control: Vec<Point3>,
}

impl UniformBSpline {
    /// The closed curve of a closed polygon (segment i centred on P_i..P_{i+1}).
    pub fn closed(degree: usize, polygon: &[Point3]) -> Self {
        let n = polygon.len();
        let control = (0..n + degree).map(|i| polygon[(i + n - 1) % n]).collect();
        Self { degree, control }
    }
    pub fn segments(&self) -> usize {
        self.control.len() - self.degree
    }
    pub fn eval(&self, seg: usize, t: f64) -> Point3 {
        combine(&basis(self.degree, t), &self.control[seg..=seg + self.degree])
    }
    pub fn distance(&self, p: Point3) -> f64 {
        curve_distance(|s, t| self.eval(s, t), self.segments(), p)
    }
}

/// The clamped (open-uniform) quadratic B-spline of a polygon of n ≥ 3 points:
/// knots 0,0,0,1,…,L,L,L with L = n − 2, evaluated by de Boor's algorithm.
pub struct ClampedQuadratic {
    pub control: Vec<Point3>,
}

impl ClampedQuadratic {
    fn knot(&self, i: usize) -> f64 {
        let l = self.control.len() - 2;
        i.saturating_sub(2).min(l) as f64
    }
    pub fn segments(&self) -> usize {
        self.control.len() - 2
    }
    /// The curve at parameter `seg + t`.
    pub fn eval(&self, seg: usize, t: f64) -> Point3 {
        const P: usize = 2;
        let x = seg as f64 + t;
        let k = seg + P; // knot span [t_k, t_{k+1}) = [seg, seg + 1)
        let mut d: Vec<Point3> = (0..=P).map(|j| self.control[j + k - P]).collect();
        for r in 1..=P {
            for j in (r..=P).rev() {
                let i = j + k - P;
                let alpha = (x - self.knot(i)) / (self.knot(i + 1 + P - r) - self.knot(i));
                d[j] = add(scale(d[j - 1], 1.0 - alpha), scale(d[j], alpha));
            }
        }
        d[P]
    }
    pub fn distance(&self, p: Point3) -> f64 {
        curve_distance(|s, t| self.eval(s, t), self.segments(), p)
    }
}

/// Distance from `p` to a curve given segment-wise on [0, 1]: sampling, then
/// golden-section refinement around every sampled local minimum (so a curve
/// passing near itself cannot trap the search in the wrong branch).
pub fn curve_distance(eval: impl Fn(usize, f64) -> Point3, segments: usize, p: Point3) -> f64 {
    const SAMPLES: usize = 64;
    let h = 1.0 / SAMPLES as f64;
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let mut best = f64::INFINITY;
    for s in 0..segments {
        let f = |t: f64| dist(eval(s, t), p);
        let d: Vec<f64> = (0..=SAMPLES).map(|k| f(k as f64 * h)).collect();
        for k in 0..=SAMPLES {
            let left = if k == 0 { f64::INFINITY } else { d[k - 1] };
            let right = if k == SAMPLES { f64::INFINITY } else { d[k + 1] };
            if d[k] > left || d[k] > right {
                continue;
            }
            let t0 = k as f64 * h;
            let (mut lo, mut hi) = ((t0 - h).max(0.0), (t0 + h).min(1.0));
            for _ in 0..80 {
                let (a, b) = (hi - g * (hi - lo), lo + g * (hi - lo));
                if f(a) < f(b) {
                    hi = b;
                } else {
                    lo = a;
                }
            }
            best = best.min(d[k]).min(f(0.5 * (lo + hi)));
        }
    }
    best
}

/// Left eigenvector of `s` (rows = new points as combinations of old) for
/// eigenvalue 1, by power iteration on sᵀ, normalised to sum 1.
pub fn dominant_left_eigenvector(s: &[Vec<f64>]) -> Vec<f64> {
    let n = s.len();
    let mut x = vec![1.0 / n as f64; n];
    for _ in 0..5000 {
        let mut y = vec![0.0; n];
        for (i, row) in s.iter().enumerate() {
            for (j, &w) in row.iter().enumerate() {
                y[j] += x[i] * w;
            }
        }
        let sum: f64 = y.iter().sum();
        x = y.into_iter().map(|v| v / sum).collect();
    }
    x
}

/// The solution of lᵀ(S − I) = 0 with Σl = 1 by dense Gaussian elimination
/// with partial pivoting (the last equation replaced by the normalisation):
/// the left eigenvector of eigenvalue 1 of a simple eigenvalue, without
/// assuming it dominant. An independent check of closed-form limit masks.
pub fn left_fixed_point(s: &[Vec<f64>]) -> Vec<f64> {
    let n = s.len();
    // Row j of the system: column j of S − I; the last row Σl = 1.
    let mut a: Vec<Vec<f64>> =
        (0..n).map(|j| (0..n).map(|i| s[i][j] - if i == j { 1.0 } else { 0.0 }).collect()).collect();
    let mut b = vec![0.0; n];
    a[n - 1].fill(1.0);
    b[n - 1] = 1.0;
    for c in 0..n {
        let p = (c..n).max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs())).expect("a row");
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..n {
            let f = a[r][c] / a[c][c];
            if f != 0.0 {
                for k in c..n {
                    a[r][k] -= f * a[c][k];
                }
                b[r] -= f * b[c];
            }
        }
    }
    let mut x = vec![0.0; n];
    for r in (0..n).rev() {
        let tail: f64 = (r + 1..n).map(|k| a[r][k] * x[k]).sum();
        x[r] = (b[r] - tail) / a[r][r];
    }
    x
}
