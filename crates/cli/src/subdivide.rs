//! `subdiv subdivide MESH --scheme S --levels N [--limit] [...] -o OUT`: the flags given become
//! the options of [`subdiv::job::run::subdivide`]; and the surface options, scheme and β of the
//! evaluation commands (`evaluate`, `sample`, `project`, `fit`).

use crate::failure::Failure;
use crate::options::{named, SubdivideFlags};
use crate::progress;
use std::path::PathBuf;
use subdiv::job::{Command, SubdivideOptions};
use subdiv_stencil::{BoundaryInterpolation, CreaseMethod, FVarInterpolation, LoopBeta, Options, Scheme};

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
}

impl SurfaceArgs {
    /// The options for `scheme`.
    pub fn options(&self, scheme: Scheme) -> Options {
        Options::new(scheme).with_boundary(self.boundary).with_crease_method(self.crease_method).with_fvar(self.fvar)
    }
}

/// `--scheme` of the evaluation commands: a name of the scheme table.
pub fn scheme_parser(s: &str) -> Result<Scheme, String> {
    s.parse()
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

/// The scheme of an evaluation command (`evaluate`, `sample`, `project`, `fit`) with Loop's β;
/// refused (exit 2) when the scheme has no limit evaluation.
pub fn evaluated_scheme(scheme: Scheme, beta: LoopBeta) -> Result<Scheme, Failure> {
    match scheme {
        Scheme::Loop(_) => Ok(Scheme::Loop(beta)),
        Scheme::CatmullClark | Scheme::DooSabin => Ok(scheme),
        Scheme::DengMa(_) => Err(subdiv::job::JobError::bad_input(
            "--scheme deng-ma: the scheme is interpolatory and has no limit evaluation; its refined vertices are the \
             surface (use subdivide)",
        )
        .into()),
    }
}
