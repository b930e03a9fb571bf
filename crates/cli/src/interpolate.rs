//! `subdiv interpolate MESH --method M [...]` (SPEC §6).

use crate::failure::{bad_input, Failure};
use crate::load::load_mesh;
use crate::params;
use crate::subdivide::{BetaArg, TensionArgs};
use anyhow::anyhow;
use clap::ValueEnum;
use serde_json::json;
use std::path::{Path, PathBuf};
use std::time::Instant;
use subdiv_interp::{
    cheng, deng_ma, deng_wang, fan_cheng_lai, nasri, zheng_cai, ChengOptions, CommonOptions, DengMaOptions,
    DengWangOptions, FanChengLaiOptions, InterpError, Interpolant, NasriOptions, Shape, SolverChoice, ZhengCaiOptions,
};
use subdiv_io::MeshView;
use subdiv_mesh::Mesh;
use subdiv_solve::Solver;
use subdiv_stencil::LoopBeta;

/// Method names on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MethodArg {
    /// Nasri 1987: Doo-Sabin, global system C·M⁰ = P.
    Nasri,
    /// Zheng & Cai 2005: Doo-Sabin, a few Gauss-Seidel sweeps + exact perturbation of M¹.
    ZhengCai,
    /// Cheng et al.: Catmull-Clark, A·M̂ = P.
    Cheng,
    /// Fan, Cheng & Lai: two-phase Doo-Sabin with per-face shape λ.
    FanChengLai,
    /// Deng & Wang 2010: Loop, explicit modified first step.
    DengWang,
    /// Deng & Ma 2011: interpolatory scheme (writes the refined surface).
    DengMa,
}

/// Arguments of `subdiv interpolate`.
#[derive(clap::Args, Debug)]
pub struct InterpolateArgs {
    /// Input mesh: its vertices are the data to interpolate.
    mesh: PathBuf,
    /// Interpolation method.
    #[arg(long, value_enum)]
    method: MethodArg,
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
    /// deng-wang: Loop's β.
    #[arg(long, value_enum, default_value = "warren")]
    beta: BetaArg,
    /// deng-ma: the tension.
    #[command(flatten)]
    tension: TensionArgs,
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
    /// Write the JSON report (SPEC §6).
    #[arg(long)]
    report: Option<PathBuf>,
}

fn solver_choice(name: &str) -> Result<SolverChoice, Failure> {
    if name == "auto" {
        return Ok(SolverChoice::Auto);
    }
    let s: Solver = name.parse().map_err(|_| bad_input(anyhow!("--solver: unknown solver '{name}'")))?;
    Ok(SolverChoice::Use(s))
}

fn check_applies(args: &InterpolateArgs) -> Result<(), Failure> {
    use MethodArg::*;
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
    if !(args.tol > 0.0 && args.tol.is_finite()) {
        return Err(bad_input(anyhow!("--tol must be positive, got {}", args.tol)));
    }
    Ok(())
}

fn run_method(args: &InterpolateArgs, mesh: &Mesh) -> Result<Interpolant, Failure> {
    let n = mesh.topology().vertex_count();
    let subset = args.subset.as_deref().map(|p| params::subset(p, n)).transpose().map_err(bad_input)?;
    let common = CommonOptions { subset, tol: args.tol, max_iter: args.max_iter, solver: solver_choice(&args.solver)? };
    let normals = args.normals.as_deref().map(|p| params::normals(p, n)).transpose().map_err(bad_input)?;
    let beta: LoopBeta = args.beta.into();
    let result = match args.method {
        MethodArg::Nasri => nasri::interpolate(mesh, &NasriOptions { common }),
        MethodArg::Cheng => cheng::interpolate(mesh, &ChengOptions { common }),
        MethodArg::ZhengCai => {
            let handles = args.handles.as_deref().map(|p| params::handles(p, n)).transpose().map_err(bad_input)?;
            let opts = ZhengCaiOptions { common, ite_max: args.ite_max, eps: args.eps, normals, handles };
            zheng_cai::interpolate(mesh, &opts)
        }
        MethodArg::FanChengLai => {
            let shape = match (&args.shape, &args.shape_file) {
                (_, Some(file)) => Shape::PerFace(params::shape_file(file, mesh).map_err(bad_input)?),
                (Some(l), None) => Shape::Uniform(*l),
                (None, None) => Shape::default(),
            };
            fan_cheng_lai::interpolate(mesh, &FanChengLaiOptions { common, shape })
        }
        MethodArg::DengWang => deng_wang::interpolate(mesh, &DengWangOptions { common, mu: args.mu, beta, normals }),
        MethodArg::DengMa => deng_ma::interpolate(mesh, &DengMaOptions { tension: args.tension.tension() }),
    };
    result.map_err(|e| classify(&args.mesh, e))
}

/// Exit 3 when the solver did not get there (with the error reached), 2 otherwise.
fn classify(input: &Path, e: InterpError) -> Failure {
    let error = anyhow!("{}: {e}", input.display());
    if e.is_not_converged() {
        Failure::NotConverged(error)
    } else {
        Failure::BadInput(error)
    }
}

fn write(path: &Path, mesh: &Mesh, normals: bool) -> Result<(), Failure> {
    let n = normals.then(|| mesh.vertex_normals());
    let mut view = MeshView::new(mesh.positions(), mesh.topology().faces());
    if let Some(n) = &n {
        view = view.with_normals(n);
    }
    subdiv_io::write_mesh(path, view).map_err(|e| Failure::Other(e.into()))
}

/// Runs `subdiv interpolate`.
pub fn run(args: &InterpolateArgs) -> Result<(), Failure> {
    let total = Instant::now();
    check_applies(args)?;
    let mesh = load_mesh(&args.mesh)?;
    let result = run_method(args, &mesh)?;
    let d = mesh.bbox_diagonal();
    let n = mesh.topology().vertex_count();
    let interpolated = match &args.subset {
        Some(p) => {
            let mut flags = vec![false; n];
            for v in params::subset(p, n).map_err(bad_input)? {
                flags[v as usize] = true;
            }
            flags
        }
        None => vec![true; n],
    };
    // Build every output before writing any, so a failure leaves no file.
    let is_deng_ma = args.method == MethodArg::DengMa;
    let control_out = if is_deng_ma {
        result.surface(args.levels).map_err(|e| classify(&args.mesh, e))?
    } else {
        result.control.clone()
    };
    let surface =
        args.surface.as_ref().map(|_| result.surface(args.levels)).transpose().map_err(|e| classify(&args.mesh, e))?;
    if let Some(path) = &args.output {
        write(path, &control_out, is_deng_ma)?;
    }
    if let (Some(path), Some(s)) = (&args.surface, &surface) {
        write(path, s, true)?;
    }
    // The error, measured from the control mesh as written (SPEC §1, §6).
    let measured = measured_interpolant(&result, args.output.as_deref(), is_deng_ma);
    let error = measured.error(mesh.positions(), &interpolated, d);
    let total_ms = total.elapsed().as_secs_f64() * 1e3;
    let solve = result.solve.clone().unwrap_or_default();
    let report = json!({
        "method": args_method_name(args.method),
        "control_scheme": result.scheme.report_name(),
        "input": {"file": args.mesh.display().to_string(), "vertices": n, "faces": mesh.topology().face_count(), "bbox_diagonal": d},
        "control": {"vertices": control_out.topology().vertex_count(), "faces": control_out.topology().face_count()},
        "solver": {
            "name": if result.solve.is_some() { json!(solve.solver) } else { json!(null) },
            "iterations": solve.iterations,
            "converged": result.solve.as_ref().is_none_or(|s| s.converged),
            "matvecs": solve.matvecs,
            "residual": solve.residual,
            "residual_history": solve.history,
        },
        "error": {"max_rel": error.max_rel, "mean_rel": error.mean_rel, "max_abs": error.max_abs, "mean_abs": error.mean_abs, "vertices": error.count},
        "timing_ms": {"setup": result.setup_seconds * 1e3, "solve": result.solve_seconds * 1e3, "total": total_ms},
        "parameters": result.parameters,
        "warnings": result.warnings,
    });
    for w in &result.warnings {
        eprintln!("subdiv: warning: {w}");
    }
    if let Some(path) = &args.report {
        let text = serde_json::to_string_pretty(&report).map_err(|e| Failure::Other(e.into()))?;
        std::fs::write(path, text + "\n").map_err(|e| Failure::Other(anyhow!("{}: {e}", path.display())))?;
    }
    println!(
        "{}: {} vertices interpolated, max error {:.3e}·d (mean {:.3e}·d), {} iterations, {:.1} ms",
        args_method_name(args.method),
        error.count,
        error.max_rel,
        error.mean_rel,
        solve.iterations,
        total_ms
    );
    Ok(())
}

fn args_method_name(m: MethodArg) -> &'static str {
    let method = match m {
        MethodArg::Nasri => subdiv_interp::Method::Nasri,
        MethodArg::ZhengCai => subdiv_interp::Method::ZhengCai,
        MethodArg::Cheng => subdiv_interp::Method::Cheng,
        MethodArg::FanChengLai => subdiv_interp::Method::FanChengLai,
        MethodArg::DengWang => subdiv_interp::Method::DengWang,
        MethodArg::DengMa => subdiv_interp::Method::DengMa,
    };
    method.name()
}

/// The interpolant with the control positions read back from the written file
/// when the format keeps vertices (so the report measures what was written).
fn measured_interpolant(result: &Interpolant, written: Option<&Path>, is_deng_ma: bool) -> Interpolant {
    let Some(path) = written.filter(|_| !is_deng_ma) else { return result.clone() };
    match subdiv_io::read_mesh(path) {
        Ok(soup)
            if soup.positions.len() == result.control.topology().vertex_count()
                && soup.faces == *result.control.topology().faces() =>
        {
            let mut copy = result.clone();
            copy.control = result.control.with_positions(soup.positions);
            copy
        }
        _ => result.clone(),
    }
}
