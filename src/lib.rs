//! # raymip
//!
//! Texture level-of-detail, MIP fetch and filtering for the texture unit of a
//! ray-tracing accelerator, in fixed point, for `no_std` controllers.
//!
//! Design principle: everything a scene fixes is computed once at set-up
//! (one `log2 Pb` per textured triangle, the MIP pyramid), so that each ray
//! hit costs one logarithm and one subtraction, then a fetch and a filter,
//! all in integer arithmetic that is bit-identical on every target.
#![no_std]
#![forbid(unsafe_code)]
#![deny(
    missing_docs,
    missing_debug_implementations,
    trivial_casts,
    trivial_numeric_casts,
    rustdoc::broken_intra_doc_links
)]

pub mod lod;
pub mod log2;
pub mod raystack;
pub mod table;
