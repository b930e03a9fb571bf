//! The tags of the tagged benchmarks (`benches/tagged.rs`, `examples/tagged_time.rs`):
//! every 10th edge (by a fixed hash of its id) creased — a third each
//! infinitely sharp (10), 2.5 and 1.0 — and every 50th vertex a corner (10).

use subdiv_mesh::{Mesh, Tags};

/// A fixed scramble of an index (splitmix64's finaliser).
fn scramble(i: u64) -> u64 {
    let mut z = i.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The mesh with ~10 % of its edges creased and ~2 % of its vertices corners.
pub fn tagged(mesh: &Mesh) -> Mesh {
    let t = mesh.topology();
    let sharpness = [10.0, 2.5, 1.0];
    let edges = (0..t.edge_count() as u64)
        .map(|e| sharpness.get((scramble(e) % 30) as usize).copied().unwrap_or(0.0))
        .collect();
    let vertices =
        (0..t.vertex_count() as u64).map(|v| if scramble(v ^ 0xabcd) % 50 == 0 { 10.0 } else { 0.0 }).collect();
    mesh.clone().with_tags(Tags::from_arrays(t, edges, vertices).expect("valid tags"))
}
