//! The flags of the commands that run the one pipeline (`interpolate`, `subdivide`, `batch`):
//! each given flag becomes the option of the same name in a JSON object (`--max-iter 50` →
//! `"max_iter": 50`), which [`subdiv::job::Command::from_json`] parses and checks — the parser
//! of the batch and of the Python package, so the defaults, the checks and the messages are the
//! same everywhere. A flag not given is absent: the library's default applies.

use serde_json::{json, Map, Value};
use std::path::PathBuf;
use subdiv::budget::parse_bytes;

/// A value parser for the option enums that name their values (`FromStr`).
pub fn named<T: std::str::FromStr<Err = String>>(s: &str) -> Result<T, String> {
    s.parse()
}

/// Puts each `(key, value)` whose value is given into `map`.
macro_rules! put_given {
    ($map:expr, $($key:expr => $value:expr),+ $(,)?) => {{
        $(if let Some(v) = $value { $map.insert($key.to_string(), json!(v)); })+
    }};
}
pub(crate) use put_given as put;

/// The options every refining command shares: the surface's options, the tags, the budget.
#[derive(clap::Args, Debug, Default)]
pub struct SurfaceFlags {
    /// Boundary interpolation (OpenSubdiv): edge-and-corner (default: boundary curves, one-face
    /// corners kept), edge-only (corners rounded), none (as edge-only; OpenSubdiv's boundary holes).
    #[arg(long)]
    pub boundary: Option<String>,
    /// How semi-sharp creases decay per level: uniform (default, s − 1) or chaikin.
    #[arg(long)]
    pub crease_method: Option<String>,
    /// Face-varying interpolation of the texture coordinates (OpenSubdiv): linear-all (default),
    /// linear-boundaries, linear-corners-plus2, linear-corners-plus1, linear-corners-only, linear-none.
    #[arg(long)]
    pub fvar: Option<String>,
    /// Catmull-Clark's rule for triangles: catmark (default) or smooth (OpenSubdiv's
    /// TRI_SUB_SMOOTH: rounder over triangles). A mesh file's own option tags (`t
    /// interpolateboundary`, `t creasemethod`, `t facevaryinginterpolateboundary`, `t
    /// smoothtriangles`) apply where these options are not given.
    #[arg(long)]
    pub triangle_rule: Option<String>,
    /// Which limit point a dart (one sharp edge at a smooth vertex) gets: exact (default: the
    /// limit of refinement, what patch evaluators such as Blender's modifier show) or smooth-mask
    /// (OpenSubdiv's limit-stencil shortcut, `Far::PrimvarRefiner::Limit`).
    #[arg(long)]
    pub dart_limit: Option<String>,
    /// Crease and corner tags besides the file's own: JSON {"creases": [[v0, v1, s], …],
    /// "corners": [[v, s], …]}, 0-based vertices, sharpness 0 smooth … ≥ 10 infinitely sharp.
    #[arg(long)]
    pub tags: Option<PathBuf>,
    /// Tag every interior edge whose faces turn by at least DEG degrees as an infinitely sharp
    /// crease; tags of the file or --tags on the same edges win.
    #[arg(long, value_name = "DEG")]
    pub feature_angle: Option<f64>,
    /// A USD input: process only the Mesh prim at PATH (default: every Mesh prim, written
    /// together to a USD output at the same prim paths).
    #[arg(long, value_name = "PATH")]
    pub prim: Option<String>,
    /// Memory budget of the method and the refinements, in bytes (suffixes K, M, G, T: powers of
    /// 1024; default ¾ of the memory available). Larger work is refused with exit 2.
    #[arg(long, value_name = "BYTES", value_parser = parse_bytes)]
    pub max_memory: Option<u64>,
    /// Loop's β: loop (default: Loop's original, OpenSubdiv's) or warren.
    #[arg(long)]
    pub beta: Option<String>,
}

impl SurfaceFlags {
    pub fn put(&self, map: &mut Map<String, Value>) {
        put_given!(map,
            "boundary" => &self.boundary, "crease_method" => &self.crease_method, "fvar" => &self.fvar,
            "triangle_rule" => &self.triangle_rule, "dart_limit" => &self.dart_limit,
            "tags" => &self.tags, "feature_angle" => self.feature_angle, "prim" => &self.prim,
            "max_memory" => self.max_memory,
            "beta" => &self.beta);
    }
}

/// Deng-Ma's tension.
#[derive(clap::Args, Debug, Default)]
pub struct TensionFlags {
    /// Deng-Ma: global tension ω ∈ (0, 1] (default 1).
    #[arg(long)]
    pub omega: Option<f64>,
    /// Deng-Ma: displacement-safe variable tension with this λ ∈ (0, 1] (report §3.4).
    #[arg(long)]
    pub variable_tension: Option<f64>,
}

impl TensionFlags {
    pub fn put(&self, map: &mut Map<String, Value>) {
        put_given!(map, "omega" => self.omega, "variable_tension" => self.variable_tension);
    }
}

/// The method and its options (`subdiv interpolate`, `subdiv batch interpolate`).
#[derive(clap::Args, Debug, Default)]
pub struct MethodFlags {
    /// Interpolation method (the method table's names).
    #[arg(long, help = format!("Interpolation method: {}", subdiv_interp::Method::ALL.map(|m| m.name()).join(", ")))]
    pub method: Option<String>,
    /// Solver: auto (default), pia, weighted-pia, jacobi, gauss-seidel, gauss-seidel-symmetric,
    /// gauss-seidel-multicolor, chebyshev, cg, cg-jacobi, minres, gmres, ldl, dense. auto: CG on
    /// positive definite symmetric systems, MINRES on possibly indefinite ones, GMRES on
    /// nonsymmetric ones.
    #[arg(long)]
    pub solver: Option<String>,
    /// Tolerance: max over vertices of |P − limit| / d (d = bounding-box diagonal; default 1e-6).
    #[arg(long)]
    pub tol: Option<f64>,
    /// Iteration cap of the iterative solvers (default 10000).
    #[arg(long)]
    pub max_iter: Option<usize>,
    /// fan-cheng-lai: one shape parameter λ ∈ (0, 1) for every face.
    #[arg(long)]
    pub shape: Option<f64>,
    /// fan-cheng-lai: JSON {"default": λ, "faces": {"f": λ}, "groups": {"obj group": λ}}.
    #[arg(long)]
    pub shape_file: Option<PathBuf>,
    /// Vertices to interpolate (0-based indices, text or JSON array); default all.
    #[arg(long)]
    pub subset: Option<PathBuf>,
    /// zheng-cai: Brunet shape handles, lines "i S" or JSON {"i": S}.
    #[arg(long)]
    pub handles: Option<PathBuf>,
    /// zheng-cai: ITE_MAX, the Gauss-Seidel sweeps on the auxiliary mesh (default 5, the paper's).
    #[arg(long)]
    pub ite_max: Option<usize>,
    /// zheng-cai: EPS, stop sweeping when every update is below EPS·d (default 0.003, the paper's).
    #[arg(long)]
    pub eps: Option<f64>,
    /// deng-wang: the edge parameter μ of Eq. 9 (default ⅜: measured best, see the deng_wang module docs).
    #[arg(long)]
    pub mu: Option<f64>,
    /// fair: the control mesh is the input refined K times (default 1; 0: the scheme's exact method).
    #[arg(long, value_name = "K")]
    pub refine: Option<usize>,
    /// fair: trade interpolation for fairness, minimising |limit − data|² + W·energy (W > 0; the
    /// result approximates and --tol is not checked); default: exact interpolation.
    #[arg(long, value_name = "W")]
    pub fairness_weight: Option<f64>,
}

impl MethodFlags {
    pub fn put(&self, map: &mut Map<String, Value>) {
        put_given!(map,
            "method" => &self.method, "solver" => &self.solver, "tol" => self.tol, "max_iter" => self.max_iter,
            "shape" => self.shape, "shape_file" => &self.shape_file, "subset" => &self.subset,
            "handles" => &self.handles, "ite_max" => self.ite_max, "eps" => self.eps, "mu" => self.mu,
            "refine" => self.refine, "fairness_weight" => self.fairness_weight);
    }
}

/// `subdiv interpolate`'s options.
#[derive(clap::Args, Debug)]
pub struct InterpolateFlags {
    /// The method and its options.
    #[command(flatten)]
    pub method: MethodFlags,
    /// zheng-cai, deng-wang: per-vertex normals, lines "i nx ny nz" or JSON {"i": [x, y, z]}.
    #[arg(long)]
    pub normals: Option<PathBuf>,
    /// cheng, fair: the control mesh's scheme (default catmull-clark).
    #[arg(long, help = format!(
        "cheng (catmull-clark, loop, sqrt3), fair (catmull-clark, loop, doo-sabin): the control mesh's scheme \
         (default catmull-clark); the scheme table: {}",
        scheme_names()
    ))]
    pub scheme: Option<String>,
    /// Levels of --surface (and deng-ma's -o; default 3).
    #[arg(long)]
    pub levels: Option<usize>,
    /// Deng-Ma's tension.
    #[command(flatten)]
    pub tension: TensionFlags,
    /// The surface's options, tags, budget.
    #[command(flatten)]
    pub surface: SurfaceFlags,
}

impl InterpolateFlags {
    /// The options given, as `subdiv::job::InterpolateOptions` takes them.
    pub fn to_json(&self) -> Value {
        let mut map = Map::new();
        self.method.put(&mut map);
        put_given!(map, "normals" => &self.normals, "scheme" => &self.scheme, "levels" => self.levels);
        self.tension.put(&mut map);
        self.surface.put(&mut map);
        Value::Object(map)
    }
}

/// The names of the scheme table, for help texts.
pub fn scheme_names() -> String {
    subdiv_stencil::Scheme::ALL.map(|s| s.name()).join(", ")
}

/// `subdiv subdivide`'s options.
#[derive(clap::Args, Debug)]
pub struct SubdivideFlags {
    /// Subdivision scheme (the scheme table's names).
    #[arg(long, help = format!("Subdivision scheme: {}", scheme_names()))]
    pub scheme: Option<String>,
    /// Number of subdivision steps (0 with --limit: the input's limit positions).
    #[arg(long)]
    pub levels: Option<usize>,
    /// Move the final vertices to their limit positions (not for deng-ma, which interpolates).
    #[arg(long)]
    pub limit: bool,
    /// Loop on a mesh with non-triangles: triangulate every face first (keeping the mesh manifold).
    #[arg(long)]
    pub triangulate: bool,
    /// Write angle-weighted vertex normals (formats that store them).
    #[arg(long)]
    pub normals: bool,
    /// Deng-Ma's tension.
    #[command(flatten)]
    pub tension: TensionFlags,
    /// The surface's options, tags, budget.
    #[command(flatten)]
    pub surface: SurfaceFlags,
}

impl SubdivideFlags {
    /// The options given, as `subdiv::job::SubdivideOptions` takes them.
    pub fn to_json(&self) -> Value {
        let mut map = Map::new();
        put_given!(map, "scheme" => &self.scheme, "levels" => self.levels);
        for (key, on) in [("limit", self.limit), ("triangulate", self.triangulate), ("normals", self.normals)] {
            put_given!(map, key => on.then_some(true));
        }
        self.tension.put(&mut map);
        self.surface.put(&mut map);
        Value::Object(map)
    }
}
