//! Geometric queries: bounding box, centroids, normals, areas.

use glam::DVec3;

/// Axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Minimum corner.
    pub min: DVec3,
    /// Maximum corner.
    pub max: DVec3,
}

impl Aabb {
    /// The bounding box of `points`; `None` when there are none.
    pub fn of(points: impl IntoIterator<Item = DVec3>) -> Option<Self> {
        let mut it = points.into_iter();
        let first = it.next()?;
        let (min, max) = it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
        Some(Self { min, max })
    }

    /// Length of the diagonal: the scale *d* every relative tolerance refers to (SPEC §1).
    pub fn diagonal(&self) -> f64 {
        (self.max - self.min).length()
    }
}

/// An exact change of scale by a power of two, 2^`exponent`.
///
/// Multiplying by a power of two only changes a float's exponent, so it is
/// exact (outside the subnormal range) and commutes with every affine
/// combination, sum, product and square root a subdivision rule or a solver
/// forms: a computation on scaled data gives the scaled result of the same
/// computation on the original data, bit for bit, as long as nothing
/// overflows or underflows on either side. [`PowerOfTwoScale::normalizing`]
/// picks the exponent that brings the largest coordinate into [½, 1), so that
/// meshes with coordinates near ±1e308 or 1e-300 can be refined and
/// interpolated without overflow or underflow, and mapped back.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct PowerOfTwoScale {
    /// The power of two: data are multiplied by 2^exponent.
    pub exponent: i32,
}

impl PowerOfTwoScale {
    /// No change of scale.
    pub const IDENTITY: Self = Self { exponent: 0 };

    /// The scale that maps the largest finite |coordinate| of `points` into
    /// [½, 1); the identity when there is no finite non-zero coordinate.
    pub fn normalizing(points: impl IntoIterator<Item = DVec3>) -> Self {
        let largest = points
            .into_iter()
            .flat_map(|p| p.to_array())
            .filter(|c| c.is_finite())
            .fold(0.0_f64, |m, c| m.max(c.abs()));
        if largest == 0.0 {
            return Self::IDENTITY;
        }
        // largest ∈ [2^e, 2^(e+1)) ⇒ largest·2^-(e+1) ∈ [½, 1).
        Self { exponent: -(binary_exponent(largest) + 1) }
    }

    /// The inverse scale, 2^-exponent.
    pub fn inverse(self) -> Self {
        Self { exponent: -self.exponent }
    }

    /// True for the identity.
    pub fn is_identity(self) -> bool {
        self.exponent == 0
    }

    /// x·2^exponent, exact unless the result is subnormal or overflows.
    pub fn apply(self, x: f64) -> f64 {
        // 2^k is a normal f64 only for k ∈ [-1022, 1023]: scale in steps.
        let mut k = self.exponent;
        let mut y = x;
        while k != 0 {
            let step = k.clamp(-1000, 1000);
            y *= f64::from_bits(((step + 1023) as u64) << 52);
            k -= step;
        }
        y
    }

    /// Scales a point.
    pub fn apply_point(self, p: DVec3) -> DVec3 {
        DVec3::new(self.apply(p.x), self.apply(p.y), self.apply(p.z))
    }

    /// Scales points in place.
    pub fn apply_points(self, points: &mut [DVec3]) {
        if !self.is_identity() {
            points.iter_mut().for_each(|p| *p = self.apply_point(*p));
        }
    }
}

/// e with |x| ∈ [2^e, 2^(e+1)) for finite non-zero x (subnormals included).
fn binary_exponent(x: f64) -> i32 {
    let x = x.abs();
    if x < f64::MIN_POSITIVE {
        // Subnormal: scale into the normal range first (exact).
        return binary_exponent(x * f64::from_bits((64 + 1023_u64) << 52)) - 64;
    }
    ((x.to_bits() >> 52) & 0x7ff) as i32 - 1023
}

/// Newell's vector of a polygon: twice its vector area, exact for planar polygons
/// and translation-invariant (Zheng-Cai Eq. 10 with cyclic indices, ERRATA Z5).
pub fn newell_normal(corners: impl Iterator<Item = DVec3> + Clone) -> DVec3 {
    let first = corners.clone().next().unwrap_or(DVec3::ZERO);
    let next = corners.clone().skip(1).chain(std::iter::once(first));
    // Translate to the first corner to keep round-off relative to the face size.
    corners.zip(next).fold(DVec3::ZERO, |acc, (a, b)| acc + (a - first).cross(b - first))
}

/// Centroid (vertex average) of a polygon.
pub fn centroid(corners: impl ExactSizeIterator<Item = DVec3>) -> DVec3 {
    let n = corners.len() as f64;
    corners.sum::<DVec3>() / n
}

/// Interior angle at corner `b` between `a` and `c`, in radians (0 for a degenerate corner).
pub fn corner_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let u = a - b;
    let v = c - b;
    // atan2(|u×v|, u·v) is accurate for tiny and near-straight angles alike.
    u.cross(v).length().atan2(u.dot(v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_of_two_scale_normalises_extremes_exactly_and_inverts() {
        for &m in &[1.0, 0.75, 3.0, 1.7e308, f64::MAX, 1e-300, 5e-324, 2.2e-308, 1e154] {
            let points = [DVec3::new(m, -m / 2.0, 0.0), DVec3::ZERO];
            let s = PowerOfTwoScale::normalizing(points);
            let top = s.apply(m);
            assert!((0.5..1.0).contains(&top), "{m}: {top}");
            // Exact round trip (the scaled values are normal numbers).
            assert_eq!(s.inverse().apply(top), m, "{m}");
            assert_eq!(s.inverse().apply(s.apply(-m / 2.0)), -m / 2.0);
        }
        // Already in [½, 1): identity. Nothing finite: identity.
        assert!(PowerOfTwoScale::normalizing([DVec3::splat(0.5)]).is_identity());
        assert!(PowerOfTwoScale::normalizing([DVec3::splat(f64::NAN), DVec3::ZERO]).is_identity());
        // Equivalent to multiplying by the power itself where that is representable.
        let s = PowerOfTwoScale { exponent: -10 };
        assert_eq!(s.apply(3.0), 3.0 / 1024.0);
        assert_eq!(PowerOfTwoScale { exponent: 2000 }.apply(1e-300), 1e-300 * 2f64.powi(1000) * 2f64.powi(1000));
    }
}
