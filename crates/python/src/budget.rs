//! The size guard of every refinement the bindings run (`subdivide`, `Interpolation.surface`):
//! the exact size of the result is known before anything is allocated
//! (`subdiv::stencil::size`), so a refinement that cannot fit is an `InputError` naming its
//! size instead of an abort on a failed allocation — the command line's rule
//! (`crates/cli/src/budget.rs`, whose budget this repeats in short: ¾ of the memory available).

use crate::errors::{input, Error};
use subdiv::mesh::Topology;
use subdiv::stencil::size::{estimated_subdivide_bytes, refined_sizes};
use subdiv::Scheme;

/// Refuses `levels` steps of `scheme` on `t` when the result cannot have 32-bit ids or needs
/// more than ¾ of the available memory (with `vertex_arrays` further arrays of one point per
/// final vertex: limit positions).
pub fn check(what: &str, t: &Topology, scheme: Scheme, levels: usize, vertex_arrays: u64) -> Result<(), Error> {
    let sizes = refined_sizes(t, scheme, levels);
    let Some(last) = sizes.last() else { return Ok(()) };
    let complete = sizes.len() == levels;
    let approx = if complete { "" } else { "more than " };
    let describe = format!("{approx}{} vertices and {approx}{} faces", last.vertices, last.faces);
    if !complete || !last.fits_u32_ids() {
        return Err(input(format!(
            "{what}: {levels} levels of {} make {describe}: more than 32-bit ids can number; use fewer levels",
            scheme.name()
        )));
    }
    let need =
        estimated_subdivide_bytes(scheme, &sizes).saturating_add(last.vertices.saturating_mul(24 * vertex_arrays));
    if let Some(available) = available_memory() {
        let budget = available / 4 * 3;
        if need > budget {
            return Err(input(format!(
                "{what}: {levels} levels of {} make {describe}, needing about {} MiB: more than the memory budget of \
                 {} MiB (¾ of the memory available); use fewer levels",
                scheme.name(),
                need >> 20,
                budget >> 20
            )));
        }
    }
    Ok(())
}

/// `MemAvailable` of /proc/meminfo in bytes (Linux); `None` elsewhere (then only the id
/// limit is checked).
fn available_memory() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line["MemAvailable:".len()..].split_whitespace().next()?.parse().ok()?;
    Some(kib.saturating_mul(1024))
}
