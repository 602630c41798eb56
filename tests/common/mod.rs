//! Helpers shared by the integration tests (`mod common;` in each): the
//! harness's one test RNG, included from its home in `host-tests`.
#![allow(dead_code)]

#[path = "../../host-tests/src/reference/rng.rs"]
mod rng;

pub use rng::Rng;
