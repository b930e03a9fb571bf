//! Shared pieces of the reproduction tables: context, fixtures, timing,
//! Markdown/JSON output, regression metrics.

use anyhow::{Context, Result};
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;
use subdiv_mesh::Mesh;

/// Where and how a reproduction runs.
pub struct Ctx {
    /// Quick mode (CI): small sizes, one timing run, no figures.
    pub quick: bool,
    /// Repository root.
    pub root: PathBuf,
    /// Output folder (`docs/results`).
    pub out: PathBuf,
}

impl Ctx {
    /// A fixture below `fixtures/`.
    pub fn fixture(&self, rel: &str) -> Result<Mesh> {
        load(&self.root.join("fixtures").join(rel))
    }
    /// Timing runs per measurement (median reported).
    pub fn runs(&self) -> usize {
        if self.quick {
            1
        } else {
            3
        }
    }
}

/// Reads and validates a mesh file.
pub fn load(path: &Path) -> Result<Mesh> {
    let soup = subdiv_io::read_mesh(path)?;
    let (mesh, _) = Mesh::from_soup(soup).with_context(|| path.display().to_string())?;
    Ok(mesh)
}

/// Runs `f` at least `runs` times — and, when `runs` > 1, until 0.2 s have
/// passed (at most 1000 runs), so that sub-millisecond calls are timed warm
/// and many times; returns the last result and the median wall time in ms.
pub fn timed<T>(runs: usize, mut f: impl FnMut() -> T) -> (T, f64) {
    let mut times = Vec::with_capacity(runs);
    let mut last = None;
    let started = Instant::now();
    while times.len() < runs.max(1) || (runs > 1 && times.len() < 1000 && started.elapsed().as_secs_f64() < 0.2) {
        let start = Instant::now();
        last = Some(f());
        times.push(start.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    (last.expect("at least one run"), times[times.len() / 2])
}

/// What a regression metric measures, which fixes how it may move (docs/ARCHITECTURE.md,
/// "Contract: paper reproduction":
/// iteration counts and errors are compared, never times).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// An iteration count: may not grow by more than 10 % + 1.
    Iterations,
    /// An error: may not grow by more than 10× (and past 1e-12 when it was round-off).
    Error,
}

/// One table of `docs/results/`.
pub struct Table {
    /// File stem, e.g. `table1-zheng-cai-nasri`.
    pub id: &'static str,
    /// Heading.
    pub title: String,
    /// Paragraph on setup: meshes, parameters, what the paper reports.
    pub setup: String,
    /// Column names.
    pub header: Vec<String>,
    /// Rows of cells.
    pub rows: Vec<Vec<String>>,
    /// Notes after the table (observations, explanations).
    pub notes: Vec<String>,
    /// Machine-readable results.
    pub json: Vec<Value>,
    /// Regression metrics by key.
    pub metrics: BTreeMap<String, (f64, Kind)>,
    /// Figures written next to the table (file names).
    pub figures: Vec<String>,
}

impl Table {
    /// An empty table.
    pub fn new(id: &'static str, title: impl Into<String>, header: &[&str]) -> Self {
        Table {
            id,
            title: title.into(),
            setup: String::new(),
            header: header.iter().map(|s| s.to_string()).collect(),
            rows: Vec::new(),
            notes: Vec::new(),
            json: Vec::new(),
            metrics: BTreeMap::new(),
            figures: Vec::new(),
        }
    }

    /// Adds a row.
    pub fn row(&mut self, cells: Vec<String>) {
        self.rows.push(cells);
    }

    /// Records a regression metric.
    pub fn metric(&mut self, key: impl Into<String>, value: f64, kind: Kind) {
        self.metrics.insert(format!("{}/{}", self.id, key.into()), (value, kind));
    }

    /// The Markdown page.
    pub fn markdown(&self, machine: &str, quick: bool) -> String {
        let mut s = format!("# {}\n\n{}\n\n", self.title, self.setup);
        s += &format!(
            "*Machine:* {machine}. *Build:* release (`cargo xtask reproduce-paper{}`). Times are {} \
             on a shared machine: compare ratios, not absolutes.\n\n",
            if quick { " --quick" } else { "" },
            if quick { "single runs" } else { "medians of at least 3 runs (of as many as fit in 0.2 s, up to 1000)" }
        );
        s += &format!("| {} |\n|{}|\n", self.header.join(" | "), vec!["---"; self.header.len()].join("|"));
        for r in &self.rows {
            s += &format!("| {} |\n", r.join(" | "));
        }
        for n in &self.notes {
            s += &format!("\n{n}\n");
        }
        for f in &self.figures {
            s += &format!("\n![{f}]({f})\n");
        }
        s
    }

    /// Writes `<id>.md` and `<id>.json`.
    pub fn write(&self, ctx: &Ctx, machine: &str) -> Result<()> {
        std::fs::write(ctx.out.join(format!("{}.md", self.id)), self.markdown(machine, ctx.quick))?;
        let json = json!({
            "id": self.id, "title": self.title, "quick": ctx.quick, "machine": machine,
            "header": self.header, "rows": self.rows, "results": self.json,
            "metrics": self.metrics.iter().map(|(k, (v, _))| (k.clone(), json!(v))).collect::<serde_json::Map<_, _>>(),
        });
        std::fs::write(ctx.out.join(format!("{}.json", self.id)), serde_json::to_string_pretty(&json)? + "\n")?;
        Ok(())
    }
}

/// Scientific notation with 2 decimals.
pub fn sci(x: f64) -> String {
    format!("{x:.2e}")
}

/// Fixed notation with 2 decimals (times in ms).
pub fn ms(x: f64) -> String {
    if x >= 100.0 {
        format!("{x:.0}")
    } else if x >= 1.0 {
        format!("{x:.1}")
    } else {
        format!("{x:.3}")
    }
}

/// A one-line description of the machine.
pub fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1);
    let rustc = std::process::Command::new("rustc")
        .arg("--version")
        .output()
        .ok()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default();
    format!("{cpu}, {cores} cores, {rustc}")
}
