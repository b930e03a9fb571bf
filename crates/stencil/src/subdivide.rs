//! Multi-level subdivision: topology once, geometry as one sparse product per level.
//!
//! Geometry is computed on positions scaled by the normalising power of two
//! and scaled back ([`crate::normalized`]): exact, so ordinary meshes give the
//! same bits, and free of overflow and underflow for coordinates near
//! ±1e308 or 1e-300. [`subdivide`] and [`SubdivisionPlan::subdivide`] then
//! check that every output coordinate is a finite f64
//! ([`StencilError::NotRepresentable`] otherwise).

use crate::normalized::{map_back, normalize};
use crate::{apply, catmull_clark, deng_ma, doo_sabin, loop_subdivision, SparseMatrix, StencilError};
use glam::DVec3;
use subdiv_mesh::refine::{quad_split, DualProvenance};
use subdiv_mesh::{Mesh, PowerOfTwoScale, Topology};
use subdiv_rules::deng_ma::Tension;
use subdiv_rules::LoopBeta;

/// A subdivision scheme with the options that change its surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scheme {
    /// Catmull-Clark (any polygons; quads after one step).
    CatmullClark,
    /// Loop (triangles only), with Warren's or Loop's β.
    Loop(LoopBeta),
    /// Standard Doo-Sabin (any polygons).
    DooSabin,
    /// Deng-Ma's interpolatory scheme (any polygons, open or closed: 4-point
    /// boundary curves), global or variable tension.
    DengMa(Tension),
}

impl Scheme {
    /// Short name, as on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Scheme::CatmullClark => "catmull-clark",
            Scheme::Loop(_) => "loop",
            Scheme::DooSabin => "doo-sabin",
            Scheme::DengMa(_) => "deng-ma",
        }
    }
}

/// One level of a plan: the refined connectivity and the operator producing
/// its positions from the previous level's.
#[derive(Clone, Debug)]
pub struct Refinement {
    /// Connectivity after this level.
    pub topology: Topology,
    /// New × old stencil (P_{k+1} = R·P_k); `None` for Deng-Ma, evaluated
    /// geometrically (its variable tension is nonlinear in the positions; for a
    /// global ω, `deng_ma::stencil` gives the matrix on request).
    pub stencil: Option<SparseMatrix>,
    /// Doo-Sabin provenance of the new faces and vertices.
    pub dual: Option<DualProvenance>,
}

/// The topology of `levels` steps of a scheme, computed once; [`Self::apply`]
/// maps any positions through them.
#[derive(Clone, Debug)]
pub struct SubdivisionPlan {
    scheme: Scheme,
    base: Topology,
    levels: Vec<Refinement>,
}

/// Largest element count a refined mesh may have (ids are `u32`).
const MAX_ELEMENTS: usize = u32::MAX as usize - 1;

fn check_size(t: &Topology, scheme: Scheme) -> Result<(), StencilError> {
    let (v, f, e, h) = (t.vertex_count(), t.face_count(), t.edge_count(), t.half_edge_count());
    let (new_vertices, new_corners) = match scheme {
        Scheme::CatmullClark | Scheme::DengMa(_) => (v + f + e, 4 * h),
        Scheme::Loop(_) => (v + e, 12 * f),
        Scheme::DooSabin => (h + 2 * e, 2 * h + 4 * e),
    };
    if new_vertices.max(new_corners) > MAX_ELEMENTS {
        return Err(StencilError::TooLarge);
    }
    Ok(())
}

/// One level of `scheme` on `current`: the refined connectivity and its stencil.
fn refine_level(current: &Topology, scheme: Scheme) -> Result<Refinement, StencilError> {
    check_size(current, scheme)?;
    Ok(match scheme {
        // The refined connectivity and the stencil depend on the coarse
        // topology only: build them on both cores at once.
        Scheme::CatmullClark => {
            let (topology, stencil) =
                rayon::join(|| quad_split(current), || catmull_clark::refinement_stencil(current));
            Refinement { topology, stencil: Some(stencil), dual: None }
        }
        Scheme::Loop(beta) => {
            let (topology, stencil) = rayon::join(
                || subdiv_mesh::refine::triangle_split(current),
                || loop_subdivision::refinement_stencil(current, beta),
            );
            let stencil = stencil?;
            let topology = topology.expect("the stencil accepted the mesh, so it is a triangle mesh");
            Refinement { topology, stencil: Some(stencil), dual: None }
        }
        Scheme::DooSabin => {
            let ((topology, dual), stencil) = rayon::join(
                || subdiv_mesh::refine::dual_split(current),
                || doo_sabin::refinement_stencil(current, doo_sabin::CornerRule::Standard),
            );
            Refinement { topology, stencil: Some(stencil?), dual: Some(dual) }
        }
        Scheme::DengMa(tension) => {
            deng_ma::check_tension(tension)?;
            // Evaluated geometrically even for a global ω: its matrix
            // (`deng_ma::stencil`) is dense-ish (every moved vertex
            // expands over all corners around its vertex) and measured
            // 3-4× slower to build and apply than the direct step.
            Refinement { topology: quad_split(current), stencil: None, dual: None }
        }
    })
}

/// Positions after `level`, from the positions on its coarse connectivity.
fn step(level: &Refinement, scheme: Scheme, coarse: &Topology, positions: &[DVec3]) -> Vec<DVec3> {
    match (&level.stencil, scheme) {
        (Some(r), _) => apply(r, positions),
        (None, Scheme::DengMa(tension)) => {
            deng_ma::step_positions(coarse, positions, tension).expect("the tension was checked when planning")
        }
        (None, _) => unreachable!("only Deng-Ma has no stencil"),
    }
}

/// The limit points of the vertices of `t` (a mesh refined at least once by
/// `scheme`, or any mesh for the primal schemes); `None` for Deng-Ma.
fn limit_points_of(t: &Topology, scheme: Scheme, positions: &[DVec3]) -> Option<Vec<DVec3>> {
    match scheme {
        Scheme::CatmullClark => Some(catmull_clark::limit_points(t, positions)),
        Scheme::Loop(beta) => {
            Some(loop_subdivision::limit_points(t, beta, positions).expect("Loop levels stay triangular"))
        }
        Scheme::DooSabin => Some(doo_sabin::limit_points(t, positions)),
        Scheme::DengMa(_) => None,
    }
}

/// Maps `positions` (computed on `input` scaled by `scale`) back and checks
/// that every coordinate is a finite f64. When `copies_input`, the first
/// positions are input vertices by construction (zero levels without limit;
/// the old vertices of the interpolatory Deng-Ma step) and are copied from
/// `input` instead, so they stay bit for bit even where their scaled copy
/// was subnormal.
fn map_back_checked(
    scheme: Scheme,
    scale: PowerOfTwoScale,
    positions: &mut [DVec3],
    input: &[DVec3],
    copies_input: bool,
) -> Result<(), StencilError> {
    let kept = if copies_input { input.len() } else { 0 };
    positions[..kept].copy_from_slice(&input[..kept]);
    let mapped = map_back(scale.inverse(), &mut positions[kept..]);
    let reason = match (input.iter().position(|p| !p.is_finite()), mapped) {
        (Some(v), _) => format!("input vertex {v} has a non-finite coordinate ({})", input[v]),
        (None, Err(mut out)) => {
            out.index += kept;
            format!("the refined surface leaves the range of f64: {out}")
        }
        (None, Ok(())) => return Ok(()),
    };
    Err(StencilError::NotRepresentable { scheme: scheme.name(), reason })
}

impl SubdivisionPlan {
    /// Plans `levels` steps of `scheme` on `t`. Fails when the scheme cannot
    /// take the mesh (Loop on non-triangles), on a bad parameter, or when the
    /// result would not fit `u32` ids.
    pub fn new(t: &Topology, scheme: Scheme, levels: usize) -> Result<Self, StencilError> {
        // Also with 0 levels: the plan's limit points need triangles.
        if let Scheme::Loop(_) = scheme {
            loop_subdivision::require_triangles(t)?;
        }
        let mut out: Vec<Refinement> = Vec::with_capacity(levels);
        for _ in 0..levels {
            let level = refine_level(out.last().map_or(t, |r| &r.topology), scheme)?;
            out.push(level);
        }
        Ok(Self { scheme, base: t.clone(), levels: out })
    }

    /// The scheme.
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }
    /// The levels, coarse to fine.
    pub fn levels(&self) -> &[Refinement] {
        &self.levels
    }
    /// The input connectivity.
    pub fn base(&self) -> &Topology {
        &self.base
    }
    /// Connectivity after the last level (the input for zero levels).
    pub fn topology(&self) -> &Topology {
        self.levels.last().map_or(&self.base, |r| &r.topology)
    }

    /// Positions after every level, from positions of the input's vertices
    /// (computed on normalised positions and scaled back, module docs; a
    /// coordinate beyond the range of f64 comes back as ±inf —
    /// [`Self::subdivide`] checks for that).
    ///
    /// # Panics
    /// If `positions.len()` differs from the input's vertex count (a caller bug).
    pub fn apply(&self, positions: &[DVec3]) -> Vec<DVec3> {
        assert_eq!(positions.len(), self.base.vertex_count(), "one position per input vertex");
        let (scale, scaled) = normalize(positions);
        let mut current = self.apply_unscaled(scaled);
        scale.inverse().apply_points(&mut current);
        current
    }

    /// The levels applied to `current` as it is.
    fn apply_unscaled(&self, mut current: Vec<DVec3>) -> Vec<DVec3> {
        let mut coarse = &self.base;
        for level in &self.levels {
            current = step(level, self.scheme, coarse, &current);
            coarse = &level.topology;
        }
        current
    }

    /// Limit stencil of the final level's vertices (`None` for Deng-Ma,
    /// an interpolatory scheme whose refined vertices already lie on the surface).
    pub fn limit_stencil(&self) -> Option<SparseMatrix> {
        let t = self.topology();
        match self.scheme {
            Scheme::CatmullClark => Some(catmull_clark::limit_stencil(t)),
            Scheme::Loop(beta) => Some(loop_subdivision::limit_stencil(t, beta).expect("Loop levels stay triangular")),
            Scheme::DooSabin => Some(doo_sabin::limit_stencil(t)),
            Scheme::DengMa(_) => None,
        }
    }

    /// The limit points of the final level's vertices from their positions
    /// (`apply(&self.limit_stencil()?, positions)` up to round-off, without
    /// building the stencil; `None` for Deng-Ma). Computed on normalised
    /// positions and scaled back, as [`Self::apply`].
    ///
    /// # Panics
    /// If `positions.len()` differs from the final vertex count (a caller bug).
    pub fn limit_points(&self, positions: &[DVec3]) -> Option<Vec<DVec3>> {
        let (scale, scaled) = normalize(positions);
        let mut limits = limit_points_of(self.topology(), self.scheme, &scaled)?;
        scale.inverse().apply_points(&mut limits);
        Some(limits)
    }

    /// Subdivides a mesh: positions after every level, moved to their limit
    /// positions when `limit` is set and the scheme has a limit mask.
    ///
    /// # Errors
    /// [`StencilError::NotRepresentable`] when an output coordinate is not a
    /// finite f64 (the surface leaves the range of f64).
    ///
    /// # Panics
    /// If `mesh` does not have the plan's input vertex count (a caller bug).
    pub fn subdivide(&self, mesh: &Mesh, limit: bool) -> Result<Mesh, StencilError> {
        assert_eq!(mesh.positions().len(), self.base.vertex_count(), "one position per input vertex");
        let (scale, scaled) = normalize(mesh.positions());
        let positions = self.apply_unscaled(scaled);
        let mut positions =
            limit.then(|| limit_points_of(self.topology(), self.scheme, &positions)).flatten().unwrap_or(positions);
        let copies_input = copies_input(self.scheme, self.levels.len(), limit);
        map_back_checked(self.scheme, scale, &mut positions, mesh.positions(), copies_input)?;
        Ok(Mesh::from_topology(self.topology().clone(), positions))
    }
}

/// Whether the first output positions are the input's vertices themselves:
/// after zero levels without limit, or Deng-Ma (whose old vertices stay).
fn copies_input(scheme: Scheme, levels: usize, limit: bool) -> bool {
    matches!(scheme, Scheme::DengMa(_)) || (levels == 0 && !limit)
}

/// `levels` steps of `scheme` applied to `mesh`, moved to the limit positions
/// when `limit` is set and the scheme has a limit mask — the mesh of
/// [`SubdivisionPlan::subdivide`] up to round-off, for a
/// single use: each level is refined and applied in turn and dropped once
/// the next exists, so only two connectivities are held at a time, and no
/// stencil is built: the points are evaluated directly
/// ([`doo_sabin::first_step`] face by face, [`catmull_clark::step_points`],
/// [`loop_subdivision::step_points`] row by row); the final connectivity is
/// moved into the mesh rather than copied.
///
/// Computed on normalised positions and scaled back (module docs).
///
/// # Errors
/// As [`SubdivisionPlan::new`]; [`StencilError::NotRepresentable`] when an
/// output coordinate is not a finite f64 (the surface leaves the range of f64).
pub fn subdivide(mesh: &Mesh, scheme: Scheme, levels: usize, limit: bool) -> Result<Mesh, StencilError> {
    // Also with 0 levels and limit: Loop's limit mask needs triangles.
    if let Scheme::Loop(_) = scheme {
        loop_subdivision::require_triangles(mesh.topology())?;
    }
    let mut fine: Option<Topology> = None; // None: still the input's connectivity
    let (scale, mut positions) = normalize(mesh.positions());
    for _ in 0..levels {
        let coarse = fine.as_ref().unwrap_or(mesh.topology());
        check_size(coarse, scheme)?;
        // The refined connectivity on one core, the points on the other.
        let (topology, next) = match scheme {
            Scheme::DooSabin => {
                let ((topology, _), next) = rayon::join(
                    || subdiv_mesh::refine::dual_split(coarse),
                    || doo_sabin::first_step(coarse, doo_sabin::CornerRule::Standard, &positions),
                );
                (topology, next?)
            }
            Scheme::CatmullClark => {
                rayon::join(|| quad_split(coarse), || catmull_clark::step_points(coarse, &positions))
            }
            Scheme::Loop(beta) => {
                let (topology, next) = rayon::join(
                    || subdiv_mesh::refine::triangle_split(coarse),
                    || loop_subdivision::step_points(coarse, beta, &positions),
                );
                let next = next?;
                (topology.expect("the step accepted the mesh, so it is a triangle mesh"), next)
            }
            Scheme::DengMa(_) => {
                let level = refine_level(coarse, scheme)?;
                let next = step(&level, scheme, coarse, &positions);
                (level.topology, next)
            }
        };
        positions = next;
        fine = Some(topology);
    }
    let t = fine.as_ref().unwrap_or(mesh.topology());
    let mut positions = limit.then(|| limit_points_of(t, scheme, &positions)).flatten().unwrap_or(positions);
    map_back_checked(scheme, scale, &mut positions, mesh.positions(), copies_input(scheme, levels, limit))?;
    Ok(match fine {
        Some(t) => Mesh::from_topology(t, positions),
        None => mesh.with_positions(positions),
    })
}
