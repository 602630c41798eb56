//! `raymip-host memory`: the memory a controller firmware needs for a
//! scene, from a scene file (the set-up analysis bounds every textured
//! hit's path length and trims the pyramids) or from numbers on the command
//! line (triangles, textures with their sizes and formats, `--path-range`
//! for the trimmed pyramids), for a target and a cargo feature set.
//!
//! Where each figure comes from: the Pb table is `size_of::<Log2Pb>()` per
//! triangle; pyramids are `image_len` (the firmware's own size function)
//! per texture, trimmed by the firmware's `LodRange::levels` and
//! `Geometry::trimmed`; the ray stack is `stack_bound(bounces, branches)`
//! entries; the sizes of a ray-stack entry, a sampler and a texel cache on
//! the target, and the code of the feature set, are the ones
//! `scripts/features` measured in the target's images (BUDGETS.md,
//! "Feature sets", compiled in here); a cache geometry other than the
//! measured 8 × 2 adds the per-way bytes of the cache's arrays, which do
//! not depend on the target (tested against `size_of`).

use std::collections::BTreeSet;
use std::fmt::{self, Write as _};
use std::mem::size_of;
use std::path::{Path, PathBuf};

use raymip::Log2Pb;
use raymip::path::raystack::stack_bound;
use raymip::texture::Mode;
use raymip::texture::storage::analysis::LodRange;
use raymip::texture::storage::cache::TexelCache;
use raymip::texture::storage::format::TexelFormat;
use raymip::texture::storage::image::image_len;
use raymip::texture::storage::mip::{Pyramid, full_levels};
use raymip::units::Lod;

use super::parse_size;
use super::sample::FormatArg;
use crate::output::report::{markdown_cells, write_between_markers};
use crate::render::skip::plan;
use crate::render::{Arithmetic, Method, Options, Prepared};
use crate::scene::scene_label;
use crate::scene::{load_scene, load_scene_dir};

/// BUDGETS.md as built: the "Feature sets" tables of `scripts/features`.
const BUDGETS: &str = include_str!("../../../BUDGETS.md");

/// The default stages (`default` and `ffi` expand to them).
const STAGES: [&str; 4] = ["cone", "trilinear", "cache", "mipgen"];

/// The opt-in stages; `scripts/features` measures each beside the
/// default stages (and `raydiff` with `envmap`).
const OPT_IN: [&str; 4] = ["raydiff", "envmap", "f32", "pcpi"];

/// Whether `s` is a stage a measured feature set can hold (`ffi` is not:
/// its code is the C ABI's, `scripts/c-abi`).
fn is_stage(s: &str) -> bool {
    STAGES.contains(&s) || OPT_IN.contains(&s)
}

/// The targets `scripts/features` measures.
pub const TARGETS: [&str; 2] = ["thumbv7em-none-eabihf", "riscv32imac-unknown-none-elf"];

/// Arguments of `raymip-host memory`.
#[derive(clap::Args, Clone, Debug)]
pub struct MemoryArgs {
    /// A scene: `builtin:NAME`, an `.aff` file or a BART scene folder
    /// (counts its triangles and textures, runs the set-up analysis).
    /// Without it the scene is described by --triangles and --texture.
    #[arg(long)]
    pub scene: Option<String>,
    /// Image size WxH for the scene's camera (default: the camera's).
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// Triangles of the scene (untextured ones too).
    #[arg(long, conflicts_with = "scene")]
    pub triangles: Option<u64>,
    /// Textures, repeatable: `WxH[:FORMAT][*COUNT]`, e.g. `1024x1024*20`
    /// or `512x256:bc1`. Formats: rgba8 (default), rgb565, rgba5551,
    /// rgba4444, la8, l8, a8, bc1, bc2, bc3, bc4.
    #[arg(long = "texture", value_parser = parse_texture, conflicts_with = "scene")]
    pub textures: Vec<TextureSpec>,
    /// Path lengths `NEAR..FAR` (scene units) of every textured hit: the
    /// pyramids are then trimmed to the levels such hits can read (with
    /// --texel-size, --fov-y and --rows). A scene file needs none: its
    /// analysis finds them.
    #[arg(long, value_parser = parse_range, conflicts_with = "scene")]
    pub path_range: Option<(f64, f64)>,
    /// World size of one level-0 texel on the scene's surfaces, `MIN..MAX`
    /// or one value (scene units), for --path-range.
    #[arg(long, value_parser = parse_range, default_value = "0.01")]
    pub texel_size: (f64, f64),
    /// Vertical field of view in degrees, for --path-range.
    #[arg(long, default_value_t = 60.0)]
    pub fov_y: f64,
    /// Image rows, for --path-range.
    #[arg(long, default_value_t = 480)]
    pub rows: u32,
    /// Bounces per path.
    #[arg(long, default_value_t = 10)]
    pub bounces: u8,
    /// Continuations a hit pushes (2: reflection and refraction).
    #[arg(long, default_value_t = 2)]
    pub branches: u8,
    /// Texel cache in front of each cached texture: `SETSxWAYS` (lines of
    /// 4×4 texels; 64x4 = 256 lines); none without it.
    #[arg(long, value_parser = parse_size)]
    pub cache: Option<(u32, u32)>,
    /// Textures with a cache (default: every texture).
    #[arg(long)]
    pub cached_textures: Option<u32>,
    /// Target: thumbv7em-none-eabihf or riscv32imac-unknown-none-elf.
    #[arg(long, default_value = TARGETS[0])]
    pub target: String,
    /// Cargo features of raymip, comma-separated (`default` = cone,
    /// trilinear, cache, mipgen).
    #[arg(long, value_delimiter = ',', default_value = "default")]
    pub features: Vec<String>,
    /// Also write the table into FILE between `<!-- BLOCK:begin -->` and
    /// `<!-- BLOCK:end -->`.
    #[arg(long, requires = "block")]
    pub write: Option<PathBuf>,
    /// The block name for --write.
    #[arg(long)]
    pub block: Option<String>,
}

/// Textures of one size and format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TextureSpec {
    /// Level-0 width in texels.
    pub width: u32,
    /// Level-0 height in texels.
    pub height: u32,
    /// Pixel format.
    pub format: TexelFormat,
    /// How many.
    pub count: u32,
}

/// Why `memory` failed.
#[derive(Debug)]
pub enum MemoryError {
    /// A bad argument (names it).
    Arg(String),
    /// The scene could not be loaded or prepared.
    Scene(String),
    /// BUDGETS.md lacks the measurement (run scripts/features).
    Budgets(String),
    /// The output file could not be written.
    Write(String),
}

impl fmt::Display for MemoryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Arg(s) | Self::Scene(s) | Self::Write(s) => f.write_str(s),
            Self::Budgets(s) => write!(f, "BUDGETS.md: {s} (run scripts/features)"),
        }
    }
}

impl std::error::Error for MemoryError {}

/// Parses `WxH[:FORMAT][*COUNT]`.
///
/// # Errors
/// A message naming the bad part.
pub fn parse_texture(s: &str) -> Result<TextureSpec, String> {
    let (rest, count) = match s.split_once('*') {
        Some((r, c)) => (
            r,
            c.parse::<u32>()
                .ok()
                .filter(|&n| n > 0)
                .ok_or(format!("texture `{s}`: count `{c}` is not a number ≥ 1"))?,
        ),
        None => (s, 1),
    };
    let (size, format) = match rest.split_once(':') {
        Some((size, f)) => (
            size,
            <FormatArg as clap::ValueEnum>::from_str(f, true)
                .map_err(|_| format!("texture `{s}`: unknown format `{f}`"))?
                .format(),
        ),
        None => (rest, TexelFormat::Rgba8),
    };
    let (width, height) = parse_size(size).map_err(|e| format!("texture `{s}`: {e}"))?;
    Ok(TextureSpec {
        width,
        height,
        format,
        count,
    })
}

/// Parses `A..B` or a single value `A` (both positive and finite, A ≤ B).
///
/// # Errors
/// A message naming the value.
pub fn parse_range(s: &str) -> Result<(f64, f64), String> {
    let num = |t: &str| {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && *v > 0.0)
            .ok_or(format!("`{s}`: `{t}` is not a positive number"))
    };
    let (a, b) = match s.split_once("..") {
        Some((a, b)) => (num(a)?, num(b)?),
        None => (num(s)?, num(s)?),
    };
    if a > b {
        return Err(format!("`{s}`: the first value is above the second"));
    }
    Ok((a, b))
}

/// One row of the "Feature sets" measurement for a target.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
struct Measured {
    stages: BTreeSet<String>,
    text: u64,
    rodata: u64,
    path_state: u64,
    sampler: u64,
    cache_8x2: Option<u64>,
}

/// The feature sets `scripts/features` measured on `target`.
fn measured(budgets: &str, target: &str) -> Result<Vec<Measured>, MemoryError> {
    let block = budgets
        .split("<!-- features:begin -->")
        .nth(1)
        .and_then(|b| b.split("<!-- features:end -->").next())
        .ok_or_else(|| MemoryError::Budgets("no \"Feature sets\" block".into()))?;
    let col = TARGETS
        .iter()
        .position(|t| *t == target)
        .ok_or_else(|| MemoryError::Arg(format!("--target {target}: one of {TARGETS:?}")))?;
    let stages_of = |label: &str| -> BTreeSet<String> {
        let inner = label
            .trim_matches('`')
            .trim_start_matches("default (")
            .trim_end_matches(')');
        inner
            .split('+')
            .filter(|s| is_stage(s))
            .map(str::to_string)
            .collect()
    };
    let mut sets: Vec<Measured> = Vec::new();
    for line in block.lines().filter(|l| l.starts_with("| ")) {
        let c = markdown_cells(line);
        let num = |i: usize| c.get(i).and_then(|v| v.parse::<u64>().ok());
        if let Some(t) = c.get(1).filter(|v| v.starts_with('`')) {
            // | set | `target` | PathState | Sampler | TexelCache 8x2 |
            if t.trim_matches('`') != target {
                continue;
            }
            let stages = stages_of(&c[0]);
            if let (Some(ps), Some(sampler), Some(m)) =
                (num(2), num(3), sets.iter_mut().find(|m| m.stages == stages))
            {
                m.path_state = ps;
                m.sampler = sampler;
                m.cache_8x2 = num(4);
            }
        } else if let (Some(text), Some(rodata)) = (num(1 + 2 * col), num(2 + 2 * col)) {
            // | set | thumbv7em .text | .rodata | riscv32imac .text | .rodata |
            sets.push(Measured {
                stages: stages_of(&c[0]),
                text,
                rodata,
                ..Measured::default()
            });
        }
    }
    if sets.is_empty() || sets.iter().any(|m| m.path_state == 0) {
        return Err(MemoryError::Budgets(format!(
            "no feature-set sizes and type sizes for {target}"
        )));
    }
    Ok(sets)
}

/// Bytes of a `TexelCache<_, sets, ways>` on a target where the 8 × 2
/// cache takes `bytes_8x2`: the per-way arrays (texels, tag, stamp) scale
/// with `sets · ways`, padded to the struct's 8-byte alignment; the rest
/// (the texture source, layout, clock, counters) is in `bytes_8x2`.
#[must_use]
pub fn cache_bytes(bytes_8x2: u64, sets: u32, ways: u32) -> u64 {
    let per_way = PER_WAY as u64;
    let round8 = |b: u64| b.div_ceil(8) * 8;
    bytes_8x2 - round8(16 * per_way) + round8(u64::from(sets) * u64::from(ways) * per_way)
}

/// Bytes one way of one set adds to a texel cache (host `size_of`; the
/// arrays hold only fixed-width integers, the same on every target).
const PER_WAY: usize = (size_of::<TexelCache<Pyramid<'static>, 8, 4>>()
    - size_of::<TexelCache<Pyramid<'static>, 8, 2>>())
    / 16;

/// What a table row says.
struct Row {
    part: String,
    count: String,
    each: String,
    total: Option<u64>,
}

fn bytes(b: u64) -> String {
    match b {
        b if b >= 10 << 20 => format!("{:.1} MiB", b as f64 / (1u64 << 20) as f64),
        b if b >= 10 << 10 => format!("{:.1} KiB", b as f64 / 1024.0),
        b => format!("{b} B"),
    }
}

/// The textures of a scene: size, levels, and bytes stored after trimming
/// (`None`: not trimmed).
struct SceneTextures {
    label: String,
    triangles: u64,
    textures: Vec<(TextureSpec, u64, Option<u64>)>,
    trimmed_by: Option<String>,
}

fn from_scene(
    spec: &str,
    size: Option<(u32, u32)>,
    bounces: u8,
) -> Result<SceneTextures, MemoryError> {
    let path = Path::new(spec);
    let scene = if path.is_dir() {
        load_scene_dir(path, 0.0)
    } else {
        load_scene(spec, 0.0)
    }
    .map_err(|e| MemoryError::Scene(e.to_string()))?;
    let prep = Prepared::new(scene, size).map_err(|e| MemoryError::Scene(e.to_string()))?;
    let opts = Options {
        method: Method::Table,
        arithmetic: Arithmetic::Fixed,
        size: Some((prep.width, prep.height)),
        bounces,
        spp: 1,
        record_blocks: false,
        progress: false,
        aniso: None,
    };
    let p = plan(&prep, &opts);
    let textures = prep
        .textures
        .iter()
        .zip(&p.textures)
        .map(|(t, s)| {
            let spec = TextureSpec {
                width: t.width,
                height: t.height,
                format: TexelFormat::Rgba8,
                count: 1,
            };
            (
                spec,
                s.full_texels * 4,
                p.applies.then_some(s.stored_texels * 4),
            )
        })
        .collect();
    Ok(SceneTextures {
        label: format!(
            "{} at {}×{}",
            scene_label(spec.trim_end_matches('/')),
            prep.width,
            prep.height
        ),
        triangles: prep.pb_fixed.len() as u64,
        textures,
        trimmed_by: p.applies.then(|| {
            format!(
                "the set-up analysis of its paths ({} textures skipped)",
                p.textures_skipped
            )
        }),
    })
}

fn from_numbers(a: &MemoryArgs) -> Result<SceneTextures, MemoryError> {
    let triangles = a
        .triangles
        .ok_or_else(|| MemoryError::Arg("give --scene, or --triangles and --texture".into()))?;
    // The lods of hits between NEAR and FAR on texels of TEXEL scene units:
    // log2(Pl / Pb) with Pb = texel / γ.
    let lods = a.path_range.map(|(near, far)| {
        let gamma = (2.0 * (a.fov_y.to_radians() / 2.0).tan() / f64::from(a.rows)).atan();
        let (tmin, tmax) = a.texel_size;
        let lod = |x: f64| Lod::saturating_from_num(x.log2());
        LodRange {
            min: lod(near * gamma / tmax),
            max: lod(far * gamma / tmin),
        }
    });
    let mut textures = Vec::new();
    for spec in &a.textures {
        let full = full_levels(spec.width, spec.height);
        let whole = image_len(spec.width, spec.height, full, spec.format) as u64;
        let trimmed = lods.map(|r| {
            let l = r.levels(Mode::Trilinear, full);
            (image_len(spec.width, spec.height, l.last + 1, spec.format)
                - image_len(spec.width, spec.height, l.first, spec.format)) as u64
        });
        textures.push((*spec, whole, trimmed));
    }
    Ok(SceneTextures {
        label: format!(
            "{triangles} triangles, {} textures",
            a.textures.iter().map(|t| u64::from(t.count)).sum::<u64>()
        ),
        triangles,
        textures,
        trimmed_by: a.path_range.map(|(near, far)| {
            format!(
                "--path-range {near}..{far} (texels of {}..{} scene units, {}° over {} rows)",
                a.texel_size.0, a.texel_size.1, a.fov_y, a.rows
            )
        }),
    })
}

/// The requested features, `default` and `ffi` expanded.
fn parse_features(list: &[String]) -> Result<BTreeSet<String>, MemoryError> {
    let mut features = BTreeSet::new();
    for f in list {
        match f.trim() {
            "default" => features.extend(STAGES.iter().map(|s| (*s).to_string())),
            "ffi" => {
                features.extend(STAGES.iter().map(|s| (*s).to_string()));
                features.insert("ffi".into());
            }
            f @ ("cone" | "trilinear" | "cache" | "mipgen" | "raydiff" | "envmap" | "f32"
            | "pcpi") => {
                features.insert(f.into());
            }
            "" => {}
            other => {
                return Err(MemoryError::Arg(format!(
                    "--features: unknown feature `{other}`"
                )));
            }
        }
    }
    Ok(features)
}

fn set_name(m: &Measured) -> String {
    if m.stages.is_empty() {
        "none".to_string()
    } else {
        m.stages.iter().cloned().collect::<Vec<_>>().join("+")
    }
}

/// The Pb table and pyramid rows; returns the texture memory (trimmed
/// when the scene says how).
fn scene_rows(scene: &SceneTextures, n_textures: u64, rows: &mut Vec<Row>) -> u64 {
    let log2pb = size_of::<Log2Pb>() as u64;
    rows.push(Row {
        part: "Pb table: one `Log2Pb` (I16F16) per triangle, untextured ones too".into(),
        count: format!("{} triangles", scene.triangles),
        each: log2pb.to_string(),
        total: Some(scene.triangles * log2pb),
    });
    let full: u64 = scene
        .textures
        .iter()
        .map(|(s, b, _)| b * u64::from(s.count))
        .sum();
    let largest = scene.textures.iter().max_by_key(|(_, b, _)| *b);
    rows.push(Row {
        part: "pyramids, full (every level; `image_len`)".into(),
        count: format!("{n_textures} textures"),
        each: largest.map_or("—".into(), |(s, b, _)| {
            format!(
                "largest {}×{} {:?}, {} levels: {}",
                s.width,
                s.height,
                s.format,
                full_levels(s.width, s.height),
                bytes(*b)
            )
        }),
        total: Some(full),
    });
    let Some(by) = &scene.trimmed_by else {
        return full;
    };
    let trimmed: u64 = scene
        .textures
        .iter()
        .map(|(s, b, t)| t.unwrap_or(*b) * u64::from(s.count))
        .sum();
    rows.push(Row {
        part: format!("pyramids, trimmed to the levels trilinear hits can read, by {by}"),
        count: format!("{n_textures} textures"),
        each: format!(
            "{:.1} % saved",
            100.0 * (full - trimmed) as f64 / full.max(1) as f64
        ),
        total: Some(trimmed),
    });
    trimmed
}

/// The ray-stack, cache and sampler rows; returns their RAM.
fn runtime_rows(
    a: &MemoryArgs,
    features: &BTreeSet<String>,
    sets: &[Measured],
    set: &Measured,
    n_textures: u64,
    rows: &mut Vec<Row>,
) -> Result<u64, MemoryError> {
    let entries = stack_bound(a.bounces, a.branches) as u64;
    let cone = features.contains("cone");
    // The entry size of a measured set with the same `cone` and `raydiff`
    // (the only features that change it).
    let raydiff = features.contains("raydiff");
    let path_state = sets
        .iter()
        .find(|m| m.stages.contains("cone") == cone && m.stages.contains("raydiff") == raydiff)
        .map(|m| m.path_state);
    rows.push(Row {
        part: format!(
            "ray stack: `stack_bound({}, {})` entries of `PathState` ({})",
            a.bounces,
            a.branches,
            if cone {
                "with the cone state"
            } else {
                "no cone state"
            }
        ),
        count: format!("{entries} entries"),
        each: path_state.map_or("not measured (raydiff without cone)".into(), |b| {
            b.to_string()
        }),
        total: path_state.map(|b| b * entries),
    });
    let mut ram = path_state.map_or(0, |b| b * entries);
    if let Some((n_sets, ways)) = a.cache {
        if !features.contains("cache") {
            return Err(MemoryError::Arg("--cache needs the feature `cache`".into()));
        }
        let m82 = sets
            .iter()
            .filter(|m| m.stages.contains("cache"))
            .find_map(|m| m.cache_8x2)
            .ok_or_else(|| MemoryError::Budgets("no texel-cache size".into()))?;
        let each = cache_bytes(m82, n_sets, ways);
        let n = a
            .cached_textures
            .map_or(n_textures, |c| u64::from(c).min(n_textures));
        rows.push(Row {
            part: format!(
                "texel caches `TexelCache<Pyramid, {n_sets}, {ways}>`, one per cached texture ({} of texels each)",
                bytes(u64::from(n_sets) * u64::from(ways) * 64)
            ),
            count: format!("{n} caches"),
            each: each.to_string(),
            total: Some(each * n),
        });
        ram += each * n;
    }
    rows.push(Row {
        part: "samplers `Sampler<Pyramid, Cfg<Wrap>>`, one per texture (state and counters; no texels)"
            .into(),
        count: format!("{n_textures} samplers"),
        each: set.sampler.to_string(),
        total: Some(set.sampler * n_textures),
    });
    Ok(ram + set.sampler * n_textures)
}

/// The memory table of `a` (Markdown).
///
/// # Errors
/// [`MemoryError`] naming the bad argument, the scene or the missing
/// measurement.
pub fn memory_table(a: &MemoryArgs) -> Result<String, MemoryError> {
    let features = parse_features(&a.features)?;
    let sets = measured(BUDGETS, &a.target)?;
    let stages: BTreeSet<String> = features.iter().filter(|f| is_stage(f)).cloned().collect();
    // The smallest measured set holding the requested stages (the default
    // set holds them all).
    let set = sets
        .iter()
        .filter(|m| m.stages.is_superset(&stages))
        .min_by_key(|m| m.stages.len())
        .ok_or_else(|| {
            MemoryError::Arg(format!(
                "--features: no measured feature set holds {}; the measured sets are {} \
                 (to measure another, add it to MEASURED in scripts/features and run that script)",
                stages.iter().cloned().collect::<Vec<_>>().join("+"),
                sets.iter().map(set_name).collect::<Vec<_>>().join(", ")
            ))
        })?;
    let scene = match &a.scene {
        Some(spec) => from_scene(spec, a.size, a.bounces)?,
        None => from_numbers(a)?,
    };
    let n_textures: u64 = scene
        .textures
        .iter()
        .map(|(s, ..)| u64::from(s.count))
        .sum();

    let mut rows = Vec::new();
    let texture_bytes = scene_rows(&scene, n_textures, &mut rows);
    let ram = scene.triangles * size_of::<Log2Pb>() as u64
        + runtime_rows(a, &features, &sets, set, n_textures, &mut rows)?;
    let code = set.text + set.rodata;
    let mut note = String::new();
    if set.stages != stages || features.len() != stages.len() {
        note.push_str(": the smallest measured set holding the stages, an upper bound");
        let unmeasured: Vec<_> = features.difference(&set.stages).cloned().collect();
        if !unmeasured.is_empty() {
            let _ = write!(note, "; not measured: {}", unmeasured.join(", "));
        }
    }
    rows.push(Row {
        part: format!(
            "code: `.text` + `.rodata` of the feature set {} ({} + {}){note}",
            set_name(set),
            set.text,
            set.rodata
        ),
        count: "1".into(),
        each: "—".into(),
        total: Some(code),
    });

    let mut t = String::new();
    let _ = writeln!(
        t,
        "Memory for {} on `{}` with the features {} (`raymip-host memory`; target sizes from BUDGETS.md, \"Feature sets\", measured by `scripts/features`).\n",
        scene.label,
        a.target,
        features.iter().cloned().collect::<Vec<_>>().join(", ")
    );
    let _ = writeln!(t, "| part | count | bytes each | total |");
    let _ = writeln!(t, "|---|---|---|---|");
    for r in &rows {
        let total = r.total.map_or("—".into(), bytes);
        let _ = writeln!(t, "| {} | {} | {} | {} |", r.part, r.count, r.each, total);
    }
    let _ = writeln!(
        t,
        "| **RAM** (Pb table, ray stack, caches, samplers) | | | **{}** |",
        bytes(ram)
    );
    let _ = writeln!(
        t,
        "| **texture memory** (pyramids{}) | | | **{}** |",
        if scene.trimmed_by.is_some() {
            ", trimmed"
        } else {
            ""
        },
        bytes(texture_bytes)
    );
    let _ = writeln!(t, "| **code** (flash) | | | **{}** |", bytes(code));
    Ok(t)
}

/// `raymip-host memory`: prints the table and, with `--write`, puts it
/// into the file's block.
///
/// # Errors
/// As [`memory_table`]; [`MemoryError::Write`] when the file cannot be written.
pub fn cmd_memory(a: &MemoryArgs) -> Result<(), MemoryError> {
    let t = memory_table(a)?;
    print!("{t}");
    if let (Some(path), Some(block)) = (&a.write, &a.block) {
        write_between_markers(path, block, &t).map_err(|e| MemoryError::Write(e.to_string()))?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        args: MemoryArgs,
    }

    fn args(line: &str) -> MemoryArgs {
        Cli::try_parse_from(std::iter::once("memory").chain(line.split_whitespace()))
            .unwrap_or_else(|e| panic!("{line}: {e}"))
            .args
    }

    #[test]
    fn cache_bytes_is_size_of() {
        let base = size_of::<TexelCache<Pyramid<'static>, 8, 2>>() as u64;
        macro_rules! check {
            ($($s:literal x $w:literal),*) => {$(
                assert_eq!(
                    cache_bytes(base, $s, $w),
                    size_of::<TexelCache<Pyramid<'static>, $s, $w>>() as u64,
                    "{}x{}", $s, $w
                );
            )*};
        }
        check!(1 x 1, 3 x 1, 5 x 3, 8 x 2, 16 x 4, 64 x 4, 128 x 8, 7 x 5);
    }

    #[test]
    fn parses_textures_and_ranges() {
        let t = parse_texture("512x256:bc1*8").unwrap();
        assert_eq!(
            (t.width, t.height, t.format, t.count),
            (512, 256, TexelFormat::Bc1, 8)
        );
        assert_eq!(parse_texture("64x64").unwrap().format, TexelFormat::Rgba8);
        for bad in ["64x64*0", "64x64:png", "64", "64x64*x"] {
            let e = parse_texture(bad).unwrap_err();
            assert!(e.contains(bad), "{e}");
        }
        assert_eq!(parse_range("1..200"), Ok((1.0, 200.0)));
        assert_eq!(parse_range("0.5"), Ok((0.5, 0.5)));
        for bad in ["200..1", "0..1", "a..b", "nan"] {
            assert!(parse_range(bad).is_err(), "{bad}");
        }
    }

    /// The figures of a made-up scene, each against its own arithmetic.
    #[test]
    fn numbers_give_the_expected_rows() {
        let a = args(
            "--triangles 50000 --texture 1024x1024*20 --bounces 10 --cache 64x4 \
             --path-range 1..200 --texel-size 0.001..0.01",
        );
        let t = memory_table(&a).unwrap();
        let row = |start: &str| {
            t.lines()
                .find(|l| l.starts_with(&format!("| {start}")))
                .unwrap_or_else(|| panic!("no row `{start}` in\n{t}"))
                .to_string()
        };
        // 4 bytes per triangle.
        assert!(row("Pb table").contains("| 4 | 195.3 KiB |"), "{t}");
        // 20 full 1024² RGBA8 pyramids: 20 · 4 · 1398101 texels.
        assert_eq!(pyramid_bytes(1024, 11), 4 * 1_398_101);
        assert!(
            row("pyramids, full").ends_with(&format!("| {} |", bytes(20 * 4 * 1_398_101))),
            "{t}"
        );
        assert!(row("ray stack").contains("| 11 entries |"), "{t}");
        assert!(row("texel caches").contains("| 20 caches |"), "{t}");
        assert!(row("pyramids, trimmed").contains("% saved"), "{t}");
        // Without --path-range: no trimmed row; the code row names the set.
        let t = memory_table(&args("--triangles 10 --texture 64x64 --features trilinear")).unwrap();
        assert!(!t.contains("trimmed"), "{t}");
        assert!(t.contains("feature set trilinear ("), "{t}");
        // A stage set that was not measured as such: an upper bound, said so.
        let t = memory_table(&args(
            "--triangles 10 --texture 64x64 --features cone,trilinear",
        ))
        .unwrap();
        assert!(t.contains("upper bound"), "{t}");
        // Each opt-in stage is measured beside the defaults: an upper bound
        // for the stage alone, named by its measured set.
        let t = memory_table(&args("--triangles 10 --texture 64x64 --features envmap")).unwrap();
        assert!(
            t.contains("feature set cache+cone+envmap+mipgen+trilinear ("),
            "{t}"
        );
        assert!(!t.contains("not measured:"), "{t}");
        let t = memory_table(&args(
            "--triangles 10 --texture 64x64 --features f32,raydiff",
        ))
        .unwrap_err()
        .to_string();
        assert!(
            t.contains("no measured feature set holds f32+raydiff"),
            "{t}"
        );
        let t = memory_table(&args("--triangles 10 --texture 64x64 --features raydiff")).unwrap();
        assert!(t.contains("not measured (raydiff without cone)"), "{t}");
    }

    fn pyramid_bytes(side: u32, levels: u8) -> u64 {
        image_len(side, side, levels, TexelFormat::Rgba8) as u64
    }

    #[test]
    fn bad_arguments_name_themselves() {
        let e = memory_table(&args("--texture 8x8"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("--triangles"), "{e}");
        let e = memory_table(&args("--triangles 1 --features cone,warp"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("warp"), "{e}");
        let e = memory_table(&args("--triangles 1 --target x86_64"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("x86_64"), "{e}");
        let e = memory_table(&args("--triangles 1 --features trilinear --cache 8x2"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("cache"), "{e}");
    }
}
