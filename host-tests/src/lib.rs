//! Host harness for raymip: f64 references, scene loaders, renderer, CLI.
#![warn(missing_docs)]
#![allow(clippy::needless_range_loop)]

pub mod aff;
pub mod app;
pub mod builtin;
pub mod bvh;
pub mod compare;
pub mod demo_data;
pub mod output;
pub mod ppm;
pub mod render;
pub mod sample;
pub mod sampler_ref;
pub mod scene;
pub mod table1;
pub mod texf32;
pub mod texformat;
pub mod texunit;
pub mod workload;
