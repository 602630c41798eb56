//! f64 `log2 Pb` of a textured triangle (Park et al. 2011 with the
//! derivation in the firmware's `setup::table` module), written without the
//! firmware.

/// f64 `log2 Pb = ½·log2(A/N) − log2 γ` of the triangle with world
/// positions `p` and UVs `uv` (texture repeats) on a `w × h` texture, for a
/// pixel spread angle `gamma` (radians). `A` is the world area, `N` the
/// number of texels covered. Independent of the firmware.
#[must_use]
pub fn log2_pb_f64(p: &[[f64; 3]; 3], uv: &[[f64; 2]; 3], w: f64, h: f64, gamma: f64) -> f64 {
    let e1 = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
    let e2 = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
    let c = [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ];
    let a = 0.5 * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
    let n = 0.5
        * ((uv[1][0] - uv[0][0]) * (uv[2][1] - uv[0][1])
            - (uv[1][1] - uv[0][1]) * (uv[2][0] - uv[0][0]))
            .abs()
        * w
        * h;
    0.5 * (a / n).log2() - gamma.log2()
}
