//! One level in memory: the texel word, the size limits, and validated
//! views of power-of-two levels.
//!
//! A [`LevelView`] is a level's first texel, its sides and masks and its
//! row stride, checked once when it is made; [`Pow2Levels`] holds one per
//! level index `0 ..= 16`. The sampler reads the texels of a
//! [`Pow2Pyramid`](crate::texture::storage::pow2::Pow2Pyramid) through
//! them: two row pointers (`base + y·stride`) and the four texels
//! `row[x]` per footprint, with no bounds check per sample. [`Texel`],
//! [`MAX_SIZE`] and [`MAX_LEVELS`] are here, below the pyramids
//! ([`crate::texture::storage::mip`] re-exports them), so that
//! [`TexelSource`](crate::texture::storage::mip::TexelSource) can hand
//! out these views; so is the one-multiply wrap of a power-of-two side
//! (`pow2_wrap_taps`) that the views and the address modes share.
//!
//! # Safety
//!
//! This is the crate's only texture module with `unsafe` code: the texel
//! reads of [`LevelView`]. The argument, in full:
//!
//! * A view is made only by [`LevelView::new`] from a slice
//!   `&'a [Texel]` (`F::Stored` of [`Rgba8`]), or by
//!   [`LevelView::from_bytes`] (of [`Rgb565`]) from a byte slice
//!   `&'a [u8]` read as pairs `[u8; 2]` (alignment 1, every bit pattern a
//!   value, so its first `2·⌊len/2⌋` bytes are `⌊len/2⌋` initialised
//!   pairs), of at least `w·h` texels, `w = 2^kx`, `h = 2^ky`,
//!   `kx, ky ≤ 15` ([`MAX_SIZE`]); it keeps the slice's start pointer
//!   (whose provenance covers the whole slice), `w`, `h`, `mx = w − 1`,
//!   `my = h − 1`, the row stride `w·size_of::<F::Stored>()` in bytes
//!   (and two shift counts and the wrap constants, which no read uses:
//!   a wrapped index is below the side whatever the constant). Its fields are private and
//!   never written after construction, and it holds a
//!   `PhantomData<&'a [F::Stored]>`: it cannot outlive the shared borrow,
//!   during which the texels can be neither freed nor written, and moving
//!   a view does not move them.
//! * Every read first reduces its indices to `x ≤ mx`, `y ≤ my` (a mask
//!   `& mx` / `& my`, or a `min` with them; or, for a wrapped
//!   footprint, takes the first index as the high word of the 32×32-bit
//!   product of a 32-bit fraction with the side, which is below the
//!   side, and the second as the first plus one, masked; or, for a
//!   footprint inside the level, tests `x < mx` and `y < my` before it
//!   reads `x + 1` and `y + 1`), so the texel index
//!   `y·w + x ≤ (h − 1)·w + w − 1 = w·h − 1` lies inside the slice. The
//!   row's byte offset `y·stride`, below the slice's length in bytes, is
//!   computed in `usize` (no overflow), and the read is one
//!   `ptr::byte_add` (the row), one `ptr::add` (the column) and
//!   `ptr::read` of an initialised, aligned `F::Stored` (a `Copy` value of
//!   the slice), expanded to RGBA8 by `F::expand` (safe code); the slice's
//!   length is not compared again.
//!
//! With feature `cfu` on riscv32, `cfu_footprint` reads memory at the
//! four addresses the co-processor's `tex.addr`/`tex.tap` return. Each is `base + 4·(y·2^kx + x)` with `x < 2^kx` and `y < 2^ky`
//! by construction of the RTL (every mode's index map ends in a mask or a
//! clamp to the level; the Verilator testbench checks every address bit
//! of the reference vectors, `scripts/softcore`), where `base`, `2^kx` and
//! `2^ky` are a [`LevelView`]'s first texel and sides: the view guarantees
//! `2^(kx + ky)` initialised texels there for as long as it lives (its
//! construction checks them against a borrowed slice,
//! `texture::storage::pow2`). So each address is that of one of those
//! texels, aligned, read while the view is borrowed. On a core without the
//! co-processor the first instruction traps (illegal instruction) before
//! any read.
//!
//! Tests: views of every level of trimmed and full pyramids read exactly
//! what [`Pyramid::get`](crate::texture::storage::mip::Pyramid::get) reads, over every index and beyond (masks and
//! clamps), also under Miri (`scripts/robustness`, filter `pow2::`).

#![allow(unsafe_code)]

use core::fmt;
use core::marker::PhantomData;
use core::ptr::NonNull;

#[cfg(all(feature = "cfu", target_arch = "riscv32"))]
use crate::coproc::cfu::{addr, level, tap};
#[cfg(all(feature = "cfu", target_arch = "riscv32"))]
use crate::coproc::{TAP01, TAP10, TAP11};
use crate::texture::storage::format::{Rgb565, Rgba8};
pub use crate::texture::storage::format::{Texel, ViewFormat};
use crate::units::TexCoord;

/// Largest number of stored levels (a 32768-texel side has 16).
pub const MAX_LEVELS: u8 = 16;

/// Largest texture side in texels: 2¹⁵ = 32768 (keeps every offset and
/// block number inside `u32` on 32-bit targets).
pub const MAX_SIZE: u32 = 1 << 15;

/// The weight widths whose wrap constants a [`LevelView`] holds: the
/// kernels' (FAST 8, ACCURATE 12, sRGB 16).
const WRAP_BITS: [u32; 3] = [8, 12, 16];

/// `(2^(31 − bits) − 2³¹)/2^k` as wrapping `u32` for a power-of-two side
/// `2^k`, `k ≤ 31 − bits` (exact: the numerator is a multiple of
/// `2^(31 − bits)`): the constant of [`pow2_wrap_taps`].
#[must_use]
pub(crate) const fn wrap_constant(k: u32, bits: u32) -> u32 {
    let c = (1i32 << (31 - bits)).wrapping_add(i32::MIN);
    c.wrapping_shr(k) as u32
}

/// [`AddressMode::taps`](crate::texture::address::AddressMode::taps) of
/// [`Wrap`](crate::texture::address::AddressMode::Wrap) for a power-of-two
/// side `size = 2^k` with one 32×32→64-bit multiply, `c =`
/// [`wrap_constant`]`(k, bits)`. With `x = u·size − ½ + 2^−(bits+1)` in
/// 2⁻³²-texel units and `u` the fractional bits of the coordinate,
/// `x = size·y` for the integer `y = u + c` (exact for `k ≤ 31 − bits`).
/// For `y mod 2³²` the product `size·y` has `i₀ = floor(x / 2³²)` already
/// wrapped to `[0, size)` in its high word and the weight in the top
/// `bits` bits of its low word; `i₁ = (i₀ + 1) & m` with `m = size − 1`
/// (given: a level view's mask, so that the view's own mask of the same
/// index folds into it). Tested equal to
/// `taps` for every side up to [`MAX_SIZE`].
#[inline(always)]
pub(crate) fn pow2_wrap_taps(
    coord: TexCoord,
    size: u32,
    m: u32,
    c: u32,
    bits: u32,
) -> (u32, u32, u32) {
    let y = (coord.to_bits() as u32).wrapping_add(c);
    let p = u64::from(y) * u64::from(size);
    let i0 = (p >> 32) as u32;
    let f = (p as u32) >> (32 - bits);
    (i0, i0.wrapping_add(1) & m, f)
}

/// One power-of-two level in memory, validated ([module docs](self)):
/// every read is in bounds by construction. Its texels are stored as
/// `F::Stored` ([`ViewFormat`]); every read returns them as RGBA8.
#[derive(Clone, Copy)]
pub struct LevelView<'a, F: ViewFormat = Rgba8> {
    /// The level's first texel (of at least `w·h` in a slice borrowed
    /// for `'a`).
    base: NonNull<F::Stored>,
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
    /// Row stride in bytes (`w` times the size of `F::Stored`).
    stride: u32,
    /// The wrap constants [`wrap_constant`]`(k, bits)` of both axes for
    /// the kernels' weight widths `bits` = 8, 12, 16
    /// ([`wrap_constants`](Self::wrap_constants)): in the view, so that a
    /// sample reads a level's constants through the same pointer as its
    /// sides and first texel.
    c: [[u32; 2]; 3],
    /// Pads the view to 64 bytes: a level's view is then one shift of the
    /// level index away from the table's start.
    _pad: [u32; 2],
    _texels: PhantomData<&'a [F::Stored]>,
}

// SAFETY: a view is a shared borrow of texels (`&'a [F::Stored]`, which
// is `Send` and `Sync` because `F::Stored` is `Sync`) plus plain
// integers; nothing writes through it.
unsafe impl<F: ViewFormat> Send for LevelView<'_, F> {}
// SAFETY: as for `Send`.
unsafe impl<F: ViewFormat> Sync for LevelView<'_, F> {}

impl<F: ViewFormat> fmt::Debug for LevelView<'_, F> {
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
        Self::at(NonNull::from(texels).cast(), texels.len(), w, h)
    }
}

impl<'a, F: ViewFormat> LevelView<'a, F> {
    /// The view of the `w × h` level at `base`, where `len` initialised
    /// `F::Stored` values lie, borrowed shared for `'a` (the callers'
    /// slices); `None` as for [`new`](Self::new).
    fn at(base: NonNull<F::Stored>, len: usize, w: u32, h: u32) -> Option<Self> {
        let ok = w.is_power_of_two() && h.is_power_of_two() && w <= MAX_SIZE && h <= MAX_SIZE;
        let texels = (w as usize).checked_mul(h as usize)?;
        // The row stride in bytes: 4w for RGBA8, 2w for RGB565.
        let stride = u32::try_from(size_of::<F::Stored>()).ok()?.checked_mul(w)?;
        if !ok || len < texels {
            return None;
        }
        Some(Self {
            base,
            w,
            h,
            mx: w - 1,
            my: h - 1,
            sx: w.leading_zeros(),
            sy: h.leading_zeros(),
            stride,
            c: WRAP_BITS.map(|bits| [w, h].map(|n| wrap_constant(n.trailing_zeros(), bits))),
            _pad: [0; 2],
            _texels: PhantomData,
        })
    }
}

impl<'a> LevelView<'a, Rgb565> {
    /// A view of the `w × h` RGB565 level starting at `bytes[0]` (two
    /// bytes per texel, little-endian, any alignment), `None` unless `w`
    /// and `h` are powers of two `≤ 2¹⁵` and `bytes` holds `2·w·h` bytes.
    #[must_use]
    pub fn from_bytes(bytes: &'a [u8], w: u32, h: u32) -> Option<Self> {
        // `[u8; 2]` has alignment 1 and every value: the first
        // `2·⌊len/2⌋` bytes are `⌊len/2⌋` initialised pairs.
        Self::at(NonNull::from(bytes).cast(), bytes.len() / 2, w, h)
    }
}

impl LevelView<'_> {
    /// The level's first texel: the start of `w·h` initialised texels,
    /// valid and unwritten while the view lives (the co-processor's
    /// addressing returns addresses inside them, read by
    /// `cfu_footprint`; the texture unit's descriptor block
    /// locates them, `texture::coproc::descriptor_block`).
    #[inline(always)]
    #[must_use]
    pub(crate) fn base(&self) -> NonNull<Texel> {
        self.base
    }
}

impl<F: ViewFormat> LevelView<'_, F> {
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

    /// The wrap constants [`wrap_constant`]`(k, bits)` of the sides
    /// `2^k` (`[u, v]`) for `bits` weight bits: from the view for the
    /// kernels' widths 8, 12 and 16 (a constant `bits` selects the field
    /// at compile time), computed for any other `bits ≤ 16`.
    #[inline(always)]
    #[must_use]
    pub(crate) fn wrap_constants(&self, bits: u32) -> [u32; 2] {
        match bits {
            8 => self.c[0],
            12 => self.c[1],
            16 => self.c[2],
            _ => [self.w, self.h].map(|n| wrap_constant(n.trailing_zeros(), bits)),
        }
    }

    /// The texel at row `y ≤ my`, column `x ≤ mx` (the callers' reduced
    /// indices).
    #[inline(always)]
    fn read(&self, x: u32, y: u32) -> Texel {
        debug_assert!(x <= self.mx && y <= self.my);
        let row = y as usize * self.stride as usize;
        // SAFETY: `x ≤ mx`, `y ≤ my` (every caller reduces them), so the
        // texel `y·w + x ≤ w·h − 1` lies in the slice of at least `w·h`
        // texels the view was made from (checked by `new`), which is
        // borrowed shared for `'a` (module docs).
        F::expand(unsafe { self.base.as_ptr().byte_add(row).add(x as usize).read() })
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

    /// The footprint `(x, y)`, `(x + 1, y)`, `(x, y + 1)`, `(x + 1, y + 1)`
    /// of a first tap whose footprint lies inside the level (`x < w − 1`
    /// and `y < h − 1`: one unsigned compare per axis, so a negative tap
    /// as `u32` is outside), else `None`. The two texels of a row are
    /// adjacent in memory (one `ldrd` on the M4), and no index is masked.
    #[inline(always)]
    #[must_use]
    pub(crate) fn inside_footprint(&self, x: u32, y: u32) -> Option<[Texel; 4]> {
        if x < self.mx && y < self.my {
            let stride = self.stride as usize;
            // SAFETY: `x + 1 ≤ mx` and `y + 1 ≤ my`, so the four texels
            // `(y + dy)·w + x + dx` (`dx, dy ≤ 1`) lie in the slice of at
            // least `w·h` texels the view was made from, borrowed shared
            // for `'a` (module docs); `p` is the first of them.
            unsafe {
                let p = self
                    .base
                    .as_ptr()
                    .byte_add(y as usize * stride)
                    .add(x as usize);
                let q = p.byte_add(stride);
                Some([p.read(), p.add(1).read(), q.read(), q.add(1).read()].map(F::expand))
            }
        } else {
            None
        }
    }

    /// The footprint of a coordinate wrapped on both axes
    /// ([`pow2_wrap_taps`] with this level's
    /// [`wrap_constants`](Self::wrap_constants) for `bits` weight bits)
    /// and its weights `(fx, fy)`. No mask:
    /// `pow2_wrap_taps` gives `i₀` as the high word of a 32×32-bit product
    /// with the side (so `i₀ < w`, resp. `< h`) and `i₁ = (i₀ + 1) & m`.
    #[inline(always)]
    #[must_use]
    pub(crate) fn wrap_footprint(
        &self,
        u: TexCoord,
        v: TexCoord,
        bits: u32,
    ) -> ([Texel; 4], u32, u32) {
        let [cx, cy] = self.wrap_constants(bits);
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
    /// `min(y, h − 1)`), as [`TexelSource::texel`](crate::texture::storage::mip::TexelSource::texel) reads.
    #[inline(always)]
    #[must_use]
    pub fn texel(&self, x: u32, y: u32) -> Texel {
        self.read(x.min(self.mx), y.min(self.my))
    }
}
/// Feature `cfu` on riscv32, the addressing instructions of
/// [`crate::coproc::cfu`] (module docs: the safety of this read).
///
/// The bilinear footprint `[t00, t10, t01, t11]` of the coordinates
/// `(u, v)` ([`coord_i4f28`](crate::texture::coproc::coord_i4f28) operands) on the level `l`, addressed
/// in the modes of `modes` (`level_config(0, 0, mu, mv)`); the weights
/// stay latched in the co-processor for `tex.bt`/`tex.bb`. The texels are
/// those the software taps select (same bits, `scripts/softcore`).
#[cfg(all(feature = "cfu", target_arch = "riscv32"))]
#[inline(always)]
#[must_use]
pub fn cfu_footprint(l: &LevelView<'_>, modes: u32, u: u32, v: u32) -> [Texel; 4] {
    // `shift = 31 − log2(side)`, sides ≤ 2¹⁵ (`LevelView::new`).
    let (kx, ky) = (31 - l.shift_x(), 31 - l.shift_y());
    let base = l.base().as_ptr().expose_provenance() as u32;
    level(base, kx | ky << 4 | modes);
    let a = [addr(u, v), tap::<TAP10>(), tap::<TAP01>(), tap::<TAP11>()];
    // SAFETY: each address is that of one of the `2^(kx + ky)` texels at
    // `base` (module docs: `base + 4·j`, `j < 2^(kx + ky)`, aligned), which
    // the view keeps initialised and unwritten while it lives (its
    // invariant, `LevelView::base`); `expose_provenance` exposed the
    // provenance of that memory above, and `Texel` (u32) has no invalid
    // values.
    a.map(|a| unsafe { core::ptr::with_exposed_provenance::<Texel>(a as usize).read() })
}

/// The [`LevelView`]s of a
/// [`Pow2Pyramid`](crate::texture::storage::pow2::Pow2Pyramid), indexed by level `0 ..= 16`
/// (levels outside the stored range repeat the nearest stored one).
#[derive(Clone, Copy, Debug)]
pub struct Pow2Levels<'a, F: ViewFormat = Rgba8>(
    pub(crate) [LevelView<'a, F>; MAX_LEVELS as usize + 1],
);

impl<'a, F: ViewFormat> Pow2Levels<'a, F> {
    /// The views `view(k)` of every level index `k ≤ 16`, or `None` when
    /// one of them is `None`.
    pub(crate) fn from_fn(view: impl Fn(u8) -> Option<LevelView<'a, F>>) -> Option<Self> {
        let top = view(0)?;
        let mut levels = [top; MAX_LEVELS as usize + 1];
        for (k, v) in (0u8..).zip(levels.iter_mut()) {
            *v = view(k)?;
        }
        Some(Self(levels))
    }

    /// The view of `level` (`≤ 16`; larger indices read the top entry).
    #[inline(always)]
    #[must_use]
    pub fn level(&self, level: usize) -> &LevelView<'a, F> {
        &self.0[level.min(MAX_LEVELS as usize)]
    }

    /// Texel `(x, y)` of `level` (`≤ 16`), the indices masked to the level
    /// as [`LevelView::texel`] does: a power-of-two source's
    /// `TexelSource::texel`.
    #[inline]
    #[must_use]
    pub fn texel(&self, level: u8, x: u32, y: u32) -> Texel {
        self.level(usize::from(level)).texel(x, y)
    }

    /// The footprint of columns `x` and rows `y` of `level` (`≤ 16`), each
    /// index clamped to the level's last column or row (an index past the
    /// edge reads the edge texel): a power-of-two source's
    /// `TexelSource::footprint`.
    #[inline]
    #[must_use]
    pub fn clamped_footprint(&self, level: u8, x: [u32; 2], y: [u32; 2]) -> [Texel; 4] {
        let v = self.level(usize::from(level));
        v.footprint(x.map(|x| x.min(v.mask_x())), y.map(|y| y.min(v.mask_y())))
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::vec::Vec;

    /// A level whose texels name their position: `0xA500_0000 | y << 12 | x`.
    fn named(w: u32, h: u32) -> Vec<Texel> {
        (0..h)
            .flat_map(|y| (0..w).map(move |x| 0xA500_0000 | y << 12 | x))
            .collect()
    }

    /// The texel of `named` at `(x, y)` (the reference of every read).
    fn name(x: u32, y: u32) -> Texel {
        0xA500_0000 | y << 12 | x
    }

    /// The sides the views are tested on (all shapes: square, 1-wide,
    /// 1-high, wide, tall).
    const SIDES: [(u32, u32); 6] = [(1, 1), (1, 8), (8, 1), (4, 16), (32, 2), (16, 16)];

    /// `wrap_constant(k, bits)` by its definition, in i64: the exact
    /// quotient `(2^(31 − bits) − 2³¹)/2^k`, taken mod 2³².
    fn wrap_constant_ref(k: u32, bits: u32) -> u32 {
        let num = (1i64 << (31 - bits)) - (1i64 << 31);
        assert_eq!(num % (1i64 << k), 0);
        (num / (1i64 << k)).rem_euclid(1 << 32) as u32
    }

    /// The wrap taps by their definition, in i128: the position
    /// `x = u·n − ½ + 2^−(bits+1)` texels (`u` the coordinate's 32
    /// fractional bits) in units of 2⁻³², `i₀ = floor(x) mod n`,
    /// `i₁ = (i₀ + 1) mod n`, the weight the top `bits` bits of `frac(x)`.
    fn wrap_taps_ref(coord: TexCoord, n: u32, bits: u32) -> (u32, u32, u32) {
        let frac = i128::from(coord.to_bits() as u32);
        let x = frac * i128::from(n) - (1i128 << 31) + (1i128 << (31 - bits));
        let i0 = x.div_euclid(1 << 32).rem_euclid(i128::from(n)) as u32;
        let f = (x.rem_euclid(1 << 32) >> (32 - bits)) as u32;
        (i0, (i0 + 1) % n, f)
    }

    /// Coordinates: the edges of the fractional word, integer parts that
    /// must not matter (negative too) and pseudo-random fractions.
    fn coords() -> impl Iterator<Item = TexCoord> {
        let mut s = 0x2545_F491_4F6C_DD1Du64;
        let edges = [
            0u32,
            1,
            0x7FFF_FFFF,
            0x8000_0000,
            0x8000_0001,
            u32::MAX,
            0x0080_0000,
        ];
        let random = (0..if cfg!(miri) { 20 } else { 2000 }).map(move |_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s as u32
        });
        edges.into_iter().chain(random).flat_map(|frac| {
            [0i64, 1, -1, 7].map(|int| TexCoord::from_bits(int << 32 | i64::from(frac)))
        })
    }

    #[test]
    fn wrap_constant_is_the_exact_quotient() {
        for bits in [8, 12, 16, 1, 10] {
            for k in 0..=15 {
                assert_eq!(
                    wrap_constant(k, bits),
                    wrap_constant_ref(k, bits),
                    "{k} {bits}"
                );
            }
        }
        // Worked by hand: k = 0, bits = 8: 2²³ − 2³¹ mod 2³² = 0x8080_0000;
        // k = 3: (2²³ − 2³¹)/8 = −0x0FF0_0000.
        assert_eq!(wrap_constant(0, 8), 0x8080_0000);
        assert_eq!(wrap_constant(3, 8), 0xF010_0000);
    }

    #[test]
    fn pow2_wrap_taps_match_the_definition() {
        for k in 0..=15 {
            let n = 1u32 << k;
            for bits in [8, 12, 16] {
                let c = wrap_constant_ref(k, bits);
                for coord in coords() {
                    assert_eq!(
                        pow2_wrap_taps(coord, n, n - 1, c, bits),
                        wrap_taps_ref(coord, n, bits),
                        "{n} {bits} {coord:?}"
                    );
                }
            }
        }
        // By hand: u = ½ on a side of 4 is x = 1.5 + 2⁻⁹ texels: taps 1, 2,
        // weight 128 + ½ → 128 at 8 bits; u = 0 is x = −½: taps 3, 0.
        let half = TexCoord::from_bits(1 << 31);
        assert_eq!(
            pow2_wrap_taps(half, 4, 3, wrap_constant(2, 8), 8),
            (1, 2, 128)
        );
        let zero = TexCoord::from_bits(0);
        assert_eq!(
            pow2_wrap_taps(zero, 4, 3, wrap_constant(2, 8), 8),
            (3, 0, 128)
        );
    }

    #[test]
    fn views_are_made_only_of_valid_levels() {
        let t = named(32, 32);
        for (w, h) in SIDES {
            let n = (w * h) as usize;
            assert!(LevelView::new(&t[..n], w, h).is_some(), "{w} {h}");
            assert!(LevelView::new(&t[..n - 1], w, h).is_none(), "{w} {h}");
        }
        for (w, h) in [(3, 4), (4, 3), (0, 4), (4, 0), (6, 6)] {
            assert!(LevelView::new(&t, w, h).is_none(), "{w} {h}");
        }
        // The largest side on either axis, and one past it.
        let long = std::vec![0u32; 1 << 16];
        assert!(LevelView::new(&long[..1 << 15], MAX_SIZE, 1).is_some());
        assert!(LevelView::new(&long[..1 << 15], 1, MAX_SIZE).is_some());
        assert!(LevelView::new(&long, 2 * MAX_SIZE, 1).is_none());
        assert!(LevelView::new(&long, 1, 2 * MAX_SIZE).is_none());
        // RGB565: two bytes per texel; an odd byte holds no texel.
        let bytes = [0u8; 33];
        assert!(LevelView::from_bytes(&bytes[..32], 4, 4).is_some());
        assert!(LevelView::from_bytes(&bytes[..31], 4, 4).is_none());
        assert!(LevelView::from_bytes(&bytes, 16, 1).is_some());
        assert!(LevelView::from_bytes(&bytes, 3, 1).is_none());
    }

    #[test]
    fn accessors_are_the_sides() {
        for (w, h) in SIDES {
            let t = named(w, h);
            let v = LevelView::new(&t, w, h).unwrap();
            assert_eq!((v.width(), v.height()), (w, h));
            assert_eq!((v.mask_x(), v.mask_y()), (w - 1, h - 1));
            assert_eq!((v.shift_x(), v.shift_y()), (31 - w.ilog2(), 31 - h.ilog2()));
            assert_eq!(v.base().as_ptr().cast_const(), t.as_ptr());
            // Bit log2(w) of an index lands in bit 31.
            assert_eq!(w << v.shift_x(), 1 << 31);
            for bits in [8, 12, 16, 10, 4] {
                let want = [w, h].map(|n| wrap_constant_ref(n.ilog2(), bits));
                assert_eq!(v.wrap_constants(bits), want, "{w} {h} {bits}");
            }
        }
    }

    #[test]
    fn reads_are_the_slice_at_the_reduced_indices() {
        let big = [0, 1, 2, 5, 31, 32, 33, 1000, u32::MAX - 1, u32::MAX];
        for (w, h) in SIDES {
            let t = named(w, h);
            let v = LevelView::new(&t, w, h).unwrap();
            for y in 0..h {
                for x in 0..w {
                    assert_eq!(v.read(x, y), name(x, y));
                }
            }
            for &x0 in &big {
                for &y0 in &big {
                    let (x1, y1) = (x0.wrapping_add(1), y0.wrapping_add(1));
                    // Masked: a wrap beyond the level.
                    let (mx, my) = (x0 % w, y0 % h);
                    let (mx1, my1) = (x1 % w, y1 % h);
                    assert_eq!(
                        v.footprint([x0, x1], [y0, y1]),
                        [name(mx, my), name(mx1, my), name(mx, my1), name(mx1, my1)],
                        "{w} {h} {x0} {y0}"
                    );
                    // Clamped: the edge texel beyond the level.
                    assert_eq!(v.texel(x0, y0), name(x0.min(w - 1), y0.min(h - 1)));
                    // Inside: only when the whole footprint is.
                    let inside =
                        u64::from(x0) + 1 < u64::from(w) && u64::from(y0) + 1 < u64::from(h);
                    let want =
                        inside.then(|| [name(x0, y0), name(x1, y0), name(x0, y1), name(x1, y1)]);
                    assert_eq!(v.inside_footprint(x0, y0), want, "{w} {h} {x0} {y0}");
                }
            }
        }
    }

    #[test]
    fn rgb565_reads_step_two_bytes() {
        // Texel (x, y) of a 4 × 2 level holds the bytes [8y + 2x, 8y + 2x + 1].
        let bytes: Vec<u8> = (0..16).collect();
        let v = LevelView::from_bytes(&bytes, 4, 2).unwrap();
        let expand = |x: u32, y: u32| {
            let i = (8 * y + 2 * x) as u8;
            Rgb565::expand([i, i + 1])
        };
        for y in 0..2 {
            for x in 0..4 {
                assert_eq!(v.texel(x, y), expand(x, y), "{x} {y}");
            }
        }
        assert_eq!(
            v.inside_footprint(2, 0),
            Some([expand(2, 0), expand(3, 0), expand(2, 1), expand(3, 1)])
        );
        assert_eq!(
            v.footprint([3, 4], [1, 2]),
            [expand(3, 1), expand(0, 1), expand(3, 0), expand(0, 0)]
        );
    }

    #[test]
    fn wrap_footprint_reads_the_wrapped_taps() {
        for (w, h) in SIDES {
            let t = named(w, h);
            let v = LevelView::new(&t, w, h).unwrap();
            for bits in [8, 12, 16] {
                for (u, v_) in coords().zip(coords().skip(3)) {
                    let (x0, x1, fx) = wrap_taps_ref(u, w, bits);
                    let (y0, y1, fy) = wrap_taps_ref(v_, h, bits);
                    let want = [name(x0, y0), name(x1, y0), name(x0, y1), name(x1, y1)];
                    assert_eq!(
                        v.wrap_footprint(u, v_, bits),
                        (want, fx, fy),
                        "{w} {h} {bits}"
                    );
                }
            }
        }
    }

    #[test]
    fn pow2_levels_index_their_views() {
        let side = |k: u8| 32u32 >> k.min(5);
        let data: Vec<Vec<Texel>> = (0..=5).map(|k| named(side(k), side(k))).collect();
        let t = &data[0];
        let levels =
            Pow2Levels::from_fn(|k| LevelView::new(&data[usize::from(k.min(5))], side(k), side(k)))
                .unwrap();
        for k in 0..=20usize {
            let want = side(k.min(16) as u8);
            assert_eq!(levels.level(k).width(), want, "{k}");
        }
        assert_eq!(levels.texel(1, 3, 40), name(3, 15));
        assert_eq!(levels.texel(5, 3, 0), name(0, 0));
        assert_eq!(
            levels.clamped_footprint(2, [6, 9], [7, 8]),
            [name(6, 7), name(7, 7), name(6, 7), name(7, 7)]
        );
        assert!(
            Pow2Levels::from_fn(|k| LevelView::new(t, side(k), if k == 9 { 3 } else { 1 }))
                .is_none()
        );
        assert!(
            Pow2Levels::from_fn(|k| LevelView::new(t, if k == 0 { 3 } else { 1 }, 1)).is_none()
        );
    }
}
