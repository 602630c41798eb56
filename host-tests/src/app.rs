//! The CLI commands (`render`, `compare`, `table1`) as library functions.

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde_json::json;

use crate::builtin;
use crate::compare::{compare, markdown};
use crate::output::{level_image, write_json, write_png, write_text};
use crate::render::{Method, Options, Prepared, render};
use crate::scene::{Scene, aff_adapter};

/// Loads `builtin:NAME` or an `.aff` file at animation time `time`.
pub fn load_scene(spec: &str, time: f64) -> Result<Scene, String> {
    if let Some(name) = spec.strip_prefix("builtin:") {
        return builtin::by_name(name);
    }
    load_aff(Path::new(spec), time)
}

/// Loads an AFF scene file.
pub fn load_aff(path: &Path, time: f64) -> Result<Scene, String> {
    crate::aff::load(path, time)
        .map(aff_adapter)
        .map_err(|e| e.to_string())
}

/// Parses `WxH`.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("size `{s}`: expected WxH, e.g. 800x480"))?;
    let p = |t: &str| {
        t.trim()
            .parse::<u32>()
            .ok()
            .filter(|&n| n > 0 && n <= 16384)
            .ok_or_else(|| format!("size `{s}`: `{t}` is not a number in 1..=16384"))
    };
    Ok((p(w)?, p(h)?))
}

fn scene_label(spec: &str) -> String {
    spec.strip_prefix("builtin:").map_or_else(
        || {
            Path::new(spec)
                .file_stem()
                .map_or("scene".into(), |s| s.to_string_lossy().into_owned())
        },
        str::to_string,
    )
}

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

/// `compare`: truth and every method in both precisions; writes images,
/// heat-maps and `compare.json` / `compare.md` into `out`.
pub fn cmd_compare(
    spec: &str,
    time: f64,
    opts: &Options,
    methods: &[Method],
    out: &Path,
) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let scene = load_scene(spec, time)?;
    let size = opts.size.or_else(|| {
        spec.starts_with("builtin:")
            .then_some(builtin::DEFAULT_SIZE)
    });
    let prep = Prepared::new(scene, size)?;
    let c = compare(&prep, opts, methods, Some(out))?;
    let md = format!(
        "# raymip compare: {spec} ({}×{}, {} bounces)\n\n{}",
        prep.width,
        prep.height,
        opts.bounces,
        markdown(&c)
    );
    write_text(&out.join("compare.md"), &md)?;
    write_json(
        &out.join("compare.json"),
        &json!({"scene": spec, "width": prep.width, "height": prep.height, "bounces": opts.bounces, "comparison": c}),
    )?;
    println!("{md}");
    Ok(())
}

/// The default BART folder: `../shared/scenes/bart` relative to the current
/// directory, else relative to the repository root.
#[must_use]
pub fn default_bart_dir() -> PathBuf {
    let cwd = PathBuf::from("../shared/scenes/bart");
    if cwd.is_dir() {
        return cwd;
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/scenes/bart")
}

/// A deferred scene load.
type SceneLoader = Box<dyn Fn() -> Result<Scene, String>>;

/// Loads the scene in a BART folder (its top-level `.aff` file).
pub fn load_scene_dir(dir: &Path, time: f64) -> Result<Scene, String> {
    let top = crate::aff::find_top_level(dir).map_err(|e| e.to_string())?;
    load_aff(&top, time)
}

/// `table1`: every scene folder under `scenes` (and the built-in scenes if
/// `builtin`), printed beside the paper's values; `table1.md` / `table1.json`
/// into `out` when given.
pub fn cmd_table1(
    scenes: Option<&Path>,
    size: (u32, u32),
    bounces: u8,
    time: f64,
    builtin_too: bool,
    out: Option<&Path>,
) -> Result<(), String> {
    let mut jobs: Vec<(String, SceneLoader)> = Vec::new();
    let dir = scenes.map_or_else(default_bart_dir, Path::to_path_buf);
    if dir.is_dir() {
        let mut subs: Vec<PathBuf> = std::fs::read_dir(&dir)
            .map_err(|e| format!("{}: {e}", dir.display()))?
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| p.is_dir())
            .collect();
        subs.sort();
        for s in subs {
            let name = s
                .file_name()
                .map_or("scene".into(), |n| n.to_string_lossy().into_owned());
            jobs.push((name, Box::new(move || load_scene_dir(&s, time))));
        }
    } else if !builtin_too {
        return Err(format!(
            "{}: scene folder not found (pass --scenes DIR, or --builtin for the built-in scenes)",
            dir.display()
        ));
    } else {
        println!("SKIP: {} not found; built-in scenes only", dir.display());
    }
    if builtin_too {
        for n in builtin::NAMES {
            jobs.push((
                format!("builtin:{n}"),
                Box::new(move || builtin::by_name(n)),
            ));
        }
    }
    let mut rows = Vec::new();
    for (name, load) in jobs {
        let t0 = Instant::now();
        let scene = match load() {
            Ok(s) => s,
            Err(e) => {
                eprintln!("error: {name}: {e}");
                continue;
            }
        };
        println!(
            "{name}: loaded {} triangles in {:.2} s",
            scene.triangles.len(),
            t0.elapsed().as_secs_f64()
        );
        let row = crate::table1::measure(&name, scene, size, bounces, true)?;
        println!(
            "{name}: levels {:.1}/{:.1}/{:.1}/{:.1} %, cache {:.1} -> {:.1} %, frame {:.2} / {:.2} s",
            row.level_share[0],
            row.level_share[1],
            row.level_share[2],
            row.level_share[3],
            row.cache_off,
            row.cache_on,
            row.frame_s[0],
            row.frame_s[1]
        );
        rows.push(row);
    }
    let md = crate::table1::markdown(&rows, bounces);
    println!("\n{md}");
    if let Some(out) = out {
        std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
        write_text(&out.join("table1.md"), &md)?;
        write_json(
            &out.join("table1.json"),
            &json!({"bounces": bounces, "width": size.0, "height": size.1, "cache": {"sets": crate::table1::SETS, "ways": crate::table1::WAYS, "line_bytes": crate::table1::LINE_BYTES}, "rows": rows}),
        )?;
    }
    if rows.is_empty() {
        return Err("no scene could be measured".into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_and_scene_errors() {
        assert_eq!(parse_size("800x480"), Ok((800, 480)));
        assert_eq!(parse_size("64X48"), Ok((64, 48)));
        for bad in ["800", "0x10", "ax4", "10x", "99999x2"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
        let e = load_scene("builtin:nope", 0.0).unwrap_err();
        assert!(e.contains("nope") && e.contains("hall"), "{e}");
        assert!(
            load_scene("/no/such/file.aff", 0.0)
                .unwrap_err()
                .contains("/no/such/file.aff")
        );
    }
}
