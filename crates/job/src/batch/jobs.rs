//! One command on one input of a batch: the outputs named after the input in the output
//! directory, then the one pipeline ([`crate::run`]) — the files and messages of the single
//! command.

use super::RecordError;
use crate::error::{ErrorKind, JobError};
use crate::options::{InfoOptions, InterpolateOptions, SubdivideOptions};
use crate::progress::Warnings;
use crate::run::{self, InterpolateOutputs};
use serde::Serialize;
use std::path::{Path, PathBuf};
use subdiv_io::Format;

/// What a job produced: its outputs (committed), its report.
pub(super) struct Done {
    pub outputs: Vec<PathBuf>,
    pub report: serde_json::Value,
}

/// A failed job: why, and the report when there is one (`info` of an invalid mesh describes it
/// and fails).
pub(super) struct Failed {
    pub error: RecordError,
    pub report: Option<serde_json::Value>,
}

impl From<JobError> for Failed {
    fn from(e: JobError) -> Self {
        Failed { error: RecordError::new(e.kind, e.message), report: None }
    }
}

fn to_value(report: &impl Serialize) -> Result<serde_json::Value, Failed> {
    serde_json::to_value(report).map_err(|e| JobError::new(ErrorKind::Panic, format!("report: {e}")).into())
}

/// A job's context: the input, where its outputs go, the warnings so far.
pub(super) struct Job<'a> {
    pub input: &'a Path,
    pub out_dir: &'a Path,
    pub name: &'a str,
    pub warnings: Warnings,
}

impl<'a> Job<'a> {
    pub fn new(input: &'a Path, out_dir: &'a Path, name: &'a str) -> Self {
        Job { input, out_dir, name, warnings: Warnings::default() }
    }

    /// `out_dir/NAME.SUFFIX.EXT`.
    fn output(&self, suffix: &str, ext: &str) -> PathBuf {
        self.out_dir.join(format!("{}.{suffix}.{ext}", self.name))
    }

    /// The output extension: the option's, else the input's when it is a format, else `obj`.
    fn extension(&self, format: Option<&str>) -> String {
        if let Some(ext) = format {
            return ext.to_string();
        }
        match self.input.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()) {
            Some(ext) if Format::from_path(Path::new(&format!("x.{ext}"))).is_ok() => ext,
            _ => "obj".to_string(),
        }
    }

    /// `subdiv info`: the summary; an invalid mesh (or, with `strict`, a warning) fails with the
    /// summary as its report.
    pub fn info(&mut self, options: &InfoOptions) -> Result<Done, Failed> {
        let (summary, error) = run::info(self.input, options, &mut self.warnings)?;
        let report = to_value(&summary)?;
        match error {
            Some(e) => Err(Failed { error: RecordError::new(e.kind, e.message), report: Some(report) }),
            None => Ok(Done { outputs: Vec::new(), report }),
        }
    }

    /// `subdiv subdivide … -o NAME.subdivided.EXT`.
    pub fn subdivide(&mut self, o: &SubdivideOptions) -> Result<Done, Failed> {
        let path = self.output("subdivided", &self.extension(o.format.as_deref()));
        let done = run::subdivide(self.input, o, &path, &mut self.warnings)?;
        Ok(Done { outputs: done.outputs, report: to_value(&done.report)? })
    }

    /// `subdiv interpolate … -o NAME.control.EXT --surface NAME.surface.EXT --levels L`
    /// (Deng-Ma: its refined surface as `NAME.surface.EXT` only).
    pub fn interpolate(&mut self, o: &InterpolateOptions) -> Result<Done, Failed> {
        let ext = self.extension(o.format.as_deref());
        let is_deng_ma = o.method == subdiv_interp::Method::DengMa;
        let paths = InterpolateOutputs {
            control: (!is_deng_ma).then(|| self.output("control", &ext)),
            surface: (o.levels > 0).then(|| self.output("surface", &ext)),
            report: None,
        };
        let done = run::interpolate(self.input, o, &paths, &mut self.warnings)?;
        Ok(Done { outputs: done.outputs, report: to_value(&done.report)? })
    }
}
