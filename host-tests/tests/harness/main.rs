//! The harness's integration tests, one module per topic, in one test
//! binary: one compile and one link of the harness instead of one per file
//! (the host-test step of `scripts/test-all` is mostly that build). A
//! single topic runs with its path as the filter, e.g.
//! `cargo test --release -p raymip-host --test harness tracer::`.

mod aff_errors;
mod aff_scenes;
mod aniso_render;
mod bart_load;
mod bart_render;
mod bc_decode;
mod cli_render;
mod demo_scene;
mod geomlod;
mod raydiff_chains;
mod skipping;
mod stress;
mod texture_f32;
mod texture_sample_cmd;
mod texture_sampler_accuracy;
mod tracer;
mod tradeoff;
