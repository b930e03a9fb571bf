//! Standard output that never panics: `println!` panics when the reader has
//! gone (`subdiv info m.obj | head -3`). A closed pipe ends the process quietly
//! with 141 (128 + SIGPIPE, what a shell reports for a command killed by it);
//! any other failure to write is a write failure (exit 4).

use std::io::Write;

/// Writes `text` and a newline to stdout.
pub fn line(text: &str) {
    let mut out = std::io::stdout().lock();
    let result = out.write_all(text.as_bytes()).and_then(|()| out.write_all(b"\n")).and_then(|()| out.flush());
    if let Err(e) = result {
        subdiv_io::remove_staged_files();
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(141);
        }
        eprintln!("subdiv: error: standard output: {e}");
        std::process::exit(4);
    }
}
