//! Texel addressing and filtering: nearest, bilinear, trilinear.
//!
//! Coordinates are normalized [`TexCoord`]s (I32F32): `u = 0` is the left
//! edge, `u = 1` the right edge of every level; texel `i` of a level of
//! width `w` has its centre at `(i + 0.5)/w`. The same holds for `v` and
//! rows.
//!
//! * **Addressing** ([`Address`]): `Wrap` repeats the texture (only the
//!   fractional part of `u` matters, taken exactly from the fixed-point
//!   bits); `Clamp` clamps texel indices to the edge (`u` outside
//!   `[−1, 2]` is first clamped to it, which changes nothing).
//! * **Nearest texel**: `i = floor(u·w)` (wrapped or clamped).
//! * **Bilinear**: `x = u·w − ½` rounded to 1/4096 texel, `i₀ = floor(x)`,
//!   `i₁ = i₀ + 1` (wrapped or clamped), weight `fx = x − i₀` with 12
//!   fractional bits; the kernel is [`crate::bilerp`].
//! * **Levels**: lod (I8F8) is clamped to `[0, levels − 1]`. Nearest-level
//!   modes use level `floor(lod + ½)`. Linear-level modes use levels
//!   `floor(lod)` and `floor(lod) + 1` with blend weight `frac(lod)`
//!   (8 fractional bits, exact). When the weight is 0 (lod integral,
//!   lod ≤ 0, or lod at the top stored level) only one level is fetched and
//!   the avoided texel reads are counted in [`FetchStats::skipped`].
//!
//! Output is RGBA8, rounded to nearest per channel; error bound
//! [`BILERP_MAX_ERROR_LSB`](crate::bilerp::BILERP_MAX_ERROR_LSB) = 0.5625 LSB for
//! bilinear and trilinear, exact for the nearest-texel modes.
//!
//! Two trilinear paths: ACCURATE [`Sampler::sample_trilinear`] (the one
//! [`Mode::Trilinear`] uses; bit-identical on every target, bound
//! 0.5625 LSB) and FAST [`Sampler::sample_trilinear_fast`] (both levels'
//! eight texels in one multiply-accumulate chain per channel, 10-bit
//! position weights; bound
//! [`FAST_TRILINEAR_MAX_ERROR_LSB`](crate::bilerp::FAST_TRILINEAR_MAX_ERROR_LSB)
//! = 0.8125 LSB, proof in [`crate::bilerp`]).
//!
//! # Precision for large coordinates
//!
//! [`TexCoord`] has 32 fractional bits at every magnitude and covers
//! `|u| < 2³¹`; wrapping takes the fractional part of the bits exactly, so
//! the firmware path is exact for every representable coordinate (a level
//! side of at most 2¹⁵ texels with 12-bit weights needs 27 fractional bits).
//! Precision is lost only where floats come in: an `f64` has a 53-bit
//! significand, so a coordinate `|u| ≥ 2²¹` (≈ 2.1·10⁶) is itself quantized
//! more coarsely than 2⁻³², and beyond `|u| ≈ 2^(40 − s)` for a `2^s`-texel
//! side (2²⁸ for 4096 texels) the quantization exceeds 1/4096 texel.
//! ±10⁶ is exact. [`Sampler::sample_f64`] reduces wrapped coordinates in
//! f64 (exactly) before converting, so it accepts any finite value;
//! [`tex_coord_from_f64`] rejects values outside the [`TexCoord`] range.

use core::fmt;

use fixed::types::I32F32;

use crate::bilerp::{self, WEIGHT_BITS, Wide};
use crate::lod::{Lod, clamp_lod};
use crate::mip::{Geometry, MAX_LEVELS, Texel, TexelSource};

/// A normalized texture coordinate (I32F32: range `[−2³¹, 2³¹)`, step 2⁻³²).
pub type TexCoord = I32F32;

/// Addressing outside `[0, 1)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Address {
    /// Repeat: only the fractional part of the coordinate is used.
    Wrap = 0,
    /// Clamp to edge: texel indices are clamped to `[0, size − 1]`.
    Clamp = 1,
}

impl Address {
    /// The addressing numbered `n` (0 wrap, 1 clamp: the discriminants),
    /// `None` otherwise.
    #[must_use]
    pub const fn from_index(n: u8) -> Option<Self> {
        match n {
            0 => Some(Self::Wrap),
            1 => Some(Self::Clamp),
            _ => None,
        }
    }
}

/// Filter mode, numbered as in the `sample` command. The linear-level
/// modes (0 and 3) need the `trilinear` feature.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Bilinear within a level, linear between levels.
    #[cfg(feature = "trilinear")]
    Trilinear = 0,
    /// Bilinear within the nearest level `floor(lod + ½)`.
    BilinearNearestLevel = 1,
    /// Nearest texel of the nearest level.
    Nearest = 2,
    /// Nearest texel in each of two levels, linear between levels.
    #[cfg(feature = "trilinear")]
    NearestTexelLinearLevel = 3,
}

impl Mode {
    /// The mode numbered `n` (0..=3), `None` otherwise (and for 0 and 3
    /// without the `trilinear` feature).
    #[must_use]
    pub const fn from_index(n: u8) -> Option<Self> {
        match n {
            #[cfg(feature = "trilinear")]
            0 => Some(Self::Trilinear),
            1 => Some(Self::BilinearNearestLevel),
            2 => Some(Self::Nearest),
            #[cfg(feature = "trilinear")]
            3 => Some(Self::NearestTexelLinearLevel),
            _ => None,
        }
    }
}

/// Texel-read counters of a [`Sampler`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FetchStats {
    /// Texels read from the source (4 per bilinear level, 1 per
    /// nearest-texel level).
    pub fetched: u64,
    /// Texel reads avoided because the second level of a linear-level mode
    /// could not change the result (blend weight 0): 4 per skipped
    /// bilinear level, 1 per skipped nearest-texel level.
    pub skipped: u64,
}

/// Errors at the float edge of the sampler.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum FilterError {
    /// A coordinate or lod is NaN or infinite.
    NonFinite,
    /// A coordinate lies outside the [`TexCoord`] range `[−2³¹, 2³¹)`.
    OutOfRange,
}

impl fmt::Display for FilterError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NonFinite => f.write_str("texture coordinate or lod is NaN or infinite"),
            Self::OutOfRange => f.write_str("texture coordinate outside [-2^31, 2^31)"),
        }
    }
}

impl core::error::Error for FilterError {}

/// Converts a float coordinate to a [`TexCoord`] (rounded to nearest 2⁻³²).
/// Set-up/host convenience (uses floats).
///
/// # Errors
/// [`FilterError::NonFinite`] for NaN/±inf, [`FilterError::OutOfRange`]
/// for `|x| ≥ 2³¹`.
pub fn tex_coord_from_f64(x: f64) -> Result<TexCoord, FilterError> {
    if !x.is_finite() {
        return Err(FilterError::NonFinite);
    }
    TexCoord::checked_from_num(x).ok_or(FilterError::OutOfRange)
}

/// Samples a [`TexelSource`] (a [`Pyramid`](crate::mip::Pyramid) or a
/// [`TexelCache`](crate::cache::TexelCache)) with one addressing mode.
#[derive(Debug)]
pub struct Sampler<S: TexelSource> {
    pub(crate) source: S,
    pub(crate) geometry: Geometry,
    pub(crate) address: Address,
    pub(crate) stats: FetchStats,
    /// `clamp_lod(Lod::MAX, levels)` in I8F8 bits: the top stored level.
    top_lod: i16,
    /// Per-level addressing when every level side is a power of two and
    /// the addressing is [`Address::Wrap`] (set up by [`Sampler::new`]);
    /// otherwise every entry is [`Pow2Level::OFF`].
    pow2_wrap: [Pow2Level; MAX_LEVELS as usize + 1],
}

/// Addressing of one level of a power-of-two texture under
/// [`Address::Wrap`]: the level's offset in texels, its width and height
/// (`2^k ≤ 2¹⁵`), `log2(width·height)` and the per-axis constant
/// `c = (2¹⁹ − 2³¹)/2^k` of [`pow2_wrap_taps`] (wrapping `u32`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Pow2Level {
    /// Offset of the level in the texel slice (`< 2³¹`); `u32::MAX` for
    /// [`Pow2Level::OFF`].
    offset: u32,
    w: u32,
    h: u32,
    cx: u32,
    cy: u32,
    /// `log2(w·h) ≤ 30`: the level holds `1 << log2_len` texels.
    log2_len: u32,
}

impl Pow2Level {
    /// No power-of-two addressing: the offset `u32::MAX`, read as the
    /// level start `usize::MAX` (sign-extended, [`Pow2Level::start`]),
    /// never lies in a slice (the range end wraps below its start),
    /// so [`Pow2Level::footprint`] returns `None` and the sampler takes
    /// the generic path. A table of these costs the per-hit path no test
    /// of its own.
    const OFF: Self = Self {
        offset: u32::MAX,
        w: 0,
        h: 0,
        cx: 0,
        cy: 0,
        log2_len: 0,
    };

    /// The table for `g` when both sides are powers of two (then every
    /// level's are; levels past the top repeat the top level), else
    /// [`Pow2Level::OFF`] throughout.
    fn table(g: &Geometry) -> [Self; MAX_LEVELS as usize + 1] {
        let mut t = [Self::OFF; MAX_LEVELS as usize + 1];
        if g.width().is_power_of_two() && g.height().is_power_of_two() {
            for (k, e) in (0u8..).zip(t.iter_mut()) {
                let (w, h) = g.level_size(k);
                let (kx, ky) = (w.trailing_zeros(), h.trailing_zeros());
                let Ok(offset) = u32::try_from(g.level_offset(k)) else {
                    return [Self::OFF; MAX_LEVELS as usize + 1];
                };
                *e = Self {
                    offset,
                    w,
                    h,
                    cx: wrap_constant_log2(kx),
                    cy: wrap_constant_log2(ky),
                    log2_len: kx + ky,
                };
            }
        }
        t
    }

    /// The level's first texel index: `offset` sign-extended, so that
    /// [`Pow2Level::OFF`]'s `u32::MAX` becomes `usize::MAX` on every target
    /// and real offsets (`< 2³¹`, the [`Geometry`] bound) are unchanged (no
    /// instruction on a 32-bit target).
    #[inline(always)]
    fn start(&self) -> usize {
        self.offset as i32 as isize as usize
    }

    /// The 2×2 footprint at `(u, v)` in this level of `texels` and its
    /// weights `(fx, fy)`, as [`linear_taps`] and [`Pyramid::get`](crate::mip::Pyramid::get)
    /// give them; `None` if the slice is shorter than the level (a
    /// [`Pyramid`](crate::mip::Pyramid) rules that out). One bounds check for
    /// the level (`offset + 2^log2_len ≤ len`); the four indices are
    /// masked with `2^log2_len − 1`, which lets the compiler drop the
    /// per-texel checks (it changes no index: each is below `w·h`).
    #[inline(always)]
    fn footprint(
        &self,
        texels: &[Texel],
        u: TexCoord,
        v: TexCoord,
    ) -> Option<([Texel; 4], u32, u32)> {
        let n = 1usize << (self.log2_len & 31);
        let start = self.start();
        let level = texels.get(start..start.wrapping_add(n))?;
        let m = n - 1;
        let (x0, x1, fx) = pow2_wrap_taps(u, self.w, self.cx);
        let (y0, _, fy) = pow2_wrap_taps(v, self.h, self.cy);
        let row0 = y0.wrapping_mul(self.w) as usize;
        let w = self.w as usize;
        let i00 = row0.wrapping_add(x0 as usize) & m;
        let i10 = row0.wrapping_add(x1 as usize) & m;
        let i01 = i00.wrapping_add(w) & m;
        let i11 = i10.wrapping_add(w) & m;
        Some(([level[i00], level[i10], level[i01], level[i11]], fx, fy))
    }
}

/// `(2¹⁹ − 2³¹)/2^k` as wrapping `u32` for a power-of-two side `2^k`,
/// `k ≤ 19` (exact: the numerator is a multiple of 2¹⁹).
fn wrap_constant_log2(k: u32) -> u32 {
    const C: i32 = (1 << 19) + i32::MIN; // 2¹⁹ − 2³¹
    C.wrapping_shr(k) as u32
}

/// Bilinear footprint on one axis of a power-of-two side `size = 2^k`
/// under [`Address::Wrap`]: the same `(i₀, i₁, weight)` as [`linear_taps`]
/// with one 32×32→64-bit multiply. With `x = u·size − ½ + 2⁻¹³` in
/// 2⁻³²-texel units and `u` the fractional bits of the coordinate,
/// `x = size·y` for the integer `y = u + c`, `c = (2¹⁹ − 2³¹)/size` (exact
/// for `k ≤ 19`). For `y mod 2³²` the product `size·y` has `i₀ = floor(x / 2³²)`
/// already wrapped to `[0, size)` in its high word and the weight in bits
/// 20..32 of its low word; `i₁ = (i₀ + 1) mod size`. Tested equal to
/// [`linear_taps`] for every side up to [`crate::mip::MAX_SIZE`].
#[inline(always)]
fn pow2_wrap_taps(coord: TexCoord, size: u32, c: u32) -> (u32, u32, u32) {
    let y = (coord.to_bits() as u32).wrapping_add(c);
    let p = u64::from(y) * u64::from(size);
    let i0 = (p >> 32) as u32;
    let f = (p as u32) >> (32 - WEIGHT_BITS);
    (i0, i0.wrapping_add(1) & size.wrapping_sub(1), f)
}

/// Rounding offset that turns the truncation to 12 fractional bits into
/// round-to-nearest: 2⁻¹³ in 32-fractional-bit units.
const ROUND_WEIGHT: i64 = 1 << (31 - WEIGHT_BITS);

/// Coordinate clamp for [`Address::Clamp`]: `[−1, 2]` in I32F32 bits.
const CLAMP_LO: i64 = -(1 << 32);
const CLAMP_HI: i64 = 2 << 32;

/// `u · size` in 32-fractional-bit units after addressing: for `Wrap` the
/// fractional part of `u` (in `[0, size)`), for `Clamp` `u` clamped to
/// `[−1, 2]` (in `[−size, 2·size]`). `|result| < 2⁴⁹`.
#[inline(always)]
fn scaled(coord: TexCoord, size: u32, address: Address) -> i64 {
    let c = match address {
        Address::Wrap => coord.to_bits() & 0xFFFF_FFFF,
        Address::Clamp => coord.to_bits().clamp(CLAMP_LO, CLAMP_HI),
    };
    c * i64::from(size)
}

/// Integer part of a [`scaled`] value (`|x| < 2⁴⁹`, so `x >> 32` lies in
/// `(−2¹⁷, 2¹⁷)` and the cast to `i32` is exact).
#[inline(always)]
fn int_part(x: i64) -> i32 {
    (x >> 32) as i32
}

/// Clamps `i` into `[0, size − 1]` (`size ≥ 1`).
#[inline(always)]
fn clamp_index(i: i32, size: u32) -> u32 {
    // `max`/`min`, not `clamp`: no panic branch for unordered bounds.
    let top = i32::try_from(size).unwrap_or(i32::MAX).saturating_sub(1);
    i.min(top).max(0).unsigned_abs()
}

/// Nearest texel index `floor(u·size)`, addressed. For `Wrap` the index is
/// already in `[0, size)`; the clamp is the `Clamp` mode (and a guard).
#[inline(always)]
pub(crate) fn nearest_index(coord: TexCoord, size: u32, address: Address) -> u32 {
    clamp_index(int_part(scaled(coord, size, address)), size)
}

/// Bilinear footprint on one axis: `(i₀, i₁, weight of i₁ in 1/4096)`.
///
/// `x = u·size − ½ + 2⁻¹³` (the `+ 2⁻¹³` rounds the 12-bit weight to
/// nearest); `i₀ = floor(x)`, `i₁ = i₀ + 1`. For `Wrap`, `u ∈ [0, 1)` so
/// `i₀ ∈ [−1, size − 1]` and `i₁ ∈ [0, size]`: one compare each wraps
/// them. Indices stay below `size` in every case (sources clamp again).
#[inline(always)]
pub(crate) fn linear_taps(coord: TexCoord, size: u32, address: Address) -> (u32, u32, u32) {
    let x = scaled(coord, size, address) - (1 << 31) + ROUND_WEIGHT;
    let i = int_part(x);
    // Bits 20..32 of x: the fraction's top 12 bits (masking keeps the low
    // 32 bits of the two's-complement value exactly).
    let f = (((x & 0xFFFF_FFFF) as u32) >> (32 - WEIGHT_BITS)) & ((1 << WEIGHT_BITS) - 1);
    match address {
        Address::Wrap => {
            let i0 = if i < 0 {
                size.saturating_sub(1)
            } else {
                i.unsigned_abs()
            };
            let i1 = i.saturating_add(1).unsigned_abs();
            (i0, if i1 >= size { 0 } else { i1 }, f)
        }
        Address::Clamp => (
            clamp_index(i, size),
            clamp_index(i.saturating_add(1), size),
            f,
        ),
    }
}

/// The levels a lod selects: `lower = floor(lod)`, blend weight
/// `t = frac(lod)` (8 fractional bits, exact), `nearest = floor(lod + ½)`,
/// after clamping lod to `[0, levels − 1]` (so `t = 0` at the top level).
#[derive(Clone, Copy, Debug)]
pub(crate) struct LevelSplit {
    pub(crate) lower: u8,
    pub(crate) t: u32,
    pub(crate) nearest: u8,
}

impl LevelSplit {
    #[inline(always)]
    pub(crate) fn new(lod: Lod, geometry: &Geometry) -> Self {
        let lod = clamp_lod(lod, geometry.levels());
        // lod ∈ [0, 15]: bits ∈ [0, 3840].
        let bits = u16::try_from(lod.to_bits()).unwrap_or(0);
        Self {
            lower: (bits >> 8) as u8,
            t: u32::from(bits & 0xFF),
            nearest: (((bits + 0x80) >> 8) as u8).min(geometry.top_level()),
        }
    }
}

impl<S: TexelSource> Sampler<S> {
    /// A sampler over `source` with addressing `address`.
    pub fn new(source: S, address: Address) -> Self {
        let geometry = source.geometry();
        let pow2_wrap = match address {
            Address::Wrap => Pow2Level::table(&geometry),
            Address::Clamp => [Pow2Level::OFF; MAX_LEVELS as usize + 1],
        };
        Self {
            source,
            geometry,
            address,
            stats: FetchStats::default(),
            top_lod: clamp_lod(Lod::MAX, geometry.levels()).to_bits(),
            pow2_wrap,
        }
    }

    /// Filtered texel at `(u, v)` and level of detail `lod` (clamped to
    /// `[0, levels − 1]`) with filter `mode`. Never panics. Dispatches to
    /// [`sample_trilinear`](Self::sample_trilinear),
    /// [`sample_bilinear`](Self::sample_bilinear),
    /// [`sample_nearest`](Self::sample_nearest) and
    /// [`sample_nearest_linear_level`](Self::sample_nearest_linear_level) (always inlined,
    /// so a constant `mode` costs no dispatch).
    #[inline(always)]
    pub fn sample(&mut self, u: TexCoord, v: TexCoord, lod: Lod, mode: Mode) -> Texel {
        match mode {
            #[cfg(feature = "trilinear")]
            Mode::Trilinear => self.sample_trilinear(u, v, lod),
            Mode::BilinearNearestLevel => self.sample_bilinear(u, v, lod),
            Mode::Nearest => self.sample_nearest(u, v, lod),
            #[cfg(feature = "trilinear")]
            Mode::NearestTexelLinearLevel => self.sample_nearest_linear_level(u, v, lod),
        }
    }

    /// `lod` clamped to the stored levels, as I8F8 bits in `[0, 3840]`.
    #[inline(always)]
    fn lod_bits(&self, lod: Lod) -> u16 {
        // = clamp_lod(lod, levels): `top_lod ≥ 0`, so the result is in
        // `[0, top_lod]` and the cast is exact.
        lod.to_bits().min(self.top_lod).max(0) as u16
    }

    /// The nearest level `floor(lod + ½)` of clamped lod bits
    /// (`bits ≤ top_lod = top level · 256`, so the result is at most the top
    /// level).
    #[inline(always)]
    fn nearest_level(bits: u16) -> u8 {
        ((bits + 0x80) >> 8) as u8
    }

    /// [`Mode::Trilinear`]: bilinear in levels `floor(lod)` and
    /// `floor(lod) + 1`, blended by `frac(lod)` (one level when the
    /// fraction is 0). Feature `trilinear`.
    #[cfg(feature = "trilinear")]
    #[inline(always)]
    pub fn sample_trilinear(&mut self, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
        self.trilinear_counted(u, v, lod, |s, one_level| {
            if one_level {
                s.fetched += 4;
                s.skipped += 4;
            } else {
                s.fetched += 8;
            }
        })
    }

    /// FAST trilinear ([`Mode::Trilinear`] semantics, a different
    /// kernel): the two levels' eight texels summed in one chain per
    /// channel with the level weight folded into 10-bit corner weights
    /// (`bilerp::trilerp_fast_level`); error bound
    /// [`FAST_TRILINEAR_MAX_ERROR_LSB`](bilerp::FAST_TRILINEAR_MAX_ERROR_LSB)
    /// = 0.8125 LSB per channel against the exact trilinear filter, where
    /// the ACCURATE [`sample_trilinear`](Self::sample_trilinear) has
    /// [`BILERP_MAX_ERROR_LSB`](bilerp::BILERP_MAX_ERROR_LSB) = 0.5625.
    /// When the blend weight is 0 it returns the ACCURATE one-level value.
    /// Fetch counters as [`sample_trilinear`](Self::sample_trilinear).
    /// Results are the same on every target. Feature `trilinear`.
    #[cfg(feature = "trilinear")]
    #[inline(always)]
    pub fn sample_trilinear_fast(&mut self, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
        let bits = self.lod_bits(lod);
        // As in `trilinear_counted`: `lower + 1 ≤ 16` needs no check.
        let lower = usize::from(bits >> 8) & 15;
        let t = u32::from(bits & 0xFF);
        let (ta, fxa, fya) = self.footprint(u, v, lower);
        if t == 0 {
            self.stats.fetched += 4;
            self.stats.skipped += 4;
            bilerp::bilerp_rounded(ta, fxa, fya)
        } else {
            let s = (1 << bilerp::BLEND_BITS) - t;
            let acc = bilerp::trilerp_fast_level(bilerp::FAST_ROUND, ta, fxa, fya, s);
            let (tb, fxb, fyb) = self.footprint(u, v, lower + 1);
            self.stats.fetched += 8;
            bilerp::trilerp_fast_texel(bilerp::trilerp_fast_level(acc, tb, fxb, fyb, t))
        }
    }

    /// [`sample_trilinear`](Self::sample_trilinear) with the fetch counting
    /// left to `count(stats, one_level)`, called once: `one_level` when the
    /// blend weight is 0 (one level read, 4 texel reads skipped), else 8
    /// texels were read. (Called in each branch, where the single call's
    /// counter updates cost least; the batch counts once per batch.)
    #[cfg(feature = "trilinear")]
    #[inline(always)]
    fn trilinear_counted(
        &mut self,
        u: TexCoord,
        v: TexCoord,
        lod: Lod,
        mut count: impl FnMut(&mut FetchStats, bool),
    ) -> Texel {
        let bits = self.lod_bits(lod);
        // `bits ≤ 3840`: the mask changes nothing and tells the compiler
        // that `lower + 1 ≤ 16` indexes the level table without a check,
        // next to `lower`'s entry (one address for both levels).
        let lower = usize::from(bits >> 8) & 15;
        let t = u32::from(bits & 0xFF);
        let (ta, fxa, fya) = self.footprint(u, v, lower);
        let a = bilerp::bilerp_in_range(ta, fxa, fya);
        if t == 0 {
            count(&mut self.stats, true);
            bilerp::round_wide_in_range(a)
        } else {
            let (tb, fxb, fyb) = self.footprint(u, v, lower + 1);
            let b = bilerp::bilerp_in_range(tb, fxb, fyb);
            count(&mut self.stats, false);
            bilerp::blend_wide_in_range(a, b, t)
        }
    }

    /// [`Mode::BilinearNearestLevel`]: bilinear in level `floor(lod + ½)`.
    #[inline(always)]
    pub fn sample_bilinear(&mut self, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
        self.stats.fetched += 4;
        self.bilinear_uncounted(u, v, lod)
    }

    /// [`sample_bilinear`](Self::sample_bilinear) without the fetch counter.
    #[inline(always)]
    fn bilinear_uncounted(&mut self, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
        let level = Self::nearest_level(self.lod_bits(lod));
        let (t, fx, fy) = self.footprint(u, v, usize::from(level) & 15);
        bilerp::bilerp_rounded(t, fx, fy)
    }

    /// [`Mode::Nearest`]: nearest texel of level `floor(lod + ½)`.
    #[inline]
    pub fn sample_nearest(&mut self, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
        let level = Self::nearest_level(self.lod_bits(lod));
        self.nearest(u, v, level)
    }

    /// [`Mode::NearestTexelLinearLevel`]: nearest texel in levels
    /// `floor(lod)` and `floor(lod) + 1`, blended by `frac(lod)`. Feature
    /// `trilinear`.
    #[cfg(feature = "trilinear")]
    #[inline]
    pub fn sample_nearest_linear_level(&mut self, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
        let bits = self.lod_bits(lod);
        let lower = (bits >> 8) as u8;
        let t = u32::from(bits & 0xFF);
        let a = self.nearest(u, v, lower);
        if t == 0 {
            self.stats.skipped += 1;
            a
        } else {
            let b = self.nearest(u, v, lower + 1);
            bilerp::blend_texels(a, b, t)
        }
    }

    /// Batch of [`sample`](Self::sample): `out[i]` = the sample at
    /// `hits[i] = (u, v, lod)` with filter `mode`, for
    /// `i < n = min(hits.len(), out.len())`, in caller memory; returns `n`.
    /// Same results and fetch counters as `n` single calls; never panics.
    /// Always inlined, so a constant `mode` compiles to its loop alone.
    #[inline(always)]
    pub fn sample_batch(
        &mut self,
        hits: &[(TexCoord, TexCoord, Lod)],
        mode: Mode,
        out: &mut [Texel],
    ) -> usize {
        let n = hits.len().min(out.len());
        macro_rules! each {
            ($f:ident) => {
                for (o, &(u, v, lod)) in out.iter_mut().zip(hits) {
                    *o = self.$f(u, v, lod);
                }
            };
        }
        // `n ≤ isize::MAX`: the casts to `u64` are exact.
        let texels = n as u64 * 4;
        match mode {
            // The two filtered modes count once per batch (the same totals
            // as per call), keeping the counters out of the loop.
            #[cfg(feature = "trilinear")]
            Mode::Trilinear => {
                let mut one_level = 0usize;
                for (o, &(u, v, lod)) in out.iter_mut().zip(hits) {
                    *o = self.trilinear_counted(u, v, lod, |_, one| {
                        one_level += usize::from(one);
                    });
                }
                let skipped = one_level as u64 * 4;
                self.stats.fetched += 2 * texels - skipped;
                self.stats.skipped += skipped;
            }
            Mode::BilinearNearestLevel => {
                for (o, &(u, v, lod)) in out.iter_mut().zip(hits) {
                    *o = self.bilinear_uncounted(u, v, lod);
                }
                self.stats.fetched += texels;
            }
            Mode::Nearest => each!(sample_nearest),
            #[cfg(feature = "trilinear")]
            Mode::NearestTexelLinearLevel => each!(sample_nearest_linear_level),
        }
        n
    }

    /// [`sample`](Self::sample) with float inputs: a set-up/host
    /// convenience, not for the per-hit path (it uses floats). Wrapped
    /// coordinates are reduced to `[0, 1)` in f64 first (exact), so any
    /// finite value works; clamped ones are clamped to `[−1, 2]`. `lod` is
    /// rounded to 1/256 and clamped like [`sample`](Self::sample).
    ///
    /// # Errors
    /// [`FilterError::NonFinite`] when `u`, `v` or `lod` is NaN or ±inf.
    pub fn sample_f64(
        &mut self,
        u: f64,
        v: f64,
        lod: f64,
        mode: Mode,
    ) -> Result<Texel, FilterError> {
        if !(u.is_finite() && v.is_finite() && lod.is_finite()) {
            return Err(FilterError::NonFinite);
        }
        let reduce = |x: f64| match self.address {
            Address::Wrap => x - libm::floor(x),
            Address::Clamp => x.clamp(-1.0, 2.0),
        };
        let u = tex_coord_from_f64(reduce(u))?;
        let v = tex_coord_from_f64(reduce(v))?;
        let lod = Lod::saturating_from_num(lod);
        Ok(self.sample(u, v, lod, mode))
    }

    /// The 2×2 footprint at `level` and its weights `(fx, fy)` (counted in
    /// [`FetchStats::fetched`] by the caller). Power-of-two textures under
    /// [`Address::Wrap`] read from memory with one address computation and
    /// one bounds check per footprint ([`Pow2Level::footprint`]); every
    /// other case (and a texel slice shorter than the level) goes through
    /// the source's [`TexelSource::footprint`]. Both give the same texels.
    /// `level ≤ 16` (the callers mask it; the table has an entry for 16,
    /// a copy of 15, so that `level + 1` needs no check either).
    #[inline(always)]
    fn footprint(&mut self, u: TexCoord, v: TexCoord, level: usize) -> ([Texel; 4], u32, u32) {
        if let Some(texels) = self.source.texel_slice()
            && let Some(f) = self.pow2_wrap[level].footprint(texels, u, v)
        {
            return f;
        }
        let level = level as u8;
        let (w, h) = self.geometry.level_size(level);
        let (x0, x1, fx) = linear_taps(u, w, self.address);
        let (y0, y1, fy) = linear_taps(v, h, self.address);
        (self.source.footprint(level, [x0, x1], [y0, y1]), fx, fy)
    }

    /// Bilinear value at `level` in 8.16 per channel, not counted in the
    /// fetch statistics (the caller counts).
    /// Bilinear value at `level` in 8.16 per channel (4 texels counted).
    #[inline(always)]
    pub(crate) fn bilinear(&mut self, u: TexCoord, v: TexCoord, level: u8) -> Wide {
        self.stats.fetched += 4;
        let (t, fx, fy) = self.footprint(u, v, usize::from(level) & 15);
        bilerp::bilerp_in_range(t, fx, fy)
    }

    /// Nearest texel at `level`.
    #[inline(always)]
    pub(crate) fn nearest(&mut self, u: TexCoord, v: TexCoord, level: u8) -> Texel {
        let (w, h) = self.geometry.level_size(level);
        let x = nearest_index(u, w, self.address);
        let y = nearest_index(v, h, self.address);
        self.stats.fetched += 1;
        self.source.texel(level, x, y)
    }

    /// The addressing mode.
    #[must_use]
    pub fn address(&self) -> Address {
        self.address
    }

    /// The source's geometry (read once at construction).
    #[must_use]
    pub fn geometry(&self) -> Geometry {
        self.geometry
    }

    /// Fetch counters since construction or the last
    /// [`reset_stats`](Self::reset_stats).
    #[must_use]
    pub fn stats(&self) -> FetchStats {
        self.stats
    }

    /// Zeroes the fetch counters.
    pub fn reset_stats(&mut self) {
        self.stats = FetchStats::default();
    }

    /// The texel source.
    #[must_use]
    pub fn source(&self) -> &S {
        &self.source
    }

    /// The texel source, mutable (e.g. to read cache counters).
    #[must_use]
    pub fn source_mut(&mut self) -> &mut S {
        &mut self.source
    }

    /// Gives the texel source back.
    #[must_use]
    pub fn into_source(self) -> S {
        self.source
    }
}

#[cfg(all(test, feature = "trilinear", feature = "mipgen"))]
mod tests {
    extern crate std;
    use super::*;
    use crate::mip::{Pyramid, generate};
    use std::vec;
    use std::vec::Vec;

    fn c(x: f64) -> TexCoord {
        TexCoord::from_num(x)
    }

    /// Storage for `g` with hashed level-0 texels (`i·0x9E3779B9 ^ salt`)
    /// and the levels above generated from them.
    fn hashed_pyramid(g: &Geometry, salt: u32) -> Vec<Texel> {
        let mut buf: Vec<Texel> = (0..g.len() as u32)
            .map(|i| i.wrapping_mul(0x9E37_79B9) ^ salt)
            .collect();
        generate(g, &mut buf).unwrap();
        buf
    }

    fn gray(v: u8) -> Texel {
        u32::from_le_bytes([v, v, v, 255])
    }

    #[test]
    fn address_from_index_is_the_discriminant() {
        for a in [Address::Wrap, Address::Clamp] {
            assert_eq!(Address::from_index(a as u8), Some(a));
        }
        for n in 2..=u8::MAX {
            assert_eq!(Address::from_index(n), None);
        }
    }

    #[test]
    fn centres_return_texels() {
        let g = Geometry::new(4, 2, 3).unwrap();
        let mut buf: Vec<Texel> = (0..g.len() as u32).map(|i| gray((i * 20) as u8)).collect();
        generate(&g, &mut buf).unwrap();
        let p = Pyramid::new(g, &buf).unwrap();
        let mut s = Sampler::new(p, Address::Wrap);
        for y in 0..2u32 {
            for x in 0..4u32 {
                let u = c((f64::from(x) + 0.5) / 4.0);
                let v = c((f64::from(y) + 0.5) / 2.0);
                let want = p.get(0, x, y);
                for mode in [Mode::Trilinear, Mode::BilinearNearestLevel, Mode::Nearest] {
                    assert_eq!(s.sample(u, v, Lod::ZERO, mode), want, "{x},{y} {mode:?}");
                }
            }
        }
        assert_eq!(s.stats().skipped, 8 * 4);
    }

    #[test]
    fn wrap_seam_and_clamp_edge() {
        let g = Geometry::new(2, 1, 1).unwrap();
        let buf = [gray(0), gray(200)];
        let p = Pyramid::new(g, &buf).unwrap();
        let mut w = Sampler::new(p, Address::Wrap);
        let mut k = Sampler::new(p, Address::Clamp);
        // u = 0: halfway between texel 1 (wrapped) and texel 0.
        assert_eq!(
            w.sample(c(0.0), c(0.5), Lod::ZERO, Mode::Trilinear),
            gray(100)
        );
        assert_eq!(
            k.sample(c(0.0), c(0.5), Lod::ZERO, Mode::Trilinear),
            gray(0)
        );
        assert_eq!(
            k.sample(c(1e6), c(-1e6), Lod::ZERO, Mode::Trilinear),
            gray(200)
        );
        assert_eq!(
            w.sample(c(-1e6 + 0.75), c(0.5), Lod::ZERO, Mode::Nearest),
            gray(200)
        );
        assert_eq!(
            w.sample(TexCoord::MIN, TexCoord::MAX, Lod::MAX, Mode::Trilinear),
            w.sample(c(0.0), c(1.0 - 1e-9), Lod::ZERO, Mode::Trilinear)
        );
    }

    #[test]
    fn trilinear_blends_levels() {
        let g = Geometry::new(2, 2, 2).unwrap();
        let buf = vec![gray(0), gray(0), gray(0), gray(0), gray(100)];
        let p = Pyramid::new(g, &buf).unwrap();
        let mut s = Sampler::new(p, Address::Clamp);
        let half = Lod::from_num(0.5);
        assert_eq!(s.sample(c(0.25), c(0.25), half, Mode::Trilinear), gray(50));
        assert_eq!(
            s.sample(c(0.25), c(0.25), half, Mode::NearestTexelLinearLevel),
            gray(50)
        );
        assert_eq!(s.sample(c(0.25), c(0.25), half, Mode::Nearest), gray(100));
        assert_eq!(
            s.sample(c(0.25), c(0.25), Lod::from_num(0.49), Mode::Nearest),
            gray(0)
        );
        assert_eq!(
            s.stats(),
            FetchStats {
                fetched: 8 + 2 + 1 + 1,
                skipped: 0
            }
        );
        assert_eq!(
            s.sample(c(0.25), c(0.25), Lod::from_num(9), Mode::Trilinear),
            gray(100)
        );
        assert_eq!(s.stats().skipped, 4);
        assert_eq!(
            s.sample_f64(f64::NAN, 0.0, 0.0, Mode::Trilinear),
            Err(FilterError::NonFinite)
        );
        assert_eq!(
            s.sample_f64(0.0, 0.0, f64::INFINITY, Mode::Trilinear),
            Err(FilterError::NonFinite)
        );
        assert_eq!(
            s.sample_f64(1e300, -1e300, 1e300, Mode::Nearest),
            Ok(gray(100))
        );
        assert_eq!(tex_coord_from_f64(3e9), Err(FilterError::OutOfRange));
        assert_eq!(tex_coord_from_f64(-0.25), Ok(c(-0.25)));
    }

    #[test]
    fn pow2_wrap_taps_equal_linear_taps() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        for k in 0..=15u32 {
            let size = 1u32 << k;
            for n in 0..if cfg!(miri) { 20 } else { 4000u64 } {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                // Random bits, and the seam/edge values of this size.
                let edge = (n % (2 * u64::from(size) + 1)) << (31 - k);
                for bits in [
                    x as i64,
                    edge as i64,
                    -(edge as i64),
                    (x as i64) >> (n % 40),
                ] {
                    let c = TexCoord::from_bits(bits);
                    assert_eq!(
                        pow2_wrap_taps(c, size, wrap_constant_log2(k)),
                        linear_taps(c, size, Address::Wrap),
                        "k {k} bits {bits:#x}"
                    );
                }
            }
        }
    }

    /// `sample_batch` gives the results and the fetch counters of single
    /// calls for every mode (lods with and without a fraction, so both
    /// trilinear branches and their counting), writes `min(hits, out)`
    /// results and leaves the rest of `out` alone.
    #[test]
    fn batch_equals_single_calls() {
        use crate::cache::TexelCache;
        let g = Geometry::new(16, 8, 4).unwrap();
        let buf = hashed_pyramid(&g, 0);
        let p = Pyramid::new(g, &buf).unwrap();
        let hits: Vec<(TexCoord, TexCoord, Lod)> = (0..50u32)
            .map(|i| {
                let lod = if i % 3 == 0 {
                    i32::from(i as u8 % 4) * 256
                } else {
                    (i * 37 % 1000) as i32 - 100
                };
                (
                    TexCoord::from_bits(i64::from(i.wrapping_mul(0x2F6B_1E3D)) << 1),
                    TexCoord::from_bits(-i64::from(i.wrapping_mul(0x61C8_8647))),
                    Lod::from_bits(lod as i16),
                )
            })
            .collect();
        for address in [Address::Wrap, Address::Clamp] {
            for mode in [
                Mode::Trilinear,
                Mode::BilinearNearestLevel,
                Mode::Nearest,
                Mode::NearestTexelLinearLevel,
            ] {
                let mut single = Sampler::new(p, address);
                let want: Vec<Texel> = hits
                    .iter()
                    .map(|&(u, v, lod)| single.sample(u, v, lod, mode))
                    .collect();
                let mut batch = Sampler::new(p, address);
                let mut out = vec![7; hits.len() + 3];
                assert_eq!(batch.sample_batch(&hits, mode, &mut out), hits.len());
                assert_eq!(&out[..hits.len()], &want[..], "{address:?} {mode:?}");
                assert_eq!(&out[hits.len()..], &[7; 3]);
                assert_eq!(batch.stats(), single.stats(), "{address:?} {mode:?}");
                // Shorter output: only that many hits, counted as such.
                let mut short = Sampler::new(TexelCache::<_, 4, 2>::new(p), address);
                let mut out = [0; 10];
                assert_eq!(short.sample_batch(&hits, mode, &mut out), 10);
                assert_eq!(&out[..], &want[..10]);
                let mut ten = Sampler::new(p, address);
                for &(u, v, lod) in &hits[..10] {
                    ten.sample(u, v, lod, mode);
                }
                assert_eq!(short.stats(), ten.stats());
            }
        }
    }

    /// A source whose texel slice is shorter than a level (which a
    /// `Pyramid` rules out) falls back to the generic path for that level
    /// and gives the same results as reading through `footprint`.
    #[test]
    fn short_texel_slice_falls_back_to_generic_path() {
        struct Short<'a>(Pyramid<'a>, usize);
        impl TexelSource for Short<'_> {
            fn geometry(&self) -> Geometry {
                self.0.geometry()
            }
            fn texel(&mut self, level: u8, x: u32, y: u32) -> Texel {
                self.0.texel(level, x, y)
            }
            fn texel_slice(&self) -> Option<&[Texel]> {
                self.0.texel_slice().map(|t| &t[..self.1])
            }
        }
        let g = Geometry::new(8, 4, 3).unwrap();
        let buf = hashed_pyramid(&g, 0);
        let p = Pyramid::new(g, &buf).unwrap();
        let mut reference = Sampler::new(p, Address::Wrap);
        // Level 0 whole, level 1 cut short, level 2 missing.
        for len in [0, 20, 33, g.len()] {
            let mut short = Sampler::new(Short(p, len), Address::Wrap);
            for i in 0..if cfg!(miri) { 40 } else { 200u32 } {
                let u = TexCoord::from_bits(i64::from(i.wrapping_mul(0x2F6B_1E3D)));
                let v = TexCoord::from_bits(i64::from(i.wrapping_mul(0x61C8_8647)) << 2);
                let lod = Lod::from_bits((i * 7 % 700) as i16);
                for mode in [Mode::Trilinear, Mode::BilinearNearestLevel] {
                    assert_eq!(
                        short.sample(u, v, lod, mode),
                        reference.sample(u, v, lod, mode)
                    );
                }
            }
        }
    }

    /// The power-of-two wrap path (addresses computed by the sampler) and
    /// the generic path through a cache (`TexelSource::footprint`, no
    /// texel slice) give the same texels for every mode.
    #[test]
    fn pow2_wrap_path_equals_generic_path() {
        use crate::cache::TexelCache;
        for (w, h, levels) in [
            (32u32, 32u32, 6u8),
            (64, 4, 7),
            (1, 16, 5),
            (8, 1, 2),
            (1, 1, 1),
        ] {
            let g = Geometry::new(w, h, levels).unwrap();
            let buf = hashed_pyramid(&g, 0x5A5A_1234);
            let p = Pyramid::new(g, &buf).unwrap();
            let mut fast = Sampler::new(p, Address::Wrap);
            assert_ne!(fast.pow2_wrap[0], Pow2Level::OFF);
            let mut generic = Sampler::new(TexelCache::<_, 4, 2>::new(p), Address::Wrap);
            let mut x = 12345u64;
            for _ in 0..if cfg!(miri) { 20 } else { 3000 } {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                let u = TexCoord::from_bits((x as i64) >> (x % 29));
                let v = TexCoord::from_bits(((x >> 3) as i64).wrapping_mul(7) >> (x % 31));
                let lod = Lod::from_bits(((x >> 40) % 2400) as i16 - 200);
                for mode in [
                    Mode::Trilinear,
                    Mode::BilinearNearestLevel,
                    Mode::Nearest,
                    Mode::NearestTexelLinearLevel,
                ] {
                    assert_eq!(
                        fast.sample(u, v, lod, mode),
                        generic.sample(u, v, lod, mode),
                        "{w}x{h} {mode:?} {u} {v} {lod}"
                    );
                }
            }
            assert_eq!(fast.stats(), generic.stats());
        }
        // Non-power-of-two sides or clamp: no table.
        let g = Geometry::new(6, 4, 2).unwrap();
        let buf = vec![0; g.len()];
        assert_eq!(
            Sampler::new(Pyramid::new(g, &buf).unwrap(), Address::Wrap).pow2_wrap,
            [Pow2Level::OFF; 17]
        );
        let g = Geometry::new(8, 4, 2).unwrap();
        let buf = vec![0; g.len()];
        assert_eq!(
            Sampler::new(Pyramid::new(g, &buf).unwrap(), Address::Clamp).pow2_wrap,
            [Pow2Level::OFF; 17]
        );
    }
}
