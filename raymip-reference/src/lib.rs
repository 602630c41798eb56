//! f64 references of raymip's stages, written from the definitions (papers,
//! API specifications) without the firmware, and the deterministic test
//! generator's f64 draws. The firmware's unit and integration tests, the
//! host harness (`raymip-host`) and the fuzz targets compare the firmware
//! against these; each reference states the definition it follows.
//!
//! Pure f64 and `std`: no dependency on `raymip`, so the firmware's unit
//! tests can use this crate without a second copy of the firmware's types.
//! Where a reference needs a firmware choice (an address mode, a filter
//! mode), it has its own enum numbered as the firmware's.
//!
//! | module | reference of |
//! |---|---|
//! | [`rng`] | f64 draws from the test inputs' generator (`raymip::rng::XorShift64`) |
//! | [`pb`] | `log2 Pb` of a textured triangle (table method set-up) |
//! | [`lod`] | the lod of each method: table, ray cone, ray-differential footprint |
//! | [`geomlod`] | the geometric-LOD parameter of an instance from its depth |
//! | [`envmap`] | environment-map lods and the direction → (u, v) mapping |
//! | [`raydiff`] | ray differentials (Igehy): primary set-up, transfer, reflection, refraction, a textured triangle's footprint and lod with the degenerate classes |
//! | [`sampler`] | the texture sampler: address modes, border, lod bias and clamps, every filter mode, sRGB, anisotropic probes |
#![warn(missing_docs)]

pub mod envmap;
pub mod geomlod;
pub mod lod;
pub mod pb;
pub mod raydiff;
pub mod rng;
pub mod sampler;

pub use rng::Draw;
