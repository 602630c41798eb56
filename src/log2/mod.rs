//! Fixed-point base-2 logarithm: leading-zero count + 64-entry table with
//! linear interpolation.
//!
//! This module is the ACCURATE tier's logarithm; [`fast`] is the FAST
//! tier's (1024-entry table, no interpolation). Set-up, path state, lod
//! and texture all call them, so they sit on the ground floor beside
//! [`units`](crate::units).
//!
//! # Method
//!
//! For an unsigned fixed-point value `x = bits · 2^-f` with `bits ≠ 0`, let
//! `n` be the index of the most significant set bit of `bits`. Then
//!
//! ```text
//! log2 x = (n − f) + log2 m,   m = bits / 2^n ∈ [1, 2)
//! ```
//!
//! The mantissa is normalised to 32 bits with its top bit set. Its next six
//! bits index a table of `log2(1 + i/64)` in U0F16 (`i = 0..=64`), and the
//! following 16 bits interpolate linearly between two entries.
//!
//! # Error bound
//!
//! Linear interpolation of `log2(1+x)` on steps of `h = 1/64` is off by at
//! most `h²/8 · max|f''| = h²/(8 ln 2) ≈ 4.4·10⁻⁵`; table rounding and the
//! final rounding add `2 · 2⁻¹⁷`, and the mantissa bits beyond the 22 that
//! are used add below `2⁻²²`. The documented bound is
//! [`LOG2_MAX_ERROR`] `= 2⁻¹³ ≈ 1.22·10⁻⁴` (tested against `f64::log2` over
//! every power of two, random mantissas and the extremes; the measured
//! maximum is about `5·10⁻⁵`).
//!
//! The result is monotonic non-decreasing in the input: the table is
//! increasing, interpolation and rounding preserve order, and the value at
//! the end of one octave meets the start of the next.
//!
//! # Zero
//!
//! `log2 0 = −∞` has no fixed-point value. [`log2_bits`] and its typed
//! wrappers read a zero input as the smallest positive value of its format
//! (one raw unit), so `log2 0 = −frac_bits` (−32 for U32F32): the lowest
//! result of the format, reached without a branch. A zero path length thus
//! selects the finest level once a caller clamps. Only
//! `log2_bits_u128` (crate-internal set-up code) returns [`LOG2_ZERO`].
//!
//! # Count leading zeros
//!
//! Cortex-M4 (and x86-64) have a count-leading-zeros instruction, used via
//! [`u32::leading_zeros`]. RV32IMAC has none (it is in the Zbb extension):
//! on `riscv32` without `zbb` two compare-and-shift steps and a 256-entry
//! byte table ([`clz32_soft`]) replace the compiler's generic sequence.
//! A 64-bit input is normalised word-wise on 32-bit cores (one `clz` of the
//! high word, or of the low word when the high word is zero).

pub mod fast;

use fixed::types::{I16F16, U16F16, U32F32};

/// Documented maximum absolute error of every function in this module,
/// in units of one (log2 units, i.e. MIP levels): `2⁻¹³`.
pub const LOG2_MAX_ERROR: f64 = 1.0 / 8192.0;

/// Result of the crate-internal `log2_bits_u128` for a zero input (`log2 0 = −∞`): `I16F16::MIN`.
pub const LOG2_ZERO: I16F16 = I16F16::MIN;

/// `round(log2(1 + i/64) · 2^16)` for `i = 0..=64`.
const TABLE: [u32; 65] = [
    0, 1466, 2909, 4331, 5732, 7112, 8473, 9814, //
    11136, 12440, 13727, 14996, 16248, 17484, 18704, 19909, //
    21098, 22272, 23433, 24579, 25711, 26830, 27936, 29029, //
    30109, 31178, 32234, 33279, 34312, 35334, 36346, 37346, //
    38336, 39316, 40286, 41246, 42196, 43137, 44068, 44990, //
    45904, 46809, 47705, 48593, 49472, 50344, 51207, 52063, //
    52911, 53751, 54584, 55410, 56229, 57040, 57845, 58643, //
    59434, 60219, 60997, 61769, 62534, 63294, 64047, 64794, //
    65536,
];

/// Count of leading zero bits of `x` (32 for `x = 0`).
#[inline(always)]
#[must_use]
pub fn clz32(x: u32) -> u32 {
    #[cfg(all(target_arch = "riscv32", not(target_feature = "zbb")))]
    {
        clz32_soft(x)
    }
    #[cfg(not(all(target_arch = "riscv32", not(target_feature = "zbb"))))]
    {
        x.leading_zeros()
    }
}

/// Portable count-leading-zeros for cores without a `clz` instruction: two
/// compare-and-shift steps (16, 8 bits) and a 256-entry table of the
/// leading zeros of the top byte (the private table `CLZ8`). Equal to
/// [`u32::leading_zeros`] for every input (tested).
#[inline(always)]
#[must_use]
pub fn clz32_soft(x: u32) -> u32 {
    let (x, n) = shift_zero_bytes(x);
    // `x >> 24 ≤ 255`: the index is in bounds and the check folds away.
    n + u32::from(CLZ8[(x >> 24) as usize])
}

/// The first two steps of [`clz32_soft`]: `x` shifted left by 16 and/or 8
/// while its top 16, then top 8 bits are zero, and the shift `n`
/// (`0, 8, 16, 24`). The top byte of the result is non-zero unless `x = 0`.
#[inline(always)]
fn shift_zero_bytes(x: u32) -> (u32, u32) {
    let mut x = x;
    let mut n = 0;
    if x < 1 << 16 {
        n += 16;
        x <<= 16;
    }
    if x < 1 << 24 {
        n += 8;
        x <<= 8;
    }
    (x, n)
}

/// Leading zeros of a byte (8 for 0), the last step of [`clz32_soft`].
const CLZ8: [u8; 256] = {
    let mut t = [0u8; 256];
    let mut i = 0;
    while i < 256 {
        t[i] = (i as u8).leading_zeros() as u8;
        i += 1;
    }
    t
};

/// Bias folded into the interval table: `(31 << 16) + 0x80`, i.e. the
/// integer part of a U32F32 log2 with no leading zeros (31) plus the
/// rounding offset of an I8F8 result (½ of 2⁻⁸): a table lod then needs no
/// constant of its own.
pub(crate) const LOD_BIAS: u32 = (31 << 16) + 0x80;

/// `(TABLE[i] + LOD_BIAS, TABLE[i + 1] − TABLE[i])` for `i = 0..64`: biased
/// entry and slope of each interpolation interval, read together. (Packing
/// both into one word saves a load but costs two extracts: measured no
/// fewer instructions on the M4 and two more on RV32.)
const INTERVALS: [(u32, u32); 64] = {
    let mut t = [(0u32, 0u32); 64];
    let mut i = 0;
    while i < 64 {
        t[i] = (TABLE[i] + LOD_BIAS, TABLE[i + 1] - TABLE[i]);
        i += 1;
    }
    t
};

/// `log2(m / 2^31) + LOD_BIAS` in U0F16 bits for a normalised mantissa
/// `m ∈ [2^31, 2^32)`: the log2 part in `0..=65536`. `m = 0` gives the
/// value of `m = 2^31` (log2 part 0).
#[inline(always)]
fn mantissa_log2_biased(m: u32) -> u32 {
    let idx = ((m >> 25) & 63) as usize;
    let t = (m >> 9) & 0xFFFF;
    // `idx ≤ 63`, so the read is in bounds and the check folds away.
    let (a, d) = INTERVALS[idx];
    // d ≤ 1466 and t < 2^16: the product stays below 2^27.
    a + ((d * t + 0x8000) >> 16)
}

/// `log2(m / 2^31)` in U0F16 bits (`0..=65536`), see [`mantissa_log2_biased`].
#[inline(always)]
pub(crate) fn mantissa_log2(m: u32) -> u32 {
    mantissa_log2_biased(m) - LOD_BIAS
}

/// Normalised mantissa and leading-zero count of a 64-bit value: `(m, lz)`
/// with `m` the top 32 bits of `bits << lz` (top bit set) and
/// `lz = clz(bits | 1)`, so zero gives `(0, 63)`, whose log2 equals that of
/// one raw unit (the mantissa of `m = 0` is that of `2^31`: 0). On 32-bit
/// targets the high word decides: one normalisation of the high word and
/// the low word's top bits shifted in when it is non-zero, one
/// normalisation of the low word when it is zero.
#[inline(always)]
pub(crate) fn normalise64(bits: u64) -> (u32, u32) {
    #[cfg(target_pointer_width = "64")]
    {
        let lz = (bits | 1).leading_zeros();
        ((bits.wrapping_shl(lz) >> 32) as u32, lz)
    }
    #[cfg(not(target_pointer_width = "64"))]
    {
        normalise64_words(bits)
    }
}

/// [`normalise64`] in 32-bit words (used on 32-bit targets; tested against
/// the 64-bit form on the host).
#[cfg_attr(target_pointer_width = "64", allow(dead_code))]
#[inline(always)]
fn normalise64_words(bits: u64) -> (u32, u32) {
    let hi = (bits >> 32) as u32;
    let lo = bits as u32;
    if hi != 0 {
        // lz ≤ 31, so `31 ^ lz = 31 − lz` and the shift is in range.
        let (m, lz) = normalise32_nonzero(hi);
        (m | (lo >> 1).wrapping_shr(31 ^ lz), lz)
    } else {
        // Block layout: the longer high-word branch falls through into the
        // caller's table read, this one jumps back (the longest path of a
        // table lod takes no taken branch here).
        unlikely();
        let (m, lz) = normalise32(lo);
        (m, lz + 32)
    }
}

/// Marks the branch that calls it as the less likely one: block layout
/// only (the stable form of a cold-path hint; `core::hint::cold_path`
/// needs Rust 1.95, above this crate's `rust-version`).
#[cold]
#[inline]
fn unlikely() {}

/// `(x << lz, lz)` with `lz = clz(x | 1)` (zero gives `(0, 31)`).
#[inline(always)]
pub(crate) fn normalise32(x: u32) -> (u32, u32) {
    #[cfg(all(target_arch = "riscv32", not(target_feature = "zbb")))]
    {
        normalise32_soft(x)
    }
    #[cfg(not(all(target_arch = "riscv32", not(target_feature = "zbb"))))]
    {
        let lz = (x | 1).leading_zeros();
        (x.wrapping_shl(lz), lz)
    }
}

/// [`normalise32`] for `x ≠ 0` (then `clz(x | 1) = clz(x)`: the `| 1` is
/// left out).
#[inline(always)]
pub(crate) fn normalise32_nonzero(x: u32) -> (u32, u32) {
    #[cfg(all(target_arch = "riscv32", not(target_feature = "zbb")))]
    {
        normalise32_soft(x)
    }
    #[cfg(not(all(target_arch = "riscv32", not(target_feature = "zbb"))))]
    {
        let lz = x.leading_zeros();
        (x.wrapping_shl(lz), lz)
    }
}

/// [`normalise32`] without a `clz` instruction: the steps of
/// [`clz32_soft`] shift the value as they count, so no second shift is
/// needed. The table index `| 1` reads a zero top byte (only for `x = 0`)
/// as 1: `lz = 31` as `clz(x | 1)`. Equal to the `clz` form for every
/// input (tested).
#[cfg_attr(
    not(all(target_arch = "riscv32", not(target_feature = "zbb"))),
    allow(dead_code)
)]
#[inline(always)]
fn normalise32_soft(x: u32) -> (u32, u32) {
    let (x, n) = shift_zero_bytes(x);
    let c = u32::from(CLZ8[((x >> 24) | 1) as usize]);
    (x << c, n + c)
}

/// log2 of a U32F32 raw value, split for callers that add more terms:
/// returns `(lz, biased)` with
/// `log2 (I16F16 bits) + 0x80 = biased − (lz << 16)`, `lz ∈ 0..=63`
/// (bit-identical to [`log2_u32f32`]; the `0x80` is the I8F8 rounding
/// offset, see [`LOD_BIAS`]).
#[inline(always)]
pub(crate) fn log2_u32f32_parts(bits: u64) -> (u32, u32) {
    let (m, lz) = normalise64(bits);
    (lz, mantissa_log2_biased(m))
}

/// log2 of a U1F31 raw value in I16F16 bits plus [`LOD_BIAS`]:
/// `log2_bits(u64::from(x), 31) + LOD_BIAS`, for `x ≠ 0`.
#[cfg_attr(
    any(not(feature = "cone"), all(feature = "pcpi", target_arch = "riscv32")),
    allow(dead_code)
)]
#[inline(always)]
pub(crate) fn log2_u1f31_biased(x: u32) -> i32 {
    let (m, lz) = normalise32(x);
    mantissa_log2_biased(m) as i32 - ((lz as i32) << 16)
}

/// log2 of an unsigned fixed-point number given as raw `bits` with
/// `frac_bits` fractional bits, as I16F16.
///
/// Range: the result lies in `[−frac_bits, 64 − frac_bits)`; zero gives
/// `−frac_bits` (see [Zero](self#zero)). Error ≤ [`LOG2_MAX_ERROR`]. The
/// formats of this crate have `frac_bits ≤ 64`; any larger count is still
/// `log2 x − frac_bits`, saturated at `I16F16::MIN` (a separate set-up
/// path; a constant `frac_bits ≤ 64` compiles to the branch-free one).
#[inline]
#[must_use]
pub fn log2_bits(bits: u64, frac_bits: u32) -> I16F16 {
    if frac_bits > 64 {
        return log2_bits_wide(bits, frac_bits);
    }
    log2_bits_narrow(bits, frac_bits)
}

/// [`log2_bits`] for `frac_bits ≤ 64` (the result then fits I16F16).
#[inline(always)]
fn log2_bits_narrow(bits: u64, frac_bits: u32) -> I16F16 {
    // Zero is read as the smallest positive value (branch-free, see
    // `normalise64`).
    let (m, lz) = normalise64(bits); // lz 0..=63
    let int = 63 - lz as i32 - frac_bits as i32;
    I16F16::from_bits((int << 16) + mantissa_log2(m) as i32)
}

/// [`log2_bits`] for `frac_bits > 64`: `log2 x ∈ [0, 64)` minus
/// `frac_bits` in 64-bit arithmetic (no overflow), saturated at `I16F16::MIN`.
#[cold]
fn log2_bits_wide(bits: u64, frac_bits: u32) -> I16F16 {
    let l = i64::from(log2_bits_narrow(bits, 0).to_bits()) - (i64::from(frac_bits) << 16);
    I16F16::from_bits(l.max(i64::from(i32::MIN)) as i32)
}

/// Count of leading zero bits of a 64-bit value (64 for zero): one
/// instruction on x86-64, two `clz` and a select on Cortex-M4, two
/// [`clz32_soft`] searches on RV32 without Zbb.
#[inline(always)]
#[must_use]
pub fn clz64(x: u64) -> u32 {
    #[cfg(target_pointer_width = "64")]
    {
        x.leading_zeros()
    }
    #[cfg(not(target_pointer_width = "64"))]
    {
        clz64_words(x)
    }
}

/// [`clz64`] in 32-bit words (used on 32-bit targets; tested against
/// [`u64::leading_zeros`] on the host).
#[cfg_attr(target_pointer_width = "64", allow(dead_code))]
#[inline(always)]
fn clz64_words(x: u64) -> u32 {
    let hi = (x >> 32) as u32;
    if hi != 0 {
        clz32(hi)
    } else {
        32 + clz32(x as u32)
    }
}

/// log2 of a path length or distance in U32F32 (range `[2⁻³², 2³²)` →
/// `[−32, 32)`); zero gives −32. Error ≤ [`LOG2_MAX_ERROR`].
#[inline]
#[must_use]
pub fn log2_u32f32(x: U32F32) -> I16F16 {
    log2_bits(x.to_bits(), 32)
}

/// log2 of a U16F16 value (range `[2⁻¹⁶, 2¹⁶)` → `[−16, 16)`); zero gives
/// −16. Error ≤ [`LOG2_MAX_ERROR`].
#[inline]
#[must_use]
pub fn log2_u16f16(x: U16F16) -> I16F16 {
    log2_bits(u64::from(x.to_bits()), 16)
}

/// log2 of an integer (range `[1, 2³²)` → `[0, 32)`); zero gives 0. Exact for powers of two; error ≤ [`LOG2_MAX_ERROR`].
#[inline]
#[must_use]
pub fn log2_u32(x: u32) -> I16F16 {
    log2_bits(u64::from(x), 0)
}

/// log2 of a 128-bit unsigned fixed-point value with `frac_bits`
/// fractional bits (`0 ≤ frac_bits ≤ 128`), for set-up code (triangle
/// areas). The top 64 significant bits are used. Zero gives [`LOG2_ZERO`];
/// results below −32768 saturate to it. Error ≤ [`LOG2_MAX_ERROR`].
#[must_use]
pub(crate) fn log2_bits_u128(bits: u128, frac_bits: u32) -> I16F16 {
    if bits == 0 {
        return LOG2_ZERO;
    }
    let top = 127 - bits.leading_zeros(); // 0..=127
    let shift = top.saturating_sub(63);
    let l = log2_bits((bits >> shift) as u64, 0);
    // l ∈ [0, 64); add back the shift and remove the fractional bits.
    let adj = shift as i32 - frac_bits as i32;
    l.saturating_add(I16F16::from_bits(adj.saturating_mul(1 << 16)))
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use proptest::prelude::*;

    /// Independent f64 reference.
    fn reference(bits: u64, frac: u32) -> f64 {
        (bits as f64).log2() - f64::from(frac)
    }

    fn check(bits: u64, frac: u32) -> f64 {
        let got = log2_bits(bits, frac).to_num::<f64>();
        let want = reference(bits, frac);
        let err = (got - want).abs();
        assert!(
            err <= LOG2_MAX_ERROR,
            "log2_bits({bits:#x}, {frac}) = {got}, f64 {want}, error {err:e} > {LOG2_MAX_ERROR:e}"
        );
        err
    }

    /// The method as first written (64-bit shift, two table reads): the
    /// optimised code must give the same bits.
    fn log2_bits_formula(bits: u64, frac: u32) -> I16F16 {
        let bits = bits.max(1);
        let lz = bits.leading_zeros();
        let m = ((bits << lz) >> 32) as u32;
        let idx = ((m >> 25) & 63) as usize;
        let t = (m >> 9) & 0xFFFF;
        let (a, b) = (TABLE[idx], TABLE[idx + 1]);
        let mant = a + (((b - a) * t + 0x8000) >> 16);
        I16F16::from_bits(((63 - lz as i32 - frac as i32) << 16) + mant as i32)
    }

    #[test]
    fn bit_identical_to_the_formula_at_the_edges() {
        for s in 0..64 {
            for x in [
                0u64,
                1u64 << s,
                (1u64 << s) | 1,
                u64::MAX >> (63 - s),
                (1u64 << s) - 1,
            ] {
                for frac in [0, 31, 32, 64] {
                    assert_eq!(
                        log2_bits(x, frac),
                        log2_bits_formula(x, frac),
                        "{x:#x} {frac}"
                    );
                }
                let (lz, biased) = log2_u32f32_parts(x);
                let want = log2_bits_formula(x, 32).to_bits() + 0x80;
                assert_eq!(biased as i32 - ((lz as i32) << 16), want, "{x:#x}");
                let y = (x >> 32) as u32 | 1;
                let want = log2_bits_formula(u64::from(y), 31).to_bits() + LOD_BIAS as i32;
                assert_eq!(log2_u1f31_biased(y), want);
                assert_eq!(normalise32_soft(x as u32), normalise32(x as u32));
                assert_eq!(clz64_words(x), x.leading_zeros(), "{x:#x}");
                if x as u32 != 0 {
                    assert_eq!(normalise32_nonzero(x as u32), normalise32(x as u32));
                }
            }
        }
    }

    #[test]
    fn table_matches_f64() {
        for (i, &t) in TABLE.iter().enumerate() {
            let want = (1.0 + i as f64 / 64.0).log2() * 65536.0;
            assert!(
                (f64::from(t) - want).abs() <= 0.5,
                "entry {i}: {t} vs {want}"
            );
        }
    }

    #[test]
    fn soft_clz_matches_hardware() {
        assert_eq!(clz32_soft(0), 32);
        for s in 0..32 {
            for x in [1u32 << s, (1u32 << s) | 1, u32::MAX >> (31 - s)] {
                assert_eq!(clz32_soft(x), x.leading_zeros(), "x = {x:#x}");
            }
        }
    }

    #[test]
    fn clz64_matches_std() {
        for s in 0..64 {
            for x in [1u64 << s, (1u64 << s) | 1, u64::MAX >> (63 - s)] {
                assert_eq!(clz64(x), x.leading_zeros(), "x = {x:#x}");
            }
        }
        assert_eq!(clz64(0), 64);
    }

    #[test]
    fn powers_of_two_are_exact() {
        for frac in [0, 16, 32, 64] {
            for n in 0..64 {
                let got = log2_bits(1u64 << n, frac);
                assert_eq!(
                    got.to_num::<f64>(),
                    f64::from(n) - f64::from(frac),
                    "2^{n} with {frac} fractional bits"
                );
            }
        }
    }

    #[test]
    fn extremes_and_zero() {
        assert_eq!(log2_bits(0, 32).to_num::<f64>(), -32.0);
        assert_eq!(log2_bits(0, 0).to_num::<f64>(), 0.0);
        assert_eq!(log2_u32(0).to_num::<f64>(), 0.0);
        assert_eq!(log2_u16f16(U16F16::ZERO).to_num::<f64>(), -16.0);
        assert_eq!(log2_u32f32(U32F32::ZERO).to_num::<f64>(), -32.0);
        assert_eq!(log2_u32f32(U32F32::DELTA).to_num::<f64>(), -32.0);
        check(1, 32);
        check(u64::MAX, 32);
        check(u64::MAX, 0);
        check(u64::MAX - 1, 64);
        check(u32::MAX as u64, 0);
        check((1u64 << 32) - 1, 32);
        check((1u64 << 32) + 1, 32);
    }

    #[test]
    fn sweep_every_octave_and_mantissa_step() {
        let mut worst = 0.0f64;
        for n in 0..64u32 {
            for k in 0..4096u64 {
                let base = 1u64 << n;
                // k/4096 of the way through the octave.
                let bits = base + ((base as u128 * k as u128) / 4096) as u64;
                worst = worst.max(check(bits, 32));
            }
        }
        std::println!(
            "log2: max |error| over the octave sweep = {worst:.3e} (limit {LOG2_MAX_ERROR:.3e})"
        );
        // The documented bound is a tight one: within 4× of the measured
        // error (callers size their own error budgets from it).
        assert!(
            worst > LOG2_MAX_ERROR / 4.0,
            "LOG2_MAX_ERROR {LOG2_MAX_ERROR:.3e} is over 4x the measured {worst:.3e}"
        );
    }

    #[test]
    fn u128_variant_matches_f64() {
        for (bits, frac) in [
            (1u128, 0u32),
            (3, 0),
            (u128::MAX, 64),
            (u128::MAX, 128),
            (1u128 << 100, 64),
            ((1u128 << 100) + (1u128 << 99), 64),
            (12345678901234567890123456789u128, 96),
        ] {
            let got = log2_bits_u128(bits, frac).to_num::<f64>();
            let want = (bits as f64).log2() - f64::from(frac);
            assert!(
                (got - want).abs() <= LOG2_MAX_ERROR,
                "{bits} / 2^{frac}: {got} vs {want}"
            );
        }
        assert_eq!(log2_bits_u128(0, 10), LOG2_ZERO);
    }

    /// f64 reference of `log2_bits` for any `frac_bits`, saturated at the
    /// bottom of I16F16 (the top, `64 − frac_bits < 64`, is never reached).
    fn reference_saturated(bits: u64, frac: u32) -> f64 {
        reference(bits.max(1), frac).max(I16F16::MIN.to_num::<f64>())
    }

    /// `frac_bits` above 64 is outside the formats the crate uses but must
    /// still give `log2 x − frac_bits`, saturated at `I16F16::MIN`, not
    /// wrapped (or, in debug, a panic on the subtraction).
    #[test]
    fn frac_bits_beyond_64_saturate() {
        assert_eq!(log2_bits(1 << 63, 100).to_num::<f64>(), -37.0);
        assert_eq!(log2_bits(1, 32_768), I16F16::MIN);
        assert_eq!(log2_bits(1, 40_000), I16F16::MIN);
        assert_eq!(log2_bits(u64::MAX, u32::MAX), I16F16::MIN);
        assert_eq!(log2_bits(0, 1 << 31), I16F16::MIN);
        assert_eq!(log2_bits(1 << 20, (1 << 31) + 5), I16F16::MIN);
        // Just above the bottom: still the true value.
        assert_eq!(log2_bits(1 << 40, 32_768 + 40).to_num::<f64>(), -32_768.0);
        let near = log2_bits(3 << 40, 32_768 + 40).to_num::<f64>();
        assert!((near - reference(3 << 40, 32_768 + 40)).abs() <= LOG2_MAX_ERROR);
    }

    /// Neighbours `(x, x + 1)` at every place where the method changes
    /// branch: each octave boundary and each table-segment boundary of every
    /// octave (a property over random pairs rarely draws adjacent ones).
    #[test]
    fn monotonic_at_every_octave_and_segment_boundary() {
        for frac in [0, 16, 31, 32, 64] {
            for n in 0..64u32 {
                let base = 1u64 << n;
                for i in 0..=64u64 {
                    // Start of segment i of octave n (i = 64: the next octave).
                    let b = base.saturating_add(((u128::from(base) * u128::from(i)) / 64) as u64);
                    for x in [
                        b.saturating_sub(2),
                        b.saturating_sub(1),
                        b,
                        b.saturating_add(1),
                    ] {
                        if x == u64::MAX {
                            continue;
                        }
                        assert!(
                            log2_bits(x, frac) <= log2_bits(x + 1, frac),
                            "log2({x:#x}) > log2({:#x}) with {frac} fractional bits",
                            x + 1
                        );
                    }
                }
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]
        #[test]
        fn random_inputs_within_bound(bits in 1u64.., frac in 0u32..=64) {
            check(bits, frac);
        }

        #[test]
        fn random_u128_within_bound(bits in 1u128.., frac in 0u32..=128) {
            let got = log2_bits_u128(bits, frac).to_num::<f64>();
            let want = (bits as f64).log2() - f64::from(frac);
            prop_assert!((got - want).abs() <= LOG2_MAX_ERROR, "{} vs {}", got, want);
        }

        /// Neighbours `(x, x + 1)` drawn uniformly over the octaves (a plain
        /// `any::<u64>()` would put half the draws in the top octave), with
        /// every format the crate uses.
        #[test]
        fn monotonic_neighbours_over_the_whole_range(n in 0u32..64, m in any::<u64>(), frac in 0u32..=64) {
            let x = (1u64 << n) | (m & ((1u64 << n) - 1));
            prop_assume!(x < u64::MAX);
            prop_assert!(log2_bits(x, frac) <= log2_bits(x + 1, frac), "x = {:#x}", x);
            prop_assert!(log2_bits(x - 1, frac) <= log2_bits(x, frac), "x = {:#x}", x);
        }

        /// Any `frac_bits`, saturated at the bottom, within the error bound.
        #[test]
        fn any_frac_bits_within_bound(bits in any::<u64>(), frac in any::<u32>()) {
            let got = log2_bits(bits, frac).to_num::<f64>();
            let want = reference_saturated(bits, frac);
            prop_assert!((got - want).abs() <= LOG2_MAX_ERROR, "log2_bits({:#x}, {}) = {} vs {}", bits, frac, got, want);
        }

        #[test]
        fn bit_identical_to_the_formula(bits in any::<u64>(), s in 0u32..64, frac in 0u32..=64) {
            let x = bits >> s;
            prop_assert_eq!(log2_bits(x, frac), log2_bits_formula(x, frac));
            prop_assert_eq!(normalise64_words(x), normalise64(x));
            prop_assert_eq!(clz64_words(x), x.leading_zeros());
            let y = (x as u32) | 1;
            let want = log2_bits_formula(u64::from(y), 31).to_bits() + LOD_BIAS as i32;
            prop_assert_eq!(log2_u1f31_biased(y), want);
            prop_assert_eq!(normalise32_soft(x as u32), normalise32(x as u32));
            prop_assert_eq!(clz32_soft(x as u32), (x as u32).leading_zeros());
        }

        #[test]
        fn monotonic(a in 0u64.., b in 0u64..) {
            let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
            prop_assert!(log2_bits(lo, 32) <= log2_bits(hi, 32));
        }
    }
}
