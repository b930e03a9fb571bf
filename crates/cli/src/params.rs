//! Parameter files of `subdiv interpolate`: subsets, normals, shape handles,
//! per-face shape parameters. Text (one item per line, `#` comments) or JSON;
//! errors name the file and line.

use anyhow::{anyhow, bail, Context, Result};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;
use subdiv_mesh::{DVec3, Mesh};

fn read(path: &Path) -> Result<String> {
    std::fs::read_to_string(path).with_context(|| format!("{}: cannot read", path.display()))
}

fn is_json(text: &str) -> bool {
    matches!(text.trim_start().chars().next(), Some('[' | '{'))
}

fn json(path: &Path, text: &str) -> Result<Value> {
    serde_json::from_str(text).map_err(|e| anyhow!("{}:{}: invalid JSON: {e}", path.display(), e.line()))
}

/// Numeric lines of a text file: `(line number, fields)`, comments and blank lines skipped.
fn text_rows(text: &str) -> impl Iterator<Item = (usize, Vec<&str>)> {
    text.lines().enumerate().filter_map(|(i, line)| {
        let line = line.split('#').next().unwrap_or("").trim();
        (!line.is_empty())
            .then(|| (i + 1, line.split(|c: char| c.is_whitespace() || c == ',').filter(|s| !s.is_empty()).collect()))
    })
}

fn vertex(path: &Path, line: usize, field: &str, n: usize) -> Result<u32> {
    let v: u32 = field.parse().map_err(|_| anyhow!("{}:{line}: '{field}' is not a vertex index", path.display()))?;
    if v as usize >= n {
        bail!("{}:{line}: vertex {v} does not exist (the mesh has {n} vertices, 0-based)", path.display());
    }
    Ok(v)
}

fn number(path: &Path, line: usize, field: &str) -> Result<f64> {
    let x: f64 = field.parse().map_err(|_| anyhow!("{}:{line}: '{field}' is not a number", path.display()))?;
    if !x.is_finite() {
        bail!("{}:{line}: '{field}' is not finite", path.display());
    }
    Ok(x)
}

/// Vertex indices (0-based): whitespace/comma separated, or a JSON array.
pub fn subset(path: &Path, n: usize) -> Result<Vec<u32>> {
    let text = read(path)?;
    if is_json(&text) {
        let Value::Array(items) = json(path, &text)? else {
            bail!("{}: expected a JSON array of vertex indices", path.display())
        };
        return items
            .iter()
            .map(|x| {
                let v = x.as_u64().ok_or_else(|| anyhow!("{}: '{x}' is not a vertex index", path.display()))?;
                vertex(path, 1, &v.to_string(), n)
            })
            .collect();
    }
    let mut out = Vec::new();
    for (line, fields) in text_rows(&text) {
        for f in fields {
            out.push(vertex(path, line, f, n)?);
        }
    }
    Ok(out)
}

/// Per-vertex values from lines `i x…` (`width` numbers) or JSON `{"i": x | [x…]}`.
fn per_vertex(path: &Path, n: usize, width: usize) -> Result<BTreeMap<u32, Vec<f64>>> {
    let text = read(path)?;
    let mut out = BTreeMap::new();
    if is_json(&text) {
        let Value::Object(map) = json(path, &text)? else {
            bail!("{}: expected a JSON object {{\"vertex\": value}}", path.display())
        };
        for (k, v) in map {
            let i = vertex(path, 1, &k, n)?;
            let values: Vec<f64> = match v {
                Value::Number(x) => vec![x.as_f64().unwrap_or(f64::NAN)],
                Value::Array(xs) => xs.iter().map(|x| x.as_f64().unwrap_or(f64::NAN)).collect(),
                other => bail!("{}: vertex {k}: '{other}' is not a number or list", path.display()),
            };
            if values.len() != width || values.iter().any(|x| !x.is_finite()) {
                bail!("{}: vertex {k}: expected {width} finite numbers", path.display());
            }
            out.insert(i, values);
        }
        return Ok(out);
    }
    for (line, fields) in text_rows(&text) {
        if fields.len() != width + 1 {
            bail!("{}:{line}: expected a vertex index and {width} numbers", path.display());
        }
        let i = vertex(path, line, fields[0], n)?;
        let values = fields[1..].iter().map(|f| number(path, line, f)).collect::<Result<Vec<_>>>()?;
        out.insert(i, values);
    }
    Ok(out)
}

/// Per-vertex normals (`i nx ny nz`); zero vectors are rejected.
pub fn normals(path: &Path, n: usize) -> Result<Vec<Option<DVec3>>> {
    let mut out = vec![None; n];
    for (i, v) in per_vertex(path, n, 3)? {
        let normal = DVec3::new(v[0], v[1], v[2]);
        if normal.length() == 0.0 {
            bail!("{}: vertex {i}: the normal is zero", path.display());
        }
        out[i as usize] = Some(normal.normalize());
    }
    Ok(out)
}

/// Per-vertex shape handles (`i S`), default 1; S must be positive.
pub fn handles(path: &Path, n: usize) -> Result<Vec<f64>> {
    let mut out = vec![1.0; n];
    for (i, v) in per_vertex(path, n, 1)? {
        if v[0] <= 0.0 {
            bail!("{}: vertex {i}: shape handle {} must be positive", path.display(), v[0]);
        }
        out[i as usize] = v[0];
    }
    Ok(out)
}

/// Per-face λ from `{"default": λ, "faces": {"f": λ}, "groups": {"name": λ}}`
/// (groups are the mesh file's OBJ `g`/`o` names; faces override groups).
pub fn shape_file(path: &Path, mesh: &Mesh) -> Result<Vec<f64>> {
    let text = read(path)?;
    let value = json(path, &text)?;
    let nf = mesh.topology().face_count();
    let get = |v: &Value, what: &str| -> Result<f64> {
        v.as_f64().filter(|x| x.is_finite()).ok_or_else(|| anyhow!("{}: {what}: '{v}' is not a number", path.display()))
    };
    let default = match value.get("default") {
        Some(v) => get(v, "default")?,
        None => 0.5,
    };
    let mut lambdas = vec![default; nf];
    if let Some(groups) = value.get("groups") {
        let Value::Object(groups) = groups else { bail!("{}: \"groups\" must be an object", path.display()) };
        let g = mesh.groups();
        for (name, v) in groups {
            let lambda = get(v, &format!("group {name}"))?;
            let Some(id) = g.names.iter().position(|n| n == name) else {
                bail!("{}: group '{name}' is not in the mesh (it has: {})", path.display(), g.names.join(", "))
            };
            for (f, &gid) in g.face_group.iter().enumerate() {
                if gid as usize == id {
                    lambdas[f] = lambda;
                }
            }
        }
    }
    if let Some(faces) = value.get("faces") {
        let Value::Object(faces) = faces else { bail!("{}: \"faces\" must be an object", path.display()) };
        for (k, v) in faces {
            let f: usize = k.parse().map_err(|_| anyhow!("{}: '{k}' is not a face index", path.display()))?;
            if f >= nf {
                bail!("{}: face {f} does not exist (the mesh has {nf} faces)", path.display());
            }
            lambdas[f] = get(v, &format!("face {f}"))?;
        }
    }
    Ok(lambdas)
}
