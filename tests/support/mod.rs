//! Helpers shared by the integration tests: the test models and the corpus, property tests
//! that count their cases, and the record `cargo xtask test` summarises. Each test file
//! uses part of it.
#![allow(dead_code, unused_macros, unused_imports)]

pub mod boss;
pub mod fuzz;
pub mod models;
pub mod property;
pub mod record;
