//! Typed `u32` indices for the elements of a [`crate::mesh::Mesh`].

macro_rules! id_type {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub struct $name(pub u32);

        impl $name {
            /// Marker for "no such element" (e.g. the face of a boundary halfedge).
            pub const INVALID: $name = $name(u32::MAX);

            /// The index as `usize`, for indexing per-element arrays.
            #[inline]
            pub fn idx(self) -> usize {
                self.0 as usize
            }

            /// Whether this id refers to an element (is not [`Self::INVALID`]).
            #[inline]
            pub fn is_valid(self) -> bool {
                self.0 != u32::MAX
            }
        }

        impl From<usize> for $name {
            #[inline]
            fn from(i: usize) -> Self {
                debug_assert!(i < u32::MAX as usize);
                $name(i as u32)
            }
        }
    };
}

id_type!(
    /// A vertex of a mesh.
    VertexId
);
id_type!(
    /// A triangle of a mesh.
    FaceId
);
id_type!(
    /// An undirected edge; its two halfedges are `2e` and `2e + 1`.
    EdgeId
);
id_type!(
    /// A directed edge; `h ^ 1` is its twin and `h / 2` its edge.
    HalfedgeId
);
