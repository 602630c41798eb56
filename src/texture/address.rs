//! Address modes of a GPU sampler (D3D11 `D3D11_TEXTURE_ADDRESS_MODE`,
//! Vulkan `VkSamplerAddressMode`), applied per axis to integer texel
//! indices as the Vulkan specification's "wrapping operation" does.
//!
//! A normalized [`TexCoord`] `u` is first reduced without changing any
//! texel it can select (exactly, on the fixed-point bits), then scaled by
//! the level size: `x = u·size` for the nearest texel, `x = u·size − ½` for
//! the bilinear pair `i₀ = floor(x)`, `i₁ = i₀ + 1` with the weight of `i₁`
//! the fraction of `x` rounded to 12 bits ([`WEIGHT_BITS`]; the D3D11 minimum
//! is 8 bits of sub-texel precision). Each index then goes through
//! [`AddressMode::index`]:
//!
//! | mode | reduction of `u` | index `i` → texel |
//! |---|---|---|
//! | [`Wrap`](AddressMode::Wrap) | `u mod 1` | `i mod size` |
//! | [`Mirror`](AddressMode::Mirror) | `u mod 2` | `m = i mod 2·size`; `m` if `m < size`, else `2·size − 1 − m` |
//! | [`ClampToEdge`](AddressMode::ClampToEdge) | clamp to `[−1, 2]` | `clamp(i, 0, size − 1)` |
//! | [`MirrorOnce`](AddressMode::MirrorOnce) | clamp to `[−2, 2]` | `clamp(i ≥ 0 ? i : −1 − i, 0, size − 1)` |
//! | [`ClampToBorder`](AddressMode::ClampToBorder) | clamp to `[−1, 2]` | `i` if `0 ≤ i < size`, else the border colour (`None`) |
//!
//! Every reduction keeps `|u·size| < 2⁴⁹` in 32-fractional-bit units, so
//! indices lie in `(−2¹⁷, 2¹⁷)`; the mapping handles any `i32` (a final
//! clamp keeps results in range), so no input panics.

use crate::texture::storage::level::pow2_wrap_taps;
use crate::units::TexCoord;

/// Fractional bits of the bilinear weights.
pub const WEIGHT_BITS: u32 = 12;

/// What a sampler does with coordinates outside `[0, 1)`, per axis.
///
/// # Example
/// ```
/// use raymip::AddressMode;
/// // Texel index −1 and 8 of a level 8 texels wide (valid: 0..=7).
/// assert_eq!(AddressMode::Wrap.index(-1, 8), Some(7));
/// assert_eq!(AddressMode::Mirror.index(8, 8), Some(7)); // mirrored copy
/// assert_eq!(AddressMode::ClampToEdge.index(-1, 8), Some(0));
/// assert_eq!(AddressMode::MirrorOnce.index(-3, 8), Some(2)); // |−3| − 1
/// assert_eq!(AddressMode::ClampToBorder.index(8, 8), None); // border colour
/// // A sampler picks it at run time: `Sampler::with_address(pyramid, mode)`.
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum AddressMode {
    /// Repeat (D3D `WRAP`, Vulkan `REPEAT`).
    #[default]
    Wrap = 0,
    /// Repeat, every other copy mirrored (D3D `MIRROR`, Vulkan
    /// `MIRRORED_REPEAT`).
    Mirror = 1,
    /// Clamp texel indices to the edge (D3D `CLAMP`, Vulkan
    /// `CLAMP_TO_EDGE`).
    ClampToEdge = 2,
    /// Mirror once around 0, then clamp to the edge (D3D `MIRROR_ONCE`,
    /// Vulkan `MIRROR_CLAMP_TO_EDGE`).
    MirrorOnce = 3,
    /// Texels outside the level read the sampler's border colour (D3D
    /// `BORDER`, Vulkan `CLAMP_TO_BORDER`).
    ClampToBorder = 4,
}

indexed_enum! { AddressMode: Wrap, Mirror, ClampToEdge, MirrorOnce, ClampToBorder }

impl AddressMode {
    /// `u` reduced (exactly) to the range that selects the same texels,
    /// in I32F32 bits: `[0, 2³²)` (wrap), `[0, 2³³)` (mirror),
    /// `[−2³², 2³³]` (clamp, border), `[−2³³, 2³³]` (mirror once).
    #[cfg(test)]
    fn reduce(self, coord: TexCoord) -> i64 {
        let b = coord.to_bits();
        match self {
            Self::Wrap => b & 0xFFFF_FFFF,
            Self::Mirror => b & 0x1_FFFF_FFFF,
            Self::ClampToEdge | Self::ClampToBorder => b.clamp(-(1 << 32), 2 << 32),
            Self::MirrorOnce => b.clamp(-(2 << 32), 2 << 32),
        }
    }

    /// Texel of a level `size` texels wide (`size ≥ 1`) addressed by the
    /// integer index `i`, or `None` for the border colour
    /// ([`ClampToBorder`](Self::ClampToBorder) only). Any `i` is accepted;
    /// results are always `< size`.
    #[inline(always)]
    #[must_use]
    pub fn index(self, i: i32, size: u32) -> Option<u32> {
        // Sides are at most 2¹⁵ (`mip::MAX_SIZE`): 2·n fits i32.
        let n = size.clamp(1, crate::texture::storage::mip::MAX_SIZE) as i32;
        let top = n - 1;
        let inside = i >= 0 && i < n;
        let j = match self {
            // Inside, or the one-off neighbour a reduced coordinate gives:
            // no division on the per-sample path.
            _ if inside => i,
            Self::Wrap if i == -1 => top,
            Self::Wrap if i == n => 0,
            Self::Wrap => i.checked_rem_euclid(n).unwrap_or(0),
            Self::Mirror => {
                let m = i.checked_rem_euclid(2 * n).unwrap_or(0);
                if m < n { m } else { 2 * n - 1 - m }
            }
            Self::ClampToEdge => i,
            Self::MirrorOnce => {
                if i < 0 {
                    -1 - i
                } else {
                    i
                }
            }
            Self::ClampToBorder => return None,
        };
        // In range already except for the clamping modes; never truncates.
        Some(j.clamp(0, top).unsigned_abs())
    }

    /// Nearest texel `floor(u·size)`, addressed (`None` = border).
    #[inline]
    #[must_use]
    pub fn nearest(self, coord: TexCoord, size: u32) -> Option<u32> {
        let (i, border) = self.nearest_tap(coord, size);
        (!border).then_some(i)
    }

    /// Bilinear pair on one axis: `([i₀, i₁], weight of i₁ in 1/4096)`,
    /// addressed (`None` = border), with `x = u·size − ½` and the weight
    /// rounded to nearest 1/4096.
    #[inline]
    #[must_use]
    pub fn linear(self, coord: TexCoord, size: u32) -> ([Option<u32>; 2], u32) {
        let t = self.taps(coord, size, WEIGHT_BITS);
        (
            [
                (!t.border[0]).then_some(t.i[0]),
                (!t.border[1]).then_some(t.i[1]),
            ],
            t.f,
        )
    }

    /// Nearest texel `floor(u·size)` on one axis: `(index, border)`, the
    /// index always `< size` (for a border tap the clamped one, which the
    /// sampler reads in place of nothing and then replaces).
    #[inline(always)]
    pub(crate) fn nearest_tap(self, coord: TexCoord, size: u32) -> (u32, bool) {
        let (i, _) = self.scaled(coord, size, 0);
        self.map(i, size)
    }

    /// `x = u'·size + offset` for the coordinate `u' = hi + lo/2³²` that
    /// selects the same texels as `u` under this mode, computed in 32-bit
    /// words with one 32×32→64-bit multiply: `(floor(x), frac(x)·2³²)`.
    /// `hi` is 0 (wrap: `u mod 1`), `hi mod 2` (mirror: `u mod 2`) or the
    /// integer part clamped to `[−4, 3]` (the clamping modes: a coordinate
    /// beyond `[−1, 2]` puts both taps of an axis on the same edge texel
    /// or outside, exactly as the reduction to `[−1, 2]` (`[−2, 2]` for
    /// mirror once) does; tested against [`reduce`](Self::reduce); on the
    /// Cortex-M4 the clamp is one `ssat`). For sizes up to 2¹⁵ and
    /// `|offset| < 2³²`, `floor(x) ∈ (−2¹⁸, 2¹⁸)`; larger sizes give
    /// meaningless but harmless values (wrapping arithmetic, and
    /// [`map`](Self::map) keeps every index below `size`).
    #[inline(always)]
    fn scaled(self, coord: TexCoord, size: u32, offset: i64) -> (i32, u32) {
        let b = coord.to_bits();
        let hi = (b >> 32) as i32;
        let hi = match self {
            Self::Wrap => 0,
            Self::Mirror => hi & 1,
            _ => hi.clamp(-4, 3),
        };
        let p = (u64::from(b as u32) * u64::from(size)) as i64 + offset;
        let i = ((p >> 32) as i32).wrapping_add(hi.wrapping_mul(size as i32));
        (i, p as u32)
    }

    /// Index `i` of the range [`scaled`](Self::scaled) gives mapped to
    /// `(texel, border)`: [`index`](Self::index) written for that range
    /// (tested equal to it), with the border case as a flag and the
    /// clamped index; the index is below `size` for every `i` and
    /// `size ≥ 1` (a [`Geometry`](crate::texture::Geometry)'s sides are).
    #[inline(always)]
    fn map(self, i: i32, size: u32) -> (u32, bool) {
        let n = size as i32;
        let top = n.wrapping_sub(1);
        // `max`/`min`, not `clamp`: no panic branch whatever the bounds.
        let clamp = |j: i32| j.min(top).max(0) as u32;
        match self {
            // Reduced `u ∈ [0, 1)`: `i ∈ [−1, n]`.
            Self::Wrap => {
                let j = if i < 0 {
                    top
                } else if i >= n {
                    0
                } else {
                    i
                };
                (j as u32, false)
            }
            // Reduced `u ∈ [0, 2)`: `i ∈ [−1, 2n]`; `min(i, 2n − 1 − i)`
            // mirrors the second copy, and −1 and 2n (both copies' seam
            // neighbours) go to 0.
            Self::Mirror => (
                clamp(i.min(n.wrapping_mul(2).wrapping_sub(1).wrapping_sub(i))),
                false,
            ),
            Self::ClampToEdge => (clamp(i), false),
            // `i ^ (i >> 31)` is `−1 − i` for negative `i`.
            Self::MirrorOnce => (clamp(i ^ (i >> 31)), false),
            // A negative `i` as `u32` is above any size.
            Self::ClampToBorder => (clamp(i), i as u32 >= size),
        }
    }

    /// The first bilinear tap on one axis before the mode maps it, and
    /// its weight: `x = u'·size − ½ + 2^−(bits+1)` by
    /// [`scaled`](Self::scaled) (the half step rounds the weight to
    /// nearest): `(floor(x), the top `bits` bits of frac(x))`, the weight
    /// below `2^bits` (`bits ∈ [1, 31]`: 8, 12 or 16 here). What
    /// [`taps`](Self::taps) and the clamping modes'
    /// [`pow2_first_tap`](Self::pow2_first_tap) start from.
    #[inline(always)]
    fn first_tap(self, coord: TexCoord, size: u32, bits: u32) -> (i32, u32) {
        let offset = (1i64 << (31 - bits)) - (1 << 31);
        let (i, frac) = self.scaled(coord, size, offset);
        (i, frac >> (32 - bits))
    }

    /// Bilinear taps on one axis with `bits` fractional weight bits
    /// (12 for ACCURATE, 8 for FAST, 16 for sRGB): `x = u·size − ½ +
    /// 2^−(bits+1)` (the half step rounds the weight to nearest),
    /// `i₀ = floor(x)`, `i₁ = i₀ + 1`, weight of `i₁` the top `bits` bits
    /// of `frac(x)`. Indices are always `< size`.
    /// Both taps inside the level (`0 ≤ i₀`, `i₁ ≤ size − 1`: one
    /// unsigned compare) are their own texels in every mode; only the
    /// others go through [`map`](Self::map) (decided once per axis).
    #[inline(always)]
    pub(crate) fn taps(self, coord: TexCoord, size: u32, bits: u32) -> AxisTaps {
        let (i, f) = self.first_tap(coord, size, bits);
        if (i as u32) < size.wrapping_sub(1) {
            return AxisTaps {
                i: [i as u32, (i as u32).wrapping_add(1)],
                f,
                border: [false; 2],
            };
        }
        let (i0, b0) = self.map(i, size);
        let (i1, b1) = self.map(i.wrapping_add(1), size);
        AxisTaps {
            i: [i0, i1],
            f,
            border: [b0, b1],
        }
    }
}

impl AddressMode {
    /// [`taps`](Self::taps) on a power-of-two side `n = 2^k` with
    /// `m = n − 1`, `s = 31 − k` and the wrap constant `c =`
    /// [`wrap_constant`](crate::texture::storage::level::wrap_constant)`(k, bits)`:
    /// wrap and mirror by [`pow2_first_tap`](Self::pow2_first_tap) and
    /// [`pow2_edge_taps`](Self::pow2_edge_taps) (wrap by [`pow2_wrap_taps`],
    /// one multiply; mirror by [`pow2_mirror_tap`], a multiply-accumulate,
    /// and [`mirror_fold`], an XOR per tap), the clamping modes as for any
    /// size. Equal to
    /// `taps` for every input (tested). With `MASKED`, for a reader that
    /// masks its indices with `m` and replaces border taps by the border
    /// colour (a sampler's direct level views):
    /// [`ClampToBorder`](Self::ClampToBorder) by the same two steps, a
    /// range test per tap (a
    /// border tap's index is not clamped, and no branch decides it); the
    /// flags, weight and the indices of taps inside are the same (tested).
    #[inline(always)]
    pub(crate) fn pow2_taps<const MASKED: bool>(
        self,
        coord: TexCoord,
        n: u32,
        m: u32,
        s: u32,
        c: u32,
        bits: u32,
    ) -> AxisTaps {
        match self {
            // `taps` itself: its branch on inside taps skips the mapping
            // (the same taps as the edge form, in fewer instructions on
            // the generic path).
            Self::ClampToEdge | Self::MirrorOnce => self.taps(coord, n, bits),
            Self::ClampToBorder if !MASKED => self.taps(coord, n, bits),
            _ => {
                let (i, f) = self.pow2_first_tap(coord, n, c, bits);
                self.pow2_edge_taps::<MASKED>(i, f, n, m, s)
            }
        }
    }

    /// The first tap of an axis on a power-of-two side `n = 2^k` before
    /// the mode maps it, and its weight (`bits` bits), `c` as for
    /// [`pow2_taps`](Self::pow2_taps). When `i < n − 1` (unsigned) both
    /// taps `i`, `i + 1` are texels of the level that the mode maps to
    /// themselves (no wrap, fold, clamp or border: the footprint axis is
    /// inside), for wrap and the clamping modes exactly then; any tap goes
    /// through
    /// [`pow2_edge_taps`](Self::pow2_edge_taps). Per mode:
    /// * wrap: `i₀ ∈ [0, n)` of [`pow2_wrap_taps`];
    /// * mirror: [`pow2_mirror_tap`], the tap modulo 2³² (then `i < n − 1`
    ///   means a first-copy footprint without the seam, every such one
    ///   for `u ∈ [0, 1)`; other copies are mapped by the edge taps);
    /// * the clamping modes: `floor(x)` of [`first_tap`](Self::first_tap), any
    ///   `i32` as `u32` (a negative tap is above `n − 1`).
    #[inline(always)]
    pub(crate) fn pow2_first_tap(self, coord: TexCoord, n: u32, c: u32, bits: u32) -> (u32, u32) {
        match self {
            Self::Wrap => {
                let (i0, _, f) = pow2_wrap_taps(coord, n, n.wrapping_sub(1), c, bits);
                (i0, f)
            }
            Self::Mirror => pow2_mirror_tap(coord, n, bits),
            _ => {
                let (i, f) = self.first_tap(coord, n, bits);
                (i as u32, f)
            }
        }
    }

    /// The taps of an axis from its first tap `i` and weight `f`
    /// ([`pow2_first_tap`](Self::pow2_first_tap)) on the side `n = 2^k`,
    /// `m = n − 1`, `s = 31 − k`: wrap `[i, (i + 1) & m]`; mirror by
    /// [`mirror_fold`] of `i` and `i + 1`; the clamping modes as
    /// [`taps`](Self::taps) maps them (inside: themselves, else
    /// [`map`](Self::map)); with `MASKED`, clamp-to-border as `i & m`,
    /// `(i + 1) & m` with a range test per tap for the border flags.
    #[inline(always)]
    pub(crate) fn pow2_edge_taps<const MASKED: bool>(
        self,
        i: u32,
        f: u32,
        n: u32,
        m: u32,
        s: u32,
    ) -> AxisTaps {
        let i1 = i.wrapping_add(1);
        let (i, border) = match self {
            Self::Wrap => ([i, i1 & m], [false; 2]),
            Self::Mirror => ([mirror_fold(i, m, s), mirror_fold(i1, m, s)], [false; 2]),
            // A negative tap as `u32` is above any side.
            Self::ClampToBorder if MASKED => ([i & m, i1 & m], [i >= n, i1 >= n]),
            _ if i < m => ([i, i1], [false; 2]),
            _ => {
                let (i0, b0) = self.map(i as i32, n);
                let (i1, b1) = self.map(i1 as i32, n);
                ([i0, i1], [b0, b1])
            }
        };
        AxisTaps { i, f, border }
    }
}

/// The first tap of [`Mirror`](AddressMode::Mirror) on a power-of-two
/// side `n = 2^k` and its weight (`bits` bits). With `h` the integer part
/// of `u` and `lo` its fractional bits, the position
/// `x = u·n − ½ + 2^−(bits+1)` in 32.32 fixed point is
/// `lo·n + h·n·2³² + 2^(31−bits) − 2³¹`: one 32×32→64-bit
/// multiply-accumulate (`umlal` on the M4) onto the constant
/// `−2³² + 2³¹ + 2^(31−bits)`, then `h·n` added to the high word (`mla`).
/// The tap `j` is the true one modulo 2³², of which only `j mod 2n`
/// decides the texel ([`mirror_fold`]; `2n` divides 2³²). For
/// `u ∈ [0, 1)` it is in `[−1, n − 1]`. The weight is the top `bits`
/// bits of the low word.
#[inline(always)]
pub(crate) fn pow2_mirror_tap(coord: TexCoord, n: u32, bits: u32) -> (u32, u32) {
    let b = coord.to_bits();
    let h = (b >> 32) as u32;
    // The three terms share no bit (`1 ≤ bits ≤ 31`): `+` packs them.
    let start = (u64::from(u32::MAX) << 32) + u64::from((1u32 << 31) + (1 << (31 - bits)));
    let p = u64::from(b as u32)
        .wrapping_mul(u64::from(n))
        .wrapping_add(start);
    let j = ((p >> 32) as u32).wrapping_add(h.wrapping_mul(n));
    (j, (p as u32) >> (32 - bits))
}

/// The texel of a mirrored tap `j` (its value modulo `2n` decides) on a
/// side `n = 2^k`, `m = n − 1`, `s = 31 − k`: a tap of the second copy
/// (bit `k` set) maps to `2n − 1 − (j mod 2n)`, i.e. its low `k` bits
/// inverted: `(j ^ (bit k of j ? all ones : 0)) & m`, the sign of
/// `j << s` spread by an arithmetic shift.
#[inline(always)]
pub(crate) fn mirror_fold(j: u32, m: u32, s: u32) -> u32 {
    (j ^ ((j.wrapping_shl(s) as i32 >> 31) as u32)) & m
}

/// The bilinear taps of one axis: texel indices `i₀, i₁` (each `< size`),
/// the weight of `i₁` and which of the two read the border colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct AxisTaps {
    pub(crate) i: [u32; 2],
    pub(crate) f: u32,
    pub(crate) border: [bool; 2],
}

/// An address mode as a type: what a [`Sampler`](crate::texture::Sampler)
/// compiles in for one axis. The five static modes are zero-sized;
/// [`AnyAxis`] carries its mode as a value (the run-time form's fallback,
/// matched once per axis and level, not per texel).
pub trait Axis: Copy + Default + core::fmt::Debug + Send + Sync + 'static {
    /// Whether this axis may read the border colour (only
    /// [`ClampToBorder`] and [`AnyAxis`]): without it the sampler has no
    /// border selects.
    const MAY_BORDER: bool;
    /// Whether this axis wraps whatever the run-time state (only the
    /// [`Wrap`] type): a sampler compiles its wrap-only shortcuts (the
    /// anisotropic probe loop in 32-bit words) for such keys alone.
    const ALWAYS_WRAP: bool;
    /// The mode of this axis.
    fn mode(self) -> AddressMode;
    /// The axis for `mode`, `None` when this type cannot address so.
    fn from_mode(mode: AddressMode) -> Option<Self>;
}

macro_rules! static_axes {
    ($($(#[$doc:meta])* $name:ident = $mode:ident, $border:literal;)*) => {$(
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
        pub struct $name;

        impl Axis for $name {
            const MAY_BORDER: bool = $border;
            const ALWAYS_WRAP: bool = matches!(AddressMode::$mode, AddressMode::Wrap);
            #[inline(always)]
            fn mode(self) -> AddressMode {
                AddressMode::$mode
            }
            fn from_mode(mode: AddressMode) -> Option<Self> {
                (mode == AddressMode::$mode).then_some(Self)
            }
        }
    )*};
}

static_axes! {
    /// [`AddressMode::Wrap`] as a type.
    Wrap = Wrap, false;
    /// [`AddressMode::Mirror`] as a type.
    Mirror = Mirror, false;
    /// [`AddressMode::ClampToEdge`] as a type.
    ClampToEdge = ClampToEdge, false;
    /// [`AddressMode::MirrorOnce`] as a type.
    MirrorOnce = MirrorOnce, false;
    /// [`AddressMode::ClampToBorder`] as a type.
    ClampToBorder = ClampToBorder, true;
}

/// Any address mode, chosen at run time (the
/// [`DynSampler`](crate::texture::sampler::dynamic::DynSampler)'s
/// fallback for mixed modes): the mode is matched once per axis and
/// level of a sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AnyAxis(pub AddressMode);

impl Axis for AnyAxis {
    const MAY_BORDER: bool = true;
    const ALWAYS_WRAP: bool = false;
    #[inline(always)]
    fn mode(self) -> AddressMode {
        self.0
    }
    fn from_mode(mode: AddressMode) -> Option<Self> {
        Some(Self(mode))
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::texture::storage::level::wrap_constant;
    use proptest::prelude::*;

    /// Reference: the Vulkan wrapping operation on an integer index, in
    /// plain i64 arithmetic written independently.
    fn reference_index(mode: AddressMode, i: i64, size: i64) -> Option<i64> {
        match mode {
            AddressMode::Wrap => Some(((i % size) + size) % size),
            AddressMode::Mirror => {
                // Vulkan: mirror(a) = a ≥ 0 ? a : −(1 + a);
                // (size − 1) − mirror((i mod 2size) − size)
                let m = ((i % (2 * size)) + 2 * size) % (2 * size) - size;
                let mir = if m >= 0 { m } else { -(1 + m) };
                Some(size - 1 - mir)
            }
            AddressMode::ClampToEdge => Some(i.clamp(0, size - 1)),
            AddressMode::MirrorOnce => {
                let mir = if i >= 0 { i } else { -(1 + i) };
                Some(mir.clamp(0, size - 1))
            }
            AddressMode::ClampToBorder => (0..size).contains(&i).then_some(i),
        }
    }

    #[test]
    fn index_reference_vectors() {
        use AddressMode::*;
        // (mode, i, size, expected)
        let v: [(AddressMode, i32, u32, Option<u32>); 14] = [
            (Wrap, -1, 4, Some(3)),
            (Wrap, 4, 4, Some(0)),
            (Mirror, -1, 4, Some(0)),
            (Mirror, 4, 4, Some(3)),
            (Mirror, 8, 4, Some(0)),
            (Mirror, -5, 4, Some(3)),
            (ClampToEdge, -7, 4, Some(0)),
            (ClampToEdge, 9, 4, Some(3)),
            (MirrorOnce, -1, 4, Some(0)),
            (MirrorOnce, -3, 4, Some(2)),
            (MirrorOnce, -9, 4, Some(3)),
            (ClampToBorder, -1, 4, None),
            (ClampToBorder, 4, 4, None),
            (ClampToBorder, 3, 4, Some(3)),
        ];
        for (mode, i, size, want) in v {
            assert_eq!(mode.index(i, size), want, "{mode:?} {i} {size}");
        }
        for (n, mode) in AddressMode::ALL.iter().enumerate() {
            assert_eq!(AddressMode::from_index(n as u8), Some(*mode));
        }
        assert_eq!(AddressMode::from_index(5), None);
    }

    #[test]
    fn mirror_coordinates() {
        let c = |x: f64| TexCoord::from_num(x);
        // 4 texels: u = 1.1 mirrors to 0.9 → texel 3; u = −0.1 → 0.1 → 0.
        assert_eq!(AddressMode::Mirror.nearest(c(1.1), 4), Some(3));
        assert_eq!(AddressMode::Mirror.nearest(c(-0.1), 4), Some(0));
        assert_eq!(AddressMode::Mirror.nearest(c(2.1), 4), Some(0));
        assert_eq!(AddressMode::MirrorOnce.nearest(c(-0.3), 4), Some(1));
        assert_eq!(AddressMode::MirrorOnce.nearest(c(-7.0), 4), Some(3));
        assert_eq!(AddressMode::ClampToBorder.nearest(c(1.0), 4), None);
        // Bilinear at u = 0 with mirror: texels −1 → 0 and 0, weight ½.
        assert_eq!(
            AddressMode::Mirror.linear(c(0.0), 4),
            ([Some(0), Some(0)], 2048)
        );
        assert_eq!(
            AddressMode::ClampToBorder.linear(c(0.0), 4),
            ([None, Some(0)], 2048)
        );
    }

    proptest! {
        #[test]
        fn index_matches_reference(m in 0u8..5, i in any::<i32>(), size in 1u32..=(1 << 15)) {
            let mode = AddressMode::from_index(m).unwrap();
            let got = mode.index(i, size).map(i64::from);
            prop_assert_eq!(got, reference_index(mode, i64::from(i), i64::from(size)));
        }

        /// The reduction never changes the addressed texel: compare with
        /// the unreduced f64 position for |u| ≤ 10⁴ (exact in f64).
        #[test]
        fn reduction_is_exact(m in 0u8..5, u in -1.0e4f64..1.0e4, size in 1u32..=4096) {
            let mode = AddressMode::from_index(m).unwrap();
            let coord = TexCoord::from_num(u);
            let exact = coord.to_num::<f64>() * f64::from(size);
            let want = reference_index(mode, exact.floor() as i64, i64::from(size)).map(|x| x as u32);
            prop_assert_eq!(mode.nearest(coord, size), want);
            let x = exact - 0.5;
            let (pair, f) = mode.linear(coord, size);
            let w = ((x - x.floor()) * 4096.0).round() as u32;
            // Rounding the weight can carry into the next index: compare
            // the pair only when it does not.
            if w < 4096 {
                let i0 = x.floor() as i64;
                let r0 = reference_index(mode, i0, i64::from(size)).map(|x| x as u32);
                let r1 = reference_index(mode, i0 + 1, i64::from(size)).map(|x| x as u32);
                prop_assert_eq!(pair, [r0, r1]);
                // The weight matters only between two different texels
                // (clamping reductions may change it otherwise).
                if r0 != r1 {
                    prop_assert_eq!(f, w);
                }
            }
        }
    }

    /// The power-of-two forms (`pow2_taps`: wrap by one multiply, mirror
    /// by a multiply-accumulate and an XOR, the clamping modes decided
    /// once per axis) equal the general taps for every mode, side `2^k`,
    /// weight width, and random, seam and edge coordinates; so does
    /// `pow2_taps::<true>` but for the indices of border taps, which stay
    /// inside the level.
    #[test]
    fn pow2_taps_equal_general_taps() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        for m in AddressMode::ALL {
            for k in 0..=15u32 {
                let size = 1u32 << k;
                for n in 0..if cfg!(miri) { 10 } else { 2000u64 } {
                    x ^= x << 13;
                    x ^= x >> 7;
                    x ^= x << 17;
                    // Random bits, and the seam/edge values of this size.
                    let edge = (n % (4 * u64::from(size) + 1)) << (31 - k);
                    for bits in [
                        x as i64,
                        edge as i64,
                        -(edge as i64),
                        (edge as i64) + (3 << 32),
                        (x as i64) >> (n % 40),
                    ] {
                        let c = TexCoord::from_bits(bits);
                        for b in [8, 12, 16] {
                            let want = m.taps(c, size, b);
                            let wc = wrap_constant(k, b);
                            assert_eq!(
                                m.pow2_taps::<false>(c, size, size - 1, 31 - k, wc, b),
                                want,
                                "{m:?} k {k} bits {bits:#x} weight bits {b}"
                            );
                            // The masked form: the same flags, weight and
                            // inside indices; a border tap's index is any
                            // texel of the level.
                            let got = m.pow2_taps::<true>(c, size, size - 1, 31 - k, wc, b);
                            let inside =
                                |t: AxisTaps| [0, 1].map(|k| (!t.border[k]).then_some(t.i[k]));
                            assert_eq!(
                                (got.border, got.f, inside(got)),
                                (want.border, want.f, inside(want)),
                                "{m:?} k {k} bits {bits:#x} weight bits {b}"
                            );
                            assert!(
                                got.i.iter().all(|&i| i < size),
                                "{m:?} k {k} bits {bits:#x}"
                            );
                            // A first tap below `n − 1` is an inside
                            // footprint axis: both taps their own texels,
                            // no border; for wrap and the clamping modes
                            // that is every inside one, for mirror every
                            // one with `u ∈ [0, 1)`.
                            let (i, f) = m.pow2_first_tap(c, size, wc, b);
                            assert_eq!(f, want.f, "{m:?} k {k} bits {bits:#x}");
                            // Mirror's first tap is the unreduced one,
                            // `floor(u·n − ½ + 2^−(b+1))` modulo 2³² (in
                            // i128 from the coordinate's bits): only a
                            // footprint of the first copy is inside.
                            if m == AddressMode::Mirror {
                                let x = i128::from(bits) * i128::from(size) - (1 << 31)
                                    + (1 << (31 - b));
                                assert_eq!(
                                    i,
                                    (x >> 32) as u32,
                                    "k {k} bits {bits:#x} weight bits {b}"
                                );
                            }
                            if i < size - 1 {
                                assert_eq!(want.i, [i, i + 1], "{m:?} k {k} bits {bits:#x}");
                                assert_eq!(want.border, [false; 2]);
                            }
                            // And every footprint axis inside is found so
                            // (mirror: for `u ∈ [0, 1)`): the first tap of
                            // the reduced position, in i64.
                            let x = m.reduce(c) * i64::from(size) - (1 << 31) + (1 << (31 - b));
                            let p = x >> 32;
                            let p = if m == AddressMode::Wrap {
                                p.rem_euclid(i64::from(size))
                            } else {
                                p
                            };
                            if (0..i64::from(size) - 1).contains(&p)
                                && (m != AddressMode::Mirror || (0..1 << 32).contains(&bits))
                            {
                                assert!(i < size - 1, "{m:?} k {k} bits {bits:#x}");
                            }
                        }
                    }
                }
            }
        }
    }

    /// The 32-bit tap computation (`scaled` + `map`) selects the same
    /// texels with the same weights as the definition: the exact reduction
    /// (`reduce`), `x = u·size − ½ + round` in 64 bits and [`index`]; where
    /// both taps of an axis land on the same texel (or both on the border)
    /// the weight is free (it cannot change the result).
    #[test]
    fn fast_taps_equal_definition() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        for m in AddressMode::ALL {
            for size in [1u32, 2, 3, 5, 8, 13, 64, 100, 1 << 15] {
                for n in 0..if cfg!(miri) { 30 } else { 3000u32 } {
                    x ^= x << 13;
                    x ^= x >> 7;
                    x ^= x << 17;
                    let edge = i64::from(n % 41) - 20;
                    for bits in [
                        x as i64,
                        (x as i64) >> (n % 40),
                        edge << 31,
                        (edge << 32) / i64::from(size),
                    ] {
                        let c = TexCoord::from_bits(bits);
                        for wb in [8, 12, 16] {
                            let xr = m.reduce(c) * i64::from(size) - (1 << 31) + (1 << (31 - wb));
                            let i = (xr >> 32) as i32;
                            let want = [m.index(i, size), m.index(i + 1, size)];
                            let f = ((xr & 0xFFFF_FFFF) as u32) >> (32 - wb);
                            let t = m.taps(c, size, wb);
                            let got = [0, 1].map(|k| (!t.border[k]).then_some(t.i[k]));
                            assert_eq!(got, want, "{m:?} {size} {bits:#x} {wb}");
                            if want[0] != want[1] {
                                assert_eq!(t.f, f, "{m:?} {size} {bits:#x} {wb}");
                            }
                        }
                        let i = ((m.reduce(c) * i64::from(size)) >> 32) as i32;
                        let (j, b) = m.nearest_tap(c, size);
                        assert_eq!(
                            (!b).then_some(j),
                            m.index(i, size),
                            "{m:?} {size} {bits:#x}"
                        );
                    }
                }
            }
        }
    }
}
