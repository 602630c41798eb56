//! Anisotropic filtering: from a pixel's texture-space footprint to a row
//! of trilinear probes (up to 16).
//!
//! The caller gives the footprint as two axis vectors in normalized
//! texture coordinates, [`Footprint`] — the change of `(u, v)` per pixel
//! step in x and in y, as ray differentials give them (pbrt's
//! `dudx, dvdx, dudy, dvdy`). It is *not* derived here from a ray cone:
//! this module only consumes two axes. With the axes scaled to level-0
//! texels, `|a| ≥ |b|` (major, minor):
//!
//! ```text
//! minor' = max(|b|, |a| / max_aniso)             (pbrt's clamp of the eccentricity)
//! N      = min(max_aniso, ceil(|a| / minor'))    probes, 1 ..= 16
//! lod    = log2(minor')                           (levels, before the sampler's bias/clamp)
//! t_i    = (2i + 1 − N) / (2N),  i = 0 … N−1     probe i at (u, v) + t_i·a_uv
//! ```
//!
//! Every probe is one trilinear (or the caller's filter mode) sample at
//! `lod`; the result is their mean, weights `1/N` summing to exactly 1.
//! The probes split the major axis's extent `[−½, ½]·a` into `N` equal
//! parts, each sampled at its centre with a filter as wide as the minor
//! axis.
//!
//! Fixed point: axis components in texels are clamped to `|x| < 2¹⁵`
//! (the largest texture side) with 16 fractional bits, squared lengths
//! are U32F32 in `u64`, logarithms come from [`crate::log2`] (error
//! 2⁻¹³) and `N` from a comparison with `log2 k`, `k = 1 … 16`, by a
//! table of the ratio's top bits; the probe step `a_uv / N` is a multiply
//! by a reciprocal. A zero axis reads as the smallest positive length
//! (lod ≈ −16, clamped later).
//!
//! Cost: a footprint below one normalized unit per component on a level
//! 0 below 2¹⁵ texels a side (every real pixel's) is scaled and squared
//! in 32-bit words (one multiply per component, no clamp: `lengths`),
//! any other one by the clamped 64-bit form in a cold function; the same
//! values. A sampler that wraps on both axes of a power-of-two texture
//! steps its probes in 32-bit words (the coordinates' fractions), with
//! no saturation to test per probe.

use super::{Key, Sampler};
use crate::log2::log2_bits;
use crate::texture::Stats;
use crate::texture::address::Axis;
use crate::texture::kernel::Kernel;
use crate::texture::storage::mip::{Texel, TexelSource};
use crate::units::{Footprint, Lod, TexCoord};

/// What [`probes`] computes for one anisotropic sample. Example:
/// [`Footprint`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Probes {
    /// Number of probes, `1 ..= max_aniso`.
    pub count: u8,
    /// Level of detail of every probe (before the sampler's bias and
    /// clamps).
    pub lod: Lod,
    /// Offset of the first probe from the sample point, `t₀·a_uv`.
    pub first: [TexCoord; 2],
    /// Step from one probe to the next, `a_uv / N`.
    pub step: [TexCoord; 2],
}

/// `round(log2(k) · 2¹⁶)` for `k = 1 … 16` (checked against f64 in the
/// tests).
const LOG2_K: [i32; 16] = [
    0, 65536, 103872, 131072, 152170, 169408, 183983, 196608, 207744, 217706, 226717, 234944,
    242512, 249519, 256042, 262144,
];

/// `BELOW[b] = (c, e)` for the ratio bucket `b = ratio >> 12`: `c` the
/// number of [`LOG2_K`] entries below the bucket, `e` the entry inside it
/// (at most one: neighbouring entries are more than 2¹² apart, tested) or
/// `i32::MAX`. The entries below a ratio `r` of bucket `b` are then
/// `c + (r > e)`: [`LOG2_K`]`.partition_point(|&l| l < r)` without a
/// search. Ratios are in `[0, 2¹⁸]` (at most `log2 16`): 65 buckets.
const BELOW: [(u8, i32); 65] = {
    let mut t = [(0u8, i32::MAX); 65];
    let mut b = 0;
    while b < 65 {
        let lo = (b as i32) << 12;
        let mut c = 0;
        let mut k = 0;
        while k < 16 {
            if LOG2_K[k] < lo {
                c += 1;
            } else if LOG2_K[k] < lo + (1 << 12) {
                t[b].1 = LOG2_K[k];
            }
            k += 1;
        }
        t[b].0 = c;
        b += 1;
    }
    t
};

/// `LOG2_K.partition_point(|&l| l < ratio)` for `ratio ∈ [0, 2¹⁸]` by
/// [`BELOW`] (tested equal over the whole range).
#[inline(always)]
fn entries_below(ratio: i32) -> u8 {
    let (c, e) = BELOW
        .get((ratio >> 12) as usize)
        .copied()
        .unwrap_or((16, i32::MAX));
    c + u8::from(ratio > e)
}

/// Largest axis component [`probes`] takes, `2¹⁵` in normalized units
/// (I32F32 bits `2⁴⁷`): larger components are clamped to it (a footprint
/// that long covers every texel of any texture thousands of times).
const AXIS_LIMIT: i64 = 1 << 47;

/// `ceil(2³²/N)` for `N = 2 … 16` (entry `N − 1`; entry 0, `N = 1`, is
/// unused: [`div_small`] returns `c` itself).
const RECIP: [u32; 16] = {
    let mut r = [0u32; 16];
    let mut n = 2u64;
    while n <= 16 {
        r[(n - 1) as usize] = (1u64 << 32).div_ceil(n) as u32;
        n += 1;
    }
    r
};

/// `c / N` for `|c| ≤ 2⁴⁷` and `N = 1 … 16` (`N = 1`: `c`; `N > 16` reads
/// entry `(N − 1) mod 16`) by the reciprocal
/// [`RECIP`]: `floor(c·R / 2³²)` from one 32×32-bit and one small
/// multiply, within `1 + |c|·2⁻⁶⁴` of the exact quotient in I32F32 units
/// (`R` overestimates `2³²/N` by less than 1). No division on the
/// per-sample path.
#[inline(always)]
fn div_small(c: i64, n: u8) -> i64 {
    if n <= 1 {
        return c;
    }
    let r = RECIP[usize::from(n.wrapping_sub(1)) & 15];
    let hi = c >> 32;
    let lo = u64::from(c as u32) * u64::from(r);
    hi * i64::from(r) + (lo >> 32) as i64
}

/// Axis component `c` (normalized, I32F32 bits, clamped to
/// `±2⁴⁷`, i.e. `±2¹⁵` normalized units) times `size` texels (at most
/// `2¹⁵`), in texels with 16 fractional bits, clamped to `|x| < 2¹⁵`.
#[inline(always)]
fn texels(c: i64, size: u32) -> i64 {
    const LIMIT: i64 = (1 << 31) - 1;
    let size = size.min(crate::texture::storage::mip::MAX_SIZE);
    ((c * i64::from(size)) >> 16).clamp(-LIMIT, LIMIT)
}

/// Squared length (U32F32 bits) of a texel-space vector with 16
/// fractional bits per component (`|x|, |y| < 2³¹`: one 32×32-bit
/// multiply each, the sum `< 2⁶³`).
#[inline(always)]
fn len2(x: i64, y: i64) -> u64 {
    let (x, y) = (x.unsigned_abs() as u32, y.unsigned_abs() as u32);
    u64::from(x) * u64::from(x) + u64::from(y) * u64::from(y)
}

/// The footprint's four axis components (normalized, I32F32 bits), `[x₀,
/// x₁, y₀, y₁]`.
#[inline(always)]
fn components(fp: &Footprint) -> [i64; 4] {
    [fp.x[0], fp.x[1], fp.y[0], fp.y[1]].map(TexCoord::to_bits)
}

/// Whether the 32-bit [`lengths`] apply: every axis component `c` inside
/// `[−2³², 2³²)` (below one normalized unit: the footprints of real
/// pixels) and both sides of level 0 below `2¹⁵` texels.
#[inline(always)]
fn small(c: [i64; 4], width: u32, height: u32) -> bool {
    // `(c >> 32) + 1` is 0 or 1 exactly for `c ∈ [−2³², 2³²)`.
    let hi = |c: i64| ((c >> 32) as u32).wrapping_add(1);
    ((hi(c[0]) | hi(c[1]) | hi(c[2]) | hi(c[3])) >> 1) | ((width | height) >> 15) == 0
}

/// The squared lengths `(|a|², |b|²)` of the footprint's axes `c = [a₀,
/// a₁, b₀, b₁]` (normalized, I32F32 bits; [`small`]) in texels of a
/// `width × height` level 0, U32F32 bits: each scaled component is the
/// 32-bit word `(c·size) >> 16` (`|c·size| < 2⁴⁷`, so it fits and no
/// clamp applies) and each square one signed 32×32→64-bit multiply
/// (`smull`/`smlal` on the Cortex-M4). The values of
/// [`lengths_general`] (tested over both sides of each bound).
///
/// With `c = hi·2³² + lo` (`hi ∈ {−1, 0}`, `lo` the low word) and
/// `s = size·2¹⁶ < 2³¹`, `(c·size) >> 16 = hi·s + floor(lo·s / 2³²)`
/// exactly (`hi·size·2³²` is a multiple of `2¹⁶`): the high word of one
/// 32×32-bit product plus one 32-bit multiply-add (`umull`, `mla`).
#[inline(always)]
fn lengths(c: [i64; 4], width: u32, height: u32) -> (u64, u64) {
    let t = |c: i64, size: u32| {
        let s = size << 16;
        let lo = ((u64::from(c as u32) * u64::from(s)) >> 32) as u32;
        i64::from(lo.wrapping_add(((c >> 32) as u32).wrapping_mul(s)) as i32)
    };
    let sq = |x: i64, y: i64| (x * x + y * y) as u64;
    (
        sq(t(c[0], width), t(c[1], height)),
        sq(t(c[2], width), t(c[3], height)),
    )
}

/// [`lengths`] for any components and sides: components clamped to
/// `±2⁴⁷` ([`AXIS_LIMIT`]), scaled by [`texels`], squared by [`len2`].
#[inline(always)]
fn lengths_general(c: [i64; 4], width: u32, height: u32) -> (u64, u64) {
    let c = c.map(|x| x.clamp(-AXIS_LIMIT, AXIS_LIMIT));
    (
        len2(texels(c[0], width), texels(c[1], height)),
        len2(texels(c[2], width), texels(c[3], height)),
    )
}

/// The probe rule's results for one footprint: the probe count `N`, the
/// lod (I8F8 bits, before the sampler's bias and clamps) and the major
/// axis (normalized, I32F32 bits, clamped to `±2⁴⁷`).
#[derive(Clone, Copy)]
struct Rule {
    count: u8,
    lod: i16,
    major: [i64; 2],
}

/// The probe rule (module docs) of the footprint `fp` on a `width ×
/// height` level 0 with at most `max ∈ 1 ..= 16` probes (any other value
/// reads entry `(max − 1) mod 16` of [`LOG2_K`]; no panic): [`lengths`]
/// when they apply ([`small`]), else [`rule_general`]. Inlined: the
/// common path keeps its results in registers (no call frame, no result
/// written to memory and read back); the general path stays one
/// out-of-line copy.
#[inline(always)]
fn rule(fp: &Footprint, width: u32, height: u32, max: u8) -> Rule {
    let c = components(fp);
    if !small(c, width, height) {
        return rule_general(fp, width, height, max);
    }
    let (count, lod, y) = rule_of(lengths(c, width, height), max);
    // The components are within `±2³²` here (`small`): the clamp to
    // `±2⁴⁷` is the identity, and the major axis is read from `fp` again
    // (not kept in registers through the logarithms).
    let major = if y { fp.y } else { fp.x };
    Rule {
        count,
        lod,
        major: major.map(TexCoord::to_bits),
    }
}

/// [`rule`] for any footprint: the components clamped to `±2⁴⁷`, the
/// lengths by [`lengths_general`].
#[cold]
#[inline(never)]
fn rule_general(fp: &Footprint, width: u32, height: u32, max: u8) -> Rule {
    let c = components(fp).map(|x| x.clamp(-AXIS_LIMIT, AXIS_LIMIT));
    let (count, lod, y) = rule_of(lengths_general(c, width, height), max);
    Rule {
        count,
        lod,
        major: if y { [c[2], c[3]] } else { [c[0], c[1]] },
    }
}

/// The probe rule from the axes' squared lengths `(lx, ly)`: their two
/// logarithms, the minor axis's clamp, the count from the ratio's bucket
/// ([`entries_below`]; at most `max`, as the clamped ratio is at most
/// `log2 max`) and the lod, the clamped minor axis's log2 to 8
/// fractional bits (rounded down, as `Lod::saturating_from_num` rounds;
/// no value in `[−16, 16)` saturates). Returns the count, the lod and
/// whether the second axis (`y`) is the major one (`ly > lx`).
#[inline(always)]
fn rule_of((lx, ly): (u64, u64), max: u8) -> (u8, i16, bool) {
    let y = lx < ly;
    let (l_major, l_minor) = if y { (ly, lx) } else { (lx, ly) };
    // log2 of the lengths: half the log2 of the squares (I16F16 bits, in
    // `[−16, 16)`).
    let log_major = log2_bits(l_major, 32).to_bits() >> 1;
    let log_minor = log2_bits(l_minor, 32).to_bits() >> 1;
    let log_max = LOG2_K[usize::from(max.wrapping_sub(1)) & 15];
    let log_minor = log_minor.max(log_major - log_max);
    // `0 ≤ ratio ≤ log2 max`: the first k with ratio ≤ log2 k is one more
    // than the number of table entries below the ratio, at most `max`.
    let ratio = log_major - log_minor;
    (entries_below(ratio) + 1, (log_minor >> 8) as i16, y)
}

/// Probe count, lod and probe positions of the footprint `fp` on a
/// `width × height` level 0 with at most `max_aniso` probes (clamped to
/// `1 ..= 16`). Axis components beyond `±2¹⁵` normalized units are clamped
/// to it.
/// Never panics.
#[inline]
#[must_use]
pub fn probes(fp: &Footprint, width: u32, height: u32, max_aniso: u8) -> Probes {
    let r = rule(fp, width, height, max_aniso.clamp(1, 16));
    let count = r.count;
    let step = r.major.map(|c| TexCoord::from_bits(div_small(c, count)));
    let first =
        step.map(|s| TexCoord::from_bits(s.to_bits().wrapping_mul(1 - i64::from(count)) >> 1));
    Probes {
        count,
        lod: Lod::from_bits(r.lod),
        first,
        step,
    }
}

impl<S: TexelSource, K: Key> Sampler<S, K> {
    /// Anisotropic sample at `(u, v)` over the footprint `fp`: up to the
    /// state's maximum anisotropy trilinear probes (bilinear in the
    /// nearest level without the `trilinear` feature) along the major
    /// axis ([`probes`]), all at the minor axis's lod (through the lod
    /// window), averaged with equal weights and rounded once by the key's
    /// kernel. With `max_anisotropy` 1 it is one probe. The lod, its
    /// window and the level choice are computed once per sample; each
    /// probe costs an addressing and the filter. Never panics.
    pub fn sample_aniso(&mut self, u: TexCoord, v: TexCoord, fp: &Footprint) -> Texel {
        let g = self.source.geometry();
        // The state holds `1 ..= 16` (validated when it was made).
        let r = rule(fp, g.width(), g.height(), self.state.max_anisotropy());
        let bits = self.lod.apply(Lod::from_bits(r.lod));
        #[cfg(feature = "trilinear")]
        let (lower, t) = ((bits >> 8) as usize & 15, bits & 0xFF);
        #[cfg(not(feature = "trilinear"))]
        let (lower, t) = (((bits + 0x80) >> 8) as usize & 15, 0);
        let n = u32::from(r.count);
        let step = r.major.map(|c| div_small(c, r.count));
        let first = step.map(|s| s.wrapping_mul(1 - i64::from(n)) >> 1);
        // From a coordinate within ±2⁶² (the top two bits equal) no
        // offset can saturate: `|first|, |step| ≤ 2⁴⁷` (the clamped axis
        // over the count), at most 15 steps.
        let near = |c: TexCoord| (c.to_bits() >> 62) == (c.to_bits() >> 63);
        let words = self.wraps_in_words();
        let sum = if words && near(u) && near(v) {
            // Only the coordinates' low words (their fractions) address,
            // and no position saturates: positions modulo 1, in 32-bit
            // words.
            let low = |c: TexCoord, d: i64| (c.to_bits() as u32).wrapping_add(d as u32);
            let start = [low(u, first[0]), low(v, first[1])];
            let at = |c: u32| TexCoord::from_bits(i64::from(c));
            self.probe_sum(
                start,
                step.map(|s| s as u32),
                n,
                (lower, t),
                at,
                u32::wrapping_add,
            )
        } else {
            let c = TexCoord::from_bits;
            let start = [u.saturating_add(c(first[0])), v.saturating_add(c(first[1]))];
            let step = step.map(c);
            // Plain adds from a start that is near, the same coordinates
            // (a sampler that steps in words saturates here: it came for
            // a coordinate beyond ±2⁶², and one loop less is code size).
            let same = |c: TexCoord| c;
            if !words && near(start[0]) && near(start[1]) {
                self.probe_sum(start, step, n, (lower, t), same, TexCoord::wrapping_add)
            } else {
                self.probe_sum(start, step, n, (lower, t), same, TexCoord::saturating_add)
            }
        };
        let per_probe = if t == 0 { 4 } else { 8 };
        self.stats.count(
            u64::from(n * per_probe),
            u64::from(n * (8 - per_probe)) * u64::from(cfg!(feature = "trilinear")),
        );
        <K::Kernel as Kernel>::probe_mean(sum, n)
    }

    /// Whether this sampler's footprints depend on a coordinate's low
    /// word alone: a key whose two axes are the [`Wrap`](crate::texture::address::Wrap)
    /// type (decided at compile time, so keys with run-time modes carry
    /// no third probe loop), on a power-of-two level 0 (the taps
    /// of `pow2_wrap_taps`, with or without direct level views), where a
    /// whole number of texture widths added changes no tap.
    #[inline(always)]
    fn wraps_in_words(&self) -> bool {
        K::U::ALWAYS_WRAP && K::V::ALWAYS_WRAP && (self.source.levels().is_some() || self.pow2)
    }

    /// The channel sums of `n` probes from `start` by `step` (positions
    /// advanced by `add`, read as coordinates by `at`) in level `lower`
    /// and, when the blend weight `t ≠ 0`, `lower + 1`.
    #[inline(always)]
    fn probe_sum<P: Copy>(
        &mut self,
        start: [P; 2],
        step: [P; 2],
        n: u32,
        (lower, t): (usize, u32),
        at: impl Fn(P) -> TexCoord,
        add: impl Fn(P, P) -> P,
    ) -> [u32; 4] {
        let mut sum = [0u32; 4];
        let [mut pu, mut pv] = start;
        let k = self.rounding;
        for _ in 0..n {
            let (u, v) = (at(pu), at(pv));
            let (ta, fxa, fya) = self.footprint(u, v, lower);
            let a = <K::Kernel as Kernel>::bilinear(ta, fxa, fya, k);
            let value = if t == 0 {
                <K::Kernel as Kernel>::probe(a)
            } else {
                let (tb, fxb, fyb) = self.footprint(u, v, lower + 1);
                let b = <K::Kernel as Kernel>::bilinear(tb, fxb, fyb, k);
                <K::Kernel as Kernel>::probe_blend(a, b, t, k)
            };
            for (s, x) in sum.iter_mut().zip(value) {
                *s = s.wrapping_add(x);
            }
            pu = add(pu, step[0]);
            pv = add(pv, step[1]);
        }
        sum
    }
}

#[cfg(test)]
mod tests {
    use crate::units::Footprint;
    extern crate std;
    use super::*;
    use proptest::prelude::*;

    /// The bucket table gives the binary search's count for every ratio
    /// the probe rule produces (and the entries are far enough apart for
    /// one per bucket).
    #[test]
    fn entries_below_equals_the_search() {
        for w in LOG2_K.windows(2) {
            assert!(w[1] - w[0] > 1 << 12);
        }
        // Each bucket's entry lies inside it, `[b·2¹², (b + 1)·2¹²)`, or is
        // `i32::MAX`; the count is the number of entries below its start.
        for (b, &(c, e)) in BELOW.iter().enumerate() {
            let lo = (b as i32) << 12;
            let inside = LOG2_K.iter().find(|&&l| l >= lo && l < lo + (1 << 12));
            assert_eq!(e, inside.copied().unwrap_or(i32::MAX), "{b}");
            assert_eq!(
                usize::from(c),
                LOG2_K.iter().filter(|&&l| l < lo).count(),
                "{b}"
            );
        }
        for ratio in 0..=(1 << 18) {
            let want = LOG2_K.partition_point(|&l| l < ratio) as u8;
            assert_eq!(entries_below(ratio), want, "{ratio}");
        }
    }

    /// The 32-bit lengths (components below one normalized unit, sides
    /// below 2¹⁵) equal the general 64-bit ones, on both sides of each
    /// bound: components at and around `±2³²` and far beyond, sides up to
    /// and past `2¹⁵`.
    #[test]
    fn lengths_equal_the_general_form() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let edges = [
            0,
            1,
            -1,
            (1 << 32) - 1,
            1 << 32,
            -(1 << 32),
            -(1 << 32) + 1,
            -(1 << 32) - 1,
            AXIS_LIMIT,
            -AXIS_LIMIT - 1,
            i64::MAX,
            i64::MIN,
        ];
        let sizes = [1, 2, 3, 32, 1000, (1 << 15) - 1, 1 << 15, u32::MAX];
        for n in 0..if cfg!(miri) { 100 } else { 100_000u32 } {
            let mut c = [0i64; 4];
            for (k, c) in c.iter_mut().enumerate() {
                let r = next();
                *c = if r % 4 == 0 {
                    edges[(r >> 8) as usize % edges.len()]
                } else {
                    (r as i64) >> (29 + (n + k as u32) % 34)
                };
            }
            let (w, h) = (sizes[n as usize % 8], sizes[(n as usize / 8) % 8]);
            if small(c, w, h) {
                assert_eq!(lengths(c, w, h), lengths_general(c, w, h), "{c:?} {w} {h}");
            }
        }
    }

    /// The 32-bit path applies exactly when every component lies in
    /// `[−2³², 2³²)` and both sides are below `2¹⁵`: on both sides of
    /// each bound, one component or side at a time.
    #[test]
    fn small_is_the_documented_bound() {
        let comps = [
            0,
            1,
            -1,
            (1 << 32) - 1,
            1 << 32,
            -(1 << 32),
            -(1 << 32) - 1,
            i64::MAX,
            i64::MIN,
        ];
        let sizes = [1, (1 << 15) - 1, 1 << 15, u32::MAX];
        for &x in &comps {
            for k in 0..4 {
                let mut c = [1 << 20, -(1 << 20), 0, 1 << 31];
                c[k] = x;
                for &w in &sizes {
                    for &h in &sizes {
                        let want = (-(1 << 32)..1 << 32).contains(&x) && w < 1 << 15 && h < 1 << 15;
                        assert_eq!(small(c, w, h), want, "{c:?} {w} {h}");
                    }
                }
            }
        }
    }

    /// A scaled component keeps 16 fractional bits and clamps just inside
    /// `±2¹⁵` texels, `±(2³¹ − 1)` (its magnitude fits `len2`'s `u32`):
    /// below the bound it is exact, at `2³¹` and beyond it is the bound,
    /// and a side above `2¹⁵` counts as `2¹⁵`.
    #[test]
    fn texels_clamp_inside_2_15() {
        let lim = (1i64 << 31) - 1;
        assert_eq!(texels(1 << 32, 1 << 14), 1 << 30);
        assert_eq!(texels(lim << 16, 1), lim);
        assert_eq!(texels(-(lim << 16), 1), -lim);
        assert_eq!(texels(1 << 47, 1), lim);
        assert_eq!(texels(-(1 << 47), 1), -lim);
        assert_eq!(texels(AXIS_LIMIT, 1 << 15), lim);
        assert_eq!(texels(-AXIS_LIMIT, u32::MAX), -lim);
        assert_eq!(texels(1 << 16, u32::MAX), 1 << 15);
        assert_eq!(len2(lim, -lim), 2 * (lim * lim) as u64);
    }

    #[test]
    fn log2_table() {
        for (k, &l) in LOG2_K.iter().enumerate() {
            assert_eq!(
                f64::from(l),
                (((k + 1) as f64).log2() * 65536.0).round(),
                "{k}"
            );
        }
    }

    fn fp(ax: f64, ay: f64, bx: f64, by: f64) -> Footprint {
        let c = TexCoord::from_num;
        Footprint {
            x: [c(ax), c(ay)],
            y: [c(bx), c(by)],
        }
    }

    /// Reference vectors on a 256×256 texture.
    #[test]
    fn reference_vectors() {
        // Isotropic 1-texel footprint: one probe, lod 0. The lengths tie,
        // and on a tie the first axis is the major one (`|a| ≥ |b|`): the
        // step is the x axis.
        let p = probes(&fp(1.0 / 256.0, 0.0, 0.0, 1.0 / 256.0), 256, 256, 16);
        assert_eq!((p.count, p.lod), (1, Lod::ZERO));
        assert_eq!(p.step, [TexCoord::from_num(1.0 / 256.0), TexCoord::ZERO]);
        // 8:1 along u, minor 2 texels: 8 probes at lod 1.
        let p = probes(&fp(16.0 / 256.0, 0.0, 0.0, 2.0 / 256.0), 256, 256, 16);
        assert_eq!((p.count, p.lod), (8, Lod::ONE));
        assert_eq!(p.step[0], TexCoord::from_num(2.0 / 256.0));
        assert_eq!(p.first[0], TexCoord::from_num(-7.0 / 256.0));
        // Capped at 4: minor' = 16/4 = 4 texels, lod 2.
        let p = probes(&fp(16.0 / 256.0, 0.0, 0.0, 2.0 / 256.0), 256, 256, 4);
        assert_eq!((p.count, p.lod), (4, Lod::from_num(2)));
        // Major along y (v), 3:1 → 3 probes.
        let p = probes(&fp(1.0 / 256.0, 0.0, 0.0, 3.0 / 256.0), 256, 256, 16);
        assert_eq!(p.count, 3);
        assert_eq!(p.step, [TexCoord::ZERO, TexCoord::from_num(1.0 / 256.0)]);
        // Degenerate: zero footprint → one probe at the lowest lod.
        let p = probes(&Footprint::default(), 256, 256, 16);
        assert_eq!(p.count, 1);
        assert!(p.lod < Lod::from_num(-15));
        // Extreme: saturates, no panic.
        let p = probes(&fp(-2e9, 2e9, 1e-9, 0.0), 32768, 32768, 200);
        assert_eq!(p.count, 16);
    }

    /// The 32-bit probe loop is chosen exactly for a key whose two axes are
    /// the static `Wrap` type on a power-of-two level 0: not for one static
    /// wrap axis, not for the run-time address key in wrap mode, not on a
    /// 48-texel-wide level 0.
    #[test]
    fn wraps_in_words_only_for_static_wrap_on_pow2() {
        use crate::texture::Cfg;
        use crate::texture::address::{AnyAxis, ClampToEdge, Wrap};
        use crate::texture::storage::mip::{Geometry, Pyramid, pyramid_len};
        let pow2 = std::vec![0u32; pyramid_len(64, 32, 7)];
        let npot = std::vec![0u32; pyramid_len(48, 32, 6)];
        let p = Pyramid::new(Geometry::new(64, 32, 7).unwrap(), &pow2).unwrap();
        let q = Pyramid::new(Geometry::new(48, 32, 6).unwrap(), &npot).unwrap();
        assert!(Sampler::<_, Cfg<Wrap>>::new(p).wraps_in_words());
        assert!(!Sampler::<_, Cfg<Wrap>>::new(q).wraps_in_words());
        assert!(!Sampler::<_, Cfg<Wrap, ClampToEdge>>::new(p).wraps_in_words());
        assert!(!Sampler::<_, Cfg<ClampToEdge, Wrap>>::new(p).wraps_in_words());
        assert!(!Sampler::<_, Cfg<AnyAxis>>::new(p).wraps_in_words());
    }

    /// The 64×32 pyramid of 7 levels the sampling tests read: level 0
    /// random from `r`, the others generated from it. Returns the sides and
    /// level count, the geometry and the texels.
    #[cfg(feature = "trilinear")]
    fn random_pyramid(
        r: &mut crate::rng::XorShift64,
    ) -> (
        (u32, u32, u8),
        crate::texture::storage::mip::Geometry,
        std::vec::Vec<u32>,
    ) {
        use crate::texture::storage::mip::{Geometry, generate, pyramid_len};
        let (w, h, levels) = (64u32, 32u32, 7u8);
        let g = Geometry::new(w, h, levels).unwrap();
        let mut buf = std::vec![0u32; pyramid_len(w, h, levels)];
        r.fill_u32(&mut buf[..(w * h) as usize]);
        generate(&g, &mut buf).unwrap();
        ((w, h, levels), g, buf)
    }

    /// `sample_aniso` against the f64 reference's anisotropic filter (the
    /// mean of exact trilinear probes by pbrt's rule, over the same
    /// levels): a random 64×32 texture, every cap `1..=16`, footprints of
    /// every eccentricity. Three keys cover the three probe loops: the
    /// static wrap key (32-bit positions on this power-of-two texture),
    /// the run-time address key in wrap and clamp to edge (coordinate
    /// adds) and, from coordinates near `TexCoord::MAX`, the saturating
    /// adds. A probe-count near-tie (a ratio within 10⁻³ of an integer)
    /// or two axes within 10⁻³ of the same length are left out (counted).
    /// The fetch counters count 4 texels per probe and level: 8 and none
    /// skipped between levels, 4 and 4 skipped at a whole lod.
    #[cfg(feature = "trilinear")]
    #[test]
    fn sample_aniso_matches_the_f64_reference() {
        use crate::rng::XorShift64;
        use crate::texture::address::AnyAxis;
        use crate::texture::storage::mip::Pyramid;
        use crate::texture::{AddressMode, Cfg, FetchStats, Mode, SamplerDesc, SamplerState};
        use raymip_reference::sampler as reference;
        let mut r = XorShift64(0x5A11_A115_0000_0037);
        let ((w, h, levels), g, buf) = random_pyramid(&mut r);
        let tex = reference::Texture::from_rgba8_levels(w, h, levels, &buf);
        let p = Pyramid::new(g, &buf).unwrap();
        let mode = reference::Mode::from_index(Mode::Trilinear as u8).unwrap();
        let unit = |r: &mut XorShift64| (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        let (mut skipped, mut worst, n) = (0, 0.0f64, 1200);
        for i in 0..n {
            let max = (i % 16) as u8 + 1;
            let (a_mode, far) = match i % 4 {
                0 | 1 => (AddressMode::Wrap, false),
                2 => (AddressMode::ClampToEdge, false),
                _ => (AddressMode::ClampToEdge, true),
            };
            let squash = unit(&mut r);
            let scale = 0.25 * unit(&mut r);
            let mut axis =
                |s: f64| [0, 1].map(|_| TexCoord::from_num((unit(&mut r) - 0.5) * scale * s));
            let fp = Footprint {
                x: axis(1.0),
                y: axis(squash),
            };
            // Far: both coordinates within 0.01 of `TexCoord::MAX` (bits
            // that are multiples of 4), where only saturating adds keep
            // the probes on the texture's last column and row.
            let far_coord = |r: &mut XorShift64| {
                let back = (unit(r) * 0.01 * f64::from(1u32 << 31) * 2.0) as i64;
                TexCoord::from_bits((TexCoord::MAX.to_bits() - back) & !3)
            };
            let (u, v) = if far {
                (far_coord(&mut r), far_coord(&mut r))
            } else {
                (
                    TexCoord::from_num(unit(&mut r) * 3.0 - 1.0),
                    TexCoord::from_num(unit(&mut r) * 3.0 - 1.0),
                )
            };
            let axes = [fp.x, fp.y].map(|a| a.map(|c| c.to_num::<f64>()));
            let len = |a: [f64; 2]| (a[0] * f64::from(w)).hypot(a[1] * f64::from(h));
            let (la, lb) = (len(axes[0]), len(axes[1]));
            let ratio = la.max(lb) / la.min(lb).max(1e-300);
            if (ratio - ratio.round()).abs() < 1e-3 || (la - lb).abs() < 1e-3 * la.max(lb) {
                skipped += 1;
                continue;
            }
            let state = SamplerState::new(SamplerDesc {
                address_u: a_mode,
                address_v: a_mode,
                max_anisotropy: max,
                ..SamplerDesc::default()
            })
            .unwrap();
            let got = if i % 4 == 0 {
                let mut s = Sampler::<_, Cfg>::with_state(p, state).unwrap();
                (s.sample_aniso(u, v, &fp), s.stats())
            } else {
                let mut s = Sampler::<_, Cfg<AnyAxis>>::with_state(p, state).unwrap();
                (s.sample_aniso(u, v, &fp), s.stats())
            };
            let exact = reference::Sampler {
                tex: &tex,
                state: reference::State {
                    address: [reference::Address::from_index(a_mode as u8).unwrap(); 2],
                    max_aniso: u32::from(max),
                    ..reference::State::default()
                },
            };
            let (uf, vf) = (u.to_num::<f64>(), v.to_num::<f64>());
            let want = exact.sample_aniso(uf, vf, axes, mode);
            for (c, &wc) in want.iter().enumerate() {
                let e = (f64::from((got.0 >> (8 * c)) & 0xFF) - wc).abs();
                worst = worst.max(e);
                assert!(
                    e <= 1.0,
                    "{i}: max {max} {a_mode:?} ({uf}, {vf}) {axes:?} ch{c}: {:08x} vs {want:?}",
                    got.0
                );
            }
            let pr = probes(&fp, w, h, max);
            let lod = pr.lod.to_bits().clamp(0, i16::from(levels - 1) << 8);
            let per_probe = if lod & 0xFF == 0 { 4 } else { 8 };
            let count = u64::from(pr.count);
            let want_stats = FetchStats {
                fetched: count * per_probe,
                skipped: count * (8 - per_probe),
            };
            assert_eq!(got.1, want_stats, "{i}: {pr:?}");
        }
        assert!(skipped * 20 < n, "{skipped} of {n} left out");
        std::println!("worst {worst}");
    }

    /// In clamp to edge every probe right of the texture reads its last
    /// column, however far: two probes from a start 2⁻¹² below
    /// `TexCoord::MAX` whose second step passes it (only a saturating add
    /// keeps it there; a wrapping one lands at the far left) give the same
    /// texel as two probes around `u = 40`, and not the first column's.
    #[cfg(feature = "trilinear")]
    #[test]
    fn probes_past_the_largest_coordinate_stay_on_the_last_column() {
        use crate::rng::XorShift64;
        use crate::texture::address::AnyAxis;
        use crate::texture::storage::mip::Pyramid;
        use crate::texture::{AddressMode, Cfg, SamplerDesc, SamplerState};
        let ((w, h, _), g, buf) = random_pyramid(&mut XorShift64(0xC1A3_7ED6_E000_0037));
        let p = Pyramid::new(g, &buf).unwrap();
        let state = SamplerState::new(SamplerDesc {
            address_u: AddressMode::ClampToEdge,
            address_v: AddressMode::ClampToEdge,
            max_anisotropy: 16,
            ..SamplerDesc::default()
        })
        .unwrap();
        // Major axis 16 texels along u, minor 9.6 along v: 2 probes,
        // 2²⁹ (0.125) apart, the first 2²⁸ left of the centre.
        let fp = Footprint {
            x: [TexCoord::from_num(0.25), TexCoord::ZERO],
            y: [TexCoord::ZERO, TexCoord::from_num(0.3)],
        };
        assert_eq!(probes(&fp, w, h, 16).count, 2);
        let v = TexCoord::from_num(0.5);
        let sample = |u: TexCoord| {
            let mut s = Sampler::<_, Cfg<AnyAxis>>::with_state(p, state).unwrap();
            s.sample_aniso(u, v, &fp)
        };
        let far = TexCoord::from_bits((TexCoord::MAX.to_bits() - (1 << 20)) & !3);
        let right = sample(TexCoord::from_num(40));
        assert_eq!(sample(far), right);
        assert_ne!(sample(TexCoord::from_num(-40)), right);
    }

    proptest! {
        /// f64 reference (pbrt-style clamp, ceil of the ratio, log2 of the
        /// clamped minor axis); near-ties of the probe count (within 2⁻¹²
        /// in log2) may go either way.
        #[test]
        fn matches_f64(ax in -0.5f64..0.5, ay in -0.5f64..0.5, bx in -0.5f64..0.5, by in -0.5f64..0.5,
                       size in 1u32..=4096, max in 1u8..=16) {
            let f = fp(ax, ay, bx, by);
            let p = probes(&f, size, size, max);
            let s = f64::from(size);
            let la = (ax * s).hypot(ay * s);
            let lb = (bx * s).hypot(by * s);
            let (maj, min) = (la.max(lb), la.min(lb));
            prop_assume!(min > 1e-3);
            let min_c = min.max(maj / f64::from(max));
            let ratio = maj / min_c;
            let near_tie = (1..=16).any(|k| (ratio.log2() - f64::from(k).log2()).abs() < 1.0 / 4096.0);
            if !near_tie {
                let n = (ratio.ceil() as u8).clamp(1, max);
                prop_assert_eq!(p.count, n);
            }
            prop_assert!((p.lod.to_num::<f64>() - min_c.log2()).abs() <= 1.0 / 256.0 + 1.0 / 8192.0,
                "lod {} vs {}", p.lod, min_c.log2());
            // Probes centred and spanning the major axis.
            let major = if la >= lb { [ax, ay] } else { [bx, by] };
            let n = f64::from(p.count);
            // Which axis is major is a tie when the lengths nearly agree.
            for c in (0..2).filter(|_| (la - lb).abs() > 1e-6 * maj) {
                prop_assert!((p.step[c].to_num::<f64>() - major[c] / n).abs() < 1e-8);
                prop_assert!((p.first[c].to_num::<f64>() - major[c] * (1.0 - n) / (2.0 * n)).abs() < 1e-8);
            }
        }
    }
}
