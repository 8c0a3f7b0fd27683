//! The mesh: [`PolyMesh`] (faces with holes and attributes), its validation, and its
//! half-edge [`Topology`].

mod attributes;
pub mod holes;
mod ids;
mod inspect;
mod polymesh;
pub mod shapes;
mod topology;
pub(crate) mod validate;

pub use attributes::INFINITELY_SHARP;
pub(crate) use ids::id_type;
pub use ids::{EdgeId, FaceId, HalfedgeId, LoopId, VertexId};
pub use inspect::{inspect, MeshReport};
pub use polymesh::PolyMesh;
pub use topology::{Defects, HalfedgeRef, LoopWalk, Outgoing, Topology, TopologyOptions};
