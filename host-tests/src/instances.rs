//! `builtin:instances`: stochastic geometric LOD end to end (NVIDIA, 2020,
//! "Implementing Stochastic Levels of Detail with DirectX Raytracing").
//!
//! A 64 × 60 grid of randomly rotated instances of one dense mesh
//! ([`crate::lodmesh`]: displaced icosphere, 81 920 triangles, 8 LODs
//! halving each time) on a reflective ground plane, in a two-level BVH
//! ([`crate::tlas`]). Per frame the firmware ([`raymip::geomlod`]) turns
//! each instance's camera-space depth into LOD records (one, or two with
//! complementary 8-bit masks during a transition); per path the firmware
//! generator ([`raymip::rng`]) draws one ray-mask bit, which the firmware
//! ray stack carries to every later ray of the path: reflection rays and
//! shadow rays are traced with the path's mask. Each hit of every ray is
//! checked against the primary ray's mask (a mismatch counter that must
//! stay 0).
//!
//! Shading: sun with shadow rays, ambient, checkered ground with a 35 %
//! mirror term, instances with a 15 % mirror term, up to `bounces`
//! reflections. A second image colours each pixel by the LOD of the
//! instance its primary ray hit (LOD 0 red … LOD 7 blue, ground grey, sky
//! black); averaging frames shows the cross-dissolve converging.

use std::path::Path;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use raymip::geomlod::{
    Depth, InstanceLod, LodBias, LodMode, LodRange, Selector, Transition, ray_mask, visible,
};
use raymip::raystack::{PathLength, PathState, RayStack, Spread};
use raymip::rng::Rng;
use raymip::table::PixelSpread;
use rayon::prelude::*;
use serde::Serialize;
use serde_json::json;

use crate::bvh::Bvh;
use crate::lodmesh::{displaced_icosphere, lod_chain};
use crate::output::{write_json, write_png, write_text};
use crate::render::CameraFrame;
use crate::scene::{Camera, V3, v};
use crate::tlas::{Instance, TwoLevel, TwoLevelStats, rotation_from_quaternion};

/// Instances along x and z.
pub const GRID: (u32, u32) = (64, 60);
/// Distance between neighbouring instances (scene units; the mesh radius
/// is about 1).
pub const SPACING: f64 = 3.0;
/// Number of LODs.
pub const LEVELS: u8 = 8;
/// Icosphere subdivisions of LOD 0 (20·4⁶ = 81 920 triangles).
pub const SUBDIVISIONS: u32 = 6;
/// Camera-space depth of LOD 0 (scene units).
pub const Z_NEAR: f64 = 4.0;
/// Camera-space depth where the LOD parameter reaches `L` = 8.
pub const Z_FAR: f64 = 300.0;
/// Default image size.
pub const DEFAULT_SIZE: (u32, u32) = (800, 480);
/// Index of the ground mesh in [`InstanceScene::meshes`].
pub const GROUND: u32 = LEVELS as u32;
/// Height of the instance centres above the ground.
const CENTRE_Y: f64 = 1.25;
/// Sun direction (towards the sun) and colour; ambient; sky.
const SUN: V3 = [-0.38, 0.85, 0.36];
const AMBIENT: f64 = 0.18;
const RAY_EPS: f64 = 1e-4;

/// Geometric LOD selection.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum GeomLodMode {
    /// Every instance at LOD 0.
    None,
    /// One LOD per instance from its depth (nearest level).
    Discrete,
    /// Two LODs with complementary masks inside the transition interval.
    Stochastic,
}

/// Camera views of the grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum View {
    /// Straight down from 250 units: every instance far (coarse LODs).
    Top,
    /// Oblique from 30 units up: near rows fine, far rows coarse.
    High,
    /// Grazing, 3 units above the ground across the whole grid.
    Low,
    /// A few units from one instance of the front row.
    Close,
}

impl View {
    /// Every view.
    pub const ALL: [Self; 4] = [Self::Top, Self::High, Self::Low, Self::Close];

    /// Lower-case name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Top => "top",
            Self::High => "high",
            Self::Low => "low",
            Self::Close => "close",
        }
    }

    /// The camera at `width`×`height`.
    #[must_use]
    pub fn camera(self, width: u32, height: u32) -> Camera {
        let front = (f64::from(GRID.1) - 1.0) / 2.0 * SPACING; // z of the front row
        let (from, at, fov) = match self {
            Self::Top => ([0.0, 250.0, 0.01], [0.0, 0.0, 0.0], 45.0),
            Self::High => ([0.0, 30.0, front + 25.0], [0.0, 0.0, front - 50.0], 50.0),
            Self::Low => ([0.0, 3.0, front + 6.0], [0.0, 1.5, front - 60.0], 50.0),
            Self::Close => ([4.3, 2.6, front + 4.4], [1.5, 1.1, front], 40.0),
        };
        Camera {
            from,
            at,
            up: [0.0, 1.0, 0.0],
            fov_y_deg: fov,
            width,
            height,
        }
    }
}

/// Which mask the secondary rays of a path use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum MaskPolicy {
    /// The primary ray's mask, from the ray stack (correct).
    PerPath,
    /// A fresh random bit per ray (deliberately wrong: shows that the
    /// mismatch counter catches inconsistent paths).
    PerRay,
}

/// Render settings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Config {
    /// LOD selection.
    pub mode: GeomLodMode,
    /// Transition interval `t` in `[0, 1]` (stochastic mode).
    pub transition: f64,
    /// LOD bias (levels).
    pub bias: f64,
    /// Camera view.
    pub view: View,
    /// Image size.
    pub size: (u32, u32),
    /// Frames to accumulate (≥ 1).
    pub frames: u32,
    /// Maximum reflection bounces per path.
    pub bounces: u8,
    /// Mask of secondary rays.
    pub policy: MaskPolicy,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            mode: GeomLodMode::Stochastic,
            transition: 0.5,
            bias: 0.0,
            view: View::High,
            size: DEFAULT_SIZE,
            frames: 16,
            bounces: 2,
            policy: MaskPolicy::PerPath,
        }
    }
}

impl Config {
    /// Checks the settings (transition interval in `[0, 1]`, a non-empty image).
    pub fn check(&self) -> Result<(), String> {
        if !(0.0..=1.0).contains(&self.transition) {
            return Err(format!(
                "--transition {}: must lie in [0, 1]",
                self.transition
            ));
        }
        if self.size.0 == 0 || self.size.1 == 0 {
            return Err("image size must be at least 1x1".into());
        }
        Ok(())
    }
}

/// One grid cell: where the instance stands and how it looks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Object → world rotation.
    pub rotation: crate::tlas::Mat3,
    /// Centre.
    pub translation: V3,
    /// Diffuse colour.
    pub albedo: V3,
}

/// The meshes (8 LODs + ground) and the grid.
#[derive(Debug)]
pub struct InstanceScene {
    /// Bottom levels: LOD 0…7, then the ground quad.
    pub meshes: Vec<Bvh>,
    /// Triangles per LOD.
    pub lod_triangles: Vec<usize>,
    /// The grid cells (id = index).
    pub placements: Vec<Placement>,
    /// Seconds to make the mesh, simplify it and build the bottom levels.
    pub build_s: f64,
}

impl InstanceScene {
    /// Builds the scene (about a second in release mode).
    #[must_use]
    pub fn build() -> Self {
        let t0 = Instant::now();
        let chain = lod_chain(&displaced_icosphere(SUBDIVISIONS), usize::from(LEVELS));
        let lod_triangles = chain.iter().map(|m| m.triangle_count()).collect();
        let mut meshes: Vec<Bvh> = chain
            .par_iter()
            .map(|m| Bvh::build(m.triangles()))
            .collect();
        let (hx, hz) = (
            f64::from(GRID.0) * SPACING * 0.5 + 40.0,
            f64::from(GRID.1) * SPACING * 0.5 + 40.0,
        );
        let g = |x: f64, z: f64| [x, 0.0, z];
        meshes.push(Bvh::build(vec![
            [g(-hx, -hz), g(-hx, hz), g(hx, hz)],
            [g(-hx, -hz), g(hx, hz), g(hx, -hz)],
        ]));
        let mut rng = Rng::new(0x5EED_0001);
        let mut uni = move || f64::from(rng.next_u32()) / 4_294_967_296.0;
        let mut placements = Vec::with_capacity((GRID.0 * GRID.1) as usize);
        for j in 0..GRID.1 {
            for i in 0..GRID.0 {
                // Uniform random rotation (Shoemake's quaternion from three uniforms).
                let (u1, u2, u3) = (uni(), uni(), uni());
                let tau = std::f64::consts::TAU;
                let q = [
                    (1.0 - u1).sqrt() * (tau * u2).sin(),
                    (1.0 - u1).sqrt() * (tau * u2).cos(),
                    u1.sqrt() * (tau * u3).sin(),
                    u1.sqrt() * (tau * u3).cos(),
                ];
                let hue = uni();
                placements.push(Placement {
                    rotation: rotation_from_quaternion(q),
                    translation: [
                        (f64::from(i) - (f64::from(GRID.0) - 1.0) / 2.0) * SPACING,
                        CENTRE_Y,
                        (f64::from(j) - (f64::from(GRID.1) - 1.0) / 2.0) * SPACING,
                    ],
                    albedo: v::add([0.25; 3], v::scale(hue_color(hue * 300.0), 0.5)),
                });
            }
        }
        Self {
            meshes,
            lod_triangles,
            placements,
            build_s: t0.elapsed().as_secs_f64(),
        }
    }

    /// The firmware's LOD records for a camera (ids = grid cells):
    /// `none` gives every instance LOD 0 with mask 0xFF.
    pub fn select(&self, cam: &CameraFrame, cfg: &Config) -> Result<Vec<InstanceLod>, String> {
        let n = self.placements.len();
        if cfg.mode == GeomLodMode::None {
            return Ok((0..n as u32)
                .map(|id| InstanceLod {
                    id,
                    lod: 0,
                    mask: 0xFF,
                })
                .collect());
        }
        cfg.check()?;
        let range = LodRange::new(
            Depth::from_num(Z_NEAR),
            Depth::from_num(Z_FAR),
            LEVELS,
            LodBias::saturating_from_num(cfg.bias),
        )
        .map_err(|e| e.to_string())?;
        let mode = match cfg.mode {
            GeomLodMode::Stochastic => LodMode::Stochastic(Transition::from_num(cfg.transition)),
            _ => LodMode::Discrete,
        };
        let sel = Selector::new(range, mode).map_err(|e| e.to_string())?;
        let depths = self.placements.iter().enumerate().map(|(i, p)| {
            let z = v::dot(v::sub(p.translation, cam.eye), cam.fwd);
            (i as u32, Depth::saturating_from_num(z))
        });
        let mut out = vec![InstanceLod::default(); 2 * n];
        let k = sel.fill(depths, &mut out).map_err(|e| e.to_string())?;
        out.truncate(k);
        Ok(out)
    }

    /// The two-level BVH of LOD records (plus the ground, mask 0xFF).
    #[must_use]
    pub fn two_level(&self, records: &[InstanceLod]) -> TwoLevel<'_> {
        let mut inst: Vec<Instance> = records
            .iter()
            .map(|r| {
                let p = &self.placements[r.id as usize];
                Instance {
                    rotation: p.rotation,
                    translation: p.translation,
                    mesh: u32::from(r.lod),
                    mask: r.mask,
                    id: r.id,
                }
            })
            .collect();
        inst.push(Instance {
            rotation: rotation_from_quaternion([1.0, 0.0, 0.0, 0.0]),
            translation: [0.0; 3],
            mesh: GROUND,
            mask: 0xFF,
            id: u32::MAX,
        });
        TwoLevel::build(&self.meshes, inst)
    }
}

/// HSV hue (degrees, full saturation, value 0.9) to linear RGB.
fn hue_color(h: f64) -> V3 {
    let h = h.rem_euclid(360.0) / 60.0;
    let x = 1.0 - (h % 2.0 - 1.0).abs();
    let c = match h as u32 {
        0 => [1.0, x, 0.0],
        1 => [x, 1.0, 0.0],
        2 => [0.0, 1.0, x],
        3 => [0.0, x, 1.0],
        4 => [x, 0.0, 1.0],
        _ => [1.0, 0.0, x],
    };
    v::scale(c, 0.9)
}

/// Colour of LOD `l`: LOD 0 red, then through yellow, green and cyan to
/// LOD 7 blue (hue 0° … 240°).
#[must_use]
pub fn lod_color(l: u8) -> V3 {
    hue_color(240.0 * f64::from(l.min(LEVELS - 1)) / f64::from(LEVELS - 1))
}

/// Work and time of one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct FrameStats {
    /// Primary rays.
    pub primary: u64,
    /// Reflection rays.
    pub reflection: u64,
    /// Shadow rays.
    pub shadow: u64,
    /// Top-level nodes entered.
    pub top_nodes: u64,
    /// Instances tested (top-level leaves).
    pub instances_tested: u64,
    /// Instances skipped by their mask.
    pub masked: u64,
    /// Bottom-level nodes entered.
    pub bottom_nodes: u64,
    /// Triangles tested.
    pub triangles: u64,
    /// Hits (of any ray) on an instance whose mask excludes the path's
    /// primary mask: must be 0.
    pub mismatches: u64,
    /// Render wall time (s).
    pub render_s: f64,
}

impl FrameStats {
    fn add_traversal(&mut self, t: &TwoLevelStats) {
        self.top_nodes += t.top.nodes;
        self.instances_tested += t.top.prims;
        self.bottom_nodes += t.bottom.nodes;
        self.triangles += t.bottom.prims;
        self.masked += t.masked;
    }

    fn add(&mut self, o: &Self) {
        self.primary += o.primary;
        self.reflection += o.reflection;
        self.shadow += o.shadow;
        self.top_nodes += o.top_nodes;
        self.instances_tested += o.instances_tested;
        self.masked += o.masked;
        self.bottom_nodes += o.bottom_nodes;
        self.triangles += o.triangles;
        self.mismatches += o.mismatches;
        self.render_s += o.render_s;
    }

    /// All rays.
    #[must_use]
    pub fn rays(&self) -> u64 {
        self.primary + self.reflection + self.shadow
    }

    /// BVH nodes (both levels) entered per ray.
    #[must_use]
    pub fn nodes_per_ray(&self) -> f64 {
        (self.top_nodes + self.bottom_nodes) as f64 / self.rays().max(1) as f64
    }

    /// Triangles tested per ray.
    #[must_use]
    pub fn triangles_per_ray(&self) -> f64 {
        self.triangles as f64 / self.rays().max(1) as f64
    }
}

/// One rendered frame: linear colour and LOD colour per pixel.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Linear RGB, row-major.
    pub rgb: Vec<V3>,
    /// LOD colour of the primary hit ([`lod_color`]; ground grey, sky black).
    pub lod: Vec<V3>,
    /// Counters.
    pub stats: FrameStats,
}

/// A prepared view: camera, LOD records, two-level BVH.
#[derive(Debug)]
pub struct Prepared<'a> {
    /// Camera frame.
    pub cam: CameraFrame,
    /// Firmware pixel spread (ray stack path state).
    pub spread: PixelSpread,
    /// The LOD records of this view.
    pub records: Vec<InstanceLod>,
    /// The acceleration structure.
    pub tl: TwoLevel<'a>,
    /// Seconds for selection + top-level build.
    pub setup_s: f64,
}

impl<'a> Prepared<'a> {
    /// Selects LODs and builds the top level for `cfg`.
    pub fn new(scene: &'a InstanceScene, cfg: &Config) -> Result<Self, String> {
        let t0 = Instant::now();
        let (w, h) = cfg.size;
        let camera = cfg.view.camera(w, h);
        let cam = CameraFrame::new(&camera, w, h);
        let spread = PixelSpread::from_fov_y(camera.fov_y_deg.to_radians(), h)
            .map_err(|e| format!("camera: {e}"))?;
        let records = scene.select(&cam, cfg)?;
        let tl = scene.two_level(&records);
        Ok(Self {
            cam,
            spread,
            records,
            tl,
            setup_s: t0.elapsed().as_secs_f64(),
        })
    }

    /// Renders frame `frame` (its ray masks come from the pixel and frame
    /// number); `fixed_mask` forces one ray mask on every path (for the
    /// exact per-pixel blend: the mean of the 8 single-bit renders).
    #[must_use]
    pub fn render_frame(
        &self,
        scene: &InstanceScene,
        cfg: &Config,
        frame: u32,
        fixed_mask: Option<u8>,
    ) -> Frame {
        let (w, h) = cfg.size;
        let t0 = Instant::now();
        let rows: Vec<(Vec<V3>, Vec<V3>, FrameStats)> = (0..h)
            .into_par_iter()
            .map(|y| {
                let mut st = FrameStats::default();
                let mut rgb = Vec::with_capacity(w as usize);
                let mut lod = Vec::with_capacity(w as usize);
                for x in 0..w {
                    let (c, l) = self.path(scene, cfg, x, y, frame, fixed_mask, &mut st);
                    rgb.push(c);
                    lod.push(l);
                }
                (rgb, lod, st)
            })
            .collect();
        let mut out = Frame {
            rgb: Vec::with_capacity((w * h) as usize),
            lod: Vec::with_capacity((w * h) as usize),
            stats: FrameStats::default(),
        };
        for (rgb, lod, st) in rows {
            out.rgb.extend(rgb);
            out.lod.extend(lod);
            out.stats.add(&st);
        }
        out.stats.render_s = t0.elapsed().as_secs_f64();
        out
    }

    #[allow(clippy::too_many_arguments)]
    fn path(
        &self,
        scene: &InstanceScene,
        cfg: &Config,
        x: u32,
        y: u32,
        frame: u32,
        fixed_mask: Option<u8>,
        st: &mut FrameStats,
    ) -> (V3, V3) {
        let mut rng = Rng::for_pixel(x, y, frame);
        let primary_mask = fixed_mask.unwrap_or_else(|| ray_mask(&mut rng));
        let mut stack: RayStack = RayStack::new();
        let mut state = PathState::primary(&self.spread, primary_mask);
        let mut o = self.cam.eye;
        let mut d = v::norm(self.cam.dir(f64::from(x) + 0.5, f64::from(y) + 0.5));
        let mut weight = [1.0; 3];
        let mut color = [0.0; 3];
        let mut lod_col = [0.0; 3];
        let insts = self.tl.instances();
        loop {
            let mask = match cfg.policy {
                MaskPolicy::PerRay if state.depth > 0 => ray_mask(&mut rng),
                _ => state.mask,
            };
            let mut ts = TwoLevelStats::default();
            let hit = self
                .tl
                .query(o, d, (RAY_EPS, f64::INFINITY), mask, false, &mut ts);
            st.add_traversal(&ts);
            if state.depth == 0 {
                st.primary += 1;
            } else {
                st.reflection += 1;
            }
            let Some(hit) = hit else {
                color = v::add(color, v::mul(weight, sky(d)));
                break;
            };
            let inst = &insts[hit.instance as usize];
            st.mismatches += u64::from(!visible(inst.mask, primary_mask));
            let ground = inst.mesh == GROUND;
            if state.depth == 0 {
                lod_col = if ground {
                    [0.25; 3]
                } else {
                    lod_color(inst.mesh as u8)
                };
            }
            let p = v::madd(o, d, hit.hit.t);
            let tri = scene.meshes[inst.mesh as usize].triangle(hit.hit.tri);
            let mut n = v::norm(
                inst.dir_to_world(v::cross(v::sub(tri[1], tri[0]), v::sub(tri[2], tri[0]))),
            );
            if v::dot(n, d) > 0.0 {
                n = v::scale(n, -1.0);
            }
            let (albedo, reflect) = if ground {
                let c = ((p[0] / 2.0).floor() + (p[2] / 2.0).floor()).rem_euclid(2.0);
                ([0.45 + 0.2 * c; 3], 0.35)
            } else {
                (scene.placements[inst.id as usize].albedo, 0.15)
            };
            let origin = v::madd(p, n, RAY_EPS * (1.0 + v::max_c(p.map(f64::abs))));
            let sun = v::norm(SUN);
            let cos = v::dot(n, sun);
            let mut light = AMBIENT;
            if cos > 0.0 {
                let smask = match cfg.policy {
                    MaskPolicy::PerRay => ray_mask(&mut rng),
                    MaskPolicy::PerPath => state.mask,
                };
                let mut ss = TwoLevelStats::default();
                let blocker =
                    self.tl
                        .query(origin, sun, (RAY_EPS, f64::INFINITY), smask, true, &mut ss);
                st.add_traversal(&ss);
                st.shadow += 1;
                match blocker {
                    Some(b) => {
                        let bi = &insts[b.instance as usize];
                        st.mismatches += u64::from(!visible(bi.mask, primary_mask));
                    }
                    None => light += cos,
                }
            }
            color = v::add(
                color,
                v::scale(v::mul(weight, albedo), light * (1.0 - reflect)),
            );
            if state.depth >= cfg.bounces {
                break;
            }
            // The continuation goes through the firmware ray stack, which
            // carries the path's mask to the reflection ray.
            state = state.advance(PathLength::saturating_from_num(hit.hit.t));
            if stack.push(state.bounce(Spread::ZERO)).is_err() {
                break;
            }
            let Some(next) = stack.pop() else { break };
            state = next;
            weight = v::scale(weight, reflect);
            d = v::sub(d, v::scale(n, 2.0 * v::dot(d, n)));
            o = origin;
        }
        (color, lod_col)
    }
}

fn sky(d: V3) -> V3 {
    let t = d[1].clamp(0.0, 1.0);
    v::add(
        v::scale([0.75, 0.82, 0.9], 1.0 - t),
        v::scale([0.35, 0.5, 0.85], t),
    )
}

/// Linear RGB in [0, 1] to 8-bit sRGB-ish (gamma 2.2).
fn to_rgb8(c: &[V3], gamma: bool) -> Vec<[u8; 3]> {
    c.iter()
        .map(|p| {
            p.map(|x| {
                let x = x.clamp(0.0, 1.0);
                let y = if gamma { x.powf(1.0 / 2.2) } else { x };
                (y * 255.0).round() as u8
            })
        })
        .collect()
}

/// Root-mean-square difference of two images (all channels).
#[must_use]
pub fn rms(a: &[V3], b: &[V3]) -> f64 {
    let s: f64 = a
        .iter()
        .zip(b)
        .map(|(p, q)| (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>())
        .sum();
    (s / (3 * a.len().max(1)) as f64).sqrt()
}

/// Mean of images.
#[must_use]
pub fn mean(images: &[&[V3]]) -> Vec<V3> {
    let n = images.len().max(1) as f64;
    (0..images.first().map_or(0, |i| i.len()))
        .map(|p| {
            let s = images.iter().fold([0.0; 3], |s, img| v::add(s, img[p]));
            v::scale(s, 1.0 / n)
        })
        .collect()
}

/// The exact expectation of a frame over the path's ray mask: the mean of
/// the 8 single-bit renders (for primary hits, the per-pixel blend
/// `(popcount(mask_a)·C_a + popcount(mask_b)·C_b)/8` of the two LODs).
#[must_use]
pub fn blend(prep: &Prepared<'_>, scene: &InstanceScene, cfg: &Config) -> Frame {
    let frames: Vec<Frame> = (0..8)
        .map(|b| prep.render_frame(scene, cfg, 0, Some(1 << b)))
        .collect();
    let mut stats = FrameStats::default();
    for f in &frames {
        stats.add(&f.stats);
    }
    Frame {
        rgb: mean(&frames.iter().map(|f| f.rgb.as_slice()).collect::<Vec<_>>()),
        lod: mean(&frames.iter().map(|f| f.lod.as_slice()).collect::<Vec<_>>()),
        stats,
    }
}

/// The result of accumulating frames.
#[derive(Clone, Debug)]
pub struct Accumulated {
    /// Mean colour.
    pub rgb: Vec<V3>,
    /// Mean LOD colour.
    pub lod: Vec<V3>,
    /// The first frame alone.
    pub first: Frame,
    /// Counters summed over frames.
    pub stats: FrameStats,
    /// Per frame count `k` (powers of two and the last), the accumulated
    /// LOD image after `k` frames.
    pub snapshots: Vec<(u32, Vec<V3>)>,
}

/// Renders and averages `cfg.frames` frames (frame numbers 0, 1, …).
#[must_use]
pub fn accumulate(
    prep: &Prepared<'_>,
    scene: &InstanceScene,
    cfg: &Config,
    progress: bool,
) -> Accumulated {
    let n = cfg.frames.max(1);
    let bar = if progress {
        let b = ProgressBar::new(u64::from(n));
        b.set_style(
            ProgressStyle::with_template("{msg} [{elapsed_precise}] {wide_bar} {pos}/{len} frames")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        b.set_message(format!("instances {}", cfg.view.name()));
        b
    } else {
        ProgressBar::hidden()
    };
    let px = (cfg.size.0 * cfg.size.1) as usize;
    let mut rgb = vec![[0.0; 3]; px];
    let mut lod = vec![[0.0; 3]; px];
    let mut stats = FrameStats::default();
    let mut first = None;
    let mut snapshots = Vec::new();
    for f in 0..n {
        let fr = prep.render_frame(scene, cfg, f, None);
        for p in 0..px {
            rgb[p] = v::add(rgb[p], fr.rgb[p]);
            lod[p] = v::add(lod[p], fr.lod[p]);
        }
        stats.add(&fr.stats);
        let k = f + 1;
        if k.is_power_of_two() || k == n {
            let s = 1.0 / f64::from(k);
            snapshots.push((k, lod.iter().map(|c| v::scale(*c, s)).collect()));
        }
        if first.is_none() {
            first = Some(fr);
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    let s = 1.0 / f64::from(n);
    Accumulated {
        rgb: rgb.iter().map(|c| v::scale(*c, s)).collect(),
        lod: lod.iter().map(|c| v::scale(*c, s)).collect(),
        first: first.unwrap_or(Frame {
            rgb: Vec::new(),
            lod: Vec::new(),
            stats: FrameStats::default(),
        }),
        stats,
        snapshots,
    }
}

/// `render --scene builtin:instances`: writes `image.png` (accumulated),
/// `lod.png` (accumulated LOD colours), `frame0.png`, `lod_frame0.png`,
/// `lod_blend.png` and the convergence curve (with `reference`),
/// `report.json` and `report.md` into `out`.
pub fn cmd_render(cfg: &Config, reference: bool, out: &Path) -> Result<(), String> {
    cfg.check()?;
    let t0 = Instant::now();
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let scene = InstanceScene::build();
    let prep = Prepared::new(&scene, cfg)?;
    let acc = accumulate(&prep, &scene, cfg, true);
    let (w, h) = cfg.size;
    write_png(&out.join("image.png"), w, h, &to_rgb8(&acc.rgb, true))?;
    write_png(&out.join("lod.png"), w, h, &to_rgb8(&acc.lod, false))?;
    write_png(
        &out.join("frame0.png"),
        w,
        h,
        &to_rgb8(&acc.first.rgb, true),
    )?;
    write_png(
        &out.join("lod_frame0.png"),
        w,
        h,
        &to_rgb8(&acc.first.lod, false),
    )?;
    let mut curve = Vec::new();
    if reference {
        let b = blend(&prep, &scene, cfg);
        write_png(&out.join("lod_blend.png"), w, h, &to_rgb8(&b.lod, false))?;
        for (k, img) in &acc.snapshots {
            curve.push((*k, rms(img, &b.lod)));
        }
    }
    let s = &acc.stats;
    let frames = cfg.frames.max(1);
    let two = prep.records.len() - scene.placements.len();
    let rec_bytes = prep.records.len() * std::mem::size_of::<InstanceLod>();
    let report = json!({
        "scene": "builtin:instances", "config": cfg, "reference": reference,
        "instances": scene.placements.len(), "records": prep.records.len(), "doubled_instances": two,
        "record_bytes": rec_bytes, "top_level_bytes": prep.tl.top_bytes(),
        "lod_triangles": scene.lod_triangles,
        "timings_s": {"scene": scene.build_s, "select_and_top_level": prep.setup_s, "render_per_frame": s.render_s / f64::from(frames), "total": t0.elapsed().as_secs_f64()},
        "per_frame": { "rays": s.rays() / u64::from(frames), "nodes_per_ray": s.nodes_per_ray(), "triangles_per_ray": s.triangles_per_ray() },
        "stats": s, "convergence_rms_vs_blend": curve,
    });
    write_json(&out.join("report.json"), &report)?;
    let mut md = format!(
        "# raymip render: builtin:instances\n\n| | |\n|---|---|\n| view / size | {} / {}×{} |\n| geometric LOD / transition / bias | {:?} / {} / {} |\n| frames / bounces | {} / {} |\n| LOD triangles | {:?} |\n| instances / records (doubled) | {} / {} ({}) |\n| record memory | {} B ({} B each) |\n| scene build / select + top level (s) | {:.3} / {:.3} |\n| render per frame (s) | {:.3} |\n| rays per frame (primary / reflection / shadow) | {} / {} / {} |\n| BVH nodes per ray (top + bottom) | {:.1} |\n| triangles tested per ray | {:.1} |\n| instances skipped by mask | {} |\n| path mismatches | {} |\n",
        cfg.view.name(),
        w,
        h,
        cfg.mode,
        cfg.transition,
        cfg.bias,
        frames,
        cfg.bounces,
        scene.lod_triangles,
        scene.placements.len(),
        prep.records.len(),
        two,
        rec_bytes,
        std::mem::size_of::<InstanceLod>(),
        scene.build_s,
        prep.setup_s,
        s.render_s / f64::from(frames),
        s.primary / u64::from(frames),
        s.reflection / u64::from(frames),
        s.shadow / u64::from(frames),
        s.nodes_per_ray(),
        s.triangles_per_ray(),
        s.masked,
        s.mismatches,
    );
    if !curve.is_empty() {
        md += "\nRMS of the accumulated LOD image against the exact blend (mean of the 8 single-bit renders):\n\n| frames | RMS |\n|---|---|\n";
        for (k, r) in &curve {
            md += &format!("| {k} | {r:.4} |\n");
        }
    }
    write_text(&out.join("report.md"), &md)?;
    println!(
        "instances {} {:?} t={}: {}x{}, {} frames in {:.2} s ({:.3} s/frame), {:.1} nodes and {:.1} triangles per ray, {} records, {} mismatches -> {}",
        cfg.view.name(),
        cfg.mode,
        cfg.transition,
        w,
        h,
        frames,
        t0.elapsed().as_secs_f64(),
        s.render_s / f64::from(frames),
        s.nodes_per_ray(),
        s.triangles_per_ray(),
        prep.records.len(),
        s.mismatches,
        out.display()
    );
    if s.mismatches > 0 {
        return Err(format!("{} path mismatches", s.mismatches));
    }
    Ok(())
}

/// One benchmark row.
#[derive(Clone, Debug, Serialize)]
pub struct BenchRow {
    /// View.
    pub view: View,
    /// `none`, `discrete` or `stochastic t=…`.
    pub config: String,
    /// Instance records.
    pub records: usize,
    /// Rays per frame.
    pub rays: u64,
    /// Nodes per ray (top + bottom).
    pub nodes_per_ray: f64,
    /// Top-level nodes per ray.
    pub top_nodes_per_ray: f64,
    /// Triangles tested per ray.
    pub triangles_per_ray: f64,
    /// Best frame time over the repeats (s).
    pub frame_s: f64,
}

/// The configurations of the benchmark: none, discrete, stochastic with
/// t ∈ {0, 0.25, 0.5, 1}.
#[must_use]
pub fn bench_configs() -> Vec<(String, GeomLodMode, f64)> {
    let mut c = vec![
        ("none".to_string(), GeomLodMode::None, 0.0),
        ("discrete".to_string(), GeomLodMode::Discrete, 0.0),
    ];
    for t in [0.0, 0.25, 0.5, 1.0] {
        c.push((format!("stochastic t={t}"), GeomLodMode::Stochastic, t));
    }
    c
}

/// Runs every view × configuration at `size`, best frame time of
/// `repeats` frames; returns the rows and a Markdown report.
pub fn bench(
    size: (u32, u32),
    repeats: u32,
    bounces: u8,
) -> Result<(Vec<BenchRow>, String), String> {
    let scene = InstanceScene::build();
    let configs = bench_configs();
    let bar = ProgressBar::new((View::ALL.len() * configs.len()) as u64);
    let mut rows = Vec::new();
    for view in View::ALL {
        for (label, mode, t) in &configs {
            let cfg = Config {
                mode: *mode,
                transition: *t,
                view,
                size,
                frames: 1,
                bounces,
                ..Config::default()
            };
            let prep = Prepared::new(&scene, &cfg)?;
            let mut best = f64::INFINITY;
            let mut stats = FrameStats::default();
            for r in 0..repeats.max(1) {
                let f = prep.render_frame(&scene, &cfg, r, None);
                best = best.min(f.stats.render_s);
                stats = f.stats;
            }
            if stats.mismatches > 0 {
                return Err(format!(
                    "{} {label}: {} path mismatches",
                    view.name(),
                    stats.mismatches
                ));
            }
            rows.push(BenchRow {
                view,
                config: label.clone(),
                records: prep.records.len(),
                rays: stats.rays(),
                nodes_per_ray: stats.nodes_per_ray(),
                top_nodes_per_ray: stats.top_nodes as f64 / stats.rays().max(1) as f64,
                triangles_per_ray: stats.triangles_per_ray(),
                frame_s: best,
            });
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    let md = bench_markdown(&scene, &rows, size, repeats, bounces);
    Ok((rows, md))
}

fn bench_markdown(
    scene: &InstanceScene,
    rows: &[BenchRow],
    size: (u32, u32),
    repeats: u32,
    bounces: u8,
) -> String {
    let n = scene.placements.len();
    let rec = std::mem::size_of::<InstanceLod>();
    let mut md = format!(
        "`builtin:instances`: {} × {} = {n} instances, LOD triangles {:?}; {}×{} pixels, 1 sample per pixel, up to {bounces} reflection bounces, a shadow ray per hit facing the sun; best frame time of {repeats} frames on {} threads. Speed-up = time of `none` / time; cost = time / time of `discrete` − 1. Instance records are {rec} bytes each.\n\n",
        GRID.0,
        GRID.1,
        scene.lod_triangles,
        size.0,
        size.1,
        rayon::current_num_threads(),
    );
    md += "| view | LOD | records (memory) | rays | nodes / ray (top) | triangles / ray | frame (ms) | speed-up vs none | cost vs discrete |\n|---|---|---|---|---|---|---|---|---|\n";
    for view in View::ALL {
        let vr: Vec<&BenchRow> = rows.iter().filter(|r| r.view == view).collect();
        let none = vr
            .iter()
            .find(|r| r.config == "none")
            .map_or(f64::NAN, |r| r.frame_s);
        let disc = vr
            .iter()
            .find(|r| r.config == "discrete")
            .map_or(f64::NAN, |r| r.frame_s);
        for r in vr {
            md += &format!(
                "| {} | {} | {} ({:.1} KiB) | {} | {:.1} ({:.1}) | {:.1} | {:.1} | {:.2}× | {:+.1} % |\n",
                view.name(),
                r.config,
                r.records,
                (r.records * rec) as f64 / 1024.0,
                r.rays,
                r.nodes_per_ray,
                r.top_nodes_per_ray,
                r.triangles_per_ray,
                r.frame_s * 1e3,
                none / r.frame_s,
                100.0 * (r.frame_s / disc - 1.0),
            );
        }
    }
    md += &format!(
        "\nDoubled instances (records beyond {n}) per view at t = 1: {}.\n",
        View::ALL
            .iter()
            .map(|&vw| {
                let r = rows
                    .iter()
                    .find(|r| r.view == vw && r.config == "stochastic t=1")
                    .map_or(0, |r| r.records);
                format!(
                    "{} {} (+{:.1} %)",
                    vw.name(),
                    r.saturating_sub(n),
                    100.0 * r.saturating_sub(n) as f64 / n as f64
                )
            })
            .collect::<Vec<_>>()
            .join(", ")
    );
    md
}

/// `geomlod-bench`: writes `bench.md` and `bench.json` into `out`.
pub fn cmd_bench(size: (u32, u32), repeats: u32, bounces: u8, out: &Path) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let (rows, md) = bench(size, repeats, bounces)?;
    write_text(&out.join("bench.md"), &md)?;
    write_json(
        &out.join("bench.json"),
        &json!({ "size": size, "repeats": repeats, "bounces": bounces, "rows": rows }),
    )?;
    println!("{md}");
    Ok(())
}

/// Used by tests: the LOD parameter in f64 of an instance at depth `z`.
#[must_use]
pub fn lod_param_f64(z: f64, bias: f64) -> f64 {
    (f64::from(LEVELS) * ((z - Z_NEAR) / (Z_FAR - Z_NEAR)).clamp(0.0, 1.0) + bias)
        .clamp(0.0, f64::from(LEVELS - 1))
}
