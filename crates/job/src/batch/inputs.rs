//! A batch's inputs: paths, directories and glob patterns expanded to a
//! list of files ([`expand_inputs`]), and the unique name each one's outputs
//! take ([`output_names`]).

use super::BatchError;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

/// True for a file name with the extension of a mesh format.
fn is_mesh_file(path: &Path) -> bool {
    path.is_file() && subdiv_io::Format::from_path(path).is_ok()
}

/// Expands each input, in order, into files:
///
/// - a directory: its mesh files (an extension [`subdiv_io::Format`]
///   knows; not its subdirectories), sorted by name;
/// - an existing path: itself (whatever it is: a file that is no mesh fails
///   in its own record);
/// - a path that does not exist and holds `*`, `?` or `[`: a glob pattern
///   (the `glob` crate: `*` and `?` within a name, `[...]` classes, `**`
///   across directories), its matching mesh files in sorted order;
/// - any other path: itself (its record will say it does not exist).
///
/// A file named twice (also through another spelling of its path) is kept
/// at its first place.
///
/// # Errors
/// [`BatchError::Pattern`] for a malformed pattern, [`BatchError::NoMatch`]
/// for a pattern without mesh files (a typo would otherwise run on
/// nothing), [`BatchError::NoMeshInDirectory`] for such a directory,
/// [`BatchError::Io`] for a directory that cannot be listed.
pub fn expand_inputs(inputs: &[PathBuf]) -> Result<Vec<PathBuf>, BatchError> {
    let mut files = Vec::new();
    for input in inputs {
        let before = files.len();
        if input.is_dir() {
            let mut entries =
                subdiv_io::fs::list_dir(input).map_err(|source| BatchError::Io { path: input.clone(), source })?;
            let subdirectories = entries.iter().any(|p| p.is_dir());
            entries.retain(|p| is_mesh_file(p));
            if entries.is_empty() {
                return Err(BatchError::NoMeshInDirectory { dir: input.clone(), subdirectories });
            }
            entries.sort();
            files.extend(entries);
        } else if input.exists() {
            files.push(input.clone());
            continue;
        } else if input.to_string_lossy().contains(['*', '?', '[']) {
            let pattern = input.to_string_lossy();
            let paths = glob::glob(&pattern)
                .map_err(|e| BatchError::Pattern { pattern: pattern.to_string(), message: e.to_string() })?;
            let mut matched: Vec<PathBuf> = paths.filter_map(Result::ok).filter(|p| is_mesh_file(p)).collect();
            matched.sort();
            files.extend(matched);
        } else {
            files.push(input.clone());
            continue;
        }
        if files.len() == before {
            return Err(BatchError::NoMatch { input: input.clone() });
        }
    }
    let mut seen = HashSet::new();
    files.retain(|p| seen.insert(identity(p)));
    Ok(files)
}

/// The file's canonical path when it resolves, else the path as given.
fn identity(path: &Path) -> PathBuf {
    subdiv_io::fs::canonical(path).unwrap_or_else(|| path.to_path_buf())
}

/// The name of an input's outputs: its file stem, made safe for a file name
/// (characters other than letters, digits, `-`, `_` and `.` become `_`).
pub fn stem_name(input: &Path) -> String {
    let stem = input.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let safe: String =
        stem.chars().map(|c| if c.is_alphanumeric() || matches!(c, '-' | '_' | '.') { c } else { '_' }).collect();
    if safe.is_empty() || safe.starts_with('.') {
        format!("mesh{safe}")
    } else {
        safe
    }
}

/// Unique output names for `inputs`, one each, in order: the file stem
/// ([`stem_name`]) when no other input has the same, else the stem, `-` and
/// 8 hexadecimal digits of a hash of the file's canonical path (64-bit
/// FNV-1a, stable across runs, machines and Rust versions):
/// `a/cube.obj` and `b/cube.obj` become `cube-1f0c3a9e` and
/// `cube-77d2b410`, the same in every run over the same files.
pub fn output_names(inputs: &[PathBuf]) -> Vec<String> {
    let stems: Vec<String> = inputs.iter().map(|p| stem_name(p)).collect();
    let mut count: HashMap<&str, usize> = HashMap::new();
    for s in &stems {
        *count.entry(s).or_default() += 1;
    }
    stems
        .iter()
        .zip(inputs)
        .map(|(stem, input)| {
            if count[stem.as_str()] == 1 {
                stem.clone()
            } else {
                let hash = fnv1a(identity(input).to_string_lossy().as_bytes());
                format!("{stem}-{:08x}", hash as u32 ^ (hash >> 32) as u32)
            }
        })
        .collect()
}

/// 64-bit FNV-1a (Fowler, Noll, Vo): a few lines, and unlike std's
/// `DefaultHasher` its values are specified, so names do not change with
/// the compiler.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_the_published_test_vectors() {
        // From the FNV reference test suite.
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn shared_stems_get_distinct_stable_names() {
        let inputs: Vec<PathBuf> =
            ["a/cube.obj", "b/cube.obj", "b/cube.off", "torus.obj", "we ird.obj"].iter().map(PathBuf::from).collect();
        let names = output_names(&inputs);
        assert_eq!(names[3], "torus");
        assert_eq!(names[4], "we_ird");
        let unique: HashSet<&String> = names.iter().collect();
        assert_eq!(unique.len(), names.len(), "{names:?}");
        for name in &names[..3] {
            assert!(name.starts_with("cube-") && name.len() == "cube-".len() + 8, "{name}");
        }
        assert_eq!(output_names(&inputs), names, "stable");
        assert_eq!(stem_name(Path::new(".hidden")), "mesh.hidden");
    }
}
