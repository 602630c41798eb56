//! The crate's deterministic random number generators, for the controller
//! and for measurement and test inputs.
//!
//! [`Rng`] serves per-pixel, per-frame decisions on the controller (the
//! stochastic-LOD ray mask; other stages that need reproducible random
//! choices can share it). The two generators of measurement and test
//! inputs, [`XorShift32`] (the demo firmware's budget and cycle-count
//! inputs) and [`XorShift64`] (the host tests' inputs), are kept here so
//! that every generator has one home; recorded budget rows and golden
//! hashes depend on their sequences.
//!
//! [`Rng`] is counter-based: the state advances by the golden-ratio Weyl constant
//! `0x9E37_79B9` (odd, so the state visits all 2³² values before repeating)
//! and each output is a bijective 32-bit integer hash of the state
//! (xor-shift / multiply finaliser, constants `0x7FEB_352D`, `0x846C_A68B`,
//! shifts 16, 15, 16). Over one full period every 32-bit value appears
//! exactly once, so every bit field of the output is exactly uniform over
//! the period. Two 32×32-bit multiplications per output, no division, no
//! float: the same sequence on x86-64, Cortex-M4 and RV32IMAC.
//!
//! [`Rng::for_pixel`] derives the stream of pixel `(x, y)` in frame `frame`
//! by hashing the three numbers in turn, so neighbouring pixels and
//! consecutive frames get unrelated streams.

/// The Weyl increment: `2³²/φ` rounded to odd.
pub const WEYL: u32 = 0x9E37_79B9;

/// Bijective 32-bit mixing function (the generator's output hash).
#[inline]
#[must_use]
pub const fn mix32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7FEB_352D);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846C_A68B);
    x ^= x >> 16;
    x
}

/// Counter-based generator: state + Weyl step, hashed output.
///
/// # Example
/// ```
/// use raymip::rng::{Rng, WEYL};
/// // Each step adds WEYL to the state, then hashes it: a generator seeded
/// // with WEYL is the seed-0 generator one step later.
/// let mut a = Rng::new(0);
/// let _ = a.next_u32();
/// let mut b = Rng::new(WEYL);
/// assert_eq!(a.next_u32(), b.next_u32());
/// // The hash maps 0 to 0 (xor-shifts and products of 0 stay 0), so the
/// // stream seeded one step before state 0 starts with 0.
/// assert_eq!(Rng::new(0u32.wrapping_sub(WEYL)).next_u32(), 0);
/// // One stream per pixel and frame, the same on every target: a path's
/// // stochastic-LOD ray mask is one of the 8 bits.
/// let mut pixel = Rng::for_pixel(17, 4, 0);
/// let mask = raymip::geomlod::ray_mask(&mut pixel);
/// assert_eq!(mask.count_ones(), 1);
/// assert_eq!(Rng::for_pixel(17, 4, 0), Rng::for_pixel(17, 4, 0));
/// assert_ne!(Rng::for_pixel(17, 4, 0), Rng::for_pixel(17, 4, 1));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Rng {
    state: u32,
}

impl Rng {
    /// A generator starting from `seed` (any value, 0 included).
    #[must_use]
    pub const fn new(seed: u32) -> Self {
        Self { state: seed }
    }

    /// The stream of pixel `(x, y)` in frame `frame` (any values).
    #[inline]
    #[must_use]
    pub const fn for_pixel(x: u32, y: u32, frame: u32) -> Self {
        let h = mix32(frame.wrapping_add(WEYL));
        let h = mix32(h ^ y.wrapping_mul(0x85EB_CA6B));
        Self {
            state: mix32(h ^ x.wrapping_mul(0xC2B2_AE35)),
        }
    }

    /// The next uniformly distributed 32-bit value.
    #[inline]
    #[must_use]
    pub const fn next_u32(&mut self) -> u32 {
        self.state = self.state.wrapping_add(WEYL);
        mix32(self.state)
    }
}

/// Marsaglia's xorshift32 (shifts 13, 17, 5): the generator of the budget
/// and cycle-count inputs of the demo firmware (`raymip_demo_firmware::inputs`),
/// whose recorded rows depend on its sequence. Not for decisions on the
/// controller ([`Rng`] is). The state must not be 0 (0 stays 0).
///
/// # Example
/// ```
/// use raymip::rng::XorShift32;
/// let mut r = XorShift32(0x2545_F491);
/// assert_eq!(r.next_u32(), 0xE124_B63A);
/// assert_eq!(r.0, 0xE124_B63A); // the output is the new state
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct XorShift32(pub u32);

impl XorShift32 {
    /// The next 32 pseudo-random bits (the new state).
    #[inline]
    #[must_use]
    pub const fn next_u32(&mut self) -> u32 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        x
    }
}

/// Marsaglia's xorshift64 (shifts 13, 7, 17): the generator of the host
/// tests' inputs (random textures, coordinates, states; the f64 draws of
/// `raymip_reference::Draw` read it as an iterator), whose recorded golden
/// hashes depend on its sequence. The state must not be 0 (0 stays 0).
///
/// # Example
/// ```
/// use raymip::rng::XorShift64;
/// let mut r = XorShift64(0x9E37_79B9_7F4A_7C15);
/// assert_eq!(r.next_u64(), 0xDC1B_77AE_0BF3_4DAD);
/// let mut words = [0u32; 2];
/// r.fill_u32(&mut words); // the low halves of the next two outputs
/// assert_eq!(words, [0x026E_6076, 0xE590_6136]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct XorShift64(pub u64);

impl XorShift64 {
    /// The next 64 pseudo-random bits (the new state).
    #[inline]
    #[must_use]
    pub const fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x
    }

    /// Fills `out` with the low 32 bits of successive
    /// [`next_u64`](Self::next_u64) values (random texels of a test texture).
    pub fn fill_u32(&mut self, out: &mut [u32]) {
        for w in out {
            *w = self.next_u64() as u32;
        }
    }
}

/// Never ends: every call is [`XorShift64::next_u64`].
impl Iterator for XorShift64 {
    type Item = u64;

    fn next(&mut self) -> Option<u64> {
        Some(self.next_u64())
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::vec::Vec;

    /// The input generators' sequences, pinned (the recorded budget rows
    /// and golden hashes depend on them).
    #[test]
    fn xorshift_sequences_are_pinned() {
        let mut a = XorShift32(0x2545_F491);
        let got = [a.next_u32(), a.next_u32(), a.next_u32()];
        assert_eq!(got, [0xE124_B63A, 0x8B9A_74AB, 0x64E1_B3AC]);
        assert_eq!(a.0, 0x64E1_B3AC);
        let mut b = XorShift64(0x9E37_79B9_7F4A_7C15);
        assert_eq!(b.next(), Some(0xDC1B_77AE_0BF3_4DAD));
        let mut w = [0u32; 2];
        b.fill_u32(&mut w);
        assert_eq!(w, [0x026E_6076, 0xE590_6136]);
        assert_eq!(b.next_u64(), 0x305F_050C_368D_CC74);
    }

    /// Reference vectors: the hash written out step by step in u64
    /// arithmetic (independent of the wrapping u32 code above).
    fn mix_ref(x: u64) -> u64 {
        let m = 0xFFFF_FFFFu64;
        let mut x = x & m;
        x ^= x >> 16;
        x = (x * 0x7FEB_352D) & m;
        x ^= x >> 15;
        x = (x * 0x846C_A68B) & m;
        x ^ (x >> 16)
    }

    #[test]
    fn mix_matches_reference_and_fixed_vectors() {
        let mut s = 1u64;
        for _ in 0..10_000 {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let x = (s >> 32) as u32;
            assert_eq!(u64::from(mix32(x)), mix_ref(u64::from(x)));
        }
        // Pinned outputs (any change of the generator changes every
        // stochastic image: it must be deliberate).
        assert_eq!(mix32(0), 0);
        assert_eq!(u64::from(mix32(1)), mix_ref(1));
        let mut r = Rng::new(0);
        let first: Vec<u32> = (0..3).map(|_| r.next_u32()).collect();
        let want: Vec<u32> = (1..=3u64)
            .map(|i| mix_ref(i * u64::from(WEYL)) as u32)
            .collect();
        assert_eq!(first, want);
    }

    #[test]
    fn for_pixel_hashes_frame_then_row_then_column() {
        // The documented derivation in u64 arithmetic: each combining step
        // is an xor (an `|` or `&` there would still look uniform).
        let m = 0xFFFF_FFFFu64;
        let mut s = 7u64;
        for _ in 0..2_000 {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let (x, y, f) = (s as u32 >> 8, (s >> 24) as u32, (s >> 40) as u32);
            let h = mix_ref((u64::from(f) + u64::from(WEYL)) & m);
            let h = mix_ref(h ^ ((u64::from(y) * 0x85EB_CA6B) & m));
            let want = mix_ref(h ^ ((u64::from(x) * 0xC2B2_AE35) & m));
            assert_eq!(
                u64::from(Rng::for_pixel(x, y, f).state),
                want,
                "{x} {y} {f}"
            );
        }
    }

    #[test]
    fn mix_is_bijective_on_a_subspace() {
        // Injective on 2^20 consecutive inputs (a bijection has no collision).
        let mut seen: Vec<u32> = (0..1u32 << 20).map(mix32).collect();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(seen.len(), 1 << 20);
    }

    /// Chi-square statistic of counts against a uniform distribution.
    fn chi2(counts: &[u64]) -> f64 {
        let n: u64 = counts.iter().sum();
        let e = n as f64 / counts.len() as f64;
        counts.iter().map(|&c| (c as f64 - e).powi(2) / e).sum()
    }

    #[test]
    fn low_three_bits_uniform_over_pixels_and_frames() {
        // 7 degrees of freedom: P(chi2 > 24.3) = 0.001.
        let mut over_pixels = [0u64; 8];
        for y in 0..240 {
            for x in 0..320 {
                over_pixels[(Rng::for_pixel(x, y, 5).next_u32() & 7) as usize] += 1;
            }
        }
        assert!(chi2(&over_pixels) < 24.3, "{over_pixels:?}");
        let mut over_frames = [0u64; 8];
        for f in 0..20_000 {
            over_frames[(Rng::for_pixel(17, 3, f).next_u32() & 7) as usize] += 1;
        }
        assert!(chi2(&over_frames) < 24.3, "{over_frames:?}");
        // Pairs of consecutive frames of one pixel: 64 cells, 63 dof,
        // P(chi2 > 103.4) = 0.001.
        let mut pairs = [0u64; 64];
        for f in 0..40_000 {
            let a = Rng::for_pixel(9, 11, f).next_u32() & 7;
            let b = Rng::for_pixel(9, 11, f + 1).next_u32() & 7;
            pairs[(a * 8 + b) as usize] += 1;
        }
        assert!(chi2(&pairs) < 103.4, "{pairs:?}");
        // Horizontal neighbours in one frame.
        let mut nb = [0u64; 64];
        for y in 0..200 {
            for x in 0..200 {
                let a = Rng::for_pixel(x, y, 0).next_u32() & 7;
                let b = Rng::for_pixel(x + 1, y, 0).next_u32() & 7;
                nb[(a * 8 + b) as usize] += 1;
            }
        }
        assert!(chi2(&nb) < 103.4, "{nb:?}");
    }

    #[test]
    fn full_period_is_exactly_uniform_in_small_state() {
        // The Weyl step is odd: the state sequence is a permutation of
        // Z/2^32. Check the structure on the low 16 bits: 2^16 steps visit
        // every low-16-bit state once.
        let mut r = Rng::new(12345);
        let mut seen = std::vec![false; 1 << 16];
        for _ in 0..1 << 16 {
            let _ = r.next_u32();
            seen[(r.state & 0xFFFF) as usize] = true;
        }
        assert!(seen.iter().all(|&s| s));
    }
}
