//! Host harness for raymip: f64 references, scene loaders, renderer.
#![warn(missing_docs)]
pub mod aff;
pub mod ppm;
pub mod sample;
pub mod texf32;
