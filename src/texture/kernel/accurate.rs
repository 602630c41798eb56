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
//! # Evaluation
//!
//! `top·(4096 − fy) + bot·fy` is evaluated expanded, as the corner sum
//! `X = a·w₀₀ + b·w₁₀ + c·w₀₁ + d·w₁₁` with the four corner weights
//! `w₀₀ = (4096 − fx)(4096 − fy)`, `w₁₀ = fx(4096 − fy)`,
//! `w₀₁ = (4096 − fx)fy`, `w₁₁ = fx·fy` (each `≤ 2²⁴`, sum `2²⁴`): the
//! same integer (distribute the products), so the results are the ones
//! of the formulas above bit for bit (tested against them). The weights
//! are computed once per footprint from one multiply (`w₁₁`; the others
//! by shifts and subtractions, all non-negative), and each channel is one
//! chain of four multiply-accumulates started from the rounding constant
//! (`mla` on the Cortex-M4): every intermediate of the chain is a partial
//! sum of non-negative terms of `X + 2⁷ + 2²³ < 2³²`, so wrapping `u32`
//! operations never wrap.
//!
//! The lerp form `top = a·2¹² + (b − a)·fx` (and likewise for the vertical
//! step and the level blend) also gives the same integers in wrapping
//! `u32` arithmetic — the exact value lies in `[0, 2³²)` and wrapping
//! arithmetic is exact modulo `2³²` — with three multiplies per channel
//! instead of four, but each of them needs a subtraction and a shift
//! beside it; measured (scripts/budgets, QEMU traces) it executed more
//! instructions than the per-channel corner sum: bilinear 136 → 141
//! (Cortex-M4), 162 → 179 (RV32IMAC), trilinear 275 → 300 and 316 → 354.
//!
//! # Error bound
//!
//! Against the exact real-valued filter at the exact sample position, per
//! channel, in 8-bit LSB: final rounding ½, the 8.16 intermediate 2⁻¹⁷, and
//! the texel position rounded to 1/4096 texel per axis (done by the caller,
//! [`crate::texture::address`]), at most `255 · 2⁻¹³` per axis. Total
//! `0.5 + 2·255/8192 + 2⁻¹⁷ < 0.5623 ≤` [`BILERP_MAX_ERROR_LSB`] `= 0.5625`, for
//! bilinear and trilinear alike (the blend of two values each within
//! `0.0623` stays within it).
//!
//! # 16-bit lanes (sRGB)
//!
//! sRGB texels are decoded to 16-bit linear channels ([`crate::texture::storage::srgb::DECODE`],
//! 65535 = 1.0) before filtering, and a 16-bit channel times a 24-bit
//! weight does not fit 32 bits. The same corner sum then runs with
//! 16-bit corner weights from 16-bit position weights ([`Lin16`],
//! `corner_weights16`): `W₁₁ = (fx·fy + 2¹⁵) >> 16`, `W₁₀ = fx − W₁₁`,
//! `W₀₁ = fy − W₁₁`, `W₀₀ = 2¹⁶ − fx − W₀₁` (all non-negative, sum
//! exactly 2¹⁶), `X = Σ c·W ≤ 65535·2¹⁶`, one level's value
//! `(X + 2⁷) >> 8` in 16.8 (the same shift as the 8.16 value of 8-bit
//! lanes) and the level blend `(a·(256 − t) + b·t + 2⁷) >> 8`, again 16.8.
//! Error of the 16.8 result against the exact linear filter, in units of
//! full scale: position `2·2⁻¹⁷`, weights `|c₀₀ − c₁₀ − c₀₁ + c₁₁|·2⁻¹⁷ ≤ 2⁻¹⁶`,
//! the two 16.8 roundings `< 2⁻²³`, below `3.1·10⁻⁵` in all
//! (the sRGB bound that follows is in [`super::srgb`]).

use crate::texture::storage::mip::Texel;

/// Fractional bits of the bilinear weights: the address stage's
/// ([`address::WEIGHT_BITS`](crate::texture::address::WEIGHT_BITS)).
pub use crate::texture::address::WEIGHT_BITS;

/// Weight 1.0 in [`WEIGHT_BITS`] format (4096).
pub const WEIGHT_ONE: u32 = 1 << WEIGHT_BITS;

/// Fractional bits of the trilinear blend weight (an I8F8 lod fraction).
pub const BLEND_BITS: u32 = 8;

/// Documented error bound of bilinear and trilinear filtering against the
/// exact f64 filter, in 8-bit LSB per channel: 0.5625.
pub const BILERP_MAX_ERROR_LSB: f64 = 0.5625;

/// The rounding term of one level's 8.16 value, `2⁷` (`(X + 2⁷) >> 8`).
pub const ROUND_WIDE: u32 = 1 << 7;
/// The rounding term of a bilinear texel, `2⁷ + 2²³`
/// (`(X + 2⁷ + 2²³) >> 24`).
pub const ROUND_TEXEL: u32 = (1 << 7) + (1 << 23);
/// The rounding term of the level blend, `2²³`
/// (`(a·(256 − t) + b·t + 2²³) >> 24`).
pub const ROUND_BLEND: u32 = 1 << 23;

/// Four channels (r, g, b, a) in 8.16 unsigned fixed point, each in
/// `[0, 255·2¹⁶]`.
pub type Wide = [u32; 4];

/// Channel `c` (0 = r … 3 = a) of a texel, 0..=255.
#[inline(always)]
fn ch(t: Texel, c: usize) -> u32 {
    (t >> (8 * c)) & 0xFF
}

/// A texel as the ACCURATE kernel filters it: four channels of 8 bits
/// (an RGBA8 [`Texel`]) or 16 bits ([`Lin16`]).
pub(crate) trait Lanes: Copy {
    /// Channel `c` (0 = r … 3 = a), `< 2^BITS`.
    fn ch(self, c: usize) -> u32;
}

impl Lanes for Texel {
    #[inline(always)]
    fn ch(self, c: usize) -> u32 {
        ch(self, c)
    }
}

/// Four 16-bit linear channels (65535 = 1.0), one per word: `[r, g, b,
/// a]` (decoded sRGB texels, [`super::srgb`]), so that the filter reads a
/// channel without an extract.
pub type Lin16 = [u32; 4];

impl Lanes for Lin16 {
    #[inline(always)]
    fn ch(self, c: usize) -> u32 {
        self[c & 3]
    }
}

/// The corner weights of 16-bit lanes from 16-bit position weights
/// `fx, fy ≤ 65535` (module docs): `W₁₁ = (fx·fy + 2¹⁵) >> 16`,
/// `W₁₀ = fx − W₁₁`, `W₀₁ = fy − W₁₁`, `W₀₀ = 2¹⁶ − fx − W₀₁`; each
/// `≥ 0` (`W₁₁ ≤ min(fx, fy)`, and `W₀₀` is within ½ of
/// `(2¹⁶ − fx)(2¹⁶ − fy)/2¹⁶ ≥ 2⁻¹⁶`), sum exactly 2¹⁶, each within ½ of
/// its exact value (`W₁₁`, `W₀₀` off by `+e`, `W₁₀`, `W₀₁` by `−e`).
#[inline(always)]
pub(crate) fn corner_weights16(fx: u32, fy: u32) -> [u32; 4] {
    let w11 = fx.wrapping_mul(fy).wrapping_add(1 << 15) >> 16;
    let w10 = fx.wrapping_sub(w11);
    let w01 = fy.wrapping_sub(w11);
    let w00 = (1u32 << 16).wrapping_sub(fx).wrapping_sub(w01);
    [w00, w10, w01, w11]
}

/// One level's bilinear value of lanes `t` with the corner weights `w`
/// of [`corner_weights`] (8-bit lanes) or [`corner_weights16`] (16-bit):
/// `(X + 2⁷) >> 8` per channel (8.16 for 8-bit lanes, 16.8 for 16-bit
/// lanes; `X < 2³²`), with `r =` [`ROUND_WIDE`] (the sampler's
/// [`Rounding`](super::Rounding)).
#[inline(always)]
pub(crate) fn bilerp_lanes<L: Lanes>(t: [L; 4], w: [u32; 4], r: u32) -> Wide {
    debug_assert_eq!(r, ROUND_WIDE);
    bilerp_lanes_with(t, w, r)
}

/// `(corner_sum + r) >> 8` per channel for a rounding term `r ≤ 2²³ + 2⁷`
/// (below `2³²`: [`corner_sum`]).
#[inline(always)]
fn bilerp_lanes_with<L: Lanes>(t: [L; 4], w: [u32; 4], r: u32) -> Wide {
    let mut out = [0u32; 4];
    for (c, o) in out.iter_mut().enumerate() {
        *o = corner_sum(t, w, c, r) >> 8;
    }
    out
}

/// The level blend of two [`bilerp_lanes`] values kept at their
/// precision: `(a·(256 − t) + b·t + 2⁷) >> 8` per channel (`r =`
/// [`ROUND_WIDE`]) (`a, b < 2²⁴`,
/// `t ≤ 256`: the sum is below 2³²). For 8-bit lanes its
/// `(x + 2¹⁵) >> 16` is [`blend_wide_in_range`] bit for bit (a floor of
/// an integer plus an integer composes).
#[inline(always)]
pub(crate) fn blend_keep(a: Wide, b: Wide, t: u32, r: u32) -> Wide {
    debug_assert_eq!(r, ROUND_WIDE);
    let s = (1u32 << BLEND_BITS).wrapping_sub(t);
    let mut out = [0u32; 4];
    for (c, o) in out.iter_mut().enumerate() {
        *o = r
            .wrapping_add(a[c].wrapping_mul(s))
            .wrapping_add(b[c].wrapping_mul(t))
            >> 8;
    }
    out
}

/// Bilinear interpolation of the 2×2 footprint `t00` (x0, y0), `t10`
/// (x1, y0), `t01` (x0, y1), `t11` (x1, y1) with weights `fx, fy` in
/// `[0, 4096]` (values above 4096 are clamped); result in 8.16 per channel.
#[inline]
#[must_use]
pub fn bilerp(t00: Texel, t10: Texel, t01: Texel, t11: Texel, fx: u32, fy: u32) -> Wide {
    bilerp_in_range(
        [t00, t10, t01, t11],
        fx.min(WEIGHT_ONE),
        fy.min(WEIGHT_ONE),
        ROUND_WIDE,
    )
}

/// [`bilerp`] for `fx, fy ≤ 4096` (the sampler's weights are masked to 12
/// bits): `(X + 2⁷) >> 8` per channel with `X` the corner sum of
/// [`corner_sum`] (`≤ 255·2²⁴`, so nothing overflows).
#[inline(always)]
pub(crate) fn bilerp_in_range(t: [Texel; 4], fx: u32, fy: u32, r: u32) -> Wide {
    bilerp_lanes(t, corner_weights(fx, fy), r)
}

/// The four corner weights `[(4096 − fx)(4096 − fy), fx(4096 − fy),
/// (4096 − fx)fy, fx·fy]` of `t00, t10, t01, t11` for `fx, fy ≤ 4096`
/// (each `≤ 2²⁴`, sum `2²⁴`), from one multiply: `w₁₁ = fx·fy`,
/// `w₁₀ = 2¹²fx − w₁₁`, `w₀₁ = 2¹²fy − w₁₁`, `w₀₀ = 2²⁴ − 2¹²fx − w₀₁`.
#[inline(always)]
pub(crate) fn corner_weights(fx: u32, fy: u32) -> [u32; 4] {
    let w11 = fx.wrapping_mul(fy);
    let w10 = (fx << WEIGHT_BITS).wrapping_sub(w11);
    let w01 = (fy << WEIGHT_BITS).wrapping_sub(w11);
    let w00 = (1u32 << (2 * WEIGHT_BITS))
        .wrapping_sub(fx << WEIGHT_BITS)
        .wrapping_sub(w01);
    [w00, w10, w01, w11]
}

/// `r + Σᵢ tᵢ[c]·wᵢ` for channel `c` with the [`corner_weights`] `w`:
/// the exact `X = top·(4096 − fy) + bot·fy` of the module docs (expand
/// `top` and `bot`) plus `r`. `X ≤ 255·2²⁴`, and the callers' `r` is a
/// rounding constant `≤ 2²³ + 2⁷`, so the sum is below `2³²` and the
/// wrapping operations never wrap (for 16-bit lanes likewise with the
/// 16-bit weights: `X ≤ 65535·2¹⁶`). One chain of multiply-accumulates
/// (`mla` on the M4) starting from `r`.
#[inline(always)]
fn corner_sum<L: Lanes>(t: [L; 4], w: [u32; 4], c: usize, r: u32) -> u32 {
    r.wrapping_add(t[0].ch(c).wrapping_mul(w[0]))
        .wrapping_add(t[1].ch(c).wrapping_mul(w[1]))
        .wrapping_add(t[2].ch(c).wrapping_mul(w[2]))
        .wrapping_add(t[3].ch(c).wrapping_mul(w[3]))
}

/// [`bilerp_in_range`] rounded to a texel in one step, bit-identical to
/// `round_wide_in_range(bilerp_in_range(t, fx, fy))`: with
/// `X = top·(4096 − fy) + bot·fy ≤ 255·2²⁴`,
/// `floor((floor((X + 2⁷)/2⁸) + 2¹⁵)/2¹⁶) = floor((X + 2⁷ + 2²³)/2²⁴)`
/// (a floor of an integer plus an integer composes), and
/// `X + 2⁷ + 2²³ < 2²⁴·256`, so each channel's result is at most 255
/// (`r =` [`ROUND_TEXEL`]).
/// (With feature `pcpi` on riscv32 the co-processor's `tex.bb` replaces it.)
#[cfg_attr(all(feature = "pcpi", target_arch = "riscv32"), allow(dead_code))]
#[inline(always)]
pub(crate) fn bilerp_rounded(t: [Texel; 4], fx: u32, fy: u32, r: u32) -> Texel {
    debug_assert_eq!(r, ROUND_TEXEL);
    let w = corner_weights(fx, fy);
    let mut out = 0u32;
    for c in 0..4 {
        out |= (corner_sum(t, w, c, r) >> 24) << (8 * c);
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
        ROUND_BLEND,
    )
}

/// [`blend_wide`] for channels `≤ 255·2¹⁶` and `t ≤ 256`:
/// `a·(256 − t) + b·t + 2²³ ≤ 255·2²⁴ + 2²³ < 2³²`, result `≤ 255`
/// (`r =` [`ROUND_BLEND`]).
#[inline(always)]
pub(crate) fn blend_wide_in_range(a: Wide, b: Wide, t: u32, r: u32) -> Texel {
    debug_assert_eq!(r, ROUND_BLEND);
    let s = (1u32 << BLEND_BITS).wrapping_sub(t);
    let mut out = 0u32;
    for c in 0..4 {
        let v = r
            .wrapping_add(a[c].wrapping_mul(s))
            .wrapping_add(b[c].wrapping_mul(t))
            >> 24;
        out |= v << (8 * c);
    }
    out
}

/// One level of a trilinear sample: the 8.16 value plus ½ LSB,
/// `(X + 2⁷ + 2²³) >> 8 = bilerp + 2¹⁵` per channel (`r =`
/// [`ROUND_TEXEL`]: the chains start from the bilinear texel's rounding
/// term, and the level blend needs no rounding term of its own:
/// `a·(256 − t) + b·t + 2²³ = (a + 2¹⁵)·(256 − t) + (b + 2¹⁵)·t`).
/// Each channel `≤ 255·2¹⁶ + 2¹⁵ < 2²⁴`. Unused where feature `pcpi` on
/// riscv32 filters the ACCURATE levels on the co-processor.
#[cfg(not(all(feature = "pcpi", target_arch = "riscv32")))]
#[inline(always)]
pub(crate) fn bilerp_half(t: [Texel; 4], fx: u32, fy: u32, r: u32) -> Wide {
    debug_assert_eq!(r, ROUND_TEXEL);
    bilerp_lanes_with(t, corner_weights(fx, fy), r)
}

/// The first level's share of the level blend of two [`bilerp_half`]
/// values: `a·(256 − t)` per channel (`t ≤ 256`; `< 2³²`).
/// [`blend_finish`] adds the second level's share and rounds; with
/// `t = 0` [`blend_finish_one`] rounds it alone.
#[cfg(not(all(feature = "pcpi", target_arch = "riscv32")))]
#[inline(always)]
pub(crate) fn blend_start(a: Wide, t: u32) -> Wide {
    let s = (1u32 << BLEND_BITS).wrapping_sub(t);
    a.map(|a| a.wrapping_mul(s))
}

/// `(started + b·t) >> 24` per channel for `started =`
/// [`blend_start`]`(a + 2¹⁵, t)` and `b + 2¹⁵` ([`bilerp_half`] values):
/// `(a·(256 − t) + b·t + 2²³) >> 24`, which is
/// [`blend_wide_in_range`]`(a, b, t, 2²³)` (tested), each `≤ 255`.
#[cfg(not(all(feature = "pcpi", target_arch = "riscv32")))]
#[inline(always)]
pub(crate) fn blend_finish(started: Wide, b: Wide, t: u32) -> Texel {
    let mut out = 0u32;
    for c in 0..4 {
        out |= (started[c].wrapping_add(b[c].wrapping_mul(t)) >> 24) << (8 * c);
    }
    out
}

/// `started >> 24` per channel for `started =` [`blend_start`]`(a + 2¹⁵, 0)
/// = 256·(a + 2¹⁵)`: `(a + 2¹⁵) >> 16`, which is
/// [`round_wide_in_range`]`(a)` (tested).
#[cfg(not(all(feature = "pcpi", target_arch = "riscv32")))]
#[inline(always)]
pub(crate) fn blend_finish_one(started: Wide) -> Texel {
    let mut out = 0u32;
    for (c, &v) in started.iter().enumerate() {
        out |= (v >> 24) << (8 * c);
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
    use crate::rng::XorShift64;
    use crate::texture::kernel::footprint;

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

    /// The nested two-step form of the module docs, written out directly
    /// (`top`, `bot`, then the vertical step, per channel): the integer
    /// reference of the corner sum.
    fn nested(t: [Texel; 4], fx: u32, fy: u32, c: usize) -> u32 {
        let (gx, gy) = (4096 - fx, 4096 - fy);
        let top = ch(t[0], c) * gx + ch(t[1], c) * fx;
        let bot = ch(t[2], c) * gx + ch(t[3], c) * fx;
        top * gy + bot * fy
    }

    /// The corner sum equals the nested form for every weight pair
    /// `fx ∈ [0, 4096]` (all) × `fy` (a stride through `[0, 4096]` and
    /// both ends), on pseudo-random and extreme texels: bilerp, the
    /// rounded bilerp and the wide values are bit-identical to it.
    #[test]
    fn corner_sum_equals_nested_form() {
        let mut rng = XorShift64(0x9E37_79B9);
        let (step_x, step_y) = if cfg!(miri) { (1024, 2048) } else { (1, 61) };
        for fx in (0..=4096u32).step_by(step_x) {
            for fy in (0..=4096u32).step_by(step_y).chain([1, 4095, 4096]) {
                let x = rng.next_u64();
                let t = match fx % 5 {
                    0 => [u32::MAX, 0, 0, u32::MAX],
                    _ => footprint(x, fx),
                };
                let w = bilerp_in_range(t, fx, fy, ROUND_WIDE);
                let mut rounded = 0;
                for (c, &wc) in w.iter().enumerate() {
                    let exact = nested(t, fx, fy, c);
                    assert_eq!(wc, (exact + (1 << 7)) >> 8, "{t:x?} {fx} {fy} {c}");
                    rounded |= ((exact + (1 << 7) + (1 << 23)) >> 24) << (8 * c);
                }
                assert_eq!(
                    bilerp_rounded(t, fx, fy, ROUND_TEXEL),
                    rounded,
                    "{t:x?} {fx} {fy}"
                );
            }
        }
    }

    /// The level blend equals `(a·(256 − t) + b·t + 2²³) >> 24` per channel
    /// for every `t` and pseudo-random and extreme 8.16 values.
    #[test]
    fn blend_equals_formula() {
        let mut x = 0x2545_F491_4F6C_DD1D_u64;
        for t in 0..=256u32 {
            for n in 0..if cfg!(miri) { 2 } else { 64 } {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                let v = |k: u32| match n % 4 {
                    0 => 255 << 16,
                    1 => 0,
                    _ => ((x >> (8 * k)) as u32) % ((255 << 16) + 1),
                };
                let (a, b) = ([v(0), v(1), v(2), v(3)], [v(4), v(1), v(5), v(6)]);
                let mut want = 0;
                for c in 0..4 {
                    want |= ((a[c] * (256 - t) + b[c] * t + (1 << 23)) >> 24) << (8 * c);
                }
                assert_eq!(
                    blend_wide_in_range(a, b, t, ROUND_BLEND),
                    want,
                    "{a:x?} {b:x?} {t}"
                );
            }
        }
    }

    /// The trilinear level form: [`bilerp_half`] is the 8.16 value plus
    /// 2¹⁵, and the started blend of two of them gives
    /// [`blend_wide_in_range`] (and, with `t = 0`, [`round_wide_in_range`])
    /// of the 8.16 values, for every `t` and pseudo-random and extreme
    /// footprints and weights.
    #[test]
    fn started_blend_equals_blend_of_levels() {
        let mut rng = XorShift64(0x5851_F42D_4C95_7F2D);
        let mut next = || rng.next_u64();
        let draws = if cfg!(miri) { 4 } else { 400 };
        for n in 0..draws {
            let (ta, tb) = (footprint(next(), n), footprint(next(), n / 5));
            let r = next();
            let w = |k: u32| match (n + k) % 7 {
                0 => 0,
                1 => 4096,
                _ => (r >> (12 * k)) as u32 % 4097,
            };
            let (fxa, fya, fxb, fyb) = (w(0), w(1), w(2), w(3));
            let (a, b) = (
                bilerp_in_range(ta, fxa, fya, ROUND_WIDE),
                bilerp_in_range(tb, fxb, fyb, ROUND_WIDE),
            );
            let (ha, hb) = (
                bilerp_half(ta, fxa, fya, ROUND_TEXEL),
                bilerp_half(tb, fxb, fyb, ROUND_TEXEL),
            );
            assert_eq!(ha, a.map(|v| v + (1 << 15)));
            assert_eq!(hb, b.map(|v| v + (1 << 15)));
            assert_eq!(blend_finish_one(blend_start(ha, 0)), round_wide_in_range(a));
            for t in 0..=256u32 {
                assert_eq!(
                    blend_finish(blend_start(ha, t), hb, t),
                    blend_wide_in_range(a, b, t, ROUND_BLEND),
                    "{ta:x?} {tb:x?} {t}"
                );
            }
        }
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
                bilerp_rounded(t, fx, fy, ROUND_TEXEL),
                round_wide_in_range(bilerp_in_range(t, fx, fy, ROUND_WIDE)),
                "{t:x?} {fx} {fy}"
            );
        }
    }
}
