//! The tagged test meshes shared by the interpolation tests with creases
//! (`tests/integration/creases.rs`, `tests/integration/deng_wang_creases.rs`).

use glam::DVec3;
use subdiv_mesh::{shapes, EdgeTag, Mesh, TagList, Tags, VertexTag, SHARPNESS_INFINITE};

/// Infinitely sharp.
pub const INF: f32 = SHARPNESS_INFINITE;

/// `mesh` with the edges `creases` (vertex pairs, sharpness) and corners tagged.
pub fn tagged(mesh: &Mesh, creases: &[(u32, u32, f32)], corners: &[(u32, f32)]) -> Mesh {
    let list = TagList {
        creases: creases.iter().map(|&(a, b, sharpness)| EdgeTag { a, b, sharpness }).collect(),
        corners: corners.iter().map(|&(vertex, sharpness)| VertexTag { vertex, sharpness }).collect(),
        ..Default::default()
    };
    let tags = Tags::from_list(mesh.topology(), &list).expect("valid tags");
    mesh.clone().with_tags(tags)
}

/// Moves every vertex by a small deterministic offset (no symmetry left).
pub fn jittered(mesh: &Mesh, amount: f64) -> Mesh {
    super::perturbed(mesh.clone(), amount, 17)
}

/// The cube's top loop (z = 1: vertices 4, 5, 7, 6).
pub const CUBE_TOP: [(u32, u32); 4] = [(4, 5), (5, 7), (7, 6), (6, 4)];
/// All 12 edges of the cube.
pub const CUBE_EDGES: [(u32, u32); 12] =
    [(0, 1), (1, 3), (3, 2), (2, 0), (4, 5), (5, 7), (7, 6), (6, 4), (0, 4), (1, 5), (2, 6), (3, 7)];

pub fn with_sharpness(pairs: &[(u32, u32)], s: f32) -> Vec<(u32, u32, f32)> {
    pairs.iter().map(|&(a, b)| (a, b, s)).collect()
}

/// Grid vertex (i, j) of `shapes::quad_grid(nx, _)`.
pub fn grid_id(nx: u32, i: u32, j: u32) -> u32 {
    j * (nx + 1) + i
}

/// The bumpy open 6 × 5 quad grid of the cases.
pub fn bumpy_grid() -> Mesh {
    let g = shapes::quad_grid(6, 5);
    let p = g.positions().iter().map(|&p| DVec3::new(p.x, p.y, 0.3 * (3.0 * p.x).sin() * (2.0 * p.y).cos())).collect();
    g.with_positions(p)
}

/// A bumpy open grid with an interior crease row from boundary to boundary
/// (corners where it meets the boundary) and a corner tag on the boundary.
pub fn grid_case(s: f32) -> Mesh {
    let nx = 6u32;
    let row: Vec<(u32, u32, f32)> = (0..nx).map(|i| (grid_id(nx, i, 2), grid_id(nx, i + 1, 2), s)).collect();
    tagged(&bumpy_grid(), &row, &[(grid_id(nx, 3, 0), INF)])
}

/// A torus with a closed crease ring around the tube and a dart (one crease
/// edge ending in the smooth surface).
pub fn torus_case(s: f32) -> Mesh {
    let torus = jittered(&shapes::torus(12, 8), 0.05);
    let ring: Vec<(u32, u32, f32)> = (0..8).map(|j| (j, (j + 1) % 8, s)).collect();
    let mut creases = ring;
    creases.push((8 * 6 + 2, 8 * 7 + 2, INF)); // a dart at both ends
    tagged(&torus, &creases, &[])
}

/// The tagged cases every method is tested on, with a name and whether
/// they have semi-sharp values.
pub fn common_cases() -> Vec<(&'static str, Mesh, bool)> {
    let cube = jittered(&shapes::cube(), 0.1);
    vec![
        ("cube, top loop infinitely sharp", tagged(&cube, &with_sharpness(&CUBE_TOP, INF), &[]), false),
        ("cube, all 12 edges infinitely sharp", tagged(&cube, &with_sharpness(&CUBE_EDGES, INF), &[]), false),
        ("cube, two corners", tagged(&cube, &[], &[(1, INF), (5, INF)]), false),
        ("cube, top loop at 2.5", tagged(&cube, &with_sharpness(&CUBE_TOP, 2.5), &[]), true),
        (
            "cube, top loop 0.75/2.5 and a semi-sharp corner",
            tagged(&cube, &[(4, 5, 0.75), (5, 7, 2.5), (7, 6, 0.75), (6, 4, 2.5)], &[(1, 1.5)]),
            true,
        ),
        ("torus, ring and dart", torus_case(INF), false),
        ("torus, ring at 3 and dart", torus_case(3.0), true),
        ("open grid, crease row and corner", grid_case(INF), false),
        ("open grid, crease row at 1.5", grid_case(1.5), true),
    ]
}
