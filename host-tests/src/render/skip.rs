//! What a scene doesn't need (issue 13), on the host: path-length bounds per
//! texture from the scene's geometry, the firmware's set-up analysis
//! (`raymip::analysis`) over the Pb table, pyramids trimmed to the levels
//! any hit can select, and a render with them.
//!
//! Bounds ([`path_bounds`]), per texture, from the bounding box `B` of the
//! triangles that use it and the box `S` of the whole scene:
//!
//! * nearest: the distance from the eye to `B` (every path starts at the
//!   eye, so its length to a point of `B` is at least the straight line),
//!   less one ray offset per bounce (continuations start `eps` off the
//!   surface);
//! * farthest: the largest eye-to-corner distance of `B` without mirrors or
//!   glass; with them, also the largest eye-to-corner distance of `S` plus
//!   `bounces` segments of at most the diagonal of `S` (plus offsets);
//!
//! both widened by 10⁻⁶ relative and `10⁻⁶ · diagonal + 2⁻²⁰` absolute
//! (float rounding of the distances, fixed-point rounding of each
//! segment). Only the firmware table method and the level-0 methods (mip0,
//! truth) are trimmed; cone, ray-differential and float renders keep full
//! pyramids (see `raymip::analysis` on cones).

use raymip::analysis::{LevelRange, LodRange, PathBounds, TextureUse, analyse, mark_skipped};
use raymip::filter::Mode;
use raymip::lod::Lod;
use raymip::mip::{Geometry, Pyramid, TexelSource};
use raymip::raystack::PathLength;
use serde::Serialize;

use super::texunit::MipTexture;
use super::{Image, Method, Options, Precision, Prepared, render};
use crate::scene::{V3, v};

/// Bytes per stored texel (RGBA8888).
const TEXEL_BYTES: u64 = 4;

/// One texture's part of a [`SkipPlan`].
#[derive(Clone, Debug, Serialize)]
pub struct TextureSkip {
    /// Texture name.
    pub name: String,
    /// Textured triangles using it.
    pub triangles: u32,
    /// Lod range of every hit (table method), if any hit can sample it.
    pub lod: Option<(f64, f64)>,
    /// Stored levels `(first, last)`; `None`: nothing stored.
    pub stored: Option<(u8, u8)>,
    /// Levels of the full pyramid.
    pub levels: u8,
    /// Texels of the full pyramid.
    pub full_texels: u64,
    /// Texels stored.
    pub stored_texels: u64,
}

/// The set-up analysis of one render.
#[derive(Clone, Debug, Serialize)]
pub struct SkipPlan {
    /// Whether the render's method and precision allow trimming.
    pub applies: bool,
    /// Per texture.
    pub textures: Vec<TextureSkip>,
    /// Textures no hit can sample (nothing stored).
    pub textures_skipped: u32,
    /// Pb entries marked untextured because their texture is never sampled.
    pub triangles_marked: u32,
    /// Bytes of all full pyramids.
    pub full_bytes: u64,
    /// Bytes stored after trimming.
    pub stored_bytes: u64,
}

impl SkipPlan {
    /// Bytes saved.
    #[must_use]
    pub fn saved_bytes(&self) -> u64 {
        self.full_bytes - self.stored_bytes
    }

    /// Bytes saved in % of the full pyramids.
    #[must_use]
    pub fn saved_percent(&self) -> f64 {
        100.0 * self.saved_bytes() as f64 / self.full_bytes.max(1) as f64
    }
}

fn box_of<'a>(points: impl Iterator<Item = &'a V3>) -> Option<(V3, V3)> {
    let mut b: Option<(V3, V3)> = None;
    for p in points {
        let (lo, hi) = b.get_or_insert((*p, *p));
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    b
}

/// Distance from `p` to the box (0 inside).
fn dist_to_box(p: V3, (lo, hi): (V3, V3)) -> f64 {
    let d: V3 = std::array::from_fn(|k| (lo[k] - p[k]).max(p[k] - hi[k]).max(0.0));
    v::len(d)
}

/// Largest distance from `p` to a corner of the box.
fn far_in_box(p: V3, (lo, hi): (V3, V3)) -> f64 {
    let d: V3 = std::array::from_fn(|k| (p[k] - lo[k]).abs().max((p[k] - hi[k]).abs()));
    v::len(d)
}

/// Path-length bounds per texture (module docs); `None` for a texture no
/// triangle uses.
#[must_use]
pub fn path_bounds(prep: &Prepared, bounces: u8) -> Vec<Option<PathBounds>> {
    let scene = &prep.scene;
    let eye = prep.cam.eye;
    let eps = prep.eps();
    let secondary = bounces > 0
        && scene
            .materials
            .iter()
            .any(|m| v::max_c(m.specular) > 0.0 || v::max_c(m.transmission) > 0.0);
    let all = box_of(scene.triangles.iter().flat_map(|t| t.p.iter()));
    let diag = all.map_or(0.0, |(lo, hi)| v::len(v::sub(hi, lo)));
    let abs = 1e-6 * diag + 2f64.powi(-20);
    let n = f64::from(bounces);
    (0..scene.textures.len())
        .map(|x| {
            let tris = scene
                .triangles
                .iter()
                .filter(|t| t.is_textured() && t.texture == Some(x as u32));
            let b = box_of(tris.flat_map(|t| t.p.iter()))?;
            let mut near = dist_to_box(eye, b);
            let mut far = far_in_box(eye, b);
            if secondary {
                near -= n * eps;
                far = far.max(all.map_or(0.0, |s| far_in_box(eye, s)) + n * (diag + 2.0 * eps));
            }
            let near = (near * (1.0 - 1e-6) - abs).max(0.0);
            let far = far * (1.0 + 1e-6) + abs;
            Some(PathBounds {
                nearest: PathLength::saturating_from_num(near),
                farthest: PathLength::saturating_from_num(far),
            })
        })
        .collect()
}

/// The analysis for a render with `opts`: per-texture level ranges and
/// bytes. `applies` is false (full pyramids kept) for methods the analysis
/// does not bound.
#[must_use]
pub fn plan(prep: &Prepared, opts: &Options) -> SkipPlan {
    let fixed = opts.precision == Precision::Fixed;
    let applies = fixed && matches!(opts.method, Method::Table | Method::Mip0 | Method::Truth);
    let texture_of: Vec<u16> = prep
        .scene
        .triangles
        .iter()
        .map(|t| {
            t.texture
                .map_or(u16::MAX, |x| u16::try_from(x).unwrap_or(u16::MAX))
        })
        .collect();
    let bounds = path_bounds(prep, opts.bounces);
    let mut usage = vec![TextureUse::default(); prep.textures.len()];
    let analysed = analyse(&prep.pb_fixed, &texture_of, &bounds, &mut usage).is_ok();
    let mut pbs = prep.pb_fixed.clone();
    let triangles_marked = if analysed {
        mark_skipped(&mut pbs, &texture_of, &usage)
    } else {
        0
    };
    let mut plan = SkipPlan {
        applies: applies && analysed,
        textures: Vec::new(),
        textures_skipped: 0,
        triangles_marked,
        full_bytes: 0,
        stored_bytes: 0,
    };
    for (tex, u) in prep.textures.iter().zip(&usage) {
        let g = tex.geometry();
        let full_texels = g.len() as u64;
        let lod = match opts.method {
            Method::Mip0 | Method::Truth => u.lod.map(|_| LodRange {
                min: Lod::ZERO,
                max: Lod::ZERO,
            }),
            _ => u.lod,
        };
        let stored = if plan.applies {
            lod.map(|r| r.levels(Mode::Trilinear, tex.levels))
                .map(|LevelRange { first, last }| (first, last))
        } else {
            Some((0, tex.levels - 1))
        };
        let stored_texels = stored
            .and_then(|(f, l)| Geometry::trimmed(tex.width, tex.height, tex.levels, f, l).ok())
            .map_or(0, |g| g.len() as u64);
        if stored.is_none() {
            plan.textures_skipped += 1;
        }
        plan.full_bytes += full_texels * TEXEL_BYTES;
        plan.stored_bytes += stored_texels * TEXEL_BYTES;
        plan.textures.push(TextureSkip {
            name: tex.name.clone(),
            triangles: u.triangles,
            lod: u.lod.map(|r| (r.min.to_num(), r.max.to_num())),
            stored,
            levels: tex.levels,
            full_texels,
            stored_texels,
        });
    }
    plan
}

/// The pyramids `plan` stores: each texture's stored levels copied out of
/// its full pyramid into a buffer of their own (nothing for a skipped
/// texture).
#[must_use]
pub fn trimmed_textures(prep: &Prepared, plan: &SkipPlan) -> Vec<MipTexture> {
    prep.textures
        .iter()
        .zip(&plan.textures)
        .map(|(tex, s)| {
            let trimmed = s.stored.and_then(|(first, last)| {
                Pyramid::new(tex.geometry(), &tex.texels)
                    .and_then(|p| p.trim(first, last))
                    .ok()
            });
            match trimmed {
                Some(p) => tex.with_pyramid(p.geometry(), p.texels().to_vec()),
                None => tex.with_pyramid(tex.geometry(), Vec::new()),
            }
        })
        .collect()
}

/// A render with the trimmed pyramids of `plan` (the prepared scene's
/// textures are swapped for the render and restored).
#[must_use]
pub fn render_trimmed(prep: &mut Prepared, opts: &Options, plan: &SkipPlan) -> Image {
    let trimmed = trimmed_textures(prep, plan);
    let full = std::mem::replace(&mut prep.textures, trimmed);
    let img = render(prep, opts);
    prep.textures = full;
    img
}

/// True when two renders are bit-identical (colours, lods, counters of
/// hits and fetches).
#[must_use]
pub fn bit_identical(a: &Image, b: &Image) -> bool {
    let bits = |img: &Image| -> (Vec<u32>, Vec<u32>) {
        (
            img.rgb.iter().flatten().map(|x| x.to_bits()).collect(),
            img.lod.iter().map(|x| x.to_bits()).collect(),
        )
    };
    let (ca, cb) = (&a.counters, &b.counters);
    bits(a) == bits(b)
        && (
            ca.textured_hits,
            ca.untextured_skipped,
            ca.fetched,
            ca.fetch_skipped,
        ) == (
            cb.textured_hits,
            cb.untextured_skipped,
            cb.fetched,
            cb.fetch_skipped,
        )
        && ca.level_hist == cb.level_hist
}
