//! Plain-data entry points: a [`Mesh`] from arrays of coordinates and of
//! vertex indices ([`Mesh::from_arrays`]), and back
//! ([`Mesh::positions_to_arrays`], [`Mesh::faces_as_csr`]).
//!
//! Faces come in the shapes other libraries hand them out ([`FaceArrays`]):
//! fixed-size faces (`&[[u32; 3]]`, `&[[usize; 4]]`, a flat index buffer),
//! one `Vec` per face, or CSR offsets and indices. They are converted to the
//! crate's [`FaceList`] (what needs no vertex count: `u32` overflow and the
//! CSR structure is checked there), then validated by [`Mesh::from_soup`]
//! like any file's faces. No input makes this panic.

use crate::error::{MeshError, Warning};
use crate::mesh::Mesh;
use crate::soup::{FaceList, PolygonSoup};
use glam::DVec3;

/// Limit on faces and corners: what [`crate::Topology::new`] accepts
/// (`u32` ids, one value kept free as a marker).
const MAX_ELEMENTS: usize = u32::MAX as usize - 1;

/// A borrowed array of vertex indices or offsets, as `u32` or `usize`: what
/// [`FaceArrays::csr`] and [`FaceArrays::uniform`] take. Built by `From`
/// from `&[u32]`, `&[usize]`, `&Vec<_>` and `&[_; N]` of either.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IndexSlice<'a>(Ints<'a>);

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Ints<'a> {
    U32(&'a [u32]),
    Usize(&'a [usize]),
}

impl Ints<'_> {
    fn len(self) -> usize {
        match self {
            Ints::U32(s) => s.len(),
            Ints::Usize(s) => s.len(),
        }
    }

    fn get(self, i: usize) -> usize {
        match self {
            Ints::U32(s) => s[i] as usize,
            Ints::Usize(s) => s[i],
        }
    }

    /// The values as `u32`; the first that does not fit is
    /// [`MeshError::IndexTooLarge`] in face `face_of(position)`.
    fn to_u32(self, face_of: impl Fn(usize) -> usize) -> Result<Vec<u32>, MeshError> {
        match self {
            Ints::U32(s) => Ok(s.to_vec()),
            Ints::Usize(s) => s
                .iter()
                .enumerate()
                .map(|(k, &index)| {
                    u32::try_from(index).map_err(|_| MeshError::IndexTooLarge { face: face_of(k) as u32, index })
                })
                .collect(),
        }
    }
}

/// Faces as plain data, borrowed: the argument of [`Mesh::from_arrays`].
/// Vertex indices are 0-based, `u32` or `usize`; faces have any number of
/// corners (a face needs 3, which [`Mesh::from_soup`] checks).
///
/// Built by `From` (so that `Mesh::from_arrays` takes any of these
/// directly) from
/// - fixed-size faces: `&[[u32; N]]`, `&[[usize; N]]` (triangles, quads, …),
///   also as `&Vec<[_; N]>` and `&[[_; N]; M]`;
/// - one vector per face: `&[Vec<u32>]`, `&[Vec<usize>]`, also as
///   `&Vec<Vec<_>>` and `&[Vec<_>; M]`;
/// - a [`FaceList`];
///
/// and by [`FaceArrays::csr`] (offsets and indices) and
/// [`FaceArrays::uniform`] (a flat index buffer of faces of one size).
///
/// ```
/// use subdiv_mesh::{FaceArrays, FaceList};
/// let quads = [[0u32, 1, 2, 3], [3, 2, 4, 5]];
/// let list = FaceArrays::from(&quads).to_face_list()?;
/// assert_eq!(list, FaceList::from_faces(quads));
/// let csr = FaceArrays::csr(&[0usize, 4, 8], &[0usize, 1, 2, 3, 3, 2, 4, 5]);
/// assert_eq!(csr.to_face_list()?, list);
/// let flat = FaceArrays::uniform(4, &[0u32, 1, 2, 3, 3, 2, 4, 5]);
/// assert_eq!(flat.to_face_list()?, list);
/// let nested = vec![vec![0usize, 1, 2, 3], vec![3, 2, 4, 5]];
/// assert_eq!(FaceArrays::from(&nested).to_face_list()?, list);
/// # Ok::<(), subdiv_mesh::MeshError>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct FaceArrays<'a>(Layout<'a>);

#[derive(Clone, Copy, Debug)]
enum Layout<'a> {
    /// `faces` faces of `size` corners each, corner after corner.
    Uniform {
        faces: usize,
        size: usize,
        indices: Ints<'a>,
    },
    /// Faces of `size` corners each, their number to be derived from the
    /// length of `indices` (which may not be a multiple of `size`).
    Flat {
        size: usize,
        indices: Ints<'a>,
    },
    NestedU32(&'a [Vec<u32>]),
    NestedUsize(&'a [Vec<usize>]),
    /// Face `f` is `indices[offsets[f]..offsets[f + 1]]`.
    Csr {
        offsets: Ints<'a>,
        indices: Ints<'a>,
    },
    List(&'a FaceList),
}

impl<'a> FaceArrays<'a> {
    /// Faces in CSR form: face `f` is `indices[offsets[f]..offsets[f + 1]]`,
    /// so `offsets` has one entry more than there are faces, starts at 0,
    /// never decreases and ends at `indices.len()`. Offsets and indices are
    /// `u32` or `usize` arrays, independently (see [`IndexSlice`]).
    ///
    /// Checked when converted: [`MeshError::OffsetsEmpty`],
    /// [`MeshError::OffsetsStart`], [`MeshError::OffsetsDecrease`],
    /// [`MeshError::OffsetsEnd`].
    pub fn csr(offsets: impl Into<IndexSlice<'a>>, indices: impl Into<IndexSlice<'a>>) -> Self {
        Self(Layout::Csr { offsets: offsets.into().0, indices: indices.into().0 })
    }

    /// Faces of `size` corners each in one flat index array (a GPU index
    /// buffer: `size` 3 for triangles), face `f` being
    /// `indices[f·size..(f + 1)·size]`.
    ///
    /// Checked when converted: [`MeshError::UniformIndexCount`] when the
    /// length is not a multiple of `size`, or `size` is 0.
    pub fn uniform(size: usize, indices: impl Into<IndexSlice<'a>>) -> Self {
        Self(Layout::Flat { size, indices: indices.into().0 })
    }

    /// The faces as a [`FaceList`] (`u32` CSR), unvalidated but for what the
    /// conversion needs: the CSR structure ([`Self::csr`]), the length of a
    /// flat array ([`Self::uniform`]), indices that fit `u32`
    /// ([`MeshError::IndexTooLarge`]) and at most 2³² − 2 faces and corners
    /// ([`MeshError::TooLarge`]). Everything else (face sizes, index range,
    /// repeats, manifoldness) is [`Mesh::from_soup`]'s.
    ///
    /// # Errors
    /// Those named above, the first one met.
    pub fn to_face_list(&self) -> Result<FaceList, MeshError> {
        match self.0 {
            Layout::List(list) => Ok(list.clone()),
            Layout::Uniform { faces, size, indices } => uniform(faces, size, indices),
            Layout::Flat { size, indices } => {
                let n = indices.len();
                if size == 0 || n % size != 0 {
                    return Err(MeshError::UniformIndexCount { size, indices: n });
                }
                uniform(n / size, size, indices)
            }
            Layout::NestedU32(faces) => nested(faces),
            Layout::NestedUsize(faces) => nested(faces),
            Layout::Csr { offsets, indices } => csr(offsets, indices),
        }
    }
}

/// Refuses more faces or corners than a [`crate::Topology`] can number.
fn check_counts(faces: usize, corners: usize) -> Result<(), MeshError> {
    if corners > MAX_ELEMENTS {
        return Err(MeshError::TooLarge { what: "more than 2³² − 2 corners" });
    }
    if faces > MAX_ELEMENTS {
        return Err(MeshError::TooLarge { what: "more than 2³² − 2 faces" });
    }
    Ok(())
}

fn uniform(faces: usize, size: usize, indices: Ints<'_>) -> Result<FaceList, MeshError> {
    check_counts(faces, indices.len())?;
    // A corner exists only when size > 0, so the division is safe.
    let indices = indices.to_u32(|corner| corner / size)?;
    let offsets = (0..=faces).map(|f| (f * size) as u32).collect();
    Ok(FaceList::from_raw(offsets, indices))
}

/// An index type of plain-data faces.
trait Index: Copy {
    fn to_u32(self) -> Option<u32>;
    fn to_usize(self) -> usize;
}

impl Index for u32 {
    fn to_u32(self) -> Option<u32> {
        Some(self)
    }
    fn to_usize(self) -> usize {
        self as usize
    }
}

impl Index for usize {
    fn to_u32(self) -> Option<u32> {
        u32::try_from(self).ok()
    }
    fn to_usize(self) -> usize {
        self
    }
}

fn nested<T: Index>(faces: &[Vec<T>]) -> Result<FaceList, MeshError> {
    // The vectors are all in memory: their total length cannot overflow.
    let corners = faces.iter().map(Vec::len).sum();
    check_counts(faces.len(), corners)?;
    let mut offsets = Vec::with_capacity(faces.len() + 1);
    let mut indices = Vec::with_capacity(corners);
    offsets.push(0);
    for (f, face) in faces.iter().enumerate() {
        for &v in face {
            let index = v.to_u32().ok_or(MeshError::IndexTooLarge { face: f as u32, index: v.to_usize() })?;
            indices.push(index);
        }
        offsets.push(indices.len() as u32);
    }
    Ok(FaceList::from_raw(offsets, indices))
}

fn csr(offsets: Ints<'_>, indices: Ints<'_>) -> Result<FaceList, MeshError> {
    let n = indices.len();
    let Some(faces) = offsets.len().checked_sub(1) else { return Err(MeshError::OffsetsEmpty) };
    let first = offsets.get(0);
    if first != 0 {
        return Err(MeshError::OffsetsStart { first });
    }
    for face in 0..faces {
        let (start, end) = (offsets.get(face), offsets.get(face + 1));
        if end < start {
            return Err(MeshError::OffsetsDecrease { face, start, end });
        }
    }
    let last = offsets.get(faces);
    if last != n {
        return Err(MeshError::OffsetsEnd { last, indices: n });
    }
    check_counts(faces, n)?;
    // Corner k lies in the last face starting at or before it (empty faces
    // start where the next one does); searched only for an error message.
    let face_of = |k: usize| {
        let (mut lo, mut hi) = (0, faces);
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if offsets.get(mid) <= k {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    };
    let indices = indices.to_u32(face_of)?;
    // Every offset is ≤ n ≤ 2³² − 2 now.
    let offsets = (0..=faces).map(|f| offsets.get(f) as u32).collect();
    Ok(FaceList::from_raw(offsets, indices))
}

macro_rules! from_plain_data {
    ($t:ty, $ints:ident, $nested:ident) => {
        impl<'a> From<&'a [$t]> for IndexSlice<'a> {
            fn from(values: &'a [$t]) -> Self {
                Self(Ints::$ints(values))
            }
        }
        impl<'a> From<&'a Vec<$t>> for IndexSlice<'a> {
            fn from(values: &'a Vec<$t>) -> Self {
                values.as_slice().into()
            }
        }
        impl<'a, const M: usize> From<&'a [$t; M]> for IndexSlice<'a> {
            fn from(values: &'a [$t; M]) -> Self {
                values.as_slice().into()
            }
        }
        impl<'a, const N: usize> From<&'a [[$t; N]]> for FaceArrays<'a> {
            /// Faces of `N` corners each.
            fn from(faces: &'a [[$t; N]]) -> Self {
                Self(Layout::Uniform { faces: faces.len(), size: N, indices: Ints::$ints(faces.as_flattened()) })
            }
        }
        impl<'a, const N: usize> From<&'a Vec<[$t; N]>> for FaceArrays<'a> {
            /// Faces of `N` corners each.
            fn from(faces: &'a Vec<[$t; N]>) -> Self {
                faces.as_slice().into()
            }
        }
        impl<'a, const N: usize, const M: usize> From<&'a [[$t; N]; M]> for FaceArrays<'a> {
            /// `M` faces of `N` corners each.
            fn from(faces: &'a [[$t; N]; M]) -> Self {
                faces.as_slice().into()
            }
        }
        impl<'a> From<&'a [Vec<$t>]> for FaceArrays<'a> {
            /// One vector of vertex indices per face.
            fn from(faces: &'a [Vec<$t>]) -> Self {
                Self(Layout::$nested(faces))
            }
        }
        impl<'a> From<&'a Vec<Vec<$t>>> for FaceArrays<'a> {
            /// One vector of vertex indices per face.
            fn from(faces: &'a Vec<Vec<$t>>) -> Self {
                faces.as_slice().into()
            }
        }
        impl<'a, const M: usize> From<&'a [Vec<$t>; M]> for FaceArrays<'a> {
            /// One vector of vertex indices per face.
            fn from(faces: &'a [Vec<$t>; M]) -> Self {
                faces.as_slice().into()
            }
        }
    };
}

from_plain_data!(u32, U32, NestedU32);
from_plain_data!(usize, Usize, NestedUsize);

impl<'a> From<&'a FaceList> for FaceArrays<'a> {
    /// The faces of a face list (converted by a copy).
    fn from(faces: &'a FaceList) -> Self {
        Self(Layout::List(faces))
    }
}

impl PolygonSoup {
    /// A soup of plain-data positions and faces, unvalidated but for what
    /// the conversion checks ([`FaceArrays::to_face_list`]): validate it with
    /// [`Mesh::from_soup`] to get the warnings too (isolated vertices,
    /// zero-area faces), which [`Mesh::from_arrays`] leaves out.
    ///
    /// ```
    /// use subdiv_mesh::{Mesh, PolygonSoup, Warning};
    /// // A triangle and a vertex no face uses.
    /// let soup = PolygonSoup::from_arrays(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [5.0; 3]], &[[0u32, 1, 2]])?;
    /// let (mesh, warnings) = Mesh::from_soup(soup)?;
    /// assert_eq!(warnings, [Warning::IsolatedVertices { vertices: vec![3] }]);
    /// assert_eq!(mesh.topology().face_count(), 1);
    /// # Ok::<(), subdiv_mesh::MeshError>(())
    /// ```
    ///
    /// # Errors
    /// Those of [`FaceArrays::to_face_list`].
    pub fn from_arrays<'a>(positions: &[[f64; 3]], faces: impl Into<FaceArrays<'a>>) -> Result<Self, MeshError> {
        let faces = faces.into().to_face_list()?;
        Ok(Self::new(positions.iter().map(|&p| DVec3::from_array(p)).collect(), faces))
    }
}

impl Mesh {
    /// A validated mesh from plain data: one `[x, y, z]` per vertex, and
    /// faces as 0-based vertex indices in any of the forms of [`FaceArrays`]
    /// (`&[[u32; 3]]`, `&[[usize; 4]]`, `&[Vec<u32>]`, CSR, …), oriented
    /// consistently (counter-clockwise seen from outside makes the normals
    /// point outwards). Warnings are dropped; [`PolygonSoup::from_arrays`]
    /// with [`Mesh::from_soup`] keeps them.
    ///
    /// ```
    /// use subdiv_mesh::{FaceArrays, Mesh, MeshError};
    /// // A square pyramid: four triangles and the quad base.
    /// let positions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.5, 0.5, 1.0]];
    /// let faces = vec![vec![0u32, 1, 4], vec![1, 2, 4], vec![2, 3, 4], vec![3, 0, 4], vec![0, 3, 2, 1]];
    /// let mesh = Mesh::from_arrays(&positions, &faces)?;
    /// assert!(mesh.topology().is_closed());
    /// assert_eq!(mesh.topology().genus(), Some(0));
    ///
    /// // The same faces in CSR form, and back.
    /// let offsets = [0usize, 3, 6, 9, 12, 16];
    /// let indices = [0u32, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4, 0, 3, 2, 1];
    /// let same = Mesh::from_arrays(&positions, FaceArrays::csr(&offsets, &indices))?;
    /// assert_eq!(same.faces_as_csr(), (&[0u32, 3, 6, 9, 12, 16][..], &indices[..]));
    /// assert_eq!(same.positions_to_arrays(), positions);
    ///
    /// // Malformed input is an error, never a panic.
    /// let e = Mesh::from_arrays(&positions, &[[0u32, 1, 7]]).unwrap_err();
    /// assert_eq!(e, MeshError::IndexOutOfRange { face: 0, vertex: 7, vertex_count: 5 });
    /// let e = Mesh::from_arrays(&positions, FaceArrays::csr(&[0usize, 3, 2], &indices[..3])).unwrap_err();
    /// assert!(matches!(e, MeshError::OffsetsDecrease { face: 1, .. }));
    /// # Ok::<(), MeshError>(())
    /// ```
    ///
    /// # Errors
    /// Those of [`FaceArrays::to_face_list`] (malformed CSR offsets, indices
    /// beyond `u32`), then those of [`Mesh::from_soup`]: no faces, a face of
    /// fewer than 3 corners, an index out of range or repeated in a face, a
    /// non-finite coordinate, a non-manifold edge or vertex, inconsistent
    /// orientation, all vertices at one point.
    pub fn from_arrays<'a>(positions: &[[f64; 3]], faces: impl Into<FaceArrays<'a>>) -> Result<Self, MeshError> {
        Self::from_soup(PolygonSoup::from_arrays(positions, faces)?).map(|(mesh, _)| mesh)
    }

    /// [`Mesh::from_arrays`], also returning the warning-level defects
    /// ([`Mesh::warnings`]: isolated vertices, zero-area faces).
    ///
    /// # Errors
    /// Those of [`Mesh::from_arrays`].
    pub fn from_arrays_with_warnings<'a>(
        positions: &[[f64; 3]],
        faces: impl Into<FaceArrays<'a>>,
    ) -> Result<(Self, Vec<Warning>), MeshError> {
        Self::from_soup(PolygonSoup::from_arrays(positions, faces)?)
    }

    /// The vertex positions as `[x, y, z]` arrays (a copy: the mesh keeps
    /// [`DVec3`]s, [`Mesh::positions`]).
    pub fn positions_to_arrays(&self) -> Vec<[f64; 3]> {
        self.positions().iter().map(|p| p.to_array()).collect()
    }

    /// The faces in CSR form, borrowed: `(offsets, indices)`, face `f` being
    /// `indices[offsets[f]..offsets[f + 1]]` (`offsets` has one entry more
    /// than there are faces, the first 0, the last the corner count). What
    /// [`FaceArrays::csr`] takes back.
    pub fn faces_as_csr(&self) -> (&[u32], &[u32]) {
        let faces = self.topology().faces();
        (faces.offsets(), faces.indices())
    }

    /// The faces as one vector of vertex indices each (a copy; see
    /// [`Mesh::faces_as_csr`] for the borrowed form).
    pub fn faces_to_vecs(&self) -> Vec<Vec<u32>> {
        self.topology().faces().iter().map(<[u32]>::to_vec).collect()
    }
}
