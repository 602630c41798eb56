//! Rays that leave the scene: a latitude-longitude environment map
//! (`Scene::environment`) sampled at the method's environment-map lod
//! (Ray Tracing Gems ch. 21; the firmware's `raymip::lod::envmap`), through the
//! same texture units as surface hits ([`Unit`]: the firmware sampler in
//! fixed point, the f64 one in float).
//!
//! | method | lod of a miss (fixed: firmware; float: `raymip_reference::envmap`) |
//! |---|---|
//! | mip0, truth | 0 (bilinear in level 0, the method's filter) |
//! | table | the camera's pixel spread `γ` as the cone spread (the table method assumes flat surfaces) |
//! | cone | the path's cone spread angle |
//! | raydiff | the larger of `∂D/∂x`, `∂D/∂y` |
//!
//! All three with the pole term of the ray's direction (`−log2 cos φ`).
//! Addressing wraps on both axes (the units' one mode): the seam in `u` is
//! seamless, the poles blend with the opposite row at coarse levels.

use raymip::lod::envmap::{EnvMap, direction_uv};
use raymip::path::raystack::PathState;
use raymip::units::{Lod, Spread, UnitVec};

use super::RenderError;
use super::options::{Method, Options};
use super::texunit::{FetchLog, Filter, MipTexture, Unit};
use crate::scene::{TextureImage, V3};
use raymip_reference::envmap as reference;

/// An environment map ready to sample: its pyramid and the firmware's lod
/// constants.
#[derive(Clone, Debug)]
pub struct EnvLookup {
    /// The full pyramid (firmware `mip::generate`).
    pub tex: MipTexture,
    /// The firmware constants of its size.
    pub map: EnvMap,
}

/// The f64 LOD state of a missing ray (float precision only): cone spread
/// and direction differentials.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FloatMiss {
    /// f64 cone spread angle (radians).
    pub spread: f64,
    /// f64 direction differentials per pixel in x.
    pub ddx: V3,
    /// The same in y.
    pub ddy: V3,
}

/// What a miss reads of its ray: the f64 direction, the quantised
/// direction the firmware takes, and (float precision only) the f64 LOD
/// state.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MissRay {
    /// Unit direction.
    pub d: V3,
    /// The same, firmware I2F30.
    pub dq: UnitVec,
    /// The f64 LOD state (`None` in fixed precision).
    pub float: Option<FloatMiss>,
}

impl EnvLookup {
    /// The pyramid and constants of `img`.
    ///
    /// # Errors
    /// [`RenderError::Environment`] for a size outside the firmware's
    /// `1 ..= 2¹⁵`, [`RenderError::Pyramid`] for one that cannot form a
    /// pyramid.
    pub fn new(img: &TextureImage) -> Result<Self, RenderError> {
        let map =
            EnvMap::new(img.width, img.height).map_err(|source| RenderError::Environment {
                texture: img.name.clone(),
                source,
            })?;
        Ok(Self {
            tex: MipTexture::new(img)?,
            map,
        })
    }

    /// The firmware lod of a miss for `method` (table above); `state` is
    /// the path's firmware state, `gamma` the camera's pixel spread.
    fn fixed_lod(&self, method: Method, state: &PathState, gamma: Spread, ray: &MissRay) -> Lod {
        match method {
            Method::Mip0 | Method::Truth => Lod::ZERO,
            Method::Table => self.map.cone_lod(gamma, Some(ray.dq)),
            Method::Cone => self.map.cone_lod(state.cone.spread, Some(ray.dq)),
            Method::Raydiff | Method::Gbuffer => {
                self.map
                    .raydiff_lod(state.diff.dddx, state.diff.dddy, Some(ray.dq))
            }
        }
    }

    /// The f64 lod of a miss for `method` (table above); `gamma` is the
    /// camera's pixel spread (radians).
    fn float_lod(&self, method: Method, gamma: f64, ray: &MissRay, f: &FloatMiss) -> f64 {
        let (w, h) = (self.tex.width, self.tex.height);
        let d = Some(ray.d.to_array());
        match method {
            Method::Mip0 | Method::Truth => 0.0,
            Method::Table => reference::cone_lod_f64(w, h, gamma, d),
            Method::Cone => reference::cone_lod_f64(w, h, f.spread, d),
            Method::Raydiff | Method::Gbuffer => {
                reference::raydiff_lod_f64(w, h, f.ddx.to_array(), f.ddy.to_array(), d)
            }
        }
    }

    /// The map's colour for a miss with the method's filter, at the
    /// method's lod in the arithmetic of the render's precision: the
    /// firmware lod, the CORDIC `(u, v)` and the firmware sampler in fixed
    /// point; f64 lod, `(u, v)` and sampler in float (one flow per unit, as
    /// for surface hits: no lod crosses between them). Fetches are not
    /// counted with the surface hits'.
    pub(crate) fn color(
        &self,
        opts: &Options,
        state: &PathState,
        gamma: (Spread, f64),
        ray: &MissRay,
    ) -> V3 {
        let fixed = ray.float.is_none();
        let mut unit = Unit::new(std::slice::from_ref(&self.tex), fixed, false, None);
        let filter = Filter::of(opts.method);
        let mut log = FetchLog::default();
        let rgb = match (&mut unit, &ray.float) {
            (Unit::Firmware(unit), _) => {
                let lod = self.fixed_lod(opts.method, state, gamma.0, ray);
                let (u, v) = direction_uv(ray.dq);
                unit.sample_rgb(0, u.to_num(), v.to_num(), lod, filter, 0, &mut log)
            }
            (Unit::Float(unit), Some(f)) => {
                let lod = self.float_lod(opts.method, gamma.1, ray, f);
                let (u, v) = reference::direction_uv_f64(ray.d.to_array());
                unit.sample(0, u, v, lod, filter, &mut log)
            }
            (Unit::Float(_), None) => [0.0; 3],
        };
        V3::from(rgb)
    }
}
