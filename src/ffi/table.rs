//! The Pb table through C: build and update from triangles, and the
//! ray-cone constant `Δ` of an entry.

use crate::setup::camera::PixelSpread;
use crate::setup::table::{BuildStats, PbTable, TableError, TexTriangle};
use crate::units::{Coord, Log2Pb, Spread, TexCoord};

use super::*;

/// Raw bits of the untextured table marker (`INT32_MIN`).
pub const RM_UNTEXTURED: i32 = i32::MIN;

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
    /// The table's input: `None` when untextured.
    ///
    /// # Errors
    /// [`TableError::ZeroTextureSize`] for a textured triangle with a zero
    /// texture side.
    pub fn tex_triangle(&self) -> Result<Option<TexTriangle>, TableError> {
        if self.textured == 0 {
            return Ok(None);
        }
        TexTriangle::new(
            self.positions.map(|p| p.map(Coord::from_bits)),
            self.uvs.map(|p| p.map(TexCoord::from_bits)),
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

pub(super) fn table_status(e: TableError) -> RmStatus {
    match e {
        TableError::ZeroTextureSize => RmStatus::ZeroSize,
        TableError::TableFull => RmStatus::TableFull,
        _ => RmStatus::OutOfRange,
    }
}

/// The camera's pixel spread from its I2F30 `bits`; `BadAngle` unless
/// `0 < γ < 2` radians.
pub(super) fn spread_from_bits(bits: i32) -> Result<PixelSpread, RmStatus> {
    PixelSpread::from_angle(Spread::from_bits(bits)).map_err(|_| RmStatus::BadAngle)
}

/// Computes table entries `start .. start + count` of `entries` (length
/// `len`) from `tris[0 .. count]` for a camera with pixel spread angle
/// `spread` (I2F30 bits, `0 < γ < 2` radians); fills `stats` if not null.
///
/// Returns `RM_STATUS_OK`; `RM_STATUS_TABLE_FULL` when `start + count >
/// len` (the entries that fit are written); `RM_STATUS_ZERO_SIZE` for a
/// textured triangle with a zero texture side (the entries before it are
/// written); `RM_STATUS_BAD_ANGLE` unless `0 < spread < 2` radians;
/// `RM_STATUS_NULL_POINTER` (`entries` or `tris` null with a non-zero
/// length); `RM_STATUS_MISALIGNED` (a pointer not aligned for its type).
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

/// [`rm_table_update`] from entry 0 (a whole build); the same status codes.
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

/// Ray-cone triangle constant `Δ = −log2 Pb − log2 γ` (I16F16 bits, as
/// [`rm_cone_lod`] takes it) of table entry `entry_bits` (I16F16 bits) for a
/// camera with pixel spread angle `spread` (I2F30 bits, `0 < γ < 2`
/// radians), saturating.
///
/// Returns `RM_STATUS_OK`; `RM_STATUS_UNTEXTURED` (nothing written) for
/// [`RM_UNTEXTURED`]; `RM_STATUS_BAD_ANGLE` unless `0 < spread < 2`
/// radians; `RM_STATUS_NULL_POINTER`; `RM_STATUS_MISALIGNED`.
///
/// # Safety
/// `out` is null or points to a writable `int32_t`.
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
