//! Every f64/f32 reference of the harness, written independently of the
//! firmware: the f32 texture filters of the bench, the bench workload.

mod pb;
pub mod texf32;
pub mod workload;

pub use pb::log2_pb_f64;
