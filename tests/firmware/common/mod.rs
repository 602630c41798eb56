//! Helpers shared by the integration tests (`mod common;` in each): the
//! harness's one test RNG, f64 `log2 Pb` and random test texture, included
//! from their home in `host-tests/src/reference`.
#![allow(dead_code, unused_imports)]

#[path = "../../../host-tests/src/reference/pb.rs"]
mod pb;
#[path = "../../../host-tests/src/reference/rng.rs"]
mod rng;
#[path = "../../../host-tests/src/reference/workload.rs"]
mod workload;

pub use pb::log2_pb_f64;
pub use rng::Rng;
pub use workload::random_texture;
