//! MIP pyramid in caller memory: geometry, in-place generation, texel fetch.
//!
//! A texture of `w × h` texels (RGBA8888, one [`Texel`] each) stores levels
//! `0 .. levels`; level `k` has `max(1, w >> k) × max(1, h >> k)` texels,
//! row-major, and the levels follow each other in one slice (level 0 first).
//! Level offsets are computed once by [`Geometry::new`], never stored per
//! texel. [`pyramid_len`] is a `const fn`, so storage can be a `static`:
//!
//! ```
//! use raymip::texture::storage::mip::{pyramid_len, Texel};
//! // 256×128 texels with all 9 levels: 32768 + 8192 + … + 2 + 1 texels.
//! const LEN: usize = pyramid_len(256, 128, 9);
//! assert_eq!(LEN, 43_691);
//! static PYRAMID: [Texel; LEN] = [0; LEN];
//! # let _ = &PYRAMID;
//! ```
//!
//! # Generation filter ([`generate`])
//!
//! Each level is made from the one below, per axis and per channel, with one
//! rounding at the end (round half up):
//!
//! * source extent even (`2n → n`): 2-tap box, weights `½, ½`;
//! * source extent 1 (`1 → 1`): copied;
//! * source extent odd (`2n + 1 → n`, non-power-of-two textures): the exact
//!   box of width `(2n+1)/n` source texels (a polyphase box). Output `i`
//!   covers source texels `2i, 2i+1, 2i+2` with weights
//!   `(n − i, n, i + 1) / (2n + 1)`: the area of each source texel inside
//!   the output texel's footprint. Unlike a fixed `¼, ½, ¼` tent it keeps
//!   every output centred on its footprint and preserves the mean exactly.
//!
//! The 2-D weights are the products of the axis weights, so a power-of-two
//! level is `(a + b + c + d + 2) >> 2`, a 1-wide one `(a + b + 1) >> 1`, and
//! every level is the box average rounded to nearest (ties up): error
//! ≤ ½ LSB per channel against the exact f64 box of the level below
//! (tested; exact for power-of-two sizes).
//!
//! Generation is set-up work (64-bit integer arithmetic, no floats); the
//! per-hit path is [`TexelSource::texel`].

use core::fmt;

use crate::texture::storage::format::Rgb565;
use crate::texture::storage::level::Pow2Levels;
pub use crate::texture::storage::level::{MAX_LEVELS, MAX_SIZE, Texel};

/// Number of levels of the full chain down to 1×1:
/// `1 + floor(log2(max(w, h)))`; 0 when a side is 0.
#[must_use]
pub const fn full_levels(width: u32, height: u32) -> u8 {
    let m = if width > height { width } else { height };
    if width == 0 || height == 0 {
        0
    } else {
        (32 - m.leading_zeros()) as u8
    }
}

/// Total texels of levels `0 .. levels` of a `width × height` texture
/// (`levels` is limited to [`full_levels`]); 0 when a side is 0. Saturates
/// at `usize::MAX` (only reachable beyond [`MAX_SIZE`]: for sides near 2³²
/// the sum exceeds `u64`, so it saturates there too).
#[must_use]
pub const fn pyramid_len(width: u32, height: u32, levels: u8) -> usize {
    let full = full_levels(width, height);
    let n = if levels < full { levels } else { full };
    let mut total: u64 = 0;
    let mut k = 0;
    while k < n {
        let (w, h) = level_dims(width, height, k);
        // One level is below 2⁶⁴; the sum of all of them need not be.
        total = total.saturating_add(w as u64 * h as u64);
        k += 1;
    }
    clamp_to(total, usize::MAX as u64)
}

/// `total` as a `usize`, clamped to `max` (`usize::MAX` as `u64` in
/// [`pyramid_len`] and [`image_len`](crate::texture::storage::image::image_len):
/// `u32::MAX` on the 32-bit targets; a parameter so that
/// the host tests check that clamp too).
pub(crate) const fn clamp_to(total: u64, max: u64) -> usize {
    if total > max {
        max as usize
    } else {
        total as usize
    }
}

/// `max(1, w >> k) × max(1, h >> k)` (`k < 32`).
#[inline(always)]
const fn level_dims(width: u32, height: u32, k: u8) -> (u32, u32) {
    let k = (k & 31) as u32;
    let w = width >> k;
    let h = height >> k;
    (if w == 0 { 1 } else { w }, if h == 0 { 1 } else { h })
}

/// Errors of pyramid set-up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum MipError {
    /// Width or height is 0.
    ZeroSize,
    /// Width or height exceeds [`MAX_SIZE`].
    TooLarge,
    /// `levels` is 0 or more than [`full_levels`] of the size.
    BadLevels,
    /// A side is not a power of two where one is needed
    /// ([`Pow2Pyramid`](crate::texture::storage::pow2::Pow2Pyramid)).
    NotPowerOfTwo,
    /// The texel slice is shorter than [`Geometry::len`].
    BufferTooShort {
        /// Texels needed.
        needed: usize,
        /// Texels given.
        got: usize,
    },
}

impl fmt::Display for MipError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::ZeroSize => f.write_str("texture width or height is 0"),
            Self::TooLarge => write!(f, "texture side exceeds {MAX_SIZE} texels"),
            Self::BadLevels => f.write_str("levels must be in 1..=full_levels(width, height)"),
            Self::NotPowerOfTwo => f.write_str("texture sides must be powers of two"),
            Self::BufferTooShort { needed, got } => {
                write!(f, "texel buffer holds {got} texels, pyramid needs {needed}")
            }
        }
    }
}

impl core::error::Error for MipError {}

/// Size and level layout of a pyramid: width, height (1 ..= [`MAX_SIZE`])
/// and stored levels (1 ..= [`full_levels`]), with precomputed level offsets.
///
/// # Example
/// ```
/// use raymip::Geometry;
/// use raymip::texture::storage::mip::{full_levels, pyramid_len};
/// // A 16×8 texture with every level down to 1×1: 16×8 + 8×4 + 4×2 + 2×1 + 1×1 texels.
/// let g = Geometry::new(16, 8, full_levels(16, 8))?;
/// assert_eq!(g.levels(), 5);
/// assert_eq!(g.len(), 128 + 32 + 8 + 2 + 1);
/// assert_eq!(g.len(), pyramid_len(16, 8, 5));
/// assert_eq!(g.level_size(2), (4, 2));
/// assert!(Geometry::new(16, 8, 6).is_err()); // more levels than the size has
/// # Ok::<(), raymip::MipError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Geometry {
    width: u32,
    height: u32,
    levels: u8,
    /// First and last stored level (`0` and `levels − 1` unless trimmed).
    first: u8,
    last: u8,
    /// Offset of level k in texels (0 below `first`); entries past `last`
    /// hold the total.
    offsets: [u32; MAX_LEVELS as usize + 1],
}

impl Geometry {
    /// Geometry of a `width × height` texture storing `levels` levels.
    ///
    /// # Errors
    /// [`MipError::ZeroSize`], [`MipError::TooLarge`] (a side above
    /// [`MAX_SIZE`]), [`MipError::BadLevels`] (`levels` 0 or above
    /// [`full_levels`]).
    pub const fn new(width: u32, height: u32, levels: u8) -> Result<Self, MipError> {
        // Every level stored; for `levels = 0` the last level wraps to 255,
        // which `trimmed` rejects (`last ≥ levels`).
        Self::trimmed(width, height, levels, 0, levels.wrapping_sub(1))
    }

    /// Geometry of a trimmed pyramid: a `width × height` texture whose
    /// samplers address `levels` levels (lod clamped to `[0, levels − 1]`,
    /// as for [`Geometry::new`]) but which stores only levels
    /// `first ..= last`, `first` first. Reads of a level outside that range
    /// are clamped into it, so a sampler gives the same texels as with the
    /// full pyramid for every lod whose levels are stored
    /// (`crate::texture::storage::analysis` computes that range for a scene). The stored
    /// texels are the sub-slice [`Geometry::stored_range`] of the full
    /// pyramid (see [`Pyramid::trim`]).
    ///
    /// # Errors
    /// As [`Geometry::new`]; [`MipError::BadLevels`] also when
    /// `first > last` or `last ≥ levels`.
    pub const fn trimmed(
        width: u32,
        height: u32,
        levels: u8,
        first: u8,
        last: u8,
    ) -> Result<Self, MipError> {
        if width == 0 || height == 0 {
            return Err(MipError::ZeroSize);
        }
        if width > MAX_SIZE || height > MAX_SIZE {
            return Err(MipError::TooLarge);
        }
        // `last < levels` also rejects `levels = 0`.
        if levels > full_levels(width, height) || first > last || last >= levels {
            return Err(MipError::BadLevels);
        }
        let mut offsets = [0u32; MAX_LEVELS as usize + 1];
        let mut total: u32 = 0;
        let mut k = 0u8;
        while k < MAX_LEVELS {
            offsets[k as usize] = total;
            if k >= first && k <= last {
                let (w, h) = level_dims(width, height, k);
                // ≤ 4/3 · 2³⁰ < 2³¹: no overflow for sides ≤ MAX_SIZE.
                total += w * h;
            }
            k += 1;
        }
        offsets[MAX_LEVELS as usize] = total;
        Ok(Self {
            width,
            height,
            levels,
            first,
            last,
            offsets,
        })
    }

    /// First stored level (0 unless trimmed).
    #[inline]
    #[must_use]
    pub const fn first_level(&self) -> u8 {
        self.first
    }

    /// Last stored level (`levels − 1` unless trimmed).
    #[inline]
    #[must_use]
    pub const fn last_level(&self) -> u8 {
        self.last
    }

    /// True when every level `0 .. levels` is stored.
    #[inline]
    #[must_use]
    pub const fn is_full(&self) -> bool {
        self.first == 0 && self.last == self.top_level()
    }

    /// The texels of this geometry's stored levels inside the full
    /// pyramid of the same size and `levels` (level 0 first): the
    /// sub-slice a trimmed pyramid stores.
    #[must_use]
    pub const fn stored_range(&self) -> core::ops::Range<usize> {
        let start = pyramid_len(self.width, self.height, self.first);
        start..start + self.len()
    }

    /// Width of level 0 in texels.
    #[inline]
    #[must_use]
    pub const fn width(&self) -> u32 {
        self.width
    }

    /// Height of level 0 in texels.
    #[inline]
    #[must_use]
    pub const fn height(&self) -> u32 {
        self.height
    }

    /// Number of levels the samplers address (≥ 1): lod is clamped to
    /// `[0, levels − 1]`. All of them are stored unless the geometry is
    /// [trimmed](Geometry::trimmed).
    #[inline]
    #[must_use]
    pub const fn levels(&self) -> u8 {
        self.levels
    }

    /// Index of the top (coarsest) addressed level, `levels − 1`.
    #[inline]
    #[must_use]
    pub const fn top_level(&self) -> u8 {
        self.levels.saturating_sub(1)
    }

    /// `level` clamped to the stored levels `[first, last]`.
    #[inline(always)]
    const fn stored_level(&self, level: u8) -> u8 {
        if level > self.last {
            self.last
        } else if level < self.first {
            self.first
        } else {
            level
        }
    }

    /// Size of `level` in texels: `(max(1, w >> k), max(1, h >> k))`, with
    /// `k` = `level` clamped to the stored levels (to `levels − 1` unless
    /// trimmed).
    #[inline]
    #[must_use]
    pub const fn level_size(&self, level: u8) -> (u32, u32) {
        level_dims(self.width, self.height, self.stored_level(level))
    }

    /// Offset of `level` in texels from the start of the stored texels
    /// (level clamped to the stored levels).
    #[inline]
    #[must_use]
    pub fn level_offset(&self, level: u8) -> usize {
        let k = usize::from(self.stored_level(level));
        self.offsets.get(k).copied().unwrap_or(0) as usize
    }

    /// Total stored texels (= [`pyramid_len`]`(w, h, levels)` unless
    /// trimmed; at least 1).
    #[inline]
    #[must_use]
    #[allow(clippy::len_without_is_empty)] // a geometry has at least one texel
    pub const fn len(&self) -> usize {
        self.offsets[MAX_LEVELS as usize] as usize
    }

    /// Index of texel `(x, y)` of `level` in the pyramid slice. Level,
    /// `x` and `y` are clamped to the stored range (clamp to edge).
    #[inline]
    #[must_use]
    pub fn texel_index(&self, level: u8, x: u32, y: u32) -> usize {
        let (w, h) = self.level_size(level);
        let x = x.min(w - 1) as usize;
        let y = y.min(h - 1) as usize;
        self.level_offset(level) + y * w as usize + x
    }
}

/// One axis of the generation filter: up to 3 source taps with integer
/// weights summing to `den`.
#[cfg(feature = "mipgen")]
#[derive(Clone, Copy)]
struct Taps {
    first: u32,
    weights: [u64; 3],
    count: usize,
    den: u64,
}

/// Taps of output texel `i` for a source extent `src` (see module docs).
#[cfg(feature = "mipgen")]
fn axis_taps(src: u32, i: u32) -> Taps {
    if src == 1 {
        Taps {
            first: 0,
            weights: [1, 0, 0],
            count: 1,
            den: 1,
        }
    } else if src % 2 == 0 {
        Taps {
            first: 2 * i,
            weights: [1, 1, 0],
            count: 2,
            den: 2,
        }
    } else {
        let n = u64::from(src / 2);
        let i64_ = u64::from(i);
        Taps {
            first: 2 * i,
            weights: [n - i64_, n, i64_ + 1],
            count: 3,
            den: 2 * n + 1,
        }
    }
}

/// Fills levels `1 .. levels` from level 0 (already in `buf[..w*h]`), in
/// place, with the filter of the module docs. For a
/// [trimmed](Geometry::trimmed) geometry: the stored levels after the
/// first from the first (already at the start of `buf`); each level depends
/// only on the one below, so they equal the full pyramid's.
///
/// # Errors
/// [`MipError::BufferTooShort`] when `buf` is shorter than
/// [`Geometry::len`] (nothing is written).
///
/// Feature `mipgen`.
#[cfg(feature = "mipgen")]
pub fn generate(geometry: &Geometry, buf: &mut [Texel]) -> Result<(), MipError> {
    generate_mapped(
        geometry,
        buf,
        |t| [0, 1, 2, 3].map(|c| (t >> (8 * c)) & 0xFF),
        |sum, den| {
            // Round half up: floor(S/D + ½) = floor((2S + D) / 2D); D ≥ 1.
            let mut out = 0u32;
            for (c, s) in sum.iter().enumerate() {
                let v = (2 * s + den).checked_div(2 * den).unwrap_or(0);
                out |= (v.min(255) as u32) << (8 * c);
            }
            out
        },
    )
}

/// [`generate`] with the channel mapping as parameters: each source texel
/// is read as four channel values by `decode` (each `< 2³²`), the box
/// filter sums `weight · value` per channel (integer weights), and
/// `encode(sums, den)` turns the sums and the common denominator `den ≥ 1`
/// into the output texel. [`generate`] uses the 8-bit channels as they
/// are; sRGB pyramids (`crate::texture::storage::srgb`) filter in linear space.
#[cfg(feature = "mipgen")]
pub(crate) fn generate_mapped(
    geometry: &Geometry,
    buf: &mut [Texel],
    decode: impl Fn(Texel) -> [u32; 4],
    encode: impl Fn([u64; 4], u64) -> Texel,
) -> Result<(), MipError> {
    let needed = geometry.len();
    if buf.len() < needed {
        return Err(MipError::BufferTooShort {
            needed,
            got: buf.len(),
        });
    }
    for k in geometry.first_level().saturating_add(1)..=geometry.last_level() {
        let (sw, sh) = geometry.level_size(k - 1);
        let (dw, dh) = geometry.level_size(k);
        // Every access below is checked (`get`), so no input can panic; the
        // length check above makes the `None` arms unreachable in practice.
        let (lower, upper) = buf
            .split_at_mut_checked(geometry.level_offset(k))
            .ok_or(MipError::BufferTooShort { needed, got: 0 })?;
        let src = lower
            .get(geometry.level_offset(k - 1)..)
            .ok_or(MipError::BufferTooShort { needed, got: 0 })?;
        let dst = upper
            .get_mut(..(dw as usize).saturating_mul(dh as usize))
            .ok_or(MipError::BufferTooShort { needed, got: 0 })?;
        for (y, dst_row) in (0..dh).zip(dst.chunks_exact_mut(dw.max(1) as usize)) {
            let ty = axis_taps(sh, y);
            for (x, d) in (0..dw).zip(dst_row.iter_mut()) {
                let tx = axis_taps(sw, x);
                let den = tx.den.saturating_mul(ty.den);
                let mut sum = [0u64; 4];
                for (j, &wy) in ty.weights.iter().take(ty.count).enumerate() {
                    let row = (ty.first as usize + j).saturating_mul(sw as usize);
                    let taps = src
                        .get(row.saturating_add(tx.first as usize)..)
                        .unwrap_or(&[]);
                    for (&t, &wx) in taps.iter().zip(tx.weights.iter().take(tx.count)) {
                        let w = wx * wy;
                        for (s, v) in sum.iter_mut().zip(decode(t)) {
                            *s = s.saturating_add(w * u64::from(v));
                        }
                    }
                }
                *d = encode(sum, den);
            }
        }
    }
    Ok(())
}

/// Read access to stored texels: the fetch stage's view of a pyramid
/// (directly in memory, or through a [`TexelCache`](crate::texture::storage::cache::TexelCache)).
pub trait TexelSource {
    /// The pyramid's geometry.
    fn geometry(&self) -> Geometry;
    /// Texel `(x, y)` of `level`. Out-of-range level or coordinates are
    /// clamped to the stored range (never a panic).
    fn texel(&mut self, level: u8, x: u32, y: u32) -> Texel;
    /// The bilinear footprint of `level`: texels `(x[0], y[0])`,
    /// `(x[1], y[0])`, `(x[0], y[1])`, `(x[1], y[1])`, clamped like
    /// [`texel`](Self::texel). The default reads them one by one; a source
    /// may override it to compute the level's address once.
    #[inline]
    fn footprint(&mut self, level: u8, x: [u32; 2], y: [u32; 2]) -> [Texel; 4] {
        [
            self.texel(level, x[0], y[0]),
            self.texel(level, x[1], y[0]),
            self.texel(level, x[0], y[1]),
            self.texel(level, x[1], y[1]),
        ]
    }
    /// [`footprint`](Self::footprint) for indices inside `level` (`level
    /// ≤ 16`, `x[i] <` its width and `y[i] <` its height as
    /// [`Geometry::level_size`] gives them, which a sampler's taps are): a
    /// source may skip the clamps. Other indices give texels of the
    /// source unspecified by this contract (never a panic). The default is
    /// [`footprint`](Self::footprint).
    #[inline(always)]
    fn footprint_in_level(&mut self, level: u8, x: [u32; 2], y: [u32; 2]) -> [Texel; 4] {
        self.footprint(level, x, y)
    }
    /// The level views of a power-of-two pyramid in memory
    /// ([`Pow2Pyramid`](crate::texture::storage::pow2::Pow2Pyramid)): lets a
    /// [`Sampler`](crate::texture::Sampler) compute texel addresses itself
    /// (two row pointers per 2×2 footprint, no check per sample). Every
    /// other source returns `None`, the default, and is read through
    /// [`footprint`](Self::footprint).
    #[inline(always)]
    fn levels(&self) -> Option<&Pow2Levels<'_>> {
        None
    }
    /// The 16-bit level views of a power-of-two RGB565 image in memory
    /// ([`Pow2Rgb565`](crate::texture::storage::image::Pow2Rgb565)), read
    /// by a [`Sampler`](crate::texture::Sampler) as it reads
    /// [`levels`](Self::levels), each texel expanded once. Every other
    /// source returns `None`, the default.
    #[inline(always)]
    fn rgb565_levels(&self) -> Option<&Pow2Levels<'_, Rgb565>> {
        None
    }
}

/// A pyramid: geometry plus a borrowed texel slice laid out as in the
/// module docs.
///
/// # Example
/// ```
/// use raymip::texture::storage::mip::generate;
/// use raymip::{Geometry, Pyramid};
/// let g = Geometry::new(2, 2, 2)?;
/// // Level 0 (2×2) given, level 1 (1×1) generated in place: the 2×2 box mean.
/// let mut texels = [0xFF00_0000, 0xFF00_0000, 0xFFFF_FFFF, 0xFFFF_FFFF, 0];
/// generate(&g, &mut texels)?;
/// let pyramid = Pyramid::new(g, &texels)?;
/// assert_eq!(pyramid.get(0, 0, 1), 0xFFFF_FFFF);
/// let mean = pyramid.get(1, 0, 0);
/// assert!((mean & 0xFF).abs_diff(0x80) <= 1 && mean >> 24 == 0xFF);
/// assert!(Pyramid::new(g, &texels[..4]).is_err()); // buffer too short
/// # Ok::<(), raymip::MipError>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Pyramid<'a> {
    geometry: Geometry,
    texels: &'a [Texel],
}

impl<'a> Pyramid<'a> {
    /// Wraps `texels` (at least [`Geometry::len`] long; extra texels are
    /// ignored).
    ///
    /// # Errors
    /// [`MipError::BufferTooShort`].
    pub fn new(geometry: Geometry, texels: &'a [Texel]) -> Result<Self, MipError> {
        if texels.len() < geometry.len() {
            return Err(MipError::BufferTooShort {
                needed: geometry.len(),
                got: texels.len(),
            });
        }
        Ok(Self { geometry, texels })
    }

    /// The texel slice.
    #[must_use]
    pub fn texels(&self) -> &'a [Texel] {
        self.texels
    }

    /// The same pyramid storing only levels `first ..= last` (a
    /// [trimmed](Geometry::trimmed) geometry over a sub-slice of these
    /// texels; nothing is copied). Every lod whose levels lie in that range
    /// samples exactly the same texels as before.
    ///
    /// # Errors
    /// [`MipError::BadLevels`] when `first > last` or the range is not
    /// stored here.
    pub fn trim(&self, first: u8, last: u8) -> Result<Self, MipError> {
        let g = &self.geometry;
        if first < g.first_level() || last > g.last_level() {
            return Err(MipError::BadLevels);
        }
        let geometry = Geometry::trimmed(g.width(), g.height(), g.levels(), first, last)?;
        let start = geometry.stored_range().start - g.stored_range().start;
        let texels =
            self.texels
                .get(start..start + geometry.len())
                .ok_or(MipError::BufferTooShort {
                    needed: start + geometry.len(),
                    got: self.texels.len(),
                })?;
        Ok(Self { geometry, texels })
    }

    /// Texel `(x, y)` of `level`, clamped as in [`TexelSource::texel`].
    #[inline]
    #[must_use]
    pub fn get(&self, level: u8, x: u32, y: u32) -> Texel {
        self.texels
            .get(self.geometry.texel_index(level, x, y))
            .copied()
            .unwrap_or(0)
    }
}

impl TexelSource for Pyramid<'_> {
    #[inline]
    fn geometry(&self) -> Geometry {
        self.geometry
    }

    #[inline]
    fn texel(&mut self, level: u8, x: u32, y: u32) -> Texel {
        self.get(level, x, y)
    }

    #[inline]
    fn footprint(&mut self, level: u8, x: [u32; 2], y: [u32; 2]) -> [Texel; 4] {
        let (w, h) = self.geometry.level_size(level);
        let base = self.geometry.level_offset(level);
        let stride = w as usize;
        let row0 = base + y[0].min(h - 1) as usize * stride;
        let row1 = base + y[1].min(h - 1) as usize * stride;
        let (x0, x1) = (x[0].min(w - 1) as usize, x[1].min(w - 1) as usize);
        let get = |i: usize| self.texels.get(i).copied().unwrap_or(0);
        [
            get(row0 + x0),
            get(row0 + x1),
            get(row1 + x0),
            get(row1 + x1),
        ]
    }
}

impl<T: TexelSource + ?Sized> TexelSource for &mut T {
    #[inline]
    fn geometry(&self) -> Geometry {
        (**self).geometry()
    }

    #[inline]
    fn texel(&mut self, level: u8, x: u32, y: u32) -> Texel {
        (**self).texel(level, x, y)
    }

    #[inline]
    fn footprint(&mut self, level: u8, x: [u32; 2], y: [u32; 2]) -> [Texel; 4] {
        (**self).footprint(level, x, y)
    }

    #[inline]
    fn footprint_in_level(&mut self, level: u8, x: [u32; 2], y: [u32; 2]) -> [Texel; 4] {
        (**self).footprint_in_level(level, x, y)
    }

    #[inline(always)]
    fn levels(&self) -> Option<&Pow2Levels<'_>> {
        (**self).levels()
    }

    #[inline(always)]
    fn rgb565_levels(&self) -> Option<&Pow2Levels<'_, Rgb565>> {
        (**self).rgb565_levels()
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    #[cfg(feature = "mipgen")]
    use std::vec;

    /// A pyramid's footprint reads the texels of the module docs' layout,
    /// each index past its level's side clamped to the last column or
    /// row; and a `&mut` of a source reads as the source: the same
    /// geometry, texels, footprints and level views (the views keep a
    /// sampler over a borrowed power-of-two source on its direct path).
    #[test]
    fn footprints_clamp_and_a_borrowed_source_reads_as_its_referent() {
        use crate::texture::storage::format::{ColorSpace, Rgb565, TexelFormat};
        use crate::texture::storage::image::{Image, Pow2Rgb565, image_len};
        use crate::texture::storage::pow2::Pow2Pyramid;
        use std::vec::Vec;
        let g = Geometry::new(4, 2, 3).unwrap();
        // Texel i of the buffer is i + 1 in every byte: distinct, non-zero.
        let texels: Vec<Texel> = (1..=pyramid_len(4, 2, 3) as u32)
            .map(|i| i * 0x0101_0101)
            .collect();
        let mut p = Pyramid::new(g, &texels).unwrap();
        // Level 0 is 4×2 at 0, level 1 2×1 at 8, level 2 1×1 at 10.
        let layout = [(4u32, 2u32, 0usize), (2, 1, 8), (1, 1, 10)];
        for (level, &(w, h, offset)) in (0u8..).zip(&layout) {
            let at = |x: u32, y: u32| texels[offset + (y.min(h - 1) * w + x.min(w - 1)) as usize];
            for (x, y) in [
                ([0, 1], [0, 1]),
                ([w - 1, w], [h - 1, h + 3]),
                ([w + 7, 0], [h, 0]),
            ] {
                let want = [
                    at(x[0], y[0]),
                    at(x[1], y[0]),
                    at(x[0], y[1]),
                    at(x[1], y[1]),
                ];
                assert_eq!(
                    p.footprint(level, x, y),
                    want,
                    "level {level} x {x:?} y {y:?}"
                );
                let mut r = &mut p;
                assert_eq!(TexelSource::footprint(&mut r, level, x, y), want);
                assert_eq!(TexelSource::footprint_in_level(&mut r, level, x, y), want);
                assert_eq!(TexelSource::texel(&mut r, level, x[0], y[0]), want[0]);
                assert_eq!(TexelSource::geometry(&r), g);
            }
        }
        let mut d = Pow2Pyramid::new(p).unwrap();
        let views = d.levels().map(|l| core::ptr::from_ref(l).addr());
        assert!(views.is_some());
        let r = &mut d;
        assert_eq!(
            TexelSource::levels(&r).map(|l| core::ptr::from_ref(l).addr()),
            views
        );
        assert!(TexelSource::rgb565_levels(&r).is_none());
        let bytes: Vec<u8> = (0..image_len(4, 2, 3, TexelFormat::Rgb565) as u32)
            .map(|i| i as u8)
            .collect();
        let image = Image::<Rgb565>::typed(g, ColorSpace::Linear, &bytes).unwrap();
        let mut d = Pow2Rgb565::new(image).unwrap();
        let views = d.rgb565_levels().map(|l| core::ptr::from_ref(l).addr());
        assert!(views.is_some());
        let r = &mut d;
        assert_eq!(
            TexelSource::rgb565_levels(&r).map(|l| core::ptr::from_ref(l).addr()),
            views
        );
        assert!(TexelSource::levels(&r).is_none());
    }

    #[test]
    fn levels_and_lengths() {
        assert_eq!(full_levels(1, 1), 1);
        assert_eq!(full_levels(256, 256), 9);
        assert_eq!(full_levels(1044, 1044), 11);
        assert_eq!(full_levels(128, 512), 10);
        assert_eq!(full_levels(0, 5), 0);
        assert_eq!(pyramid_len(4, 4, 3), 16 + 4 + 1);
        assert_eq!(pyramid_len(4, 1, 3), 4 + 2 + 1);
        assert_eq!(pyramid_len(4, 4, 99), 21);
        assert_eq!(pyramid_len(0, 4, 3), 0);
        let g = Geometry::new(128, 512, 10).unwrap();
        assert_eq!(g.len(), pyramid_len(128, 512, 10));
        assert_eq!(g.level_size(7), (1, 4));
        assert_eq!(g.level_size(9), (1, 1));
        assert_eq!(g.level_size(200), (1, 1));
        assert_eq!(g.level_offset(1), 128 * 512);
        assert_eq!(Geometry::new(0, 1, 1), Err(MipError::ZeroSize));
        assert_eq!(Geometry::new(1 << 16, 1, 1), Err(MipError::TooLarge));
        assert_eq!(Geometry::new(4, 4, 4), Err(MipError::BadLevels));
        assert_eq!(Geometry::new(4, 4, 0), Err(MipError::BadLevels));
        let g = Geometry::new(MAX_SIZE, MAX_SIZE, 16).unwrap();
        assert_eq!(g.len(), pyramid_len(MAX_SIZE, MAX_SIZE, 16));
    }

    /// The error messages name the limit and both counts, each in its place.
    #[test]
    fn error_messages() {
        use std::string::ToString;
        let short = MipError::BufferTooShort {
            needed: 21,
            got: 16,
        };
        assert_eq!(
            short.to_string(),
            "texel buffer holds 16 texels, pyramid needs 21"
        );
        assert_eq!(
            MipError::TooLarge.to_string(),
            std::format!("texture side exceeds {MAX_SIZE} texels")
        );
        assert_eq!(
            MipError::ZeroSize.to_string(),
            "texture width or height is 0"
        );
    }

    /// `pyramid_len` in a const context, as a `static` pyramid's length
    /// (module docs): rustc evaluates it while building the tests, so a
    /// level loop that did not end fails that build (rustc's
    /// `long_running_const_eval` limit) instead of hanging a test run.
    /// 256×128, 9 levels: 32768 + 8192 + 2048 + 512 + 128 + 32 + 8 + 2 + 1.
    const _: () = assert!(pyramid_len(256, 128, 9) == 43_691);

    /// The clamp of [`pyramid_len`] on the 32-bit targets (`usize::MAX =
    /// 2³² − 1`), checked on the host: a 65536² pyramid has 4/3 · 2³²
    /// texels, more than a 32-bit `usize` holds.
    #[test]
    fn pyramid_len_clamps_to_a_32_bit_usize() {
        let max32 = u64::from(u32::MAX);
        let total = (0..17).map(|k| (65536u64 >> k).pow(2)).sum::<u64>();
        assert_eq!(total, 0x1_5555_5555);
        assert_eq!(clamp_to(total, max32), u32::MAX as usize);
        assert_eq!(clamp_to(max32 + 1, max32), u32::MAX as usize);
        assert_eq!(clamp_to(max32, max32), u32::MAX as usize);
        assert_eq!(clamp_to(max32 - 1, max32), u32::MAX as usize - 1);
        assert_eq!(clamp_to(0, max32), 0);
        // On the host `pyramid_len` has the 64-bit bound: the same sides exactly.
        assert_eq!(pyramid_len(65536, 65536, 17) as u64, total);
    }

    /// Sides near 2³² saturate the 64-bit sum as documented (an overflow
    /// would wrap in release and panic in debug).
    #[test]
    fn pyramid_len_saturates_for_huge_sides() {
        // Level 0 alone is (2³² − 1)² = 2⁶⁴ − 2³³ + 1 texels; level 1 adds ≈ 2⁶²:
        // the exact total exceeds u64 (and usize).
        assert_eq!(pyramid_len(u32::MAX, u32::MAX, 32), usize::MAX);
        assert_eq!(pyramid_len(u32::MAX, u32::MAX, 2), usize::MAX);
        // One level still fits u64 exactly (and saturates only on 32-bit targets).
        let one = u64::from(u32::MAX) * u64::from(u32::MAX);
        assert_eq!(
            pyramid_len(u32::MAX, u32::MAX, 1),
            usize::try_from(one).unwrap_or(usize::MAX)
        );
        // Monotonic in the level count over the whole u32 side range.
        for side in [1u32 << 31, (1 << 31) + 1, u32::MAX - 1, u32::MAX] {
            let mut last = 0;
            for levels in 0..=33 {
                let n = pyramid_len(side, side, levels);
                assert!(n >= last, "{side}: {levels} levels {n} < {last}");
                last = n;
            }
        }
    }

    #[test]
    #[cfg(feature = "mipgen")]
    fn pot_box_and_one_wide() {
        let g = Geometry::new(2, 2, 2).unwrap();
        let mut buf = vec![0u32; g.len()];
        buf[..4].copy_from_slice(&[0x0000_0001, 0x0000_0002, 0x0000_0000, 0x0000_00FF]);
        generate(&g, &mut buf).unwrap();
        // (1 + 2 + 0 + 255 + 2) >> 2 = 65
        assert_eq!(buf[4], 65);
        let g = Geometry::new(2, 1, 2).unwrap();
        let mut buf = vec![0x0000_0003u32, 0x0000_0004, 0];
        generate(&g, &mut buf).unwrap();
        assert_eq!(buf[2], 4); // (3 + 4 + 1) >> 1
        assert_eq!(
            generate(&g, &mut [0u32; 2]),
            Err(MipError::BufferTooShort { needed: 3, got: 2 })
        );
    }

    #[test]
    #[cfg(feature = "mipgen")]
    fn odd_extent_polyphase_box() {
        // 3 → 1: weights (1, 1, 1)/3.
        let g = Geometry::new(3, 1, 2).unwrap();
        let mut buf = vec![0u32, 1, 1, 0];
        generate(&g, &mut buf).unwrap();
        assert_eq!(buf[3], 1); // 2/3 → 1
        // 5 → 2: output 0 = (2·a + 2·b + 1·c)/5, output 1 = (1·c + 2·d + 2·e)/5.
        let g = Geometry::new(5, 1, 2).unwrap();
        let mut buf = vec![10u32, 20, 30, 40, 50, 0, 0];
        generate(&g, &mut buf).unwrap();
        assert_eq!(buf[5], 18); // 90/5
        assert_eq!(buf[6], 42); // 210/5
        // 7 → 3 (den 2·3 + 1 = 7): (3a + 3b + c)/7 = 120/7, (2c + 3d + 2e)/7 =
        // 280/7, (e + 3f + 3g)/7 = 440/7, rounded to nearest.
        let g = Geometry::new(7, 1, 2).unwrap();
        let mut buf = vec![10u32, 20, 30, 40, 50, 60, 70, 0, 0, 0];
        generate(&g, &mut buf).unwrap();
        assert_eq!(buf[7..], [17, 40, 63]);
    }

    /// Every channel is filtered in its own byte, and a 2-D odd level
    /// weighs each source texel by the product of its axis weights. 5×5:
    /// the only non-zero texel, (2, 0), has x weight 1 (of 2, 2, 1 for
    /// output 0 and 1, 2, 2 for output 1) and y weight 2 (of 2, 2, 1) in
    /// both outputs of row 0, so each gets 2·v/25 per channel; row 1
    /// reads source rows 2 to 4 only.
    #[test]
    #[cfg(feature = "mipgen")]
    fn odd_2d_weights_in_every_channel() {
        let g = Geometry::new(5, 5, 3).unwrap();
        let mut buf = vec![0u32; g.len()];
        // Channels 50, 100, 150, 200, red in the low byte.
        buf[2] = 0xC896_6432;
        generate(&g, &mut buf).unwrap();
        // Level 1 (2×2): 2·v/25 = 4, 8, 12, 16.
        assert_eq!(buf[25..29], [0x100C_0804, 0x100C_0804, 0, 0]);
        // Level 2 (1×1): the 2×2 box, (4 + 4 + 0 + 0)/4 = 2, 4, 6, 8.
        assert_eq!(buf[29..], [0x0806_0402]);
    }

    #[test]
    fn pyramid_fetch_clamps() {
        let g = Geometry::new(2, 2, 2).unwrap();
        let buf = [1u32, 2, 3, 4, 5];
        let mut p = Pyramid::new(g, &buf).unwrap();
        assert_eq!(p.texel(0, 1, 1), 4);
        assert_eq!(p.texel(0, 9, 0), 2);
        assert_eq!(p.texel(1, 0, 0), 5);
        assert_eq!(p.texel(7, 3, 3), 5);
        assert!(Pyramid::new(g, &buf[..4]).is_err());
    }

    /// A trimmed pyramid reads the full pyramid's texels at every stored
    /// level and clamps other levels into its range; generated in place
    /// from its first level it equals the full pyramid's sub-slice.
    #[test]
    fn trimmed_reads_the_full_pyramids_texels() {
        for (w, h) in [(8u32, 8u32), (5, 3), (1, 16), (13, 7)] {
            let levels = full_levels(w, h);
            let full = Geometry::new(w, h, levels).unwrap();
            assert!(full.is_full() && full.stored_range() == (0..full.len()));
            let buf: std::vec::Vec<Texel> = (0..full.len() as u32).map(|i| i * 7919).collect();
            let p = Pyramid::new(full, &buf).unwrap();
            for first in 0..levels {
                for last in first..levels {
                    let t = p.trim(first, last).unwrap();
                    let g = t.geometry();
                    assert_eq!(
                        (g.first_level(), g.last_level(), g.levels()),
                        (first, last, levels)
                    );
                    assert_eq!(g.len(), g.stored_range().len());
                    assert_eq!(g.is_full(), first == 0 && last == levels - 1);
                    for level in 0..levels + 2 {
                        let k = level.clamp(first, last);
                        assert_eq!(g.level_size(level), full.level_size(k));
                        let (lw, lh) = full.level_size(k);
                        for (x, y) in [(0, 0), (lw - 1, lh - 1), (lw / 2, lh / 3), (99, 99)] {
                            assert_eq!(
                                t.get(level, x, y),
                                p.get(k, x, y),
                                "{w}x{h} [{first},{last}] level {level}"
                            );
                        }
                    }
                    assert_eq!(t.trim(first, last).unwrap().texels(), t.texels());
                    if first > 0 {
                        assert_eq!(t.trim(first - 1, last).unwrap_err(), MipError::BadLevels);
                    }
                }
            }
            assert_eq!(
                Geometry::trimmed(w, h, levels, 1, 0),
                Err(MipError::BadLevels)
            );
            assert_eq!(
                Geometry::trimmed(w, h, levels, 0, levels),
                Err(MipError::BadLevels)
            );
        }
    }

    #[test]
    #[cfg(feature = "mipgen")]
    fn trimmed_generation_equals_the_full_pyramid() {
        let full = Geometry::new(13, 7, 4).unwrap();
        let mut buf: std::vec::Vec<Texel> = (0..full.len() as u32)
            .map(|i| i.wrapping_mul(2_654_435_761))
            .collect();
        generate(&full, &mut buf).unwrap();
        for first in 0..4 {
            let g = Geometry::trimmed(13, 7, 4, first, 3).unwrap();
            let range = g.stored_range();
            let (w, h) = g.level_size(first);
            let mut t = std::vec![0u32; g.len()];
            let n = (w * h) as usize;
            t[..n].copy_from_slice(&buf[range.start..range.start + n]);
            generate(&g, &mut t).unwrap();
            assert_eq!(t[..], buf[range]);
        }
    }

    /// A mutable borrow of a source reads as the source: geometry,
    /// texels, footprints (clamped and in-level) and, for a power-of-two
    /// pyramid, its level views (the sampler's direct path), so a sampler
    /// over `&mut source` takes the same path as over the source.
    #[test]
    fn mutable_borrow_reads_as_its_source() {
        use crate::texture::storage::pow2::Pow2Pyramid;
        /// What `s` reads at `level`, `x`, `y` through the trait (for
        /// `S = &mut T`, the borrow's own impl): geometry, texel
        /// `(x[1], y[0])`, footprint, in-level footprint, and texel
        /// `(x[0], y[1])` of the level view when there are views.
        fn reads<S: TexelSource>(
            mut s: S,
            level: u8,
            x: [u32; 2],
            y: [u32; 2],
        ) -> (Geometry, Texel, [Texel; 4], [Texel; 4], Option<Texel>) {
            let view = s
                .levels()
                .map(|l| l.level(usize::from(level)).texel(x[0], y[1]));
            (
                s.geometry(),
                s.texel(level, x[1], y[0]),
                s.footprint(level, x, y),
                s.footprint_in_level(level, x, y),
                view,
            )
        }
        let g = Geometry::new(4, 2, 3).unwrap();
        let buf: std::vec::Vec<Texel> =
            (0..g.len() as u32).map(|i| 0x0101_0101 * (i + 1)).collect();
        let mut p = Pyramid::new(g, &buf).unwrap();
        let mut d = Pow2Pyramid::new(p).unwrap();
        for level in 0..4u8 {
            for (x, y) in [([0, 1], [0, 1]), ([3, 0], [1, 0]), ([1, 2], [1, 1])] {
                let want = reads(p, level, x, y);
                assert_eq!(want.0, g);
                assert_eq!(want.1, p.get(level, x[1], y[0]));
                assert_eq!(want.2[2], p.get(level, x[0], y[1]));
                assert_eq!(want.3, want.2);
                assert_eq!(want.4, None);
                assert_eq!(reads(&mut p, level, x, y), want);
                let views = (want.0, want.1, want.2, want.3, Some(want.2[2]));
                assert_eq!(reads(d, level, x, y), views);
                assert_eq!(reads(&mut d, level, x, y), views);
            }
        }
    }

    /// A source that implements only `geometry` and `texel` gets the
    /// trait's defaults: its footprint is its four texel reads in the
    /// documented order (one `texel` call each), its in-level footprint is
    /// that footprint, and it has no level views (a sampler then reads it
    /// through `footprint`). Every source of the crate overrides
    /// `footprint`, so only such a source runs the default.
    #[test]
    fn default_footprint_reads_four_texels() {
        /// A pyramid read texel by texel, counting the reads.
        struct Reads<'a>(Pyramid<'a>, u32);
        impl TexelSource for Reads<'_> {
            fn geometry(&self) -> Geometry {
                self.0.geometry
            }
            fn texel(&mut self, level: u8, x: u32, y: u32) -> Texel {
                self.1 += 1;
                self.0.get(level, x, y)
            }
        }
        let g = Geometry::new(5, 3, 3).unwrap();
        let buf: std::vec::Vec<Texel> =
            (0..g.len() as u32).map(|i| 0x0101_0101 * (i + 1)).collect();
        let mut p = Pyramid::new(g, &buf).unwrap();
        let mut s = Reads(p, 0);
        assert!(s.levels().is_none());
        for level in 0..4u8 {
            for (x, y) in [([0, 1], [0, 1]), ([4, 0], [2, 0]), ([9, 99], [7, u32::MAX])] {
                // The pyramid's own footprint: its four texel reads
                // (`footprint_equals_texel_reads`).
                let want = p.footprint(level, x, y);
                assert_eq!(s.footprint(level, x, y), want);
                assert_eq!(s.footprint_in_level(level, x, y), want);
            }
        }
        // 4 levels × 3 footprints × 2 calls × 4 texels.
        assert_eq!(s.1, 96);
    }

    #[test]
    fn footprint_equals_texel_reads() {
        let g = Geometry::new(5, 3, 3).unwrap();
        let buf: std::vec::Vec<Texel> = (0..g.len() as u32).collect();
        let mut p = Pyramid::new(g, &buf).unwrap();
        for level in 0..5u8 {
            for (x, y) in [([0, 1], [0, 1]), ([4, 0], [2, 0]), ([9, 99], [7, u32::MAX])] {
                let want = [
                    p.texel(level, x[0], y[0]),
                    p.texel(level, x[1], y[0]),
                    p.texel(level, x[0], y[1]),
                    p.texel(level, x[1], y[1]),
                ];
                assert_eq!(p.footprint(level, x, y), want);
            }
        }
    }
}
