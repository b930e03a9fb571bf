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
use crate::options::{put, MethodFlags, SurfaceFlags, TensionFlags};
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
    /// Mesh files, directories (their mesh files) and glob patterns ('scans/**/*.obj').
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
    /// Where the outputs and records go (created if needed).
    #[arg(long)]
    out_dir: PathBuf,
    /// Meshes processed at once (0: one per core).
    #[arg(long, default_value_t = 0)]
    jobs: usize,
    /// Run every input again, even those whose record says they are done.
    #[arg(long)]
    no_resume: bool,
    /// info: warnings are errors.
    #[arg(long)]
    strict: bool,
    /// The outputs' extension (obj, off, ply, stl, gltf, glb; default: the input's).
    #[arg(long)]
    format: Option<String>,
    /// interpolate: the method and its options (as `subdiv interpolate`).
    #[command(flatten)]
    method: MethodFlags,
    /// subdivide: write vertex normals (bare `--normals`); interpolate: zheng-cai, deng-wang's
    /// normals file (`--normals=FILE`: with `=`, so that an input after a bare flag stays an input).
    #[arg(long, num_args = 0..=1, require_equals = true, value_name = "FILE")]
    normals: Option<Option<PathBuf>>,
    /// subdivide: the scheme; interpolate --method fair: the control mesh's scheme.
    #[arg(long)]
    scheme: Option<String>,
    /// subdivide: the steps; interpolate: the surface's levels (default 3; 0: no surface).
    #[arg(long)]
    levels: Option<usize>,
    /// subdivide: limit positions.
    #[arg(long)]
    limit: bool,
    /// subdivide --scheme loop: triangulate first.
    #[arg(long)]
    triangulate: bool,
    /// Deng-Ma's tension.
    #[command(flatten)]
    tension: TensionFlags,
    /// The surface's options, tags, budget.
    #[command(flatten)]
    surface: SurfaceFlags,
}

impl BatchArgs {
    /// Every flag given, by the names `Command::from_json` takes (the single commands' own,
    /// `format`, `strict`): what the chosen command does not take is refused by name.
    fn options(&self) -> Value {
        let mut map = Map::new();
        self.method.put(&mut map);
        self.tension.put(&mut map);
        self.surface.put(&mut map);
        match &self.normals {
            Some(Some(file)) => map.insert("normals".into(), json!(file)),
            Some(None) => map.insert("normals".into(), json!(true)),
            None => None,
        };
        put!(map, "scheme" => &self.scheme, "levels" => self.levels, "format" => &self.format);
        for (key, on) in [("limit", self.limit), ("triangulate", self.triangulate), ("strict", self.strict)] {
            put!(map, key => on.then_some(true));
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
    let command = Command::from_json(name, &args.options())?;
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
