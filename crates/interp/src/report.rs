//! The typed report of an interpolation (what `subdiv interpolate --report`
//! writes), its parts, and the parameters each method records.
//!
//! Every struct is `#[non_exhaustive]` and serialises with serde: a new
//! field is a new JSON key, never a breaking change for readers of the file
//! or users of the type.

use crate::{ErrorStats, Interpolant, Method};
use serde::Serialize;
use subdiv_mesh::Mesh;

/// How many crease and corner tags a mesh has, by kind (boundaries are not
/// counted: they are sharp by topology, not by tag).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[non_exhaustive]
pub struct TagCounts {
    /// Edges with sharpness > 0.
    pub creases: usize,
    /// Vertices with corner sharpness > 0.
    pub corners: usize,
    /// Of both, those ≥ 10 (infinitely sharp).
    pub infinitely_sharp: usize,
    /// Of both, those in (0, 10) (semi-sharp: they decay level by level).
    pub semi_sharp: usize,
    /// Faces tagged as holes (left out of the JSON when none).
    #[serde(skip_serializing_if = "is_zero")]
    pub holes: usize,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

impl TagCounts {
    /// The tags of a validated mesh.
    pub fn of_mesh(mesh: &Mesh) -> Self {
        let tags = mesh.tags();
        let counts = Self::of(tags.edge_values().iter().copied(), tags.vertex_values().iter().copied());
        counts.with_holes(tags.hole_count())
    }

    /// The same counts with `holes` hole faces.
    pub fn with_holes(self, holes: usize) -> Self {
        Self { holes, ..self }
    }

    /// The counts of edge sharpness values `creases` and vertex sharpness
    /// values `corners` (zeros are not tags).
    pub fn of(creases: impl Iterator<Item = f32>, corners: impl Iterator<Item = f32>) -> Self {
        let creases: Vec<f32> = creases.filter(|&s| s > 0.0).collect();
        let corners: Vec<f32> = corners.filter(|&s| s > 0.0).collect();
        let infinitely_sharp =
            creases.iter().chain(&corners).filter(|&&s| s >= subdiv_mesh::SHARPNESS_INFINITE).count();
        TagCounts {
            creases: creases.len(),
            corners: corners.len(),
            infinitely_sharp,
            semi_sharp: creases.len() + corners.len() - infinitely_sharp,
            holes: 0,
        }
    }
}

/// The input or the control mesh of a report.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
#[non_exhaustive]
pub struct MeshSummary {
    /// The file it was read from (input only, when known).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// Vertices.
    pub vertices: usize,
    /// Faces.
    pub faces: usize,
    /// The bounding-box diagonal d errors are relative to (input only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bbox_diagonal: Option<f64>,
    /// Its crease and corner tags.
    pub tags: TagCounts,
    /// Whether it has texture coordinates.
    pub uvs: bool,
}

impl MeshSummary {
    /// The summary of `mesh` (no file, no d).
    pub fn of(mesh: &Mesh) -> Self {
        MeshSummary {
            file: None,
            // A non-manifold input's vertices, not its cover's copies.
            vertices: mesh.welds().map_or(mesh.topology().vertex_count(), |welds| welds.vertex_count()),
            faces: mesh.topology().face_count(),
            bbox_diagonal: None,
            tags: TagCounts::of_mesh(mesh),
            uvs: mesh.uvs().is_some(),
        }
    }
}

/// The surface options as names (`edge-and-corner`, `uniform`, …).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
#[non_exhaustive]
pub struct SurfaceOptionsSummary {
    /// [`crate::SurfaceOptions::boundary`].
    pub boundary: String,
    /// [`crate::SurfaceOptions::crease_method`].
    pub crease_method: String,
    /// [`crate::SurfaceOptions::fvar`].
    pub fvar: String,
}

/// How the solve went, as reported (explicit methods: no name, 0
/// iterations, converged).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
#[non_exhaustive]
pub struct SolverReport {
    /// The solver (`None` for the explicit methods).
    pub name: Option<String>,
    /// Iterations.
    pub iterations: usize,
    /// Whether the solver reached its tolerance.
    pub converged: bool,
    /// Sparse products.
    pub matvecs: usize,
    /// Final residual / d.
    pub residual: f64,
    /// Residual / d per iteration.
    pub residual_history: Vec<f64>,
}

/// The measured error, relative to d and absolute.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
#[non_exhaustive]
pub struct ErrorReport {
    /// max |L_i − P_i| / d.
    pub max_rel: f64,
    /// mean |L_i − P_i| / d.
    pub mean_rel: f64,
    /// max |L_i − P_i|.
    pub max_abs: f64,
    /// mean |L_i − P_i|.
    pub mean_abs: f64,
    /// Vertices measured.
    pub vertices: usize,
}

impl From<ErrorStats> for ErrorReport {
    fn from(e: ErrorStats) -> Self {
        ErrorReport {
            max_rel: e.max_rel,
            mean_rel: e.mean_rel,
            max_abs: e.max_abs,
            mean_abs: e.mean_abs,
            vertices: e.count,
        }
    }
}

/// Milliseconds per phase.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
#[non_exhaustive]
pub struct Timing {
    /// Building operators.
    pub setup: f64,
    /// Solving and assembling the control mesh.
    pub solve: f64,
    /// The whole job as the caller timed it (reading and writing included
    /// for the command line).
    pub total: f64,
}

/// A summary of a list of values: how many, smallest, largest.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[non_exhaustive]
pub struct Range {
    /// How many values (one per face).
    pub per_face: usize,
    /// Smallest.
    pub min: f64,
    /// Largest.
    pub max: f64,
}

impl Range {
    /// The range of `values` (no values, min +∞, max −∞ when empty).
    pub fn of(values: &[f64]) -> Self {
        let (min, max) = values.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        Range { per_face: values.len(), min, max }
    }
}

/// Brunet's shape handles as reported: how many were applied and their range.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[non_exhaustive]
pub struct HandlesSummary {
    /// Handles applied (at interpolated interior vertices).
    pub count: usize,
    /// Smallest S_k given.
    pub min: f64,
    /// Largest S_k given.
    pub max: f64,
}

/// A shape parameter as reported: one λ (Fan-Cheng-Lai uniform, Deng-Ma's
/// variable tension) or the range of per-face values.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Lambda {
    /// One value.
    Uniform(f64),
    /// Per face: count, min, max.
    PerFace(Range),
}

/// How many interpolated vertices' limit rows were of each kind (Deng-Wang's
/// `limit_rows`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[non_exhaustive]
pub struct RowCounts {
    /// Smooth rows (the plain mask).
    pub smooth: usize,
    /// Crease rows.
    pub crease: usize,
    /// Corner rows.
    pub corner: usize,
    /// Composed rows (darts, semi-sharp, boundary options).
    pub general: usize,
}

/// The parameters a method used, for the report: one struct for every
/// method, each setting the fields it has (the others are left out of the
/// JSON).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
#[non_exhaustive]
pub struct Parameters {
    /// The solver or iteration that ran (solved methods, Zheng-Cai).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub solver: Option<String>,
    /// The solve tolerance (solved methods).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tol: Option<f64>,
    /// Zheng-Cai's ITE_MAX.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ite_max: Option<usize>,
    /// Zheng-Cai's EPS.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub eps: Option<f64>,
    /// What the solver history holds (Zheng-Cai).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub history: Option<String>,
    /// Prescribed normals given (Zheng-Cai).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub normals: Option<usize>,
    /// Brunet's handles (Zheng-Cai; `Some(None)`: none given, JSON `null`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub handles: Option<Option<HandlesSummary>>,
    /// Fan-Cheng-Lai's λ, or Deng-Ma's variable-tension λ.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lambda: Option<Lambda>,
    /// Deng-Ma's global tension ω.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub omega: Option<f64>,
    /// Deng-Wang's μ.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mu: Option<f64>,
    /// Loop's β (`loop`, `warren`): Deng-Wang's, and cheng's or fair's with
    /// the Loop scheme.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub beta: Option<String>,
    /// Prescribed normals given (Deng-Wang).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub user_normals: Option<usize>,
    /// Faces Deng-Wang triangulated first.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub triangulated_faces: Option<usize>,
    /// Deng-Wang's limit rows by kind.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub limit_rows: Option<RowCounts>,
    /// Crease tags of Deng-Wang's control mesh.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub control_creases: Option<usize>,
    /// Corner tags of Deng-Wang's control mesh.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub control_corners: Option<usize>,
    /// The fair method's refinement count K.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refine: Option<usize>,
    /// The fair method's fairness weight w (`None`: exact constraints).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fairness_weight: Option<f64>,
    /// The control scheme of cheng and fair (`catmull-clark`, `loop`,
    /// `doo-sabin`, `sqrt3`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scheme: Option<String>,
    /// The fair method's energy (1) of its result, relative to d²
    /// (`subdiv_interp::fair` module docs).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy: Option<f64>,
    /// Vertices interpolated (every method).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interpolated_vertices: Option<usize>,
}

impl Parameters {
    /// Records a method's control `scheme` and, for Loop, its β.
    pub(crate) fn record_scheme(&mut self, scheme: subdiv_stencil::Scheme) {
        self.scheme = Some(scheme.name().to_string());
        if let (Some(beta), _) = scheme.parameters() {
            self.beta = Some(beta.to_string());
        }
    }
}

/// The report of one interpolation: what `subdiv interpolate --report`
/// writes, and what the bindings return. Serialise it with serde
/// (`serde_json::to_string_pretty(&report)`).
///
/// ```
/// use subdiv_interp::{interpolate, Method, MethodOptions, Report};
/// let torus = subdiv_mesh::shapes::torus(8, 6);
/// let result = interpolate(&torus, &MethodOptions::new(Method::Cheng)).unwrap();
/// let report = Report::new(&torus, &result, result.error_all(&torus));
/// assert_eq!(report.method, "cheng");
/// assert_eq!(report.input.vertices, 48);
/// assert!(report.error.max_rel <= 1e-6);
/// ```
#[derive(Clone, Debug, PartialEq, Serialize)]
#[non_exhaustive]
pub struct Report {
    /// [`Method::name`].
    pub method: String,
    /// The control mesh's scheme (`doo-sabin`, `catmull-clark`, `loop`;
    /// `None` for Deng-Ma, whose output is no control mesh).
    pub control_scheme: Option<String>,
    /// The input (with its file and d).
    pub input: MeshSummary,
    /// The control mesh as written (for Deng-Ma the refined surface).
    pub control: MeshSummary,
    /// The surface options of the control mesh's scheme.
    pub surface_options: SurfaceOptionsSummary,
    /// How the solve went.
    pub solver: SolverReport,
    /// The measured error (never the solver's residual).
    pub error: ErrorReport,
    /// Milliseconds per phase.
    pub timing_ms: Timing,
    /// The method's parameters.
    pub parameters: Parameters,
    /// Things the user should know.
    pub warnings: Vec<String>,
}

impl Report {
    /// The report of `result`, computed from `input`, with the error
    /// `error` measured independently ([`Interpolant::error`]). The total
    /// time is setup + solve until [`Self::with_total_ms`] sets the caller's.
    pub fn new(input: &Mesh, result: &Interpolant, error: ErrorStats) -> Self {
        let solve = result.solve.clone().unwrap_or_default();
        let surface = result.surface_options;
        let timing = Timing {
            setup: result.setup_seconds * 1e3,
            solve: result.solve_seconds * 1e3,
            total: (result.setup_seconds + result.solve_seconds) * 1e3,
        };
        Report {
            method: result.method.name().to_string(),
            control_scheme: (!result.scheme.traits().interpolating).then(|| result.scheme.name().to_string()),
            input: MeshSummary { bbox_diagonal: Some(input.bbox_diagonal()), ..MeshSummary::of(input) },
            control: MeshSummary::of(&result.control),
            surface_options: SurfaceOptionsSummary {
                boundary: surface.boundary.name().to_string(),
                crease_method: surface.crease_method.name().to_string(),
                fvar: surface.fvar.name().to_string(),
            },
            solver: SolverReport {
                name: result.solve.as_ref().map(|s| s.solver.clone()),
                iterations: solve.iterations,
                converged: result.solve.as_ref().is_none_or(|s| s.converged),
                matvecs: solve.matvecs,
                residual: solve.residual,
                residual_history: solve.history,
            },
            error: error.into(),
            timing_ms: timing,
            parameters: result.parameters.clone(),
            warnings: result.warnings.clone(),
        }
    }

    /// Names the input file.
    pub fn with_input_file(mut self, file: impl Into<String>) -> Self {
        self.input.file = Some(file.into());
        self
    }

    /// Describes the control mesh as written (Deng-Ma: the refined surface).
    pub fn with_control(mut self, control: &Mesh) -> Self {
        self.control = MeshSummary::of(control);
        self
    }

    /// Sets the total time (milliseconds) as the caller measured it.
    pub fn with_total_ms(mut self, total: f64) -> Self {
        self.timing_ms.total = total;
        self
    }

    /// The method, parsed back.
    pub fn method(&self) -> Option<Method> {
        self.method.parse().ok()
    }
}
