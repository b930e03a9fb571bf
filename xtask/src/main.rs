//! `cargo xtask …`: repository tasks (paper reproduction, benchmarks, figures).

mod plot;
mod render;
mod reproduce;

use clap::{Parser, Subcommand};

/// Repository tasks.
#[derive(Parser, Debug)]
#[command(name = "xtask")]
struct Cli {
    #[command(subcommand)]
    task: Task,
}

#[derive(Subcommand, Debug)]
enum Task {
    /// Regenerate the papers' tables and figures into docs/results/.
    ReproducePaper(reproduce::Args),
    /// Render one mesh file headless to a PNG (to try the figure renderer).
    Render(render::RenderArgs),
}

fn main() -> anyhow::Result<()> {
    match Cli::parse().task {
        Task::ReproducePaper(args) => reproduce::run(&args),
        Task::Render(args) => render::run(&args),
    }
}
