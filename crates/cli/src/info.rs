//! `subdiv info MESH [--json] [--strict]`.

use crate::failure::{bad_input, Failure};
use anyhow::anyhow;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::PathBuf;
use subdiv_interp::{Method, TagCounts};
use subdiv_mesh::{diagnose, Mesh, Warning};

/// Arguments of `subdiv info`.
#[derive(clap::Args, Debug)]
pub struct InfoArgs {
    /// Mesh file (.obj, .off, .ply, .stl, .gltf, .glb).
    mesh: PathBuf,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
    /// Treat warnings (isolated vertices, zero-area faces) as errors: exit 2.
    #[arg(long)]
    strict: bool,
}

/// The summary printed by `info` (the keys of [report JSON], plus a few more).
///
/// [report JSON]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-report-json
#[derive(Serialize, Debug)]
struct Summary {
    file: String,
    vertices: usize,
    faces: usize,
    edges: usize,
    face_sizes: BTreeMap<usize, usize>,
    /// `null` when the mesh is not a valid manifold (no fans to count).
    valences: Option<BTreeMap<usize, usize>>,
    boundary_edges: Option<usize>,
    boundary_loops: Option<usize>,
    components: usize,
    euler_characteristic: Option<i64>,
    genus: Option<u32>,
    closed: Option<bool>,
    manifold: bool,
    oriented: bool,
    isolated_vertices: usize,
    bbox_diagonal: Option<f64>,
    /// Crease and corner tags (OBJ `t` lines); boundaries are not counted.
    tags: TagCounts,
    /// Texture coordinates (face-varying values), when the file has them.
    uvs: Option<UvCounts>,
    warnings: Vec<String>,
    /// Error-level defect counts (all zero for a valid mesh).
    problems: BTreeMap<&'static str, usize>,
    /// The first error that makes the mesh unusable, if any.
    error: Option<String>,
    /// Per interpolation method: does it take this mesh, and if not, why
    /// (`subdiv_interp::Method::check`, the check the method itself makes).
    methods: BTreeMap<&'static str, MethodVerdict>,
}

/// The texture-coordinate channel.
#[derive(Serialize, Debug)]
struct UvCounts {
    /// Distinct values.
    values: usize,
    /// Vertices with more than one value (on a seam).
    seam_vertices: usize,
}

impl UvCounts {
    fn of(uvs: &subdiv_mesh::FaceVarying, faces: &subdiv_mesh::FaceList, vertices: usize) -> Self {
        // First value seen per vertex; a vertex with another one is on a seam.
        let mut first = vec![u32::MAX; vertices];
        let mut seam = vec![false; vertices];
        for (&v, &value) in faces.indices().iter().zip(&uvs.indices) {
            let Some(slot) = first.get_mut(v as usize) else { continue };
            if *slot == u32::MAX {
                *slot = value;
            } else if *slot != value {
                seam[v as usize] = true;
            }
        }
        UvCounts { values: uvs.values.len(), seam_vertices: seam.iter().filter(|&&s| s).count() }
    }
}

/// Whether one interpolation method takes the mesh.
#[derive(Serialize, Debug)]
struct MethodVerdict {
    accepts: bool,
    reason: Option<String>,
}

/// Every method's verdict: from its own check on a valid mesh; "no" with the
/// validation error for a mesh that is not a valid manifold.
fn method_verdicts(mesh: Result<&Mesh, &str>) -> BTreeMap<&'static str, MethodVerdict> {
    Method::ALL
        .into_iter()
        .map(|m| {
            let verdict = match mesh.map(|mesh| m.check(mesh)) {
                Ok(Ok(())) => MethodVerdict { accepts: true, reason: None },
                Ok(Err(reason)) => MethodVerdict { accepts: false, reason: Some(reason) },
                Err(error) => MethodVerdict { accepts: false, reason: Some(format!("the mesh is not valid: {error}")) },
            };
            (m.name(), verdict)
        })
        .collect()
}

/// Runs `subdiv info`.
pub fn run(args: &InfoArgs) -> Result<(), Failure> {
    let soup = crate::load::read_soup(&args.mesh)?;
    let file = args.mesh.display().to_string();
    let summary = match Mesh::from_soup(soup.clone()) {
        Ok((mesh, warnings)) => valid_summary(file.clone(), &mesh, &warnings),
        Err(_) => invalid_summary(file.clone(), &soup),
    };
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

fn valid_summary(file: String, mesh: &Mesh, warnings: &[Warning]) -> Summary {
    let t = mesh.topology();
    let boundary_edges = t.edges().filter(|&e| t.is_boundary_edge(e)).count();
    let face_sizes = t.faces().iter().fold(BTreeMap::new(), |mut h, f| {
        *h.entry(f.len()).or_insert(0) += 1;
        h
    });
    Summary {
        file,
        vertices: t.vertex_count(),
        faces: t.face_count(),
        edges: t.edge_count(),
        face_sizes,
        valences: Some(t.valence_histogram()),
        boundary_edges: Some(boundary_edges),
        boundary_loops: Some(t.boundary_loop_count()),
        components: t.component_count(),
        euler_characteristic: Some(t.euler_characteristic()),
        genus: t.genus(),
        closed: Some(t.is_closed()),
        manifold: true,
        oriented: true,
        isolated_vertices: t.vertices().filter(|&v| t.is_isolated(v)).count(),
        bbox_diagonal: Some(mesh.bbox_diagonal()),
        tags: TagCounts::of_mesh(mesh),
        uvs: mesh.uvs().map(|uvs| UvCounts::of(uvs, t.faces(), t.vertex_count())),
        warnings: warnings.iter().map(ToString::to_string).collect(),
        problems: BTreeMap::new(),
        error: None,
        methods: method_verdicts(Ok(mesh)),
    }
}

fn invalid_summary(file: String, soup: &subdiv_mesh::PolygonSoup) -> Summary {
    let d = diagnose(soup);
    let problems: BTreeMap<&'static str, usize> = [
        ("faces_too_small", d.faces_too_small),
        ("out_of_range_indices", d.out_of_range_indices),
        ("faces_with_repeated_index", d.faces_with_repeated_index),
        ("non_finite_vertices", d.non_finite_vertices),
        ("non_manifold_edges", d.non_manifold_edges),
        ("non_manifold_vertices", d.non_manifold_vertices),
        ("inconsistently_oriented_edges", d.inconsistently_oriented_edges),
    ]
    .into_iter()
    .filter(|&(_, n)| n > 0)
    .collect();
    let mut warnings = Vec::new();
    if d.isolated_vertices > 0 {
        warnings.push(format!("{} isolated vertices (no face uses them)", d.isolated_vertices));
    }
    Summary {
        file,
        vertices: d.vertices,
        faces: d.faces,
        edges: d.edges,
        face_sizes: d.face_sizes,
        valences: None,
        boundary_edges: None,
        boundary_loops: None,
        components: d.components,
        euler_characteristic: None,
        genus: None,
        closed: None,
        manifold: d.non_manifold_edges == 0 && d.non_manifold_vertices == 0 && d.faces_with_repeated_index == 0,
        oriented: d.inconsistently_oriented_edges == 0,
        isolated_vertices: d.isolated_vertices,
        bbox_diagonal: d.bbox.map(|b| b.diagonal()),
        tags: TagCounts::of(
            soup.tags.creases.iter().map(|t| t.sharpness),
            soup.tags.corners.iter().map(|t| t.sharpness),
        ),
        uvs: soup.uvs.as_ref().map(|uvs| UvCounts::of(uvs, &soup.faces, soup.positions.len())),
        warnings,
        problems,
        methods: method_verdicts(Err(&d.first_error.as_ref().map_or_else(|| "invalid".to_string(), |e| e.to_string()))),
        error: d.first_error.map(|e| e.to_string()),
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
    emit!("file:                 {}", s.file);
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
    out
}
