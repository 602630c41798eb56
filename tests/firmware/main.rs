//! The firmware crate's integration tests (against f64 references written
//! here), one module per topic, in one test binary: one compile and link
//! instead of one per file. A single topic runs with its path as the
//! filter, e.g. `cargo test --release -p raymip --test firmware lod_accuracy::`.

mod common;
mod doc_tables;
mod layering;
mod lod_accuracy;
mod sampler_golden;
mod texture_accuracy;
mod texture_cache;
mod texture_mip;
