//! Test data in every firmware texel format: RGBA8 pyramids converted to
//! the byte layout of `raymip::texture::storage::image` (uncompressed formats quantized by
//! `TexelFormat::encode`, BC1–BC4 by a simple block encoder written here).
//!
//! The BC encoder is deliberately simple (quality is not the point, being
//! correct is): per 4×4 block the colour endpoints are the per-channel
//! minimum and maximum of the block quantized to RGB565 (the box's
//! diagonal), every texel takes the nearest palette entry (squared RGB
//! distance); BC1 blocks with a texel of alpha < 128 use the three-colour
//! mode with index 3 (transparent black) for those texels; BC2 alpha is
//! `round(a/17)`; BC3 alpha and BC4 red use the min/max as the two values
//! in eight-value mode and the nearest of the eight. Decoding is the
//! firmware's (`raymip::texture::storage::bc`), itself checked against an independent
//! decoder in `tests/bc_decode.rs`.

use raymip::texture::storage::bc;
use raymip::texture::storage::format::TexelFormat;
use raymip::texture::storage::mip::{Geometry, Texel};

/// Channel `c` of `t`.
fn ch(t: Texel, c: usize) -> i32 {
    i32::from(t.to_le_bytes()[c])
}

/// Squared RGB distance.
fn dist(a: Texel, b: Texel) -> i32 {
    (0..3).map(|c| (ch(a, c) - ch(b, c)).pow(2)).sum()
}

/// RGB565 of an RGBA8 texel (rounded).
fn to565(t: Texel) -> u16 {
    TexelFormat::Rgb565.encode(t) as u16
}

/// The 8-byte BC1 colour block of `texels`; `four_colour` forces the
/// four-colour palette (BC2/BC3), otherwise transparent texels (alpha
/// < 128) select the three-colour mode.
fn colour_block(texels: &[Texel; 16], four_colour: bool) -> [u8; 8] {
    let transparent = !four_colour && texels.iter().any(|&t| t >> 24 < 128);
    // Endpoints: the two (opaque) texels farthest apart.
    let used: Vec<Texel> = texels
        .iter()
        .copied()
        .filter(|&t| four_colour || t >> 24 >= 128)
        .collect();
    let (mut e0, mut e1) = (
        used.first().copied().unwrap_or(0),
        used.first().copied().unwrap_or(0),
    );
    for (i, &a) in used.iter().enumerate() {
        for &b in &used[i + 1..] {
            if dist(a, b) > dist(e0, e1) {
                (e0, e1) = (a, b);
            }
        }
    }
    let (mut c0, mut c1) = (to565(e0), to565(e1));
    // Four-colour mode needs c0 > c1, three-colour mode c0 ≤ c1.
    if transparent == (c0 > c1) {
        std::mem::swap(&mut c0, &mut c1);
    }
    if !transparent && !four_colour && c0 == c1 {
        // Equal endpoints would mean three-colour mode: nudge apart.
        if c0 > 0 {
            c1 = c0 - 1;
        } else {
            c0 = 1;
        }
    }
    let mut block = [0u8; 8];
    block[..2].copy_from_slice(&c0.to_le_bytes());
    block[2..4].copy_from_slice(&c1.to_le_bytes());
    // The palette as the firmware decodes it: texel 0 with index k.
    let mut entries = [0u32; 4];
    for (k, e) in entries.iter_mut().enumerate() {
        let mut b = block;
        b[4] = k as u8;
        let mut out = [0u32; 16];
        if four_colour {
            let mut full = [0u8; 16];
            full[8..].copy_from_slice(&b);
            bc::decode_block(TexelFormat::Bc2, &full, &mut out);
        } else {
            bc::decode_block(TexelFormat::Bc1, &b, &mut out);
        }
        *e = out[0];
    }
    let mut bits = 0u32;
    for (i, &t) in texels.iter().enumerate() {
        let k = if transparent && t >> 24 < 128 {
            3
        } else {
            let usable = if transparent { 3 } else { 4 };
            (0..usable)
                .min_by_key(|&k| dist(t, entries[k]))
                .unwrap_or(0)
        };
        bits |= (k as u32) << (2 * i);
    }
    block[4..].copy_from_slice(&bits.to_le_bytes());
    block
}

/// The 8-byte BC4 block of channel values `v` (eight-value mode).
fn value_block(v: &[u8; 16]) -> [u8; 8] {
    let (lo, hi) = (*v.iter().min().unwrap_or(&0), *v.iter().max().unwrap_or(&0));
    // r0 = max > r1 = min: eight-value mode (equal values: six-value
    // mode, whose first two entries are that value).
    let mut block = [0u8; 8];
    block[0] = hi;
    block[1] = lo;
    let mut entries = [0u32; 8];
    for (k, e) in entries.iter_mut().enumerate() {
        let mut b = block;
        b[2] = k as u8;
        *e = bc::decode_texel(TexelFormat::Bc4, &b, 0) & 0xFF;
    }
    let mut bits = 0u64;
    for (i, &x) in v.iter().enumerate() {
        let k = (0..8)
            .min_by_key(|&k| (i64::from(x) - i64::from(entries[k])).abs())
            .unwrap_or(0);
        bits |= (k as u64) << (3 * i);
    }
    block[2..].copy_from_slice(&bits.to_le_bytes()[..6]);
    block
}

/// Encodes one 4×4 block of RGBA8 texels (row-major) in a BC `format`
/// (8 or 16 bytes); an uncompressed format gives an empty vector.
#[must_use]
pub fn encode_block(format: TexelFormat, texels: &[Texel; 16]) -> Vec<u8> {
    let channel = |c: usize| -> [u8; 16] { texels.map(|t| t.to_le_bytes()[c]) };
    match format {
        TexelFormat::Bc1 => colour_block(texels, false).to_vec(),
        TexelFormat::Bc2 => {
            let mut out = vec![0u8; 8];
            for (i, a) in channel(3).iter().enumerate() {
                let q = (u32::from(*a) + 8) / 17;
                out[i / 2] |= (q as u8) << (4 * (i % 2));
            }
            out.extend_from_slice(&colour_block(texels, true));
            out
        }
        TexelFormat::Bc3 => {
            let mut out = value_block(&channel(3)).to_vec();
            out.extend_from_slice(&colour_block(texels, true));
            out
        }
        TexelFormat::Bc4 => value_block(&channel(0)).to_vec(),
        _ => Vec::new(),
    }
}

/// Converts an RGBA8 pyramid (`raymip::texture::storage::mip` layout, every level present)
/// to the byte layout of `raymip::texture::storage::image::Image` in `format`.
#[must_use]
pub fn encode_pyramid(geometry: &Geometry, texels: &[Texel], format: TexelFormat) -> Vec<u8> {
    let mut out = Vec::with_capacity(raymip::texture::storage::image::image_len(
        geometry.width(),
        geometry.height(),
        geometry.levels(),
        format,
    ));
    for level in 0..geometry.levels() {
        let (w, h) = geometry.level_size(level);
        let get = |x: u32, y: u32| {
            texels
                .get(geometry.texel_index(level, x, y))
                .copied()
                .unwrap_or(0)
        };
        if format.is_block_compressed() {
            for by in 0..h.div_ceil(4) {
                for bx in 0..w.div_ceil(4) {
                    let mut block = [0u32; 16];
                    for (i, t) in block.iter_mut().enumerate() {
                        // Edge texels repeat into the padding.
                        *t = get(bx * 4 + (i as u32 % 4), by * 4 + (i as u32 / 4));
                    }
                    out.extend_from_slice(&encode_block(format, &block));
                }
            }
        } else {
            let n = format.unit_bytes() as usize;
            for y in 0..h {
                for x in 0..w {
                    out.extend_from_slice(&format.encode(get(x, y)).to_le_bytes()[..n]);
                }
            }
        }
    }
    out
}
