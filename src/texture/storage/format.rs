//! Texel formats: how stored texels expand to RGBA8 before filtering.
//!
//! Uncompressed formats are little-endian words with the first-named
//! channel in the most significant bits (Vulkan's `…_PACK16` layouts):
//!
//! | format | bytes | bits (MSB → LSB) | RGBA8 result |
//! |---|---|---|---|
//! | [`Rgba8`](TexelFormat::Rgba8) | 4 | bytes r, g, b, a | as stored |
//! | [`Rgb565`](TexelFormat::Rgb565) | 2 | r5 g6 b5 | `(r, g, b, 255)` |
//! | [`Rgba5551`](TexelFormat::Rgba5551) | 2 | r5 g5 b5 a1 | `(r, g, b, a)` |
//! | [`Rgba4444`](TexelFormat::Rgba4444) | 2 | r4 g4 b4 a4 | `(r, g, b, a)` |
//! | [`La8`](TexelFormat::La8) | 2 | bytes l, a | `(l, l, l, a)` |
//! | [`L8`](TexelFormat::L8) | 1 | byte l | `(l, l, l, 255)` |
//! | [`A8`](TexelFormat::A8) | 1 | byte a | `(0, 0, 0, a)` |
//! | [`Bc1`](TexelFormat::Bc1) … [`Bc4`](TexelFormat::Bc4) | 8 / 16 / 16 / 8 per 4×4 block | see [`crate::texture::storage::bc`] | |
//!
//! An `n`-bit channel widens to 8 bits by **bit replication** (the value's
//! bits repeated from the top: `x·2^(8−n) | x >> (2n − 8)` for `n ≥ 4`,
//! `255·x` for one bit), the UNORM expansion the D3D and Vulkan conversion
//! rules allow for hardware; for 1, 2, 4 and 8 bits it equals the exact
//! `round(x·255/(2ⁿ − 1))`, for 5 and 6 bits it differs from it by at most
//! one LSB (tested).
//!
//! [`Format`] adds the colour space: sRGB variants exist for the 8-bit
//! colour formats ([`Rgba8`](TexelFormat::Rgba8), [`La8`](TexelFormat::La8),
//! [`L8`](TexelFormat::L8)) and BC1–BC3 (as in Vulkan); their RGB channels
//! are decoded to linear by [`crate::texture::storage::srgb`] before filtering, alpha never.

use core::fmt;

/// Storage format of a texture's texels (the C ABI's `RmFormat`, the
/// pixel format of an `RmImage`).
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum TexelFormat {
    /// 8 bits per channel, bytes r, g, b, a in memory (as a 32-bit word
    /// on a little-endian core: red in bits 0–7, alpha in bits 24–31).
    #[default]
    Rgba8 = 0,
    /// 16 bits little-endian: red 5, green 6, blue 5 (alpha 255).
    Rgb565 = 1,
    /// 16 bits: red 5, green 5, blue 5, alpha 1.
    Rgba5551 = 2,
    /// 16 bits: 4 bits per channel.
    Rgba4444 = 3,
    /// Luminance and alpha, 8 bits each.
    La8 = 4,
    /// Luminance, 8 bits.
    L8 = 5,
    /// Alpha, 8 bits (colour 0).
    A8 = 6,
    /// BC1 (DXT1): 8 bytes per 4×4 block, RGB + 1-bit alpha.
    Bc1 = 7,
    /// BC2 (DXT3): 16 bytes per block, explicit 4-bit alpha + BC1 colour.
    Bc2 = 8,
    /// BC3 (DXT5): 16 bytes per block, interpolated alpha + BC1 colour.
    Bc3 = 9,
    /// BC4: 8 bytes per block, one interpolated channel (red).
    Bc4 = 10,
}

indexed_enum! { TexelFormat: Rgba8, Rgb565, Rgba5551, Rgba4444, La8, L8, A8, Bc1, Bc2, Bc3, Bc4 }

impl TexelFormat {
    /// Whether texels are stored in 4×4 compressed blocks (BC1–BC4).
    #[must_use]
    pub const fn is_block_compressed(self) -> bool {
        matches!(self, Self::Bc1 | Self::Bc2 | Self::Bc3 | Self::Bc4)
    }

    /// Bytes per texel (uncompressed) or per 4×4 block (BC).
    #[must_use]
    pub const fn unit_bytes(self) -> u32 {
        match self {
            Self::Rgba8 => 4,
            Self::Rgb565 | Self::Rgba5551 | Self::Rgba4444 | Self::La8 => 2,
            Self::L8 | Self::A8 => 1,
            Self::Bc1 | Self::Bc4 => 8,
            Self::Bc2 | Self::Bc3 => 16,
        }
    }

    /// Whether an sRGB variant exists (8-bit colour formats and BC1–BC3).
    #[must_use]
    pub const fn has_srgb(self) -> bool {
        matches!(
            self,
            Self::Rgba8 | Self::La8 | Self::L8 | Self::Bc1 | Self::Bc2 | Self::Bc3
        )
    }

    /// Expands one stored uncompressed texel (its bytes as a little-endian
    /// word, `unit_bytes` long, higher bytes ignored) to RGBA8 by bit
    /// replication. BC formats return 0 (use [`crate::texture::storage::bc`]).
    #[inline]
    #[must_use]
    pub fn decode(self, raw: u32) -> Texel {
        let rgba = |r: u32, g: u32, b: u32, a: u32| r | (g << 8) | (b << 16) | (a << 24);
        match self {
            Self::Rgba8 => raw,
            Self::Rgb565 => rgba(widen5(raw >> 11), widen6(raw >> 5), widen5(raw), 0xFF),
            Self::Rgba5551 => rgba(
                widen5(raw >> 11),
                widen5(raw >> 6),
                widen5(raw >> 1),
                (raw & 1) * 0xFF,
            ),
            Self::Rgba4444 => rgba(
                widen4(raw >> 12),
                widen4(raw >> 8),
                widen4(raw >> 4),
                widen4(raw),
            ),
            Self::La8 => {
                let l = raw & 0xFF;
                rgba(l, l, l, (raw >> 8) & 0xFF)
            }
            Self::L8 => {
                let l = raw & 0xFF;
                rgba(l, l, l, 0xFF)
            }
            Self::A8 => (raw & 0xFF) << 24,
            Self::Bc1 | Self::Bc2 | Self::Bc3 | Self::Bc4 => 0,
        }
    }

    /// Quantizes an RGBA8 texel to this format (round to nearest per
    /// channel, `round(x·(2ⁿ − 1)/255)`; luminance = red): set-up work for
    /// making test data and uploads, the inverse of [`decode`](Self::decode)
    /// up to quantization. BC formats return 0 (encoders live in the host
    /// harness).
    #[must_use]
    pub fn encode(self, t: Texel) -> u32 {
        let [r, g, b, a] = t.to_le_bytes().map(u32::from);
        let q = |x: u32, bits: u32| (x * ((1 << bits) - 1) + 127) / 255;
        // Each field is below 2^bits (`q(x, bits) ≤ 2^bits − 1` for
        // `x ≤ 255`), so the fields share no bit and the sum is the packed
        // word; `+` rather than `|` makes a wrong operator change the word.
        match self {
            Self::Rgba8 => t,
            Self::Rgb565 => (q(r, 5) << 11) + (q(g, 6) << 5) + q(b, 5),
            Self::Rgba5551 => (q(r, 5) << 11) + (q(g, 5) << 6) + (q(b, 5) << 1) + q(a, 1),
            Self::Rgba4444 => (q(r, 4) << 12) + (q(g, 4) << 8) + (q(b, 4) << 4) + q(a, 4),
            Self::La8 => r + (a << 8),
            Self::L8 => r,
            Self::A8 => a,
            Self::Bc1 | Self::Bc2 | Self::Bc3 | Self::Bc4 => 0,
        }
    }
}

/// A texel format as a type: what an [`Image`](crate::texture::storage::image::Image)
/// decodes with. The marker types ([`Rgba8`], [`Rgb565`], … [`Bc4`]) are
/// zero-sized and give their [`TexelFormat`] as a constant, so an image of
/// one of them carries that format's decode alone; [`AnyFormat`] holds the
/// format as a value (the run-time form: the decode is a `match`, which a
/// [`TexelCache`](crate::texture::storage::cache::TexelCache) in front of
/// the image runs once per 4×4 block fill instead of per texel).
///
/// # Example
/// ```
/// use raymip::texture::storage::format::{A8, Bc1, Bc2, Bc3, Bc4, L8, La8, PixelFormat};
/// use raymip::texture::storage::format::{Rgb565, Rgba4444, Rgba5551, Rgba8, TexelFormat};
/// // Bytes per texel (per 4×4 block for BC), from the layouts in the module docs.
/// assert_eq!(Rgba8.texel().unit_bytes(), 4);
/// for two in [Rgb565.texel(), Rgba5551.texel(), Rgba4444.texel(), La8.texel()] {
///     assert_eq!(two.unit_bytes(), 2);
/// }
/// assert_eq!((L8.texel().unit_bytes(), A8.texel().unit_bytes()), (1, 1));
/// assert_eq!((Bc1.texel().unit_bytes(), Bc4.texel().unit_bytes()), (8, 8));
/// assert_eq!((Bc2.texel().unit_bytes(), Bc3.texel().unit_bytes()), (16, 16));
/// assert_eq!(Bc3.texel(), TexelFormat::Bc3);
/// // RGBA4444 widens each 4-bit channel by bit replication (x·17):
/// // 0x1234 → r 0x11, g 0x22, b 0x33, a 0x44.
/// assert_eq!(Rgba4444.texel().decode(0x1234), 0x4433_2211);
/// ```
pub trait PixelFormat: Copy + fmt::Debug + Send + Sync + 'static {
    /// The format.
    fn texel(self) -> TexelFormat;
}

/// Any [`TexelFormat`], chosen at run time.
///
/// # Example
/// ```
/// use raymip::texture::storage::format::{AnyFormat, PixelFormat, Rgb565, TexelFormat};
/// // A format read from a texture header at run time.
/// let header_byte = 5;
/// let any = AnyFormat(TexelFormat::from_index(header_byte).ok_or("bad format")?);
/// assert_eq!(any.texel(), TexelFormat::L8);
/// // The same decode as the marker type of that format.
/// assert_eq!(AnyFormat(TexelFormat::Rgb565).texel(), Rgb565.texel());
/// # Ok::<(), &str>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct AnyFormat(pub TexelFormat);

impl PixelFormat for AnyFormat {
    #[inline(always)]
    fn texel(self) -> TexelFormat {
        self.0
    }
}

macro_rules! pixel_formats {
    ($($name:ident),*) => {$(
        #[doc = concat!("[`TexelFormat::", stringify!($name), "`] as a type.")]
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
        pub struct $name;

        impl PixelFormat for $name {
            #[inline(always)]
            fn texel(self) -> TexelFormat {
                TexelFormat::$name
            }
        }
    )*};
}

pixel_formats!(
    Rgba8, Rgb565, Rgba5551, Rgba4444, La8, L8, A8, Bc1, Bc2, Bc3, Bc4
);

/// 4-bit channel (low bits of `x`) to 8 bits: `x·17`.
#[inline(always)]
fn widen4(x: u32) -> u32 {
    let x = x & 0xF;
    (x << 4) | x
}

/// 5-bit channel (low bits of `x`) to 8 bits by bit replication.
#[inline(always)]
pub(crate) const fn widen5(x: u32) -> u32 {
    let x = x & 0x1F;
    (x << 3) | (x >> 2)
}

/// 6-bit channel (low bits of `x`) to 8 bits by bit replication.
#[inline(always)]
pub(crate) const fn widen6(x: u32) -> u32 {
    let x = x & 0x3F;
    (x << 2) | (x >> 4)
}

/// The RGB565 expansion split by stored byte, 2 KiB: `RGB565_SPLIT[0][lo]
/// | RGB565_SPLIT[1][hi]` is [`TexelFormat::decode`] of the texel whose
/// low byte is `lo` and high byte `hi` (tested for all 65 536). Bit
/// replication is separable by byte: green's three low bits (in `lo`)
/// land in bits 2–4 of the green byte, its three high bits (in `hi`) in
/// bits 5–7 and, replicated, 0–1; no other bit of a channel depends on
/// both bytes, so the two words never share a set bit but alpha (255 in
/// both). Two loads and an OR per texel instead of three extractions and
/// replications (`Image`'s footprint of RGB565 levels and the 16-bit
/// level views, [`ViewFormat`] of [`Rgb565`]).
pub(crate) static RGB565_SPLIT: [[Texel; 256]; 2] = {
    let mut t = [[0; 256]; 2];
    let mut b = 0;
    while b < 256 {
        let (lo, hi) = (b as u32, (b as u32) << 8);
        t[0][b] = widen6(lo >> 5) << 8 | widen5(lo) << 16 | 0xFF << 24;
        t[1][b] = widen5(hi >> 11) | widen6(hi >> 5) << 8 | 0xFF << 24;
        b += 1;
    }
    t
};

/// One RGBA8888 texel: `u32::from_le_bytes([r, g, b, a])`.
///
/// # Example
/// ```
/// use raymip::Texel;
/// let t: Texel = u32::from_le_bytes([0x10, 0x20, 0x30, 0xFF]); // r, g, b, a
/// assert_eq!(t, 0xFF30_2010);
/// assert_eq!((t & 0xFF, t >> 24), (0x10, 0xFF)); // red low, alpha high
/// ```
pub type Texel = u32;

/// How a [`LevelView`](crate::texture::storage::level::LevelView) stores its texels and reads one as RGBA8: the
/// format marker of its key ([`Rgba8`], the default: a [`Texel`] as it
/// is; [`Rgb565`]: two bytes expanded by a split table).
pub trait ViewFormat: Copy + fmt::Debug + 'static {
    /// One stored texel (its size is the view's step per column).
    type Stored: Copy + Send + Sync;
    /// The RGBA8 texel of `s`.
    fn expand(s: Self::Stored) -> Texel;
}

impl ViewFormat for Rgba8 {
    type Stored = Texel;
    #[inline(always)]
    fn expand(s: Texel) -> Texel {
        s
    }
}

/// An RGB565 level view ([`LevelView<'_, Rgb565>`](crate::texture::storage::level::LevelView))
/// stores a texel as its two bytes, little-endian (the image's layout, no
/// alignment needed) and expands it by the 2 KiB table of the bytes'
/// parts (bit replication is separable by byte): two table loads and an
/// OR.
impl ViewFormat for Rgb565 {
    type Stored = [u8; 2];
    #[inline(always)]
    fn expand([lo, hi]: [u8; 2]) -> Texel {
        let [l, h] = &RGB565_SPLIT;
        l[usize::from(lo)] | h[usize::from(hi)]
    }
}

/// Colour space of a texture's colour channels. Example: [`Format`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ColorSpace {
    /// Values are linear (UNORM).
    #[default]
    Linear,
    /// RGB are sRGB-encoded (decoded to linear before filtering); alpha is
    /// linear.
    Srgb,
}

/// A texel format with its colour space, validated.
///
/// # Example
/// ```
/// use raymip::texture::storage::format::{ColorSpace, Format, NoSrgbVariant, TexelFormat};
/// let albedo = Format::new(TexelFormat::Bc1, ColorSpace::Srgb)?;
/// assert_eq!((albedo.texel(), albedo.space()), (TexelFormat::Bc1, ColorSpace::Srgb));
/// assert_eq!(Format::linear(TexelFormat::Rgb565).space(), ColorSpace::Linear);
/// // RGB565 exists as UNORM only (as in Vulkan).
/// let err = Format::new(TexelFormat::Rgb565, ColorSpace::Srgb).unwrap_err();
/// assert_eq!(err, NoSrgbVariant(TexelFormat::Rgb565));
/// assert_eq!(err.to_string(), "Rgb565 has no sRGB variant (only RGBA8, LA8, L8, BC1-BC3)");
/// # Ok::<(), NoSrgbVariant>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Format {
    texel: TexelFormat,
    space: ColorSpace,
}

/// A format/colour-space pair that does not exist. Example: [`Format`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NoSrgbVariant(pub TexelFormat);

impl fmt::Display for NoSrgbVariant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:?} has no sRGB variant (only RGBA8, LA8, L8, BC1-BC3)",
            self.0
        )
    }
}

impl core::error::Error for NoSrgbVariant {}

impl Format {
    /// `texel` in colour space `space`.
    ///
    /// # Errors
    /// [`NoSrgbVariant`] for sRGB with a format that has none
    /// ([`TexelFormat::has_srgb`]).
    pub const fn new(texel: TexelFormat, space: ColorSpace) -> Result<Self, NoSrgbVariant> {
        if matches!(space, ColorSpace::Srgb) && !texel.has_srgb() {
            return Err(NoSrgbVariant(texel));
        }
        Ok(Self { texel, space })
    }

    /// The linear (UNORM) variant of `texel`.
    #[must_use]
    pub const fn linear(texel: TexelFormat) -> Self {
        Self {
            texel,
            space: ColorSpace::Linear,
        }
    }

    /// The storage format.
    #[must_use]
    pub const fn texel(&self) -> TexelFormat {
        self.texel
    }

    /// The colour space.
    #[must_use]
    pub const fn space(&self) -> ColorSpace {
        self.space
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use proptest::prelude::*;

    /// Reference vectors worked out by hand from the bit layouts.
    #[test]
    fn decode_reference_vectors() {
        let t = |r: u8, g: u8, b: u8, a: u8| u32::from_le_bytes([r, g, b, a]);
        let v = [
            (TexelFormat::Rgb565, 0xF800, t(255, 0, 0, 255)),
            (TexelFormat::Rgb565, 0x07E0, t(0, 255, 0, 255)),
            // r = 1 → 0b00001_000 | 0b00 = 8; g = 1 → 4; b = 0b10000 → 0x84.
            (TexelFormat::Rgb565, 0x0830, t(8, 4, 0x84, 255)),
            (TexelFormat::Rgba5551, 0x0001, t(0, 0, 0, 255)),
            (TexelFormat::Rgba5551, 0xFFFE, t(255, 255, 255, 0)),
            (TexelFormat::Rgba4444, 0x1234, t(0x11, 0x22, 0x33, 0x44)),
            (TexelFormat::La8, 0x80_40, t(0x40, 0x40, 0x40, 0x80)),
            (TexelFormat::L8, 0x7F, t(0x7F, 0x7F, 0x7F, 255)),
            (TexelFormat::A8, 0x7F, t(0, 0, 0, 0x7F)),
            (TexelFormat::Rgba8, 0x1122_3344, 0x1122_3344),
        ];
        for (f, raw, want) in v {
            assert_eq!(f.decode(raw), want, "{f:?} {raw:#x}");
        }
    }

    #[test]
    fn replication_vs_exact_expansion() {
        for bits in [4u32, 5, 6] {
            let max = (1 << bits) - 1;
            for x in 0..=max {
                let got = match bits {
                    4 => widen4(x),
                    5 => widen5(x),
                    _ => widen6(x),
                };
                let exact = f64::from(x) * 255.0 / f64::from(max);
                // Exact for 4 bits; within one LSB for 5 and 6.
                let limit = if bits == 4 { 0.5 } else { 1.0 };
                assert!((f64::from(got) - exact).abs() <= limit, "{bits} {x}");
            }
        }
        assert_eq!(
            Format::new(TexelFormat::Rgb565, ColorSpace::Srgb),
            Err(NoSrgbVariant(TexelFormat::Rgb565))
        );
        assert!(Format::new(TexelFormat::Bc3, ColorSpace::Srgb).is_ok());
        for (i, f) in TexelFormat::ALL.iter().enumerate() {
            assert_eq!(TexelFormat::from_index(i as u8), Some(*f));
        }
        assert_eq!(TexelFormat::from_index(11), None);
    }

    /// Each format's layout facts from the module docs, written out:
    /// block compression, bytes per texel (per 4×4 block for BC), an sRGB
    /// variant; the run-time and marker forms give the same format, and
    /// a `Format` keeps its parts (an sRGB request without a variant is
    /// refused, with its message).
    #[test]
    fn format_facts_by_hand() {
        use TexelFormat as T;
        let facts = [
            (T::Rgba8, false, 4, true),
            (T::Rgb565, false, 2, false),
            (T::Rgba5551, false, 2, false),
            (T::Rgba4444, false, 2, false),
            (T::La8, false, 2, true),
            (T::L8, false, 1, true),
            (T::A8, false, 1, false),
            (T::Bc1, true, 8, true),
            (T::Bc2, true, 16, true),
            (T::Bc3, true, 16, true),
            (T::Bc4, true, 8, false),
        ];
        assert_eq!(facts.map(|f| f.0), TexelFormat::ALL);
        for (f, bc, bytes, srgb) in facts {
            let got = (f.is_block_compressed(), f.unit_bytes(), f.has_srgb());
            assert_eq!(got, (bc, bytes, srgb), "{f:?}");
            assert_eq!(AnyFormat(f).texel(), f);
            let linear = Format::linear(f);
            assert_eq!((linear.texel(), linear.space()), (f, ColorSpace::Linear));
            match Format::new(f, ColorSpace::Srgb) {
                Ok(s) => assert_eq!((s.texel(), s.space(), srgb), (f, ColorSpace::Srgb, true)),
                Err(e) => assert_eq!((e, srgb), (NoSrgbVariant(f), false)),
            }
        }
        let markers = [
            Rgba8.texel(),
            Rgb565.texel(),
            Rgba5551.texel(),
            Rgba4444.texel(),
            La8.texel(),
            L8.texel(),
            A8.texel(),
            Bc1.texel(),
            Bc2.texel(),
            Bc3.texel(),
            Bc4.texel(),
        ];
        assert_eq!(markers, TexelFormat::ALL);
        assert_eq!(
            std::format!("{}", NoSrgbVariant(T::A8)),
            "A8 has no sRGB variant (only RGBA8, LA8, L8, BC1-BC3)"
        );
    }

    /// The split RGB565 table gives the bit-replicated expansion of
    /// every 16-bit value, and each part alone that of the texel whose
    /// other byte is 0 (alpha 255 in both: `Image` reads the expansion of
    /// 0 past its bytes as `RGB565_SPLIT[0][0]`).
    #[test]
    fn rgb565_split_table_equals_decode() {
        for raw in 0..=u16::MAX {
            let [lo, hi] = raw.to_le_bytes().map(usize::from);
            let want = TexelFormat::Rgb565.decode(u32::from(raw));
            assert_eq!(
                RGB565_SPLIT[0][lo] | RGB565_SPLIT[1][hi],
                want,
                "{raw:#06x}"
            );
        }
        for b in 0..=255u32 {
            let [low, high] = RGB565_SPLIT.map(|t| t[b as usize]);
            assert_eq!(low, TexelFormat::Rgb565.decode(b), "{b}");
            assert_eq!(high, TexelFormat::Rgb565.decode(b << 8), "{b}");
        }
    }

    proptest! {
        /// decode(encode(t)) is within half a quantization step of `t`
        /// (f64), and encode(decode(raw)) = raw for every raw value.
        #[test]
        fn round_trip(t in any::<u32>(), raw in any::<u16>()) {
            for f in TexelFormat::ALL.into_iter().filter(|f| !f.is_block_compressed()) {
                let d = f.decode(f.encode(t));
                let bits: [u32; 4] = match f {
                    TexelFormat::Rgb565 => [5, 6, 5, 0],
                    TexelFormat::Rgba5551 => [5, 5, 5, 1],
                    TexelFormat::Rgba4444 => [4, 4, 4, 4],
                    _ => [8, 8, 8, 8],
                };
                let src = t.to_le_bytes();
                let out = d.to_le_bytes();
                for c in 0..4 {
                    let want = match f {
                        TexelFormat::La8 | TexelFormat::L8 if c < 3 => src[0],
                        TexelFormat::A8 if c < 3 => 0,
                        TexelFormat::L8 | TexelFormat::Rgb565 if c == 3 => 255,
                        _ => src[c],
                    };
                    let step = if bits[c] == 0 { 0.0 } else { 255.0 / f64::from((1u32 << bits[c]) - 1) };
                    // Half a step of quantization plus one LSB of replication.
                    prop_assert!((f64::from(out[c]) - f64::from(want)).abs() <= step / 2.0 + 1.0,
                        "{f:?} {t:#x} channel {c}: {} vs {}", out[c], want);
                }
                let mask = (1u64 << (8 * f.unit_bytes())) - 1;
                let r = u32::from(raw) & mask as u32;
                prop_assert_eq!(f.encode(f.decode(r)), r, "{:?} {:#x}", f, r);
            }
        }
    }
}
