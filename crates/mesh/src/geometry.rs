//! Geometric queries: bounding box, centroids, normals, areas, angles.
//!
//! All of them are free of overflow and underflow for finite coordinates
//! anywhere in the `f64` range: where a product or a difference could leave
//! the range, the points are first scaled by an exact power of two
//! ([`PowerOfTwoScale`]) and the result scaled back. In the ordinary range
//! nothing is scaled and the results are the naive formulas', bit for bit.

use glam::DVec3;
use rayon::prelude::*;

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

    /// Length of the diagonal: the scale *d* every relative tolerance refers to ([how the error is measured]).
    ///
    /// Computed without overflow or underflow (a scaled hypot): the corners
    /// are scaled by the power of two that brings their largest |coordinate|
    /// into [½, 1), so that max − min cannot overflow (1.7e308 − (−1.7e308)),
    /// the extent by the one that brings its largest component into [½, 1),
    /// so that its squares neither overflow nor underflow, and the length is
    /// scaled back. Powers of two are exact: wherever the naive ‖max − min‖
    /// neither overflows nor underflows, this is the same number bit for bit.
    ///
    /// The result is finite whenever the diagonal is: +∞ only when it exceeds
    /// `f64::MAX` ≈ 1.8e308 (an extent beyond about 1.04e308 on each axis, or
    /// 1.8e308 on one), which callers must refuse (or first normalise the
    /// data with [`PowerOfTwoScale`]). It is 0 exactly when `min == max`, and
    /// NaN or ∞ when a corner is not finite.
    ///
    /// [how the error is measured]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-how-the-error-is-measured
    pub fn diagonal(&self) -> f64 {
        self.diagonal_magnitude().value()
    }

    /// The diagonal as an unrounded [`Magnitude`] (finite even beyond `f64::MAX`).
    pub(crate) fn diagonal_magnitude(&self) -> Magnitude {
        let outer = PowerOfTwoScale::normalizing([self.min, self.max]);
        let extent = outer.apply_point(self.max) - outer.apply_point(self.min);
        Magnitude::length(extent).scaled(outer.inverse())
    }
}

/// A non-negative number kept as mantissa · 2^exponent with the mantissa in
/// [½, 1) (or 0; or the value itself when it is NaN or ∞), so that lengths, areas and their products and comparisons
/// stay exact in range whatever the scale: areas of faces with coordinates
/// near 1e200 (1e400, beyond `f64::MAX`) and of faces near 1e-200 (1e-400,
/// below the smallest subnormal) compare correctly against d².
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Magnitude {
    mantissa: f64,
    exponent: i32,
}

impl Magnitude {
    /// A non-negative `x`, exactly.
    pub(crate) fn new(x: f64) -> Self {
        if x == 0.0 || !x.is_finite() {
            // Zero, or NaN/∞ from non-finite coordinates: carried as they are.
            return Self { mantissa: x, exponent: 0 };
        }
        // x ∈ [2^e, 2^(e+1)) ⇒ x·2^-(e+1) ∈ [½, 1), exact (scaling up a subnormal is exact too).
        let exponent = binary_exponent(x) + 1;
        Self { mantissa: PowerOfTwoScale { exponent: -exponent }.apply(x), exponent }
    }

    /// ‖v‖ for a finite `v`, with its squares formed in a scaling that can
    /// neither overflow nor underflow.
    pub(crate) fn length(v: DVec3) -> Self {
        let s = PowerOfTwoScale::normalizing([v]);
        Self::new(s.apply_point(v).length()).scaled(s.inverse())
    }

    /// self · 2^`s.exponent`, exactly.
    pub(crate) fn scaled(self, s: PowerOfTwoScale) -> Self {
        if self.mantissa == 0.0 || !self.mantissa.is_finite() {
            return self;
        }
        Self { mantissa: self.mantissa, exponent: self.exponent + s.exponent }
    }

    /// self · other, rounded once (the product of the mantissas).
    pub(crate) fn times(self, other: Self) -> Self {
        Self::new(self.mantissa * other.mantissa).scaled(PowerOfTwoScale { exponent: self.exponent + other.exponent })
    }

    /// The nearest `f64`: +∞ beyond `f64::MAX`, 0 or subnormal below the normal range.
    pub(crate) fn value(self) -> f64 {
        PowerOfTwoScale { exponent: self.exponent }.apply(self.mantissa)
    }

    /// self ≤ other, exactly (normalised mantissas compare by exponent first);
    /// false when either is NaN.
    pub(crate) fn le(self, other: Self) -> bool {
        let special = |m: f64| m == 0.0 || !m.is_finite();
        if special(self.mantissa) || special(other.mantissa) {
            return self.value() <= other.value();
        }
        (self.exponent, self.mantissa) <= (other.exponent, other.mantissa)
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
        let finite = |c: f64| if c.is_finite() { c.abs() } else { 0.0 };
        let largest = points.into_iter().fold(0.0_f64, |m, p| m.max(finite(p.x)).max(finite(p.y)).max(finite(p.z)));
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
    #[inline]
    pub fn apply(self, x: f64) -> f64 {
        if (-1000..=1000).contains(&self.exponent) {
            return x * power_of_two(self.exponent);
        }
        // 2^k is a normal f64 only for k ∈ [-1022, 1023]: scale in steps.
        let mut k = self.exponent;
        let mut y = x;
        while k != 0 {
            let step = k.clamp(-1000, 1000);
            y *= power_of_two(step);
            k -= step;
        }
        y
    }

    /// Scales a point.
    #[inline]
    pub fn apply_point(self, p: DVec3) -> DVec3 {
        DVec3::new(self.apply(p.x), self.apply(p.y), self.apply(p.z))
    }

    /// Scales points in place; a long slice on every thread (each point on
    /// its own, so the bits do not depend on the split).
    pub fn apply_points(self, points: &mut [DVec3]) {
        if self.is_identity() {
            return;
        }
        if points.len() < PARALLEL_POINTS {
            points.iter_mut().for_each(|p| *p = self.apply_point(*p));
        } else {
            points.par_iter_mut().with_min_len(PARALLEL_POINTS).for_each(|p| *p = self.apply_point(*p));
        }
    }

    /// `points` scaled, as a new vector: [`Self::apply_points`] on a copy,
    /// bit for bit, in one pass (a copy of 8.4M points and then a second
    /// pass over it cost twice the memory traffic and fault the new pages on
    /// one thread).
    pub fn scaled_points(self, points: &[DVec3]) -> Vec<DVec3> {
        if self.is_identity() {
            points.to_vec()
        } else if points.len() < PARALLEL_POINTS {
            points.iter().map(|&p| self.apply_point(p)).collect()
        } else {
            points.par_iter().with_min_len(PARALLEL_POINTS).map(|&p| self.apply_point(p)).collect()
        }
    }
}

/// Points from which [`PowerOfTwoScale::apply_points`] and
/// [`PowerOfTwoScale::scaled_points`] split the work across threads.
const PARALLEL_POINTS: usize = 1 << 16;

/// 2^k for k ∈ [-1022, 1023] (a normal number), from its bits.
#[inline]
fn power_of_two(k: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((k + 1023) as u64) << 52)
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

/// ‖a − b‖ without overflow or underflow: the difference (of the halves, if
/// the full difference overflows) is scaled by an exact power of two before
/// it is squared, so the result is the naive `a.distance(b)` bit for bit
/// wherever that neither overflows nor underflows, and correct where it
/// would (coordinates near ±1e308, or differences of 1e-300 whose squares
/// vanish). +∞ only when the distance exceeds `f64::MAX`; NaN when a
/// coordinate is NaN.
pub fn distance(a: DVec3, b: DVec3) -> f64 {
    let (diff, factor) = match a - b {
        d if d.is_finite() => (d, 1.0),
        _ => (a * 0.5 - b * 0.5, 2.0),
    };
    let scale = PowerOfTwoScale::normalizing([diff]);
    factor * scale.inverse().apply(scale.apply_point(diff).length())
}

/// Newell's vector of a polygon: twice its vector area, exact for planar polygons
/// and translation-invariant (Zheng-Cai Eq. 10 with cyclic indices, [correction Z5]).
///
/// Formed in exact power-of-two scalings of the corners, so no intermediate
/// overflows or underflows: the result
/// is the naive Σ (Vᵢ − V₀) × (Vᵢ₊₁ − V₀) bit for bit wherever that neither
/// overflows nor underflows, and a component is ±∞ only where the true
/// vector's exceeds `f64::MAX` (areas beyond about 1e308: coordinates beyond
/// about ±1e154). For a direction use [`unit_newell_normal`], finite always.
///
/// [correction Z5]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#z5
pub fn newell_normal(corners: impl Iterator<Item = DVec3> + Clone) -> DVec3 {
    let (n, s) = scaled_newell(corners);
    s.inverse().apply_point(n)
}

/// The unit normal of a polygon: its Newell vector ([`newell_normal`])
/// normalised, computed without overflow or underflow whatever the
/// coordinates' scale (a face of size 1e-200 or 1e200 has a unit normal);
/// zero when the Newell vector is exactly zero (fewer than three distinct
/// corners, or collinear ones without round-off).
pub fn unit_newell_normal(corners: impl Iterator<Item = DVec3> + Clone) -> DVec3 {
    unit_vector(scaled_newell(corners).0)
}

/// The Newell vector of `corners` multiplied by an exact power of two `s`,
/// returned as (N·s, s): the corners are scaled so their largest |coordinate|
/// is in [½, 1) (offsets from the first corner then cannot overflow), the
/// offsets so their largest component is in [½, 1) (the cross products then
/// neither overflow nor underflow, whatever the face's size or distance from
/// the origin). Both scalings are exact, so N·s is the naive sum scaled, bit
/// for bit, wherever the naive sum neither overflows nor underflows.
pub(crate) fn scaled_newell(corners: impl Iterator<Item = DVec3> + Clone) -> (DVec3, PowerOfTwoScale) {
    let Some(first) = corners.clone().next() else { return (DVec3::ZERO, PowerOfTwoScale::IDENTITY) };
    // The common case first: offsets within [2^-250, 2^250], whose products
    // can neither overflow nor underflow, summed unscaled (the scaled sum
    // would be the same bits; this saves three passes).
    if let Some(naive) = unscaled_newell(corners.clone()) {
        return (naive, PowerOfTwoScale::IDENTITY);
    }
    let outer = PowerOfTwoScale::normalizing(corners.clone());
    let origin = outer.apply_point(first);
    let offsets = corners.map(move |p| outer.apply_point(p) - origin);
    let inner = PowerOfTwoScale::normalizing(offsets.clone());
    let q = offsets.map(move |d| inner.apply_point(d));
    let next = q.clone().skip(1).chain(std::iter::once(DVec3::ZERO));
    // Newell, as above, on the scaled offsets.
    let n = q.zip(next).fold(DVec3::ZERO, |acc, (a, b)| acc + a.cross(b));
    // N' = Σ (2^k dᵢ) × (2^k dᵢ₊₁) = 2^2k N for the combined exponent k.
    (n, PowerOfTwoScale { exponent: 2 * (outer.exponent + inner.exponent) })
}

/// The Newell vector N = Σ (Vᵢ − V₀) × (Vᵢ₊₁ − V₀) (Zheng-Cai Eq. 10)
/// summed unscaled, when the offsets' largest |component| lies in
/// [2^-250, 2^250] (see [`in_safe_range`]); `None` otherwise (and for no
/// corners).
pub(crate) fn unscaled_newell(mut corners: impl Iterator<Item = DVec3>) -> Option<DVec3> {
    let first = corners.next()?;
    let mut reach = 0.0_f64;
    // One pass over the pairs (Vᵢ, Vᵢ₊₁), the last closing on V₀.
    let (mut naive, mut a) = (DVec3::ZERO, first);
    for b in corners.chain(std::iter::once(first)) {
        let (da, db) = (a - first, b - first);
        reach = reach.max(da.abs().max_element());
        naive += da.cross(db);
        a = b;
    }
    in_safe_range(reach).then_some(naive)
}

/// True when a largest |component| `x` lies in [2^-250, 2^250], where products
/// of two such vectors (and sums of up to 2³² of them) neither overflow nor
/// underflow in their leading terms: the naive formulas are then exact to
/// rounding and need no scaling. False for NaN and ∞.
#[inline]
fn in_safe_range(x: f64) -> bool {
    (power_of_two(-250)..=power_of_two(250)).contains(&x)
}

/// v / ‖v‖ without overflow or underflow (v is scaled by a power of two
/// first, which changes neither its direction nor, in range, the result's
/// bits); zero for a zero (or non-finite) vector.
pub fn unit_vector(v: DVec3) -> DVec3 {
    if in_safe_range(v.abs().max_element()) {
        return v.normalize_or_zero(); // the same bits as scaled
    }
    PowerOfTwoScale::normalizing([v]).apply_point(v).normalize_or_zero()
}

/// Centroid (vertex average) of a polygon, summed in coordinates scaled by a
/// power of two so the sum cannot overflow (two corners at 1.7e308); the
/// naive Σ Vᵢ / n bit for bit wherever that does not overflow.
pub fn centroid(corners: impl ExactSizeIterator<Item = DVec3> + Clone) -> DVec3 {
    let n = corners.len() as f64;
    // A finite sum of finite numbers never overflowed on the way (∞ stays ∞).
    let naive = corners.clone().sum::<DVec3>();
    if naive.is_finite() {
        return naive / n;
    }
    let s = PowerOfTwoScale::normalizing(corners.clone());
    s.inverse().apply_point(corners.map(|p| s.apply_point(p)).sum::<DVec3>() / n)
}

/// Interior angle at corner `b` between `a` and `c`, in radians (0 for a degenerate corner).
///
/// Scale-free: the corners are scaled so that the offsets u = a − b and
/// v = c − b cannot overflow, and u and v each by the power of two that
/// brings their largest component into [½, 1) (the angle does not depend on
/// their lengths), so corners near 1e300 or 1e-300 give the same angle as
/// the same corners near 1.
#[inline]
pub fn corner_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (u, v) = (a - b, c - b);
    if in_safe_range(u.abs().max_element()) && in_safe_range(v.abs().max_element()) {
        // The common case: scaling would change neither the products nor the angle.
        angle_between(u, v)
    } else {
        scaled_corner_angle(a, b, c)
    }
}

/// [`corner_angle`] for offsets out of the safe range (or overflowing).
#[cold]
#[inline(never)]
fn scaled_corner_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let outer = PowerOfTwoScale::normalizing([a, b, c]);
    let (a, b, c) = (outer.apply_point(a), outer.apply_point(b), outer.apply_point(c));
    let (u, v) = (a - b, c - b);
    let u = PowerOfTwoScale::normalizing([u]).apply_point(u);
    let v = PowerOfTwoScale::normalizing([v]).apply_point(v);
    angle_between(u, v)
}

/// The angle between u and v: atan2(|u×v|, u·v) is accurate for tiny and near-straight angles alike.
#[inline]
fn angle_between(u: DVec3, v: DVec3) -> f64 {
    u.cross(v).length().atan2(u.dot(v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_neither_overflows_nor_underflows() {
        let (a, b) = (DVec3::new(3.0, 0.0, 0.0), DVec3::new(0.0, 4.0, 0.0));
        assert_eq!(distance(a, b), a.distance(b));
        assert!((distance(a * 1e-300, b * 1e-300) / 5e-300 - 1.0).abs() < 1e-15);
        assert!((distance(a * 1e300, b * 1e300) / 5e300 - 1.0).abs() < 1e-15);
        let far = DVec3::new(1.7e308, 0.0, 0.0);
        assert_eq!(distance(far, -far), f64::INFINITY);
        assert!((distance(far, DVec3::ZERO) / 1.7e308 - 1.0).abs() < 1e-15);
        // A tiny difference on top of a huge offset.
        let offset = DVec3::new(1e-301, 0.9, 0.0);
        assert_eq!(distance(offset, DVec3::new(0.0, 0.9, 0.0)), 1e-301);
        assert!(distance(DVec3::splat(f64::NAN), a).is_nan());
    }

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

    #[test]
    fn bulk_scalings_equal_the_pointwise_scale_bit_for_bit_on_either_side_of_the_thread_split() {
        // Magnitudes from subnormal to near overflow, signs, zeros and NaN,
        // by an exponent sequence that visits every kind in each chunk.
        let kinds = [5e-324, 2.2e-308, 1e-300, 0.0, -0.0, 0.3, -7.5, 1e154, 1.7e308, f64::NAN];
        for len in [0, 1, 100, PARALLEL_POINTS - 1, PARALLEL_POINTS, 3 * PARALLEL_POINTS + 7] {
            let points: Vec<DVec3> =
                (0..len).map(|i| DVec3::new(kinds[i % 10], -kinds[(i / 10) % 10], kinds[(i * 7 + 3) % 10])).collect();
            for exponent in [0, -1, 5, -1074, 1100, 2000] {
                let s = PowerOfTwoScale { exponent };
                let bits = |p: &[DVec3]| p.iter().map(|q| q.to_array().map(f64::to_bits)).collect::<Vec<_>>();
                let pointwise: Vec<DVec3> =
                    points.iter().map(|&p| if s.is_identity() { p } else { s.apply_point(p) }).collect();
                let mut in_place = points.clone();
                s.apply_points(&mut in_place);
                assert_eq!(bits(&in_place), bits(&pointwise), "apply_points, {len} points, 2^{exponent}");
                assert_eq!(bits(&s.scaled_points(&points)), bits(&pointwise), "scaled_points, {len}, 2^{exponent}");
            }
        }
    }
}
