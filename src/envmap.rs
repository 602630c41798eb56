//! Environment-map level of detail (Akenine-Möller and Nilsson, Ray
//! Tracing Gems ch. 21) for rays that leave the scene, and the direction →
//! texture coordinate mapping of a latitude-longitude map, in fixed point.
//! Feature `envmap` (the ray-differential variant also needs `raydiff`).
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
//! [`direction_uv`] is within [`ENVMAP_UV_MAX_ERROR`] `= 2⁻²⁴` (normalized
//! texture units, 1/512 texel of a 2¹⁵-texel map) of the f64 mapping of the
//! same direction: two CORDIC vectorings (Volder 1959: shifts and adds,
//! no multiplier, no division, no table beyond 26 arctangents), residual
//! angle `≤ atan 2⁻²⁵`, 60-bit normalised operands.

use core::fmt;

use fixed::types::I2F30;

use crate::lod::Lod;
use crate::log2::{log2_bits, log2_u32};
use crate::raystack::{Spread, UnitVec};
use crate::texture::TexCoord;

/// Documented error bound of [`EnvMap::cone_lod`] and
/// [`EnvMap::raydiff_lod`] against f64, in levels: 2⁻⁸ (derivation in the
/// [module docs](self#error-bound)).
pub const ENVMAP_LOD_MAX_ERROR: f64 = 1.0 / 256.0;

/// Documented error bound of [`direction_uv`] against f64, in normalized
/// texture units per coordinate: 2⁻²⁴.
pub const ENVMAP_UV_MAX_ERROR: f64 = 1.0 / 16_777_216.0;

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
/// use raymip::envmap::{ENVMAP_LOD_MAX_ERROR, EnvMap};
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
/// let d = [I2F30::ZERO, s, -c];
/// let lod = map.cone_lod(g, Some(d)).to_num::<f64>();
/// assert!((lod - 3.0).abs() <= ENVMAP_LOD_MAX_ERROR);
/// // At the pole the longitude term is clamped to 16 levels.
/// let up = [I2F30::ZERO, I2F30::ONE, I2F30::ZERO];
/// assert!((map.cone_lod(g, Some(up)).to_num::<f64>() - 18.0).abs() <= ENVMAP_LOD_MAX_ERROR);
/// # Ok::<(), raymip::envmap::EnvMapError>(())
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
    /// angle, radians; [`crate::raystack::RayCone::spread`]), with the
    /// pole term of direction `d` when given (formula, clamps and bound in
    /// the [module docs](self)). Per ray; never panics.
    #[inline]
    #[must_use]
    pub fn cone_lod(&self, spread: Spread, d: Option<UnitVec>) -> Lod {
        let la = log2_bits(u64::from(spread.to_bits().unsigned_abs()), 30).to_bits();
        self.lod_of(la, d)
    }

    /// Lod of a ray with direction differentials `dddx`, `dddy` (per
    /// pixel; [`crate::raydiff::RayDiff::dddx`]) leaving the scene:
    /// `α = max(|∂D/∂x|, |∂D/∂y|)`, with the pole term of direction `d`
    /// when given (formula, clamps and bound in the [module docs](self)).
    /// Features `envmap` and `raydiff`. Per ray; never panics.
    #[cfg(feature = "raydiff")]
    #[inline]
    #[must_use]
    pub fn raydiff_lod(
        &self,
        dddx: [crate::raydiff::DirDiff; 3],
        dddy: [crate::raydiff::DirDiff; 3],
        d: Option<UnitVec>,
    ) -> Lod {
        // |∂D|² in 2⁻⁶⁰ units, exact: each square ≤ 2⁶², the sum < 2⁶⁴.
        let len2 = |v: [crate::raydiff::DirDiff; 3]| -> u64 {
            v.iter()
                .map(|c| {
                    let a = u64::from(c.to_bits().unsigned_abs());
                    a * a
                })
                .fold(0u64, u64::saturating_add)
        };
        let l2 = len2(dddx).max(len2(dddy));
        let la = log2_bits(l2, 60).to_bits() >> 1;
        self.lod_of(la, d)
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

/// CORDIC iterations of [`direction_uv`].
const CORDIC_STEPS: usize = 26;

/// `round(atan(2⁻ⁱ) / 2π · 2⁴⁰)`: the CORDIC angles in 2⁻⁴⁰ turns.
const ATAN_TURNS: [i64; CORDIC_STEPS] = [
    137_438_953_472,
    81_134_951_838,
    42_869_480_287,
    21_761_217_566,
    10_922_836_750,
    5_466_743_129,
    2_734_038_620,
    1_367_102_738,
    683_561_799,
    341_782_203,
    170_891_265,
    85_445_653,
    42_722_829,
    21_361_415,
    10_680_707,
    5_340_354,
    2_670_177,
    1_335_088,
    667_544,
    333_772,
    166_886,
    83_443,
    41_722,
    20_861,
    10_430,
    5_215,
];

/// The CORDIC gain `K = Π √(1 + 2⁻²ⁱ)` of [`CORDIC_STEPS`] steps, 2⁻³⁰
/// units.
const CORDIC_GAIN: i64 = 1_768_195_363;

/// CORDIC vectoring of `(x, y)` with `x ≥ 0`, `|x|, |y| < 2⁶⁰`: the angle
/// `atan2(y, x)` in 2⁻⁴⁰ turns (`[−¼, ¼]`) and `K·√(x² + y²)` (< 2⁶²).
#[inline(always)]
fn vectoring(mut x: i64, mut y: i64) -> (i64, i64) {
    let mut a = 0i64;
    for (i, &t) in ATAN_TURNS.iter().enumerate() {
        let (dx, dy) = (y >> i, x >> i);
        if y > 0 {
            x += dx;
            y -= dy;
            a += t;
        } else {
            x -= dx;
            y += dy;
            a -= t;
        }
    }
    (a, x)
}

/// `(u, v)` of a latitude-longitude map for direction `d`
/// (`u = ½ + atan2(x, −z)/2π ∈ [0, 1]`, `v = ½ − asin(y)/π ∈ [0, 1]`,
/// with `asin(y) = atan2(y, √(x² + z²))`, so `d` need not be unit length;
/// see the [module docs](self)), within [`ENVMAP_UV_MAX_ERROR`] of f64.
/// At a pole (`x = z = 0`) `u = ½`; the zero vector gives `(½, ½)`. Integer
/// only; per ray; never panics.
///
/// # Example
/// ```
/// use raymip::envmap::{ENVMAP_UV_MAX_ERROR, direction_uv};
/// use fixed::types::I2F30;
/// let (o, z) = (I2F30::ONE, I2F30::ZERO);
/// let near = |a: raymip::TexCoord, b: f64| (a.to_num::<f64>() - b).abs() <= ENVMAP_UV_MAX_ERROR;
/// // Forward (−z): the centre of the map.
/// let (u, v) = direction_uv([z, z, -o]);
/// assert!(near(u, 0.5) && near(v, 0.5));
/// // +x is a quarter turn further along u; up (+y) is the top row.
/// let (u, _) = direction_uv([o, z, z]);
/// assert!(near(u, 0.75));
/// let (_, v) = direction_uv([z, o, z]);
/// assert!(near(v, 0.0));
/// ```
#[must_use]
pub fn direction_uv(d: UnitVec) -> (TexCoord, TexCoord) {
    let half = 1i64 << 31;
    let [x, y, z] = d.map(|c| i64::from(c.to_bits()));
    // Longitude: atan2(x, −z), operands normalised to a top bit at 2⁵⁹.
    let (mut cx, mut cy) = (-z, x);
    let top = cx.unsigned_abs().max(cy.unsigned_abs());
    let s = top.leading_zeros().saturating_sub(4).min(59);
    cx <<= s;
    cy <<= s;
    // Left half-plane: turn by ½ (the vectoring converges for x ≥ 0).
    let mut base = 0i64;
    if cx < 0 {
        base = if cy >= 0 { 1 << 39 } else { -(1 << 39) };
        cx = -cx;
        cy = -cy;
    }
    let (lon, r) = if top == 0 {
        (0, 0)
    } else {
        let (a, r) = vectoring(cx, cy);
        (base + a, r)
    };
    // Latitude: atan2(y, √(x² + z²)) with y scaled by the same 2ˢ and gain
    // K as r; both in 2^(−60−s) units (< 2¹²³), normalised below 2⁶⁰.
    let yk = i128::from(y * CORDIC_GAIN) << s;
    let rk = i128::from(r) << 30;
    let top2 = 128 - yk.unsigned_abs().max(rk.unsigned_abs()).leading_zeros();
    let s2 = top2.saturating_sub(60);
    let lat = if yk == 0 {
        0
    } else {
        vectoring((rk >> s2) as i64, (yk >> s2) as i64).0
    };
    // 2⁻⁴⁰ turns → I32F32 (2⁻³² units), rounded: u = ½ + lon, v = ½ − 2·lat.
    // The CORDIC residual may overshoot ±½ turn (seam) or ±¼ (poles) by
    // up to atan 2⁻²⁵: clamped to [0, 1].
    let u = (half + ((lon + (1 << 7)) >> 8)).clamp(0, 2 * half);
    let v = (half - ((lat + (1 << 6)) >> 7)).clamp(0, 2 * half);
    (TexCoord::from_bits(u), TexCoord::from_bits(v))
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::envmap_reference as reference;
    use proptest::prelude::*;

    fn q(v: [f64; 3]) -> UnitVec {
        v.map(I2F30::saturating_from_num)
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
        let m = EnvMap::new(MAX_SIZE, 1).unwrap();
        assert_eq!((m.width(), m.height()), (MAX_SIZE, 1));
    }

    #[test]
    fn edges_clamp_like_the_other_methods() {
        let m = EnvMap::new(2048, 1024).unwrap();
        let (o, z) = (I2F30::ONE, I2F30::ZERO);
        let g = Spread::from_num(2.0 * core::f64::consts::PI / 2048.0);
        // One texel of spread at the equator: level 0.
        assert!(m.cone_lod(g, None).abs() <= Lod::from_bits(1));
        assert_eq!(m.cone_lod(g, Some([z, z, -o])), m.cone_lod(g, None));
        // Poles, and the zero direction: the pole term saturates at 16.
        for d in [[z, o, z], [z, -o, z], [z, z, z]] {
            let l = m.cone_lod(g, Some(d)).to_num::<f64>();
            assert!((l - 16.0).abs() <= ENVMAP_LOD_MAX_ERROR, "{l}");
        }
        // Zero spread: 2⁻³⁰ rad, far below level 0; negative spread: |γ|.
        let zero = m.cone_lod(Spread::ZERO, None).to_num::<f64>();
        assert!((zero - (-30.0 + (2048.0 / (2.0 * core::f64::consts::PI)).log2())).abs() < 0.01);
        assert_eq!(m.cone_lod(-g, None), m.cone_lod(g, None));
        // Extremes never panic and stay inside ±64 levels.
        for s in [Spread::MIN, Spread::MAX, Spread::DELTA] {
            for d in [None, Some([I2F30::MAX; 3]), Some([I2F30::MIN; 3])] {
                assert!(m.cone_lod(s, d).abs() < Lod::from_num(64));
            }
        }
        // A non-unit direction with x² + z² > 1: the pole term clamps at 0.
        assert_eq!(
            m.cone_lod(g, Some([I2F30::MAX, z, I2F30::MAX])),
            m.cone_lod(g, None)
        );
    }

    #[test]
    #[cfg(feature = "raydiff")]
    fn raydiff_edges() {
        use crate::raydiff::DirDiff;
        let m = EnvMap::new(1024, 512).unwrap();
        let z = [DirDiff::ZERO; 3];
        let g = 2.0 * core::f64::consts::PI / 1024.0;
        let a = [DirDiff::from_num(g), DirDiff::ZERO, DirDiff::ZERO];
        // The larger axis rules; zero differentials read as 2⁻³⁰ rad.
        assert!(m.raydiff_lod(a, z, None).abs() <= Lod::from_bits(1));
        assert_eq!(m.raydiff_lod(z, a, None), m.raydiff_lod(a, z, None));
        assert_eq!(m.raydiff_lod(z, z, None), m.cone_lod(Spread::ZERO, None));
        for v in [[DirDiff::MIN; 3], [DirDiff::MAX; 3]] {
            assert!(m.raydiff_lod(v, v, Some([I2F30::ZERO; 3])).abs() < Lod::from_num(64));
        }
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
            let (gu, gv) = direction_uv(d);
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
        let (u, _) = direction_uv([-I2F30::DELTA, z, o]);
        assert!(u.to_num::<f64>() < 1e-6);
        // Extremes never panic and stay in [0, 1].
        for d in [
            [I2F30::MAX; 3],
            [I2F30::MIN; 3],
            [I2F30::MIN, I2F30::MAX, I2F30::DELTA],
        ] {
            let (u, v) = direction_uv(d);
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
                2 => Some([I2F30::from_bits(raw[0] >> 20), I2F30::ONE, I2F30::from_bits(raw[2] >> 20)]),
                _ => Some(raw.map(I2F30::from_bits)),
            };
            let want = reference::cone_lod_f64(w, h, g.to_num(), dir.map(f));
            check_lod(m.cone_lod(g, dir), want)?;
        }

        /// Ray-differential lod against f64 over the whole input range.
        #[test]
        #[cfg(feature = "raydiff")]
        fn raydiff_lod_matches_f64(w in size(), h in size(), a in any::<[i32; 3]>(), b in any::<[i32; 3]>(),
                                   e in 0u32..32, d in unit(), with_dir in any::<bool>()) {
            use crate::raydiff::DirDiff;
            let m = EnvMap::new(w, h).unwrap();
            let dx = a.map(|c| DirDiff::from_bits(c >> e));
            let dy = b.map(|c| DirDiff::from_bits(c >> (31 - e)));
            let dir = with_dir.then(|| q(d));
            let want = reference::raydiff_lod_f64(w, h, dx.map(|c| c.to_num()), dy.map(|c| c.to_num()), dir.map(f));
            check_lod(m.raydiff_lod(dx, dy, dir), want)?;
        }

        /// `direction_uv` against f64 for unit directions, near-pole ones
        /// and arbitrary I2F30 vectors (u compared around the seam).
        #[test]
        fn uv_matches_f64(d in unit(), raw in any::<[i32; 3]>(), s in 0u32..31, pick in 0u8..3) {
            let dir = match pick {
                0 => q(d),
                1 => [I2F30::from_bits(raw[0] >> s), I2F30::from_bits(raw[1]), I2F30::from_bits(raw[2] >> s)],
                _ => raw.map(|c| I2F30::from_bits(c >> s)),
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
