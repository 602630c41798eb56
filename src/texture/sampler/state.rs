//! Sampler state: what a GPU sampler object holds (D3D11
//! `D3D11_SAMPLER_DESC`, Vulkan `VkSamplerCreateInfo`), as one small
//! `Copy` struct validated once at set-up.
//!
//! * Address mode per axis ([`AddressMode`]) and a border colour for
//!   [`AddressMode::ClampToBorder`] (RGBA8, linear: like Vulkan's border
//!   colours it is never sRGB-decoded).
//! * Level of detail: a bias in `[−16, 16)` with 8 fractional bits and a
//!   `[min, max]` clamp, applied in fixed point ([`Lod`], I8F8, exact) in
//!   the order both specifications give ([`SamplerState::lod`]):
//!
//!   ```text
//!   λ' = clamp(λ + bias, min_lod, max_lod)     (saturating add)
//!   λ  = clamp(λ', 0, levels − 1)               (the stored levels)
//!   ```
//!
//!   8 fractional lod bits, as D3D11 requires (Vulkan asks for 6).
//! * Maximum anisotropy `1 ..= 16` ([`crate::texture::sampler::aniso`]).
//! * For sRGB textures: whether filtered results come back re-encoded to
//!   sRGB or as linear values ([`SrgbOutput`]).

use crate::lod::clamp_lod;
use crate::texture::address::AddressMode;
use crate::texture::storage::mip::Texel;
use crate::units::Lod;

/// Largest supported maximum anisotropy (16×, as D3D11 and Vulkan).
pub const MAX_ANISOTROPY: u8 = 16;

/// What an sRGB texture's filtered result is returned as. Example:
/// [`DynSampler`](crate::texture::sampler::dynamic::DynSampler).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SrgbOutput {
    /// Re-encoded to sRGB (what a GPU writes to an sRGB render target).
    #[default]
    Encoded,
    /// Linear, rounded to 8 bits (what a shader reads from an sRGB view).
    Linear,
}

/// Sampler settings before validation (every field public; see
/// [`SamplerState::new`]). `Default`: wrap on both axes, transparent
/// black border, no bias, lod clamp `[−128, 128)` (no clamp), no
/// anisotropy, sRGB results re-encoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SamplerDesc {
    /// Address mode of `u`.
    pub address_u: AddressMode,
    /// Address mode of `v`.
    pub address_v: AddressMode,
    /// Border colour (RGBA8 `u32::from_le_bytes([r, g, b, a])`, linear).
    pub border: Texel,
    /// LOD bias in levels, `[−16, 16)`.
    pub lod_bias: Lod,
    /// Lower lod clamp in levels (any [`Lod`]; at most `max_lod`).
    pub min_lod: Lod,
    /// Upper lod clamp in levels (any [`Lod`]).
    pub max_lod: Lod,
    /// Maximum anisotropy, `1 ..= 16` (1 = isotropic).
    pub max_anisotropy: u8,
    /// Result encoding of sRGB textures.
    pub srgb_output: SrgbOutput,
}

impl Default for SamplerDesc {
    fn default() -> Self {
        Self {
            address_u: AddressMode::Wrap,
            address_v: AddressMode::Wrap,
            border: 0,
            lod_bias: Lod::ZERO,
            min_lod: Lod::MIN,
            max_lod: Lod::MAX,
            max_anisotropy: 1,
            srgb_output: SrgbOutput::Encoded,
        }
    }
}

unit_error! {
    /// Why a [`SamplerDesc`] is rejected.
    ///
    /// # Example
    /// ```
    /// use raymip::texture::sampler::state::SamplerStateError;
    /// use raymip::texture::SamplerDesc;
    /// use raymip::{Lod, SamplerState};
    /// let inverted = SamplerDesc { min_lod: Lod::from_num(3), max_lod: Lod::ONE, ..SamplerDesc::default() };
    /// let err = SamplerState::new(inverted).unwrap_err();
    /// assert_eq!(err, SamplerStateError::LodClampInverted);
    /// assert_eq!(err.to_string(), "min lod above max lod");
    /// // 17× is above the D3D11/Vulkan limit of 16×.
    /// let aniso = SamplerDesc { max_anisotropy: 17, ..SamplerDesc::default() };
    /// assert_eq!(SamplerState::new(aniso), Err(SamplerStateError::BadAnisotropy));
    /// ```
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[non_exhaustive]
    pub enum SamplerStateError {
        /// `lod_bias` outside `[−16, 16)`.
        BiasOutOfRange => "lod bias outside [-16, 16)",
        /// `min_lod > max_lod`.
        LodClampInverted => "min lod above max lod",
        /// `max_anisotropy` outside `1 ..= 16`.
        BadAnisotropy => "max anisotropy outside 1..=16",
    }
}

/// Validated sampler state (see the module docs). Build it once with
/// [`SamplerState::new`]; per sample it is only read.
///
/// # Example
/// ```
/// use raymip::texture::address::AnyAxis;
/// use raymip::texture::{AddressMode, SamplerDesc};
/// use raymip::{Cfg, Geometry, Lod, Mode, Pyramid, Sampler, SamplerState, TexCoord};
/// let state = SamplerState::new(SamplerDesc {
///     address_u: AddressMode::ClampToBorder,
///     address_v: AddressMode::ClampToBorder,
///     border: 0xFF00_FF00, // opaque green
///     lod_bias: Lod::from_num(0.5),
///     ..SamplerDesc::default()
/// })?;
/// // Validation happens here, once: a bias outside [−16, 16) is refused.
/// let bad = SamplerDesc { lod_bias: Lod::from_num(20), ..SamplerDesc::default() };
/// assert!(SamplerState::new(bad).is_err());
/// let texels = [0xFFFF_FFFFu32; 4];
/// let pyramid = Pyramid::new(Geometry::new(2, 2, 1)?, &texels)?;
/// let mut s: Sampler<_, Cfg<AnyAxis>> = Sampler::with_state(pyramid, state)?;
/// let out = TexCoord::from_num(1.5);
/// assert_eq!(s.sample(out, out, Lod::ZERO, Mode::Nearest), 0xFF00_FF00);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct SamplerState {
    desc: SamplerDesc,
}

impl SamplerState {
    /// Validates `desc`.
    ///
    /// # Errors
    /// [`SamplerStateError`] naming the first field out of range.
    pub fn new(desc: SamplerDesc) -> Result<Self, SamplerStateError> {
        if desc.lod_bias < Lod::from_bits(-16 << 8) || desc.lod_bias >= Lod::from_bits(16 << 8) {
            return Err(SamplerStateError::BiasOutOfRange);
        }
        if desc.min_lod > desc.max_lod {
            return Err(SamplerStateError::LodClampInverted);
        }
        if desc.max_anisotropy == 0 || desc.max_anisotropy > MAX_ANISOTROPY {
            return Err(SamplerStateError::BadAnisotropy);
        }
        Ok(Self { desc })
    }

    /// The settings.
    #[must_use]
    pub const fn desc(&self) -> &SamplerDesc {
        &self.desc
    }

    /// Address modes of `u` and `v`.
    #[inline]
    #[must_use]
    pub const fn address(&self) -> [AddressMode; 2] {
        [self.desc.address_u, self.desc.address_v]
    }

    /// Border colour (RGBA8, linear).
    #[inline]
    #[must_use]
    pub const fn border(&self) -> Texel {
        self.desc.border
    }

    /// Maximum anisotropy, `1 ..= 16`.
    #[inline]
    #[must_use]
    pub const fn max_anisotropy(&self) -> u8 {
        self.desc.max_anisotropy
    }

    /// Result encoding of sRGB textures.
    #[inline]
    #[must_use]
    pub const fn srgb_output(&self) -> SrgbOutput {
        self.desc.srgb_output
    }

    /// The level of detail a sample uses: `lod + bias` (saturating),
    /// clamped to `[min_lod, max_lod]`, then to the stored levels
    /// `[0, levels − 1]`. Exact in I8F8; never panics.
    #[inline]
    #[must_use]
    pub fn lod(&self, lod: Lod, levels: u8) -> Lod {
        let biased = lod.saturating_add(self.desc.lod_bias);
        // `max`/`min`, not `clamp`: validated, but no panic branch either way.
        let clamped = biased.max(self.desc.min_lod).min(self.desc.max_lod);
        clamp_lod(clamped, levels)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use proptest::prelude::*;

    fn l(x: f64) -> Lod {
        Lod::from_num(x)
    }

    #[test]
    fn validation() {
        let ok = SamplerDesc::default();
        assert!(SamplerState::new(ok).is_ok());
        for (bias, good) in [
            (-16.0, true),
            (15.996, true),
            (16.0, false),
            (-16.004, false),
        ] {
            let d = SamplerDesc {
                lod_bias: l(bias),
                ..ok
            };
            assert_eq!(SamplerState::new(d).is_ok(), good, "{bias}");
        }
        let inverted = SamplerDesc {
            min_lod: l(2.0),
            max_lod: l(1.0),
            ..ok
        };
        assert_eq!(
            SamplerState::new(inverted),
            Err(SamplerStateError::LodClampInverted)
        );
        for (a, good) in [(0u8, false), (1, true), (16, true), (17, false)] {
            let d = SamplerDesc {
                max_anisotropy: a,
                ..ok
            };
            assert_eq!(SamplerState::new(d).is_ok(), good, "{a}");
        }
    }

    /// Reference vectors: (lod, bias, min, max, levels, expected).
    #[test]
    fn lod_order_reference_vectors() {
        let v = [
            (1.5, 0.25, -128.0, 127.0, 9, 1.75),
            (1.5, -4.0, -128.0, 127.0, 9, 0.0),
            (1.5, 0.0, 2.0, 3.0, 9, 2.0),
            (7.0, 0.0, 2.0, 3.0, 9, 3.0),
            // The clamp to [min, max] comes before the clamp to the levels:
            // min 12 on a 4-level texture still gives the top level.
            (0.0, 0.0, 12.0, 13.0, 4, 3.0),
            // Bias before the clamp: −2 + 1.5 = −0.5 → min 0.25.
            (-2.0, 1.5, 0.25, 5.0, 9, 0.25),
            (127.0, 15.99609375, -128.0, 127.0, 16, 15.0),
            (-128.0, -16.0, -128.0, 127.0, 16, 0.0),
        ];
        for (lod, bias, lo, hi, levels, want) in v {
            let s = SamplerState::new(SamplerDesc {
                lod_bias: l(bias),
                min_lod: l(lo),
                max_lod: l(hi),
                ..SamplerDesc::default()
            })
            .unwrap();
            assert_eq!(s.lod(l(lod), levels), l(want), "{lod} {bias} {lo} {hi}");
        }
    }

    proptest! {
        /// f64 reference of the D3D11/Vulkan order over the full I8F8 range.
        #[test]
        fn lod_matches_f64(lod in any::<i16>(), bias in -4096i16..4096, a in any::<i16>(), b in any::<i16>(), levels in 1u8..=16) {
            let (lo, hi) = (a.min(b), a.max(b));
            let s = SamplerState::new(SamplerDesc {
                lod_bias: Lod::from_bits(bias),
                min_lod: Lod::from_bits(lo),
                max_lod: Lod::from_bits(hi),
                ..SamplerDesc::default()
            }).unwrap();
            let f = |x: i16| f64::from(x) / 256.0;
            let biased = (f(lod) + f(bias)).clamp(-128.0, 127.99609375);
            let want = biased.clamp(f(lo), f(hi)).clamp(0.0, f64::from(levels - 1));
            prop_assert_eq!(s.lod(Lod::from_bits(lod), levels).to_num::<f64>(), want);
        }
    }
}
