//! Fixed-point bilinear kernel (Bilerp) and the level blend of trilinear
//! filtering, per RGBA8 channel, in 32-bit integer arithmetic.
//!
//! Weights have [`WEIGHT_BITS`] = 12 fractional bits (`fx, fy ∈ [0, 4096]`).
//! For channel values `a, b` (top row) and `c, d` (bottom row):
//!
//! ```text
//! top  = a·(4096 − fx) + b·fx                      ≤ 255·2¹²   (8.12)
//! bot  = c·(4096 − fx) + d·fx
//! wide = (top·(4096 − fy) + bot·fy + 2⁷) >> 8      ≤ 255·2¹⁶   (8.16)
//! ```
//!
//! `top·(4096 − fy) + bot·fy ≤ 255·2²⁴ < 2³²`, so nothing overflows `u32`.
//! A [`Wide`] value keeps 16 fractional bits for the level blend of
//! trilinear filtering, whose weight `t ∈ [0, 256]` (8 fractional bits, the
//! fraction of an I8F8 lod) is exact:
//! `out = (wide₀·(256 − t) + wide₁·t + 2²³) >> 24`, again `≤ 255·2²⁴ + 2²³`.
//! Outputs are rounded to nearest (ties up) per channel.
//!
//! # Error bound
//!
//! Against the exact real-valued filter at the exact sample position, per
//! channel, in 8-bit LSB: final rounding ½, the 8.16 intermediate 2⁻¹⁷, and
//! the texel position rounded to 1/4096 texel per axis (done by the caller,
//! [`crate::filter`]), at most `255 · 2⁻¹³` per axis. Total
//! `0.5 + 2·255/8192 + 2⁻¹⁷ < 0.5623 ≤` [`BILERP_MAX_ERROR_LSB`] `= 0.5625`, for
//! bilinear and trilinear alike (the blend of two values each within
//! `0.0623` stays within it).

use crate::mip::Texel;

/// Fractional bits of the bilinear weights.
pub const WEIGHT_BITS: u32 = 12;

/// Weight 1.0 in [`WEIGHT_BITS`] format (4096).
pub const WEIGHT_ONE: u32 = 1 << WEIGHT_BITS;

/// Fractional bits of the trilinear blend weight (an I8F8 lod fraction).
pub const BLEND_BITS: u32 = 8;

/// Documented error bound of bilinear and trilinear filtering against the
/// exact f64 filter, in 8-bit LSB per channel: 0.5625.
pub const BILERP_MAX_ERROR_LSB: f64 = 0.5625;

/// Four channels (r, g, b, a) in 8.16 unsigned fixed point, each in
/// `[0, 255·2¹⁶]`.
pub type Wide = [u32; 4];

/// Channel `c` (0 = r … 3 = a) of a texel, 0..=255.
#[inline(always)]
fn ch(t: Texel, c: usize) -> u32 {
    (t >> (8 * c)) & 0xFF
}

/// Bilinear interpolation of the 2×2 footprint `t00` (x0, y0), `t10`
/// (x1, y0), `t01` (x0, y1), `t11` (x1, y1) with weights `fx, fy` in
/// `[0, 4096]` (values above 4096 are clamped); result in 8.16 per channel.
#[inline]
#[must_use]
pub fn bilerp(t00: Texel, t10: Texel, t01: Texel, t11: Texel, fx: u32, fy: u32) -> Wide {
    bilerp_in_range([t00, t10, t01, t11], fx.min(WEIGHT_ONE), fy.min(WEIGHT_ONE))
}

/// [`bilerp`] for `fx, fy ≤ 4096` (the sampler's weights are masked to 12
/// bits). Every intermediate is `≤ 255·2²⁴ + 2⁷ < 2³²` for such weights;
/// wrapping operations only avoid a debug overflow check on a path that
/// cannot overflow.
#[inline(always)]
pub(crate) fn bilerp_in_range(t: [Texel; 4], fx: u32, fy: u32) -> Wide {
    let gx = WEIGHT_ONE.wrapping_sub(fx);
    let gy = WEIGHT_ONE.wrapping_sub(fy);
    let mut out = [0u32; 4];
    for (c, o) in out.iter_mut().enumerate() {
        let (top, bot) = rows(t, c, fx, gx);
        *o = top
            .wrapping_mul(gy)
            .wrapping_add(bot.wrapping_mul(fy))
            .wrapping_add(1 << 7)
            >> 8;
    }
    out
}

/// Channel `c` of the top and the bottom texel pair blended along x:
/// `(t₀·gx + t₁·fx, t₂·gx + t₃·fx)` with `gx = 4096 − fx` (each
/// `≤ 255·2¹²`).
#[inline(always)]
fn rows(t: [Texel; 4], c: usize, fx: u32, gx: u32) -> (u32, u32) {
    let top = ch(t[0], c)
        .wrapping_mul(gx)
        .wrapping_add(ch(t[1], c).wrapping_mul(fx));
    let bot = ch(t[2], c)
        .wrapping_mul(gx)
        .wrapping_add(ch(t[3], c).wrapping_mul(fx));
    (top, bot)
}

/// [`bilerp_in_range`] rounded to a texel in one step, bit-identical to
/// `round_wide_in_range(bilerp_in_range(t, fx, fy))`: with
/// `X = top·(4096 − fy) + bot·fy ≤ 255·2²⁴`,
/// `floor((floor((X + 2⁷)/2⁸) + 2¹⁵)/2¹⁶) = floor((X + 2⁷ + 2²³)/2²⁴)`
/// (a floor of an integer plus an integer composes), and
/// `X + 2⁷ + 2²³ < 2³²`.
#[inline(always)]
pub(crate) fn bilerp_rounded(t: [Texel; 4], fx: u32, fy: u32) -> Texel {
    let gx = WEIGHT_ONE.wrapping_sub(fx);
    let gy = WEIGHT_ONE.wrapping_sub(fy);
    let mut out = 0u32;
    for c in 0..4 {
        let (top, bot) = rows(t, c, fx, gx);
        let r = top
            .wrapping_mul(gy)
            .wrapping_add(bot.wrapping_mul(fy))
            .wrapping_add((1 << 7) + (1 << 23))
            >> 24;
        out |= (r & 0xFF) << (8 * c);
    }
    out
}

/// A texel widened to 8.16 per channel (exact).
#[inline]
#[must_use]
pub fn widen(t: Texel) -> Wide {
    [
        ch(t, 0) << 16,
        ch(t, 1) << 16,
        ch(t, 2) << 16,
        ch(t, 3) << 16,
    ]
}

/// Rounds an 8.16 value to a texel (nearest, ties up; saturates at 255).
#[inline]
#[must_use]
pub fn round_wide(w: Wide) -> Texel {
    round_wide_in_range(w.map(|v| v.min(255 << 16)))
}

/// [`round_wide`] for channels `≤ 255·2¹⁶` (as [`bilerp`] returns them):
/// `(v + 2¹⁵) >> 16 ≤ 255`; the mask keeps channels apart for any input.
#[inline(always)]
pub(crate) fn round_wide_in_range(w: Wide) -> Texel {
    let mut out = 0u32;
    for (c, &v) in w.iter().enumerate() {
        out |= ((v.wrapping_add(1 << 15) >> 16) & 0xFF) << (8 * c);
    }
    out
}

/// Level blend `a·(1 − t/256) + b·t/256` of two 8.16 values, rounded to a
/// texel (nearest, ties up). `t` in `[0, 256]` (clamped); channels above
/// `255·2¹⁶` are clamped.
#[inline]
#[must_use]
pub fn blend_wide(a: Wide, b: Wide, t: u32) -> Texel {
    blend_wide_in_range(
        a.map(|v| v.min(255 << 16)),
        b.map(|v| v.min(255 << 16)),
        t.min(1 << BLEND_BITS),
    )
}

/// [`blend_wide`] for channels `≤ 255·2¹⁶` and `t ≤ 256`:
/// `a·(256 − t) + b·t + 2²³ ≤ 255·2²⁴ + 2²³ < 2³²`, result `≤ 255`.
#[inline(always)]
pub(crate) fn blend_wide_in_range(a: Wide, b: Wide, t: u32) -> Texel {
    let s = (1u32 << BLEND_BITS).wrapping_sub(t);
    let mut out = 0u32;
    for c in 0..4 {
        let r = a[c]
            .wrapping_mul(s)
            .wrapping_add(b[c].wrapping_mul(t))
            .wrapping_add(1 << 23)
            >> 24;
        out |= (r & 0xFF) << (8 * c);
    }
    out
}

/// Level blend of two texels (nearest texel, linear between levels),
/// rounded to nearest (ties up). `t` in `[0, 256]` (clamped).
#[inline]
#[must_use]
pub fn blend_texels(a: Texel, b: Texel, t: u32) -> Texel {
    let t = t.min(1 << BLEND_BITS);
    let s = (1 << BLEND_BITS) - t;
    let mut out = 0u32;
    for c in 0..4 {
        let r = (ch(a, c) * s + ch(b, c) * t + (1 << 7)) >> 8;
        out |= r << (8 * c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texel(r: u8, g: u8, b: u8, a: u8) -> Texel {
        u32::from_le_bytes([r, g, b, a])
    }

    /// Reference vectors: (t00, t10, t01, t11, fx/4096, fy/4096, exact
    /// real-valued red channel, worked out by hand).
    #[allow(clippy::type_complexity)]
    const BILERP_VECTORS: [(u8, u8, u8, u8, u32, u32, f64); 8] = [
        (0, 255, 0, 255, 2048, 0, 127.5),
        (0, 255, 0, 255, 2048, 2048, 127.5),
        (0, 0, 0, 255, 2048, 2048, 63.75),
        (10, 20, 30, 40, 0, 0, 10.0),
        (10, 20, 30, 40, 4096, 4096, 40.0),
        (10, 20, 30, 40, 1024, 3072, 10.0 + 2.5 + 15.0),
        (255, 255, 255, 255, 1, 4095, 255.0),
        (
            0,
            255,
            255,
            0,
            1024,
            1024,
            255.0 * (3.0 / 16.0 + 3.0 / 16.0),
        ),
    ];

    #[test]
    fn reference_vectors_within_limit() {
        for &(a, b, c, d, fx, fy, exact) in &BILERP_VECTORS {
            let w = bilerp(
                texel(a, 0, 0, 255),
                texel(b, 0, 0, 255),
                texel(c, 0, 0, 255),
                texel(d, 0, 0, 255),
                fx,
                fy,
            );
            let out = round_wide(w);
            let r = f64::from(out & 0xFF);
            assert!(
                (r - exact).abs() <= BILERP_MAX_ERROR_LSB,
                "{a},{b},{c},{d} @ {fx},{fy}: {r} vs {exact}"
            );
            // The 8.16 value is within 2^-17 LSB of exact.
            assert!((f64::from(w[0]) / 65536.0 - exact).abs() <= 1.0 / 131072.0);
            assert_eq!(out >> 24, 255, "alpha");
        }
    }

    /// Reference vectors of the level blend: (a, b, t/256, exact).
    const BLEND_VECTORS: [(u8, u8, u32, f64); 6] = [
        (0, 255, 128, 127.5),
        (0, 255, 1, 255.0 / 256.0),
        (100, 200, 64, 125.0),
        (200, 100, 192, 125.0),
        (7, 7, 77, 7.0),
        (255, 0, 256, 0.0),
    ];

    #[test]
    fn blend_vectors_within_limit() {
        for &(a, b, t, exact) in &BLEND_VECTORS {
            let wa = widen(texel(a, a, a, a));
            let wb = widen(texel(b, b, b, b));
            let out = blend_wide(wa, wb, t);
            let out2 = blend_texels(texel(a, a, a, a), texel(b, b, b, b), t);
            assert_eq!(out, out2);
            for c in 0..4 {
                let v = f64::from((out >> (8 * c)) & 0xFF);
                assert!((v - exact).abs() <= 0.5, "{a},{b},{t}: {v} vs {exact}");
            }
        }
    }

    #[test]
    fn extremes_do_not_overflow() {
        let w = bilerp(u32::MAX, u32::MAX, u32::MAX, u32::MAX, 5000, 9999);
        assert_eq!(w, [255 << 16; 4]);
        assert_eq!(round_wide(w), u32::MAX);
        assert_eq!(blend_wide([u32::MAX; 4], [u32::MAX; 4], 999), u32::MAX);
        assert_eq!(blend_texels(u32::MAX, u32::MAX, 999), u32::MAX);
    }

    #[test]
    fn rounded_bilerp_equals_two_roundings() {
        let mut x = 0x2545_F491_u64;
        let draws = if cfg!(miri) { 300 } else { 200_000u32 };
        for n in 0..draws {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let t = [
                x as u32,
                (x >> 16) as u32,
                (x >> 32) as u32,
                (x >> 40) as u32 | (n << 24),
            ];
            let (fx, fy) = ((x >> 48) as u32 & 0xFFF, (n * 37) % 4097);
            let t = if n % 7 == 0 { [u32::MAX; 4] } else { t };
            assert_eq!(
                bilerp_rounded(t, fx, fy),
                round_wide_in_range(bilerp_in_range(t, fx, fy)),
                "{t:x?} {fx} {fy}"
            );
        }
    }
}
