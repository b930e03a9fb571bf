//! Which method takes which mesh: the structural preconditions of every
//! method in one place, so that a method's refusal, the methods it
//! recommends instead, and `subdiv info`'s advice all come from the same
//! checks.
//!
//! | method | takes | refuses |
//! |---|---|---|
//! | `nasri`, `zheng-cai`, `fan-cheng-lai` | every valid mesh: any polygons, open or closed, valence 2 | — |
//! | `cheng` | every valid mesh (valence 2: MINRES on the indefinite A) | data outside the range of a singular A: a closed component with only valence-3 vertices and a bipartite vertex graph (the cube) whose checkerboard c has Σ c_v P_v ≠ 0 (where c is also A's left null vector; with a dart there, the solve decides) |
//! | `cheng --scheme loop` | triangles, open or closed, every tag | other polygons |
//! | `cheng --scheme sqrt3` | triangles, open or closed, corner tags on boundary vertices | other polygons, crease and other vertex tags, interior vertices of valence 2 |
//! | `deng-wang` | triangles; other polygons are triangulated inside the method | a polygon with no valid triangulation over its own corners |
//! | `deng-ma` | every valid mesh, open or closed | — |
//! | `fair` (Catmull-Clark, refine 1) | every valid mesh | semi-sharp creases whose limit rows share every control point (rare) |
//!
//! The checks look at the mesh with the default options (all vertices
//! interpolated, the default tolerance, the default control scheme —
//! [`Method::check_with_scheme`] takes another); options such as a solver
//! that needs a definite matrix can still be refused by the method itself.

use crate::{FairOptions, InterpError, Method, SurfaceOptions, DEFAULT_TOL};
use glam::DVec3;
use subdiv_mesh::{Mesh, PowerOfTwoScale, VertexId};
use subdiv_stencil::{catmull_clark_kernel, limit_matrix_catmull_clark_sharp, LimitMatrix, Scheme, StencilError};

impl Method {
    /// Whether this method interpolates every vertex of `mesh` with its
    /// default options: `Err(reason)` says why not (module table).
    pub fn check(self, mesh: &Mesh) -> Result<(), String> {
        non_manifold(mesh, self, Scheme::CatmullClark).map_err(|refusal| refusal.reason)?;
        match self {
            Method::Nasri | Method::ZhengCai | Method::FanChengLai | Method::DengMa => Ok(()),
            Method::Cheng => cheng_range(mesh, DEFAULT_TOL),
            Method::DengWang => subdiv_mesh::check_triangulation(mesh).map_err(|e| e.to_string()),
            // Catmull-Clark, refine 1: every private pivot exists on untagged
            // meshes; semi-sharp tags that spread the limit rows are refused.
            Method::Fair => Ok(()),
        }
    }

    /// [`Self::check`] with the control scheme `scheme` (`--scheme`) for the
    /// methods that take one: `cheng` (Catmull-Clark, Loop, √3; module
    /// table) and `fair` (Catmull-Clark, Loop on triangles, Doo-Sabin); a
    /// scheme the method refuses is an `Err` too. The other methods have a
    /// scheme of their own and ignore `scheme`. With Catmull-Clark this is
    /// [`Self::check`].
    ///
    /// ```
    /// use subdiv_interp::{Method, Scheme};
    /// let cube = subdiv_mesh::shapes::cube();
    /// assert!(Method::Cheng.check_with_scheme(&cube, Scheme::CatmullClark).is_ok());
    /// assert!(Method::Cheng.check_with_scheme(&cube, Scheme::Sqrt3).unwrap_err().contains("triangles"));
    /// assert!(Method::Cheng.check_with_scheme(&subdiv_mesh::shapes::icosahedron(), Scheme::Sqrt3).is_ok());
    /// assert!(Method::Cheng.check_with_scheme(&cube, Scheme::DooSabin).is_err());
    /// ```
    pub fn check_with_scheme(self, mesh: &Mesh, scheme: Scheme) -> Result<(), String> {
        non_manifold(mesh, self, scheme).map_err(|refusal| refusal.reason)?;
        match self {
            Method::Cheng => {
                cheng_scheme(scheme)?;
                match scheme {
                    Scheme::CatmullClark => self.check(mesh),
                    Scheme::Loop(_) | Scheme::Sqrt3 | Scheme::DooSabin | Scheme::DengMa(_) => {
                        cheng_mesh(mesh, scheme).map_err(|refusal| refusal.reason)
                    }
                }
            }
            Method::Fair => {
                FairOptions::default().with_scheme(scheme).map_err(|e| e.to_string())?;
                match triangles(mesh, scheme) {
                    Err(refusal) => Err(refusal.reason),
                    Ok(()) => self.check(mesh),
                }
            }
            Method::Nasri | Method::ZhengCai | Method::FanChengLai | Method::DengWang | Method::DengMa => {
                self.check(mesh)
            }
        }
    }
}

/// Whether `cheng` takes `scheme` as its control scheme: those whose limit
/// points are rows of a matrix over the control mesh's own vertices
/// (`cheng` module docs, "Other control schemes"); `Err(reason)` names the
/// methods for the others.
pub(crate) fn cheng_scheme(scheme: Scheme) -> Result<(), String> {
    let takes = "cheng takes catmull-clark, loop and sqrt3 (the schemes whose limit points are rows of a matrix over \
                 the control mesh's vertices)";
    match scheme {
        Scheme::CatmullClark | Scheme::Loop(_) | Scheme::Sqrt3 => Ok(()),
        Scheme::DooSabin => Err(format!(
            "{takes}; doo-sabin's limit points are face centroids of the refined mesh: use --method nasri (or \
             zheng-cai, fan-cheng-lai)"
        )),
        Scheme::DengMa(_) => Err(format!("{takes}; deng-ma interpolates by itself: use --method deng-ma")),
    }
}

/// Why a method does not take a mesh, and what does.
#[derive(Debug)]
pub(crate) struct Refusal {
    /// What is wrong with the mesh.
    pub reason: String,
    /// What works instead.
    pub suggestion: String,
}

/// Whether `method` (with control scheme `scheme`, for the methods that
/// take one) takes a non-manifold mesh ([`subdiv_mesh::nonmanifold`]): the
/// methods whose control mesh is the input's topology under Catmull-Clark or
/// Loop (`cheng`, `fair`), whose rules OpenSubdiv defines on non-manifold
/// meshes (infinitely sharp non-manifold edges and vertices). The others
/// build their control mesh by a split of their own (Doo-Sabin's dual,
/// Deng-Wang's triangulation, Deng-Ma's tension rules, √3's flips), which
/// no evaluator defines there.
pub(crate) fn non_manifold(mesh: &Mesh, method: Method, scheme: Scheme) -> Result<(), Refusal> {
    let Some(report) = mesh.non_manifold() else {
        return Ok(());
    };
    let takes =
        matches!(method, Method::Cheng | Method::Fair) && matches!(scheme, Scheme::CatmullClark | Scheme::Loop(_));
    if takes {
        return Ok(());
    }
    let with = match method {
        Method::Cheng | Method::Fair => format!("--scheme {scheme}"),
        other => format!("--method {other}"),
    };
    Err(Refusal {
        reason: format!(
            "the mesh is non-manifold ({} edges, {} vertices), which {with} does not define (OpenSubdiv's rules              for non-manifold meshes are Catmull-Clark's and Loop's)",
            report.edges.len(),
            report.vertices.len()
        ),
        suggestion: "use --method cheng or --method fair (Catmull-Clark or Loop)".into(),
    })
}

/// The triangle requirement of a triangles-only scheme
/// ([`subdiv_stencil::SchemeTraits::triangles_only`]); every mesh passes for the others.
fn triangles(mesh: &Mesh, scheme: Scheme) -> Result<(), Refusal> {
    let t = mesh.topology();
    if !scheme.traits().triangles_only {
        return Ok(());
    }
    match t.face_ids().find(|&f| t.face_size(f) != 3) {
        None => Ok(()),
        Some(f) => Err(Refusal {
            reason: format!("the {scheme} scheme needs triangles and face {f} has {} corners", t.face_size(f)),
            suggestion: format!(
                "--method deng-wang (Loop; it triangulates the polygons itself), or triangulate the mesh first \
                 (subdiv subdivide --scheme {scheme} --triangulate --levels 0), or --scheme catmull-clark"
            ),
        }),
    }
}

/// Whether `cheng` with control scheme `scheme` takes `mesh` (module table):
/// Loop needs triangles; √3 triangles, no tags but corners on boundary
/// vertices ([`subdiv_stencil::sqrt3::check`]) and interior valence ≥ 3.
/// Catmull-Clark takes every mesh here (its range test is
/// [`cheng_range`]), and the refused schemes ([`cheng_scheme`]) every mesh
/// too: they are an invalid parameter, not a mesh's fault.
pub(crate) fn cheng_mesh(mesh: &Mesh, scheme: Scheme) -> Result<(), Refusal> {
    triangles(mesh, scheme)?;
    match scheme {
        Scheme::Sqrt3 => {
            let sharp = SurfaceOptions::default().sharpness(mesh.tags());
            subdiv_stencil::sqrt3::check(mesh.topology(), &sharp).map_err(|e| {
                let suggestion = match e {
                    StencilError::TagsNotSupported { .. } => {
                        "--scheme loop or catmull-clark (they take every crease and corner tag)"
                    }
                    _ => "--scheme loop or catmull-clark (they take every valence)",
                };
                Refusal { reason: e.to_string(), suggestion: suggestion.to_string() }
            })
        }
        Scheme::CatmullClark | Scheme::Loop(_) | Scheme::DooSabin | Scheme::DengMa(_) => Ok(()),
    }
}

/// Data outside the range of a singular Catmull-Clark A: for each closed
/// all-valence-3 bipartite component with checkerboard c (A·c = 0, D
/// constant on it) that is also a left null vector (cᵀA = 0: A symmetric
/// there), every residual r = P − A·X has c·r = c·P, so
/// max_v |r_v| ≥ |c·P| / n_c; interpolation to `tol`·d is possible only if
/// |c·P| / n_c ≤ tol·d (and then the solver finds it). A dart's exact limit
/// row breaks the symmetry (the cube with one crease edge: A·c = 0 still,
/// but the left null vector is not c); there the solve itself says whether
/// the data are in the range.
pub(crate) fn cheng_range(mesh: &Mesh, tol: f64) -> Result<(), String> {
    let built = if mesh.tags().is_empty() || catmull_clark_kernel(mesh.topology()).is_empty() {
        None
    } else {
        let sharp = SurfaceOptions::default().sharpness(mesh.tags());
        limit_matrix_catmull_clark_sharp(mesh.topology(), &sharp).ok()
    };
    let mut kernel = cheng_kernel(mesh, built.as_ref());
    if let Some(a) = &built {
        kernel.retain(|c| is_left_null(a, c));
    }
    if kernel.is_empty() {
        return Ok(());
    }
    // On positions scaled by a power of two (exact; the ratio floor/d does
    // not change), so that neither c·P nor d overflows near ±1e308.
    let scale = PowerOfTwoScale::normalizing(mesh.positions().iter().copied());
    let scaled = mesh.with_positions(scale.scaled_points(mesh.positions()));
    let d = scaled.bbox_diagonal();
    for c in kernel {
        let dot: glam::DVec3 = c.iter().map(|&(v, s)| s * scaled.position(v)).sum();
        let floor = dot.length() / c.len() as f64;
        if floor.is_nan() || floor > tol * d {
            return Err(format!(
                "the Catmull-Clark limit matrix is singular on the closed component of vertex {} (only valence-3 \
                 vertices, bipartite vertex graph) and the data are outside its range: no control mesh gets \
                 closer than {:.1e}·d",
                c[0].0,
                floor / d
            ));
        }
    }
    Ok(())
}

/// The kernel of Cheng's A that the structure gives, with the mesh's tags
/// and the default surface options: the checkerboard vectors c of
/// [`catmull_clark_kernel`] that A still annihilates. A crease vertex or a
/// corner on such a component gives a row that does not (its curve point of
/// c is ±(6 − 2)/8 ≠ 0, a corner ±1); a dart does not change the first
/// step's points of c (all 0, its crease edge's midpoint too), so the cube
/// with one crease edge is as singular as the plain cube. Tested on A itself
/// (A·c = 0 to round-off), which also covers every semi-sharp case.
pub(crate) fn cheng_kernel(mesh: &Mesh, a: Option<&LimitMatrix>) -> Vec<Vec<(VertexId, f64)>> {
    let mut kernel = catmull_clark_kernel(mesh.topology());
    if kernel.is_empty() || mesh.tags().is_empty() {
        return kernel;
    }
    let built;
    let a = match a {
        Some(a) => a,
        None => {
            let sharp = SurfaceOptions::default().sharpness(mesh.tags());
            match limit_matrix_catmull_clark_sharp(mesh.topology(), &sharp) {
                Ok(m) => {
                    built = m;
                    &built
                }
                Err(_) => return kernel,
            }
        }
    };
    kernel.retain(|c| {
        let mut x = vec![DVec3::ZERO; a.size()];
        c.iter().for_each(|&(v, s)| x[v.index()] = DVec3::splat(s));
        a.apply(&x).iter().all(|y| y.abs().max_element() <= 1e-12)
    });
    kernel
}

/// Whether the sparse vector `c` (vertex, value) is a left null vector of
/// `a`: cᵀA = 0 to round-off.
fn is_left_null(a: &LimitMatrix, c: &[(VertexId, f64)]) -> bool {
    let csr = a.to_csr();
    let mut y = vec![0.0; a.size()];
    for &(v, s) in c {
        let row = csr.outer_view(v.index()).expect("a row per vertex");
        row.iter().for_each(|(j, &w)| y[j] += s * w);
    }
    y.iter().all(|x| x.abs() <= 1e-12)
}

/// The methods other than `except` that take `mesh` ([`Method::check`]).
pub fn accepting_methods(mesh: &Mesh, except: Method) -> Vec<Method> {
    Method::ALL.into_iter().filter(|&m| m != except && m.check(mesh).is_ok()).collect()
}

/// "a, b or c" for a refusal's suggestion; "no other method" when empty.
pub(crate) fn suggestion(mesh: &Mesh, except: Method) -> String {
    let names: Vec<&str> = accepting_methods(mesh, except).into_iter().map(Method::name).collect();
    match names.as_slice() {
        [] => "no other method takes this mesh".to_string(),
        [one] => format!("{one} (it takes this mesh)"),
        [init @ .., last] => format!("{} or {last} (they take this mesh)", init.join(", ")),
    }
}

/// The refusal of `method` on `mesh` for `reason`, naming the methods that take it.
pub(crate) fn unsupported(method: Method, mesh: &Mesh, reason: String) -> InterpError {
    InterpError::UnsupportedMesh { method: method.name(), reason, suggestion: suggestion(mesh, method) }
}
