//! Read → write in every format → read back, on real fixtures.

use crate::common::{assert_round_trip, fixture, scratch_dir};
use subdiv_io::{read_mesh, read_mesh_from_bytes, write_mesh_as, write_mesh_to_vec, write_mesh_view, Format, MeshView};

const FIXTURES: &[&str] = &[
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
    "poly/mpi.off",
    "poly/mesh_with_colors.off",
    "quad/spot_control_mesh.obj",
    "quad/fandisk_quads.off",
    "tri/eight.off",
    "open/fairing-cross.off",
    "open/halftunnel.off",
];

#[test]
fn every_fixture_round_trips_through_every_format_in_memory() {
    for name in FIXTURES {
        let original = read_mesh(&fixture(name)).unwrap_or_else(|e| panic!("{e}"));
        assert!(!original.faces.is_empty(), "{name}");
        for format in Format::ALL {
            let bytes = write_mesh_to_vec(MeshView::from(&original), format).unwrap();
            let back = read_mesh_from_bytes(&bytes, format, name).unwrap_or_else(|e| panic!("{format}: {e}"));
            assert_round_trip(&original, &back, format, &format!("{name} as {format}"));
        }
    }
}

#[test]
fn every_format_round_trips_through_files() {
    let dir = scratch_dir("round_trip_files");
    let original = read_mesh(&fixture("poly/mpi.off")).unwrap();
    for format in Format::ALL {
        let path = dir.join(format!("mpi_{format:?}.{}", format.extension()));
        write_mesh_as(&path, MeshView::from(&original), format).unwrap();
        let back = read_mesh(&path).unwrap();
        assert_round_trip(&original, &back, format, &format!("mpi via {}", path.display()));
    }
    // The extension alone picks the (binary) format.
    let path = dir.join("by_extension.PLY");
    write_mesh_view(&path, MeshView::from(&original)).unwrap();
    assert!(std::fs::read(&path).unwrap().starts_with(b"ply\nformat binary_little_endian"));
    // Nothing but the outputs is left in the directory: no temporary files.
    let count = std::fs::read_dir(&dir).unwrap().count();
    assert_eq!(count, Format::ALL.len() + 1);
}

/// Files are streamed through a 1 MiB buffer: on a mesh whose every
/// encoding is larger than that, with normals, the file holds exactly the
/// bytes of the in-memory encoding.
#[test]
fn streamed_files_equal_the_in_memory_encoding() {
    let dir = scratch_dir("streamed_files");
    let torus = subdiv_mesh::shapes::torus(300, 200);
    let (positions, faces) = (torus.positions(), torus.topology().faces());
    let normals = torus.vertex_normals();
    let view = MeshView::new(positions, faces).with_normals(&normals);
    for format in Format::ALL {
        let path = dir.join(format!("torus.{}", format.extension()));
        write_mesh_as(&path, view, format).unwrap();
        let in_memory = write_mesh_to_vec(view, format).unwrap();
        // USD's binary layers compress their arrays.
        let least = if matches!(format, Format::Usdc | Format::Usdz) { 1 << 20 } else { 2 << 20 };
        assert!(in_memory.len() > least, "{format}: {} bytes", in_memory.len());
        assert!(std::fs::read(&path).unwrap() == in_memory, "{format}");
    }
}

#[test]
fn normals_are_written_where_the_format_has_them() {
    let original = read_mesh(&fixture("canonical/icosahedron.obj")).unwrap();
    let normals: Vec<_> = original.positions.iter().map(|p| p.normalize()).collect();
    let view = MeshView::from(&original).with_normals(&normals);
    let obj = String::from_utf8(write_mesh_to_vec(view, Format::Obj).unwrap()).unwrap();
    assert_eq!(obj.lines().filter(|l| l.starts_with("vn ")).count(), 12);
    assert!(obj.contains("f 1//1 "), "{obj}");
    let ply = write_mesh_to_vec(view, Format::PlyAscii).unwrap();
    assert!(String::from_utf8_lossy(&ply).contains("property double nz"));
    let glb = write_mesh_to_vec(view, Format::Glb).unwrap();
    assert!(String::from_utf8_lossy(&glb).contains("\"NORMAL\""));
    // Normals never change what is read back.
    for format in Format::ALL {
        let back = read_mesh_from_bytes(&write_mesh_to_vec(view, format).unwrap(), format, "n").unwrap();
        assert_round_trip(&original, &back, format, &format!("with normals as {format}"));
    }
}

#[test]
fn obj_groups_survive_reading() {
    let src = "g left\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\no right part\nf 2 4 3\ng left\nf 3 2 1\n";
    let soup = read_mesh_from_bytes(src.as_bytes(), Format::Obj, "g.obj").unwrap();
    assert_eq!(soup.groups.names, vec!["left", "right part"]);
    assert_eq!(soup.groups.face_group, vec![0, 1, 0]);
}

#[test]
fn faces_with_more_than_255_corners_round_trip_through_ply() {
    let n = 300u32;
    let positions: Vec<_> = (0..n)
        .map(|i| {
            let a = f64::from(i) * std::f64::consts::TAU / f64::from(n);
            subdiv_mesh::DVec3::new(a.cos(), a.sin(), 0.0)
        })
        .collect();
    let faces = subdiv_mesh::FaceList::from_faces([(0..n).collect::<Vec<_>>(), (0..n).rev().collect()]);
    for format in Format::ALL {
        let bytes = write_mesh_to_vec(MeshView::new(&positions, &faces), format).unwrap();
        if format == Format::PlyBinary {
            assert!(String::from_utf8_lossy(&bytes).contains("property list uint int vertex_indices"));
        }
        let back = read_mesh_from_bytes(&bytes, format, "disc").unwrap();
        let original = subdiv_mesh::PolygonSoup::new(positions.clone(), faces.clone());
        assert_round_trip(&original, &back, format, &format!("300-gon as {format}"));
    }
}
