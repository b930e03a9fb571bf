//! `subdiv.info`, `subdiv.batch` and the per-file task of `subdiv.dask`:
//! the facade's `subdiv::info` and `subdiv::batch`, with records and
//! summaries crossing into Python as JSON text (`json.loads` in
//! `__init__.py`), so that a record is the command line's JSON line exactly.

use crate::errors::{detached, input, Error, RaiseExt};
use crate::mesh::PyMesh;
use pyo3::prelude::*;
use std::path::PathBuf;
use subdiv::batch::{BatchError, BatchOptions, Command};

impl From<BatchError> for Error {
    fn from(e: BatchError) -> Self {
        match e {
            BatchError::Io { path, source } => {
                Error::Os { message: format!("{}: {source}", path.display()), kind: source.kind() }
            }
            e => Error::Input(e.to_string()),
        }
    }
}

/// The command `name` with the options of the JSON object `options_json`.
fn command(name: &str, options_json: &str) -> Result<Command, Error> {
    let options: serde_json::Value =
        serde_json::from_str(options_json).map_err(|e| input(format!("batch {name}: options: {e}")))?;
    Ok(Command::from_json(name, &options)?)
}

/// JSON text of a serialisable value.
fn to_json<T: serde::Serialize>(value: &T) -> Result<String, Error> {
    serde_json::to_string(value).map_err(|e| Error::Other(format!("cannot serialise the result: {e}")))
}

/// `info(mesh) -> str`: the `subdiv info --json` object of `mesh`, as JSON text.
#[pyfunction]
pub fn info(py: Python<'_>, mesh: &PyMesh) -> PyResult<String> {
    let (inner, file) = (mesh.inner.clone(), mesh.path.clone());
    detached(py, move || to_json(&subdiv::info::summarize(&inner, file.as_deref())))
}

/// `batch(inputs, out_dir, command, options_json, jobs, resume) -> list[str]`:
/// [`subdiv::batch::run`], one JSON record per input, in input order.
#[pyfunction]
#[pyo3(signature = (inputs, out_dir, command_name, options_json, jobs = 0, resume = true))]
pub fn batch(
    py: Python<'_>,
    inputs: Vec<PathBuf>,
    out_dir: PathBuf,
    command_name: &str,
    options_json: &str,
    jobs: usize,
    resume: bool,
) -> PyResult<Vec<String>> {
    let command = command(command_name, options_json).raise(py)?;
    let options = BatchOptions::default().with_jobs(jobs).with_resume(resume);
    detached(py, move || {
        let records = subdiv::batch::run(&inputs, &out_dir, &command, &options, |_| {})?;
        records.iter().map(to_json).collect()
    })
}

/// `expand_inputs(inputs) -> (files, names)`: the files a batch over
/// `inputs` (paths, directories, glob patterns) runs on, and the output
/// name of each ([`subdiv::batch::expand_inputs`], [`subdiv::batch::output_names`]).
#[pyfunction]
pub fn expand_inputs(py: Python<'_>, inputs: Vec<PathBuf>) -> PyResult<(Vec<PathBuf>, Vec<String>)> {
    detached(py, move || {
        let files = subdiv::batch::expand_inputs(&inputs)?;
        let names = subdiv::batch::output_names(&files);
        Ok((files, names))
    })
}

/// `run_one(index, input, name, out_dir, command, options_json, resume) -> str`:
/// one input of a batch ([`subdiv::batch::run_one_as`]), its JSON record;
/// what a distributed task runs.
#[pyfunction]
#[pyo3(signature = (index, input_path, name, out_dir, command_name, options_json, resume = true))]
// The task's arguments are the Python call's: one per field of the job.
#[allow(clippy::too_many_arguments)]
pub fn run_one(
    py: Python<'_>,
    index: usize,
    input_path: PathBuf,
    name: String,
    out_dir: PathBuf,
    command_name: &str,
    options_json: &str,
    resume: bool,
) -> PyResult<String> {
    let command = command(command_name, options_json).raise(py)?;
    let options = BatchOptions::default().with_resume(resume);
    detached(py, move || to_json(&subdiv::batch::run_one_as(index, &input_path, &name, &out_dir, &command, &options)))
}

/// `check_command(command, options_json)`: raises `InputError` (a
/// `ValueError`) naming the option when the command or an option is wrong,
/// before a distributed batch submits anything.
#[pyfunction]
pub fn check_command(py: Python<'_>, command_name: &str, options_json: &str) -> PyResult<()> {
    command(command_name, options_json).raise(py).map(drop)
}
