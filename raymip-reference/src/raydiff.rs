//! Ray differentials (Igehy 1999, "Tracing Ray Differentials") in f64,
//! written from the paper without the firmware: the primary set-up of a
//! pinhole camera, the transfer to a hit, reflection and refraction with
//! shading-normal differentials, the texture-space footprint of a textured
//! triangle (barycentric differentials through its UVs) and its lod. The
//! clamps and degenerate-triangle conventions are the firmware's documented
//! ones (`raymip::raydiff` module docs), restated here:
//!
//! * `|D·n|` of a transfer and `cos θₜ` of a refraction are clamped to
//!   `≥ MIN_COS = 2⁻¹⁶` (sign kept, zero reads as `+MIN_COS`);
//! * a triangle of zero world area (`e₁ × e₂ = 0`, decided exactly on the
//!   quantised vertices) has the lod `+∞` (the firmware's `Lod::MAX`);
//! * a triangle of zero UV area (`Δu₁Δv₂ − Δu₂Δv₁ = 0`, exactly) and a
//!   zero footprint have the lod `−∞` (`Lod::MIN`).

/// A 3-vector.
pub type V = [f64; 3];

/// Smallest `|D·n|` and `cos θₜ` used as a divisor: 2⁻¹⁶.
pub const MIN_COS: f64 = 1.0 / 65_536.0;

/// `a·b`.
#[must_use]
pub fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a + s·b`.
#[must_use]
pub fn axpy(a: V, s: f64, b: V) -> V {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}

/// `s·a`.
#[must_use]
pub fn scale(s: f64, a: V) -> V {
    [s * a[0], s * a[1], s * a[2]]
}

/// `a × b`.
#[must_use]
pub fn cross(a: V, b: V) -> V {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Euclidean length.
#[must_use]
pub fn norm(a: V) -> f64 {
    dot(a, a).sqrt()
}

/// `a / |a|` (the zero vector stays zero).
#[must_use]
pub fn unit(a: V) -> V {
    let l = norm(a);
    if l > 0.0 { scale(1.0 / l, a) } else { a }
}

/// The differential state of a ray: `∂O/∂x, ∂O/∂y` (scene units per
/// pixel) and `∂D/∂x, ∂D/∂y` (per pixel; `D` a unit vector).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Diff {
    /// `∂O/∂x`.
    pub dox: V,
    /// `∂O/∂y`.
    pub doy: V,
    /// `∂D/∂x`.
    pub ddx: V,
    /// `∂D/∂y`.
    pub ddy: V,
}

/// `|x| ≥ MIN_COS`, sign kept, zero read as `+MIN_COS`.
fn clamp_cos(x: f64) -> f64 {
    if x.abs() >= MIN_COS {
        x
    } else if x < 0.0 {
        -MIN_COS
    } else {
        MIN_COS
    }
}

/// Primary ray of a pinhole camera through the unnormalised direction
/// `d = f + x·r + y·u` (`f` the unit forward axis, `r`, `u` the per-pixel
/// steps on the image plane at unit distance, both `⟂ f`), given the unit
/// `dir = d/|d|`: `∂D/∂x = (r − (D·r)·D)/|d|` with `1/|d| = D·f` (Igehy
/// eq. 4, `D = d/|d|` differentiated), `∂O = 0`.
#[must_use]
pub fn primary(dir: V, f: V, r: V, u: V) -> Diff {
    let inv = dot(dir, f);
    let axis = |a: V| scale(inv, axpy(a, -dot(dir, a), dir));
    Diff {
        ddx: axis(r),
        ddy: axis(u),
        ..Diff::default()
    }
}

/// Transfer to a hit at distance `t` on a plane of unit normal `n` (Igehy
/// eq. 10–12): `q = ∂O + t·∂D`, `∂t = −(q·n)/(D·n)`, `∂O' = q + ∂t·D`;
/// `∂D` unchanged.
#[must_use]
pub fn transfer(s: &Diff, d: V, t: f64, n: V) -> Diff {
    let dn = clamp_cos(dot(d, n));
    let axis = |o: V, dd: V| {
        let q = axpy(o, t, dd);
        axpy(q, -dot(q, n) / dn, d)
    };
    Diff {
        dox: axis(s.dox, s.ddx),
        doy: axis(s.doy, s.ddy),
        ..*s
    }
}

/// Reflection about the unit normal `n` with its differentials `dnx`,
/// `dny` (Igehy eq. 14–15): `∂R = ∂D − 2((D·n)∂n + ∂(D·n)·n)`,
/// `∂(D·n) = ∂D·n + D·∂n`; `∂O` kept.
#[must_use]
pub fn reflect(s: &Diff, d: V, n: V, dnx: V, dny: V) -> Diff {
    let dn = dot(d, n);
    let axis = |dd: V, dnv: V| {
        let ddn = dot(dd, n) + dot(d, dnv);
        axpy(axpy(dd, -2.0 * dn, dnv), -2.0 * ddn, n)
    };
    Diff {
        ddx: axis(s.ddx, dnx),
        ddy: axis(s.ddy, dny),
        ..*s
    }
}

/// Refraction through the unit normal `n` facing the ray (`D·n < 0`) with
/// differentials `dnx`, `dny`, relative index `eta = n₁/n₂` and `cos_t =
/// cos θₜ` (clamped to `MIN_COS`) (Igehy eq. 16–18): `cos θᵢ = −D·n`,
/// `μ = η cos θᵢ − cos θₜ`, `∂cos θᵢ = −(∂D·n + D·∂n)`,
/// `∂μ = (η − η² cos θᵢ / cos θₜ)·∂cos θᵢ`, `∂T = η∂D + ∂μ·n + μ·∂n`;
/// `∂O` kept.
#[must_use]
pub fn refract(s: &Diff, d: V, n: V, dnx: V, dny: V, eta: f64, cos_t: f64) -> Diff {
    let cosi = -dot(d, n);
    let cos_t = cos_t.max(MIN_COS);
    let mu = eta * cosi - cos_t;
    let coef = eta - eta * eta * cosi / cos_t;
    let axis = |dd: V, dnv: V| {
        let dmu = -coef * (dot(dd, n) + dot(d, dnv));
        axpy(axpy(scale(eta, dd), dmu, n), mu, dnv)
    };
    Diff {
        ddx: axis(s.ddx, dnx),
        ddy: axis(s.ddy, dny),
        ..*s
    }
}

/// A textured triangle: vertices (scene units), UVs (normalized texture
/// coordinates) and texture size (texels).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// Vertex positions.
    pub p: [V; 3],
    /// Vertex UVs.
    pub uv: [[f64; 2]; 3],
    /// Texture width (texels).
    pub w: u32,
    /// Texture height (texels).
    pub h: u32,
}

/// The lod class of a hit on a [`Triangle`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Footprint {
    /// Zero world area: lod `+∞`.
    Degenerate,
    /// Zero UV area: lod `−∞`.
    FlatUv,
    /// The two axes `[(∂u/∂x, ∂v/∂x), (∂u/∂y, ∂v/∂y)]` (normalized units
    /// per pixel).
    Axes([[f64; 2]; 2]),
}

/// `a·d = b·c` exactly? The products are equal exactly when their
/// rounded values and their rounding errors (`fma(a, d, −a·d)`, exact) are
/// equal. The edges are exact differences for vertices on the firmware's
/// 2⁻³² grid below 2²⁰ in magnitude (53 significant bits), so the
/// degenerate classes are decided exactly on the quantised vertices.
fn det2_is_zero(a: f64, b: f64, c: f64, d: f64) -> bool {
    let (p, q) = (a * d, b * c);
    p == q && a.mul_add(d, -p) == b.mul_add(c, -q)
}

impl Triangle {
    /// True for zero world area: `e₁ × e₂ = 0` (exactly).
    #[must_use]
    pub fn is_degenerate(&self) -> bool {
        let e1 = axpy(self.p[1], -1.0, self.p[0]);
        let e2 = axpy(self.p[2], -1.0, self.p[0]);
        det2_is_zero(e1[1], e1[2], e2[1], e2[2])
            && det2_is_zero(e1[2], e1[0], e2[2], e2[0])
            && det2_is_zero(e1[0], e1[1], e2[0], e2[1])
    }

    /// True for zero UV area: `Δu₁Δv₂ − Δu₂Δv₁ = 0` (exactly).
    #[must_use]
    pub fn is_flat_uv(&self) -> bool {
        let du = [self.uv[1][0] - self.uv[0][0], self.uv[2][0] - self.uv[0][0]];
        let dv = [self.uv[1][1] - self.uv[0][1], self.uv[2][1] - self.uv[0][1]];
        det2_is_zero(du[0], du[1], dv[0], dv[1])
    }

    /// The footprint of position differentials `dpx`, `dpy` at a hit
    /// (pbrt's barycentric differentials: `∂b₁ = ((∂P × e₂)·N)/|N|²`,
    /// `∂b₂ = ((e₁ × ∂P)·N)/|N|²`, then through the UV edges).
    #[must_use]
    pub fn footprint(&self, dpx: V, dpy: V) -> Footprint {
        if self.is_degenerate() {
            return Footprint::Degenerate;
        }
        if self.is_flat_uv() {
            return Footprint::FlatUv;
        }
        let e1 = axpy(self.p[1], -1.0, self.p[0]);
        let e2 = axpy(self.p[2], -1.0, self.p[0]);
        let n = cross(e1, e2);
        let n2 = dot(n, n);
        let uv = self.uv;
        let axis = |dp: V| {
            let b1 = dot(cross(dp, e2), n) / n2;
            let b2 = dot(cross(e1, dp), n) / n2;
            [
                b1 * (uv[1][0] - uv[0][0]) + b2 * (uv[2][0] - uv[0][0]),
                b1 * (uv[1][1] - uv[0][1]) + b2 * (uv[2][1] - uv[0][1]),
            ]
        };
        Footprint::Axes([axis(dpx), axis(dpy)])
    }

    /// The lod of a footprint: `log2` of the larger axis in level-0 texels
    /// ([`crate::lod::footprint`]; `±∞` for the degenerate classes).
    #[must_use]
    pub fn lod(&self, fp: &Footprint) -> f64 {
        match fp {
            Footprint::Degenerate => f64::INFINITY,
            Footprint::FlatUv => f64::NEG_INFINITY,
            Footprint::Axes(axes) => {
                crate::lod::footprint(*axes, (f64::from(self.w), f64::from(self.h)))
            }
        }
    }

    /// The texel-space matrix `M` of the footprint (rows `w·∇u`, `h·∇v`:
    /// texels per scene unit, in the triangle's plane), `None` for the
    /// degenerate classes. `|M·∂P|` is a footprint axis in texels.
    #[must_use]
    pub fn texel_gradients(&self) -> Option<[V; 2]> {
        if self.is_degenerate() || self.is_flat_uv() {
            return None;
        }
        let e1 = axpy(self.p[1], -1.0, self.p[0]);
        let e2 = axpy(self.p[2], -1.0, self.p[0]);
        let n = cross(e1, e2);
        let n2 = dot(n, n);
        let g1 = scale(1.0 / n2, cross(e2, n));
        let g2 = scale(1.0 / n2, cross(n, e1));
        let uv = self.uv;
        let row = |c: usize, s: u32| {
            let a = axpy(scale(uv[1][c] - uv[0][c], g1), uv[2][c] - uv[0][c], g2);
            scale(f64::from(s), a)
        };
        Some([row(0, self.w), row(1, self.h)])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn head_on_wall_and_mirror() {
        let s = 1.0 / 1024.0;
        let f = [0.0, 0.0, -1.0];
        let p = primary(f, f, [s, 0.0, 0.0], [0.0, s, 0.0]);
        assert_eq!(p.ddx, [s, 0.0, 0.0]);
        let hit = transfer(&p, f, 100.0, [0.0, 0.0, 1.0]);
        assert_eq!(hit.dox, [100.0 * s, 0.0, 0.0]);
        let m = reflect(&hit, f, [0.0, 0.0, 1.0], [0.0; 3], [0.0; 3]);
        assert_eq!(m.ddx, hit.ddx);
        let r = refract(&hit, f, [0.0, 0.0, 1.0], [0.0; 3], [0.0; 3], 0.5, 1.0);
        assert_eq!(r.ddx, [0.5 * s, 0.0, 0.0]);
        let t = Triangle {
            p: [[0.0, 0.0, -100.0], [1.0, 0.0, -100.0], [0.0, 1.0, -100.0]],
            uv: [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
            w: 256,
            h: 256,
        };
        let fp = t.footprint(hit.dox, hit.doy);
        assert!((t.lod(&fp) - 25f64.log2()).abs() < 1e-12);
        let g = t.texel_gradients().unwrap();
        assert_eq!(g, [[256.0, 0.0, 0.0], [0.0, 256.0, 0.0]]);
    }

    #[test]
    fn degenerate_classes_are_exact() {
        let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let a = [0.125, 0.375, 2.25];
        let b = [1.0 / 3.0, 2.0 / 7.0, 0.9];
        // p2 = 2p1 − p0 exactly (dyadic values): collinear.
        let p1 = axpy(a, 1.0, [0.5, 0.25, 0.125]);
        let line = [a, p1, axpy(scale(2.0, p1), -1.0, a)];
        let t = Triangle {
            p: line,
            uv,
            w: 4,
            h: 4,
        };
        assert!(t.is_degenerate());
        assert_eq!(t.lod(&t.footprint(b, b)), f64::INFINITY);
        // One unit in the last place off the line: not degenerate.
        let mut off = line;
        off[2][1] = f64::from_bits(off[2][1].to_bits() + 1);
        assert!(!Triangle { p: off, ..t }.is_degenerate());
        let flat = Triangle {
            p: [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            uv: [[0.0, 0.0], [0.5, 0.25], [1.0, 0.5]],
            w: 4,
            h: 4,
        };
        assert!(flat.is_flat_uv());
        assert_eq!(flat.lod(&flat.footprint(b, b)), f64::NEG_INFINITY);
        assert!(t.texel_gradients().is_none() && flat.texel_gradients().is_none());
    }
}
