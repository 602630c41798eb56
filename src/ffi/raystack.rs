//! The ray stack and path state through C: a fixed-capacity stack of
//! plain integers in caller memory, and the primary, advance and bounce
//! steps of a path state.

use crate::path::raystack::{PathState, RayCone, stack_bound};

use super::*;
use crate::units::{PathLength, Spread, Width};

/// Bounces per path that an [`RmRayStack`] holds with two continuations
/// (a reflection and a refraction) pushed per hit: the hardware paper's 10.
pub const RM_MAX_BOUNCES: u8 = 10;

/// Capacity of [`RmRayStack`]: `RM_STACK_BOUND(RM_MAX_BOUNCES, 2)` =
/// `(2 − 1) · 10 + 1` = 11 entries, what a depth-first tracer needs for
/// `RM_MAX_BOUNCES` bounces of two continuations per hit (checked at
/// compile time, in the library and in this header with `RM_STACK_BOUND`).
/// A stack of the paper's 10 entries would drop a branch of the deepest
/// paths.
pub const RM_RAY_STACK_CAPACITY: usize = 11;
const _: () = assert!(RM_RAY_STACK_CAPACITY == stack_bound(RM_MAX_BOUNCES, 2));

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
/// Plain integers, not opaque: C code may read its entries, and any bits
/// a caller leaves in it are handled (a `len` above the capacity is read
/// as full and popped in range). Holds `RM_RAY_STACK_CAPACITY` entries:
/// paths of `RM_MAX_BOUNCES` bounces with two continuations per hit.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RmRayStack {
    /// Storage; entries `0 .. len` are valid.
    pub entries: [RmPathState; RM_RAY_STACK_CAPACITY],
    /// Number of valid entries (`0 ..= RM_RAY_STACK_CAPACITY`).
    pub len: u32,
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
        let pl = PathLength::from_bits(s.pl);
        Self {
            pl,
            pl_norm: crate::log2::fast::NormPl::new(pl),
            cone: RayCone {
                width: Width::from_bits(s.cone_width),
                spread: Spread::from_bits(s.cone_spread),
            },
            // The C ABI carries no ray differentials.
            #[cfg(feature = "raydiff")]
            diff: crate::path::raydiff::RayDiff::ZERO,
            mask: s.mask,
            depth: s.depth,
            saturated: s.saturated != 0,
        }
    }
}

/// Empties `stack`.
///
/// Returns `RM_STATUS_OK`, `RM_STATUS_NULL_POINTER` or
/// `RM_STATUS_MISALIGNED`.
///
/// # Safety
/// `stack` is null or points to a writable [`RmRayStack`].
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
/// entries).
///
/// Returns `RM_STATUS_OK`; `RM_STATUS_STACK_FULL` (stack unchanged) when
/// it holds `RM_RAY_STACK_CAPACITY` entries; `RM_STATUS_NULL_POINTER`;
/// `RM_STATUS_MISALIGNED`.
///
/// # Safety
/// `stack` and `state` are null, misaligned or valid (`stack` initialised
/// by [`rm_ray_stack_init`]; a `len` above the capacity is read as full).
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
    // Held in a local the optimiser must keep (`black_box`): a direct copy
    // between entries that may overlap would link a `memmove` for it.
    let state = core::hint::black_box(unsafe { state.read() });
    // SAFETY: as above; no other reference to the stack is live.
    let stack = unsafe { &mut *stack };
    let Some(slot) = stack.entries.get_mut(stack.len as usize) else {
        return RmStatus::StackFull;
    };
    *slot = state;
    stack.len += 1;
    RmStatus::Ok
}

/// Pops the most recent state into `out`.
///
/// Returns `RM_STATUS_OK`; `RM_STATUS_STACK_EMPTY` (nothing written) when
/// empty; `RM_STATUS_NULL_POINTER`; `RM_STATUS_MISALIGNED`.
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
        // Through a local, as in `rm_ray_stack_push`: `out` may point
        // into the stack.
        core::hint::black_box(s)
    };
    // SAFETY: non-null, aligned (checked), writable (caller).
    unsafe { out.write(s) };
    RmStatus::Ok
}

/// A primary ray's state (`Pl = 0`, width 0, spread `spread` in I2F30
/// bits) with ray mask `mask`.
///
/// Returns `RM_STATUS_OK`; `RM_STATUS_BAD_ANGLE` unless `0 < spread < 2`
/// radians; `RM_STATUS_NULL_POINTER`; `RM_STATUS_MISALIGNED`.
///
/// # Safety
/// `out` is null or writable.
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
/// Returns `RM_STATUS_OK`, `RM_STATUS_NULL_POINTER` or
/// `RM_STATUS_MISALIGNED`.
///
/// # Safety
/// `state` is null or valid and writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_path_advance(state: *mut RmPathState, t: u64) -> RmStatus {
    // SAFETY: same contract.
    unsafe { update_state(state, |s| s.advance(PathLength::from_bits(t))) }
}

/// A reflection/refraction continuation: spread `+= beta` (I2F30 bits,
/// surface spread angle; 0 for a flat surface), depth + 1 (saturating).
///
/// Returns `RM_STATUS_OK`, `RM_STATUS_NULL_POINTER` or
/// `RM_STATUS_MISALIGNED`.
///
/// # Safety
/// As [`rm_path_advance`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn rm_path_bounce(state: *mut RmPathState, beta: i32) -> RmStatus {
    // SAFETY: same contract.
    unsafe { update_state(state, |s| s.bounce(Spread::from_bits(beta))) }
}

/// Replaces `*state` by `f(*state)` through `PathState`.
///
/// # Safety
/// As [`rm_path_advance`].
pub(super) unsafe fn update_state(
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
