//! Fixed-point base-2 logarithm: leading-zero count + 64-entry table with
//! linear interpolation.
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
//! [`log2_bits_u128`] (set-up code) returns [`LOG2_ZERO`].
//!
//! # Count leading zeros
//!
//! Cortex-M4 (and x86-64) have a count-leading-zeros instruction, used via
//! [`u32::leading_zeros`]. RV32IMAC has none (it is in the Zbb extension):
//! on `riscv32` without `zbb` a five-step branch-light binary search is
//! used instead of the compiler's generic sequence.

use fixed::types::{I16F16, U16F16, U32F32};

/// Documented maximum absolute error of every function in this module,
/// in units of one (log2 units, i.e. MIP levels): `2⁻¹³`.
pub const LOG2_MAX_ERROR: f64 = 1.0 / 8192.0;

/// Result of [`log2_bits_u128`] for a zero input (`log2 0 = −∞`): `I16F16::MIN`.
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

/// Portable count-leading-zeros by binary search (five compare-and-shift
/// steps), for cores without a `clz` instruction. Equal to
/// [`u32::leading_zeros`] for every input (tested).
#[inline(always)]
#[must_use]
pub fn clz32_soft(x: u32) -> u32 {
    if x == 0 {
        return 32;
    }
    let mut x = x;
    let mut n = 0;
    if x & 0xFFFF_0000 == 0 {
        n += 16;
        x <<= 16;
    }
    if x & 0xFF00_0000 == 0 {
        n += 8;
        x <<= 8;
    }
    if x & 0xF000_0000 == 0 {
        n += 4;
        x <<= 4;
    }
    if x & 0xC000_0000 == 0 {
        n += 2;
        x <<= 2;
    }
    if x & 0x8000_0000 == 0 {
        n += 1;
    }
    n
}

/// `log2(m / 2^31)` in U0F16 bits for a normalised mantissa `m ∈ [2^31, 2^32)`;
/// result in `0..=65536`.
#[inline(always)]
fn mantissa_log2(m: u32) -> u32 {
    let idx = ((m >> 25) & 63) as usize;
    let t = (m >> 9) & 0xFFFF;
    // `idx ≤ 63`, so both reads are in bounds and the checks fold away.
    let a = TABLE[idx];
    let b = TABLE[idx + 1];
    // (b − a) ≤ 1466 and t < 2^16: the product stays below 2^27.
    a + (((b - a) * t + 0x8000) >> 16)
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
    // Zero is read as the smallest positive value (branch-free).
    let bits = if bits == 0 { 1 } else { bits };
    let lz = clz64(bits); // 0..=63
    // Normalised mantissa: the top set bit moved to bit 31 of a u32.
    let m = ((bits << lz) >> 32) as u32;
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
        let hi = (x >> 32) as u32;
        if hi != 0 {
            clz32(hi)
        } else {
            32 + clz32(x as u32)
        }
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
pub fn log2_bits_u128(bits: u128, frac_bits: u32) -> I16F16 {
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

    /// Regression (issue 11, defect 6): `frac_bits` above 64 is outside the
    /// formats the crate uses but must still give `log2 x − frac_bits`,
    /// saturated at `I16F16::MIN`, instead of wrapping (or, in debug,
    /// panicking on the subtraction).
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
    /// octave (issue 11, defect 6: the old property drew far-apart pairs only).
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
        fn monotonic(a in 0u64.., b in 0u64..) {
            let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
            prop_assert!(log2_bits(lo, 32) <= log2_bits(hi, 32));
        }
    }
}
