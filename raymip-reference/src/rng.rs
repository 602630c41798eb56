//! The one generator of test inputs: xorshift64 (Marsaglia 2003),
//! deterministic from its seed, the same sequence on every host. Recorded
//! results (the firmware's golden sampler hashes) depend on its sequence.
//! The firmware's own generator for decisions on the controller is
//! `raymip::rng` (32-bit, counter-based): a part of the product, not of the
//! tests.

/// Deterministic xorshift64 generator (the seed must be non-zero).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rng(pub u64);

impl Rng {
    /// Next 64 pseudo-random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// Uniform in [0, 1) with 53 bits.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Fills `out` with the low 32 bits of successive [`next_u64`](Self::next_u64)
    /// values (random texels of a test texture).
    pub fn fill_u32(&mut self, out: &mut [u32]) {
        for w in out {
            *w = self.next_u64() as u32;
        }
    }

    /// Uniform in [`lo`, `hi`).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}
