//! Texture storage: how texels sit in caller memory and come out as RGBA8.
//!
//! | module | holds |
//! |---|---|
//! | [`mip`] | [`Geometry`](mip::Geometry), RGBA8 [`Pyramid`](mip::Pyramid)s, in-place generation, the [`TexelSource`](mip::TexelSource) trait |
//! | [`format`] | texel formats as types ([`format::PixelFormat`]) and as values ([`format::TexelFormat`]), colour spaces |
//! | [`level`] | the texel word, the size limits, validated views of power-of-two levels ([`level::LevelView`]) |
//! | [`pow2`] | power-of-two pyramids with validated per-level views ([`pow2::Pow2Pyramid`]): the sampler's direct source |
//! | [`image`] | a texture in any format in caller memory ([`image::Image`]) |
//! | [`bc`] | BC1–BC4 block decoding (the cache's fill path) |
//! | [`cache`] | the texel cache (4×4 blocks, Morton order, LRU) |
//! | [`srgb`] | sRGB decode/encode tables, linear-space pyramids |
//! | [`analysis`] | set-up: the MIP levels a scene can select per texture (trimmed pyramids) and the textures it never samples |

pub mod analysis;
pub mod bc;
#[cfg(feature = "cache")]
pub mod cache;
pub mod format;
// Images decode BC blocks as the texel cache's fill path.
#[cfg(feature = "cache")]
pub mod image;
pub mod level;
pub mod mip;
pub mod pow2;
pub mod srgb;
