//! `subdiv subdivide MESH --scheme S --levels N [--limit] [...] -o OUT`: the flags given become
//! the options of [`subdiv::job::run::subdivide`]; and the surface options, scheme and β of the
//! evaluation commands (`evaluate`, `sample`, `project`, `fit`).

use crate::failure::Failure;
use crate::options::{named, SubdivideFlags};
use crate::progress;
use std::path::PathBuf;
use subdiv::job::{Command, SubdivideOptions};
use subdiv_stencil::{
    BoundaryInterpolation, CreaseMethod, DartLimit, FVarInterpolation, LoopBeta, Options, Scheme, TriangleRule,
};

/// OpenSubdiv's surface options on the command line of the evaluation commands.
#[derive(clap::Args, Debug)]
pub struct SurfaceArgs {
    /// Boundary interpolation (OpenSubdiv): edge-and-corner (boundary curves, one-face corners
    /// kept), edge-only (boundary curves, corners rounded), none (as edge-only; OpenSubdiv's
    /// boundary holes).
    #[arg(long, default_value = "edge-and-corner", value_parser = named::<BoundaryInterpolation>)]
    pub boundary: BoundaryInterpolation,
    /// How semi-sharp creases decay per level: uniform (s − 1) or chaikin (averaged with the
    /// other semi-sharp edges at each end).
    #[arg(long, default_value = "uniform", value_parser = named::<CreaseMethod>)]
    pub crease_method: CreaseMethod,
    /// Face-varying interpolation of the texture coordinates (OpenSubdiv): linear-all (bilinear),
    /// linear-boundaries, linear-corners-plus2, linear-corners-plus1, linear-corners-only,
    /// linear-none (smooth everywhere, seams as boundaries).
    #[arg(long, default_value = "linear-all", value_parser = named::<FVarInterpolation>)]
    pub fvar: FVarInterpolation,
    /// Catmull-Clark's rule for triangles: catmark, or smooth (OpenSubdiv's TRI_SUB_SMOOTH).
    #[arg(long, default_value = "catmark", value_parser = named::<TriangleRule>)]
    pub triangle_rule: TriangleRule,
    /// Which limit point a dart gets: exact (the limit of refinement, what patch evaluators show)
    /// or smooth-mask (OpenSubdiv's limit-stencil shortcut).
    #[arg(long, default_value = "exact", value_parser = named::<DartLimit>)]
    pub dart_limit: DartLimit,
}

impl SurfaceArgs {
    /// The options for `scheme`.
    pub fn options(&self, scheme: Scheme) -> Options {
        Options::new(scheme)
            .with_boundary(self.boundary)
            .with_crease_method(self.crease_method)
            .with_fvar(self.fvar)
            .with_triangle_rule(self.triangle_rule)
            .with_dart_limit(self.dart_limit)
    }
}

/// `--scheme` of the evaluation commands: a name of the scheme table.
pub fn scheme_parser(s: &str) -> Result<Scheme, String> {
    s.parse().map_err(|e: subdiv_stencil::StencilError| e.to_string())
}

/// `--beta`: Loop's β by name.
pub fn beta_parser(s: &str) -> Result<LoopBeta, String> {
    s.parse()
}

/// Arguments of `subdiv subdivide`.
#[derive(clap::Args, Debug)]
pub struct SubdivideArgs {
    /// Input mesh.
    mesh: PathBuf,
    /// The scheme and its options.
    #[command(flatten)]
    flags: SubdivideFlags,
    /// Output mesh (format by extension).
    #[arg(short, long)]
    output: PathBuf,
}

/// Runs `subdiv subdivide`.
pub fn run(args: &SubdivideArgs) -> Result<(), Failure> {
    let Command::Subdivide(options) = Command::from_json("subdivide", &args.flags.to_json())? else {
        unreachable!("a subdivide command parses as one")
    };
    let options: SubdivideOptions = options;
    subdiv::job::run::subdivide(&args.mesh, &options, &args.output, &mut progress::Terminal::default())?;
    Ok(())
}

/// The scheme of an evaluation command (`evaluate`, `sample`, `project`, `fit`) with Loop's β
/// when given; refused (exit 2) when the scheme has no limit evaluation (the scheme table's
/// `evaluable`) or β is given for another scheme.
pub fn evaluated_scheme(scheme: Scheme, beta: Option<LoopBeta>) -> Result<Scheme, Failure> {
    if !scheme.traits().evaluable {
        return Err(subdiv::job::JobError::bad_input(format!(
            "--scheme {scheme}: no limit evaluation for this scheme (deng-ma is interpolatory: its refined vertices \
             are the surface; use subdivide)"
        ))
        .into());
    }
    scheme.with_parameters(beta, None).map_err(|e| subdiv::job::JobError::bad_input(e.to_string()).into())
}
