//! `subdiv subdivide MESH --scheme S --levels N [--limit] [--beta B]
//! [--boundary B] [--crease-method M] -o OUT`.

use crate::budget::{refused, MemoryArgs};
use crate::failure::{bad_input, Failure};
use crate::load::{load_tagged_mesh, TagArgs};
use crate::outputs::Outputs;
use crate::progress;
use anyhow::anyhow;
use clap::ValueEnum;
use std::path::PathBuf;
use subdiv_mesh::Mesh;
use subdiv_stencil::{
    BoundaryInterpolation, CreaseMethod, FVarInterpolation, LoopBeta, Options, Scheme, StencilError, Tension,
};

/// A value parser for the option enums that name their values (`FromStr`).
pub fn named<T: std::str::FromStr<Err = String>>(s: &str) -> Result<T, String> {
    s.parse()
}

/// OpenSubdiv's surface options on the command line, shared by `subdivide`
/// and `interpolate`.
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

/// Scheme names on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SchemeArg {
    /// Doo-Sabin (any polygons; Chaikin boundary).
    DooSabin,
    /// Catmull-Clark (any polygons; OpenSubdiv EDGE_AND_CORNER boundary).
    CatmullClark,
    /// Loop (triangles; same boundary rule).
    Loop,
    /// Deng-Ma interpolatory scheme (any polygons, open or closed; 4-point boundary curves).
    DengMa,
}

/// Loop's β.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BetaArg {
    /// Warren: 3/16 (k = 3), 3/(8k) (k > 3).
    Warren,
    /// Loop's original (1/k)[5/8 − (3/8 + ¼cos(2π/k))²].
    Loop,
}

impl From<BetaArg> for LoopBeta {
    fn from(b: BetaArg) -> Self {
        match b {
            BetaArg::Warren => LoopBeta::Warren,
            BetaArg::Loop => LoopBeta::Loop,
        }
    }
}

/// Deng-Ma's tension flags, shared by `subdivide` and `interpolate`.
#[derive(clap::Args, Debug)]
pub struct TensionArgs {
    /// Deng-Ma: global tension ω ∈ (0, 1] (default 1).
    #[arg(long, conflicts_with = "variable_tension")]
    omega: Option<f64>,
    /// Deng-Ma: displacement-safe variable tension with this λ ∈ (0, 1] (report §3.4).
    #[arg(long)]
    variable_tension: Option<f64>,
}

impl TensionArgs {
    /// True when either flag was given.
    pub fn given(&self) -> bool {
        self.omega.is_some() || self.variable_tension.is_some()
    }
    /// The tension the flags ask for (global ω = 1 by default).
    pub fn tension(&self) -> Tension {
        match (self.omega, self.variable_tension) {
            (_, Some(lambda)) => Tension::Variable { lambda },
            (omega, None) => Tension::Global(omega.unwrap_or(1.0)),
        }
    }
}

/// Arguments of `subdiv subdivide`.
#[derive(clap::Args, Debug)]
pub struct SubdivideArgs {
    /// Input mesh.
    mesh: PathBuf,
    /// Subdivision scheme.
    #[arg(long, value_enum)]
    scheme: SchemeArg,
    /// Number of subdivision steps (0 with --limit: the input's limit positions).
    #[arg(long)]
    levels: usize,
    /// Move the final vertices to their limit positions (not for deng-ma, which interpolates).
    #[arg(long)]
    limit: bool,
    /// Loop's β.
    #[arg(long, value_enum, default_value = "warren")]
    beta: BetaArg,
    /// Deng-Ma's tension.
    #[command(flatten)]
    tension: TensionArgs,
    /// Boundary and crease options.
    #[command(flatten)]
    surface: SurfaceArgs,
    /// Tags besides the file's own: a tag file, feature edges by angle.
    #[command(flatten)]
    tags: TagArgs,
    /// Loop on a mesh with non-triangles: triangulate every face first (over its own corners,
    /// keeping the mesh manifold: quads along the shorter valid diagonal, larger faces by ear clipping).
    #[arg(long)]
    triangulate: bool,
    /// Write angle-weighted vertex normals (formats that store them).
    #[arg(long)]
    normals: bool,
    /// Output mesh (format by extension).
    #[arg(short, long)]
    output: PathBuf,
    /// Memory budget.
    #[command(flatten)]
    memory: MemoryArgs,
}

/// Runs `subdiv subdivide`.
pub fn run(args: &SubdivideArgs) -> Result<(), Failure> {
    let scheme = match args.scheme {
        SchemeArg::DooSabin => Scheme::DooSabin,
        SchemeArg::CatmullClark => Scheme::CatmullClark,
        SchemeArg::Loop => Scheme::Loop(args.beta.into()),
        SchemeArg::DengMa => Scheme::DengMa(args.tension.tension()),
    };
    if args.scheme != SchemeArg::DengMa && args.tension.given() {
        return Err(bad_input(anyhow!("--omega and --variable-tension apply to --scheme deng-ma only")));
    }
    if args.limit && args.scheme == SchemeArg::DengMa {
        return Err(bad_input(anyhow!(
            "--limit: the Deng-Ma scheme is interpolatory and has no limit mask; its refined vertices are the surface"
        )));
    }
    let mut outputs = Outputs::new(std::iter::once(args.mesh.as_path()).chain(args.tags.files()));
    let format = outputs.mesh("--output", &args.output)?;
    let mut mesh = load_tagged_mesh(&args.mesh, &args.tags)?;
    let input = args.mesh.display();
    if args.triangulate && args.scheme == SchemeArg::Loop {
        mesh = subdiv_mesh::triangulate(&mesh).map_err(|e| bad_input(anyhow!("{input}: --triangulate: {e}")))?.mesh;
    }
    // Normals and limit positions: one more array per vertex each.
    let vertex_arrays = u64::from(args.normals) + u64::from(args.limit);
    let budget = args.memory.budget();
    budget.check("subdivide", mesh.topology(), scheme, args.levels, vertex_arrays, Some(format)).map_err(refused)?;
    let refined = refine(&mesh, args.surface.options(scheme), args.levels, args.limit).map_err(|e| {
        let hint = match e {
            subdiv_stencil::StencilError::NotTriangles { .. } => " (or pass --triangulate)",
            subdiv_stencil::StencilError::TagsNotSupported { .. } => {
                " (catmull-clark and loop take every crease and corner tag, doo-sabin infinitely sharp ones)"
            }
            _ => "",
        };
        bad_input(anyhow!("{input}: {e}{hint}"))
    })?;
    outputs.stage_mesh("--output", &args.output, &refined, args.normals)?;
    outputs.commit()
}

/// `levels` steps with `options` ([`subdiv_stencil::subdivide_for_output`]:
/// each level's mesh carries its decayed tags to the next, then limit
/// positions) with a progress bar; texture coordinates the scheme cannot
/// refine (Doo-Sabin with seams or tags) are dropped with a warning.
pub fn refine(mesh: &Mesh, options: impl Into<Options>, levels: usize, limit: bool) -> Result<Mesh, StencilError> {
    let options = options.into();
    let bar = progress::steps(format!("{} subdivision", options.scheme.name()), levels as u64);
    let refined = subdiv_stencil::subdivide_for_output(mesh, options, levels, limit, |_| bar.inc(1));
    bar.finish_and_clear();
    let refined = refined?;
    if let Some(reason) = refined.uvs_dropped {
        progress::warn(format!("texture coordinates not written: {reason}"));
    }
    Ok(refined.mesh)
}
