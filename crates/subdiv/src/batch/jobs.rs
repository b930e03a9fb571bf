//! One command on one mesh: the pipelines of `subdiv info`, `interpolate`
//! and `subdivide`, with the command line's checks and messages, writing
//! every output or none.

use super::command::{InfoOptions, InterpolateOptions, SubdivideOptions};
use super::{in_option_terms, ErrorKind, RecordError};
use crate::budget::MemoryBudget;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;
use subdiv_interp::report::MeshSummary;
use subdiv_interp::{
    DengMaOptions, DengWangOptions, FanChengLaiOptions, InterpError, Method, MethodOptions, Parameter, Report, Shape,
    SurfaceOptions, ZhengCaiOptions,
};
use subdiv_io::{Format, IoError, StagedFile};
use subdiv_mesh::{DVec3, Mesh};
use subdiv_stencil::{Options, StencilError};

/// What a job produced: its outputs (committed), its report.
pub(super) struct Done {
    pub outputs: Vec<PathBuf>,
    pub report: serde_json::Value,
}

/// A failed job: why, and the report when there is one (`info` of an
/// invalid mesh describes it and fails).
pub(super) struct Failed {
    pub error: RecordError,
    pub report: Option<serde_json::Value>,
}

impl From<RecordError> for Failed {
    fn from(error: RecordError) -> Self {
        Failed { error, report: None }
    }
}

/// The error and its causes on one line, each once (a cause the message
/// already ends with is not repeated), in the command line's terms: the
/// line `subdiv` prints after `subdiv: error: `.
pub(super) fn one_line(error: &(dyn std::error::Error + 'static)) -> String {
    let mut line = error.to_string();
    let mut cause = error.source();
    while let Some(c) = cause {
        let text = c.to_string();
        if !line.ends_with(&text) {
            line.push_str(": ");
            line.push_str(&text);
        }
        cause = c.source();
    }
    in_option_terms(&line.replace(['\n', '\r'], " "))
}

fn failure(kind: ErrorKind, message: impl Into<String>) -> RecordError {
    RecordError::new(kind, in_option_terms(&message.into()))
}

fn bad_input(message: impl Into<String>) -> RecordError {
    failure(ErrorKind::BadInput, message)
}

fn to_value(report: &impl Serialize) -> Result<serde_json::Value, RecordError> {
    serde_json::to_value(report).map_err(|e| failure(ErrorKind::Panic, format!("report: {e}")))
}

/// A job's context: the input, where its outputs go, the warnings so far.
pub(super) struct Job<'a> {
    pub input: &'a Path,
    pub out_dir: &'a Path,
    pub name: &'a str,
    pub warnings: Vec<String>,
    staged: Vec<StagedFile>,
}

impl<'a> Job<'a> {
    pub fn new(input: &'a Path, out_dir: &'a Path, name: &'a str) -> Self {
        Job { input, out_dir, name, warnings: Vec::new(), staged: Vec::new() }
    }

    fn shown(&self) -> String {
        self.input.display().to_string()
    }

    /// `out_dir/NAME.SUFFIX.EXT`.
    fn output(&self, suffix: &str, ext: &str) -> PathBuf {
        self.out_dir.join(format!("{}.{suffix}.{ext}", self.name))
    }

    /// The output extension: the option's, else the input's when it is a
    /// format, else `obj`.
    fn extension(&self, format: Option<&str>) -> String {
        if let Some(ext) = format {
            return ext.to_string();
        }
        match self.input.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()) {
            Some(ext) if Format::from_path(Path::new(&format!("x.{ext}"))).is_ok() => ext,
            _ => "obj".to_string(),
        }
    }

    /// Reads and validates the input (the file's tags and texture
    /// coordinates), as `subdiv interpolate` and `subdivide` do.
    fn load(&mut self) -> Result<Mesh, RecordError> {
        let (mesh, warnings) = subdiv_io::load_mesh_with_warnings(self.input).map_err(|e| bad_input(one_line(&e)))?;
        self.warnings.extend(warnings.iter().map(ToString::to_string));
        Ok(mesh)
    }

    /// Stages `mesh` at `path` (vertex normals when `normals`), as the
    /// command line does: nothing non-finite, the positions as the format
    /// stores them, tags and texture coordinates where the format has a
    /// place for them (a warning where not).
    fn stage_mesh(&mut self, path: &Path, mesh: &Mesh, normals: bool) -> Result<(), RecordError> {
        let shown = path.display();
        let format = Format::from_path(path).map_err(|e| bad_input(one_line(&e)))?;
        let n = normals.then(|| mesh.vertex_normals());
        require_finite(&shown.to_string(), mesh, n.as_deref())?;
        let positions = as_written(path, format, mesh.positions())?;
        let tags = mesh.tags().to_list(mesh.topology());
        let (mut view, left_out) = subdiv_io::view_for_format(mesh, &positions, &tags, format);
        if let Some(n) = &n {
            view = view.with_normals(n);
        }
        self.warnings.extend(left_out.iter().map(|what| format!("{shown}: {what}")));
        let staged = subdiv_io::stage_mesh(path, view, format, &mut |_| {}).map_err(|e| {
            let kind = if matches!(e, IoError::Io { .. }) { ErrorKind::WriteFailed } else { ErrorKind::BadInput };
            failure(kind, one_line(&e))
        })?;
        self.staged.push(staged);
        Ok(())
    }

    /// Puts every staged output in place, or none.
    fn commit(&mut self) -> Result<Vec<PathBuf>, RecordError> {
        let staged = std::mem::take(&mut self.staged);
        let paths = staged.iter().map(|s| s.target().to_path_buf()).collect();
        subdiv_io::commit_all(staged).map_err(|e| failure(ErrorKind::WriteFailed, one_line(&e)))?;
        Ok(paths)
    }

    /// `subdiv info`: the summary; an invalid mesh (or, with `strict`, a
    /// warning) fails with the summary as its report.
    pub fn info(&mut self, options: &InfoOptions) -> Result<Done, Failed> {
        let (soup, warnings) =
            subdiv_io::read_mesh_with_warnings(self.input, &mut |_, _| {}).map_err(|e| bad_input(one_line(&e)))?;
        self.warnings.extend(warnings.iter().map(ToString::to_string));
        let file = self.shown();
        let summary = crate::info::summarize_soup(soup, Some(&file));
        let report = to_value(&summary)?;
        let error = match &summary.error {
            Some(error) => Some(format!("{file}: {error}")),
            None if options.strict && !summary.warnings.is_empty() => {
                Some(format!("{file}: {} (--strict)", summary.warnings.join("; ")))
            }
            None => None,
        };
        match error {
            Some(message) => Err(Failed { error: bad_input(message), report: Some(report) }),
            None => Ok(Done { outputs: Vec::new(), report }),
        }
    }

    /// `subdiv subdivide … -o NAME.subdivided.EXT`.
    pub fn subdivide(&mut self, o: &SubdivideOptions) -> Result<Done, Failed> {
        let path = self.output("subdivided", &self.extension(o.format.as_deref()));
        let mut mesh = self.load()?;
        let input = self.shown();
        if o.triangulate {
            let t = subdiv_mesh::triangulate(&mesh).map_err(|e| bad_input(format!("{input}: --triangulate: {e}")))?;
            mesh = t.mesh;
        }
        let options = o.options();
        let format = Format::from_path(&path).map_err(|e| bad_input(one_line(&e)))?;
        let vertex_arrays = u64::from(o.normals) + u64::from(o.limit);
        MemoryBudget::available()
            .check("subdivide", mesh.topology(), options.scheme, o.levels, vertex_arrays, Some(format))
            .map_err(|e| bad_input(e.to_string()))?;
        let refined = refine(&mut self.warnings, &mesh, options, o.levels, o.limit).map_err(|e| {
            let hint = match e {
                StencilError::NotTriangles { .. } => " (or pass --triangulate)",
                StencilError::TagsNotSupported { .. } => {
                    " (catmull-clark and loop take every crease and corner tag, doo-sabin infinitely sharp ones)"
                }
                _ => "",
            };
            bad_input(format!("{input}: {e}{hint}"))
        })?;
        self.stage_mesh(&path, &refined, o.normals)?;
        let outputs = self.commit()?;
        let mut input_summary = MeshSummary::of(&mesh);
        input_summary.file = Some(input);
        let report = SubdivideReport {
            scheme: options.scheme.name(),
            levels: o.levels,
            limit: o.limit,
            input: input_summary,
            output: MeshSummary::of(&refined),
        };
        Ok(Done { outputs, report: to_value(&report)? })
    }

    /// `subdiv interpolate … -o NAME.control.EXT --surface NAME.surface.EXT
    /// --levels L` (Deng-Ma: its `-o`, the refined surface, as
    /// `NAME.surface.EXT` only).
    pub fn interpolate(&mut self, o: &InterpolateOptions) -> Result<Done, Failed> {
        let total = Instant::now();
        let ext = self.extension(o.format.as_deref());
        let mesh = self.load()?;
        let name = o.method.name();
        let input = self.shown();
        let options = method_options(o).map_err(|e| classify(&input, e))?;
        let result = subdiv_interp::interpolate(&mesh, &options).map_err(|e| classify(&input, e))?;
        let is_deng_ma = o.method == Method::DengMa;
        let surface = if o.levels > 0 {
            let surface_path = self.output("surface", &ext);
            let format = Format::from_path(&surface_path).map_err(|e| bad_input(one_line(&e)))?;
            let what = format!("--surface {}", surface_path.display());
            MemoryBudget::available()
                .check(&what, result.control.topology(), result.options().scheme, o.levels, 2, Some(format))
                .map_err(|e| bad_input(e.to_string()))?;
            let refined = refine(&mut self.warnings, &result.control, result.options(), o.levels, true);
            Some(refined.map_err(|e| classify(&input, e.into()))?)
        } else {
            None
        };
        let control_path = (!is_deng_ma).then(|| self.output("control", &ext));
        // The error, measured on the control positions as they will be written
        // (f32 formats round them), by the plain scheme's rules; positions
        // written unchanged: the method's own measurement on these very bits.
        let mut rounded = None;
        if let Some(path) = &control_path {
            let format = Format::from_path(path).map_err(|e| bad_input(one_line(&e)))?;
            if !format.keeps_f64() {
                rounded = Some(as_written(path, format, result.control.positions())?);
            }
        }
        let error = match (rounded, result.measured_error) {
            (None, Some(error)) => {
                require_finite(name, &result.control, None)?;
                error
            }
            (rounded, _) => {
                let mut measured = result.clone();
                if let Some(positions) = rounded {
                    measured.control = result.control.with_positions(positions);
                }
                require_finite(name, &measured.control, None)?;
                measured.error(mesh.positions(), &result.interpolated, mesh.bbox_diagonal())
            }
        };
        if error.max_rel.is_nan() || error.max_rel > o.tol {
            return Err(failure(
                ErrorKind::NotConverged,
                format!(
                    "{input}: {name}: the measured error {:.3e}·d exceeds --tol {:.1e} (mean {:.3e}·d); nothing written",
                    error.max_rel, o.tol, error.mean_rel
                ),
            )
            .into());
        }
        if let Some(path) = &control_path {
            self.stage_mesh(path, &result.control, false)?;
        }
        if let Some(s) = &surface {
            self.stage_mesh(&self.output("surface", &ext), s, true)?;
        }
        let control_mesh = if is_deng_ma { surface.as_ref().unwrap_or(&result.control) } else { &result.control };
        let report = Report::new(&mesh, &result, error)
            .with_input_file(input)
            .with_control(control_mesh)
            .with_total_ms(total.elapsed().as_secs_f64() * 1e3);
        let outputs = self.commit()?;
        self.warnings.extend(result.warnings.iter().cloned());
        Ok(Done { outputs, report: to_value(&report)? })
    }
}

/// The report of a `subdivide` job.
#[derive(Serialize)]
struct SubdivideReport {
    /// [`subdiv_stencil::Scheme::name`].
    scheme: &'static str,
    levels: usize,
    limit: bool,
    /// The input, with its file.
    input: MeshSummary,
    /// The mesh written.
    output: MeshSummary,
}

/// The method's options from the batch options.
fn method_options(o: &InterpolateOptions) -> Result<MethodOptions, InterpError> {
    let options: MethodOptions = match o.method {
        Method::ZhengCai => {
            ZhengCaiOptions::default().with_ite_max(o.ite_max.unwrap_or(5)).with_eps(o.eps.unwrap_or(0.003)).into()
        }
        Method::FanChengLai => {
            FanChengLaiOptions::default().with_shape(o.shape.map_or_else(Shape::default, Shape::Uniform)).into()
        }
        Method::DengWang => {
            let mut options = DengWangOptions::default();
            if let Some(mu) = o.mu {
                options = options.with_mu(mu);
            }
            if let Some(beta) = o.beta {
                options = options.with_beta(beta.into());
            }
            options.into()
        }
        Method::DengMa => {
            let tension = match (o.omega, o.variable_tension) {
                (_, Some(lambda)) => subdiv_stencil::Tension::Variable { lambda },
                (omega, None) => subdiv_stencil::Tension::Global(omega.unwrap_or(1.0)),
            };
            DengMaOptions::default().with_tension(tension).into()
        }
        method => MethodOptions::new(method),
    };
    let surface =
        SurfaceOptions::default().with_boundary(o.boundary).with_crease_method(o.crease_method).with_fvar(o.fvar);
    options.with_tol(o.tol).with_max_iter(o.max_iter).with_solver(o.solver).with_surface(surface).with_subset(None)
}

/// Not converged (exit 3) when the solver did not get there, bad input
/// otherwise; the message names the option a parameter error is about,
/// else the input.
fn classify(input: &str, e: InterpError) -> RecordError {
    let subject = match &e {
        InterpError::InvalidParameter { parameter, .. } => match parameter {
            Parameter::Tol => "--tol",
            Parameter::Eps => "--eps",
            Parameter::Mu => "--mu",
            Parameter::Tension => "--omega/--variable-tension",
            Parameter::Shape => "--shape",
            _ => input,
        },
        _ => input,
    };
    let kind = if e.is_not_converged() { ErrorKind::NotConverged } else { ErrorKind::BadInput };
    failure(kind, format!("{subject}: {e}"))
}

/// `subdiv subdivide`'s refinement ([`subdiv_stencil::subdivide_for_output`]):
/// texture coordinates the scheme cannot refine are dropped with a warning.
fn refine(
    warnings: &mut Vec<String>,
    mesh: &Mesh,
    options: Options,
    levels: usize,
    limit: bool,
) -> Result<Mesh, StencilError> {
    let refined = subdiv_stencil::subdivide_for_output(mesh, options, levels, limit, |_| {})?;
    if let Some(reason) = refined.uvs_dropped {
        warnings.push(format!("texture coordinates not written: {reason}"));
    }
    Ok(refined.mesh)
}

/// The positions as `format` stores them (f32 formats round them); bad
/// input when a coordinate does not fit in f32.
fn as_written(path: &Path, format: Format, positions: &[DVec3]) -> Result<Vec<DVec3>, RecordError> {
    if format.keeps_f64() {
        return Ok(positions.to_vec());
    }
    let rounded: Vec<DVec3> = positions.iter().map(|p| p.as_vec3().as_dvec3()).collect();
    if let Some(i) = rounded.iter().position(|p| !p.is_finite()) {
        return Err(bad_input(format!(
            "{}: {format} stores 32-bit floats, which cannot hold vertex {i} at {}; use .obj, .off or .ply",
            path.display(),
            positions[i]
        )));
    }
    Ok(rounded)
}

/// Not converged (exit 3) for a result with a coordinate or normal that is
/// not finite: nothing non-finite is written.
fn require_finite(what: &str, mesh: &Mesh, normals: Option<&[DVec3]>) -> Result<(), RecordError> {
    let bad = mesh.positions().iter().filter(|p| !p.is_finite()).count();
    if bad > 0 {
        return Err(failure(
            ErrorKind::NotConverged,
            format!(
                "{what}: {bad} of {} vertices are not finite (NaN or infinite); nothing written",
                mesh.positions().len()
            ),
        ));
    }
    if let Some(n) = normals {
        let bad = n.iter().filter(|p| !p.is_finite()).count();
        if bad > 0 {
            return Err(failure(
                ErrorKind::NotConverged,
                format!("{what}: {bad} vertex normals are not finite; nothing written"),
            ));
        }
    }
    Ok(())
}
