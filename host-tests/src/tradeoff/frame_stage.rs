//! Whole frames: table / cone / raydiff / mip0 × fixed / float × the
//! filters on each scene, ms per frame (median of repeated renders) and
//! error against the supersampled ground truth (PSNR, max and RMS in LSB)
//! and against the f64 render of the same method.

use std::path::Path;

use crate::output::metrics::{max_diff, psnr};
use crate::render::texunit::Filter;
use crate::render::{
    Arithmetic, Counters, FrameFilter, Image, Method, Options, Prepared, render_filtered,
    render_truth,
};
use crate::scene::{Scene, SceneError, load_scene, load_scene_dir};

use super::budgets::frame_calls;
use super::filter_stage::{STOCHASTIC, stochastic_name};
use super::timing::median;
use super::{Row, Settings, Stage, TradeoffError, error_stats};

/// Loads `spec`: `builtin:NAME`, an `.aff` file or a BART folder.
pub fn load(spec: &str) -> Result<Scene, SceneError> {
    let p = Path::new(spec);
    if p.is_dir() {
        load_scene_dir(p, 0.0)
    } else {
        load_scene(spec, 0.0)
    }
}

/// Loads `spec` (see [`load`]) and prepares its render at `size`.
///
/// # Errors
/// [`TradeoffError::Scene`] or [`TradeoffError::Render`], naming `spec`.
pub fn prepare(spec: &str, size: (u32, u32)) -> Result<Prepared, TradeoffError> {
    let scene = load(spec).map_err(|source| TradeoffError::Scene {
        spec: spec.to_string(),
        source,
    })?;
    Prepared::new(scene, Some(size)).map_err(|source| TradeoffError::Render {
        spec: spec.to_string(),
        source,
    })
}

/// Filter name of a frame filter.
fn filter_name(f: Filter) -> &'static str {
    match f {
        Filter::Trilinear => "trilinear",
        Filter::BilinearLevel0 | Filter::Bilinear => "bilinear",
        Filter::Nearest => "nearest",
        Filter::Stochastic(m) => stochastic_name(m),
    }
}

/// The deterministic filter of a frame filter (the float render it is
/// compared with).
fn expectation(f: Filter) -> Filter {
    match f {
        Filter::Stochastic(m) => match super::filter_stage::expectation(m) {
            raymip::texture::Mode::BilinearNearestLevel => Filter::Bilinear,
            _ => Filter::Trilinear,
        },
        f => f,
    }
}

/// The filters rendered with `method`.
/// The frame stage's LOD methods: the talk's three (table and ray cones,
/// ray differentials ray-traced and from a G-buffer) and no LOD.
const METHODS: [Method; 5] = [
    Method::Table,
    Method::Cone,
    Method::Raydiff,
    Method::Gbuffer,
    Method::Mip0,
];

fn filters(method: Method) -> Vec<Filter> {
    let mut f = vec![Filter::Nearest, Filter::Bilinear];
    if method != Method::Mip0 {
        f.push(Filter::Trilinear);
        f.extend(STOCHASTIC.map(Filter::Stochastic));
    }
    f
}

/// Number of renders [`rows`] makes per scene (for the progress bar).
#[must_use]
pub fn renders_per_scene(s: &Settings) -> u64 {
    let per = |m: Method| {
        let f = filters(m);
        let det = f
            .iter()
            .filter(|f| !matches!(f, Filter::Stochastic(_)))
            .count();
        let sto = f.len() - det;
        (det * 2 + sto) * s.frame_repeats + sto * s.frame_accumulate as usize
    };
    1 + METHODS.map(per).iter().sum::<usize>() as u64
}

struct Scored<'a> {
    truth: &'a [[u8; 3]],
    tick: &'a dyn Fn(),
}

impl Scored<'_> {
    fn row(
        &self,
        scene: &str,
        method: Method,
        precision: &str,
        filter: Filter,
        (img, ms, counters): &(Vec<[u8; 3]>, f64, Counters),
    ) -> Row {
        let (max, rms) = error_stats(
            img.iter()
                .zip(self.truth)
                .flat_map(|(a, b)| (0..3).map(move |k| f64::from(a[k]) - f64::from(b[k]))),
        );
        debug_assert_eq!(max, f64::from(max_diff(img, self.truth)));
        let f64_row = precision == "f64";
        Row {
            scene: Some(scene.to_string()),
            filter: Some(filter_name(filter).to_string()),
            time_ms: Some(*ms),
            psnr_truth_db: Some(psnr(img, self.truth)),
            frame_calls: frame_calls(method, filter, counters).map(|c| (c, f64_row)),
            ..Row::new(Stage::Frame, method.name(), precision, max, rms, "LSB")
        }
    }
}

/// Renders `frames` frames `0..frames` with `filter` (median time of the
/// first `repeats` renders of frame 0) and returns the mean image in RGB8.
fn frames(
    prep: &Prepared,
    o: &Options,
    filter: Filter,
    frames: u32,
    repeats: usize,
    tick: &dyn Fn(),
) -> (Vec<[u8; 3]>, f64, Counters) {
    let mut times = Vec::new();
    let mut acc: Option<Image> = None;
    for f in 0..frames.max(1) {
        let n = if f == 0 { repeats.max(1) } else { 1 };
        for _ in 0..n {
            let img = render_filtered(prep, o, Some(FrameFilter { filter, frame: f }));
            if f == 0 {
                times.push(img.render_s * 1e3);
            }
            tick();
            match &mut acc {
                None => acc = Some(img),
                Some(a) if f > 0 => a.rgb.iter_mut().zip(&img.rgb).for_each(|(a, b)| {
                    for k in 0..3 {
                        a[k] += b[k];
                    }
                }),
                Some(_) => {}
            }
        }
    }
    let mut img = acc.unwrap_or_else(|| unreachable!("at least one frame"));
    let k = frames.max(1) as f32;
    img.rgb.iter_mut().for_each(|c| *c = c.map(|x| x / k));
    (img.to_rgb8(), median(&mut times), img.counters)
}

/// Every frame row of one scene.
fn scene_rows(spec: &str, s: &Settings, tick: &dyn Fn()) -> Result<Vec<Row>, TradeoffError> {
    let name = crate::scene::scene_label(spec);
    let prep = prepare(spec, s.size)?;
    let base = Options {
        size: Some(s.size),
        bounces: s.bounces,
        spp: s.spp,
        ..Options::default()
    };
    let truth = render_truth(&prep, &base).to_rgb8();
    tick();
    let sc = Scored {
        truth: &truth,
        tick,
    };
    let mut out = Vec::new();
    for method in METHODS {
        let o = |arithmetic| Options {
            method,
            arithmetic,
            ..base.clone()
        };
        let (fixed, float) = (o(Arithmetic::Fixed), o(Arithmetic::Float));
        let mut float_imgs = Vec::new();
        for f in filters(method)
            .into_iter()
            .filter(|f| !matches!(f, Filter::Stochastic(_)))
        {
            let fr = frames(&prep, &float, f, 1, s.frame_repeats, sc.tick);
            out.push(sc.row(&name, method, "f64", f, &fr));
            float_imgs.push((f, fr.0));
        }
        let float_of = |f: Filter| {
            float_imgs
                .iter()
                .find(|(g, _)| *g == expectation(f))
                .map(|(_, i)| i)
        };
        for f in filters(method) {
            let acc = if matches!(f, Filter::Stochastic(_)) {
                vec![1, s.frame_accumulate]
            } else {
                vec![1]
            };
            for k in acc {
                let fr = frames(&prep, &fixed, f, k, s.frame_repeats, sc.tick);
                let mut r = sc.row(&name, method, "fixed accurate", f, &fr);
                r.frames = k;
                r.psnr_float_db = float_of(f).map(|b| psnr(&fr.0, b));
                out.push(r);
            }
        }
    }
    Ok(out)
}

/// Every frame row of every scene in `s.scenes`.
pub fn rows(s: &Settings, tick: &dyn Fn()) -> Result<Vec<Row>, TradeoffError> {
    let mut out = Vec::new();
    for spec in &s.scenes {
        out.extend(scene_rows(spec, s, tick)?);
    }
    Ok(out)
}
