//! The one pipeline of the subdiv tools.
//!
//! `subdiv interpolate`, `subdiv subdivide`, `subdiv info`, every job of `subdiv batch` and the
//! Python package are thin maps onto this crate:
//!
//! - **Options** ([`options`]) are serde values: [`InterpolateOptions`], [`SubdivideOptions`],
//!   [`InfoOptions`] in a [`Command`], parsed from JSON (the command line's flags, a batch's
//!   options, Python's keyword arguments) by [`Command::from_json`]. An absent option takes the
//!   library's default; an unknown one, or one that does not apply to the chosen method or
//!   scheme, is refused the same way everywhere.
//! - **One run per file** ([`run`]): [`run::interpolate`], [`run::subdivide`], [`run::info`] —
//!   outputs checked before any work, input read with its tags, the method, every refinement
//!   sized against the memory budget ([`budget`]), the error measured on the positions as
//!   written, every output staged and committed together (all or none), a typed report.
//! - **Scenes** ([`scene`]): a USD input is the meshes of its `Mesh` prims (`--prim` keeps
//!   one); `interpolate` and `subdivide` run on each and write every result into one USD file at
//!   the input's prim paths (other formats take one mesh).
//! - **Many files** ([`batch`]): one [`Command`] over files, directories and glob patterns, in
//!   parallel and resumable, one [`batch::Record`] per input.
//! - **Failures** ([`JobError`]) are one line in the command line's terms with an
//!   [`ErrorKind`] that fixes the exit code, the record's error and the Python exception.
//! - **Progress** ([`Progress`]): phases, warnings and solver iterations go to the front-end
//!   (bars on a terminal, a record's warnings, Python warnings).
//!
//! ```
//! use subdiv_job::{run, Command, Silent};
//! let dir = std::env::temp_dir().join(format!("subdiv-job-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir)?;
//! let input = dir.join("torus.obj");
//! subdiv_io::write_mesh(&input, &subdiv_mesh::shapes::torus(8, 6), &Default::default())?;
//! let json = serde_json::json!({"method": "cheng", "tol": 1e-9});
//! let Command::Interpolate(options) = Command::from_json("interpolate", &json)? else { unreachable!() };
//! let outputs = run::InterpolateOutputs::default().with_control(Some(dir.join("control.obj")));
//! let done = run::interpolate(&input, &options, &outputs, &mut Silent)?;
//! assert!(done.error.max_rel <= 1e-9 && done.outputs.len() == 1);
//! std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod batch;
pub mod budget;
mod error;
pub mod info;
pub mod load;
pub mod options;
pub mod outputs;
mod progress;
pub mod run;
pub mod scene;

pub use error::{in_option_terms, one_line, ErrorKind, JobError};
pub use options::{
    Command, InfoOptions, InterpolateOptions, Parameter, ShapeValue, SubdivideOptions, SurfaceChoice, TagOptions,
    COMMAND_NAMES,
};
pub use progress::{Phase, Progress, Silent, Warnings};
pub use run::{interpolate_mesh, method_options, subdivide_mesh};
