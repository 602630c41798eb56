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
//! # Safety
//!
//! This is the crate's only texture module with `unsafe` code: the texel
//! reads of [`LevelView`]. The argument, in full:
//!
//! * A view is made only by [`LevelView::new`] from a slice `&'a [Texel]`
//!   of at least `w·h` texels, `w = 2^kx`, `h = 2^ky`, `kx, ky ≤ 15`
//!   ([`MAX_SIZE`]); it keeps the slice's start pointer (whose provenance
//!   covers the whole slice), `w`, `h`, `mx = w − 1`, `my = h − 1`, the
//!   row stride `4w` in bytes (and two shift counts no read uses). Its
//!   fields are private and never written after construction, and it
//!   holds a `PhantomData<&'a [Texel]>`: it cannot outlive the shared
//!   borrow, during which the texels can be neither freed nor written,
//!   and moving a view does not move them.
//! * Every read first reduces its indices to `x ≤ mx`, `y ≤ my` (a mask
//!   `& mx` / `& my`, or a `min` with them; or, for a wrapped
//!   footprint, takes the first index as the high word of the 32×32-bit
//!   product of a 32-bit fraction with the side, which is below the
//!   side, and the second as the first plus one, masked), so the texel index
//!   `y·w + x ≤ (h − 1)·w + w − 1 = w·h − 1` lies inside the slice. The
//!   row's byte offset `y·4w < 2³²` is computed in `usize` (no overflow
//!   on 32-bit or wider targets), and the read is one `ptr::byte_add`
//!   (the row), one `ptr::add` (the column) and `ptr::read` of an
//!   initialised, aligned `Texel`; the slice's length is not compared
//!   again.
//!
//! Tests: views of every level of trimmed and full pyramids read exactly
//! what [`Pyramid::get`] reads, over every index and beyond (masks and
//! clamps), also under Miri (`scripts/robustness`, filter `pow2::`).

#![allow(unsafe_code)]

use core::fmt;
use core::marker::PhantomData;
use core::ptr::NonNull;

use crate::texture::address::pow2_wrap_taps;
use crate::texture::storage::mip::{
    Geometry, MAX_LEVELS, MAX_SIZE, MipError, Pyramid, Texel, TexelSource,
};
use crate::units::TexCoord;

/// One power-of-two level in memory, validated ([module docs](self)):
/// every read is in bounds by construction.
#[derive(Clone, Copy)]
pub struct LevelView<'a> {
    /// The level's first texel (of at least `w·h` in a slice borrowed
    /// for `'a`).
    base: NonNull<Texel>,
    /// Sides `w = 2^kx`, `h = 2^ky ≤ 2¹⁵`; `w` is also the row stride.
    w: u32,
    h: u32,
    /// `w − 1`, `h − 1`.
    mx: u32,
    my: u32,
    /// `31 − kx`, `31 − ky`: shifts that move bit `kx` (`ky`) of an index
    /// to bit 31 (the copy bit of a mirrored axis).
    sx: u32,
    sy: u32,
    /// Row stride in bytes (`4w`).
    stride: u32,
    _texels: PhantomData<&'a [Texel]>,
}

// SAFETY: a view is a shared borrow of texels (`&'a [Texel]`, which is
// `Send` and `Sync`) plus plain integers; nothing writes through it.
unsafe impl Send for LevelView<'_> {}
// SAFETY: as for `Send`.
unsafe impl Sync for LevelView<'_> {}

impl fmt::Debug for LevelView<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("LevelView")
            .field("w", &self.w)
            .field("h", &self.h)
            .finish_non_exhaustive()
    }
}

impl<'a> LevelView<'a> {
    /// A view of the `w × h` level starting at `texels[0]`, `None` unless
    /// `w` and `h` are powers of two `≤ 2¹⁵` and `texels` holds `w·h`
    /// texels.
    #[must_use]
    pub fn new(texels: &'a [Texel], w: u32, h: u32) -> Option<Self> {
        let ok = w.is_power_of_two() && h.is_power_of_two() && w <= MAX_SIZE && h <= MAX_SIZE;
        let len = (w as usize).checked_mul(h as usize)?;
        if !ok || texels.len() < len {
            return None;
        }
        Some(Self {
            base: NonNull::from(texels).cast(),
            w,
            h,
            mx: w - 1,
            my: h - 1,
            sx: w.leading_zeros(),
            sy: h.leading_zeros(),
            stride: w * 4,
            _texels: PhantomData,
        })
    }

    /// The level's first texel: the start of `w·h` initialised texels,
    /// valid and unwritten while the view lives (the co-processor's
    /// addressing returns addresses inside them, read by
    /// `coproc::cfu::footprint`; the texture unit's descriptor block
    /// locates them, `coproc::descriptor_block`).
    #[inline(always)]
    #[must_use]
    pub(crate) fn base(&self) -> NonNull<Texel> {
        self.base
    }

    /// Width `w` in texels (a power of two).
    #[inline(always)]
    #[must_use]
    pub fn width(&self) -> u32 {
        self.w
    }

    /// Height `h` in texels (a power of two).
    #[inline(always)]
    #[must_use]
    pub fn height(&self) -> u32 {
        self.h
    }

    /// `w − 1`, the mask of a column index.
    #[inline(always)]
    #[must_use]
    pub fn mask_x(&self) -> u32 {
        self.mx
    }

    /// `h − 1`, the mask of a row index.
    #[inline(always)]
    #[must_use]
    pub fn mask_y(&self) -> u32 {
        self.my
    }

    /// `31 − log2 w`: `x << shift_x()` has bit `log2 w` of `x` in bit 31.
    #[inline(always)]
    #[must_use]
    pub fn shift_x(&self) -> u32 {
        self.sx
    }

    /// `31 − log2 h`, as [`shift_x`](Self::shift_x) for rows.
    #[inline(always)]
    #[must_use]
    pub fn shift_y(&self) -> u32 {
        self.sy
    }

    /// The texel at row `y ≤ my`, column `x ≤ mx` (the callers' reduced
    /// indices).
    #[inline(always)]
    fn read(&self, x: u32, y: u32) -> Texel {
        debug_assert!(x <= self.mx && y <= self.my);
        let row = y as usize * self.stride as usize;
        // SAFETY: `x ≤ mx`, `y ≤ my` (every caller reduces them), so the
        // byte offset `4(y·w + x) ≤ 4(w·h − 1)` lies in the slice of at
        // least `w·h` texels the view was made from (checked by `new`),
        // which is borrowed shared for `'a` (module docs).
        unsafe { self.base.as_ptr().byte_add(row).add(x as usize).read() }
    }

    /// The footprint `(x[0], y[0])`, `(x[1], y[0])`, `(x[0], y[1])`,
    /// `(x[1], y[1])` with the indices masked to the level (`x & (w − 1)`,
    /// `y & (h − 1)`: the identity on in-range indices, a wrap beyond).
    #[inline(always)]
    #[must_use]
    pub fn footprint(&self, x: [u32; 2], y: [u32; 2]) -> [Texel; 4] {
        let (x0, x1) = (x[0] & self.mx, x[1] & self.mx);
        let (y0, y1) = (y[0] & self.my, y[1] & self.my);
        [
            self.read(x0, y0),
            self.read(x1, y0),
            self.read(x0, y1),
            self.read(x1, y1),
        ]
    }

    /// The footprint of a coordinate wrapped on both axes
    /// ([`pow2_wrap_taps`] with the wrap constants `cx`, `cy` of this
    /// level and `bits` weight bits) and its weights `(fx, fy)`. No mask:
    /// `pow2_wrap_taps` gives `i₀` as the high word of a 32×32-bit product
    /// with the side (so `i₀ < w`, resp. `< h`) and `i₁ = (i₀ + 1) & m`.
    #[inline(always)]
    #[must_use]
    pub(crate) fn wrap_footprint(
        &self,
        u: TexCoord,
        v: TexCoord,
        [cx, cy]: [u32; 2],
        bits: u32,
    ) -> ([Texel; 4], u32, u32) {
        let (x0, x1, fx) = pow2_wrap_taps(u, self.w, self.mx, cx, bits);
        let (y0, y1, fy) = pow2_wrap_taps(v, self.h, self.my, cy, bits);
        let t = [
            self.read(x0, y0),
            self.read(x1, y0),
            self.read(x0, y1),
            self.read(x1, y1),
        ];
        (t, fx, fy)
    }

    /// The texel `(x, y)` clamped to the level (`min(x, w − 1)`,
    /// `min(y, h − 1)`), as [`TexelSource::texel`] reads.
    #[inline(always)]
    #[must_use]
    pub fn texel(&self, x: u32, y: u32) -> Texel {
        self.read(x.min(self.mx), y.min(self.my))
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
#[derive(Clone, Copy)]
pub struct Pow2Pyramid<'a> {
    pyramid: Pyramid<'a>,
    levels: Pow2Levels<'a>,
}

/// The [`LevelView`]s of a [`Pow2Pyramid`], indexed by level `0 ..= 16`
/// (levels outside the stored range repeat the nearest stored one).
#[derive(Clone, Copy, Debug)]
pub struct Pow2Levels<'a>([LevelView<'a>; MAX_LEVELS as usize + 1]);

impl<'a> Pow2Levels<'a> {
    /// The view of `level` (`≤ 16`; larger indices read the top entry).
    #[inline(always)]
    #[must_use]
    pub fn level(&self, level: usize) -> &LevelView<'a> {
        &self.0[level.min(MAX_LEVELS as usize)]
    }
}

impl fmt::Debug for Pow2Pyramid<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Pow2Pyramid")
            .field("pyramid", &self.pyramid)
            .finish_non_exhaustive()
    }
}

impl<'a> Pow2Pyramid<'a> {
    /// The views of `pyramid`.
    ///
    /// # Errors
    /// [`MipError::NotPowerOfTwo`] when a side is not a power of two;
    /// [`MipError::BufferTooShort`] when a level lies outside the texels
    /// (a [`Pyramid`] rules that out).
    pub fn new(pyramid: Pyramid<'a>) -> Result<Self, MipError> {
        let g = pyramid.geometry();
        if !(g.width().is_power_of_two() && g.height().is_power_of_two()) {
            return Err(MipError::NotPowerOfTwo);
        }
        let texels = pyramid.texels();
        let short = MipError::BufferTooShort {
            needed: g.len(),
            got: texels.len(),
        };
        let view = |k: u8| {
            let (w, h) = g.level_size(k);
            LevelView::new(texels.get(g.level_offset(k)..)?, w, h)
        };
        let top = view(0).ok_or(short)?;
        let mut levels = [top; MAX_LEVELS as usize + 1];
        for (k, v) in (0u8..).zip(levels.iter_mut()) {
            *v = view(k).ok_or(short)?;
        }
        Ok(Self {
            pyramid,
            levels: Pow2Levels(levels),
        })
    }

    /// The pyramid.
    #[must_use]
    pub fn pyramid(&self) -> Pyramid<'a> {
        self.pyramid
    }
}

impl TexelSource for Pow2Pyramid<'_> {
    #[inline]
    fn geometry(&self) -> Geometry {
        self.pyramid.geometry()
    }

    #[inline]
    fn texel(&mut self, level: u8, x: u32, y: u32) -> Texel {
        self.levels.level(usize::from(level)).texel(x, y)
    }

    #[inline]
    fn footprint(&mut self, level: u8, x: [u32; 2], y: [u32; 2]) -> [Texel; 4] {
        let v = self.levels.level(usize::from(level));
        let c = |i: [u32; 2], m: u32| [i[0].min(m), i[1].min(m)];
        v.footprint(c(x, v.mask_x()), c(y, v.mask_y()))
    }

    #[inline(always)]
    fn levels(&self) -> Option<&Pow2Levels<'_>> {
        Some(&self.levels)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
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
            for level in 0..=MAX_LEVELS + 1 {
                let (lw, lh) = g.level_size(level);
                let view = *views.levels().unwrap().level(usize::from(level));
                assert_eq!((view.width(), view.height()), (lw, lh));
                assert_eq!((view.mask_x(), view.mask_y()), (lw - 1, lh - 1));
                // Bit log2 w of a column (log2 h of a row) shifted to bit 31.
                assert_eq!(
                    (lw << view.shift_x(), lh << view.shift_y()),
                    (1 << 31, 1 << 31)
                );
                for y in 0..lh + 2 {
                    for x in 0..lw + 2 {
                        assert_eq!(d.texel(level, x, y), p.get(level, x, y));
                        let (xm, ym) = (x & (lw - 1), y & (lh - 1));
                        let want = [
                            p.get(level, xm, ym),
                            p.get(level, (x + 1) & (lw - 1), ym),
                            p.get(level, xm, (y + 1) & (lh - 1)),
                            p.get(level, (x + 1) & (lw - 1), (y + 1) & (lh - 1)),
                        ];
                        assert_eq!(view.footprint([x, x + 1], [y, y + 1]), want);
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
            pyramid.starts_with("Pow2Pyramid") && pyramid.contains("Pyramid"),
            "{pyramid}"
        );
    }
}
