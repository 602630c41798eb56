//! Ray differentials (Igehy 1999, "Tracing Ray Differentials") in 32-bit
//! block floating point.
//!
//! The per-pixel derivatives of a ray's origin and direction, carried by
//! the ray stack, transferred to each hit, reflected and refracted there,
//! and turned into a texture-space footprint ([`crate::lod::raydiff`])
//! whose larger axis gives the lod and whose two axes drive anisotropic
//! filtering. Primary rays are set up from the camera
//! ([`RayDiff::primary`]), or first hits from a G-buffer ([`gbuffer`]).
//! Feature `raydiff`.
//!
//! # State and number formats
//!
//! Each differential is a 3-vector of 32-bit mantissas (block floating
//! point, [`PosDiff`], [`DirDiff`]), and the `x` and `y` differentials of
//! one quantity share one exponent: `∂O/∂x, ∂O/∂y` one, `∂D/∂x, ∂D/∂y`
//! another. The largest of a pair's six components has 31 significant
//! bits whatever the pair's size, so the pair keeps its relative precision
//! from `2⁻¹⁶³⁸⁴` to `2¹⁶³⁸⁴` (a footprint beyond the
//! [`Lod`](crate::units::Lod) range saturates the lod, not the state).
//! [`RayDiff`] stores the twelve mantissas and two 16-bit exponents: 52
//! bytes. Each operation then aligns, normalises and clamps once per pair
//! instead of once per vector.
//!
//! **What the shared exponent costs.** The smaller vector of a pair keeps
//! the absolute precision of the larger one, not its own relative one: its
//! unit is at most `2⁻²⁹·(1 + 2⁻³⁰)` of the larger's largest component. So
//! every error bound below is stated on the pair's scale (`|∂O|` is the
//! larger of `|∂O/∂x|`, `|∂O/∂y|`, and so on), and both axes of a result
//! are within the bound on that one scale. For a lopsided footprint
//! (`|∂P/∂x| = k·|∂P/∂y|`, `k ≥ 1`) the smaller axis's error relative to
//! its own length is up to `k` times the bound's relative value: at the
//! bounds' `2⁻²³` it keeps about `23 − log2 k` bits. The lod takes the
//! larger axis (unaffected); the anisotropic axes of a ray-traced pixel
//! stretch by at most `1/MIN_COS = 2¹⁶` at a grazing hit, where the
//! shorter axis still has 7 bits, more than a filter's anisotropy clamp
//! resolves. [`RayDiff::new`] truncates the smaller vector of each pair to
//! the larger's unit; the accessors ([`RayDiff::dox`] …) return each
//! vector normalised on its own (exactly).
//!
//! | quantity | type | format |
//! |---|---|---|
//! | `∂O/∂x`, `∂O/∂y` (scene units per pixel) | [`PosDiff`] | 3 × i32 mantissa, exponent |
//! | `∂D/∂x`, `∂D/∂y`, `∂n/∂x`, `∂n/∂y` (per pixel) | [`DirDiff`] | 3 × i32 mantissa, exponent |
//! | ray direction `D`, normal `n` (unit vectors) | [`UnitVec`] | I2F30 components |
//! | hit distance `t` | [`PathLength`] | U32F32 |
//! | relative index `η = n₁/n₂` | [`Eta`] | I4F28, `(0, 8)` |
//! | `cos θₜ` | `I2F30` | `[0, 1]` |
//!
//! Every operation is 32-bit: products by multiply-high (`smmul`/`smmla`
//! and `smull`/`smlal` on the Cortex-M4, `mulh`/`mul` on RV32), the one
//! reciprocal per transfer or refraction by a 32/16-bit division and a
//! Newton step, no 128-bit arithmetic and no 64-bit division. Nothing
//! panics; the exponents saturate at `±2¹⁴` (far beyond every lod).
//!
//! # Grazing angles
//!
//! A transfer divides by `D·n` and a refraction by `cos θₜ`; both are
//! clamped to `|·| ≥ `[`MIN_COS`]` = 2⁻¹⁶` (as the cone method's normal
//! term), so the footprint of a grazing hit is at most `2¹⁶` times the
//! head-on one.
//!
//! # Error bound
//!
//! Each operation is exact on its stored inputs up to a local error found
//! by counting its truncations: every shift and multiply-high truncates
//! towards −∞ by less than one unit of its result, and a normalised
//! vector's unit is at most `u·|v|∞` (`u = 2⁻³⁰`, to first order; the
//! second-order terms are below `2⁻⁵⁰` of each scale). On the largest
//! component of the error, for every input (`|·|` Euclidean):
//!
//! Each length in a scale is the larger of the pair's two (`|∂O| =
//! max(|∂O/∂x|, |∂O/∂y|)`, `|∂D|`, `|∂n|` and, for the primary set-up,
//! `|r| = max(|right|, |up|)`): the bound holds for both axes of the
//! result on that one scale.
//!
//! | operation | constant | scale |
//! |---|---|---|
//! | [`RayDiff::primary`] | [`PRIMARY_ERROR`] = 2⁻²⁵ | `(|D·f| + 1)·|r|` |
//! | [`RayDiff::transfer`] | [`TRANSFER_ERROR`] = 2⁻²³ | `(|∂O| + t·|∂D|)·(1 + 1/|D·n|)` |
//! | [`RayDiff::reflect`] | [`REFLECT_ERROR`] = 2⁻²³ | `|∂D| + 4·|∂n|` |
//! | [`RayDiff::refract`] | [`REFRACT_ERROR`] = 2⁻²⁴ | `(1 + 2η + η²/cos θₜ)·(|∂D| + |∂n|)` |
//!
//! The derivations below count truncations in units of a pair's exponent;
//! every such unit is at most `u` times the pair's scale, so they hold for
//! the smaller vector of a pair as for the larger.
//!
//! * **Primary.** `(D·r)` from an exact 64-bit dot product, one truncation
//!   (`< 2u|r|`); `r − (D·r)·D` at twice the unit of `r`, not normalised:
//!   the halved `r` (`< 2u|r|∞`), the term `(D·r)·D` by one multiply-high
//!   at eight times the unit (`< 8u|r|∞`) and that error, `< 12u|r|∞`;
//!   times `D·f` (exact dot, `< u`) by one multiply-high at eight times
//!   the unit of `r` (`< 8u|r|∞`), the smaller axis aligned to the
//!   larger's unit (`< 8u|r|`), then normalised (exact):
//!   `12u·|D·f||r| + 17u|r| ≤ 32u·(|D·f| + 1)|r|`.
//! * **Transfer.** `t` to 31 bits (`< u·t`), shifted to the unit `2^eq`
//!   of `q` (`2^eq ≤ 2u|∂O| + 4u·t|∂D| ≤ 4u·S`, `S = |∂O| + t|∂D|`) and
//!   multiplied by `∂D` (one multiply-high, `|∂D| ≤ 2³¹` units: the
//!   shift's truncation `< ½` unit of `q`, the product's `< 1`), added to
//!   `∂O` shifted to `2^eq` (`< 1`): `|δq| < 11u·S`. `D·n` exact in 64
//!   bits, clamped, its 32-bit mantissa (`< u/2`), `1/|D·n|` by one
//!   32/16-bit division and a Newton step (`≤ 3u`). `q·n` exact,
//!   truncated once (`< 8u·S`) and normalised with the other axis's (one
//!   shift for both: the larger of the two has 31 bits); per axis
//!   `s = (q·n)/(D·n)` by one multiply-high (`< ¼` unit of the term, `≤
//!   4u·S/|D·n|`) and the term `s·D` by one multiply-high per component
//!   (`< 16u·S/|D·n|`: the term's unit); the difference at the larger
//!   exponent (`< 16u·S + 32u·S/|D·n|`). With `|q·n| ≤ S`, `|s·D| ≤
//!   S/|D·n|` and `|δq·n| ≤ √3|δq|∞`: `29u·S + 86u·S/|D·n| ≤ 128u·S·(1 +
//!   1/|D·n|)`.
//! * **Reflection.** `∂D` and `∂n` of both axes at one exponent with 3
//!   and 5 bits of headroom (`2ᵉ ≤ 8u|∂D| + 32u|∂n|`, one truncation
//!   each, `< 2ᵉ`), `∂n`
//!   also at `2ᵉ⁻²` (`< 2ᵉ/4`); `D·n` to `2⁻³⁰` (`< u`); `∂(D·n)` from
//!   exact dot products, one truncation (`< (2√3 + ½)·2ᵉ` with the
//!   inputs'); `n` saturated at `1 − 2⁻³⁰` (`< u`, times
//!   `|∂(D·n)| < 0.55·2³⁰·2ᵉ`: `< 0.55·2ᵉ`); the half term
//!   `(D·n)·∂n + ∂(D·n)·n` by two multiply-highs (`< 2ᵉ` each):
//!   `6.76·2ᵉ + u|∂n|`, doubled, and `∂D`'s truncation:
//!   `14.5·2ᵉ + 2u|∂n| ≤ 128u·(|∂D| + 4|∂n|)`.
//! * **Refraction.** The scalars `μ`, `1/cos θₜ` (division and Newton step) and
//!   `c = η − η²·cos θᵢ/cos θₜ` as normalised 31-bit mantissas: each
//!   multiply-high `< 4u` relative, `cos θᵢ` to `2⁻³⁰`, so
//!   `|δc| ≤ 19u·η + 20u·η²/cos θₜ` and `|δμ| ≤ (9 + η)u + u|μ|`; `∂cos θᵢ`
//!   from `∂D` and `∂n` of both axes at their largest exponent plus one
//!   (one truncation each, `< 2u` of the larger), two exact dot products
//!   and one truncation (`< 11u·N`, `N = |∂D| + |∂n|`), normalised with
//!   the other axis's (one shift), `∂μ` by one multiply-high, normalised
//!   likewise (`< (34η + 35η²/cos θₜ)·u·N`); the three terms by one
//!   multiply-high each and summed at the largest exponent of both axes
//!   (`< 24u·(η + |c| + |μ|)·N`):
//!   `(37 + 120η + 63η²/cos θₜ)·u·N ≤ 64u·(1 + 2η + η²/cos θₜ)·N`.
//!
//! The footprint and lod add their own ([`crate::lod::raydiff`]); along a
//! path the local errors propagate with each operation's gain (`1/|D·n|`
//! for a transfer, 1 for a reflection's `∂D` and 4 for its `∂n`,
//! `η + |c|` and `|c| + |μ|` for a refraction, `|κ|` from the normal
//! differentials of a curved surface): the resulting bound of the lod, as
//! a function of the path, is derived and tested there.

use fixed::types::{I2F30, I4F28};

use crate::log2::normalise64;
use crate::units::MIN_COS;
use crate::units::PathLength;

mod bfp;
pub mod gbuffer;

pub(crate) use bfp::{
    Bfp3, Bfp3x2, EXP_MAX, EXP_MIN, dot64, mulhi, norm_shift, norm_shift2, recip, shr,
};

use crate::units::UnitVec;

/// Documented bound of [`RayDiff::primary`]: the largest component of the
/// error of `∂D/∂x` and of `∂D/∂y` is at most this times
/// `(|D·f| + 1)·max(|r|, |u|)`: 2⁻²⁵ (derivation in the
/// [module docs](self#error-bound)).
pub const PRIMARY_ERROR: f64 = 1.0 / 33_554_432.0;
/// Documented bound of [`RayDiff::transfer`]: the largest component of the
/// error of `∂O'` (either axis) is at most this times
/// `(|∂O| + t·|∂D|)·(1 + 1/|D·n|)`, each length the larger of its pair
/// (`|D·n|` clamped): 2⁻²³.
pub const TRANSFER_ERROR: f64 = 1.0 / 8_388_608.0;
/// Documented bound of [`RayDiff::reflect`]: at most this times
/// `|∂D| + 4·|∂n|` per component of either axis, each length the larger
/// of its pair: 2⁻²³.
pub const REFLECT_ERROR: f64 = 1.0 / 8_388_608.0;
/// Documented bound of [`RayDiff::refract`]: at most this times
/// `(1 + 2η + η²/cos θₜ)·(|∂D| + |∂n|)` per component of either axis,
/// each length the larger of its pair (`cos θₜ` clamped): 2⁻²⁴.
pub const REFRACT_ERROR: f64 = 1.0 / 16_777_216.0;

/// [`MIN_COS`] in I2F30 bits (the unit of `UnitVec` dot products).
const MIN_COS_I2F30: i32 = (MIN_COS.to_bits() >> 1) as i32;

/// A position differential `∂O/∂x` or `∂O/∂y`: scene units per pixel, a
/// block-floating-point 3-vector (`mₖ·2ᵉ`, the largest `|mₖ|` in
/// `[2³⁰ − 1, 2³¹]`, see the [module docs](self)).
///
/// # Example
/// ```
/// use raymip::path::raydiff::PosDiff;
/// // (3/8, 0, −1/2) scene units per pixel.
/// let p = PosDiff::new([3, 0, -4], -3);
/// let (m, e) = p.parts();
/// assert_eq!(m.map(|x| f64::from(x) * f64::from(e).exp2()), [0.375, 0.0, -0.5]);
/// assert_eq!((m[2], e), (i32::MIN, -32)); // normalised: no redundant sign bit
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(transparent)]
pub struct PosDiff(Bfp3);

/// A direction differential `∂D/∂x`, `∂D/∂y` (change of the unit ray
/// direction per pixel) or a normal differential `∂n/∂x`, `∂n/∂y`: a
/// block-floating-point 3-vector as [`PosDiff`].
///
/// # Example
/// ```
/// use fixed::types::I2F30;
/// use raymip::path::raydiff::DirDiff;
/// // From I2F30 components (exact): 2⁻¹⁰ along x.
/// let s = I2F30::from_num(1.0 / 1024.0);
/// let d = DirDiff::from_i2f30([s, I2F30::ZERO, I2F30::ZERO]);
/// assert_eq!(d.parts(), ([1 << 30, 0, 0], -40));
/// assert_eq!(d.to_i2f30(), [s, I2F30::ZERO, I2F30::ZERO]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(transparent)]
pub struct DirDiff(Bfp3);

macro_rules! diff_vec {
    ($t:ident) => {
        impl $t {
            /// The zero vector.
            pub const ZERO: Self = Self(Bfp3::ZERO);

            /// `mₖ·2ᵉ`, normalised (any mantissas and exponent; exact
            /// unless the exponent saturates at `−2¹⁴` or `2¹⁴ − 1`).
            #[inline]
            #[must_use]
            pub fn new(m: [i32; 3], e: i32) -> Self {
                Self(Bfp3::new(m, e.clamp(2 * EXP_MIN, 2 * EXP_MAX)))
            }

            /// `mₖ·2ᵉ` from 64-bit mantissas, truncated to 31 significant
            /// bits of the largest.
            #[must_use]
            pub fn from_wide(m: [i64; 3], e: i32) -> Self {
                Self(Bfp3::from_wide(m, e))
            }

            /// The normalised mantissas and exponent: component `k` is
            /// `m[k]·2ᵉ`.
            #[inline]
            #[must_use]
            pub const fn parts(self) -> ([i32; 3], i32) {
                (self.0.m, self.0.e)
            }

            /// From f64 components (set-up and host code, not per hit):
            /// truncated to 31 significant bits of the largest; non-finite
            /// components read as 0.
            #[must_use]
            pub fn from_f64(v: [f64; 3]) -> Self {
                let v = v.map(|x| if x.is_finite() { x } else { 0.0 });
                let top = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                if top == 0.0 {
                    return Self::ZERO;
                }
                // 2^(30 − e)·top ∈ [2³⁰, 2³¹) with e = ⌊log2 top⌋ (via the
                // f64 exponent field; subnormal tops read as 2⁻¹⁰²²).
                let e = (((top.to_bits() >> 52) & 0x7FF) as i32 - 1023).max(-1022);
                let m = v.map(|x| (x * pow2(30 - e)) as i32);
                Self::new(m, e - 30)
            }

            /// As f64 components (host code, tests): `m·2ᵉ`, 0 or `±∞`
            /// where the exponent leaves the f64 range.
            #[must_use]
            pub fn to_f64(self) -> [f64; 3] {
                let (m, e) = self.parts();
                m.map(|x| f64::from(x) * pow2(e))
            }
        }

        impl Default for $t {
            fn default() -> Self {
                Self::ZERO
            }
        }
    };
}
diff_vec!(PosDiff);
diff_vec!(DirDiff);

impl DirDiff {
    /// From I2F30 components (exact).
    #[must_use]
    pub fn from_i2f30(v: [I2F30; 3]) -> Self {
        Self::new(v.map(I2F30::to_bits), -30)
    }

    /// As I2F30 components, rounded towards −∞ below `2⁻³⁰` and saturated
    /// at `±2`.
    #[must_use]
    pub fn to_i2f30(self) -> [I2F30; 3] {
        let (m, e) = self.parts();
        let s = e + 30;
        m.map(|x| {
            let v = if s >= 0 {
                // |x| ≤ 2³¹, so 2³² or more saturates whatever x ≠ 0 is.
                (i64::from(x) << s.min(32)).clamp(i64::from(i32::MIN), i64::from(i32::MAX))
            } else {
                i64::from(shr(x, -s))
            };
            I2F30::from_bits(v as i32)
        })
    }
}

impl PosDiff {
    /// From I32F32 components (scene units; e.g. a difference of two
    /// positions), truncated to 31 significant bits.
    #[must_use]
    pub fn from_i32f32(v: [fixed::types::I32F32; 3]) -> Self {
        Self::from_wide(v.map(fixed::types::I32F32::to_bits), -32)
    }
}

/// `2ᵏ` in f64 for `−1022 ≤ k ≤ 1023` (exact; 0 below, ∞ above).
fn pow2(k: i32) -> f64 {
    match k {
        -1022..=1023 => f64::from_bits(((k + 1023) as u64) << 52),
        k if k < 0 => 0.0,
        _ => f64::INFINITY,
    }
}

/// Relative index of refraction `η = n₁/n₂` (incident over transmitted
/// medium), I4F28, `(0, 8)`.
///
/// # Example
/// ```
/// use fixed::types::I4F28;
/// use raymip::path::raydiff::Eta;
/// // Air into glass: η = 1/1.5.
/// let eta = Eta::from_fixed(I4F28::from_num(1.0 / 1.5));
/// assert_eq!(eta.to_fixed(), I4F28::from_num(1.0 / 1.5));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(transparent)]
pub struct Eta(I4F28);

impl Eta {
    /// `η = 1` (no refraction).
    pub const ONE: Self = Self(I4F28::ONE);

    /// From its I4F28 value.
    #[inline]
    #[must_use]
    pub const fn from_fixed(v: I4F28) -> Self {
        Self(v)
    }

    /// Its I4F28 value.
    #[inline]
    #[must_use]
    pub const fn to_fixed(self) -> I4F28 {
        self.0
    }
}

/// The differential state of one ray (one ray-stack entry, feature
/// `raydiff`): `∂O/∂x, ∂O/∂y, ∂D/∂x, ∂D/∂y` as four block-floating-point
/// vectors, each pair (`∂O`, `∂D`) with one exponent (formats in the
/// [module docs](self)). 52 bytes.
///
/// # Example
/// ```
/// use fixed::types::{I2F30, I4F28};
/// use raymip::PathLength;
/// use raymip::units::UnitVec;
/// use raymip::path::raydiff::{DirDiff, Eta, PosDiff, RayDiff};
/// let (one, zero) = (I2F30::ONE, I2F30::ZERO);
/// let v = |p: DirDiff| -> [f64; 3] { let (m, e) = p.parts(); m.map(|x| f64::from(x) * f64::from(e).exp2()) };
/// // A camera looking down −z; one pixel step turns the unnormalised
/// // direction by s = 2⁻¹⁰ along x (right) or y (up).
/// let s = I2F30::from_num(1.0 / 1024.0);
/// let (right, up) = (DirDiff::from_i2f30([s, zero, zero]), DirDiff::from_i2f30([zero, s, zero]));
/// let forward = UnitVec([zero, zero, -one]);
/// let mut ray = RayDiff::primary(forward, forward, right, up);
/// // The centre ray: D·f = 1, D·r = 0, so ∂D/∂x = r and ∂D/∂y = u.
/// assert_eq!((v(ray.ddx()), v(ray.ddy())), ([1.0 / 1024.0, 0.0, 0.0], [0.0, 1.0 / 1024.0, 0.0]));
/// // Transfer to a wall facing the camera (n = +z) at t = 100: ∂D·t
/// // lies in the wall, so ∂O = 100·2⁻¹⁰ scene units per pixel along x.
/// let wall = UnitVec([zero, zero, one]);
/// ray.transfer(forward, PathLength::from_num(100), wall);
/// let (m, e) = ray.dox().parts();
/// assert_eq!(m.map(|x| f64::from(x) * f64::from(e).exp2()), [100.0 / 1024.0, 0.0, 0.0]);
/// // A flat mirror (∂n = 0) facing the ray: ∂D ⟂ n stays as it is.
/// let mut mirrored = ray;
/// mirrored.reflect(forward, wall, [DirDiff::ZERO; 2]);
/// assert_eq!(v(mirrored.ddx()), v(ray.ddx()));
/// // Head-on into a denser medium, η = ½ (cos θₜ = 1): ∂T = η·∂D.
/// let mut refracted = ray;
/// refracted.refract(forward, wall, [DirDiff::ZERO; 2], Eta::from_fixed(I4F28::from_num(0.5)), one);
/// assert_eq!(v(refracted.ddx()), [1.0 / 2048.0, 0.0, 0.0]);
/// assert_eq!(refracted.dox(), ray.dox()); // the hit point's ∂O is kept
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RayDiff {
    /// Mantissas of `∂O/∂x, ∂O/∂y, ∂D/∂x, ∂D/∂y`.
    m: [[i32; 3]; 4],
    /// The exponent of the `∂O` pair and of the `∂D` pair
    /// (`[EXP_MIN, EXP_MAX]`).
    e: [i16; 2],
}

impl Default for RayDiff {
    fn default() -> Self {
        Self::ZERO
    }
}

/// `(m, e)` of I2F30 unit-vector components: the raw bits.
#[inline(always)]
fn bits(v: UnitVec) -> [i32; 3] {
    v.map(I2F30::to_bits)
}

impl RayDiff {
    /// No differential (a pinhole camera's primary ray has `∂O = 0`).
    pub const ZERO: Self = Self {
        m: [[0; 3]; 4],
        e: [EXP_MIN as i16; 2],
    };

    /// A state from its four differentials: each pair (`∂O`, `∂D`) at the
    /// larger of its two exponents, the smaller vector truncated to that
    /// unit (below `2⁻²⁹·(1 + 2⁻³⁰)` of the larger's largest component;
    /// see the [module docs](self#state-and-number-formats)).
    #[must_use]
    pub fn new(dox: PosDiff, doy: PosDiff, ddx: DirDiff, ddy: DirDiff) -> Self {
        let mut s = Self::ZERO;
        s.set_pair(0, Bfp3x2::aligned([dox.0.m, doy.0.m], [dox.0.e, doy.0.e]));
        s.set_pair(1, Bfp3x2::aligned([ddx.0.m, ddy.0.m], [ddx.0.e, ddy.0.e]));
        s
    }

    /// Pair `p`: 0 for `∂O`, 1 for `∂D`.
    #[inline(always)]
    pub(crate) fn pair(&self, p: usize) -> Bfp3x2 {
        let p = p & 1;
        Bfp3x2 {
            m: [self.m[2 * p], self.m[2 * p + 1]],
            e: i32::from(self.e[p]),
        }
    }

    #[inline(always)]
    pub(crate) fn set_pair(&mut self, p: usize, v: Bfp3x2) {
        let p = p & 1;
        self.m[2 * p] = v.m[0];
        self.m[2 * p + 1] = v.m[1];
        // `normalise` keeps the exponent in [EXP_MIN, EXP_MAX] ⊂ i16.
        self.e[p] = v.e as i16;
    }

    /// Differential `i` (`∂O/∂x, ∂O/∂y, ∂D/∂x, ∂D/∂y`) normalised on its
    /// own.
    #[inline(always)]
    fn get(&self, i: usize) -> Bfp3 {
        self.pair(i >> 1).get(i & 1)
    }

    /// `∂O/∂x` (scene units per pixel).
    #[inline]
    #[must_use]
    pub fn dox(&self) -> PosDiff {
        PosDiff(self.get(0))
    }

    /// `∂O/∂y`.
    #[inline]
    #[must_use]
    pub fn doy(&self) -> PosDiff {
        PosDiff(self.get(1))
    }

    /// `∂D/∂x` (per pixel).
    #[inline]
    #[must_use]
    pub fn ddx(&self) -> DirDiff {
        DirDiff(self.get(2))
    }

    /// `∂D/∂y`.
    #[inline]
    #[must_use]
    pub fn ddy(&self) -> DirDiff {
        DirDiff(self.get(3))
    }

    /// Primary ray of a pinhole camera (`∂O = 0`): for the unit ray
    /// direction `d`, the camera's unit forward axis `forward` and the
    /// change of the unnormalised direction `f + x·r + y·u` per pixel in x
    /// (`right`) and y (`up`) on the image plane at unit distance
    /// (`⟂ forward`), `∂D/∂x = (D·f)·(r − (D·r)·D)` (the derivative of
    /// `d/|d|`, with `1/|d| = D·f`), the same with `u` in y. Set-up per
    /// pixel; never panics.
    #[must_use]
    #[inline]
    pub fn primary(d: UnitVec, forward: UnitVec, right: DirDiff, up: DirDiff) -> Self {
        let d = bits(d);
        // D·f in 2⁻³⁰ units (one truncation; ≤ 2³⁰ + 1 for unit vectors).
        let df = (dot64(d, bits(forward)) >> 30) as i32;
        // Both axes inline and the state built in place (no call, no copy
        // of `ZERO`).
        let (x, y) = (primary_axis(d, df, right.0), primary_axis(d, df, up.0));
        let dd = Bfp3x2::aligned([x, y], [right.0.e + 3, up.0.e + 3]);
        Self {
            m: [[0; 3], [0; 3], dd.m[0], dd.m[1]],
            // `normalise` keeps the exponent in [EXP_MIN, EXP_MAX] ⊂ i16.
            e: [EXP_MIN as i16, dd.e as i16],
        }
    }

    /// Transfer to a hit at distance `t` on a surface of unit normal `n`
    /// (Igehy eq. 10–12): `q = ∂O + t·∂D`, `∂t = −(q·n)/(D·n)`,
    /// `∂O' = q + ∂t·D`; `∂D` is unchanged. `∂O'` is then the hit point's
    /// differential on the tangent plane ([`crate::lod::raydiff`] reads
    /// it). `|D·n|` is clamped to [`MIN_COS`]. Per hit; never panics.
    #[inline]
    pub fn transfer(&mut self, d: UnitVec, t: PathLength, n: UnitVec) {
        let (d, n) = (bits(d), bits(n));
        // D·n exact in 2⁻⁶⁰ units, |D·n| clamped to ≥ MIN_COS (2⁴⁴ units):
        // the high word is then ≥ 2¹², its leading zeros lz ≤ 19.
        let c = dot64(d, n);
        let a = c.unsigned_abs().max((MIN_COS_I2F30 as u64) << 30);
        let (hi, lo) = ((a >> 32) as u32, a as u32);
        let lz = hi.leading_zeros();
        // |D·n| = cm·2^(−28−lz), cm ∈ [2³¹, 2³²) (one truncation).
        let cm = (hi << lz) | ((lo >> 1) >> (31 - lz));
        // −1/(D·n) = y·2^(lz−34), y ∈ ±[2³⁰, 2³¹): the sign that makes
        // the term below one multiply-accumulate (`smmla`).
        let y = recip(cm) as i32;
        let y = if c < 0 { y } else { -y };
        // t = tm·2^et, tm ∈ [2³⁰, 2³¹) (zero: tm = 0 at EXP_MIN).
        let (tn, tz) = normalise64(t.to_bits());
        let tm = (tn >> 1) as i32;
        let et = if tm == 0 { EXP_MIN } else { 1 - tz as i32 };
        let (o, dd) = (self.pair(0), self.pair(1));
        // q = ∂O + t·∂D at 2^eq for both axes, |qₖ| ≤ 2³¹ (∂O shifted by
        // at least 1, t·∂D = mulhi(tm, ∂D)·2^(et+e+32) with |mulhi| ≤ 2³⁰).
        // t is shifted to 2^eq before the product (`tm >> sp`, below half a
        // unit of q in the product, `|∂D| ≤ 2³¹`), so each component is
        // one shift and one multiply-accumulate (`smmla`).
        let ep = et + dd.e + 32;
        let eq = (o.e + 1).max(ep);
        let (so, ts) = (eq - o.e, shr(tm, eq - ep));
        let q: [[i32; 3]; 2] = core::array::from_fn(|a| {
            core::array::from_fn(|k| shr(o.m[a][k], so) + mulhi(ts, dd.m[a][k]))
        });
        // q·n = qn·2^(eq+1) per axis (exact dot, one truncation,
        // |qn| < √3·2³⁰), both normalised by one shift to qm·2^(eq+1−sn).
        let qn = q.map(|q| (dot64(q, n) >> 31) as i32);
        let sn = norm_shift2(qn[0], qn[1]);
        // ∂P = q − s·D with s = (q·n)/(D·n) per axis: the scalar
        // −s = mulhi(qm, y)·2^(eq−1−sn+lz), |·| ≤ 2³⁰, the term
        // mulhi(−s, D)·2^(eq+1−sn+lz), |mulhi| ≤ 2²⁸, and q shifted by at
        // least one: |rₖ| < 2³¹.
        // Both at er = max(eq + 1, eq + 1 − sn + lz) = eq + 1 + max(0, gap),
        // gap = lz − sn ∈ [−31, 19] (lz ∈ [0, 19] for any `D`, `n`,
        // sn ∈ [0, 31]): the shift 1 + max(0, gap) ≤ 20 needs no clamp.
        // The term's shift to er, st = max(0, −gap) ≤ sn, is taken from
        // qm = qn·2^sn before the products: qm >> st = qn << min(sn, lz)
        // drops only zero bits (one shift per axis instead of one per
        // component); the scalar's truncation is then below ¼ unit of er
        // (|D| ≤ 2³⁰ units).
        let gap = lz as i32 - sn;
        let sq = 1 + gap.max(0);
        let sm = sn.min(lz as i32);
        let r: [[i32; 3]; 2] = core::array::from_fn(|a| {
            let s = mulhi(qn[a] << sm, y);
            core::array::from_fn(|k| {
                // Wrapping: only inputs outside every documented range
                // (non-unit `D`, `n`) reach ±2³¹; the result is then
                // garbage, but no panic.
                q[a][k].wrapping_shr(sq as u32).wrapping_add(mulhi(s, d[k]))
            })
        });
        self.set_pair(0, Bfp3x2::new(r, eq + sq));
    }

    /// Reflection about the unit shading normal `n` with its per-pixel
    /// differentials `dn = [∂n/∂x, ∂n/∂y]` (zero on flat triangles) (Igehy
    /// eq. 14–15): `∂R = ∂D − 2·((D·n)·∂n + ∂(D·n)·n)`,
    /// `∂(D·n) = ∂D·n + D·∂n`; `∂O` (the hit's) is kept. Per hit; never
    /// panics.
    #[inline]
    pub fn reflect(&mut self, d: UnitVec, n: UnitVec, dn: [DirDiff; 2]) {
        let (d, n) = (bits(d), bits(n));
        // D·n in 2⁻³⁰ units (one truncation).
        let c = (dot64(d, n) >> 30) as i32;
        // 2n in 2⁻³² units (a component of ±1 saturated to 1 − 2⁻³⁰: one
        // `ssat` and a shift).
        let n2 = n.map(|x| x.clamp(-(1 << 30), (1 << 30) - 1) << 1);
        let dd = self.pair(1);
        // One exponent for both axes with headroom: |∂D| ≤ 2²⁸, |∂n| ≤ 2²⁶
        // units, so |∂(D·n)| < √3·(2²⁸ + 2²⁶) and the term below < 1.2·2³⁰.
        let e = (dd.e + 3).max(dn[0].0.e.max(dn[1].0.e) + 5);
        let sd = e - dd.e;
        let r: [[i32; 3]; 2] = core::array::from_fn(|axis| {
            let nn = dn[axis].0;
            let a = dd.m[axis].map(|x| shr(x, sd));
            // ∂n at 2^(e−2) (|·| ≤ 2²⁸) for its product with D·n, and at 2ᵉ.
            let b4 = nn.m.map(|x| shr(x, e - 2 - nn.e));
            let b = b4.map(|x| x >> 2);
            // 2·∂(D·n) in units of 2ᵉ (|·| < 1.1·2³⁰), one truncation.
            let s2 = ((dot64(a, n) + dot64(d, b)) >> 29) as i32;
            core::array::from_fn(|k| {
                // (D·n)·∂n + ∂(D·n)·n = mulhi(c, 4∂n) + mulhi(2∂(D·n), 2n)
                // in units of 2ᵉ (below 0.6·2³⁰; one `smmul` and one
                // `smmla`), doubled in the subtraction.
                let h = mulhi(c, b4[k]).wrapping_add(mulhi(s2, n2[k]));
                // Wrapping: only non-unit `D`, `n` reach ±2³¹ (no panic).
                a[k].wrapping_sub(h << 1)
            })
        });
        self.set_pair(1, Bfp3x2::new(r, e));
    }

    /// Refraction through the unit shading normal `n` facing the incoming
    /// ray (`D·n < 0`) with differentials `dn`, relative index `eta` and
    /// `cos_t = cos θₜ = √(1 − η²(1 − (D·n)²))` (the caller has it from the
    /// refracted direction `T = ηD + μn`); Igehy eq. 16–18 with
    /// `cos θᵢ = −D·n`, `μ = η·cos θᵢ − cos θₜ`:
    /// `∂μ = (η − η²·cos θᵢ / cos θₜ)·∂cos θᵢ`, `∂cos θᵢ = −(∂D·n + D·∂n)`,
    /// `∂T = η·∂D + ∂μ·n + μ·∂n`; `∂O` is kept. `cos θₜ` is clamped to
    /// [`MIN_COS`] (near the critical angle). Per hit; never panics.
    #[inline]
    pub fn refract(&mut self, d: UnitVec, n: UnitVec, dn: [DirDiff; 2], eta: Eta, cos_t: I2F30) {
        let (d, n) = (bits(d), bits(n));
        let eta = eta.0.to_bits();
        // cos θᵢ in 2⁻³⁰ units (one truncation), cos θₜ clamped. Wrapping
        // negation: only non-unit `D`, `n` (D·n = −2) reach `i32::MIN`,
        // whose result is then garbage, but no panic.
        let ci = ((dot64(d, n) >> 30) as i32).wrapping_neg();
        let ct = cos_t.to_bits().max(MIN_COS_I2F30);
        // μ = η·cos θᵢ − cos θₜ in 2⁻²⁸ units (one truncation): for unit
        // `D`, `n` facing each other, η < 8 and cos θₜ ∈ [MIN_COS, 2) it
        // lies in (−2, 8), within 32 bits, so it is normalised from 32 bits
        // (the wrapping difference is exact whenever the result fits, so
        // bit for bit the value a 64-bit normalisation gives); inputs
        // outside that range wrap (garbage, no panic).
        let mu = Scalar::new(
            (((i64::from(eta) * i64::from(ci)) >> 30) as i32).wrapping_sub(ct >> 2),
            -28,
        );
        let eta_s = Scalar::new(eta, -28);
        // 1/cos θₜ: cos θₜ = x·2^(−30−lz), x = ct·2^lz ∈ [2³¹, 2³²), so
        // 1/cos θₜ = recip(x)·2^(lz−32).
        let lz = (ct as u32).leading_zeros();
        let inv_ct = Scalar::factor(recip((ct as u32) << lz) as i32, lz as i32 - 32);
        // c = η − η²·cos θᵢ/cos θₜ (the factors' zero exponents do not
        // matter: see `Scalar::factor`).
        let coef = eta_s.sub(
            eta_s
                .mul_factor(eta_s)
                .mul_factor(Scalar::factor(ci, -30))
                .mul(inv_ct),
        );
        let dd = self.pair(1);
        let nn = [dn[0].0, dn[1].0];
        // −∂cos θᵢ = ∂D·n + D·∂n with ∂D and ∂n of both axes at one
        // exponent and one bit of headroom (|·| ≤ 2³⁰, so each dot product
        // is below √3·2⁶⁰ for unit `D`, `n`), in units of 2^(ea+1) after one
        // truncation.
        let ea = dd.e.max(nn[0].e).max(nn[1].e) + 1;
        let sd = ea - dd.e;
        let g: [i32; 2] = core::array::from_fn(|axis| {
            let a = dd.m[axis].map(|x| shr(x, sd));
            let b = nn[axis].m.map(|x| shr(x, ea - nn[axis].e));
            // Wrapping: only non-unit `D`, `n` reach ±2⁶³ (no panic).
            (dot64(a, n).wrapping_add(dot64(d, b)) >> 31) as i32
        });
        // ∂μ = −c·(∂D·n + D·∂n): both axes' g normalised by one shift, one
        // multiply-high each, the products normalised by one shift (both
        // zero: EXP_MIN, so that the term never sets the exponent below).
        let sg = norm_shift2(g[0], g[1]);
        let p = g.map(|x| mulhi(coef.m, x << sg));
        let sp = norm_shift2(p[0], p[1]);
        let dmu = p.map(|x| x << sp);
        let dmu_e = if (p[0] | p[1]) == 0 {
            EXP_MIN
        } else {
            coef.e + ea + 33 - sg - sp
        };
        // The three terms η·∂D, −∂μ·n (mulhi with n: 2⁻³⁰ units), μ·∂n at
        // their exponents, each below 2³⁰ before the shift, summed at one
        // exponent for both axes.
        let e1 = dd.e + eta_s.e + 32;
        let e2 = dmu_e + 2;
        let e3 = nn.map(|v| v.e + mu.e + 32);
        let e = e1.max(e2).max(e3[0].max(e3[1])) + 1;
        let r: [[i32; 3]; 2] = core::array::from_fn(|axis| {
            core::array::from_fn(|k| {
                // Wrapping: only inputs outside every documented range
                // reach ±2³¹ (no panic).
                shr(mulhi(dd.m[axis][k], eta_s.m), e - e1)
                    .wrapping_sub(shr(mulhi(dmu[axis], n[k]), e - e2))
                    .wrapping_add(shr(mulhi(nn[axis].m[k], mu.m), e - e3[axis]))
            })
        });
        self.set_pair(1, Bfp3x2::new(r, e));
    }
}

/// One axis of [`RayDiff::primary`]: `(D·f)·(r − (D·r)·D)` for the unit
/// direction `d` (I2F30 bits), `df` = `D·f` in 2⁻³⁰ units and the step `r`,
/// in units of `2^(e + 3)` (`e` the exponent of `r`), not normalised.
#[inline(always)]
fn primary_axis(d: [i32; 3], df: i32, r: Bfp3) -> [i32; 3] {
    // (D·r)/2 in the units of r (|·| ≤ √3·2³⁰), one truncation.
    let dr = (dot64(r.m, d) >> 31) as i32;
    // (r − (D·r)·D)/2 in the units of r (|·| ≤ √3·2³⁰ for unit `D`: the
    // projection is no longer than r), not normalised: the product with
    // D·f below keeps its absolute error within the bound.
    let v: [i32; 3] = core::array::from_fn(|k| (r.m[k] >> 1).wrapping_sub(mulhi(dr, d[k]) << 2));
    // (D·f)·v = mulhi(v, df)·2³: df is D·f·2³⁰.
    v.map(|x| mulhi(x, df))
}

/// A normalised scalar `m·2ᵉ` (`|m| ∈ [2³⁰ − 1, 2³¹]` or zero at
/// [`EXP_MIN`]) for the few scalars of a refraction. Its exponent is not
/// clamped: the per-call scalars (`η`, `μ`, `cos θᵢ`, `1/cos θₜ` and their
/// products) have exponents within ±100, and a per-axis one adds an
/// exponent of the state (`[EXP_MIN, EXP_MAX]`), so every exponent stays
/// within `±2¹⁶` (far from `i32` overflow); the result vector's
/// [`Bfp3::new`] clamps.
#[derive(Clone, Copy, Debug)]
struct Scalar {
    m: i32,
    e: i32,
}

impl Scalar {
    /// `m·2ᵉ` normalised as [`Bfp3::new_in_range`] (bit for bit, so as
    /// [`Bfp3::new`] for `e ∈ [EXP_MIN + 31, EXP_MAX]`): zero at
    /// [`EXP_MIN`], no clamp.
    #[inline(always)]
    fn new(m: i32, e: i32) -> Self {
        let f = Self::factor(m, e);
        Self {
            m: f.m,
            e: if m == 0 { EXP_MIN } else { f.e },
        }
    }

    /// [`Scalar::new`] without the zero case (a zero `m` keeps `e − 31`),
    /// for a value used only as a factor of [`Scalar::mul`] or
    /// [`Scalar::mul_factor`]: a zero factor makes a zero product
    /// whatever its exponent (and two non-zero normalised factors never
    /// do, `|mulhi| ≥ 2²⁸`), so the product is bit for bit the one of
    /// [`Scalar::new`]'s factor.
    #[inline(always)]
    fn factor(m: i32, e: i32) -> Self {
        let s = norm_shift([m, 0, 0]);
        Self {
            m: m << s,
            e: e - s,
        }
    }

    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Self::new(mulhi(self.m, o.m), self.e + o.e + 32)
    }

    /// [`Scalar::mul`] made as a [`Scalar::factor`]: for a product used
    /// only as a factor of another.
    #[inline(always)]
    fn mul_factor(self, o: Self) -> Self {
        Self::factor(mulhi(self.m, o.m), self.e + o.e + 32)
    }

    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        let e = self.e.max(o.e) + 1;
        Self::new(shr(self.m, e - self.e) - shr(o.m, e - o.e), e)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    extern crate std;
    use super::*;
    use proptest::prelude::*;
    use raymip_reference::raydiff::{self as rf, V, dot, norm};

    /// f64 value of I2F30 unit-vector components.
    pub(crate) fn vu(v: UnitVec) -> V {
        v.map(|c| f64::from(c.to_bits()) * 2f64.powi(-30))
    }
    /// `v/|v|` as I2F30 components.
    pub(crate) fn unit_q(v: V) -> UnitVec {
        let l = norm(v);
        UnitVec(v.map(|c| I2F30::saturating_from_num(c / l)))
    }
    pub(crate) fn state(s: &RayDiff) -> rf::Diff {
        rf::Diff {
            dox: s.dox().to_f64(),
            doy: s.doy().to_f64(),
            ddx: s.ddx().to_f64(),
            ddy: s.ddy().to_f64(),
        }
    }
    /// Largest component of `a − b`.
    fn dist(a: V, b: V) -> f64 {
        (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max)
    }

    /// A block-floating-point vector of any mantissas (down to one
    /// significant bit) with an exponent in `e` (f64 values stay normal).
    fn bfp(e: core::ops::Range<i32>) -> impl Strategy<Value = Bfp3> {
        (any::<[i32; 3]>(), e, 0u32..32).prop_map(|(m, e, s)| Bfp3::new(m.map(|x| x >> s), e))
    }
    fn unit() -> impl Strategy<Value = V> {
        [-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64].prop_filter("non-zero", |v| dot(*v, *v) > 1e-6)
    }
    /// A normal at `|D·n| = c` to `d`, facing it, turned by `side`.
    fn normal_at(d: V, c: f64, side: V) -> V {
        let s = rf::axpy(side, -dot(side, d), d);
        let s = rf::scale(1.0 / norm(s).max(1e-300), s);
        rf::axpy(rf::scale(-c, d), (1.0 - c * c).max(0.0).sqrt(), s)
    }

    #[test]
    fn head_on_cases_are_exact() {
        let (z, o) = (I2F30::ZERO, I2F30::ONE);
        let s = I2F30::from_num(1.0 / 512.0);
        let f = UnitVec([z, z, o]);
        let r = RayDiff::primary(
            f,
            f,
            DirDiff::from_i2f30([s, z, z]),
            DirDiff::from_i2f30([z, -s, z]),
        );
        assert_eq!(r.ddx().to_f64(), [1.0 / 512.0, 0.0, 0.0]);
        assert_eq!(r.ddy().to_f64(), [0.0, -1.0 / 512.0, 0.0]);
        assert_eq!(r.dox(), PosDiff::ZERO);
        let mut t = r;
        t.transfer(f, PathLength::from_num(3), UnitVec([z, z, -o]));
        assert_eq!(t.dox().to_f64(), [3.0 / 512.0, 0.0, 0.0]);
        assert_eq!(t.ddx(), r.ddx());
    }

    #[test]
    fn grazing_zero_and_extreme_inputs() {
        let (z, o) = (I2F30::ZERO, I2F30::ONE);
        let d = UnitVec([o, z, z]);
        let n = UnitVec([z, z, o]); // D·n = 0: clamped to +2⁻¹⁶
        let base = RayDiff::new(
            PosDiff::ZERO,
            PosDiff::ZERO,
            DirDiff::new([0, 0, 1], -10),
            DirDiff::ZERO,
        );
        let mut r = base;
        r.transfer(d, PathLength::from_num(10), n);
        // q = (0, 0, 10/1024); ∂t = −q·n / 2⁻¹⁶; ∂O' = q + ∂t·D.
        let want = -(10.0 / 1024.0) * 65536.0;
        assert!(
            (r.dox().to_f64()[0] - want).abs() <= want.abs() * 2f64.powi(-24),
            "{:?}",
            r.dox()
        );
        // t = 0 keeps ∂O; zero states stay zero.
        let mut k = RayDiff::new(
            PosDiff::new([5, 0, 0], -3),
            PosDiff::ZERO,
            DirDiff::new([1, 2, 3], 4),
            DirDiff::ZERO,
        );
        k.transfer(UnitVec([z, z, o]), PathLength::ZERO, UnitVec([z, z, -o]));
        assert_eq!(k.dox().to_f64(), [5.0 / 8.0, 0.0, 0.0]);
        let zero = RayDiff::ZERO;
        let mut zz = zero;
        zz.transfer(d, PathLength::MAX, n);
        zz.reflect(d, n, [DirDiff::ZERO; 2]);
        zz.refract(d, n, [DirDiff::ZERO; 2], Eta::ONE, z);
        assert_eq!(zz, zero);
        // Every extreme: no panic, exponents inside their range.
        let big = |e: i32| DirDiff::new([i32::MIN, i32::MAX, -1], e);
        let pbig = |e: i32| PosDiff::new([i32::MAX, i32::MIN, 1], e);
        for e in [EXP_MIN, -100, 0, 100, EXP_MAX] {
            let st = RayDiff::new(pbig(e), pbig(-e), big(e), big(-e));
            for v in [
                UnitVec([I2F30::MAX; 3]),
                UnitVec([I2F30::MIN; 3]),
                UnitVec([z; 3]),
                d,
            ] {
                let mut s = st;
                s.transfer(v, PathLength::MAX, v);
                s.reflect(v, v, [big(e), big(EXP_MAX)]);
                s.refract(
                    v,
                    v,
                    [big(EXP_MAX), big(e)],
                    Eta::from_fixed(I4F28::MAX),
                    I2F30::MIN,
                );
                s.refract(
                    v,
                    v,
                    [big(e), big(e)],
                    Eta::from_fixed(I4F28::MIN),
                    I2F30::MAX,
                );
                let _ = RayDiff::primary(v, v, big(e), big(EXP_MAX));
                for p in [s.dox().parts(), s.ddy().parts()] {
                    assert!((EXP_MIN..=EXP_MAX).contains(&p.1));
                }
            }
        }
    }

    /// A hit where `∂O` lies almost in the surface (`q·n = −2⁻²⁰·|q|`) at
    /// `|D·n| = 2⁻¹⁰`: `q·n` is normalised before its product with
    /// `D/(D·n)`, so the result keeps the precision of `q` (within `2⁻²⁴`
    /// of its scale here, where the documented bound allows `2⁻¹³`); an
    /// unnormalised `q·n` would align `q` to the term's unit and lose 14
    /// bits of it.
    #[test]
    fn transfer_keeps_a_small_q_dot_n_exact() {
        let z = I2F30::ZERO;
        let d = unit_q([(1.0 - 2f64.powi(-20)).sqrt(), 0.0, -(2f64.powi(-10))]);
        let n = UnitVec([z, z, I2F30::ONE]);
        let o = PosDiff::from_f64([1.0, 0.0, -(2f64.powi(-20))]);
        let s = RayDiff::new(o, o, DirDiff::ZERO, DirDiff::ZERO);
        let mut got = s;
        got.transfer(d, PathLength::ZERO, n);
        let want = rf::transfer(&state(&s), vu(d), 0.0, vu(n));
        let err = dist(got.dox().to_f64(), want.dox);
        assert!(
            err <= 2f64.powi(-24),
            "{err:e}: {:?} vs {:?}",
            got.dox().to_f64(),
            want.dox
        );
    }

    /// A non-unit direction and normal whose `D·n` is `−2` exactly, so
    /// that `cos θᵢ` is `2³¹` units, one beyond `i32`: the refraction
    /// wraps (no panic in an overflow-checked build) and the state keeps
    /// its exponents in range.
    #[test]
    fn refract_cos_at_i32_min_does_not_panic() {
        let (z, o) = (I2F30::ZERO, I2F30::ONE);
        let d = UnitVec([I2F30::MIN, z, z]);
        let n = UnitVec([o, z, z]);
        assert_eq!((dot64(bits(d), bits(n)) >> 30) as i32, i32::MIN);
        let dd = DirDiff::new([1 << 30, -5, 7], -20);
        let mut s = RayDiff::new(PosDiff::ZERO, PosDiff::ZERO, dd, dd);
        s.refract(
            d,
            n,
            [dd, DirDiff::ZERO],
            Eta::from_fixed(I4F28::from_num(1.5)),
            o,
        );
        for p in [s.ddx().parts(), s.ddy().parts()] {
            assert!((EXP_MIN..=EXP_MAX).contains(&p.1));
        }
        assert_eq!(s.dox(), PosDiff::ZERO);
    }

    /// `∂D` and `∂n` at one exponent, every mantissa at its largest and
    /// the two dot products of `∂cos θᵢ` of one sign: their sum is
    /// `2√3` times a vector's scale, inside 32 bits only with the bit of
    /// headroom the alignment leaves.
    #[test]
    fn refract_largest_aligned_dot_products() {
        let c = I2F30::from_num(0.577_350_269_189_625_7);
        let (n, d) = (UnitVec([c; 3]), UnitVec([-c; 3]));
        let (dd, dn) = (Bfp3::new([i32::MIN; 3], -40), Bfp3::new([i32::MAX; 3], -40));
        assert_eq!((dd.e, dn.e), (-40, -40));
        refract_x_within_bound(d, n, dd, dn, I4F28::from_num(1.0 / 1.5), I2F30::ONE);
    }

    /// The three terms of `∂T` (η·∂D, ∂μ·n, μ·∂n) near their largest at
    /// one exponent and of one sign (η just below 8, cos θₜ = 1, the
    /// largest mantissas): their sum fits 32 bits only with the bit of
    /// headroom of the common exponent (without it the x axis is off by
    /// 0.14 of its scale).
    #[test]
    fn refract_largest_aligned_terms() {
        let unit = |b: [i32; 3]| UnitVec(b.map(I2F30::from_bits));
        let d = unit([150_477_606, -465_389_534, 955_871_632]);
        let n = unit([193_524_233, 470_637_611, -945_499_929]);
        let dd = Bfp3::new([1 << 30, 1 << 30, 2_146_119_543], -47);
        let dn = Bfp3::new([1_270_073_125, i32::MAX, i32::MAX], -47);
        refract_x_within_bound(d, n, dd, dn, I4F28::MAX, I2F30::ONE);
    }

    /// A reflection at the largest `∂(D·n)`: `∂D` and `∂n` at their
    /// largest mantissas with the exponents that give both their least
    /// headroom (3 and 5 bits), `n` and `D` along `±(1, 1, 1)` and the two
    /// dot products of one sign: `2∂(D·n)` is `1.08·2³⁰` units, inside 32
    /// bits only with the bit the halving leaves; and an axis normal,
    /// whose component 1 is saturated.
    #[test]
    fn reflect_largest_dot_product_and_axis_normal() {
        let c = I2F30::from_num(0.577_350_269_189_625_7);
        let (z, o) = (I2F30::ZERO, I2F30::ONE);
        let cases = [
            (
                UnitVec([-c; 3]),
                UnitVec([c; 3]),
                [i32::MIN; 3],
                [i32::MAX; 3],
            ),
            (
                UnitVec([c; 3]),
                UnitVec([c; 3]),
                [i32::MAX; 3],
                [i32::MAX; 3],
            ),
            (
                UnitVec([z, c, -c]),
                UnitVec([z, z, o]),
                [i32::MAX, 0, i32::MIN],
                [1 << 30, 7, -1],
            ),
            (
                UnitVec([-o, z, z]),
                UnitVec([o, z, z]),
                [i32::MIN, 5, 0],
                [i32::MIN, 0, 3],
            ),
        ];
        for (d, n, dd, dn) in cases {
            let (dd, dn) = (Bfp3::new(dd, -40), Bfp3::new(dn, -42));
            let s = RayDiff::new(PosDiff::ZERO, PosDiff::ZERO, DirDiff(dd), DirDiff::ZERO);
            let mut got = s;
            got.reflect(d, n, [DirDiff(dn), DirDiff::ZERO]);
            let want = rf::reflect(&state(&s), vu(d), vu(n), val(dn), [0.0; 3]);
            let scale = norm(val(dd)) + 4.0 * norm(val(dn));
            let err = dist(got.ddx().to_f64(), want.ddx);
            assert!(
                err <= REFLECT_ERROR * scale,
                "{:e}: {:?} vs {:?}",
                err / scale,
                got.ddx().to_f64(),
                want.ddx
            );
        }
    }

    /// `refract` of the x axis (`∂D = dd`, `∂n = dn`) within
    /// `REFRACT_ERROR·(1 + 2η + η²/cos θₜ)·(|∂D| + |∂n|)` of f64.
    fn refract_x_within_bound(d: UnitVec, n: UnitVec, dd: Bfp3, dn: Bfp3, eta: I4F28, ct: I2F30) {
        let s = RayDiff::new(PosDiff::ZERO, PosDiff::ZERO, DirDiff(dd), DirDiff::ZERO);
        let mut got = s;
        got.refract(d, n, [DirDiff(dn), DirDiff::ZERO], Eta::from_fixed(eta), ct);
        let (ef, ctf) = (eta.to_num::<f64>(), ct.to_num::<f64>().max(rf::MIN_COS));
        let want = rf::refract(&state(&s), vu(d), vu(n), val(dn), [0.0; 3], ef, ctf);
        let scale = (1.0 + 2.0 * ef + ef * ef / ctf) * (norm(val(dd)) + norm(val(dn)));
        let err = dist(got.ddx().to_f64(), want.ddx);
        assert!(
            err <= REFRACT_ERROR * scale,
            "{:e}: {:?} vs {:?}",
            err / scale,
            got.ddx().to_f64(),
            want.ddx
        );
    }

    #[test]
    fn conversions() {
        let v = [0.375, -1e-9, 3.0e12];
        let p = PosDiff::from_f64(v).to_f64();
        for k in 0..3 {
            assert!((p[k] - v[k]).abs() <= 3.0e12 * 2f64.powi(-29));
        }
        assert_eq!(
            DirDiff::from_f64([0.0, f64::NAN, f64::INFINITY]),
            DirDiff::ZERO
        );
        assert_eq!(
            DirDiff::from_f64([1.0, 0.5, -0.25]).to_f64(),
            [1.0, 0.5, -0.25]
        );
        let s = I2F30::from_bits(-7);
        assert_eq!(DirDiff::from_i2f30([s; 3]).to_i2f30(), [s; 3]);
        assert_eq!(DirDiff::new([1, 0, 0], 40).to_i2f30()[0], I2F30::MAX);
        assert_eq!(
            DirDiff::new([1 << 30, 0, 0], -90).to_i2f30()[0],
            I2F30::ZERO
        );
        assert_eq!(core::mem::size_of::<RayDiff>(), 52);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]

        /// `Scalar::new` normalises as `Bfp3::new_in_range` on one
        /// component, bit for bit (shifts down to 0 and −1, any exponent of
        /// a refraction's scalars), and so as `Bfp3::new` inside its range.
        #[test]
        fn scalar_normalises_as_bfp3(m in any::<i64>(), s in 0u32..64, e in -(1i32 << 16)..=1 << 16) {
            let m = m >> s;
            let (a, b) = (Scalar::new(m as i32, e), Bfp3::new_in_range([m as i32, 0, 0], e));
            prop_assert_eq!((a.m, a.e), (b.m[0], b.e));
            if (EXP_MIN + 31..=EXP_MAX).contains(&e) {
                let b = Bfp3::new([m as i32, 0, 0], e);
                prop_assert_eq!((a.m, a.e), (b.m[0], b.e));
            }
        }

        /// A factor's exponent does not matter when it is zero: products
        /// of factors (`factor`, `mul_factor`) equal those of `new` and
        /// `mul` bit for bit, zeros (at EXP_MIN) among them, and a factor
        /// is `new`'s value wherever that is not zero.
        #[test]
        fn factors_multiply_as_scalars(a in prop_oneof![Just(0), Just(-1), any::<i32>()],
                                       b in prop_oneof![Just(0), Just(1), any::<i32>()],
                                       c in prop_oneof![Just(0), any::<i32>()],
                                       ea in -200i32..200, eb in -200i32..200, ec in -200i32..200) {
            let (fa, na) = (Scalar::factor(a, ea), Scalar::new(a, ea));
            let (fb, nb) = (Scalar::factor(b, eb), Scalar::new(b, eb));
            let nc = Scalar::new(c, ec);
            prop_assert_eq!(fa.m, na.m);
            if a != 0 {
                prop_assert_eq!(fa.e, na.e);
            }
            let want = na.mul(nb).mul(nc);
            let got = fa.mul_factor(fb).mul(nc);
            prop_assert_eq!((got.m, got.e), (want.m, want.e));
            let got = nc.mul(fa.mul_factor(fb));
            prop_assert_eq!((got.m, got.e), (want.m, want.e));
            prop_assert_eq!(fa.mul_factor(nb).m, na.mul(nb).m);
        }

        /// The transfer within `TRANSFER_ERROR·(|∂O| + t|∂D|)(1 + 1/|D·n|)`
        /// of f64 on the same inputs: any mantissas, exponents across 120
        /// octaves, t over the whole U32F32 range, |D·n| from 1 down to
        /// below MIN_COS.
        #[test]
        fn transfer_within_its_bound(o in bfp(-80..40), o2 in bfp(-80..40), dd in bfp(-80..0), dd2 in bfp(-80..0),
                                     t in any::<u64>(), ts in 0u32..64,
                                     d in unit(), side in unit(), lc in -17.0..0.0f64) {
            let du = unit_q(d);
            let df = vu(du);
            let n = unit_q(normal_at(df, lc.exp2(), side));
            let t = PathLength::from_bits(t >> ts);
            // The y axis its own ∂O and ∂D: the pair's two vectors differ
            // by up to 2¹²⁰ (∂O) and 2⁸⁰ (∂D).
            let s = RayDiff::new(PosDiff(o), PosDiff(o2), DirDiff(dd), DirDiff(dd2));
            let mut got = s;
            got.transfer(du, t, n);
            let want = rf::transfer(&state(&s), df, t.to_num(), vu(n));
            let c = dot(df, vu(n)).abs().max(rf::MIN_COS);
            let scale = (pair_norm(s.dox().to_f64(), s.doy().to_f64()) + t.to_num::<f64>() * pair_norm(s.ddx().to_f64(), s.ddy().to_f64())) * (1.0 + 1.0 / c);
            for (g, w) in [(got.dox(), want.dox), (got.doy(), want.doy)] {
                let err = dist(g.to_f64(), w);
                prop_assert!(err <= TRANSFER_ERROR * scale, "{:e} > {:e}: {:?} vs {:?}", err, TRANSFER_ERROR * scale, g.to_f64(), w);
            }
            prop_assert_eq!((got.ddx(), got.ddy()), (s.ddx(), s.ddy()));
        }

        /// The reflection within `REFLECT_ERROR·(|∂D| + 4|∂n|)`.
        #[test]
        fn reflect_within_its_bound(dd in bfp(-80..0), dd2 in bfp(-80..0), dn in bfp(-80..0), dn2 in bfp(-80..0),
                                    d in unit(), n in unit(), flat_y in any::<bool>()) {
            let (du, nu) = (unit_q(d), unit_q(n));
            let dn2 = if flat_y { Bfp3::ZERO } else { dn2 };
            let s = RayDiff::new(PosDiff::ZERO, PosDiff::ZERO, DirDiff(dd), DirDiff(dd2));
            let mut got = s;
            got.reflect(du, nu, [DirDiff(dn), DirDiff(dn2)]);
            let want = rf::reflect(&state(&s), vu(du), vu(nu), val(dn), val(dn2));
            let sc = pair_norm(s.ddx().to_f64(), s.ddy().to_f64()) + 4.0 * norm(val(dn)).max(norm(val(dn2)));
            for (g, w) in [(got.ddx(), want.ddx), (got.ddy(), want.ddy)] {
                let err = dist(g.to_f64(), w);
                prop_assert!(err <= REFLECT_ERROR * sc, "{:e}: {:?} vs {:?}", err / sc, g.to_f64(), w);
            }
            prop_assert_eq!(got.dox(), s.dox());
        }

        /// The refraction within `REFRACT_ERROR·(1 + 2η + η²/cos θₜ)(|∂D| + |∂n|)`,
        /// η over the I4F28 range used (0.25–7.9), cos θₜ down to 0.
        #[test]
        fn refract_within_its_bound(dd in bfp(-80..0), dn in bfp(-80..0), dd2 in bfp(-80..0), dn2 in bfp(-80..0),
                                    o in bfp(-80..40), d in unit(), n in unit(), eta in 0.25..7.9f64,
                                    ct_frac in 0.0..1.0f64, exact in any::<bool>()) {
            let du = unit_q(d);
            let nf = if dot(vu(du), vu(unit_q(n))) > 0.0 { n.map(|x| -x) } else { n };
            let nu = unit_q(nf);
            let (df, nq) = (vu(du), vu(nu));
            let eta = I4F28::from_num(eta);
            let ef = eta.to_num::<f64>();
            let ci = -dot(df, nq);
            let k = 1.0 - ef * ef * (1.0 - ci * ci);
            // cos θₜ from the directions, or any value (the caller's).
            let ct = I2F30::from_num(if exact && k >= 0.0 { k.sqrt() } else { ct_frac });
            // Each axis its own ∂D and ∂n, and ∂O set (kept).
            let s = RayDiff::new(PosDiff(o), PosDiff(Bfp3::new([1, -2, 3], o.e - 7)), DirDiff(dd), DirDiff(dd2));
            let mut got = s;
            got.refract(du, nu, [DirDiff(dn), DirDiff(dn2)], Eta::from_fixed(eta), ct);
            let ctf = ct.to_num::<f64>().max(rf::MIN_COS);
            let want = rf::refract(&state(&s), df, nq, val(dn), val(dn2), ef, ctf);
            let scale = (1.0 + 2.0 * ef + ef * ef / ctf)
                * (pair_norm(s.ddx().to_f64(), s.ddy().to_f64()) + norm(val(dn)).max(norm(val(dn2))));
            for (g, w) in [(got.ddx(), want.ddx), (got.ddy(), want.ddy)] {
                let err = dist(g.to_f64(), w);
                prop_assert!(err <= REFRACT_ERROR * scale, "{:e}: {:?} vs {:?}", err / scale, g.to_f64(), w);
            }
            prop_assert_eq!((got.dox(), got.doy()), (s.dox(), s.doy()));
        }

        /// The primary set-up within `PRIMARY_ERROR·(|D·f| + 1)·|r|`, any
        /// direction against any forward axis, steps across 60 octaves.
        #[test]
        fn primary_within_its_bound(r in bfp(-60..0), u in bfp(-60..0), d in unit(), f in unit()) {
            let (du, fu) = (unit_q(d), unit_q(f));
            let got = RayDiff::primary(du, fu, DirDiff(r), DirDiff(u));
            let want = rf::primary(vu(du), vu(fu), val(r), val(u));
            let df = dot(vu(du), vu(fu)).abs() + 1.0;
            let sc = df * norm(val(r)).max(norm(val(u)));
            for (g, w) in [(got.ddx(), want.ddx), (got.ddy(), want.ddy)] {
                let err = dist(g.to_f64(), w);
                prop_assert!(err <= PRIMARY_ERROR * sc, "{:e}", err / sc);
            }
        }
    }

    /// f64 value of a block-floating-point vector.
    fn val(v: Bfp3) -> V {
        PosDiff(v).to_f64()
    }

    /// The larger Euclidean length of a pair (the scale of the pair's one
    /// exponent).
    fn pair_norm(a: V, b: V) -> f64 {
        norm(a).max(norm(b))
    }
}
