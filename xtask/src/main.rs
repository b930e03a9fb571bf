//! `cargo xtask …`: repository tasks (paper reproduction, benchmarks, figures).

mod plot;
mod render;
mod reproduce;
mod valence2;

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
    /// Write a copy of a mesh with interior valence-2 vertices (split edges between quads).
    Valence2Mesh(valence2::Valence2Args),
}

fn main() -> anyhow::Result<()> {
    match Cli::parse().task {
        Task::ReproducePaper(args) => reproduce::run(&args),
        Task::Render(args) => render::run(&args),
        Task::Valence2Mesh(args) => valence2::run(&args),
    }
}
