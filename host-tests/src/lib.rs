//! Host harness for raymip: f64 references, scene loaders, renderer, CLI.
#![warn(missing_docs)]
// No function over 100 lines (clippy counts code lines; the default limit).
#![warn(clippy::too_many_lines)]
#![allow(clippy::needless_range_loop)]

pub mod cli;
pub mod error;
pub mod raydiff_chains;
pub mod reference;
pub mod render;
pub mod scene;
pub mod tradeoff;
