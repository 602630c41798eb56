//! f64 lods of the firmware's methods, written from their definitions
//! (the formulas of the firmware's `lod` and `lod::raydiff` module docs),
//! with the firmware's documented clamps.

/// Smallest cone width the firmware represents (its raw unit): 2⁻³²; a
/// zero width reads as this.
pub const MIN_WIDTH: f64 = 1.0 / 4_294_967_296.0;

/// Smallest `|n·d|` of the cone's normal term: 2⁻¹⁶ (the firmware's
/// `MIN_COS`).
pub const MIN_COS: f64 = 1.0 / 65_536.0;

/// Table method (Park et al. 2011): `lod = log2 Pl − log2 Pb` for a path
/// length `pl > 0`.
#[must_use]
pub fn table(pl: f64, log2_pb: f64) -> f64 {
    pl.log2() - log2_pb
}

/// Ray cones (Ray Tracing Gems ch. 20): `lod = Δ + log2 |w| − log2 |n·d|`
/// with `Δ` the triangle's constant, `|w|` the cone width clamped to at
/// least [`MIN_WIDTH`], and the normal term (when given) `|n·d|` clamped
/// to `[MIN_COS, 1]`.
#[must_use]
pub fn cone(delta: f64, width: f64, n_dot_d: Option<f64>) -> f64 {
    let normal = n_dot_d.map_or(0.0, |c| c.abs().clamp(MIN_COS, 1.0).log2());
    delta + width.abs().max(MIN_WIDTH).log2() - normal
}

/// Ray differentials (Igehy 1999): `log2` of the longer texel-space
/// footprint axis, for axes `[x, y]` in texture coordinates per pixel on a
/// level 0 of `size = (width, height)` texels; a zero footprint reads as
/// the smallest positive f64.
#[must_use]
pub fn footprint(axes: [[f64; 2]; 2], size: (f64, f64)) -> f64 {
    let len = |a: [f64; 2]| ((a[0] * size.0).powi(2) + (a[1] * size.1).powi(2)).sqrt();
    len(axes[0]).max(len(axes[1])).max(1e-300).log2()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formulas_at_known_points() {
        assert_eq!(table(8.0, 1.0), 2.0);
        assert_eq!(cone(-3.0, 0.5, None), -4.0);
        assert_eq!(cone(-3.0, -0.5, Some(0.25)), -2.0);
        assert_eq!(cone(0.0, 0.0, Some(0.0)), -32.0 + 16.0);
        assert_eq!(footprint([[0.5, 0.0], [0.0, 0.25]], (16.0, 16.0)), 3.0);
        assert_eq!(footprint([[0.0; 2]; 2], (1.0, 1.0)), 1e-300f64.log2());
    }
}
