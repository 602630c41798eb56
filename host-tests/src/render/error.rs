//! Why a render could not be set up: options that do not go together, an
//! empty image, a camera or triangle the firmware rejects, a scene that
//! refers to a material or texture it does not have.

use std::fmt;

use raymip::geomlod::{ConfigError, RecordsFull};
use raymip::lod::envmap::EnvMapError;
use raymip::setup::camera::CameraError;
use raymip::setup::table::TableError;
use raymip::texture::storage::mip::MipError;

use super::Method;

/// Why a render could not be set up.
#[derive(Debug)]
pub enum RenderError {
    /// The image has zero width or height.
    EmptyImage {
        /// Width asked for, pixels.
        width: u32,
        /// Height asked for, pixels.
        height: u32,
    },
    /// `--filter aniso` with a method that gives no footprint axes.
    AnisoNeedsRaydiff {
        /// The method given.
        method: Method,
    },
    /// `--transition` outside `[0, 1]`.
    Transition {
        /// The value given.
        value: f64,
    },
    /// The firmware rejects the camera's field of view.
    Camera {
        /// The vertical field of view, degrees.
        fov_y_deg: f64,
        /// The firmware's error.
        source: CameraError,
    },
    /// A triangle names a material the scene does not have.
    MissingMaterial {
        /// Triangle index.
        triangle: usize,
        /// The material index it names.
        material: u32,
    },
    /// A triangle names a texture the scene does not have.
    MissingTexture {
        /// Triangle index.
        triangle: usize,
        /// The texture index it names.
        texture: u32,
    },
    /// A texture cannot form a MIP pyramid.
    Pyramid {
        /// The texture's name (its file).
        texture: String,
        /// Width, texels.
        width: u32,
        /// Height, texels.
        height: u32,
        /// The firmware's error.
        source: MipError,
    },
    /// The firmware rejects the environment map's size.
    Environment {
        /// The map's name.
        texture: String,
        /// The firmware's error.
        source: EnvMapError,
    },
    /// The firmware rejects a textured triangle (coordinates out of range).
    Triangle {
        /// Triangle index.
        triangle: usize,
        /// The firmware's error.
        source: TableError,
    },
    /// The firmware's Pb table could not be built.
    PbTable(TableError),
    /// The firmware rejects the geometric-LOD settings (`--lod-bias`, range).
    GeomLod(ConfigError),
    /// The geometric-LOD record buffer is too small.
    Records(RecordsFull),
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::EmptyImage { width, height } => {
                write!(f, "image size {width}x{height}: must be at least 1x1")
            }
            Self::AnisoNeedsRaydiff { method } => write!(
                f,
                "--filter aniso needs the footprint axes of --method raydiff or gbuffer; --method {} \
                 gives an isotropic lod only (use --filter trilinear, or --method raydiff)",
                method.name()
            ),
            Self::Transition { value } => write!(f, "--transition {value}: must lie in [0, 1]"),
            Self::Camera { fov_y_deg, source } => {
                write!(f, "camera: {source} (fov_y {fov_y_deg} deg)")
            }
            Self::MissingMaterial { triangle, material } => {
                write!(f, "triangle {triangle}: material {material} does not exist")
            }
            Self::MissingTexture { triangle, texture } => {
                write!(f, "triangle {triangle}: texture {texture} does not exist")
            }
            Self::Pyramid {
                texture,
                width,
                height,
                source,
            } => write!(f, "texture {texture} ({width}x{height}): {source}"),
            Self::Environment { texture, source } => {
                write!(f, "environment map {texture}: {source}")
            }
            Self::Triangle { triangle, source } => write!(f, "triangle {triangle}: {source}"),
            Self::PbTable(e) => write!(f, "Pb table: {e}"),
            Self::GeomLod(e) => write!(f, "geometric LOD settings: {e}"),
            Self::Records(e) => write!(f, "geometric LOD records: {e}"),
        }
    }
}

impl std::error::Error for RenderError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Camera { source, .. } => Some(source),
            Self::Pyramid { source, .. } => Some(source),
            Self::Environment { source, .. } => Some(source),
            Self::Triangle { source, .. } | Self::PbTable(source) => Some(source),
            Self::GeomLod(e) => Some(e),
            Self::Records(e) => Some(e),
            Self::EmptyImage { .. }
            | Self::AnisoNeedsRaydiff { .. }
            | Self::Transition { .. }
            | Self::MissingMaterial { .. }
            | Self::MissingTexture { .. } => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::error::Error as _;

    #[test]
    fn display_names_the_option_and_the_item() {
        let e = RenderError::AnisoNeedsRaydiff {
            method: Method::Cone,
        };
        assert!(e.to_string().contains("--method cone"), "{e}");
        let e = RenderError::Transition { value: 1.5 };
        assert!(e.to_string().starts_with("--transition 1.5:"), "{e}");
        let e = RenderError::MissingTexture {
            triangle: 7,
            texture: 3,
        };
        assert_eq!(e.to_string(), "triangle 7: texture 3 does not exist");
        let e = RenderError::EmptyImage {
            width: 0,
            height: 4,
        };
        assert!(e.to_string().contains("0x4"), "{e}");
        let e = RenderError::Camera {
            fov_y_deg: 200.0,
            source: CameraError::BadAngle,
        };
        assert!(e.to_string().contains("fov_y 200 deg"), "{e}");
        assert!(e.source().is_some());
    }
}
