//! Acceptance: evaluation at dyadic parameters equals the limit positions of
//! the corresponding vertices of refined meshes (`subdivide --limit`, which
//! matches OpenSubdiv), to 1e-12 of the bounding-box diagonal, from every
//! face a vertex is a corner of (so also continuity across shared edges).

use crate::common::dyadic_error;
use subdiv_mesh::{shapes, Mesh, Tags};
use subdiv_rules::{BoundaryInterpolation, CreaseMethod, LoopBeta};
use subdiv_stencil::{Options, Scheme};

const TOL: f64 = 1e-12;

fn cc() -> Options {
    Options::new(Scheme::CatmullClark)
}

fn lp() -> Options {
    Options::new(Scheme::Loop(LoopBeta::default()))
}

fn assert_dyadic(name: &str, mesh: &Mesh, options: Options) {
    for levels in 1..=2 {
        let e = dyadic_error(mesh, options, levels);
        assert!(e <= TOL, "{name}, level {levels}: error {e:e}·d");
    }
}

/// Tags on `mesh`: edges by index with sharpness, vertices likewise.
fn tagged(mesh: &Mesh, edges: &[(u32, f32)], vertices: &[(u32, f32)]) -> Mesh {
    let t = mesh.topology();
    let mut e = vec![0f32; t.edge_count()];
    for &(i, s) in edges {
        e[i as usize] = s;
    }
    let mut v = vec![0f32; t.vertex_count()];
    for &(i, s) in vertices {
        v[i as usize] = s;
    }
    mesh.clone().with_tags(Tags::from_arrays(t, e, v).unwrap())
}

#[test]
fn catmull_clark_closed_extraordinary() {
    assert_dyadic("cube", &shapes::cube(), cc());
    assert_dyadic("torus", &shapes::torus(4, 3), cc());
    assert_dyadic("pillow", &shapes::pillow(), cc());
}

#[test]
fn catmull_clark_boundaries_and_corners() {
    assert_dyadic("grid", &shapes::quad_grid(3, 2), cc());
    assert_dyadic("grid 1x1", &shapes::quad_grid(1, 1), cc());
    let edge_only = cc().with_boundary(BoundaryInterpolation::EdgeOnly);
    assert_dyadic("grid edge-only", &shapes::quad_grid(3, 3), edge_only);
    assert_dyadic("plate", &shapes::plate_with_holes(4, 4, &[(1, 1)], false), cc());
    let none = cc().with_boundary(BoundaryInterpolation::None);
    assert_dyadic("grid none", &shapes::quad_grid(3, 3), none);
}

#[test]
fn catmull_clark_ngons_and_triangles() {
    assert_dyadic("pyramid", &shapes::pyramid(5), cc());
    assert_dyadic("prism", &shapes::prism(6), cc());
    assert_dyadic("tetrahedron", &shapes::tetrahedron(), cc());
    let mix = shapes::polygon_mix(&shapes::torus(6, 5), 3, 0.2, 0.2, 0.1);
    assert_dyadic("mix", &mix, cc());
    let open_mix = shapes::polygon_mix(&shapes::quad_grid(5, 4), 5, 0.2, 0.2, 0.1);
    assert_dyadic("open mix", &open_mix, cc());
}

#[test]
fn catmull_clark_tags() {
    let cube = shapes::cube();
    assert_dyadic("cube crease", &tagged(&cube, &[(0, 10.0), (1, 10.0), (2, 10.0)], &[]), cc());
    assert_dyadic("cube semi-sharp", &tagged(&cube, &[(0, 1.5), (3, 0.5)], &[]), cc());
    assert_dyadic("cube corner", &tagged(&cube, &[], &[(0, 10.0), (5, 2.0)]), cc());
    let chaikin = cc().with_crease_method(CreaseMethod::Chaikin);
    assert_dyadic("cube chaikin", &tagged(&cube, &[(0, 1.5), (1, 2.5), (2, 10.0)], &[]), chaikin);
    let grid = shapes::quad_grid(4, 4);
    // A crease across the grid's middle row of edges.
    let t = grid.topology();
    let row: Vec<(u32, f32)> = t
        .edges()
        .filter(|&e| {
            let (a, b) = t.edge_vertices(e);
            let (pa, pb) = (grid.position(a), grid.position(b));
            pa.y == 2.0 && pb.y == 2.0
        })
        .map(|e| (e.0, 10.0))
        .collect();
    assert_dyadic("grid crease", &tagged(&grid, &row, &[]), cc());
}

#[test]
fn loop_closed_and_open() {
    assert_dyadic("icosahedron", &shapes::icosahedron(), lp());
    assert_dyadic("octahedron", &shapes::octahedron(), lp());
    assert_dyadic("tetrahedron", &shapes::tetrahedron(), lp());
    assert_dyadic("triangle grid", &shapes::triangle_grid(3, 3), lp());
    let edge_only = lp().with_boundary(BoundaryInterpolation::EdgeOnly);
    assert_dyadic("triangle grid edge-only", &shapes::triangle_grid(3, 2), edge_only);
    let none = lp().with_boundary(BoundaryInterpolation::None);
    assert_dyadic("triangle grid none", &shapes::triangle_grid(3, 2), none);
    let loop_beta = Options::new(Scheme::Loop(LoopBeta::Loop));
    assert_dyadic("icosahedron loop beta", &shapes::icosahedron(), loop_beta);
}

#[test]
fn loop_tags() {
    let ico = shapes::icosahedron();
    assert_dyadic("ico crease", &tagged(&ico, &[(0, 10.0), (1, 10.0)], &[]), lp());
    assert_dyadic("ico semi", &tagged(&ico, &[(0, 1.5), (4, 0.5)], &[(3, 10.0)]), lp());
}
