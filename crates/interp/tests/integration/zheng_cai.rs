//! Zheng & Cai 2005: exact interpolation whatever ITE_MAX and the sweep, an
//! independent check from the control mesh alone, prescribed normals, Brunet
//! shape handles, subsets, and random polygon meshes.
//!
//! Measured numbers are printed; run with `-- --nocapture` to see them
//! (`--release -- --ignored --nocapture` for the timings).

use crate::support::fixture;
use glam::DVec3;
use proptest::prelude::*;
use std::collections::HashMap;
use subdiv_interp::CornerRule;
use subdiv_interp::{zheng_cai, InterpError, Interpolant, LimitAssociation, Parameter, SolverChoice, ZhengCaiOptions};
use subdiv_mesh::{newell_normal, shapes, FaceId, FaceList, Mesh, Topology, VertexId};
use subdiv_solve::{Solver, SweepOrder};
use subdiv_stencil::doo_sabin;
use subdiv_stencil::{apply, Scheme, SubdivisionPlan};

/// Round-off bound on the interpolation error, relative to d.
const EXACT: f64 = 1e-12;

/// Closed and open fixtures of every face mix (polygons, quads, triangles, boundaries).
const FIXTURES: &[&str] = &[
    "canonical/tetrahedron.obj",
    "canonical/cube_quad.obj",
    "canonical/octahedron.obj",
    "canonical/icosahedron.obj",
    "canonical/dodecahedron.obj",
    "canonical/pyramid_mixed.obj",
    "canonical/hexagonal_prism.obj",
    "canonical/cross3d_quad.obj",
    "canonical/icosphere_2.obj",
    "canonical/torus_quad_16x8.obj",
    "canonical/grid_quad_8x8_open.obj",
    "poly/mpi.off",
    "poly/P.off",
    "poly/cube_poly.off",
    "poly/corner_poly.off",
    "poly/chamfer-cube.off",
    "poly/mesh_with_colors.off",
    "quad/spot_control_mesh.obj",
    "quad/penguin_control_mesh.obj",
    "quad/3torus.off",
    "quad/torus_quad.off",
    "quad/cross_quad.off",
    "quad/fandisk_quads.off",
    "tri/decimated-knight.off",
    "tri/eight.off",
    "open/halftunnel.off",
    "open/nefertiti_small.off",
    "open/grid.off",
    "open/hemisphere.off",
];

/// Flags of the vertices that lie on a face (isolated ones have no limit point).
fn on_faces(mesh: &Mesh) -> Vec<bool> {
    let t = mesh.topology();
    t.vertices().map(|v| !t.is_isolated(v)).collect()
}

fn options(ite_max: usize, jacobi: bool) -> ZhengCaiOptions {
    let solver = if jacobi { SolverChoice::Use(Solver::Jacobi) } else { SolverChoice::Auto };
    ZhengCaiOptions::default().with_ite_max(ite_max).with_solver(solver)
}

fn max_rel(mesh: &Mesh, result: &Interpolant, flags: &[bool]) -> f64 {
    result.error(mesh.positions(), flags, mesh.bbox_diagonal()).max_rel
}

/// Sign-insensitive angle between two directions, in radians.
fn line_angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b).abs())
}

/// Signed volume of a closed polygon mesh (divergence theorem, fans from each face's first corner).
fn volume(mesh: &Mesh) -> f64 {
    let p = mesh.positions();
    let mut vol = 0.0;
    for face in mesh.topology().faces().iter() {
        for k in 1..face.len() - 1 {
            let (a, b, c) = (p[face[0] as usize], p[face[k] as usize], p[face[k + 1] as usize]);
            vol += a.dot(b.cross(c)) / 6.0;
        }
    }
    vol
}

// ---- the independent check: one plain Doo-Sabin step of the output only ----

/// Every limit point one plain Doo-Sabin step exposes: the face centroids of
/// the refined mesh and the midpoints of consecutive vertices of its boundary
/// loops (points of the quadratic B-spline boundary).
fn exposed_limit_points(control: &Mesh) -> Vec<DVec3> {
    let plan = SubdivisionPlan::new(control.topology(), Scheme::DooSabin, 1).unwrap();
    let refined = plan.subdivide(control, false).unwrap();
    let t = refined.topology();
    let mut points = refined.face_centroids();
    for lp in t.boundary_loops() {
        points.extend(lp.iter().map(|&h| (refined.position(t.he_from(h)) + refined.position(t.he_to(h))) / 2.0));
    }
    points
}

/// For every target, the distance to the nearest candidate, relative to d
/// (uniform grid of cell d/50; targets with no candidate in their 27 cells
/// report +∞, i.e. "farther than d/50").
fn nearest_distances(targets: &[DVec3], candidates: &[DVec3], d: f64) -> Vec<f64> {
    let cell = d / 50.0;
    let key = |p: DVec3| {
        let k = (p / cell).floor();
        (k.x as i64, k.y as i64, k.z as i64)
    };
    let mut grid: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
    for (i, &c) in candidates.iter().enumerate() {
        grid.entry(key(c)).or_default().push(i);
    }
    targets
        .iter()
        .map(|&p| {
            let (x, y, z) = key(p);
            let mut best = f64::INFINITY;
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        for &i in grid.get(&(x + dx, y + dy, z + dz)).map_or(&[][..], Vec::as_slice) {
                            best = best.min(candidates[i].distance(p));
                        }
                    }
                }
            }
            best / d
        })
        .collect()
}

fn worst(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(0.0, f64::max)
}

#[test]
fn every_fixture_is_interpolated_to_round_off_for_any_ite_max_and_sweep() {
    println!(
        "{:<34} {:>6} | sweeps GS 0/1/5, Jacobi 0/1/5 | max |I − Z·M⁰|/d at ITE_MAX 5 | max error/d",
        "fixture", "V"
    );
    for name in FIXTURES {
        let mesh = fixture(name);
        let flags = on_faces(&mesh);
        let (mut sweeps, mut errors, mut residual) = (Vec::new(), Vec::new(), 0.0);
        for jacobi in [false, true] {
            for ite_max in [0, 1, 5] {
                let result = zheng_cai::interpolate(&mesh, &options(ite_max, jacobi)).unwrap();
                let summary = result.solve.as_ref().unwrap();
                assert!(summary.iterations <= ite_max);
                assert_eq!(summary.history.len(), summary.iterations);
                if ite_max == 5 && !jacobi {
                    residual = summary.residual;
                }
                sweeps.push(summary.iterations);
                let err = max_rel(&mesh, &result, &flags);
                assert!(err <= EXACT, "{name}, ITE_MAX {ite_max}, jacobi {jacobi}: error {err:e}");
                errors.push(err);
            }
        }
        println!(
            "{name:<34} {:>6} | {sweeps:?} | {residual:9.2e} | {:9.2e}",
            mesh.topology().vertex_count(),
            worst(errors)
        );
    }
}

#[test]
fn the_paper_stopping_rule_is_the_update_size() {
    // decimated-knight (502 vertices) is the size of the paper's first example
    // (562 vertices, "three iterations with an iterative termination threshold of 0.3%").
    let mesh = fixture("tri/decimated-knight.off");
    let d = mesh.bbox_diagonal();
    let aux = zheng_cai::auxiliary_mesh(&mesh, &ZhengCaiOptions::default().with_ite_max(100)).unwrap();
    let s = &aux.summary;
    println!("decimated-knight, EPS 0.3 %: {} sweeps, max update / d per sweep {:?}", s.iterations, s.history);
    assert!(s.converged);
    assert!(*s.history.last().unwrap() <= 0.003);
    assert!(s.history[..s.history.len() - 1].iter().all(|&u| u > 0.003), "stops at the first small sweep");
    // The recorded update is the real one: M⁰ after k and after k − 1 sweeps differ by it.
    let sweeps = |k| zheng_cai::auxiliary_mesh(&mesh, &ZhengCaiOptions::default().with_ite_max(k).with_eps(0.0));
    for k in 1..=s.iterations {
        let (before, after) = (sweeps(k - 1).unwrap(), sweeps(k).unwrap());
        assert!(!after.summary.converged);
        let moved = worst(before.mesh.positions().iter().zip(after.mesh.positions()).map(|(p, q)| p.distance(*q) / d));
        assert!((moved - s.history[k - 1]).abs() <= 1e-12 * moved, "sweep {k}: {moved:e} vs {:e}", s.history[k - 1]);
        if k == s.iterations {
            assert_eq!(after.mesh.positions(), aux.mesh.positions());
        }
    }
    // EPS = 0 runs ITE_MAX sweeps, unless one moves nothing at all (a fixed
    // point in floating point), and the update shrinks geometrically (spec(Z) ⊂ [½, 1]).
    let long = zheng_cai::auxiliary_mesh(&mesh, &ZhengCaiOptions::default().with_ite_max(30).with_eps(0.0)).unwrap();
    let h = &long.summary.history;
    let last = *h.last().unwrap();
    assert!(h.len() == 30 || (h.len() < 30 && last == 0.0 && long.summary.converged), "{} sweeps", h.len());
    println!("EPS 0: {} sweeps, update {:.2e} → {:.2e}, residual {:.2e}", h.len(), h[0], last, long.summary.residual);
    assert!(last < 1e-12 && long.summary.residual < 1e-12);
}

/// The paper's sweeps (Eq. 7), run to convergence, reach the solution that
/// LDLᵀ finds for Z·M⁰ = I.
#[test]
fn the_paper_sweeps_converge_to_the_direct_solution_of_z() {
    for name in ["poly/mpi.off", "open/nefertiti_small.off", "open/halftunnel.off", "tri/decimated-knight.off"] {
        let mesh = fixture(name);
        let d = mesh.bbox_diagonal();
        for jacobi in [false, true] {
            let swept =
                zheng_cai::auxiliary_mesh(&mesh, &options(0, jacobi).with_ite_max(200).with_eps(1e-15)).unwrap();
            let direct = zheng_cai::auxiliary_mesh(
                &mesh,
                &ZhengCaiOptions::default()
                    .with_ite_max(10)
                    .with_eps(1e-14)
                    .with_solver(SolverChoice::Use(Solver::Ldl)),
            )
            .unwrap();
            let gap =
                worst(swept.mesh.positions().iter().zip(direct.mesh.positions()).map(|(p, q)| p.distance(*q) / d));
            assert!(gap <= 1e-12, "{name}, jacobi {jacobi}: {gap:e}");
            assert!(swept.summary.residual <= 1e-13 && direct.summary.residual <= 1e-13, "{name}");
        }
    }
}

#[test]
fn other_solvers_on_z_also_interpolate_and_solve_z_when_given_the_budget() {
    for name in ["poly/mpi.off", "quad/spot_control_mesh.obj", "open/nefertiti_small.off", "open/halftunnel.off"] {
        let mesh = fixture(name);
        let flags = on_faces(&mesh);
        for solver in
            [Solver::Cg { jacobi: true }, Solver::Ldl, Solver::GaussSeidel(SweepOrder::Multicolor), Solver::Pia]
        {
            for (ite_max, eps) in [(1, 0.003), (200, 1e-13)] {
                let opts = ZhengCaiOptions::default()
                    .with_ite_max(ite_max)
                    .with_eps(eps)
                    .with_solver(SolverChoice::Use(solver));
                let result = zheng_cai::interpolate(&mesh, &opts).unwrap();
                let err = max_rel(&mesh, &result, &flags);
                let s = result.solve.as_ref().unwrap();
                assert_eq!(s.solver, solver.name());
                assert!(err <= EXACT, "{name} {solver}: {err:e}");
                if ite_max == 200 {
                    // Given the budget, the solver solves Z·M⁰ = I itself (both stages on open meshes).
                    assert!(s.converged && s.residual <= 1e-12, "{name} {solver}: residual {:e}", s.residual);
                }
            }
        }
    }
}

#[test]
fn independent_check_one_plain_step_of_the_output_has_a_limit_point_at_every_input_vertex() {
    println!("{:<34} {:>9} {:>12} {:>16}", "fixture", "vertices", "max gap/d", "unperturbed, ITE_MAX 0");
    for name in FIXTURES {
        let mesh = fixture(name);
        let d = mesh.bbox_diagonal();
        let result = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default()).unwrap();
        let targets: Vec<DVec3> =
            mesh.topology().vertices().filter(|&v| !mesh.topology().is_isolated(v)).map(|v| mesh.position(v)).collect();
        let gap = worst(nearest_distances(&targets, &exposed_limit_points(&result.control), d));
        assert!(gap <= EXACT, "{name}: an input vertex is {gap:e}·d from every exposed limit point");
        // The check can fail: without the perturbation, the Eq. 4 step of M⁰ = I
        // (ITE_MAX 0) misses. (With ITE_MAX 5 it may not: Gauss-Seidel solves the
        // octahedron's Z·M⁰ = I exactly in two sweeps.)
        let aux = zheng_cai::auxiliary_mesh(&mesh, &ZhengCaiOptions::default().with_ite_max(0)).unwrap();
        let (t1, _, r) = doo_sabin::refine(mesh.topology(), &CornerRule::Uniform(0.5)).unwrap();
        let unperturbed = Mesh::from_topology(t1, apply(&r, aux.mesh.positions()));
        let miss = worst(nearest_distances(&targets, &exposed_limit_points(&unperturbed), d));
        let miss_text = if miss.is_finite() { format!("{miss:.2e}") } else { "> 2.0e-2".into() };
        println!("{name:<34} {:>9} {gap:>12.2e} {miss_text:>16}", targets.len());
        assert!(miss > 1e3 * EXACT, "{name}: the unperturbed mesh should not interpolate ({miss:e})");
    }
}

// ---- normals (§4.1) ----

/// The faces of `control` that touch a vertex of face `f`, as a separate mesh
/// with `f` first. One Doo-Sabin step maps the 1-ring of a face to (a superset
/// of) the 1-ring of its F-face child, so every level of this patch agrees
/// with the whole mesh on the F-face descendant of `f` and its edge neighbours.
fn patch_around(control: &Mesh, f: FaceId) -> Mesh {
    let t = control.topology();
    let mut faces: Vec<FaceId> = vec![f];
    for &w in t.face(f) {
        for c in t.vertex_corners(VertexId(w)) {
            if !faces.contains(&c.face) {
                faces.push(c.face);
            }
        }
    }
    let mut index: HashMap<u32, u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut list = FaceList::new();
    for &g in &faces {
        let local: Vec<u32> = t
            .face(g)
            .iter()
            .map(|&v| {
                *index.entry(v).or_insert_with(|| {
                    positions.push(control.position(VertexId(v)));
                    positions.len() as u32 - 1
                })
            })
            .collect();
        list.push(&local);
    }
    Mesh::new(positions, list).expect("the faces around a face form a disk")
}

/// Per level 1..=levels: the angle of the F-face descendant of face 0 to
/// `normal`, and the largest angle of its edge-neighbours to `normal`.
fn normal_angles(patch: &Mesh, normal: DVec3, levels: usize) -> Vec<(f64, f64)> {
    let plan = SubdivisionPlan::new(patch.topology(), Scheme::DooSabin, levels).unwrap();
    let mut positions = patch.positions().to_vec();
    let mut out = Vec::new();
    for level in plan.levels() {
        positions = apply(level.stencil.as_ref().unwrap(), &positions);
        let t: &Topology = &level.topology;
        let face_normal = |g: FaceId| newell_normal(t.face(g).iter().map(|&v| positions[v as usize]));
        let f = FaceId(0); // F-faces keep their face id across levels
        let ring =
            t.face_half_edges(f).filter_map(|h| t.he_twin(h)).map(|h| line_angle(face_normal(t.he_face(h)), normal));
        out.push((line_angle(face_normal(f), normal), worst(ring)));
    }
    out
}

/// Interpolates with `normals`, then measures every constrained vertex in
/// `sample`; with `settles`, also asserts that the faces around the F-face
/// approach the given plane level by level.
fn check_normals(name: &str, mesh: &Mesh, normals: Vec<Option<DVec3>>, sample: &[usize], settles: bool) -> f64 {
    let levels = 6;
    let with = ZhengCaiOptions::default().with_normals(normals.clone());
    let result = zheng_cai::interpolate(mesh, &with).unwrap();
    let plain = zheng_cai::interpolate(mesh, &ZhengCaiOptions::default()).unwrap();
    assert!(max_rel(mesh, &result, &on_faces(mesh)) <= EXACT, "{name}: normals broke interpolation");
    let v_face = &v_faces(&result.association);
    let (mut worst_face, mut default_min) = (0.0_f64, f64::INFINITY);
    let mut ring_by_level = vec![0.0_f64; levels];
    for &i in sample {
        let n = normals[i].unwrap();
        let f = v_face[i].unwrap();
        let angles = normal_angles(&patch_around(&result.control, f), n, levels);
        worst_face = worst_face.max(worst(angles.iter().map(|a| a.0)));
        angles.iter().enumerate().for_each(|(l, a)| ring_by_level[l] = ring_by_level[l].max(a.1));
        // Control: Eq. 10's average normal is a different plane.
        default_min = default_min.min(line_angle(plain.control.face_normal(f), n));
    }
    println!(
        "{name}: {} constrained vertices measured, F-face normal vs given ≤ {worst_face:.2e} rad (levels 1-{levels}); \
         edge-neighbour faces vs given, max per level {:?}; without the normals the V-face is ≥ {default_min:.2e} rad off",
        sample.len(),
        ring_by_level.iter().map(|a| format!("{a:.2e}")).collect::<Vec<_>>()
    );
    assert!(worst_face <= 1e-3, "{name}: F-face descendant normal {worst_face:e} rad from the given normal");
    if settles {
        // Neighbours approach the tangent plane level by level (ratio ½: DS eigenvalues ¼ / ½).
        assert!(ring_by_level.windows(2).skip(1).all(|w| w[1] < 0.75 * w[0]), "{name}: {ring_by_level:?}");
    }
    default_min
}

/// A uniformly random direction (rejection sampling in a ball shell).
fn random_unit(rng: &mut shapes::SplitMix64) -> DVec3 {
    loop {
        let u = DVec3::new(rng.next_f64() - 0.5, rng.next_f64() - 0.5, rng.next_f64() - 0.5);
        if u.length() > 0.1 && u.length() < 0.5 {
            return u.normalize();
        }
    }
}

#[test]
fn prescribed_normals_are_the_tangent_planes() {
    // icosphere_2: the unit sphere, radial normals at every vertex.
    let sphere = fixture("canonical/icosphere_2.obj");
    let radial: Vec<Option<DVec3>> = sphere.positions().iter().map(|p| Some(p.normalize())).collect();
    let sample: Vec<usize> = (0..sphere.topology().vertex_count()).step_by(11).collect();
    check_normals("icosphere_2 (radial)", &sphere, radial, &sample, true);

    // spot: unit normals at 8 random vertices, Eq. 10 elsewhere. (a) Any direction:
    // the V-face is projected onto an arbitrary plane, possibly almost edge-on, and
    // the F-face still lies in it exactly, but the surface around may fold; the
    // neighbours are reported, not asserted. (b) Within 30° of Eq. 10's normal
    // (a designer's tilt): the neighbours settle onto the plane too.
    let spot = fixture("quad/spot_control_mesh.obj");
    let plain = zheng_cai::interpolate(&spot, &ZhengCaiOptions::default()).unwrap();
    let v_face = &v_faces(&plain.association);
    let mut rng = shapes::SplitMix64(2005);
    let nv = spot.topology().vertex_count();
    let chosen: Vec<usize> = (0..8).map(|_| rng.below(nv)).collect();
    let (mut any, mut tilted) = (vec![None; nv], vec![None; nv]);
    for &i in &chosen {
        any[i] = Some(random_unit(&mut rng));
        let n0 = plain.control.face_normal(v_face[i].unwrap());
        let side = n0.cross(random_unit(&mut rng)).normalize();
        let angle = 30f64.to_radians() * rng.next_f64();
        tilted[i] = Some(n0 * angle.cos() + side * angle.sin());
    }
    let default_min = check_normals("spot (any direction)", &spot, any, &chosen, false);
    assert!(default_min > 1e-2, "the random normals should differ from Eq. 10's");
    check_normals("spot (≤ 30° tilt)", &spot, tilted, &chosen, true);
}

// ---- shape handles (§4.2) ----

#[test]
fn shape_handles_keep_interpolation_and_move_the_surface_monotonically() {
    println!(
        "{:<32} {:>12} {:>12} {:>12}   (volume of the level-4 limit-positioned surface; input volume)",
        "fixture", "S = 0.4", "S = 1", "S = 2.5"
    );
    for name in [
        "canonical/icosphere_2.obj",
        "canonical/dodecahedron.obj",
        "canonical/cube_quad.obj",
        "canonical/torus_quad_16x8.obj",
        "poly/mpi.off",
        "quad/spot_control_mesh.obj",
        "tri/eight.off",
    ] {
        let mesh = fixture(name);
        let nv = mesh.topology().vertex_count();
        let mut volumes = Vec::new();
        for s in [0.4, 1.0, 2.5] {
            let opts = ZhengCaiOptions::default().with_handles(vec![s; nv]);
            let result = zheng_cai::interpolate(&mesh, &opts).unwrap();
            let err = max_rel(&mesh, &result, &on_faces(&mesh));
            assert!(err <= EXACT, "{name}, S = {s}: {err:e}");
            volumes.push(volume(&result.surface(4).unwrap()));
        }
        println!("{name:<32} {:>12.6} {:>12.6} {:>12.6}   ({:.6})", volumes[0], volumes[1], volumes[2], volume(&mesh));
        assert!(
            volumes[0] < volumes[1] && volumes[1] < volumes[2],
            "{name}: volume not increasing with S: {volumes:?}"
        );
    }
    // Open meshes: the boundary V-face is scaled about the boundary curve point.
    for name in ["open/nefertiti_small.off", "open/halftunnel.off"] {
        let mesh = fixture(name);
        let nv = mesh.topology().vertex_count();
        for s in [0.4, 2.5] {
            let result = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default().with_handles(vec![s; nv])).unwrap();
            assert!(max_rel(&mesh, &result, &on_faces(&mesh)) <= EXACT, "{name}, S = {s}");
        }
    }
}

#[test]
fn handles_and_normals_combine() {
    let mesh = fixture("canonical/icosphere_2.obj");
    let nv = mesh.topology().vertex_count();
    let opts = ZhengCaiOptions::default()
        .with_normals(mesh.positions().iter().map(|p| Some(p.normalize())).collect::<Vec<_>>())
        .with_handles((0..nv).map(|i| if i % 2 == 0 { 0.4 } else { 2.5 }).collect::<Vec<_>>());
    let result = zheng_cai::interpolate(&mesh, &opts).unwrap();
    assert!(max_rel(&mesh, &result, &on_faces(&mesh)) <= EXACT);
    let v_face = &v_faces(&result.association);
    for (i, p) in mesh.positions().iter().enumerate() {
        let angle = line_angle(result.control.face_normal(v_face[i].unwrap()), p.normalize());
        assert!(angle <= 1e-9, "vertex {i}: V-face {angle:e} rad off the given normal after the homothety");
    }
}

// ---- subsets ----

#[test]
fn a_subset_is_interpolated_and_the_other_vertices_are_not_perturbed() {
    for name in ["quad/spot_control_mesh.obj", "poly/mpi.off", "open/nefertiti_small.off", "tri/eight.off"] {
        let mesh = fixture(name);
        let t = mesh.topology();
        let subset: Vec<u32> = (0..t.vertex_count() as u32).step_by(3).collect();
        let flags: Vec<bool> = (0..t.vertex_count()).map(|i| i % 3 == 0).collect();
        let others: Vec<bool> = flags.iter().map(|f| !f).collect();
        let opts = ZhengCaiOptions::default().with_subset(subset);
        let result = zheng_cai::interpolate(&mesh, &opts).unwrap();
        let err = max_rel(&mesh, &result, &flags);
        assert!(err <= EXACT, "{name}: subset error {err:e}");
        // M⁰ keeps the data at the other vertices (§2: V_j = I_j) ...
        let aux = zheng_cai::auxiliary_mesh(&mesh, &opts).unwrap();
        for v in t.vertices().filter(|v| others[v.index()]) {
            assert_eq!(aux.mesh.position(v), mesh.position(v));
        }
        // ... and their V-faces in M¹ are exactly the plain Eq. 4 step of M⁰.
        let (t1, dual) = subdiv_mesh::refine::dual_split(t);
        let plain = doo_sabin::first_step(t, &CornerRule::Uniform(0.5), aux.mesh.positions()).unwrap();
        let mut compared = 0;
        for v in t.vertices().filter(|v| others[v.index()]) {
            for &w in t1.face(dual.vertex_face[v.index()].unwrap()) {
                assert_eq!(result.control.positions()[w as usize], plain[w as usize], "{name}: vertex {v} perturbed");
                compared += 1;
            }
        }
        // The interpolated ones did move (otherwise this test proves nothing).
        let moved = t
            .vertices()
            .filter(|v| flags[v.index()])
            .flat_map(|v| t1.face(dual.vertex_face[v.index()].unwrap()).to_vec())
            .filter(|&w| result.control.positions()[w as usize] != plain[w as usize])
            .count();
        let other_err = result.error(mesh.positions(), &others, mesh.bbox_diagonal());
        println!(
            "{name}: subset error {err:.2e}; {compared} M¹ vertices of the other vertices unchanged, {moved} moved; \
             the other vertices' limit points are {:.2e}·d (max) from their data",
            other_err.max_rel
        );
        assert!(moved > 0 && other_err.max_rel > 1e-6);
    }
}

// ---- ITE_MAX ----

#[test]
fn ite_max_changes_the_auxiliary_mesh_not_the_error() {
    for name in ["quad/spot_control_mesh.obj", "poly/mpi.off", "tri/decimated-knight.off", "open/halftunnel.off"] {
        let mesh = fixture(name);
        let d = mesh.bbox_diagonal();
        let flags = on_faces(&mesh);
        let run = |ite_max| {
            zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default().with_ite_max(ite_max).with_eps(0.0)).unwrap()
        };
        let (r0, r5, r50) = (run(0), run(5), run(50));
        let (e0, e5) = (max_rel(&mesh, &r0, &flags), max_rel(&mesh, &r5, &flags));
        assert!(e0 <= EXACT && e5 <= EXACT);
        let gap = |a: &Mesh, b: &Mesh| worst(a.positions().iter().zip(b.positions()).map(|(p, q)| p.distance(*q) / d));
        let control = gap(&r0.control, &r5.control);
        let control_to_solved = gap(&r5.control, &r50.control);
        let surface = gap(&r0.surface(3).unwrap(), &r5.surface(3).unwrap());
        let (res0, res5) = (r0.solve.as_ref().unwrap().residual, r5.solve.as_ref().unwrap().residual);
        println!(
            "{name}: error ITE_MAX 0 {e0:.2e}, 5 {e5:.2e}; |I − Z·M⁰|/d {res0:.2e} → {res5:.2e}; \
             M¹ differs by {control:.2e}·d (ITE_MAX 5 vs 50: {control_to_solved:.2e}·d), level-3 surface by {surface:.2e}·d"
        );
        assert!(res5 < 0.1 * res0, "the sweeps reduce the residual the perturbation has to absorb");
        assert!(control > 1e-6, "ITE_MAX changes the control mesh");
    }
}

// ---- bad input ----

#[test]
fn bad_parameters_are_refused_naming_the_vertex() {
    let open = fixture("open/nefertiti_small.off");
    let t = open.topology();
    let nv = t.vertex_count();
    let b = t.vertices().find(|&v| t.is_boundary_vertex(v)).unwrap();
    let mut normals = vec![None; nv];
    normals[b.index()] = Some(DVec3::Z);
    let err = zheng_cai::interpolate(&open, &ZhengCaiOptions::default().with_normals(normals)).unwrap_err();
    assert!(
        matches!(&err, InterpError::InvalidParameter { parameter: Parameter::Normals, reason: m }
            if m.contains(&format!("vertex {}", b.0)) && m.contains("boundary")),
        "{err}"
    );

    let closed = fixture("poly/mpi.off");
    let nv = closed.topology().vertex_count();
    let cases: Vec<(ZhengCaiOptions, &str, Parameter)> = vec![
        (ZhengCaiOptions::default().with_normals(vec![None; nv - 1]), "normals for", Parameter::Normals),
        (
            ZhengCaiOptions::default()
                .with_normals((0..nv).map(|i| (i == 7).then_some(DVec3::ZERO)).collect::<Vec<_>>()),
            "vertex 7",
            Parameter::Normals,
        ),
        (
            ZhengCaiOptions::default()
                .with_normals((0..nv).map(|i| (i == 4).then_some(DVec3::X)).collect::<Vec<_>>())
                .with_subset(vec![0, 1, 2]),
            "vertex 4 has a normal but is not interpolated",
            Parameter::Normals,
        ),
        (ZhengCaiOptions::default().with_handles(vec![1.0; nv + 1]), "shape handles for", Parameter::Handles),
        (
            ZhengCaiOptions::default()
                .with_handles((0..nv).map(|i| if i == 9 { -1.0 } else { 1.0 }).collect::<Vec<_>>()),
            "vertex 9",
            Parameter::Handles,
        ),
        (
            ZhengCaiOptions::default()
                .with_handles((0..nv).map(|i| if i == 3 { f64::NAN } else { 1.0 }).collect::<Vec<_>>()),
            "vertex 3",
            Parameter::Handles,
        ),
        (ZhengCaiOptions::default().with_eps(-1.0), "EPS", Parameter::Eps),
        (ZhengCaiOptions::default().with_subset(vec![nv as u32]), "does not exist", Parameter::Subset),
    ];
    for (opts, needle, expected) in cases {
        let err = zheng_cai::interpolate(&closed, &opts).unwrap_err();
        assert!(
            matches!(&err, InterpError::InvalidParameter { parameter, reason } if reason.contains(needle) && *parameter == expected),
            "expected {needle:?} about {expected}, got {err}"
        );
    }
    // Interior valence 2 (no V-face, the digon is left out) is interpolated:
    // the pillow, all of whose vertices have valence 2.
    let pillow = shapes::pillow();
    let result = zheng_cai::interpolate(&pillow, &ZhengCaiOptions::default()).unwrap();
    assert!(max_rel(&pillow, &result, &on_faces(&pillow)) <= EXACT);
}

#[test]
fn isolated_vertices_are_left_out_with_a_warning() {
    let cube = shapes::cube();
    let mut positions = cube.positions().to_vec();
    positions.push(DVec3::new(5.0, 5.0, 5.0));
    let mesh = Mesh::new(positions, cube.topology().faces().clone()).unwrap();
    let result = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default()).unwrap();
    assert!(result.warnings.iter().any(|w| w.contains("isolated")), "{:?}", result.warnings);
    assert_eq!(result.parameters.interpolated_vertices, Some(8));
    assert!(max_rel(&mesh, &result, &on_faces(&mesh)) <= EXACT);
}

#[test]
fn the_report_says_what_was_run() {
    let mesh = fixture("poly/P.off");
    let result = zheng_cai::interpolate(&mesh, &options(5, true)).unwrap();
    // As the report writes them.
    let p = serde_json::to_value(&result.parameters).unwrap();
    assert_eq!(p["solver"], "jacobi");
    assert_eq!(p["ite_max"], 5);
    assert_eq!(p["eps"], 0.003);
    assert_eq!(p["history"], "max update / d per sweep");
    assert_eq!(result.solve.as_ref().unwrap().solver, "jacobi");
    assert_eq!(result.scheme, subdiv_stencil::Scheme::DooSabin);
    assert_eq!(result.method.name(), "zheng-cai");
}

// ---- random polygon meshes ----

fn random_closed_mesh() -> impl Strategy<Value = Mesh> {
    let plate = (3usize..28, 3usize..28, 0usize..3, any::<u64>()).prop_map(|(nx, ny, holes, seed)| {
        // Up to two holes (genus 0-2), off the border and not touching.
        let mut list = Vec::new();
        if holes >= 1 && nx >= 3 && ny >= 3 {
            list.push((1, 1));
        }
        if holes >= 2 && nx >= 5 && ny >= 5 {
            list.push((nx - 2, ny - 2));
        }
        (shapes::plate_with_holes(nx, ny, &list, true), seed)
    });
    let torus = (3usize..45, 3usize..45, any::<u64>()).prop_map(|(nu, nv, seed)| (shapes::torus(nu, nv), seed));
    // Polygon mixes often have interior valence-2 vertices (two merges at one
    // valence-4 vertex); a few split edges add more, some adjacent.
    (prop_oneof![plate, torus], 0.0..0.3f64, 0.0..0.5f64, 0.0..0.3f64, 0usize..4)
        .prop_map(|((base, seed), merge, split, jitter, splits)| {
            let mix = shapes::polygon_mix(&base, seed, merge, split, jitter);
            let ne = mix.topology().edge_count();
            let edges: Vec<subdiv_mesh::EdgeId> = (0..splits)
                .map(|k| subdiv_mesh::EdgeId(((seed as usize).wrapping_add(k * 7919) % ne) as u32))
                .collect();
            let mut edges = edges;
            edges.sort();
            edges.dedup();
            shapes::split_edges(&mix, &edges, 0.05)
        })
        .prop_filter("10 to 2000 vertices", |m| (10..=2000).contains(&m.topology().vertex_count()))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn random_closed_polygon_meshes_are_interpolated(mesh in random_closed_mesh(), ite_max in 0usize..6, jacobi: bool) {
        let result = zheng_cai::interpolate(&mesh, &options(ite_max, jacobi)).unwrap();
        let err = max_rel(&mesh, &result, &on_faces(&mesh));
        let t = mesh.topology();
        let largest = t.face_ids().map(|f| t.face_size(f)).max().unwrap();
        prop_assert!(err <= EXACT, "error {:e} on {} vertices, genus {:?}, faces up to {largest}-gons", err, t.vertex_count(), t.genus());
    }
}

// ---- timing ---------------------------------------------------------------------
// Release: `cargo test --release -p subdiv-interp --test integration zheng_cai:: -- --ignored --nocapture`.

#[test]
#[ignore = "timing; run in release"]
fn timing() {
    for name in
        ["quad/spot_control_mesh.obj", "tri/decimated-knight.off", "tri/armadillo.obj", "quad/sword-quad-dominant.obj"]
    {
        let mesh = fixture(name);
        let start = std::time::Instant::now();
        let result = zheng_cai::interpolate(&mesh, &ZhengCaiOptions::default()).unwrap();
        let total = start.elapsed().as_secs_f64();
        let err = max_rel(&mesh, &result, &on_faces(&mesh));
        let s = result.solve.as_ref().unwrap();
        let aux_start = std::time::Instant::now();
        let _ = zheng_cai::auxiliary_mesh(&mesh, &ZhengCaiOptions::default()).unwrap();
        let aux = aux_start.elapsed().as_secs_f64();
        println!(
            "{name}: {} vertices → M¹ {} vertices; setup {:.2} ms, solve {:.2} ms, total {:.2} ms (auxiliary mesh alone {:.2} ms, {} sweeps); error {err:.2e}",
            mesh.topology().vertex_count(),
            result.control.topology().vertex_count(),
            1e3 * result.setup_seconds,
            1e3 * result.solve_seconds,
            1e3 * total,
            1e3 * aux,
            s.iterations
        );
        assert!(err <= EXACT);
    }
}

/// The V-face of every input vertex in Zheng-Cai's M¹ (`None` where its
/// limit point is not a face centroid).
fn v_faces(association: &LimitAssociation) -> Vec<Option<subdiv_mesh::FaceId>> {
    let LimitAssociation::DualSites(sites) = association else { panic!("Zheng-Cai gives a dual-site association") };
    sites.iter().map(|s| if let subdiv_stencil::DualLimitSite::FaceCentroid(f) = s { Some(*f) } else { None }).collect()
}
