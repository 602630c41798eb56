//! Level of detail through C: table and ray-cone lods, and the clamp to a
//! texture's stored levels.

use fixed::types::U1F31;

use crate::lod::{clamp_lod, cone_lod, table_lod};
use crate::units::{Accurate, Delta, Lod, Log2Pb, PathLength, Width};

use super::*;

/// Table lod `log2 Pl − log2 Pb` for path length `pl` (U32F32 bits) and
/// table entry `entry` (I16F16 bits); writes the lod (I8F8 bits) to `out`.
///
/// Returns `RM_STATUS_OK`; `RM_STATUS_UNTEXTURED` (nothing written) for
/// [`RM_UNTEXTURED`]; `RM_STATUS_NULL_POINTER`; `RM_STATUS_MISALIGNED`.
///
/// # Safety
/// `out` is null or points to a writable `int16_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_table_lod(pl: u64, entry_bits: i32, out: *mut i16) -> RmStatus {
    if let Err(e) = check_ptr(out.cast_const(), false) {
        return e;
    }
    match table_lod::<Accurate>(PathLength::from_bits(pl), Log2Pb::from_bits(entry_bits)) {
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
/// `|n·d|` (U1F31 bits): `|n·d|` is clamped to `[2⁻¹⁶, 1]`, so a grazing
/// hit (`n_dot_d = 0`) is 16 levels coarser than a head-on one.
/// [`RM_COS_ONE`] (or more) leaves the normal term out. Saturates at the
/// I8F8 range `[−128, 128)`; no status (it cannot fail).
#[unsafe(no_mangle)]
pub extern "C" fn rm_cone_lod(width: i64, delta: i32, n_dot_d: u32) -> i16 {
    let c = U1F31::from_bits(n_dot_d);
    cone_lod::<Accurate>(Width::from_bits(width), Delta::from_bits(delta), Some(c)).to_bits()
}

/// `lod` (I8F8 bits) clamped to the stored levels `[0, levels − 1]` (to 0
/// for `levels` 0 or 1); no status (it cannot fail).
#[unsafe(no_mangle)]
pub extern "C" fn rm_clamp_lod(lod: i16, levels: u8) -> i16 {
    clamp_lod(Lod::from_bits(lod), levels).to_bits()
}
