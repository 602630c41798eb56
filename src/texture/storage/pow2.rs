//! Power-of-two pyramids in memory, validated once: the sampler's direct
//! source.
//!
//! A [`Pow2Pyramid`] is a [`Pyramid`] whose sides are powers of two
//! (then every level's are), checked when it is made. It holds one
//! [`LevelView`] per level index `0 ..= 16` (indices past the top stored
//! level repeat it, as [`Geometry::level_size`] clamps them): the level's
//! first texel, its sides and masks and its row stride. A
//! [`Sampler`](crate::texture::Sampler) over it computes texel addresses
//! itself, per footprint: two row pointers (`base + y·stride`) and the four
//! texels `row[x]`, with no bounds check per sample and no generic-path
//! code; every other source goes through
//! [`TexelSource::footprint`].
//!
//!
//! The views and their safety argument are in
//! [`level`](crate::texture::storage::level); this module makes them
//! from a [`Pyramid`].

use core::fmt;

use crate::texture::storage::format::{Rgb565, Rgba8};
use crate::texture::storage::level::{LevelView, Pow2Levels, ViewFormat};
use crate::texture::storage::mip::{Geometry, MipError, Pyramid, Texel, TexelSource};

/// A source `S` with power-of-two sides and its [`LevelView`]s of format
/// `F`, one per level index `0 ..= 16` ([module docs](self)): the
/// sampler's direct source. [`Pow2Pyramid`] (RGBA8) and
/// [`Pow2Rgb565`](crate::texture::storage::image::Pow2Rgb565) are its
/// two kinds; as a [`TexelSource`] it reads every texel through the
/// views and hands them to the sampler ([`Pow2Format`]).
#[derive(Clone, Copy)]
pub struct Pow2Source<'a, S, F: ViewFormat = Rgba8> {
    source: S,
    levels: Pow2Levels<'a, F>,
}

impl<S: fmt::Debug, F: ViewFormat> fmt::Debug for Pow2Source<'_, S, F> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Pow2Source")
            .field("source", &self.source)
            .finish_non_exhaustive()
    }
}

impl<'a, S: TexelSource, F: ViewFormat> Pow2Source<'a, S, F> {
    /// `source` with the views `view(k, w, h)` of every level index
    /// `k ≤ 16` (`w × h` its sides by `source`'s geometry); `got` is the
    /// length in texels that [`MipError::BufferTooShort`] reports when a
    /// view is `None`.
    ///
    /// # Errors
    /// [`MipError::NotPowerOfTwo`] when a side is not a power of two;
    /// [`MipError::BufferTooShort`] when a view is `None`.
    pub(crate) fn with_views(
        source: S,
        got: usize,
        view: impl Fn(u8, u32, u32) -> Option<LevelView<'a, F>>,
    ) -> Result<Self, MipError> {
        let g = source.geometry();
        if !(g.width().is_power_of_two() && g.height().is_power_of_two()) {
            return Err(MipError::NotPowerOfTwo);
        }
        let short = MipError::BufferTooShort {
            needed: g.len(),
            got,
        };
        let levels = Pow2Levels::from_fn(|k| {
            let (w, h) = g.level_size(k);
            view(k, w, h)
        })
        .ok_or(short)?;
        Ok(Self { source, levels })
    }
}

impl<S: Copy, F: ViewFormat> Pow2Source<'_, S, F> {
    /// The viewed source.
    #[must_use]
    pub fn source(&self) -> S {
        self.source
    }
}

/// A [`ViewFormat`] whose [`Pow2Levels`] a [`Pow2Source`] hands to the
/// sampler: through [`TexelSource::levels`] (RGBA8) or
/// [`TexelSource::rgb565_levels`] (RGB565).
pub trait Pow2Format: ViewFormat {
    /// `levels` as RGBA8 views, or `None` for another format.
    #[inline(always)]
    fn rgba8<'v, 'a>(levels: &'v Pow2Levels<'a, Self>) -> Option<&'v Pow2Levels<'a, Rgba8>> {
        let _ = levels;
        None
    }
    /// `levels` as RGB565 views, or `None` for another format.
    #[inline(always)]
    fn rgb565<'v, 'a>(levels: &'v Pow2Levels<'a, Self>) -> Option<&'v Pow2Levels<'a, Rgb565>> {
        let _ = levels;
        None
    }
}

impl Pow2Format for Rgba8 {
    #[inline(always)]
    fn rgba8<'v, 'a>(levels: &'v Pow2Levels<'a, Self>) -> Option<&'v Pow2Levels<'a, Rgba8>> {
        Some(levels)
    }
}

impl Pow2Format for Rgb565 {
    #[inline(always)]
    fn rgb565<'v, 'a>(levels: &'v Pow2Levels<'a, Self>) -> Option<&'v Pow2Levels<'a, Rgb565>> {
        Some(levels)
    }
}

impl<S: TexelSource, F: Pow2Format> TexelSource for Pow2Source<'_, S, F> {
    #[inline]
    fn geometry(&self) -> Geometry {
        self.source.geometry()
    }

    #[inline]
    fn texel(&mut self, level: u8, x: u32, y: u32) -> Texel {
        self.levels.texel(level, x, y)
    }

    #[inline]
    fn footprint(&mut self, level: u8, x: [u32; 2], y: [u32; 2]) -> [Texel; 4] {
        self.levels.clamped_footprint(level, x, y)
    }

    #[inline(always)]
    fn levels(&self) -> Option<&Pow2Levels<'_>> {
        F::rgba8(&self.levels)
    }

    #[inline(always)]
    fn rgb565_levels(&self) -> Option<&Pow2Levels<'_, Rgb565>> {
        F::rgb565(&self.levels)
    }
}

/// A [`Pyramid`] with power-of-two sides and its [`LevelView`]s, one per
/// level index `0 ..= 16` ([module docs](self)).
///
/// # Example
/// ```
/// use raymip::texture::storage::pow2::Pow2Pyramid;
/// use raymip::texture::storage::mip::pyramid_len;
/// use raymip::{Geometry, Lod, Mode, Pyramid, Sampler, TexCoord};
/// let texels: Vec<u32> = (0..pyramid_len(4, 2, 3) as u32).collect(); // 4×2, 2×1, 1×1
/// let pyramid = Pyramid::new(Geometry::new(4, 2, 3)?, &texels)?;
/// let direct = Pow2Pyramid::new(pyramid)?;
/// // The same texels as the pyramid, read by the sampler without a check.
/// let (u, v) = (TexCoord::from_num(0.3), TexCoord::from_num(0.6));
/// let mode = Mode::Trilinear;
/// let a = Sampler::wrap(direct).sample(u, v, Lod::from_num(0.5), mode);
/// let b = Sampler::wrap(pyramid).sample(u, v, Lod::from_num(0.5), mode);
/// assert_eq!(a, b);
/// // Sides that are not powers of two have no direct views.
/// let odd = Pyramid::new(Geometry::new(3, 2, 1)?, &texels)?;
/// assert_eq!(Pow2Pyramid::new(odd).unwrap_err(), raymip::MipError::NotPowerOfTwo);
/// # Ok::<(), raymip::MipError>(())
/// ```
pub type Pow2Pyramid<'a> = Pow2Source<'a, Pyramid<'a>>;

impl<'a> Pow2Pyramid<'a> {
    /// The views of `pyramid`.
    ///
    /// # Errors
    /// [`MipError::NotPowerOfTwo`] when a side is not a power of two;
    /// [`MipError::BufferTooShort`] when a level lies outside the texels
    /// (a [`Pyramid`] rules that out).
    pub fn new(pyramid: Pyramid<'a>) -> Result<Self, MipError> {
        let (g, texels) = (pyramid.geometry(), pyramid.texels());
        Self::with_views(pyramid, texels.len(), |k, w, h| {
            LevelView::new(texels.get(g.level_offset(k)..)?, w, h)
        })
    }

    /// The pyramid.
    #[must_use]
    pub fn pyramid(&self) -> Pyramid<'a> {
        self.source
    }
}

/// The level indices and the indices along one level side that the views'
/// read tests visit: every one natively; under Miri (which checks the views'
/// unchecked reads for undefined behaviour, at several thousand times the
/// cost of a native read) the stored levels, one level past the top and the
/// indices next to an edge (`0`, `1` and the last three, up to `n + 1`): an
/// interior index reads through the same code with an in-range index.
#[cfg(test)]
pub(super) mod test_indices {
    /// Levels `0 ..= last`; under Miri the stored ones (`< stored`), the
    /// first past them and `last`.
    pub fn levels(stored: u8, last: u8) -> impl Iterator<Item = u8> {
        (0..=last).filter(move |&l| !cfg!(miri) || l <= stored || l == last)
    }

    /// Indices `0 .. n + 2` of a side of `n` texels; under Miri those within
    /// two of an edge.
    pub fn side(n: u32) -> impl Iterator<Item = u32> {
        (0..n + 2).filter(move |&i| !cfg!(miri) || i < 2 || i + 2 >= n)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::texture::storage::mip::MAX_LEVELS;
    use std::vec::Vec;

    /// Every view reads what the pyramid reads: all levels of full and
    /// trimmed pyramids, every index and indices beyond the level
    /// (clamped by `texel`, masked by the view's `footprint`).
    #[test]
    fn views_read_the_pyramid() {
        for (w, h, levels, first, last) in [
            (8u32, 4u32, 4u8, 0u8, 3u8),
            (1, 16, 5, 0, 4),
            (16, 16, 5, 1, 3),
            (2, 1, 2, 0, 1),
            (1, 1, 1, 0, 0),
        ] {
            let full = Geometry::new(w, h, levels).unwrap();
            let buf: Vec<Texel> = (0..full.len() as u32)
                .map(|i| i.wrapping_mul(0x9E37_79B9))
                .collect();
            let p = Pyramid::new(full, &buf).unwrap().trim(first, last).unwrap();
            let mut d = Pow2Pyramid::new(p).unwrap();
            let views = d;
            let g = p.geometry();
            for level in super::test_indices::levels(g.levels(), MAX_LEVELS + 1) {
                let (lw, lh) = g.level_size(level);
                let view = *views.levels().unwrap().level(usize::from(level));
                assert_eq!((view.width(), view.height()), (lw, lh));
                assert_eq!((view.mask_x(), view.mask_y()), (lw - 1, lh - 1));
                // Bit log2 w of a column (log2 h of a row) shifted to bit 31.
                assert_eq!(
                    (lw << view.shift_x(), lh << view.shift_y()),
                    (1 << 31, 1 << 31)
                );
                // The wrap constants `(2^(31 − b) − 2³¹)/side`, exact, for
                // the kernels' widths (held) and others (computed).
                for b in [8u32, 10, 12, 16] {
                    let want = [lw, lh].map(|n| {
                        ((i64::from(1u32 << (31 - b)) - (1i64 << 31)) / i64::from(n)) as u32
                    });
                    assert_eq!(view.wrap_constants(b), want, "level {level} bits {b}");
                }
                for y in super::test_indices::side(lh) {
                    for x in super::test_indices::side(lw) {
                        assert_eq!(d.texel(level, x, y), p.get(level, x, y));
                        let (xm, ym) = (x & (lw - 1), y & (lh - 1));
                        let want = [
                            p.get(level, xm, ym),
                            p.get(level, (x + 1) & (lw - 1), ym),
                            p.get(level, xm, (y + 1) & (lh - 1)),
                            p.get(level, (x + 1) & (lw - 1), (y + 1) & (lh - 1)),
                        ];
                        assert_eq!(view.footprint([x, x + 1], [y, y + 1]), want);
                        // Inside the level: the same four texels; else none
                        // (also for the negative taps of an edge, as u32).
                        let inside = x + 1 < lw && y + 1 < lh;
                        assert_eq!(view.inside_footprint(x, y), inside.then_some(want));
                        assert_eq!(view.inside_footprint(x.wrapping_sub(lw + 2), y), None);
                        assert_eq!(view.inside_footprint(x, y.wrapping_sub(lh + 2)), None);
                        let clamped = [
                            p.get(level, x, y),
                            p.get(level, x + 1, y),
                            p.get(level, x, y + 1),
                            p.get(level, x + 1, y + 1),
                        ];
                        assert_eq!(d.footprint(level, [x, x + 1], [y, y + 1]), clamped);
                    }
                }
            }
        }
    }

    /// Non-power-of-two sides and short slices have no views.
    #[test]
    fn rejects_what_it_cannot_view() {
        let buf = [0u32; 64];
        for (w, h) in [(3u32, 2u32), (2, 6), (5, 5)] {
            let p = Pyramid::new(Geometry::new(w, h, 1).unwrap(), &buf).unwrap();
            assert_eq!(Pow2Pyramid::new(p).unwrap_err(), MipError::NotPowerOfTwo);
        }
        assert!(LevelView::new(&buf[..7], 4, 2).is_none());
        assert!(LevelView::new(&buf[..8], 4, 2).is_some());
        assert!(LevelView::new(&buf, 3, 2).is_none());
        assert!(LevelView::new(&buf, 4, 3).is_none());
        assert!(LevelView::new(&buf, 1 << 16, 1).is_none());
        assert!(LevelView::new(&buf, 1, 1 << 16).is_none());
        // The largest sides, 2¹⁵, are viewed.
        let long = std::vec![0u32; 1 << 15];
        assert!(LevelView::new(&long, 1 << 15, 1).is_some());
        assert!(LevelView::new(&long, 1, 1 << 15).is_some());
    }

    /// The views' and the pyramid's `Debug` name them and the sides.
    #[test]
    fn debug_names_the_sides() {
        let buf = [0u32; 11];
        let p = Pyramid::new(Geometry::new(4, 2, 3).unwrap(), &buf).unwrap();
        let d = Pow2Pyramid::new(p).unwrap();
        let view = std::format!("{:?}", d.levels().unwrap().level(0));
        assert!(
            view.starts_with("LevelView") && view.contains("w: 4, h: 2"),
            "{view}"
        );
        let pyramid = std::format!("{d:?}");
        assert!(
            pyramid.starts_with("Pow2Source") && pyramid.contains("source: Pyramid"),
            "{pyramid}"
        );
    }
}
