//! `subdiv info MESH [--json] [--strict]`: prints [`subdiv::info::Summary`]
//! (computed by the facade, shared with `subdiv batch info`) as text or JSON.

use crate::failure::{bad_input, Failure};
use anyhow::anyhow;
use std::collections::BTreeMap;
use std::path::PathBuf;
use subdiv::info::{summarize_soup, Summary};
use subdiv_interp::Method;

/// Arguments of `subdiv info`.
#[derive(clap::Args, Debug)]
pub struct InfoArgs {
    /// Mesh file (.obj, .off, .ply, .stl, .gltf, .glb, .usda, .usdc, .usd, .usdz). A USD file is
    /// described Mesh prim by Mesh prim (its path, scheme and tags).
    mesh: PathBuf,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// Treat warnings (isolated vertices, zero-area faces) as errors: exit 2.
    #[arg(long)]
    strict: bool,
}

/// Runs `subdiv info`.
pub fn run(args: &InfoArgs) -> Result<(), Failure> {
    if subdiv_io::Format::from_path(&args.mesh).is_ok_and(subdiv_io::Format::is_usd) {
        return run_usd(args);
    }
    let soup = crate::load::read_soup(&args.mesh)?;
    let file = args.mesh.display().to_string();
    let summary = summarize_soup(soup, Some(&file));
    if args.json {
        let text = serde_json::to_string_pretty(&summary).map_err(|e| Failure::Other(e.into()))?;
        crate::stdout::line(&text);
    } else {
        crate::stdout::line(print_text(&summary).trim_end());
    }
    if let Some(error) = &summary.error {
        return Err(bad_input(anyhow!("{file}: {error}")));
    }
    if args.strict && !summary.warnings.is_empty() {
        return Err(bad_input(anyhow!("{file}: {} (--strict)", summary.warnings.join("; "))));
    }
    Ok(())
}

/// `subdiv info` on a USD file: every Mesh prim's summary, with its prim path and scheme (JSON:
/// `{"file": …, "prims": [{"prim": …, "scheme": …, …summary}]}`).
fn run_usd(args: &InfoArgs) -> Result<(), Failure> {
    let file = args.mesh.display().to_string();
    let (scene, warnings) = subdiv_io::usd::read_scene(&args.mesh)
        .map_err(|e| Failure::from(subdiv::job::JobError::from_error(subdiv::job::ErrorKind::BadInput, &e)))?;
    for w in warnings {
        crate::progress::warn(w);
    }
    let mut failure = None;
    let mut prims = Vec::new();
    let mut text = String::new();
    for mesh in scene.meshes {
        let (prim, scheme) = (mesh.path.clone(), mesh.scheme);
        let label = format!("{file}:{prim}");
        let summary = summarize_soup(mesh.soup, Some(&file));
        if let Some(error) = &summary.error {
            failure.get_or_insert_with(|| format!("{label}: {error}"));
        } else if args.strict && !summary.warnings.is_empty() {
            failure.get_or_insert_with(|| format!("{label}: {} (--strict)", summary.warnings.join("; ")));
        }
        text.push_str(&format!("prim:                 {prim}\nscheme:               {scheme}\n"));
        text.push_str(&print_text(&summary));
        text.push('\n');
        let mut value = serde_json::to_value(&summary).map_err(|e| Failure::Other(e.into()))?;
        if let Some(object) = value.as_object_mut() {
            object.insert("prim".into(), prim.into());
            object.insert("scheme".into(), scheme.token().into());
        }
        prims.push(value);
    }
    if args.json {
        let value = serde_json::json!({ "file": file, "prims": prims });
        let text = serde_json::to_string_pretty(&value).map_err(|e| Failure::Other(e.into()))?;
        crate::stdout::line(&text);
    } else {
        crate::stdout::line(text.trim_end());
    }
    match failure {
        Some(message) => Err(bad_input(anyhow!("{message}"))),
        None => Ok(()),
    }
}

fn histogram(h: &BTreeMap<usize, usize>) -> String {
    let parts: Vec<String> = h.iter().map(|(k, n)| format!("{k}:{n}")).collect();
    if parts.is_empty() {
        "-".into()
    } else {
        parts.join(" ")
    }
}

/// A length for people: fixed point in the usual range, scientific outside it
/// (a diagonal of 1e-300 is not "0.000000").
fn length(x: f64) -> String {
    if x == 0.0 || (1e-3..1e7).contains(&x) {
        format!("{x:.6}")
    } else {
        format!("{x:.6e}")
    }
}

fn print_text(s: &Summary) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    // Writing to a String cannot fail.
    macro_rules! emit {
        ($($arg:tt)*) => {{ let _ = writeln!(out, $($arg)*); }};
    }
    let opt = |x: Option<String>| x.unwrap_or_else(|| "undefined".into());
    emit!("file:                 {}", s.file.as_deref().unwrap_or("-"));
    emit!("vertices:             {} ({} isolated)", s.vertices, s.isolated_vertices);
    emit!("faces:                {}", s.faces);
    emit!("edges:                {}", s.edges);
    emit!("face sizes:           {}", histogram(&s.face_sizes));
    emit!("valences:             {}", opt(s.valences.as_ref().map(histogram)));
    emit!(
        "boundary:             {}",
        match (s.boundary_loops, s.boundary_edges) {
            (Some(0), _) => "none (closed)".to_string(),
            (Some(l), Some(e)) => format!("{l} loops, {e} edges"),
            _ => "undefined".to_string(),
        }
    );
    emit!("components:           {}", s.components);
    emit!("euler characteristic: {}", opt(s.euler_characteristic.map(|x| x.to_string())));
    emit!("genus:                {}", opt(s.genus.map(|x| x.to_string())));
    emit!("manifold, oriented:   {}, {}", if s.manifold { "yes" } else { "no" }, if s.oriented { "yes" } else { "no" });
    emit!("bbox diagonal:        {}", opt(s.bbox_diagonal.map(length)));
    let t = &s.tags;
    if t.creases + t.corners > 0 {
        emit!(
            "tags:                 {} creases, {} corners ({} infinitely sharp, {} semi-sharp)",
            t.creases,
            t.corners,
            t.infinitely_sharp,
            t.semi_sharp
        );
    }
    if let Some(uv) = &s.uvs {
        emit!("texture coordinates:  {} values, {} seam vertices", uv.values, uv.seam_vertices);
    }
    for (k, n) in &s.problems {
        emit!("problem:              {n} {}", k.replace('_', " "));
    }
    for w in &s.warnings {
        emit!("warning:              {w}");
    }
    emit!("interpolation methods:");
    for (name, v) in Method::ALL.iter().filter_map(|m| s.methods.get(m.name()).map(|v| (m.name(), v))) {
        match &v.reason {
            None => emit!("  {name:<14} accepts"),
            Some(reason) => emit!("  {name:<14} refuses: {reason}"),
        }
    }
    emit!("subdivision schemes:");
    for (name, v) in subdiv_stencil::Scheme::ALL.iter().filter_map(|m| s.schemes.get(m.name()).map(|v| (m.name(), v))) {
        match &v.reason {
            None => emit!("  {name:<14} takes it"),
            Some(reason) => emit!("  {name:<14} refuses: {reason}"),
        }
    }
    out
}
