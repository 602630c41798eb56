//! FAST filter kernel at GPU precision: 8 sub-texel bits, 8-bit corner
//! weights, 8-bit level weight, two channels per 32-bit register.
//!
//! D3D11 requires 8 fractional sub-texel bits and 8 fractional lod bits
//! (`D3D11_SUBTEXEL_FRACTIONAL_BIT_COUNT`, `D3D11_MIP_LOD_FRACTIONAL_BIT_COUNT`);
//! this kernel uses exactly those. The position weights `x, y ∈ [0, 255]`
//! (units of 1/256 texel, rounded to nearest by the addressing) give the
//! corner weights
//!
//! ```text
//! W₁₁ = (x·y + 128) >> 8,  W₁₀ = x − W₁₁,  W₀₁ = y − W₁₁,  W₀₀ = 256 − x − W₀₁
//! ```
//!
//! each `≥ 0` (`W₁₁ ≤ x` since `y < 256`; `W₀₀` is within ½ of
//! `(256 − x)(256 − y)/256 ≥ 1/256`), summing to exactly 256. A texel
//! splits into two words of two 16-bit lanes, `rb = t & 0x00FF00FF` and
//! `ga = (t >> 8) & 0x00FF00FF`, and one multiply-accumulate per word and
//! texel filters two channels: `RB = Σ rbᵢ·Wᵢ`, each lane
//! `≤ 255·256 = 65280 < 2¹⁶`, so no lane carries into the next and none
//! goes negative (every term is a non-negative `a·w`, the
//! `a·(256 − f) + b·f` form). One level's value [`Wide`] keeps both words
//! unrounded (lane = 256 × the filtered value at the quantized position,
//! exact); a bilinear sample rounds it once, `(lane + 128) >> 8`.
//!
//! Between levels the blend `Y = A·(256 − t) + B·t` of two lanes needs 24
//! bits, so each lane is split into its high and low byte, blended
//! separately (each `≤ 255·256`), and recombined exactly:
//! `round(Y / 2¹⁶) = (H + (L >> 8) + 128) >> 8` with
//! `H = Aₕ(256 − t) + Bₕt`, `L = Aₗ(256 − t) + Bₗt` (a floor of an
//! integer plus an integer composes, and `2¹⁵ = 128·2⁸`), each lane
//! `≤ 65280 + 128`. So the trilinear result is the exact blend of the two
//! levels' values, rounded once.
//!
//! # Error bound (proof)
//!
//! Per channel, in 8-bit LSB, against the exact real-valued filter at the
//! exact sample position (what the f64 references compute):
//!
//! * final rounding: `≤ ½` (one rounding of an exact value, bilinear and
//!   trilinear alike: the level blend is exact);
//! * one level: `E = Σ cᵢ·(Wᵢ/256 − wᵢ(x, y))` for channel values
//!   `cᵢ ∈ [0, 255]` and the exact bilinear weights `wᵢ` at the exact
//!   position `(x, y)` inside the cell of the quantized `(x₈, y₈)`
//!   (`|x − x₈/256| ≤ 1/512`, likewise `y`). For fixed cell and weights,
//!   `E` is linear in `c`, so its maximum over `[0, 255]⁴` is at a vertex
//!   `c ∈ {0, 255}⁴`; for fixed `c`, `E` is bilinear in `(x, y)` (the `Wᵢ`
//!   are constant in the cell), so its maximum over the cell is at a
//!   corner. Enumerating all `257²` cells (`x₈ = 256` stands for a
//!   position rounded up to the next texel pair), their four corners
//!   (clipped to the texel) and the 16 vertices gives the exact maximum,
//!   [`FAST_LEVEL_MAX_ERROR_LSB`] `= 1.9008` (at `x₈ = 8, y₈ = 240`:
//!   the corner weight `W₁₀ = 0` where the exact one is ½, plus
//!   the position). The enumeration runs as a test.
//! * the level blend is a convex combination of two levels' errors.
//!
//! Total `≤ ½ + 1.9008 <` [`FAST_MAX_ERROR_LSB`] `= 2.40625`, bilinear and
//! trilinear. Any kernel with 8-bit corner weights has a worst case of at
//! least `255/256 + ½ ≈ 1.496` LSB even at exact positions (at
//! `x = ½, y = 127/256` the four exact weights are all `k + ½` in 1/256,
//! and rounding two of them up and two down leaves `255·(½ + ½)/256` for
//! some `c`), so packing two channels per register cannot reach 1.5 LSB
//! with D3D11's 8-bit positions (up to `2·255/512` more); this kernel
//! trades that for half the multiplies of the ACCURATE one.

use crate::texture::storage::mip::Texel;

/// Fractional bits of the FAST position weights (D3D11's sub-texel bits).
pub const FAST_WEIGHT_BITS: u32 = 8;

/// The exact worst case of one level before the final rounding, in 8-bit
/// LSB (enumerated in the tests; module docs).
pub const FAST_LEVEL_MAX_ERROR_LSB: f64 = 1.9008;

/// Documented error bound of the FAST kernel against the exact f64
/// filter, in 8-bit LSB per channel, bilinear and trilinear: 2.40625
/// (proof in the [module docs](self)).
pub const FAST_MAX_ERROR_LSB: f64 = 2.40625;

/// Lane mask: channels 0 and 2 (or 1 and 3 after `>> 8`).
const LANES: u32 = 0x00FF_00FF;

/// Rounding constant of both lanes: 128 each.
const HALF: u32 = 0x0080_0080;

/// One level's unrounded value: `[RB, GA]`, each lane 256 × the filtered
/// channel (`≤ 65280`).
pub type Wide = [u32; 2];

/// The corner weights `[W₀₀, W₁₀, W₀₁, W₁₁]` of the 8-bit position
/// weights `x, y ≤ 255` (module docs; sum 256, each `≥ 0`).
#[inline(always)]
#[must_use]
pub fn corner_weights(x: u32, y: u32) -> [u32; 4] {
    let w11 = x.wrapping_mul(y).wrapping_add(128) >> 8;
    let w10 = x.wrapping_sub(w11);
    let w01 = y.wrapping_sub(w11);
    let w00 = 256u32.wrapping_sub(x).wrapping_sub(w01);
    [w00, w10, w01, w11]
}

/// One level of the footprint `t` (`t00, t10, t01, t11`) at the 8-bit
/// position weights `x, y ≤ 255`: both words' sums, unrounded.
#[inline(always)]
#[must_use]
pub fn bilinear(t: [Texel; 4], x: u32, y: u32) -> Wide {
    let w = corner_weights(x, y);
    let mut rb = 0u32;
    let mut ga = 0u32;
    for (&texel, &wi) in t.iter().zip(&w) {
        rb = rb.wrapping_add((texel & LANES).wrapping_mul(wi));
        ga = ga.wrapping_add(((texel >> 8) & LANES).wrapping_mul(wi));
    }
    [rb, ga]
}

/// A [`Wide`] value rounded to a texel: `(lane + 128) >> 8` per lane
/// (`≤ 255`; the sum stays below 2¹⁶ in every lane).
#[inline(always)]
#[must_use]
pub fn round(v: Wide) -> Texel {
    let rb = (v[0].wrapping_add(HALF) >> 8) & LANES;
    let ga = v[1].wrapping_add(HALF) & !LANES;
    rb | ga
}

/// The level blend `A·(256 − t) + B·t` of two [`Wide`] values, rounded
/// once (module docs: high and low bytes blended apart, recombined
/// exactly). `t ≤ 256`.
#[inline(always)]
#[must_use]
pub fn blend(a: Wide, b: Wide, t: u32) -> Texel {
    let s = 256u32.wrapping_sub(t);
    let word = |a: u32, b: u32| {
        let h = ((a >> 8) & LANES)
            .wrapping_mul(s)
            .wrapping_add(((b >> 8) & LANES).wrapping_mul(t));
        let l = (a & LANES)
            .wrapping_mul(s)
            .wrapping_add((b & LANES).wrapping_mul(t));
        h.wrapping_add((l >> 8) & LANES).wrapping_add(HALF)
    };
    ((word(a[0], b[0]) >> 8) & LANES) | (word(a[1], b[1]) & !LANES)
}

/// The four channels of a [`Wide`] value in 8.16 (exact: `lane << 8`),
/// for sums over anisotropic probes.
#[inline(always)]
#[must_use]
pub fn unpack(v: Wide) -> [u32; 4] {
    [
        (v[0] & 0xFFFF) << 8,
        (v[1] & 0xFFFF) << 8,
        (v[0] >> 16) << 8,
        (v[1] >> 16) << 8,
    ]
}

/// The exact level blend of two [`Wide`] values in 8.16 per channel:
/// `A·(256 − t) + B·t` (lanes are 256 × the value, so the blend is
/// 2¹⁶ × the value; `≤ 65280·256 < 2²⁴`), for sums over anisotropic
/// probes.
#[inline(always)]
#[must_use]
pub fn blend_unpacked(a: Wide, b: Wide, t: u32) -> [u32; 4] {
    let s = 256u32.wrapping_sub(t);
    let (a, b) = (unpack(a), unpack(b));
    let mut out = [0u32; 4];
    for (o, (x, y)) in out.iter_mut().zip(a.iter().zip(&b)) {
        *o = (x >> 8)
            .wrapping_mul(s)
            .wrapping_add((y >> 8).wrapping_mul(t));
    }
    out
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;

    fn ch(t: Texel, c: usize) -> f64 {
        f64::from((t >> (8 * c)) & 0xFF)
    }

    /// The proof's enumeration: every cell, corner and channel vertex.
    /// Also checks the weights: non-negative, sum 256.
    #[test]
    fn level_error_enumerated() {
        let mut worst = 0.0f64;
        let step = if cfg!(miri) { 37 } else { 1 };
        for x8 in (0..=256u32).step_by(step) {
            for y8 in (0..=256u32).step_by(step) {
                let w = corner_weights(x8.min(256), y8.min(256));
                assert_eq!(w.iter().sum::<u32>(), 256, "{x8} {y8}");
                assert!(w.iter().all(|&v| v <= 256), "{x8} {y8} {w:?}");
                for dx in [-0.5, 0.5] {
                    for dy in [-0.5, 0.5] {
                        let x = ((f64::from(x8) + dx) / 256.0).clamp(0.0, 1.0);
                        let y = ((f64::from(y8) + dy) / 256.0).clamp(0.0, 1.0);
                        let exact = [(1.0 - x) * (1.0 - y), x * (1.0 - y), (1.0 - x) * y, x * y];
                        let (mut up, mut down) = (0.0, 0.0);
                        for (&wi, &e) in w.iter().zip(&exact) {
                            let d = f64::from(wi) / 256.0 - e;
                            if d > 0.0 {
                                up += d;
                            } else {
                                down -= d;
                            }
                        }
                        worst = worst.max(255.0 * up.max(down));
                    }
                }
            }
        }
        assert!(worst <= FAST_LEVEL_MAX_ERROR_LSB, "{worst}");
        if !cfg!(miri) {
            assert!(worst > FAST_LEVEL_MAX_ERROR_LSB - 1e-3, "{worst}");
        }
        const { assert!(FAST_LEVEL_MAX_ERROR_LSB + 0.5 <= FAST_MAX_ERROR_LSB) };
    }

    /// Packed results equal the per-channel formulas, for random texels,
    /// weights and level weights (a second, plain-integer computation).
    #[test]
    fn packed_equals_per_channel() {
        let mut s = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        for _ in 0..if cfg!(miri) { 200 } else { 100_000 } {
            let r = next();
            let t = [r as u32, (r >> 32) as u32, next() as u32, next() as u32];
            let t = if r % 5 == 0 { [u32::MAX; 4] } else { t };
            let (x, y) = ((r >> 8) as u32 & 0xFF, (r >> 16) as u32 & 0xFF);
            let u = (r >> 24) as u32 % 257;
            let w = corner_weights(x, y);
            let t2 = [next() as u32, next() as u32, next() as u32, next() as u32];
            let (x2, y2) = ((r >> 40) as u32 & 0xFF, (r >> 48) as u32 & 0xFF);
            let w2 = corner_weights(x2, y2);
            let a = bilinear(t, x, y);
            let b = bilinear(t2, x2, y2);
            for c in 0..4 {
                let sum = |t: [Texel; 4], w: [u32; 4]| -> u64 {
                    (0..4)
                        .map(|i| u64::from((t[i] >> (8 * c)) & 0xFF) * u64::from(w[i]))
                        .sum()
                };
                let (sa, sb) = (sum(t, w), sum(t2, w2));
                assert_eq!(u64::from((round(a) >> (8 * c)) & 0xFF), (sa + 128) >> 8);
                let y_exact = sa * u64::from(256 - u) + sb * u64::from(u);
                assert_eq!(
                    u64::from((blend(a, b, u) >> (8 * c)) & 0xFF),
                    (y_exact + (1 << 15)) >> 16,
                    "{t:x?} {t2:x?} {u}"
                );
                assert_eq!(u64::from(unpack(a)[c]), sa << 8);
                assert_eq!(
                    u64::from(blend_unpacked(a, b, u)[c]),
                    y_exact,
                    "unpacked blend"
                );
            }
        }
    }

    /// Reference vectors: (texels, x, y, exact red), within the bound.
    #[test]
    fn reference_vectors() {
        let v = |r: u8| u32::from_le_bytes([r, 0, 0, 255]);
        for (t, x, y, exact) in [
            ([0, 255, 0, 255], 128, 0, 127.5),
            ([0, 0, 0, 255], 128, 128, 63.75),
            ([10, 20, 30, 40], 0, 0, 10.0),
            ([10, 20, 30, 40], 64, 192, 10.0 + 2.5 + 15.0),
            ([255, 255, 255, 255], 1, 255, 255.0),
        ] {
            let out = round(bilinear(t.map(v), x, y));
            assert!((ch(out, 0) - exact).abs() <= FAST_MAX_ERROR_LSB, "{t:?}");
            assert_eq!(out >> 24, 255);
        }
    }
}
