//! # raymip
//!
//! Texture level-of-detail, MIP fetch and filtering for the texture unit of a
//! ray-tracing accelerator, in fixed point, for `no_std` controllers
//! (Cortex-M4F, RV32IMAC soft cores).
//!
//! **Design principle:** everything a scene fixes is computed once at set-up
//! (one `log2 Pb` per textured triangle, the MIP pyramid), so that each ray
//! hit costs one logarithm and one subtraction, then a fetch and a filter,
//! all in integer arithmetic that is bit-identical on every target. No heap,
//! no floats on the per-hit path, no panics: saturating arithmetic with
//! documented ranges and small error enums at the API edges.
//!
//! Data flows one way, one folder per part of the pipeline, one module per
//! stage:
//!
//! | part | stage | module | per hit |
//! |---|---|---|---|
//! | set-up | camera pixel spread `γ` | [`setup::camera`] | – |
//! | set-up | per-triangle `log2 Pb` | [`setup::table`] | one table read |
//! | set-up | scene analysis: MIP levels a scene can select per texture, skips | [`setup::analysis`] | — (trimmed pyramids, untextured marks) |
//! | path state | path state across bounces | [`path::raystack`] | `Pl += t`, `w += γ·t` |
//! | path state | ray differentials (feature `raydiff`) | `path::raydiff` | transfer, reflection, refraction per hit |
//! | lod | fixed-point logarithms, ACCURATE and FAST | [`lod::log2`], [`lod::log2_fast`] | leading zeros + table read |
//! | lod | level of detail | [`lod`] | `log2 Pl − log2 Pb` or ray cones |
//! | lod | texture-space footprint and lod from ray differentials (feature `raydiff`) | `lod::raydiff` | four dot products, one logarithm |
//! | lod | environment-map lod and lat-long mapping of rays that leave the scene (feature `envmap`) | `lod::envmap` | one or two logarithms; `(u, v)`: two 3-step CORDIC vectorings, a division and short series in 32-bit words |
//! | texture | storage: pyramids, typed image formats, BC, texel cache, sRGB (set-up) | [`texture::storage`] | level offset + texel index |
//! | texture | addressing per axis (wrap, mirror, clamp, mirror once, border) | [`texture::address`] | one multiply per axis and level |
//! | texture | filter kernels, ACCURATE and FAST | [`texture::kernel`] | 4–8 texel reads, one multiply-accumulate chain |
//! | texture | the one sampler: state, modes, batches, anisotropy, stochastic filtering | [`texture::sampler`] | lod window, level choice, footprint, kernel |
//! | geometric LOD | stochastic geometric LOD (per instance) | [`geomlod`] | depth → LOD, two 8-bit instance masks |
//! | – | per-pixel, per-frame random numbers | [`rng`] | Weyl step + 32-bit hash |
//! | co-processor | custom instructions of a soft core's texture unit (feature `pcpi`) | [`coproc`] | the same bits in hardware |
//! | f32 baseline | the per-hit stages in `f32` (feature `f32`) | `baseline_f32` | – (comparison only) |
//! | C ABI | `extern "C"` functions and `#[repr(C)]` types (feature `ffi`) | `ffi` | – |
//!
//! # Cargo features
//!
//! Each feature compiles a whole stage in; the defaults are what most
//! users need (everything but the C ABI). A scene that needs less sets
//! `default-features = false` and lists what it uses. Code a program does
//! not call is not linked anyway; what a feature removes beyond that is
//! the part every per-hit call carries (the cone update in
//! [`PathState::advance`](path::raystack::PathState::advance), the linear-level
//! arms of [`Sampler::sample`](texture::Sampler::sample)) and API surface.
//! Linked `.text` / `.rodata` per feature set on both targets:
//! `BUDGETS.md`, "Feature sets" (written by `scripts/features`).
//!
//! | feature | default | stage | left out |
//! |---|---|---|---|
//! | `cone` | yes | ray cones: `lod::cone_lod`, `Log2Pb::delta`, cone state on the ray stack | table method only; a [`path::raystack::PathState`] is 16 bytes instead of 32 ([`path::raystack::PATH_STATE_BYTES`]) |
//! | `trilinear` | yes | linear-between-levels modes (`Mode::Trilinear`, `Mode::NearestTexelLinearLevel`) | nearest-level modes only |
//! | `cache` | yes | texel cache, images in any format, BC decoding (`texture::storage::{cache, image}`) | the sampler reads RGBA8 pyramids in memory directly |
//! | `mipgen` | yes | in-place pyramid generation (`mip::generate`) | pyramids prebuilt (host, flash) |
//! | `ffi` | no | C ABI (`ffi`, `include/raymip.h`); implies all four above | — |
//! | `envmap` | no | environment-map lod (cone; with `raydiff` also ray differentials) and the latitude-longitude `(u, v)` of a direction (`lod::envmap`) | no environment-map stage |
//! | `raydiff` | no | fixed-point ray differentials in every path state, their transfer, reflection, refraction, G-buffer set-up, texture-space footprint and lod (`path::raydiff`, `lod::raydiff`) | table and cone methods only; no differential state on the ray stack |
//! | `f32` | no | the per-hit stages in `f32`, the comparison baseline (`baseline_f32`); implies `trilinear` | no float code |
//! | `pcpi` | no | PicoRV32 texture co-processor instructions for the ACCURATE table and cone lod and the ACCURATE linear bilinear/trilinear filter (`coproc::pcpi`, riscv32 only; no effect on other targets) | software log2 and filter |
//!
//! The sampler is one type, [`texture::Sampler<S, K>`](texture::Sampler),
//! specialised at compile time by its key `K` (address mode per axis,
//! colour space, precision tier: [`texture::Cfg`]); a configuration that
//! does not use a feature carries none of its instructions. See
//! [`texture`] for the tiers and their bounds.
//!
//! ```
//! use raymip::lod::table_lod;
//! use raymip::path::raystack::{PathState, RayStack};
//! use raymip::setup::camera::PixelSpread;
//! use raymip::setup::table::{PbTable, TexTriangle};
//! use raymip::units::{Accurate, Lod, Log2Pb, PathLength, Spread};
//!
//! // Set-up: camera with 60° vertical field of view, 480 rows.
//! let spread = PixelSpread::from_fov_y(60f64.to_radians(), 480)?;
//! // A 1×1 square (two triangles) mapped once onto a 256×256 texture, and
//! // an untextured triangle.
//! let a = TexTriangle::from_f32(
//!     [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
//!     [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], 256, 256)?;
//! let mut storage = [Log2Pb::UNTEXTURED; 3];
//! let mut table = PbTable::new(&mut storage);
//! table.build([Some(a), Some(a), None], &spread)?;
//!
//! // Per hit: the primary ray hits triangle 0 at t = 1.2 scene units, a
//! // mirror bounce adds 0.8 more.
//! let mut stack: RayStack = RayStack::new();
//! let hit = PathState::primary(&spread, 0xFF).advance(PathLength::from_num(1.2));
//! stack.push(hit.bounce(Spread::ZERO))?;
//! let lod0 = table_lod::<Accurate>(hit.pl, table.get(0).ok_or("index")?).ok_or("untextured")?;
//! let next = stack.pop().ok_or("empty")?.advance(PathLength::from_num(0.8));
//! let lod1 = table_lod::<Accurate>(next.pl, table.get(0).ok_or("index")?).ok_or("untextured")?;
//! // Pl went from 1.2 to 2.0: log2(2.0/1.2) ≈ 0.74 levels coarser.
//! assert!((lod1 - lod0 - Lod::from_num(0.737)).abs() < Lod::from_num(0.01));
//! // Untextured triangles skip the texture path.
//! assert_eq!(table_lod::<Accurate>(next.pl, table.get(2).ok_or("index")?), None);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The texture half: a pyramid in a caller-provided buffer sized at compile
//! time by [`texture::storage::mip::pyramid_len`], generated in place, then
//! sampled per hit with a fixed-point [`Lod`]:
//!
//! ```
//! use raymip::units::{Lod, TexCoord};
//! use raymip::texture::storage::mip::{generate, pyramid_len, Geometry, Pyramid, Texel};
//! use raymip::texture::{Mode, Sampler};
//!
//! const W: u32 = 8;
//! const H: u32 = 8;
//! const LEVELS: u8 = 4; // 8×8, 4×4, 2×2, 1×1
//! let mut texels: [Texel; pyramid_len(W, H, LEVELS)] = [0; pyramid_len(W, H, LEVELS)];
//! // Level 0: a black/white checkerboard of single texels (alpha 255).
//! for y in 0..H {
//!     for x in 0..W {
//!         let v = if (x + y) % 2 == 0 { 255 } else { 0 };
//!         texels[(y * W + x) as usize] = u32::from_le_bytes([v, v, v, 255]);
//!     }
//! }
//! let geometry = Geometry::new(W, H, LEVELS)?;
//! generate(&geometry, &mut texels)?; // every coarser level is mid-gray
//! // Wrap on both axes, linear data, ACCURATE: `Sampler<_, Cfg<Wrap>>`.
//! let mut sampler = Sampler::wrap(Pyramid::new(geometry, &texels)?);
//!
//! // Centre of texel (0, 0) at lod 0: exactly that texel.
//! let c = TexCoord::from_num(0.5 / 8.0);
//! assert_eq!(sampler.sample(c, c, Lod::ZERO, Mode::Trilinear), 0xFFFF_FFFF);
//! // Halfway to level 1 (lod 0.5): white blended with gray 128 → 191.5 → 192.
//! let t = sampler.sample(c, c, Lod::from_num(0.5), Mode::Trilinear);
//! assert_eq!(t.to_le_bytes(), [192, 192, 192, 255]);
//! // The first sample needed only one level; the second read two.
//! assert_eq!(sampler.stats().fetched, 4 + 8);
//! assert_eq!(sampler.stats().skipped, 4);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![no_std]
// Safe Rust only; with the `ffi` feature the C ABI module may use `unsafe`
// for caller pointers, and with `pcpi` on riscv32 the co-processor module
// for its one-instruction `asm!` wrappers: `deny` then, `forbid` otherwise.
#![cfg_attr(
    not(any(feature = "ffi", all(feature = "pcpi", target_arch = "riscv32"))),
    forbid(unsafe_code)
)]
#![cfg_attr(
    any(feature = "ffi", all(feature = "pcpi", target_arch = "riscv32")),
    deny(unsafe_code)
)]
#![deny(
    missing_docs,
    missing_debug_implementations,
    trivial_casts,
    trivial_numeric_casts,
    rustdoc::broken_intra_doc_links
)]

#[macro_use]
mod macros;

#[cfg(feature = "f32")]
pub mod baseline_f32;
pub mod coproc;
#[cfg(feature = "ffi")]
pub mod ffi;
pub mod geomlod;
pub mod lod;
pub mod path;
pub mod rng;
pub mod setup;
pub mod texture;
pub mod units;

// The harness's f64 reference of `log2 Pb`, shared by the unit tests.
#[cfg(test)]
#[path = "../host-tests/src/reference/pb.rs"]
mod pb_reference;

// The harness's f64 reference of the environment-map lod and mapping.
#[cfg(all(test, feature = "envmap"))]
#[path = "../host-tests/src/reference/envmap.rs"]
mod envmap_reference;

// The README's Rust example runs as a doctest (`cargo test --doc`), so the
// front page cannot drift from the API.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExample;

// The everyday types, re-exported at the crate root.
pub use path::raystack::{PathState, RayStack, StackFull};
pub use setup::camera::{CameraError, PixelSpread};
pub use setup::table::{PbTable, TableError, TexTriangle};
#[cfg(feature = "cache")]
pub use texture::storage::cache::{BlockCache, BlockLayout, TexelCache};
pub use texture::storage::mip::{Geometry, MipError, Pyramid, Texel};
pub use texture::{AddressMode, Cfg, Mode, Sampler, SamplerState};
pub use units::{Delta, Lod, Log2Pb, PathLength, Spread, TexCoord, Width};
