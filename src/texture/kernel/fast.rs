//! FAST filter kernel at GPU precision: D3D11's 8 sub-texel bits and 8
//! lod-fraction bits, exact corner weights, two channels per multiply.
//!
//! D3D11 requires 8 fractional sub-texel bits and 8 fractional lod bits
//! (`D3D11_SUBTEXEL_FRACTIONAL_BIT_COUNT`, `D3D11_MIP_LOD_FRACTIONAL_BIT_COUNT`);
//! this kernel uses exactly those. The position weights `x, y ∈ [0, 255]`
//! (units of 1/256 texel, rounded to nearest by the addressing; a
//! position that rounds to 256 moves to the next texel pair with weight
//! 0) give the corner weights as exact products, in units of 2⁻¹⁶:
//!
//! ```text
//! W₁₁ = x·y,  W₁₀ = 256x − x·y,  W₀₁ = 256y − x·y,  W₀₀ = 2¹⁶ − 256x − 256y + x·y
//! ```
//!
//! i.e. `(256 − x)(256 − y)`, `x(256 − y)`, `(256 − x)y`, `xy`: each
//! `≥ 0`, summing to exactly 2¹⁶, with no rounding. They are computed
//! scaled by 2⁸ (`W' = 2⁸W ≤ 2²⁴`), which is
//! [`accurate`]'s corner-weight computation at the
//! 12-bit positions `16x, 16y` (one multiply, shifts and subtractions).
//! One level's value per channel, `V = Σ cᵢ·Wᵢ ≤ 255·2¹⁶`, is then the
//! exact bilinear value at the quantized position in 8.16 (the
//! [`Wide`] of the ACCURATE kernel), and rounding and the level blend
//! are the ACCURATE kernel's functions on it: a bilinear sample is
//! `(V + 2¹⁵) >> 16`, a trilinear one the exact blend
//! `Y = A·(256 − t) + B·t ≤ 255·2²⁴` of two levels rounded once,
//! `(Y + 2²³) >> 24`. The FAST tier is therefore *the exact filter at
//! D3D11's quantized position and lod, rounded once*; it differs from
//! the ACCURATE tier only in the 8-bit (instead of 12-bit) positions.
//!
//! # Two channels per multiply
//!
//! A texel `t = c₀ | c₁<<8 | c₂<<16 | c₃<<24` gives two pair words with
//! one channel in the low byte and one in the high byte:
//! `t & 0xFF0000FF` (`c₀`, `c₃`) and `rotr(t, 16) & 0xFF0000FF`
//! (`c₂`, `c₁`). (Rotating by 8 both ways instead puts the rounded
//! results next to their bytes, but on the Cortex-M4 that costs more
//! instructions in both the bilinear and the trilinear call.) For `p = c_lo + c_hi·2²⁴` and a weight `W' = 2⁸W`, the
//! 64-bit product is
//!
//! ```text
//! p·W' = c_lo·W' + c_hi·W·2³²,   c_lo·W' ≤ 255·2²⁴ < 2³²
//! ```
//!
//! so its low word is `c_lo·W'` and its high word `c_hi·W`, exactly, and
//! the sums over the four texels stay apart too (low word
//! `Σ c_lo·W' ≤ 255·2²⁴` plus a rounding constant `≤ 2²³` never carries
//! into the high word). One 32×32→64-bit multiply-accumulate per word
//! and texel filters two channels: `umlal` on the Cortex-M4 (a 64-bit
//! accumulator); on RISC-V, which has no 64-bit accumulate, the low and
//! high words are summed apart (`mul` and `mulhu`, no carry to
//! propagate). Both forms compute the same integers (tested against each
//! other, against the per-channel sums and against the ACCURATE kernel on
//! the host), so results are bit-identical on every target.
//!
//! # Error bound (proof)
//!
//! Per channel, in 8-bit LSB, against the exact real-valued filter at the
//! exact sample position and lod (what the f64 references compute):
//!
//! * one level: the kernel's value is *exactly* the bilinear
//!   interpolant `f` of the texels at the quantized position `q`
//!   (above), so the error is `f(p) − f(q)` for the exact position `p`
//!   with `|pₓ − qₓ|, |p_y − q_y| ≤ 1/512` texel (rounding to nearest
//!   1/256). The interpolant of texel values in `[0, 255]` is
//!   continuous and piecewise bilinear, and along either axis piecewise
//!   linear with slopes that are convex combinations of neighbour
//!   differences, so at most 255 per texel: `|f(p) − f(q)| ≤
//!   255·(1/512 + 1/512) = 255/256 =` [`FAST_LEVEL_MAX_ERROR_LSB`]
//!   `≈ 0.9961`. It is nearly reached: inside a cell, for fixed texels
//!   the error is bilinear in `p` and, for fixed `p`, linear in the
//!   texels, so its maximum lies at a corner of the rounding box (clipped
//!   to the cell; a box reaching into the neighbour cell is the mirror
//!   image of one that does not) and at texel values in `{0, 255}`; the
//!   enumeration of all `256²` positions, corners and `2⁴` texel vertices
//!   (a test) finds `255·(1 − (511/512)²) ≈ 0.9951` (texels `0, 255, 255,
//!   255`, `q` on the texel centre, `p` 1/512 off on both axes).
//! * final rounding: `≤ ½` (one rounding of an exact value, bilinear and
//!   trilinear alike: the level blend with the exact 8-bit lod fraction
//!   is exact, and a convex combination of two levels' errors is within
//!   the larger).
//!
//! Total `≤ ½ + 255/256 = 1.49609375 ≤` [`FAST_MAX_ERROR_LSB`] `= 1.5`,
//! bilinear and trilinear (an anisotropic mean of probes adds two 8.16
//! roundings, `≤ 2⁻¹⁶` LSB, still below 1.5 before the lod term of
//! [`crate::texture::sampler::aniso`]). No kernel with D3D11's 8-bit
//! positions can do better than `255·(1 − (511/512)²) + ½ ≈ 1.4951` on
//! every input, since the quantized position alone loses that much.
//! The corner weights stay exact 16-bit products: rounding them to 8 bits
//! would cost up to `255/256` more (any kernel with 8-bit corner weights is
//! `≥ 1.496` off even at exact positions).

use crate::texture::kernel::accurate::{self, Wide};
use crate::texture::storage::mip::Texel;

/// Fractional bits of the FAST position weights (D3D11's sub-texel bits).
pub const FAST_WEIGHT_BITS: u32 = 8;

/// The proven bound of one level before the final rounding, in 8-bit
/// LSB: `255/256` (the position quantized to 1/256 texel; module docs).
/// The enumeration test finds the exact maximum `255·(1 − (511/512)²)`
/// just below it.
pub const FAST_LEVEL_MAX_ERROR_LSB: f64 = 255.0 / 256.0;

/// Documented error bound of the FAST kernel against the exact f64
/// filter, in 8-bit LSB per channel, bilinear and trilinear: 1.5
/// (`½ + 255/256 = 1.4961`; proof in the [module docs](self)).
pub const FAST_MAX_ERROR_LSB: f64 = 1.5;

/// The mask of a pair word: channel `lo` in bits 0..8, `hi` in bits
/// 24..32 (the two bytes a pair sum keeps apart).
pub const PAIR: u32 = 0xFF00_00FF;

/// Rounding constants of a pair sum for a rounded bilinear texel: `2²³`
/// in the low word (`c_lo` in 8.24), `2¹⁵` in the high word (`c_hi` in
/// 8.16).
pub const ROUND_PAIR: u64 = (1 << 23) | (1 << (32 + 15));

/// Bit 7 of channels 1 and 3 of a texel: flipped in the texels before the
/// signed pair sums of [`bilinear_texel`] on the Cortex-M4 (so that the
/// high byte of each pair word, read as a signed byte, is `c_hi − 128`)
/// and in the result after them (which gives back `c_hi`).
pub const FLIP: u32 = 0x8000_8000;

/// The scaled corner weights `2⁸·[W₀₀, W₁₀, W₀₁, W₁₁]` of the 8-bit
/// position weights `x, y ≤ 255` (module docs: exact products, sum 2²⁴,
/// each `≤ 2²⁴`): the ACCURATE weights at `16x, 16y`.
#[inline(always)]
#[must_use]
pub fn corner_weights(x: u32, y: u32) -> [u32; 4] {
    accurate::corner_weights(x << 4, y << 4)
}

/// Which pair-sum form the kernel uses: the 64-bit accumulator on Arm
/// (`umlal`), low and high words apart elsewhere (`mul`, `mulhu`).
const WIDE: bool = cfg!(target_arch = "arm");

/// Whether a bilinear call alone (not in a batch loop) takes the signed
/// pair sums ([`pair_sum_signed`]): on Arm, where they keep the `smlal`
/// chain whole (a shorter Cortex-M4 bilinear call). A batch loop keeps
/// the unsigned chain: with the flips its loop values no longer fit the
/// registers, and the loop costs more per hit.
const SIGNED: bool = cfg!(target_arch = "arm");

/// The pair words of a texel: `[c₀ | c₃<<24, c₂ | c₁<<24]`, with the
/// mask `m =` [`PAIR`].
#[inline(always)]
fn pairs(t: Texel, m: u32) -> [u32; 2] {
    [t & m, t.rotate_right(16) & m]
}

/// `r + Σᵢ pᵢ·wᵢ` for pair words `pᵢ` and scaled weights `wᵢ` (sum
/// `2²⁴`): the low word is `r_lo + Σ c_lo·w` and the high word
/// `r_hi + Σ c_hi·w/2⁸`, with no carry between them for `r_lo ≤ 2²³`
/// (module docs). `WIDE`: one 64-bit accumulator (`umlal` chain); else
/// the low and high words of each product summed apart (`mul`,
/// `mulhu`), the same integers since the low words' sum never carries.
#[inline(always)]
fn pair_sum<const WIDE: bool>(p: [u32; 4], w: [u32; 4], r: u64) -> u64 {
    if WIDE {
        let mut acc = r;
        for (&pi, &wi) in p.iter().zip(&w) {
            acc = acc.wrapping_add(u64::from(pi).wrapping_mul(u64::from(wi)));
        }
        acc
    } else {
        let mut lo = r as u32;
        let mut hi = (r >> 32) as u32;
        for (&pi, &wi) in p.iter().zip(&w) {
            let prod = u64::from(pi).wrapping_mul(u64::from(wi));
            lo = lo.wrapping_add(prod as u32);
            hi = hi.wrapping_add((prod >> 32) as u32);
        }
        u64::from(lo) | (u64::from(hi) << 32)
    }
}

/// [`pair_sum`] in signed 64-bit arithmetic (an `smlal` chain on the
/// Cortex-M4) for pair words of texels with [`FLIP`] applied. As an
/// `i32`, such a word is `c_lo + (c_hi − 128)·2²⁴`, and each weight
/// `wᵢ = 2⁸Wᵢ ≤ 2²⁴` is positive, so each product is
/// `c_lo·wᵢ + (c_hi − 128)·Wᵢ·2³²`. Summed from `r =` [`ROUND_PAIR`]: the
/// low word is `2²³ + Σ c_lo·wᵢ < 2³²` (no carry into the high word), the
/// same as [`pair_sum`]'s, and the high word (two's complement) is
/// `2¹⁵ + Σ c_hi·Wᵢ − 128·2¹⁶`; since `128·2¹⁶` is a multiple of 2¹⁶,
/// its bits 16..24 are `pair_sum`'s with bit 23 flipped, i.e. the rounded
/// `c_hi` with bit 7 flipped. Why signed: LLVM's Arm back end keeps an
/// `smlal` chain whole but splits every second `umlal` of an unsigned one
/// into `umull`, `adds` and `adc` (where the accumulator comes from a
/// `umlal`, its search for a `umaal` gives up on the `umlal` as well):
/// four extra instructions per sum, against one `eor` per texel and one
/// for the result.
#[inline(always)]
fn pair_sum_signed(p: [u32; 4], w: [u32; 4], r: u64) -> u64 {
    let mut acc = r as i64;
    for (&pi, &wi) in p.iter().zip(&w) {
        acc = acc.wrapping_add(i64::from(pi as i32).wrapping_mul(i64::from(wi as i32)));
    }
    acc as u64
}

/// The two pair sums `[c₀ | c₃, c₂ | c₁]` of the footprint `t` (`t00,
/// t10, t01, t11`) with scaled weights `w`, started from `r`.
#[inline(always)]
fn pair_sums<const WIDE: bool>(t: [Texel; 4], w: [u32; 4], r: u64, m: u32) -> [u64; 2] {
    let p = t.map(|t| pairs(t, m));
    [
        pair_sum::<WIDE>(p.map(|x| x[0]), w, r),
        pair_sum::<WIDE>(p.map(|x| x[1]), w, r),
    ]
}

/// [`bilinear`] in a sum form (both give the same integers; tested).
#[inline(always)]
fn bilinear_with<const WIDE: bool>(t: [Texel; 4], x: u32, y: u32, m: u32) -> Wide {
    let [a, b] = pair_sums::<WIDE>(t, corner_weights(x, y), 0, m);
    // Low words 8.24 (`c₀`, `c₂`), high words 8.16 (`c₃`, `c₁`).
    [
        (a as u32) >> 8,
        (b >> 32) as u32,
        (b as u32) >> 8,
        (a >> 32) as u32,
    ]
}

/// [`bilinear_texel`] in a sum form (all give the same texel; tested):
/// `SIGNED`, the signed sums of the flipped texels ([`pair_sum_signed`],
/// an `smlal` chain on Arm); else [`pair_sum`]`::<WIDE>`.
#[inline(always)]
fn bilinear_texel_with<const WIDE: bool, const SIGNED: bool>(
    t: [Texel; 4],
    x: u32,
    y: u32,
    r: u64,
    m: u32,
) -> Texel {
    debug_assert_eq!(r, ROUND_PAIR);
    let w = corner_weights(x, y);
    let (flip, [a, b]) = if SIGNED {
        let p = t.map(|t| pairs(t ^ FLIP, m));
        // `b` first: on the Cortex-M4 the mirror/border bilinear call
        // is shorter than with `a` first (register allocation).
        let b = pair_sum_signed(p.map(|x| x[1]), w, r);
        (FLIP, [pair_sum_signed(p.map(|x| x[0]), w, r), b])
    } else {
        (0, pair_sums::<WIDE>(t, w, r, m))
    };
    // Rounded results: the low lane in bits 24..32 of the low word, the
    // high lane in bits 16..24 of the high word (unsigned, below 2²⁴;
    // signed, with bit 7 flipped, flipped back by `flip`, and the high
    // word of `b` negative for `c₁ < 128`, so its lane is masked).
    let (a_lo, a_hi) = (a as u32, (a >> 32) as u32);
    let (b_lo, b_hi) = (b as u32, (b >> 32) as u32);
    let b_hi = if SIGNED { b_hi & 0x00FF_FFFF } else { b_hi };
    ((a_lo >> 24) | ((b_hi >> 16) << 8) | ((b_lo >> 24) << 16) | ((a_hi >> 16) << 24)) ^ flip
}

/// One level of the footprint `t` (`t00, t10, t01, t11`) at the 8-bit
/// position weights `x, y ≤ 255`: the exact bilinear value at the
/// quantized position, 8.16 per channel (`≤ 255·2¹⁶`).
#[inline(always)]
#[must_use]
pub fn bilinear(t: [Texel; 4], x: u32, y: u32) -> Wide {
    bilinear_with::<WIDE>(t, x, y, PAIR)
}

/// [`bilinear`] with the pair mask `m =` [`PAIR`] given (the sampler's
/// [`Rounding`](super::Rounding): a register or one load, where a constant
/// the compiler sees is rematerialised by two instructions on the M4 in a
/// loop short of registers).
#[inline(always)]
pub(crate) fn bilinear_masked(t: [Texel; 4], x: u32, y: u32, m: u32) -> Wide {
    bilinear_with::<WIDE>(t, x, y, m)
}

/// [`bilinear`] rounded to a texel, bit-identical to
/// `accurate::round_wide_in_range(bilinear(t, x, y))`: the rounding
/// constants start the sums (`(c_lo·2²⁴ + 2²³) >> 24` and
/// `(c_hi·2¹⁶ + 2¹⁵) >> 16`, each `≤ 255`).
#[inline(always)]
#[must_use]
pub fn bilinear_texel(t: [Texel; 4], x: u32, y: u32) -> Texel {
    bilinear_texel_with::<WIDE, SIGNED>(t, x, y, ROUND_PAIR, PAIR)
}

/// [`bilinear_texel`] with the rounding constants `r =` [`ROUND_PAIR`]
/// given (the sampler's [`Rounding`](super::Rounding): the sums then start
/// from registers); `ALONE`, for a call alone (the signed sums where
/// [`SIGNED`]), else for a batch loop (the unsigned ones). The same texel
/// either way.
#[inline(always)]
pub(crate) fn bilinear_texel_rounded<const ALONE: bool>(
    t: [Texel; 4],
    x: u32,
    y: u32,
    r: u64,
) -> Texel {
    if ALONE {
        bilinear_texel_with::<WIDE, SIGNED>(t, x, y, r, PAIR)
    } else {
        bilinear_texel_with::<WIDE, false>(t, x, y, r, PAIR)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;

    /// The exact-product weights `[W₀₀, W₁₀, W₀₁, W₁₁]` (units 2⁻¹⁶),
    /// computed directly.
    fn exact_weights(x: u64, y: u64) -> [u64; 4] {
        [(256 - x) * (256 - y), x * (256 - y), (256 - x) * y, x * y]
    }

    /// The kernel's weights are 2⁸ × the exact products for every 8-bit
    /// position (so each is `≥ 0` and they sum to 2²⁴).
    #[test]
    fn corner_weights_are_exact_products() {
        for x in 0..256u32 {
            for y in 0..256u32 {
                let w = corner_weights(x, y);
                let e = exact_weights(u64::from(x), u64::from(y));
                for (&wi, &ei) in w.iter().zip(&e) {
                    assert_eq!(u64::from(wi), ei << 8, "{x} {y}");
                }
                assert_eq!(w.iter().map(|&v| u64::from(v)).sum::<u64>(), 1 << 24);
            }
        }
    }

    /// The proof's enumeration: every quantized position, every corner
    /// of its rounding box (clipped to the cell) and every texel vertex
    /// `{0, 255}⁴`: the largest `|f(p) − f(q)|` of the exact bilinear
    /// interpolant, against the proven bound.
    #[test]
    fn level_error_enumerated() {
        let mut worst = 0.0f64;
        let step = if cfg!(miri) { 37 } else { 1 };
        let exact = |x: f64, y: f64| [(1.0 - x) * (1.0 - y), x * (1.0 - y), (1.0 - x) * y, x * y];
        for x8 in (0..256u32).step_by(step) {
            for y8 in (0..256u32).step_by(step) {
                let q = exact(f64::from(x8) / 256.0, f64::from(y8) / 256.0);
                for dx in [-0.5, 0.5] {
                    for dy in [-0.5, 0.5] {
                        let x = ((f64::from(x8) + dx) / 256.0).max(0.0);
                        let y = ((f64::from(y8) + dy) / 256.0).max(0.0);
                        let (mut up, mut down) = (0.0, 0.0);
                        for (&wq, &wp) in q.iter().zip(&exact(x, y)) {
                            let d = wq - wp;
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
        let attained = 255.0 * (1.0 - (511.0f64 / 512.0).powi(2));
        assert!((worst - attained).abs() < 1e-12, "{worst} {attained}");
        const { assert!(FAST_LEVEL_MAX_ERROR_LSB + 0.5 <= FAST_MAX_ERROR_LSB) };
    }

    /// Both pair-sum forms give the same integers, and the level values
    /// equal the per-channel exact sums `Σ cᵢ·Wᵢ` (a plain u64
    /// computation) and the ACCURATE kernel at the 12-bit positions
    /// `16x, 16y`, for random and extreme texels and weights.
    #[test]
    fn pair_sums_equal_per_channel() {
        let mut s = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        for n in 0..if cfg!(miri) { 200 } else { 100_000u32 } {
            let r = next();
            let t = match n % 7 {
                0 => [u32::MAX; 4],
                1 => [0, u32::MAX, u32::MAX, u32::MAX],
                _ => [r as u32, (r >> 32) as u32, next() as u32, next() as u32],
            };
            let (x, y) = match n % 5 {
                0 => (0, 0),
                1 => (255, 255),
                _ => ((r >> 8) as u32 & 0xFF, (r >> 16) as u32 & 0xFF),
            };
            let w = corner_weights(x, y);
            for start in [0, ROUND_PAIR] {
                for k in 0..2 {
                    let words = t.map(|v| pairs(v, PAIR)[k]);
                    assert_eq!(
                        pair_sum::<true>(words, w, start),
                        pair_sum::<false>(words, w, start),
                        "{t:x?} {x} {y}"
                    );
                }
            }
            // Both sum forms: the same values.
            assert_eq!(
                bilinear_with::<true>(t, x, y, PAIR),
                bilinear_with::<false>(t, x, y, PAIR)
            );
            let texel_forms = [
                bilinear_texel_with::<true, false>(t, x, y, ROUND_PAIR, PAIR),
                bilinear_texel_with::<false, true>(t, x, y, ROUND_PAIR, PAIR),
                bilinear_texel_with::<true, true>(t, x, y, ROUND_PAIR, PAIR),
                bilinear_texel_rounded::<true>(t, x, y, ROUND_PAIR),
                bilinear_texel_rounded::<false>(t, x, y, ROUND_PAIR),
            ];
            for form in texel_forms {
                assert_eq!(
                    form,
                    bilinear_texel_with::<false, false>(t, x, y, ROUND_PAIR, PAIR)
                );
            }
            // The signed sums of the flipped words: the unsigned sums'
            // low words, and their high words less 2²³.
            for k in 0..2 {
                let signed = pair_sum_signed(t.map(|v| pairs(v ^ FLIP, PAIR)[k]), w, ROUND_PAIR);
                let unsigned = pair_sum::<true>(t.map(|v| pairs(v, PAIR)[k]), w, ROUND_PAIR);
                assert_eq!(
                    signed,
                    unsigned.wrapping_sub(1 << (32 + 23)),
                    "{t:x?} {x} {y} {k}"
                );
            }
            let e = exact_weights(u64::from(x), u64::from(y));
            let wide = bilinear(t, x, y);
            let texel = bilinear_texel(t, x, y);
            for (c, &wc) in wide.iter().enumerate() {
                let sum: u64 = t
                    .iter()
                    .zip(&e)
                    .map(|(&ti, &ei)| u64::from((ti >> (8 * c)) & 0xFF) * ei)
                    .sum();
                assert_eq!(u64::from(wc), sum, "{t:x?} {x} {y} {c}");
                assert_eq!(
                    u64::from((texel >> (8 * c)) & 0xFF),
                    (sum + (1 << 15)) >> 16,
                    "{t:x?} {x} {y} {c}"
                );
            }
            assert_eq!(
                wide,
                accurate::bilerp_in_range(t, x << 4, y << 4, accurate::ROUND_WIDE)
            );
            assert_eq!(
                texel,
                accurate::bilerp_rounded(t, x << 4, y << 4, accurate::ROUND_TEXEL)
            );
        }
    }

    /// Reference vectors: (texels, x, y, exact red at the 8-bit
    /// position, worked out by hand): exact before the final rounding.
    #[test]
    fn reference_vectors() {
        let v = |r: u8| u32::from_le_bytes([r, 0, 0, 255]);
        for (t, x, y, exact) in [
            ([0, 255, 0, 255], 128, 0, 127.5),
            ([0, 0, 0, 255], 128, 128, 63.75),
            ([10, 20, 30, 40], 0, 0, 10.0),
            ([10, 20, 30, 40], 64, 192, 10.0 + 2.5 + 15.0),
            ([255, 255, 255, 255], 1, 255, 255.0),
            ([0, 255, 255, 0], 1, 1, 255.0 * 2.0 * 255.0 / 65536.0),
        ] {
            let wide = bilinear(t.map(v), x, y);
            assert_eq!(f64::from(wide[0]), exact * 65536.0, "{t:?}");
            assert_eq!(wide[3], 255 << 16);
            let out = bilinear_texel(t.map(v), x, y);
            assert!((f64::from(out & 0xFF) - exact).abs() <= 0.5, "{t:?}");
            assert_eq!(out >> 24, 255);
        }
    }
}
