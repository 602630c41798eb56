//! Files and figures the commands write: PNG images and the mip-level
//! palette ([`image`]), image differences ([`metrics`]: PSNR, largest
//! difference, heat maps), JSON, text and README blocks ([`report`]), the
//! machine line of a measurement ([`machine`]). Below every command
//! (`cli`), the trade-off study (`tradeoff`) and the examples.

use std::fmt;
use std::path::PathBuf;

use crate::error::FileError;

pub mod image;
pub mod machine;
pub mod metrics;
pub mod report;

/// What went wrong writing or reading an output file.
#[derive(Debug)]
pub enum OutputError {
    /// The file could not be opened, created, read or written.
    File(FileError),
    /// The PNG encoder failed on the file.
    PngEncode {
        /// The file.
        path: PathBuf,
        /// The encoder's error.
        source: png::EncodingError,
    },
    /// The file is not a readable PNG.
    PngDecode {
        /// The file.
        path: PathBuf,
        /// The decoder's error.
        source: png::DecodingError,
    },
    /// The PNG is not 8-bit RGB or RGBA.
    PngFormat {
        /// The file.
        path: PathBuf,
        /// Its colour type.
        color: png::ColorType,
        /// Its bit depth.
        depth: png::BitDepth,
    },
    /// A value could not be serialised as JSON.
    Json {
        /// The file it was meant for.
        path: PathBuf,
        /// Serde's error.
        source: serde_json::Error,
    },
    /// The file lacks the `<!-- NAME:begin -->` / `<!-- NAME:end -->` lines.
    MissingMarkers {
        /// The file.
        path: PathBuf,
        /// The block's `NAME`.
        name: String,
    },
    /// The end marker comes before the begin marker.
    MarkersOutOfOrder {
        /// The file.
        path: PathBuf,
        /// The block's `NAME`.
        name: String,
    },
}

impl fmt::Display for OutputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::File(e) => e.fmt(f),
            Self::PngEncode { path, source } => {
                write!(f, "{}: cannot encode PNG: {source}", path.display())
            }
            Self::PngDecode { path, source } => {
                write!(f, "{}: not a readable PNG: {source}", path.display())
            }
            Self::PngFormat { path, color, depth } => write!(
                f,
                "{}: unsupported PNG format {color:?} {depth:?} (expected 8-bit RGB or RGBA)",
                path.display()
            ),
            Self::Json { path, source } => {
                write!(f, "{}: cannot serialise JSON: {source}", path.display())
            }
            Self::MissingMarkers { path, name } => write!(
                f,
                "{}: markers <!-- {name}:begin --> / <!-- {name}:end --> not found",
                path.display()
            ),
            Self::MarkersOutOfOrder { path, name } => write!(
                f,
                "{}: <!-- {name}:end --> before <!-- {name}:begin -->",
                path.display()
            ),
        }
    }
}

impl std::error::Error for OutputError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::File(e) => Some(e),
            Self::PngEncode { source, .. } => Some(source),
            Self::PngDecode { source, .. } => Some(source),
            Self::Json { source, .. } => Some(source),
            Self::PngFormat { .. }
            | Self::MissingMarkers { .. }
            | Self::MarkersOutOfOrder { .. } => None,
        }
    }
}

impl From<FileError> for OutputError {
    fn from(e: FileError) -> Self {
        Self::File(e)
    }
}
