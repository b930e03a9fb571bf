//! `subdiv batch COMMAND INPUTS... --out-dir DIR [--jobs N] [--no-resume]
//! [options]`: [`subdiv::batch::run`] with the single commands' flags.
//!
//! The flags given become the command's options by name (`--max-iter 50`
//! → `"max_iter": 50`) and are checked by [`subdiv::batch::Command::from_json`],
//! the parser the Python package uses: a flag the command does not take is
//! an error naming it. One JSON line per input on stdout (the record),
//! progress on stderr; exit 0 when every input succeeded, 5 when any failed
//! (their records say why), 2 when the batch cannot start.

use crate::failure::{bad_input, write_failed, Failure};
use anyhow::anyhow;
use serde_json::{json, Map, Value};
use std::path::PathBuf;
use std::process::ExitCode;
use subdiv::batch::{BatchError, BatchOptions, Command};

/// Exit code of a batch in which some inputs failed.
pub const SOME_FAILED: u8 = 5;

/// The commands a batch runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum CommandName {
    /// `subdiv info` on each mesh (the summary is the record's report).
    Info,
    /// `subdiv interpolate`: NAME.control.EXT, NAME.surface.EXT (with --levels > 0).
    Interpolate,
    /// `subdiv subdivide`: NAME.subdivided.EXT.
    Subdivide,
}

/// Arguments of `subdiv batch`.
#[derive(clap::Args, Debug)]
pub struct BatchArgs {
    /// The command to run on every input.
    #[arg(value_enum)]
    command: CommandName,
    /// Mesh files, directories (the mesh files in them, not in their subdirectories) and glob patterns (`'meshes/**/*.obj'` searches subdirectories too).
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
    /// Where the outputs and the records (NAME.record.json) go; created if needed.
    #[arg(long)]
    out_dir: PathBuf,
    /// Meshes processed at once (default: one per core).
    #[arg(long, default_value_t = 0)]
    jobs: usize,
    /// Run every input again, even those whose record says they are done.
    #[arg(long)]
    no_resume: bool,
    /// info: treat warnings as errors.
    #[arg(long)]
    strict: bool,
    /// interpolate: the method.
    #[arg(long)]
    method: Option<String>,
    /// interpolate: tolerance.
    #[arg(long)]
    tol: Option<f64>,
    /// interpolate: iteration cap.
    #[arg(long)]
    max_iter: Option<usize>,
    /// interpolate: solver (auto or a solver name, as `subdiv interpolate`).
    #[arg(long)]
    solver: Option<String>,
    /// interpolate: surface levels (0: no surface; default 3); subdivide: steps (required).
    #[arg(long)]
    levels: Option<usize>,
    /// Output extension (obj, off, ply, stl, gltf, glb; default the input's).
    #[arg(long)]
    format: Option<String>,
    /// Boundary interpolation (as `subdiv subdivide`).
    #[arg(long)]
    boundary: Option<String>,
    /// Semi-sharp crease decay (as `subdiv subdivide`).
    #[arg(long)]
    crease_method: Option<String>,
    /// Face-varying interpolation (as `subdiv subdivide`).
    #[arg(long)]
    fvar: Option<String>,
    /// interpolate, fan-cheng-lai: one shape parameter λ.
    #[arg(long)]
    shape: Option<f64>,
    /// interpolate, zheng-cai: ITE_MAX.
    #[arg(long)]
    ite_max: Option<usize>,
    /// interpolate, zheng-cai: EPS.
    #[arg(long)]
    eps: Option<f64>,
    /// interpolate, deng-wang: μ.
    #[arg(long)]
    mu: Option<f64>,
    /// Loop's β (warren, loop): interpolate deng-wang, subdivide loop.
    #[arg(long)]
    beta: Option<String>,
    /// Deng-Ma's global tension ω.
    #[arg(long)]
    omega: Option<f64>,
    /// Deng-Ma's variable tension λ.
    #[arg(long)]
    variable_tension: Option<f64>,
    /// subdivide: the scheme (doo-sabin, catmull-clark, loop, deng-ma).
    #[arg(long)]
    scheme: Option<String>,
    /// subdivide: move the final vertices to their limit positions.
    #[arg(long)]
    limit: bool,
    /// subdivide, loop: triangulate non-triangles first.
    #[arg(long)]
    triangulate: bool,
    /// subdivide: write vertex normals.
    #[arg(long)]
    normals: bool,
}

impl BatchArgs {
    /// The options given, by their JSON names; flags not given are left out
    /// (the command's defaults), so a flag of another command is refused.
    fn options(&self) -> Value {
        let mut map = Map::new();
        let mut put = |key: &str, value: Option<Value>| {
            if let Some(v) = value {
                map.insert(key.to_string(), v);
            }
        };
        put("method", self.method.as_ref().map(|v| json!(v)));
        put("tol", self.tol.map(|v| json!(v)));
        put("max_iter", self.max_iter.map(|v| json!(v)));
        put("solver", self.solver.as_ref().map(|v| json!(v)));
        put("levels", self.levels.map(|v| json!(v)));
        put("format", self.format.as_ref().map(|v| json!(v)));
        put("boundary", self.boundary.as_ref().map(|v| json!(v)));
        put("crease_method", self.crease_method.as_ref().map(|v| json!(v)));
        put("fvar", self.fvar.as_ref().map(|v| json!(v)));
        put("shape", self.shape.map(|v| json!(v)));
        put("ite_max", self.ite_max.map(|v| json!(v)));
        put("eps", self.eps.map(|v| json!(v)));
        put("mu", self.mu.map(|v| json!(v)));
        put("beta", self.beta.as_ref().map(|v| json!(v)));
        put("omega", self.omega.map(|v| json!(v)));
        put("variable_tension", self.variable_tension.map(|v| json!(v)));
        put("scheme", self.scheme.as_ref().map(|v| json!(v)));
        for (key, on) in [
            ("strict", self.strict),
            ("limit", self.limit),
            ("triangulate", self.triangulate),
            ("normals", self.normals),
        ] {
            put(key, on.then_some(json!(true)));
        }
        Value::Object(map)
    }
}

/// Runs `subdiv batch`: `Ok` with 0 when every input succeeded, 5 when any
/// failed (each record says why and has the single command's exit code).
pub fn run(args: &BatchArgs) -> Result<ExitCode, Failure> {
    let name = match args.command {
        CommandName::Info => "info",
        CommandName::Interpolate => "interpolate",
        CommandName::Subdivide => "subdivide",
    };
    let command = Command::from_json(name, &args.options()).map_err(|e| bad_input(flags(e)))?;
    let options = BatchOptions::default().with_jobs(args.jobs).with_resume(!args.no_resume);
    let starting = |e: BatchError| match e {
        BatchError::Io { ref path, .. } if *path == args.out_dir => write_failed(e),
        other => bad_input(other),
    };
    let total = subdiv::batch::expand_inputs(&args.inputs).map_err(starting)?.len();
    let (mut failed, mut skipped) = (0, 0);
    let records = subdiv::batch::run(&args.inputs, &args.out_dir, &command, &options, |record| {
        let line = serde_json::to_string(record).expect("a record serialises");
        crate::stdout::line(&line);
        failed += usize::from(!record.succeeded());
        skipped += usize::from(record.skipped);
        if !crate::progress::quiet() {
            let how = match (&record.error, record.skipped) {
                (Some(e), _) => format!("error: {}", e.message),
                (None, true) => "done before (skipped)".to_string(),
                (None, false) => format!("ok ({:.2} s)", record.seconds),
            };
            eprintln!("subdiv: batch [{}/{total}] {}: {how}", record.index + 1, record.input);
        }
    })
    .map_err(starting)?;
    if !crate::progress::quiet() {
        eprintln!(
            "subdiv: batch {name}: {} inputs, {} ok, {failed} failed, {skipped} skipped",
            records.len(),
            records.len() - failed
        );
    }
    Ok(if failed > 0 { ExitCode::from(SOME_FAILED) } else { ExitCode::SUCCESS })
}

/// An options error in the command line's terms: the options are the
/// flags (`max_iter` is `--max-iter`).
fn flags(e: BatchError) -> anyhow::Error {
    anyhow!(e.to_string().replace("unknown field", "unknown option").replace("missing field", "missing option"))
}
