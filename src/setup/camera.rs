//! The camera's pixel spread angle `γ = atan(2·tan(fov_y/2)/H)` (radians,
//! I2F30) with its `log2` precomputed.
//!
//! It is the camera constant of the Pb table (`log2 Pb = −Δ − log2 γ`, see
//! [`table`](crate::setup::table)) and of the primary ray cone. Set up once
//! per camera and image height.

use fixed::types::I16F16;

use crate::log2::log2_bits;
use crate::units::Spread;

unit_error! {
    /// Errors of the camera set-up.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    #[non_exhaustive]
    pub enum CameraError {
        /// The field of view was NaN or infinite.
        NonFinite => "field of view is NaN or infinite",
        /// Field of view outside `(0, π)` radians or pixel spread outside `(0, 2)`.
        BadAngle => "field of view must be in (0, pi), pixel spread in (0, 2) radians",
        /// Image height was zero.
        ZeroImageHeight => "image height is zero",
    }
}

/// The pixel spread angle `γ` of a camera (radians, I2F30, range `(0, 2)`)
/// with its log2 precomputed.
///
/// # Example
/// ```
/// use raymip::PixelSpread;
/// // 60° vertical field of view over 480 rows: γ ≈ 2·tan(30°)/480 radians.
/// let spread = PixelSpread::from_fov_y(60f64.to_radians(), 480)?;
/// let expected = (2.0 * 30f64.to_radians().tan() / 480.0).atan();
/// assert!((spread.angle().to_num::<f64>() - expected).abs() < 1e-6);
/// assert!(PixelSpread::from_fov_y(f64::NAN, 480).is_err());
/// # Ok::<(), raymip::CameraError>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelSpread {
    angle: Spread,
    log2: I16F16,
}

impl PixelSpread {
    /// From the angle itself (radians, `0 < γ < 2`); float-free.
    pub fn from_angle(angle: Spread) -> Result<Self, CameraError> {
        if angle <= Spread::ZERO {
            return Err(CameraError::BadAngle);
        }
        Ok(Self {
            angle,
            log2: log2_bits(angle.to_bits() as u64, 30),
        })
    }

    /// `γ = atan(2·tan(fov_y/2)/H)` from the full vertical field of view
    /// (radians, `0 < fov_y < π`) and the image height in pixels (≥ 1).
    /// Set-up only: uses `libm` floats.
    pub fn from_fov_y(fov_y: f64, image_height: u32) -> Result<Self, CameraError> {
        if !fov_y.is_finite() {
            return Err(CameraError::NonFinite);
        }
        if !(fov_y > 0.0 && fov_y < core::f64::consts::PI) {
            return Err(CameraError::BadAngle);
        }
        if image_height == 0 {
            return Err(CameraError::ZeroImageHeight);
        }
        let g = libm::atan(2.0 * libm::tan(fov_y / 2.0) / f64::from(image_height));
        let a = Spread::checked_from_num(g).ok_or(CameraError::BadAngle)?;
        Self::from_angle(a)
    }

    /// `γ` in radians (I2F30).
    #[must_use]
    pub const fn angle(&self) -> Spread {
        self.angle
    }

    /// `log2 γ` (I16F16; error ≤ [`LOG2_MAX_ERROR`](crate::log2::LOG2_MAX_ERROR)).
    #[must_use]
    pub const fn log2(&self) -> I16F16 {
        self.log2
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;

    #[test]
    fn pixel_spread_from_fov() {
        let s = PixelSpread::from_fov_y(40f64.to_radians(), 600).unwrap();
        let want = (2.0 * (20f64.to_radians()).tan() / 600.0).atan();
        assert!((s.angle().to_num::<f64>() - want).abs() < 1e-9);
        assert!((s.log2().to_num::<f64>() - want.log2()).abs() <= crate::log2::LOG2_MAX_ERROR);
        assert_eq!(
            PixelSpread::from_fov_y(0.0, 600),
            Err(CameraError::BadAngle)
        );
        assert_eq!(
            PixelSpread::from_fov_y(4.0, 600),
            Err(CameraError::BadAngle)
        );
        // The open interval's ends: π itself is out (tan(π/2) is finite in
        // f64, so only the check stops it), the largest f64 below π is in.
        let pi = core::f64::consts::PI;
        assert_eq!(PixelSpread::from_fov_y(pi, 600), Err(CameraError::BadAngle));
        assert!(PixelSpread::from_fov_y(f64::from_bits(pi.to_bits() - 1), 600).is_ok());
        assert_eq!(
            PixelSpread::from_fov_y(f64::NAN, 600),
            Err(CameraError::NonFinite)
        );
        assert_eq!(
            PixelSpread::from_fov_y(1.0, 0),
            Err(CameraError::ZeroImageHeight)
        );
        assert_eq!(
            PixelSpread::from_angle(Spread::ZERO),
            Err(CameraError::BadAngle)
        );
        assert_eq!(
            PixelSpread::from_angle(Spread::from_num(-0.1)),
            Err(CameraError::BadAngle)
        );
    }
}
