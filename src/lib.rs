//! # katachi (形, "shape")
//!
//! A mesh-modelling kernel: solid-aware Catmull-Clark subdivision ([`subdivide`], seed 001),
//! the stroke cut ([`cut`], seed 002), curved meshing ([`curved`], seed 000) and rough-model
//! editing ([`rough`], seed 003: segmentation from a brushed band and B-spline base-surface
//! fitting so far) over polygon meshes whose faces may have holes ([`mesh`]), with OBJ, PLY and OFF files ([`io`]), shipped as a
//! Rust library, a C library ([`ffi`], `include/katachi.h`), a command-line tool, a Blender
//! add-on and a MeshLab plugin.
//!
//! Every operation is a pure function `op(&PolyMesh, &Options) -> Result<Output, Error>`:
//! it never changes its input, and bad input gets an [`Error`] naming the element at fault.
//!
//! ```
//! use katachi::{mesh::shapes, PolyMesh};
//! let cube: PolyMesh = shapes::cube(1.0).unwrap();
//! let topo = cube.connectivity().unwrap();
//! assert_eq!(topo.edge_count(), 12);
//! assert_eq!(topo.euler_characteristic(&cube), 2);
//! ```

pub mod curved;
pub mod cut;
pub mod error;
pub mod ffi;
pub mod io;
mod mem;
pub mod mesh;
pub mod rough;
pub mod subdivide;

pub use error::{Error, ErrorKind, Result};
pub use glam::DVec3;
pub use mesh::{FaceId, HalfedgeId, PolyMesh, Topology, VertexId};
