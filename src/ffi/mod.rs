//! C ABI for soft-core firmware written in C (feature `ffi`).
//!
//! Every function is `extern "C"`, takes and returns plain `#[repr(C)]`
//! types or fixed-point values as their raw integer bits, and reports
//! errors as [`RmStatus`] codes. Nothing panics across the boundary: every
//! pointer is checked for null, every length is checked, and the library
//! code behind it is panic-free on these paths (machine-checked by
//! `scripts/link-checks`). The header `include/raymip.h` is generated from
//! this module by `cbindgen` (CI fails when it is stale); the static
//! library is built by the `raymip-ffi` crate (`ffi/`).
//!
//! MIP generation ([`rm_mip_generate`]) runs in place in the caller's
//! buffer, so a C controller can build its pyramids at start-up; it is
//! panic-free like the rest (every access is checked), machine-checked by
//! the same panic-never link.
//!
//! # Number formats (raw bits)
//!
//! | value | Rust type | C type |
//! |---|---|---|
//! | position, UV, texture coordinate | I32F32 | `int64_t` |
//! | path length `Pl`, hit distance `t` | U32F32 | `uint64_t` |
//! | cone width | I32F32 | `int64_t` |
//! | spread angle (radians) | I2F30 | `int32_t` |
//! | table entry `log2 Pb`, `Δ` | I16F16 | `int32_t` (`RM_UNTEXTURED` = `INT32_MIN`) |
//! | level of detail | I8F8 | `int16_t` |
//! | `|n·d|` | U1F31 | `uint32_t` |
//! | texel | RGBA8888 | `uint32_t` (little-endian bytes r, g, b, a) |
//!
//! # Safety
//!
//! This is the crate's only module with `unsafe` code (the crate is
//! `#![deny(unsafe_code)]` with the feature, `#![forbid(unsafe_code)]`
//! without it): turning caller pointers into references and slices. Each
//! function documents what the caller guarantees: non-null pointers (null
//! is checked and reported), pointing to the stated number of valid,
//! aligned, initialised elements. A pointer that is not aligned for its
//! type is reported ([`RmStatus::Misaligned`]) and never dereferenced.
//! Inputs are read before outputs are written, so an input may point into
//! an output (pushing an entry of the same ray stack is allowed).
#![allow(unsafe_code)]

use fixed::types::{I2F30, I8F8, I16F16, I32F32, U1F31, U32F32};

use crate::camera::PixelSpread;
use crate::lod::{clamp_lod, cone_lod, table_lod};
use crate::raystack::{DEFAULT_CAPACITY, PathState, RayCone};
use crate::table::{BuildStats, Log2Pb, PbTable, TableError, TexTriangle};
use crate::texture::kernel::Precision;
use crate::texture::sampler::aniso::Footprint;
use crate::texture::sampler::dynamic::DynSampler;
use crate::texture::sampler::state::SrgbOutput;
use crate::texture::storage::format::{AnyFormat, ColorSpace, Format, TexelFormat};
use crate::texture::storage::image::{Image, image_len};
use crate::texture::storage::mip::{Geometry, MipError, Pyramid, Texel, generate, pyramid_len};
use crate::texture::{AddressMode, Mode, SamplerDesc, SamplerState};

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
    /// The [`RmSampler`] was not set up by [`rm_sampler_init`].
    Uninitialised = -10,
}

/// Filter mode of [`rm_sample`] (the numbering of the Rust `Mode`).
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RmMode {
    /// Bilinear within a level, linear between levels.
    Trilinear = 0,
    /// Bilinear within the nearest level `floor(lod + 1/2)`.
    BilinearNearestLevel = 1,
    /// Nearest texel of the nearest level.
    Nearest = 2,
    /// Nearest texel in each of two levels, linear between levels.
    NearestTexelLinearLevel = 3,
}
const _: () = assert!(
    RmMode::Trilinear as u8 == Mode::Trilinear as u8
        && RmMode::BilinearNearestLevel as u8 == Mode::BilinearNearestLevel as u8
        && RmMode::Nearest as u8 == Mode::Nearest as u8
        && RmMode::NearestTexelLinearLevel as u8 == Mode::NearestTexelLinearLevel as u8
);

/// Addressing of a texture axis: [`rm_sampler_init`] takes one for both
/// axes, [`RmSamplerDesc`] one per axis.
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RmAddress {
    /// Repeat: only the fractional part of a coordinate is used.
    Wrap = 0,
    /// Clamp to edge.
    Clamp = 1,
    /// Repeat, every other copy mirrored (D3D `MIRROR`).
    Mirror = 2,
    /// Mirror once around 0, then clamp to the edge (D3D `MIRROR_ONCE`).
    MirrorOnce = 3,
    /// Texels outside the level read the border colour (D3D `BORDER`).
    Border = 4,
}

impl RmAddress {
    /// The address mode numbered `n` (the discriminants above).
    fn mode(n: u8) -> Option<AddressMode> {
        match n {
            0 => Some(AddressMode::Wrap),
            1 => Some(AddressMode::ClampToEdge),
            2 => Some(AddressMode::Mirror),
            3 => Some(AddressMode::MirrorOnce),
            4 => Some(AddressMode::ClampToBorder),
            _ => None,
        }
    }
}

/// Precision tier of a sampler ([`RmSamplerDesc::precision`]).
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RmPrecision {
    /// ACCURATE (default): linear filtering ≤ 0.5625 LSB from the exact
    /// f64 filter, sRGB re-encoded ≤ 0.6875 LSB; bit-identical on every
    /// target.
    Accurate = 0,
    /// FAST: GPU precision (8-bit sub-texel weights and lod fraction,
    /// exact filter at the quantized position), linear filtering ≤ 1.5 LSB
    /// from the exact f64 filter (proof in the Rust `texture::kernel::fast`
    /// docs); bit-identical on every target.
    Fast = 1,
}

/// Result encoding of an sRGB texture ([`RmSamplerDesc::srgb_output`]).
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RmSrgbOutput {
    /// Re-encoded to sRGB (what a GPU writes to an sRGB render target).
    Encoded = 0,
    /// Linear, rounded to 8 bits (what a shader reads from an sRGB view).
    Linear = 1,
}

/// Pixel format of an [`RmImage`] (the numbering of the Rust
/// `TexelFormat`).
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RmFormat {
    /// 8 bits per channel, bytes r, g, b, a.
    Rgba8 = 0,
    /// 16 bits little-endian: red 5, green 6, blue 5 (alpha 255).
    Rgb565 = 1,
    /// 16 bits: red 5, green 5, blue 5, alpha 1.
    Rgba5551 = 2,
    /// 16 bits: 4 bits per channel.
    Rgba4444 = 3,
    /// Luminance and alpha, 8 bits each.
    La8 = 4,
    /// Luminance, 8 bits.
    L8 = 5,
    /// Alpha, 8 bits (colour 0).
    A8 = 6,
    /// BC1 (DXT1): 8 bytes per 4×4 block.
    Bc1 = 7,
    /// BC2 (DXT3): 16 bytes per block.
    Bc2 = 8,
    /// BC3 (DXT5): 16 bytes per block.
    Bc3 = 9,
    /// BC4: 8 bytes per block, one channel (red).
    Bc4 = 10,
}
const _: () = {
    let c = [
        RmFormat::Rgba8,
        RmFormat::Rgb565,
        RmFormat::Rgba5551,
        RmFormat::Rgba4444,
        RmFormat::La8,
        RmFormat::L8,
        RmFormat::A8,
        RmFormat::Bc1,
        RmFormat::Bc2,
        RmFormat::Bc3,
        RmFormat::Bc4,
    ];
    assert!(c.len() == TexelFormat::ALL.len());
    let mut i = 0;
    while i < c.len() {
        assert!(c[i] as u8 == TexelFormat::ALL[i] as u8);
        i += 1;
    }
};

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

/// Raw bits of the untextured table marker (`INT32_MIN`).
pub const RM_UNTEXTURED: i32 = i32::MIN;
/// Capacity of [`RmRayStack`] (10, as in the hardware paper).
pub const RM_RAY_STACK_CAPACITY: usize = 10;
const _: () = assert!(RM_RAY_STACK_CAPACITY == DEFAULT_CAPACITY);

/// One triangle for the Pb table.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RmTriangle {
    /// Vertex positions, I32F32 bits (scene units).
    pub positions: [[i64; 3]; 3],
    /// Vertex UVs, I32F32 bits (texture repeats).
    pub uvs: [[i64; 2]; 3],
    /// Level-0 texture width in texels (≥ 1 when textured).
    pub tex_width: u32,
    /// Level-0 texture height in texels (≥ 1 when textured).
    pub tex_height: u32,
    /// 0 = untextured (gets [`RM_UNTEXTURED`], no table work), else textured.
    pub textured: u8,
}

impl RmTriangle {
    /// The Rust table input: `None` when untextured, `ZeroTextureSize`
    /// for a textured triangle with a zero texture side.
    ///
    /// # Errors
    /// [`TableError::ZeroTextureSize`].
    pub fn tex_triangle(&self) -> Result<Option<TexTriangle>, TableError> {
        if self.textured == 0 {
            return Ok(None);
        }
        TexTriangle::new(
            self.positions.map(|p| p.map(I32F32::from_bits)),
            self.uvs.map(|p| p.map(I32F32::from_bits)),
            self.tex_width,
            self.tex_height,
        )
        .map(Some)
    }
}

/// What a table build or update wrote.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RmBuildStats {
    /// Entries computed for textured triangles.
    pub textured: u32,
    /// Untextured markers written.
    pub untextured: u32,
    /// Textured triangles with zero world area.
    pub degenerate_geometry: u32,
    /// Textured triangles with zero UV area.
    pub degenerate_uv: u32,
}

/// One ray stack entry: the path state LOD needs across bounces.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RmPathState {
    /// Accumulated path length `Pl`, U32F32 bits (scene units).
    pub pl: u64,
    /// Ray-cone width, I32F32 bits (scene units).
    pub cone_width: i64,
    /// Ray-cone spread angle, I2F30 bits (radians).
    pub cone_spread: i32,
    /// 8-bit ray mask of the path.
    pub mask: u8,
    /// Bounces so far (saturates at 255).
    pub depth: u8,
    /// Non-zero once any quantity saturated.
    pub saturated: u8,
}

/// A fixed-capacity ray stack in caller memory (initialise with
/// [`rm_ray_stack_init`]).
///
/// A C struct of plain integers rather than the Rust `RayStack` in opaque
/// storage (as [`RmSampler`] is): C code reads its entries (peeks, pushes
/// one of its own entries), and every bit pattern a C caller may leave in
/// it is valid, so a corrupt `len` is an error case (read as full, popped
/// in range) instead of undefined behaviour. `RayStack` keeps its entries
/// in a `heapless::Vec` whose layout is not fixed and its `PathState`s hold
/// a `bool`; in caller memory, a stray write would be undefined behaviour.
/// The capacity is the Rust default (checked at compile time) and the
/// entries are converted to and from `PathState`; what is left is a bounds
/// check and a length update per push or pop.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RmRayStack {
    /// Storage; entries `0 .. len` are valid.
    pub entries: [RmPathState; RM_RAY_STACK_CAPACITY],
    /// Number of valid entries (`0 ..= RM_RAY_STACK_CAPACITY`).
    pub len: u32,
}

/// A MIP pyramid in caller memory: levels stored one after another, level 0
/// first, each row-major (`rm_pyramid_len` texels in all).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct RmTexture {
    /// The texels (RGBA8888).
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

impl From<BuildStats> for RmBuildStats {
    fn from(s: BuildStats) -> Self {
        Self {
            textured: s.textured,
            untextured: s.untextured,
            degenerate_geometry: s.degenerate_geometry,
            degenerate_uv: s.degenerate_uv,
        }
    }
}

impl From<PathState> for RmPathState {
    fn from(s: PathState) -> Self {
        Self {
            pl: s.pl.to_bits(),
            cone_width: s.cone.width.to_bits(),
            cone_spread: s.cone.spread.to_bits(),
            mask: s.mask,
            depth: s.depth,
            saturated: u8::from(s.saturated),
        }
    }
}

impl From<RmPathState> for PathState {
    fn from(s: RmPathState) -> Self {
        let pl = U32F32::from_bits(s.pl);
        Self {
            pl,
            pl_norm: crate::log2_fast::NormPl::new(pl),
            cone: RayCone {
                width: I32F32::from_bits(s.cone_width),
                spread: I2F30::from_bits(s.cone_spread),
            },
            // The C ABI carries no ray differentials.
            #[cfg(feature = "raydiff")]
            diff: crate::raydiff::RayDiff::ZERO,
            mask: s.mask,
            depth: s.depth,
            saturated: s.saturated != 0,
        }
    }
}

fn table_status(e: TableError) -> RmStatus {
    match e {
        TableError::ZeroTextureSize => RmStatus::ZeroSize,
        TableError::TableFull => RmStatus::TableFull,
        _ => RmStatus::OutOfRange,
    }
}

fn mip_status(e: MipError) -> RmStatus {
    match e {
        MipError::ZeroSize => RmStatus::ZeroSize,
        MipError::BufferTooShort { .. } => RmStatus::BufferTooShort,
        _ => RmStatus::OutOfRange,
    }
}

/// `NullPointer` if `p` is null and `may_be_null` is false, `Misaligned` if
/// it is not aligned for `T` (null counts as aligned).
fn check_ptr<T>(p: *const T, may_be_null: bool) -> Result<(), RmStatus> {
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

/// The camera's pixel spread from its I2F30 `bits`; `BadAngle` unless
/// `0 < γ < 2` radians.
fn spread_from_bits(bits: i32) -> Result<PixelSpread, RmStatus> {
    PixelSpread::from_angle(I2F30::from_bits(bits)).map_err(|_| RmStatus::BadAngle)
}

/// Computes table entries `start .. start + count` of `entries` (length
/// `len`) from `tris[0 .. count]` for a camera with pixel spread angle
/// `spread` (I2F30 bits, `0 < γ < 2` radians); fills `stats` if not null.
/// Returns `TableFull` when `start + count > len` (the entries that fit are
/// written), `BadAngle`, `ZeroSize` (a textured triangle with a zero texture
/// side; entries before it are written), `NullPointer`, `Misaligned`.
///
/// # Safety
/// `entries` points to `len` writable `int32_t`, `tris` to `count`
/// readable [`RmTriangle`]s (either may be null only when its length is 0),
/// `stats` is null or points to a writable [`RmBuildStats`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_table_update(
    entries: *mut i32,
    len: usize,
    start: usize,
    tris: *const RmTriangle,
    count: usize,
    spread: i32,
    stats: *mut RmBuildStats,
) -> RmStatus {
    let checked = check_ptr(entries.cast_const(), len == 0)
        .and(check_ptr(tris, count == 0))
        .and(check_ptr(stats.cast_const(), true))
        .and(spread_from_bits(spread));
    let spread = match checked {
        Ok(s) => s,
        Err(e) => return e,
    };
    let entries: &mut [Log2Pb] = if len == 0 {
        &mut []
    } else {
        // SAFETY: non-null, aligned (checked), `len` writable elements
        // (caller); `Log2Pb` is `repr(transparent)` over `I16F16`, itself
        // over `i32`, and every `i32` is a valid entry (markers included).
        unsafe { core::slice::from_raw_parts_mut(entries.cast::<Log2Pb>(), len) }
    };
    let tris: &[RmTriangle] = if count == 0 {
        &[]
    } else {
        // SAFETY: non-null (checked), `count` readable elements (caller).
        unsafe { core::slice::from_raw_parts(tris, count) }
    };
    // The items in order, as `PbTable::update` takes them: the first one
    // with no slot left gives `TableFull`, the first invalid one (a zero
    // texture side) its error; the ones before are written and counted.
    let slots = len.saturating_sub(start);
    let valid = tris.iter().take_while(|t| t.tex_triangle().is_ok()).count();
    let fit = valid.min(slots);
    let items = tris
        .iter()
        .take(fit)
        .map(|t| t.tex_triangle().ok().flatten());
    let (st, status) = match PbTable::new(entries).update(start, items, &spread) {
        Ok(st) if fit == tris.len() => (st, RmStatus::Ok),
        Ok(st) if fit == slots => (st, RmStatus::TableFull),
        Ok(st) => {
            let e = tris.get(fit).map_or(Ok(None), RmTriangle::tex_triangle);
            (st, e.map_or_else(table_status, |_| RmStatus::OutOfRange))
        }
        // Unreachable: every item given has a slot.
        Err(e) => (BuildStats::default(), table_status(e)),
    };
    if !stats.is_null() {
        // SAFETY: non-null, aligned (checked), writable (caller).
        unsafe { *stats = st.into() };
    }
    status
}

/// [`rm_table_update`] from entry 0 (a whole build).
///
/// # Safety
/// As [`rm_table_update`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_table_build(
    entries: *mut i32,
    len: usize,
    tris: *const RmTriangle,
    count: usize,
    spread: i32,
    stats: *mut RmBuildStats,
) -> RmStatus {
    // SAFETY: same contract.
    unsafe { rm_table_update(entries, len, 0, tris, count, spread, stats) }
}

/// Table lod `log2 Pl − log2 Pb` for path length `pl` (U32F32 bits) and
/// table entry `entry` (I16F16 bits); writes the lod (I8F8 bits) to `out`.
/// Returns `Untextured` (and writes nothing) for [`RM_UNTEXTURED`].
///
/// # Safety
/// `out` is null (→ `NullPointer`) or points to a writable `int16_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_table_lod(pl: u64, entry_bits: i32, out: *mut i16) -> RmStatus {
    if let Err(e) = check_ptr(out.cast_const(), false) {
        return e;
    }
    match table_lod(U32F32::from_bits(pl), Log2Pb::from_bits(entry_bits)) {
        Some(l) => {
            // SAFETY: non-null, writable (caller).
            unsafe { *out = l.to_bits() };
            RmStatus::Ok
        }
        None => RmStatus::Untextured,
    }
}

/// `|n·d| = 1` in U1F31 bits: passed to [`rm_cone_lod`] it leaves the
/// normal term out (`log2 1 = 0` exactly).
pub const RM_COS_ONE: u32 = 0x8000_0000;

/// Ray-cone lod `Δ + log2|w| − log2|n·d|` (I8F8 bits) for cone width
/// `width` (I32F32 bits), triangle constant `delta` (I16F16 bits) and
/// `|n·d|` (U1F31 bits), exactly as the Rust `cone_lod`: `|n·d|` is clamped
/// to `[2⁻¹⁶, 1]`, so a grazing hit (`n_dot_d = 0`) is 16 levels coarser
/// than a head-on one. [`RM_COS_ONE`] (or more) leaves the normal term out.
#[unsafe(no_mangle)]
pub extern "C" fn rm_cone_lod(width: i64, delta: i32, n_dot_d: u32) -> i16 {
    let c = U1F31::from_bits(n_dot_d);
    cone_lod(I32F32::from_bits(width), I16F16::from_bits(delta), Some(c)).to_bits()
}

/// Ray-cone triangle constant `Δ = −log2 Pb − log2 γ` (I16F16 bits, as
/// [`rm_cone_lod`] takes it) of table entry `entry_bits` (I16F16 bits) for a
/// camera with pixel spread angle `spread` (I2F30 bits, `0 < γ < 2`
/// radians); the same value as the Rust `Log2Pb::delta`, saturating.
/// Returns `Untextured` (and writes nothing) for [`RM_UNTEXTURED`],
/// `BadAngle` for `γ ≤ 0`.
///
/// # Safety
/// `out` is null (→ `NullPointer`) or points to a writable `int32_t`
/// (→ `Misaligned` if it is not aligned).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_delta(entry_bits: i32, spread: i32, out: *mut i32) -> RmStatus {
    let spread = match check_ptr(out.cast_const(), false).and(spread_from_bits(spread)) {
        Ok(s) => s,
        Err(e) => return e,
    };
    match Log2Pb::from_bits(entry_bits).delta(&spread) {
        Some(d) => {
            // SAFETY: non-null, aligned, writable (caller).
            unsafe { *out = d.to_bits() };
            RmStatus::Ok
        }
        None => RmStatus::Untextured,
    }
}

/// `lod` (I8F8 bits) clamped to the stored levels `[0, levels − 1]`.
#[unsafe(no_mangle)]
pub extern "C" fn rm_clamp_lod(lod: i16, levels: u8) -> i16 {
    clamp_lod(I8F8::from_bits(lod), levels).to_bits()
}

/// Empties `stack`.
///
/// # Safety
/// `stack` is null (→ `NullPointer`) or points to a writable [`RmRayStack`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_ray_stack_init(stack: *mut RmRayStack) -> RmStatus {
    if let Err(e) = check_ptr(stack.cast_const(), false) {
        return e;
    }
    // SAFETY: non-null, writable (caller).
    unsafe {
        *stack = RmRayStack {
            entries: [RmPathState::default(); RM_RAY_STACK_CAPACITY],
            len: 0,
        };
    }
    RmStatus::Ok
}

/// Pushes `state` (which may point into `stack`, e.g. to one of its
/// entries); `StackFull` (stack unchanged) when full.
///
/// # Safety
/// `stack` and `state` are null (→ `NullPointer`), misaligned
/// (→ `Misaligned`) or valid (`stack` initialised by [`rm_ray_stack_init`];
/// a corrupt `len` above the capacity is read as full).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_ray_stack_push(
    stack: *mut RmRayStack,
    state: *const RmPathState,
) -> RmStatus {
    if let Err(e) = check_ptr(stack.cast_const(), false).and(check_ptr(state, false)) {
        return e;
    }
    // SAFETY: non-null, aligned (checked), valid (caller). The input is
    // copied out before the stack is borrowed mutably, so `state` may alias it.
    let state = unsafe { state.read() };
    // SAFETY: as above; no other reference to the stack is live.
    let stack = unsafe { &mut *stack };
    let Some(slot) = stack.entries.get_mut(stack.len as usize) else {
        return RmStatus::StackFull;
    };
    *slot = state;
    stack.len += 1;
    RmStatus::Ok
}

/// Pops the most recent state into `out`; `StackEmpty` when empty.
///
/// # Safety
/// As [`rm_ray_stack_push`]; `out` writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_ray_stack_pop(
    stack: *mut RmRayStack,
    out: *mut RmPathState,
) -> RmStatus {
    if let Err(e) = check_ptr(stack.cast_const(), false).and(check_ptr(out.cast_const(), false)) {
        return e;
    }
    // SAFETY: non-null, aligned (checked), valid (caller); the borrow ends
    // before `out` (which may point into the stack) is written.
    let s = {
        let stack = unsafe { &mut *stack };
        let len = (stack.len as usize).min(RM_RAY_STACK_CAPACITY);
        let Some(i) = len.checked_sub(1) else {
            return RmStatus::StackEmpty;
        };
        let Some(&s) = stack.entries.get(i) else {
            return RmStatus::StackEmpty;
        };
        stack.len = i as u32;
        s
    };
    // SAFETY: non-null, aligned (checked), writable (caller).
    unsafe { out.write(s) };
    RmStatus::Ok
}

/// A primary ray's state (`Pl = 0`, width 0, spread `spread` in I2F30
/// bits) with ray mask `mask`.
///
/// # Safety
/// `out` is null (→ `NullPointer`) or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_path_primary(spread: i32, mask: u8, out: *mut RmPathState) -> RmStatus {
    let spread = match check_ptr(out.cast_const(), false).and(spread_from_bits(spread)) {
        Ok(s) => s,
        Err(e) => return e,
    };
    // SAFETY: non-null, writable (caller).
    unsafe { *out = PathState::primary(&spread, mask).into() };
    RmStatus::Ok
}

/// After a hit at distance `t` (U32F32 bits): `Pl += t`, `w += γ·t`
/// (saturating; sets `saturated`).
///
/// # Safety
/// `state` is null (→ `NullPointer`) or valid and writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_path_advance(state: *mut RmPathState, t: u64) -> RmStatus {
    // SAFETY: same contract.
    unsafe { update_state(state, |s| s.advance(U32F32::from_bits(t))) }
}

/// A reflection/refraction continuation: spread `+= beta` (I2F30 bits,
/// surface spread angle), depth + 1.
///
/// # Safety
/// As [`rm_path_advance`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_path_bounce(state: *mut RmPathState, beta: i32) -> RmStatus {
    // SAFETY: same contract.
    unsafe { update_state(state, |s| s.bounce(I2F30::from_bits(beta))) }
}

/// Replaces `*state` by `f(*state)` through `PathState`.
///
/// # Safety
/// As [`rm_path_advance`].
unsafe fn update_state(
    state: *mut RmPathState,
    f: impl FnOnce(PathState) -> PathState,
) -> RmStatus {
    if let Err(e) = check_ptr(state.cast_const(), false) {
        return e;
    }
    // SAFETY: non-null, aligned (checked), valid and writable (caller).
    unsafe { state.write(f(PathState::from(state.read())).into()) };
    RmStatus::Ok
}

/// Texels of a pyramid of `levels` levels of a `width × height` texture
/// (0 when a side is 0).
#[unsafe(no_mangle)]
pub extern "C" fn rm_pyramid_len(width: u32, height: u32, levels: u8) -> usize {
    pyramid_len(width, height, levels)
}

/// Generates levels `1 .. levels` of a `width × height` pyramid in place
/// from level 0 (the first `width·height` texels at `texels`), with the
/// filter of `mip::generate` (2×2 box, round half up; exact area box for odd
/// sides). Set-up time, not per hit.
///
/// Returns `NullPointer`, `ZeroSize`, `OutOfRange` (bad level count or side
/// above 32768) or `BufferTooShort` (`len` < [`rm_pyramid_len`]; nothing is
/// written).
///
/// # Safety
/// `texels` is null (→ `NullPointer`) or points to `len` writable texels.
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

/// Size of an [`RmSampler`] in 64-bit words (1024 bytes: enough for the
/// sampler of a pyramid or an image on 32- and 64-bit targets, checked at
/// compile time; 808 bytes are used on x86-64).
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
const SAMPLER_MAGIC: u64 = u64::from_le_bytes(*b"raymipSm");

/// The texture behind a sampler: an RGBA8 pyramid or an image in any
/// format. One `match` per call picks it (none per texel).
enum SlotSampler {
    Pyramid(DynSampler<Pyramid<'static>>),
    Image(DynSampler<Image<'static, AnyFormat>>),
}

/// `$s` bound to the slot's [`DynSampler`] in both arms.
macro_rules! each_slot {
    ($slot:expr, $s:ident => $e:expr) => {
        match $slot {
            SlotSampler::Pyramid($s) => $e,
            SlotSampler::Image($s) => $e,
        }
    };
}

/// What an [`RmSampler`] holds: the magic word, then the Rust sampler over
/// the caller's texels (their lifetime is the caller's promise).
#[repr(C)]
struct SamplerSlot {
    magic: u64,
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
    /// Border colour (RGBA8888, linear) of `RM_ADDRESS_BORDER`.
    pub border: u32,
    /// LOD bias, I8F8 bits, `[−16, 16)` levels.
    pub lod_bias: i16,
    /// Lower lod clamp, I8F8 bits (at most `max_lod`).
    pub min_lod: i16,
    /// Upper lod clamp, I8F8 bits.
    pub max_lod: i16,
    /// Address mode of `u` (`RM_ADDRESS_*`).
    pub address_u: RmAddressBits,
    /// Address mode of `v` (`RM_ADDRESS_*`).
    pub address_v: RmAddressBits,
    /// Maximum anisotropy of [`rm_sample_aniso`], `1 ..= 16` (1 =
    /// isotropic).
    pub max_anisotropy: u8,
    /// Result encoding of sRGB images (`RM_SRGB_OUTPUT_*`).
    pub srgb_output: u8,
    /// Precision tier (`RM_PRECISION_*`).
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
            lod_bias: I8F8::from_bits(self.lod_bias),
            min_lod: I8F8::from_bits(self.min_lod),
            max_lod: I8F8::from_bits(self.max_lod),
            max_anisotropy: self.max_anisotropy,
            srgb_output,
        })
        .map_err(|_| RmStatus::OutOfRange)?;
        Ok((state, precision))
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

/// Writes the default [`RmSamplerDesc`] to `out` (see its docs). Returns
/// `NullPointer` or `Misaligned`.
///
/// # Safety
/// `out` is null (→ `NullPointer`) or points to a writable
/// [`RmSamplerDesc`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_sampler_desc_default(out: *mut RmSamplerDesc) -> RmStatus {
    if let Err(e) = check_ptr(out.cast_const(), false) {
        return e;
    }
    // SAFETY: non-null, aligned (checked), writable (caller).
    unsafe { out.write(RmSamplerDesc::default()) };
    RmStatus::Ok
}

/// Bytes an [`RmImage`] of `format` with `levels` levels (capped at the
/// full chain) of a `width × height` level 0 needs; 0 for a zero side or
/// an unknown format.
#[unsafe(no_mangle)]
pub extern "C" fn rm_image_len(width: u32, height: u32, levels: u8, format: u8) -> usize {
    match TexelFormat::from_index(format) {
        Some(f) if width > 0 && height > 0 => image_len(width, height, levels, f),
        _ => 0,
    }
}

/// Writes `slot` into `sampler`.
///
/// # Safety
/// `sampler` is non-null, aligned and writable.
unsafe fn write_slot(sampler: *mut RmSampler, sampler_slot: SlotSampler) {
    let slot = SamplerSlot {
        magic: SAMPLER_MAGIC,
        sampler: sampler_slot,
    };
    // SAFETY: non-null, aligned and large enough (caller; size and
    // alignment checked at compile time), writable (caller).
    unsafe { sampler.cast::<SamplerSlot>().write(slot) };
}

/// The pyramid of `tex` after its checks.
///
/// # Safety
/// As [`rm_sampler_init`]'s `tex`.
unsafe fn pyramid_of(tex: *const RmTexture) -> Result<Pyramid<'static>, RmStatus> {
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

/// Sets up `sampler` for the pyramid `tex` with addressing `address`
/// (`RM_ADDRESS_*`, both axes) and otherwise default settings: checks the
/// texture once (size, levels, length) and stores what [`rm_sample`]
/// needs. On error `sampler` is left unchanged.
///
/// Returns `NullPointer`, `Misaligned`, `OutOfRange` (address, level count
/// or a side above 32768), `ZeroSize` or `BufferTooShort`.
///
/// # Safety
/// `sampler` and `tex` are null (→ `NullPointer`) or valid;
/// `tex->texels` points to `tex->len` readable texels that stay valid and
/// unchanged while the sampler is used.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_sampler_init(
    sampler: *mut RmSampler,
    tex: *const RmTexture,
    address: RmAddressBits,
) -> RmStatus {
    let desc = RmSamplerDesc {
        address_u: address,
        address_v: address,
        ..RmSamplerDesc::default()
    };
    // SAFETY: the caller's guarantees are this function's; `desc` is a
    // valid local.
    unsafe { rm_sampler_init_desc(sampler, tex, &desc) }
}

/// Sets up `sampler` for the RGBA8 pyramid `tex` with the settings `desc`
/// (address mode per axis, border, bias and clamps, anisotropy, tier),
/// checked once here: every sample then runs the specialised path of the
/// configuration (the Rust `DynSampler` key table). On error `sampler` is
/// left unchanged.
///
/// Returns `NullPointer`, `Misaligned`, `OutOfRange` (a `desc` field, level
/// count or a side above 32768), `ZeroSize` or `BufferTooShort`.
///
/// # Safety
/// `sampler`, `tex` and `desc` are null (→ `NullPointer`) or valid;
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
    // SAFETY: `sampler` non-null, aligned (checked), writable (caller).
    unsafe { write_slot(sampler, SlotSampler::Pyramid(s)) };
    RmStatus::Ok
}

/// Sets up `sampler` for the image `img` (any [`RmFormat`], linear or
/// sRGB) with the settings `desc`, checked once here. Formats are decoded
/// per texel read (BC1–BC4 decode the texel's block; a Rust firmware puts
/// a texel cache in front). On error `sampler` is left unchanged.
///
/// Returns `NullPointer`, `Misaligned`, `OutOfRange` (a `desc` field, the
/// format, an sRGB flag the format has no variant for, level count or a
/// side above 32768), `ZeroSize` or `BufferTooShort`.
///
/// # Safety
/// `sampler`, `img` and `desc` are null (→ `NullPointer`) or valid;
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
    // SAFETY: `sampler` non-null, aligned (checked), writable (caller).
    unsafe { write_slot(sampler, SlotSampler::Image(s)) };
    RmStatus::Ok
}

/// The set-up sampler behind `sampler`, or `NullPointer`, `Misaligned`,
/// `Uninitialised`.
///
/// # Safety
/// `sampler` is null or valid and zeroed or set up by an init function;
/// no other reference to it is live for `'a`.
unsafe fn slot_of<'a>(sampler: *mut RmSampler) -> Result<&'a mut SlotSampler, RmStatus> {
    check_ptr(sampler.cast_const(), false)?;
    let slot = sampler.cast::<SamplerSlot>();
    // SAFETY: non-null, aligned (checked), readable (caller); only the
    // `u64` magic word is read (any bits are valid), no reference is made.
    if unsafe { (&raw const (*slot).magic).read() } != SAMPLER_MAGIC {
        return Err(RmStatus::Uninitialised);
    }
    // SAFETY: written by an init function (magic, caller); no other
    // reference to it is live; its texels are valid (caller).
    Ok(unsafe { &mut (*slot).sampler })
}

/// Filtered texel at `(u, v)` (I32F32 bits, normalised; texel centres at
/// `(i + 0.5)/size`) and lod `lod` (I8F8 bits; the sampler's bias and
/// clamps apply, then the stored levels) with filter `mode` (`RM_MODE_*`)
/// from the texture `sampler` was set up with; writes RGBA8888 to `out`.
/// The same texel as the Rust `Sampler::sample` of that configuration.
/// Returns `NullPointer`, `Misaligned`, `Uninitialised` (`sampler` not
/// written by an init function; a zeroed one is recognised) or
/// `OutOfRange` (mode).
///
/// # Safety
/// `sampler` and `out` are null (→ `NullPointer`) or valid; `sampler` was
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
    let slot = match unsafe { slot_of(sampler) } {
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
    let texel = each_slot!(slot, s => s.sample(u, v, lod, mode));
    // SAFETY: non-null, aligned (checked), writable (caller); the borrow
    // of the sampler has ended (an `out` inside it would corrupt it).
    unsafe { *out = texel };
    RmStatus::Ok
}

/// Hits per chunk of [`rm_sample_batch`] (converted on the stack, then
/// sampled by the Rust batch loop).
const BATCH_CHUNK: usize = 16;

/// `out[i]` = [`rm_sample`] of `hits[i]` with filter `mode`, for
/// `i < n`: the same texels and counters as `n` single calls, one status
/// for all. Returns `NullPointer` (either array null with `n > 0`),
/// `Misaligned`, `Uninitialised` or `OutOfRange` (mode); on error nothing
/// is written.
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
    let slot = match unsafe { slot_of(sampler) } {
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
    let mut buf = [(I32F32::ZERO, I32F32::ZERO, I8F8::ZERO); BATCH_CHUNK];
    for (h, o) in hits.chunks(BATCH_CHUNK).zip(out.chunks_mut(BATCH_CHUNK)) {
        for (b, x) in buf.iter_mut().zip(h) {
            *b = (
                I32F32::from_bits(x.u),
                I32F32::from_bits(x.v),
                I8F8::from_bits(x.lod),
            );
        }
        let k = h.len().min(BATCH_CHUNK);
        each_slot!(&mut *slot, s => s.sample_batch(buf.get(..k).unwrap_or(&[]), mode, o));
    }
    RmStatus::Ok
}

/// Anisotropic filtered texel at `(u, v)` for the pixel footprint `fp`
/// (the texture-coordinate derivatives): up to the sampler's
/// `max_anisotropy` trilinear probes along the footprint's major axis at
/// the lod of its minor axis (the Rust `Sampler::sample_aniso`); writes
/// RGBA8888 to `out`. Returns `NullPointer`, `Misaligned` or
/// `Uninitialised`.
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
    let slot = match unsafe { slot_of(sampler) } {
        Ok(s) => s,
        Err(e) => return e,
    };
    let fp = Footprint {
        x: [I32F32::from_bits(f.dudx), I32F32::from_bits(f.dvdx)],
        y: [I32F32::from_bits(f.dudy), I32F32::from_bits(f.dvdy)],
    };
    let (u, v) = (I32F32::from_bits(u), I32F32::from_bits(v));
    let texel: Texel = each_slot!(slot, s => s.sample_aniso(u, v, &fp));
    // SAFETY: non-null, aligned (checked), writable (caller); the borrow
    // of the sampler has ended.
    unsafe { *out = texel };
    RmStatus::Ok
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use proptest::prelude::*;

    /// `n` pseudo-random words (a 64-bit LCG from `seed`).
    fn lcg_texels(seed: u64, n: usize) -> std::vec::Vec<u32> {
        let mut x = seed;
        (0..n)
            .map(|_| {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (x >> 32) as u32
            })
            .collect()
    }

    fn ok_lod(pl: u64, e: i32) -> (RmStatus, i16) {
        let mut out = i16::MIN;
        // SAFETY: `out` is a valid local.
        let s = unsafe { rm_table_lod(pl, e, &mut out) };
        (s, out)
    }

    #[test]
    fn null_pointers_are_reported() {
        // SAFETY: null pointers are the inputs under test; nothing is dereferenced.
        unsafe {
            assert_eq!(
                rm_table_lod(1, 0, core::ptr::null_mut()),
                RmStatus::NullPointer
            );
            assert_eq!(
                rm_ray_stack_init(core::ptr::null_mut()),
                RmStatus::NullPointer
            );
            assert_eq!(
                rm_ray_stack_push(core::ptr::null_mut(), core::ptr::null()),
                RmStatus::NullPointer
            );
            assert_eq!(
                rm_ray_stack_pop(core::ptr::null_mut(), core::ptr::null_mut()),
                RmStatus::NullPointer
            );
            assert_eq!(
                rm_path_advance(core::ptr::null_mut(), 1),
                RmStatus::NullPointer
            );
            assert_eq!(
                rm_path_bounce(core::ptr::null_mut(), 1),
                RmStatus::NullPointer
            );
            assert_eq!(
                rm_path_primary(1 << 20, 0, core::ptr::null_mut()),
                RmStatus::NullPointer
            );
            assert_eq!(
                rm_table_build(
                    core::ptr::null_mut(),
                    1,
                    core::ptr::null(),
                    0,
                    1 << 20,
                    core::ptr::null_mut()
                ),
                RmStatus::NullPointer
            );
            assert_eq!(
                rm_sampler_init(
                    core::ptr::null_mut(),
                    core::ptr::null(),
                    RmAddressBits(RmAddress::Wrap as u8)
                ),
                RmStatus::NullPointer
            );
            assert_eq!(
                rm_sample(
                    core::ptr::null_mut(),
                    0,
                    0,
                    0,
                    RmModeBits(RmMode::Trilinear as u8),
                    core::ptr::null_mut()
                ),
                RmStatus::NullPointer
            );
        }
    }

    #[test]
    fn corrupt_stack_length_is_read_as_full_and_pops_in_range() {
        let mut st = RmRayStack {
            entries: [RmPathState::default(); RM_RAY_STACK_CAPACITY],
            len: 1000,
        };
        let s = RmPathState::default();
        let mut out = RmPathState::default();
        // SAFETY: valid locals.
        unsafe {
            assert_eq!(rm_ray_stack_push(&mut st, &s), RmStatus::StackFull);
            assert_eq!(rm_ray_stack_pop(&mut st, &mut out), RmStatus::Ok);
        }
        assert_eq!(st.len as usize, RM_RAY_STACK_CAPACITY - 1);
    }

    /// A partial update reports what it wrote: the items before the first
    /// one without a slot (`TableFull`) or the first invalid one
    /// (`ZeroSize`; a missing slot wins when both apply), counted in
    /// `stats`, the entries after them untouched.
    #[test]
    fn partial_update_counts_what_it_wrote() {
        let unit = RmTriangle {
            positions: [[0, 0, 0], [1 << 32, 0, 0], [0, 1 << 32, 0]],
            uvs: [[0, 0], [1 << 32, 0], [0, 1 << 32]],
            tex_width: 64,
            tex_height: 64,
            textured: 1,
        };
        let plain = RmTriangle {
            textured: 0,
            ..unit
        };
        let zero = RmTriangle {
            tex_width: 0,
            ..unit
        };
        let mk = |t, u| RmBuildStats {
            textured: t,
            untextured: u,
            ..RmBuildStats::default()
        };
        for (start, tris, status, want, written) in [
            (
                1,
                &[unit, plain, unit][..],
                RmStatus::TableFull,
                mk(1, 1),
                2,
            ),
            (0, &[plain, zero, unit][..], RmStatus::ZeroSize, mk(0, 1), 1),
            (2, &[unit, zero][..], RmStatus::TableFull, mk(1, 0), 1),
            (5, &[unit][..], RmStatus::TableFull, mk(0, 0), 0),
            (0, &[unit, plain][..], RmStatus::Ok, mk(1, 1), 2),
        ] {
            let mut e = [0x5A5A_5A5A; 3];
            let mut st = RmBuildStats::default();
            // SAFETY: valid locals of the stated lengths.
            let s = unsafe {
                rm_table_update(
                    e.as_mut_ptr(),
                    3,
                    start,
                    tris.as_ptr(),
                    tris.len(),
                    1 << 20,
                    &mut st,
                )
            };
            assert_eq!(
                (s, st),
                (status, want),
                "start {start}, {} items",
                tris.len()
            );
            let touched = e.iter().filter(|&&x| x != 0x5A5A_5A5A).count();
            assert_eq!(touched, written, "start {start}");
        }
    }

    /// Regression (issue 11, defect 1): a grazing hit (`|n·d| = 0`) through
    /// C clamps like the Rust `cone_lod` (2⁻¹⁶, 16 levels coarser) instead
    /// of dropping the normal term; `|n·d| = 1` is "no normal term".
    #[test]
    fn grazing_cone_lod_agrees_with_rust() {
        let w = I32F32::ONE;
        let grazing = cone_lod(w, I16F16::ZERO, Some(U1F31::ZERO));
        assert_eq!(grazing, I8F8::from_num(16));
        assert_eq!(rm_cone_lod(w.to_bits(), 0, 0), grazing.to_bits());
        assert_eq!(rm_cone_lod(w.to_bits(), 0, 1), grazing.to_bits());
        assert_eq!(rm_cone_lod(w.to_bits(), 0, 1 << 31), 0);
        assert_eq!(
            cone_lod(w, I16F16::ZERO, None),
            cone_lod(w, I16F16::ZERO, Some(U1F31::from_bits(1 << 31)))
        );
    }

    /// `rm_delta` against the f64 formula `−log2 Pb − log2 γ` (γ rounded
    /// to I2F30 first); bad input is reported and nothing is written.
    #[test]
    fn delta_matches_f64_and_rejects_bad_input() {
        let gamma = 0.01f64;
        let spread = I2F30::from_num(gamma).to_bits();
        for pb in [-3.5f64, 0.0, 2.25, 11.0] {
            let mut d = 0i32;
            let entry = I16F16::from_num(pb).to_bits();
            // SAFETY: a valid, aligned out pointer.
            assert_eq!(unsafe { rm_delta(entry, spread, &mut d) }, RmStatus::Ok);
            let want = -pb - I2F30::from_num(gamma).to_num::<f64>().log2();
            let got = I16F16::from_bits(d).to_num::<f64>();
            assert!((got - want).abs() < 1.0 / 4096.0, "{pb}: {got} vs {want}");
        }
        let mut d = 7i32;
        // SAFETY: as above; null is reported, not dereferenced.
        unsafe {
            assert_eq!(
                rm_delta(RM_UNTEXTURED, spread, &mut d),
                RmStatus::Untextured
            );
            assert_eq!(rm_delta(0, 0, &mut d), RmStatus::BadAngle);
            assert_eq!(rm_delta(0, -5, &mut d), RmStatus::BadAngle);
            assert_eq!(
                rm_delta(0, spread, core::ptr::null_mut()),
                RmStatus::NullPointer
            );
        }
        assert_eq!(d, 7);
    }

    /// Regression (issue 11, defect 3): pushing an entry of the same stack
    /// (`rm_ray_stack_push(&s, &s.entries[i])`) is a natural C idiom; the
    /// state must be read before the stack is borrowed mutably (Miri reports
    /// undefined behaviour otherwise).
    #[test]
    fn push_an_entry_of_the_same_stack() {
        let mut st = RmRayStack {
            entries: [RmPathState::default(); RM_RAY_STACK_CAPACITY],
            len: 0,
        };
        let p: *mut RmRayStack = &mut st;
        let first = RmPathState {
            pl: 42,
            depth: 3,
            ..RmPathState::default()
        };
        // SAFETY: `p` points to a valid local stack; `entry` points into it
        // (the aliasing under test).
        unsafe {
            assert_eq!(rm_ray_stack_push(p, &first), RmStatus::Ok);
            let entry: *const RmPathState = core::ptr::addr_of!((*p).entries[0]);
            assert_eq!(rm_ray_stack_push(p, entry), RmStatus::Ok);
            assert_eq!((*p).len, 2);
            assert_eq!((*p).entries[1], first);
            // Pop into the slot being popped (out aliases the stack too).
            let out: *mut RmPathState = core::ptr::addr_of_mut!((*p).entries[1]);
            assert_eq!(rm_ray_stack_pop(p, out), RmStatus::Ok);
            assert_eq!((*p).len, 1);
            assert_eq!((*p).entries[1], first);
        }
    }

    /// Regression (issue 11, defect 3): a misaligned caller pointer is an
    /// error, never dereferenced (`from_raw_parts` and `*p` require
    /// alignment; debug builds panic on it, release builds are UB).
    #[test]
    fn misaligned_pointers_are_rejected() {
        let mut raw = [0u64; 64];
        let base = raw.as_mut_ptr().cast::<u8>();
        // SAFETY: offsets stay inside `raw`; the misaligned pointers are only
        // handed to the entry points, which must not dereference them.
        unsafe {
            let mis = base.add(1);
            assert_eq!(rm_table_lod(1 << 32, 0, mis.cast()), RmStatus::Misaligned);
            assert_eq!(rm_ray_stack_init(base.add(4).cast()), RmStatus::Misaligned);
            let good = RmPathState::default();
            assert_eq!(
                rm_ray_stack_push(base.add(4).cast(), &good),
                RmStatus::Misaligned
            );
            let mut st = RmRayStack {
                entries: [RmPathState::default(); RM_RAY_STACK_CAPACITY],
                len: 0,
            };
            assert_eq!(
                rm_ray_stack_push(&mut st, base.add(4).cast()),
                RmStatus::Misaligned
            );
            assert_eq!(st.len, 0);
            assert_eq!(
                rm_ray_stack_pop(&mut st, base.add(4).cast()),
                RmStatus::Misaligned
            );
            assert_eq!(
                rm_path_primary(1 << 20, 0, base.add(4).cast()),
                RmStatus::Misaligned
            );
            assert_eq!(rm_path_advance(base.add(4).cast(), 1), RmStatus::Misaligned);
            assert_eq!(rm_path_bounce(base.add(4).cast(), 1), RmStatus::Misaligned);
            assert_eq!(
                rm_mip_generate(base.add(2).cast(), 21, 4, 4, 3),
                RmStatus::Misaligned
            );
            let tri = RmTriangle {
                positions: [[0; 3]; 3],
                uvs: [[0; 2]; 3],
                tex_width: 1,
                tex_height: 1,
                textured: 0,
            };
            assert_eq!(
                rm_table_build(mis.cast(), 1, &tri, 1, 1 << 20, core::ptr::null_mut()),
                RmStatus::Misaligned
            );
            let mut e = [0i32; 1];
            assert_eq!(
                rm_table_build(
                    e.as_mut_ptr(),
                    1,
                    base.add(4).cast(),
                    1,
                    1 << 20,
                    core::ptr::null_mut()
                ),
                RmStatus::Misaligned
            );
            assert_eq!(
                rm_table_build(e.as_mut_ptr(), 1, &tri, 1, 1 << 20, base.add(2).cast()),
                RmStatus::Misaligned
            );
            let texels = [0u32; 1];
            let tex = RmTexture {
                texels: base.add(2).cast(),
                len: 1,
                width: 1,
                height: 1,
                levels: 1,
            };
            let wrap = RmAddressBits(RmAddress::Wrap as u8);
            let mut sm = RmSampler {
                opaque: [0; RM_SAMPLER_WORDS],
            };
            assert_eq!(rm_sampler_init(&mut sm, &tex, wrap), RmStatus::Misaligned);
            let tex_ok = RmTexture {
                texels: texels.as_ptr(),
                ..tex
            };
            assert_eq!(
                rm_sampler_init(base.add(4).cast(), &tex_ok, wrap),
                RmStatus::Misaligned
            );
            assert_eq!(
                rm_sampler_init(&mut sm, base.add(4).cast(), wrap),
                RmStatus::Misaligned
            );
            let tri = RmModeBits(RmMode::Trilinear as u8);
            let mut out = 0u32;
            assert_eq!(
                rm_sample(&mut sm, 0, 0, 0, tri, &mut out),
                RmStatus::Uninitialised
            );
            assert_eq!(rm_sampler_init(&mut sm, &tex_ok, wrap), RmStatus::Ok);
            assert_eq!(
                rm_sample(base.add(4).cast(), 0, 0, 0, tri, &mut out),
                RmStatus::Misaligned
            );
            assert_eq!(
                rm_sample(&mut sm, 0, 0, 0, tri, base.add(2).cast()),
                RmStatus::Misaligned
            );
            assert_eq!(rm_sample(&mut sm, 0, 0, 0, tri, &mut out), RmStatus::Ok);
        }
        assert!(
            raw.iter().all(|&x| x == 0),
            "a misaligned pointer was written through"
        );
    }

    proptest! {
        /// The C entry points agree with the Rust API for every input.
        #[test]
        fn c_lod_equals_rust_lod(pl in any::<u64>(), e in any::<i32>(), w in any::<i64>(), d in any::<i32>(), c in any::<u32>(), lod in any::<i16>(), levels in any::<u8>()) {
            let (s, out) = ok_lod(pl, e);
            match table_lod(U32F32::from_bits(pl), Log2Pb::from_bits(e)) {
                Some(l) => prop_assert_eq!((s, out), (RmStatus::Ok, l.to_bits())),
                None => prop_assert_eq!((s, e), (RmStatus::Untextured, RM_UNTEXTURED)),
            }
            let want = cone_lod(I32F32::from_bits(w), I16F16::from_bits(d), Some(U1F31::from_bits(c)));
            prop_assert_eq!(rm_cone_lod(w, d, c), want.to_bits());
            prop_assert_eq!(rm_clamp_lod(lod, levels), clamp_lod(I8F8::from_bits(lod), levels).to_bits());
        }

        /// A sampler set up once gives, sample after sample, the texel of
        /// the Rust `Sampler` built afresh for each sample (what `rm_sample`
        /// did before it took a set-up sampler); bad modes and addresses are
        /// `OutOfRange`.
        #[test]
        fn set_up_sampler_equals_fresh_rust_sampler(
            w in 1u32..9, h in 1u32..9, seed in any::<u64>(), address in 0u8..7,
            samples in proptest::collection::vec((any::<i64>(), any::<i64>(), -512i16..4096, 0u8..5), 1..24),
        ) {
            let levels = crate::texture::storage::mip::full_levels(w, h);
            let n = pyramid_len(w, h, levels);
            let texels = lcg_texels(seed, n);
            let tex = RmTexture { texels: texels.as_ptr(), len: n, width: w, height: h, levels };
            let mut sm = RmSampler { opaque: [0; RM_SAMPLER_WORDS] };
            // SAFETY: valid locals; `texels` outlives `sm`'s use.
            let st = unsafe { rm_sampler_init(&mut sm, &tex, RmAddressBits(address)) };
            let Some(addr) = RmAddress::mode(address) else {
                prop_assert_eq!(st, RmStatus::OutOfRange);
                return Ok(());
            };
            prop_assert_eq!(st, RmStatus::Ok);
            let g = Geometry::new(w, h, levels).unwrap();
            for (u, v, lod, mode) in samples {
                let mut out = 0u32;
                // SAFETY: `sm` set up above, `out` a valid local.
                let s = unsafe { rm_sample(&mut sm, u, v, lod, RmModeBits(mode), &mut out) };
                match Mode::from_index(mode) {
                    Some(m) => {
                        let fresh = crate::texture::Sampler::with_address(Pyramid::new(g, &texels).unwrap(), addr)
                            .sample(I32F32::from_bits(u), I32F32::from_bits(v), I8F8::from_bits(lod), m);
                        prop_assert_eq!((s, out), (RmStatus::Ok, fresh));
                    }
                    None => prop_assert_eq!(s, RmStatus::OutOfRange),
                }
            }
        }

        /// A sampler set up from an `RmSamplerDesc` (any address pair,
        /// border, bias, clamps, anisotropy, tier) samples, batches and
        /// filters anisotropically exactly as the Rust sampler of the same
        /// settings; out-of-range fields are `OutOfRange` and leave the
        /// sampler unchanged.
        #[test]
        fn desc_sampler_equals_rust(
            w in 1u32..17, h in 1u32..17, seed in any::<u64>(),
            au in 0u8..6, av in 0u8..6, border in any::<u32>(),
            bias in -5000i16..5000, lo in any::<i16>(), hi in any::<i16>(),
            aniso in 0u8..18, srgb_output in 0u8..3, precision in 0u8..3, mode in 0u8..4,
            samples in proptest::collection::vec((any::<i64>(), any::<i64>(), -512i16..4096, any::<[i32; 4]>()), 1..20),
        ) {
            let levels = crate::texture::storage::mip::full_levels(w, h);
            let n = pyramid_len(w, h, levels);
            let texels = lcg_texels(seed, n);
            let tex = RmTexture { texels: texels.as_ptr(), len: n, width: w, height: h, levels };
            let desc = RmSamplerDesc {
                border, lod_bias: bias, min_lod: lo, max_lod: hi,
                address_u: RmAddressBits(au), address_v: RmAddressBits(av),
                max_anisotropy: aniso, srgb_output, precision,
            };
            let mut sm = RmSampler { opaque: [0x77; RM_SAMPLER_WORDS] };
            // SAFETY: valid locals; `texels` outlives `sm`'s use.
            let st = unsafe { rm_sampler_init_desc(&mut sm, &tex, &desc) };
            // The Rust settings, built here from the C fields' documented meaning.
            let want = (|| {
                let state = SamplerState::new(SamplerDesc {
                    address_u: RmAddress::mode(au)?,
                    address_v: RmAddress::mode(av)?,
                    border,
                    lod_bias: I8F8::from_bits(bias),
                    min_lod: I8F8::from_bits(lo),
                    max_lod: I8F8::from_bits(hi),
                    max_anisotropy: aniso,
                    srgb_output: [SrgbOutput::Encoded, SrgbOutput::Linear].get(usize::from(srgb_output)).copied()?,
                }).ok()?;
                let precision = [Precision::Accurate, Precision::Fast].get(usize::from(precision)).copied()?;
                Some((state, precision))
            })();
            let Some((state, prec)) = want else {
                prop_assert_eq!(st, RmStatus::OutOfRange);
                prop_assert!(sm.opaque.iter().all(|&x| x == 0x77), "a rejected set-up wrote the sampler");
                return Ok(());
            };
            prop_assert_eq!(st, RmStatus::Ok);
            let g = Geometry::new(w, h, levels).unwrap();
            let mut rust = DynSampler::new(Pyramid::new(g, &texels).unwrap(), state, ColorSpace::Linear, prec);
            let m = Mode::from_index(mode).unwrap();
            let hits: std::vec::Vec<RmHit> = samples.iter().map(|&(u, v, lod, _)| RmHit { u, v, lod }).collect();
            let mut batch = std::vec![0u32; hits.len()];
            // SAFETY: `sm` set up above; `hits` and `batch` valid, of length `hits.len()`.
            let sb = unsafe { rm_sample_batch(&mut sm, hits.as_ptr(), hits.len(), RmModeBits(mode), batch.as_mut_ptr()) };
            prop_assert_eq!(sb, RmStatus::Ok);
            for (i, &(u, v, lod, d)) in samples.iter().enumerate() {
                let (fu, fv) = (I32F32::from_bits(u), I32F32::from_bits(v));
                let want = rust.sample(fu, fv, I8F8::from_bits(lod), m);
                let mut out = 0u32;
                // SAFETY: `sm` set up above, `out` a valid local.
                let s = unsafe { rm_sample(&mut sm, u, v, lod, RmModeBits(mode), &mut out) };
                prop_assert_eq!((s, out, batch[i]), (RmStatus::Ok, want, want));
                // Footprints up to ±8 texture widths per pixel.
                let [a, b, c, e] = d.map(|x| i64::from(x) << 3);
                let fp = RmFootprint { dudx: a, dvdx: b, dudy: c, dvdy: e };
                let want = rust.sample_aniso(fu, fv, &Footprint {
                    x: [I32F32::from_bits(a), I32F32::from_bits(b)],
                    y: [I32F32::from_bits(c), I32F32::from_bits(e)],
                });
                // SAFETY: as above; `fp` a valid local.
                let s = unsafe { rm_sample_aniso(&mut sm, u, v, &fp, &mut out) };
                prop_assert_eq!((s, out), (RmStatus::Ok, want));
            }
        }

        /// An image in any format and colour space samples exactly as the
        /// Rust sampler over the same `Image`; wrong formats, sRGB flags
        /// and short buffers are refused.
        #[test]
        fn image_sampler_equals_rust(
            w in 1u32..13, h in 1u32..13, seed in any::<u64>(), format in 0u8..12, srgb in 0u8..3,
            precision in 0u8..2, short in any::<bool>(),
            samples in proptest::collection::vec((any::<i64>(), any::<i64>(), -512i16..4096, 0u8..4), 1..16),
        ) {
            let levels = crate::texture::storage::mip::full_levels(w, h);
            let len = rm_image_len(w, h, levels, format);
            let words = lcg_texels(seed, len / 4 + 1);
            let bytes: std::vec::Vec<u8> = words.iter().flat_map(|x| x.to_le_bytes()).take(len).collect();
            let given = if short && len > 0 { len - 1 } else { len };
            let img = RmImage { bytes: bytes.as_ptr(), len: given, width: w, height: h, levels, format, srgb };
            let desc = RmSamplerDesc { precision, ..RmSamplerDesc::default() };
            let mut sm = RmSampler { opaque: [0; RM_SAMPLER_WORDS] };
            // SAFETY: valid locals; `bytes` outlives `sm`'s use.
            let st = unsafe { rm_sampler_init_image(&mut sm, &img, &desc) };
            let space = [ColorSpace::Linear, ColorSpace::Srgb].get(usize::from(srgb)).copied();
            let fmt = TexelFormat::from_index(format).zip(space).and_then(|(f, s)| Format::new(f, s).ok());
            let Some(fmt) = fmt else {
                prop_assert_eq!(st, RmStatus::OutOfRange);
                return Ok(());
            };
            if short {
                prop_assert_eq!(st, RmStatus::BufferTooShort);
                return Ok(());
            }
            prop_assert_eq!(st, RmStatus::Ok);
            let g = Geometry::new(w, h, levels).unwrap();
            let prec = [Precision::Accurate, Precision::Fast][usize::from(precision)];
            let state = SamplerState::new(SamplerDesc::default()).unwrap();
            let mut rust = DynSampler::new(Image::new(g, fmt, &bytes).unwrap(), state, fmt.space(), prec);
            for (u, v, lod, mode) in samples {
                let m = Mode::from_index(mode).unwrap();
                let want = rust.sample(I32F32::from_bits(u), I32F32::from_bits(v), I8F8::from_bits(lod), m);
                let mut out = 0u32;
                // SAFETY: `sm` set up above, `out` a valid local.
                let s = unsafe { rm_sample(&mut sm, u, v, lod, RmModeBits(mode), &mut out) };
                prop_assert_eq!((s, out), (RmStatus::Ok, want));
            }
        }

        /// Path state round-trips and advances exactly as `PathState`.
        #[test]
        fn c_path_state_equals_rust(g in 1i32..i32::MAX, ts in proptest::collection::vec(any::<u64>(), 0..12), beta in any::<i32>()) {
            let mut c = RmPathState::default();
            // SAFETY: valid local.
            prop_assert_eq!(unsafe { rm_path_primary(g, 7, &mut c) }, RmStatus::Ok);
            let spread = PixelSpread::from_angle(I2F30::from_bits(g)).unwrap();
            let mut r = PathState::primary(&spread, 7);
            for &t in &ts {
                // SAFETY: valid local.
                unsafe {
                    rm_path_advance(&mut c, t);
                    rm_path_bounce(&mut c, beta);
                }
                r = r.advance(U32F32::from_bits(t)).bounce(I2F30::from_bits(beta));
                prop_assert_eq!(PathState::from(c), r);
            }
        }
    }
}
