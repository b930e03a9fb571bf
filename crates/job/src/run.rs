//! The one pipeline of `interpolate`, `subdivide` and `info` on one file: what `subdiv
//! interpolate|subdivide|info`, every job of `subdiv batch` and the Python package's file
//! functions run.
//!
//! [`interpolate`]: outputs checked before any work (not an input, not twice, a writable
//! directory, a regular file or none) → input read and validated with its tags (tag file,
//! feature angle) → parameter files read → the method ([`subdiv_interp::interpolate`]) →
//! every refinement sized against the memory budget before it is built → the error measured
//! on the control positions exactly as the output format stores them, by the plain scheme's
//! rules ([how the error is measured]) → refused above `tol` or when not finite → every output
//! staged, then committed together (all or none) → the typed [`Report`].
//!
//! [how the error is measured]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-how-the-error-is-measured

use crate::budget::{BudgetError, MemoryBudget};
use crate::error::{ErrorKind, JobError};
use crate::info::{summarize_soup, Summary};
use crate::load::read_soup;
use crate::options::{InfoOptions, InterpolateOptions, Parameter, ShapeValue, SubdivideOptions};
use crate::outputs::{self, Outputs, UsdOutput};
use crate::progress::{Phase, Progress};
use crate::scene::{check_output, load_scene};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;
use subdiv_interp::report::MeshSummary;
use subdiv_interp::{
    params, ChengOptions, DengMaOptions, DengWangOptions, ErrorStats, FairOptions, FanChengLaiOptions, InterpError,
    Interpolant, Method, MethodOptions, ParamFileError, Report, Shape, ZhengCaiOptions,
};
use subdiv_io::usd::SubdivisionScheme;
use subdiv_mesh::{DVec3, Mesh};
use subdiv_stencil::{Options, Scheme, StencilError};

/// Where `interpolate` writes (each optional).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct InterpolateOutputs {
    /// The control mesh (Deng-Ma: its surface refined `levels` times), `-o`.
    pub control: Option<PathBuf>,
    /// The limit surface refined `levels` times with vertex normals, `--surface`.
    pub surface: Option<PathBuf>,
    /// The JSON report, `--report`.
    pub report: Option<PathBuf>,
}

impl InterpolateOutputs {
    /// With the control mesh written to `path` (`None`: not written).
    pub fn with_control(self, path: Option<PathBuf>) -> Self {
        Self { control: path, ..self }
    }

    /// With the surface written to `path`.
    pub fn with_surface(self, path: Option<PathBuf>) -> Self {
        Self { surface: path, ..self }
    }

    /// With the report written to `path`.
    pub fn with_report(self, path: Option<PathBuf>) -> Self {
        Self { report: path, ..self }
    }
}

/// What [`interpolate`] did.
#[derive(Debug)]
#[non_exhaustive]
pub struct Interpolated {
    /// The files written.
    pub outputs: Vec<PathBuf>,
    /// The report (what `--report` holds for an input of one mesh); of the first mesh of a
    /// scene ([`Interpolated::prims`] has every mesh's).
    pub report: Report,
    /// The error measured on the control mesh as written; the largest over a scene's meshes.
    pub error: ErrorStats,
    /// Every mesh of a USD input, by prim path, with its report (empty for other formats).
    pub prims: Vec<PrimReport>,
}

/// The result of one Mesh prim of a USD input.
#[derive(Clone, Debug, Serialize)]
#[non_exhaustive]
pub struct PrimReport {
    /// Its prim path.
    pub prim: String,
    /// Its report.
    pub report: Report,
}

/// One mesh's interpolation, before its outputs are written.
struct OneDone {
    control_out: Option<Mesh>,
    surface: Option<Mesh>,
    scheme: Scheme,
    report: Report,
    error: ErrorStats,
    warnings: Vec<String>,
}

/// The scheme a renderer shows a control mesh of `scheme` with: Catmull-Clark and Loop are
/// USD's (and OpenSubdiv's); any other is written as polygons, with a warning.
fn usd_scheme(scheme: Scheme, flag: &str, path: &Path, progress: &mut dyn Progress) -> SubdivisionScheme {
    match scheme {
        Scheme::CatmullClark => SubdivisionScheme::CatmullClark,
        Scheme::Loop(_) => SubdivisionScheme::Loop,
        other => {
            progress.warn(&format!(
                "{flag} {}: USD has no {} scheme: the control mesh is written with subdivisionScheme \"none\", so \
                 a renderer shows its polygons",
                path.display(),
                other.name()
            ));
            SubdivisionScheme::None
        }
    }
}

/// The warnings a job met, passed on to `progress` once the outputs are committed.
fn warn_all(progress: &mut dyn Progress, warnings: &[String]) {
    for w in warnings {
        progress.warn(w);
    }
}

/// A refusal of the size guard as bad input, naming the option that raises the budget.
fn refused(e: BudgetError) -> JobError {
    let hint = if matches!(e, BudgetError::OverBudget { .. }) { " or set --max-memory" } else { "" };
    JobError::bad_input(format!("{e}{hint}"))
}

/// Exit 3 when the solver did not get there (with the error reached), 2 otherwise; the message
/// names the option or parameter file a parameter error is about, else the input.
fn classify(input: &Path, o: &InterpolateOptions, e: InterpError) -> JobError {
    use subdiv_interp::Parameter as P;
    let file = |p: &Option<Parameter>, flag: &str| match p {
        Some(Parameter::File(path)) => path.display().to_string(),
        _ => flag.to_string(),
    };
    let subject = match &e {
        InterpError::InvalidParameter { parameter, .. } => match parameter {
            P::Normals => file(&o.normals, "--normals"),
            P::Handles => file(&o.handles, "--handles"),
            P::Subset => file(&o.subset, "--subset"),
            P::Shape if o.shape_file.is_some() => file(&o.shape_file, "--shape-file"),
            P::Shape => "--shape".into(),
            P::Tol => "--tol".into(),
            P::Eps => "--eps".into(),
            P::Mu => "--mu".into(),
            P::Tension => "--omega/--variable-tension".into(),
            P::Refine => "--refine".into(),
            P::FairnessWeight => "--fairness-weight".into(),
            P::Scheme => "--scheme".into(),
            _ => input.display().to_string(),
        },
        _ => input.display().to_string(),
    };
    let kind = if e.is_not_converged() { ErrorKind::NotConverged } else { ErrorKind::BadInput };
    let mut error = JobError::new(kind, format!("{subject}: {e}"));
    let solver_state = |s: &subdiv_solve::SolveError| match s {
        subdiv_solve::SolveError::NotConverged { iterations, residual, .. }
        | subdiv_solve::SolveError::Diverged { iterations, residual, .. } => (Some(*iterations), Some(*residual)),
        _ => (None, None),
    };
    (error.iterations, error.residual) = match &e {
        InterpError::Solve { source, .. } | InterpError::Unsolvable { source, .. } => solver_state(source),
        InterpError::ToleranceNotMet { max_rel, .. } => (None, Some(*max_rel)),
        _ => (None, None),
    };
    error
}

/// A parameter given as a file (read through [`subdiv_io::read_text`]: special files refused,
/// size capped, UTF-8) or inline (its JSON text), parsed by `parse`; errors name the file, or
/// the option for inline values.
fn parameter<T>(
    value: &Option<Parameter>,
    flag: &str,
    parse: impl FnOnce(&str) -> Result<T, ParamFileError>,
) -> Result<Option<T>, JobError> {
    match value {
        None => Ok(None),
        Some(Parameter::File(path)) => {
            let text = subdiv_io::read_text(path).map_err(|e| JobError::from_error(ErrorKind::BadInput, &e))?;
            parse(&text).map(Some).map_err(|e| JobError::bad_input(e.with_path(path).to_string()))
        }
        Some(Parameter::Inline(json)) => {
            parse(&json.to_string()).map(Some).map_err(|e| JobError::bad_input(format!("{flag}: {}", e.message())))
        }
    }
}

/// The method's options from the job's options, with the parameter files read: the defaults
/// are the method's own (an option left `None` is not set), the checks are
/// [`InterpolateOptions::validate`]'s and then the method's.
///
/// # Errors
/// Bad input for invalid options or parameter files.
pub fn method_options(
    input: &Path,
    o: &InterpolateOptions,
    mesh: &Mesh,
    observer: subdiv_solve::IterationObserver,
) -> Result<MethodOptions, JobError> {
    o.validate()?;
    // Parameter files number the input's vertices (a non-manifold input's, not its cover's).
    let n = mesh.welds().map_or(mesh.topology().vertex_count(), |welds| welds.vertex_count());
    let subset = parameter(&o.subset, "--subset", |t| params::parse_subset(t, n))?;
    // On a cover, every copy of a vertex of the subset is interpolated with it.
    let subset = match (subset, mesh.welds()) {
        (Some(subset), Some(welds)) => {
            let mut chosen = vec![false; welds.vertex_count()];
            subset.iter().for_each(|&v| chosen[v as usize] = true);
            let classes = welds.vertex_classes().iter().enumerate();
            Some(classes.filter(|&(_, &class)| chosen[class as usize]).map(|(v, _)| v as u32).collect())
        }
        (subset, _) => subset,
    };
    let normals = parameter(&o.normals, "--normals", |t| params::parse_normals(t, n))?;
    let options: MethodOptions = match o.method {
        Method::ZhengCai => {
            let handles = parameter(&o.handles, "--handles", |t| params::parse_handles(t, n))?;
            let mut options = ZhengCaiOptions::default().with_normals(normals).with_handles(handles);
            if let Some(ite_max) = o.ite_max {
                options = options.with_ite_max(ite_max);
            }
            if let Some(eps) = o.eps {
                options = options.with_eps(eps);
            }
            options.into()
        }
        Method::FanChengLai => {
            let per_face = parameter(&o.shape_file, "--shape-file", |t| params::parse_shape_file(t, mesh))?;
            let shape = match (&o.shape, per_face) {
                (_, Some(lambdas)) => Shape::PerFace(lambdas),
                (Some(ShapeValue::Uniform(lambda)), None) => Shape::Uniform(*lambda),
                (Some(ShapeValue::PerFace(lambdas)), None) => Shape::PerFace(lambdas.clone()),
                (None, None) => Shape::default(),
            };
            FanChengLaiOptions::default().with_shape(shape).into()
        }
        Method::DengWang => {
            let mut options = DengWangOptions::default().with_normals(normals);
            if let Some(mu) = o.mu {
                options = options.with_mu(mu);
            }
            if let Some(beta) = o.beta {
                options = options.with_beta(beta);
            }
            options.into()
        }
        Method::DengMa => DengMaOptions::default().with_tension(o.tension().unwrap_or_default()).into(),
        Method::Cheng => {
            let scheme = control_scheme(o)?;
            ChengOptions::default().with_scheme(scheme).map_err(|e| classify(input, o, e))?.into()
        }
        Method::Fair => {
            let scheme = control_scheme(o)?;
            let options = FairOptions::default().with_scheme(scheme).map_err(|e| classify(input, o, e))?;
            let mut options = options.with_fairness_weight(o.fairness_weight);
            if let Some(refine) = o.refine {
                options = options.with_refine(refine);
            }
            options.into()
        }
        method => MethodOptions::new(method),
    };
    let surface = o.surface.surface_options(mesh.tags().options());
    options
        .with_tol(o.tol)
        .with_max_iter(o.max_iter)
        .with_solver(o.solver)
        .with_observer(observer)
        .with_surface(surface)
        .with_subset(subset)
        .map_err(|e| classify(input, o, e))
}

/// The control scheme of `cheng` and `fair`: `--scheme` (default Catmull-Clark) with Loop's β,
/// an option of its own (the scheme names the rules).
fn control_scheme(o: &InterpolateOptions) -> Result<Scheme, JobError> {
    o.scheme
        .unwrap_or(Scheme::CatmullClark)
        .with_parameters(o.beta, None)
        .map_err(|e| JobError::bad_input(e.to_string()))
}

/// The method on a mesh in memory: [`method_options`], then [`subdiv_interp::interpolate`];
/// messages name `input` (the mesh's file, or what stands for it) as the command line does.
///
/// # Errors
/// Bad input for invalid options, parameter files or a mesh the method refuses; not converged
/// when the solver stopped early or the tolerance was not met.
pub fn interpolate_mesh(
    input: &Path,
    mesh: &Mesh,
    o: &InterpolateOptions,
    observer: subdiv_solve::IterationObserver,
) -> Result<Interpolant, JobError> {
    let options = method_options(input, o, mesh, observer)?;
    // The method's matrices and solver, sized before they are built (subdiv-interp's measured peak
    // per vertex of the mesh it solves on).
    let (vertices, bytes_each) = options.estimated_memory(mesh);
    let what = format!("--method {}", o.method.name());
    MemoryBudget::given_or_available(o.max_memory, "--max-memory")
        .check_items(&what, vertices, "vertices to solve on", bytes_each, "use a smaller mesh, or set --max-memory")
        .map_err(refused)?;
    let result = subdiv_interp::interpolate(mesh, &options).map_err(|e| classify(input, o, e))?;
    Ok(with_written_options(result))
}

/// `result` with the options its surface needs in its control mesh's tags ([`written_options`]),
/// so that every writer (the command, the batch, the Python package) writes them.
fn with_written_options(mut result: Interpolant) -> Interpolant {
    if let Some(options) = written_options(&result.control, result.options()) {
        let tags = result.control.tags().clone().with_options(options);
        result.control = result.control.with_tags(tags);
    }
    result
}

/// The parameter files of `o`: inputs that no output may overwrite.
fn parameter_files(o: &InterpolateOptions) -> impl Iterator<Item = &Path> {
    [&o.shape_file, &o.normals, &o.subset, &o.handles]
        .into_iter()
        .filter_map(|p| match p {
            Some(Parameter::File(path)) => Some(path.as_path()),
            _ => None,
        })
        .chain(o.tags.tags.as_deref())
}

/// `levels` steps with `options` ([`subdiv_stencil::subdivide_for_output`]: each level's mesh
/// carries its decayed tags to the next, then limit positions), each level reported; texture
/// coordinates the scheme cannot refine (Doo-Sabin with seams or tags) are dropped with a
/// warning.
pub fn refine(
    mesh: &Mesh,
    options: Options,
    levels: usize,
    limit: bool,
    progress: &mut dyn Progress,
) -> Result<(Mesh, Option<String>), StencilError> {
    progress.begin(Phase::Refine, &format!("{} subdivision", options.scheme.name()), levels as u64);
    let mut done = 0;
    let refined = subdiv_stencil::subdivide_for_output(mesh, options, levels, limit, |_| {
        done += 1;
        progress.advance(done);
    });
    progress.end();
    let refined = refined?;
    let dropped = refined.uvs_dropped.map(|reason| format!("texture coordinates not written: {reason}"));
    Ok((refined.mesh, dropped))
}

/// `subdiv interpolate INPUT --method … [-o CONTROL] [--surface SURFACE --levels L] [--report
/// R]` (the module docs give the steps).
///
/// # Errors
/// A [`JobError`] whose kind is the exit code (nothing written on any error).
pub fn interpolate(
    input: &Path,
    o: &InterpolateOptions,
    paths: &InterpolateOutputs,
    progress: &mut dyn Progress,
) -> Result<Interpolated, JobError> {
    let total = Instant::now();
    o.validate()?;
    // Every output is checked before any work, and written at the end or not at all.
    let mut outputs = Outputs::new(std::iter::once(input).chain(parameter_files(o)));
    let control_format = paths.control.as_deref().map(|p| outputs.mesh("--output", p)).transpose()?;
    let surface_format = paths.surface.as_deref().map(|p| outputs.mesh("--surface", p)).transpose()?;
    if let Some(path) = &paths.report {
        outputs.other("--report", path)?;
    }
    let scene = load_scene(input, &o.tags, progress)?;
    for (flag, path, format) in
        [("--output", &paths.control, control_format), ("--surface", &paths.surface, surface_format)]
    {
        if let (Some(path), Some(format)) = (path, format) {
            check_output(&scene, input, flag, path, format)?;
        }
    }
    let mut done = Vec::with_capacity(scene.meshes.len());
    for entry in &scene.meshes {
        let label = entry.label(input);
        let one = interpolate_one(Path::new(&label), &entry.mesh, o, paths, control_format, surface_format, progress)?;
        done.push(one);
    }
    let is_deng_ma = o.method == Method::DengMa;
    let total_ms = total.elapsed().as_secs_f64() * 1e3;
    for one in &mut done {
        one.report = one.report.clone().with_total_ms(total_ms);
    }
    let to_usd = |format: Option<subdiv_io::Format>| format.is_some_and(subdiv_io::Format::is_usd);
    let prim_of = |i: usize| scene.meshes[i].prim.clone().unwrap_or_else(|| subdiv_io::usd::DEFAULT_PRIM_PATH.into());
    for (flag, path, format, is_surface) in
        [("--output", &paths.control, control_format, is_deng_ma), ("--surface", &paths.surface, surface_format, true)]
    {
        let Some(path) = path else { continue };
        let control = flag == "--output";
        fn mesh_of(one: &OneDone, control: bool) -> Option<&Mesh> {
            if control {
                one.control_out.as_ref()
            } else {
                one.surface.as_ref()
            }
        }
        if to_usd(format) {
            let prims: Vec<String> = (0..done.len()).map(prim_of).collect();
            let mut meshes = Vec::with_capacity(done.len());
            for (one, prim) in done.iter().zip(&prims) {
                let Some(mesh) = mesh_of(one, control) else { continue };
                let scheme =
                    if is_surface { SubdivisionScheme::None } else { usd_scheme(one.scheme, flag, path, progress) };
                meshes.push(UsdOutput { prim, mesh, scheme });
            }
            outputs.stage_usd(flag, path, &meshes, scene.usd.as_ref(), is_surface, is_surface, progress)?;
        } else if let Some(mesh) = done.first().and_then(|one| mesh_of(one, control)) {
            outputs.stage_mesh(flag, path, mesh, is_surface, is_surface, progress)?;
        }
    }
    let prims: Vec<PrimReport> = if scene.usd.is_some() {
        done.iter().enumerate().map(|(i, one)| PrimReport { prim: prim_of(i), report: one.report.clone() }).collect()
    } else {
        Vec::new()
    };
    if let Some(path) = &paths.report {
        let text = if prims.len() > 1 {
            serde_json::to_string_pretty(&prims)
        } else {
            serde_json::to_string_pretty(&done[0].report)
        }
        .map_err(|e| JobError::new(ErrorKind::Panic, format!("report: {e}")))?;
        outputs.stage_bytes(path, (text + "\n").as_bytes())?;
    }
    let written = outputs.commit()?;
    for one in &done {
        warn_all(progress, &one.warnings);
    }
    let error = done
        .iter()
        .map(|one| one.error)
        .max_by(|a, b| a.max_rel.total_cmp(&b.max_rel))
        .ok_or_else(|| JobError::bad_input(format!("{}: no mesh", input.display())))?;
    let report = done.swap_remove(0).report;
    Ok(Interpolated { outputs: written, report, error, prims })
}

/// [`interpolate`] on one mesh of the input (`input` names it in messages): the method, the
/// refinements sized and built, the error measured as the control output's format stores it.
fn interpolate_one(
    input: &Path,
    mesh: &Mesh,
    o: &InterpolateOptions,
    paths: &InterpolateOutputs,
    control_format: Option<subdiv_io::Format>,
    surface_format: Option<subdiv_io::Format>,
    progress: &mut dyn Progress,
) -> Result<OneDone, JobError> {
    let name = o.method.name();
    let label = format!("{name}: {} vertices", mesh.topology().vertex_count());
    let observer = progress.solver(&label, o.tol);
    let result = interpolate_mesh(input, mesh, o, observer);
    progress.solver_end();
    let mut result = result?;
    let mut warnings = Vec::new();
    let d = mesh.bbox_diagonal();

    // The refined meshes to write: sized before they are built.
    let is_deng_ma = o.method == Method::DengMa;
    let budget = MemoryBudget::given_or_available(o.max_memory, "--max-memory");
    let plain = result.options().scheme;
    for (refined, flag, format) in [(is_deng_ma, "--output", control_format), (true, "--surface", surface_format)] {
        if let (true, Some(format)) = (refined, format) {
            let what = format!("{flag} (--levels {})", o.levels);
            // Limit positions and normals.
            budget.check(&what, result.control.topology(), plain, o.levels, 2, Some(format)).map_err(refused)?;
        }
    }
    let mut refine_surface = |result: &Interpolant, progress: &mut dyn Progress| {
        let (surface, dropped) = refine(&result.control, result.options(), o.levels, true, progress)
            .map_err(|e| classify(input, o, e.into()))?;
        warnings.extend(dropped);
        Ok::<_, JobError>(surface)
    };
    let surface = paths.surface.as_ref().map(|_| refine_surface(&result, progress)).transpose()?;

    // The error, measured on the control positions exactly as they will be written (f32
    // formats round them), by the plain scheme's rules. The rounded positions are swapped in
    // and out of the result: no copy of the control mesh.
    let mut written = match (&paths.control, control_format, is_deng_ma) {
        (Some(path), Some(format), false) if !format.keeps_f64() => {
            Some(outputs::as_written("--output", path, format, result.control.positions())?.into_owned())
        }
        _ => None,
    };
    let swap = |result: &mut Interpolant, written: &mut Option<Vec<DVec3>>| {
        if let Some(w) = written {
            result.control.positions_mut().swap_with_slice(w);
        }
    };
    swap(&mut result, &mut written);
    // Positions written unchanged (a 64-bit format, or none written): the method's own
    // measurement on these very bits is the same computation.
    // The method measures on its normalised positions: mapped back into the subnormal range
    // (|x| < 2.2e-308) they keep fewer digits, so those are measured as written, exactly.
    let subnormal = has_subnormal(result.control.positions());
    let measured =
        outputs::require_finite(name, &result.control, None).map(|()| match (&written, result.measured_error) {
            (None, Some(error)) if !subnormal => error,
            _ if subnormal => error_scaled_up(&mut result, mesh.positions(), d),
            _ => result.error(mesh.positions(), &result.interpolated, d),
        });
    swap(&mut result, &mut written);
    drop(written);
    let error = measured?;
    // NaN fails too. A fair result with a fairness weight approximates: its error is reported,
    // not held to `tol`.
    let approximates = o.method == Method::Fair && o.fairness_weight.is_some();
    if error.max_rel.is_nan() || (error.max_rel > o.tol && !approximates) {
        let why = if subnormal {
            " (the control mesh has subnormal coordinates, below 2.2e-308, which hold too few digits: \
             scale the mesh up)"
        } else {
            ""
        };
        return Err(JobError::not_converged(format!(
            "{}: {name}: the measured error {:.3e}·d exceeds --tol {:.1e} (mean {:.3e}·d){why}; nothing written",
            input.display(),
            error.max_rel,
            o.tol,
            error.mean_rel
        )));
    }
    // Deng-Ma's -o is its refined surface; every other method's the control mesh itself.
    let control_out: Option<Mesh> = match (&paths.control, is_deng_ma) {
        (None, _) => None,
        (Some(_), true) => Some(match &surface {
            Some(s) => s.clone(),
            None => refine_surface(&result, progress)?,
        }),
        (Some(_), false) => Some(result.control.clone()),
    };

    // The report's control mesh is what stands for it: Deng-Ma's is its refined surface
    // (written as -o, or as the surface alone).
    let control_mesh = match (&control_out, is_deng_ma, &surface) {
        (Some(control), _, _) => control,
        (None, true, Some(surface)) => surface,
        (None, _, _) => &result.control,
    };
    let report =
        Report::new(mesh, &result, error).with_input_file(input.display().to_string()).with_control(control_mesh);
    warnings.extend(result.warnings.iter().cloned());
    Ok(OneDone { control_out, surface, scheme: plain, report, error, warnings })
}

/// [`Interpolant::error`] of the control mesh as written, when it has subnormal coordinates:
/// computed in f64, its limit points would round onto the subnormal grid (spacing 4.9e-324)
/// and a control mesh that misses the data by a fraction of that grid would measure 0. The
/// control mesh and the data are scaled up by the power of two that brings their largest
/// coordinate into [½, 1) — exact for every coordinate — and measured there; the relative
/// errors are those of the written mesh, the absolute ones are mapped back. When a large
/// coordinate keeps the scale from going up, the subnormal ones are below d·2⁻¹⁰⁰⁰ and
/// their rounding does not show in the relative error: measured as usual.
fn error_scaled_up(result: &mut Interpolant, data: &[DVec3], d: f64) -> subdiv_interp::ErrorStats {
    let scale = subdiv_mesh::PowerOfTwoScale::normalizing(result.control.positions().iter().chain(data).copied());
    if scale.exponent <= 0 {
        return result.error(data, &result.interpolated, d);
    }
    let mut scaled = scale.scaled_points(result.control.positions());
    result.control.positions_mut().swap_with_slice(&mut scaled);
    let data_scaled = scale.scaled_points(data);
    let d_scaled = subdiv_mesh::Aabb::of(data_scaled.iter().copied()).map_or(scale.apply(d), |b| b.diagonal());
    let mut error = result.error(&data_scaled, &result.interpolated, d_scaled);
    result.control.positions_mut().swap_with_slice(&mut scaled);
    let back = scale.inverse();
    error.max_abs = back.apply(error.max_abs);
    error.mean_abs = back.apply(error.mean_abs);
    error
}

/// Whether a coordinate is subnormal (non-zero, below `f64::MIN_POSITIVE` in magnitude).
fn has_subnormal(positions: &[DVec3]) -> bool {
    positions.iter().flat_map(|p| p.to_array()).any(|x| x != 0.0 && x.abs() < f64::MIN_POSITIVE)
}

/// The options a control mesh of Catmull-Clark or Loop carries into its file, so that an
/// OpenSubdiv-based tool reading its option tags (`t interpolateboundary` …) makes the same
/// surface of it: the boundary option on an open mesh, the crease method with semi-sharp tags,
/// the face-varying mode with texture coordinates, the triangle rule for Catmull-Clark with
/// triangles. `None` when none applies and the mesh carries none.
fn written_options(control: &Mesh, options: Options) -> Option<subdiv_mesh::FileOptions> {
    let t = control.topology();
    let tags = control.tags();
    if !matches!(options.scheme, Scheme::CatmullClark | Scheme::Loop(_)) {
        return None;
    }
    let semi_sharp = |s: &f32| *s > 0.0 && *s < subdiv_mesh::SHARPNESS_INFINITE;
    let written = subdiv_mesh::FileOptions {
        boundary: (!t.is_closed()).then_some(options.boundary),
        crease_method: (tags.edge_values().iter().chain(tags.vertex_values()).any(semi_sharp))
            .then_some(options.crease_method),
        fvar: control.uvs().map(|_| options.fvar),
        triangle_rule: (options.scheme == Scheme::CatmullClark && t.faces().iter().any(|f| f.len() == 3))
            .then_some(options.triangle_rule),
    };
    (written != tags.options()).then_some(written)
}

/// The report of [`subdivide`]: scheme, levels, limit, input and output counts.
#[derive(Clone, Debug, Serialize)]
#[non_exhaustive]
pub struct SubdivideReport {
    /// [`subdiv_stencil::Scheme::name`].
    pub scheme: &'static str,
    /// Loop's β (`loop`, `warren`); absent for the other schemes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub beta: Option<String>,
    /// Subdivision steps.
    pub levels: usize,
    /// Limit positions.
    pub limit: bool,
    /// The input, with its file.
    pub input: MeshSummary,
    /// The mesh written.
    pub output: MeshSummary,
}

/// What [`subdivide`] did.
#[derive(Debug)]
#[non_exhaustive]
pub struct Subdivided {
    /// The files written.
    pub outputs: Vec<PathBuf>,
    /// The counts.
    pub report: SubdivideReport,
}

/// `subdiv subdivide INPUT --scheme S --levels N … -o OUTPUT`.
///
/// # Errors
/// A [`JobError`] whose kind is the exit code (nothing written on any error).
pub fn subdivide(
    input: &Path,
    o: &SubdivideOptions,
    output: &Path,
    progress: &mut dyn Progress,
) -> Result<Subdivided, JobError> {
    o.validate()?;
    let mut outputs = Outputs::new(std::iter::once(input).chain(o.tags.tags.as_deref()));
    let format = outputs.mesh("--output", output)?;
    let scene = load_scene(input, &o.tags, progress)?;
    check_output(&scene, input, "--output", output, format)?;
    let mut done = Vec::with_capacity(scene.meshes.len());
    let mut warnings = Vec::new();
    for entry in scene.meshes {
        let label = entry.label(input);
        let (mesh, refined, dropped) = subdivide_mesh(Path::new(&label), entry.mesh, o, Some(format), progress)?;
        warnings.extend(dropped);
        let prim = entry.prim.unwrap_or_else(|| subdiv_io::usd::DEFAULT_PRIM_PATH.into());
        done.push((prim, mesh, refined));
    }
    if format.is_usd() {
        // A refined surface: plain polygons for a renderer.
        let meshes: Vec<UsdOutput<'_>> = done
            .iter()
            .map(|(prim, _, refined)| UsdOutput { prim, mesh: refined, scheme: SubdivisionScheme::None })
            .collect();
        outputs.stage_usd("--output", output, &meshes, scene.usd.as_ref(), o.normals, true, progress)?;
    } else {
        outputs.stage_mesh("--output", output, &done[0].2, o.normals, true, progress)?;
    }
    let written = outputs.commit()?;
    warn_all(progress, warnings.as_slice());
    let (_, mesh, refined) = &done[0];
    let mut input_summary = MeshSummary::of(mesh);
    input_summary.file = Some(input.display().to_string());
    let scheme = o.options(mesh.tags().options()).scheme;
    let report = SubdivideReport {
        scheme: scheme.name(),
        beta: scheme.parameters().0.map(|beta| beta.to_string()),
        levels: o.levels,
        limit: o.limit,
        input: input_summary,
        output: MeshSummary::of(refined),
    };
    Ok(Subdivided { outputs: written, report })
}

/// `o` on a mesh in memory: triangulated first if asked, sized against the memory budget (with
/// what writing it as `format` holds), refined; returns the mesh refined (the triangulated one
/// when triangulated), the result and the warning of texture coordinates left out. Messages
/// name `input`.
///
/// # Errors
/// Bad input for a mesh the scheme refuses, or a result over the budget.
pub fn subdivide_mesh(
    input: &Path,
    mut mesh: Mesh,
    o: &SubdivideOptions,
    format: Option<subdiv_io::Format>,
    progress: &mut dyn Progress,
) -> Result<(Mesh, Mesh, Option<String>), JobError> {
    o.validate()?;
    let shown = input.display();
    if o.triangulate {
        mesh = subdiv_mesh::triangulate(&mesh)
            .map_err(|e| JobError::bad_input(format!("{shown}: --triangulate: {e}")))?
            .mesh;
    }
    let options = o.options(mesh.tags().options());
    // Normals and limit positions: one more array per vertex each.
    let vertex_arrays = u64::from(o.normals) + u64::from(o.limit);
    MemoryBudget::given_or_available(o.max_memory, "--max-memory")
        .check("subdivide", mesh.topology(), options.scheme, o.levels, vertex_arrays, format)
        .map_err(refused)?;
    let (refined, dropped) = refine(&mesh, options, o.levels, o.limit, progress).map_err(|e| {
        let hint = match e {
            StencilError::NotTriangles { .. } => " (or pass --triangulate)",
            StencilError::TagsNotSupported { .. } => {
                " (catmull-clark and loop take every crease and corner tag, doo-sabin infinitely sharp ones)"
            }
            _ => "",
        };
        JobError::bad_input(format!("{shown}: {e}{hint}"))
    })?;
    Ok((mesh, refined, dropped))
}

/// `subdiv info INPUT`: the summary, and the error of an invalid mesh (or, with `strict`, of
/// its warnings) beside it — an invalid mesh is described and fails.
pub fn info(
    input: &Path,
    o: &InfoOptions,
    progress: &mut dyn Progress,
) -> Result<(Summary, Option<JobError>), JobError> {
    let soup = read_soup(input, progress)?;
    let file = input.display().to_string();
    let summary = summarize_soup(soup, Some(&file));
    let error = match &summary.error {
        Some(error) => Some(JobError::bad_input(format!("{file}: {error}"))),
        None if o.strict && !summary.warnings.is_empty() => {
            Some(JobError::bad_input(format!("{file}: {} (--strict)", summary.warnings.join("; "))))
        }
        None => None,
    };
    Ok((summary, error))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;
    use subdiv_stencil::LoopBeta;

    /// `--scheme` (with Loop's `--beta`) reaches the options of cheng and fair; absent, both
    /// keep Catmull-Clark, and cheng's options are its defaults.
    #[test]
    fn the_control_scheme_is_passed_on() {
        let mesh = subdiv_mesh::shapes::icosahedron();
        let input = Path::new("icosahedron.obj");
        let options = |json: serde_json::Value| {
            let o = InterpolateOptions::from_json(&json).unwrap();
            method_options(input, &o, &mesh, Default::default()).unwrap()
        };
        let cheng = |json| match options(json) {
            MethodOptions::Cheng(o) => o,
            other => panic!("{other:?}"),
        };
        assert_eq!(cheng(json!({"method": "cheng"})), ChengOptions::default());
        assert_eq!(cheng(json!({"method": "cheng", "scheme": "sqrt3"})).scheme, Scheme::Sqrt3);
        let loop_scheme = cheng(json!({"method": "cheng", "scheme": "loop", "beta": "warren"})).scheme;
        assert_eq!(loop_scheme, Scheme::Loop(LoopBeta::Warren));
        let MethodOptions::Fair(fair) = options(json!({"method": "fair", "scheme": "loop"})) else { panic!() };
        assert_eq!(fair.scheme, Scheme::Loop(LoopBeta::Loop));
        // A scheme cheng does not take: a bad-input error naming --scheme and the method that takes it.
        let o = InterpolateOptions::from_json(&json!({"method": "cheng", "scheme": "doo-sabin"})).unwrap();
        let e = method_options(input, &o, &mesh, Default::default()).unwrap_err();
        assert_eq!(e.kind, ErrorKind::BadInput);
        assert!(e.to_string().starts_with("--scheme: ") && e.to_string().contains("--method nasri"), "{e}");
    }
}
