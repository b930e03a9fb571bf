//! Differential test: our OBJ reader against `tobj` on the OBJ fixtures
//! without unreferenced vertices.
//!
//! `tobj` renumbers vertices per model by first use, so its indices are
//! mapped back to ours by position; the polygons must agree, in order.

use crate::common::fixture;
use std::collections::HashMap;
use subdiv_io::read_mesh;

const FILES: &[&str] = &[
    "canonical/cross3d_quad.obj",
    "canonical/cube_quad.obj",
    "canonical/dodecahedron.obj",
    "canonical/grid_quad_8x8_open.obj",
    "canonical/hexagonal_prism.obj",
    "canonical/icosahedron.obj",
    "canonical/icosphere_2.obj",
    "canonical/octahedron.obj",
    "canonical/pyramid_mixed.obj",
    "canonical/tetrahedron.obj",
    "canonical/torus_quad_16x8.obj",
    "quad/spot_control_mesh.obj",
];

#[test]
fn polygons_agree_with_tobj() {
    for name in FILES {
        let path = fixture(name);
        let ours = read_mesh(&path).unwrap();
        let key = |p: [f32; 3]| p.map(f32::to_bits);
        let mut by_position = HashMap::new();
        for (i, p) in ours.positions.iter().enumerate() {
            let previous = by_position.insert(key(p.as_vec3().to_array()), i as u32);
            assert!(previous.is_none(), "{name}: coincident vertices make the mapping ambiguous");
        }

        let options = tobj::LoadOptions { triangulate: false, single_index: false, ..Default::default() };
        let (models, _) = tobj::load_obj(&path, &options).unwrap();
        let mut theirs: Vec<Vec<u32>> = Vec::new();
        for model in &models {
            let m = &model.mesh;
            let arities: Vec<u32> =
                if m.face_arities.is_empty() { vec![3; m.indices.len() / 3] } else { m.face_arities.clone() };
            let mut at = 0;
            for arity in arities {
                let face = m.indices[at..at + arity as usize]
                    .iter()
                    .map(|&v| {
                        let p = &m.positions[3 * v as usize..3 * v as usize + 3];
                        by_position[&key([p[0], p[1], p[2]])]
                    })
                    .collect();
                theirs.push(face);
                at += arity as usize;
            }
        }
        let ours: Vec<Vec<u32>> = ours.faces.iter().map(<[u32]>::to_vec).collect();
        assert_eq!(ours, theirs, "{name}");
    }
}
