//! Tidy: rules on the source tree that the compiler cannot check, run by
//! `cargo test --workspace` (as rust-analyzer keeps its `tidy.rs`).
//!
//! Each rule is a function over one file's path and text returning its
//! violations (`file:line: what`), unit-tested below on planted violations
//! (so each is shown to fail) and run over every `src/` of the workspace's
//! crates. Test code is exempt: files named `tests.rs` or `*_tests.rs`, and
//! everything from a file's top-level `#[cfg(test)]` on (unit tests sit at
//! the bottom of a file). So are comments and string literals.
//!
//! 1. **Files through subdiv-io.** No `std::fs` outside `crates/io` (and
//!    `xtask`, which is not a crate of the library): every file the tools
//!    read passes subdiv-io's special-file check (FIFOs, devices refused
//!    before opening), size cap and encoding check.
//! 2. **Exhaustive scheme matches.** No `_ =>` arm in a `match` whose arms
//!    name `Scheme::`: a new scheme must break every match over schemes
//!    (docs/ARCHITECTURE.md, "Library surface").
//! 3. **Methods live in subdiv-interp.** No crate below it (rules, mesh,
//!    stencil, solve, eval, io) declares an identifier (`fn`, `struct`,
//!    `enum`, `const`, `static`, `mod`, `type`, `trait`, `use … as`) that
//!    names an interpolation method (Nasri, Zheng-Cai, Cheng, Fan-Cheng-Lai,
//!    Deng-Wang, the two-phase scheme) or one of the method-level types
//!    listed in [`METHOD_TYPES`]; comments citing the papers are fine.
//!    Deng-Ma is a subdivision scheme, not a method, and may be named.
//!
//! The real tree's current violations are listed in [`ALLOWED`] (file and
//! item, not line); the test also fails when an allowed item is gone, so the
//! list only shrinks.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// One rule broken at one place.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Violation {
    /// Path relative to the workspace root, `/`-separated.
    file: String,
    /// 1-based line.
    line: usize,
    /// The rule's number (1, 2, 3).
    rule: u8,
    /// The offending item: `std::fs::metadata`, `match on line 12`'s
    /// scheme, an identifier.
    item: String,
}

impl std::fmt::Display for Violation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let what = match self.rule {
            1 => "std::fs outside subdiv-io (read through subdiv_io::read_text / read_mesh)",
            2 => "`_ =>` in a match over Scheme (name every scheme)",
            _ => "an interpolation method named below subdiv-interp (move it to crates/interp)",
        };
        write!(f, "{}:{}: rule {}: {what}: {}", self.file, self.line, self.rule, self.item)
    }
}

/// Current violations of the real tree, as (rule, file, item). Only removals
/// are expected: the test fails when an item here no longer occurs.
const ALLOWED: &[(u8, &str, &str)] = &[];

/// The crates below subdiv-interp (rule 3).
const BELOW_INTERP: &[&str] = &["rules", "mesh", "stencil", "solve", "eval", "io"];

/// Interpolation methods, lower case without separators: an identifier
/// whose lower-case, underscore-free form contains one breaks rule 3.
const METHOD_NAMES: &[&str] = &["nasri", "zhengcai", "cheng", "fanchenglai", "dengwang", "twophase"];

/// Types that belong to the methods though their names do not say so: the
/// first-step rules of Zheng-Cai and Fan-Cheng-Lai, Cheng's singularity
/// classes, the methods' block solve order.
const METHOD_TYPES: &[&str] = &["CornerRule", "Degeneracy", "SolveBlocks"];

// ---- source text ---------------------------------------------------------------------------------

/// `text` with comments, string literals and character literals blanked
/// (newlines kept, so lines and offsets stay), and cut at the first
/// top-level `#[cfg(test)]`.
fn code_of(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    let blank =
        |out: &mut Vec<u8>, bytes: &[u8]| out.extend(bytes.iter().map(|&c| if c == b'\n' { b'\n' } else { b' ' }));
    while i < b.len() {
        let rest = &b[i..];
        if rest.starts_with(b"//") {
            let end = rest.iter().position(|&c| c == b'\n').unwrap_or(rest.len());
            blank(&mut out, &rest[..end]);
            i += end;
        } else if rest.starts_with(b"/*") {
            let (mut depth, mut j) = (0usize, 0);
            while j < rest.len() {
                if rest[j..].starts_with(b"/*") {
                    depth += 1;
                    j += 2;
                } else if rest[j..].starts_with(b"*/") {
                    depth -= 1;
                    j += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    j += 1;
                }
            }
            blank(&mut out, &rest[..j]);
            i += j;
        } else if let Some(len) = raw_string_len(rest, i == 0 || !is_ident(b[i - 1])) {
            out.push(b'"');
            blank(&mut out, &rest[1..len - 1]);
            out.push(b'"');
            i += len;
        } else if rest[0] == b'"' {
            let mut j = 1;
            while j < rest.len() && rest[j] != b'"' {
                j += if rest[j] == b'\\' { 2 } else { 1 };
            }
            let len = (j + 1).min(rest.len());
            out.push(b'"');
            blank(&mut out, &rest[1..len.saturating_sub(1).max(1)]);
            if len > 1 {
                out.push(b'"');
            }
            i += len;
        } else if rest[0] == b'\'' {
            // A character literal ('x', '\n', '\u{..}', '{'), else a lifetime.
            let len = if rest.get(1) == Some(&b'\\') {
                rest.iter().skip(2).position(|&c| c == b'\'').map(|p| p + 3)
            } else {
                let ch = std::str::from_utf8(&rest[1..rest.len().min(5)])
                    .or_else(|e| std::str::from_utf8(&rest[1..1 + e.valid_up_to()]))
                    .ok()
                    .and_then(|s| s.chars().next());
                ch.map(|c| 1 + c.len_utf8()).filter(|&k| rest.get(k) == Some(&b'\'')).map(|k| k + 1)
            };
            match len {
                Some(len) => {
                    out.push(b'\'');
                    blank(&mut out, &rest[1..len - 1]);
                    out.push(b'\'');
                    i += len;
                }
                None => {
                    out.push(b'\'');
                    i += 1;
                }
            }
        } else {
            out.push(rest[0]);
            i += 1;
        }
    }
    let mut code = String::from_utf8(out).unwrap_or_default();
    if let Some(cut) = code.find("\n#[cfg(test)]") {
        code.truncate(cut + 1);
    }
    code
}

/// The length of a raw string literal (`r"…"`, `r#"…"#`, `br"…"`) at the
/// start of `rest`, when one starts there.
fn raw_string_len(rest: &[u8], at_token_start: bool) -> Option<usize> {
    if !at_token_start {
        return None;
    }
    let start = if rest.starts_with(b"br") {
        2
    } else if rest.starts_with(b"r") {
        1
    } else {
        return None;
    };
    let hashes = rest[start..].iter().take_while(|&&c| c == b'#').count();
    if rest.get(start + hashes) != Some(&b'"') {
        return None;
    }
    let close: Vec<u8> = std::iter::once(b'"').chain(std::iter::repeat_n(b'#', hashes)).collect();
    let body = start + hashes + 1;
    let end = rest[body..].windows(close.len()).position(|w| w == close.as_slice())?;
    Some(body + end + close.len())
}

fn is_ident(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// 1-based line of byte `offset`.
fn line_of(code: &str, offset: usize) -> usize {
    1 + code.as_bytes()[..offset].iter().filter(|&&c| c == b'\n').count()
}

/// Offsets of `word` in `code` as a whole word.
fn word_offsets<'a>(code: &'a str, word: &'a str) -> impl Iterator<Item = usize> + 'a {
    code.match_indices(word).map(|(k, _)| k).filter(move |&k| {
        let b = code.as_bytes();
        (k == 0 || !is_ident(b[k - 1])) && b.get(k + word.len()).is_none_or(|&c| !is_ident(c))
    })
}

/// Whether a file is test code (exempt from every rule).
fn is_test_file(path: &str) -> bool {
    let name = path.rsplit('/').next().unwrap_or(path);
    name == "tests.rs" || name.ends_with("_tests.rs") || path.split('/').any(|c| c == "tests")
}

// ---- rule 1: std::fs only in subdiv-io ------------------------------------------------------------

fn rule_fs(path: &str, text: &str) -> Vec<Violation> {
    if path.starts_with("crates/io/") || path.starts_with("xtask/") || is_test_file(path) {
        return Vec::new();
    }
    let code = code_of(text);
    let mut found = Vec::new();
    for k in word_offsets(&code, "std") {
        let rest = code[k + 3..].trim_start();
        let Some(rest) = rest.strip_prefix("::") else { continue };
        let rest = rest.trim_start();
        let item = if let Some(after) = rest.strip_prefix("fs") {
            if after.starts_with(|c: char| c.is_alphanumeric() || c == '_') {
                continue;
            }
            let after = after.trim_start();
            match after.strip_prefix("::") {
                Some(tail) => {
                    let name: String =
                        tail.trim_start().chars().take_while(|&c| c.is_alphanumeric() || c == '_').collect();
                    if name.is_empty() {
                        "std::fs".to_string()
                    } else {
                        format!("std::fs::{name}")
                    }
                }
                None => "std::fs".to_string(),
            }
        } else if let Some(group) = rest.strip_prefix('{') {
            // `use std::{fs, io}`: a top-level `fs` in the group.
            let group = &group[..group.find('}').unwrap_or(group.len())];
            if !group.split(',').any(|g| g.trim() == "fs" || g.trim().starts_with("fs::")) {
                continue;
            }
            "std::fs".to_string()
        } else {
            continue;
        };
        let line_start = code[..k].rfind('\n').map_or(0, |p| p + 1);
        let item = if code[line_start..k].trim_start().starts_with("use ") && item == "std::fs" {
            "use std::fs".to_string()
        } else {
            item
        };
        found.push(Violation { file: path.to_string(), line: line_of(&code, k), rule: 1, item });
    }
    found
}

// ---- rule 2: no `_ =>` in a match over Scheme ---------------------------------------------------

/// The arm patterns of the `match` whose body opens at `open` (the `{`), with
/// their offsets; nested blocks and calls are skipped as arm bodies.
fn arm_patterns(code: &str, open: usize) -> Vec<(usize, String)> {
    let b = code.as_bytes();
    let mut arms = Vec::new();
    let mut i = open + 1;
    loop {
        // The pattern: up to `=>` at depth 0.
        while i < b.len() && b[i].is_ascii_whitespace() {
            i += 1;
        }
        if i >= b.len() || b[i] == b'}' {
            return arms;
        }
        let start = i;
        let mut depth = 0i32;
        while i < b.len() {
            match b[i] {
                b'(' | b'[' | b'{' => depth += 1,
                b')' | b']' | b'}' => depth -= 1,
                b'=' if depth == 0 && b.get(i + 1) == Some(&b'>') => break,
                _ => {}
            }
            if depth < 0 {
                return arms;
            }
            i += 1;
        }
        arms.push((start, code[start..i.min(b.len())].trim().to_string()));
        i += 2;
        // The body: a block, or an expression up to `,` at depth 0 (or the match's `}`).
        while i < b.len() && b[i].is_ascii_whitespace() {
            i += 1;
        }
        let mut depth = 0i32;
        let block = b.get(i) == Some(&b'{');
        while i < b.len() {
            match b[i] {
                b'(' | b'[' | b'{' => depth += 1,
                b')' | b']' | b'}' => {
                    depth -= 1;
                    if depth < 0 {
                        return arms;
                    }
                    if depth == 0 && block {
                        i += 1;
                        break;
                    }
                }
                b',' if depth == 0 => break,
                _ => {}
            }
            i += 1;
        }
        while i < b.len() && (b[i].is_ascii_whitespace() || b[i] == b',') {
            i += 1;
        }
    }
}

/// The `{` that opens the body of the `match` at `k`: the first `{` outside
/// parentheses and brackets after the scrutinee.
fn match_body(code: &str, k: usize) -> Option<usize> {
    let b = code.as_bytes();
    let mut depth = 0i32;
    for (j, &c) in b.iter().enumerate().skip(k + 5) {
        match c {
            b'(' | b'[' => depth += 1,
            b')' | b']' => depth -= 1,
            b'{' if depth == 0 => return Some(j),
            b';' | b'}' if depth <= 0 => return None,
            _ => {}
        }
    }
    None
}

/// The name of the last `fn` declared before `offset` (the function a
/// `match` sits in, for the allowlist: stable when lines move).
fn enclosing_fn(code: &str, offset: usize) -> String {
    word_offsets(&code[..offset], "fn")
        .filter_map(|k| {
            let rest = &code[k + 2..offset];
            let name: String = rest.trim_start().chars().take_while(|&c| c.is_alphanumeric() || c == '_').collect();
            (rest.starts_with(char::is_whitespace) && !name.is_empty()).then_some(name)
        })
        .last()
        .unwrap_or_else(|| "?".to_string())
}

fn rule_scheme_wildcard(path: &str, text: &str) -> Vec<Violation> {
    if is_test_file(path) {
        return Vec::new();
    }
    let code = code_of(text);
    let mut found = Vec::new();
    for k in word_offsets(&code, "match") {
        let Some(open) = match_body(&code, k) else { continue };
        let arms = arm_patterns(&code, open);
        let over_scheme = arms.iter().any(|(_, p)| word_offsets(p, "Scheme").any(|s| p[s + 6..].starts_with("::")));
        if !over_scheme {
            continue;
        }
        for (at, pattern) in &arms {
            // `_ if guard =>` is not a catch-all.
            if pattern == "_" {
                let item = format!("match in fn {}", enclosing_fn(&code, k));
                found.push(Violation { file: path.to_string(), line: line_of(&code, *at), rule: 2, item });
            }
        }
    }
    found
}

// ---- rule 3: no method names below subdiv-interp ------------------------------------------------

fn rule_method_names(path: &str, text: &str) -> Vec<Violation> {
    let below = BELOW_INTERP.iter().any(|c| path.starts_with(&format!("crates/{c}/")));
    if !below || is_test_file(path) {
        return Vec::new();
    }
    let code = code_of(text);
    let mut found = Vec::new();
    for keyword in ["fn", "struct", "enum", "const", "static", "mod", "type", "trait", "union", "as"] {
        for k in word_offsets(&code, keyword) {
            let rest = &code[k + keyword.len()..];
            let trimmed = rest.trim_start();
            if trimmed.len() == rest.len() {
                continue; // `fn(` in a type, not a declaration
            }
            let name: String = trimmed.chars().take_while(|&c| c.is_alphanumeric() || c == '_').collect();
            if name.is_empty() {
                continue;
            }
            let folded = name.to_lowercase().replace('_', "");
            if METHOD_NAMES.iter().any(|m| folded.contains(m)) || METHOD_TYPES.contains(&name.as_str()) {
                found.push(Violation { file: path.to_string(), line: line_of(&code, k), rule: 3, item: name });
            }
        }
    }
    found
}

// ---- the tree --------------------------------------------------------------------------------------

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf()
}

/// Every `.rs` file under the `src/` of every workspace crate, relative to the root.
fn source_files(root: &Path) -> Vec<String> {
    let mut srcs: Vec<PathBuf> = std::fs::read_dir(root.join("crates"))
        .unwrap()
        .map(|e| e.unwrap().path().join("src"))
        .filter(|p| p.is_dir())
        .collect();
    srcs.push(root.join("xtask/src"));
    let mut files = Vec::new();
    while let Some(dir) = srcs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                srcs.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let relative = path.strip_prefix(root).unwrap();
                files
                    .push(relative.components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/"));
            }
        }
    }
    files.sort();
    files
}

fn all_rules(path: &str, text: &str) -> Vec<Violation> {
    let mut v = rule_fs(path, text);
    v.extend(rule_scheme_wildcard(path, text));
    v.extend(rule_method_names(path, text));
    v
}

#[test]
fn the_tree_is_tidy_apart_from_the_allowed_items() {
    let root = workspace_root();
    let files = source_files(&root);
    assert!(files.len() > 100, "{} source files: wrong root {}", files.len(), root.display());
    let mut violations = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(root.join(file)).unwrap();
        violations.extend(all_rules(file, &text));
    }
    let allowed = |v: &Violation| ALLOWED.iter().any(|&(r, f, item)| r == v.rule && f == v.file && item == v.item);
    let new: Vec<String> = violations.iter().filter(|v| !allowed(v)).map(ToString::to_string).collect();
    let present: BTreeSet<(u8, &str, &str)> =
        violations.iter().map(|v| (v.rule, v.file.as_str(), v.item.as_str())).collect();
    let gone: Vec<String> =
        ALLOWED.iter().filter(|a| !present.contains(a)).map(|(r, f, item)| format!("rule {r}: {f}: {item}")).collect();
    assert!(new.is_empty(), "{} tidy violation(s):\n{}", new.len(), new.join("\n"));
    assert!(
        gone.is_empty(),
        "allowed item(s) no longer found; remove them from ALLOWED in xtask/tests/tidy.rs:\n{}",
        gone.join("\n")
    );
}

// ---- the rules on planted violations ---------------------------------------------------------------

fn items(v: Vec<Violation>) -> Vec<(usize, String)> {
    v.into_iter().map(|v| (v.line, v.item)).collect()
}

#[test]
fn rule_1_finds_std_fs_in_every_spelling_outside_io() {
    let text = "use std::fs;\nfn a() { let _ = std::fs::read(\"x\"); }\nuse std::{fs::File, io};\n\
                use std::{io, fs};\n// std::fs::read in a comment\nconst S: &str = \"std::fs::read\";\n\
                use std::os::unix::fs::MetadataExt;\nfn b(fs: u8) {}\nuse std :: fs :: write;\n";
    let found = items(rule_fs("crates/mesh/src/a.rs", text));
    assert_eq!(
        found,
        [
            (1, "use std::fs".to_string()),
            (2, "std::fs::read".to_string()),
            (3, "use std::fs".to_string()),
            (4, "use std::fs".to_string()),
            (9, "std::fs::write".to_string()),
        ]
    );
    assert!(rule_fs("crates/io/src/a.rs", text).is_empty());
    assert!(rule_fs("xtask/src/main.rs", text).is_empty());
    assert!(rule_fs("crates/mesh/src/a_tests.rs", text).is_empty());
    // Unit tests at the bottom of a file are test code.
    let with_tests = "fn a() {}\n#[cfg(test)]\nmod tests {\n    fn t() { std::fs::read(\"x\").unwrap(); }\n}\n";
    assert!(rule_fs("crates/mesh/src/a.rs", with_tests).is_empty());
}

#[test]
fn rule_2_finds_a_wildcard_in_a_match_over_schemes_only() {
    let text = r#"
fn a(s: Scheme) -> u8 {
    match s {
        Scheme::CatmullClark => 1,
        Scheme::Loop(_) => { 2 }
        _ => 3,
    }
}
fn b(s: Scheme) -> u8 {
    match s {
        Scheme::CatmullClark | Scheme::DengMa(_) => 1,
        Scheme::Loop(_) | Scheme::DooSabin => match 4u8 { 4 => 0, _ => 1 },
    }
}
fn c(x: Option<u8>) -> u8 {
    match x { Some(_) => 1, _ => 0 }
}
fn d(s: &subdiv_stencil::Scheme, k: u8) -> u8 {
    match (s, k) {
        (subdiv_stencil::Scheme::Loop(_), 0) => { if k > 0 { 1 } else { 2 } }
        _ if k > 3 => 2,
        _ => 5,
    }
}
fn e(s: SchemeArg) -> u8 {
    match s { SchemeArg::Loop => 1, _ => 0 }
}
"#;
    let found = items(rule_scheme_wildcard("crates/cli/src/x.rs", text));
    assert_eq!(found, [(6, "match in fn a".to_string()), (22, "match in fn d".to_string())]);
    assert!(rule_scheme_wildcard("crates/cli/tests/x.rs", text).is_empty());
    // In strings and comments there is no match.
    let quoted =
        "const S: &str = \"match s { Scheme::Loop(_) => 1, _ => 2 }\";\n// match s { Scheme::A => 1, _ => 2 }\n";
    assert!(rule_scheme_wildcard("crates/cli/src/x.rs", quoted).is_empty());
}

#[test]
fn rule_3_finds_method_names_in_declarations_below_interp() {
    let text = "pub fn limit_matrix_nasri() {}\nstruct ZhengCaiRows;\nconst TWO_PHASE: u8 = 1;\n\
                mod fan_cheng_lai;\nuse a::b as cheng_limit;\npub enum CornerRule {}\nenum DengWangRule {}\n\
                // Nasri 1987, Eq. (3); Cheng's Eq. 5\nfn deng_ma_step() {}\nfn call() { nasri(); }\n\
                type F = fn(u8) -> u8;\nconst S: &str = \"fn nasri\";\n";
    let found = items(rule_method_names("crates/stencil/src/a.rs", text));
    let expected = [
        (1, "limit_matrix_nasri"),
        (4, "fan_cheng_lai"),
        (2, "ZhengCaiRows"),
        (7, "DengWangRule"),
        (6, "CornerRule"),
        (3, "TWO_PHASE"),
        (5, "cheng_limit"),
    ];
    let mut found = found;
    let mut expected: Vec<(usize, String)> = expected.iter().map(|&(l, s)| (l, s.to_string())).collect();
    found.sort();
    expected.sort();
    assert_eq!(found, expected);
    // Above subdiv-interp, and in test code, the names are fine.
    assert!(rule_method_names("crates/interp/src/a.rs", text).is_empty());
    assert!(rule_method_names("crates/cli/src/a.rs", text).is_empty());
    assert!(rule_method_names("crates/stencil/src/limit_matrix_tests.rs", text).is_empty());
    assert!(rule_method_names("crates/stencil/tests/a.rs", text).is_empty());
}

#[test]
fn source_text_is_cleaned_of_comments_and_literals_keeping_lines() {
    let text = "let a = '{'; let b = '\\''; let c: &'static str = r#\"}\"#;\n/* { \n } */ let d = \"\\\"{\";\n";
    let code = code_of(text);
    assert_eq!(code.lines().count(), text.lines().count());
    assert!(!code.contains('{') && !code.contains('}'), "{code}");
    assert!(code.contains("&'static str"), "{code}");
}
