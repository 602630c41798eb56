//! Texture-space footprint of a hit from its ray differentials: the
//! barycentric differentials of the transferred `∂P = ∂O'`
//! ([`crate::path::raydiff::RayDiff::transfer`]), mapped through the triangle's UVs to
//! `(∂u/∂x, ∂v/∂x), (∂u/∂y, ∂v/∂y)` (pbrt's `dudx, dvdx, dudy, dvdy`, the
//! two axes [`crate::texture::sampler::aniso`] takes), and the lod as
//! `log2` of the larger axis in level-0 texels (the hardware paper's eq. 1).
//!
//! # Per-triangle constant
//!
//! With `e₁ = p₁ − p₀`, `e₂ = p₂ − p₀`, `N = e₁ × e₂`, the barycentric
//! differentials of a point differential `∂P` in the plane are
//! `∂b₁ = ∂P·(e₂ × N)/|N|²`, `∂b₂ = ∂P·(N × e₁)/|N|²`, so
//! `∂u = ∂P·G_u` with `G_u = ((u₁ − u₀)(e₂ × N) + (u₂ − u₀)(N × e₁))/|N|²`
//! (and `G_v` alike): [`RayDiffTriangle::new`] computes both once per
//! triangle in integer arithmetic (edges and UV edges rounded to 20
//! significant bits, 128-bit products, one division per component: relative
//! error below 2⁻¹⁸), I32F32 (normalized texture units per scene unit,
//! `±2³¹`, saturating). A hit then needs four 3-vector dot products.
//!
//! # Degenerate cases (as the table method's markers)
//!
//! * zero world area (`N = 0`): [`RayDiffTriangle::is_degenerate`]; the
//!   footprint is the largest one [`Footprint`] holds and the lod
//!   saturates high (coarsest stored level);
//! * zero UV extent: `G = 0`, footprint 0, lod saturates low (level 0);
//! * grazing hits: bounded by the transfer's clamp ([`crate::path::raydiff::MIN_COS`]).
//!
//! # Error bound
//!
//! [`RAYDIFF_LOD_MAX_ERROR`] `= 2⁻⁷` level against the same differentials
//! in f64 (the harness's tracer), for footprints whose larger axis is at
//! least `2⁻¹⁶` normalized units and hit states that did not saturate:
//! `G` within 2⁻¹⁸ relative, the dot products within 2⁻³² absolute
//! (`≤ 2⁻¹⁴` relative at that size), `log2` of the squared length within
//! 2⁻¹³ (halved), output rounding 2⁻⁹. Smaller footprints are below the
//! finest level of any texture up to 2¹⁶ texels wide and clamp to level 0.

use fixed::types::I32F32;

use crate::lod::log2::log2_bits_u128;
use crate::path::raydiff::PosDiff;
use crate::setup::table::TexTriangle;
use crate::units::{Coord, Footprint, Lod, TexCoord};

/// Documented error bound of [`RayDiffTriangle::lod`] against f64 ray
/// differentials, in levels: 2⁻⁷ (conditions in the [module docs](self)).
pub const RAYDIFF_LOD_MAX_ERROR: f64 = 1.0 / 128.0;

/// Per-triangle constant of the ray-differential footprint:
/// `G_u`, `G_v` (normalized texture units per scene unit, I32F32) and the
/// texture size. Built once per triangle by [`RayDiffTriangle::new`].
///
/// # Example
/// ```
/// use raymip::TexTriangle;
/// use raymip::path::raydiff::PosDiff;
/// use raymip::lod::raydiff::{RAYDIFF_LOD_MAX_ERROR, RayDiffTriangle};
/// // A wall at z = −100 with u = x, v = y, on a 256×256 texture.
/// let p = [[0.0, 0.0, -100.0], [1.0, 0.0, -100.0], [0.0, 1.0, -100.0]];
/// let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
/// let tri = RayDiffTriangle::new(&TexTriangle::from_f32(p, uv, 256, 256)?);
/// assert!(!tri.is_degenerate());
/// // A hit whose position moves 100·2⁻¹⁰ scene units per pixel in x and in y
/// // (as `RayDiff::transfer` gives for a 2⁻¹⁰ pixel spread at t = 100).
/// let (d, z) = (PosDiff::from_num(100.0 / 1024.0), PosDiff::ZERO);
/// let fp = tri.footprint([d, z, z], [z, d, z]);
/// // u = x: ∂u/∂x = 100/1024 ≈ 0.098 normalised units = 25 texels.
/// assert!((fp.x[0].to_num::<f64>() - 100.0 / 1024.0).abs() < 1e-5);
/// assert!(fp.x[1].abs().to_num::<f64>() < 1e-5);
/// let lod = tri.lod(&fp).to_num::<f64>();
/// assert!((lod - 25f64.log2()).abs() <= RAYDIFF_LOD_MAX_ERROR);
/// // Collinear vertices: no footprint, the coarsest level.
/// let line = [[0.0, 0.0, -100.0], [1.0, 0.0, -100.0], [2.0, 0.0, -100.0]];
/// let flat = RayDiffTriangle::new(&TexTriangle::from_f32(line, uv, 256, 256)?);
/// assert!(flat.is_degenerate());
/// assert_eq!(flat.lod(&fp), raymip::Lod::MAX);
/// # Ok::<(), raymip::TableError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RayDiffTriangle {
    gu: [I32F32; 3],
    gv: [I32F32; 3],
    width: u32,
    height: u32,
    degenerate: bool,
}

/// `(v >> s, s)` with the smallest `s` such that every `|v[k] >> s| < 2²⁰`.
fn normalise_top<const N: usize>(v: [i128; N]) -> ([i128; N], u32) {
    let top = v
        .iter()
        .map(|x| 128 - x.unsigned_abs().leading_zeros())
        .max()
        .unwrap_or(0);
    let s = top.saturating_sub(20);
    (v.map(|x| x >> s), s)
}

fn cross(a: [i128; 3], b: [i128; 3]) -> [i128; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `v · 2^e` saturated to I32F32 bits, rounded when `e < 0`.
fn scale_sat(v: i128, e: i32) -> I32F32 {
    let r = if e >= 0 {
        let e = e.unsigned_abs().min(127);
        if v.unsigned_abs().leading_zeros() <= e {
            if v < 0 { i128::MIN } else { i128::MAX }
        } else {
            v << e
        }
    } else {
        let e = e.unsigned_abs();
        if e >= 127 {
            0
        } else {
            (v + (1i128 << (e - 1))) >> e
        }
    };
    I32F32::from_bits(r.clamp(i128::from(i64::MIN), i128::from(i64::MAX)) as i64)
}

impl RayDiffTriangle {
    /// The constant of one textured triangle (set-up time, integer
    /// arithmetic; never panics). A zero-area triangle is marked
    /// degenerate (see the [module docs](self)).
    #[must_use]
    pub fn new(tri: &TexTriangle) -> Self {
        let (p, uv, width, height) = tri.parts();
        let sub = |a: [Coord; 3], b: [Coord; 3]| -> [i128; 3] {
            core::array::from_fn(|k| i128::from(a[k].to_bits()) - i128::from(b[k].to_bits()))
        };
        let (e, se) = normalise_top::<6>({
            let (a, b) = (sub(p[1], p[0]), sub(p[2], p[0]));
            [a[0], a[1], a[2], b[0], b[1], b[2]]
        });
        let (e1, e2) = ([e[0], e[1], e[2]], [e[3], e[4], e[5]]);
        let n = cross(e1, e2);
        let den: i128 = n.iter().map(|x| x * x).sum();
        let zero = Self {
            gu: [I32F32::ZERO; 3],
            gv: [I32F32::ZERO; 3],
            width,
            height,
            degenerate: true,
        };
        if den == 0 {
            return zero;
        }
        let a = cross(e2, n); // ∝ ∂b₁ direction, |a| < 2⁶²
        let b = cross(n, e1);
        let d =
            |i: usize, c: usize| i128::from(uv[i][c].to_bits()) - i128::from(uv[0][c].to_bits());
        let (w, suv) = normalise_top::<4>([d(1, 0), d(2, 0), d(1, 1), d(2, 1)]);
        // G bits (2⁻³²) = (num/den)·2^(suv − se + 32); num < 2⁸⁴, so num·2⁴⁰ fits.
        let g = |c1: i128, c2: i128| -> [I32F32; 3] {
            core::array::from_fn(|k| {
                let num = c1 * a[k] + c2 * b[k];
                let q = (num << 40).checked_div(den).unwrap_or(0);
                scale_sat(q, suv as i32 - se as i32 + 32 - 40)
            })
        };
        Self {
            gu: g(w[0], w[1]),
            gv: g(w[2], w[3]),
            degenerate: false,
            ..zero
        }
    }

    /// True for a zero-area triangle (no footprint: the lod saturates high).
    #[must_use]
    pub const fn is_degenerate(&self) -> bool {
        self.degenerate
    }

    /// The footprint of a hit with transferred position differentials
    /// `dpdx`, `dpdy` ([`crate::path::raydiff::RayDiff::dodx`] after
    /// [`crate::path::raydiff::RayDiff::transfer`]): `(∂u/∂x, ∂v/∂x), (∂u/∂y, ∂v/∂y)` in
    /// normalized texture coordinates, saturating. Degenerate triangle: the
    /// largest footprint. Per hit; never panics.
    #[must_use]
    pub fn footprint(&self, dpdx: [PosDiff; 3], dpdy: [PosDiff; 3]) -> Footprint {
        if self.degenerate {
            return Footprint {
                x: [TexCoord::MAX, TexCoord::ZERO],
                y: [TexCoord::ZERO, TexCoord::MAX],
            };
        }
        let dot = |g: [I32F32; 3], p: [PosDiff; 3]| -> TexCoord {
            let s: i128 = (0..3)
                .map(|k| {
                    (i128::from(g[k].to_bits()) * i128::from(p[k].to_bits()) + (1 << 31)) >> 32
                })
                .sum();
            TexCoord::from_bits(s.clamp(i128::from(i64::MIN), i128::from(i64::MAX)) as i64)
        };
        Footprint {
            x: [dot(self.gu, dpdx), dot(self.gv, dpdx)],
            y: [dot(self.gu, dpdy), dot(self.gv, dpdy)],
        }
    }

    /// Lod of a footprint: `log2` of the larger axis length in level-0
    /// texels, `½·log2 max(|a_x|², |a_y|²)` (the hardware paper's eq. 1),
    /// rounded to 1/256 level, saturating (a zero footprint gives
    /// `Lod::MIN`, the degenerate triangle's `Lod::MAX`). Within
    /// [`RAYDIFF_LOD_MAX_ERROR`] of f64 (conditions in the
    /// [module docs](self)). Per hit; never panics.
    #[must_use]
    pub fn lod(&self, fp: &Footprint) -> Lod {
        if self.degenerate {
            return Lod::MAX;
        }
        let (w, h) = (i128::from(self.width), i128::from(self.height));
        // Texel components in 2⁻³² units, clamped to 2³⁰ texels.
        let lim = 1i128 << 62;
        let len2 = |a: [TexCoord; 2]| -> u128 {
            let x = (i128::from(a[0].to_bits()) * w).clamp(-lim, lim);
            let y = (i128::from(a[1].to_bits()) * h).clamp(-lim, lim);
            (x * x + y * y) as u128
        };
        let l2 = len2(fp.x).max(len2(fp.y));
        // log2 of the squared length (2⁻⁶⁴ units), halved, rounded to I8F8.
        let l = log2_bits_u128(l2, 64).to_bits();
        let r = ((l >> 1) + 0x80) >> 8;
        Lod::from_bits(r.clamp(i32::from(i16::MIN), i32::from(i16::MAX)) as i16)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::path::raydiff::RayDiff;
    use crate::path::raydiff::tests::{V, add, dot, norm, transfer_f64, uq};
    use crate::units::{PathLength, UnitVec};
    use proptest::prelude::*;

    fn tri(p: [V; 3], uv: [[f64; 2]; 3], w: u32, h: u32) -> TexTriangle {
        TexTriangle::new(
            p.map(|v| v.map(Coord::from_num)),
            uv.map(|v| v.map(TexCoord::from_num)),
            w,
            h,
        )
        .unwrap()
    }

    fn crossf(a: V, b: V) -> V {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    /// f64 footprint as the harness writes it (barycentric differentials
    /// of ∂P, then through the UV edges), and its lod.
    fn footprint_f64(p: [V; 3], uv: [[f64; 2]; 3], dp: [V; 2]) -> [[f64; 2]; 2] {
        let e1 = add(p[1], p[0], -1.0);
        let e2 = add(p[2], p[0], -1.0);
        let n = crossf(e1, e2);
        let n2 = dot(n, n);
        dp.map(|d| {
            let b1 = dot(crossf(d, e2), n) / n2;
            let b2 = dot(crossf(e1, d), n) / n2;
            [
                b1 * (uv[1][0] - uv[0][0]) + b2 * (uv[2][0] - uv[0][0]),
                b1 * (uv[1][1] - uv[0][1]) + b2 * (uv[2][1] - uv[0][1]),
            ]
        })
    }

    fn lod_f64(a: [[f64; 2]; 2], w: u32, h: u32) -> f64 {
        let len =
            |v: [f64; 2]| ((v[0] * f64::from(w)).powi(2) + (v[1] * f64::from(h)).powi(2)).sqrt();
        len(a[0]).max(len(a[1])).log2()
    }

    #[test]
    fn fronto_parallel_square_one_texel_per_pixel() {
        // A 1×1 square at z = 0 with a 256² texture, pixel footprint 1/256.
        let t = RayDiffTriangle::new(&tri(
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
            256,
            256,
        ));
        let s = 1.0 / 256.0;
        let dp = |x: f64, y: f64| [x, y, 0.0].map(PosDiff::from_num);
        let fp = t.footprint(dp(s, 0.0), dp(0.0, s));
        assert_eq!(fp.x[0].to_num::<f64>(), s);
        assert_eq!(fp.y[1].to_num::<f64>(), s);
        assert_eq!(t.lod(&fp), Lod::ZERO);
        let fp = t.footprint(dp(4.0 * s, 0.0), dp(0.0, s));
        assert_eq!(t.lod(&fp), Lod::from_num(2), "the larger axis");
    }

    #[test]
    fn degenerate_and_zero_cases() {
        let flat = RayDiffTriangle::new(&tri(
            [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]],
            [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
            64,
            64,
        ));
        assert!(flat.is_degenerate());
        let z = [PosDiff::ZERO; 3];
        assert_eq!(flat.lod(&flat.footprint(z, z)), Lod::MAX);
        let no_uv = RayDiffTriangle::new(&tri(
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [[0.5, 0.5]; 3],
            64,
            64,
        ));
        let one = [PosDiff::from_num(1); 3];
        let fp = no_uv.footprint(one, one);
        assert_eq!(fp, Footprint::default());
        assert_eq!(no_uv.lod(&fp), Lod::MIN);
        // Saturated inputs never panic.
        let big = [PosDiff::MAX, PosDiff::MIN, PosDiff::MAX];
        let huge = RayDiffTriangle::new(&tri(
            [[-3e4, -3e4, 0.0], [3e4, -3e4, 1.0], [0.0, 3e4, -2.0]],
            [[-1e4, 0.0], [1e4, 1.0], [0.0, -1e4]],
            4096,
            4096,
        ));
        let fp = huge.footprint(big, big);
        let _ = huge.lod(&fp);
        let tiny = RayDiffTriangle::new(&tri(
            [[0.0, 0.0, 0.0], [1e-8, 0.0, 0.0], [0.0, 1e-8, 0.0]],
            [[0.0, 0.0], [1e4, 0.0], [0.0, 1e4]],
            4096,
            1,
        ));
        let _ = tiny.lod(&tiny.footprint(big, big));
    }

    fn coord() -> impl Strategy<Value = f64> {
        prop_oneof![-1.0e3..1.0e3f64, -10.0..10.0f64]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3_000))]

        /// The whole chain (primary set-up, transfer to the triangle's
        /// plane, footprint, lod) against f64 of the same quantised inputs.
        #[test]
        fn chain_lod_matches_f64(
            p in [[coord(), coord(), coord()], [coord(), coord(), coord()], [coord(), coord(), coord()]],
            uv in [[-50.0..50.0f64, -50.0..50.0], [-50.0..50.0f64, -50.0..50.0], [-50.0..50.0f64, -50.0..50.0]],
            w in 1u32..4096, h in 1u32..4096,
            back in 1.0e-2..1.0e3f64,
            gamma in 1.0e-4..0.05f64,
            sideways in [-1.0..1.0f64, -1.0..1.0, -1.0..1.0],
        ) {
            let pq: [V; 3] = p.map(|v| v.map(|x| Coord::from_num(x).to_num()));
            let uvq = uv.map(|v| v.map(|x| Coord::from_num(x).to_num::<f64>()));
            let t = RayDiffTriangle::new(&tri(pq, uvq, w, h));
            prop_assume!(!t.is_degenerate());
            // A hit on the triangle's plane seen from an eye `back` away.
            let n = norm(crossf(add(pq[1], pq[0], -1.0), add(pq[2], pq[0], -1.0)));
            prop_assume!(n.iter().all(|x| x.is_finite()));
            let dir = norm(add(n.map(|x| -x), sideways, 0.5));
            let cos = dot(dir, n).abs();
            prop_assume!(cos > 0.05);
            let dq = uq(dir).map(|x| x.to_num::<f64>());
            // Pinhole camera looking along `dir`, pixel steps r, u ⟂ dir.
            let r = norm(crossf(dq, if dq[0].abs() < 0.9 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] }));
            let u = crossf(dq, r);
            let rq = uq(r.map(|x| x * gamma)).map(|x| x.to_num::<f64>());
            let uqv = uq(u.map(|x| x * gamma)).map(|x| x.to_num::<f64>());
            let (s, sat0) = RayDiff::primary(UnitVec(uq(dq)), UnitVec(uq(dq)), uq(rq), uq(uqv));
            let tq = PathLength::from_num(back);
            let nq = uq(n).map(|x| x.to_num::<f64>());
            let (s, sat1) = s.transfer(UnitVec(uq(dq)), tq, UnitVec(uq(nq)));
            prop_assume!(!sat0 && !sat1);
            let fp = t.footprint(s.dodx, s.dody);
            // f64: the same set-up and transfer.
            let ddx: V = core::array::from_fn(|k| rq[k] - dot(dq, rq) * dq[k]);
            let ddy: V = core::array::from_fn(|k| uqv[k] - dot(dq, uqv) * dq[k]);
            let tf = tq.to_num::<f64>();
            let dpx = transfer_f64([0.0; 3], ddx, dq, tf, nq);
            let dpy = transfer_f64([0.0; 3], ddy, dq, tf, nq);
            let want = footprint_f64(pq, uvq, [dpx, dpy]);
            let big = want.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
            prop_assume!(big >= 2f64.powi(-16) && big < 2f64.powi(14));
            let got = t.lod(&fp).to_num::<f64>();
            let wl = lod_f64(want, w, h);
            prop_assume!(wl.abs() < 120.0);
            prop_assert!((got - wl).abs() <= RAYDIFF_LOD_MAX_ERROR,
                "lod {} vs f64 {} (footprint {:?} vs {:?})", got, wl, fp, want);
        }
    }
}
