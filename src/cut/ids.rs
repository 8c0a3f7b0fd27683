//! The cut region's three id spaces ([`super::region::Region`]): its vertices, faces and
//! edges are numbered from 0 (ascending global ids for vertices and faces, ascending end
//! pairs for edges), so the steps keep their data in small dense arrays. Each space has its
//! own type, so an id of one is never used as an id of another.

macro_rules! local_id {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
        #[repr(transparent)]
        pub(crate) struct $name(pub u32);

        impl $name {
            /// No element (a missing second face of a boundary edge, an unset entry).
            pub const NONE: $name = $name(u32::MAX);

            /// The id as an array index.
            #[inline]
            pub fn idx(self) -> usize {
                self.0 as usize
            }

            /// Whether this is not [`Self::NONE`].
            #[inline]
            #[allow(dead_code)]
            pub fn is_some(self) -> bool {
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

local_id!(
    /// A vertex of the region: one of its faces' corners, or (from
    /// [`super::region::Region::vertex_count`] on) a vertex the cut adds.
    Lv
);
local_id!(
    /// A face of the region.
    Lf
);
local_id!(
    /// An edge of the region.
    Le
);
