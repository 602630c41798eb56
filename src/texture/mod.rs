//! The texture half of the unit: texture storage, addressing, the filter
//! kernels and the one [`Sampler`] over all of them.
//!
//! | stage | module | per sample |
//! |---|---|---|
//! | storage: pyramids, images in any format, BC blocks, the texel cache, sRGB; the levels a scene can select (set-up) | [`storage`] | level offset, texel decode or cache tag compare |
//! | addressing per axis (wrap, mirror, clamp, mirror once, border) | [`address`] | one multiply per axis and level |
//! | filter kernels, one per precision tier | [`kernel`] | 4 or 8 texels, one multiply-accumulate chain |
//! | the sampler (state, filter modes, batches, anisotropy, stochastic filtering) | [`sampler`], [`mode`] | lod window, level choice, footprint, kernel |
//! | co-processor operands and the texture unit's descriptor block (features `pcpi`, `cfu`) | [`coproc`] | – (the same bits in hardware) |
//!
//! # One sampler, specialised at compile time
//!
//! A [`Sampler<S, K>`](Sampler) reads a texel source `S` (a
//! [`Pyramid`] in memory, an [`Image`](storage::image::Image) in a typed
//! pixel format, or a [`TexelCache`](storage::cache::TexelCache) in front
//! of either) with a *key* `K` ([`Cfg<U, V, C, P>`](sampler::Cfg)): the
//! address mode of each axis (`U`, `V`: [`address::Wrap`],
//! [`address::ClampToEdge`], …), the colour space (`C`:
//! [`kernel::Linear`], [`kernel::Srgb`], [`kernel::SrgbToLinear`]) and
//! the precision tier (`P`: [`kernel::Accurate`], the default, or
//! [`kernel::Fast`]). Each is a type, so a configuration that does not use
//! a feature carries none of its instructions: a wrap sampler has no
//! border test, a linear one no sRGB table, an RGBA8 pyramid no texel
//! decode. Lod bias and clamps, the border colour and the anisotropy
//! limit come from a [`SamplerState`] validated once at set-up. The C ABI
//! and the harness's CLI use [`DynSampler`](sampler::dynamic::DynSampler),
//! which picks one specialised sampler from a small table of keys once at
//! set-up, not per texel.
//!
//! # Precision tiers
//!
//! | tier | weights | per channel | bound vs the exact f64 filter |
//! |---|---|---|---|
//! | ACCURATE ([`kernel::Accurate`], default) | 12-bit position, 24-bit corner weights, exact 8-bit level weight | one chain of four multiply-accumulates per texel footprint | [`kernel::accurate::BILERP_MAX_ERROR_LSB`] = 0.5625 LSB (linear); sRGB re-encoded [`kernel::srgb::SRGB_MAX_ERROR_LSB`] = 0.6875 LSB |
//! | FAST ([`kernel::Fast`]) | 8 sub-texel bits (D3D11's minimum), exact 16-bit corner weights (products), exact 8-bit level weight | two channels per 32×32→64-bit multiply-accumulate | [`kernel::fast::FAST_MAX_ERROR_LSB`] = 1.5 LSB (proof in [`kernel::fast`]) |
//!
//! Both tiers give the same bits on every target. ACCURATE RGBA8 results
//! under wrap and clamp-to-edge are pinned bit for bit by recorded hashes
//! (`tests/firmware/sampler_golden.rs`).

use core::fmt;

pub mod address;
pub mod coproc;
pub mod kernel;
pub mod mode;
pub mod sampler;
pub mod storage;

use crate::units::TexCoord;
pub use address::AddressMode;
pub use mode::Mode;
pub use sampler::state::{SamplerDesc, SamplerState};
pub use sampler::{Cfg, Sampler};
pub use storage::mip::{Geometry, Pyramid, Texel, TexelSource};

/// Texel-read counters of a [`Sampler`].
///
/// # Example
/// ```
/// use raymip::texture::FetchStats;
/// use raymip::texture::storage::mip::pyramid_len;
/// use raymip::{Geometry, Lod, Mode, Pyramid, Sampler, TexCoord};
/// let texels = [0xFF80_8080u32; pyramid_len(4, 4, 3)]; // 4×4, 2×2, 1×1
/// let mut sampler = Sampler::wrap(Pyramid::new(Geometry::new(4, 4, 3)?, &texels)?);
/// let c = TexCoord::from_num(0.5);
/// // Trilinear between levels 0 and 1: two bilinear footprints of 4 texels.
/// let _ = sampler.sample(c, c, Lod::from_num(0.5), Mode::Trilinear);
/// assert_eq!(sampler.stats(), FetchStats { fetched: 8, skipped: 0 });
/// // At lod 1 exactly the blend weight of level 2 is 0: its 4 reads are skipped.
/// sampler.reset_stats();
/// let _ = sampler.sample(c, c, Lod::ONE, Mode::Trilinear);
/// assert_eq!(sampler.stats(), FetchStats { fetched: 4, skipped: 4 });
/// // Nearest texel of the nearest level: one read.
/// sampler.reset_stats();
/// let _ = sampler.sample(c, c, Lod::ONE, Mode::Nearest);
/// assert_eq!(sampler.stats().fetched, 1);
/// # Ok::<(), raymip::MipError>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FetchStats {
    /// Texels read from the source (4 per bilinear level, 1 per
    /// nearest-texel level; border texels are not reads).
    pub fetched: u64,
    /// Texel reads avoided because the second level of a linear-level mode
    /// could not change the result (blend weight 0): 4 per skipped
    /// bilinear level, 1 per skipped nearest-texel level.
    pub skipped: u64,
}

/// What a [`Sampler`] counts of its texel reads: the statistics part of
/// its key ([`Cfg`]'s last parameter). [`FetchStats`] (the default)
/// counts every read exactly; [`NoStats`] counts nothing, for a firmware
/// that reads no statistics (each count is then no instruction, where
/// [`FetchStats`] costs a 64-bit add per call). Sealed.
pub trait Stats: sealed::Sealed + Copy + Default + fmt::Debug + Send + Sync + 'static {
    /// Adds `fetched` texel reads and `skipped` avoided ones.
    fn count(&mut self, fetched: u64, skipped: u64);
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::FetchStats {}
    impl Sealed for super::NoStats {}
}

impl Stats for FetchStats {
    #[inline(always)]
    fn count(&mut self, fetched: u64, skipped: u64) {
        self.fetched += fetched;
        self.skipped += skipped;
    }
}

/// No fetch statistics ([`Stats`]): a sampler with this key part has no
/// counters and no `stats()` method.
///
/// # Example
/// ```
/// use raymip::texture::NoStats;
/// use raymip::texture::address::Wrap;
/// use raymip::texture::kernel::Linear;
/// use raymip::units::Accurate;
/// use raymip::{Cfg, Geometry, Lod, Mode, Pyramid, Sampler, TexCoord};
/// let texels = [0xFF80_8080u32; 1];
/// let pyramid = Pyramid::new(Geometry::new(1, 1, 1)?, &texels)?;
/// // The same results as the counting sampler, without the counters.
/// let mut quiet: Sampler<_, Cfg<Wrap, Wrap, Linear, Accurate, NoStats>> = Sampler::new(pyramid);
/// let mut counted = Sampler::wrap(pyramid);
/// let c = TexCoord::from_num(0.5);
/// let mode = Mode::Trilinear;
/// assert_eq!(quiet.sample(c, c, Lod::ZERO, mode), counted.sample(c, c, Lod::ZERO, mode));
/// assert_eq!(counted.stats().fetched, 4);
/// # Ok::<(), raymip::MipError>(())
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NoStats;

impl Stats for NoStats {
    #[inline(always)]
    fn count(&mut self, _fetched: u64, _skipped: u64) {}
}

/// Errors at the float edge of the sampler.
///
/// # Example
/// ```
/// use raymip::texture::{FilterError, tex_coord_from_f64};
/// use raymip::{Geometry, Mode, Pyramid, Sampler, TexCoord};
/// assert_eq!(tex_coord_from_f64(0.25), Ok(TexCoord::from_num(0.25)));
/// let err = tex_coord_from_f64(f64::NAN).unwrap_err();
/// assert_eq!(err, FilterError::NonFinite);
/// assert_eq!(err.to_string(), "texture coordinate or lod is NaN or infinite");
/// // 3·10⁹ ≥ 2³¹: no I32F32 coordinate holds it.
/// let err = tex_coord_from_f64(3e9).unwrap_err();
/// assert_eq!(err, FilterError::OutOfRange);
/// assert_eq!(err.to_string(), "texture coordinate outside [-2^31, 2^31)");
/// // The sampler's float entry point refuses an infinite lod.
/// let texels = [0u32; 1];
/// let mut sampler = Sampler::wrap(Pyramid::new(Geometry::new(1, 1, 1)?, &texels)?);
/// assert_eq!(sampler.sample_f64(0.5, 0.5, f64::INFINITY, Mode::Nearest), Err(FilterError::NonFinite));
/// # Ok::<(), raymip::MipError>(())
/// ```
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

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::string::ToString;

    /// Each counter adds its own argument, call after call.
    #[test]
    fn fetch_stats_add_each_count() {
        let mut s = FetchStats::default();
        s.count(3, 1);
        s.count(2, 5);
        assert_eq!(
            s,
            FetchStats {
                fetched: 5,
                skipped: 6
            }
        );
    }

    /// Finite coordinates inside `[−2³¹, 2³¹)` convert (both ends of the
    /// range exactly), NaN and ±inf are `NonFinite`, finite values outside
    /// are `OutOfRange`; each error has its own message.
    #[test]
    fn float_coordinates_convert_or_fail_by_kind() {
        let edge = 2_147_483_648.0; // 2³¹
        assert_eq!(tex_coord_from_f64(0.25), Ok(TexCoord::from_num(0.25)));
        assert_eq!(tex_coord_from_f64(-1.5), Ok(TexCoord::from_num(-1.5)));
        assert_eq!(tex_coord_from_f64(-edge), Ok(TexCoord::MIN));
        assert_eq!(tex_coord_from_f64(0.0), Ok(TexCoord::ZERO));
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(tex_coord_from_f64(x), Err(FilterError::NonFinite), "{x}");
        }
        for x in [edge, -edge - 1.0, 3e9, f64::MAX] {
            assert_eq!(tex_coord_from_f64(x), Err(FilterError::OutOfRange), "{x}");
        }
        assert_eq!(
            FilterError::NonFinite.to_string(),
            "texture coordinate or lod is NaN or infinite"
        );
        assert_eq!(
            FilterError::OutOfRange.to_string(),
            "texture coordinate outside [-2^31, 2^31)"
        );
    }
}
