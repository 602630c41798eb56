//! Every f64/f32 reference of the harness, written independently of the
//! firmware: `log2 Pb`, the test RNG, the GPU-style sampler's f64 reference and its test
//! textures in every texel format, the f32 texture filters of the bench and
//! the bench workload, the environment-map lod and mapping, the ray differentials.

pub mod envmap;
mod pb;
pub mod raydiff;
mod rng;
pub mod sampler_ref;
pub mod texf32;
pub mod texformat;
pub mod workload;

pub use pb::log2_pb_f64;
pub use rng::Rng;
