//! At a dart (a vertex with one infinitely sharp edge) the evaluator returns
//! the limit itself (the dominant left eigenvector of the local subdivision
//! matrix), and so does `subdivide --limit` by default
//! (`DartLimit::Exact`: the dart's own mask): the two agree at every level.
//! Under `DartLimit::SmoothMask` `--limit` uses the smooth limit mask, as
//! OpenSubdiv's `Limit` does: an approximation whose value changes level by
//! level; those points must converge to the evaluator's geometrically, and
//! Aitken's extrapolation of the last three must agree with it.

use subdiv_eval::{LimitSurface, SurfaceParam};
use subdiv_mesh::{shapes, Mesh, Tags};
use subdiv_rules::LoopBeta;
use subdiv_stencil::{DartLimit, Options, Scheme};

fn with_edge_tags(mesh: &Mesh, edges: &[u32]) -> Mesh {
    let t = mesh.topology();
    let mut e = vec![0f32; t.edge_count()];
    for &i in edges {
        e[i as usize] = 10.0;
    }
    mesh.clone().with_tags(Tags::from_arrays(t, e, Vec::new()).unwrap())
}

fn check_dart(mesh: &Mesh, options: Options, vertex: u32, param: SurfaceParam) {
    let surface = LimitSurface::new(mesh, &options).unwrap();
    let ours = surface.evaluate(mesh.positions(), param).unwrap().position;
    // The limit row (the dart mask) at every level is the evaluator's point.
    let d = mesh.bbox_diagonal();
    for l in 0..=4 {
        let row = subdiv_stencil::subdivide(mesh, options, l, true).unwrap().positions()[vertex as usize];
        let gap = (row - ours).length() / d;
        assert!(gap < 1e-12, "level {l}: the limit row is {gap:e}·d from the evaluator");
    }
    // The same point as weights: the evaluator's stencil is the plan's limit row.
    let stencil = surface.stencil(param).unwrap();
    let plan = subdiv_stencil::SubdivisionPlan::with_tags(mesh.topology(), mesh.tags(), options, 0).unwrap();
    let limit = plan.limit_stencil().unwrap().unwrap();
    let mut dense = vec![0.0; mesh.positions().len()];
    limit.outer_view(vertex as usize).unwrap().iter().for_each(|(j, &w)| dense[j] += w);
    stencil.indices.iter().zip(&stencil.position).for_each(|(&j, &w)| dense[j as usize] -= w);
    let off = dense.iter().fold(0.0f64, |m, w| m.max(w.abs()));
    assert!(off < 1e-12, "the evaluator's weights differ from the limit row by {off:e}");

    // OpenSubdiv's smooth mask: an approximation that converges to the limit.
    let options = options.with_dart_limit(DartLimit::SmoothMask);
    let levels: Vec<_> = (1..=8)
        .map(|l| subdiv_stencil::subdivide(mesh, options, l, true).unwrap().positions()[vertex as usize])
        .collect();
    let errors: Vec<f64> = levels.iter().map(|x| (*x - ours).length()).collect();
    assert!(errors[7] < 1e-2 * errors[0], "{errors:?}");
    let ratio = errors[7] / errors[6];
    assert!(ratio > 0.1 && ratio < 0.9, "not geometric: {errors:?}");
    let (x0, x1, x2) = (levels[5], levels[6], levels[7]);
    let aitken = glam::DVec3::from_array([0, 1, 2].map(|c| {
        let (a, b, z) = (x0[c], x1[c], x2[c]);
        let den = z - 2.0 * b + a;
        if den.abs() < 1e-300 {
            z
        } else {
            z - (z - b) * (z - b) / den
        }
    }));
    assert!((aitken - ours).length() < 1e-1 * errors[7], "aitken {aitken} ours {ours} {errors:?}");
}

#[test]
fn catmull_clark_dart_is_the_limit_of_the_levels() {
    // Cube with edges 0-2, 2-3, 3-1 sharp: vertices 0 and 1 are darts.
    let mesh = with_edge_tags(&shapes::cube(), &[0, 1, 2]);
    check_dart(&mesh, Options::new(Scheme::CatmullClark), 0, SurfaceParam::new(0, 0, 0.0, 0.0));
}

#[test]
fn loop_dart_is_the_limit_of_the_levels() {
    let mesh = with_edge_tags(&shapes::icosahedron(), &[0]);
    let t = mesh.topology();
    let (a, _) = t.edge_vertices(subdiv_mesh::EdgeId(0));
    let corner = t.vertex_corners(a).next().unwrap();
    let uv = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)][corner.index as usize];
    let param = SurfaceParam::new(corner.face.0, 0, uv.0, uv.1);
    check_dart(&mesh, Options::new(Scheme::Loop(LoopBeta::default())), a.0, param);
}
