//! Computing on normalised positions and mapping the results back (issue #14).
//!
//! Every refinement here runs on positions scaled by
//! [`PowerOfTwoScale::normalizing`] (largest |coordinate| in [½, 1)) and
//! scales its output back with the inverse. The scale is an exact power of
//! two, so for ordinary meshes the result is bit for bit the one computed on
//! the raw positions; for meshes with coordinates near ±1e308 or 1e-300 no
//! intermediate sum, product or square overflows or underflows. What can
//! still fail is the way back: a surface that bulges beyond ±1.8e308 has no
//! f64 coordinates. [`map_back`] finds that and names the first point.

use glam::DVec3;
use std::fmt;
use subdiv_mesh::PowerOfTwoScale;

/// The normalising scale of `points` and the scaled copy.
pub fn normalize(points: &[DVec3]) -> (PowerOfTwoScale, Vec<DVec3>) {
    let scale = PowerOfTwoScale::normalizing(points.iter().copied());
    (scale, scale.scaled_points(points))
}

/// A point that is not a finite f64 once mapped back.
///
/// `#[non_exhaustive]`: made by [`map_back`], read through its public
/// fields (a new field is not a breaking change).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct OutOfRange {
    /// Index of the point (the first one out of range).
    pub index: usize,
    /// The point in the normalised space (not finite when the computation
    /// itself broke down, e.g. on non-finite input).
    pub normalized: DVec3,
    /// The scale that maps it back.
    pub back: PowerOfTwoScale,
}

impl OutOfRange {
    /// The largest |coordinate| the point would have, as text: "about
    /// 2.1e308" (computed from the normalised value, so it can exceed f64),
    /// or "NaN"/"inf" when the normalised point is not finite either.
    pub fn magnitude(&self) -> String {
        let p = self.normalized;
        if !p.is_finite() {
            return if p.is_nan() { "NaN".into() } else { "inf".into() };
        }
        magnitude(p.abs().max_element(), self.back)
    }
}

/// |`normalized`·2^`back.exponent`| as text, "about 2.1e308", for a finite
/// non-zero `normalized` whose mapped-back value may exceed the range of f64.
pub fn magnitude(normalized: f64, back: PowerOfTwoScale) -> String {
    // log10(c·2^e) = log10(c) + e·log10(2), exact enough for one digit.
    let log = normalized.abs().log10() + f64::from(back.exponent) * std::f64::consts::LOG10_2;
    let power = log.floor();
    format!("about {:.1}e{}", 10f64.powf(log - power), power as i64)
}

impl fmt::Display for OutOfRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.normalized.is_finite() {
            write!(
                f,
                "vertex {} would have a coordinate of {}, beyond the largest f64 ({:.4e})",
                self.index,
                self.magnitude(),
                f64::MAX
            )
        } else {
            write!(f, "vertex {} came out {} before mapping back", self.index, self.magnitude())
        }
    }
}

/// Scales `points` by `back` in place; `Err` names the first point that is
/// not finite afterwards (the others are mapped back all the same).
pub fn map_back(back: PowerOfTwoScale, points: &mut [DVec3]) -> Result<(), OutOfRange> {
    let mut first = None;
    for (index, p) in points.iter_mut().enumerate() {
        let mapped = back.apply_point(*p);
        if first.is_none() && !mapped.is_finite() {
            first = Some(OutOfRange { index, normalized: *p, back });
        }
        *p = mapped;
    }
    first.map_or(Ok(()), Err)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_back_names_the_first_point_beyond_f64_and_its_magnitude() {
        // 0.75·2^1024 ≈ 1.3e308 is still finite: nothing out of range.
        let mut points = vec![DVec3::new(0.5, 0.0, 0.0), DVec3::new(0.0, -0.75, 0.25)];
        map_back(PowerOfTwoScale { exponent: 1024 }, &mut points).unwrap();
        assert_eq!(points[0].x, 2f64.powi(1023));
        let mut points = vec![DVec3::new(0.5, 0.0, 0.0), DVec3::new(0.0, -0.75, 0.25)];
        let err = map_back(PowerOfTwoScale { exponent: 1025 }, &mut points).unwrap_err();
        assert_eq!(err.index, 0);
        assert_eq!(err.magnitude(), "about 1.8e308");
        assert_eq!(
            err.to_string(),
            "vertex 0 would have a coordinate of about 1.8e308, beyond the largest f64 (1.7977e308)"
        );
        assert!(points[1].y == f64::NEG_INFINITY && points[1].z.is_finite());
        let mut nan = vec![DVec3::ZERO, DVec3::new(f64::NAN, 0.0, 0.0)];
        let err = map_back(PowerOfTwoScale::IDENTITY, &mut nan).unwrap_err();
        assert_eq!((err.index, err.magnitude()), (1, "NaN".to_string()));
        let mut fine = vec![DVec3::new(0.75, -0.5, 1e-3)];
        map_back(PowerOfTwoScale { exponent: 3 }, &mut fine).unwrap();
        assert_eq!(fine[0], DVec3::new(6.0, -4.0, 8e-3));
    }

    #[test]
    fn normalize_brings_the_largest_coordinate_into_half_one() {
        let (scale, scaled) = normalize(&[DVec3::new(1.7e308, 1.0, -2.0), DVec3::splat(-1e300)]);
        assert!((0.5..1.0).contains(&scaled[0].x));
        assert_eq!(scale.inverse().apply(scaled[0].x), 1.7e308);
    }
}
