//! The C ABI (`src/ffi`) compiled a second time, against katachi's *public* API: this crate's
//! root stands in for katachi's (`crate::mesh` is `katachi::mesh`, and so on), so a C
//! function that reached into a crate-private item would not compile here. Only checked
//! (`cargo clippy --workspace` in `cargo xtask test`), never linked: the exported symbols are
//! katachi's, so the module is left out of this crate's own test build, which links.

#![allow(dead_code, clippy::all)]

pub use katachi::{curved, cut, error, io, mesh, subdivide};
pub use katachi::{
    DVec3, Error, ErrorKind, FaceId, HalfedgeId, PolyMesh, Result, Topology, VertexId,
};

#[cfg(not(test))]
#[path = "../../../src/ffi/mod.rs"]
pub mod ffi;
