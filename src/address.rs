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

use crate::bilerp::WEIGHT_BITS;
use crate::filter::TexCoord;

indexed_enum! {
    /// What a sampler does with coordinates outside `[0, 1)`, per axis.
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
}

impl AddressMode {
    /// `u` reduced (exactly) to the range that selects the same texels,
    /// in I32F32 bits: `[0, 2³²)` (wrap), `[0, 2³³)` (mirror),
    /// `[−2³², 2³³]` (clamp, border), `[−2³³, 2³³]` (mirror once).
    #[inline(always)]
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
        let n = size.clamp(1, crate::mip::MAX_SIZE) as i32;
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
        let x = self.reduce(coord) * i64::from(size);
        self.index((x >> 32) as i32, size)
    }

    /// Bilinear pair on one axis: `([i₀, i₁], weight of i₁ in 1/4096)`,
    /// addressed (`None` = border), with `x = u·size − ½` and the weight
    /// rounded to nearest 1/4096.
    #[inline]
    #[must_use]
    pub fn linear(self, coord: TexCoord, size: u32) -> ([Option<u32>; 2], u32) {
        // Round the 12-bit weight to nearest: + 2⁻¹³ texel.
        const ROUND: i64 = 1 << (31 - WEIGHT_BITS);
        let x = self.reduce(coord) * i64::from(size) - (1 << 31) + ROUND;
        let i = (x >> 32) as i32;
        let f = (((x & 0xFFFF_FFFF) as u32) >> (32 - WEIGHT_BITS)) & ((1 << WEIGHT_BITS) - 1);
        (
            [self.index(i, size), self.index(i.saturating_add(1), size)],
            f,
        )
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
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
}
