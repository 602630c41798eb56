//! Textures in caller memory through C: RGBA8 pyramids (length, in-place
//! generation) and images in any pixel format (length).

use crate::texture::storage::format::TexelFormat;
use crate::texture::storage::image::image_len;
use crate::texture::storage::mip::{Geometry, MipError, Pyramid, generate, pyramid_len};

use super::*;

/// A MIP pyramid in caller memory: levels stored one after another, level 0
/// first, each row-major (`rm_pyramid_len` texels in all).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct RmTexture {
    /// The texels (RGBA8: red in bits 0–7, alpha in bits 24–31).
    pub texels: *const u32,
    /// Number of texels at `texels`.
    pub len: usize,
    /// Level-0 width in texels.
    pub width: u32,
    /// Level-0 height in texels.
    pub height: u32,
    /// Stored levels (1 ..= full chain).
    pub levels: u8,
}

pub(super) fn mip_status(e: MipError) -> RmStatus {
    match e {
        MipError::ZeroSize => RmStatus::ZeroSize,
        MipError::BufferTooShort { .. } => RmStatus::BufferTooShort,
        _ => RmStatus::OutOfRange,
    }
}

/// Texels of a pyramid of `levels` levels (capped at the full chain) of a
/// `width × height` texture (0 when a side is 0); no status (it cannot
/// fail).
#[unsafe(no_mangle)]
pub extern "C" fn rm_pyramid_len(width: u32, height: u32, levels: u8) -> usize {
    pyramid_len(width, height, levels)
}

/// Generates levels `1 .. levels` of a `width × height` pyramid in place
/// from level 0 (the first `width·height` texels at `texels`): a 2×2 box
/// filter rounding half up (an exact area box for odd sides). Set-up time,
/// not per hit.
///
/// Returns `RM_STATUS_OK`; `RM_STATUS_NULL_POINTER`; `RM_STATUS_MISALIGNED`;
/// `RM_STATUS_ZERO_SIZE`; `RM_STATUS_OUT_OF_RANGE` (a level count outside
/// `1 ..=` the full chain, or a side above 32768); `RM_STATUS_BUFFER_TOO_SHORT`
/// (`len` < [`rm_pyramid_len`]; nothing written).
///
/// # Safety
/// `texels` is null or points to `len` writable texels.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_mip_generate(
    texels: *mut u32,
    len: usize,
    width: u32,
    height: u32,
    levels: u8,
) -> RmStatus {
    if let Err(e) = check_ptr(texels.cast_const(), false) {
        return e;
    }
    let g = match Geometry::new(width, height, levels) {
        Ok(g) => g,
        Err(e) => return mip_status(e),
    };
    // SAFETY: non-null, `len` writable texels (caller).
    let buf = unsafe { core::slice::from_raw_parts_mut(texels, len) };
    match generate(&g, buf) {
        Ok(()) => RmStatus::Ok,
        Err(e) => mip_status(e),
    }
}

/// A texture in any [`RmFormat`] in caller memory: the levels from level 0
/// (finest) on, each row-major (BC formats: rows of 4×4 blocks, 8 or 16
/// bytes each), `rm_image_len` bytes in all. 16-bit texels are
/// little-endian.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct RmImage {
    /// The texel bytes.
    pub bytes: *const u8,
    /// Number of bytes at `bytes`.
    pub len: usize,
    /// Level-0 width in texels.
    pub width: u32,
    /// Level-0 height in texels.
    pub height: u32,
    /// Stored levels (1 ..= full chain).
    pub levels: u8,
    /// Pixel format (`RM_FORMAT_*`).
    pub format: u8,
    /// 0: linear channels; 1: sRGB-encoded colour (alpha linear; not for
    /// `RM_FORMAT_A8` and `RM_FORMAT_BC4`).
    pub srgb: u8,
}

/// Bytes an [`RmImage`] of `format` with `levels` levels (capped at the
/// full chain) of a `width × height` level 0 needs; 0 for a zero side or
/// an unknown format (no status: it cannot fail).
#[unsafe(no_mangle)]
pub extern "C" fn rm_image_len(width: u32, height: u32, levels: u8, format: u8) -> usize {
    // `image_len` is 0 for a zero side (no level).
    TexelFormat::from_index(format).map_or(0, |f| image_len(width, height, levels, f))
}

/// The pyramid of `tex` after its checks.
///
/// # Safety
/// As [`rm_sampler_init`]'s `tex`.
pub(super) unsafe fn pyramid_of(tex: *const RmTexture) -> Result<Pyramid<'static>, RmStatus> {
    check_ptr(tex, false)?;
    // SAFETY: non-null, aligned (checked), valid (caller).
    let t = unsafe { tex.read() };
    check_ptr(t.texels, false)?;
    let g = Geometry::new(t.width, t.height, t.levels).map_err(mip_status)?;
    // SAFETY: non-null, aligned (checked), `len` readable texels that
    // outlive every use of the sampler (caller).
    let texels = unsafe { core::slice::from_raw_parts(t.texels, t.len) };
    Pyramid::new(g, texels).map_err(mip_status)
}
