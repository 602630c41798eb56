//! Environment-map level of detail for rays that leave the scene, and the
//! direction → texture coordinate mapping of a latitude-longitude map, in
//! fixed point.
//!
//! After Akenine-Möller and Nilsson, Ray Tracing Gems ch. 21. Feature
//! `envmap` (the ray-differential variant also needs `raydiff`).
//!
//! An environment map lies infinitely far away: its lookup depends only on
//! the ray's direction, and its footprint only on the ray's angular spread
//! (the cone's spread angle, or the change of the direction per pixel),
//! not on the cone width or the ray's origin.
//!
//! # Map layout
//!
//! A `W × H` latitude-longitude map (`1 ≤ W, H ≤ 2¹⁵`, typically
//! `H = W/2`), `+y` up, for a unit direction `D = (x, y, z)`:
//!
//! ```text
//! u = ½ + atan2(x, −z) / 2π      (longitude; −z, the usual camera forward, is u = ½)
//! v = ½ − asin(y) / π            (latitude; v = 0 is the top row, +y)
//! ```
//!
//! One texel spans `2π/W` radians of longitude and `π/H` of latitude. A
//! circle of latitude `φ` is `cos φ = √(x² + z²)` shorter than the
//! equator, so there a texel spans only `cos φ · 2π/W` radians across.
//!
//! # Lod
//!
//! For an angular footprint of `α` radians per pixel (a cone's spread
//! angle `|γ|`: [`EnvMap::cone_lod`]; the larger of `|∂D/∂x|`, `|∂D/∂y|`:
//! [`EnvMap::raydiff_lod`]), the lod is `log2` of the larger footprint
//! axis in level-0 texels (the hardware paper's eq. 1, as for surfaces):
//!
//! ```text
//! λ = log2 α + max(log2(W/2π) − log2 cos φ,  log2(H/π))
//! ```
//!
//! The `−log2 cos φ` term (the longitude compression towards the poles) is
//! applied when the caller passes the direction (`Some(D)`), and left out
//! with `None` (RTG ch. 21's plain `log2(α / texel angle)` with the
//! equator's texel). With it, the footprint is a bound: a footprint that
//! is round in direction space covers `α/cos φ` radians of longitude, so
//! no direction aliases; it is not the exact anisotropic projection (a
//! footprint stretched along a meridian is over-blurred by up to that
//! factor, and at most ½ level for a round one measured along two
//! orthogonal axes, as ray differentials are). `|∂D|` is the angle per
//! pixel because `D` is a unit vector (`∂D ⟂ D`, `atan|∂D| ≈ |∂D|`).
//!
//! # Clamping and ranges
//!
//! * `cos φ` is clamped to `[`[`MIN_COS_LAT`]` = 2⁻¹⁶, 1]`: the pole term
//!   lies in `[0, 16]` levels (as the cone method's grazing clamp). At a
//!   pole itself (`x = z = 0`) the lod is thus 16 levels above the
//!   equator's, the coarsest level of any map once clamped to its levels.
//! * A zero spread (`γ = 0`, `∂D = 0`) is read as one raw unit, `2⁻³⁰`
//!   radians: the lod is about −30 levels below, level 0 once clamped
//!   ([`crate::lod::clamp_lod`]).
//! * `log2 α ∈ [−30, 1]`, the map terms `∈ [−2.66, 28.4]`: every result
//!   lies in `[−33, 30]` levels, inside [`Lod`]; nothing saturates.
//!
//! # Error bound
//!
//! Every lod is within [`ENVMAP_LOD_MAX_ERROR`] `= 2⁻⁸` level of the same
//! formula in f64 on the same (quantised) inputs, for every input: the
//! spread's `log2` within 2⁻¹³ ([`crate::log2::LOG2_MAX_ERROR`]; halved for
//! the squared `|∂D|²`), the map constant `log2 W − log2 2π` within
//! `2⁻¹³ + 2⁻¹⁷`, the latitude term (`½·log2(x² + z²)`, `x² + z²` exact)
//! within `2⁻¹⁴ + 2⁻¹⁷`, the output rounding 2⁻⁹: at most `2⁻⁹ + 2.6·2⁻¹³
//! ≈ 2.27·10⁻³`.
//!
//! # The mapping to (u, v)
//!
//! [`direction_uv`] works in 32-bit words (the results are 64-bit
//! [`TexCoord`]s). Each angle is an `atan2` of a pair of magnitudes:
//! `(|z|, |x|)` for the longitude, `(√(x² + z²), |y|)` for the latitude;
//! signs and a swap fold it into the first octant, `(a, b)` with
//! `0 ≤ b ≤ a`, normalised by a leading-zero count to `2³⁰ ≤ a < 2³¹`
//! (the latitude pair by the larger of its two exponents). Then:
//!
//! 1. three CORDIC vectoring steps (Volder 1959; shifts 1, 2, 3, the sign
//!    of `y` as a mask `m`, `v ^ m = −v − 1` for a negative turn)
//!    rotate `(a, b)` by `Σ ±atan 2⁻ⁱ` (a table of three angles in 2⁻³⁴
//!    turns) to `(x, y)`, `x ∈ [2³⁰, 1.65·2³¹)`, residual angle
//!    `|φ| ≤ atan ⅛` (plus the rounding below);
//! 2. `t = tan φ = y/x`: `1/x` from one 32-bit division by `x >> 16`
//!    (relative error in `(−2⁻¹⁶·³, 2⁻¹⁴]`) and one Newton step;
//! 3. `φ/2π = t·(1 − t²/3 + t⁴/5 − t⁶/7)/2π` (Taylor, four multiply-highs);
//!    for the longitude also `√(a² + b²) = x·√(1 + t²)/K₃` (binomial series
//!    to `t⁸`; `K₃ = √(5/4 · 17/16 · 65/64)` the gain of the three steps),
//!    the `r = √(x² + z²)` of the latitude pair;
//! 4. the octant angle is rounded to 2⁻³² turns (`u`) or 2⁻³³ turns (the
//!    latitude, `v = ½ − 2·lat`), clamped to `[0, ⅛]` and unfolded.
//!
//! Error of one octant angle, in units of 2⁻³⁴ turn (`2π·2⁻³⁴` rad):
//!
//! * the CORDIC roundings: each step leaves each coordinate less than 1
//!   off (floors; the `−v − 1`), carried through the remaining steps (gain
//!   `≤ √(17/16 · 65/64)`): `|E| ≤ √2·(1.0389 + 1.0078 + 1) = 4.31` beside
//!   a vector of length `≥ K₃·2³⁰`, an angle `≤ 3.71·2⁻³⁰` rad: **9.45**
//!   (and a relative length error `≤ 3.71·2⁻³⁰`);
//! * the three table angles (rounded) and the `−1` of the negated ones:
//!   **1.52**;
//! * `t`: the Newton step leaves `1/x` within the division's error squared
//!   plus its own floors, `2⁻²⁸ + 1.65·2⁻²⁹ ≤ 1.83·2⁻²⁸` (relative), the
//!   floor of `t·2³³` 2⁻³³: `|t|·1.83·2⁻²⁸ + 2⁻³³ ≤ 2.08·2⁻³¹` rad for
//!   `|t| ≤ ⅛`: **2.64**;
//! * the Taylor remainder `|t|⁹/9 ≤ 2⁻²⁷/9` rad: **2.27**;
//! * the Horner roundings (four floors, four rounded constants): **1.32**;
//!
//! together **17.2** (17.18). The length `√(a² + b²)` is
//! within `5.7·2⁻³⁰` (relative): the CORDIC roundings 3.71, its Horner
//! roundings 0.82, the final floor 1, `t` and the series remainder 0.16.
//! Per coordinate (normalized texture units, again
//! in units of 2⁻³⁴):
//!
//! * `u`: the octant 17.2, the rounding to 2⁻³² 2, the normalisation's
//!   dropped bit when `x` or `z` is `−2` (`I2F30::MIN`) 3.6 (`√2·2⁻³⁰` rad):
//!   **22.8·2⁻³⁴ ≈ 2⁻²⁹·⁵**;
//! * `v = ½ − 2·lat`, twice the latitude's error: the octant 17.2, the
//!   latitude pair's normalisation (a right shift of each word) 3.6, the
//!   length `r` (an angle error of at most half its relative error,
//!   `2.85·2⁻³⁰` rad) 7.26, the longitude pair's dropped bit at
//!   `I2F30::MIN` 1.8, the rounding to 2⁻³³ 1: **2·30.9·2⁻³⁴ =
//!   3.86·2⁻³⁰ < 2⁻²⁸**.
//!
//! [`ENVMAP_UV_MAX_ERROR`] `= 2⁻²⁸` (1/8192 texel of a 2¹⁵-texel map)
//! bounds both against the f64 mapping of the same (quantised) direction,
//! unit or not (measured over 10⁸ random directions, near-pole and scaled
//! ones and every combination of powers of two, `±(2ᵏ ± 1)`, 0 and the
//! extremes: `u` 2⁻³¹·⁰, `v` 2⁻²⁹·⁹).

use core::fmt;

use fixed::types::I2F30;

use crate::log2::{clz32, log2_bits, log2_u32};
use crate::units::{Lod, Spread, TexCoord, UnitVec};

/// Documented error bound of [`EnvMap::cone_lod`] and
/// [`EnvMap::raydiff_lod`] against f64, in levels: 2⁻⁸ (derivation in the
/// [module docs](self#error-bound)).
pub const ENVMAP_LOD_MAX_ERROR: f64 = 1.0 / 256.0;

/// Documented error bound of [`direction_uv`] against f64, in normalized
/// texture units per coordinate: 2⁻²⁸ (derived: `u ≤ 1.43·2⁻³⁰`,
/// `v ≤ 3.86·2⁻³⁰`, in the [module docs](self#the-mapping-to-u-v)).
pub const ENVMAP_UV_MAX_ERROR: f64 = 1.0 / 268_435_456.0;

/// Smallest `cos φ` (latitude) used by the pole term: 2⁻¹⁶ (I2F30 raw
/// `1 << 14`).
pub const MIN_COS_LAT: I2F30 = I2F30::from_bits(1 << 14);

/// Largest width or height of an environment map: 2¹⁵ texels.
pub const MAX_SIZE: u32 = 1 << 15;

/// `round(log2(2π) · 2¹⁶)`.
const LOG2_2PI: i32 = 173_768;
/// `round(log2(π) · 2¹⁶)`.
const LOG2_PI: i32 = 108_232;

/// An environment map's size outside `1 ..= MAX_SIZE`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EnvMapError {
    /// The width given.
    pub width: u32,
    /// The height given.
    pub height: u32,
}

impl fmt::Display for EnvMapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "environment map {}x{}: width and height must lie in 1..={MAX_SIZE}",
            self.width, self.height
        )
    }
}

impl core::error::Error for EnvMapError {}

/// A latitude-longitude environment map's lod constants:
/// `log2(W/2π)` and `log2(H/π)` (level-0 texels per radian of longitude at
/// the equator and of latitude), computed once at set-up.
///
/// # Example
/// ```
/// use raymip::lod::envmap::{ENVMAP_LOD_MAX_ERROR, EnvMap};
/// use raymip::units::UnitVec;
/// use raymip::{Lod, Spread};
/// use fixed::types::I2F30;
/// // A 2048×1024 map: one texel is 2π/2048 ≈ 3.07 mrad both ways.
/// let map = EnvMap::new(2048, 1024)?;
/// // A cone of 4 texels' spread: two levels up.
/// let g = Spread::from_num(4.0 * 2.0 * std::f64::consts::PI / 2048.0);
/// let lod = map.cone_lod(g, None).to_num::<f64>();
/// assert!((lod - 2.0).abs() <= ENVMAP_LOD_MAX_ERROR);
/// // The same ray leaving at 60° latitude: a circle of latitude of half
/// // the equator's length, one level more.
/// let (c, s) = (I2F30::from_num(0.5), I2F30::from_num(0.75f64.sqrt()));
/// let d = UnitVec::new([I2F30::ZERO, s, -c]);
/// let lod = map.cone_lod(g, Some(d)).to_num::<f64>();
/// assert!((lod - 3.0).abs() <= ENVMAP_LOD_MAX_ERROR);
/// // At the pole the longitude term is clamped to 16 levels.
/// let up = UnitVec::new([I2F30::ZERO, I2F30::ONE, I2F30::ZERO]);
/// assert!((map.cone_lod(g, Some(up)).to_num::<f64>() - 18.0).abs() <= ENVMAP_LOD_MAX_ERROR);
/// # Ok::<(), raymip::lod::envmap::EnvMapError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EnvMap {
    width: u32,
    height: u32,
    /// `log2(W/2π)`, I16F16 bits.
    log2_u: i32,
    /// `log2(H/π)`, I16F16 bits.
    log2_v: i32,
}

impl EnvMap {
    /// The constants of a `width × height` map (set-up; integer
    /// arithmetic). Sizes outside `1 ..= MAX_SIZE`: [`EnvMapError`].
    pub fn new(width: u32, height: u32) -> Result<Self, EnvMapError> {
        if !(1..=MAX_SIZE).contains(&width) || !(1..=MAX_SIZE).contains(&height) {
            return Err(EnvMapError { width, height });
        }
        Ok(Self {
            width,
            height,
            log2_u: log2_u32(width).to_bits() - LOG2_2PI,
            log2_v: log2_u32(height).to_bits() - LOG2_PI,
        })
    }

    /// Width in texels.
    #[must_use]
    pub const fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels.
    #[must_use]
    pub const fn height(&self) -> u32 {
        self.height
    }

    /// Lod of a ray cone leaving the scene: `α = |γ|` (the cone's spread
    /// angle, radians; [`crate::path::raystack::RayCone::spread`]), with the
    /// pole term of direction `d` when given (formula, clamps and bound in
    /// the [module docs](self)). Per ray; never panics.
    #[inline]
    #[must_use]
    pub fn cone_lod(&self, spread: Spread, d: Option<UnitVec>) -> Lod {
        let la = log2_bits(u64::from(spread.to_bits().unsigned_abs()), 30).to_bits();
        self.lod_of(la, d)
    }

    /// Lod of a ray with direction differentials `dddx`, `dddy` (per
    /// pixel; [`crate::path::raydiff::RayDiff::ddx`]) leaving the scene:
    /// `α = max(|∂D/∂x|, |∂D/∂y|)` (read as `2⁻³⁰` when smaller, as the
    /// cone's raw unit), with the pole term of direction `d` when given
    /// (formula, clamps and bound in the [module docs](self)). Features
    /// `envmap` and `raydiff`. Per ray; never panics.
    #[cfg(feature = "raydiff")]
    #[inline]
    #[must_use]
    pub fn raydiff_lod(
        &self,
        dddx: crate::path::raydiff::DirDiff,
        dddy: crate::path::raydiff::DirDiff,
        d: Option<UnitVec>,
    ) -> Lod {
        // |∂D|² = Σ mₖ²·4ᵉ: each square ≤ 2⁶², the sum < 2⁶⁴ (exact).
        let len2 = |m: [i32; 3]| -> u64 {
            m.iter()
                .map(|&c| {
                    let a = u64::from(c.unsigned_abs());
                    a * a
                })
                .sum()
        };
        let ((mx, ex), (my, ey)) = (dddx.parts(), dddy.parts());
        let la = crate::lod::raydiff::half_log2_max([len2(mx), len2(my)], [ex, ey]);
        self.lod_of(la.max(-30 << 16), d)
    }

    /// `log2 α` (I16F16 bits) plus the larger map term, rounded to [`Lod`].
    #[inline(always)]
    fn lod_of(&self, log2_alpha: i32, d: Option<UnitVec>) -> Lod {
        let mut lu = self.log2_u;
        if let Some(d) = d {
            // x² + z² in 2⁻⁶⁰ units (exact, < 2⁶³), clamped to
            // [MIN_COS_LAT², 1]; −log2 cos φ = −½·log2(x² + z²) ∈ [0, 16].
            let sq = |c: I2F30| {
                let a = u64::from(c.to_bits().unsigned_abs());
                a * a
            };
            let c2 = (sq(d[0]) + sq(d[2])).clamp(1 << 28, 1 << 60);
            lu -= log2_bits(c2, 60).to_bits() >> 1;
        }
        // |l| < 2²³ (module docs): no overflow; the clamp is for the type.
        let l = log2_alpha + lu.max(self.log2_v);
        let r = (l + 0x80) >> 8;
        Lod::from_bits(r.clamp(i32::from(i16::MIN), i32::from(i16::MAX)) as i16)
    }
}

/// `round(atan(2⁻ⁱ)/2π · 2³⁴)` for `i = 1, 2, 3`: the CORDIC angles of
/// [`direction_uv`] in 2⁻³⁴ turns (the first less 2³⁰, the centre of the
/// octant: the accumulator stays inside `i32`).
const ATAN_TURNS: [i32; 3] = [1_267_733_622 - (1 << 30), 669_835_629, 340_019_024];

/// `round(2^(32−2j)/((2j+1)π))`, `j = 0..=3`: `atan(t)/2π` in 2⁻³⁴ turns
/// is `t·2³³ · Σ (−t²)ʲ/((2j+1)π)` (Taylor), the coefficients at the
/// Horner scales of [`octant_atan`].
const ATAN_SERIES: [i32; 4] = [1_367_130_551, 113_927_546, 17_089_132, 3_051_631];

/// `round(c_j · 2^(31−2j) / K₃)`, `j = 0..=4`, with `c_j` the binomial
/// coefficients of `√(1 + s) = 1 + s/2 − s²/8 + s³/16 − 5s⁴/128 + …` and
/// `K₃ = √(5/4 · 17/16 · 65/64)` the gain of the three CORDIC steps: the
/// length of the vectored pair, `√(1 + t²)/K₃`, at the Horner scales.
const LENGTH_SERIES: [i32; 5] = [1_849_028_897, 231_128_612, 14_445_538, 1_805_692, 282_139];

/// `⌊a·b / 2³²⌋` (signed; one multiply-high).
#[inline(always)]
fn mulhi(a: i32, b: i32) -> i32 {
    ((i64::from(a) * i64::from(b)) >> 32) as i32
}

/// `⌊a·b / 2³²⌋` (unsigned; one multiply-high).
#[inline(always)]
fn mulhi_u(a: u32, b: u32) -> u32 {
    ((u64::from(a) * u64::from(b)) >> 32) as u32
}

/// The angle of `(a, b)` in the first octant, `2³⁰ ≤ a < 2³¹`,
/// `0 ≤ b ≤ a`: `atan(b/a)/2π − 1/16` in 2⁻³⁴ turns (bound in the
/// [module docs](self#the-mapping-to-u-v)), and `√(a² + b²)` in the units
/// of `a` (`< 1.42·2³¹`, relative error in the module docs; unused results
/// are optimised away).
///
/// Three CORDIC vectoring steps (shifts 1, 2, 3; the first always turns
/// by `−atan ½` as `b ≥ 0`) leave a residual angle `|φ| ≤ atan ⅛ + 2⁻²⁸`;
/// `t = tan φ = y/x` from one division and a Newton step of `1/x`, `φ` by
/// its Taylor series to `t⁷`, `√(1 + t²)` to `t⁸`.
#[inline(always)]
fn octant_atan(a: u32, b: u32) -> (i32, u32) {
    // Step 1 (σ = +1): x ∈ [2³⁰, 1.5·2³¹), y ∈ [−2²⁹, 2³⁰).
    let mut x = a + (b >> 1);
    let mut y = b as i32 - (a >> 1) as i32;
    let mut c = ATAN_TURNS[0];
    // Steps 2, 3: σ = sign(y) as a mask m (0 or −1); v ^ m is v or
    // −v − 1. x only grows (each term is ≥ 0) and stays below 1.65·2³¹.
    for (i, t) in [(2, ATAN_TURNS[1]), (3, ATAN_TURNS[2])] {
        let m = y >> 31;
        let dx = ((y >> i) ^ m) as u32;
        y -= ((x >> i) as i32) ^ m;
        x += dx;
        c += t ^ m;
    }
    // 1/x: q ≈ 2⁶²/x within (−2⁻¹⁶·³, 2⁻¹⁴·(1 + 2⁻¹⁴)] (x >> 16 ≥ 2¹⁴;
    // never 0: the check folds to one branch), one Newton step
    // r = q·(2 − x·q/2⁶²)/4 ≈ 2⁶⁰/x ≤ 2³⁰ (relative error ≤ 1.83·2⁻²⁸).
    let q = u32::MAX.checked_div(x >> 16).unwrap_or(0) << 14;
    let r = mulhi_u(q, (1 << 31) - mulhi_u(x, q));
    // t·2³³ (|t| ≤ tan(atan ⅛ + 2⁻²⁸): |T| < 2³⁰ + 2¹⁸), t²·2³⁴ (< 2²⁸·1.0001).
    let t = ((i64::from(y) * i64::from(r as i32)) >> 27) as i32;
    let s = mulhi(t, t);
    let [k1, k3, k5, k7] = ATAN_SERIES;
    let series = k1 - mulhi(s, k3 - mulhi(s, k5 - mulhi(s, k7)));
    let [g0, g1, g2, g3, g4] = LENGTH_SERIES;
    let len = g0 + mulhi(s, g1 - mulhi(s, g2 - mulhi(s, g3 - mulhi(s, g4))));
    (
        c + mulhi(t, series),
        ((u64::from(x) * u64::from(len as u32)) >> 31) as u32,
    )
}

/// The angle of `(a, b)`, `a, b ≥ 0`, `2³⁰ ≤ max(a, b) < 2³¹`, in
/// `2^−(32+e)` turns, `e ∈ {0, 1}` (`[0, 2^(30+e)]`, a quarter turn), and
/// the length `√(a² + b²)` in the units of `a` (see [`octant_atan`]).
#[inline(always)]
fn quadrant_atan<const E: i32>(a: u32, b: u32) -> (u32, u32) {
    let (swap, a, b) = if b > a { (true, b, a) } else { (false, a, b) };
    let (c, len) = octant_atan(a, b);
    // 2⁻³⁴ → 2^−(32+e) turns, rounded, clamped to the octant [0, 1/8].
    let sh = 2 - E;
    let octant = ((c + (1 << (sh - 1))) >> sh) + (1 << (28 + E));
    let octant = octant.clamp(0, 1 << (29 + E)) as u32;
    (
        if swap {
            (1 << (30 + E)) - octant
        } else {
            octant
        },
        len,
    )
}

/// The scale of [`direction_uv`]'s latitude pair: `r` the longitude
/// pair's length in units of 2^(1−s) raw (`s = clz(max(|x|, |z|))`; bit
/// length 30 to 32, `2³⁰·(1 − 2⁻²⁶) ≤ r < 1.42·2³¹`), `ay = |y|` raw
/// (`≤ 2³¹`). Returns the one `e ∈ [−31, 2]` for which the larger of
/// `r·2^(1−s−e)` and `ay·2⁻ᵉ` (floored) lies in `[2³⁰, 2³¹)`,
/// [`quadrant_atan`]'s input range, with no headroom bit left unused.
#[inline(always)]
fn latitude_exponent(r: u32, s: u32, ay: u32) -> i32 {
    let len_r = 30 + u32::from(r >= 1 << 30) + u32::from(r >= 1 << 31);
    (32 - clz32(ay)).max(len_r + 1 - s) as i32 - 31
}

/// `(u, v)` of a latitude-longitude map for direction `d`
/// (`u = ½ + atan2(x, −z)/2π ∈ [0, 1]`, `v = ½ − asin(y)/π ∈ [0, 1]`,
/// with `asin(y) = atan2(y, √(x² + z²))`, so `d` need not be unit length;
/// see the [module docs](self)), within [`ENVMAP_UV_MAX_ERROR`] of f64.
/// At a pole (`x = z = 0`) `u = ½`; the zero vector gives `(½, ½)`. Integer
/// only (32-bit words but for the results); per ray; never panics.
///
/// # Example
/// ```
/// use raymip::lod::envmap::{ENVMAP_UV_MAX_ERROR, direction_uv};
/// use fixed::types::I2F30;
/// use raymip::units::UnitVec;
/// let (o, z) = (I2F30::ONE, I2F30::ZERO);
/// let near = |a: raymip::TexCoord, b: f64| (a.to_num::<f64>() - b).abs() <= ENVMAP_UV_MAX_ERROR;
/// // Forward (−z): the centre of the map.
/// let (u, v) = direction_uv(UnitVec::new([z, z, -o]));
/// assert!(near(u, 0.5) && near(v, 0.5));
/// // +x is a quarter turn further along u; up (+y) is the top row.
/// let (u, _) = direction_uv(UnitVec::new([o, z, z]));
/// assert!(near(u, 0.75));
/// let (_, v) = direction_uv(UnitVec::new([z, o, z]));
/// assert!(near(v, 0.0));
/// ```
#[must_use]
pub fn direction_uv(d: UnitVec) -> (TexCoord, TexCoord) {
    let half = 1i64 << 31;
    let [x, y, z] = d.to_array().map(I2F30::to_bits);
    // Longitude atan2(x, −z): magnitudes (≤ 2³¹) normalised to
    // max ∈ [2³⁰, 2³¹) (raw·2^(s−1); only s = 0, a component of −2³¹
    // raw, drops a bit).
    let (ax, az) = (x.unsigned_abs(), z.unsigned_abs());
    let top = ax.max(az);
    if top == 0 {
        // A pole or the zero vector: u = ½, v = 0, 1 or ½.
        let v = half - i64::from(y.signum()) * half;
        return (TexCoord::from_bits(half), TexCoord::from_bits(v));
    }
    let s = clz32(top);
    let (lon, r) = quadrant_atan::<0>((az << s) >> 1, (ax << s) >> 1);
    // u = ½ ± lon for −z ≥ 0, else 1 − lon (x ≥ 0) or lon (x < 0).
    let lon = i64::from(lon);
    let u = match (z > 0, x < 0) {
        (false, false) => half + lon,
        (false, true) => half - lon,
        (true, false) => 2 * half - lon,
        (true, true) => lon,
    };
    // Latitude atan2(y, r): both scaled by 2⁻ᵉ.
    let ay = y.unsigned_abs();
    let e = latitude_exponent(r, s, ay);
    // r·2^(1−s−e): a left shift of at most 1 or a right shift ≤ 31.
    let sr = 1 - s as i32 - e;
    let rn = if sr >= 0 { r << sr } else { r >> -sr };
    let yn = if e <= 0 { ay << -e } else { ay >> e };
    let (lat, _) = quadrant_atan::<1>(rn, yn);
    // v = ½ − 2·lat: lat in 2⁻³³ turns is 2·lat in 2⁻³².
    let lat = i64::from(lat);
    let v = if y < 0 { half + lat } else { half - lat };
    (TexCoord::from_bits(u), TexCoord::from_bits(v))
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use proptest::prelude::*;
    use raymip_reference::envmap as reference;

    fn q(v: [f64; 3]) -> UnitVec {
        UnitVec(v.map(I2F30::saturating_from_num))
    }
    fn f(v: UnitVec) -> [f64; 3] {
        v.map(|c| c.to_num())
    }

    fn unit() -> impl Strategy<Value = [f64; 3]> {
        [-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64]
            .prop_filter("non-zero", |v| v.iter().map(|c| c * c).sum::<f64>() > 1e-6)
            .prop_map(|v| {
                let l = v.iter().map(|c| c * c).sum::<f64>().sqrt();
                v.map(|c| c / l)
            })
    }

    /// Map sizes over the whole range: powers of two, NPOT, 1 and 2¹⁵.
    fn size() -> impl Strategy<Value = u32> {
        prop_oneof![
            (0u32..=15).prop_map(|e| 1 << e),
            1u32..=MAX_SIZE,
            Just(1u32),
            Just(MAX_SIZE)
        ]
    }

    fn check_lod(got: Lod, want: f64) -> Result<(), TestCaseError> {
        prop_assert!(
            (got.to_num::<f64>() - want).abs() <= ENVMAP_LOD_MAX_ERROR,
            "lod {} vs f64 {}",
            got,
            want
        );
        Ok(())
    }

    #[test]
    fn sizes_outside_the_range_are_refused() {
        for (w, h) in [(0, 1), (1, 0), (MAX_SIZE + 1, 1), (1, MAX_SIZE + 1), (0, 0)] {
            let e = EnvMap::new(w, h).unwrap_err();
            assert_eq!(
                e,
                EnvMapError {
                    width: w,
                    height: h
                }
            );
            assert!(std::format!("{e}").contains(&std::format!("{w}x{h}")));
        }
        for (w, h) in [(MAX_SIZE, 1), (7, MAX_SIZE)] {
            let m = EnvMap::new(w, h).unwrap();
            assert_eq!((m.width(), m.height()), (w, h));
        }
    }

    #[test]
    fn edges_clamp_like_the_other_methods() {
        let m = EnvMap::new(2048, 1024).unwrap();
        let (o, z) = (I2F30::ONE, I2F30::ZERO);
        let g = Spread::from_num(2.0 * core::f64::consts::PI / 2048.0);
        // One texel of spread at the equator: level 0.
        assert!(m.cone_lod(g, None).abs() <= Lod::from_bits(1));
        assert_eq!(
            m.cone_lod(g, Some(UnitVec([z, z, -o]))),
            m.cone_lod(g, None)
        );
        // Poles, and the zero direction: the pole term saturates at 16,
        // −log2 MIN_COS_LAT (the documented clamp is the one applied).
        let pole = -MIN_COS_LAT.to_num::<f64>().log2();
        assert_eq!(pole, 16.0);
        for d in [[z, o, z], [z, -o, z], [z, z, z]] {
            let l = m.cone_lod(g, Some(UnitVec(d))).to_num::<f64>();
            assert!((l - pole).abs() <= ENVMAP_LOD_MAX_ERROR, "{l}");
        }
        // Zero spread: 2⁻³⁰ rad, far below level 0; negative spread: |γ|.
        let zero = m.cone_lod(Spread::ZERO, None).to_num::<f64>();
        assert!((zero - (-30.0 + (2048.0 / (2.0 * core::f64::consts::PI)).log2())).abs() < 0.01);
        assert_eq!(m.cone_lod(-g, None), m.cone_lod(g, None));
        // Extremes never panic and stay inside ±64 levels.
        for s in [Spread::MIN, Spread::MAX, Spread::DELTA] {
            for d in [
                None,
                Some(UnitVec([I2F30::MAX; 3])),
                Some(UnitVec([I2F30::MIN; 3])),
            ] {
                assert!(m.cone_lod(s, d).abs() < Lod::from_num(64));
            }
        }
        // A non-unit direction with x² + z² > 1: the pole term clamps at 0.
        assert_eq!(
            m.cone_lod(g, Some(UnitVec([I2F30::MAX, z, I2F30::MAX]))),
            m.cone_lod(g, None)
        );
    }

    #[test]
    #[cfg(feature = "raydiff")]
    fn raydiff_edges() {
        use crate::path::raydiff::DirDiff;
        let m = EnvMap::new(1024, 512).unwrap();
        let z = DirDiff::ZERO;
        let g = 2.0 * core::f64::consts::PI / 1024.0;
        let a = DirDiff::from_i2f30([I2F30::from_num(g), I2F30::ZERO, I2F30::ZERO]);
        // The larger axis rules; zero differentials read as 2⁻³⁰ rad, and
        // so does anything smaller.
        assert!(m.raydiff_lod(a, z, None).abs() <= Lod::from_bits(1));
        assert_eq!(m.raydiff_lod(z, a, None), m.raydiff_lod(a, z, None));
        assert_eq!(m.raydiff_lod(z, z, None), m.cone_lod(Spread::ZERO, None));
        let tiny = DirDiff::new([1, 2, 3], -400);
        assert_eq!(m.raydiff_lod(tiny, z, None), m.cone_lod(Spread::ZERO, None));
        // Huge differentials saturate the lod.
        let huge = DirDiff::new([i32::MIN; 3], 1000);
        assert_eq!(
            m.raydiff_lod(huge, huge, Some(UnitVec([I2F30::ZERO; 3]))),
            Lod::MAX
        );
    }

    /// The tables of `direction_uv`, recomputed in f64 from their formulas.
    #[test]
    fn uv_tables_match_their_formulas() {
        use core::f64::consts::PI;
        let round = |v: f64| v.round() as i64;
        for (i, &a) in ATAN_TURNS.iter().enumerate() {
            let off = if i == 0 { 1 << 30 } else { 0 };
            let want = round(0.5f64.powi(i as i32 + 1).atan() / (2.0 * PI) * 2f64.powi(34));
            assert_eq!(i64::from(a) + off, want, "atan 2^-{}", i + 1);
        }
        for (j, &k) in ATAN_SERIES.iter().enumerate() {
            let want = round(2f64.powi(32 - 2 * j as i32) / ((2 * j + 1) as f64 * PI));
            assert_eq!(i64::from(k), want, "atan series {j}");
        }
        let gain = (5.0f64 / 4.0 * 17.0 / 16.0 * 65.0 / 64.0).sqrt();
        let binomial = [1.0, 0.5, 0.125, 0.0625, 5.0 / 128.0];
        for (j, (&g, c)) in LENGTH_SERIES.iter().zip(binomial).enumerate() {
            let want = round(c * 2f64.powi(31 - 2 * j as i32) / gain);
            assert_eq!(i64::from(g), want, "length series {j}");
        }
    }

    /// The length series at its largest residual angle, without the CORDIC
    /// roundings: pairs of multiples of 64 (every shift exact) at angles
    /// just above `atan ½ + atan ¼ ≈ 40.6°` (no negated step, residual
    /// `φ ≈ −atan ⅛`). What is left is the series's own error, its Horner
    /// roundings 0.82, the final floor 1 and the remainder 0.16 (module
    /// docs): within 2·2⁻³⁰ (relative), where a wrong `t⁸` coefficient is
    /// 5·2⁻³⁰ off.
    #[test]
    fn octant_length_series_at_the_largest_residual() {
        let mut worst = 0.0f64;
        for i in 0..2_000u32 {
            let theta = (40.605 + f64::from(i) * 5e-5).to_radians();
            let a = ((1 << 30) + (i.wrapping_mul(500_009) << 6) % (1 << 30)) & !63;
            let b = (f64::from(a) * theta.tan()) as u32 & !63;
            let (_, len) = octant_atan(a, b);
            let l = f64::from(a).hypot(f64::from(b));
            worst = worst.max((f64::from(len) - l).abs() / l * 2f64.powi(30));
        }
        assert!(worst <= 2.0, "length error {worst:.2}·2⁻³⁰");
    }

    /// `quadrant_atan` rounds the octant angle to nearest: over random
    /// pairs of the lower octant (`b ≤ a`) its mean signed error against
    /// f64 is below ¼ unit of `2^−(32+e)` turn,
    /// where a rounding constant off by a factor of two or a sign shifts it
    /// by ½ unit or more. And the fold keeps each pair on its side of ⅛
    /// turn: the diagonal `b = a` is the lower octant's, never past it.
    #[test]
    fn quadrant_atan_rounds_to_nearest_and_keeps_the_diagonal() {
        use crate::rng::XorShift64;
        fn check<const E: i32>() {
            let unit = 2f64.powi(32 + E);
            let eighth = 1u32 << (29 + E);
            let mut r = XorShift64(0x9E37_79B9_7F4A_7C15);
            let (mut sum, n) = (0.0f64, 8_192);
            for _ in 0..n {
                let w = r.next_u64();
                let a = (1 << 30) | (w as u32 >> 2);
                let b = ((w >> 32) as u32) % (a + 1);
                let (got, _) = quadrant_atan::<E>(a, b);
                let want = f64::from(b).atan2(f64::from(a)) / (2.0 * core::f64::consts::PI) * unit;
                sum += f64::from(got) - want;
            }
            let mean = sum / f64::from(n);
            assert!(mean.abs() < 0.25, "e = {E}: mean error {mean:.3} units");
            for k in 0..4_096u32 {
                let a = (1 << 30) + k * 262_143;
                assert!(quadrant_atan::<E>(a, a).0 <= eighth, "e = {E}: ({a}, {a})");
                assert!(
                    quadrant_atan::<E>(a - 1, a).0 >= eighth,
                    "e = {E}: ({}, {a})",
                    a - 1
                );
            }
        }
        check::<0>();
        check::<1>();
    }

    /// Each closed hemisphere maps into its half of the map, its boundary
    /// included: `−z ≥ 0` (forward) into `u ∈ [¼, ¾]`, `y ≥ 0` (up) into
    /// `v ≤ ½`. On the boundaries `z = 0`, `y = 0` the angles' last-unit
    /// roundings must not carry a direction across (one in about 30 of
    /// these magnitudes rounds the axis angle off zero).
    #[test]
    fn uv_hemispheres_keep_their_boundaries() {
        let (quarter, half) = (1i64 << 30, 1i64 << 31);
        for k in 0..4_096i32 {
            for x in [(1 << 29) + k * 131_071, -(1 << 29) - k * 131_071] {
                for z in [0, x / 3, -(x / 7)] {
                    let d = [x, 0, z].map(I2F30::from_bits);
                    let (u, v) = direction_uv(UnitVec(d));
                    let (u, v) = (u.to_bits(), v.to_bits());
                    assert!(v <= half, "{d:?}: v {v} below the equator");
                    if z <= 0 {
                        assert!((quarter..=3 * quarter).contains(&u), "{d:?}: u {u}");
                    }
                }
            }
        }
    }

    /// The latitude pair's scale keeps every headroom bit: for lengths at
    /// and around the bit-length boundaries of `r` (2³⁰, the smallest `r`
    /// `2³⁰·(1 − 2⁻²⁶)` just below it, 2³¹, the largest `1.42·2³¹`), every
    /// normalisation shift `s` and latitudes from 0 to 2³¹, `e` is the one
    /// exponent for which the larger of `r·2^(1−s−e)` and `|y|·2⁻ᵉ`
    /// (floored) lies in `[2³⁰, 2³¹)`, [`quadrant_atan`]'s input range. A
    /// scale one bit too small keeps the same angle but doubles the CORDIC
    /// steps' relative roundings.
    #[test]
    fn latitude_scale_fills_the_word() {
        let r_min = (f64::from(1u32 << 30) * (1.0 - 2f64.powi(-26))).ceil() as u32;
        let r_max = (1.42 * f64::from(1u32 << 31)) as u32;
        let mut rs = std::vec![r_min, r_max];
        for edge in [1u32 << 30, 1 << 31] {
            rs.extend((1..=16).map(|k| edge - k));
            rs.extend((0..16).map(|k| edge + k));
        }
        rs.retain(|r| (r_min..=r_max).contains(r));
        let mut ays = std::vec![0u32, 1, u32::MAX / 3, 1 << 31];
        for k in 0..31 {
            ays.extend([1u32 << k, (1u32 << (k + 1)) - 1, (1u32 << k) + 1]);
        }
        for &r in &rs {
            for s in 0..32u32 {
                for &ay in &ays {
                    // The pair at scale 2ᵉ, e from −40 to 3, exactly (u128).
                    let at = |e: i32| {
                        let sh = |v: u128, k: i32| if k >= 0 { v << k } else { v >> -k };
                        (sh(u128::from(r), 1 - s as i32 - e), sh(u128::from(ay), -e))
                    };
                    let fits = |(a, b): (u128, u128)| (1 << 30..1 << 31).contains(&a.max(b));
                    let want = (-40..=3).find(|&e| fits(at(e))).unwrap();
                    assert_eq!(latitude_exponent(r, s, ay), want, "r {r}, s {s}, |y| {ay}");
                }
            }
        }
    }

    /// Every combination of 0, `±(2ᵏ ± 1)`, `±2ᵏ` and the extremes: in
    /// `[0, 1]` and within the bound (the normalisation shifts, the octant
    /// and quadrant edges and `I2F30::MIN`).
    #[test]
    fn uv_at_powers_of_two_and_the_extremes() {
        let mut vals = std::vec![0, i32::MIN, i32::MAX, i32::MIN + 1];
        for k in (0..31).step_by(2) {
            for v in [1i32 << k, (1 << k) - 1, (1 << k) + 1] {
                vals.extend([v, -v]);
            }
        }
        let mut worst = 0.0f64;
        for &a in &vals {
            for &b in &vals {
                for &c in &vals {
                    let d = [a, b, c].map(I2F30::from_bits);
                    let (u, v) = direction_uv(UnitVec(d));
                    let (u, v) = (u.to_num::<f64>(), v.to_num::<f64>());
                    let (wu, wv) = reference::direction_uv_f64(f(UnitVec(d)));
                    let du = (u - wu).abs();
                    assert!(
                        du.min(1.0 - du) <= ENVMAP_UV_MAX_ERROR,
                        "{d:?}: u {u} vs {wu}"
                    );
                    assert!(
                        (v - wv).abs() <= ENVMAP_UV_MAX_ERROR,
                        "{d:?}: v {v} vs {wv}"
                    );
                    assert!((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v));
                    worst = worst.max(du.min(1.0 - du)).max((v - wv).abs());
                }
            }
        }
        // The documented bound is not far above the measured error.
        std::println!("direction_uv: max |error| {worst:.3e} (bound {ENVMAP_UV_MAX_ERROR:.3e})");
        assert!(
            ENVMAP_UV_MAX_ERROR <= 8.0 * worst,
            "bound over 8x {worst:.3e}"
        );
    }

    /// The cone lod against f64 on a grid of map sizes, spreads (every
    /// power of two and its neighbours) and directions: within
    /// [`ENVMAP_LOD_MAX_ERROR`], and that bound within 4× of the measured
    /// error.
    #[test]
    fn cone_lod_bound_is_tight() {
        let dirs = [
            None,
            Some([0.0, 0.0, 1.0]),
            Some([0.6, 0.0, 0.8]),
            Some([0.1, 0.99, 0.0]),
            Some([-0.48, -0.6, 0.64]),
        ];
        let mut worst = 0.0f64;
        for (w, h) in [
            (1, 1),
            (7, 3),
            (256, 128),
            (1000, 500),
            (MAX_SIZE, MAX_SIZE),
        ] {
            let m = EnvMap::new(w, h).unwrap();
            for k in 0..31 {
                for g in [1i32 << k, (1 << k) + 1, (1 << k) - 1, 3 << k.min(29)] {
                    let g = Spread::from_bits(g.max(1));
                    for dir in dirs {
                        let dir = dir.map(|d: [f64; 3]| UnitVec(d.map(I2F30::from_num)));
                        let want = reference::cone_lod_f64(w, h, g.to_num(), dir.map(f));
                        let got = m.cone_lod(g, dir).to_num::<f64>();
                        assert!(
                            (got - want).abs() <= ENVMAP_LOD_MAX_ERROR,
                            "{got} vs {want}"
                        );
                        worst = worst.max((got - want).abs());
                    }
                }
            }
        }
        std::println!("cone_lod: max |error| {worst:.3e} (bound {ENVMAP_LOD_MAX_ERROR:.3e})");
        assert!(
            ENVMAP_LOD_MAX_ERROR <= 4.0 * worst,
            "bound over 4x {worst:.3e}"
        );
    }

    #[test]
    fn uv_at_the_axes_and_the_seam() {
        let (o, z) = (I2F30::ONE, I2F30::ZERO);
        let cases = [
            ([z, z, -o], (0.5, 0.5)),
            ([o, z, z], (0.75, 0.5)),
            ([-o, z, z], (0.25, 0.5)),
            ([z, z, o], (1.0, 0.5)),
            ([z, o, z], (0.5, 0.0)),
            ([z, -o, z], (0.5, 1.0)),
            ([z, z, z], (0.5, 0.5)),
        ];
        for (d, (u, v)) in cases {
            let (gu, gv) = direction_uv(UnitVec(d));
            assert!(
                (gu.to_num::<f64>() - u).abs() <= ENVMAP_UV_MAX_ERROR,
                "{d:?}: u {gu}"
            );
            assert!(
                (gv.to_num::<f64>() - v).abs() <= ENVMAP_UV_MAX_ERROR,
                "{d:?}: v {gv}"
            );
        }
        // Just below the seam (z > 0, x < 0): u near 0, not 1.
        let (u, _) = direction_uv(UnitVec([-I2F30::DELTA, z, o]));
        assert!(u.to_num::<f64>() < 1e-6);
        // Extremes never panic and stay in [0, 1].
        for d in [
            [I2F30::MAX; 3],
            [I2F30::MIN; 3],
            [I2F30::MIN, I2F30::MAX, I2F30::DELTA],
        ] {
            let (u, v) = direction_uv(UnitVec(d));
            assert!(
                (0.0..=1.0).contains(&u.to_num::<f64>())
                    && (0.0..=1.0).contains(&v.to_num::<f64>())
            );
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4_000))]

        /// Cone lod against f64 for every size, spread and direction
        /// (unit, near-pole and arbitrary I2F30 vectors).
        #[test]
        fn cone_lod_matches_f64(w in size(), h in size(), g in any::<i32>(), e in 0u32..32,
                                d in unit(), raw in any::<[i32; 3]>(), pick in 0u8..4) {
            let m = EnvMap::new(w, h).unwrap();
            let g = Spread::from_bits(g >> e);
            let dir = match pick {
                0 => None,
                1 => Some(q(d)),
                // Near a pole: x, z of a few raw units.
                2 => Some(UnitVec([I2F30::from_bits(raw[0] >> 20), I2F30::ONE, I2F30::from_bits(raw[2] >> 20)])),
                _ => Some(UnitVec(raw.map(I2F30::from_bits))),
            };
            let want = reference::cone_lod_f64(w, h, g.to_num(), dir.map(f));
            check_lod(m.cone_lod(g, dir), want)?;
        }

        /// Ray-differential lod against f64 over the whole input range.
        #[test]
        #[cfg(feature = "raydiff")]
        fn raydiff_lod_matches_f64(w in size(), h in size(), a in any::<[i32; 3]>(), b in any::<[i32; 3]>(),
                                   ea in -70i32..-20, eb in -70i32..-20, d in unit(), with_dir in any::<bool>()) {
            use crate::path::raydiff::DirDiff;
            let m = EnvMap::new(w, h).unwrap();
            let (dx, dy) = (DirDiff::new(a, ea), DirDiff::new(b, eb));
            let v = |x: DirDiff| { let (m, e) = x.parts(); m.map(|c| f64::from(c) * f64::from(e).exp2()) };
            let dir = with_dir.then(|| q(d));
            let want = reference::raydiff_lod_f64(w, h, v(dx), v(dy), dir.map(f));
            check_lod(m.raydiff_lod(dx, dy, dir), want)?;
        }

        /// One octant of `direction_uv` against f64 over its whole domain
        /// (`2³⁰ ≤ a < 2³¹`, `0 ≤ b ≤ a`; the edges by the masks): the
        /// angle within 17.2 units of 2⁻³⁴ turn, the length within
        /// 5.7·2⁻³⁰ (relative; module docs).
        #[test]
        fn octant_atan_within_its_bounds(a in 0u32..1 << 30, b in any::<u32>(), edge in 0u8..6) {
            let a = match edge {
                0 => 1 << 30,
                1 => u32::MAX >> 1,
                _ => (1 << 30) | a,
            };
            let b = match edge {
                2 => a,
                3 => 0,
                4 => b % 4096,
                _ => b % (a + 1),
            };
            let (c, len) = octant_atan(a, b);
            let (fa, fb) = (f64::from(a), f64::from(b));
            let want = fb.atan2(fa) / (2.0 * core::f64::consts::PI) * 2f64.powi(34) - 2f64.powi(30);
            prop_assert!((f64::from(c) - want).abs() <= 17.2, "angle of ({a}, {b}): {c} vs {want}");
            let l = fa.hypot(fb);
            prop_assert!((f64::from(len) - l).abs() <= 5.7 * l / 2f64.powi(30), "length of ({a}, {b}): {len} vs {l}");
        }

        /// `direction_uv` against f64 for unit directions, near-pole ones
        /// and arbitrary I2F30 vectors (u compared around the seam).
        #[test]
        fn uv_matches_f64(d in unit(), raw in any::<[i32; 3]>(), s in 0u32..31, pick in 0u8..3) {
            let dir = match pick {
                0 => q(d),
                1 => UnitVec([I2F30::from_bits(raw[0] >> s), I2F30::from_bits(raw[1]), I2F30::from_bits(raw[2] >> s)]),
                _ => UnitVec(raw.map(|c| I2F30::from_bits(c >> s))),
            };
            let (u, v) = direction_uv(dir);
            let (wu, wv) = reference::direction_uv_f64(f(dir));
            let du = (u.to_num::<f64>() - wu).abs();
            prop_assert!(du.min(1.0 - du) <= ENVMAP_UV_MAX_ERROR, "u {} vs {} ({:?})", u, wu, f(dir));
            prop_assert!((v.to_num::<f64>() - wv).abs() <= ENVMAP_UV_MAX_ERROR, "v {} vs {} ({:?})", v, wv, f(dir));
            prop_assert!((0.0..=1.0).contains(&u.to_num::<f64>()));
        }
    }
}
