//! The sampler's accuracy against the f64 reference
//! (`raymip_reference::sampler`): the firmware sampler
//! (`raymip::texture::Sampler`, measured through its run-time form
//! `DynSampler` so that every key is reached) and the reference sample the
//! same random textures, states and positions in every texel format,
//! colour space, filter and tier; each row has its documented bound.
//!
//! The reference reads the stored bytes of uncompressed formats with the
//! decoder written here (bit replication as exact floors:
//! `floor(x·33/4)` for 5 bits, `floor(x·65/16)` for 6 bits, `17x` for 4
//! bits); BC images are given to it already decoded by the firmware
//! (`raymip::texture::storage::bc`), which `tests/harness/bc_decode.rs`
//! checks bit for bit against an independent decoder. Test textures in
//! every format come from [`texformat`].

pub mod texformat;

use raymip::rng::XorShift64;
use raymip::texture::Mode;
use raymip::texture::address::AddressMode;
use raymip::texture::kernel::accurate::BILERP_MAX_ERROR_LSB;
use raymip::texture::kernel::fast::FAST_MAX_ERROR_LSB;
use raymip::texture::kernel::srgb::{SRGB_LINEAR_MAX_ERROR_LSB, SRGB_MAX_ERROR_LSB};
use raymip::texture::sampler::dynamic::DynSampler;
use raymip::texture::sampler::state::{SamplerDesc, SamplerState, SrgbOutput};
use raymip::texture::storage::cache::TexelCache;
use raymip::texture::storage::format::{ColorSpace, Format, TexelFormat};
use raymip::texture::storage::image::Image;
use raymip::texture::storage::mip::{Geometry, Texel};
use raymip::units::{Lod, Precision, TexCoord};
use raymip_reference::Draw;
use raymip_reference::sampler::{self as reference, Address, State, Texture};

/// One stored uncompressed texel (little-endian word) to RGBA 0..=255
/// channel values, by bit replication written as exact floors.
#[must_use]
pub fn decode_texel(format: TexelFormat, raw: u32) -> [f64; 4] {
    let f = |x: u32| f64::from(x);
    let r5 = |x: u32| (f(x & 31) * 33.0 / 4.0).floor();
    let r6 = |x: u32| (f(x & 63) * 65.0 / 16.0).floor();
    let r4 = |x: u32| f(x & 15) * 17.0;
    match format {
        TexelFormat::Rgba8 => raw.to_le_bytes().map(f64::from),
        TexelFormat::Rgb565 => [r5(raw >> 11), r6(raw >> 5), r5(raw), 255.0],
        TexelFormat::Rgba5551 => [
            r5(raw >> 11),
            r5(raw >> 6),
            r5(raw >> 1),
            f(raw & 1) * 255.0,
        ],
        TexelFormat::Rgba4444 => [r4(raw >> 12), r4(raw >> 8), r4(raw >> 4), r4(raw)],
        TexelFormat::La8 => {
            let l = f(raw & 255);
            [l, l, l, f((raw >> 8) & 255)]
        }
        TexelFormat::L8 => {
            let l = f(raw & 255);
            [l, l, l, 255.0]
        }
        TexelFormat::A8 => [0.0, 0.0, 0.0, f(raw & 255)],
        _ => [0.0; 4],
    }
}

/// The reference's address mode of a firmware one (same numbering).
#[must_use]
pub fn address(mode: AddressMode) -> Address {
    Address::from_index(mode as u8).expect("the reference numbers every firmware address mode")
}

/// The reference's filter mode of a firmware one (same numbering).
#[must_use]
pub fn mode(mode: Mode) -> reference::Mode {
    reference::Mode::from_index(mode as u8).expect("the reference numbers every firmware mode")
}

/// The reference's texture of an RGBA8 pyramid of `geometry` (level
/// sizes and layout by the definition, not the firmware's indexing).
#[must_use]
pub fn texture_rgba8(geometry: &Geometry, texels: &[Texel]) -> Texture {
    Texture::from_rgba8_levels(
        geometry.width(),
        geometry.height(),
        geometry.levels(),
        texels,
    )
}

/// The reference's texture of uncompressed `bytes` in the
/// `raymip::texture::storage::image` layout of `format` (levels one after
/// the other, rows of `unit_bytes` texels), decoded by [`decode_texel`].
#[must_use]
pub fn texture_bytes(geometry: &Geometry, format: TexelFormat, bytes: &[u8]) -> Texture {
    let sizes = reference::level_sizes(geometry.width(), geometry.height(), geometry.levels());
    let unit = format.unit_bytes() as usize;
    let mut offsets = Vec::new();
    let mut offset = 0usize;
    for &(w, h) in &sizes {
        offsets.push(offset);
        offset += (w * h) as usize * unit;
    }
    Texture::from_fn(&sizes, |level, x, y| {
        let at = offsets[level] + (y * sizes[level].0 + x) as usize * unit;
        let mut raw = [0u8; 4];
        raw[..unit].copy_from_slice(&bytes[at..at + unit]);
        decode_texel(format, u32::from_le_bytes(raw))
    })
}

/// One row of the accuracy table: a format/colour space and a filter.
#[derive(Clone, Debug)]
pub struct AccuracyRow {
    /// Format name (with `_SRGB` for sRGB; `+enc`/`+lin` = result encoding).
    pub format: String,
    /// Filter name.
    pub filter: &'static str,
    /// Samples compared.
    pub samples: usize,
    /// Anisotropic samples left out as probe-count ties (the count's
    /// `ceil` is within 2⁻¹² in log2 of an integer).
    pub ties: usize,
    /// Largest |firmware − reference| over all channels, 8-bit LSB.
    pub max_error: f64,
    /// The documented bound for this row.
    pub bound: f64,
    /// The precision tier asked for.
    pub precision: Precision,
}

/// The filters of the accuracy table.
pub const FILTERS: [&str; 5] = [
    "nearest",
    "nearest texel, linear level",
    "bilinear",
    "trilinear",
    "anisotropic 16x (trilinear probes)",
];

/// Measures the firmware sampler of tier `precision` against the reference sampler for every
/// format (linear, and sRGB re-encoded and linear where it exists) and
/// filter, over `samples` random samples each: random 24×20 RGBA8 level 0
/// (pyramid by `mip::generate`, or `srgb::generate` for sRGB), converted
/// by [`texformat::encode_pyramid`]; random address modes per axis,
/// border colour, bias in [−16, 16), lod clamps, coordinates in
/// [−3, 3], lods in [−2, 8], anisotropic footprints with axes up to ±0.5
/// (up to 12 texels), through the texel cache. The reference reads the
/// stored bytes with its own decoder for uncompressed formats; BC texel
/// values come from `raymip::texture::storage::bc`, which `tests/bc_decode.rs` proves
/// bit-identical to an independent decoder.
#[must_use]
pub fn measure(samples: usize, seed: u64, precision: Precision) -> Vec<AccuracyRow> {
    let mut rng = XorShift64(seed.max(1));
    let geometry = Geometry::new(24, 20, 5).expect("geometry");
    let mut rows = Vec::new();
    for format in TexelFormat::ALL {
        let spaces: &[(ColorSpace, SrgbOutput, &str)] = if format.has_srgb() {
            &[
                (ColorSpace::Linear, SrgbOutput::Encoded, ""),
                (ColorSpace::Srgb, SrgbOutput::Encoded, "_SRGB (encoded)"),
                (ColorSpace::Srgb, SrgbOutput::Linear, "_SRGB (linear)"),
            ]
        } else {
            &[(ColorSpace::Linear, SrgbOutput::Encoded, "")]
        };
        for &(space, out, suffix) in spaces {
            let bytes = random_image_bytes(&mut rng, &geometry, format, space);
            let fmt = Format::new(format, space).expect("format");
            let image = Image::new(geometry, fmt, &bytes).expect("image");
            let reference = reference_texture(&geometry, format, &image, &bytes);
            for (fi, &filter) in FILTERS.iter().enumerate() {
                let mut max_error = 0.0f64;
                let mut ties = 0;
                for _ in 0..samples {
                    let Some((got, want)) =
                        sample_pair(&mut rng, fi, image, &reference, (space, out, precision))
                    else {
                        ties += 1;
                        continue;
                    };
                    max_error = max_error.max(channel_error(got, want));
                }
                rows.push(AccuracyRow {
                    format: format!("{format:?}{suffix}"),
                    filter,
                    samples,
                    ties,
                    max_error,
                    bound: error_bound(fi, space, out, precision),
                    precision,
                });
            }
        }
    }
    rows
}

/// The largest channel difference between a firmware texel and the
/// reference's channels (8-bit LSB).
fn channel_error(got: Texel, want: [f64; 4]) -> f64 {
    got.to_le_bytes()
        .iter()
        .zip(want)
        .map(|(g, w)| (f64::from(*g) - w).abs())
        .fold(0.0, f64::max)
}

/// A pseudo-random pyramid of `geometry` (levels generated from random
/// level-0 texels, in sRGB space when `space` is sRGB) stored as `format`.
fn random_image_bytes(
    rng: &mut XorShift64,
    geometry: &Geometry,
    format: TexelFormat,
    space: ColorSpace,
) -> Vec<u8> {
    let mut texels: Vec<Texel> = (0..geometry.len())
        .map(|_| (rng.unit() * 4_294_967_296.0) as u32)
        .collect();
    if space == ColorSpace::Srgb {
        raymip::texture::storage::srgb::generate(geometry, &mut texels).expect("srgb pyramid");
    } else {
        raymip::texture::storage::mip::generate(geometry, &mut texels).expect("pyramid");
    }
    texformat::encode_pyramid(geometry, &texels, format)
}

/// One case of the `sampler_ref` fuzz target: the run-time-configured
/// sampler ([`DynSampler`] through a texel cache) against the reference sampler.
/// The first four bytes of `bytes` choose the format, the colour space
/// (linear, sRGB re-encoded, sRGB linear), the tier and the filter; the
/// next eight seed the texels, the sampler state (address modes per axis,
/// border, bias, lod clamps) and the sample position, lod or footprint, as
/// in [`measure`] (missing bytes read as zero). Returns
/// `(case, error, bound)`: the largest channel error in 8-bit LSB and the
/// documented bound of that configuration, or `None` for an anisotropic
/// footprint whose probe count is a rounding tie.
#[must_use]
pub fn fuzz_case(bytes: &[u8]) -> Option<(String, f64, f64)> {
    let mut b = [0u8; 12];
    for (d, s) in b.iter_mut().zip(bytes) {
        *d = *s;
    }
    let format = TexelFormat::ALL[usize::from(b[0]) % TexelFormat::ALL.len()];
    let (space, out) = match (format.has_srgb(), b[1] % 3) {
        (true, 1) => (ColorSpace::Srgb, SrgbOutput::Encoded),
        (true, 2) => (ColorSpace::Srgb, SrgbOutput::Linear),
        _ => (ColorSpace::Linear, SrgbOutput::Encoded),
    };
    let precision = if b[2] & 1 == 0 {
        Precision::Accurate
    } else {
        Precision::Fast
    };
    let fi = usize::from(b[3]) % FILTERS.len();
    let mut seed = [0u8; 8];
    seed.copy_from_slice(&b[4..]);
    let mut rng = XorShift64(u64::from_le_bytes(seed).max(1));
    let geometry = Geometry::new(24, 20, 5).expect("geometry");
    let bytes = random_image_bytes(&mut rng, &geometry, format, space);
    let image = Image::new(
        geometry,
        Format::new(format, space).expect("format"),
        &bytes,
    )
    .expect("image");
    let reference = reference_texture(&geometry, format, &image, &bytes);
    let (got, want) = sample_pair(&mut rng, fi, image, &reference, (space, out, precision))?;
    let case = format!("{format:?} {space:?} {out:?} {precision:?} {}", FILTERS[fi]);
    Some((
        case,
        channel_error(got, want),
        error_bound(fi, space, out, precision),
    ))
}

/// The reference's view of `image`: its own decode of the stored bytes,
/// or the firmware's BC decode (checked bit for bit elsewhere).
fn reference_texture(
    geometry: &Geometry,
    format: TexelFormat,
    image: &Image<'_>,
    bytes: &[u8],
) -> Texture {
    if format.is_block_compressed() {
        let decoded: Vec<Texel> = (0..geometry.levels())
            .flat_map(|k| {
                let (w, h) = geometry.level_size(k);
                (0..h).flat_map(move |y| (0..w).map(move |x| (k, x, y)))
            })
            .map(|(k, x, y)| image.get(k, x, y))
            .collect();
        texture_rgba8(geometry, &decoded)
    } else {
        texture_bytes(geometry, format, bytes)
    }
}

/// Documented bound of filter `fi` (index into [`FILTERS`]) for the
/// tier `precision` (sRGB data filters ACCURATE in both tiers).
fn error_bound(fi: usize, space: ColorSpace, out: SrgbOutput, precision: Precision) -> f64 {
    let encoded = space == ColorSpace::Srgb && out == SrgbOutput::Encoded;
    let base = match (space, out, precision) {
        (ColorSpace::Srgb, SrgbOutput::Encoded, _) => SRGB_MAX_ERROR_LSB,
        (ColorSpace::Srgb, SrgbOutput::Linear, _) => SRGB_LINEAR_MAX_ERROR_LSB,
        (_, _, Precision::Fast) => FAST_MAX_ERROR_LSB,
        (_, _, Precision::Accurate) => BILERP_MAX_ERROR_LSB,
    };
    match fi {
        // sRGB: the decoded (or border) value is rounded once.
        0 if space == ColorSpace::Srgb => 0.5,
        0 => 0.0,
        1..=3 => base,
        // Re-encoded: the probe lod's error is a linear-space error, and
        // the sRGB curve is steepest (12.92) at the dark end, where a blend
        // of a dark level with a bright one lands (as SRGB_MAX_ERROR_LSB).
        _ => base + ANISO_LOD_ERROR_LSB * if encoded { SRGB_STEEPEST_SLOPE } else { 1.0 },
    }
}

/// A random sampler state (address modes, border, bias, lod clamps).
fn random_state(rng: &mut XorShift64, out: SrgbOutput) -> (SamplerDesc, [AddressMode; 2]) {
    let pick = |x: f64| AddressMode::ALL[((x * 5.0) as usize).min(4)];
    let address = [pick(rng.unit()), pick(rng.unit())];
    let border_bits = (rng.unit() * 4_294_967_296.0) as u32;
    let bias = Lod::from_bits(((rng.unit() * 8192.0) as i32 - 4096) as i16);
    let (a, b) = (
        Lod::from_bits(((rng.unit() * 3072.0) as i32 - 512) as i16),
        Lod::from_bits(((rng.unit() * 3072.0) as i32 - 512) as i16),
    );
    let (lo, hi) = if rng.unit() < 0.5 {
        (a.min(b), a.max(b))
    } else {
        (Lod::MIN, Lod::MAX)
    };
    let desc = SamplerDesc {
        address_u: address[0],
        address_v: address[1],
        border: border_bits,
        lod_bias: bias,
        min_lod: lo,
        max_lod: hi,
        max_anisotropy: 16,
        srgb_output: out,
    };
    (desc, address)
}

/// One random sample of filter `fi` through the firmware and the
/// reference: `(firmware texel, reference channels)`, or `None` for an
/// anisotropic footprint whose probe count is a rounding tie.
fn sample_pair(
    rng: &mut XorShift64,
    fi: usize,
    image: Image<'_>,
    reference: &Texture,
    (space, out, precision): (ColorSpace, SrgbOutput, Precision),
) -> Option<(Texel, [f64; 4])> {
    let (desc, address) = random_state(rng, out);
    let state = SamplerState::new(desc).expect("state");
    let mut fw = DynSampler::new(TexelCache::<_, 8, 2>::new(image), state, space, precision);
    let rs = reference::Sampler {
        tex: reference,
        state: State {
            address: address.map(self::address),
            border: desc.border.to_le_bytes().map(f64::from),
            bias: desc.lod_bias.to_num(),
            min_lod: desc.min_lod.to_num(),
            max_lod: desc.max_lod.to_num(),
            max_aniso: 16,
            srgb: space == ColorSpace::Srgb,
            encode_srgb: out == SrgbOutput::Encoded,
        },
    };
    let u = TexCoord::from_num(rng.unit() * 6.0 - 3.0);
    let v = TexCoord::from_num(rng.unit() * 6.0 - 3.0);
    let (uf, vf) = (u.to_num::<f64>(), v.to_num::<f64>());
    if fi < 4 {
        let mode = [
            Mode::Nearest,
            Mode::NearestTexelLinearLevel,
            Mode::BilinearNearestLevel,
            Mode::Trilinear,
        ][fi];
        let lod = Lod::from_bits(((rng.unit() * 2560.0) as i32 - 512) as i16);
        return Some((
            fw.sample(u, v, lod, mode),
            rs.sample(uf, vf, lod.to_num(), self::mode(mode)),
        ));
    }
    let axis = |x: f64| TexCoord::from_num(x);
    let ax = [axis(rng.unit() - 0.5), axis(rng.unit() - 0.5)];
    let s = rng.unit() * rng.unit();
    let ay = [axis((rng.unit() - 0.5) * s), axis((rng.unit() - 0.5) * s)];
    let axes = [
        [ax[0].to_num::<f64>(), ax[1].to_num::<f64>()],
        [ay[0].to_num::<f64>(), ay[1].to_num::<f64>()],
    ];
    let (w, h) = (24.0, 20.0);
    let len = |a: [f64; 2]| (a[0] * w).hypot(a[1] * h);
    let (l0, l1) = (len(axes[0]), len(axes[1]));
    // Above 16:1 the count is 16 whatever the rounding.
    let ratio = (l0.max(l1) / l0.min(l1)).log2();
    let tie = (1..=16).any(|k| (ratio - f64::from(k).log2()).abs() < 1.0 / 4096.0)
        || (l0 - l1).abs() < 1e-9 * l0.max(l1)
        || l0.min(l1) < 1e-6;
    if tie {
        return None;
    }
    let fp = raymip::units::Footprint { x: ax, y: ay };
    Some((
        fw.sample_aniso(u, v, &fp),
        rs.sample_aniso(uf, vf, axes, reference::Mode::Trilinear),
    ))
}

/// Extra error of anisotropic samples against the exact-lod reference:
/// the probe lod carries the log2 error (2⁻¹³) and is rounded to 8
/// fractional bits, so the level blend weight may differ by
/// `2⁻⁸ + 2⁻¹³`, times at most 255 LSB between the two levels.
pub const ANISO_LOD_ERROR_LSB: f64 = 255.0 * (1.0 / 256.0 + 1.0 / 8192.0);

/// The sRGB encoding's steepest slope (its linear segment, `12.92`):
/// a linear-space error `e` LSB changes a re-encoded channel by at most
/// `12.92·e` LSB.
pub const SRGB_STEEPEST_SLOPE: f64 = 12.92;
