//! The numeric rule every method goes through (issue #14): a result is
//! returned only if every coordinate of it is a finite f64 and its error,
//! measured independently from the control mesh ([`Interpolant::error`],
//! [how the error is measured]), is within the tolerance; NaN never disappears from a maximum.
//!
//! Every method's `interpolate` is [`run`] around its own computation:
//! 1. **Check the scale.** The data are scaled by the power of two that
//!    brings their largest |coordinate| into [½, 1)
//!    ([`PowerOfTwoScale::normalizing`]). The bounding-box diagonal d of the
//!    scaled data must be > 0 ([`InterpError::CoincidentVertices`]) and d
//!    itself (mapped back) finite ([`InterpError::NotRepresentable`]: the
//!    data span more than f64 holds) — before any work.
//! 2. **The interpolated set.** The subset (default: every vertex) without
//!    the isolated vertices, which lie on no face and so have no limit
//!    point: they are left out with a warning that says how many (the
//!    documented repair of [error behaviour]), for every method alike.
//!    [`Interpolant::interpolated`] says which vertices were interpolated.
//! 3. **Compute on the scaled data.** The method sees the scaled mesh. The
//!    scale is exact, so on ordinary meshes every number is the scaled
//!    number of the same computation on the raw data, bit for bit, while
//!    coordinates near ±1e308 or 1e-300 no longer overflow or underflow in
//!    sums, squares and cross products. No option has a length unit — tol
//!    and EPS are relative to d, normals, shape handles, λ, μ and ω are
//!    dimensionless — so the options pass unchanged.
//! 4. **Map back and check.** The control mesh is scaled back; a coordinate
//!    that is not finite then is [`InterpError::NotRepresentable`], naming
//!    the vertex and how large it would be.
//! 5. **Measure.** [`Interpolant::error`] of the interpolated set against
//!    the original data, with the original d; max_rel > tol or NaN is
//!    [`InterpError::ToleranceNotMet`] (exit 3), also for the methods that
//!    are exact by construction: round-off of extreme parameters (shape
//!    handles of 1e12, μ = 1e300) is caught here.
//!
//! [how the error is measured]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-how-the-error-is-measured
//! [error behaviour]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-error-behaviour-and-exit-codes

use crate::{CommonOptions, InterpError, Interpolant, Method, Parameter};
use glam::DVec3;
use std::borrow::Cow;
use subdiv_mesh::{Mesh, PowerOfTwoScale, VertexId};
use subdiv_stencil::normalized::{magnitude, map_back};

/// The larger of `a` and `b`, NaN if either is NaN (`f64::max` drops NaN,
/// which would hide a failed point from every maximum).
pub(crate) fn max_nan(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// The unit vector along `n`, or `None` when `n` is zero or not finite.
/// Normalised by a power of two first, so that a direction given with
/// components of 1e-200 or 1e200 is not lost to underflow or overflow of |n|².
pub(crate) fn unit_direction(n: DVec3) -> Option<DVec3> {
    if !n.is_finite() {
        return None;
    }
    PowerOfTwoScale::normalizing([n]).apply_point(n).try_normalize()
}

/// A method's input after steps 1-2 of the rule: what the method computes
/// on, and what its result is checked against.
pub(crate) struct Prepared<'a> {
    method: Method,
    /// The original data.
    data: &'a Mesh,
    /// The data as the method sees them (scaled by `scale`).
    pub mesh: Cow<'a, Mesh>,
    /// The scale applied to `mesh`.
    scale: PowerOfTwoScale,
    /// d of the original data (finite, > 0).
    d: f64,
    /// The tolerance the measured error must meet.
    tol: f64,
    /// Per input vertex: interpolated?
    pub interpolated: Vec<bool>,
    /// Warnings of the preparation (isolated vertices left out).
    pub warnings: Vec<String>,
}

/// Steps 1-2 of the rule for `method` on `data`: the scaled mesh, d, the
/// interpolated set. `common` gives the subset and the tolerance; `None` is
/// an exact method (every vertex, the error must be exactly 0).
pub(crate) fn prepare<'a>(
    method: Method,
    data: &'a Mesh,
    common: Option<&CommonOptions>,
) -> Result<Prepared<'a>, InterpError> {
    let tol = match common {
        Some(c) if !(c.tol > 0.0 && c.tol.is_finite()) => {
            return Err(InterpError::invalid(Parameter::Tol, format!("the tolerance {} must be finite and > 0", c.tol)))
        }
        Some(c) => c.tol,
        None => 0.0,
    };
    let not_representable = |reason: String| InterpError::NotRepresentable { method: method.name(), reason };
    if let Some((v, p)) = data.positions().iter().enumerate().find(|(_, p)| !p.is_finite()) {
        return Err(not_representable(format!("vertex {v} has a non-finite coordinate ({p})")));
    }
    let scale = PowerOfTwoScale::normalizing(data.positions().iter().copied());
    let mesh = if scale.is_identity() {
        Cow::Borrowed(data)
    } else {
        Cow::Owned(data.with_positions(scale.scaled_points(data.positions())))
    };
    let scaled_d = mesh.bbox_diagonal();
    if scaled_d == 0.0 || scaled_d.is_nan() {
        return Err(InterpError::CoincidentVertices { method: method.name() });
    }
    let d = scale.inverse().apply(scaled_d);
    if !d.is_finite() {
        return Err(not_representable(format!(
            "the data span more than f64 holds: their bounding-box diagonal is {}, beyond the largest f64 \
             ({:.4e}); scale the mesh down",
            magnitude(scaled_d, scale.inverse()),
            f64::MAX
        )));
    }
    let t = data.topology();
    let mut interpolated = match common {
        Some(c) => c.interpolated(t.vertex_count())?,
        None => vec![true; t.vertex_count()],
    };
    let mut warnings = Vec::new();
    let isolated: Vec<VertexId> = t.vertices().filter(|&v| interpolated[v.index()] && t.is_isolated(v)).collect();
    if let Some(first) = isolated.first() {
        isolated.iter().for_each(|v| interpolated[v.index()] = false);
        warnings.push(format!(
            "{} isolated vertices (first: {first}) lie on no face and are not interpolated",
            isolated.len()
        ));
        if !interpolated.contains(&true) {
            return Err(InterpError::invalid(
                Parameter::Subset,
                "no vertex of the subset lies on a face: there is nothing to interpolate",
            ));
        }
    }
    Ok(Prepared { method, data, mesh, scale, d, tol, interpolated, warnings })
}

impl<'a> Prepared<'a> {
    /// For a method that computes nothing from the positions (Deng-Ma: the
    /// control mesh is the input): the method sees the original data, and
    /// nothing is mapped back.
    pub fn unscaled(self) -> Self {
        Self { mesh: Cow::Borrowed(self.data), scale: PowerOfTwoScale::IDENTITY, ..self }
    }

    /// For a result that approximates rather than interpolates (the fair
    /// method's penalty): [`Self::finish`] measures the error but accepts
    /// any finite value.
    pub fn without_tolerance(self) -> Self {
        Self { tol: f64::INFINITY, ..self }
    }

    /// Maps `positions` computed on [`Self::mesh`] back to the data's scale;
    /// `what` names them in the error ("the control mesh").
    pub fn map_back(&self, what: &str, positions: &mut [DVec3]) -> Result<(), InterpError> {
        map_back(self.scale.inverse(), positions).map_err(|out| InterpError::NotRepresentable {
            method: self.method.name(),
            reason: format!("{what} leaves the range of f64: {out}"),
        })
    }

    /// Steps 4-5 of the rule: maps the result's control mesh back, checks
    /// it, measures the error; adds the preparation's warnings (first) and
    /// the number of interpolated vertices to the report's parameters.
    pub fn finish(mut self, mut result: Interpolant) -> Result<Interpolant, InterpError> {
        debug_assert_eq!(result.interpolated, self.interpolated, "the method interpolates the prepared set");
        // The scaled copy of the data is done with: freed before the limit points are made.
        self.mesh = Cow::Borrowed(self.data);
        self.map_back("the control mesh", result.control.positions_mut())?;
        let error = result.error(self.data.positions(), &result.interpolated, self.d);
        if error.max_rel.is_nan() || error.max_rel > self.tol {
            return Err(InterpError::ToleranceNotMet {
                method: self.method.name(),
                max_rel: error.max_rel,
                tol: self.tol,
            });
        }
        result.measured_error = Some(error);
        let count = result.interpolated.iter().filter(|&&b| b).count();
        result.parameters.interpolated_vertices = Some(count);
        result.warnings.splice(0..0, self.warnings);
        Ok(result)
    }
}

/// The whole rule around `body`, which computes the method's result on the
/// scaled mesh for the given interpolated set (its `interpolated` field must
/// be that set).
pub(crate) fn run(
    method: Method,
    data: &Mesh,
    common: Option<&CommonOptions>,
    body: impl FnOnce(&Mesh, Vec<bool>) -> Result<Interpolant, InterpError>,
) -> Result<Interpolant, InterpError> {
    let prepared = prepare(method, data, common)?;
    let result = body(&prepared.mesh, prepared.interpolated.clone())?;
    prepared.finish(result)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn max_nan_keeps_nan_wherever_it_is() {
        assert!([1.0, f64::NAN, 3.0].into_iter().fold(0.0, max_nan).is_nan());
        assert!([f64::NAN, 1.0].into_iter().fold(0.0, max_nan).is_nan());
        assert_eq!([1.0, 3.0, 2.0].into_iter().fold(0.0, max_nan), 3.0);
        // What f64::max would have done.
        assert_eq!([1.0, f64::NAN, 3.0].into_iter().fold(0.0, f64::max), 3.0);
    }

    #[test]
    fn unit_direction_survives_tiny_and_huge_components() {
        assert_eq!(unit_direction(DVec3::new(0.0, 0.0, 1e-200)), Some(DVec3::Z));
        assert_eq!(unit_direction(DVec3::new(1e300, 0.0, 0.0)), Some(DVec3::X));
        let n = unit_direction(DVec3::new(1e200, 1e200, 0.0)).unwrap();
        assert!((n - DVec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-15);
        assert_eq!(unit_direction(DVec3::ZERO), None);
        assert_eq!(unit_direction(DVec3::new(f64::NAN, 0.0, 1.0)), None);
        assert_eq!(unit_direction(DVec3::new(f64::INFINITY, 0.0, 1.0)), None);
    }
}

#[cfg(test)]
mod before_after {
    //! The rule changes no bit on ordinary meshes: each method through
    //! [`run`] against its body on the raw data (what it computed before the
    //! rule existed).
    use crate::*;
    use subdiv_mesh::{shapes, Mesh, PowerOfTwoScale};

    fn bits(mesh: &Mesh) -> Vec<[u64; 3]> {
        mesh.positions().iter().map(|p| p.to_array().map(f64::to_bits)).collect()
    }

    #[test]
    fn normalising_changes_no_bit_of_any_method_on_ordinary_meshes() {
        let meshes = [
            shapes::torus(10, 6),
            shapes::polygon_mix(&shapes::torus(10, 8), 4, 0.2, 0.2, 0.1),
            shapes::quad_grid(4, 3),
            {
                let ico = shapes::icosahedron();
                ico.with_positions(ico.positions().iter().map(|&p| 3.0 * p).collect())
            },
        ];
        for mesh in &meshes {
            let scale = PowerOfTwoScale::normalizing(mesh.positions().iter().copied());
            assert!(!scale.is_identity(), "the test needs a mesh that is actually scaled");
            let all = vec![true; mesh.topology().vertex_count()];
            let pairs = [
                (
                    nasri::interpolate(mesh, &NasriOptions::default()),
                    nasri::interpolate_prepared(mesh, all.clone(), &NasriOptions::default()),
                ),
                (
                    zheng_cai::interpolate(mesh, &ZhengCaiOptions::default()),
                    zheng_cai::interpolate_prepared(mesh, all.clone(), &ZhengCaiOptions::default()),
                ),
                (
                    cheng::interpolate(mesh, &ChengOptions::default()),
                    cheng::interpolate_prepared(mesh, all.clone(), &ChengOptions::default()),
                ),
                (
                    fan_cheng_lai::interpolate(mesh, &FanChengLaiOptions::default()),
                    fan_cheng_lai::interpolate_prepared(mesh, all.clone(), &FanChengLaiOptions::default()),
                ),
                (
                    deng_wang::interpolate(mesh, &DengWangOptions::default()),
                    deng_wang::interpolate_prepared(mesh, all.clone(), &DengWangOptions::default()),
                ),
            ];
            for (ruled, raw) in pairs {
                let (ruled, raw) = (ruled.unwrap(), raw.unwrap());
                assert_eq!(bits(&ruled.control), bits(&raw.control), "{}", ruled.method.name());
                assert_eq!(ruled.solve, raw.solve, "{}", ruled.method.name());
            }
            // Deng-Ma: the control mesh is the input itself.
            let r = deng_ma::interpolate(mesh, &DengMaOptions::default()).unwrap();
            assert_eq!(bits(&r.control), bits(mesh));
        }
    }
}
