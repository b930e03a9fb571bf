//! The order a block solve of A·X = P takes: corners, the crease polygons
//! of the sharp block, the interior (`subdiv_stencil::limit_matrix`, "Blocks").

use subdiv_stencil::{LimitMatrix, RowKind};

/// The order a solve can take ([`solve_blocks`]): each set depends only on
/// itself and the sets before it.
///
/// `#[non_exhaustive]`: read through its public fields (a new block is not a
/// breaking change).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct SolveBlocks {
    /// Identity rows: X = P.
    pub corners: Vec<u32>,
    /// Crease and boundary polygon rows of the sharp block: (1, 4, 1)/6
    /// (Doo-Sabin (1, 6, 1)/8; (2, 5, 1)/8 and (2, 4, 2)/8 next to corners)
    /// among themselves, symmetric, and corners.
    pub creases: Vec<u32>,
    /// Every other row: smooth rows (symmetric among themselves), general
    /// rows and the crease rows that lean on one ([`LimitMatrix::asymmetric_rows`]
    /// says whether the block is symmetric).
    pub interior: Vec<u32>,
}

/// The rows of `a` split in solve order: corners, the crease polygons of the
/// sharp block ([`LimitMatrix::boundary_rows`]), the interior.
pub fn solve_blocks(a: &LimitMatrix) -> SolveBlocks {
    let mut sharp = vec![false; a.size()];
    a.boundary_rows.iter().for_each(|&v| sharp[v as usize] = true);
    let mut out = SolveBlocks::default();
    for (v, &kind) in a.row_kinds.iter().enumerate() {
        let block = match kind {
            RowKind::Corner => &mut out.corners,
            _ if sharp[v] => &mut out.creases,
            _ => &mut out.interior,
        };
        block.push(v as u32);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::{shapes, EdgeTag, TagList, Tags, VertexTag};
    use subdiv_stencil::{limit_matrix_catmull_clark_sharp, LevelSharpness};

    /// The blocks partition the rows; corners are the corner rows, creases
    /// the other rows of the sharp block, and every block's columns lie in
    /// it and the blocks before it (block lower-triangular order).
    #[test]
    fn blocks_partition_the_rows_in_a_triangular_order() {
        let grid = shapes::quad_grid(6, 5);
        let id = |i: u32, j: u32| j * 7 + i;
        let list = TagList {
            creases: vec![
                EdgeTag { a: id(1, 2), b: id(2, 2), sharpness: 10.0 },
                EdgeTag { a: id(2, 2), b: id(3, 2), sharpness: 10.0 },
                EdgeTag { a: id(3, 2), b: id(3, 3), sharpness: 1.5 },
            ],
            corners: vec![VertexTag { vertex: id(4, 4), sharpness: 10.0 }],
            ..Default::default()
        };
        let tags = Tags::from_list(grid.topology(), &list).unwrap();
        let sharp = LevelSharpness::new(&tags, Default::default(), Default::default());
        let a = limit_matrix_catmull_clark_sharp(grid.topology(), &sharp).unwrap();
        let blocks = solve_blocks(&a);
        let mut all: Vec<u32> = [&blocks.corners[..], &blocks.creases, &blocks.interior].concat();
        all.sort_unstable();
        assert_eq!(all, (0..a.size() as u32).collect::<Vec<_>>());
        assert_eq!(blocks.corners, a.rows_of(RowKind::Corner));
        let sharp_block: Vec<u32> = a.boundary_rows.iter().copied().filter(|v| !blocks.corners.contains(v)).collect();
        assert_eq!(blocks.creases, sharp_block);
        assert!(!blocks.creases.is_empty() && !blocks.interior.is_empty());
        let order: Vec<&[u32]> = vec![&blocks.corners, &blocks.creases, &blocks.interior];
        for (k, block) in order.iter().enumerate() {
            for &v in *block {
                for &c in a.s.outer_view(v as usize).unwrap().indices() {
                    assert!(order[..=k].iter().any(|b| b.contains(&c)), "row {v} of block {k} reads {c}");
                }
            }
        }
    }
}
