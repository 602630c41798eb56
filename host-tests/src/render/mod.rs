//! Whitted ray tracer: point lights with shadows, mirror reflection and
//! refraction up to `bounces` levels, the firmware [`RayStack`](raymip::path::raystack::RayStack) /
//! [`PathState`](raymip::path::raystack::PathState) carrying `Pl` and the ray cone (with the surface spread
//! angle β of curved mirrors) along each path, and a
//! texture LOD chosen per [`Method`] and [`Arithmetic`].
//!
//! Pixels are traversed in 8×8 tiles in row-major tile order (the order the
//! cache study replays); tiles are rendered in parallel with rayon.

use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

/// Sums counter structs field by field: `add_fields!(self, o; a, b.c)`
/// adds `o.a` to `self.a` and `o.b.c` to `self.b.c`.
macro_rules! add_fields {
    ($s:ident, $o:ident; $($($f:ident).+),+ $(,)?) => {
        $( $s.$($f).+ += $o.$($f).+; )+
    };
}

pub mod bvh;
pub mod camera;
mod counters;
pub mod envmap;
mod error;
pub mod gbuffer;
pub mod instances;
pub mod lod;
mod options;
mod setup;
pub mod skip;
pub mod texunit;
pub mod tlas;
mod tracer;

pub use camera::CameraFrame;
pub use counters::Counters;
pub use error::RenderError;
pub use options::{Arithmetic, Method, Options};
pub use setup::{Prepared, SetupTimes};
pub use tracer::STACK_CAPACITY;

use texunit::{FetchLog, Unit};
use tracer::Ctx;

/// Tile edge in pixels.
pub const TILE: u32 = 8;
/// Number of integer mip levels in the histogram.
pub const HIST_LEVELS: usize = 16;

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

/// The ground truth: `base` rendered with [`Method::Truth`] in f64
/// (jittered supersampling, `base.spp` samples per pixel).
#[must_use]
pub fn render_truth(prep: &Prepared, base: &Options) -> Image {
    render(
        prep,
        &Options {
            method: Method::Truth,
            arithmetic: Arithmetic::Float,
            ..base.clone()
        },
    )
}

/// Renders an image.
#[must_use]
pub fn render(prep: &Prepared, opts: &Options) -> Image {
    render_filtered(prep, opts, None)
}

/// The frame of `opts` in both arithmetics, `[fixed, float]` (rendered in
/// that order; `opts.arithmetic` is not read): how the examples and tests
/// compare the firmware path with the f64 one.
#[must_use]
pub fn render_fixed_and_float(prep: &Prepared, opts: &Options) -> [Image; 2] {
    [Arithmetic::Fixed, Arithmetic::Float].map(|arithmetic| {
        render(
            prep,
            &Options {
                arithmetic,
                ..opts.clone()
            },
        )
    })
}

/// A texture-filter override for one frame of a render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameFilter {
    /// The filter of every textured hit (instead of the method's).
    pub filter: texunit::Filter,
    /// Frame number: stochastic filters draw their bits from
    /// `raymip::rng::Rng::for_pixel(x, y, frame)`, so frames differ and
    /// each is reproducible.
    pub frame: u32,
}

/// Renders an image with the filter of `ff` (the method's when `None`).
/// Anisotropic options take precedence over the override.
#[must_use]
pub fn render_filtered(prep: &Prepared, opts: &Options, ff: Option<FrameFilter>) -> Image {
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
            opts.arithmetic.name(),
            w,
            h
        ));
        b
    } else {
        ProgressBar::hidden()
    };
    let fixed = opts.arithmetic == Arithmetic::Fixed;
    let t0 = Instant::now();
    // The G-buffer pass (method gbuffer): part of the frame's time.
    let gbuffer = (opts.method == Method::Gbuffer).then(|| tracer::gbuffer_pass(prep, fixed));
    let tiles: Vec<_> = (0..n_tiles)
        .into_par_iter()
        .map(|ti| {
            let tx = ti % tiles_x;
            let ty = ti / tiles_x;
            let mut ctx = Ctx {
                prep,
                opts,
                unit: Unit::new(&prep.textures, fixed, opts.record_blocks, opts.aniso),
                counters: Counters {
                    depth_hist: vec![0; usize::from(opts.bounces) + 1],
                    ..Counters::default()
                },
                log: FetchLog {
                    blocks: opts.record_blocks.then(Vec::new),
                    ..FetchLog::default()
                },
                filter: ff.map(|f| f.filter),
                rng: raymip::rng::Rng::new(0),
                gbuffer: gbuffer.as_ref(),
                px: (0, 0),
            };
            let frame = ff.map_or(0, |f| f.frame);
            let mut px = Vec::new();
            for y in ty * TILE..((ty + 1) * TILE).min(h) {
                for x in tx * TILE..((tx + 1) * TILE).min(w) {
                    ctx.rng = raymip::rng::Rng::for_pixel(x, y, frame);
                    px.push((x, y, ctx.pixel(x, y)));
                }
            }
            bar.inc(1);
            ctx.counters.fetched = ctx.log.fetched;
            ctx.counters.fetch_skipped = ctx.log.skipped;
            ctx.counters.samples = ctx.log.samples;
            ctx.counters.aniso_samples = ctx.log.aniso_samples;
            ctx.counters.sampled_lod_sum_256 = ctx.log.lod_sum_256;
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
            rgb[i] = col.to_array().map(|c| c as f32);
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
