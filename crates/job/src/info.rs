//! A mesh's statistics: what `subdiv info --json` prints, as a typed,
//! serialisable [`Summary`].
//!
//! [`summarize`] describes a valid [`Mesh`]; [`summarize_soup`] describes
//! whatever a reader returned, valid or not: a soup that is no valid mesh
//! gets the counts the validator can still make ([`subdiv_mesh::diagnose`]),
//! its defects in [`Summary::problems`] and the first of them in
//! [`Summary::error`].
//!
//! ```
//! use subdiv_job::info::summarize;
//! let torus = subdiv_mesh::shapes::torus(8, 6);
//! let s = summarize(&torus, Some("torus.obj"));
//! assert_eq!((s.vertices, s.faces, s.edges), (48, 48, 96));
//! assert_eq!((s.genus, s.closed), (Some(1), Some(true)));
//! assert!(s.methods["cheng"].accepts);
//! assert!(s.schemes["catmull-clark"].accepts && !s.schemes["loop"].accepts); // quads
//! let json = serde_json::to_value(&s).unwrap();
//! assert_eq!(json["euler_characteristic"], 0);
//! ```

use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;
use subdiv_interp::{Method, TagCounts};
use subdiv_mesh::{diagnose, FaceList, FaceVarying, Mesh, PolygonSoup, Warning};
use subdiv_stencil::{LevelSharpness, Scheme};

/// The summary of a mesh: the object `subdiv info --json` prints (the keys
/// of the [report JSON]'s input, plus counts, validity and every method's
/// verdict). Keys and their order are a contract: new keys may come, none
/// goes.
///
/// [report JSON]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-report-json
#[derive(Serialize, Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Summary {
    /// The file it was read from (`null` when not given).
    pub file: Option<String>,
    /// Vertices (isolated ones included).
    pub vertices: usize,
    /// Faces.
    pub faces: usize,
    /// Distinct edges.
    pub edges: usize,
    /// Face size → how many faces have it.
    pub face_sizes: BTreeMap<usize, usize>,
    /// Vertex valence → how many vertices have it; `null` when the mesh is
    /// not a valid manifold (no fans to count).
    pub valences: Option<BTreeMap<usize, usize>>,
    /// Edges with one face (`null` for an invalid mesh).
    pub boundary_edges: Option<usize>,
    /// Boundary loops (`null` for an invalid mesh).
    pub boundary_loops: Option<usize>,
    /// Connected components.
    pub components: usize,
    /// V − E + F (`null` for an invalid mesh).
    pub euler_characteristic: Option<i64>,
    /// The genus of a closed connected mesh.
    pub genus: Option<u32>,
    /// No boundary (`null` for an invalid mesh).
    pub closed: Option<bool>,
    /// Every edge has one or two faces, every vertex one fan.
    pub manifold: bool,
    /// The faces agree on their orientation.
    pub oriented: bool,
    /// Vertices no face uses.
    pub isolated_vertices: usize,
    /// The bounding-box diagonal d (`null` without finite vertices).
    pub bbox_diagonal: Option<f64>,
    /// Crease and corner tags (OBJ `t` lines); boundaries are not counted.
    pub tags: TagCounts,
    /// The subdivision options the file sets for itself (OpenSubdiv's option tags: `boundary`,
    /// `crease_method`, `fvar`, `triangle_rule`), by name; left out of the JSON when none.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub file_options: BTreeMap<&'static str, String>,
    /// Texture coordinates (face-varying values), when the file has them.
    pub uvs: Option<UvCounts>,
    /// Warning-level defects (isolated vertices, zero-area faces), one line each.
    pub warnings: Vec<String>,
    /// Error-level defect counts by kind (empty for a valid mesh).
    pub problems: BTreeMap<&'static str, usize>,
    /// The first error that makes the mesh unusable, if any.
    pub error: Option<String>,
    /// Per interpolation method ([`Method::name`]): does it take this mesh,
    /// and if not, why ([`Method::check`], the check the method itself makes).
    pub methods: BTreeMap<&'static str, MethodVerdict>,
    /// Per subdivision scheme of the scheme table ([`Scheme::ALL`]): do its rules take this
    /// mesh with its tags (OpenSubdiv's default options), and if not, why.
    pub schemes: BTreeMap<&'static str, MethodVerdict>,
    /// The non-manifold edges and vertices of a mesh that has them (refined as OpenSubdiv
    /// does: [`subdiv_mesh::nonmanifold`]); left out of the JSON for a manifold mesh.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub non_manifold: Option<NonManifoldSummary>,
}

/// What is non-manifold in a mesh ([`Summary::non_manifold`]).
#[derive(Serialize, Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct NonManifoldSummary {
    /// Non-manifold edges, by their ends (OpenSubdiv's edge order): edges of 3+ faces, of two
    /// faces using them the same way, degenerate edges, an edge a face uses twice. Infinitely sharp.
    pub edges: Vec<[u32; 2]>,
    /// Non-manifold vertices, ascending: the ends of those edges and vertices joining separate fans.
    pub vertices: Vec<u32>,
    /// The non-manifold vertices that are infinitely sharp corners (all but those inside an
    /// interior non-manifold crease, which follow the crease), ascending.
    pub corners: Vec<u32>,
}

/// The options a file sets, by option name ([`Summary::file_options`]).
fn option_names(options: subdiv_mesh::FileOptions) -> BTreeMap<&'static str, String> {
    let subdiv_mesh::FileOptions { boundary, crease_method, fvar, triangle_rule } = options;
    [
        ("boundary", boundary.map(|o| o.to_string())),
        ("crease_method", crease_method.map(|o| o.to_string())),
        ("fvar", fvar.map(|o| o.to_string())),
        ("triangle_rule", triangle_rule.map(|o| o.to_string())),
    ]
    .into_iter()
    .filter_map(|(name, value)| Some((name, value?)))
    .collect()
}

/// The texture-coordinate channel of a [`Summary`].
#[derive(Serialize, Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct UvCounts {
    /// Distinct values.
    pub values: usize,
    /// Vertices with more than one value (on a seam).
    pub seam_vertices: usize,
}

impl UvCounts {
    fn of(uvs: &FaceVarying, faces: &FaceList, vertices: usize) -> Self {
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
#[derive(Serialize, Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct MethodVerdict {
    /// It does.
    pub accepts: bool,
    /// Why not (`None` when it does).
    pub reason: Option<String>,
}

/// Every method's verdict: from its own check on a valid mesh; "no" with the
/// validation error for a mesh that is not a valid manifold.
fn method_verdicts(mesh: Result<&Mesh, &str>) -> BTreeMap<&'static str, MethodVerdict> {
    // The checks are independent (Deng-Wang's triangulation check is the
    // longest): across threads, collected by name.
    Method::ALL
        .into_par_iter()
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

/// Every scheme's verdict: its rules' own check of the topology and tags (the check
/// `subdivide` makes first); "no" with the validation error for an invalid mesh.
fn scheme_verdicts(mesh: Result<&Mesh, &str>) -> BTreeMap<&'static str, MethodVerdict> {
    Scheme::ALL
        .into_iter()
        .map(|scheme| {
            let verdict = match mesh {
                Ok(mesh) => {
                    let sharp = LevelSharpness::new(mesh.tags(), Default::default(), Default::default());
                    let checked = subdiv_stencil::welds::check_scheme(scheme, mesh.welds())
                        .and_then(|()| scheme.rules().check(mesh.topology(), &sharp));
                    match checked {
                        Ok(()) => MethodVerdict { accepts: true, reason: None },
                        Err(e) => MethodVerdict { accepts: false, reason: Some(e.to_string()) },
                    }
                }
                Err(error) => MethodVerdict { accepts: false, reason: Some(format!("the mesh is not valid: {error}")) },
            };
            (scheme.name(), verdict)
        })
        .collect()
}

/// The summary of a valid mesh, its warnings from [`Mesh::warnings`].
pub fn summarize(mesh: &Mesh, file: Option<&str>) -> Summary {
    summarize_with_warnings(mesh, file, &mesh.warnings())
}

/// The summary of what a reader returned: validated here
/// ([`Mesh::from_soup`]); a soup that is no valid mesh is described as far
/// as it can be, with [`Summary::error`] set.
///
/// ```
/// use subdiv_job::info::summarize_soup;
/// use subdiv_io::{read_mesh_from_bytes, Format};
/// // Three faces on edge (0, 1): non-manifold, refined as OpenSubdiv does.
/// let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0 -1 0\nf 1 2 3\nf 2 1 4\nf 1 2 5\n";
/// let soup = read_mesh_from_bytes(obj.as_bytes(), Format::Obj, "fin.obj").unwrap();
/// let s = summarize_soup(soup, Some("fin.obj"));
/// assert!(!s.manifold && s.valences.is_none() && s.error.is_none());
/// assert_eq!((s.vertices, s.edges), (5, 7));
/// assert_eq!(s.non_manifold.unwrap().edges, [[0, 1]]);
/// // A face with two corners: no mesh, described as far as it goes.
/// let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 2 1\n";
/// let soup = read_mesh_from_bytes(obj.as_bytes(), Format::Obj, "two.obj").unwrap();
/// let s = summarize_soup(soup, Some("two.obj"));
/// assert_eq!(s.problems["faces_too_small"], 1);
/// assert!(s.error.unwrap().contains("at least 3"));
/// ```
pub fn summarize_soup(soup: PolygonSoup, file: Option<&str>) -> Summary {
    // A refused soup comes back, uncopied, to be described.
    match Mesh::try_from_soup_covering(soup) {
        Ok((mesh, warnings)) => summarize_with_warnings(&mesh, file, &warnings),
        Err(rejected) => invalid_summary(file, &rejected.soup),
    }
}

/// [`summarize`] with the warnings validation already found.
pub fn summarize_with_warnings(mesh: &Mesh, file: Option<&str>, warnings: &[Warning]) -> Summary {
    let (summary, methods) = rayon::join(|| counts(mesh, file, warnings), || method_verdicts(Ok(mesh)));
    Summary { methods, schemes: scheme_verdicts(Ok(mesh)), ..summary }
}

/// Everything of a valid mesh's [`Summary`] but the method verdicts (left empty).
fn counts(mesh: &Mesh, file: Option<&str>, warnings: &[Warning]) -> Summary {
    if let Some(report) = mesh.non_manifold() {
        // The counts of the input (the cover welded back), as for an invalid soup, without its
        // problems: OpenSubdiv's rules define the surface.
        let soup = mesh.clone().into_soup();
        let summary = invalid_summary(file, &soup);
        return Summary {
            problems: BTreeMap::new(),
            error: None,
            warnings: warnings.iter().map(ToString::to_string).collect(),
            euler_characteristic: None,
            bbox_diagonal: Some(mesh.bbox_diagonal()),
            methods: BTreeMap::new(),
            schemes: BTreeMap::new(),
            non_manifold: Some(NonManifoldSummary {
                edges: report.edges.clone(),
                vertices: report.vertices.clone(),
                corners: report.corners.clone(),
            }),
            ..summary
        };
    }
    let t = mesh.topology();
    Summary {
        file: file.map(str::to_string),
        vertices: t.vertex_count(),
        faces: t.face_count(),
        edges: t.edge_count(),
        face_sizes: t.faces().size_histogram(),
        valences: Some(t.valence_histogram()),
        boundary_edges: Some(t.boundary_edge_count()),
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
        file_options: option_names(mesh.tags().options()),
        uvs: mesh.uvs().map(|uvs| UvCounts::of(uvs, t.faces(), t.vertex_count())),
        warnings: warnings.iter().map(ToString::to_string).collect(),
        problems: BTreeMap::new(),
        error: None,
        methods: BTreeMap::new(),
        schemes: BTreeMap::new(),
        non_manifold: None,
    }
}

fn invalid_summary(file: Option<&str>, soup: &PolygonSoup) -> Summary {
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
        file: file.map(str::to_string),
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
        )
        .with_holes(soup.tags.holes.len()),
        file_options: option_names(soup.tags.options),
        uvs: soup.uvs.as_ref().map(|uvs| UvCounts::of(uvs, &soup.faces, soup.positions.len())),
        warnings,
        problems,
        methods: method_verdicts(Err(&d.first_error.as_ref().map_or_else(|| "invalid".to_string(), |e| e.to_string()))),
        schemes: scheme_verdicts(Err(&d.first_error.as_ref().map_or_else(|| "invalid".to_string(), |e| e.to_string()))),
        error: d.first_error.map(|e| e.to_string()),
        non_manifold: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_valid_soup_summarises_as_its_mesh() {
        let cube = subdiv_mesh::shapes::cube();
        let soup = PolygonSoup::new(cube.positions().to_vec(), cube.topology().faces().clone());
        assert_eq!(summarize_soup(soup, Some("cube")), summarize(&cube, Some("cube")));
        let s = summarize(&cube, None);
        // Independent counts: a cube has V − E + F = 8 − 12 + 6 = 2, genus 0.
        assert_eq!((s.vertices, s.edges, s.faces, s.euler_characteristic), (8, 12, 6, Some(2)));
        assert_eq!(s.face_sizes, BTreeMap::from([(4, 6)]));
        assert_eq!(s.valences, Some(BTreeMap::from([(3, 8)])));
        assert_eq!(serde_json::to_value(&s).unwrap()["file"], serde_json::Value::Null);
    }
}
