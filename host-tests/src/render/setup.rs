//! Set-up of a scene for rendering at one size: BVH, pyramids, Pb tables,
//! camera frame.

use std::time::Instant;

use raymip::lod::raydiff::RayDiffTriangle;
use raymip::setup::camera::PixelSpread;
use raymip::setup::table::{PbTable, TexTriangle};
use raymip::units::Log2Pb;
use rayon::prelude::*;
use serde::Serialize;

use super::RenderError;
use super::bvh::Bvh;
use super::camera::CameraFrame;
use super::envmap::EnvLookup;
use super::texunit::{MipTexture, assign_block_bases};
use crate::scene::{Scene, V3};
use raymip_reference::pb::log2_pb_f64;

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
    /// Firmware ray-differential constant per triangle (`None` =
    /// untextured), from the same fixed-point triangles as `pb_fixed`.
    pub rd_tris: Vec<Option<RayDiffTriangle>>,
    /// Scene bounding-box diagonal (for ray offsets).
    pub scale: f64,
    /// Set-up timings.
    pub times: SetupTimes,
    /// Camera frame (f64).
    pub cam: CameraFrame,
    /// The firmware's pixel spread of the camera.
    pub spread: PixelSpread,
    /// The scene's environment map, ready to sample (`None`: the
    /// background colour).
    pub env: Option<EnvLookup>,
}

impl Prepared {
    /// Builds BVH, pyramids and tables; `size` overrides the camera's.
    ///
    /// # Errors
    /// A zero image size, a bad camera, a missing material or texture, a
    /// texture that cannot form a pyramid, a triangle outside the firmware's
    /// coordinate range.
    pub fn new(scene: Scene, size: Option<(u32, u32)>) -> Result<Self, RenderError> {
        let (width, height) = size.unwrap_or((scene.camera.width, scene.camera.height));
        if width == 0 || height == 0 {
            return Err(RenderError::EmptyImage { width, height });
        }
        let spread = CameraFrame::pixel_spread(&scene.camera, height)?;
        let cam = CameraFrame::new(&scene.camera, width, height);
        check_references(&scene)?;
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
        let env = scene.environment.as_ref().map(EnvLookup::new).transpose()?;
        let pyramids_s = t0.elapsed().as_secs_f64();
        let t0 = Instant::now();
        let (pb_fixed, pb_float, rd_tris) = pb_tables(&scene, &cam, &spread)?;
        let table_s = t0.elapsed().as_secs_f64();
        let scale = scene_scale(&scene);
        Ok(Self {
            scene,
            width,
            height,
            bvh,
            textures,
            pb_fixed,
            pb_float,
            rd_tris,
            scale,
            times: SetupTimes {
                bvh_s,
                pyramids_s,
                table_s,
            },
            cam,
            spread,
            env,
        })
    }
}

impl Prepared {
    /// Ray offset along the normal at continuation rays (scene units:
    /// 10⁻⁷ of the scene diagonal).
    pub(crate) fn eps(&self) -> f64 {
        1e-7 * self.scale
    }
}

/// Every triangle's material and texture exist.
fn check_references(scene: &Scene) -> Result<(), RenderError> {
    for (i, t) in scene.triangles.iter().enumerate() {
        if scene.materials.get(t.material as usize).is_none() {
            return Err(RenderError::MissingMaterial {
                triangle: i,
                material: t.material,
            });
        }
        if let Some(x) = t.texture
            && scene.textures.get(x as usize).is_none()
        {
            return Err(RenderError::MissingTexture {
                triangle: i,
                texture: x,
            });
        }
    }
    Ok(())
}

/// Per-triangle LOD tables: the firmware Pb table (built by
/// `PbTable::build` from the triangles in f32, as a controller receives
/// them), the f64 one (NaN = untextured) and the firmware ray-differential
/// constants of the same fixed-point triangles.
type LodTables = (Vec<Log2Pb>, Vec<f64>, Vec<Option<RayDiffTriangle>>);

/// See [`LodTables`].
fn pb_tables(
    scene: &Scene,
    cam: &CameraFrame,
    spread: &PixelSpread,
) -> Result<LodTables, RenderError> {
    let mut tex_tris = Vec::with_capacity(scene.triangles.len());
    let mut pb_float = Vec::with_capacity(scene.triangles.len());
    for (i, t) in scene.triangles.iter().enumerate() {
        match (t.texture, t.uv) {
            (Some(x), Some(uv)) => {
                let tex = &scene.textures[x as usize];
                let p32 = t.p.map(|p| p.to_array().map(|c| c as f32));
                let uv32 = uv.map(|q| q.map(|c| c as f32));
                let tt =
                    TexTriangle::from_f32(p32, uv32, tex.width, tex.height).map_err(|source| {
                        RenderError::Triangle {
                            triangle: i,
                            source,
                        }
                    })?;
                tex_tris.push(Some(tt));
                pb_float.push(log2_pb_f64(
                    &t.p.map(|p| p.to_array()),
                    &uv,
                    f64::from(tex.width),
                    f64::from(tex.height),
                    cam.gamma,
                ));
            }
            _ => {
                tex_tris.push(None);
                pb_float.push(f64::NAN);
            }
        }
    }
    let rd_tris = tex_tris
        .iter()
        .map(|t| t.as_ref().map(RayDiffTriangle::new))
        .collect();
    let mut pb_fixed = vec![Log2Pb::UNTEXTURED; scene.triangles.len()];
    PbTable::new(&mut pb_fixed)
        .build(tex_tris, spread)
        .map_err(RenderError::PbTable)?;
    Ok((pb_fixed, pb_float, rd_tris))
}

/// Scene bounding-box diagonal (1 for an empty scene, at least 10⁻⁹).
fn scene_scale(scene: &Scene) -> f64 {
    let mut lo = V3::INFINITY;
    let mut hi = V3::NEG_INFINITY;
    for t in &scene.triangles {
        for p in &t.p {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    if scene.triangles.is_empty() {
        1.0
    } else {
        (hi - lo).length().max(1e-9)
    }
}
