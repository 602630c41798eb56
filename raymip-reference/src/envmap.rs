//! f64 environment-map lod and latitude-longitude mapping (Ray Tracing Gems
//! ch. 21, with the formulas of the firmware's `lod::envmap` module docs),
//! written without the firmware.

use core::f64::consts::PI;

/// Smallest `cos φ` of the pole term (the firmware's `MIN_COS_LAT`): 2⁻¹⁶.
const MIN_COS_LAT: f64 = 1.0 / 65_536.0;

/// `log2 α + max(log2(W/2π) − log2 cos φ, log2(H/π))` for an angular
/// footprint `alpha` (radians; 0 reads as 2⁻³⁰, the firmware's raw unit)
/// on a `w × h` latitude-longitude map; the pole term from direction `d`
/// (`cos φ = √(x² + z²)` clamped to `[2⁻¹⁶, 1]`) when given.
#[must_use]
pub fn lod_f64(w: u32, h: u32, alpha: f64, d: Option<[f64; 3]>) -> f64 {
    let alpha = alpha.abs().max(2f64.powi(-30));
    let pole = d.map_or(0.0, |d| {
        -(d[0] * d[0] + d[2] * d[2])
            .sqrt()
            .clamp(MIN_COS_LAT, 1.0)
            .log2()
    });
    let lu = (f64::from(w) / (2.0 * PI)).log2() + pole;
    let lv = (f64::from(h) / PI).log2();
    alpha.log2() + lu.max(lv)
}

/// Cone lod: `α = |γ|`, the cone's spread angle (radians).
#[must_use]
pub fn cone_lod_f64(w: u32, h: u32, spread: f64, d: Option<[f64; 3]>) -> f64 {
    lod_f64(w, h, spread, d)
}

/// Ray-differential lod: `α = max(|∂D/∂x|, |∂D/∂y|)`.
#[must_use]
pub fn raydiff_lod_f64(w: u32, h: u32, dddx: [f64; 3], dddy: [f64; 3], d: Option<[f64; 3]>) -> f64 {
    let len = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    lod_f64(w, h, len(dddx).max(len(dddy)), d)
}

/// `(u, v) = (½ + atan2(x, −z)/2π, ½ − atan2(y, √(x² + z²))/π)`, `+y` up;
/// `(½, ½)` for the zero vector.
#[must_use]
pub fn direction_uv_f64(d: [f64; 3]) -> (f64, f64) {
    let c = (d[0] * d[0] + d[2] * d[2]).sqrt();
    let lon = if c == 0.0 { 0.0 } else { d[0].atan2(-d[2]) };
    let lat = if c == 0.0 && d[1] == 0.0 {
        0.0
    } else {
        d[1].atan2(c)
    };
    (0.5 + lon / (2.0 * PI), 0.5 - lat / PI)
}
