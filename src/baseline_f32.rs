//! The per-hit stages in `f32` (feature `f32`): table lod, cone lod and the
//! texture filters, as the comparison baseline.
//!
//! They are written with floats and [`libm`], with the same definitions as
//! the fixed-point modules. They are the comparison baseline of
//! `BUDGETS.md` (the same calls counted on Cortex-M4F, whose FPU runs them,
//! and on RV32IMAC, where they become soft-float calls) and of the host
//! benches; the fixed-point modules stay the product.
//!
//! Not for FPU-less cores' per-hit path (soft float); not bit-identical
//! across targets. Cost of the feature: nothing unless called (the module
//! adds no dependency: `libm` is already used at set-up).
//!
//! Definitions (as [`crate::lod`] and [`crate::texture::sampler`]):
//! `lod = log2 Pl − log2 Pb`; `λ = Δ + log2|w| − log2 max(|n·d|, 2⁻¹⁶)`
//! (`|n·d|` clamped to 1); texel centres at `(i + ½)/size`, any
//! [`AddressMode`] on both axes (indices mapped by
//! [`AddressMode::index`]; border texels are transparent black, the
//! default border colour), lod clamped to the stored levels, nearest level `floor(lod + ½)`,
//! blend weight `frac(lod)`.

use crate::texture::storage::mip::{Geometry, Texel};
use crate::texture::{AddressMode, Mode};

/// `log2 Pl − log2 Pb` in f32 for a path length `pl > 0` (scene units) and
/// the triangle's `log2 Pb`. `pl ≤ 0` or NaN gives NaN or −∞ (no check: the
/// float baseline of [`crate::lod::table_lod`]).
#[inline]
#[must_use]
pub fn table_lod_f32(pl: f32, log2_pb: f32) -> f32 {
    libm::log2f(pl) - log2_pb
}

/// Ray-cone `λ = Δ + log2|w| − log2|n·d|` in f32, `|n·d|` clamped to
/// `[2⁻¹⁶, 1]` as [`crate::lod::cone_lod`] does. `w = 0` gives −∞.
#[inline]
#[must_use]
pub fn cone_lod_f32(width: f32, delta: f32, n_dot_d: Option<f32>) -> f32 {
    let mut l = delta + libm::log2f(libm::fabsf(width));
    if let Some(c) = n_dot_d {
        l -= libm::log2f(libm::fabsf(c).clamp(1.0 / 65536.0, 1.0));
    }
    l
}

/// A pyramid sampled in f32 (same memory layout as
/// [`Pyramid`](crate::texture::storage::mip::Pyramid)).
///
/// # Example
/// ```
/// use raymip::baseline_f32::SamplerF32;
/// use raymip::{AddressMode, Geometry, Mode};
/// // A 2×1 texture, opaque black then white.
/// let texels = [0xFF00_0000u32, 0xFFFF_FFFF];
/// let geometry = Geometry::new(2, 1, 1)?;
/// let sampler = SamplerF32::new(geometry, &texels, AddressMode::ClampToEdge).ok_or("short")?;
/// // Midway between the texel centres ¼ and ¾: ½·0 + ½·255 = 127.5,
/// // rounded half up to 128 (alpha stays 255).
/// assert_eq!(sampler.sample(0.5, 0.5, 0.0, Mode::BilinearNearestLevel), 0xFF80_8080);
/// // At texel 0's centre: texel 0 exactly.
/// assert_eq!(sampler.sample(0.25, 0.5, 0.0, Mode::BilinearNearestLevel), 0xFF00_0000);
/// // A slice shorter than the geometry's texel count is refused.
/// assert!(SamplerF32::new(geometry, &texels[..1], AddressMode::Wrap).is_none());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct SamplerF32<'a> {
    geometry: Geometry,
    texels: &'a [Texel],
    address: AddressMode,
}

/// `floor` without a libm call (baseline x86-64 has no SSE4.1 `roundss`,
/// so `libm::floorf` would be a call): exact for every f32, since values
/// with `|x| ≥ 2²³` are integers already.
#[inline(always)]
fn floor(x: f32) -> f32 {
    if libm::fabsf(x) < 8_388_608.0 {
        let t = x as i32 as f32;
        if t > x { t - 1.0 } else { t }
    } else {
        x
    }
}

#[inline(always)]
fn channels(t: Texel) -> [f32; 4] {
    let b = t.to_le_bytes();
    [
        f32::from(b[0]),
        f32::from(b[1]),
        f32::from(b[2]),
        f32::from(b[3]),
    ]
}

#[inline(always)]
fn pack(c: [f32; 4]) -> Texel {
    // Round to nearest; `as u8` saturates (values are in [0, 255]).
    u32::from_le_bytes(c.map(|x| (x + 0.5) as u8))
}

impl<'a> SamplerF32<'a> {
    /// A sampler over `texels` laid out as `geometry` describes. `None`
    /// when the slice is too short.
    #[must_use]
    pub fn new(geometry: Geometry, texels: &'a [Texel], address: AddressMode) -> Option<Self> {
        (texels.len() >= geometry.len()).then_some(Self {
            geometry,
            texels,
            address,
        })
    }

    /// Index `i` of a level `n` wide, addressed (`None`: the border).
    #[inline(always)]
    fn fix(&self, i: i32, n: u32) -> Option<u32> {
        self.address.index(i, n)
    }

    #[inline(always)]
    fn reduce(&self, u: f32) -> f32 {
        match self.address {
            AddressMode::Wrap => u - floor(u),
            AddressMode::Mirror => u - 2.0 * floor(u * 0.5),
            AddressMode::ClampToEdge | AddressMode::ClampToBorder => u.clamp(-1.0, 2.0),
            AddressMode::MirrorOnce => u.clamp(-2.0, 2.0),
        }
    }

    #[inline(always)]
    fn texel(&self, level: u8, x: Option<u32>, y: Option<u32>) -> Texel {
        let (Some(x), Some(y)) = (x, y) else {
            return 0;
        };
        let (w, _) = self.geometry.level_size(level);
        let i = self.geometry.level_offset(level) + (y * w + x) as usize;
        self.texels.get(i).copied().unwrap_or(0)
    }

    #[inline(always)]
    fn bilinear(&self, u: f32, v: f32, level: u8) -> [f32; 4] {
        let (w, h) = self.geometry.level_size(level);
        let x = u * w as f32 - 0.5;
        let y = v * h as f32 - 0.5;
        let (x0, y0) = (floor(x), floor(y));
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i32, y0 as i32);
        let (xa, xb) = (self.fix(x0, w), self.fix(x0 + 1, w));
        let (ya, yb) = (self.fix(y0, h), self.fix(y0 + 1, h));
        let p = channels(self.texel(level, xa, ya));
        let q = channels(self.texel(level, xb, ya));
        let r = channels(self.texel(level, xa, yb));
        let s = channels(self.texel(level, xb, yb));
        let mut out = [0.0; 4];
        for c in 0..4 {
            let top = p[c] + (q[c] - p[c]) * fx;
            let bot = r[c] + (s[c] - r[c]) * fx;
            out[c] = top + (bot - top) * fy;
        }
        out
    }

    #[inline(always)]
    fn nearest(&self, u: f32, v: f32, level: u8) -> Texel {
        let (w, h) = self.geometry.level_size(level);
        let x = self.fix(floor(u * w as f32) as i32, w);
        let y = self.fix(floor(v * h as f32) as i32, h);
        self.texel(level, x, y)
    }

    /// Filtered texel at `(u, v)`, level of detail `lod`, in f32. Non-finite
    /// inputs give an unspecified texel (no panic).
    #[inline]
    pub fn sample(&self, u: f32, v: f32, lod: f32, mode: Mode) -> Texel {
        pack(self.filter(u, v, lod, mode))
    }

    /// Anisotropic sample in f32 with the definitions of [`crate::texture::sampler::aniso`]:
    /// `axes` = the footprint `[(du/dx, dv/dx), (du/dy, dv/dy)]` in
    /// normalized texture coordinates; with the axes in level-0 texels,
    /// `minor' = max(|minor|, |major| / max_aniso)` (`max_aniso` clamped to
    /// `1 ..= 16`), `N = min(max_aniso, ceil(|major| / minor'))` probes of
    /// filter `mode` at lod `log2 minor'`, at `(u, v) + t_i·major` with
    /// `t_i = (2i + 1 − N)/(2N)`; the unrounded probe values are averaged
    /// and rounded once. Non-finite inputs give an unspecified texel (no
    /// panic).
    pub fn sample_aniso(
        &self,
        u: f32,
        v: f32,
        axes: [[f32; 2]; 2],
        max_aniso: u8,
        mode: Mode,
    ) -> Texel {
        let (w, h) = (self.geometry.width() as f32, self.geometry.height() as f32);
        let len = |a: [f32; 2]| libm::hypotf(a[0] * w, a[1] * h);
        let (la, lb) = (len(axes[0]), len(axes[1]));
        let (major, l_major, l_minor) = if la >= lb {
            (axes[0], la, lb)
        } else {
            (axes[1], lb, la)
        };
        let max = f32::from(max_aniso.clamp(1, 16));
        let minor = l_minor.max(l_major / max).max(f32::MIN_POSITIVE);
        // `as u8` saturates (NaN → 0, then 1).
        let count = (libm::ceilf(l_major / minor).min(max) as u8).max(1);
        let lod = libm::log2f(minor);
        let n = f32::from(count);
        let mut acc = [0.0f32; 4];
        for i in 0..count {
            let t = (2.0 * f32::from(i) + 1.0 - n) / (2.0 * n);
            let c = self.filter(u + major[0] * t, v + major[1] * t, lod, mode);
            for (a, x) in acc.iter_mut().zip(c) {
                *a += x;
            }
        }
        pack(acc.map(|a| a / n))
    }

    /// The filter's unrounded channel values (0..=255).
    #[inline(always)]
    fn filter(&self, u: f32, v: f32, lod: f32, mode: Mode) -> [f32; 4] {
        let (u, v) = (self.reduce(u), self.reduce(v));
        let top = f32::from(self.geometry.top_level());
        let lod = lod.max(0.0).min(top);
        let lower = floor(lod);
        let t = lod - lower;
        let l0 = lower as u8;
        let nearest_level = floor(lod + 0.5).min(top) as u8;
        match mode {
            Mode::Trilinear => {
                let a = self.bilinear(u, v, l0);
                if t == 0.0 {
                    a
                } else {
                    let b = self.bilinear(u, v, l0.saturating_add(1));
                    [0, 1, 2, 3].map(|c| a[c] + (b[c] - a[c]) * t)
                }
            }
            Mode::BilinearNearestLevel => self.bilinear(u, v, nearest_level),
            Mode::Nearest => channels(self.nearest(u, v, nearest_level)),
            Mode::NearestTexelLinearLevel => {
                let a = channels(self.nearest(u, v, l0));
                if t == 0.0 {
                    a
                } else {
                    let b = channels(self.nearest(u, v, l0.saturating_add(1)));
                    [0, 1, 2, 3].map(|c| a[c] + (b[c] - a[c]) * t)
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::rng::XorShift64;
    use raymip_reference::sampler::{
        Address, Mode as RefMode, Sampler as RefSampler, State, Texture,
    };

    /// The filter modes and their f64 counterparts.
    const MODES: [(Mode, RefMode); 4] = [
        (Mode::Trilinear, RefMode::Trilinear),
        (Mode::BilinearNearestLevel, RefMode::BilinearNearestLevel),
        (Mode::Nearest, RefMode::Nearest),
        (
            Mode::NearestTexelLinearLevel,
            RefMode::NearestTexelLinearLevel,
        ),
    ];

    /// Each channel of `got` within ½ + 1/64 of the unrounded f64 value:
    /// the final rounding plus the f32 arithmetic's own error.
    fn near(got: Texel, want: [f64; 4]) -> bool {
        (0..4).all(|c| (f64::from(got.to_le_bytes()[c]) - want[c]).abs() <= 0.5 + 1.0 / 64.0)
    }

    /// A 6×5 texture of 3 levels (odd and even sides) with random texels,
    /// as the f32 sampler and the f64 reference read it.
    fn texture(r: &mut XorShift64) -> (Geometry, std::vec::Vec<Texel>, Texture) {
        let g = Geometry::new(6, 5, 3).unwrap();
        let mut texels = std::vec![0; g.len()];
        r.fill_u32(&mut texels);
        let t = Texture::from_rgba8_levels(6, 5, 3, &texels);
        (g, texels, t)
    }

    /// `k/2^bits` for a random `k < span·2^bits`, plus `lo`: exact in f32.
    fn dyadic(r: &mut XorShift64, lo: f32, span: u32, bits: u32) -> f32 {
        lo + (r.next_u64() % u64::from(span << bits)) as f32 / (1u32 << bits) as f32
    }

    /// The f32 sampler computes the f64 reference's definitions: every
    /// address mode and filter mode, coordinates in `[−2.5, 2.5)` and far
    /// out (multiples of 2¹⁶ added, where only the reduction to one period
    /// keeps `u·w` exact in f32), lods below, between and above the stored
    /// levels. The inputs are short dyadic fractions, so `u·w`, the floors
    /// and the weights are exact and the nearest modes read the reference's
    /// texels: only the interpolations' f32 roundings and the final
    /// rounding remain.
    #[test]
    fn sample_matches_the_f64_reference() {
        let mut r = XorShift64(0x5EED_F32B_A5E1_1AE5);
        let (g, texels, t) = texture(&mut r);
        for (a, ra) in AddressMode::ALL.into_iter().zip(Address::ALL) {
            let sampler = SamplerF32::new(g, &texels, a).unwrap();
            let exact = RefSampler {
                tex: &t,
                state: State {
                    address: [ra; 2],
                    ..State::default()
                },
            };
            for (mode, ref_mode) in MODES {
                for i in 0..200 {
                    let far = |r: &mut XorShift64| {
                        if i % 4 == 0 {
                            (r.next_u64() % 7) as f32 * 65_536.0 - 196_608.0
                        } else {
                            0.0
                        }
                    };
                    let u = far(&mut r) + dyadic(&mut r, -2.5, 5, 6);
                    let v = far(&mut r) + dyadic(&mut r, -2.5, 5, 6);
                    let lod = dyadic(&mut r, -1.0, 5, 6);
                    let got = sampler.sample(u, v, lod, mode);
                    let want = exact.sample(f64::from(u), f64::from(v), f64::from(lod), ref_mode);
                    assert!(
                        near(got, want),
                        "{a:?} {mode:?} ({u}, {v}) lod {lod}: {got:08x} vs {want:?}"
                    );
                }
            }
        }
    }

    /// The anisotropic f32 filter against the f64 reference's probe rule:
    /// random footprints of every eccentricity and every cap `1..=16`.
    /// Footprints at a discontinuity of the rule are left out (counted):
    /// a probe count `major/minor` within 10⁻⁴ of an integer, two axes
    /// within 10⁻⁴ of the same length.
    #[test]
    fn sample_aniso_matches_the_f64_reference() {
        let mut r = XorShift64(0xA115_0F32_0000_0001);
        let (g, texels, t) = texture(&mut r);
        let sampler = SamplerF32::new(g, &texels, AddressMode::Wrap).unwrap();
        let (mut skipped, n) = (0, 800);
        for i in 0..n {
            let max = (i % 16) as u8 + 1;
            let exact = RefSampler {
                tex: &t,
                state: State {
                    max_aniso: u32::from(max),
                    ..State::default()
                },
            };
            let (u, v) = (dyadic(&mut r, -1.0, 2, 8), dyadic(&mut r, -1.0, 2, 8));
            let squash = dyadic(&mut r, 0.0, 1, 8);
            let a = [dyadic(&mut r, -0.5, 1, 8), dyadic(&mut r, -0.5, 1, 8)];
            let b = [
                dyadic(&mut r, -0.5, 1, 8) * squash,
                dyadic(&mut r, -0.5, 1, 8) * squash,
            ];
            let len = |a: [f32; 2]| (f64::from(a[0]) * 6.0).hypot(f64::from(a[1]) * 5.0);
            let (la, lb) = (len(a), len(b));
            let ratio = la.max(lb) / la.min(lb).max(1e-300);
            if (ratio - ratio.round()).abs() < 1e-4 || (la - lb).abs() < 1e-4 * la.max(lb) {
                skipped += 1;
                continue;
            }
            // Trilinear: continuous in the probe positions and the lod.
            let got = sampler.sample_aniso(u, v, [a, b], max, Mode::Trilinear);
            let axes = [a.map(f64::from), b.map(f64::from)];
            let want = exact.sample_aniso(f64::from(u), f64::from(v), axes, RefMode::Trilinear);
            assert!(
                near(got, want),
                "max {max} ({u}, {v}) {axes:?}: {got:08x} vs {want:?}"
            );
        }
        assert!(skipped * 50 < n, "{skipped} of {n} left out");
    }

    /// `floor` is `f32::floor` on integers, halves, either side of zero
    /// and at and beyond 2²³ (where every f32 is an integer).
    #[test]
    fn floor_of_reference_values() {
        for x in [
            0.0f32,
            -0.0,
            2.0,
            -2.0,
            2.5,
            -2.5,
            0.25,
            -0.25,
            8_388_607.5,
            -8_388_607.5,
        ] {
            assert_eq!(floor(x), libm::floorf(x), "{x}");
        }
        for x in [8_388_608.0f32, -8_388_608.0, 1e9, -1e9, 3e38] {
            assert_eq!(floor(x), x, "{x}");
        }
    }

    /// `pack` rounds each channel half up: 0.49 → 0, 0.5 → 1, 254.5 →
    /// 255, 255 → 255, red in the low byte.
    #[test]
    fn pack_rounds_half_up() {
        assert_eq!(pack([0.49, 0.5, 254.5, 255.0]), 0xFFFF_0100);
        assert_eq!(channels(0xFFFF_0100), [0.0, 1.0, 255.0, 255.0]);
    }

    /// Reference values worked out by hand (exact in f32).
    #[test]
    fn lod_reference_values() {
        assert_eq!(table_lod_f32(8.0, 1.0), 2.0);
        assert_eq!(table_lod_f32(0.25, -3.0), 1.0);
        assert_eq!(cone_lod_f32(-4.0, 0.5, None), 2.5);
        assert_eq!(cone_lod_f32(1.0, 0.0, Some(0.5)), 1.0);
        assert_eq!(cone_lod_f32(1.0, 0.0, Some(0.0)), 16.0);
        assert_eq!(cone_lod_f32(1.0, 0.0, Some(3.0)), 0.0);
    }
}
