//! The run-time-configured sampler for the C ABI and the harness's CLI.
//!
//! A small static table of keys, one of which is picked once at set-up from
//! a [`SamplerState`], a colour space and a [`Precision`]; every sample
//! then runs that key's specialised code (one `match` per call on the
//! stored variant, none per texel).
//!
//! | [`DynKey`] | key | when |
//! |---|---|---|
//! | `WrapAccurate` / `WrapFast` | `Cfg<Wrap, Wrap, Linear, _>` | linear data, wrap on both axes |
//! | `ClampAccurate` / `ClampFast` | `Cfg<ClampToEdge, ClampToEdge, Linear, _>` | linear data, clamp-to-edge on both axes |
//! | `AnyAccurate` / `AnyFast` | `Cfg<AnyAxis, AnyAxis, Linear, _>` | linear data, any other pair of modes |
//! | `Srgb` | `Cfg<AnyAxis, AnyAxis, Srgb>` | sRGB data, results re-encoded (both tiers: the sRGB kernel is one) |
//! | `SrgbToLinear` | `Cfg<AnyAxis, AnyAxis, SrgbToLinear>` | sRGB data, results linear |
//!
//! Results are those of the static sampler with the same key, bit for
//! bit (tested). A firmware that knows its textures names the static
//! [`Sampler`] type instead and links one key's code.

use super::stochastic::StochasticMode;
use super::{Cfg, Sampler, SamplerState, SrgbOutput};
use crate::texture::address::{AddressMode, AnyAxis, ClampToEdge, Wrap};
use crate::texture::kernel::{Linear, Srgb, SrgbToLinear};
use crate::texture::storage::format::ColorSpace;
use crate::texture::storage::mip::{Geometry, Texel, TexelSource};
use crate::texture::{FetchStats, Mode};
use crate::units::{Fast, Footprint, Lod, Precision, TexCoord};

/// Which entry of the key table a [`DynSampler`] runs (module docs).
/// Example: [`DynSampler`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DynKey {
    /// Wrap, linear, ACCURATE.
    WrapAccurate,
    /// Clamp-to-edge, linear, ACCURATE.
    ClampAccurate,
    /// Any modes, linear, ACCURATE.
    AnyAccurate,
    /// Wrap, linear, FAST.
    WrapFast,
    /// Clamp-to-edge, linear, FAST.
    ClampFast,
    /// Any modes, linear, FAST.
    AnyFast,
    /// Any modes, sRGB re-encoded.
    Srgb,
    /// Any modes, sRGB to linear.
    SrgbToLinear,
}

impl DynKey {
    /// The entry for address modes `[u, v]`, colour space `space`, sRGB
    /// result encoding `output` and tier `precision`.
    #[must_use]
    pub fn select(
        address: [AddressMode; 2],
        space: ColorSpace,
        output: SrgbOutput,
        precision: Precision,
    ) -> Self {
        let fast = precision == Precision::Fast;
        match (space, output, address) {
            (ColorSpace::Srgb, SrgbOutput::Encoded, _) => Self::Srgb,
            (ColorSpace::Srgb, SrgbOutput::Linear, _) => Self::SrgbToLinear,
            (_, _, [AddressMode::Wrap, AddressMode::Wrap]) if fast => Self::WrapFast,
            (_, _, [AddressMode::Wrap, AddressMode::Wrap]) => Self::WrapAccurate,
            (_, _, [AddressMode::ClampToEdge, AddressMode::ClampToEdge]) if fast => Self::ClampFast,
            (_, _, [AddressMode::ClampToEdge, AddressMode::ClampToEdge]) => Self::ClampAccurate,
            _ if fast => Self::AnyFast,
            _ => Self::AnyAccurate,
        }
    }
}

/// A sampler whose key is chosen at run time (module docs).
///
/// # Example
/// ```
/// use raymip::units::Precision;
/// use raymip::texture::sampler::SrgbOutput;
/// use raymip::texture::sampler::dynamic::{DynKey, DynSampler};
/// use raymip::texture::storage::format::ColorSpace;
/// use raymip::texture::SamplerDesc;
/// use raymip::{AddressMode, Geometry, Lod, Mode, Pyramid, SamplerState, TexCoord};
/// // Settings read at run time (a texture header, the C ABI).
/// let wrap = [AddressMode::Wrap; 2];
/// let (linear, srgb) = (ColorSpace::Linear, ColorSpace::Srgb);
/// let enc = SrgbOutput::Encoded;
/// assert_eq!(DynKey::select(wrap, linear, enc, Precision::Fast), DynKey::WrapFast);
/// let mixed = [AddressMode::Mirror, AddressMode::Wrap];
/// assert_eq!(DynKey::select(mixed, linear, enc, Precision::Accurate), DynKey::AnyAccurate);
/// // sRGB data has one kernel for both tiers.
/// assert_eq!(DynKey::select(wrap, srgb, enc, Precision::Fast), DynKey::Srgb);
/// // A 2×1 sRGB texture, black then white, sampled midway (weights ½, ½):
/// // ½ linear, re-encoded 255·(1.055·0.5^(1/2.4) − 0.055) = 187.5, or
/// // returned linear, 127.5 (within 0.6875 and 0.5101 LSB).
/// let texels = [0xFF00_0000u32, 0xFFFF_FFFF];
/// let pyramid = Pyramid::new(Geometry::new(2, 1, 1)?, &texels)?;
/// let half = TexCoord::from_num(0.5);
/// let red = |s: &mut DynSampler<_>| f64::from(s.sample(half, half, Lod::ZERO, Mode::BilinearNearestLevel) & 0xFF);
/// let state = SamplerState::new(SamplerDesc::default())?;
/// let mut encoded = DynSampler::new(pyramid, state, srgb, Precision::Accurate);
/// assert_eq!((encoded.key(), encoded.precision()), (DynKey::Srgb, Precision::Accurate));
/// assert!((red(&mut encoded) - 255.0 * (1.055 * 0.5f64.powf(1.0 / 2.4) - 0.055)).abs() <= 0.6875);
/// let state = SamplerState::new(SamplerDesc { srgb_output: SrgbOutput::Linear, ..SamplerDesc::default() })?;
/// let mut to_linear = DynSampler::new(pyramid, state, srgb, Precision::Accurate);
/// assert_eq!(to_linear.key(), DynKey::SrgbToLinear);
/// assert!((red(&mut to_linear) - 127.5).abs() <= 0.5101);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
#[allow(missing_docs, clippy::large_enum_variant)]
pub enum DynSampler<S: TexelSource> {
    WrapAccurate(Sampler<S, Cfg<Wrap>>),
    ClampAccurate(Sampler<S, Cfg<ClampToEdge>>),
    AnyAccurate(Sampler<S, Cfg<AnyAxis>>),
    WrapFast(Sampler<S, Cfg<Wrap, Wrap, Linear, Fast>>),
    ClampFast(Sampler<S, Cfg<ClampToEdge, ClampToEdge, Linear, Fast>>),
    AnyFast(Sampler<S, Cfg<AnyAxis, AnyAxis, Linear, Fast>>),
    Srgb(Sampler<S, Cfg<AnyAxis, AnyAxis, Srgb>>),
    SrgbToLinear(Sampler<S, Cfg<AnyAxis, AnyAxis, SrgbToLinear>>),
}

/// `$s` bound to the variant's sampler in every arm.
macro_rules! each {
    ($self:expr, $s:ident => $e:expr) => {
        match $self {
            DynSampler::WrapAccurate($s) => $e,
            DynSampler::ClampAccurate($s) => $e,
            DynSampler::AnyAccurate($s) => $e,
            DynSampler::WrapFast($s) => $e,
            DynSampler::ClampFast($s) => $e,
            DynSampler::AnyFast($s) => $e,
            DynSampler::Srgb($s) => $e,
            DynSampler::SrgbToLinear($s) => $e,
        }
    };
}

/// `pub fn`s that call the selected key's [`Sampler`] method of the same
/// name with the same arguments, one per `fn name(&self | &mut self, arg:
/// Type, …) -> Return;` (after its docs and attributes).
macro_rules! forward {
    () => {};
    ($(#[$a:meta])* fn $name:ident(&mut self $(, $arg:ident: $ty:ty)*) $(-> $ret:ty)?; $($rest:tt)*) => {
        $(#[$a])*
        pub fn $name(&mut self $(, $arg: $ty)*) $(-> $ret)? {
            each!(self, s => s.$name($($arg),*))
        }
        forward!($($rest)*);
    };
    ($(#[$a:meta])* fn $name:ident(&self $(, $arg:ident: $ty:ty)*) $(-> $ret:ty)?; $($rest:tt)*) => {
        $(#[$a])*
        pub fn $name(&self $(, $arg: $ty)*) $(-> $ret)? {
            each!(self, s => s.$name($($arg),*))
        }
        forward!($($rest)*);
    };
}

impl<S: TexelSource> DynSampler<S> {
    /// The sampler of the key [`DynKey::select`] picks for `state`'s
    /// address modes and sRGB output, `space` and `precision`, over
    /// `source`. Never fails (every state has a key).
    pub fn new(source: S, state: SamplerState, space: ColorSpace, precision: Precision) -> Self {
        let key = DynKey::select(state.address(), space, state.srgb_output(), precision);
        let [mu, mv] = state.address();
        let any = (AnyAxis(mu), AnyAxis(mv));
        match key {
            DynKey::WrapAccurate => Self::WrapAccurate(Sampler::build(source, state, (Wrap, Wrap))),
            DynKey::ClampAccurate => {
                Self::ClampAccurate(Sampler::build(source, state, (ClampToEdge, ClampToEdge)))
            }
            DynKey::AnyAccurate => Self::AnyAccurate(Sampler::build(source, state, any)),
            DynKey::WrapFast => Self::WrapFast(Sampler::build(source, state, (Wrap, Wrap))),
            DynKey::ClampFast => {
                Self::ClampFast(Sampler::build(source, state, (ClampToEdge, ClampToEdge)))
            }
            DynKey::AnyFast => Self::AnyFast(Sampler::build(source, state, any)),
            DynKey::Srgb => Self::Srgb(Sampler::build(source, state, any)),
            DynKey::SrgbToLinear => Self::SrgbToLinear(Sampler::build(source, state, any)),
        }
    }

    /// The key this sampler runs.
    #[must_use]
    pub fn key(&self) -> DynKey {
        match self {
            Self::WrapAccurate(_) => DynKey::WrapAccurate,
            Self::ClampAccurate(_) => DynKey::ClampAccurate,
            Self::AnyAccurate(_) => DynKey::AnyAccurate,
            Self::WrapFast(_) => DynKey::WrapFast,
            Self::ClampFast(_) => DynKey::ClampFast,
            Self::AnyFast(_) => DynKey::AnyFast,
            Self::Srgb(_) => DynKey::Srgb,
            Self::SrgbToLinear(_) => DynKey::SrgbToLinear,
        }
    }

    forward! {
        /// [`Sampler::sample`] of the selected key.
        #[inline]
        fn sample(&mut self, u: TexCoord, v: TexCoord, lod: Lod, mode: Mode) -> Texel;
        /// [`Sampler::sample_batch`] of the selected key.
        fn sample_batch(&mut self, hits: &[(TexCoord, TexCoord, Lod)], mode: Mode, out: &mut [Texel]) -> usize;
        /// [`Sampler::sample_aniso`] of the selected key.
        fn sample_aniso(&mut self, u: TexCoord, v: TexCoord, fp: &Footprint) -> Texel;
        /// [`Sampler::sample_stochastic`] of the selected key.
        fn sample_stochastic(&mut self, u: TexCoord, v: TexCoord, lod: Lod, mode: StochasticMode, bits: u32) -> Texel;
        /// The precision tier of the results.
        #[must_use]
        fn precision(&self) -> Precision;
        /// The sampler state.
        #[must_use]
        fn state(&self) -> &SamplerState;
        /// The source's geometry.
        #[must_use]
        fn geometry(&self) -> Geometry;
        /// Fetch counters.
        #[must_use]
        fn stats(&self) -> FetchStats;
        /// Zeroes the fetch counters.
        fn reset_stats(&mut self);
        /// The texel source.
        #[must_use]
        fn source(&self) -> &S;
        /// The texel source, mutable.
        #[must_use]
        fn source_mut(&mut self) -> &mut S;
    }
}
