//! Stochastic texture filtering (Pharr et al., "Filtering After Shading
//! with Stochastic Texture Filtering", 2024).
//!
//! Instead of blending texels, pick one level or one texel at random with
//! probability equal to its filter weight. One sample is noisy; its
//! expectation is the filter, so the noise averages out over the samples a
//! renderer takes anyway (frames, pixels' sub-samples), at a fraction of
//! the texel reads.
//!
//! | [`StochasticMode`] | texel reads | expectation |
//! |---|---|---|
//! | [`Trilinear`](StochasticMode::Trilinear) | 4 | [`Mode::Trilinear`](crate::texture::Mode::Trilinear) |
//! | [`Bilinear`](StochasticMode::Bilinear) | 1 | [`Mode::BilinearNearestLevel`](crate::texture::Mode::BilinearNearestLevel) |
//! | [`TrilinearBilinear`](StochasticMode::TrilinearBilinear) | 1 | [`Mode::Trilinear`](crate::texture::Mode::Trilinear) |
//!
//! against 8 reads for deterministic trilinear and 4 for bilinear.
//!
//! # Random bits
//!
//! The caller passes 32 uniformly random bits per sample (from a small
//! deterministic generator seeded per path, e.g. pixel and frame, so a
//! frame is reproducible). They are split into independent fields:
//!
//! | bits | use | decision |
//! |---|---|---|
//! | 0..8 | level | upper level `floor(lod) + 1` iff `field < t`, `t ∈ [0, 256)` the 8-bit blend weight |
//! | 8..20 | column | right tap `i₁` iff `field < fx`, `fx ∈ [0, 4096]` the 12-bit weight |
//! | 20..32 | row | bottom tap `j₁` iff `field < fy` |
//!
//! Each field is compared with a weight of the same width, so every
//! choice has *exactly* the probability of its quantized weight:
//! `P(upper) = t/256`, `P(i₁) = fx/4096`, `P(j₁) = fy/4096`. Addressing,
//! weights and levels are those of [`Sampler::sample`] (the same code).
//!
//! # Error bounds (per channel, 8-bit LSB)
//!
//! Let `F` be the exact real-valued filter at the exact sample position
//! (what the f64 references compute).
//!
//! * [`Bilinear`](StochasticMode::Bilinear),
//!   [`TrilinearBilinear`](StochasticMode::TrilinearBilinear): a sample is a
//!   stored texel, unrounded, so the expectation is the filter with the
//!   12-bit weights exactly; the only bias is the texel position rounded
//!   to 1/4096 texel, `≤ 2·255/8192 <` [`MEAN_ERROR_TEXEL_LSB`] `= 0.0625`.
//! * [`Trilinear`](StochasticMode::Trilinear): each sample is one bilinear
//!   value rounded to 8 bits, so the expectation is within
//!   [`BILERP_MAX_ERROR_LSB`](crate::texture::kernel::accurate::BILERP_MAX_ERROR_LSB) `= 0.5625` of `F`, the
//!   bound of the deterministic filter.
//!
//! A single sample's error is not bounded below the texel contrast of the
//! footprint: that is the noise the mean removes, with a standard deviation
//! that falls as `1/√N` over `N` independent samples (tested: see the
//! convergence plot of `raymip-host tradeoff`).
//!
//! Allocation-free, float-free, panic-free (linked by `demo/panic-check`)
//! and bit-identical on every target: integer compares and shifts only.

use super::{Key, Sampler};
use crate::texture::Stats;
use crate::texture::address::Axis;
use crate::texture::kernel::Kernel;
use crate::texture::kernel::accurate as bilerp;
use crate::texture::storage::mip::{Texel, TexelSource};
use crate::units::{Lod, TexCoord};

/// Bias of the mean of the one-read modes against the exact filter, in
/// 8-bit LSB per channel: the 1/4096-texel position rounding on two axes,
/// `2·255/8192 ≈ 0.0623 < 0.0625`.
pub const MEAN_ERROR_TEXEL_LSB: f64 = 0.0625;

/// Which stochastic filter (see the [module docs](self)).
///
/// # Example
/// ```
/// use raymip::texture::sampler::stochastic::StochasticMode;
/// use raymip::{Geometry, Lod, Pyramid, Sampler, TexCoord};
/// // Level 0 (2×2) white, level 1 (1×1) black.
/// let texels = [0xFFFF_FFFFu32, 0xFFFF_FFFF, 0xFFFF_FFFF, 0xFFFF_FFFF, 0xFF00_0000];
/// let mut sampler = Sampler::wrap(Pyramid::new(Geometry::new(2, 2, 2)?, &texels)?);
/// let (c, lod) = (TexCoord::from_num(0.5), Lod::from_num(0.25));
/// // lod 0.25: blend weight t = 64/256, so level 1 for level fields 0..64.
/// let mode = StochasticMode::TrilinearBilinear;
/// assert_eq!(sampler.sample_stochastic(c, c, lod, mode, 0), 0xFF00_0000);
/// assert_eq!(sampler.sample_stochastic(c, c, lod, mode, 200), 0xFFFF_FFFF);
/// // Over every value of the 8-bit level field exactly 64 pick level 1:
/// // the expectation is the trilinear blend, 3/4 white + 1/4 black.
/// let black = (0..256u32)
///     .filter(|&bits| sampler.sample_stochastic(c, c, lod, mode, bits) == 0xFF00_0000)
///     .count();
/// assert_eq!(black, 64);
/// // One texel read per sample (8 for a deterministic trilinear sample).
/// assert_eq!(sampler.stats().fetched, 2 + 256);
/// # Ok::<(), raymip::MipError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StochasticMode {
    /// Stochastic trilinear: one of the two levels around the lod, chosen
    /// with probability equal to its blend weight, filtered bilinearly
    /// (4 texel reads instead of 8).
    Trilinear,
    /// Stochastic bilinear in the nearest level `floor(lod + ½)`: one texel
    /// of the 2×2 footprint, chosen with probability equal to its bilinear
    /// weight (1 read instead of 4).
    Bilinear,
    /// Both: a random level, then a random texel of its footprint
    /// (1 read instead of 8); expectation = trilinear.
    TrilinearBilinear,
}

/// Bits 0..8 of the random word: the level field.
const LEVEL_MASK: u32 = 0xFF;
/// Shift of the 12-bit column field.
const COLUMN_SHIFT: u32 = 8;
/// Shift of the 12-bit row field.
const ROW_SHIFT: u32 = 20;
/// Mask of a 12-bit field.
const TAP_MASK: u32 = (1 << bilerp::WEIGHT_BITS) - 1;

/// 1 iff `field < weight`: probability `weight / 2^width` for a uniform
/// `width`-bit field.
#[inline(always)]
fn pick(field: u32, weight: u32) -> u32 {
    u32::from(field < weight)
}

impl<S: TexelSource, K: Key> Sampler<S, K> {
    /// One stochastic sample at `(u, v)` and level of detail `lod`
    /// (through the lod window like [`sample`](Self::sample)) with
    /// `mode`, driven by 32 uniformly random `bits` (layout in the
    /// [module docs](crate::texture::sampler::stochastic)). Returns a
    /// stored texel (one-read modes; the border colour for a border tap)
    /// or one rounded bilinear value of the key's kernel. Never panics;
    /// counts the texel reads in [`stats`](Self::stats).
    #[inline]
    pub fn sample_stochastic(
        &mut self,
        u: TexCoord,
        v: TexCoord,
        lod: Lod,
        mode: StochasticMode,
        bits: u32,
    ) -> Texel {
        let lod_bits = self.lod.apply(lod);
        let (lower, t) = ((lod_bits >> 8) as u8, lod_bits & 0xFF);
        let nearest = ((lod_bits + 0x80) >> 8) as u8;
        // `t = 0` (integer lod, top level) always picks `lower`, which is
        // then the only level; otherwise `lower + 1 ≤ top`.
        let level = lower.wrapping_add(pick(bits & LEVEL_MASK, t) as u8);
        match mode {
            StochasticMode::Trilinear => {
                self.stats.count(4, 0);
                let (l, fx, fy) = self.footprint(u, v, usize::from(level) & 15);
                <K::Kernel as Kernel>::bilinear_texel(l, fx, fy, self.rounding)
            }
            StochasticMode::Bilinear => self.one_texel(u, v, nearest, bits),
            StochasticMode::TrilinearBilinear => self.one_texel(u, v, level, bits),
        }
    }

    /// One texel of the bilinear footprint at `level` (12-bit weights,
    /// whatever the kernel's tier: the probabilities of the module docs),
    /// chosen by the column and row fields of `bits`.
    #[inline(always)]
    fn one_texel(&mut self, u: TexCoord, v: TexCoord, level: u8, bits: u32) -> Texel {
        let (w, h) = self.source.geometry().level_size(level);
        let xt = self.axes.0.mode().taps(u, w, bilerp::WEIGHT_BITS);
        let yt = self.axes.1.mode().taps(v, h, bilerp::WEIGHT_BITS);
        let cx = pick((bits >> COLUMN_SHIFT) & TAP_MASK, xt.f) as usize;
        let cy = pick((bits >> ROW_SHIFT) & TAP_MASK, yt.f) as usize;
        self.stats.count(1, 0);
        let t = self.source.texel(level, xt.i[cx & 1], yt.i[cy & 1]);
        if xt.border[cx & 1] | yt.border[cy & 1] {
            self.border_nearest
        } else {
            <K::Kernel as Kernel>::nearest(t)
        }
    }
}

#[cfg(all(test, feature = "trilinear", feature = "mipgen"))]
mod tests {
    extern crate std;
    use super::*;
    use crate::texture::kernel::accurate::BILERP_MAX_ERROR_LSB;
    use crate::texture::storage::mip::{Geometry, Pyramid, full_levels, generate};
    use crate::texture::{AddressMode, Mode};
    use proptest::prelude::*;
    use std::vec;
    use std::vec::Vec;

    /// xorshift64* (test-only source of bits).
    struct Bits(u64);
    impl Bits {
        fn next(&mut self) -> u32 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 32) as u32
        }
    }

    fn random_pyramid(w: u32, h: u32, seed: u64) -> (Geometry, Vec<Texel>) {
        let g = Geometry::new(w, h, full_levels(w, h)).unwrap();
        let mut buf = vec![0; g.len()];
        let mut r = Bits(seed | 1);
        for t in &mut buf[..(w * h) as usize] {
            *t = r.next();
        }
        generate(&g, &mut buf).unwrap();
        (g, buf)
    }

    fn ch(t: Texel) -> [f64; 4] {
        [0, 1, 2, 3].map(|c| f64::from((t >> (8 * c)) & 0xFF))
    }

    /// f64 reference of one axis: `(i₀, i₁, weight of i₁)` from the
    /// definitions (texel centres at (i + ½)/n, wrap = modulo, clamp to edge).
    fn ref_axis(u: f64, n: u32, a: AddressMode) -> (u32, u32, f64) {
        let u = match a {
            AddressMode::Wrap => u - u.floor(),
            AddressMode::ClampToEdge => u.clamp(-1.0, 2.0),
            m => panic!("reference for wrap and clamp only, not {m:?}"),
        };
        let x = u * f64::from(n) - 0.5;
        let x0 = x.floor();
        let fix = |i: i64| match a {
            AddressMode::Wrap => i.rem_euclid(i64::from(n)) as u32,
            _ => i.clamp(0, i64::from(n) - 1) as u32,
        };
        (fix(x0 as i64), fix(x0 as i64 + 1), x - x0)
    }

    /// f64 reference outcome distribution of a one-read mode: (level, x, y,
    /// probability) for every texel that can be picked.
    fn ref_outcomes(
        g: &Geometry,
        u: f64,
        v: f64,
        lod: f64,
        mode: StochasticMode,
        a: AddressMode,
    ) -> Vec<(u8, u32, u32, f64)> {
        let top = f64::from(g.levels() - 1);
        let l = lod.clamp(0.0, top);
        let levels: Vec<(u8, f64)> = match mode {
            StochasticMode::Bilinear => vec![(((l + 0.5).floor().min(top)) as u8, 1.0)],
            _ => {
                let l0 = l.floor();
                let t = l - l0;
                if t > 0.0 {
                    vec![(l0 as u8, 1.0 - t), (l0 as u8 + 1, t)]
                } else {
                    vec![(l0 as u8, 1.0)]
                }
            }
        };
        let mut out = Vec::new();
        for (k, pk) in levels {
            let (w, h) = g.level_size(k);
            let (x0, x1, fx) = ref_axis(u, w, a);
            let (y0, y1, fy) = ref_axis(v, h, a);
            for (y, py) in [(y0, 1.0 - fy), (y1, fy)] {
                for (x, px) in [(x0, 1.0 - fx), (x1, fx)] {
                    out.push((k, x, y, pk * px * py));
                }
            }
        }
        out
    }

    /// Mean and standard deviation per channel of a reference distribution.
    fn moments(p: &Pyramid<'_>, outcomes: &[(u8, u32, u32, f64)]) -> ([f64; 4], [f64; 4]) {
        let mut m = [0.0; 4];
        let mut m2 = [0.0; 4];
        for &(k, x, y, w) in outcomes {
            let c = ch(p.get(k, x, y));
            for i in 0..4 {
                m[i] += w * c[i];
                m2[i] += w * c[i] * c[i];
            }
        }
        let sd = [0, 1, 2, 3].map(|i| (m2[i] - m[i] * m[i]).max(0.0).sqrt());
        (m, sd)
    }

    /// Exact selection probabilities: over every value of a field, the
    /// number of "take the upper/right/bottom tap" decisions equals the
    /// weight.
    #[test]
    fn fields_choose_with_exact_probability() {
        for t in 0..256 {
            assert_eq!((0..256).map(|f| pick(f, t)).sum::<u32>(), t);
        }
        for w in [0, 1, 2047, 2048, 4095, 4096] {
            assert_eq!((0..4096).map(|f| pick(f, w)).sum::<u32>(), w);
        }
    }

    /// Reference vectors on a 2×2 level 0 (red 0, 64 / 128, 255) over a
    /// 1×1 level 1 (red 112), sampled at the centre of the four texels
    /// (fx = fy = ½) and lod 0.25: the bits select exactly the texel the
    /// layout says.
    #[test]
    fn reference_vectors() {
        let g = Geometry::new(2, 2, 2).unwrap();
        let red = |r: u32| r | 0xFF00_0000;
        let mut buf = vec![red(0), red(64), red(128), red(255), 0];
        generate(&g, &mut buf).unwrap();
        assert_eq!(buf[4], red((447 + 2) / 4));
        let p = Pyramid::new(g, &buf).unwrap();
        let mut s = Sampler::with_address(p, AddressMode::ClampToEdge);
        let c = TexCoord::from_num(0.5);
        let q = Lod::from_num(0.25); // t = 64
        let m = StochasticMode::TrilinearBilinear;
        // (bits, expected red): level field < 64 → level 1; a column/row
        // field < 2048 → the right/bottom tap.
        let vectors: [(u32, u32); 6] = [
            (63, 112),                          // level 1 (1×1)
            (64 | 2048 << 8 | 2048 << 20, 0),   // level 0, x0 y0
            (64 | 2047 << 8 | 2048 << 20, 64),  // x1 y0
            (64 | 2048 << 8 | 2047 << 20, 128), // x0 y1
            (64, 255),                          // x1 y1
            (255 | 4095 << 8 | 4095 << 20, 0),  // level 0, x0 y0
        ];
        for (bits, r) in vectors {
            assert_eq!(s.sample_stochastic(c, c, q, m, bits), red(r), "{bits:#x}");
        }
        assert_eq!(s.stats().fetched, 6);
        // Stochastic trilinear: level 1 (112) or the level-0 bilinear 111.75 → 112.
        let t = StochasticMode::Trilinear;
        assert_eq!(s.sample_stochastic(c, c, q, t, 0), red(112));
        assert_eq!(s.sample_stochastic(c, c, q, t, 255), red(112));
        // Bilinear uses the nearest level (0 at lod 0.25) and no level bits.
        let b = StochasticMode::Bilinear;
        assert_eq!(s.sample_stochastic(c, c, q, b, u32::MAX), red(0));
        assert_eq!(s.stats().fetched, 6 + 8 + 1);
    }

    /// A border tap on one axis only: a one-read mode returns the border
    /// colour when its draw picks the outside column (or row), whatever
    /// it picks on the other axis, and the texel when it picks the inside
    /// one. 2×2 level 0 at u = 0 (columns −1 and 0, fx = ½), v = ½ (rows
    /// 0 and 1): a column field of 2048 picks the left tap, 2047 the right.
    #[test]
    fn border_on_one_axis_picks_the_border_colour() {
        use crate::texture::address::AnyAxis;
        use crate::texture::sampler::{Cfg, SamplerDesc, SamplerState};
        let g = Geometry::new(2, 2, 2).unwrap();
        let mut buf = vec![0xFF00_0010, 0xFF00_0020, 0xFF00_0030, 0xFF00_0040, 0];
        generate(&g, &mut buf).unwrap();
        let border = 0x8070_6050;
        let (zero, half) = (TexCoord::ZERO, TexCoord::from_num(0.5));
        let b = StochasticMode::Bilinear;
        for border_u in [true, false] {
            let (bu, bv) = if border_u {
                (AddressMode::ClampToBorder, AddressMode::ClampToEdge)
            } else {
                (AddressMode::ClampToEdge, AddressMode::ClampToBorder)
            };
            let desc = SamplerDesc {
                address_u: bu,
                address_v: bv,
                border,
                ..SamplerDesc::default()
            };
            let state = SamplerState::new(desc).unwrap();
            let p = Pyramid::new(g, &buf).unwrap();
            let mut s = Sampler::<_, Cfg<AnyAxis>>::with_state(p, state).unwrap();
            let (u, v) = if border_u { (zero, half) } else { (half, zero) };
            // The outside tap on the border axis, either tap on the other.
            let field = |outside: bool, other: u32| {
                let (c, r) = if border_u {
                    (if outside { 2048 } else { 2047 }, other)
                } else {
                    (other, if outside { 2048 } else { 2047 })
                };
                c << 8 | r << 20
            };
            for other in [2047, 2048] {
                let out = s.sample_stochastic(u, v, Lod::ZERO, b, field(true, other));
                assert_eq!(out, border, "border_u {border_u}, other field {other}");
                let inside = s.sample_stochastic(u, v, Lod::ZERO, b, field(false, other));
                assert_ne!(inside, border, "border_u {border_u}, other field {other}");
                assert_eq!(inside >> 24, 0xFF, "a texel of level 0");
            }
        }
    }

    /// Border taps on both axes (2×2 level 0 at u = v = 0, both axes
    /// clamp-to-border: column −1 and row −1 outside): a one-read mode
    /// returns the border colour when its draw picks an outside tap on
    /// either axis or on both, and the texel (0, 0) only when it picks the
    /// inside tap on both. A field of 2048 picks the outside tap, 2047 the
    /// inside one.
    #[test]
    fn border_on_both_axes_picks_the_border_colour() {
        use crate::texture::address::AnyAxis;
        use crate::texture::sampler::{Cfg, SamplerDesc, SamplerState};
        let g = Geometry::new(2, 2, 2).unwrap();
        let mut buf = vec![0xFF00_0010, 0xFF00_0020, 0xFF00_0030, 0xFF00_0040, 0];
        generate(&g, &mut buf).unwrap();
        let border = 0x8070_6050;
        let desc = SamplerDesc {
            address_u: AddressMode::ClampToBorder,
            address_v: AddressMode::ClampToBorder,
            border,
            ..SamplerDesc::default()
        };
        let state = SamplerState::new(desc).unwrap();
        let p = Pyramid::new(g, &buf).unwrap();
        let mut s = Sampler::<_, Cfg<AnyAxis>>::with_state(p, state).unwrap();
        let zero = TexCoord::ZERO;
        let b = StochasticMode::Bilinear;
        for (column, row, want) in [
            (2048u32, 2048u32, border),
            (2048, 2047, border),
            (2047, 2048, border),
            (2047, 2047, 0xFF00_0010),
        ] {
            let got = s.sample_stochastic(zero, zero, Lod::ZERO, b, column << 8 | row << 20);
            assert_eq!(got, want, "column field {column}, row field {row}");
        }
    }

    /// f64 reference of a single draw: the firmware picks the texel the
    /// reference picks with the same uniform numbers, except where a
    /// uniform lies within the 2⁻¹² weight quantization of a boundary.
    #[test]
    fn single_draws_match_f64_reference() {
        let mut r = Bits(0x1234_5678_9ABC_DEF1);
        for (w, h, a) in [
            (16, 16, AddressMode::Wrap),
            (13, 7, AddressMode::ClampToEdge),
            (64, 32, AddressMode::Wrap),
        ] {
            let (g, buf) = random_pyramid(w, h, u64::from(w * h));
            let p = Pyramid::new(g, &buf).unwrap();
            let mut s = Sampler::with_address(p, a);
            let mut checked = 0;
            for _ in 0..20_000 {
                let u = f64::from(r.next()) / 2f64.powi(30) - 1.5;
                let v = f64::from(r.next()) / 2f64.powi(30) - 1.5;
                let lod = f64::from(r.next() >> 24) / 32.0; // [0, 8), 1/32 steps
                let bits = r.next();
                let (uq, vq) = (TexCoord::from_num(u), TexCoord::from_num(v));
                let l = Lod::from_num(lod);
                let got = s.sample_stochastic(uq, vq, l, StochasticMode::TrilinearBilinear, bits);
                // Reference decision with the same uniforms.
                let top = f64::from(g.levels() - 1);
                let lc = lod.clamp(0.0, top);
                let l0 = lc.floor();
                let rl = f64::from(bits & 0xFF) / 256.0;
                let k = l0 as u8 + u8::from(rl < lc - l0);
                let (lw, lh) = g.level_size(k);
                let (x0, x1, fx) = ref_axis(u, lw, a);
                let (y0, y1, fy) = ref_axis(v, lh, a);
                let rx = f64::from((bits >> 8) & 0xFFF) / 4096.0;
                let ry = f64::from(bits >> 20) / 4096.0;
                let near = |r: f64, f: f64| (r - f).abs() <= 1.5 / 4096.0;
                if near(rx, fx) || near(ry, fy) {
                    continue;
                }
                let want = p.get(
                    k,
                    if rx < fx { x1 } else { x0 },
                    if ry < fy { y1 } else { y0 },
                );
                assert_eq!(
                    got, want,
                    "{w}x{h} {a:?} u {u} v {v} lod {lod} bits {bits:#x}"
                );
                checked += 1;
            }
            assert!(checked > 19_000, "{checked}");
        }
    }

    /// Unbiasedness: the mean of `N` draws is within `bias + 5σ/√N` of
    /// the f64 expectation of the reference distribution (σ its exact
    /// standard deviation; 5σ: a false failure has probability < 10⁻⁶ per
    /// channel), and within the deterministic filter's rounding of the
    /// firmware's own deterministic result.
    #[test]
    fn mean_converges_to_the_filter() {
        const N: u32 = 1 << 14;
        let (g, buf) = random_pyramid(32, 16, 7);
        let p = Pyramid::new(g, &buf).unwrap();
        let mut r = Bits(99);
        for (i, (u, v, lod)) in [
            (0.3, 0.7, 0.5),
            (0.01, 0.99, 1.25),
            (-0.37, 1.61, 2.875),
            (0.5, 0.5, 0.0),
            (0.123, 0.456, 9.0),
        ]
        .into_iter()
        .enumerate()
        {
            let a = if i % 2 == 0 {
                AddressMode::Wrap
            } else {
                AddressMode::ClampToEdge
            };
            let mut s = Sampler::with_address(p, a);
            let (uq, vq, lq) = (
                TexCoord::from_num(u),
                TexCoord::from_num(v),
                Lod::from_num(lod),
            );
            for (mode, det, bias) in [
                (
                    StochasticMode::Trilinear,
                    Mode::Trilinear,
                    BILERP_MAX_ERROR_LSB,
                ),
                (
                    StochasticMode::Bilinear,
                    Mode::BilinearNearestLevel,
                    MEAN_ERROR_TEXEL_LSB,
                ),
                (
                    StochasticMode::TrilinearBilinear,
                    Mode::Trilinear,
                    MEAN_ERROR_TEXEL_LSB,
                ),
            ] {
                let mut sum = [0.0; 4];
                for _ in 0..N {
                    let c = ch(s.sample_stochastic(uq, vq, lq, mode, r.next()));
                    for k in 0..4 {
                        sum[k] += c[k];
                    }
                }
                let ref_mode = if mode == StochasticMode::Bilinear {
                    StochasticMode::Bilinear
                } else {
                    StochasticMode::TrilinearBilinear
                };
                let (mean, sd) = moments(&p, &ref_outcomes(&g, u, v, lod, ref_mode, a));
                let d = ch(s.sample(uq, vq, lq, det));
                for k in 0..4 {
                    let m = sum[k] / f64::from(N);
                    let tol = 5.0 * sd[k] / f64::from(N).sqrt();
                    assert!(
                        (m - mean[k]).abs() <= bias + tol,
                        "{mode:?} {u},{v},{lod} ch {k}: mean {m} vs f64 {} (bias {bias}, 5σ/√N {tol})",
                        mean[k]
                    );
                    assert!(
                        (m - d[k]).abs() <= BILERP_MAX_ERROR_LSB + bias + tol,
                        "{mode:?} ch {k}: mean {m} vs deterministic {}",
                        d[k]
                    );
                }
            }
        }
    }

    proptest! {
        /// Any input: no panic, the result is a texel of the footprint
        /// (one-read modes) and the read counts are 4 / 1 / 1.
        #[test]
        fn any_input_is_a_footprint_texel(
            ub in any::<i64>(), vb in any::<i64>(), lb in any::<i16>(), bits in any::<u32>(),
            wrap in any::<bool>(), w in 1u32..40, h in 1u32..40,
        ) {
            let (g, buf) = random_pyramid(w, h, u64::from(w * 41 + h));
            let p = Pyramid::new(g, &buf).unwrap();
            let a = if wrap { AddressMode::Wrap } else { AddressMode::ClampToEdge };
            let mut s = Sampler::with_address(p, a);
            let (u, v, l) = (TexCoord::from_bits(ub), TexCoord::from_bits(vb), Lod::from_bits(lb));
            let _ = s.sample_stochastic(u, v, l, StochasticMode::Trilinear, bits);
            prop_assert_eq!(s.stats().fetched, 4);
            for mode in [StochasticMode::Bilinear, StochasticMode::TrilinearBilinear] {
                let got = s.sample_stochastic(u, v, l, mode, bits);
                // Every texel of every level the lod can select.
                let found = (0..g.levels()).any(|k| {
                    let (lw, lh) = g.level_size(k);
                    (0..lh).any(|y| (0..lw).any(|x| p.get(k, x, y) == got))
                });
                prop_assert!(found);
            }
            prop_assert_eq!(s.stats().fetched, 6);
        }
    }
}
