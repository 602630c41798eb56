//! C ABI for soft-core firmware written in C (feature `ffi`).
//!
//! Every function is `extern "C"`, takes and returns plain `#[repr(C)]`
//! types or fixed-point values as their raw integer bits, and reports
//! errors as [`RmStatus`] codes. Nothing panics across the boundary: every
//! pointer is checked for null, every length is checked, and the library
//! code behind it is panic-free on these paths (machine-checked by
//! `scripts/link-checks`). The header `include/raymip.h` is generated from
//! this module by `cbindgen` (CI fails when it is stale); the static
//! library is built by the `raymip-ffi` crate (`ffi/`).
//!
//! MIP generation ([`rm_mip_generate`]) runs in place in the caller's
//! buffer, so a C controller can build its pyramids at start-up; it is
//! panic-free like the rest (every access is checked), machine-checked by
//! the same panic-never link.
//!
//! # Number formats (raw bits)
//!
//! | value | Rust type | C type |
//! |---|---|---|
//! | position, UV, texture coordinate | I32F32 | `int64_t` |
//! | path length `Pl`, hit distance `t` | U32F32 | `uint64_t` |
//! | cone width | I32F32 | `int64_t` |
//! | spread angle (radians) | I2F30 | `int32_t` |
//! | table entry `log2 Pb`, `Δ` | I16F16 | `int32_t` (`RM_UNTEXTURED` = `INT32_MIN`) |
//! | level of detail | I8F8 | `int16_t` |
//! | `|n·d|` | U1F31 | `uint32_t` |
//! | texel | RGBA8888 | `uint32_t` (little-endian bytes r, g, b, a) |
//!
//! # Safety
//!
//! With the co-processor wrappers ([`crate::coproc`]) and the texel reads
//! of the level views ([`crate::texture::storage::pow2`]), this is the only
//! code with `unsafe` (the crate is `#![deny(unsafe_code)]`, each of these
//! modules allowing it with its safety argument): turning caller pointers
//! into references and slices. Each function documents what the caller
//! guarantees: non-null pointers (null is checked and reported), pointing to the stated number of valid,
//! aligned, initialised elements. A pointer that is not aligned for its
//! type is reported ([`RmStatus::Misaligned`]) and never dereferenced.
//! Inputs are read before outputs are written, so an input may point into
//! an output (pushing an entry of the same ray stack is allowed).
#![allow(unsafe_code)]

// One module per stage, in pipeline order (cbindgen writes the header in
// this order): status codes and byte enums, set-up, lod, path state,
// texture storage, sampling. Every item is re-exported here: C sees one
// flat namespace, and so does Rust (`raymip::ffi::rm_sample`).
mod status;
pub use status::*;
mod table;
pub use table::*;
mod lod;
pub use lod::*;
mod raystack;
pub use raystack::*;
mod mip;
pub use mip::*;
mod sampler;
pub use sampler::*;

#[cfg(test)]
mod tests;
