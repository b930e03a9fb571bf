//! Meshes with interior vertices of valence 2 — two faces sharing two
//! consecutive edges, as DCC exports often leave them — for every
//! interpolating method, with the default options: the error is measured
//! by the plain scheme's own rules on the output (`Interpolant::error`) and
//! again, knowing nothing of the method, as the distance from every data
//! point to the nearest limit point the plain scheme exposes on the control
//! mesh (`verify`).

use crate::support::{candidate_limit_points, fixture, nearest_gap, Scheme};
use glam::DVec3;
use subdiv_interp::{
    cheng, deng_wang, fan_cheng_lai, nasri, zheng_cai, ChengOptions, CommonOptions, DengWangOptions,
    FanChengLaiOptions, InterpError, Interpolant, NasriOptions, Parameter, Shape, ZhengCaiOptions,
};
use subdiv_mesh::{shapes, EdgeId, FaceId, Mesh, Topology, VertexId};

const TOL: f64 = 1e-6;

fn interior_edges(t: &Topology) -> Vec<EdgeId> {
    t.edges().filter(|&e| t.edge_faces(e).1.is_some()).collect()
}

/// `mesh` with `count` interior edges split (spread over the mesh), plus
/// one edge split twice, which makes two adjacent valence-2 vertices.
fn with_valence_two(mesh: &Mesh, count: usize, offset: f64) -> Mesh {
    let edges = interior_edges(mesh.topology());
    let step = (edges.len() / (count + 1)).max(1);
    let picked: Vec<EdgeId> = (0..count).map(|k| edges[(k * step + step / 2) % edges.len()]).collect();
    let once = shapes::split_edges(mesh, &picked, offset);
    // The first split vertex's edge towards one end of the old edge: split it again.
    let t = once.topology();
    let first = VertexId(mesh.topology().vertex_count() as u32);
    let h = t.vertex_fan(first)[0];
    shapes::split_edges(&once, &[t.he_edge(h)], -offset)
}

fn valence_two_vertices(t: &Topology) -> Vec<VertexId> {
    t.vertices().filter(|&v| !t.is_boundary_vertex(v) && t.vertex_face_count(v) == 2).collect()
}

/// Closed and open meshes with valence-2 vertices: quads, triangles,
/// polygons, and the two classic small cases.
fn meshes() -> Vec<(String, Mesh)> {
    let mut out = vec![
        ("pillow".to_string(), shapes::pillow()),
        ("cube, one split edge".to_string(), shapes::split_edges(&shapes::cube(), &[EdgeId(0)], 0.1)),
    ];
    for (name, count) in [
        ("quad/spot_control_mesh.obj", 4),
        ("quad/fandisk_quads.off", 3),
        ("poly/mpi.off", 2),
        ("tri/decimated-knight.off", 3),
        ("open/halftunnel.off", 3),
        ("canonical/grid_quad_8x8_open.obj", 2),
    ] {
        out.push((format!("{name} + {} valence-2", count + 1), with_valence_two(&fixture(name), count, 0.05)));
    }
    for (name, mesh) in &out {
        let t = mesh.topology();
        assert!(valence_two_vertices(t).len() >= 2 || name == "cube, one split edge", "{name}");
    }
    out
}

/// Both error measures ≤ `tol`; returns the reported max error.
fn check(name: &str, mesh: &Mesh, result: &Interpolant, plain: Scheme, tol: f64) -> f64 {
    let all = vec![true; mesh.topology().vertex_count()];
    let d = mesh.bbox_diagonal();
    let reported = result.error(mesh.positions(), &all, d);
    assert!(reported.max_rel <= tol, "{name}: reported error {:e}·d", reported.max_rel);
    let v2 = valence_two_vertices(mesh.topology());
    let targets: Vec<DVec3> = v2.iter().map(|&v| mesh.position(v)).collect();
    let candidates = candidate_limit_points(&result.control, plain);
    let independent = nearest_gap(mesh.positions(), &candidates, d);
    assert!(independent <= tol * (1.0 + 1e-9), "{name}: independent error {independent:e}·d");
    let at_v2 = nearest_gap(&targets, &candidates, d);
    assert!(at_v2 <= tol * (1.0 + 1e-9), "{name}: independent error at the valence-2 vertices {at_v2:e}·d");
    reported.max_rel
}

#[test]
fn doo_sabin_methods_interpolate_valence_two_vertices() {
    for (name, mesh) in meshes() {
        let common = CommonOptions::default().with_tol(TOL);
        let r = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default())
            .unwrap_or_else(|e| panic!("zheng-cai {name}: {e}"));
        // Exact by construction (step 4), so round-off.
        let e_zc = check(&format!("zheng-cai {name}"), &mesh, &r, Scheme::DooSabin, 1e-13);
        let r = fan_cheng_lai::interpolate(&mesh, &FanChengLaiOptions::default().with_common(common.clone()))
            .unwrap_or_else(|e| panic!("fan-cheng-lai {name}: {e}"));
        let e_fcl = check(&format!("fan-cheng-lai {name}"), &mesh, &r, Scheme::DooSabin, TOL);
        let r = nasri::interpolate(&mesh, &NasriOptions::default().with_common(common.clone()))
            .unwrap_or_else(|e| panic!("nasri {name}: {e}"));
        let e_nasri = check(&format!("nasri {name}"), &mesh, &r, Scheme::DooSabin, TOL);
        eprintln!("{name}: nasri {e_nasri:.1e}, zheng-cai {e_zc:.1e}, fan-cheng-lai {e_fcl:.1e}");
    }
}

#[test]
fn cheng_and_deng_wang_interpolate_valence_two_vertices() {
    for (name, mesh) in meshes() {
        let r = cheng::interpolate(&mesh, &ChengOptions::default()).unwrap_or_else(|e| panic!("cheng {name}: {e}"));
        let e_cheng = check(&format!("cheng {name}"), &mesh, &r, Scheme::CatmullClark, TOL);
        let r = deng_wang::interpolate(&mesh, &DengWangOptions::default())
            .unwrap_or_else(|e| panic!("deng-wang {name}: {e}"));
        let beta = DengWangOptions::default().beta;
        let e_dw = check(&format!("deng-wang {name}"), &mesh, &r, Scheme::Loop(beta), 1e-13);
        eprintln!("{name}: cheng {e_cheng:.1e}, deng-wang {e_dw:.1e}");
    }
}

/// Per-face λ, subsets and Zheng-Cai's handles and normals on a mesh with
/// valence-2 vertices.
#[test]
fn shape_control_and_subsets_with_valence_two_vertices() {
    let mesh = with_valence_two(&fixture("quad/spot_control_mesh.obj"), 3, 0.05);
    let t = mesh.topology();
    let n = t.vertex_count();
    let d = mesh.bbox_diagonal();
    let v2 = valence_two_vertices(t);
    // Two-phase λ per face, from 0.2 to 0.8.
    let lambdas: Vec<f64> = (0..t.face_count()).map(|f| 0.2 + 0.6 * (f % 7) as f64 / 6.0).collect();
    let opts = FanChengLaiOptions::default().with_shape(Shape::PerFace(lambdas));
    let r = fan_cheng_lai::interpolate(&mesh, &opts).unwrap();
    check("fan-cheng-lai per-face λ", &mesh, &r, Scheme::DooSabin, TOL);
    // A subset that holds the valence-2 vertices and every third other vertex.
    let subset: Vec<u32> = (0..n as u32).filter(|&v| v % 3 == 0 || v2.contains(&VertexId(v))).collect();
    let flags: Vec<bool> = (0..n).map(|v| subset.contains(&(v as u32))).collect();
    let common = CommonOptions::default().with_subset(subset.clone());
    let results = [
        nasri::interpolate(&mesh, &NasriOptions::default().with_common(common.clone())).unwrap(),
        zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default().with_common(common.clone())).unwrap(),
        fan_cheng_lai::interpolate(&mesh, &FanChengLaiOptions::default().with_common(common.clone())).unwrap(),
    ];
    for r in &results {
        assert!(r.error(mesh.positions(), &flags, d).max_rel <= TOL, "{:?}", r.method);
    }
    // Handles everywhere (valence-2 vertices included) keep the interpolation exact
    // and change the surface.
    let handles: Vec<f64> = (0..n).map(|v| if v % 2 == 0 { 0.4 } else { 2.5 }).collect();
    let plain = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default()).unwrap();
    let handled = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default().with_handles(handles)).unwrap();
    check("zheng-cai handles", &mesh, &handled, Scheme::DooSabin, 1e-13);
    let moved =
        plain.control.positions().iter().zip(handled.control.positions()).any(|(a, b)| a.distance(*b) > 1e-3 * d);
    assert!(moved, "the handles change the control mesh");
    // Normals: at ordinary interior vertices next to valence-2 ones they are met;
    // at a valence-2 vertex they are refused, naming the vertex.
    let v = v2[0];
    let mut normals = vec![None; n];
    let neighbour = t.vertex_neighbors(v).find(|&w| !t.is_boundary_vertex(w) && t.valence(w) > 2).unwrap();
    normals[neighbour.index()] = Some(DVec3::new(0.3, 0.9, 0.1));
    let r = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default().with_normals(normals.clone())).unwrap();
    check("zheng-cai normals", &mesh, &r, Scheme::DooSabin, 1e-13);
    normals[v.index()] = Some(DVec3::Z);
    let err = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default().with_normals(normals)).unwrap_err();
    assert!(matches!(err, InterpError::InvalidParameter { parameter: Parameter::Normals, .. }), "{err}");
    assert!(err.to_string().contains(&format!("vertex {v}")) && err.to_string().contains("valence 2"), "{err}");
}

/// The Doo-Sabin limit rows at valence 2 are what the plain scheme does:
/// Nasri's control mesh refined 8 levels keeps, for every valence-2 vertex,
/// a face (the second-level E-face of the edge between its images, and its
/// F-face descendants) whose corners close in on the data point.
#[test]
fn nasri_surface_closes_in_on_valence_two_data_points_by_brute_force() {
    let mesh = shapes::split_edges(&shapes::torus(6, 4), &[EdgeId(0), EdgeId(9)], 0.15);
    let r = nasri::interpolate(&mesh, &NasriOptions::default()).unwrap();
    let t = mesh.topology();
    let d = mesh.bbox_diagonal();
    let plan = subdiv_stencil::SubdivisionPlan::new(t, subdiv_stencil::Scheme::DooSabin, 8).unwrap();
    let levels = plan.levels();
    for v in valence_two_vertices(t) {
        // Level 1: the edge v₀v₁ between the images of v's two corners; level 2: its E-face.
        let [h0, h1] = [t.vertex_fan(v)[0], t.vertex_fan(v)[1]];
        let l1 = &levels[0].topology;
        let h = *l1.vertex_fan(VertexId(h0.0)).iter().find(|&&h| l1.he_to(h) == VertexId(h1.0)).unwrap();
        let e = l1.he_edge(h);
        let origin = &levels[1].dual.as_ref().unwrap().face_origin;
        let f = FaceId(origin.iter().position(|o| *o == subdiv_mesh::refine::DualFace::E(e)).unwrap() as u32);
        let mut x = r.control.positions().to_vec();
        let mut radii = Vec::new();
        for (k, level) in levels.iter().enumerate() {
            x = subdiv_stencil::apply(level.stencil.as_ref().unwrap(), &x);
            if k == 0 {
                continue; // the tracked face exists from level 2 on
            }
            let corners: Vec<DVec3> = level.topology.face(f).iter().map(|&c| x[c as usize]).collect();
            let centroid = corners.iter().sum::<DVec3>() / corners.len() as f64;
            // Face centroids are kept at every level: the data point, to the tolerance.
            assert!(centroid.distance(mesh.position(v)) <= TOL * d, "vertex {v}, level {}", k + 1);
            radii.push(corners.iter().map(|c| c.distance(centroid)).fold(0.0, f64::max) / d);
        }
        // ... and the face shrinks onto it: 6 more levels shrink it ~2⁻⁶.
        let (first, last) = (radii[0], *radii.last().unwrap());
        assert!(last <= first / 40.0 && first > 0.0, "vertex {v}: radii {radii:?}");
    }
}
