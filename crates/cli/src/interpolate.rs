//! `subdiv interpolate MESH --method M [...]`: the flags given become the options of
//! [`subdiv::job::run::interpolate`] (its report: [report JSON]).
//!
//! [report JSON]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-report-json

use crate::failure::Failure;
use crate::options::InterpolateFlags;
use crate::progress;
use std::path::PathBuf;
use subdiv::job::run::{self, InterpolateOutputs};
use subdiv::job::InterpolateOptions;

/// Arguments of `subdiv interpolate`.
#[derive(clap::Args, Debug)]
pub struct InterpolateArgs {
    /// Input mesh: its vertices are the data to interpolate.
    mesh: PathBuf,
    /// The method, its options and the surface's.
    #[command(flatten)]
    flags: InterpolateFlags,
    /// Write the control mesh (deng-ma: the refined surface).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Write the surface: the control mesh refined --levels times by its plain scheme, at limit
    /// positions, with vertex normals.
    #[arg(long)]
    surface: Option<PathBuf>,
    /// Write the JSON report (keys: docs/ARCHITECTURE.md, "Contract: report JSON").
    #[arg(long)]
    report: Option<PathBuf>,
}

/// Runs `subdiv interpolate`.
pub fn run(args: &InterpolateArgs) -> Result<(), Failure> {
    let options = InterpolateOptions::from_json(&args.flags.to_json())?;
    let paths = InterpolateOutputs::default()
        .with_control(args.output.clone())
        .with_surface(args.surface.clone())
        .with_report(args.report.clone());
    let done = run::interpolate(&args.mesh, &options, &paths, &mut progress::Terminal::default())?;
    for prim in done.prims.iter().filter(|_| done.prims.len() > 1) {
        let e = &prim.report.error;
        progress::summary(format!("{}: max error {:.3e}·d (mean {:.3e}·d)", prim.prim, e.max_rel, e.mean_rel));
    }
    let (error, report) = (&done.error, &done.report);
    progress::summary(format!(
        "{}: {} vertices interpolated, max error {:.3e}·d (mean {:.3e}·d), {} iterations, {:.1} ms",
        options.method.name(),
        error.count,
        error.max_rel,
        error.mean_rel,
        report.solver.iterations,
        report.timing_ms.total
    ));
    Ok(())
}
