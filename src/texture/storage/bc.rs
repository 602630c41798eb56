//! Block compression BC1–BC4 (D3D names; DXT1, DXT3, DXT5, ATI1/RGTC1):
//! decoding of one 4×4 block to RGBA8 texels.
//!
//! Texel `i = 4·y + x` of a block, row-major. Little-endian fields:
//!
//! * **BC1** (8 bytes): colours `c₀, c₁` (RGB565, bytes 0–1 and 2–3), then
//!   32 bits of 2-bit indices (texel `i` at bit `2i`). The endpoints expand
//!   to RGB8 by bit replication ([`crate::texture::storage::format`]). If `c₀ > c₁` (as
//!   16-bit integers) the block has **four colours**: `c₂ = (2c₀ + c₁)/3`,
//!   `c₃ = (c₀ + 2c₁)/3`; otherwise **three colours and transparent
//!   black**: `c₂ = (c₀ + c₁)/2`, `c₃ = (0, 0, 0, 0)`. Alpha is 255 except
//!   for that black.
//! * **BC2** (16 bytes): 64 bits of explicit 4-bit alpha (texel `i` in
//!   nibble `i`, low nibble first), widened ×17, then a BC1 colour block
//!   that is **always decoded in four-colour mode** (D3D: the `c₀ ≤ c₁`
//!   case has no special meaning in BC2/BC3).
//! * **BC3** (16 bytes): an alpha block as BC4's, then a BC1 colour block
//!   in four-colour mode.
//! * **BC4** (8 bytes): values `r₀, r₁` (bytes 0, 1), then 48 bits of
//!   3-bit indices (texel `i` at bit `3i` of bytes 2–7). If `r₀ > r₁`,
//!   **eight values**: `r_k = ((8 − k)·r₀ + (k − 1)·r₁)/7` for
//!   `k = 2 … 7`; otherwise **six values and the two extremes**:
//!   `r_k = ((6 − k)·r₀ + (k − 1)·r₁)/5` for `k = 2 … 5`, `r₆ = 0`,
//!   `r₇ = 255`. BC4 decodes to `(r, 0, 0, 255)` (the D3D defaults for the
//!   missing channels).
//!
//! Interpolation is per 8-bit channel in integers, the division truncating
//! (`/` below is integer division). The D3D specification states the
//! palettes as real-valued fractions of the endpoints and lets hardware
//! round within a tolerance; this integer form is the one common software
//! decoders implement and is tested bit-exact against one (the
//! `texture2ddecoder` crate, in `host-tests/tests/harness/bc_decode.rs`), over
//! random blocks and every mode edge.
//!
//! The texel cache decodes a whole block on a fill ([`decode_block`]); an
//! uncached read decodes one texel ([`decode_texel`]). Both never panic: a
//! byte slice shorter than the block reads as zeros.

use crate::texture::storage::format::{TexelFormat, widen5, widen6};
use crate::texture::storage::mip::Texel;

/// Texels per block (4 × 4).
pub const BLOCK_TEXELS: usize = 16;

/// The `N` bytes at `at` of `bytes`, zeros where the slice is short.
#[inline(always)]
fn bytes_at<const N: usize>(bytes: &[u8], at: usize) -> [u8; N] {
    let mut out = [0u8; N];
    for (i, o) in out.iter_mut().enumerate() {
        *o = bytes.get(at + i).copied().unwrap_or(0);
    }
    out
}

/// An RGB565 endpoint as `[r, g, b]` 8-bit channels (bit replication).
#[inline(always)]
fn endpoint(c: u16) -> [u32; 3] {
    let c = u32::from(c);
    [widen5(c >> 11), widen6(c >> 5), widen5(c)]
}

/// RGBA8 texel from channels (each ≤ 255).
#[inline(always)]
fn pack(rgb: [u32; 3], a: u32) -> Texel {
    rgb[0] | (rgb[1] << 8) | (rgb[2] << 16) | (a << 24)
}

/// The four palette colours of the BC1 colour block at `bytes[at..at+8]`;
/// `four_colour_only` for BC2/BC3.
#[inline]
fn colour_palette(bytes: &[u8], at: usize, four_colour_only: bool) -> [Texel; 4] {
    let [a0, a1, b0, b1] = bytes_at::<4>(bytes, at);
    let (c0, c1) = (u16::from_le_bytes([a0, a1]), u16::from_le_bytes([b0, b1]));
    let (e0, e1) = (endpoint(c0), endpoint(c1));
    let mix = |w0: u32, w1: u32, den: u32| -> [u32; 3] {
        [0, 1, 2].map(|k| (w0 * e0[k] + w1 * e1[k]) / den)
    };
    if c0 > c1 || four_colour_only {
        [
            pack(e0, 255),
            pack(e1, 255),
            pack(mix(2, 1, 3), 255),
            pack(mix(1, 2, 3), 255),
        ]
    } else {
        [pack(e0, 255), pack(e1, 255), pack(mix(1, 1, 2), 255), 0]
    }
}

/// The eight values of the BC4/BC3-alpha block at `bytes[at..at+8]`.
#[inline]
fn value_palette(bytes: &[u8], at: usize) -> [u32; 8] {
    let [r0, r1] = bytes_at::<2>(bytes, at).map(u32::from);
    let mut p = [r0, r1, 0, 0, 0, 0, 0, 255];
    if r0 > r1 {
        for (k, v) in (2u32..).zip(p.iter_mut().skip(2)) {
            *v = ((8 - k) * r0 + (k - 1) * r1) / 7;
        }
    } else {
        for (k, v) in (2u32..).zip(p.iter_mut().skip(2).take(4)) {
            *v = ((6 - k) * r0 + (k - 1) * r1) / 5;
        }
        p[6] = 0;
    }
    p
}

/// 2-bit colour index of texel `i` of the colour block at `at`.
#[inline(always)]
fn colour_index(bytes: &[u8], at: usize, i: usize) -> usize {
    let bits = u32::from_le_bytes(bytes_at::<4>(bytes, at + 4));
    ((bits >> (2 * (i & 15))) & 3) as usize
}

/// 3-bit value index of texel `i` of the value block at `at`.
#[inline(always)]
fn value_index(bytes: &[u8], at: usize, i: usize) -> usize {
    let [a, b, c, d, e, f] = bytes_at::<6>(bytes, at + 2);
    let bits = u64::from_le_bytes([a, b, c, d, e, f, 0, 0]);
    ((bits >> (3 * (i & 15))) & 7) as usize
}

/// Explicit 4-bit alpha of texel `i` (BC2), widened to 8 bits.
#[inline(always)]
fn explicit_alpha(bytes: &[u8], i: usize) -> u32 {
    let i = i & 15;
    let byte = u32::from(bytes.get(i / 2).copied().unwrap_or(0));
    let a = (byte >> (4 * (i & 1))) & 0xF;
    a * 17
}

/// Replaces the alpha of `t`.
#[inline(always)]
fn with_alpha(t: Texel, a: u32) -> Texel {
    (t & 0x00FF_FFFF) | (a << 24)
}

/// Decodes the whole block `bytes` (at least [`TexelFormat::unit_bytes`]
/// long; missing bytes read as 0) of a BC `format` into `out`, row-major.
/// Uncompressed formats fill `out` with 0.
pub fn decode_block(format: TexelFormat, bytes: &[u8], out: &mut [Texel; BLOCK_TEXELS]) {
    match format {
        TexelFormat::Bc1 => {
            let p = colour_palette(bytes, 0, false);
            for (i, o) in out.iter_mut().enumerate() {
                *o = p[colour_index(bytes, 0, i)];
            }
        }
        TexelFormat::Bc2 => {
            let p = colour_palette(bytes, 8, true);
            for (i, o) in out.iter_mut().enumerate() {
                *o = with_alpha(p[colour_index(bytes, 8, i)], explicit_alpha(bytes, i));
            }
        }
        TexelFormat::Bc3 => {
            let p = colour_palette(bytes, 8, true);
            let a = value_palette(bytes, 0);
            for (i, o) in out.iter_mut().enumerate() {
                *o = with_alpha(p[colour_index(bytes, 8, i)], a[value_index(bytes, 0, i)]);
            }
        }
        TexelFormat::Bc4 => {
            let r = value_palette(bytes, 0);
            for (i, o) in out.iter_mut().enumerate() {
                *o = r[value_index(bytes, 0, i)] | 0xFF00_0000;
            }
        }
        _ => *out = [0; BLOCK_TEXELS],
    }
}

/// Decodes texel `i` (`0..16`, row-major; taken mod 16) of the block
/// `bytes` of a BC `format` (as [`decode_block`], one texel).
#[must_use]
pub fn decode_texel(format: TexelFormat, bytes: &[u8], i: usize) -> Texel {
    match format {
        TexelFormat::Bc1 => colour_palette(bytes, 0, false)[colour_index(bytes, 0, i)],
        TexelFormat::Bc2 => with_alpha(
            colour_palette(bytes, 8, true)[colour_index(bytes, 8, i)],
            explicit_alpha(bytes, i),
        ),
        TexelFormat::Bc3 => with_alpha(
            colour_palette(bytes, 8, true)[colour_index(bytes, 8, i)],
            value_palette(bytes, 0)[value_index(bytes, 0, i)],
        ),
        TexelFormat::Bc4 => value_palette(bytes, 0)[value_index(bytes, 0, i)] | 0xFF00_0000,
        _ => 0,
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use proptest::prelude::*;

    fn t(r: u8, g: u8, b: u8, a: u8) -> Texel {
        u32::from_le_bytes([r, g, b, a])
    }

    /// Hand-worked reference vectors of each mode.
    #[test]
    fn reference_vectors() {
        // BC1 four-colour: c0 = white (0xFFFF), c1 = black; indices 0,1,2,3.
        let four = [0xFF, 0xFF, 0x00, 0x00, 0b1110_0100, 0, 0, 0];
        // BC1 three-colour: c0 = black < c1 = white: c2 = 127, c3 transparent.
        let three = [0x00, 0x00, 0xFF, 0xFF, 0b1110_0100, 0, 0, 0];
        // The same colour block in BC2/BC3 is four-colour.
        let mut bc2 = [0u8; 16];
        bc2[0] = 0xF0; // texel 0 alpha 0, texel 1 alpha 255
        bc2[8..].copy_from_slice(&three);
        let (white, black) = (t(255, 255, 255, 255), t(0, 0, 0, 255));
        for (name, format, block, want) in [
            (
                "BC1 four-colour",
                TexelFormat::Bc1,
                &four[..],
                [white, black, t(170, 170, 170, 255), t(85, 85, 85, 255)],
            ),
            (
                "BC1 three-colour",
                TexelFormat::Bc1,
                &three[..],
                [black, white, t(127, 127, 127, 255), 0],
            ),
            (
                "BC2",
                TexelFormat::Bc2,
                &bc2[..],
                [t(0, 0, 0, 0), white, t(85, 85, 85, 0), t(170, 170, 170, 0)],
            ),
        ] {
            let mut out = [0; 16];
            decode_block(format, block, &mut out);
            assert_eq!(out[..4], want, "{name}");
        }
        let mut out = [0; 16];
        // BC4 eight values: r0 = 255, r1 = 0: index 2 → 6·255/7 = 218.
        let b4 = [255, 0, 0b0000_0010, 0, 0, 0, 0, 0];
        decode_block(TexelFormat::Bc4, &b4, &mut out);
        assert_eq!(out[0] & 0xFF, 218);
        assert_eq!(out[1] & 0xFF, 255); // texel 1: index 0 = r0
        // BC4 six values: r0 = 0 ≤ r1 = 100: indices 6 → 0, 7 → 255, 2 → 20.
        let b4 = [0, 100, 0b10_111_110, 0, 0, 0, 0, 0];
        decode_block(TexelFormat::Bc4, &b4, &mut out);
        assert_eq!([out[0] & 0xFF, out[1] & 0xFF, out[2] & 0xFF], [0, 255, 20]);
        assert!(out.iter().all(|&x| x >> 8 == 0xFF_0000));
    }

    /// Every texel of one block per mode: endpoints whose channels are all
    /// non-zero and different (each term of an interpolation counts),
    /// every index at several texel positions (no periodic pattern), the
    /// palettes worked by hand from the formulas of the module docs. Also
    /// the one-texel decode (texel numbers taken mod 16) and an
    /// uncompressed format, which decodes to zeros.
    #[test]
    fn every_texel_of_each_mode() {
        // Colour indices of texels 0..16 (bytes 4..8 of a colour block).
        const CI: [usize; 16] = [0, 1, 2, 3, 3, 2, 1, 0, 1, 3, 0, 2, 2, 0, 3, 1];
        const CI_BYTES: [u8; 4] = [0xE4, 0x1B, 0x8D, 0x72];
        // Value indices of texels 0..16 (bytes 2..8 of a value block).
        const VI: [usize; 16] = [0, 1, 2, 3, 4, 5, 6, 7, 7, 5, 3, 1, 6, 4, 2, 0];
        const VI_BYTES: [u8; 6] = [0x88, 0xC6, 0xFA, 0xEF, 0x62, 0x0A];
        // RGB565 (31, 20, 10) = 0xFA8A widens to (255, 81, 82), (4, 50, 25)
        // = 0x2659 to (33, 203, 206).
        let (hi, lo) = ([0x8A, 0xFA], [0x59, 0x26]);
        let (e_hi, e_lo) = (t(255, 81, 82, 255), t(33, 203, 206, 255));
        let colour = |c0: [u8; 2], c1: [u8; 2]| [&c0[..], &c1, &CI_BYTES].concat();
        let value = |r0: u8, r1: u8| [&[r0, r1][..], &VI_BYTES].concat();
        // c₂ = (2c₀ + c₁)/3 = (543, 365, 370)/3, c₃ = (c₀ + 2c₁)/3 =
        // (321, 487, 494)/3.
        let four = [e_hi, e_lo, t(181, 121, 123, 255), t(107, 162, 164, 255)];
        // c₀ < c₁: c₂ = (c₀ + c₁)/2 = (288, 284, 288)/2, c₃ transparent.
        let three = [e_lo, e_hi, t(144, 142, 144, 255), 0];
        // c₀ = c₁ is the three-colour mode too.
        let same = [e_lo, e_lo, e_lo, 0];
        // r₀ = 200 > r₁ = 50: r_k = ((8 − k)·200 + (k − 1)·50)/7.
        let eight = [200, 50, 178, 157, 135, 114, 92, 71];
        // r₀ = 50 ≤ r₁ = 201: r_k = ((6 − k)·50 + (k − 1)·201)/5, 0, 255.
        let six = [50, 201, 80, 110, 140, 170, 0, 255];
        // r₀ = r₁ = 90: six values, all 90, then 0 and 255.
        let equal = [90, 90, 90, 90, 90, 90, 0, 255];
        // BC2: the alpha nibble of texel i is 7i mod 16.
        let alpha = [0x70, 0x5E, 0x3C, 0x1A, 0xF8, 0xD6, 0xB4, 0x92];
        let nibble = |i: usize| (7 * i as u32 % 16) * 17;
        let rgb = |c: Texel| c & 0x00FF_FFFF;
        let cases: [(TexelFormat, std::vec::Vec<u8>, [Texel; 16]); 8] = [
            (TexelFormat::Bc1, colour(hi, lo), CI.map(|k| four[k])),
            (TexelFormat::Bc1, colour(lo, hi), CI.map(|k| three[k])),
            (TexelFormat::Bc1, colour(lo, lo), CI.map(|k| same[k])),
            // BC2 and BC3 colour blocks are four-colour, also for c₀ < c₁.
            (
                TexelFormat::Bc2,
                [&alpha[..], &colour(lo, hi)].concat(),
                core::array::from_fn(|i| {
                    rgb([e_lo, e_hi, four[3], four[2]][CI[i]]) | nibble(i) << 24
                }),
            ),
            (
                TexelFormat::Bc3,
                [value(200, 50), colour(hi, lo)].concat(),
                core::array::from_fn(|i| rgb(four[CI[i]]) | eight[VI[i]] << 24),
            ),
            (
                TexelFormat::Bc4,
                value(200, 50),
                VI.map(|k| eight[k] | 0xFF00_0000),
            ),
            (
                TexelFormat::Bc4,
                value(50, 201),
                VI.map(|k| six[k] | 0xFF00_0000),
            ),
            (
                TexelFormat::Bc4,
                value(90, 90),
                VI.map(|k| equal[k] | 0xFF00_0000),
            ),
        ];
        for (format, block, want) in cases {
            let mut out = [0; 16];
            decode_block(format, &block, &mut out);
            assert_eq!(out, want, "{format:?} {block:02x?}");
            for (i, &w) in want.iter().enumerate() {
                assert_eq!(decode_texel(format, &block, i), w, "{format:?} texel {i}");
                assert_eq!(
                    decode_texel(format, &block, i + 16),
                    w,
                    "{format:?} texel {i} + 16"
                );
            }
        }
        let mut out = [1; 16];
        decode_block(TexelFormat::Rgba8, &[0xFF; 16], &mut out);
        assert_eq!(out, [0; 16]);
        assert_eq!(decode_texel(TexelFormat::Rgba8, &[0xFF; 16], 3), 0);
    }

    proptest! {
        /// One-texel decode equals the block decode, for every format.
        #[test]
        fn texel_equals_block(bytes in proptest::collection::vec(any::<u8>(), 0..20)) {
            for f in [TexelFormat::Bc1, TexelFormat::Bc2, TexelFormat::Bc3, TexelFormat::Bc4] {
                let mut out = [0; 16];
                decode_block(f, &bytes, &mut out);
                for (i, &o) in out.iter().enumerate() {
                    prop_assert_eq!(decode_texel(f, &bytes, i), o);
                }
            }
        }
    }
}
