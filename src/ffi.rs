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
use crate::filter::{Address, Mode, Sampler};
use crate::lod::{clamp_lod, cone_lod, table_lod};
use crate::mip::{Geometry, MipError, Pyramid, generate, pyramid_len};
use crate::raystack::{DEFAULT_CAPACITY, PathState, RayCone};
use crate::table::{Log2Pb, TableError, TexTriangle};

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
}

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
        Self {
            pl: U32F32::from_bits(s.pl),
            cone: RayCone {
                width: I32F32::from_bits(s.cone_width),
                spread: I2F30::from_bits(s.cone_spread),
            },
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

/// A table entry from raw bits (markers included).
fn entry(bits: i32) -> Log2Pb {
    Log2Pb::from_bits(bits)
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
    for c in [
        check_ptr(entries.cast_const(), len == 0),
        check_ptr(tris, count == 0),
        check_ptr(stats.cast_const(), true),
    ] {
        if let Err(e) = c {
            return e;
        }
    }
    let Ok(spread) = PixelSpread::from_angle(I2F30::from_bits(spread)) else {
        return RmStatus::BadAngle;
    };
    let entries: &mut [i32] = if len == 0 {
        &mut []
    } else {
        // SAFETY: non-null (checked), `len` writable elements (caller).
        unsafe { core::slice::from_raw_parts_mut(entries, len) }
    };
    let tris: &[RmTriangle] = if count == 0 {
        &[]
    } else {
        // SAFETY: non-null (checked), `count` readable elements (caller).
        unsafe { core::slice::from_raw_parts(tris, count) }
    };
    let mut st = RmBuildStats::default();
    let mut status = RmStatus::Ok;
    let mut slots = entries.iter_mut().skip(start);
    for t in tris {
        let Some(slot) = slots.next() else {
            status = RmStatus::TableFull;
            break;
        };
        let e = if t.textured == 0 {
            st.untextured += 1;
            Log2Pb::UNTEXTURED
        } else {
            let tri = TexTriangle::new(
                t.positions.map(|p| p.map(I32F32::from_bits)),
                t.uvs.map(|p| p.map(I32F32::from_bits)),
                t.tex_width,
                t.tex_height,
            );
            match tri {
                Ok(tri) => {
                    let e = Log2Pb::compute(&tri, &spread);
                    if e == Log2Pb::DEGENERATE_GEOMETRY {
                        st.degenerate_geometry += 1;
                    } else if e == Log2Pb::DEGENERATE_UV {
                        st.degenerate_uv += 1;
                    } else {
                        st.textured += 1;
                    }
                    e
                }
                Err(e) => {
                    status = table_status(e);
                    break;
                }
            }
        };
        *slot = e.to_i16f16().to_bits();
    }
    if !stats.is_null() {
        // SAFETY: non-null, writable (caller).
        unsafe { *stats = st };
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
    match table_lod(U32F32::from_bits(pl), entry(entry_bits)) {
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
    if let Err(e) = check_ptr(out.cast_const(), false) {
        return e;
    }
    let Ok(spread) = PixelSpread::from_angle(I2F30::from_bits(spread)) else {
        return RmStatus::BadAngle;
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
    if let Err(e) = check_ptr(state.cast_const(), false) {
        return e;
    }
    // SAFETY: non-null, valid, writable (caller).
    let s = unsafe { &mut *state };
    *s = PathState::from(*s).advance(U32F32::from_bits(t)).into();
    RmStatus::Ok
}

/// A reflection/refraction continuation: spread `+= beta` (I2F30 bits,
/// surface spread angle), depth + 1.
///
/// # Safety
/// As [`rm_path_advance`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_path_bounce(state: *mut RmPathState, beta: i32) -> RmStatus {
    if let Err(e) = check_ptr(state.cast_const(), false) {
        return e;
    }
    // SAFETY: non-null, valid, writable (caller).
    let s = unsafe { &mut *state };
    *s = PathState::from(*s).bounce(I2F30::from_bits(beta)).into();
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

/// Filtered texel of `tex` at `(u, v)` (I32F32 bits, normalised; texel
/// centres at `(i + 0.5)/size`) and lod `lod` (I8F8 bits, clamped to the
/// stored levels) with filter `mode` (0 trilinear, 1 bilinear at the nearest
/// level, 2 nearest, 3 nearest texel with linear level blend) and
/// addressing `address` (0 wrap, 1 clamp); writes RGBA8888 to `out`.
///
/// # Safety
/// `tex` and `out` are null (→ `NullPointer`) or valid; `tex->texels`
/// points to `tex->len` readable texels.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_sample(
    tex: *const RmTexture,
    u: i64,
    v: i64,
    lod: i16,
    mode: u8,
    address: u8,
    out: *mut u32,
) -> RmStatus {
    if let Err(e) = check_ptr(tex, false).and(check_ptr(out.cast_const(), false)) {
        return e;
    }
    // SAFETY: non-null, aligned (checked), valid (caller).
    let t = unsafe { *tex };
    if let Err(e) = check_ptr(t.texels, false) {
        return e;
    }
    let Some(mode) = Mode::from_index(mode) else {
        return RmStatus::OutOfRange;
    };
    let Some(address) = Address::from_index(address) else {
        return RmStatus::OutOfRange;
    };
    let g = match Geometry::new(t.width, t.height, t.levels) {
        Ok(g) => g,
        Err(e) => return mip_status(e),
    };
    // SAFETY: non-null, `len` readable texels (caller).
    let texels = unsafe { core::slice::from_raw_parts(t.texels, t.len) };
    let p = match Pyramid::new(g, texels) {
        Ok(p) => p,
        Err(e) => return mip_status(e),
    };
    let texel = Sampler::new(p, address).sample(
        I32F32::from_bits(u),
        I32F32::from_bits(v),
        I8F8::from_bits(lod),
        mode,
    );
    // SAFETY: non-null, writable (caller).
    unsafe { *out = texel };
    RmStatus::Ok
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use proptest::prelude::*;

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
                rm_sample(core::ptr::null(), 0, 0, 0, 0, 0, core::ptr::null_mut()),
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
            let mut out = 0u32;
            assert_eq!(
                rm_sample(&tex, 0, 0, 0, 0, 0, &mut out),
                RmStatus::Misaligned
            );
            let tex_ok = RmTexture {
                texels: texels.as_ptr(),
                ..tex
            };
            assert_eq!(
                rm_sample(base.add(4).cast(), 0, 0, 0, 0, 0, &mut out),
                RmStatus::Misaligned
            );
            assert_eq!(
                rm_sample(&tex_ok, 0, 0, 0, 0, 0, base.add(2).cast()),
                RmStatus::Misaligned
            );
            assert_eq!(rm_sample(&tex_ok, 0, 0, 0, 0, 0, &mut out), RmStatus::Ok);
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
            match table_lod(U32F32::from_bits(pl), entry(e)) {
                Some(l) => prop_assert_eq!((s, out), (RmStatus::Ok, l.to_bits())),
                None => prop_assert_eq!((s, e), (RmStatus::Untextured, RM_UNTEXTURED)),
            }
            let want = cone_lod(I32F32::from_bits(w), I16F16::from_bits(d), Some(U1F31::from_bits(c)));
            prop_assert_eq!(rm_cone_lod(w, d, c), want.to_bits());
            prop_assert_eq!(rm_clamp_lod(lod, levels), clamp_lod(I8F8::from_bits(lod), levels).to_bits());
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
