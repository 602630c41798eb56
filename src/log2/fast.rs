//! FAST fixed-point base-2 logarithm for the per-hit fast paths
//! ([`table_lod::<Fast>`](crate::lod::table_lod), [`cone_lod::<Fast>`](crate::lod::cone_lod)):
//! leading-zero count + one read of a 1024-entry mantissa table, no
//! interpolation.
//!
//! # Method
//!
//! As in [`crate::log2`], `log2 x = (n − f) + log2 m` with `m ∈ [1, 2)` the
//! mantissa normalised to 32 bits (same normalisation, same zero rule: a
//! zero input reads as one raw unit). The ten bits after the leading one
//! select an interval `[1 + i/1024, 1 + (i+1)/1024)` of the mantissa; the
//! table holds `log2` of the interval's midpoint `1 + (i + ½)/1024`,
//! rounded to U0F16 (the I8F8 rounding offset and the integer bias of
//! [`crate::log2`] folded in, so a lod needs no constant of its own).
//! Against the accurate kernel this saves the slope read, the weight
//! extract, the multiply and the rounding add.
//!
//! # Error bound
//!
//! `log2` changes by at most `½ · 2⁻¹⁰ / ln 2 ≈ 7.04·10⁻⁴` between a
//! midpoint and the ends of its interval (the slope `1/(m ln 2)` is largest
//! at `m = 1`); the entry's rounding adds `2⁻¹⁷`. The documented bound is
//! [`FAST_LOG2_MAX_ERROR`] `= 2⁻¹⁰ ≈ 9.77·10⁻⁴` (tested against `f64::log2`
//! over every octave, the extremes and random inputs; the measured maximum
//! is about `7.1·10⁻⁴`). It is monotonic non-decreasing: the table is
//! increasing and the last entry of an octave, `log2(2 − 2⁻¹¹) < 1`, lies
//! below the first of the next.
//!
//! The table is 4 KiB of `.rodata` (u32 entries: a u16 table would need the
//! bias added per call), linked only when a fast path is called.

use fixed::types::{I16F16, U32F32};

use crate::log2::{LOD_BIAS, normalise64};
use crate::units::PathLength;

/// Documented maximum absolute error of [`log2_u32f32_fast`] (and of the
/// fast log2 inside [`table_lod::<Fast>`](crate::lod::table_lod) and
/// [`cone_lod::<Fast>`](crate::lod::cone_lod)) against f64, in log2 units: `2⁻¹⁰`.
pub const FAST_LOG2_MAX_ERROR: f64 = 1.0 / 1024.0;

/// Mantissa bits used as the table index.
const INDEX_BITS: u32 = 10;

/// `log2(y)` of `y ∈ [1, 2)` given in Q62, to 24 fractional bits, by
/// repeated squaring (each square `≥ 2` gives a one bit and is halved):
/// integer arithmetic, so the table below is computed at compile time.
/// The squares are truncated to 62 fractional bits; over 24 steps that
/// moves the result by far less than the 2⁻²⁴ kept (checked against f64 in
/// the tests).
const fn log2_q62(mut y: u64) -> u32 {
    let mut r = 0u32;
    let mut k = 0;
    while k < 24 {
        y = ((y as u128 * y as u128) >> 62) as u64;
        r <<= 1;
        if y >= 2 << 62 {
            y >>= 1;
            r |= 1;
        }
        k += 1;
    }
    r
}

/// `round(log2(1 + (i + ½)/1024) · 2¹⁶) + LOD_BIAS` for `i = 0..1024`: the
/// midpoint log2 of each mantissa interval in U0F16, biased as the
/// accurate kernel's intervals (see [`LOD_BIAS`]).
const FAST_TABLE: [u32; 1 << INDEX_BITS] = {
    let mut t = [0u32; 1 << INDEX_BITS];
    let mut i = 0;
    while i < t.len() {
        // 1 + (2i + 1)/2^11 in Q62.
        let y = (1u64 << 62) + ((2 * i as u64 + 1) << (62 - INDEX_BITS - 1));
        t[i] = ((log2_q62(y) + 0x80) >> 8) + LOD_BIAS;
        i += 1;
    }
    t
};

/// `log2(m / 2³¹) + LOD_BIAS` in U0F16 bits for a normalised mantissa `m`
/// (top bit set; `m = 0` reads as `2³¹`), within [`FAST_LOG2_MAX_ERROR`].
#[inline(always)]
fn mantissa_log2_fast_biased(m: u32) -> u32 {
    // The index is below 1024: the read is in bounds and the check folds away.
    FAST_TABLE[((m >> (31 - INDEX_BITS)) & ((1 << INDEX_BITS) - 1)) as usize]
}

/// FAST log2 of a U32F32 raw value, split as
/// [`crate::log2::log2_u32f32_parts`]: `(lz, biased)` with
/// `log2 (I16F16 bits) + 0x80 ≈ biased − (lz << 16)`, `lz ∈ 0..=63`,
/// within [`FAST_LOG2_MAX_ERROR`].
#[inline(always)]
pub(crate) fn log2_u32f32_fast_parts(bits: u64) -> (u32, u32) {
    let (m, lz) = normalise64(bits);
    (lz, mantissa_log2_fast_biased(m))
}

/// FAST log2 of a U1F31 raw value `x ≠ 0` in I16F16 bits plus
/// [`LOD_BIAS`] (as [`crate::log2`]'s accurate `log2_u1f31_biased`),
/// within [`FAST_LOG2_MAX_ERROR`].
#[cfg(feature = "cone")]
#[inline(always)]
pub(crate) fn log2_u1f31_fast_biased(x: u32) -> i32 {
    let (m, lz) = crate::log2::normalise32_nonzero(x);
    mantissa_log2_fast_biased(m) as i32 - ((lz as i32) << 16)
}

/// FAST log2 of a path length or distance in U32F32 (range `[2⁻³², 2³²)` →
/// `[−32, 32)`); zero gives about −32 (read as 2⁻³²). Error ≤
/// [`FAST_LOG2_MAX_ERROR`] `= 2⁻¹⁰` (the ACCURATE
/// [`crate::log2::log2_u32f32`] is within 2⁻¹³). Monotonic non-decreasing.
#[inline]
#[must_use]
pub fn log2_u32f32_fast(x: U32F32) -> I16F16 {
    let (lz, biased) = log2_u32f32_fast_parts(x.to_bits());
    I16F16::from_bits(biased as i32 - ((lz as i32) << 16) - 0x80)
}

/// `log2(1 + (i + ½)/1024) + 0x80` in I16F16 bits minus `i`, for
/// `i = 0..1024`: [`FAST_TABLE`] re-based for a [`NormPl`] word, whose low
/// ten bits hold `i` (so `word + NORM_TABLE[word & 1023]` is the FAST
/// `log2 Pl` plus the I8F8 rounding offset, with no mask of the exponent).
const NORM_TABLE: [i32; 1 << INDEX_BITS] = {
    let mut t = [0i32; 1 << INDEX_BITS];
    let mut i = 0;
    while i < t.len() {
        t[i] = (FAST_TABLE[i] - LOD_BIAS) as i32 + 0x80 - i as i32;
        i += 1;
    }
    t
};

/// An accumulated path length `Pl` normalised for the FAST log2: its binary
/// exponent `e = ⌊log2 Pl⌋ ∈ [−32, 31]` in the upper half-word and the ten
/// mantissa bits after the leading one (the index of the FAST 1024-entry table
/// `i ∈ 0..1024`) in the low bits, one `i32` `(e << 16) | i`.
///
/// Made once per segment by [`NormPl::new`] (the leading-zero count) and
/// kept beside `Pl` in every ray-stack entry
/// ([`crate::path::raystack::PathState::pl_norm`]), so a lod from it
/// ([`crate::lod::table_lod_norm`], [`crate::lod::table_lod_norm_batch`])
/// is one table read and two additions. `Pl = 0` is read as 2⁻³² (as
/// [`log2_u32f32_fast`]). Every key is one [`NormPl::new`] can make or lies
/// between two such keys: [`NormPl::from_bits`] clamps the exponent to
/// `[−32, 31]` and clears bits 10..16, so `log2 Pl + 2⁻⁹` of any key lies in
/// `[−32, 32 + 2⁻⁹]` and the lod of any key and any textured [`crate::Log2Pb`]
/// in `[−127, 127]` levels (the range [`crate::lod::LodWord`] relies on).
///
/// # Example
/// ```
/// use raymip::log2::fast::NormPl;
/// use raymip::lod::{LOD_MAX_ERROR, table_lod_norm};
/// use raymip::{Log2Pb, PathLength};
/// // Pl = 12 = 2³ · 1.5: exponent 3, mantissa bits after the leading one
/// // 0.5 · 1024 = 512.
/// let key = NormPl::new(PathLength::from_num(12));
/// assert_eq!(key.to_bits(), (3 << 16) | 512);
/// assert_eq!(NormPl::new(PathLength::ZERO), NormPl::ZERO);
/// // The per-hit lod from the key: log2 12 − log2 Pb (here log2 Pb = 0).
/// let lod = table_lod_norm(key, Log2Pb::from_bits(0)).ok_or("textured")?;
/// assert!((lod.to_num::<f64>() - 12f64.log2()).abs() <= LOD_MAX_ERROR);
/// # Ok::<(), &str>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NormPl(i32);

/// [`NormPl::ZERO`], the key of the default (zero) path length.
impl Default for NormPl {
    fn default() -> Self {
        Self::ZERO
    }
}

impl NormPl {
    /// The key of `Pl = 0` (read as 2⁻³²: exponent −32, index 0).
    pub const ZERO: Self = Self(-32 << 16);

    /// Normalises a U32F32 path length (one leading-zero count). Never panics.
    #[inline]
    #[must_use]
    pub fn new(pl: PathLength) -> Self {
        let (m, lz) = normalise64(pl.to_bits());
        // lz ∈ 0..=63: exponent 31 − lz ∈ [−32, 31].
        let e = 31 - lz as i32;
        Self((e << 16) | ((m >> (31 - INDEX_BITS)) & ((1 << INDEX_BITS) - 1)) as i32)
    }

    /// The raw word `(e << 16) | i`.
    #[inline]
    #[must_use]
    pub const fn to_bits(self) -> i32 {
        self.0
    }

    /// A key from a raw word: the inverse of [`NormPl::to_bits`] for every
    /// key [`NormPl::new`] makes. Any other word is made a valid key: the
    /// exponent (bits 16..32, signed) clamped to `[−32, 31]`, the index (bits
    /// 0..10) kept, bits 10..16 cleared. Never panics.
    #[inline]
    #[must_use]
    pub const fn from_bits(bits: i32) -> Self {
        let e = bits >> 16;
        let e = if e < -32 {
            -32
        } else if e > 31 {
            31
        } else {
            e
        };
        // `e << 16` has its low 16 bits clear: the sum packs the index in.
        Self((e << 16) + (bits & ((1 << INDEX_BITS) - 1)))
    }

    /// FAST `log2 Pl` plus the I8F8 rounding offset `0x80`, in I16F16
    /// bits: one table read and one addition, within
    /// [`FAST_LOG2_MAX_ERROR`] of `log2 Pl` (bit-identical to
    /// [`log2_u32f32_fast`] `+ 0x80` of the path length it was made from).
    #[inline(always)]
    pub(crate) fn log2_rounding_bits(self) -> i32 {
        // The index is below 1024: the read is in bounds and the check folds away.
        self.0
            .wrapping_add(NORM_TABLE[(self.0 & ((1 << INDEX_BITS) - 1)) as usize])
    }

    /// FAST `log2 Pl` (range `[−32, 32)`), within [`FAST_LOG2_MAX_ERROR`];
    /// equal to [`log2_u32f32_fast`] of the path length it was made from.
    #[inline]
    #[must_use]
    pub fn log2(self) -> I16F16 {
        I16F16::from_bits(self.log2_rounding_bits().wrapping_sub(0x80))
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use proptest::prelude::*;

    /// Independent f64 reference (zero read as one raw unit).
    fn reference(bits: u64) -> f64 {
        (bits.max(1) as f64).log2() - 32.0
    }

    fn check(bits: u64) -> f64 {
        let got = log2_u32f32_fast(U32F32::from_bits(bits)).to_num::<f64>();
        let err = (got - reference(bits)).abs();
        assert!(
            err <= FAST_LOG2_MAX_ERROR,
            "log2_u32f32_fast({bits:#x}) = {got}, f64 {}, error {err:e}",
            reference(bits)
        );
        err
    }

    #[test]
    fn table_matches_f64() {
        for (i, &t) in FAST_TABLE.iter().enumerate() {
            let want = (1.0 + (i as f64 + 0.5) / 1024.0).log2() * 65536.0;
            let got = f64::from(t - LOD_BIAS);
            assert!(
                (got - want).abs() <= 0.5 + 1e-6,
                "entry {i}: {got} vs {want}"
            );
        }
        assert!(FAST_TABLE.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn sweep_every_octave_and_interval() {
        let mut worst = 0.0f64;
        for n in 0..64u32 {
            let base = 1u64 << n;
            for k in 0..8192u64 {
                let bits = base + ((u128::from(base) * u128::from(k)) / 8192) as u64;
                worst = worst.max(check(bits));
                worst = worst.max(check(bits.saturating_sub(1)));
            }
        }
        std::println!("fast log2: max |error| = {worst:.3e} (limit {FAST_LOG2_MAX_ERROR:.3e})");
        assert!(worst > 6.5e-4, "the sweep must reach the interval ends");
        // The documented bound is a tight one: within 4× of the measured error.
        assert!(
            worst > FAST_LOG2_MAX_ERROR / 4.0,
            "FAST_LOG2_MAX_ERROR {FAST_LOG2_MAX_ERROR:.3e} is over 4x the measured {worst:.3e}"
        );
    }

    #[test]
    fn monotonic_at_every_interval_boundary() {
        for n in 0..64u32 {
            let base = 1u64 << n;
            for i in 0..=1024u64 {
                let b = base.saturating_add(((u128::from(base) * u128::from(i)) / 1024) as u64);
                for x in [b.saturating_sub(1), b] {
                    if x == u64::MAX {
                        continue;
                    }
                    let f = |x| log2_u32f32_fast(U32F32::from_bits(x));
                    assert!(f(x) <= f(x + 1), "log2({x:#x}) > log2({:#x})", x + 1);
                }
            }
        }
    }

    /// Reference vectors: U32F32 raw inputs and `log2` from Python's
    /// `math.log2(bits) − 32` (written down, not computed by this crate).
    #[test]
    fn reference_vectors() {
        const VECTORS: [(u64, f64); 10] = [
            (0, -32.0),
            (1, -32.0),
            (3, -30.415037499278846),
            (1 << 32, 0.0),
            (0x1_8000_0000, 0.5849625007211543),
            (0x2B7E_1516, -2.5573049594252417),
            (0x0700_0000_0000, 10.807354922057606),
            (0xFFFF_FFFF, -3.3589694677385835e-10),
            (1 << 63, 31.0),
            (u64::MAX, 32.0),
        ];
        for (bits, want) in VECTORS {
            let got = log2_u32f32_fast(U32F32::from_bits(bits)).to_num::<f64>();
            assert!(
                (got - want).abs() <= FAST_LOG2_MAX_ERROR,
                "{bits:#x}: {got} vs {want}"
            );
        }
    }

    /// The normalised key gives the FAST log2 bit for bit, at every
    /// octave's interval boundaries and zero.
    #[test]
    fn norm_pl_equals_fast_log2_at_every_boundary() {
        for n in 0..64u32 {
            let base = 1u64 << n;
            for i in 0..=1024u64 {
                let b = base.saturating_add(((u128::from(base) * u128::from(i)) / 1024) as u64);
                for x in [b.saturating_sub(1), b] {
                    let pl = U32F32::from_bits(x);
                    assert_eq!(
                        NormPl::new(PathLength::from_fixed(pl)).log2(),
                        log2_u32f32_fast(pl),
                        "{x:#x}"
                    );
                }
            }
        }
        assert_eq!(NormPl::new(PathLength::ZERO), NormPl::ZERO);
        assert_eq!(NormPl::from_bits(i32::MIN), NormPl::ZERO);
        assert_eq!(NormPl::from_bits(i32::MAX).to_bits(), (31 << 16) | 1023);
        assert_eq!(
            NormPl::from_bits((5 << 16) | 0xFC05).to_bits(),
            (5 << 16) | 5
        );
        assert_eq!(NormPl::from_bits(-1).to_bits(), (-1 << 16) | 1023);
        // Every index of the re-based table against f64.
        for i in 0..1024i32 {
            let want =
                (1.0 + (f64::from(i) + 0.5) / 1024.0).log2() * 65536.0 + 128.0 - f64::from(i);
            assert!(
                (f64::from(NORM_TABLE[i as usize]) - want).abs() <= 0.5 + 1e-6,
                "entry {i}"
            );
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]
        /// Uniform over the octaves (a plain `any::<u64>()` would put half
        /// the draws in the top octave).
        #[test]
        fn random_inputs_within_bound(n in 0u32..64, m in any::<u64>()) {
            let x = (1u64 << n) | (m & ((1u64 << n) - 1));
            check(x);
            let f = |x| log2_u32f32_fast(U32F32::from_bits(x));
            if x < u64::MAX {
                prop_assert!(f(x) <= f(x + 1));
            }
        }

        /// Any key word is safe, and a key from a path length is within
        /// the FAST bound of f64.
        #[test]
        fn norm_pl_any_bits_and_f64(bits in any::<i32>(), n in 0u32..64, m in any::<u64>()) {
            // A raw word becomes a valid key: exponent clamped, bits 10..16
            // cleared, index kept; log2 within [−32, 32].
            let raw = NormPl::from_bits(bits);
            let e = (bits >> 16).clamp(-32, 31);
            prop_assert_eq!(raw.to_bits(), (e << 16) | (bits & 1023));
            prop_assert_eq!(NormPl::from_bits(raw.to_bits()), raw);
            prop_assert!((-32.0..=32.0).contains(&raw.log2().to_num::<f64>()));
            let x = (1u64 << n) | (m & ((1u64 << n) - 1));
            let k = NormPl::new(PathLength::from_bits(x));
            prop_assert_eq!(NormPl::from_bits(k.to_bits()), k);
            let got = k.log2().to_num::<f64>();
            prop_assert!((got - reference(x)).abs() <= FAST_LOG2_MAX_ERROR, "{:#x}: {} vs {}", x, got, reference(x));
            prop_assert_eq!(k.to_bits() >> 16, n as i32 - 32);
        }

        #[test]
        #[cfg(feature = "cone")]
        fn u1f31_within_bound(x in 1u32..) {
            let got = f64::from(log2_u1f31_fast_biased(x) - LOD_BIAS as i32) / 65536.0;
            let want = f64::from(x).log2() - 31.0;
            prop_assert!((got - want).abs() <= FAST_LOG2_MAX_ERROR, "{:#x}: {} vs {}", x, got, want);
        }
    }
}
