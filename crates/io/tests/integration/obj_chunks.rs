//! The parallel OBJ path against the serial reader: on every file it reads,
//! the same soup and warnings as the serial reader; on every file without
//! what it declines, it does read (so that the first property is not
//! vacuous); and through the public API, on files large enough to take it,
//! the same soups, warnings and error messages.

use proptest::prelude::*;
use subdiv_io::internals::{read_obj_chunked, read_obj_serial, OBJ_CHUNKED_MIN_BYTES};
use subdiv_io::{read_mesh_from_bytes_with_warnings, Format, IoError, PolygonSoup, ReadWarning};

type Read = (PolygonSoup, Vec<ReadWarning>);

/// Where two sequences first differ, for a message that stays short.
fn first_difference<T: PartialEq + std::fmt::Debug>(a: &[T], b: &[T]) -> Option<String> {
    let at = a.iter().zip(b).position(|(x, y)| x != y).unwrap_or(a.len().min(b.len()));
    (a.len() != b.len() || at < a.len()).then(|| {
        format!("lengths {} and {}, first difference at {at}: {:?} vs {:?}", a.len(), b.len(), a.get(at), b.get(at))
    })
}

/// Equal soups and warnings, coordinates compared by bits (a `nan` token
/// reads as NaN, which `==` never equals).
fn assert_same(fast: &Read, serial: &Read, context: &str) {
    let ((a, wa), (b, wb)) = (fast, serial);
    let bits = |p: &[subdiv_mesh::DVec3]| p.iter().map(|p| p.to_array().map(f64::to_bits)).collect::<Vec<_>>();
    let uv_bits = |s: &PolygonSoup| {
        s.uvs.as_ref().map_or((Vec::new(), Vec::new()), |uvs| {
            (uvs.values.iter().map(|uv| uv.to_array().map(f64::to_bits)).collect(), uvs.indices.clone())
        })
    };
    let (ua, ub) = (uv_bits(a), uv_bits(b));
    let differences = [
        ("positions", first_difference(&bits(&a.positions), &bits(&b.positions))),
        ("face offsets", first_difference(a.faces.offsets(), b.faces.offsets())),
        ("face indices", first_difference(a.faces.indices(), b.faces.indices())),
        ("group names", first_difference(&a.groups.names, &b.groups.names)),
        ("face groups", first_difference(&a.groups.face_group, &b.groups.face_group)),
        ("creases", first_difference(&a.tags.creases, &b.tags.creases)),
        ("corners", first_difference(&a.tags.corners, &b.tags.corners)),
        ("texture coordinate channel", (a.uvs.is_some() != b.uvs.is_some()).then(|| "present in one only".to_owned())),
        ("texture coordinates", first_difference(&ua.0, &ub.0)),
        ("texture coordinate indices", first_difference(&ua.1, &ub.1)),
        ("warnings", first_difference(wa, wb)),
    ];
    for (what, difference) in differences {
        if let Some(difference) = difference {
            let context: String = context.chars().take(2000).collect();
            panic!("{what} differ ({difference}): {context}");
        }
    }
}

/// The outcome of a read as text: the soup's debug form or the error message.
fn outcome(read: &Result<Read, IoError>) -> String {
    match read {
        Ok((soup, warnings)) => format!(
            "{} vertices, faces {:?}, groups {:?}, tags {:?}, uvs {:?}, warnings {warnings:?}",
            soup.positions.len(),
            soup.faces,
            soup.groups,
            soup.tags,
            soup.uvs.as_ref().map(|uvs| &uvs.indices)
        ),
        Err(e) => format!("error: {e}"),
    }
}

/// One generated line (without its end) and what it does to the parallel
/// path: `declines` when the serial reader fails on it or needs what a chunk
/// does not know; `uvs` for a face with corners: whether it gives texture
/// coordinates.
#[derive(Clone, Debug)]
struct Line {
    text: String,
    declines: bool,
    uvs: Option<bool>,
    /// A `v` line or an `f` line: the file is not empty.
    data: bool,
}

impl Line {
    fn plain(text: impl Into<String>) -> Self {
        Line { text: text.into(), declines: false, uvs: None, data: false }
    }
}

/// A coordinate token, and whether it is not a number.
fn number() -> impl Strategy<Value = (String, bool)> {
    let good = prop_oneof![
        any::<f64>().prop_map(|x| format!("{x:?}")),
        any::<f64>().prop_map(|x| format!("{x:e}")),
        (-1000i32..1000).prop_map(|i| i.to_string()),
        prop::sample::select(vec!["nan", "inf", "-inf", "+.5", "1.", "-0", "1E+5", "Infinity", "0.1"])
            .prop_map(str::to_owned),
    ]
    .prop_map(|t| (t, false));
    let bad = prop::sample::select(vec!["x", "1..2", "0x10", "1_0", "1,5"]).prop_map(|t| (t.to_owned(), true));
    prop_oneof![200 => good, 1 => bad]
}

/// A `v` (3 coordinates, sometimes a w and colours after them, rarely too
/// few) or `vt` (1 to 3 values, rarely none) line: `needed` values, of
/// which the first `read` are parsed (the rest ignored, whatever they are).
fn element(keyword: &'static str, needed: usize, read: usize) -> impl Strategy<Value = Line> {
    let count = prop_oneof![80 => needed..needed + 4, 1 => 0..needed];
    count.prop_flat_map(|n| prop::collection::vec(number(), n)).prop_map(move |values| {
        let declines = values.len() < needed || values.iter().take(read).any(|(_, bad)| *bad);
        let tokens: Vec<&str> = values.iter().map(|(t, _)| t.as_str()).collect();
        Line { text: format!("{keyword} {}", tokens.join(" ")), declines, uvs: None, data: keyword == "v" }
    })
}

/// A face index as written, and whether the parallel path declines it
/// (relative, 0, beyond `u32`, not an integer).
fn index() -> impl Strategy<Value = (String, bool)> {
    prop_oneof![
        200 => (1u32..24).prop_map(|i| (i.to_string(), false)),
        10 => prop::sample::select(vec!["+3", "007", "4294967296"]).prop_map(|t| (t.to_owned(), false)),
        2 => (1u32..4).prop_map(|i| (format!("-{i}"), true)),
        1 => prop::sample::select(vec!["0", "4294967297", "99999999999999999999", "x", "1.5", "-"])
            .prop_map(|t| (t.to_owned(), true)),
    ]
}

/// How a face gives its corners: `v`, `v/vt`, `v/vt/vn`, `v//vn`.
#[derive(Clone, Copy, Debug)]
enum Form {
    V,
    VVt,
    VVtVn,
    VVn,
}

/// An `f`/`fo` line of 0 to 6 corners in `form`, its texture coordinates
/// present or not as `with_uvs` says (one corner rarely of another form).
fn face(with_uvs: bool) -> impl Strategy<Value = Line> {
    let form = if with_uvs {
        prop_oneof![Just(Form::VVt), Just(Form::VVtVn)].boxed()
    } else {
        prop_oneof![Just(Form::V), Just(Form::VVn)].boxed()
    };
    let corner = (index(), index(), prop::sample::select(vec!["1", "2", "x", ""]));
    let odd_one = prop_oneof![100 => Just(None), 1 => (0..6usize).prop_map(Some)];
    (prop::sample::select(vec!["f", "f", "f", "fo"]), form, prop::collection::vec(corner, 0..7), odd_one).prop_map(
        move |(keyword, form, corners, odd_one)| {
            let mut text = keyword.to_owned();
            let mut declines = false;
            let mut with = 0;
            for (k, ((v, bad_v), (vt, bad_vt), vn)) in corners.iter().enumerate() {
                let form = match (odd_one == Some(k), form) {
                    (true, Form::V | Form::VVn) => Form::VVt,
                    (true, _) => Form::V,
                    (false, form) => form,
                };
                declines |= *bad_v;
                text.push(' ');
                text += &match form {
                    Form::V => v.clone(),
                    Form::VVt => format!("{v}/{vt}"),
                    Form::VVtVn => format!("{v}/{vt}/{vn}"),
                    Form::VVn => format!("{v}//{vn}"),
                };
                if matches!(form, Form::VVt | Form::VVtVn) && !vt.is_empty() {
                    declines |= *bad_vt;
                    with += 1;
                }
            }
            // Texture coordinates for some corners only: an error.
            declines |= with != 0 && with != corners.len();
            let uvs = (!corners.is_empty()).then_some(with > 0);
            Line { text, declines, uvs, data: true }
        },
    )
}

/// Any line of a generated file; `with_uvs` for its faces.
fn line(with_uvs: bool) -> impl Strategy<Value = Line> {
    let names = prop::collection::vec(prop::sample::select(vec!["default", "a", "top", "b", "caf\u{e9}"]), 0..3);
    let group = (prop::sample::select(vec!["g", "o"]), names).prop_map(|(k, names)| {
        let mut text = k.to_owned();
        for name in names {
            text = format!("{text} {name}");
        }
        Line::plain(text)
    });
    let ignored = prop::sample::select(vec![
        "vn 0 0 1",
        "vn 1 x",
        "s 1",
        "s off",
        "usemtl stone",
        "mtllib a b.mtl",
        "l 1 2",
        "p 1",
        "vp 0.5",
        "unknown 1 2 3",
        "",
        "   \t ",
        "# a comment",
        "# a comment ending in a backslash \\",
        "\u{c}",
    ])
    .prop_map(Line::plain);
    let declined = prop::sample::select(vec![
        "t crease 2/1/0 0 1 2.5",
        "t interpolateboundary 1/0/0 1",
        // Continuation lines, some of which read alone too (the `\` in
        // the place of an ignored `w`, a group name, an ignored statement).
        "v 1 2 \\",
        "f 1 2 \\",
        "v 1 2 3 \\",
        "vt 0.5 0.5 \\",
        "g a \\",
        "usemtl m \\",
        "\u{1}v 0 0 0",
    ])
    .prop_map(|t| Line { text: t.to_owned(), declines: true, uvs: None, data: false });
    let stmt = prop_oneof![
        90 => element("v", 3, 3),
        60 => face(with_uvs),
        1 => face(!with_uvs),
        24 => element("vt", 1, 2),
        15 => group,
        30 => ignored,
        1 => declined,
    ];
    // A trailing comment, sometimes.
    (stmt, prop_oneof![8 => Just(""), 1 => Just(" # trailing"), 1 => Just("\t#\\")]).prop_map(|(mut line, tail)| {
        line.text.push_str(tail);
        line
    })
}

/// A file: its bytes, and whether the parallel path must read it.
fn file() -> impl Strategy<Value = (Vec<u8>, bool)> {
    let ends = prop::collection::vec(prop_oneof![8 => Just("\n"), 4 => Just("\r\n"), 1 => Just("\r")], 0..80);
    any::<bool>()
        .prop_flat_map(move |with_uvs| (prop::collection::vec(line(with_uvs), 0..80), ends.clone(), any::<bool>()))
        .prop_map(|(lines, ends, last_end)| {
            let mut bytes = Vec::new();
            for (i, line) in lines.iter().enumerate() {
                bytes.extend_from_slice(line.text.as_bytes());
                if i + 1 < lines.len() || last_end {
                    bytes.extend_from_slice(ends.get(i).copied().unwrap_or("\n").as_bytes());
                }
            }
            let with = lines.iter().any(|l| l.uvs == Some(true));
            let without = lines.iter().any(|l| l.uvs == Some(false));
            let declines = lines.iter().any(|l| l.declines) || (with && without);
            let reads = !declines && lines.iter().any(|l| l.data);
            (bytes, reads)
        })
}

/// Checks the parallel path on `bytes` in chunks of `chunk` bytes against
/// the serial reader; returns whether it read the file.
fn check(bytes: &[u8], chunk: usize) -> bool {
    let serial = read_obj_serial(bytes, "gen.obj");
    let Some(fast) = read_obj_chunked(bytes, "gen.obj", chunk) else { return false };
    let context = format!("chunks of {chunk} bytes, file {:?}", String::from_utf8_lossy(bytes));
    match &serial {
        Ok(serial) => assert_same(&fast, serial, &context),
        Err(e) => panic!("the parallel path read what the serial reader refuses ({e}): {context}"),
    }
    true
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]

    #[test]
    fn chunked_reads_equal_serial_reads((bytes, reads) in file(), chunk in 1..96usize) {
        let len = bytes.len().max(1);
        for chunk in [chunk, 1, 2, 13, len / 2 + 1, len] {
            let read = check(&bytes, chunk);
            // Nothing it declines should it read, and nothing else decline:
            // a file it reads must be one without what it declines.
            prop_assert_eq!(read, reads, "chunks of {} bytes, file {:?}", chunk, String::from_utf8_lossy(&bytes));
        }
        // The public entry, whichever path it takes, reads as the serial reader.
        let public = read_mesh_from_bytes_with_warnings(&bytes, Format::Obj, "gen.obj");
        prop_assert_eq!(outcome(&public), outcome(&read_obj_serial(&bytes, "gen.obj")));
    }

    #[test]
    fn a_bom_or_utf16_or_binary_start_is_read_as_the_serial_reader_reads_it(
        (bytes, _) in file(),
        prefix in prop::sample::select(vec![&b"\xEF\xBB\xBF"[..], b"\xFF\xFE", b"\0\0\0\0", b"\x01\x02\x03"]),
    ) {
        let bytes = [prefix, &bytes].concat();
        check(&bytes, 7);
    }
}

/// A file of `faces` quads on a grid of vertices: texture coordinates on
/// every face or none, groups every few hundred faces (some before the
/// first name: `default`), normals, comments, CRLF on some lines.
fn big_file(faces: usize, with_uvs: bool, groups: bool) -> Vec<u8> {
    let side = (faces as f64).sqrt().ceil() as usize + 1;
    let mut text = String::from("# generated\nmtllib grid.mtl\n");
    for y in 0..side {
        for x in 0..side {
            let end = if (x + y) % 7 == 0 { "\r\n" } else { "\n" };
            text += &format!("v {} {} {:?}{end}", x as f64 * 0.1, y as f64 / 3.0, ((x * y) as f64).sin());
            if with_uvs {
                text += &format!("vt {} {}\n", x as f64 / side as f64, y as f64 / side as f64);
            }
        }
        text += &format!("vn 0 0 1 # row {y}\n");
    }
    text += "s 1\nusemtl grid\n";
    for f in 0..faces {
        if groups && f % 333 == 100 {
            text.push_str(["g left\n", "o right side\n", "g\n", "g left\n"][(f / 333) % 4]);
        }
        let (x, y) = (f % (side - 1), f / (side - 1));
        let v = [y * side + x, y * side + x + 1, (y + 1) * side + x + 1, (y + 1) * side + x].map(|i| i + 1);
        text += "f";
        for (k, i) in v.iter().enumerate() {
            text += &match (with_uvs, k % 2) {
                (true, 0) => format!(" {i}/{i}"),
                (true, _) => format!(" {i}/{i}/1"),
                (false, 0) => format!(" {i}"),
                (false, _) => format!(" {i}//1"),
            };
        }
        text += if f % 5 == 0 { "\r\n" } else { "\n" };
    }
    text.into_bytes()
}

#[test]
fn a_file_of_many_chunks_reads_as_the_serial_reader_reads_it() {
    for (with_uvs, groups) in [(false, false), (true, true), (false, true)] {
        let bytes = big_file(60_000, with_uvs, groups);
        assert!(bytes.len() > 2 * OBJ_CHUNKED_MIN_BYTES, "{} bytes: too small for several chunks", bytes.len());
        let serial = read_obj_serial(&bytes, "big.obj").unwrap();
        assert_eq!(serial.0.faces.len(), 60_000);
        assert_eq!(serial.0.uvs.is_some(), with_uvs);
        assert_eq!(serial.0.groups.names.is_empty(), !groups);
        for chunk in [64 << 10, 1 << 20, 1000, bytes.len()] {
            assert!(check(&bytes, chunk), "chunks of {chunk} bytes declined a plain file");
        }
        let public = read_mesh_from_bytes_with_warnings(&bytes, Format::Obj, "big.obj").unwrap();
        assert_same(&public, &serial, "public read");
    }
}

#[test]
fn what_a_large_file_declines_is_read_or_refused_as_the_serial_reader_does() {
    let bytes = big_file(50_000, true, true);
    // A line start among the faces, past the first chunks.
    let middle = 9 * bytes.len() / 10;
    let middle = middle + bytes[middle..].iter().position(|&b| b == b'\n').unwrap() + 1;
    let with = |insert: &str, at: usize| [&bytes[..at], insert.as_bytes(), &bytes[at..]].concat();
    let cases = [
        // Relative indices (read by the serial reader), a bad index, a
        // vertex short of a coordinate, index 0 (errors naming their line).
        with("f -1/-1 -2/-2 -3/-3\n", bytes.len()),
        with("f -1/-1 -2/-2 -3/-3\n", middle),
        with("f 1/1 2/2 x/3\n", middle),
        with("v 1 2\n", middle),
        with("f 0/1 2/2 3/3\n", bytes.len()),
        // Texture coordinates on some faces only: a warning naming lines.
        with("f 1 2 3\n", middle),
        // On some corners only: an error.
        with("f 1/1 2 3/3\n", middle),
        // A tag line (applied), one that is not applied (a warning).
        with("t crease 2/1/0 0 1 2.5\n", middle),
        with("t hole 1/0/0 3\n", middle),
        // A continuation line, a binary tail, a BOM.
        with("f 1/1 2/2 \\\n 3/3\n", middle),
        with("\u{1}\u{2}\u{3}\n", middle),
        with("\u{feff}", 0),
    ];
    for (k, bytes) in cases.iter().enumerate() {
        let serial = read_obj_serial(bytes, "big.obj");
        let public = read_mesh_from_bytes_with_warnings(bytes, Format::Obj, "big.obj");
        match (&public, &serial) {
            (Ok(public), Ok(serial)) => assert_same(public, serial, &format!("case {k}")),
            _ => assert_eq!(outcome(&public), outcome(&serial), "case {k}"),
        }
        // The parallel path reads only the BOM case.
        assert_eq!(read_obj_chunked(bytes, "big.obj", 100_000).is_some(), k == cases.len() - 1, "case {k}");
    }
    // The errors name lines past the first chunk.
    let e = read_mesh_from_bytes_with_warnings(&cases[2], Format::Obj, "big.obj").unwrap_err();
    let line = bytes[..middle].iter().filter(|&&b| b == b'\n').count() + 1;
    assert_eq!(e.to_string(), format!("big.obj:{line}: face index 'x/3' is not an integer"));
    let (_, warnings) = read_mesh_from_bytes_with_warnings(&cases[5], Format::Obj, "big.obj").unwrap();
    assert!(matches!(&warnings[..], [ReadWarning::UvsDropped { line: Some(l), .. }] if *l == line), "{warnings:?}");
}

#[test]
fn the_generated_files_exercise_both_outcomes() {
    // The property above means little if nearly every file is declined (or
    // none is): a fixed sample of the generator has plenty of both.
    use proptest::strategy::ValueTree;
    use proptest::test_runner::{Config, TestRng, TestRunner};
    let mut runner = TestRunner::new_with_rng(Config::default(), TestRng::deterministic_rng(Default::default()));
    let strategy = file();
    let total = 500;
    let (mut read, mut faces, mut with_groups, mut with_uvs) = (0, 0, 0, 0);
    for _ in 0..total {
        let (bytes, reads) = strategy.new_tree(&mut runner).unwrap().current();
        if let (true, Some((soup, _))) = (reads, read_obj_chunked(&bytes, "gen.obj", 5)) {
            read += 1;
            faces += soup.faces.len();
            with_groups += usize::from(!soup.groups.names.is_empty());
            with_uvs += usize::from(soup.uvs.is_some());
        }
    }
    assert!(read > total / 5 && read < 4 * total / 5, "{read} of {total} generated files read");
    assert!(faces > 3 * read, "{faces} faces in the {read} files read");
    assert!(with_groups > total / 20 && with_uvs > total / 20, "{with_groups} with groups, {with_uvs} with uvs");
}

#[test]
fn the_repository_fixtures_read_as_the_serial_reader_reads_them() {
    // The OBJ files of the workspace's fixtures/ (absent from the packaged
    // crate), each in chunks of 64 KiB and of a few lines.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
    let mut pending = vec![root];
    let (mut files, mut read) = (0, 0);
    while let Some(dir) = pending.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        for path in entries.map(|e| e.unwrap().path()) {
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "obj") {
                let bytes = std::fs::read(&path).unwrap();
                let name = path.display().to_string();
                files += 1;
                for chunk in [64 << 10, 100] {
                    if let Some(fast) = read_obj_chunked(&bytes, &name, chunk) {
                        read += 1;
                        assert_same(&fast, &read_obj_serial(&bytes, &name).unwrap(), &name);
                    }
                }
            }
        }
    }
    eprintln!("{files} fixture files, {read} parallel reads");
}
