//! Loader for BART's AFF scene format (`../shared/scenes/bart/FORMAT.md`).
//!
//! [`load`] reads a top-level `.aff` file with every include expanded in
//! place and returns a static frame at a chosen animation time: world-space
//! triangles (polygons fan-triangulated, meshes de-indexed per corner,
//! spheres and cones tessellated, see [`mesh`]), materials, textures (each
//! PPM read once and shared by index), lights, background, global ambient
//! and the camera (the `camera` track, when present, replaces the `v`
//! block's from/at/up).
//!
//! # Pitfalls handled (FORMAT.md §8)
//! * **global material state** — `fm` is never restored at `}` or at the
//!   end of an include; each primitive takes the material current when read;
//! * **late-bound animation names** — `x NAME` may precede `k NAME`; names
//!   bind after the whole scene is read; the last track of a name wins; an
//!   `x` without a track is the identity (listed in
//!   [`LoadStats::unbound_tracks`]);
//! * **separate vertex/normal/UV index streams** — de-indexed per corner;
//! * **animated camera** replaces `v`'s from/at/up ([`load`]);
//! * **CRLF and Latin-1 bytes** — the lexer works on bytes;
//! * **backwards and repeated key times** — first-match segment rule;
//! * **non-unit rotation axes** — used as written in the quaternion spline,
//!   `w` clamped before `acos` (no NaN at robots `grip_rot2`); the
//!   quaternion log divides by `sin φ` as the reference does (FORMAT.md
//!   writes `|v|`, which differs for non-unit quaternions; the documented
//!   NaN window of the reference is reproduced only with `sin φ`);
//! * **unwelded meshes** — nothing assumes shared vertices;
//! * **zero-area triangles** — dropped and counted (see [`LoadStats`]);
//! * non-uniform `xs` scales — normals use the inverse transpose;
//! * `ior <= 0` → 1; `hither < 1e-4` → 1 (as the reference parser);
//! * PPM header comments and stray trailing bytes (read by [`crate::scene::ppm`]).
//!
//! # Counting definition
//! BART's published counts (kitchen 110,561 triangles of which 5,328
//! textured; robots 71,708 / 65,786) are the triangles **read** after
//! expanding includes and triangulating, **before** zero-area triangles are
//! dropped: [`LoadStats::triangles_read`] and [`LoadStats::textured_read`].
//! `Scene::triangles.len()` is `triangles_read − skipped_degenerate −
//! hidden − skipped_non_finite` (kitchen 110,520, robots 71,580 at
//! [`DEFAULT_TIME`]; hidden and non-finite are 0 there).
//!
//! # Performance
//! Tokens are slices of the file bytes (no allocation per token), plain
//! decimals take an exact fast path, each distinct file is read from disk
//! once however often it is included, each texture once however often it
//! is named. Release build on the shared 2-vCPU EPYC (load average ≈ 5):
//! kitchen ≈ 80–130 ms, robots ≈ 100–145 ms per load, textures included.

mod anim;
mod error;
mod lexer;
pub mod mesh;
mod parser;

use std::path::{Path, PathBuf};

/// The loader produces the renderer's own scene types.
pub use crate::scene::{Camera, Light, Material, Triangle};
pub use error::{AffError, AffErrorKind};
pub use parser::{DEFAULT_MATERIAL, MAX_INCLUDE_DEPTH};

/// Default animation time (scene seconds): 0.0.
///
/// Why: both BART clocks start at 0 (`a 0 20 800` kitchen, `a 0 50 800`
/// robots), so t = 0 is frame 0, the first frame of the benchmark. At t = 0
/// every camera track is at its first usable key (kitchen keys −1, 0, …;
/// robots 0, 0, …), i.e. at a key rather than between keys, so the frame is
/// the authored one and not an interpolation artefact. It is also a fixed
/// number rather than "the scene's `a` start", so every scene and every run
/// means the same instant.
pub const DEFAULT_TIME: f64 = 0.0;

/// A scene frozen at one animation time, in world space.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Camera (from the `camera` track at the load time when there is one).
    pub camera: Camera,
    /// Colour of rays that hit nothing (`b`; default black).
    pub background: crate::scene::V3,
    /// Global ambient intensity (`am`; default 1 1 1); multiplies each
    /// material's ambient colour.
    pub ambient: crate::scene::V3,
    /// Point lights in world space.
    pub lights: Vec<Light>,
    /// Distinct materials (identical `fm` records share one entry).
    pub materials: Vec<Material>,
    /// Textures referenced by the scene, each read once, in order of first
    /// use.
    pub textures: Vec<Texture>,
    /// World-space triangles (zero-area ones dropped, see [`LoadStats`]).
    pub triangles: Vec<Triangle>,
    /// What was read.
    pub stats: LoadStats,
}

/// A texture image.
#[derive(Clone, Debug)]
pub struct Texture {
    /// Name as written in the scene.
    pub name: String,
    /// Resolved file path.
    pub path: PathBuf,
    /// Pixels (any size, NPOT too); v = 0 is the first row of the file.
    pub image: crate::scene::ppm::RgbImage,
}

/// What the loader read.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadStats {
    /// Files parsed, counting each inclusion (the top file included).
    pub files: usize,
    /// Distinct files read from disk.
    pub distinct_files: usize,
    /// Lines parsed, over all inclusions.
    pub lines: usize,
    /// Triangles read (after triangulation / tessellation, before dropping
    /// zero-area ones) — the number BART publishes.
    pub triangles_read: usize,
    /// Of those, textured.
    pub textured_read: usize,
    /// Zero-area triangles (exactly zero cross product in object space),
    /// dropped: a ray can never hit them and their texel density is
    /// undefined.
    pub skipped_degenerate: usize,
    /// Of those, textured.
    pub skipped_degenerate_textured: usize,
    /// Textured triangles read whose UV area is exactly zero (kept).
    pub zero_uv_area: usize,
    /// Triangles dropped because a world coordinate overflowed to ±inf
    /// (absurd scales only; 0 in BART).
    pub skipped_non_finite: usize,
    /// Triangles hidden by a visibility channel at the load time.
    pub hidden: usize,
    /// Kept triangles whose normals were dropped (singular transform or a
    /// zero normal); the renderer uses the geometric normal.
    pub dropped_normals: usize,
    /// `m` records.
    pub meshes: usize,
    /// `p`/`pp` records.
    pub polygons: usize,
    /// `s` records.
    pub spheres: usize,
    /// `c` records.
    pub cones: usize,
    /// `tpa` records.
    pub animated_triangles: usize,
    /// `k` records parsed (repeats counted).
    pub tracks: usize,
    /// `x NAME` names without a track (identity used).
    pub unbound_tracks: Vec<String>,
    /// The camera came from a `camera` track.
    pub camera_from_track: bool,
    /// Some primitive came before any material; [`DEFAULT_MATERIAL`] used.
    pub used_default_material: bool,
    /// The `a t_start t_end frames` clock, if given.
    pub clock: Option<(f64, f64, usize)>,
    /// Animation time the scene was evaluated at.
    pub time: f64,
}

/// Loads the scene of top-level file `path` at animation time `time`
/// (scene seconds; use [`DEFAULT_TIME`] unless choosing a frame).
/// Includes and textures resolve against `path`'s folder.
pub fn load(path: &Path, time: f64) -> Result<Scene, AffError> {
    finite_time(path, time)?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut p = parser::Parser::new(dir, time);
    p.parse_top(path)?;
    p.finish(path)
}

fn finite_time(path: &Path, time: f64) -> Result<(), AffError> {
    if time.is_finite() {
        Ok(())
    } else {
        Err(AffError::new(
            path,
            0,
            AffErrorKind::Syntax(format!("animation time {time} is not finite")),
        ))
    }
}

/// [`load`] from memory: `files` are (name, bytes) pairs of scene files
/// and PPM textures, `top` the name of the top-level file; includes and
/// textures resolve among `files` only (the file system is never read;
/// a missing name is a located "not found" error). Errors name the files
/// as `mem/NAME`. For tests and fuzzing.
///
/// # Errors
/// As [`load`].
pub fn load_from_memory(files: &[(&str, &[u8])], top: &str, time: f64) -> Result<Scene, AffError> {
    let dir = PathBuf::from("mem");
    let path = dir.join(top);
    finite_time(&path, time)?;
    let mut p = parser::Parser::from_memory(dir, time, files);
    p.parse_top(&path)?;
    p.finish(&path)
}

/// Finds the top-level file of one scene folder.
///
/// DIR holds one folder per scene; the top-level file is the .aff no other
/// file in the folder includes. This function takes one such scene folder
/// (e.g. `bart/kitchen`) and returns the only `.aff` in it that no other
/// `.aff` there names in an `i LEVEL NAME` record (commented-out records do
/// not count). Errors when there is none or more than one.
pub fn find_top_level(dir: &Path) -> Result<PathBuf, AffError> {
    let io = |e| AffError::new(dir, 0, AffErrorKind::Io(e));
    let mut affs: Vec<PathBuf> = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(io)? {
        let path = entry.map_err(io)?.path();
        if path.extension().is_some_and(|e| e == "aff") && path.is_file() {
            affs.push(path);
        }
    }
    affs.sort();
    let mut included: std::collections::HashSet<Vec<u8>> = std::collections::HashSet::new();
    for path in &affs {
        let bytes = std::fs::read(path).map_err(|e| AffError::new(path, 0, AffErrorKind::Io(e)))?;
        let mut lx = lexer::Lexer::new(&bytes);
        while let Some(t) = lx.next_token() {
            if matches!(t.text, [b'#' | b'%', ..]) {
                lx.skip_line();
            } else if t.text == b"i" {
                let level = lx.next_token();
                if level.is_some_and(|l| lexer::parse_i64(l.text).is_some())
                    && let Some(name) = lx.next_token()
                {
                    included.insert(name.text.to_vec());
                }
            }
        }
    }
    let tops: Vec<&PathBuf> = affs
        .iter()
        .filter(|p| {
            let name = p.file_name().map(|n| n.to_string_lossy().into_owned());
            !name.is_some_and(|n| included.contains(n.as_bytes()))
        })
        .collect();
    match tops.as_slice() {
        [one] => Ok((*one).clone()),
        [] => Err(AffError::new(
            dir,
            0,
            AffErrorKind::TopLevel(format!(
                "no top-level .aff: {} .aff files, each included by another",
                affs.len()
            )),
        )),
        many => Err(AffError::new(
            dir,
            0,
            AffErrorKind::TopLevel(format!(
                "several .aff files are included by no other file: {}",
                many.iter()
                    .map(|p| p.file_name().unwrap_or_default().to_string_lossy())
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
        )),
    }
}
