//! A validated topology with positions.

use crate::error::{MeshError, Warning};
use crate::geometry::{centroid, corner_angle, scaled_newell, unit_vector, unscaled_newell, Aabb, Magnitude};
use crate::ids::{FaceId, VertexId};
use crate::nonmanifold::{is_non_manifold, manifold_cover, NonManifoldReport, Welds};
use crate::soup::{FaceGroups, FaceList, PolygonSoup};
use crate::tags::{EdgeTag, FaceVarying, TagList, Tags, VertexTag};
use crate::topology::Topology;
use glam::DVec3;
use rayon::prelude::*;
use std::sync::Arc;

/// Relative area below which a face counts as zero-area: area ≤ this · d².
pub const ZERO_AREA_REL: f64 = 1e-14;

/// A polygon mesh: validated [`Topology`] plus one `f64` position per vertex.
///
/// The topology is shared: cloning a mesh or giving it new positions
/// ([`Self::with_positions`], how every method returns a control mesh on the
/// input's connectivity) copies no connectivity.
#[derive(Clone, Debug)]
pub struct Mesh {
    topology: Arc<Topology>,
    positions: Vec<DVec3>,
    groups: FaceGroups,
    tags: Tags,
    uvs: Option<Arc<FaceVarying>>,
    /// For the manifold cover of a non-manifold input ([`crate::nonmanifold`]):
    /// which cover vertices are one input vertex.
    welds: Option<Arc<Welds>>,
}

/// A soup [`Mesh::try_from_soup`] refused: why, and the soup itself, as given.
#[derive(Clone, Debug)]
pub struct Rejected {
    /// The first error that makes the soup no valid mesh.
    pub error: MeshError,
    /// The soup, unchanged.
    pub soup: PolygonSoup,
}

impl Mesh {
    /// Validates a soup: per-face checks, finite coordinates, then connectivity
    /// (see [`Topology::new`]), then extent: a mesh whose faces' vertices all
    /// coincide (bounding-box diagonal 0, no scale for any tolerance) is
    /// refused with [`MeshError::AllVerticesCoincide`]. Returns the mesh and
    /// the warning-level defects (isolated vertices, zero-area faces), which
    /// do not prevent its use. Time linear in the number of corners.
    ///
    /// A non-manifold soup is refused here (the mesh's vertices are always
    /// the soup's); [`Mesh::from_soup_covering`] takes it as OpenSubdiv does.
    pub fn from_soup(soup: PolygonSoup) -> Result<(Self, Vec<Warning>), MeshError> {
        Self::try_from_soup(soup).map_err(|rejected| rejected.error)
    }

    /// [`Mesh::from_soup`] that gives the soup back, unchanged, with the
    /// error: for a caller that goes on to describe what is wrong with it
    /// ([`crate::diagnose`]) without having copied it first.
    pub fn try_from_soup(soup: PolygonSoup) -> Result<(Self, Vec<Warning>), Box<Rejected>> {
        Self::validate(soup, false)
    }

    /// [`Mesh::from_soup`] that also takes a non-manifold soup (edges of
    /// three or more faces, two faces using an edge the same way, vertices
    /// joining separate fans, a vertex repeated in a face), as OpenSubdiv's
    /// `Vtr` refines it: the mesh is then its manifold cover
    /// ([`crate::nonmanifold`]), with a copy of a vertex per fan appended
    /// after the soup's vertices, [`Mesh::welds`] to write it back, and a
    /// [`Warning::NonManifold`]. What the command-line tool and the file
    /// loaders use.
    ///
    /// # Errors
    /// As [`Mesh::from_soup`] for the other defects;
    /// [`MeshError::NonManifoldUnsupported`] for a configuration a cover
    /// cannot express.
    pub fn from_soup_covering(soup: PolygonSoup) -> Result<(Self, Vec<Warning>), MeshError> {
        Self::try_from_soup_covering(soup).map_err(|rejected| rejected.error)
    }

    /// [`Mesh::from_soup_covering`] that gives the soup back with the error.
    pub fn try_from_soup_covering(soup: PolygonSoup) -> Result<(Self, Vec<Warning>), Box<Rejected>> {
        Self::validate(soup, true)
    }

    fn validate(soup: PolygonSoup, covering: bool) -> Result<(Self, Vec<Warning>), Box<Rejected>> {
        if soup.faces.is_empty() {
            return Err(Box::new(Rejected { error: MeshError::NoFaces, soup }));
        }
        if let Some((v, p)) = soup.positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
            let error = MeshError::NonFiniteCoordinate { vertex: v as u32, x: p.x, y: p.y, z: p.z };
            return Err(Box::new(Rejected { error, soup }));
        }
        let PolygonSoup { mut positions, faces, groups, tags, uvs } = soup;
        let (topology, welds, report) = match Topology::new_or_return(faces, positions.len()) {
            Ok(topology) => (topology, None, None),
            Err((error, faces)) if covering && is_non_manifold(&error) => {
                // OpenSubdiv refines it: through its manifold cover.
                let covered = manifold_cover(&faces, positions.len()).and_then(|(cover, report)| {
                    let topology = Topology::new(cover.faces, cover.vertex_count)?;
                    cover.welds.check_creases(&topology)?;
                    Ok((topology, cover.welds, report))
                });
                match covered {
                    Ok((topology, welds, report)) => {
                        for v in positions.len()..welds.cover_vertex_count() {
                            positions.push(positions[welds.vertex(VertexId(v as u32)) as usize]);
                        }
                        (topology, Some(Arc::new(welds)), Some(report))
                    }
                    Err(error) => {
                        return Err(Box::new(Rejected {
                            error,
                            soup: PolygonSoup { positions, faces, groups, tags, uvs },
                        }));
                    }
                }
            }
            Err((error, faces)) => {
                return Err(Box::new(Rejected { error, soup: PolygonSoup { positions, faces, groups, tags, uvs } }));
            }
        };
        let cover_tags = match &welds {
            Some(welds) => welds.cover_tags(&topology, &tags),
            None => Ok(tags.clone()),
        };
        let crease_copies = welds.as_ref().map(|welds| welds.crease_copies().to_vec()).unwrap_or_default();
        let checked = cover_tags.and_then(|tags| Tags::from_list(&topology, &tags)).and_then(|checked| {
            let checked = checked.with_crease_copies(crease_copies);
            if let Some(uvs) = &uvs {
                uvs.validate(topology.half_edge_count())?;
            }
            Ok(checked)
        });
        let checked_tags = match checked {
            Ok(checked_tags) => checked_tags,
            Err(error) => {
                let faces = match &welds {
                    Some(welds) => welds.faces(&topology),
                    None => topology.into_faces(),
                };
                if let Some(welds) = &welds {
                    positions.truncate(welds.vertex_count());
                }
                return Err(Box::new(Rejected { error, soup: PolygonSoup { positions, faces, groups, tags, uvs } }));
            }
        };
        let mesh =
            Self { topology: Arc::new(topology), positions, groups, tags: checked_tags, uvs: uvs.map(Arc::new), welds };
        let bbox = mesh.bbox();
        if bbox.min == bbox.max {
            let p = bbox.min;
            let vertices = mesh.topology.referenced_vertex_count();
            let error = MeshError::AllVerticesCoincide { vertices, x: p.x, y: p.y, z: p.z };
            return Err(Box::new(Rejected { error, soup: PolygonSoup { tags, ..mesh.into_soup() } }));
        }
        let mut warnings = mesh.warnings();
        if let Some(report) = report {
            warnings.push(Warning::NonManifold(Box::new(report)));
        }
        Ok((mesh, warnings))
    }

    /// Builds a mesh from positions and faces, ignoring warnings.
    pub fn new(positions: Vec<DVec3>, faces: FaceList) -> Result<Self, MeshError> {
        Self::from_soup(PolygonSoup::new(positions, faces)).map(|(m, _)| m)
    }

    /// The same connectivity (and tags and texture coordinates) with other
    /// positions (e.g. a solved control mesh).
    ///
    /// # Panics
    /// If `positions.len()` differs from the vertex count (a caller bug).
    pub fn with_positions(&self, positions: Vec<DVec3>) -> Self {
        assert_eq!(positions.len(), self.positions.len(), "one position per vertex");
        let mut positions = positions;
        if let Some(welds) = &self.welds {
            // Copies of one vertex are one point (a solver may leave them a
            // rounding apart).
            welds.unify(&mut positions);
        }
        Self { positions, ..self.clone_without_positions() }
    }

    /// Builds from an already validated topology.
    ///
    /// # Panics
    /// If `positions.len()` differs from the topology's vertex count (a caller bug).
    pub fn from_topology(topology: Topology, positions: Vec<DVec3>) -> Self {
        assert_eq!(positions.len(), topology.vertex_count(), "one position per vertex");
        Self {
            topology: Arc::new(topology),
            positions,
            groups: FaceGroups::default(),
            tags: Tags::none(),
            uvs: None,
            welds: None,
        }
    }

    /// Everything but the positions, shared (the connectivity and texture
    /// coordinates are reference-counted).
    fn clone_without_positions(&self) -> Self {
        Self {
            topology: self.topology.clone(),
            positions: Vec::new(),
            groups: self.groups.clone(),
            tags: self.tags.clone(),
            uvs: self.uvs.clone(),
            welds: self.welds.clone(),
        }
    }

    /// The welds of a manifold cover ([`crate::nonmanifold`]): `Some` when
    /// this mesh is the cover of a non-manifold input (or a refinement of
    /// one), whose copies of a vertex are one vertex of the mesh written.
    pub fn welds(&self) -> Option<&Welds> {
        self.welds.as_deref()
    }

    /// The same mesh as the cover described by `welds` (`None`: a manifold
    /// mesh of its own).
    ///
    /// # Panics
    /// If `welds` does not cover this mesh's vertices (a caller bug).
    pub fn with_welds(mut self, welds: Option<Welds>) -> Self {
        if let Some(welds) = &welds {
            assert_eq!(welds.cover_vertex_count(), self.positions.len(), "welds of this cover");
        }
        self.welds = welds.map(Arc::new);
        self
    }

    /// The non-manifold features of the input this mesh covers (`None` for
    /// a manifold mesh, and for a refined cover).
    pub fn non_manifold(&self) -> Option<&NonManifoldReport> {
        self.welds.as_ref().and_then(|welds| welds.report())
    }

    /// The mesh as a writer writes it: for a cover, the input's vertices
    /// (copies welded) with its faces and tags; otherwise the mesh itself.
    /// Positions, faces and tags by vertex index.
    pub fn welded(&self) -> (std::borrow::Cow<'_, [DVec3]>, std::borrow::Cow<'_, FaceList>, TagList) {
        use std::borrow::Cow;
        let list = self.tags.to_list(&self.topology);
        match &self.welds {
            Some(welds) => {
                (Cow::Owned(welds.weld(&self.positions)), Cow::Owned(welds.faces(&self.topology)), welds.tags(&list))
            }
            None => (Cow::Borrowed(&self.positions), Cow::Borrowed(self.topology.faces()), list),
        }
    }

    /// The same mesh with other sharpness tags (validated against this
    /// topology: [`Tags::from_arrays`], [`Tags::from_list`]).
    pub fn with_tags(mut self, tags: Tags) -> Self {
        self.tags = tags;
        self
    }

    /// The same mesh with other texture coordinates.
    ///
    /// # Errors
    /// As [`FaceVarying::validate`] for this mesh's face corners.
    pub fn with_uvs(mut self, uvs: Option<FaceVarying>) -> Result<Self, MeshError> {
        if let Some(uvs) = &uvs {
            uvs.validate(self.topology.half_edge_count())?;
        }
        self.uvs = uvs.map(Arc::new);
        Ok(self)
    }

    /// Crease and corner sharpness (all smooth when the input had no tags).
    pub fn tags(&self) -> &Tags {
        &self.tags
    }

    /// Texture coordinates (one face-varying channel), if any.
    pub fn uvs(&self) -> Option<&FaceVarying> {
        self.uvs.as_deref()
    }

    /// The connectivity.
    pub fn topology(&self) -> &Topology {
        &self.topology
    }
    /// Vertex positions.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }
    /// Mutable vertex positions (connectivity is fixed).
    pub fn positions_mut(&mut self) -> &mut [DVec3] {
        &mut self.positions
    }
    /// Position of vertex `v`.
    pub fn position(&self, v: VertexId) -> DVec3 {
        self.positions[v.index()]
    }
    /// Face groups carried over from the file (may be empty).
    pub fn groups(&self) -> &FaceGroups {
        &self.groups
    }
    /// Back to plain data (a cover welded back: [`Self::welded`]).
    pub fn into_soup(self) -> PolygonSoup {
        let (positions, faces, tags) = self.welded();
        let (positions, faces) = (positions.into_owned(), faces.into_owned());
        let uvs = self.uvs.map(|uvs| Arc::try_unwrap(uvs).unwrap_or_else(|shared| (*shared).clone()));
        PolygonSoup { positions, faces, groups: self.groups, tags, uvs }
    }

    /// Bounding box of the vertices that faces use.
    pub fn bbox(&self) -> Aabb {
        let t = &self.topology;
        Aabb::of(t.vertices().filter(|&v| !t.is_isolated(v)).map(|v| self.position(v)))
            .expect("a valid mesh has at least one face")
    }
    /// The scale *d* ([how the error is measured]): length of the bounding-box diagonal, without
    /// overflow or underflow ([`Aabb::diagonal`]): finite and exact to
    /// rounding for every mesh whose diagonal is at most `f64::MAX`, +∞ only
    /// beyond (coordinates spanning more than about ±0.5e308 on every axis),
    /// which callers must refuse or normalise away ([`crate::PowerOfTwoScale`]).
    /// Never 0 for a mesh [`Self::from_soup`] accepted.
    ///
    /// [how the error is measured]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-how-the-error-is-measured
    pub fn bbox_diagonal(&self) -> f64 {
        self.bbox().diagonal()
    }

    fn face_points(&self, f: FaceId) -> impl ExactSizeIterator<Item = DVec3> + Clone + '_ {
        self.topology.face(f).iter().map(|&v| self.positions[v as usize])
    }
    /// Centroid (vertex average) of face `f`: a Doo-Sabin limit point ([how the error is measured]).
    ///
    /// [how the error is measured]: https://github.com/subdiv/subdiv/blob/main/docs/ARCHITECTURE.md#contract-how-the-error-is-measured
    pub fn face_centroid(&self, f: FaceId) -> DVec3 {
        centroid(self.face_points(f))
    }
    /// Centroids of all faces.
    pub fn face_centroids(&self) -> Vec<DVec3> {
        self.topology.face_ids().map(|f| self.face_centroid(f)).collect()
    }
    /// Area of face `f` (half the Newell vector's length; exact for planar
    /// faces), formed without overflow or underflow: +∞ only when the area
    /// exceeds `f64::MAX` (coordinates beyond about 1e154), 0 or subnormal
    /// only when it is below the normal range. The zero-area check of
    /// [`Self::warnings`] does not round it and is scale-free.
    pub fn face_area(&self, f: FaceId) -> f64 {
        self.face_area_magnitude(f).value()
    }
    fn face_area_magnitude(&self, f: FaceId) -> Magnitude {
        let (n, s) = scaled_newell(self.face_points(f));
        Magnitude::length(n).times(Magnitude::new(0.5)).scaled(s.inverse())
    }
    /// Unit normal of face `f` (Newell), finite whatever the coordinates'
    /// scale ([`crate::unit_newell_normal`]); zero for a face whose Newell
    /// vector is exactly zero.
    pub fn face_normal(&self, f: FaceId) -> DVec3 {
        unit_vector(scaled_newell(self.face_points(f)).0)
    }
    /// Unit normals of all faces.
    pub fn face_normals(&self) -> Vec<DVec3> {
        self.topology.face_ids().map(|f| self.face_normal(f)).collect()
    }
    /// Angle-weighted unit vertex normals: nᵢ = Σⱼ θⱼ nⱼ / ‖Σⱼ θⱼ nⱼ‖ with θⱼ the
    /// angle of face j at vertex i (Deng-Wang Eq. 8, [correction W5]). Zero for
    /// isolated vertices and where the sum vanishes. Scale-free: the face
    /// normals and angles are ([`Self::face_normal`], [`crate::corner_angle`]).
    ///
    /// [correction W5]: https://github.com/subdiv/subdiv/blob/main/docs/REFERENCES.md#w5
    pub fn vertex_normals(&self) -> Vec<DVec3> {
        let t = &self.topology;
        let mut normals = vec![DVec3::ZERO; t.vertex_count()];
        for f in t.face_ids() {
            let face = t.face(f);
            let normal = self.face_normal(f);
            let p = |v: u32| self.positions[v as usize];
            // Corner k between corners k − 1 and k + 1, cyclically.
            let mut previous = p(face[face.len() - 1]);
            for (k, &v) in face.iter().enumerate() {
                let next = p(face[if k + 1 == face.len() { 0 } else { k + 1 }]);
                let here = p(v);
                normals[v as usize] += corner_angle(previous, here, next) * normal;
                previous = here;
            }
        }
        normals.iter_mut().for_each(|n| *n = unit_vector(*n));
        normals
    }

    /// Warning-level defects: isolated vertices and zero-area faces
    /// (area ≤ [`ZERO_AREA_REL`] · d²). Areas and d² are compared unrounded,
    /// so a mesh and the same mesh scaled by any power of two (2^±900, where
    /// d² and the areas leave the `f64` range) get the same verdict.
    pub fn warnings(&self) -> Vec<Warning> {
        let t = &self.topology;
        let mut warnings = Vec::new();
        let isolated: Vec<u32> = t.vertices().filter(|&v| t.is_isolated(v)).map(|v| v.0).collect();
        if !isolated.is_empty() {
            warnings.push(Warning::IsolatedVertices { vertices: isolated });
        }
        let d = self.bbox().diagonal_magnitude();
        let threshold = Magnitude::new(ZERO_AREA_REL).times(d).times(d);
        // The common case in plain `f64`, the same verdicts: with d, the
        // offsets and ‖N‖² in the normal range, the exact path's scalings by
        // powers of two commute with every rounding (same bits).
        let plain_threshold =
            (2f64.powi(-200)..=2f64.powi(200)).contains(&d.value()).then(|| ZERO_AREA_REL * d.value() * d.value());
        let is_degenerate = |f: FaceId| {
            let plain = plain_threshold.and_then(|threshold| {
                let n = unscaled_newell(self.face_points(f))?;
                let squared = n.length_squared();
                in_plain_range(squared).then(|| 0.5 * squared.sqrt() <= threshold)
            });
            plain.unwrap_or_else(|| self.face_area_magnitude(f).le(threshold))
        };
        let degenerate: Vec<u32> =
            (0..t.face_count() as u32).into_par_iter().filter(|&f| is_degenerate(FaceId(f))).collect();
        if !degenerate.is_empty() {
            warnings.push(Warning::ZeroAreaFaces { faces: degenerate });
        }
        warnings
    }
}

impl PolygonSoup {
    /// Removes vertices no face uses (the documented repair for
    /// [`Warning::IsolatedVertices`]). Returns the compacted soup and, for every
    /// old vertex, its new index (`None` if removed). Faces with out-of-range
    /// indices are kept unchanged so validation still reports them.
    pub fn without_isolated_vertices(&self) -> (PolygonSoup, Vec<Option<u32>>) {
        let n = self.positions.len();
        let mut used = vec![false; n];
        for &v in self.faces.indices() {
            if let Some(u) = used.get_mut(v as usize) {
                *u = true;
            }
        }
        let mut map = vec![None; n];
        let mut positions = Vec::with_capacity(n);
        for (v, p) in self.positions.iter().enumerate() {
            if used[v] {
                map[v] = Some(positions.len() as u32);
                positions.push(*p);
            }
        }
        let indices =
            self.faces.indices().iter().map(|&v| map.get(v as usize).copied().flatten().unwrap_or(v)).collect();
        let faces = FaceList::from_raw(self.faces.offsets().to_vec(), indices);
        // Tags follow their vertices; a tag on a removed vertex names no edge
        // and no face corner, so it goes.
        let new = |v: u32| map.get(v as usize).copied().flatten();
        let creases =
            (self.tags.creases.iter()).filter_map(|t| Some(EdgeTag { a: new(t.a)?, b: new(t.b)?, ..*t })).collect();
        let corners =
            (self.tags.corners.iter()).filter_map(|t| Some(VertexTag { vertex: new(t.vertex)?, ..*t })).collect();
        // Faces keep their numbers: hole tags and the file's options stay as they are.
        let tags = TagList { creases, corners, holes: self.tags.holes.clone(), options: self.tags.options };
        (PolygonSoup { positions, faces, groups: self.groups.clone(), tags, uvs: self.uvs.clone() }, map)
    }
}

/// True for x in [2^-900, 2^900]: far from the subnormals and from overflow,
/// where scaling by a power of two and rounding commute.
fn in_plain_range(x: f64) -> bool {
    (2f64.powi(-900)..=2f64.powi(900)).contains(&x)
}
