//! The fairness energy: the umbrella Laplacian of a level's points, with the
//! curve rule along boundaries and creases, and its weighted sum of squares.

use crate::SurfaceOptions;
use glam::DVec3;
use subdiv_mesh::{Mesh, Topology, VertexId};
use subdiv_stencil::{LevelSharpness, SparseMatrix};

/// The row of the discrete Laplacian at one vertex: which neighbours it
/// averages (the centre has weight −1).
enum LaplacianRow {
    /// Interior (or a dart): the mean of every edge neighbour.
    Surface,
    /// On a boundary or a crease (two sharp edges): the mean of the two
    /// neighbours along it (the curve's second difference).
    Curve(VertexId, VertexId),
    /// A corner (vertex tag, three or more sharp edges, an isolated vertex):
    /// no term, the point is not smooth there.
    None,
}

fn row_kind(t: &Topology, sharp: &LevelSharpness, v: VertexId) -> LaplacianRow {
    if t.is_isolated(v) || sharp.vertex(t, v) > 0.0 {
        return LaplacianRow::None;
    }
    let fan = t.vertex_fan(v);
    let mut ends = [VertexId(u32::MAX); 2];
    let mut count = 0;
    let mut note = |e, w: VertexId| {
        if sharp.edge(t, e) > 0.0 {
            if count < 2 {
                ends[count] = w;
            }
            count += 1;
        }
    };
    for &h in fan {
        note(t.he_edge(h), t.he_to(h));
    }
    if t.is_boundary_vertex(v) {
        let closing = t.he_prev(fan[fan.len() - 1]);
        note(t.he_edge(closing), t.he_from(closing));
    }
    match count {
        0 | 1 => LaplacianRow::Surface,
        2 => LaplacianRow::Curve(ends[0], ends[1]),
        _ => LaplacianRow::None,
    }
}

/// V × V umbrella Laplacian of `t` with the sharpness `sharp`: row v gives
/// (Δx)_v = mean of v's neighbours − x_v, where the neighbours are every
/// edge neighbour for a smooth vertex or a dart, the two neighbours along
/// the boundary or crease for a vertex on one, and there is no row (zero) at
/// a corner.
pub(crate) fn umbrella(t: &Topology, sharp: &LevelSharpness) -> SparseMatrix {
    use rayon::prelude::*;
    let n = t.vertex_count();
    // Rows in parallel over fixed ranges of vertices, concatenated in order
    // (the same matrix whatever the thread count).
    const CHUNK: usize = 8192;
    let chunks: Vec<(Vec<u32>, Vec<u32>, Vec<f64>)> = (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let range = c * CHUNK..((c + 1) * CHUNK).min(n);
            let mut ends = Vec::with_capacity(range.len());
            let (mut indices, mut data) = (Vec::with_capacity(6 * range.len()), Vec::with_capacity(6 * range.len()));
            let mut row: Vec<(u32, f64)> = Vec::new();
            for v in range.map(|v| VertexId(v as u32)) {
                row.clear();
                match row_kind(t, sharp, v) {
                    LaplacianRow::None => {}
                    LaplacianRow::Curve(a, b) => row.extend([(a.0, 0.5), (b.0, 0.5), (v.0, -1.0)]),
                    LaplacianRow::Surface => {
                        let k = t.valence(v);
                        let w = 1.0 / k as f64;
                        row.extend(t.vertex_neighbors(v).map(|u| (u.0, w)));
                        row.push((v.0, -1.0));
                    }
                }
                // Sorted columns, repeated ones summed (a neighbour twice on coarse meshes).
                row.sort_unstable_by_key(|e| e.0);
                let mut last = u32::MAX;
                for &(j, w) in &row {
                    if j == last {
                        *data.last_mut().expect("a previous entry") += w;
                    } else {
                        indices.push(j);
                        data.push(w);
                        last = j;
                    }
                }
                ends.push(indices.len() as u32);
            }
            (ends, indices, data)
        })
        .collect();
    let nnz: usize = chunks.iter().map(|c| c.1.len()).sum();
    let mut indptr = Vec::with_capacity(n + 1);
    let (mut indices, mut data) = (Vec::with_capacity(nnz), Vec::with_capacity(nnz));
    indptr.push(0u32);
    for (ends, i, d) in chunks {
        let base = indices.len() as u32;
        indptr.extend(ends.iter().map(|e| base + e));
        indices.extend(i);
        data.extend(d);
    }
    SparseMatrix::new((n, n), indptr, indices, data)
}

/// Σ_v ‖(Δx)_v‖² of the points `x` of `t` with `sharp` ([`umbrella`]'s rows).
pub(crate) fn umbrella_sum(t: &Topology, sharp: &LevelSharpness, x: &[DVec3]) -> f64 {
    let mut sum = 0.0;
    let mut ring = Vec::new();
    for v in t.vertices() {
        let lap = match row_kind(t, sharp, v) {
            LaplacianRow::None => continue,
            LaplacianRow::Curve(a, b) => (x[a.index()] + x[b.index()]) * 0.5 - x[v.index()],
            LaplacianRow::Surface => {
                ring.clear();
                ring.extend(t.vertex_neighbors(v));
                ring.iter().map(|u| x[u.index()]).sum::<DVec3>() / ring.len() as f64 - x[v.index()]
            }
        };
        sum += lap.length_squared();
    }
    sum
}

/// The discrete thin-plate energy of a surface sampled at `level` refinement
/// levels of the input, relative to `d` (the input's bounding-box diagonal,
/// the same for every surface compared):
///
/// E = 4^level · Σ_v ‖(Δx)_v‖² / d²,
///
/// with Δ the umbrella Laplacian of the mesh's connectivity (the mean of the
/// edge neighbours minus the point; along boundaries and creases of the
/// mesh's tags, the mean of the two neighbours on the curve; no term at
/// corners). On a parametrically regular sampling of spacing h ∝ 2^−level,
/// Δx ≈ (h²/4)·(x_uu + x_vv) and the sum has ∝ 4^level terms, so 4^level·Σ
/// tends to a multiple of the parametric thin-plate functional
/// ∫‖x_uu + x_vv‖² as the level grows: the factor makes energies of one
/// surface sampled at different levels comparable. Dividing by d² makes it
/// invariant under scaling (d is a parameter: surfaces through the same
/// data have different bounding boxes). `surface` gives the boundary option, which makes
/// a boundary vertex in one face a corner (`edge-and-corner`).
///
/// This is the function by which every method's result is compared
/// (`xtask reproduce-paper --only table7`): apply it to
/// [`crate::Interpolant::surface`] of the levels that bring the control mesh
/// to `level` levels of the input.
pub fn thin_plate_energy(mesh: &Mesh, surface: SurfaceOptions, level: u32, d: f64) -> f64 {
    let sharp = surface.sharpness(mesh.tags());
    4f64.powi(level as i32) * umbrella_sum(mesh.topology(), &sharp, mesh.positions()) / (d * d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::shapes;

    #[test]
    fn the_matrix_and_the_direct_sum_agree() {
        for mesh in [shapes::torus(6, 5), shapes::quad_grid(4, 3), shapes::icosahedron()] {
            let sharp = SurfaceOptions::default().sharpness(mesh.tags());
            let l = umbrella(mesh.topology(), &sharp);
            let lx = subdiv_stencil::apply(&l, mesh.positions());
            let by_matrix: f64 = lx.iter().map(|p| p.length_squared()).sum();
            let direct = umbrella_sum(mesh.topology(), &sharp, mesh.positions());
            assert!((by_matrix - direct).abs() <= 1e-12 * direct.max(1.0), "{by_matrix} vs {direct}");
        }
    }

    #[test]
    fn a_plane_has_no_energy_inside_and_rows_sum_to_zero() {
        // A flat grid: every interior umbrella vanishes, the boundary rows
        // are second differences of straight lines (zero), corners have none.
        let grid = shapes::quad_grid(5, 4);
        let e = thin_plate_energy(&grid, SurfaceOptions::default(), 0, 1.0);
        assert!(e.abs() < 1e-24, "{e}");
        let l = umbrella(grid.topology(), &SurfaceOptions::default().sharpness(grid.tags()));
        for (i, row) in l.outer_iterator().enumerate() {
            let s: f64 = row.iter().map(|(_, w)| w).sum();
            assert!(s.abs() < 1e-15, "row {i} sums to {s}");
        }
    }
}
