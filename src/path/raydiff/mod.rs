//! Ray differentials (Igehy 1999, "Tracing Ray Differentials") in fixed
//! point: the per-pixel derivatives of a ray's origin and direction,
//! carried by the ray stack, transferred to each hit, reflected and
//! refracted there, and turned into a texture-space footprint
//! ([`crate::lod::raydiff`]) whose larger axis gives the lod and whose two axes drive
//! anisotropic filtering. Primary rays are set up from the camera
//! ([`RayDiff::primary`]), or first hits from a G-buffer ([`gbuffer`]).
//! Feature `raydiff`.
//!
//! # State and number formats
//!
//! | quantity | type | range | step |
//! |---|---|---|---|
//! | `∂O/∂x`, `∂O/∂y` (scene units per pixel) | [`PosDiff`] = I32F32 | `±2³¹` | `2⁻³²` |
//! | `∂D/∂x`, `∂D/∂y` (per pixel; `D` a unit vector) | [`DirDiff`] = I2F30 | `±2` | `2⁻³⁰ ≈ 9.3·10⁻¹⁰` |
//! | ray direction `D`, normals `n` (unit vectors) | [`UnitVec`] = `[I2F30; 3]` | `±2` per component | `2⁻³⁰` |
//! | hit distance `t` | [`PathLength`] = U32F32 | `[0, 2³²)` | `2⁻³²` |
//! | relative index `η = n₁/n₂` | [`Eta`] = I4F28 | `±8` | `2⁻²⁸` |
//!
//! A 4K image has a pixel spread of about `2.5·10⁻⁴` radians, so `∂D` is
//! resolved to about `4·10⁻⁶` relative; `|∂D|` beyond 2 (a mirror curved
//! more sharply than a pixel) saturates. Every operation returns a flag that
//! is true when a result saturated (its footprint is then a bound, not a
//! value), as [`crate::path::raystack::PathState::saturated`]. Intermediate
//! products are 128-bit (compiler-builtins `__multi3` on 32-bit cores, one
//! 64-bit division per transfer); the cost per call on the targets is in
//! `BUDGETS.md`.
//!
//! # Grazing angles
//!
//! A transfer divides by `D·n` and a refraction by `cos θₜ`; both are
//! clamped to `|·| ≥ `[`MIN_COS`]` = 2⁻¹⁶` (as the cone method's normal
//! term), so the footprint of a grazing hit is at most `2¹⁶` times the
//! head-on one and stays finite.
//!
//! # Error bound
//!
//! See [`crate::lod::raydiff`]: the lod from these differentials is within
//! [`crate::lod::raydiff::RAYDIFF_LOD_MAX_ERROR`] of the same computation in f64.

use fixed::types::{I2F30, I4F28, I32F32};

use crate::units::{PathLength, UnitVec};

pub mod gbuffer;

/// A position differential component: scene units per pixel, I32F32.
/// Example: [`RayDiff`].
pub type PosDiff = I32F32;
/// A direction differential component: per pixel, I2F30. Example:
/// [`RayDiff`].
pub type DirDiff = I2F30;
/// Relative index of refraction `η = n₁/n₂` (incident over transmitted
/// medium), I4F28. Example: [`RayDiff`].
pub type Eta = I4F28;

/// Smallest `|D·n|` and `cos θₜ` used as a divisor: 2⁻¹⁶ (see
/// [Grazing angles](self#grazing-angles)).
pub const MIN_COS: I2F30 = I2F30::from_bits(1 << 14);

/// The differential state of one ray (one ray-stack entry, feature
/// `raydiff`): `∂O/∂x, ∂O/∂y, ∂D/∂x, ∂D/∂y` (formats in the
/// [module docs](self)). 72 bytes.
///
/// # Example
/// ```
/// use raymip::PathLength;
/// use raymip::path::raydiff::{DirDiff, Eta, PosDiff, RayDiff};
/// use raymip::units::UnitVec;
/// let (one, zero) = (DirDiff::ONE, DirDiff::ZERO);
/// // A camera looking down −z; one pixel step turns the unnormalised
/// // direction by s = 2⁻¹⁰ along x (right) or y (up).
/// let s = DirDiff::from_num(1.0 / 1024.0);
/// let forward = UnitVec::new([zero, zero, -one]);
/// let (primary, _) = RayDiff::primary(forward, forward, [s, zero, zero], [zero, s, zero]);
/// // The centre ray: D·f = 1, D·r = 0, so ∂D/∂x = r and ∂D/∂y = u.
/// assert_eq!((primary.dddx, primary.dddy), ([s, zero, zero], [zero, s, zero]));
/// // Transfer to a wall facing the camera (n = +z) at t = 100: ∂D·t
/// // lies in the wall, so ∂O = 100·2⁻¹⁰ scene units per pixel along x.
/// let up = UnitVec::new([zero, zero, one]);
/// let (hit, saturated) = primary.transfer(forward, PathLength::from_num(100), up);
/// assert!(!saturated);
/// assert_eq!(hit.dodx, [PosDiff::from_num(100.0 / 1024.0), PosDiff::ZERO, PosDiff::ZERO]);
/// // A flat mirror (∂n = 0) facing the ray: ∂D ⟂ n stays as it is.
/// let flat = [zero; 3];
/// let (mirrored, _) = hit.reflect(forward, up, flat, flat);
/// assert_eq!(mirrored.dddx, hit.dddx);
/// // Head-on into a denser medium, η = ½ (cos θₜ = 1): ∂T = η·∂D.
/// let (refracted, _) = hit.refract(forward, up, flat, flat, Eta::from_num(0.5), one);
/// assert_eq!(refracted.dddx, [DirDiff::from_num(1.0 / 2048.0), zero, zero]);
/// assert_eq!(refracted.dodx, hit.dodx); // the hit point's ∂O is kept
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct RayDiff {
    /// `∂O/∂x` (scene units per pixel).
    pub dodx: [PosDiff; 3],
    /// `∂O/∂y`.
    pub dody: [PosDiff; 3],
    /// `∂D/∂x` (per pixel).
    pub dddx: [DirDiff; 3],
    /// `∂D/∂y`.
    pub dddy: [DirDiff; 3],
}

/// `round(v / 2ˢ)` for `1 ≤ s ≤ 64` (`|v| < 2¹²⁶`, so the offset cannot
/// overflow).
#[inline(always)]
fn shr_round(v: i128, s: u32) -> i128 {
    (v + (1i128 << (s - 1))) >> s
}

/// `v` saturated to `i64`, `sat` set when it did not fit.
#[inline(always)]
fn sat64(v: i128, sat: &mut bool) -> i64 {
    let c = v.clamp(i128::from(i64::MIN), i128::from(i64::MAX));
    *sat |= c != v;
    c as i64
}

/// `v` saturated to `i32`, `sat` set when it did not fit.
#[inline(always)]
fn sat32(v: i128, sat: &mut bool) -> i32 {
    let c = v.clamp(i128::from(i32::MIN), i128::from(i32::MAX));
    *sat |= c != v;
    c as i32
}

/// `a·b` of two I2F30 vectors in 2⁻⁶⁰ units (exact).
#[inline(always)]
fn dot60(a: [I2F30; 3], b: [I2F30; 3]) -> i128 {
    (0..3)
        .map(|k| i128::from(a[k].to_bits()) * i128::from(b[k].to_bits()))
        .sum()
}

/// `a·b` of two I2F30 vectors in 2⁻³⁰ units (rounded).
#[inline(always)]
fn dot30(a: [I2F30; 3], b: [I2F30; 3]) -> i128 {
    shr_round(dot60(a, b), 30)
}

/// `x` with `|x| ≥ MIN_COS` (sign kept; zero reads as `+MIN_COS`), 2⁻³⁰ units.
#[inline(always)]
fn clamp_cos(x: i128) -> i128 {
    let m = i128::from(MIN_COS.to_bits());
    if x < 0 { x.min(-m) } else { x.max(m) }
}

impl RayDiff {
    /// No differential (a pinhole camera's primary ray has `∂O = 0`).
    pub const ZERO: Self = Self {
        dodx: [PosDiff::ZERO; 3],
        dody: [PosDiff::ZERO; 3],
        dddx: [DirDiff::ZERO; 3],
        dddy: [DirDiff::ZERO; 3],
    };

    /// Primary ray of a pinhole camera (`∂O = 0`): for the unit ray
    /// direction `d`, the camera's unit forward axis `forward` and the
    /// change of the unnormalised direction `f + x·r + y·u` per pixel in x
    /// (`right`) and y (`up`) on the image plane at unit distance,
    /// `∂D/∂x = (D·f)·(r − (D·r)·D)` (the derivative of `d/|d|`, with
    /// `1/|d| = D·f`), the same with `u` in y. Saturating (flag).
    #[must_use]
    pub fn primary(
        d: UnitVec,
        forward: UnitVec,
        right: [DirDiff; 3],
        up: [DirDiff; 3],
    ) -> (Self, bool) {
        let mut sat = false;
        let df = dot30(d.0, forward.0);
        let mut axis = |r: [DirDiff; 3]| -> [DirDiff; 3] {
            let dr = dot30(d.0, r);
            core::array::from_fn(|k| {
                let t = i128::from(r[k].to_bits()) - shr_round(dr * i128::from(d[k].to_bits()), 30);
                DirDiff::from_bits(sat32(shr_round(df * t, 30), &mut sat))
            })
        };
        let dddx = axis(right);
        let dddy = axis(up);
        (
            Self {
                dddx,
                dddy,
                ..Self::ZERO
            },
            sat,
        )
    }

    /// Transfer to a hit at distance `t` on a surface of unit normal `n`
    /// (Igehy eq. 10–12): `q = ∂O + t·∂D`, `∂t = −(q·n)/(D·n)`,
    /// `∂O' = q + ∂t·D`; `∂D` is unchanged. `∂O'` is then the hit point's
    /// differential on the tangent plane ([`crate::lod::raydiff`] reads it).
    /// `|D·n|` is clamped to [`MIN_COS`]. Saturating (flag).
    #[must_use]
    pub fn transfer(self, d: UnitVec, t: PathLength, n: UnitVec) -> (Self, bool) {
        let mut sat = false;
        // |D·n| ∈ [2⁻¹⁶, 12] after the clamp: 2⁻³⁰ bits fit i64.
        let dn = clamp_cos(dot30(d.0, n.0)) as i64;
        // 1/(D·n) in 2⁻³⁰ units, |inv| ≤ 2⁴⁶ (dn ≠ 0: the fallback is never taken).
        let inv = i128::from((1i64 << 60).checked_div(dn).unwrap_or(0));
        let t = i128::from(t.to_bits());
        let mut axis = |o: [PosDiff; 3], dd: [DirDiff; 3]| -> [PosDiff; 3] {
            // q in 2⁻³² units, |q| < 2⁶³ + 2⁶⁶.
            let q: [i128; 3] = core::array::from_fn(|k| {
                i128::from(o[k].to_bits()) + shr_round(t * i128::from(dd[k].to_bits()), 30)
            });
            let qn: i128 = (0..3)
                .map(|k| shr_round(q[k] * i128::from(n[k].to_bits()), 30))
                .sum();
            // ∂t in 2⁻³² units (|qn·inv| < 2¹¹⁵).
            let dt = -shr_round(qn * inv, 30);
            let dt = dt.clamp(-(1i128 << 90), 1i128 << 90);
            core::array::from_fn(|k| {
                PosDiff::from_bits(sat64(
                    q[k] + shr_round(dt * i128::from(d[k].to_bits()), 30),
                    &mut sat,
                ))
            })
        };
        let dodx = axis(self.dodx, self.dddx);
        let dody = axis(self.dody, self.dddy);
        (Self { dodx, dody, ..self }, sat)
    }

    /// Reflection about the unit shading normal `n` with its per-pixel
    /// differentials `dndx`, `dndy` (passed by the caller, zero on flat
    /// triangles) (Igehy eq. 14–15): `∂R = ∂D − 2·((D·n)·∂n + ∂(D·n)·n)`,
    /// `∂(D·n) = ∂D·n + D·∂n`; `∂O` (the hit's) is kept. Saturating (flag).
    #[must_use]
    pub fn reflect(
        self,
        d: UnitVec,
        n: UnitVec,
        dndx: [DirDiff; 3],
        dndy: [DirDiff; 3],
    ) -> (Self, bool) {
        let mut sat = false;
        let dn = dot30(d.0, n.0);
        let mut axis = |dd: [DirDiff; 3], dnv: [DirDiff; 3]| -> [DirDiff; 3] {
            let ddn = shr_round(dot60(dd, n.0) + dot60(d.0, dnv), 30);
            core::array::from_fn(|k| {
                let s = dn * i128::from(dnv[k].to_bits()) + ddn * i128::from(n[k].to_bits());
                DirDiff::from_bits(sat32(
                    i128::from(dd[k].to_bits()) - 2 * shr_round(s, 30),
                    &mut sat,
                ))
            })
        };
        let dddx = axis(self.dddx, dndx);
        let dddy = axis(self.dddy, dndy);
        (Self { dddx, dddy, ..self }, sat)
    }

    /// Refraction through the unit shading normal `n` facing the incoming
    /// ray (`D·n < 0`) with differentials `dndx`, `dndy`, relative index
    /// `eta` and `cos_t = cos θₜ = √(1 − η²(1 − (D·n)²))` (the caller has
    /// it from the refracted direction `T = ηD + μn`); Igehy eq. 16–18 with
    /// `cos θᵢ = −D·n`, `μ = η·cos θᵢ − cos θₜ`:
    /// `∂μ = (η − η²·cos θᵢ / cos θₜ)·∂cos θᵢ`, `∂cos θᵢ = −(∂D·n + D·∂n)`,
    /// `∂T = η·∂D + ∂μ·n + μ·∂n`; `∂O` is kept. `cos θₜ` is clamped to
    /// [`MIN_COS`] (near the critical angle). Saturating (flag).
    #[must_use]
    pub fn refract(
        self,
        d: UnitVec,
        n: UnitVec,
        dndx: [DirDiff; 3],
        dndy: [DirDiff; 3],
        eta: Eta,
        cos_t: I2F30,
    ) -> (Self, bool) {
        let mut sat = false;
        let eta = i128::from(eta.to_bits()); // 2⁻²⁸
        let cosi = -dot30(d.0, n.0); // 2⁻³⁰
        let cos_t = i128::from(cos_t.to_bits()).max(i128::from(MIN_COS.to_bits()));
        // μ in 2⁻³⁰ units.
        let mu = shr_round(eta * cosi, 28) - cos_t;
        // η²·cos θᵢ / cos θₜ in 2⁻³⁰ units: η² cos θᵢ is 2⁻⁸⁶, / 2⁻³⁰ → 2⁻⁵⁶.
        // cos_t ≥ 2¹⁴ > 0: the fallback is never taken.
        let ratio = shr_round((eta * eta * cosi).checked_div(cos_t).unwrap_or(0), 26);
        let coef = (eta << 2) - ratio; // 2⁻³⁰, |coef| < 2⁵⁵
        let mut axis = |dd: [DirDiff; 3], dnv: [DirDiff; 3]| -> [DirDiff; 3] {
            let dcos = -shr_round(dot60(dd, n.0) + dot60(d.0, dnv), 30);
            let dmu = shr_round(coef * dcos, 30);
            core::array::from_fn(|k| {
                let v = shr_round(eta * i128::from(dd[k].to_bits()), 28)
                    + shr_round(dmu * i128::from(n[k].to_bits()), 30)
                    + shr_round(mu * i128::from(dnv[k].to_bits()), 30);
                DirDiff::from_bits(sat32(v, &mut sat))
            })
        };
        let dddx = axis(self.dddx, dndx);
        let dddy = axis(self.dddy, dndy);
        (Self { dddx, dddy, ..self }, sat)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    extern crate std;
    use super::*;
    use proptest::prelude::*;

    pub(crate) type V = [f64; 3];

    pub(crate) fn dot(a: V, b: V) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }
    pub(crate) fn add(a: V, b: V, s: f64) -> V {
        [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
    }
    pub(crate) fn norm(a: V) -> V {
        let l = dot(a, a).sqrt();
        [a[0] / l, a[1] / l, a[2] / l]
    }
    pub(crate) fn uq(a: V) -> [I2F30; 3] {
        a.map(I2F30::from_num)
    }
    pub(crate) fn pf(a: [PosDiff; 3]) -> V {
        a.map(|x| x.to_num())
    }
    pub(crate) fn df(a: [DirDiff; 3]) -> V {
        a.map(|x| x.to_num())
    }

    /// f64 Igehy transfer, as the harness's tracer writes it.
    pub(crate) fn transfer_f64(o: V, dd: V, d: V, t: f64, n: V) -> V {
        let q = add(o, dd, t);
        let dn = dot(d, n);
        let dn = if dn.abs() < MIN_COS.to_num::<f64>() {
            MIN_COS
                .to_num::<f64>()
                .copysign(if dn == 0.0 { 1.0 } else { dn })
        } else {
            dn
        };
        add(q, d, -dot(q, n) / dn)
    }

    fn unit() -> impl Strategy<Value = V> {
        ([-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64])
            .prop_filter("non-zero", |v| dot(*v, *v) > 1e-3)
            .prop_map(norm)
    }

    fn close(a: V, b: V, tol: f64) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() <= tol)
    }

    #[test]
    fn primary_of_a_head_on_ray_is_the_pixel_step() {
        let g = 1.0 / 512.0;
        let f = [0.0, 0.0, 1.0];
        let (r, sat) = RayDiff::primary(
            UnitVec(uq(f)),
            UnitVec(uq(f)),
            uq([g, 0.0, 0.0]),
            uq([0.0, -g, 0.0]),
        );
        assert!(!sat);
        assert_eq!(df(r.dddx), [g, 0.0, 0.0]);
        assert_eq!(df(r.dddy), [0.0, -g, 0.0]);
        assert_eq!(r.dodx, [PosDiff::ZERO; 3]);
    }

    #[test]
    fn grazing_and_zero_cases_clamp() {
        let d = uq([1.0, 0.0, 0.0]);
        let n = uq([0.0, 0.0, 1.0]); // D·n = 0: clamped
        let base = RayDiff {
            dddx: uq([0.0, 0.0, 1.0 / 1024.0]),
            ..RayDiff::ZERO
        };
        let (r, sat) = base.transfer(UnitVec(d), PathLength::from_num(10), UnitVec(n));
        // q = (0, 0, 10/1024); ∂t = −q·n / 2⁻¹⁶; ∂O' = q + ∂t·D.
        let want = -(10.0 / 1024.0) * 65536.0;
        assert!(!sat);
        assert!(
            (r.dodx[0].to_num::<f64>() - want).abs() < 1e-6,
            "{:?}",
            r.dodx
        );
        // Zero state stays zero through every operation.
        let z = RayDiff::ZERO;
        assert_eq!(z.transfer(UnitVec(d), PathLength::MAX, UnitVec(n)).0, z);
        assert_eq!(
            z.reflect(
                UnitVec(d),
                UnitVec(n),
                [DirDiff::ZERO; 3],
                [DirDiff::ZERO; 3]
            )
            .0,
            z
        );
        let (rr, _) = z.refract(
            UnitVec(d),
            UnitVec(n),
            [DirDiff::ZERO; 3],
            [DirDiff::ZERO; 3],
            Eta::from_num(1),
            I2F30::ZERO,
        );
        assert_eq!(rr, z);
        // Extremes saturate with the flag, never panic.
        let big = RayDiff {
            dodx: [PosDiff::MAX; 3],
            dody: [PosDiff::MIN; 3],
            dddx: [DirDiff::MAX; 3],
            dddy: [DirDiff::MIN; 3],
        };
        let zero = [I2F30::ZERO; 3];
        assert!(
            big.transfer(UnitVec(zero), PathLength::MAX, UnitVec(zero))
                .1
        );
        for v in [[I2F30::MAX; 3], [I2F30::MIN; 3], zero] {
            let _ = big.transfer(UnitVec(v), PathLength::MAX, UnitVec(v));
            let _ = big.reflect(UnitVec(v), UnitVec(v), [DirDiff::MAX; 3], [DirDiff::MIN; 3]);
            let _ = big.refract(
                UnitVec(v),
                UnitVec(v),
                [DirDiff::MAX; 3],
                [DirDiff::MIN; 3],
                Eta::MAX,
                I2F30::MIN,
            );
            let _ = big.refract(
                UnitVec(v),
                UnitVec(v),
                [DirDiff::MIN; 3],
                [DirDiff::MAX; 3],
                Eta::MIN,
                I2F30::MAX,
            );
            let _ = RayDiff::primary(UnitVec(v), UnitVec(v), [DirDiff::MAX; 3], [DirDiff::MIN; 3]);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3_000))]

        /// Transfer, reflection and refraction against f64 of the same
        /// (quantised) inputs: position differentials within
        /// `2⁻²⁴ + 2⁻²⁹/|D·n|` relative (+ `2⁻²⁸ + 2⁻³⁰/|D·n|` absolute), reflected
        /// direction differentials within 2⁻²⁶ of the input magnitudes (+ 8
        /// LSB), refracted ones within `2⁻²²/cos θₜ` (+ 16 LSB).
        #[test]
        fn operations_match_f64(
            d in unit(), n in unit(), f in unit(),
            ox in [-1.0..1.0f64, -1.0..1.0, -1.0..1.0],
            dx in [-1.0..1.0f64, -1.0..1.0, -1.0..1.0],
            nx in [-1.0..1.0f64, -1.0..1.0, -1.0..1.0],
            so in -20i32..8, sd in -16i32..-2, sn in -16i32..0,
            t in 1.0e-3..1.0e3f64,
            eta in 0.4..2.5f64,
        ) {
            let (so, sd, sn) = (2f64.powi(so), 2f64.powi(sd), 2f64.powi(sn));
            let dq = df(uq(d));
            let nq = df(uq(n));
            let o = pf(ox.map(|x| PosDiff::from_num(x * so)));
            let dd = df(uq(dx.map(|x| x * sd)));
            let dn = df(uq(nx.map(|x| x * sn)));
            let tq = PathLength::from_num(t);
            let s = RayDiff {
                dodx: o.map(PosDiff::from_num),
                dody: [PosDiff::ZERO; 3],
                dddx: uq(dd),
                dddy: [DirDiff::ZERO; 3],
            };
            // Transfer.
            let cos = dot(dq, nq).abs();
            prop_assume!(cos > 1e-3);
            let (r, sat) = s.transfer(UnitVec(uq(dq)), tq, UnitVec(uq(nq)));
            let want = transfer_f64(o, dd, dq, tq.to_num(), nq);
            let mag = want.iter().chain(&o).fold(0.0f64, |m, x| m.max(x.abs())) + sd * t / cos;
            prop_assert!(!sat);
            // D·n is resolved to 2⁻³⁰: relative error up to 2⁻²⁹/|D·n| near grazing.
            let rel = 2f64.powi(-24) + 2f64.powi(-29) / cos;
            // q is rounded to 2⁻³³ per component; ∂t amplifies that by 1/|D·n|.
            let abs = 2f64.powi(-28) + 2f64.powi(-30) / cos;
            prop_assert!(close(pf(r.dodx), want, mag * rel + abs),
                "transfer {:?} vs {:?}", pf(r.dodx), want);
            // Reflection (Igehy eq. 14–15).
            let (r, _) = s.reflect(UnitVec(uq(dq)), UnitVec(uq(nq)), uq(dn), [DirDiff::ZERO; 3]);
            let dnd = dot(dq, nq);
            let ddn = dot(dd, nq) + dot(dq, dn);
            let want: V = core::array::from_fn(|k| dd[k] - 2.0 * (dnd * dn[k] + ddn * nq[k]));
            let tol = (sd + sn) * 2f64.powi(-26) + 8.0 * 2f64.powi(-30);
            prop_assume!(want.iter().all(|x| x.abs() < 1.99));
            prop_assert!(close(df(r.dddx), want, tol), "reflect {:?} vs {:?}", df(r.dddx), want);
            // Refraction, with n facing the ray.
            let nf = if dnd > 0.0 { nq.map(|x| -x) } else { nq };
            let dnf = if dnd > 0.0 { dn.map(|x| -x) } else { dn };
            let cosi = -dot(dq, nf);
            let etaq = Eta::from_num(eta).to_num::<f64>();
            let k = 1.0 - etaq * etaq * (1.0 - cosi * cosi);
            if k > 1e-2 {
                let ct = I2F30::from_num(k.sqrt());
                let ctf = ct.to_num::<f64>();
                let (r, sat) = s.refract(UnitVec(uq(dq)), UnitVec(uq(nf)), uq(dnf), [DirDiff::ZERO; 3], Eta::from_num(eta), ct);
                let mu = etaq * cosi - ctf;
                let dcos = -(dot(dd, nf) + dot(dq, dnf));
                let dmu = (etaq - etaq * etaq * cosi / ctf) * dcos;
                let want: V = core::array::from_fn(|k| etaq * dd[k] + dmu * nf[k] + mu * dnf[k]);
                if !sat {
                    let tol = (sd + sn) * 2f64.powi(-22) / ctf + 16.0 * 2f64.powi(-30);
                    prop_assert!(close(df(r.dddx), want, tol), "refract {:?} vs {:?}", df(r.dddx), want);
            }
            }
            // Primary set-up.
            let g = sd;
            let rq = df(uq([g, 0.0, 0.0]));
            let (p, _) = RayDiff::primary(UnitVec(uq(dq)), UnitVec(uq(f)), uq(rq), uq(rq));
            let dr = dot(dq, rq);
            let want: V = core::array::from_fn(|k| dot(dq, f) * (rq[k] - dr * dq[k]));
            prop_assert!(close(df(p.dddx), want, 4.0 * 2f64.powi(-30)), "primary {:?} vs {:?}", df(p.dddx), want);
        }
    }
}
