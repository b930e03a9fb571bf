//! `cargo xtask valence2-mesh IN OUT --count N [--chain K]`: a copy of a
//! mesh with interior valence-2 vertices, the vertices Cheng's proof excludes
//! (the quadratic form of the Catmull-Clark limit matrix has the term
//! n(n − 3)/4·x², negative for n = 2: Cheng et al., appendix Eq. 6).
//!
//! Each of `N` interior edges (a, b) shared by two quads gets `K` new
//! vertices v₁ … v_K: both faces get (a, v₁, …, v_K, b) in place of (a, b), so
//! every vᵢ has two edges and two faces. vᵢ sits at a + i/(K + 1)·(b − a),
//! moved off the surface along the mean normal of the two faces by
//! `--offset` × |b − a|, so the data are not on the flat patch. The input's
//! vertices keep their order and positions; the new ones come after them. The
//! edges are spread evenly over the edge list, and no two split edges share a
//! vertex or a face, so the groups stay apart.
//!
//! Which of the two makes the limit matrix indefinite matters: a **lone**
//! valence-2 vertex (K = 1, two pentagons sharing two consecutive edges)
//! leaves it positive definite — x = e_v gives 2/5 + 1 − ½ > 0 and the
//! neighbours only add (LDLᵀ finds no negative pivot on such meshes); a
//! **chain** of two (K = 2, two hexagons sharing three consecutive edges)
//! makes it indefinite: x = e_{v₁} − e_{v₂} zeroes every face and the middle
//! edge term, leaving ½ + ½ from the outer edges against −½ − ½ from the two
//! vertex terms, i.e. 0, and moving x_a, x_b off zero makes it negative (one
//! negative eigenvalue per chain, as the pillow, [correction C3]).
//!
//! [correction C3]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#c3

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
    /// Valence-2 vertices per split edge: 1 leaves Catmull-Clark's A definite, 2 makes it indefinite.
    #[arg(long, default_value_t = 1)]
    chain: usize,
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
    let split = split_edges(&mesh, args.count, args.chain, args.offset)
        .with_context(|| format!("{}: cannot split {} edges", args.input.display(), args.count))?;
    let view = subdiv_io::MeshView::new(split.positions(), split.topology().faces());
    subdiv_io::write_mesh_view(&args.output, view).with_context(|| args.output.display().to_string())?;
    let t = split.topology();
    eprintln!(
        "valence2-mesh: {} vertices ({} of valence 2 in chains of {}, numbered from {}), {} faces → {}",
        t.vertex_count(),
        args.count * args.chain,
        args.chain,
        mesh.topology().vertex_count(),
        t.face_count(),
        args.output.display()
    );
    Ok(())
}

/// `mesh` with `count` interior edges between two quads split by `chain`
/// new vertices each (see the module doc); the new vertices are numbered
/// from `mesh`'s vertex count on, edge by edge, each edge's from a to b.
///
/// # Errors
/// If the mesh has fewer than `count` such edges that share no vertex and
/// no face, `chain` is 0, or `offset` is not finite.
pub fn split_edges(mesh: &Mesh, count: usize, chain: usize, offset: f64) -> Result<Mesh> {
    if !offset.is_finite() {
        bail!("--offset must be finite, got {offset}");
    }
    if chain == 0 {
        bail!("--chain must be at least 1");
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
    // Per face: the corner after which the chain goes, its first vertex, and
    // whether the face runs a → b (chain in order) or b → a (reversed).
    let mut insert: Vec<Option<(usize, u32, bool)>> = vec![None; t.face_count()];
    for (k, &e) in chosen.iter().enumerate() {
        let ((a, b), (f, g)) = (t.edge_vertices(e), t.edge_faces(e));
        let g = g.expect("interior");
        let (pa, pb) = (mesh.position(a), mesh.position(b));
        let lift = offset * pa.distance(pb) * (mesh.face_normal(f) + mesh.face_normal(g)).normalize_or_zero();
        for i in 1..=chain {
            positions.push(pa.lerp(pb, i as f64 / (chain + 1) as f64) + lift);
        }
        let first = n + (k * chain) as u32;
        for face in [f, g] {
            let corners = t.face(face);
            let m = corners.len();
            let (i, forward) = (0..m)
                .find_map(|i| match (corners[i], corners[(i + 1) % m]) {
                    (x, y) if (x, y) == (a.0, b.0) => Some((i, true)),
                    (x, y) if (x, y) == (b.0, a.0) => Some((i, false)),
                    _ => None,
                })
                .expect("the edge is a side of both its faces");
            insert[face.0 as usize] = Some((i, first, forward));
        }
    }
    let mut faces = FaceList::new();
    let mut buffer = Vec::with_capacity(4 + chain);
    for (face, corners) in t.faces().iter().enumerate() {
        buffer.clear();
        buffer.extend_from_slice(corners);
        if let Some((i, first, forward)) = insert[face] {
            let run = first..first + chain as u32;
            if forward {
                buffer.splice(i + 1..i + 1, run);
            } else {
                buffer.splice(i + 1..i + 1, run.rev());
            }
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
        let split = split_edges(&mesh, 6, 1, 0.1).unwrap();
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

    /// Negative pivots of the sparse LDLᵀ of Catmull-Clark's S: by Sylvester's
    /// law of inertia, the number of negative eigenvalues of A = D·S.
    fn negative_eigenvalues(mesh: &Mesh) -> usize {
        use subdiv_solve::{FactoredMatrix, SolveOptions, Solver};
        let a = subdiv_stencil::limit_matrix_catmull_clark(mesh.topology());
        let fm = FactoredMatrix::new(a.d, a.s).unwrap();
        let p: Vec<[f64; 3]> = mesh.positions().iter().map(|q| q.to_array()).collect();
        let opts = SolveOptions::default().with_tol(1e-9).with_scale(mesh.bbox_diagonal());
        Solver::Ldl.solve(&fm, &p, &opts).unwrap().negative_pivots.unwrap()
    }

    #[test]
    fn lone_valence_2_vertices_keep_a_definite_and_chains_of_two_or_three_make_one_negative_eigenvalue_each() {
        let mesh = shapes::torus(12, 8);
        assert_eq!(negative_eigenvalues(&mesh), 0);
        assert_eq!(negative_eigenvalues(&split_edges(&mesh, 3, 1, 0.1).unwrap()), 0);
        for chain in [2, 3] {
            let split = split_edges(&mesh, 3, chain, 0.1).unwrap();
            assert_eq!(negative_eigenvalues(&split), 3, "chains of {chain}");
        }
        let pillow = shapes::pillow();
        assert_eq!(negative_eigenvalues(&pillow), 1, "the pillow: λ = −1/7 (correction C3, docs/REFERENCES.md)");
    }

    #[test]
    fn a_chain_runs_from_a_to_b_in_both_faces_in_opposite_directions() {
        let mesh = shapes::torus(6, 4);
        let n = mesh.topology().vertex_count() as u32;
        let split = split_edges(&mesh, 1, 3, 0.0).unwrap();
        let s = split.topology();
        let chain = [n, n + 1, n + 2];
        let (mut forward, mut backward) = (0, 0);
        for f in s.faces().iter().filter(|f| f.len() == 7) {
            let at = f.iter().position(|&v| v == n).unwrap();
            let run: Vec<u32> = (0..3).map(|k| f[(at + k) % 7]).collect();
            let back: Vec<u32> = (0..3).map(|k| f[(at + 7 - k) % 7]).collect();
            forward += usize::from(run == chain);
            backward += usize::from(back == chain);
        }
        assert_eq!((forward, backward), (1, 1), "one face a → b, the other b → a");
        // With no offset the chain divides the edge evenly: v_i = a + i/4·(b − a).
        let (p, q) = (split.position(VertexId(n)), split.position(VertexId(n + 2)));
        let ends: Vec<_> = s.vertex_neighbors(VertexId(n)).chain(s.vertex_neighbors(VertexId(n + 2))).collect();
        let a = ends.iter().find(|v| v.0 < n).map(|&v| split.position(v)).unwrap();
        let b = ends.iter().rev().find(|v| v.0 < n).map(|&v| split.position(v)).unwrap();
        assert!((p - a.lerp(b, 0.25)).length() < 1e-15 && (q - a.lerp(b, 0.75)).length() < 1e-15);
        assert_eq!(s.vertices().filter(|&v| s.valence(v) == 2).count(), 3);
    }

    #[test]
    fn split_edges_refuses_more_edges_than_fit() {
        // Each split takes two of the 16 quads: at most 8 fit.
        assert!(split_edges(&shapes::torus(4, 4), 2, 1, 0.1).is_ok());
        assert!(split_edges(&shapes::torus(4, 4), 9, 1, 0.1).is_err());
        assert!(split_edges(&shapes::quad_grid(1, 1), 1, 1, 0.1).is_err(), "no interior edge");
        assert!(split_edges(&shapes::torus(8, 8), 1, 1, f64::NAN).is_err());
        assert!(split_edges(&shapes::torus(8, 8), 1, 0, 0.1).is_err());
    }
}
