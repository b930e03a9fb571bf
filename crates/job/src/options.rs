//! What a job runs: [`Command`] and its options, as serde values.
//!
//! Every front-end builds its options here and nowhere else: the command line turns the flags it
//! was given into a JSON object (`--max-iter 50` → `"max_iter": 50`), `subdiv batch` the same,
//! the Python package its keyword arguments, Rust code the structs and their setters. So the
//! defaults, the checks and the messages are the same everywhere:
//!
//! - an option that is absent takes the library's default (the method's options struct:
//!   [`subdiv_interp::ZhengCaiOptions`]'s `ite_max`, [`subdiv_interp::deng_wang::DEFAULT_MU`], …);
//! - an option no command has is an error naming it (`deny_unknown_fields`), so a misspelled
//!   keyword never passes silently;
//! - an option that does not apply to the chosen method or scheme is refused by
//!   [`Command::validate`], with the same message on every front-end
//!   (`--mu applies to --method deng-wang only`).
//!
//! Messages name options in the command line's terms (`--max-iter`); the JSON keys and Python
//! keywords are the same names in snake case (`max_iter`).

use crate::error::JobError;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt::Display;
use std::path::PathBuf;
use std::str::FromStr;
use subdiv_interp::SurfaceOptions;
use subdiv_interp::{Method, SolverChoice};
use subdiv_mesh::FileOptions;
use subdiv_stencil::{
    BoundaryInterpolation, CreaseMethod, DartLimit, FVarInterpolation, LoopBeta, Scheme, Tension, TriangleRule,
};

/// One command, run on one mesh ([`crate::run`]) or on every input of a batch ([`crate::batch`]).
///
/// Serialised with its name under `"command"` and its options beside it
/// (`{"command": "interpolate", "method": "cheng", "tol": 1e-9}`).
///
/// ```
/// use subdiv_job::{Command, InterpolateOptions};
/// use subdiv_interp::Method;
/// let json = serde_json::json!({"method": "cheng", "tol": 1e-9, "levels": 2});
/// let command = Command::from_json("interpolate", &json)?;
/// let options = InterpolateOptions::new(Method::Cheng).with_tol(1e-9).with_levels(2);
/// assert_eq!(command, Command::Interpolate(options));
///
/// let typo = serde_json::json!({"method": "cheng", "tolerance": 1e-9});
/// let e = Command::from_json("interpolate", &typo).unwrap_err();
/// assert!(e.to_string().contains("unknown option `tolerance`"), "{e}");
///
/// let misplaced = serde_json::json!({"method": "cheng", "mu": 0.3});
/// let e = Command::from_json("interpolate", &misplaced).unwrap_err();
/// assert_eq!(e.to_string(), "--mu applies to --method deng-wang only");
/// # Ok::<(), subdiv_job::JobError>(())
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "command", rename_all = "kebab-case")]
#[non_exhaustive]
// One command is built per run or batch and matched by value everywhere: boxing the large
// variant would cost every caller a `Box` for nothing.
#[allow(clippy::large_enum_variant)]
pub enum Command {
    /// `subdiv info`: the [`crate::info::Summary`] of each mesh; writes no mesh.
    Info(InfoOptions),
    /// `subdiv interpolate`: a control mesh (and its surface) per mesh.
    Interpolate(InterpolateOptions),
    /// `subdiv subdivide`: the refined mesh per mesh.
    Subdivide(SubdivideOptions),
}

/// The command names [`Command::from_json`] takes.
pub const COMMAND_NAMES: [&str; 3] = ["info", "interpolate", "subdivide"];

impl Command {
    /// The command `name` (`info`, `interpolate`, `subdivide`) with the options of the JSON
    /// object `options` (`null` or `{}`: the defaults), checked ([`Self::validate`]).
    ///
    /// # Errors
    /// A bad-input [`JobError`] for an unknown command, an unknown or mistyped option, a
    /// missing required one (`method`, `scheme`, `levels`), a value out of range or an option
    /// of another method or scheme.
    pub fn from_json(name: &str, options: &serde_json::Value) -> Result<Self, JobError> {
        let empty = serde_json::Value::Object(serde_json::Map::new());
        let options = if options.is_null() { &empty } else { options };
        // The options are the flags and keyword arguments: "unknown option `tolerance`".
        let parse = |e: serde_json::Error| {
            JobError::bad_input(
                e.to_string().replace("unknown field", "unknown option").replace("missing field", "missing option"),
            )
        };
        let command = match name {
            "info" => Command::Info(InfoOptions::deserialize(options).map_err(parse)?),
            "interpolate" => Command::Interpolate(InterpolateOptions::deserialize(options).map_err(parse)?),
            "subdivide" => Command::Subdivide(SubdivideOptions::deserialize(options).map_err(parse)?),
            _ => {
                return Err(JobError::bad_input(format!(
                    "unknown command '{name}' (expected one of: {})",
                    COMMAND_NAMES.join(", ")
                )))
            }
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

    /// Checks what the types cannot: options that apply to one method or scheme only, ranges,
    /// the output format. Every runner checks too; an invalid command runs on nothing.
    ///
    /// # Errors
    /// A bad-input [`JobError`] naming the option.
    pub fn validate(&self) -> Result<(), JobError> {
        match self {
            Command::Info(_) => Ok(()),
            Command::Interpolate(o) => o.validate(),
            Command::Subdivide(o) => o.validate(),
        }
    }
}

/// `Err` naming `flag` as applying to `what` only.
fn misplaced(flag: &str, what: &str) -> Result<(), JobError> {
    Err(JobError::bad_input(format!("{flag} applies to {what} only")))
}

/// An output extension must be a format the writers know.
fn check_format(format: Option<&str>) -> Result<(), JobError> {
    let Some(ext) = format else { return Ok(()) };
    subdiv_io::Format::from_path(std::path::Path::new(&format!("output.{ext}")))
        .map(drop)
        .map_err(|e| JobError::bad_input(format!("--format: {e}")))
}

/// Deng-Ma's tension flags: at most one, in range.
fn tension(omega: Option<f64>, variable_tension: Option<f64>) -> Result<Option<Tension>, JobError> {
    let tension = match (omega, variable_tension) {
        (Some(_), Some(_)) => return Err(JobError::bad_input("--omega and --variable-tension exclude each other")),
        (_, Some(lambda)) => Tension::Variable { lambda },
        (Some(omega), None) => Tension::Global(omega),
        (None, None) => return Ok(None),
    };
    tension.validate().map_err(|e| JobError::bad_input(format!("--omega/--variable-tension: {e}")))?;
    Ok(Some(tension))
}

/// The feature angle in range.
fn check_feature_angle(deg: Option<f64>) -> Result<(), JobError> {
    match deg {
        Some(deg) if !(deg > 0.0 && deg <= 180.0) => {
            Err(JobError::bad_input(format!("--feature-angle: {deg}° is outside (0, 180]")))
        }
        _ => Ok(()),
    }
}

/// The options of [`Command::Info`].
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[non_exhaustive]
pub struct InfoOptions {
    /// Warnings (isolated vertices, zero-area faces) are errors, as `subdiv info --strict`.
    #[serde(default)]
    pub strict: bool,
}

impl InfoOptions {
    /// With or without `strict`.
    pub fn with_strict(self, strict: bool) -> Self {
        Self { strict }
    }
}

/// Where the tags of a mesh come from besides its file's own `t` lines: a tag file, feature
/// edges by angle. Shared by [`InterpolateOptions`] and [`SubdivideOptions`].
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[non_exhaustive]
pub struct TagOptions {
    /// A JSON tag file `{"creases": [[v0, v1, s], …], "corners": [[v, s], …]}` (`--tags`).
    #[serde(default)]
    pub tags: Option<PathBuf>,
    /// Every interior edge whose faces turn by at least this many degrees becomes an
    /// infinitely sharp crease (`--feature-angle`); tags of the file win.
    #[serde(default)]
    pub feature_angle: Option<f64>,
    /// The one `Mesh` prim of a USD input to process, by its path (`--prim /World/Body`);
    /// absent: every Mesh prim of the file ([`crate::scene`]).
    #[serde(default)]
    pub prim: Option<String>,
}

/// OpenSubdiv's surface options as a command gives them (`--boundary`, `--crease-method`,
/// `--fvar`, `--triangle-rule`, `--dart-limit`): each `None` when not given, and then the mesh file's own option
/// tags (`t interpolateboundary` …, [`FileOptions`]) decide, and then the default. Shared by
/// [`InterpolateOptions`] and [`SubdivideOptions`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[non_exhaustive]
pub struct SurfaceChoice {
    /// Boundary interpolation.
    #[serde(default, with = "optional_named", skip_serializing_if = "Option::is_none")]
    pub boundary: Option<BoundaryInterpolation>,
    /// Semi-sharp crease decay.
    #[serde(default, with = "optional_named", skip_serializing_if = "Option::is_none")]
    pub crease_method: Option<CreaseMethod>,
    /// Face-varying (texture coordinate) interpolation.
    #[serde(default, with = "optional_named", skip_serializing_if = "Option::is_none")]
    pub fvar: Option<FVarInterpolation>,
    /// Catmull-Clark's triangle rule.
    #[serde(default, with = "optional_named", skip_serializing_if = "Option::is_none")]
    pub triangle_rule: Option<TriangleRule>,
    /// Which limit point a dart gets (`--dart-limit`): the limit of refinement (default), or
    /// OpenSubdiv's limit-stencil shortcut. Not a file option.
    #[serde(default, with = "optional_named", skip_serializing_if = "Option::is_none")]
    pub dart_limit: Option<DartLimit>,
}

impl SurfaceChoice {
    /// The surface options under these choices and the file's options `file`: each the
    /// command's where given, else the file's, else the default.
    pub fn surface_options(&self, file: FileOptions) -> SurfaceOptions {
        SurfaceOptions::default()
            .with_boundary(self.boundary.or(file.boundary).unwrap_or_default())
            .with_crease_method(self.crease_method.or(file.crease_method).unwrap_or_default())
            .with_fvar(self.fvar.or(file.fvar).unwrap_or_default())
            .with_triangle_rule(self.triangle_rule.or(file.triangle_rule).unwrap_or_default())
            .with_dart_limit(self.dart_limit.unwrap_or_default())
    }

    /// The subdivision options of `scheme` under these choices and the file's options.
    pub fn options(&self, scheme: Scheme, file: FileOptions) -> subdiv_stencil::Options {
        self.surface_options(file).for_scheme(scheme)
    }
}

/// A per-vertex or per-face parameter: a parameter file's path, or its content inline (the
/// JSON form of the file: `{"3": [0, 0, 1]}`, `[0, 4, 7]`, …), which the Python package passes.
/// Both are read by the one parser, [`subdiv_interp::params`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Parameter {
    /// A parameter file (text or JSON), read through `subdiv-io`.
    File(PathBuf),
    /// The file's JSON content.
    Inline(serde_json::Value),
}

/// The options of [`Command::Interpolate`]: `subdiv interpolate`'s, one for one.
///
/// An option left `None` takes the library's default; one of another method is refused by
/// [`Self::validate`]. The outputs of a batch job are `NAME.control.EXT` (the control mesh;
/// not for Deng-Ma, whose control mesh is the input) and, when `levels > 0`,
/// `NAME.surface.EXT` (the surface `levels` levels down, with vertex normals).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[non_exhaustive]
pub struct InterpolateOptions {
    /// The method ([`Method::name`]; required).
    #[serde(with = "named")]
    pub method: Method,
    /// Tolerance: max over vertices of |P − limit| / d (default [`subdiv_interp::DEFAULT_TOL`]).
    #[serde(default = "default_tol")]
    pub tol: f64,
    /// Iteration cap of the iterative solvers (default [`subdiv_interp::DEFAULT_MAX_ITER`]).
    #[serde(default = "default_max_iter")]
    pub max_iter: usize,
    /// `auto` or a [`subdiv_solve::Solver::name`].
    #[serde(default, with = "solver_choice")]
    pub solver: SolverChoice,
    /// Levels of the surface written; 0: no surface (Deng-Ma: ≥ 1, its output is the surface).
    #[serde(default = "default_levels")]
    pub levels: usize,
    /// A batch's output extension (`obj`, `ply`, `glb`, …); `None`: the input's (`obj` when the
    /// input's is no format the writers know).
    #[serde(default)]
    pub format: Option<String>,
    /// OpenSubdiv's surface options (each defaulting to the file's, then OpenSubdiv's).
    #[serde(default, flatten)]
    pub surface: SurfaceChoice,
    /// Tags besides the file's.
    #[serde(default, flatten)]
    pub tags: TagOptions,
    /// The vertices to interpolate (default all).
    #[serde(default)]
    pub subset: Option<Parameter>,
    /// Zheng-Cai, Deng-Wang: prescribed normals.
    #[serde(default)]
    pub normals: Option<Parameter>,
    /// Zheng-Cai: Brunet shape handles.
    #[serde(default)]
    pub handles: Option<Parameter>,
    /// Fan-Cheng-Lai: one λ ∈ (0, 1) for every face, or one per face (a list).
    #[serde(default)]
    pub shape: Option<ShapeValue>,
    /// Fan-Cheng-Lai: a shape file `{"default": λ, "faces": {…}, "groups": {…}}`.
    #[serde(default)]
    pub shape_file: Option<Parameter>,
    /// Zheng-Cai: ITE_MAX, the Gauss-Seidel sweeps on the auxiliary mesh.
    #[serde(default)]
    pub ite_max: Option<usize>,
    /// Zheng-Cai: EPS, the sweeps stop when every update is below EPS·d.
    #[serde(default)]
    pub eps: Option<f64>,
    /// Deng-Wang: μ of Eq. 9.
    #[serde(default)]
    pub mu: Option<f64>,
    /// Deng-Wang, and `cheng` and `fair` with the Loop scheme: Loop's β.
    #[serde(default, with = "optional_named")]
    pub beta: Option<LoopBeta>,
    /// Deng-Ma: global tension ω ∈ (0, 1].
    #[serde(default)]
    pub omega: Option<f64>,
    /// Deng-Ma: displacement-safe variable tension with this λ ∈ (0, 1].
    #[serde(default)]
    pub variable_tension: Option<f64>,
    /// `fair`: the control mesh is the input refined this many times.
    #[serde(default)]
    pub refine: Option<usize>,
    /// `fair`: trade interpolation for fairness (the result approximates).
    #[serde(default)]
    pub fairness_weight: Option<f64>,
    /// `cheng` and `fair`: the control mesh's scheme (default Catmull-Clark; `cheng` also
    /// takes Loop and √3, `fair` Loop and Doo-Sabin).
    #[serde(default, with = "optional_named")]
    pub scheme: Option<Scheme>,
    /// Memory budget of the method and the refinements, in bytes (default ¾ of the memory
    /// available).
    #[serde(default)]
    pub max_memory: Option<u64>,
}

/// Fan-Cheng-Lai's `shape`: one λ, or one per face.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ShapeValue {
    /// One λ for every face.
    Uniform(f64),
    /// One λ per face, in face order.
    PerFace(Vec<f64>),
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
    /// `method` with the defaults (tolerance, iteration cap, automatic solver, 3 surface levels,
    /// the input's format, OpenSubdiv's default surface options, each method's own defaults).
    pub fn new(method: Method) -> Self {
        Self {
            method,
            tol: default_tol(),
            max_iter: default_max_iter(),
            solver: SolverChoice::Auto,
            levels: default_levels(),
            format: None,
            surface: SurfaceChoice::default(),
            tags: TagOptions::default(),
            subset: None,
            normals: None,
            handles: None,
            shape: None,
            shape_file: None,
            ite_max: None,
            eps: None,
            mu: None,
            beta: None,
            omega: None,
            variable_tension: None,
            refine: None,
            fairness_weight: None,
            scheme: None,
            max_memory: None,
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

    /// With this output extension (batch).
    pub fn with_format(self, format: impl Into<String>) -> Self {
        Self { format: Some(format.into()), ..self }
    }

    /// The options from a JSON object (as [`Command::from_json`] for `interpolate`).
    ///
    /// # Errors
    /// As [`Command::from_json`].
    pub fn from_json(options: &serde_json::Value) -> Result<Self, JobError> {
        match Command::from_json("interpolate", options)? {
            Command::Interpolate(o) => Ok(o),
            _ => unreachable!("an interpolate command parses as one"),
        }
    }

    /// Checks the options that apply to some methods only, and the ranges the types do not
    /// hold, in the order the command line lists them.
    ///
    /// # Errors
    /// A bad-input [`JobError`] naming the option.
    pub fn validate(&self) -> Result<(), JobError> {
        use Method::*;
        let m = self.method;
        if self.shape.is_some() && self.shape_file.is_some() {
            return Err(JobError::bad_input("--shape and --shape-file exclude each other"));
        }
        if self.shape.is_some() && m != FanChengLai {
            return misplaced("--shape", "--method fan-cheng-lai");
        }
        if self.shape_file.is_some() && m != FanChengLai {
            return misplaced("--shape-file", "--method fan-cheng-lai");
        }
        if self.handles.is_some() && m != ZhengCai {
            return misplaced("--handles", "--method zheng-cai");
        }
        if self.ite_max.is_some() && m != ZhengCai {
            return misplaced("--ite-max", "--method zheng-cai");
        }
        if self.eps.is_some() && m != ZhengCai {
            return misplaced("--eps", "--method zheng-cai");
        }
        if self.normals.is_some() && !matches!(m, ZhengCai | DengWang) {
            return misplaced("--normals", "--method zheng-cai or deng-wang");
        }
        if self.mu.is_some() && m != DengWang {
            return misplaced("--mu", "--method deng-wang");
        }
        if self.omega.is_some() && m != DengMa {
            return misplaced("--omega", "--method deng-ma");
        }
        if self.variable_tension.is_some() && m != DengMa {
            return misplaced("--variable-tension", "--method deng-ma");
        }
        if self.refine.is_some() && m != Fair {
            return misplaced("--refine", "--method fair");
        }
        if self.fairness_weight.is_some() && m != Fair {
            return misplaced("--fairness-weight", "--method fair");
        }
        if self.scheme.is_some() && !matches!(m, Cheng | Fair) {
            return misplaced("--scheme", "--method cheng and --method fair");
        }
        if self.beta.is_some() {
            let loop_scheme = matches!(m, Cheng | Fair) && matches!(self.scheme, Some(Scheme::Loop(_)));
            if m != DengWang && !loop_scheme {
                return misplaced("--beta", "--method deng-wang and --method cheng or fair with --scheme loop");
            }
        }
        if let Some(ShapeValue::Uniform(lambda)) = self.shape {
            if !(lambda > 0.0 && lambda < 1.0) {
                return Err(JobError::bad_input(format!("--shape: λ = {lambda} is outside (0, 1)")));
            }
        }
        if !(self.tol > 0.0 && self.tol.is_finite()) {
            return Err(JobError::bad_input(format!("--tol must be positive, got {}", self.tol)));
        }
        tension(self.omega, self.variable_tension)?;
        check_feature_angle(self.tags.feature_angle)?;
        if m == DengMa && self.levels == 0 {
            return Err(JobError::bad_input(
                "--levels: method deng-ma writes its refined surface, which needs --levels ≥ 1",
            ));
        }
        check_format(self.format.as_deref())
    }

    /// Deng-Ma's tension (`None`: the default).
    pub(crate) fn tension(&self) -> Option<Tension> {
        tension(self.omega, self.variable_tension).ok().flatten()
    }
}

/// The options of [`Command::Subdivide`]: `subdiv subdivide`'s. Writes `NAME.subdivided.EXT` in
/// a batch.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[non_exhaustive]
pub struct SubdivideOptions {
    /// The scheme (required; [`Scheme::name`]).
    #[serde(with = "named")]
    pub scheme: Scheme,
    /// Subdivision steps (required; 0 with `limit`: the limit positions).
    pub levels: usize,
    /// Move the final vertices to their limit positions (not Deng-Ma).
    #[serde(default)]
    pub limit: bool,
    /// Loop's β (default Loop's, as OpenSubdiv).
    #[serde(default, with = "optional_named")]
    pub beta: Option<LoopBeta>,
    /// Deng-Ma: global tension ω (default 1).
    #[serde(default)]
    pub omega: Option<f64>,
    /// Deng-Ma: variable tension λ.
    #[serde(default)]
    pub variable_tension: Option<f64>,
    /// OpenSubdiv's surface options (each defaulting to the file's, then OpenSubdiv's).
    #[serde(default, flatten)]
    pub surface: SurfaceChoice,
    /// Tags besides the file's.
    #[serde(default, flatten)]
    pub tags: TagOptions,
    /// Loop on non-triangles: triangulate first.
    #[serde(default)]
    pub triangulate: bool,
    /// Write vertex normals.
    #[serde(default)]
    pub normals: bool,
    /// A batch's output extension; `None`: the input's (or `obj`).
    #[serde(default)]
    pub format: Option<String>,
    /// Memory budget of the refinement, in bytes (default ¾ of the memory available).
    #[serde(default)]
    pub max_memory: Option<u64>,
}

impl SubdivideOptions {
    /// `levels` steps of `scheme` (its parameters, Loop's β and Deng-Ma's tension, are taken
    /// from it), the defaults otherwise.
    pub fn new(scheme: Scheme, levels: usize) -> Self {
        // The parameters that differ from the scheme's defaults become the options that set them.
        let (beta, tension) = scheme.parameters();
        let beta = beta.filter(|&b| b != LoopBeta::default());
        let (omega, variable_tension) = match tension.filter(|&t| t != Tension::default()) {
            Some(Tension::Global(omega)) => (Some(omega), None),
            Some(Tension::Variable { lambda }) => (None, Some(lambda)),
            None => (None, None),
        };
        Self {
            scheme,
            levels,
            limit: false,
            beta,
            omega,
            variable_tension,
            surface: SurfaceChoice::default(),
            tags: TagOptions::default(),
            triangulate: false,
            normals: false,
            format: None,
            max_memory: None,
        }
    }

    /// With limit positions.
    pub fn with_limit(self, limit: bool) -> Self {
        Self { limit, ..self }
    }

    /// With this output extension (batch).
    pub fn with_format(self, format: impl Into<String>) -> Self {
        Self { format: Some(format.into()), ..self }
    }

    /// Checks the options that apply to some schemes only.
    ///
    /// # Errors
    /// A bad-input [`JobError`] naming the option.
    pub fn validate(&self) -> Result<(), JobError> {
        // The scheme table says which parameters belong to which scheme.
        self.scheme_with_parameters()?;
        let traits = self.scheme.traits();
        if self.triangulate && !traits.triangles_only {
            return misplaced("--triangulate", "the triangle schemes (--scheme loop)");
        }
        check_feature_angle(self.tags.feature_angle)?;
        if self.limit && traits.interpolating {
            return Err(JobError::bad_input(format!(
                "--limit: the {} scheme is interpolatory and has no limit mask; its refined vertices are the surface",
                self.scheme.name()
            )));
        }
        check_format(self.format.as_deref())
    }

    /// The scheme with Loop's β and Deng-Ma's tension of these options.
    fn scheme_with_parameters(&self) -> Result<Scheme, JobError> {
        let tension = tension(self.omega, self.variable_tension)?;
        self.scheme.with_parameters(self.beta, tension).map_err(|e| JobError::bad_input(e.to_string()))
    }

    /// The subdivision options these name for a mesh whose file sets `file` (the options given
    /// here win).
    pub fn options(&self, file: FileOptions) -> subdiv_stencil::Options {
        self.surface.options(self.scheme_with_parameters().unwrap_or(self.scheme), file)
    }
}

/// Option enums as their names (`"edge-and-corner"`), through `Display` and `FromStr` (the
/// names the command line takes).
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

/// [`named`] for an optional value (`null` or absent: `None`).
mod optional_named {
    use super::*;

    pub fn serialize<S: Serializer, T: Display>(value: &Option<T>, s: S) -> Result<S::Ok, S::Error> {
        match value {
            Some(v) => s.collect_str(v),
            None => s.serialize_none(),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>, T>(d: D) -> Result<Option<T>, D::Error>
    where
        T: FromStr,
        T::Err: Display,
    {
        let name = Option::<String>::deserialize(d)?;
        name.map(|n| n.parse().map_err(serde::de::Error::custom)).transpose()
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
        name.parse::<Solver>()
            .map(SolverChoice::Use)
            .map_err(|_| serde::de::Error::custom(format!("--solver: unknown solver '{name}'")))
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
        interpolate.surface.boundary = Some(BoundaryInterpolation::EdgeOnly);
        interpolate.normals = Some(Parameter::Inline(json!({"3": [0.0, 0.0, 1.0]})));
        interpolate.tags.feature_angle = Some(30.0);
        let mut fair = InterpolateOptions::new(Method::Fair);
        fair.scheme = Some(Scheme::Loop(LoopBeta::default())); // by name: β is its own option
        fair.beta = Some(LoopBeta::Warren);
        fair.refine = Some(2);
        let mut subdivide = SubdivideOptions::new(Scheme::Loop(LoopBeta::Loop), 2);
        subdivide.beta = Some(LoopBeta::Warren);
        for command in [
            Command::Info(InfoOptions { strict: true }),
            Command::Interpolate(interpolate),
            Command::Interpolate(fair),
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
        assert!(e.to_string().contains("unknown option `normal`"), "{e}");
        let e = Command::from_json("interpolate", &json!({"method": "chen"})).unwrap_err();
        assert!(e.to_string().contains("unknown method 'chen'"), "{e}");
        let e = Command::from_json("interpolate", &json!({"method": "cheng", "omega": 0.5})).unwrap_err();
        assert_eq!(e.to_string(), "--omega applies to --method deng-ma only");
        let e = Command::from_json("interpolate", &json!({"method": "cheng", "ite_max": 9})).unwrap_err();
        assert_eq!(e.to_string(), "--ite-max applies to --method zheng-cai only");
        let e = Command::from_json("interpolate", &json!({"method": "cheng", "boundary": "edge"})).unwrap_err();
        assert!(e.to_string().contains("unknown boundary interpolation `edge`"), "{e}");
        let e = Command::from_json("interpolate", &json!({"method": "cheng", "format": "xyz"})).unwrap_err();
        assert!(e.to_string().contains("--format"), "{e}");
        let e = Command::from_json("interpolate", &json!({"method": "fair", "beta": "loop"})).unwrap_err();
        assert!(e.to_string().starts_with("--beta applies to"), "{e}");
        let e = Command::from_json("interpolate", &json!({"method": "nasri", "scheme": "loop"})).unwrap_err();
        assert_eq!(e.to_string(), "--scheme applies to --method cheng and --method fair only");
        let e = Command::from_json("interpolate", &json!({"method": "cheng", "scheme": "sqrt3", "beta": "loop"}))
            .unwrap_err();
        assert_eq!(
            e.to_string(),
            "--beta applies to --method deng-wang and --method cheng or fair with --scheme loop only"
        );
        for (method, scheme) in [("cheng", "sqrt3"), ("cheng", "loop"), ("fair", "loop")] {
            let o = json!({"method": method, "scheme": scheme, "beta": if scheme == "loop" { json!("loop") } else { json!(null) }});
            assert!(Command::from_json("interpolate", &o).is_ok(), "{method} --scheme {scheme}");
        }
        let e = Command::from_json("subdivide", &json!({"scheme": "loop"})).unwrap_err();
        assert!(e.to_string().contains("missing option `levels`"), "{e}");
        let e = Command::from_json("subdivide", &json!({"scheme": "loop", "levels": 1, "omega": 0.5})).unwrap_err();
        assert_eq!(e.to_string(), "--omega/--variable-tension apply to --scheme deng-ma only");
        let e = Command::from_json("interpolat", &json!({})).unwrap_err();
        assert!(e.to_string().starts_with("unknown command 'interpolat'"), "{e}");
        let e = Command::from_json("interpolate", &json!({"method": "deng-ma", "omega": 2.0})).unwrap_err();
        assert!(e.to_string().starts_with("--omega/--variable-tension: "), "{e}");
        assert_eq!(
            Command::from_json("info", &serde_json::Value::Null).unwrap(),
            Command::Info(InfoOptions::default())
        );
    }

    #[test]
    fn every_method_and_scheme_parses_by_name() {
        for method in Method::ALL {
            let o = InterpolateOptions::from_json(&json!({"method": method.name(), "levels": 1})).unwrap();
            assert_eq!(o.method, method);
        }
        for scheme in Scheme::ALL {
            let c = Command::from_json("subdivide", &json!({"scheme": scheme.name(), "levels": 1})).unwrap();
            let Command::Subdivide(o) = c else { panic!() };
            assert_eq!(o.scheme, scheme);
        }
    }
}
