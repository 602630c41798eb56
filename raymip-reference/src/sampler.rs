//! f64 reference of the texture sampler, written from the definitions in
//! exact sample positions, weights and lods: texel centres at
//! `(i + ½)/size`; every address mode as the Vulkan "wrapping operation"
//! defines it, the border colour for clamp-to-border; lod bias, then the
//! sampler's `[min, max]` clamps, then the stored levels (D3D11 order);
//! nearest level `floor(lod + ½)`; sRGB EOTF/OETF (IEC 61966-2-1);
//! anisotropic footprints pbrt-style ([`aniso_probes`]).
//!
//! The texels come from any [`Texels`] (channel values 0..=255 as stored,
//! before any sRGB decode): [`Texture`] holds them in f64; a caller with
//! texels of its own (a renderer's texture memory) implements the trait.
//! The enums [`Address`] and [`Mode`] are numbered as the firmware's
//! `AddressMode` and `Mode`, so a test maps one to the other by number.

/// sRGB EOTF (code fraction → linear).
#[must_use]
pub fn srgb_to_linear(s: f64) -> f64 {
    if s <= 0.04045 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

/// sRGB OETF (linear → code fraction).
#[must_use]
pub fn linear_to_srgb(l: f64) -> f64 {
    if l <= 0.003_130_8 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

// An enum numbered as its firmware counterpart: the variants in number
// order, `ALL` in that order and `from_index`, the variant of a firmware
// number (the firmware's tests check that the names agree).
macro_rules! numbered {
    ($(#[$m:meta])* $name:ident: $n:literal { $($(#[$vm:meta])* $v:ident,)+ }) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum $name {
            $($(#[$vm])* $v,)+
        }

        impl $name {
            /// Every variant, in number order.
            pub const ALL: [Self; $n] = [$(Self::$v,)+];

            /// The variant numbered `n`, `None` past the last.
            #[must_use]
            pub fn from_index(n: u8) -> Option<Self> {
                Self::ALL.get(usize::from(n)).copied()
            }
        }
    };
}

numbered! {
    /// Address mode of one axis (numbered as the firmware's `AddressMode`).
    Address: 5 {
        /// Vulkan `REPEAT`.
        Wrap,
        /// Vulkan `MIRRORED_REPEAT`.
        Mirror,
        /// Vulkan `CLAMP_TO_EDGE`.
        ClampToEdge,
        /// Vulkan `MIRROR_CLAMP_TO_EDGE`.
        MirrorOnce,
        /// Vulkan `CLAMP_TO_BORDER`.
        ClampToBorder,
    }
}

impl Address {
    /// The wrapping operation on an integer texel index `i` of a level
    /// `n ≥ 1` texels wide: the texel read, or `None` for the border colour.
    #[must_use]
    pub fn index(self, i: i64, n: i64) -> Option<i64> {
        let mirror = |a: i64| if a >= 0 { a } else { -(1 + a) };
        match self {
            Self::Wrap => Some(i.rem_euclid(n)),
            Self::Mirror => Some((n - 1) - mirror(i.rem_euclid(2 * n) - n)),
            Self::ClampToEdge => Some(i.clamp(0, n - 1)),
            Self::MirrorOnce => Some(mirror(i).clamp(0, n - 1)),
            Self::ClampToBorder => (0..n).contains(&i).then_some(i),
        }
    }
}

numbered! {
    /// Filter mode (numbered as the firmware's `Mode`).
    Mode: 4 {
        /// Bilinear within a level, linear between the levels around the lod.
        Trilinear,
        /// Bilinear within the nearest level.
        BilinearNearestLevel,
        /// Nearest texel of the nearest level.
        Nearest,
        /// Nearest texel in each of the two levels around the lod, linear
        /// between them.
        NearestTexelLinearLevel,
    }
}

/// The texels a reference sampler reads.
pub trait Texels {
    /// Number of stored levels (at least 1).
    fn levels(&self) -> usize;
    /// `(width, height)` of `level` (`< levels()`), each at least 1.
    fn size(&self, level: usize) -> (u32, u32);
    /// RGBA channel values 0..=255 (as stored) of texel `(x, y)` of
    /// `level`, inside the level.
    fn texel(&self, level: usize, x: u32, y: u32) -> [f64; 4];
}

/// Level sizes of a `width × height` level 0 with `levels` levels, by the
/// definition: level `k` is `max(1, width >> k) × max(1, height >> k)`.
#[must_use]
pub fn level_sizes(width: u32, height: u32, levels: u8) -> Vec<(u32, u32)> {
    (0..u32::from(levels))
        .map(|k| {
            (
                width.checked_shr(k).unwrap_or(0).max(1),
                height.checked_shr(k).unwrap_or(0).max(1),
            )
        })
        .collect()
}

/// A texture held in f64: every level's RGBA channel values 0..=255.
#[derive(Clone, Debug)]
pub struct Texture {
    /// `(width, height)` of each level.
    pub sizes: Vec<(u32, u32)>,
    /// Texels of each level, row-major.
    pub levels: Vec<Vec<[f64; 4]>>,
}

impl Texture {
    /// Texture of the level `sizes` whose texel `(x, y)` of level `k` is
    /// `f(k, x, y)`.
    #[must_use]
    pub fn from_fn(sizes: &[(u32, u32)], f: impl Fn(usize, u32, u32) -> [f64; 4]) -> Self {
        let levels = sizes
            .iter()
            .enumerate()
            .map(|(k, &(w, h))| {
                (0..h)
                    .flat_map(|y| (0..w).map(move |x| (x, y)))
                    .map(|(x, y)| f(k, x, y))
                    .collect()
            })
            .collect();
        Self {
            sizes: sizes.to_vec(),
            levels,
        }
    }

    /// From RGBA8 words (red in the low byte) stored level after level,
    /// each level row-major, with the level sizes of [`level_sizes`].
    ///
    /// # Panics
    /// When `texels` is shorter than the levels.
    #[must_use]
    pub fn from_rgba8_levels(width: u32, height: u32, levels: u8, texels: &[u32]) -> Self {
        let sizes = level_sizes(width, height, levels);
        let mut offsets = Vec::with_capacity(sizes.len());
        let mut offset = 0usize;
        for &(w, h) in &sizes {
            offsets.push(offset);
            offset += w as usize * h as usize;
        }
        Self::from_fn(&sizes, |k, x, y| {
            let w = sizes[k].0 as usize;
            texels[offsets[k] + y as usize * w + x as usize]
                .to_le_bytes()
                .map(f64::from)
        })
    }
}

impl Texels for Texture {
    fn levels(&self) -> usize {
        self.levels.len()
    }

    fn size(&self, level: usize) -> (u32, u32) {
        self.sizes[level]
    }

    fn texel(&self, level: usize, x: u32, y: u32) -> [f64; 4] {
        let w = self.sizes[level].0 as usize;
        self.levels[level][y as usize * w + x as usize]
    }
}

/// Sampler options of the reference.
#[derive(Clone, Copy, Debug)]
pub struct State {
    /// Address modes of u and v.
    pub address: [Address; 2],
    /// Border colour, channel values 0..=255 (linear).
    pub border: [f64; 4],
    /// Lod bias.
    pub bias: f64,
    /// Lower lod clamp.
    pub min_lod: f64,
    /// Upper lod clamp.
    pub max_lod: f64,
    /// Maximum anisotropy (1..=16).
    pub max_aniso: u32,
    /// Texels are sRGB-encoded (RGB).
    pub srgb: bool,
    /// Return sRGB results re-encoded (else linear).
    pub encode_srgb: bool,
}

impl Default for State {
    /// Wrap on both axes, transparent black border, no bias, no clamps
    /// but the stored levels, isotropic, linear texels.
    fn default() -> Self {
        Self {
            address: [Address::Wrap; 2],
            border: [0.0; 4],
            bias: 0.0,
            min_lod: f64::NEG_INFINITY,
            max_lod: f64::INFINITY,
            max_aniso: 1,
            srgb: false,
            encode_srgb: false,
        }
    }
}

/// The reference sampler over texels `T`.
#[derive(Clone, Debug)]
pub struct Sampler<'a, T: Texels + ?Sized> {
    /// The texels.
    pub tex: &'a T,
    /// The options.
    pub state: State,
}

impl<T: Texels + ?Sized> Sampler<'_, T> {
    /// Texel `(i, j)` of `level` in linear 0..1 (addressing, border, sRGB
    /// decode).
    fn texel(&self, level: usize, i: i64, j: i64) -> [f64; 4] {
        let (w, h) = self.tex.size(level);
        let x = self.state.address[0].index(i, i64::from(w));
        let y = self.state.address[1].index(j, i64::from(h));
        let t = match (x, y) {
            (Some(x), Some(y)) => {
                let t = self.tex.texel(level, x as u32, y as u32);
                if self.state.srgb {
                    [
                        srgb_to_linear(t[0] / 255.0) * 255.0,
                        srgb_to_linear(t[1] / 255.0) * 255.0,
                        srgb_to_linear(t[2] / 255.0) * 255.0,
                        t[3],
                    ]
                } else {
                    t
                }
            }
            _ => self.state.border,
        };
        t.map(|c| c / 255.0)
    }

    fn bilinear(&self, u: f64, v: f64, level: usize) -> [f64; 4] {
        let (w, h) = self.tex.size(level);
        let x = u * f64::from(w) - 0.5;
        let y = v * f64::from(h) - 0.5;
        let (i, j) = (x.floor(), y.floor());
        let (fx, fy) = (x - i, y - j);
        let (i, j) = (i as i64, j as i64);
        let t = [
            self.texel(level, i, j),
            self.texel(level, i + 1, j),
            self.texel(level, i, j + 1),
            self.texel(level, i + 1, j + 1),
        ];
        std::array::from_fn(|c| {
            (t[0][c] * (1.0 - fx) + t[1][c] * fx) * (1.0 - fy)
                + (t[2][c] * (1.0 - fx) + t[3][c] * fx) * fy
        })
    }

    fn nearest(&self, u: f64, v: f64, level: usize) -> [f64; 4] {
        let (w, h) = self.tex.size(level);
        self.texel(
            level,
            (u * f64::from(w)).floor() as i64,
            (v * f64::from(h)).floor() as i64,
        )
    }

    /// The lod a sample uses: bias, `[min, max]`, stored levels (a NaN lod
    /// reads as 0).
    #[must_use]
    pub fn lod(&self, lod: f64) -> f64 {
        let lod = if lod.is_nan() { 0.0 } else { lod };
        let top = (self.tex.levels() - 1) as f64;
        (lod + self.state.bias)
            .clamp(self.state.min_lod, self.state.max_lod)
            .clamp(0.0, top)
    }

    /// Linear 0..1 filter value at an already processed lod. Between two
    /// levels at a zero blend weight only the lower level is read (the
    /// blend is that level's value exactly).
    fn filter(&self, u: f64, v: f64, lod: f64, mode: Mode) -> [f64; 4] {
        let top = self.tex.levels() - 1;
        let lower = lod.floor() as usize;
        let t = lod - lod.floor();
        let upper = (lower + 1).min(top);
        let nearest = ((lod + 0.5).floor() as usize).min(top);
        let mix = |a: [f64; 4], b: [f64; 4]| std::array::from_fn(|c| a[c] * (1.0 - t) + b[c] * t);
        let two = |level: &dyn Fn(usize) -> [f64; 4]| {
            if t == 0.0 {
                level(lower)
            } else {
                mix(level(lower), level(upper))
            }
        };
        match mode {
            Mode::Trilinear => two(&|k| self.bilinear(u, v, k)),
            Mode::BilinearNearestLevel => self.bilinear(u, v, nearest),
            Mode::Nearest => self.nearest(u, v, nearest),
            Mode::NearestTexelLinearLevel => two(&|k| self.nearest(u, v, k)),
        }
    }

    /// Output channel values 0..=255 (unrounded) of a linear 0..1 result.
    fn output(&self, lin: [f64; 4]) -> [f64; 4] {
        std::array::from_fn(|c| {
            if self.state.srgb && self.state.encode_srgb && c < 3 {
                linear_to_srgb(lin[c]) * 255.0
            } else {
                lin[c] * 255.0
            }
        })
    }

    /// Exact sample at `(u, v)` and `lod` with filter `mode`, linear 0..1
    /// (sRGB texels decoded, not re-encoded).
    #[must_use]
    pub fn sample_linear(&self, u: f64, v: f64, lod: f64, mode: Mode) -> [f64; 4] {
        self.filter(u, v, self.lod(lod), mode)
    }

    /// Exact sample at `(u, v)` and `lod` with filter `mode`, channel
    /// values 0..=255 (unrounded; sRGB re-encoded when asked).
    #[must_use]
    pub fn sample(&self, u: f64, v: f64, lod: f64, mode: Mode) -> [f64; 4] {
        self.output(self.sample_linear(u, v, lod, mode))
    }

    /// Exact anisotropic sample (mean of the probes' `mode` samples,
    /// [`aniso_probes`]), linear 0..1.
    #[must_use]
    pub fn sample_aniso_linear(&self, u: f64, v: f64, axes: [[f64; 2]; 2], mode: Mode) -> [f64; 4] {
        let (n, lod, probes) = aniso_probes(self.tex.size(0), self.state.max_aniso, u, v, axes);
        let lod = self.lod(lod);
        let mut acc = [0.0; 4];
        for p in &probes {
            let s = self.filter(p[0], p[1], lod, mode);
            for c in 0..4 {
                acc[c] += s[c] / f64::from(n);
            }
        }
        acc
    }

    /// Exact anisotropic sample, channel values 0..=255 (unrounded).
    #[must_use]
    pub fn sample_aniso(&self, u: f64, v: f64, axes: [[f64; 2]; 2], mode: Mode) -> [f64; 4] {
        self.output(self.sample_aniso_linear(u, v, axes, mode))
    }
}

/// Probe count, lod (before bias/clamps) and exact probe positions of the
/// anisotropic footprint `axes = [(du/dx, dv/dx), (du/dy, dv/dy)]` at
/// `(u, v)` on a level 0 of `size` texels with at most `max` probes
/// (pbrt-style: minor axis clamped to major/max, `N = ceil(major/minor')`,
/// lod `log2 minor'`, probes at `t_i = (2i + 1 − N)/(2N)` along the major
/// axis).
#[must_use]
pub fn aniso_probes(
    size: (u32, u32),
    max: u32,
    u: f64,
    v: f64,
    axes: [[f64; 2]; 2],
) -> (u32, f64, Vec<[f64; 2]>) {
    let (w, h) = size;
    let len = |a: [f64; 2]| (a[0] * f64::from(w)).hypot(a[1] * f64::from(h));
    let (major, minor) = if len(axes[0]) >= len(axes[1]) {
        (axes[0], len(axes[1]))
    } else {
        (axes[1], len(axes[0]))
    };
    let lmaj = len(major);
    let max = max.max(1);
    let minor = minor.max(lmaj / f64::from(max)).max(f64::MIN_POSITIVE);
    let n = ((lmaj / minor).ceil() as u32).clamp(1, max);
    let nf = f64::from(n);
    let probes = (0..n)
        .map(|i| {
            let t = (2.0 * f64::from(i) + 1.0 - nf) / (2.0 * nf);
            [u + major[0] * t, v + major[1] * t]
        })
        .collect();
    (n, minor.log2(), probes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn address_modes_follow_the_wrapping_operation() {
        let n = 4;
        let got = |a: Address| (-5..9).map(|i| a.index(i, n)).collect::<Vec<_>>();
        let s = |v: &[i64]| v.iter().map(|&x| Some(x)).collect::<Vec<_>>();
        for (a, want) in [
            (Address::Wrap, [3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0]),
            (Address::Mirror, [3, 3, 2, 1, 0, 0, 1, 2, 3, 3, 2, 1, 0, 0]),
            (
                Address::ClampToEdge,
                [0, 0, 0, 0, 0, 0, 1, 2, 3, 3, 3, 3, 3, 3],
            ),
            (
                Address::MirrorOnce,
                [3, 3, 2, 1, 0, 0, 1, 2, 3, 3, 3, 3, 3, 3],
            ),
        ] {
            assert_eq!(got(a), s(&want), "{a:?}");
        }
        let border = got(Address::ClampToBorder);
        assert_eq!(border.iter().filter(|x| x.is_some()).count(), 4);
        assert_eq!(border[5..9], s(&[0, 1, 2, 3])[..]);
    }

    #[test]
    fn trilinear_blends_two_bilinear_levels() {
        // Level 0 all 0, level 1 all 255: the result is 255·frac(lod).
        let tex = Texture::from_fn(&level_sizes(2, 2, 2), |k, _, _| [255.0 * k as f64; 4]);
        let s = Sampler {
            tex: &tex,
            state: State::default(),
        };
        for (lod, want) in [
            (0.0, 0.0),
            (0.25, 63.75),
            (1.0, 255.0),
            (7.0, 255.0),
            (-3.0, 0.0),
        ] {
            let got = s.sample(0.3, 0.7, lod, Mode::Trilinear);
            assert!((got[0] - want).abs() < 1e-9, "lod {lod}: {got:?}");
        }
        assert_eq!(s.sample(0.3, 0.7, f64::NAN, Mode::Trilinear)[0], 0.0);
    }

    #[test]
    fn aniso_probe_count_and_lod() {
        // Major axis 8 texels, minor 2: 4 probes at lod 1.
        let (n, lod, p) = aniso_probes((16, 16), 16, 0.5, 0.5, [[0.5, 0.0], [0.0, 0.125]]);
        assert_eq!(n, 4);
        assert!((lod - 1.0).abs() < 1e-12);
        assert_eq!(p.len(), 4);
        assert!((p[0][0] - (0.5 - 0.5 * 3.0 / 8.0)).abs() < 1e-12);
    }
}
