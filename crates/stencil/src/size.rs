//! What `levels` steps of a scheme will produce, counted before anything is
//! allocated: the size guard of every command that refines.
//!
//! The counts are exact. After one step every scheme's counts follow from the
//! previous level's vertex, edge, face, corner (half-edge) and boundary-edge
//! counts alone:
//!
//! | split ([`SchemeTraits::split`]) | schemes | V′ | E′ | F′ | H′ |
//! |---|---|---|---|---|---|
//! | quad | Catmull-Clark, Deng-Ma | V + E + F | 2E + H | H | 4H |
//! | triangle | Loop | V + E | 2E + 3F | 4F | 12F |
//! | dual | Doo-Sabin | H + 2B | V′ + F′ − χ | F + E + V_f | 2E′ − B′ |
//! | √3, odd step | √3 | V + F | E + 3F | 3F | 9F |
//! | √3, even step | √3 | V + F + B | E + 3F + B | 3F | 9F |
//!
//! with B′ = 2B in every split but √3's (B′ = B after an odd step, 3B after an even one, the
//! first step on the input being odd; each other split halves every boundary edge: Doo-Sabin's
//! two Chaikin points per boundary edge double the boundary polygon), χ the
//! Euler characteristic (kept by every step) and V_f the vertices that get a
//! Doo-Sabin V-face: all vertices used by a face except interior ones of
//! valence 2 (after one step there are none of those). Isolated vertices are
//! kept by the primal schemes and dropped by Doo-Sabin.
//!
//! The memory estimate covers what [`crate::subdivide()`] holds at its peak:
//! every level's topology and stencil (a [`crate::SubdivisionPlan`] keeps them
//! all) and two levels of positions. Its constants are the peak resident
//! memory per final-level corner measured on meshes of 0.7–73 M corners
//! (Catmull-Clark 39 B, Loop 36–38 B, Doo-Sabin 48 B, Deng-Ma 53 B; √3 is
//! not measured yet and takes Loop's constant — the same triangle topology
//! per corner, no stencil held by `subdivide` —: the
//! earlier levels and the positions add a fixed fraction, as every level has
//! 4× the corners of the one before), rounded up by about 15%
//! ([`SchemeTraits::bytes_per_corner`]).
//!
//! [`SchemeTraits::split`]: crate::SchemeTraits::split
//! [`SchemeTraits::bytes_per_corner`]: crate::SchemeTraits::bytes_per_corner

use crate::{Scheme, Split};
use subdiv_mesh::Topology;

/// Element counts of one level (saturating at `u64::MAX`: a count that
/// large only ever serves to refuse).
///
/// `#[non_exhaustive]`: made by [`LevelSize::of`] and [`refined_sizes`], read
/// through its public fields (a new count is not a breaking change).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct LevelSize {
    /// Vertices.
    pub vertices: u64,
    /// Undirected edges.
    pub edges: u64,
    /// Faces.
    pub faces: u64,
    /// Face corners (half-edges).
    pub corners: u64,
    /// Boundary edges.
    pub boundary_edges: u64,
}

impl LevelSize {
    /// The counts of a topology.
    pub fn of(t: &Topology) -> Self {
        let boundary: usize = t.boundary_loops().map(<[_]>::len).sum();
        Self {
            vertices: t.vertex_count() as u64,
            edges: t.edge_count() as u64,
            faces: t.face_count() as u64,
            corners: t.half_edge_count() as u64,
            boundary_edges: boundary as u64,
        }
    }

    /// True when every count fits a `u32` id (what a refined mesh may hold).
    pub fn fits_u32_ids(&self) -> bool {
        let limit = u64::from(u32::MAX) - 1;
        [self.vertices, self.edges, self.faces, self.corners].iter().all(|&c| c <= limit)
    }
}

/// The sizes after 1, 2, …, `levels` steps of `scheme` on `t` (element `k` is
/// level k + 1). Stops early, with the last entry saturated, once a count
/// passes `u64::MAX`.
pub fn refined_sizes(t: &Topology, scheme: Scheme, levels: usize) -> Vec<LevelSize> {
    let euler = t.euler_characteristic();
    let with_v_face = t
        .vertices()
        .filter(|&v| {
            let faces = t.vertex_face_count(v);
            faces > 0 && (faces != 2 || t.is_boundary_vertex(v))
        })
        .count() as u128;
    let split = scheme.traits().split;
    let mut level = LevelSize::of(t);
    let mut out = Vec::with_capacity(levels.min(64));
    for step in 0..levels {
        let (v, e, f, h, b) = (
            u128::from(level.vertices),
            u128::from(level.edges),
            u128::from(level.faces),
            u128::from(level.corners),
            u128::from(level.boundary_edges),
        );
        let (nv, ne, nf, nh) = match split {
            Split::Quad => (v + e + f, 2 * e + h, h, 4 * h),
            Split::Triangle => (v + e, 2 * e + 3 * f, 4 * f, 12 * f),
            Split::Dual => {
                let v_faces = if step == 0 { with_v_face } else { v };
                let (nv, nf) = (h + 2 * b, f + e + v_faces);
                // V − E + F = χ on the refined surface (no isolated vertices).
                let ne = u128::try_from((nv + nf) as i128 - i128::from(euler)).unwrap_or(0);
                (nv, ne, nf, (2 * ne).saturating_sub(2 * b))
            }
            // Kobbelt §4: the even steps (step 2, 4, …) trisect the boundary.
            Split::Sqrt3 if step % 2 == 1 => (v + f + b, e + 3 * f + b, 3 * f, 9 * f),
            Split::Sqrt3 => (v + f, e + 3 * f, 3 * f, 9 * f),
        };
        let nb = match split {
            Split::Sqrt3 if step % 2 == 1 => 3 * b,
            Split::Sqrt3 => b,
            Split::Quad | Split::Triangle | Split::Dual => 2 * b,
        };
        let saturate = |x: u128| u64::try_from(x).unwrap_or(u64::MAX);
        level = LevelSize {
            vertices: saturate(nv),
            edges: saturate(ne),
            faces: saturate(nf),
            corners: saturate(nh),
            boundary_edges: saturate(nb),
        };
        out.push(level);
        if [nv, ne, nf, nh].iter().any(|&c| c > u128::from(u64::MAX) / 16) {
            break;
        }
    }
    out
}

/// Peak resident bytes of [`crate::subdivide()`] with these level sizes
/// (saturating), not counting the input mesh: a constant per corner of the
/// last level (module docs). Add 24 bytes per final vertex
/// for each further per-vertex array a caller builds (normals, limit
/// positions).
pub fn estimated_subdivide_bytes(scheme: Scheme, sizes: &[LevelSize]) -> u64 {
    sizes.last().map_or(0, |s| s.corners.saturating_mul(scheme.traits().bytes_per_corner))
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::{shapes, Mesh};
    use subdiv_rules::deng_ma::Tension;
    use subdiv_rules::LoopBeta;

    /// The counts of the meshes `subdivide` really builds, level by level.
    fn actual(mesh: &Mesh, scheme: Scheme, levels: usize) -> Vec<LevelSize> {
        (1..=levels).map(|l| LevelSize::of(crate::subdivide(mesh, scheme, l, false).unwrap().topology())).collect()
    }

    #[test]
    fn predicted_counts_match_the_refined_meshes_exactly() {
        let valence_two = shapes::split_edges(&shapes::cube(), &[subdiv_mesh::EdgeId(0)], 0.0);
        let cube = shapes::cube();
        let mut positions = cube.positions().to_vec();
        positions.push(subdiv_mesh::DVec3::splat(5.0));
        let soup = subdiv_mesh::PolygonSoup::new(positions, cube.topology().faces().clone());
        let with_isolated_vertex = Mesh::from_soup(soup).unwrap().0;
        let polys: Vec<(&str, Mesh)> = vec![
            ("isolated vertex", with_isolated_vertex),
            ("cube", shapes::cube()),
            ("torus", shapes::torus(6, 4)),
            ("open grid", shapes::quad_grid(3, 2)),
            ("pillow", shapes::pillow()),
            ("plate with holes", shapes::plate_with_holes(5, 4, &[(1, 1), (3, 2)], false)),
            ("polygon mix", shapes::polygon_mix(&shapes::torus(8, 6), 7, 0.3, 0.3, 0.1)),
            ("valence 2", valence_two),
        ];
        let schemes = [Scheme::CatmullClark, Scheme::DooSabin, Scheme::DengMa(Tension::Global(1.0))];
        for (name, mesh) in &polys {
            for scheme in schemes {
                assert_eq!(refined_sizes(mesh.topology(), scheme, 3), actual(mesh, scheme, 3), "{name} {scheme:?}");
            }
        }
        for (name, mesh) in [("icosahedron", shapes::icosahedron()), ("open triangles", shapes::triangle_grid(3, 3))] {
            for scheme in [Scheme::Loop(LoopBeta::Warren), Scheme::Sqrt3] {
                assert_eq!(refined_sizes(mesh.topology(), scheme, 4), actual(&mesh, scheme, 4), "{name} {scheme:?}");
            }
        }
    }

    #[test]
    fn huge_level_counts_saturate_instead_of_overflowing() {
        let sizes = refined_sizes(shapes::cube().topology(), Scheme::CatmullClark, 1000);
        assert!(sizes.len() < 40, "stops once past u64");
        let last = sizes.last().unwrap();
        assert!(!last.fits_u32_ids());
        assert_eq!(estimated_subdivide_bytes(Scheme::CatmullClark, &sizes), u64::MAX);
        // Level 1 of the cube: 26 vertices, 48 edges, 24 faces.
        assert_eq!((sizes[0].vertices, sizes[0].edges, sizes[0].faces), (26, 48, 24));
    }
}
