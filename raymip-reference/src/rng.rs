//! f64 draws from the test inputs' generator. The generators themselves
//! live in `raymip::rng` (xorshift64 for the host tests' inputs beside the
//! firmware's own 32-bit generators); this crate does not depend on
//! `raymip`, so it reads any source of 64-bit words: an
//! `Iterator<Item = u64>`, which `raymip::rng::XorShift64` is.

/// Uniform f64 draws from a never-ending source of 64-bit words.
pub trait Draw {
    /// The next 64 pseudo-random bits.
    fn bits(&mut self) -> u64;

    /// Uniform in [0, 1) with 53 bits (the top 53 of [`bits`](Self::bits)).
    fn unit(&mut self) -> f64 {
        (self.bits() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [`lo`, `hi`).
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

impl<I: Iterator<Item = u64>> Draw for I {
    /// The iterator's next word (0 once it ends, which a generator never does).
    fn bits(&mut self) -> u64 {
        self.next().unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::Draw;

    /// `unit` takes the top 53 bits, `range` scales it.
    #[test]
    fn unit_and_range_scale_the_top_bits() {
        let mut words = [u64::MAX, 0, 1 << 63].into_iter();
        assert_eq!(words.unit(), 1.0 - 2f64.powi(-53));
        assert_eq!(words.range(2.0, 4.0), 2.0);
        assert_eq!(words.range(2.0, 4.0), 3.0);
        assert_eq!(words.bits(), 0);
    }
}
