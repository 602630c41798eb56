//! What a scene doesn't need, on the host: path-length bounds per
//! texture from the scene's geometry, the firmware's set-up analysis
//! (`raymip::texture::storage::analysis`) over the Pb table, pyramids trimmed to the levels
//! any hit can select, and a render with them.
//!
//! Bounds ([`path_bounds`]), per texture, from the triangles that use it
//! and the bounding box `S` of the whole scene:
//!
//! * nearest: the smallest distance from the eye to one of the triangles
//!   (every path starts at the eye, so its length to a point on them is at
//!   least the straight line), less one ray offset per bounce
//!   (continuations start `eps` off the surface);
//! * farthest: the largest eye-to-vertex distance of the triangles without
//!   mirrors or glass; with them, also the largest eye-to-corner distance of
//!   `S` plus `bounces` segments of at most the diagonal of `S` (plus
//!   offsets);
//!
//! both widened by 10⁻⁶ relative and `10⁻⁶ · diagonal + 2⁻²⁰` absolute
//! (float rounding of the distances, fixed-point rounding of each
//! segment). Only the firmware table method and the level-0 methods (mip0,
//! truth) are trimmed; cone, ray-differential and float renders keep full
//! pyramids (see `raymip::texture::storage::analysis` on cones).

use raymip::texture::Mode;
use raymip::texture::storage::analysis::{
    LevelRange, LodRange, PathBounds, TextureUse, analyse, mark_skipped,
};
use raymip::texture::storage::mip::{Geometry, Pyramid, TexelSource};
use raymip::units::{Lod, PathLength};
use serde::Serialize;

use super::texunit::MipTexture;
use super::{Arithmetic, Image, Method, Options, Prepared, render};
use crate::scene::V3;

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

/// Distance from `p` to the triangle `t` (closest point by Voronoi
/// regions, Ericson, Real-Time Collision Detection 5.1.5).
fn dist_to_triangle(p: V3, [a, b, c]: [V3; 3]) -> f64 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    let closest = if d1 <= 0.0 && d2 <= 0.0 {
        a
    } else {
        let bp = p - b;
        let (d3, d4) = (ab.dot(bp), ac.dot(bp));
        let cp = p - c;
        let (d5, d6) = (ab.dot(cp), ac.dot(cp));
        let (vc, vb, va) = (d1 * d4 - d3 * d2, d5 * d2 - d1 * d6, d3 * d6 - d5 * d4);
        if d3 >= 0.0 && d4 <= d3 {
            b
        } else if d6 >= 0.0 && d5 <= d6 {
            c
        } else if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
            a + ab * (d1 / (d1 - d3))
        } else if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
            a + ac * (d2 / (d2 - d6))
        } else if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
            b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))
        } else {
            let den = va + vb + vc;
            if den.abs() < f64::MIN_POSITIVE {
                // Degenerate (collinear) triangle: its nearest edge.
                return dist_to_segment(p, a, b)
                    .min(dist_to_segment(p, b, c))
                    .min(dist_to_segment(p, a, c));
            }
            (a + ab * (vb / den)) + (ac * (vc / den))
        }
    };
    (p - closest).length()
}

/// Distance from `p` to the segment `ab`.
fn dist_to_segment(p: V3, a: V3, b: V3) -> f64 {
    let ab = b - a;
    let l2 = ab.dot(ab);
    let t = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).length()
}

/// Largest distance from `p` to a corner of the box.
fn far_in_box(p: V3, (lo, hi): (V3, V3)) -> f64 {
    let d = V3::from(std::array::from_fn::<f64, 3, _>(|k| {
        (p[k] - lo[k]).abs().max((p[k] - hi[k]).abs())
    }));
    d.length()
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
            .any(|m| m.specular.max_element() > 0.0 || m.transmission.max_element() > 0.0);
    let all = box_of(scene.triangles.iter().flat_map(|t| t.p.iter()));
    let diag = all.map_or(0.0, |(lo, hi)| (hi - lo).length());
    let abs = 1e-6 * diag + 2f64.powi(-20);
    let n = f64::from(bounces);
    (0..scene.textures.len())
        .map(|x| {
            let mut tris = scene
                .triangles
                .iter()
                .filter(|t| t.is_textured() && t.texture == Some(x as u32))
                .peekable();
            tris.peek()?;
            let (mut near, mut far) = (f64::INFINITY, 0.0f64);
            for t in tris {
                near = near.min(dist_to_triangle(eye, t.p));
                for p in &t.p {
                    far = far.max((eye - *p).length());
                }
            }
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
    let fixed = opts.arithmetic == Arithmetic::Fixed;
    // Anisotropic probes choose their own lods: not bounded here.
    let applies = fixed
        && opts.aniso.is_none()
        && matches!(opts.method, Method::Table | Method::Mip0 | Method::Truth);
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

#[cfg(test)]
mod tests {
    use super::*;
    use raymip::rng::XorShift64;
    use raymip_reference::Draw;

    /// The closest-point distance against a dense barycentric sampling of
    /// the triangle: never larger than any sample's distance (a bound that
    /// must not be too large), and within the sampling step of the best.
    #[test]
    fn triangle_distance_against_sampling() {
        let mut rng = XorShift64(0x5EED);
        let mut r = || rng.range(-2.0, 2.0);
        for _ in 0..300 {
            let tri: [V3; 3] = std::array::from_fn(|_| V3::new(r(), r(), r()));
            let p = V3::new(r() * 2.0, r() * 2.0, r() * 2.0);
            let d = dist_to_triangle(p, tri);
            let n = 60;
            let mut best = f64::INFINITY;
            for i in 0..=n {
                for j in 0..=(n - i) {
                    let (b1, b2) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                    let q = ((tri[0] * (1.0 - b1 - b2)) + tri[1] * b1) + (tri[2] * b2);
                    best = best.min((p - q).length());
                }
            }
            let edge = (0..3)
                .map(|k| (tri[k] - tri[(k + 1) % 3]).length())
                .fold(0.0, f64::max);
            assert!(d <= best + 1e-12, "{d} > sampled {best}");
            assert!(
                best - d <= edge / f64::from(n) + 1e-12,
                "{d} vs sampled {best}"
            );
        }
    }
}
