//! The `sample` command: filtered texels through the firmware fixed-point
//! path, one output line per input line.
//!
//! Input lines are `u,v,lod,mode` (decimal numbers; mode 0 = trilinear,
//! 1 = bilinear + nearest level, 2 = nearest texel + nearest level,
//! 3 = nearest texel + linear between levels), or, for an anisotropic
//! sample, `u,v,mode,dudx,dvdx,dudy,dvdy` (the footprint's two axis vectors
//! in normalized texture coordinates; trilinear probes, mode 0). Output lines
//! are `r,g,b,a` (0–255). Any malformed line (wrong field count, bad
//! number, NaN/inf, unknown mode, blank) stops the command with an error
//! naming the line; nothing is skipped silently.
//!
//! Every line goes through the one firmware sampler in its run-time form
//! (`raymip::texture::sampler::dynamic::DynSampler`: the specialised key
//! for the options, picked once), in the precision tier of `--precision`
//! (accurate, the default, or fast). With RGBA8 and no other sampler
//! option it reads the pyramid in memory directly (the outputs of the
//! earlier plain sampler, bit for bit); with `--format`, `--srgb` or any
//! other state option (`--address` with another mode or two axes,
//! `--border`, `--linear-output`, `--bias`, `--min-lod`, `--max-lod`) the
//! PPM becomes an RGBA8 pyramid (generated in linear space with `--srgb`),
//! converted to `--format` (BC by the harness encoder) and read through a
//! 16 KiB texel cache (BC blocks decoded on fill).

use std::fmt;
use std::io::{self, BufRead, Write};
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use raymip::texture::address::AddressMode;
use raymip::texture::sampler::dynamic::DynSampler;
use raymip::texture::sampler::state::SamplerStateError;
use raymip::texture::sampler::state::{SamplerDesc, SamplerState, SrgbOutput};
use raymip::texture::storage::cache::TexelCache;
use raymip::texture::storage::format::NoSrgbVariant;
use raymip::texture::storage::format::{ColorSpace, Format, TexelFormat};
use raymip::texture::storage::image::Image;
use raymip::texture::storage::image::ImageTooShort;
use raymip::texture::storage::mip::TexelSource;
use raymip::texture::storage::mip::{Geometry, MipError, Pyramid, Texel, full_levels, generate};
use raymip::texture::{FilterError, Mode, tex_coord_from_f64};
use raymip::units::{Footprint, Lod, Precision, TexCoord};

use crate::scene::ppm::{PpmError, RgbImage, read_ppm};

/// Addressing mode on the command line, numbered as [`AddressMode`] (and
/// the C ABI's `RmAddress`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
#[repr(u8)]
pub enum AddressArg {
    /// Repeat the texture.
    Wrap = AddressMode::Wrap as u8,
    /// Clamp to the edge texels.
    Clamp = AddressMode::ClampToEdge as u8,
    /// Repeat, every other copy mirrored.
    Mirror = AddressMode::Mirror as u8,
    /// Mirror once around 0, then clamp to the edge.
    MirrorOnce = AddressMode::MirrorOnce as u8,
    /// Outside the texture: the border colour (--border).
    Border = AddressMode::ClampToBorder as u8,
}

impl AddressArg {
    /// The firmware address mode: the one of the same number.
    #[must_use]
    pub fn mode(self) -> AddressMode {
        AddressMode::ALL[usize::from(self as u8)]
    }

    /// The original sampler's addressing, for wrap and clamp.
    #[must_use]
    pub fn plain(self) -> Option<AddressMode> {
        match self {
            Self::Wrap | Self::Clamp => Some(self.mode()),
            _ => None,
        }
    }
}

/// Texel format on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FormatArg {
    /// 8 bits per channel.
    Rgba8,
    /// 5/6/5 bits, alpha 255.
    Rgb565,
    /// 5/5/5/1 bits.
    Rgba5551,
    /// 4 bits per channel.
    Rgba4444,
    /// Luminance (red) and alpha.
    La8,
    /// Luminance (red).
    L8,
    /// Alpha only.
    A8,
    /// BC1 (DXT1).
    Bc1,
    /// BC2 (DXT3).
    Bc2,
    /// BC3 (DXT5).
    Bc3,
    /// BC4 (red).
    Bc4,
}

impl FormatArg {
    /// The firmware format.
    #[must_use]
    pub fn format(self) -> TexelFormat {
        match self {
            Self::Rgba8 => TexelFormat::Rgba8,
            Self::Rgb565 => TexelFormat::Rgb565,
            Self::Rgba5551 => TexelFormat::Rgba5551,
            Self::Rgba4444 => TexelFormat::Rgba4444,
            Self::La8 => TexelFormat::La8,
            Self::L8 => TexelFormat::L8,
            Self::A8 => TexelFormat::A8,
            Self::Bc1 => TexelFormat::Bc1,
            Self::Bc2 => TexelFormat::Bc2,
            Self::Bc3 => TexelFormat::Bc3,
            Self::Bc4 => TexelFormat::Bc4,
        }
    }
}

/// Parses `R,G,B,A` (0–255 each) into an RGBA8 texel.
///
/// # Errors
/// [`RgbaError`] when there are not four integers in 0..=255.
pub fn parse_rgba(s: &str) -> Result<Texel, RgbaError> {
    let v: Vec<u8> = s
        .split(',')
        .map(|x| x.trim().parse::<u8>())
        .collect::<Result<_, _>>()
        .map_err(|_| RgbaError::NotBytes { value: s.into() })?;
    match v.as_slice() {
        &[r, g, b, a] => Ok(u32::from_le_bytes([r, g, b, a])),
        _ => Err(RgbaError::Count {
            value: s.into(),
            found: v.len(),
        }),
    }
}

/// A bad `R,G,B,A` option value (`--border`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RgbaError {
    /// A component is not an integer in 0..=255.
    NotBytes {
        /// The value given.
        value: String,
    },
    /// Not four components.
    Count {
        /// The value given.
        value: String,
        /// How many components it has.
        found: usize,
    },
}

impl fmt::Display for RgbaError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotBytes { value } => write!(f, "{value:?}: expected R,G,B,A with values 0-255"),
            Self::Count { value, found } => {
                write!(f, "{value:?}: expected four values R,G,B,A, found {found}")
            }
        }
    }
}

impl std::error::Error for RgbaError {}

/// An invalid sampler option of `sample`.
#[derive(Debug)]
pub enum OptionError {
    /// A level-of-detail option is NaN or infinite.
    LodNotFinite {
        /// The option (`bias`, `min-lod`, `max-lod`).
        option: &'static str,
        /// Its value.
        value: f64,
    },
    /// A level-of-detail option is outside the firmware's `[-128, 128)`.
    LodOutOfRange {
        /// The option.
        option: &'static str,
        /// Its value.
        value: f64,
    },
    /// The firmware rejected the sampler state.
    Sampler(SamplerStateError),
    /// `--srgb` with a format that has no sRGB variant.
    Format(NoSrgbVariant),
    /// `--linear-output` without `--srgb`.
    LinearOutputNeedsSrgb,
    /// The encoded texture is shorter than its geometry needs.
    Image(ImageTooShort),
}

impl fmt::Display for OptionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::LodNotFinite { option, value } => write!(f, "--{option}: {value} is not finite"),
            Self::LodOutOfRange { option, value } => {
                write!(f, "--{option}: {value} outside [-128, 128)")
            }
            Self::Sampler(e) => write!(f, "sampler options: {e}"),
            Self::Format(e) => write!(f, "--format with --srgb: {e}"),
            Self::LinearOutputNeedsSrgb => f.write_str("--linear-output needs --srgb"),
            Self::Image(e) => write!(f, "texture: {e}"),
        }
    }
}

impl std::error::Error for OptionError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Sampler(e) => Some(e),
            Self::Format(e) => Some(e),
            Self::Image(e) => Some(e),
            _ => None,
        }
    }
}

/// A malformed input line of `sample` (see [`LINE_FORMAT`]).
#[derive(Clone, Debug, PartialEq)]
pub enum LineError {
    /// Neither 4 nor 7 comma-separated fields.
    FieldCount {
        /// Fields found.
        found: usize,
        /// The line.
        text: String,
    },
    /// A field is not a number.
    NotANumber {
        /// The field (`u`, `v`, `lod`, `dudx`, …).
        field: &'static str,
        /// Its text.
        text: String,
    },
    /// A field is NaN or infinite.
    NotFinite {
        /// The field.
        field: &'static str,
        /// Its text.
        text: String,
    },
    /// The mode is not 0, 1, 2 or 3.
    BadMode {
        /// Its text.
        text: String,
    },
    /// Anisotropic lines take trilinear probes only.
    AnisoMode {
        /// The mode given.
        mode: u8,
    },
    /// A coordinate the firmware cannot represent.
    Coord(FilterError),
}

impl fmt::Display for LineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::FieldCount { found, text } => write!(
                f,
                "expected 4 comma-separated fields u,v,lod,mode or 7 fields u,v,mode,dudx,dvdx,dudy,dvdy, found {found} in {text:?}"
            ),
            Self::NotANumber { field, text } => write!(f, "{field}: {text:?} is not a number"),
            Self::NotFinite { field, text } => write!(f, "{field}: {text:?} is not finite"),
            Self::BadMode { text } => write!(f, "mode: {text:?} is not one of 0, 1, 2, 3"),
            Self::AnisoMode { mode } => write!(
                f,
                "anisotropic lines take trilinear probes (mode 0), not mode {mode}"
            ),
            Self::Coord(e) => write!(f, "coordinate: {e}"),
        }
    }
}

impl std::error::Error for LineError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Coord(e) => Some(e),
            _ => None,
        }
    }
}

/// Arguments of `raymip-host sample`.
#[derive(Clone, Debug, Args)]
#[command(after_long_help = LINE_FORMAT)]
pub struct SampleArgs {
    /// Texture, binary PPM (P6); alpha is 255.
    #[arg(long)]
    pub texture: PathBuf,
    /// Stored MIP levels (1 ..= full chain); default: the full chain.
    #[arg(long)]
    pub levels: Option<u8>,
    /// Addressing outside [0, 1): one mode for both axes, or `U,V`
    /// (wrap, clamp, mirror, mirror-once, border).
    #[arg(long, value_delimiter = ',', num_args = 1..=2, default_value = "wrap")]
    pub address: Vec<AddressArg>,
    /// Border colour `R,G,B,A` (0-255, linear) for `--address border`.
    #[arg(long, value_parser = parse_rgba)]
    pub border: Option<Texel>,
    /// Stored texel format (the PPM is converted to it).
    #[arg(long, value_enum, default_value_t = FormatArg::Rgba8)]
    pub format: FormatArg,
    /// The texture is sRGB (rgba8, la8, l8, bc1-bc3): decoded to linear
    /// before filtering, pyramid generated in linear space, results
    /// re-encoded to sRGB (see --linear-output).
    #[arg(long)]
    pub srgb: bool,
    /// With --srgb: print linear results instead of re-encoding them.
    #[arg(long)]
    pub linear_output: bool,
    /// LOD bias in levels, [-16, 16) (steps of 1/256).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub bias: f64,
    /// Lower lod clamp in levels (applied after the bias).
    #[arg(long, allow_negative_numbers = true)]
    pub min_lod: Option<f64>,
    /// Upper lod clamp in levels (applied after the bias).
    #[arg(long, allow_negative_numbers = true)]
    pub max_lod: Option<f64>,
    /// Maximum anisotropy 1..=16 for anisotropic lines.
    #[arg(long, default_value_t = 16)]
    pub max_aniso: u8,
    /// Precision tier: accurate (12-bit weights, ≤ 0.5625 LSB) or fast
    /// (GPU precision: 8 sub-texel bits, ≤ 1.5 LSB; sRGB data filters
    /// accurate in both).
    #[arg(long, value_enum, default_value_t = PrecisionArg::Accurate)]
    pub precision: PrecisionArg,
}

/// Precision tier on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PrecisionArg {
    /// ACCURATE (default).
    Accurate,
    /// FAST.
    Fast,
}

impl PrecisionArg {
    /// The firmware tier.
    #[must_use]
    pub fn precision(self) -> Precision {
        match self {
            Self::Accurate => Precision::Accurate,
            Self::Fast => Precision::Fast,
        }
    }
}

/// The line format, printed by `sample --help`.
pub const LINE_FORMAT: &str = "\
Input lines (stdin), decimal numbers, comma-separated:
  u,v,lod,mode                      one sample at lod (levels)
  u,v,mode,dudx,dvdx,dudy,dvdy      anisotropic sample over the footprint
                                    (du/dx, dv/dx), (du/dy, dv/dy) in
                                    normalized coordinates; up to
                                    --max-aniso trilinear probes
                                    (mode must be 0)
mode: 0 trilinear, 1 bilinear + nearest level, 2 nearest texel + nearest
level, 3 nearest texel + linear between levels.
Output lines (stdout): r,g,b,a (0-255), one per input line.
Lod order (D3D11/Vulkan): lod + bias, clamp to [min-lod, max-lod], clamp to
the stored levels.";

impl SampleArgs {
    /// Whether any GPU-sampler option is set (else the original sampler
    /// runs).
    #[must_use]
    pub fn uses_sampler_state(&self) -> bool {
        self.address.len() > 1
            || self.address.iter().any(|a| a.plain().is_none())
            || self.border.is_some()
            || self.format != FormatArg::Rgba8
            || self.srgb
            || self.linear_output
            || self.bias != 0.0
            || self.min_lod.is_some()
            || self.max_lod.is_some()
    }

    /// The validated sampler state and format of the options.
    ///
    /// # Errors
    /// [`OptionError`] naming the option out of range.
    pub fn state(&self) -> Result<(SamplerState, Format), OptionError> {
        let lod = |option: &'static str, value: f64| -> Result<Lod, OptionError> {
            if !value.is_finite() {
                return Err(OptionError::LodNotFinite { option, value });
            }
            Lod::checked_from_num(value).ok_or(OptionError::LodOutOfRange { option, value })
        };
        let au = self.address.first().copied().unwrap_or(AddressArg::Wrap);
        let av = self.address.get(1).copied().unwrap_or(au);
        let state = SamplerState::new(SamplerDesc {
            address_u: au.mode(),
            address_v: av.mode(),
            border: self.border.unwrap_or(0),
            lod_bias: lod("bias", self.bias)?,
            min_lod: self.min_lod.map_or(Ok(Lod::MIN), |x| lod("min-lod", x))?,
            max_lod: self.max_lod.map_or(Ok(Lod::MAX), |x| lod("max-lod", x))?,
            max_anisotropy: self.max_aniso,
            srgb_output: if self.linear_output {
                SrgbOutput::Linear
            } else {
                SrgbOutput::Encoded
            },
        })
        .map_err(OptionError::Sampler)?;
        let space = if self.srgb {
            ColorSpace::Srgb
        } else {
            ColorSpace::Linear
        };
        let format = Format::new(self.format.format(), space).map_err(OptionError::Format)?;
        if self.linear_output && !self.srgb {
            return Err(OptionError::LinearOutputNeedsSrgb);
        }
        Ok((state, format))
    }
}

/// What went wrong in `sample`.
#[derive(Debug)]
pub enum SampleError {
    /// The texture could not be read.
    Texture(PpmError),
    /// The texture cannot form a pyramid (size or levels).
    Pyramid {
        /// The texture file.
        path: PathBuf,
        /// Why.
        error: MipError,
        /// Requested levels, when that was the problem.
        levels: Option<u8>,
    },
    /// A malformed input line.
    Line {
        /// Name of the input (`<stdin>`).
        input: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        error: LineError,
    },
    /// Invalid sampler options.
    Options(OptionError),
    /// Reading input or writing output failed.
    Io(io::Error),
}

impl fmt::Display for SampleError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Texture(e) => write!(f, "{e}"),
            Self::Pyramid {
                path,
                error,
                levels: Some(l),
            } => write!(f, "{}: --levels {l}: {error}", path.display()),
            Self::Pyramid { path, error, .. } => write!(f, "{}: {error}", path.display()),
            Self::Line { input, line, error } => write!(f, "{input}:{line}: {error}"),
            Self::Options(m) => write!(f, "{m}"),
            Self::Io(e) => write!(f, "i/o error: {e}"),
        }
    }
}

impl std::error::Error for SampleError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Texture(e) => Some(e),
            Self::Pyramid { error, .. } => Some(error),
            Self::Line { error, .. } => Some(error),
            Self::Options(e) => Some(e),
            Self::Io(e) => Some(e),
        }
    }
}

impl From<io::Error> for SampleError {
    fn from(e: io::Error) -> Self {
        Self::Io(e)
    }
}

/// A texture's pyramid, owned: geometry and texels (levels generated).
#[derive(Clone, Debug)]
pub struct OwnedPyramid {
    /// Size and levels.
    pub geometry: Geometry,
    /// All stored levels, level 0 first.
    pub texels: Vec<Texel>,
}

impl OwnedPyramid {
    /// Borrowed view for the firmware sampler.
    ///
    /// # Errors
    /// [`MipError::BufferTooShort`] if `texels` was shortened after
    /// [`build_pyramid`].
    pub fn pyramid(&self) -> Result<Pyramid<'_>, MipError> {
        Pyramid::new(self.geometry, &self.texels)
    }
}

/// Builds the pyramid of `img` (RGBA8, alpha 255) with `levels` levels
/// (default: the full chain), generated by the firmware filter.
pub fn build_pyramid(
    img: &RgbImage,
    levels: Option<u8>,
    path: &Path,
) -> Result<OwnedPyramid, SampleError> {
    let n = levels.unwrap_or_else(|| full_levels(img.width, img.height));
    let err = |error| SampleError::Pyramid {
        path: path.to_path_buf(),
        error,
        levels,
    };
    let geometry = Geometry::new(img.width, img.height, n).map_err(err)?;
    let mut texels = img.to_rgba8888();
    texels.resize(geometry.len(), 0);
    generate(&geometry, &mut texels).map_err(err)?;
    Ok(OwnedPyramid { geometry, texels })
}

/// One parsed input line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SampleLine {
    /// `u,v,lod,mode`.
    Lod {
        /// Coordinates.
        u: f64,
        /// Coordinates.
        v: f64,
        /// Level of detail.
        lod: f64,
        /// Filter.
        mode: Mode,
    },
    /// `u,v,mode,dudx,dvdx,dudy,dvdy`.
    Aniso {
        /// Coordinates.
        u: f64,
        /// Coordinates.
        v: f64,
        /// Filter of the probes.
        mode: Mode,
        /// `[[du/dx, dv/dx], [du/dy, dv/dy]]`.
        axes: [[f64; 2]; 2],
    },
}

/// Parses one input line (see [`LINE_FORMAT`]).
fn parse_line(text: &str) -> Result<SampleLine, LineError> {
    let fields: Vec<&str> = text.split(',').map(str::trim).collect();
    if fields.len() != 4 && fields.len() != 7 {
        return Err(LineError::FieldCount {
            found: fields.len(),
            text: text.into(),
        });
    }
    let num = |i: usize, field: &'static str| -> Result<f64, LineError> {
        let s = fields[i];
        let x: f64 = s.parse().map_err(|_| LineError::NotANumber {
            field,
            text: s.into(),
        })?;
        if x.is_finite() {
            Ok(x)
        } else {
            Err(LineError::NotFinite {
                field,
                text: s.into(),
            })
        }
    };
    let mode_at = |i: usize| {
        fields[i]
            .parse::<u8>()
            .ok()
            .and_then(Mode::from_index)
            .ok_or_else(|| LineError::BadMode {
                text: fields[i].into(),
            })
    };
    let (u, v) = (num(0, "u")?, num(1, "v")?);
    if fields.len() == 4 {
        Ok(SampleLine::Lod {
            u,
            v,
            lod: num(2, "lod")?,
            mode: mode_at(3)?,
        })
    } else {
        Ok(SampleLine::Aniso {
            u,
            v,
            mode: mode_at(2)?,
            axes: [
                [num(3, "dudx")?, num(4, "dvdx")?],
                [num(5, "dudy")?, num(6, "dvdy")?],
            ],
        })
    }
}

/// `x` reduced (exactly, in f64) to the range that addresses the same
/// texels under `mode`, as a [`TexCoord`].
fn coord(x: f64, mode: AddressMode) -> Result<TexCoord, LineError> {
    let r = match mode {
        AddressMode::Wrap => x - x.floor(),
        AddressMode::Mirror => x - 2.0 * (x / 2.0).floor(),
        _ => x.clamp(-2.0, 2.0),
    };
    tex_coord_from_f64(r).map_err(LineError::Coord)
}

/// Samples every line of `input` (`u,v,lod,mode`, or anisotropic lines)
/// from `pyramid` in memory with address mode `address` on both axes and
/// the default state, ACCURATE, and writes `r,g,b,a` lines to `output`, in
/// order. `input_name` names the input in errors. Returns the number of
/// samples written.
///
/// # Errors
/// [`SampleError::Line`] for the first malformed line (earlier results are
/// already written), [`SampleError::Io`] for read/write failures.
pub fn sample_lines<R: BufRead, W: Write>(
    pyramid: &OwnedPyramid,
    address: AddressMode,
    input: R,
    output: W,
    input_name: &str,
) -> Result<usize, SampleError> {
    let state = SamplerState::new(SamplerDesc {
        address_u: address,
        address_v: address,
        ..SamplerDesc::default()
    })
    .map_err(|e| SampleError::Options(OptionError::Sampler(e)))?;
    let sampler = DynSampler::new(
        view(pyramid, input_name)?,
        state,
        ColorSpace::Linear,
        Precision::Accurate,
    );
    run_lines(sampler, input, output, input_name)
}

/// Samples every line of `input` with `sampler` (coordinates reduced in
/// f64 as its address modes reduce them) and writes `r,g,b,a` lines.
fn run_lines<S: TexelSource, R: BufRead, W: Write>(
    mut sampler: DynSampler<S>,
    input: R,
    output: W,
    input_name: &str,
) -> Result<usize, SampleError> {
    let [au, av] = sampler.state().address();
    sample_each_line(input, output, input_name, |line, line_err| {
        Ok(match line {
            SampleLine::Lod { u, v, lod, mode } => {
                let (u, v) = (
                    coord(u, au).map_err(line_err)?,
                    coord(v, av).map_err(line_err)?,
                );
                sampler.sample(u, v, Lod::saturating_from_num(lod), mode)
            }
            SampleLine::Aniso { u, v, mode, axes } => {
                let (u, v) = (
                    coord(u, au).map_err(line_err)?,
                    coord(v, av).map_err(line_err)?,
                );
                if mode != Mode::Trilinear {
                    return Err(line_err(LineError::AnisoMode { mode: mode as u8 }));
                }
                let a = |x: f64| TexCoord::saturating_from_num(x);
                let fp = Footprint {
                    x: [a(axes[0][0]), a(axes[0][1])],
                    y: [a(axes[1][0]), a(axes[1][1])],
                };
                sampler.sample_aniso(u, v, &fp)
            }
        })
    })
}

/// The pyramid of `pyramid` to sample (`input_name` names the input in the
/// error).
fn view<'a>(pyramid: &'a OwnedPyramid, input_name: &str) -> Result<Pyramid<'a>, SampleError> {
    pyramid.pyramid().map_err(|error| SampleError::Pyramid {
        path: PathBuf::from(input_name),
        error,
        levels: None,
    })
}

/// Reads `input` line by line, parses each line (errors name `input_name`
/// and the line number), samples it with `sample` (given the line and its
/// error constructor) and writes one `r,g,b,a` line to `output`, in order.
/// Returns the number of samples written.
fn sample_each_line<R: BufRead, W: Write>(
    input: R,
    mut output: W,
    input_name: &str,
    mut sample: impl FnMut(SampleLine, &dyn Fn(LineError) -> SampleError) -> Result<Texel, SampleError>,
) -> Result<usize, SampleError> {
    let mut count = 0;
    for (i, line) in input.lines().enumerate() {
        let line = line?;
        let line_err = |error: LineError| SampleError::Line {
            input: input_name.to_string(),
            line: i + 1,
            error,
        };
        let text = line.strip_suffix('\r').unwrap_or(&line);
        let [r, g, b, a] = sample(parse_line(text).map_err(line_err)?, &line_err)?.to_le_bytes();
        writeln!(output, "{r},{g},{b},{a}")?;
        count += 1;
    }
    output.flush()?;
    Ok(count)
}

/// Samples every line of `input` through the sampler of `state`,
/// `format` and `precision` over `pyramid` (RGBA8; generated in linear
/// space for sRGB) converted to `format` and read through a texel cache;
/// writes `r,g,b,a` lines. Returns the count.
///
/// # Errors
/// As [`sample_lines`].
pub fn sample_lines_state<R: BufRead, W: Write>(
    pyramid: &OwnedPyramid,
    (state, format, precision): (SamplerState, Format, Precision),
    input: R,
    output: W,
    input_name: &str,
) -> Result<usize, SampleError> {
    let bytes = crate::accuracy::texformat::encode_pyramid(
        &pyramid.geometry,
        &pyramid.texels,
        format.texel(),
    );
    let image = Image::new(pyramid.geometry, format, &bytes)
        .map_err(|e| SampleError::Options(OptionError::Image(e)))?;
    let mut cache: Box<TexelCache<Image<'_>, 64, 4>> = Box::new(TexelCache::new(image));
    let sampler = DynSampler::new(&mut *cache, state, format.space(), precision);
    run_lines(sampler, input, output, input_name)
}

/// The whole command: read the texture, build the pyramid, sample `input`
/// into `output` (the original sampler unless a GPU-sampler option is
/// set; anisotropic lines need one, `--max-aniso` counts).
///
/// # Errors
/// See [`SampleError`].
pub fn run<R: BufRead, W: Write>(
    args: &SampleArgs,
    input: R,
    output: W,
) -> Result<usize, SampleError> {
    let img = read_ppm(&args.texture).map_err(SampleError::Texture)?;
    let (state, format) = args.state().map_err(SampleError::Options)?;
    let mut pyramid = build_pyramid(&img, args.levels, &args.texture)?;
    let precision = args.precision.precision();
    if !args.uses_sampler_state() {
        // RGBA8 in memory, wrap or clamp, no state: read directly.
        let view = view(&pyramid, "<stdin>")?;
        let sampler = DynSampler::new(view, state, ColorSpace::Linear, precision);
        return run_lines(sampler, input, output, "<stdin>");
    }
    if args.srgb {
        // Regenerate the levels in linear space.
        raymip::texture::storage::srgb::generate(&pyramid.geometry, &mut pyramid.texels).map_err(
            |error| SampleError::Pyramid {
                path: args.texture.clone(),
                error,
                levels: args.levels,
            },
        )?;
    }
    sample_lines_state(
        &pyramid,
        (state, format, precision),
        input,
        output,
        "<stdin>",
    )
}

#[cfg(test)]
mod address_tests {
    use super::{AddressArg, AddressMode};
    use clap::ValueEnum;

    /// Each command-line name selects the mode it names, and every mode has one.
    #[test]
    fn address_names_select_their_modes() {
        let named = [
            ("wrap", AddressMode::Wrap),
            ("clamp", AddressMode::ClampToEdge),
            ("mirror", AddressMode::Mirror),
            ("mirror-once", AddressMode::MirrorOnce),
            ("border", AddressMode::ClampToBorder),
        ];
        assert_eq!(AddressArg::value_variants().len(), AddressMode::ALL.len());
        for (name, mode) in named {
            assert_eq!(
                AddressArg::from_str(name, false).map(AddressArg::mode),
                Ok(mode),
                "{name}"
            );
        }
    }
}
