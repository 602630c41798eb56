//! The sampler: one type for every texel source, address mode, colour
//! space, filter mode and precision tier, specialised at compile time by
//! its key [`Cfg`].
//!
//! * **Addressing** ([`crate::texture::address`]): per axis, reduced
//!   exactly on the fixed-point bits, then scaled by the level size:
//!   nearest texel `i = floor(u·w)`, bilinear `x = u·w − ½` rounded to the
//!   kernel's weight step, `i₀ = floor(x)`, `i₁ = i₀ + 1`, each index
//!   mapped by the axis's mode. Power-of-two wrapped axes use one multiply
//!   for index and weight; power-of-two textures in memory are read with
//!   one bounds check per level.
//! * **Levels**: the lod (I8F8) goes through the [`SamplerState`]'s
//!   window, `clamp(lod + bias, min_lod, max_lod)`, then to the stored
//!   levels `[0, levels − 1]` (both folded into one `[lo, hi]` clamp at
//!   set-up). Nearest-level modes use level `floor(lod + ½)`; linear-level
//!   modes `floor(lod)` and the next with weight `frac(lod)` (8 bits,
//!   exact). When that weight is 0 only one level is read and the avoided
//!   reads are counted in [`FetchStats::skipped`].
//! * **Kernel** ([`crate::texture::kernel`]): chosen by the key's colour
//!   space and tier; the sampler hands it addressed footprints.
//!
//! Everything a key does not name costs nothing: without a border axis
//! there is no border select, without sRGB no decode table, an RGBA8
//! pyramid has no texel decode.
//!
//! # Precision for large coordinates
//!
//! [`TexCoord`] has 32 fractional bits at every magnitude and covers
//! `|u| < 2³¹`; wrapping takes the fractional part of the bits exactly, so
//! the firmware path is exact for every representable coordinate. Precision
//! is lost only where floats come in: an `f64` coordinate `|u| ≥ 2²¹` is
//! itself quantized more coarsely than 2⁻³². [`Sampler::sample_f64`]
//! reduces wrapped coordinates in f64 (exactly) before converting, so it
//! accepts any finite value; [`tex_coord_from_f64`] rejects values outside
//! the [`TexCoord`] range.

use core::fmt;
use core::marker::PhantomData;

use crate::texture::address::{AddressMode, AnyAxis, Axis, ClampToEdge, Wrap};
use crate::texture::kernel::{Kernel, Linear, Rounding};
use crate::texture::storage::level::{LevelView, ViewFormat, wrap_constant};
use crate::texture::storage::mip::{Geometry, MAX_LEVELS, Texel, TexelSource};
use crate::texture::{FetchStats, FilterError, Mode, Stats, tex_coord_from_f64};
use crate::units::{Accurate, Lod, Precision, TexCoord};

pub mod aniso;
pub mod dynamic;
pub mod state;
pub mod stochastic;

pub use state::{SamplerDesc, SamplerState, SrgbOutput};

/// What a [`Sampler`] is specialised for (implemented by [`Cfg`]).
pub trait Key: 'static {
    /// Address mode of `u`.
    type U: Axis;
    /// Address mode of `v`.
    type V: Axis;
    /// The filter kernel (colour space and precision tier).
    type Kernel: Kernel;
    /// The fetch statistics ([`FetchStats`] or [`NoStats`](crate::texture::NoStats)).
    type Stats: Stats;
}

/// A sampler key: address mode of `u` ([`Wrap`],
/// [`Mirror`](crate::texture::address::Mirror),
/// [`ClampToEdge`],
/// [`MirrorOnce`](crate::texture::address::MirrorOnce),
/// [`ClampToBorder`](crate::texture::address::ClampToBorder) or
/// [`AnyAxis`]), of `v` (default: as `u`), colour space `C`
/// ([`Linear`], [`Srgb`](crate::texture::kernel::Srgb),
/// [`SrgbToLinear`](crate::texture::kernel::SrgbToLinear)) and precision
/// tier `P` ([`Accurate`], [`Fast`](crate::units::Fast)) and
/// what it counts, `N` ([`FetchStats`], the default, or [`NoStats`](crate::texture::NoStats)).
/// `Cfg` alone is wrap, linear, ACCURATE, counted.
///
/// # Example
/// ```
/// use raymip::texture::address::ClampToEdge;
/// use raymip::{Cfg, Geometry, Lod, Mode, Pyramid, Sampler, TexCoord};
/// // A 2×1 texture 5, 9; u = 1.75 lies past the right edge.
/// let texels = [5u32, 9];
/// let pyramid = Pyramid::new(Geometry::new(2, 1, 1)?, &texels)?;
/// let (u, v) = (TexCoord::from_num(1.75), TexCoord::from_num(0.5));
/// // Clamp-to-edge in u and v (the key is a type: no mode test per sample).
/// let mut clamp = Sampler::<_, Cfg<ClampToEdge>>::new(pyramid);
/// assert_eq!(clamp.sample(u, v, Lod::ZERO, Mode::Nearest), 9); // last texel
/// // The default key `Cfg` wraps: 1.75 ≡ 0.75, texel floor(0.75 · 2) = 1.
/// let mut wrap = Sampler::<_, Cfg>::new(pyramid);
/// assert_eq!(wrap.sample(u, v, Lod::ZERO, Mode::Nearest), 9);
/// let u = TexCoord::from_num(1.25); // wrap: 0.25 → texel 0; clamp: texel 1
/// assert_eq!(wrap.sample(u, v, Lod::ZERO, Mode::Nearest), 5);
/// assert_eq!(clamp.sample(u, v, Lod::ZERO, Mode::Nearest), 9);
/// # Ok::<(), raymip::MipError>(())
/// ```
pub struct Cfg<U = Wrap, V = U, C = Linear, P = Accurate, N = FetchStats>(
    PhantomData<KeyParts<U, V, C, P, N>>,
);

/// The parts of a [`Cfg`] (a `fn` pointer type: no auto-trait or drop
/// obligations on them).
type KeyParts<U, V, C, P, N> = fn() -> (U, V, C, P, N);

impl<U, V, C, P, N> fmt::Debug for Cfg<U, V, C, P, N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("Cfg")
    }
}

impl<U: Axis, V: Axis, C: 'static, P: 'static, N: Stats> Key for Cfg<U, V, C, P, N>
where
    (C, P): Kernel,
{
    type U = U;
    type V = V;
    type Kernel = (C, P);
    type Stats = N;
}

/// The kernel of key `K`.
type Kern<K> = <K as Key>::Kernel;
/// The lanes of key `K`'s kernel.
type Lanes<K> = <Kern<K> as Kernel>::Lanes;

/// Why a [`SamplerState`] does not fit a sampler's key.
///
/// # Example
/// ```
/// use raymip::texture::SamplerDesc;
/// use raymip::texture::address::{AnyAxis, Wrap};
/// use raymip::texture::sampler::SamplerError;
/// use raymip::{AddressMode, Cfg, Geometry, Pyramid, Sampler, SamplerState};
/// let texels = [0u32; 1];
/// let pyramid = Pyramid::new(Geometry::new(1, 1, 1)?, &texels)?;
/// let desc = SamplerDesc { address_v: AddressMode::ClampToEdge, ..SamplerDesc::default() };
/// let state = SamplerState::new(desc)?;
/// // A key compiled for wrap on both axes cannot take clamp on v ...
/// let err = Sampler::<_, Cfg<Wrap>>::with_state(pyramid, state).unwrap_err();
/// assert_eq!(err, SamplerError::AddressV(AddressMode::ClampToEdge));
/// assert_eq!(err.to_string(), "address mode ClampToEdge of v is not the sampler key's");
/// // ... a key with run-time address modes can.
/// assert!(Sampler::<_, Cfg<AnyAxis>>::with_state(pyramid, state).is_ok());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SamplerError {
    /// The state's address mode of `u` is not the key's.
    AddressU(AddressMode),
    /// The state's address mode of `v` is not the key's.
    AddressV(AddressMode),
}

impl fmt::Display for SamplerError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::AddressU(m) => write!(f, "address mode {m:?} of u is not the sampler key's"),
            Self::AddressV(m) => write!(f, "address mode {m:?} of v is not the sampler key's"),
        }
    }
}

impl core::error::Error for SamplerError {}

/// The addressing constants of every level index `0 ..= 16` of a
/// power-of-two geometry, per axis `[u, v]`: the wrap constants
/// [`wrap_constant`]`(k, bits)` for the kernel's weight width, and the
/// shifts `s = 31 − k` of the sides `n = 2^k ≤ 2¹⁵` (the mask is
/// `n − 1 = (2³¹ − 1) >> s`): the arguments of `AddressMode::pow2_taps`.
/// The generic path's table: the direct path reads the same constants
/// from the level views (`LevelView::wrap_constants`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct LevelTable {
    c: [[u32; 2]; MAX_LEVELS as usize + 1],
    s: [[u8; 2]; MAX_LEVELS as usize + 1],
}

impl LevelTable {
    /// The masks `n − 1` of both axes of level `level ≤ 16`.
    #[inline(always)]
    fn masks(&self, level: usize) -> [u32; 2] {
        self.s[level].map(|s| i32::MAX as u32 >> (s & 31))
    }
}

/// The [`LevelTable`] of `g` (levels past the top repeat it, as
/// [`Geometry::level_size`] clamps them) when both sides are powers of two
/// (then every level's are), else `None`.
fn level_table(g: &Geometry, bits: u32) -> Option<LevelTable> {
    if !(g.width().is_power_of_two() && g.height().is_power_of_two()) {
        return None;
    }
    let mut t = LevelTable::default();
    for ((k, c), s) in (0u8..).zip(t.c.iter_mut()).zip(t.s.iter_mut()) {
        let (w, h) = g.level_size(k);
        let n = [w, h];
        *c = n.map(|n| wrap_constant(n.trailing_zeros(), bits));
        *s = n.map(|n| n.leading_zeros() as u8);
    }
    Some(t)
}

/// The lod window of a [`SamplerState`] on `levels` stored levels, in I8F8
/// bits: `clamp(clamp(λ + bias, min, max), 0, top) = clamp(λ + bias, lo, hi)`
/// with `lo = clamp(min, 0, top)`, `hi = clamp(max, 0, top)` (clamps
/// compose so for `min ≤ max`), and `λ + bias` needs no saturation in
/// `i32`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct LodWindow {
    bias: i32,
    lo: i32,
    hi: i32,
}

impl LodWindow {
    fn new(state: &SamplerState, geometry: &Geometry) -> Self {
        let top = i32::from(geometry.top_level()) << 8;
        let d = state.desc();
        let clamp = |x: Lod| i32::from(x.to_bits()).clamp(0, top);
        Self {
            bias: i32::from(d.lod_bias.to_bits()),
            lo: clamp(d.min_lod),
            hi: clamp(d.max_lod),
        }
    }

    /// The window applied to `lod`: I8F8 bits in `[0, top·256] ⊂ [0, 3840]`.
    #[inline(always)]
    fn apply(&self, lod: Lod) -> u32 {
        // `max`/`min`, not `clamp`: no panic branch. `0 ≤ lo ≤ hi` by
        // set-up, so the result is non-negative and the cast exact.
        (i32::from(lod.to_bits()) + self.bias)
            .max(self.lo)
            .min(self.hi) as u32
    }
}

/// Samples a [`TexelSource`] with the key `K` (module docs).
///
/// # Example
/// ```
/// use raymip::texture::address::ClampToEdge;
/// use raymip::{Cfg, Geometry, Lod, Mode, Pyramid, Sampler, TexCoord};
/// let texels = [0xFF00_0000u32, 0xFFFF_FFFF, 0xFFFF_FFFF, 0xFF00_0000]; // 2×2, one level
/// let pyramid = Pyramid::new(Geometry::new(2, 2, 1)?, &texels)?;
/// // Specialised at compile time: wrap, linear, ACCURATE.
/// let mut wrap = Sampler::wrap(pyramid);
/// let (u, v) = (TexCoord::from_num(0.25), TexCoord::from_num(0.25)); // texel (0, 0)'s centre
/// assert_eq!(wrap.sample(u, v, Lod::ZERO, Mode::BilinearNearestLevel), 0xFF00_0000);
/// // The same through a key naming the address mode per axis.
/// let mut clamp: Sampler<_, Cfg<ClampToEdge>> = Sampler::new(pyramid);
/// let left = TexCoord::from_num(-0.5); // outside [0, 1): the edge texel
/// assert_eq!(clamp.sample(left, v, Lod::ZERO, Mode::Nearest), 0xFF00_0000);
/// // Wrapped, u = −0.5 is u = 0.5: texel (1, 0).
/// assert_eq!(wrap.sample(left, v, Lod::ZERO, Mode::Nearest), 0xFFFF_FFFF);
/// # Ok::<(), raymip::MipError>(())
/// ```
// In declaration order (`repr(C)`): the per-call fields first, within
// the reach of the Cortex-M4's `ldrd` offsets (1020 bytes) from the
// sampler's address, whatever the size of the source (a power-of-two
// source's level views are 1088 bytes).
#[repr(C)]
pub struct Sampler<S: TexelSource, K: Key = Cfg> {
    lod: LodWindow,
    /// The kernel's rounding terms (a field, so that each filter chain
    /// starts from a register: [`Rounding`]).
    rounding: Rounding,
    /// The border colour as the kernel's lanes and as a nearest result.
    border: Lanes<K>,
    border_nearest: Texel,
    stats: K::Stats,
    axes: (K::U, K::V),
    pow2: bool,
    state: SamplerState,
    /// [`level_table`] for the kernel's weight bits (entry 16 repeats the
    /// top level so that `lower + 1` needs no check); all zero, and
    /// `pow2` false, for other geometries.
    levels: LevelTable,
    source: S,
    /// Feature `cfu` on riscv32: the co-processor's texture unit with this
    /// sampler's descriptor block ([`texture_unit_block`](Self::texture_unit_block)
    /// for the unit's RAM), or none.
    #[cfg(all(feature = "cfu", target_arch = "riscv32"))]
    unit: crate::coproc::cfu::TextureUnit,
}

impl<S: TexelSource + fmt::Debug, K: Key> fmt::Debug for Sampler<S, K> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Sampler")
            .field("source", &self.source)
            .field("address", &self.address())
            .field("tier", &Kern::<K>::TIER)
            .field("state", &self.state)
            .field("stats", &self.stats)
            .finish_non_exhaustive()
    }
}

impl<S: TexelSource> Sampler<S, Cfg<Wrap>> {
    /// A wrapping, linear, ACCURATE sampler over `source` with the default
    /// state (no bias, no clamp).
    pub fn wrap(source: S) -> Self {
        Self::new(source)
    }
}

impl<S: TexelSource> Sampler<S, Cfg<ClampToEdge>> {
    /// A clamp-to-edge, linear, ACCURATE sampler over `source` with the
    /// default state (no bias, no clamp).
    pub fn clamp(source: S) -> Self {
        Self::new(source)
    }
}

impl<S: TexelSource> Sampler<S, Cfg<AnyAxis>> {
    /// A linear, ACCURATE sampler with address mode `mode` on both axes
    /// chosen at run time (matched once per axis and level, not per
    /// texel) and the default state.
    pub fn with_address(source: S, mode: AddressMode) -> Self {
        let desc = SamplerDesc {
            address_u: mode,
            address_v: mode,
            ..SamplerDesc::default()
        };
        let state = SamplerState::new(desc).unwrap_or_default();
        Self::build(source, state, (AnyAxis(mode), AnyAxis(mode)))
    }
}

impl<S: TexelSource, K: Key> Sampler<S, K> {
    /// A sampler over `source` with the default state for the key (its
    /// address modes; [`AnyAxis`] axes wrap). Never fails.
    pub fn new(source: S) -> Self {
        let u = K::U::default();
        let v = K::V::default();
        let desc = SamplerDesc {
            address_u: u.mode(),
            address_v: v.mode(),
            ..SamplerDesc::default()
        };
        let state = SamplerState::new(desc).unwrap_or_default();
        Self::build(source, state, (u, v))
    }

    /// A sampler over `source` with `state` (lod bias and clamps, border
    /// colour, anisotropy; its address modes must be the key's unless the
    /// key's axis is [`AnyAxis`]).
    ///
    /// # Errors
    /// [`SamplerError`] naming the axis whose mode the key cannot take.
    pub fn with_state(source: S, state: SamplerState) -> Result<Self, SamplerError> {
        let [mu, mv] = state.address();
        let u = K::U::from_mode(mu).ok_or(SamplerError::AddressU(mu))?;
        let v = K::V::from_mode(mv).ok_or(SamplerError::AddressV(mv))?;
        Ok(Self::build(source, state, (u, v)))
    }

    fn build(source: S, state: SamplerState, axes: (K::U, K::V)) -> Self {
        let geometry = source.geometry();
        #[cfg_attr(not(all(feature = "cfu", target_arch = "riscv32")), expect(unused_mut))]
        let mut s = Self {
            levels: level_table(&geometry, Kern::<K>::WEIGHT_BITS).unwrap_or_default(),
            pow2: level_table(&geometry, Kern::<K>::WEIGHT_BITS).is_some(),
            lod: LodWindow::new(&state, &geometry),
            border: Kern::<K>::load_border(state.border()),
            border_nearest: Kern::<K>::border_nearest(state.border()),
            source,
            state,
            axes,
            stats: K::Stats::default(),
            rounding: Rounding::new(),
            #[cfg(all(feature = "cfu", target_arch = "riscv32"))]
            unit: crate::coproc::cfu::TextureUnit::new(None),
        };
        #[cfg(all(feature = "cfu", target_arch = "riscv32"))]
        {
            s.unit = crate::coproc::cfu::TextureUnit::new(
                s.texture_unit_block(crate::coproc::cfu::ram()),
            );
        }
        s
    }

    /// The descriptor block of this sampler for the CFU co-processor's
    /// texture unit reading the `ram.1` bytes at address `ram.0`
    /// ([`crate::texture::coproc::descriptor_block`] of the source's level views,
    /// the lod window and the address modes), `None` when the unit cannot
    /// sample for it: a kernel other than the ACCURATE linear one, a source
    /// without direct power-of-two level views, the border colour, or
    /// texels outside that RAM. With feature `cfu` on riscv32 the sampler
    /// keeps the block for the unit's RAM and its trilinear and bilinear
    /// samples go through the unit (the same bits).
    #[must_use]
    pub fn texture_unit_block(
        &self,
        ram: (usize, usize),
    ) -> Option<[u32; crate::coproc::BLOCK_WORDS]> {
        if !Kern::<K>::COPROC_FOOTPRINT {
            return None;
        }
        crate::texture::coproc::descriptor_block(
            self.source.levels()?,
            self.lod.bias,
            (self.lod.lo, self.lod.hi),
            (self.axes.0.mode(), self.axes.1.mode()),
            ram,
        )
    }

    /// Feature `cfu` on riscv32: the trilinear (else bilinear) sample
    /// through the co-processor's texture unit, `None` when the sampler has
    /// no descriptor block or the unit's RAM does not hold it.
    #[cfg(all(feature = "cfu", target_arch = "riscv32"))]
    #[inline(always)]
    fn unit_sample(&self, u: TexCoord, v: TexCoord, lod: Lod, trilinear: bool) -> Option<Texel> {
        use crate::coproc::cfu;
        use crate::texture::coproc::coord_i4f28;
        if !Kern::<K>::COPROC_FOOTPRINT || !self.unit.select(lod) {
            return None;
        }
        let (mu, mv) = (self.axes.0.mode(), self.axes.1.mode());
        let (u, v) = (coord_i4f28(mu, u), coord_i4f28(mv, v));
        Some(if trilinear {
            cfu::trilinear(u, v)
        } else {
            cfu::bilinear(u, v)
        })
    }

    /// Filtered texel at `(u, v)` and level of detail `lod` (through the
    /// state's lod window) with filter `mode`. Never panics. Dispatches to
    /// [`sample_trilinear`](Self::sample_trilinear),
    /// [`sample_bilinear`](Self::sample_bilinear),
    /// [`sample_nearest`](Self::sample_nearest) and
    /// [`sample_nearest_linear_level`](Self::sample_nearest_linear_level)
    /// (always inlined, so a constant `mode` costs no dispatch).
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

    /// The nearest level `floor(lod + ½)` of windowed lod bits (at most
    /// `top·256`, so the result is at most the top level).
    #[inline(always)]
    fn nearest_level(bits: u32) -> u8 {
        ((bits + 0x80) >> 8) as u8
    }

    /// [`Mode::Trilinear`]: bilinear in levels `floor(lod)` and
    /// `floor(lod) + 1`, blended by `frac(lod)` (one level when the
    /// fraction is 0). Feature `trilinear`.
    #[cfg(feature = "trilinear")]
    #[inline(always)]
    pub fn sample_trilinear(&mut self, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
        self.trilinear_counted(u, v, lod, self.rounding, |s, one_level| {
            if one_level {
                s.count(4, 4);
            } else {
                s.count(8, 0);
            }
        })
    }

    /// [`sample_trilinear`](Self::sample_trilinear) with the fetch counting
    /// left to `count(stats, one_level)`, called once: `one_level` when the
    /// blend weight is 0 (one level read, 4 texel reads skipped), else 8
    /// texels are read. (Called once the lod is windowed, before either
    /// level is addressed: a single call's counter update then costs the
    /// add and its branch on the Cortex-M4, with no register held across
    /// the levels for it; the batch counts once per batch.) `k`:
    /// the rounding terms (the sampler's field for a single call, the
    /// constants in a batch: [`sample_batch`](Self::sample_batch)).
    #[cfg(feature = "trilinear")]
    #[inline(always)]
    fn trilinear_counted(
        &mut self,
        u: TexCoord,
        v: TexCoord,
        lod: Lod,
        k: Rounding,
        mut count: impl FnMut(&mut K::Stats, bool),
    ) -> Texel {
        #[cfg(all(feature = "cfu", target_arch = "riscv32"))]
        if let Some(t) = self.unit_sample(u, v, lod, true) {
            // The unit reads one level when the fraction is 0.
            count(&mut self.stats, self.lod.apply(lod) & 0xFF == 0);
            return t;
        }
        let bits = self.lod.apply(lod);
        // `bits ≤ 3840`: the mask changes nothing and tells the compiler
        // that `lower + 1 ≤ 16` indexes the level table without a check,
        // next to `lower`'s entry (one address for both levels).
        let lower = (bits >> 8) as usize & 15;
        let t = bits & 0xFF;
        // Counted first, while the registers are free: the counters'
        // address and update then share no live range with the levels'
        // addressing and channels.
        count(&mut self.stats, t == 0);
        let a = self.level_value(u, v, lower, k);
        // Level `a` enters the blend before the branch: its own values
        // are dead before the second level's footprint is read.
        let started = Kern::<K>::start_blend(a, t, k);
        if t == 0 {
            Kern::<K>::finish_one(started)
        } else {
            let b = self.level_value(u, v, lower + 1, k);
            Kern::<K>::finish_blend(started, b, t, k)
        }
    }

    /// [`Mode::BilinearNearestLevel`]: bilinear in level `floor(lod + ½)`.
    #[inline(always)]
    pub fn sample_bilinear(&mut self, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
        self.stats.count(4, 0);
        self.bilinear_uncounted::<true>(u, v, lod, self.rounding)
    }

    /// [`sample_bilinear`](Self::sample_bilinear) without the fetch counter,
    /// with the rounding terms `k` (as for
    /// [`trilinear_counted`](Self::trilinear_counted)); `ALONE`: a call
    /// alone (the kernel's [`Kernel::bilinear_texel_alone`]), else one
    /// iteration of a batch loop (the same texel).
    #[inline(always)]
    fn bilinear_uncounted<const ALONE: bool>(
        &mut self,
        u: TexCoord,
        v: TexCoord,
        lod: Lod,
        k: Rounding,
    ) -> Texel {
        #[cfg(all(feature = "cfu", target_arch = "riscv32"))]
        if let Some(t) = self.unit_sample(u, v, lod, false) {
            return t;
        }
        let level = usize::from(Self::nearest_level(self.lod.apply(lod))) & 15;
        #[cfg(all(feature = "cfu", target_arch = "riscv32"))]
        if let Some(a) = self.coproc_level(u, v, level) {
            return Kern::<K>::round_level(a);
        }
        let (t, fx, fy) = self.footprint(u, v, level);
        if ALONE {
            Kern::<K>::bilinear_texel_alone(t, fx, fy, k)
        } else {
            Kern::<K>::bilinear_texel(t, fx, fy, k)
        }
    }

    /// [`Mode::Nearest`]: nearest texel of level `floor(lod + ½)`.
    #[inline]
    pub fn sample_nearest(&mut self, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
        let level = Self::nearest_level(self.lod.apply(lod));
        let (t, border) = self.nearest(u, v, level);
        if border {
            self.border_nearest
        } else {
            Kern::<K>::nearest(t)
        }
    }

    /// [`Mode::NearestTexelLinearLevel`]: nearest texel in levels
    /// `floor(lod)` and `floor(lod) + 1`, blended by `frac(lod)`. Feature
    /// `trilinear`.
    #[cfg(feature = "trilinear")]
    #[inline]
    pub fn sample_nearest_linear_level(&mut self, u: TexCoord, v: TexCoord, lod: Lod) -> Texel {
        let bits = self.lod.apply(lod);
        let lower = (bits >> 8) as u8;
        let t = bits & 0xFF;
        let (a, a_border) = self.nearest(u, v, lower);
        if t == 0 {
            self.stats.count(0, 1);
            if a_border {
                self.border_nearest
            } else {
                Kern::<K>::nearest(a)
            }
        } else {
            let (b, b_border) = self.nearest(u, v, lower + 1);
            let la = self.lanes(a, a_border);
            let lb = self.lanes(b, b_border);
            Kern::<K>::blend_nearest(la, lb, t)
        }
    }

    /// A texel as lanes, or the border colour's.
    #[cfg(feature = "trilinear")]
    #[inline(always)]
    fn lanes(&self, t: Texel, border: bool) -> Lanes<K> {
        if border {
            self.border
        } else {
            Kern::<K>::load(t)
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
        // The filtered modes take the rounding terms as constants, not the
        // sampler's field: a loop would keep the field's values in
        // registers across iterations (on the Cortex-M4, spilled with the
        // loop's pointers), while constants are rebuilt where a chain uses
        // them. The values are the same (`Rounding::new`).
        let k = Rounding::new();
        match mode {
            // The two filtered modes count once per batch (the same totals
            // as per call), keeping the counters out of the loop.
            #[cfg(feature = "trilinear")]
            Mode::Trilinear => {
                let mut one_level = 0usize;
                for (o, &(u, v, lod)) in out.iter_mut().zip(hits) {
                    *o = self.trilinear_counted(u, v, lod, k, |_, one| {
                        one_level += usize::from(one);
                    });
                }
                let skipped = one_level as u64 * 4;
                self.stats.count(2 * texels - skipped, skipped);
            }
            Mode::BilinearNearestLevel => {
                for (o, &(u, v, lod)) in out.iter_mut().zip(hits) {
                    *o = self.bilinear_uncounted::<false>(u, v, lod, k);
                }
                self.stats.count(texels, 0);
            }
            Mode::Nearest => each!(sample_nearest),
            #[cfg(feature = "trilinear")]
            Mode::NearestTexelLinearLevel => each!(sample_nearest_linear_level),
        }
        n
    }

    /// [`sample`](Self::sample) with float inputs: a set-up/host
    /// convenience, not for the per-hit path (it uses floats). Coordinates
    /// are reduced in f64 first as the axis's mode reduces them (exact), so
    /// any finite value works. `lod` is rounded to 1/256 and goes through
    /// the lod window like [`sample`](Self::sample).
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
        let u = tex_coord_from_f64(reduce_f64(self.axes.0.mode(), u))?;
        let v = tex_coord_from_f64(reduce_f64(self.axes.1.mode(), v))?;
        let lod = Lod::saturating_from_num(lod);
        Ok(self.sample(u, v, lod, mode))
    }

    /// The kernel's level value of the footprint at `level` (`≤ 16`):
    /// through the co-processor's addressing where it applies
    /// ([`coproc_level`](Self::coproc_level)), else [`footprint`](Self::footprint)
    /// and the kernel, with the rounding terms `k`.
    #[cfg(feature = "trilinear")]
    #[inline(always)]
    fn level_value(
        &mut self,
        u: TexCoord,
        v: TexCoord,
        level: usize,
        k: Rounding,
    ) -> <Kern<K> as Kernel>::Level {
        #[cfg(all(feature = "cfu", target_arch = "riscv32"))]
        if let Some(a) = self.coproc_level(u, v, level) {
            return a;
        }
        let (t, fx, fy) = self.footprint(u, v, level);
        Kern::<K>::level(t, fx, fy, k)
    }

    /// Feature `cfu` on riscv32: the level value at `level` (`≤ 16`) with
    /// the footprint and its weights from the co-processor's addressing
    /// instructions (`texture::storage::level::cfu_footprint`: the same taps and weights as
    /// [`footprint`](Self::footprint)'s direct path, tested bit for bit),
    /// for a kernel that keeps its weights there, addressable axes (no
    /// border colour) and a source with direct level views; `None`
    /// otherwise (decided at compile time but for the source).
    #[cfg(all(feature = "cfu", target_arch = "riscv32"))]
    #[inline(always)]
    fn coproc_level(
        &self,
        u: TexCoord,
        v: TexCoord,
        level: usize,
    ) -> Option<<Kern<K> as Kernel>::Level> {
        use crate::texture::coproc::{addressable, coord_i4f28, level_config};
        use crate::texture::storage::level::cfu_footprint;
        let (mu, mv) = (self.axes.0.mode(), self.axes.1.mode());
        if !Kern::<K>::COPROC_FOOTPRINT || !addressable(mu) || !addressable(mv) {
            return None;
        }
        let l = self.source.levels()?.level(level);
        let modes = level_config(0, 0, mu, mv);
        let t = cfu_footprint(l, modes, coord_i4f28(mu, u), coord_i4f28(mv, v));
        Some(Kern::<K>::coproc_level(t, self.rounding))
    }

    /// The 2×2 footprint at `level` as the kernel's lanes (border taps
    /// replaced by the border colour) and its weights `(fx, fy)` (counted
    /// by the caller). A source with direct level views
    /// ([`TexelSource::levels`]: a power-of-two pyramid in memory;
    /// [`TexelSource::rgb565_levels`]: a power-of-two RGB565 image) is
    /// read with two row pointers and no check
    /// ([`direct_footprint`](Self::direct_footprint)); every other source
    /// through its [`TexelSource::footprint`]. Both give the same texels.
    /// `level ≤ 16` (the callers mask it; the tables have an entry for
    /// 16, a copy of 15, so that `level + 1` needs no check either).
    #[inline(always)]
    fn footprint(&mut self, u: TexCoord, v: TexCoord, level: usize) -> ([Lanes<K>; 4], u32, u32) {
        if let Some(levels) = self.source.levels() {
            return self.direct_footprint(levels.level(level), u, v);
        }
        if let Some(levels) = self.source.rgb565_levels() {
            return self.direct_footprint(levels.level(level), u, v);
        }
        let bits = Kern::<K>::WEIGHT_BITS;
        let (mu, mv) = (self.axes.0.mode(), self.axes.1.mode());
        // Power-of-two geometries address as the direct path does (the
        // level's constants from the table); other sizes by the
        // general taps.
        let (xt, yt) = if self.pow2 {
            let [mx, my] = self.levels.masks(level);
            let [sx, sy] = self.levels.s[level].map(u32::from);
            let [cx, cy] = self.levels.c[level];
            (
                mu.pow2_taps::<false>(u, mx + 1, mx, sx, cx, bits),
                mv.pow2_taps::<false>(v, my + 1, my, sy, cy, bits),
            )
        } else {
            let (w, h) = self.source.geometry().level_size(level as u8);
            (mu.taps(u, w, bits), mv.taps(v, h, bits))
        };
        // The taps are inside the level (`level_size`): no clamp.
        let t = self.source.footprint_in_level(level as u8, xt.i, yt.i);
        let mut lanes = t.map(Kern::<K>::load);
        if (K::U::MAY_BORDER || K::V::MAY_BORDER)
            && (xt.border != [false; 2] || yt.border != [false; 2])
        {
            let out = [
                xt.border[0] | yt.border[0],
                xt.border[1] | yt.border[0],
                xt.border[0] | yt.border[1],
                xt.border[1] | yt.border[1],
            ];
            for (l, o) in lanes.iter_mut().zip(out) {
                if o {
                    *l = self.border;
                }
            }
        }
        (lanes, xt.f, yt.f)
    }

    /// [`footprint`](Self::footprint) through the view `l` of a level (its
    /// sides, masks and wrap constants), its texels expanded to RGBA8 by
    /// the view's format.
    #[inline(always)]
    fn direct_footprint<F: ViewFormat>(
        &self,
        l: &LevelView<'_, F>,
        u: TexCoord,
        v: TexCoord,
    ) -> ([Lanes<K>; 4], u32, u32) {
        let bits = Kern::<K>::WEIGHT_BITS;
        let (mu, mv) = (self.axes.0.mode(), self.axes.1.mode());
        if mu == AddressMode::Wrap && mv == AddressMode::Wrap {
            // Wrapped on both axes: every tap is a texel (no border),
            // addressed by the view without a mask.
            let (t, fx, fy) = l.wrap_footprint(u, v, bits);
            return (t.map(Kern::<K>::load), fx, fy);
        }
        // Decided once per footprint: both axes' taps inside the
        // level are read as they are (two adjacent pairs); otherwise
        // every tap is mapped by its mode, read (the view masks it
        // into the level) and a border tap replaced afterwards (a
        // range test per tap, no branch).
        let [cx, cy] = l.wrap_constants(bits);
        let (x, fx) = mu.pow2_first_tap(u, l.width(), cx, bits);
        let (y, fy) = mv.pow2_first_tap(v, l.height(), cy, bits);
        if let Some(t) = l.inside_footprint(x, y) {
            return (t.map(Kern::<K>::load), fx, fy);
        }
        let xt = mu.pow2_edge_taps::<true>(x, fx, l.width(), l.mask_x(), l.shift_x());
        let yt = mv.pow2_edge_taps::<true>(y, fy, l.height(), l.mask_y(), l.shift_y());
        let mut lanes = l.footprint(xt.i, yt.i).map(Kern::<K>::load);
        if K::U::MAY_BORDER || K::V::MAY_BORDER {
            for (k, l) in lanes.iter_mut().enumerate() {
                if xt.border[k & 1] | yt.border[k >> 1] {
                    *l = self.border;
                }
            }
        }
        (lanes, xt.f, yt.f)
    }

    /// Nearest texel at `level` (counted) and whether it is the border.
    #[inline(always)]
    fn nearest(&mut self, u: TexCoord, v: TexCoord, level: u8) -> (Texel, bool) {
        let (w, h) = self.source.geometry().level_size(level);
        let (x, bx) = self.axes.0.mode().nearest_tap(u, w);
        let (y, by) = self.axes.1.mode().nearest_tap(v, h);
        self.stats.count(1, 0);
        (self.source.texel(level, x, y), bx | by)
    }

    /// The levels a sample with `lod` and `mode` reads: the nearest level
    /// for the nearest-level modes, `floor(lod)` and (when `frac(lod) ≠ 0`)
    /// the next one for the linear-level modes, after the lod window.
    /// The split every sampling path uses.
    #[must_use]
    pub fn levels(&self, lod: Lod, mode: Mode) -> (u8, Option<u8>) {
        let bits = self.lod.apply(lod);
        match mode {
            Mode::BilinearNearestLevel | Mode::Nearest => (Self::nearest_level(bits), None),
            #[cfg(feature = "trilinear")]
            Mode::Trilinear | Mode::NearestTexelLinearLevel => {
                let lower = (bits >> 8) as u8;
                (lower, (bits & 0xFF != 0).then_some(lower + 1))
            }
        }
    }

    /// The address modes of `u` and `v`.
    #[must_use]
    pub fn address(&self) -> [AddressMode; 2] {
        [self.axes.0.mode(), self.axes.1.mode()]
    }

    /// The precision tier of the results.
    #[must_use]
    pub fn precision(&self) -> Precision {
        Kern::<K>::TIER
    }

    /// The sampler state.
    #[must_use]
    pub fn state(&self) -> &SamplerState {
        &self.state
    }

    /// The source's geometry.
    #[must_use]
    pub fn geometry(&self) -> Geometry {
        self.source.geometry()
    }

    /// The texel source.
    #[must_use]
    pub fn source(&self) -> &S {
        &self.source
    }

    /// The texel source, mutable (e.g. to read cache counters). With
    /// feature `cfu` on riscv32 the sampler then drops its texture-unit
    /// block (the source may change): it samples without the unit.
    #[must_use]
    pub fn source_mut(&mut self) -> &mut S {
        #[cfg(all(feature = "cfu", target_arch = "riscv32"))]
        {
            self.unit = crate::coproc::cfu::TextureUnit::new(None);
        }
        &mut self.source
    }

    /// Gives the texel source back.
    #[must_use]
    pub fn into_source(self) -> S {
        self.source
    }
}

impl<S: TexelSource, K: Key<Stats = FetchStats>> Sampler<S, K> {
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
}

/// `x` reduced in f64 as `mode` reduces coordinates (exact: `x − floor(x)`
/// and `x − 2·floor(x/2)` are exact in binary floating point), for
/// [`Sampler::sample_f64`].
fn reduce_f64(mode: AddressMode, x: f64) -> f64 {
    match mode {
        AddressMode::Wrap => x - libm::floor(x),
        AddressMode::Mirror => x - 2.0 * libm::floor(x / 2.0),
        AddressMode::ClampToEdge | AddressMode::ClampToBorder => x.clamp(-1.0, 2.0),
        AddressMode::MirrorOnce => x.clamp(-2.0, 2.0),
    }
}
#[cfg(all(test, feature = "trilinear", feature = "mipgen"))]
mod tests {
    extern crate std;
    use super::*;
    use crate::texture::address::AddressMode;
    use crate::texture::storage::mip::{Pyramid, generate};
    use crate::texture::{FetchStats, FilterError, Mode, tex_coord_from_f64};
    use crate::units::TexCoord;
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

    /// `with_address` puts its mode on both axes of the key and of the
    /// state it reports.
    #[test]
    fn with_address_sets_both_axes() {
        let buf = [0u32; 4];
        let p = Pyramid::new(Geometry::new(2, 2, 1).unwrap(), &buf).unwrap();
        for mode in AddressMode::ALL {
            let s = Sampler::with_address(p, mode);
            assert_eq!(s.address(), [mode; 2]);
            assert_eq!(s.state().address(), [mode; 2]);
        }
    }

    #[test]
    fn centres_return_texels() {
        let g = Geometry::new(4, 2, 3).unwrap();
        let mut buf: Vec<Texel> = (0..g.len() as u32).map(|i| gray((i * 20) as u8)).collect();
        generate(&g, &mut buf).unwrap();
        let p = Pyramid::new(g, &buf).unwrap();
        let mut s = Sampler::wrap(p);
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
        let mut w = Sampler::wrap(p);
        let mut k = Sampler::clamp(p);
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
        let mut s = Sampler::clamp(p);
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

    /// `sample_batch` gives the results and the fetch counters of single
    /// calls for every mode (lods with and without a fraction, so both
    /// trilinear branches and their counting), writes `min(hits, out)`
    /// results and leaves the rest of `out` alone.
    #[test]
    fn batch_equals_single_calls() {
        use crate::texture::storage::cache::TexelCache;
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
        for address in [AddressMode::Wrap, AddressMode::ClampToEdge] {
            for mode in [
                Mode::Trilinear,
                Mode::BilinearNearestLevel,
                Mode::Nearest,
                Mode::NearestTexelLinearLevel,
            ] {
                let mut single = Sampler::with_address(p, address);
                let want: Vec<Texel> = hits
                    .iter()
                    .map(|&(u, v, lod)| single.sample(u, v, lod, mode))
                    .collect();
                let mut batch = Sampler::with_address(p, address);
                let mut out = vec![7; hits.len() + 3];
                assert_eq!(batch.sample_batch(&hits, mode, &mut out), hits.len());
                assert_eq!(&out[..hits.len()], &want[..], "{address:?} {mode:?}");
                assert_eq!(&out[hits.len()..], &[7; 3]);
                assert_eq!(batch.stats(), single.stats(), "{address:?} {mode:?}");
                // Shorter output: only that many hits, counted as such.
                let mut short = Sampler::with_address(TexelCache::<_, 4, 2>::new(p), address);
                let mut out = [0; 10];
                assert_eq!(short.sample_batch(&hits, mode, &mut out), 10);
                assert_eq!(&out[..], &want[..10]);
                let mut ten = Sampler::with_address(p, address);
                for &(u, v, lod) in &hits[..10] {
                    ten.sample(u, v, lod, mode);
                }
                assert_eq!(short.stats(), ten.stats());
            }
        }
    }

    /// The direct path (a power-of-two pyramid's level views: wrap
    /// without masks, mirror by XOR, clamp decided once per axis, border
    /// taps replaced after a range test per tap) and the generic path (`TexelSource::footprint` of the same
    /// pyramid, and of a texel cache) give the same results and counters
    /// for every filter mode, key kind (static axes, run-time axes, mixed),
    /// tier and colour space, on square, long and one-texel-wide
    /// pyramids (full and trimmed).
    #[test]
    fn direct_path_equals_generic_path() {
        use crate::texture::address::{ClampToBorder, Mirror, MirrorOnce};
        use crate::texture::kernel::{Srgb, SrgbToLinear};
        use crate::texture::storage::cache::TexelCache;
        use crate::texture::storage::pow2::Pow2Pyramid;
        use crate::units::Fast;

        /// Samples `n` pseudo-random inputs of every mode through the
        /// direct, generic and cached samplers of key `K`.
        fn check<K: Key<Stats = FetchStats>>(p: Pyramid<'_>, state: SamplerState, n: u32) {
            let d = Pow2Pyramid::new(p).unwrap();
            let mut direct = Sampler::<_, K>::with_state(d, state).unwrap();
            let mut generic = Sampler::<_, K>::with_state(p, state).unwrap();
            let mut cached =
                Sampler::<_, K>::with_state(TexelCache::<_, 4, 2>::new(p), state).unwrap();
            // An image of the same texels (untrimmed pyramids only: an
            // image stores every level).
            let bytes: Vec<u8> = p.texels().iter().flat_map(|t| t.to_le_bytes()).collect();
            let g = p.geometry();
            let mut image = g.is_full().then(|| {
                use crate::texture::storage::format::{Format, TexelFormat};
                use crate::texture::storage::image::Image;
                let i = Image::new(g, Format::linear(TexelFormat::Rgba8), &bytes).unwrap();
                Sampler::<_, K>::with_state(i, state).unwrap()
            });
            let mut x = 12345u64 ^ u64::from(n);
            for _ in 0..n {
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
                    let want = generic.sample(u, v, lod, mode);
                    let g = p.geometry();
                    let what = (g.width(), g.height(), state.address(), mode, u, v, lod);
                    assert_eq!(direct.sample(u, v, lod, mode), want, "{what:?}");
                    assert_eq!(cached.sample(u, v, lod, mode), want, "{what:?}");
                    if let Some(image) = image.as_mut() {
                        assert_eq!(image.sample(u, v, lod, mode), want, "{what:?}");
                    }
                }
            }
            assert_eq!(direct.stats(), generic.stats());
            assert_eq!(cached.stats(), generic.stats());
        }

        let n = if cfg!(miri) { 8 } else { 600 };
        for (w, h, levels, trim) in [
            (32u32, 32u32, 6u8, None),
            (64, 4, 7, None),
            (1, 16, 5, None),
            (8, 1, 2, None),
            (1, 1, 1, None),
            (16, 8, 5, Some((1u8, 3u8))),
        ] {
            let g = Geometry::new(w, h, levels).unwrap();
            let buf = hashed_pyramid(&g, 0x5A5A_1234);
            let mut p = Pyramid::new(g, &buf).unwrap();
            if let Some((first, last)) = trim {
                p = p.trim(first, last).unwrap();
            }
            for (i, mu) in AddressMode::ALL.into_iter().enumerate() {
                let mv = AddressMode::ALL[(i + 2) % 5];
                let state = SamplerState::new(SamplerDesc {
                    address_u: mu,
                    address_v: mv,
                    border: 0x8040_2010,
                    lod_bias: Lod::from_bits(40),
                    ..SamplerDesc::default()
                })
                .unwrap();
                check::<Cfg<AnyAxis>>(p, state, n);
                check::<Cfg<AnyAxis, AnyAxis, Linear, Fast>>(p, state, n);
                check::<Cfg<AnyAxis, AnyAxis, Srgb>>(p, state, n / 4);
                check::<Cfg<AnyAxis, AnyAxis, SrgbToLinear>>(p, state, n / 4);
                let same = SamplerState::new(SamplerDesc {
                    address_v: mu,
                    ..*state.desc()
                })
                .unwrap();
                check::<Cfg<AnyAxis>>(p, same, n / 2);
            }
            let state = |u, v| {
                SamplerState::new(SamplerDesc {
                    address_u: u,
                    address_v: v,
                    border: 0x1234_5678,
                    ..SamplerDesc::default()
                })
                .unwrap()
            };
            use AddressMode as A;
            check::<Cfg<Wrap>>(p, state(A::Wrap, A::Wrap), n);
            check::<Cfg<Wrap, Wrap, Linear, Fast>>(p, state(A::Wrap, A::Wrap), n);
            check::<Cfg<Mirror, ClampToBorder>>(p, state(A::Mirror, A::ClampToBorder), n);
            let mb = state(A::Mirror, A::ClampToBorder);
            check::<Cfg<Mirror, ClampToBorder, Linear, Fast>>(p, mb, n);
            check::<Cfg<ClampToEdge, MirrorOnce>>(p, state(A::ClampToEdge, A::MirrorOnce), n);
            check::<Cfg<Wrap, Mirror>>(p, state(A::Wrap, A::Mirror), n);
        }
        // Sides that are not powers of two have no direct views.
        let g = Geometry::new(6, 4, 2).unwrap();
        let buf = vec![0; g.len()];
        assert!(Pow2Pyramid::new(Pyramid::new(g, &buf).unwrap()).is_err());
    }
}
