//! The filter mode of a sample: nearest or bilinear within a level, one
//! level or two.
//!
//! The C ABI exports [`Mode`] as it is (`RmMode` in `include/raymip.h`,
//! which cbindgen generates from this file).

/// Filter mode of a sample, numbered as in the `sample` command; the C
/// ABI's `RmMode` (the mode of `rm_sample` and `rm_sample_batch`). The
/// linear-level modes (0 and 3) need the `trilinear` feature, which the C
/// ABI's feature `ffi` includes.
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Bilinear within a level, linear between levels.
    #[cfg(feature = "trilinear")]
    Trilinear = 0,
    /// Bilinear within the nearest level `floor(lod + ½)`.
    BilinearNearestLevel = 1,
    /// Nearest texel of the nearest level.
    Nearest = 2,
    /// Nearest texel in each of two levels, linear between levels.
    #[cfg(feature = "trilinear")]
    NearestTexelLinearLevel = 3,
}

impl Mode {
    /// The mode numbered `n` (0..=3), `None` otherwise (and for 0 and 3
    /// without the `trilinear` feature).
    ///
    /// # Example
    /// ```
    /// use raymip::{Geometry, Lod, Mode, Pyramid, Sampler, TexCoord};
    /// // A 2×1 texture: red 0 and red 200 (alpha 255), texel centres at u = ¼ and ¾.
    /// let texels = [0xFF00_0000u32, 0xFF00_00C8];
    /// let mut sampler = Sampler::clamp(Pyramid::new(Geometry::new(2, 1, 1)?, &texels)?);
    /// let (u, v) = (TexCoord::from_num(0.5), TexCoord::from_num(0.5));
    /// // Halfway between the centres, bilinear weighs both ½: red (0 + 200)/2 = 100.
    /// assert_eq!(sampler.sample(u, v, Lod::ZERO, Mode::BilinearNearestLevel), 0xFF00_0064);
    /// // Nearest takes texel floor(0.5 · 2) = 1.
    /// assert_eq!(sampler.sample(u, v, Lod::ZERO, Mode::Nearest), 0xFF00_00C8);
    /// // Numbered as in the `sample` command.
    /// assert_eq!(Mode::from_index(2), Some(Mode::Nearest));
    /// assert_eq!(Mode::from_index(4), None);
    /// # Ok::<(), raymip::MipError>(())
    /// ```
    #[must_use]
    pub const fn from_index(n: u8) -> Option<Self> {
        match n {
            #[cfg(feature = "trilinear")]
            0 => Some(Self::Trilinear),
            1 => Some(Self::BilinearNearestLevel),
            2 => Some(Self::Nearest),
            #[cfg(feature = "trilinear")]
            3 => Some(Self::NearestTexelLinearLevel),
            _ => None,
        }
    }
}
