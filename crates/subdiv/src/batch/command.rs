//! What a batch runs on every mesh: [`Command`] and its options, parsed
//! from JSON (the Python package's keyword arguments, the command line's
//! flags) or built in Rust.

use super::BatchError;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt::Display;
use std::str::FromStr;
use subdiv_interp::{Method, SolverChoice};
use subdiv_stencil::{BoundaryInterpolation, CreaseMethod, FVarInterpolation};

/// One command, run on every input of a batch.
///
/// Serialised with its name under `"command"` and its options beside it
/// (`{"command": "interpolate", "method": "cheng", "tol": 1e-9}`); an
/// option no command has is an error naming it (`deny_unknown_fields`), so
/// a misspelled keyword argument never passes silently.
///
/// ```
/// use subdiv::batch::{Command, InterpolateOptions};
/// use subdiv::Method;
/// let json = serde_json::json!({"method": "cheng", "tol": 1e-9, "levels": 2});
/// let command = Command::from_json("interpolate", &json)?;
/// let mut options = InterpolateOptions::new(Method::Cheng).with_tol(1e-9);
/// options.levels = 2;
/// assert_eq!(command, Command::Interpolate(options));
///
/// let typo = serde_json::json!({"method": "cheng", "tolerance": 1e-9});
/// let e = Command::from_json("interpolate", &typo).unwrap_err();
/// assert!(e.to_string().contains("unknown field `tolerance`"), "{e}");
/// # Ok::<(), subdiv::batch::BatchError>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "command", rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Command {
    /// `subdiv info`: the [`crate::info::Summary`] of each mesh; writes no
    /// mesh.
    Info(InfoOptions),
    /// `subdiv interpolate`: a control mesh (and its surface) per mesh.
    Interpolate(InterpolateOptions),
    /// `subdiv subdivide`: the refined mesh per mesh.
    Subdivide(SubdivideOptions),
}

/// The command names [`Command::from_json`] takes.
pub const COMMAND_NAMES: [&str; 3] = ["info", "interpolate", "subdivide"];

impl Command {
    /// The command `name` (`info`, `interpolate`, `subdivide`) with the
    /// options of the JSON object `options` (`null` or `{}`: the defaults),
    /// checked ([`Self::validate`]).
    ///
    /// # Errors
    /// [`BatchError::UnknownCommand`]; [`BatchError::Options`] for an
    /// unknown or mistyped option, a missing required one (`method`,
    /// `scheme`, `levels`) or a value out of range.
    pub fn from_json(name: &str, options: &serde_json::Value) -> Result<Self, BatchError> {
        let empty = serde_json::Value::Object(serde_json::Map::new());
        let options = if options.is_null() { &empty } else { options };
        let parse = |e: serde_json::Error| BatchError::Options { command: name.to_string(), message: e.to_string() };
        let command = match name {
            "info" => Command::Info(InfoOptions::deserialize(options).map_err(parse)?),
            "interpolate" => Command::Interpolate(InterpolateOptions::deserialize(options).map_err(parse)?),
            "subdivide" => Command::Subdivide(SubdivideOptions::deserialize(options).map_err(parse)?),
            _ => return Err(BatchError::UnknownCommand { name: name.to_string() }),
        };
        command.validate()?;
        Ok(command)
    }

    /// The command's name, as [`Self::from_json`] takes it.
    pub fn name(&self) -> &'static str {
        match self {
            Command::Info(_) => "info",
            Command::Interpolate(_) => "interpolate",
            Command::Subdivide(_) => "subdivide",
        }
    }

    /// Checks what the types cannot: options that apply to one method or
    /// scheme only, ranges, the output format. [`super::run`] and
    /// [`super::run_one`] check too; an invalid command runs on nothing.
    ///
    /// # Errors
    /// [`BatchError::Options`] naming the option.
    pub fn validate(&self) -> Result<(), BatchError> {
        let fail = |message: String| Err(BatchError::Options { command: self.name().to_string(), message });
        match self {
            Command::Info(_) => Ok(()),
            Command::Interpolate(o) => {
                use Method::*;
                let misuse = |option: &str, methods: &str| fail(format!("{option} applies to method {methods} only"));
                if o.shape.is_some() && o.method != FanChengLai {
                    return misuse("shape", "fan-cheng-lai");
                }
                if (o.ite_max.is_some() || o.eps.is_some()) && o.method != ZhengCai {
                    return misuse("ite_max/eps", "zheng-cai");
                }
                if (o.mu.is_some() || o.beta.is_some()) && o.method != DengWang {
                    return misuse("mu/beta", "deng-wang");
                }
                if (o.omega.is_some() || o.variable_tension.is_some()) && o.method != DengMa {
                    return misuse("omega/variable_tension", "deng-ma");
                }
                if o.omega.is_some() && o.variable_tension.is_some() {
                    return fail("omega and variable_tension exclude each other".into());
                }
                if let Some(lambda) = o.shape {
                    if !(lambda > 0.0 && lambda < 1.0) {
                        return fail(format!("shape: λ = {lambda} is outside (0, 1)"));
                    }
                }
                if !(o.tol > 0.0 && o.tol.is_finite()) {
                    return fail(format!("tol must be positive, got {}", o.tol));
                }
                if o.method == DengMa && o.levels == 0 {
                    return fail("levels: method deng-ma writes its refined surface, which needs levels ≥ 1".into());
                }
                check_format(self.name(), o.format.as_deref())
            }
            Command::Subdivide(o) => {
                if o.scheme != SchemeName::DengMa && (o.omega.is_some() || o.variable_tension.is_some()) {
                    return fail("omega and variable_tension apply to scheme deng-ma only".into());
                }
                if o.omega.is_some() && o.variable_tension.is_some() {
                    return fail("omega and variable_tension exclude each other".into());
                }
                if o.scheme != SchemeName::Loop && (o.beta.is_some() || o.triangulate) {
                    return fail("beta and triangulate apply to scheme loop only".into());
                }
                if o.limit && o.scheme == SchemeName::DengMa {
                    return fail(
                        "limit: the Deng-Ma scheme is interpolatory and has no limit mask; its refined vertices are \
                         the surface"
                            .into(),
                    );
                }
                check_format(self.name(), o.format.as_deref())
            }
        }
    }
}

/// An output extension must be a format the writers know.
fn check_format(command: &str, format: Option<&str>) -> Result<(), BatchError> {
    let Some(ext) = format else { return Ok(()) };
    subdiv_io::Format::from_path(std::path::Path::new(&format!("output.{ext}")))
        .map(drop)
        .map_err(|e| BatchError::Options { command: command.to_string(), message: format!("format: {e}") })
}

/// The options of [`Command::Info`].
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[non_exhaustive]
pub struct InfoOptions {
    /// Warnings (isolated vertices, zero-area faces) are errors, as
    /// `subdiv info --strict`.
    #[serde(default)]
    pub strict: bool,
}

/// The options of [`Command::Interpolate`]: `subdiv interpolate`'s, less
/// the per-mesh parameter files (normals, handles, subsets, shape files).
///
/// Writes `NAME.control.EXT` (the control mesh; not for Deng-Ma, whose
/// control mesh is the input) and, when `levels > 0`, `NAME.surface.EXT`
/// (the limit surface `levels` levels down, with vertex normals): the files
/// `subdiv interpolate -o … --surface … --levels …` writes. The method's
/// own options (`shape`, `ite_max`, …) are `None` for its defaults and an
/// error for another method.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[non_exhaustive]
pub struct InterpolateOptions {
    /// The method ([`Method::name`]; required).
    #[serde(with = "named")]
    pub method: Method,
    /// Tolerance: max over vertices of |P − limit| / d.
    #[serde(default = "default_tol")]
    pub tol: f64,
    /// Iteration cap of the iterative solvers.
    #[serde(default = "default_max_iter")]
    pub max_iter: usize,
    /// `auto` or a [`subdiv_solve::Solver::name`].
    #[serde(default, with = "solver_choice")]
    pub solver: SolverChoice,
    /// Levels of the surface written; 0: no surface (Deng-Ma: ≥ 1).
    #[serde(default = "default_levels")]
    pub levels: usize,
    /// The output extension (`obj`, `ply`, `glb`, …); `None`: the input's
    /// (`obj` when the input's is no format the writers know).
    #[serde(default)]
    pub format: Option<String>,
    /// Boundary interpolation.
    #[serde(default, with = "named")]
    pub boundary: BoundaryInterpolation,
    /// Semi-sharp crease decay.
    #[serde(default, with = "named")]
    pub crease_method: CreaseMethod,
    /// Face-varying (texture coordinate) interpolation.
    #[serde(default, with = "named")]
    pub fvar: FVarInterpolation,
    /// Fan-Cheng-Lai: one shape parameter λ ∈ (0, 1) for every face.
    #[serde(default)]
    pub shape: Option<f64>,
    /// Zheng-Cai: ITE_MAX (default 5).
    #[serde(default)]
    pub ite_max: Option<usize>,
    /// Zheng-Cai: EPS (default 0.003).
    #[serde(default)]
    pub eps: Option<f64>,
    /// Deng-Wang: μ of Eq. 9 (default ⅜).
    #[serde(default)]
    pub mu: Option<f64>,
    /// Deng-Wang: Loop's β (default Warren's).
    #[serde(default)]
    pub beta: Option<Beta>,
    /// Deng-Ma: global tension ω ∈ (0, 1] (default 1).
    #[serde(default)]
    pub omega: Option<f64>,
    /// Deng-Ma: displacement-safe variable tension with this λ ∈ (0, 1].
    #[serde(default)]
    pub variable_tension: Option<f64>,
}

fn default_tol() -> f64 {
    subdiv_interp::DEFAULT_TOL
}
fn default_max_iter() -> usize {
    subdiv_interp::DEFAULT_MAX_ITER
}
fn default_levels() -> usize {
    3
}

impl InterpolateOptions {
    /// `method` with the command line's defaults (tolerance, iteration cap,
    /// automatic solver, 3 surface levels, the input's format, OpenSubdiv's
    /// default surface options). The other fields are public: set them.
    pub fn new(method: Method) -> Self {
        Self {
            method,
            tol: default_tol(),
            max_iter: default_max_iter(),
            solver: SolverChoice::Auto,
            levels: default_levels(),
            format: None,
            boundary: BoundaryInterpolation::default(),
            crease_method: CreaseMethod::default(),
            fvar: FVarInterpolation::default(),
            shape: None,
            ite_max: None,
            eps: None,
            mu: None,
            beta: None,
            omega: None,
            variable_tension: None,
        }
    }

    /// With this tolerance.
    pub fn with_tol(self, tol: f64) -> Self {
        Self { tol, ..self }
    }

    /// With this many surface levels (0: no surface).
    pub fn with_levels(self, levels: usize) -> Self {
        Self { levels, ..self }
    }

    /// With this output extension.
    pub fn with_format(self, format: impl Into<String>) -> Self {
        Self { format: Some(format.into()), ..self }
    }
}

/// Scheme names of [`SubdivideOptions::scheme`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum SchemeName {
    /// Doo-Sabin.
    DooSabin,
    /// Catmull-Clark.
    CatmullClark,
    /// Loop (triangles).
    Loop,
    /// Deng-Ma's interpolatory scheme.
    DengMa,
}

/// Loop's β by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Beta {
    /// Warren: 3/16 (k = 3), 3/(8k) (k > 3).
    Warren,
    /// Loop's original.
    Loop,
}

impl From<Beta> for subdiv_stencil::LoopBeta {
    fn from(b: Beta) -> Self {
        match b {
            Beta::Warren => subdiv_stencil::LoopBeta::Warren,
            Beta::Loop => subdiv_stencil::LoopBeta::Loop,
        }
    }
}

/// The options of [`Command::Subdivide`]: `subdiv subdivide`'s. Writes
/// `NAME.subdivided.EXT`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[non_exhaustive]
pub struct SubdivideOptions {
    /// The scheme (required).
    pub scheme: SchemeName,
    /// Subdivision steps (required; 0 with `limit`: the limit positions).
    pub levels: usize,
    /// Move the final vertices to their limit positions (not Deng-Ma).
    #[serde(default)]
    pub limit: bool,
    /// Loop's β (default Warren's).
    #[serde(default)]
    pub beta: Option<Beta>,
    /// Deng-Ma: global tension ω (default 1).
    #[serde(default)]
    pub omega: Option<f64>,
    /// Deng-Ma: variable tension λ.
    #[serde(default)]
    pub variable_tension: Option<f64>,
    /// Boundary interpolation.
    #[serde(default, with = "named")]
    pub boundary: BoundaryInterpolation,
    /// Semi-sharp crease decay.
    #[serde(default, with = "named")]
    pub crease_method: CreaseMethod,
    /// Face-varying interpolation.
    #[serde(default, with = "named")]
    pub fvar: FVarInterpolation,
    /// Loop on non-triangles: triangulate first.
    #[serde(default)]
    pub triangulate: bool,
    /// Write vertex normals.
    #[serde(default)]
    pub normals: bool,
    /// The output extension; `None`: the input's (or `obj`).
    #[serde(default)]
    pub format: Option<String>,
}

impl SubdivideOptions {
    /// `levels` steps of `scheme`, the command line's defaults otherwise.
    pub fn new(scheme: SchemeName, levels: usize) -> Self {
        Self {
            scheme,
            levels,
            limit: false,
            beta: None,
            omega: None,
            variable_tension: None,
            boundary: BoundaryInterpolation::default(),
            crease_method: CreaseMethod::default(),
            fvar: FVarInterpolation::default(),
            triangulate: false,
            normals: false,
            format: None,
        }
    }

    /// The subdivision options these name.
    pub fn options(&self) -> subdiv_stencil::Options {
        use subdiv_stencil::{Scheme, Tension};
        let scheme = match self.scheme {
            SchemeName::DooSabin => Scheme::DooSabin,
            SchemeName::CatmullClark => Scheme::CatmullClark,
            SchemeName::Loop => Scheme::Loop(self.beta.unwrap_or(Beta::Warren).into()),
            SchemeName::DengMa => Scheme::DengMa(match (self.omega, self.variable_tension) {
                (_, Some(lambda)) => Tension::Variable { lambda },
                (omega, None) => Tension::Global(omega.unwrap_or(1.0)),
            }),
        };
        subdiv_stencil::Options::new(scheme)
            .with_boundary(self.boundary)
            .with_crease_method(self.crease_method)
            .with_fvar(self.fvar)
    }
}

/// Option enums as their names (`"edge-and-corner"`), through `Display` and
/// `FromStr` (the names the command line takes).
mod named {
    use super::*;

    pub fn serialize<S: Serializer, T: Display>(value: &T, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(value)
    }

    pub fn deserialize<'de, D: Deserializer<'de>, T>(d: D) -> Result<T, D::Error>
    where
        T: FromStr,
        T::Err: Display,
    {
        let name = String::deserialize(d)?;
        name.parse().map_err(serde::de::Error::custom)
    }
}

/// [`SolverChoice`] as `"auto"` or a solver's name.
mod solver_choice {
    use super::*;
    use subdiv_solve::Solver;

    pub fn serialize<S: Serializer>(value: &SolverChoice, s: S) -> Result<S::Ok, S::Error> {
        match value {
            SolverChoice::Use(solver) => s.serialize_str(solver.name()),
            _ => s.serialize_str("auto"),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<SolverChoice, D::Error> {
        let name = String::deserialize(d)?;
        if name == "auto" {
            return Ok(SolverChoice::Auto);
        }
        name.parse::<Solver>().map(SolverChoice::Use).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn commands_round_trip_through_json() {
        let mut interpolate = InterpolateOptions::new(Method::ZhengCai).with_format("ply");
        interpolate.ite_max = Some(3);
        interpolate.solver = SolverChoice::Use(subdiv_solve::Solver::Minres);
        interpolate.boundary = BoundaryInterpolation::EdgeOnly;
        let mut subdivide = SubdivideOptions::new(SchemeName::Loop, 2);
        subdivide.beta = Some(Beta::Loop);
        for command in [
            Command::Info(InfoOptions { strict: true }),
            Command::Interpolate(interpolate),
            Command::Subdivide(subdivide),
        ] {
            let text = serde_json::to_value(&command).unwrap();
            assert_eq!(text["command"], command.name());
            assert_eq!(serde_json::from_value::<Command>(text.clone()).unwrap(), command);
            let mut options = text.as_object().unwrap().clone();
            options.remove("command");
            assert_eq!(Command::from_json(command.name(), &options.into()).unwrap(), command);
        }
    }

    #[test]
    fn misspelled_and_misapplied_options_are_errors_naming_them() {
        let e = Command::from_json("subdivide", &json!({"scheme": "loop", "levels": 1, "normal": true})).unwrap_err();
        assert!(e.to_string().contains("unknown field `normal`"), "{e}");
        let e = Command::from_json("interpolate", &json!({"method": "chen"})).unwrap_err();
        assert!(e.to_string().contains("unknown method 'chen'"), "{e}");
        let e = Command::from_json("interpolate", &json!({"method": "cheng", "omega": 0.5})).unwrap_err();
        assert!(e.to_string().contains("omega/variable_tension applies to method deng-ma only"), "{e}");
        let e = Command::from_json("interpolate", &json!({"method": "cheng", "boundary": "edge"})).unwrap_err();
        assert!(e.to_string().contains("unknown boundary interpolation `edge`"), "{e}");
        let e = Command::from_json("interpolate", &json!({"method": "cheng", "format": "xyz"})).unwrap_err();
        assert!(e.to_string().contains("format"), "{e}");
        let e = Command::from_json("subdivide", &json!({"scheme": "loop"})).unwrap_err();
        assert!(e.to_string().contains("missing field `levels`"), "{e}");
        let e = Command::from_json("interpolat", &json!({})).unwrap_err();
        assert!(matches!(e, BatchError::UnknownCommand { .. }), "{e}");
        assert_eq!(
            Command::from_json("info", &serde_json::Value::Null).unwrap(),
            Command::Info(InfoOptions::default())
        );
    }
}
