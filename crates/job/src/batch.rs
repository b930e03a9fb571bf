//! One command over many meshes: `subdiv batch` on the command line,
//! `subdiv.batch` and `subdiv.dask.map_files` in Python.
//!
//! A [`Command`] (`info`, `interpolate` or `subdivide`, with the options of
//! the single command) runs on every input, in parallel across meshes
//! ([`run`], rayon; each job may use rayon inside too), or on one
//! ([`run_one`], what a distributed task calls). Each input gives one
//! [`Record`] — its outputs and report, or its error with the command
//! line's message and exit code — and a failing mesh (a bad file, a method
//! that refuses it, a solver that does not converge, even a panic) never
//! stops the others.
//!
//! # Outputs
//!
//! Into `out_dir`, under the input's name ([`output_names`]: its file stem,
//! or the stem and a stable hash of its path when two inputs share a
//! stem):
//!
//! | command | files |
//! |---|---|
//! | `info` | none (the [`crate::info::Summary`] is the report) |
//! | `interpolate` | `NAME.control.EXT` (not Deng-Ma), `NAME.surface.EXT` when `levels > 0` |
//! | `subdivide` | `NAME.subdivided.EXT` |
//! | every command | `NAME.record.json`, the [`Record`], written last |
//!
//! byte for byte the files the single command writes (`subdiv interpolate
//! IN -o NAME.control.EXT --surface NAME.surface.EXT --levels L`).
//! A job's outputs are staged beside their targets and renamed into place
//! together (all or none), then its record.
//!
//! # Resuming
//!
//! With [`BatchOptions::resume`] (the default) an input is skipped when its
//! record exists, was made by the same command from the same file (its
//! canonical path, size and modification time), every output it lists still
//! exists, and it did not fail for a reason that may pass (a write failure,
//! a panic). The record returned is the stored one with
//! [`Record::skipped`] set; nothing is rewritten. Inputs that failed on
//! their content (bad input, no convergence) are skipped too: the same file
//! fails the same way.
//!
//! ```
//! use subdiv_job::batch::{run, BatchOptions, Command, InterpolateOptions};
//! use subdiv_interp::Method;
//! use subdiv_io::{write_mesh, WriteOptions};
//!
//! let dir = std::env::temp_dir().join(format!("subdiv-batch-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir)?;
//! let torus = dir.join("torus.obj");
//! write_mesh(&torus, &subdiv_mesh::shapes::torus(8, 6), &WriteOptions::default())?;
//! let missing = dir.join("missing.obj");
//! let command = Command::Interpolate(InterpolateOptions::new(Method::Cheng).with_levels(1));
//!
//! let out = dir.join("out");
//! let records = run(&[torus, missing], &out, &command, &BatchOptions::default(), |_| {})?;
//! assert!(records[0].error.is_none() && records[0].outputs.len() == 2);
//! assert_eq!(records[1].error.as_ref().unwrap().exit_code, 2); // one bad input stops nothing
//! assert_eq!(records[0].report.as_ref().unwrap()["method"], "cheng");
//!
//! // Again: everything is skipped, nothing rewritten.
//! let again = run(&[dir.join("torus.obj"), dir.join("missing.obj")], &out, &command, &BatchOptions::default(), |_| {})?;
//! assert!(again[0].skipped);
//! std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Order
//!
//! [`run`] calls `on_record` on the calling thread in input order (a record
//! waits for the ones before it), and returns the records in that order;
//! each record also carries its [`Record::index`].

mod inputs;
mod jobs;

pub use crate::error::{in_option_terms, ErrorKind};
pub use crate::options::{Command, InfoOptions, InterpolateOptions, SubdivideOptions, COMMAND_NAMES};
pub use inputs::{expand_inputs, output_names, stem_name};

use crate::error::JobError;

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;
use subdiv_io::fs::Destination;

/// What [`BatchError::NoMeshInDirectory`] adds when the mesh files may be
/// further down.
fn subdirectory_hint(dir: &Path, subdirectories: bool) -> String {
    match subdirectories {
        true => format!(" (subdirectories are not searched: '{}' reaches them)", dir.join("**").join("*").display()),
        false => String::new(),
    }
}

/// Why a batch could not start (a problem of one input is in its
/// [`Record`] instead).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BatchError {
    /// An invalid command: an unknown or mistyped option, a missing required one, a value out of
    /// range, an option of another method or scheme (the message of the single command).
    #[error(transparent)]
    Options(#[from] JobError),
    /// A malformed glob pattern.
    #[error("{pattern}: invalid pattern: {message}")]
    Pattern {
        /// The pattern.
        pattern: String,
        /// What is wrong with it.
        message: String,
    },
    /// A pattern without mesh files.
    #[error("{}: no mesh file matches", .input.display())]
    NoMatch {
        /// The pattern.
        input: PathBuf,
    },
    /// A directory without mesh files of its own (its subdirectories are not
    /// searched; the message names the pattern that would search them).
    #[error("{}: no mesh file in this directory{}", .dir.display(), subdirectory_hint(.dir, *.subdirectories))]
    NoMeshInDirectory {
        /// The directory.
        dir: PathBuf,
        /// Whether it has subdirectories.
        subdirectories: bool,
    },
    /// A directory (an input to list, or the output directory) could not be
    /// read or created.
    #[error("{}: {source}", .path.display())]
    Io {
        /// The directory.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The worker threads could not be started.
    #[error("cannot start {jobs} worker threads: {message}")]
    Threads {
        /// Threads asked for.
        jobs: usize,
        /// The reason.
        message: String,
    },
}

/// How a batch runs. Build with `BatchOptions::default()` and the setters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[non_exhaustive]
pub struct BatchOptions {
    /// Meshes processed at once; 0: one per core (rayon's default).
    pub jobs: usize,
    /// Skip inputs whose record says they are done (see the module docs).
    pub resume: bool,
}

impl Default for BatchOptions {
    fn default() -> Self {
        Self { jobs: 0, resume: true }
    }
}

impl BatchOptions {
    /// With this many meshes at once (0: one per core).
    pub fn with_jobs(self, jobs: usize) -> Self {
        Self { jobs, ..self }
    }

    /// With or without resuming.
    pub fn with_resume(self, resume: bool) -> Self {
        Self { resume, ..self }
    }
}

/// The error of one input.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct RecordError {
    /// The line the single command prints after `subdiv: error: `.
    pub message: String,
    /// Its kind.
    pub kind: ErrorKind,
    /// [`ErrorKind::exit_code`].
    pub exit_code: u8,
}

impl RecordError {
    /// An error of `kind`.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Self {
        Self { message: message.into(), kind, exit_code: kind.exit_code() }
    }
}

/// What a record was made from: resuming compares it with the input now.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct Fingerprint {
    /// The input's canonical path.
    pub path: String,
    /// Its size in bytes.
    pub size: u64,
    /// Its modification time, nanoseconds since the Unix epoch.
    pub modified_ns: u64,
    /// The command.
    pub command: Command,
}

impl Fingerprint {
    /// The fingerprint of `input` for `command`; `None` when the file's
    /// metadata cannot be read (a missing file is never skipped).
    pub fn of(input: &Path, command: &Command) -> Option<Self> {
        let stamp = subdiv_io::fs::file_stamp(input)?;
        Some(Fingerprint {
            path: subdiv_io::fs::canonical(input)?.to_string_lossy().into_owned(),
            size: stamp.size,
            modified_ns: stamp.modified_ns,
            command: command.clone(),
        })
    }
}

/// The result of one input: one JSON line of `subdiv batch`, one element of
/// Python's `subdiv.batch`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[non_exhaustive]
pub struct Record {
    /// The input as given (after expansion).
    pub input: String,
    /// The files written (none on error).
    pub outputs: Vec<String>,
    /// The report: `info`: the [`crate::info::Summary`]; `interpolate`: the
    /// [`subdiv_interp::Report`] (`--report`'s JSON); `subdivide`: scheme, levels,
    /// limit, input and output counts. `null` on error, except `info` of an
    /// invalid mesh, which has both.
    pub report: Option<serde_json::Value>,
    /// Why it failed.
    pub error: Option<RecordError>,
    /// True when resumed from the stored record (nothing ran).
    pub skipped: bool,
    /// Wall-clock seconds of the job (of the run that made it, when skipped).
    pub seconds: f64,
    /// The input's place in the batch.
    pub index: usize,
    /// The name of its outputs ([`output_names`]).
    pub name: String,
    /// Warnings (what a reader dropped, mesh defects, a method's notes).
    pub warnings: Vec<String>,
    /// What it was made from (`None` when the input could not be read).
    pub fingerprint: Option<Fingerprint>,
}

impl Record {
    /// True when it has no error.
    pub fn succeeded(&self) -> bool {
        self.error.is_none()
    }
}

/// [`run_one_as`] under the input's [`stem_name`], resuming: what a
/// distributed task runs for one file. Inputs of one batch that share a
/// stem need [`output_names`] and [`run_one_as`].
pub fn run_one(input: &Path, out_dir: &Path, command: &Command) -> Record {
    run_one_as(0, input, &stem_name(input), out_dir, command, &BatchOptions::default())
}

/// Runs `command` on `input`, writing into `out_dir` (created if needed)
/// under `name`; the record says how it went and is stored as
/// `out_dir/NAME.record.json` last. Never fails and never panics: every
/// failure is in [`Record::error`].
pub fn run_one_as(
    index: usize,
    input: &Path,
    name: &str,
    out_dir: &Path,
    command: &Command,
    options: &BatchOptions,
) -> Record {
    let start = Instant::now();
    let fingerprint = Fingerprint::of(input, command);
    let record_path = out_dir.join(format!("{name}.record.json"));
    if options.resume {
        if let Some(stored) = resumable(&record_path, fingerprint.as_ref(), out_dir) {
            return Record { index, input: input.display().to_string(), skipped: true, ..stored };
        }
    }
    let mut warnings = Vec::new();
    let (outputs, report, error) = guarded(input, || {
        command.validate()?;
        subdiv_io::fs::ensure_dir(out_dir)
            .map_err(|e| JobError::write_failed(format!("{}: {e}", out_dir.display())))?;
        // The record is an output too: checked before any work, as the outputs are.
        if !matches!(subdiv_io::fs::destination(&record_path), Destination::Absent | Destination::File) {
            return Err(JobError::bad_input(format!(
                "{} exists and is not a regular file: refusing to replace it with the record",
                record_path.display()
            ))
            .into());
        }
        let mut job = jobs::Job::new(input, out_dir, name);
        let result = match command {
            Command::Info(o) => job.info(o),
            Command::Interpolate(o) => job.interpolate(o),
            Command::Subdivide(o) => job.subdivide(o),
        };
        warnings = std::mem::take(&mut job.warnings.0);
        result
    });
    let mut record = Record {
        input: input.display().to_string(),
        outputs: outputs.iter().map(|p| p.display().to_string()).collect(),
        report,
        error,
        skipped: false,
        seconds: start.elapsed().as_secs_f64(),
        index,
        name: name.to_string(),
        warnings,
        fingerprint,
    };
    if let Err(e) = store(&record_path, &record) {
        if record.error.is_none() {
            // A special file put there since the check is refused as the check refuses it.
            let kind = if matches!(e, subdiv_io::IoError::NotAFile { .. }) {
                ErrorKind::BadInput
            } else {
                ErrorKind::WriteFailed
            };
            record.error = Some(RecordError::new(kind, crate::error::one_line(&e)));
        }
    }
    record
}

/// A job's outputs, report and error; a panic (a bug) becomes an error of
/// kind [`ErrorKind::Panic`] naming the input, so one mesh cannot stop the
/// batch.
fn guarded(
    input: &Path,
    job: impl FnOnce() -> Result<jobs::Done, jobs::Failed>,
) -> (Vec<PathBuf>, Option<serde_json::Value>, Option<RecordError>) {
    match catch_unwind(AssertUnwindSafe(job)) {
        Ok(Ok(done)) => (done.outputs, Some(done.report), None),
        Ok(Err(failed)) => (Vec::new(), failed.report, Some(failed.error)),
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic".into());
            let message = format!("{}: internal error (please report it): {what}", input.display());
            (Vec::new(), None, Some(RecordError::new(ErrorKind::Panic, message)))
        }
    }
}

/// Writes the record atomically.
fn store(path: &Path, record: &Record) -> Result<(), subdiv_io::IoError> {
    let dir = path.parent().unwrap_or(Path::new("."));
    if !dir.is_dir() {
        // The output directory could not be made: the record says so.
        return Ok(());
    }
    let mut text = serde_json::to_string_pretty(record).expect("a record serialises");
    text.push('\n');
    subdiv_io::stage_bytes(path, text.as_bytes())?.commit()
}

/// The stored record at `path` when the input need not run again.
fn resumable(path: &Path, now: Option<&Fingerprint>, out_dir: &Path) -> Option<Record> {
    let now = now?;
    // A stored record is small text: read with the special-file check.
    let text = subdiv_io::read_text(path).ok()?;
    let stored: Record = serde_json::from_str(&text).ok()?;
    let same = stored.fingerprint.as_ref() == Some(now);
    let retry = stored.error.as_ref().is_some_and(|e| !e.kind.is_deterministic());
    // Outputs are looked for in out_dir as it is named now (the record may
    // have been made from another working directory).
    let complete = stored.outputs.iter().all(|o| Path::new(o).file_name().is_some_and(|f| out_dir.join(f).is_file()));
    (same && !retry && complete).then_some(stored)
}

/// Runs `command` on every input ([`expand_inputs`]: paths, directories,
/// glob patterns) into `out_dir`, `options.jobs` meshes at a time, calling
/// `on_record` with each record in input order; returns them all, in order.
///
/// # Errors
/// Only what prevents the batch from starting: an invalid command, a
/// pattern or directory without mesh files, an output directory that cannot
/// be created, no threads. A failing input is a record with an error.
pub fn run(
    inputs: &[PathBuf],
    out_dir: &Path,
    command: &Command,
    options: &BatchOptions,
    mut on_record: impl FnMut(&Record),
) -> Result<Vec<Record>, BatchError> {
    command.validate()?;
    let inputs = expand_inputs(inputs)?;
    subdiv_io::fs::ensure_dir(out_dir).map_err(|source| BatchError::Io { path: out_dir.to_path_buf(), source })?;
    let names = output_names(&inputs);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.jobs)
        .build()
        .map_err(|e| BatchError::Threads { jobs: options.jobs, message: e.to_string() })?;
    let workers = pool.current_num_threads().min(inputs.len());
    let next = AtomicUsize::new(0);
    let (sender, receiver) = std::sync::mpsc::channel::<Record>();
    let mut records = Vec::with_capacity(inputs.len());
    let (inputs, names, next, pool) = (&inputs, &names, &next, &pool);
    std::thread::scope(|scope| {
        scope.spawn(move || {
            // Each worker takes the next input when it is free, so inputs start
            // in order and a slow mesh delays no other.
            pool.scope(move |s| {
                for _ in 0..workers {
                    let sender = sender.clone();
                    s.spawn(move |_| loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(input) = inputs.get(i) else { break };
                        let record = run_one_as(i, input, &names[i], out_dir, command, options);
                        if sender.send(record).is_err() {
                            break;
                        }
                    });
                }
                drop(sender);
            });
        });
        let mut pending = BTreeMap::new();
        for record in receiver {
            pending.insert(record.index, record);
            while let Some(record) = pending.remove(&records.len()) {
                on_record(&record);
                records.push(record);
            }
        }
    });
    Ok(records)
}

#[cfg(test)]
mod tests;
