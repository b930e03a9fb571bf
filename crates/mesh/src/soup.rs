//! Unvalidated polygon data: what a file holds before we trust it.

use crate::tags::{FaceVarying, TagList};
use glam::DVec3;

/// Faces of any size stored contiguously (CSR): face `f` is
/// `indices[offsets[f]..offsets[f + 1]]`.
///
/// One allocation for all faces instead of a `Vec` per face; this is the
/// layout every other crate of the workspace reads faces in.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FaceList {
    offsets: Vec<u32>,
    indices: Vec<u32>,
}

impl Default for FaceList {
    fn default() -> Self {
        Self::new()
    }
}

impl FaceList {
    /// An empty face list.
    pub fn new() -> Self {
        Self { offsets: vec![0], indices: Vec::new() }
    }

    /// An empty face list with room for `faces` faces and `corners` corners.
    pub fn with_capacity(faces: usize, corners: usize) -> Self {
        let mut offsets = Vec::with_capacity(faces + 1);
        offsets.push(0);
        Self { offsets, indices: Vec::with_capacity(corners) }
    }

    /// Builds a face list from per-face slices (convenient in tests and shapes).
    pub fn from_faces<F: AsRef<[u32]>>(faces: impl IntoIterator<Item = F>) -> Self {
        let mut list = Self::new();
        for face in faces {
            list.push(face.as_ref());
        }
        list
    }

    /// Builds a face list of `faces.len() / size` faces that all have `size` corners.
    ///
    /// # Panics
    /// If `faces.len()` is not a multiple of `size` (a caller bug, not user data).
    pub fn from_uniform(size: usize, faces: Vec<u32>) -> Self {
        assert!(size > 0 && faces.len() % size == 0, "uniform face list length mismatch");
        let offsets = (0..=faces.len() / size).map(|f| (f * size) as u32).collect();
        Self { offsets, indices: faces }
    }

    /// Builds a face list from raw CSR arrays.
    ///
    /// # Panics
    /// If `offsets` is empty, does not start at 0, decreases, or does not end at
    /// `indices.len()` (a caller bug, not user data).
    pub fn from_raw(offsets: Vec<u32>, indices: Vec<u32>) -> Self {
        assert!(
            offsets.first() == Some(&0)
                && offsets.last().map(|&l| l as usize) == Some(indices.len())
                && offsets.windows(2).all(|w| w[0] <= w[1]),
            "malformed CSR face offsets"
        );
        Self { offsets, indices }
    }

    /// Appends one face.
    pub fn push(&mut self, face: &[u32]) {
        self.indices.extend_from_slice(face);
        self.offsets.push(self.indices.len() as u32);
    }

    /// Number of faces.
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    /// True when there are no faces.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The vertex indices of face `f`, in order.
    #[inline]
    pub fn face(&self, f: usize) -> &[u32] {
        &self.indices[self.offsets[f] as usize..self.offsets[f + 1] as usize]
    }

    /// Number of corners of face `f`.
    #[inline]
    pub fn face_size(&self, f: usize) -> usize {
        (self.offsets[f + 1] - self.offsets[f]) as usize
    }

    /// Iterates over the faces in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = &[u32]> + '_ {
        self.offsets.windows(2).map(|w| &self.indices[w[0] as usize..w[1] as usize])
    }

    /// CSR offsets: `len() + 1` entries, the first 0, the last `corner_count()`.
    #[inline]
    pub fn offsets(&self) -> &[u32] {
        &self.offsets
    }

    /// All corners of all faces, face after face.
    #[inline]
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }

    /// Total number of corners (= half-edges of a manifold mesh).
    pub fn corner_count(&self) -> usize {
        self.indices.len()
    }

    /// Histogram face size → number of faces.
    pub fn size_histogram(&self) -> std::collections::BTreeMap<usize, usize> {
        crate::topology::histogram(self.len(), |f| self.face_size(f))
    }

    /// True when every face has exactly `size` corners.
    pub fn all_of_size(&self, size: usize) -> bool {
        self.offsets.windows(2).all(|w| (w[1] - w[0]) as usize == size)
    }
}

/// Named groups of faces (OBJ `g`/`o` names), used e.g. to set a shape parameter
/// on a region. `face_group[f]` indexes `names`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FaceGroups {
    /// Group names, in order of first appearance.
    pub names: Vec<String>,
    /// For every face, the index into `names` of its group.
    pub face_group: Vec<u32>,
}

/// Positions and faces as read from a file, before validation.
///
/// Nothing here is trusted: indices may be out of range, coordinates may be
/// NaN, faces may be degenerate. [`crate::Mesh::from_soup`] validates it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolygonSoup {
    /// Vertex positions, in file order.
    pub positions: Vec<DVec3>,
    /// Faces as 0-based vertex indices.
    pub faces: FaceList,
    /// Optional face groups (empty `names` when the format has none).
    pub groups: FaceGroups,
    /// Crease and corner tags by vertex index (empty when the file has none).
    pub tags: TagList,
    /// Texture coordinates as a face-varying channel, when the file has them.
    pub uvs: Option<FaceVarying>,
}

impl PolygonSoup {
    /// A soup of the given positions and faces, without groups.
    pub fn new(positions: Vec<DVec3>, faces: FaceList) -> Self {
        Self { positions, faces, ..Self::default() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn face_list_round_trips_mixed_faces() {
        let list = FaceList::from_faces([vec![0u32, 1, 2], vec![2, 1, 3, 4], vec![4, 5, 6, 7, 8]]);
        assert_eq!(list.len(), 3);
        assert_eq!(list.face(1), &[2, 1, 3, 4]);
        assert_eq!(list.face_size(2), 5);
        assert_eq!(list.corner_count(), 12);
        let collected: Vec<Vec<u32>> = list.iter().map(<[u32]>::to_vec).collect();
        assert_eq!(FaceList::from_faces(collected), list);
        assert!(!list.all_of_size(3));
        assert!(FaceList::from_uniform(3, vec![0, 1, 2, 2, 1, 3]).all_of_size(3));
    }

    #[test]
    #[should_panic(expected = "malformed CSR")]
    fn raw_offsets_must_cover_indices() {
        let _ = FaceList::from_raw(vec![0, 3], vec![0, 1]);
    }
}
