//! Rays that leave the scene: a latitude-longitude environment map
//! (`Scene::environment`) sampled at the method's environment-map lod
//! (Ray Tracing Gems ch. 21; the firmware's `raymip::envmap`), through the
//! same texture units as surface hits ([`Unit`]: the firmware sampler in
//! fixed point, the f64 one in float).
//!
//! | method | lod of a miss (fixed: firmware; float: `reference::envmap`) |
//! |---|---|
//! | mip0, truth | 0 (bilinear in level 0, the method's filter) |
//! | table | the camera's pixel spread `γ` as the cone spread (the table method assumes flat surfaces) |
//! | cone | the path's cone spread angle |
//! | raydiff | the larger of `∂D/∂x`, `∂D/∂y` |
//!
//! All three with the pole term of the ray's direction (`−log2 cos φ`).
//! Addressing wraps on both axes (the units' one mode): the seam in `u` is
//! seamless, the poles blend with the opposite row at coarse levels.

use raymip::envmap::{EnvMap, direction_uv};
use raymip::lod::Lod;
use raymip::raystack::{PathState, UnitVec};

use super::lod::HitLod;
use super::texunit::{FetchLog, Filter, MipTexture, Unit};
use super::{Method, Options, Precision};
use crate::reference::envmap as reference;
use crate::scene::{TextureImage, V3};

/// An environment map ready to sample: its pyramid and the firmware's lod
/// constants.
#[derive(Clone, Debug)]
pub struct EnvLookup {
    /// The full pyramid (firmware `mip::generate`).
    pub tex: MipTexture,
    /// The firmware constants of its size.
    pub map: EnvMap,
}

/// What a miss reads of its ray: f64 direction and differentials, the
/// quantised direction the firmware takes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MissRay {
    /// Unit direction.
    pub d: V3,
    /// The same, firmware I2F30.
    pub dq: UnitVec,
    /// f64 cone spread angle (radians).
    pub spread: f64,
    /// f64 direction differentials per pixel in x and y.
    pub ddx: V3,
    /// The same in y.
    pub ddy: V3,
}

impl EnvLookup {
    /// The pyramid and constants of `img`.
    ///
    /// # Errors
    /// A size outside the firmware's `1 ..= 2¹⁵` or one that cannot form
    /// a pyramid.
    pub fn new(img: &TextureImage) -> Result<Self, String> {
        let map = EnvMap::new(img.width, img.height)
            .map_err(|e| format!("environment {}: {e}", img.name))?;
        Ok(Self {
            tex: MipTexture::new(img)?,
            map,
        })
    }

    /// The lod of a miss for the render's method and precision (table
    /// above); `state` is the path's firmware state, `gamma` the camera's
    /// pixel spread (the firmware's and f64).
    pub(crate) fn lod(
        &self,
        opts: &Options,
        state: &PathState,
        gamma: (raymip::raystack::Spread, f64),
        ray: &MissRay,
    ) -> HitLod {
        let fixed = opts.precision == Precision::Fixed;
        let (w, h) = (self.tex.width, self.tex.height);
        let d = Some(ray.d.to_array());
        match opts.method {
            Method::Mip0 | Method::Truth if fixed => HitLod::Fixed(Lod::ZERO),
            Method::Mip0 | Method::Truth => HitLod::Float(0.0),
            Method::Table if fixed => HitLod::Fixed(self.map.cone_lod(gamma.0, Some(ray.dq))),
            Method::Table => HitLod::Float(reference::cone_lod_f64(w, h, gamma.1, d)),
            Method::Cone if fixed => {
                HitLod::Fixed(self.map.cone_lod(state.cone.spread, Some(ray.dq)))
            }
            Method::Cone => HitLod::Float(reference::cone_lod_f64(w, h, ray.spread, d)),
            Method::Raydiff if fixed => HitLod::Fixed(self.map.raydiff_lod(
                state.diff.dddx,
                state.diff.dddy,
                Some(ray.dq),
            )),
            Method::Raydiff => HitLod::Float(reference::raydiff_lod_f64(
                w,
                h,
                ray.ddx.to_array(),
                ray.ddy.to_array(),
                d,
            )),
        }
    }

    /// The map's colour for a miss at `lod` with the method's filter:
    /// `(u, v)` from the firmware's CORDIC mapping in fixed point, from
    /// f64 in float; one sample of a texture unit of the render's
    /// precision (fetches not counted with the surface hits').
    pub(crate) fn color(&self, opts: &Options, lod: HitLod, ray: &MissRay) -> V3 {
        let fixed = opts.precision == Precision::Fixed;
        let (u, v) = if fixed {
            let (u, v) = direction_uv(ray.dq);
            (u.to_num(), v.to_num())
        } else {
            reference::direction_uv_f64(ray.d.to_array())
        };
        let mut unit = Unit::new(std::slice::from_ref(&self.tex), fixed, false, None);
        let filter = Filter::of(opts.method);
        V3::from(unit.sample(0, u, v, lod, filter, 0, &mut FetchLog::default()))
    }
}
