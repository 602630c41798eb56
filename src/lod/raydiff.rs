//! Texture-space footprint and lod of a hit from its ray differentials.
//!
//! The barycentric differentials of the transferred `∂P = ∂O'`
//! ([`crate::path::raydiff::RayDiff::transfer`]) are mapped through the
//! triangle's UVs to `(∂u/∂x, ∂v/∂x), (∂u/∂y, ∂v/∂y)` (pbrt's `dudx, dvdx,
//! dudy, dvdy`, the two axes [`crate::texture::sampler::aniso`] takes); the
//! lod is `log2` of the larger axis in level-0 texels (the hardware paper's
//! eq. 1).
//!
//! # Per-triangle constant
//!
//! With `e₁ = p₁ − p₀`, `e₂ = p₂ − p₀`, `N = e₁ × e₂`, the barycentric
//! gradients are `∇b₁ = (e₂ × N)/|N|²`, `∇b₂ = (N × e₁)/|N|²`, so
//! `∇u = Δu₁∇b₁ + Δu₂∇b₂ = (N × a_u)/|N|²` with
//! `a_u = Δu₂·e₁ − Δu₁·e₂` (and `∇v` alike). [`RayDiffTriangle::new`]
//! computes, once per triangle and in integers only:
//!
//! * `e₁`, `e₂` and the UV edges exactly (65-bit differences);
//! * the zero tests exactly: zero world area when every component of
//!   `e₁ × e₂` is zero (`e₁ᵢe₂ⱼ = e₁ⱼe₂ᵢ`, compared as 128-bit products),
//!   zero UV area when `Δu₁Δv₂ = Δu₂Δv₁`;
//! * `N`, `a_u`, `a_v` exactly (129-bit differences of 128-bit products:
//!   the cancellation of a sliver or of UVs proportional to the positions
//!   costs nothing), each rounded once to a 62-bit mantissa;
//! * `N × a`, `|N|²`, the quotient and the texture sizes in 62-bit
//!   mantissas with exponents (relative error below `2⁻⁵⁸`): no step is
//!   absolute, so slivers, lopsided UVs and slowly varying UVs keep their
//!   precision;
//!
//! and keeps the texel-space gradients `w·∇u`, `h·∇v` (texels per scene
//! unit) as six 32-bit mantissas with one exponent (the largest below
//! `2³⁰`). A hit then needs four 3-vector dot products.
//!
//! # Degenerate cases (as the table method's markers)
//!
//! * zero world area (collinear or coincident vertices):
//!   [`RayDiffTriangle::is_degenerate`]; the footprint is the largest one
//!   and the lod is [`Lod::MAX`] (coarsest stored level);
//! * zero UV area: [`RayDiffTriangle::is_flat_uv`]; the footprint is zero
//!   and the lod [`Lod::MIN`] (level 0);
//! * grazing hits: bounded by the transfer's clamp
//!   ([`MIN_COS`](crate::units::MIN_COS)).
//!
//! # Error bound
//!
//! * **Set-up.** `N`, `a_u`, `a_v` exact, then six roundings to 62 bits
//!   and the products, sums and the quotient of `(N × a)·w/|N|²` (each
//!   `< 2⁻⁶¹` relative; `N ⟂ a`, so a cancelling component errs by less
//!   than `2⁻⁵⁹` of `|N × a|`): the texel gradients within `2⁻⁵⁶` of
//!   `|M|∞`, then truncated to one exponent (`< 2u·|M|∞`, `u = 2⁻³⁰`).
//! * **Footprint** ([`FOOTPRINT_ERROR`] = 2⁻²⁴): three multiply-highs per
//!   component (`< 8u·|M|∞|∂P|∞` each) and the gradients' truncation
//!   (`≤ √3·2.01u·|M|∞|∂P|`): per axis `≤ √2·27.5u ≤ 64u` times
//!   `|M|∞·|∂P|`, `|∂P|` the larger of `|∂P/∂x|`, `|∂P/∂y|` (the two
//!   share one exponent: the shorter axis is read at the longer one's
//!   unit, see [`crate::path::raydiff`]).
//! * **Lod** ([`LOD_ROUNDING_ERROR`] = 2⁻⁹ + 2⁻¹⁴ + 2⁻¹⁶ against the exact
//!   lod of the computed footprint): the squared lengths exact in 64
//!   bits, the larger by its normalised top 32 bits (`< 2⁻³¹`), the
//!   table logarithm (`2⁻¹³`, halved), the halving and the rounding to
//!   1/256 level.
//!
//! Along a path, the differential operations' local errors
//! ([`crate::path::raydiff`]: `PRIMARY_ERROR`, `TRANSFER_ERROR`,
//! `REFLECT_ERROR`, `REFRACT_ERROR`) add up with each operation's gain: a
//! transfer divides the bounds of `∂O + t·∂D` by `|D·n|`, a reflection
//! keeps that of `∂D` and adds 4 times that of `∂n`, a refraction
//! multiplies them by `η + |c|` and `|c| + |μ|`, and a curved surface's
//! normal differentials `∂n = κ·∂P` carry `|κ|` times the bound of `∂P`
//! (the bound of a normal differential handed in, its rounding). With
//! `B` the resulting bound of `∂P` at the textured hit (the larger axis; the
//! operations' local errors are on each pair's scale, the larger of its
//! `x` and `y` vectors, so both axes' bounds grow with the larger),
//! `M` the texel gradients and `F` the exact footprint's larger axis,
//!
//! ```text
//! ρ = (|M|·B + FOOTPRINT_ERROR·|M|∞·|∂P|) / |F|,
//! |lod − lod_f64| ≤ LOD_ROUNDING_ERROR + log2(1/(1 − ρ))   (ρ < ½),
//! ```
//!
//! a function of the path's cosines, distances, curvatures, indices of
//! refraction and of the triangle's gradients, first order in `u`.
//! [`RAYDIFF_LOD_MAX_ERROR`] = 2⁻⁷ follows wherever `ρ ≤ 0.004`. Slivers
//! and slowly varying or lopsided UVs do not enter `ρ` beyond `|M|/|F|`
//! (exact set-up, relative precision everywhere), and a grazing transfer's
//! `1/|D·n|` grows the larger axis as much as its error; what does grow
//! `ρ` is an axis whose footprint cancels (a focus) or whose gradient is
//! the smaller one of a lopsided pair. The harness computes `ρ` for random
//! camera chains of every case class (`host-tests/src/raydiff_chains.rs`:
//! slivers to 2²⁰:1, u and v ranges differing by 2¹⁶, UV gradients down
//! to 2⁻³⁰, collinear and zero-UV-area triangles, cosines down to
//! [`MIN_COS`](crate::units::MIN_COS), ten bounces through planes, convex
//! and concave mirrors and refractions up to total internal reflection,
//! concave mirrors near their focus) and tests the lod against f64 within
//! this bound (proptests and the fuzz target `raydiff_chain`); the
//! degenerate classes are exact; it asserts `ρ ≤ 0.004` for at least 99 %
//! of the ordinary, sliver, lopsided-UV and slow-UV chains. The measured
//! errors per class (all below 2⁻⁷) are in `docs/lod-methods.md`.

use crate::log2::{mantissa_log2, normalise64};
use crate::path::raydiff::{EXP_MIN, RayDiff, mulhi, shr};
use crate::setup::table::TexTriangle;
use crate::units::Footprint;
use crate::units::Lod;
use crate::units::{Coord, TexCoord};

/// Documented error bound of [`RayDiffFootprint::lod`] against f64 ray
/// differentials, in levels, where the chain's amplification allows it:
/// 2⁻⁷ (conditions in the [module docs](self#error-bound)).
pub const RAYDIFF_LOD_MAX_ERROR: f64 = 1.0 / 128.0;

/// Documented bound of [`RayDiffTriangle::footprint`]: the Euclidean error
/// of each axis (texels per pixel) is at most this times
/// `|M|∞·|∂P|`, `|M|∞` the largest component of the texel-space gradients
/// `w·∇u`, `h·∇v`, `|∂P|` the larger of `|∂P/∂x|`, `|∂P/∂y|`: 2⁻²⁴ (derivation in the [module docs](self#error-bound)).
pub const FOOTPRINT_ERROR: f64 = 1.0 / 16_777_216.0;

/// Documented bound of [`RayDiffFootprint::lod`] against the exact lod of
/// its own footprint, in levels: the table logarithm halved (2⁻¹⁴), the
/// halving and the squared length's truncation (below 2⁻¹⁷) and the
/// rounding to 1/256 level (2⁻⁹): `2⁻⁹ + 2⁻¹⁴ + 2⁻¹⁶`.
pub const LOD_ROUNDING_ERROR: f64 = 1.0 / 512.0 + 1.0 / 16_384.0 + 1.0 / 65_536.0;

/// What a triangle's footprint is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Kind {
    Textured,
    Degenerate,
    FlatUv,
}

/// Per-triangle constant of the ray-differential footprint: the
/// texel-space gradients `w·∇u`, `h·∇v` (texels per scene unit, 32-bit
/// mantissas with one exponent), the reciprocal texture size for the
/// normalized axes, and the degenerate classes. Built once per triangle by
/// [`RayDiffTriangle::new`].
///
/// # Example
/// ```
/// use fixed::types::I2F30;
/// use raymip::units::UnitVec;
/// use raymip::{Lod, PathLength, TexTriangle};
/// use raymip::lod::raydiff::{RAYDIFF_LOD_MAX_ERROR, RayDiffTriangle};
/// use raymip::path::raydiff::{DirDiff, RayDiff};
/// // A wall at z = −100 with u = x, v = y, on a 256×256 texture.
/// let p = [[0.0, 0.0, -100.0], [1.0, 0.0, -100.0], [0.0, 1.0, -100.0]];
/// let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
/// let tri = RayDiffTriangle::new(&TexTriangle::from_f32(p, uv, 256, 256)?);
/// assert!(!tri.is_degenerate() && !tri.is_flat_uv());
/// // A camera ray head-on with a 2⁻¹⁰ pixel spread, transferred to the
/// // wall at t = 100: ∂P = 100·2⁻¹⁰ scene units per pixel.
/// let (z, o, s) = (I2F30::ZERO, I2F30::ONE, I2F30::from_num(1.0 / 1024.0));
/// let fwd = UnitVec([z, z, -o]);
/// let mut ray = RayDiff::primary(fwd, fwd, DirDiff::from_i2f30([s, z, z]), DirDiff::from_i2f30([z, s, z]));
/// ray.transfer(fwd, PathLength::from_num(100), UnitVec([z, z, o]));
/// let fp = tri.footprint(&ray);
/// // u = x: ∂u/∂x = 100/1024 normalised units = 25 texels.
/// let lod = fp.lod().to_num::<f64>();
/// assert!((lod - 25f64.log2()).abs() <= RAYDIFF_LOD_MAX_ERROR);
/// let axes = fp.axes(&tri);
/// assert!((axes.x[0].to_num::<f64>() - 100.0 / 1024.0).abs() < 1e-6);
/// // Collinear vertices: no footprint, the coarsest level.
/// let line = [[0.0, 0.0, -100.0], [1.0, 0.0, -100.0], [2.0, 0.0, -100.0]];
/// let flat = RayDiffTriangle::new(&TexTriangle::from_f32(line, uv, 256, 256)?);
/// assert!(flat.is_degenerate());
/// assert_eq!(flat.footprint(&ray).lod(), Lod::MAX);
/// # Ok::<(), raymip::TableError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RayDiffTriangle {
    /// `w·∇u`, `h·∇v` mantissas (the largest `|·|` in `[2²⁹, 2³⁰)`).
    g: [[i32; 3]; 2],
    /// Their exponent.
    e: i32,
    /// `1/w`, `1/h` mantissas in `(2³⁰, 2³¹]` … with their exponents.
    inv: [(i32, i32); 2],
    kind: Kind,
}

/// The footprint of one hit in texel space: axis `a` (`x`, `y`) is
/// `(w·∂u, h·∂v) = m[a]·2ᵉ` texels per pixel, both axes at one exponent
/// (that of the state's `∂P` pair). [`RayDiffFootprint::lod`]
/// takes its larger axis, [`RayDiffFootprint::axes`] gives both in
/// normalized texture coordinates for anisotropic filtering.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RayDiffFootprint {
    m: [[i32; 2]; 2],
    e: i32,
}

/// A 62-bit soft float for the set-up: `m·2ᵉ`, `|m| ∈ [2⁶¹, 2⁶²)` or `m = 0`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Wide {
    m: i64,
    e: i32,
}

impl Wide {
    const ZERO: Self = Self { m: 0, e: EXP_MIN };

    /// `±mag·2ᵉ`, truncated to 62 bits.
    fn from_mag(neg: bool, mag: u128, e: i32) -> Self {
        if mag == 0 {
            return Self::ZERO;
        }
        let top = 128 - mag.leading_zeros() as i32; // 1..=128
        let s = top - 62;
        let m = if s >= 0 { mag >> s } else { mag << -s } as i64;
        Self {
            m: if neg { -m } else { m },
            e: e.saturating_add(s),
        }
    }

    fn from_i128(v: i128, e: i32) -> Self {
        Self::from_mag(v < 0, v.unsigned_abs(), e)
    }

    fn mul(self, o: Self) -> Self {
        // |m·m| < 2¹²⁴.
        Self::from_i128(
            i128::from(self.m) * i128::from(o.m),
            self.e.saturating_add(o.e),
        )
    }

    fn add(self, o: Self) -> Self {
        // Both at the larger exponent with 64 guard bits: |·| < 2¹²⁶ each.
        let e = self.e.max(o.e);
        let at = |x: Self| (i128::from(x.m) << 64) >> (e - x.e).clamp(0, 127);
        Self::from_i128(at(self) + at(o), e.saturating_sub(64))
    }

    fn neg(self) -> Self {
        Self { m: -self.m, ..self }
    }

    /// `self / o` (`o ≠ 0`; zero for `o = 0`): `|m·2⁶⁴ / m'| < 2⁶⁵`.
    fn div(self, o: Self) -> Self {
        let q = (i128::from(self.m) << 64)
            .checked_div(i128::from(o.m))
            .unwrap_or(0);
        Self::from_i128(q, self.e.saturating_sub(o.e).saturating_sub(64))
    }
}

/// `a·b − c·d` exactly (`|a|, …, |d| < 2⁶⁴`: 128-bit products, the
/// difference in 129 bits), rounded once to a [`Wide`].
fn det(a: i128, b: i128, c: i128, d: i128) -> Wide {
    let (p, sp) = (a.unsigned_abs() * b.unsigned_abs(), (a < 0) != (b < 0));
    let (q, sq) = (c.unsigned_abs() * d.unsigned_abs(), (c < 0) != (d < 0));
    if sp == sq {
        if p >= q {
            Wide::from_mag(sp, p - q, 0)
        } else {
            Wide::from_mag(!sp, q - p, 0)
        }
    } else {
        match p.checked_add(q) {
            Some(s) => Wide::from_mag(sp, s, 0),
            None => Wide::from_mag(sp, (p >> 1) + (q >> 1) + (p & q & 1), 1),
        }
    }
}

/// `a·b = c·d` exactly (`|a|, …, |d| < 2⁶⁴`).
fn prod_eq(a: i128, b: i128, c: i128, d: i128) -> bool {
    let p = a.unsigned_abs() * b.unsigned_abs();
    let q = c.unsigned_abs() * d.unsigned_abs();
    p == q && (p == 0 || ((a < 0) != (b < 0)) == ((c < 0) != (d < 0)))
}

/// `value·2^s` as I32F32 bits, saturated (`value = m·2ᵉ`).
fn texcoord(m: i32, e: i32) -> TexCoord {
    let s = e + 32;
    let v = if s >= 0 {
        let s = s.min(63) as u32;
        let x = i64::from(m);
        if x.unsigned_abs().leading_zeros() <= s {
            if x < 0 { i64::MIN } else { i64::MAX }
        } else {
            x << s
        }
    } else {
        i64::from(shr(m, -s))
    };
    TexCoord::from_bits(v)
}

/// The three components of a cross product `u × v` through `f`:
/// component `k` is `f(u[i], v[j], u[j], v[i])` with `(i, j)` = (1, 2),
/// (2, 0), (0, 1) for `k` = 0, 1, 2 (for `f(a, b, c, d) = a·b − c·d`, the
/// cross product). Constant indices: no bounds check survives.
fn cross_terms<T: Copy, R>(u: [T; 3], v: [T; 3], f: impl Fn(T, T, T, T) -> R) -> [R; 3] {
    [
        f(u[1], v[2], u[2], v[1]),
        f(u[2], v[0], u[0], v[2]),
        f(u[0], v[1], u[1], v[0]),
    ]
}

impl RayDiffTriangle {
    /// The constant of one textured triangle (set-up time, integer
    /// arithmetic; never panics). A zero-area triangle is marked
    /// degenerate, a zero-UV-area one flat (see the [module docs](self)).
    #[must_use]
    pub fn new(tri: &TexTriangle) -> Self {
        let (p, uv, w, h) = tri.parts();
        let d = |a: Coord, b: Coord| i128::from(b.to_bits()) - i128::from(a.to_bits());
        let e1: [i128; 3] = core::array::from_fn(|k| d(p[0][k], p[1][k]));
        let e2: [i128; 3] = core::array::from_fn(|k| d(p[0][k], p[2][k]));
        let dt = |a: TexCoord, b: TexCoord| i128::from(b.to_bits()) - i128::from(a.to_bits());
        let du = [dt(uv[0][0], uv[1][0]), dt(uv[0][0], uv[2][0])];
        let dv = [dt(uv[0][1], uv[1][1]), dt(uv[0][1], uv[2][1])];
        let inv = [w, h].map(|s| {
            // 1/s = (2⁶²/s)·2⁻⁶², normalised to 31 bits (s ≥ 1).
            let q = Wide::from_mag(false, (1u128 << 62) / u128::from(s.max(1)), -62);
            ((q.m >> 31) as i32, q.e + 31)
        });
        let mut t = Self {
            g: [[0; 3]; 2],
            e: EXP_MIN,
            inv,
            kind: Kind::Degenerate,
        };
        if cross_terms(e1, e2, prod_eq).iter().all(|&eq| eq) {
            return t;
        }
        if prod_eq(du[0], dv[1], du[1], dv[0]) {
            t.kind = Kind::FlatUv;
            return t;
        }
        // N, a_u, a_v exact, then rounded (units 2⁻⁶⁴ each: they cancel).
        let n = cross_terms(e1, e2, det);
        let a = |dd: [i128; 2]| -> [Wide; 3] {
            core::array::from_fn(|k| det(dd[1], e1[k], dd[0], e2[k]))
        };
        let n2 = n[0].mul(n[0]).add(n[1].mul(n[1])).add(n[2].mul(n[2]));
        let row = |a: [Wide; 3], s: u32| -> [Wide; 3] {
            let f = Wide::from_mag(false, u128::from(s), 0).div(n2);
            cross_terms(n, a, |ni, aj, nj, ai| {
                ni.mul(aj).add(nj.mul(ai).neg()).mul(f)
            })
        };
        let rows = [row(a(du), w), row(a(dv), h)];
        // One exponent for the six: the largest mantissa below 2³⁰.
        let top = rows
            .iter()
            .flatten()
            .filter(|x| x.m != 0)
            .map(|x| x.e)
            .max()
            .unwrap_or(EXP_MIN);
        let e = top + 32;
        t.g = rows.map(|r| r.map(|x| (x.m >> (e - x.e).clamp(0, 63)) as i32));
        t.e = e;
        t.kind = Kind::Textured;
        t
    }

    /// True for a zero-area triangle (no footprint: the lod saturates high).
    #[must_use]
    pub const fn is_degenerate(&self) -> bool {
        matches!(self.kind, Kind::Degenerate)
    }

    /// True for a triangle of zero UV area (the lod saturates low).
    #[must_use]
    pub const fn is_flat_uv(&self) -> bool {
        matches!(self.kind, Kind::FlatUv)
    }

    /// The footprint of a hit whose state `s` was transferred to it
    /// ([`RayDiff::transfer`], or set up from a G-buffer): `∂P/∂x`,
    /// `∂P/∂y` through the texel-space gradients. Degenerate triangle: the
    /// largest footprint; zero UV area: zero. Per hit; never panics.
    #[must_use]
    #[inline]
    pub fn footprint(&self, s: &RayDiff) -> RayDiffFootprint {
        match self.kind {
            Kind::Textured => {}
            Kind::Degenerate => {
                return RayDiffFootprint {
                    m: [[1 << 30, 0], [0, 1 << 30]],
                    e: crate::path::raydiff::EXP_MAX,
                };
            }
            Kind::FlatUv => {
                return RayDiffFootprint {
                    m: [[0; 2]; 2],
                    e: EXP_MIN,
                };
            }
        }
        let g = self.g;
        // |g·p| ≤ |g|·|p| < √3·2³⁰·√3·2³¹: each sum of three multiply-highs
        // is below 3·2²⁹.
        // ∂P/∂x and ∂P/∂y at their one exponent.
        let p = s.pair(0);
        let axis = |m: [i32; 3]| -> [i32; 2] {
            let dot = |r: [i32; 3]| mulhi(r[0], m[0]) + mulhi(r[1], m[1]) + mulhi(r[2], m[2]);
            [dot(g[0]), dot(g[1])]
        };
        RayDiffFootprint {
            m: [axis(p.m[0]), axis(p.m[1])],
            e: self.e + p.e + 32,
        }
    }
}

impl RayDiffFootprint {
    /// Lod of the footprint: `log2` of the larger axis length in level-0
    /// texels (the hardware paper's eq. 1), rounded to 1/256 level,
    /// saturating (a zero footprint gives [`Lod::MIN`], a degenerate
    /// triangle's [`Lod::MAX`]). Within [`RAYDIFF_LOD_MAX_ERROR`] of f64
    /// (conditions in the [module docs](self)). Per hit; never panics.
    #[must_use]
    #[inline]
    pub fn lod(&self) -> Lod {
        // |a|² of each axis: |u|, |v| < 1.5·2³⁰, so the sum is below 2⁶³.
        let len2 =
            |[u, v]: [i32; 2]| (i64::from(u) * i64::from(u) + i64::from(v) * i64::from(v)) as u64;
        // Both axes at one exponent: the larger square is the longer axis.
        let l = half_log2(len2(self.m[0]).max(len2(self.m[1])), self.e);
        // I16F16 → I8F8, rounded, saturating.
        let r = (l + 0x80) >> 8;
        Lod::from_bits(r.clamp(i32::from(i16::MIN), i32::from(i16::MAX)) as i16)
    }

    /// Both axes `[(∂u/∂x, ∂v/∂x), (∂u/∂y, ∂v/∂y)]` in normalized texture
    /// coordinates (the texel axes times `1/w`, `1/h` of `tri`, the
    /// triangle it was taken on), saturating: what
    /// [`crate::texture::sampler::aniso::probes`] takes. Per hit (with
    /// anisotropic filtering); never panics.
    #[must_use]
    pub fn axes(&self, tri: &RayDiffTriangle) -> Footprint {
        let c = |a: usize, k: usize| {
            let (im, ie) = tri.inv[k];
            texcoord(mulhi(self.m[a][k], im), self.e + ie + 32)
        };
        Footprint {
            x: [c(0, 0), c(0, 1)],
            y: [c(1, 0), c(1, 1)],
        }
    }
}

/// `½·log2 max(s₀·4^e₀, s₁·4^e₁)` in I16F16 bits: the log2 of the larger
/// of two lengths whose squares are `sᵢ·4^eᵢ` (`eᵢ` clamped to
/// `[−1024, 1023]`, a zero `sᵢ` never wins, both zero give `−2²⁷`). The square's top 32 bits
/// and the crate's table logarithm: within `2⁻¹⁴ + 2⁻³¹` of the exact
/// value (the table's `2⁻¹³` halved). Shared with the environment map's
/// ray-differential lod.
#[cfg(any(feature = "envmap", test))]
#[inline(always)]
pub(crate) fn half_log2_max(s: [u64; 2], e: [i32; 2]) -> i32 {
    half_log2_of_key(log_key(s[0], e[0]).max(log_key(s[1], e[1])))
}

/// [`half_log2_max`] of one length (`½·log2(s·4ᵉ)`, zero: `−2²⁷`): bit for
/// bit `half_log2_max([s, 0], [e, e])`, as a zero square never wins.
#[inline(always)]
fn half_log2(s: u64, e: i32) -> i32 {
    half_log2_of_key(log_key(s, e))
}

/// The key that orders squares `s·4ᵉ` (log2 integer part, mantissa) as
/// one u64: `2·e` (clamped to `[−2048, 2046]`, one `ssat`) plus the top
/// bit's index, offset to stay positive, above the normalised mantissa. A
/// zero square gets key 0 and never wins.
#[inline(always)]
fn log_key(s: u64, e: i32) -> u64 {
    let (m, lz) = normalise64(s);
    let k = (2 * e.clamp(-1024, 1023) + 63 - lz as i32 + 4096) as u64;
    // `k << 32` and the 32-bit mantissa share no bit: the sum packs them.
    if s == 0 { 0 } else { (k << 32) + u64::from(m) }
}

/// `½·log2` of the square whose [`log_key`] is `top`, in I16F16 bits.
#[inline(always)]
fn half_log2_of_key(top: u64) -> i32 {
    let (k, m) = ((top >> 32) as i32 - 4096, top as u32);
    // k ∈ [−4096, 2109] (−4096: zero): the I16F16 sum fits.
    ((k << 16) + mantissa_log2(m) as i32) >> 1
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::path::raydiff::{DirDiff, PosDiff};
    use proptest::prelude::*;
    use raymip_reference::raydiff::{self as rf, V, dot, norm};

    fn tex(p: [V; 3], uv: [[f64; 2]; 3], w: u32, h: u32) -> (TexTriangle, rf::Triangle) {
        let pq = p.map(|v| v.map(Coord::saturating_from_num));
        let uq = uv.map(|v| v.map(TexCoord::saturating_from_num));
        let t = TexTriangle::new(pq, uq, w, h).unwrap();
        let r = rf::Triangle {
            p: pq.map(|v| v.map(|x| x.to_num())),
            uv: uq.map(|v| v.map(|x| x.to_num())),
            w,
            h,
        };
        (t, r)
    }

    fn state(px: V, py: V) -> RayDiff {
        RayDiff::new(
            PosDiff::from_f64(px),
            PosDiff::from_f64(py),
            DirDiff::ZERO,
            DirDiff::ZERO,
        )
    }

    /// The texel gradients in f64.
    fn gradients(t: &RayDiffTriangle) -> [V; 2] {
        t.g.map(|r| r.map(|m| f64::from(m) * f64::from(t.e).exp2()))
    }

    #[test]
    fn fronto_parallel_square_one_texel_per_pixel() {
        let (t, _) = tex(
            [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
            256,
            256,
        );
        let t = RayDiffTriangle::new(&t);
        let s = 1.0 / 256.0;
        let fp = t.footprint(&state([s, 0.0, 0.0], [0.0, s, 0.0]));
        assert_eq!(fp.lod(), Lod::ZERO);
        let axes = fp.axes(&t);
        assert_eq!(axes.x[0].to_num::<f64>(), s);
        assert_eq!(axes.y[1].to_num::<f64>(), s);
        assert_eq!(
            t.footprint(&state([4.0 * s, 0.0, 0.0], [0.0, s, 0.0]))
                .lod(),
            Lod::from_num(2)
        );
        assert_eq!(t.footprint(&state([0.0; 3], [0.0; 3])).lod(), Lod::MIN);
    }

    #[test]
    fn degenerate_classes_are_exact_at_any_size() {
        let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let c = |x: i64| Coord::from_bits(x);
        let any = state([1.0, 2.0, 3.0], [-1.0, 0.5, 0.0]);
        // p₂ = 2p₁ − p₀ exactly, with coordinates up to the I32F32 limits.
        for (a, b) in [
            (1i64, 3i64),
            (i64::MAX / 4, -(i64::MAX / 4)),
            (-(1 << 62), 1 << 61),
            (12345, -98765),
        ] {
            let p0 = [c(a), c(b), c(a ^ b)];
            let p1 = [c(b / 2), c(a / 2), c(3)];
            let p2: [Coord; 3] = core::array::from_fn(|k| c(2 * p1[k].to_bits() - p0[k].to_bits()));
            let uvq = uv.map(|v| v.map(TexCoord::from_num));
            let t = RayDiffTriangle::new(&TexTriangle::new([p0, p1, p2], uvq, 8, 8).unwrap());
            assert!(t.is_degenerate(), "{a} {b}");
            assert_eq!(t.footprint(&any).lod(), Lod::MAX);
            // One raw unit off the line: a sliver, not degenerate.
            let mut off = p2;
            off[1] = c(off[1].to_bits() ^ 1);
            let t = RayDiffTriangle::new(&TexTriangle::new([p0, p1, off], uvq, 8, 8).unwrap());
            assert!(!t.is_degenerate(), "{a} {b} off");
            // Coincident vertices.
            let t = RayDiffTriangle::new(&TexTriangle::new([p0, p1, p1], uvq, 8, 8).unwrap());
            assert!(t.is_degenerate());
        }
        let p = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        for flat in [[[0.5, 0.5]; 3], [[0.0, 0.0], [0.25, 0.5], [0.5, 1.0]]] {
            let (t, _) = tex(p, flat, 64, 64);
            let t = RayDiffTriangle::new(&t);
            assert!(t.is_flat_uv() && !t.is_degenerate());
            let fp = t.footprint(&any);
            assert_eq!(fp.lod(), Lod::MIN);
            assert_eq!(fp.axes(&t), Footprint::default());
        }
        // The degenerate footprint is the largest one for anisotropy.
        let (t, _) = tex([[0.0; 3], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]], uv, 64, 64);
        let t = RayDiffTriangle::new(&t);
        let a = t.footprint(&any).axes(&t);
        assert_eq!((a.x[0], a.y[1]), (TexCoord::MAX, TexCoord::MAX));
    }

    #[test]
    fn the_larger_of_two_lengths() {
        let l = |s: [u64; 2], e: [i32; 2]| f64::from(half_log2_max(s, e)) / 65536.0;
        assert_eq!(l([4, 1], [0, 0]), 1.0);
        assert_eq!(l([1, 4], [0, 0]), 1.0);
        assert_eq!(l([1, 1], [3, 0]), 3.0);
        // A zero axis never wins, whatever its exponent.
        assert_eq!(l([0, 16], [500, -10]), -8.0);
        assert_eq!(l([0, 0], [5, 5]), -2048.0);
        assert_eq!(l([u64::MAX, 1], [i32::MAX, i32::MIN]), 1023.0 + 32.0);
    }

    fn coord() -> impl Strategy<Value = f64> {
        prop_oneof![-1.0e3..1.0e3f64, -4.0..4.0f64]
    }
    fn v3() -> impl Strategy<Value = V> {
        [coord(), coord(), coord()]
    }
    fn unit() -> impl Strategy<Value = V> {
        [-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64].prop_filter("non-zero", |v| dot(*v, *v) > 1e-4)
    }

    /// Footprint mantissas as the footprint makes them (`|·| < 1.5·2³⁰`),
    /// zero and small ones as often as large.
    fn fp_mantissa() -> impl Strategy<Value = i32> {
        prop_oneof![
            Just(0),
            Just(-1),
            (any::<i32>(), 1u32..32).prop_map(|(m, s)| m >> s)
        ]
    }

    /// Squares of any size, zero as often as not.
    fn square() -> impl Strategy<Value = u64> {
        prop_oneof![Just(0), (any::<u64>(), 0u32..64).prop_map(|(x, k)| x >> k)]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(5_000))]

        /// The lod of any footprint (both axes at one exponent) is `log2`
        /// of the longer axis in f64 within LOD_ROUNDING_ERROR (clamped to
        /// the Lod range), and `Lod::MIN` for a zero footprint.
        #[test]
        fn lod_is_the_longer_axis(m in [fp_mantissa(), fp_mantissa(), fp_mantissa(), fp_mantissa()],
                                  e in -300i32..300) {
            let fp = RayDiffFootprint { m: [[m[0], m[1]], [m[2], m[3]]], e };
            let len = |a: usize| {
                f64::from(fp.m[a][0]).hypot(f64::from(fp.m[a][1])) * f64::from(fp.e).exp2()
            };
            let top = len(0).max(len(1));
            let got = fp.lod();
            if top == 0.0 {
                prop_assert_eq!(got, Lod::MIN);
            } else {
                let want = top.log2().clamp(-128.0, 127.99609375);
                let got = got.to_num::<f64>();
                prop_assert!((got - want).abs() <= LOD_ROUNDING_ERROR, "{} vs {}", got, want);
            }
        }

        /// `half_log2_max` of two squares at two exponents (the
        /// environment map's two direction differentials) is half the f64
        /// log2 of the larger within 2⁻¹⁴ + 2⁻¹⁶ (the table's error halved,
        /// the truncations and the I16F16 step), `−2048` when both are zero,
        /// and one length alone gives the same value as the pair with a
        /// zero square.
        #[test]
        fn half_log2_of_the_larger_square(s in [square(), square()],
                                          e in -300i32..300, de in prop_oneof![Just(0), -70i32..70]) {
            let e2 = [e, e + de];
            let got = f64::from(half_log2_max(s, e2)) / 65536.0;
            let sq = |i: usize| s[i] as f64 * f64::from(2 * e2[i]).exp2();
            let top = sq(0).max(sq(1));
            if top == 0.0 {
                prop_assert_eq!(got, -2048.0);
            } else {
                let want = 0.5 * top.log2();
                prop_assert!((got - want).abs() <= 1.0 / 16_384.0 + 1.0 / 65_536.0, "{} vs {}", got, want);
            }
            for i in 0..2 {
                prop_assert_eq!(half_log2(s[i], e2[i]), half_log2_max([s[i], 0], [e2[i], e2[1 - i]]));
            }
        }

        /// Set-up, footprint and lod against f64 over the documented range:
        /// slivers to 2²⁰:1 (and unit UVs on them: anisotropy 2²⁰), u and v
        /// ranges differing by up to 2¹⁶, UV gradients from 2⁻³⁰ to 2¹⁰
        /// units per scene unit, textures of 1–4096 texels. Gradients within
        /// 2⁻²⁸ of the largest, axes within FOOTPRINT_ERROR, the lod within
        /// LOD_ROUNDING_ERROR + log2(1 + ρ).
        #[test]
        fn setup_footprint_and_lod_match_f64(
            p0 in v3(), a in unit(), b in unit(), len in -6.0..10.0f64, aspect in 0.0..20.0f64,
            lam in -0.5..1.5f64, g in -30.0..10.0f64, lop in -16.0..16.0f64, th in 0.0..6.3f64,
            unit_uv in any::<bool>(), w in 0u32..13, h in 0u32..13, dpx in unit(), dpy in unit(), ps in -20.0..10.0f64,
            aniso in -40.0..40.0f64,
        ) {
            let (w, h) = (1u32 << w, (1u32 << h).max(1) - u32::from(h > 3));
            let l = len.exp2();
            let bn = rf::unit(rf::axpy(b, -dot(a, b) / dot(a, a), a));
            prop_assume!(norm(bn) > 0.5);
            let an = rf::unit(a);
            let at = |x: f64, y: f64| rf::axpy(rf::axpy(p0, l * x, an), l * y, bn);
            let p = [at(0.0, 0.0), at(1.0, 0.0), at(lam, (-aspect).exp2())];
            let (gu, gv) = ((g + lop.max(0.0)).exp2() / l.max(1.0), (g - lop.min(0.0) - lop.max(0.0)).exp2() / l.max(1.0));
            let uv = if unit_uv {
                [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
            } else {
                p.map(|v| {
                    let (x, y) = (dot(rf::axpy(v, -1.0, p0), an), dot(rf::axpy(v, -1.0, p0), bn));
                    [gu * (th.cos() * x - th.sin() * y), gv * (th.sin() * x + th.cos() * y)]
                })
            };
            let (tq, tr) = tex(p, uv, w, h);
            let t = RayDiffTriangle::new(&tq);
            prop_assert_eq!(t.is_degenerate(), tr.is_degenerate());
            prop_assert_eq!(t.is_flat_uv(), !tr.is_degenerate() && tr.is_flat_uv());
            let Some(m) = tr.texel_gradients() else { return Ok(()); };
            let big = m.iter().flatten().fold(0.0f64, |x, y| x.max(y.abs()));
            let got = gradients(&t);
            for r in 0..2 {
                for k in 0..3 {
                    prop_assert!((got[r][k] - m[r][k]).abs() <= 2f64.powi(-28) * big,
                        "M[{}][{}]: {:e} vs {:e}", r, k, got[r][k], m[r][k]);
                }
            }
            // Position differentials in the triangle's plane (as a transfer
            // leaves them), of any size.
            let nrm = rf::unit(rf::cross(rf::axpy(tr.p[1], -1.0, tr.p[0]), rf::axpy(tr.p[2], -1.0, tr.p[0])));
            // ∂P/∂y up to 2⁴⁰ times longer or shorter than ∂P/∂x (one
            // exponent for both: the shorter keeps the longer's absolute
            // precision).
            let inplane = |v: V, k: f64| rf::scale((ps + k).exp2(), rf::axpy(v, -dot(v, nrm), nrm));
            let s = state(inplane(dpx, 0.0), inplane(dpy, aniso));
            let (px, py) = (s.dox().to_f64(), s.doy().to_f64());
            let fp = t.footprint(&s);
            let rf::Footprint::Axes(want) = tr.footprint(px, py) else { unreachable!() };
            let texel = |a: [f64; 2]| [a[0] * f64::from(w), a[1] * f64::from(h)];
            let (wx, wy) = (texel(want[0]), texel(want[1]));
            let fa = |a: usize| -> [f64; 2] { fp.m[a].map(|x| f64::from(x) * f64::from(fp.e).exp2()) };
            let pmax = norm(px).max(norm(py));
            for (a, wa) in [(0, wx), (1, wy)] {
                let e = (fa(a)[0] - wa[0]).hypot(fa(a)[1] - wa[1]);
                prop_assert!(e <= FOOTPRINT_ERROR * big * pmax, "axis {}: {:e}", a, e / (big * pmax));
            }
            let fmax = wx[0].hypot(wx[1]).max(wy[0].hypot(wy[1]));
            prop_assume!(fmax > 0.0);
            let rho = FOOTPRINT_ERROR * big * norm(px).max(norm(py)) / fmax;
            prop_assume!(rho < 0.5);
            let want_lod = tr.lod(&tr.footprint(px, py)).clamp(-128.0, 127.99609375);
            let bound = LOD_ROUNDING_ERROR + (-(1.0 - rho).log2());
            let got_lod = fp.lod().to_num::<f64>();
            prop_assert!((got_lod - want_lod).abs() <= bound, "lod {} vs {} (ρ {:e})", got_lod, want_lod, rho);
            // The normalized axes for anisotropic filtering (I32F32 steps).
            let ax = fp.axes(&t);
            let size = [f64::from(w), f64::from(h)];
            for (g, wa) in [(ax.x, want[0]), (ax.y, want[1])] {
                for k in 0..2 {
                    let tol = 2.0 * FOOTPRINT_ERROR * big * norm(px).max(norm(py)) / size[k] + 2f64.powi(-31);
                    let e = (g[k].to_num::<f64>() - wa[k]).abs();
                    prop_assert!(e <= tol || g[k].to_num::<f64>().abs() >= 2f64.powi(30), "axes {:e} > {:e}", e, tol);
                }
            }
        }
    }
}
