//! Face-varying UVs against OpenSubdiv 3.5 (`fixtures/peer/creases/`, whose
//! README gives the commands): every `…-fvar-…` file of `uv_grid` (no seams,
//! `edge-and-corner` and `edge-only` boundaries) and `spot_uv` (267 UVs with
//! seams on 188 vertices, triangles, quads and pentagons), Catmull-Clark at
//! levels 1 and 2, modes `linear-none`, `linear-corners-only`, `linear-all`.
//!
//! UVs are compared per face corner, ≤ 1e-12 absolute. OpenSubdiv's faces come
//! in our order but a child quad of a quad starts at another corner, and its
//! level-2 numbering differs, so corners are matched through positions: our
//! vertices are mapped to theirs by position (within 1e-9 of the bounding-box
//! diagonal, uniquely), faces by their vertex sets, corners by their vertex.
//! The value counts must be equal too (both group values by vertex: one per
//! vertex, face and continuous edge, one more per extra value of a seam).
//!
//! The files are read by a minimal parser here (`v`, `vt`, `f v/vt`),
//! independent of `subdiv-io`.

use glam::{DVec2, DVec3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use subdiv_mesh::{FaceList, FaceVarying, Mesh, PolygonSoup};
use subdiv_stencil::{
    fvar, BoundaryInterpolation, FVarInterpolation, LevelSharpness, Options, Scheme, SubdivisionPlan,
};

/// Largest accepted UV deviation (absolute).
pub(crate) const UV_TOL: f64 = 1e-12;

fn creases_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/peer/creases")
}

/// An OBJ file as read: positions, UV values, and per face its (vertex, uv) corners.
pub(crate) struct Obj {
    pub(crate) positions: Vec<DVec3>,
    pub(crate) uvs: Vec<DVec2>,
    pub(crate) faces: Vec<Vec<(u32, u32)>>,
}

pub(crate) fn read_obj(path: &Path) -> Obj {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut obj = Obj { positions: Vec::new(), uvs: Vec::new(), faces: Vec::new() };
    let number = |w: &str| w.parse::<f64>().unwrap_or_else(|e| panic!("{}: {w}: {e}", path.display()));
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let c: Vec<f64> = words.take(3).map(number).collect();
                obj.positions.push(DVec3::new(c[0], c[1], c[2]));
            }
            Some("vt") => {
                let c: Vec<f64> = words.take(2).map(number).collect();
                obj.uvs.push(DVec2::new(c[0], c[1]));
            }
            Some("f") => {
                let corner = |w: &str| {
                    let mut parts = w.split('/').map(|p| p.parse::<u32>().unwrap() - 1);
                    let v = parts.next().unwrap();
                    let vt = parts.next().unwrap_or_else(|| panic!("{}: face corner {w} has no vt", path.display()));
                    (v, vt)
                };
                obj.faces.push(words.map(corner).collect());
            }
            _ => {}
        }
    }
    obj
}

/// The input mesh of a case, with its UVs as the face-varying channel.
fn input_mesh(obj: &Obj) -> Mesh {
    let faces = FaceList::from_faces(obj.faces.iter().map(|f| f.iter().map(|c| c.0).collect::<Vec<_>>()));
    let mut soup = PolygonSoup::new(obj.positions.clone(), faces);
    let indices = obj.faces.iter().flatten().map(|c| c.1).collect();
    soup.uvs = Some(FaceVarying { values: obj.uvs.clone(), indices });
    Mesh::from_soup(soup).unwrap().0
}

/// What a face-varying reference file name says: options, mode and level.
fn parse_name(name: &str) -> Option<(Options, FVarInterpolation, usize)> {
    let rest = name.strip_prefix("opensubdiv-catmull-clark-")?;
    let (rest, boundary) = match rest.strip_prefix("edge-only-") {
        Some(rest) => (rest, BoundaryInterpolation::EdgeOnly),
        None => (rest, BoundaryInterpolation::EdgeAndCorner),
    };
    let (mode, level) = rest.strip_prefix("fvar-")?.strip_suffix(".obj")?.rsplit_once("-L")?;
    let mode: FVarInterpolation = mode.parse().ok()?;
    let options = Options::new(Scheme::CatmullClark).with_boundary(boundary).with_fvar(mode);
    Some((options, mode, level.parse().ok()?))
}

/// For every point of `ours`, the index of the point of `theirs` within
/// `tol`, which must exist and be unique.
fn match_vertices(ours: &[DVec3], theirs: &[DVec3], tol: f64) -> Vec<usize> {
    let mut by_x: Vec<usize> = (0..theirs.len()).collect();
    by_x.sort_by(|&a, &b| theirs[a].x.total_cmp(&theirs[b].x));
    ours.iter()
        .enumerate()
        .map(|(i, p)| {
            let from = by_x.partition_point(|&k| theirs[k].x < p.x - tol);
            let near: Vec<usize> = by_x[from..]
                .iter()
                .take_while(|&&k| theirs[k].x <= p.x + tol)
                .copied()
                .filter(|&k| theirs[k].distance(*p) <= tol)
                .collect();
            assert_eq!(near.len(), 1, "our vertex {i} at {p} matches {} of theirs", near.len());
            near[0]
        })
        .collect()
}

/// The largest UV difference over all face corners, matched through positions.
fn corner_deviation(mesh: &Mesh, positions: &[DVec3], uvs: &FaceVarying, reference: &Obj, what: &str) -> f64 {
    let t = mesh.topology();
    let tol = 1e-9 * mesh.bbox_diagonal();
    let map = match_vertices(positions, &reference.positions, tol);
    let key = |vertices: &mut Vec<usize>| {
        vertices.sort_unstable();
        vertices.clone()
    };
    let theirs: HashMap<Vec<usize>, usize> = (reference.faces.iter().enumerate())
        .map(|(k, f)| (key(&mut f.iter().map(|c| c.0 as usize).collect()), k))
        .collect();
    assert_eq!(theirs.len(), reference.faces.len(), "{what}: faces with equal vertex sets");
    let mut worst = 0.0f64;
    for f in t.face_ids() {
        let mut vertices: Vec<usize> = t.face(f).iter().map(|&v| map[v as usize]).collect();
        let k = *theirs.get(&key(&mut vertices)).unwrap_or_else(|| panic!("{what}: our face {f:?} has no match"));
        for h in t.face_half_edges(f) {
            let v = map[t.he_from(h).index()] as u32;
            let &(_, vt) = reference.faces[k].iter().find(|c| c.0 == v).unwrap();
            let ours = uvs.values[uvs.indices[h.index()] as usize];
            worst = worst.max(ours.distance(reference.uvs[vt as usize]));
        }
    }
    worst
}

#[test]
fn face_varying_uvs_equal_opensubdiv_per_face_corner() {
    let mut checked = 0;
    let mut table = Vec::new();
    for case in ["uv_grid", "spot_uv"] {
        let dir = creases_dir().join(case);
        let input = input_mesh(&read_obj(&dir.join(format!("{case}.obj"))));
        let mut files: Vec<_> = std::fs::read_dir(&dir).unwrap().flatten().map(|e| e.path()).collect();
        files.sort();
        for file in files {
            let name = file.file_name().unwrap().to_string_lossy().to_string();
            if !name.contains("-fvar-") {
                continue;
            }
            let (options, mode, level) = parse_name(&name).unwrap_or_else(|| panic!("unexpected file {name}"));
            let plan = SubdivisionPlan::with_tags(input.topology(), input.tags(), options, level).unwrap();
            let base = LevelSharpness::new(input.tags(), options.boundary, options.crease_method);
            let levels = plan.levels().iter().map(|r| (&r.topology, &r.sharpness));
            let uvs = fvar::refine_levels(input.topology(), &base, levels, options.scheme, mode, input.uvs().unwrap())
                .unwrap();
            let positions = plan.apply(input.positions());
            let refined = Mesh::from_topology(plan.topology().clone(), positions.clone());
            let reference = read_obj(&file);
            let what = format!("{case}/{name}");
            assert_eq!(refined.topology().face_count(), reference.faces.len(), "{what}: face count");
            assert_eq!(uvs.values.len(), reference.uvs.len(), "{what}: value count");
            assert_eq!(uvs.indices.len(), refined.topology().half_edge_count(), "{what}: one index per corner");
            let worst = corner_deviation(&refined, &positions, &uvs, &reference, &what);
            table.push(format!("{what:70} L{level} {} values, max |Δuv| {worst:.1e}", uvs.values.len()));
            assert!(worst <= UV_TOL, "{what}: UVs off by {worst:.3e}");
            checked += 1;
        }
    }
    println!("{}", table.join("\n"));
    assert_eq!(checked, 16, "every face-varying reference file");
}
