//! `render`: one image, its mip-level map and a report.

use std::path::Path;
use std::time::Instant;

use serde_json::json;

use super::output::{level_image, write_json, write_png, write_text};
use super::scene_label;
use crate::render::{Method, Options, Prepared, render};
use crate::scene::{builtin, load_scene};

/// `render`: writes `image.png`, `levels.png`, `report.json`, `report.md` into `out`.
pub fn cmd_render(spec: &str, time: f64, opts: &Options, out: &Path) -> Result<(), String> {
    let t0 = Instant::now();
    let scene = load_scene(spec, time)?;
    let load_s = t0.elapsed().as_secs_f64();
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let size = opts.size.or_else(|| {
        spec.starts_with("builtin:")
            .then_some(builtin::DEFAULT_SIZE)
    });
    let prep = Prepared::new(scene, size)?;
    let img = render(&prep, opts);
    let total_s = t0.elapsed().as_secs_f64();
    write_png(
        &out.join("image.png"),
        img.width,
        img.height,
        &img.to_rgb8(),
    )?;
    write_png(
        &out.join("levels.png"),
        img.width,
        img.height,
        &level_image(&img.lod),
    )?;
    let c = &img.counters;
    let report = json!({
        "scene": spec, "time": time, "method": opts.method, "precision": opts.precision,
        "width": img.width, "height": img.height, "bounces": opts.bounces,
        "spp": if opts.method == Method::Truth { opts.spp } else { 1 },
        "triangles": prep.scene.triangles.len(), "textured_triangles": prep.scene.textured_count(),
        "textures": prep.textures.iter().map(|t| json!({"name": t.name, "width": t.width, "height": t.height, "levels": t.levels})).collect::<Vec<_>>(),
        "threads": rayon::current_num_threads(),
        "timings_s": { "load": load_s, "bvh": prep.times.bvh_s, "pyramids": prep.times.pyramids_s, "table": prep.times.table_s, "render": img.render_s, "total": total_s },
        "counters": c, "max_depth": c.max_depth(),
    });
    write_json(&out.join("report.json"), &report)?;
    let tex = c.textured_hits.max(1) as f64;
    let mut md = format!(
        "# raymip render: {}\n\n| | |\n|---|---|\n| method / precision | {} / {} |\n| size | {}×{} |\n| bounces (max) | {} |\n| triangles (textured) | {} ({}) |\n| threads | {} |\n| load / BVH / pyramids / table (s) | {:.3} / {:.3} / {:.3} / {:.3} |\n| render (s) | {:.3} |\n| total (s) | {:.3} |\n| paths / rays / hits | {} / {} / {} |\n| textured hits / untextured skipped | {} / {} |\n| bounces pushed / stack full | {} / {} |\n| deepest hit (bounces) | {} |\n| saturations | {} |\n| shadow rays | {} |\n| texels fetched / skipped | {} / {} |\n\nTextured hits per mip level:\n\n| level | share |\n|---|---|\n",
        spec,
        opts.method.name(),
        opts.precision.name(),
        img.width,
        img.height,
        opts.bounces,
        prep.scene.triangles.len(),
        prep.scene.textured_count(),
        rayon::current_num_threads(),
        load_s,
        prep.times.bvh_s,
        prep.times.pyramids_s,
        prep.times.table_s,
        img.render_s,
        total_s,
        c.paths,
        c.rays,
        c.hits,
        c.textured_hits,
        c.untextured_skipped,
        c.bounces,
        c.stack_full,
        c.max_depth(),
        c.saturations,
        c.shadow_rays,
        c.fetched,
        c.fetch_skipped
    );
    for (l, n) in c.level_hist.iter().enumerate().filter(|(_, n)| **n > 0) {
        md += &format!("| {l} | {:.1} % |\n", 100.0 * *n as f64 / tex);
    }
    md += "\nHits per path depth: ";
    md += &c
        .depth_hist
        .iter()
        .map(u64::to_string)
        .collect::<Vec<_>>()
        .join(" / ");
    md += "\n";
    write_text(&out.join("report.md"), &md)?;
    println!(
        "{} {} {}: {}x{} in {:.2} s (render {:.2} s), {} textured hits, deepest path {} bounces -> {}",
        scene_label(spec),
        opts.method.name(),
        opts.precision.name(),
        img.width,
        img.height,
        total_s,
        img.render_s,
        c.textured_hits,
        c.max_depth(),
        out.display()
    );
    Ok(())
}
