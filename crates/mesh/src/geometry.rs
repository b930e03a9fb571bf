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
