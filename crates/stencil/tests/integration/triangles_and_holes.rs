//! OpenSubdiv's smooth triangle rule (`TRI_SUB_SMOOTH`) and holes (hole
//! tags, boundary `none`), checked independently: the edge points next to a
//! triangle recomputed from the rule's formula on face centroids, limits
//! against many levels of refinement, and holes against the same mesh
//! without them (a hole moves no point).

use glam::DVec3;
use subdiv_mesh::{shapes, FaceId, Mesh, Tags};
use subdiv_stencil::{
    limit_points_with_options, subdivide, BoundaryInterpolation, LoopBeta, Options, Scheme, StencilError,
    SubdivisionPlan, TriangleRule,
};

fn smooth() -> Options {
    Options::new(Scheme::CatmullClark).with_triangle_rule(TriangleRule::Smooth)
}

fn centroid(mesh: &Mesh, f: FaceId) -> DVec3 {
    let face = mesh.topology().face(f);
    face.iter().map(|&v| mesh.positions()[v as usize]).sum::<DVec3>() / face.len() as f64
}

/// A pyramid (four triangles on a square) with its apex moved off-centre, so no symmetry hides
/// a wrong weight.
fn pyramid() -> Mesh {
    let p = shapes::pyramid(4);
    let mut positions = p.positions().to_vec();
    let apex = positions.len() - 1;
    positions[apex] += DVec3::new(0.13, -0.07, 0.21);
    p.with_positions(positions)
}

#[test]
fn edge_points_next_to_triangles_follow_opensubdivs_formula() {
    let mesh = pyramid();
    let t = mesh.topology();
    let (nv, nf) = (t.vertex_count(), t.face_count());
    let plain = subdivide(&mesh, Options::new(Scheme::CatmullClark), 1, false).unwrap();
    let rounded = subdivide(&mesh, smooth(), 1, false).unwrap();
    for e in t.edges() {
        let h = t.edge_half_edge(e);
        let g = t.he_twin(h).expect("closed");
        let (a, b) = t.edge_vertices(e);
        let (fa, fb) = (t.he_face(h), t.he_face(g));
        let weight = |f: FaceId| if t.face_size(f) == 3 { 0.470 } else { 0.25 };
        let (wf, ends) = if t.face_size(fa) == 3 || t.face_size(fb) == 3 {
            let wf = 0.5 * (weight(fa) + weight(fb));
            (wf, 0.5 * (1.0 - 2.0 * wf))
        } else {
            (0.25, 0.25)
        };
        let expected = ends * (mesh.position(a) + mesh.position(b)) + wf * (centroid(&mesh, fa) + centroid(&mesh, fb));
        let i = nv + nf + e.index();
        assert!((rounded.positions()[i] - expected).length() < 1e-15, "edge {e:?}");
        // Catmull-Clark's own rule is the ¼ of everything.
        let catmark = 0.25 * (mesh.position(a) + mesh.position(b) + centroid(&mesh, fa) + centroid(&mesh, fb));
        assert!((plain.positions()[i] - catmark).length() < 1e-15, "edge {e:?}");
    }
    // Face and vertex points are Catmull-Clark's.
    assert_eq!(plain.positions()[..nv + nf], rounded.positions()[..nv + nf]);
    // From level 1 on there is no triangle: the rules are the same.
    let two = subdivide(&mesh, smooth(), 2, false).unwrap();
    let again = subdivide(&subdivide(&mesh, smooth(), 1, false).unwrap(), Options::new(Scheme::CatmullClark), 1, false);
    let diff =
        (two.positions().iter().zip(again.unwrap().positions())).map(|(a, b)| (*a - *b).length()).fold(0.0, f64::max);
    assert!(diff < 1e-14, "{diff}");
}

#[test]
fn smooth_triangle_limits_are_the_limits_of_refinement() {
    for mesh in [pyramid(), shapes::tetrahedron(), shapes::pyramid(5)] {
        let d = mesh.bbox_diagonal();
        let n = mesh.topology().vertex_count();
        let limits =
            limit_points_with_options(mesh.topology(), mesh.tags(), smooth(), mesh.positions()).unwrap().unwrap();
        // Brute force: 10 levels, vertex v is still vertex v.
        let fine = subdivide(&mesh, smooth(), 10, false).unwrap();
        let brute =
            (limits.iter().zip(&fine.positions()[..n])).map(|(a, b)| (*a - *b).length() / d).fold(0.0, f64::max);
        assert!(brute < 1e-5, "limit vs 10 levels {brute:.2e}·d");
        // The plan's limit points (general rows) are the same points.
        let plan = SubdivisionPlan::new(mesh.topology(), smooth(), 0).unwrap();
        let planned = plan.limit_points(mesh.positions()).unwrap();
        let dev = (limits.iter().zip(&planned)).map(|(a, b)| (*a - *b).length() / d).fold(0.0, f64::max);
        assert!(dev < 1e-13, "plan {dev:.2e}·d");
        // And they are not Catmull-Clark's (the rule changes the surface).
        let catmark = limit_points_with_options(mesh.topology(), mesh.tags(), Scheme::CatmullClark, mesh.positions())
            .unwrap()
            .unwrap();
        let moved = (limits.iter().zip(&catmark)).map(|(a, b)| (*a - *b).length() / d).fold(0.0, f64::max);
        assert!(moved > 1e-3, "{moved:.2e}·d");
    }
}

#[test]
fn the_smooth_triangle_rule_is_catmull_clarks_alone() {
    let e = Options::new(Scheme::Loop(LoopBeta::Loop)).with_triangle_rule(TriangleRule::Smooth).validate().unwrap_err();
    assert!(matches!(e, StencilError::InvalidParameter(_)), "{e}");
    assert!(e.to_string().contains("Catmull-Clark"), "{e}");
}

#[test]
fn holes_move_no_point_and_pass_to_every_child_face() {
    let torus = shapes::torus(8, 6);
    let holes: Vec<bool> = (0..torus.topology().face_count()).map(|f| f % 7 == 2).collect();
    let count = holes.iter().filter(|&&h| h).count();
    let tagged = torus.clone().with_tags(Tags::none().with_holes(holes.clone()));
    // Every quad and every triangle has four children.
    for scheme in [Scheme::CatmullClark, Scheme::Loop(LoopBeta::Loop)] {
        let (plain, holed) = if scheme == Scheme::CatmullClark {
            (torus.clone(), tagged.clone())
        } else {
            let tri = subdiv_mesh::triangulate(&torus).unwrap().mesh;
            let holes: Vec<bool> = (0..tri.topology().face_count()).map(|f| f % 7 == 2).collect();
            (tri.clone(), tri.with_tags(Tags::none().with_holes(holes)))
        };
        let base = holed.tags().hole_count();
        for levels in 1..=3 {
            let a = subdivide(&plain, scheme, levels, false).unwrap();
            let b = subdivide(&holed, scheme, levels, false).unwrap();
            assert_eq!(a.positions(), b.positions(), "{scheme} level {levels}: holes moved points");
            assert_eq!(b.tags().hole_count(), base * 4usize.pow(levels as u32));
            // The plan gives the same mesh.
            let plan = SubdivisionPlan::with_tags(holed.topology(), holed.tags(), scheme, levels).unwrap();
            assert_eq!(plan.subdivide(&holed, false).unwrap().tags().holes(), b.tags().holes());
        }
    }
    assert!(count > 0);
    // The dual split cannot keep them: refused, never dropped.
    let e = subdivide(&tagged, Scheme::DooSabin, 1, false).unwrap_err();
    assert!(matches!(e, StencilError::TagsNotSupported { .. }), "{e}");
}

#[test]
fn boundary_none_is_edge_only_with_the_boundary_faces_as_holes() {
    let grid = shapes::quad_grid(6, 5);
    let none = Options::new(Scheme::CatmullClark).with_boundary(BoundaryInterpolation::None);
    let edge_only = none.with_boundary(BoundaryInterpolation::EdgeOnly);
    let a = subdivide(&grid, none, 2, false).unwrap();
    let b = subdivide(&grid, edge_only, 2, false).unwrap();
    assert_eq!(a.positions(), b.positions());
    // 30 faces, the inner 4×3 are not at the boundary: 18 holes, 16 children each after two levels.
    assert_eq!(a.tags().hole_count(), 18 * 16);
    assert_eq!(b.tags().hole_count(), 0);
}
