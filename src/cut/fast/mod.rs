//! The cut's speed machinery: the candidate grid and its whole-mesh passes (with their SIMD
//! forms), radix sorts, scheduling helpers and step timings.

#[cfg(target_arch = "x86_64")]
pub(crate) mod codes_simd;
#[cfg(target_arch = "x86_64")]
pub(crate) mod faces_simd;
pub(crate) mod grid;
pub(crate) mod radix;
pub(crate) mod schedule;
pub(crate) mod trace;
