//! Random camera chains for the ray differentials: a pinhole camera's pixel
//! ray through 0–10 bounces (planes, convex and concave mirrors,
//! refractions up to total internal reflection) to a textured triangle, run
//! through the firmware (`raymip::path::raydiff`, by the [`Firmware`] adapter) and
//! through the f64 reference ([`raymip_reference::raydiff`]) on the same
//! quantised inputs, with the lod of each and the chain's error
//! amplification. One generator per case [`Class`] of the firmware's
//! documented input range; used by the bound tests
//! (`tests/harness/raydiff_chains.rs`), the fuzz target `raydiff_chain` and
//! the `raydiff_accuracy` example (error per class).
//!
//! # Amplification
//!
//! Besides both lods, [`run`] propagates a first-order bound of the
//! firmware's error along the chain in f64: each firmware operation is
//! exact on its (stored) inputs up to a local error of at most
//! `c_op · |scale_op|` ([`Local`], the constants the firmware's module docs
//! derive), and each operation's Jacobian carries the input errors forward
//! (`1/|D·n|` for a transfer, `|κ|` from a curved surface's normal
//! differentials, `η + |∂μ/∂cos θᵢ|` for a refraction, `|M|` from the
//! texel-space gradients of the triangle). The result, divided by the
//! footprint's larger axis, bounds the relative footprint error; its value
//! with every `c_op = 1` is the chain's amplification [`Outcome::amp`].

use raymip::units::Lod;

use raymip::rng::XorShift64;
use raymip_reference::Draw;
use raymip_reference::raydiff::{
    self as rf, Diff, MIN_COS, Triangle, V, axpy, cross, dot, norm, scale, unit,
};

/// The case classes of the input range.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Class {
    /// Ordinary triangles and UVs, up to two planar bounces, `cos ≥ 2⁻³`.
    Ordinary,
    /// Sliver triangles, edge aspect `2¹⁰`–`2²⁰`, planar or unit UVs.
    Sliver,
    /// `u` and `v` ranges differing by `2⁴`–`2¹⁶`.
    Lopsided,
    /// UV gradients of `2⁻³⁰`–`2⁻²⁰` normalized units per scene unit.
    SlowUv,
    /// Collinear or coincident vertices (zero world area): `Lod::MAX`.
    Collinear,
    /// Zero UV area (collinear or equal UVs): `Lod::MIN`.
    FlatUv,
    /// One to three hits at `|D·n|` down to `MIN_COS`.
    Grazing,
    /// Ten bounces through planes, convex and concave mirrors and
    /// refractions (`η` 0.5–2, near-critical and total internal reflection).
    Chain,
    /// A concave mirror and the next hit near its focus.
    Focus,
}

/// Every class, in report order.
pub const CLASSES: [Class; 9] = [
    Class::Ordinary,
    Class::Sliver,
    Class::Lopsided,
    Class::SlowUv,
    Class::Collinear,
    Class::FlatUv,
    Class::Grazing,
    Class::Chain,
    Class::Focus,
];

impl Class {
    /// Short name (reports, test names).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Ordinary => "ordinary",
            Self::Sliver => "sliver",
            Self::Lopsided => "lopsided-uv",
            Self::SlowUv => "slow-uv",
            Self::Collinear => "collinear",
            Self::FlatUv => "zero-uv-area",
            Self::Grazing => "grazing",
            Self::Chain => "chain-10",
            Self::Focus => "focus",
        }
    }
}

/// Local error constants of the firmware's operations: the largest
/// component of an operation's error is at most `c_op` times its scale
/// (the scales of the firmware's module docs, restated per field). See the
/// [module docs](self).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Local {
    /// Primary set-up, relative to `(|D·f| + 1)·|r|`.
    pub primary: f64,
    /// Transfer, relative to `(|∂O| + t·|∂D|)·(1 + 1/|D·n|)`.
    pub transfer: f64,
    /// Reflection, relative to `|∂D| + 4|∂n|`.
    pub reflect: f64,
    /// Refraction, relative to `(1 + 2η + η²/cos θₜ)·(|∂D| + |∂n|)`.
    pub refract: f64,
    /// Normal differentials handed to the firmware (their rounding),
    /// relative to `|∂n|`.
    pub normal: f64,
    /// Footprint axis (Euclidean), relative to `|M|∞·|∂P|`, `|M|∞` the
    /// largest texel-space gradient component.
    pub footprint: f64,
    /// The lod from the footprint: absolute, in levels (table logarithm
    /// and rounding).
    pub lod: f64,
}

impl Local {
    /// Every relative constant 2⁻³⁰ and no absolute lod term: the bound
    /// is then the chain's amplification times 2⁻³⁰ (see [`Outcome::amp`]).
    pub const UNIT: Self = Self {
        primary: 1.0 / 1_073_741_824.0,
        transfer: 1.0 / 1_073_741_824.0,
        reflect: 1.0 / 1_073_741_824.0,
        refract: 1.0 / 1_073_741_824.0,
        normal: 1.0 / 1_073_741_824.0,
        footprint: 1.0 / 1_073_741_824.0,
        lod: 0.0,
    };
}

/// The firmware under test, seen through f64: quantisers (the value the
/// firmware receives for an f64 input) and the operations on its state.
pub trait Firmware {
    /// The firmware's differential state.
    type State: Copy;
    /// A unit vector (direction, normal).
    fn q_unit(&self, v: V) -> V;
    /// A hit distance.
    fn q_len(&self, t: f64) -> f64;
    /// A camera axis step or a normal differential.
    fn q_dvec(&self, v: V) -> V;
    /// A relative index of refraction.
    fn q_eta(&self, eta: f64) -> f64;
    /// `cos θₜ`.
    fn q_cos(&self, c: f64) -> f64;
    /// A vertex coordinate or UV.
    fn q_coord(&self, x: f64) -> f64;
    /// Primary set-up.
    fn primary(&self, d: V, f: V, r: V, u: V) -> Self::State;
    /// Transfer.
    fn transfer(&self, s: &Self::State, d: V, t: f64, n: V) -> Self::State;
    /// Reflection.
    fn reflect(&self, s: &Self::State, d: V, n: V, dn: [V; 2]) -> Self::State;
    /// Refraction.
    fn refract(&self, s: &Self::State, d: V, n: V, dn: [V; 2], eta: f64, cos_t: f64)
    -> Self::State;
    /// The state in f64.
    fn to_f64(&self, s: &Self::State) -> Diff;
    /// Triangle set-up, footprint and lod of a hit with state `s`.
    fn lod(&self, tri: &Triangle, s: &Self::State) -> f64;
    /// The local error constants of the operations.
    fn local(&self) -> Local;
}

/// One chain's result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome {
    /// Its class.
    pub class: Class,
    /// The firmware's lod (levels).
    pub lod: f64,
    /// The reference lod, clamped to the [`Lod`] range.
    pub want: f64,
    /// `|lod − want|`.
    pub err: f64,
    /// The firmware's first-order error bound ([`Firmware::local`]), in
    /// levels (0 for the degenerate classes, which must be exact; `∞`
    /// where the relative footprint error may reach ½).
    pub bound: f64,
    /// The chain's amplification: the relative footprint error bound with
    /// every local constant 1 ([`Local::UNIT`] scaled by 2³⁰).
    pub amp: f64,
    /// Smallest `|D·n|` (and `cos θₜ`) on the path.
    pub cos_min: f64,
    /// Bounces before the textured hit.
    pub bounces: u32,
}

/// Uniform in `[2^lo, 2^hi)` on a log scale.
fn log_uniform(rng: &mut XorShift64, lo: f64, hi: f64) -> f64 {
    rng.range(lo, hi).exp2()
}

/// True with probability `1/k`.
fn one_in(rng: &mut XorShift64, k: u64) -> bool {
    rng.next_u64().is_multiple_of(k)
}

/// A random unit vector.
fn random_unit(rng: &mut XorShift64) -> V {
    loop {
        let v = [
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        ];
        let l = norm(v);
        if l > 0.1 && l <= 1.0 {
            return scale(1.0 / l, v);
        }
    }
}

/// Two unit vectors completing `n` to an orthonormal basis.
fn basis(n: V) -> (V, V) {
    let h = if n[0].abs() < 0.6 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let a = unit(cross(n, h));
    (a, cross(n, a))
}

/// A unit normal facing `d` at `|D·n| = c`, otherwise random.
fn facing_normal(rng: &mut XorShift64, d: V, c: f64) -> V {
    let (a, b) = basis(d);
    let phi = rng.range(0.0, core::f64::consts::TAU);
    let w = axpy(scale(phi.cos(), a), phi.sin(), b);
    let s = (1.0 - c * c).max(0.0).sqrt();
    unit(axpy(scale(-c, d), s, w))
}

/// `|D·n|` of a hit: ordinary in `[2⁻³, 1]`, grazing down to `MIN_COS`.
fn cosine(rng: &mut XorShift64, grazing: bool) -> f64 {
    if grazing {
        log_uniform(rng, -16.0, -4.0).max(MIN_COS)
    } else {
        rng.range(0.125, 1.0)
    }
}

/// Both chains and the first-order error bounds of the firmware's state
/// (Euclidean, per vector `∂O/∂x, ∂O/∂y, ∂D/∂x, ∂D/∂y`), once with the
/// firmware's constants and once with [`Local::UNIT`].
struct Chain<'a, F: Firmware> {
    fw: &'a F,
    loc: [Local; 2],
    s: F::State,
    rf: Diff,
    bound: [[f64; 4]; 2],
    d: V,
    cos_min: f64,
}

/// `√3`: an ∞-norm bound of a 3-vector as a Euclidean one.
const SQRT3: f64 = 1.732_050_807_568_877_2;

/// The larger length of a pair of differentials (`x`, `y`): the scale of
/// the firmware's local errors, whose pairs share one exponent.
fn pair_norm(a: V, b: V) -> f64 {
    norm(a).max(norm(b))
}

impl<F: Firmware> Chain<'_, F> {
    /// Transfer to a hit at `t` on the plane of normal `n`: the bounds
    /// grow by the projection's `1/|D·n|` and the local error.
    fn transfer(&mut self, t: f64, n: V) {
        let c = dot(self.d, n).abs().max(MIN_COS);
        self.cos_min = self.cos_min.min(c);
        let before = self.rf;
        self.s = self.fw.transfer(&self.s, self.d, t, n);
        self.rf = rf::transfer(&self.rf, self.d, t, n);
        // The local error's scale is the pair's (one exponent for the x
        // and y differentials): the larger `∂O` plus `t` times the larger
        // `∂D`.
        let sc = (pair_norm(before.dox, before.doy) + t * pair_norm(before.ddx, before.ddy))
            * (1.0 + 1.0 / c);
        for (b, l) in self.bound.iter_mut().zip(&self.loc) {
            for a in 0..2 {
                b[a] = (b[a] + t * b[2 + a]) / c + SQRT3 * l.transfer * sc;
            }
        }
    }

    /// Reflection (`refract: None`) or refraction `(η, cos θₜ)` at a
    /// surface of normal `n` and curvature `kappa` (`∂n = κ·∂P`, each side
    /// from its own `∂P`).
    fn bounce(&mut self, n: V, kappa: f64, refract: Option<(f64, f64)>) {
        let fwd = self.fw.to_f64(&self.s);
        let dn_fw = [fwd.dox, fwd.doy].map(|p| self.fw.q_dvec(scale(kappa, p)));
        let dn = [scale(kappa, self.rf.dox), scale(kappa, self.rf.doy)];
        let before = self.rf;
        let dd = [before.ddx, before.ddy];
        let d = self.d;
        // (Jacobian of ∂D, of ∂n, the local scale's factor) per operation.
        let (gd, gn, sc) = match refract {
            None => {
                self.s = self.fw.reflect(&self.s, d, n, dn_fw);
                self.rf = rf::reflect(&before, d, n, dn[0], dn[1]);
                (
                    1.0,
                    4.0,
                    pair_norm(dd[0], dd[1]) + 4.0 * pair_norm(dn[0], dn[1]),
                )
            }
            Some((eta, ct)) => {
                let ct = ct.max(MIN_COS);
                self.cos_min = self.cos_min.min(ct);
                let ci = -dot(d, n);
                self.s = self.fw.refract(&self.s, d, n, dn_fw, eta, ct);
                self.rf = rf::refract(&before, d, n, dn[0], dn[1], eta, ct);
                let mu = (eta * ci - ct).abs();
                let coef = (eta - eta * eta * ci / ct).abs();
                let k = 1.0 + 2.0 * eta + eta * eta / ct;
                (
                    eta + coef,
                    coef + mu,
                    k * (pair_norm(dd[0], dd[1]) + pair_norm(dn[0], dn[1])),
                )
            }
        };
        for (b, l) in self.bound.iter_mut().zip(&self.loc) {
            let local = if refract.is_some() {
                l.refract
            } else {
                l.reflect
            };
            for a in 0..2 {
                let bn = kappa.abs() * b[a] + SQRT3 * l.normal * norm(dn[a]);
                b[2 + a] = gd * b[2 + a] + gn * bn + SQRT3 * local * sc;
            }
        }
    }
}

/// Runs one chain of class `class` from `rng`.
pub fn run<F: Firmware>(fw: &F, class: Class, rng: &mut XorShift64) -> Outcome {
    let loc = [fw.local(), Local::UNIT];
    // Camera: unit forward axis, per-pixel steps γ ⟂ f, a pixel anywhere
    // in a 1024² image.
    let f = fw.q_unit(random_unit(rng));
    let (ra, ua) = basis(f);
    let gamma = log_uniform(rng, -14.0, -6.0);
    let r = fw.q_dvec(scale(gamma, ra));
    let u = fw.q_dvec(scale(gamma, ua));
    let (px, py) = (rng.range(-512.0, 512.0), rng.range(-512.0, 512.0));
    let d = fw.q_unit(unit(axpy(axpy(f, px, r), py, u)));
    let rf0 = rf::primary(d, f, r, u);
    let p = (dot(d, f).abs() + 1.0) * SQRT3;
    let mut ch = Chain {
        fw,
        loc,
        s: fw.primary(d, f, r, u),
        rf: rf0,
        bound: loc.map(|l| {
            let b = p * l.primary * pair_norm(r, u);
            [0.0, 0.0, b, b]
        }),
        d,
        cos_min: 1.0,
    };
    let bounces = match class {
        Class::Chain => 10,
        Class::Focus => 1 + (rng.next_u64() % 3) as u32,
        _ => (rng.next_u64() % 3) as u32,
    };
    let grazing_at = (rng.next_u64() % u64::from(bounces + 1)) as u32;
    let mut focus_t = None;
    let mut last_n = f;
    for k in 0..=bounces {
        let graze = class == Class::Grazing && (k == bounces || k == grazing_at);
        let c = cosine(rng, graze);
        let n = fw.q_unit(facing_normal(rng, ch.d, c));
        let t = fw.q_len(
            focus_t
                .take()
                .unwrap_or_else(|| log_uniform(rng, -4.0, 8.0)),
        );
        ch.transfer(t, n);
        last_n = n;
        if k == bounces {
            break;
        }
        // The surface: plane, convex or concave sphere of radius R.
        let roll = rng.next_u64() % 10;
        let curved = class == Class::Focus || (class == Class::Chain && roll >= 4);
        let (sigma, radius) = if curved {
            let concave = class == Class::Focus || one_in(rng, 2);
            (
                if concave { -1.0 } else { 1.0 },
                t * log_uniform(rng, -3.0, 3.0),
            )
        } else {
            (0.0, 1.0)
        };
        let cosi = dot(ch.d, n).abs();
        let mut refracted = None;
        if class == Class::Chain && roll.is_multiple_of(3) {
            let eta = fw.q_eta(log_uniform(rng, -1.0, 1.0));
            let kk = 1.0 - eta * eta * (1.0 - cosi * cosi);
            if kk >= 0.0 {
                let ct = fw.q_cos(kk.sqrt());
                ch.bounce(n, sigma / radius, Some((eta, ct)));
                refracted = Some(unit(axpy(scale(eta, ch.d), eta * cosi - ct, n)));
            }
        }
        let next = refracted.unwrap_or_else(|| {
            ch.bounce(n, sigma / radius, None);
            unit(axpy(ch.d, 2.0 * cosi, n))
        });
        if sigma < 0.0 && (class == Class::Focus || one_in(rng, 4)) {
            // Near the focus of the concave mirror (R/2, paraxial).
            let off = log_uniform(rng, -12.0, -2.0) * if one_in(rng, 2) { -1.0 } else { 1.0 };
            focus_t = Some(radius / 2.0 * (1.0 + off));
        }
        ch.d = fw.q_unit(next);
    }
    finish(&ch, class, triangle(fw, class, rng, last_n), bounces)
}

/// Both lods of the final state on `tri`, the error and the bound.
fn finish<F: Firmware>(ch: &Chain<'_, F>, class: Class, tri: Triangle, bounces: u32) -> Outcome {
    let want_raw = tri.lod(&tri.footprint(ch.rf.dox, ch.rf.doy));
    let want = want_raw.clamp(Lod::MIN.to_num(), Lod::MAX.to_num());
    let lod = ch.fw.lod(&tri, &ch.s);
    // Relative error bound of the larger footprint axis: the texel-space
    // gradients M carry the ∂P bounds (|M|, Frobenius) and add the
    // footprint's own error (relative to |M|∞·|∂P|).
    let rel = |b: &[f64; 4], l: &Local| -> f64 {
        let Some(m) = tri.texel_gradients() else {
            return 0.0;
        };
        let mf = norm(m[0]).hypot(norm(m[1]));
        let minf = m.iter().flatten().fold(0.0f64, |x, y| x.max(y.abs()));
        let axis = |p: V| norm([dot(m[0], p), dot(m[1], p), 0.0]);
        let big = axis(ch.rf.dox).max(axis(ch.rf.doy));
        let pmax = norm(ch.rf.dox).max(norm(ch.rf.doy));
        if big == 0.0 {
            return f64::INFINITY;
        }
        (mf * b[0].max(b[1]) + l.footprint * minf * pmax) / big
    };
    let degenerate = !want_raw.is_finite();
    let rho = rel(&ch.bound[0], &ch.loc[0]);
    let bound = if degenerate {
        0.0
    } else if rho >= 0.5 {
        f64::INFINITY
    } else {
        ch.loc[0].lod + (-(1.0 - rho).log2()).max((1.0 + rho).log2())
    };
    Outcome {
        class,
        lod,
        want,
        err: (lod - want).abs(),
        bound,
        amp: if degenerate {
            0.0
        } else {
            rel(&ch.bound[1], &ch.loc[1]) * 1_073_741_824.0
        },
        cos_min: ch.cos_min,
        bounces,
    }
}

/// The textured triangle at the last hit, in the plane of its normal
/// (`⟂ n`, any offset), shaped by the class; quantised by the firmware's
/// coordinate format (vertices below 2²⁰ on the 2⁻³² grid: the
/// reference decides the degenerate classes exactly).
fn triangle<F: Firmware>(fw: &F, class: Class, rng: &mut XorShift64, n: V) -> Triangle {
    let (a, b) = basis(n);
    let l = if class == Class::SlowUv {
        log_uniform(rng, 4.0, 12.0)
    } else {
        log_uniform(rng, -6.0, 8.0)
    };
    let c0 = [
        rng.range(-1024.0, 1024.0),
        rng.range(-1024.0, 1024.0),
        rng.range(-1024.0, 1024.0),
    ];
    let at = |x: f64, y: f64| axpy(axpy(c0, l * x, a), l * y, b);
    let mut p = match class {
        Class::Sliver => {
            let s = log_uniform(rng, 10.0, 20.0);
            let lam = rng.range(-0.5, 1.5);
            [at(0.0, 0.0), at(1.0, 0.0), at(lam, 1.0 / s)]
        }
        _ => loop {
            let q: [f64; 4] = core::array::from_fn(|_| rng.range(-1.0, 1.0));
            if (q[0] * q[3] - q[1] * q[2]).abs() > 0.05 {
                break [at(0.0, 0.0), at(q[0], q[1]), at(q[2], q[3])];
            }
        },
    };
    p = p.map(|v| v.map(|x| fw.q_coord(x)));
    if class == Class::Collinear {
        // p₂ = 2p₁ − p₀ on the grid (exact), or p₁ = p₀.
        p[2] = if rng.unit() < 0.75 {
            core::array::from_fn(|k| 2.0 * p[1][k] - p[0][k])
        } else {
            p[1]
        };
    }
    // Planar UVs: uv = A·(x, y) + offset with A of gradient scale g (per
    // scene unit) and anisotropy by class.
    let g = match class {
        Class::SlowUv => log_uniform(rng, -30.0, -20.0),
        _ => log_uniform(rng, -6.0, 4.0) / l,
    };
    let (gu, gv) = match class {
        Class::Lopsided => {
            let k = log_uniform(rng, 4.0, 16.0);
            if rng.unit() < 0.5 {
                (g, g / k)
            } else {
                (g / k, g)
            }
        }
        _ => (g * rng.range(0.5, 2.0), g * rng.range(0.5, 2.0)),
    };
    let th = rng.range(0.0, core::f64::consts::TAU);
    let off = [rng.range(-4.0, 4.0), rng.range(-4.0, 4.0)];
    let proj = |v: V| {
        let w = axpy(v, -1.0, c0);
        let (x, y) = (dot(w, a), dot(w, b));
        let (xr, yr) = (th.cos() * x - th.sin() * y, th.sin() * x + th.cos() * y);
        [off[0] + gu * xr, off[1] + gv * yr]
    };
    let unit_uv = class == Class::Sliver && rng.unit() < 0.5;
    let mut uv = if unit_uv {
        [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
    } else {
        p.map(proj)
    };
    uv = uv.map(|v| v.map(|x| fw.q_coord(x)));
    if class == Class::FlatUv {
        uv[2] = if rng.unit() < 0.75 {
            core::array::from_fn(|k| 2.0 * uv[1][k] - uv[0][k])
        } else {
            uv[0]
        };
        if rng.unit() < 0.2 {
            uv = [uv[0]; 3];
        }
    }
    let size = |rng: &mut XorShift64| (log_uniform(rng, 0.0, 12.0).round() as u32).clamp(1, 4096);
    Triangle {
        p,
        uv,
        w: size(rng),
        h: size(rng),
    }
}

/// The firmware's `raymip::path::raydiff` through the [`Firmware`] adapter.
#[derive(Clone, Copy, Debug, Default)]
pub struct Raymip;

mod adapter {
    use fixed::types::{I2F30, I4F28, U32F32};
    use raymip::lod::raydiff::RayDiffTriangle;
    use raymip::path::raydiff::{DirDiff, Eta, PosDiff, RayDiff};
    use raymip::setup::table::TexTriangle;
    use raymip::units::{Coord, PathLength, TexCoord, UnitVec};

    use super::{Diff, Firmware, Local, Raymip, Triangle, V};

    fn u(v: V) -> UnitVec {
        UnitVec(v.map(I2F30::saturating_from_num))
    }
    fn f(v: UnitVec) -> V {
        v.map(|x| x.to_num())
    }
    fn eta(e: f64) -> Eta {
        Eta::from_fixed(I4F28::saturating_from_num(e))
    }

    impl Firmware for Raymip {
        type State = RayDiff;
        fn q_unit(&self, v: V) -> V {
            f(u(v))
        }
        fn q_len(&self, t: f64) -> f64 {
            U32F32::saturating_from_num(t).to_num()
        }
        fn q_dvec(&self, v: V) -> V {
            DirDiff::from_f64(v).to_f64()
        }
        fn q_eta(&self, e: f64) -> f64 {
            eta(e).to_fixed().to_num()
        }
        fn q_cos(&self, c: f64) -> f64 {
            I2F30::saturating_from_num(c).to_num()
        }
        fn q_coord(&self, x: f64) -> f64 {
            Coord::saturating_from_num(x).to_num()
        }
        fn primary(&self, d: V, fw: V, r: V, up: V) -> RayDiff {
            RayDiff::primary(u(d), u(fw), DirDiff::from_f64(r), DirDiff::from_f64(up))
        }
        fn transfer(&self, s: &RayDiff, d: V, t: f64, n: V) -> RayDiff {
            let mut s = *s;
            s.transfer(u(d), PathLength::saturating_from_num(t), u(n));
            s
        }
        fn reflect(&self, s: &RayDiff, d: V, n: V, dn: [V; 2]) -> RayDiff {
            let mut s = *s;
            s.reflect(u(d), u(n), dn.map(DirDiff::from_f64));
            s
        }
        fn refract(&self, s: &RayDiff, d: V, n: V, dn: [V; 2], e: f64, cos_t: f64) -> RayDiff {
            let mut s = *s;
            s.refract(
                u(d),
                u(n),
                dn.map(DirDiff::from_f64),
                eta(e),
                I2F30::saturating_from_num(cos_t),
            );
            s
        }
        fn to_f64(&self, s: &RayDiff) -> Diff {
            Diff {
                dox: s.dox().to_f64(),
                doy: s.doy().to_f64(),
                ddx: s.ddx().to_f64(),
                ddy: s.ddy().to_f64(),
            }
        }
        fn lod(&self, tri: &Triangle, s: &RayDiff) -> f64 {
            let Ok(t) = TexTriangle::new(
                tri.p.map(|v| v.map(Coord::saturating_from_num)),
                tri.uv.map(|v| v.map(TexCoord::saturating_from_num)),
                tri.w,
                tri.h,
            ) else {
                return f64::NAN;
            };
            let _: PosDiff = s.dox();
            RayDiffTriangle::new(&t).footprint(s).lod().to_num()
        }
        fn local(&self) -> Local {
            use raymip::lod::raydiff as l;
            use raymip::path::raydiff as p;
            Local {
                primary: p::PRIMARY_ERROR,
                transfer: p::TRANSFER_ERROR,
                reflect: p::REFLECT_ERROR,
                refract: p::REFRACT_ERROR,
                // DirDiff::from_f64 truncates below 2⁻²⁹ of the largest.
                normal: 2f64.powi(-29),
                footprint: l::FOOTPRINT_ERROR,
                lod: l::LOD_ROUNDING_ERROR,
            }
        }
    }
}
