//! Host harness for raymip: scene loaders, renderer, CLI, the sampler's
//! accuracy against the f64 references (`raymip-reference`), benchmarks.
//!
//! Floors, top first: `cli`, `tradeoff`, `stress`, `render`, `scene`,
//! `accuracy`, `raydiff_chains`, `output`, `workload`, `error`. Each
//! module uses only its own floor and those after it
//! (`tests/firmware/layering.rs` checks it).
#![warn(missing_docs)]
// No function over 100 lines (clippy counts code lines; the default limit).
#![warn(clippy::too_many_lines)]
#![allow(clippy::needless_range_loop)]

pub mod accuracy;
pub mod cli;
pub mod error;
pub mod output;
pub mod raydiff_chains;
pub mod render;
pub mod scene;
pub mod stress;
pub mod tradeoff;
pub mod workload;
