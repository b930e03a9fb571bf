//! Keyword arguments → the one pipeline's options (`subdiv::job`): the keywords are put into a
//! JSON object by their names and parsed by `Command::from_json`, the parser of the command
//! line's flags and of the batch, so the defaults, the checks and the messages are theirs.

use crate::errors::{input, Error};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use serde_json::{Map, Value};
use subdiv::job::{Command, InterpolateOptions, SubdivideOptions};

/// The keyword arguments of a call, taken one by one; what is left at the
/// end is an unexpected keyword (a `TypeError`, as Python's own).
pub struct Kwargs<'py> {
    pub(crate) function: &'static str,
    pub(crate) dict: Option<Bound<'py, PyDict>>,
}

impl<'py> Kwargs<'py> {
    /// The keywords of `function`.
    pub fn new(function: &'static str, dict: Option<Bound<'py, PyDict>>) -> Self {
        Self { function, dict }
    }
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

/// A Python value as JSON: `None`, `bool`, `int`, `float`, `str`, `os.PathLike`, and lists,
/// tuples, NumPy arrays (`tolist()`) and dicts of them.
fn to_json(key: &str, value: &Bound<'_, PyAny>) -> Result<Value, Error> {
    if value.is_none() {
        return Ok(Value::Null);
    }
    if let Ok(b) = value.extract::<bool>() {
        if value.is_instance_of::<pyo3::types::PyBool>() {
            return Ok(Value::Bool(b));
        }
    }
    if value.is_instance_of::<pyo3::types::PyInt>() {
        if let Ok(i) = value.extract::<i64>() {
            return Ok(Value::from(i));
        }
        if let Ok(u) = value.extract::<u64>() {
            return Ok(Value::from(u));
        }
    }
    if let Ok(x) = value.extract::<f64>() {
        if !value.is_instance_of::<pyo3::types::PyString>() {
            return serde_json::Number::from_f64(x)
                .map(Value::Number)
                .ok_or_else(|| input(format!("{key}: {x} is not a finite number")));
        }
    }
    if let Ok(s) = value.extract::<String>() {
        return Ok(Value::String(s));
    }
    if let Ok(p) = value.extract::<std::path::PathBuf>() {
        return Ok(Value::String(p.to_string_lossy().into_owned()));
    }
    if let Ok(dict) = value.cast::<PyDict>() {
        let mut map = Map::new();
        for (k, v) in dict.iter() {
            map.insert(k.str().map_err(|_| input(format!("{key}: a key is no text")))?.to_string(), to_json(key, &v)?);
        }
        return Ok(Value::Object(map));
    }
    let listed = if value.hasattr("tolist").unwrap_or(false) { value.call_method0("tolist").ok() } else { None };
    let seq = listed.as_ref().unwrap_or(value);
    if seq.is_instance_of::<PyList>() || seq.is_instance_of::<PyTuple>() {
        let items: Vec<Bound<'_, PyAny>> = seq.extract().map_err(|_| input(format!("{key}: not a sequence")))?;
        return items.iter().map(|v| to_json(key, v)).collect::<Result<Vec<_>, _>>().map(Value::Array);
    }
    if listed.is_some() {
        return to_json(key, seq);
    }
    Err(input(format!(
        "{key}: {} values are not taken",
        value.get_type().name().map(|n| n.to_string()).unwrap_or_default()
    )))
}

/// The keyword arguments as the options' JSON object: `normals` and `handles` through their
/// per-vertex form (`NaN` rows: none), the others as they are. Keywords about files written or
/// read (levels, format, tags, feature_angle, max_memory) are no options of a call on a mesh in
/// memory: `TypeError`, as Python's own for an unexpected keyword.
fn options_json(kw: &mut Kwargs<'_>, map: &mut Map<String, Value>) -> PyResult<Result<(), Error>> {
    let Some(dict) = kw.dict.take() else { return Ok(Ok(())) };
    for (key, value) in dict.iter() {
        let key: String = key.extract()?;
        if ["levels", "format", "tags", "feature_angle", "max_memory", "solver_observer"].contains(&key.as_str()) {
            return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                "{}() got an unexpected keyword argument '{key}'",
                kw.function
            )));
        }
        let json = match key.as_str() {
            "normals" => per_vertex_json(&value, "normals", 3)?.and_then(|t| parse_json(&t)),
            "handles" => per_vertex_json(&value, "handles", 1)?.and_then(|t| parse_json(&t)),
            _ => to_json(&key, &value),
        };
        match json {
            Ok(Value::Null) => {}
            Ok(v) => {
                map.insert(key, v);
            }
            Err(e) => return Ok(Err(e)),
        }
    }
    Ok(Ok(()))
}

fn parse_json(text: &str) -> Result<Value, Error> {
    serde_json::from_str(text).map_err(|e| input(e.to_string()))
}

/// The options of `interpolate(mesh, method, tol, solver, max_iter, **options)`: the job's
/// [`InterpolateOptions`], parsed and checked as the command line's.
pub fn interpolate(
    method: &str,
    tol: f64,
    solver: &str,
    max_iter: Option<usize>,
    kw: &mut Kwargs<'_>,
) -> PyResult<Result<InterpolateOptions, Error>> {
    let mut map = Map::new();
    map.insert("method".into(), Value::String(method.to_string()));
    map.insert("tol".into(), serde_json::Number::from_f64(tol).map_or(Value::Null, Value::Number));
    map.insert("solver".into(), Value::String(solver.to_string()));
    if let Some(max_iter) = max_iter {
        map.insert("max_iter".into(), Value::from(max_iter));
    }
    if let Err(e) = options_json(kw, &mut map)? {
        return Ok(Err(e));
    }
    if !tol.is_finite() {
        return Ok(Err(input(format!("--tol must be positive, got {tol}"))));
    }
    match InterpolateOptions::from_json(&Value::Object(map)) {
        Ok(options) => Ok(Ok(options)),
        Err(e) => unexpected_keyword(kw.function, e).map(Err),
    }
}

/// A keyword no option has is Python's `TypeError` ("got an unexpected keyword argument"), as
/// for any function; every other refusal is the job's error.
fn unexpected_keyword(function: &str, e: subdiv::job::JobError) -> PyResult<Error> {
    if let Some(name) = e.message.strip_prefix("unknown option `").and_then(|rest| rest.split('`').next()) {
        return Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "{function}() got an unexpected keyword argument '{name}'"
        )));
    }
    Ok(e.into())
}

/// The options of `subdivide(mesh, scheme, levels, limit, **options)`: the job's
/// [`SubdivideOptions`], parsed and checked as the command line's.
pub fn subdivide(
    scheme: &str,
    levels: usize,
    limit: bool,
    kw: &mut Kwargs<'_>,
) -> PyResult<Result<SubdivideOptions, Error>> {
    let mut map = Map::new();
    map.insert("scheme".into(), Value::String(scheme.to_ascii_lowercase().replace('_', "-")));
    map.insert("levels".into(), Value::from(levels));
    map.insert("limit".into(), Value::Bool(limit));
    if let Err(e) = options_json(kw, &mut map)? {
        return Ok(Err(e));
    }
    match Command::from_json("subdivide", &Value::Object(map)) {
        Ok(Command::Subdivide(o)) => Ok(Ok(o)),
        Ok(_) => unreachable!("a subdivide command parses as one"),
        Err(e) => unexpected_keyword(kw.function, e).map(Err),
    }
}
