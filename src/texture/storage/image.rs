//! A texture stored in any [`TexelFormat`]: geometry, format and a borrowed
//! byte slice holding every level, read as RGBA8 texels.
//!
//! # Layout
//!
//! Levels follow each other, level 0 first, each tightly packed:
//! uncompressed levels row-major at [`TexelFormat::unit_bytes`] per texel
//! (multi-byte texels little-endian); BC levels as
//! `ceil(w/4) × ceil(h/4)` blocks row-major, 8 or 16 bytes each (texels of
//! a block beyond the level's edge are padding and never read).
//! [`image_len`] is a `const fn`, so storage can be a `static`. A BC1 level
//! costs half a byte per texel.
//!
//! # Reads
//!
//! As a [`TexelSource`] an image decodes each texel on read (a BC texel
//! decodes its block's palette: slow, for tests and cache-less use). As a
//! [`TexelMemory`] it decodes a whole 4×4 block per cache fill, so a
//! [`TexelCache`](crate::texture::storage::cache::TexelCache) in front of a BC image is the
//! block decoder: the cache holds decoded RGBA8 texels. sRGB data stays
//! encoded here; the sampler ([`crate::texture::kernel::srgb`]) linearizes it.

use core::fmt;

use crate::texture::storage::bc::{self, BLOCK_TEXELS};
use crate::texture::storage::cache::{BLOCK, TexelMemory};
use crate::texture::storage::format::{
    AnyFormat, ColorSpace, Format, NoSrgbVariant, PixelFormat, RGB565_SPLIT, Rgb565, TexelFormat,
};
use crate::texture::storage::level::{LevelView, ViewFormat};
use crate::texture::storage::mip::{Geometry, MAX_LEVELS, MipError, Texel, TexelSource, clamp_to};
use crate::texture::storage::pow2::Pow2Source;

/// Bytes of level `k` of a `width × height` texture in `format`.
const fn level_bytes(width: u32, height: u32, k: u8, format: TexelFormat) -> u64 {
    let k = (k & 31) as u32;
    let w = if width >> k == 0 { 1 } else { width >> k } as u64;
    let h = if height >> k == 0 { 1 } else { height >> k } as u64;
    let unit = format.unit_bytes() as u64;
    if format.is_block_compressed() {
        // Blocks < 2⁶⁰, but 16 bytes each need not fit u64: saturate.
        (w.div_ceil(BLOCK as u64) * h.div_ceil(BLOCK as u64)).saturating_mul(unit)
    } else {
        // w·h < 2⁶⁴, but times up to 4 bytes it need not fit: saturate.
        (w * h).saturating_mul(unit)
    }
}

/// Bytes of levels `0 .. levels` of a `width × height` texture in `format`
/// (levels limited to [`full_levels`](crate::texture::storage::mip::full_levels); 0 for a
/// zero side; saturates at `usize::MAX`).
#[must_use]
pub const fn image_len(width: u32, height: u32, levels: u8, format: TexelFormat) -> usize {
    let full = crate::texture::storage::mip::full_levels(width, height);
    let mut total = 0u64;
    let mut k = 0;
    while k < levels && k < full {
        total = total.saturating_add(level_bytes(width, height, k, format));
        k += 1;
    }
    clamp_to(total, usize::MAX as u64)
}

/// The byte slice is shorter than the image needs. Example: [`Image`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageTooShort {
    /// Bytes needed ([`image_len`]).
    pub needed: usize,
    /// Bytes given.
    pub got: usize,
}

impl fmt::Display for ImageTooShort {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "image data holds {} bytes, the levels need {}",
            self.got, self.needed
        )
    }
}

impl core::error::Error for ImageTooShort {}

/// A texture in caller memory (see the module docs) in the pixel format
/// `F`: a marker type such as [`Rgb565`]
/// (the decode of that format alone, [`Image::typed`]) or [`AnyFormat`]
/// (chosen at run time, [`Image::new`]).
///
/// # Example
/// ```
/// use raymip::Geometry;
/// use raymip::texture::storage::format::{ColorSpace, Format, NoSrgbVariant, Rgb565, TexelFormat};
/// use raymip::texture::storage::image::{Image, ImageError, ImageTooShort, image_len};
/// // A 4×4 RGB565 texture with 3 levels: (16 + 4 + 1) texels · 2 bytes = 42.
/// const LEN: usize = image_len(4, 4, 3, TexelFormat::Rgb565);
/// assert_eq!(LEN, 42);
/// let mut bytes = [0u8; LEN];
/// bytes[..2].copy_from_slice(&0xF800u16.to_le_bytes()); // texel (0, 0): r5 = 31
/// let geometry = Geometry::new(4, 4, 3)?;
/// let image = Image::<Rgb565>::typed(geometry, ColorSpace::Linear, &bytes)?;
/// // Decoded to RGBA8 (red in the low byte): red 255, alpha 255.
/// assert_eq!(image.get(0, 0, 0), 0xFF00_00FF);
/// assert_eq!(image.level_offset(2), 40); // after 16 + 4 texels
/// // One byte short; sRGB for a format without an sRGB variant.
/// let short = Image::<Rgb565>::typed(geometry, ColorSpace::Linear, &bytes[..41]);
/// let too_short = ImageTooShort { needed: 42, got: 41 };
/// assert_eq!(short.unwrap_err(), ImageError::TooShort(too_short));
/// assert_eq!(too_short.to_string(), "image data holds 41 bytes, the levels need 42");
/// let srgb = Image::<Rgb565>::typed(geometry, ColorSpace::Srgb, &bytes);
/// assert_eq!(srgb.unwrap_err(), ImageError::NoSrgb(NoSrgbVariant(TexelFormat::Rgb565)));
/// // The format chosen at run time instead (`Image<AnyFormat>`).
/// let any = Image::new(geometry, Format::linear(TexelFormat::Rgb565), &bytes)?;
/// assert_eq!(any.get(0, 0, 0), image.get(0, 0, 0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Image<'a, F: PixelFormat = AnyFormat> {
    geometry: Geometry,
    kind: F,
    format: Format,
    bytes: &'a [u8],
    /// Where each level index `0 .. MAX_LEVELS` reads (clamped as
    /// [`get`](Self::get) clamps; indices past the top level repeat the
    /// top's record): made once here, so that a read loads one record
    /// instead of recomputing the level's size and offset.
    rows: [LevelRows; MAX_LEVELS as usize],
}

/// One level of an [`Image`] as a read addresses it.
#[derive(Clone, Copy, Debug, Default)]
struct LevelRows {
    /// Byte offset of the level ([`Image::level_offset`]; at most the
    /// image's byte length).
    offset: usize,
    /// The last column and row (`w − 1`, `h − 1` of
    /// [`Geometry::level_size`]; below [`MAX_SIZE`](crate::texture::storage::mip::MAX_SIZE), so 16 bits).
    last: [u16; 2],
}

impl LevelRows {
    /// Byte offset of texel `(x, y)` of the level (both in range; for a
    /// BC format the texel's block).
    #[inline(always)]
    fn byte(self, x: u32, y: u32, f: TexelFormat) -> usize {
        let [lx, _] = self.last.map(usize::from);
        let (x, y) = (x as usize, y as usize);
        let unit = f.unit_bytes() as usize;
        if f.is_block_compressed() {
            // ⌈w/4⌉ = ⌊(w − 1)/4⌋ + 1 blocks per row.
            let b = BLOCK as usize;
            self.offset + ((y / b) * (lx / b + 1) + x / b) * unit
        } else {
            self.offset + (y * (lx + 1) + x) * unit
        }
    }
}

impl<'a> Image<'a, AnyFormat> {
    /// Wraps `bytes` (at least [`image_len`] long; extra bytes ignored) in
    /// `format`, chosen at run time.
    ///
    /// # Errors
    /// [`ImageTooShort`].
    pub fn new(geometry: Geometry, format: Format, bytes: &'a [u8]) -> Result<Self, ImageTooShort> {
        Self::with_kind(geometry, AnyFormat(format.texel()), format, bytes)
    }
}

/// Why [`Image::typed`] refuses its input. Example: [`Image`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageError {
    /// The byte slice is shorter than the levels need.
    TooShort(ImageTooShort),
    /// The format has no sRGB variant.
    NoSrgb(NoSrgbVariant),
}

impl fmt::Display for ImageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooShort(e) => e.fmt(f),
            Self::NoSrgb(e) => e.fmt(f),
        }
    }
}

impl core::error::Error for ImageError {}

impl<'a, F: PixelFormat + Default> Image<'a, F> {
    /// Wraps `bytes` (at least [`image_len`] long) in the format `F` with
    /// colour space `space`.
    ///
    /// # Errors
    /// [`ImageError::TooShort`], [`ImageError::NoSrgb`] (sRGB for a format
    /// without an sRGB variant).
    pub fn typed(
        geometry: Geometry,
        space: ColorSpace,
        bytes: &'a [u8],
    ) -> Result<Self, ImageError> {
        let kind = F::default();
        let format = Format::new(kind.texel(), space).map_err(ImageError::NoSrgb)?;
        Self::with_kind(geometry, kind, format, bytes).map_err(ImageError::TooShort)
    }
}

impl<'a, F: PixelFormat> Image<'a, F> {
    fn with_kind(
        geometry: Geometry,
        kind: F,
        format: Format,
        bytes: &'a [u8],
    ) -> Result<Self, ImageTooShort> {
        let f = format.texel();
        let mut rows = [LevelRows::default(); MAX_LEVELS as usize];
        let (mut total, mut offset) = (0usize, 0usize);
        for (k, r) in (0u8..).zip(rows.iter_mut()) {
            // Past the top level the top's offset stays.
            if k < geometry.levels() {
                offset = total;
                let n = level_bytes(geometry.width(), geometry.height(), k, f);
                total = total.saturating_add(usize::try_from(n).unwrap_or(usize::MAX));
            }
            let (w, h) = geometry.level_size(k);
            *r = LevelRows {
                offset,
                // Sides ≤ MAX_SIZE = 2¹⁵ (`Geometry`): `w − 1` fits.
                last: [(w - 1) as u16, (h - 1) as u16],
            };
        }
        let needed = total;
        if bytes.len() < needed {
            return Err(ImageTooShort {
                needed,
                got: bytes.len(),
            });
        }
        Ok(Self {
            geometry,
            kind,
            format,
            bytes,
            rows,
        })
    }

    /// The record of `level` (clamped to the top level: the records past
    /// it repeat the top's).
    #[inline(always)]
    fn level(&self, level: u8) -> LevelRows {
        self.rows[usize::from(level.min(MAX_LEVELS - 1))]
    }

    /// The format.
    #[must_use]
    pub fn format(&self) -> Format {
        self.format
    }

    /// The stored bytes.
    #[must_use]
    pub fn bytes(&self) -> &'a [u8] {
        self.bytes
    }

    /// Byte offset of `level` (clamped to the top stored level).
    #[must_use]
    pub fn level_offset(&self, level: u8) -> usize {
        self.level(level).offset
    }

    /// The bytes of block `(bx, by)` of a BC `level` (clamped to the
    /// level's block grid; empty if out of data).
    #[inline]
    fn block_bytes(&self, level: u8, bx: u32, by: u32) -> &'a [u8] {
        let l = self.level(level);
        // The last block column and row: ⌈w/4⌉ − 1 = ⌊(w − 1)/4⌋.
        let [lx, ly] = l.last.map(|n| u32::from(n) / BLOCK);
        let (x, y) = (bx.min(lx) * BLOCK, by.min(ly) * BLOCK);
        self.bytes
            .get(l.byte(x, y, self.kind.texel())..)
            .unwrap_or(&[])
    }

    /// Texel `(x, y)` of `level` as RGBA8 (sRGB data left encoded); level
    /// and coordinates clamped to the stored range.
    #[inline]
    #[must_use]
    pub fn get(&self, level: u8, x: u32, y: u32) -> Texel {
        let l = self.level(level);
        let [lx, ly] = l.last.map(u32::from);
        let (x, y) = (x.min(lx), y.min(ly));
        let f = self.kind.texel();
        if f.is_block_compressed() {
            let block = self.block_bytes(level, x / BLOCK, y / BLOCK);
            bc::decode_texel(f, block, ((y % BLOCK) * BLOCK + x % BLOCK) as usize)
        } else {
            f.decode(self.raw(l.byte(x, y, f), f.unit_bytes() as usize))
        }
    }

    /// The `unit ≤ 4` bytes at `at` as a little-endian word (0 past the
    /// data: one check for all of them).
    #[inline(always)]
    fn raw(&self, at: usize, unit: usize) -> u32 {
        match self.bytes.get(at..at.wrapping_add(unit)) {
            Some(b) => b
                .iter()
                .take(4)
                .rev()
                // `v << 8` has its low byte clear: `+` adds the byte.
                .fold(0, |v, &x| (v << 8) + u32::from(x)),
            None => 0,
        }
    }
}

impl<F: PixelFormat> TexelSource for Image<'_, F> {
    #[inline]
    fn geometry(&self) -> Geometry {
        self.geometry
    }

    #[inline]
    fn texel(&mut self, level: u8, x: u32, y: u32) -> Texel {
        self.get(level, x, y)
    }

    /// Uncompressed formats: the level's record (offset, last column and
    /// row) and the two row starts once per footprint, then per texel one
    /// read of its bytes and the format's expansion (BC formats read texel
    /// by texel).
    #[inline]
    fn footprint(&mut self, level: u8, x: [u32; 2], y: [u32; 2]) -> [Texel; 4] {
        let [lx, ly] = self.level(level).last.map(u32::from);
        self.footprint_in_level(level, x.map(|x| x.min(lx)), y.map(|y| y.min(ly)))
    }

    /// [`footprint`](Self::footprint) without the clamps: an index past
    /// the level reads another texel of the image, or past its bytes the
    /// expansion of 0. RGB565 expands each texel by the split table
    /// (`RGB565_SPLIT`: two loads and an OR).
    #[inline]
    fn footprint_in_level(&mut self, level: u8, x: [u32; 2], y: [u32; 2]) -> [Texel; 4] {
        let f = self.kind.texel();
        if f.is_block_compressed() {
            return [
                self.get(level, x[0], y[0]),
                self.get(level, x[1], y[0]),
                self.get(level, x[0], y[1]),
                self.get(level, x[1], y[1]),
            ];
        }
        let l = self.level(level);
        let unit = f.unit_bytes() as usize;
        let pitch = (usize::from(l.last[0]) + 1) * unit;
        let rows = y.map(|y| l.offset + y as usize * pitch);
        let cols = x.map(|x| x as usize * unit);
        let at = [
            rows[0] + cols[0],
            rows[0] + cols[1],
            rows[1] + cols[0],
            rows[1] + cols[1],
        ];
        if f == TexelFormat::Rgb565 {
            let texel = |at: usize| match self.bytes.get(at..).and_then(<[u8]>::first_chunk) {
                Some(&b) => Rgb565::expand(b),
                // Past the bytes: the expansion of 0 (`RGB565_SPLIT[1][0]`
                // is alpha alone).
                None => RGB565_SPLIT[0][0],
            };
            return [texel(at[0]), texel(at[1]), texel(at[2]), texel(at[3])];
        }
        at.map(|at| f.decode(self.raw(at, unit)))
    }
}

impl<F: PixelFormat> TexelMemory for Image<'_, F> {
    fn geometry(&self) -> Geometry {
        self.geometry
    }

    /// Decodes block `(bx, by)` of `level`: BC blocks in one go (the block
    /// decoder as the cache's fill path), uncompressed ones texel by texel
    /// (edge texels repeated beyond the level's edge).
    fn read_block(&mut self, level: u8, bx: u32, by: u32, out: &mut [Texel; BLOCK_TEXELS]) {
        let f = self.kind.texel();
        if f.is_block_compressed() {
            bc::decode_block(f, self.block_bytes(level, bx, by), out);
        } else {
            let (x0, y0) = (bx.saturating_mul(BLOCK), by.saturating_mul(BLOCK));
            for (i, t) in (0u32..).zip(out.iter_mut()) {
                *t = self.get(
                    level,
                    x0.saturating_add(i % BLOCK),
                    y0.saturating_add(i / BLOCK),
                );
            }
        }
    }
}

/// An RGB565 [`Image`] with power-of-two sides and its 16-bit level
/// views, one per level index `0 ..= 16` (indices past the top level
/// repeat it): the sampler's direct source for RGB565. A
/// [`Sampler`](crate::texture::Sampler) over it addresses the texels as
/// over a [`Pow2Pyramid`](crate::texture::storage::pow2::Pow2Pyramid)
/// (two row pointers per footprint, no check per sample) and expands
/// each of the four texels once (two loads of a split table and an OR).
///
/// # Example
/// ```
/// use raymip::texture::storage::format::{ColorSpace, Rgb565, TexelFormat};
/// use raymip::texture::storage::image::{Image, Pow2Rgb565, image_len};
/// use raymip::{Geometry, Lod, Mode, Sampler, TexCoord};
/// const LEN: usize = image_len(4, 4, 3, TexelFormat::Rgb565);
/// let bytes: Vec<u8> = (0..LEN as u32).map(|i| (i * 37) as u8).collect();
/// let image = Image::<Rgb565>::typed(Geometry::new(4, 4, 3)?, ColorSpace::Linear, &bytes)?;
/// let direct = Pow2Rgb565::new(image)?;
/// // The same texels as the image, read by the sampler without a check.
/// let (u, v, lod) = (TexCoord::from_num(0.3), TexCoord::from_num(0.6), Lod::from_num(0.5));
/// let a = Sampler::wrap(direct).sample(u, v, lod, Mode::Trilinear);
/// let b = Sampler::wrap(image).sample(u, v, lod, Mode::Trilinear);
/// assert_eq!(a, b);
/// // Sides that are not powers of two have no direct views.
/// let odd = Image::<Rgb565>::typed(Geometry::new(3, 4, 1)?, ColorSpace::Linear, &bytes)?;
/// assert_eq!(Pow2Rgb565::new(odd).unwrap_err(), raymip::MipError::NotPowerOfTwo);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub type Pow2Rgb565<'a> = Pow2Source<'a, Image<'a, Rgb565>, Rgb565>;

impl<'a> Pow2Rgb565<'a> {
    /// The views of `image`.
    ///
    /// # Errors
    /// [`MipError::NotPowerOfTwo`] when a side is not a power of two;
    /// [`MipError::BufferTooShort`] (in texels) when a level lies outside
    /// the bytes (an [`Image`] rules that out).
    pub fn new(image: Image<'a, Rgb565>) -> Result<Self, MipError> {
        Self::with_views(image, image.bytes.len() / 2, |k, w, h| {
            LevelView::from_bytes(image.bytes.get(image.level_offset(k)..)?, w, h)
        })
    }

    /// The image.
    #[must_use]
    pub fn image(&self) -> Image<'a, Rgb565> {
        self.source()
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::texture::storage::cache::TexelCache;
    use crate::texture::storage::format::ColorSpace;
    use std::vec::Vec;

    // `image_len` is a `const fn` (storage can be a `static`).
    const _: () = assert!(image_len(9, 5, 4, TexelFormat::Bc3) == 16 * 9);

    #[test]
    fn lengths() {
        assert_eq!(image_len(4, 4, 3, TexelFormat::Rgba8), 4 * 21);
        assert_eq!(image_len(4, 4, 3, TexelFormat::Rgb565), 2 * 21);
        // Levels past the full pyramid add nothing; fewer levels, fewer bytes.
        assert_eq!(image_len(4, 4, 9, TexelFormat::Rgb565), 2 * 21);
        assert_eq!(image_len(4, 4, 2, TexelFormat::Rgb565), 2 * 20);
        assert_eq!(image_len(4, 4, 0, TexelFormat::Rgb565), 0);
        assert_eq!(image_len(0, 4, 3, TexelFormat::Rgb565), 0);
        // BC1: 1 block + 1 + 1 (2×2 and 1×1 still take a whole block).
        assert_eq!(image_len(4, 4, 3, TexelFormat::Bc1), 24);
        assert_eq!(
            image_len(9, 5, 4, TexelFormat::Bc3),
            16 * (3 * 2 + 1 + 1 + 1)
        );
        let g = Geometry::new(4, 4, 3).unwrap();
        let f = Format::linear(TexelFormat::L8);
        assert_eq!(
            Image::new(g, f, &[0; 20]).unwrap_err(),
            ImageTooShort {
                needed: 21,
                got: 20
            }
        );
        assert!(Format::new(TexelFormat::L8, ColorSpace::Srgb).is_ok());
        // A typed image keeps its colour space.
        let srgb =
            Image::<crate::texture::storage::format::Rgba8>::typed(g, ColorSpace::Srgb, &[0; 84]);
        let want = Format::new(TexelFormat::Rgba8, ColorSpace::Srgb).unwrap();
        assert_eq!(srgb.unwrap().format(), want);
    }

    /// The errors say what is wrong, in numbers or by the format's name.
    #[test]
    fn errors_name_the_problem() {
        use std::string::ToString;
        let short = ImageTooShort {
            needed: 42,
            got: 41,
        };
        let msg = "image data holds 41 bytes, the levels need 42";
        assert_eq!(short.to_string(), msg);
        assert_eq!(ImageError::TooShort(short).to_string(), msg);
        let no_srgb = ImageError::NoSrgb(NoSrgbVariant(TexelFormat::Rgb565));
        let msg = "Rgb565 has no sRGB variant (only RGBA8, LA8, L8, BC1-BC3)";
        assert_eq!(no_srgb.to_string(), msg);
    }

    /// Like `mip::pyramid_len`: sides near 2³² must
    /// saturate, not overflow the 64-bit byte count.
    #[test]
    fn image_len_saturates_for_huge_sides() {
        for f in [TexelFormat::Rgba8, TexelFormat::L8, TexelFormat::Bc3] {
            assert_eq!(image_len(u32::MAX, u32::MAX, 32, f), usize::MAX, "{f:?}");
        }
        assert_eq!(
            image_len(u32::MAX, u32::MAX, 1, TexelFormat::Rgba8),
            usize::MAX
        );
        let one_row = usize::try_from(4 * u64::from(u32::MAX)).unwrap_or(usize::MAX);
        assert_eq!(image_len(u32::MAX, 1, 1, TexelFormat::Rgba8), one_row);
    }

    /// `n` pseudo-random bytes (bits `shift ..` of a multiplicative hash
    /// of the index).
    fn pattern(n: usize, shift: u32) -> Vec<u8> {
        (0..n as u32)
            .map(|i| (i.wrapping_mul(2_654_435_761) >> shift) as u8)
            .collect()
    }

    /// Texel `(x, y)` of `level` addressed from the layout of the module
    /// docs alone (level and indices clamped), not from the records.
    fn reference_texel(
        bytes: &[u8],
        g: Geometry,
        f: TexelFormat,
        level: u8,
        x: u32,
        y: u32,
    ) -> Texel {
        let k = level.min(g.top_level());
        let (w, h) = ((g.width() >> k).max(1), (g.height() >> k).max(1));
        let (x, y) = (x.min(w - 1) as usize, y.min(h - 1) as usize);
        let base = image_len(g.width(), g.height(), k, f);
        let unit = f.unit_bytes() as usize;
        if f.is_block_compressed() {
            let bw = w.div_ceil(BLOCK) as usize;
            let at = base + ((y / 4) * bw + x / 4) * unit;
            bc::decode_texel(f, &bytes[at..at + unit], (y % 4) * 4 + x % 4)
        } else {
            let at = base + (y * w as usize + x) * unit;
            let raw = bytes[at..at + unit]
                .iter()
                .rev()
                .fold(0, |v, &b| (v << 8) | u32::from(b));
            f.decode(raw)
        }
    }

    /// `get` reads the texel the module docs' layout places at `(x, y)`,
    /// in every format, for sizes with partial blocks and a single column,
    /// at every level index (past the top too) and with indices past the
    /// edges.
    #[test]
    fn get_follows_the_layout() {
        for (w, h, levels) in [(9, 6, 4), (8, 4, 4), (1, 5, 3), (13, 7, 2)] {
            let g = Geometry::new(w, h, levels).unwrap();
            for f in TexelFormat::ALL {
                let bytes = pattern(image_len(w, h, levels, f), 9);
                let img = Image::new(g, Format::linear(f), &bytes).unwrap();
                assert_eq!((img.format(), img.bytes()), (Format::linear(f), &bytes[..]));
                for level in 0..=20u8 {
                    for y in (0..h + 2).chain([u32::MAX]) {
                        for x in (0..w + 2).chain([u32::MAX]) {
                            assert_eq!(
                                img.get(level, x, y),
                                reference_texel(&bytes, g, f, level, x, y),
                                "{f:?} {w}x{h} {level} {x} {y}"
                            );
                        }
                    }
                }
                let k = levels - 1;
                assert_eq!(img.level_offset(20), image_len(w, h, k, f));
            }
        }
    }

    /// The footprint (the level records made once) reads the texels
    /// `get` reads, in every uncompressed format and size, at every level
    /// index (past the top too) and with indices past the edges.
    #[test]
    fn footprint_equals_texel_reads() {
        for (w, h, levels) in [(9, 6, 4), (8, 4, 4), (1, 5, 3)] {
            let g = Geometry::new(w, h, levels).unwrap();
            for f in TexelFormat::ALL {
                let bytes = pattern(image_len(w, h, levels, f), 11);
                let mut img = Image::new(g, Format::linear(f), &bytes).unwrap();
                for level in 0..=20u8 {
                    for x in [[0, 1], [3, 0], [8, 9], [7, u32::MAX]] {
                        for y in [[0, 1], [2, 0], [5, 6], [u32::MAX, 3]] {
                            let want = [
                                img.get(level, x[0], y[0]),
                                img.get(level, x[1], y[0]),
                                img.get(level, x[0], y[1]),
                                img.get(level, x[1], y[1]),
                            ];
                            assert_eq!(
                                img.footprint(level, x, y),
                                want,
                                "{f:?} {level} {x:?} {y:?}"
                            );
                            let (lw, lh) = g.level_size(level);
                            if x.iter().all(|&x| x < lw) && y.iter().all(|&y| y < lh) {
                                assert_eq!(
                                    img.footprint_in_level(level, x, y),
                                    want,
                                    "in level: {f:?} {level} {x:?} {y:?}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    /// A BC block index past the level's block grid reads the last block
    /// of its row or column (the cache asks for blocks beyond the edge).
    #[test]
    fn blocks_past_the_grid_read_the_edge_block() {
        let g = Geometry::new(9, 6, 4).unwrap();
        for f in TexelFormat::ALL
            .into_iter()
            .filter(|f| f.is_block_compressed())
        {
            let bytes = pattern(image_len(9, 6, 4, f), 5);
            let mut img = Image::new(g, Format::linear(f), &bytes).unwrap();
            for level in 0..4u8 {
                let (w, h) = g.level_size(level);
                let (lbx, lby) = ((w - 1) / BLOCK, (h - 1) / BLOCK);
                for (bx, by) in [
                    (lbx + 1, 0),
                    (0, lby + 1),
                    (lbx + 3, lby + 2),
                    (u32::MAX, 1),
                ] {
                    let mut got = [0; BLOCK_TEXELS];
                    let mut want = [0; BLOCK_TEXELS];
                    img.read_block(level, bx, by, &mut got);
                    img.read_block(level, bx.min(lbx), by.min(lby), &mut want);
                    assert_eq!(got, want, "{f:?} {level} {bx} {by}");
                }
            }
        }
    }

    /// Indices whose bytes lie past the image's data read the expansion
    /// of 0 (never a panic), in every uncompressed format.
    #[test]
    fn footprint_past_the_data_reads_the_expansion_of_zero() {
        let g = Geometry::new(4, 4, 3).unwrap();
        for f in TexelFormat::ALL
            .into_iter()
            .filter(|f| !f.is_block_compressed())
        {
            let bytes = pattern(image_len(4, 4, 3, f), 7);
            let mut img = Image::new(g, Format::linear(f), &bytes).unwrap();
            let far = u32::MAX / 2;
            let got = img.footprint_in_level(0, [far, far], [far, 1 << 30]);
            assert_eq!(got, [f.decode(0); 4], "{f:?}");
        }
    }

    /// Through the cache (block decode on fill) and directly (texel
    /// decode), every format reads the same texels.
    #[test]
    fn cache_fill_equals_direct_reads() {
        let g = Geometry::new(9, 6, 4).unwrap();
        for f in TexelFormat::ALL {
            let n = image_len(9, 6, 4, f);
            let bytes: Vec<u8> = (0..n as u32)
                .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
                .collect();
            let img = Image::new(g, Format::linear(f), &bytes).unwrap();
            let mut c: TexelCache<Image<'_>, 2, 2> = TexelCache::new(img);
            for k in 0..4u8 {
                for y in 0..8 {
                    for x in 0..11 {
                        assert_eq!(c.texel(k, x, y), img.get(k, x, y), "{f:?} {k} {x} {y}");
                    }
                }
            }
        }
    }

    /// The 16-bit level views of power-of-two RGB565 images (a module
    /// of its own: Miri runs the `pow2::` tests, `scripts/robustness`).
    mod pow2 {
        use super::*;
        use crate::texture::address::{
            AddressMode, AnyAxis, ClampToBorder, ClampToEdge, Mirror, MirrorOnce, Wrap,
        };
        use crate::texture::kernel::Linear;
        use crate::texture::sampler::{Cfg, Key, Sampler};
        use crate::texture::storage::pow2::test_indices;
        use crate::texture::{FetchStats, Mode, SamplerDesc, SamplerState};
        use crate::units::{Fast, Lod, TexCoord};

        const SIZES: [(u32, u32, u8); 5] = [(8, 4, 4), (1, 16, 5), (4, 4, 3), (2, 1, 2), (1, 1, 1)];

        fn image(g: Geometry, bytes: &[u8]) -> Image<'_, Rgb565> {
            Image::typed(g, ColorSpace::Linear, bytes).unwrap()
        }

        /// Every level index's view (past the top too) has the level's
        /// sides and reads what `Image::get` reads: texels with clamped
        /// indices (also as a source), footprints with masked indices,
        /// and footprints inside the level exactly where they are inside.
        #[test]
        fn views_read_what_the_image_reads() {
            // Under Miri the two sizes with four or more levels (see below).
            for (w, h, levels) in SIZES.into_iter().filter(|&(.., l)| !cfg!(miri) || l >= 4) {
                let g = Geometry::new(w, h, levels).unwrap();
                let bytes = pattern(image_len(w, h, levels, TexelFormat::Rgb565), 5);
                let img = image(g, &bytes);
                let d = Pow2Rgb565::new(img).unwrap();
                let mut e = d;
                for level in test_indices::levels(levels, 18) {
                    let view = *d.rgb565_levels().unwrap().level(usize::from(level));
                    let (lw, lh) = g.level_size(level);
                    assert_eq!((view.width(), view.height()), (lw, lh));
                    let get = |x: u32, y: u32| img.get(level, x, y);
                    for y in test_indices::side(lh).chain([u32::MAX]) {
                        for x in test_indices::side(lw).chain([u32::MAX]) {
                            assert_eq!(view.texel(x, y), get(x, y), "{w}x{h} {level} {x} {y}");
                            assert_eq!(e.texel(level, x, y), get(x, y));
                            let (xs, ys) = ([x, x.wrapping_add(1)], [y, y.wrapping_add(1)]);
                            let clamped = [get(xs[0], ys[0]), get(xs[1], ys[0]), get(xs[0], ys[1])];
                            assert_eq!(e.footprint(level, xs, ys)[..3], clamped);
                            let (mx, my) = (lw - 1, lh - 1);
                            let masked = [
                                get(xs[0] & mx, ys[0] & my),
                                get(xs[1] & mx, ys[0] & my),
                                get(xs[0] & mx, ys[1] & my),
                                get(xs[1] & mx, ys[1] & my),
                            ];
                            assert_eq!(view.footprint(xs, ys), masked);
                            let inside = x < lw - 1 && y < lh - 1;
                            let want = inside.then_some(masked);
                            assert_eq!(view.inside_footprint(x, y), want, "{level} {x} {y}");
                        }
                    }
                }
                assert_eq!(d.geometry(), g);
                assert_eq!(d.image().bytes(), &bytes[..]);
            }
        }

        /// Sides that are not powers of two have no views; the error
        /// names the first failing condition.
        #[test]
        fn only_power_of_two_images_have_views() {
            let bytes = pattern(image_len(6, 4, 2, TexelFormat::Rgb565), 3);
            for (w, h) in [(6, 4), (4, 6), (3, 3)] {
                let img = image(Geometry::new(w, h, 1).unwrap(), &bytes);
                assert_eq!(Pow2Rgb565::new(img).unwrap_err(), MipError::NotPowerOfTwo);
            }
            // A view needs two bytes per texel.
            assert!(LevelView::<Rgb565>::from_bytes(&bytes[..7], 2, 2).is_none());
            assert!(LevelView::<Rgb565>::from_bytes(&bytes[..8], 2, 2).is_some());
            assert!(LevelView::<Rgb565>::from_bytes(&bytes[..8], 3, 1).is_none());
        }

        /// A sampler over the views (the direct path) gives the results
        /// and counters of a sampler over the image (the generic path)
        /// for every filter mode and the keys of every address mode, at
        /// both tiers.
        #[test]
        fn sampler_reads_the_views_as_the_image() {
            fn check<K: Key<Stats = FetchStats>>(
                img: Image<'_, Rgb565>,
                state: SamplerState,
                n: u32,
            ) {
                let views = Pow2Rgb565::new(img).unwrap();
                let mut direct = Sampler::<_, K>::with_state(views, state).unwrap();
                let mut generic = Sampler::<_, K>::with_state(img, state).unwrap();
                // Coordinates on a grid of steps of 3/64 from −2 (edges,
                // seams and mirror copies), lods from −0.5 to past the top.
                for i in 0..n {
                    let u = TexCoord::from_num(-2) + TexCoord::from_bits((i64::from(i) * 3) << 26);
                    let v = TexCoord::from_num(3) - TexCoord::from_bits(i64::from(i * 7 % n) << 28);
                    let lod = Lod::from_bits((i * 37 % 1600) as i16 - 128);
                    use Mode::{BilinearNearestLevel, Nearest, NearestTexelLinearLevel, Trilinear};
                    for mode in [
                        Trilinear,
                        BilinearNearestLevel,
                        Nearest,
                        NearestTexelLinearLevel,
                    ] {
                        let want = generic.sample(u, v, lod, mode);
                        assert_eq!(
                            direct.sample(u, v, lod, mode),
                            want,
                            "{mode:?} {u} {v} {lod}"
                        );
                    }
                }
                assert_eq!(direct.stats(), generic.stats());
            }
            // Under Miri: four coordinates per sampler and the two sizes
            // with four or more levels (a wide and a one-texel-wide level 0,
            // down to 1×1: every read path of the views); natively all.
            let n = if cfg!(miri) { 4 } else { 300 };
            for (w, h, levels) in SIZES.into_iter().filter(|&(.., l)| !cfg!(miri) || l >= 4) {
                let g = Geometry::new(w, h, levels).unwrap();
                let bytes = pattern(image_len(w, h, levels, TexelFormat::Rgb565), 7);
                let img = image(g, &bytes);
                let state = |address_u, address_v| {
                    SamplerState::new(SamplerDesc {
                        address_u,
                        address_v,
                        border: 0x8040_2010,
                        lod_bias: Lod::from_bits(40),
                        ..SamplerDesc::default()
                    })
                    .unwrap()
                };
                use AddressMode as A;
                check::<Cfg<Wrap>>(img, state(A::Wrap, A::Wrap), n);
                check::<Cfg<Wrap, Wrap, Linear, Fast>>(img, state(A::Wrap, A::Wrap), n);
                let mb = state(A::Mirror, A::ClampToBorder);
                check::<Cfg<Mirror, ClampToBorder>>(img, mb, n);
                check::<Cfg<Mirror, ClampToBorder, Linear, Fast>>(img, mb, n);
                check::<Cfg<ClampToEdge, MirrorOnce>>(img, state(A::ClampToEdge, A::MirrorOnce), n);
                for (i, mu) in A::ALL.into_iter().enumerate() {
                    let mv = A::ALL[(i + 2) % 5];
                    check::<Cfg<AnyAxis>>(img, state(mu, mv), n / 4);
                }
            }
        }
    }
}
