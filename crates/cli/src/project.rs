//! `subdiv project MESH --scheme S --points Q.(xyz|ply|obj|off) -o OUT`: the
//! closest point of the limit surface to every query, one line each:
//! `FACE U V x y z distance` (`FACE.K` for the sub-domain K of a face with
//! several, as `evaluate` reads them).

use crate::failure::{bad_input, budget, over_budget, Failure};
use crate::outputs::Outputs;
use crate::sample::LimitArgs;
use anyhow::anyhow;
use glam::DVec3;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use subdiv_eval::{project_on, Domain, ProjectOptions, Projection};

/// Arguments of `subdiv project`.
#[derive(clap::Args, Debug)]
pub struct ProjectArgs {
    /// Control mesh.
    mesh: PathBuf,
    /// The limit surface.
    #[command(flatten)]
    limit: LimitArgs,
    /// Query points: .xyz (one `x y z` per line, further columns ignored, `#` comments), or the
    /// vertices of a mesh or point cloud file (.ply, .obj, .off, …).
    #[arg(long)]
    points: PathBuf,
    /// Output text file, one `FACE U V x y z distance` line per query (shortest round-trip decimals).
    #[arg(short, long)]
    output: PathBuf,
    /// Memory budget of the projection, in bytes (suffixes K, M, G, T; default ¾ of the memory
    /// available). More query points are refused with exit 2.
    #[arg(long, value_name = "BYTES", value_parser = subdiv::budget::parse_bytes)]
    max_memory: Option<u64>,
}

/// Bytes held per query: the point, its scaled copy, the projection and the output line (at most
/// 25 characters a number, 7 numbers and a domain).
const BYTES_PER_QUERY: u64 = (2 * std::mem::size_of::<DVec3>() + std::mem::size_of::<Projection>()) as u64 + 200;

/// Reads query points: `.xyz` text, or any mesh file's vertices; at most what `budget` holds
/// ([`BYTES_PER_QUERY`] each).
pub fn read_points(path: &Path, budget: &subdiv::budget::MemoryBudget) -> Result<Vec<DVec3>, Failure> {
    let is_xyz = path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("xyz"));
    let what = format!("--points {}", path.display());
    let check = |count: usize| {
        budget
            .check_items(&what, u64::try_from(count).ok(), "query points", BYTES_PER_QUERY, "split the query file")
            .map_err(over_budget)
    };
    if !is_xyz {
        let points = crate::load::read_soup(path)?.positions;
        check(points.len())?;
        return Ok(points);
    }
    let text = crate::load::read_text(path)?;
    // Sized before the lines are parsed: at most one point a line.
    check(text.lines().count())?;
    let mut points = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let mut xyz = [0.0; 3];
        let mut fields = line.split_whitespace();
        for c in &mut xyz {
            let field = fields.next().ok_or_else(|| {
                bad_input(anyhow!("{}:{}: expected three coordinates `x y z`", path.display(), k + 1))
            })?;
            *c =
                field.parse::<f64>().ok().filter(|x| x.is_finite()).ok_or_else(|| {
                    bad_input(anyhow!("{}:{}: '{field}' is not a finite number", path.display(), k + 1))
                })?;
        }
        points.push(DVec3::from_array(xyz));
    }
    Ok(points)
}

/// `f` for a face with one domain, `f.K` otherwise.
pub fn domain_name(domain: Domain, domains_of_face: &[u32]) -> String {
    if domains_of_face[domain.face as usize] > 1 {
        format!("{}.{}", domain.face, domain.corner)
    } else {
        domain.face.to_string()
    }
}

/// Domains per face.
pub fn domain_counts(domains: &[Domain], faces: usize) -> Vec<u32> {
    let mut count = vec![0u32; faces];
    for d in domains {
        count[d.face as usize] += 1;
    }
    count
}

/// Runs `subdiv project`.
pub fn run(args: &ProjectArgs) -> Result<(), Failure> {
    let inputs = [args.mesh.as_path(), args.points.as_path()];
    let mut outputs = Outputs::new(inputs.into_iter().chain(args.limit.tags.files()));
    outputs.other("--output", &args.output)?;
    let queries = read_points(&args.points, &budget(args.max_memory))?;
    let (mesh, options, surface) = args.limit.load(&args.mesh)?;
    let shown = args.mesh.display();
    let bar = crate::progress::spinner(format!("projecting {} points", queries.len()));
    // On the normalised mesh and queries, mapped back (the numeric rule).
    let found = project_on(&surface, &mesh, &options, &queries, &ProjectOptions::default());
    bar.finish_and_clear();
    let found = found.map_err(|e| bad_input(anyhow!("{shown}: {e}")))?;
    if let Some(k) = found.iter().position(|p| !(p.position.is_finite() && p.distance.is_finite())) {
        return Err(Failure::NotConverged(anyhow!(
            "{}: query {k}: its closest point or distance is not representable in f64 (beyond ±1.8e308 at the \
             mesh's scale); nothing written",
            args.points.display()
        )));
    }
    let counts = domain_counts(surface.domains(), mesh.topology().face_count());
    let mut text = String::with_capacity(80 * found.len());
    for p in &found {
        let d = subdiv_eval::Domain { face: p.param.face, corner: p.param.corner };
        let x = p.position;
        let _ = writeln!(
            text,
            "{} {:?} {:?} {:?} {:?} {:?} {:?}",
            domain_name(d, &counts),
            p.param.u,
            p.param.v,
            x.x,
            x.y,
            x.z,
            p.distance
        );
    }
    outputs.stage_bytes(&args.output, text.as_bytes())?;
    outputs.commit()?;
    let max = found.iter().map(|p| p.distance).fold(0.0f64, f64::max);
    crate::progress::summary(format!("project: {} points, max distance {max:.6e}", found.len()));
    Ok(())
}
