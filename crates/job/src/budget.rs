//! The size guard of every command that refines (the command line's
//! `subdivide` and `--surface`, the batch, the Python bindings): the exact
//! size of the result is known before anything is allocated
//! ([`subdiv_stencil::size`]), so a refinement that would not fit in memory
//! is refused, with the estimate, instead of aborting on a failed
//! allocation. The same budget guards every other result whose size the
//! caller gives: samples (`sample --count`, `--per-face`), evaluation
//! parameters and projection queries ([`MemoryBudget::check_items`]).
//!
//! The budget is a given number of bytes (the command line's `--max-memory`),
//! else ¾ of the memory this process can still get: the least of the
//! system's available memory (`MemAvailable`), the cgroup's remaining limit,
//! and the address-space and data-size limits (`ulimit -v`, `-d`) minus what
//! the process already uses.

use std::fmt;
use subdiv_io::Format;
use subdiv_mesh::Topology;
use subdiv_stencil::size::{estimated_subdivide_bytes, refined_sizes, LevelSize};
use subdiv_stencil::Scheme;

/// A refinement refused by [`MemoryBudget::check`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BudgetError {
    /// More vertices or faces than 32-bit ids can number.
    #[error("{what}: {levels} levels of {scheme} make {size}: more than 32-bit ids can number; use fewer levels")]
    TooManyIds {
        /// The refinement ("subdivide", "--surface out.ply").
        what: String,
        /// Levels asked for.
        levels: usize,
        /// The scheme's name.
        scheme: &'static str,
        /// "N vertices and M faces" (with "more than" when not computed to the end).
        size: String,
    },
    /// More memory than the budget.
    #[error(
        "{what}: {levels} levels of {scheme} make {size}, needing about {}: more than the memory budget of {} ({source_of_budget}); use fewer levels",
        Bytes(*.need), Bytes(*.budget)
    )]
    OverBudget {
        /// The refinement.
        what: String,
        /// Levels asked for.
        levels: usize,
        /// The scheme's name.
        scheme: &'static str,
        /// "N vertices and M faces".
        size: String,
        /// Estimated bytes.
        need: u64,
        /// The budget in bytes.
        budget: u64,
        /// Where the budget comes from ("--max-memory", "¾ of the 20.1 GiB available").
        source_of_budget: String,
    },
    /// A result of a given number of items (samples, evaluation parameters,
    /// projection queries) needs more memory than the budget.
    #[error(
        "{what}: {items} need about {}: more than the memory budget of {} ({source_of_budget}); {remedy}",
        Bytes(*.need), Bytes(*.budget)
    )]
    TooManyItems {
        /// What asks for them ("--count", "--at p.txt").
        what: String,
        /// "1,000,000,000,000 samples" (or "more than 18,446,744,073,709,551,615 samples").
        items: String,
        /// Estimated bytes (saturated at `u64::MAX`).
        need: u64,
        /// The budget in bytes (`isize::MAX` when the memory available is unknown).
        budget: u64,
        /// Where the budget comes from.
        source_of_budget: String,
        /// What to do ("use a smaller --count").
        remedy: String,
    },
}

impl BudgetError {
    /// A result of `items` needing `need` bytes, over `budget` (for
    /// [`MemoryBudget::check_items`]).
    fn too_many(what: &str, items: String, need: u64, budget: &MemoryBudget, remedy: &str) -> Self {
        BudgetError::TooManyItems {
            what: what.to_string(),
            items,
            need,
            budget: budget.bytes.unwrap_or(isize::MAX as u64),
            source_of_budget: budget.source.clone(),
            remedy: remedy.to_string(),
        }
    }
}

/// A number of bytes, printed with a binary unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Bytes(pub u64);

impl fmt::Display for Bytes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        const UNITS: [&str; 7] = ["B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
        let mut value = self.0 as f64;
        let mut unit = 0;
        while value >= 1024.0 && unit + 1 < UNITS.len() {
            value /= 1024.0;
            unit += 1;
        }
        if unit == 0 {
            write!(f, "{} B", self.0)
        } else {
            write!(f, "{value:.1} {}", UNITS[unit])
        }
    }
}

/// Parses `4096`, `512M`, `8G`, `1.5GiB`, `2TB` (K/M/G/T are powers of 1024).
pub fn parse_bytes(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let split = t.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(t.len());
    let (number, unit) = t.split_at(split);
    let shift = match unit.trim().to_ascii_uppercase().trim_end_matches("IB").trim_end_matches('B') {
        "" => 0,
        "K" => 10,
        "M" => 20,
        "G" => 30,
        "T" => 40,
        other => return Err(format!("unknown unit '{other}' (use K, M, G or T)")),
    };
    let value: f64 = number.parse().map_err(|_| format!("'{text}' is not a number of bytes"))?;
    let bytes = value * (1u64 << shift) as f64;
    if !(1.0..1.8e19).contains(&bytes) {
        return Err(format!("'{text}' is not a positive number of bytes below 16 EiB"));
    }
    Ok(bytes as u64)
}

/// How much a refinement may use, and where that figure comes from.
#[derive(Clone, Debug)]
pub struct MemoryBudget {
    bytes: Option<u64>,
    source: String,
}

impl MemoryBudget {
    /// `bytes`, given by the caller; `source` names it in refusals
    /// (the command line: "--max-memory").
    pub fn given(bytes: u64, source: impl Into<String>) -> Self {
        MemoryBudget { bytes: Some(bytes), source: source.into() }
    }

    /// ¾ of the memory this process can still get (module docs); no limit
    /// but the 32-bit ids when that cannot be read.
    pub fn available() -> Self {
        match available_memory() {
            Some(avail) => {
                MemoryBudget { bytes: Some(avail / 4 * 3), source: format!("¾ of the {} available", Bytes(avail)) }
            }
            None => MemoryBudget { bytes: None, source: "available memory unknown".into() },
        }
    }

    /// [`Self::given`] when `bytes` is set, else [`Self::available`].
    pub fn given_or_available(bytes: Option<u64>, source: &str) -> Self {
        bytes.map_or_else(Self::available, |b| Self::given(b, source))
    }

    /// Refuses `levels` steps of `scheme` on `t` when the result
    /// cannot have 32-bit ids or its estimated memory — plus `vertex_arrays`
    /// further arrays of one point per final vertex (normals, limit
    /// positions) and what writing it as `format` holds in memory (an f32
    /// format's rounded copy of the positions, glTF's buffers, triangles) — exceeds
    /// the budget. `what` names the refinement in the message.
    pub fn check(
        &self,
        what: &str,
        t: &Topology,
        scheme: Scheme,
        levels: usize,
        vertex_arrays: u64,
        format: Option<Format>,
    ) -> Result<(), BudgetError> {
        // glTF is encoded in memory (positions and normals as f32); triangulating formats hold the triangles.
        // Not written (`None`): nothing more held.
        let gltf = if matches!(format, Some(Format::Gltf | Format::Glb)) { 24 } else { 0 };
        // An f32 format's positions are rounded into a copy (`outputs::as_written`); f64 formats write
        // the positions as they are.
        let rounded = if format.is_none_or(Format::keeps_f64) { 0 } else { 24 };
        let extra_per_vertex = 24 * vertex_arrays + gltf + rounded;
        let extra_per_face = if format.is_some_and(Format::triangulates) { 24 } else { 0 };
        let sizes = refined_sizes(t, scheme, levels);
        let Some(last) = sizes.last() else { return Ok(()) };
        let complete = sizes.len() == levels;
        let describe = |s: &LevelSize| {
            let approx = if complete { "" } else { "more than " };
            format!("{approx}{} vertices and {approx}{} faces", group(s.vertices), group(s.faces))
        };
        let need = estimated_subdivide_bytes(scheme, &sizes)
            .saturating_add(last.vertices.saturating_mul(extra_per_vertex))
            .saturating_add(last.faces.saturating_mul(extra_per_face));
        if !complete || !last.fits_u32_ids() {
            return Err(BudgetError::TooManyIds {
                what: what.to_string(),
                levels,
                scheme: scheme.name(),
                size: describe(last),
            });
        }
        if let Some(budget) = self.bytes {
            if need > budget {
                return Err(BudgetError::OverBudget {
                    what: what.to_string(),
                    levels,
                    scheme: scheme.name(),
                    size: describe(last),
                    need,
                    budget,
                    source_of_budget: self.source.clone(),
                });
            }
        }
        Ok(())
    }
}

impl MemoryBudget {
    /// Refuses a result of `count` items of `bytes_each` bytes (`count`
    /// `None`: beyond `u64`) when it exceeds the budget — or, when the
    /// memory available is unknown, what one allocation can hold
    /// (`isize::MAX` bytes). `what` names the request ("--count"), `noun`
    /// the items ("samples"), `remedy` what to do instead.
    ///
    /// ```
    /// use subdiv_job::budget::MemoryBudget;
    /// let budget = MemoryBudget::given(1 << 30, "--max-memory");
    /// assert!(budget.check_items("--count", Some(1000), "samples", 144, "use a smaller --count").is_ok());
    /// let e = budget.check_items("--count", Some(1_000_000_000_000), "samples", 144, "use a smaller --count");
    /// assert_eq!(
    ///     e.unwrap_err().to_string(),
    ///     "--count: 1,000,000,000,000 samples need about 131.0 TiB: more than the memory budget of 1.0 GiB \
    ///      (--max-memory); use a smaller --count"
    /// );
    /// ```
    ///
    /// # Errors
    /// [`BudgetError::TooManyItems`].
    pub fn check_items(
        &self,
        what: &str,
        count: Option<u64>,
        noun: &str,
        bytes_each: u64,
        remedy: &str,
    ) -> Result<(), BudgetError> {
        let limit = self.bytes.unwrap_or(isize::MAX as u64).min(isize::MAX as u64);
        let Some(count) = count else {
            return Err(BudgetError::too_many(
                what,
                format!("more than {} {noun}", group(u64::MAX)),
                u64::MAX,
                self,
                remedy,
            ));
        };
        let need = count.saturating_mul(bytes_each);
        if need > limit {
            return Err(BudgetError::too_many(what, format!("{} {noun}", group(count)), need, self, remedy));
        }
        Ok(())
    }
}

/// 1234567 → "1,234,567".
pub fn group(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// The least of the memory limits that apply to this process, in bytes
/// (Linux: /proc and the cgroup v2 files); `None` when none can be read.
fn available_memory() -> Option<u64> {
    // Through read_text: regular files only (the special-file check), size
    // capped; /proc files report size 0 and are read to their end.
    let read = |p: &str| subdiv_io::read_text(std::path::Path::new(p)).ok();
    let mut limits = Vec::new();
    if let Some(meminfo) = read("/proc/meminfo") {
        limits.extend(field_kib(&meminfo, "MemAvailable:"));
    }
    if let (Some(max), Some(current)) = (read("/sys/fs/cgroup/memory.max"), read("/sys/fs/cgroup/memory.current")) {
        if let (Ok(max), Ok(current)) = (max.trim().parse::<u64>(), current.trim().parse::<u64>()) {
            limits.push(max.saturating_sub(current));
        }
    }
    if let (Some(proc_limits), Some(status)) = (read("/proc/self/limits"), read("/proc/self/status")) {
        for (limit, used) in [("Max address space", "VmSize:"), ("Max data size", "VmData:")] {
            if let (Some(soft), Some(used)) = (soft_limit(&proc_limits, limit), field_kib(&status, used)) {
                limits.push(soft.saturating_sub(used));
            }
        }
    }
    limits.into_iter().min()
}

/// `Key:   123 kB` → bytes.
fn field_kib(text: &str, key: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(key))?;
    let kib: u64 = line[key.len()..].split_whitespace().next()?.parse().ok()?;
    Some(kib * 1024)
}

/// The soft limit of a /proc/self/limits row, `None` when unlimited.
fn soft_limit(limits: &str, name: &str) -> Option<u64> {
    let line = limits.lines().find(|l| l.starts_with(name))?;
    line[name.len()..].split_whitespace().next()?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_sizes_parse_with_binary_units() {
        assert_eq!(parse_bytes("4096"), Ok(4096));
        assert_eq!(parse_bytes("512M"), Ok(512 << 20));
        assert_eq!(parse_bytes("8G"), Ok(8 << 30));
        assert_eq!(parse_bytes("1.5GiB"), Ok(3 << 29));
        assert_eq!(parse_bytes("2 TB"), Ok(2 << 40));
        assert!(parse_bytes("0").is_err());
        assert!(parse_bytes("-1G").is_err());
        assert!(parse_bytes("12 parsecs").is_err());
        assert!(parse_bytes("1e30").is_err());
        assert_eq!(Bytes(3 << 29).to_string(), "1.5 GiB");
        assert_eq!(group(1234567), "1,234,567");
    }

    #[test]
    fn proc_fields_parse() {
        assert_eq!(field_kib("MemTotal: 10 kB\nMemAvailable:  2048 kB\n", "MemAvailable:"), Some(2 << 20));
        let limits = "Limit                     Soft Limit           Hard Limit           Units\n\
                      Max address space         4294967296           unlimited            bytes\n\
                      Max data size             unlimited            unlimited            bytes\n";
        assert_eq!(soft_limit(limits, "Max address space"), Some(4 << 30));
        assert_eq!(soft_limit(limits, "Max data size"), None);
        assert!(available_memory().is_some_and(|b| b > 0), "readable on Linux");
    }

    /// Writing f64 positions takes no copy of them, an f32 format a rounded
    /// one: 24 bytes per vertex more (`outputs::as_written`).
    #[test]
    fn an_f32_format_needs_its_rounded_copy_and_an_f64_format_none() {
        let cube = subdiv_mesh::shapes::cube();
        let (levels, scheme) = (6, Scheme::CatmullClark);
        let sizes = refined_sizes(cube.topology(), scheme, levels);
        let (vertices, faces) = (sizes.last().unwrap().vertices, sizes.last().unwrap().faces);
        // Exactly what the f64 write needs (refined mesh, limit positions, normals).
        let obj = estimated_subdivide_bytes(scheme, &sizes) + 24 * 2 * vertices;
        let check = |bytes: u64, format: Format| {
            let budget = MemoryBudget::given(bytes, "test");
            budget.check("subdivide", cube.topology(), scheme, levels, 2, Some(format)).is_ok()
        };
        assert!(check(obj, Format::Obj) && check(obj, Format::PlyBinary));
        // Binary STL: f32 and triangles (24 B per face) — and the rounded copy on top.
        assert!(Format::StlBinary.triangulates() && !Format::StlBinary.keeps_f64());
        let stl_triangles = obj + 24 * faces;
        assert!(!check(stl_triangles, Format::StlBinary), "the rounded copy is counted");
        assert!(check(stl_triangles + 24 * vertices, Format::StlBinary));
        assert!(!check(obj - 1, Format::Obj));
    }

    #[test]
    fn the_refusal_quotes_the_true_size_of_each_level() {
        let cube = subdiv_mesh::shapes::cube();
        let budget = MemoryBudget::given(1 << 30, "test");
        let message = |levels| match budget.check(
            "subdivide",
            cube.topology(),
            Scheme::CatmullClark,
            levels,
            0,
            Some(Format::Obj),
        ) {
            Err(e) => e.to_string(),
            other => panic!("{other:?}"),
        };
        // Cube: 6·4^L faces, 6·4^(L-1)·... vertices: 4^L·6 faces at level L.
        assert!(message(11).contains("25,165,824 faces"), "{}", message(11));
        assert!(message(12).contains("100,663,296 faces"), "{}", message(12));
        assert!(message(40).contains("32-bit"), "{}", message(40));
        assert!(budget.check("subdivide", cube.topology(), Scheme::CatmullClark, 5, 0, Some(Format::Obj)).is_ok());
    }
}
