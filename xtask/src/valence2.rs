//! `cargo xtask valence2-mesh IN OUT --count N`: a copy of a mesh with `N`
//! interior valence-2 vertices, the case that makes Cheng's Catmull-Clark
//! limit matrix indefinite (its quadratic form has the term n(n − 3)/4·x²,
//! negative for n = 2: Cheng et al., appendix Eq. 6).
//!
//! Each new vertex splits an interior edge (a, b) shared by two quads: both
//! faces get (a, v, b) in place of (a, b) and become pentagons, so v has two
//! edges and two faces. v sits at the edge midpoint moved off the surface
//! along the mean normal of the two faces by `--offset` × |b − a|, so the
//! data are not on the flat Catmull-Clark patch. The input's vertices keep
//! their order and positions; the new vertices come after them. The edges are
//! spread evenly over the edge list, and no two split edges share a vertex
//! or a face, so the valence-2 vertices stay apart.

use anyhow::{bail, Context, Result};
use std::path::PathBuf;
use subdiv_mesh::{FaceList, Mesh};

/// Arguments of `valence2-mesh`.
#[derive(clap::Args, Debug)]
pub struct Valence2Args {
    /// Input mesh (any format `subdiv-io` reads).
    input: PathBuf,
    /// Output mesh (format by extension).
    output: PathBuf,
    /// How many interior edges between two quads to split.
    #[arg(long, default_value_t = 4)]
    count: usize,
    /// How far each new vertex leaves the surface, in units of its edge's length.
    #[arg(long, default_value_t = DEFAULT_OFFSET)]
    offset: f64,
}

/// The default off-surface offset of a new vertex, in edge lengths.
pub const DEFAULT_OFFSET: f64 = 0.1;

/// Runs `valence2-mesh`.
pub fn run(args: &Valence2Args) -> Result<()> {
    let soup = subdiv_io::read_mesh(&args.input)?;
    let (mesh, _) = Mesh::from_soup(soup).with_context(|| args.input.display().to_string())?;
    let split = split_edges(&mesh, args.count, args.offset)
        .with_context(|| format!("{}: cannot place {} valence-2 vertices", args.input.display(), args.count))?;
    let view = subdiv_io::MeshView::new(split.positions(), split.topology().faces());
    subdiv_io::write_mesh(&args.output, view).with_context(|| args.output.display().to_string())?;
    let t = split.topology();
    eprintln!(
        "valence2-mesh: {} vertices ({} of valence 2, numbered from {}), {} faces → {}",
        t.vertex_count(),
        args.count,
        mesh.topology().vertex_count(),
        t.face_count(),
        args.output.display()
    );
    Ok(())
}

/// `mesh` with `count` interior edges between two quads split by a new
/// vertex each (see the module doc); the new vertices are numbered from
/// `mesh`'s vertex count on, in the order of their edges.
///
/// # Errors
/// If the mesh has fewer than `count` such edges that share no vertex and
/// no face, or `offset` is not finite.
pub fn split_edges(mesh: &Mesh, count: usize, offset: f64) -> Result<Mesh> {
    if !offset.is_finite() {
        bail!("--offset must be finite, got {offset}");
    }
    let t = mesh.topology();
    let candidates: Vec<_> = t
        .edges()
        .filter(|&e| match t.edge_faces(e) {
            (f, Some(g)) => t.face_size(f) == 4 && t.face_size(g) == 4,
            _ => false,
        })
        .collect();
    let (mut face_used, mut vertex_used) = (vec![false; t.face_count()], vec![false; t.vertex_count()]);
    let mut chosen = Vec::with_capacity(count);
    // Evenly spaced starting points; from each, the first free candidate.
    for k in 0..count {
        let start = (2 * k + 1) * candidates.len() / (2 * count.max(1));
        let free = (start..candidates.len()).chain(0..start).map(|i| candidates[i]).find(|&e| {
            let ((a, b), (f, g)) = (t.edge_vertices(e), t.edge_faces(e));
            let g = g.expect("candidates are interior");
            !(vertex_used[a.0 as usize]
                || vertex_used[b.0 as usize]
                || face_used[f.0 as usize]
                || face_used[g.0 as usize])
        });
        let Some(e) = free else {
            bail!(
                "only {} of the {count} edges found ({} interior edges between two quads)",
                chosen.len(),
                candidates.len()
            );
        };
        let ((a, b), (f, g)) = (t.edge_vertices(e), t.edge_faces(e));
        vertex_used[a.0 as usize] = true;
        vertex_used[b.0 as usize] = true;
        face_used[f.0 as usize] = true;
        face_used[g.expect("interior").0 as usize] = true;
        chosen.push(e);
    }
    let n = t.vertex_count() as u32;
    let mut positions = mesh.positions().to_vec();
    // Per face, the split edge's first corner and the new vertex.
    let mut insert: Vec<Option<(u32, u32)>> = vec![None; t.face_count()];
    for (k, &e) in chosen.iter().enumerate() {
        let ((a, b), (f, g)) = (t.edge_vertices(e), t.edge_faces(e));
        let g = g.expect("interior");
        let (pa, pb) = (mesh.position(a), mesh.position(b));
        let normal = (mesh.face_normal(f) + mesh.face_normal(g)).normalize_or_zero();
        positions.push((pa + pb) / 2.0 + offset * pa.distance(pb) * normal);
        let w = n + k as u32;
        for face in [f, g] {
            let corners = t.face(face);
            let i = (0..corners.len())
                .find(|&i| {
                    let (x, y) = (corners[i], corners[(i + 1) % corners.len()]);
                    (x, y) == (a.0, b.0) || (x, y) == (b.0, a.0)
                })
                .expect("the edge is a side of both its faces");
            insert[face.0 as usize] = Some((i as u32, w));
        }
    }
    let mut faces = FaceList::new();
    let mut buffer = Vec::with_capacity(8);
    for (face, corners) in t.faces().iter().enumerate() {
        buffer.clear();
        buffer.extend_from_slice(corners);
        if let Some((i, w)) = insert[face] {
            buffer.insert(i as usize + 1, w);
        }
        faces.push(&buffer);
    }
    Ok(Mesh::new(positions, faces)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::{shapes, VertexId};

    #[test]
    fn split_edges_adds_separate_interior_valence_2_vertices_and_keeps_the_input() {
        let mesh = shapes::torus(12, 8);
        let t = mesh.topology();
        let split = split_edges(&mesh, 6, 0.1).unwrap();
        let s = split.topology();
        assert_eq!(s.vertex_count(), t.vertex_count() + 6);
        assert_eq!(s.face_count(), t.face_count());
        assert_eq!(s.edge_count(), t.edge_count() + 6);
        assert_eq!(s.euler_characteristic(), t.euler_characteristic());
        assert!(s.is_closed());
        assert_eq!(&split.positions()[..t.vertex_count()], mesh.positions());
        let valence2: Vec<u32> = s.vertices().filter(|&v| s.valence(v) == 2).map(|v| v.0).collect();
        assert_eq!(valence2, (t.vertex_count() as u32..s.vertex_count() as u32).collect::<Vec<_>>());
        let mut neighbours = std::collections::HashSet::new();
        for &v in &valence2 {
            let v = VertexId(v);
            assert!(!s.is_boundary_vertex(v));
            assert_eq!(s.vertex_face_count(v), 2);
            for u in s.vertex_neighbors(v) {
                assert!(u.0 < t.vertex_count() as u32, "valence-2 vertices are not adjacent");
                assert!(neighbours.insert(u), "two split edges share vertex {}", u.0);
            }
            // Off the surface by a tenth of the edge (the torus's faces are nearly flat).
            let ends: Vec<_> = s.vertex_neighbors(v).map(|u| split.position(u)).collect();
            let mid = (ends[0] + ends[1]) / 2.0;
            let rel = split.position(v).distance(mid) / ends[0].distance(ends[1]);
            assert!((rel - 0.1).abs() < 1e-12, "offset {rel}");
        }
        let sizes = s.faces().iter().filter(|f| f.len() == 5).count();
        assert_eq!(sizes, 12, "each split turns two quads into pentagons");
    }

    #[test]
    fn split_edges_refuses_more_edges_than_fit() {
        // Each split takes two of the 16 quads: at most 8 fit.
        assert!(split_edges(&shapes::torus(4, 4), 2, 0.1).is_ok());
        assert!(split_edges(&shapes::torus(4, 4), 9, 0.1).is_err());
        assert!(split_edges(&shapes::quad_grid(1, 1), 1, 0.1).is_err(), "no interior edge");
        assert!(split_edges(&shapes::torus(8, 8), 1, f64::NAN).is_err());
    }
}
