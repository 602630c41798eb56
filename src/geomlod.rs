//! Stochastic geometric level of detail for instanced geometry: a LOD per
//! instance from its depth, and a dissolve between two LODs by ray masks.
//!
//! After NVIDIA's "Implementing Stochastic Levels of Detail with DirectX
//! Raytracing", 2020: per instance a LOD from its camera-space depth, and
//! during a LOD transition two instances (the two neighbouring LODs) with
//! complementary 8-bit instance masks; each path draws one random ray-mask
//! bit, so a path sees exactly one of the two and the image dissolves from
//! one LOD to the other as the LOD parameter moves.
//!
//! # Per instance (float-free, panic-free, two multiplications, one division)
//!
//! 1. LOD parameter ([`DepthToLod::lod_param`]):
//!    `l = L·(z − z_near)/(z_far − z_near) + bias`, clamped to `[0, L − 1]`
//!    (`L` = number of LODs, 1…[`MAX_LODS`]). [`GeomLod`] = U16F16.
//! 2. Discrete mode: the nearest LOD, `round(l)` (ties up), mask `0xFF`.
//! 3. Stochastic mode with transition interval `t ∈ [0, 1]`:
//!    `k_a = ⌊l⌋`, `k_b = min(k_a + 1, L − 1)`, `f = l − ⌊l⌋`,
//!    `f' = clamp((f − ½)/t + ½, 0, 1)` (`t = 0`: `f' = 1` for `f ≥ ½`,
//!    else 0, which is exactly the discrete mode),
//!    `mask_b = (1 << ⌊9·f'⌋) − 1` kept to 8 bits, `mask_a = !mask_b`.
//!    An instance record is emitted for each non-zero mask (`a` first).
//!    `⌊9·f'⌋` is computed exactly as the integer quotient
//!    `⌊(18·(f − ½) + 9·t) / (2·t)⌋` (f, t in 2⁻¹⁶ units) clamped to
//!    `[0, 9]`, so `popcount(mask_b) = min(⌊9·f'⌋, 8)` holds to the bit.
//!
//! # Per path
//!
//! [`ray_mask`]: one uniformly random bit `1 << (r & 7)` from the
//! [`crate::rng::Rng`] of the pixel and frame; the path keeps it in its
//! [`crate::path::raystack::PathState::mask`] for every later ray (reflection,
//! refraction, shadow, ambient occlusion). An instance is visible to a ray
//! iff `instance_mask & ray_mask != 0` ([`visible`]).
//!
//! # Number formats and error bound
//!
//! * [`Depth`] = I32F32 scene units (camera-space depth; negative = behind
//!   the camera, read as `z_near`).
//! * [`GeomLod`] = U16F16 levels, result range `[0, L − 1] ⊂ [0, 7]`.
//! * [`LodBias`] = I16F16 levels; [`Transition`] = U16F16 in `[0, 1]`.
//!
//! `lod_param` is within [`LOD_PARAM_MAX_ERROR`] `= 2⁻¹⁵` level of the exact
//! value of its (quantised) inputs: the set-up normalises `z_far − z_near`
//! to a 32-bit mantissa `r` (top bit set, relative error ≤ 2⁻³¹) and
//! stores `k = ⌊L·2⁴⁸/r⌋` (≥ 2¹⁶, so ≤ 1 unit = 2⁻¹⁶ relative error); per
//! instance `l·2¹⁶ = ⌊d·k/2³²⌋` with `d < r` (≤ 1 unit from `k`, ≤ 1 unit
//! from the floor, < 2⁻¹² unit from truncating `d`), so the error is below
//! 2 units = 2⁻¹⁵. The bias is added exactly; clamping does not add error.

use core::fmt;

use crate::units::{Depth, GeomLod, LodBias, Transition};

/// Most LODs a mesh may have: 8, one per instance-mask bit.
pub const MAX_LODS: u8 = 8;

/// Error bound of [`DepthToLod::lod_param`] against the exact value of its
/// inputs, in levels: 2⁻¹⁵.
pub const LOD_PARAM_MAX_ERROR: f64 = 1.0 / 32768.0;

/// A set-up error of [`DepthToLod::new`] or [`Selector::new`].
///
/// # Example
/// ```
/// use raymip::geomlod::{ConfigError, DepthToLod, LodMode, Selector};
/// use raymip::units::{Depth, LodBias, Transition};
/// let (near, far) = (Depth::from_num(1), Depth::from_num(33));
/// let err = DepthToLod::new(near, far, 0, LodBias::ZERO).unwrap_err();
/// assert_eq!(err, ConfigError::Levels(0));
/// assert_eq!(err.to_string(), "0 LODs: need 1 to 8");
/// // z_far must lie beyond z_near.
/// let err = DepthToLod::new(far, near, 4, LodBias::ZERO).unwrap_err();
/// assert_eq!(err, ConfigError::EmptyRange);
/// assert_eq!(err.to_string(), "LOD depth range empty: z_far must exceed z_near");
/// // A transition interval of 2 is longer than the interval between two LODs.
/// let range = DepthToLod::new(near, far, 4, LodBias::ZERO)?;
/// let err = Selector::new(range, LodMode::Stochastic(Transition::from_num(2))).unwrap_err();
/// assert_eq!(err, ConfigError::Transition(Transition::from_num(2)));
/// assert_eq!(err.to_string(), "transition interval 2: must lie in [0, 1]");
/// # Ok::<(), ConfigError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ConfigError {
    /// The number of LODs is 0 or above [`MAX_LODS`].
    Levels(u8),
    /// `z_far ≤ z_near`, or the difference overflows I32F32.
    EmptyRange,
    /// The transition interval is above 1.
    Transition(Transition),
}

impl core::error::Error for ConfigError {}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Levels(n) => write!(f, "{n} LODs: need 1 to {MAX_LODS}"),
            Self::EmptyRange => f.write_str("LOD depth range empty: z_far must exceed z_near"),
            Self::Transition(t) => write!(f, "transition interval {t}: must lie in [0, 1]"),
        }
    }
}

/// The depth-to-LOD mapping: `l = L·(z − z_near)/(z_far − z_near) + bias`,
/// clamped to `[0, L − 1]`. Built once (integer division at set-up only).
///
/// # Example
/// ```
/// use raymip::geomlod::DepthToLod;
/// use raymip::units::{Depth, GeomLod, LodBias};
/// // 4 LODs over depths 0..32: l = 4·z/32 = z/8.
/// let range = DepthToLod::new(Depth::ZERO, Depth::from_num(32), 4, LodBias::ZERO)?;
/// assert_eq!(range.levels(), 4);
/// assert_eq!(range.lod_param(Depth::from_num(12)), GeomLod::from_num(1.5));
/// // Behind the near plane: LOD 0; beyond the far plane: clamped to L − 1 = 3.
/// assert_eq!(range.lod_param(Depth::from_num(-5)), GeomLod::ZERO);
/// assert_eq!(range.lod_param(Depth::from_num(100)), GeomLod::from_num(3));
/// // A bias of half a level is added before the clamp: 8/8 + ½.
/// let biased = DepthToLod::new(Depth::ZERO, Depth::from_num(32), 4, LodBias::from_num(0.5))?;
/// assert_eq!(biased.lod_param(Depth::from_num(8)), GeomLod::from_num(1.5));
/// # Ok::<(), raymip::geomlod::ConfigError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DepthToLod {
    z_near: i64,
    range: u64,
    /// Left shift (negative: right shift) that brings `range` to `[2³¹, 2³²)`.
    shift: i32,
    /// `⌊L·2⁴⁸ / (range normalised)⌋`.
    k: u32,
    levels: u8,
    bias: i32,
}

impl DepthToLod {
    /// `levels` LODs (1…8) spread from `z_near` (LOD 0) to `z_far`
    /// (parameter `L`, clamped to `L − 1`), plus `bias` levels.
    pub fn new(
        z_near: Depth,
        z_far: Depth,
        levels: u8,
        bias: LodBias,
    ) -> Result<Self, ConfigError> {
        if levels == 0 || levels > MAX_LODS {
            return Err(ConfigError::Levels(levels));
        }
        let range = z_far
            .to_bits()
            .checked_sub(z_near.to_bits())
            .filter(|&r| r > 0)
            .ok_or(ConfigError::EmptyRange)? as u64;
        let shift = range.leading_zeros() as i32 - 32;
        let r32 = normalise(range, shift);
        let k = ((u64::from(levels) << 48) / u64::from(r32.max(1 << 31))) as u32;
        Ok(Self {
            z_near: z_near.to_bits(),
            range,
            shift,
            k,
            levels,
            bias: bias.to_bits(),
        })
    }

    /// Number of LODs `L`.
    #[must_use]
    pub const fn levels(&self) -> u8 {
        self.levels
    }

    /// The LOD parameter of an instance at camera-space depth `z`, in
    /// `[0, L − 1]`, within [`LOD_PARAM_MAX_ERROR`].
    #[inline]
    #[must_use]
    pub fn lod_param(&self, z: Depth) -> GeomLod {
        let d = z.to_bits().saturating_sub(self.z_near);
        let l = if d <= 0 {
            0
        } else if d as u64 >= self.range {
            i32::from(self.levels) << 16
        } else {
            let d32 = normalise(d as u64, self.shift);
            ((u64::from(d32) * u64::from(self.k)) >> 32) as i32 // ≤ 8·2¹⁶
        };
        let top = i32::from(self.levels - 1) << 16;
        GeomLod::from_bits(l.saturating_add(self.bias).clamp(0, top) as u32)
    }
}

/// `x·2^shift` for `x ≤ range` (fits 32 bits by construction of `shift`).
#[inline]
fn normalise(x: u64, shift: i32) -> u32 {
    if shift >= 0 {
        (x << (shift as u32 & 63)) as u32
    } else {
        (x >> (shift.unsigned_abs() & 63)) as u32
    }
}

/// How instances pick their LOD. Example: [`Selector`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LodMode {
    /// One LOD per instance, `round(l)`, mask `0xFF`.
    Discrete,
    /// Cross-dissolve between `⌊l⌋` and `⌊l⌋ + 1` over the transition
    /// interval `t` around `f = ½`.
    Stochastic(Transition),
}

/// The LOD choice for one instance: LOD `a` with `mask_a` and LOD `b` with
/// `mask_b`; a zero mask means that record is not emitted.
/// `mask_a | mask_b == 0xFF` and `mask_a & mask_b == 0` always.
/// Example: [`Selector`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Choice {
    /// `k_a = ⌊l⌋` (discrete mode: the chosen LOD).
    pub lod_a: u8,
    /// Instance mask of LOD `a`.
    pub mask_a: u8,
    /// `k_b = min(k_a + 1, L − 1)`.
    pub lod_b: u8,
    /// Instance mask of LOD `b`.
    pub mask_b: u8,
}

/// `⌊9·f'⌋` clamped to `[0, 9]` for `f = f16/2¹⁶`, `t = t16/2¹⁶`, exactly.
#[inline]
#[must_use]
pub fn transition_step(f16: u32, t16: u32) -> u32 {
    let f16 = f16 & 0xFFFF;
    if t16 == 0 {
        return if f16 >= 0x8000 { 9 } else { 0 };
    }
    // 9·f' = 9·(f − ½)/t + 4.5 = (18·(f − ½) + 9·t) / (2·t).
    let t16 = t16.min(1 << 16) as i32;
    let num = 18 * (f16 as i32 - 0x8000) + 9 * t16;
    if num <= 0 {
        return 0;
    }
    (num as u32).checked_div(2 * t16 as u32).unwrap_or(0).min(9)
}

/// The instance choice for LOD parameter `l` with `levels` LODs.
#[inline]
#[must_use]
pub fn choose(l: GeomLod, levels: u8, mode: LodMode) -> Choice {
    let bits = l.to_bits();
    let top = levels.clamp(1, MAX_LODS) - 1;
    let lod_a = ((bits >> 16).min(u32::from(top))) as u8;
    let lod_b = (lod_a + 1).min(top);
    let f = if lod_a == top { 0 } else { bits & 0xFFFF };
    match mode {
        LodMode::Discrete => Choice {
            lod_a: if f >= 0x8000 { lod_b } else { lod_a },
            mask_a: 0xFF,
            lod_b,
            mask_b: 0,
        },
        LodMode::Stochastic(t) => {
            let step = transition_step(f, t.to_bits());
            let mask_b = ((1u32 << step) - 1) as u8;
            Choice {
                lod_a,
                mask_a: !mask_b,
                lod_b,
                mask_b,
            }
        }
    }
}

/// One instance record for the top-level acceleration structure: which
/// instance, which of its LOD meshes, which ray-mask bits see it.
/// 8 bytes (`#[repr(C)]`: `u32`, `u8`, `u8`, 2 bytes padding).
/// Example: [`Selector`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct InstanceLod {
    /// Instance id (the caller's).
    pub id: u32,
    /// LOD index (0 = finest).
    pub lod: u8,
    /// 8-bit instance mask.
    pub mask: u8,
}

/// The record array was too small. The first `capacity` records were
/// written; `needed` is how many the whole set takes (retry with that many).
///
/// # Example
/// ```
/// use raymip::geomlod::{DepthToLod, InstanceLod, LodMode, RecordsFull, Selector};
/// use raymip::units::{Depth, LodBias, Transition};
/// let range = DepthToLod::new(Depth::ZERO, Depth::from_num(32), 4, LodBias::ZERO)?;
/// let selector = Selector::new(range, LodMode::Stochastic(Transition::ONE))?;
/// // Depth 12 is l = 1.5, mid-transition: two records (LODs 1 and 2).
/// let mut out = [InstanceLod::default(); 1];
/// let err: RecordsFull = selector.fill([(5, Depth::from_num(12))], &mut out).unwrap_err();
/// assert_eq!((err.needed, err.capacity), (2, 1));
/// assert_eq!(err.to_string(), "instance record array too small: 2 records needed, room for 1");
/// assert_eq!(out[0].lod, 1); // the first record was written
/// # Ok::<(), raymip::geomlod::ConfigError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct RecordsFull {
    /// Records the whole input needs.
    pub needed: usize,
    /// Records the given array holds.
    pub capacity: usize,
}

impl core::error::Error for RecordsFull {}

impl fmt::Display for RecordsFull {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "instance record array too small: {} records needed, room for {}",
            self.needed, self.capacity
        )
    }
}

/// Depth range + mode: picks LODs and masks per instance.
///
/// # Example
/// ```
/// use raymip::geomlod::{Choice, DepthToLod, InstanceLod, LodMode, Selector};
/// use raymip::units::{Depth, LodBias, Transition};
/// use raymip::geomlod::visible;
/// // 4 LODs over depths 0..32: l = z/8.
/// let range = DepthToLod::new(Depth::ZERO, Depth::from_num(32), 4, LodBias::ZERO)?;
/// // Discrete: round(l), ties up; depth 12 is l = 1.5 → LOD 2 for every ray.
/// let discrete = Selector::new(range, LodMode::Discrete)?;
/// assert_eq!((discrete.pick(Depth::from_num(12)).lod_a, discrete.pick(Depth::from_num(12)).mask_a), (2, 0xFF));
/// // Stochastic over the whole interval (t = 1): f' = (f − ½)/1 + ½ = f.
/// let dissolve = Selector::new(range, LodMode::Stochastic(Transition::ONE))?;
/// // l = 1.5: ⌊9·½⌋ = 4 mask bits for LOD 2, the other 4 for LOD 1.
/// let c = dissolve.pick(Depth::from_num(12));
/// assert_eq!(c, Choice { lod_a: 1, mask_a: 0xF0, lod_b: 2, mask_b: 0x0F });
/// // l = 1.0: f = 0, every bit for LOD 1 and no record for LOD 2.
/// let mut records = [InstanceLod::default(); 4];
/// let n = dissolve.fill([(7, Depth::from_num(8)), (9, Depth::from_num(12))], &mut records)?;
/// assert_eq!(n, 3);
/// assert_eq!(records[0], InstanceLod { id: 7, lod: 1, mask: 0xFF });
/// assert_eq!(records[1], InstanceLod { id: 9, lod: 1, mask: 0xF0 });
/// assert_eq!(records[2], InstanceLod { id: 9, lod: 2, mask: 0x0F });
/// // A path with ray-mask bit 0 sees instance 9 at LOD 2 only.
/// assert!(visible(records[2].mask, 0x01) && !visible(records[1].mask, 0x01));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Selector {
    range: DepthToLod,
    mode: LodMode,
}

impl Selector {
    /// A selector; errors for a transition interval above 1.
    pub fn new(range: DepthToLod, mode: LodMode) -> Result<Self, ConfigError> {
        if let LodMode::Stochastic(t) = mode
            && t > Transition::ONE
        {
            return Err(ConfigError::Transition(t));
        }
        Ok(Self { range, mode })
    }

    /// The choice for an instance at camera-space depth `z`.
    #[inline]
    #[must_use]
    pub fn pick(&self, z: Depth) -> Choice {
        choose(self.range.lod_param(z), self.range.levels, self.mode)
    }

    /// Writes the records of every `(id, depth)` into `out` (`a` before `b`
    /// for each instance; a record only for a non-zero mask) and returns how
    /// many it wrote: between N and 2N for N instances. When `out` is too
    /// small, it is filled and the error says how many records the whole
    /// input needs.
    pub fn fill<I>(&self, instances: I, out: &mut [InstanceLod]) -> Result<usize, RecordsFull>
    where
        I: IntoIterator<Item = (u32, Depth)>,
    {
        let mut n = 0usize;
        for (id, z) in instances {
            let c = self.pick(z);
            for (lod, mask) in [(c.lod_a, c.mask_a), (c.lod_b, c.mask_b)] {
                if mask != 0 {
                    if let Some(slot) = out.get_mut(n) {
                        *slot = InstanceLod { id, lod, mask };
                    }
                    n = n.saturating_add(1);
                }
            }
        }
        if n > out.len() {
            Err(RecordsFull {
                needed: n,
                capacity: out.len(),
            })
        } else {
            Ok(n)
        }
    }
}

/// The ray mask of a new path: one uniformly random bit, `1 << (r & 7)`.
#[inline]
#[must_use]
pub fn ray_mask(rng: &mut crate::rng::Rng) -> u8 {
    1u8 << (rng.next_u32() & 7)
}

/// True iff an instance with `instance_mask` is visible to a ray with
/// `ray_mask`: `instance_mask & ray_mask != 0`.
#[inline]
#[must_use]
pub const fn visible(instance_mask: u8, ray_mask: u8) -> bool {
    instance_mask & ray_mask != 0
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::rng::Rng;
    use proptest::prelude::*;
    use std::vec::Vec;

    fn d(x: f64) -> Depth {
        Depth::from_num(x)
    }

    /// f64 reference of `⌊9·f'⌋`; `None` when 9·f' lies within 1e-9 of an
    /// integer (f64 rounding may fall either side there).
    fn step_ref(f: f64, t: f64) -> Option<u32> {
        let fp = if t == 0.0 {
            if f >= 0.5 { 1.0 } else { 0.0 }
        } else {
            ((f - 0.5) / t + 0.5).clamp(0.0, 1.0)
        };
        let x = 9.0 * fp;
        ((x - x.round()).abs() > 1e-9 || x == 0.0 || x == 9.0).then(|| x.floor() as u32)
    }

    /// The largest error of `lod_param` against f64 on a fixed grid of
    /// ranges, depths and biases: within [`LOD_PARAM_MAX_ERROR`], and that
    /// documented bound within 4× of it.
    #[test]
    fn lod_param_bound_is_tight() {
        let mut worst = 0.0f64;
        for (near, span) in [(0.0, 8.0), (-3.25, 0.7), (1.0e3, 1.7e4), (12.5, 0.001)] {
            for levels in 1u8..=8 {
                for bias in [-1.5, 0.0, 0.3] {
                    let (zn, zf, b) = (d(near), d(near + span), LodBias::from_num(bias));
                    let r = DepthToLod::new(zn, zf, levels, b).unwrap();
                    let (znf, zff) = (zn.to_num::<f64>(), zf.to_num::<f64>());
                    for k in 0..=1000 {
                        let z = d(near + span * f64::from(k) / 1000.0);
                        let f = ((z.to_num::<f64>() - znf) / (zff - znf)).clamp(0.0, 1.0);
                        let l = f64::from(levels) * f + b.to_num::<f64>();
                        let want = l.clamp(0.0, f64::from(levels - 1));
                        worst = worst.max((r.lod_param(z).to_num::<f64>() - want).abs());
                    }
                }
            }
        }
        std::println!("lod_param: max |error| {worst:.3e} (bound {LOD_PARAM_MAX_ERROR:.3e})");
        assert!(worst <= LOD_PARAM_MAX_ERROR);
        assert!(
            LOD_PARAM_MAX_ERROR <= 4.0 * worst,
            "bound over 4x the measured {worst:.3e}"
        );
    }

    #[test]
    fn reference_vectors() {
        let r = DepthToLod::new(d(0.0), d(8.0), 8, LodBias::ZERO).unwrap();
        let s = |z: f64, t: f64| {
            let sel = Selector::new(r, LodMode::Stochastic(Transition::from_num(t))).unwrap();
            sel.pick(d(z))
        };
        // l = 2.5, t = 1: f' = 0.5, ⌊4.5⌋ = 4 bits of b.
        assert_eq!(
            s(2.5, 1.0),
            Choice {
                lod_a: 2,
                mask_a: 0xF0,
                lod_b: 3,
                mask_b: 0x0F
            }
        );
        // l = 2.25, t = 0.5: f' = 0, all a.
        assert_eq!(s(2.25, 0.5).mask_a, 0xFF);
        // l = 2.6, t = 0.5: f' = 0.7, ⌊6.3⌋ = 6.
        assert_eq!(s(2.6, 0.5).mask_b, 0x3F);
        // l = 2.99, t = 1: f' = 0.99, ⌊8.91⌋ = 8 → 0xFF, a gets nothing.
        assert_eq!((s(2.99, 1.0).mask_a, s(2.99, 1.0).mask_b), (0, 0xFF));
        // Depth beyond z_far: clamped to L − 1 = 7.
        assert_eq!(r.lod_param(d(100.0)), GeomLod::from_num(7));
        assert_eq!(r.lod_param(d(-5.0)), GeomLod::ZERO);
        let biased = DepthToLod::new(d(0.0), d(8.0), 8, LodBias::from_num(-1.5)).unwrap();
        assert_eq!(biased.lod_param(d(4.0)), GeomLod::from_num(2.5));
        assert_eq!(biased.lod_param(d(1.0)), GeomLod::ZERO);
    }

    #[test]
    fn config_errors_and_display() {
        assert_eq!(
            DepthToLod::new(d(1.0), d(2.0), 0, LodBias::ZERO),
            Err(ConfigError::Levels(0))
        );
        assert_eq!(
            DepthToLod::new(d(1.0), d(2.0), 9, LodBias::ZERO),
            Err(ConfigError::Levels(9))
        );
        assert_eq!(
            DepthToLod::new(d(2.0), d(2.0), 8, LodBias::ZERO),
            Err(ConfigError::EmptyRange)
        );
        assert_eq!(
            DepthToLod::new(Depth::MIN, Depth::MAX, 8, LodBias::ZERO),
            Err(ConfigError::EmptyRange)
        );
        let r = DepthToLod::new(d(1.0), d(2.0), 8, LodBias::ZERO).unwrap();
        let t = Transition::from_num(1.5);
        assert_eq!(
            Selector::new(r, LodMode::Stochastic(t)),
            Err(ConfigError::Transition(t))
        );
        for e in [
            ConfigError::Levels(9),
            ConfigError::EmptyRange,
            ConfigError::Transition(t),
        ] {
            assert!(!std::format!("{e}").is_empty());
        }
    }

    #[test]
    fn fill_counts_and_too_small_loses_nothing() {
        let r = DepthToLod::new(d(0.0), d(8.0), 8, LodBias::ZERO).unwrap();
        let sel = Selector::new(r, LodMode::Stochastic(Transition::ONE)).unwrap();
        // Depths 0.5, 2.5, 7.0 (l = 7 = top: only a) and 3.0 (f = 0: only a).
        let inst: Vec<(u32, Depth)> = [(10, 0.5), (11, 2.5), (12, 7.0), (13, 3.0)]
            .iter()
            .map(|&(i, z)| (i, d(z)))
            .collect();
        let mut out = [InstanceLod::default(); 8];
        let n = sel.fill(inst.iter().copied(), &mut out).unwrap();
        assert_eq!(n, 6);
        assert_eq!(
            out[..n],
            [
                InstanceLod {
                    id: 10,
                    lod: 0,
                    mask: 0xF0
                },
                InstanceLod {
                    id: 10,
                    lod: 1,
                    mask: 0x0F
                },
                InstanceLod {
                    id: 11,
                    lod: 2,
                    mask: 0xF0
                },
                InstanceLod {
                    id: 11,
                    lod: 3,
                    mask: 0x0F
                },
                InstanceLod {
                    id: 12,
                    lod: 7,
                    mask: 0xFF
                },
                InstanceLod {
                    id: 13,
                    lod: 3,
                    mask: 0xFF
                },
            ]
        );
        let mut small = [InstanceLod::default(); 4];
        let e = sel.fill(inst.iter().copied(), &mut small).unwrap_err();
        assert_eq!((e.needed, e.capacity), (6, 4));
        assert_eq!(small[..], out[..4], "the prefix is written");
        let msg = std::format!("{e}");
        assert!(
            msg.contains("6 records needed") && msg.contains('4'),
            "{msg}"
        );
        let mut big = [InstanceLod::default(); 6];
        assert_eq!(sel.fill(inst.iter().copied(), &mut big), Ok(6));
        assert_eq!(sel.fill(core::iter::empty(), &mut []), Ok(0));
    }

    #[test]
    fn ray_mask_is_one_uniform_bit() {
        let mut counts = [0u32; 8];
        for p in 0..80_000u32 {
            let m = ray_mask(&mut Rng::for_pixel(p % 400, p / 400, 3));
            assert_eq!(m.count_ones(), 1);
            counts[m.trailing_zeros() as usize] += 1;
        }
        let e = 10_000.0;
        let chi2: f64 = counts.iter().map(|&c| (f64::from(c) - e).powi(2) / e).sum();
        assert!(chi2 < 24.3, "{counts:?}");
        assert!(visible(0x0F, 0x04) && !visible(0xF0, 0x04) && !visible(0, 0xFF));
    }

    /// Every (instance mask pair, ray bit): exactly one of the two records
    /// is visible, so a path sees each instance exactly once.
    #[test]
    fn each_ray_bit_sees_exactly_one_lod() {
        for f in (0..=0xFFFFu32).step_by(97) {
            for t in [0u32, 1, 0x4000, 0x8000, 0xC000, 0x10000] {
                let c = choose(
                    GeomLod::from_bits(0x30000 | f),
                    8,
                    LodMode::Stochastic(Transition::from_bits(t)),
                );
                for b in 0..8 {
                    let m = 1u8 << b;
                    assert!(visible(c.mask_a, m) ^ visible(c.mask_b, m));
                }
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]

        /// Masks complementary, popcount(mask_b) = min(⌊9·f'⌋, 8) against
        /// the f64 reference, over every l, t and level count.
        #[test]
        fn masks_match_f64(l in 0u32..=7 << 16, t in 0u32..=1 << 16, levels in 1u8..=8) {
            let c = choose(GeomLod::from_bits(l), levels, LodMode::Stochastic(Transition::from_bits(t)));
            prop_assert_eq!(c.mask_a | c.mask_b, 0xFF);
            prop_assert_eq!(c.mask_a & c.mask_b, 0);
            let top = f64::from(levels - 1);
            let lf = (f64::from(l) / 65536.0).min(top);
            let ka = lf.floor();
            let f = lf - ka;
            prop_assert_eq!(f64::from(c.lod_a), ka);
            prop_assert_eq!(f64::from(c.lod_b), (ka + 1.0).min(top));
            if let Some(step) = step_ref(f, f64::from(t) / 65536.0) {
                prop_assert_eq!(c.mask_b.count_ones(), step.min(8), "l {} t {}", lf, t);
            }
            // The exact integer step is always within one of the f64 one.
            let exact = transition_step((l.min(u32::from(levels - 1) << 16)) & 0xFFFF, t);
            let fp = if t == 0 { if f >= 0.5 { 1.0 } else { 0.0 } }
                else { ((f - 0.5) / (f64::from(t) / 65536.0) + 0.5).clamp(0.0, 1.0) };
            prop_assert!((f64::from(exact) - (9.0 * fp).floor()).abs() <= 1.0);
        }

        /// t = 0 is exactly the discrete mode: one record, same LOD, 0xFF.
        #[test]
        fn t0_is_discrete(l in 0u32..=7 << 16, levels in 1u8..=8) {
            let lod = GeomLod::from_bits(l);
            let s = choose(lod, levels, LodMode::Stochastic(Transition::ZERO));
            let dsc = choose(lod, levels, LodMode::Discrete);
            let (lod_s, mask_s) = if s.mask_a != 0 { (s.lod_a, s.mask_a) } else { (s.lod_b, s.mask_b) };
            prop_assert!(s.mask_a == 0 || s.mask_b == 0);
            prop_assert_eq!((lod_s, mask_s), (dsc.lod_a, dsc.mask_a));
            // Discrete = round(l), ties up, clamped to L − 1.
            let want = (f64::from(l) / 65536.0).min(f64::from(levels - 1));
            prop_assert_eq!(f64::from(dsc.lod_a), (want + 0.5).floor().min(f64::from(levels - 1)));
        }

        /// The LOD parameter against f64 over the whole depth range.
        #[test]
        fn lod_param_matches_f64(
            near in -1.0e4..1.0e4f64,
            span in 1.0e-3..2.0e4f64,
            zr in -0.2..1.2f64,
            levels in 1u8..=8,
            bias in -8.0..8.0f64,
        ) {
            let (zn, zf) = (d(near), d(near + span));
            let b = LodBias::from_num(bias);
            let r = DepthToLod::new(zn, zf, levels, b).unwrap();
            let z = d(near + zr * span);
            let (znf, zff, zf64, bf) = (zn.to_num::<f64>(), zf.to_num::<f64>(), z.to_num::<f64>(), b.to_num::<f64>());
            let l = f64::from(levels) * ((zf64 - znf) / (zff - znf)).clamp(0.0, 1.0) + bf;
            let want = l.clamp(0.0, f64::from(levels - 1));
            let got = r.lod_param(z).to_num::<f64>();
            prop_assert!((got - want).abs() <= LOD_PARAM_MAX_ERROR, "got {} want {}", got, want);
        }

        /// Extreme inputs never panic and stay in range.
        #[test]
        fn extremes_stay_in_range(a in any::<i64>(), b in any::<i64>(), z in any::<i64>(), bias in any::<i32>(), levels in 1u8..=8, t in any::<u32>()) {
            if let Ok(r) = DepthToLod::new(Depth::from_bits(a), Depth::from_bits(b), levels, LodBias::from_bits(bias)) {
                let l = r.lod_param(Depth::from_bits(z));
                prop_assert!(l <= GeomLod::from_num(levels - 1));
                let c = choose(l, levels, LodMode::Stochastic(Transition::from_bits(t)));
                prop_assert_eq!(c.mask_a | c.mask_b, 0xFF);
                prop_assert!(c.lod_a <= c.lod_b && c.lod_b < levels);
            }
        }
    }
}
