//! The ray stack: fixed-capacity storage of the path state that texture LOD
//! needs across reflection and refraction bounces.
//!
//! Park et al. 2011 carry the accumulated path length `Pl`; ray cones carry
//! width and spread.
//!
//! # Number formats: range analysis
//!
//! * [`PathLength`] = U32F32. Scenes are specified from 10⁻³ to 10⁴ scene
//!   units; a segment is at most the scene diagonal (≤ 1.8·10⁴ for a 10⁴
//!   cube), so 10 bounces accumulate ≤ 1.8·10⁵ < 2¹⁸, far below the format's
//!   maximum 2³² − 2⁻³² (headroom 2¹⁴). The step 2⁻³² ≈ 2.3·10⁻¹⁰ is a
//!   relative error ≤ 2.3·10⁻⁷ at 10⁻³ units (3·10⁻⁷ levels) and ≤ 2⁻¹⁶ at
//!   `Pl = 2⁻¹⁶` (2·10⁻⁵ levels). Sums saturate at the maximum and set
//!   [`PathState::saturated`]; nothing wraps.
//! * [`Width`] = I32F32 (cone width, scene units, signed: a concave surface
//!   can make it shrink through zero; the LOD uses `|w|`). Same range as Pl.
//! * [`Spread`] = I2F30 (cone spread angle, radians, range ±2, step
//!   9.3·10⁻¹⁰). A 4K image has `γ ≈ 2.5·10⁻⁴`, a relative step of 4·10⁻⁶.
//!   Sums saturate and set the flag.
//!
//! # How many entries a path needs
//!
//! A tracer that pops an entry, traces its segment and, when the entry's
//! depth `d` is below the bounce limit `B`, pushes at most `k ≥ 1`
//! continuations of depth `d + 1` (the primary ray alone at depth 0) needs
//! at most [`stack_bound`]`(B, k) = (k − 1)·B + 1` entries, and a path can
//! reach that many. Derivation (depth-first order, pop = most recent):
//!
//! * Invariant, true before every pop: from bottom to top the depths never
//!   decrease, every depth is held by at most `k − 1` entries except the
//!   top depth, which may hold `k` (the children just pushed).
//!   It holds for the primary entry alone. Popping the top entry (depth
//!   `d`) leaves at most `k − 1` entries of each depth `1 ..= d` (the top
//!   group lost one; depth 0 is only ever the primary, popped first), so
//!   at most `(k − 1)·d` entries. Pushing its `≤ k` children of depth
//!   `d + 1` (greater than every depth below) restores the invariant with
//!   at most `(k − 1)·d + k` entries.
//! * Pushes happen only for `d ≤ B − 1`, so the stack never exceeds
//!   `(k − 1)·(B − 1) + k = (k − 1)·B + 1` (and 1, the primary, for
//!   `B = 0`).
//! * The bound is reached: when every hit along the chain of most recently
//!   pushed entries pushes `k` continuations, `k − 1` siblings wait at each
//!   depth `1 ..= B − 1` when the `k` entries of depth `B` are pushed.
//!
//! Reflection plus refraction (`k = 2`) for `B` bounces thus needs `B + 1`
//! entries: the paper's 10 entries ([`DEFAULT_CAPACITY`]) hold 9 such
//! bounces, 10 bounces need 11 and drop a branch on the deepest paths
//! otherwise. One continuation per hit (`k = 1`: a mirror chain, pushed and
//! popped at once) needs a single entry at any depth.

use core::fmt;

use crate::log2::fast::NormPl;
use crate::setup::camera::PixelSpread;
#[cfg(feature = "cone")]
use crate::units::Width;
use crate::units::{PathLength, Spread};

/// Default stack capacity: 10 entries, as in the hardware paper: enough for
/// `stack_bound(9, 2)` (9 bounces with a reflection and a refraction per
/// hit) or any depth with one continuation per hit. Size a stack for `B`
/// bounces of `k` branches as `RayStack<T, { stack_bound(B, k) }>`.
pub const DEFAULT_CAPACITY: usize = 10;

/// Entries a depth-first tracer needs for paths of up to `bounces` bounces
/// when each hit pushes at most `branches` continuations (1 ..= 255;
/// 0 is taken as 1) and pop takes the most recent: `(branches − 1)·bounces
/// + 1` (derivation in the [module docs](self); the bound is reached).
/// Examples: `stack_bound(10, 2) = 11`, `stack_bound(b, 1) = 1`,
/// `stack_bound(255, 255) = 64 771` (no overflow for any `u8` inputs).
#[must_use]
pub const fn stack_bound(bounces: u8, branches: u8) -> usize {
    let k = if branches == 0 { 1 } else { branches as usize };
    (k - 1) * bounces as usize + 1
}

/// Ray-cone state (Akenine-Möller et al., RTG ch. 20): width `w` and spread
/// angle `γ`. Feature `cone`.
///
/// # Example
/// ```
/// use raymip::path::raystack::RayCone;
/// use raymip::{PathLength, Spread, Width};
/// // A cone from a point (w = 0) with spread γ = 2⁻¹⁰ rad (exact in I2F30).
/// let cone = RayCone { width: Width::ZERO, spread: Spread::from_num(1.0 / 1024.0) };
/// // w' = w + γ·t = 2⁻¹⁰ · 1024 = 1 scene unit.
/// let (hit, saturated) = cone.advance(PathLength::from_num(1024));
/// assert_eq!((hit.width, saturated), (Width::ONE, false));
/// // A convex surface widens the spread by β = 2⁻¹⁰: γ' = 2⁻⁹; 512 further
/// // the width is 1 + 2⁻⁹ · 512 = 2.
/// let (bounced, _) = hit.bounce(Spread::from_num(1.0 / 1024.0));
/// assert_eq!(bounced.spread, Spread::from_num(1.0 / 512.0));
/// assert_eq!(bounced.advance(PathLength::from_num(512)).0.width, Width::from_num(2));
/// // Beyond the I32F32 range the width saturates and says so.
/// let wide = RayCone { width: Width::MAX, spread: Spread::from_num(0.5) };
/// assert_eq!(wide.advance(PathLength::ONE), (wide, true));
/// ```
#[cfg(feature = "cone")]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct RayCone {
    /// Cone width at the current origin (scene units).
    pub width: Width,
    /// Spread angle (radians).
    pub spread: Spread,
}

#[cfg(feature = "cone")]
impl RayCone {
    /// `w' = w + γ·t`, saturating; the flag is true if it saturated.
    #[inline]
    #[must_use]
    pub fn advance(self, t: PathLength) -> (Self, bool) {
        let (grow, sat_mul) = mul_spread(self.spread, t);
        let (width, sat_add) = match self.width.checked_add(grow) {
            Some(w) => (w, false),
            None => (self.width.saturating_add(grow), true),
        };
        (
            Self {
                width,
                spread: self.spread,
            },
            sat_mul | sat_add,
        )
    }

    /// `γ' = γ + β` for a surface spread angle `β` (0 for flat surfaces),
    /// saturating; the flag is true if it saturated.
    #[inline]
    #[must_use]
    pub fn bounce(self, beta: Spread) -> (Self, bool) {
        match self.spread.checked_add(beta) {
            Some(spread) => (
                Self {
                    width: self.width,
                    spread,
                },
                false,
            ),
            None => (
                Self {
                    width: self.width,
                    spread: self.spread.saturating_add(beta),
                },
                true,
            ),
        }
    }
}

/// `γ·t` as I32F32 with two 32×32→64 multiplications (no 128-bit product);
/// saturates (flag true) beyond the I32F32 range. Rounded to nearest:
/// error ≤ 2⁻³³.
#[cfg(feature = "cone")]
#[inline]
fn mul_spread(g: Spread, t: PathLength) -> (Width, bool) {
    let g = i64::from(g.to_bits());
    let t = t.to_bits();
    let hi = g * ((t >> 32) as i64); // |.| < 2^31 · 2^32
    let lo = g * i64::from(t as u32); // |.| < 2^31 · 2^32
    // γ·t in 2^-62 units = hi·2^32 + lo; in 2^-32 units: hi·4 + lo/2^30.
    match hi
        .checked_mul(4)
        .and_then(|h| h.checked_add((lo + (1 << 29)) >> 30))
    {
        Some(v) => (Width::from_bits(v), false),
        None if g < 0 => (Width::MIN, true),
        None => (Width::MAX, true),
    }
}

/// The state of one path (one stack entry): what LOD needs, the path's ray
/// mask (stochastic LOD: chosen once per path, kept on every bounce) and its
/// depth. [`PATH_STATE_BYTES`] per entry: 32 with the `cone` feature, 16
/// without (no cone state carried, no `γ·t` per advance).
///
/// # Example
/// ```
/// use raymip::{PathLength, PathState, PixelSpread, Spread};
/// let spread = PixelSpread::from_fov_y(60f64.to_radians(), 480)?;
/// // A primary ray (ray mask 0xFF) hits at t = 100, bounces off a flat mirror
/// // (spread β = 0) and travels 47 more: the path length Pl is the sum.
/// let hit = PathState::primary(&spread, 0xFF).advance(PathLength::from_num(100));
/// let next = hit.bounce(Spread::ZERO).advance(PathLength::from_num(47));
/// assert_eq!(next.pl, PathLength::from_num(147));
/// assert_eq!(next.depth, hit.depth + 1);
/// # Ok::<(), raymip::CameraError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct PathState {
    /// Accumulated path length `Pl` from the camera (scene units).
    pub pl: PathLength,
    /// `Pl` normalised for the FAST table lod: [`NormPl::new`]`(pl)`, kept
    /// by [`PathState::primary`] and [`PathState::advance`] (the one
    /// leading-zero count of a segment is made there, so
    /// [`crate::lod::table_lod_norm`] and
    /// [`crate::lod::table_lod_norm_batch`] need none per hit). A caller
    /// that writes `pl` directly sets this to `NormPl::new(pl)` too. Lies
    /// in the padding of the entry: [`PATH_STATE_BYTES`] is unchanged.
    pub pl_norm: NormPl,
    /// Ray-cone state (feature `cone`).
    #[cfg(feature = "cone")]
    pub cone: RayCone,
    /// Ray differentials of the path's current ray (feature `raydiff`):
    /// zero in [`PathState::primary`]; the caller sets them up
    /// ([`crate::path::raydiff::RayDiff::primary`]) and updates them at each hit
    /// (transfer, then reflection or refraction for a continuation).
    #[cfg(feature = "raydiff")]
    pub diff: crate::path::raydiff::RayDiff,
    /// 8-bit ray mask of the path.
    pub mask: u8,
    /// Bounces so far (0 for a primary ray; saturates at 255).
    pub depth: u8,
    /// True once any quantity of this path saturated (its LOD is then a
    /// bound, not a value).
    pub saturated: bool,
}

impl PathState {
    /// A primary ray: `Pl = 0`, cone width 0 and spread `γ` of the camera.
    #[must_use]
    pub const fn primary(spread: &PixelSpread, mask: u8) -> Self {
        #[cfg(not(feature = "cone"))]
        let _ = spread;
        Self {
            pl: PathLength::ZERO,
            pl_norm: NormPl::ZERO,
            #[cfg(feature = "cone")]
            cone: RayCone {
                width: Width::ZERO,
                spread: spread.angle(),
            },
            #[cfg(feature = "raydiff")]
            diff: crate::path::raydiff::RayDiff::ZERO,
            mask,
            depth: 0,
            saturated: false,
        }
    }

    /// After a hit at distance `t`: `Pl += t` (and its [`NormPl`]), `w += γ·t`
    /// (saturating, flagged).
    #[inline]
    #[must_use]
    pub fn advance(self, t: PathLength) -> Self {
        let (pl, pl_sat) = match self.pl.checked_add(t) {
            Some(v) => (v, false),
            None => (PathLength::MAX, true),
        };
        #[cfg(feature = "cone")]
        let (cone, c_sat) = self.cone.advance(t);
        #[cfg(not(feature = "cone"))]
        let c_sat = false;
        Self {
            pl,
            pl_norm: NormPl::new(pl),
            #[cfg(feature = "cone")]
            cone,
            saturated: self.saturated | pl_sat | c_sat,
            ..self
        }
    }

    /// The state of a reflected or refracted continuation: spread `γ + β`
    /// (`β` = surface spread angle, 0 for flat; ignored without the `cone`
    /// feature), depth + 1.
    #[inline]
    #[must_use]
    pub fn bounce(self, beta: Spread) -> Self {
        #[cfg(feature = "cone")]
        let (cone, sat) = self.cone.bounce(beta);
        #[cfg(not(feature = "cone"))]
        let (sat, _) = (false, beta);
        Self {
            #[cfg(feature = "cone")]
            cone,
            depth: self.depth.saturating_add(1),
            saturated: self.saturated | sat,
            ..self
        }
    }
}

/// Bytes of one [`PathState`] (one ray-stack entry) on every target:
/// 32 with the `cone` feature (the cone is a 16-byte aligned pair), 16
/// without; the `raydiff` feature adds the 52-byte differential state
/// (88 with `cone`, 72 without: the entry's alignment pads it). Checked at compile time on every target.
pub const PATH_STATE_BYTES: usize = match (cfg!(feature = "cone"), cfg!(feature = "raydiff")) {
    (true, false) => 32,
    (false, false) => 16,
    (true, true) => 88,
    (false, true) => 72,
};
const _: () = assert!(core::mem::size_of::<PathState>() == PATH_STATE_BYTES);

/// A push onto a full stack: the rejected state and its caller payload are
/// handed back; the stack is unchanged.
///
/// # Example
/// ```
/// use raymip::{PathLength, PathState, PixelSpread, RayStack, StackFull};
/// let spread = PixelSpread::from_fov_y(1.0, 480)?;
/// let first = PathState::primary(&spread, 0xFF);
/// let mut stack: RayStack<u16, 1> = RayStack::new();
/// stack.push_with(first, 1)?;
/// // A second continuation (a bounce: depth 1) does not fit in one entry.
/// let second = first.advance(PathLength::from_num(3)).bounce(raymip::Spread::ZERO);
/// let err: StackFull<u16> = stack.push_with(second, 2).unwrap_err();
/// assert_eq!((err.0.pl, err.1), (PathLength::from_num(3), 2)); // handed back
/// assert_eq!(err.to_string(), "ray stack full (path depth 1)");
/// assert_eq!(stack.len(), 1);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct StackFull<T = ()>(pub PathState, pub T);

impl<T: fmt::Debug> core::error::Error for StackFull<T> {}

impl<T> fmt::Display for StackFull<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "ray stack full (path depth {})", self.0.depth)
    }
}

/// Fixed-capacity LIFO of [`PathState`]s (capacity `N`, default 10), each
/// with a caller payload `T` (default `()`: none), e.g. the host side of a
/// ray (origin, direction, weight) so that the caller keeps no second stack
/// in lockstep. At a hit push both the reflection and the refraction
/// branch; `pop` continues the most recently pushed one, then the other.
///
/// # Example
/// ```
/// use raymip::{PathState, PixelSpread, RayStack};
/// let spread = PixelSpread::from_fov_y(1.0, 480)?;
/// let primary = PathState::primary(&spread, 0xFF);
/// // Capacity 2, each entry carrying a caller payload (here a branch name).
/// let mut stack: RayStack<&str, 2> = RayStack::new();
/// stack.push_with(primary, "reflection")?;
/// stack.push_with(primary, "refraction")?;
/// assert!(stack.push_with(primary, "third").is_err()); // full: nothing lost
/// assert_eq!(stack.pop_with().map(|(_, p)| p), Some("refraction"));
/// assert_eq!(stack.len(), 1);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct RayStack<T = (), const N: usize = DEFAULT_CAPACITY> {
    entries: heapless::Vec<(PathState, T), N>,
}

impl<T, const N: usize> Default for RayStack<T, N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T, const N: usize> RayStack<T, N> {
    /// An empty stack.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            entries: heapless::Vec::new(),
        }
    }

    /// Pushes a state with its payload; on overflow returns both in
    /// [`StackFull`] and keeps everything already on the stack.
    #[inline]
    pub fn push_with(&mut self, state: PathState, payload: T) -> Result<(), StackFull<T>> {
        self.entries
            .push((state, payload))
            .map_err(|(s, p)| StackFull(s, p))
    }

    /// Pops the most recent state with its payload.
    #[inline]
    pub fn pop_with(&mut self) -> Option<(PathState, T)> {
        self.entries.pop()
    }

    /// The most recent state and its payload without removing them.
    #[inline]
    #[must_use]
    pub fn peek_with(&self) -> Option<(&PathState, &T)> {
        self.entries.last().map(|(s, p)| (s, p))
    }

    /// Number of states on the stack.
    #[must_use]
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when empty.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Capacity `N`.
    #[must_use]
    pub const fn capacity(&self) -> usize {
        N
    }

    /// Removes every state.
    pub fn clear(&mut self) {
        self.entries.clear();
    }
}

impl<const N: usize> RayStack<(), N> {
    /// Pushes a state; on overflow returns it in [`StackFull`] and keeps
    /// everything already on the stack.
    #[inline]
    pub fn push(&mut self, state: PathState) -> Result<(), StackFull> {
        self.push_with(state, ())
    }

    /// Pops the most recent state.
    #[inline]
    pub fn pop(&mut self) -> Option<PathState> {
        self.pop_with().map(|(s, ())| s)
    }

    /// The most recent state without removing it.
    #[inline]
    #[must_use]
    pub fn peek(&self) -> Option<&PathState> {
        self.peek_with().map(|(s, _)| s)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use proptest::prelude::*;

    fn spread(g: f64) -> PixelSpread {
        PixelSpread::from_angle(Spread::from_num(g)).unwrap()
    }

    /// The normalised `Pl` in every entry is the one of its `Pl`, after
    /// any sequence of segments (saturation included) and by default.
    #[test]
    fn pl_norm_follows_pl() {
        assert_eq!(PathState::default().pl_norm, NormPl::new(PathLength::ZERO));
        let spread = PixelSpread::from_angle(Spread::from_num(0.001)).unwrap();
        let mut st = PathState::primary(&spread, 0);
        assert_eq!(st.pl_norm, NormPl::new(st.pl));
        for t in [0u64, 1, 3 << 20, 1 << 32, 7 << 40, u64::MAX / 3, u64::MAX] {
            st = st.advance(PathLength::from_bits(t)).bounce(Spread::ZERO);
            assert_eq!(st.pl_norm, NormPl::new(st.pl), "after +{t:#x}");
        }
        assert!(st.saturated);
        // Saturation is sticky: a further segment that saturates `Pl` again
        // (the cone does not) keeps the flag.
        st = st.advance(PathLength::ONE);
        assert!(st.saturated && st.pl == PathLength::MAX);
    }

    /// When `γ·t` saturates and the sum with the width overflows too, the
    /// cone still reports saturation (both flags set at once).
    #[cfg(feature = "cone")]
    #[test]
    fn cone_flags_saturation_of_product_and_sum() {
        let cone = RayCone {
            width: Width::ONE,
            spread: Spread::from_num(1.5),
        };
        let (got, saturated) = cone.advance(PathLength::MAX);
        assert_eq!((got.width, saturated), (Width::MAX, true));
        let neg = RayCone {
            width: Width::from_num(-1),
            spread: Spread::from_num(-1.5),
        };
        assert_eq!(
            neg.advance(PathLength::MAX),
            (
                RayCone {
                    width: Width::MIN,
                    ..neg
                },
                true
            )
        );
    }

    /// A bounce whose spread saturates keeps the flag of a path that had
    /// saturated before.
    #[cfg(feature = "cone")]
    #[test]
    fn bounce_keeps_saturation() {
        let once = PathState::primary(&spread(0.001), 0).bounce(Spread::MAX);
        assert!(once.saturated && once.cone.spread == Spread::MAX);
        let twice = once.bounce(Spread::MAX);
        assert!(twice.saturated && twice.cone.spread == Spread::MAX);
    }

    #[test]
    fn push_pop_order_and_overflow() {
        let mut s: RayStack<(), 3> = RayStack::new();
        let base = PathState::primary(&spread(0.001), 0b0000_0100);
        for d in 0..3u8 {
            s.push(PathState { depth: d, ..base }).unwrap();
        }
        assert!(!s.is_empty());
        let extra = PathState { depth: 9, ..base };
        assert_eq!(s.push(extra), Err(StackFull(extra, ())));
        assert_eq!(s.len(), 3, "overflow keeps the stack");
        assert_eq!(s.pop().map(|p| p.depth), Some(2));
        assert_eq!(s.pop().map(|p| p.depth), Some(1));
        assert_eq!(s.peek().map(|p| p.depth), Some(0));
        s.clear();
        assert!(s.is_empty() && s.pop().is_none());
        assert_eq!(RayStack::<(), 10>::new().capacity(), 10);
        assert!(std::format!("{}", StackFull(extra, ())).contains("full"));
    }

    #[test]
    fn payload_travels_with_its_state() {
        let base = PathState::primary(&spread(0.001), 0xFF);
        let mut s: RayStack<u32, 2> = RayStack::new();
        s.push_with(base.bounce(Spread::ZERO), 7).unwrap();
        s.push_with(base.bounce(Spread::ZERO).bounce(Spread::ZERO), 8)
            .unwrap();
        let extra = base;
        assert_eq!(s.push_with(extra, 9), Err(StackFull(extra, 9)));
        assert_eq!(s.peek_with().map(|(st, p)| (st.depth, *p)), Some((2, 8)));
        assert_eq!(s.pop_with().map(|(st, p)| (st.depth, p)), Some((2, 8)));
        assert_eq!(s.pop_with().map(|(st, p)| (st.depth, p)), Some((1, 7)));
        assert_eq!(s.pop_with(), None);
        assert!(s.is_empty());
    }

    #[test]
    fn both_branches_continue_with_their_state() {
        // At a hit after t = 2, push refraction (β = 0) and reflection
        // (β = 0.01); pop reflection first, then refraction; mask kept.
        let mut s: RayStack = RayStack::new();
        let hit = PathState::primary(&spread(0.001), 0x80).advance(PathLength::from_num(2));
        s.push(hit.bounce(Spread::ZERO)).unwrap();
        s.push(hit.bounce(Spread::from_num(0.01))).unwrap();
        let refl = s.pop().unwrap().advance(PathLength::from_num(1));
        let refr = s.pop().unwrap().advance(PathLength::from_num(3));
        assert_eq!(refl.pl, PathLength::from_num(3));
        assert_eq!(refr.pl, PathLength::from_num(5));
        assert_eq!(
            (refl.depth, refr.depth, refl.mask, refr.mask),
            (1, 1, 0x80, 0x80)
        );
        #[cfg(feature = "cone")]
        {
            let w = refl.cone.width.to_num::<f64>();
            let want = 0.001 * 2.0 + (0.001 + 0.01) * 1.0;
            assert!((w - want).abs() < 1e-8, "{w} vs {want}");
        }
    }

    #[test]
    fn saturation_is_flagged_not_wrapped() {
        let p = PathState::primary(&spread(1.5), 0).advance(PathLength::MAX);
        // Pl = 0 + MAX is exact; only the cone width (1.5·MAX) saturates.
        assert_eq!(p.saturated, cfg!(feature = "cone"));
        assert_eq!(p.pl, PathLength::MAX);
        #[cfg(feature = "cone")]
        assert_eq!(p.cone.width, Width::MAX);
        let p2 = PathState::primary(&spread(0.5), 0)
            .advance(PathLength::from_num(4.0e9))
            .advance(PathLength::from_num(4.0e9));
        assert!(p2.saturated && p2.pl == PathLength::MAX);
        #[cfg(feature = "cone")]
        let neg = PathState::primary(&spread(0.5), 0)
            .bounce(Spread::MIN)
            .bounce(Spread::MIN);
        #[cfg(feature = "cone")]
        {
            assert!(neg.saturated && neg.cone.spread == Spread::MIN);
            let neg_w = neg.advance(PathLength::from_num(4.0e9));
            assert_eq!(neg_w.cone.width, Width::MIN);
        }
        let deep = (0..300).fold(PathState::default(), |p, _| p.bounce(Spread::ZERO));
        assert_eq!(deep.depth, 255);
    }

    /// A depth-first tracer over a 64-entry stack: pops, and below depth
    /// `bounces` pushes `branches(node)` children; returns the largest
    /// occupancy seen and whether a push failed.
    fn trace_tree(bounces: u8, mut branches: impl FnMut(u32) -> u8) -> (usize, bool) {
        let mut s: RayStack<(), 64> = RayStack::new();
        let mut full = false;
        let mut node = 0u32;
        s.push(PathState::default()).unwrap();
        let mut most = s.len();
        while let Some(p) = s.pop() {
            node += 1;
            if p.depth < bounces {
                for _ in 0..branches(node) {
                    full |= s.push(p.bounce(Spread::ZERO)).is_err();
                }
            }
            most = most.max(s.len());
        }
        (most, full)
    }

    #[test]
    fn stack_bound_is_reached_by_full_trees() {
        // Full k-ary trees reach (k − 1)·B + 1 exactly.
        for (k, max_b) in [(1u8, 12u8), (2, 10), (3, 5)] {
            for b in 0..=max_b {
                let (most, full) = trace_tree(b, |_| k);
                assert!(!full);
                assert_eq!(most, stack_bound(b, k), "B = {b}, k = {k}");
            }
        }
        assert_eq!(stack_bound(10, 2), 11);
        assert_eq!(stack_bound(9, 2), DEFAULT_CAPACITY);
        assert_eq!(stack_bound(200, 0), 1);
        assert_eq!(stack_bound(u8::MAX, u8::MAX), 254 * 255 + 1);
        // The paper's 10 entries drop a branch of a full binary tree of
        // 10 bounces: the case the host renderer sizes its stack for.
        let mut s: RayStack<(), DEFAULT_CAPACITY> = RayStack::new();
        let mut dropped = 0;
        s.push(PathState::default()).unwrap();
        while let Some(p) = s.pop() {
            if p.depth < 10 {
                for _ in 0..2 {
                    dropped += u32::from(s.push(p.bounce(Spread::ZERO)).is_err());
                }
            }
        }
        assert!(dropped > 0);
    }

    proptest! {
        /// Any branching of at most 2 (0, 1 or 2 per hit) stays within
        /// `stack_bound(B, 2)`.
        #[test]
        fn binary_branching_stays_within_the_bound(
            b in 0u8..=10,
            picks in proptest::collection::vec(0u8..=2, 1..2048),
        ) {
            let (most, full) = trace_tree(b, |n| picks[n as usize % picks.len()]);
            prop_assert!(!full);
            prop_assert!(most <= stack_bound(b, 2), "{} > {}", most, stack_bound(b, 2));
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(5_000))]
        /// Ten bounces against an f64 reference of the same recurrences.
        #[cfg(feature = "cone")]
        #[test]
        fn ten_bounces_match_f64(
            g in 1.0e-5..0.1f64,
            segs in proptest::collection::vec((1.0e-3..1.0e4f64, -0.05..0.05f64), 1..=10),
        ) {
            let mut st = PathState::primary(&spread(g), 1);
            let mut pl = 0.0f64;
            let mut w = 0.0f64;
            let mut gam = Spread::from_num(g).to_num::<f64>();
            for &(t, beta) in &segs {
                let tq = PathLength::from_num(t);
                let bq = Spread::from_num(beta);
                st = st.advance(tq).bounce(bq);
                pl += tq.to_num::<f64>();
                w += gam * tq.to_num::<f64>();
                gam += bq.to_num::<f64>();
            }
            prop_assert!(!st.saturated);
            prop_assert_eq!(st.pl.to_num::<f64>(), pl, "Pl sums exactly");
            let ew = (st.cone.width.to_num::<f64>() - w).abs();
            prop_assert!(ew <= 1e-8 * (1.0 + w.abs()), "width {} vs {}", st.cone.width, w);
            prop_assert_eq!(st.cone.spread.to_num::<f64>(), gam);
            prop_assert_eq!(usize::from(st.depth), segs.len());
        }

        #[cfg(feature = "cone")]
        #[test]
        fn mul_spread_matches_f64(g in any::<i32>(), t in any::<u64>()) {
            let (got, sat) = mul_spread(Spread::from_bits(g), PathLength::from_bits(t));
            let want = f64::from(g) * 2f64.powi(-30) * (t as f64) * 2f64.powi(-32);
            if want.abs() < 2.1e9 {
                prop_assert!(!sat);
                prop_assert!((got.to_num::<f64>() - want).abs() <= 1e-9 * want.abs().max(1.0));
            } else if want.abs() > 2.2e9 {
                prop_assert!(sat);
                prop_assert_eq!(got, if g < 0 { Width::MIN } else { Width::MAX });
            }
        }
    }
}
