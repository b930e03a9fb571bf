//! Keyword arguments → the library's options, as the command line turns its flags into them
//! (`crates/cli/src/interpolate.rs`, `subdivide.rs`): the same defaults, the same checks, the
//! same messages with the keyword in place of the flag.

use crate::errors::{input, Error};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use subdiv::interp::{params, FairOptions, Shape};
use subdiv::prelude::*;

/// The keyword arguments of a call, taken one by one; what is left at the
/// end is an unexpected keyword (a `TypeError`, as Python's own).
pub struct Kwargs<'py> {
    function: &'static str,
    dict: Option<Bound<'py, PyDict>>,
}

impl<'py> Kwargs<'py> {
    /// The keywords of `function`.
    pub fn new(function: &'static str, dict: Option<Bound<'py, PyDict>>) -> Self {
        Self { function, dict }
    }

    /// Removes and returns `key` (`None` when absent or `None`).
    pub fn take(&mut self, key: &str) -> PyResult<Option<Bound<'py, PyAny>>> {
        let Some(dict) = &self.dict else { return Ok(None) };
        let value = dict.get_item(key)?;
        if value.is_some() {
            dict.del_item(key)?;
        }
        Ok(value.filter(|v| !v.is_none()))
    }

    /// [`Self::take`], extracted as `T`, with a message naming the keyword.
    pub fn get<T: for<'a> FromPyObjectOwned<'a>>(&mut self, key: &str, what: &str) -> PyResult<Option<T>> {
        let Some(value) = self.take(key)? else { return Ok(None) };
        value
            .extract::<T>()
            .map(Some)
            .map_err(|_| pyo3::exceptions::PyTypeError::new_err(format!("{}(): {key} must be {what}", self.function)))
    }

    /// A `TypeError` for the first keyword nobody took.
    pub fn finish(self) -> PyResult<()> {
        if let Some(dict) = self.dict {
            if let Some((key, _)) = dict.iter().next() {
                return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                    "{}() got an unexpected keyword argument '{key}'",
                    self.function
                )));
            }
        }
        Ok(())
    }
}

/// `name` parsed by the option's `FromStr` (`edge-and-corner`, `chaikin`, `linear-all`, …),
/// `_` accepted for `-`.
fn named<T: std::str::FromStr<Err = String>>(key: &str, value: Option<String>, default: T) -> Result<T, Error> {
    match value {
        None => Ok(default),
        Some(name) => name.replace('_', "-").parse().map_err(|e| input(format!("{key}: {e}"))),
    }
}

/// Loop's β by name (`warren`, `loop`).
fn beta(value: Option<String>) -> Result<LoopBeta, Error> {
    match value.as_deref() {
        None | Some("warren") => Ok(LoopBeta::Warren),
        Some("loop") => Ok(LoopBeta::Loop),
        Some(other) => Err(input(format!("beta: unknown Loop β `{other}` (expected one of: warren, loop)"))),
    }
}

/// The surface options (`boundary`, `crease_method`, `fvar`), shared by `subdivide` and
/// `interpolate`.
pub fn surface(kw: &mut Kwargs<'_>) -> PyResult<Result<SurfaceOptions, Error>> {
    let boundary = kw.get::<String>("boundary", "a str")?;
    let crease_method = kw.get::<String>("crease_method", "a str")?;
    let fvar = kw.get::<String>("fvar", "a str")?;
    Ok((|| {
        Ok(SurfaceOptions::default()
            .with_boundary(named("boundary", boundary, BoundaryInterpolation::default())?)
            .with_crease_method(named("crease_method", crease_method, CreaseMethod::default())?)
            .with_fvar(named("fvar", fvar, FVarInterpolation::default())?))
    })())
}

/// Deng-Ma's tension from `omega` / `variable_tension` (global ω = 1 by default); `None`
/// when neither is given.
fn tension(kw: &mut Kwargs<'_>) -> PyResult<Result<Option<Tension>, Error>> {
    let omega = kw.get::<f64>("omega", "a float")?;
    let lambda = kw.get::<f64>("variable_tension", "a float")?;
    Ok(match (omega, lambda) {
        (Some(_), Some(_)) => Err(input("omega and variable_tension exclude each other")),
        (_, Some(lambda)) => Ok(Some(Tension::Variable { lambda })),
        (Some(omega), None) => Ok(Some(Tension::Global(omega))),
        (None, None) => Ok(None),
    })
}

/// What `subdivide` runs: the options and whether to triangulate first.
pub struct Subdivide {
    /// Scheme and surface options.
    pub options: Options,
    /// Triangulate before Loop.
    pub triangulate: bool,
}

/// `subdivide(mesh, scheme, levels, limit, **options)`'s options.
pub fn subdivide(scheme: &str, limit: bool, kw: &mut Kwargs<'_>) -> PyResult<Result<Subdivide, Error>> {
    let beta_name = kw.get::<String>("beta", "a str")?;
    let tension = tension(kw)?;
    let surface = surface(kw)?;
    let triangulate = kw.get::<bool>("triangulate", "a bool")?;
    Ok((|| {
        let name = scheme.to_ascii_lowercase().replace('_', "-");
        let tension = tension?;
        let scheme = match name.as_str() {
            "doo-sabin" => Scheme::DooSabin,
            "catmull-clark" => Scheme::CatmullClark,
            "loop" => Scheme::Loop(beta(beta_name.clone())?),
            "deng-ma" => Scheme::DengMa(tension.unwrap_or_default()),
            _ => {
                return Err(input(format!(
                    "unknown scheme '{scheme}' (expected one of: doo-sabin, catmull-clark, loop, deng-ma)"
                )))
            }
        };
        if name != "deng-ma" && tension.is_some() {
            return Err(input("omega and variable_tension apply to scheme deng-ma only"));
        }
        if name != "loop" && beta_name.is_some() {
            return Err(input("beta applies to scheme loop only"));
        }
        if name != "loop" && triangulate.is_some() {
            return Err(input("triangulate applies to scheme loop only"));
        }
        if limit && name == "deng-ma" {
            return Err(input(
                "limit: the Deng-Ma scheme is interpolatory and has no limit mask; its refined vertices are the \
                 surface",
            ));
        }
        Ok(Subdivide { options: surface?.for_scheme(scheme), triangulate: triangulate.unwrap_or(false) })
    })())
}

/// A per-vertex parameter given as a dict `{vertex: value}` or an array with one entry per
/// vertex (`NaN` rows: none), as the JSON text of the command line's parameter files, so
/// that the one parser checks it (`subdiv::interp::params`) and its messages are the CLI's.
fn per_vertex_json(value: &Bound<'_, PyAny>, key: &str, width: usize) -> PyResult<Result<String, Error>> {
    use std::fmt::Write;
    let mut json = String::from("{");
    let mut push = |i: i64, values: &[f64]| -> Result<(), Error> {
        if values.iter().any(|x| !x.is_finite()) {
            if values.iter().all(|x| x.is_nan()) {
                return Ok(()); // none at this vertex
            }
            return Err(input(format!("{key}: vertex {i}: {values:?} is not finite")));
        }
        let sep = if json.len() > 1 { "," } else { "" };
        let shown: Vec<String> = values.iter().map(|x| format!("{x:?}")).collect();
        match width {
            1 => write!(json, "{sep}\"{i}\":{}", shown[0]),
            _ => write!(json, "{sep}\"{i}\":[{}]", shown.join(",")),
        }
        .expect("a String takes every write");
        Ok(())
    };
    let values = |v: &Bound<'_, PyAny>| -> PyResult<Vec<f64>> {
        if width == 1 {
            v.extract::<f64>().map(|x| vec![x])
        } else {
            v.extract::<Vec<f64>>()
        }
    };
    let what = if width == 1 { "a number" } else { "3 numbers" };
    let bad = |i: &dyn std::fmt::Display| input(format!("{key}: entry {i} must be {what}"));
    if let Ok(dict) = value.cast::<PyDict>() {
        for (k, v) in dict.iter() {
            let Ok(i) = k.extract::<i64>() else { return Ok(Err(input(format!("{key}: key {k} is no vertex index")))) };
            match values(&v) {
                Ok(vals) if vals.len() == width => {
                    if let Err(e) = push(i, &vals) {
                        return Ok(Err(e));
                    }
                }
                _ => return Ok(Err(bad(&i))),
            }
        }
    } else {
        let Ok(rows) = value.extract::<Vec<Bound<'_, PyAny>>>() else {
            return Ok(Err(input(format!("{key} must be a dict {{vertex: value}} or one entry per vertex"))));
        };
        for (i, row) in rows.iter().enumerate() {
            match values(row) {
                Ok(vals) if vals.len() == width => {
                    if let Err(e) = push(i as i64, &vals) {
                        return Ok(Err(e));
                    }
                }
                _ => return Ok(Err(bad(&i))),
            }
        }
    }
    json.push('}');
    Ok(Ok(json))
}

/// The options of `interpolate(mesh, method, tol, solver, max_iter, **options)`, built in
/// the command line's order (method's own options, then surface, tolerance, iteration cap,
/// solver, subset), with its checks.
pub fn interpolate(
    mesh: &subdiv::Mesh,
    method: &str,
    tol: f64,
    solver: &str,
    max_iter: Option<usize>,
    kw: &mut Kwargs<'_>,
) -> PyResult<Result<MethodOptions, Error>> {
    let n = mesh.topology().vertex_count();
    let shape_value = kw.take("shape")?;
    let normals = kw.take("normals")?.map(|v| per_vertex_json(&v, "normals", 3)).transpose()?;
    let handles = kw.take("handles")?.map(|v| per_vertex_json(&v, "handles", 1)).transpose()?;
    let subset = kw.get::<Vec<i64>>("subset", "a sequence of vertex indices")?;
    let ite_max = kw.get::<usize>("ite_max", "a non-negative int")?;
    let eps = kw.get::<f64>("eps", "a float")?;
    let mu = kw.get::<f64>("mu", "a float")?;
    let beta_name = kw.get::<String>("beta", "a str")?;
    let refine = kw.get::<usize>("refine", "a non-negative int")?;
    let fairness_weight = kw.get::<f64>("fairness_weight", "a float")?;
    let scheme = kw.get::<String>("scheme", "a str")?;
    let tension = tension(kw)?;
    let surface = surface(kw)?;
    let shape = shape_value.as_ref().map(|v| match v.extract::<f64>() {
        Ok(lambda) => Ok(Shape::Uniform(lambda)),
        Err(_) => {
            v.extract::<Vec<f64>>().map(Shape::PerFace).map_err(|_| input("shape must be a float λ or one λ per face"))
        }
    });
    Ok((|| {
        let method: Method = method.parse().map_err(|e: subdiv::interp::UnknownMethod| input(e.to_string()))?;
        use Method::*;
        let misuse = |key: &str, methods: &str| Err(input(format!("{key} applies to method {methods} only")));
        if shape.is_some() && method != FanChengLai {
            return misuse("shape", "fan-cheng-lai");
        }
        if (handles.is_some() || ite_max.is_some() || eps.is_some()) && method != ZhengCai {
            let key = if handles.is_some() {
                "handles"
            } else if ite_max.is_some() {
                "ite_max"
            } else {
                "eps"
            };
            return misuse(key, "zheng-cai");
        }
        if normals.is_some() && !matches!(method, ZhengCai | DengWang) {
            return misuse("normals", "zheng-cai or deng-wang");
        }
        if mu.is_some() && method != DengWang {
            return misuse("mu", "deng-wang");
        }
        if beta_name.is_some() && !matches!(method, DengWang | Fair) {
            return misuse("beta", "deng-wang or fair");
        }
        if (refine.is_some() || fairness_weight.is_some() || scheme.is_some()) && method != Fair {
            let key = if refine.is_some() {
                "refine"
            } else if fairness_weight.is_some() {
                "fairness_weight"
            } else {
                "scheme"
            };
            return misuse(key, "fair");
        }
        let beta_given = beta_name.is_some();
        let tension = tension?;
        if tension.is_some() && method != DengMa {
            return misuse("omega/variable_tension", "deng-ma");
        }
        let shape = shape.transpose()?;
        if let Some(Shape::Uniform(lambda)) = shape {
            if !(lambda > 0.0 && lambda < 1.0) {
                return Err(input(format!("shape: λ = {lambda} is outside (0, 1)")));
            }
        }
        if !(tol > 0.0 && tol.is_finite()) {
            return Err(input(format!("tol must be positive, got {tol}")));
        }
        // The JSON is ours: its line numbers mean nothing to the caller, the message is the point.
        let param = |key: &str, e: subdiv::interp::ParamFileError| input(format!("{key}: {}", e.message()));
        let normals =
            normals.transpose()?.map(|j| params::parse_normals(&j, n)).transpose().map_err(|e| param("normals", e))?;
        let subset = match subset {
            None => None,
            Some(list) => Some(
                list.into_iter()
                    .map(|v| {
                        u32::try_from(v).map_err(|_| {
                            input(format!("subset: vertex {v} does not exist (the mesh has {n} vertices)"))
                        })
                    })
                    .collect::<Result<Vec<u32>, _>>()?,
            ),
        };
        let options: MethodOptions = match method {
            ZhengCai => {
                let handles = handles
                    .transpose()?
                    .map(|j| params::parse_handles(&j, n))
                    .transpose()
                    .map_err(|e| param("handles", e))?;
                ZhengCaiOptions::default()
                    .with_ite_max(ite_max.unwrap_or(5))
                    .with_eps(eps.unwrap_or(0.003))
                    .with_normals(normals)
                    .with_handles(handles)
                    .into()
            }
            FanChengLai => FanChengLaiOptions::default().with_shape(shape.unwrap_or_default()).into(),
            DengWang => DengWangOptions::default()
                .with_mu(mu.unwrap_or(subdiv::interp::deng_wang::DEFAULT_MU))
                .with_beta(beta(beta_name)?)
                .with_normals(normals)
                .into(),
            DengMa => DengMaOptions::default().with_tension(tension.unwrap_or_default()).into(),
            Fair => {
                let scheme = match scheme.as_deref().map(|s| s.to_ascii_lowercase().replace('_', "-")) {
                    None => Scheme::CatmullClark,
                    Some(s) if s == "loop" => Scheme::Loop(beta(beta_name)?),
                    Some(s) => match s.as_str() {
                        "cc" => Scheme::CatmullClark,
                        "ds" => Scheme::DooSabin,
                        s => s.parse::<Scheme>().map_err(|e| input(format!("scheme: {e}")))?,
                    },
                };
                if beta_given && !matches!(scheme, Scheme::Loop(_)) {
                    return misuse("beta", "fair with scheme loop");
                }
                FairOptions::default()
                    .with_scheme(scheme)
                    .map_err(|e| input(format!("scheme: {e}")))?
                    .with_refine(refine.unwrap_or(subdiv::interp::fair::DEFAULT_REFINE))
                    .with_fairness_weight(fairness_weight)
                    .into()
            }
            method => MethodOptions::new(method),
        };
        let solver = match solver {
            "auto" => SolverChoice::Auto,
            name => SolverChoice::Use(name.parse().map_err(|_| input(format!("solver: unknown solver '{name}'")))?),
        };
        Ok(options
            .with_tol(tol)
            .with_max_iter(max_iter.unwrap_or(subdiv::interp::DEFAULT_MAX_ITER))
            .with_solver(solver)
            .with_surface(surface?)
            .with_subset(subset)?)
    })())
}
