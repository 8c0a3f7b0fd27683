//! Index newtypes. `u32` inside, with an `INVALID` value; no raw `usize` in public signatures.

macro_rules! id_type {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
        #[repr(transparent)]
        pub struct $name(pub u32);

        impl $name {
            /// The "no element" value.
            pub const INVALID: $name = $name(u32::MAX);

            /// The index as `usize`, for indexing arrays.
            #[inline]
            pub fn idx(self) -> usize {
                self.0 as usize
            }

            /// Whether this is not [`Self::INVALID`].
            #[inline]
            pub fn is_valid(self) -> bool {
                self.0 != u32::MAX
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
    /// A vertex of a [`crate::PolyMesh`].
    VertexId
);
id_type!(
    /// A half-edge of a [`crate::Topology`]; its twin is `h ^ 1`.
    HalfedgeId
);
id_type!(
    /// An undirected edge of a [`crate::Topology`]; its half-edges are `2e` and `2e + 1`.
    EdgeId
);
id_type!(
    /// A face of a [`crate::PolyMesh`].
    FaceId
);
id_type!(
    /// A loop (outer boundary or hole) of a face, numbered across the whole mesh.
    LoopId
);

// Other modules (curved meshing) declare their own handles with the same macro.
pub(crate) use id_type;
