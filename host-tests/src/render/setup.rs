//! Set-up of a scene for rendering at one size: BVH, pyramids, Pb tables,
//! camera frame.

use std::time::Instant;

use raymip::table::{Log2Pb, PbTable, PixelSpread, TexTriangle};
use rayon::prelude::*;
use serde::Serialize;

use super::bvh::Bvh;
use super::texunit::{MipTexture, assign_block_bases};
use crate::reference::log2_pb_f64;
use crate::scene::{Scene, V3, v};

/// Set-up timings (seconds).
#[derive(Clone, Debug, Default, Serialize)]
pub struct SetupTimes {
    /// BVH build.
    pub bvh_s: f64,
    /// MIP pyramids.
    pub pyramids_s: f64,
    /// Pb tables (fixed and f64).
    pub table_s: f64,
}

/// A scene ready to render at one image size.
#[derive(Debug)]
pub struct Prepared {
    /// The scene.
    pub scene: Scene,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// BVH.
    pub bvh: Bvh,
    /// Pyramids (block bases assigned).
    pub textures: Vec<MipTexture>,
    /// Firmware `log2 Pb` per triangle.
    pub pb_fixed: Vec<Log2Pb>,
    /// f64 `log2 Pb` per triangle (NaN = untextured).
    pub pb_float: Vec<f64>,
    /// Firmware pixel spread.
    pub spread: PixelSpread,
    /// f64 pixel spread angle γ (radians).
    pub gamma: f64,
    /// Scene bounding-box diagonal (for ray offsets).
    pub scale: f64,
    /// Set-up timings.
    pub times: SetupTimes,
    pub(crate) cam: CameraFrame,
}

/// A pinhole camera's orthonormal frame at one image size.
#[derive(Clone, Copy, Debug)]
pub struct CameraFrame {
    /// Eye position.
    pub eye: V3,
    /// Unit view direction.
    pub fwd: V3,
    /// Unit right vector.
    pub right: V3,
    /// Unit up vector.
    pub up: V3,
    /// Film-plane size of one pixel at distance 1.
    pub px: f64,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

impl CameraFrame {
    /// The frame of camera `c` rendering `width`×`height` pixels.
    #[must_use]
    pub fn new(c: &crate::scene::Camera, width: u32, height: u32) -> Self {
        let fov = c.fov_y_deg.to_radians();
        let fwd = v::norm(v::sub(c.at, c.from));
        let mut right = v::norm(v::cross(fwd, c.up));
        if v::len(right) < 0.5 {
            right = v::norm(v::cross(fwd, [0.0, 0.0, 1.0]));
            if v::len(right) < 0.5 {
                right = v::norm(v::cross(fwd, [1.0, 0.0, 0.0]));
            }
        }
        let up = v::cross(right, fwd);
        Self {
            eye: c.from,
            fwd,
            right,
            up,
            px: 2.0 * (fov / 2.0).tan() / f64::from(height),
            width,
            height,
        }
    }

    /// Unnormalised direction through film point `(fx, fy)` (pixels from
    /// the top-left corner; `x + 0.5` is a pixel centre).
    #[must_use]
    pub fn dir(&self, fx: f64, fy: f64) -> V3 {
        let sx = (fx - f64::from(self.width) / 2.0) * self.px;
        let sy = (f64::from(self.height) / 2.0 - fy) * self.px;
        v::add(
            v::add(self.fwd, v::scale(self.right, sx)),
            v::scale(self.up, sy),
        )
    }
}

impl Prepared {
    /// Builds BVH, pyramids and tables; `size` overrides the camera's.
    pub fn new(scene: Scene, size: Option<(u32, u32)>) -> Result<Self, String> {
        let (width, height) = size.unwrap_or((scene.camera.width, scene.camera.height));
        if width == 0 || height == 0 {
            return Err("image size must be at least 1x1".into());
        }
        let fov = scene.camera.fov_y_deg.to_radians();
        let spread = PixelSpread::from_fov_y(fov, height)
            .map_err(|e| format!("camera: {e} (fov_y {} deg)", scene.camera.fov_y_deg))?;
        let gamma = (2.0 * (fov / 2.0).tan() / f64::from(height)).atan();
        for (i, t) in scene.triangles.iter().enumerate() {
            if scene.materials.get(t.material as usize).is_none() {
                return Err(format!(
                    "triangle {i}: material {} does not exist",
                    t.material
                ));
            }
            if let Some(x) = t.texture
                && scene.textures.get(x as usize).is_none()
            {
                return Err(format!("triangle {i}: texture {x} does not exist"));
            }
        }
        let t0 = Instant::now();
        let bvh = Bvh::build(scene.triangles.iter().map(|t| t.p).collect());
        let bvh_s = t0.elapsed().as_secs_f64();
        let t0 = Instant::now();
        let mut textures = scene
            .textures
            .par_iter()
            .map(MipTexture::new)
            .collect::<Result<Vec<_>, _>>()?;
        assign_block_bases(&mut textures);
        let pyramids_s = t0.elapsed().as_secs_f64();
        let t0 = Instant::now();
        let mut tex_tris = Vec::with_capacity(scene.triangles.len());
        let mut pb_float = Vec::with_capacity(scene.triangles.len());
        for (i, t) in scene.triangles.iter().enumerate() {
            match (t.texture, t.uv) {
                (Some(x), Some(uv)) => {
                    let tex = &scene.textures[x as usize];
                    let p32 = t.p.map(|p| p.map(|c| c as f32));
                    let uv32 = uv.map(|q| q.map(|c| c as f32));
                    let tt = TexTriangle::from_f32(p32, uv32, tex.width, tex.height)
                        .map_err(|e| format!("triangle {i}: {e}"))?;
                    tex_tris.push(Some(tt));
                    pb_float.push(log2_pb_f64(&t.p, &uv, tex.width, tex.height, gamma));
                }
                _ => {
                    tex_tris.push(None);
                    pb_float.push(f64::NAN);
                }
            }
        }
        let mut pb_fixed = vec![Log2Pb::UNTEXTURED; scene.triangles.len()];
        PbTable::new(&mut pb_fixed)
            .build(tex_tris, &spread)
            .map_err(|e| format!("Pb table: {e}"))?;
        let table_s = t0.elapsed().as_secs_f64();
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for t in &scene.triangles {
            for p in &t.p {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        }
        let scale = if scene.triangles.is_empty() {
            1.0
        } else {
            v::len(v::sub(hi, lo)).max(1e-9)
        };
        let cam = CameraFrame::new(&scene.camera, width, height);
        Ok(Self {
            scene,
            width,
            height,
            bvh,
            textures,
            pb_fixed,
            pb_float,
            spread,
            gamma,
            scale,
            times: SetupTimes {
                bvh_s,
                pyramids_s,
                table_s,
            },
            cam,
        })
    }

    /// Ray offset along the normal at continuation rays (scene units:
    /// 10⁻⁷ of the scene diagonal).
    pub(crate) fn eps(&self) -> f64 {
        1e-7 * self.scale
    }

    /// Unnormalized primary direction through film point `(fx, fy)` (pixels,
    /// origin top-left) and its derivatives per pixel in x and y.
    pub(crate) fn primary_dir(&self, fx: f64, fy: f64) -> (V3, V3, V3) {
        let c = &self.cam;
        (
            c.dir(fx, fy),
            v::scale(c.right, c.px),
            v::scale(c.up, -c.px),
        )
    }
}
