//! `subdiv interpolate MESH --method M [...]` (its report: [report JSON]).
//!
//! [report JSON]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-report-json

use crate::budget::{refused, MemoryArgs};
use crate::failure::{bad_input, Failure};
use crate::load::{load_tagged_mesh, TagArgs};
use crate::outputs::{self, Outputs};
use crate::progress;
use crate::subdivide::{BetaArg, SurfaceArgs, TensionArgs};
use anyhow::anyhow;
use std::path::{Path, PathBuf};
use std::time::Instant;
use subdiv_interp::params;
use subdiv_interp::{
    DengMaOptions, DengWangOptions, FairOptions, FanChengLaiOptions, InterpError, IterationObserver, Method,
    MethodOptions, Parameter, Report, Shape, Solver, SolverChoice, SurfaceOptions, ZhengCaiOptions,
};
use subdiv_mesh::Mesh;

/// `--method`: the library's method names ([`Method::from_str`]), each with
/// its [`Method::summary`] in the help.
fn method_parser() -> impl clap::builder::TypedValueParser<Value = Method> {
    use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
    PossibleValuesParser::new(Method::ALL.map(|m| PossibleValue::new(m.name()).help(m.summary())))
        .map(|name| name.parse::<Method>().expect("a possible value is a method name"))
}

/// `--scheme` of `--method fair`: the control mesh's scheme.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum FairSchemeArg {
    /// Catmull-Clark (any polygons).
    CatmullClark,
    /// Loop (triangles only; --beta chooses β).
    Loop,
    /// Doo-Sabin (any polygons; --refine 0 or 1).
    DooSabin,
}

/// Arguments of `subdiv interpolate`.
#[derive(clap::Args, Debug)]
pub struct InterpolateArgs {
    /// Input mesh: its vertices are the data to interpolate.
    mesh: PathBuf,
    /// Interpolation method.
    #[arg(long, value_parser = method_parser())]
    method: Method,
    /// Solver: auto, pia, weighted-pia, jacobi, gauss-seidel, gauss-seidel-symmetric,
    /// gauss-seidel-multicolor, chebyshev, cg, cg-jacobi, minres, gmres, ldl, dense.
    /// auto: CG on positive definite symmetric systems, MINRES on possibly
    /// indefinite ones (cheng with valence-2 vertices), GMRES on nonsymmetric ones.
    #[arg(long, default_value = "auto")]
    solver: String,
    /// Tolerance: max over vertices of |P − limit| / d (d = bounding-box diagonal).
    #[arg(long, default_value_t = subdiv_interp::DEFAULT_TOL)]
    tol: f64,
    /// Iteration cap of the iterative solvers.
    #[arg(long, default_value_t = subdiv_interp::DEFAULT_MAX_ITER)]
    max_iter: usize,
    /// fan-cheng-lai: one shape parameter λ ∈ (0, 1) for every face.
    #[arg(long, conflicts_with = "shape_file")]
    shape: Option<f64>,
    /// fan-cheng-lai: JSON {"default": λ, "faces": {"f": λ}, "groups": {"obj group": λ}}.
    #[arg(long)]
    shape_file: Option<PathBuf>,
    /// zheng-cai, deng-wang: per-vertex normals, lines "i nx ny nz" or JSON {"i": [x, y, z]}.
    #[arg(long)]
    normals: Option<PathBuf>,
    /// Vertices to interpolate (0-based indices, text or JSON array); default all.
    #[arg(long)]
    subset: Option<PathBuf>,
    /// zheng-cai: Brunet shape handles, lines "i S" or JSON {"i": S}.
    #[arg(long)]
    handles: Option<PathBuf>,
    /// zheng-cai: ITE_MAX, the Gauss-Seidel sweeps on the auxiliary mesh (paper: 5).
    #[arg(long, default_value_t = 5)]
    ite_max: usize,
    /// zheng-cai: EPS, stop sweeping when every update is below EPS·d (paper: 0.003).
    #[arg(long, default_value_t = 0.003)]
    eps: f64,
    /// deng-wang: the edge parameter μ of Eq. 9 (default ⅜: measured best, see the deng_wang module docs).
    #[arg(long, default_value_t = subdiv_interp::deng_wang::DEFAULT_MU)]
    mu: f64,
    /// deng-wang, fair --scheme loop: Loop's β.
    #[arg(long, value_enum, default_value = "warren")]
    beta: BetaArg,
    /// deng-ma: the tension.
    #[command(flatten)]
    tension: TensionArgs,
    /// fair: the control mesh is the input refined K times (default 1; 0: the scheme's exact method).
    #[arg(long, value_name = "K")]
    refine: Option<usize>,
    /// fair: trade interpolation for fairness, minimising |limit − data|² + W·energy (W > 0; the
    /// result approximates and --tol is not checked); default: exact interpolation.
    #[arg(long, value_name = "W")]
    fairness_weight: Option<f64>,
    /// fair: the control mesh's scheme (default catmull-clark).
    #[arg(long, value_enum)]
    scheme: Option<FairSchemeArg>,
    /// The surface's boundary, crease and face-varying options (as `subdivide`): the control
    /// mesh interpolates the data under these options and its tags.
    #[command(flatten)]
    surface_options: SurfaceArgs,
    /// Tags besides the file's own: a tag file, feature edges by angle.
    #[command(flatten)]
    tags: TagArgs,
    /// Write the control mesh (deng-ma: the refined surface).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Write the surface: the control mesh refined --levels times by its plain
    /// scheme, at limit positions, with vertex normals.
    #[arg(long)]
    surface: Option<PathBuf>,
    /// Levels for --surface (and deng-ma's -o).
    #[arg(long, default_value_t = 3)]
    levels: usize,
    /// Write the JSON report (keys: docs/ARCHITECTURE.md, "Contract: report JSON").
    #[arg(long)]
    report: Option<PathBuf>,
    /// Memory budget of --surface and deng-ma's -o.
    #[command(flatten)]
    memory: MemoryArgs,
}

fn solver_choice(name: &str) -> Result<SolverChoice, Failure> {
    if name == "auto" {
        return Ok(SolverChoice::Auto);
    }
    let s: Solver = name.parse().map_err(|_| bad_input(anyhow!("--solver: unknown solver '{name}'")))?;
    Ok(SolverChoice::Use(s))
}

fn check_applies(args: &InterpolateArgs) -> Result<(), Failure> {
    use Method::*;
    let misuse = |flag: &str, methods: &str| Err(bad_input(anyhow!("{flag} applies to --method {methods} only")));
    if (args.shape.is_some() || args.shape_file.is_some()) && args.method != FanChengLai {
        return misuse("--shape/--shape-file", "fan-cheng-lai");
    }
    if args.handles.is_some() && args.method != ZhengCai {
        return misuse("--handles", "zheng-cai");
    }
    if args.normals.is_some() && !matches!(args.method, ZhengCai | DengWang) {
        return misuse("--normals", "zheng-cai or deng-wang");
    }
    if args.tension.given() && args.method != DengMa {
        return misuse("--omega/--variable-tension", "deng-ma");
    }
    if (args.refine.is_some() || args.fairness_weight.is_some() || args.scheme.is_some()) && args.method != Fair {
        return misuse("--refine/--fairness-weight/--scheme", "fair");
    }
    if let Some(lambda) = args.shape {
        if !(lambda > 0.0 && lambda < 1.0) {
            return Err(bad_input(anyhow!("--shape: λ = {lambda} is outside (0, 1)")));
        }
    }
    if !(args.tol > 0.0 && args.tol.is_finite()) {
        return Err(bad_input(anyhow!("--tol must be positive, got {}", args.tol)));
    }
    Ok(())
}

/// The method's options from the flags and parameter files.
fn method_options(args: &InterpolateArgs, mesh: &Mesh, observer: IterationObserver) -> Result<MethodOptions, Failure> {
    let n = mesh.topology().vertex_count();
    let subset = args.subset.as_deref().map(|p| params::subset(p, n)).transpose().map_err(bad_input)?;
    let normals = args.normals.as_deref().map(|p| params::normals(p, n)).transpose().map_err(bad_input)?;
    let options: MethodOptions = match args.method {
        Method::ZhengCai => {
            let handles = args.handles.as_deref().map(|p| params::handles(p, n)).transpose().map_err(bad_input)?;
            ZhengCaiOptions::default()
                .with_ite_max(args.ite_max)
                .with_eps(args.eps)
                .with_normals(normals)
                .with_handles(handles)
                .into()
        }
        Method::FanChengLai => {
            let shape = match (&args.shape, &args.shape_file) {
                (_, Some(file)) => Shape::PerFace(params::shape_file(file, mesh).map_err(bad_input)?),
                (Some(l), None) => Shape::Uniform(*l),
                (None, None) => Shape::default(),
            };
            FanChengLaiOptions::default().with_shape(shape).into()
        }
        Method::DengWang => {
            DengWangOptions::default().with_mu(args.mu).with_beta(args.beta.into()).with_normals(normals).into()
        }
        Method::DengMa => DengMaOptions::default().with_tension(args.tension.tension()).into(),
        Method::Fair => {
            let scheme = match args.scheme.unwrap_or(FairSchemeArg::CatmullClark) {
                FairSchemeArg::CatmullClark => subdiv::Scheme::CatmullClark,
                FairSchemeArg::Loop => subdiv::Scheme::Loop(args.beta.into()),
                FairSchemeArg::DooSabin => subdiv::Scheme::DooSabin,
            };
            FairOptions::default()
                .with_scheme(scheme)
                .map_err(bad_input)?
                .with_refine(args.refine.unwrap_or(subdiv_interp::fair::DEFAULT_REFINE))
                .with_fairness_weight(args.fairness_weight)
                .into()
        }
        method => MethodOptions::new(method),
    };
    let surface = SurfaceOptions::default()
        .with_boundary(args.surface_options.boundary)
        .with_crease_method(args.surface_options.crease_method)
        .with_fvar(args.surface_options.fvar);
    let options = options
        .with_tol(args.tol)
        .with_max_iter(args.max_iter)
        .with_solver(solver_choice(&args.solver)?)
        .with_observer(observer)
        .with_surface(surface)
        .with_subset(subset)
        .map_err(|e| classify(args, e))?;
    Ok(options)
}

/// Exit 3 when the solver did not get there (with the error reached), 2 otherwise.
/// What an error is about: the parameter file or flag a parameter error
/// concerns, else the mesh file.
fn subject(args: &InterpolateArgs, e: &InterpError) -> String {
    let file =
        |p: &Option<PathBuf>, flag: &str| p.as_ref().map_or_else(|| flag.to_string(), |p| p.display().to_string());
    match e {
        InterpError::InvalidParameter { parameter, .. } => match parameter {
            Parameter::Normals => file(&args.normals, "--normals"),
            Parameter::Handles => file(&args.handles, "--handles"),
            Parameter::Subset => file(&args.subset, "--subset"),
            Parameter::Shape => file(&args.shape_file, "--shape"),
            Parameter::Tol => "--tol".into(),
            Parameter::Eps => "--eps".into(),
            Parameter::Mu => "--mu".into(),
            Parameter::Tension => "--omega/--variable-tension".into(),
            Parameter::Refine => "--refine".into(),
            Parameter::FairnessWeight => "--fairness-weight".into(),
            Parameter::Scheme => "--scheme".into(),
            _ => args.mesh.display().to_string(),
        },
        _ => args.mesh.display().to_string(),
    }
}

fn classify(args: &InterpolateArgs, e: InterpError) -> Failure {
    let error = anyhow!("{}: {e}", subject(args, &e));
    if e.is_not_converged() {
        Failure::NotConverged(error)
    } else {
        Failure::BadInput(error)
    }
}

/// The parameter files given: inputs that no output may overwrite.
fn parameter_files(args: &InterpolateArgs) -> impl Iterator<Item = &Path> {
    [&args.shape_file, &args.normals, &args.subset, &args.handles]
        .into_iter()
        .flatten()
        .map(PathBuf::as_path)
        .chain(args.tags.files())
}

/// Runs `subdiv interpolate`.
pub fn run(args: &InterpolateArgs) -> Result<(), Failure> {
    let total = Instant::now();
    check_applies(args)?;
    // Every output is checked before any work, and written at the end or not at all.
    let mut outputs = Outputs::new(std::iter::once(args.mesh.as_path()).chain(parameter_files(args)));
    let control_format = args.output.as_deref().map(|p| outputs.mesh("--output", p)).transpose()?;
    let surface_format = args.surface.as_deref().map(|p| outputs.mesh("--surface", p)).transpose()?;
    if let Some(path) = &args.report {
        outputs.other("--report", path)?;
    }
    let mesh = load_tagged_mesh(&args.mesh, &args.tags)?;
    let name = args.method.name();
    let (bar, observer) = progress::solver(format!("{name}: {} vertices", mesh.topology().vertex_count()), args.tol);
    let result = method_options(args, &mesh, observer)
        .and_then(|options| subdiv_interp::interpolate(&mesh, &options).map_err(|e| classify(args, e)));
    bar.finish_and_clear();
    let result = result?;
    let d = mesh.bbox_diagonal();

    // The refined meshes to write: sized before they are built.
    let is_deng_ma = args.method == Method::DengMa;
    let budget = args.memory.budget();
    let plain = result.scheme;
    let refined_outputs = [(is_deng_ma, "--output", control_format), (true, "--surface", surface_format)];
    for (refined, flag, format) in refined_outputs {
        if let (true, Some(format)) = (refined, format) {
            let what = format!("{flag} (--levels {})", args.levels);
            // Limit positions and normals.
            budget.check(&what, result.control.topology(), plain, args.levels, 2, Some(format)).map_err(refused)?;
        }
    }
    let refine_surface = |result: &subdiv_interp::Interpolant| {
        crate::subdivide::refine(&result.control, result.options(), args.levels, true)
            .map_err(|e| classify(args, e.into()))
    };
    let surface = args.surface.as_ref().map(|_| refine_surface(&result)).transpose()?;

    // The error, measured on the control positions exactly as they will be
    // written (f32 formats round them), by the plain scheme's rules (docs/ARCHITECTURE.md,
    // "Contract: how the error is measured"). The rounded positions are
    // swapped in and out of the result: no copy of the control mesh.
    let mut result = result;
    let mut written = match (&args.output, control_format, is_deng_ma) {
        (Some(path), Some(format), false) if !format.keeps_f64() => {
            Some(crate::outputs::as_written("--output", path, format, result.control.positions())?.into_owned())
        }
        _ => None,
    };
    let swap = |result: &mut subdiv_interp::Interpolant, written: &mut Option<Vec<glam::DVec3>>| {
        if let Some(w) = written {
            result.control.positions_mut().swap_with_slice(w);
        }
    };
    swap(&mut result, &mut written);
    // Positions written unchanged (a 64-bit format, or none written): the
    // method's own measurement on these very bits is the same computation.
    let measured =
        outputs::require_finite(name, &result.control, None).map(|()| match (&written, result.measured_error) {
            (None, Some(error)) => error,
            _ => result.error(mesh.positions(), &result.interpolated, d),
        });
    swap(&mut result, &mut written);
    drop(written);
    let error = measured?;
    // NaN fails too. A fair result with a fairness weight approximates: its
    // error is reported, not held to --tol.
    let approximates = args.method == Method::Fair && args.fairness_weight.is_some();
    if error.max_rel.is_nan() || (error.max_rel > args.tol && !approximates) {
        return Err(Failure::NotConverged(anyhow!(
            "{}: {name}: the measured error {:.3e}·d exceeds --tol {:.1e} (mean {:.3e}·d); nothing written",
            args.mesh.display(),
            error.max_rel,
            args.tol,
            error.mean_rel
        )));
    }
    // Deng-Ma's -o is its refined surface; every other method's the control mesh itself.
    let control_out: Option<std::borrow::Cow<Mesh>> = match (&args.output, is_deng_ma) {
        (None, _) => None,
        (Some(_), true) => Some(std::borrow::Cow::Owned(match &surface {
            Some(s) => s.clone(),
            None => refine_surface(&result)?,
        })),
        (Some(_), false) => Some(std::borrow::Cow::Borrowed(&result.control)),
    };

    let total_ms = total.elapsed().as_secs_f64() * 1e3;
    let control_mesh = control_out.as_deref().unwrap_or(&result.control);
    let report = Report::new(&mesh, &result, error)
        .with_input_file(args.mesh.display().to_string())
        .with_control(control_mesh)
        .with_total_ms(total_ms);
    if let (Some(path), Some(control)) = (&args.output, &control_out) {
        outputs.stage_mesh("--output", path, control, is_deng_ma)?;
    }
    if let (Some(path), Some(s)) = (&args.surface, &surface) {
        outputs.stage_mesh("--surface", path, s, true)?;
    }
    if let Some(path) = &args.report {
        let text = serde_json::to_string_pretty(&report).map_err(|e| Failure::Other(e.into()))?;
        outputs.stage_bytes(path, (text + "\n").as_bytes())?;
    }
    outputs.commit()?;
    for w in &result.warnings {
        progress::warn(w);
    }
    progress::summary(format!(
        "{name}: {} vertices interpolated, max error {:.3e}·d (mean {:.3e}·d), {} iterations, {:.1} ms",
        error.count, error.max_rel, error.mean_rel, report.solver.iterations, total_ms
    ));
    Ok(())
}
