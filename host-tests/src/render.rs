//! Whitted ray tracer: point lights with shadows, mirror reflection and
//! refraction up to `bounces` levels, the firmware [`RayStack`] /
//! [`PathState`] carrying `Pl` and the ray cone (with the surface spread
//! angle β of curved mirrors) along each path, and a
//! texture LOD chosen per [`Method`] and [`Precision`].
//!
//! Pixels are traversed in 8×8 tiles in row-major tile order (the order the
//! cache study replays); tiles are rendered in parallel with rayon.

use std::time::Instant;

use fixed::types::{U1F31, U32F32};
use indicatif::{ProgressBar, ProgressStyle};
use raymip::lod::{Lod, clamp_lod, cone_lod, table_lod};
use raymip::raystack::{PathState, RayStack};
use raymip::table::{Log2Pb, PbTable, PixelSpread, TexTriangle};
use rayon::prelude::*;
use serde::Serialize;

use crate::bvh::Bvh;
use crate::scene::{Scene, V3, v};
use crate::texunit::{
    FetchLog, Filter, FirmwareUnit, FloatUnit, MipTexture, TextureUnit, assign_block_bases,
};

/// Tile edge in pixels.
pub const TILE: u32 = 8;
/// Number of integer mip levels in the histogram.
pub const HIST_LEVELS: usize = 16;

/// Texture LOD method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Per-triangle Pb table and accumulated path length (Park et al.).
    Table,
    /// Ray cones (Akenine-Möller et al., RTG ch. 20), with the |n·d| term.
    Cone,
    /// Ray differentials (Igehy 1999), f64 only.
    Raydiff,
    /// No LOD: bilinear in level 0.
    Mip0,
    /// Ground truth: jittered supersampling, bilinear in level 0.
    Truth,
}

impl Method {
    /// Lower-case name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Table => "table",
            Self::Cone => "cone",
            Self::Raydiff => "raydiff",
            Self::Mip0 => "mip0",
            Self::Truth => "truth",
        }
    }
}

/// Arithmetic of the LOD and the texture unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Precision {
    /// Firmware fixed point (table, ray stack, lod, sampler).
    Fixed,
    /// f64 reference written in this crate.
    Float,
}

impl Precision {
    /// Lower-case name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Fixed => "fixed",
            Self::Float => "float",
        }
    }
}

/// Render options.
#[derive(Clone, Debug)]
pub struct Options {
    /// LOD method.
    pub method: Method,
    /// Precision.
    pub precision: Precision,
    /// Image size; `None` = the scene camera's.
    pub size: Option<(u32, u32)>,
    /// Maximum reflection/refraction depth (≤ 10 fits the ray stack).
    pub bounces: u8,
    /// Samples per pixel for [`Method::Truth`].
    pub spp: u32,
    /// Record the texel-block address of every fetch (firmware unit).
    pub record_blocks: bool,
    /// Show a progress bar.
    pub progress: bool,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            method: Method::Table,
            precision: Precision::Fixed,
            size: None,
            bounces: 10,
            spp: 256,
            record_blocks: false,
            progress: false,
        }
    }
}

/// Counters of one render.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Counters {
    /// Camera paths started (pixels × spp).
    pub paths: u64,
    /// Ray segments traced (primary + secondary).
    pub rays: u64,
    /// Segments that hit a triangle.
    pub hits: u64,
    /// Hits on textured triangles (texture path taken).
    pub textured_hits: u64,
    /// Hits on untextured triangles (texture path skipped).
    pub untextured_skipped: u64,
    /// Textured hits per selected integer mip level 0..15 (clamped lod, floor).
    pub level_hist: [u64; HIST_LEVELS],
    /// Hits per path depth (index = bounces before the hit).
    pub depth_hist: Vec<u64>,
    /// Reflection/refraction continuations pushed on the ray stack.
    pub bounces: u64,
    /// Continuations dropped because the ray stack was full.
    pub stack_full: u64,
    /// Hits whose path state saturated (lod is then a bound).
    pub saturations: u64,
    /// Shadow rays.
    pub shadow_rays: u64,
    /// Texels fetched.
    pub fetched: u64,
    /// Texel fetches skipped by the filter.
    pub fetch_skipped: u64,
}

impl Counters {
    fn add(&mut self, o: &Counters) {
        self.paths += o.paths;
        self.rays += o.rays;
        self.hits += o.hits;
        self.textured_hits += o.textured_hits;
        self.untextured_skipped += o.untextured_skipped;
        for (a, b) in self.level_hist.iter_mut().zip(o.level_hist.iter()) {
            *a += b;
        }
        if self.depth_hist.len() < o.depth_hist.len() {
            self.depth_hist.resize(o.depth_hist.len(), 0);
        }
        for (a, b) in self.depth_hist.iter_mut().zip(o.depth_hist.iter()) {
            *a += b;
        }
        self.bounces += o.bounces;
        self.stack_full += o.stack_full;
        self.saturations += o.saturations;
        self.shadow_rays += o.shadow_rays;
        self.fetched += o.fetched;
        self.fetch_skipped += o.fetch_skipped;
    }

    /// Deepest depth with a hit.
    #[must_use]
    pub fn max_depth(&self) -> usize {
        self.depth_hist.iter().rposition(|&n| n > 0).unwrap_or(0)
    }
}

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
    cam: CameraFrame,
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

    /// Unnormalized primary direction through film point `(fx, fy)` (pixels,
    /// origin top-left) and its derivatives per pixel in x and y.
    fn primary_dir(&self, fx: f64, fy: f64) -> (V3, V3, V3) {
        let c = &self.cam;
        (
            c.dir(fx, fy),
            v::scale(c.right, c.px),
            v::scale(c.up, -c.px),
        )
    }
}

/// f64 `log2 Pb = ½·log2(A/N) − log2 γ` (independent of the firmware).
#[must_use]
pub fn log2_pb_f64(p: &[V3; 3], uv: &[[f64; 2]; 3], w: u32, h: u32, gamma: f64) -> f64 {
    let a = 0.5 * v::len(v::cross(v::sub(p[1], p[0]), v::sub(p[2], p[0])));
    let n = 0.5
        * ((uv[1][0] - uv[0][0]) * (uv[2][1] - uv[0][1])
            - (uv[1][1] - uv[0][1]) * (uv[2][0] - uv[0][0]))
            .abs()
        * f64::from(w)
        * f64::from(h);
    0.5 * (a / n).log2() - gamma.log2()
}

/// Result of a render.
#[derive(Clone, Debug)]
pub struct Image {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Linear RGB per pixel, row-major (not clamped).
    pub rgb: Vec<[f32; 3]>,
    /// Unclamped lod of the first textured hit of each pixel's path
    /// (first sample for truth), or NaN.
    pub lod: Vec<f32>,
    /// Counters.
    pub counters: Counters,
    /// Fetched block addresses in tile order (when recorded).
    pub blocks: Option<Vec<u32>>,
    /// Wall-clock render time (s).
    pub render_s: f64,
}

impl Image {
    /// RGB8 pixels (clamped, rounded).
    #[must_use]
    pub fn to_rgb8(&self) -> Vec<[u8; 3]> {
        self.rgb
            .iter()
            .map(|c| c.map(|x| (x.clamp(0.0, 1.0) * 255.0).round() as u8))
            .collect()
    }
}

/// Ray-differential state (Igehy 1999): position and unit-direction
/// derivatives per pixel in x and y.
#[derive(Clone, Copy, Debug, Default)]
struct Diff {
    dpx: V3,
    dpy: V3,
    ddx: V3,
    ddy: V3,
}

/// Host side of one ray-stack entry (the firmware [`PathState`] carries the
/// fixed-point Pl and cone).
#[derive(Clone, Copy, Debug)]
struct Ray {
    o: V3,
    d: V3,
    weight: V3,
    tmin: f64,
    pl: f64,
    width: f64,
    spread: f64,
    diff: Diff,
}

struct Ctx<'a> {
    prep: &'a Prepared,
    opts: &'a Options,
    unit: &'a dyn TextureUnit,
    counters: Counters,
    log: FetchLog,
}

/// Renders an image.
#[must_use]
pub fn render(prep: &Prepared, opts: &Options) -> Image {
    let (w, h) = (prep.width, prep.height);
    let tiles_x = w.div_ceil(TILE);
    let tiles_y = h.div_ceil(TILE);
    let n_tiles = tiles_x * tiles_y;
    let bar = if opts.progress {
        let b = ProgressBar::new(u64::from(n_tiles));
        b.set_style(
            ProgressStyle::with_template(
                "{msg} [{elapsed_precise}] {wide_bar} {pos}/{len} tiles (eta {eta})",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        b.set_message(format!(
            "{} {} {}x{}",
            opts.method.name(),
            opts.precision.name(),
            w,
            h
        ));
        b
    } else {
        ProgressBar::hidden()
    };
    let unit: &dyn TextureUnit = match opts.precision {
        Precision::Fixed => &FirmwareUnit,
        Precision::Float => &FloatUnit,
    };
    let t0 = Instant::now();
    let tiles: Vec<_> = (0..n_tiles)
        .into_par_iter()
        .map(|ti| {
            let tx = ti % tiles_x;
            let ty = ti / tiles_x;
            let mut ctx = Ctx {
                prep,
                opts,
                unit,
                counters: Counters {
                    depth_hist: vec![0; usize::from(opts.bounces) + 1],
                    ..Counters::default()
                },
                log: FetchLog {
                    blocks: opts.record_blocks.then(Vec::new),
                    ..FetchLog::default()
                },
            };
            let mut px = Vec::new();
            for y in ty * TILE..((ty + 1) * TILE).min(h) {
                for x in tx * TILE..((tx + 1) * TILE).min(w) {
                    px.push((x, y, ctx.pixel(x, y)));
                }
            }
            bar.inc(1);
            ctx.counters.fetched = ctx.log.fetched;
            ctx.counters.fetch_skipped = ctx.log.skipped;
            (px, ctx.counters, ctx.log.blocks)
        })
        .collect();
    let render_s = t0.elapsed().as_secs_f64();
    bar.finish_and_clear();
    let mut rgb = vec![[0.0f32; 3]; (w * h) as usize];
    let mut lod = vec![f32::NAN; (w * h) as usize];
    let mut counters = Counters::default();
    let mut blocks = opts.record_blocks.then(Vec::new);
    for (px, c, b) in tiles {
        for (x, y, (col, l)) in px {
            let i = (y * w + x) as usize;
            rgb[i] = col.map(|c| c as f32);
            lod[i] = l as f32;
        }
        counters.add(&c);
        if let (Some(all), Some(b)) = (blocks.as_mut(), b) {
            all.extend_from_slice(&b);
        }
    }
    Image {
        width: w,
        height: h,
        rgb,
        lod,
        counters,
        blocks,
        render_s,
    }
}

/// Deterministic per-sample random numbers in [0, 1).
fn hash01(x: u32, y: u32, s: u32, k: u32) -> f64 {
    let mut z = u64::from(x)
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(u64::from(y).wrapping_mul(0xC2B2_AE3D_27D4_EB4F))
        .wrapping_add(u64::from(s).wrapping_mul(0x1656_67B1_9E37_79F9))
        .wrapping_add(u64::from(k));
    z ^= z >> 30;
    z = z.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z ^= z >> 27;
    z = z.wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

impl Ctx<'_> {
    fn pixel(&mut self, x: u32, y: u32) -> ([f64; 3], f64) {
        if self.opts.method == Method::Truth {
            let n = self.opts.spp.max(1);
            let k = (f64::from(n).sqrt() as u32).max(1);
            let mut acc = [0.0; 3];
            let mut first = f64::NAN;
            for s in 0..n {
                // Stratified k×k jitter for the first k² samples, uniform after.
                let (jx, jy) = if s < k * k {
                    (
                        (f64::from(s % k) + hash01(x, y, s, 0)) / f64::from(k),
                        (f64::from(s / k) + hash01(x, y, s, 1)) / f64::from(k),
                    )
                } else {
                    (hash01(x, y, s, 0), hash01(x, y, s, 1))
                };
                let (c, l) = self.path(f64::from(x) + jx, f64::from(y) + jy);
                acc = v::add(acc, c);
                if s == 0 {
                    first = l;
                }
            }
            (v::scale(acc, 1.0 / f64::from(n)), first)
        } else {
            self.path(f64::from(x) + 0.5, f64::from(y) + 0.5)
        }
    }

    /// Traces one camera path; returns colour and the first textured lod.
    fn path(&mut self, fx: f64, fy: f64) -> ([f64; 3], f64) {
        let prep = self.prep;
        let (dv, dxv, dyv) = prep.primary_dir(fx, fy);
        let dd = v::dot(dv, dv);
        let ddir = |r: V3| {
            v::scale(
                v::sub(v::scale(r, dd), v::scale(dv, v::dot(dv, r))),
                dd.powf(-1.5),
            )
        };
        let ray = Ray {
            o: prep.cam.eye,
            d: v::norm(dv),
            weight: [1.0; 3],
            tmin: 0.0,
            pl: 0.0,
            width: 0.0,
            spread: prep.gamma,
            diff: Diff {
                ddx: ddir(dxv),
                ddy: ddir(dyv),
                ..Diff::default()
            },
        };
        self.counters.paths += 1;
        let mut stack: RayStack = RayStack::new();
        let mut host: Vec<Ray> = Vec::with_capacity(12);
        let mut color = [0.0; 3];
        let mut first_lod = f64::NAN;
        if stack.push(PathState::primary(&prep.spread, 0xFF)).is_ok() {
            host.push(ray);
        }
        while let (Some(state), Some(ray)) = (stack.pop(), host.pop()) {
            self.segment(
                state,
                ray,
                &mut stack,
                &mut host,
                &mut color,
                &mut first_lod,
            );
        }
        (color, first_lod)
    }

    #[allow(clippy::too_many_lines)]
    fn segment(
        &mut self,
        state: PathState,
        ray: Ray,
        stack: &mut RayStack,
        host: &mut Vec<Ray>,
        color: &mut [f64; 3],
        first_lod: &mut f64,
    ) {
        let prep = self.prep;
        let scene = &prep.scene;
        self.counters.rays += 1;
        let eps = 1e-7 * prep.scale;
        let Some(hit) = prep.bvh.closest(ray.o, ray.d, ray.tmin, f64::INFINITY) else {
            *color = v::add(*color, v::mul(ray.weight, scene.background));
            return;
        };
        self.counters.hits += 1;
        let depth = usize::from(state.depth);
        if let Some(c) = self.counters.depth_hist.get_mut(depth) {
            *c += 1;
        }
        let t = hit.t;
        let state = state.advance(U32F32::saturating_from_num(t));
        if state.saturated {
            self.counters.saturations += 1;
        }
        let pl = ray.pl + t;
        let width = ray.width + ray.spread * t;
        let tri = &scene.triangles[hit.tri as usize];
        let mat = &scene.materials[tri.material as usize];
        let p = v::madd(ray.o, ray.d, t);
        let (b0, b1, b2) = (1.0 - hit.b1 - hit.b2, hit.b1, hit.b2);
        let e1 = v::sub(tri.p[1], tri.p[0]);
        let e2 = v::sub(tri.p[2], tri.p[0]);
        let gn_raw = v::cross(e1, e2);
        let gn2 = v::dot(gn_raw, gn_raw);
        let ng = v::norm(gn_raw);
        let entering = v::dot(ng, ray.d) < 0.0;
        // Ray-differential transfer to the hit plane.
        let transfer = |dp: V3, dd: V3| {
            let q = v::madd(dp, dd, t);
            let dt = -v::dot(q, ng) / v::dot(ray.d, ng);
            v::madd(q, ray.d, dt)
        };
        let dpx = transfer(ray.diff.dpx, ray.diff.ddx);
        let dpy = transfer(ray.diff.dpy, ray.diff.ddy);
        let bary_d = |dp: V3| {
            (
                v::dot(v::cross(dp, e2), gn_raw) / gn2,
                v::dot(v::cross(e1, dp), gn_raw) / gn2,
            )
        };
        let (db1x, db2x) = bary_d(dpx);
        let (db1y, db2y) = bary_d(dpy);
        // Shading normal (interpolated) and its differentials.
        let (mut ns, mut dnx, mut dny) = match tri.n {
            Some(n) => {
                let nn = v::add(
                    v::add(v::scale(n[0], b0), v::scale(n[1], b1)),
                    v::scale(n[2], b2),
                );
                let l2 = v::dot(nn, nn);
                if l2 > 0.0 {
                    let dn = |a: f64, b: f64| {
                        let d = v::add(
                            v::scale(v::sub(n[1], n[0]), a),
                            v::scale(v::sub(n[2], n[0]), b),
                        );
                        v::scale(
                            v::sub(v::scale(d, l2), v::scale(nn, v::dot(nn, d))),
                            l2.powf(-1.5),
                        )
                    };
                    (v::norm(nn), dn(db1x, db2x), dn(db1y, db2y))
                } else {
                    (ng, [0.0; 3], [0.0; 3])
                }
            }
            None => (ng, [0.0; 3], [0.0; 3]),
        };
        if v::dot(ns, ray.d) > 0.0 {
            ns = v::scale(ns, -1.0);
            dnx = v::scale(dnx, -1.0);
            dny = v::scale(dny, -1.0);
        }
        let face_ng = if entering { ng } else { v::scale(ng, -1.0) };

        // Texture.
        let mut kd = mat.diffuse;
        let textured = match (tri.texture, tri.uv) {
            (Some(x), Some(uv)) => Some((&prep.textures[x as usize], uv)),
            _ => None,
        };
        match textured {
            None => self.counters.untextured_skipped += 1,
            Some((tex, uv)) => {
                let u = b0 * uv[0][0] + b1 * uv[1][0] + b2 * uv[2][0];
                let vv = b0 * uv[0][1] + b1 * uv[1][1] + b2 * uv[2][1];
                let fixed = self.opts.precision == Precision::Fixed;
                let ndotd = v::dot(ng, ray.d).abs();
                let pbf = prep.pb_float[hit.tri as usize];
                let pbx = prep.pb_fixed[hit.tri as usize];
                let (lod, filter) = match self.opts.method {
                    Method::Mip0 | Method::Truth => (Some(0.0), Filter::BilinearLevel0),
                    Method::Table if fixed => (
                        table_lod(state.pl, pbx).map(|l| l.to_num::<f64>()),
                        Filter::Trilinear,
                    ),
                    Method::Table => (Some(pl.log2() - pbf), Filter::Trilinear),
                    Method::Cone if fixed => (
                        pbx.delta(&prep.spread).map(|delta| {
                            let nd = U1F31::saturating_from_num(ndotd);
                            cone_lod(state.cone.width, delta, Some(nd)).to_num::<f64>()
                        }),
                        Filter::Trilinear,
                    ),
                    Method::Cone => {
                        let delta = -pbf - prep.gamma.log2();
                        let w = if width == 0.0 {
                            2f64.powi(-32)
                        } else {
                            width.abs()
                        };
                        let nd = ndotd.clamp(2f64.powi(-16), 1.0);
                        (Some(delta + w.log2() - nd.log2()), Filter::Trilinear)
                    }
                    Method::Raydiff => {
                        let (tw, th) = (f64::from(tex.width), f64::from(tex.height));
                        let du = |a: f64, b: f64| {
                            let su = a * (uv[1][0] - uv[0][0]) + b * (uv[2][0] - uv[0][0]);
                            let sv = a * (uv[1][1] - uv[0][1]) + b * (uv[2][1] - uv[0][1]);
                            ((su * tw).powi(2) + (sv * th).powi(2)).sqrt()
                        };
                        let l = du(db1x, db2x).max(du(db1y, db2y)).max(1e-300).log2();
                        let l = if fixed {
                            Lod::saturating_from_num(l).to_num()
                        } else {
                            l
                        };
                        (Some(l), Filter::Trilinear)
                    }
                };
                match lod {
                    None => self.counters.untextured_skipped += 1,
                    Some(l) => {
                        self.counters.textured_hits += 1;
                        let top = f64::from(tex.levels - 1);
                        let level = if fixed {
                            clamp_lod(Lod::saturating_from_num(l), tex.levels).to_num::<f64>()
                        } else {
                            l.clamp(0.0, top)
                        };
                        let li = if level.is_nan() {
                            0
                        } else {
                            level.floor() as usize
                        };
                        self.counters.level_hist[li.min(HIST_LEVELS - 1)] += 1;
                        if first_lod.is_nan() {
                            *first_lod = l;
                        }
                        let c = self.unit.sample(tex, u, vv, l, filter, &mut self.log);
                        kd = v::mul(kd, c);
                    }
                }
            }
        }

        // Local shading.
        let mut local = v::mul(
            v::mul(scene.ambient, mat.ambient),
            if textured.is_some() {
                kd_ratio(kd, mat.diffuse)
            } else {
                [1.0; 3]
            },
        );
        let po = v::madd(p, face_ng, eps);
        for light in &scene.lights {
            let to = v::sub(light.position, po);
            let dist = v::len(to);
            let l = v::scale(to, 1.0 / dist);
            let nl = v::dot(ns, l);
            if nl <= 0.0 || v::dot(face_ng, l) <= 0.0 {
                continue;
            }
            let att = self.shadow(po, l, dist);
            if v::max_c(att) <= 0.0 {
                continue;
            }
            let hv = v::norm(v::sub(l, ray.d));
            let spec = v::dot(ns, hv).max(0.0).powf(mat.shine.max(1.0));
            let c = v::add(v::scale(kd, nl), v::scale(mat.specular, spec));
            local = v::add(local, v::mul(v::mul(c, light.color), att));
        }
        *color = v::add(*color, v::mul(ray.weight, local));

        // Continuations.
        if usize::from(state.depth) >= usize::from(self.opts.bounces) {
            return;
        }
        let mut refl_w = v::mul(ray.weight, mat.specular);
        let trans_w = v::mul(ray.weight, mat.transmission);
        let cosi = -v::dot(ray.d, ns);
        let mut refr: Option<Ray> = None;
        if v::max_c(trans_w) > 1e-3 {
            let eta = if entering {
                1.0 / mat.ior.max(1e-3)
            } else {
                mat.ior
            };
            let k = 1.0 - eta * eta * (1.0 - cosi * cosi);
            if k < 0.0 {
                refl_w = v::add(refl_w, trans_w);
            } else {
                let sk = k.sqrt();
                let mu = eta * cosi - sk;
                let mut dir = v::norm(v::add(v::scale(ray.d, eta), v::scale(ns, mu)));
                if v::dot(dir, face_ng) >= 0.0 {
                    // The interpolated normal bent the ray back out: refract
                    // about the geometric normal instead.
                    let c = -v::dot(ray.d, face_ng);
                    let kg = (1.0 - eta * eta * (1.0 - c * c)).max(0.0);
                    dir = v::norm(v::add(
                        v::scale(ray.d, eta),
                        v::scale(face_ng, eta * c - kg.sqrt()),
                    ));
                }
                let dtr = |dd: V3, dn: V3| {
                    let dcos = -(v::dot(dd, ns) + v::dot(ray.d, dn));
                    let dmu = (eta - eta * eta * cosi / sk) * dcos;
                    v::add(
                        v::add(v::scale(dd, eta), v::scale(ns, dmu)),
                        v::scale(dn, mu),
                    )
                };
                refr = Some(Ray {
                    o: v::madd(p, face_ng, -eps),
                    d: dir,
                    weight: trans_w,
                    tmin: 0.0,
                    pl,
                    width,
                    spread: ray.spread,
                    diff: Diff {
                        dpx,
                        dpy,
                        ddx: dtr(ray.diff.ddx, dnx),
                        ddy: dtr(ray.diff.ddy, dny),
                    },
                });
            }
        }
        let refl = (v::max_c(refl_w) > 1e-3).then(|| {
            let dn_ = v::dot(ray.d, ns);
            let mut dir = v::norm(v::madd(ray.d, ns, -2.0 * dn_));
            if v::dot(dir, face_ng) <= 0.0 {
                // Interpolated normal sends the ray below the surface:
                // reflect about the geometric normal instead.
                dir = v::norm(v::madd(ray.d, face_ng, -2.0 * v::dot(ray.d, face_ng)));
            }
            let drf = |dd: V3, dn: V3| {
                let ddn = v::dot(dd, ns) + v::dot(ray.d, dn);
                v::sub(
                    dd,
                    v::scale(v::add(v::scale(dn, dn_), v::scale(ns, ddn)), 2.0),
                )
            };
            Ray {
                o: po,
                d: dir,
                weight: refl_w,
                tmin: 0.0,
                pl,
                width,
                spread: ray.spread,
                diff: Diff {
                    dpx,
                    dpy,
                    ddx: drf(ray.diff.ddx, dnx),
                    ddy: drf(ray.diff.ddy, dny),
                },
            }
        });
        // Surface spread angle β of the reflected cone (curved surfaces):
        // across the cone's footprint (width |w|) the shading normal turns
        // by κ·|w|, κ = |dn|/|dp| from the ray differentials, and the
        // reflected direction by twice that; positive (spreading) on convex
        // surfaces (dp·dn > 0), negative on concave ones. Flat: 0.
        // Refracted cones keep β = 0.
        let kappa = |dp: V3, dn: V3| {
            let l = v::len(dp);
            if l > 0.0 { v::len(dn) / l } else { 0.0 }
        };
        let k = kappa(dpx, dnx).max(kappa(dpy, dny));
        let convex = v::dot(dpx, dnx) + v::dot(dpy, dny) >= 0.0;
        let beta = if k.is_finite() {
            let b = (2.0 * k * width.abs()).min(1.0);
            if convex { b } else { -b }
        } else {
            0.0
        };
        let beta_fixed = raymip::raystack::Spread::saturating_from_num(beta);
        let refl = refl.map(|mut r| {
            r.spread += if self.opts.precision == Precision::Fixed {
                beta_fixed.to_num::<f64>()
            } else {
                beta
            };
            (r, beta_fixed)
        });
        let refr = refr.map(|r| (r, raymip::raystack::Spread::ZERO));
        for (r, b) in [refr, refl].into_iter().flatten() {
            if stack.push(state.bounce(b)).is_ok() {
                host.push(r);
                self.counters.bounces += 1;
            } else {
                self.counters.stack_full += 1;
            }
        }
    }

    /// Transmission towards a light at `dist` (0 = blocked by an opaque surface).
    fn shadow(&mut self, o: V3, l: V3, dist: f64) -> V3 {
        let prep = self.prep;
        let mut att = [1.0; 3];
        let mut tmin = 0.0;
        for _ in 0..8 {
            self.counters.shadow_rays += 1;
            let Some(h) = prep.bvh.closest(o, l, tmin, dist) else {
                return att;
            };
            let m = &prep.scene.materials[prep.scene.triangles[h.tri as usize].material as usize];
            att = v::mul(att, m.transmission);
            if v::max_c(att) < 1e-3 {
                return [0.0; 3];
            }
            tmin = h.t + 1e-7 * prep.scale;
        }
        att
    }
}

/// Texture modulation factor `kd / diffuse` (1 where the diffuse is 0).
fn kd_ratio(kd: V3, diffuse: V3) -> V3 {
    std::array::from_fn(|k| {
        if diffuse[k] > 0.0 {
            kd[k] / diffuse[k]
        } else {
            1.0
        }
    })
}
