//! `builtin:instances`: stochastic geometric LOD end to end (NVIDIA, 2020,
//! "Implementing Stochastic Levels of Detail with DirectX Raytracing").
//!
//! The scene ([`crate::scene::instances`]): a 64 × 60 grid of randomly rotated instances of one dense mesh
//! ([`crate::scene::lodmesh`]: displaced icosphere, 81 920 triangles, 8 LODs
//! halving each time) on a reflective ground plane, in a two-level BVH
//! ([`super::tlas`]). Per frame the firmware ([`raymip::geomlod`]) turns
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

use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use raymip::geomlod::{DepthToLod, InstanceLod, LodMode, Selector, ray_mask, visible};
use raymip::path::raystack::{PathState, RayStack};
use raymip::rng::Rng;
use raymip::setup::camera::PixelSpread;
use raymip::units::{Depth, LodBias, PathLength, Spread, Transition};
use rayon::prelude::*;
use serde::Serialize;

use super::bvh::Bvh;
use super::tlas::{Instance, TwoLevel, TwoLevelStats};
use super::{CameraFrame, RenderError};
use crate::scene::V3;
use crate::scene::instances::{
    DEFAULT_SIZE, GROUND, LEVELS, Placement, SUBDIVISIONS, View, Z_FAR, Z_NEAR, ground, lod_color,
    placements, rotation_from_quaternion,
};
use crate::scene::lodmesh::{displaced_icosphere, lod_chain};

/// Sun direction (towards the sun) and colour; ambient; sky.
const SUN: V3 = V3::new(-0.38, 0.85, 0.36);
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
    /// Render on the calling thread only (the benchmark: its CPU time is
    /// then measurable on a machine shared with other jobs).
    pub serial: bool,
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
            serial: false,
        }
    }
}

impl Config {
    /// Checks the settings (transition interval in `[0, 1]`, a non-empty image).
    ///
    /// # Errors
    /// [`RenderError::Transition`] or [`RenderError::EmptyImage`].
    pub fn check(&self) -> Result<(), RenderError> {
        if !(0.0..=1.0).contains(&self.transition) {
            return Err(RenderError::Transition {
                value: self.transition,
            });
        }
        if self.size.0 == 0 || self.size.1 == 0 {
            return Err(RenderError::EmptyImage {
                width: self.size.0,
                height: self.size.1,
            });
        }
        Ok(())
    }
}

/// The scene of `builtin:instances` ready to trace: the meshes (8 LODs,
/// then the ground) as bottom-level BVHs, and the grid.
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
        meshes.push(Bvh::build(ground()));
        Self {
            meshes,
            lod_triangles,
            placements: placements(),
            build_s: t0.elapsed().as_secs_f64(),
        }
    }

    /// The firmware's LOD records for a camera (ids = grid cells):
    /// `none` gives every instance LOD 0 with mask 0xFF.
    pub fn select(&self, cam: &CameraFrame, cfg: &Config) -> Result<Vec<InstanceLod>, RenderError> {
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
        let range = DepthToLod::new(
            Depth::from_num(Z_NEAR),
            Depth::from_num(Z_FAR),
            LEVELS,
            LodBias::saturating_from_num(cfg.bias),
        )
        .map_err(RenderError::GeomLod)?;
        let mode = match cfg.mode {
            GeomLodMode::Stochastic => LodMode::Stochastic(Transition::from_num(cfg.transition)),
            _ => LodMode::Discrete,
        };
        let sel = Selector::new(range, mode).map_err(RenderError::GeomLod)?;
        let depths = self.placements.iter().enumerate().map(|(i, p)| {
            let z = (p.translation - cam.eye).dot(cam.fwd);
            (i as u32, Depth::saturating_from_num(z))
        });
        let mut out = vec![InstanceLod::default(); 2 * n];
        let k = sel.fill(depths, &mut out).map_err(RenderError::Records)?;
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
            translation: V3::ZERO,
            mesh: GROUND,
            mask: 0xFF,
            id: u32::MAX,
        });
        TwoLevel::build(&self.meshes, inst)
    }
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
    /// Render CPU time of a serial frame (s; NaN when rendered in
    /// parallel or when the thread clock is unavailable).
    pub cpu_s: f64,
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
        add_fields!(self, o; primary, reflection, shadow, top_nodes, instances_tested, masked,
            bottom_nodes, triangles, mismatches, render_s, cpu_s);
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
    pub fn new(scene: &'a InstanceScene, cfg: &Config) -> Result<Self, RenderError> {
        let t0 = Instant::now();
        let (w, h) = cfg.size;
        let camera = cfg.view.camera(w, h);
        let cam = CameraFrame::new(&camera, w, h);
        let spread = CameraFrame::pixel_spread(&camera, h)?;
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
        let row = |y: u32| {
            let mut st = FrameStats::default();
            let mut rgb = Vec::with_capacity(w as usize);
            let mut lod = Vec::with_capacity(w as usize);
            for x in 0..w {
                let (c, l) = self.path(scene, cfg, x, y, frame, fixed_mask, &mut st);
                rgb.push(c);
                lod.push(l);
            }
            (rgb, lod, st)
        };
        let cpu0 = thread_cpu_ns();
        let rows: Vec<(Vec<V3>, Vec<V3>, FrameStats)> = if cfg.serial {
            (0..h).map(row).collect()
        } else {
            (0..h).into_par_iter().map(row).collect()
        };
        let cpu = cfg.serial.then(|| Some(thread_cpu_ns()? - cpu0?)).flatten();
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
        out.stats.cpu_s = cpu.map_or(f64::NAN, |ns| ns as f64 * 1e-9);
        out
    }

    /// Traces the shadow ray from `origin` towards the sun with `mask`,
    /// counting it and any hit whose instance the primary ray's mask
    /// excludes; true when nothing blocks the sun.
    fn sun_visible(
        &self,
        origin: V3,
        sun: V3,
        mask: u8,
        primary_mask: u8,
        st: &mut FrameStats,
    ) -> bool {
        let mut ss = TwoLevelStats::default();
        let blocker = self
            .tl
            .query(origin, sun, (RAY_EPS, f64::INFINITY), mask, true, &mut ss);
        st.add_traversal(&ss);
        st.shadow += 1;
        let Some(b) = blocker else { return true };
        let bi = &self.tl.instances()[b.instance as usize];
        st.mismatches += u64::from(!visible(bi.mask, primary_mask));
        false
    }

    /// One path through pixel (`x`, `y`) in `frame`: its colour and the
    /// LOD colour of its primary hit.
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
        let mut d = self
            .cam
            .dir(f64::from(x) + 0.5, f64::from(y) + 0.5)
            .normalize_or_zero();
        let mut weight = V3::ONE;
        let mut color = V3::ZERO;
        let mut lod_col = V3::ZERO;
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
                color += weight * sky(d);
                break;
            };
            let inst = &insts[hit.instance as usize];
            st.mismatches += u64::from(!visible(inst.mask, primary_mask));
            let ground = inst.mesh == GROUND;
            if state.depth == 0 {
                lod_col = if ground {
                    V3::splat(0.25)
                } else {
                    lod_color(inst.mesh as u8)
                };
            }
            let p = o + d * hit.hit.t;
            let tri = scene.meshes[inst.mesh as usize].triangle(hit.hit.tri);
            let mut n = inst
                .dir_to_world((tri[1] - tri[0]).cross(tri[2] - tri[0]))
                .normalize_or_zero();
            if n.dot(d) > 0.0 {
                n *= -1.0;
            }
            let (albedo, reflect) = if ground {
                let c = ((p[0] / 2.0).floor() + (p[2] / 2.0).floor()).rem_euclid(2.0);
                (V3::splat(0.45 + 0.2 * c), 0.35)
            } else {
                (scene.placements[inst.id as usize].albedo, 0.15)
            };
            let origin = p + n * (RAY_EPS * (1.0 + p.map(f64::abs).max_element()));
            let sun = SUN.normalize_or_zero();
            let cos = n.dot(sun);
            let mut light = AMBIENT;
            if cos > 0.0 {
                let smask = match cfg.policy {
                    MaskPolicy::PerRay => ray_mask(&mut rng),
                    MaskPolicy::PerPath => state.mask,
                };
                if self.sun_visible(origin, sun, smask, primary_mask, st) {
                    light += cos;
                }
            }
            color += (weight * albedo) * (light * (1.0 - reflect));
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
            weight *= reflect;
            d = d - (n * (2.0 * d.dot(n)));
            o = origin;
        }
        (color, lod_col)
    }
}

/// CPU time of the calling thread in ns (`clock_gettime` with
/// `CLOCK_THREAD_CPUTIME_ID`: nanosecond resolution, time other jobs on
/// the machine take does not count).
#[must_use]
pub fn thread_cpu_ns() -> Option<u64> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec for the call.
    #[allow(unsafe_code)]
    let r = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    (r == 0).then(|| ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64)
}

fn sky(d: V3) -> V3 {
    let t = d[1].clamp(0.0, 1.0);
    (V3::new(0.75, 0.82, 0.9) * (1.0 - t)) + (V3::new(0.35, 0.5, 0.85) * t)
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
            let s = images.iter().fold(V3::ZERO, |s, img| s + img[p]);
            s * (1.0 / n)
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
    let mut rgb = vec![V3::ZERO; px];
    let mut lod = vec![V3::ZERO; px];
    let mut stats = FrameStats::default();
    let mut first = None;
    let mut snapshots = Vec::new();
    for f in 0..n {
        let fr = prep.render_frame(scene, cfg, f, None);
        for p in 0..px {
            rgb[p] += fr.rgb[p];
            lod[p] += fr.lod[p];
        }
        stats.add(&fr.stats);
        let k = f + 1;
        if k.is_power_of_two() || k == n {
            let s = 1.0 / f64::from(k);
            snapshots.push((k, lod.iter().map(|c| *c * s).collect()));
        }
        if first.is_none() {
            first = Some(fr);
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    let s = 1.0 / f64::from(n);
    Accumulated {
        rgb: rgb.iter().map(|c| *c * s).collect(),
        lod: lod.iter().map(|c| *c * s).collect(),
        first: first.unwrap_or(Frame {
            rgb: Vec::new(),
            lod: Vec::new(),
            stats: FrameStats::default(),
        }),
        stats,
        snapshots,
    }
}
