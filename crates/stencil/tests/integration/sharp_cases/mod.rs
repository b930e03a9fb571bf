//! Tagged meshes shared by the tests of the limit matrices with creases
//! (`limit_matrices_creases.rs`, `limit_matrices_creases_brute_force.rs`):
//! the OpenSubdiv cases of `fixtures/peer/creases/` with their own tag lines,
//! and constructed ones (infinitely sharp loops and rows, darts, 3-vertex
//! crease loops, corner tags, a crop that pinches a rim vertex).
#![allow(dead_code)]

use glam::DVec3;
use std::path::{Path, PathBuf};
use subdiv_mesh::{shapes, EdgeTag, Mesh, TagList, Tags, VertexTag};
use subdiv_stencil::limit_matrix::{limit_matrix_catmull_clark_sharp, limit_matrix_loop_sharp, LimitMatrix};
use subdiv_stencil::{
    BoundaryInterpolation, CreaseMethod, LevelSharpness, LoopBeta, Options, Scheme, SparseMatrix, SubdivisionPlan,
};

/// A tagged mesh with the options it is subdivided with.
pub struct Case {
    pub name: String,
    pub mesh: Mesh,
    pub tags: Tags,
    pub options: Options,
    /// OpenSubdiv's limit points of the input vertices, when the case is a peer file.
    pub peer_limit: Option<PathBuf>,
}

impl Case {
    /// The level-0 sharpness of the case.
    pub fn sharpness(&self) -> LevelSharpness {
        LevelSharpness::from_options(&self.tags, &self.options)
    }

    /// The tagged limit matrix of the case's scheme.
    pub fn matrix(&self) -> LimitMatrix {
        let t = self.mesh.topology();
        match self.options.scheme {
            Scheme::CatmullClark => limit_matrix_catmull_clark_sharp(t, &self.sharpness()).unwrap(),
            Scheme::Loop(beta) => limit_matrix_loop_sharp(t, &self.sharpness(), beta).unwrap(),
            s => panic!("{}: no tagged limit matrix for {s:?}", self.name),
        }
    }

    /// The plan's limit stencil, the reference of every row.
    pub fn plan_stencil(&self) -> SparseMatrix {
        let plan = SubdivisionPlan::with_tags(self.mesh.topology(), &self.tags, self.options, 0).unwrap();
        plan.limit_stencil().unwrap().unwrap()
    }

    /// The mesh carrying its tags (what `subdivide` refines).
    pub fn tagged_mesh(&self) -> Mesh {
        self.mesh.clone().with_tags(self.tags.clone())
    }
}

pub fn creases_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/peer/creases")
}

/// OpenSubdiv's tag lines (`t crease NI/NF/0 a b … s …`, `t corner NI/NF/0 v … s …`).
pub fn read_tag_lines(path: &Path) -> TagList {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut list = TagList::default();
    for line in text.lines() {
        let mut words = line.split_whitespace();
        if words.next() != Some("t") {
            continue;
        }
        let name = words.next().unwrap();
        let counts: Vec<usize> = words.next().unwrap().split('/').map(|c| c.parse().unwrap()).collect();
        let rest: Vec<&str> = words.collect();
        let ints: Vec<u32> = rest[..counts[0]].iter().map(|w| w.parse().unwrap()).collect();
        let floats: Vec<f32> = rest[counts[0]..counts[0] + counts[1]].iter().map(|w| w.parse().unwrap()).collect();
        let value = |k: usize| floats[if floats.len() == 1 { 0 } else { k }];
        match name {
            "crease" => (ints.chunks(2).enumerate())
                .for_each(|(k, p)| list.creases.push(EdgeTag { a: p[0], b: p[1], sharpness: value(k) })),
            "corner" => (ints.iter().enumerate())
                .for_each(|(k, &vertex)| list.corners.push(VertexTag { vertex, sharpness: value(k) })),
            _ => {}
        }
    }
    list
}

pub fn read_points(path: &Path) -> Vec<DVec3> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    (text.lines().filter(|l| !l.trim().is_empty() && !l.starts_with('#')))
        .map(|l| {
            let c: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
            DVec3::new(c[0], c[1], c[2])
        })
        .collect()
}

fn load(path: &Path) -> Mesh {
    let soup = subdiv_io::read_mesh(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    Mesh::from_soup(soup).unwrap().0
}

/// Tags from (a, b, s) creases and (v, s) corners.
pub fn tags(mesh: &Mesh, creases: &[(u32, u32, f32)], corners: &[(u32, f32)]) -> Tags {
    let list = TagList {
        creases: creases.iter().map(|&(a, b, sharpness)| EdgeTag { a, b, sharpness }).collect(),
        corners: corners.iter().map(|&(vertex, sharpness)| VertexTag { vertex, sharpness }).collect(),
        ..Default::default()
    };
    Tags::from_list(mesh.topology(), &list).unwrap()
}

pub fn options(scheme: Scheme, boundary: BoundaryInterpolation, method: CreaseMethod) -> Options {
    Options::new(scheme).with_boundary(boundary).with_crease_method(method)
}

const CC: Scheme = Scheme::CatmullClark;
const LOOP: Scheme = Scheme::Loop(LoopBeta::Loop);
use BoundaryInterpolation::{EdgeAndCorner, EdgeOnly};
use CreaseMethod::{Chaikin, Uniform};

/// The OpenSubdiv cases with a limit file: (folder, scheme, crease method,
/// limit file).
pub fn peer_cases() -> Vec<Case> {
    let cc = "opensubdiv-catmull-clark";
    let lo = "opensubdiv-loop-origbeta";
    let list: &[(&str, Scheme, CreaseMethod, &str)] = &[
        ("cube_crease_all10", CC, Uniform, cc),
        ("cube_corners2", CC, Uniform, cc),
        ("cube_corners_semi", CC, Uniform, cc),
        ("cube_corners_semi", CC, Chaikin, cc),
        ("cube_crease_top_s1", CC, Uniform, cc),
        ("cube_crease_top_s1", CC, Chaikin, cc),
        ("cube_crease_top_s2.5", CC, Uniform, cc),
        ("cube_crease_top_mixed", CC, Uniform, cc),
        ("cube_crease_top_mixed", CC, Chaikin, cc),
        ("grid_crease_row_corner", CC, Uniform, cc),
        ("grid_crease_row_corner", CC, Chaikin, cc),
        ("torus_ring_s3", CC, Uniform, cc),
        ("torus_ring_s3", CC, Chaikin, cc),
        ("octahedron_corner_creases", LOOP, Uniform, lo),
        ("octahedron_corner_creases", LOOP, Chaikin, lo),
    ];
    list.iter()
        .map(|&(stem, scheme, method, prefix)| {
            let dir = creases_dir().join(stem);
            let input = dir.join(format!("{stem}.obj"));
            let mesh = load(&input);
            let tags = Tags::from_list(mesh.topology(), &read_tag_lines(&input)).unwrap();
            let suffix = if method == Chaikin { "-chaikin" } else { "" };
            Case {
                name: format!("{stem} ({}{suffix})", scheme.name()),
                mesh,
                tags,
                options: options(scheme, EdgeAndCorner, method),
                peer_limit: Some(dir.join(format!("{prefix}{suffix}-limit.txt"))),
            }
        })
        .collect()
}

/// `mesh` with z = 0.2 sin(2πx + 0.5) cos(1.3πy) + 0.15x²y (a flat grid's
/// creases move no point) after scaling x, y to [0, 1].
pub fn curved_grid(nx: usize, ny: usize) -> Mesh {
    let grid = shapes::quad_grid(nx, ny);
    let p = (grid.positions().iter())
        .map(|p| {
            let (x, y) = (p.x / nx as f64, p.y / ny as f64);
            let z = 0.2 * (std::f64::consts::TAU * x + 0.5).sin() * (1.3 * std::f64::consts::PI * y).cos()
                + 0.15 * x * x * y;
            DVec3::new(x, y, z)
        })
        .collect();
    grid.with_positions(p)
}

/// Positions moved by up to 0.2 of the mean edge length (deterministic).
pub fn jittered(mesh: &Mesh, seed: u64) -> Mesh {
    let mut rng = shapes::SplitMix64(seed);
    let scale = shapes::mean_edge_length(mesh) * 0.2;
    let p = (mesh.positions().iter())
        .map(|&p| p + scale * DVec3::new(rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5))
        .collect();
    mesh.with_positions(p)
}

fn case(name: &str, mesh: Mesh, tags: Tags, options: Options) -> Case {
    Case { name: name.into(), mesh, tags, options, peer_limit: None }
}

/// Vertex (i, j) of `shapes::quad_grid(nx, _)`.
pub fn grid_id(nx: usize, i: usize, j: usize) -> u32 {
    (j * (nx + 1) + i) as u32
}

/// The edges of row j from column i0 to i1 of a quad grid, at sharpness s.
fn grid_row(nx: usize, j: usize, i0: usize, i1: usize, s: f32) -> Vec<(u32, u32, f32)> {
    (i0..i1).map(|i| (grid_id(nx, i, j), grid_id(nx, i + 1, j), s)).collect()
}

/// The ring i = 0 of `shapes::torus(nu, nv)` (vertices 0..nv, around the
/// tube), as edges at sharpness s.
fn torus_ring(nv: usize, s: f32) -> Vec<(u32, u32, f32)> {
    (0..nv).map(|j| (j as u32, ((j + 1) % nv) as u32, s)).collect()
}

/// Constructed cases, small enough for 8 levels of brute force.
pub fn constructed_cases() -> Vec<Case> {
    let mut out = Vec::new();
    let cube = jittered(&shapes::cube(), 7);
    // shapes::cube: vertex i at (i & 1, i >> 1 & 1, i >> 2 & 1); top face z = 1: 4, 5, 7, 6.
    let top = [(4, 5, 10.0), (5, 7, 10.0), (7, 6, 10.0), (6, 4, 10.0)];
    out.push(case("cube, top loop s=10", cube.clone(), tags(&cube, &top, &[]), options(CC, EdgeAndCorner, Uniform)));
    let semi = [(4, 5, 1.0), (5, 7, 2.5), (7, 6, 1.0), (6, 4, 2.5)];
    for method in [Uniform, Chaikin] {
        let name = format!("cube, top loop s=1/2.5 ({method})");
        out.push(case(&name, cube.clone(), tags(&cube, &semi, &[]), options(CC, EdgeAndCorner, method)));
    }
    // Two infinitely sharp top edges and a semi-sharp vertical one at vertex 5:
    // a corner while the vertical edge lasts, a crease after it.
    let mixed = [(4, 5, 10.0), (5, 7, 10.0), (5, 1, 1.5)];
    out.push(case(
        "cube, crease with a semi-sharp branch",
        cube.clone(),
        tags(&cube, &mixed, &[]),
        options(CC, EdgeAndCorner, Uniform),
    ));
    out.push(case(
        "cube, corner tags 10 and 2.5",
        cube.clone(),
        tags(&cube, &[], &[(0, 10.0), (7, 2.5)]),
        options(CC, EdgeAndCorner, Uniform),
    ));

    // A triangle whose three edges are infinitely sharp: a 3-vertex crease loop.
    let tet = jittered(&shapes::tetrahedron(), 8);
    let loop3 = [(0, 1, 10.0), (1, 2, 10.0), (2, 0, 10.0)];
    out.push(case(
        "tetrahedron (CC), 3-vertex crease loop",
        tet.clone(),
        tags(&tet, &loop3, &[]),
        options(CC, EdgeAndCorner, Uniform),
    ));

    let (nu, nv) = (6, 4);
    let torus = jittered(&shapes::torus(nu, nv), 9);
    out.push(case(
        "torus 6×4, ring s=10",
        torus.clone(),
        tags(&torus, &torus_ring(nv, 10.0), &[]),
        options(CC, EdgeAndCorner, Uniform),
    ));
    out.push(case(
        "torus 6×4, ring s=3",
        torus.clone(),
        tags(&torus, &torus_ring(nv, 3.0), &[]),
        options(CC, EdgeAndCorner, Uniform),
    ));

    let n = 4;
    let grid = curved_grid(n, n);
    let row = grid_row(n, 2, 0, n, 10.0);
    for boundary in [EdgeAndCorner, EdgeOnly] {
        let name = format!("grid 4×4, crease row s=10 to the boundary, corner tag ({boundary})");
        let corner = [(grid_id(n, 1, 0), 10.0)];
        out.push(case(&name, grid.clone(), tags(&grid, &row, &corner), options(CC, boundary, Uniform)));
    }
    out.push(case(
        "grid 4×4, crease row s=2 to the boundary",
        grid.clone(),
        tags(&grid, &grid_row(n, 2, 0, n, 2.0), &[]),
        options(CC, EdgeAndCorner, Uniform),
    ));
    // An interior crease segment: darts at both ends.
    out.push(case(
        "grid 4×4, interior crease segment s=10 (darts)",
        grid.clone(),
        tags(&grid, &grid_row(n, 2, 1, 3, 10.0), &[]),
        options(CC, EdgeAndCorner, Uniform),
    ));

    let octa = jittered(&shapes::octahedron(), 10);
    // shapes::octahedron: vertex 4 = (0, 0, 1), in the 4 upper faces.
    let star = |s: f32| [(4, 0, s), (4, 1, s), (4, 2, s), (4, 3, s)];
    for s in [1.5, 10.0] {
        for method in [Uniform, Chaikin] {
            let name = format!("octahedron (Loop), corner + 4 creases s={s} ({method})");
            out.push(case(
                &name,
                octa.clone(),
                tags(&octa, &star(s), &[(4, 10.0)]),
                options(LOOP, EdgeAndCorner, method),
            ));
        }
    }
    // The equator 0-2-1-3 at 10: a closed crease loop of 4 under Loop.
    let equator = [(0, 2, 10.0), (2, 1, 10.0), (1, 3, 10.0), (3, 0, 10.0)];
    out.push(case(
        "octahedron (Loop), equator s=10",
        octa.clone(),
        tags(&octa, &equator, &[]),
        options(LOOP, EdgeAndCorner, Uniform),
    ));
    let tri = jittered(&shapes::triangle_grid(3, 3), 11);
    out.push(case(
        "triangle grid 3×3 (Loop), dart and a semi-sharp edge",
        tri.clone(),
        tags(&tri, &[(5, 6, 10.0), (9, 10, 1.25)], &[]),
        options(LOOP, EdgeOnly, Uniform),
    ));
    out
}

/// A crop around the general rows that pinches a rim vertex: on a 6×5
/// grid, semi-sharp corners at (1, 0) and (4, 3) keep, of the faces of
/// vertex (2, 2), only the two that meet at that vertex alone.
pub fn pinched_crop_case() -> Case {
    let grid = curved_grid(6, 5);
    let corners = [(grid_id(6, 1, 0), 2.0), (grid_id(6, 4, 3), 2.0)];
    case(
        "grid 6×5, semi-sharp corners whose crop pinches (2, 2)",
        grid.clone(),
        tags(&grid, &[], &corners),
        options(CC, EdgeAndCorner, Uniform),
    )
}

/// Every case.
pub fn all_cases() -> Vec<Case> {
    let mut all = peer_cases();
    all.extend(constructed_cases());
    all.push(pinched_crop_case());
    all
}
