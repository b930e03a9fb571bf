//! `subdiv sample MESH --scheme S (--per-face N | --count N) [--seed K] -o POINTS.ply`:
//! points with normals on the limit surface (a point cloud: PLY, OBJ or OFF
//! vertices with normals, no faces).

use crate::failure::{bad_input, budget, over_budget, Failure};
use crate::load::{load_tagged_mesh, TagArgs};
use crate::outputs::Outputs;
use crate::subdivide::{beta_parser, evaluated_scheme, scheme_parser, SurfaceArgs};
use anyhow::anyhow;
use std::path::{Path, PathBuf};
use subdiv_eval::{per_domain_count, sample_surface, LimitSurface, Sampling, SAMPLE_BYTES};
use subdiv_mesh::{FaceList, Mesh};
use subdiv_stencil::{Options, Scheme};

/// The limit surface on the command line (`sample`, `project`, `fit`): the
/// scheme, its options and the tags.
#[derive(clap::Args, Debug)]
pub struct LimitArgs {
    /// Subdivision scheme of the limit surface (deng-ma is interpolatory: no limit evaluation).
    #[arg(long, value_parser = scheme_parser, help = format!("Subdivision scheme: {}", crate::options::scheme_names()))]
    pub scheme: Scheme,
    /// Loop's β: loop (default, OpenSubdiv's) or warren.
    #[arg(long, value_parser = beta_parser)]
    pub beta: Option<subdiv_stencil::LoopBeta>,
    /// Boundary and crease options.
    #[command(flatten)]
    pub surface: SurfaceArgs,
    /// Tags besides the file's own.
    #[command(flatten)]
    pub tags: TagArgs,
}

impl LimitArgs {
    /// The surface options; Deng-Ma is refused.
    pub fn options(&self) -> Result<Options, Failure> {
        let scheme = evaluated_scheme(self.scheme, self.beta)?;
        Ok(self.surface.options(scheme))
    }

    /// Loads `path` with these tags and builds its limit surface.
    pub fn load(&self, path: &Path) -> Result<(Mesh, Options, LimitSurface), Failure> {
        let options = self.options()?;
        let mesh = load_tagged_mesh(path, &self.tags)?;
        let surface = LimitSurface::new(&mesh, &options).map_err(|e| bad_input(anyhow!("{}: {e}", path.display())))?;
        Ok((mesh, options, surface))
    }
}

/// Arguments of `subdiv sample`.
#[derive(clap::Args, Debug)]
pub struct SampleArgs {
    /// Control mesh.
    mesh: PathBuf,
    /// The limit surface.
    #[command(flatten)]
    limit: LimitArgs,
    /// Uniform in every domain: an N×N grid of cell centres per quad domain (the centroids of
    /// the N² sub-triangles of a Loop triangle).
    #[arg(long, value_name = "N", conflicts_with = "count", required_unless_present = "count")]
    per_face: Option<usize>,
    /// N points by area: the area is estimated from a tessellation (8×8 per domain), the
    /// tessellation's triangles drawn by systematic sampling of their cumulative area, each
    /// point uniform in its triangle; reproducible from --seed.
    #[arg(long, value_name = "N")]
    count: Option<usize>,
    /// Seed of --count's random stream.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Output point cloud with normals (.ply, .obj or .off).
    #[arg(short, long)]
    output: PathBuf,
    /// Memory budget of the samples, in bytes (suffixes K, M, G, T; default ¾ of the memory
    /// available). More samples are refused with exit 2.
    #[arg(long, value_name = "BYTES", value_parser = subdiv::budget::parse_bytes)]
    max_memory: Option<u64>,
}

/// Bytes the command holds per sample: the library's ([`SAMPLE_BYTES`]) and the positions and
/// normals handed to the writer.
const CLI_SAMPLE_BYTES: u64 = SAMPLE_BYTES + 48;

/// Runs `subdiv sample`.
pub fn run(args: &SampleArgs) -> Result<(), Failure> {
    let mut outputs = Outputs::new(std::iter::once(args.mesh.as_path()).chain(args.limit.tags.files()));
    let format = outputs.mesh("--output", &args.output)?;
    if !matches!(
        format,
        subdiv_io::Format::PlyAscii | subdiv_io::Format::PlyBinary | subdiv_io::Format::Obj | subdiv_io::Format::Off
    ) {
        return Err(bad_input(anyhow!(
            "--output {}: {format} cannot store a point cloud with normals; use .ply, .obj or .off",
            args.output.display()
        )));
    }
    let (mesh, _, surface) = args.limit.load(&args.mesh)?;
    // Sized before anything is allocated.
    let domains = surface.domains().len();
    let (how, count, flag) = match (args.per_face, args.count) {
        (Some(n), _) => (Sampling::PerDomain(n), per_domain_count(domains, n), "--per-face"),
        (None, Some(n)) => (Sampling::ByArea { count: n, seed: args.seed }, u64::try_from(n).ok(), "--count"),
        (None, None) => return Err(bad_input(anyhow!("give --per-face N or --count N"))),
    };
    let remedy = format!("use a smaller {flag}");
    budget(args.max_memory).check_items(flag, count, "samples", CLI_SAMPLE_BYTES, &remedy).map_err(over_budget)?;
    let samples = sample_surface(&surface, mesh.positions(), how)
        .map_err(|e| bad_input(anyhow!("{}: {e}", args.mesh.display())))?;
    let positions: Vec<_> = samples.iter().map(|s| s.position).collect();
    let normals: Vec<_> = samples.iter().map(|s| s.normal).collect();
    stage_cloud(&mut outputs, &args.output, format, &positions, &normals)?;
    outputs.commit()?;
    crate::progress::summary(format!("sample: {} points on {} domains", positions.len(), surface.domains().len()));
    Ok(())
}

/// Stages a point cloud with normals (a mesh file without faces).
pub fn stage_cloud(
    outputs: &mut Outputs,
    path: &Path,
    format: subdiv_io::Format,
    positions: &[glam::DVec3],
    normals: &[glam::DVec3],
) -> Result<(), Failure> {
    if positions.iter().chain(normals).any(|p| !p.is_finite()) {
        return Err(Failure::NotConverged(anyhow!(
            "{}: a point or normal is not finite; nothing written",
            path.display()
        )));
    }
    let faces = FaceList::new();
    let view = subdiv_io::MeshView::new(positions, &faces).with_normals(normals);
    let staged = subdiv_io::stage_mesh(path, view, format, &mut |_| {}).map_err(|e| match e {
        subdiv_io::IoError::Io { .. } => crate::failure::write_failed(e),
        other => bad_input(other),
    })?;
    outputs.stage(staged);
    Ok(())
}
