//! The few `[f64; 3]` operations the curve schemes and Deng-Ma need.

/// A point or vector in space.
pub type Point3 = [f64; 3];

#[inline]
pub(crate) fn add(a: Point3, b: Point3) -> Point3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

#[inline]
pub(crate) fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline]
pub(crate) fn scale(a: Point3, s: f64) -> Point3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `wa·a + wb·b`.
#[inline]
pub(crate) fn lin2(wa: f64, a: Point3, wb: f64, b: Point3) -> Point3 {
    [wa * a[0] + wb * b[0], wa * a[1] + wb * b[1], wa * a[2] + wb * b[2]]
}

#[inline]
pub(crate) fn norm(a: Point3) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

#[inline]
pub(crate) fn dist(a: Point3, b: Point3) -> f64 {
    norm(sub(a, b))
}

/// The centroid (mean) of a non-empty set of points.
///
/// # Panics
/// If `points` is empty.
pub fn centroid(points: &[Point3]) -> Point3 {
    assert!(!points.is_empty(), "centroid of no points");
    let sum = points.iter().fold([0.0; 3], |s, &p| add(s, p));
    scale(sum, 1.0 / points.len() as f64)
}
