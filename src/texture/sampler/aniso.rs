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
//! 2⁻¹³) and `N` from a comparison with `log2 k`, `k = 1 … 16`; the probe
//! step `a_uv / N` is one 64-bit division at set-up of the sample. A zero
//! axis reads as the smallest positive length (lod ≈ −16, clamped later).

use fixed::types::I16F16;

use super::{Key, Sampler};
use crate::log2::log2_bits;
use crate::texture::Stats;
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

/// `c / N` for `|c| ≤ 2⁴⁷` and `N = 1 … 16` (`N = 1`: `c`) by the reciprocal
/// [`RECIP`]: `floor(c·R / 2³²)` from one 32×32-bit and one small
/// multiply, within `1 + |c|·2⁻⁶⁴` of the exact quotient in I32F32 units
/// (`R` overestimates `2³²/N` by less than 1). No division on the
/// per-sample path.
#[inline(always)]
fn div_small(c: i64, n: u8) -> i64 {
    if n <= 1 {
        return c;
    }
    let r = RECIP
        .get(usize::from(n).wrapping_sub(1))
        .copied()
        .unwrap_or(0);
    let hi = c >> 32;
    let lo = u64::from(c as u32) * u64::from(r);
    hi * i64::from(r) + (lo >> 32) as i64
}

/// Axis component `c` (normalized, I32F32 bits, clamped to
/// `±2⁴⁷`, i.e. `±2¹⁵` normalized units) times `size ≤ 2¹⁵` texels, in texels with 16 fractional
/// bits, clamped to `|x| < 2¹⁵`.
#[inline(always)]
fn texels(c: i64, size: u32) -> i64 {
    const LIMIT: i64 = (1 << 31) - 1;
    let size = size.min(crate::texture::storage::mip::MAX_SIZE);
    // A component below one normalized unit (`|c| < 2³¹` bits, every
    // footprint of a texel or a few): one 32×32→64-bit multiply, and the
    // result (`|c·size| < 2⁴⁶`, shifted: `< 2³⁰`) needs no clamp. The
    // same value as the general form below.
    if let Ok(c) = i32::try_from(c) {
        return (i64::from(c) * i64::from(size)) >> 16;
    }
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

/// Probe count, lod and probe positions of the footprint `fp` on a
/// `width × height` level 0 with at most `max_aniso` probes (clamped to
/// `1 ..= 16`). Axis components beyond `±2¹⁵` normalized units are clamped
/// to it.
/// Never panics.
#[inline]
#[must_use]
pub fn probes(fp: &Footprint, width: u32, height: u32, max_aniso: u8) -> Probes {
    let max = max_aniso.clamp(1, 16);
    let c = |x: TexCoord| x.to_bits().clamp(-AXIS_LIMIT, AXIS_LIMIT);
    let (ax, ay) = ([c(fp.x[0]), c(fp.x[1])], [c(fp.y[0]), c(fp.y[1])]);
    let lx = len2(texels(ax[0], width), texels(ax[1], height));
    let ly = len2(texels(ay[0], width), texels(ay[1], height));
    let (major, l_major, l_minor) = if lx >= ly { (ax, lx, ly) } else { (ay, ly, lx) };
    // log2 of the lengths: half the log2 of the squares (I16F16 bits).
    let log_major = log2_bits(l_major, 32).to_bits() >> 1;
    let log_minor = log2_bits(l_minor, 32).to_bits() >> 1;
    let log_max = LOG2_K.get(usize::from(max) - 1).copied().unwrap_or(0);
    let log_minor = log_minor.max(log_major - log_max);
    let ratio = log_major - log_minor;
    // The first k with ratio ≤ log2 k: one more than the number of table
    // entries below the ratio (a binary search), at most `max`.
    let below = entries_below(ratio);
    let count = below.saturating_add(1).min(max);
    // I16F16 → I8F8, rounded, saturating.
    let lod = Lod::saturating_from_num(I16F16::from_bits(log_minor));
    let step = major.map(|c| TexCoord::from_bits(div_small(c, count)));
    let first =
        step.map(|s| TexCoord::from_bits(s.to_bits().wrapping_mul(1 - i64::from(count)) >> 1));
    Probes {
        count,
        lod,
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
        let p = probes(
            fp,
            self.source.geometry().width(),
            self.source.geometry().height(),
            self.state.max_anisotropy(),
        );
        let bits = self.lod.apply(p.lod);
        #[cfg(feature = "trilinear")]
        let (lower, t) = ((bits >> 8) as usize & 15, bits & 0xFF);
        #[cfg(not(feature = "trilinear"))]
        let (lower, t) = (((bits + 0x80) >> 8) as usize & 15, 0);
        let n = u32::from(p.count.max(1));
        let start = [u.saturating_add(p.first[0]), v.saturating_add(p.first[1])];
        // From a start within ±2⁶² (the top two bits equal) no step can
        // saturate: `|step| ≤ 2⁴⁷` (the clamped axis over the count), at
        // most 15 steps. Plain adds then, the same coordinates.
        let near = |c: TexCoord| (c.to_bits() >> 62) == (c.to_bits() >> 63);
        let sum = if near(start[0]) && near(start[1]) {
            self.probe_sum::<false>(start, p.step, n, lower, t)
        } else {
            self.probe_sum::<true>(start, p.step, n, lower, t)
        };
        let per_probe = if t == 0 { 4 } else { 8 };
        self.stats.count(
            u64::from(n * per_probe),
            u64::from(n * (8 - per_probe)) * u64::from(cfg!(feature = "trilinear")),
        );
        <K::Kernel as Kernel>::probe_mean(sum, n)
    }

    /// The channel sums of `n` probes from `start` by `step` (saturating
    /// adds when `SAT`, else wrapping ones, which give the same
    /// coordinates when nothing saturates) in level `lower` and, when
    /// the blend weight `t ≠ 0`, `lower + 1`.
    #[inline(always)]
    fn probe_sum<const SAT: bool>(
        &mut self,
        start: [TexCoord; 2],
        step: [TexCoord; 2],
        n: u32,
        lower: usize,
        t: u32,
    ) -> [u32; 4] {
        let add = |a: TexCoord, b: TexCoord| {
            if SAT {
                a.saturating_add(b)
            } else {
                a.wrapping_add(b)
            }
        };
        let mut sum = [0u32; 4];
        let [mut pu, mut pv] = start;
        let k = self.rounding;
        for _ in 0..n {
            let (ta, fxa, fya) = self.footprint(pu, pv, lower);
            let a = <K::Kernel as Kernel>::bilinear(ta, fxa, fya, k);
            let value = if t == 0 {
                <K::Kernel as Kernel>::probe(a)
            } else {
                let (tb, fxb, fyb) = self.footprint(pu, pv, lower + 1);
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
        for ratio in 0..=(1 << 18) {
            let want = LOG2_K.partition_point(|&l| l < ratio) as u8;
            assert_eq!(entries_below(ratio), want, "{ratio}");
        }
    }

    /// The 32-bit form of `texels` equals the 64-bit one for components
    /// around and beyond one normalized unit.
    #[test]
    fn texels_fast_path_equals_general() {
        let general = |c: i64, size: u32| {
            ((c * i64::from(size.min(1 << 15))) >> 16).clamp(-((1 << 31) - 1), (1 << 31) - 1)
        };
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        for n in 0..if cfg!(miri) { 100 } else { 200_000u32 } {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let c = ((x as i64) >> (n % 40)).clamp(-AXIS_LIMIT, AXIS_LIMIT);
            for size in [1, 2, 3, 32, 1000, 1 << 15, u32::MAX] {
                assert_eq!(texels(c, size), general(c, size), "{c} {size}");
            }
        }
        for c in [
            i64::from(i32::MIN),
            i64::from(i32::MAX),
            -1,
            0,
            1 << 31,
            -(1 << 31) - 1,
        ] {
            assert_eq!(texels(c, 1 << 15), general(c, 1 << 15));
        }
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
        // Isotropic 1-texel footprint: one probe, lod 0.
        let p = probes(&fp(1.0 / 256.0, 0.0, 0.0, 1.0 / 256.0), 256, 256, 16);
        assert_eq!((p.count, p.lod), (1, Lod::ZERO));
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
