//! The errors of curved meshing live with every other error in [`crate::error`] (the frame
//! knows no algorithm module); this re-export keeps the module's paths short.

pub use crate::error::CurvedError;
