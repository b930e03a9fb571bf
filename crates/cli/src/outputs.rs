//! A command's outputs: the one pipeline's ([`subdiv::job::outputs`]), checked before any work
//! starts, staged as they are built, committed together at the end (all of them or none).

use crate::failure::Failure;
use std::path::Path;
use subdiv_io::Format;

/// The outputs of one command, with the command line's progress bars and exit codes.
pub struct Outputs(subdiv::job::outputs::Outputs);

impl Outputs {
    /// Outputs of a command reading `inputs` (the mesh and parameter files).
    pub fn new<'a>(inputs: impl IntoIterator<Item = &'a Path>) -> Self {
        Self(subdiv::job::outputs::Outputs::new(inputs))
    }

    /// Plans a mesh output given by `flag`; returns its format.
    pub fn mesh(&mut self, flag: &'static str, path: &Path) -> Result<Format, Failure> {
        Ok(self.0.mesh(flag, path)?)
    }

    /// Plans a non-mesh output given by `flag`.
    pub fn other(&mut self, flag: &'static str, path: &Path) -> Result<(), Failure> {
        Ok(self.0.other(flag, path)?)
    }

    /// Checks and stages a control mesh output (with vertex normals when `normals`; hole faces
    /// kept).
    pub fn stage_mesh(
        &mut self,
        flag: &str,
        path: &Path,
        mesh: &subdiv_mesh::Mesh,
        normals: bool,
    ) -> Result<(), Failure> {
        Ok(self.0.stage_mesh(flag, path, mesh, normals, false, &mut crate::progress::Terminal::default())?)
    }

    /// Adds a staged output (one of the planned paths).
    pub fn stage(&mut self, file: subdiv_io::StagedFile) {
        self.0.stage(file);
    }

    /// Stages a non-mesh output.
    pub fn stage_bytes(&mut self, path: &Path, bytes: &[u8]) -> Result<(), Failure> {
        Ok(self.0.stage_bytes(path, bytes)?)
    }

    /// Puts every staged output in place, or none (exit 4 on failure).
    pub fn commit(self) -> Result<(), Failure> {
        self.0.commit()?;
        Ok(())
    }
}
