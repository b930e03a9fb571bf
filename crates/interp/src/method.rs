//! One dispatch over the methods: their names, their typed options
//! ([`MethodOptions`]) and [`interpolate`], which the command line, the
//! paper reproduction, the examples and the bindings share.

use crate::{
    cheng, deng_ma, deng_wang, fair, fan_cheng_lai, nasri, zheng_cai, ChengOptions, CommonOptions, DengMaOptions,
    DengWangOptions, FairOptions, FanChengLaiOptions, InterpError, Interpolant, NasriOptions, Scheme, SolverChoice,
    SurfaceOptions, ZhengCaiOptions,
};
use std::fmt;
use std::str::FromStr;
use subdiv_mesh::Mesh;

/// The interpolation methods.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Method {
    /// Nasri 1987: standard Doo-Sabin, C·M⁰ = P.
    Nasri,
    /// Zheng & Cai 2005.
    ZhengCai,
    /// Cheng et al.: Catmull-Clark progressive interpolation (also with
    /// Loop or √3 as the control scheme).
    Cheng,
    /// Fan, Cheng & Lai: two-phase Doo-Sabin progressive interpolation.
    FanChengLai,
    /// Deng & Wang 2010: explicit Loop interpolation.
    DengWang,
    /// Deng & Ma 2011: interpolatory scheme derived from Doo-Sabin.
    DengMa,
    /// Fair interpolation after Halstead, Kass & DeRose 1993: the control
    /// mesh of the input refined K times with the least thin-plate energy.
    Fair,
}

impl Method {
    /// Every method, in the order of the papers' tables, then `fair` (no
    /// seed paper's table has it: the tables that reproduce a paper filter
    /// for their methods).
    pub const ALL: [Method; 7] = [
        Method::Nasri,
        Method::ZhengCai,
        Method::Cheng,
        Method::FanChengLai,
        Method::DengWang,
        Method::DengMa,
        Method::Fair,
    ];

    /// The method's id in reports and on the command line (`nasri`,
    /// `zheng-cai`, `cheng`, `fan-cheng-lai`, `deng-wang`, `deng-ma`, `fair`);
    /// [`FromStr`] parses it back.
    pub fn name(self) -> &'static str {
        match self {
            Method::Nasri => "nasri",
            Method::ZhengCai => "zheng-cai",
            Method::Cheng => "cheng",
            Method::FanChengLai => "fan-cheng-lai",
            Method::DengWang => "deng-wang",
            Method::DengMa => "deng-ma",
            Method::Fair => "fair",
        }
    }

    /// One line on what the method does: paper, control scheme, how the
    /// control mesh is found (for help texts).
    pub fn summary(self) -> &'static str {
        match self {
            Method::Nasri => "Nasri 1987: Doo-Sabin, the global system C·M⁰ = P",
            Method::ZhengCai => "Zheng & Cai 2005: Doo-Sabin, a few Gauss-Seidel sweeps + exact perturbation of M¹",
            Method::Cheng => "Cheng et al.: Catmull-Clark (or Loop, √3), A·M̂ = P",
            Method::FanChengLai => "Fan, Cheng & Lai: two-phase Doo-Sabin with per-face shape λ",
            Method::DengWang => "Deng & Wang 2010: Loop, explicit modified first step",
            Method::DengMa => "Deng & Ma 2011: interpolatory scheme derived from Doo-Sabin (no control mesh)",
            Method::Fair => {
                "Halstead, Kass & DeRose 1993: Catmull-Clark (or Loop, Doo-Sabin), the fairest control mesh of the \
                 input refined K times"
            }
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A method name [`Method::from_str`] does not know.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown method '{name}' (expected one of: {})", method_names())]
pub struct UnknownMethod {
    /// The name given.
    pub name: String,
}

fn method_names() -> String {
    Method::ALL.map(Method::name).join(", ")
}

impl FromStr for Method {
    type Err = UnknownMethod;

    /// Parses [`Method::name`] (also with `_` for `-`, any case).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let wanted = s.trim().to_ascii_lowercase().replace('_', "-");
        Method::ALL.into_iter().find(|m| m.name() == wanted).ok_or_else(|| UnknownMethod { name: s.to_string() })
    }
}

/// A method with its own options: what [`interpolate`] runs.
///
/// `MethodOptions::new(method)` gives the method's defaults; the `with_*`
/// setters change the options every method shares ([`CommonOptions`],
/// [`SurfaceOptions`]); a method's own options are set on its options
/// struct, converted with `From`:
///
/// ```
/// use subdiv_interp::{interpolate, Method, MethodOptions, ZhengCaiOptions};
/// let torus = subdiv_mesh::shapes::torus(8, 6);
/// let cheng = MethodOptions::new(Method::Cheng).with_tol(1e-8);
/// let zheng_cai: MethodOptions = ZhengCaiOptions::default().with_ite_max(3).into();
/// for options in [cheng, zheng_cai] {
///     let result = interpolate(&torus, &options).unwrap();
///     assert!(result.error_all(&torus).max_rel <= options.tol());
/// }
/// let by_name: subdiv_interp::Method = "fan-cheng-lai".parse().unwrap();
/// assert_eq!(MethodOptions::new(by_name).method(), subdiv_interp::Method::FanChengLai);
/// ```
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum MethodOptions {
    /// [`nasri::interpolate`].
    Nasri(NasriOptions),
    /// [`zheng_cai::interpolate`].
    ZhengCai(ZhengCaiOptions),
    /// [`cheng::interpolate`].
    Cheng(ChengOptions),
    /// [`fan_cheng_lai::interpolate`].
    FanChengLai(FanChengLaiOptions),
    /// [`deng_wang::interpolate`].
    DengWang(DengWangOptions),
    /// [`deng_ma::interpolate`].
    DengMa(DengMaOptions),
    /// [`fair::interpolate`].
    Fair(FairOptions),
}

impl MethodOptions {
    /// `method` with its default options.
    pub fn new(method: Method) -> Self {
        match method {
            Method::Nasri => MethodOptions::Nasri(NasriOptions::default()),
            Method::ZhengCai => MethodOptions::ZhengCai(ZhengCaiOptions::default()),
            Method::Cheng => MethodOptions::Cheng(ChengOptions::default()),
            Method::FanChengLai => MethodOptions::FanChengLai(FanChengLaiOptions::default()),
            Method::DengWang => MethodOptions::DengWang(DengWangOptions::default()),
            Method::DengMa => MethodOptions::DengMa(DengMaOptions::default()),
            Method::Fair => MethodOptions::Fair(FairOptions::default()),
        }
    }

    /// What [`interpolate`] with these options needs on `mesh`, before anything
    /// is allocated: (the vertices of the mesh the method solves on, bytes per
    /// such vertex). The vertices are the input's, or for `fair` those of the
    /// input refined K times (exact, [`subdiv_stencil::size::refined_sizes`];
    /// `None` past `u64::MAX`). The bytes are the method's peak resident memory
    /// per vertex, measured on grids of 2·10⁴ to 5·10⁵ vertices (whole runs of
    /// `subdiv interpolate`: the mesh, the matrices, the solver, the output)
    /// with about half as much again for margin; semi-sharp tags widen the
    /// limit rows around them (composed over ⌈s⌉ levels) and cost more.
    ///
    /// | method | untagged | tagged |
    /// |---|---|---|
    /// | nasri, zheng-cai, fan-cheng-lai | 0.65–1.04 kB → 1.5 kB | (infinitely sharp only) |
    /// | cheng | 0.68 kB → 1 kB | 0.98–1.66 kB → 2.5 kB |
    /// | deng-wang | 1.07 kB → 1.6 kB | 1.34–2.06 kB → 3.2 kB |
    /// | fair (per refined vertex) | 0.78 kB → 1.2 kB | 1.0–1.13 kB → 1.8 kB |
    /// | deng-ma | 0.2 kB → 1 kB (its refined output is sized where it is written) | |
    pub fn estimated_memory(&self, mesh: &Mesh) -> (Option<u64>, u64) {
        let tagged = !mesh.tags().is_empty();
        let vertices = match self {
            MethodOptions::Fair(o) if o.refine > 0 => {
                // Past fair::MAX_REFINE the method refuses the option itself, with its reason.
                let levels = o.refine.min(fair::MAX_REFINE);
                let sizes = subdiv_stencil::size::refined_sizes(mesh.topology(), o.scheme, levels);
                sizes.last().filter(|_| sizes.len() == levels).map(|last| last.vertices)
            }
            _ => Some(mesh.topology().vertex_count() as u64),
        };
        let per_vertex = match (self.method(), tagged) {
            (Method::Nasri | Method::ZhengCai | Method::FanChengLai, _) => 1_536,
            (Method::Cheng, false) => 1_024,
            (Method::Cheng, true) => 2_560,
            (Method::DengWang, false) => 1_640,
            (Method::DengWang, true) => 3_280,
            (Method::Fair, false) => 1_230,
            (Method::Fair, true) => 1_840,
            (Method::DengMa, _) => 1_024,
        };
        (vertices, per_vertex)
    }

    /// The method these options run.
    pub fn method(&self) -> Method {
        match self {
            MethodOptions::Nasri(_) => Method::Nasri,
            MethodOptions::ZhengCai(_) => Method::ZhengCai,
            MethodOptions::Cheng(_) => Method::Cheng,
            MethodOptions::FanChengLai(_) => Method::FanChengLai,
            MethodOptions::DengWang(_) => Method::DengWang,
            MethodOptions::DengMa(_) => Method::DengMa,
            MethodOptions::Fair(_) => Method::Fair,
        }
    }

    /// The shared options (subset, tolerance, solver, surface); `None` for
    /// Deng-Ma, which solves nothing and interpolates every vertex exactly.
    pub fn common(&self) -> Option<&CommonOptions> {
        match self {
            MethodOptions::Nasri(o) => Some(&o.common),
            MethodOptions::ZhengCai(o) => Some(&o.common),
            MethodOptions::Cheng(o) => Some(&o.common),
            MethodOptions::FanChengLai(o) => Some(&o.common),
            MethodOptions::DengWang(o) => Some(&o.common),
            MethodOptions::Fair(o) => Some(&o.common),
            MethodOptions::DengMa(_) => None,
        }
    }

    /// [`Self::common`], mutable.
    pub fn common_mut(&mut self) -> Option<&mut CommonOptions> {
        match self {
            MethodOptions::Nasri(o) => Some(&mut o.common),
            MethodOptions::ZhengCai(o) => Some(&mut o.common),
            MethodOptions::Cheng(o) => Some(&mut o.common),
            MethodOptions::FanChengLai(o) => Some(&mut o.common),
            MethodOptions::DengWang(o) => Some(&mut o.common),
            MethodOptions::Fair(o) => Some(&mut o.common),
            MethodOptions::DengMa(_) => None,
        }
    }

    /// The surface options of the control mesh's scheme.
    pub fn surface(&self) -> SurfaceOptions {
        match self {
            MethodOptions::DengMa(o) => o.surface,
            other => other.common().expect("every other method has common options").surface,
        }
    }

    /// The bound on the measured error the result meets (relative to the
    /// bounding-box diagonal d); Deng-Ma's is 0: its surface passes through
    /// the data by construction.
    pub fn tol(&self) -> f64 {
        self.common().map_or(0.0, |c| c.tol)
    }

    /// Sets the tolerance (not read by Deng-Ma).
    pub fn with_tol(mut self, tol: f64) -> Self {
        if let Some(c) = self.common_mut() {
            c.tol = tol;
        }
        self
    }

    /// Sets the iteration cap (read by the solved methods).
    pub fn with_max_iter(mut self, max_iter: usize) -> Self {
        if let Some(c) = self.common_mut() {
            c.max_iter = max_iter;
        }
        self
    }

    /// Sets the solver (read by the solved methods).
    pub fn with_solver(mut self, solver: SolverChoice) -> Self {
        if let Some(c) = self.common_mut() {
            c.solver = solver;
        }
        self
    }

    /// Sets the vertices to interpolate (`None`: all).
    ///
    /// # Errors
    /// [`InterpError::InvalidParameter`] for Deng-Ma, whose surface passes
    /// through every vertex.
    pub fn with_subset(mut self, subset: impl Into<Option<Vec<u32>>>) -> Result<Self, InterpError> {
        let subset = subset.into();
        match self.common_mut() {
            Some(c) => c.subset = subset,
            None if subset.is_none() => {}
            None => {
                return Err(InterpError::invalid(
                    crate::Parameter::Subset,
                    "deng-ma passes through every vertex: it takes no subset",
                ))
            }
        }
        Ok(self)
    }

    /// Sets the observer told every iterate's residual (progress bars).
    pub fn with_observer(mut self, observer: subdiv_solve::IterationObserver) -> Self {
        if let Some(c) = self.common_mut() {
            c.observer = observer;
        }
        self
    }

    /// Sets the surface options (boundary, crease method, face-varying mode).
    pub fn with_surface(mut self, surface: SurfaceOptions) -> Self {
        match &mut self {
            MethodOptions::DengMa(o) => o.surface = surface,
            other => other.common_mut().expect("every other method has common options").surface = surface,
        }
        self
    }
}

impl Default for MethodOptions {
    /// Cheng's method with its defaults.
    fn default() -> Self {
        MethodOptions::new(Method::Cheng)
    }
}

impl From<Method> for MethodOptions {
    fn from(method: Method) -> Self {
        MethodOptions::new(method)
    }
}

macro_rules! method_options_from {
    ($($variant:ident($options:ty)),* $(,)?) => {$(
        impl From<$options> for MethodOptions {
            fn from(options: $options) -> Self {
                MethodOptions::$variant(options)
            }
        }
    )*};
}
method_options_from!(
    Nasri(NasriOptions),
    ZhengCai(ZhengCaiOptions),
    Cheng(ChengOptions),
    FanChengLai(FanChengLaiOptions),
    DengWang(DengWangOptions),
    DengMa(DengMaOptions),
    Fair(FairOptions),
);

/// Runs the method of `options` on `mesh` (its vertices are the data):
/// [`nasri::interpolate`], [`zheng_cai::interpolate`], … by
/// [`MethodOptions::method`].
///
/// # Errors
/// The method's [`InterpError`].
pub fn interpolate(mesh: &Mesh, options: &MethodOptions) -> Result<Interpolant, InterpError> {
    check_holes(mesh, options)?;
    let scheme = match options {
        MethodOptions::Cheng(o) => o.scheme,
        MethodOptions::Fair(o) => o.scheme,
        _ => Scheme::CatmullClark,
    };
    crate::preconditions::non_manifold(mesh, options.method(), scheme).map_err(|refusal| {
        InterpError::UnsupportedMesh {
            method: options.method().name(),
            reason: refusal.reason,
            suggestion: refusal.suggestion,
        }
    })?;
    match options {
        MethodOptions::Nasri(o) => nasri::interpolate(mesh, o),
        MethodOptions::ZhengCai(o) => zheng_cai::interpolate(mesh, o),
        MethodOptions::Cheng(o) => cheng::interpolate(mesh, o),
        MethodOptions::FanChengLai(o) => fan_cheng_lai::interpolate(mesh, o),
        MethodOptions::DengWang(o) => deng_wang::interpolate(mesh, o),
        MethodOptions::DengMa(o) => deng_ma::interpolate(mesh, o),
        MethodOptions::Fair(o) => fair::interpolate(mesh, o),
    }
}

/// Holes (`subdiv_stencil::holes`) are kept by the methods whose control
/// mesh is the input's topology under Catmull-Clark or Loop (`cheng`, `fair`
/// with either scheme) and by `deng-ma` (its surface is refined on the quad
/// split); the others make their control mesh by a split that mixes faces
/// (Doo-Sabin's dual split, Deng-Wang's triangulated first step) and refuse
/// a mesh with holes rather than lose them.
fn check_holes(mesh: &Mesh, options: &MethodOptions) -> Result<(), InterpError> {
    let holes = mesh.tags().hole_count();
    let keeps = match options {
        MethodOptions::Cheng(o) => matches!(o.scheme, Scheme::CatmullClark | Scheme::Loop(_)),
        MethodOptions::Fair(o) => matches!(o.scheme, Scheme::CatmullClark | Scheme::Loop(_)),
        MethodOptions::DengMa(_) => true,
        MethodOptions::Nasri(_)
        | MethodOptions::ZhengCai(_)
        | MethodOptions::FanChengLai(_)
        | MethodOptions::DengWang(_) => false,
    };
    if holes == 0 || keeps {
        return Ok(());
    }
    Err(InterpError::UnsupportedMesh {
        method: options.method().name(),
        reason: format!(
            "the mesh has {holes} hole face(s), which this method's control mesh cannot keep (holes stay on \
             Catmull-Clark and Loop control meshes of the input's topology, as in OpenSubdiv)"
        ),
        suggestion: "use --method cheng or --method fair (Catmull-Clark or Loop), or remove the hole tags".into(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_list_the_methods() {
        for m in Method::ALL {
            assert_eq!(m.name().parse::<Method>(), Ok(m));
            assert_eq!(m.to_string(), m.name());
            assert_eq!(MethodOptions::new(m).method(), m);
        }
        assert_eq!("Zheng_Cai".parse::<Method>(), Ok(Method::ZhengCai));
        let e = "catmull".parse::<Method>().unwrap_err();
        assert!(e.to_string().contains("'catmull'") && e.to_string().contains("deng-ma"), "{e}");
    }

    #[test]
    fn shared_setters_reach_every_method_with_common_options() {
        for m in Method::ALL {
            let o = MethodOptions::new(m).with_tol(1e-9).with_max_iter(7);
            match o.common() {
                Some(c) => assert_eq!((c.tol, c.max_iter), (1e-9, 7), "{m}"),
                None => assert_eq!(m, Method::DengMa),
            }
        }
        assert!(MethodOptions::new(Method::DengMa).with_subset(vec![0]).is_err());
        assert!(MethodOptions::new(Method::DengMa).with_subset(None).is_ok());
    }
}
