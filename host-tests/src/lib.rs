//! Host harness for raymip: scene loaders, renderer, CLI, the sampler's
//! accuracy against the f64 references (`raymip-reference`), benchmarks.
//!
//! Floors, top first: `cli`, `tradeoff`, `stress`, `render`, `scene`,
//! `accuracy`, `raydiff_chains`, `output`, `workload`, `error`. Each
//! module uses only its own floor and those after it
//! (`tests/firmware/layering.rs` checks it).
//!
//! Without the default feature `app` only `accuracy`, `raydiff_chains`,
//! the scene types and loaders (`scene::aff`, `scene::ppm`) and
//! `cli::sample` are built: what the fuzz targets call.
#![warn(missing_docs)]
// No function over 100 lines (clippy counts code lines; the default limit).
#![warn(clippy::too_many_lines)]
#![allow(clippy::needless_range_loop)]

pub mod accuracy;
#[cfg(feature = "app")]
pub mod cli;
/// Without the feature `app`: the `sample` command's parser only (the
/// fuzz target `sample_lines`).
#[cfg(not(feature = "app"))]
pub mod cli {
    pub mod sample;
}
#[cfg(feature = "app")]
pub mod error;
#[cfg(feature = "app")]
pub mod output;
pub mod raydiff_chains;
#[cfg(feature = "app")]
pub mod render;
pub mod scene;
#[cfg(feature = "app")]
pub mod stress;
#[cfg(feature = "app")]
pub mod tradeoff;
#[cfg(feature = "app")]
pub mod workload;
