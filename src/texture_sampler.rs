//! A GPU-style texture sampler: [`SamplerState`] (address modes per axis,
//! border colour, lod bias and clamps, anisotropy) over any
//! [`TexelSource`] (an [`Image`](crate::image::Image) in any format, a
//! [`TexelCache`](crate::cache::TexelCache) in front of one, or an RGBA8
//! [`Pyramid`](crate::mip::Pyramid)), with sRGB decoding before filtering.
//!
//! The older [`filter::Sampler`](crate::filter::Sampler) (wrap/clamp, RGBA8,
//! no state) stays as it is; this one adds the sampler-object options.
//!
//! # Arithmetic
//!
//! Every texel becomes four 16-bit linear channels ("L16", 65535 = 1.0):
//! `c·257` for linear data (exact), [`srgb::DECODE`] for the RGB of sRGB
//! data (alpha `a·257`); the border colour (linear RGBA8) `·257`. Filters
//! work in L16 with 8 more fractional bits (16.8):
//!
//! * bilinear ([`crate::address`] gives the taps and the 12-bit weights):
//!   `top = c₀₀·(4096 − fx) + c₁₀·fx < 2²⁸`, then
//!   `(top·(4096 − fy) + bot·fy + 2¹⁵) >> 16` in 64 bits;
//! * between levels: `(a·(256 − t) + b·t + 2⁷) >> 8` with the exact 8-bit
//!   lod fraction `t` (`≤ 65535·2⁸·2⁸ < 2³²`);
//! * anisotropic: the mean of `N ≤ 16` probes, rounded (`< 2²⁸`);
//! * out: linear data and [`SrgbOutput::Linear`] round `x / (257·2⁸)` to
//!   8 bits; [`SrgbOutput::Encoded`] re-encodes RGB with [`srgb::encode`].
//!
//! The level is chosen exactly as in [`filter`](crate::filter) (nearest
//! level `floor(lod + ½)`, linear levels `floor(lod)` and the next with
//! weight `frac(lod)`, the second level skipped and counted when its weight
//! is 0), after [`SamplerState::lod`] (bias, clamp, stored levels).
//!
//! # Error bounds (per channel, 8-bit LSB, against the exact f64 filter)
//!
//! * linear data: [`SAMPLER_MAX_ERROR_LSB`] = 0.5625 for every filter (½ final
//!   rounding, `255·2⁻¹³` per axis from the 12-bit weights, `< 2⁻¹⁵` from
//!   the 16.8 intermediates); nearest-texel modes exact;
//! * sRGB, re-encoded: [`SRGB_MAX_ERROR_LSB`] = 1.4: ½ rounding, plus the
//!   linear error (weights `2·2⁻¹³` of full scale at most, decode table
//!   `2⁻¹⁷`) times the steepest slope of the sRGB curve, `12.92·255`.

use crate::address::AddressMode;
use crate::aniso::{Footprint, probes};
use crate::filter::{FetchStats, LevelSplit, Mode, TexCoord};
use crate::format::ColorSpace;
use crate::lod::Lod;
use crate::mip::{Geometry, Texel, TexelSource};
use crate::sampler_state::{SamplerState, SrgbOutput};
use crate::srgb;

/// Error bound of every filter on linear data (8-bit LSB), as
/// [`bilerp::BILERP_MAX_ERROR_LSB`](crate::bilerp::BILERP_MAX_ERROR_LSB).
pub const SAMPLER_MAX_ERROR_LSB: f64 = crate::bilerp::BILERP_MAX_ERROR_LSB;

/// Error bound of filtered sRGB data re-encoded to sRGB (8-bit sRGB LSB).
pub const SRGB_MAX_ERROR_LSB: f64 = 1.4;

/// Four channels in 16.8 linear fixed point (65535·256 = 1.0).
type Lin = [u32; 4];

/// Samples a [`TexelSource`] with a [`SamplerState`] (module docs).
#[derive(Debug)]
pub struct TextureSampler<S: TexelSource> {
    source: S,
    geometry: Geometry,
    state: SamplerState,
    space: ColorSpace,
    /// The border colour in L16.
    border: [u32; 4],
    stats: FetchStats,
}

impl<S: TexelSource> TextureSampler<S> {
    /// A sampler over `source` whose texels are in colour space `space`
    /// (an [`Image`](crate::image::Image) knows it:
    /// `image.format().space()`).
    pub fn new(source: S, state: SamplerState, space: ColorSpace) -> Self {
        let geometry = source.geometry();
        let border = state.border().to_le_bytes().map(|c| u32::from(c) * 257);
        Self {
            source,
            geometry,
            state,
            space,
            border,
            stats: FetchStats::default(),
        }
    }

    /// Filtered texel at `(u, v)` and level of detail `lod` (bias and
    /// clamps of the state applied) with filter `mode`. Never panics.
    #[inline]
    pub fn sample(&mut self, u: TexCoord, v: TexCoord, lod: Lod, mode: Mode) -> Texel {
        let lod = self.state.lod(lod, self.geometry.levels());
        let lin = self.filter(u, v, lod, mode);
        self.output(lin)
    }

    /// Anisotropic sample at `(u, v)` over the footprint `fp` (two axis
    /// vectors, [`crate::aniso`]): up to the state's maximum anisotropy
    /// probes of filter `mode` (normally [`Mode::Trilinear`]) along the
    /// major axis, averaged. With `max_anisotropy` 1 it is one probe at the
    /// major axis's lod. Never panics.
    pub fn sample_aniso(&mut self, u: TexCoord, v: TexCoord, fp: &Footprint, mode: Mode) -> Texel {
        let p = probes(
            fp,
            self.geometry.width(),
            self.geometry.height(),
            self.state.max_anisotropy(),
        );
        let lod = self.state.lod(p.lod, self.geometry.levels());
        let mut sum = [0u32; 4];
        let (mut pu, mut pv) = (u.saturating_add(p.first[0]), v.saturating_add(p.first[1]));
        for _ in 0..p.count {
            let s = self.filter(pu, pv, lod, mode);
            for (a, b) in sum.iter_mut().zip(s) {
                *a = a.wrapping_add(b);
            }
            pu = pu.saturating_add(p.step[0]);
            pv = pv.saturating_add(p.step[1]);
        }
        let n = u32::from(p.count.max(1));
        let mean = sum.map(|s| (s + n / 2) / n);
        self.output(mean)
    }

    /// The filter at an already clamped lod, in 16.8 linear.
    #[inline]
    fn filter(&mut self, u: TexCoord, v: TexCoord, lod: Lod, mode: Mode) -> Lin {
        let LevelSplit {
            lower,
            t,
            nearest: nearest_level,
        } = LevelSplit::new(lod, &self.geometry);
        #[cfg(not(feature = "trilinear"))]
        let _ = (lower, t);
        match mode {
            #[cfg(feature = "trilinear")]
            Mode::Trilinear => {
                let a = self.bilinear(u, v, lower);
                if t == 0 {
                    self.stats.skipped += 4;
                    a
                } else {
                    let b = self.bilinear(u, v, lower + 1);
                    blend(a, b, t)
                }
            }
            Mode::BilinearNearestLevel => self.bilinear(u, v, nearest_level),
            Mode::Nearest => self.nearest(u, v, nearest_level),
            #[cfg(feature = "trilinear")]
            Mode::NearestTexelLinearLevel => {
                let a = self.nearest(u, v, lower);
                if t == 0 {
                    self.stats.skipped += 1;
                    a
                } else {
                    let b = self.nearest(u, v, lower + 1);
                    blend(a, b, t)
                }
            }
        }
    }

    /// A texel (or the border) in L16.
    #[inline(always)]
    fn fetch(&mut self, level: u8, x: Option<u32>, y: Option<u32>) -> [u32; 4] {
        let (Some(x), Some(y)) = (x, y) else {
            return self.border;
        };
        self.stats.fetched += 1;
        let t = self.source.texel(level, x, y).to_le_bytes();
        match self.space {
            ColorSpace::Linear => t.map(|c| u32::from(c) * 257),
            ColorSpace::Srgb => [
                u32::from(srgb::decode(t[0])),
                u32::from(srgb::decode(t[1])),
                u32::from(srgb::decode(t[2])),
                u32::from(t[3]) * 257,
            ],
        }
    }

    /// Bilinear value at `level` in 16.8.
    #[inline]
    fn bilinear(&mut self, u: TexCoord, v: TexCoord, level: u8) -> Lin {
        let (w, h) = self.geometry.level_size(level);
        let [au, av] = self.state.address();
        let ([x0, x1], fx) = au.linear(u, w);
        let ([y0, y1], fy) = av.linear(v, h);
        let t00 = self.fetch(level, x0, y0);
        let t10 = self.fetch(level, x1, y0);
        let t01 = self.fetch(level, x0, y1);
        let t11 = self.fetch(level, x1, y1);
        let (gx, gy) = (4096 - fx, 4096 - fy);
        let mut out = [0u32; 4];
        for (c, o) in out.iter_mut().enumerate() {
            let top = t00[c] * gx + t10[c] * fx;
            let bot = t01[c] * gx + t11[c] * fx;
            let v = u64::from(top) * u64::from(gy) + u64::from(bot) * u64::from(fy) + (1 << 15);
            *o = (v >> 16) as u32;
        }
        out
    }

    /// Nearest texel at `level` in 16.8.
    #[inline]
    fn nearest(&mut self, u: TexCoord, v: TexCoord, level: u8) -> Lin {
        let (w, h) = self.geometry.level_size(level);
        let [au, av] = self.state.address();
        let x = au.nearest(u, w);
        let y = av.nearest(v, h);
        self.fetch(level, x, y).map(|c| c << 8)
    }

    /// 16.8 linear to the output texel (module docs).
    #[inline]
    fn output(&self, lin: Lin) -> Texel {
        let to8 = |x: u32| (x.min(65535 << 8) + 257 * 128) / (257 * 256);
        let encoded =
            self.space == ColorSpace::Srgb && self.state.srgb_output() == SrgbOutput::Encoded;
        let mut out = 0u32;
        for (c, &x) in lin.iter().enumerate() {
            let b = if encoded && c < 3 {
                u32::from(srgb::encode(x))
            } else {
                to8(x)
            };
            out |= (b & 0xFF) << (8 * c);
        }
        out
    }

    /// The sampler state.
    #[must_use]
    pub fn state(&self) -> &SamplerState {
        &self.state
    }

    /// The address mode of `u` and `v`.
    #[must_use]
    pub fn address(&self) -> [AddressMode; 2] {
        self.state.address()
    }

    /// The source's geometry (read once at construction).
    #[must_use]
    pub fn geometry(&self) -> Geometry {
        self.geometry
    }

    /// Fetch counters (border reads are not fetches).
    #[must_use]
    pub fn stats(&self) -> FetchStats {
        self.stats
    }

    /// Zeroes the fetch counters.
    pub fn reset_stats(&mut self) {
        self.stats = FetchStats::default();
    }

    /// The texel source, mutable (e.g. for cache counters).
    #[must_use]
    pub fn source_mut(&mut self) -> &mut S {
        &mut self.source
    }
}

/// `a·(1 − t/256) + b·t/256` in 16.8, rounded; `t ≤ 256`.
#[cfg(feature = "trilinear")]
#[inline(always)]
fn blend(a: Lin, b: Lin, t: u32) -> Lin {
    let t = t.min(256);
    let s = 256 - t;
    let mut out = [0u32; 4];
    for (o, (x, y)) in out.iter_mut().zip(a.iter().zip(b)) {
        *o = (x
            .wrapping_mul(s)
            .wrapping_add(y.wrapping_mul(t))
            .wrapping_add(128))
            >> 8;
    }
    out
}

#[cfg(all(test, feature = "trilinear", feature = "mipgen"))]
mod tests {
    extern crate std;
    use super::*;
    use crate::filter::{Address, Sampler};
    use crate::mip::{Pyramid, generate};
    use crate::sampler_state::SamplerDesc;
    use proptest::prelude::*;
    use std::vec::Vec;

    fn state(address: AddressMode, border: Texel) -> SamplerState {
        SamplerState::new(SamplerDesc {
            address_u: address,
            address_v: address,
            border,
            ..SamplerDesc::default()
        })
        .unwrap()
    }

    #[test]
    fn border_and_srgb() {
        let g = Geometry::new(2, 1, 1).unwrap();
        let buf = [0x80_80_80_80u32, 0xFF_FF_FF_FF];
        let p = Pyramid::new(g, &buf).unwrap();
        let red = 0xFF00_00FF;
        let mut s = TextureSampler::new(
            p,
            state(AddressMode::ClampToBorder, red),
            ColorSpace::Linear,
        );
        let c = TexCoord::from_num;
        // u = 0: half border (red), half texel 0.
        let t = s.sample(c(0.0), c(0.5), Lod::ZERO, Mode::BilinearNearestLevel);
        assert_eq!(t.to_le_bytes(), [192, 64, 64, 192]);
        assert_eq!(s.sample(c(-3.0), c(0.5), Lod::ZERO, Mode::Nearest), red);
        // sRGB: the mean of codes 0 and 255 is linear ½ → sRGB 188.
        let buf = [0xFF00_0000u32, 0xFFFF_FFFF];
        let p = Pyramid::new(g, &buf).unwrap();
        let mut s = TextureSampler::new(p, state(AddressMode::Wrap, 0), ColorSpace::Srgb);
        let t = s.sample(c(0.5), c(0.5), Lod::ZERO, Mode::Trilinear);
        assert_eq!(t.to_le_bytes(), [188, 188, 188, 255]);
        let lin = SamplerState::new(SamplerDesc {
            srgb_output: SrgbOutput::Linear,
            ..SamplerDesc::default()
        })
        .unwrap();
        let mut s = TextureSampler::new(p, lin, ColorSpace::Srgb);
        let t = s.sample(c(0.5), c(0.5), Lod::ZERO, Mode::Trilinear);
        assert_eq!(t.to_le_bytes(), [128, 128, 128, 255]);
    }

    proptest! {
        /// With wrap/clamp-to-edge on linear RGBA8 data the new sampler
        /// agrees with the old `filter::Sampler` within one LSB (both are
        /// within 0.5625 of the same exact value; different rounding).
        #[test]
        fn agrees_with_filter_sampler(seed in any::<u32>(), u in -3.0f64..3.0, v in -3.0f64..3.0,
                                      lod in -2.0f64..8.0, mode in 0u8..4, clamp in any::<bool>()) {
            let g = Geometry::new(16, 8, 5).unwrap();
            let mut buf: Vec<Texel> = (0..g.len() as u32)
                .map(|i| (i ^ seed).wrapping_mul(2_654_435_761))
                .collect();
            generate(&g, &mut buf).unwrap();
            let p = Pyramid::new(g, &buf).unwrap();
            let (old_addr, new_addr) = if clamp {
                (Address::Clamp, AddressMode::ClampToEdge)
            } else {
                (Address::Wrap, AddressMode::Wrap)
            };
            let mut old = Sampler::new(p, old_addr);
            let mut new = TextureSampler::new(p, state(new_addr, 0), ColorSpace::Linear);
            let (u, v, l) = (TexCoord::from_num(u), TexCoord::from_num(v), Lod::from_num(lod));
            let mode = Mode::from_index(mode).unwrap();
            let a = old.sample(u, v, l, mode).to_le_bytes();
            let b = new.sample(u, v, l, mode).to_le_bytes();
            for c in 0..4 {
                prop_assert!(a[c].abs_diff(b[c]) <= 1, "{a:?} {b:?}");
            }
            prop_assert_eq!(old.stats(), new.stats());
        }
    }
}
