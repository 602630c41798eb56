//! Table I of the hardware paper: per scene, the share of textured hits per
//! selected integer mip level (0, 1, 2, 3+), the texel-cache hit rate with
//! mip mapping off (every fetch bilinear in level 0) and on (table method,
//! trilinear), and the frame time off/on.
//!
//! Cache model: the firmware [`BlockCache`]`<64, 4>` — 64 sets × 4 ways of
//! 64-byte lines (one 4×4 block of RGBA8 texels) = 16 KiB, LRU — fed the
//! global block address (per-texture base + `cache::BlockLayout::index`) of every
//! texel fetch, pixels in 8×8 tiles in row-major tile order, each pixel's
//! whole path (primary + bounces + no texture fetch for shadows) before the
//! next pixel. One cache, no per-thread split.

use std::path::{Path, PathBuf};
use std::time::Instant;

use raymip::texture::storage::cache::BlockCache;
use serde::Serialize;
use serde_json::json;

use super::error::CommandError;
use crate::error::FileError;
use crate::output::report::{write_json, write_text};
use crate::render::{Arithmetic, Counters, Method, Options, Prepared, render};
use crate::scene::Scene;
use crate::scene::{SceneError, builtin, default_bart_dir, load_scene_dir};

/// Cache sets.
pub const SETS: usize = 64;
/// Cache ways.
pub const WAYS: usize = 4;
/// Line size in bytes (4×4 RGBA8 texels).
pub const LINE_BYTES: usize = 64;

/// The paper's values: name, level shares 0/1/2/3+ (%), cache hit rate off → on (%).
pub const PAPER: [(&str, [f64; 4], f64, f64); 3] = [
    ("kitchen", [13.0, 30.0, 9.0, 48.0], 74.5, 93.7),
    ("robots", [2.0, 1.0, 2.0, 95.0], 73.9, 98.6),
    ("museum", [0.0, 58.0, 26.0, 16.0], 79.6, 97.2),
];

/// One scene's row.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// Scene name (folder).
    pub scene: String,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Triangles.
    pub triangles: usize,
    /// Textured triangles.
    pub textured_triangles: usize,
    /// Textures.
    pub textures: usize,
    /// Textured hits (mip mapping on).
    pub textured_hits: u64,
    /// Share of textured hits per integer level 0, 1, 2, 3+ (%).
    pub level_share: [f64; 4],
    /// Cache hit rate, mip mapping off (%).
    pub cache_off: f64,
    /// Cache hit rate, mip mapping on (%).
    pub cache_on: f64,
    /// Block accesses, off / on.
    pub accesses: [u64; 2],
    /// Render time off / on (s, all threads).
    pub frame_s: [f64; 2],
    /// Counters of the mip-mapped render.
    pub counters: Counters,
}

/// Cache hit rate (%) of a block-address stream.
#[must_use]
pub fn hit_rate(blocks: &[u32]) -> f64 {
    let mut cache: BlockCache<SETS, WAYS> = BlockCache::new();
    for &b in blocks {
        cache.access(b);
    }
    100.0 * cache.stats().hit_rate()
}

/// Level shares 0/1/2/3+ (%) of a level histogram.
#[must_use]
pub fn level_shares(hist: &[u64]) -> [f64; 4] {
    let total: u64 = hist.iter().sum();
    let t = total.max(1) as f64;
    let mut s = [0.0; 4];
    for (l, &n) in hist.iter().enumerate() {
        s[l.min(3)] += 100.0 * n as f64 / t;
    }
    s
}

/// Measures one scene.
pub fn measure(
    name: &str,
    scene: Scene,
    size: (u32, u32),
    bounces: u8,
    progress: bool,
) -> Result<Row, CommandError> {
    let t0 = Instant::now();
    let prep = Prepared::new(scene, Some(size))?;
    let _ = t0;
    let base = Options {
        method: Method::Mip0,
        arithmetic: Arithmetic::Fixed,
        size: Some(size),
        bounces,
        spp: 1,
        record_blocks: true,
        aniso: None,
        progress,
    };
    let off = render(&prep, &base);
    let on = render(
        &prep,
        &Options {
            method: Method::Table,
            ..base
        },
    );
    let b_off = off.blocks.as_deref().unwrap_or(&[]);
    let b_on = on.blocks.as_deref().unwrap_or(&[]);
    Ok(Row {
        scene: name.to_string(),
        width: prep.width,
        height: prep.height,
        triangles: prep.scene.triangles.len(),
        textured_triangles: prep.scene.textured_count(),
        textures: prep.textures.len(),
        textured_hits: on.counters.textured_hits,
        level_share: level_shares(&on.counters.level_hist),
        cache_off: hit_rate(b_off),
        cache_on: hit_rate(b_on),
        accesses: [b_off.len() as u64, b_on.len() as u64],
        frame_s: [off.render_s, on.render_s],
        counters: on.counters,
    })
}

/// The printed table: ours beside the paper's.
#[must_use]
pub fn markdown(rows: &[Row], bounces: u8) -> String {
    let mut s = format!(
        "Table I (ours beside the paper's). Cache: {SETS} sets × {WAYS} ways × {LINE_BYTES} B = {} KiB, LRU, 4×4 RGBA8 texel blocks; 8×8-pixel tiles; up to {bounces} bounces; mip mapping off = bilinear level 0, on = table lod, trilinear.\n\n",
        SETS * WAYS * LINE_BYTES / 1024
    );
    s += "| scene | size | textured hits | level 0 / 1 / 2 / 3+ (%) ours | paper | cache off → on (%) ours | paper | frame off / on (s) |\n|---|---|---|---|---|---|---|---|\n";
    for r in rows {
        let paper = PAPER.iter().find(|p| r.scene.to_lowercase().contains(p.0));
        let (pl, pc) = paper.map_or(("–".to_string(), "–".to_string()), |p| {
            (
                format!(
                    "{:.0} / {:.0} / {:.0} / {:.0}",
                    p.1[0], p.1[1], p.1[2], p.1[3]
                ),
                format!("{:.1} → {:.1}", p.2, p.3),
            )
        });
        s += &format!(
            "| {} | {}×{} | {} | {:.1} / {:.1} / {:.1} / {:.1} | {} | {:.1} → {:.1} | {} | {:.2} / {:.2} |\n",
            r.scene,
            r.width,
            r.height,
            r.textured_hits,
            r.level_share[0],
            r.level_share[1],
            r.level_share[2],
            r.level_share[3],
            pl,
            r.cache_off,
            r.cache_on,
            pc,
            r.frame_s[0],
            r.frame_s[1]
        );
    }
    s += "\nNotes: level = floor of the table lod clamped to the texture's levels, at every textured hit of every path (primary and secondary). \
Differences from the paper have known sources: the camera frame (ours: the animation at `--time`, default 0, and 800×480 with the file's vertical angle, \
while the files say 800×600; one level is one halving of the image size, so the level shares move by about one level per factor 2 in resolution), \
the lod itself (the table method has no |n·d| term), the filter (trilinear: up to 8 texel fetches per hit with mip mapping on, 4 bilinear level-0 fetches off), \
and the cache (a 16 KiB 4-way LRU block cache with Morton-ordered 4×4 blocks; the paper's cache organisation and traversal order may differ).\n";
    s
}

/// A deferred scene load.
type SceneLoader = Box<dyn Fn() -> Result<Scene, SceneError>>;

/// `table1`: every scene folder under `scenes` (and the built-in scenes if
/// `builtin`), printed beside the paper's values; `table1.md` / `table1.json`
/// into `out` when given. A scene that fails to load is an error naming it
/// and the reason, unless `skip_unloadable` (then it is named on stderr and
/// the others are measured).
pub fn cmd_table1(
    scenes: Option<&Path>,
    size: (u32, u32),
    bounces: u8,
    time: f64,
    builtin_too: bool,
    out: Option<&Path>,
    skip_unloadable: bool,
) -> Result<(), CommandError> {
    let mut jobs: Vec<(String, SceneLoader)> = Vec::new();
    let dir = scenes.map_or_else(default_bart_dir, Path::to_path_buf);
    if dir.is_dir() {
        let mut subs: Vec<PathBuf> = std::fs::read_dir(&dir)
            .map_err(|e| FileError::read(&dir, e))?
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
        return Err(CommandError::ScenesNotFound { dir });
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
            Err(e) if skip_unloadable => {
                eprintln!("skipped (--skip-unloadable): {name}: {e}");
                continue;
            }
            Err(source) => return Err(CommandError::Unloadable { name, source }),
        };
        println!(
            "{name}: loaded {} triangles in {:.2} s",
            scene.triangles.len(),
            t0.elapsed().as_secs_f64()
        );
        let row = measure(&name, scene, size, bounces, true)?;
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
    let md = markdown(&rows, bounces);
    println!("\n{md}");
    if let Some(out) = out {
        std::fs::create_dir_all(out).map_err(|e| FileError::write(out, e))?;
        write_text(&out.join("table1.md"), &md)?;
        write_json(
            &out.join("table1.json"),
            &json!({"bounces": bounces, "width": size.0, "height": size.1, "cache": {"sets": SETS, "ways": WAYS, "line_bytes": LINE_BYTES}, "rows": rows}),
        )?;
    }
    if rows.is_empty() {
        return Err(CommandError::NothingMeasured);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hit_rate_of_known_streams() {
        // One block n times: one cold miss.
        assert!((hit_rate(&[7; 100]) - 99.0).abs() < 1e-9);
        // WAYS + 1 blocks of one set in a cycle: LRU misses every time.
        let thrash: Vec<u32> = (0..40)
            .map(|i| (i % (WAYS as u32 + 1)) * SETS as u32)
            .collect();
        assert_eq!(hit_rate(&thrash), 0.0);
        // WAYS blocks of one set in a cycle: only the cold misses.
        let fit: Vec<u32> = (0..40).map(|i| (i % WAYS as u32) * SETS as u32).collect();
        assert!((hit_rate(&fit) - 90.0).abs() < 1e-9);
    }

    #[test]
    fn level_shares_fold_three_and_up() {
        let mut h = [0u64; 16];
        h[0] = 1;
        h[1] = 2;
        h[2] = 3;
        h[3] = 2;
        h[9] = 2;
        assert_eq!(level_shares(&h), [10.0, 20.0, 30.0, 40.0]);
        assert_eq!(level_shares(&[0; 16]), [0.0; 4]);
    }
}
