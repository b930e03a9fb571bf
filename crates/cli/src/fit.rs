//! `subdiv fit TARGET --control COARSE --scheme S -o FITTED [--report R.json]
//! [--iterations N] [--smoothness w] [--method gauss-newton|lspia|tangent]
//! [--loss l2|huber|cauchy] [--tolerance t] [--min-improvement r]
//! [--max-time SECONDS]`: moves COARSE's control points (topology and tags
//! kept) so that its limit surface fits TARGET, a mesh or a point cloud (a
//! file without faces), possibly covering only part of the surface.

use crate::failure::{bad_input, Failure};
use crate::outputs::Outputs;
use crate::sample::LimitArgs;
use anyhow::anyhow;
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use std::path::PathBuf;
use std::time::Instant;
use subdiv_eval::fit::{FitLoss, FitMethod, FitObserver, TANGENT_LAMBDA};
use subdiv_eval::{fit, FitIteration, FitOptions, FitTarget};

/// `--method`'s parser: the names of [`FitMethod::ALL`] (defined once, in subdiv-eval).
fn method_parser() -> impl clap::builder::TypedValueParser<Value = FitMethod> {
    let values = FitMethod::ALL.map(|m| PossibleValue::new(m.name()).help(m.summary()));
    PossibleValuesParser::new(values).map(|s| s.parse::<FitMethod>().expect("a listed name"))
}

/// `--loss`'s parser: the names of [`FitLoss::ALL`].
fn loss_parser() -> impl clap::builder::TypedValueParser<Value = FitLoss> {
    let values = FitLoss::ALL.map(|l| PossibleValue::new(l.name()).help(l.summary()));
    PossibleValuesParser::new(values).map(|s| s.parse::<FitLoss>().expect("a listed name"))
}

/// Arguments of `subdiv fit`.
#[derive(clap::Args, Debug)]
pub struct FitArgs {
    /// The target: a mesh (its faces as triangles) or a point cloud (a file without faces).
    target: PathBuf,
    /// The control mesh to fit (its topology and tags are kept).
    #[arg(long)]
    control: PathBuf,
    /// The limit surface.
    #[command(flatten)]
    limit: LimitArgs,
    /// Kept rounds of foot-point projection and least-squares step at most.
    #[arg(long, default_value_t = 30)]
    iterations: usize,
    /// Weight (≥ 0) of an umbrella-Laplacian smoothness term on the control points.
    #[arg(long, default_value_t = 0.0)]
    smoothness: f64,
    /// Stop when the RMS target→surface distance is at most this times d (target bbox diagonal).
    #[arg(long, default_value_t = 0.0)]
    tolerance: f64,
    /// Stop when a kept round lowers the objective by less than this fraction.
    #[arg(long, default_value_t = 1e-3)]
    min_improvement: f64,
    /// Stop after this many seconds (checked after every round).
    #[arg(long)]
    max_time: Option<f64>,
    /// The error term and its minimisation.
    #[arg(long, value_parser = method_parser(), default_value = "gauss-newton")]
    method: FitMethod,
    /// λ of `--method tangent` at the start.
    #[arg(long, default_value_t = TANGENT_LAMBDA)]
    lambda: f64,
    /// The loss on the target→surface distances (robust losses weigh outliers down).
    #[arg(long, value_parser = loss_parser(), default_value = "l2")]
    loss: FitLoss,
    /// The fitted control mesh (format by extension).
    #[arg(short, long)]
    output: PathBuf,
    /// JSON report: distances in both directions per round, absolute and relative to d.
    #[arg(long)]
    report: Option<PathBuf>,
}

fn iteration_json(it: &FitIteration) -> serde_json::Value {
    let d = it.scale.max(f64::MIN_POSITIVE);
    serde_json::json!({
        "iteration": it.iteration,
        "rms_target_to_surface": it.rms_target_to_surface,
        "max_target_to_surface": it.max_target_to_surface,
        "rms_surface_to_target": it.rms_surface_to_target,
        "max_surface_to_target": it.max_surface_to_target,
        "rms_target_to_surface_rel": it.rms_target_to_surface / d,
        "max_target_to_surface_rel": it.max_target_to_surface / d,
        "rms_surface_to_target_rel": it.rms_surface_to_target / d,
        "max_surface_to_target_rel": it.max_surface_to_target / d,
        "damping": it.damping,
        "retries": it.retries,
        "regularised": it.regularised,
        "robust_scale_rel": it.robust_scale,
        "solver": it.solver,
        "solver_iterations": it.solver_iterations,
        "seconds": it.seconds,
    })
}

/// Runs `subdiv fit`.
pub fn run(args: &FitArgs) -> Result<(), Failure> {
    let start = Instant::now();
    let inputs = [args.target.as_path(), args.control.as_path()];
    let mut outputs = Outputs::new(inputs.into_iter().chain(args.limit.tags.files()));
    outputs.mesh("--output", &args.output)?;
    if let Some(path) = &args.report {
        outputs.other("--report", path)?;
    }
    let soup = crate::load::read_soup(&args.target)?;
    let mut triangles = Vec::new();
    for (k, f) in soup.faces.iter().enumerate() {
        if let Some(&v) = f.iter().find(|&&v| v as usize >= soup.positions.len()) {
            return Err(bad_input(anyhow!(
                "{}: face {k} names vertex {v}, which does not exist",
                args.target.display()
            )));
        }
        for i in 1..f.len().saturating_sub(1) {
            triangles.push([f[0], f[i], f[i + 1]]);
        }
    }
    let target = FitTarget { points: soup.positions, triangles };
    let (control, options, _) = args.limit.load(&args.control)?;
    let method = args.method.with_lambda(args.lambda);
    let loss = args.loss;
    let bar = crate::progress::spinner(format!("fitting {}", args.control.display()));
    let observer = {
        let bar = bar.clone();
        FitObserver::new(move |it: &FitIteration| {
            let d = it.scale.max(f64::MIN_POSITIVE);
            bar.set_message(format!(
                "fitting: round {}, target→surface RMS {:.3e}·d max {:.3e}·d",
                it.iteration,
                it.rms_target_to_surface / d,
                it.max_target_to_surface / d
            ));
        })
    };
    let fit_options = FitOptions {
        surface: options,
        iterations: args.iterations,
        smoothness: args.smoothness,
        tolerance: args.tolerance,
        min_improvement: args.min_improvement,
        max_time: args.max_time,
        method,
        loss,
        observer,
        ..FitOptions::default()
    };
    // Every number is checked before any work (the library checks again).
    fit_options.validate().map_err(|e| bad_input(anyhow!("{e}")))?;
    let result = fit(&target, &control, &fit_options);
    bar.finish_and_clear();
    // The library's messages name the command already ("fit: …").
    let result = result.map_err(|e| bad_input(anyhow!("{e}")))?;
    outputs.stage_mesh("--output", &args.output, &result.mesh, false)?;
    if let Some(path) = &args.report {
        let report = serde_json::json!({
            "target": args.target.display().to_string(),
            "control": args.control.display().to_string(),
            "scheme": options.scheme.name(),
            "target_points": target.points.len(),
            "target_triangles": target.triangles.len(),
            "scale": result.iterations.first().map_or(0.0, |i| i.scale),
            "method": method.name(),
            "loss": loss.name(),
            "parameters": {
                "iterations": args.iterations,
                "smoothness": args.smoothness,
                "tolerance": args.tolerance,
                "min_improvement": args.min_improvement,
                "max_time": args.max_time,
                "lambda": args.lambda,
            },
            "stop": result.stop.name(),
            "regularised": {"count": result.regularised.len(), "vertices": result.regularised},
            "iterations": result.iterations.iter().map(iteration_json).collect::<Vec<_>>(),
            "total_ms": start.elapsed().as_secs_f64() * 1e3,
        });
        let text = serde_json::to_string_pretty(&report).map_err(|e| Failure::Other(e.into()))?;
        outputs.stage_bytes(path, (text + "\n").as_bytes())?;
    }
    outputs.commit()?;
    if let (Some(first), Some(last)) = (result.iterations.first(), result.iterations.last()) {
        let d = first.scale.max(f64::MIN_POSITIVE);
        crate::progress::summary(format!(
            "fit: {} rounds ({}, stopped: {}), target→surface RMS {:.3e}·d max {:.3e}·d (start {:.3e}·d, {:.3e}·d), surface→target RMS {:.3e}·d max {:.3e}·d{}",
            last.iteration,
            method.name(),
            result.stop.name(),
            last.rms_target_to_surface / d,
            last.max_target_to_surface / d,
            first.rms_target_to_surface / d,
            first.max_target_to_surface / d,
            last.rms_surface_to_target / d,
            last.max_surface_to_target / d,
            regularised_note(&result.regularised),
        ));
    }
    Ok(())
}

/// ", 3 control vertices regularised (low target support: 4, 9, 17)", or "".
fn regularised_note(list: &[u32]) -> String {
    if list.is_empty() {
        return String::new();
    }
    let shown: Vec<String> = list.iter().take(12).map(u32::to_string).collect();
    let more = if list.len() > 12 { ", …" } else { "" };
    format!("; {} control vertices regularised (little or no target support: {}{more})", list.len(), shown.join(", "))
}
