//! sRGB transfer functions for sRGB texel formats (Vulkan specification,
//! Appendix C / the sRGB EOTF of IEC 61966-2-1), in integer tables.
//!
//! * **Decode** (before filtering): an 8-bit sRGB code `c` becomes the
//!   linear value [`DECODE`]`[c] = round(EOTF(c/255)·65535)`, 16-bit
//!   unsigned ("L16", 65535 = 1.0), with
//!   `EOTF(s) = s/12.92` for `s ≤ 0.04045`, else `((s + 0.055)/1.055)^2.4`.
//!   A 256-entry table: exact to half an L16 step.
//! * **Encode** (after filtering, [`encode`]): a linear value in L16 with 8
//!   more fractional bits (16.8, as the filters produce it) becomes the
//!   8-bit code `round(255·OETF(x))`: the number of the 255 decision
//!   thresholds [`ENCODE_THRESHOLDS`]`[k] = ceil(EOTF((k + ½)/255)·65535·256)`
//!   at or below `x`, read from a 1216-byte bucket table of counts and one
//!   compare (no search). Exact for the 16.8 input: the result equals the f64
//!   rounding of `255·OETF(x)` except where `x` lies within one 16.8 step
//!   of a threshold.
//! * **Pyramids** of sRGB textures are generated in linear space
//!   ([`generate`]): the exact box filter of `mip::generate` applied to the
//!   decoded values, re-encoded once; alpha is filtered as stored.
//!
//! Both tables are computed while compiling, from the EOTF in f64, and
//! checked against the f64 `powf` form in the tests below.
//!
//! # Error bound
//!
//! Decode is within 2⁻¹⁷ of the exact EOTF. An encoded result is within
//! [`SRGB_ENCODE_MAX_ERROR_LSB`] = 0.55 sRGB LSB of `255·OETF(exact linear)`:
//! ½ from rounding, plus the input's linear error times the OETF's
//! steepest slope (12.92·255 LSB per unit, 0.05 LSB per L16 step).

#[cfg(feature = "mipgen")]
use crate::texture::storage::mip::{Geometry, MipError, Texel, generate_mapped};

/// `EOTF(s)` of IEC 61966-2-1 for `s ∈ [0, 1]` in f64, evaluated only
/// while compiling the two tables below (no float code is emitted).
const fn eotf(s: f64) -> f64 {
    if s <= 0.04045 {
        return s / 12.92;
    }
    // ((s + 0.055)/1.055)^2.4 = x² · (x²)^(1/5): the fifth root by Newton's
    // iteration from 1, which decreases to the root (x² ∈ (0, 1]) and
    // stops when a step no longer lowers it.
    let x = (s + 0.055) / 1.055;
    let x2 = x * x;
    let mut r = 1.0;
    loop {
        let r4 = r * r * r * r;
        let next = (4.0 * r + x2 / r4) / 5.0;
        if next >= r {
            return x2 * r;
        }
        r = next;
    }
}

/// Linear L16 value (65535 = 1.0) of every 8-bit sRGB code:
/// `round(EOTF(c/255)·65535)`.
pub const DECODE: [u16; 256] = {
    let mut t = [0u16; 256];
    let mut c = 0;
    while c < 256 {
        // Half up: the values are positive.
        t[c] = (eotf(c as f64 / 255.0) * 65535.0 + 0.5) as u16;
        c += 1;
    }
    t
};

/// Decision thresholds of [`encode`] in 16.8 linear units: code `k + 1`
/// starts at entry `k`, `ceil(EOTF((k + ½)/255)·65535·256)`; entry 255 is a
/// sentinel (`u32::MAX`).
pub const ENCODE_THRESHOLDS: [u32; 256] = {
    let mut t = [u32::MAX; 256];
    let mut k = 0;
    while k < 255 {
        let x = eotf((k as f64 + 0.5) / 255.0) * (65535.0 * 256.0);
        let whole = x as u32;
        t[k] = if (whole as f64) < x { whole + 1 } else { whole };
        k += 1;
    }
    t
};

/// Error bound of a re-encoded filtered result against the f64 sRGB
/// encoding of the exact linear filter, in 8-bit sRGB LSB (with
/// 12-bit bilinear weights the position error adds to it; see
/// `crate::texture::kernel::srgb`).
pub const SRGB_ENCODE_MAX_ERROR_LSB: f64 = 0.55;

/// Tier boundary of [`ENCODE_BUCKETS`]: values below `2²⁰` fall into
/// buckets of 2¹² (the thresholds there are more than 2¹² apart: at most
/// one per bucket), values above into buckets of 2¹⁴ (thresholds more than
/// 2¹⁴ apart there: at most one per bucket). Tested.
const ENCODE_TIER: u32 = 1 << ENCODE_TIER_BITS;

/// `log2` of [`ENCODE_TIER`].
const ENCODE_TIER_BITS: u32 = 20;

/// Buckets of [`ENCODE_BUCKETS`]: 256 of 2¹² below [`ENCODE_TIER`], 960 of
/// 2¹⁴ from it up to 2²⁴.
const ENCODE_BUCKET_COUNT: usize = 256 + (((1 << 24) - ENCODE_TIER) >> 14) as usize;

/// The largest input [`encode`] distinguishes (`2²⁴ − 1`, above 1.0 in
/// 16.8): larger values are clamped to it.
const ENCODE_MAX: u32 = (1 << 24) - 1;

/// The bucket of `x < 2²⁴`: `x >> 12` below [`ENCODE_TIER`] (`x >> 20 =
/// 0`), else `192 + (x >> 14)` (the first coarse bucket, `2²⁰ >> 14 = 64`,
/// follows the 256 fine ones); below [`ENCODE_BUCKET_COUNT`]. (Both forms
/// give 256 at the tier, so the test is on the tier's bits.)
#[inline(always)]
const fn encode_bucket(x: u32) -> u32 {
    if x >> ENCODE_TIER_BITS == 0 {
        x >> 12
    } else {
        192 + (x >> 14)
    }
}

/// The start of bucket `b` (the inverse of [`encode_bucket`] on bucket
/// starts; both forms give `2²⁰` at `b = 256`).
const fn encode_bucket_start(b: u32) -> u32 {
    if b >> 8 == 0 {
        b << 12
    } else {
        (b - 192) << 14
    }
}

/// `ENCODE_BUCKETS[b]`: the number of [`ENCODE_THRESHOLDS`] entries at or
/// below the start of bucket `b` ([`encode_bucket`]; values of `2²⁴` and
/// more are clamped to the last bucket, whose count is 255).
const ENCODE_BUCKETS: [u8; ENCODE_BUCKET_COUNT] = {
    let mut t = [0u8; ENCODE_BUCKET_COUNT];
    let mut b = 0;
    while b < ENCODE_BUCKET_COUNT {
        let start = encode_bucket_start(b as u32);
        let mut c = 0;
        while c < 255 && ENCODE_THRESHOLDS[c] <= start {
            c += 1;
        }
        t[b] = c as u8;
        b += 1;
    }
    t
};

/// 8-bit sRGB code of a linear 16.8 value `x` (65535·256 = 1.0; larger
/// values give 255): `round(255·OETF(x))`, the number of
/// [`ENCODE_THRESHOLDS`] entries at or below `x`: the count below the
/// bucket of `x` (the private table `ENCODE_BUCKETS`) plus the (at most
/// one) threshold inside it that `x` reaches. Never panics.
#[inline]
#[must_use]
pub fn encode(x: u32) -> u8 {
    let x = x.min(ENCODE_MAX);
    let b = encode_bucket(x);
    let c = ENCODE_BUCKETS.get(b as usize).copied().unwrap_or(255);
    // Entry 255 is the sentinel `u32::MAX`: `c ≤ 255` reads it at most.
    let t = ENCODE_THRESHOLDS[usize::from(c)];
    c + u8::from(x >= t)
}

/// The linear L16 value of sRGB code `c`.
#[inline(always)]
#[must_use]
pub fn decode(c: u8) -> u16 {
    DECODE[usize::from(c)]
}

/// Fills levels `1 .. levels` of an sRGB RGBA8 pyramid from level 0 like
/// [`mip::generate`](crate::texture::storage::mip::generate), but averaging RGB in linear
/// space (decoded by [`DECODE`], the exact box weights of `mip`, re-encoded
/// once by [`encode`] after rounding to 16.8); alpha is averaged as stored
/// and rounded half up.
///
/// # Errors
/// [`MipError::BufferTooShort`] when `buf` is shorter than the geometry.
///
/// Feature `mipgen`.
#[cfg(feature = "mipgen")]
pub fn generate(geometry: &Geometry, buf: &mut [Texel]) -> Result<(), MipError> {
    generate_mapped(
        geometry,
        buf,
        |t| {
            let [r, g, b, a] = t.to_le_bytes();
            [
                u32::from(decode(r)),
                u32::from(decode(g)),
                u32::from(decode(b)),
                u32::from(a),
            ]
        },
        |sum, den| {
            let den = den.max(1);
            let mut out = [0u8; 4];
            for (c, (o, s)) in out.iter_mut().zip(sum).enumerate() {
                // Half up: floor((2S·k + D) / 2D) with k = 256 (16.8) or 1.
                *o = if c < 3 {
                    let x = (s.saturating_mul(512).saturating_add(den)) / (2 * den);
                    encode(u32::try_from(x).unwrap_or(u32::MAX))
                } else {
                    u8::try_from((2 * s + den) / (2 * den)).unwrap_or(255)
                };
            }
            u32::from_le_bytes(out)
        },
    )
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use proptest::prelude::*;

    fn eotf(s: f64) -> f64 {
        if s <= 0.04045 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        }
    }

    fn oetf(l: f64) -> f64 {
        if l <= 0.0031308 {
            l * 12.92
        } else {
            1.055 * l.powf(1.0 / 2.4) - 0.055
        }
    }

    /// The compile-time EOTF takes the linear piece at its threshold
    /// `0.04045` itself (the power piece differs there in the last bits),
    /// and the power piece just above it.
    #[test]
    fn compile_time_eotf_at_the_threshold() {
        assert_eq!(super::eotf(0.04045), 0.04045 / 12.92);
        let above: f64 = 0.040_450_000_1;
        assert!((super::eotf(above) - eotf(above)).abs() < 1e-15);
    }

    #[test]
    fn tables_match_f64() {
        for (c, &d) in DECODE.iter().enumerate() {
            let want = (eotf(c as f64 / 255.0) * 65535.0).round();
            assert_eq!(f64::from(d), want, "decode {c}");
        }
        for (k, &t) in ENCODE_THRESHOLDS.iter().take(255).enumerate() {
            let want = (eotf((k as f64 + 0.5) / 255.0) * 65535.0 * 256.0).ceil();
            assert_eq!(f64::from(t), want, "threshold {k}");
        }
        assert_eq!(ENCODE_THRESHOLDS[255], u32::MAX);
    }

    /// The bucketed encode equals the binary search over every input of
    /// the 16.8 range and beyond, and the buckets hold at most one
    /// threshold (below 2²⁰ of 2¹², above of 2¹⁴), each bucket starting
    /// where the previous one ends.
    #[test]
    fn encode_equals_the_search() {
        let search = |x: u32| {
            let mut code = 0usize;
            for step in [128, 64, 32, 16, 8, 4, 2, 1] {
                if x >= ENCODE_THRESHOLDS[(code + step - 1) & 0xFF] {
                    code += step;
                }
            }
            code as u8
        };
        let step = if cfg!(miri) { 9973 } else { 1 };
        for x in (0..(1u32 << 24) + 4096).step_by(step) {
            assert_eq!(encode(x), search(x), "{x}");
        }
        for x in [u32::MAX, u32::MAX - 1, 1 << 31] {
            assert_eq!(encode(x), search(x), "{x}");
        }
        for w in ENCODE_THRESHOLDS[..255].windows(2) {
            let gap = w[1] - w[0];
            assert!(gap > 1 << 12, "{w:?}");
            assert!(w[0] < ENCODE_TIER || gap > 1 << 14, "{w:?}");
        }
        assert_eq!(ENCODE_BUCKET_COUNT, 1216);
        for b in 1..ENCODE_BUCKET_COUNT as u32 {
            let (start, end) = (encode_bucket_start(b - 1), encode_bucket_start(b));
            assert_eq!(end - start, if b <= 256 { 1 << 12 } else { 1 << 14 }, "{b}");
            assert_eq!(
                (encode_bucket(start), encode_bucket(end - 1)),
                (b - 1, b - 1)
            );
        }
        assert_eq!(encode_bucket(ENCODE_MAX), ENCODE_BUCKET_COUNT as u32 - 1);
        assert_eq!(encode_bucket(ENCODE_TIER - 1), 255);
        assert_eq!(encode_bucket(ENCODE_TIER), 256);
    }

    #[test]
    fn encode_inverts_decode() {
        for c in 0..=255u8 {
            assert_eq!(encode(u32::from(decode(c)) << 8), c);
        }
        assert_eq!(encode(0), 0);
        assert_eq!(encode(u32::MAX), 255);
    }

    proptest! {
        /// encode is the f64 rounding of 255·OETF(x) within the bound.
        #[test]
        fn encode_matches_f64(x in 0u32..=(65535 * 256)) {
            let exact = 255.0 * oetf(f64::from(x) / (65535.0 * 256.0));
            let got = f64::from(encode(x));
            prop_assert!((got - exact).abs() <= 0.5 + 1e-9, "{x}: {got} vs {exact}");
        }

        /// Linear-space pyramids: every level-1 texel against the f64
        /// linear box of its four sources, re-encoded.
        #[test]
        #[cfg(feature = "mipgen")]
        fn generate_in_linear_space(texels in proptest::collection::vec(any::<u32>(), 16)) {
            let g = Geometry::new(4, 4, 3).unwrap();
            let mut buf = std::vec![0u32; g.len()];
            buf[..16].copy_from_slice(&texels);
            generate(&g, &mut buf).unwrap();
            for y in 0..2usize {
                for x in 0..2usize {
                    let out = buf[16 + y * 2 + x].to_le_bytes();
                    for (c, &o) in out.iter().enumerate() {
                        let mut acc = 0.0;
                        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                            let v = f64::from(texels[(2 * y + dy) * 4 + 2 * x + dx].to_le_bytes()[c]);
                            acc += if c < 3 { eotf(v / 255.0) } else { v } / 4.0;
                        }
                        let exact = if c < 3 { 255.0 * oetf(acc) } else { acc };
                        prop_assert!((f64::from(o) - exact).abs() <= SRGB_ENCODE_MAX_ERROR_LSB,
                            "channel {c}: {o} vs {exact}");
                    }
                }
            }
        }
    }
}
