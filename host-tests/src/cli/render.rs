//! `render`: one image, its mip-level map and a report.

use std::path::Path;
use std::time::Instant;

use serde_json::json;

use super::error::CommandError;
use crate::error::FileError;
use crate::output::image::{level_image, write_png};
use crate::output::report::{write_json, write_text};
use crate::render::skip::{SkipPlan, bit_identical, plan, render_trimmed};
use crate::render::{Counters, Image, Method, Options, Prepared, render};
use crate::scene::scene_label;
use crate::scene::{builtin, load_scene};

/// `render`: writes `image.png`, `levels.png`, `report.json`, `report.md` into `out`.
pub fn cmd_render(spec: &str, time: f64, opts: &Options, out: &Path) -> Result<(), CommandError> {
    opts.validate()?;
    let t0 = Instant::now();
    let scene = load_scene(spec, time)?;
    let load_s = t0.elapsed().as_secs_f64();
    std::fs::create_dir_all(out).map_err(|e| FileError::write(out, e))?;
    let size = opts.size.or_else(|| {
        spec.starts_with("builtin:")
            .then_some(builtin::DEFAULT_SIZE)
    });
    let mut prep = Prepared::new(scene, size)?;
    let img = render(&prep, opts);
    let total_s = t0.elapsed().as_secs_f64();
    // What the scene doesn't need: the set-up analysis, and a second render
    // with the trimmed pyramids (timed, compared bit for bit).
    let skip = plan(&prep, opts);
    let trimmed = skip.applies.then(|| render_trimmed(&mut prep, opts, &skip));
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
        "scene": spec, "time": time, "method": opts.method, "precision": opts.arithmetic, "max_aniso": opts.aniso,
        "width": img.width, "height": img.height, "bounces": opts.bounces,
        "spp": if opts.method == Method::Truth { opts.spp } else { 1 },
        "triangles": prep.scene.triangles.len(), "textured_triangles": prep.scene.textured_count(),
        "textures": prep.textures.iter().map(|t| json!({"name": t.name, "width": t.width, "height": t.height, "levels": t.levels})).collect::<Vec<_>>(),
        "threads": rayon::current_num_threads(),
        "timings_s": { "load": load_s, "bvh": prep.times.bvh_s, "pyramids": prep.times.pyramids_s, "table": prep.times.table_s, "render": img.render_s, "total": total_s },
        "counters": c, "max_depth": c.max_depth(),
        "skips": skips_json(&skip, &img, trimmed.as_ref()),
    });
    write_json(&out.join("report.json"), &report)?;
    let tex = c.textured_hits.max(1) as f64;
    let mut md = format!(
        "# raymip render: {}\n\n| | |\n|---|---|\n| method / precision | {} / {} |\n| size | {}×{} |\n| bounces (max) | {} |\n| triangles (textured) | {} ({}) |\n| threads | {} |\n| load / BVH / pyramids / table (s) | {:.3} / {:.3} / {:.3} / {:.3} |\n| render (s) | {:.3} |\n| total (s) | {:.3} |\n| paths / rays / hits | {} / {} / {} |\n| textured hits / untextured skipped | {} / {} |\n| bounces pushed / stack full | {} / {} |\n| deepest hit (bounces) | {} |\n| saturations | {} |\n| shadow rays | {} |\n| texels fetched / skipped | {} / {} |\n\nTextured hits per mip level:\n\n| level | share |\n|---|---|\n",
        spec,
        opts.method.name(),
        opts.arithmetic.name(),
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
    md += &skips_md(&skip, &img, trimmed.as_ref());
    write_text(&out.join("report.md"), &md)?;
    print_summary(spec, opts, &img, total_s, out);
    println!(
        "  {}",
        skips_line(&skip, c, trimmed.as_ref().map(|t| bit_identical(&img, t)))
    );
    if trimmed.as_ref().is_some_and(|t| !bit_identical(&img, t)) {
        return Err(CommandError::TrimmedDiffers);
    }
    Ok(())
}

/// Second trilinear levels skipped: the filter counts 4 avoided texel
/// reads per skipped bilinear level.
fn second_levels_skipped(c: &Counters) -> u64 {
    c.fetch_skipped / 4
}

fn skips_json(p: &SkipPlan, img: &Image, trimmed: Option<&Image>) -> serde_json::Value {
    let c = &img.counters;
    json!({
        "trimmed": p.applies,
        "pyramid_bytes_full": p.full_bytes, "pyramid_bytes_stored": p.stored_bytes,
        "pyramid_bytes_saved": p.saved_bytes(), "pyramid_saved_percent": p.saved_percent(),
        "textures_skipped": p.textures_skipped, "triangles_marked_untextured": p.triangles_marked,
        "untextured_hits_skipped": c.untextured_skipped,
        "second_trilinear_levels_skipped": second_levels_skipped(c),
        "render_s_full_pyramids": img.render_s,
        "render_s_trimmed_pyramids": trimmed.map(|t| t.render_s),
        "bit_identical": trimmed.map(|t| bit_identical(img, t)),
        "textures": p.textures,
    })
}

fn skips_md(p: &SkipPlan, img: &Image, trimmed: Option<&Image>) -> String {
    let c = &img.counters;
    let mut md = String::from("\n## Skipped (what the scene doesn't need)\n\n| | |\n|---|---|\n");
    if p.applies {
        md += &format!(
            "| pyramids stored / full (bytes) | {} / {} ({:.1} % saved) |\n",
            p.stored_bytes,
            p.full_bytes,
            p.saved_percent()
        );
    } else {
        md +=
            "| pyramids | full (the analysis bounds the firmware table method and mip 0 only) |\n";
    }
    md += &format!(
        "| textures skipped / triangles marked untextured | {} / {} |\n| untextured hits skipped | {} |\n| second trilinear levels skipped | {} |\n| render with full pyramids (s) | {:.3} |\n",
        p.textures_skipped,
        p.triangles_marked,
        c.untextured_skipped,
        second_levels_skipped(c),
        img.render_s
    );
    if let Some(t) = trimmed {
        md += &format!(
            "| render with trimmed pyramids (s) | {:.3} |\n| bit-identical | {} |\n",
            t.render_s,
            bit_identical(img, t)
        );
    }
    md += "\n| texture | triangles | lod range | stored levels | texels stored / full |\n|---|---|---|---|---|\n";
    for t in &p.textures {
        md += &format!(
            "| {} | {} | {} | {} | {} / {} |\n",
            t.name,
            t.triangles,
            t.lod
                .map_or("—".into(), |(a, b)| format!("{a:.2} … {b:.2}")),
            t.stored
                .map_or("none".into(), |(f, l)| format!("{f}..={l} of {}", t.levels)),
            t.stored_texels,
            t.full_texels
        );
    }
    md
}

fn skips_line(p: &SkipPlan, c: &Counters, identical: Option<bool>) -> String {
    let mut s = if p.applies {
        format!(
            "skips: pyramids {} of {} bytes stored ({:.1} % saved)",
            p.stored_bytes,
            p.full_bytes,
            p.saved_percent()
        )
    } else {
        "skips: full pyramids (method not bounded by the analysis)".into()
    };
    s += &format!(
        ", {} textures skipped, {} untextured hits skipped, {} second trilinear levels skipped",
        p.textures_skipped,
        c.untextured_skipped,
        second_levels_skipped(c)
    );
    if let Some(b) = identical {
        s += if b {
            ", trimmed render bit-identical"
        } else {
            ", TRIMMED RENDER DIFFERS"
        };
    }
    s
}

/// The one-line summary of a render on stdout.
fn print_summary(spec: &str, opts: &Options, img: &Image, total_s: f64, out: &Path) {
    let c = &img.counters;
    println!(
        "{} {} {}: {}x{} in {:.2} s (render {:.2} s), {} textured hits, deepest path {} bounces -> {}",
        scene_label(spec),
        opts.method.name(),
        opts.arithmetic.name(),
        img.width,
        img.height,
        total_s,
        img.render_s,
        c.textured_hits,
        c.max_depth(),
        out.display()
    );
}
