//! The C ABI, declared in `include/katachi.h` (generated from this module by the pinned
//! cbindgen: `cargo xtask header`).
//!
//! One file per kernel module ([`mesh`], [`inspect`], [`io`], [`subdivide`], [`cut`] and its
//! host layout [`cut_polygons`], [`curved`]) plus
//! the frame ([`status`], [`version`] and the private `boundary`), and nothing but conversion
//! and error mapping:
//!
//! - every function returns a `KatachiStatus` (a few return a value that cannot fail), and
//!   `katachi_last_error_message()` gives the calling thread's last message;
//! - every exported function runs inside a panic boundary (`catch_unwind`): a panic comes
//!   back as `KATACHI_STATUS_INTERNAL_ERROR` with the panic's text, and no panic hook is
//!   installed;
//! - pointers are checked for NULL (the message names the parameter), arrays come with counts,
//!   results are read with count + copy-into-caller-buffer calls, and structs katachi fills in
//!   start with `uint32_t struct_size`;
//! - on failure, out-handles are NULL, caller buffers and structs unchanged, and input meshes
//!   untouched.

// The frame. (Blank lines keep rustfmt from sorting the modules: cbindgen emits items in
// this order.)
mod boundary;

pub mod status;

pub mod version;

// One file per kernel module.
pub mod mesh;

pub mod inspect;

pub mod io;

pub mod subdivide;

pub mod cut;

pub mod cut_polygons;

pub mod curved;

pub use curved::*;
pub use cut::*;
pub use cut_polygons::*;
pub use inspect::*;
pub use io::*;
pub use mesh::*;
pub use status::*;
pub use subdivide::*;
pub use version::*;
