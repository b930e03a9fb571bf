//! `subdiv evaluate MESH --scheme S --at PARAMS -o OUT [--derivs]`: the limit
//! surface at given parameters (subdiv-eval).
//!
//! PARAMS: one parameter per line, `FACE U V` (a quad under Catmull-Clark, a
//! triangle under Loop) or `FACE.K U V` (sub-domain K: the ptex quad at
//! corner K of a Catmull-Clark n-gon, the corner K of a Doo-Sabin face);
//! `#` starts a comment, blank lines are skipped. OUT: one line per
//! parameter, `x y z nx ny nz`, with `--derivs` also `dxu dyu dzu dxv dyv
//! dzv`, numbers in the shortest form that reads back to the same f64.

use crate::failure::{bad_input, budget, over_budget, Failure};
use crate::load::{load_tagged_mesh, TagArgs};
use crate::outputs::Outputs;
use crate::subdivide::{beta_parser, evaluated_scheme, scheme_parser, SurfaceArgs};
use anyhow::anyhow;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use subdiv_eval::{EvalError, LimitSurface, SurfaceParam};
use subdiv_stencil::Scheme;

/// Arguments of `subdiv evaluate`.
#[derive(clap::Args, Debug)]
pub struct EvaluateArgs {
    /// Control mesh.
    mesh: PathBuf,
    /// Subdivision scheme (catmull-clark, loop, doo-sabin).
    #[arg(long, value_parser = scheme_parser, help = format!("Subdivision scheme: {}", crate::options::scheme_names()))]
    scheme: Scheme,
    /// Parameters: one `FACE U V` or `FACE.K U V` per line (`#` comments).
    #[arg(long, value_name = "PARAMS")]
    at: PathBuf,
    /// Also write ∂S/∂u and ∂S/∂v.
    #[arg(long)]
    derivs: bool,
    /// Loop's β: loop (default, OpenSubdiv's) or warren.
    #[arg(long, value_parser = beta_parser)]
    beta: Option<subdiv_stencil::LoopBeta>,
    /// Boundary and crease options.
    #[command(flatten)]
    surface: SurfaceArgs,
    /// Tags besides the file's own: a tag file, feature edges by angle.
    #[command(flatten)]
    tags: TagArgs,
    /// Output text file.
    #[arg(short, long)]
    output: PathBuf,
    /// Memory budget of the evaluation, in bytes (suffixes K, M, G, T; default ¾ of the memory
    /// available). More parameters are refused with exit 2.
    #[arg(long, value_name = "BYTES", value_parser = subdiv::budget::parse_bytes)]
    max_memory: Option<u64>,
}

/// Bytes held per parameter line: the parsed line, the parameter, the sample and the output
/// line (at most 25 characters a number, 6 numbers or 12 with `--derivs`).
fn bytes_per_line(derivs: bool) -> u64 {
    let numbers = if derivs { 12 } else { 6 };
    (std::mem::size_of::<Line>()
        + std::mem::size_of::<SurfaceParam>()
        + std::mem::size_of::<subdiv_eval::LimitSample>()) as u64
        + 25 * numbers
}

/// A parameter line: the domain given (`K` when written) and (u, v).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Line {
    face: u32,
    corner: Option<u32>,
    u: f64,
    v: f64,
    number: usize,
}

/// Parses the parameter file's text (errors name the line).
fn parse(text: &str, file: &Path) -> Result<Vec<Line>, Failure> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let number = i + 1;
        let content = raw.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let bad = |what: String| bad_input(anyhow!("{}:{number}: {what}", file.display()));
        let tokens: Vec<&str> = content.split_whitespace().collect();
        if tokens.len() != 3 {
            return Err(bad(format!("expected `FACE U V` or `FACE.K U V`, found {} fields", tokens.len())));
        }
        let (face, corner) = match tokens[0].split_once('.') {
            Some((f, k)) => (f, Some(k)),
            None => (tokens[0], None),
        };
        let face: u32 = face.parse().map_err(|_| bad(format!("face `{face}` is not a face index")))?;
        let corner = match corner {
            Some(k) => Some(k.parse::<u32>().map_err(|_| bad(format!("corner `{k}` is not an index")))?),
            None => None,
        };
        let number_of = |t: &str| t.parse::<f64>().map_err(|_| bad(format!("`{t}` is not a number")));
        let (u, v) = (number_of(tokens[1])?, number_of(tokens[2])?);
        out.push(Line { face, corner, u, v, number });
    }
    Ok(out)
}

/// Runs `subdiv evaluate`.
pub fn run(args: &EvaluateArgs) -> Result<(), Failure> {
    let scheme = evaluated_scheme(args.scheme, args.beta)?;
    let mut outputs = Outputs::new([args.mesh.as_path(), args.at.as_path()].into_iter().chain(args.tags.files()));
    outputs.other("--output", &args.output)?;
    let mesh = load_tagged_mesh(&args.mesh, &args.tags)?;
    let text = crate::load::read_text(&args.at)?;
    // Sized before the lines are parsed: at most one parameter a line.
    let lines = u64::try_from(text.lines().count()).ok();
    let what = format!("--at {}", args.at.display());
    budget(args.max_memory)
        .check_items(&what, lines, "parameter lines", bytes_per_line(args.derivs), "split the parameter file")
        .map_err(over_budget)?;
    let lines = parse(&text, &args.at)?;
    drop(text);
    let input = args.mesh.display();
    let surface =
        LimitSurface::new(&mesh, &args.surface.options(scheme)).map_err(|e| bad_input(anyhow!("{input}: {e}")))?;
    let mut params = Vec::with_capacity(lines.len());
    for line in &lines {
        let domains = surface.face_domains(line.face);
        let corner = match (line.corner, domains.len()) {
            (Some(k), _) => k,
            (None, 1) => 0,
            (None, 0) => {
                let e = EvalError::NoSuchDomain { face: line.face, corner: 0 };
                return Err(bad_input(anyhow!("{}:{}: {e}", args.at.display(), line.number)));
            }
            (None, n) => {
                return Err(bad_input(anyhow!(
                    "{}:{}: face {} has {n} domains (one per corner); give FACE.K with K in 0..{n}",
                    args.at.display(),
                    line.number,
                    line.face
                )))
            }
        };
        params.push(SurfaceParam::new(line.face, corner, line.u, line.v));
    }
    // Evaluated on the normalised positions and mapped back (the numeric rule).
    let samples = surface.evaluate_all(mesh.positions(), &params).map_err(|(i, e)| {
        let number = lines.get(i).map_or(0, |l| l.number);
        bad_input(anyhow!("{}:{number}: {e}", args.at.display()))
    })?;
    let mut out = String::new();
    out.try_reserve(lines.len() * if args.derivs { 240 } else { 120 })
        .map_err(|_| bad_input(anyhow!("{what}: the output of {} lines does not fit in memory", lines.len())))?;
    for (line, s) in lines.iter().zip(&samples) {
        let mut values = vec![s.position, s.normal];
        if args.derivs {
            values.extend([s.du, s.dv]);
        }
        if values.iter().any(|p| !p.is_finite()) {
            return Err(Failure::NotConverged(anyhow!(
                "{}:{}: the limit surface there is not representable in f64 (beyond ±1.8e308); nothing written",
                args.at.display(),
                line.number
            )));
        }
        for (i, c) in values.iter().flat_map(|p| p.to_array()).enumerate() {
            if i > 0 {
                out.push(' ');
            }
            // `{:?}`: the shortest decimal that reads back to the same bits
            // (the layout of subdiv-io's writers).
            let _ = write!(out, "{c:?}");
        }
        out.push('\n');
    }
    outputs.stage_bytes(&args.output, out.as_bytes())?;
    outputs.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_faces_corners_comments_and_names_bad_lines() {
        let file = Path::new("p.txt");
        let lines = parse("# header\n\n3 0.5 0.25  # trailing\n7.2 1 0\n", file).unwrap();
        assert_eq!(lines.len(), 2);
        assert_eq!((lines[0].face, lines[0].corner, lines[0].u, lines[0].v, lines[0].number), (3, None, 0.5, 0.25, 3));
        assert_eq!((lines[1].face, lines[1].corner), (7, Some(2)));
        for (text, needle) in [
            ("1 2\n", ":1: expected"),
            ("\nx 0 0\n", ":2: face `x`"),
            ("1.y 0 0", "corner `y`"),
            ("1 a 0", "`a` is not"),
        ] {
            let Err(Failure::BadInput(e)) = parse(text, file) else { panic!("{text}") };
            assert!(e.to_string().contains(needle), "{e}");
        }
    }
}
