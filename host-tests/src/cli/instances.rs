//! `render --scene builtin:instances` and `geomlod-bench`: images,
//! reports and the benchmark table of stochastic geometric LOD
//! ([`crate::render::instances`]).

use std::path::Path;
use std::time::Instant;

use indicatif::ProgressBar;
use raymip::geomlod::InstanceLod;
use serde::Serialize;
use serde_json::json;

use super::error::CommandError;
use crate::error::FileError;
use crate::output::image::write_png;
use crate::output::report::{write_between_markers, write_json, write_text};
use crate::render::instances::InstanceScene;
use crate::render::instances::{Config, FrameStats, GeomLodMode, Prepared, accumulate, blend, rms};
use crate::scene::V3;
use crate::scene::instances::{GRID, View};

/// Linear RGB in [0, 1] to 8-bit sRGB-ish (gamma 2.2).
fn to_rgb8(c: &[V3], gamma: bool) -> Vec<[u8; 3]> {
    c.iter()
        .map(|p| {
            p.to_array().map(|x| {
                let x = x.clamp(0.0, 1.0);
                let y = if gamma { x.powf(1.0 / 2.2) } else { x };
                (y * 255.0).round() as u8
            })
        })
        .collect()
}

/// `render --scene builtin:instances`: writes `image.png` (accumulated),
/// `lod.png` (accumulated LOD colours), `frame0.png`, `lod_frame0.png`,
/// `lod_blend.png` and the convergence curve (with `reference`),
/// `report.json` and `report.md` into `out`.
pub fn cmd_render(cfg: &Config, reference: bool, out: &Path) -> Result<(), CommandError> {
    cfg.check()?;
    let t0 = Instant::now();
    std::fs::create_dir_all(out).map_err(|e| FileError::write(out, e))?;
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
        return Err(CommandError::PathMismatches {
            render: format!("{} {:?}", cfg.view.name(), cfg.mode),
            count: s.mismatches,
        });
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
    /// Best CPU time of a frame rendered on one thread, over the repeats (s).
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
) -> Result<(Vec<BenchRow>, String), CommandError> {
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
                serial: true,
                ..Config::default()
            };
            let prep = Prepared::new(&scene, &cfg)?;
            let mut best = f64::INFINITY;
            let mut stats = FrameStats::default();
            for r in 0..repeats.max(1) {
                let f = prep.render_frame(&scene, &cfg, r, None);
                best = best.min(if f.stats.cpu_s.is_finite() {
                    f.stats.cpu_s
                } else {
                    f.stats.render_s
                });
                stats = f.stats;
            }
            if stats.mismatches > 0 {
                return Err(CommandError::PathMismatches {
                    render: format!("{} {label}", view.name()),
                    count: stats.mismatches,
                });
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
        "`builtin:instances`: {} × {} = {n} instances, LOD triangles {:?}; {}×{} pixels, 1 sample per pixel, up to {bounces} reflection bounces, a shadow ray per hit facing the sun; each frame rendered on one thread; frame time = the least CPU time of {repeats} frames (`clock_gettime(CLOCK_THREAD_CPUTIME_ID)`, so other jobs on the machine do not count; machine: {} hardware threads). Speed-up = time of `none` / time; cost = time / time of `discrete` − 1. Instance records are {rec} bytes each.\n\n",
        GRID.0,
        GRID.1,
        scene.lod_triangles,
        size.0,
        size.1,
        std::thread::available_parallelism().map_or(0, usize::from),
    );
    md += "| view | LOD | records (memory) | rays | nodes / ray (top) | triangles / ray | frame CPU (ms) | speed-up vs none | cost vs discrete |\n|---|---|---|---|---|---|---|---|---|\n";
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
    md += "\nBeside the article (NVIDIA 2020: up to 2.2× faster with LOD in its top view, at most 10 % extra cost from ray divergence in the transitions, 1.6 % from the doubled instances):\n\n| view | discrete vs none: time / nodes / triangles per ray | stochastic t = 0.5 / t = 1 vs discrete: time | top-level nodes per ray, t = 1 vs discrete | doubled instances at t = 0.5 / t = 1 |\n|---|---|---|---|---|\n";
    for view in View::ALL {
        let get = |c: &str| rows.iter().find(|r| r.view == view && r.config == c);
        let (Some(none), Some(disc), Some(h), Some(one)) = (
            get("none"),
            get("discrete"),
            get("stochastic t=0.5"),
            get("stochastic t=1"),
        ) else {
            continue;
        };
        let pct = |a: f64, b: f64| 100.0 * (a / b - 1.0);
        let extra = |r: &BenchRow| 100.0 * r.records.saturating_sub(n) as f64 / n as f64;
        md += &format!(
            "| {} | {:.2}× / {:.2}× / {:.1}× | {:+.1} % / {:+.1} % | {:.1} → {:.1} ({:+.1} %) | {:.1} % / {:.1} % |\n",
            view.name(),
            none.frame_s / disc.frame_s,
            none.nodes_per_ray / disc.nodes_per_ray,
            none.triangles_per_ray / disc.triangles_per_ray,
            pct(h.frame_s, disc.frame_s),
            pct(one.frame_s, disc.frame_s),
            disc.top_nodes_per_ray,
            one.top_nodes_per_ray,
            pct(one.top_nodes_per_ray, disc.top_nodes_per_ray),
            extra(h),
            extra(one),
        );
    }
    md
}

/// `geomlod-bench`: writes `bench.md` and `bench.json` into `out`.
/// With `write`, the table also replaces the text between
/// `<!-- geomlod-bench:begin -->` and `<!-- geomlod-bench:end -->` in each
/// file (docs/geometric-lod.md, BENCHMARKS.md).
pub fn cmd_bench(
    size: (u32, u32),
    repeats: u32,
    bounces: u8,
    out: &Path,
    write: &[std::path::PathBuf],
) -> Result<(), CommandError> {
    std::fs::create_dir_all(out).map_err(|e| FileError::write(out, e))?;
    let (rows, md) = bench(size, repeats, bounces)?;
    let md = format!(
        "Measured on {} by `bash scripts/geomlod-bench` (`raymip-host geomlod-bench --size {}x{} --repeats {repeats} --bounces {bounces}`).\n\n{md}",
        crate::output::machine::machine_line(),
        size.0,
        size.1,
    );
    for f in write {
        write_between_markers(f, "geomlod-bench", &md)?;
        eprintln!("wrote {}", f.display());
    }
    write_text(&out.join("bench.md"), &md)?;
    write_json(
        &out.join("bench.json"),
        &json!({ "size": size, "repeats": repeats, "bounces": bounces, "rows": rows }),
    )?;
    println!("{md}");
    Ok(())
}
