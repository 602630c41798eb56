//! Textures as the renderer uses them: MIP pyramids of RGBA8888 texels and
//! the two texture units of a render ([`Unit`]):
//!
//! * [`FirmwareUnit`]: the firmware texture unit, one
//!   `raymip::texture::Sampler` per texture (fixed point: [`TexCoord`],
//!   [`Lod`], [`Mode`] in, a texel out; wrap addressing), which also records
//!   the texel-block address of every fetch for the cache study;
//! * [`FloatUnit`]: the f64 reference sampler (`raymip_reference::sampler`,
//!   wrap addressing) over the same texels, counting the texels it reads.
//!
//! Anisotropic filtering (`Options::aniso`): the firmware unit's samplers
//! carry the maximum anisotropy in their state and sample the footprint
//! (`Sampler::sample_aniso`), the float unit takes the reference's
//! anisotropic sample (trilinear probes of `aniso_probes`).

use raymip::texture::sampler::state::{SamplerDesc, SamplerState};
use raymip::texture::sampler::stochastic::StochasticMode;
use raymip::texture::storage::cache::BlockLayout;
use raymip::texture::storage::mip::{Geometry, Pyramid, Texel, TexelSource, full_levels, generate};
use raymip::texture::{Mode, Sampler};
use raymip::units::{Footprint, Lod, TexCoord};

use super::RenderError;
use super::options::Method;
use crate::scene::TextureImage;
use raymip_reference::sampler::{self as reference, Texels, aniso_probes};

/// Which filter a sample uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    /// Trilinear between the two levels around the lod.
    Trilinear,
    /// Bilinear in level 0 only (mip mapping off, ground truth).
    BilinearLevel0,
    /// Bilinear in the nearest level `floor(lod + ½)`.
    Bilinear,
    /// Nearest texel of the nearest level.
    Nearest,
    /// A firmware stochastic filter (`raymip::texture::sampler::stochastic`), driven by the
    /// random bits passed to [`FirmwareUnit::sample_rgb`]. The f64 unit has no
    /// stochastic mode: it returns the filter's expectation (trilinear for
    /// the level-choosing modes, bilinear for stochastic bilinear).
    Stochastic(StochasticMode),
}

impl Filter {
    /// The filter of a LOD method: bilinear in level 0 without LOD (mip 0,
    /// ground truth), trilinear otherwise.
    #[must_use]
    pub fn of(method: Method) -> Self {
        match method {
            Method::Mip0 | Method::Truth => Self::BilinearLevel0,
            Method::Table | Method::Cone | Method::Raydiff | Method::Gbuffer => Self::Trilinear,
        }
    }
}

/// Fetch counters and, optionally, the log of fetched texel-block
/// addresses (global: per-texture block base + block index).
#[derive(Clone, Debug, Default)]
pub struct FetchLog {
    /// Texels fetched.
    pub fetched: u64,
    /// Fetches the filter skipped (zero-weight texels or levels).
    pub skipped: u64,
    /// Block addresses in fetch order, when recording.
    pub blocks: Option<Vec<u32>>,
    /// Isotropic samples taken.
    pub samples: u64,
    /// Anisotropic samples taken.
    pub aniso_samples: u64,
    /// Σ of the lods the unit was given for its isotropic samples, in
    /// 1/256 level (exact for fixed-point lods, rounded for f64 ones).
    pub lod_sum_256: i64,
}

impl FetchLog {
    /// Adds a sampler's counters and moves the block addresses its
    /// recorder logged.
    fn take(&mut self, st: raymip::texture::FetchStats, source: &mut Recorder<'_>) {
        self.fetched += st.fetched;
        self.skipped += st.skipped;
        if let (Some(all), Some(b)) = (self.blocks.as_mut(), source.blocks.as_mut()) {
            all.append(b);
        }
    }
}

/// RGB of an RGBA8 texel in 0..1.
fn texel_rgb(t: Texel) -> [f64; 3] {
    let c = t.to_le_bytes();
    [
        f64::from(c[0]) / 255.0,
        f64::from(c[1]) / 255.0,
        f64::from(c[2]) / 255.0,
    ]
}

/// A MIP pyramid in one buffer (level 0 first), built by the firmware's
/// `mip::generate`.
#[derive(Clone, Debug)]
pub struct MipTexture {
    /// Name.
    pub name: String,
    /// Level-0 width.
    pub width: u32,
    /// Level-0 height.
    pub height: u32,
    /// Number of levels (full chain down to 1×1).
    pub levels: u8,
    /// All levels' texels.
    pub texels: Vec<Texel>,
    /// First 4×4-block address of this texture in the global texel memory.
    pub block_base: u32,
    /// Number of block addresses this texture spans (`BlockLayout::len`).
    pub block_span: u32,
    geometry: Geometry,
    layout: BlockLayout,
}

impl MipTexture {
    /// Builds the full pyramid of `img` with the firmware generator.
    ///
    /// # Errors
    /// [`RenderError::Pyramid`] naming the texture when its size cannot
    /// form a pyramid.
    pub fn new(img: &TextureImage) -> Result<Self, RenderError> {
        let levels = full_levels(img.width, img.height);
        let pyramid = |source| RenderError::Pyramid {
            texture: img.name.clone(),
            width: img.width,
            height: img.height,
            source,
        };
        let geometry = Geometry::new(img.width, img.height, levels).map_err(pyramid)?;
        let mut texels = vec![0u32; geometry.len()];
        let n = img.texels.len().min(texels.len());
        texels[..n].copy_from_slice(&img.texels[..n]);
        generate(&geometry, &mut texels).map_err(pyramid)?;
        Ok(Self {
            name: img.name.clone(),
            width: img.width,
            height: img.height,
            levels,
            texels,
            block_base: 0,
            block_span: BlockLayout::new(&geometry).len(),
            geometry,
            layout: BlockLayout::new(&geometry),
        })
    }

    /// The same texture over other stored texels: `geometry` (the full
    /// one or a [trimmed](Geometry::trimmed) one) and its texels (empty: a
    /// texture with nothing stored, which samples black). Block addresses
    /// stay those of the full pyramid.
    #[must_use]
    pub fn with_pyramid(&self, geometry: Geometry, texels: Vec<Texel>) -> Self {
        Self {
            texels,
            geometry,
            layout: BlockLayout::new(&geometry),
            ..self.clone()
        }
    }

    /// Size of `level`.
    #[must_use]
    pub fn level_size(&self, level: u8) -> (u32, u32) {
        self.geometry.level_size(level)
    }

    /// The firmware geometry.
    #[must_use]
    pub fn geometry(&self) -> Geometry {
        self.geometry
    }

    fn texel(&self, level: u8, x: u32, y: u32) -> u32 {
        self.texels
            .get(self.geometry.texel_index(level, x, y))
            .copied()
            .unwrap_or(0)
    }
}

/// Assigns consecutive block bases to the textures.
pub fn assign_block_bases(textures: &mut [MipTexture]) {
    let mut base = 0u32;
    for t in textures {
        t.block_base = base;
        base = base.saturating_add(t.block_span);
    }
}

/// The texture unit of one render (per tile: it holds the samplers' state).
#[derive(Debug)]
pub enum Unit<'a> {
    /// The firmware unit (fixed-point renders).
    Firmware(FirmwareUnit<'a>),
    /// The f64 reference unit (float renders).
    Float(FloatUnit<'a>),
}

impl<'a> Unit<'a> {
    /// The unit for `textures`: the firmware one for fixed-point renders
    /// (recording block addresses when `record`), else the f64 one.
    #[must_use]
    pub fn new(textures: &'a [MipTexture], fixed: bool, record: bool, aniso: Option<u8>) -> Self {
        if fixed {
            Self::Firmware(FirmwareUnit::new(textures, record, aniso))
        } else {
            Self::Float(FloatUnit {
                textures,
                max_aniso: aniso.unwrap_or(1),
            })
        }
    }
}

/// The f64 reference sampler over the render's textures.
#[derive(Clone, Copy, Debug)]
pub struct FloatUnit<'a> {
    textures: &'a [MipTexture],
    max_aniso: u8,
}

/// One texture as the reference reads it, counting the texels read.
struct Counted<'a> {
    tex: &'a MipTexture,
    reads: std::cell::Cell<u64>,
}

impl Texels for Counted<'_> {
    fn levels(&self) -> usize {
        usize::from(self.tex.levels)
    }

    fn size(&self, level: usize) -> (u32, u32) {
        self.tex.level_size(level as u8)
    }

    fn texel(&self, level: usize, x: u32, y: u32) -> [f64; 4] {
        self.reads.set(self.reads.get() + 1);
        self.tex
            .texel(level as u8, x, y)
            .to_le_bytes()
            .map(f64::from)
    }
}

impl FloatUnit<'_> {
    /// Runs `f` on the reference sampler of texture `tex` (wrap, the
    /// render's maximum anisotropy) and adds the texels it read to `log`;
    /// black for an unknown texture.
    fn with_reference(
        &self,
        tex: usize,
        log: &mut FetchLog,
        f: impl FnOnce(&reference::Sampler<'_, Counted<'_>>) -> [f64; 4],
    ) -> [f64; 3] {
        let Some(tex) = self.textures.get(tex) else {
            return [0.0; 3];
        };
        let counted = Counted {
            tex,
            reads: std::cell::Cell::new(0),
        };
        let sampler = reference::Sampler {
            tex: &counted,
            state: reference::State {
                max_aniso: u32::from(self.max_aniso),
                ..reference::State::default()
            },
        };
        let c = f(&sampler);
        log.fetched += counted.reads.get();
        [c[0], c[1], c[2]]
    }

    /// One sample of texture `tex` (f64 lod, clamped to the stored levels;
    /// NaN = level 0), linear RGB in 0..1; black for an unknown texture.
    /// A trilinear sample that reads one level (the lod is a whole level)
    /// counts the other level's four texels as skipped.
    pub fn sample(
        &self,
        tex: usize,
        u: f64,
        v: f64,
        lod: f64,
        filter: Filter,
        log: &mut FetchLog,
    ) -> [f64; 3] {
        let (mode, lod) = match filter {
            Filter::BilinearLevel0 => (reference::Mode::BilinearNearestLevel, 0.0),
            Filter::Bilinear | Filter::Stochastic(StochasticMode::Bilinear) => {
                (reference::Mode::BilinearNearestLevel, lod)
            }
            Filter::Nearest => (reference::Mode::Nearest, lod),
            Filter::Trilinear | Filter::Stochastic(_) => (reference::Mode::Trilinear, lod),
        };
        let before = log.fetched;
        let rgb = self.with_reference(tex, log, |s| s.sample_linear(u, v, lod, mode));
        if mode == reference::Mode::Trilinear && log.fetched - before == 4 {
            log.skipped += 4;
        }
        rgb
    }

    /// Anisotropic sample: the reference's mean of trilinear samples at
    /// the probes of `aniso_probes` (exact positions and lod), linear RGB
    /// in 0..1. Probes at a whole-level lod count the other level's texels
    /// as skipped, as [`sample`](Self::sample) does.
    pub fn sample_aniso(
        &self,
        tex: usize,
        u: f64,
        v: f64,
        axes: [[f64; 2]; 2],
        log: &mut FetchLog,
    ) -> [f64; 3] {
        let mut probes = 0;
        let before = log.fetched;
        let rgb = self.with_reference(tex, log, |s| {
            probes = u64::from(aniso_probes(s.tex.size(0), s.state.max_aniso, u, v, axes).0);
            s.sample_aniso_linear(u, v, axes, reference::Mode::Trilinear)
        });
        log.skipped += 8 * probes - (log.fetched - before);
        rgb
    }
}

/// A [`TexelSource`] over one texture's pyramid that logs the global block
/// address of every fetch (when recording).
#[derive(Debug)]
struct Recorder<'a> {
    pyramid: Pyramid<'a>,
    layout: &'a BlockLayout,
    base: u32,
    blocks: Option<Vec<u32>>,
}

impl TexelSource for Recorder<'_> {
    fn geometry(&self) -> Geometry {
        self.pyramid.geometry()
    }

    fn texel(&mut self, level: u8, x: u32, y: u32) -> Texel {
        if let Some(b) = self.blocks.as_mut() {
            b.push(self.base.wrapping_add(self.layout.index(level, x, y)));
        }
        self.pyramid.get(level, x, y)
    }

    fn footprint(&mut self, level: u8, x: [u32; 2], y: [u32; 2]) -> [Texel; 4] {
        if let Some(b) = self.blocks.as_mut() {
            for (xx, yy) in [(x[0], y[0]), (x[1], y[0]), (x[0], y[1]), (x[1], y[1])] {
                b.push(self.base.wrapping_add(self.layout.index(level, xx, yy)));
            }
        }
        self.pyramid.footprint(level, x, y)
    }
}

/// The firmware texture unit: one [`Sampler`] per texture, built once.
#[derive(Debug)]
pub struct FirmwareUnit<'a> {
    samplers: Vec<Option<Sampler<Recorder<'a>>>>,
}

impl<'a> FirmwareUnit<'a> {
    /// One wrap-addressing sampler per texture; `record` logs the block
    /// address of every fetch.
    #[must_use]
    pub fn new(textures: &'a [MipTexture], record: bool, aniso: Option<u8>) -> Self {
        let source = |tex: &'a MipTexture| {
            Some(Recorder {
                pyramid: Pyramid::new(tex.geometry, &tex.texels).ok()?,
                layout: &tex.layout,
                base: tex.block_base,
                blocks: record.then(Vec::new),
            })
        };
        // Wrap on both axes (the default), the maximum anisotropy of the
        // render (1 = isotropic; only `sample_aniso` reads it).
        let state = SamplerState::new(SamplerDesc {
            max_anisotropy: aniso.unwrap_or(1).clamp(1, 16),
            ..SamplerDesc::default()
        })
        .unwrap_or_default();
        let samplers = textures
            .iter()
            .map(|tex| Sampler::with_state(source(tex)?, state).ok())
            .collect();
        Self { samplers }
    }

    /// One anisotropic sample of texture `tex` through the firmware
    /// sampler (trilinear probes); fetches go to `log`. Texel 0 for an
    /// unknown texture.
    pub fn sample_aniso(
        &mut self,
        tex: usize,
        u: TexCoord,
        v: TexCoord,
        fp: &Footprint,
        log: &mut FetchLog,
    ) -> Texel {
        let Some(Some(sampler)) = self.samplers.get_mut(tex) else {
            return 0;
        };
        let t = sampler.sample_aniso(u, v, fp);
        log.take(sampler.stats(), sampler.source_mut());
        sampler.reset_stats();
        t
    }

    /// One isotropic sample of texture `tex` at `(u, v)` in texture
    /// repeats (wrap addressing) at the fixed-point `lod` with `filter`, as
    /// linear RGB in 0..1; `bits`: the 32 random bits of a
    /// [`Filter::Stochastic`] sample (ignored by the other filters).
    #[allow(clippy::too_many_arguments)]
    pub fn sample_rgb(
        &mut self,
        tex: usize,
        u: f64,
        v: f64,
        lod: Lod,
        filter: Filter,
        bits: u32,
        log: &mut FetchLog,
    ) -> [f64; 3] {
        let (u, v) = (wrap_coord(u), wrap_coord(v));
        let mode = match filter {
            Filter::Trilinear => Mode::Trilinear,
            Filter::BilinearLevel0 | Filter::Bilinear => Mode::BilinearNearestLevel,
            Filter::Nearest => Mode::Nearest,
            Filter::Stochastic(m) => {
                return texel_rgb(self.sample_stochastic(tex, u, v, lod, m, bits, log));
            }
        };
        texel_rgb(self.sample(tex, u, v, lod, mode, log))
    }

    /// One anisotropic sample of texture `tex` at `(u, v)` in texture
    /// repeats over the firmware footprint `fp` (normalized texture
    /// coordinates per pixel), as linear RGB in 0..1.
    pub fn sample_aniso_rgb(
        &mut self,
        tex: usize,
        u: f64,
        v: f64,
        fp: &Footprint,
        log: &mut FetchLog,
    ) -> [f64; 3] {
        texel_rgb(self.sample_aniso(tex, wrap_coord(u), wrap_coord(v), fp, log))
    }

    /// One sample of texture `tex` through the firmware sampler; fetch
    /// counts (and block addresses) go to `log`. Texel 0 (black) for an
    /// unknown texture.
    pub fn sample(
        &mut self,
        tex: usize,
        u: TexCoord,
        v: TexCoord,
        lod: Lod,
        mode: Mode,
        log: &mut FetchLog,
    ) -> Texel {
        let Some(Some(sampler)) = self.samplers.get_mut(tex) else {
            return 0;
        };
        let t = sampler.sample(u, v, lod, mode);
        log.take(sampler.stats(), sampler.source_mut());
        sampler.reset_stats();
        t
    }

    /// One stochastic sample (`raymip::texture::sampler::stochastic`) of texture `tex` with
    /// the random `bits`; fetches go to `log`. Texel 0 for an unknown
    /// texture.
    #[allow(clippy::too_many_arguments)]
    pub fn sample_stochastic(
        &mut self,
        tex: usize,
        u: TexCoord,
        v: TexCoord,
        lod: Lod,
        mode: StochasticMode,
        bits: u32,
        log: &mut FetchLog,
    ) -> Texel {
        let Some(Some(sampler)) = self.samplers.get_mut(tex) else {
            return 0;
        };
        let t = sampler.sample_stochastic(u, v, lod, mode, bits);
        log.take(sampler.stats(), sampler.source_mut());
        sampler.reset_stats();
        t
    }
}

/// `u` reduced to `[0, 1)` (wrap addressing, exact in f64) as a [`TexCoord`].
fn wrap_coord(u: f64) -> TexCoord {
    if u.is_finite() {
        TexCoord::saturating_from_num(u - u.floor())
    } else {
        TexCoord::ZERO
    }
}
