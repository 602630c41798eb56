//! Cross-target check of the sampler in its run-time form
//! (`raymip::texture::sampler::dynamic::DynSampler`, every key of its
//! table): a fixed set of samples over every texel format, colour space,
//! address mode, sampler state, filter (anisotropic included) and
//! precision tier, hashed. The
//! firmware binary `parity` prints the line on Cortex-M4 and RV32IMAC under
//! QEMU, `raymip-demo parity` on the host; `scripts/demos` requires the
//! three lines to be identical.
//!
//! The texture is 32×32 with 6 levels stored as pseudo-random bytes (every
//! byte pattern is a valid texel in every format, BC blocks included), read
//! directly and through a texel cache (BC: block decode on fill).

use raymip::texture::Mode;
use raymip::texture::address::AddressMode;
use raymip::texture::sampler::dynamic::DynSampler;
use raymip::texture::sampler::state::{SamplerDesc, SamplerState, SrgbOutput};
use raymip::texture::storage::cache::TexelCache;
use raymip::texture::storage::format::{ColorSpace, Format, TexelFormat};
use raymip::texture::storage::image::{Image, image_len};
use raymip::texture::storage::mip::{Geometry, TexelSource};
use raymip::units::{Footprint, Lod, Precision, TexCoord};

use crate::Fnv1a;

/// Texture side and levels of the check.
const SIDE: u32 = 32;
const LEVELS: u8 = 6;
/// Bytes of the largest format (RGBA8).
const LEN: usize = image_len(SIDE, SIDE, LEVELS, TexelFormat::Rgba8);

/// Pseudo-random storage (xorshift32, computed at compile time).
static BYTES: [u8; LEN] = {
    let mut b = [0u8; LEN];
    let mut x: u32 = 0x1234_5678;
    let mut i = 0;
    while i < LEN {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        b[i] = (x >> 24) as u8;
        i += 1;
    }
    b
};

/// Deterministic 32-bit generator for the sample inputs.
struct Lcg(u32);

impl Lcg {
    fn next(&mut self) -> u32 {
        self.0 = self.0.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        self.0
    }

    /// A signed value with `bits` random low bits, sign-extended.
    fn signed(&mut self, bits: u32) -> i64 {
        i64::from((self.next() as i32) >> (32 - bits))
    }
}

/// Samples hashed per sampler configuration.
const PER_CONFIG: u32 = 8;

/// Feeds `n` samples of every filter (and 2 anisotropic ones) to `h`.
fn run<S: TexelSource>(s: &mut DynSampler<S>, rng: &mut Lcg, h: &mut Fnv1a) -> u32 {
    let mut count = 0;
    for _ in 0..PER_CONFIG {
        // u, v in [−4, 4), lod in [−2, 14).
        let u = TexCoord::from_bits(rng.signed(35));
        let v = TexCoord::from_bits(rng.signed(35));
        let lod = Lod::from_bits((rng.signed(12) + 1536) as i16);
        for m in 0..4 {
            let mode = Mode::from_index(m).unwrap_or(Mode::Trilinear);
            h.write(&s.sample(u, v, lod, mode).to_le_bytes());
            count += 1;
        }
        let fp = Footprint {
            x: [
                TexCoord::from_bits(rng.signed(31)),
                TexCoord::from_bits(rng.signed(31)),
            ],
            y: [
                TexCoord::from_bits(rng.signed(28)),
                TexCoord::from_bits(rng.signed(28)),
            ],
        };
        h.write(&s.sample_aniso(u, v, &fp).to_le_bytes());
        count += 1;
    }
    count
}

/// The parity checksum (FNV-1a of every result) and the number of
/// samples; `None` if the set-up fails (it cannot with these constants).
#[must_use]
pub fn checksum() -> Option<ParityLine> {
    let geometry = Geometry::new(SIDE, SIDE, LEVELS).ok()?;
    let mut h = Fnv1a::default();
    let mut rng = Lcg(2026);
    let mut samples = 0;
    for format in TexelFormat::ALL {
        for space in [ColorSpace::Linear, ColorSpace::Srgb] {
            let Ok(fmt) = Format::new(format, space) else {
                continue;
            };
            let image = Image::new(geometry, fmt, &BYTES).ok()?;
            for (i, au) in AddressMode::ALL.into_iter().enumerate() {
                let av = AddressMode::ALL[(i + 2) % 5];
                let lo = Lod::from_bits((rng.signed(10) + 256) as i16);
                let state = SamplerState::new(SamplerDesc {
                    address_u: au,
                    address_v: av,
                    border: rng.next(),
                    lod_bias: Lod::from_bits(rng.signed(13) as i16),
                    min_lod: lo,
                    max_lod: lo.saturating_add(Lod::from_bits((rng.next() & 0x7FF) as i16)),
                    max_anisotropy: (rng.next() % 16) as u8 + 1,
                    srgb_output: if rng.next() & 1 == 0 {
                        SrgbOutput::Encoded
                    } else {
                        SrgbOutput::Linear
                    },
                })
                .ok()?;
                for precision in [Precision::Accurate, Precision::Fast] {
                    let mut direct = DynSampler::new(image, state, space, precision);
                    samples += run(&mut direct, &mut rng, &mut h);
                    let cache: TexelCache<_, 4, 2> = TexelCache::new(image);
                    let mut cached = DynSampler::new(cache, state, space, precision);
                    samples += run(&mut cached, &mut rng, &mut h);
                }
            }
        }
    }
    Some(ParityLine {
        checksum: h.finish(),
        samples,
    })
}

/// The line the firmware and the host print (`Display`):
/// `parity: 0x… (N sampler results …)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ParityLine {
    /// FNV-1a of every sampler result (RGBA8 bytes, in order).
    pub checksum: u32,
    /// Number of results.
    pub samples: u32,
}

impl core::fmt::Display for ParityLine {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "parity: {:#010x} ({} sampler results over every format, address mode and filter, FNV-1a)",
            self.checksum, self.samples
        )
    }
}
