//! Typed `u32` ids, so a vertex index is never passed where a face index is meant.

macro_rules! id_type {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub struct $name(pub u32);

        impl $name {
            /// The id as an index into per-element arrays.
            #[inline]
            pub fn index(self) -> usize {
                self.0 as usize
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, "{}", self.0)
            }
        }
    };
}

id_type!(
    /// A vertex: index into the position array (0-based, file order).
    VertexId
);
id_type!(
    /// A face: index into the face list.
    FaceId
);
id_type!(
    /// A half-edge: a face corner `k` of face `f`, directed from corner `k` to
    /// corner `k + 1`. Half-edges of a face are numbered contiguously, so the
    /// id equals the corner's position in [`crate::FaceList::indices`].
    HalfEdgeId
);
id_type!(
    /// An undirected edge.
    EdgeId
);
