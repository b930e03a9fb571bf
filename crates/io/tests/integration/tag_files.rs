//! JSON tag files (`--tags FILE.json`): what they hold, every way they can be
//! malformed, and the bounds on what reading one costs.

use crate::common::{make_fifo, scratch_dir, within};
use subdiv_io::{parse_tag_json, read_tag_file, EdgeTag, IoError, TagList, VertexTag, TAG_FILE_LIMIT};

#[test]
fn a_tag_file_gives_creases_and_corners_in_file_order() {
    let dir = scratch_dir("tag_file_ok");
    let path = dir.join("tags.json");
    std::fs::write(
        &path,
        "\u{feff}{\n  \"creases\": [[0, 1, 2.5], [1, 2, 10], [2, 3, 0]],\n  \"corners\": [[3, 10.0], [0, 0.25]]\n}\n",
    )
    .unwrap();
    let list = read_tag_file(&path).unwrap();
    let e = |a, b, sharpness| EdgeTag { a, b, sharpness };
    assert_eq!(list.creases, vec![e(0, 1, 2.5), e(1, 2, 10.0), e(2, 3, 0.0)]);
    assert_eq!(list.corners, vec![VertexTag { vertex: 3, sharpness: 10.0 }, VertexTag { vertex: 0, sharpness: 0.25 }]);
    assert_eq!(parse_tag_json(r#"{"creases": []}"#).unwrap(), TagList::default());
    assert_eq!(parse_tag_json(" { } ").unwrap(), TagList::default());
}

#[test]
fn malformed_tag_files_are_parse_errors_naming_the_entry() {
    for (json, message) in [
        ("", "tag file is empty"),
        ("  \n ", "tag file is empty"),
        ("{", "EOF while parsing"),
        ("[]", "invalid type: sequence, expected a tag object"),
        ("null", "invalid type: null, expected a tag object"),
        (r#"{"creases": {}}"#, r#"expected "creases" as an array of [v0, v1, sharpness] entries"#),
        (r#"{"corners": 3}"#, r#"expected "corners" as an array of [v, sharpness] entries"#),
        (r#"{"creases": [5]}"#, "invalid type: integer `5`, expected [v0, v1, sharpness] for creases[0]"),
        (r#"{"creases": [[0, 1]]}"#, "creases[0]: expected [v0, v1, sharpness], found 2 values"),
        (r#"{"creases": [[0, 1, 1], [0, 1, 2, 3]]}"#, "creases[1]: expected [v0, v1, sharpness], found 4 values"),
        (r#"{"creases": [[-1, 1, 2]]}"#, "creases[0]: vertex index -1 is negative"),
        (r#"{"creases": [[0, 1.5, 2]]}"#, "creases[0]: vertex index 1.5 is not an integer"),
        (r#"{"creases": [[0, "1", 2]]}"#, r#"creases[0]: vertex index "1" is not a number"#),
        (r#"{"creases": [[0, 4294967296, 2]]}"#, "creases[0]: vertex index 4294967296 out of range"),
        (r#"{"creases": [[0, 1e20, 2]]}"#, "creases[0]: vertex index 1e+20 out of range"),
        (r#"{"creases": [[0, 1, -0.5]]}"#, "creases[0]: sharpness -0.5 is negative"),
        (r#"{"creases": [[0, 1, null]]}"#, "creases[0]: sharpness null is not a number"),
        (r#"{"corners": [[0]]}"#, "corners[0]: expected [v, sharpness], found 1 values"),
        (r#"{"corners": [[1, 1], [2, "sharp"]]}"#, r#"corners[1]: sharpness "sharp" is not a number"#),
        (r#"{"corner": []}"#, r#"unknown key "corner" (a tag file has "creases", "corners" and "holes")"#),
        (r#"{"creases": [], "creases": []}"#, r#"key "creases" appears twice"#),
        (r#"{"creases": [[0, 1, 1e999]]}"#, "number out of range"),
        ("{} {}", "trailing characters"),
        ("\0\0\0\0\x01\x02", "binary data, not a JSON tag file"),
    ] {
        let e = parse_tag_json(json).expect_err(json);
        assert!(matches!(e, IoError::Parse { .. }), "{json}: {e:?}");
        let shown = e.to_string();
        assert!(shown.starts_with("<memory>"), "{json}: {shown}");
        assert!(shown.contains(message), "{json}: {shown}");
        assert!(!shown.contains('\n') && !shown.contains("column"), "{json}: {shown}");
    }
}

#[test]
fn errors_name_the_line_of_the_entry_in_a_file() {
    let dir = scratch_dir("tag_file_lines");
    let path = dir.join("bad.json");
    std::fs::write(&path, "{\n  \"creases\": [\n    [0, 1, 1],\n    [1, 2, -3]\n  ]\n}\n").unwrap();
    let e = read_tag_file(&path).unwrap_err();
    assert_eq!(e.line(), Some(4), "{e}");
    assert_eq!(e.to_string(), format!("{}:4: creases[1]: sharpness -3 is negative", path.display()));
    // A control character in a key stays escaped, on one line.
    let e = parse_tag_json("{\"a\\u001b[2J\": 1}").unwrap_err();
    assert!(!e.to_string().contains('\u{1b}'), "{e}");
}

#[test]
fn only_regular_files_of_bounded_size_are_read() {
    let dir = scratch_dir("tag_file_special");
    let e = read_tag_file(&dir).unwrap_err();
    assert!(matches!(e, IoError::NotAFile { kind: "a directory", .. }), "{e}");
    let e = read_tag_file(&dir.join("missing.json")).unwrap_err();
    assert!(matches!(e, IoError::Io { .. }) && e.to_string().contains("missing.json"), "{e}");
    let fifo = dir.join("fifo.json");
    if make_fifo(&fifo) {
        let e = within(10, "tag file FIFO", move || read_tag_file(&fifo).unwrap_err());
        assert!(matches!(e, IoError::NotAFile { kind: "a FIFO", .. }), "{e}");
    }
    // A sparse file one byte over the limit: refused before anything is read.
    let big = dir.join("big.json");
    std::fs::File::create(&big).unwrap().set_len(TAG_FILE_LIMIT + 1).unwrap();
    let e = within(10, "oversized tag file", move || read_tag_file(&big).unwrap_err());
    assert!(matches!(e, IoError::Unsupported { .. }), "{e}");
    assert!(e.to_string().contains(&format!("tag file of {} bytes", TAG_FILE_LIMIT + 1)), "{e}");
    let utf16 = dir.join("utf16.json");
    std::fs::write(&utf16, "{\"creases\": []}".encode_utf16().flat_map(u16::to_le_bytes).collect::<Vec<u8>>()).unwrap();
    assert!(matches!(read_tag_file(&utf16), Err(IoError::Utf16 { .. })));
}

#[test]
fn hostile_nesting_is_an_error_not_a_stack_overflow() {
    let deep = format!("{{\"creases\": [{}{}]}}", "[".repeat(100_000), "]".repeat(100_000));
    let e = within(10, "deep nesting", move || parse_tag_json(&deep).unwrap_err());
    assert!(e.to_string().contains("recursion limit exceeded"), "{e}");
}

#[test]
fn three_hundred_thousand_entries_parse_in_linear_time() {
    // Minutes if parsing were quadratic in the entries; well under a second when linear.
    let n = 300_000u32;
    let mut json = String::from("{\"creases\": [");
    for i in 0..n {
        json.push_str(&format!("{}[{i}, {}, 1.5]", if i > 0 { "," } else { "" }, i + 1));
    }
    json.push_str("], \"corners\": [[0, 10]]}");
    let list = within(60, "300 000 creases", move || parse_tag_json(&json).unwrap());
    assert_eq!((list.creases.len(), list.corners.len()), (n as usize, 1));
    assert_eq!(list.creases[299_999], EdgeTag { a: 299_999, b: 300_000, sharpness: 1.5 });
}
