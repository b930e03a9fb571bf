//! The methods' first-step rules (`CornerRule`) inside the stencil's Doo-Sabin
//! step: the closed-form images (λV + (1 − λ)A, evaluated by
//! `first_step_tagged`) against the stencil's rows (the rule's weights), on
//! meshes large enough for parallel chunks that start inside faces; tags that
//! are empty or all zero change nothing, bit for bit; bad λ are refused.

use glam::DVec3;
use subdiv_interp::CornerRule;
use subdiv_mesh::shapes::{self, SplitMix64};
use subdiv_mesh::{Mesh, Tags};
use subdiv_stencil::{apply, doo_sabin, row_sums, StencilError};

fn meshes() -> Vec<(&'static str, Mesh)> {
    // A big face too (m = 40), and enough corners (> 8192) for parallel chunks.
    let big = {
        let mut p: Vec<DVec3> =
            (0..40).map(|k| DVec3::new((k as f64 * 0.157).cos(), (k as f64 * 0.157).sin(), 0.0)).collect();
        p.push(DVec3::ZERO);
        let mut faces = vec![(0..40u32).collect::<Vec<_>>()];
        faces.extend((0..40u32).map(|k| vec![(k + 1) % 40, k, 40]));
        Mesh::new(p, subdiv_mesh::FaceList::from_faces(faces)).unwrap()
    };
    let mix = shapes::polygon_mix(&shapes::plate_with_holes(80, 60, &[(20, 20)], false), 2, 0.3, 0.2, 0.1);
    assert!(mix.topology().half_edge_count() > 3 * 4096);
    let starts_inside = |h: u32| mix.topology().faces().offsets().binary_search(&h).is_err();
    assert!(starts_inside(4096) || starts_inside(8192), "a chunk boundary falls inside a face");
    vec![
        ("cube", shapes::cube()),
        ("torus mix", shapes::polygon_mix(&shapes::torus(8, 6), 3, 0.2, 0.2, 0.05)),
        ("40-gon with a triangle fan", big),
        ("large plate mix (open)", mix),
    ]
}

#[test]
fn the_first_step_is_the_stencil_product_for_every_rule() {
    for (name, mesh) in meshes() {
        let (t, x, d) = (mesh.topology(), mesh.positions(), mesh.bbox_diagonal());
        let mut rng = SplitMix64(3);
        let lambdas: Vec<f64> = (0..t.face_count()).map(|_| 0.05 + 0.9 * rng.next_f64()).collect();
        for rule in [CornerRule::Standard, CornerRule::Uniform(0.5), CornerRule::PerFace(&lambdas)] {
            let r = doo_sabin::refinement_stencil(t, &rule).unwrap();
            for (i, s) in row_sums(&r).iter().enumerate() {
                assert!((s - 1.0).abs() <= 1e-14, "{name}, {rule:?}: row {i} sums to {s:.17}");
            }
            let direct = doo_sabin::first_step(t, &rule, x).unwrap();
            let product = apply(&r, x);
            assert_eq!(direct.len(), product.len(), "{name}, {rule:?}");
            let gap = direct.iter().zip(&product).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
            assert!(gap <= 1e-15 * d, "{name}, {rule:?}: {gap:e}");
            // Untagged and with all-zero tags: the same points, bit for bit.
            let zero = Tags::from_arrays(t, vec![0.0; t.edge_count()], vec![0.0; t.vertex_count()]).unwrap();
            let tagged = doo_sabin::first_step_tagged(t, &zero, &rule, x).unwrap();
            let bits = |p: &[DVec3]| p.iter().map(|q| q.to_array().map(f64::to_bits)).collect::<Vec<_>>();
            assert_eq!(bits(&direct), bits(&tagged), "{name}, {rule:?}");
        }
    }
}

#[test]
fn bad_lambdas_are_refused_by_every_step_function() {
    let cube = shapes::cube();
    let (t, x) = (cube.topology(), cube.positions());
    for rule in [CornerRule::Uniform(1.0), CornerRule::PerFace(&[2.0]), CornerRule::PerFace(&[0.5, 0.5])] {
        let refused = |e: Option<StencilError>| matches!(e, Some(StencilError::InvalidParameter(_)));
        assert!(refused(doo_sabin::first_step(t, &rule, x).err()), "{rule:?}");
        assert!(refused(doo_sabin::refinement_stencil(t, &rule).err()), "{rule:?}");
        assert!(refused(doo_sabin::refine(t, &rule).err()), "{rule:?}");
        assert!(refused(subdiv_interp::limit_matrix_two_phase(t, rule).err()), "{rule:?}");
    }
}
