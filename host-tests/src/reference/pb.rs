//! f64 `log2 Pb` of a textured triangle (Park et al. 2011 with the
//! derivation in the firmware's `table` module), written without the
//! firmware.

use crate::scene::{V3, v};

/// f64 `log2 Pb = ½·log2(A/N) − log2 γ` (independent of the firmware).
#[must_use]
pub fn log2_pb_f64(p: &[V3; 3], uv: &[[f64; 2]; 3], w: u32, h: u32, gamma: f64) -> f64 {
    let a = 0.5 * v::len(v::cross(v::sub(p[1], p[0]), v::sub(p[2], p[0])));
    let n = 0.5
        * ((uv[1][0] - uv[0][0]) * (uv[2][1] - uv[0][1])
            - (uv[1][1] - uv[0][1]) * (uv[2][0] - uv[0][0]))
            .abs()
        * f64::from(w)
        * f64::from(h);
    0.5 * (a / n).log2() - gamma.log2()
}
