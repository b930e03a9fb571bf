//! Bodies of subdiv's fuzz targets: one `pub fn(&[u8])` per target.
//!
//! Plain library code without a fuzzer dependency, so that it has two
//! callers: the three-line libFuzzer wrappers in `fuzz_targets/`, and
//! `crates/cli/tests/integration/fuzz_corpus.rs`, which includes this file with
//! `#[path]` and replays the committed corpus and regressions in an ordinary
//! `cargo test`. A body returns when the contract of issue #14 holds and
//! panics with a message naming the broken rule when it does not.
//!
//! | body | feeds the bytes to | asserts |
//! |---|---|---|
//! | [`obj`], [`off`], [`ply`], [`stl`], [`gltf`] | `subdiv_io::read_mesh_from_bytes` | `Ok`, or an [`IoError`] on one line naming the file; a valid mesh read writes to every format and reads back (finite, same faces) |
//! | [`from_soup`] | a [`PolygonSoup`] decoded from the bytes | [`Mesh::from_soup`] agrees with [`diagnose`]; a valid mesh's half-edges, fans, loops, components and bounding-box diagonal are consistent |
//! | [`end_to_end`] | a small procedural mesh with coordinates from the bytes, one of the six methods or `subdivide` | a typed error, or every output coordinate finite and the measured interpolation error ≤ tol |
//!
//! What the bodies deliberately do not do: read or write files (glTF buffers
//! are only accepted from `data:` URIs and GLB chunks here), or time anything
//! (libFuzzer's `-timeout` catches hangs).

use std::collections::HashSet;
use subdiv_interp::{
    deng_wang, zheng_cai, CommonOptions, DengMaOptions, DengWangOptions, FanChengLaiOptions, Interpolant, Method,
    MethodOptions, Shape, SolverChoice, ZhengCaiOptions,
};
use subdiv_io::{read_mesh_from_bytes, write_mesh_to_vec, Format, IoError, MeshView};
use subdiv_mesh::{diagnose, shapes, DVec3, EdgeId, FaceList, HalfEdgeId, Mesh, MeshError, PolygonSoup, Warning};
use subdiv_solve::Solver;
use subdiv_stencil::{LoopBeta, Options, Scheme, Tension};

// ---- readers ---------------------------------------------------------------

/// OBJ reader.
pub fn obj(data: &[u8]) {
    reader(data, Format::Obj, "fuzz.obj");
}

/// OFF reader (ASCII and binary).
pub fn off(data: &[u8]) {
    reader(data, Format::Off, "fuzz.off");
}

/// PLY reader (ASCII and both binary byte orders, told apart by the header).
pub fn ply(data: &[u8]) {
    reader(data, Format::PlyBinary, "fuzz.ply");
}

/// STL reader (ASCII and binary, told apart by the content).
pub fn stl(data: &[u8]) {
    reader(data, Format::StlBinary, "fuzz.stl");
}

/// glTF reader: JSON glTF, or GLB when the bytes start with its magic.
pub fn gltf(data: &[u8]) {
    // The reader detects GLB by its magic whatever the hint; the name only
    // makes the messages read naturally.
    if data.starts_with(b"glTF") {
        reader(data, Format::Glb, "fuzz.glb");
    } else {
        reader(data, Format::Gltf, "fuzz.gltf");
    }
}

/// USD reader: a binary crate file (`PXR-USDC`), a usdz package (a zip)
/// or a text layer, told by the content as the reader tells them.
pub fn usd(data: &[u8]) {
    if data.starts_with(b"PXR-USDC") {
        reader(data, Format::Usdc, "fuzz.usdc");
    } else if data.starts_with(b"PK") {
        reader(data, Format::Usdz, "fuzz.usdz");
    } else {
        reader(data, Format::Usda, "fuzz.usda");
    }
}

/// One reader's contract: a soup or a one-line error naming the file; a soup
/// is then checked like any other ([`check_soup`]) and, if it is a valid
/// mesh, written to every format and read back.
fn reader(data: &[u8], format: Format, name: &str) {
    match read_mesh_from_bytes(data, format, name) {
        Ok(soup) => {
            check_groups(&soup);
            if let Some(mesh) = check_soup(&soup) {
                round_trip(&mesh);
            }
        }
        Err(e) => assert_message(&e, name),
    }
}

/// An error message is one non-empty line that starts with the file's name.
fn assert_message(e: &IoError, name: &str) {
    let message = e.to_string();
    assert!(!message.contains(['\n', '\r']), "error message is not one line: {message:?}");
    assert!(message.starts_with(name), "error message does not name the file {name}: {message:?}");
    assert!(message.len() > name.len() + 2, "error message says nothing: {message:?}");
}

/// Face groups, when a format has them, cover every face with a known name.
fn check_groups(soup: &PolygonSoup) {
    let groups = &soup.groups;
    if groups.names.is_empty() {
        assert!(groups.face_group.is_empty(), "face groups without names");
        return;
    }
    assert_eq!(groups.face_group.len(), soup.faces.len(), "one group per face");
    assert!(groups.face_group.iter().all(|&g| (g as usize) < groups.names.len()), "group index out of range");
}

/// Writes a valid mesh in every format and reads it back: every write of a
/// valid mesh succeeds (formats storing `f32` may refuse coordinates outside
/// its range, on one line), and what was written reads back with finite
/// coordinates and the faces the format promises to keep.
fn round_trip(mesh: &Mesh) {
    let t = mesh.topology();
    let normals = mesh.vertex_normals();
    let triangles: usize = t.face_ids().map(|f| t.face_size(f) - 2).sum();
    for format in Format::ALL {
        let name = format!("<memory>.{}", format.extension());
        let view = MeshView::new(mesh.positions(), t.faces()).with_normals(&normals);
        let bytes = match write_mesh_to_vec(view, format) {
            Ok(bytes) => bytes,
            Err(e) => {
                let message = e.to_string();
                assert!(!message.contains('\n'), "{format}: write error is not one line: {message:?}");
                assert!(
                    !format.keeps_f64() && matches!(e, IoError::InvalidMesh { .. }),
                    "{format}: a valid mesh could not be written: {message}"
                );
                continue;
            }
        };
        let back = match read_mesh_from_bytes(&bytes, format, &name) {
            Ok(back) => back,
            Err(e) => panic!("{format}: a written mesh does not read back: {e}"),
        };
        if let Some((v, p)) = back.positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
            panic!("{format}: a mesh with finite coordinates was written with vertex {v} = {p:?}");
        }
        if format.triangulates() {
            assert_eq!(back.faces.len(), triangles, "{format}: triangle count after a write and read");
        } else {
            assert_eq!(&back.faces, t.faces(), "{format}: faces after a write and read");
        }
        if format.keeps_vertices() {
            let expected: Vec<DVec3> = if format.keeps_f64() {
                mesh.positions().to_vec()
            } else {
                mesh.positions().iter().map(|p| p.as_vec3().as_dvec3()).collect()
            };
            assert_eq!(back.positions, expected, "{format}: positions after a write and read");
        } else {
            assert!(back.positions.len() <= t.vertex_count(), "{format}: more vertices read back than written");
        }
    }
}

// ---- validation ------------------------------------------------------------

/// Validation of a soup decoded from the bytes.
///
/// Layout: one byte = vertex count (0–64); three coordinates per vertex
/// ([`Bytes::coordinate`]: small values, or NaN, ±inf, subnormals, ±1e308,
/// raw bits); then faces until the bytes run out, each a size byte (0–15, or
/// a 16-bit size) followed by its indices (mostly `0..=n`, so one past the
/// end, sometimes 32 raw bits).
pub fn from_soup(data: &[u8]) {
    let mut bytes = Bytes::new(data);
    let n = usize::from(bytes.u8() % 65);
    let positions: Vec<DVec3> =
        (0..n).map(|_| DVec3::new(bytes.coordinate(), bytes.coordinate(), bytes.coordinate())).collect();
    let mut faces = FaceList::new();
    let mut face = Vec::new();
    while !bytes.is_empty() {
        let size = match bytes.u8() {
            255 => usize::from(bytes.u16()),
            s => usize::from(s % 16),
        };
        face.clear();
        for _ in 0..size.min(bytes.remaining()) {
            face.push(match bytes.u8() {
                255 => bytes.u32(),
                i => u32::from(i) % (n as u32 + 1),
            });
        }
        faces.push(&face);
    }
    check_soup(&PolygonSoup::new(positions, faces));
}

/// [`Mesh::from_soup`] and [`diagnose`] agree (two independent validators:
/// the error reported is among the defects counted, and a valid mesh has no
/// defect counted but isolated vertices); a valid mesh's topology and bounding
/// box pass [`check_mesh`]. Returns the mesh when the soup is valid.
fn check_soup(soup: &PolygonSoup) -> Option<Mesh> {
    let d = diagnose(soup);
    assert_eq!((d.vertices, d.faces), (soup.positions.len(), soup.faces.len()), "diagnosis counts");
    assert_eq!(d.face_sizes.values().sum::<usize>(), d.faces, "face size histogram covers every face");
    let (mesh, warnings) = match Mesh::from_soup(soup.clone()) {
        Ok(ok) => ok,
        Err(e) => {
            let counted = match &e {
                MeshError::NoFaces => d.faces == 0,
                MeshError::FaceTooSmall { .. } => d.faces_too_small > 0,
                MeshError::IndexOutOfRange { .. } => d.out_of_range_indices > 0,
                MeshError::RepeatedIndex { .. } => d.faces_with_repeated_index > 0,
                MeshError::NonFiniteCoordinate { .. } => d.non_finite_vertices > 0,
                MeshError::NonManifoldEdge { .. } => d.non_manifold_edges > 0,
                // Two faces one way and a third the other is an edge with 3 faces.
                MeshError::InconsistentOrientation { .. } => d.inconsistently_oriented_edges + d.non_manifold_edges > 0,
                MeshError::NonManifoldVertex { .. } => d.non_manifold_vertices > 0,
                _ => true,
            };
            assert!(counted, "from_soup says \"{e}\" but diagnose counts no such defect: {d:?}");
            check_cover(soup, &e);
            return None;
        }
    };
    let defects = [
        d.faces_too_small,
        d.out_of_range_indices,
        d.faces_with_repeated_index,
        d.non_finite_vertices,
        d.non_manifold_edges,
        d.inconsistently_oriented_edges,
        d.non_manifold_vertices,
    ];
    assert!(defects.iter().all(|&c| c == 0), "from_soup accepts a soup in which diagnose counts defects: {d:?}");
    let t = mesh.topology();
    assert_eq!(d.edges, t.edge_count(), "edge count: diagnose vs topology");
    assert_eq!(d.components, t.component_count(), "component count: diagnose vs topology");
    assert_eq!(d.bbox, Some(mesh.bbox()), "bounding box: diagnose vs mesh");
    let isolated: Vec<u32> = t.vertices().filter(|&v| t.is_isolated(v)).map(|v| v.0).collect();
    assert_eq!(d.isolated_vertices, isolated.len(), "isolated vertex count: diagnose vs topology");
    let warned = warnings.iter().find_map(|w| match w {
        Warning::IsolatedVertices { vertices } => Some(vertices.clone()),
        _ => None,
    });
    assert_eq!(warned.unwrap_or_default(), isolated, "the isolated-vertex warning lists the isolated vertices");
    check_mesh(&mesh);
    Some(mesh)
}

/// A soup [`Mesh::from_soup`] refused as non-manifold, taken by
/// [`Mesh::from_soup_covering`] as OpenSubdiv does: a typed refusal, or a
/// manifold cover whose welds give back the soup's vertices and faces,
/// with the non-manifold warning, and whose copies refine to one point.
fn check_cover(soup: &PolygonSoup, error: &subdiv_mesh::MeshError) {
    let (mesh, warnings) = match Mesh::from_soup_covering(soup.clone()) {
        Ok(ok) => ok,
        Err(e) => return assert_one_line(&e.to_string()),
    };
    let Some(welds) = mesh.welds() else {
        panic!("from_soup refused ({error}) what from_soup_covering takes without a cover");
    };
    assert_eq!(welds.vertex_count(), soup.positions.len(), "welded vertices are the soup's");
    assert_eq!(&welds.faces(mesh.topology()), &soup.faces, "welded faces are the soup's");
    assert!(warnings.iter().any(|w| matches!(w, Warning::NonManifold(_))), "the non-manifold warning");
    check_mesh(&mesh);
    let d = mesh.bbox_diagonal();
    for scheme in [Scheme::CatmullClark, Scheme::Loop(LoopBeta::Loop)] {
        if let Ok(refined) = subdiv_stencil::subdivide(&mesh, scheme, 1, false) {
            let welds = refined.welds().expect("a refined cover keeps its welds");
            let members = welds.weld(refined.positions());
            for (v, p) in refined.positions().iter().enumerate() {
                let q = members[welds.vertex(subdiv_mesh::VertexId(v as u32)) as usize];
                assert!((*p - q).length() <= 1e-12 * d, "copies of a vertex refine to one point");
            }
        }
    }
}

/// Invariants of any valid mesh: half-edge algebra, fans, boundary loops,
/// edges, components, Euler characteristic and the bounding-box diagonal.
fn check_mesh(mesh: &Mesh) {
    let t = mesh.topology();
    let nh = t.half_edge_count();
    assert_eq!(nh, t.faces().corner_count(), "one half-edge per corner");
    let mut boundary_half_edges = 0;
    for h in (0..nh as u32).map(HalfEdgeId) {
        assert_eq!(t.he_prev(t.he_next(h)), h, "prev(next(h)) = h");
        assert_eq!(t.he_face(t.he_next(h)), t.he_face(h), "next stays in the face");
        assert_eq!(t.he_to(h), t.he_from(t.he_next(h)), "to(h) = from(next(h))");
        match t.he_twin(h) {
            Some(g) => {
                assert_eq!(t.he_twin(g), Some(h), "twin(twin(h)) = h");
                assert_eq!((t.he_from(g), t.he_to(g)), (t.he_to(h), t.he_from(h)), "a twin runs backwards");
                assert_ne!(t.he_face(g), t.he_face(h), "a face is its own neighbour");
                assert_eq!(t.he_edge(g), t.he_edge(h), "twins share their edge");
            }
            None => boundary_half_edges += 1,
        }
        let e = t.he_edge(h);
        assert!(t.edge_half_edge(e) == h || t.he_twin(h) == Some(t.edge_half_edge(e)), "edge of a half-edge");
    }
    assert_eq!(2 * t.edge_count(), nh + boundary_half_edges, "2E = H + boundary half-edges");
    let boundary_edges = t.edges().filter(|&e| t.is_boundary_edge(e)).count();
    assert_eq!(boundary_edges, boundary_half_edges, "boundary edges = half-edges without twin");

    // Fans: h_{i+1} = twin(prev(h_i)), every corner of v exactly once.
    let mut corners_seen = 0;
    for v in t.vertices() {
        let fan = t.vertex_fan(v);
        corners_seen += fan.len();
        assert_eq!(t.vertex_face_count(v), fan.len(), "vertex {v}: face count = fan length");
        assert_eq!(t.is_isolated(v), fan.is_empty(), "vertex {v}: isolated iff no fan");
        if fan.is_empty() {
            assert_eq!(t.valence(v), 0, "isolated vertex {v} has valence 0");
            continue;
        }
        assert!(fan.iter().all(|&h| t.he_from(h) == v), "vertex {v}: fan half-edges leave v");
        for w in fan.windows(2) {
            assert_eq!(t.he_twin(t.he_prev(w[0])), Some(w[1]), "vertex {v}: fan order");
        }
        let closing = t.he_twin(t.he_prev(fan[fan.len() - 1]));
        if t.is_boundary_vertex(v) {
            assert_eq!(t.he_twin(fan[0]), None, "boundary vertex {v}: the fan starts on the boundary");
            assert_eq!(closing, None, "boundary vertex {v}: the fan ends on the boundary");
        } else {
            assert_eq!(closing, Some(fan[0]), "interior vertex {v}: the fan closes");
        }
        let neighbours: Vec<_> = t.vertex_neighbors(v).collect();
        assert_eq!(neighbours.len(), t.valence(v), "vertex {v}: one neighbour per edge");
        let distinct: HashSet<_> = neighbours.iter().collect();
        assert_eq!(distinct.len(), neighbours.len(), "vertex {v}: neighbours are distinct");
        assert!(!distinct.contains(&v), "vertex {v} is its own neighbour");
    }
    assert_eq!(corners_seen, nh, "fans cover every corner once");

    // Boundary loops: closed chains of twinless half-edges covering the
    // boundary, each boundary vertex on exactly one loop once (manifold).
    let mut on_loops = HashSet::new();
    let mut loop_vertices = HashSet::new();
    for lp in t.boundary_loops() {
        assert!(lp.len() >= 3, "a boundary loop of {} edges", lp.len());
        for (k, &h) in lp.iter().enumerate() {
            assert_eq!(t.he_twin(h), None, "a boundary loop half-edge has a twin");
            let next = lp[(k + 1) % lp.len()];
            assert_eq!(t.he_to(h), t.he_from(next), "boundary loop is not a chain");
            assert!(t.is_boundary_vertex(t.he_from(h)), "loop vertex not on the boundary");
            assert!(on_loops.insert(h), "half-edge on two boundary loops");
            assert!(loop_vertices.insert(t.he_from(h)), "vertex {} twice on the boundary", t.he_from(h));
        }
    }
    assert_eq!(on_loops.len(), boundary_half_edges, "loops cover the boundary");
    let boundary_vertices = t.vertices().filter(|&v| t.is_boundary_vertex(v)).count();
    assert_eq!(loop_vertices.len(), boundary_vertices, "every boundary vertex is on a loop");
    assert_eq!(t.is_closed(), boundary_half_edges == 0, "closed iff no boundary");

    // Components: neighbours across an edge share a component; ids are dense.
    let mut ids = HashSet::new();
    for f in t.face_ids() {
        ids.insert(t.face_component(f));
        for h in t.face_half_edges(f) {
            if let Some(g) = t.he_twin(h) {
                assert_eq!(t.face_component(t.he_face(g)), t.face_component(f), "component across an edge");
            }
        }
    }
    assert_eq!(ids.len(), t.component_count(), "component ids");
    assert!(ids.iter().all(|&c| (c as usize) < t.component_count()), "component ids are 0-based and dense");
    assert!(t.genus().is_some(), "a valid oriented manifold has an integral genus");

    // The scale d, without overflow or underflow (issue #14: scaled hypot).
    let b = mesh.bbox();
    let reference = 2.0 * half_distance(b.max, b.min);
    let d = mesh.bbox_diagonal();
    // A few units of the last place, and a few subnormal steps near zero.
    let close = (d - reference).abs() <= 1e-12 * reference + 4.0 * f64::from_bits(1);
    assert!(
        close || (d.is_infinite() && reference.is_infinite()),
        "bbox diagonal {d:e} of a box from {:?} to {:?} should be {reference:e}",
        b.min,
        b.max
    );
}

// ---- end to end ------------------------------------------------------------

/// What [`end_to_end`] runs: a method (in [`Method::ALL`]'s order), or `subdivide`.
#[derive(Clone, Copy, Debug)]
enum Operation {
    Interpolate(Method),
    Subdivide,
}

const OPERATIONS: [Operation; 7] = {
    let m = Method::ALL;
    [
        Operation::Interpolate(m[0]),
        Operation::Interpolate(m[1]),
        Operation::Interpolate(m[2]),
        Operation::Interpolate(m[3]),
        Operation::Interpolate(m[4]),
        Operation::Interpolate(m[5]),
        Operation::Subdivide,
    ]
};

/// A method or `subdivide` on a small procedural mesh with coordinates from
/// the bytes, asserting the numeric rule of issue #14: a typed error, or every
/// output coordinate finite and, for interpolation, the error measured from
/// the control mesh by its plain scheme ≤ tol.
///
/// Layout: a fixed header of [`HEADER_LEN`] bytes (operation, shape and its
/// two parameters, isolated vertices, levels, the scale's exponent, then one
/// byte per option, [`Bytes::pick`] style), so that mutating a coordinate
/// never changes an option; then the tail: translation and per-vertex
/// coordinates ([`coordinates`]), then per-vertex option lists (subset,
/// normals, handles, per-face λ). Zero bytes decode to the defaults and the
/// shape as generated.
pub fn end_to_end(data: &[u8]) {
    let (head, tail) = data.split_at(data.len().min(HEADER_LEN));
    let (mut head, mut tail) = (Bytes::new(head), Bytes::new(tail));
    let operation = head.pick(&OPERATIONS);
    let base = shape(&mut head);
    let isolated = match head.u8() {
        0..=191 => 0,
        x => 1 + usize::from(x % 3),
    };
    let levels = usize::from(head.u8() % 4);
    // 0..=308 as is, 309..=631 as −1..=−323: zero bytes mean scale 1.
    let e = i32::from(head.u16() % 632);
    let scale = 10f64.powi(if e <= 308 { e } else { 308 - e });
    // All vertices at one point (duplicates, or coordinates that round alike) is refused by validation.
    let Some(mesh) = coordinates(&base, isolated, scale, &mut tail) else { return };
    match operation {
        Operation::Subdivide => subdivide(&mesh, levels, &mut head),
        Operation::Interpolate(method) => interpolate(&mesh, method, levels, &mut head, &mut tail),
    }
}

/// Bytes of [`end_to_end`]'s fixed header: 8 for the mesh, the rest options.
pub const HEADER_LEN: usize = 24;

/// One of the procedural shapes of `subdiv_mesh::shapes`, small enough for
/// three levels of refinement in a few milliseconds.
fn shape(bytes: &mut Bytes) -> Mesh {
    let (kind, p, q) = (bytes.u8() % 16, usize::from(bytes.u8()), usize::from(bytes.u8()));
    match kind {
        0 => shapes::tetrahedron(),
        1 => shapes::cube(),
        2 => shapes::octahedron(),
        3 => shapes::icosahedron(),
        4 => shapes::quad_grid(1 + p % 3, 1 + q % 3),
        5 => shapes::triangle_grid(1 + p % 3, 1 + q % 3),
        6 => shapes::torus(3 + p % 3, 3 + q % 3),
        7 => shapes::prism(3 + p % 4),
        8 => shapes::pyramid(3 + p % 6),
        9 => shapes::pillow(),
        10 => shapes::plate_with_holes(3, 3, &[(1, 1)], q % 2 == 0),
        11 => shapes::polygon_mix(&shapes::torus(4, 4), p as u64, 0.3, 0.3, 0.0),
        12 => shapes::polygon_mix(&shapes::quad_grid(3, 3), p as u64, 0.3, 0.5, 0.0),
        // Valence-2 vertices: one or two edges of a cube split.
        13 => {
            let cube = shapes::cube();
            let mut edges = vec![EdgeId((p % 12) as u32)];
            if q % 12 != p % 12 && q % 3 == 0 {
                edges.push(EdgeId((q % 12) as u32));
            }
            shapes::split_edges(&cube, &edges, 0.1)
        }
        14 => {
            let source = if p % 2 == 0 { shapes::cube() } else { shapes::torus(3, 3) };
            subdiv_mesh::triangulate(&source).expect("a valid mesh triangulates").mesh
        }
        _ => shapes::quad_grid(1, 1),
    }
}

/// `base`'s connectivity with `isolated` extra unused vertices and new
/// coordinates: the shape times `scale` and translated, then per vertex
/// kept, jittered, replaced by arbitrary finite values, or made a duplicate
/// of another vertex. Every coordinate is finite: the input is valid, so only
/// the method can be at fault.
fn coordinates(base: &Mesh, isolated: usize, scale: f64, bytes: &mut Bytes) -> Option<Mesh> {
    let translation = DVec3::new(bytes.finite(), bytes.finite(), bytes.finite());
    let mut positions: Vec<DVec3> = base.positions().to_vec();
    positions.extend((0..isolated).map(|k| DVec3::new(0.5, 0.25 * k as f64, 2.0)));
    let n = positions.len();
    let mut duplicates = Vec::new();
    for (v, p) in positions.iter_mut().enumerate() {
        let placed = *p * scale + translation;
        *p = match bytes.u8() {
            0..=159 => placed,
            160..=199 => placed * (1.0 + f64::from(bytes.u8() as i8) * 1e-3),
            200..=219 => {
                duplicates.push((v, usize::from(bytes.u8()) % n));
                placed
            }
            _ => DVec3::new(bytes.finite(), bytes.finite(), bytes.finite()),
        }
        .map(clamp_finite);
    }
    for (v, of) in duplicates {
        positions[v] = positions[of];
    }
    let soup = PolygonSoup::new(positions, base.topology().faces().clone());
    match Mesh::from_soup(soup) {
        Ok((mesh, _)) => Some(mesh),
        Err(subdiv_mesh::MeshError::AllVerticesCoincide { .. }) => None,
        Err(e) => panic!("finite coordinates on a valid connectivity: {e:?}"),
    }
}

/// A finite value for a non-finite one (±inf → ±f64::MAX, NaN → 0).
fn clamp_finite(x: f64) -> f64 {
    if x.is_nan() {
        0.0
    } else if x.is_infinite() {
        f64::MAX.copysign(x)
    } else {
        x
    }
}

/// `subdivide` with any scheme, 0–3 levels, at limit positions or not: a
/// typed error, or finite positions and the scheme's face count.
fn subdivide(mesh: &Mesh, levels: usize, bytes: &mut Bytes) {
    let tension = tension(bytes);
    let scheme = bytes.pick(&[
        Scheme::CatmullClark,
        Scheme::Loop(LoopBeta::Warren),
        Scheme::Loop(LoopBeta::Loop),
        Scheme::DooSabin,
        Scheme::DengMa(tension),
        Scheme::Sqrt3,
    ]);
    let limit = bytes.u8() % 2 == 0;
    match subdiv_stencil::subdivide(mesh, scheme, levels, limit) {
        Ok(refined) => {
            assert_finite(refined.positions(), &format!("subdivide --scheme {} --levels {levels}", scheme.name()));
            if levels == 1 {
                let t = mesh.topology();
                let faces = refined.topology().face_count();
                match scheme {
                    Scheme::CatmullClark | Scheme::DengMa(_) => {
                        assert_eq!(faces, t.half_edge_count(), "one quad per corner")
                    }
                    Scheme::Loop(_) => assert_eq!(faces, 4 * t.face_count(), "four triangles per triangle"),
                    Scheme::DooSabin => {}
                    Scheme::Sqrt3 => assert_eq!(faces, 3 * t.face_count(), "three triangles per triangle"),
                }
            }
        }
        Err(e) => assert_one_line(&e.to_string()),
    }
}

/// A method with options from the bytes: a typed error, or a finite control
/// mesh (and surface) interpolating the data within tol.
fn interpolate(mesh: &Mesh, method: Method, levels: usize, head: &mut Bytes, tail: &mut Bytes) {
    let n = mesh.topology().vertex_count();
    let nf = mesh.topology().face_count();
    let tol = head.pick(&[subdiv_interp::DEFAULT_TOL, subdiv_interp::DEFAULT_TOL, 1e-3, 1e-10]);
    let solver = match head.u8() {
        s if s < 128 => SolverChoice::Auto,
        s => SolverChoice::Use(Solver::ALL[usize::from(s) % Solver::ALL.len()]),
    };
    let max_iter = head.pick(&[subdiv_interp::DEFAULT_MAX_ITER, 200]);
    let subset = match head.u8() {
        0..=199 => None,
        count => Some((0..count % 8).map(|_| u32::from(tail.u8()) % (n as u32 + 1)).collect()),
    };
    let common = CommonOptions::default().with_subset(subset).with_tol(tol).with_max_iter(max_iter).with_solver(solver);
    let mut options: MethodOptions = match method {
        Method::ZhengCai => {
            let ite_max = head.pick(&[zheng_cai::DEFAULT_ITE_MAX, 0, 1, 50]);
            let eps = head.pick(&[zheng_cai::DEFAULT_EPS, 0.0, 1e-12, 0.5, 1e300, -1.0, f64::NAN]);
            let normals = normals(n, head, tail);
            let handles = (head.u8() >= 192).then(|| (0..n).map(|_| tail.pick(&HANDLES)).collect());
            ZhengCaiOptions::default()
                .with_ite_max(ite_max)
                .with_eps(eps)
                .with_normals(normals)
                .with_handles(handles)
                .into()
        }
        Method::FanChengLai => {
            let shape = match head.u8() {
                0..=191 => Shape::Uniform(head.pick(&LAMBDAS)),
                k => Shape::PerFace((0..nf + usize::from(k % 3) - 1).map(|_| tail.pick(&LAMBDAS)).collect()),
            };
            FanChengLaiOptions::default().with_shape(shape).into()
        }
        Method::DengWang => {
            let mu = head.pick(&[deng_wang::DEFAULT_MU, 0.25, 0.0, 0.5, 1.0, -1.0, 1e300, 1e-300, f64::NAN]);
            let beta = head.pick(&[LoopBeta::Warren, LoopBeta::Loop]);
            let normals = normals(n, head, tail);
            DengWangOptions::default().with_mu(mu).with_beta(beta).with_normals(normals).into()
        }
        Method::DengMa => DengMaOptions::default().with_tension(tension(head)).into(),
        other => MethodOptions::new(other),
    };
    // Deng-Ma has no shared options: it interpolates every vertex exactly.
    if let Some(shared) = options.common_mut() {
        *shared = common;
    }
    let result = subdiv_interp::interpolate(mesh, &options);
    let name = format!("{method:?}");
    let result = match result {
        Ok(result) => result,
        Err(e) => return assert_one_line(&e.to_string()),
    };
    // The subset less the isolated vertices (no limit point), which every method leaves out with a warning.
    let mut interpolated = match options.common() {
        None => vec![true; n],
        Some(shared) => shared.interpolated(n).expect("the method accepted the subset"),
    };
    let t = mesh.topology();
    for v in t.vertices().filter(|&v| t.is_isolated(v)) {
        interpolated[v.index()] = false;
    }
    assert_eq!(
        result.interpolated, interpolated,
        "{method:?}: the interpolated set is the subset less isolated vertices"
    );
    assert_finite(result.control.positions(), &format!("{name}: control mesh"));
    assert_interpolates(&result, mesh, &interpolated, tol, &name);
    match result.surface(levels) {
        Ok(surface) => assert_finite(surface.positions(), &format!("{name}: surface at {levels} levels")),
        Err(e) => assert_one_line(&e.to_string()),
    }
}

/// λ values for Fan-Cheng-Lai: the paper's, the ends of (0, 1), and outside.
const LAMBDAS: [f64; 10] = [0.5, 0.85, 0.4, 0.0, 1.0, 1e-12, 0.999_999, -1.0, 2.0, f64::NAN];
/// Brunet shape handles for Zheng-Cai: none (1), sharper, flatter, extreme, invalid.
const HANDLES: [f64; 10] = [1.0, 1.0, 0.5, 2.0, 1e12, 1e-12, 0.0, -1.0, 1e300, f64::NAN];

/// Deng-Ma tension: the default, valid values, the ends of (0, 1], outside.
fn tension(bytes: &mut Bytes) -> Tension {
    let value = bytes.pick(&[1.0, 0.5, 1e-300, 0.0, 2.0, -1.0, f64::NAN]);
    if bytes.u8() % 2 == 0 {
        Tension::Global(value)
    } else {
        Tension::Variable { lambda: value }
    }
}

/// Prescribed normals (Zheng-Cai, Deng-Wang), usually none; some vertices get
/// a normal of any length, zero, or huge.
fn normals(n: usize, head: &mut Bytes, tail: &mut Bytes) -> Option<Vec<Option<DVec3>>> {
    if head.u8() < 192 {
        return None;
    }
    Some(
        (0..n)
            .map(|_| match tail.u8() % 4 {
                0 => Some(DVec3::new(tail.finite(), tail.finite(), tail.finite())),
                1 => Some(DVec3::Z),
                _ => None,
            })
            .collect(),
    )
}

/// Every coordinate of `positions` is finite.
fn assert_finite(positions: &[DVec3], what: &str) {
    if let Some((v, p)) = positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
        panic!("{what}: Ok with a non-finite vertex {v} = {p:?}");
    }
}

/// The error measured as the CLI reports it ([`Interpolant::error`] with the
/// mesh's d) and measured without overflow (each distance and d halved) are
/// both ≤ tol. NaN fails both comparisons.
fn assert_interpolates(result: &Interpolant, mesh: &Mesh, interpolated: &[bool], tol: f64, name: &str) {
    let data = mesh.positions();
    let reported = result.error(data, interpolated, mesh.bbox_diagonal());
    assert!(
        reported.max_rel <= tol,
        "{name}: Ok with max error {:e}·d > tol {tol:e} (d = {:e}, max_abs = {:e})",
        reported.max_rel,
        mesh.bbox_diagonal(),
        reported.max_abs
    );
    let b = mesh.bbox();
    let half_d = half_distance(b.max, b.min);
    let limits = result.limit_points(data.len());
    for (v, ((l, p), &on)) in limits.iter().zip(data).zip(interpolated).enumerate() {
        if on {
            let relative = half_distance(*l, *p) / half_d;
            assert!(
                relative <= tol,
                "{name}: vertex {v} at {p:?} has limit point {l:?}: error {relative:e}·d > tol {tol:e} \
                 (scaled measure, d = {:e}; the mesh's d = {:e})",
                2.0 * half_d,
                mesh.bbox_diagonal()
            );
        }
    }
}

/// An error message is one line (the CLI prints it after the file name).
fn assert_one_line(message: &str) {
    assert!(!message.contains(['\n', '\r']), "error message is not one line: {message:?}");
}

// ---- the limit surface: evaluate, sample, project, fit ---------------------------

/// The mesh, scheme and options of the surface targets, from the first
/// [`SURFACE_HEADER_LEN`] bytes: a shape and its coordinates as
/// [`end_to_end`] makes them (scale 1e-323…1e308), and the scheme
/// (Catmull-Clark, Loop with either β on the triangulated shape, Doo-Sabin)
/// and boundary rule. `None` when every vertex coincides.
fn surface_input(head: &mut Bytes, tail: &mut Bytes) -> Option<(Mesh, Options)> {
    let base = shape(head);
    let e = i32::from(head.u16() % 632);
    let scale = 10f64.powi(if e <= 308 { e } else { 308 - e });
    let scheme = head.pick(&[
        Scheme::CatmullClark,
        Scheme::Loop(LoopBeta::Loop),
        Scheme::Loop(LoopBeta::Warren),
        Scheme::DooSabin,
    ]);
    let base = if matches!(scheme, Scheme::Loop(_)) && base.topology().faces().iter().any(|f| f.len() != 3) {
        subdiv_mesh::triangulate(&base).ok()?.mesh
    } else {
        base
    };
    let mesh = coordinates(&base, 0, scale, tail)?;
    let mut options = Options::new(scheme);
    if head.u8() % 4 == 0 {
        options.boundary = subdiv_stencil::BoundaryInterpolation::EdgeOnly;
    }
    Some((mesh, options))
}

/// Bytes of the surface targets' header.
pub const SURFACE_HEADER_LEN: usize = 8;

/// Splits a surface target's input into header and tail (as [`end_to_end`]).
fn split_surface(data: &[u8]) -> (Bytes<'_>, Bytes<'_>) {
    let (head, tail) = data.split_at(data.len().min(SURFACE_HEADER_LEN));
    (Bytes::new(head), Bytes::new(tail))
}

/// The control points' bounding box and the slack of a point inside it
/// (limit points are convex combinations of control points: every scheme's
/// weights here are positive): rounding relative to the largest coordinate
/// of any axis — the numeric rule measures relative to the mesh's scale, and
/// an axis whose coordinates are 1e-575 of the largest one (a flat mesh at
/// z = 9e-311 with x ~ 1e264) is computed on the normalised data, where it
/// underflows: its feet come back at z = 0, 1e-575·d away (the project
/// campaign's three artifacts, `regressions/project/flat_far_axis_*`) —
/// and the subnormal grid.
fn hull(mesh: &Mesh) -> (DVec3, DVec3, DVec3) {
    let b = mesh.bbox();
    let slack = b.min.abs().max(b.max.abs()).max_element() * 1e-9 + 1e-318;
    (b.min, b.max, DVec3::splat(slack))
}

/// `p` is finite and inside the control points' box (with slack).
fn assert_in_hull(p: DVec3, (min, max, slack): (DVec3, DVec3, DVec3), what: &str) {
    assert!(p.is_finite(), "{what}: Ok with a non-finite point {p:?}");
    assert!(
        p.cmpge(min - slack).all() && p.cmple(max + slack).all(),
        "{what}: point {p:?} outside the control points' box {min:?} … {max:?}"
    );
}

/// A normal is unit or zero, and unit and perpendicular to the tangents where
/// they are well apart (checked on the tangents scaled jointly: no overflow or
/// underflow in the test itself).
fn assert_normal(normal: DVec3, du: DVec3, dv: DVec3, what: &str) {
    let length = normal.length();
    assert!(
        length == 0.0 || (length - 1.0).abs() < 1e-9,
        "{what}: normal {normal:?} is neither unit nor zero (tangents {du:?}, {dv:?})"
    );
    if !(du.is_finite() && dv.is_finite()) {
        return;
    }
    let m = du.abs().max_element().max(dv.abs().max_element());
    if m == 0.0 {
        return;
    }
    let scale = subdiv_mesh::PowerOfTwoScale::normalizing([du, dv]);
    let (u, v) = (scale.apply_point(du), scale.apply_point(dv));
    let (lu, lv) = (u.length(), v.length());
    if lu < 1e-6 * lv || lv < 1e-6 * lu || u.cross(v).length() < 1e-6 * lu * lv {
        return;
    }
    assert!((length - 1.0).abs() < 1e-9, "{what}: normal {normal:?} where the tangents {du:?}, {dv:?} span a plane");
    assert!(
        normal.dot(u / lu).abs() < 1e-6 && normal.dot(v / lv).abs() < 1e-6,
        "{what}: normal {normal:?} not perpendicular to the tangents {du:?}, {dv:?}"
    );
}

/// `subdiv evaluate`'s computation (`LimitSurface::evaluate_all`, the
/// normalised evaluation): up to 32 parameters (face, corner, u, v: in the
/// domain mostly, anywhere sometimes) on a shape at any scale. Contract: a
/// typed, one-line error, or every position finite and inside the control
/// points' box, every normal unit (and perpendicular to the tangents) or
/// zero.
pub fn evaluate(data: &[u8]) {
    let (mut head, mut tail) = split_surface(data);
    let Some((mesh, options)) = surface_input(&mut head, &mut tail) else { return };
    let surface = match subdiv_eval::LimitSurface::new(&mesh, &options) {
        Ok(s) => s,
        Err(e) => return assert_one_line(&e.to_string()),
    };
    let faces = mesh.topology().face_count() as u32;
    let mut params = Vec::new();
    while !tail.is_empty() && params.len() < 32 {
        let face = u32::from(tail.u8()) % (faces + 1);
        let corner = u32::from(tail.u8() % 5);
        let unit = |t: &mut Bytes| match t.u8() {
            0..=199 => f64::from(t.u8()) / 255.0,
            200..=219 => 0.0,
            220..=239 => 1.0,
            _ => t.coordinate(),
        };
        let (u, v) = (unit(&mut tail), unit(&mut tail));
        params.push(subdiv_eval::SurfaceParam::new(face, corner, u, v));
    }
    match surface.evaluate_all(mesh.positions(), &params) {
        Ok(samples) => {
            let box_ = hull(&mesh);
            for (p, s) in params.iter().zip(&samples) {
                let what = format!("evaluate {p:?}");
                assert_in_hull(s.position, box_, &what);
                assert_normal(s.normal, s.du, s.dv, &what);
            }
        }
        Err((_, e)) => assert_one_line(&e.to_string()),
    }
}

/// `subdiv sample`'s computation (`sample_surface`): 1–4 per domain side or
/// 0–255 points by area, any seed, on a shape at any scale. Contract: a typed,
/// one-line error, or exactly the asked number of samples, each inside its
/// domain, finite and inside the control points' box, with a unit or zero
/// normal.
pub fn sample(data: &[u8]) {
    let (mut head, mut tail) = split_surface(data);
    let Some((mesh, options)) = surface_input(&mut head, &mut tail) else { return };
    let surface = match subdiv_eval::LimitSurface::new(&mesh, &options) {
        Ok(s) => s,
        Err(e) => return assert_one_line(&e.to_string()),
    };
    let how = if tail.u8() % 2 == 0 {
        subdiv_eval::Sampling::PerDomain(1 + usize::from(tail.u8() % 4))
    } else {
        subdiv_eval::Sampling::ByArea { count: usize::from(tail.u8()), seed: tail.u64() }
    };
    let expected = match how {
        subdiv_eval::Sampling::PerDomain(n) => subdiv_eval::per_domain_count(surface.domains().len(), n),
        subdiv_eval::Sampling::ByArea { count, .. } => Some(count as u64),
    };
    match subdiv_eval::sample_surface(&surface, mesh.positions(), how) {
        Ok(samples) => {
            assert_eq!(Some(samples.len() as u64), expected, "{how:?}: wrong number of samples");
            let box_ = hull(&mesh);
            let shape = subdiv_eval::DomainShape::of(options.scheme);
            for s in &samples {
                let what = format!("sample {how:?} at {:?}", s.param);
                assert!(shape.contains(s.param.u, s.param.v), "{what}: outside its domain");
                assert_in_hull(s.position, box_, &what);
                let l = s.normal.length();
                assert!(l == 0.0 || (l - 1.0).abs() < 1e-9, "{what}: normal {:?} neither unit nor zero", s.normal);
            }
        }
        Err(e) => assert_one_line(&e.to_string()),
    }
}

/// `subdiv project`'s computation (`project_on`, on the normalised mesh and
/// queries): up to 16 queries around the shape (within 1.5 box
/// half-extents of its centre) at any scale. Contract: a typed, one-line
/// error, or every foot finite and inside the control points' box, its
/// distance finite, equal to ‖foot − query‖, and no larger than the distance
/// to any of a grid of surface points (2×2 per domain) beyond a small slack.
pub fn project(data: &[u8]) {
    let (mut head, mut tail) = split_surface(data);
    let Some((mesh, options)) = surface_input(&mut head, &mut tail) else { return };
    let surface = match subdiv_eval::LimitSurface::new(&mesh, &options) {
        Ok(s) => s,
        Err(e) => return assert_one_line(&e.to_string()),
    };
    let b = mesh.bbox();
    let (centre, half) = (b.min * 0.5 + b.max * 0.5, b.max * 0.5 - b.min * 0.5);
    let mut queries = Vec::new();
    while !tail.is_empty() && queries.len() < 16 {
        let t = DVec3::new(tail.u8().into(), tail.u8().into(), tail.u8().into()) / 85.0 - 1.5;
        let q = centre + half * t;
        if q.is_finite() {
            queries.push(q);
        }
    }
    let found = match subdiv_eval::project_on(&surface, &mesh, &options, &queries, &Default::default()) {
        Ok(found) => found,
        Err(e) => return assert_one_line(&e.to_string()),
    };
    let grid = match subdiv_eval::sample_surface(&surface, mesh.positions(), subdiv_eval::Sampling::PerDomain(2)) {
        Ok(grid) => grid,
        Err(e) => return assert_one_line(&e.to_string()),
    };
    let box_ = hull(&mesh);
    let extent = 2.0 * scaled_length(half);
    let far = scaled_length(centre.abs() * 0.5 + half * 0.5) * 2.0;
    for (q, p) in queries.iter().zip(&found) {
        let what = format!("project {q:?}");
        assert_in_hull(p.position, box_, &what);
        assert!(p.distance.is_finite() && p.distance >= 0.0, "{what}: distance {}", p.distance);
        let measured = 2.0 * half_distance(p.position, *q);
        let rounding = 1e-9 * far + 1e-318;
        assert!(
            (p.distance - measured).abs() <= 1e-9 * measured + rounding,
            "{what}: distance {:e} but the foot {:?} is {measured:e} away",
            p.distance,
            p.position
        );
        let nearest = grid.iter().map(|g| 2.0 * half_distance(g.position, *q)).fold(f64::INFINITY, f64::min);
        assert!(
            p.distance <= nearest + 1e-3 * extent + rounding,
            "{what}: distance {:e} (foot {:?} on {:?}) but a surface point is {nearest:e} away",
            p.distance,
            p.position,
            p.param
        );
    }
}

/// `subdiv fit`'s computation (`subdiv_eval::fit`): the shape at any scale as
/// the control mesh, its vertices (some moved) as the target cloud or the
/// mesh itself as the target, 1–3 rounds, a smoothness from 0 to 1e6 or a
/// bad one. Contract: a typed, one-line error, or a finite control mesh and
/// finite distances in every round.
pub fn fit(data: &[u8]) {
    let (mut head, mut tail) = split_surface(data);
    let Some((mesh, options)) = surface_input(&mut head, &mut tail) else { return };
    let target = if tail.u8() % 2 == 0 {
        subdiv_eval::FitTarget::from_mesh(&mesh)
    } else {
        let points = mesh
            .positions()
            .iter()
            .map(|&p| p * (1.0 + f64::from(tail.u8() as i8) * 1e-3))
            .filter(|p| p.is_finite())
            .collect();
        subdiv_eval::FitTarget::cloud(points)
    };
    let fit_options = subdiv_eval::FitOptions {
        surface: options,
        iterations: 1 + usize::from(tail.u8() % 3),
        smoothness: tail.pick(&[0.0, 1e-3, 0.1, 1.0, 1e6, -1.0, f64::NAN]),
        samples_per_domain: 2,
        ..Default::default()
    };
    match subdiv_eval::fit(&target, &mesh, &fit_options) {
        Ok(result) => {
            assert_finite(result.mesh.positions(), "fit");
            for it in &result.iterations {
                assert!(
                    it.rms_target_to_surface.is_finite() && it.max_target_to_surface.is_finite(),
                    "fit: Ok with round {} distances rms {:e}, max {:e}",
                    it.iteration,
                    it.rms_target_to_surface,
                    it.max_target_to_surface
                );
            }
        }
        Err(e) => assert_one_line(&e.to_string()),
    }
}

// ---- numeric helpers ---------------------------------------------------------

/// ‖a − b‖ / 2 for finite `a`, `b`, without overflow (the halves' difference
/// is finite) and without losing subnormal differences (the full difference
/// is used when it is finite).
fn half_distance(a: DVec3, b: DVec3) -> f64 {
    let diff = a - b;
    if diff.is_finite() {
        scaled_length(diff) * 0.5
    } else {
        scaled_length(a * 0.5 - b * 0.5)
    }
}

/// ‖v‖ as m·‖v/m‖ with m the largest component: no overflow or underflow in
/// the squares.
fn scaled_length(v: DVec3) -> f64 {
    let m = v.abs().max_element();
    if m == 0.0 || !m.is_finite() {
        m
    } else {
        m * (v / m).length()
    }
}

// ---- decoding bytes ------------------------------------------------------------

/// The fuzz input read as a stream of small decisions; zeros once exhausted,
/// so every input, even empty, decodes to something.
struct Bytes<'a> {
    data: &'a [u8],
}

impl<'a> Bytes<'a> {
    fn new(data: &'a [u8]) -> Self {
        Self { data }
    }

    fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    fn remaining(&self) -> usize {
        self.data.len()
    }

    fn u8(&mut self) -> u8 {
        let (&first, rest) = self.data.split_first().unwrap_or((&0, &[]));
        self.data = rest;
        first
    }

    fn array<const N: usize>(&mut self) -> [u8; N] {
        let mut out = [0; N];
        for b in &mut out {
            *b = self.u8();
        }
        out
    }

    fn u16(&mut self) -> u16 {
        u16::from_le_bytes(self.array())
    }

    fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.array())
    }

    fn u64(&mut self) -> u64 {
        u64::from_le_bytes(self.array())
    }

    /// One of `items`, by the next byte.
    fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[usize::from(self.u8()) % items.len()]
    }

    /// A coordinate of any kind: mostly a small value on a 1/4 grid, sometimes
    /// one of the extremes, a scaled value of any magnitude, or raw bits
    /// (NaN payloads included).
    fn coordinate(&mut self) -> f64 {
        match self.u8() {
            c @ 0..=239 => (f64::from(c) - 120.0) / 4.0,
            240 => f64::from_bits(self.u64()),
            241 => f64::NAN,
            242 => f64::INFINITY,
            243 => f64::NEG_INFINITY,
            244 => f64::from_bits(1),
            245 => 1e308,
            246 => -1e308,
            247 => f64::MAX,
            248 => 1e-300,
            249 => 1e154,
            _ => self.scaled(),
        }
    }

    /// Any finite value: a scaled one, a grid value, or raw bits with a
    /// non-finite pattern turned finite (its exponent cleared).
    fn finite(&mut self) -> f64 {
        match self.u8() % 4 {
            0 => 0.0,
            1 => (f64::from(self.u8()) - 128.0) / 8.0,
            2 => clamp_finite(self.scaled()),
            _ => {
                let x = f64::from_bits(self.u64());
                if x.is_finite() {
                    x
                } else {
                    f64::from_bits(x.to_bits() & !(0x7ff << 52))
                }
            }
        }
    }

    /// m · 10^e for a small signed mantissa m and e in −330..=309 (so
    /// subnormals, zero and overflow to ±inf occur).
    fn scaled(&mut self) -> f64 {
        let mantissa = f64::from(self.u8() as i8);
        let exponent = i32::from(self.u16() % 640) - 330;
        mantissa * 10f64.powi(exponent)
    }
}
