//! Fixed-point `log2` variants that trade table size and bits for time,
//! set against the firmware's accurate path (64-entry table with linear
//! interpolation, error 2⁻¹³) in the `tradeoff` LOD rows. Each takes the
//! raw bits of a U32F32 (`x > 0`; 0 is read as 2⁻³²) and returns `log2 x`
//! in I16F16 bits. Written here from the definitions; not firmware code.
//!
//! | variant | table | interpolation | error of `log2` |
//! |---|---|---|---|
//! | [`Log2Fx::Lut16Lerp`] | 17 entries | linear, 12-bit weight | ≤ `1/(8·16²·ln 2)` ≈ 7.1·10⁻⁴ |
//! | [`Log2Fx::Lut256`] | 256 entries (interval midpoints) | none | ≤ `1/(2·256·ln 2)` ≈ 2.8·10⁻³ |
//! | [`Log2Fx::Mitchell`] | none | `log2(1 + f) ≈ f` | ≤ 0.0861 |

/// A `log2` variant (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Log2Fx {
    /// 16 intervals, chord interpolation.
    Lut16Lerp,
    /// 256 intervals, one read, no interpolation.
    Lut256,
    /// No table: the mantissa fraction itself (Mitchell 1962).
    Mitchell,
}

/// The tables of the variants (built once, in I16F16 bits).
#[derive(Clone, Debug)]
pub struct Log2Tables {
    lut16: [i32; 17],
    lut256: [i32; 256],
}

impl Default for Log2Tables {
    fn default() -> Self {
        let q = |x: f64| (x * 65536.0).round() as i32;
        Self {
            lut16: std::array::from_fn(|i| q((1.0 + i as f64 / 16.0).log2())),
            lut256: std::array::from_fn(|i| q((1.0 + (i as f64 + 0.5) / 256.0).log2())),
        }
    }
}

/// Name of a variant in the tables and charts.
#[must_use]
pub fn name(v: Log2Fx) -> &'static str {
    match v {
        Log2Fx::Lut16Lerp => "fixed lut16+lerp",
        Log2Fx::Lut256 => "fixed lut256",
        Log2Fx::Mitchell => "fixed mitchell",
    }
}

impl Log2Tables {
    /// `log2` of the U32F32 bits `x` in I16F16 bits with variant `v`.
    #[inline(always)]
    #[must_use]
    pub fn log2(&self, v: Log2Fx, x: u64) -> i32 {
        let x = x.max(1);
        let lz = x.leading_zeros();
        // Integer part: bit 63 − lz of a value with 32 fractional bits.
        let e = 31 - lz as i32;
        // Mantissa fraction, 32 bits below the leading one.
        let f = ((x << lz) << 1 >> 32) as u32;
        let frac = match v {
            Log2Fx::Mitchell => (f >> 16) as i32,
            Log2Fx::Lut256 => self.lut256[(f >> 24) as usize],
            Log2Fx::Lut16Lerp => {
                let i = (f >> 28) as usize;
                let w = ((f >> 16) & 0xFFF) as i32;
                let (a, b) = (self.lut16[i], self.lut16[i + 1]);
                a + (((b - a) * w + 0x800) >> 12)
            }
        };
        (e << 16) + frac
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_variant_within_its_bound() {
        let t = Log2Tables::default();
        let bounds = [
            (Log2Fx::Lut16Lerp, 7.2e-4),
            (Log2Fx::Lut256, 2.9e-3),
            (Log2Fx::Mitchell, 0.0862),
        ];
        let mut r = raymip::rng::XorShift64(0x9E37_79B9_7F4A_7C15);
        for (v, bound) in bounds {
            let mut worst = 0.0f64;
            for _ in 0..20_000 {
                let x = (r.next_u64() >> (r.next_u64() % 60)).max(1);
                let exact = (x as f64 / 2f64.powi(32)).log2();
                let got = f64::from(t.log2(v, x)) / 65536.0;
                worst = worst.max((got - exact).abs());
            }
            // Plus the 2⁻¹⁷ output rounding.
            assert!(worst <= bound + 2f64.powi(-16), "{v:?}: {worst}");
            assert!(worst > bound / 8.0, "{v:?}: {worst} (bound not approached)");
        }
    }
}
