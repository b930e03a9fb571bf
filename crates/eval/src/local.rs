//! Local refinement: a small submesh around one face, refined with the
//! workspace's own [`SubdivisionPlan`] (the scheme's rules and tags, nothing
//! re-derived here), every vertex of it carried as weights on the vertices
//! of the *root* submesh (so on the control points).
//!
//! The claim this rests on (tested in `tests/local.rs`): the vertices of a
//! face's *ring* — every face sharing a vertex with it — refined once give
//! every vertex of the rings of the face's children exactly as global
//! subdivision does. The points of a child's ring are vertex points of the
//! parent face's corners (whose faces are all in the ring), edge points of
//! edges at those corners (both faces in the ring) and face points of ring
//! faces; the submesh's own artificial boundary changes only points that are
//! not used. Sharpness decays the same way: the child edges of a child ring
//! are halves of edges at the parent's corners (whose incident edges are
//! complete) or new edges inside faces.
//!
//! A submesh can touch a vertex in two separate fans of faces (a bowtie,
//! which [`Topology`] refuses): such a vertex gets one local copy per fan,
//! each carrying the same weights.

use crate::surface::EvalError;
use std::collections::HashMap;
use std::sync::Arc;
use subdiv_mesh::{EdgeId, FaceId, FaceList, HalfEdgeId, Tags, Topology, VertexId};
use subdiv_stencil::{LevelSharpness, Options, SparseMatrix, SubdivisionPlan};

/// A submesh at some level with each vertex as weights on the root's vertices.
#[derive(Clone, Debug)]
pub(crate) struct Local {
    /// The submesh's connectivity (shared by the levels of one structure:
    /// a [`Step`]'s next level and every level it is applied to).
    pub t: Arc<Topology>,
    /// Its tags at this level (decayed), with the options' boundary rule.
    pub sharp: Arc<LevelSharpness>,
    /// `vertex_count × root` weights, row-major: local vertex i is
    /// Σ_j rows\[i·root + j\]·(root vertex j).
    pub rows: Vec<f64>,
    /// Vertex count of the root submesh (the width of `rows`).
    pub root: usize,
    /// Whether this is the control mesh's own level (tags on the base level
    /// need one step before the limit masks are exact).
    pub is_base: bool,
}

/// The face ring of a face in the control mesh as a root [`Local`]: its
/// vertices are the columns of every later stencil, `ids` maps them to the
/// control mesh.
#[derive(Clone, Debug)]
pub(crate) struct Root {
    /// The ring itself (identity weights).
    pub local: Local,
    /// Control-mesh vertex of every root vertex.
    pub ids: Vec<u32>,
    /// The face the ring is built around, in the ring's numbering.
    pub face: FaceId,
}

/// A submesh picked from a bigger topology: faces (in local numbering),
/// the parent vertex of every local vertex, the local id of each picked face.
struct Picked {
    faces: FaceList,
    parent_vertex: Vec<u32>,
    /// Local half-edge → parent half-edge.
    parent_half_edge: Vec<u32>,
}

/// Picks `faces` of `t` (distinct), giving one local vertex per fan of
/// picked faces around each vertex (bowties split).
fn pick(t: &Topology, faces: &[FaceId]) -> Picked {
    let picked: HashMap<u32, u32> = faces.iter().enumerate().map(|(i, f)| (f.0, i as u32)).collect();
    // Local vertex of each picked corner (parent half-edge leaving the corner).
    let mut corner_vertex: HashMap<u32, u32> = HashMap::new();
    let mut parent_vertex = Vec::new();
    for &f in faces {
        for h in t.face_half_edges(f) {
            if corner_vertex.contains_key(&h.0) {
                continue;
            }
            // Walk the fan of picked faces containing this corner, both ways,
            // and give every corner of it the same new local vertex.
            let v = t.he_from(h);
            let id = parent_vertex.len() as u32;
            parent_vertex.push(v.0);
            let mut run = vec![h];
            // Counter-clockwise: twin(prev(h)) leaves v in the next face.
            let mut g = h;
            loop {
                match t.he_twin(t.he_prev(g)) {
                    Some(n) if picked.contains_key(&t.he_face(n).0) && n != h => {
                        run.push(n);
                        g = n;
                    }
                    _ => break,
                }
            }
            let closed = t.he_twin(t.he_prev(g)) == Some(h);
            if !closed {
                let mut g = h;
                while let Some(tw) = t.he_twin(g) {
                    let n = t.he_next(tw);
                    if !picked.contains_key(&t.he_face(n).0) || n == h {
                        break;
                    }
                    run.push(n);
                    g = n;
                }
            }
            for c in run {
                corner_vertex.insert(c.0, id);
            }
        }
    }
    let mut list = FaceList::with_capacity(faces.len(), faces.len() * 4);
    let mut parent_half_edge = Vec::new();
    let mut buf = Vec::new();
    for &f in faces {
        buf.clear();
        for h in t.face_half_edges(f) {
            buf.push(corner_vertex[&h.0]);
            parent_half_edge.push(h.0);
        }
        list.push(&buf);
    }
    Picked { faces: list, parent_vertex, parent_half_edge }
}

/// The faces sharing a vertex with `face` (it first), each once.
pub(crate) fn ring_faces(t: &Topology, face: FaceId) -> Vec<FaceId> {
    let mut out = vec![face];
    for &v in t.face(face) {
        for h in t.vertex_fan(VertexId(v)) {
            let g = t.he_face(*h);
            if !out.contains(&g) {
                out.push(g);
            }
        }
    }
    out
}

/// The faces around vertex `v`, in fan order.
pub(crate) fn star_faces(t: &Topology, v: VertexId) -> Vec<FaceId> {
    t.vertex_fan(v).iter().map(|&h| t.he_face(h)).collect()
}

/// The submesh of `faces` of a level (`t`, `tags`), each local vertex
/// carrying its parent's row of `rows` (`width` wide), or the identity on
/// the submesh's own vertices when `rows` is `None` (a root); returns it and
/// the map local vertex → parent vertex.
pub(crate) fn submesh(
    t: &Topology,
    tags: &Tags,
    options: &Options,
    rows: Option<(&[f64], usize)>,
    faces: &[FaceId],
    is_base: bool,
) -> Result<(Local, Vec<u32>), EvalError> {
    let picked = pick(t, faces);
    let n = picked.parent_vertex.len();
    let topo = Topology::new(picked.faces, n).map_err(|e| EvalError::Internal(format!("local submesh: {e}")))?;
    let mut edges = vec![0f32; topo.edge_count()];
    for (local_h, &parent_h) in picked.parent_half_edge.iter().enumerate() {
        let e = topo.he_edge(HalfEdgeId(local_h as u32));
        edges[e.index()] = tags.edge_sharpness(t.he_edge(HalfEdgeId(parent_h)));
    }
    let vertices: Vec<f32> = picked.parent_vertex.iter().map(|&v| tags.vertex_sharpness(VertexId(v))).collect();
    let local_tags =
        Tags::from_arrays(&topo, edges, vertices).map_err(|e| EvalError::Internal(format!("local tags: {e}")))?;
    let sharp = options.sharpness(&local_tags);
    let (out, root) = match rows {
        Some((rows, width)) => {
            let mut out = vec![0.0; n * width];
            for (i, &p) in picked.parent_vertex.iter().enumerate() {
                let p = p as usize;
                out[i * width..(i + 1) * width].copy_from_slice(&rows[p * width..(p + 1) * width]);
            }
            (out, width)
        }
        None => {
            let mut out = vec![0.0; n * n];
            (0..n).for_each(|i| out[i * n + i] = 1.0);
            (out, n)
        }
    };
    Ok((Local { t: Arc::new(topo), sharp: Arc::new(sharp), rows: out, root, is_base }, picked.parent_vertex))
}

impl Root {
    /// The ring of `face` in the control mesh (`t` with `tags`).
    pub fn new(t: &Topology, tags: &Tags, options: &Options, face: FaceId) -> Result<Self, EvalError> {
        let faces = ring_faces(t, face);
        let (local, ids) = submesh(t, tags, options, None, &faces, true)?;
        Ok(Self { local, ids, face: FaceId(0) })
    }
}

/// One level of the scheme on a local submesh: the refined connectivity,
/// its tags and the composed rows.
pub(crate) struct Refined {
    /// The refined connectivity.
    pub t: Topology,
    /// Its tags.
    pub tags: Tags,
    /// Composed rows (new vertices × root).
    pub rows: Vec<f64>,
    /// Width of the rows.
    pub root: usize,
}

impl Local {
    /// Refines the submesh once with `options`' scheme.
    pub fn refine(&self, options: &Options) -> Result<Refined, EvalError> {
        let tags = self.sharp.tags(&self.t);
        let plan = SubdivisionPlan::with_tags(&self.t, &tags, *options, 1)?;
        let level = &plan.levels()[0];
        let r = level.stencil.as_ref().ok_or(EvalError::Internal("the scheme has no refinement stencil".into()))?;
        let rows = compose(r, &self.rows, self.root);
        Ok(Refined { t: level.topology.clone(), tags: level.sharpness.tags(&level.topology), rows, root: self.root })
    }

    /// The weights on the root of a combination of local vertices.
    pub fn combine(&self, combo: &[(u32, f64)], out: &mut [f64]) {
        for &(v, w) in combo {
            let row = &self.rows[v as usize * self.root..(v as usize + 1) * self.root];
            out.iter_mut().zip(row).for_each(|(o, r)| *o += w * r);
        }
    }
}

/// One step of on-demand refinement as a linear map: from a local level's
/// points to those of the next level's ring around child `k` of a cell.
/// What a step does depends only on the level's structure (connectivity,
/// tags, the cell and the child), not on its rows, so it is computed once
/// per structure ([`Local::step_key`]) and applied to the rows of every
/// level of that structure ([`Local::apply`]): near an irregular vertex
/// every level has the same structure.
#[derive(Debug)]
pub(crate) struct Step {
    /// The next level; its rows are the map (its vertices × the parent's).
    pub next: Local,
    /// The cell within the next level's ring.
    pub cell: FaceId,
}

/// Everything a [`Step`] depends on besides the scheme's options: the
/// level's faces, its tags (as words), whether it is the base level, the
/// cell and the child.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct StepKey(Vec<u32>);

impl Local {
    /// The structure a [`Step`] from `face`'s child `k` depends on.
    pub fn step_key(&self, face: FaceId, k: usize) -> StepKey {
        let tags = self.sharp.tags(&self.t);
        let faces = self.t.faces();
        let (offsets, indices) = (faces.offsets(), faces.indices());
        let (edges, vertices) = (self.t.edge_count(), self.t.vertex_count());
        let mut words = Vec::with_capacity(6 + offsets.len() + indices.len() + edges + vertices);
        words.extend([u32::from(self.is_base), face.0, k as u32, offsets.len() as u32, edges as u32, vertices as u32]);
        words.extend_from_slice(offsets);
        words.extend_from_slice(indices);
        words.extend((0..edges as u32).map(|e| tags.edge_sharpness(EdgeId(e)).to_bits()));
        words.extend((0..vertices as u32).map(|v| tags.vertex_sharpness(VertexId(v)).to_bits()));
        words.extend_from_slice(tags.crease_copies());
        StepKey(words)
    }

    /// The step from `face`'s child `k`, computed on this level's structure
    /// with the identity as its rows; `child_cell` names the child's refined
    /// face and its cell ([`crate::surface`]'s patching row).
    pub fn step(
        &self,
        options: &Options,
        face: FaceId,
        k: usize,
        child_cell: impl FnOnce(&Local, &Refined, FaceId, usize) -> Result<(FaceId, u32), EvalError>,
    ) -> Result<Step, EvalError> {
        let n = self.t.vertex_count();
        let mut rows = vec![0.0; n * n];
        (0..n).for_each(|i| rows[i * n + i] = 1.0);
        let identity = Local { t: self.t.clone(), sharp: self.sharp.clone(), rows, root: n, is_base: self.is_base };
        let refined = identity.refine(options)?;
        let (child, cell) = child_cell(&identity, &refined, face, k)?;
        let (next, _) = refined.ring(options, child)?;
        Ok(Step { next, cell: FaceId(cell) })
    }

    /// The next level after `step`: its rows are the step's map applied to
    /// this level's (the sums in the order refinement composes them, so the
    /// weights are those of refining these rows directly).
    pub fn apply(&self, step: &Step) -> Local {
        let (map, from, width) = (&step.next.rows, step.next.root, self.root);
        let n = step.next.t.vertex_count();
        let mut rows = vec![0.0; n * width];
        for (i, out) in rows.chunks_exact_mut(width).enumerate() {
            for (j, &w) in map[i * from..(i + 1) * from].iter().enumerate() {
                if w != 0.0 {
                    let src = &self.rows[j * width..(j + 1) * width];
                    out.iter_mut().zip(src).for_each(|(a, b)| *a += w * b);
                }
            }
        }
        Local { t: step.next.t.clone(), sharp: step.next.sharp.clone(), rows, root: width, is_base: step.next.is_base }
    }
}

impl Refined {
    /// The ring of `face` of the refined level as the next [`Local`].
    pub fn ring(&self, options: &Options, face: FaceId) -> Result<(Local, FaceId), EvalError> {
        let faces = ring_faces(&self.t, face);
        let (local, _) = submesh(&self.t, &self.tags, options, Some((&self.rows, self.root)), &faces, false)?;
        Ok((local, FaceId(0)))
    }
}

/// `R · X` for a sparse R (n' × n) and dense X (n × width, row-major).
pub(crate) fn compose(r: &SparseMatrix, x: &[f64], width: usize) -> Vec<f64> {
    let mut out = vec![0.0; r.rows() * width];
    for (i, row) in r.outer_iterator().enumerate() {
        let o = &mut out[i * width..(i + 1) * width];
        for (j, &w) in row.iter() {
            let src = &x[j * width..(j + 1) * width];
            o.iter_mut().zip(src).for_each(|(a, b)| *a += w * b);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use subdiv_mesh::{shapes, EdgeId, Mesh};
    use subdiv_stencil::Scheme;

    /// The module's claim: a face's ring refined once gives every vertex of
    /// its children's rings as global subdivision does (Catmull-Clark, with
    /// semi-sharp and sharp tags, n-gons and boundaries).
    fn check(mesh: &Mesh, options: Options) {
        let t = mesh.topology();
        let global = subdiv_stencil::subdivide(mesh, options, 1, false).unwrap();
        let (nv, nf) = (t.vertex_count(), t.face_count());
        for f in t.face_ids() {
            let faces = ring_faces(t, f);
            let root = Root::new(t, mesh.tags(), &options, f).unwrap();
            let refined = root.local.refine(&options).unwrap();
            let (lv, lf) = (root.local.t.vertex_count(), root.local.t.face_count());
            let position = |r: usize| -> DVec3 {
                let row = &refined.rows[r * refined.root..(r + 1) * refined.root];
                root.ids.iter().zip(row).fold(DVec3::ZERO, |acc, (&v, &w)| acc + w * mesh.positions()[v as usize])
            };
            // The refined vertex r of the ring as a vertex of the global level 1.
            let global_id = |r: usize| -> usize {
                if r < lv {
                    root.ids[r] as usize
                } else if r < lv + lf {
                    nv + faces[r - lv].index()
                } else {
                    let (a, b) = root.local.t.edge_vertices(EdgeId((r - lv - lf) as u32));
                    let (a, b) = (VertexId(root.ids[a.index()]), VertexId(root.ids[b.index()]));
                    nv + nf + t.find_edge(a, b).expect("a ring edge is a mesh edge").index()
                }
            };
            let h0 = root.local.t.faces().offsets()[0];
            for k in 0..t.face_size(f) as u32 {
                let child = FaceId(h0 + k);
                for g in ring_faces(&refined.t, child) {
                    for &r in refined.t.face(g) {
                        let (got, want) = (position(r as usize), global.positions()[global_id(r as usize)]);
                        assert!((got - want).length() < 1e-12, "face {f:?}, child {k}, vertex {r}: {got} vs {want}");
                    }
                }
            }
        }
    }

    #[test]
    fn a_refined_ring_holds_its_childrens_rings() {
        let options = Options::new(Scheme::CatmullClark);
        check(&shapes::polygon_mix(&shapes::torus(6, 5), 3, 0.25, 0.25, 0.1), options);
        check(&shapes::polygon_mix(&shapes::quad_grid(4, 3), 5, 0.25, 0.25, 0.1), options);
        let cube = shapes::cube();
        let mut e = vec![0f32; cube.topology().edge_count()];
        (e[0], e[1], e[4]) = (1.5, 10.0, 0.5);
        let tagged = cube.clone().with_tags(Tags::from_arrays(cube.topology(), e, Vec::new()).unwrap());
        check(&tagged, options);
        check(&tagged, options.with_crease_method(subdiv_stencil::CreaseMethod::Chaikin));
    }

    /// A step applied to a level's rows gives the bits of refining that
    /// level directly, and its key tells structures apart: three levels
    /// down every child of every face (irregular vertices, n-gons, semi-sharp
    /// and sharp tags decaying), each step computed on the identity.
    #[test]
    fn a_step_applied_is_the_level_refined() {
        let options = Options::new(Scheme::CatmullClark);
        let cube = shapes::cube();
        let mut e = vec![0f32; cube.topology().edge_count()];
        (e[0], e[1], e[4]) = (1.5, 10.0, 0.5);
        let tagged = cube.clone().with_tags(Tags::from_arrays(cube.topology(), e, Vec::new()).unwrap());
        let mix = shapes::polygon_mix(&shapes::torus(5, 4), 3, 0.25, 0.25, 0.1);
        let child_cell = |l: &Local, _: &Refined, face: FaceId, k: usize| {
            Ok((FaceId(l.t.faces().offsets()[face.index()] + k as u32), 0))
        };
        let mut keys = std::collections::HashSet::new();
        for mesh in [&tagged, &mix] {
            let t = mesh.topology();
            for f in t.face_ids().filter(|&f| t.face_size(f) == 4) {
                let mut level = Root::new(t, mesh.tags(), &options, f).unwrap().local;
                for _ in 0..3 {
                    let k = 2;
                    let refined = level.refine(&options).unwrap();
                    let (child, _) = child_cell(&level, &refined, FaceId(0), k).unwrap();
                    let (direct, _) = refined.ring(&options, child).unwrap();
                    let stepped = level.apply(&level.step(&options, FaceId(0), k, child_cell).unwrap());
                    assert_eq!(stepped.t.faces(), direct.t.faces());
                    assert_eq!(stepped.sharp.tags(&stepped.t), direct.sharp.tags(&direct.t));
                    let same = stepped.rows.iter().zip(&direct.rows).all(|(a, b)| a.to_bits() == b.to_bits());
                    assert!(same && stepped.rows.len() == direct.rows.len(), "face {f:?}: rows differ");
                    keys.insert(level.step_key(FaceId(0), k));
                    level = direct;
                }
            }
        }
        // Structures repeat (the cache's point) but are told apart.
        assert!(keys.len() > 10, "{} structures", keys.len());
    }
}
