//! Filter kernels: one arithmetic definition per precision tier, chosen by
//! type.
//!
//! | kernel ([`Kernel`] for `(C, P)`) | lanes | position weights | module | bound vs exact f64 |
//! |---|---|---|---|---|
//! | `(Linear, Accurate)` | RGBA8, one channel per multiply | 12 bits | [`accurate`] | 0.5625 LSB |
//! | `(Linear, Fast)` | RGBA8, two channels per multiply | 8 bits (exact corner weights) | [`fast`] | 1.5 LSB |
//! | `(Srgb, _)`, `(SrgbToLinear, _)` | 16-bit linear, one channel per multiply | 16 bits | [`accurate`] + [`srgb`] | 0.6875 sRGB LSB / 0.5101 LSB |
//!
//! The sRGB kernels are the same for both tiers: with 8-bit weights the
//! position error alone, times the sRGB curve's slope near black
//! (12.92), would exceed 20 LSB, so a FAST sRGB sampler filters as the
//! ACCURATE one does (documented, not silent: [`Kernel::TIER`]).
//!
//! A [`Kernel`] works on a texel footprint the sampler has read and
//! addressed; it never reads memory.

use core::fmt::Debug;

use crate::texture::storage::mip::Texel;
// The tiers are the crate's one pair of tier types; the kernels below name
// them as `super::Accurate`, `super::Fast`.
pub(crate) use crate::units::{Accurate, Fast, Precision};

pub mod accurate;
pub mod fast;
pub mod srgb;

/// Colour space `Linear`: UNORM data, filtered as stored.
///
/// Example: [`Kernel`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Linear;

/// Colour space `Srgb`: RGB decoded to linear before filtering, results
/// re-encoded to sRGB (what a GPU writes to an sRGB target).
///
/// Example: [`Kernel`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Srgb;

/// Colour space `SrgbToLinear`: RGB decoded to linear before filtering,
/// results returned linear (what a shader reads from an sRGB view).
///
/// Example: [`Kernel`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SrgbToLinear;

mod sealed {
    pub trait Sealed {}
    impl<C, P> Sealed for (C, P) {}
}

/// The rounding terms of the filter arithmetic, made once per sampler
/// ([`Rounding::new`]) and handed to every kernel call: each
/// multiply-accumulate chain then starts from a register holding its
/// rounding term, instead of a separate add after the chain (which is what
/// a compiler emits for a constant it can see). On Arm it also holds the
/// FAST pair mask [`fast::PAIR`], which the anisotropic probe loop reads
/// from here rather than rebuilding it (two instructions on the M4) per
/// probe; elsewhere the mask stays a constant (RV32 builds it in one
/// instruction, and the larger record cost cycles there). The values are
/// fixed ([`accurate::ROUND_WIDE`], [`accurate::ROUND_TEXEL`],
/// [`accurate::ROUND_BLEND`], [`fast::ROUND_PAIR`], [`fast::PAIR`]); only
/// where they come from differs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rounding {
    wide: u32,
    texel: u32,
    blend: u32,
    pair: u64,
    #[cfg(target_arch = "arm")]
    pair_mask: u32,
}

impl Rounding {
    /// The rounding terms.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            wide: accurate::ROUND_WIDE,
            texel: accurate::ROUND_TEXEL,
            blend: accurate::ROUND_BLEND,
            pair: fast::ROUND_PAIR,
            #[cfg(target_arch = "arm")]
            pair_mask: fast::PAIR,
        }
    }

    /// The FAST pair mask [`fast::PAIR`]: read from the record on Arm, the
    /// constant elsewhere.
    #[inline(always)]
    fn pair_mask(self) -> u32 {
        #[cfg(target_arch = "arm")]
        let m = self.pair_mask;
        #[cfg(not(target_arch = "arm"))]
        let m = fast::PAIR;
        m
    }
}

impl Default for Rounding {
    fn default() -> Self {
        Self::new()
    }
}

/// A filter kernel: the arithmetic of one colour space and precision
/// tier on texel footprints (implemented for the pairs `(C, P)` of the
/// table above; sealed).
///
/// # Example
/// ```
/// use raymip::texture::address::ClampToEdge;
/// use raymip::texture::kernel::{Kernel, Linear, Srgb, SrgbToLinear};
/// use raymip::units::{Accurate, Fast, Precision};
/// use raymip::{Cfg, Geometry, Lod, Mode, Pyramid, Sampler, TexCoord};
/// // A 2×1 texture, opaque black then white; u = ½ lies midway between
/// // the texel centres ¼ and ¾: bilinear weight ½ each.
/// let texels = [0xFF00_0000u32, 0xFFFF_FFFF];
/// let pyramid = Pyramid::new(Geometry::new(2, 1, 1)?, &texels)?;
/// let (u, v) = (TexCoord::from_num(0.5), TexCoord::from_num(0.5));
/// let (lod, mode) = (Lod::ZERO, Mode::BilinearNearestLevel);
/// let red = |texel: u32| f64::from(texel & 0xFF);
/// // Linear data: the mean 127.5, within 0.5625 LSB (ACCURATE), 1.5 (FAST).
/// let mut acc: Sampler<_, Cfg<ClampToEdge, ClampToEdge, Linear, Accurate>> = Sampler::new(pyramid);
/// assert!((red(acc.sample(u, v, lod, mode)) - 127.5).abs() <= 0.5625);
/// let mut fast: Sampler<_, Cfg<ClampToEdge, ClampToEdge, Linear, Fast>> = Sampler::new(pyramid);
/// assert!((red(fast.sample(u, v, lod, mode)) - 127.5).abs() <= 1.5);
/// // sRGB data: decoded (0 and 1 linear), mean ½ linear, re-encoded:
/// // 255·(1.055·0.5^(1/2.4) − 0.055) = 187.5, within 0.6875 sRGB LSB.
/// let mut srgb: Sampler<_, Cfg<ClampToEdge, ClampToEdge, Srgb, Fast>> = Sampler::new(pyramid);
/// let encoded = 255.0 * (1.055 * 0.5f64.powf(1.0 / 2.4) - 0.055);
/// assert!((red(srgb.sample(u, v, lod, mode)) - encoded).abs() <= 0.6875);
/// // The same mean returned linear: 127.5 within 0.5101 LSB.
/// let mut lin: Sampler<_, Cfg<ClampToEdge, ClampToEdge, SrgbToLinear>> = Sampler::new(pyramid);
/// assert!((red(lin.sample(u, v, lod, mode)) - 127.5).abs() <= 0.5101);
/// // A FAST sRGB kernel filters at ACCURATE precision, and says so.
/// assert_eq!(<(Srgb, Fast) as Kernel>::TIER, Precision::Accurate);
/// assert_eq!(<(Linear, Fast) as Kernel>::TIER, Precision::Fast);
/// # Ok::<(), raymip::MipError>(())
/// ```
pub trait Kernel: sealed::Sealed + 'static {
    /// Fractional bits of the position weights the addressing computes
    /// (12 ACCURATE, 8 FAST, 16 for 16-bit lanes).
    const WEIGHT_BITS: u32;
    /// The tier the results have (an sRGB FAST kernel filters ACCURATE).
    const TIER: Precision;
    /// A texel as filtered (an RGBA8 word, or decoded 16-bit lanes).
    type Lanes: Copy + Debug;
    /// One level's filtered value before the final rounding.
    type Wide: Copy + Debug;

    /// A stored texel as lanes.
    fn load(t: Texel) -> Self::Lanes;
    /// The border colour (linear RGBA8, never decoded) as lanes.
    fn load_border(t: Texel) -> Self::Lanes;
    /// A stored texel as a nearest-texel result (identity but for
    /// sRGB data returned linear).
    fn nearest(t: Texel) -> Texel;
    /// The border colour as a nearest-texel result.
    fn border_nearest(t: Texel) -> Texel;
    /// One level's bilinear value of the footprint `l` (`t00, t10, t01,
    /// t11`) with position weights `fx, fy < 2^WEIGHT_BITS` (`k`: the
    /// sampler's [`Rounding`], as for every filter below).
    fn bilinear(l: [Self::Lanes; 4], fx: u32, fy: u32, k: Rounding) -> Self::Wide;
    /// [`bilinear`](Self::bilinear) rounded to a result texel.
    fn bilinear_texel(l: [Self::Lanes; 4], fx: u32, fy: u32, k: Rounding) -> Texel;
    /// [`bilinear_texel`](Self::bilinear_texel) for a call alone, not in a
    /// batch loop: the same texel, in the form that is shorter where the
    /// registers are free (the FAST kernel's signed pair sums on Arm, module
    /// `fast`); by default `bilinear_texel` itself.
    #[inline(always)]
    fn bilinear_texel_alone(l: [Self::Lanes; 4], fx: u32, fy: u32, k: Rounding) -> Texel {
        Self::bilinear_texel(l, fx, fy, k)
    }
    /// A level value rounded to a result texel.
    fn round(w: Self::Wide) -> Texel;
    /// One level of a trilinear sample: the footprint's filtered value as
    /// the kernel keeps it for [`round_level`](Self::round_level) or
    /// [`start_blend`](Self::start_blend) (the [`bilinear`](Self::bilinear)
    /// value; the ACCURATE linear kernel's is that value plus 2¹⁵, the
    /// blend's rounding term shared out over the levels; with feature
    /// `pcpi` on riscv32 the ACCURATE linear kernel keeps it in the
    /// co-processor, `raymip::coproc::pcpi` (`src/coproc/pcpi.rs`), and
    /// returns the rounded texel).
    type Level: Copy;
    /// The [`Level`](Self::Level) of the footprint `l` with weights `fx, fy`.
    fn level(l: [Self::Lanes; 4], fx: u32, fy: u32, k: Rounding) -> Self::Level;
    /// A level alone rounded to a result texel (the
    /// [`round`](Self::round) of its value).
    fn round_level(a: Self::Level) -> Texel;
    /// Whether the CFU co-processor's filter computes this kernel (the
    /// ACCURATE linear kernel, RGBA8): the sampler may then sample through
    /// its texture unit (`texture::coproc::descriptor_block`) or take footprints
    /// from its addressing instructions and filter them with
    /// [`coproc_level`](Self::coproc_level) (feature `cfu` on riscv32).
    const COPROC_FOOTPRINT: bool = false;
    /// The [`Level`](Self::Level) of the footprint `t` (`t00, t10, t01,
    /// t11` as stored) with the weights the co-processor latched (only
    /// called when [`COPROC_FOOTPRINT`](Self::COPROC_FOOTPRINT); otherwise
    /// the level with zero weights).
    #[inline(always)]
    fn coproc_level(t: [Texel; 4], k: Rounding) -> Self::Level {
        Self::level(t.map(Self::load), 0, 0, k)
    }
    /// A trilinear sample's first level `a` as the level blend with the
    /// lod fraction `t ∈ [0, 255]` holds it before the second level is
    /// read (for the 8.16 kernels `a·(256 − t) + 2²³` per channel: the
    /// first level's share of the blend, rounding included).
    type Started: Copy;
    /// Level `a` started for the blend with `t ∈ [0, 255]`.
    fn start_blend(a: Self::Level, t: u32, k: Rounding) -> Self::Started;
    /// A started level with `t = 0` (one level read) as a result texel:
    /// the [`round`](Self::round) of the level's value.
    fn finish_one(s: Self::Started) -> Texel;
    /// The [`blend`](Self::blend) of the started first level and the
    /// second level `b` (the last two [`level`](Self::level) calls, in
    /// that order) with `t ∈ [1, 255]`.
    fn finish_blend(s: Self::Started, b: Self::Level, t: u32, k: Rounding) -> Texel;
    /// The blend of two levels' values with the 8-bit lod fraction
    /// `t ∈ [1, 255]`, rounded to a result texel.
    fn blend(a: Self::Wide, b: Self::Wide, t: u32, k: Rounding) -> Texel;
    /// The blend of two nearest texels' lanes, rounded.
    fn blend_nearest(a: Self::Lanes, b: Self::Lanes, t: u32) -> Texel;
    /// A level value as a probe value that sums over 16 probes: four
    /// channels with 16 fractional bits (8.16 for 8-bit results, 16.8
    /// linear for sRGB data).
    fn probe(w: Self::Wide) -> [u32; 4];
    /// [`blend`](Self::blend) as a probe value.
    fn probe_blend(a: Self::Wide, b: Self::Wide, t: u32, k: Rounding) -> [u32; 4];
    /// The mean of `n ∈ [1, 16]` probe values (their channel sums),
    /// rounded to a result texel.
    fn probe_mean(sum: [u32; 4], n: u32) -> Texel;
}

/// The trilinear levels of a kernel in software: [`Kernel::Level`] is the
/// wide value, `level` and `round_level` are `bilinear` and `round`.
macro_rules! software_levels {
    () => {
        type Level = Self::Wide;
        #[inline(always)]
        fn level(l: [Self::Lanes; 4], fx: u32, fy: u32, k: Rounding) -> Self::Wide {
            Self::bilinear(l, fx, fy, k)
        }
        #[inline(always)]
        fn round_level(a: Self::Wide) -> Texel {
            Self::round(a)
        }
    };
}

/// The started blend of a kernel without a started form: the first
/// level's value and the fraction, blended when the second is there.
macro_rules! blend_later {
    () => {
        type Started = (Self::Wide, u32);
        #[inline(always)]
        fn start_blend(a: Self::Wide, t: u32, _: Rounding) -> (Self::Wide, u32) {
            (a, t)
        }
        #[inline(always)]
        fn finish_one((a, _): (Self::Wide, u32)) -> Texel {
            Self::round(a)
        }
        #[inline(always)]
        fn finish_blend((a, _): (Self::Wide, u32), b: Self::Wide, t: u32, k: Rounding) -> Texel {
            Self::blend(a, b, t, k)
        }
    };
}

/// The trilinear levels of the ACCURATE linear kernel (in software; feature
/// `pcpi` on riscv32 filters them on the co-processor): a level is its 8.16
/// value plus 2¹⁵ (`$level`: the chains start from the bilinear texel's
/// rounding term),
/// the first level is started as `a·(256 − t)` ([`accurate::blend_start`])
/// and the second adds `b·t` and rounds: the level blend with its rounding
/// folded into the levels (`accurate::bilerp_half`).
#[cfg(not(all(feature = "pcpi", target_arch = "riscv32")))]
macro_rules! levels_8_16 {
    ($level:expr) => {
        type Level = accurate::Wide;
        #[inline(always)]
        fn level(l: [Texel; 4], fx: u32, fy: u32, k: Rounding) -> accurate::Wide {
            $level(l, fx, fy, k)
        }
        #[inline(always)]
        fn round_level(a: accurate::Wide) -> Texel {
            accurate::blend_finish_one(accurate::blend_start(a, 0))
        }
        type Started = accurate::Wide;
        #[inline(always)]
        fn start_blend(a: accurate::Wide, t: u32, _: Rounding) -> accurate::Wide {
            accurate::blend_start(a, t)
        }
        #[inline(always)]
        fn finish_one(s: accurate::Wide) -> Texel {
            accurate::blend_finish_one(s)
        }
        #[inline(always)]
        fn finish_blend(s: accurate::Wide, b: accurate::Wide, t: u32, _: Rounding) -> Texel {
            accurate::blend_finish(s, b, t)
        }
    };
}

/// The texel hooks of an RGBA8 linear kernel: a texel is its own lanes
/// (load, border, nearest are the identity).
macro_rules! rgba8_texels {
    () => {
        #[inline(always)]
        fn load(t: Texel) -> Texel {
            t
        }
        #[inline(always)]
        fn load_border(t: Texel) -> Texel {
            t
        }
        #[inline(always)]
        fn nearest(t: Texel) -> Texel {
            t
        }
        #[inline(always)]
        fn border_nearest(t: Texel) -> Texel {
            t
        }
    };
}

/// The probe hooks of a kernel whose wide value is the four channel sums
/// `[u32; 4]` (linear 8.16 and sRGB 16.8 alike): a probe is the wide value,
/// the level blend keeps its fraction bits (`accurate::blend_keep`).
macro_rules! wide_probes {
    () => {
        #[inline(always)]
        fn probe(w: Self::Wide) -> [u32; 4] {
            w
        }
        #[inline(always)]
        fn probe_blend(a: Self::Wide, b: Self::Wide, t: u32, k: Rounding) -> [u32; 4] {
            accurate::blend_keep(a, b, t, k.wide)
        }
    };
}

/// Rounding, level blend and probes of a linear kernel whose level value
/// is the exact 8.16 [`accurate::Wide`] (ACCURATE, and FAST, whose levels
/// are exact at its 8-bit positions): one definition, the ACCURATE one.
macro_rules! linear_8_16 {
    () => {
        #[inline(always)]
        fn round(w: Self::Wide) -> Texel {
            accurate::round_wide_in_range(w)
        }
        #[inline(always)]
        fn blend(a: Self::Wide, b: Self::Wide, t: u32, k: Rounding) -> Texel {
            accurate::blend_wide_in_range(a, b, t, k.blend)
        }
        #[inline(always)]
        fn blend_nearest(a: Texel, b: Texel, t: u32) -> Texel {
            accurate::blend_texels(a, b, t)
        }
        wide_probes!();
        #[inline(always)]
        fn probe_mean(sum: [u32; 4], n: u32) -> Texel {
            round_mean(sum, n)
        }
    };
}

/// `ceil(2²⁸/n)` for `n = 1 … 16` (entry `n − 1`): the reciprocals of
/// [`round_mean`] (`2²⁸ / n` rounded up fits 29 bits for every `n`).
const RECIP_16N: [u32; 16] = {
    let mut r = [0u32; 16];
    let mut n = 1u32;
    while n <= 16 {
        r[(n - 1) as usize] = (1u32 << 28).div_ceil(n);
        n += 1;
    }
    r
};

/// [`round_wide_in_range`](accurate::round_wide_in_range) of [`mean`]
/// without a division, bit for bit for channel sums `s < 2³¹` (16 probes
/// of at most `255·2¹⁶` are below `2²⁸`) and `n ∈ [1, 16]` (other `n`
/// read entry `(n − 1) mod 16`):
///
/// * the two roundings are one: `floor((floor((s + n/2)/n) + 2¹⁵)/2¹⁶)
///   = floor(x/(n·2¹⁶))` with `x = s + n/2 + n·2¹⁵` (a floor of an
///   integer quotient divided again is the floor of the product divisor);
/// * `floor(x/(n·2¹⁶)) = floor(y/(16n))` with `y = x >> 12 < 2²⁰`, and
///   that is the high word of `y·R`, `R = ceil(2³²/(16n)) =` [`RECIP_16N`]:
///   `R·16n = 2³² + e` with `e < 16n ≤ 256`, so `y·R/2³²` exceeds
///   `y/(16n)` by `y·e/(16n·2³²) < 1/(16n)`, less than the distance from
///   `y/(16n)` to the next integer above it (at least `1/(16n)`).
///
/// One multiply per channel (`umull` on the Cortex-M4) instead of a
/// division (tested against the divisions over all `n` and sums at and
/// around every rounding boundary).
#[inline(always)]
fn round_mean(sum: [u32; 4], n: u32) -> Texel {
    let r = u64::from(RECIP_16N[(n.wrapping_sub(1) & 15) as usize]);
    let bias = (n << 15) + (n >> 1);
    let mut out = 0u32;
    for (c, &s) in sum.iter().enumerate() {
        let y = u64::from(s.wrapping_add(bias) >> 12);
        out += (((y * r) >> 32) as u32 & 0xFF) << (8 * c);
    }
    out
}

/// `(Σ + n/2) / n` per channel: the rounded mean of `n ≥ 1` probe values.
#[inline(always)]
fn mean(sum: [u32; 4], n: u32) -> [u32; 4] {
    let n = n.max(1);
    sum.map(|s| s.wrapping_add(n / 2) / n)
}

impl Kernel for (Linear, Accurate) {
    const WEIGHT_BITS: u32 = accurate::WEIGHT_BITS;
    const TIER: Precision = Precision::Accurate;
    type Lanes = Texel;
    type Wide = accurate::Wide;

    rgba8_texels!();
    #[inline(always)]
    fn bilinear(l: [Texel; 4], fx: u32, fy: u32, k: Rounding) -> Self::Wide {
        accurate::bilerp_in_range(l, fx, fy, k.wide)
    }
    #[cfg(not(all(feature = "pcpi", target_arch = "riscv32")))]
    #[inline(always)]
    fn bilinear_texel(l: [Texel; 4], fx: u32, fy: u32, k: Rounding) -> Texel {
        accurate::bilerp_rounded(l, fx, fy, k.texel)
    }
    // Feature `pcpi` on riscv32: the co-processor's corner sum, the same
    // bits as `bilerp_rounded` (`fx, fy < 4096`).
    #[cfg(all(feature = "pcpi", target_arch = "riscv32"))]
    #[inline(always)]
    fn bilinear_texel(l: [Texel; 4], fx: u32, fy: u32, _: Rounding) -> Texel {
        crate::coproc::pcpi::bw(fx, fy);
        crate::coproc::pcpi::bt(l[0], l[1]);
        crate::coproc::pcpi::bb(l[2], l[3])
    }
    // Feature `pcpi` on riscv32: each level on the co-processor (the
    // rounded texel returned, `bilinear_texel`; the 8.16 value kept), the
    // blend `tex.blend` of the last two: the same bits as `round` and
    // `blend_wide_in_range` of the software values.
    #[cfg(not(all(feature = "pcpi", target_arch = "riscv32")))]
    levels_8_16!(|l, fx, fy, k: Rounding| accurate::bilerp_half(l, fx, fy, k.texel));
    #[cfg(all(feature = "pcpi", target_arch = "riscv32"))]
    type Level = Texel;
    #[cfg(all(feature = "pcpi", target_arch = "riscv32"))]
    #[inline(always)]
    fn level(l: [Texel; 4], fx: u32, fy: u32, k: Rounding) -> Texel {
        Self::bilinear_texel(l, fx, fy, k)
    }
    #[cfg(all(feature = "pcpi", target_arch = "riscv32"))]
    #[inline(always)]
    fn round_level(a: Texel) -> Texel {
        a
    }
    #[cfg(all(feature = "pcpi", target_arch = "riscv32"))]
    type Started = Texel;
    #[cfg(all(feature = "pcpi", target_arch = "riscv32"))]
    #[inline(always)]
    fn start_blend(a: Texel, _: u32, _: Rounding) -> Texel {
        a
    }
    #[cfg(all(feature = "pcpi", target_arch = "riscv32"))]
    #[inline(always)]
    fn finish_one(a: Texel) -> Texel {
        a
    }
    #[cfg(all(feature = "pcpi", target_arch = "riscv32"))]
    #[inline(always)]
    fn finish_blend(_: Texel, _: Texel, t: u32, _: Rounding) -> Texel {
        crate::coproc::pcpi::blend(t)
    }
    const COPROC_FOOTPRINT: bool = true;
    // Feature `cfu` on riscv32: the footprint's weights are the ones
    // `tex.addr` latched, so a level is `tex.bt` and `tex.bb` alone.
    #[cfg(all(feature = "cfu", target_arch = "riscv32"))]
    #[inline(always)]
    fn coproc_level(t: [Texel; 4], _: Rounding) -> Texel {
        crate::coproc::pcpi::bt(t[0], t[1]);
        crate::coproc::pcpi::bb(t[2], t[3])
    }
    linear_8_16!();
}

impl Kernel for (Linear, Fast) {
    const WEIGHT_BITS: u32 = fast::FAST_WEIGHT_BITS;
    const TIER: Precision = Precision::Fast;
    type Lanes = Texel;
    type Wide = accurate::Wide;
    type Level = Self::Wide;
    // The sampler's levels take the mask as a constant (kept in a
    // register there); the probe loop's bilinear takes it from `k`.
    #[inline(always)]
    fn level(l: [Texel; 4], fx: u32, fy: u32, _: Rounding) -> Self::Wide {
        fast::bilinear(l, fx, fy)
    }
    #[inline(always)]
    fn round_level(a: Self::Wide) -> Texel {
        Self::round(a)
    }
    blend_later!();

    rgba8_texels!();
    #[inline(always)]
    fn bilinear(l: [Texel; 4], fx: u32, fy: u32, k: Rounding) -> Self::Wide {
        fast::bilinear_masked(l, fx, fy, k.pair_mask())
    }
    #[inline(always)]
    fn bilinear_texel(l: [Texel; 4], fx: u32, fy: u32, k: Rounding) -> Texel {
        fast::bilinear_texel_rounded::<false>(l, fx, fy, k.pair)
    }
    #[inline(always)]
    fn bilinear_texel_alone(l: [Texel; 4], fx: u32, fy: u32, k: Rounding) -> Texel {
        fast::bilinear_texel_rounded::<true>(l, fx, fy, k.pair)
    }
    // A FAST level value is an exact 8.16 value: rounding, level blend and
    // probes are the ACCURATE kernel's (module docs of `fast`).
    linear_8_16!();
}

/// The sRGB kernels: 16-bit lanes and weights ([`accurate`]), the output
/// stage `OUT` ([`srgb::encode_output`] or [`srgb::linear_output`]), the
/// same for both tiers.
macro_rules! srgb_kernel {
    ($space:ty, $out:path, $nearest:expr, $border:expr) => {
        impl<P: 'static> Kernel for ($space, P) {
            const WEIGHT_BITS: u32 = 16;
            const TIER: Precision = Precision::Accurate;
            type Lanes = accurate::Lin16;
            type Wide = accurate::Wide;
            software_levels!();
            blend_later!();

            #[inline(always)]
            fn load(t: Texel) -> accurate::Lin16 {
                srgb::load(t)
            }
            #[inline(always)]
            fn load_border(t: Texel) -> accurate::Lin16 {
                srgb::load_linear(t)
            }
            #[inline(always)]
            fn nearest(t: Texel) -> Texel {
                $nearest(t)
            }
            #[inline(always)]
            fn border_nearest(t: Texel) -> Texel {
                $border(t)
            }
            #[inline(always)]
            fn bilinear(l: [accurate::Lin16; 4], fx: u32, fy: u32, k: Rounding) -> Self::Wide {
                accurate::bilerp_lanes(l, accurate::corner_weights16(fx, fy), k.wide)
            }
            #[inline(always)]
            fn bilinear_texel(l: [accurate::Lin16; 4], fx: u32, fy: u32, k: Rounding) -> Texel {
                $out(Self::bilinear(l, fx, fy, k))
            }
            #[inline(always)]
            fn round(w: Self::Wide) -> Texel {
                $out(w)
            }
            #[inline(always)]
            fn blend(a: Self::Wide, b: Self::Wide, t: u32, k: Rounding) -> Texel {
                $out(accurate::blend_keep(a, b, t, k.wide))
            }
            #[inline(always)]
            fn blend_nearest(a: accurate::Lin16, b: accurate::Lin16, t: u32) -> Texel {
                $out(accurate::blend_keep(
                    srgb::widen(a),
                    srgb::widen(b),
                    t,
                    accurate::ROUND_WIDE,
                ))
            }
            wide_probes!();
            #[inline(always)]
            fn probe_mean(sum: [u32; 4], n: u32) -> Texel {
                $out(mean(sum, n))
            }
        }
    };
}

srgb_kernel!(Srgb, srgb::encode_output, |t| t, |t| srgb::encode_output(
    srgb::widen(srgb::load_linear(t))
));
srgb_kernel!(
    SrgbToLinear,
    srgb::linear_output,
    |t| srgb::linear_output(srgb::widen(srgb::load(t))),
    |t| t
);

/// A test footprint of four packed texels from 64 random bits: every
/// channel at its maximum when `n % 5 == 0`, a checkerboard of extremes
/// when `n % 5 == 1`, else four words of `x`.
#[cfg(test)]
pub(crate) fn footprint(x: u64, n: u32) -> [u32; 4] {
    match n % 5 {
        0 => [u32::MAX; 4],
        1 => [0, u32::MAX, u32::MAX, 0],
        _ => [
            x as u32,
            (x >> 32) as u32,
            (x >> 16) as u32,
            (x as u32).rotate_left(7),
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::XorShift64;

    /// The reciprocal mean rounds as the two divisions do (the rounded
    /// mean, then the rounded 8-bit channel), for every `n ∈ [1, 16]`:
    /// each channel at and one either side of every multiple of `n·2¹⁶`
    /// shifted by the rounding offsets (where a result changes), over
    /// every result value, and pseudo-random sums up to `2³¹`.
    #[test]
    fn round_mean_equals_the_divisions() {
        let old = |sum: [u32; 4], n: u32| accurate::round_wide_in_range(mean(sum, n));
        let mut rng = XorShift64(0x3EA2_0000_0000_0032);
        for n in 1..=16u32 {
            for q in 0..=256u32 {
                // The smallest sum whose rounded mean reaches `q·2¹⁶ − 2¹⁵`.
                let edge = ((q * n) << 16).saturating_sub((n << 15) + n / 2);
                for d in 0..3u32 {
                    let s = (edge + d).saturating_sub(1);
                    let sum = [s, s.saturating_sub(n), s / 2, edge];
                    assert_eq!(round_mean(sum, n), old(sum, n), "{n} {sum:?}");
                }
            }
            for _ in 0..if cfg!(miri) { 10 } else { 20_000 } {
                let r = rng.next_u64();
                let sum = [
                    r as u32,
                    (r >> 32) as u32,
                    (r >> 16) as u32,
                    (r >> 5) as u32,
                ]
                .map(|x| x >> 1 >> (r % 4 * 3));
                assert_eq!(round_mean(sum, n), old(sum, n), "{n} {sum:?}");
            }
        }
        // The table is `ceil(2²⁸/n)`, checked in 64-bit arithmetic.
        for (i, &r) in RECIP_16N.iter().enumerate() {
            let n = i as u64 + 1;
            assert!(u64::from(r) * n >= 1 << 28 && (u64::from(r) - 1) * n < 1 << 28);
        }
    }

    /// Every kernel's trilinear levels: a first level started with `t` and
    /// a second level give [`Kernel::blend`] of their bilinear values, a
    /// level started with `t = 0` and [`Kernel::round_level`] give
    /// [`Kernel::round`] of its value, for every `t`, on pseudo-random
    /// and extreme footprints and weights (`< 2^WEIGHT_BITS`).
    fn started_levels_blend<K: Kernel>() {
        let k = Rounding::new();
        let mut rng = XorShift64(0x9E37_79B9_7F4A_7C15);
        let mut next = || rng.next_u64();
        let draws = if cfg!(miri) { 3 } else { 300 };
        for n in 0..draws {
            let (ta, tb) = (
                footprint(next(), n).map(K::load),
                footprint(next(), n / 5).map(K::load),
            );
            let r = next();
            let top = (1u32 << K::WEIGHT_BITS) - 1;
            let w = |i: u32| match (n + i) % 7 {
                0 => 0,
                1 => top,
                _ => (r >> (16 * i)) as u32 & top,
            };
            let (fxa, fya, fxb, fyb) = (w(0), w(1), w(2), w(3));
            let (la, lb) = (K::level(ta, fxa, fya, k), K::level(tb, fxb, fyb, k));
            let (a, b) = (K::bilinear(ta, fxa, fya, k), K::bilinear(tb, fxb, fyb, k));
            assert_eq!(K::round_level(la), K::round(a));
            assert_eq!(K::finish_one(K::start_blend(la, 0, k)), K::round(a));
            for t in 1..=255u32 {
                assert_eq!(
                    K::finish_blend(K::start_blend(la, t, k), lb, t, k),
                    K::blend(a, b, t, k),
                    "{n} {t}"
                );
            }
        }
    }

    #[test]
    fn started_levels_blend_every_kernel() {
        started_levels_blend::<(Linear, Accurate)>();
        started_levels_blend::<(Linear, Fast)>();
        started_levels_blend::<(Srgb, Accurate)>();
        started_levels_blend::<(SrgbToLinear, Fast)>();
    }
}
