//! The camera of a render at one image size: the frame of the primary rays
//! and the pixel spread angle `γ`, computed once (f64 for the float paths,
//! the firmware's [`PixelSpread`] from the same field of view for the fixed
//! path, [`CameraFrame::pixel_spread`]).

use raymip::setup::camera::PixelSpread;

use super::RenderError;
use crate::scene::{Camera, V3};

/// Primary-ray frame and pixel spread of a camera at one image size.
#[derive(Clone, Copy, Debug)]
pub struct CameraFrame {
    /// Eye position.
    pub eye: V3,
    /// Unit view direction.
    pub fwd: V3,
    /// Unit right vector.
    pub right: V3,
    /// Unit up vector (orthogonal to `fwd` and `right`).
    pub up: V3,
    /// Film-plane size of one pixel at distance 1: `2·tan(fov_y/2)/H`.
    pub px: f64,
    /// f64 pixel spread angle `γ = atan(px)` (radians).
    pub gamma: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

impl CameraFrame {
    /// The frame of `camera` for a `width × height` image (both ≥ 1).
    #[must_use]
    pub fn new(camera: &Camera, width: u32, height: u32) -> Self {
        let fov = camera.fov_y_deg.to_radians();
        let px = 2.0 * (fov / 2.0).tan() / f64::from(height);
        let fwd = (camera.at - camera.from).normalize_or_zero();
        let mut right = fwd.cross(camera.up).normalize_or_zero();
        if right.length() < 0.5 {
            right = fwd.cross(V3::new(0.0, 0.0, 1.0)).normalize_or_zero();
            if right.length() < 0.5 {
                right = fwd.cross(V3::new(1.0, 0.0, 0.0)).normalize_or_zero();
            }
        }
        Self {
            eye: camera.from,
            fwd,
            right,
            up: right.cross(fwd),
            px,
            gamma: px.atan(),
            width,
            height,
        }
    }

    /// The firmware's pixel spread for this camera (`PixelSpread::from_fov_y`).
    ///
    /// # Errors
    /// When the firmware rejects the field of view.
    pub fn pixel_spread(camera: &Camera, height: u32) -> Result<PixelSpread, RenderError> {
        PixelSpread::from_fov_y(camera.fov_y_deg.to_radians(), height).map_err(|source| {
            RenderError::Camera {
                fov_y_deg: camera.fov_y_deg,
                source,
            }
        })
    }

    /// Unnormalised direction through film point `(fx, fy)` (pixels from
    /// the top-left corner; `x + 0.5` is a pixel centre).
    #[must_use]
    pub fn dir(&self, fx: f64, fy: f64) -> V3 {
        self.primary_dir(fx, fy).0
    }

    /// Unnormalized primary direction through film point `(fx, fy)` (pixels,
    /// origin top-left) and its derivatives per pixel in x and y.
    #[must_use]
    pub fn primary_dir(&self, fx: f64, fy: f64) -> (V3, V3, V3) {
        let sx = (fx - f64::from(self.width) / 2.0) * self.px;
        let sy = (f64::from(self.height) / 2.0 - fy) * self.px;
        let d = (self.fwd + (self.right * sx)) + (self.up * sy);
        (d, self.right * self.px, self.up * -self.px)
    }
}
