//! Texture sampling through C: an opaque sampler in caller memory set up
//! once per texture, then single, batched and anisotropic samples.

use fixed::types::{I8F8, I32F32};

use crate::texture::sampler::dynamic::DynSampler;
use crate::texture::sampler::state::SrgbOutput;
use crate::texture::storage::format::{AnyFormat, ColorSpace, Format, TexelFormat};
use crate::texture::storage::image::Image;
use crate::texture::storage::mip::{Geometry, Pyramid, Texel};
use crate::texture::{AddressMode, Sampler};
use crate::texture::{Mode, SamplerDesc, SamplerState};
use crate::units::{Footprint, Lod, Precision, TexCoord};

use super::*;

/// Size of an [`RmSampler`] in 64-bit words (1024 bytes: enough for the
/// sampler of a pyramid or an image on 32- and 64-bit targets, checked at
/// compile time).
pub const RM_SAMPLER_WORDS: usize = 128;

/// A texture sampler in caller memory: set up once per texture and
/// addressing by [`rm_sampler_init`] (which checks the texture), then used
/// by [`rm_sample`] for every hit without rebuilding the pyramid geometry
/// or the power-of-two addressing tables. Opaque: C code allocates it
/// (static, stack or heap, 8-byte aligned), may copy it bytewise, and never
/// writes into it. It borrows the texels of the [`RmTexture`] it was set up
/// with: they must stay valid and unchanged while it is used.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct RmSampler {
    /// Owned by the library.
    pub opaque: [u64; RM_SAMPLER_WORDS],
}

/// Marks an [`RmSampler`] written by [`rm_sampler_init`],
/// [`rm_sampler_init_desc`] or [`rm_sampler_init_image`] ("raymipSm").
pub(super) const SAMPLER_MAGIC: u64 = u64::from_le_bytes(*b"raymipSm");

/// The texture behind a sampler: an RGBA8 pyramid or an image in any
/// format, in the sampler of its key.
///
/// The variants differ in size (an [`Image`] keeps a footprint record per
/// level); the slot lives in the caller's [`RmSampler`] words, so the enum's
/// size is the largest variant's either way and there is no heap to box it in.
#[allow(
    clippy::large_enum_variant,
    reason = "no allocator: the slot is stored in the caller's RmSampler words"
)]
pub(super) enum SlotSampler {
    Pyramid(DynSampler<Pyramid<'static>>),
    Image(DynSampler<Image<'static, AnyFormat>>),
}

/// A batch of hits as the Rust batch loop takes them.
type Hits<'a> = &'a [(TexCoord, TexCoord, Lod)];

/// The sampling function of one key (slot kind and [`DynSampler`]
/// variant). An init function stores the one of the key it set up, and
/// `rm_sample` calls through it, so a firmware links the sampling code of
/// the keys its init calls can select and no other
/// (`rm_sampler_init_wrap`: one key). It answers only its own variant
/// (transparent black otherwise, which an init never pairs). The batch and
/// anisotropic entry points match every key: their code is linked only
/// when they are called.
pub(super) struct SlotOps {
    sample: fn(&mut SlotSampler, TexCoord, TexCoord, Lod, Mode) -> Texel,
}

/// `const NAME: SlotOps` for the slot kind `$kind` and key `$key`.
macro_rules! slot_ops {
    ($($name:ident = $kind:ident $key:ident;)*) => {$(
        const $name: SlotOps = SlotOps {
            sample: |slot, u, v, lod, mode| match slot {
                SlotSampler::$kind(DynSampler::$key(s)) => s.sample(u, v, lod, mode),
                _ => 0,
            },
        };
    )*};
}

slot_ops! {
    PYRAMID_WRAP_ACCURATE = Pyramid WrapAccurate;
    PYRAMID_CLAMP_ACCURATE = Pyramid ClampAccurate;
    PYRAMID_ANY_ACCURATE = Pyramid AnyAccurate;
    PYRAMID_WRAP_FAST = Pyramid WrapFast;
    PYRAMID_CLAMP_FAST = Pyramid ClampFast;
    PYRAMID_ANY_FAST = Pyramid AnyFast;
    PYRAMID_SRGB = Pyramid Srgb;
    PYRAMID_SRGB_TO_LINEAR = Pyramid SrgbToLinear;
    IMAGE_WRAP_ACCURATE = Image WrapAccurate;
    IMAGE_CLAMP_ACCURATE = Image ClampAccurate;
    IMAGE_ANY_ACCURATE = Image AnyAccurate;
    IMAGE_WRAP_FAST = Image WrapFast;
    IMAGE_CLAMP_FAST = Image ClampFast;
    IMAGE_ANY_FAST = Image AnyFast;
    IMAGE_SRGB = Image Srgb;
    IMAGE_SRGB_TO_LINEAR = Image SrgbToLinear;
}

/// The table of a pyramid sampler's key.
fn pyramid_ops(s: &DynSampler<Pyramid<'static>>) -> &'static SlotOps {
    match s {
        DynSampler::WrapAccurate(_) => &PYRAMID_WRAP_ACCURATE,
        DynSampler::ClampAccurate(_) => &PYRAMID_CLAMP_ACCURATE,
        DynSampler::AnyAccurate(_) => &PYRAMID_ANY_ACCURATE,
        DynSampler::WrapFast(_) => &PYRAMID_WRAP_FAST,
        DynSampler::ClampFast(_) => &PYRAMID_CLAMP_FAST,
        DynSampler::AnyFast(_) => &PYRAMID_ANY_FAST,
        DynSampler::Srgb(_) => &PYRAMID_SRGB,
        DynSampler::SrgbToLinear(_) => &PYRAMID_SRGB_TO_LINEAR,
    }
}

/// The table of an image sampler's key.
fn image_ops(s: &DynSampler<Image<'static, AnyFormat>>) -> &'static SlotOps {
    match s {
        DynSampler::WrapAccurate(_) => &IMAGE_WRAP_ACCURATE,
        DynSampler::ClampAccurate(_) => &IMAGE_CLAMP_ACCURATE,
        DynSampler::AnyAccurate(_) => &IMAGE_ANY_ACCURATE,
        DynSampler::WrapFast(_) => &IMAGE_WRAP_FAST,
        DynSampler::ClampFast(_) => &IMAGE_CLAMP_FAST,
        DynSampler::AnyFast(_) => &IMAGE_ANY_FAST,
        DynSampler::Srgb(_) => &IMAGE_SRGB,
        DynSampler::SrgbToLinear(_) => &IMAGE_SRGB_TO_LINEAR,
    }
}

/// What an [`RmSampler`] holds: the magic word, the sampling functions of
/// its key, then the Rust sampler over the caller's texels (their lifetime
/// is the caller's promise).
#[repr(C)]
pub(super) struct SamplerSlot {
    magic: u64,
    ops: &'static SlotOps,
    sampler: SlotSampler,
}

const _: () = assert!(
    core::mem::size_of::<SamplerSlot>() <= core::mem::size_of::<RmSampler>()
        && core::mem::align_of::<SamplerSlot>() <= core::mem::align_of::<RmSampler>()
);

/// Sampler settings of [`rm_sampler_init_desc`] and
/// [`rm_sampler_init_image`]. [`rm_sampler_desc_default`] fills the
/// defaults (wrap on both axes, transparent black border, no bias, no lod
/// clamp, isotropic, sRGB re-encoded, ACCURATE); every field is checked at
/// set-up, none per sample.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RmSamplerDesc {
    /// Border colour of `RM_ADDRESS_BORDER` (RGBA8, linear: red in bits
    /// 0–7, alpha in bits 24–31). Default 0 (transparent black).
    pub border: u32,
    /// LOD bias added to every lod, I8F8 bits, `[−16, 16)` levels
    /// (`[-4096, 4095]` in bits). Default 0.
    pub lod_bias: i16,
    /// Lower lod clamp (after the bias), I8F8 bits, any value up to
    /// `max_lod`. Default `INT16_MIN` (−128 levels: no clamp).
    pub min_lod: i16,
    /// Upper lod clamp, I8F8 bits, at least `min_lod`. Default `INT16_MAX`
    /// (128 levels: no clamp; the stored levels clamp anyway).
    pub max_lod: i16,
    /// Address mode of `u` (`RM_ADDRESS_*`). Default `RM_ADDRESS_WRAP`.
    pub address_u: RmAddressBits,
    /// Address mode of `v` (`RM_ADDRESS_*`). Default `RM_ADDRESS_WRAP`.
    pub address_v: RmAddressBits,
    /// Maximum anisotropy of [`rm_sample_aniso`], `1 ..= 16` (1 =
    /// isotropic). Default 1.
    pub max_anisotropy: u8,
    /// Result encoding of sRGB images (`RM_SRGB_OUTPUT_*`). Default
    /// `RM_SRGB_OUTPUT_ENCODED`.
    pub srgb_output: u8,
    /// Precision tier (`RM_PRECISION_*`). Default `RM_PRECISION_ACCURATE`.
    pub precision: u8,
}

impl Default for RmSamplerDesc {
    fn default() -> Self {
        let d = SamplerDesc::default();
        Self {
            border: d.border,
            lod_bias: d.lod_bias.to_bits(),
            min_lod: d.min_lod.to_bits(),
            max_lod: d.max_lod.to_bits(),
            address_u: RmAddressBits(RmAddress::Wrap as u8),
            address_v: RmAddressBits(RmAddress::Wrap as u8),
            max_anisotropy: d.max_anisotropy,
            srgb_output: RmSrgbOutput::Encoded as u8,
            precision: RmPrecision::Accurate as u8,
        }
    }
}

impl RmSamplerDesc {
    /// The validated state and tier, or `OutOfRange` naming nothing more
    /// (C has the field ranges in the header).
    fn state(&self) -> Result<(SamplerState, Precision), RmStatus> {
        let (Some(address_u), Some(address_v)) = (
            RmAddress::mode(self.address_u.0),
            RmAddress::mode(self.address_v.0),
        ) else {
            return Err(RmStatus::OutOfRange);
        };
        let srgb_output = match self.srgb_output {
            0 => SrgbOutput::Encoded,
            1 => SrgbOutput::Linear,
            _ => return Err(RmStatus::OutOfRange),
        };
        let precision = match self.precision {
            0 => Precision::Accurate,
            1 => Precision::Fast,
            _ => return Err(RmStatus::OutOfRange),
        };
        let state = SamplerState::new(SamplerDesc {
            address_u,
            address_v,
            border: self.border,
            lod_bias: Lod::from_bits(self.lod_bias),
            min_lod: Lod::from_bits(self.min_lod),
            max_lod: Lod::from_bits(self.max_lod),
            max_anisotropy: self.max_anisotropy,
            srgb_output,
        })
        .map_err(|_| RmStatus::OutOfRange)?;
        Ok((state, precision))
    }
}

/// One sample of [`rm_sample_batch`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RmHit {
    /// `u`, I32F32 bits (normalised; texel centres at `(i + 0.5)/width`).
    pub u: i64,
    /// `v`, I32F32 bits.
    pub v: i64,
    /// Level of detail, I8F8 bits.
    pub lod: i16,
}

/// Screen-space derivatives of the texture coordinates for
/// [`rm_sample_aniso`], I32F32 bits (normalised texture units per pixel).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RmFootprint {
    /// `∂u/∂x`.
    pub dudx: i64,
    /// `∂v/∂x`.
    pub dvdx: i64,
    /// `∂u/∂y`.
    pub dudy: i64,
    /// `∂v/∂y`.
    pub dvdy: i64,
}

/// Writes the default [`RmSamplerDesc`] to `out` (the defaults are in its
/// field docs).
///
/// Returns `RM_STATUS_OK`, `RM_STATUS_NULL_POINTER` or
/// `RM_STATUS_MISALIGNED`.
///
/// # Safety
/// `out` is null or points to a writable [`RmSamplerDesc`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_sampler_desc_default(out: *mut RmSamplerDesc) -> RmStatus {
    if let Err(e) = check_ptr(out.cast_const(), false) {
        return e;
    }
    // SAFETY: non-null, aligned (checked), writable (caller).
    unsafe { out.write(RmSamplerDesc::default()) };
    RmStatus::Ok
}

/// Writes `sampler_slot` with the sampling functions `ops` of its key
/// into `sampler`.
///
/// # Safety
/// `sampler` is non-null, aligned and writable.
pub(super) unsafe fn write_slot(
    sampler: *mut RmSampler,
    sampler_slot: SlotSampler,
    ops: &'static SlotOps,
) {
    let slot = SamplerSlot {
        magic: SAMPLER_MAGIC,
        ops,
        sampler: sampler_slot,
    };
    // SAFETY: non-null, aligned and large enough (caller; size and
    // alignment checked at compile time), writable (caller).
    unsafe { sampler.cast::<SamplerSlot>().write(slot) };
}

/// Sets up `sampler` for the pyramid `tex` with addressing `address`
/// (`RM_ADDRESS_*`, both axes) and otherwise default settings: checks the
/// texture once (size, levels, length) and stores what [`rm_sample`]
/// needs. On error `sampler` is left unchanged.
///
/// Returns `RM_STATUS_OK`; `RM_STATUS_NULL_POINTER`;
/// `RM_STATUS_MISALIGNED`; `RM_STATUS_OUT_OF_RANGE` (the address byte, a
/// level count outside `1 ..=` the full chain, or a side above 32768);
/// `RM_STATUS_ZERO_SIZE`; `RM_STATUS_BUFFER_TOO_SHORT` (`tex->len` below
/// `rm_pyramid_len`).
///
/// # Safety
/// `sampler` and `tex` are null or valid;
/// `tex->texels` points to `tex->len` readable texels that stay valid and
/// unchanged while the sampler is used.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_sampler_init(
    sampler: *mut RmSampler,
    tex: *const RmTexture,
    address: RmAddressBits,
) -> RmStatus {
    if let Err(e) = check_ptr(sampler.cast_const(), false) {
        return e;
    }
    let Some(mode) = RmAddress::mode(address.0) else {
        return RmStatus::OutOfRange;
    };
    // SAFETY: `tex` as the caller guarantees.
    let p = match unsafe { pyramid_of(tex) } {
        Ok(p) => p,
        Err(e) => return e,
    };
    // The keys of the default settings with one address mode, and no other:
    // the same samplers as `rm_sampler_init_desc` builds for them.
    let (s, ops) = match mode {
        AddressMode::Wrap => (
            DynSampler::WrapAccurate(Sampler::wrap(p)),
            &PYRAMID_WRAP_ACCURATE,
        ),
        AddressMode::ClampToEdge => (
            DynSampler::ClampAccurate(Sampler::clamp(p)),
            &PYRAMID_CLAMP_ACCURATE,
        ),
        _ => (
            DynSampler::AnyAccurate(Sampler::with_address(p, mode)),
            &PYRAMID_ANY_ACCURATE,
        ),
    };
    // SAFETY: `sampler` non-null, aligned (checked), writable (caller).
    unsafe { write_slot(sampler, SlotSampler::Pyramid(s), ops) };
    RmStatus::Ok
}

/// Sets up `sampler` for the pyramid `tex` with wrap addressing on both
/// axes and otherwise default settings, as `rm_sampler_init` with
/// `RM_ADDRESS_WRAP` does; a firmware that sets up its samplers only
/// this way links the sampling code of this one configuration (`.text`
/// per configuration in docs/bare-metal.md). On error `sampler` is left
/// unchanged.
///
/// Returns `RM_STATUS_OK`; `RM_STATUS_NULL_POINTER`;
/// `RM_STATUS_MISALIGNED`; `RM_STATUS_OUT_OF_RANGE` (a level count outside
/// `1 ..=` the full chain, or a side above 32768); `RM_STATUS_ZERO_SIZE`;
/// `RM_STATUS_BUFFER_TOO_SHORT` (`tex->len` below `rm_pyramid_len`).
///
/// # Safety
/// As [`rm_sampler_init`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_sampler_init_wrap(
    sampler: *mut RmSampler,
    tex: *const RmTexture,
) -> RmStatus {
    if let Err(e) = check_ptr(sampler.cast_const(), false) {
        return e;
    }
    // SAFETY: `tex` as the caller guarantees.
    let p = match unsafe { pyramid_of(tex) } {
        Ok(p) => p,
        Err(e) => return e,
    };
    let s = DynSampler::WrapAccurate(Sampler::wrap(p));
    // SAFETY: `sampler` non-null, aligned (checked), writable (caller).
    unsafe { write_slot(sampler, SlotSampler::Pyramid(s), &PYRAMID_WRAP_ACCURATE) };
    RmStatus::Ok
}

/// Sets up `sampler` for the RGBA8 pyramid `tex` with the settings `desc`
/// (address mode per axis, border, bias and clamps, anisotropy, tier),
/// checked once here: every sample then runs the code specialised for the
/// configuration. On error `sampler` is left unchanged.
///
/// Returns `RM_STATUS_OK`; `RM_STATUS_NULL_POINTER`;
/// `RM_STATUS_MISALIGNED`; `RM_STATUS_OUT_OF_RANGE` (a `desc` field outside
/// its range, a level count outside `1 ..=` the full chain, or a side above
/// 32768); `RM_STATUS_ZERO_SIZE`; `RM_STATUS_BUFFER_TOO_SHORT`.
///
/// # Safety
/// `sampler`, `tex` and `desc` are null or valid;
/// `tex->texels` points to `tex->len` readable texels that stay valid and
/// unchanged while the sampler is used.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_sampler_init_desc(
    sampler: *mut RmSampler,
    tex: *const RmTexture,
    desc: *const RmSamplerDesc,
) -> RmStatus {
    if let Err(e) = check_ptr(sampler.cast_const(), false).and(check_ptr(desc, false)) {
        return e;
    }
    // SAFETY: non-null, aligned (checked), valid (caller).
    let (state, precision) = match unsafe { desc.read() }.state() {
        Ok(x) => x,
        Err(e) => return e,
    };
    // SAFETY: `tex` as the caller guarantees.
    let p = match unsafe { pyramid_of(tex) } {
        Ok(p) => p,
        Err(e) => return e,
    };
    let s = DynSampler::new(p, state, ColorSpace::Linear, precision);
    let ops = pyramid_ops(&s);
    // SAFETY: `sampler` non-null, aligned (checked), writable (caller).
    unsafe { write_slot(sampler, SlotSampler::Pyramid(s), ops) };
    RmStatus::Ok
}

/// Sets up `sampler` for the image `img` (any [`RmFormat`], linear or
/// sRGB) with the settings `desc`, checked once here. Formats are decoded
/// per texel read (BC1–BC4 decode the texel's 4×4 block each time). On
/// error `sampler` is left unchanged.
///
/// Returns `RM_STATUS_OK`; `RM_STATUS_NULL_POINTER`;
/// `RM_STATUS_MISALIGNED`; `RM_STATUS_OUT_OF_RANGE` (a `desc` field, the
/// format, an `srgb` flag the format has no sRGB variant for, a level
/// count outside `1 ..=` the full chain, or a side above 32768);
/// `RM_STATUS_ZERO_SIZE`; `RM_STATUS_BUFFER_TOO_SHORT` (`img->len` below
/// `rm_image_len`).
///
/// # Safety
/// `sampler`, `img` and `desc` are null or valid;
/// `img->bytes` points to `img->len` readable bytes that stay valid and
/// unchanged while the sampler is used.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_sampler_init_image(
    sampler: *mut RmSampler,
    img: *const RmImage,
    desc: *const RmSamplerDesc,
) -> RmStatus {
    if let Err(e) = check_ptr(sampler.cast_const(), false)
        .and(check_ptr(img, false))
        .and(check_ptr(desc, false))
    {
        return e;
    }
    // SAFETY: non-null, aligned (checked), valid (caller).
    let (state, precision) = match unsafe { desc.read() }.state() {
        Ok(x) => x,
        Err(e) => return e,
    };
    // SAFETY: non-null, aligned (checked), valid (caller).
    let m = unsafe { img.read() };
    if let Err(e) = check_ptr(m.bytes, false) {
        return e;
    }
    let space = match m.srgb {
        0 => ColorSpace::Linear,
        1 => ColorSpace::Srgb,
        _ => return RmStatus::OutOfRange,
    };
    let Some(texel) = TexelFormat::from_index(m.format) else {
        return RmStatus::OutOfRange;
    };
    let Ok(format) = Format::new(texel, space) else {
        return RmStatus::OutOfRange;
    };
    let g = match Geometry::new(m.width, m.height, m.levels) {
        Ok(g) => g,
        Err(e) => return mip_status(e),
    };
    // SAFETY: non-null (checked), `len` readable bytes that outlive every
    // use of the sampler (caller); `u8` needs no alignment.
    let bytes = unsafe { core::slice::from_raw_parts(m.bytes, m.len) };
    let Ok(image) = Image::new(g, format, bytes) else {
        return RmStatus::BufferTooShort;
    };
    let s = DynSampler::new(image, state, space, precision);
    let ops = image_ops(&s);
    // SAFETY: `sampler` non-null, aligned (checked), writable (caller).
    unsafe { write_slot(sampler, SlotSampler::Image(s), ops) };
    RmStatus::Ok
}

/// The set-up sampler behind `sampler` and its key's sampling functions,
/// or `NullPointer`, `Misaligned`, `Uninitialised`.
///
/// # Safety
/// `sampler` is null or valid and zeroed or set up by an init function;
/// no other reference to it is live for `'a`.
pub(super) unsafe fn slot_of<'a>(
    sampler: *mut RmSampler,
) -> Result<(&'static SlotOps, &'a mut SlotSampler), RmStatus> {
    check_ptr(sampler.cast_const(), false)?;
    let slot = sampler.cast::<SamplerSlot>();
    // SAFETY: non-null, aligned (checked), readable (caller); only the
    // `u64` magic word is read (any bits are valid), no reference is made.
    if unsafe { (&raw const (*slot).magic).read() } != SAMPLER_MAGIC {
        return Err(RmStatus::Uninitialised);
    }
    // SAFETY: written by an init function (magic, caller); no other
    // reference to it is live; its texels are valid (caller).
    let slot = unsafe { &mut *slot };
    Ok((slot.ops, &mut slot.sampler))
}

/// Filtered texel at `(u, v)` (I32F32 bits, normalised; texel centres at
/// `(i + 0.5)/size`) and lod `lod` (I8F8 bits; the sampler's bias and
/// clamps apply, then the stored levels) with filter `mode` (`RM_MODE_*`)
/// from the texture `sampler` was set up with; writes the RGBA8 texel to
/// `out` (red in bits 0–7, alpha in bits 24–31). Bit-identical on every
/// target.
///
/// Returns `RM_STATUS_OK`; `RM_STATUS_NULL_POINTER`;
/// `RM_STATUS_MISALIGNED`; `RM_STATUS_UNINITIALISED` (`sampler` not written
/// by an init function; a zeroed one is recognised); `RM_STATUS_OUT_OF_RANGE`
/// (`mode`).
///
/// # Safety
/// `sampler` and `out` are null or valid; `sampler` was
/// zeroed or set up by an init function (and not written since), and its
/// texels are still valid. Not for two threads at once on one sampler (it
/// keeps fetch counters).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_sample(
    sampler: *mut RmSampler,
    u: i64,
    v: i64,
    lod: i16,
    mode: RmModeBits,
    out: *mut u32,
) -> RmStatus {
    if let Err(e) = check_ptr(out.cast_const(), false) {
        return e;
    }
    // SAFETY: as the caller guarantees; the borrow ends in this function.
    let (ops, slot) = match unsafe { slot_of(sampler) } {
        Ok(s) => s,
        Err(e) => return e,
    };
    let Some(mode) = Mode::from_index(mode.0) else {
        return RmStatus::OutOfRange;
    };
    let (u, v, lod) = (
        I32F32::from_bits(u),
        I32F32::from_bits(v),
        I8F8::from_bits(lod),
    );
    let texel = (ops.sample)(
        slot,
        TexCoord::from_fixed(u),
        TexCoord::from_fixed(v),
        Lod::from_fixed(lod),
        mode,
    );
    // SAFETY: non-null, aligned (checked), writable (caller); the borrow
    // of the sampler has ended (an `out` inside it would corrupt it).
    unsafe { *out = texel };
    RmStatus::Ok
}

/// Hits per chunk of [`rm_sample_batch`] (converted on the stack, then
/// sampled by the Rust batch loop).
pub(super) const BATCH_CHUNK: usize = 16;

/// `out[i]` = [`rm_sample`] of `hits[i]` with filter `mode`, for
/// `i < n`: the same texels and counters as `n` single calls, one status
/// for all.
///
/// Returns `RM_STATUS_OK`; `RM_STATUS_NULL_POINTER` (`sampler` null, or
/// either array null with `n > 0`); `RM_STATUS_MISALIGNED`;
/// `RM_STATUS_UNINITIALISED`; `RM_STATUS_OUT_OF_RANGE` (`mode`). On error
/// nothing is written.
///
/// # Safety
/// `sampler` as for [`rm_sample`]; `hits` points to `n` readable
/// [`RmHit`]s and `out` to `n` writable texels (either may be null only
/// when `n` is 0), neither inside the sampler.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_sample_batch(
    sampler: *mut RmSampler,
    hits: *const RmHit,
    n: usize,
    mode: RmModeBits,
    out: *mut u32,
) -> RmStatus {
    if let Err(e) = check_ptr(hits, n == 0).and(check_ptr(out.cast_const(), n == 0)) {
        return e;
    }
    // SAFETY: as the caller guarantees; the borrow ends in this function.
    let (_, slot) = match unsafe { slot_of(sampler) } {
        Ok(s) => s,
        Err(e) => return e,
    };
    let Some(mode) = Mode::from_index(mode.0) else {
        return RmStatus::OutOfRange;
    };
    if n == 0 {
        return RmStatus::Ok;
    }
    // SAFETY: non-null, aligned (checked), `n` readable hits and `n`
    // writable texels, disjoint from each other and from the sampler
    // (caller).
    let (hits, out) = unsafe {
        (
            core::slice::from_raw_parts(hits, n),
            core::slice::from_raw_parts_mut(out, n),
        )
    };
    let mut buf = [(TexCoord::ZERO, TexCoord::ZERO, Lod::ZERO); BATCH_CHUNK];
    for (h, o) in hits.chunks(BATCH_CHUNK).zip(out.chunks_mut(BATCH_CHUNK)) {
        for (b, x) in buf.iter_mut().zip(h) {
            *b = (
                TexCoord::from_bits(x.u),
                TexCoord::from_bits(x.v),
                Lod::from_bits(x.lod),
            );
        }
        let k = h.len().min(BATCH_CHUNK);
        let hits: Hits<'_> = buf.get(..k).unwrap_or(&[]);
        match &mut *slot {
            SlotSampler::Pyramid(s) => s.sample_batch(hits, mode, o),
            SlotSampler::Image(s) => s.sample_batch(hits, mode, o),
        };
    }
    RmStatus::Ok
}

/// Anisotropic filtered texel at `(u, v)` for the pixel footprint `fp`
/// (the texture-coordinate derivatives): up to the sampler's
/// `max_anisotropy` trilinear probes along the footprint's major axis at
/// the lod of its minor axis; writes the RGBA8 texel to `out`.
///
/// Returns `RM_STATUS_OK`, `RM_STATUS_NULL_POINTER`,
/// `RM_STATUS_MISALIGNED` or `RM_STATUS_UNINITIALISED`.
///
/// # Safety
/// `sampler` as for [`rm_sample`]; `fp` points to a readable
/// [`RmFootprint`] and `out` to a writable texel (neither inside the
/// sampler).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_sample_aniso(
    sampler: *mut RmSampler,
    u: i64,
    v: i64,
    fp: *const RmFootprint,
    out: *mut u32,
) -> RmStatus {
    if let Err(e) = check_ptr(fp, false).and(check_ptr(out.cast_const(), false)) {
        return e;
    }
    // SAFETY: non-null, aligned (checked), readable (caller).
    let f = unsafe { fp.read() };
    // SAFETY: as the caller guarantees; the borrow ends in this function.
    let (_, slot) = match unsafe { slot_of(sampler) } {
        Ok(s) => s,
        Err(e) => return e,
    };
    let fp = Footprint {
        x: [TexCoord::from_bits(f.dudx), TexCoord::from_bits(f.dvdx)],
        y: [TexCoord::from_bits(f.dudy), TexCoord::from_bits(f.dvdy)],
    };
    let (u, v) = (I32F32::from_bits(u), I32F32::from_bits(v));
    // Every key's anisotropic code: linked only when this is called.
    let texel: Texel = match slot {
        SlotSampler::Pyramid(s) => {
            s.sample_aniso(TexCoord::from_fixed(u), TexCoord::from_fixed(v), &fp)
        }
        SlotSampler::Image(s) => {
            s.sample_aniso(TexCoord::from_fixed(u), TexCoord::from_fixed(v), &fp)
        }
    };
    // SAFETY: non-null, aligned (checked), writable (caller); the borrow
    // of the sampler has ended.
    unsafe { *out = texel };
    RmStatus::Ok
}
