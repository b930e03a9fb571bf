//! Multi-level subdivision: topology once, geometry as one sparse product per level.
//!
//! Geometry is computed on positions scaled by the normalising power of two
//! and scaled back ([`crate::normalized`]): exact, so ordinary meshes give the
//! same bits, and free of overflow and underflow for coordinates near
//! ±1e308 or 1e-300. [`subdivide`] and [`SubdivisionPlan::subdivide`] then
//! check that every output coordinate is a finite f64
//! ([`StencilError::NotRepresentable`] otherwise).

use crate::holes;
use crate::limit_matrix::{composed_rows, row_rule, RowRule};
use crate::normalized::{map_back, normalize};
use crate::scheme::SchemeRules;
use crate::sharpness::LevelSharpness;
use crate::welds;
use crate::{apply, fvar, Options, RowBuilder, Scheme, SparseMatrix, Split, StencilError};
use glam::DVec3;
use std::borrow::Cow;
use subdiv_mesh::refine::DualProvenance;
use subdiv_mesh::{Mesh, PowerOfTwoScale, Tags, Topology, VertexId};

/// One level of a plan: the refined connectivity, the operator producing
/// its positions from the previous level's, and its tags.
///
/// `#[non_exhaustive]`: made by [`SubdivisionPlan`], read through its
/// public fields (a new field is not a breaking change).
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Refinement {
    /// Connectivity after this level.
    pub topology: Topology,
    /// New × old stencil (P_{k+1} = R·P_k); `None` for Deng-Ma, evaluated
    /// geometrically (its variable tension is nonlinear in the positions; for a
    /// global ω, `deng_ma::stencil` gives the matrix on request).
    pub stencil: Option<SparseMatrix>,
    /// Doo-Sabin provenance of the new faces and vertices.
    pub dual: Option<DualProvenance>,
    /// Sharpness of this level (the tags decayed by the crease method).
    pub sharpness: LevelSharpness,
}

/// The topology of `levels` steps of a scheme, computed once; [`Self::apply`]
/// maps any positions through them.
#[derive(Clone, Debug)]
pub struct SubdivisionPlan {
    options: Options,
    base: Topology,
    base_sharpness: LevelSharpness,
    levels: Vec<Refinement>,
}

/// Largest element count a refined mesh may have (ids are `u32`).
const MAX_ELEMENTS: usize = u32::MAX as usize - 1;

fn check_size(t: &Topology, scheme: Scheme) -> Result<(), StencilError> {
    let (v, f, e, h) = (t.vertex_count(), t.face_count(), t.edge_count(), t.half_edge_count());
    // Upper bounds of the next level's vertex and corner counts from this
    // level's own (`size::refined_sizes` has the exact ones, which need the
    // boundary and the Euler characteristic).
    let (new_vertices, new_corners) = match scheme.traits().split {
        Split::Quad => (v + f + e, 4 * h),
        Split::Triangle => (v + e, 12 * f),
        Split::Dual => (h + 2 * e, 2 * h + 4 * e),
        Split::Sqrt3 => (v + f + t.boundary_edge_count(), 9 * f),
    };
    if new_vertices.max(new_corners) > MAX_ELEMENTS {
        return Err(StencilError::TooLarge);
    }
    Ok(())
}

/// One level of `scheme` on `current`: the refined connectivity (and its
/// sharpness) and the stencil, built on both cores at once (both depend on
/// the coarse level only).
fn refine_level(
    rules: &dyn SchemeRules,
    scheme: Scheme,
    current: &Topology,
    sharp: &LevelSharpness,
) -> Result<Refinement, StencilError> {
    check_size(current, scheme)?;
    rules.check(current, sharp)?;
    let (split, stencil) = rayon::join(|| rules.split(current, sharp), || rules.stencil(current, sharp));
    let (split, stencil) = (split?, stencil?);
    Ok(Refinement { topology: split.topology, stencil, dual: split.dual, sharpness: split.sharpness })
}

/// The limit points of the first `count` vertices of level `t` (`None` for
/// Deng-Ma). Where semi-sharp tags are left (or on a tagged base level),
/// the positions are refined the levels the masks need first
/// ([`SchemeRules::levels_before_limit`]; only the points, no stencil is
/// kept): the first vertices of every primal level descend from the
/// previous level's, in order.
fn limit_points_of(
    rules: &dyn SchemeRules,
    scheme: Scheme,
    t: &Topology,
    sharp: &LevelSharpness,
    positions: &[DVec3],
    is_base: bool,
) -> Option<Result<Vec<DVec3>, StencilError>> {
    let count = t.vertex_count();
    let extra = rules.levels_before_limit(t, sharp, is_base);
    if extra == 0 {
        return rules.limit_points(t, sharp, positions, count);
    }
    if matches!(scheme.traits().split, Split::Quad | Split::Triangle) && !matches!(scheme, Scheme::DengMa(_)) {
        return Some(local_limit_points(rules, scheme, t, sharp, positions));
    }
    let refined = (|| {
        let (mut topology, mut sharp, mut x) = (Cow::Borrowed(t), Cow::Borrowed(sharp), Cow::Borrowed(positions));
        for _ in 0..extra {
            check_size(&topology, scheme)?;
            let (split, next) =
                rayon::join(|| rules.split(&topology, &sharp), || rules.step_points(&topology, &sharp, &x));
            let split = split?;
            x = Cow::Owned(next?);
            topology = Cow::Owned(split.topology);
            sharp = Cow::Owned(split.sharpness);
        }
        Ok((topology.into_owned(), sharp.into_owned(), x.into_owned()))
    })();
    match refined {
        Ok((topology, sharp, x)) => rules.limit_points(&topology, &sharp, &x, count),
        Err(e) => Some(Err(e)),
    }
}

/// Catmull-Clark's and Loop's limit points where levels must be refined
/// first (semi-sharp values, darts, smooth triangles), refining only where
/// they are needed, as OpenSubdiv's adaptive refinement does: a vertex whose
/// rule never changes ([`row_rule`] not general) takes its limit mask on this
/// level, which is exact for it; the others take their rows of the composed
/// limit stencil, computed on a crop around them at every level
/// ([`composed_rows`]: time and memory linear in those vertices and the
/// levels, instead of the whole mesh × 4^levels).
fn local_limit_points(
    rules: &dyn SchemeRules,
    scheme: Scheme,
    t: &Topology,
    sharp: &LevelSharpness,
    positions: &[DVec3],
) -> Result<Vec<DVec3>, StencilError> {
    let count = t.vertex_count();
    let mut points =
        rules.limit_points(t, sharp, positions, count).expect("Catmull-Clark and Loop have limit masks")?;
    let general: Vec<u32> =
        (0..count as u32).filter(|&v| row_rule(t, sharp, VertexId(v)) == RowRule::General).collect();
    if general.is_empty() {
        return Ok(points);
    }
    let rows = composed_rows(t, sharp, scheme, &general)?;
    for (row, &v) in rows.outer_iterator().zip(&general) {
        points[v as usize] = row.iter().map(|(c, &w)| w * positions[c]).sum();
    }
    Ok(points)
}

/// The limit points of every vertex of `t` with `tags` under `options`
/// (`None` for Deng-Ma, which has no limit mask): the points of
/// [`SubdivisionPlan::limit_points`] of a plan of 0 levels, bit for bit,
/// without building the plan, which keeps a copy of the connectivity (on
/// an 8.4M-vertex mesh, 850 MB at the peak of an interpolation's error
/// check). Computed on normalised positions and scaled back (module docs).
///
/// # Errors
/// Invalid options; the scheme's refusal of the mesh (e.g. Loop on
/// polygons); [`StencilError::TooLarge`] when the semi-sharp levels refined
/// first would be too large.
pub fn limit_points_with_options(
    t: &Topology,
    tags: &Tags,
    options: impl Into<Options>,
    positions: &[DVec3],
) -> Result<Option<Vec<DVec3>>, StencilError> {
    let options = options.into();
    options.validate()?;
    let rules = options.scheme.rules();
    let sharp = options.sharpness(tags);
    rules.check(t, &sharp)?;
    let (scale, scaled) = normalize(positions);
    let Some(limits) = limit_points_of(rules.as_ref(), options.scheme, t, &sharp, &scaled, true) else {
        return Ok(None);
    };
    let mut limits = limits?;
    scale.inverse().apply_points(&mut limits);
    Ok(Some(limits))
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
    /// Plans `levels` steps on the untagged topology `t` with `options` (a
    /// [`Scheme`] for the defaults). Fails when the scheme cannot take the
    /// mesh (Loop on non-triangles), on a bad parameter, or when the result
    /// would not fit `u32` ids.
    pub fn new(t: &Topology, options: impl Into<Options>, levels: usize) -> Result<Self, StencilError> {
        Self::with_tags(t, &Tags::none(), options, levels)
    }

    /// Plans `levels` steps on `t` with sharpness `tags` (creases and
    /// corners, refined and decayed level by level).
    pub fn with_tags(
        t: &Topology,
        tags: &Tags,
        options: impl Into<Options>,
        levels: usize,
    ) -> Result<Self, StencilError> {
        let options = options.into();
        options.validate()?;
        let rules = options.scheme.rules();
        let base_sharpness = options.sharpness(tags);
        // Also with 0 levels: the plan's limit points need what the scheme needs.
        rules.check(t, &base_sharpness)?;
        let mut out: Vec<Refinement> = Vec::with_capacity(levels);
        for _ in 0..levels {
            let (coarse, sharp) = out.last().map_or((t, &base_sharpness), |r| (&r.topology, &r.sharpness));
            let level = refine_level(rules.as_ref(), options.scheme, coarse, sharp)?;
            out.push(level);
        }
        Ok(Self { options, base: t.clone(), base_sharpness, levels: out })
    }

    /// The scheme.
    pub fn scheme(&self) -> Scheme {
        self.options.scheme
    }
    /// The options.
    pub fn options(&self) -> &Options {
        &self.options
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
    /// Sharpness after the last level (the input's for zero levels).
    pub fn sharpness(&self) -> &LevelSharpness {
        self.levels.last().map_or(&self.base_sharpness, |r| &r.sharpness)
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
        let rules = self.options.scheme.rules();
        let (mut coarse, mut sharp) = (&self.base, &self.base_sharpness);
        for level in &self.levels {
            current = match &level.stencil {
                Some(r) => apply(r, &current),
                None => rules.step_points(coarse, sharp, &current).expect("the level was checked when planning"),
            };
            (coarse, sharp) = (&level.topology, &level.sharpness);
        }
        current
    }

    /// Limit stencil of the final level's vertices (`None` for Deng-Ma,
    /// an interpolatory scheme whose refined vertices already lie on the
    /// surface). Where semi-sharp tags are left (or on a tagged base level)
    /// it is the product L·R_k⋯R_1 of the limit rows after the levels the
    /// masks need and their refinement stencils, restricted to the final
    /// level's vertices.
    ///
    /// # Errors
    /// As [`Self::new`] for the extra levels.
    pub fn limit_stencil(&self) -> Option<Result<SparseMatrix, StencilError>> {
        let rules = self.options.scheme.rules();
        let (t, sharp) = (self.topology(), self.sharpness());
        let n = t.vertex_count();
        let extra = rules.levels_before_limit(t, sharp, self.levels.is_empty());
        if extra == 0 {
            return rules.limit_stencil(t, sharp, n);
        }
        let composed = (|| {
            let (mut topology, mut sharp) = (Cow::Borrowed(t), Cow::Borrowed(sharp));
            let mut product: Option<SparseMatrix> = None; // R_k⋯R_1
            for _ in 0..extra {
                let level = refine_level(rules.as_ref(), self.options.scheme, &topology, &sharp)?;
                let r = level.stencil.expect("the schemes with limit masks have stencils");
                product = Some(match product {
                    None => r,
                    Some(p) => &r * &p,
                });
                topology = Cow::Owned(level.topology);
                sharp = Cow::Owned(level.sharpness);
            }
            let limit = rules.limit_stencil(&topology, &sharp, n).expect("the scheme has limit masks")?;
            Ok(&limit * &product.expect("extra > 0"))
        })();
        Some(composed)
    }

    /// [`Self::limit_stencil`] computed where it is needed only, as
    /// [`Self::limit_points`] does: the rows of vertices whose rule never
    /// changes are their limit masks on this level (exact for them), the
    /// others the composed rows on crops around them (`composed_rows`).
    /// The same matrix up to the order of the sums, in memory linear in the
    /// vertices and the levels the semi-sharp values need, where
    /// [`Self::limit_stencil`] refines the whole level that many times (4^levels
    /// times its size: what the interpolation methods cannot afford on a large
    /// tagged mesh). Schemes whose limit the crops do not serve (Doo-Sabin, √3)
    /// take [`Self::limit_stencil`].
    ///
    /// # Errors
    /// As [`Self::limit_stencil`].
    pub fn limit_stencil_local(&self) -> Option<Result<SparseMatrix, StencilError>> {
        let scheme = self.scheme();
        if !matches!(scheme.traits().split, Split::Quad | Split::Triangle) || matches!(scheme, Scheme::DengMa(_)) {
            return self.limit_stencil();
        }
        let rules = scheme.rules();
        let (t, sharp) = (self.topology(), self.sharpness());
        let n = t.vertex_count();
        let masks = match rules.limit_stencil(t, sharp, n)? {
            Ok(masks) => masks,
            Err(e) => return Some(Err(e)),
        };
        if rules.levels_before_limit(t, sharp, self.levels.is_empty()) == 0 {
            return Some(Ok(masks));
        }
        let general: Vec<u32> =
            (0..n as u32).filter(|&v| row_rule(t, sharp, VertexId(v)) == RowRule::General).collect();
        let composed = match composed_rows(t, sharp, scheme, &general) {
            Ok(composed) => composed,
            Err(e) => return Some(Err(e)),
        };
        let mut rows = RowBuilder::with_capacity(n, masks.nnz() + composed.nnz());
        let mut composed_rows_left = general.iter().zip(composed.outer_iterator()).peekable();
        for (v, mask) in masks.outer_iterator().enumerate() {
            let row = match composed_rows_left.next_if(|&(&g, _)| g as usize == v) {
                Some((_, row)) => row,
                None => mask,
            };
            row.iter().for_each(|(c, &w)| rows.add(c as u32, w));
            rows.finish_row();
        }
        Some(Ok(rows.build(n)))
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
        let rules = self.options.scheme.rules();
        let is_base = self.levels.is_empty();
        let mut limits =
            limit_points_of(rules.as_ref(), self.scheme(), self.topology(), self.sharpness(), &scaled, is_base)?
                .expect("the plan's levels were checked; the extra levels are of the same kind");
        scale.inverse().apply_points(&mut limits);
        Some(limits)
    }

    /// Subdivides a mesh: positions after every level, moved to their limit
    /// positions when `limit` is set and the scheme has a limit mask; the
    /// tags of the final level; the mesh's texture coordinates refined with
    /// the face-varying interpolation of the options ([`fvar`]; at the final
    /// level, not at the limit).
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
        let rules = self.options.scheme.rules();
        let (t, sharp) = (self.topology(), self.sharpness());
        let limits = if limit {
            limit_points_of(rules.as_ref(), self.scheme(), t, sharp, &positions, self.levels.is_empty()).transpose()?
        } else {
            None
        };
        let mut positions = limits.unwrap_or(positions);
        let copies_input = copies_input(self.scheme(), self.levels.len(), limit);
        map_back_checked(self.scheme(), scale, &mut positions, mesh.positions(), copies_input)?;
        let uvs = match mesh.uvs() {
            Some(channel) => {
                let levels = self.levels.iter().map(|r| (&r.topology, &r.sharpness));
                let refined = fvar::refine_levels(
                    &self.base,
                    &self.base_sharpness,
                    levels,
                    self.scheme(),
                    self.options.fvar,
                    channel,
                );
                Some(refined.map_err(face_varying_error)?)
            }
            None => None,
        };
        let mut holes = holes::base_holes(&self.base, mesh.tags(), &self.options);
        let mut welds = mesh.welds().cloned();
        welds::check_scheme(self.scheme(), welds.as_ref())?;
        let mut coarse = &self.base;
        for level in &self.levels {
            holes = holes::child_holes(self.scheme(), coarse, &holes)?;
            welds = welds::child_welds(self.scheme(), coarse, welds.as_ref())?;
            coarse = &level.topology;
        }
        let tags = if self.levels.is_empty() { mesh.tags().clone() } else { sharp.tags(t) };
        let refined = Mesh::from_topology(t.clone(), positions).with_tags(tags.with_holes(holes)).with_welds(welds);
        Ok(refined.with_uvs(uvs).expect("the refined channel has one value per refined face corner"))
    }
}

/// Whether the first output positions are the input's vertices themselves:
/// after zero levels without limit, or Deng-Ma (whose old vertices stay).
fn copies_input(scheme: Scheme, levels: usize, limit: bool) -> bool {
    matches!(scheme, Scheme::DengMa(_)) || (levels == 0 && !limit)
}

/// `levels` steps of the scheme of `options` (a [`Scheme`] for the
/// defaults) applied to `mesh` with its tags and texture coordinates, moved to the limit positions
/// when `limit` is set and the scheme has a limit mask — the mesh of
/// [`SubdivisionPlan::subdivide`] up to round-off, for a single use: each
/// level is refined and applied in turn and dropped once the next exists, so
/// only two connectivities are held at a time, and no stencil is built: the
/// points are evaluated directly ([`SchemeRules::step_points`]: Doo-Sabin
/// face by face, Catmull-Clark and Loop row by row); the final connectivity
/// is moved into the mesh rather than copied.
///
/// Computed on normalised positions and scaled back (module docs).
///
/// # Errors
/// As [`SubdivisionPlan::new`]; [`StencilError::NotRepresentable`] when an
/// output coordinate is not a finite f64 (the surface leaves the range of f64);
/// [`StencilError::FaceVarying`] when the scheme cannot refine the mesh's
/// texture coordinates (Doo-Sabin with seams or tags).
pub fn subdivide(mesh: &Mesh, options: impl Into<Options>, levels: usize, limit: bool) -> Result<Mesh, StencilError> {
    subdivide_observed(mesh, options.into(), levels, limit, &mut |_| {})
}

/// A mesh subdivided for output, and what had to be left out of it.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Subdivided {
    /// The refined mesh (limit positions when asked for).
    pub mesh: Mesh,
    /// Why the input's texture coordinates are not in [`Subdivided::mesh`]
    /// (the scheme cannot refine them: Doo-Sabin with seams or tags);
    /// `None` when they are, or the input had none.
    pub uvs_dropped: Option<String>,
}

/// [`subdivide`] as every writer of a refined surface wants it (the command
/// line's `subdivide` and `--surface`, [`Interpolant::surface`], the batch,
/// the Python bindings): texture coordinates the scheme cannot refine are
/// dropped, the reason returned, and the positions computed anyway (the
/// refusal comes at the first level, so little is redone); `on_level(k)` is
/// called after level `k` (1-based) is done, for progress.
///
/// [`Interpolant::surface`]: https://docs.rs/subdiv-interp/latest/subdiv_interp/struct.Interpolant.html#method.surface
///
/// # Errors
/// As [`subdivide`], but never [`StencilError::FaceVarying`].
pub fn subdivide_for_output(
    mesh: &Mesh,
    options: impl Into<Options>,
    levels: usize,
    limit: bool,
    mut on_level: impl FnMut(usize),
) -> Result<Subdivided, StencilError> {
    let options = options.into();
    match subdivide_observed(mesh, options, levels, limit, &mut on_level) {
        Err(StencilError::FaceVarying(reason)) => {
            let positions_only = mesh.clone().with_uvs(None).expect("no channel is always valid");
            let mesh = subdivide_observed(&positions_only, options, levels, limit, &mut on_level)?;
            Ok(Subdivided { mesh, uvs_dropped: Some(reason) })
        }
        other => other.map(|mesh| Subdivided { mesh, uvs_dropped: None }),
    }
}

/// [`subdivide`], calling `on_level(k)` after level `k`.
fn subdivide_observed(
    mesh: &Mesh,
    options: Options,
    levels: usize,
    limit: bool,
    on_level: &mut dyn FnMut(usize),
) -> Result<Mesh, StencilError> {
    options.validate()?;
    let scheme = options.scheme;
    let rules = scheme.rules();
    let mut sharp = options.sharpness(mesh.tags());
    // Also with 0 levels and limit: Loop's limit mask needs triangles.
    rules.check(mesh.topology(), &sharp)?;
    let mut fine: Option<Topology> = None; // None: still the input's connectivity
    let (scale, mut positions) = normalize(mesh.positions());
    let mut uvs = mesh.uvs().map(Cow::Borrowed);
    let mut holes = holes::base_holes(mesh.topology(), mesh.tags(), &options);
    let mut welds = mesh.welds().cloned();
    welds::check_scheme(scheme, welds.as_ref())?;
    for level in 0..levels {
        let coarse = fine.as_ref().unwrap_or(mesh.topology());
        check_size(coarse, scheme)?;
        holes = holes::child_holes(scheme, coarse, &holes)?;
        welds = welds::child_welds(scheme, coarse, welds.as_ref())?;
        // The refined connectivity on one core, the points on the other.
        let (split, next) =
            rayon::join(|| rules.split(coarse, &sharp), || rules.step_points(coarse, &sharp, &positions));
        let split = split?;
        positions = next?;
        if let Some(channel) = &uvs {
            let refined = fvar::refine(coarse, &sharp, &split.topology, scheme, options.fvar, channel);
            uvs = Some(Cow::Owned(refined.map_err(face_varying_error)?));
        }
        sharp = split.sharpness;
        fine = Some(split.topology);
        on_level(level + 1);
    }
    let t = fine.as_ref().unwrap_or(mesh.topology());
    let limits = if limit {
        limit_points_of(rules.as_ref(), scheme, t, &sharp, &positions, levels == 0).transpose()?
    } else {
        None
    };
    let mut positions = limits.unwrap_or(positions);
    map_back_checked(scheme, scale, &mut positions, mesh.positions(), copies_input(scheme, levels, limit))?;
    Ok(match fine {
        Some(t) => {
            let tags = sharp.into_tags(&t).with_holes(holes);
            let uvs = uvs.map(Cow::into_owned);
            Mesh::from_topology(t, positions)
                .with_tags(tags)
                .with_welds(welds)
                .with_uvs(uvs)
                .expect("the refined channel has one value per refined face corner")
        }
        None => {
            let tags = mesh.tags().clone().with_holes(holes);
            mesh.with_positions(positions).with_tags(tags)
        }
    })
}

/// A face-varying error as the subdivision's: the scheme's own refusal as
/// it is, the channel's as [`StencilError::FaceVarying`].
fn face_varying_error(e: fvar::FVarError) -> StencilError {
    match e {
        fvar::FVarError::Stencil(e) => e,
        other => StencilError::FaceVarying(other.to_string()),
    }
}
