//! Result codes and the enums C passes as bytes (filter mode, addressing,
//! precision tier, sRGB output, pixel format), with their checked byte
//! forms and the pointer check every function makes.

use crate::texture::AddressMode;

// The sampler and image types the enums are documented against.
#[cfg(doc)]
use super::*;

/// Result codes of the C ABI (`0` = success, negative = error, positive =
/// a documented non-error outcome).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RmStatus {
    /// Success.
    Ok = 0,
    /// The triangle is untextured: no lod (nothing to fetch).
    Untextured = 1,
    /// A required pointer was null.
    NullPointer = -1,
    /// A size, level count, mode or address value is out of range.
    OutOfRange = -2,
    /// Ray stack full: the state was not pushed.
    StackFull = -3,
    /// Ray stack empty: nothing popped.
    StackEmpty = -4,
    /// Texture width or height is zero.
    ZeroSize = -5,
    /// Spread angle outside `(0, 2)` radians.
    BadAngle = -6,
    /// More triangles than table entries (the ones that fit were written).
    TableFull = -7,
    /// The texel buffer is shorter than the pyramid.
    BufferTooShort = -8,
    /// A pointer is not aligned for its type (nothing was read or written).
    Misaligned = -9,
    /// The [`RmSampler`] was not set up by an init function
    /// ([`rm_sampler_init`], [`rm_sampler_init_desc`],
    /// [`rm_sampler_init_image`]); a zeroed one is recognised.
    Uninitialised = -10,
}

/// Filter mode of [`rm_sample`] and [`rm_sample_batch`]: raymip's
/// [`Mode`](crate::texture::Mode) itself, which the header declares under this name (constants
/// `RM_MODE_*`, numbered by the discriminants; `ffi` includes the
/// `trilinear` feature, so all four are there).
pub use crate::texture::Mode as RmMode;

/// Addressing of a texture axis: [`rm_sampler_init`] takes one for both
/// axes, [`RmSamplerDesc`] one per axis.
///
/// The numbers are those of raymip's Rust `AddressMode`, which the
/// co-processor's operands carry too. They follow Vulkan's
/// `VkSamplerAddressMode` for 0–2 (`REPEAT`, `MIRRORED_REPEAT`,
/// `CLAMP_TO_EDGE`), as D3D11's `D3D11_TEXTURE_ADDRESS_MODE` orders them
/// (`WRAP`, `MIRROR`, `CLAMP`, numbered there from 1); 3 and 4 are swapped
/// against Vulkan (`CLAMP_TO_BORDER` = 3, `MIRROR_CLAMP_TO_EDGE` = 4).
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RmAddress {
    /// Repeat: only the fractional part of a coordinate is used (Vulkan
    /// `REPEAT`).
    Wrap = 0,
    /// Repeat, every other copy mirrored (Vulkan `MIRRORED_REPEAT`, D3D
    /// `MIRROR`).
    Mirror = 1,
    /// Clamp to edge (Vulkan `CLAMP_TO_EDGE`).
    Clamp = 2,
    /// Mirror once around 0, then clamp to the edge (Vulkan
    /// `MIRROR_CLAMP_TO_EDGE`, D3D `MIRROR_ONCE`).
    MirrorOnce = 3,
    /// Texels outside the level read the border colour (Vulkan
    /// `CLAMP_TO_BORDER`, D3D `BORDER`).
    Border = 4,
}
// The C numbers are `AddressMode`'s: `RmAddress::mode` is `from_index`.
const _: () = assert!(
    RmAddress::Wrap as u8 == AddressMode::Wrap as u8
        && RmAddress::Mirror as u8 == AddressMode::Mirror as u8
        && RmAddress::Clamp as u8 == AddressMode::ClampToEdge as u8
        && RmAddress::MirrorOnce as u8 == AddressMode::MirrorOnce as u8
        && RmAddress::Border as u8 == AddressMode::ClampToBorder as u8
        && AddressMode::ALL.len() == 5
);

impl RmAddress {
    /// The address mode numbered `n` in C (the discriminants above, which
    /// are [`AddressMode`]'s), `None` for a number above 4.
    #[must_use]
    pub const fn mode(n: u8) -> Option<AddressMode> {
        AddressMode::from_index(n)
    }
}

/// Precision tier of a sampler (the `precision` field of [`RmSamplerDesc`]).
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RmPrecision {
    /// ACCURATE (default): linear filtering ≤ 0.5625 LSB from the exact
    /// f64 filter, sRGB re-encoded ≤ 0.6875 LSB; bit-identical on every
    /// target.
    Accurate = 0,
    /// FAST: GPU precision (8-bit sub-texel weights and lod fraction,
    /// exact filter at the quantized position), linear filtering ≤ 1.5 LSB
    /// from the exact f64 filter (derived in raymip's documentation and
    /// tested against f64); bit-identical on every target.
    Fast = 1,
}

/// Result encoding of an sRGB texture (the `srgb_output` field of [`RmSamplerDesc`]).
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RmSrgbOutput {
    /// Re-encoded to sRGB (what a GPU writes to an sRGB render target).
    Encoded = 0,
    /// Linear, rounded to 8 bits (what a shader reads from an sRGB view).
    Linear = 1,
}

/// Pixel format of an [`RmImage`]: raymip's
/// [`TexelFormat`](crate::texture::storage::format::TexelFormat) itself,
/// which the header declares under this name (constants `RM_FORMAT_*`,
/// numbered by the discriminants).
pub use crate::texture::storage::format::TexelFormat as RmFormat;

/// An [`RmMode`] as it crosses the boundary: any byte (an enum parameter
/// holding a value outside the enum would be undefined behaviour in Rust),
/// checked by the callee (`OutOfRange`). The header names it `RmMode`.
#[repr(transparent)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RmModeBits(pub u8);

/// An [`RmAddress`] as it crosses the boundary (any byte, checked; see
/// [`RmModeBits`]). The header names it `RmAddress`.
#[repr(transparent)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RmAddressBits(pub u8);

/// `NullPointer` if `p` is null and `may_be_null` is false, `Misaligned` if
/// it is not aligned for `T` (null counts as aligned).
pub(super) fn check_ptr<T>(p: *const T, may_be_null: bool) -> Result<(), RmStatus> {
    if p.is_null() {
        if may_be_null {
            Ok(())
        } else {
            Err(RmStatus::NullPointer)
        }
    } else if p.is_aligned() {
        Ok(())
    } else {
        Err(RmStatus::Misaligned)
    }
}
