//! Helpers shared by the integration tests (`mod common;` in each).
#![allow(dead_code)]

/// Deterministic xorshift64 generator (seed must be non-zero).
pub struct Rng(pub u64);

impl Rng {
    /// Next 64 pseudo-random bits.
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// Uniform in [0, 1) with 53 bits.
    pub fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}
