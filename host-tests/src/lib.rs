//! Host harness for raymip: f64 references, scene loaders, renderer, CLI.
#![warn(missing_docs)]
#![allow(clippy::needless_range_loop)]

pub mod cli;
pub mod reference;
pub mod render;
pub mod scene;
