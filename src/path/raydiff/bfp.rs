//! Block floating point for the ray differentials: a 3-vector of 32-bit
//! mantissas with one exponent, and the 32-bit kernels the differential
//! operations are made of (multiply-high, alignment, normalisation, the
//! reciprocal by one division and a Newton step).
//!
//! A vector `(m₀, m₁, m₂; e)` stands for `mₖ·2ᵉ`. Normalised: the largest
//! `|mₖ|` lies in `[2³⁰ − 1, 2³¹]` (`mₖ ^ (mₖ >> 31)` has one leading zero),
//! or every `mₖ = 0` with `e` = [`EXP_MIN`]. Truncating a normalised vector
//! to `2ᵉ` costs less than `2⁻²⁹·(1 + 2⁻³⁰)` of its largest component.

use crate::log2::clz32;

/// Smallest exponent (that of the zero vector): `−2¹⁴`.
pub const EXP_MIN: i32 = -(1 << 14);
/// Largest exponent: `2¹⁴ − 1`. A vector there is beyond every lod (the
/// lod saturates at `Lod::MAX` long before); nothing larger is
/// represented. (`[EXP_MIN, EXP_MAX]` is one `ssat` on the Cortex-M4.)
pub const EXP_MAX: i32 = (1 << 14) - 1;

/// `⌊a·b / 2³²⌋` (one `smmul` on the Cortex-M4, one `mulh` on RV32).
#[inline(always)]
#[must_use]
pub(crate) fn mulhi(a: i32, b: i32) -> i32 {
    ((i64::from(a) * i64::from(b)) >> 32) as i32
}

/// `⌊a·b / 2³²⌋` unsigned (`umull` / `mulhu`).
#[inline(always)]
#[must_use]
pub(crate) fn mulhi_u(a: u32, b: u32) -> u32 {
    ((u64::from(a) * u64::from(b)) >> 32) as u32
}

/// `Σ aₖ·bₖ` in 64 bits (`smull` + two `smlal`): exact when `|Σ| < 2⁶³`,
/// which holds whenever one side has components of magnitude at most
/// `2³⁰` (a unit vector in I2F30); wrapping otherwise (inputs outside
/// every documented range).
#[inline(always)]
#[must_use]
pub(crate) fn dot64(a: [i32; 3], b: [i32; 3]) -> i64 {
    (i64::from(a[0]) * i64::from(b[0]))
        .wrapping_add(i64::from(a[1]) * i64::from(b[1]))
        .wrapping_add(i64::from(a[2]) * i64::from(b[2]))
}

/// `x >> s` for any `s ≥ 0` (`s ≥ 31` gives the sign: `0` or `−1`); the
/// shift count saturates in one `usat`.
#[inline(always)]
#[must_use]
pub(crate) fn shr(x: i32, s: i32) -> i32 {
    x >> s.clamp(0, 31)
}

/// `≈ 2⁶²/x` for `x ∈ [2³¹, 2³²)`, in `[2³⁰, 2³¹)`, within `3·2⁻³⁰`
/// relative: one 32/16-bit division (`udiv` / `divu`, relative error
/// `< 2⁻¹⁵`) and one Newton step, which squares that error (`< 2⁻³⁰`), and
/// two truncations.
///
/// Below `2³¹` without a clamp: the exact Newton step `y(2 − x·y/2⁶²)`
/// never exceeds `2⁶²/x` whatever the start `y` (the difference is
/// `x·(2⁶²/x − y)²/2⁶²`), the truncated `p` raises it by at most
/// `q/2³⁰ < 2`, and `2⁶²/x + 2 < 2³¹` for `x > 2³¹ + 2`; the three smaller
/// `x` give `2³¹ − 1` (tested).
#[inline(always)]
#[must_use]
pub(crate) fn recip(x: u32) -> u32 {
    // x >> 16 ∈ [2¹⁵, 2¹⁶); the `| 0x8000` (no change) shows the divisor
    // is not zero, so no check remains.
    let q = (u32::MAX / ((x >> 16) | 0x8000)) << 14;
    // q < 2⁶²/x·(1 + 2⁻¹⁵): p = x·q/2³² ≤ 2³⁰, 2³¹ − p ∈ [2³⁰, 2³¹).
    let p = mulhi_u(x, q);
    mulhi_u(q << 1, (0x8000_0000 - p) << 1)
}

/// A normalised block-floating-point 3-vector (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Bfp3 {
    /// Mantissas.
    pub m: [i32; 3],
    /// Exponent of the mantissas' unit.
    pub e: i32,
}

impl Bfp3 {
    /// The zero vector.
    pub const ZERO: Self = Self {
        m: [0; 3],
        e: EXP_MIN,
    };

    /// `m·2ᵉ` normalised, for any mantissas and `|e| ≤ 2¹⁷` (every
    /// caller's exponent is within `2¹⁶`); the exponent saturates at
    /// [`EXP_MIN`], [`EXP_MAX`].
    #[inline(always)]
    #[must_use]
    pub fn new(m: [i32; 3], e: i32) -> Self {
        let ([m], e) = normalise([m], e);
        Self { m, e }
    }

    /// [`Bfp3::new`] (bit for bit) for `e ∈ [EXP_MIN + 31, EXP_MAX]`,
    /// where no clamp is needed: a zero vector selects [`EXP_MIN`]. For a
    /// constant `e`, one selected constant costs less than the clamp the
    /// pushed exponent of [`Bfp3::new`] would keep.
    #[inline(always)]
    #[must_use]
    pub fn new_in_range(m: [i32; 3], e: i32) -> Self {
        let ([m], e) = normalise_in_range([m], e);
        Self { m, e }
    }

    /// `m·2ᵉ` from 64-bit mantissas, truncated to 31 significant bits of
    /// the largest (any `e`: it saturates).
    #[must_use]
    pub fn from_wide(m: [i64; 3], e: i32) -> Self {
        let s = wide_shift(m);
        Self::new(
            m.map(|x| (x >> s) as i32),
            e.clamp(2 * EXP_MIN, 2 * EXP_MAX) + s,
        )
    }
}

/// `N` vectors `m·2ᵉ` normalised together (one exponent, the largest
/// mantissa of all `3N` with one leading zero), for any mantissas and
/// `|e| ≤ 2¹⁷`; the exponent saturates at [`EXP_MIN`], [`EXP_MAX`] (all
/// zero: [`EXP_MIN`]). `N = 1` is [`Bfp3::new`]; `N = 2` a
/// [`Bfp3x2`](Bfp3x2::new).
#[inline(always)]
#[must_use]
pub(crate) fn normalise<const N: usize>(m: [[i32; 3]; N], e: i32) -> ([[i32; 3]; N], i32) {
    let o = m.iter().fold(0, |o, v| o | sign_changes(*v));
    let s = shift_of(o);
    let zero = o == 0;
    // Bit for bit the same; the cheaper per target (the Cortex-M4
    // subtracts conditionally; on RV32 a pushed exponent costs more).
    #[cfg(target_arch = "arm")]
    let e = exp_pushed(e - s, zero);
    #[cfg(not(target_arch = "arm"))]
    let e = exp_selected(e - s, zero);
    (m.map(|v| v.map(|x| x << s)), e)
}

/// [`normalise`] (bit for bit) for `e ∈ [EXP_MIN + 31, EXP_MAX]`, where no
/// clamp is needed: all zero selects [`EXP_MIN`].
#[inline(always)]
#[must_use]
fn normalise_in_range<const N: usize>(m: [[i32; 3]; N], e: i32) -> ([[i32; 3]; N], i32) {
    let o = m.iter().fold(0, |o, v| o | sign_changes(*v));
    let s = shift_of(o);
    let e = if o == 0 { EXP_MIN } else { e - s };
    (m.map(|v| v.map(|x| x << s)), e)
}

/// `x ^ (x << 1)`: bit `i` is set where bits `i` and `i − 1` of `x`
/// differ, so its leading zeros are one less than the leading sign bits
/// of `x` (31 for `−1`), and it is zero exactly for `x = 0`.
#[inline(always)]
fn sign_change(x: i32) -> u32 {
    (x ^ (x << 1)) as u32
}

/// The OR of [`sign_change`] over the mantissas `m`: its leading zeros are
/// one less than the fewest leading sign bits of a non-zero mantissa (the
/// largest magnitude's), and it is zero exactly when every mantissa is
/// zero, so one value gives both the shift ([`shift_of`]) and the zero
/// test.
#[inline(always)]
fn sign_changes(m: [i32; 3]) -> u32 {
    sign_change(m[0]) | sign_change(m[1]) | sign_change(m[2])
}

/// The left shift that gives the largest magnitude of mantissas whose
/// [`sign_changes`] are `o` one leading zero (one sign bit):
/// `clz(o) ∈ [0, 31]` for any non-zero mantissa, 31 when all are zero
/// (`| 1`; they stay zero).
#[inline(always)]
fn shift_of(o: u32) -> i32 {
    clz32(o | 1) as i32
}

/// The left shift that normalises the mantissas `m`: the largest
/// magnitude gets one leading zero (`m ^ (m >> 31)` below `2³¹`, at least
/// `2³⁰`), 31 for a zero vector (which stays zero).
#[inline(always)]
#[must_use]
pub(crate) fn norm_shift(m: [i32; 3]) -> i32 {
    shift_of(sign_changes(m))
}

/// The left shift that normalises the scalars `a`, `b` together (the
/// larger magnitude gets one leading zero; both zero: 31).
#[inline(always)]
#[must_use]
pub(crate) fn norm_shift2(a: i32, b: i32) -> i32 {
    shift_of(sign_change(a) | sign_change(b))
}

/// Two block-floating-point 3-vectors with one exponent (the `x` and `y`
/// differentials of one quantity): `m[a]·2ᵉ`, the largest of the six
/// `|mₖ|` in `[2³⁰ − 1, 2³¹]`, or all zero at [`EXP_MIN`]. The smaller
/// vector keeps the absolute precision of the larger (a unit of at most
/// `2⁻²⁹·(1 + 2⁻³⁰)` of the larger's largest component), not its own
/// relative one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct Bfp3x2 {
    /// Mantissas of the two vectors.
    pub m: [[i32; 3]; 2],
    /// Exponent of their unit.
    pub e: i32,
}

impl Bfp3x2 {
    /// `m[a]·2ᵉ` normalised together (as [`Bfp3::new`], any mantissas,
    /// `|e| ≤ 2¹⁷`, the exponent saturating).
    #[inline(always)]
    #[must_use]
    pub fn new(m: [[i32; 3]; 2], e: i32) -> Self {
        let (m, e) = normalise(m, e);
        Self { m, e }
    }

    /// The pair of vectors `m[a]·2^e[a]` (each `|mₖ| ≤ 2³¹`, `|e[a]| ≤
    /// 2¹⁷`) at the larger exponent, the other one's mantissas truncated
    /// (by less than one unit of the larger exponent), then normalised.
    #[inline(always)]
    #[must_use]
    pub fn aligned(m: [[i32; 3]; 2], e: [i32; 2]) -> Self {
        let top = e[0].max(e[1]);
        Self::new([0, 1].map(|a| m[a].map(|x| shr(x, top - e[a]))), top)
    }

    /// [`Bfp3x2::new`] (bit for bit) for `e ∈ [EXP_MIN + 31, EXP_MAX]`
    /// (no clamp: all zero selects [`EXP_MIN`]), as
    /// [`Bfp3::new_in_range`].
    #[inline(always)]
    #[must_use]
    pub fn new_in_range(m: [[i32; 3]; 2], e: i32) -> Self {
        let (m, e) = normalise_in_range(m, e);
        Self { m, e }
    }

    /// Vector `a` (0 or 1) normalised on its own (exact).
    #[inline(always)]
    #[must_use]
    pub fn get(&self, a: usize) -> Bfp3 {
        Bfp3::new(self.m[a & 1], self.e)
    }
}

/// `e` clamped to [`EXP_MIN`, `EXP_MAX`], or [`EXP_MIN`] for a zero
/// vector, for `|e| ≤ 2¹⁷ + 31`: a zero vector's exponent is pushed 2¹⁸
/// below, where the clamp gives EXP_MIN (on the Cortex-M4 a conditional
/// subtract of an immediate, where EXP_MIN is a constant to load).
#[inline(always)]
#[must_use]
#[cfg_attr(
    not(target_arch = "arm"),
    allow(
        dead_code,
        reason = "the Cortex-M4's form: tested on the host against exp_selected"
    )
)]
pub(crate) fn exp_pushed(e: i32, zero: bool) -> i32 {
    let e = if zero { e - (1 << 18) } else { e };
    e.clamp(EXP_MIN, EXP_MAX)
}

/// [`exp_pushed`] (same value) with EXP_MIN selected after the clamp, for
/// any `e`.
#[inline(always)]
#[must_use]
#[cfg_attr(
    target_arch = "arm",
    allow(
        dead_code,
        reason = "the RV32 form: tested on the host against exp_pushed"
    )
)]
pub(crate) fn exp_selected(e: i32, zero: bool) -> i32 {
    // Both made, then one selected (no branch: the caller's block
    // continues, and values it made stay in 32-bit registers).
    let e = e.clamp(EXP_MIN, EXP_MAX);
    if zero { EXP_MIN } else { e }
}

/// The right shift that leaves 64-bit mantissas `m` within 32 bits, the
/// largest with 31 significant bits (0 when they fit already).
#[inline(always)]
#[must_use]
pub(crate) fn wide_shift(m: [i64; 3]) -> i32 {
    let o = (m[0] ^ (m[0] >> 63)) | (m[1] ^ (m[1] >> 63)) | (m[2] ^ (m[2] >> 63));
    (64 - o.leading_zeros() as i32 - 31).max(0)
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use proptest::prelude::*;

    fn value(v: Bfp3) -> [f64; 3] {
        v.m.map(|m| f64::from(m) * f64::from(v.e).exp2())
    }

    #[test]
    fn normalisation_edges() {
        assert_eq!(Bfp3::new([0; 3], 5), Bfp3::ZERO);
        let v = Bfp3::new([1, 0, -1], 0);
        assert_eq!((v.m, v.e), ([1 << 30, 0, -(1 << 30)], -30));
        let v = Bfp3::new([i32::MIN, 0, 0], 0);
        assert_eq!((v.m, v.e), ([i32::MIN, 0, 0], 0));
        let v = Bfp3::new([-(1 << 30), 0, 0], 0);
        assert_eq!((v.m, v.e), ([i32::MIN, 0, 0], -1));
        assert_eq!(Bfp3::new([1, 1, 1], EXP_MAX + 100).e, EXP_MAX);
        assert_eq!(Bfp3::new([1, 1, 1], EXP_MIN - 100).e, EXP_MIN);
        assert_eq!(Bfp3::new([1, 1, 1], EXP_MIN).e, EXP_MIN);
        // The documented saturation points, ±2¹⁴ (one `ssat #15`), as
        // numbers: the constants themselves are what is checked.
        assert_eq!(Bfp3::new([1, 1, 1], 1 << 17).e, (1 << 14) - 1);
        assert_eq!(Bfp3::new([1, 1, 1], -(1 << 17)).e, -(1 << 14));
        assert_eq!(Bfp3::ZERO.e, -(1 << 14));
        assert_eq!(Bfp3::from_wide([i64::MIN, 0, 1], 0).m[0], i32::MIN);
        assert_eq!(shr(-5, 40), -1);
        assert_eq!(shr(5, -3), 5);
    }

    #[test]
    fn reciprocal_bound_at_the_ends_and_powers_of_two() {
        let mut xs: std::vec::Vec<u32> = std::vec![1 << 31, u32::MAX, (1 << 31) + 1, (1 << 31) + 2];
        // The three below 2³¹ + 3, where the documented argument does not
        // hold, give 2³¹ − 1 (hand-run Newton step at x = 2³¹:
        // q = (2¹⁷ − 1)·2¹⁴, p = 2³⁰ − 2¹³, y = ⌊(2⁶³ − 2²⁹)/2³²⌋).
        for x in [1 << 31, (1 << 31) + 1, (1 << 31) + 2] {
            assert_eq!(recip(x), 0x7FFF_FFFF, "{x}");
        }
        for k in 0..31 {
            xs.push((1u32 << 31) | (1 << k));
            xs.push(u32::MAX - (1 << k));
        }
        for x in xs {
            let y = recip(x);
            let want = 2f64.powi(62) / f64::from(x);
            let rel = (want - f64::from(y)) / want;
            assert!(
                rel.abs() <= 3.0 * 2f64.powi(-30),
                "{x}: {y} vs {want} ({rel:e})"
            );
            assert!((1 << 30..1 << 31).contains(&y));
        }
    }

    /// Mantissas with zero, equal and bit-disjoint components as often as
    /// any (the zero vector among them), so that a zero test that is not
    /// exactly "all three zero" shows.
    fn mantissas() -> impl Strategy<Value = [i32; 3]> {
        let c = prop_oneof![Just(0), Just(1), Just(2), Just(-1), any::<i32>()];
        [c.clone(), c.clone(), c]
    }

    /// The two zero-exponent forms agree over all of `exp_pushed`'s range
    /// (every exponent, both flags).
    #[test]
    fn exponent_forms_agree() {
        let r = (1 << 17) + 31;
        for e in -r..=r {
            for zero in [false, true] {
                assert_eq!(exp_pushed(e, zero), exp_selected(e, zero), "{e} {zero}");
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]

        #[test]
        fn in_range_normalises_as_new(m in mantissas(), e in EXP_MIN + 31..=EXP_MAX) {
            prop_assert_eq!(Bfp3::new_in_range(m, e), Bfp3::new(m, e));
        }

        #[test]
        fn reciprocal_within_its_bound(x in (1u32 << 31)..=u32::MAX) {
            let y = recip(x);
            let want = 2f64.powi(62) / f64::from(x);
            let rel = (want - f64::from(y)) / want;
            prop_assert!(rel.abs() <= 3.0 * 2f64.powi(-30), "{} vs {} ({:e})", y, want, rel);
        }

        #[test]
        fn normalise_keeps_the_value(m in mantissas(), e in -1000i32..1000) {
            let v = Bfp3::new(m, e);
            let want = m.map(|x| f64::from(x) * f64::from(e).exp2());
            prop_assert_eq!(value(v), want);
            let top = v.m.iter().map(|x| x ^ (x >> 31)).fold(0, |o, x| o | x);
            prop_assert!(m == [0; 3] || top.leading_zeros() == 1);
        }

        /// A pair normalised together keeps both values exactly, the
        /// larger magnitude of the six with one leading zero, and agrees
        /// with its in-range form and (for one vector) with `Bfp3::new`.
        #[test]
        fn pair_normalises_together(a in mantissas(), b in mantissas(), e in -1000i32..1000) {
            let p = Bfp3x2::new([a, b], e);
            prop_assert_eq!(p, Bfp3x2::new_in_range([a, b], e));
            for (m, v) in [(a, p.m[0]), (b, p.m[1])] {
                let want = m.map(|x| f64::from(x) * f64::from(e).exp2());
                prop_assert_eq!(value(Bfp3 { m: v, e: p.e }), want);
            }
            let top = p.m.iter().flatten().map(|x| x ^ (x >> 31)).fold(0, |o, x| o | x);
            prop_assert!(([a, b] == [[0; 3]; 2] && p.e == EXP_MIN) || top.leading_zeros() == 1);
            // Each vector on its own: exact, normalised as Bfp3::new.
            prop_assert_eq!(p.get(0), Bfp3::new(p.m[0], p.e));
            prop_assert_eq!(p.get(1), Bfp3::new(b, e));
            prop_assert_eq!(Bfp3x2::new([a, [0; 3]], e).m[0], Bfp3::new(a, e).m);
            prop_assert_eq!(Bfp3x2::new([a, [0; 3]], e).e, Bfp3::new(a, e).e);
        }

        /// Aligned: the vector at the larger exponent exact, the other
        /// truncated by less than one unit of the larger exponent.
        #[test]
        fn aligned_truncates_below_the_larger_unit(a in mantissas(), b in mantissas(),
                                                   ea in -900i32..900, eb in -900i32..900) {
            let p = Bfp3x2::aligned([a, b], [ea, eb]);
            let unit = f64::from(ea.max(eb)).exp2();
            for (m, e, v) in [(a, ea, p.m[0]), (b, eb, p.m[1])] {
                let got = value(Bfp3 { m: v, e: p.e });
                for k in 0..3 {
                    let want = f64::from(m[k]) * f64::from(e).exp2();
                    let err = want - got[k];
                    // Below one unit (at most one in f64, whose sum may round up).
                    prop_assert!((0.0..=unit).contains(&err), "{} vs {}", got[k], want);
                    if e == ea.max(eb) {
                        prop_assert_eq!(err, 0.0);
                    }
                }
            }
        }

        #[test]
        fn wide_truncates_below_a_unit(m in any::<[i64; 3]>(), e in -1000i32..900) {
            let v = Bfp3::from_wide(m, e);
            let top = m.iter().map(|x| x.unsigned_abs()).max().unwrap_or(0) as f64;
            for (&mk, got) in m.iter().zip(value(v)) {
                let want = mk as f64 * f64::from(e).exp2();
                prop_assert!((got - want).abs() <= 2f64.powi(-29) * top * f64::from(e).exp2() + 1e-300);
            }
        }
    }
}
