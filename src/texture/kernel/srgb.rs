//! The sRGB ends of the ACCURATE kernel: decoding texels to linear before
//! filtering, re-encoding after it.
//!
//! Texels are decoded to 16-bit linear lanes before filtering ([`load`]);
//! filtered values (16.8, 65535·256 = 1.0) are re-encoded to sRGB or
//! rounded to 8-bit linear after it ([`encode_output`], [`linear_output`]).
//! The filter between them is the corner sum of [`super::accurate`] on
//! 16-bit lanes with 16-bit position weights.
//!
//! # Error bounds (per channel, against the exact f64 filter)
//!
//! The 16.8 value of one sample is within, in units of full scale
//! (`1/65535`-steps × 65535): the decode table `2⁻¹⁷` (each texel within
//! half an L16 step, and the filter's weights sum to 1), the 16-bit
//! position `2·2⁻¹⁷`, the 16-bit corner weights `2⁻¹⁶`, the two 16.8
//! roundings `2⁻²³`: together `< 3.9·10⁻⁵`.
//!
//! * re-encoded ([`Srgb`](super::Srgb)): the encoding's own
//!   [`SRGB_ENCODE_MAX_ERROR_LSB`](crate::texture::storage::srgb::SRGB_ENCODE_MAX_ERROR_LSB)
//!   = 0.55 plus the linear error times the steepest slope of the sRGB
//!   curve, `12.92·255` LSB per unit: `0.55 + 3.9·10⁻⁵·3294.6 < 0.68 ≤`
//!   [`SRGB_MAX_ERROR_LSB`] `= 0.6875`;
//! * linear results ([`SrgbToLinear`](super::SrgbToLinear)) and alpha:
//!   `½ + 3.9·10⁻⁵·255 <` [`SRGB_LINEAR_MAX_ERROR_LSB`] `= 0.5101` (8-bit
//!   linear LSB).

use super::accurate::Lin16;
use crate::texture::storage::mip::Texel;
use crate::texture::storage::srgb;

/// Error bound of filtered sRGB data re-encoded to sRGB, in 8-bit sRGB
/// LSB (module docs).
pub const SRGB_MAX_ERROR_LSB: f64 = 0.6875;

/// Error bound of filtered sRGB data returned linear (and of the alpha
/// channel), in 8-bit linear LSB (module docs).
pub const SRGB_LINEAR_MAX_ERROR_LSB: f64 = 0.5101;

/// An sRGB texel decoded: RGB through [`srgb::DECODE`], alpha `a·257`.
#[inline(always)]
#[must_use]
pub fn load(t: Texel) -> Lin16 {
    let [r, g, b, a] = t.to_le_bytes();
    [
        u32::from(srgb::decode(r)),
        u32::from(srgb::decode(g)),
        u32::from(srgb::decode(b)),
        u32::from(a) * 257,
    ]
}

/// A linear RGBA8 texel (the border colour) as 16-bit lanes: `c·257`.
#[inline(always)]
#[must_use]
pub fn load_linear(t: Texel) -> Lin16 {
    t.to_le_bytes().map(|c| u32::from(c) * 257)
}

/// A 16.8 linear value (`≤ 65535·256`, larger values saturate) rounded to
/// 8 bits: `round(x / (257·256))`.
#[inline(always)]
fn to8(x: u32) -> u32 {
    (x.min(65535 << 8) + 257 * 128) / (257 * 256)
}

/// Four 16.8 linear channels as a texel: RGB re-encoded to sRGB
/// ([`srgb::encode`]), alpha rounded to 8 bits.
#[inline(always)]
#[must_use]
pub fn encode_output(v: [u32; 4]) -> Texel {
    // Four 8-bit channels (`to8 ≤ 255`): the sum is the packed word.
    u32::from(srgb::encode(v[0]))
        + (u32::from(srgb::encode(v[1])) << 8)
        + (u32::from(srgb::encode(v[2])) << 16)
        + (to8(v[3]) << 24)
}

/// Four 16.8 linear channels rounded to 8-bit linear.
#[inline(always)]
#[must_use]
pub fn linear_output(v: [u32; 4]) -> Texel {
    // Four 8-bit channels (`to8 ≤ 255`): the sum is the packed word.
    to8(v[0]) + (to8(v[1]) << 8) + (to8(v[2]) << 16) + (to8(v[3]) << 24)
}

/// The 16.8 channels of decoded lanes (exact, for nearest-texel modes).
#[inline(always)]
#[must_use]
pub fn widen(l: Lin16) -> [u32; 4] {
    l.map(|c| (c & 0xFFFF) << 8)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Decoding then re-encoding gives every code back (so a nearest
    /// sample of sRGB data needs neither), and the linear output of a
    /// decoded code is `round(255·EOTF(c/255))`.
    #[test]
    fn round_trips() {
        for c in 0..=255u8 {
            let t = u32::from_le_bytes([c, c, c, c]);
            assert_eq!(encode_output(widen(load(t))), t, "{c}");
            let s = f64::from(c) / 255.0;
            let lin = if s <= 0.04045 {
                s / 12.92
            } else {
                ((s + 0.055) / 1.055).powf(2.4)
            };
            let got = linear_output(widen(load(t)));
            assert!((f64::from(got & 0xFF) - 255.0 * lin).abs() <= SRGB_LINEAR_MAX_ERROR_LSB);
            assert_eq!(got >> 24, u32::from(c));
            assert_eq!(linear_output(widen(load_linear(t))), t);
        }
    }
}
