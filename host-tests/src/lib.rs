//! Host harness for raymip: f64 references, scene loaders, renderer.
#![warn(missing_docs)]
pub mod demo_data;
pub mod ppm;
