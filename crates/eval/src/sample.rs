//! Points with normals on the limit surface.
//!
//! - [`sample_per_domain`]: uniform in the parameter of every domain, an
//!   N × N grid of cell centres ((i + ½)/N, (j + ½)/N) on a square domain,
//!   the centroids of the N² triangles of the N-split barycentric domain on
//!   a triangle — no point on a domain edge, so no point twice.
//! - [`sample_by_area`]: `count` points distributed by surface area. The area
//!   is estimated from a tessellation of every domain ([`AREA_SPLITS`]
//!   splits per side, two triangles per cell, vertices on the surface); the
//!   tessellation's triangles are chosen by *systematic* sampling of their
//!   cumulative area (sample i at (i + ξᵢ)/count of the total, so that every
//!   triangle of area A gets count·A/total samples ± 1), and each point is
//!   uniform in the chosen triangle's parameter triangle. The distribution
//!   is uniform per unit area up to the variation of the surface's area
//!   element inside one tessellation triangle. Deterministic: the ξ come
//!   from a SplitMix64 stream seeded by `seed`.
//! - [`sample_surface`]: either of them on a [`LimitSurface`] at given
//!   positions, computed on the positions scaled by the power of two that
//!   normalises them and mapped back, so that a surface at 1e-300 or 1e300
//!   has the areas, points and normals it has at 1.
//!
//! Sizes: a count that memory cannot hold ([`SAMPLE_BYTES`] per sample,
//! more than `isize::MAX` bytes) is [`EvalError::InvalidInput`], never a
//! panic or an abort; callers with a memory budget check
//! [`per_domain_count`] or the count against it before they call.

use crate::project::{BoundLimitSurface, DomainShape, PatchEvaluator};
use crate::surface::{EvalError, LimitSurface, SurfaceParam};
use glam::DVec3;
use rayon::prelude::*;
use subdiv_mesh::shapes::SplitMix64;
use subdiv_mesh::PowerOfTwoScale;

/// Bytes the sampling functions hold per sample: the sample itself and,
/// for [`sample_by_area`], its pick (triangle, two random numbers).
pub const SAMPLE_BYTES: u64 = (std::mem::size_of::<SurfaceSample>() + std::mem::size_of::<(usize, f64, f64)>()) as u64;

/// The number of samples [`sample_per_domain`] makes with `n` per side on
/// `domains` domains: n² each (cells of a square, sub-triangles of a
/// triangle); `None` beyond `u64`.
pub fn per_domain_count(domains: usize, n: usize) -> Option<u64> {
    let n = u64::try_from(n).ok()?;
    n.checked_mul(n)?.checked_mul(u64::try_from(domains).ok()?)
}

/// Refuses `count` samples when their [`SAMPLE_BYTES`] cannot be held
/// (more than `isize::MAX` bytes, or a count beyond `u64`).
fn check_count(count: Option<u64>, what: impl FnOnce() -> String) -> Result<usize, EvalError> {
    count
        .filter(|&c| c.checked_mul(SAMPLE_BYTES).is_some_and(|b| b <= isize::MAX as u64))
        .and_then(|c| usize::try_from(c).ok())
        .ok_or_else(|| EvalError::InvalidInput {
            what: format!("{}: more samples than memory can hold ({SAMPLE_BYTES} bytes each)", what()),
        })
}

/// How [`sample_surface`] places its points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sampling {
    /// [`sample_per_domain`] with N per side.
    PerDomain(usize),
    /// [`sample_by_area`]: `count` points from `seed`.
    ByArea {
        /// Points in all.
        count: usize,
        /// Seed of the random stream.
        seed: u64,
    },
}

/// Samples of `surface` at control points `positions` (module docs),
/// computed on the positions scaled by an exact power of two into
/// [½, 1) ([`PowerOfTwoScale::normalizing`]) and mapped back: areas,
/// points and normals do not underflow or overflow for coordinates from
/// 1e-300 to 1e308. A point whose mapped-back coordinates exceed the range
/// of `f64` (a surface bulging beyond ±1.8e308) comes back infinite; the
/// caller refuses to write it.
///
/// # Errors
/// Those of [`sample_per_domain`] and [`sample_by_area`];
/// [`EvalError::PositionCount`].
pub fn sample_surface(
    surface: &LimitSurface,
    positions: &[DVec3],
    how: Sampling,
) -> Result<Vec<SurfaceSample>, EvalError> {
    let scale = PowerOfTwoScale::normalizing(positions.iter().copied());
    let scaled = scale.scaled_points(positions);
    let bound = BoundLimitSurface::new(surface, &scaled)?;
    let mut samples = match how {
        Sampling::PerDomain(n) => sample_per_domain(&bound, n)?,
        Sampling::ByArea { count, seed } => sample_by_area(&bound, count, seed)?,
    };
    let back = scale.inverse();
    if !back.is_identity() {
        samples.par_iter_mut().for_each(|s| s.position = back.apply_point(s.position));
    }
    Ok(samples)
}

/// Tessellation splits per domain side for [`sample_by_area`]'s areas.
pub const AREA_SPLITS: usize = 8;

/// One point on the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceSample {
    /// Where it is.
    pub param: SurfaceParam,
    /// The limit position.
    pub position: DVec3,
    /// The unit normal.
    pub normal: DVec3,
}

/// The triangles of the domain split `n` times along each side, as (u, v) corners.
pub(crate) fn sub_triangles(shape: DomainShape, n: usize) -> Vec<[(f64, f64); 3]> {
    let n = n.max(1);
    let t = |i: usize| i as f64 / n as f64;
    let mut out = Vec::with_capacity(2 * n * n);
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = ((t(i), t(j)), (t(i + 1), t(j)), (t(i + 1), t(j + 1)), (t(i), t(j + 1)));
            match shape {
                DomainShape::Square => {
                    out.push([a, b, c]);
                    out.push([a, c, d]);
                }
                DomainShape::Triangle if i + j < n => {
                    out.push([a, b, d]);
                    if i + j + 1 < n {
                        out.push([b, c, d]);
                    }
                }
                DomainShape::Triangle => {}
            }
        }
    }
    out
}

/// `n` × `n` samples per domain (cell centres; triangles: sub-triangle
/// centroids), domain by domain in [`PatchEvaluator::domains`] order.
///
/// # Errors
/// [`EvalError::InvalidInput`] for `n = 0` and for more samples than memory
/// can hold; what evaluation returns.
pub fn sample_per_domain<E: PatchEvaluator>(eval: &E, n: usize) -> Result<Vec<SurfaceSample>, EvalError> {
    if n == 0 {
        return Err(EvalError::InvalidInput { what: "samples per domain: N must be at least 1".into() });
    }
    let domains = eval.domains().len();
    check_count(per_domain_count(domains, n), || format!("{n}×{n} samples on each of {domains} domains"))?;
    let params: Vec<(f64, f64)> = match eval.shape() {
        DomainShape::Square => {
            (0..n * n).map(|k| (((k % n) as f64 + 0.5) / n as f64, ((k / n) as f64 + 0.5) / n as f64)).collect()
        }
        DomainShape::Triangle => sub_triangles(DomainShape::Triangle, n)
            .iter()
            .map(|[a, b, c]| ((a.0 + b.0 + c.0) / 3.0, (a.1 + b.1 + c.1) / 3.0))
            .collect(),
    };
    let per_domain: Vec<Vec<SurfaceSample>> = eval
        .domains()
        .par_iter()
        .map(|d| {
            params
                .iter()
                .map(|&(u, v)| {
                    let param = SurfaceParam { face: d.face, corner: d.corner, u, v };
                    eval.evaluate(param).map(|s| SurfaceSample { param, position: s.position, normal: s.normal })
                })
                .collect()
        })
        .collect::<Result<_, _>>()?;
    Ok(per_domain.concat())
}

/// `count` samples distributed by area (module docs), reproducible from `seed`.
///
/// # Errors
/// [`EvalError::NoSurface`] when the surface has no domain or no area;
/// [`EvalError::InvalidInput`] for more samples than memory can hold; what
/// evaluation returns.
pub fn sample_by_area<E: PatchEvaluator>(eval: &E, count: usize, seed: u64) -> Result<Vec<SurfaceSample>, EvalError> {
    check_count(u64::try_from(count).ok(), || format!("{count} samples"))?;
    let shape = eval.shape();
    let tris = sub_triangles(shape, AREA_SPLITS);
    let domains = eval.domains();
    // Area of every tessellation triangle, domain by domain.
    let areas: Vec<Vec<f64>> = domains
        .par_iter()
        .map(|d| {
            let at = |(u, v): (f64, f64)| eval.evaluate(SurfaceParam { face: d.face, corner: d.corner, u, v });
            tris.iter()
                .map(|&[a, b, c]| {
                    let (pa, pb, pc) = (at(a)?.position, at(b)?.position, at(c)?.position);
                    Ok(0.5 * (pb - pa).cross(pc - pa).length())
                })
                .collect()
        })
        .collect::<Result<_, EvalError>>()?;
    let mut cumulative = Vec::with_capacity(domains.len() * tris.len());
    let mut total = 0.0;
    for a in areas.iter().flatten() {
        total += a;
        cumulative.push(total);
    }
    if domains.is_empty() || total.is_nan() || total <= 0.0 {
        return Err(EvalError::NoSurface);
    }
    let mut rng = SplitMix64(seed);
    let mut picks: Vec<(usize, f64, f64)> = Vec::new();
    picks.try_reserve_exact(count).map_err(|_| EvalError::InvalidInput {
        what: format!("{count} samples: more than memory can hold ({SAMPLE_BYTES} bytes each)"),
    })?;
    picks.extend((0..count).map(|i| {
        let x = (i as f64 + rng.next_f64()) / count as f64 * total;
        let k = cumulative.partition_point(|&c| c <= x).min(cumulative.len() - 1);
        (k, rng.next_f64(), rng.next_f64())
    }));
    picks
        .par_iter()
        .map(|&(k, r1, r2)| {
            let d = domains[k / tris.len()];
            let [a, b, c] = tris[k % tris.len()];
            // Uniform in a triangle: √r₁ folds the square onto it.
            let s = r1.sqrt();
            let (wa, wb, wc) = (1.0 - s, s * (1.0 - r2), s * r2);
            let (u, v) = shape.clamp(wa * a.0 + wb * b.0 + wc * c.0, wa * a.1 + wb * b.1 + wc * c.1);
            let param = SurfaceParam { face: d.face, corner: d.corner, u, v };
            eval.evaluate(param).map(|s| SurfaceSample { param, position: s.position, normal: s.normal })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sub_triangles_tile_the_domain() {
        for (shape, area) in [(DomainShape::Square, 1.0), (DomainShape::Triangle, 0.5)] {
            for n in 1..6 {
                let tris = sub_triangles(shape, n);
                let sum: f64 =
                    tris.iter().map(|[a, b, c]| 0.5 * ((b.0 - a.0) * (c.1 - a.1) - (c.0 - a.0) * (b.1 - a.1))).sum();
                assert!((sum - area).abs() < 1e-12, "{shape:?} {n}: {sum}");
                assert!(tris
                    .iter()
                    .all(|[a, b, c]| { 0.5 * ((b.0 - a.0) * (c.1 - a.1) - (c.0 - a.0) * (b.1 - a.1)) > 0.0 }));
            }
        }
    }
}
