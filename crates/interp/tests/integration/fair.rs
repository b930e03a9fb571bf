//! The fair method (issue #18): interpolation checked independently from
//! the control mesh alone on closed and open meshes, quads, triangles and
//! polygons, for its three schemes; a lower thin-plate energy than the exact
//! method's; the reduction to the exact methods as the fairness weight → 0
//! at refine 0; and a property test on generated meshes.

use crate::support;
use crate::support::{bumpy, candidate_limit_points, fixture, nearest_gap};
use proptest::prelude::*;
use subdiv_interp::fair::{self, thin_plate_energy, FairAlgorithm, FairOptions};
use subdiv_interp::{
    cheng, interpolate, nasri, ChengOptions, InterpError, Interpolant, LoopBeta, Method, MethodOptions, NasriOptions,
    SurfaceOptions,
};
use subdiv_mesh::{shapes, Mesh};
use subdiv_stencil::Scheme;

const TOL: f64 = 1e-6;

/// The error ≤ 1e-6·d twice: by the result's own measure and by the
/// nearest candidate limit point of the control mesh (`verify`).
fn check(name: &str, mesh: &Mesh, result: &Interpolant, scheme: Scheme) -> f64 {
    let d = mesh.bbox_diagonal();
    let reported = result.error_all(mesh).max_rel;
    assert!(reported <= TOL, "{name}: reported error {reported:e}");
    let independent = nearest_gap(mesh.positions(), &candidate_limit_points(&result.control, scheme), d);
    assert!(independent <= TOL, "{name}: independent error {independent:e}");
    reported
}

fn cases() -> Vec<(&'static str, Mesh, Scheme)> {
    let cc = Scheme::CatmullClark;
    let lp = Scheme::Loop(LoopBeta::Warren);
    let ds = Scheme::DooSabin;
    vec![
        ("torus quads (closed)", bumpy(shapes::torus(10, 7), 0.02, 1), cc),
        ("grid quads (open)", bumpy(shapes::quad_grid(6, 5), 0.05, 2), cc),
        ("polygon mix (closed)", shapes::polygon_mix(&shapes::torus(10, 8), 3, 0.2, 0.2, 0.1), cc),
        ("spot", fixture("quad/spot_control_mesh.obj"), cc),
        ("halftunnel (open)", fixture("open/halftunnel.off"), cc),
        ("icosahedron Loop (closed)", shapes::icosahedron(), lp),
        ("triangle grid Loop (open)", bumpy(shapes::triangle_grid(5, 4), 0.05, 3), lp),
        ("knight Loop", fixture("tri/decimated-knight.off"), lp),
        ("torus Doo-Sabin (closed)", bumpy(shapes::torus(9, 6), 0.02, 4), ds),
        ("polygon mix Doo-Sabin", shapes::polygon_mix(&shapes::torus(8, 8), 5, 0.2, 0.2, 0.1), ds),
        ("grid Doo-Sabin (open)", bumpy(shapes::quad_grid(5, 5), 0.05, 5), ds),
    ]
}

#[test]
fn interpolates_within_tolerance_measured_independently() {
    for (name, mesh, scheme) in cases() {
        for refine in [0, 1, 2] {
            if scheme == Scheme::DooSabin && refine > 1 {
                continue;
            }
            let opts = FairOptions::default().with_scheme(scheme).unwrap().with_refine(refine).with_tol(TOL);
            let r = fair::interpolate(&mesh, &opts).unwrap_or_else(|e| panic!("{name}, refine {refine}: {e}"));
            assert_eq!(r.method, Method::Fair);
            let e = check(&format!("{name}, refine {refine}"), &mesh, &r, scheme);
            eprintln!("{name} refine {refine}: {e:.2e}, {}", r.solve.as_ref().unwrap());
        }
    }
}

/// The energy of the level-`level` limit surface (relative to the input) of
/// a result whose control mesh is at `control_level`.
fn energy(r: &Interpolant, control_level: usize, level: usize, d: f64) -> f64 {
    let surface = r.surface(level - control_level).unwrap();
    thin_plate_energy(&surface, SurfaceOptions::default(), level as u32, d)
}

#[test]
fn the_energy_is_below_the_exact_methods() {
    for (name, mesh, scheme) in cases() {
        let exact = FairOptions::default().with_scheme(scheme).unwrap().with_refine(0);
        let exact = fair::interpolate(&mesh, &exact).unwrap();
        let fair = fair::interpolate(&mesh, &FairOptions::default().with_scheme(scheme).unwrap()).unwrap();
        // On the level-1 limit points: the quantity fair minimises, where the
        // exact method's refined control mesh is a feasible point.
        let d = mesh.bbox_diagonal();
        let (e0, e1) = (energy(&exact, 0, 1, d), energy(&fair, 1, 1, d));
        assert!(e1 <= e0 * (1.0 + 1e-9), "{name}: {e1} > {e0}");
        // On the level-3 surface, which fair does not see.
        let (f0, f1) = (energy(&exact, 0, 3, d), energy(&fair, 1, 3, d));
        eprintln!("{name}: level 1 {e1:.3e} vs {e0:.3e}, level 3 {f1:.3e} vs {f0:.3e}");
        assert!(f1 < f0, "{name} at level 3: {f1} ≥ {f0}");
    }
}

#[test]
fn the_reported_energy_is_the_thin_plate_energy_of_the_limit_points() {
    let mesh = fixture("quad/spot_control_mesh.obj");
    let r = fair::interpolate(&mesh, &FairOptions::default()).unwrap();
    let reported = r.parameters.energy.unwrap();
    let limit = r.surface(0).unwrap();
    let d = mesh.bbox_diagonal();
    let by_mesh = thin_plate_energy(&limit, SurfaceOptions::default(), 1, d);
    assert!((reported - by_mesh).abs() <= 1e-9 * by_mesh, "{reported} vs {by_mesh}");
}

fn max_gap(a: &Mesh, b: &Mesh) -> f64 {
    a.positions().iter().zip(b.positions()).map(|(p, q)| p.distance(*q)).fold(0.0, f64::max)
}

#[test]
fn refine_zero_and_a_vanishing_weight_give_the_exact_methods_solution() {
    let quads = bumpy(shapes::torus(8, 6), 0.03, 7);
    let open = bumpy(shapes::quad_grid(5, 4), 0.05, 8);
    let tris = bumpy(shapes::icosahedron(), 0.03, 9);
    let cases: Vec<(&str, &Mesh, Scheme, Interpolant)> = vec![
        (
            "cheng torus",
            &quads,
            Scheme::CatmullClark,
            cheng::interpolate(&quads, &ChengOptions::default().with_tol(1e-12)).unwrap(),
        ),
        (
            "cheng grid",
            &open,
            Scheme::CatmullClark,
            cheng::interpolate(&open, &ChengOptions::default().with_tol(1e-12)).unwrap(),
        ),
        (
            "nasri torus",
            &quads,
            Scheme::DooSabin,
            nasri::interpolate(&quads, &NasriOptions::default().with_tol(1e-12)).unwrap(),
        ),
        (
            "loop icosahedron",
            &tris,
            Scheme::Loop(LoopBeta::Warren),
            // The unique solution of the Loop limit matrix, by the refine-0 path.
            fair::interpolate(
                &tris,
                &FairOptions::default()
                    .with_scheme(Scheme::Loop(LoopBeta::Warren))
                    .unwrap()
                    .with_refine(0)
                    .with_tol(1e-12),
            )
            .unwrap(),
        ),
    ];
    for (name, mesh, scheme, exact) in cases {
        let d = mesh.bbox_diagonal();
        let mut gaps = Vec::new();
        for w in [1e-2, 1e-4, 1e-6, 1e-9] {
            let opts = FairOptions::default().with_scheme(scheme).unwrap().with_refine(0).with_fairness_weight(w);
            let r = fair::interpolate(mesh, &opts).unwrap();
            gaps.push(max_gap(&r.control, &exact.control) / d);
        }
        eprintln!("{name}: {gaps:?}");
        // The penalty solution tends to the exact one, linearly in w.
        assert!(gaps.windows(2).all(|g| g[1] < g[0] || g[1] < 1e-10), "{name}: {gaps:?}");
        assert!(gaps[3] < 1e-8, "{name}: {gaps:?}");
    }
}

#[test]
fn a_vanishing_weight_at_refine_one_tends_to_the_exact_fair_solution() {
    let mesh = bumpy(shapes::torus(8, 6), 0.03, 11);
    let d = mesh.bbox_diagonal();
    let exact = fair::interpolate(&mesh, &FairOptions::default()).unwrap();
    let mut gaps = Vec::new();
    for w in [1e-1, 1e-3, 1e-5] {
        let r = fair::interpolate(&mesh, &FairOptions::default().with_fairness_weight(w)).unwrap();
        gaps.push(max_gap(&r.control, &exact.control) / d);
        // A penalty result approximates: its error grows with w.
        assert!(r.measured_error.unwrap().max_rel > 0.0);
    }
    assert!(gaps[0] > gaps[1] && gaps[1] > gaps[2] && gaps[2] < 1e-4, "{gaps:?}");
}

#[test]
fn the_dispatch_runs_it_by_name_and_refuses_bad_options() {
    let torus = shapes::torus(8, 6);
    let method: Method = "fair".parse().unwrap();
    let r = interpolate(&torus, &MethodOptions::new(method)).unwrap();
    assert!(r.error_all(&torus).max_rel <= TOL);
    assert_eq!(r.parameters.refine, Some(1));
    let bad = |o: FairOptions| fair::interpolate(&torus, &o).unwrap_err();
    assert!(matches!(bad(FairOptions::default().with_refine(9)), InterpError::InvalidParameter { .. }));
    assert!(matches!(bad(FairOptions::default().with_fairness_weight(-1.0)), InterpError::InvalidParameter { .. }));
    let ds2 = FairOptions::default().with_scheme(Scheme::DooSabin).unwrap().with_refine(2);
    assert!(matches!(bad(ds2), InterpError::InvalidParameter { .. }));
    // Loop takes triangles only.
    let lp = FairOptions::default().with_scheme(Scheme::Loop(LoopBeta::Warren)).unwrap();
    assert!(matches!(bad(lp), InterpError::UnsupportedMesh { .. }));
    // Every scheme of the table but the interpolatory one (no limit points to constrain) and
    // √3 (no fairing built on its split: refused, naming cheng).
    for scheme in Scheme::ALL {
        let set = FairOptions::default().with_scheme(scheme);
        let refused = scheme.traits().interpolating || scheme.traits().split == subdiv_stencil::Split::Sqrt3;
        assert_eq!(set.is_err(), refused, "{scheme}");
        if let Err(e) = set {
            assert!(matches!(e, InterpError::InvalidParameter { parameter: subdiv_interp::Parameter::Scheme, .. }));
        }
    }
    // The public field set directly is refused by the method too.
    let mut deng_ma = FairOptions::default();
    deng_ma.scheme = Scheme::DengMa(Default::default());
    assert!(matches!(bad(deng_ma), InterpError::InvalidParameter { .. }));
}

#[test]
fn tagged_meshes_interpolate_their_tagged_surface() {
    for (name, mesh, _) in support::tagged::common_cases() {
        match fair::interpolate(&mesh, &FairOptions::default().with_tol(TOL)) {
            Ok(r) => {
                let e = check(&format!("tagged {name}"), &mesh, &r, Scheme::CatmullClark);
                eprintln!("tagged {name}: {e:.2e}");
            }
            // Semi-sharp creases may spread limit rows beyond a private point.
            Err(e @ InterpError::UnsupportedMesh { .. }) => eprintln!("tagged {name}: {e}"),
            Err(e) => panic!("tagged {name}: {e}"),
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// On generated polygon meshes (tori with merged and split faces,
    /// jittered), fair interpolates, and its energy on the level-1 limit
    /// points is at most that of the exact method's control mesh refined
    /// once (a feasible point of its problem).
    #[test]
    fn generated_meshes(nu in 4usize..10, nv in 4usize..8, seed in 0u64..1000, merge in 0.0f64..0.3, split in 0.0f64..0.3) {
        let mesh = shapes::polygon_mix(&shapes::torus(nu, nv), seed, merge, split, 0.15);
        let fair = fair::interpolate(&mesh, &FairOptions::default()).unwrap();
        check("generated", &mesh, &fair, Scheme::CatmullClark);
        if let Ok(exact) = fair::interpolate(&mesh, &FairOptions::default().with_refine(0)) {
            let d = mesh.bbox_diagonal();
            let (e0, e1) = (energy(&exact, 0, 1, d), energy(&fair, 1, 1, d));
            prop_assert!(e1 <= e0 * (1.0 + 1e-9), "{} > {}", e1, e0);
        }
    }
}

#[test]
fn energy_on_further_levels_is_minimised_there() {
    // With J energy levels fair minimises the energy of the level-(K+J) limit
    // points, where the exact method's control mesh refined K times is feasible.
    for (name, mesh, scheme) in cases().into_iter().filter(|c| c.2 != Scheme::DooSabin) {
        let d = mesh.bbox_diagonal();
        let exact =
            fair::interpolate(&mesh, &FairOptions::default().with_scheme(scheme).unwrap().with_refine(0)).unwrap();
        let o = FairOptions::default().with_scheme(scheme).unwrap().with_energy_levels(1);
        let r = fair::interpolate(&mesh, &o).unwrap();
        check(&format!("{name}, J = 1"), &mesh, &r, scheme);
        let (e0, e1) = (energy(&exact, 0, 2, d), energy(&r, 1, 2, d));
        assert!(e1 <= e0 * (1.0 + 1e-9), "{name}: {e1} > {e0}");
        // And below fair's own J = 0 result there.
        let j0 = fair::interpolate(&mesh, &FairOptions::default().with_scheme(scheme).unwrap()).unwrap();
        assert!(e1 <= energy(&j0, 1, 2, d) * (1.0 + 1e-9), "{name}");
    }
}

#[test]
fn the_two_algorithms_find_the_same_minimiser() {
    // Limit points (fair Y with the data pinned, then T·X = Y) against
    // elimination (private pivots, CG in the control points): the same
    // problem (2), solved by different code.
    for (name, mesh, scheme) in cases().into_iter().filter(|c| c.2 != Scheme::DooSabin) {
        let d = mesh.bbox_diagonal();
        let base = FairOptions::default().with_scheme(scheme).unwrap().with_tol(1e-12);
        let by = |a: FairAlgorithm| fair::interpolate(&mesh, &base.clone().with_algorithm(a)).unwrap();
        let (lp, el) = (by(FairAlgorithm::LimitPoints), by(FairAlgorithm::Elimination));
        check(&format!("{name}, limit points"), &mesh, &lp, scheme);
        let gap = max_gap(&lp.control, &el.control) / d;
        let (e1, e2) = (lp.parameters.energy.unwrap(), el.parameters.energy.unwrap());
        eprintln!("{name}: control gap {gap:.1e}·d, energies {e1:.6e} / {e2:.6e}");
        assert!(gap < 1e-4, "{name}: {gap:e}");
        assert!((e1 - e2).abs() <= 1e-6 * e2, "{name}: {e1} vs {e2}");
    }
}
