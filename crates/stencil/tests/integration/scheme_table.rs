//! The scheme table (`Scheme::ALL`, `traits`, names, parameters) held
//! against the code it describes: names round-trip through every spelling,
//! the size rule of each split predicts the counts that subdivision really
//! produces, and the flags agree with what the rules accept.

use crate::common;

use subdiv_mesh::{shapes, Mesh};
use subdiv_stencil::size::{refined_sizes, LevelSize};
use subdiv_stencil::{subdivide, LoopBeta, Scheme, StencilError, SubdivisionPlan, Tension};

/// Closed and open meshes of triangles, quads and mixed polygons, procedural and from `fixtures/`.
fn meshes() -> Vec<(String, Mesh)> {
    let mut out: Vec<(String, Mesh)> = vec![
        ("tetrahedron".into(), shapes::tetrahedron()),
        ("icosahedron".into(), shapes::icosahedron()),
        ("open triangle grid".into(), shapes::triangle_grid(3, 2)),
        ("cube".into(), shapes::cube()),
        ("torus".into(), shapes::torus(6, 4)),
        ("open quad grid".into(), shapes::quad_grid(3, 2)),
        ("plate with holes".into(), shapes::plate_with_holes(5, 4, &[(1, 1), (3, 2)], false)),
        ("polygon mix".into(), shapes::polygon_mix(&shapes::torus(8, 6), 7, 0.3, 0.3, 0.1)),
        ("valence 2".into(), shapes::split_edges(&shapes::cube(), &[subdiv_mesh::EdgeId(0)], 0.0)),
    ];
    for stem in ["eight", "P", "pyramid_mixed", "grid_quad_8x8_open", "cube_quad"] {
        out.push((format!("fixture {stem}"), common::fixture(stem)));
    }
    out
}

fn is_triangle_mesh(mesh: &Mesh) -> bool {
    mesh.topology().faces().all_of_size(3)
}

#[test]
fn every_scheme_round_trips_through_its_name_display_and_serde() {
    for scheme in Scheme::ALL {
        assert_eq!(scheme.to_string(), scheme.name());
        assert_eq!(scheme.name().parse::<Scheme>(), Ok(scheme));
        let json = serde_json::to_string(&scheme).unwrap();
        assert_eq!(json, format!("\"{}\"", scheme.name()));
        assert_eq!(serde_json::from_str::<Scheme>(&json).unwrap(), scheme);
        assert!(!scheme.summary().is_empty() && !scheme.summary().contains('\n'));
    }
    // ALL has each scheme once, with its default parameters.
    for (i, a) in Scheme::ALL.iter().enumerate() {
        assert!(Scheme::ALL[i + 1..].iter().all(|b| a.name() != b.name()));
    }
    assert!(Scheme::ALL.contains(&Scheme::Loop(LoopBeta::default())));
    assert!(Scheme::ALL.contains(&Scheme::DengMa(Tension::default())));
    // The parameters are not part of the name: a Loop β round-trips to the default.
    let loop_ = serde_json::to_string(&Scheme::Loop(LoopBeta::Loop)).unwrap();
    let warren = serde_json::to_string(&Scheme::Loop(LoopBeta::Warren)).unwrap();
    assert_eq!(serde_json::from_str::<Scheme>(&warren).unwrap(), Scheme::Loop(LoopBeta::Loop));
    assert_eq!(loop_, warren);
}

#[test]
fn unknown_names_are_refused_with_the_valid_ones() {
    let names: Vec<&str> = Scheme::ALL.iter().map(Scheme::name).collect();
    for bad in ["butterfly", "Loop", "catmull_clark", " loop", "", "sqrt-3"] {
        let e = bad.parse::<Scheme>().unwrap_err();
        assert!(matches!(e, StencilError::UnknownScheme { .. }), "{bad}");
        assert_eq!(e.to_string(), format!("unknown scheme `{bad}` (expected one of: {})", names.join(", ")));
        let json = format!("\"{bad}\"");
        let e = serde_json::from_str::<Scheme>(&json).unwrap_err().to_string();
        assert!(e.contains("expected one of: catmull-clark"), "{e}");
    }
}

#[test]
fn with_parameters_sets_its_own_and_refuses_misplaced_parameters() {
    let beta = Some(LoopBeta::Loop);
    let variable = Tension::Variable { lambda: 0.5 };
    let tension = Some(variable);
    for scheme in Scheme::ALL {
        assert_eq!(scheme.with_parameters(None, None), Ok(scheme));
        let with_beta = scheme.with_parameters(beta, None);
        let with_tension = scheme.with_parameters(None, tension);
        match scheme {
            Scheme::Loop(_) => {
                assert_eq!(with_beta, Ok(Scheme::Loop(LoopBeta::Loop)));
                assert!(with_tension.is_err());
            }
            Scheme::DengMa(_) => {
                assert_eq!(with_tension, Ok(Scheme::DengMa(variable)));
                assert!(with_beta.is_err());
            }
            Scheme::CatmullClark | Scheme::DooSabin | Scheme::Sqrt3 => {
                assert!(with_beta.is_err() && with_tension.is_err())
            }
        }
        if let Err(e) = with_beta {
            assert_eq!(e, StencilError::ParameterNotApplicable("--beta applies to --scheme loop only".into()));
        }
        if let Err(e) = with_tension {
            assert_eq!(
                e,
                StencilError::ParameterNotApplicable(
                    "--omega/--variable-tension apply to --scheme deng-ma only".into()
                )
            );
        }
        assert!(scheme.with_parameters(beta, tension).is_err());
    }
}

/// The table's size rule (per split) against the meshes `subdivide` builds,
/// element for element, for 1–3 levels.
#[test]
fn the_size_rule_of_every_scheme_predicts_the_refined_counts() {
    let mut checked = 0;
    for (name, mesh) in meshes() {
        for scheme in Scheme::ALL {
            if scheme.traits().triangles_only && !is_triangle_mesh(&mesh) {
                continue;
            }
            let predicted = refined_sizes(mesh.topology(), scheme, 3);
            for levels in 1..=3 {
                let refined =
                    subdivide(&mesh, scheme, levels, false).unwrap_or_else(|e| panic!("{name} {scheme}: {e}"));
                let t = refined.topology();
                let boundary: usize = t.boundary_loops().map(<[_]>::len).sum();
                let p: LevelSize = predicted[levels - 1];
                assert_eq!(
                    (p.vertices, p.edges, p.faces, p.corners, p.boundary_edges),
                    (
                        t.vertex_count() as u64,
                        t.edge_count() as u64,
                        t.face_count() as u64,
                        t.half_edge_count() as u64,
                        boundary as u64
                    ),
                    "{name}, {scheme}, level {levels}"
                );
                checked += 1;
            }
        }
    }
    assert!(checked >= 3 * (3 * 14 + 3), "every mesh with every scheme that takes it: {checked}");
}

#[test]
fn triangles_only_agrees_with_the_refusal_of_other_polygons() {
    for (name, mesh) in meshes() {
        for scheme in Scheme::ALL {
            let result = subdivide(&mesh, scheme, 1, false);
            let refused = matches!(result, Err(StencilError::NotTriangles { .. }));
            assert_eq!(refused, scheme.traits().triangles_only && !is_triangle_mesh(&mesh), "{name}, {scheme}");
            if !refused {
                result.unwrap_or_else(|e| panic!("{name}, {scheme}: {e}"));
            }
        }
    }
}

#[test]
fn interpolating_schemes_are_the_ones_without_limit_masks() {
    let (cube, ico) = (shapes::cube(), shapes::icosahedron());
    for scheme in Scheme::ALL {
        let mesh = if scheme.traits().triangles_only { &ico } else { &cube };
        let plan = SubdivisionPlan::new(mesh.topology(), scheme, 1).unwrap();
        let limits = plan.limit_points(&plan.apply(mesh.positions()));
        assert_eq!(limits.is_none(), scheme.traits().interpolating, "{scheme}");
    }
}

#[test]
fn the_regular_sizes_are_those_of_the_split() {
    for scheme in Scheme::ALL {
        let traits = scheme.traits();
        // A regular vertex of a closed surface of regular faces has valence
        // 2m/(m − 2) for face size m (Euler: 4 for quads, 6 for triangles).
        let m = traits.regular_face_size;
        assert_eq!(traits.regular_valence, 2 * m / (m - 2), "{scheme}");
        assert_eq!(traits.triangles_only, m == 3, "{scheme}");
    }
}
